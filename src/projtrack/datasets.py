"""Real multi-object tracking data that ships inside an installed package: no download.

The ``motmetrics`` package (py-motmetrics, PyPI) ships in its wheel two real pedestrian
sequences of the MOTChallenge 2015 benchmark with human-annotated ground truth,
TUD-Campus (Andriluka, Roth & Schiele 2008) and TUD-Stadtmitte (Andriluka, Roth &
Schiele 2010), as ``motmetrics/data/<name>/gt.txt``, together with the output of a real
tracker on them (``test.txt``). Both are 640 x 480 pixel videos; the files hold one
bounding box per line in the MOTChallenge text format
``frame, id, left, top, width, height, confidence, x, y, z`` (1-based pixel
coordinates). :func:`load_mot_sequence` reads one file with ``importlib.resources`` from
the installed package and returns its boxes in 0-based pixels, the convention of
``motmetrics.io.loadtxt``. Nothing is fetched from the network: without ``motmetrics``
the loader raises an :class:`ImportError` that names the package.

This module makes no data and runs no estimator: it only reads what the package ships
(the layer of :mod:`projtrack.scenes`, the synthetic stand-ins).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources

import numpy as np

from projtrack._validation import as_choice, as_int

__all__ = ["SEQUENCES", "SOURCES", "IMAGE_SIZE", "MOTBoxes", "mot_data_file", "load_mot_sequence"]

#: The real sequences ``motmetrics`` ships (MOTChallenge 2015 names).
SEQUENCES: tuple[str, ...] = ("TUD-Campus", "TUD-Stadtmitte")

#: The files of each sequence: the annotated ground truth and a real tracker's output.
SOURCES: tuple[str, ...] = ("gt", "test")

#: Width and height of both videos in pixels (MOTChallenge 2015 sequence information).
IMAGE_SIZE: tuple[int, int] = (640, 480)

_PACKAGE = "motmetrics"


@dataclass(frozen=True)
class MOTBoxes:
    """The boxes of one file of a MOTChallenge sequence (output of :func:`load_mot_sequence`).

    Attributes
    ----------
    name, source : str
        Sequence (one of :data:`SEQUENCES`) and file (``"gt"`` or ``"test"``).
    frame : ndarray of int, shape (n,)
        Frame number of each box (1-based, as in the file), sorted.
    ident : ndarray of int, shape (n,)
        Identity of each box: the person (ground truth) or the tracker's track (test).
    box : ndarray, shape (n, 4)
        ``(left, top, width, height)`` in 0-based pixels.
    n_frames : int
        Frames of the sequence (the last annotated frame of the ground truth).
    image_size : tuple of int
        ``(width, height)`` of the video in pixels.
    """

    name: str
    source: str
    frame: np.ndarray
    ident: np.ndarray
    box: np.ndarray
    n_frames: int
    image_size: tuple[int, int] = IMAGE_SIZE

    @property
    def centres(self) -> np.ndarray:
        """Box centres ``(x, y)``, shape (n, 2)."""
        return self.box[:, :2] + self.box[:, 2:] / 2

    @property
    def identities(self) -> np.ndarray:
        """The distinct identities, sorted."""
        return np.unique(self.ident)

    def in_frame(self, frame: int) -> np.ndarray:
        """Indices of the boxes of one frame (1-based), in file order."""
        frame = as_int(frame, "frame", minimum=1)
        lo, hi = np.searchsorted(self.frame, [frame, frame + 1])
        return np.arange(lo, hi)


def mot_data_file(name: str, source: str = "gt"):
    """The shipped file ``motmetrics/data/<name>/<source>.txt`` as an ``importlib.resources`` path.

    Raises
    ------
    ImportError
        If ``motmetrics`` is not installed (``pip install motmetrics``; it also needs
        ``xmltodict``).
    """
    name = as_choice(name, "name", SEQUENCES)
    source = as_choice(source, "source", SOURCES)
    try:
        root = resources.files(_PACKAGE)
    except ModuleNotFoundError as exc:
        raise ImportError(
            f"the real pedestrian sequences are read from the installed '{_PACKAGE}' package, "
            f"which is missing or incomplete ({exc}); install it with "
            f"'pip install {_PACKAGE}' (the book's environment.lock pins it)") from None
    path = root / "data" / name / f"{source}.txt"
    if not path.is_file():
        raise FileNotFoundError(f"the installed '{_PACKAGE}' package has no data/{name}/{source}.txt")
    return path


def load_mot_sequence(name: str, source: str = "gt") -> MOTBoxes:
    """Read one shipped MOTChallenge file (:data:`SEQUENCES` x :data:`SOURCES`).

    Parameters
    ----------
    name : {"TUD-Campus", "TUD-Stadtmitte"}
    source : {"gt", "test"}
        The annotated ground truth, or the shipped tracker output.

    Returns
    -------
    MOTBoxes
        Boxes sorted by frame, then identity; 1 is subtracted from the file's left and top
        (1-based pixels), as ``motmetrics.io.loadtxt`` does. ``n_frames`` is the last
        frame of the sequence's ground truth.

    Examples
    --------
    >>> gt = load_mot_sequence("TUD-Campus")  # doctest: +SKIP
    >>> gt.n_frames, len(gt.identities), len(gt.frame)  # doctest: +SKIP
    (71, 8, 359)
    """
    path = mot_data_file(name, source)
    raw = np.loadtxt(path.open("r"), delimiter=",", ndmin=2)
    if raw.shape[1] < 6:
        raise ValueError(f"{name}/{source}.txt: expected at least 6 comma-separated columns, "
                         f"got {raw.shape[1]}")
    order = np.lexsort((raw[:, 1], raw[:, 0]))
    raw = raw[order]
    frame = raw[:, 0].astype(int)
    box = raw[:, 2:6].copy()
    box[:, :2] -= 1.0
    if source == "gt":
        n_frames = int(frame.max())
    else:
        n_frames = load_mot_sequence(name, "gt").n_frames
    return MOTBoxes(name=name, source=source, frame=frame, ident=raw[:, 1].astype(int), box=box,
                    n_frames=n_frames)

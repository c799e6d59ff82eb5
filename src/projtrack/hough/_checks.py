"""Argument checks that only the Hough package needs (point lists, binary images, planes).

The general checks (ints, reals, shapes, choices) are in :mod:`projtrack._validation`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack._validation import as_array, as_choice, only_value_errors

#: The two places ``rho`` may be measured from (see :mod:`projtrack.hough`).
ORIGINS = ("center", "corner")


def _check_origin(origin: object) -> str:
    """Where ``rho`` is measured from: ``"center"`` (the paper's) or ``"corner"``."""
    return as_choice(origin, "origin", ORIGINS)


def _check_points(points: object, shape: tuple[int, int], name: str = "points",
                  allow_empty: bool = False) -> np.ndarray:
    """An ``(N, 2)`` float array of ``(x, y)`` pixel coordinates inside an image of ``shape``."""
    pts = as_array(points, name, finite=False)
    if pts.size == 0 and pts.ndim <= 2:
        if not allow_empty:
            raise ValueError(f"{name} is empty: there is nothing to transform (pass allow_empty=True "
                             "to get an all-zero Hough plane)")
        return np.zeros((0, 2))
    pts = as_array(pts, name, shape=(None, 2))  # one (x, y) row per point, finite
    h, w = shape
    bad = (pts[:, 0] < 0) | (pts[:, 0] >= w) | (pts[:, 1] < 0) | (pts[:, 1] >= h)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}[{i}] = ({pts[i, 0]:g}, {pts[i, 1]:g}) lies outside the image of "
                         f"shape (height, width) = {shape}: need 0 <= x < {w} and 0 <= y < {h}")
    return pts


def _origin_xy(shape: tuple[int, int], origin: str) -> tuple[float, float]:
    h, w = shape
    return (w / 2.0, h / 2.0) if origin == "center" else (0.0, 0.0)


def _check_binary_image(image: object, name: str = "image") -> np.ndarray:
    img = np.asarray(image)
    if img.ndim != 2 or img.size == 0:
        raise ValueError(f"{name} must be a non-empty 2-D array, got shape {img.shape}")
    if img.dtype == bool:
        return img
    if not np.issubdtype(img.dtype, np.number):
        raise TypeError(f"{name} must be a numeric or boolean array, got dtype {img.dtype}")
    if not np.all(np.isin(img, (0, 1))):
        raise ValueError(f"{name} must be binary (only 0 and 1): the Hough transform of Sec. II "
                         "acts on binary detection images")
    return img.astype(bool)


def _check_frames(frames: object, shape: tuple[int, int]) -> list[np.ndarray]:
    if isinstance(frames, np.ndarray) and frames.ndim == 3 and frames.shape[-1] == 2:
        frames = list(frames)
    if not isinstance(frames, Sequence) or isinstance(frames, (str, bytes)):
        raise TypeError("frames must be a sequence of (N_k, 2) point arrays, one per frame")
    if len(frames) == 0:
        raise ValueError("frames is empty: need at least one frame")
    out = [_check_points(f, shape, name=f"frames[{k}]", allow_empty=True) for k, f in enumerate(frames)]
    if sum(len(f) for f in out) == 0:
        raise ValueError("every frame is empty: there are no detections to transform")
    return out


def _check_plane(H: object, rhos: object, thetas_deg: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A Hough plane ``H`` (``rho`` along axis 0) and its two axes, as float arrays."""
    r = as_array(rhos, "rhos", ndim=1)
    t = as_array(thetas_deg, "thetas_deg", ndim=1)
    if r.size < 2 or t.size < 2:
        raise ValueError("rhos and thetas_deg must be 1-D arrays with at least 2 samples each")
    Hf = as_array(H, "H", shape=(r.size, t.size))  # (len(rhos), len(thetas_deg))
    if np.any(Hf < 0):
        raise ValueError("H must be non-negative (vote counts)")
    if np.any(np.diff(r) <= 0) or np.any(np.diff(t) <= 0):
        raise ValueError("rhos and thetas_deg must be strictly increasing")
    return Hf, r, t


def _check_hint(heading_hint: object) -> np.ndarray:
    """The prior direction of motion: a non-zero finite 2-vector (any error is a ValueError)."""
    h = only_value_errors(as_array, heading_hint, "heading_hint", shape=(2,))
    if not np.any(h != 0):
        raise ValueError(f"heading_hint must be a non-zero finite 2-vector, got {heading_hint!r}")
    return h

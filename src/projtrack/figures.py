"""One figure style for the whole book, and deterministic saving of figures and tables.

Importing this module selects the non-interactive Agg renderer when no display backend
has been chosen (inside a Jupyter kernel the inline backend, itself Agg-based, is kept
so that figures still show) and applies :data:`STYLE`: the STIX fonts that ship with
matplotlib (a Times-like serif, matching the look of the source papers), fixed sizes and
a fixed resolution.

:func:`save` writes ``<root>/<part>/<name>.png`` with no time stamp or version in the
PNG metadata, so the same figure gives the same bytes on every run; :func:`save_table`
writes a CSV beside it. ``<root>`` is ``figures/`` at the repository root unless the
environment variable ``PROJTRACK_FIGURES_DIR`` names another folder.

Names ending in ``.timing`` (``"jpda/scaling.timing"``) mark outputs that depend on
wall-clock time: the figure-regression test checks that they exist but does not compare
their pixels or values.
"""

from __future__ import annotations

import os
import re
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

import matplotlib

if "MPLBACKEND" not in os.environ and "ipykernel" not in sys.modules:
    # Plain Python (tests, scripts): render off-screen. A Jupyter kernel keeps its
    # inline backend so that figures also appear in the notebook.
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from projtrack._paths import figures_root  # noqa: E402

__all__ = ["STYLE", "DPI", "apply_style", "style", "save", "save_table", "output_path", "SavedFigure"]

#: Resolution of every saved figure (dots per inch).
DPI = 120

#: The book's matplotlib settings.
STYLE: dict[str, Any] = {
    "font.family": "serif",
    "font.serif": ["STIXGeneral", "DejaVu Serif"],
    "mathtext.fontset": "stix",
    "font.size": 10.0,
    "axes.titlesize": 10.0,
    "axes.labelsize": 10.0,
    "legend.fontsize": 8.5,
    "xtick.labelsize": 9.0,
    "ytick.labelsize": 9.0,
    "figure.figsize": (6.4, 4.0),
    "figure.dpi": DPI,
    "savefig.dpi": DPI,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.05,
    "savefig.facecolor": "white",
    "axes.grid": False,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "image.cmap": "viridis",
    "image.interpolation": "nearest",
    "lines.linewidth": 1.3,
    "svg.hashsalt": "projtrack",
    "path.simplify": True,
}

_NAME = re.compile(r"^[A-Za-z0-9_-]+(/[A-Za-z0-9_.-]+)+$")


def apply_style() -> None:
    """Apply :data:`STYLE` to matplotlib's global settings."""
    matplotlib.rcParams.update(STYLE)


@contextmanager
def style() -> Iterator[None]:
    """Context manager applying :data:`STYLE` only inside the ``with`` block."""
    with matplotlib.rc_context(STYLE):
        yield


def output_path(name: str, suffix: str) -> Path:
    """Return the path ``<root>/<name><suffix>`` for a figure or table name.

    Parameters
    ----------
    name : str
        ``"<part>/<name>"``, e.g. ``"jpda/table1"``: a part folder and a file stem made
        of letters, digits, ``_``, ``-`` and ``.``; sub-folders are allowed.
    suffix : str
        File suffix including the dot (``".png"``, ``".csv"``).

    Raises
    ------
    TypeError
        If ``name`` is not a string.
    ValueError
        If ``name`` is not of the form ``"part/name"``.
    """
    if not isinstance(name, str):
        raise TypeError(f"name must be a str like 'part/name', got {type(name).__name__}")
    if not _NAME.match(name) or name.endswith(suffix) or ".." in name:
        raise ValueError(
            f"name must look like 'part/name' (letters, digits, '_', '-', '.'; no suffix), got {name!r}"
        )
    return figures_root() / f"{name}{suffix}"


class SavedFigure:
    """What :func:`save` returns: shows the saved PNG in a notebook, prints its path."""

    def __init__(self, path: Path, name: str):
        self.path = path
        self.name = name

    def _repr_png_(self) -> bytes:
        return self.path.read_bytes()

    def __repr__(self) -> str:
        return f"figures/{self.name}.png"


def save(fig: matplotlib.figure.Figure, name: str, *, close: bool = True) -> SavedFigure:
    """Save ``fig`` as ``figures/<name>.png`` deterministically.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to save.
    name : str
        ``"<part>/<name>"``, without suffix (see :func:`output_path`).
    close : bool, default True
        Close the figure after saving so that a notebook shows it once, through the
        returned object, exactly as saved.

    Returns
    -------
    SavedFigure
        Displays the saved PNG in a notebook; its text form is the relative path.
    """
    if not isinstance(fig, matplotlib.figure.Figure):
        raise TypeError(f"fig must be a matplotlib Figure, got {type(fig).__name__}")
    path = output_path(name, ".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    with style():
        fig.savefig(path, format="png", dpi=DPI, metadata={"Software": None})
    if close:
        plt.close(fig)
    return SavedFigure(path, name)


def save_table(table: Any, name: str, *, float_format: str | None = None) -> Path:
    """Save a table as ``figures/<name>.csv``.

    Parameters
    ----------
    table : pandas.DataFrame
        The table; its index is written only if it is named (a plain RangeIndex is not).
    name : str
        ``"<part>/<name>"``, without suffix.
    float_format : str, optional
        Format for floats, e.g. ``"%.4g"``, to keep the CSV stable and readable.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    import pandas as pd

    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame, got {type(table).__name__}")
    path = output_path(name, ".csv")
    path.parent.mkdir(parents=True, exist_ok=True)
    write_index = any(n is not None for n in table.index.names)
    table.to_csv(path, index=write_index, float_format=float_format, lineterminator="\n")
    return path


apply_style()

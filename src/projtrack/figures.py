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
from typing import Any, Iterator, Mapping

import matplotlib

if "MPLBACKEND" not in os.environ and "ipykernel" not in sys.modules:
    # Plain Python (tests, scripts): render off-screen. A Jupyter kernel keeps its
    # inline backend so that figures also appear in the notebook.
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from projtrack._paths import figures_root  # noqa: E402
from projtrack.tolerance import EXACT, Manifest, Tolerance, write_manifest  # noqa: E402

__all__ = ["STYLE", "DPI", "apply_style", "style", "save", "save_table", "table_manifest", "output_path",
           "SavedFigure", "SavedTable", "legibility_problems", "COLUMN_PX", "MIN_DISPLAYED_PT",
           "MAX_PANELS_PER_ROW", "show_table"]

#: Resolution of every saved figure (dots per inch).
DPI = 120

#: Width of the book's text column in CSS pixels (Chromium at 1400 x 900, sphinx-book-theme):
#: a wider figure is shown shrunk to this width.
COLUMN_PX = 772

#: Smallest text a figure may show, in CSS points at the width the page shows it.
MIN_DISPLAYED_PT = 9.0

#: Most panels (axes) side by side in one row of a figure.
MAX_PANELS_PER_ROW = 3

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
    problems = legibility_problems(fig, _png_width(path))
    if problems and os.environ.get("PROJTRACK_LEGIBILITY", "strict") != "off":
        path.unlink()
        plt.close(fig)
        raise ValueError(f"figure {name!r} would not be legible in the book: " + "; ".join(problems))
    if close:
        plt.close(fig)
    return SavedFigure(path, name)


def _png_width(path: Path) -> int:
    with open(path, "rb") as fh:
        head = fh.read(24)
    return int.from_bytes(head[16:20], "big")


def _drawn_texts(fig: matplotlib.figure.Figure) -> list[Any]:
    """The visible, non-empty text artists of a drawn figure (tick labels only where a tick is shown)."""
    from matplotlib.text import Text

    fig.canvas.draw()
    tick_texts, shown = set(), set()
    for ax in fig.get_axes():
        for axis in (ax.xaxis, ax.yaxis):
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                tick_texts.update({id(tick.label1), id(tick.label2)})
            for minor in (False, True):
                shown.update(id(t) for t in axis.get_ticklabels(minor=minor, which="both"))
    out = []
    for t in fig.findobj(Text):
        if not t.get_visible() or not t.get_text().strip():
            continue
        if t.axes is not None and not t.axes.get_visible():
            continue
        if id(t) in tick_texts and id(t) not in shown:
            continue
        out.append(t)
    return out


def _panel_rows(fig: matplotlib.figure.Figure) -> int:
    """The largest number of panels side by side (colour bars and insets not counted)."""
    panels = []
    for ax in fig.get_axes():
        if not ax.get_visible() or ax.get_label() == "<colorbar>" or hasattr(ax, "_colorbar"):
            continue
        parent = getattr(ax, "_axes_locator", None)
        if ax.get_subplotspec() is None and parent is not None:
            continue  # an inset
        b = ax.get_position()
        if b.width <= 0 or b.height <= 0:
            continue
        panels.append(b)
    best = 0
    for b in panels:  # a horizontal line through the middle of each panel
        y = 0.5 * (b.y0 + b.y1)
        best = max(best, sum(1 for c in panels if c.y0 < y < c.y1))
    return best


def legibility_problems(fig: matplotlib.figure.Figure, width_px: int | None = None) -> list[str]:
    """Why a figure would not be legible in the book (an empty list when it is).

    The book shows a figure at its saved size, shrunk to :data:`COLUMN_PX` when it is wider.
    At that width every text must be at least :data:`MIN_DISPLAYED_PT` CSS points (a
    ``s``-point font saved at :data:`DPI` shows at ``s * DPI / 96 * scale`` CSS points), and no
    row may hold more than :data:`MAX_PANELS_PER_ROW` panels.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    width_px : int, optional
        Width of the saved PNG in pixels (default: the figure's width at :data:`DPI`).
    """
    if not isinstance(fig, matplotlib.figure.Figure):
        raise TypeError(f"fig must be a matplotlib Figure, got {type(fig).__name__}")
    width = width_px if width_px is not None else int(fig.get_figwidth() * DPI)
    scale = min(1.0, COLUMN_PX / max(width, 1))
    problems = []
    small = sorted({(round(t.get_fontsize(), 2), t.get_text().strip()[:30]) for t in _drawn_texts(fig)
                    if t.get_fontsize() * DPI / 96 * scale < MIN_DISPLAYED_PT - 1e-9})
    if small:
        need = MIN_DISPLAYED_PT * 96 / DPI / scale
        examples = ", ".join(f"{txt!r} at {size:g} pt" for size, txt in small[:4])
        problems.append(f"{len(small)} texts would show below {MIN_DISPLAYED_PT:g} pt at the book's column width "
                        f"({width} px wide, shown at {scale:.0%}: fonts need >= {need:.1f} pt; e.g. {examples})")
    n = _panel_rows(fig)
    if n > MAX_PANELS_PER_ROW:
        problems.append(f"{n} panels side by side (at most {MAX_PANELS_PER_ROW}: stack or split the figure)")
    return problems


def _needs_tolerance(column) -> bool:
    """Whether a column holds non-integer numbers (and so needs a declared tolerance)."""
    import pandas as pd

    if pd.api.types.is_bool_dtype(column) or pd.api.types.is_integer_dtype(column):
        return False
    if pd.api.types.is_float_dtype(column):
        return True
    return any(isinstance(v, (float, np.floating)) and not isinstance(v, bool) for v in column)


def table_manifest(table: Any, tolerance: "Tolerance | Mapping[str, Tolerance] | None") -> Manifest:
    """The :class:`~projtrack.tolerance.Manifest` :func:`save_table` writes for ``table``.

    Parameters
    ----------
    table : pandas.DataFrame
        The table as it will be written (a named index counts as leading columns).
    tolerance : Tolerance or mapping of column name to Tolerance, or None
        One tolerance for every column of non-integer numbers, or one per column (the key
        ``"*"`` for the others). Integer, boolean and text columns are exact.

    Raises
    ------
    ValueError
        If a column of non-integer numbers has no tolerance, a mapping names a column the
        table does not have, or an integer or text column is given a non-exact tolerance.
    TypeError
        If ``tolerance`` is neither a Tolerance nor a mapping of them.
    """
    import pandas as pd

    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame, got {type(table).__name__}")
    flat = table.reset_index() if any(n is not None for n in table.index.names) else table
    names = [str(c) for c in flat.columns]
    if tolerance is None:
        spec: dict[str, Tolerance] = {}
    elif isinstance(tolerance, Tolerance):
        spec = {"*": tolerance}
    elif isinstance(tolerance, Mapping):
        spec = {}
        for k, v in tolerance.items():
            if not isinstance(v, Tolerance):
                raise TypeError(f"tolerance[{k!r}] must be a projtrack.tolerance.Tolerance, got {type(v).__name__}")
            spec[str(k)] = v
        unknown = sorted(set(spec) - set(names) - {"*"})
        if unknown:
            raise ValueError(f"tolerance names columns the table does not have: {unknown}")
    else:
        raise TypeError("tolerance must be a projtrack.tolerance.Tolerance or a mapping of column name to one, "
                        f"got {type(tolerance).__name__}")
    columns: dict[str, Tolerance] = {}
    undeclared = []
    for name, (_, col) in zip(names, flat.items()):
        if _needs_tolerance(col):
            tol = spec.get(name, spec.get("*"))
            if tol is None:
                undeclared.append(name)
            columns[name] = tol
        else:
            tol = spec.get(name)
            if tol is not None and not tol.is_exact:
                raise ValueError(f"column {name!r} holds integers or text, which are compared exactly: "
                                 f"it cannot take a {tol.kind} tolerance (store a share or a mean instead)")
            columns[name] = EXACT
    if undeclared:
        raise ValueError(f"columns {undeclared} hold non-integer numbers: declare their tolerance "
                         "(tolerance=, see projtrack.tolerance)")
    return Manifest(columns)


def save_table(table: Any, name: str, *, tolerance: "Tolerance | Mapping[str, Tolerance] | None" = None,
               float_format: str | None = None, formats: Mapping[str, str] | None = None,
               caption: str | None = None) -> "SavedTable":
    """Save a table as ``figures/<name>.csv``, with its tolerances in ``<name>.tolerance.json``.

    Parameters
    ----------
    table : pandas.DataFrame
        The table; its index is written only if it is named (a plain RangeIndex is not).
    name : str
        ``"<part>/<name>"``, without suffix.
    tolerance : Tolerance or mapping of column name to Tolerance
        How far each column of non-integer numbers may move on another machine
        (:mod:`projtrack.tolerance`: exact, numerical or statistical): one tolerance for
        all of them, or one per column (``"*"`` for the rest). Integer, boolean and text
        columns are always exact. The figure-regression test reads the manifest.
    float_format : str, optional
        Format for floats, e.g. ``"%.4g"``, to keep the CSV stable and readable.
    formats, caption : optional
        How the returned object shows the table on the page (see :func:`show_table`).

    Returns
    -------
    SavedTable
        Shows the table on the page (no index column, one number format per column, "—" for
        missing values); its path is ``.path``. nbval does not compare the table's text
        (the regression test compares the CSV under its tolerances; see
        ``tests/nbval_sanitize.cfg``).

    Raises
    ------
    ValueError
        If a column of non-integer numbers has no declared tolerance
        (:func:`table_manifest`).
    """
    manifest = table_manifest(table, tolerance)
    path = output_path(name, ".csv")
    path.parent.mkdir(parents=True, exist_ok=True)
    write_index = any(n is not None for n in table.index.names)
    table.to_csv(path, index=write_index, float_format=float_format, lineterminator="\n")
    write_manifest(path, manifest)
    return SavedTable(path, name, table.reset_index() if write_index else table, formats=formats,
                      caption=caption)


def _column_format(col) -> "Any":
    """One format for a whole column: integers as they are, floats with a fixed number of
    decimals chosen from the column's magnitude (3 significant digits for its largest value,
    at most 4 decimals)."""
    import pandas as pd

    if pd.api.types.is_bool_dtype(col) or pd.api.types.is_integer_dtype(col):
        return "{}"
    nums = [float(v) for v in col if isinstance(v, (int, float, np.integer, np.floating))
            and not isinstance(v, bool) and np.isfinite(v)]
    if not nums:
        return "{}"
    if all(float(v).is_integer() for v in nums) and max(abs(v) for v in nums) < 1e15:
        return "{:.0f}"
    big = max(abs(v) for v in nums)
    decimals = 0 if big >= 100 else 1 if big >= 10 else 2 if big >= 1 else 3 if big >= 0.1 else 4
    return "{:." + str(decimals) + "f}"


def _cell(v: Any, fmt: str) -> str:
    import html as _html

    if v is None or (isinstance(v, (float, np.floating)) and np.isnan(v)):
        return "—"
    if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
        text = fmt.format(v)
        return "0" + text[2:] if text.startswith("-0") and float(text) == 0 else text.replace("-", "−")
    text = str(v)
    return "—" if text in ("", "nan", "NaN", "None") else _html.escape(text)


def table_html(table: Any, formats: Mapping[str, str] | None = None, caption: str | None = None) -> str:
    """A table as HTML for the book: no index column, one number format per column, "—" for
    missing values, numbers right-aligned, text wrapped, nothing truncated.

    Parameters
    ----------
    table : pandas.DataFrame
    formats : mapping of column name to format, optional
        ``str.format`` patterns (``"{:.2f}"``) or format specs (``".2f"``) for some columns;
        the others get :func:`_column_format`.
    caption : str, optional
        A caption shown above the table.
    """
    import html as _html

    import pandas as pd

    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame, got {type(table).__name__}")
    formats = dict(formats or {})
    unknown = sorted(set(map(str, formats)) - set(map(str, table.columns)))
    if unknown:
        raise ValueError(f"formats names columns the table does not have: {unknown}")
    fmts = []
    for name, col in table.items():
        f = formats.get(str(name))
        if f is None:
            f = _column_format(col)
        elif "{" not in f:
            f = "{:" + f + "}"
        fmts.append(f)
    numeric = [pd.api.types.is_numeric_dtype(col) and not pd.api.types.is_bool_dtype(col) for _, col in table.items()]
    th = 'style="padding:0.3em 0.6em;border-bottom:2px solid #888;text-align:{}"'
    td = 'style="padding:0.25em 0.6em;border-top:1px solid #ddd;text-align:{};vertical-align:top"'
    head = "".join(f"<th {th.format('right' if n else 'left')}>{_html.escape(str(c))}</th>"
                   for c, n in zip(table.columns, numeric))
    rows = []
    for rec in table.itertuples(index=False, name=None):
        rows.append("<tr>" + "".join(f"<td {td.format('right' if n else 'left')}>{_cell(v, f)}</td>"
                                     for v, f, n in zip(rec, fmts, numeric)) + "</tr>")
    cap = (f'<caption style="caption-side:top;text-align:left;font-weight:600;padding:0.2em 0">'
           f'{_html.escape(caption)}</caption>') if caption else ""
    return (f'<table class="pt-table" style="border-collapse:collapse;font-size:0.9em;line-height:1.35;'
            f'margin:0.4em 0 0.8em 0">{cap}<thead><tr>{head}</tr></thead><tbody>{"".join(rows)}</tbody></table>')


class show_table:  # noqa: N801 (used like a function: show_table(df))
    """Show a table that is not saved (a paper's own values, a small summary): nbval compares
    its text exactly, so it may hold only exact numbers or numbers printed far above their
    tolerance. See :func:`table_html` for the parameters."""

    def __init__(self, table: Any, formats: Mapping[str, str] | None = None, caption: str | None = None):
        self._html = table_html(table, formats, caption)
        self._text = table.to_string(index=False)

    def _repr_html_(self) -> str:
        return self._html

    def __repr__(self) -> str:
        return self._text


class SavedTable:
    """What :func:`save_table` returns: shows the saved table on the page.

    Its HTML is wrapped in ``<div class="pt-compared" data-file="figures/<name>.csv">``, which
    ``tests/nbval_sanitize.cfg`` replaces by the file name before nbval compares outputs:
    the numbers are compared by the figure-regression test under the tolerances declared for
    them, not as text. Its plain-text form is the file name.
    """

    def __init__(self, path: Path, name: str, table: Any, formats: Mapping[str, str] | None = None,
                 caption: str | None = None):
        self.path, self.name = path, name
        self._html = table_html(table, formats, caption)

    def __fspath__(self) -> str:
        return str(self.path)

    def _repr_html_(self) -> str:
        return (f'<div class="pt-compared" data-file="figures/{self.name}.csv">{self._html}</div>'
                "<!--/pt-compared-->")

    def __repr__(self) -> str:
        return f"figures/{self.name}.csv"


apply_style()

"""The reproduction scorecard.

Every notebook ends with a :class:`Scorecard`: one row per inventory item it
reproduces, saying what the paper claims, what the paper reports, what the notebook
obtained and a verdict:

``reproduced``
    the same value (deterministic quantities, exact formulas, tables of counts);
``within-tolerance``
    a stochastic or rendering-dependent value within a stated tolerance;
``qualitative``
    the behaviour the paper describes is seen, the number is not comparable;
``differs``
    it does not reproduce; the note says how and the most likely reason;
``not-reproducible``
    the paper gives too little to try; the note says what is missing;
``misprint``
    the printed value contradicts the paper's own other numbers; the note gives the
    proof (which numbers, which arithmetic). Not counted as a failure to reproduce;
``beyond``
    the row is not a claim of the paper (an extension, a baseline, a
    self-consistency check, a sensitivity study). It carries no reproduction verdict
    and is counted apart.

Each inventory id is counted once. An id covered by several rows (its headline row and
sub-rows such as ``PC-F3.peak2d``) shows the weakest verdict among its rows that are not
``beyond`` (:data:`RANK`: ``misprint`` counts as weaker than ``qualitative`` but stronger
than ``differs``), so the verdict shown for an id never looks better than any of its rows;
an id whose rows are all ``beyond`` is ``beyond``.

Numbers inside a row's ``reproduced`` and ``note`` text are compared by the figure-regression
test under the row's ``tolerance=`` (:mod:`projtrack.tolerance`; exact by default), which
:meth:`Scorecard.save` writes to ``figures/<part>/scorecard.tolerance.json``. The verdict is
always compared exactly.

Several notebooks of one part (or chapter) share the file
``figures/<part>/scorecard.csv`` (columns ``item,claim,paper,reproduced,verdict,note``).
Each notebook replaces only its own rows; which notebook wrote which row is kept in
``figures/<part>/scorecard-sources.csv`` (columns ``item,notebook``), read by the
book's Reproducibility summary page.
"""

from __future__ import annotations

import csv
import html
from collections import Counter
import io
import re
from dataclasses import astuple, dataclass, fields
from pathlib import Path

from projtrack._paths import figures_root
from projtrack.inventory import inventory_ids
from projtrack.tolerance import EXACT, Manifest, Tolerance, read_manifest, write_manifest

__all__ = ["VERDICTS", "REPRODUCTION_VERDICTS", "RANK", "NOTE_REQUIRED", "COLUMNS", "COLOURS", "Row", "Scorecard",
           "read_scorecards", "id_verdict", "headline_row", "summary", "badge", "Glance", "scorecard_html", "fold_scorecard"]

#: The verdicts that judge a claim of the paper, from strongest to weakest.
REPRODUCTION_VERDICTS: tuple[str, ...] = (
    "reproduced", "within-tolerance", "qualitative", "misprint", "differs", "not-reproducible")

#: The allowed verdicts: the reproduction verdicts, then ``beyond`` (not a claim of the paper).
VERDICTS: tuple[str, ...] = (*REPRODUCTION_VERDICTS, "beyond")

#: Strength order used to combine sub-rows (lower is stronger); ``beyond`` rows are left out.
RANK: dict[str, int] = {v: i for i, v in enumerate(REPRODUCTION_VERDICTS)}

#: Verdicts whose row must carry a note (the reason, the missing information, or the proof).
NOTE_REQUIRED: tuple[str, ...] = ("differs", "not-reproducible", "misprint", "beyond")

#: Columns of ``scorecard.csv``.
COLUMNS: tuple[str, ...] = ("item", "claim", "paper", "reproduced", "verdict", "note")

#: Colour of each verdict's badge (and of the summary's bars).
COLOURS: dict[str, str] = {
    "reproduced": "#1b7837", "within-tolerance": "#5aae61", "qualitative": "#a6dba0",
    "misprint": "#9970ab", "differs": "#d6604d", "not-reproducible": "#878787", "beyond": "#92c5de",
}
_DARK_TEXT = ("qualitative", "beyond")
#: Columns whose numbers follow a row's own tolerance.
TEXT_COLUMNS: tuple[str, ...] = ("reproduced", "note")

_SOURCES = "scorecard-sources.csv"
_PART = re.compile(r"^[A-Za-z0-9_-]+$")
_SUFFIX = re.compile(r"^[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*$")


@dataclass(frozen=True)
class Row:
    """One scorecard row."""

    item: str
    claim: str
    paper: str
    reproduced: str
    verdict: str
    note: str = ""

    @property
    def base_id(self) -> str:
        """The inventory id without sub-row suffix (``"PC-F3"`` for ``"PC-F3.peak2d"``)."""
        return self.item.split(".", 1)[0]


def _text(value: object, what: str) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (str, int)) and not isinstance(value, bool):
        return str(value).strip()
    raise TypeError(f"{what} must be a str or a number, got {type(value).__name__}")


def _sort_key(item: str, order: dict[str, int]) -> tuple[int, str]:
    return (order.get(item.split(".", 1)[0], len(order)), item)


class Scorecard:
    """Rows of the reproduction scorecard of one notebook.

    Parameters
    ----------
    part : str
        Folder under ``figures/`` shared by the notebooks of one part or chapter
        (``"kvw"``, ``"jpda"``, ...).
    notebook : str
        The notebook's path relative to ``book/`` (``"part3/jpda/feasible-events.ipynb"``),
        shown on the Reproducibility summary page.

    Examples
    --------
    >>> card = Scorecard("jpda", "part3/jpda/feasible-events.ipynb")
    >>> card.add("JPDA-T1", "eq. (1) counts", "Table I", "all 100 equal", "reproduced")
    >>> card.save()  # doctest: +SKIP
    """

    def __init__(self, part: str, notebook: str):
        if not isinstance(part, str) or not _PART.match(part):
            raise ValueError(f"part must be a folder name of letters, digits, '_' or '-', got {part!r}")
        if not isinstance(notebook, str) or not notebook.endswith((".ipynb", ".md")):
            raise ValueError(f"notebook must be a path ending in .ipynb or .md, got {notebook!r}")
        self.part = part
        self.notebook = notebook
        self.rows: list[Row] = []
        #: Item -> the tolerance of the numbers in its text (only rows that are not exact).
        self.tolerances: dict[str, Tolerance] = {}

    def add(self, item: str, claim: object, paper: object, reproduced: object, verdict: str,
            note: object = "", *, tolerance: Tolerance | None = None) -> Row:
        """Add a row and return it.

        Parameters
        ----------
        item : str
            An inventory id (``"JPDA-T1"``), optionally with a sub-row suffix
            (``"PC-F3.peak2d"``).
        claim : str
            What the paper claims, in a few words.
        paper : str or number
            The value or behaviour the paper reports.
        reproduced : str or number
            What this notebook obtained.
        verdict : str
            One of :data:`VERDICTS`.
        note : str, optional
            How it was obtained, the tolerance, or why it differs.
        tolerance : projtrack.tolerance.Tolerance, optional
            The kind of the numbers written in ``reproduced`` and ``note`` (exact when not
            given): a row quoting a Monte Carlo result or anything after a discrete decision
            declares its statistical tolerance here, so the regression test compares those
            numbers within it (:mod:`projtrack.tolerance`).

        Raises
        ------
        ValueError
            If the item is not an inventory id, is already in this scorecard, or the
            verdict is not one of :data:`VERDICTS`; or if a row whose verdict is in
            :data:`NOTE_REQUIRED` (``differs``, ``not-reproducible``, ``misprint``,
            ``beyond``) has no note.
        """
        if not isinstance(item, str):
            raise TypeError(f"item must be a str, got {type(item).__name__}")
        base, _, suffix = item.partition(".")
        if base not in inventory_ids():
            raise ValueError(f"item {item!r}: {base!r} is not an id of the project's inventory")
        if suffix and not _SUFFIX.match(suffix):
            raise ValueError(f"item {item!r}: the sub-row suffix must be letters, digits, '_', '-' or '.'")
        if any(r.item == item for r in self.rows):
            raise ValueError(f"item {item!r} is already in this scorecard")
        if verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {', '.join(VERDICTS)}; got {verdict!r}")
        note_text = _text(note, "note")
        if verdict in NOTE_REQUIRED and not note_text:
            raise ValueError(f"a {verdict!r} verdict needs a note saying why")
        row = Row(item, _text(claim, "claim"), _text(paper, "paper"), _text(reproduced, "reproduced"),
                  verdict, note_text)
        for f in fields(row):
            if "\n" in getattr(row, f.name):
                raise ValueError(f"{f.name} must be a single line")
        if tolerance is not None and not isinstance(tolerance, Tolerance):
            raise TypeError(f"tolerance must be a projtrack.tolerance.Tolerance, got {type(tolerance).__name__}")
        self.rows.append(row)
        if tolerance is not None and not tolerance.is_exact:
            self.tolerances[item] = tolerance
        return row

    # -- display -------------------------------------------------------------------
    def to_frame(self):
        """Return the rows as a :class:`pandas.DataFrame`."""
        import pandas as pd

        return pd.DataFrame([astuple(r) for r in self.rows], columns=list(COLUMNS))

    def _repr_html_(self) -> str:
        return _compared(fold_scorecard(scorecard_html(self.rows)), self.part)

    def __repr__(self) -> str:
        lines = [f"Scorecard({self.part!r}, {self.notebook!r}): {len(self.rows)} rows"]
        lines += [f"  {r.item}: {r.verdict}" for r in self.rows]
        return "\n".join(lines)

    def glance(self) -> "Glance":
        """The page's result at a glance: its rows with paper value, ours and a verdict badge."""
        return Glance(self.rows, self.part)

    def publish(self, headline: object = None) -> "Scorecard":
        """Save the scorecard and glue what the top of the page shows; return it for display.

        Saves (:meth:`save`), then glues (``myst_nb.glue``, not displayed here) the page's
        result at a glance under the name ``glance`` and, when given, the headline figure
        under ``headline``, so that the page's first cell can show them with
        ``{glue:} glance`` and ``{glue:figure} headline``.

        Parameters
        ----------
        headline : projtrack.figures.SavedFigure or str, optional
            The page's headline figure: what :func:`projtrack.figures.save` returned, or its
            name (``"dma/fig9-slot-car"``).
        """
        from myst_nb import glue

        self.save()
        glue("glance", self.glance(), display=False)
        if headline is not None:
            glue("headline", _headline(headline), display=False)
        return self

    # -- files ---------------------------------------------------------------------
    def save(self) -> Path:
        """Merge this notebook's rows into ``figures/<part>/scorecard.csv`` and return its path.

        Rows previously written by the same notebook are replaced; rows of other
        notebooks are kept. Rows are sorted in inventory order.

        Raises
        ------
        ValueError
            If the scorecard is empty, or another notebook already wrote one of its items.
        """
        if not self.rows:
            raise ValueError("the scorecard has no rows")
        folder = figures_root() / self.part
        folder.mkdir(parents=True, exist_ok=True)
        card_path, src_path = folder / "scorecard.csv", folder / _SOURCES
        old_rows = _read_rows(card_path)
        old_src = {r["item"]: r["notebook"] for r in _read_dicts(src_path)}
        kept = [r for r in old_rows if old_src.get(r.item, self.notebook) != self.notebook]
        clash = {r.item for r in kept} & {r.item for r in self.rows}
        if clash:
            raise ValueError(f"items {sorted(clash)} are already in {card_path} from another notebook")
        order = {k: i for i, k in enumerate(inventory_ids())}
        rows = sorted(kept + self.rows, key=lambda r: _sort_key(r.item, order))
        sources = {**{r.item: old_src[r.item] for r in kept}, **{r.item: self.notebook for r in self.rows}}
        old_tols = read_manifest(card_path).rows
        tols = {**{k: v for k, v in old_tols.items() if k in {r.item for r in kept}}, **self.tolerances}
        _write(card_path, COLUMNS, [astuple(r) for r in rows])
        _write(src_path, ("item", "notebook"), [(r.item, sources[r.item]) for r in rows])
        write_manifest(card_path, Manifest({}, "item", TEXT_COLUMNS,
                                           {r.item: tols[r.item] for r in rows if r.item in tols}))
        return card_path


def _read_dicts(path: Path) -> list[dict[str, str]]:
    if not path.is_file():
        return []
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _read_rows(path: Path) -> list[Row]:
    return [Row(**{c: d.get(c) or "" for c in COLUMNS}) for d in _read_dicts(path)]


def _write(path: Path, header: tuple[str, ...], rows: list[tuple[str, ...]]) -> None:
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    path.write_text(buf.getvalue(), encoding="utf-8")


def read_scorecards(root: Path | None = None) -> list[dict[str, str]]:
    """Read every ``<root>/*/scorecard.csv``.

    Returns
    -------
    list of dict
        One dict per row with the :data:`COLUMNS` plus ``part`` (the folder) and
        ``notebook`` (from ``scorecard-sources.csv``, empty if unknown).
    """
    root = figures_root() if root is None else Path(root)
    out = []
    for card in sorted(root.glob("*/scorecard.csv")):
        src = {r["item"]: r["notebook"] for r in _read_dicts(card.parent / _SOURCES)}
        for d in _read_dicts(card):
            out.append({**{c: d.get(c) or "" for c in COLUMNS}, "part": card.parent.name,
                        "notebook": src.get(d.get("item", ""), "")})
    return out


def id_verdict(item: str, rows: list[dict[str, str]]) -> str:
    """Combine the scorecard rows of one inventory id into the id's verdict.

    Parameters
    ----------
    item : str
        The inventory id (``"PC-F3"``).
    rows : list of dict
        Its rows (each with ``item`` and ``verdict``): the headline row (``item`` itself)
        and sub-rows (``"PC-F3.peak2d"``), e.g. from :func:`read_scorecards`.

    Returns
    -------
    str
        The weakest (:data:`RANK`) verdict among the rows that are not ``beyond``, so the
        id never looks better than any of its rows; ``"beyond"`` when every row is
        ``beyond``; ``""`` when there are no rows.
    """
    judged = [r["verdict"] for r in rows if r["verdict"] != "beyond"]
    if judged:
        return max(judged, key=lambda v: RANK.get(v, len(RANK)))
    return "beyond" if rows else ""


def headline_row(item: str, rows: list[dict[str, str]]) -> dict[str, str] | None:
    """The row that speaks for an id: its own row, else its first sub-row (None if none)."""
    own = [r for r in rows if r["item"] == item]
    return own[0] if own else (rows[0] if rows else None)


def summary(root: Path | None = None):
    """Collect every scorecard against the inventory, for the Reproducibility summary page.

    Parameters
    ----------
    root : path-like, optional
        Folder holding ``<part>/scorecard.csv`` files (default: :func:`figures_root`).

    Returns
    -------
    items : pandas.DataFrame
        One row per inventory id, in inventory order, with columns ``id``, ``part``,
        ``kind``, ``item`` (what it is), ``verdict`` (:func:`id_verdict`; empty if not
        covered), ``paper`` and ``ours`` (from the id's :func:`headline_row`), ``rows`` (how
        many scorecard rows cover it), ``beyond rows`` (how many of them are ``beyond``),
        ``sub-row verdicts`` (e.g. ``"2 reproduced, 1 misprint"``, empty for a single row)
        and ``notebook``.
    counts : pandas.DataFrame
        Number of inventory ids per verdict (plus ``not yet covered``).
    """
    import pandas as pd

    from projtrack.inventory import PARTS, load_inventory

    rows = read_scorecards(root)
    by_id: dict[str, list[dict[str, str]]] = {}
    for r in rows:
        by_id.setdefault(r["item"].split(".", 1)[0], []).append(r)
    records = []
    for inv in load_inventory():
        hits = by_id.get(inv.id, [])
        verdict = id_verdict(inv.id, hits)
        notebooks = sorted({h["notebook"] for h in hits if h["notebook"]})
        head = headline_row(inv.id, hits) or {}
        tally = Counter(h["verdict"] for h in hits)
        records.append({
            "id": inv.id, "part": PARTS[inv.prefix][0], "kind": inv.kind, "item": inv.item,
            "verdict": verdict, "paper": head.get("paper", ""), "ours": head.get("reproduced", ""),
            "sub-row verdicts": ", ".join(f"{tally[v]} {v}" for v in VERDICTS if tally[v]) if len(hits) > 1 else "",
            "rows": len(hits),
            "beyond rows": sum(h["verdict"] == "beyond" for h in hits), "notebook": "; ".join(notebooks),
        })
    items = pd.DataFrame.from_records(records)
    labels = [*VERDICTS, "not yet covered"]
    counts = pd.DataFrame({
        "verdict": labels,
        "inventory ids": [int((items["verdict"] == v).sum()) for v in VERDICTS]
        + [int((items["verdict"] == "").sum())],
    })
    return items, counts


# -- how a scorecard looks on a page ------------------------------------------------------------

def badge(verdict: str) -> str:
    """An HTML badge for a verdict, coloured by :data:`COLOURS`."""
    if verdict not in COLOURS:
        raise ValueError(f"verdict must be one of {', '.join(VERDICTS)}; got {verdict!r}")
    fg = "#1a1a1a" if verdict in _DARK_TEXT else "#ffffff"
    return (f'<span class="pt-badge" style="background:{COLOURS[verdict]};color:{fg};padding:0.1em 0.55em;'
            f'border-radius:0.8em;font-size:0.85em;white-space:nowrap;font-weight:600">{html.escape(verdict)}</span>')


def _first_sentence(note: str, limit: int = 160) -> tuple[str, str]:
    """Split a note into its first sentence (the visible reason) and the rest."""
    note = note.strip()
    for stop in (". ", "; "):
        i = note.find(stop)
        if 0 < i < limit:
            return note[: i + 1].rstrip(";") + ("" if stop == ". " else ""), note[i + 2:].strip()
    if len(note) <= limit:
        return note, ""
    cut = note.rfind(" ", 0, limit)
    cut = cut if cut > 0 else limit
    return note[:cut] + " ...", note[cut:].strip()


_TABLE_STYLE = ('style="border-collapse:collapse;width:100%;table-layout:auto;font-size:0.92em;'
                'line-height:1.35"')
_CELL = 'style="padding:0.35em 0.5em;vertical-align:top;border-top:1px solid #d0d0d0;text-align:left"'
_HEAD = 'style="padding:0.35em 0.5em;text-align:left;border-bottom:2px solid #888"'


def _compared(table_html: str, part: str) -> str:
    """Mark HTML whose numbers the regression test compares in the part's scorecard.csv
    (``tests/nbval_sanitize.cfg`` then hides it from nbval's text comparison)."""
    return (f'<div class="pt-compared" data-file="figures/{part}/scorecard.csv">{table_html}</div>'
            "<!--/pt-compared-->")


_ROW_START = f"<tr><td {_CELL}><code>"


def fold_scorecard(table_html: str) -> str:
    """Fold a scorecard table (:func:`scorecard_html`) under a one-line summary: the page's
    result at a glance already shows each claim's values and verdict at the top, so the full
    table with its notes opens on demand. Already folded HTML is returned unchanged."""
    if table_html.startswith('<details class="pt-scorecard-fold">'):
        return table_html
    n = table_html.count(_ROW_START)
    return ('<details class="pt-scorecard-fold"><summary style="cursor:pointer;font-weight:600">'
            f"The scorecard: all {n} rows of this page, with their notes</summary>{table_html}</details>")


def scorecard_html(rows: list[Row]) -> str:
    """The scorecard as a table: item, claim, paper, ours and a verdict badge, with each note
    folded under its row (its first sentence visible)."""
    head = "".join(f"<th {_HEAD}>{h}</th>" for h in ("item", "claim", "paper", "ours", "verdict"))
    body = []
    for r in rows:
        body.append("<tr>" + "".join(f"<td {_CELL}>{v}</td>" for v in (
            f"<code>{html.escape(r.item)}</code>", html.escape(r.claim), html.escape(r.paper),
            html.escape(r.reproduced), badge(r.verdict))) + "</tr>")
        if r.note:
            first, rest = _first_sentence(r.note)
            inner = (f"<details><summary style=\"cursor:pointer\">{html.escape(first)}</summary>"
                     f"<div style=\"margin:0.3em 0 0.2em 1em\">{html.escape(r.note)}</div></details>"
                     if rest else html.escape(first))
            body.append(f'<tr><td></td><td colspan="4" style="padding:0 0.5em 0.45em 0.5em;color:#444;'
                        f'font-size:0.95em">{inner}</td></tr>')
    return f'<table class="pt-scorecard" {_TABLE_STYLE}><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


class Glance:
    """The result at a glance: one line per inventory id of the page, with the claim, the
    paper's value, ours and the id's verdict badge (the weakest of its rows,
    :func:`id_verdict`).

    Shown at the top of a page (glued by :meth:`Scorecard.publish`). The line of an id is its
    headline row (the row named by the id itself, else its first row); ids whose rows are all
    ``beyond`` are left out unless the page has nothing else.
    """

    def __init__(self, rows: list[Row], part: str):
        by_id: dict[str, list[Row]] = {}
        for r in rows:
            by_id.setdefault(r.base_id, []).append(r)
        lines = []
        for base, group in by_id.items():
            dicts = [{"item": r.item, "verdict": r.verdict} for r in group]
            head = next((r for r in group if r.item == base), group[0])
            lines.append((head, id_verdict(base, dicts), len(group)))
        judged = [ln for ln in lines if ln[1] != "beyond"]
        self.lines = judged or lines
        self.part = part

    @property
    def rows(self) -> list[Row]:
        """The headline row of each id shown."""
        return [head for head, _, _ in self.lines]

    def _repr_html_(self) -> str:
        head = "".join(f"<th {_HEAD}>{h}</th>" for h in ("claim", "paper", "ours", "verdict"))
        body = []
        for r, verdict, n in self.lines:
            more = f' <span style="color:#666;font-size:0.8em">(+{n - 1} sub-rows)</span>' if n > 1 else ""
            body.append("<tr>" + "".join(f"<td {_CELL}>{v}</td>" for v in (
                f"{html.escape(r.claim)} <code style=\"font-size:0.8em\">{html.escape(r.base_id)}</code>",
                html.escape(r.paper), html.escape(r.reproduced), badge(verdict) + more)) + "</tr>")
        return _compared(f'<table class="pt-glance" {_TABLE_STYLE}><thead><tr>{head}</tr></thead>'
                         f'<tbody>{"".join(body)}</tbody></table>', self.part)

    def __repr__(self) -> str:
        return "\n".join(f"{r.base_id}: {v}" for r, v, _ in self.lines)


class _Headline:
    """A saved figure, for glueing at the top of a page (shows the PNG, prints its path)."""

    def __init__(self, path: Path, name: str):
        self.path, self.name = path, name

    def _repr_png_(self) -> bytes:
        return self.path.read_bytes()

    def __repr__(self) -> str:
        return f"figures/{self.name}.png"


def _headline(fig: object) -> _Headline:
    if isinstance(fig, str):
        path = figures_root() / f"{fig}.png"
        if not path.is_file():
            raise ValueError(f"headline: no saved figure {fig!r} (save it with projtrack.figures.save first)")
        return _Headline(path, fig)
    path, name = getattr(fig, "path", None), getattr(fig, "name", None)
    if isinstance(path, Path) and isinstance(name, str) and path.is_file():
        return _Headline(path, name)
    raise TypeError("headline must be the name of a saved figure or what projtrack.figures.save returned, "
                    f"got {type(fig).__name__}")

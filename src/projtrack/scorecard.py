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

An inventory id covered by several sub-rows takes its own row's verdict, or else the
weakest verdict among its sub-rows that are not ``beyond`` (:data:`RANK`: ``misprint``
counts as weaker than ``qualitative`` but stronger than ``differs``); an id whose rows
are all ``beyond`` is ``beyond``.

Several notebooks of one part (or chapter) share the file
``figures/<part>/scorecard.csv`` (columns ``item,claim,paper,reproduced,verdict,note``).
Each notebook replaces only its own rows; which notebook wrote which row is kept in
``figures/<part>/scorecard-sources.csv`` (columns ``item,notebook``), read by the
book's Reproducibility summary page.
"""

from __future__ import annotations

import csv
import html
import io
import re
from dataclasses import astuple, dataclass, fields
from pathlib import Path

from projtrack._paths import figures_root
from projtrack.inventory import inventory_ids

__all__ = ["VERDICTS", "REPRODUCTION_VERDICTS", "RANK", "NOTE_REQUIRED", "COLUMNS", "Row", "Scorecard",
           "read_scorecards", "id_verdict", "summary"]

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

    def add(self, item: str, claim: object, paper: object, reproduced: object, verdict: str,
            note: object = "") -> Row:
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
        self.rows.append(row)
        return row

    # -- display -------------------------------------------------------------------
    def to_frame(self):
        """Return the rows as a :class:`pandas.DataFrame`."""
        import pandas as pd

        return pd.DataFrame([astuple(r) for r in self.rows], columns=list(COLUMNS))

    def _repr_html_(self) -> str:
        head = "".join(f"<th>{c}</th>" for c in COLUMNS)
        body = "".join(
            "<tr>" + "".join(f"<td>{html.escape(v)}</td>" for v in astuple(r)) + "</tr>" for r in self.rows
        )
        return f'<table class="scorecard"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'

    def __repr__(self) -> str:
        lines = [f"Scorecard({self.part!r}, {self.notebook!r}): {len(self.rows)} rows"]
        lines += [f"  {r.item}: {r.verdict}  ({r.reproduced})" for r in self.rows]
        return "\n".join(lines)

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
        _write(card_path, COLUMNS, [astuple(r) for r in rows])
        _write(src_path, ("item", "notebook"), [(r.item, sources[r.item]) for r in rows])
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
        Its rows (each with ``item`` and ``verdict``), e.g. from :func:`read_scorecards`.

    Returns
    -------
    str
        The verdict of the id's own row if there is one; otherwise the weakest
        (:data:`RANK`) verdict among the sub-rows that are not ``beyond``; ``"beyond"``
        when every row is ``beyond``; ``""`` when there are no rows.
    """
    own = [r["verdict"] for r in rows if r["item"] == item]
    if own:
        return own[0]
    judged = [r["verdict"] for r in rows if r["verdict"] != "beyond"]
    if judged:
        return max(judged, key=lambda v: RANK.get(v, len(RANK)))
    return "beyond" if rows else ""


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
        covered), ``rows`` (how many scorecard rows cover it), ``beyond rows`` (how many
        of them are ``beyond``) and ``notebook``.
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
        records.append({
            "id": inv.id, "part": PARTS[inv.prefix][0], "kind": inv.kind, "item": inv.item,
            "verdict": verdict, "rows": len(hits),
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

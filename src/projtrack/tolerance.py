"""How closely a number the book compares must match on another machine: its kind and tolerance.

The book's tests compare every number a notebook shows or saves with the committed one
(nbval for printed text, ``tests/test_figure_regression.py`` for the tables of
``figures/``). A number has one of three kinds, each with a tolerance that follows from
what the number is, declared where the number is made (:func:`projtrack.figures.save_table`
and :meth:`projtrack.scorecard.Scorecard.add` take a ``tolerance=``):

``exact``
    counts, integers, strings, closed forms with exact results and the papers' own values:
    equal or different, nothing in between. Integer and text columns of a table are always
    exact.
``numerical``
    the output of a solver, an iteration or a floating-point formula: it can differ in its
    last bits from one CPU or BLAS kernel to another, so it carries a relative and/or
    absolute tolerance above the solver's own tolerance (or above rounding, ``1e-9``
    relative for a direct formula).
``statistical``
    a Monte Carlo summary, or anything downstream of a discrete decision (a k-means or EM
    assignment, a Viterbi path, a threshold, a peak picker): a last-bit difference can flip
    one decision, so the number may move by the size of one flip. :func:`share` (a share
    of N trials moves by 1/N) and :func:`mean_over` (a mean over N items moves by one
    item's worth) build the common cases; :func:`statistical` takes any other, with the
    reason.

A table stored with a fixed number of digits (``float_format="%.4g"``) can also move by one
unit of its last stored digit when the unrounded value sits on a rounding boundary; the
comparison of a non-exact number allows that too (:meth:`Tolerance.allows`), so a declared
tolerance stays the size of the effect itself.

Printed text follows the same rule: a numerical number is printed at a precision far above
its tolerance (:mod:`projtrack.stable`); a statistical one is shown in a table or a scorecard
that the regression test compares by its tolerance, and the cell's text output is left out of
nbval (the ``nbval-ignore-output`` tag, with a comment in the cell saying which file compares
it).
"""

from __future__ import annotations

import math
import re
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

__all__ = ["KINDS", "Tolerance", "EXACT", "ROUNDING", "exact", "numerical", "statistical", "share", "mean_over",
           "last_digit_unit", "split_numbers", "text_matches", "table_differences", "moved_numbers",
           "cell_matches", "Manifest", "MANIFEST_SUFFIX", "manifest_path", "write_manifest", "read_manifest"]

#: The kinds of compared numbers.
KINDS: tuple[str, ...] = ("exact", "numerical", "statistical")

_NUMBER = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$")


def _nonneg(x: object, name: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise TypeError(f"{name} must be a real number, got {type(x).__name__}")
    x = float(x)
    if not math.isfinite(x) or x < 0:
        raise ValueError(f"{name} must be finite and >= 0, got {x}")
    return x


@dataclass(frozen=True)
class Tolerance:
    """The kind of a compared number and how far it may move.

    Parameters
    ----------
    kind : {"exact", "numerical", "statistical"}
        See the module docstring.
    atol, rtol : float, default 0
        Absolute and relative tolerance: ``actual`` matches ``expected`` when
        ``|actual - expected| <= atol + rtol * |expected|`` (plus one unit of the last stored
        digit, see :meth:`allows`). Both 0 for ``exact``; at least one positive otherwise.
    why : str
        What the tolerance is the size of (required unless ``exact``), e.g. "one of 200
        trials". It is written into the table's manifest beside the CSV.
    """

    kind: str
    atol: float = 0.0
    rtol: float = 0.0
    why: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {', '.join(KINDS)}; got {self.kind!r}")
        atol, rtol = _nonneg(self.atol, "atol"), _nonneg(self.rtol, "rtol")
        object.__setattr__(self, "atol", atol)
        object.__setattr__(self, "rtol", rtol)
        if not isinstance(self.why, str):
            raise TypeError(f"why must be a str, got {type(self.why).__name__}")
        if self.kind == "exact":
            if atol or rtol:
                raise ValueError("an exact number has no tolerance (atol = rtol = 0)")
        else:
            if not (atol or rtol):
                raise ValueError(f"a {self.kind} number needs atol > 0 or rtol > 0")
            if not self.why.strip():
                raise ValueError(f"a {self.kind} tolerance needs why=: what it is the size of")
            if rtol >= 1:
                raise ValueError(f"rtol must be below 1 (a tolerance, not a blanket), got {rtol}")

    @property
    def is_exact(self) -> bool:
        """True for the ``exact`` kind."""
        return self.kind == "exact"

    def allows(self, expected: Any, actual: Any) -> bool:
        """Whether ``actual`` matches ``expected`` under this tolerance.

        Parameters
        ----------
        expected, actual : str or number
            The committed and the fresh value. Strings are compared as text when either is
            not a number. For a non-exact tolerance, a number given as text may also differ
            by one unit of the last digit written in ``expected`` (:func:`last_digit_unit`):
            a table stored with a fixed number of digits flips that digit when the value
            sits on a rounding boundary.

        Returns
        -------
        bool
        """
        if isinstance(expected, str) and isinstance(actual, str):
            if expected == actual:
                return True
            if not (_NUMBER.match(expected) and _NUMBER.match(actual)):
                return False
            unit = last_digit_unit(expected)
        else:
            unit = 0.0
        if self.is_exact:
            return _as_float(expected) == _as_float(actual)
        e, a = _as_float(expected), _as_float(actual)
        if math.isnan(e) or math.isnan(a):
            return math.isnan(e) and math.isnan(a)
        if math.isinf(e) or math.isinf(a):
            return e == a
        return abs(a - e) <= self.atol + self.rtol * abs(e) + unit * (1 + 1e-9)

    def as_dict(self) -> dict[str, Any]:
        """The tolerance as a JSON-ready dict (``kind`` only for ``exact``; ``atol`` and ``rtol``
        to three significant digits, so the manifest does not depend on the last bits of a
        tolerance computed from data)."""
        if self.is_exact:
            return {"kind": "exact"}
        return {"kind": self.kind, "atol": float(f"{self.atol:.3g}"), "rtol": float(f"{self.rtol:.3g}"),
                "why": self.why}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Tolerance":
        """The inverse of :meth:`as_dict`."""
        if not isinstance(d, Mapping) or "kind" not in d:
            raise ValueError(f"a tolerance must be a mapping with a 'kind', got {d!r}")
        return cls(d["kind"], d.get("atol", 0.0), d.get("rtol", 0.0), d.get("why", ""))

    def __str__(self) -> str:
        if self.is_exact:
            return "exact"
        parts = [f"atol {self.atol:g}" if self.atol else "", f"rtol {self.rtol:g}" if self.rtol else ""]
        return f"{self.kind} ({', '.join(p for p in parts if p)}: {self.why})"


def _as_float(x: Any) -> float:
    if isinstance(x, str):
        return float(x)
    if isinstance(x, bool):
        return float(x)
    return float(x)


def last_digit_unit(text: str) -> float:
    """One unit of the last digit written in a number's text.

    Examples
    --------
    >>> last_digit_unit("0.6385")
    0.0001
    >>> last_digit_unit("1.5e-05")
    1e-06
    >>> last_digit_unit("120")
    1.0
    """
    if not isinstance(text, str) or not _NUMBER.match(text):
        raise ValueError(f"text must be a number written in decimal, got {text!r}")
    s = text.strip().lstrip("+-")
    mant, _, exp = s.lower().partition("e")
    decimals = len(mant.split(".", 1)[1]) if "." in mant else 0
    return float(f"1e{int(exp or 0) - decimals}")


#: Integers, text, closed forms and the papers' values.
EXACT = Tolerance("exact")

#: A direct floating-point computation (no iteration, no decision): only the last bits move.
ROUNDING = Tolerance("numerical", atol=1e-12, rtol=1e-9,
                     why="a direct floating-point computation: only the last bits differ between CPUs")


def exact() -> Tolerance:
    """The ``exact`` kind (:data:`EXACT`)."""
    return EXACT


def numerical(*, rtol: float = 0.0, atol: float = 0.0, why: str) -> Tolerance:
    """A solver's or an iteration's output, with a tolerance above the solver's.

    Examples
    --------
    >>> numerical(rtol=1e-6, why="SCS stops at 1e-8 relative").kind
    'numerical'
    """
    return Tolerance("numerical", atol=atol, rtol=rtol, why=why)


def statistical(*, atol: float = 0.0, rtol: float = 0.0, why: str) -> Tolerance:
    """A Monte Carlo summary or a number downstream of a discrete decision.

    ``why`` says what one flipped decision is worth, e.g. "a Viterbi path that changes over
    a few frames moves the mean over 593 frames by about 2 px / 593".
    """
    return Tolerance("statistical", atol=atol, rtol=rtol, why=why)


def share(n_trials: int, *, flips: int = 1, percent: bool = False) -> Tolerance:
    """A share (or a percentage) of ``n_trials`` trials: it moves by ``flips / n_trials``.

    Parameters
    ----------
    n_trials : int
        The number of trials the share is taken over (>= 1).
    flips : int, default 1
        How many trials may change their outcome.
    percent : bool, default False
        True when the share is written in percent.

    Examples
    --------
    >>> share(200).atol
    0.005
    >>> share(200, percent=True).atol
    0.5
    """
    if isinstance(n_trials, bool) or not isinstance(n_trials, int) or n_trials < 1:
        raise ValueError(f"n_trials must be an int >= 1, got {n_trials!r}")
    if isinstance(flips, bool) or not isinstance(flips, int) or flips < 1:
        raise ValueError(f"flips must be an int >= 1, got {flips!r}")
    if not isinstance(percent, bool):
        raise TypeError(f"percent must be a bool, got {type(percent).__name__}")
    scale = 100.0 if percent else 1.0
    what = "trial" if flips == 1 else "trials"
    return statistical(atol=scale * flips / n_trials,
                       why=f"a share of {n_trials} trials: {flips} {what} changing outcome moves it by "
                           f"{flips}/{n_trials}")


def mean_over(n_items: int, per_item: float, *, flips: int = 1, what: str = "item") -> Tolerance:
    """A mean over ``n_items`` items, any ``flips`` of which may change by up to ``per_item``.

    Parameters
    ----------
    n_items : int
        Number of items averaged (frames, trials, targets), >= 1.
    per_item : float
        How much one item's value can change when its decision flips (in the number's unit),
        > 0.
    flips : int, default 1
        How many items may flip.
    what : str, default "item"
        The name of an item, for the manifest ("frame", "trial").

    Examples
    --------
    >>> round(mean_over(593, 2.0, what="frame").atol, 6)
    0.003373
    """
    if isinstance(n_items, bool) or not isinstance(n_items, int) or n_items < 1:
        raise ValueError(f"n_items must be an int >= 1, got {n_items!r}")
    per = _nonneg(per_item, "per_item")
    if per == 0:
        raise ValueError("per_item must be > 0")
    if isinstance(flips, bool) or not isinstance(flips, int) or flips < 1:
        raise ValueError(f"flips must be an int >= 1, got {flips!r}")
    if not isinstance(what, str) or not what.strip():
        raise ValueError("what must be a non-empty str")
    return statistical(atol=flips * per / n_items,
                       why=f"a mean over {n_items} {what}s: {flips} {what}{'s' if flips > 1 else ''} "
                           f"changing by up to {per:g} moves it by {flips} x {per:g} / {n_items}")


# -- comparing stored tables and text ---------------------------------------------------------

#: A number inside text: not part of a word (``F9``, ``x2``), with an optional sign and exponent.
_TOKEN = re.compile(r"(?<![A-Za-z_\d])[-+]?(?:\d+(?:\.\d+)?|(?<!\.)\.\d+)(?:[eE][-+]?\d+)?")


def split_numbers(text: str) -> tuple[list[str], list[str]]:
    """Split text into its words between numbers and the numbers themselves.

    Returns
    -------
    skeleton : list of str
        The text between the numbers (one more item than ``numbers``).
    numbers : list of str
        The numbers as written.

    Examples
    --------
    >>> split_numbers("error 0.64 px over 8 videos (DMA-F9)")
    (['error ', ' px over ', ' videos (DMA-F9)'], ['0.64', '8'])
    """
    if not isinstance(text, str):
        raise TypeError(f"text must be a str, got {type(text).__name__}")
    numbers = _TOKEN.findall(text)
    skeleton = _TOKEN.split(text)
    return skeleton, numbers


def text_matches(expected: str, actual: str, tolerance: Tolerance) -> bool:
    """Whether two texts are equal, with the numbers in them compared under ``tolerance``.

    The words between the numbers must be equal; each number must match its counterpart
    (:meth:`Tolerance.allows`). With an exact tolerance this is plain string equality.
    """
    if expected == actual:
        return True
    if tolerance.is_exact:
        return False
    e_skel, e_num = split_numbers(expected)
    a_skel, a_num = split_numbers(actual)
    if e_skel != a_skel or len(e_num) != len(a_num):
        return False
    return all(tolerance.allows(e, a) for e, a in zip(e_num, a_num))


def cell_matches(expected: str, actual: str, tolerance: Tolerance) -> bool:
    """Whether a stored cell matches: a number under ``tolerance``, text with its numbers
    compared under ``tolerance`` (:func:`text_matches`)."""
    if expected == actual:
        return True
    if _NUMBER.match(expected) and _NUMBER.match(actual):
        return tolerance.allows(expected, actual)
    return text_matches(expected, actual, tolerance)


#: File written beside ``<name>.csv``: ``<name>.tolerance.json``.
MANIFEST_SUFFIX = ".tolerance.json"


@dataclass
class Manifest:
    """The tolerances of one stored table (the ``<name>.tolerance.json`` beside its CSV).

    Parameters
    ----------
    columns : dict of str to Tolerance
        The tolerance of each column by header name; a column not listed is exact.
    row_key : str, optional
        For tables whose rows carry their own tolerance (the scorecard): the column holding
        each row's key.
    row_columns : tuple of str
        The columns a row's own tolerance applies to (text with numbers in it).
    rows : dict of str to Tolerance
        Row key -> tolerance; rows not listed keep the column tolerances.
    """

    columns: dict[str, Tolerance] = field(default_factory=dict)
    row_key: str = ""
    row_columns: tuple[str, ...] = ()
    rows: dict[str, Tolerance] = field(default_factory=dict)

    def tolerances(self, header: list[str], row: list[str]) -> list[Tolerance]:
        """The tolerance of each cell of one row."""
        tols = [self.columns.get(name, EXACT) for name in header]
        if self.row_key and self.row_key in header:
            own = self.rows.get(row[header.index(self.row_key)])
            if own is not None:
                tols = [own if name in self.row_columns else t for name, t in zip(header, tols)]
        return tols

    def as_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"columns": {k: v.as_dict() for k, v in self.columns.items()}}
        if self.row_key:
            d["rows"] = {"key": self.row_key, "columns": list(self.row_columns),
                         "tolerances": {k: v.as_dict() for k, v in self.rows.items()}}
        return d

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Manifest":
        columns = {k: Tolerance.from_dict(v) for k, v in d.get("columns", {}).items()}
        rows = d.get("rows") or {}
        return cls(columns, rows.get("key", ""), tuple(rows.get("columns", ())),
                   {k: Tolerance.from_dict(v) for k, v in rows.get("tolerances", {}).items()})


def manifest_path(csv_path: str | Path) -> Path:
    """``<name>.tolerance.json`` for ``<name>.csv``."""
    p = Path(csv_path)
    if p.suffix != ".csv":
        raise ValueError(f"csv_path must end in .csv, got {str(csv_path)!r}")
    return p.with_name(p.name[: -len(".csv")] + MANIFEST_SUFFIX)


def write_manifest(csv_path: str | Path, manifest: Manifest) -> Path:
    """Write ``manifest`` beside ``csv_path`` (deterministic JSON) and return its path."""
    if not isinstance(manifest, Manifest):
        raise TypeError(f"manifest must be a Manifest, got {type(manifest).__name__}")
    path = manifest_path(csv_path)
    path.write_text(json.dumps(manifest.as_dict(), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    return path


def read_manifest(csv_path: str | Path) -> Manifest:
    """The manifest beside ``csv_path``; every column exact when there is none."""
    path = manifest_path(csv_path)
    if not path.is_file():
        return Manifest()
    return Manifest.from_dict(json.loads(path.read_text(encoding="utf-8")))


def table_differences(expected: list[list[str]], actual: list[list[str]], manifest: Manifest | None = None,
                      *, limit: int = 5) -> list[str]:
    """The cells of a stored table that do not match, each described in one line.

    Parameters
    ----------
    expected, actual : list of list of str
        The committed and the fresh CSV, rows of text, the header first.
    manifest : Manifest, optional
        The table's tolerances (default: every cell exact).
    limit : int, default 5
        Stop after this many differences.

    Returns
    -------
    list of str
        Empty when the tables match.
    """
    manifest = manifest or Manifest()
    if not expected or not actual:
        return [] if expected == actual else ["one table is empty"]
    header = expected[0]
    if header != actual[0]:
        return [f"header {actual[0]} instead of {header}"]
    if len(expected) != len(actual):
        return [f"{len(actual) - 1} rows instead of {len(expected) - 1}"]
    out: list[str] = []
    for i, (er, ar) in enumerate(zip(expected[1:], actual[1:]), start=1):
        if len(er) != len(ar):
            out.append(f"row {i}: {len(ar)} cells instead of {len(er)}")
        else:
            for name, tol, e, a in zip(header, manifest.tolerances(header, er), er, ar):
                if not cell_matches(e, a, tol):
                    out.append(f"row {i}, column {name!r}: {a!r} instead of {e!r} ({tol})")
        if len(out) >= limit:
            break
    return out


def moved_numbers(expected: list[list[str]], actual: list[list[str]],
                  manifest: Manifest | None = None) -> list[dict[str, Any]]:
    """Every number of a stored table that changed at all, with what its tolerance allows.

    For the cross-check report: unlike :func:`table_differences` it lists changes within
    tolerance too. A change that is not a change of numbers (other text, another shape) has
    ``delta = inf``.

    Returns
    -------
    list of dict
        Keys ``row``, ``column``, ``expected``, ``actual``, ``delta`` (absolute change),
        ``allowed`` (what the tolerance allows there; 0 for exact), ``tolerance`` (its text)
        and ``ok`` (whether the cell matches).
    """
    manifest = manifest or Manifest()
    if not expected or not actual or expected[0] != actual[0] or len(expected) != len(actual):
        return [{"row": -1, "column": "", "expected": "", "actual": "", "delta": math.inf, "allowed": 0.0,
                 "tolerance": "the table's shape changed", "ok": False}]
    header = expected[0]
    out: list[dict[str, Any]] = []
    for i, (er, ar) in enumerate(zip(expected[1:], actual[1:]), start=1):
        if len(er) != len(ar):
            out.append({"row": i, "column": "", "expected": "", "actual": "", "delta": math.inf,
                        "allowed": 0.0, "tolerance": "the row's length changed", "ok": False})
            continue
        for name, tol, e, a in zip(header, manifest.tolerances(header, er), er, ar):
            if e == a:
                continue
            ok = cell_matches(e, a, tol)
            if _NUMBER.match(e) and _NUMBER.match(a):
                pairs = [(e, a)]
            else:
                (es, en), (as_, an) = split_numbers(e), split_numbers(a)
                pairs = [(x, y) for x, y in zip(en, an) if x != y] if es == as_ and len(en) == len(an) else []
                if not pairs:
                    out.append({"row": i, "column": name, "expected": e, "actual": a, "delta": math.inf,
                                "allowed": 0.0, "tolerance": str(tol), "ok": ok})
                    continue
            for x, y in pairs:
                allowed = 0.0 if tol.is_exact else tol.atol + tol.rtol * abs(float(x)) + last_digit_unit(x)
                out.append({"row": i, "column": name, "expected": x, "actual": y,
                            "delta": abs(float(y) - float(x)), "allowed": allowed, "tolerance": str(tol),
                            "ok": ok})
    return out

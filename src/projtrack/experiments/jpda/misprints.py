"""Evidence behind the JPDA chapter's readings of Tables III-VI.

The paper's operation-count tables (IV, V) differ from the instrumented counts in a few
cells; these functions decide which value the paper's other tables support.
:func:`multiplication_rules` and :func:`rule_fits` test a multiplications-per-matrix rule
against Table IV; :func:`table5_additions_rule` and :func:`table5_additions_proof` test
Table V's additions against Table III's vector sizes; :func:`ratio_fits` and
:func:`supported_value` read Table VI's printed savings ratios as evidence.
:func:`grows_geometrically`, :func:`growth_readings` and :func:`relative_growth_table`
tabulate three readings of the claim that the vector length "does not increase
appreciably" (Sec. III.B), each run on a baseline.
:func:`misprint_evidence` gathers, for every cell where Tables IV or V differ from the
instrumented counts, the arithmetic that proves it misprinted, and
:func:`count_table_verdict` turns it into a table's verdict. :func:`fast_count_readings` pins which words a stage of the fast algorithm computes on one
printed Table V cell and judges the reading on the others.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence

import numpy as np
import pandas as pd

from projtrack._validation import as_bool, as_int, as_real
from projtrack.jpda import count_feasible_events, vector_size

from .optables import all_ones_mvm, beta_in_situ, half_up

__all__ = ["multiplication_rules", "rule_fits", "multiplication_rule_table",
           "table5_additions_rule", "table5_additions_proof", "ratio_fits", "supported_value",
           "grows_geometrically", "growth_readings", "relative_growth_table", "RELATIVE_FALL",
           "row_growth", "fast_count_readings", "misprint_evidence",
           "count_table_verdict"]

Cell = tuple[int, int]
Counts = Mapping[Cell, tuple[int, int]]


def _cell(k: object, name: str = "k") -> Cell:
    if not isinstance(k, tuple) or len(k) != 2:
        raise TypeError(f"{name} must be a tuple (m, T), got {k!r}")
    return as_int(k[0], f"{name}[0]", minimum=1), as_int(k[1], f"{name}[1]", minimum=1)


def multiplication_rules() -> dict[str, Callable[[int, int], int]]:
    """Candidate multiplication counts of the conventional enumeration (Table IV).

    Each rule maps ``(m, T)`` to the number of feasible events of eq. (1)
    (:func:`projtrack.jpda.count_feasible_events`) times the multiplications per
    feasibility matrix: ``T - 1`` (one product over the targets), ``m - 1`` (over the
    rows) or ``m`` (as the text says).
    """
    return {"T - 1 (per target)": lambda m, T: count_feasible_events(m, T) * (T - 1),
            "m - 1 (per row)": lambda m, T: count_feasible_events(m, T) * (m - 1),
            "m (the text)": lambda m, T: count_feasible_events(m, T) * m}


def rule_fits(rule: Callable[[int, int], int], printed: Counts, index: int = 1,
              exclude: Iterable[Cell] = ()) -> tuple[int, list[Cell]]:
    """How many cells of ``printed`` (component ``index``) ``rule(m, T)`` equals, and the misfits.

    Cells in ``exclude`` (e.g. the cell that calibrated the rule) are not judged.
    Returns ``(number of fitting cells, list of misfitting cells)``, in ``printed``'s order.
    """
    if not callable(rule):
        raise TypeError(f"rule must be callable, got {type(rule).__name__}")
    index = as_int(index, "index", minimum=0, maximum=1)
    skip = {_cell(k, "exclude[]") for k in exclude}
    judged = [k for k in printed if _cell(k, "printed key") not in skip]
    misfits = [k for k in judged if rule(*k) != printed[k][index]]
    return len(judged) - len(misfits), misfits


def multiplication_rule_table(printed: Counts, cells: Sequence[Cell] = ((7, 3), (7, 7))) -> pd.DataFrame:
    """One row per rule of :func:`multiplication_rules`: cells of ``printed`` (Table IV) it fits.

    Columns: ``cells of Table IV equal`` (multiplications) and the rule's value at each of
    ``cells``, labelled ``m = 7, T = 3`` or ``m = T = 7``.
    """
    cells = [_cell(k, "cells[]") for k in cells]
    rows = []
    for name, f in multiplication_rules().items():
        row = {"multiplications per matrix": name,
               "cells of Table IV equal": rule_fits(f, printed)[0]}
        for m, T in cells:
            row[f"m = T = {m}" if m == T else f"m = {m}, T = {T}"] = f(m, T)
        rows.append(row)
    return pd.DataFrame(rows).set_index("multiplications per matrix")


def table5_additions_rule(m: int, T: int) -> int:
    """Table V additions from Table III: ``m T sum_{k=0}^{T-2} V(m - 1, T - k)``.

    ``V`` is :func:`projtrack.jpda.vector_size`; ``m`` and ``T`` are at least 2.
    """
    m = as_int(m, "m", minimum=2)
    T = as_int(T, "T", minimum=2)
    return m * T * sum(vector_size(m - 1, T - k) for k in range(T - 1))


def table5_additions_proof(k: Cell, ours: Counts, printed: Counts,
                           table3_sizes: Sequence[int] = range(3, 8)) -> tuple[bool, str]:
    """Does Table III's rule prove the printed Table V additions at cell ``k`` a misprint?

    Proven when :func:`table5_additions_rule` reproduces the printed additions of every
    other cell of ``printed``, all of them are multiples of ``m T`` while the printed value
    at ``k`` is not, and the rule gives our count ``ours[k]``. Returns ``(proven, text)``,
    the text giving the numbers; a size ``V`` outside the printed Table III (rows and
    columns ``table3_sizes``) is named as such: it comes from the formula the 25 printed
    sizes follow, not from the table.
    """
    k = _cell(k)
    if k not in printed or k not in ours:
        raise ValueError(f"k = {k} must be a cell of both ours and printed")
    others = [q for q in printed if q != k]
    fits = sum(table5_additions_rule(*q) == printed[q][0] for q in others)
    multiples = sum(printed[q][0] % (q[0] * q[1]) == 0 for q in others)
    mT = k[0] * k[1]
    p = printed[k][0]
    rule_k = table5_additions_rule(*k)
    proven = (fits == len(others) and multiples == len(others) and p % mT != 0
              and rule_k == ours[k][0])
    shown = {as_int(x, "table3_sizes[]", minimum=1) for x in table3_sizes}
    sizes = [(k[0] - 1, k[1] - i) for i in range(k[1] - 1)]
    terms = " + ".join(str(vector_size(*v)) for v in sizes)
    outside = [v for v in sizes if v[0] not in shown or v[1] not in shown]
    text = (f"the rule additions = mT sum_(k=0..T-2) V(m-1, T-k) (V: the vector length, "
            f"sum_(j >= max(0, m-T+1)) C(m, j), which gives all 25 printed Table III sizes) "
            f"reproduces {fits}/{len(others)} other printed additions cells and {multiples}/{len(others)} "
            f"of them are multiples of mT; the printed {p} is not ({p}/{mT} = "
            f"{p / mT:.2f}); the rule gives {mT} x ({terms}) = {rule_k}")
    if outside:
        text += ("; " + ", ".join(f"V({a}, {b}) = {vector_size(a, b)}" for a, b in outside)
                 + " lie" + ("s" if len(outside) == 1 else "") + " outside the printed Table III: "
                 "from its formula, as V(m-1, 2) is in every cell the rule fits")
    return proven, text


def ratio_fits(printed: Sequence[float], num: Sequence[int], den: Sequence[int]) -> bool:
    """Does a printed Table VI cell equal ``num / den`` rounded half-up, for both components?

    ``printed``, ``num`` and ``den`` are (additions, multiplications) pairs; the rounding
    is :func:`~projtrack.experiments.jpda.half_up`.
    """
    pairs = [tuple(x) for x in (printed, num, den)]
    if any(len(x) != 2 for x in pairs):
        raise ValueError("printed, num and den must be (additions, multiplications) pairs")
    return all(half_up(a, b) == as_real(p, "printed[]") for a, b, p in zip(num, den, printed))


def supported_value(fits_ours: bool, fits_printed: bool) -> str:
    """Which value Table VI supports: ``"ours"``, ``"ours+paper"``, ``"paper"`` or ``""`` (neither)."""
    as_bool(fits_ours, "fits_ours")
    as_bool(fits_printed, "fits_printed")
    return {(True, False): "ours", (True, True): "ours+paper",
            (False, True): "paper", (False, False): ""}[bool(fits_ours), bool(fits_printed)]


def grows_geometrically(lengths: Mapping[int, float] | pd.Series, start: int = 5,
                        factor: float = 1.9) -> bool:
    """True when ``lengths`` (keyed by ``n``) grows by at least ``factor`` at every step from ``start``.

    The steps run from ``n = start`` to the largest ``n`` (at least one step needed).
    """
    start = as_int(start, "start")
    factor = as_real(factor, "factor", 0, low_open=True)
    s = pd.Series(lengths).sort_index().loc[start:].to_numpy(dtype=float)
    if len(s) < 2:
        raise ValueError(f"lengths must hold at least two values from n = {start}")
    return bool((s[1:] / s[:-1] >= factor).all())


def _span(r: Sequence[int]) -> str:
    return f"{r[0]}..{r[-1]}"


#: Reading 2 of the growth remark: the length over eq. (1) must fall at least this much per step.
RELATIVE_FALL = 2.0


def _relative_candidates() -> dict[str, Callable[[int], int]]:
    """Sizes along ``m = T = n`` judged against eq. (1) by reading 2 (the length and baselines)."""
    from math import factorial

    return {"vector length (Table III)": lambda n: vector_size(n, n),
            "eq. (1) itself": lambda n: count_feasible_events(n, n),
            "eq. (1) of m - 1, T - 1": lambda n: count_feasible_events(n - 1, n - 1),
            "n!": factorial,
            "n 2^n": lambda n: n * 2**n}


def relative_growth_table(diag: Sequence[int] = range(3, 8)) -> pd.DataFrame:
    """Reading 2 of "does not increase appreciably", run on the length and on baselines.

    For each candidate size along ``m = T = n`` (the Table III length, eq. (1) itself, eq. (1)
    of the problem one size smaller, ``n!`` and ``n 2^n``), the factor by which
    ``size / eq. (1)`` falls at each step of ``diag`` (smallest and largest) and whether it
    falls by at least :data:`RELATIVE_FALL` at every step. Eq. (1) and its smaller problem
    grow combinatorially and must fail; an exponential size is small next to eq. (1) and
    passes, as the reading intends.
    """
    diag = [as_int(x, "diag[]", minimum=2) for x in diag]
    if len(diag) < 2:
        raise ValueError("diag needs at least two sizes")
    rows = []
    for name, f in _relative_candidates().items():
        r = [f(n) / count_feasible_events(n, n) for n in diag]
        falls = [a / b for a, b in zip(r[:-1], r[1:])]
        rows.append({"size along m = T": name, "smallest fall per step": min(falls),
                     "largest fall per step": max(falls),
                     f"falls >= {RELATIVE_FALL:g}x at every step": bool(min(falls) >= RELATIVE_FALL)})
    return pd.DataFrame(rows)


def growth_readings(growth: pd.DataFrame, diag: Sequence[int] = range(3, 8)) -> pd.DataFrame:
    """Two readings of "the vector length does not increase appreciably", each with a baseline.

    1. *absolute, along* ``m = T``: the claim holds unless :func:`grows_geometrically` judges
       ``growth["vector length"]`` (a :func:`~projtrack.experiments.jpda.vector_growth`
       table) geometric; the baseline ``n + 1`` (the length of a column of beta), which does
       not grow appreciably, must pass.
    2. *relative to eq. (1)*, the comparison the text itself makes: the length over the event
       count falls by at least :data:`RELATIVE_FALL` at every step along ``m = T`` in ``diag``;
       the baseline eq. (1) of the problem one size smaller, which grows combinatorially,
       must fail (:func:`relative_growth_table` runs more baselines).

    The growth in ``T`` at fixed ``m`` is not a reading: the length is capped at ``2^m`` once
    ``T > m`` by construction (:func:`row_growth` reports it).

    One row per reading: ``values`` (what the length gives), ``claim holds``, ``baseline`` and
    ``baseline holds``.
    """
    if not isinstance(growth, pd.DataFrame) or "vector length" not in growth:
        raise TypeError("growth must be a vector_growth table (a DataFrame with 'vector length')")
    diag = [as_int(x, "diag[]", minimum=2) for x in diag]
    if len(diag) < 2:
        raise ValueError("diag needs at least two sizes")
    lengths = growth["vector length"]
    n = lengths.index
    step = lengths.iloc[-1] / lengths.iloc[-2]
    rel = relative_growth_table(diag).set_index("size along m = T")
    ok2 = f"falls >= {RELATIVE_FALL:g}x at every step"
    return pd.DataFrame([
        {"reading": "1. absolute, along m = T",
         "values": ", ".join(str(vector_size(i, i)) for i in diag)
         + f" (m = T = {_span(diag)}); x{step:.2f} from {n[-2]} to {n[-1]}",
         "claim holds": not grows_geometrically(lengths),
         "baseline": "m + 1 (a column of beta)",
         "baseline holds": not grows_geometrically({i: i + 1 for i in n})},
        {"reading": "2. relative to eq. (1)",
         "values": f"falls x{rel.iloc[0, 0]:.1f} to x{rel.iloc[0, 1]:.1f} per step (m = T = {_span(diag)})",
         "claim holds": bool(rel.iloc[0][ok2]),
         "baseline": f"eq. (1) of m - 1, T - 1 (x{rel.iloc[2, 0]:.2f} to x{rel.iloc[2, 1]:.2f})",
         "baseline holds": bool(rel.iloc[2][ok2])},
    ])


def row_growth(sizes: Sequence[int] = range(3, 8)) -> dict:
    """How the length grows along the rows of Table III (``T`` from ``sizes[0]`` to ``sizes[-1]``
    at each ``m`` of ``sizes``): a fact, not a test, since the length is capped at ``2^m``
    once ``T > m`` by construction.

    Returns ``low`` and ``high`` (smallest and largest factor over the rows), ``m_high`` and the
    lengths ``(first, last)`` of the row with the largest factor.
    """
    sizes = [as_int(x, "sizes[]", minimum=1) for x in sizes]
    if len(sizes) < 2:
        raise ValueError("sizes needs at least two sizes")
    g = {m: (vector_size(m, sizes[0]), vector_size(m, sizes[-1])) for m in sizes}
    f = {m: b / a for m, (a, b) in g.items()}
    m_hi = max(f, key=f.get)
    return {"low": min(f.values()), "high": f[m_hi], "m_high": m_hi, "lengths": g[m_hi]}


def fast_count_readings(printed: Counts, calibrate: Cell = (7, 7)) -> pd.DataFrame:
    """Which words each stage computes, pinned by one printed Table V cell and judged on the rest.

    Two readings of the fast algorithm's count (:func:`~projtrack.experiments.jpda.beta_in_situ`
    on all-ones MVMs): ``needed`` (each stage computes only the MU words the later stages
    read, as :func:`projtrack.jpda.beta_paper`) and ``all`` (each stage recomputes the
    whole Table III vector). One row per reading: its count at the cell ``calibrate``
    (the text's ``m = T = 7``), whether that equals the printed cell, and how many of the
    other printed cells of ``printed`` (additions and multiplications both) it gives.
    """
    calibrate = _cell(calibrate, "calibrate")
    if calibrate not in printed:
        raise ValueError(f"calibrate = {calibrate} must be a cell of printed")
    rows = []
    for reading in ("needed", "all"):
        counts = {}
        for k in printed:
            ops = beta_in_situ(all_ones_mvm(*_cell(k, "printed key")), words=reading).ops
            counts[k] = (ops.additions, ops.multiplications)
        others = [k for k in printed if k != calibrate]
        m, T = calibrate
        rows.append({"words computed per stage": reading,
                     (f"m = T = {m}" if m == T else f"m = {m}, T = {T}"): "{}/{}".format(*counts[calibrate]),
                     "equals the printed cell": counts[calibrate] == tuple(printed[calibrate]),
                     "other cells equal": sum(counts[k] == tuple(printed[k]) for k in others)})
    return pd.DataFrame(rows)


def misprint_evidence(conv: Counts, fast: Counts, printed4: Counts, printed5: Counts,
                      printed6: Mapping[Cell, Sequence[float]]) -> pd.DataFrame:
    """Every cell where Table IV or V differs from the instrumented count, and what proves it.

    A differing cell is a proven misprint when (a) the savings ratio of Table VI (printed
    independently, to one decimal) equals the ratio computed with our count, rounded
    half-up, and not the ratio with the printed count (:func:`ratio_fits`); or, for the
    additions of Table V, (b) Table III's rule proves it (:func:`table5_additions_proof`)
    while the cell's multiplications agree with ours.

    Parameters
    ----------
    conv, fast : dict
        Our counts (:func:`~projtrack.experiments.jpda.instrumented_counts`), keyed ``(m, T)``.
    printed4, printed5 : dict
        Tables IV and V as printed (:func:`~projtrack.experiments.jpda.parse_count_table`).
    printed6 : dict
        Table VI as printed (:func:`~projtrack.experiments.jpda.parse_ratio_table`).

    Returns
    -------
    pandas.DataFrame
        One row per differing cell: ``table`` ("IV" or "V"), ``m``, ``T``, ``printed`` and
        ``ours`` (``"additions/multiplications"``), ``decided by`` ("Table VI", "Table III",
        or "" when nothing decides), ``proven`` and ``proof`` (the arithmetic, one line).
    """
    for name, d in (("conv", conv), ("fast", fast), ("printed4", printed4), ("printed5", printed5),
                    ("printed6", printed6)):
        if not isinstance(d, Mapping) or not d:
            raise ValueError(f"{name} must be a non-empty dict keyed by (m, T)")
    cells = list(printed4)
    if any(k not in d for k in cells for d in (conv, fast, printed5, printed6)):
        raise ValueError("conv, fast, printed5 and printed6 must hold every cell of printed4")
    what = ("additions", "multiplications")
    rows = []
    for table, ours_d, printed_d in (("IV", conv, printed4), ("V", fast, printed5)):
        for k in cells:
            ours, printed = tuple(ours_d[k]), tuple(printed_d[k])
            if ours == printed:
                continue
            num_o, den_o = conv[k], fast[k]
            num_p, den_p = (printed, fast[k]) if table == "IV" else (conv[k], printed)
            evid = supported_value(ratio_fits(printed6[k], num_o, den_o), ratio_fits(printed6[k], num_p, den_p))
            parts = [f"Table VI prints {printed6[k][i]:.1f} for {what[i]}: {num_o[i]}/{den_o[i]} = "
                     f"{num_o[i] / den_o[i]:.2f} with our count, {num_p[i]}/{den_p[i]} = "
                     f"{num_p[i] / den_p[i]:.2f} with the printed one"
                     for i in (0, 1) if ours[i] != printed[i]]
            decided, proven = ("Table VI", True) if evid == "ours" else ("", False)
            if evid == "ours+paper":
                parts.append("both round to the printed ratio: Table VI does not decide")
            elif evid != "ours":
                parts.append("Table VI does not support our count")
            if not proven and table == "V" and ours[0] != printed[0] and ours[1] == printed[1]:
                ok, text = table5_additions_proof(k, fast, printed5)
                parts.append(f"Table III: {text}")
                decided, proven = ("Table III", True) if ok else ("", False)
            if table == "IV" and ours[1] != printed[1]:
                parts.append(f"our count is (T - 1) x Table I = {k[1] - 1} x "
                             f"{count_feasible_events(*k)} = {(k[1] - 1) * count_feasible_events(*k)}")
            rows.append({"table": table, "m": k[0], "T": k[1], "printed": "{}/{}".format(*printed),
                         "ours": "{}/{}".format(*ours), "decided by": decided, "proven": proven,
                         "proof": "; ".join(parts)})
    return pd.DataFrame(rows, columns=["table", "m", "T", "printed", "ours", "decided by", "proven", "proof"])


def count_table_verdict(n_cells: int, evidence: pd.DataFrame, table: str) -> tuple[str, int, int]:
    """The verdict of Table IV or V under the book's rule, from :func:`misprint_evidence`.

    ``reproduced`` when no cell differs, ``misprint`` when every differing cell is a proven
    misprint (the table as printed contains an error its own paper disproves), ``differs``
    otherwise. Returns ``(verdict, cells equal, proven misprints)``.
    """
    n_cells = as_int(n_cells, "n_cells", minimum=1)
    if not isinstance(evidence, pd.DataFrame) or "table" not in evidence:
        raise TypeError("evidence must be a misprint_evidence table")
    rows = evidence[evidence["table"] == table]
    proven = int(rows["proven"].sum())
    verdict = "reproduced" if rows.empty else "misprint" if proven == len(rows) else "differs"
    return verdict, n_cells - len(rows), proven

"""Scoring a reproduction against the numbers Casasent & Song print, and the glyph ensembles it needs.

* :func:`inside_widened`: is a printed value inside the widened central 95 % of our draws;
  :func:`inside_share`: how settled that answer is (a bootstrap over the draws);
* :func:`error_count_pmf` and :func:`counts_consistent`: are the printed error counts of
  the 26-letter test (0 errors at sigma 0.44, 2 at 0.45) plausible under per-letter
  error rates we measured; :func:`counts_consistent_mc` adds the Monte Carlo uncertainty
  of that answer (a bootstrap over the draws);
* :func:`last_perfect`: the largest noise level of a grid up to which a classifier is
  always right;
* :func:`summarize_draws`: median, central 95 % and the :func:`inside_widened` test of
  printed values, per reading.

The report prints one number about its bitmaps, the 43 pixels of its C (Sec. III.B), and
describes them (Sec. III.A: most letters in the central 10 x 10 pixels, with 40-75 pixels,
all under 110). That pins how many pixels the C has and about how large the letters are,
not the font or the sub-pixel position of the glyphs on the grid.
:func:`projtrack.scenes.letters.glyph_ensemble` renders every combination of the serif
fonts that ship with matplotlib, cap heights and sub-pixel shifts that gives a 43-pixel C
and says which fit the description; the glyph-ensemble functions measure the printed
numbers on each:

* :func:`ensemble_table`: the ensemble as a table, one row per glyph set (``member``);
* :func:`member_alphabet`: the 26 letters of one glyph set;
* :func:`letter_numbers`: the Fig. 3, Fig. 4 and Fig. 6 numbers of one C and one P;
* :func:`ensemble_numbers`: :func:`letter_numbers` of every glyph set;
* :func:`close_to_printed` and :func:`share_within`: the chapter's rule for a glyph-dependent
  number (within 10 % of the printed one, and nearer it than a no-information value such as
  a cross/auto ratio of 1) and the share of glyph sets that pass it;
* :func:`compare_printed` and :func:`glyph_verdict`: printed numbers against our glyph and the
  ensemble, and the chapter's verdict rule for glyph-dependent numbers.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack._validation import as_array, as_int, as_probability, as_real, as_rng
from projtrack.scenes import letters

from .autocorrelation import in_frame, peak_measures
from .discrimination import correlation_peak, unit_image

__all__ = ["inside_widened", "inside_share", "error_count_pmf", "counts_consistent", "counts_consistent_mc", "last_perfect",
           "summarize_draws",
           "ensemble_table", "member_alphabet", "FIG6_KINDS", "letter_numbers", "ensemble_numbers", "share_within",
           "close_to_printed", "compare_printed", "glyph_verdict"]


def inside_widened(values: np.ndarray, printed: float, *, widen: float = 0.1) -> bool:
    """Whether ``printed`` lies in ``[(1 - widen) q2.5, (1 + widen) q97.5]`` of ``values``.

    The criterion of the chapter for a number read off one noisy draw in the paper:
    the central 95 % of our draws, widened by ``widen`` (10 %) on each side.
    """
    v = as_array(values, "values", ndim=1, allow_empty=False)
    printed = as_real(printed, "printed")
    widen = as_real(widen, "widen", 0.0)
    lo, hi = np.quantile(v, [0.025, 0.975])
    return bool((1 - widen) * lo <= printed <= (1 + widen) * hi)


def inside_share(values: np.ndarray, printed: float, rng: np.random.Generator, *, widen: float = 0.1,
                 n_boot: int = 400) -> float:
    """Share of bootstrap resamples of ``values`` in which :func:`inside_widened` holds.

    The Monte Carlo uncertainty of the criterion's answer: near 1 or 0 the draws settle it;
    in between (say 5-95 %) the printed value sits on the edge of the widened interval.
    """
    v = as_array(values, "values", ndim=1, allow_empty=False)
    rng = as_rng(rng)
    n_boot = as_int(n_boot, "n_boot", minimum=1)
    return float(np.mean([inside_widened(v[rng.integers(0, len(v), size=len(v))], printed, widen=widen)
                          for _ in range(n_boot)]))


def error_count_pmf(p: np.ndarray) -> np.ndarray:
    """Exact distribution of the number of errors among independent items with error rates ``p``.

    Returns ``pmf`` of length ``len(p) + 1``: ``pmf[k]`` is the probability of ``k`` errors
    (a Poisson-binomial distribution, by the usual recursion).
    """
    p = as_array(p, "p", ndim=1)
    if np.any((p < 0) | (p > 1)):
        raise ValueError(f"p must hold error rates in [0, 1], got {p}")
    pmf = np.zeros(len(p) + 1)
    pmf[0] = 1.0
    for q in p:
        pmf[1:] = pmf[1:] * (1 - q) + pmf[:-1] * q
        pmf[0] *= 1 - q
    return pmf


def counts_consistent(p_first: np.ndarray, p_second: np.ndarray, *, level: float = 0.025
                      ) -> tuple[bool, float, float]:
    """Whether "0 errors at the first noise level, 2 at the second" is plausible.

    With per-item error rates ``p_first`` and ``p_second`` (independent items), the
    printed pair is consistent when ``P(0 errors | p_first)``, ``P(>= 2 errors | p_second)``
    and ``P(<= 2 errors | p_second)`` all reach ``level``.

    Returns
    -------
    tuple
        ``(consistent, P(0 errors at the first), P(>= 2 errors at the second))``.
    """
    level = as_probability(level, "level")
    a, b = error_count_pmf(p_first), error_count_pmf(p_second)
    if len(b) < 3:
        raise ValueError(f"p_second must hold at least 2 error rates, got {len(b) - 1}")
    ok = bool(a[0] >= level and b[2:].sum() >= level and b[:3].sum() >= level)
    return ok, float(a[0]), float(b[2:].sum())


def counts_consistent_mc(correct_first: np.ndarray, correct_second: np.ndarray, rng: np.random.Generator, *,
                         n_boot: int = 400, level: float = 0.025) -> dict[str, object]:
    """:func:`counts_consistent` from Monte Carlo draws, with a bootstrap of its uncertainty.

    Parameters
    ----------
    correct_first, correct_second : array_like of bool, shape (n_draws, n_items)
        Whether each item was classified correctly in each draw, at the first and the
        second noise level (e.g. one slice of
        :func:`projtrack.experiments.correlators.recognition_study`).
    rng : numpy.random.Generator
        Source of the bootstrap resamples.
    n_boot : int, default 400
        Bootstrap resamples of the draws (with replacement, the same for both levels).
    level : float, default 0.025
        The level of :func:`counts_consistent`.

    Returns
    -------
    dict
        ``consistent`` and ``P0`` (:func:`counts_consistent` on the measured error rates),
        ``P0 low`` and ``P0 high`` (the bootstrap 2.5 % and 97.5 % quantiles of ``P0``),
        ``share consistent`` (the share of resamples that are consistent) and ``edge``
        (True when the answer is not settled by the draws: the share is between 5 % and 95 %).
    """
    a = np.asarray(correct_first)
    b = np.asarray(correct_second)
    if a.ndim != 2 or a.shape != b.shape or a.size == 0 or a.dtype != bool or b.dtype != bool:
        raise ValueError("correct_first and correct_second must be bool arrays of one shape (n_draws, n_items)")
    rng = as_rng(rng)
    n_boot = as_int(n_boot, "n_boot", minimum=1)
    ok, p0, _ = counts_consistent(1.0 - a.mean(axis=0), 1.0 - b.mean(axis=0), level=level)
    p0s, oks = np.empty(n_boot), np.empty(n_boot, dtype=bool)
    for i in range(n_boot):
        idx = rng.integers(0, len(a), size=len(a))
        oks[i], p0s[i], _ = counts_consistent(1.0 - a[idx].mean(axis=0), 1.0 - b[idx].mean(axis=0), level=level)
    share = float(oks.mean())
    lo, hi = np.quantile(p0s, [0.025, 0.975])
    return {"consistent": ok, "P0": p0, "P0 low": float(lo), "P0 high": float(hi), "share consistent": share,
            "edge": bool(0.05 <= share <= 0.95)}


def last_perfect(accuracy: np.ndarray, levels: np.ndarray) -> float:
    """Largest level of an increasing grid up to which ``accuracy`` is exactly 1 (NaN if none).

    Only the first run of perfect accuracies counts: the answer is the level before the
    first imperfect one.
    """
    acc = as_array(accuracy, "accuracy", ndim=1, allow_empty=False)
    lv = as_array(levels, "levels", ndim=1)
    if lv.shape != acc.shape:
        raise ValueError(f"levels must have the shape of accuracy {acc.shape}, got {lv.shape}")
    ok = acc == 1.0
    n_ok = len(ok) if ok.all() else int(np.argmin(ok))
    return float(lv[n_ok - 1]) if n_ok else float("nan")


def summarize_draws(draws: Mapping[str, pd.DataFrame], printed: Mapping[str, float]) -> pd.DataFrame:
    """Median, 2.5 % and 97.5 % quantiles of each printed quantity's draws, per reading.

    Parameters
    ----------
    draws : mapping of reading name to DataFrame
        One row per draw, one column per quantity (e.g. from
        :func:`projtrack.experiments.correlators.noisy_study`).
    printed : mapping of quantity to the paper's value
        The quantities summarized; each must be a column of every table of ``draws``.

    Returns
    -------
    pandas.DataFrame
        One row per reading and quantity: ``reading``, ``quantity``, ``paper``, ``median``,
        ``2.5 %``, ``97.5 %`` and ``paper inside`` (:func:`inside_widened`).
    """
    if not draws or not printed:
        raise ValueError("draws and printed must not be empty")
    rows = []
    for name, d in draws.items():
        for q, value in printed.items():
            if q not in d:
                raise ValueError(f"the draws of {name!r} have no column {q!r}")
            v = d[q].to_numpy(dtype=float)
            lo, hi = np.quantile(v, [0.025, 0.975])
            rows.append({"reading": name, "quantity": q, "paper": float(value), "median": float(np.median(v)),
                         "2.5 %": float(lo), "97.5 %": float(hi), "paper inside": inside_widened(v, value)})
    return pd.DataFrame(rows)


#: The correlations of Fig. 6: name -> projection angle in degrees (``None``: the 2-D correlation).
#: "45 deg (y up)" is theta = 45 with y pointing up (the paper's Fig. 1); "45 deg (y down)" the
#: same formula with y pointing down (row index), theta = 135 in our convention.
FIG6_KINDS: dict[str, float | None] = {"horizontal": 90, "vertical": 0, "45 deg (y up)": 45,
                                       "45 deg (y down)": 135, "2-D": None}


def ensemble_table(**kwargs) -> pd.DataFrame:
    """:func:`projtrack.scenes.letters.glyph_ensemble` as a table with a ``member`` number per row.

    Keyword arguments go to :func:`~projtrack.scenes.letters.glyph_ensemble`. The column
    ``fits`` says whether a glyph set fits the description of Sec. III.A;
    :func:`ensemble_numbers` measures only those.
    """
    table = pd.DataFrame(letters.glyph_ensemble(**kwargs))
    if table.empty:
        raise ValueError("no glyph set of the ensemble gives the letter the requested pixel count")
    table.insert(0, "member", np.arange(len(table)))
    return table


def _member(row: Mapping[str, object]) -> dict[str, object]:
    try:
        return {"cap_height": float(row["cap_height"]), "min_coverage": float(row["min_coverage"]),
                "font": str(row["font"]), "offset": (float(row["dx"]), float(row["dy"]))}
    except KeyError as exc:
        raise ValueError(f"row must have the columns of ensemble_table, missing {exc}") from None


def member_alphabet(row: Mapping[str, object]) -> np.ndarray:
    """The 26 letters (``(26, 32, 32)``) of the glyph set of one row of :func:`ensemble_table`."""
    m = _member(row)
    return letters.alphabet(32, m["cap_height"], m["min_coverage"], font=m["font"], offset=m["offset"])


def letter_numbers(c: np.ndarray, p: np.ndarray, frame: int = 64) -> dict[str, float]:
    """The numbers the paper prints about its C (Figs. 3-4) and about C against P (Fig. 6).

    Parameters
    ----------
    c, p : array_like, shape (32, 32)
        Binary images of the letters C and P.
    frame : int, default 64
        Frame in which the mean is removed for Fig. 4 (pinned at 64 on the letter page).

    Returns
    -------
    dict
        ``pixels``; Fig. 3 (binary C): ``2-D PSR``, ``vertical peak``, ``vertical PSR``,
        ``horizontal peak``, ``horizontal PSR`` (11-sample window); Fig. 4 (C zero-mean in the
        frame): the same names prefixed ``zero-mean``; Fig. 6 (zero-mean unit-energy letters in
        their 32 x 32 frame, filter C): ``cross/auto <kind>`` for every kind of
        :data:`FIG6_KINDS`.
    """
    c = as_array(c, "c", shape=(32, 32))
    p = as_array(p, "p", shape=(32, 32))
    m3 = peak_measures(c, c)
    cz = C.zero_mean(in_frame(c, frame))
    m4 = peak_measures(cz, cz)
    out = {"pixels": float(np.count_nonzero(c)), "2-D PSR": m3["2-D"][1], "vertical peak": m3["vertical"][0],
           "vertical PSR": m3["vertical"][1], "horizontal peak": m3["horizontal"][0],
           "horizontal PSR": m3["horizontal"][1], "zero-mean 2-D PSR": m4["2-D"][1],
           "zero-mean vertical peak": m4["vertical"][0], "zero-mean vertical PSR": m4["vertical"][1],
           "zero-mean horizontal peak": m4["horizontal"][0], "zero-mean horizontal PSR": m4["horizontal"][1]}
    uc, up = unit_image(c), unit_image(p)
    for name, angle in FIG6_KINDS.items():
        out[f"cross/auto {name}"] = correlation_peak(up, uc, angle) / correlation_peak(uc, uc, angle)
    return out


def ensemble_numbers(table: pd.DataFrame, *, which: str | None = "fits") -> pd.DataFrame:
    """:func:`letter_numbers` of the C and P of the glyph sets of ``table`` (:func:`ensemble_table`).

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`ensemble_table`.
    which : str or None, default "fits"
        A bool column of ``table`` that selects the glyph sets measured: ``"fits"`` (the whole
        description of Sec. III.A), ``"fits_counts"`` (its pixel counts only); ``None``: all.

    Returns
    -------
    pandas.DataFrame
        The columns ``member``, ``font``, ``cap_height``, ``dx``, ``dy``, ``box`` of ``table``
        and one column per number of :func:`letter_numbers`.
    """
    if not isinstance(table, pd.DataFrame) or table.empty:
        raise ValueError("table must be a non-empty DataFrame from ensemble_table")
    if which is not None and which not in table:
        raise ValueError(f"table has no column {which!r} to select glyph sets by")
    rows = []
    for _, row in (table if which is None else table[table[which].astype(bool)]).iterrows():
        m = _member(row)
        c, p = (letters.render_letter(ch, 32, m["cap_height"], m["min_coverage"], font=m["font"],
                                      offset=m["offset"]) for ch in "CP")
        rows.append({k: row[k] for k in ("member", "font", "cap_height", "dx", "dy", "box") if k in row}
                    | letter_numbers(c, p))
    return pd.DataFrame(rows)


def share_within(values: np.ndarray, printed: float, rtol: float = 0.10, *, baseline: float | None = None) -> float:
    """Share of ``values`` that match the ``printed`` value by the chapter's rule (:func:`close_to_printed`)."""
    v = as_array(values, "values", ndim=1, allow_empty=False)
    return float(np.mean(close_to_printed(v, printed, rtol, baseline=baseline)))


def close_to_printed(values: np.ndarray, printed: float, rtol: float = 0.10, *,
                     baseline: float | None = None) -> np.ndarray:
    """Whether each value matches a printed glyph-dependent number: the chapter's rule.

    A value matches when it is within ``rtol`` (relative) of ``printed`` and, where the
    number has a no-information value ``baseline`` (1 for a cross/auto peak ratio: no
    discrimination), it is also nearer ``printed`` than ``baseline``, so that the trivial
    baseline itself cannot pass (a ratio of 1 is within 10 % of a printed 0.95).
    """
    v = np.asarray(values, dtype=float)
    printed = as_real(printed, "printed")
    rtol = as_real(rtol, "rtol", 0.0)
    ok = np.abs(v - printed) <= rtol * abs(printed)
    if baseline is not None:
        baseline = as_real(baseline, "baseline")
        ok &= np.abs(v - printed) < np.abs(v - baseline)
    return ok


def compare_printed(numbers: pd.DataFrame, ours: Mapping[str, float], printed: Mapping[str, float],
                    rtol: float = 0.10, *, baseline: Mapping[str, float] | None = None) -> pd.DataFrame:
    """Printed values beside ours and the glyph ensemble's range.

    Parameters
    ----------
    numbers : pandas.DataFrame
        :func:`ensemble_numbers`.
    ours : mapping of column to value
        Our glyph's numbers (e.g. :func:`letter_numbers` of the calibrated letters).
    printed : mapping of column to the paper's value
        The numbers compared (columns of ``numbers``).
    rtol : float, default 0.10
        The tolerance of :func:`close_to_printed`.
    baseline : mapping of column to value, optional
        The no-information value of a number (:func:`close_to_printed`), where it has one.

    Returns
    -------
    pandas.DataFrame
        One row per printed number: ``quantity``, ``paper``, ``ours``, ``glyph sets: min``,
        ``max`` and ``match`` (the share of glyph sets that match, :func:`share_within`).
    """
    baseline = dict(baseline or {})
    rows = []
    for q, value in printed.items():
        if q not in numbers or q not in ours:
            raise ValueError(f"{q!r} must be a column of numbers and a key of ours")
        v = numbers[q].to_numpy(dtype=float)
        rows.append({"quantity": q, "paper": float(value), "ours": float(ours[q]), "glyph sets: min": float(v.min()),
                     "max": float(v.max()), "match": share_within(v, value, rtol, baseline=baseline.get(q))})
    return pd.DataFrame(rows)


def glyph_verdict(ours: Mapping[str, float], numbers: pd.DataFrame, printed: Mapping[str, float],
                  rtol: float = 0.10, *, baseline: Mapping[str, float] | None = None) -> str:
    """The chapter's verdict for numbers that depend on the unpublished glyphs.

    ``within-tolerance`` if our glyph matches every printed number of ``printed``
    (:func:`close_to_printed`, with the ``baseline`` of each number where it has one);
    ``qualitative`` if at least one glyph set of the ensemble (``numbers``) matches them
    all; ``differs`` if none does.
    """
    if not printed:
        raise ValueError("printed must not be empty")
    baseline = dict(baseline or {})

    def close(values, q):
        return close_to_printed(values, printed[q], rtol, baseline=baseline.get(q))

    if all(bool(close([ours[q]], q)[0]) for q in printed):
        return "within-tolerance"
    every = np.all([close(numbers[q], q) for q in printed], axis=0)
    return "qualitative" if bool(np.any(every)) else "differs"

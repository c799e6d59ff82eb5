"""Scoring a reproduction against the numbers Casasent & Song print, and the glyph ensembles it needs.

* :func:`inside_widened`: is a printed value inside the widened central 95 % of our draws;
* :func:`error_count_pmf` and :func:`counts_consistent`: are the printed error counts of
  the 26-letter test (0 errors at sigma 0.44, 2 at 0.45) plausible under per-letter
  error rates we measured;
* :func:`last_perfect`: the largest noise level of a grid up to which a classifier is
  always right;
* :func:`summarize_draws`: median, central 95 % and the :func:`inside_widened` test of
  printed values, per reading.

The report prints one number about its bitmaps, the 43 pixels of its C (Sec. III.B). That
pins how many pixels the C has, not the font, the size or the sub-pixel position of the
glyphs on the grid. :func:`projtrack.scenes.letters.glyph_ensemble` renders every
combination of the serif fonts that ship with matplotlib, cap heights and sub-pixel shifts
that gives a 43-pixel C; the glyph-ensemble functions measure the printed numbers on each:

* :func:`ensemble_table`: the ensemble as a table, one row per glyph set (``member``);
* :func:`member_alphabet`: the 26 letters of one glyph set;
* :func:`letter_numbers`: the Fig. 3, Fig. 4 and Fig. 6 numbers of one C and one P;
* :func:`ensemble_numbers`: :func:`letter_numbers` of every glyph set;
* :func:`share_within`: the share of glyph sets whose number is within a tolerance of the printed one;
* :func:`compare_printed` and :func:`glyph_verdict`: printed numbers against our glyph and the
  ensemble, and the chapter's verdict rule for glyph-dependent numbers.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack._validation import as_array, as_probability, as_real
from projtrack.scenes import letters

from .autocorrelation import in_frame, peak_measures
from .discrimination import correlation_peak, unit_image

__all__ = ["inside_widened", "error_count_pmf", "counts_consistent", "last_perfect", "summarize_draws",
           "ensemble_table", "member_alphabet", "FIG6_KINDS", "letter_numbers", "ensemble_numbers", "share_within",
           "compare_printed", "glyph_verdict"]


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


def ensemble_numbers(table: pd.DataFrame) -> pd.DataFrame:
    """:func:`letter_numbers` of the C and P of every glyph set of ``table`` (:func:`ensemble_table`)
    that fits the description of Sec. III.A.

    Returns
    -------
    pandas.DataFrame
        The columns ``member``, ``font``, ``cap_height``, ``dx``, ``dy`` of ``table`` and one
        column per number of :func:`letter_numbers`.
    """
    if not isinstance(table, pd.DataFrame) or table.empty:
        raise ValueError("table must be a non-empty DataFrame from ensemble_table")
    rows = []
    for _, row in table[table["fits"]].iterrows() if "fits" in table else table.iterrows():
        m = _member(row)
        c, p = (letters.render_letter(ch, 32, m["cap_height"], m["min_coverage"], font=m["font"],
                                      offset=m["offset"]) for ch in "CP")
        rows.append({k: row[k] for k in ("member", "font", "cap_height", "dx", "dy")} | letter_numbers(c, p))
    return pd.DataFrame(rows)


def share_within(values: np.ndarray, printed: float, rtol: float = 0.10) -> float:
    """Share of ``values`` within ``rtol`` (relative) of the ``printed`` value."""
    v = as_array(values, "values", ndim=1, allow_empty=False)
    printed = as_real(printed, "printed")
    rtol = as_real(rtol, "rtol", 0.0)
    return float(np.mean(np.abs(v - printed) <= rtol * abs(printed)))


def compare_printed(numbers: pd.DataFrame, ours: Mapping[str, float], printed: Mapping[str, float],
                    rtol: float = 0.10) -> pd.DataFrame:
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
        The tolerance of :func:`share_within`.

    Returns
    -------
    pandas.DataFrame
        One row per printed number: ``quantity``, ``paper``, ``ours``, ``glyph sets: min``,
        ``max`` and ``within 10 %`` (the share of glyph sets within ``rtol``).
    """
    rows = []
    for q, value in printed.items():
        if q not in numbers or q not in ours:
            raise ValueError(f"{q!r} must be a column of numbers and a key of ours")
        v = numbers[q].to_numpy(dtype=float)
        rows.append({"quantity": q, "paper": float(value), "ours": float(ours[q]), "glyph sets: min": float(v.min()),
                     "max": float(v.max()), "within 10 %": share_within(v, value, rtol)})
    return pd.DataFrame(rows)


def glyph_verdict(ours: Mapping[str, float], numbers: pd.DataFrame, printed: Mapping[str, float],
                  rtol: float = 0.10) -> str:
    """The chapter's verdict for numbers that depend on the unpublished glyphs.

    ``within-tolerance`` if our glyph gives every printed number of ``printed`` within
    ``rtol``; ``qualitative`` if at least one glyph set of the ensemble (``numbers``) does;
    ``differs`` if none does.
    """
    rtol = as_real(rtol, "rtol", 0.0)
    if not printed:
        raise ValueError("printed must not be empty")

    def close(values, q):
        return np.abs(np.asarray(values, dtype=float) - printed[q]) <= rtol * abs(printed[q])

    if all(bool(close([ours[q]], q)[0]) for q in printed):
        return "within-tolerance"
    every = np.all([close(numbers[q], q) for q in printed], axis=0)
    return "qualitative" if bool(np.any(every)) else "differs"

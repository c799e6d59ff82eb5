"""Scoring a reproduction against the numbers Casasent & Song print.

* :func:`inside_widened`: is a printed value inside the widened central 95 % of our draws;
* :func:`error_count_pmf` and :func:`counts_consistent`: are the printed error counts of
  the 26-letter test (0 errors at sigma 0.44, 2 at 0.45) plausible under per-letter
  error rates we measured;
* :func:`last_perfect`: the largest noise level of a grid up to which a classifier is
  always right.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_probability, as_real

__all__ = ["inside_widened", "error_count_pmf", "counts_consistent", "last_perfect"]


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

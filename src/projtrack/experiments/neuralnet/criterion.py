"""The chapter's criterion for Table 1: how likely a ten-run table at least as good as the paper's is.

The paper gives ten simulations per noise level. A reproduction at success rates ``p`` is
judged by the exact binomial probability that ten runs per level give at least the paper's
count of successes in every row:

* :func:`rate_ci`: the 95% Clopper-Pearson interval of a rate ``k / n``;
* :func:`k_range`: the counts out of ten that rates in an interval give with probability >= 95%;
* :func:`p_row`, :func:`p_table`: the probability of one row, and of the whole table, at least
  as good as the paper's (optionally with no run converging to a wrong assignment);
* :func:`fmt_p`: such a probability printed to two significant digits;
* :func:`table1_readings`: the simulations of each noise level read against the paper's row.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import pandas as pd
from scipy import stats

from projtrack._validation import as_int, as_probability
from projtrack.stable import fmt

__all__ = ["rate_ci", "k_range", "p_row", "p_table", "fmt_p", "table1_readings"]


def rate_ci(k: int, n: int) -> tuple[float, float]:
    """95% Clopper-Pearson (exact) interval of the rate ``k / n``, ``0 <= k <= n``, ``n >= 1``."""
    n = as_int(n, "n", minimum=1)
    k = as_int(k, "k", minimum=0, maximum=n)
    ci = stats.binomtest(k, n).proportion_ci(0.95, method="exact")
    return float(ci.low), float(ci.high)


def k_range(p_lo: float, p_hi: float, n: int = 10) -> tuple[int, int]:
    """Counts out of ``n`` runs that rates in ``[p_lo, p_hi]`` give with probability >= 95%.

    Returns ``(lo, hi)``: the 2.5% quantile of ``Bin(n, p_lo)`` and the 97.5% quantile of
    ``Bin(n, p_hi)``.
    """
    p_lo = as_probability(p_lo, "p_lo")
    p_hi = as_probability(p_hi, "p_hi")
    if p_hi < p_lo:
        raise ValueError(f"p_hi ({p_hi}) must be >= p_lo ({p_lo})")
    n = as_int(n, "n", minimum=1)
    k = np.arange(n + 1)
    lo = int(np.searchsorted(stats.binom.cdf(k, n, p_lo), 0.025 - 1e-12))
    hi = int(np.searchsorted(stats.binom.cdf(k, n, p_hi), 0.975 - 1e-12))
    return lo, hi


def p_row(p: float, k: int, wrong: float | None = None, n: int = 10) -> float:
    """Probability that ``n`` runs at success rate ``p`` give at least ``k`` successes.

    With a wrong-convergence rate ``wrong``, also that no run converges to a wrong assignment:
    ``(1 - wrong)^n P(Bin(n, p / (1 - wrong)) >= k)``.
    """
    p = as_probability(p, "p")
    n = as_int(n, "n", minimum=1)
    k = as_int(k, "k", minimum=0, maximum=n)
    if wrong is None:
        return float(stats.binom.sf(k - 1, n, p))
    wrong = as_probability(wrong, "wrong")
    if wrong >= 1:
        return 0.0
    return float((1 - wrong) ** n * stats.binom.sf(k - 1, n, min(1.0, p / (1 - wrong))))


def p_table(rates: Sequence[float], paper_k: Sequence[int], wrong: Sequence[float] | None = None) -> float:
    """Probability of a ten-run table at least as good as the paper's in every row.

    Parameters
    ----------
    rates : sequence of float
        Success rate per row (noise level).
    paper_k : sequence of int
        The paper's successes out of ten per row.
    wrong : sequence of float, optional
        Wrong-convergence rate per row (see :func:`p_row`).

    Returns
    -------
    float
        The product of :func:`p_row` over the rows.
    """
    rates, paper_k = list(rates), list(paper_k)
    wrong = [None] * len(paper_k) if wrong is None else list(wrong)
    if not (len(rates) == len(paper_k) == len(wrong)) or not rates:
        raise ValueError(f"rates, paper_k and wrong must have one (and the same) number of rows, got "
                         f"{len(rates)}, {len(paper_k)}, {len(wrong)}")
    return float(np.prod([p_row(p, k, w) for p, k, w in zip(rates, paper_k, wrong)]))


def fmt_p(p: float, eq: bool = False) -> str:
    """A probability to two significant digits, ``"< 1e-12"`` below that (``"= "`` in front with ``eq``)."""
    return "< 1e-12" if p < 1e-12 else ("= " if eq else "") + fmt(float(p), ".2g")


def table1_readings(results: Mapping[float, Mapping[str, np.ndarray]], paper_k: Sequence[int],
                    paper_iterations: Sequence[int]) -> pd.DataFrame:
    """The simulations of each noise level read against the paper's row of Table 1.

    Parameters
    ----------
    results : mapping noise level -> dict of arrays
        Per level, the per-run arrays ``correct``, ``converged``, ``iterations``, ``status`` and
        ``optimal_correct`` (as from :func:`projtrack.experiments.neuralnet.table1_study`).
    paper_k : sequence of int
        The paper's successes out of ten, one per level (in the order of ``results``).
    paper_iterations : sequence of int
        The paper's mean iterations, one per level.

    Returns
    -------
    pandas.DataFrame
        One row per level: ``noise %``, ``paper k/10``, ``success %`` with its 95% interval
        (:func:`rate_ci`), the ``k/10 95% range`` of ten runs at rates in it (:func:`k_range`),
        ``P(k >= paper's)`` at the rate and ``at 95% high`` (:func:`p_row`, as text), the mean
        ``iterations`` of the converged runs, ``paper it.``, counts of ``converged``,
        ``converged but wrong``, ``oscillating`` and ``wandering`` runs, and
        ``optimum correct %`` (the optimum of the cost is the true assignment).
    """
    if not isinstance(results, Mapping):
        raise TypeError(f"results must be a mapping of noise level -> arrays, got {type(results).__name__}")
    paper_k, paper_iterations = list(paper_k), list(paper_iterations)
    if not (len(results) == len(paper_k) == len(paper_iterations)) or not paper_k:
        raise ValueError(f"results, paper_k and paper_iterations must have one (and the same) number of levels, "
                         f"got {len(results)}, {len(paper_k)}, {len(paper_iterations)}")
    rows = []
    for (n, r), k_p, it_p in zip(results.items(), paper_k, paper_iterations):
        missing = {"correct", "converged", "iterations", "status", "optimal_correct"} - set(r)
        if missing:
            raise ValueError(f"results[{n}] lacks {sorted(missing)}")
        n_sim = len(r["correct"])
        k = int(r["correct"].sum())
        lo, hi = rate_ci(k, n_sim)
        klo, khi = k_range(lo, hi)
        it = r["iterations"][r["converged"]]
        rows.append({"noise %": n, "paper k/10": k_p,
                     "success %": 100 * k / n_sim, "95% %": f"{100 * lo:.1f}-{100 * hi:.1f}",
                     "k/10 95% range": f"{klo}-{khi}",
                     "P(k >= paper's)": fmt_p(p_row(k / n_sim, k_p)), "at 95% high": fmt_p(p_row(hi, k_p)),
                     "iterations": float(it.mean()) if it.size else float("nan"), "paper it.": int(it_p),
                     "converged": int(r["converged"].sum()),
                     "converged but wrong": int((r["converged"] & ~r["correct"]).sum()),
                     "oscillating": int((r["status"] == "oscillating").sum()),
                     "wandering": int((r["status"] == "wandering").sum()),
                     "optimum correct %": 100 * float(np.mean(r["optimal_correct"]))})
    return pd.DataFrame(rows)

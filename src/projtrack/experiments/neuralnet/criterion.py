"""The chapter's criterion for Table 1: how likely a ten-run table at least as good as the paper's is.

The paper gives ten simulations per noise level. A reproduction at success rates ``p`` is
judged by the exact binomial probability that ten runs per level give at least the paper's
count of successes in every row:

* :func:`rate_ci`: the 95% Clopper-Pearson interval of a rate ``k / n``; :func:`ci_step`, how far
  one run moves its bounds;
* :func:`k_range`: the counts out of ten that rates in an interval give with probability >= 95%;
* :func:`p_row`, :func:`p_table`: the probability of one row, and of the whole table, at least
  as good as the paper's (optionally with no run converging to a wrong assignment);
* :func:`fmt_p`: such a probability printed to two significant digits;
* :func:`table1_readings`: the simulations of each noise level read against the paper's row;
* :func:`ten_run_replications`: the same runs cut into replications of the paper's ten;
* :func:`table1_tables`: the page's views of both, six columns at most;
* :func:`mode_probability`: the paper's account of its failures (Table 1 has :data:`PAPER_FAILURES`
  failed runs, which either wandered or oscillated between the correct state and one a pairing
  away) against the shares of the failure modes of our runs;
* :func:`stable_up`, :func:`stable_down`: tolerances computed from the data, rounded so that one
  run changing its outcome does not change them.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import pandas as pd
from scipy import stats

from projtrack._validation import as_int, as_probability
from projtrack.stable import fmt
from projtrack.tolerance import EXACT, Tolerance, mean_over, share, statistical

from .table1 import FAILURE_MODES

__all__ = ["stable_up", "stable_down", "rate_ci", "ci_step", "k_range", "p_row", "p_table", "fmt_p", "table1_readings",
           "ten_run_replications", "table1_tables", "PAPER_FAILURES", "mode_probability"]


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


def stable_up(x: float) -> float:
    """``x`` rounded up to one significant digit (``0.0061 -> 0.007``).

    A tolerance computed from the data would change, and with it the committed manifest, when
    one run changes its outcome; rounded up to one digit it stays put unless the data move it
    across a digit.
    """
    x = float(x)
    if not np.isfinite(x) or x <= 0:
        raise ValueError(f"x must be finite and > 0, got {x}")
    e = 10.0 ** np.floor(np.log10(x))
    d = np.ceil(round(x / e, 9))
    return float(f"{d * e:.1g}")


def stable_down(n: int) -> int:
    """A count ``n >= 1`` rounded down to one significant digit (``331 -> 300``): the same for
    the counts one run changing its outcome gives, except across a digit."""
    n = as_int(n, "n", minimum=1)
    e = 10 ** (len(str(n)) - 1)
    return (n // e) * e


def ci_step(n: int) -> float:
    """The largest change of a 95% Clopper-Pearson bound of ``k / n`` when ``k`` changes by one."""
    n = as_int(n, "n", minimum=1)
    lo, hi = np.array([rate_ci(k, n) for k in range(n + 1)]).T
    return float(max(np.abs(np.diff(lo)).max(), np.abs(np.diff(hi)).max()))


def table1_readings(results: Mapping[float, Mapping[str, np.ndarray]], paper_k: Sequence[int],
                    paper_iterations: Sequence[int]) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """The simulations of each noise level read against the paper's row of Table 1.

    Parameters
    ----------
    results : mapping noise level -> dict of arrays
        Per level, the per-run arrays ``correct``, ``converged``, ``iterations``, ``mode`` and
        ``optimal_correct`` (as from :func:`projtrack.experiments.neuralnet.table1_study`).
    paper_k : sequence of int
        The paper's successes out of ten, one per level (in the order of ``results``).
    paper_iterations : sequence of int
        The paper's mean iterations, one per level.

    Returns
    -------
    table : pandas.DataFrame
        One row per level: ``noise %``, ``paper k/10``, ``paper it.``, ``runs``, ``success %``
        and its 95% interval ``95% low %``, ``95% high %`` (:func:`rate_ci`), ``P(k >= paper's)``
        (:func:`p_row` at the upper end), the mean ``iterations`` of the converged runs, the
        percentage of runs in each of :data:`FAILURE_MODES`
        (``wrong %`` is a convergence to a wrong assignment) and ``optimum correct %`` (the
        optimum of the cost is the true assignment).
    tolerance : dict of str to Tolerance
        Shares of the runs move by one run; an interval bound by :func:`ci_step`; the mean
        iterations by one converged run changing its count by up to 50 sweeps (over the smallest
        number of converged runs of a level, :func:`stable_down`); the probability by one run at
        the upper end (:func:`stable_up`).
    """
    if not isinstance(results, Mapping):
        raise TypeError(f"results must be a mapping of noise level -> arrays, got {type(results).__name__}")
    paper_k, paper_iterations = list(paper_k), list(paper_iterations)
    if not (len(results) == len(paper_k) == len(paper_iterations)) or not paper_k:
        raise ValueError(f"results, paper_k and paper_iterations must have one (and the same) number of levels, "
                         f"got {len(results)}, {len(paper_k)}, {len(paper_iterations)}")
    rows, n_conv, p_step = [], [], 0.0
    for (n, r), k_p, it_p in zip(results.items(), paper_k, paper_iterations):
        missing = {"correct", "converged", "iterations", "mode", "optimal_correct"} - set(r)
        if missing:
            raise ValueError(f"results[{n}] lacks {sorted(missing)}")
        n_sim = len(r["correct"])
        k = int(r["correct"].sum())
        lo, hi = rate_ci(k, n_sim)
        it = r["iterations"][r["converged"]]
        if it.size:
            n_conv.append(int(it.size))
        modes = np.asarray(r["mode"])
        p_step = max(p_step, *(abs(p_row(rate_ci(j, n_sim)[1], k_p) - p_row(hi, k_p))
                               for j in (k - 1, k + 1) if 0 <= j <= n_sim))
        rows.append({"noise %": n, "paper k/10": int(k_p), "paper it.": int(it_p), "runs": n_sim,
                     "success %": 100 * k / n_sim, "95% low %": 100 * lo, "95% high %": 100 * hi,
                     "P(k >= paper's)": p_row(hi, k_p),
                     "iterations": float(it.mean()) if it.size else float("nan"),
                     **{f"{m} %": 100 * float(np.mean(modes == m)) for m in FAILURE_MODES},
                     "optimum correct %": 100 * float(np.mean(r["optimal_correct"]))})
    n_min = min(len(r["correct"]) for r in results.values())
    runs = share(n_min, percent=True)
    tolerance = {"noise %": EXACT, "success %": runs, "optimum correct %": runs,
                 **{f"{m} %": runs for m in FAILURE_MODES},
                 "95% low %": statistical(atol=100 * ci_step(n_min),
                                          why=f"one of {n_min} runs changing outcome moves a 95% Clopper-Pearson "
                                              "bound by at most this much"),
                 "95% high %": statistical(atol=100 * ci_step(n_min),
                                           why=f"one of {n_min} runs changing outcome moves a 95% Clopper-Pearson "
                                               "bound by at most this much"),
                 "P(k >= paper's)": statistical(atol=stable_up(max(p_step, 1e-12)),
                                                why="one run changing outcome moves the upper bound of the rate, "
                                                    "and this probability by at most this much (rounded up to one "
                                                    "digit)"),
                 "iterations": mean_over(stable_down(min(n_conv)) if n_conv else 1, 50.0, what="converged run")}
    return pd.DataFrame(rows), tolerance


def ten_run_replications(results: Mapping[float, Mapping[str, np.ndarray]], paper_k: Sequence[int], size: int = 10
                         ) -> tuple[pd.DataFrame, int, dict[str, Tolerance]]:
    """The runs of each level cut into the paper's format: replication ``j`` is runs ``size j .. size j + size - 1``.

    Parameters
    ----------
    results : mapping noise level -> dict of arrays
        Per level, the per-run array ``correct`` (all levels of one length, a multiple of ``size``).
    paper_k : sequence of int
        The paper's successes out of ``size``, one per level.
    size : int, default 10
        Runs per replication (the paper's ten).

    Returns
    -------
    table : pandas.DataFrame
        Per level: ``noise %``, ``paper k/10`` and, over the replications, the ``median k/10``,
        ``min k/10``, ``max k/10`` and ``as good as the paper's %`` (share of replications with at
        least the paper's count).
    as_good : int
        Replications at least as good as the paper's in every row.
    tolerance : dict of str to Tolerance
        One run changing outcome changes one replication's count by one.
    """
    if not isinstance(results, Mapping) or not results:
        raise TypeError("results must be a non-empty mapping of noise level -> arrays")
    size = as_int(size, "size", minimum=1)
    paper_k = list(paper_k)
    if len(paper_k) != len(results):
        raise ValueError(f"paper_k has {len(paper_k)} levels, results {len(results)}")
    lengths = {len(r["correct"]) for r in results.values()}
    if len(lengths) != 1 or next(iter(lengths)) % size:
        raise ValueError(f"every level must have the same number of runs, a multiple of {size}; got {sorted(lengths)}")
    n_rep = next(iter(lengths)) // size
    k_rep = np.array([np.asarray(r["correct"]).reshape(n_rep, size).sum(axis=1) for r in results.values()]).T
    good = k_rep >= np.array(paper_k)[None, :]
    table = pd.DataFrame({"noise %": list(results), "paper k/10": [int(k) for k in paper_k],
                          "median k/10": np.median(k_rep, axis=0), "min k/10": k_rep.min(axis=0).astype(float),
                          "max k/10": k_rep.max(axis=0).astype(float),
                          "as good as the paper's %": 100 * good.mean(axis=0)})
    one = statistical(atol=1.0, why="one run changing outcome changes one replication's count by one, and a "
                                    "median, minimum or maximum over replications by at most one")
    tolerance = {"noise %": EXACT, "median k/10": one, "min k/10": one, "max k/10": one,
                 "as good as the paper's %": share(n_rep, percent=True)}
    return table, int(good.all(axis=1).sum()), tolerance


def table1_tables(readings: pd.DataFrame, replications: pd.DataFrame, readings_tol: Mapping[str, Tolerance],
                  replications_tol: Mapping[str, Tolerance]) -> dict[str, tuple[pd.DataFrame, dict[str, Tolerance]]]:
    """The page's three views of Table 1, each at most six columns, with their tolerances.

    Parameters
    ----------
    readings, readings_tol
        What :func:`table1_readings` returns.
    replications, replications_tol
        The table and tolerance of :func:`ten_run_replications`.

    Returns
    -------
    dict
        ``"table1"``: ``noise %``, ``paper k/10 (it.)`` (the paper's row as text), ``success %``,
        ``95% high %``, ``median k/10`` (over the ten-run replications) and ``iterations``;
        ``"outcomes"``: ``noise %`` and the percentage of runs ending in each mode
        (``correct %`` is the success); ``"intervals"``: ``noise %``, ``95% low %``,
        ``95% high %``, ``P(k >= paper's)``, ``optimum correct %`` and ``as good as the paper's %``
        (share of the replications). Each as ``(table, tolerance)``.
    """
    if not isinstance(readings, pd.DataFrame) or not isinstance(replications, pd.DataFrame):
        raise TypeError("readings and replications must be pandas DataFrames")
    if list(readings["noise %"]) != list(replications["noise %"]):
        raise ValueError("readings and replications must have the same noise levels")
    tol = {**dict(readings_tol), **dict(replications_tol)}
    main = pd.DataFrame({"noise %": readings["noise %"],
                         "paper k/10 (it.)": [f"{k} ({i})" for k, i in zip(readings["paper k/10"],
                                                                            readings["paper it."])],
                         "success %": readings["success %"], "95% high %": readings["95% high %"],
                         "median k/10": replications["median k/10"], "iterations": readings["iterations"]})
    outcomes = pd.DataFrame({"noise %": readings["noise %"], "correct %": readings["success %"],
                             **{f"{m} %": readings[f"{m} %"] for m in FAILURE_MODES}})
    intervals = pd.DataFrame({"noise %": readings["noise %"], "95% low %": readings["95% low %"],
                              "95% high %": readings["95% high %"], "P(k >= paper's)": readings["P(k >= paper's)"],
                              "optimum correct %": readings["optimum correct %"],
                              "as good as the paper's %": replications["as good as the paper's %"]})
    out = {}
    for name, t in [("table1", main), ("outcomes", outcomes), ("intervals", intervals)]:
        out[name] = (t, {c: tol["success %" if c == "correct %" else c] for c in t.columns
                         if c in tol or c == "correct %"})
    return out


# ----------------------------------------------------------------------------- the failures


#: Failed runs in Table 1: 10 - 9 at 5% noise and 10 - 8 at 7.5%.
PAPER_FAILURES = 3


def mode_probability(truth_cycle: float, wandering: float, n_failures: int = PAPER_FAILURES) -> float:
    """Probability that ``n_failures`` failed runs show both of the paper's modes and no other.

    With the shares ``q`` (a 2-cycle with the correct state) and ``w`` (wandering) among failed
    runs, ``n`` independent failures all fall in these two modes, at least one in each, with
    probability ``(q + w)^n - q^n - w^n``.

    Parameters
    ----------
    truth_cycle, wandering : float
        The shares ``q`` and ``w`` (``q + w <= 1``).
    n_failures : int, default 3
        Failed runs in the paper's Table 1 (:data:`PAPER_FAILURES`).
    """
    q = as_probability(truth_cycle, "truth_cycle")
    w = as_probability(wandering, "wandering")
    if q + w > 1 + 1e-12:
        raise ValueError(f"truth_cycle + wandering must be <= 1, got {q + w}")
    n = as_int(n_failures, "n_failures", minimum=2)
    return float(max(0.0, min(1.0, (q + w) ** n - q ** n - w ** n)))

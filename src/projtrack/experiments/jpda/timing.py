"""Wall-clock scaling of the exact beta methods on fully gated and on clustered MVMs (JPDA chapter).

:func:`scaling_timings` times the enumeration, the paper's algorithm and the package's
methods on random ``m = T = n`` MVMs (:func:`projtrack.scenes.jpda.random_mvm`), fully
gated and cut into independent clusters. Timings depend on the machine and its load.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from projtrack._validation import as_int
from projtrack.jpda import (beta, beta_enumerated, beta_forward_backward, beta_paper,
                            count_feasible_events)
from projtrack.scenes.jpda import random_mvm

__all__ = ["best_of", "scaling_timings"]


def best_of(fn: Callable[[], object], repeats: int) -> float:
    """The shortest wall-clock time, in seconds, of ``repeats`` calls of ``fn()``."""
    if not callable(fn):
        raise TypeError(f"fn must be callable, got {type(fn).__name__}")
    repeats = as_int(repeats, "repeats", minimum=1)
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def scaling_timings(sizes: Sequence[int], seed: int, *, enumerate_max: int = 7,
                    paper_max: int = 13, cluster_size: int = 4,
                    single_run_from: int = 17) -> pd.DataFrame:
    """Seconds per beta of each method for fully gated and clustered ``m = T = n`` MVMs.

    For every ``n`` of ``sizes`` one fully gated and one clustered (clusters of
    ``cluster_size``) random MVM are drawn from ``default_rng(seed)``, in that order.
    Columns: the eq. (1) event count, ``enumerate`` (up to ``enumerate_max``),
    ``paper`` (up to ``paper_max``) and ``auto`` on the full MVM, then ``paper``,
    forward-backward without the split, and ``auto`` on the clustered one (NaN: not
    run). Best of 2 runs, of one run from ``n = single_run_from`` on (the clustered
    ``auto`` best of 3).
    """
    sizes = [as_int(n, "sizes[]", minimum=1) for n in sizes]
    seed = as_int(seed, "seed", minimum=0)
    enumerate_max = as_int(enumerate_max, "enumerate_max", minimum=0)
    paper_max = as_int(paper_max, "paper_max", minimum=0)
    cluster_size = as_int(cluster_size, "cluster_size", minimum=1)
    single_run_from = as_int(single_run_from, "single_run_from", minimum=1)
    rng = np.random.default_rng(seed)
    timing = []
    for n in sizes:
        w = random_mvm(rng, n, n)
        wc = random_mvm(rng, n, n, cluster_size=cluster_size)
        rep = 2 if n < single_run_from else 1
        timing.append({
            "n": n,
            "events (Table I)": float(count_feasible_events(n, n)),
            "enumerate": best_of(lambda: beta_enumerated(w), rep) if n <= enumerate_max else np.nan,
            "paper": best_of(lambda: beta_paper(w), rep) if n <= paper_max else np.nan,
            "auto": best_of(lambda: beta(w), rep),
            "clustered: paper": best_of(lambda: beta_paper(wc), rep) if n <= paper_max else np.nan,
            "clustered: forward-backward, no split": best_of(lambda: beta_forward_backward(wc), rep),
            "clustered: auto": best_of(lambda: beta(wc), 3),
        })
    return pd.DataFrame(timing).set_index("n")

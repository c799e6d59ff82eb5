"""Reproducible Monte Carlo loops, serial or parallel.

:func:`run` gives every trial its own child :class:`numpy.random.Generator`, spawned
from the caller's generator with :meth:`numpy.random.Generator.spawn`, so trial ``i``
sees the same random stream whatever ``n_jobs`` is, and the results are identical
serially and in parallel (joblib's loky processes).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import numpy as np
from joblib import Parallel, delayed

__all__ = ["run", "default_n_jobs"]


def default_n_jobs() -> int:
    """Number of worker processes: ``$PROJTRACK_N_JOBS`` if set, else 1."""
    raw = os.environ.get("PROJTRACK_N_JOBS", "").strip()
    if not raw:
        return 1
    try:
        n = int(raw)
    except ValueError:
        raise ValueError(f"PROJTRACK_N_JOBS must be an integer, got {raw!r}") from None
    return n


def run(fn: Callable[..., Any], n_trials: int, rng: np.random.Generator, *args: Any,
        n_jobs: int | None = None, **kwargs: Any) -> list[Any]:
    """Run ``fn(child_rng, *args, **kwargs)`` for ``n_trials`` independent trials.

    Parameters
    ----------
    fn : callable
        Called as ``fn(rng_i, *args, **kwargs)``; must use only ``rng_i`` for randomness.
        With ``n_jobs != 1`` it must be picklable by cloudpickle (functions defined in a
        notebook are).
    n_trials : int
        Number of trials, >= 0.
    rng : numpy.random.Generator
        Parent generator; ``n_trials`` children are spawned from it (advancing its
        spawn counter, not its stream).
    *args, **kwargs
        Passed to every call.
    n_jobs : int, optional
        Worker processes (joblib convention: -1 for all cores). Defaults to
        :func:`default_n_jobs`. Results do not depend on it.

    Returns
    -------
    list
        ``[fn(rng_0, ...), ..., fn(rng_{n-1}, ...)]`` in trial order.
    """
    if not callable(fn):
        raise TypeError(f"fn must be callable, got {type(fn).__name__}")
    if isinstance(n_trials, bool) or not isinstance(n_trials, (int, np.integer)):
        raise TypeError(f"n_trials must be an int, got {type(n_trials).__name__}")
    if n_trials < 0:
        raise ValueError(f"n_trials must be >= 0, got {n_trials}")
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    n_jobs = default_n_jobs() if n_jobs is None else n_jobs
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, (int, np.integer)) or n_jobs == 0:
        raise ValueError(f"n_jobs must be a non-zero int (joblib convention), got {n_jobs!r}")
    children = rng.spawn(int(n_trials))
    if n_jobs == 1 or n_trials <= 1:
        return [fn(child, *args, **kwargs) for child in children]
    return list(Parallel(n_jobs=int(n_jobs))(delayed(fn)(child, *args, **kwargs) for child in children))

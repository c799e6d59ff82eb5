"""Reproducible Monte Carlo loops, serial, parallel or on a Dask cluster.

:func:`run` gives every trial its own child :class:`numpy.random.Generator`, spawned
from the caller's generator with :meth:`numpy.random.Generator.spawn`, so trial ``i``
sees the same random stream wherever it runs: the results are identical serially, in
parallel on one machine (joblib's loky processes, ``n_jobs``) and on a Dask cluster
(joblib's Dask backend, ``scheduler=`` or ``$PROJTRACK_DASK_SCHEDULER``).

:func:`size` is the one switch between the book's Monte Carlo sizes (chosen so that the
whole book executes in about 10 minutes on 2 cores) and the full sizes (the paper's, or
larger), selected by ``PROJTRACK_FULL=1``::

    PROJTRACK_FULL=1 PROJTRACK_DASK_SCHEDULER=tcp://scheduler:8786 make figures

runs every study at full size on the cluster (the workers need this package and its
locked dependencies installed, and the scheduler's address reachable from the machine
running the notebooks).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import numpy as np
from joblib import Parallel, delayed

from projtrack._validation import as_int, as_rng, only_value_errors

__all__ = ["run", "default_n_jobs", "default_scheduler", "full_size", "size"]

_TRUE = ("1", "true", "yes", "on")
_FALSE = ("", "0", "false", "no", "off")


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


def default_scheduler() -> str | None:
    """The Dask scheduler address in ``$PROJTRACK_DASK_SCHEDULER`` (``tcp://host:8786``), or None."""
    raw = os.environ.get("PROJTRACK_DASK_SCHEDULER", "").strip()
    return raw or None


def full_size() -> bool:
    """Whether ``$PROJTRACK_FULL`` asks for the full-size Monte Carlo studies.

    Raises
    ------
    ValueError
        If the variable holds something other than 1/0, true/false, yes/no, on/off.
    """
    raw = os.environ.get("PROJTRACK_FULL", "").strip().lower()
    if raw in _TRUE:
        return True
    if raw in _FALSE:
        return False
    raise ValueError(f"PROJTRACK_FULL must be 1/0, true/false, yes/no or on/off, got {raw!r}")


def size(book: int, full: int) -> int:
    """The number of Monte Carlo trials of one study: ``book`` normally, ``full`` with ``PROJTRACK_FULL=1``.

    Parameters
    ----------
    book : int
        The size the book uses by default (keeps the whole book within its time budget).
    full : int
        The full size (the paper's, or one large enough for tight intervals); ``>= book``.

    Returns
    -------
    int
    """
    book = as_int(book, "book", minimum=1)
    full = as_int(full, "full", minimum=1)
    if full < book:
        raise ValueError(f"full ({full}) must be >= book ({book})")
    return int(full if full_size() else book)


def run(fn: Callable[..., Any], n_trials: int, rng: np.random.Generator, *args: Any,
        n_jobs: int | None = None, scheduler: Any = None, **kwargs: Any) -> list[Any]:
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
        :func:`default_n_jobs`. Results do not depend on it. Ignored on a Dask cluster.
    scheduler : str or dask.distributed.Client, optional
        Run the trials on a Dask cluster: a scheduler address (``"tcp://host:8786"``) or a
        connected ``Client``. Defaults to :func:`default_scheduler`; ``None`` (and no
        ``$PROJTRACK_DASK_SCHEDULER``) runs locally. Needs the ``cluster`` extra
        (``dask[distributed]``). Results do not depend on it.

    Returns
    -------
    list
        ``[fn(rng_0, ...), ..., fn(rng_{n-1}, ...)]`` in trial order.
    """
    if not callable(fn):
        raise TypeError(f"fn must be callable, got {type(fn).__name__}")
    n_trials = as_int(n_trials, "n_trials", minimum=0)
    rng = as_rng(rng)
    n_jobs = only_value_errors(as_int, default_n_jobs() if n_jobs is None else n_jobs, "n_jobs")
    if n_jobs == 0:
        raise ValueError("n_jobs must be a non-zero int (joblib convention), got 0")
    scheduler = default_scheduler() if scheduler is None else scheduler
    children = rng.spawn(int(n_trials))
    if scheduler is not None:
        return _run_on_dask(fn, children, scheduler, args, kwargs)
    if n_jobs == 1 or n_trials <= 1:
        return [fn(child, *args, **kwargs) for child in children]
    return list(Parallel(n_jobs=int(n_jobs))(delayed(fn)(child, *args, **kwargs) for child in children))


def _run_on_dask(fn: Callable[..., Any], children: list[np.random.Generator], scheduler: Any,
                 args: tuple[Any, ...], kwargs: dict[str, Any]) -> list[Any]:
    """Run the trials through joblib's Dask backend on ``scheduler`` (address or Client)."""
    try:
        from dask.distributed import Client
    except ImportError as exc:  # pragma: no cover - the lock installs dask
        raise ImportError("running on a Dask cluster needs dask[distributed] "
                          "(pip install 'projtrack[cluster]')") from exc
    from joblib import parallel_backend

    if isinstance(scheduler, Client):
        client, own = scheduler, False
    elif isinstance(scheduler, str) and scheduler.strip():
        client, own = Client(scheduler.strip(), set_as_default=False), True
    else:
        raise TypeError(f"scheduler must be an address string or a dask.distributed.Client, got {scheduler!r}")
    try:
        with parallel_backend("dask", client=client):
            return list(Parallel()(delayed(fn)(child, *args, **kwargs) for child in children))
    finally:
        if own:
            client.close()

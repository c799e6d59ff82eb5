"""The net against the reference solvers of the same cost: accuracy against noise and against size.

A trial is one data set with its net starts (:func:`comparison_trial`, the Sec. VI experiment
of :func:`projtrack.experiments.neuralnet.simulate` with the reference solvers). Every study
draws its trials through :func:`projtrack.montecarlo.run` (cell ``c`` from
``numpy.random.default_rng(seed_c)``), runs the nets of all trials with the same number of
targets as one batch (:func:`projtrack.experiments.neuralnet.run_draws`) and scores them, with
the results of running :func:`comparison_trial` trial by trial:

* :func:`comparison_cells`: the per-run and per-data-set arrays of several cells;
* :func:`accuracy`: the percentage of correct assignments of the net and of every reference;
* :func:`noise_sweep`, :func:`size_sweep`: the rows of the chapter's two comparison tables.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real

from .table1 import draw_simulation, run_draws, score_simulation, simulate

__all__ = ["METHODS", "comparison_trial", "comparison_cells", "accuracy", "noise_sweep", "size_sweep"]

#: The compared methods and the key of their per-run or per-data-set success in :func:`simulate`.
METHODS = {"net": "correct", "optimum": "optimal_correct", "coordinate descent": "cd_correct",
           "greedy on eq. (7)": "greedy_correct", "nearest neighbour": "nn_correct"}


def comparison_trial(rng: np.random.Generator, n_starts: int, noise_percent: float,
                     n_targets: int = 4) -> dict[str, np.ndarray]:
    """One data set (five frames, ``N_M = N_T``), ``n_starts`` net starts, and the reference solvers.

    :func:`projtrack.experiments.neuralnet.simulate` with ``n_datasets = 1`` and the paper's
    settings otherwise (unit 256 px, update as printed).
    """
    return simulate(rng, 1, n_starts, noise_percent, n_targets=n_targets)


def _as_sequence(values: object, name: str) -> list:
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or not values:
        raise TypeError(f"{name} must be a non-empty sequence")
    return list(values)


def comparison_cells(cells: Sequence[tuple[float, int, object]], n_datasets: int, n_starts: int, *,
                     n_jobs: int | None = None) -> list[dict[str, np.ndarray]]:
    """``n_datasets`` trials of :func:`comparison_trial` for every cell, the nets batched by size.

    Parameters
    ----------
    cells : sequence of (noise_percent, n_targets, seed)
        Cell ``c`` draws its trials from ``numpy.random.default_rng(seed)`` (``seed`` anything
        ``default_rng`` accepts).
    n_datasets : int
        Trials (data sets) per cell, >= 1.
    n_starts : int
        Net starts per data set, >= 1.
    n_jobs : int, optional
        Passed to :func:`projtrack.montecarlo.run` for the drawing; results do not depend on it.

    Returns
    -------
    list of dict
        Per cell, the arrays of :func:`simulate` over its trials in trial order (``dataset``
        numbers the trials), equal to concatenating
        ``montecarlo.run(comparison_trial, n_datasets, default_rng(seed), n_starts, noise, n_targets)``.
    """
    cells = _as_sequence(cells, "cells")
    n_datasets = as_int(n_datasets, "n_datasets", minimum=1)
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    draws, groups = [], {}
    for j, cell in enumerate(cells):
        if not isinstance(cell, (tuple, list)) or len(cell) != 3:
            raise ValueError(f"cells[{j}] must be (noise_percent, n_targets, seed), got {cell!r}")
        noise, n_targets, seed = cell
        noise = as_real(noise, "noise_percent", 0.0)
        n_targets = as_int(n_targets, "n_targets", minimum=2)
        draws.append(montecarlo.run(draw_simulation, n_datasets, np.random.default_rng(seed), 1, n_starts, noise,
                                    n_targets=n_targets, n_jobs=n_jobs))
        groups.setdefault(n_targets, []).append(j)
    out: list[dict[str, np.ndarray]] = [{} for _ in cells]
    for members in groups.values():
        results = iter(run_draws([d for j in members for d in draws[j]]))   # all nets of one size at once
        for j in members:
            parts = [score_simulation(d, next(results)) for d in draws[j]]
            merged = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
            merged["dataset"] = np.repeat(np.arange(n_datasets), n_starts)
            out[j] = merged
    return out


def accuracy(res: dict[str, np.ndarray]) -> dict[str, float]:
    """Percentage of correct assignments of every method of :data:`METHODS` in one cell.

    The net's is the mean over data sets of the share of its starts that converge to the
    correct assignment; the other methods are deterministic (NaN where the optimum was not
    computed).

    Parameters
    ----------
    res : dict of arrays
        A result of :func:`simulate` with the reference solvers (or one cell of
        :func:`comparison_cells`).
    """
    if not isinstance(res, dict):
        raise TypeError(f"res must be a dict of arrays, got {type(res).__name__}")
    missing = [k for k in ("dataset", *METHODS.values()) if k not in res]
    if missing:
        raise ValueError(f"res lacks {missing} (run with the reference solvers)")
    dataset = np.asarray(res["dataset"])
    counts = np.bincount(dataset)
    per_set = np.bincount(dataset, weights=np.asarray(res["correct"], dtype=float))[counts > 0] / counts[counts > 0]
    out = {"net": 100 * float(per_set.mean())}
    for name, key in list(METHODS.items())[1:]:
        v = np.asarray(res[key], dtype=float)
        out[name] = 100 * float(v.mean()) if np.all(np.isfinite(v)) else float("nan")
    return out


def noise_sweep(noise_levels: Sequence[float], n_datasets: int, n_starts: int, seed: int, *,
                n_jobs: int | None = None) -> list[dict[str, float]]:
    """Accuracy against noise, four targets: one row per level (level ``i`` from ``default_rng(seed + i)``).

    Returns
    -------
    list of dict
        ``noise %``, the :func:`accuracy` of every method, ``net sweeps per run`` (mean
        iterations, a failed run counting the full 50) and ``optimum cost <= true cost %``.
    """
    levels = _as_sequence(noise_levels, "noise_levels")
    seed = as_int(seed, "seed", minimum=0)
    cells = comparison_cells([(n, 4, seed + i) for i, n in enumerate(levels)], n_datasets, n_starts, n_jobs=n_jobs)
    return [{"noise %": float(n), **accuracy(res), "net sweeps per run": float(res["iterations"].mean()),
             "optimum cost <= true cost %": 100 * float(np.mean(res["optimal_cost"] <= res["true_cost"] + 1e-12))}
            for n, res in zip(levels, cells)]


def size_sweep(sizes: Sequence[int], noise_levels: Sequence[float], n_datasets: int, n_starts: int, seed: int, *,
               n_jobs: int | None = None) -> list[dict[str, float]]:
    """Accuracy against the number of targets ``N_T = N_M``: one row per size and noise level.

    Size ``i`` at noise level ``j`` is drawn from ``default_rng(seed + 10 i + j)`` (at most
    ten noise levels).

    Returns
    -------
    list of dict
        ``targets``, ``noise %``, the :func:`accuracy` of every method, ``net converged %``
        and ``net iterations`` (mean over the converged runs, NaN if none).
    """
    sizes = [as_int(nt, "size", minimum=2) for nt in _as_sequence(sizes, "sizes")]
    levels = _as_sequence(noise_levels, "noise_levels")
    if len(levels) > 10:
        raise ValueError(f"at most 10 noise levels (seeds seed + 10 i + j), got {len(levels)}")
    seed = as_int(seed, "seed", minimum=0)
    keys = [(nt, n) for nt in sizes for n in levels]
    cells = comparison_cells([(n, nt, seed + 10 * i + j) for i, nt in enumerate(sizes) for j, n in enumerate(levels)],
                             n_datasets, n_starts, n_jobs=n_jobs)
    rows = []
    for (nt, n), res in zip(keys, cells):
        conv = res["converged"]
        rows.append({"targets": nt, "noise %": float(n), **accuracy(res),
                     "net converged %": 100 * float(conv.mean()),
                     "net iterations": float(res["iterations"][conv].mean()) if conv.any() else float("nan")})
    return rows

"""The Monte Carlo studies of the Table 1 chapter: success rates, Fig. 5 runs, the fixed-point bound.

Every study draws its trials through :func:`projtrack.montecarlo.run`, so its results do
not depend on ``n_jobs``. A trial function takes the trial's generator first. The studies
draw every trial's data sets and starts first and then run the nets of all trials that share
an update rule as one batch (:func:`projtrack.experiments.neuralnet.run_draws`), with the
same results as running the trial functions one by one:

* :func:`table1_trial` / :func:`table1_study`: the paper's simulations (own data set and own
  start each) at several noise levels, scored as in Table 1;
* :func:`sensitivity_trial` / :func:`sensitivity_cell` / :func:`sensitivity_cells`: the same under
  another reading of the paper (unit of D, update rule, noise law), reduced to counts of
  successes and wrong stops;
* :func:`evolution_trial`: noise-free runs with their recorded states (Fig. 5);
* :func:`bound_trial` / :func:`fixed_point_bound`: for one data set, the largest summed
  distance of the true assignment's neurons and the smallest one of any wrong assignment
  (an assignment is a fixed point when that is below :func:`projtrack.neuralnet.fixed_point_limit`);
* :func:`truth_index`, :func:`bound_direct_check`: the true assignment in the enumeration of
  :func:`projtrack.neuralnet.assignment_max_sums`, and the bound against a direct evaluation
  of every neuron (:func:`direct_check_trial` on a data set of its own).
"""

from __future__ import annotations

import itertools
from typing import Any, Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng
from projtrack.neuralnet import (assignment_max_sums, distance_tensor, fixed_point_limit, initial_states,
                                 is_correct_assignment, is_fixed_point, run_net, states_to_assignment)
from projtrack.scenes.tracks3d import TrackScene, make_tracks

from .failures import draws_modes, mode_counts
from .table1 import draw_simulation, run_draws, score_simulation, simulate

__all__ = [
    "TABLE1_KEYS",
    "table1_trial",
    "table1_study",
    "sensitivity_trial",
    "sensitivity_cell",
    "sensitivity_cells",
    "evolution_trial",
    "truth_index",
    "bound_trial",
    "fixed_point_bound",
    "bound_direct_check",
    "direct_check_trial",
]

#: Per-run results of :func:`simulate` kept by :func:`table1_study`, with the run's
#: :data:`~projtrack.experiments.neuralnet.MODES` label (``mode``).
TABLE1_KEYS = ("status", "iterations", "converged", "correct", "optimal_correct", "mode")

_PERMS4 = np.array(list(itertools.permutations(range(4))))
_PERM4_INDEX = {tuple(p): k for k, p in enumerate(_PERMS4)}


def _as_noise_levels(noise_levels: object) -> list[float]:
    if isinstance(noise_levels, (str, bytes)) or not isinstance(noise_levels, Sequence) or not noise_levels:
        raise TypeError("noise_levels must be a non-empty sequence of numbers")
    return [as_real(n, "noise level", 0.0) for n in noise_levels]


def _as_trials(n_runs: int, chunk: int, name: str) -> int:
    n_runs = as_int(n_runs, name, minimum=1)
    chunk = as_int(chunk, "chunk", minimum=1)
    if n_runs % chunk:
        raise ValueError(f"{name} = {n_runs} must be a multiple of chunk = {chunk}")
    return n_runs // chunk


def table1_trial(rng: np.random.Generator, noise_percent: float, n_runs: int) -> dict[str, np.ndarray]:
    """One Monte Carlo trial of Table 1: ``n_runs`` simulations, each with its own data set and start.

    :func:`projtrack.experiments.neuralnet.simulate` with ``n_starts = 1`` and the paper's
    settings (four targets, five frames, unit 256 px, update as printed).
    """
    return simulate(rng, n_runs, 1, noise_percent)


def table1_study(noise_levels: Sequence[float], n_runs: int, chunk: int, seed: int
                 ) -> dict[float, dict[str, np.ndarray]]:
    """Table 1 as a Monte Carlo study: ``n_runs`` simulations per noise level.

    Level ``i`` draws ``n_runs // chunk`` trials of :func:`table1_trial` (``chunk``
    simulations each) from ``numpy.random.default_rng(seed + i)``; the nets of all trials
    and levels run as one batch, with the results of running the trials one by one.

    Parameters
    ----------
    noise_levels : sequence of float
        Noise ``n`` in percent, each >= 0.
    n_runs : int
        Simulations per level, a multiple of ``chunk``.
    chunk : int
        Simulations per Monte Carlo trial.
    seed : int
        Seed of the first level.

    Returns
    -------
    dict
        For every level, the arrays :data:`TABLE1_KEYS` of length ``n_runs`` in trial order.
    """
    levels = _as_noise_levels(noise_levels)
    n_trials = _as_trials(n_runs, chunk, "n_runs")
    seed = as_int(seed, "seed", minimum=0)
    draws = {n: montecarlo.run(draw_simulation, n_trials, np.random.default_rng(seed + i), chunk, 1, n)
             for i, n in enumerate(levels)}
    flat = [d for n in levels for d in draws[n]]
    results = run_draws(flat)   # all nets of all levels at once
    modes = iter(draws_modes(flat, results))
    results = iter(results)
    out = {}
    for n in levels:
        parts = [{**score_simulation(d, next(results)), "mode": next(modes)} for d in draws[n]]
        out[n] = {k: np.concatenate([p[k] for p in parts]) for k in TABLE1_KEYS}
    return out


def sensitivity_trial(rng: np.random.Generator, noise_percent: float, unit: float, noise_law: str,
                      n_runs: int, options: dict[str, Any]) -> dict[str, np.ndarray]:
    """``n_runs`` simulations under one reading (``unit`` of D, ``noise_law``, ``options`` of the update).

    ``options`` are passed to :func:`projtrack.experiments.neuralnet.simulate` (``mode``,
    ``self_coupling``, ``exact_energy``, ``offset``); no reference solvers are run.
    Returns the per-run ``converged`` and ``correct`` masks.
    """
    if not isinstance(options, dict):
        raise TypeError(f"options must be a dict of keyword arguments, got {type(options).__name__}")
    r = simulate(rng, n_runs, 1, noise_percent, noise_law=noise_law, unit=float(unit), references=False,
                 **options)
    return {k: r[k] for k in ("converged", "correct")}


def sensitivity_cell(noise_percent: float, unit: float, noise_law: str, options: dict[str, Any],
                     seed: object, n_runs: int, chunk: int) -> dict[str, int]:
    """How ``n_runs`` simulations under one reading end.

    ``n_runs // chunk`` trials of :func:`sensitivity_trial` drawn from
    ``numpy.random.default_rng(seed)`` (``seed`` anything ``default_rng`` accepts, e.g. a
    list of ints naming the cell).

    Returns
    -------
    dict
        The number of runs in each of :data:`~projtrack.experiments.neuralnet.MODES`
        (:func:`~projtrack.experiments.neuralnet.run_modes`): ``correct`` (the paper's success),
        ``wrong`` (converged to a wrong state), ``cycle with the truth``, ``other cycle``,
        ``wandering``.
    """
    return sensitivity_cells([(noise_percent, unit, noise_law, options, seed)], n_runs, chunk)[0]


def sensitivity_cells(cells: Sequence[tuple[float, float, str, dict[str, Any], object]], n_runs: int, chunk: int
                      ) -> list[dict[str, int]]:
    """:func:`sensitivity_cell` for many cells, the nets of all cells with the same options in one batch.

    Parameters
    ----------
    cells : sequence of (noise_percent, unit, noise_law, options, seed)
        The arguments of :func:`sensitivity_cell` for each cell.
    n_runs, chunk : int
        Simulations per cell and per Monte Carlo trial.

    Returns
    -------
    list of dict
        In the order of ``cells``; equal to ``[sensitivity_cell(*c, n_runs, chunk) for c in cells]``.
    """
    n_trials = _as_trials(n_runs, chunk, "n_runs")
    cells = list(cells)
    draws, groups = [], {}
    for j, cell in enumerate(cells):
        if not isinstance(cell, (tuple, list)) or len(cell) != 5:
            raise ValueError(f"cells[{j}] must be (noise_percent, unit, noise_law, options, seed), got {cell!r}")
        noise, unit, law, options, seed = cell
        if not isinstance(options, dict):
            raise TypeError(f"options must be a dict of keyword arguments, got {type(options).__name__}")
        draws.append(montecarlo.run(draw_simulation, n_trials, np.random.default_rng(seed), chunk, 1, noise,
                                    noise_law=law, unit=float(unit)))
        groups.setdefault(tuple(sorted(options.items())), []).append(j)
    out: list[dict[str, int]] = [{} for _ in cells]
    for key, members in groups.items():
        flat = [d for j in members for d in draws[j]]
        results = run_draws(flat, **dict(key))
        modes = iter(draws_modes(flat, results, **dict(key)))
        for j in members:
            out[j] = mode_counts(np.concatenate([next(modes) for _ in draws[j]]))
    return out


def evolution_trial(rng: np.random.Generator, n_runs: int) -> list[dict[str, Any]]:
    """``n_runs`` noise-free simulations (own data set and start each) with their states recorded.

    Returns
    -------
    list of dict, one per run
        ``scene`` (:class:`~projtrack.scenes.tracks3d.TrackScene`), ``history`` (the start and
        the state after every sweep, see :class:`projtrack.neuralnet.NetResult`),
        ``iterations``, ``correct`` (converged to the true assignment), ``first admissible``
        and ``first correct`` (the state after the first sweep).
    """
    rng = as_rng(rng)
    n_runs = as_int(n_runs, "n_runs", minimum=1)
    scenes = [make_tracks(rng, 4, 5, noise_percent=0.0) for _ in range(n_runs)]
    D = distance_tensor(np.stack([s.positions for s in scenes]) / 256)
    run = run_net(D, initial_states(rng, n_runs, 4, 4, 5), record=True)
    out = []
    for k, scene in enumerate(scenes):
        ok = bool(run.status[k] == "converged"
                  and is_correct_assignment(states_to_assignment(run.states[k]), scene.labels))
        first = run.history[1, k].astype(np.int8)
        out.append({"scene": scene, "history": run.history[:, k], "iterations": int(run.iterations[k]),
                    "correct": ok, "first admissible": states_to_assignment(first) is not None,
                    "first correct": is_correct_assignment(states_to_assignment(first), scene.labels)})
    return out


def truth_index(labels: np.ndarray) -> tuple[int, ...]:
    """Index of the true assignment in the array of :func:`projtrack.neuralnet.assignment_max_sums`.

    Four targets, labelled by their measurement in frame 1 (frame 1 is the identity there).

    Parameters
    ----------
    labels : array_like of int, shape (N_P, 4)
        ``labels[a, alpha]``: target of measurement ``alpha`` of frame ``a`` (a permutation per frame).
    """
    labels = np.asarray(labels)
    if labels.ndim != 2 or labels.shape[1] != 4 or labels.shape[0] < 3 or np.any(
            np.sort(labels, axis=1) != np.arange(4)):
        raise ValueError(f"labels must be a (N_P >= 3, 4) array of permutations of 0..3, got {labels.shape}")
    rel = np.argsort(labels, axis=1).T[labels[0]]
    return tuple(_PERM4_INDEX[tuple(rel[:, a])] for a in range(1, rel.shape[1]))


def bound_trial(rng: np.random.Generator, noise_percent: float) -> dict[str, float]:
    """One data set of the fixed-point bound (four targets, five frames, D in pixels).

    Returns
    -------
    dict
        ``truth``: the largest summed distance (:func:`projtrack.neuralnet.neuron_distance_sums`)
        over the neurons of the true assignment; ``wrong``: the smallest such value over all
        other one-to-one assignments.
    """
    scene = make_tracks(rng, 4, 5, noise_percent=noise_percent)
    M = assignment_max_sums(distance_tensor(scene.positions))
    t = truth_index(scene.labels)
    truth = float(M[t])
    M[t] = np.inf
    return {"truth": truth, "wrong": float(M.min())}


def fixed_point_bound(noise_levels: Sequence[float], n_sets: int, seed: int) -> dict[float, list[dict[str, float]]]:
    """:func:`bound_trial` for ``n_sets`` data sets per noise level (level ``i`` from ``default_rng(seed + i)``)."""
    levels = _as_noise_levels(noise_levels)
    n_sets = as_int(n_sets, "n_sets", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    return {n: montecarlo.run(bound_trial, n_sets, np.random.default_rng(seed + i), n)
            for i, n in enumerate(levels)}


def bound_direct_check(scene: TrackScene, unit: float) -> tuple[int, int, int]:
    """The bound against a direct evaluation of every neuron's input.

    For all ``24^3`` one-to-one assignments whose frames 1 and 2 are the true ones (D in
    units of ``unit`` pixels), compares :func:`projtrack.neuralnet.is_fixed_point` with the
    test ``max S < fixed_point_limit()``.

    Returns
    -------
    states : int
        Number of assignments checked.
    agree : int
        How many of them both methods classify alike.
    fixed : int
        How many are fixed points.
    """
    if not isinstance(scene, TrackScene):
        raise TypeError(f"scene must be a TrackScene, got {type(scene).__name__}")
    unit = as_real(unit, "unit", 0.0, low_open=True)
    if scene.positions.shape[1:] != (4, 3) or scene.positions.shape[0] != 5:
        raise ValueError(f"scene must have 5 frames of 4 targets, got positions {scene.positions.shape}")
    p2 = truth_index(scene.labels)[0]
    D = distance_tensor(scene.positions / unit)
    M = assignment_max_sums(D)
    rest = np.array(list(itertools.product(range(24), repeat=3)))
    m = len(rest)
    A = np.stack([np.broadcast_to(_PERMS4[0], (m, 4)), np.broadcast_to(_PERMS4[p2], (m, 4)),
                  _PERMS4[rest[:, 0]], _PERMS4[rest[:, 1]], _PERMS4[rest[:, 2]]], axis=-1)
    X = np.zeros((m, 4, 4, 5))
    X[np.arange(m)[:, None, None], np.arange(4)[None, :, None], A, np.arange(5)[None, None, :]] = 1
    direct = is_fixed_point(X, D)
    by_bound = M[p2][tuple(rest.T)] < fixed_point_limit()
    return m, int((direct == by_bound).sum()), int(direct.sum())


def direct_check_trial(rng: np.random.Generator, noise_percent: float, unit: float) -> tuple[int, int, int]:
    """:func:`bound_direct_check` on a data set of its own (four targets, five frames) drawn from ``rng``."""
    scene = make_tracks(rng, 4, 5, noise_percent=noise_percent)
    return bound_direct_check(scene, unit)

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
  of every neuron (:func:`direct_check_trial` on a data set of its own);
* :func:`bound_table`, :func:`fixed_point_grid`, :func:`cut_for_rates`: the bound read at one cut,
  over update rules and units, and the cut the paper's rates would need;
* :func:`bound_holds`: the bound against the simulated success of every reading;
  :func:`plot_fixed_point_bound` draws the bound against the cut.
"""

from __future__ import annotations

import itertools
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_probability, as_real, as_rng
from projtrack.neuralnet import (assignment_max_sums, distance_tensor, fixed_point_limit, initial_states,
                                 is_correct_assignment, is_fixed_point, run_net, states_to_assignment)
from projtrack.scenes.tracks3d import TrackScene, make_tracks

from projtrack.stable import tidy
from projtrack.tolerance import EXACT, ROUNDING, Tolerance, share, statistical

from .criterion import ci_step, rate_ci
from .table1 import draw_simulation, draws_modes, mode_counts, run_draws, score_simulation, simulate

__all__ = [
    "TABLE1_KEYS",
    "table1_trial",
    "table1_study",
    "sensitivity_trial",
    "sensitivity_cell",
    "sensitivity_cells",
    "evolution_trial",
    "first_sweep_pattern",
    "end_states",
    "truth_index",
    "bound_trial",
    "fixed_point_bound",
    "bound_direct_check",
    "direct_check_trial",
    "bound_table",
    "fixed_point_grid",
    "cut_for_rates",
    "bound_holds",
    "plot_fixed_point_bound",
]

#: Per-run results of :func:`simulate` kept by :func:`table1_study`, with the run's
#: :data:`MODES` label (``mode``).
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
        The number of runs in each of :data:`MODES`
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


def evolution_trial(rng: np.random.Generator, n_runs: int, unit: float = 256.0) -> list[dict[str, Any]]:
    """``n_runs`` noise-free simulations (own data set and start each) with their states recorded.

    ``unit`` is the unit of D in pixels (the book's reading: 256 px).

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
    D = distance_tensor(np.stack([s.positions for s in scenes]) / float(unit))
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


def _bound_frames(bound: Mapping[float, Sequence[Mapping[str, float]]]) -> dict[float, tuple[np.ndarray, np.ndarray]]:
    if not isinstance(bound, Mapping) or not bound or 0.0 not in bound:
        raise ValueError("bound must map noise levels (including 0.0) to the rows of fixed_point_bound")
    return {float(n): (np.array([r["truth"] for r in rows], dtype=float),
                       np.array([r["wrong"] for r in rows], dtype=float)) for n, rows in bound.items()}


def bound_table(bound: Mapping[float, Sequence[Mapping[str, float]]], cut: float
                ) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """The fixed-point bound at one cut on ``max S`` (pixels), per noise level.

    Parameters
    ----------
    bound : mapping noise level -> list of dict
        :func:`fixed_point_bound` (``truth``, ``wrong``: the smallest ``max S`` in pixels).
    cut : float
        An assignment is a fixed point when its ``max S`` is below ``cut``.

    Returns
    -------
    table : pandas.DataFrame
        ``noise %``, ``truth is a fixed point %`` (the bound on the success rate), ``bound, 95% high %``,
        ``median max S of the truth (px)`` (below ``1e-9``, rounding noise of straight tracks, shown as
        0) and ``a wrong one is a fixed point %``.
    tolerance : dict of str to Tolerance
        Shares of the data sets (a data set near the cut may flip); the median is a direct
        computation on the positions.
    """
    frames = _bound_frames(bound)
    cut = as_real(cut, "cut", 0.0)
    n_min = min(len(t) for t, _ in frames.values())
    rows = []
    for n, (t, w) in frames.items():
        k = int((t < cut).sum())
        rows.append({"noise %": n, "truth is a fixed point %": 100 * k / len(t),
                     "bound, 95% high %": 100 * rate_ci(k, len(t))[1],
                     "median max S of the truth (px)": float(tidy(np.median(t), 9, atol=1e-9)),
                     "a wrong one is a fixed point %": 100 * float((w < cut).mean())})
    runs = share(n_min, percent=True)
    ci = statistical(atol=100 * ci_step(n_min),
                     why=f"one of {n_min} data sets crossing the cut moves a 95% Clopper-Pearson bound by at most "
                         "this much")
    return pd.DataFrame(rows), {"noise %": EXACT, "truth is a fixed point %": runs,
                                "a wrong one is a fixed point %": runs, "bound, 95% high %": ci,
                                "median max S of the truth (px)": ROUNDING}


def fixed_point_grid(bound: Mapping[float, Sequence[Mapping[str, float]]], rules: Mapping[str, Mapping[str, Any]],
                     units: Sequence[float]) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """Which true and wrong assignments are fixed points, for every update rule and unit of D.

    An assignment is a fixed point when its ``max S`` (pixels) is below ``fixed_point_limit(**rule) * unit``.

    Parameters
    ----------
    bound : mapping noise level -> list of dict
        :func:`fixed_point_bound`.
    rules : mapping name -> options of :func:`projtrack.neuralnet.fixed_point_limit`
    units : sequence of float
        Units of D in pixels.

    Returns
    -------
    table : pandas.DataFrame
        ``rule``, ``unit (px)``, ``truth fixed at <n>% %`` for every noisy level and ``wrong fixed
        at 0% %`` (share of noise-free data sets where some wrong assignment is a fixed point).
    tolerance : dict of str to Tolerance
        Shares of the data sets.
    """
    frames = _bound_frames(bound)
    if not isinstance(rules, Mapping) or not rules:
        raise TypeError("rules must be a non-empty mapping of name -> options")
    units = [as_real(u, "unit", 0.0, low_open=True) for u in units]
    rows = []
    for name, kw in rules.items():
        lim = fixed_point_limit(**dict(kw))
        for u in units:
            cut = lim * u
            row = {"rule": name, "unit (px)": int(u) if float(u).is_integer() else u}
            for n, (t, _) in frames.items():
                if n > 0:
                    row[f"truth fixed at {n:g}% %"] = 100 * float((t < cut).mean())
            row["wrong fixed at 0% %"] = 100 * float((frames[0.0][1] < cut).mean())
            rows.append(row)
    n_min = min(len(t) for t, _ in frames.values())
    return pd.DataFrame(rows), {"unit (px)": EXACT, "*": share(n_min, percent=True)}


def cut_for_rates(bound: Mapping[float, Sequence[Mapping[str, float]]], rates: Mapping[float, float]) -> float:
    """The smallest cut on ``max S`` (pixels) at which the bound allows the given success rates.

    Parameters
    ----------
    bound : mapping noise level -> list of dict
        :func:`fixed_point_bound`.
    rates : mapping noise level -> rate in [0, 1]
        E.g. the lower ends of the 95% intervals of the paper's rates.

    Returns
    -------
    float
        The largest, over the levels, ``inverted_cdf`` quantile of the truth's ``max S`` at the
        level's rate, raised by one part in a million (so that the share below it reaches the rate).
    """
    frames = _bound_frames(bound)
    if not isinstance(rates, Mapping) or not rates:
        raise TypeError("rates must be a non-empty mapping of noise level -> rate")
    out = 0.0
    for n, p in rates.items():
        p = as_probability(p, "rate")
        if float(n) not in frames:
            raise ValueError(f"no bound data at noise level {n}")
        if p > 0:
            out = max(out, float(np.quantile(frames[float(n)][0], p, method="inverted_cdf")))
    return out * 1.000001


def bound_holds(grid: pd.DataFrame, shares: pd.DataFrame, runs: int, n_sets: int) -> pd.DataFrame:
    """The fixed-point bound against the simulations of every reading with ball noise.

    A reading's success rate cannot exceed the share of data sets whose truth is a fixed point.
    The two come from different data sets, so the check compares the lower 95% end of the
    simulated rate with the upper 95% end of the bound.

    Parameters
    ----------
    grid : pandas.DataFrame
        :func:`fixed_point_grid` (``rule``, ``unit (px)``, ``truth fixed at <n>% %``).
    shares : pandas.DataFrame
        :func:`~projtrack.experiments.neuralnet.sensitivity_table` (``reading``, ``noise %``, ``correct %``).
    runs : int
        Simulations per cell of ``shares``.
    n_sets : int
        Data sets per level of the bound.

    Returns
    -------
    pandas.DataFrame
        One row per noisy cell found in both: ``reading``, ``noise %``, ``bound %``, ``correct %``
        and ``holds`` (the lower end of the rate at most the upper end of the bound).
    """
    runs = as_int(runs, "runs", minimum=1)
    n_sets = as_int(n_sets, "n_sets", minimum=1)
    rows = []
    for _, g in grid.iterrows():
        unit = g["unit (px)"]
        label = f"{g['rule']}, ball, unit {int(unit) if float(unit).is_integer() else unit}"
        sim = shares[shares["reading"] == label]
        for _, s in sim.iterrows():
            key = f"truth fixed at {s['noise %']:g}% %"
            if key not in g or s["noise %"] == 0:
                continue
            b, c = float(g[key]), float(s["correct %"])
            lo = rate_ci(int(round(c * runs / 100)), runs)[0]
            hi = rate_ci(int(round(b * n_sets / 100)), n_sets)[1]
            rows.append({"reading": label, "noise %": float(s["noise %"]), "bound %": b, "correct %": c,
                         "holds": bool(lo <= hi + 1e-12)})
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- figures


def plot_fixed_point_bound(bound: Mapping[float, object], cut_book: float, cut_needed: float):
    """Share of data sets whose truth (blue) or some wrong assignment (red, noise-free) is a fixed
    point, against the cut on ``max S`` in pixels. ``bound`` maps noise level -> rows with keys
    ``truth`` and ``wrong`` (the smallest ``max S``, pixels), as the rows of
    :func:`~projtrack.experiments.neuralnet.fixed_point_bound`."""
    import matplotlib.pyplot as plt

    cuts = np.geomspace(1, 1e3, 200)
    fig, ax = plt.subplots(figsize=(6.4, 3.3))
    levels = [n for n in bound if n > 0]
    for n, ls in zip(levels, ["-", "--", ":"]):
        t = np.array([r["truth"] for r in bound[n]], dtype=float)
        ax.plot(cuts, [100 * float((t < c).mean()) for c in cuts], "C0", ls=ls, label=f"truth fixed, {n:g}% noise")
    w = np.array([r["wrong"] for r in bound[0.0]], dtype=float)
    ax.plot(cuts, [100 * float((w < c).mean()) for c in cuts], "C3", label="a wrong one fixed, no noise")
    ax.axvline(cut_book, color="0.3", lw=0.9)
    ax.axvline(cut_needed, color="0.3", lw=0.9, ls="--")
    ax.text(cut_book * 1.08, 4, "as read", rotation=90, va="bottom", fontsize=9)
    ax.text(cut_needed * 1.08, 4, "paper's rates", rotation=90, va="bottom", fontsize=9)
    ax.set_xscale("log")
    ax.set_xlabel("cut on max $S$ (pixels) $= c\\,u / A_4$")
    ax.set_ylabel("data sets, %")
    ax.legend(frameon=False, loc="center right")
    fig.tight_layout()
    return fig


def first_sweep_pattern(history: np.ndarray, sweep: int = 1) -> dict[str, Any]:
    """The state of one run after a sweep, against Sec. VI's description of Fig. 5.

    The paper: after the first iteration "the target-measurement associations appear random
    (i.e. the neural net has assigned many of the measurements to only one target and vice
    versa)". Read: in some frame a target holds two or more measurements, or a measurement is
    held by two or more targets.

    Parameters
    ----------
    history : array_like, shape (n_sweeps + 1, N_T, N_M, N_P)
        The start and the state after every sweep (``history`` of :func:`evolution_trial`).
    sweep : int, default 1
        Which sweep's state.

    Returns
    -------
    dict
        ``active`` (number of neurons on), ``target with several`` (some target holds two or
        more measurements in some frame), ``measurement with several`` (the converse) and
        ``conflict`` (either).
    """
    H = as_array(history, "history", ndim=4)
    sweep = as_int(sweep, "sweep", minimum=0, maximum=H.shape[0] - 1)
    X = np.rint(H[sweep]).astype(int)
    rows, cols = X.sum(axis=1), X.sum(axis=0)   # (N_T, N_P), (N_M, N_P)
    t, m = bool((rows >= 2).any()), bool((cols >= 2).any())
    return {"active": int(X.sum()), "target with several": t, "measurement with several": m, "conflict": t or m}


def end_states(rules: Mapping[str, Mapping[str, Any]], units: Sequence[float], noise_levels: Sequence[float],
               n_runs: int, seed: int) -> pd.DataFrame:
    """How the runs of several update rules end, admissible or not, under several units of D.

    Level ``j`` draws ``n_runs`` simulations (one data set and start each,
    :func:`~projtrack.experiments.neuralnet.draw_simulation` in pixels) from
    ``numpy.random.default_rng([seed, j])``; every rule and unit runs on them.

    Parameters
    ----------
    rules : mapping of label to options of :func:`projtrack.neuralnet.run_net`
    units : sequence of float
        Units of D in pixels.
    noise_levels : sequence of float
    n_runs : int
    seed : int

    Returns
    -------
    pandas.DataFrame
        ``rule``, ``unit (px)``, ``noise %`` and the percentages of runs that converge to the
        true assignment (``correct %``), to another admissible state (``wrong admissible %``),
        to an inadmissible state (``inadmissible %``), or do not converge.
    """
    if not isinstance(rules, Mapping) or not rules:
        raise TypeError("rules must be a non-empty mapping of label -> options")
    units = [as_real(u, "unit", 0.0, low_open=True) for u in units]
    levels = [as_real(n, "noise level", 0.0) for n in noise_levels]
    n_runs = as_int(n_runs, "n_runs", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    rows = []
    for j, noise in enumerate(levels):
        d = draw_simulation(np.random.default_rng([seed, j]), n_runs, 1, noise, unit=1.0)
        for label, options in rules.items():
            for u in units:
                r = run_net(d.D / u, d.X0, **options)
                A = [states_to_assignment(r.states[k]) if r.converged[k] else None for k in range(n_runs)]
                ok = [a is not None and is_correct_assignment(a, s.labels) for a, s in zip(A, d.scenes)]
                inad = [bool(r.converged[k]) and A[k] is None for k in range(n_runs)]
                rows.append({"rule": label, "unit (px)": u, "noise %": noise, "correct %": 100 * float(np.mean(ok)),
                             "wrong admissible %": 100 * float(np.mean(r.converged & ~np.array(ok) & ~np.array(inad))),
                             "inadmissible %": 100 * float(np.mean(inad)),
                             "not converged %": 100 * float(np.mean(~r.converged))})
    return pd.DataFrame(rows)

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

Other update rules of the same energy. Sec. VI updates the neurons serially and says this
"results in faster convergence than if all new neuron states are calculated in parallel and
simultaneously fed back, as is usually done": :func:`update_order_study` runs both orders on the
same data sets and starts. The chapter's fixed-point bound shows that a neuron-by-neuron rule of
eq. (4) cannot keep a noisy correct assignment, whatever the start; a rule that keeps the paper's
energy and does find noisy tracks updates the neurons of one *frame* together. It is the
block-coordinate descent of :func:`projtrack.neuralnet.coordinate_descent_assignment` with another
start (a conventional solver, not a neural rule), and it is not shown to be the nearest working
rule: no rule closer to eq. (4), such as swaps of two targets within a frame, is tried. With the other frames fixed, terms 1-3 of eq. (8) vanish on
every admissible state of the frame and term 4 is linear in it, so the frame's state of least
energy is a linear assignment (:func:`frame_descent`, from the admissible state nearest to the
net's start, :func:`nearest_admissible`; :func:`frame_rule_study` on the Table 1 data sets,
:func:`frame_rule_table` beside the paper's Table 1). Every
state stays admissible, the energy falls at every change, and the run stops at a state no single
frame can improve. :func:`plot_comparison` and :func:`plot_timing` draw the page's figures.

Computation. Sec. II says conventional optimisation "generally require[s] much more computation
than the Hopfield net": :func:`operation_counts` counts the arithmetic operations of each solver
per data set (machine-independent, unlike timings), and :func:`descent_rounds` the rounds
coordinate descent takes.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real
from projtrack.neuralnet import assignment_cost, is_correct_assignment
from projtrack.neuralnet._checks import _check_D
from projtrack.neuralnet.references import _frame_cost
from projtrack.tolerance import EXACT, Tolerance, mean_over, share

from .table1 import draw_simulation, run_draws, score_simulation, simulate

__all__ = ["METHODS", "comparison_trial", "comparison_cells", "accuracy", "net_standard_error", "noise_sweep", "size_sweep",
           "nearest_admissible", "frame_descent", "frame_rule_study", "frame_rule_table", "update_order_study",
           "plot_comparison", "plot_timing", "operation_counts", "descent_rounds"]

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


def net_standard_error(res: dict[str, np.ndarray]) -> float:
    """Monte Carlo standard error (percentage points) of the net's :func:`accuracy` in one cell.

    The net's accuracy is a mean over data sets of the share of their starts that succeed, so its
    standard error is the standard deviation of those shares over the square root of the number
    of data sets (the starts of one data set are not independent). NaN with fewer than two.
    """
    if not isinstance(res, dict) or "dataset" not in res or "correct" not in res:
        raise TypeError("res must be a dict of arrays with 'dataset' and 'correct'")
    dataset = np.asarray(res["dataset"])
    counts = np.bincount(dataset)
    per_set = np.bincount(dataset, weights=np.asarray(res["correct"], dtype=float))[counts > 0] / counts[counts > 0]
    if per_set.size < 2:
        return float("nan")
    return 100 * float(per_set.std(ddof=1) / np.sqrt(per_set.size))


def noise_sweep(noise_levels: Sequence[float], n_datasets: int, n_starts: int, seed: int, *,
                n_jobs: int | None = None) -> list[dict[str, float]]:
    """Accuracy against noise, four targets: one row per level (level ``i`` from ``default_rng(seed + i)``).

    Returns
    -------
    list of dict
        ``noise %``, the :func:`accuracy` of every method, ``net s.e.`` (:func:`net_standard_error`),
        ``net sweeps per run`` (mean iterations, a failed run counting the full 50) and
        ``optimum cost <= true cost %``.
    """
    levels = _as_sequence(noise_levels, "noise_levels")
    seed = as_int(seed, "seed", minimum=0)
    cells = comparison_cells([(n, 4, seed + i) for i, n in enumerate(levels)], n_datasets, n_starts, n_jobs=n_jobs)
    return [{"noise %": float(n), **accuracy(res), "net s.e.": net_standard_error(res),
             "net sweeps per run": float(res["iterations"].mean()),
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
        ``targets``, ``noise %``, the :func:`accuracy` of every method, ``net s.e.``
        (:func:`net_standard_error`), ``net converged %``
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
        rows.append({"targets": nt, "noise %": float(n), **accuracy(res), "net s.e.": net_standard_error(res),
                     "net converged %": 100 * float(conv.mean()),
                     "net iterations": float(res["iterations"][conv].mean()) if conv.any() else float("nan")})
    return rows


# ----------------------------------------------------------------------------- other update rules


def nearest_admissible(X0: np.ndarray) -> np.ndarray:
    """The admissible assignment closest to an analog state: per frame, the largest summed value.

    Parameters
    ----------
    X0 : array_like, shape (N_T, N_M, N_P), ``N_T <= N_M``
        E.g. a perturbed all-equal start (:func:`projtrack.neuralnet.initial_states`).

    Returns
    -------
    ndarray of int, shape (N_T, N_P)
        Measurement of target ``i`` in frame ``a``; distinct within a frame.
    """
    X0 = as_array(X0, "X0")
    if X0.ndim != 3 or X0.shape[0] > X0.shape[1]:
        raise ValueError(f"X0 must have shape (N_T, N_M, N_P) with N_T <= N_M, got {X0.shape}")
    A = np.empty((X0.shape[0], X0.shape[2]), dtype=np.intp)
    for a in range(X0.shape[2]):
        rows, cols = linear_sum_assignment(X0[:, :, a], maximize=True)
        A[rows, a] = cols
    return A


def frame_descent(D: np.ndarray, initial: np.ndarray, max_rounds: int = 50) -> tuple[np.ndarray, int, bool]:
    """Serial frame-by-frame descent of the energy of eq. (8) over admissible states.

    A round visits the frames in order; each frame takes the assignment of least energy given
    the others (a linear assignment on the summed eq. (7) distances of the triples containing
    it). On admissible states terms 1-3 of eq. (8) vanish, so the energy is ``A4`` times
    :func:`projtrack.neuralnet.assignment_cost` and does not depend on the unit of D. A frame
    keeps its assignment unless another one is strictly cheaper (by more than ``1e-12``
    relative), so the run stops.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    initial : array_like of int, shape (N_T, N_P), ``N_T <= N_M``
        An admissible start (:func:`nearest_admissible`).
    max_rounds : int, default 50
        The paper's iteration limit.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
    rounds : int
        Rounds that changed the state (the confirming round is not counted), or ``max_rounds``.
    converged : bool
        Whether a round changed nothing within ``max_rounds``.
    """
    D = _check_D(D)
    A = np.array(as_array(initial, "initial"), dtype=np.intp)
    n_p = D.shape[0] + 2
    if A.ndim != 2 or A.shape[1] != n_p or A.shape[0] > D.shape[1]:
        raise ValueError(f"initial must have shape (N_T <= {D.shape[1]}, {n_p}), got {A.shape}")
    assignment_cost(A, D)  # validates the entries
    if any(len(set(A[:, a])) != A.shape[0] for a in range(n_p)):
        raise ValueError("initial must be admissible: distinct measurements within each frame")
    max_rounds = as_int(max_rounds, "max_rounds", minimum=1)
    rows = np.arange(A.shape[0])
    for r in range(max_rounds):
        changed = False
        for f in range(n_p):
            M = _frame_cost(D, A, f)
            _, best = linear_sum_assignment(M)
            now, new = M[rows, A[:, f]].sum(), M[rows, best].sum()
            if new < now - 1e-12 * max(1.0, abs(now)):
                A[:, f] = best
                changed = True
        if not changed:
            return A, r, True
    return A, max_rounds, False


def frame_rule_study(noise_levels: Sequence[float], n_runs: int, chunk: int, seed: int
                     ) -> dict[float, dict[str, np.ndarray]]:
    """:func:`frame_descent` on the data sets and starts of ``table1_study(noise_levels, n_runs, chunk, seed)``.

    Level ``i`` draws the same ``n_runs // chunk`` trials from ``numpy.random.default_rng(seed + i)``;
    every run starts from :func:`nearest_admissible` of the net's start.

    Returns
    -------
    dict
        Per level: ``correct`` (the true tracks), ``converged`` and ``rounds``, arrays of length
        ``n_runs``.
    """
    levels = [as_real(n, "noise level", 0.0) for n in noise_levels]
    n_runs = as_int(n_runs, "n_runs", minimum=1)
    chunk = as_int(chunk, "chunk", minimum=1)
    if n_runs % chunk:
        raise ValueError(f"n_runs = {n_runs} must be a multiple of chunk = {chunk}")
    seed = as_int(seed, "seed", minimum=0)
    out = {}
    for i, n in enumerate(levels):
        draws = montecarlo.run(draw_simulation, n_runs // chunk, np.random.default_rng(seed + i), chunk, 1, n)
        ok, conv, rounds = [], [], []
        for d in draws:
            for scene, D, X0 in zip(d.scenes, d.D, d.X0):
                A, r, c = frame_descent(D, nearest_admissible(X0))
                ok.append(c and is_correct_assignment(A, scene.labels))
                conv.append(c)
                rounds.append(r)
        out[n] = {"correct": np.array(ok), "converged": np.array(conv), "rounds": np.array(rounds)}
    return out


def update_order_study(noise_levels: Sequence[float], units: Sequence[float], n_runs: int, chunk: int,
                       seed: int) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """Serial against parallel neuron updates (eq. (9) as printed) on the same data sets and starts.

    Cell (unit ``j``, level ``i``) draws ``n_runs // chunk`` trials of ``chunk`` simulations from
    ``numpy.random.default_rng([seed, j, i])``; both orders run on these draws.

    Returns
    -------
    table : pandas.DataFrame
        Per unit and level: ``unit (px)``, ``noise %``, and for each order (``serial``,
        ``parallel``) the percentage of runs that converged and the mean number of ``sweeps``
        (a run that does not converge counting the limit of 50).
    tolerance : dict of str to Tolerance
        Shares of ``n_runs`` runs; means over ``n_runs`` runs of at most 50 sweeps each.
    """
    levels = [as_real(n, "noise level", 0.0) for n in noise_levels]
    units = [as_real(u, "unit", 0.0, low_open=True) for u in units]
    if not levels or not units:
        raise ValueError("noise_levels and units must not be empty")
    n_runs = as_int(n_runs, "n_runs", minimum=1)
    chunk = as_int(chunk, "chunk", minimum=1)
    if n_runs % chunk:
        raise ValueError(f"n_runs = {n_runs} must be a multiple of chunk = {chunk}")
    seed = as_int(seed, "seed", minimum=0)
    rows = []
    for j, u in enumerate(units):
        draws = {n: montecarlo.run(draw_simulation, n_runs // chunk, np.random.default_rng([seed, j, i]), chunk, 1,
                                   n, unit=u) for i, n in enumerate(levels)}
        flat = [d for n in levels for d in draws[n]]
        by_mode = {mode: iter(run_draws(flat, mode=mode)) for mode in ("serial", "parallel")}
        for n in levels:
            row = {"unit (px)": int(u) if float(u).is_integer() else u, "noise %": n}
            for mode, results in by_mode.items():
                res = [next(results) for _ in draws[n]]
                row[f"{mode} converged %"] = 100 * float(np.concatenate([r.converged for r in res]).mean())
                row[f"{mode} sweeps"] = float(np.concatenate([r.iterations for r in res]).mean())
            rows.append(row)
    runs = share(n_runs, percent=True)
    sweeps = mean_over(n_runs, 50.0, what="run")
    return pd.DataFrame(rows), {"noise %": EXACT, "serial converged %": runs, "parallel converged %": runs,
                                "serial sweeps": sweeps, "parallel sweeps": sweeps}


def frame_rule_table(frames: Mapping[float, Mapping[str, np.ndarray]], paper_k: Sequence[int]
                     ) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """The frame-by-frame rule per noise level, beside the paper's Table 1.

    Parameters
    ----------
    frames : mapping noise level -> dict of arrays
        :func:`frame_rule_study`.
    paper_k : sequence of int
        The paper's successes out of ten, one per level.

    Returns
    -------
    table : pandas.DataFrame
        ``noise %``, ``paper k/10``, ``correct %``, ``stopped wrong %`` (converged to a wrong
        assignment) and ``rounds`` (mean).
    tolerance : dict of str to Tolerance
        Shares of the runs of a level; the mean rounds move by one run changing its count by
        up to 50 rounds.
    """
    if not isinstance(frames, Mapping) or not frames:
        raise TypeError("frames must be a non-empty mapping of noise level -> arrays")
    paper_k = list(paper_k)
    if len(paper_k) != len(frames):
        raise ValueError(f"paper_k has {len(paper_k)} levels, frames {len(frames)}")
    rows = [{"noise %": n, "paper k/10": int(k), "correct %": 100 * float(np.mean(f["correct"])),
             "stopped wrong %": 100 * float(np.mean(np.asarray(f["converged"]) & ~np.asarray(f["correct"]))),
             "rounds": float(np.mean(f["rounds"]))} for (n, f), k in zip(frames.items(), paper_k)]
    n = min(len(f["correct"]) for f in frames.values())
    return pd.DataFrame(rows), {"noise %": EXACT, "rounds": mean_over(n, 50.0, what="run"),
                                "*": share(n, percent=True)}


# ----------------------------------------------------------------------------- figures


def plot_comparison(acc_noise, acc_size, styles: Mapping[str, str]):
    """Correct assignments of every method (a) against noise, four targets, and (b) against the
    number of targets, noise-free."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(6.4, 3.0), sharey=True)
    s0 = acc_size[acc_size["noise %"] == 0.0]
    for name, st in styles.items():
        axes[0].plot(acc_noise["noise %"], acc_noise[name], st, ms=4, label=name)
        axes[1].plot(s0["targets"], s0[name], st, ms=4)
    axes[0].set_xlabel("noise, %")
    axes[0].set_ylabel("correct, %")
    axes[0].set_title("(a) four targets")
    axes[1].set_xlabel("targets $N_T = N_M$")
    axes[1].set_title("(b) noise-free")
    fig.legend(*axes[0].get_legend_handles_labels(), frameon=False, loc="lower center", ncol=3,
               bbox_to_anchor=(0.5, -0.12))
    fig.tight_layout()
    return fig


def plot_timing(timing, styles: Sequence[str]):
    """Time per data set (ms, log scale) of every method against the number of targets."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.0))
    for col, st in zip(timing.columns, styles):
        ax.semilogy(timing.index, timing[col], st, ms=4, label=col)
    ax.set_xlabel("targets $N_T = N_M$")
    ax.set_ylabel("time per data set, ms")
    ax.legend(frameon=False, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    return fig


# ----------------------------------------------------------------------------- computation


def _triples_per_frame(n_frames: int) -> np.ndarray:
    """How many of the triples (a, a+1, a+2) of eq. (7) contain each frame."""
    q = np.arange(n_frames - 2)
    return np.array([int(np.sum((q <= a) & (a <= q + 2))) for a in range(n_frames)])


def operation_counts(n_targets: int, n_frames: int = 5, net_sweeps: float = 19.0,
                     descent_rounds: float = 3.0) -> dict[str, float]:
    """Arithmetic operations (additions and multiplications) of each solver on one data set, ``N_M = N_T``.

    A machine-independent measure of computation, counted from the algorithms as written:

    * **net, one sweep**: every neuron evaluates eq. (9) once: ``N_T + N_M + N_T N_M`` terms of
      the sums of terms 1-3, and ``N_M^2`` products of term 4 for each triple of frames that
      contains its frame;
    * **net, one run**: ``net_sweeps`` sweeps (default the paper's 19 iterations without noise);
    * **exact optimum**: the dynamic programme of :func:`projtrack.neuralnet.optimal_assignment`,
      ``N_T`` additions for each of the ``(N_T!)^3`` permutation triples of each of the
      ``N_P - 2`` frame triples;
    * **coordinate descent, one round**: per frame, the ``N_T N_M`` entries of its cost matrix
      (one addition per triple containing the frame) and ``N_T^3`` for the linear assignment;
    * **coordinate descent, one run**: ``descent_rounds`` rounds.

    Parameters
    ----------
    n_targets : int
        ``N_T = N_M``.
    n_frames : int, default 5
        ``N_P``.
    net_sweeps, descent_rounds : float
        Sweeps of a net run and rounds of a descent run.

    Returns
    -------
    dict
        ``targets`` and the five counts above (floats: the exact optimum exceeds 64-bit integers
        from ``N_T = 10``).
    """
    import math

    n = as_int(n_targets, "n_targets", minimum=1)
    n_p = as_int(n_frames, "n_frames", minimum=3)
    sweeps = as_real(net_sweeps, "net_sweeps", 0.0)
    rounds = as_real(descent_rounds, "descent_rounds", 0.0)
    tri = _triples_per_frame(n_p)
    sweep = int(sum(n * n * (n + n + n * n + k * n * n) for k in tri))
    dp = (n_p - 2) * math.factorial(n) ** 3 * n
    rnd = int(sum(n * n * k + n ** 3 for k in tri))
    return {"targets": n, "net, one sweep": float(sweep), "net, one run": sweeps * sweep, "exact optimum": float(dp),
            "coordinate descent, one round": float(rnd), "coordinate descent, one run": rounds * rnd}


def optimum_net_ratios(n_targets: int, n_frames: int = 5, net_sweeps: float = 19.0) -> dict[str, float]:
    """Operations of the exact optimum over one net run, under three counting conventions.

    * **book**: :func:`operation_counts` (one operation per term);
    * **lowest**: term 4 of eq. (9) counted as two multiplications and an addition per
      ``D X X`` product (the net dearer), and the dynamic programme with frame 1 fixed (target
      labels are arbitrary: ``N_T!^2`` triples for the first frame triple);
    * **highest**: the book's net, and the dynamic programme charged ``N_T + 2`` operations per
      permutation triple (the additions plus a comparison and a store).

    Returns
    -------
    dict
        ``targets``, ``book``, ``lowest``, ``highest`` (ratios optimum / net run).
    """
    import math

    n = as_int(n_targets, "n_targets", minimum=1)
    n_p = as_int(n_frames, "n_frames", minimum=3)
    sweeps = as_real(net_sweeps, "net_sweeps", 0.0)
    tri = _triples_per_frame(n_p)
    f = math.factorial(n)
    net = sweeps * sum(n * n * (2 * n + n * n + k * n * n) for k in tri)
    net_dear = sweeps * sum(n * n * (2 * n + n * n + 3 * k * n * n) for k in tri)
    dp, dp_dear = (n_p - 2) * f ** 3 * n, (n_p - 2) * f ** 3 * (n + 2)
    dp_fixed = (f ** 2 + (n_p - 3) * f ** 3) * n
    return {"targets": n, "book": float(dp / net), "lowest": float(dp_fixed / net_dear), "highest": float(dp_dear / net)}


def descent_rounds(n_targets: int, noise_percent: float, n_datasets: int, seed: int) -> np.ndarray:
    """Rounds of block-coordinate descent from the greedy start, the confirming round included.

    :func:`frame_descent` from :func:`projtrack.neuralnet.greedy_assignment` (the start of
    :func:`projtrack.neuralnet.coordinate_descent_assignment`) on ``n_datasets`` data sets of
    :func:`projtrack.experiments.neuralnet.draw_simulation` drawn from
    ``numpy.random.default_rng(seed)``.

    Parameters
    ----------
    n_targets : int
    noise_percent : float
    n_datasets : int
    seed : int

    Returns
    -------
    ndarray of int, shape (n_datasets,)
    """
    from projtrack.neuralnet import greedy_assignment

    n_targets = as_int(n_targets, "n_targets", minimum=2)
    n_datasets = as_int(n_datasets, "n_datasets", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    draws = montecarlo.run(draw_simulation, n_datasets, np.random.default_rng(seed), 1, 1, noise_percent,
                           n_targets=n_targets)
    return np.array([frame_descent(d.D[0], greedy_assignment(d.D[0]))[1] + 1 for d in draws])

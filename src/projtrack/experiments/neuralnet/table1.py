"""The Sec. VI experiment of Barnard & Casasent: random track sets, many net starts, scored.

:func:`simulate` draws data sets with :func:`projtrack.scenes.tracks3d.make_tracks`, runs
the nets of :mod:`projtrack.neuralnet` from random starts and scores each run against the
true tracks, optionally with the reference solvers on the same data sets.

The serial update visits the neurons one at a time in Python, so a net costs about the
same whether it runs alone or in a batch of hundreds. :func:`simulate_trials` therefore
draws the data sets and starts of many Monte Carlo trials (through
:func:`projtrack.montecarlo.run`, one generator per trial), runs all their nets as one
batch of :func:`projtrack.neuralnet.run_net` (:func:`run_draws`) and scores every trial.
The nets of a batch do not interact, so the result is that of
``montecarlo.run(simulate, ...)``; the unit tests and the chapter's notebook outputs check
that it is identical, not merely close.

How a run ends (:data:`MODES`, :func:`run_modes`): converged to the correct or to a wrong
assignment, a 2-cycle between the correct state and one a single pairing away
(:func:`one_pairing_away`, the failure the paper describes: "it oscillated between two states,
one being the correct solution and the other differing in one target/measurement pairing"),
another cycle, or wandering. :func:`draws_modes` labels the runs of several draws at once and
:func:`mode_counts` counts them. :func:`plot_table1` and :func:`plot_fig5` draw the chapter's
Table 1 and Fig. 5.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng
from projtrack.neuralnet import (PAPER_OFFSET, Coefficients, NetResult, assignment_cost,
                                 coordinate_descent_assignment, distance_tensor, greedy_assignment, initial_states,
                                 is_correct_assignment, nearest_neighbour_assignment, optimal_assignment, run_net,
                                 states_to_assignment)
from projtrack.scenes.tracks3d import TrackScene, make_tracks

__all__ = ["SimulationDraw", "simulate", "draw_simulation", "score_simulation", "run_draws", "simulate_trials",
           "MODES", "FAILURE_MODES", "one_pairing_away", "run_modes", "draws_modes", "mode_counts", "plot_table1",
           "plot_fig5"]


@dataclass(frozen=True)
class SimulationDraw:
    """The random part of one :func:`simulate` call: data sets and net starts.

    Attributes
    ----------
    scenes : list of TrackScene
        The ``n_datasets`` data sets.
    positions : ndarray, shape (n_datasets, N_P, N_T, 3)
        Their measurements divided by ``unit``.
    D : ndarray, shape (n_datasets, N_P - 2, N_T, N_T, N_T)
        Distance tensors, eq. (7).
    X0 : ndarray, shape (n_datasets * n_starts, N_T, N_T, N_P)
        Start states, data set major.
    n_starts : int
        Starts per data set.
    """

    scenes: list[TrackScene]
    positions: np.ndarray
    D: np.ndarray
    X0: np.ndarray
    n_starts: int


def draw_simulation(rng: np.random.Generator, n_datasets: int, n_starts: int, noise_percent: float, *,
                    noise_law: str = "ball", n_targets: int = 4, n_frames: int = 5, unit: float = 256.0,
                    perturbation: float = 0.1) -> SimulationDraw:
    """Draw the data sets and start states of :func:`simulate` (same arguments, same order of draws)."""
    rng = as_rng(rng)
    n_datasets = as_int(n_datasets, "n_datasets", 1)
    n_starts = as_int(n_starts, "n_starts", 1)
    unit = as_real(unit, "unit", 0.0, low_open=True)
    noise_percent = as_real(noise_percent, "noise_percent", 0.0)
    scenes = [make_tracks(rng, n_targets, n_frames, noise_percent=noise_percent, noise_law=noise_law)
              for _ in range(n_datasets)]
    pos = np.stack([s.positions for s in scenes]) / unit
    D = distance_tensor(pos)
    X0 = initial_states(rng, n_datasets * n_starts, n_targets, n_targets, n_frames, perturbation)
    return SimulationDraw(scenes, pos, D, X0, n_starts)


def score_simulation(draw: SimulationDraw, res: NetResult, *, references: bool = True,
                     exact_max_targets: int = 4) -> dict[str, np.ndarray]:
    """Score the nets ``res`` run on ``draw`` (and, with ``references``, the reference solvers).

    Returns the dictionary of :func:`simulate`.
    """
    if not isinstance(draw, SimulationDraw):
        raise TypeError(f"draw must be a SimulationDraw, got {type(draw).__name__}")
    if not isinstance(res, NetResult):
        raise TypeError(f"res must be a NetResult, got {type(res).__name__}")
    if res.states.shape != draw.X0.shape:
        raise ValueError(f"res holds states of shape {res.states.shape}, the draw {draw.X0.shape}")
    scenes, D, pos, n_starts = draw.scenes, draw.D, draw.positions, draw.n_starts
    n_datasets, n_targets = len(scenes), draw.X0.shape[1]
    dataset = np.repeat(np.arange(n_datasets), n_starts)
    correct = np.array([res.status[k] == "converged" and
                        is_correct_assignment(states_to_assignment(res.states[k]), scenes[dataset[k]].labels)
                        for k in range(len(dataset))])
    out: dict[str, np.ndarray] = {
        "dataset": dataset, "status": res.status, "iterations": res.iterations,
        "converged": res.converged, "correct": correct,
    }
    if references:
        opt_ok, opt_cost, true_cost, nn_ok, gr_ok, cd_ok = [], [], [], [], [], []
        for s, d, r in zip(scenes, D, pos):
            truth = np.argsort(s.labels, axis=1).T  # measurement of target i in frame a
            true_cost.append(assignment_cost(truth, d))
            if n_targets <= exact_max_targets:
                A, c = optimal_assignment(d)
                opt_ok.append(is_correct_assignment(A, s.labels))
                opt_cost.append(c)
            else:
                opt_ok.append(np.nan)
                opt_cost.append(np.nan)
            nn_ok.append(is_correct_assignment(nearest_neighbour_assignment(r), s.labels))
            gr_ok.append(is_correct_assignment(greedy_assignment(d), s.labels))
            cd_ok.append(is_correct_assignment(coordinate_descent_assignment(d)[0], s.labels))
        out.update(optimal_correct=np.array(opt_ok, dtype=float), optimal_cost=np.array(opt_cost),
                   true_cost=np.array(true_cost), nn_correct=np.array(nn_ok),
                   greedy_correct=np.array(gr_ok), cd_correct=np.array(cd_ok))
    return out


def simulate(rng: np.random.Generator, n_datasets: int, n_starts: int, noise_percent: float, *,
             noise_law: str = "ball", n_targets: int = 4, n_frames: int = 5, unit: float = 256.0,
             coefficients: Coefficients | Sequence[float] | None = None, offset: float = PAPER_OFFSET,
             max_iter: int = 50, mode: str = "serial", self_coupling: bool = True, exact_energy: bool = False,
             perturbation: float = 0.1, references: bool = True,
             exact_max_targets: int = 4) -> dict[str, np.ndarray]:
    """The Sec. VI experiment: ``n_datasets`` track sets, ``n_starts`` net starts each.

    Data sets come from :func:`projtrack.scenes.tracks3d.make_tracks` (``N_M = N_T``);
    positions are divided by ``unit`` before eq. (7) (the paper does not say in which
    unit D was computed; ``unit = 256`` measures positions in field widths). Every net
    starts from :func:`projtrack.neuralnet.initial_states` and runs
    :func:`projtrack.neuralnet.run_net`. All nets are run as one vectorized batch.

    Parameters
    ----------
    rng : numpy.random.Generator
    n_datasets, n_starts : int
        Number of track sets and of random net starts per set (>= 1).
    noise_percent : float
        Position noise ``n >= 0`` (% of the distance from the centre), see
        :func:`projtrack.scenes.tracks3d.perturb`.
    noise_law : {"ball", "radial", "coordinate"}, default "ball"
        How the noise is drawn, see :func:`projtrack.scenes.tracks3d.perturb`.
    n_targets, n_frames, unit, coefficients, offset, max_iter, mode, self_coupling, exact_energy, perturbation
        As in :func:`projtrack.scenes.tracks3d.make_tracks`,
        :func:`projtrack.neuralnet.initial_states` and :func:`projtrack.neuralnet.run_net`.
    references : bool
        Also solve every data set with the reference methods.
    exact_max_targets : int
        Largest ``N_T`` for which the exact optimum is computed.

    Returns
    -------
    dict of arrays
        Per run (length ``n_datasets * n_starts``, data set major): ``dataset``, ``status``,
        ``iterations``, ``converged``, ``correct`` (converged and correct assignment,
        the paper's success). Per data set (length ``n_datasets``), when ``references``:
        ``optimal_correct``, ``optimal_cost``, ``true_cost``, ``nn_correct``
        (:func:`projtrack.neuralnet.nearest_neighbour_assignment`), ``greedy_correct``, ``cd_correct``
        (:func:`projtrack.neuralnet.coordinate_descent_assignment`); the exact optimum only for
        ``N_T <= exact_max_targets`` (NaN otherwise; it costs about 0.5 s per data set at
        ``N_T = 5``).
    """
    draw = draw_simulation(rng, n_datasets, n_starts, noise_percent, noise_law=noise_law, n_targets=n_targets,
                           n_frames=n_frames, unit=unit, perturbation=perturbation)
    res = run_net(np.repeat(draw.D, draw.n_starts, axis=0), draw.X0, coefficients, offset=offset,
                  max_iter=max_iter, mode=mode, self_coupling=self_coupling, exact_energy=exact_energy)
    return score_simulation(draw, res, references=references, exact_max_targets=exact_max_targets)


def run_draws(draws: Sequence[SimulationDraw], coefficients: Coefficients | Sequence[float] | None = None, *,
              offset: float = PAPER_OFFSET, max_iter: int = 50, mode: str = "serial", self_coupling: bool = True,
              exact_energy: bool = False) -> list[NetResult]:
    """Run the nets of several draws as ONE batch of :func:`projtrack.neuralnet.run_net`.

    The nets of a batch do not interact, so net ``k`` of draw ``j`` ends exactly as if its
    draw were run alone (a net that neither converges nor cycles runs ``max_iter`` sweeps
    either way, and a converged net stays put). The draws must share ``N_T`` and ``N_P``.

    Returns
    -------
    list of NetResult
        One per draw, in order (without history).
    """
    draws = list(draws)
    if not draws or not all(isinstance(d, SimulationDraw) for d in draws):
        raise TypeError("draws must be a non-empty sequence of SimulationDraw")
    shapes = {d.X0.shape[1:] for d in draws}
    if len(shapes) > 1:
        raise ValueError(f"the draws must share N_T, N_M and N_P, got {sorted(shapes)}")
    D = np.concatenate([np.repeat(d.D, d.n_starts, axis=0) for d in draws])
    X0 = np.concatenate([d.X0 for d in draws])
    res = run_net(D, X0, coefficients, offset=offset, max_iter=max_iter, mode=mode,
                  self_coupling=self_coupling, exact_energy=exact_energy)
    out, k = [], 0
    for d in draws:
        sl = slice(k, k + len(d.X0))
        out.append(NetResult(res.states[sl], res.status[sl], res.iterations[sl], res.period[sl]))
        k = sl.stop
    return out


def simulate_trials(n_trials: int, rng: np.random.Generator, n_datasets: int, n_starts: int,
                    noise_percent: float, *, noise_law: str = "ball", n_targets: int = 4, n_frames: int = 5,
                    unit: float = 256.0, perturbation: float = 0.1, references: bool = True,
                    exact_max_targets: int = 4, n_jobs: int | None = None, **net_options: Any
                    ) -> list[dict[str, np.ndarray]]:
    """``montecarlo.run(simulate, n_trials, rng, ...)`` with the nets of all trials in one batch.

    Trial ``i`` draws from the ``i``-th generator spawned from ``rng`` (as
    :func:`projtrack.montecarlo.run` does), so the results equal those of
    ``montecarlo.run(simulate, n_trials, rng, n_datasets, n_starts, noise_percent, ...)``;
    only the nets run together (:func:`run_draws`). ``net_options`` (``coefficients``,
    ``offset``, ``max_iter``, ``mode``, ``self_coupling``, ``exact_energy``) go to
    :func:`projtrack.neuralnet.run_net`; ``n_jobs`` to the drawing and scoring.

    Returns
    -------
    list of dict
        One :func:`simulate` result per trial.
    """
    draws = montecarlo.run(draw_simulation, n_trials, rng, n_datasets, n_starts, noise_percent,
                           noise_law=noise_law, n_targets=n_targets, n_frames=n_frames, unit=unit,
                           perturbation=perturbation, n_jobs=n_jobs)
    if not draws:
        return []
    results = run_draws(draws, **net_options)
    return [score_simulation(d, r, references=references, exact_max_targets=exact_max_targets)
            for d, r in zip(draws, results)]


# ----------------------------------------------------------------------------- how a run ends


#: How a run ends: converged to the correct or to a wrong state; a 2-cycle between the correct
#: state and one a single pairing away (the paper's oscillation); any other cycle; wandering
#: (neither converged nor cycling within the sweep limit).
MODES: tuple[str, ...] = ("correct", "wrong", "cycle with the truth", "other cycle", "wandering")


#: The modes of a failed run.
FAILURE_MODES: tuple[str, ...] = MODES[1:]


def one_pairing_away(X: np.ndarray, truth: np.ndarray) -> bool:
    """Whether ``X`` differs from ``truth`` in the pairings of one target in one frame only.

    The two states must differ, and only within one row ``X[i, :, a]``: one pairing added,
    removed or moved to another measurement. (A swap of two targets' measurements changes two
    rows and is two pairings.)

    Parameters
    ----------
    X, truth : array_like of 0/1, shape (N_T, N_M, N_P)
    """
    X, truth = np.asarray(X), np.asarray(truth)
    if X.shape != truth.shape or X.ndim != 3:
        raise ValueError(f"X and truth must be states of one shape (N_T, N_M, N_P), got {X.shape} and {truth.shape}")
    rows = np.any(X != truth, axis=1)  # (N_T, N_P)
    return int(rows.sum()) == 1


def run_modes(D: np.ndarray, res: NetResult, labels: Sequence[np.ndarray], **net_options: Any) -> np.ndarray:
    """The :data:`MODES` label of every run of a batch.

    Parameters
    ----------
    D : ndarray, shape (B, N_P - 2, N_M, N_M, N_M)
        The distance tensor of each run (as given to :func:`projtrack.neuralnet.run_net`).
    res : NetResult
        The batch's result.
    labels : sequence of B arrays of int, shape (N_P, N_M)
        ``labels[k][a, alpha]``: the target of measurement ``alpha`` of frame ``a`` in run ``k``'s
        data set. The net's targets are interchangeable: a state is correct when every target
        follows one true track (:func:`projtrack.neuralnet.is_correct_assignment`).
    **net_options
        The options the nets ran with (``coefficients``, ``offset``, ``mode``, ``self_coupling``,
        ``exact_energy``): a run that ends in a 2-cycle is swept once more with them, which gives
        the other state of the cycle.

    Returns
    -------
    ndarray of str, shape (B,)
    """
    if not isinstance(res, NetResult):
        raise TypeError(f"res must be a NetResult, got {type(res).__name__}")
    D = np.asarray(D, dtype=float)
    B = len(res.status)
    if D.ndim != 5 or D.shape[0] != B:
        raise ValueError(f"D must hold one tensor per run, shape ({B}, N_P - 2, N_M, N_M, N_M), got {D.shape}")
    labels = list(labels)
    if len(labels) != B:
        raise ValueError(f"labels must hold one array per run ({B}), got {len(labels)}")
    out = np.full(B, "wandering", dtype=object)
    for k in range(B):
        if res.status[k] == "converged":
            out[k] = "correct" if _is_correct(res.states[k], labels[k]) else "wrong"
        elif res.status[k] == "oscillating":
            out[k] = "other cycle"
    two = np.flatnonzero((res.status == "oscillating") & (res.period == 2))
    if two.size:
        partner = run_net(D[two], res.states[two].astype(float), max_iter=1, **net_options).states
        for j, k in enumerate(two):
            a, b = res.states[k], partner[j]
            if (_is_correct(a, labels[k]) and one_pairing_away(b, a)
                    or _is_correct(b, labels[k]) and one_pairing_away(a, b)):
                out[k] = "cycle with the truth"
    return out.astype(str)


def _is_correct(X: np.ndarray, labels: np.ndarray) -> bool:
    """Whether binary states are the correct assignment (targets are interchangeable)."""
    return is_correct_assignment(states_to_assignment(X), np.asarray(labels))


def draws_modes(draws: Sequence[Any], results: Sequence[NetResult], **net_options: Any) -> list[np.ndarray]:
    """:func:`run_modes` for the nets of several simulation draws, as one batch.

    Parameters
    ----------
    draws : sequence of SimulationDraw
        As from :func:`projtrack.experiments.neuralnet.draw_simulation`.
    results : sequence of NetResult
        One per draw (:func:`projtrack.experiments.neuralnet.run_draws`).
    **net_options
        The options the nets ran with.

    Returns
    -------
    list of ndarray of str
        The modes of each draw's runs.
    """
    draws, results = list(draws), list(results)
    if len(draws) != len(results) or not draws:
        raise ValueError(f"draws and results must be non-empty and of one length, got {len(draws)}, {len(results)}")
    D = np.concatenate([np.repeat(d.D, d.n_starts, axis=0) for d in draws])
    labels = [d.scenes[k // d.n_starts].labels for d in draws for k in range(len(d.X0))]
    res = NetResult(np.concatenate([r.states for r in results]), np.concatenate([r.status for r in results]),
                    np.concatenate([r.iterations for r in results]), np.concatenate([r.period for r in results]))
    modes = run_modes(D, res, labels, **net_options)
    out, k = [], 0
    for r in results:
        out.append(modes[k:k + len(r.status)])
        k += len(r.status)
    return out


def mode_counts(modes: np.ndarray) -> dict[str, int]:
    """How many runs end in each of :data:`MODES`."""
    modes = np.asarray(modes)
    unknown = set(np.unique(modes)) - set(MODES)
    if unknown:
        raise ValueError(f"modes holds labels that are not in MODES: {sorted(unknown)}")
    return {m: int((modes == m).sum()) for m in MODES}


# ----------------------------------------------------------------------------- figures


def plot_table1(noise: Sequence[float], paper: Sequence[float], ours: Sequence[float], ours_ci: np.ndarray,
                bound: Sequence[float], best: Sequence[float], frames: Sequence[float]):
    """Table 1 against noise: the paper, the net as read (with 95% intervals), the best reading at
    each level, the fixed-point bound of the net as read and the frame-by-frame rule (all in %)."""
    import matplotlib.pyplot as plt

    noise = np.asarray(noise, dtype=float)
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    ax.plot(noise, best, "-", color="0.6", lw=4, alpha=0.6, label="best of all readings, per level")
    ax.plot(noise, bound, "k--", lw=1.1, label="bound: truth is a fixed point")
    ci = np.asarray(ours_ci, dtype=float)
    ours = np.asarray(ours, dtype=float)
    ax.errorbar(noise, ours, yerr=[ours - ci[0], ci[1] - ours], fmt="o", color="C0", ms=6, capsize=3,
                label="the net as read (400 runs per level)")
    ax.plot(noise, frames, "s-", color="C2", ms=5, mfc="none", label="frame-by-frame rule")
    ax.plot(noise, paper, "*", color="C3", ms=13, label="paper, Table 1 (10 runs)")
    ax.set_xlabel("noise $n$ (% of the distance from the centre)")
    ax.set_ylabel("correct runs, %")
    ax.set_xticks(noise)
    ax.set_ylim(-4, 104)
    ax.legend(frameon=False, loc="center right", bbox_to_anchor=(1.0, 0.45))
    fig.tight_layout()
    return fig


def plot_fig5(history: np.ndarray, order: np.ndarray, shown: Sequence[int]):
    """Fig. 5: the states after the sweeps ``shown`` (rows). Each row is one panel holding the
    frames' 4 x 4 matrices side by side (columns: targets; rows: measurements, sorted by ``order``
    so that the correct answer is the same permutation in every frame)."""
    import matplotlib.pyplot as plt

    n_p = history.shape[-1]
    n_t, n_m = history.shape[1], history.shape[2]
    width = n_p * n_t + (n_p - 1)
    fig, axes = plt.subplots(len(shown), 1, figsize=(4.6, 0.95 * len(shown) + 0.4))
    for ax, it in zip(np.atleast_1d(axes), shown):
        img = np.full((n_m, width), np.nan)
        for a in range(n_p):
            img[:, a * (n_t + 1): a * (n_t + 1) + n_t] = history[it][:, order[a], a].T
        ax.imshow(np.ma.masked_invalid(img), cmap="Greys", vmin=0, vmax=1)
        for a in range(n_p):
            ax.add_patch(plt.Rectangle((a * (n_t + 1) - 0.5, -0.5), n_t, n_m, fill=False, lw=0.8, ec="0.4"))
        ax.set_yticks([])
        ax.set_ylabel(f"sweep {it}", fontsize=9, rotation=0, ha="right", va="center")
        ax.set_xticks([a * (n_t + 1) + (n_t - 1) / 2 for a in range(n_p)])
        ax.set_xticklabels([f"frame {a + 1}" for a in range(n_p)] if ax is np.atleast_1d(axes)[0] else [],
                           fontsize=9)
        ax.xaxis.set_ticks_position("top")
        ax.tick_params(length=0)
        for sp in ax.spines.values():
            sp.set_visible(False)
    fig.tight_layout()
    return fig

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

__all__ = ["SimulationDraw", "simulate", "draw_simulation", "score_simulation", "run_draws", "simulate_trials"]


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

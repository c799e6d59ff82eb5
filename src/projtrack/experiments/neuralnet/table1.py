"""The Sec. VI experiment of Barnard & Casasent: random track sets, many net starts, scored.

:func:`simulate` draws data sets with :func:`projtrack.scenes.tracks3d.make_tracks`, runs
the nets of :mod:`projtrack.neuralnet` from random starts and scores each run against the
true tracks, optionally with the reference solvers on the same data sets.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack._validation import as_int, as_real, as_rng
from projtrack.neuralnet import (PAPER_OFFSET, Coefficients, assignment_cost, coordinate_descent_assignment,
                                 distance_tensor, greedy_assignment, initial_states, is_correct_assignment,
                                 nearest_neighbour_assignment, optimal_assignment, run_net,
                                 states_to_assignment)
from projtrack.scenes.tracks3d import make_tracks

__all__ = ["simulate"]


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
    res = run_net(np.repeat(D, n_starts, axis=0), X0, coefficients, offset=offset, max_iter=max_iter,
                  mode=mode, self_coupling=self_coupling, exact_energy=exact_energy)
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

"""Update rules beside the paper's: parallel sweeps, and whole frames updated at once.

Sec. VI updates the neurons serially ("the state of neuron one was updated before calculating
the state of neuron two, etc.") and says this "results in faster convergence than if all new
neuron states are calculated in parallel and simultaneously fed back, as is usually done".
:func:`update_order_study` runs both orders on the same data sets and starts.

The fixed-point bound of the chapter shows that a neuron-by-neuron rule of eq. (4) cannot keep
a noisy correct assignment, whatever the start. The nearest rule that keeps the paper's energy,
its binary neurons and its serial sweeps, and does find noisy tracks, updates the neurons of
one *frame* together: with the other frames fixed, terms 1-3 of eq. (8) vanish on every
admissible state of the frame and term 4 is linear in it, so the frame's state of least energy
is a linear assignment (:func:`frame_descent`). Every state stays admissible, the energy falls
at every change, and the run stops at a state no single frame can improve.

* :func:`nearest_admissible`: the admissible state closest to an analog start (per frame, the
  assignment of largest summed start value);
* :func:`frame_descent`: serial frame-by-frame descent of eq. (8) from an admissible state;
* :func:`frame_rule_study`: that rule on the data sets and starts of
  :func:`projtrack.experiments.neuralnet.table1_study`;
* :func:`update_order_study`: serial against parallel neuron updates on the same draws.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real
from projtrack.neuralnet import assignment_cost, is_correct_assignment
from projtrack.neuralnet._checks import _check_D

from .table1 import draw_simulation, run_draws, score_simulation

__all__ = ["nearest_admissible", "frame_descent", "frame_rule_study", "update_order_study"]


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


def _frame_cost(D: np.ndarray, A: np.ndarray, f: int) -> np.ndarray:
    """Cost of every (target, measurement) choice in frame ``f`` with the other frames fixed."""
    n_t, n_p = A.shape
    M = np.zeros((n_t, D.shape[1]))
    if f + 2 < n_p:
        M += D[f][:, A[:, f + 1], A[:, f + 2]].T
    if 1 <= f <= n_p - 2:
        M += D[f - 1][A[:, f - 1], :, A[:, f + 1]]
    if f >= 2:
        M += D[f - 2][A[:, f - 2], A[:, f - 1], :]
    return M


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
                       seed: int) -> list[dict[str, float]]:
    """Serial against parallel neuron updates (eq. (9) as printed) on the same data sets and starts.

    Cell (unit ``j``, level ``i``) draws ``n_runs // chunk`` trials of ``chunk`` simulations from
    ``numpy.random.default_rng([seed, j, i])``; both orders run on these draws.

    Returns
    -------
    list of dict
        Per unit, level and order: ``unit (px)``, ``noise %``, ``update``, ``converged %``,
        ``correct %`` and ``sweeps`` (the mean number of sweeps, a run that does not converge
        counting the limit of 50).
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
        for mode in ("serial", "parallel"):
            results = iter(run_draws(flat, mode=mode))
            for n in levels:
                conv, ok, sweeps = [], [], []
                for d in draws[n]:
                    r = next(results)
                    conv.append(r.converged)
                    sweeps.append(r.iterations)
                    ok.append(score_simulation(d, r, references=False)["correct"])
                conv, ok, sweeps = np.concatenate(conv), np.concatenate(ok), np.concatenate(sweeps)
                rows.append({"unit (px)": u, "noise %": n, "update": mode, "converged %": 100 * float(conv.mean()),
                             "correct %": 100 * float(ok.mean()), "sweeps": float(sweeps.mean())})
    return rows

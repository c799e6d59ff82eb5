"""Reference solvers of the same assignment problem: exact optimum, nearest neighbour, greedy, coordinate descent."""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import linear_sum_assignment

from projtrack._validation import as_int

from ._checks import _check_square
from .assignments import _permutation_triples, assignment_cost

__all__ = ["optimal_assignment", "nearest_neighbour_assignment", "greedy_assignment",
           "coordinate_descent_assignment"]


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


def optimal_assignment(D: np.ndarray, n_targets: int | None = None, max_states: int = 20_000_000
                       ) -> tuple[np.ndarray, float]:
    """Exact minimum of the summed equation (7) cost over one-to-one assignments
    (:math:`N_T = N_M`).

    Dynamic programming (Viterbi) over pairs of consecutive frame permutations: the cost
    ``sum_i sum_a D^a(pi_a(i), pi_{a+1}(i), pi_{a+2}(i))`` couples only three consecutive
    frames. Frame 0 is labelled by the identity (targets are interchangeable). Work is
    ``N_P (N_T!)^3``: fine up to ``N_T = 5``.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
        The distance tensor of eq. (7) (:func:`distance_tensor`).
    n_targets : int, optional
        ``N_T``; default ``N_M`` (it must equal ``N_M``).
    max_states : int, default 20000000
        Refuse problems whose dynamic programme would exceed this many states.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
    cost : float
    """
    D, n = _check_square(D, n_targets)
    P = math.factorial(n)
    if P ** 3 > max_states:
        raise ValueError(f"N_T = {n} is too large for the exact search ({P}^3 states per frame)")
    perms, flat = _permutation_triples(n)
    n_q = D.shape[0]
    # cost[a, p0, p1, p2]: summed D of frames (a, a+1, a+2) under permutations p0, p1, p2
    cost = D.reshape(n_q, -1)[:, flat].sum(axis=-1)
    # V[p1, p2]: best cost with frame 0 = identity, frame a+1 = perms[p1], frame a+2 = perms[p2]
    V = cost[0, 0]  # perms[0] is the identity
    back = []
    for a in range(1, n_q):
        tot = V[:, :, None] + cost[a]
        arg = np.argmin(tot, axis=0)   # over p0 -> (p1, p2)
        back.append(arg)
        V = np.take_along_axis(tot, arg[None], axis=0)[0]
    p1, p2 = np.unravel_index(np.argmin(V), V.shape)
    best = float(V[p1, p2])
    seq = [p2, p1]
    for arg in reversed(back):
        p0 = arg[seq[-1], seq[-2]]
        seq.append(p0)
    seq = seq[::-1]  # perms for frames 1..N_P-1
    A = np.empty((n, n_q + 2), dtype=np.intp)
    A[:, 0] = np.arange(n)
    for f, p in enumerate(seq, start=1):
        A[:, f] = perms[p]
    return A, best


def nearest_neighbour_assignment(positions: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    """Frame-to-frame :func:`scipy.optimize.linear_sum_assignment` on Euclidean distance.

    Targets are the measurements of frame 0; each next frame is matched one-to-one to the
    previous one by minimum summed distance (no motion model).

    Parameters
    ----------
    positions : array_like, shape (N_P, N_M, dim), ``N_M = N_T``
        The measurements of every frame.
    n_targets : int, optional
        ``N_T``; default ``N_M``.

    Returns
    -------
    ndarray of int, shape (N_T, N_P)
    """
    r = np.asarray(positions, dtype=float)
    if r.ndim != 3 or r.shape[0] < 2:
        raise ValueError(f"positions must have shape (N_P >= 2, N_M, dim), got {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ValueError("positions must be finite")
    n = r.shape[1] if n_targets is None else as_int(n_targets, "n_targets", 1)
    if n != r.shape[1]:
        raise ValueError(f"the reference assignments need N_T == N_M, got {n} and {r.shape[1]}")
    A = np.empty((n, r.shape[0]), dtype=np.intp)
    A[:, 0] = np.arange(n)
    for a in range(1, r.shape[0]):
        prev = r[a - 1][A[:, a - 1]]
        cost = np.linalg.norm(prev[:, None, :] - r[a][None, :, :], axis=-1)
        _, cols = linear_sum_assignment(cost)
        A[:, a] = cols
    return A


def greedy_assignment(D: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    """Frame-by-frame linear assignment on the equation (7) cost.

    Frame 0 is the identity; frame 1 is matched by ``min_gamma D^0_{alpha beta gamma}``
    (the best continuation of each pair); every later frame ``a + 2`` is matched to the
    tracks fixed so far by ``D^a(track(a), track(a+1), gamma)``, each by
    :func:`scipy.optimize.linear_sum_assignment`.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
        The distance tensor of eq. (7).
    n_targets : int, optional
        ``N_T``; default ``N_M``.

    Returns
    -------
    ndarray of int, shape (N_T, N_P)
    """
    D, n = _check_square(D, n_targets)
    n_p = D.shape[0] + 2
    A = np.empty((n, n_p), dtype=np.intp)
    A[:, 0] = np.arange(n)
    _, A[:, 1] = linear_sum_assignment(D[0].min(axis=2))
    for a in range(n_p - 2):
        _, A[:, a + 2] = linear_sum_assignment(D[a][A[:, a], A[:, a + 1], :])
    return A


def coordinate_descent_assignment(D: np.ndarray, initial: np.ndarray | None = None,
                                  n_targets: int | None = None, max_rounds: int = 100) -> tuple[np.ndarray, float]:
    """Block-coordinate descent on the summed equation (7) cost (a linear-assignment
    heuristic).

    With all frames but ``a`` fixed, the cost is linear in frame ``a``'s assignment
    (the three triples containing ``a``), so each frame is re-solved exactly by
    :func:`scipy.optimize.linear_sum_assignment`; rounds over all frames repeat until the
    cost stops decreasing. Starts from :func:`greedy_assignment` unless ``initial`` is given.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
        The distance tensor of eq. (7).
    initial : array_like of int, shape (N_T, N_P), optional
        Starting assignment; default :func:`greedy_assignment`'s.
    n_targets : int, optional
        ``N_T``; default ``N_M``.
    max_rounds : int, default 100
        Largest number of rounds over all frames.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
    cost : float
    """
    D, n = _check_square(D, n_targets)
    n_q = D.shape[0]
    n_p = n_q + 2
    A = greedy_assignment(D) if initial is None else np.array(initial, dtype=np.intp, copy=True)
    if A.shape != (n, n_p):
        raise ValueError(f"initial must have shape ({n}, {n_p}), got {A.shape}")
    max_rounds = as_int(max_rounds, "max_rounds", 1)
    cost = assignment_cost(A, D)
    for _ in range(max_rounds):
        for f in range(n_p):
            _, A[:, f] = linear_sum_assignment(_frame_cost(D, A, f))
        new = assignment_cost(A, D)
        if new >= cost - 1e-12:
            cost = min(cost, new)
            break
        cost = new
    return A, cost

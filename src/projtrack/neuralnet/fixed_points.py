"""Fixed points of one-to-one assignments: the offset's limit on the summed distances of a neuron."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from projtrack._validation import as_bool, as_int, as_real

from ._checks import _check_D, _check_square
from .assignments import _permutation_triples, assignment_cost
from .coefficients import PAPER_OFFSET, Coefficients, _as_coefficients
from .dynamics import update_inputs

__all__ = ["is_fixed_point", "fixed_point_limit", "neuron_distance_sums", "assignment_max_sums"]


def is_fixed_point(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None, *,
                   offset: float = PAPER_OFFSET, self_coupling: bool = True,
                   exact_energy: bool = False) -> np.ndarray | bool:
    """Whether binary states are fixed points of the update rule (no neuron would change).

    A state is a fixed point when every neuron already equals ``[input < offset]`` with
    the input of :func:`update_inputs`; then serial and parallel sweeps both leave it
    unchanged.

    Parameters
    ----------
    X : array_like of 0/1, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients, offset, self_coupling, exact_energy
        As in :func:`run_net`.

    Returns
    -------
    bool or ndarray of bool, shape X.shape[:-3]
    """
    Xa = np.asarray(X)
    if not np.all(np.isin(Xa, (0, 1))):
        raise ValueError("X must be binary (0/1)")
    offset = as_real(offset, "offset")
    g = update_inputs(Xa, D, coefficients, self_coupling=self_coupling, exact_energy=exact_energy)
    out = np.all((g < offset) == (Xa == 1), axis=(-3, -2, -1))
    return bool(out) if np.ndim(out) == 0 else out


def fixed_point_limit(coefficients: Coefficients | Sequence[float] | None = None, *, offset: float = PAPER_OFFSET,
                      self_coupling: bool = True, exact_energy: bool = False) -> float:
    """Largest summed distance an active neuron of a one-to-one assignment may carry.

    In a one-to-one assignment state (``N_T = N_M``: every target one measurement and every
    measurement one target in every frame) terms 1 and 2 of eq. (9) vanish for an active
    neuron and term 3 is 0 (as printed), ``-2 A3`` (without the self term) or ``-A3``
    (exact energy change), so its input is ``A4 S`` plus that constant, where ``S`` is the
    sum of its D terms (:func:`neuron_distance_sums`). An inactive neuron sees at least
    ``2 A1 + 2 A2`` and stays off. The assignment is therefore a fixed point if and only if
    ``max S < limit`` with ``limit = (offset + {0, 2 A3, A3}) / A4``, returned here (in the
    unit of D; ``-inf`` when no assignment can be a fixed point).

    Parameters
    ----------
    coefficients : Coefficients or sequence of 4 floats, optional
        The weights of eq. (8); default the paper's.
    offset : float, keyword-only, default 0.035
        The neurons' threshold.
    self_coupling, exact_energy : bool, keyword-only
        The reading of eq. (4), as in :func:`update_inputs`.

    Raises
    ------
    ValueError
        If ``2 A1 + 2 A2`` plus the inactive neuron's term 3 does not exceed ``offset``
        (then inactive neurons could switch on and the statement above does not hold).
    """
    c = _as_coefficients(coefficients)
    offset = as_real(offset, "offset")
    as_bool(self_coupling, "self_coupling")
    as_bool(exact_energy, "exact_energy")
    shift = c.A3 if exact_energy else (0.0 if self_coupling else 2 * c.A3)
    inactive = 2 * c.A1 + 2 * c.A2 + (c.A3 if exact_energy else 0.0)
    if inactive < offset:
        raise ValueError(f"offset {offset} is not below 2 A1 + 2 A2 (+ A3) = {inactive}: inactive neurons "
                         "of an assignment could switch on")
    if c.A4 == 0:
        return float("inf") if offset + shift > 0 else float("-inf")
    limit = (offset + shift) / c.A4
    return float(limit) if limit > 0 else float("-inf")


def neuron_distance_sums(assignment: np.ndarray, D: np.ndarray) -> np.ndarray:
    r""":math:`S_{ia}`: the summed equation (7) distances that neuron :math:`(i,
    \alpha_{ia}, a)` of an assignment sees.

    In the assignment state, term 4 of eq. (9) for the active neuron of target ``i`` in
    frame ``a`` is ``A4 S[i, a]``: the D values of the (up to three) triples of frames of
    target ``i``'s track that contain frame ``a``.

    Parameters
    ----------
    assignment : array_like of int, shape (N_T, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)

    Returns
    -------
    ndarray, shape (N_T, N_P)
    """
    D = _check_D(D)
    A = np.asarray(assignment)
    assignment_cost(A, D)  # validates shape, dtype and range
    n_q = D.shape[0]
    a = np.arange(n_q)
    trip = D[a[None, :], A[:, :-2], A[:, 1:-1], A[:, 2:]]  # (N_T, N_P - 2)
    S = np.zeros(A.shape)
    S[:, :-2] += trip
    S[:, 1:-1] += trip
    S[:, 2:] += trip
    return S


def assignment_max_sums(D: np.ndarray, n_targets: int | None = None, max_assignments: int = 2_000_000
                        ) -> np.ndarray:
    r""":math:`\max_{i,a} S_{ia}` (:func:`neuron_distance_sums`) for every one-to-one
    assignment.

    Exhaustive over all ``(N_T!)^(N_P - 1)`` assignments with frame 0 labelled by the
    identity (targets are interchangeable): ``24^4 = 331776`` for the paper's case.
    With :func:`fixed_point_limit` this says exactly which assignments are fixed points.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M), ``N_M = N_T``
    n_targets : int, optional
    max_assignments : int
        Refuse larger enumerations.

    Returns
    -------
    ndarray, shape (N_T!,) * (N_P - 1)
        Entry ``[p_1, ..., p_{N_P-1}]``: frame ``a`` assigns measurement
        ``perms[p_a][i]`` to target ``i``, ``perms`` the permutations of ``range(N_T)`` in
        lexicographic order (:func:`itertools.permutations`).
    """
    D, n = _check_square(D, n_targets)
    P = math.factorial(n)
    n_q = D.shape[0]
    n_p = n_q + 2
    max_assignments = as_int(max_assignments, "max_assignments", 1)
    if P ** (n_p - 1) > max_assignments:
        raise ValueError(f"{P}^{n_p - 1} assignments exceed max_assignments = {max_assignments}")
    perms, flat = _permutation_triples(n)
    # trip[a, i]: D of triple a for target i under the permutations of frames a..a+2 (target axis first,
    # so that the maximum over targets is an elementwise maximum of contiguous arrays)
    trip = np.moveaxis(D.reshape(n_q, -1)[:, flat], -1, 1)  # (N_P - 2, N_T, P, P, P)
    # S of frame f for target i: sum of the triples a with a <= f <= a + 2; frame 0 is the identity.

    def triple(a: int) -> np.ndarray:
        t = trip[a][:, 0] if a == 0 else trip[a]     # frame 0 fixed: drop its axis
        first = max(a - 1, 0)                         # first free frame axis it spans
        idx = [None] * (n_p - 1)
        for k in range(first, a + 2):
            idx[k] = slice(None)
        return t[(slice(None),) + tuple(idx)]

    # D >= 0, so a frame whose triples are a subset of another frame's never holds the maximum:
    # only the maximal windows of triples need summing (one window for N_P = 5).
    windows = {tuple(range(max(0, f - 2), min(f, n_q - 1) + 1)) for f in range(n_p)}
    windows = [w for w in windows if not any(set(w) < set(v) for v in windows)]
    best = np.zeros((P,) * (n_p - 1))
    for w in sorted(windows):
        S = triple(w[0])
        for a in w[1:]:
            S = S + triple(a)
        S = np.broadcast_to(S, (n,) + best.shape)
        best = np.maximum(best, S.max(axis=0))
    return best

"""Assignments of measurements to targets: reading them from states, scoring and costing them."""

from __future__ import annotations

import functools
import itertools

import numpy as np

from projtrack._validation import as_int

from ._checks import _check_D

__all__ = ["states_to_assignment", "assignment_to_states", "is_correct_assignment", "assignment_cost"]


def states_to_assignment(X: np.ndarray) -> np.ndarray | None:
    """Read an assignment from binary states, or None if the states are not admissible.

    Admissible (conditions 4-6 of Sec. III): in every frame every target has exactly one
    active neuron and every measurement at most one.

    Parameters
    ----------
    X : array_like of 0/1, shape (N_T, N_M, N_P)

    Returns
    -------
    ndarray of int, shape (N_T, N_P), or None
    """
    X = np.asarray(X)
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    if not np.all(np.isin(X, (0, 1))):
        raise ValueError("X must be binary (0/1)")
    if np.any(X.sum(axis=1) != 1) or np.any(X.sum(axis=0) > 1):
        return None
    return np.argmax(X, axis=1)


def assignment_to_states(assignment: np.ndarray, n_measurements: int) -> np.ndarray:
    """Binary states, shape :math:`(N_T, N_M, N_P)`, of an assignment, shape :math:`(N_T,
    N_P)`.

    Parameters
    ----------
    assignment : array_like of int, shape (N_T, N_P)
        ``assignment[i, a]``: the measurement of target ``i`` in frame ``a``.
    n_measurements : int
        ``N_M``.

    Returns
    -------
    numpy.ndarray of int8, shape (N_T, N_M, N_P)
    """
    A = np.asarray(assignment)
    if A.ndim != 2 or not np.issubdtype(A.dtype, np.integer):
        raise ValueError(f"assignment must be an int array (N_T, N_P), got {A.dtype} {A.shape}")
    n_measurements = as_int(n_measurements, "n_measurements", 1)
    if A.size and (A.min() < 0 or A.max() >= n_measurements):
        raise ValueError(f"assignment entries must be in [0, {n_measurements})")
    n_t, n_p = A.shape
    X = np.zeros((n_t, n_measurements, n_p), dtype=np.int8)
    X[np.arange(n_t)[:, None], A, np.arange(n_p)[None, :]] = 1
    return X


def is_correct_assignment(assignment: np.ndarray | None, labels: np.ndarray) -> bool:
    """True when every target follows one true track through all frames.

    Parameters
    ----------
    assignment : int array (N_T, N_P) or None
        Measurement of each target in each frame (None: not admissible, so not correct).
    labels : int array (N_P, N_M)
        True track of each measurement (negative for spurious or padded measurements).
    """
    labels = np.asarray(labels)
    if labels.ndim != 2:
        raise ValueError(f"labels must have shape (N_P, N_M), got {labels.shape}")
    if assignment is None:
        return False
    A = np.asarray(assignment)
    if A.ndim != 2 or A.shape[1] != labels.shape[0]:
        raise ValueError(f"assignment must have shape (N_T, N_P = {labels.shape[0]}), got {A.shape}")
    tracks = labels[np.arange(labels.shape[0])[None, :], A]  # (N_T, N_P)
    if np.any(tracks < 0):
        return False
    if np.any(tracks != tracks[:, :1]):
        return False
    return len(set(tracks[:, 0].tolist())) == A.shape[0] and all(
        len(set(A[:, a].tolist())) == A.shape[0] for a in range(A.shape[1]))


def assignment_cost(assignment: np.ndarray, D: np.ndarray) -> float:
    """Summed equation (7) distance of an assignment: term 4 of equation (8) without
    :math:`A_4`.

    Parameters
    ----------
    assignment : array_like of int, shape (N_T, N_P)
        Measurement index of each target in each frame, every entry in ``0..N_M-1``.
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)

    Returns
    -------
    float
    """
    D = _check_D(D)
    A = np.asarray(assignment)
    if A.ndim != 2 or A.shape[1] != D.shape[0] + 2:
        raise ValueError(f"assignment must have shape (N_T, N_P = {D.shape[0] + 2}), got {A.shape}")
    if A.dtype == bool or not np.issubdtype(A.dtype, np.integer):
        raise TypeError(f"assignment must hold integer measurement indices, got dtype {A.dtype}")
    n_m = D.shape[-1]
    if A.size and (A.min() < 0 or A.max() >= n_m):
        raise ValueError(f"assignment entries must be measurement indices in 0..{n_m - 1} (N_M = {n_m}), "
                         f"got values in {int(A.min())}..{int(A.max())}")
    a = np.arange(D.shape[0])
    return float(D[a[None, :], A[:, :-2], A[:, 1:-1], A[:, 2:]].sum())


@functools.lru_cache(maxsize=8)
def _permutation_triples(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Permutations of ``range(n)`` and flat indices into ``D[a]`` of every triple of them."""
    perms = np.array(list(itertools.permutations(range(n))), dtype=np.intp)  # (P, n); perms[0] = identity
    p0 = perms[:, None, None, :]
    p1 = perms[None, :, None, :]
    p2 = perms[None, None, :, :]
    flat = (p0 * n + p1) * n + p2                                            # (P, P, P, n)
    flat.setflags(write=False)
    perms.setflags(write=False)
    return perms, flat

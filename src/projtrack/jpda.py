"""Joint probabilistic data association (JPDA): Fisher & Casasent (1989).

Implements chapter 4 of Casasent's 1989 report (J. L. Fisher and D. P. Casasent,
"Fast JPDA multitarget tracking algorithm", Appl. Opt. 28, 1989).

Notation follows the paper: ``m`` measurements, ``T`` targets, a binary validation
matrix of shape ``(m, T + 1)`` whose column 0 (the "no target", i.e. clutter, column)
is all ones, and feasibility matrices that pick exactly one 1 per row with at most one
1 per target column (Sec. II.B).
"""

from __future__ import annotations

from collections.abc import Iterator
from math import comb, factorial

import numpy as np

__all__ = ["count_feasible_events", "iter_feasibility_matrices"]


def _check_count(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value}")
    return int(value)


def count_feasible_events(m: int, T: int) -> int:
    """Number of feasibility matrices of an all-ones ``m x T`` validation matrix, eq. (1).

    Eq. (1) of Fisher & Casasent, for ``m >= T`` (the paper swaps ``m`` and ``T``
    otherwise, and the count is symmetric)::

        1 + sum_{k=0}^{T-1} C(T, k) * m! / (m - T + k)!

    The term ``k`` counts the events in which ``T - k`` targets are detected: choose
    which targets (``C(T, k)``) and give them distinct measurements in order
    (``m (m-1) ... (m - T + k + 1)``); the leading 1 is the event with no target
    detected. The result is an exact Python integer.

    Parameters
    ----------
    m : int
        Number of measurements, >= 0.
    T : int
        Number of targets, >= 0.

    Returns
    -------
    int
        The number of feasible joint events (Table I of the paper for m, T = 1..10).

    Examples
    --------
    >>> count_feasible_events(3, 2)
    13
    >>> count_feasible_events(10, 10)
    234662231
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    if m < T:
        m, T = T, m
    return 1 + sum(
        comb(T, k) * factorial(m) // factorial(m - T + k) for k in range(T)
    )


def iter_feasibility_matrices(validation: np.ndarray) -> Iterator[np.ndarray]:
    """Enumerate the feasibility matrices of a validation matrix (Sec. II.B).

    Parameters
    ----------
    validation : array_like of 0/1, shape (m, T + 1)
        Binary validation matrix; column 0 (clutter) must be all ones, column ``t``
        marks the measurements inside target ``t``'s gate.

    Yields
    ------
    numpy.ndarray of int8, shape (m, T + 1)
        Each feasibility matrix: one 1 per row, at most one 1 in each column
        ``t >= 1``. Order: lexicographic in the target chosen for measurement 1, then
        measurement 2, and so on (target 0 first).
    """
    v = np.asarray(validation)
    if v.ndim != 2 or v.shape[1] < 1:
        raise ValueError(f"validation must be a 2-D (m, T + 1) array, got shape {v.shape}")
    if not np.all(np.isin(v, (0, 1))):
        raise ValueError("validation must contain only 0 and 1")
    if v.shape[0] and not np.all(v[:, 0] == 1):
        raise ValueError("column 0 of validation (the clutter column) must be all ones")
    m, n_cols = v.shape
    choices = [np.flatnonzero(v[j]).tolist() for j in range(m)]
    assign = [0] * m

    def rec(j: int, used: set[int]) -> Iterator[np.ndarray]:
        if j == m:
            out = np.zeros((m, n_cols), dtype=np.int8)
            out[np.arange(m), assign] = 1
            yield out
            return
        for t in choices[j]:
            if t and t in used:
                continue
            assign[j] = t
            yield from rec(j + 1, used | {t} if t else used)

    yield from rec(0, set())

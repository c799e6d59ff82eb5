"""Feasible joint events (Sec. II.B): their number, eq. (1), and the feasibility matrices.

A feasibility matrix picks exactly one 1 per row of the validation matrix (the
measurement's origin: clutter or one target) with at most one 1 per target column.
"""

from __future__ import annotations

from collections.abc import Iterator
from math import comb, factorial

import numpy as np

from projtrack._validation import as_choice, as_int

from .validation import mvm_to_validation

__all__ = ["count_feasible_events", "iter_feasibility_matrices", "feasibility_matrices"]


def count_feasible_events(m: int, T: int) -> int:
    r"""Number of feasibility matrices of an all-ones :math:`m \times T` validation matrix,
    equation (1).

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
    m = as_int(m, "m", minimum=0)
    T = as_int(T, "T", minimum=0)
    if m < T:
        m, T = T, m
    return 1 + sum(
        comb(T, k) * factorial(m) // factorial(m - T + k) for k in range(T)
    )


def iter_feasibility_matrices(validation: np.ndarray,
                              order: str = "lexicographic") -> Iterator[np.ndarray]:
    """Enumerate the feasibility matrices of a validation matrix (Section II.B).

    Parameters
    ----------
    validation : array_like of 0/1, shape (m, T + 1)
        Binary validation matrix; column 0 (clutter) must be all ones, column ``t``
        marks the measurements inside target ``t``'s gate.
    order : {"lexicographic", "colexicographic"}
        Order of the matrices, as an odometer over the target chosen for each
        measurement (target 0 first). ``"lexicographic"`` (default): measurement 1's
        target changes slowest, measurement ``m``'s fastest. ``"colexicographic"``:
        measurement 1's target changes fastest, measurement ``m``'s slowest; for
        the validation matrix of Fig. 1 this puts the paper's case 1 (nothing
        detected) first and its case 5 (events ``chi_11, chi_22, chi_30``) fifth, as
        in Fig. 2.

    Yields
    ------
    numpy.ndarray of int8, shape (m, T + 1)
        Each feasibility matrix: one 1 per row, at most one 1 in each column
        ``t >= 1``.

    Raises
    ------
    ValueError
        If ``validation`` is not a 2-D 0/1 array with an all-ones column 0, or
        ``order`` is not one of the two names.
    """
    as_choice(order, "order", ("lexicographic", "colexicographic"))
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
    # rows from the slowest-changing to the fastest-changing digit of the odometer
    rows = list(range(m)) if order == "lexicographic" else list(range(m - 1, -1, -1))

    def rec(depth: int, used: set[int]) -> Iterator[np.ndarray]:
        if depth == m:
            out = np.zeros((m, n_cols), dtype=np.int8)
            out[np.arange(m), assign] = 1
            yield out
            return
        j = rows[depth]
        for t in choices[j]:
            if t and t in used:
                continue
            assign[j] = t
            yield from rec(depth + 1, used | {t} if t else used)

    yield from rec(0, set())


def feasibility_matrices(mvm: object, order: str = "lexicographic") -> list[np.ndarray]:
    r"""The feasibility matrices :math:`\Omega_i` of an MVM's validation matrix (Figure 2).

    ``order`` is passed to :func:`iter_feasibility_matrices`.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix (its zeros give the validation matrix).
    order : {"lexicographic", "colexicographic"}
        Order of the events, passed to :func:`iter_feasibility_matrices`.

    Returns
    -------
    list of numpy.ndarray of int8, shape (m, T + 1)
    """
    return list(iter_feasibility_matrices(mvm_to_validation(mvm), order=order))

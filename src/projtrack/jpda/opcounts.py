"""Operation counts of the beta computations (Tables IV-V).

:class:`OpCount` is the counter the instrumented methods fill; the conventional count has
a closed form (:func:`conventional_op_count`), the paper's fast algorithm is counted by
running it on an all-ones MVM (:func:`fast_op_count`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from math import comb, factorial

import numpy as np

from projtrack._validation import as_bool, as_int

from .feasible import count_feasible_events
from .paper import beta_paper

__all__ = ["OpCount", "conventional_op_count", "fast_op_count"]


@dataclass
class OpCount:
    """Additions and multiplications counted by an instrumented beta computation.

    Counting convention (the one that reproduces Tables IV-V of the paper exactly):
    a sum of ``n`` terms costs ``n - 1`` additions, a product of ``n`` factors
    ``n - 1`` multiplications; the final normalization (divisions) and eq. (2)
    are not counted.

    Parameters
    ----------
    additions, multiplications : int, default 0
        The running counts.
    detail : dict
        Counts by stage or kind, filled by the counting methods.
    """

    additions: int = 0
    multiplications: int = 0
    detail: dict = field(default_factory=dict)

    def add(self, n_add: int = 0, n_mul: int = 0) -> None:
        self.additions += int(n_add)
        self.multiplications += int(n_mul)

    def __str__(self) -> str:
        return f"{self.additions}/{self.multiplications}"


def conventional_op_count(m: int, T: int) -> OpCount:
    """Operation count of the conventional method for an all-ones validation matrix (Table IV).

    Closed form of what :func:`beta_enumerated` counts on an all-ones MVM:

    * multiplications: ``N (T - 1)``, where ``N`` is the number of feasible events
      of eq. (1) (:func:`count_feasible_events`) and each event's probability is
      the product of ``T`` MVM entries, one per target;
    * additions: ``sum_{j >= 1, t} (n_jt - 1)``, where ``n_jt`` is the number of
      events that contain the pairing ``chi_jt`` (``beta_jt`` sums their ``n_jt``
      probabilities). Summed over ``j`` and ``t``, ``n_jt`` counts every detection
      of every event, ``D = sum_{k >= 1} k C(m, k) C(T, k) k!`` (``k`` detections:
      choose ``k`` measurements, ``k`` targets and a matching), so the additions are
      ``D - m T``. For an all-ones matrix every ``n_jt`` equals the eq. (1) count of
      the remaining ``m - 1`` measurements and ``T - 1`` targets, i.e. the
      additions are ``m T (N(m - 1, T - 1) - 1)``.

    Neither the final normalization nor eq. (2) is counted (see :class:`OpCount`).

    Parameters
    ----------
    m, T : int
        Numbers of measurements and targets, ``>= 0``.

    Returns
    -------
    OpCount

    Examples
    --------
    >>> str(conventional_op_count(7, 7))  # Table IV, m = T = 7
    '652974/785532'
    """
    m = as_int(m, "m", minimum=0)
    T = as_int(T, "T", minimum=0)
    N = count_feasible_events(m, T)
    det = sum(comb(m, k) * comb(T, k) * factorial(k) * k for k in range(1, min(m, T) + 1))
    return OpCount(additions=det - m * T if m * T else 0, multiplications=N * max(T - 1, 0))


def fast_op_count(m: int, T: int, store_intermediates: bool = False) -> OpCount:
    """Operation count of :func:`beta_paper` (Table V) by running it on an all-ones MVM.

    Parameters
    ----------
    m, T : int
        Numbers of measurements (``0..22``) and targets (``>= 0``).
    store_intermediates : bool
        Count the variant that reuses target 1's chain (see :func:`beta_paper`).
    """
    m = as_int(m, "m", minimum=0, maximum=22)  # beta_paper needs 2^m words
    T = as_int(T, "T", minimum=0)
    as_bool(store_intermediates, "store_intermediates")
    ops = OpCount()
    mvm = np.vstack([np.full((1, T), 0.5), np.ones((m, T))])
    beta_paper(mvm, ops=ops, store_intermediates=store_intermediates)
    return ops

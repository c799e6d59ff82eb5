"""The package's default beta: independent clusters, then the forward-backward method on each.

:func:`beta` also dispatches to the paper's algorithm and to the enumeration by name.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from projtrack._validation import as_choice

from ._checks import _check_mvm, _fail_no_event
from .enumeration import beta_enumerated
from .forward_backward import beta_forward_backward
from .paper import beta_paper

if TYPE_CHECKING:
    from .opcounts import OpCount

__all__ = ["clusters", "beta"]


def clusters(mvm: object) -> list[tuple[np.ndarray, np.ndarray]]:
    """Independent clusters of an MVM: connected components of its validation graph.

    Targets with no validated measurement form singleton clusters with no measurement;
    measurements validated by no target are dropped. Joint events factor over clusters,
    so beta can be computed cluster by cluster.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix (see :func:`beta`).

    Returns
    -------
    list of (numpy.ndarray, numpy.ndarray)
        One ``(measurements, targets)`` pair of index arrays per cluster, measurements
        numbered 1..m as MVM rows.
    """
    w = _check_mvm(mvm)
    A = w[1:] > 0
    T = A.shape[1]
    if T == 0:
        return []
    # label propagation over the target-target graph (targets sharing a measurement)
    adj = (A.T.astype(np.int64) @ A.astype(np.int64) > 0) | np.eye(T, dtype=bool)
    lab = np.arange(T)
    while True:
        new = np.where(adj, lab[None, :], T).min(axis=1)
        if np.array_equal(new, lab):
            break
        lab = new
    meas_lab = np.where(A.any(axis=1), np.where(A, lab[None, :], T).min(axis=1), -1)
    out = []
    for c in np.unique(lab):
        out.append((np.flatnonzero(meas_lab == c) + 1, np.flatnonzero(lab == c)))
    return out


def beta(mvm: object, *, method: str = "auto", ops: OpCount | None = None) -> np.ndarray:
    r"""Exact JPDA association probabilities :math:`\beta_{jt}` from the MVM (Sections
    III.B-D).

    A feasible joint event gives each target either "no measurement" or a distinct
    validated measurement; its weight is the product over targets of the MVM entries it
    uses. :math:`\beta_{jt}` is the total weight of the events that give measurement
    :math:`j` to target :math:`t`, divided by the total weight of all events (eq. 2).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix. Row 0 holds the weight of "target :math:`t` has no
        measurement": :math:`1 - P_{D,t} P_G` in the package's convention
        (:func:`mvm_from_positions`, used by :class:`JPDATracker`), :math:`1 - P_{D,t}`
        in the paper's eq. (3) (:func:`modified_validation_matrix`); it must lie in
        [0, 1). Row :math:`j \ge 1` holds :math:`P_{D,t} f_t(z_j)` (eq. 4, optionally
        divided by the clutter density), zero where measurement :math:`j` is not
        validated for target :math:`t`.
    method : {"auto", "forward-backward", "paper", "enumerate"}
        ``"paper"`` is the algorithm exactly as published (:func:`beta_paper`,
        :math:`O(T^2 m 2^m)`); ``"enumerate"`` the conventional method
        (:func:`beta_enumerated`); ``"forward-backward"`` the single-sweep exact
        method (:func:`beta_forward_backward`); ``"auto"`` (default) splits the MVM
        into independent clusters (:func:`clusters`) and runs the forward-backward
        method on each, iterating over subsets of whichever is smaller of the
        cluster's measurements and targets. All four give the same probabilities.
    ops : OpCount, optional
        Operation counter passed to the chosen method.

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)
        ``beta[j, t]``: probability that measurement :math:`j` originated from target
        :math:`t`; ``beta[0, t]`` :math:`= 1 - \sum_j \beta_{jt}` (eq. 2), the
        probability that target :math:`t` has no measurement. Every column sums to 1.

    Raises
    ------
    ValueError
        If ``mvm`` is not a finite non-negative 2-D array with row 0 in [0, 1), or no
        feasible event has positive weight.

    Notes
    -----
    Complexity of ``"auto"``: :math:`O(\sum_c \max(m_c, T_c) \min(m_c, T_c)
    2^{\min(m_c, T_c)})` over clusters :math:`c`, and :math:`O(\max(m_c, T_c)
    2^{\min(m_c, T_c)})` memory: exponential in :math:`\min(m, T)` for a fully gated
    problem. Exact JPDA computes matrix permanents, which is #P-hard already for 0-1
    matrices, so no polynomial-time exact method exists unless FP = #P. On the 2-core
    machine of ``benchmarks/bench_jpda.py`` a fully gated :math:`m = T = 16` takes about
    0.02 s and :math:`m = T = 20` 0.5 to 1.2 s (measured while the machine ran other jobs).

    Examples
    --------
    Two targets, three measurements: measurement 2 lies in both gates.

    >>> import numpy as np
    >>> from projtrack.jpda import beta
    >>> mvm = np.array([[0.1, 0.1],     # 1 - P_D P_G
    ...                 [0.5, 0.0],     # measurement 1: only target 0
    ...                 [0.3, 0.6],     # measurement 2: both
    ...                 [0.0, 0.4]])    # measurement 3: only target 1
    >>> b = beta(mvm)
    >>> np.round(b, 3)
    array([[0.136, 0.111],
           [0.679, 0.   ],
           [0.185, 0.444],
           [0.   , 0.444]])
    >>> np.allclose(b.sum(axis=0), 1)
    True
    """
    as_choice(method, "method", ("auto", "forward-backward", "paper", "enumerate"))
    if method == "paper":
        return beta_paper(mvm, ops=ops)
    if method == "enumerate":
        return beta_enumerated(mvm, ops=ops)
    if method == "forward-backward":
        return beta_forward_backward(mvm, ops=ops)
    w = _check_mvm(mvm)
    m1, T = w.shape
    out = np.zeros((m1, T))
    for meas, targ in clusters(w):
        if meas.size == 0:
            if np.any(w[0, targ] <= 0):
                _fail_no_event(w[:, targ])
            out[0, targ] = 1.0
            continue
        sub = w[np.r_[0, meas]][:, targ]
        b = beta_forward_backward(sub, ops=ops)
        out[np.ix_(np.r_[0, meas], targ)] = b
    return out

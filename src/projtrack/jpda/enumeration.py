"""The conventional method (Secs. II.B-C): beta by enumerating every feasible event."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._checks import _check_mvm, _fail_no_event, _normalize_columns

if TYPE_CHECKING:
    from .opcounts import OpCount

__all__ = ["beta_enumerated"]


def _assignments(w: np.ndarray) -> np.ndarray:
    """All feasible events as an (n_events, T) array of measurement rows (0 = undetected)."""
    m1, T = w.shape
    events = np.zeros((1, 0), dtype=np.int64)
    for t in range(T):
        rows = np.flatnonzero(w[:, t] > 0)
        if rows.size == 0:
            return np.zeros((0, T), dtype=np.int64)
        new = []
        for r in rows:
            if r == 0:
                keep = events
            else:
                keep = events[~np.any(events == r, axis=1)]
            if len(keep):
                new.append(np.hstack([keep, np.full((len(keep), 1), r, dtype=np.int64)]))
        events = np.vstack(new) if new else np.zeros((0, t + 1), dtype=np.int64)
    return events


def beta_enumerated(mvm: object, *, ops: OpCount | None = None) -> np.ndarray:
    """Association probabilities by enumerating every feasible event (Sections II.B-C).

    The conventional method: every feasibility matrix of the validation matrix
    (``mvm > 0``) is generated, its probability is the product of the individual
    event probabilities (one MVM entry per target), and ``beta[j, t]`` sums the
    probabilities of the events containing ``chi_{j,t}``, normalized by the sum over
    all events. Row 0 is eq. (2), ``beta_0t = 1 - sum_j beta_jt``, computed directly
    as the probability of the events in which target ``t`` is not detected.
    Cost: the number of feasible events, up to eq. (1) (Table I) times ``T``.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix, eqs. (3)-(4).
    ops : OpCount, optional
        If given, counts the operations of the method as in Table IV: ``T - 1``
        multiplications per feasible event and ``n - 1`` additions for each
        ``beta_jt`` (``j >= 1``) that sums ``n`` event probabilities.

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)
    """
    w = _check_mvm(mvm)
    m1, T = w.shape
    if T == 0:
        return np.zeros((m1, 0))
    wn = _normalize_columns(w)
    ev = _assignments(wn)
    if len(ev) == 0:
        _fail_no_event(w)
    p = np.prod(wn[ev, np.arange(T)[None, :]], axis=1)
    Z = p.sum()
    if not Z > 0:
        _fail_no_event(w)
    out = np.zeros((m1, T))
    for t in range(T):
        np.add.at(out[:, t], ev[:, t], p)
    if ops is not None:
        counts = np.zeros((m1, T), dtype=np.int64)
        for t in range(T):
            np.add.at(counts[:, t], ev[:, t], 1)
        c = counts[1:]
        ops.add(n_add=int(np.sum(np.maximum(c - 1, 0))), n_mul=len(ev) * (T - 1))
        ops.detail["events"] = len(ev)
    return out / Z

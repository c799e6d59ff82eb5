"""A forward-backward sweep over the reachable MU words only, instrumented (JPDA chapter).

The remark after Table VI ("when intermediate f etc. vectors are stored, the improvement
exceeds a factor of 110") does not say which vectors are kept. Keeping *every* vector of
both directions is the forward-backward sweep; :func:`projtrack.jpda.beta_forward_backward`
runs it over all ``2^min(m, T)`` words at every step, which is not how Table V counts the
paper's own algorithm (a stage there computes only the words still needed).
:func:`beta_sweep_reachable` computes, at every step, only the words that step can reach,
and counts its operations with the convention of Tables IV-V
(:class:`projtrack.jpda.OpCount`), so that it can stand beside Table V as a reading of
"stored intermediate vectors". :func:`sweep_counts` tabulates its counts.

With targets taken in the MVM's order ``t = 0 .. T-1`` and a word ``v`` the set of
measurements used:

* forward ``A_0 = [v = {}]``, ``A_{t+1}[v] = a_{0t} A_t[v] + sum_{j in v} a_{jt} A_t[v - j]``,
  computed for ``|v| <= t + 1`` (targets ``< t + 1`` use at most ``t + 1`` measurements);
* backward ``B_T = 1``, ``B_t[v] = a_{0t} B_{t+1}[v] + sum_{j not in v} a_{jt} B_{t+1}[v + j]``,
  computed for ``|v| <= t`` (the words the forward messages can present to it): the
  paper's target vectors of Sec. III.C, for target 1's chain;
* ``beta_{jt} ~ a_{jt} sum_{v not containing j, |v| <= t} A_t[v] B_{t+1}[v + j]``; every
  column sums to the same constant ``Z``, the sum over all feasible events (Sec. III.D
  normalizes every column by one constant).

Products by a structural 1 (``A_0``, ``B_T``) are not counted, as the paper's algorithm does
not count them in its first vector (Sec. III.B: sums only).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_bool, as_int
from projtrack.jpda import OpCount

__all__ = ["SweepRun", "beta_sweep_reachable", "sweep_counts"]


@dataclass(frozen=True)
class SweepRun:
    """What :func:`beta_sweep_reachable` computed.

    Attributes
    ----------
    beta : ndarray, shape (m + 1, T)
        Association probabilities (columns normalized).
    column_sums : ndarray, shape (T,)
        The unnormalized column sums: each equals ``Z``, the sum of the probabilities of all
        feasible events.
    ops : OpCount
        Additions and multiplications executed.
    words : int
        Vector elements computed in all (forward and backward).
    """

    beta: np.ndarray
    column_sums: np.ndarray
    ops: OpCount
    words: int


def _mvm(mvm: object) -> np.ndarray:
    w = as_array(mvm, "mvm", ndim=2)
    if w.shape[0] < 1 or w.shape[1] < 1:
        raise ValueError(f"mvm must have a row 0 and at least one target column, got shape {w.shape}")
    if np.any(w < 0):
        raise ValueError("mvm entries must be >= 0 (probabilities and densities)")
    if w.shape[0] - 1 > 20:
        raise ValueError(f"mvm has m = {w.shape[0] - 1} measurements; the sweep indexes 2^m words "
                         "and takes at most 20")
    return w


def beta_sweep_reachable(mvm: object, *, last_forward: bool = False) -> SweepRun:
    """Exact beta by a forward-backward sweep that computes only the reachable MU words.

    See the module docstring for the recursions. The operation count follows
    :class:`projtrack.jpda.OpCount` (a sum of ``n`` terms costs ``n - 1`` additions, each
    term one product; products by a structural 1 are free); a term is counted whenever its
    word is reachable, whatever the MVM's values (as Tables IV-V count all-ones MVMs).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        A modified validation matrix (nonnegative, ``m <= 20``).
    last_forward : bool, default False
        Also compute the last forward message ``A_T`` (all targets), whose sum is ``Z``.
        Beta does not read it (every column already sums to ``Z``); it only adds to the
        count.

    Returns
    -------
    SweepRun

    Raises
    ------
    ValueError
        For a bad MVM, or when no feasible event has positive probability.
    """
    w = _mvm(mvm)
    m1, T = w.shape
    m = m1 - 1
    N = 1 << m
    S = np.arange(N, dtype=np.int64)
    pc = np.bitwise_count(S).astype(np.int64)
    has = [((S >> j) & 1) == 1 for j in range(m)]
    ops = OpCount()
    words = 0
    # forward messages A_0 .. A_{T-1} (A_t: targets < t)
    A = [np.zeros(N)]
    A[0][0] = 1.0
    for t in range(T if as_bool(last_forward, "last_forward") else T - 1):
        reach = pc <= min(t + 1, m)
        words += int(reach.sum())
        new = np.zeros(N)
        if t == 0:  # A_0 is the indicator of the empty word: the entries are the column itself
            new[0] = w[0, 0]
            for j in range(m):
                new[1 << j] = w[j + 1, 0]
        else:
            self_ = reach & (pc <= t)
            new[self_] = w[0, t] * A[t][self_]
            n_terms = int(self_.sum())
            for j in range(m):
                sel = reach & has[j]
                new[sel] += w[j + 1, t] * A[t][S[sel] ^ (1 << j)]
                n_terms += int(sel.sum())
            ops.add(n_add=n_terms - int(reach.sum()), n_mul=n_terms)
        A.append(new)
    # backward messages B_T = 1, B_{T-1} .. B_1 (B_t: targets >= t)
    B: list[np.ndarray | None] = [None] * (T + 1)
    B[T] = np.ones(N)
    for t in range(T - 1, 0, -1):
        need = pc <= min(t, m)
        words += int(need.sum())
        new = np.zeros(N)
        new[need] = w[0, t] * B[t + 1][need]
        n_terms = int(need.sum())
        for j in range(m):
            sel = need & ~has[j]
            new[sel] += w[j + 1, t] * B[t + 1][S[sel] | (1 << j)]
            n_terms += int(sel.sum())
        n_add = n_terms - int(need.sum())
        ops.add(n_add=n_add, n_mul=0 if t == T - 1 else n_terms)  # B_T = 1: sums only
        B[t] = new
    # beta_jt ~ a_jt sum_{v not containing j} A_t[v] B_{t+1}[v + j]
    out = np.zeros((m1, T))
    for t in range(T):
        reach = pc <= min(t, m)
        for j in range(m1):
            sel = reach if j == 0 else reach & ~has[j - 1]
            v = S[sel]
            n = len(v)
            s = float(A[t][v] @ B[t + 1][v if j == 0 else v | (1 << (j - 1))])
            products = 0 if (t == 0 or t == T - 1) else n  # A_0 = 1 or B_T = 1
            ops.add(n_add=n - 1, n_mul=products + 1)  # + 1: the entry a_jt (eq. (6))
            out[j, t] = w[j, t] * s
    Z = out.sum(axis=0)
    if not np.all(Z > 0):
        raise ValueError("no feasible joint event of mvm has positive probability")
    return SweepRun(out / Z, Z, ops, words)


def sweep_counts(sizes: Sequence[int]) -> pd.DataFrame:
    """Operations of :func:`beta_sweep_reachable` on the all-ones MVM along ``m = T = n``.

    One row per ``n`` of ``sizes`` (at most 20): ``additions``, ``multiplications`` and
    their sum ``reachable-words sweep``. The all-ones MVM has row 0 = 0.5 and 1 elsewhere,
    as in :func:`~projtrack.experiments.jpda.all_ones_mvm`.
    """
    sizes = [as_int(n, "sizes[]", minimum=1, maximum=20) for n in sizes]
    if not sizes:
        raise ValueError("sizes must not be empty")
    rows = []
    for n in sizes:
        w = np.vstack([np.full((1, n), 0.5), np.ones((n, n))])
        ops = beta_sweep_reachable(w).ops
        rows.append({"m = T": n, "additions": ops.additions, "multiplications": ops.multiplications,
                     "reachable-words sweep": ops.additions + ops.multiplications})
    return pd.DataFrame(rows)

"""Beyond the paper: exact beta by one forward-backward sweep over subsets of ``min(m, T)``.

The paper's target vectors (Sec. III.C) are the backward messages of a dynamic program
whose state is the set of measurements used; with the forward messages as well, every
``beta_jt`` follows from one forward and one backward sweep (:func:`beta_forward_backward`).
:func:`_fb_sweep_reference` states the recursions plainly, :func:`_fb_sweep` is their
blocked fast form.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING

import numpy as np

from projtrack._validation import as_bool

from . import _kernel
from ._checks import _check_mvm, _fail_no_event, _normalize_columns

if TYPE_CHECKING:
    from .opcounts import OpCount

__all__ = ["beta_forward_backward"]


_THREAD_MIN_BITS = 14  # overlap gradients and backward messages from 2^14 states on
_SPARSE_MAX_HIGH_BITS = 16  # up to 2^16 rows the high bits use one sparse product
_LOW_BITS = 5  # the lowest bits of a subset index are handled by a small dense matrix (BLAS)
_FAST_MIN_SLOTS = 8  # from 2^8 states on, the compiled sweep of projtrack.jpda._kernel (if numba)


def _low_matrix(u: float, w: np.ndarray, n_low: int) -> np.ndarray:
    """Matrix ``M`` of one item restricted to the low bits: ``(x @ M)[S] = u x[S] + sum w_k x[S - k]``."""
    B = 1 << n_low
    M = np.eye(B) * u
    s = np.arange(B)
    for k in range(n_low):
        if w[k]:
            lacks = s[(s >> k) & 1 == 0]
            M[lacks, lacks | (1 << k)] = w[k]
    return M


def _fb_sweep_reference(W: np.ndarray, u: np.ndarray, v: np.ndarray,
                        ops: OpCount | None = None) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Reference implementation of :func:`_fb_sweep`: the recursions written out plainly.

    Items ``i = 0..n_it-1`` (rows of ``W``) are either unmatched (weight ``u[i]``) or
    matched to a distinct slot ``k`` (weight ``W[i, k]``); a slot left unmatched
    weighs ``v[k]``. ``Z`` is the sum, over all such partial matchings, of the
    product of their weights (for JPDA: the sum of the probabilities of all
    feasible events). States ``S`` are subsets of the ``n`` slots, coded as bit
    words (the paper's MU words when the slots are measurements).

    * Forward: ``F_0 = [S == {}]`` and
      ``F_{i+1}[S] = u_i F_i[S] + sum_{k in S} W[i, k] F_i[S - {k}]``
      (items ``< i + 1`` use exactly the slots ``S``).
    * ``V[S] = prod_{k not in S} v_k`` and ``Z = sum_S F_{n_it}[S] V[S]``.
    * Backward: ``G_{n_it} = V`` and
      ``G_i[S] = u_i G_{i+1}[S] + sum_{k not in S} W[i, k] G_{i+1}[S + {k}]``
      (completions of items ``>= i`` given the slots ``S`` already used: the
      paper's target vectors of Sec. III.C are these messages).
    * Gradients: ``u_i dZ/du_i = u_i sum_S F_i[S] G_{i+1}[S]`` and
      ``W[i, k] dZ/dW[i, k] = W[i, k] sum_{S not containing k} F_i[S] G_{i+1}[S + {k}]``,
      the total weight of the matchings in which item ``i`` is unmatched, or
      matched to slot ``k``; ``unmatched[k] = sum_{S not containing k} F_{n_it}[S] V[S]``
      is the weight of those in which slot ``k`` stays unmatched.

    Returns ``(Z, W * dZ/dW, u * dZ/du, unmatched)``. Cost ``O(n_it n 2^n)``; the
    operation count (``ops``) is the one :func:`_fb_sweep` records for the same
    recursions. :func:`_fb_sweep` computes the same numbers with blocked and sparse
    products and is tested against this function on every one of its code paths.
    """
    n_it, n = W.shape
    N = 1 << n
    S = np.arange(N)
    has = [((S >> k) & 1) == 1 for k in range(n)]  # has[k][S]: slot k is in S
    F = np.zeros((n_it + 1, N))
    F[0, 0] = 1.0
    n_mul = n_add = 0
    for i in range(n_it):
        F[i + 1] = u[i] * F[i]
        n_mul += N
        for k in range(n):
            if W[i, k]:
                with_k = S[has[k]]
                F[i + 1, with_k] += W[i, k] * F[i, with_k ^ (1 << k)]
                n_mul += N >> 1
                n_add += N >> 1
    V = np.ones(N)
    for k in range(n):
        V[~has[k]] *= v[k]
    FV = F[n_it] * V
    Z = float(FV.sum())
    unmatched = np.array([FV[~has[k]].sum() for k in range(n)])
    gW = np.zeros_like(W, dtype=float)
    gu = np.zeros(n_it)
    G = V
    for i in range(n_it - 1, -1, -1):
        gu[i] = u[i] * float(F[i] @ G)
        Gn = u[i] * G
        n_mul += 2 * N
        n_add += N
        for k in range(n):
            if W[i, k]:
                without_k = S[~has[k]]
                gW[i, k] = W[i, k] * float(F[i, without_k] @ G[without_k | (1 << k)])
                Gn[without_k] += W[i, k] * G[without_k | (1 << k)]
                n_mul += 2 * (N >> 1)
                n_add += 2 * (N >> 1)
        G = Gn
    if ops is not None:
        ops.add(n_add=n_add, n_mul=n_mul)
    return Z, gW, gu, unmatched


def _fb_core(W: np.ndarray, u: np.ndarray, v: np.ndarray,
             ops: OpCount | None = None,
             reference: bool = False) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_fb_sweep` with BLAS limited to one thread for large state spaces.

    The small dense products of the sweep gain nothing from BLAS threads, and idle
    BLAS threads spin-wait, which costs several times the work on a busy machine.
    With ``reference=True`` the plain :func:`_fb_sweep_reference` runs instead; from
    ``_FAST_MIN_SLOTS`` slots on, the compiled sweep of ``projtrack.jpda._kernel`` runs
    when numba is available (``PROJTRACK_NO_NUMBA=1`` keeps this numpy sweep).
    """
    if reference:
        return _fb_sweep_reference(W, u, v, ops)
    if W.shape[1] >= _FAST_MIN_SLOTS and _kernel.numba_enabled():
        return _kernel.fb_sweep(W, u, v, ops)  # compiled, same recursions (numba)
    if W.shape[1] < 12:
        return _fb_sweep(W, u, v, ops)
    try:
        from threadpoolctl import threadpool_limits  # optional (projtrack[fast])
    except ImportError:  # BLAS threads then stay as configured; the results are the same
        return _fb_sweep(W, u, v, ops)
    with threadpool_limits(limits=1, user_api="blas"):
        return _fb_sweep(W, u, v, ops)


def _fb_sweep(W: np.ndarray, u: np.ndarray, v: np.ndarray,
              ops: OpCount | None = None) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Sum over partial matchings and its gradient (the engine of :func:`beta_forward_backward`).

    The same recursions, inputs and outputs as :func:`_fb_sweep_reference` (read that
    one first: it states them plainly); this is its fast form, tested against it on
    every code path (dense low bits only, sparse high bits, strided high bits, the
    threaded backward sweep) in ``tests/test_jpda_beta.py``.

    Items ``i`` (rows of ``W``, processed one by one) are either unmatched (weight
    ``u_i``) or matched to a distinct slot ``k`` (weight ``W[i, k]``); unmatched slots
    weigh ``v_k``. Returns ``Z``, ``W * dZ/dW``, ``u * dZ/du`` and the vector
    ``P(slot k unmatched) * Z``. States are subsets of slots (``2^n`` of them).
    Forward ``F_i[S]`` (slots used exactly ``S`` by items ``< i``) and backward
    ``G_{i+1}[S]`` (sum over the completions of items ``> i`` avoiding ``S``, the
    paper's target vectors) give the gradient as inner products
    ``dZ/dW[i, k] = sum_{S not containing k} F_i[S] G_{i+1}[S + k]``.
    The lowest ``_LOW_BITS`` bits of every item are applied as one small dense
    matrix product (BLAS) on a ``(2^n / 32, 32)`` view, the others as one sparse
    product on its rows (or as strided vector updates when there are too many rows).
    """
    n_it, n = W.shape
    N = 1 << n
    nl = min(_LOW_BITS, n)
    B = 1 << nl
    rows = N // B
    F = np.empty((n_it + 1, N))
    buf = np.empty(N >> 1)
    F[0] = 0.0
    F[0, 0] = 1.0
    n_mul = n_add = 0
    high = [np.flatnonzero(W[i, nl:]) + nl for i in range(n_it)]
    Ms = [_low_matrix(u[i], W[i], nl) for i in range(n_it)]
    raise_high = lower_high = None
    if 0 < n - nl <= _SPARSE_MAX_HIGH_BITS:
        # the high bits as one sparse "raising" matrix on the rows of the (rows, B)
        # layout: row h | bit gets row h (h without the bit) times W[i, bit]
        from scipy.sparse import csr_matrix

        h = np.arange(rows)
        src = np.concatenate([h[(h >> b) & 1 == 0] for b in range(n - nl)])
        bit = np.concatenate([np.full(rows >> 1, b) for b in range(n - nl)])
        pat = csr_matrix((bit + 1.0, (src | (1 << bit), src)), shape=(rows, rows))
        bit_of_nnz = pat.data.astype(np.int64) - 1
        raise_high = pat
        lower_high = csr_matrix((bit + 1.0, (src, src | (1 << bit))), shape=(rows, rows))
        bit_of_nnz_T = lower_high.data.astype(np.int64) - 1
    for i in range(n_it):
        Fi = F[i]
        new = F[i + 1]
        np.matmul(Fi.reshape(rows, B), Ms[i], out=new.reshape(rows, B))
        if raise_high is not None and len(high[i]):
            raise_high.data = W[i, nl + bit_of_nnz]
            new.reshape(rows, B)[...] += raise_high @ Fi.reshape(rows, B)
        else:
            for k in high[i]:
                shp = (N >> (k + 1), 2, 1 << k)
                tmp = buf.reshape(N >> (k + 1), 1 << k)
                np.multiply(Fi.reshape(shp)[:, 0, :], W[i, k], out=tmp)
                dst = new.reshape(shp)[:, 1, :]
                np.add(dst, tmp, out=dst)
        nz = int(np.count_nonzero(W[i]))
        n_mul += N + nz * (N >> 1)
        n_add += nz * (N >> 1)
    # V[S] = prod_{k not in S} v_k
    V = np.ones(N)
    for k in range(n):
        V.reshape(N >> (k + 1), 2, 1 << k)[:, 0, :] *= v[k]
    FV = F[n_it] * V
    Z = float(FV.sum())
    un = np.empty(n)
    for k in range(n):
        un[k] = FV.reshape(N >> (k + 1), 2, 1 << k)[:, 0, :].sum()
    gW = np.zeros_like(W)
    gu = np.zeros(n_it)
    G = V
    Gn = np.empty(N)
    s = np.arange(B)
    low_pairs = [(s[(s >> k) & 1 == 0], s[(s >> k) & 1 == 0] | (1 << k)) for k in range(nl)]

    def gradients(i: int, G: np.ndarray) -> None:
        Fi = F[i]
        gu[i] = u[i] * float(Fi @ G)
        C = Fi.reshape(rows, B).T @ G.reshape(rows, B)
        for k in range(nl):
            if W[i, k]:
                gW[i, k] = W[i, k] * float(C[low_pairs[k]].sum())
        for k in high[i]:
            shp = (N >> (k + 1), 2, 1 << k)
            gW[i, k] = W[i, k] * float(np.einsum("ij,ij->", Fi.reshape(shp)[:, 0, :],
                                                 G.reshape(shp)[:, 1, :]))

    # The gradients of item i (read-only inner products) run in a second thread while
    # the backward message of item i is formed; numpy releases the GIL in both.
    pool = ThreadPoolExecutor(max_workers=1) if n >= _THREAD_MIN_BITS else None
    try:
        for i in range(n_it - 1, -1, -1):
            job = pool.submit(gradients, i, G) if pool else gradients(i, G)
            np.matmul(G.reshape(rows, B), Ms[i].T, out=Gn.reshape(rows, B))
            if lower_high is not None and len(high[i]):
                lower_high.data = W[i, nl + bit_of_nnz_T]
                Gn.reshape(rows, B)[...] += lower_high @ G.reshape(rows, B)
            else:
                for k in high[i]:
                    shp = (N >> (k + 1), 2, 1 << k)
                    tmp = buf.reshape(N >> (k + 1), 1 << k)
                    np.multiply(G.reshape(shp)[:, 1, :], W[i, k], out=tmp)
                    dst = Gn.reshape(shp)[:, 0, :]
                    np.add(dst, tmp, out=dst)
            if pool:
                job.result()
            nz = int(np.count_nonzero(W[i]))
            n_mul += 2 * N + 2 * nz * (N >> 1)
            n_add += N + 2 * nz * (N >> 1)
            G, Gn = Gn, G
    finally:
        if pool:
            pool.shutdown()
    if ops is not None:
        ops.add(n_add=n_add, n_mul=n_mul)
    return Z, gW, gu, un


def beta_forward_backward(mvm: object, *, ops: OpCount | None = None,
                          reference: bool = False) -> np.ndarray:
    r"""Exact beta by a forward-backward pass over subsets of :math:`\min(m, T)` (one
    cluster).

    The paper's target vectors (Sec. III.C) are the backward messages of a dynamic
    program over targets whose state is the set of measurements used; storing the
    forward messages as well gives every ``beta_jt`` as ``a_jt * dZ/da_jt / Z`` in one
    forward and one backward sweep, instead of one chain per target: the reuse of
    intermediate vectors the paper alludes to, taken to its end. When ``T < m`` the
    roles swap (measurements are processed one by one and the state is the set of
    targets used), so the cost is ``O(max(m, T) min(m, T) 2^min(m, T))`` time and
    ``O(max(m, T) 2^min(m, T))`` memory.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix, eqs. (3)-(4).
    ops : OpCount, optional
        Counts the additions and multiplications of the sweep.
    reference : bool
        Run the plain reference sweep (``_fb_sweep_reference``, the recursions as
        written in its docstring) instead of the blocked fast one; the two agree to
        rounding. For auditing and tests.
    """
    as_bool(reference, "reference")
    w = _check_mvm(mvm)
    m1, T = w.shape
    m = m1 - 1
    if T == 0:
        return np.zeros((m1, 0))
    if min(m, T) > 26:
        raise ValueError(f"min(m, T) = {min(m, T)} is too large for exact JPDA (2^min states)")
    wn = _normalize_columns(w)
    out = np.zeros((m1, T))
    if T <= m:
        # items = measurements (unmatched weight 1), slots = targets (unmatched weight a0_t)
        Z, gW, gu, un = _fb_core(wn[1:], np.ones(m), wn[0], ops, reference)
        if not Z > 0:
            _fail_no_event(w)
        out[1:] = gW / Z
        out[0] = un / Z
    else:
        # items = targets (unmatched weight a0_t), slots = measurements (weight 1)
        Z, gW, gu, un = _fb_core(wn[1:].T.copy(), wn[0], np.ones(m), ops, reference)
        if not Z > 0:
            _fail_no_event(w)
        out[1:] = gW.T / Z
        out[0] = gu / Z
    return out

"""Compiled forward-backward sweep over subsets for exact JPDA (numba, optional).

The recursions are those of the sum over partial matchings used by exact JPDA: items
``i`` (rows of ``W``) are unmatched (weight ``u_i``) or matched to a distinct slot ``k``
(weight ``W[i, k]``); a slot left unmatched weighs ``v_k``. With states ``S`` the subsets
of slots (bit words),

* forward ``F_0 = [S == {}]``, ``F_{i+1}[S] = u_i F_i[S] + sum_{k in S} W[i, k] F_i[S - k]``;
* backward ``G_n = V`` with ``V[S] = prod_{k not in S} v_k`` and
  ``G_i[S] = u_i G_{i+1}[S] + sum_{k not in S} W[i, k] G_{i+1}[S + k]``;
* ``Z = sum_S F_n[S] V[S]``, ``W[i, k] dZ/dW[i, k] = W[i, k] sum_{S not containing k}
  F_i[S] G_{i+1}[S + k]``, ``u_i dZ/du_i = u_i sum_S F_i[S] G_{i+1}[S]`` and
  ``unmatched[k] = sum_{S not containing k} F_n[S] V[S]``.

:func:`fb_sweep` evaluates them with three savings over a plain sweep:

1. **support**: ``F_i`` vanishes on subsets of more than ``i`` slots, and the gradients of
   item ``i`` read ``G_{i+1}`` only on subsets of at most ``i + 1`` slots, so step ``i``
   of either sweep touches only the blocks (below) whose high bits number at most
   ``i + 1``; the others are never formed (forward: zeroed only where the next step reads
   them, the blocks of ``i + 2`` high bits; the rest of a reused buffer is never read);
2. **cache blocking**: a state index is split into ``_LOW_BITS`` low bits (a block of
   ``2^_LOW_BITS`` contiguous doubles, kept in L1) and the high bits (the block number);
   each output block is *pulled* from its own input block (low bits, in-block strided
   updates) and from the input blocks that differ in one high bit (contiguous vector
   updates), so every block is written by one thread and the loops vectorize; the
   gradients are accumulated in the same pass that forms the backward message;
3. **memory**: when storing every forward message would exceed ``_STORE_ALL_BYTES``, they
   are kept only at checkpoints and the messages of one segment are recomputed from its
   checkpoint during the backward sweep; segments shrink towards the end (the last one is
   recomputed while every checkpoint is still kept), ``F_0`` is rebuilt rather than kept,
   ``F_n`` and ``V`` take the two scratch buffers of the forward sweep, and the backward
   message is updated in place (a block keeps a copy of its old values; its sources, the
   blocks with one more high bit, come later in its chunk or in a chunk of the next level,
   the levels running one after the other): about
   ``sqrt(2 n_items)`` buffers of ``2^n`` doubles and a little less than one extra forward
   sweep (:func:`_schedule` weighs the two, early steps being cheap).

Blocks are dealt to a fixed number of chunks (contiguous runs) whose partial sums are added in
a fixed order, so the result does not depend on the number of threads; from
``_PARALLEL_MIN_SLOTS`` slots on, two Python threads run the (GIL-free) kernels on
alternate chunks, smaller sweeps run in the calling thread.
The message buffers of the last size swept (up to ``_POOL_BYTES``) are kept for the next
call: at ``2^20`` states the page faults of fresh buffers cost more than the arithmetic. All sums have positive terms (no cancellation): the result agrees with
the plain sweep to rounding. This module needs numba; :func:`numba_enabled` says whether
it is used (numba importable and ``PROJTRACK_NO_NUMBA`` not ``1``).
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from projtrack import _numba

__all__ = ["fb_sweep", "numba_enabled"]

_HAVE_NUMBA = _numba.HAVE_NUMBA

_LOW_BITS = 10  # a block holds 2^10 doubles (8 kB, in L1)
_CHUNKS = 32  # blocks are dealt to this many interleaved chunks (fixed: deterministic sums)
_STORE_ALL_BYTES = 1 << 28  # keep every forward message up to this much memory (fresh memory
# costs page faults: beyond what the buffer pool keeps, recomputing a segment is cheaper)


def numba_enabled() -> bool:
    """True when numba is importable and ``PROJTRACK_NO_NUMBA`` is not ``1``."""
    return _HAVE_NUMBA and _numba.switched_on()


def _forward_step(Fi, Fo, w, u, i, pc, L, chunks):  # pragma: no cover - compiled
    """``Fo = F_{i+1}`` from ``Fi = F_i`` (blocks of more than ``i + 1`` high bits: zero)."""
    B = 1 << L
    rows = Fi.shape[0] >> L
    H = w.shape[0] - L
    w0 = w[0]
    w1 = w[1]
    srcs = np.empty(max(H, 1), dtype=np.int64)
    for ch in chunks:
        for h in range(ch * rows // _CHUNKS, (ch + 1) * rows // _CHUNKS):
            fo = Fo[h * B:(h + 1) * B]
            if pc[h] > i + 1:
                if pc[h] == i + 2:  # read by the next step (its own block): zero; the
                    fo[:] = 0.0  # blocks of more high bits are never read
                continue
            fi = Fi[h * B:(h + 1) * B]
            # the item unmatched and the two lowest bits, four states at a time
            for l in range(0, B, 4):
                i0 = fi[l]
                i1 = fi[l + 1]
                i2 = fi[l + 2]
                fo[l] = u * i0
                fo[l + 1] = u * i1 + w0 * i0
                fo[l + 2] = u * i2 + w1 * i0
                fo[l + 3] = u * fi[l + 3] + w0 * i2 + w1 * i1
            for k in range(2, L):
                wk = w[k]
                if wk == 0.0:
                    continue
                st = 1 << k
                for base in range(0, B, 2 * st):
                    src = fi[base:base + st]  # views: the inner loop vectorizes
                    dst = fo[base + st:base + 2 * st]
                    for j in range(st):
                        dst[j] += wk * src[j]
            # the high bits: the blocks without one of them, four source blocks per pass
            # (fewer read-modify-write passes over the output block)
            ns = 0
            for b in range(H):
                if (h >> b) & 1 and w[L + b] != 0.0:
                    srcs[ns] = b
                    ns += 1
            q = 0
            while q + 4 <= ns:
                b0 = srcs[q]
                b1 = srcs[q + 1]
                b2 = srcs[q + 2]
                b3 = srcs[q + 3]
                wa = w[L + b0]
                wb = w[L + b1]
                wc = w[L + b2]
                wd = w[L + b3]
                sa = Fi[(h ^ (1 << b0)) * B:(h ^ (1 << b0)) * B + B]
                sb = Fi[(h ^ (1 << b1)) * B:(h ^ (1 << b1)) * B + B]
                sc = Fi[(h ^ (1 << b2)) * B:(h ^ (1 << b2)) * B + B]
                sd = Fi[(h ^ (1 << b3)) * B:(h ^ (1 << b3)) * B + B]
                for l in range(B):
                    fo[l] += (wa * sa[l] + wb * sb[l]) + (wc * sc[l] + wd * sd[l])
                q += 4
            if q + 2 <= ns:
                b0 = srcs[q]
                b1 = srcs[q + 1]
                wa = w[L + b0]
                wb = w[L + b1]
                sa = Fi[(h ^ (1 << b0)) * B:(h ^ (1 << b0)) * B + B]
                sb = Fi[(h ^ (1 << b1)) * B:(h ^ (1 << b1)) * B + B]
                for l in range(B):
                    fo[l] += wa * sa[l] + wb * sb[l]
                q += 2
            if q < ns:
                b0 = srcs[q]
                wa = w[L + b0]
                sa = Fi[(h ^ (1 << b0)) * B:(h ^ (1 << b0)) * B + B]
                for l in range(B):
                    fo[l] += wa * sa[l]


def _backward_step(Fi, Gn, Go, w, u, i, pc, L, part, chunks):  # pragma: no cover - compiled
    """``Go = G_i`` from ``Gn = G_{i+1}`` on the blocks of at most ``i`` high bits, and the
    per-chunk sums ``part[ch, k] = sum F_i[S] G_{i+1}[S + k]``, ``part[ch, n] = sum F_i G_{i+1}``.

    ``Go`` may be ``Gn`` (in place): a block reads its own old values from a copy and the
    blocks with one more high bit, which come later in its chunk or in a chunk of more high
    bits (``chunks`` then holds chunks of one such level, the levels run in increasing order)."""
    B = 1 << L
    rows = Fi.shape[0] >> L
    n = w.shape[0]
    H = n - L
    w0 = w[0]
    w1 = w[1]
    srcs = np.empty(max(H, 1), dtype=np.int64)
    gn = np.empty(B)  # the old values of the block (Go may be Gn)
    for ch in chunks:
        for k in range(n + 1):
            part[ch, k] = 0.0
        for h in range(ch * rows // _CHUNKS, (ch + 1) * rows // _CHUNKS):
            if pc[h] > i:
                continue
            fi = Fi[h * B:(h + 1) * B]
            gn[:] = Gn[h * B:(h + 1) * B]
            go = Go[h * B:(h + 1) * B]
            au = 0.0
            a0 = 0.0
            a1 = 0.0
            for l in range(0, B, 4):
                g0 = gn[l]
                g1 = gn[l + 1]
                g2 = gn[l + 2]
                g3 = gn[l + 3]
                f0 = fi[l]
                f1 = fi[l + 1]
                f2 = fi[l + 2]
                go[l] = u * g0 + w0 * g1 + w1 * g2
                go[l + 1] = u * g1 + w1 * g3
                go[l + 2] = u * g2 + w0 * g3
                go[l + 3] = u * g3
                au += f0 * g0 + f1 * g1 + f2 * g2 + fi[l + 3] * g3
                a0 += f0 * g1 + f2 * g3
                a1 += f0 * g2 + f1 * g3
            part[ch, n] += au
            part[ch, 0] += a0
            part[ch, 1] += a1
            for k in range(2, L):
                wk = w[k]
                if wk == 0.0:
                    continue
                st = 1 << k
                acc = 0.0
                for base in range(0, B, 2 * st):
                    src = gn[base + st:base + 2 * st]  # views: the inner loop vectorizes
                    dst = go[base:base + st]
                    f = fi[base:base + st]
                    for j in range(st):
                        g = src[j]
                        dst[j] += wk * g
                        acc += f[j] * g
                part[ch, k] += acc
            # the high bits: the blocks with one more of them, four source blocks per pass
            ns = 0
            for b in range(H):
                if not (h >> b) & 1 and w[L + b] != 0.0:
                    srcs[ns] = b
                    ns += 1
            q = 0
            while q + 4 <= ns:
                b0 = srcs[q]
                b1 = srcs[q + 1]
                b2 = srcs[q + 2]
                b3 = srcs[q + 3]
                wa = w[L + b0]
                wb = w[L + b1]
                wc = w[L + b2]
                wd = w[L + b3]
                sa = Gn[(h | (1 << b0)) * B:(h | (1 << b0)) * B + B]
                sb = Gn[(h | (1 << b1)) * B:(h | (1 << b1)) * B + B]
                sc = Gn[(h | (1 << b2)) * B:(h | (1 << b2)) * B + B]
                sd = Gn[(h | (1 << b3)) * B:(h | (1 << b3)) * B + B]
                acc_a = 0.0
                acc_b = 0.0
                acc_c = 0.0
                acc_d = 0.0
                for l in range(B):
                    ga = sa[l]
                    gb = sb[l]
                    gc = sc[l]
                    gd = sd[l]
                    f = fi[l]
                    go[l] += (wa * ga + wb * gb) + (wc * gc + wd * gd)
                    acc_a += f * ga
                    acc_b += f * gb
                    acc_c += f * gc
                    acc_d += f * gd
                part[ch, L + b0] += acc_a
                part[ch, L + b1] += acc_b
                part[ch, L + b2] += acc_c
                part[ch, L + b3] += acc_d
                q += 4
            while q < ns:
                b0 = srcs[q]
                wa = w[L + b0]
                sa = Gn[(h | (1 << b0)) * B:(h | (1 << b0)) * B + B]
                acc_a = 0.0
                for l in range(B):
                    ga = sa[l]
                    go[l] += wa * ga
                    acc_a += fi[l] * ga
                part[ch, L + b0] += acc_a
                q += 1


def _final_sums(F, V, L, pc, n_items, part, chunks):  # pragma: no cover - compiled
    """Per-chunk ``part[ch, k] = sum_{S not containing k} F[S] V[S]``, ``part[ch, n] = sum F V``
    (``F = F_{n_items}``, read only on the blocks of at most ``n_items`` high bits)."""
    B = 1 << L
    rows = F.shape[0] >> L
    n = part.shape[1] - 1
    H = n - L
    for ch in chunks:
        for k in range(n + 1):
            part[ch, k] = 0.0
        for h in range(ch * rows // _CHUNKS, (ch + 1) * rows // _CHUNKS):
            if pc[h] > n_items:
                continue
            o = h * B
            tot = 0.0
            for l in range(B):
                tot += F[o + l] * V[o + l]
            part[ch, n] += tot
            for k in range(L):
                st = 1 << k
                acc = 0.0
                for base in range(0, B, 2 * st):
                    for j in range(st):
                        acc += F[o + base + j] * V[o + base + j]
                part[ch, k] += acc
            for b in range(H):
                if not (h >> b) & 1:
                    part[ch, L + b] += tot


_kernels: dict[str, Any] = {}
_PARALLEL_MIN_SLOTS = 18  # below 2^18 states a step is too short to share between threads


def _kernel(name: str):
    """The compiled kernel ``name`` (compiled on first use, cached on disk where possible).

    A kernel call handles the chunks ``c0, c0 + cstep, ...``; the threaded sweep runs one
    call per thread (the kernels release the GIL). Python threads rather than numba's
    threading layer: its OpenMP layer obeys ``OMP_NUM_THREADS`` (one thread here, for the
    BLAS), and a barrier per step in small sweeps costs more than the step.
    """
    if name not in _kernels:
        fn = {"forward": _forward_step, "backward": _backward_step, "final": _final_sums}[name]
        _kernels[name] = _numba.import_numba().njit(cache=True, nogil=True,
                                              fastmath={"reassoc", "contract"})(fn)
    return _kernels[name]


def _n_threads() -> int:
    try:
        return max(1, min(2, len(os.sched_getaffinity(0))))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, min(2, os.cpu_count() or 1))


def warm_up() -> None:
    """Compile (or load from the cache) the kernels now, e.g. before timing them."""
    W = np.full((2, 3), 0.5)
    for par in (False, True):
        fb_sweep(W, np.ones(2), np.ones(3), low_bits=1, parallel=par)


def _v_message(v: np.ndarray, V: np.ndarray) -> np.ndarray:
    """``V[S] = prod_{k not in S} v_k`` for every subset ``S`` of the slots, written into ``V``."""
    V[0] = 1.0
    size = 1
    for vk in v:  # bit k doubles the table: [V * v_k (k absent), V (k present)]
        V[size:2 * size] = V[:size]
        V[:size] *= vk
        size *= 2
    return V


# Freshly allocated messages cost page faults (several times the arithmetic of a forward
# step at 2^20 states): the messages of the last size swept are kept for the next call, up
# to _POOL_BYTES. Taking and returning arrays are single list operations (thread-safe).
_POOL_BYTES = 1 << 28
_pool: dict[int, list[np.ndarray]] = {}


def _take(N: int) -> np.ndarray:
    try:
        return _pool.get(N, []).pop()
    except IndexError:
        return np.empty(N)


def _give_back(arrays: list[np.ndarray], N: int) -> None:
    keep = _POOL_BYTES // (8 * N)
    if N not in _pool:
        _pool.clear()
        _pool[N] = []
    free = _pool.get(N, [])
    for a in arrays:
        if len(free) >= keep:
            break
        free.append(a)


def fb_sweep(W: np.ndarray, u: np.ndarray, v: np.ndarray, ops: Any = None, *,
             low_bits: int | None = None,
             store_all_bytes: int | None = None,
             parallel: bool | None = None) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """``(Z, W * dZ/dW, u * dZ/du, unmatched)`` of the recursions above (needs numba).

    ``W`` is ``(n_items, n)`` (``n`` slots, ``2^n`` states), ``u`` ``(n_items,)``, ``v``
    ``(n,)``, all non-negative and already checked. ``ops`` (an object with
    ``add(n_add=, n_mul=)``) receives the operation count of the plain sweep (the same
    count as the numpy sweeps record). ``low_bits`` and ``store_all_bytes`` override the
    block size and the memory limit for keeping every forward message (for tests);
    ``parallel`` chooses the threaded kernels (default: from ``_PARALLEL_MIN_SLOTS`` slots).
    """
    if not _HAVE_NUMBA:
        raise RuntimeError("projtrack.jpda._kernel.fb_sweep needs numba")
    W = np.ascontiguousarray(W, dtype=float)
    u = np.ascontiguousarray(u, dtype=float)
    v = np.ascontiguousarray(v, dtype=float)
    n_it, n = W.shape
    N = 1 << n
    if n < 2:  # the kernels handle two bits at a time: pad with slots nobody can take
        Z, gW, gu, un = fb_sweep(np.hstack([W, np.zeros((n_it, 2 - n))]), u,
                                 np.concatenate([v, np.ones(2 - n)]), None, low_bits=2,
                                 store_all_bytes=store_all_bytes, parallel=parallel)
        _count(ops, W, N)
        return Z, gW[:, :n], gu, un[:n]
    L = min(n, max(2, _LOW_BITS if low_bits is None else int(low_bits)))
    rows = N >> L
    limit = _STORE_ALL_BYTES if store_all_bytes is None else int(store_all_bytes)
    par = n >= _PARALLEL_MIN_SLOTS if parallel is None else bool(parallel)
    n_thr = _n_threads() if par else 1
    pool = ThreadPoolExecutor(max_workers=n_thr) if n_thr > 1 else None

    # chunks holding blocks, grouped by the number of high bits of their blocks that fall in
    # the chunk number: a block's sources with one more high bit are later in its own chunk
    # or in a chunk of the next group (what the in-place backward step needs)
    H = n - L
    first = [c * rows // _CHUNKS for c in range(_CHUNKS)]
    used = [c for c in range(_CHUNKS) if (c + 1) * rows // _CHUNKS > first[c]]
    level = {c: bin(first[c] >> max(0, H - 5)).count("1") for c in used}
    groups = [np.array([c for c in used if level[c] == lv], dtype=np.int64)
              for lv in sorted(set(level.values()))]
    every = np.concatenate(groups)

    def runner(kernel, by_level):
        def run(*args):
            if pool is None:
                kernel(*args, every)
                return
            for grp in (groups if by_level else [every]):
                jobs = [pool.submit(kernel, *args, grp[t::n_thr])
                        for t in range(n_thr) if len(grp) > t]
                for job in jobs:
                    job.result()
        return run

    try:
        return _sweep(W, u, v, ops, N, L, rows, limit,
                      runner(_kernel("forward"), False), runner(_kernel("backward"), True),
                      runner(_kernel("final"), False))
    finally:
        if pool is not None:
            pool.shutdown()


_BUFFER_COST = 1.4  # first use of a fresh message buffer (page faults), in full forward steps


def _schedule(n_it: int, cost: np.ndarray) -> list[int]:
    """The checkpoints ``[0, c_1, c_2, ...]`` of the forward messages kept for the backward sweep.

    Segment ``j`` (from ``c_j`` to ``c_{j+1}``) is recomputed while the checkpoints before it
    are still kept, so with ``P`` message buffers in all (one of them for the backward
    messages, ``F_0`` rebuilt rather than kept, two scratch buffers in the forward sweep) it
    may hold up to ``P - j`` messages (``P - 1`` for the first): long segments first, short
    ones last (``O(sqrt(2 n_items))`` buffers). ``cost[i]`` is the relative cost of forward
    step ``i`` (early steps touch few blocks): ``P`` minimizes the recomputation plus
    ``_BUFFER_COST`` per buffer.
    """
    best: tuple[float, list[int]] | None = None
    for P in range(3, n_it + 5):
        starts, total, j = [], 0, 0
        while total < n_it and j <= P - 2:
            starts.append(total)
            total += min(P - j - (j == 0), n_it - total)
            j += 1
        if total < n_it:
            continue
        ends = starts[1:] + [n_it]
        val = sum(float(cost[a:b - 1].sum()) for a, b in zip(starts, ends)) + _BUFFER_COST * P
        if best is None or val < best[0]:
            best = (val, starts)
        elif val > best[0] + 2 * _BUFFER_COST:
            break
    assert best is not None
    return best[1]


def _sweep(W, u, v, ops, N, L, rows, limit, fwd, bwd, fin):
    """The body of :func:`fb_sweep`: the two sweeps with the kernels ``fwd, bwd, fin``."""
    n_it, n = W.shape
    pc = np.zeros(rows, dtype=np.int64)
    for b in range(n - L):
        pc += (np.arange(rows) >> b) & 1
    if (n_it + 1) * N * 8 <= limit:
        starts = list(range(n_it))  # every forward message kept
    else:
        starts = _schedule(n_it, np.array([np.mean(pc <= i + 1) for i in range(n_it)]))
    kept = set(starts[1:])
    owned: list[np.ndarray] = []

    def new() -> np.ndarray:
        arr = _take(N)
        owned.append(arr)
        return arr

    B = 1 << L
    read0 = np.flatnonzero(pc <= 1)  # the blocks step 0 reads

    def delta(F: np.ndarray) -> np.ndarray:  # F_0, rebuilt when needed rather than kept
        F.reshape(rows, B)[read0] = 0.0
        F[0] = 1.0
        return F

    # forward sweep: F_a kept at the checkpoints a in starts (but 0); the others go
    # through two scratch buffers, which end with F_n and V
    checkpoints: dict[int, np.ndarray] = {}
    scr = [new(), new()]
    F = delta(scr[0])
    for i in range(n_it):
        if i + 1 in kept:
            out = checkpoints[i + 1] = new()
        else:
            out = scr[1] if F is scr[0] else scr[0]
        fwd(F, out, W[i], u[i], i, pc, L)
        F = out
    V = _v_message(v, scr[1] if F is scr[0] else scr[0])
    part = np.zeros((_CHUNKS, n + 1))  # the rows of chunks without blocks stay zero
    fin(F, V, L, pc, n_it, part)
    sums = part.sum(axis=0)
    Z, un = float(sums[n]), sums[:n].copy()
    gW = np.zeros((n_it, n))
    gu = np.zeros(n_it)
    free = [F]  # F_n is no longer needed
    del F, out, scr
    # backward sweep, segment by segment from the last; a segment's forward messages are
    # recomputed from its checkpoint into free buffers
    G = V  # the backward messages, updated in place
    for j in range(len(starts) - 1, -1, -1):
        a = starts[j]
        b = starts[j + 1] if j + 1 < len(starts) else n_it
        msgs = [checkpoints.pop(a) if a else delta(free.pop() if free else new())]
        for i in range(a, b - 1):
            nxt = free.pop() if free else new()
            fwd(msgs[-1], nxt, W[i], u[i], i, pc, L)
            msgs.append(nxt)
        for i in range(b - 1, a - 1, -1):
            Fi = msgs.pop()
            bwd(Fi, G, G, W[i], u[i], i, pc, L, part)
            sums = part.sum(axis=0)
            gW[i] = W[i] * sums[:n]
            gu[i] = u[i] * sums[n]
            free.append(Fi)
    del G, msgs, free
    _give_back(owned, N)
    _count(ops, W, N)
    return Z, gW, gu, un


def _count(ops: Any, W: np.ndarray, N: int) -> None:
    """The operation count of the plain forward and backward sweeps (as the numpy sweeps record it)."""
    if ops is not None:
        nz = np.count_nonzero(W, axis=1).astype(np.int64)
        half = N >> 1
        ops.add(n_add=int(np.sum(nz * half) + np.sum(N + 2 * nz * half)),
                n_mul=int(np.sum(N + nz * half) + np.sum(2 * N + 2 * nz * half)))

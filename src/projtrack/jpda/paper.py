"""The fast algorithm of the paper (Secs. III.B-D): MU words, in-situ vectors, eq. (6).

Measurements-used (MU) bit words (Table II), the length of the target vectors
(Table III), one in-situ stage of vector inner products (Sec. III.C, Fig. 4) and the
whole algorithm :func:`beta_paper`, optionally with stored intermediate vectors or with
the detector noise of the analog processor of Sec. IV.
"""

from __future__ import annotations

from functools import lru_cache
from math import comb
from typing import TYPE_CHECKING

import numpy as np

from projtrack._validation import as_array, as_bool, as_int, as_real, as_rng

from ._checks import _check_mvm, _fail_no_event, _normalize_columns

if TYPE_CHECKING:
    from .opcounts import OpCount

__all__ = ["mu_words", "vector_size", "vector_size_text_formula", "stage_update", "stage_expressions",
           "beta_paper"]


def _popcount(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.int64)
    return np.bitwise_count(x).astype(np.int64)


def mu_words(m: int, min_count: int = 0) -> np.ndarray:
    """Measurements-used (MU) bit words of Table II, in the paper's order.

    Bit ``j - 1`` of a word is set when measurement ``j`` is used (written
    ``j_m ... j_1`` as in Table II). Words are grouped by decreasing bit count and,
    within a group, ordered as in Table II (the set not using the highest
    measurements first), and only bit counts ``>= min_count`` are kept.

    Parameters
    ----------
    m : int
        Number of measurements (>= 0).
    min_count : int, default 0
        Smallest bit count kept.

    Returns
    -------
    numpy.ndarray of int
        The words, in the paper's order.
    """
    m = as_int(m, "m", minimum=0, maximum=30)  # MU words are int64 bit words
    min_count = as_int(min_count, "min_count", minimum=0)
    return _mu_words_cached(m, min_count).copy()


@lru_cache(maxsize=256)
def _mu_words_cached(m: int, min_count: int) -> np.ndarray:
    w = np.arange(2**m, dtype=np.int64)
    pc = _popcount(w)
    # Table II order: decreasing bit count, then increasing word (0111, 1011, 1101, 1110)
    order = np.lexsort((w, -pc))
    out = w[order][pc[order] >= min_count]
    out.flags.writeable = False
    return out


def _check_vector_args(m: object, T: object) -> tuple[int, int]:
    m = as_int(m, "m", minimum=0, maximum=30)  # MU words are int64 bit words
    T = as_int(T, "T", minimum=1)  # the vectors belong to targets
    return m, T


def vector_size(m: int, T: int) -> int:
    """Length of the target vectors of the fast algorithm (Table III).

    ``sum_{j = max(0, m - T + 1)}^{m} C(m, j)``: the words whose bit count is at
    least ``m - T + 1`` (the other ``T - 1`` targets can use at most ``T - 1``
    measurements, and eq. (6) needs the words of bit counts ``m`` and ``m - 1``).
    The lower limit ``max(0, .)`` reproduces Table III; the text prints
    ``max(1, .)`` (see :func:`vector_size_text_formula`), which drops the empty word
    and disagrees with the table whenever ``m < T``.

    Parameters
    ----------
    m : int
        Number of measurements.
    T : int
        Number of targets.

    Returns
    -------
    int
    """
    m, T = _check_vector_args(m, T)
    return sum(comb(m, j) for j in range(max(0, m - T + 1), m + 1))


def vector_size_text_formula(m: int, T: int) -> int:
    r"""The vector length as printed in Section III: :math:`\sum_{j=\max(1, m-T+1)}^{m}
    \binom{m}{j}`.

    Parameters
    ----------
    m : int
        Number of measurements.
    T : int
        Number of targets.

    Returns
    -------
    int
    """
    m, T = _check_vector_args(m, T)
    return sum(comb(m, j) for j in range(max(1, m - T + 1), m + 1))


def stage_update(vec: np.ndarray, words: np.ndarray, prev_words: np.ndarray,
                 column: np.ndarray, ops: OpCount | None = None) -> np.ndarray:
    """One in-situ stage of Section III.C: the vector :math:`T - 1` from the vector
    :math:`T`.

    ``new[w] = p_0 * old[w] + sum_{j in w} p_j * old[w XOR bit_j]`` for every MU word
    ``w`` of ``words``: the XOR of ``w`` with a word of one fewer bit that leaves a
    single 1 selects the old element and the MVM entry ``p_j`` that multiplies it
    (a vector inner product per element, Fig. 4). ``vec`` is indexed like
    ``prev_words``; ``column`` is the MVM column ``(p_0, p_1, ..., p_m)``.

    Parameters
    ----------
    vec : numpy.ndarray
        The old vector, indexed like ``prev_words``.
    words : numpy.ndarray of int
        MU words of the new vector.
    prev_words : numpy.ndarray of int
        MU words of the old vector.
    column : numpy.ndarray
        The MVM column ``(p_0, p_1, ..., p_m)`` of the target.
    ops : OpCount, optional
        Operation counter.

    Returns
    -------
    numpy.ndarray, shape (len(words),)

    Raises
    ------
    ValueError
        If ``vec`` and ``prev_words`` differ in length, ``column`` is empty, a word is
        not an ``m``-bit word (``0 <= w < 2^m``), ``prev_words`` repeats a word, or a
        predecessor word (``w`` itself or ``w XOR bit_j`` for a set bit ``j``) of some
        word of ``words`` is missing from ``prev_words``.
    """
    column = as_array(column, "column", ndim=1)
    if len(column) < 1:
        raise ValueError("column must hold (p_0, p_1, ..., p_m): at least p_0")
    m = len(column) - 1
    if m > 30:
        raise ValueError(f"column has m = {m} measurement entries; at most 30 are supported")
    words = _check_words(words, "words", m)
    prev_words = _check_words(prev_words, "prev_words", m)
    if len(np.unique(prev_words)) != len(prev_words):
        raise ValueError("prev_words must not repeat a word")
    vec = as_array(vec, "vec", ndim=1)
    if len(vec) != len(prev_words):
        raise ValueError(f"vec must have one element per word of prev_words "
                         f"({len(prev_words)}), got {len(vec)}")
    have = np.zeros(2**m, dtype=bool)
    have[prev_words] = True
    need = [words] + [words[(words >> j) & 1 == 1] ^ (1 << j) for j in range(m)]
    missing = np.unique(np.concatenate(need)[~have[np.concatenate(need)]])
    if missing.size:
        shown = ", ".join(f"{x:0{m}b}" if m else "(empty)" for x in missing[:5].tolist())
        raise ValueError(f"prev_words lacks {missing.size} predecessor word(s) the new "
                         f"words need (e.g. {shown})")
    return _stage_update(vec, words, prev_words, column, ops)


def _check_words(words: object, name: str, m: int) -> np.ndarray:
    a = np.asarray(words)
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of MU words, got shape {a.shape}")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise TypeError(f"{name} must hold integer MU words, got dtype {a.dtype}")
    a = a.astype(np.int64)
    if a.size and (a.min() < 0 or a.max() >= 2**m):
        raise ValueError(f"{name} must hold {m}-bit words in [0, {2**m}) "
                         f"(m = len(column) - 1), got values in [{a.min()}, {a.max()}]")
    return a


def _stage_update(vec: np.ndarray, words: np.ndarray, prev_words: np.ndarray,
                  column: np.ndarray, ops: OpCount | None = None) -> np.ndarray:
    """:func:`stage_update` without input checks (the inner loop of :func:`beta_paper`)."""
    m = len(column) - 1
    pos = np.full(2**m, -1, dtype=np.int64)
    pos[prev_words] = np.arange(len(prev_words))
    new = column[0] * vec[pos[words]]
    n_terms = len(words)
    for j in range(m):
        bit = 1 << j
        sel = (words & bit) != 0
        idx = pos[words[sel] ^ bit]
        new[sel] += column[j + 1] * vec[idx]
        n_terms += int(sel.sum())
    if ops is not None:
        ops.add(n_add=n_terms - len(words), n_mul=n_terms)
    return new


def stage_expressions(m: int, T: int, new: str = "e", old: str = "f") -> list[tuple[int, str, str]]:
    """Table II regenerated: for each MU word of the vector :math:`e`, the VIP expression.

    Returns ``(word, binary, expression)`` rows in the paper's order, e.g. for
    ``m = 4`` the word ``1111`` gives ``e0(f1111) + e4(f0111) + e3(f1011) + ...``:
    the old-vector elements are named by their own MU words, as the XOR rule of
    Sec. III.C selects them.

    Parameters
    ----------
    m : int
        Number of measurements.
    T : int
        Number of targets.
    new, old : str, default "e" and "f"
        Names of the new and old vectors in the expressions.

    Returns
    -------
    list of (int, str, str)
        ``(word, binary, expression)`` rows.
    """
    m = as_int(m, "m", minimum=0)
    T = as_int(T, "T", minimum=0)
    rows = []
    for w in mu_words(m, max(0, m - T + 1)).tolist():
        terms = [f"{new}0({old}{w:0{m}b})"]
        for j in range(m, 0, -1):
            if (w >> (j - 1)) & 1:
                terms.append(f"{new}{j}({old}{w ^ (1 << (j - 1)):0{m}b})")
        rows.append((w, f"{w:0{m}b}", " + ".join(terms)))
    return rows


def beta_paper(mvm: object, *, ops: OpCount | None = None,
               store_intermediates: bool = False, vip_noise: float = 0.0,
               rng: np.random.Generator | None = None) -> np.ndarray:
    """Association probabilities by the paper's fast algorithm (Sections III.B-D, Figure
    4).

    For target ``t``, columns 1 and ``t`` of the MVM are interchanged; the vector of
    the last target (``T``, Sec. III.B: ``f[w] = f_0 + sum_{j in w} f_j`` over MU
    words ``w`` of bit count ``>= m - T + 1``) is formed, then targets ``T - 1`` down
    to 2 are folded in by :func:`stage_update` (Sec. III.C; only the bit counts still
    needed are kept, so the vector shrinks towards bit counts ``m`` and ``m - 1``),
    and eq. (6) ``beta_{.,t} = A b'`` with ``A = diag(a_0, ..., a_m)`` and
    ``b' = (b_{1..m}, b_{without m}, ..., b_{without 1})`` gives the unnormalized
    column. Columns are then normalized (Sec. III.D).

    Complexity: ``O(T^2 m 2^m)`` without stored intermediates (``T`` chains of
    ``T - 2`` stages over at most ``2^m`` words, ``|w| + 1`` products each).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
    ops : OpCount, optional
        Counts additions and multiplications as executed (Table V when
        ``store_intermediates`` is False).
    store_intermediates : bool
        Keep the vectors of target 1's chain and reuse their common suffix in the
        chains of the other targets: one storage scheme of this package for the
        remark after Table VI ("when intermediate vectors are stored"), which does
        not say how the paper stored them.
    vip_noise : float
        Models the analog processor of Sec. IV: every vector produced by a stage of
        inner products gets additive Gaussian noise of standard deviation
        ``vip_noise`` times the vector's largest element (detector noise relative
        to full scale), clipped at 0 (intensities). 0 (default) is exact arithmetic.
    rng : numpy.random.Generator, optional
        Required when ``vip_noise > 0``.
    """
    store_intermediates = as_bool(store_intermediates, "store_intermediates")
    w = _check_mvm(mvm)
    m1, T = w.shape
    m = m1 - 1
    vip_noise = as_real(vip_noise, "vip_noise", 0.0)
    if vip_noise > 0:
        as_rng(rng, "rng (required when vip_noise > 0)")
    if m > 22:
        raise ValueError(f"beta_paper needs 2^m words; m = {m} is too large (use beta)")
    if T == 0:
        return np.zeros((m1, 0))
    wn = _normalize_columns(w)
    full = (1 << m) - 1
    out = np.zeros((m1, T))
    cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for t in range(T):
        cols = list(range(T))
        cols[0], cols[t] = cols[t], cols[0]
        if T == 1:
            vec_words = np.array([full, *[full ^ (1 << j) for j in range(m)]], dtype=np.int64)
            vec = np.ones(len(vec_words))
        else:
            p = T - 1
            if store_intermediates and t > 0 and p > t:
                # the suffix of the chain (positions > t) is the same as target 1's
                while p > t + 1 and p - 1 in cache:
                    p -= 1
                vec_words, vec = cache[p]
            else:
                vec_words = _mu_words_cached(m, max(0, m - p))
                col = wn[:, cols[p]]
                vec = np.full(len(vec_words), col[0])
                for j in range(m):
                    vec += col[j + 1] * ((vec_words >> j) & 1)
                if ops is not None:
                    ops.add(n_add=int(_popcount(vec_words).sum()))
                if store_intermediates and t == 0:
                    cache[p] = (vec_words, vec)
            for q in range(p - 1, 0, -1):
                new_words = _mu_words_cached(m, max(0, m - q))
                vec = _stage_update(vec, new_words, vec_words, wn[:, cols[q]], ops)
                if vip_noise > 0:
                    vec = vec + rng.normal(0.0, vip_noise * np.abs(vec).max(), len(vec))
                    np.maximum(vec, 0.0, out=vec)  # detected intensities are >= 0
                vec_words = new_words
                if store_intermediates and t == 0:
                    cache[q] = (vec_words, vec)
        pos = {int(x): i for i, x in enumerate(vec_words.tolist())}
        b_prime = np.array([vec[pos[full]]] + [vec[pos[full ^ (1 << j)]] for j in range(m)])
        out[:, t] = wn[:, cols[0]] * b_prime  # eq. (6)
        if ops is not None:
            ops.add(n_mul=m1)
    Z = out.sum(axis=0)
    if not np.all(Z > 0):
        _fail_no_event(w)
    return out / Z

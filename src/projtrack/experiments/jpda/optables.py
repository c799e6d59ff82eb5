"""Operation-count tables of the JPDA chapter (Tables IV-VI): instrumented counts and the paper's.

:func:`instrumented_counts` counts the conventional enumeration and the paper's fast
algorithm (with and without stored intermediate vectors) on all-ones MVMs;
:func:`count_grid` lays a count dictionary out as a table; :func:`parse_count_table`
and :func:`parse_ratio_table` read the paper's printed tables (transcribed as text),
:func:`half_up` rounds a ratio as the paper does, and :func:`vector_growth` tabulates
the vector length and the fast algorithm's cost along ``m = T``.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from math import floor

import numpy as np
import pandas as pd

from projtrack._validation import as_int
from projtrack.jpda import (OpCount, beta_enumerated, beta_paper, count_feasible_events,
                            fast_op_count, vector_size)

__all__ = ["all_ones_mvm", "instrumented_counts", "count_grid", "parse_count_table",
           "parse_ratio_table", "half_up", "vector_growth"]

Counts = dict[tuple[int, int], tuple[int, int]]


def all_ones_mvm(m: int, T: int) -> np.ndarray:
    """The MVM of a fully gated problem with unit likelihoods: row 0 = 0.5, the rest 1."""
    m = as_int(m, "m", minimum=0)
    T = as_int(T, "T", minimum=1)
    return np.vstack([np.full((1, T), 0.5), np.ones((m, T))])


def _sizes(sizes: Sequence[int]) -> list[int]:
    out = [as_int(s, "sizes[]", minimum=1) for s in sizes]
    if not out:
        raise ValueError("sizes must not be empty")
    return out


def instrumented_counts(sizes: Sequence[int]) -> tuple[Counts, Counts, Counts]:
    """(additions, multiplications) of the three counted methods for every ``m, T`` in ``sizes``.

    Returns the dictionaries ``conv`` (:func:`projtrack.jpda.beta_enumerated`, Table IV),
    ``fast`` (:func:`projtrack.jpda.beta_paper`, Table V) and ``stored`` (``beta_paper``
    with ``store_intermediates=True``), keyed by ``(m, T)``.
    """
    sizes = _sizes(sizes)
    conv, fast, stored = {}, {}, {}
    for m in sizes:
        for T in sizes:
            ops = OpCount()
            beta_enumerated(all_ones_mvm(m, T), ops=ops)
            conv[m, T] = (ops.additions, ops.multiplications)
            ops = OpCount()
            beta_paper(all_ones_mvm(m, T), ops=ops)
            fast[m, T] = (ops.additions, ops.multiplications)
            ops = OpCount()
            beta_paper(all_ones_mvm(m, T), ops=ops, store_intermediates=True)
            stored[m, T] = (ops.additions, ops.multiplications)
    return conv, fast, stored


def count_grid(d: dict, sizes: Sequence[int], fmt: str = "{}/{}") -> pd.DataFrame:
    """An ``m x T`` table of ``fmt.format(*d[m, T])`` (rows ``m``, columns ``T``)."""
    sizes = _sizes(sizes)
    missing = [(m, T) for m in sizes for T in sizes if (m, T) not in d]
    if missing:
        raise ValueError(f"d has no entry for (m, T) = {missing[:3]}")
    return pd.DataFrame([[fmt.format(*d[m, T]) for T in sizes] for m in sizes],
                        index=pd.Index(sizes, name="m"), columns=pd.Index(sizes, name="T"))


def parse_count_table(txt: str, sizes: Sequence[int]) -> Counts:
    """A printed ``additions/multiplications`` table (one row per ``m``) as a dictionary."""
    if not isinstance(txt, str):
        raise TypeError(f"txt must be a str, got {type(txt).__name__}")
    sizes = _sizes(sizes)
    cells = [c.split("/") for line in txt.splitlines() for c in line.split()]
    if len(cells) != len(sizes) ** 2 or any(len(c) != 2 for c in cells):
        raise ValueError(f"txt must hold {len(sizes) ** 2} cells 'a/b', got {len(cells)}")
    vals = iter(cells)
    return {(m, T): tuple(int(x) for x in next(vals)) for m in sizes for T in sizes}


def parse_ratio_table(txt: str, sizes: Sequence[int]) -> dict[tuple[int, int], tuple[float, float]]:
    """Table VI as printed, whose decimal points the text conversion turned into spaces.

    A cell ``a.b/c.d`` reads ``a b/c d``: three tokens ``a``, ``b/c``, ``d``.
    """
    if not isinstance(txt, str):
        raise TypeError(f"txt must be a str, got {type(txt).__name__}")
    sizes = _sizes(sizes)
    tok = txt.split()
    if len(tok) != 3 * len(sizes) ** 2:
        raise ValueError(f"txt must hold {3 * len(sizes) ** 2} tokens, got {len(tok)}")
    out = {}
    it = iter(tok)
    for m in sizes:
        for T in sizes:
            a_int, mid, b_frac = next(it), next(it), next(it)
            a_frac, b_int = mid.split("/")
            out[m, T] = (float(f"{a_int}.{a_frac}"), float(f"{b_int}.{b_frac}"))
    return out


def half_up(num: int, den: int) -> float:
    """num / den rounded half-up to one decimal, exactly (the paper prints 300/240 = 1.25 as 1.3)."""
    num = as_int(num, "num")
    den = as_int(den, "den", minimum=1)
    return floor(Fraction(num, den) * 10 + Fraction(1, 2)) / 10


def vector_growth(sizes: Sequence[int]) -> pd.DataFrame:
    """Vector length (Table III's formula) and fast-algorithm cost along ``m = T = n``.

    One row per ``n`` of ``sizes`` (at most 22): the vector length, ``2^m``, the additions
    plus multiplications of :func:`projtrack.jpda.fast_op_count`, that cost over
    ``T^2 m 2^m`` (rounded to 3 decimals) and the length over the eq. (1) event count.
    """
    sizes = _sizes(sizes)
    if max(sizes) > 22:
        raise ValueError(f"sizes must be <= 22 (the fast algorithm needs 2^m words), got {max(sizes)}")
    growth = []
    for n in sizes:
        f = fast_op_count(n, n)
        ops_n = f.additions + f.multiplications
        growth.append({"m = T": n, "vector length": vector_size(n, n), "2^m": 2**n,
                       "fast algorithm adds + mults": ops_n,
                       "ops / (T^2 m 2^m)": round(ops_n / (n * n * n * 2**n), 3),
                       "length / eq. (1)": vector_size(n, n) / count_feasible_events(n, n)})
    return pd.DataFrame(growth).set_index("m = T")

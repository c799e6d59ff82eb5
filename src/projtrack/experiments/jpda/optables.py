"""Operation-count tables of the JPDA chapter (Tables IV-VI): instrumented counts and the paper's.

:func:`instrumented_counts` counts the conventional enumeration and the paper's fast
algorithm (with and without stored intermediate vectors) on all-ones MVMs;
:func:`count_grid` lays a count dictionary out as a table; :func:`parse_count_table`
and :func:`parse_ratio_table` read the paper's printed tables (transcribed as text),
:func:`half_up` rounds a ratio as the paper does, and :func:`vector_growth` tabulates
the vector length and the fast algorithm's cost along ``m = T``. :func:`beta_in_situ`
runs the fast algorithm with one working vector, counting the vectors it forms (Sec. III:
"only T^2 vectors ... stored in situ"), and :func:`in_situ_study` runs it on random MVMs (:func:`in_situ_summary` per ``T``);
:func:`savings`, :func:`savings_paths` and :func:`savings_orders` give the savings factor
past Table VI and how fast it grows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from math import floor

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_choice, as_int
from projtrack.jpda import (OpCount, beta_enumerated, beta_paper, conventional_op_count,
                            count_feasible_events, fast_op_count, mu_words, vector_size)
from projtrack.scenes.jpda import random_mvm

__all__ = ["all_ones_mvm", "instrumented_counts", "count_grid", "parse_count_table",
           "parse_ratio_table", "half_up", "vector_growth", "InSituRun", "beta_in_situ",
           "in_situ_study", "in_situ_summary", "savings", "savings_paths", "savings_orders"]

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


# -- Sec. III: T^2 vectors, stored in situ (JPDA-S3) ------------------------------------------

@dataclass(frozen=True)
class InSituRun:
    """What :func:`beta_in_situ` computed and how.

    Attributes
    ----------
    beta : ndarray, shape (m + 1, T)
        The association probabilities (columns sum to 1).
    vectors : int
        Probability vectors formed in all: per target, the vector of the last target, one
        vector per vector-inner-product stage and the vector ``A b'`` of eq. (6).
    vectors_per_target : tuple of int
        The same count for each target column.
    buffer_length : int
        Elements of the one working vector every target vector is written into.
    ops : OpCount
        Additions and multiplications executed (the convention of
        :class:`projtrack.jpda.OpCount`).
    column_sums : ndarray, shape (T,)
        The sums of the unnormalized columns ``A b'`` of eq. (6). Sec. III.D normalizes every
        column by the sum of any one of them, which is right when they are all equal (to the
        sum of the probabilities of all feasible events).
    """

    beta: np.ndarray
    vectors: int
    vectors_per_target: tuple[int, ...]
    buffer_length: int
    ops: OpCount
    column_sums: np.ndarray


def _as_mvm(mvm: object) -> np.ndarray:
    w = as_array(mvm, "mvm", ndim=2)
    if w.shape[0] < 1 or w.shape[1] < 1:
        raise ValueError(f"mvm must have a row 0 and at least one target column, got shape {w.shape}")
    if np.any(w < 0):
        raise ValueError("mvm entries must be >= 0 (probabilities and densities)")
    if w.shape[0] - 1 > 16:
        raise ValueError(f"mvm has m = {w.shape[0] - 1} measurements; beta_in_situ runs element "
                         "by element and takes at most 16")
    return w


def beta_in_situ(mvm: object, *, order: str = "paper", words: str = "needed",
                 length: str = "table") -> InSituRun:
    """The paper's fast algorithm (Secs. III.B-D) with a single working vector, instrumented.

    Every target vector (``T``, ``T - 1``, ..., ``2``) is written over the previous one in
    one buffer of the Table III length (:func:`projtrack.jpda.vector_size`), element by
    element, as the text says ("we need to retain only the latest vector"). An element of
    the new vector reads the old element of its own MU word and of the words with one bit
    fewer (the XOR rule of Sec. III.C), so overwriting is safe when the words are visited by
    decreasing bit count, the order of Table II (``order="paper"``); ``order="reversed"``
    (increasing bit count) overwrites elements that are still to be read, and gives wrong
    beta: the check that in-situ storage is a real constraint.

    ``words="needed"`` computes at each stage only the MU words the later stages still read
    (as :func:`projtrack.jpda.beta_paper` does); ``words="all"`` recomputes the whole
    Table III vector at every stage (terms whose word lies outside the vector are skipped;
    the words this leaves wrong are never read by eq. (6)). The two differ only in the
    operation count (a reading of Table V).

    ``length="table"`` sizes the working vector as Table III does (words of at least
    ``max(0, m - T + 1)`` bits, :func:`projtrack.jpda.vector_size`); ``length="text"`` as the
    sentence of Sec. III prints it, from ``max(1, m - T + 1)`` bits
    (:func:`projtrack.jpda.vector_size_text_formula`): the buffer then has no element for
    the empty word, terms that read it are lost, and beta is wrong whenever ``m < T`` (the
    check that the text's length cannot hold the algorithm's vectors).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        A modified validation matrix (nonnegative; ``m <= 16``).
    order : {"paper", "reversed"}
    words : {"needed", "all"}
    length : {"table", "text"}

    Returns
    -------
    InSituRun

    Raises
    ------
    ValueError
        For a bad MVM or option, or when no feasible event has positive probability.
    """
    w = _as_mvm(mvm)
    order = as_choice(order, "order", ("paper", "reversed"))
    words = as_choice(words, "words", ("needed", "all"))
    length = as_choice(length, "length", ("table", "text"))
    m1, T = w.shape
    m = m1 - 1
    full = (1 << m) - 1
    lowest = max(0 if length == "table" else 1, m - T + 1)
    vec_words = mu_words(m, lowest).tolist()  # Table II order, Table III (or the text's) length
    pos = {x: i for i, x in enumerate(vec_words)}
    bits = {x: [j for j in range(m) if (x >> j) & 1] for x in vec_words}
    buf = [0.0] * len(vec_words)  # the one working vector
    ops = OpCount()
    out = np.zeros((m1, T))
    per_target = []
    for t in range(T):
        cols = list(range(T))
        cols[0], cols[t] = cols[t], cols[0]
        formed = 0
        if T == 1:  # no other target: b' is all ones
            b_prime = [1.0] * m1
        else:
            col = w[:, cols[T - 1]].tolist()  # Sec. III.B: f[w] = f0 + sum_{j in w} f_j
            for x in vec_words:
                s = col[0]
                for j in bits[x]:
                    s += col[j + 1]
                buf[pos[x]] = s
                ops.add(n_add=len(bits[x]))
            formed += 1
            for q in range(T - 2, 0, -1):  # Sec. III.C: fold in targets T - 1, ..., 2
                col = w[:, cols[q]].tolist()
                low = m - q if words == "needed" else 0
                visit = [x for x in vec_words if len(bits[x]) >= low]
                if order == "reversed":
                    visit = visit[::-1]
                for x in visit:
                    s, n = col[0] * buf[pos[x]], 1
                    for j in bits[x]:
                        y = x ^ (1 << j)
                        if y in pos:
                            s += col[j + 1] * buf[pos[y]]
                            n += 1
                    buf[pos[x]] = s  # in situ: overwrites the old element of the same word
                    ops.add(n_add=n - 1, n_mul=n)
                formed += 1
            # a word the buffer does not hold (the text's length, m = 1) has no value: 0
            b_prime = [buf[pos[x]] if x in pos else 0.0
                       for x in [full] + [full ^ (1 << j) for j in range(m)]]
        out[:, t] = w[:, cols[0]] * np.array(b_prime)  # eq. (6): A b'
        ops.add(n_mul=m1)
        per_target.append(formed + 1)
    Z = out.sum(axis=0)
    if not np.all(Z > 0):
        raise ValueError("no feasible joint event of mvm has positive probability")
    return InSituRun(out / Z, sum(per_target), tuple(per_target), len(buf), ops, Z)


def in_situ_study(sizes: Sequence[int], seed: int) -> pd.DataFrame:
    """:func:`beta_in_situ` on one random fully gated MVM per ``m, T`` in ``sizes``.

    The MVMs are :func:`projtrack.scenes.jpda.random_mvm` draws from ``default_rng(seed)``,
    ``m`` outer, ``T`` inner. One row per ``(m, T)``: the vectors formed (and ``T^2``), the
    working-vector length (and Table III's), whether beta equals the enumeration
    (:func:`projtrack.jpda.beta_enumerated`) to ``1e-12``, whether the operation count
    equals :func:`projtrack.jpda.beta_paper`'s (Table V), and the largest beta errors with
    the words visited in the reversed order and with a working vector of the text's length
    (``length="text"``).
    """
    sizes = _sizes(sizes)
    seed = as_int(seed, "seed", minimum=0)
    rng = np.random.default_rng(seed)
    rows = []
    for m in sizes:
        for T in sizes:
            w = random_mvm(rng, m, T)
            run = beta_in_situ(w)
            ref = beta_enumerated(w)
            paper_ops = OpCount()
            beta_paper(w, ops=paper_ops)
            rows.append({"m": m, "T": T, "vectors formed": run.vectors, "T^2": T * T,
                         "working vector": run.buffer_length, "Table III": vector_size(m, T),
                         "beta exact": bool(np.abs(run.beta - ref).max() < 1e-12),
                         "ops = Table V count": (run.ops.additions, run.ops.multiplications)
                         == (paper_ops.additions, paper_ops.multiplications),
                         "reversed order: max |beta error|":
                             float(np.abs(beta_in_situ(w, order="reversed").beta - ref).max()),
                         "text's length: max |beta error|":
                             float(np.abs(beta_in_situ(w, length="text").beta - ref).max())})
    return pd.DataFrame(rows)


# -- "the improvement factor increases significantly as m and T increase" -----------------------

def savings(m: int, T: int) -> tuple[float, float]:
    """Conventional / fast (additions, multiplications) on an all-ones ``m x T`` MVM.

    The conventional count is the closed form :func:`projtrack.jpda.conventional_op_count`
    (equal to the instrumented enumeration, Table IV), the fast one
    :func:`projtrack.jpda.fast_op_count` (Table V). ``m <= 22``.
    """
    m = as_int(m, "m", minimum=1, maximum=22)
    T = as_int(T, "T", minimum=1)
    c, f = conventional_op_count(m, T), fast_op_count(m, T)
    return c.additions / f.additions, c.multiplications / f.multiplications


def savings_paths(ns: Sequence[int], fixed: int = 3, diagonal_max: int = 12) -> pd.DataFrame:
    """The savings factor (Table VI) along three paths: ``m = T = n``, ``T = fixed`` with
    ``m = n``, and ``m = fixed`` with ``T = n``.

    One row per ``n`` of ``ns``; each cell is ``"additions/multiplications"`` rounded
    half-up to one decimal as Table VI prints them (:func:`half_up`, exact), or "—" on the
    diagonal past ``diagonal_max`` (the fast algorithm's count there needs ``2^n`` words per
    stage).
    """
    ns = _sizes(ns)
    fixed = as_int(fixed, "fixed", minimum=1)
    diagonal_max = as_int(diagonal_max, "diagonal_max", minimum=1, maximum=16)

    def cell(m: int, T: int) -> str:
        c, f = conventional_op_count(m, T), fast_op_count(m, T)
        return (f"{half_up(c.additions, f.additions):.1f}/"
                f"{half_up(c.multiplications, f.multiplications):.1f}")

    return pd.DataFrame([{"n": n, "m = T = n": cell(n, n) if n <= diagonal_max else "—",
                          f"T = {fixed}, m = n": cell(n, fixed), f"m = {fixed}, T = n": cell(fixed, n)}
                         for n in ns])


def savings_orders(ns: Sequence[int], fixed: int = 3, diagonal_max: int = 12) -> pd.DataFrame:
    """How fast the savings factor grows along the three paths of :func:`savings_paths`.

    One row per path (``m = T = n`` up to ``diagonal_max``, ``m = fixed`` with ``T = n``,
    ``T = fixed`` with ``m = n``): the sizes spanned, the additions and multiplications
    savings at the first and last size (rounded half-up, as Table VI), and the local
    exponent ``d ln(saving) / d ln(n)`` between the last two sizes of the path (1 for
    linear growth, 2 for quadratic, near 0 when the saving levels off). ``ns`` needs at
    least two sizes at most ``diagonal_max``.
    """
    ns = sorted(set(_sizes(ns)))
    fixed = as_int(fixed, "fixed", minimum=1)
    diagonal_max = as_int(diagonal_max, "diagonal_max", minimum=1, maximum=16)
    diag = [n for n in ns if n <= diagonal_max]
    if len(diag) < 2:
        raise ValueError(f"ns needs at least two sizes <= diagonal_max = {diagonal_max}")
    rows = []
    for name, sizes, mt in (("m = T = n", diag, lambda n: (n, n)),
                            (f"m = {fixed}, T = n", ns, lambda n: (fixed, n)),
                            (f"T = {fixed}, m = n", ns, lambda n: (n, fixed))):
        (c0, f0), (c1, f1), (cp, fp) = ((conventional_op_count(*mt(n)), fast_op_count(*mt(n)))
                                        for n in (sizes[0], sizes[-1], sizes[-2]))
        step = np.log(sizes[-1] / sizes[-2])
        rows.append({"path": name, "n": f"{sizes[0]} to {sizes[-1]}",
                     "additions saved": f"{half_up(c0.additions, f0.additions):.1f} to "
                                        f"{half_up(c1.additions, f1.additions):.1f}",
                     "multiplications saved": f"{half_up(c0.multiplications, f0.multiplications):.1f} to "
                                              f"{half_up(c1.multiplications, f1.multiplications):.1f}",
                     "exponent (additions)": float(np.log((c1.additions / f1.additions)
                                                          / (cp.additions / fp.additions)) / step),
                     "exponent (multiplications)": float(np.log((c1.multiplications / f1.multiplications)
                                                                / (cp.multiplications / fp.multiplications)) / step)})
    return pd.DataFrame(rows)


def in_situ_summary(study: pd.DataFrame) -> pd.DataFrame:
    """One row per ``T`` of an :func:`in_situ_study` table, over all its ``m``.

    Columns: ``T``; ``vectors formed`` (the count when every ``m`` gives the same, else -1);
    ``working vector`` (its length for each ``m``, as text); ``one vector, exact``
    (every run formed its vectors in a working vector of the Table III length, with beta
    equal to the enumeration and Table V's operation count); the largest beta error of
    the reversed visiting order; and the largest beta error with the working vector of the
    text's length over the runs with ``m < T`` (NaN when there is none: for ``m >= T`` the
    two lengths are equal).
    """
    need = {"m", "T", "vectors formed", "T^2", "working vector", "Table III", "beta exact",
            "ops = Table V count", "reversed order: max |beta error|", "text's length: max |beta error|"}
    if not isinstance(study, pd.DataFrame) or not need <= set(study.columns) or study.empty:
        raise ValueError("study must be a non-empty in_situ_study table")
    rows = []
    for T, g in study.groupby("T", sort=True):
        counts = set(g["vectors formed"])
        short = g[g["m"] < T]
        rows.append({"T": int(T), "vectors formed": int(counts.pop()) if len(counts) == 1 else -1,
                     "working vector, m = " + f"{g['m'].min()}..{g['m'].max()}":
                         ", ".join(str(x) for x in g["working vector"]),
                     "one vector, exact": bool((g["working vector"] == g["Table III"]).all()
                                               and g["beta exact"].all() and g["ops = Table V count"].all()),
                     "reversed order: largest error": float(g["reversed order: max |beta error|"].max()),
                     "text's length: largest error (m < T)":
                         float(short["text's length: max |beta error|"].max()) if len(short) else np.nan})
    return pd.DataFrame(rows)

"""Viterbi with a sparse transition matrix (projtrack.dma) versus hmmlearn's dense Viterbi.

The DMA motion model (eq. (13) of Marques et al. 2002) is sparse: a prototype can only
move to a few nearby prototypes. This script decodes N = 10,000 steps over S = 1,200
prototypes arranged on a ring, each with 5 successors (nnz = 6,000), with

* ``projtrack.dma.viterbi`` on the sparse matrix (O(N nnz));
* ``projtrack.dma.viterbi`` on the dense matrix (O(N S^2), numpy);
* hmmlearn 0.3.3's compiled dense Viterbi (``hmmlearn._hmmc.viterbi``, O(N S^2)).

The dense implementations are O(N S^2): to stay within a minute they are timed on a
prefix of ``N_DENSE`` steps and their time is scaled by ``N / N_DENSE`` (Viterbi's cost is
linear in N; the scaling is stated in the table). hmmlearn's kernel takes the start and
transition *probabilities* (it takes their logs itself) and the log emission matrix.

Run: ``python benchmarks/bench_dma.py``. Prints the best of a few repeats and ratios.
"""

from __future__ import annotations


import numpy as np
import scipy.sparse as sp

from projtrack import dma
from _timing import best_of

N, S, K = 10_000, 1_200, 5
N_DENSE = 400


def main() -> None:
    rng = np.random.default_rng(0)
    rows = np.repeat(np.arange(S), K)
    cols = (rows + np.tile(np.arange(K), S)) % S
    w = rng.random(S * K) + 0.1
    P = sp.csr_array((w, (rows, cols)), shape=(S, S))
    P = sp.csr_array(sp.diags_array(1.0 / P.sum(axis=1)) @ P)
    lts = dma.log_transitions(P)
    dense_P = P.toarray()
    with np.errstate(divide="ignore"):
        ltd = np.log(dense_P)
    ls = np.full(S, -np.log(S))
    le = rng.normal(size=(N, S)) * 3

    from hmmlearn import _hmmc

    p_start = np.exp(ls)

    # same answer on the prefix
    a = dma.viterbi(ls, lts, le[:N_DENSE])
    _, b = _hmmc.viterbi(p_start, dense_P, le[:N_DENSE])
    c = dma.viterbi(ls, ltd, le[:N_DENSE])
    agree = bool((a == b).all() and (a == c).all())

    t_sparse = best_of(lambda: dma.viterbi(ls, lts, le))
    t_dense = best_of(lambda: dma.viterbi(ls, ltd, le[:N_DENSE]), 2) * N / N_DENSE
    t_hmm = best_of(lambda: _hmmc.viterbi(p_start, dense_P, le[:N_DENSE]), 2) * N / N_DENSE

    print(f"Viterbi, N = {N} steps, S = {S} states, nnz = {P.nnz} ({K} successors per state)")
    print(f"paths identical on the first {N_DENSE} steps: {agree}")
    print(f"{'implementation':42s} {'time (s)':>10s} {'vs hmmlearn':>12s}")
    print(f"{'hmmlearn _hmmc.viterbi (dense, scaled)':42s} {t_hmm:10.3f} {1.0:12.2f}")
    print(f"{'projtrack.dma.viterbi dense (scaled)':42s} {t_dense:10.3f} {t_hmm / t_dense:12.2f}")
    print(f"{'projtrack.dma.viterbi sparse':42s} {t_sparse:10.3f} {t_hmm / t_sparse:12.2f}")
    print(f"(dense times measured on {N_DENSE} steps and scaled by {N / N_DENSE:g}; "
          "ratio > 1 means faster than hmmlearn)")


if __name__ == "__main__":
    main()

"""Per-frame cost of the adaptive recursive SVD (projtrack.novelty.NoveltyFilter).

Vermeulen & Casasent's update touches only the K current eigenimages and the new frame
(Eqs. (4)-(9)), so its cost per frame should grow with the number of pixels and stay flat in
the number of frames seen.  Baselines measured in the same run:

- recomputing a batch SVD of all frames seen so far (what the recursion avoids),
- scikit-learn's IncrementalPCA with the filter's largest K (per frame, fed in batches of
  max(10, K) frames).

Frames: the synthetic walking scene (projtrack.scenes.sequences.walking_sequence), 1,000
frames of 128x128.  Run: ``python benchmarks/bench_novelty.py`` (about 30-60 s).
"""
from __future__ import annotations

import copy
import time

import numpy as np
from sklearn.decomposition import IncrementalPCA
from threadpoolctl import threadpool_limits

from projtrack.novelty import NoveltyFilter
from projtrack.scenes.sequences import walking_sequence
from _timing import best_of


def frames(n: int, side: int, seed: int = 0) -> np.ndarray:
    return walking_sequence(np.random.default_rng(seed), n_frames=n, shape=(side, side)).frames.astype(float)


def main() -> None:
    threadpool_limits(1)
    t_start = time.perf_counter()
    n_total, side = 1000, 128
    x = frames(n_total, side)
    flat = x.reshape(n_total, -1)
    filt = NoveltyFilter(novelty_threshold=0.0, information_threshold=0.99995)

    # 1. per-frame update cost as the number of frames seen grows (every frame is used: T_d = 0)
    checkpoints = {10, 100, 300, 1000}
    per_frame, ranks = {}, {}
    for j, f in enumerate(x, start=1):
        if j in checkpoints:
            state = copy.deepcopy(filt)
            ranks[j] = state.rank_
            per_frame[j] = best_of(lambda: copy.deepcopy(state).partial_fit(f)) - \
                best_of(lambda: copy.deepcopy(state))
        filt.partial_fit(f)
    K = max(ranks.values())
    ipca = IncrementalPCA(n_components=K)
    bs = max(10, K)
    for s in range(0, n_total - bs, bs):
        ipca.partial_fit(flat[s:s + bs])
    t_ipca = best_of(lambda: copy.deepcopy(ipca).partial_fit(flat[-bs:])) / bs - \
        best_of(lambda: copy.deepcopy(ipca)) / bs
    print(f"1,000 frames of {side}x{side}; adaptive filter T_d = 0, T_I = 0.99995; IPCA with K = {K}")
    print(f"{'frames seen':>12} {'K':>3} {'adaptive (ms)':>14} {'batch SVD (ms)':>15} {'IPCA (ms)':>10} "
          f"{'batch/adaptive':>15} {'IPCA/adaptive':>14}")
    for j in sorted(per_frame):
        t_batch = best_of(lambda: np.linalg.svd(flat[:j], full_matrices=False), repeats=1 if j > 300 else 2)
        a = per_frame[j]
        print(f"{j:>12} {ranks[j]:>3} {a * 1e3:>14.3f} {t_batch * 1e3:>15.2f} {t_ipca * 1e3:>10.3f} "
              f"{t_batch / a:>15.1f} {t_ipca / a:>14.2f}")

    # 2. per-frame cost against the number of pixels (same K regime, 100 frames fed first)
    print(f"\n{'pixels':>8} {'K':>3} {'adaptive (ms)':>14} {'per 10^4 pixels (ms)':>21}")
    for s in (32, 64, 128, 256):
        y = frames(101, s, seed=1)
        g = NoveltyFilter(0.0, 0.99995).fit(y[:100])
        a = best_of(lambda: copy.deepcopy(g).partial_fit(y[100])) - best_of(lambda: copy.deepcopy(g))
        print(f"{s * s:>8} {g.rank_:>3} {a * 1e3:>14.3f} {a * 1e3 / (s * s / 1e4):>21.3f}")
    print(f"\ntotal benchmark time {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()

"""Benchmark: eq. (9) of Barnard & Casasent, vectorized versus the paper's nested sums.

Times :func:`projtrack.neuralnet.energy_gradient` (numpy, all neurons at once) against
:func:`projtrack.neuralnet.energy_gradient_loops` (plain Python loops over the sums of
eq. (9)) for N_T = N_M targets/measurements and N_P = 5 frames, and one full serial
sweep of a 10 x 10 x 10 net. Best of a few repeats; prints ratios.
"""

from __future__ import annotations


import numpy as np

from projtrack import neuralnet as nn
from _timing import best_of


def main() -> None:
    rng = np.random.default_rng(0)
    print("eq. (9) derivative of all neurons, N_P = 5")
    print(f"{'N_T':>4} {'neurons':>8} {'loops [ms]':>11} {'vectorized [ms]':>16} {'ratio':>8}")
    for nt in (2, 4, 6, 8, 10):
        D = nn.distance_tensor(rng.uniform(-0.5, 0.5, (5, nt, 3)))
        X = rng.integers(0, 2, (nt, nt, 5)).astype(float)
        t_loop = best_of(lambda: nn.energy_gradient_loops(X, D), 1 if nt >= 8 else 3)
        t_vec = best_of(lambda: nn.energy_gradient(X, D), 20)
        print(f"{nt:>4} {X.size:>8} {1e3 * t_loop:>11.2f} {1e3 * t_vec:>16.3f} {t_loop / t_vec:>8.0f}")
    D = nn.distance_tensor(rng.uniform(-0.5, 0.5, (10, 10, 3)))
    X0 = nn.initial_states(rng, 1, 10, 10, 10)
    t_sweep = best_of(lambda: nn.run_net(D, X0, max_iter=1))
    X0b = nn.initial_states(rng, 1000, 10, 10, 10)
    t_batch = best_of(lambda: nn.run_net(D, X0b, max_iter=1), 1)
    print(f"one serial sweep, 10 targets x 10 measurements x 10 frames (1000 neurons): {1e3 * t_sweep:.1f} ms")
    print(f"the same sweep for a batch of 1000 nets: {1e3 * t_batch:.0f} ms "
          f"({t_sweep * 1000 / t_batch:.0f}x faster per net than one at a time)")


if __name__ == "__main__":
    main()

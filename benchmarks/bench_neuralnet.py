"""Benchmark: eq. (9) of Barnard & Casasent, vectorized versus the paper's nested sums.

Times :func:`projtrack.neuralnet.energy_gradient` (numpy, all neurons at once) against
:func:`projtrack.neuralnet.energy_gradient_loops` (plain Python loops over the sums of
eq. (9)) for N_T = N_M targets/measurements and N_P = 5 frames, one full serial sweep of a
10 x 10 x 10 net, and the Table 1 studies with the nets of all Monte Carlo trials run as one
batch against the same studies run trial by trial (same results, checked). Best of a few
repeats; prints ratios.
"""

from __future__ import annotations


import numpy as np

from projtrack import montecarlo
from projtrack import neuralnet as nn
from projtrack.experiments import neuralnet as nnx
from _timing import best_of, best_of_result

NOISE = [0.0, 2.5, 5.0, 7.5]


def serial_table1(n_runs: int, chunk: int, seed: int) -> dict:
    """The Table 1 study trial by trial (one run_net per trial), as the book ran it before batching."""
    out = {}
    for i, n in enumerate(NOISE):
        parts = montecarlo.run(nnx.table1_trial, n_runs // chunk, np.random.default_rng(seed + i), n, chunk)
        out[n] = {k: np.concatenate([p[k] for p in parts]) for k in nnx.TABLE1_KEYS}
    return out


def serial_cells(cells: list, n_runs: int, chunk: int) -> list:
    """The sensitivity cells trial by trial."""
    out = []
    for noise, unit, law, kw, seed in cells:
        parts = montecarlo.run(nnx.sensitivity_trial, n_runs // chunk, np.random.default_rng(seed), noise, unit,
                               law, chunk, kw)
        conv = np.concatenate([p["converged"] for p in parts])
        ok = np.concatenate([p["correct"] for p in parts])
        out.append((int(ok.sum()), int((conv & ~ok).sum())))
    return out


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

    # the Table 1 studies at a reduced size: 4 noise levels x 50 simulations (trials of 25), and
    # 8 sensitivity cells (4 noise levels x 2 units, update as printed) x 40 simulations (trials of 20)
    t_ser, a = best_of_result(lambda: serial_table1(50, 25, 2000), 1)
    t_bat, b = best_of_result(lambda: nnx.table1_study(NOISE, 50, 25, 2000), 1)
    same = all(np.array_equal(a[n][k], b[n][k]) for n in NOISE for k in nnx.TABLE1_KEYS)
    print(f"Table 1 study, 4 levels x 50 simulations with reference solvers: trial by trial {t_ser:.2f} s, "
          f"batched {t_bat:.2f} s, ratio {t_ser / t_bat:.1f}x (identical results: {same})")
    cells = [(n, u, "ball", {}, [3000, u, i]) for i, n in enumerate(NOISE) for u in (256, 2048)]
    t_ser, a = best_of_result(lambda: serial_cells(cells, 40, 20), 1)
    t_bat, b = best_of_result(lambda: nnx.sensitivity_cells(cells, 40, 20), 1)
    print(f"Table 1 sensitivity study, 8 cells x 40 simulations (nets only): trial by trial {t_ser:.2f} s, "
          f"batched {t_bat:.2f} s, ratio {t_ser / t_bat:.1f}x (identical results: {a == b})")


if __name__ == "__main__":
    main()

"""Benchmark: Algorithm 1 of Karl, Verghese & Willsky (successive halfspace) versus cvxpy/Clarabel.

Both solve the interval-constrained least squares problem of eq. (27) on the same random
problems: a random ellipsoid (semi-axes in [0.5, 2]) seen in n + 1 random hyperplanes with
symmetric Gaussian noise (standard deviation 2 per entry), under the PSD constraint
(lower = 0) and under the matrix interval 0.3 X <= X_hat <= 2.5 X. Times are the best of
3 repeats per problem, summed over 3 problems per n. The SDP is timed twice: with cvxpy's
problem set-up (building, canonicalizing and solving, what a cvxpy user pays per problem) and
the solver alone (Clarabel's reported solve time). The ratios are Algorithm 1 / SDP (below 1:
Algorithm 1 is faster); the difference is ||X_alg1 - X_sdp||_F / max(1, ||X_sdp||_F).
Run: ``python benchmarks/bench_ellipsoids.py``.
"""

from __future__ import annotations


import numpy as np

from projtrack import ellipsoids as E
from projtrack.scenes import ellipses as S
from _timing import best_of_result as best_of


def main() -> None:
    rng = np.random.default_rng(8)
    E.sdp_reconstruct(np.eye(3), np.ones(3), np.zeros((2, 2)), None)  # warm up cvxpy imports
    print(f"{'n':>2} {'constraint':>10} {'Alg. 1 [ms]':>12} {'SDP+setup [ms]':>15} {'SDP solve [ms]':>15} "
          f"{'ratio setup':>12} {'ratio solve':>12} {'iters':>6} {'max rel. diff':>14}")
    for n in range(2, 9):
        for kind in ("PSD", "interval"):
            t_h = t_s = t_solve = 0.0
            iters, diff = [], 0.0
            for _ in range(3):
                X = S.random_ellipsoid(n, rng)
                Cs = [S.random_projection(n, n - 1, rng) for _ in range(n + 1)]
                A = E.stacked_operator(Cs)
                y = np.concatenate([E.svec(E.project(X, C) + (lambda W: (W + W.T) / np.sqrt(2))(rng.normal(0, 2.0, (n - 1, n - 1))))
                                    for C in Cs])
                lo, hi = (np.zeros((n, n)), None) if kind == "PSD" else (0.3 * X, 2.5 * X)
                th, res = best_of(lambda: E.halfspace_reconstruct(None, None, lo, hi, A=A, y=y, max_iter=2000))
                infos = []

                def sdp():
                    info = {}
                    out = E.sdp_reconstruct(A, y, lo, hi, info=info)
                    infos.append(info["solve_time"])
                    return out

                ts, Xs = best_of(sdp)
                t_h += th
                t_s += ts
                t_solve += min(infos)
                iters.append(res.n_iter)
                diff = max(diff, float(np.linalg.norm(res.X - Xs) / max(1.0, np.linalg.norm(Xs))))
            print(f"{n:>2} {kind:>10} {1e3 * t_h:>12.2f} {1e3 * t_s:>15.2f} {1e3 * t_solve:>15.2f} "
                  f"{t_h / t_s:>12.2f} {t_h / t_solve:>12.2f} {max(iters):>6} {diff:>14.1e}")


if __name__ == "__main__":
    main()

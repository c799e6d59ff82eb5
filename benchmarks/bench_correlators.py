"""Benchmark: 1-D projection correlations against the full 2-D FFT correlation.

Casasent & Song's argument for projection correlations is that a few 1-D correlations
are much cheaper than one 2-D correlation. For N x N images (N = 32 .. 1024) we time
(a) the full 2-D bipolar FFT correlation (`correlate2d`, the baseline) and (b) two
projection correlations (horizontal + vertical: two projections of each image and two
1-D FFT correlations, `projection_correlation`), and report the ratio. Then the 26-class
letter bank on one 32 x 32 input: projection bank (H+V) against the 2-D bank.

Run: ``python benchmarks/bench_correlators.py`` (about 20-40 s).
"""

from __future__ import annotations


import numpy as np

from projtrack import correlators as C
from projtrack.scenes import letters
from _timing import best_of


def main() -> None:
    rng = np.random.default_rng(0)
    print("N x N images: full 2-D FFT correlation vs two 1-D projection correlations (H + V)")
    print(f"{'N':>6} {'2-D corr (ms)':>14} {'2 proj. corr (ms)':>18} {'ratio 2-D / proj':>17}")
    for N in (32, 64, 128, 256, 512, 1024):
        f, g = rng.normal(size=(N, N)), rng.normal(size=(N, N))
        repeats = 5 if N <= 256 else 2
        for t in (0, 90):  # build the cached projection operators outside the timing
            C.project(f, t)
        t2d = best_of(lambda: C.correlate2d(f, g), repeats)
        t1d = best_of(lambda: [C.projection_correlation(f, g, t) for t in (0, 90)], repeats)
        print(f"{N:>6} {1e3 * t2d:>14.3f} {1e3 * t1d:>18.3f} {t2d / t1d:>17.1f}")

    alpha = letters.alphabet()
    labels = np.arange(26)
    x = letters.noisy(alpha[2], 0.3, rng)[0][None]
    bank1 = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(alpha, labels)
    bank2 = C.Correlation2DClassifier().fit(alpha, labels)
    t1 = best_of(lambda: bank1.predict(x), 20)
    t2 = best_of(lambda: bank2.predict(x), 20)
    print()
    print("26-class letter bank on one 32 x 32 input")
    print(f"  projection bank (H+V): {1e3 * t1:8.3f} ms")
    print(f"  2-D correlation bank:  {1e3 * t2:8.3f} ms   ratio 2-D / projection = {t2 / t1:.1f}")


if __name__ == "__main__":
    main()

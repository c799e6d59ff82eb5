"""Accuracy of the analog processor of Fig. 5: beta computed with noisy detectors (JPDA chapter).

Each trial draws one fully gated random MVM (:func:`projtrack.scenes.jpda.random_mvm`)
and runs :func:`projtrack.jpda.beta_paper` with detector noise at several levels
(``vip_noise``, relative to full scale), recording the largest beta error at each level.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.jpda import beta_paper
from projtrack.scenes.jpda import random_mvm
from projtrack.tolerance import statistical

__all__ = ["analog_trial", "analog_accuracy", "median_interval", "ANALOG_TOLERANCE"]

#: Tolerance of the :func:`analog_accuracy` table. The noise is drawn from the trial's own
#: generator (the same numbers on every machine) and reaches beta through direct arithmetic:
#: the only decision is the clipping of a detector value at 0, whose effect is continuous, so
#: no trial can flip and the errors and their quantiles move only by rounding.
ANALOG_TOLERANCE = statistical(rtol=1e-6, why=(
    "Monte Carlo summary over draws that are the same on every machine, through direct "
    "arithmetic with no discrete decision (clipping at 0 is continuous): only rounding moves it"))


def analog_trial(rng: np.random.Generator, levels: Sequence[float], size: int = 6) -> list[float]:
    """Largest ``|beta error|`` of one random ``m = T = size`` MVM at each detector-noise level."""
    rng = as_rng(rng)
    size = as_int(size, "size", minimum=1, maximum=22)
    levels = as_array(levels, "levels", ndim=1)
    if np.any(levels < 0):
        raise ValueError(f"levels must be >= 0, got {levels}")
    w = random_mvm(rng, size, size)
    exact = beta_paper(w)
    return [float(np.abs(beta_paper(w, vip_noise=lv, rng=rng) - exact).max()) for lv in levels]


def median_interval(x: object, level: float = 0.95) -> tuple[float, float]:
    """Distribution-free confidence interval of the median of ``x``: two order statistics.

    The ranks ``l`` and ``n + 1 - l`` with ``l`` the largest rank such that
    ``P(Binomial(n, 1/2) < l) <= (1 - level) / 2``: the interval covers the true median
    with probability at least ``level`` for any continuous distribution. Needs
    ``n >= 6`` (fewer values cannot give a 95 % interval).
    """
    from fractions import Fraction
    from math import comb

    v = np.sort(as_array(x, "x", ndim=1, allow_empty=False))
    level = as_real(level, "level", 0.0, 1.0, low_open=True, high_open=True)
    n = len(v)
    alpha = (1 - Fraction(level).limit_denominator(10**6)) / 2
    l, cdf = 0, Fraction(1, 2**n)  # cdf = P(B <= l), exact
    while cdf <= alpha:
        l += 1
        cdf += Fraction(comb(n, l), 2**n)
    # now P(B <= l - 1) <= alpha < P(B <= l): ranks l and n + 1 - l (1-based)
    if l < 1:
        raise ValueError(f"x has {n} values: too few for a {level:g} interval of the median")
    return float(v[l - 1]), float(v[n - l])


def analog_accuracy(levels: Sequence[float], n_trials: int, seed: int,
                    size: int = 6) -> tuple[pd.DataFrame, np.ndarray]:
    """Beta errors of the analog processor over ``n_trials`` random MVMs, per noise level.

    Returns the table (median with its distribution-free 95 % interval,
    :func:`median_interval`, NaN with fewer than 6 trials; 90th percentile and worst of the per-trial largest error; one
    row per level) and the raw ``(n_trials, len(levels))`` errors. The
    trials go through :func:`projtrack.montecarlo.run` on ``default_rng(seed)``.
    """
    as_array(levels, "levels", ndim=1, allow_empty=False)
    n_trials = as_int(n_trials, "n_trials", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    err = np.array(montecarlo.run(analog_trial, n_trials, np.random.default_rng(seed),
                                  tuple(levels), size))
    ci = ([median_interval(err[:, k]) for k in range(err.shape[1])] if n_trials >= 6
          else [(np.nan, np.nan)] * err.shape[1])  # fewer trials give no 95 % interval
    table = pd.DataFrame({"detector noise / full scale": tuple(levels),
                          "median max |error| of beta": np.median(err, axis=0),
                          "median: 95% low": [c[0] for c in ci], "median: 95% high": [c[1] for c in ci],
                          "90th percentile": np.quantile(err, 0.9, axis=0),
                          "worst trial": err.max(axis=0)}).set_index("detector noise / full scale")
    return table, err

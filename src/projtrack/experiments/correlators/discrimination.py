"""One filter against two letters (Figs. 6-7): correlation peaks of the true and of a wrong class.

* :func:`unit_image`: the zero-mean, unit-energy input of Sec. III.C;
* :func:`correlation_peak`: the largest value of the 2-D or of a projection correlation;
* :func:`noisy_pair_study`: auto and cross peaks of noisy copies of two letters (Monte Carlo).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["unit_image", "correlation_peak", "noisy_pair_study"]


def unit_image(image: np.ndarray) -> np.ndarray:
    """``image`` with its mean removed and scaled to unit energy (Sec. III.B-C)."""
    return C.normalize_energy(C.zero_mean(image))


def correlation_peak(x: np.ndarray, reference: np.ndarray, angle: float | None) -> float:
    """Largest value of the full 2-D correlation (``angle=None``) or of the projection
    correlation at ``angle`` degrees of input ``x`` with ``reference``."""
    plane = C.correlate2d(x, reference) if angle is None else C.projection_correlation(x, reference, angle)
    return float(plane.max())


def _pair_draw(rng, auto_image, cross_image, reference, angles, sigma):
    xc = unit_image(letters.noisy(auto_image, sigma, rng)[0])
    xp = unit_image(letters.noisy(cross_image, sigma, rng)[0])
    return [(correlation_peak(xc, reference, a), correlation_peak(xp, reference, a)) for a in angles]


def noisy_pair_study(auto_image: np.ndarray, cross_image: np.ndarray, reference: np.ndarray,
                     angles: Sequence[float | None], sigma: float, n_draws: int,
                     rng: np.random.Generator) -> np.ndarray:
    """Auto and cross correlation peaks of noisy copies of two images against one filter (Fig. 7).

    Each draw adds Gaussian noise of standard deviation ``sigma`` to ``auto_image`` (the
    filter's class) and then to ``cross_image`` (:func:`projtrack.scenes.letters.noisy`),
    makes both unit-energy and zero-mean (:func:`unit_image`) and takes
    :func:`correlation_peak` with ``reference`` for every entry of ``angles`` (``None``:
    the 2-D correlation). Draws run through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    numpy.ndarray, shape (n_draws, len(angles), 2)
        The auto peak then the cross peak.
    """
    auto_image = as_array(auto_image, "auto_image", ndim=2, allow_empty=False)
    cross_image = as_array(cross_image, "cross_image", ndim=2, allow_empty=False)
    reference = as_array(reference, "reference", ndim=2, allow_empty=False)
    angles = [None if a is None else as_real(a, "angles") for a in angles]
    if not angles:
        raise ValueError("angles must not be empty")
    sigma = as_real(sigma, "sigma", 0.0)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    return np.array(montecarlo.run(_pair_draw, n_draws, as_rng(rng), auto_image, cross_image, reference, angles,
                                   sigma))

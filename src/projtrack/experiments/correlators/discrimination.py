"""One filter against two letters (Figs. 6-7): correlation peaks of the true and of a wrong class.

* :func:`unit_image`: the zero-mean, unit-energy input of Sec. III.C;
* :func:`correlation_peak`: the largest value of the 2-D or of a projection correlation;
* :func:`noisy_pair_study`: auto and cross peaks of noisy copies of two letters (Monte Carlo);
* :func:`binary_vs_zero_mean`: auto/cross peak ratios of every pair of letters with binary and
  with zero-mean data (Sec. III.B), and the most negative value of the zero-mean correlations;
* :func:`magnitude_mismatch`: how far the projection of the magnitude of a 2-D correlation is
  from the magnitude of the projection correlation (equal only for the bipolar outputs).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["unit_image", "correlation_peak", "noisy_pair_study", "binary_vs_zero_mean", "magnitude_mismatch"]


def unit_image(image: np.ndarray) -> np.ndarray:
    """``image`` with its mean removed and scaled to unit energy (Sec. III.B-C)."""
    return C.normalize_energy(C.zero_mean(image))


def _plane(x: np.ndarray, reference: np.ndarray, angle: float | None) -> np.ndarray:
    return C.correlate2d(x, reference) if angle is None else C.projection_correlation(x, reference, angle)


def correlation_peak(x: np.ndarray, reference: np.ndarray, angle: float | None, *, rectify: bool = False) -> float:
    """Largest value of the full 2-D correlation (``angle=None``) or of the projection
    correlation at ``angle`` degrees of input ``x`` with ``reference`` (with ``rectify``, of
    the output clipped at zero: the same unless every value is negative)."""
    peak = float(_plane(x, reference, angle).max())
    return max(peak, 0.0) if rectify else peak


def _pair_draw(rng, auto_image, cross_image, reference, angles, sigma, extent, distribution):
    xc = unit_image(letters.noisy(auto_image, sigma, rng, extent=extent, distribution=distribution)[0])
    xp = unit_image(letters.noisy(cross_image, sigma, rng, extent=extent, distribution=distribution)[0])
    return [(correlation_peak(xc, reference, a), correlation_peak(xp, reference, a)) for a in angles]


def noisy_pair_study(auto_image: np.ndarray, cross_image: np.ndarray, reference: np.ndarray,
                     angles: Sequence[float | None], sigma: float, n_draws: int,
                     rng: np.random.Generator, *, extent: int | None = None,
                     distribution: str = "gaussian") -> np.ndarray:
    """Auto and cross correlation peaks of noisy copies of two images against one filter (Fig. 7).

    Each draw adds noise of standard deviation ``sigma`` over the central ``extent x extent``
    pixels (``None``: the whole image; ``distribution`` and ``extent`` as in
    :func:`projtrack.scenes.letters.noisy`) to ``auto_image`` (the filter's class) and then
    to ``cross_image``,
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
                                   sigma, extent, distribution))


def binary_vs_zero_mean(images: np.ndarray, angles: Mapping[str, float | None]) -> pd.DataFrame:
    """Auto/cross peak ratios of every ordered pair of images, binary and zero-mean (Sec. III.B).

    For filter ``i`` and input ``j != i`` (all images scaled to unit energy, as in
    Sec. III.C; "zero-mean" also removes each image's mean first), the ratio is the peak of
    the autocorrelation of ``i`` over the peak of the cross-correlation of ``j`` with ``i``,
    for each correlation of ``angles`` (name -> projection angle, ``None`` for 2-D).

    Returns
    -------
    pandas.DataFrame
        One row per filter, input and correlation: ``filter``, ``input``, ``correlation``,
        ``binary ratio``, ``zero-mean ratio``, ``magnitude ratio`` (the zero-mean ratio of the
        largest magnitudes ``|c|``, what an intensity detector compares; the rectified output
        has the zero-mean ratio), ``cross most negative / peak`` (the most negative value of
        the zero-mean cross-correlation over the zero-mean auto peak) and ``auto most
        negative / peak`` (the same for the zero-mean autocorrelation of ``i``).
    """
    images = as_array(images, "images", ndim=3, allow_empty=False)
    if len(images) < 2:
        raise ValueError("images must hold at least two images")
    if not angles:
        raise ValueError("angles must not be empty")
    binary = [C.normalize_energy(x) for x in images]
    zm = [unit_image(x) for x in images]
    rows = []
    for name, angle in angles.items():
        auto_b = [correlation_peak(b, b, angle) for b in binary]
        auto_planes = [_plane(z, z, angle) for z in zm]
        auto_z = [float(p.max()) for p in auto_planes]
        for i in range(len(images)):
            for j in range(len(images)):
                if i == j:
                    continue
                cz = _plane(zm[j], zm[i], angle)
                rows.append({"filter": i, "input": j, "correlation": name,
                             "binary ratio": auto_b[i] / correlation_peak(binary[j], binary[i], angle),
                             "zero-mean ratio": auto_z[i] / float(cz.max()),
                             "magnitude ratio": float(np.abs(auto_planes[i]).max()) / float(np.abs(cz).max()),
                             "cross most negative / peak": float(cz.min()) / auto_z[i],
                             "auto most negative / peak": float(auto_planes[i].min()) / auto_z[i]})
    return pd.DataFrame(rows)


def magnitude_mismatch(f: np.ndarray, g: np.ndarray, angle: float) -> tuple[float, float]:
    """``(bipolar, magnitude)``: largest difference between the integrated 2-D correlation and
    the projection correlation of ``f`` with ``g`` at ``angle``, relative to the projection
    correlation's largest magnitude, for the bipolar outputs and for their magnitudes
    (projection of ``|c|`` against ``|projection correlation|``)."""
    f = as_array(f, "f", ndim=2, allow_empty=False)
    g = as_array(g, "g", ndim=2, allow_empty=False)
    angle = as_real(angle, "angle")
    pc = C.projection_correlation(f, g, angle)
    scale = float(np.max(np.abs(pc)))
    bip = float(np.max(np.abs(C.integrated_correlation(f, g, angle) - pc))) / scale
    mag = float(np.max(np.abs(C.project(np.abs(C.correlate2d(f, g)), angle) - np.abs(pc)))) / scale
    return bip, mag

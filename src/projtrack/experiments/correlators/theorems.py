"""Numerical checks of the central slice theorem, Eq. (2), and of Eq. (3) (projection correlation =
projection of the 2-D correlation), at exact-binning and interpolated angles.

* :func:`central_slice_errors`: 1-D spectrum of a projection against the slice of the 2-D spectrum;
* :func:`eq3_errors`: projection correlation against the integrated 2-D correlation;
* :func:`eq3_random_pairs`: the same on random image pairs of random sizes at lattice angles;
* :func:`eq3_wrong_angle`: the baseline for the interpolated angles: the same difference when
  the projection correlation is taken at a slightly wrong angle.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng

__all__ = ["central_slice_errors", "eq3_errors", "eq3_random_pairs", "eq3_wrong_angle"]


def central_slice_errors(image: np.ndarray, angles: Sequence[float], rho: np.ndarray, *,
                         low: float = 0.1) -> pd.DataFrame:
    """Largest difference between :func:`~projtrack.correlators.projection_spectrum` and
    :func:`~projtrack.correlators.fourier_slice` of ``image`` per angle, relative to ``|F(0)|``.

    ``rho`` must contain the zero frequency (the sample nearest 0 is taken as ``F(0)``).

    Returns
    -------
    pandas.DataFrame
        Columns ``theta (deg)``, ``exact binning``, ``max |diff| / |F(0)|`` and the same over
        ``|rho| <= low``.
    """
    image = as_array(image, "image", ndim=2, allow_empty=False)
    rho = as_array(rho, "rho", ndim=1, allow_empty=False)
    low = as_real(low, "low", 0.0, low_open=True)
    i0 = int(np.argmin(np.abs(rho)))
    if abs(rho[i0]) > 1e-12:
        raise ValueError("rho must contain the zero frequency")
    sel = np.abs(rho) <= low
    rows = []
    for theta in angles:
        lhs = C.projection_spectrum(image, theta, rho)
        rhs = C.fourier_slice(image, theta, rho)
        rows.append({"theta (deg)": theta, "exact binning": C.is_lattice_angle(theta),
                     "max |diff| / |F(0)|": float(np.max(np.abs(lhs - rhs)) / abs(rhs[i0])),
                     f"max |diff| / |F(0)|, |rho| <= {low:g}": float(np.max(np.abs(lhs[sel] - rhs[sel])) / abs(rhs[i0]))})
    return pd.DataFrame(rows)


def eq3_errors(f: np.ndarray, g: np.ndarray, angles: Sequence[float]) -> pd.DataFrame:
    """Largest difference between :func:`~projtrack.correlators.projection_correlation` and
    :func:`~projtrack.correlators.integrated_correlation` of ``f`` and ``g`` per angle,
    relative to the largest magnitude of the integrated correlation.

    Returns
    -------
    pandas.DataFrame
        Columns ``theta (deg)``, ``exact binning`` and ``max |diff| / max |integrated|``.
    """
    rows = []
    for theta in angles:
        a = C.projection_correlation(f, g, theta)
        b = C.integrated_correlation(f, g, theta)
        rows.append({"theta (deg)": theta, "exact binning": C.is_lattice_angle(theta),
                     "max |diff| / max |integrated|": float(np.max(np.abs(a - b)) / np.max(np.abs(b)))})
    return pd.DataFrame(rows)


_LATTICE = (0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)


def _pair_error(rng, max_side):
    shape_f = tuple(int(v) for v in rng.integers(2, max_side, size=2))
    shape_g = tuple(int(v) for v in rng.integers(2, max_side, size=2))
    rf, rg = rng.normal(size=shape_f), rng.normal(size=shape_g)
    theta = float(rng.choice(_LATTICE))
    a = C.projection_correlation(rf, rg, theta)
    b = C.integrated_correlation(rf, rg, theta)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def eq3_random_pairs(n_pairs: int, rng: np.random.Generator, *, max_side: int = 40) -> float:
    """Largest relative Eq. (3) difference over random pairs of white-noise images.

    Each pair has random sizes (sides 2 to ``max_side - 1``) and a random multiple of
    45 degrees; pairs run through :func:`projtrack.montecarlo.run`. Exact binning makes the
    answer a rounding-level number.
    """
    n_pairs = as_int(n_pairs, "n_pairs", minimum=1)
    max_side = as_int(max_side, "max_side", minimum=3)
    return max(montecarlo.run(_pair_error, n_pairs, as_rng(rng), max_side))


def eq3_wrong_angle(f: np.ndarray, g: np.ndarray, angles: Sequence[float], deltas: Sequence[float]) -> pd.DataFrame:
    """Eq. (3) difference at ``angles``, beside the difference a wrong angle makes.

    For each angle the integrated 2-D correlation at ``theta`` is compared with the
    projection correlation at ``theta`` (the Eq. (3) difference) and at ``theta + delta``
    for each of ``deltas`` (a baseline that must fail: the projection correlation at a
    wrong angle, linearly interpolated onto the bins of ``theta``); all relative to the
    largest magnitude of the integrated correlation.

    Returns
    -------
    pandas.DataFrame
        Columns ``theta (deg)``, ``Eq. (3)`` and ``theta + <delta> deg`` per delta.
    """
    f = as_array(f, "f", ndim=2, allow_empty=False)
    g = as_array(g, "g", ndim=2, allow_empty=False)
    deltas = [as_real(d, "deltas") for d in deltas]
    rows = []
    for theta in angles:
        theta = as_real(theta, "angles")
        b, r = C.integrated_correlation(f, g, theta), C.projection_axis(C.correlate2d(f, g).shape, theta)
        scale = float(np.max(np.abs(b)))
        row = {"theta (deg)": theta,
               "Eq. (3)": float(np.max(np.abs(C.projection_correlation(f, g, theta) - b))) / scale}
        for d in deltas:
            a, ra = C.projection_correlation(f, g, theta + d, return_r=True)
            row[f"theta {d:+g} deg"] = float(np.max(np.abs(np.interp(r, ra, a, left=0.0, right=0.0) - b))) / scale
        rows.append(row)
    return pd.DataFrame(rows)

"""Letter autocorrelations (Figs. 3-5): peaks, PSR and SNR of one letter, clean and noisy.

* :func:`in_frame` centres a letter in a larger frame of zeros (the paper's 64 x 64 plane);
* :func:`peak_measures`: peak and PSR of the 2-D and of the vertical and horizontal
  projection correlations (Figs. 3-4);
* :func:`psr_as_row`: the PSR of a 1-D correlation stored as one row of a 2-D window;
* :func:`noisy_measures` and :func:`noisy_study`: the Fig. 5 numbers of noisy inputs
  (Monte Carlo), with a cyclic (FFT-plane) or linear correlation;
* :func:`peak_at_centre_study`: how often each correlation peak stays at the true position.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_choice, as_int, as_odd_window, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["in_frame", "peak_measures", "psr_as_row", "NOISY_QUANTITIES", "noisy_measures", "noisy_study",
           "peak_at_centre_study"]

#: The Fig. 5 numbers of :func:`noisy_measures`, in order.
NOISY_QUANTITIES: tuple[str, ...] = ("2-D peak", "2-D PSR", "2-D SNR", "horizontal peak", "horizontal PSR",
                                     "horizontal SNR", "SNR loss (dB)")


def in_frame(image: np.ndarray, size: int = 64) -> np.ndarray:
    """``image`` centred in a ``size x size`` frame of zeros (top-left rounding down)."""
    image = as_array(image, "image", ndim=2, allow_empty=False)
    size = as_int(size, "size", minimum=1)
    if max(image.shape) > size:
        raise ValueError(f"size must be at least the image side {max(image.shape)}, got {size}")
    out = np.zeros((size, size))
    r0, c0 = (size - image.shape[0]) // 2, (size - image.shape[1]) // 2
    out[r0:r0 + image.shape[0], c0:c0 + image.shape[1]] = image
    return out


def peak_measures(image: np.ndarray, reference: np.ndarray) -> dict[str, tuple[float, float]]:
    """``(peak, PSR)`` of the full 2-D correlation and of the vertical (0 deg) and horizontal (90 deg)
    projection correlations of ``image`` with ``reference`` (default 11-sample PSR window)."""
    out = {}
    plane = C.correlate2d(image, reference)
    out["2-D"] = (float(plane.max()), C.psr(plane))
    for name, theta in (("vertical", 0), ("horizontal", 90)):
        pc = C.projection_correlation(image, reference, theta)
        out[name] = (float(pc.max()), C.psr(pc))
    return out


def psr_as_row(c1d: np.ndarray, window: int = 11) -> float:
    """PSR of a 1-D correlation stored as the middle row of a ``window``-row array of zeros.

    The sidelobe mean then runs over the ``window x window`` region of a 2-D routine, so
    the zeros of the other rows lower it (one reading of the paper's 1-D window).
    """
    c1d = as_array(c1d, "c1d", ndim=1, allow_empty=False)
    window = as_odd_window(window, "window")
    arr = np.zeros((window, len(c1d)))
    arr[window // 2] = c1d
    return C.psr(arr, window)


def noisy_measures(x: np.ndarray, reference: np.ndarray, *, cyclic: bool,
                   db_convention: str = "paper") -> list[float]:
    """The Fig. 5 numbers (:data:`NOISY_QUANTITIES`) of an input ``x`` against ``reference``.

    With ``cyclic`` the 2-D plane is the cyclic correlation of the two equal-size frames
    and the horizontal projection correlation the cyclic correlation of their projections
    (an FFT correlator of the frame size); otherwise both are full linear correlations.
    The last number is the SNR loss 2-D / horizontal in decibels (``db_convention`` as in
    :func:`projtrack.correlators.snr_db`).
    """
    if cyclic:
        plane = C.circular_correlate(x, reference)
        hp = C.circular_correlate(C.project(x, 90), C.project(reference, 90))
    else:
        plane = C.correlate2d(x, reference)
        hp = C.projection_correlation(x, reference, 90)
    out = [float(plane.max()), C.psr(plane), C.snr(plane), float(hp.max()), C.psr(hp), C.snr(hp)]
    return out + [C.snr_db(out[2] / out[5], convention=db_convention)]


def _noisy_draw(rng, image, reference, sigma, extent, cyclic, db_convention):
    x = letters.noisy(image, sigma, rng, extent=extent)[0]
    return noisy_measures(x, reference, cyclic=cyclic, db_convention=db_convention)


def _check_pair(image: object, reference: object) -> tuple[np.ndarray, np.ndarray]:
    image = as_array(image, "image", ndim=2, allow_empty=False)
    reference = as_array(reference, "reference", ndim=2, allow_empty=False)
    if image.shape != reference.shape:
        raise ValueError(f"image and reference must have the same shape, got {image.shape} and {reference.shape}")
    return image, reference


def noisy_study(image: np.ndarray, reference: np.ndarray, sigma: float, n_draws: int, rng: np.random.Generator,
                *, extent: int | None, cyclic: bool, db_convention: str = "paper") -> pd.DataFrame:
    """:func:`noisy_measures` of ``n_draws`` noisy copies of ``image`` (Monte Carlo, Fig. 5).

    Each draw adds Gaussian noise of standard deviation ``sigma`` over the central
    ``extent x extent`` pixels (``None``: the whole frame) and removes the mean
    (:func:`projtrack.scenes.letters.noisy`); draw ``i`` uses child ``i`` of ``rng``
    (:func:`projtrack.montecarlo.run`).

    Returns
    -------
    pandas.DataFrame
        One row per draw, one column per :data:`NOISY_QUANTITIES`.
    """
    image, reference = _check_pair(image, reference)
    sigma = as_real(sigma, "sigma", 0.0)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    db_convention = as_choice(db_convention, "db_convention", ("amplitude", "paper"))
    res = montecarlo.run(_noisy_draw, n_draws, as_rng(rng), image, reference, sigma, extent, bool(cyclic),
                         db_convention)
    return pd.DataFrame(res, columns=list(NOISY_QUANTITIES))


def _centre_draw(rng, image, reference, sigma, extent, tol):
    x = letters.noisy(image, sigma, rng, extent=extent)[0]
    plane = C.circular_correlate(x, reference)
    p, q = np.unravel_index(np.argmax(plane), plane.shape)
    hp = C.circular_correlate(C.project(x, 90), C.project(reference, 90))
    vp = C.circular_correlate(C.project(x, 0), C.project(reference, 0))
    return (abs(p - plane.shape[0] // 2) <= tol and abs(q - plane.shape[1] // 2) <= tol,
            abs(int(np.argmax(hp)) - len(hp) // 2) <= tol, abs(int(np.argmax(vp)) - len(vp) // 2) <= tol)


def peak_at_centre_study(image: np.ndarray, reference: np.ndarray, sigma: float, n_draws: int,
                         rng: np.random.Generator, *, extent: int | None = None, tol: int = 1) -> np.ndarray:
    """Whether each cyclic correlation peak of a noisy ``image`` lies within ``tol`` of zero lag.

    ``image`` and ``reference`` are aligned frames of one size; noise as in
    :func:`noisy_study`. Returns a bool array ``(n_draws, 3)``: the 2-D plane, the
    horizontal and the vertical projection correlations.
    """
    image, reference = _check_pair(image, reference)
    sigma = as_real(sigma, "sigma", 0.0)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    tol = as_int(tol, "tol", minimum=0)
    return np.array(montecarlo.run(_centre_draw, n_draws, as_rng(rng), image, reference, sigma, extent, tol))

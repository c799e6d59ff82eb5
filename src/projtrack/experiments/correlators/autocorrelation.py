"""Letter autocorrelations (Figs. 3-5): peaks, PSR and SNR of one letter, clean and noisy.

* :func:`in_frame` centres a letter in a larger frame of zeros (the paper's 64 x 64 plane);
* :func:`peak_measures`: peak and PSR of the 2-D and of the vertical and horizontal
  projection correlations (Figs. 3-4);
* :func:`psr_as_row`: the PSR of a 1-D correlation stored as one row of a 2-D window;
* :func:`zero_mean_psr`: the 2-D PSR of a zero-mean letter from the binary letter's PSR and
  pixel count, in closed form (pins the frame of Fig. 4);
* :func:`noisy_measures` and :func:`noisy_study`: the Fig. 5 numbers of noisy inputs
  (Monte Carlo), with a cyclic (FFT-plane) or linear correlation, bipolar or rectified;
* :func:`snr_by_extent` and :func:`calibrated_extent`: the 2-D SNR of Fig. 5 as a function
  of how far the noise extends, and the extent that gives the printed SNR
  (:data:`NOISE_EXTENT`, the chapter's noise reading);
* :func:`peak_at_centre_study`: how often each correlation peak stays at the true position.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_choice, as_int, as_odd_window, as_real, as_rng
from projtrack.scenes import letters

__all__ = ["in_frame", "peak_measures", "psr_as_row", "zero_mean_psr", "NOISY_QUANTITIES", "noisy_measures",
           "noisy_study", "PLANES", "NOISE_EXTENT", "snr_by_extent", "calibrated_extent", "peak_at_centre_study"]

#: The chapter's noise reading: Gaussian noise of standard deviation sigma over the central
#: ``NOISE_EXTENT x NOISE_EXTENT`` pixels of the letter (and of the 32 x 32 letter image), the
#: extent whose median 2-D SNR on the cyclic 64 x 64 plane is nearest the 100.8 of Fig. 5
#: (calibrated by :func:`calibrated_extent` on the letter-autocorrelation page).
NOISE_EXTENT: int = 30

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


def zero_mean_psr(n_on: int, psr_binary: float, frame: int, *, window: int = 11, cyclic: bool = False) -> float:
    """2-D PSR of a binary letter made zero mean in a ``frame x frame`` frame, from its binary PSR.

    Removing the mean ``mu = n_on / frame**2`` changes the autocorrelation at lag ``k`` by
    ``-2 mu n_on + mu**2 (frame - |k_x|)(frame - |k_y|)`` (linear correlation of a letter
    away from the frame's edges) or by ``-n_on**2 / frame**2`` (cyclic correlation); the
    peak is ``n_on``, the binary sidelobe mean ``n_on / psr_binary``. Only the paper's own
    numbers enter, so the printed zero-mean PSR pins the frame.
    """
    n_on = as_int(n_on, "n_on", minimum=1)
    psr_binary = as_real(psr_binary, "psr_binary", 0.0, low_open=True)
    frame = as_int(frame, "frame", minimum=1)
    window = as_odd_window(window, "window")
    mu = n_on / frame ** 2
    k = np.abs(np.arange(window) - window // 2)
    if cyclic:
        shift = np.full((window, window), n_on ** 2 / frame ** 2)
    else:
        shift = 2 * mu * n_on - mu ** 2 * np.outer(frame - k, frame - k)
    side = n_on / psr_binary - (shift.sum() - shift[window // 2, window // 2]) / (window * window - 1)
    return float((n_on - shift[window // 2, window // 2]) / side)


#: The readings of "the entire 64 x 64 correlation plane" (Sec. III.A) for two 64 x 64 frames.
PLANES: tuple[str, ...] = ("cyclic 64x64", "linear, central 64x64", "linear 127x127")


def _planes(x: np.ndarray, reference: np.ndarray, plane: str) -> tuple[np.ndarray, np.ndarray]:
    if plane == "cyclic 64x64":
        return C.circular_correlate(x, reference), C.circular_correlate(C.project(x, 90), C.project(reference, 90))
    full, hp = C.correlate2d(x, reference), C.projection_correlation(x, reference, 90)
    if plane == "linear 127x127":
        return full, hp
    (h, w), n = x.shape, len(hp)
    r0, c0, k0 = full.shape[0] // 2 - h // 2, full.shape[1] // 2 - w // 2, n // 2 - h // 2
    return full[r0:r0 + h, c0:c0 + w], hp[k0:k0 + h]


def _snr(plane: np.ndarray) -> float:
    # eq. (5a); a rectified plane can be zero everywhere outside the peak region: infinite SNR
    try:
        return C.snr(plane)
    except ValueError:
        if np.any(plane < 0):
            raise
        return float("inf")


def noisy_measures(x: np.ndarray, reference: np.ndarray, *, plane: str = "cyclic 64x64",
                   db_convention: str = "paper", rectify: bool = False) -> list[float]:
    """The Fig. 5 numbers (:data:`NOISY_QUANTITIES`) of an input ``x`` against ``reference``.

    ``plane`` (one of :data:`PLANES`, named for two 64 x 64 frames) says which correlation
    plane is measured: the cyclic correlation of the two equal-size frames and of their
    projections (an FFT correlator of the frame size), the full linear correlations cut to
    their central frame-size part (lags -H/2 to H/2 - 1), or the full linear correlations.
    With ``rectify`` the negative values of both are set to 0 first (the output
    "thresholded at zero volts" of Sec. III.B); a rectified plane that is zero everywhere
    outside the peak region has an infinite SNR (and an undefined loss, NaN). The last number is the SNR loss 2-D /
    horizontal in decibels (``db_convention`` as in :func:`projtrack.correlators.snr_db`).
    """
    plane = as_choice(plane, "plane", PLANES)
    p2, hp = _planes(x, reference, plane)
    if rectify:
        p2, hp = np.maximum(p2, 0.0), np.maximum(hp, 0.0)
    out = [float(p2.max()), C.psr(p2), _snr(p2), float(hp.max()), C.psr(hp), _snr(hp)]
    finite = np.isfinite(out[2]) and np.isfinite(out[5])
    return out + [C.snr_db(out[2] / out[5], convention=db_convention) if finite else float("nan")]


def _noisy_draw(rng, image, reference, sigma, extent, plane, db_convention, distribution, rectify):
    x = letters.noisy(image, sigma, rng, extent=extent, distribution=distribution)[0]
    out = noisy_measures(x, reference, plane=plane, db_convention=db_convention)
    if rectify:
        out += noisy_measures(x, reference, plane=plane, db_convention=db_convention, rectify=True)
    return out


def _check_pair(image: object, reference: object) -> tuple[np.ndarray, np.ndarray]:
    image = as_array(image, "image", ndim=2, allow_empty=False)
    reference = as_array(reference, "reference", ndim=2, allow_empty=False)
    if image.shape != reference.shape:
        raise ValueError(f"image and reference must have the same shape, got {image.shape} and {reference.shape}")
    return image, reference


def noisy_study(image: np.ndarray, reference: np.ndarray, sigma: float, n_draws: int, rng: np.random.Generator,
                *, extent: int | None, plane: str = "cyclic 64x64", db_convention: str = "paper",
                distribution: str = "gaussian", rectify: bool = False) -> pd.DataFrame:
    """:func:`noisy_measures` of ``n_draws`` noisy copies of ``image`` (Monte Carlo, Fig. 5).

    Each draw adds noise of standard deviation ``sigma`` (``distribution`` as in
    :func:`projtrack.scenes.letters.noisy`) over the central ``extent x extent`` pixels
    (``None``: the whole frame) and removes the mean; draw ``i`` uses child ``i`` of ``rng``
    (:func:`projtrack.montecarlo.run`).

    Returns
    -------
    pandas.DataFrame
        One row per draw, one column per :data:`NOISY_QUANTITIES`; with ``rectify``, the
        same numbers of the rectified planes follow in columns prefixed ``rectified``.
    """
    image, reference = _check_pair(image, reference)
    sigma = as_real(sigma, "sigma", 0.0)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    db_convention = as_choice(db_convention, "db_convention", ("amplitude", "paper"))
    distribution = as_choice(distribution, "distribution", ("gaussian", "uniform"))
    plane = as_choice(plane, "plane", PLANES)
    res = montecarlo.run(_noisy_draw, n_draws, as_rng(rng), image, reference, sigma, extent, plane,
                         db_convention, distribution, bool(rectify))
    cols = list(NOISY_QUANTITIES) + ([f"rectified {q}" for q in NOISY_QUANTITIES] if rectify else [])
    return pd.DataFrame(res, columns=cols)


def _extent_snr_draw(rng, image, reference, sigma, extents, planes):
    out = []
    for e in extents:
        x = letters.noisy(image, sigma, rng, extent=e)[0]
        out.append([noisy_measures(x, reference, plane=p)[k] for p in planes for k in (2, 5)])
    return out


def snr_by_extent(image: np.ndarray, reference: np.ndarray, sigma: float, extents: Sequence[int], n_draws: int,
                  rng: np.random.Generator, *, planes: Sequence[str] = PLANES) -> pd.DataFrame:
    """Median eq. (5a) SNRs of the 2-D and horizontal projection correlations against the noise extent.

    For every extent (Gaussian noise over the central ``extent x extent`` pixels of the
    frame) ``n_draws`` noisy copies of ``image`` are measured with :func:`noisy_measures` on
    every plane of ``planes``; each trial of :func:`projtrack.montecarlo.run` draws one copy
    per extent, measured on all planes.

    Returns
    -------
    pandas.DataFrame
        One row per plane and extent: ``plane``, ``noise extent``, ``2-D SNR`` and
        ``horizontal SNR`` (medians over the draws).
    """
    image, reference = _check_pair(image, reference)
    sigma = as_real(sigma, "sigma", 0.0, low_open=True)
    extents = [as_int(e, "extents", minimum=1) for e in extents]
    if not extents:
        raise ValueError("extents must not be empty")
    planes = [as_choice(p, "planes", PLANES) for p in planes]
    if not planes:
        raise ValueError("planes must not be empty")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    res = np.array(montecarlo.run(_extent_snr_draw, n_draws, as_rng(rng), image, reference, sigma, extents, planes))
    med = np.median(res, axis=0)  # (extents, 2 * planes)
    return pd.DataFrame([{"plane": p, "noise extent": e, "2-D SNR": med[i, 2 * k], "horizontal SNR": med[i, 2 * k + 1]}
                         for k, p in enumerate(planes) for i, e in enumerate(extents)])


def calibrated_extent(table: pd.DataFrame, printed: float, plane: str, column: str = "2-D SNR") -> int:
    """The noise extent of :func:`snr_by_extent` whose median ``column`` on ``plane`` is nearest
    ``printed`` (in ratio: smallest ``|log(median / printed)|``)."""
    printed = as_real(printed, "printed", 0.0, low_open=True)
    if not isinstance(table, pd.DataFrame) or not {column, "noise extent", "plane"} <= set(table):
        raise ValueError(f"table must be a DataFrame from snr_by_extent with the column {column!r}")
    table = table[table["plane"] == plane]
    if table.empty:
        raise ValueError(f"table has no rows for the plane {plane!r}")
    v = table[column].to_numpy(dtype=float)
    if np.any(~np.isfinite(v) | (v <= 0)):
        raise ValueError(f"column {column!r} must hold positive finite SNRs")
    return int(table["noise extent"].iloc[int(np.argmin(np.abs(np.log(v / printed))))])


def _centre_draw(rng, image, reference, sigma, extent, tol, detect):
    x = letters.noisy(image, sigma, rng, extent=extent)[0]  # Gaussian noise
    planes = (C.circular_correlate(x, reference), C.circular_correlate(C.project(x, 90), C.project(reference, 90)),
              C.circular_correlate(C.project(x, 0), C.project(reference, 0)))
    out = []
    for plane in planes:
        seen = np.abs(plane) if detect == "magnitude" else plane  # the rectified output peaks where the bipolar does
        peak = np.unravel_index(np.argmax(seen), seen.shape)
        out.append(all(abs(int(k) - n // 2) <= tol for k, n in zip(peak, plane.shape)))
    return out


def peak_at_centre_study(image: np.ndarray, reference: np.ndarray, sigma: float, n_draws: int,
                         rng: np.random.Generator, *, extent: int | None = None, tol: int = 1,
                         detect: str = "bipolar") -> np.ndarray:
    """Whether each cyclic correlation peak of a noisy ``image`` lies within ``tol`` of zero lag.

    ``image`` and ``reference`` are aligned frames of one size; noise as in
    :func:`noisy_study`. The peak is the largest value of the bipolar output (``detect``
    ``"bipolar"``; the rectified output, negative values set to 0, peaks at the same place)
    or of its magnitude (``"magnitude"``: what an intensity detector sees, where a large
    negative value becomes a peak). Returns a bool array ``(n_draws, 3)``: the 2-D plane,
    the horizontal and the vertical projection correlations.
    """
    image, reference = _check_pair(image, reference)
    sigma = as_real(sigma, "sigma", 0.0)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    tol = as_int(tol, "tol", minimum=0)
    detect = as_choice(detect, "detect", ("bipolar", "magnitude"))
    return np.array(montecarlo.run(_centre_draw, n_draws, as_rng(rng), image, reference, sigma, extent, tol, detect))

"""Projection correlations: Casasent & Song (1988), chapter 2 of Casasent's 1989 report.

D. P. Casasent and J.-H. Song, "Optical projection correlations", Appl. Opt. 27,
4977-4984 (1988). Implemented here:

* :func:`project`: the projection ``p_theta(r)`` of an image at any angle, Eq. (1);
* :func:`projection_spectrum` and :func:`fourier_slice`: the two sides of the central
  slice theorem, Eq. (2);
* :func:`correlate1d`, :func:`correlate2d`: full bipolar (signed) cross-correlations by
  FFT; :func:`projection_correlation` (1-D correlation of two projections) and
  :func:`integrated_correlation` (projection of the 2-D correlation), equal by Eq. (3);
  :func:`circular_correlate`, the cyclic (FFT-plane) correlation of two equal-size frames,
  whose plane has the size of the frame (the "64 x 64 correlation plane" of Sec. III.A);
* :func:`psr`, :func:`snr`, :func:`peak_stats`: the measures of Eqs. (5a)-(5b) with the
  windows of Sec. III.A; :func:`zero_mean`, :func:`normalize_energy` (Sec. III.B-C);
* :class:`ProjectionCorrelationClassifier`: a bank of projection-correlation filters per
  class, scored by the sum of the largest peaks (Sec. III.C), and
  :class:`Correlation2DClassifier`, the same bank with full 2-D correlations;
* :func:`backprojection_min` and :func:`locate_objects`: several projections locating
  several objects (Sec. V, Fig. 10);
* :func:`space_integrating_correlator` and :func:`time_integrating_correlator`: numerical
  models of the multichannel acousto-optic correlators of Figs. 8 and 9 (Sec. IV).

Conventions
-----------
An image ``f[i, j]`` has rows ``i`` (0 at the top) and columns ``j``. Its coordinates are
measured from the **centre of the array**: ``x = j - (W - 1) / 2`` to the right and
``y = (H - 1) / 2 - i`` upwards. The projection axis is ``r = x cos(theta) + y sin(theta)``
(Eq. (1)), theta in degrees counter-clockwise from the x axis, so

* ``theta = 0`` integrates each **column** (along y): ``p(r)`` is a function of x; the
  paper calls this the *vertical* projection (vertically integrated correlation);
* ``theta = 90`` integrates each **row** (along x): the *horizontal* projection, a
  function of y (bins ordered from the bottom row up);
* ``theta = 45`` integrates along the ``\\`` anti-diagonals, ``theta = 135`` along the
  ``/`` diagonals.

**Binning.** For theta a multiple of 45 degrees every pixel centre falls exactly on a
lattice line, and the projection is an exact sum of whole pixels over those lines: the
bin spacing is 1 pixel for multiples of 90 degrees and ``1/sqrt(2)`` pixel for odd
multiples of 45 degrees. For any other angle the bin spacing is 1 pixel, bins lie at
integer ``r`` (``r = 0`` at the array centre), and each pixel's value is split between
the two nearest bins by linear interpolation. Every projection preserves the image sum.

**Correlation.** :func:`correlate2d` returns the full ``(Hf + Hg - 1, Wf + Wg - 1)``
plane ``c[p, q] = sum f[i, j] g[i - p + Hg - 1, j - q + Wg - 1]`` (the convention of
:func:`scipy.signal.correlate`); its centre is the shift that aligns the centres of
``f`` and ``g``, so with the convention above the centre of the plane is ``r = 0``.
:func:`projection_correlation` returns the full 1-D correlation of the two projections
on the same bins as ``project(correlate2d(f, g), theta)``.

**Accuracy of Eq. (3).** For multiples of 45 degrees ``projection_correlation(f, g, t)``
equals ``project(correlate2d(f, g), t)`` to floating-point accuracy (both use FFTs;
differences are about ``1e-12`` of the peak). For other angles linear interpolation makes
them differ; on 32 x 32 letters the maximum difference is a few per cent of the peak
(measured in the book and bounded in the tests at 15 %); for white-noise images, whose
energy is at the highest spatial frequencies, it can reach 20-40 % of the peak.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Sequence

import numpy as np
import scipy.signal
import scipy.sparse
from scipy.ndimage import maximum_filter

__all__ = [
    "zero_mean", "normalize_energy", "is_lattice_angle", "projection_axis", "project",
    "project_stack", "projection_spectrum", "fourier_slice", "correlate1d", "correlate2d",
    "projection_correlation", "integrated_correlation", "circular_correlate", "psr", "snr", "snr_db", "peak_stats",
    "CorrelationFilterBank", "ProjectionCorrelationClassifier", "Correlation2DClassifier", "backprojection_min",
    "locate_objects", "space_integrating_correlator", "time_integrating_correlator",
]

_SNAP = 1e-9  # interpolation weights closer than this to 0 or 1 are snapped


# --------------------------------------------------------------------------- validation
def _as_real_array(x: object, name: str, ndim: int, what: str) -> np.ndarray:
    """A finite, non-empty float array of ``ndim`` dimensions, or a named error."""
    if isinstance(x, (str, bytes)) or x is None:
        raise TypeError(f"{name} must be a {ndim}-D numeric array, got {type(x).__name__}")
    try:
        arr = np.asarray(x)
    except Exception as exc:  # pragma: no cover - exotic objects
        raise TypeError(f"{name} must be a {ndim}-D numeric array") from exc
    if arr.dtype.kind not in "biuf":
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array{what}, got {arr.ndim} dimension(s)")
    if arr.size == 0:
        raise ValueError(f"{name} must not be empty, got shape {arr.shape}")
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or inf")
    return arr


def _as_image(x: object, name: str) -> np.ndarray:
    return _as_real_array(x, name, 2, " (an image)")


def _as_signal(x: object, name: str) -> np.ndarray:
    return _as_real_array(x, name, 1, "")


def _as_stack(x: object, name: str) -> np.ndarray:
    arr = np.asarray(x)
    if arr.dtype.kind not in "biuf":
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim == 2:
        arr = arr[None]
    if arr.ndim != 3 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty stack of images (n, H, W), got shape {arr.shape}")
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or inf")
    return arr


def _as_angle(theta_deg: object, name: str = "theta_deg") -> float:
    if isinstance(theta_deg, bool) or not isinstance(theta_deg, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number of degrees, got {type(theta_deg).__name__}")
    t = float(theta_deg)
    if not np.isfinite(t):
        raise ValueError(f"{name} must be finite, got {t}")
    return t


def _as_angles(angles: object) -> tuple[float, ...]:
    if isinstance(angles, (int, float, np.number)):
        angles = (angles,)
    try:
        out = tuple(_as_angle(a, "angles") for a in angles)  # type: ignore[union-attr]
    except TypeError as exc:
        raise TypeError(f"angles must be a sequence of numbers of degrees: {exc}") from None
    if not out:
        raise ValueError("angles must not be empty")
    return out


def _as_positive_int(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < 1:
        raise ValueError(f"{name} must be >= 1, got {value}")
    return int(value)


def _as_odd_window(value: object, name: str) -> int:
    # a window centred on the peak: an even size has no centre sample and would put
    # one more sample on one side of the peak than on the other
    value = _as_positive_int(value, name)
    if value % 2 == 0:
        raise ValueError(f"{name} must be odd (a window centred on the peak), got {value}")
    return value


# ------------------------------------------------------------------ simple operations
def zero_mean(image: np.ndarray) -> np.ndarray:
    """Subtract the mean of an image (block the dc spatial frequency), Sec. III.B.

    Raises
    ------
    ValueError, TypeError
        If ``image`` is not a non-empty, finite 2-D real array.
    """
    arr = _as_image(image, "image")
    return arr - arr.mean()


def normalize_energy(image: np.ndarray) -> np.ndarray:
    """Scale an image to unit energy (sum of squares 1), Sec. III.C.

    Raises
    ------
    ValueError
        If the image has zero energy (all zeros), or is not a finite 2-D array.
    """
    arr = _as_image(image, "image")
    energy = float(np.sum(arr * arr))
    if energy == 0.0:
        raise ValueError("image has zero energy and cannot be normalized")
    return arr / np.sqrt(energy)


# ------------------------------------------------------------------------ projections
def is_lattice_angle(theta_deg: float) -> bool:
    """True if ``theta_deg`` is a multiple of 45 degrees (exact pixel binning)."""
    t = _as_angle(theta_deg)
    return abs(t / 45.0 - round(t / 45.0)) < 1e-9


def _lattice(theta: float) -> tuple[int, int, float]:
    """Integer direction ``(a, b)`` and bin spacing of a multiple of 45 degrees.

    ``r = spacing * (a * x + b * y)`` exactly.
    """
    k = int(round(theta / 45.0)) % 8
    table = {0: (1, 0), 1: (1, 1), 2: (0, 1), 3: (-1, 1), 4: (-1, 0), 5: (-1, -1), 6: (0, -1), 7: (1, -1)}
    a, b = table[k]
    return a, b, (1.0 if k % 2 == 0 else 1.0 / np.sqrt(2.0))


def _snap_floor(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    k = np.floor(t)
    w = t - k
    up = w > 1.0 - _SNAP
    k = np.where(up, k + 1.0, k)
    w = np.where(up | (w < _SNAP), 0.0, w)
    return k.astype(np.int64), w


@lru_cache(maxsize=16)
def _operator(shape: tuple[int, int], theta: float) -> tuple[scipy.sparse.csr_matrix, np.ndarray]:
    """Sparse projection matrix ``(n_bins, H * W)`` and the ``r`` of each bin."""
    H, W = shape
    ii, jj = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    cols = np.arange(H * W)
    if is_lattice_angle(theta):
        a, b, step = _lattice(theta)
        t = (a * jj - b * ii).ravel()  # integer lattice coordinate, origin at [0, 0]
        t0 = int(min(0, a * (W - 1))) - int(max(0, b * (H - 1)))
        t1 = int(max(0, a * (W - 1))) - int(min(0, b * (H - 1)))
        n = t1 - t0 + 1
        mat = scipy.sparse.csr_matrix((np.ones(H * W), (t - t0, cols)), shape=(n, H * W))
        centre = a * (W - 1) / 2.0 - b * (H - 1) / 2.0
        r = step * (np.arange(t0, t1 + 1) - centre)
        return mat, r
    c, s = np.cos(np.deg2rad(theta)), np.sin(np.deg2rad(theta))
    x = (jj - (W - 1) / 2.0).ravel()
    y = ((H - 1) / 2.0 - ii).ravel()
    k, w = _snap_floor(x * c + y * s)
    kmin, kmax = _general_range(shape, theta)
    n = kmax - kmin + 1
    rows = np.concatenate([k - kmin, k - kmin + 1])
    vals = np.concatenate([1.0 - w, w])
    keep = vals != 0.0
    mat = scipy.sparse.csr_matrix((vals[keep], (rows[keep], np.concatenate([cols, cols])[keep])),
                                  shape=(n, H * W))
    return mat, np.arange(kmin, kmax + 1, dtype=float)


def _general_range(shape: tuple[int, int], theta: float) -> tuple[int, int]:
    """First and last bin (integer r) of the interpolated projection of an array of ``shape``."""
    H, W = shape
    c, s = np.cos(np.deg2rad(theta)), np.sin(np.deg2rad(theta))
    xs = np.array([-(W - 1) / 2.0, (W - 1) / 2.0])
    ys = np.array([-(H - 1) / 2.0, (H - 1) / 2.0])
    r = (xs[:, None] * c + ys[None, :] * s).ravel()
    k, _ = _snap_floor(np.array([r.min(), r.max()]))
    return int(k[0]), int(k[1]) + 1


def projection_axis(shape: tuple[int, int], theta_deg: float) -> np.ndarray:
    """The ``r`` coordinate (in pixels, 0 at the array centre) of each projection bin.

    Parameters
    ----------
    shape : tuple of int
        ``(H, W)`` of the image.
    theta_deg : float
        Projection angle in degrees (see the module conventions).
    """
    if (not isinstance(shape, tuple) or len(shape) != 2
            or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v > 0 for v in shape)):
        raise ValueError(f"shape must be a tuple (H, W) of positive ints, got {shape!r}")
    return _axis((int(shape[0]), int(shape[1])), _as_angle(theta_deg))


def _axis(shape: tuple[int, int], theta: float) -> np.ndarray:
    """Bin positions of :func:`_operator` without building the operator."""
    H, W = shape
    if is_lattice_angle(theta):
        a, b, step = _lattice(theta)
        t0 = int(min(0, a * (W - 1))) - int(max(0, b * (H - 1)))
        t1 = int(max(0, a * (W - 1))) - int(min(0, b * (H - 1)))
        centre = a * (W - 1) / 2.0 - b * (H - 1) / 2.0
        return step * (np.arange(t0, t1 + 1) - centre)
    kmin, kmax = _general_range(shape, theta)
    return np.arange(kmin, kmax + 1, dtype=float)


def project(image: np.ndarray, theta_deg: float, *, return_r: bool = False):
    """Projection ``p_theta(r)`` of an image, Eq. (1) of Casasent & Song.

    ``p_theta(r) = sum over pixels of f(x, y) [pixel on the line x cos(theta) + y sin(theta) = r]``
    with exact whole-pixel binning for multiples of 45 degrees and linear interpolation
    between unit-spaced bins otherwise (see the module docstring).

    Parameters
    ----------
    image : array_like, shape (H, W)
        Real, finite, non-empty image.
    theta_deg : float
        Angle of the projection axis r, degrees counter-clockwise from the x axis
        (0: vertical integration, a function of x; 90: horizontal integration).
    return_r : bool, default False
        Also return the r coordinate of each bin.

    Returns
    -------
    p : numpy.ndarray
        The projection; ``p.sum() == image.sum()``.
    r : numpy.ndarray, optional
        Bin positions in pixels, 0 at the centre of the array.
    """
    arr = _as_image(image, "image")
    theta = _as_angle(theta_deg)
    if is_lattice_angle(theta) and int(round(theta / 45.0)) % 2 == 0:
        # axis-aligned: plain row/column sums (same bins as the general operator)
        a, b, _ = _lattice(theta)
        p = arr.sum(axis=0) if b == 0 else arr.sum(axis=1)
        if a == -1 or b == 1:
            p = p[::-1]
        return (p, _axis(arr.shape, theta)) if return_r else p
    mat, r = _operator(arr.shape, theta)
    p = mat @ arr.ravel()
    return (p, r.copy()) if return_r else p


def project_stack(images: np.ndarray, theta_deg: float) -> np.ndarray:
    """:func:`project` applied to every image of a stack ``(n, H, W)``; returns ``(n, n_bins)``."""
    arr = _as_stack(images, "images")
    mat, _ = _operator(arr.shape[1:], _as_angle(theta_deg))
    return np.asarray((mat @ arr.reshape(arr.shape[0], -1).T).T)


def _as_freqs(rho: object) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(rho, dtype=float))
    if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
        raise ValueError("rho must be a non-empty 1-D array of finite frequencies (cycles per pixel)")
    return arr


def projection_spectrum(image: np.ndarray, theta_deg: float, rho: np.ndarray) -> np.ndarray:
    """1-D Fourier transform ``P_theta(rho)`` of the projection, the left side of Eq. (2).

    ``P(rho) = sum_k p(r_k) exp(-2 pi i rho r_k)`` at the frequencies ``rho`` (cycles per
    pixel), with ``r_k`` from :func:`project`.
    """
    p, r = project(image, theta_deg, return_r=True)
    rho = _as_freqs(rho)
    return np.exp(-2j * np.pi * rho[:, None] * r[None, :]) @ p


def fourier_slice(image: np.ndarray, theta_deg: float, rho: np.ndarray) -> np.ndarray:
    """The 2-D Fourier transform of the image along the line at angle theta, Eq. (2).

    ``F(rho cos(theta), rho sin(theta)) = sum f(x, y) exp(-2 pi i rho (x cos(theta) + y sin(theta)))``
    with the centred coordinates of the module conventions. By the central slice theorem
    it equals :func:`projection_spectrum` exactly for multiples of 45 degrees.
    """
    arr = _as_image(image, "image")
    t = np.deg2rad(_as_angle(theta_deg))
    rho = _as_freqs(rho)
    H, W = arr.shape
    x = np.arange(W) - (W - 1) / 2.0
    y = (H - 1) / 2.0 - np.arange(H)
    ex = np.exp(-2j * np.pi * rho[:, None] * x[None, :] * np.cos(t))  # (n_rho, W)
    ey = np.exp(-2j * np.pi * rho[:, None] * y[None, :] * np.sin(t))  # (n_rho, H)
    return np.einsum("kh,hw,kw->k", ey, arr, ex)


# ------------------------------------------------------------------------ correlations
def correlate1d(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Full bipolar 1-D cross-correlation by FFT.

    ``c[m] = sum_n f[n] g[n - m + len(g) - 1]``, length ``len(f) + len(g) - 1``; the
    zero-lag term is at ``m = len(g) - 1`` (the convention of :func:`scipy.signal.correlate`).
    """
    f = _as_signal(f, "f")
    g = _as_signal(g, "g")
    return scipy.signal.correlate(f, g, mode="full", method="fft")


def correlate2d(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Full bipolar 2-D cross-correlation of an input ``f`` with a reference ``g``, by FFT.

    Returns the signed (not intensity-detected) plane of shape
    ``(Hf + Hg - 1, Wf + Wg - 1)``, ``c[p, q] = sum f[i, j] g[i - p + Hg - 1, j - q + Wg - 1]``.
    The paper stresses (Sec. II.B) that Eq. (3) needs this bipolar correlation.
    """
    f = _as_image(f, "f")
    g = _as_image(g, "g")
    return scipy.signal.correlate(f, g, mode="full", method="fft")


def _plane_shape(f: np.ndarray, g: np.ndarray) -> tuple[int, int]:
    return f.shape[0] + g.shape[0] - 1, f.shape[1] + g.shape[1] - 1


def projection_correlation(f: np.ndarray, g: np.ndarray, theta_deg: float, *, return_r: bool = False):
    """1-D correlation of the projections of ``f`` and ``g`` at angle theta, Eq. (3).

    Equal to ``project(correlate2d(f, g), theta_deg)`` (the *integrated 2-D correlation*),
    on the same bins: exactly (to floating-point accuracy) for multiples of 45 degrees,
    approximately otherwise (linear-interpolation binning; see the module docstring).

    Parameters
    ----------
    f, g : array_like, 2-D
        Input and reference images (any sizes).
    theta_deg : float
        Projection angle in degrees.
    return_r : bool, default False
        Also return the r of each output sample (0 where the centres of f and g align).
    """
    f = _as_image(f, "f")
    g = _as_image(g, "g")
    theta = _as_angle(theta_deg)
    pf, rf = project(f, theta, return_r=True)
    pg, rg = project(g, theta, return_r=True)
    c = scipy.signal.correlate(pf, pg, mode="full", method="fft")
    plane = _plane_shape(f, g)
    r_out = _axis(plane, theta)
    if is_lattice_angle(theta):
        out = c  # same length and the same bins, exactly (see the module docstring)
    else:
        # lag (in bins) of c[m]: r of f's bin minus r of g's bin
        lag0 = int(round(rf[0] - rg[0])) - (len(pg) - 1)
        idx = np.round(r_out).astype(np.int64) - lag0
        out = np.zeros(len(r_out))
        ok = (idx >= 0) & (idx < len(c))
        out[ok] = c[idx[ok]]
    return (out, r_out) if return_r else out


def circular_correlate(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Cyclic bipolar correlation of two equal-size frames (1-D or 2-D), by FFT.

    ``c[m] = sum_n f[n] g[(n - m) mod N]`` along every axis, shifted so that zero lag is
    at index ``N // 2`` of each axis (the centre of the plane). This is the correlation an
    FFT correlator of frame size N produces: its plane has the size of the frame. The
    projection of the cyclic 2-D correlation at 0 or 90 degrees equals the cyclic 1-D
    correlation of the projections (Eq. (3) on the torus).

    Parameters
    ----------
    f, g : array_like
        Input and reference, both 1-D or both 2-D, of the same shape.

    Raises
    ------
    TypeError
        If either is not a real numeric array.
    ValueError
        If they are not both 1-D or both 2-D, differ in shape, are empty or not finite.
    """
    fa = np.asarray(f)
    ga = np.asarray(g)
    if fa.ndim == 1 and ga.ndim == 1:
        fa, ga = _as_signal(fa, "f"), _as_signal(ga, "g")
    elif fa.ndim == 2 and ga.ndim == 2:
        fa, ga = _as_image(fa, "f"), _as_image(ga, "g")
    else:
        raise ValueError(f"f and g must both be 1-D or both 2-D, got shapes {fa.shape} and {ga.shape}")
    if fa.shape != ga.shape:
        raise ValueError(f"f and g must have the same shape for a cyclic correlation, got {fa.shape} and {ga.shape}")
    c = np.real(np.fft.ifftn(np.fft.fftn(fa) * np.conj(np.fft.fftn(ga))))
    return np.fft.fftshift(c)


def integrated_correlation(f: np.ndarray, g: np.ndarray, theta_deg: float) -> np.ndarray:
    """Projection at angle theta of the full 2-D bipolar correlation (Sec. II.B)."""
    return project(correlate2d(f, g), theta_deg)


# ------------------------------------------------------------------------------ measures
def _as_plane(plane: object) -> np.ndarray:
    arr = np.asarray(plane)
    if arr.dtype.kind not in "biuf":
        raise TypeError(f"plane must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim not in (1, 2) or arr.size == 0:
        raise ValueError(f"plane must be a non-empty 1-D or 2-D array, got shape {arr.shape}")
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)):
        raise ValueError("plane contains NaN or inf")
    return arr


def _window(arr: np.ndarray, centre: tuple[int, ...], size: int) -> tuple[slice, ...]:
    half = size // 2
    return tuple(slice(max(c - half, 0), min(c - half + size, n)) for c, n in zip(centre, arr.shape))


def psr(plane: np.ndarray, window: int = 11) -> float:
    """Peak-to-sidelobe ratio, Eq. (5b), with the window of Sec. III.A.

    The peak is the largest (signed) value; the sidelobe level is the mean of the
    ``window x window`` region (``window`` samples for a 1-D plane) centred on the peak,
    excluding the peak itself, clipped at the edges of the plane.

    Parameters
    ----------
    plane : array_like, 1-D or 2-D
        Correlation plane (or 1-D correlation).
    window : int, default 11
        Odd side of the window centred on the peak (the paper's 11 x 11 region).

    Raises
    ------
    TypeError
        If ``window`` is not an int.
    ValueError
        If the plane is empty, non-finite, or the window holds only the peak; if
        ``window`` is not a positive odd int (an even window cannot be centred on the
        peak); or if the sidelobe mean is zero (the ratio is undefined).
    """
    arr = _as_plane(plane)
    window = _as_odd_window(window, "window")
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    region = arr[_window(arr, loc, window)]
    if region.size < 2:
        raise ValueError("window must contain samples besides the peak")
    side = (region.sum() - arr[loc]) / (region.size - 1)
    if side == 0.0:
        raise ValueError("the sidelobe mean is zero: PSR is undefined")
    return float(arr[loc] / side)


def snr(plane: np.ndarray, exclude: int = 32) -> float:
    """Correlation-plane SNR, Eq. (5a), with the region of Sec. III.A.

    Peak value divided by the standard deviation of the plane outside the
    ``exclude x exclude`` region (``exclude`` samples in 1-D) centred on the peak.

    Parameters
    ----------
    plane : array_like, 1-D or 2-D
        Correlation plane (or 1-D correlation).
    exclude : int, default 32
        Side of the excluded region (the paper's 32 x 32). An even region has no centre
        sample: it then covers ``exclude // 2`` samples before the peak and
        ``exclude // 2 - 1`` after it along every axis (for the default, lags -16 to +15
        relative to the peak); an odd one is symmetric. Clipped at the plane's edges.

    Raises
    ------
    TypeError
        If ``exclude`` is not an int.
    ValueError
        If ``exclude`` < 1, if fewer than two samples remain outside the excluded region
        or if their standard deviation is zero.
    """
    arr = _as_plane(plane)
    exclude = _as_positive_int(exclude, "exclude")
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    mask = np.ones(arr.shape, dtype=bool)
    mask[_window(arr, loc, exclude)] = False
    rest = arr[mask]
    if rest.size < 2:
        raise ValueError(f"the plane has fewer than 2 samples outside the {exclude}-wide region around the peak")
    sd = float(rest.std())
    if sd == 0.0:
        raise ValueError("the plane is constant away from the peak: SNR is undefined")
    return float(arr[loc] / sd)


def snr_db(ratio: float, *, convention: str = "amplitude") -> float:
    """An SNR ratio in decibels.

    Parameters
    ----------
    ratio : float
        A positive ratio, for example the amplitude SNR of Eq. (5a) (peak over the standard
        deviation of the plane).
    convention : {"amplitude", "paper"}
        ``"amplitude"`` (default): ``20 log10(ratio)``, the usual decibels of an amplitude
        ratio. ``"paper"``: ``10 log10(ratio)``, the convention of Casasent and Song, who quote
        10 log10 of their amplitude SNR (26.2 as 14.2 dB, 100.8 as 20 dB, N^1/2 = 8 as 9 dB).

    Returns
    -------
    float
        The ratio in decibels under the chosen convention.
    """
    if isinstance(ratio, bool) or not isinstance(ratio, (int, float, np.number)):
        raise TypeError(f"ratio must be a number, got {type(ratio).__name__}")
    if not np.isfinite(ratio) or ratio <= 0:
        raise ValueError(f"ratio must be finite and > 0, got {ratio}")
    factors = {"amplitude": 20.0, "paper": 10.0}
    if convention not in factors:
        raise ValueError(f"convention must be one of {sorted(factors)}, got {convention!r}")
    return float(factors[convention] * np.log10(ratio))


def peak_stats(plane: np.ndarray, *, window: int = 11, exclude: int | None = 32) -> dict[str, object]:
    """Peak value and location, PSR (Eq. 5b) and, if ``exclude`` is given, SNR (Eq. 5a)."""
    arr = _as_plane(plane)
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    out: dict[str, object] = {"peak": float(arr[loc]), "location": tuple(int(v) for v in loc),
                              "psr": psr(arr, window)}
    if exclude is not None:
        out["snr"] = snr(arr, exclude)
    return out


# -------------------------------------------------------------------------- classifiers
def _batch_correlate1d(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Full correlations of every row of ``a (n, L1)`` with every row of ``b (C, L2)``: ``(n, C, L1+L2-1)``."""
    L = a.shape[1] + b.shape[1] - 1
    nfft = scipy.fft.next_fast_len(L, real=True)
    A = np.fft.rfft(a, nfft)
    B = np.fft.rfft(b[:, ::-1], nfft)
    return np.fft.irfft(A[:, None, :] * B[None, :, :], nfft)[..., :L]


class CorrelationFilterBank:
    """Base class of the correlation filter banks: one reference filter per class.

    Subclasses define ``_build`` (prepare the filters) and ``decision_function`` (one
    score per image and class); :meth:`fit`, :meth:`predict` and :meth:`score` are shared.

    Parameters
    ----------
    zero_mean : bool
        Remove the mean of filters and inputs (Sec. III.B).
    normalize : bool
        Scale filters and inputs to unit energy (Sec. III.C).
    """

    def __init__(self, zero_mean: bool = True, normalize: bool = True):
        self.zero_mean = zero_mean
        self.normalize = normalize

    def _prepare(self, X: np.ndarray) -> np.ndarray:
        X = X.copy()
        if self.zero_mean:
            X -= X.mean(axis=(1, 2), keepdims=True)
        if self.normalize:
            e = np.sqrt(np.sum(X * X, axis=(1, 2), keepdims=True))
            if np.any(e == 0):
                raise ValueError("an image has zero energy (after zero-mean) and cannot be normalized")
            X = X / e
        return X

    def fit(self, X: np.ndarray, y: Sequence[object]):
        """Store one reference filter per class (the mean of its training images).

        Parameters
        ----------
        X : array_like, shape (n, H, W)
            Training images (for the paper's bank: the 26 clean letters).
        y : sequence of labels, length n
            At least two distinct classes (a bank of one filter cannot discriminate).

        Raises
        ------
        ValueError
            If ``X`` is not a finite, non-empty stack of images, ``y`` does not hold one
            label per image or fewer than two classes are given.
        """
        X = _as_stack(X, "X")
        y_arr = np.asarray(y)
        if y_arr.ndim != 1 or len(y_arr) != len(X):
            raise ValueError(f"y must be 1-D with one label per image ({len(X)}), got shape {y_arr.shape}")
        classes = np.unique(y_arr)
        if len(classes) < 2:
            raise ValueError(f"y must contain at least 2 classes to classify between, got {len(classes)}: "
                             f"{classes.tolist()}")
        self.classes_ = classes
        refs = np.stack([X[y_arr == c].mean(axis=0) for c in self.classes_])
        self.shape_ = X.shape[1:]
        self.filters_ = self._prepare(refs)
        self._build()
        return self

    def _check_X(self, X: np.ndarray) -> np.ndarray:
        if not hasattr(self, "filters_"):
            raise ValueError("this classifier is not fitted yet: call fit(X, y) first")
        X = _as_stack(X, "X")
        if X.shape[1:] != self.shape_:
            raise ValueError(f"X images must have shape {self.shape_}, got {X.shape[1:]}")
        return self._prepare(X)

    def _build(self) -> None:
        """Prepare the filters after :meth:`fit` (subclasses)."""

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """One score per image and class (defined by the subclasses)."""
        raise NotImplementedError("use ProjectionCorrelationClassifier or Correlation2DClassifier")

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Class with the largest score (:meth:`decision_function`) for each image."""
        scores = self.decision_function(X)
        return self.classes_[np.argmax(scores, axis=1)]

    def score(self, X: np.ndarray, y: Sequence[object]) -> float:
        """Fraction of images classified correctly."""
        return float(np.mean(self.predict(X) == np.asarray(y)))


class ProjectionCorrelationClassifier(CorrelationFilterBank):
    """Bank of 1-D projection-correlation filters, one set per class (Sec. III.C).

    Each class keeps the projections of its (zero-mean, unit-energy) reference at the
    given angles. An input is projected at the same angles, correlated (full, bipolar)
    with every class's projections, and scored by the **sum over angles of the largest
    correlation peak**; the class with the largest sum wins ("For each filter pair, the
    largest pair of correlation peaks was measured and the peak values were summed").

    Parameters
    ----------
    angles : sequence of float, default (0, 90)
        Projection angles in degrees (0 = vertical, 90 = horizontal; the paper's bank
        used horizontal and vertical, with 45 degrees optional).
    zero_mean : bool, default True
        Remove the mean of filters and inputs (Sec. III.B).
    normalize : bool, default True
        Scale filters and inputs to unit energy (Sec. III.C).
    normalize_projections : bool, default True
        Also scale every 1-D filter and every input projection to unit energy, so that
        by the Cauchy-Schwarz inequality a noise-free input scores highest on its own
        class. With 2-D normalization only, a letter with large projections (``B``)
        out-scores the true class even on noise-free inputs (shown in the book).

    Attributes
    ----------
    classes_ : numpy.ndarray
    filters_ : numpy.ndarray, shape (n_classes, H, W)
    """

    def __init__(self, angles: Sequence[float] = (0.0, 90.0), zero_mean: bool = True, normalize: bool = True,
                 normalize_projections: bool = True):
        super().__init__(zero_mean, normalize)
        self.angles = _as_angles(angles)
        self.normalize_projections = normalize_projections

    def _unit(self, P: np.ndarray) -> np.ndarray:
        if not self.normalize_projections:
            return P
        e = np.sqrt(np.sum(P * P, axis=1, keepdims=True))
        if np.any(e == 0):
            raise ValueError("a projection has zero energy and cannot be normalized")
        return P / e

    def _build(self) -> None:
        self.filter_projections_ = [self._unit(project_stack(self.filters_, t)) for t in self.angles]

    def peak_scores(self, X: np.ndarray) -> np.ndarray:
        """Largest projection-correlation peak per image, class and angle: ``(n, n_classes, n_angles)``."""
        X = self._check_X(X)
        out = np.empty((len(X), len(self.classes_), len(self.angles)))
        for a, t in enumerate(self.angles):
            P = self._unit(project_stack(X, t))
            out[:, :, a] = _batch_correlate1d(P, self.filter_projections_[a]).max(axis=2)
        return out

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """Sum over angles of the largest projection-correlation peak, ``(n, n_classes)``."""
        return self.peak_scores(X).sum(axis=2)

    def summed_output_scores(self, X: np.ndarray) -> np.ndarray:
        """Largest value of the correlations summed over angles at a common lag, ``(n, n_classes)``.

        This is what one detector of a frequency-multiplexed space-integrating correlator
        (Fig. 8) reads: the correlations of all projections of one filter set add at the
        same time step before the peak is taken. It equals :meth:`decision_function` only
        when the peaks of all angles fall at the same lag (for example, centred inputs).

        Raises
        ------
        ValueError
            If the classifier is not fitted, ``X`` is not a stack of images of the fitted
            shape, or the projections at the bank's angles differ in length (they cannot
            share one time axis).
        """
        X = self._check_X(X)
        lengths = {P.shape[1] for P in self.filter_projections_}
        if len(lengths) != 1:
            raise ValueError(f"summed outputs need projections of equal length at every angle, got {sorted(lengths)}")
        total = None
        for a, t in enumerate(self.angles):
            P = self._unit(project_stack(X, t))
            c = _batch_correlate1d(P, self.filter_projections_[a])
            total = c if total is None else total + c
        return total.max(axis=2)


class Correlation2DClassifier(CorrelationFilterBank):
    """The same filter bank with full 2-D bipolar correlations: score = largest 2-D peak.

    Parameters
    ----------
    zero_mean, normalize : bool
        As for :class:`ProjectionCorrelationClassifier`.
    chunk : int, default 256
        Inputs correlated per FFT batch (memory bound).
    """

    def __init__(self, zero_mean: bool = True, normalize: bool = True, chunk: int = 256):
        super().__init__(zero_mean, normalize)
        self.chunk = _as_positive_int(chunk, "chunk")

    def _build(self) -> None:
        H, W = self.shape_
        self._fft_shape = (scipy.fft.next_fast_len(2 * H - 1, real=True), scipy.fft.next_fast_len(2 * W - 1, real=True))
        self._F = np.fft.rfft2(self.filters_[:, ::-1, ::-1], self._fft_shape)

    def decision_function(self, X: np.ndarray) -> np.ndarray:
        """Largest 2-D correlation value per image and class, ``(n, n_classes)``."""
        X = self._check_X(X)
        H, W = self.shape_
        out = np.empty((len(X), len(self.classes_)))
        for s in range(0, len(X), self.chunk):
            A = np.fft.rfft2(X[s:s + self.chunk], self._fft_shape)
            c = np.fft.irfft2(A[:, None] * self._F[None], self._fft_shape)[..., :2 * H - 1, :2 * W - 1]
            out[s:s + self.chunk] = c.max(axis=(2, 3))
        return out


# -------------------------------------------------------------------- multiple objects
def backprojection_min(projections: Sequence[np.ndarray], r_axes: Sequence[np.ndarray],
                       angles: Sequence[float], shape: tuple[int, int]) -> np.ndarray:
    """Smear each 1-D projection correlation back over a plane and keep the minimum.

    For every pixel of a plane of ``shape`` (centred coordinates), the value is
    ``min over angles of c_theta(x cos(theta) + y sin(theta))`` with ``c_theta`` linearly
    interpolated on its ``r`` axis (0 outside). A point is a candidate object position
    only if every projection correlation is high on the line through it; with the
    horizontal and vertical projections alone, two objects that do not share a row or a
    column leave two "ghost" candidates, which a third projection removes (Sec. V).
    """
    angles = _as_angles(angles)
    if not (len(projections) == len(r_axes) == len(angles)):
        raise ValueError("projections, r_axes and angles must have the same length")
    if (not isinstance(shape, tuple) or len(shape) != 2
            or not all(isinstance(v, (int, np.integer)) and v > 0 for v in shape)):
        raise ValueError(f"shape must be a tuple (H, W) of positive ints, got {shape!r}")
    H, W = shape
    x = np.arange(W) - (W - 1) / 2.0
    y = (H - 1) / 2.0 - np.arange(H)
    out = np.full(shape, np.inf)
    for p, r, t in zip(projections, r_axes, angles):
        p = _as_signal(p, "projections[i]")
        r = _as_signal(r, "r_axes[i]")
        if len(p) != len(r) or np.any(np.diff(r) <= 0):
            raise ValueError("each r axis must be increasing and as long as its projection")
        th = np.deg2rad(t)
        rr = x[None, :] * np.cos(th) + y[:, None] * np.sin(th)
        out = np.minimum(out, np.interp(rr, r, p, left=0.0, right=0.0))
    return out


def locate_objects(scene: np.ndarray, template: np.ndarray, angles: Sequence[float],
                   threshold: float = 0.8, *, zero_mean_template: bool = True) -> dict[str, object]:
    """Locate copies of ``template`` in ``scene`` from a few projection correlations (Fig. 10).

    Each projection correlation of the scene with the template is divided by the
    template's own projection-autocorrelation peak at that angle (so one object gives 1),
    the normalized correlations are backprojected over the full correlation plane, and a
    plane point is a candidate when every backprojection reaches ``threshold`` (the
    minimum of :func:`backprojection_min`); the candidates that are local maxima (5 x 5)
    of the mean backprojection are reported.

    Returns
    -------
    dict
        ``"positions"``: list of ``(row, col)`` of the template centre in scene pixels;
        ``"map"``: the backprojected minimum on the correlation-plane grid;
        ``"projections"`` and ``"r"``: the normalized projection correlations and their axes.
    """
    scene = _as_image(scene, "scene")
    template = _as_image(template, "template")
    angles = _as_angles(angles)
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.number)) or not np.isfinite(threshold):
        raise TypeError(f"threshold must be a finite number, got {threshold!r}")
    if zero_mean_template:
        template = template - template.mean()
    if not np.any(template):
        raise ValueError("template must not be constant")
    projs, axes = [], []
    for t in angles:
        c, r = projection_correlation(scene, template, t, return_r=True)
        auto = float(projection_correlation(template, template, t).max())
        if auto <= 0:
            raise ValueError(f"the template's projection autocorrelation at {t} degrees has no positive peak")
        projs.append(c / auto)
        axes.append(r)
    plane = _plane_shape(scene, template)
    bmap = backprojection_min(projs, axes, angles, plane)
    mean_map = np.mean([backprojection_min([p], [r], [t], plane) for p, r, t in zip(projs, axes, angles)], axis=0)
    score = np.where(bmap >= threshold, mean_map, -np.inf)
    peaks = np.isfinite(score) & (score == maximum_filter(score, size=5, mode="constant", cval=-np.inf))
    Hg, Wg = template.shape
    # plane index p <-> template top-left at row p - (Hg - 1); its centre at + (Hg - 1) / 2
    pos = [(float(p - (Hg - 1) / 2.0), float(q - (Wg - 1) / 2.0)) for p, q in zip(*np.nonzero(peaks))]
    return {"positions": pos, "map": bmap, "projections": projs, "r": axes}


# ------------------------------------------------------------ acousto-optic correlators
def space_integrating_correlator(inputs: np.ndarray, references: np.ndarray, *,
                                 carriers: Sequence[int] | None = None, oversample: int = 8) -> np.ndarray:
    """Multichannel acousto-optic space-integrating correlator with frequency multiplexing (Fig. 8).

    Numerical model of Sec. IV. ``K`` 1-D input signals (e.g. the horizontal and vertical
    projections of one test image) are written on ``K`` carriers of ``carriers[k]``
    cycles per sample and summed into one AO cell at P1; the cell's light amplitude is
    sampled ``oversample`` times per signal sample and travels one sample per time step.
    At P2, channel ``n`` holds a fixed mask: the sum over ``k`` of the time-reversed
    reference ``references[n, k]`` on the conjugate carrier. Detector ``n`` at P3
    integrates the product over the aperture. Products of different carriers integrate
    to zero over each sample (they are diffracted off the detector), so detector ``n``
    receives the **sum over k of the correlations** of input ``k`` with reference
    ``(n, k)``, divided here by ``oversample``.

    Parameters
    ----------
    inputs : array_like, shape (K, L)
        Bipolar input signals.
    references : array_like, shape (N, K, M)
        Reference signals of N channels, K per channel.
    carriers : sequence of K distinct ints, optional
        Carrier frequencies in cycles per sample (default ``1, 2, ..., K``); their
        differences must not be multiples of ``oversample``.
    oversample : int, default 8
        Optical samples per signal sample.

    Returns
    -------
    numpy.ndarray, shape (N, L + M - 1)
        Detector outputs at the time steps ``t = 0 .. L + M - 2``; equal to
        ``sum_k correlate1d(inputs[k], references[n, k])``.
    """
    x = np.asarray(inputs, dtype=float)
    h = np.asarray(references, dtype=float)
    if x.ndim != 2 or x.size == 0:
        raise ValueError(f"inputs must be a non-empty (K, L) array, got shape {x.shape}")
    if h.ndim != 3 or h.shape[1] != x.shape[0] or h.size == 0:
        raise ValueError(f"references must have shape (N, K={x.shape[0]}, M), got {h.shape}")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(h))):
        raise ValueError("inputs and references must be finite")
    K, L = x.shape
    N, _, M = h.shape
    oversample = _as_positive_int(oversample, "oversample")
    car = np.arange(1, K + 1) if carriers is None else np.asarray(carriers)
    if car.shape != (K,) or car.dtype.kind not in "iu":
        raise ValueError(f"carriers must be {K} integers (cycles per sample)")
    diff = car[:, None] - car[None, :]
    if np.any((diff % oversample == 0) & ~np.eye(K, dtype=bool)):
        raise ValueError("carriers must differ by a non-multiple of oversample")
    if np.any(2 * np.abs(car) >= oversample):
        raise ValueError("oversample must exceed twice the largest carrier (no aliasing)")
    xi = np.arange(M * oversample) / oversample  # aperture positions in samples
    cell = np.floor(xi).astype(int)
    mask = np.einsum("nkm,km->nm", h[:, :, ::-1][:, :, cell],
                     np.exp(-2j * np.pi * car[:, None] * xi[None, :]))  # (N, M*oversample)
    T = L + M - 1
    padded = np.concatenate([np.zeros((K, M - 1)), x, np.zeros((K, M - 1))], axis=1)
    carrier = np.exp(2j * np.pi * car[:, None] * xi[None, :])  # (K, M*oversample)
    # at time step t the cell holds s_k(t - xi) on its carrier exp(2 pi i c_k (xi - t)),
    # and exp(-2 pi i c_k t) = 1 at integer t: one row of `field` per time step
    samples = padded[:, np.arange(T)[:, None] + (M - 1) - cell[None, :]]  # (K, T, M*oversample)
    field = np.einsum("ktm,km->tm", samples, carrier)
    return np.real(field @ mask.T).T / oversample


def time_integrating_correlator(test: np.ndarray, references: np.ndarray, *, bias: float | None = None) -> np.ndarray:
    """Multichannel acousto-optic time-integrating correlator (Fig. 9), with intensity bias.

    Numerical model of Sec. IV. Point modulator ``n`` at P1 is driven by reference
    ``references[n](t)``; the test projection ``test(t)`` travels through one AO cell at
    P2 (delayed so that all lags fit the aperture); P3 is an ``(N + 1) x (L + M - 1)``
    detector array that accumulates light **intensity** over time. Optical intensities
    cannot be negative, so both signals ride on a ``bias`` (default: the largest absolute
    value of either); an extra reference-free row measures the bias terms, which are
    subtracted to recover the bipolar correlations.

    Returns
    -------
    numpy.ndarray, shape (N, L + M - 1)
        Equal to ``correlate1d(test, references[n])`` for each channel ``n``.
    """
    s = _as_signal(test, "test")
    h = np.asarray(references, dtype=float)
    if h.ndim != 2 or h.size == 0:
        raise ValueError(f"references must be a non-empty (N, M) array, got shape {h.shape}")
    if not np.all(np.isfinite(h)):
        raise ValueError("references must be finite")
    N, M = h.shape
    L = len(s)
    b = float(max(np.abs(s).max(), np.abs(h).max())) if bias is None else float(bias)
    if not np.isfinite(b) or b < max(np.abs(s).max(), np.abs(h).max()):
        raise ValueError("bias must be finite and at least the largest |signal| (intensities are >= 0)")
    X = L + M - 1  # detector columns = AO-cell positions
    T = L + 2 * M - 2  # time steps
    # P1 drives: reference n delayed by L - 1 steps; row N is the bias-only channel
    drive = np.zeros((N + 1, T))
    drive[:N, L - 1:L - 1 + M] = h
    cell_in = np.zeros(T + X)
    cell_in[X - 1:X - 1 + L] = s  # test enters the cell at position 0 at time t
    acc = np.zeros((N + 1, X))
    for t in range(T):
        window = cell_in[t + X - 1 - np.arange(X)]  # cell position x holds test(t - x)
        acc += (b + drive[:, t])[:, None] * (b + window)[None, :]  # intensity >= 0
    ref_sums = drive[:N].sum(axis=1)
    out = acc[:N] - acc[N][None, :] - b * ref_sums[:, None]
    # column x holds sum_u h[u] s[u + L - 1 - x], the full-correlation lag m = L + M - 2 - x
    return out[:, ::-1]

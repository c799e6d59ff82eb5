"""Projections of an image at any angle, Eq. (1), and the central slice theorem, Eq. (2).

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
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.sparse

from projtrack._validation import as_bool, as_shape2

from ._checks import as_angle, as_freqs, as_image, as_stack

__all__ = ["is_lattice_angle", "projection_axis", "project", "project_stack", "projection_spectrum",
           "fourier_slice"]

_SNAP = 1e-9  # interpolation weights closer than this to 0 or 1 are snapped


def is_lattice_angle(theta_deg: float) -> bool:
    """True if ``theta_deg`` is a multiple of 45 degrees (exact pixel binning).

    Parameters
    ----------
    theta_deg : float
        An angle in degrees.

    Returns
    -------
    bool
    """
    t = as_angle(theta_deg)
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
    """The :math:`r` coordinate (in pixels, 0 at the array centre) of each projection bin.

    Parameters
    ----------
    shape : tuple of int
        ``(H, W)`` of the image.
    theta_deg : float
        Projection angle in degrees (see the module conventions).
    """
    return _axis(as_shape2(shape), as_angle(theta_deg))


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
    r"""Projection :math:`p_\theta(r)` of an image, Equation (1) of Casasent & Song.

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
    return_r = as_bool(return_r, "return_r")
    arr = as_image(image, "image")
    theta = as_angle(theta_deg)
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
    """:func:`project` applied to every image of a stack ``(n, H, W)``; returns ``(n,
    n_bins)``.

    Parameters
    ----------
    images : array_like, shape (n, H, W)
        A stack of images of one size.
    theta_deg : float
        Projection angle in degrees.

    Returns
    -------
    numpy.ndarray, shape (n, n_bins)
    """
    arr = as_stack(images, "images")
    mat, _ = _operator(arr.shape[1:], as_angle(theta_deg))
    return np.asarray((mat @ arr.reshape(arr.shape[0], -1).T).T)


def projection_spectrum(image: np.ndarray, theta_deg: float, rho: np.ndarray) -> np.ndarray:
    r"""1-D Fourier transform :math:`P_\theta(\rho)` of the projection, the left side of
    Equation (2).

    ``P(rho) = sum_k p(r_k) exp(-2 pi i rho r_k)`` at the frequencies ``rho`` (cycles per
    pixel), with ``r_k`` from :func:`project`.

    Parameters
    ----------
    image : array_like, 2-D
        The image.
    theta_deg : float
        Projection angle in degrees.
    rho : array_like, 1-D
        Spatial frequencies, cycles per pixel.

    Returns
    -------
    numpy.ndarray of complex, shape (len(rho),)
    """
    p, r = project(image, theta_deg, return_r=True)
    rho = as_freqs(rho)
    return np.exp(-2j * np.pi * rho[:, None] * r[None, :]) @ p


def fourier_slice(image: np.ndarray, theta_deg: float, rho: np.ndarray) -> np.ndarray:
    """The 2-D Fourier transform of the image along the line at angle theta, Equation (2).

    ``F(rho cos(theta), rho sin(theta)) = sum f(x, y) exp(-2 pi i rho (x cos(theta) + y sin(theta)))``
    with the centred coordinates of the module conventions. By the central slice theorem
    it equals :func:`projection_spectrum` exactly for multiples of 45 degrees.

    Parameters
    ----------
    image : array_like, 2-D
        The image.
    theta_deg : float
        Angle of the line through the origin of the frequency plane, degrees.
    rho : array_like, 1-D
        Spatial frequencies along the line, cycles per pixel.

    Returns
    -------
    numpy.ndarray of complex, shape (len(rho),)
    """
    arr = as_image(image, "image")
    t = np.deg2rad(as_angle(theta_deg))
    rho = as_freqs(rho)
    H, W = arr.shape
    x = np.arange(W) - (W - 1) / 2.0
    y = (H - 1) / 2.0 - np.arange(H)
    ex = np.exp(-2j * np.pi * rho[:, None] * x[None, :] * np.cos(t))  # (n_rho, W)
    ey = np.exp(-2j * np.pi * rho[:, None] * y[None, :] * np.sin(t))  # (n_rho, H)
    return np.einsum("kh,hw,kw->k", ey, arr, ex)


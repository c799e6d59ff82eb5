"""The straight-line Hough transform: point voting, binary images, rotate-and-integrate.

Eq. (1) by voting (:func:`hough_transform`, :func:`hough_transform_image`), the
thresholded HT of Sec. V (:func:`thresholded_hough_transform`), Eqs. (2)-(3) as
projections of the rotated image (:func:`rotate_integrate_hough`), the plane's axes
(:func:`hough_axes`) and the total-least-squares line through points in the same
convention (:func:`line_through`).
"""

from __future__ import annotations

from collections.abc import Sequence
from math import ceil

import numpy as np
from scipy import ndimage

from projtrack._validation import as_bool, as_real, as_shape2
from projtrack.hough import _kernel
from projtrack.hough._checks import (_check_binary_image, _check_frames, _check_origin, _check_points,
                                     _origin_xy)

__all__ = [
    "hough_axes",
    "hough_transform",
    "hough_transform_image",
    "thresholded_hough_transform",
    "rotate_integrate_hough",
    "line_through",
]


def hough_axes(shape: tuple[int, int], drho: float = 2.0, dtheta_deg: float = 1.0,
               origin: str = "center") -> tuple[np.ndarray, np.ndarray]:
    """Sample positions of the Hough plane (Section II.B).

    Parameters
    ----------
    shape : (int, int)
        ``(height, width)`` of the image.
    drho : float, default 2
        Resolution in ``rho`` (pixels); the paper's value is 2.
    dtheta_deg : float, default 1
        Resolution in ``theta`` (degrees); the paper's value is 1.
    origin : {"center", "corner"}
        Where ``rho`` is measured from (see the module docstring).

    Returns
    -------
    rhos : ndarray
        Bin centres ``-R, -R + drho, ..., R`` with ``R`` the farthest distance of the
        image from the origin rounded up to a multiple of ``drho`` (``R = 182`` for a
        256 x 256 image and ``drho = 2``: the paper's +-180).
    thetas_deg : ndarray
        ``0, dtheta, ...`` below 180 degrees.
    """
    shape = as_shape2(shape)
    drho = as_real(drho, "drho", 0, low_open=True)
    dtheta_deg = as_real(dtheta_deg, "dtheta_deg", 0, low_open=True)
    if dtheta_deg > 90:
        raise ValueError(f"dtheta_deg must be at most 90 degrees, got {dtheta_deg}")
    _check_origin(origin)
    h, w = shape
    cx, cy = _origin_xy(shape, origin)
    rmax = float(np.hypot(max(cx, w - cx), max(cy, h - cy)))
    n = int(ceil(rmax / drho - 1e-9))
    rhos = drho * np.arange(-n, n + 1, dtype=float)
    thetas = np.arange(0.0, 180.0 - 1e-9, dtheta_deg)
    return rhos, thetas


def _vote(pts: np.ndarray, shape: tuple[int, int], rhos: np.ndarray, thetas_deg: np.ndarray,
          drho: float, origin: str, weights: np.ndarray | None = None) -> np.ndarray:
    """Accumulate Eq. (1) for every point and angle (internal, inputs already checked)."""
    cx, cy = _origin_xy(shape, origin)
    return _kernel.vote(pts, cx, cy, float(rhos[0]), rhos.size, thetas_deg, drho, weights)


def hough_transform(points: object, shape: tuple[int, int], drho: float = 2.0,
                    dtheta_deg: float = 1.0, *, origin: str = "center",
                    allow_empty: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Straight-line Hough transform of a point list by voting, Equation (1).

    Every point ``(x, y)`` adds one vote to the cell nearest to
    ``rho = x cos(theta) + y sin(theta)`` at every sampled ``theta``; the value of a
    cell is the number of points on (within ``drho / 2`` of) that line.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        ``(x, y)`` pixel coordinates, ``0 <= x < width``, ``0 <= y < height``. A point
        listed twice votes twice (a composite of frames is a multiset).
    shape : (int, int)
        ``(height, width)`` of the image.
    drho, dtheta_deg : float
        Resolutions, the paper's ``drho = 2`` pixels and ``dtheta = 1`` degree.
    origin : {"center", "corner"}, keyword-only
        Where ``rho`` is measured from; ``"center"`` is the paper's.
    allow_empty : bool, keyword-only, default False
        Return an all-zero plane for an empty point list instead of raising.

    Returns
    -------
    H : ndarray, shape (len(rhos), len(thetas_deg))
        Vote counts (float).
    rhos : ndarray
        Centres of the ``rho`` bins (:func:`hough_axes`).
    thetas_deg : ndarray
        Sampled angles in degrees.

    Raises
    ------
    ValueError
        If a point lies outside the image, is not finite, the list is empty (unless
        ``allow_empty``), or a resolution is not positive.

    Examples
    --------
    >>> from projtrack.hough import find_peaks, hough_transform
    >>> pts = [(128 + t, 100) for t in range(-20, 21, 4)]  # the line y = 100
    >>> H, rhos, thetas = hough_transform(pts, (256, 256))
    >>> float(H.max()), H.shape
    (11.0, (183, 180))
    >>> [(round(r), round(t)) for r, t in find_peaks(H, rhos, thetas)]
    [(-28, 90)]
    """
    allow_empty = as_bool(allow_empty, "allow_empty")
    shape = as_shape2(shape)
    rhos, thetas = hough_axes(shape, drho, dtheta_deg, origin)
    pts = _check_points(points, shape, allow_empty=allow_empty)
    return _vote(pts, shape, rhos, thetas, float(drho), origin), rhos, thetas


def hough_transform_image(image: object, drho: float = 2.0, dtheta_deg: float = 1.0, *,
                          origin: str = "center") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hough transform of a binary image (every 1 pixel votes), Equation (1).

    ``image[y, x]`` is the pixel at ``(x, y)``. See :func:`hough_transform`.

    Parameters
    ----------
    image : array_like, 2-D
        Binary image (0/1 or bool); its shape is the frame's ``(height, width)``.
    drho, dtheta_deg : float, default 2 and 1
        Resolutions of the plane (pixels, degrees).
    origin : {"center", "corner"}, keyword-only
        Where ``rho`` is measured from (see :func:`hough_axes`).

    Returns
    -------
    H, rhos, thetas_deg : numpy.ndarray
        As :func:`hough_transform`.

    Raises
    ------
    ValueError
        If ``image`` is not 2-D or not binary.
    """
    img = _check_binary_image(image)
    ys, xs = np.nonzero(img)
    pts = np.column_stack([xs, ys]).astype(float)
    return hough_transform(pts, img.shape, drho, dtheta_deg, origin=origin, allow_empty=True)


def thresholded_hough_transform(frames: Sequence[object], shape: tuple[int, int], drho: float = 2.0,
                                dtheta_deg: float = 1.0, *, threshold: float = 1.0,
                                origin: str = "center") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Thresholded Hough transform of Section V: threshold each frame's HT, then sum.

    ``H = sum_k [H_k >= threshold]``. With the default ``threshold = 1`` a line made
    of several points of one frame (a cloud edge, targets that happen to be aligned in
    one frame) counts once, as the paper says ("only one unit of weight"), while a
    track, one point per frame, keeps one vote per frame.

    Parameters
    ----------
    frames : sequence of array_like (N_k, 2)
        The detections of each frame; a frame may be empty.
    shape, drho, dtheta_deg, origin
        As in :func:`hough_transform`.
    threshold : float, keyword-only, default 1
        Cells of a frame's HT at or above it count 1, the others 0.

    Returns
    -------
    H, rhos, thetas_deg
        As in :func:`hough_transform`; ``H`` counts frames.
    """
    shape = as_shape2(shape)
    threshold = as_real(threshold, "threshold", 0, low_open=True)
    rhos, thetas = hough_axes(shape, drho, dtheta_deg, origin)
    pts = _check_frames(frames, shape)
    H = np.zeros((rhos.size, thetas.size))
    for f in pts:
        H += _vote(f, shape, rhos, thetas, float(drho), origin) >= threshold
    return H, rhos, thetas


def rotate_integrate_hough(image: object, drho: float = 2.0, dtheta_deg: float = 1.0, *,
                           origin: str = "center", order: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hough transform as projections of the rotated image, Equations (2)-(3) and Figure
    11.

    The optical processor of Sec. VII rotates the image with a Dove prism and
    integrates it along one axis with a cylindrical lens: the output at angle
    ``theta`` is the projection of the image onto the direction
    ``n = (cos(theta), sin(theta))``, i.e. one column of the HT (Eq. (3)). Here each
    angle is simulated by rotating the image with :func:`scipy.ndimage.rotate`
    (interpolation ``order``), summing along the rotated ``y'`` axis and binning the
    unit-pixel projection into ``drho`` bins.

    Parameters
    ----------
    image : array_like, shape (height, width)
        Binary image, ``image[y, x]``.
    drho, dtheta_deg, origin
        As in :func:`hough_transform`.
    order : int, default 1
        Spline order of the rotation (0 nearest, 1 bilinear).

    Returns
    -------
    H, rhos, thetas_deg
        As in :func:`hough_transform` (real-valued because of interpolation).
    """
    img = _check_binary_image(image).astype(float)
    if order not in (0, 1, 2, 3):
        raise ValueError(f"order must be 0, 1, 2 or 3, got {order!r}")
    shape = img.shape
    rhos, thetas = hough_axes(shape, drho, dtheta_deg, origin)
    drho = float(drho)
    h, w = shape
    cx, cy = _origin_xy(shape, origin)
    # Pad to a square canvas centred on the origin so that rotation keeps everything.
    R = int(ceil(rhos[-1])) + 2
    canvas = np.zeros((2 * R + 1, 2 * R + 1))
    # pixel (x, y) goes to canvas[y - cy + R, x - cx + R] (integer offsets for integer cx, cy)
    ox, oy = int(round(R - cx)), int(round(R - cy))
    canvas[oy:oy + h, ox:ox + w] = img
    shift_x, shift_y = (R - cx) - ox, (R - cy) - oy  # sub-pixel remainder (odd sizes)
    u = np.arange(2 * R + 1) - R - shift_x  # rho coordinate of the canvas columns after rotation
    H = np.zeros((rhos.size, thetas.size))
    edges = np.concatenate([rhos - drho / 2, [rhos[-1] + drho / 2]])
    for j, th in enumerate(thetas):
        # Rotating the image by -theta brings n = (cos, sin) onto the +x (column) axis.
        rot = ndimage.rotate(canvas, th, reshape=False, order=order, mode="constant", cval=0.0)
        proj = rot.sum(axis=0)  # integral along y', Eq. (3)
        H[:, j] = np.histogram(u, bins=edges, weights=proj)[0]
    return H, rhos, thetas


def line_through(points: object, shape: tuple[int, int], *, origin: str = "center") -> tuple[float, float]:
    """Total-least-squares line through ``points`` as ``(rho, theta_deg)`` in the HT's
    convention.

    ``theta_deg`` lies in [0, 180); ``rho`` is measured from the origin of
    :func:`hough_transform`. Used to compare a target's true track with the Hough plane.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        At least two distinct ``(x, y)`` points.
    shape : (int, int)
        ``(height, width)`` of the frames.
    origin : {"center", "corner"}, keyword-only
        As in :func:`hough_transform`.

    Returns
    -------
    (rho, theta_deg) : (float, float)
    """
    shape = as_shape2(shape)
    pts = _check_points(points, shape)
    if pts.shape[0] < 2 or np.all(pts == pts[0]):
        raise ValueError("points must hold at least two distinct points to define a line")
    cx, cy = _origin_xy(shape, _check_origin(origin))
    c = pts.mean(axis=0)
    _, _, vt = np.linalg.svd(pts - c, full_matrices=False)
    n = vt[-1]
    th = float(np.arctan2(n[1], n[0]))
    if th < 0:
        th += np.pi
        n = -n
    if th >= np.pi:
        th -= np.pi
        n = -n
    rho = float((c - np.array([cx, cy])) @ np.array([np.cos(th), np.sin(th)]))
    return rho, float(np.rad2deg(th))

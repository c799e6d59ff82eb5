"""Hough-transform track initiation: Casasent & Slaski (1988).

Implements chapter 3 of Casasent's 1989 report (D. Casasent and J. Slaski, "Optical
track initiator for multitarget tracking", Appl. Opt. 27, 4546, 1988):

* the straight-line Hough transform (HT) in the normal parametrization,
  ``rho = x cos(theta) + y sin(theta)`` (Eq. (1)), as point voting
  (:func:`hough_transform`, :func:`hough_transform_image`) and as the integral of
  Eqs. (2)-(3), a projection of the image at every angle, computed numerically by
  rotating and integrating the image as the Dove-prism processor of Fig. 11 does
  (:func:`rotate_integrate_hough`);
* the thresholded HT of Sec. V (threshold every frame's HT, then sum:
  :func:`thresholded_hough_transform`);
* the peak detector of Sec. VII: ratio of the exact HT to its 5 x 5 local average
  above 3, split peaks bridged at 1.5 provided one cell exceeds 3, adjacent peak cells
  grouped and their centroid taken (:func:`find_peaks`, :func:`detect_peaks`), with a
  documented minimum-vote floor;
* track confirmation and state estimation of Sec. III: the strip of half-width
  ``drho`` along a detected line, its projection at increasing resolutions ``dx'``,
  the pulse correlation with empty samples set to -10, the 75 % rule, the position of
  Eq. (5), the velocity of Eqs. (6)-(7) (with ``P_D`` compensation) and a prediction
  ``k`` frames ahead (:func:`estimate_track`);
* the covariance approximations of Eqs. (8), (9), (12), (13) (:func:`track_covariance`);
* a :class:`TrackInitiator` chaining all of this over a stack of frames.

Conventions
-----------
Points are ``(x, y)`` pixel coordinates in an image of ``shape = (height, width)``
with ``0 <= x < width`` and ``0 <= y < height`` (``x`` along columns, ``y`` along rows;
figures draw ``y`` upwards). ``rho`` is measured from the image centre
``(width / 2, height / 2)``, as in the paper (``rho`` over about +-180 for a 256 x 256
frame, ``theta`` over [0, 180) degrees); ``origin="corner"`` measures it from pixel
(0, 0) instead, which is the convention of :func:`skimage.transform.hough_line`.

The paper prints Eq. (4) as ``x' = x sin(theta) + y cos(theta)``,
``y' = -x cos(theta) + y sin(theta) - rho``, which is not consistent with Eq. (1) (the
``y'`` of a point on the line would not vanish). We use the rotation that is:
``y' = x cos(theta) + y sin(theta) - rho`` (signed distance to the line) and ``x'``
along the line, oriented in the direction of motion.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from math import ceil

import numpy as np
from scipy import ndimage

from projtrack import _fast_hough

__all__ = [
    "hough_axes",
    "hough_transform",
    "hough_transform_image",
    "thresholded_hough_transform",
    "rotate_integrate_hough",
    "local_average",
    "HoughPeak",
    "detect_peaks",
    "find_peaks",
    "strip_projection",
    "pulse_correlation",
    "ProjectionResult",
    "project_and_correlate",
    "track_covariance",
    "TrackEstimate",
    "estimate_track",
    "TrackInitiator",
    "PULSE_ZERO_VALUE",
    "match_lines",
    "evaluate_initiation",
    "accuracy_experiment",
    "line_through",
    "window_neighbours",
]

#: Value given to empty projection samples in the pulse correlation (Sec. III).
PULSE_ZERO_VALUE = -10.0


# ---------------------------------------------------------------------------------
# validation helpers
# ---------------------------------------------------------------------------------
def _check_shape(shape: object) -> tuple[int, int]:
    if not isinstance(shape, (tuple, list)) or len(shape) != 2:
        raise ValueError(f"shape must be a (height, width) pair of positive ints, got {shape!r}")
    out = []
    for s in shape:
        if isinstance(s, bool) or not isinstance(s, (int, np.integer)) or s <= 0:
            raise ValueError(f"shape must be a (height, width) pair of positive ints, got {shape!r}")
        out.append(int(s))
    return out[0], out[1]


def _check_positive(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a positive number, got {type(value).__name__}")
    value = float(value)
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value}")
    return value


def _check_origin(origin: str) -> str:
    if origin not in ("center", "corner"):
        raise ValueError(f"origin must be 'center' or 'corner', got {origin!r}")
    return origin


def _check_points(points: object, shape: tuple[int, int], name: str = "points",
                  allow_empty: bool = False) -> np.ndarray:
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be an (N, 2) array of (x, y) coordinates") from exc
    if pts.size == 0 and pts.ndim <= 2:
        if not allow_empty:
            raise ValueError(f"{name} is empty: there is nothing to transform (pass allow_empty=True "
                             "to get an all-zero Hough plane)")
        return np.zeros((0, 2))
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"{name} must be an (N, 2) array of (x, y) coordinates, got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    h, w = shape
    bad = (pts[:, 0] < 0) | (pts[:, 0] >= w) | (pts[:, 1] < 0) | (pts[:, 1] >= h)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}[{i}] = ({pts[i, 0]:g}, {pts[i, 1]:g}) lies outside the image of "
                         f"shape (height, width) = {shape}: need 0 <= x < {w} and 0 <= y < {h}")
    return pts


def _origin_xy(shape: tuple[int, int], origin: str) -> tuple[float, float]:
    h, w = shape
    return (w / 2.0, h / 2.0) if origin == "center" else (0.0, 0.0)


# ---------------------------------------------------------------------------------
# the Hough transform
# ---------------------------------------------------------------------------------
def hough_axes(shape: tuple[int, int], drho: float = 2.0, dtheta_deg: float = 1.0,
               origin: str = "center") -> tuple[np.ndarray, np.ndarray]:
    """Sample positions of the Hough plane (Sec. II.B).

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
    shape = _check_shape(shape)
    drho = _check_positive(drho, "drho")
    dtheta_deg = _check_positive(dtheta_deg, "dtheta_deg")
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
    return _fast_hough.vote(pts, cx, cy, float(rhos[0]), rhos.size, thetas_deg, drho, weights)


def hough_transform(points: object, shape: tuple[int, int], drho: float = 2.0,
                    dtheta_deg: float = 1.0, *, origin: str = "center",
                    allow_empty: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Straight-line Hough transform of a point list by voting, Eq. (1).

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
    >>> pts = [(128 + t, 100) for t in range(-20, 21, 4)]   # horizontal line y = 100
    >>> H, rhos, thetas = hough_transform(pts, (256, 256))
    >>> float(H.max()), H.shape
    (11.0, (183, 180))
    >>> [(round(r), round(t)) for r, t in find_peaks(H, rhos, thetas)]
    [(-28, 90)]
    """
    shape = _check_shape(shape)
    rhos, thetas = hough_axes(shape, drho, dtheta_deg, origin)
    pts = _check_points(points, shape, allow_empty=allow_empty)
    return _vote(pts, shape, rhos, thetas, float(drho), origin), rhos, thetas


def _check_binary_image(image: object, name: str = "image") -> np.ndarray:
    img = np.asarray(image)
    if img.ndim != 2 or img.size == 0:
        raise ValueError(f"{name} must be a non-empty 2-D array, got shape {img.shape}")
    if img.dtype == bool:
        return img
    if not np.issubdtype(img.dtype, np.number):
        raise TypeError(f"{name} must be a numeric or boolean array, got dtype {img.dtype}")
    if not np.all(np.isin(img, (0, 1))):
        raise ValueError(f"{name} must be binary (only 0 and 1): the Hough transform of Sec. II "
                         "acts on binary detection images")
    return img.astype(bool)


def hough_transform_image(image: object, drho: float = 2.0, dtheta_deg: float = 1.0, *,
                          origin: str = "center") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hough transform of a binary image (every 1 pixel votes), Eq. (1).

    ``image[y, x]`` is the pixel at ``(x, y)``. See :func:`hough_transform`.

    Raises
    ------
    ValueError
        If ``image`` is not 2-D or not binary.
    """
    img = _check_binary_image(image)
    ys, xs = np.nonzero(img)
    pts = np.column_stack([xs, ys]).astype(float)
    return hough_transform(pts, img.shape, drho, dtheta_deg, origin=origin, allow_empty=True)


def _check_frames(frames: object, shape: tuple[int, int]) -> list[np.ndarray]:
    if isinstance(frames, np.ndarray) and frames.ndim == 3 and frames.shape[-1] == 2:
        frames = list(frames)
    if not isinstance(frames, Sequence) or isinstance(frames, (str, bytes)):
        raise TypeError("frames must be a sequence of (N_k, 2) point arrays, one per frame")
    if len(frames) == 0:
        raise ValueError("frames is empty: need at least one frame")
    out = [_check_points(f, shape, name=f"frames[{k}]", allow_empty=True) for k, f in enumerate(frames)]
    if sum(len(f) for f in out) == 0:
        raise ValueError("every frame is empty: there are no detections to transform")
    return out


def thresholded_hough_transform(frames: Sequence[object], shape: tuple[int, int], drho: float = 2.0,
                                dtheta_deg: float = 1.0, *, threshold: float = 1.0,
                                origin: str = "center") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Thresholded Hough transform of Sec. V: threshold each frame's HT, then sum.

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
    shape = _check_shape(shape)
    threshold = _check_positive(threshold, "threshold")
    rhos, thetas = hough_axes(shape, drho, dtheta_deg, origin)
    pts = _check_frames(frames, shape)
    H = np.zeros((rhos.size, thetas.size))
    for f in pts:
        H += _vote(f, shape, rhos, thetas, float(drho), origin) >= threshold
    return H, rhos, thetas


def rotate_integrate_hough(image: object, drho: float = 2.0, dtheta_deg: float = 1.0, *,
                           origin: str = "center", order: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hough transform as projections of the rotated image, Eqs. (2)-(3) and Fig. 11.

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


# ---------------------------------------------------------------------------------
# peak detection (Sec. VII)
# ---------------------------------------------------------------------------------
def _check_plane(H: object, rhos: object, thetas_deg: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        Hf = np.asarray(H, dtype=float)
        r = np.asarray(rhos, dtype=float)
        t = np.asarray(thetas_deg, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError("H, rhos and thetas_deg must be numeric arrays") from exc
    if r.ndim != 1 or t.ndim != 1 or r.size < 2 or t.size < 2:
        raise ValueError("rhos and thetas_deg must be 1-D arrays with at least 2 samples each")
    if Hf.shape != (r.size, t.size):
        raise ValueError(f"H must have shape (len(rhos), len(thetas_deg)) = {(r.size, t.size)}, "
                         f"got {Hf.shape}")
    if not (np.all(np.isfinite(Hf)) and np.all(np.isfinite(r)) and np.all(np.isfinite(t))):
        raise ValueError("H, rhos and thetas_deg must be finite")
    if np.any(Hf < 0):
        raise ValueError("H must be non-negative (vote counts)")
    if np.any(np.diff(r) <= 0) or np.any(np.diff(t) <= 0):
        raise ValueError("rhos and thetas_deg must be strictly increasing")
    return Hf, r, t


def _wraps(rhos: np.ndarray, thetas: np.ndarray) -> bool:
    """True when theta covers [0, 180) uniformly and rho is symmetric: the plane wraps."""
    dt = thetas[1] - thetas[0]
    return (abs(thetas[0]) < 1e-9 and abs(thetas[-1] + dt - 180.0) < 1e-6
            and np.allclose(np.diff(thetas), dt) and np.allclose(rhos, -rhos[::-1]))


def local_average(H: object, size: int = 5, *, rhos: object | None = None,
                  thetas_deg: object | None = None, exclude_ridge: int | None = None) -> np.ndarray:
    """The ``size x size`` local average of the Hough plane (the defocused HT of Sec. VII).

    Outside the plane ``rho`` is padded with zeros; ``theta`` wraps around with
    ``(rho, theta + 180) = (-rho, theta)`` when ``rhos`` and ``thetas_deg`` show that the
    plane covers [0, 180) with a symmetric ``rho`` axis, and is zero-padded otherwise.

    Parameters
    ----------
    H : array_like, 2-D
        Hough plane, ``rho`` along axis 0 and ``theta`` along axis 1.
    size : int, default 5
        Odd side of the window.
    rhos, thetas_deg : array_like, keyword-only, optional
        The plane's axes (used only to decide the wrap-around in ``theta``).
    exclude_ridge : int or None, keyword-only
        ``None`` (default, the paper's defocused HT): the mean over the whole window.
        An int ``r >= 0`` with ``2 r + 1 < size``: the mean over the window without the
        ``2 r + 1`` rows of ``rho`` bins centred on the cell, i.e. without the ridge
        that a line's own votes form along ``theta`` at its ``rho`` (every point of a
        line votes in each ``theta`` column of the window, close to the line's ``rho``).
        What remains measures the background bias of the plane, not the line itself.
        Not the paper's rule; see :func:`detect_peaks`.
    """
    Hf = np.asarray(H, dtype=float)
    if Hf.ndim != 2:
        raise ValueError(f"H must be 2-D, got shape {Hf.shape}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 1 or size % 2 == 0:
        raise ValueError(f"size must be a positive odd int, got {size!r}")
    k = size // 2
    if exclude_ridge is not None:
        if isinstance(exclude_ridge, bool) or not isinstance(exclude_ridge, (int, np.integer)) \
                or exclude_ridge < 0 or 2 * exclude_ridge + 1 >= size:
            raise ValueError(f"exclude_ridge must be None or an int r >= 0 with 2 r + 1 < size ({size}), "
                             f"got {exclude_ridge!r}")
    wrap = False
    if rhos is not None and thetas_deg is not None:
        _, r, t = _check_plane(Hf, rhos, thetas_deg)
        wrap = _wraps(r, t)
    if wrap and k > 0:
        left, right = Hf[::-1, -k:], Hf[::-1, :k]
        padded = np.concatenate([left, Hf, right], axis=1)
    else:
        padded = np.pad(Hf, ((0, 0), (k, k)))
    padded = np.pad(padded, ((k, k), (0, 0)))
    avg = ndimage.uniform_filter(padded, size=size, mode="constant", cval=0.0)
    if exclude_ridge is None:
        return avg[k:k + Hf.shape[0], k:k + Hf.shape[1]]
    r = int(exclude_ridge)
    ridge = ndimage.uniform_filter(padded, size=(2 * r + 1, size), mode="constant", cval=0.0)
    total = avg * size * size - ridge * (2 * r + 1) * size
    out = total / ((size - 2 * r - 1) * size)
    out = out[k:k + Hf.shape[0], k:k + Hf.shape[1]]
    return np.where(np.abs(out) < 1e-9 * max(1.0, float(np.abs(Hf).max(initial=0.0))), 0.0, out)


@dataclass(frozen=True)
class HoughPeak:
    """One detected line: the centroid of a group of peak cells.

    Attributes
    ----------
    rho, theta_deg : float
        Centroid of the group (weighted by the votes), the line's parameters.
    votes : float
        Largest cell value of the group.
    ratio : float
        Largest ratio of exact to averaged HT in the group.
    n_cells : int
        Number of cells in the group.
    """

    rho: float
    theta_deg: float
    votes: float
    ratio: float
    n_cells: int


def detect_peaks(H: object, rhos: object, thetas_deg: object, *, ratio: float = 3.0,
                 bridge: float = 1.5, min_votes: float = 3.0, size: int = 5,
                 exclude_ridge: int | None = None) -> list[HoughPeak]:
    """Peak detector of Sec. VII with a minimum-vote floor; see :func:`find_peaks`.

    ``exclude_ridge`` (default ``None``, the paper's rule) is passed to
    :func:`local_average`: with ``exclude_ridge=1`` the ratio compares a cell with the
    mean of its ``5 x 5`` window without the three ``rho`` rows through it, i.e. with the
    background of the plane rather than with the line's own ridge. For an ideal line of
    ``N`` votes on a bias ``b`` the paper's ratio is ``N / (N/5 + b) < 5``, the
    ridge-free one ``N / b``.

    Returns
    -------
    list of HoughPeak
        Sorted by decreasing ``votes`` (then ``ratio``).
    """
    Hf, r, t = _check_plane(H, rhos, thetas_deg)
    ratio = _check_positive(ratio, "ratio")
    bridge = _check_positive(bridge, "bridge")
    if bridge > ratio:
        raise ValueError(f"bridge ({bridge}) must not exceed ratio ({ratio})")
    if isinstance(min_votes, bool) or not isinstance(min_votes, (int, float, np.integer, np.floating)) \
            or not np.isfinite(min_votes) or min_votes < 0:
        raise ValueError(f"min_votes must be a non-negative number, got {min_votes!r}")
    avg = local_average(Hf, size, rhos=r, thetas_deg=t, exclude_ridge=exclude_ridge)
    with np.errstate(divide="ignore", invalid="ignore"):
        # an empty neighbourhood (possible only with exclude_ridge) under a voted cell: infinite ratio
        R = np.where(avg > 0, Hf / np.where(avg > 0, avg, 1.0), np.where(Hf > 0, np.inf, 0.0))
    ok = Hf >= max(float(min_votes), np.finfo(float).tiny)
    strong = (R > ratio) & ok
    weak = (R > bridge) & ok
    labels, n = ndimage.label(weak, structure=np.ones((3, 3), dtype=bool))
    if n == 0:
        return []
    wrap = _wraps(r, t)
    seam = np.zeros(n + 1, dtype=bool)
    if wrap:  # join groups across theta = 0 / 180, where (rho, 180) is (-rho, 0)
        parent = np.arange(n + 1)

        def root(a: int) -> int:
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        first, last = labels[:, 0], labels[::-1, -1]  # last column mirrored in rho
        for k in (-1, 0, 1):
            a = first[max(0, k):first.size + min(0, k)]
            b = last[max(0, -k):last.size + min(0, -k)]
            for u, v in zip(a[(a > 0) & (b > 0)], b[(a > 0) & (b > 0)]):
                ru, rv = root(int(u)), root(int(v))
                if ru != rv:
                    parent[max(ru, rv)] = min(ru, rv)
                seam[ru] = seam[rv] = True
        roots = np.array([root(a) for a in range(n + 1)])
        seam = seam[roots]
        labels = roots[labels]
    ii, jj = np.nonzero(labels)
    lab = labels[ii, jj]
    h, rr, tt, rat = Hf[ii, jj], r[ii], t[jj], R[ii, jj]
    if wrap and seam.any():  # express seam groups on theta in (-90, 90)
        flip = seam[lab] & (tt > 90.0)
        rr = np.where(flip, -rr, rr)
        tt = np.where(flip, tt - 180.0, tt)
    sc = strong[ii, jj]
    has_strong = np.bincount(lab, weights=sc, minlength=n + 1) > 0
    # The centroid is taken over the peak points (ratio above 3) of the group; the
    # bridging cells (ratio above 1.5) only join split peaks into one group.
    hs = h * sc
    wsum = np.bincount(lab, weights=hs, minlength=n + 1)
    rho_c = np.bincount(lab, weights=hs * rr, minlength=n + 1)
    th_c = np.bincount(lab, weights=hs * tt, minlength=n + 1)
    ncell = np.bincount(lab, minlength=n + 1)
    vmax = np.zeros(n + 1)
    np.maximum.at(vmax, lab, h)
    rmax = np.zeros(n + 1)
    np.maximum.at(rmax, lab, rat)
    keep = np.flatnonzero(has_strong & (wsum > 0))
    if keep.size == 0:
        return []
    peaks = []
    for k in keep:
        rho_k, th_k = rho_c[k] / wsum[k], th_c[k] / wsum[k]
        if th_k < 0:
            rho_k, th_k = -rho_k, th_k + 180.0
        peaks.append(HoughPeak(float(rho_k), float(th_k), float(vmax[k]), float(rmax[k]), int(ncell[k])))
    peaks.sort(key=lambda p: (-p.votes, -p.ratio, p.theta_deg, p.rho))
    if wrap:  # one line seen at both ends of the theta axis: keep the stronger group
        dr, dt = r[1] - r[0], t[1] - t[0]
        kept: list[HoughPeak] = []
        for p in peaks:
            dup = any(abs(abs(p.theta_deg - q.theta_deg) - 180.0) <= 2 * dt and abs(p.rho + q.rho) <= 2 * dr
                      for q in kept)
            if not dup:
                kept.append(p)
        peaks = kept
    return peaks


def find_peaks(H: object, rhos: object, thetas_deg: object, *, ratio: float = 3.0, bridge: float = 1.5,
               min_votes: float = 3.0, size: int = 5) -> list[tuple[float, float]]:
    """Lines of a Hough plane by the ratio rule of Sec. VII.

    A cell is a peak cell when the ratio of the exact HT to its ``5 x 5`` local average
    (:func:`local_average`, the optically defocused HT) exceeds ``ratio = 3``. Peaks
    that split are bridged: the cells whose ratio exceeds ``bridge = 1.5`` are grouped
    by 8-adjacency and a group is kept when at least one of its cells exceeds 3. Each
    group gives one line at its vote-weighted centroid.

    The minimum-vote floor. On a sparse accumulator the ratio alone flags cells with
    one or two votes surrounded by empty cells (the paper's Hough plane sat on a large
    bias, so this could not happen there). Any two points define a line, so a cell
    with two votes is no evidence of collinearity; the default floor ``min_votes = 3``
    is the smallest count that is. :class:`TrackInitiator` raises it to a quarter of
    the number of frames of the composite (a track must have been seen in at least a
    quarter of the frames), one rule for every experiment.

    Parameters
    ----------
    H : array_like, shape (len(rhos), len(thetas_deg))
        Non-negative Hough plane (e.g. from :func:`hough_transform`).
    rhos, thetas_deg : array_like
        Its axes, strictly increasing.
    ratio, bridge : float, keyword-only
        The paper's thresholds, 3 and 1.5.
    min_votes : float, keyword-only, default 3
        Cells with fewer votes are never peak cells.
    size : int, keyword-only, default 5
        Side of the averaging window.

    Returns
    -------
    list of (rho, theta_deg)
        One pair of floats per detected line, strongest first.
    """
    return [(p.rho, p.theta_deg) for p in detect_peaks(H, rhos, thetas_deg, ratio=ratio, bridge=bridge,
                                                       min_votes=min_votes, size=size)]


# ---------------------------------------------------------------------------------
# track confirmation and state estimation (Sec. III)
# ---------------------------------------------------------------------------------
def _line_frame(theta_deg: float, heading_hint: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """Unit normal ``n`` and unit direction ``d`` (oriented along ``heading_hint``)."""
    t = np.deg2rad(theta_deg)
    n = np.array([np.cos(t), np.sin(t)])
    d = np.array([-np.sin(t), np.cos(t)])
    hint = np.asarray(heading_hint, dtype=float)
    s = float(d @ hint)
    if s < 0 or (s == 0 and float(np.array([1.0, 1e-6]) @ d) < 0):
        d = -d
    return n, d


def _check_hint(heading_hint: object) -> np.ndarray:
    h = np.asarray(heading_hint, dtype=float)
    if h.shape != (2,) or not np.all(np.isfinite(h)) or not np.any(h != 0):
        raise ValueError(f"heading_hint must be a non-zero finite 2-vector, got {heading_hint!r}")
    return h


def strip_projection(points: object, shape: tuple[int, int], rho: float, theta_deg: float, *,
                     half_width: float = 2.0, heading_hint: Sequence[float] = (0.0, 1.0),
                     origin: str = "center") -> tuple[np.ndarray, float, np.ndarray]:
    """Projection at ``dx' = 1`` of the strip ``|y'| <= half_width`` along a line (Fig. 1(a)-(c)).

    In the rotated frame of the detected line, ``y' = x cos(theta) + y sin(theta) - rho``
    (signed distance) and ``x'`` runs along the line in the direction ``d`` that points
    along ``heading_hint`` (the prior direction of motion: boost-phase targets climb,
    so the default is +y). The strip points are binned at unit resolution in ``x'``.

    Returns
    -------
    counts : ndarray of int
        ``P_j`` at ``dx' = 1``: strip points per unit bin, bin 0 starting at ``x0``.
    x0 : float
        ``x'`` of the start of bin 0 (the image's farthest extent backwards along ``d``).
    direction : ndarray, shape (2,)
        The unit vector ``d`` of increasing ``x'``.
    """
    shape = _check_shape(shape)
    _check_origin(origin)
    pts = _check_points(points, shape, allow_empty=True)
    half_width = _check_positive(half_width, "half_width")
    hint = _check_hint(heading_hint)
    if not (np.isfinite(rho) and np.isfinite(theta_deg)):
        raise ValueError("rho and theta_deg must be finite")
    n, d = _line_frame(float(theta_deg), hint)
    cx, cy = _origin_xy(shape, origin)
    rmax = float(np.hypot(max(cx, shape[1] - cx), max(cy, shape[0] - cy)))
    x0 = -float(np.ceil(rmax)) - 1.0
    nbins = int(2 * (np.ceil(rmax) + 1)) + 1
    counts = np.zeros(nbins, dtype=np.int64)
    if pts.shape[0]:
        rel = pts - np.array([cx, cy])
        yp = rel @ n - rho
        xp = rel @ d
        inside = np.abs(yp) <= half_width
        b = np.floor(xp[inside] - x0).astype(np.int64)
        counts = np.bincount(np.clip(b, 0, nbins - 1), minlength=nbins).astype(np.int64)
    return counts, x0, d


def pulse_correlation(P: object, zero_value: float = PULSE_ZERO_VALUE) -> tuple[float, int, int]:
    """Best correlation of a projection with a unit pulse of any width ``L`` (Sec. III).

    Empty samples ``P_j = 0`` are replaced by ``zero_value`` (-10 in the paper) so that
    the best window is a contiguous run of non-empty samples; correlating with pulses of
    every width ``L`` and taking the largest peak is the maximum-sum window, found here
    by Kadane's algorithm.

    Returns
    -------
    I : float
        The correlation peak (sum of the ``P_j`` in the window).
    start, L : int
        First index and width of the window (the leading edge is ``start + L``).
        Among equal sums the latest window (largest index), then the shortest, wins.
    """
    p = np.asarray(P, dtype=float)
    if p.ndim != 1 or p.size == 0:
        raise ValueError("P must be a non-empty 1-D array")
    if not np.all(np.isfinite(p)) or np.any(p < 0):
        raise ValueError("P must be finite and non-negative (projection counts)")
    if not np.any(p > 0):
        return 0.0, 0, 0
    q = np.where(p > 0, p, float(zero_value))
    S = np.concatenate([[0.0], np.cumsum(q)])
    # For every end b the best start a <= b minimises S[a]; the latest such a gives the
    # shortest window, and the latest best end wins among equal sums.
    cmin = np.minimum.accumulate(S[:-1])
    vals = S[1:] - cmin
    best = float(vals.max())
    best_end = int(np.flatnonzero(vals == best)[-1])
    best_start = int(np.flatnonzero(S[:best_end + 1] == cmin[best_end])[-1])
    return float(best), int(best_start), int(best_end - best_start + 1)


@dataclass(frozen=True)
class ProjectionResult:
    """Outcome of the projection/pulse procedure of Sec. III on one line.

    Attributes
    ----------
    confirmed : bool
        The 75 % rule was met at some ``dx' <= dx_max``.
    n_ones : int
        Strip points at ``dx' = 1`` (the "number of ones").
    dx : int
        Resolution at which the procedure stopped (the last one tried if not confirmed).
    I : float
        Correlation peak at ``dx``.
    L : int
        Width of the best pulse, in samples of ``dx``.
    j : int
        Index of the leading sample of the pulse (its leading edge is ``j + 1``).
    P_j : float
        Projection value at ``j`` (the most recent target sample).
    x_prime : float
        Position along the line, Eq. (5), in the ``x'`` coordinate of :func:`strip_projection`.
    history : tuple of (dx, I, L)
        The correlation peak at every resolution tried.
    """

    confirmed: bool
    n_ones: int
    dx: int
    I: float
    L: int
    j: int
    P_j: float
    x_prime: float
    history: tuple = field(default_factory=tuple)


def project_and_correlate(counts: object, x0: float = 0.0, *, dx_max: int = 16,
                          confirm_fraction: float = 0.75,
                          zero_value: float = PULSE_ZERO_VALUE,
                          stop_fraction: float | None = None,
                          dx_schedule: str = "double") -> ProjectionResult:
    """Increase ``dx'`` until the 75 % rule holds, then apply Eq. (5) (Sec. III, Fig. 1(c)).

    The ``dx' = 1`` projection is summed in pairs (``dx' = 2, 4, 8, ...``) up to
    ``dx_max`` (16 in Sec. V). At each resolution the projection is correlated with
    pulses of every width (:func:`pulse_correlation`); the procedure stops at the
    first ``dx'`` whose peak ``I`` is at least ``confirm_fraction`` of the number of
    ones at ``dx' = 1``. The position is Eq. (5),
    ``x' = x0 + dx' [j + (P_j - 0.5) L / I]``, with ``j`` the leading sample.

    Parameters
    ----------
    counts : array_like of int
        ``P_j`` at ``dx' = 1`` (from :func:`strip_projection`).
    x0 : float
        ``x'`` of the start of sample 0.
    dx_max : int, keyword-only, default 16
        Largest resolution tried (a power of two).
    confirm_fraction : float, keyword-only, default 0.75
        The paper's 75 % rule.
    zero_value : float, keyword-only, default -10
        Value of empty samples in the correlation.
    stop_fraction : float or None, keyword-only
        Fraction of the ones the best run must hold for the doubling of ``dx'`` to stop;
        ``None`` (default, the paper's procedure) means ``confirm_fraction``. With
        ``stop_fraction=1`` the procedure keeps doubling ``dx'`` until one run holds all
        the ones (or ``dx_max`` is reached), so that a run ending before the newest
        sample cannot be taken for the track; the confirmation still uses
        ``confirm_fraction``. Not the paper's rule.
    dx_schedule : {"double", "step"}, keyword-only, default "double"
        How ``dx'`` grows: ``"double"`` (1, 2, 4, ..., the paper's Fig. 1) or ``"step"``
        (1, 2, 3, ..., ``dx_max``: samples of ``dx'`` consecutive ``dx' = 1`` samples).
        With ``"step"`` ``dx_max`` may be any integer >= 1.

    Returns
    -------
    ProjectionResult

    Raises
    ------
    ValueError
        If ``counts`` is empty, not 1-D, negative or not finite, or all zero (an empty
        strip has no run of ones: neither the 75 % test nor Eq. (5) is defined).
    """
    c = np.asarray(counts)
    if c.ndim != 1 or c.size == 0 or not np.all(np.isfinite(c)) or np.any(c < 0):
        raise ValueError("counts must be a non-empty 1-D array of non-negative counts")
    if dx_schedule not in ("double", "step"):
        raise ValueError(f"dx_schedule must be 'double' or 'step', got {dx_schedule!r}")
    if isinstance(dx_max, bool) or not isinstance(dx_max, (int, np.integer)) or dx_max < 1 \
            or (dx_schedule == "double" and (dx_max & (dx_max - 1)) != 0):
        raise ValueError(f"dx_max must be an integer >= 1 (a power of two when doubling), got {dx_max!r}")
    if not (0 < confirm_fraction <= 1):
        raise ValueError(f"confirm_fraction must be in (0, 1], got {confirm_fraction!r}")
    stop = confirm_fraction if stop_fraction is None else stop_fraction
    if isinstance(stop, bool) or not isinstance(stop, (int, float, np.integer, np.floating)) or not (0 < stop <= 1):
        raise ValueError(f"stop_fraction must be None or in (0, 1], got {stop_fraction!r}")
    c = c.astype(float)
    n_ones = int(round(c.sum()))
    if n_ones == 0:
        raise ValueError("counts are all zero (an empty strip): there is no run to correlate and no "
                         "position x' to estimate")
    history = []
    dx = 1
    P = c
    while True:
        I, start, L = pulse_correlation(P, zero_value)
        history.append((dx, I, L))
        if I >= stop * n_ones or dx >= dx_max:
            break
        if dx_schedule == "double":
            if P.size % 2:
                P = np.append(P, 0.0)
            P = P.reshape(-1, 2).sum(axis=1)
            dx *= 2
        else:
            dx += 1
            P = np.append(c, np.zeros(-c.size % dx)).reshape(-1, dx).sum(axis=1)
    confirmed = I >= confirm_fraction * n_ones
    j = start + L - 1
    P_j = float(P[j])
    x_prime = float(x0 + dx * (j + (P_j - 0.5) * L / I))  # Eq. (5); I >= 1 since some P_j > 0
    return ProjectionResult(bool(confirmed), n_ones, int(dx), float(I), int(L), int(j), P_j, x_prime,
                            tuple(history))


def track_covariance(speed: float, frame_time: float, n_frames: int, *, drho: float = 2.0,
                     jitter_sigma: float = 0.5, total_time: float | None = None) -> dict[str, float]:
    """Variances of the track estimates, Eqs. (8), (9), (12), (13) of Sec. VI.

    Parameters
    ----------
    speed : float
        Estimated speed ``v_x`` along the track, pixels per second.
    frame_time : float
        ``T``, seconds between frames.
    n_frames : int
        ``N_p``, the number of frames (samples) in the composite.
    drho : float, keyword-only
        HT resolution, the strip half-width.
    jitter_sigma : float, keyword-only
        ``sigma_j``, sensor jitter in pixels.
    total_time : float, keyword-only
        ``T_T``; default ``n_frames * frame_time``.

    Returns
    -------
    dict
        ``var_x``: ``(v_x T)^2 / 12 + sigma_j^2`` (Eq. (8); the paper's ``v_x^2 / 4(3)``
        with ``v_x`` the displacement per frame, as the text derives it: uniform over
        ``+-v_x T / 2``), ``var_y``: ``drho^2 / 3`` (Eq. (9)), ``var_vx``:
        ``v_x^2 / (3 N_p^2) + sigma_j^2 / (N_p^2 T^2)`` (Eq. (12)), ``var_vy``:
        ``4 drho^2 / (3 T_T^2)`` (Eq. (13)).
    """
    if not np.isfinite(speed) or speed < 0:
        raise ValueError(f"speed must be a non-negative finite number, got {speed!r}")
    T = _check_positive(frame_time, "frame_time")
    if isinstance(n_frames, bool) or not isinstance(n_frames, (int, np.integer)) or n_frames < 1:
        raise ValueError(f"n_frames must be a positive int, got {n_frames!r}")
    drho = _check_positive(drho, "drho")
    if not np.isfinite(jitter_sigma) or jitter_sigma < 0:
        raise ValueError(f"jitter_sigma must be non-negative, got {jitter_sigma!r}")
    TT = n_frames * T if total_time is None else _check_positive(total_time, "total_time")
    Np = float(n_frames)
    return {
        "var_x": (speed * T) ** 2 / 12.0 + jitter_sigma ** 2,
        "var_y": drho ** 2 / 3.0,
        "var_vx": speed ** 2 / (3.0 * Np ** 2) + jitter_sigma ** 2 / (Np ** 2 * T ** 2),
        "var_vy": 4.0 * drho ** 2 / (3.0 * TT ** 2),
    }


@dataclass(frozen=True)
class TrackEstimate:
    """A line found by the HT and the state estimated from its strip (Sec. III).

    Attributes
    ----------
    rho, theta_deg, votes : float
        The Hough peak.
    confirmed : bool
        Passed the 75 % projection test.
    position : ndarray (2,)
        ``(x, y)`` of the most recent target sample (Eq. (5) placed on the line).
    velocity : ndarray (2,)
        ``(v_x, v_y)`` pixels per second (Eqs. (6)-(7)), along the line.
    speed : float
        ``|velocity|``.
    covariance : ndarray (4, 4)
        Covariance of ``(x, y, v_x, v_y)`` from Eqs. (8), (9), (12), (13), rotated
        from the line's ``(x', y')`` frame to image axes.
    direction : ndarray (2,)
        Unit vector of ``x'``.
    projection : ProjectionResult
        Details of the projection procedure.
    frame_time : float
        ``T``.
    """

    rho: float
    theta_deg: float
    votes: float
    confirmed: bool
    position: np.ndarray
    velocity: np.ndarray
    speed: float
    covariance: np.ndarray
    direction: np.ndarray
    projection: ProjectionResult
    frame_time: float

    def predict(self, k: int | float) -> np.ndarray:
        """Position ``k`` frames after the most recent one, at constant velocity."""
        if not np.isfinite(k):
            raise ValueError("k must be finite")
        return self.position + self.velocity * float(k) * self.frame_time


def estimate_track(points: object, shape: tuple[int, int], rho: float, theta_deg: float, *,
                   frame_time: float, n_frames: int, drho: float = 2.0, p_detect: float = 1.0,
                   jitter_sigma: float = 0.5, dx_max: int = 16, confirm_fraction: float = 0.75,
                   heading_hint: Sequence[float] = (0.0, 1.0), votes: float = float("nan"),
                   origin: str = "center", stop_fraction: float | None = None,
                   dx_schedule: str = "double") -> TrackEstimate:
    """Confirm one HT line and estimate the target's state (Sec. III and VI).

    Projects the strip ``|y'| <= drho`` of the composite ``points``
    (:func:`strip_projection`), runs the ``dx'``/pulse procedure
    (:func:`project_and_correlate`), and estimates the position by Eq. (5) and the
    speed by Eq. (7), ``v = dx' P_D L / (I T)`` (Eq. (6) when ``P_D = 1``); the
    velocity points along the line in the direction of ``heading_hint``. The
    covariance is :func:`track_covariance` rotated to image axes. ``stop_fraction`` and
    ``dx_schedule`` are passed to :func:`project_and_correlate` (``None`` and
    ``"double"``: the paper's 75 % stopping rule and doubling of ``dx'``).

    Raises
    ------
    ValueError
        If an input is invalid, or if the strip ``|y'| <= drho`` around the line holds
        none of ``points`` (there is then no track to confirm or estimate; use
        :func:`strip_projection` to test a line first).
    """
    shape = _check_shape(shape)
    T = _check_positive(frame_time, "frame_time")
    if not (0 < p_detect <= 1):
        raise ValueError(f"p_detect must be in (0, 1], got {p_detect!r}")
    counts, x0, d = strip_projection(points, shape, rho, theta_deg, half_width=drho,
                                     heading_hint=heading_hint, origin=origin)
    if not np.any(counts):
        raise ValueError(f"the strip |y'| <= {drho:g} around the line (rho={float(rho):g}, "
                         f"theta_deg={float(theta_deg):g}) holds none of the points: no track to estimate")
    res = project_and_correlate(counts, x0, dx_max=dx_max, confirm_fraction=confirm_fraction,
                                stop_fraction=stop_fraction, dx_schedule=dx_schedule)
    t = np.deg2rad(theta_deg)
    n = np.array([np.cos(t), np.sin(t)])
    cx, cy = _origin_xy(shape, origin)
    speed = res.dx * p_detect * res.L / res.I / T  # Eq. (7); Eq. (6) for P_D = 1
    position = np.array([cx, cy]) + res.x_prime * d + rho * n
    cov = track_covariance(speed, T, n_frames, drho=drho, jitter_sigma=jitter_sigma)
    Rm = np.column_stack([d, n])  # columns: x' and y' axes in image coordinates
    P = Rm @ np.diag([cov["var_x"], cov["var_y"]]) @ Rm.T
    V = Rm @ np.diag([cov["var_vx"], cov["var_vy"]]) @ Rm.T
    C = np.zeros((4, 4))
    C[:2, :2], C[2:, 2:] = P, V
    return TrackEstimate(float(rho), float(theta_deg), float(votes), res.confirmed, position, speed * d,
                         float(speed), C, d, res, T)


# ---------------------------------------------------------------------------------
# the initiator
# ---------------------------------------------------------------------------------
class TrackInitiator:
    """Hough-transform track initiator of Casasent & Slaski (Secs. II-V).

    :meth:`initiate` forms the composite of a stack of frames, its Hough transform
    (plain, or thresholded as in Sec. V), detects the peaks (:func:`detect_peaks`),
    and confirms and estimates a track for every peak (:func:`estimate_track`).

    Parameters
    ----------
    drho, dtheta_deg : float
        HT resolutions (2 pixels, 1 degree).
    thresholded : bool, default False
        Use the thresholded HT of Sec. V.
    ratio, bridge : float
        Peak-detection thresholds (3 and 1.5).
    min_votes : float or None
        Minimum-vote floor of the peak detector; ``None`` (default) means
        ``max(3, ceil(n_frames / 4))``: a track must have been seen in at least a
        quarter of the frames of the composite. One rule for every experiment.
    p_detect : float
        ``P_D`` used in the velocity compensation of Eq. (7).
    jitter_sigma : float
        ``sigma_j`` used in the covariances of Eqs. (8) and (12).
    dx_max : int
        Largest projection resolution (16 in Sec. V).
    confirm_fraction : float
        The 75 % rule.
    heading_hint : (float, float)
        Prior direction of motion used to orient ``x'`` (climbing targets: +y).
    exclude_ridge : int or None
        Neighbourhood of the peak detector (:func:`detect_peaks`): ``None`` (default)
        the paper's full ``5 x 5`` window; ``1`` the window without the line's own
        ``rho`` ridge (not the paper's rule).

    Attributes
    ----------
    H_ : ndarray
        The Hough plane of the last :meth:`initiate` call.
    rhos_ : ndarray
        Its ``rho`` axis.
    thetas_deg_ : ndarray
        Its ``theta`` axis, degrees.
    peaks_ : list of HoughPeak
        The detected peaks.
    tracks_ : list of TrackEstimate
        One per peak whose strip holds at least one point, confirmed or not.
    empty_peaks_ : list of HoughPeak
        Peaks whose strip ``|y'| <= drho`` holds no point of the composite (possible
        only for a peak interpolated between cells); they are neither confirmed nor
        estimated, since :func:`estimate_track` rejects an empty strip.
    frame_time_ : float
        The frame time ``T`` of the last stack.
    """

    def __init__(self, *, drho: float = 2.0, dtheta_deg: float = 1.0, thresholded: bool = False,
                 ratio: float = 3.0, bridge: float = 1.5, min_votes: float | None = None,
                 p_detect: float = 1.0, jitter_sigma: float = 0.5, dx_max: int = 16,
                 confirm_fraction: float = 0.75, heading_hint: Sequence[float] = (0.0, 1.0),
                 exclude_ridge: int | None = None):
        self.drho = _check_positive(drho, "drho")
        self.dtheta_deg = _check_positive(dtheta_deg, "dtheta_deg")
        self.thresholded = bool(thresholded)
        self.ratio = _check_positive(ratio, "ratio")
        self.bridge = _check_positive(bridge, "bridge")
        if min_votes is not None and (not np.isfinite(min_votes) or min_votes < 0):
            raise ValueError(f"min_votes must be None or a non-negative number, got {min_votes!r}")
        self.min_votes = min_votes
        if not (0 < p_detect <= 1):
            raise ValueError(f"p_detect must be in (0, 1], got {p_detect!r}")
        self.p_detect = float(p_detect)
        if not np.isfinite(jitter_sigma) or jitter_sigma < 0:
            raise ValueError(f"jitter_sigma must be non-negative, got {jitter_sigma!r}")
        self.jitter_sigma = float(jitter_sigma)
        if isinstance(dx_max, bool) or not isinstance(dx_max, (int, np.integer)) or dx_max < 1 \
                or (dx_max & (dx_max - 1)) != 0:
            raise ValueError(f"dx_max must be a power of two >= 1, got {dx_max!r}")
        self.dx_max = int(dx_max)
        if not (0 < confirm_fraction <= 1):
            raise ValueError(f"confirm_fraction must be in (0, 1], got {confirm_fraction!r}")
        self.confirm_fraction = float(confirm_fraction)
        self.heading_hint = tuple(_check_hint(heading_hint))
        if exclude_ridge is not None and (isinstance(exclude_ridge, bool)
                                          or not isinstance(exclude_ridge, (int, np.integer))
                                          or not 0 <= exclude_ridge < 2):
            raise ValueError(f"exclude_ridge must be None, 0 or 1 (5 x 5 window), got {exclude_ridge!r}")
        self.exclude_ridge = exclude_ridge

    @staticmethod
    def default_min_votes(n_frames: int) -> int:
        """The floor used when ``min_votes is None``: ``max(3, ceil(n_frames / 4))``."""
        return max(3, int(ceil(n_frames / 4)))

    def _check_times(self, times: object, n: int) -> float:
        t = np.asarray(times, dtype=float)
        if t.ndim != 1 or t.size != n:
            raise ValueError(f"times must be a 1-D array with one time per frame ({n}), got shape {t.shape}")
        if not np.all(np.isfinite(t)):
            raise ValueError("times must be finite")
        if n == 1:
            raise ValueError("need at least two frames (and their times) to estimate a velocity")
        dt = np.diff(t)
        if np.any(dt <= 0):
            raise ValueError("times must be strictly increasing")
        T = float(dt.mean())
        if np.max(np.abs(dt - T)) > 1e-6 * max(1.0, T):
            raise ValueError("times must be evenly spaced (a constant frame time T); got spacings from "
                             f"{dt.min():g} to {dt.max():g}")
        return T

    def hough(self, frames: Sequence[object], shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The HT stage alone: plain HT of the composite, or the thresholded HT."""
        shape = _check_shape(shape)
        pts = _check_frames(frames, shape)
        if self.thresholded:
            return thresholded_hough_transform(pts, shape, self.drho, self.dtheta_deg)
        comp = np.concatenate(pts, axis=0)
        return hough_transform(comp, shape, self.drho, self.dtheta_deg)

    def initiate(self, frames: Sequence[object], times: object, shape: tuple[int, int]) -> list[TrackEstimate]:
        """Detect lines in the composite of ``frames`` and estimate their tracks.

        Parameters
        ----------
        frames : sequence of array_like (N_k, 2)
            Detections (``(x, y)`` pixels) of each frame, in time order.
        times : array_like
            Time of each frame, strictly increasing and evenly spaced (``T``).
        shape : (int, int)
            ``(height, width)`` of the frames.

        Returns
        -------
        list of TrackEstimate
            The confirmed tracks (all lines with their verdict are in ``tracks_``).
            Positions refer to the last frame of the stack.
        """
        shape = _check_shape(shape)
        pts = _check_frames(frames, shape)
        T = self._check_times(times, len(pts))
        n = len(pts)
        H, rhos, thetas = self.hough(pts, shape)
        floor = self.default_min_votes(n) if self.min_votes is None else self.min_votes
        peaks = detect_peaks(H, rhos, thetas, ratio=self.ratio, bridge=self.bridge, min_votes=floor,
                             exclude_ridge=self.exclude_ridge)
        comp = np.concatenate(pts, axis=0)
        tracks, empty = [], []
        for p in peaks:
            counts, _, _ = strip_projection(comp, shape, p.rho, p.theta_deg, half_width=self.drho,
                                            heading_hint=self.heading_hint)
            if not np.any(counts):  # possible only for a peak bridged between cells: nothing to project
                empty.append(p)
                continue
            tracks.append(estimate_track(comp, shape, p.rho, p.theta_deg, frame_time=T, n_frames=n,
                                         drho=self.drho, p_detect=self.p_detect, jitter_sigma=self.jitter_sigma,
                                         dx_max=self.dx_max, confirm_fraction=self.confirm_fraction,
                                         heading_hint=self.heading_hint, votes=p.votes))
        self.H_, self.rhos_, self.thetas_deg_ = H, rhos, thetas
        self.peaks_, self.tracks_, self.frame_time_ = peaks, tracks, T
        self.empty_peaks_ = empty
        return [t for t in tracks if t.confirmed]


# ---------------------------------------------------------------------------------
# scoring against ground truth (used by the book's experiments)
# ---------------------------------------------------------------------------------
def match_lines(lines: Sequence[tuple[float, float]], points: object, labels: object,
                shape: tuple[int, int], *, drho: float = 2.0, min_fraction: float = 0.5,
                origin: str = "center") -> np.ndarray:
    """Which target (if any) each detected line belongs to.

    A line ``(rho, theta_deg)`` belongs to target ``i`` when at least ``min_fraction``
    of the detections labelled ``i`` lie in its strip ``|y'| <= drho``; among several
    such targets the one with the largest fraction wins.

    Parameters
    ----------
    lines : sequence of (rho, theta_deg)
    points : array_like (N, 2)
        Composite detections.
    labels : array_like (N,)
        Target index of each detection, negative for false pixels.

    Returns
    -------
    ndarray of int
        Target index per line, -1 for a false line.
    """
    shape = _check_shape(shape)
    pts = _check_points(points, shape, allow_empty=True)
    lab = np.asarray(labels)
    if lab.shape != (pts.shape[0],):
        raise ValueError(f"labels must have one entry per point ({pts.shape[0]}), got shape {lab.shape}")
    if not (0 < min_fraction <= 1):
        raise ValueError(f"min_fraction must be in (0, 1], got {min_fraction!r}")
    cx, cy = _origin_xy(shape, origin)
    rel = pts - np.array([cx, cy])
    ids = np.unique(lab[lab >= 0])
    out = np.full(len(lines), -1, dtype=int)
    for k, (rho, th) in enumerate(lines):
        t = np.deg2rad(th)
        inside = np.abs(rel @ np.array([np.cos(t), np.sin(t)]) - rho) <= drho
        best = 0.0
        for i in ids:
            mine = lab == i
            frac = float(np.mean(inside[mine]))
            if frac >= min_fraction and frac > best:
                best, out[k] = frac, int(i)
    return out


def evaluate_initiation(initiator: TrackInitiator, frames: object, trajectories: Sequence[object] | None = None,
                        *, predict_frames: int = 8, min_fraction: float = 0.5) -> dict[str, object]:
    """Run ``initiator`` on a :class:`projtrack.scenes.boost.Frames` stack and score it.

    Returns a dict with the counts ``n_targets`` (targets with at least
    ``initiator``'s vote floor of detections), ``n_full_view`` (targets detectable in
    every frame), ``n_lines``, ``n_true_lines``, ``n_false_lines``, ``n_confirmed``,
    ``n_found`` (targets with a confirmed line), ``n_false_confirmed``, the sets
    ``found`` and ``full_view``, and per confirmed true track (list ``tracks``) the
    target, the position error at the last frame (``pos_err``, and its signed component
    along the track ``pos_err_along``, positive when the estimate lies ahead of the truth)
    and, when ``trajectories`` are given, the error and the along-track shortfall of the
    prediction ``predict_frames`` ahead.
    """
    pts, labs = frames.points, frames.labels  # type: ignore[attr-defined]
    times, truth, shape = frames.times, frames.truth, frames.shape  # type: ignore[attr-defined]
    initiator.initiate(pts, times, shape)
    comp = np.concatenate(pts, axis=0)
    lab = np.concatenate(labs)
    lines = [(t.rho, t.theta_deg) for t in initiator.tracks_]
    owner = match_lines(lines, comp, lab, shape, drho=initiator.drho, min_fraction=min_fraction)
    n_frames = len(pts)
    floor = initiator.default_min_votes(n_frames) if initiator.min_votes is None else initiator.min_votes
    counts = np.bincount(lab[lab >= 0], minlength=truth.shape[1]) if truth.shape[1] else np.zeros(0, int)
    present = {int(i) for i in np.flatnonzero(counts >= floor)}
    h, w = shape
    with np.errstate(invalid="ignore"):
        inview = np.all((truth[..., 0] >= 0) & (truth[..., 0] <= w - 1) & (truth[..., 1] >= 0)
                        & (truth[..., 1] <= h - 1), axis=0)
    full_view = {int(i) for i in np.flatnonzero(inview)}
    confirmed = np.array([t.confirmed for t in initiator.tracks_], dtype=bool)
    found = {int(o) for o, c in zip(owner, confirmed) if c and o >= 0}
    T = initiator.frame_time_
    rows = []
    for tr, o in zip(initiator.tracks_, owner):
        if not tr.confirmed or o < 0:
            continue
        row = {"target": int(o), "pos_err": float(np.linalg.norm(tr.position - truth[-1, o])),
               "pos_err_along": float((tr.position - truth[-1, o]) @ tr.direction), "speed": tr.speed}
        if trajectories is not None:
            t_future = times[-1] + predict_frames * T
            true_f = np.asarray(trajectories[o].position(t_future))
            pred = tr.predict(predict_frames)
            d = tr.direction
            row["pred_err"] = float(np.linalg.norm(pred - true_f))
            row["shortfall"] = float((true_f - pred) @ d)
            row["true_speed"] = float(np.linalg.norm(trajectories[o].velocity(times[-1])))
            row["true_mean_speed"] = float(np.linalg.norm(truth[-1, o] - truth[0, o]) / (times[-1] - times[0]))
        rows.append(row)
    return {
        "n_targets": len(present), "n_full_view": len(full_view),
        "n_lines": len(lines), "n_true_lines": int(np.sum(owner >= 0)), "n_false_lines": int(np.sum(owner < 0)),
        "n_confirmed": int(confirmed.sum()), "n_found": len(found),
        "n_false_confirmed": int(np.sum(confirmed & (owner < 0))),
        "found": found, "full_view": full_view, "present": present, "owner": owner, "tracks": rows,
    }


def accuracy_experiment(rng: np.random.Generator, speed: float, frame_time: float, *, total_time: float = 5.0,
                        n_targets: int = 50, jitter_sigma: float = 0.5, drho: float = 2.0,
                        shape: tuple[int, int] = (256, 256), return_errors: bool = False,
                        stop_fraction: float | None = None, dx_schedule: str = "double") -> dict[str, object]:
    """The accuracy experiment of Sec. VI for one speed and frame time.

    ``n_targets`` straight constant-velocity targets
    (:func:`projtrack.scenes.boost.straight_targets`) are imaged alone, without false
    pixels, over ``N_p = round(total_time / frame_time)`` frames with jitter
    ``jitter_sigma``; each gets its own HT, the strongest peak (the HT maximum if the
    detector finds none) is taken as its line, and :func:`estimate_track` gives the
    state at the last detected frame. Errors are resolved along (``x'``) and across
    (``y'``) the true track. ``dx_schedule`` (``"double"``, the paper's, or ``"step"``) and
    ``stop_fraction`` are passed to :func:`estimate_track`
    (``None``: the paper's 75 % stopping rule; ``1``: keep doubling ``dx'`` until one
    run holds every point).

    Returns
    -------
    dict
        Experimental standard deviations ``std_x``, ``std_y``, ``std_vx``, ``std_vy``,
        the predicted ones ``pred_x`` (Eq. (8)), ``pred_y`` (Eq. (9)), ``pred_vx``
        (Eq. (12)), ``pred_vy`` (Eq. (13)), the number of frames ``n_p``, the number of
        targets confirmed by the 75 % rule ``n_confirmed`` and of targets whose HT gave
        no peak ``n_fallback``, the number of targets that left the frame before the
        last frame ``n_left``; with ``return_errors`` also ``errors``, the
        ``(n_targets, 4)`` array of errors in ``x'``, ``y'``, ``v_x'``, ``v_y'``, and
        ``n_seen``, the number of frames in which each target was detected.
    """
    from projtrack.scenes.boost import frame_times, render_frames, straight_targets

    T = _check_positive(frame_time, "frame_time")
    n_p = int(round(total_time / T))
    times = frame_times(n_p, T)
    targets = straight_targets(n_targets, speed, shape=shape, rng=rng)
    errs, n_conf, n_fb, seen_counts = [], 0, 0, []
    h, w = shape
    for tr in targets:
        fr = render_frames([tr], times, rng, shape=shape, jitter_sigma=jitter_sigma, n_noise=0)
        pts = fr.composite()
        H, rhos, thetas = hough_transform(pts, shape, drho)
        peaks = detect_peaks(H, rhos, thetas, min_votes=TrackInitiator.default_min_votes(n_p))
        if peaks:
            rho, th = peaks[0].rho, peaks[0].theta_deg
        else:
            n_fb += 1
            i, j = np.unravel_index(np.argmax(H), H.shape)
            rho, th = float(rhos[i]), float(thetas[j])
        v_true = tr.velocity(times[-1])
        d_true = v_true / np.linalg.norm(v_true)
        est = estimate_track(pts, shape, rho, th, frame_time=T, n_frames=n_p, drho=drho,
                             jitter_sigma=jitter_sigma, heading_hint=d_true, stop_fraction=stop_fraction,
                             dx_schedule=dx_schedule)
        n_conf += int(est.projection.confirmed)
        seen = [k for k in range(n_p) if len(fr.points[k])]
        seen_counts.append(len(seen))
        p_true = fr.truth[seen[-1], 0]
        n_true = np.array([-d_true[1], d_true[0]])
        e = est.position - p_true
        ev = est.velocity - v_true
        errs.append((e @ d_true, e @ n_true, ev @ d_true, ev @ n_true))
    E = np.array(errs)
    std = E.std(axis=0, ddof=1)
    pred = track_covariance(speed, T, n_p, drho=drho, jitter_sigma=jitter_sigma, total_time=total_time)
    out = {"speed": float(speed), "T": T, "n_p": n_p,
            "std_x": float(std[0]), "std_y": float(std[1]), "std_vx": float(std[2]), "std_vy": float(std[3]),
            "pred_x": float(np.sqrt(pred["var_x"])), "pred_y": float(np.sqrt(pred["var_y"])),
            "pred_vx": float(np.sqrt(pred["var_vx"])), "pred_vy": float(np.sqrt(pred["var_vy"])),
            "n_confirmed": n_conf, "n_fallback": n_fb, "n_left": int(np.sum(np.array(seen_counts) < n_p))}
    if return_errors:
        out["errors"] = E
        out["n_seen"] = np.array(seen_counts)
    return out


def line_through(points: object, shape: tuple[int, int], *, origin: str = "center") -> tuple[float, float]:
    """Total-least-squares line through ``points`` as ``(rho, theta_deg)`` in the HT's convention.

    ``theta_deg`` lies in [0, 180); ``rho`` is measured from the origin of
    :func:`hough_transform`. Used to compare a target's true track with the Hough plane.
    """
    shape = _check_shape(shape)
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


def window_neighbours(lines: Sequence[tuple[float, float]], *, drho: float = 2.0, dtheta_deg: float = 1.0,
                      size: int = 5) -> np.ndarray:
    """For each line, whether another line falls inside its ``size x size`` averaging window.

    Two lines share a window when ``|rho_1 - rho_2| <= (size // 2) drho`` and their angles
    differ by at most ``(size // 2) dtheta`` (taking ``(rho, theta + 180) = (-rho, theta)``
    into account): the second line then raises the local average of the first's peak.
    """
    k = size // 2
    L = np.asarray(lines, dtype=float).reshape(-1, 2)
    out = np.zeros(len(L), dtype=bool)
    for a in range(len(L)):
        for b in range(len(L)):
            if a == b:
                continue
            (r1, t1), (r2, t2) = L[a], L[b]
            direct = abs(r1 - r2) <= k * drho and abs(t1 - t2) <= k * dtheta_deg
            wrapped = abs(r1 + r2) <= k * drho and abs(abs(t1 - t2) - 180.0) <= k * dtheta_deg
            out[a] |= bool(direct or wrapped)
    return out

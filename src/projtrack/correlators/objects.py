"""Several objects located from a few projection correlations by backprojection (Sec. V, Fig. 10)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy.ndimage import maximum_filter

from projtrack._validation import as_bool, as_real, as_shape2

from ._checks import as_angles, as_image, as_signal
from .correlation import _plane_shape, projection_correlation

__all__ = ["backprojection_min", "locate_objects"]


def backprojection_min(projections: Sequence[np.ndarray], r_axes: Sequence[np.ndarray],
                       angles: Sequence[float], shape: tuple[int, int]) -> np.ndarray:
    """Smear each 1-D projection correlation back over a plane and keep the minimum.

    For every pixel of a plane of ``shape`` (centred coordinates), the value is
    ``min over angles of c_theta(x cos(theta) + y sin(theta))`` with ``c_theta`` linearly
    interpolated on its ``r`` axis (0 outside). A point is a candidate object position
    only if every projection correlation is high on the line through it; with the
    horizontal and vertical projections alone, two objects that do not share a row or a
    column leave two "ghost" candidates, which a third projection removes (Sec. V).

    Parameters
    ----------
    projections : sequence of 1-D arrays
        One projection correlation per angle.
    r_axes : sequence of 1-D arrays
        Their ``r`` axes (pixels, increasing).
    angles : sequence of float
        The angles, degrees.
    shape : (int, int)
        Shape of the plane.

    Returns
    -------
    numpy.ndarray, shape ``shape``
    """
    angles = as_angles(angles)
    if not (len(projections) == len(r_axes) == len(angles)):
        raise ValueError("projections, r_axes and angles must have the same length")
    shape = as_shape2(shape)
    H, W = shape
    x = np.arange(W) - (W - 1) / 2.0
    y = (H - 1) / 2.0 - np.arange(H)
    out = np.full(shape, np.inf)
    for p, r, t in zip(projections, r_axes, angles):
        p = as_signal(p, "projections[i]")
        r = as_signal(r, "r_axes[i]")
        if len(p) != len(r) or np.any(np.diff(r) <= 0):
            raise ValueError("each r axis must be increasing and as long as its projection")
        th = np.deg2rad(t)
        rr = x[None, :] * np.cos(th) + y[:, None] * np.sin(th)
        out = np.minimum(out, np.interp(rr, r, p, left=0.0, right=0.0))
    return out


def locate_objects(scene: np.ndarray, template: np.ndarray, angles: Sequence[float],
                   threshold: float = 0.8, *, zero_mean_template: bool = True) -> dict[str, object]:
    """Locate copies of ``template`` in ``scene`` from a few projection correlations
    (Figure 10).

    Each projection correlation of the scene with the template is divided by the
    template's own projection-autocorrelation peak at that angle (so one object gives 1),
    the normalized correlations are backprojected over the full correlation plane, and a
    plane point is a candidate when every backprojection reaches ``threshold`` (the
    minimum of :func:`backprojection_min`); the candidates that are local maxima (5 x 5)
    of the mean backprojection are reported.

    Parameters
    ----------
    scene : array_like, 2-D
        The image to search.
    template : array_like, 2-D
        The object to find (smaller than the scene).
    angles : sequence of float
        Projection angles in degrees (two or three are the paper's choice).
    threshold : float, default 0.8
        Fraction of a single object's correlation peak every backprojection must reach.
    zero_mean_template : bool, keyword-only, default True
        Remove the template's mean first (Sec. III.B).

    Returns
    -------
    dict
        ``"positions"``: list of ``(row, col)`` of the template centre in scene pixels;
        ``"map"``: the backprojected minimum on the correlation-plane grid;
        ``"projections"`` and ``"r"``: the normalized projection correlations and their axes.
    """
    zero_mean_template = as_bool(zero_mean_template, "zero_mean_template")
    scene = as_image(scene, "scene")
    template = as_image(template, "template")
    angles = as_angles(angles)
    threshold = as_real(threshold, "threshold")
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


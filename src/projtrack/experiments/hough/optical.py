"""The transform itself: its parameters (Sec. II.B), Eq. (4), the optical HT (Fig. 11), its cost.

:func:`geometry_trial` measures the linearity error and the extent of the salvo's tracks
(the rules for ``drho`` and ``T_T``), :func:`plateau_width` and :func:`plateau_trial` how a
short track spreads its peak. :func:`eq4_strip_counts` checks the readings of Eq. (4).
:func:`stage_costs` counts the work of each stage against the number of targets (Sec. IV's
fixed time). :func:`composite_image` draws the binary composite of a six-launch scene,
:func:`exact_hough` is the exact voting HT with shifted bins or area pixels (the null
comparisons), :func:`match_peaks` counts peaks found again in another plane;
:func:`optics_trial`, :func:`skimage_trial` and :func:`peer_trial` are the Monte Carlo
trials of the chapter's tables (generator first, for ``projtrack.montecarlo.run``), and
:func:`skimage_cells` compares one image's plane with :func:`skimage.transform.hough_line`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from skimage.transform import hough_line, hough_line_peaks

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.experiments.hough.salvo import SALVO_TIMES
from projtrack.experiments.hough.scoring import evaluate_initiation, match_lines
from projtrack.hough import (TrackInitiator, detect_peaks, hough_transform, hough_transform_image,
                             rotate_integrate_hough)
from projtrack.scenes.boost import frame_times, in_view_launches, render_frames

__all__ = ["composite_image", "exact_hough", "match_peaks", "optics_trial", "OPT_PLANES", "skimage_cells",
           "skimage_trial", "SKIMAGE_RULES", "peer_trial", "EQ4_READINGS", "eq4_strip_counts", "geometry_trial",
           "plateau_width", "plateau_trial", "stage_costs"]

#: The planes of the optics check: key of :func:`optics_trial`'s result and its name.
OPT_PLANES = ((1, "rotate and integrate, bilinear (order=1)"), (0, "rotate and integrate, nearest (order=0)"),
              ("shift", "null: point voting, rho bins shifted 1 px"),
              ("square", "null: line integrals of square pixels (4 x 4 sub-samples)"))

#: skimage's peak picker under the settings compared in the chapter (:func:`peer_trial`).
SKIMAGE_RULES = {"skimage defaults (9, 10, half max)": {},
                 "skimage (2, 2, 6 votes)": {"min_distance": 2, "min_angle": 2, "threshold": 6},
                 "skimage (2, 2, 11 votes)": {"min_distance": 2, "min_angle": 2, "threshold": 11}}


def _binary(frames: object) -> np.ndarray:
    img = np.zeros(frames.shape, dtype=bool)  # type: ignore[attr-defined]
    c = frames.composite().astype(int)  # type: ignore[attr-defined]
    img[c[:, 1], c[:, 0]] = True
    return img


def composite_image(rng: np.random.Generator, n_targets: int = 6, n_noise: int = 5) -> np.ndarray:
    """Binary 256 x 256 composite (``image[y, x]``) of ``n_targets`` launches in view over
    21 frames of 0.25 s with ``n_noise`` false pixels per frame."""
    rng = as_rng(rng)
    n_targets = as_int(n_targets, "n_targets", minimum=0)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    times = frame_times(21, 0.25)
    tr = in_view_launches(rng, n_targets, times)
    return _binary(render_frames(tr, times, rng, n_noise=n_noise))


def exact_hough(image: object, rhos: object, thetas_deg: object, shift: float = 0.0, sub: int = 1,
                drho: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """Exact voting HT of a binary image on the axes ``rhos`` x ``thetas_deg`` (centre origin).

    The rho bins are shifted by ``shift`` pixels, and each pixel is an area of
    ``sub`` x ``sub`` sample points of weight ``1 / sub**2`` (``sub=1``: point voting).
    Returns the plane and its rho axis (bin centres, ``rhos - shift``).
    """
    img = as_array(image, "image", ndim=2)
    rhos = as_array(rhos, "rhos", ndim=1)
    thetas = as_array(thetas_deg, "thetas_deg", ndim=1)
    shift = as_real(shift, "shift")
    sub = as_int(sub, "sub", minimum=1)
    drho = as_real(drho, "drho", 0, low_open=True)
    ys, xs = np.nonzero(img)
    off = (np.arange(sub) + 0.5) / sub - 0.5
    ox, oy = (a.ravel() for a in np.meshgrid(off, off))
    px = (xs[:, None] + ox[None, :]).ravel() - img.shape[1] / 2
    py = (ys[:, None] + oy[None, :]).ravel() - img.shape[0] / 2
    t = np.deg2rad(thetas)
    rho = px[:, None] * np.cos(t) + py[:, None] * np.sin(t) + shift
    idx = np.clip(np.floor(np.round((rho - rhos[0]) / drho, 9) + 0.5).astype(np.int64), 0, rhos.size - 1)
    H = np.bincount((idx * thetas.size + np.arange(thetas.size)).ravel(), minlength=rhos.size * thetas.size)
    return H.reshape(rhos.size, thetas.size) / sub ** 2, rhos - shift


def match_peaks(a: Sequence, b: Sequence, tol_r: float = 2.0, tol_t: float = 1.0) -> int:
    """How many peaks of ``a`` have a peak of ``b`` within ``tol_r`` in rho and ``tol_t`` degrees."""
    tol_r = as_real(tol_r, "tol_r", 0)
    tol_t = as_real(tol_t, "tol_t", 0)
    return sum(any(abs(p.rho - q.rho) <= tol_r and abs(p.theta_deg - q.theta_deg) <= tol_t for q in b) for p in a)


def optics_trial(rng: np.random.Generator) -> dict[object, tuple[bool, int, int, bool, float]]:
    """One composite (:func:`composite_image`): each plane of :data:`OPT_PLANES` against point voting.

    For every key of :data:`OPT_PLANES` returns ``(peak test met, strong voting peaks
    recovered, strong voting peaks, total votes within 0.1 %, correlation)``; a strong peak
    has at least 12 votes (floor 6), recovered means within (2 px, 1 deg), and the peak test
    is met when the mass is within 0.1 % and every strong peak is recovered; the
    correlation is Pearson's, cell by cell, between the plane and point voting's (the
    planes' own rho axes, which differ only for the shifted bins).
    """
    img = composite_image(rng)
    Hv, rh, th = hough_transform_image(img)
    pv = [p for p in detect_peaks(Hv, rh, th, min_votes=6, ratio=3.0, bridge=1.5) if p.votes >= 12]
    out: dict[object, tuple[bool, int, int, bool, float]] = {}

    def corr(H: np.ndarray) -> float:
        return float(np.corrcoef(H.ravel(), Hv.ravel())[0, 1])

    for order in (1, 0):
        Hr, _, _ = rotate_integrate_hough(img, order=order)
        m = float(abs(Hr.sum() - Hv.sum()) / Hv.sum())
        k = match_peaks(pv, detect_peaks(Hr, rh, th, min_votes=6, ratio=3.0, bridge=1.5))
        out[order] = (m <= 1e-3 and k == len(pv), k, len(pv), m <= 1e-3, corr(Hr))
    for key, kw in (("shift", {"shift": 1.0}), ("square", {"sub": 4})):
        Hn, rn = exact_hough(img, rh, th, **kw)
        m = float(abs(Hn.sum() - Hv.sum()) / Hv.sum())
        k = match_peaks(pv, detect_peaks(Hn, rn, th, min_votes=6, ratio=3.0, bridge=1.5))
        out[key] = (m <= 1e-3 and k == len(pv), k, len(pv), m <= 1e-3, corr(Hn))
    return out


def skimage_cells(image: object) -> tuple[int, int, int]:
    """Cells of our corner-origin HT (``drho = 1``, theta 0..179 deg) that differ from
    :func:`skimage.transform.hough_line`'s: ``(cells, differing cells, differing cells at
    a rounding tie)``; a tie is a point whose rho lies within 1e-9 of a bin boundary."""
    img = as_array(image, "image", ndim=2).astype(bool)
    theta_rad = np.deg2rad(np.arange(180.0))
    H_sk, _, d_sk = hough_line(img, theta=theta_rad)
    H_c, rhos_c, _ = hough_transform_image(img, drho=1.0, origin="corner")
    if H_sk.shape != H_c.shape or not np.allclose(rhos_c, d_sk):
        raise RuntimeError("the rho axes differ")
    ys, xs = np.nonzero(img)
    ii, jj = np.nonzero(H_sk != H_c)
    ties = sum(bool(np.any(np.abs(np.abs(xs * np.cos(theta_rad[j]) + ys * np.sin(theta_rad[j]) - rhos_c[i]) - 0.5)
                           < 1e-9)) for i, j in zip(ii, jj))
    return H_c.size, int(ii.size), int(ties)


def skimage_trial(rng: np.random.Generator) -> tuple[int, int, int]:
    """:func:`skimage_cells` of one :func:`composite_image`."""
    return skimage_cells(composite_image(rng))


def peer_trial(rng: np.random.Generator,
               skimage_rules: Mapping[str, Mapping[str, object]] | None = None) -> list[tuple[str, int, int]]:
    """One six-launch scene (5 false pixels per frame): our peak rules against skimage's.

    Our printed rule (ratio 3, floor 6) and ridge-free rule (floor 11), and
    :func:`skimage.transform.hough_line_peaks` under each of ``skimage_rules`` (default
    :data:`SKIMAGE_RULES`), on the same voting plane. Returns ``[(picker, targets found,
    false lines), ...]``, lines matched to targets by
    :func:`~projtrack.experiments.hough.match_lines`.
    """
    rng = as_rng(rng)
    rules = SKIMAGE_RULES if skimage_rules is None else skimage_rules
    if not isinstance(rules, Mapping):
        raise TypeError(f"skimage_rules must be a mapping of name to hough_line_peaks arguments, "
                        f"got {type(rules).__name__}")
    times = frame_times(21, 0.25)
    tr = in_view_launches(rng, 6, times)
    fr = render_frames(tr, times, rng, n_noise=5)
    pts, lab = fr.composite(), np.concatenate(fr.labels)
    H, rh, th = hough_transform(pts, fr.shape)
    lines = {"ours, printed ratio 3 (floor 6)": [(p.rho, p.theta_deg) for p in detect_peaks(H, rh, th, min_votes=6, ratio=3.0, bridge=1.5)],
             "ours, ridge-free ratio 3 (floor 11)": [(p.rho, p.theta_deg)
                                                     for p in detect_peaks(H, rh, th, min_votes=11, exclude_ridge=1, ratio=3.0, bridge=1.5)]}
    for name, kw in rules.items():
        _, a, d = hough_line_peaks(H, np.deg2rad(th), rh, **kw)
        lines[name] = [(float(dd), float(np.rad2deg(aa))) for aa, dd in zip(a, d)]
    out = []
    for name, ls in lines.items():
        own = match_lines(ls, pts, lab, fr.shape)
        out.append((name, len({int(o) for o in own if o >= 0}), int(np.sum(own < 0))))
    return out


#: Readings of Eq. (4) of the paper, ``(x', y')`` of a point ``(x, y)`` (relative to the origin of
#: ``rho``) for the line ``(rho, theta)``: as printed; with ``theta`` measured from the ``y`` axis
#: (as Sec. VII measures the projections); with ``x`` and ``y`` swapped (rows and columns); and the
#: rotation consistent with Eqs. (1) and (3), which :func:`~projtrack.hough.strip_projection` uses.
EQ4_READINGS = {
    "as printed": lambda x, y, c, s, rho: (x * s + y * c, -x * c + y * s - rho),
    "theta from the y axis": lambda x, y, c, s, rho: (x * c + y * s, -x * s + y * c - rho),
    "x and y swapped": lambda x, y, c, s, rho: (y * s + x * c, -y * c + x * s - rho),
    "consistent with Eqs. (1), (3)": lambda x, y, c, s, rho: (-x * s + y * c, x * c + y * s - rho),
}


def eq4_strip_counts(thetas_deg: Sequence[float] = (0.0, 45.0, 90.0, 135.0), rho: float = 30.0, *,
                     n_points: int = 21, length: float = 100.0, half_width: float = 2.0) -> list[dict[str, object]]:
    """How many points of a line each reading of Eq. (4) puts in the strip ``|y'| <= half_width``.

    For every ``theta`` of ``thetas_deg``, ``n_points`` points evenly spread over ``length``
    pixels on the line ``rho = x cos(theta) + y sin(theta)`` (Eq. (1), coordinates relative to
    the origin of ``rho``) are mapped by each reading of :data:`EQ4_READINGS`. A consistent
    ``y'`` vanishes on the line, so every point lies in the strip; ``x'`` then runs along it
    (its range is ``length``).

    Returns
    -------
    list of dict
        One per reading and angle: ``reading``, ``theta``, ``in strip`` (points with
        ``|y'| <= half_width``), ``max |y'|`` and ``x' range`` (largest minus smallest ``x'``).
    """
    rho = as_real(rho, "rho")
    n_points = as_int(n_points, "n_points", minimum=2)
    length = as_real(length, "length", 0, low_open=True)
    half_width = as_real(half_width, "half_width", 0, low_open=True)
    u = np.linspace(-length / 2, length / 2, n_points)
    out = []
    for reading, f in EQ4_READINGS.items():
        for th in thetas_deg:
            t = np.deg2rad(as_real(th, "thetas_deg"))
            c, s = np.cos(t), np.sin(t)
            x, y = rho * c - u * s, rho * s + u * c  # on the line, along (-sin, cos)
            xp, yp = f(x, y, c, s, rho)
            out.append({"reading": reading, "theta": float(th), "in strip": int(np.sum(np.abs(yp) <= half_width + 1e-9)),
                        "max |y'|": float(np.max(np.abs(yp))), "x' range": float(np.ptp(xp))})
    return out


def geometry_trial(rng: np.random.Generator, n_targets: int = 6, **launch_kw: object) -> list[tuple[float, float]]:
    """The tracks of one salvo (:func:`~projtrack.scenes.boost.in_view_launches` over the 21
    frames of Fig. 2): per target, its linearity error (the largest distance of its jitter-free
    positions from the chord through its first and last ones, Sec. II.B's criterion for
    ``drho``) and its extent (the length of that chord, Sec. II.B's criterion for ``T_T``)."""
    rng = as_rng(rng)
    out = []
    for tr in in_view_launches(rng, as_int(n_targets, "n_targets", minimum=1), SALVO_TIMES, **launch_kw):
        p = tr.position(SALVO_TIMES)
        chord = p[-1] - p[0]
        length = float(np.hypot(*chord))
        normal = np.array([-chord[1], chord[0]]) / length
        out.append((float(np.max(np.abs((p - p[0]) @ normal))), length))
    return out


def _straight_points(extent: float, n_points: int, theta_deg: float, rho: float,
                     shape: tuple[int, int] = (256, 256)) -> np.ndarray:
    t = np.deg2rad(theta_deg)
    u = np.linspace(-extent / 2, extent / 2, n_points)
    h, w = shape
    return np.column_stack([w / 2 + rho * np.cos(t) - u * np.sin(t), h / 2 + rho * np.sin(t) + u * np.cos(t)])


def plateau_width(extent: float, n_points: int = 21, *, theta_deg: float = 30.0, rho: float = 20.0,
                  level: float = 0.9) -> int:
    """How many ``theta`` columns (1 degree each) of the HT of a noise-free straight track hold a
    cell with at least ``level`` of its ``n_points`` votes (Sec. II.B: a short track gives a
    plateau along its sinusoid rather than a peak). The track's points are evenly spread over
    ``extent`` pixels of the line ``(rho, theta_deg)``."""
    extent = as_real(extent, "extent", 0, low_open=True)
    n_points = as_int(n_points, "n_points", minimum=2)
    level = as_real(level, "level", 0, 1, low_open=True)
    H = hough_transform(_straight_points(extent, n_points, theta_deg, rho), (256, 256))[0]
    return int(np.sum(H.max(axis=0) >= level * n_points - 1e-9))


def plateau_trial(rng: np.random.Generator, extent: float, *, n_points: int = 21, n_noise: int = 5,
                  jitter_sigma: float = 0.5) -> tuple[bool, float]:
    """One straight track of ``n_points`` points over ``extent`` pixels (uniform direction,
    through a point drawn in the middle of the frame), with jitter and ``n_noise`` false pixels
    per frame, initiated with the paper's peak rule (ratio 3, bridge 1.5, a quarter of the
    frames as floor). Returns whether a confirmed line lies on it and the angle error (degrees)
    of the closest detected peak to the true line (NaN when there is no peak)."""
    rng = as_rng(rng)
    extent = as_real(extent, "extent", 0, low_open=True)
    n_points = as_int(n_points, "n_points", minimum=2)
    th = float(rng.uniform(0.0, 180.0))
    centre = rng.uniform(96.0, 160.0, size=2)
    pts = _straight_points(extent, n_points, th, 0.0) - 128.0 + centre
    frames, labels = [], []
    for k in range(n_points):
        p = np.rint(pts[k] + rng.normal(0.0, as_real(jitter_sigma, "jitter_sigma", 0), 2))
        noise = np.column_stack([rng.integers(0, 256, n_noise), rng.integers(0, 256, n_noise)]).astype(float)
        frames.append(np.vstack([np.clip(p, 0, 255)[None], noise]))
        labels.append(np.concatenate([[0], -np.ones(n_noise, dtype=int)]))
    init = TrackInitiator(ratio=3.0, bridge=1.5)
    init.initiate(frames, SALVO_TIMES[:n_points] if n_points <= len(SALVO_TIMES) else np.arange(n_points) * 0.25,
                  (256, 256))
    comp, lab = np.concatenate(frames), np.concatenate(labels)
    confirmed = [(t.rho, t.theta_deg) for t in init.tracks_ if t.confirmed]
    found = bool(np.any(match_lines(confirmed, comp, lab, (256, 256)) >= 0)) if confirmed else False
    rho_true = float((centre - 128.0) @ np.array([np.cos(np.deg2rad(th)), np.sin(np.deg2rad(th))]))
    errs = [abs((p.theta_deg - th + 90.0) % 180.0 - 90.0) for p in init.peaks_
            if abs(p.rho - rho_true) <= 6 or abs(p.rho + rho_true) <= 6]
    return found, float(min(errs)) if errs else float("nan")


def stage_costs(rng: np.random.Generator, n_targets: int, *, n_noise: int = 5) -> dict[str, float]:
    """The work of each stage of the initiator on one composite of ``n_targets`` launches (Sec. IV).

    A scene of ``n_targets`` launches in view over the 21 frames of Fig. 2 with ``n_noise``
    false pixels per frame, initiated with the paper's peak rule. Returns the number of
    ``points`` in the composite, the ``lines`` the peak detector finds and the ``targets
    found``, and the work counted in passes of the optical processor of Fig. 11 and in
    operations of a point-voting digital form: ``optical HT passes`` (one prism angle per
    ``theta``: 180, whatever the content), ``plane comparisons`` (cells of the exact and the
    defocused planes compared: the plane's size), ``optical estimation passes`` (per line one
    masked projection and one correlation per resolution tried), ``digital votes`` (points x
    angles) and ``digital strip points`` (per line, every point of the composite tested
    against the strip).
    """
    rng = as_rng(rng)
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    trajs = in_view_launches(rng, n_targets, SALVO_TIMES)
    fr = render_frames(trajs, SALVO_TIMES, rng, n_noise=as_int(n_noise, "n_noise", minimum=0))
    init = TrackInitiator(ratio=3.0, bridge=1.5)
    r = evaluate_initiation(init, fr, trajs)
    n_pts = len(fr.composite())
    n_theta = init.thetas_deg_.size
    return {"points": float(n_pts), "lines": float(len(init.tracks_)), "targets found": float(r["n_found"]),
            "optical HT passes": float(n_theta), "plane comparisons": float(init.H_.size),
            "optical estimation passes": float(sum(1 + len(t.projection.history) for t in init.tracks_)),
            "digital votes": float(n_pts * n_theta), "digital strip points": float(len(init.tracks_) * n_pts)}

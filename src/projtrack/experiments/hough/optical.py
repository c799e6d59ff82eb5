"""The optical HT of Sec. VII (Fig. 11) against point voting, and our HT against skimage's.

:func:`composite_image` draws the binary composite of a six-launch scene,
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
from projtrack.experiments.hough.scoring import match_lines
from projtrack.hough import detect_peaks, hough_transform, hough_transform_image, rotate_integrate_hough
from projtrack.scenes.boost import frame_times, in_view_launches, render_frames

__all__ = ["composite_image", "exact_hough", "match_peaks", "optics_trial", "OPT_PLANES", "skimage_cells",
           "skimage_trial", "SKIMAGE_RULES", "peer_trial"]

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


def optics_trial(rng: np.random.Generator) -> dict[object, tuple[bool, int, int, bool]]:
    """One composite (:func:`composite_image`): each plane of :data:`OPT_PLANES` against point voting.

    For every key of :data:`OPT_PLANES` returns ``(peak test met, strong voting peaks
    recovered, strong voting peaks, total votes within 0.1 %)``; a strong peak has at
    least 12 votes (floor 6), recovered means within (2 px, 1 deg), and the peak test is
    met when the mass is within 0.1 % and every strong peak is recovered.
    """
    img = composite_image(rng)
    Hv, rh, th = hough_transform_image(img)
    pv = [p for p in detect_peaks(Hv, rh, th, min_votes=6) if p.votes >= 12]
    out: dict[object, tuple[bool, int, int, bool]] = {}
    for order in (1, 0):
        Hr, _, _ = rotate_integrate_hough(img, order=order)
        m = float(abs(Hr.sum() - Hv.sum()) / Hv.sum())
        k = match_peaks(pv, detect_peaks(Hr, rh, th, min_votes=6))
        out[order] = (m <= 1e-3 and k == len(pv), k, len(pv), m <= 1e-3)
    for key, kw in (("shift", {"shift": 1.0}), ("square", {"sub": 4})):
        Hn, rn = exact_hough(img, rh, th, **kw)
        m = float(abs(Hn.sum() - Hv.sum()) / Hv.sum())
        k = match_peaks(pv, detect_peaks(Hn, rn, th, min_votes=6))
        out[key] = (m <= 1e-3 and k == len(pv), k, len(pv), m <= 1e-3)
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
    lines = {"ours, printed ratio 3 (floor 6)": [(p.rho, p.theta_deg) for p in detect_peaks(H, rh, th, min_votes=6)],
             "ours, ridge-free ratio 3 (floor 11)": [(p.rho, p.theta_deg)
                                                     for p in detect_peaks(H, rh, th, min_votes=11, exclude_ridge=1)]}
    for name, kw in rules.items():
        _, a, d = hough_line_peaks(H, np.deg2rad(th), rh, **kw)
        lines[name] = [(float(dd), float(np.rad2deg(aa))) for aa, dd in zip(a, d)]
    out = []
    for name, ls in lines.items():
        own = match_lines(ls, pts, lab, fr.shape)
        out.append((name, len({int(o) for o in own if o >= 0}), int(np.sum(own < 0))))
    return out

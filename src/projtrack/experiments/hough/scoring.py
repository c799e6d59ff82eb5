"""Scoring a Hough initiator against the ground truth of a synthetic scene.

:func:`match_lines` tells which target each detected line belongs to;
:func:`evaluate_initiation` runs a :class:`~projtrack.hough.TrackInitiator` on a
:class:`~projtrack.scenes.boost.Frames` stack and counts found, missed and false tracks
and the position and prediction errors of the true ones. :func:`mean_field_ratio` and
:func:`fraction_needed` say how a line of ``N`` votes stands against the ratio-3 peak rule
on a plane biased by false pixels.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack._validation import as_int, as_probability, as_real, as_shape2
from projtrack.hough import TrackInitiator
from projtrack.hough._checks import _check_points, _origin_xy

__all__ = ["match_lines", "evaluate_initiation", "mean_field_ratio", "fraction_needed", "rate_ci"]


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
    shape = as_shape2(shape)
    pts = _check_points(points, shape, allow_empty=True)
    lab = np.asarray(labels)
    if lab.shape != (pts.shape[0],):
        raise ValueError(f"labels must have one entry per point ({pts.shape[0]}), got shape {lab.shape}")
    min_fraction = as_probability(min_fraction, "min_fraction", low_open=True)
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


def mean_field_ratio(n_votes: float, bias: float, fraction: float = 1.0, *, size: int = 5) -> float:
    """The ratio rule's value at a line's cell, on a plane with a uniform bias (mean field).

    A straight line of ``n_votes`` points puts a ``fraction`` of its votes in its own cell
    and (when it does not spill out of the window) ``size * n_votes`` votes in the
    ``size x size`` window, one ``size``-th per ``theta`` column; false pixels add ``bias``
    votes to every cell, the line's own cell included. The cell over its window mean is

    ``(fraction * N + b) / (N / size + b)``,

    which is 5 for a perfect line on an empty plane (``fraction = 1``, ``b = 0``).
    """
    n = as_real(n_votes, "n_votes", 0, low_open=True)
    b = as_real(bias, "bias", 0)
    f = as_real(fraction, "fraction", 0, 1)
    size = as_int(size, "size", minimum=1)
    return (f * n + b) / (n / size + b)


def fraction_needed(n_votes: float, bias: float, ratio: float = 3.0, *, size: int = 5) -> float:
    """Smallest share of a line's votes its cell must hold to pass ``ratio`` (mean field).

    Solving :func:`mean_field_ratio` ``> ratio`` for the fraction gives
    ``f > ratio / size + (ratio - 1) b / N``: for the paper's ratio 3 and 5 x 5 window,
    ``f > 0.6 + 2 b / N``. Above 1 no line of ``N`` votes can pass.
    """
    n = as_real(n_votes, "n_votes", 0, low_open=True)
    b = as_real(bias, "bias", 0)
    r = as_real(ratio, "ratio", 0, low_open=True)
    size = as_int(size, "size", minimum=1)
    return r / size + (r - 1.0) * b / n


def rate_ci(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Clopper-Pearson (exact binomial) interval of the rate ``k / n`` at ``level``.

    >>> tuple(round(v, 3) for v in rate_ci(45, 49))
    (0.804, 0.977)
    """
    from scipy.stats import beta

    n = as_int(n, "n", minimum=1)
    k = as_int(k, "k", minimum=0)
    if k > n:
        raise ValueError(f"k must be at most n, got k={k}, n={n}")
    a = (1.0 - as_probability(level, "level")) / 2.0
    lo = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1.0 - a, k + 1, n - k))
    return lo, hi

"""Boost-phase trajectory scenes for the Hough track initiator (Casasent & Slaski 1988).

The paper (chapter 3 of Casasent's 1989 report) tests its track initiator on simulated
boost-phase missile launches that it does not publish: 256 x 256 binary frames every
``T = 0.25`` s, "constantly accelerating (slightly curved)" trajectories with different
launch times and angles, a Gaussian motion jitter of ``sigma_j = 0.5`` pixel on every
target point, a detection probability ``P_D`` and a few uniformly distributed false
pixels per frame. This module synthesizes such data.

The trajectory model (our choice; the paper gives no equations). A missile launched at
time ``t0`` from a site ``p0`` has a small initial velocity ``v0`` straight up (+y) and a
constant thrust acceleration ``a`` tilted by ``tilt`` from the vertical towards +x (all
launches of a salvo fly roughly the same way, so their tracks are nearly parallel)::

    p(t) = p0 + v0 (t - t0) + a (t - t0)^2 / 2,   t >= t0.

Because ``v0`` and ``a`` are not parallel the track curves slowly from vertical towards
the thrust direction; recent launches are slower, more vertical and more curved, old
ones fast and almost straight. With the defaults (``|a|`` 1-1.6 px/s^2, ``|v0|`` = 3 px/s)
the deviation of a 5-s arc from its chord stays below the paper's ``drho = 2`` pixels and
the speeds stay below 30 px/s (7.5 px/frame, the paper's fastest target) while a target
is in view.

Frames (:func:`render_frames`) hold integer pixel coordinates ``(x, y)``: the true
position plus N(0, sigma_j^2) jitter, rounded to the nearest pixel, dropped with
probability ``1 - P_D`` or when outside the image, plus ``n_noise`` uniform false pixels;
two detections on one pixel of one frame merge (a frame is a binary image).

:func:`straight_targets` makes the constant-velocity targets of the accuracy
experiment of Sec. VI (starts uniform in the lower-left quadrant, line normals evenly
spread over 90-180 degrees).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from projtrack._validation import as_count, as_probability, as_real, as_rng, as_shape2

__all__ = [
    "BoostTrajectory",
    "random_launches",
    "in_view_launches",
    "continuous_launches",
    "straight_targets",
    "Frames",
    "render_frames",
    "frame_times",
]


@dataclass(frozen=True)
class BoostTrajectory:
    """One constantly accelerating target, ``p(t) = p0 + v0 tau + a tau^2 / 2``, ``tau = t - t0``.

    Attributes
    ----------
    launch_time : float
        ``t0`` in seconds; the target does not exist before it.
    launch_xy : ndarray (2,)
        ``p0``, pixels (may lie outside the image).
    velocity0 : ndarray (2,)
        ``v0``, pixels per second.
    acceleration : ndarray (2,)
        ``a``, pixels per second squared.
    """

    launch_time: float
    launch_xy: np.ndarray
    velocity0: np.ndarray
    acceleration: np.ndarray

    def position(self, t: object) -> np.ndarray:
        """Positions at times ``t`` (shape ``t.shape + (2,)``), NaN before launch."""
        t = np.asarray(t, dtype=float)
        tau = (t - self.launch_time)[..., None]
        p = self.launch_xy + self.velocity0 * tau + 0.5 * self.acceleration * tau ** 2
        return np.where(tau >= 0, p, np.nan)

    def velocity(self, t: object) -> np.ndarray:
        """Velocities at times ``t``, NaN before launch."""
        t = np.asarray(t, dtype=float)
        tau = (t - self.launch_time)[..., None]
        v = self.velocity0 + self.acceleration * tau
        return np.where(tau >= 0, v, np.nan)


def frame_times(n_frames: int, frame_time: float = 0.25, start: float = 0.0) -> np.ndarray:
    """``start + k T`` for ``k = 0 .. n_frames - 1``."""
    as_count(n_frames, "n_frames", minimum=1)
    frame_time = as_real(frame_time, "frame_time", 0, low_open=True)
    return start + frame_time * np.arange(n_frames)


def _check_range(r: object, name: str, positive: bool = False) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in r)  # type: ignore[union-attr]
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a (low, high) pair of numbers") from exc
    if not (np.isfinite(lo) and np.isfinite(hi)) or lo > hi or (positive and lo <= 0):
        raise ValueError(f"{name} must be a finite (low, high) pair with low <= high"
                         + (" and low > 0" if positive else "") + f", got {r!r}")
    return lo, hi


def random_launches(rng: np.random.Generator, n: int, *, shape: tuple[int, int] = (256, 256),
                    launch_time_range: tuple[float, float] = (-20.0, 0.0),
                    site_y_range: tuple[float, float] = (-150.0, 20.0),
                    tilt_deg_range: tuple[float, float] = (25.0, 50.0),
                    accel_range: tuple[float, float] = (1.0, 1.6),
                    v0: float = 3.0) -> list[BoostTrajectory]:
    """Draw ``n`` launches: uniform launch time, site (``x`` across the image width,
    ``y`` in ``site_y_range``), thrust tilt from vertical and thrust magnitude.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of launches.
    shape : (int, int)
        ``(height, width)`` of the image (sites span its width).
    launch_time_range, site_y_range, tilt_deg_range, accel_range : (float, float)
        Uniform ranges (seconds, pixels, degrees towards +x, pixels/s^2).
    v0 : float
        Initial vertical speed, pixels per second.
    """
    as_rng(rng)
    as_count(n, "n", minimum=0)
    _, w = as_shape2(shape)
    t_lo, t_hi = _check_range(launch_time_range, "launch_time_range")
    y_lo, y_hi = _check_range(site_y_range, "site_y_range")
    a_lo, a_hi = _check_range(tilt_deg_range, "tilt_deg_range")
    g_lo, g_hi = _check_range(accel_range, "accel_range", positive=True)
    v0 = as_real(v0, "v0", 0)
    out = []
    for _ in range(int(n)):
        t0 = rng.uniform(t_lo, t_hi)
        site = np.array([rng.uniform(0.0, w), rng.uniform(y_lo, y_hi)])
        tilt = np.deg2rad(rng.uniform(a_lo, a_hi))
        amag = rng.uniform(g_lo, g_hi)
        acc = amag * np.array([np.sin(tilt), np.cos(tilt)])
        out.append(BoostTrajectory(float(t0), site, np.array([0.0, float(v0)]), acc))
    return out


def _in_view(p: np.ndarray, shape: tuple[int, int], margin: float) -> np.ndarray:
    h, w = shape
    with np.errstate(invalid="ignore"):
        return ((p[..., 0] >= margin) & (p[..., 0] <= w - 1 - margin)
                & (p[..., 1] >= margin) & (p[..., 1] <= h - 1 - margin))


def in_view_launches(rng: np.random.Generator, n: int, times: object, *,
                     shape: tuple[int, int] = (256, 256), margin: float = 2.0,
                     max_speed: float = 30.0, max_tries: int = 100_000,
                     **launch_kw: object) -> list[BoostTrajectory]:
    """``n`` launches (from :func:`random_launches`) in view at every one of ``times``.

    Draws launches one at a time and keeps those that are inside the image (with
    ``margin``) at all ``times`` and never faster than ``max_speed`` pixels/s there (the
    paper's fastest target moves 7.5 px/frame = 30 px/s).

    Raises
    ------
    TypeError
        If ``rng`` is not a ``numpy.random.Generator``.
    ValueError
        If ``n`` is not a non-negative int, ``max_tries`` not a positive int, or
        ``times`` not a non-empty 1-D array of finite times.
    RuntimeError
        If ``max_tries`` draws do not give ``n`` such launches.
    """
    as_rng(rng)
    as_count(n, "n", minimum=0)
    as_count(max_tries, "max_tries", minimum=1)
    shape = as_shape2(shape)
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
        raise ValueError("times must be a non-empty 1-D array of finite times")
    kept: list[BoostTrajectory] = []
    for _ in range(int(max_tries)):
        if len(kept) == n:
            break
        tr = random_launches(rng, 1, shape=shape, **launch_kw)[0]  # type: ignore[arg-type]
        p, v = tr.position(t), tr.velocity(t)
        if np.all(_in_view(p, shape, margin)) and np.all(np.linalg.norm(v, axis=-1) <= max_speed):
            kept.append(tr)
    if len(kept) < n:
        raise RuntimeError(f"only {len(kept)} of {n} launches stayed in view in {max_tries} draws")
    return kept


def continuous_launches(rng: np.random.Generator, n: int = 15, duration: float = 120.0, *,
                        shape: tuple[int, int] = (256, 256), min_time_in_view: float = 5.0,
                        frame_time: float = 0.25, max_tries: int = 100_000,
                        **launch_kw: object) -> list[BoostTrajectory]:
    """``n`` launches spread over ``[0, duration]`` that traverse the image (Fig. 4).

    Launch times are uniform over ``[-20 s, duration - min_time_in_view]`` (a target
    launched before the start may already be in view); a launch is kept when it is in
    view for at least ``min_time_in_view`` seconds of ``[0, duration]``.
    """
    shape = as_shape2(shape)
    duration = as_real(duration, "duration", 0, low_open=True)
    t = frame_times(int(round(duration / frame_time)), frame_time)
    kw = dict(launch_time_range=(-20.0, duration - min_time_in_view))
    kw.update(launch_kw)
    kept: list[BoostTrajectory] = []
    for _ in range(int(max_tries)):
        if len(kept) == n:
            break
        tr = random_launches(rng, 1, shape=shape, **kw)[0]  # type: ignore[arg-type]
        if np.count_nonzero(_in_view(tr.position(t), shape, 0.0)) * frame_time >= min_time_in_view:
            kept.append(tr)
    if len(kept) < n:
        raise RuntimeError(f"only {len(kept)} of {n} launches traversed the image in {max_tries} draws")
    kept.sort(key=lambda tr: tr.launch_time)
    return kept


def straight_targets(n: int, speed: float, *, shape: tuple[int, int] = (256, 256),
                     rng: np.random.Generator, theta_range_deg: tuple[float, float] = (90.0, 180.0),
                     ) -> list[BoostTrajectory]:
    """Constant-velocity targets of the accuracy experiment of Sec. VI.

    Starts uniform in the lower-left quadrant (``x < width/2``, ``y < height/2``) at
    ``t = 0``; the normals of the tracks are evenly spread over ``theta_range_deg`` (the
    paper's "angles evenly distributed between theta = 90 and 180 degrees"), so the
    direction of motion ``theta - 90`` runs from +x (0 degrees) to +y (90 degrees).
    """
    as_rng(rng)
    as_count(n, "n", minimum=1)
    speed = as_real(speed, "speed", 0, low_open=True)
    h, w = as_shape2(shape)
    lo, hi = _check_range(theta_range_deg, "theta_range_deg")
    thetas = np.linspace(lo, hi, n)
    out = []
    for th in thetas:
        start = np.array([rng.uniform(0, w / 2), rng.uniform(0, h / 2)])
        heading = np.deg2rad(th - 90.0)
        v = speed * np.array([np.cos(heading), np.sin(heading)])
        out.append(BoostTrajectory(0.0, start, v, np.zeros(2)))
    return out


@dataclass(frozen=True)
class Frames:
    """A stack of binary detection frames with their ground truth.

    Attributes
    ----------
    points : list of ndarray (N_k, 2)
        Detected pixels ``(x, y)`` of each frame.
    labels : list of ndarray (N_k,)
        Index of the target that made each detection, -1 for a false pixel.
    times : ndarray (K,)
        Frame times.
    truth : ndarray (K, n_targets, 2)
        True (jitter-free) positions, NaN before launch.
    shape : (int, int)
        ``(height, width)``.
    """

    points: list
    labels: list
    times: np.ndarray
    truth: np.ndarray
    shape: tuple

    def composite(self) -> np.ndarray:
        """All detections of all frames stacked, shape (sum N_k, 2)."""
        return np.concatenate(self.points, axis=0) if self.points else np.zeros((0, 2))

    def segment(self, start: int, stop: int) -> "Frames":
        """Frames ``start:stop`` as a new :class:`Frames`."""
        return Frames(self.points[start:stop], self.labels[start:stop], self.times[start:stop],
                      self.truth[start:stop], self.shape)


def render_frames(trajectories: Sequence[BoostTrajectory], times: object, rng: np.random.Generator, *,
                  shape: tuple[int, int] = (256, 256), p_detect: float = 1.0, jitter_sigma: float = 0.5,
                  n_noise: int = 5) -> Frames:
    """Binary detection frames of ``trajectories`` at ``times`` (Sec. IV of the paper).

    Each target in view gives one pixel per frame: its position plus N(0, jitter_sigma^2)
    jitter per axis, rounded; the detection is dropped when a uniform random number
    exceeds ``p_detect`` (the paper's procedure) or the pixel falls outside the image.
    ``n_noise`` false pixels are drawn uniformly over the frame. Duplicate pixels of one
    frame are merged (the target's label wins).
    """
    as_rng(rng)
    shape = as_shape2(shape)
    h, w = shape
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
        raise ValueError("times must be a non-empty 1-D array of finite times")
    p_detect = as_probability(p_detect, "p_detect")
    jitter_sigma = as_real(jitter_sigma, "jitter_sigma", 0)
    n_noise = as_count(n_noise, "n_noise", minimum=0)
    n_t = len(trajectories)
    truth = (np.stack([tr.position(t) for tr in trajectories], axis=1) if n_t
             else np.zeros((t.size, 0, 2)))
    points, labels = [], []
    for k in range(t.size):
        jit = rng.normal(0.0, jitter_sigma, size=(n_t, 2)) if n_t else np.zeros((0, 2))
        keep = rng.uniform(size=n_t) <= p_detect
        with np.errstate(invalid="ignore"):
            pix = np.rint(truth[k] + jit)
            ok = keep & np.isfinite(pix).all(axis=1) & (pix[:, 0] >= 0) & (pix[:, 0] <= w - 1) \
                & (pix[:, 1] >= 0) & (pix[:, 1] <= h - 1)
        noise = np.column_stack([rng.integers(0, w, n_noise), rng.integers(0, h, n_noise)]).astype(float)
        pk = np.concatenate([pix[ok], noise], axis=0)
        lk = np.concatenate([np.flatnonzero(ok), -np.ones(n_noise, dtype=int)])
        _, first = np.unique(pk[:, 1] * w + pk[:, 0], return_index=True)
        first = np.sort(first)
        points.append(pk[first])
        labels.append(lk[first].astype(int))
    return Frames(points, labels, t, truth, shape)

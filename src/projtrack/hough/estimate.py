"""Track confirmation and state estimation along a detected line (Sec. III, VI).

The strip projection (:func:`strip_projection`), the pulse correlation with empty
samples at -10 (:func:`pulse_correlation`), the ``dx'`` procedure with the 75 % rule
and Eq. (5) (:func:`project_and_correlate`), the covariances of Eqs. (8), (9), (12),
(13) (:func:`track_covariance`) and the estimate of one line's track
(:func:`estimate_track`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from projtrack._validation import as_choice, as_count, as_int, as_probability, as_real, as_shape2, only_value_errors
from projtrack.hough._checks import _check_hint, _check_origin, _check_points, _origin_xy

__all__ = [
    "PULSE_ZERO_VALUE",
    "strip_projection",
    "pulse_correlation",
    "ProjectionResult",
    "project_and_correlate",
    "track_covariance",
    "TrackEstimate",
    "estimate_track",
]

#: Value given to empty projection samples in the pulse correlation (Sec. III).
PULSE_ZERO_VALUE = -10.0


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


def strip_projection(points: object, shape: tuple[int, int], rho: float, theta_deg: float, *,
                     half_width: float = 2.0, heading_hint: Sequence[float] = (0.0, 1.0),
                     origin: str = "center") -> tuple[np.ndarray, float, np.ndarray]:
    r"""Projection at :math:`\Delta x' = 1` of the strip :math:`|y'| \le` ``half_width``
    along a line (Figure 1(a)-(c)).

    In the rotated frame of the detected line, ``y' = x cos(theta) + y sin(theta) - rho``
    (signed distance) and ``x'`` runs along the line in the direction ``d`` that points
    along ``heading_hint`` (the prior direction of motion: boost-phase targets climb,
    so the default is +y). The strip points are binned at unit resolution in ``x'``.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        ``(x, y)`` detections (may be empty).
    shape : (int, int)
        ``(height, width)`` of the frames.
    rho, theta_deg : float
        The line.
    half_width : float, keyword-only, default 2
        Half-width of the strip (> 0).
    heading_hint : (float, float), keyword-only, default (0, 1)
        Prior direction of motion.
    origin : {"center", "corner"}, keyword-only
        Where ``rho`` is measured from, as in :func:`hough_transform`.

    Returns
    -------
    counts : ndarray of int
        ``P_j`` at ``dx' = 1``: strip points per unit bin, bin 0 starting at ``x0``.
    x0 : float
        ``x'`` of the start of bin 0 (the image's farthest extent backwards along ``d``).
    direction : ndarray, shape (2,)
        The unit vector ``d`` of increasing ``x'``.
    """
    shape = as_shape2(shape)
    _check_origin(origin)
    pts = _check_points(points, shape, allow_empty=True)
    half_width = as_real(half_width, "half_width", 0, low_open=True)
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
    """Best correlation of a projection with a unit pulse of any width :math:`L` (Section
    III).

    Empty samples ``P_j = 0`` are replaced by ``zero_value`` (-10 in the paper) so that
    the best window is a contiguous run of non-empty samples; correlating with pulses of
    every width ``L`` and taking the largest peak is the maximum-sum window, found here
    by Kadane's algorithm.

    Parameters
    ----------
    P : array_like, 1-D
        A projection (non-negative counts), non-empty.
    zero_value : float, default -10
        Value given to empty samples.

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
    """Outcome of the projection/pulse procedure of Section III on one line.

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
    r"""Increase :math:`\Delta x'` until the 75 % rule holds, then apply Equation (5)
    (Section III, Figure 1(c)).

    The ``dx' = 1`` projection is summed in pairs (``dx' = 2, 4, 8, ...``) up to
    ``dx_max`` (16 in Sec. V). At each resolution the projection is correlated with
    pulses of every width (:func:`pulse_correlation`); the procedure stops at the
    first ``dx'`` whose peak ``I`` is at least ``confirm_fraction`` of the number of
    ones at ``dx' = 1``. The position is Eq. (5),
    :math:`x' = x_0 + \Delta x' \,[\,j + (P_j - 0.5) L / I\,]`, with :math:`j` the
    leading sample.

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
    as_choice(dx_schedule, "dx_schedule", ("double", "step"))
    dx_max = only_value_errors(as_int, dx_max, "dx_max", minimum=1)
    if dx_schedule == "double" and (dx_max & (dx_max - 1)) != 0:
        raise ValueError(f"dx_max must be an integer >= 1 (a power of two when doubling), got {dx_max!r}")
    confirm_fraction = as_probability(confirm_fraction, "confirm_fraction", low_open=True)
    stop = confirm_fraction if stop_fraction is None else only_value_errors(
        as_probability, stop_fraction, "stop_fraction", low_open=True)
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
    r"""Variances of the track estimates, Equations (8), (9), (12), (13) of Section VI.

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
        ``var_x``: :math:`(v_x T)^2 / 12 + \sigma_j^2` (Eq. (8); the paper's
        :math:`v_x^2 / 4(3)` with :math:`v_x` the displacement per frame, as the text
        derives it: uniform over :math:`\pm v_x T / 2`), ``var_y``:
        :math:`\Delta\rho^2 / 3` (Eq. (9)), ``var_vx``:
        :math:`v_x^2 / (3 N_p^2) + \sigma_j^2 / (N_p^2 T^2)` (Eq. (12)), ``var_vy``:
        :math:`4 \Delta\rho^2 / (3 T_T^2)` (Eq. (13)).
    """
    speed = as_real(speed, "speed", 0)
    T = as_real(frame_time, "frame_time", 0, low_open=True)
    n_frames = as_count(n_frames, "n_frames")
    drho = as_real(drho, "drho", 0, low_open=True)
    jitter_sigma = as_real(jitter_sigma, "jitter_sigma", 0)
    TT = n_frames * T if total_time is None else as_real(total_time, "total_time", 0, low_open=True)
    Np = float(n_frames)
    return {
        "var_x": (speed * T) ** 2 / 12.0 + jitter_sigma ** 2,
        "var_y": drho ** 2 / 3.0,
        "var_vx": speed ** 2 / (3.0 * Np ** 2) + jitter_sigma ** 2 / (Np ** 2 * T ** 2),
        "var_vy": 4.0 * drho ** 2 / (3.0 * TT ** 2),
    }


@dataclass(frozen=True)
class TrackEstimate:
    """A line found by the HT and the state estimated from its strip (Section III).

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
    refined : bool
        ``False`` for the paper's estimate (Eqs. (5)-(7)); ``True`` when ``position``,
        ``velocity``, ``speed`` and ``covariance`` come from the least-squares refinement
        of :class:`TrackInitiator` (``refine=True``).
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
    refined: bool = False

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
    r"""Confirm one HT line and estimate the target's state (Section III and VI).

    Projects the strip ``|y'| <= drho`` of the composite ``points``
    (:func:`strip_projection`), runs the ``dx'``/pulse procedure
    (:func:`project_and_correlate`), and estimates the position by Eq. (5) and the
    speed by Eq. (7), :math:`v = \Delta x' P_D L / (I T)` (Eq. (6) when :math:`P_D = 1`); the
    velocity points along the line in the direction of ``heading_hint``. The
    covariance is :func:`track_covariance` rotated to image axes. ``stop_fraction`` and
    ``dx_schedule`` are passed to :func:`project_and_correlate` (``None`` and
    ``"double"``: the paper's 75 % stopping rule and doubling of ``dx'``).

    Parameters
    ----------
    points : array_like, shape (N, 2)
        The composite's detections, ``(x, y)`` pixels.
    shape : (int, int)
        ``(height, width)`` of the frames.
    rho, theta_deg : float
        The line (e.g. a peak of :func:`find_peaks`).
    frame_time : float, keyword-only
        :math:`T`, seconds between frames (> 0).
    n_frames : int, keyword-only
        :math:`N_p`, frames in the composite (for the covariances).
    drho : float, keyword-only, default 2
        Half-width of the strip (the HT's resolution).
    p_detect : float, keyword-only, default 1
        :math:`P_D` of Eq. (7).
    jitter_sigma : float, keyword-only, default 0.5
        :math:`\sigma_j` (pixels) of the covariances.
    dx_max : int, keyword-only, default 16
        Largest projection resolution.
    confirm_fraction : float, keyword-only, default 0.75
        The 75 % rule.
    heading_hint : (float, float), keyword-only, default (0, 1)
        Prior direction of motion (orients :math:`x'`).
    votes : float, keyword-only
        The peak's votes, stored in the result.
    origin : {"center", "corner"}, keyword-only
        Where ``rho`` is measured from, as in :func:`hough_transform`.
    stop_fraction, dx_schedule : keyword-only
        See :func:`project_and_correlate`.

    Returns
    -------
    TrackEstimate

    Raises
    ------
    ValueError
        If an input is invalid, or if the strip ``|y'| <= drho`` around the line holds
        none of ``points`` (there is then no track to confirm or estimate; use
        :func:`strip_projection` to test a line first).
    """
    shape = as_shape2(shape)
    T = as_real(frame_time, "frame_time", 0, low_open=True)
    p_detect = as_probability(p_detect, "p_detect", low_open=True)
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

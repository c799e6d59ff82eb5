"""The track initiator: HT of a stack of frames, peaks, and a track per peak (Secs. II-V)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from math import ceil

import numpy as np

from projtrack._validation import as_bool, as_int, as_probability, as_real, as_shape2, only_value_errors
from projtrack.hough._checks import _check_frames, _check_hint, _origin_xy
from projtrack.hough.estimate import TrackEstimate, estimate_track, strip_projection
from projtrack.hough.peaks import detect_peaks
from projtrack.hough.transform import hough_transform, thresholded_hough_transform

__all__ = ["TrackInitiator"]


class TrackInitiator:
    r"""Hough-transform track initiator of Casasent & Slaski (Sections II-V).

    :meth:`initiate` forms the composite of a stack of frames, its Hough transform
    (plain, or thresholded as in Sec. V), detects the peaks with the paper's ratio
    rule (:func:`detect_peaks`), and confirms and estimates a track for every peak
    (:func:`estimate_track`): position of the most recent sample by Eq. (5), speed by
    Eq. (7), covariance by Eqs. (8), (9), (12), (13).

    Expected accuracy. The paper's estimator works on the projection of the line's
    strip at resolution :math:`\Delta x'` (1 to 16 pixels) and on the Hough cell of the
    line (``drho`` = 2 pixels, ``dtheta_deg`` = 1 degree), not on the points themselves.
    Measured on noise-free straight tracks of 8 to 32 frames at 1.5 to 8 pixels per frame
    moving along ``heading_hint`` (86 tracks, ``tests/test_library_inputs.py`` checks
    the bounds): median position error 0.8 pixel, 90 % under 2.3 pixels, all under 3.5;
    speed from 6 % low to 15 % high (5th to 95th percentile), all within -6 % and +23 %.
    Detections rounded to whole pixels add occasional lines split or merged by the
    rounding, with errors of tens of pixels. A target moving against ``heading_hint``
    is reported at the *oldest* end of its track with its velocity reversed: the
    projection cannot tell the direction of motion.

    ``refine=True`` re-estimates each confirmed track by least squares on its strip's
    points with their frame times (a constant-velocity fit, not the paper's estimator):
    exact on the noise-free tracks above (errors below 1e-6 pixel), and it takes the
    direction of motion from the times, whatever ``heading_hint`` says.

    Parameters
    ----------
    drho, dtheta_deg : float, default 2 and 1
        HT resolutions (pixels, degrees).
    thresholded : bool, default False
        Use the thresholded HT of Sec. V.
    ratio, bridge : float, default 3 and 1.5
        Peak-detection thresholds of the ratio rule.
    min_votes : float or None
        Minimum-vote floor of the peak detector; ``None`` (default) means
        ``max(3, ceil(n_frames / 4))``: a track must have been seen in at least a
        quarter of the frames of the composite.
    p_detect : float, default 1
        :math:`P_D` used in the velocity compensation of Eq. (7).
    jitter_sigma : float, default 0.5
        :math:`\sigma_j` (pixels) used in the covariances of Eqs. (8) and (12).
    dx_max : int, default 16
        Largest projection resolution (a power of two; 16 in Sec. V).
    confirm_fraction : float, default 0.75
        The 75 % rule.
    heading_hint : (float, float), default (0, 1)
        Prior direction of motion used to orient :math:`x'` (climbing targets: +y).
    exclude_ridge : int or None
        Neighbourhood of the peak detector (:func:`detect_peaks`): ``None`` (default)
        the paper's full ``5 x 5`` window; ``1`` the window without the line's own
        ``rho`` ridge (not the paper's rule).
    refine : bool, default False
        Re-estimate every confirmed track by least squares on the points of its strip
        (:math:`|y'| \le` ``drho``) inside the run found by the projection procedure,
        fitting :math:`(x, y)(t) = p + v (t - t_{last})` over the frames' times; the
        covariance is the fit's, with residual variance at least
        :math:`\sigma_j^2`. The returned :class:`TrackEstimate` has ``refined=True``
        (a track whose run holds fewer than two frames keeps the paper's estimate).

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
        Peaks whose strip :math:`|y'| \le` ``drho`` holds no point of the composite
        (possible only for a peak interpolated between cells); they are neither confirmed
        nor estimated, since :func:`estimate_track` rejects an empty strip.
    frame_time_ : float
        The frame time :math:`T` of the last stack.

    Raises
    ------
    TypeError, ValueError
        When a parameter has the wrong kind or value; the message names it
        (``thresholded must be a bool, got str``).

    Examples
    --------
    Two targets moving in straight lines over 16 frames of a 256 x 256 image:

    >>> import numpy as np
    >>> from projtrack.hough import TrackInitiator
    >>> times = np.arange(16) * 0.1                      # T = 0.1 s
    >>> start = np.array([[40., 30], [200, 40]])
    >>> vel = np.array([[40., 60], [-50, 70]])
    >>> frames = [start + vel * t for t in times]        # one (x, y) row per target
    >>> init = TrackInitiator(refine=True)
    >>> tracks = init.initiate(frames, times, (256, 256))
    >>> len(tracks)
    2
    >>> for tr in sorted(tracks, key=lambda tr: tr.position[0]):
    ...     print(np.round(tr.position, 1), np.round(tr.velocity, 1))
    [100. 120.] [40. 60.]
    [125. 145.] [-50.  70.]
    """

    def __init__(self, *, drho: float = 2.0, dtheta_deg: float = 1.0, thresholded: bool = False,
                 ratio: float = 3.0, bridge: float = 1.5, min_votes: float | None = None,
                 p_detect: float = 1.0, jitter_sigma: float = 0.5, dx_max: int = 16,
                 confirm_fraction: float = 0.75, heading_hint: Sequence[float] = (0.0, 1.0),
                 exclude_ridge: int | None = None, refine: bool = False):
        self.drho = as_real(drho, "drho", 0, low_open=True)
        self.dtheta_deg = as_real(dtheta_deg, "dtheta_deg", 0, low_open=True)
        self.thresholded = as_bool(thresholded, "thresholded")
        self.ratio = as_real(ratio, "ratio", 0, low_open=True)
        self.bridge = as_real(bridge, "bridge", 0, low_open=True)
        if min_votes is not None:
            only_value_errors(as_real, min_votes, "min_votes", 0)
        self.min_votes = min_votes
        self.p_detect = as_probability(p_detect, "p_detect", low_open=True)
        self.jitter_sigma = as_real(jitter_sigma, "jitter_sigma", 0)
        self.dx_max = only_value_errors(as_int, dx_max, "dx_max", minimum=1)
        if (self.dx_max & (self.dx_max - 1)) != 0:
            raise ValueError(f"dx_max must be a power of two >= 1, got {dx_max!r}")
        self.confirm_fraction = as_probability(confirm_fraction, "confirm_fraction", low_open=True)
        self.heading_hint = tuple(_check_hint(heading_hint))
        if exclude_ridge is not None:  # the 5 x 5 window leaves room for r = 0 or 1
            exclude_ridge = only_value_errors(as_int, exclude_ridge, "exclude_ridge", 0, 1)
        self.exclude_ridge = exclude_ridge
        self.refine = as_bool(refine, "refine")

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
        shape = as_shape2(shape)
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
        shape = as_shape2(shape)
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
        if self.refine:
            tk = np.asarray(times, dtype=float)
            tracks = [self._refined(tr, pts, tk, shape) if tr.confirmed else tr for tr in tracks]
        self.H_, self.rhos_, self.thetas_deg_ = H, rhos, thetas
        self.peaks_, self.tracks_, self.frame_time_ = peaks, tracks, T
        self.empty_peaks_ = empty
        return [t for t in tracks if t.confirmed]

    def _refined(self, tr: TrackEstimate, frames: list[np.ndarray], times: np.ndarray,
                 shape: tuple[int, int]) -> TrackEstimate:
        """``tr`` re-estimated by least squares on its strip's points inside the confirmed run."""
        t_pt = np.concatenate([np.full(len(f), tk) for f, tk in zip(frames, times)])
        pts = np.concatenate(frames, axis=0)
        th = np.deg2rad(tr.theta_deg)
        nrm = np.array([np.cos(th), np.sin(th)])
        rel = pts - np.array(_origin_xy(shape, "center"))
        yp, xp = rel @ nrm - tr.rho, rel @ tr.direction
        res = tr.projection
        x_start = tr.projection.x_prime - res.dx * (res.L + 1)  # run start, with one sample's slack
        sel = (np.abs(yp) <= self.drho) & (xp >= x_start) & (xp <= tr.projection.x_prime + res.dx)
        tt = t_pt[sel] - times[-1]
        if np.unique(tt).size < 2:
            return tr
        A = np.column_stack([np.ones(tt.size), tt])
        coef, *_ = np.linalg.lstsq(A, pts[sel], rcond=None)
        resid = pts[sel] - A @ coef
        dof = max(2 * (tt.size - 2), 1)
        s2 = max(float(np.sum(resid ** 2)) / dof, self.jitter_sigma ** 2)
        G = np.linalg.inv(A.T @ A) * s2
        C = np.zeros((4, 4))
        C[:2, :2], C[2:, 2:] = G[0, 0] * np.eye(2), G[1, 1] * np.eye(2)
        C[:2, 2:] = C[2:, :2] = G[0, 1] * np.eye(2)
        pos, vel = coef[0], coef[1]
        return dataclasses.replace(tr, position=pos, velocity=vel, speed=float(np.hypot(*vel)),
                                   covariance=C, refined=True)

"""The accuracy experiment of Sec. VI: errors of the track estimates against Eqs. (8)-(13).

:func:`accuracy_target` is one target (one Monte Carlo trial), :func:`accuracy_experiment`
runs one speed and frame time through :func:`projtrack.montecarlo.run`, :func:`accuracy_sweep` the
grid of Figs. 7-10 under several stopping rules, :func:`within_counts` counts the
settings whose experimental standard deviations stay within the predicted ones,
:func:`readings_table` does so under every reading (stopping rule x pixel rounding x
targets in view throughout), :func:`baseline_within` is the no-data baseline and
:func:`closest_margin` how close the closest of those comparisons comes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng
from projtrack.hough import TrackInitiator, detect_peaks, estimate_track, hough_transform, track_covariance
from projtrack.scenes.boost import frame_times, render_frames, straight_targets

__all__ = ["accuracy_target", "accuracy_experiment", "STOPS", "ROUND_VAR", "accuracy_sweep", "within_counts",
           "readings_table", "baseline_within", "closest_margin"]


def accuracy_target(rng: np.random.Generator, speed: float, frame_time: float, *, total_time: float = 5.0,
                    jitter_sigma: float = 0.5, drho: float = 2.0, shape: tuple[int, int] = (256, 256),
                    stop_fraction: float | None = None, dx_schedule: str = "double",
                    theta_range_deg: tuple[float, float] = (90.0, 180.0)) -> dict[str, object]:
    """One target of the accuracy experiment of Sec. VI (one Monte Carlo trial).

    A straight constant-velocity target (:func:`projtrack.scenes.boost.straight_targets`)
    whose track normal is drawn uniformly over ``theta_range_deg`` (the paper's "angles
    evenly distributed between 90 and 180 degrees") and whose start is uniform in the
    lower-left quadrant is imaged alone, without false pixels, over
    ``N_p = round(total_time / frame_time)`` frames with jitter ``jitter_sigma``; its HT's
    strongest peak (the HT maximum if the detector finds none) is taken as its line, and
    :func:`~projtrack.hough.estimate_track` gives the state at the last detected frame,
    with ``stop_fraction`` and ``dx_schedule`` passed on. Only ``rng`` is used for
    randomness, so the trial runs through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    dict
        ``errors``: the errors in ``x'``, ``y'``, ``v_x'``, ``v_y'`` (along and across the
        true track), ``confirmed``: whether the 75 % rule confirmed the track,
        ``fallback``: whether the HT gave no peak, ``n_seen``: the number of frames in
        which the target was detected.
    """
    rng = as_rng(rng)
    T = as_real(frame_time, "frame_time", 0, low_open=True)
    total_time = as_real(total_time, "total_time", 0, low_open=True)
    lo, hi = (as_real(v, "theta_range_deg") for v in theta_range_deg)
    if lo > hi:
        raise ValueError(f"theta_range_deg must be a (low, high) pair with low <= high, got {theta_range_deg!r}")
    n_p = int(round(total_time / T))
    if n_p < 2:
        raise ValueError(f"total_time / frame_time must give at least 2 frames, got {total_time / T:g}")
    times = frame_times(n_p, T)
    th_deg = float(rng.uniform(lo, hi))
    tr = straight_targets(1, speed, shape=shape, rng=rng, theta_range_deg=(th_deg, th_deg))[0]
    fr = render_frames([tr], times, rng, shape=shape, jitter_sigma=jitter_sigma, n_noise=0)
    pts = fr.composite()
    H, rhos, thetas = hough_transform(pts, shape, drho)
    peaks = detect_peaks(H, rhos, thetas, min_votes=TrackInitiator.default_min_votes(n_p))
    if peaks:
        rho, th = peaks[0].rho, peaks[0].theta_deg
    else:
        i, j = np.unravel_index(np.argmax(H), H.shape)
        rho, th = float(rhos[i]), float(thetas[j])
    v_true = tr.velocity(times[-1])
    d_true = v_true / np.linalg.norm(v_true)
    est = estimate_track(pts, shape, rho, th, frame_time=T, n_frames=n_p, drho=drho,
                         jitter_sigma=jitter_sigma, heading_hint=d_true, stop_fraction=stop_fraction,
                         dx_schedule=dx_schedule)
    seen = [k for k in range(n_p) if len(fr.points[k])]
    p_true = fr.truth[seen[-1], 0]
    n_true = np.array([-d_true[1], d_true[0]])
    e = est.position - p_true
    ev = est.velocity - v_true
    return {"errors": np.array([e @ d_true, e @ n_true, ev @ d_true, ev @ n_true]),
            "confirmed": bool(est.projection.confirmed), "fallback": not peaks, "n_seen": len(seen)}


def accuracy_experiment(rng: np.random.Generator, speed: float, frame_time: float, *, total_time: float = 5.0,
                        n_targets: int = 50, jitter_sigma: float = 0.5, drho: float = 2.0,
                        shape: tuple[int, int] = (256, 256), return_errors: bool = False,
                        stop_fraction: float | None = None, dx_schedule: str = "double",
                        n_jobs: int | None = None) -> dict[str, object]:
    """The accuracy experiment of Sec. VI for one speed and frame time.

    ``n_targets`` independent trials of :func:`accuracy_target` (one straight target each,
    imaged alone) through :func:`projtrack.montecarlo.run`: target ``i`` uses the ``i``-th
    child generator of ``rng``, so the result does not depend on ``n_jobs``.
    ``dx_schedule`` (``"double"``, the paper's, or ``"step"``) and ``stop_fraction`` are
    passed to :func:`~projtrack.hough.estimate_track` (``None``: the paper's 75 % stopping
    rule; ``1``: keep doubling ``dx'`` until one run holds every point).

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
    rng = as_rng(rng)
    T = as_real(frame_time, "frame_time", 0, low_open=True)
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    trials = montecarlo.run(accuracy_target, n_targets, rng, speed, T, total_time=total_time,
                            jitter_sigma=jitter_sigma, drho=drho, shape=shape, stop_fraction=stop_fraction,
                            dx_schedule=dx_schedule, n_jobs=n_jobs)
    n_p = int(round(total_time / T))
    E = np.array([t["errors"] for t in trials])
    seen_counts = np.array([t["n_seen"] for t in trials])
    std = E.std(axis=0, ddof=1)
    pred = track_covariance(speed, T, n_p, drho=drho, jitter_sigma=jitter_sigma, total_time=total_time)
    out = {"speed": float(speed), "T": T, "n_p": n_p,
           "std_x": float(std[0]), "std_y": float(std[1]), "std_vx": float(std[2]), "std_vy": float(std[3]),
           "pred_x": float(np.sqrt(pred["var_x"])), "pred_y": float(np.sqrt(pred["var_y"])),
           "pred_vx": float(np.sqrt(pred["var_vx"])), "pred_vy": float(np.sqrt(pred["var_vy"])),
           "n_confirmed": int(sum(t["confirmed"] for t in trials)),
           "n_fallback": int(sum(t["fallback"] for t in trials)), "n_left": int(np.sum(seen_counts < n_p))}
    if return_errors:
        out["errors"] = E
        out["n_seen"] = seen_counts
    return out


#: The stopping rules of the book's sweep: ``(stop_fraction, name, dx_schedule)``.
STOPS = ((None, "75 % rule", "double"), (1.0, "all points", "double"), (None, "75 % rule, dx' + 1", "step"))

#: Variance of rounding a position to the nearest pixel (uniform over one pixel).
ROUND_VAR = 1.0 / 12.0


def accuracy_sweep(speeds: Sequence[float], frame_times: Sequence[float],
                   stops: Sequence[tuple[float | None, str, str]] = STOPS, *, seed: int = 1988,
                   jitter_sigma: float = 0.5, n_targets: int = 50,
                   total_time: float = 5.0, n_jobs: int | None = None) -> tuple[list[dict[str, object]], dict[tuple, tuple]]:
    """:func:`accuracy_experiment` at every stopping rule, speed and frame time (Figs. 7-10).

    Each setting draws its targets from ``np.random.default_rng([seed, int(speed),
    round(1000 T)])`` (the same targets under every stopping rule; ``n_jobs`` worker
    processes, which do not change the result). Besides the columns of
    :func:`accuracy_experiment` each row holds ``stop`` (the rule's name), the robust
    (``1.4826`` MAD) standard deviations ``rob_x``, ``rob_y``, ``rob_vx``, ``rob_vy``, and
    ``predr_x``, ``predr_vx``: Eqs. (8) and (12) with the pixel-rounding variance
    :data:`ROUND_VAR` added to ``jitter_sigma**2``.

    Returns
    -------
    rows : list of dict
        One per setting, rules outermost, then speeds, then frame times.
    raw : dict
        ``(rule name, speed, T) -> (errors, seen in every frame)``: the ``(n_targets, 4)``
        errors and a boolean mask of the targets detected in all ``N_p`` frames.
    """
    speeds = [as_real(v, "speeds", 0, low_open=True) for v in speeds]
    frame_times = [as_real(T, "frame_times", 0, low_open=True) for T in frame_times]
    if not speeds or not frame_times:
        raise ValueError("speeds and frame_times must not be empty")
    jitter_sigma = as_real(jitter_sigma, "jitter_sigma", 0)
    rows, raw = [], {}
    for stop, stop_name, schedule in stops:
        for v in speeds:
            for T in frame_times:
                r = accuracy_experiment(np.random.default_rng([seed, int(v), int(round(T * 1000))]), v, T,
                                        total_time=total_time, n_targets=n_targets, jitter_sigma=jitter_sigma,
                                        return_errors=True, stop_fraction=stop, dx_schedule=schedule,
                                        n_jobs=n_jobs)
                E, seen = r.pop("errors"), r.pop("n_seen")
                raw[(stop_name, v, T)] = (E, seen == r["n_p"])
                mad = 1.4826 * np.median(np.abs(E - np.median(E, axis=0)), axis=0)
                r.update({"stop": stop_name, "rob_x": mad[0], "rob_y": mad[1], "rob_vx": mad[2], "rob_vy": mad[3]})
                rw = track_covariance(v, T, r["n_p"], drho=2.0,
                                      jitter_sigma=float(np.sqrt(jitter_sigma ** 2 + ROUND_VAR)), total_time=total_time)
                r.update({"predr_x": float(np.sqrt(rw["var_x"])), "predr_vx": float(np.sqrt(rw["var_vx"]))})
                rows.append(r)
    return rows, raw


def within_counts(raw: dict, table: object, stop_name: str, rounding: bool,
                  full_only: bool) -> dict[str, int]:
    """In how many settings of rule ``stop_name`` each experimental std is within its prediction.

    ``raw`` and ``table`` (a DataFrame of the rows) come from :func:`accuracy_sweep`. The
    std of ``x'``, ``y'``, ``v_x'``, ``v_y'`` errors (of the targets seen in every frame
    if ``full_only``) is compared with ``pred_*``, or for ``x'`` and ``v_x'`` with
    ``predr_*`` when ``rounding``. Returns ``{"x": n, "y": n, "vx": n, "vy": n}``.
    """
    if not isinstance(raw, dict):
        raise TypeError(f"raw must be the dict returned by accuracy_sweep, got {type(raw).__name__}")
    keys = [k for k in raw if k[0] == stop_name]
    if not keys:
        raise ValueError(f"stop_name {stop_name!r} is not a rule of the sweep")
    out = {}
    for k, i in (("x", 0), ("y", 1), ("vx", 2), ("vy", 3)):
        n = 0
        for sn, v, T in keys:
            E, full = raw[(sn, v, T)]
            e = E[full, i] if full_only else E[:, i]
            row = table[(table["stop"] == sn) & (table["speed"] == v) & (table["T"] == T)].iloc[0]  # type: ignore[index]
            pred = row[f"predr_{k}"] if rounding and k in ("x", "vx") else row[f"pred_{k}"]
            n += int(e.size > 1 and e.std(ddof=1) <= pred)
        out[k] = n
    return out


def _rule_names(stops: Sequence[tuple[float | None, str, str]]) -> list[str]:
    names = []
    for stop in stops:
        if not isinstance(stop, tuple) or len(stop) != 3 or not isinstance(stop[1], str):
            raise ValueError(f"stops must hold (stop_fraction, name, dx_schedule) triples, got {stop!r}")
        names.append(stop[1])
    if not names:
        raise ValueError("stops must not be empty")
    return names


def readings_table(raw: dict, table: object, stops: Sequence[tuple[float | None, str, str]] = STOPS, *,
                   slack: int = 2) -> list[dict[str, object]]:
    """The within counts of :func:`within_counts` under every reading of the paper's claim.

    For every stopping rule of ``stops`` (``(stop_fraction, name, dx_schedule)`` triples,
    as given to :func:`accuracy_sweep`), without and with the pixel rounding in Eqs. (8)
    and (12), over all targets and over the targets seen in every frame, one row:
    ``stopping rule``, ``rounding in Eqs. (8), (12)``, ``targets`` (``"all <n>"`` or
    ``"seen in every frame"``), ``within: y``, ``within: vy``, ``within: x``,
    ``within: vx`` (numbers of settings) and ``claim holds``: every quantity within in at
    least all but ``slack`` of the rule's settings. ``raw`` and ``table`` (a DataFrame of
    the rows) come from :func:`accuracy_sweep`.
    """
    if not isinstance(raw, dict) or not raw:
        raise ValueError("raw must be the non-empty dict returned by accuracy_sweep")
    slack = as_int(slack, "slack", minimum=0)
    names = _rule_names(stops)
    n_targets = len(next(iter(raw.values()))[0])
    rows = []
    for stop_name in names:
        n_set = sum(k[0] == stop_name for k in raw)
        for rounding in (False, True):
            for full_only in (False, True):
                w = within_counts(raw, table, stop_name, rounding, full_only)
                rows.append({"stopping rule": stop_name, "rounding in Eqs. (8), (12)": rounding,
                             "targets": "seen in every frame" if full_only else f"all {n_targets}",
                             **{f"within: {k}": w[k] for k in ("y", "vy", "x", "vx")},
                             "claim holds": min(w.values()) >= n_set - slack})
    return rows


def baseline_within(speeds: Sequence[float], frame_times: Sequence[float], *, total_time: float = 5.0,
                    jitter_sigma: float = 0.5, region: float | None = None) -> int:
    """The no-data baseline: in how many settings a guess needing no data is within Eq. (8).

    By default the guess puts the target a quarter of the track length,
    ``speed * total_time / 4``, off along the track: a constant offset, which has no spread
    and so would pass a test of the standard deviation alone. With ``region`` the guess is
    the centre of the square of that side in which the targets start uniformly: its
    along-track error has the standard deviation ``region / sqrt(12)`` of a uniform
    position (the two coordinates have the same variance, so any track direction gives
    it). The count is over every speed and frame time ``T`` (with
    ``N_p = round(total_time / T)`` frames) of settings where that error is at most the
    predicted standard deviation of ``x'``. A useful estimate must do better.
    """
    speeds = [as_real(v, "speeds", 0, low_open=True) for v in speeds]
    frame_times = [as_real(T, "frame_times", 0, low_open=True) for T in frame_times]
    total_time = as_real(total_time, "total_time", 0, low_open=True)
    spread = None if region is None else as_real(region, "region", 0, low_open=True) / np.sqrt(12.0)
    return int(sum((v * total_time / 4 if spread is None else spread)
                   <= float(np.sqrt(track_covariance(v, T, int(round(total_time / T)),
                                                     jitter_sigma=jitter_sigma)["var_x"]))
                   for v in speeds for T in frame_times))


def closest_margin(raw: dict, table: object, stops: Sequence[tuple[float | None, str, str]] = STOPS) -> float:
    """How close the closest std comes to its prediction over every reading.

    For every setting of the rules of ``stops``, every quantity (``x'``, ``y'``,
    ``v_x'``, ``v_y'``), all targets and those seen in every frame, and the prediction
    with and without pixel rounding, ``|std / prediction - 1|``; returns the smallest. A
    margin near zero would make a within count of :func:`readings_table` turn on
    floating-point rounding. ``raw`` and ``table`` come from :func:`accuracy_sweep`.
    """
    if not isinstance(raw, dict) or not raw:
        raise ValueError("raw must be the non-empty dict returned by accuracy_sweep")
    margins = []
    for stop_name in _rule_names(stops):
        for (sn, v, T), (E, full) in raw.items():
            if sn != stop_name:
                continue
            row = table[(table["stop"] == sn) & (table["speed"] == v) & (table["T"] == T)].iloc[0]  # type: ignore[index]
            for i, pk in enumerate(("x", "y", "vx", "vy")):
                for e in (E[:, i], E[full, i]):
                    for pred in {row[f"pred_{pk}"], row.get(f"predr_{pk}", row[f"pred_{pk}"])}:
                        margins.append(abs(e.std(ddof=1) / pred - 1))
    if not margins:
        raise ValueError("no setting of raw belongs to a rule of stops")
    return min(margins)

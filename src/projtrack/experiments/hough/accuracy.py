"""The accuracy experiment of Sec. VI: errors of the track estimates against Eqs. (8)-(13).

:func:`accuracy_experiment` runs one speed and frame time, :func:`accuracy_sweep` the
grid of Figs. 7-10 under several stopping rules, :func:`within_counts` counts the
settings whose experimental standard deviations stay within the predicted ones.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack._validation import as_real
from projtrack.hough import TrackInitiator, detect_peaks, estimate_track, hough_transform, track_covariance
from projtrack.scenes.boost import frame_times, render_frames, straight_targets

__all__ = ["accuracy_experiment", "STOPS", "ROUND_VAR", "accuracy_sweep", "within_counts"]


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
    T = as_real(frame_time, "frame_time", 0, low_open=True)
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


#: The stopping rules of the book's sweep: ``(stop_fraction, name, dx_schedule)``.
STOPS = ((None, "75 % rule", "double"), (1.0, "all points", "double"), (None, "75 % rule, dx' + 1", "step"))

#: Variance of rounding a position to the nearest pixel (uniform over one pixel).
ROUND_VAR = 1.0 / 12.0


def accuracy_sweep(speeds: Sequence[float], frame_times: Sequence[float],
                   stops: Sequence[tuple[float | None, str, str]] = STOPS, *, seed: int = 1988,
                   jitter_sigma: float = 0.5, n_targets: int = 50,
                   total_time: float = 5.0) -> tuple[list[dict[str, object]], dict[tuple, tuple]]:
    """:func:`accuracy_experiment` at every stopping rule, speed and frame time (Figs. 7-10).

    Each setting draws its targets from ``np.random.default_rng([seed, int(speed),
    round(1000 T)])`` (the same targets under every stopping rule). Besides the columns of
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
                                        return_errors=True, stop_fraction=stop, dx_schedule=schedule)
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

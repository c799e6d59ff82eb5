"""The accuracy experiment of Sec. VI: errors of the track estimates against Eqs. (8)-(13)."""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_real
from projtrack.hough import TrackInitiator, detect_peaks, estimate_track, hough_transform, track_covariance
from projtrack.scenes.boost import frame_times, render_frames, straight_targets

__all__ = ["accuracy_experiment"]


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

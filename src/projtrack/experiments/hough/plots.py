"""Plotting helpers of the Hough chapter used in more than one figure."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["draw_initiation"]


def draw_initiation(ax: object, frames: object, trajs: Sequence[object], init: object, result: dict,
                    title: str, *, predict_frames: int = 8, every: int = 4) -> None:
    """Draw a composite, the confirmed lines and their predictions on ``ax`` (Figs. 2-3).

    Every ``every``-th frame's detections (squares: targets, crosses: false pixels), the
    confirmed lines of ``init`` (dashed; blue on a target, red for a false track, from
    ``result["owner"]`` of :func:`~projtrack.experiments.hough.evaluate_initiation`), an
    arrow from each estimated position to its prediction ``predict_frames`` frames
    ahead, and the true positions at that time (black squares).
    """
    for k in range(0, len(frames.points), every):  # type: ignore[attr-defined]
        p, lab = frames.points[k], frames.labels[k]  # type: ignore[attr-defined]
        ax.plot(p[lab >= 0, 0], p[lab >= 0, 1], "s", ms=3, mfc="none", mec="k", mew=0.6)  # type: ignore[attr-defined]
        ax.plot(p[lab < 0, 0], p[lab < 0, 1], "x", ms=3, color="0.5", mew=0.6)  # type: ignore[attr-defined]
    h, w = frames.shape  # type: ignore[attr-defined]
    for tr, owner in zip(init.tracks_, result["owner"]):  # type: ignore[attr-defined]
        if not tr.confirmed:
            continue
        n = np.array([np.cos(np.deg2rad(tr.theta_deg)), np.sin(np.deg2rad(tr.theta_deg))])
        c = np.array([w / 2, h / 2]) + tr.rho * n
        seg = np.array([c - 200 * tr.direction, c + 200 * tr.direction])
        ax.plot(seg[:, 0], seg[:, 1], "--", lw=0.7, color="C0" if owner >= 0 else "C3")  # type: ignore[attr-defined]
        pred = tr.predict(predict_frames)
        ax.annotate("", xy=pred, xytext=tr.position,  # type: ignore[attr-defined]
                    arrowprops=dict(arrowstyle="->", color="C1", lw=1.0))
    times = frames.times  # type: ignore[attr-defined]
    t_f = times[-1] + predict_frames * init.frame_time_  # type: ignore[attr-defined]
    fut = np.array([tr.position(t_f) for tr in trajs])  # type: ignore[attr-defined]
    ax.plot(fut[:, 0], fut[:, 1], "s", ms=4, color="k")  # type: ignore[attr-defined]
    ax.set_xlim(0, w); ax.set_ylim(0, h); ax.set_aspect("equal")  # type: ignore[attr-defined]
    ax.set_title(title)  # type: ignore[attr-defined]

"""Plotting helpers of the Hough chapter: a composite with its tracks (Figs. 2-3), plain against
thresholded HT (Figs. 5-6), the ratio bound against simulation, and the Sec. V pairs."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["draw_initiation", "plot_plain_vs_thresholded", "plot_bound", "plot_pairs", "plot_continuous"]


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


def _line_segment(tr: object, shape: tuple[int, int]) -> np.ndarray:
    h, w = shape
    n = np.array([np.cos(np.deg2rad(tr.theta_deg)), np.sin(np.deg2rad(tr.theta_deg))])  # type: ignore[attr-defined]
    c = np.array([w / 2, h / 2]) + tr.rho * n  # type: ignore[attr-defined]
    return np.array([c - 200 * tr.direction, c + 200 * tr.direction])  # type: ignore[attr-defined]


def plot_plain_vs_thresholded(frames: object, runs: dict, n_targets: int = 5):
    """Figs. 5-6: the composite with the lines of the plain and of the thresholded HT, side by side.

    ``runs`` is :func:`~projtrack.experiments.hough.plain_and_thresholded`'s result. Solid
    blue: lines on true tracks; dashed orange: false lines the projection test rejects;
    dashed red: false lines it confirms. Returns the figure.
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, axes = plt.subplots(1, 2, figsize=(6.4, 3.75))
    comp, lab = frames.composite(), np.concatenate(frames.labels)  # type: ignore[attr-defined]
    for ax, (name, (init, r)) in zip(axes, runs.items()):
        ax.plot(comp[lab < 0, 0], comp[lab < 0, 1], ".", ms=1.2, color="0.6")
        ax.plot(comp[lab >= 0, 0], comp[lab >= 0, 1], "s", ms=1.8, mfc="none", mec="k", mew=0.5)
        for tr, o in zip(init.tracks_, r["owner"]):
            seg = _line_segment(tr, frames.shape)  # type: ignore[attr-defined]
            color = "C0" if o >= 0 else ("C3" if tr.confirmed else "C1")
            ax.plot(seg[:, 0], seg[:, 1], "-" if o >= 0 else "--", lw=0.8, color=color)
        ax.set_xlim(0, 256); ax.set_ylim(0, 256); ax.set_aspect("equal")
        ax.set_title(f"{name}: {r['n_found']} of {n_targets} found,\n{r['n_false_lines']} false lines, "
                     f"{r['n_false_confirmed']} confirmed")
        ax.set_xlabel("x (pixels)")
    axes[0].set_ylabel("y (pixels)")
    axes[1].set_yticklabels([])
    fig.legend(handles=[Line2D([], [], ls="none", marker="s", ms=4, mfc="none", mec="k", label="target detection"),
                        Line2D([], [], ls="none", marker=".", ms=4, color="0.6", label="false pixel"),
                        Line2D([], [], color="C0", label="line on a true track"),
                        Line2D([], [], ls="--", color="C1", label="false line, rejected"),
                        Line2D([], [], ls="--", color="C3", label="false line, confirmed")],
               loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=3, frameon=False)
    fig.tight_layout(rect=(0, 0.17, 1, 1))
    return fig


def plot_bound(perfect_ratios: Sequence[float], mean_field: float, fractions: Sequence[float],
               needed: Sequence[float]):
    """The ratio bound against simulation: (a) ratios of a perfect line on the biased plane with
    the mean-field value; (b) the share of its votes a target's best cell holds against the
    share it needs. Returns the figure."""
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(6.4, 2.7))
    r = np.asarray(perfect_ratios, dtype=float)
    a.hist(r, bins=np.arange(1.5, 5.01, 0.125), color="0.6")
    a.axvline(3.0, color="k", lw=1.0, ls="--", label="threshold 3")
    a.axvline(mean_field, color="C3", lw=1.3, label=f"mean field {mean_field:.2f}")
    a.set_xlabel("ratio at the line's cell")
    a.set_ylabel("draws")
    a.set_title("(a) perfect 21-point line")
    a.legend(frameon=False, loc="upper left")
    f, nd = np.asarray(fractions, dtype=float), np.asarray(needed, dtype=float)
    bins = np.arange(0.3, 1.0001 + 1 / 21, 1 / 21)
    b.hist(f, bins=bins, color="C0", alpha=0.7, label="share held")
    b.hist(nd, bins=bins, histtype="step", color="C3", lw=1.3, label="share needed")
    b.set_xlabel("share of a target's votes in its best cell")
    b.set_ylabel("targets")
    b.set_title("(b) our targets")
    b.legend(frameon=False, loc="upper left")
    fig.tight_layout()
    return fig


def plot_pairs(table: object):
    """Sec. V: (a) targets found when two tracks cross, against the same targets alone, by
    crossing angle; (b) confirmed lines on a pair of parallel tracks, by separation.
    ``table`` holds :func:`~projtrack.experiments.hough.pair_summary` rows. Returns the figure."""
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(6.4, 2.8))
    c = table[table["scenario"] == "crossing"]  # type: ignore[index]
    a.plot(c["value"], c["found together"], "o-", color="C3", label="crossing")
    a.plot(c["value"], c["found alone"], "s--", color="0.4", label="each alone")
    a.set_xscale("log")
    a.set_xticks(list(c["value"]), [f"{v:g}" for v in c["value"]])
    a.xaxis.set_minor_locator(plt.NullLocator())
    a.set_ylim(-0.03, 1.03)
    a.set_xlabel("crossing angle (degrees)")
    a.set_ylabel("share of targets found")
    a.set_title("(a) two crossing tracks")
    a.legend(frameon=False, loc="lower right")
    p = table[table["scenario"] == "parallel"]  # type: ignore[index]
    x = np.arange(len(p))
    bottom = np.zeros(len(p))
    for col, color in (("no line", "0.75"), ("one line", "C1"), ("two lines", "C0")):
        b.bar(x, p[col], bottom=bottom, color=color, label=col, width=0.7)
        bottom += np.asarray(p[col], dtype=float)
    b.set_xticks(x, [f"{v:g}" for v in p["value"]])
    b.set_xlabel("separation (pixels)")
    b.set_ylabel("share of draws")
    b.set_title("(b) two parallel tracks")
    b.legend(frameon=False, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=3)
    fig.tight_layout()
    return fig


def plot_continuous(run: dict, duration: float = 120.0, frame_time: float = 0.25):
    """Fig. 4: the true tracks of a 120-s run (a dot every second) and the confirmed tracks of
    its 5-s segments (arrows 2 s of estimated motion long; red: a false track).
    ``run`` is :func:`~projtrack.experiments.hough.continuous_run`'s result. Returns the figure."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    from projtrack.scenes.boost import frame_times

    fig, ax = plt.subplots(figsize=(4.8, 4.8))
    ts = frame_times(int(round(duration)) + 1, 1.0)
    tf = frame_times(int(round(duration / frame_time)), frame_time)
    for tr in run["trajs"]:
        p = tr.position(tf)
        ax.plot(p[:, 0], p[:, 1], ":", lw=0.6, color="0.4")
        q = tr.position(ts)
        ax.plot(q[:, 0], q[:, 1], ".", ms=2.5, color="k")
    for pos, vel, owner in run["arrows"]:
        ax.annotate("", xy=pos + 2.0 * vel, xytext=pos,
                    arrowprops=dict(arrowstyle="->", color="C0" if owner >= 0 else "C3", lw=0.9))
    ax.set_xlim(0, 256); ax.set_ylim(0, 256); ax.set_aspect("equal")
    ax.set_xlabel("x (pixels)"); ax.set_ylabel("y (pixels)")
    ax.legend(handles=[Line2D([], [], ls=":", marker=".", ms=4, lw=0.8, color="k", label="true track (dot every 1 s)"),
                       Line2D([], [], color="C0", lw=1.2, label="confirmed track on a target"),
                       Line2D([], [], color="C3", lw=1.2, label="confirmed false track")],
              loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, frameon=False)
    return fig

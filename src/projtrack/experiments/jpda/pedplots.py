"""Figures of the real-pedestrian page: tracks over time, association time per scan."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from projtrack.datasets import MOTBoxes

from .pedtracking import TrackRun

__all__ = ["plot_tracks_over_time", "plot_association_times"]


def plot_tracks_over_time(gt: MOTBoxes, runs: dict[str, TrackRun], scans: list | None = None,
                          width: float = 6.4, row_height: float = 2.3):
    """Horizontal position against frame: annotated people (wide, pale) and each run's tracks.

    One row per entry of ``runs`` (``{title: TrackRun}``); a track keeps one colour for its
    whole life, so an identity switch shows as a change of colour along a person's path.
    ``scans``, if given, adds the detections as grey dots.
    """
    fig, axes = plt.subplots(len(runs), 1, figsize=(width, row_height * len(runs)), sharex=True, sharey=True,
                             squeeze=False)
    colours = plt.get_cmap("tab10").colors
    for ax, (title, run) in zip(axes[:, 0], runs.items()):
        if scans is not None:
            f = np.concatenate([np.full(len(z), k + 1) for k, z in enumerate(scans)])
            x = np.concatenate([np.asarray(z, float).reshape(-1, 2)[:, 0] for z in scans])
            ax.plot(f, x, ".", color="0.75", ms=1.5, zorder=0)
        for i in gt.identities:
            sel = gt.ident == i
            ax.plot(gt.frame[sel], gt.centres[sel, 0], "-", color="0.55", lw=5, alpha=0.35, solid_capstyle="butt")
        for n, i in enumerate(np.unique(run.ident)):
            sel = run.ident == i
            ax.plot(run.frame[sel], run.point[sel, 0], "-", color=colours[n % len(colours)], lw=1.3)
        ax.set_title(title, loc="left")
        ax.set_ylabel("x [px]")
        ax.set_ylim(0, gt.image_size[0])
    axes[-1, 0].set_xlabel("frame")
    axes[-1, 0].set_xlim(1, gt.n_frames)
    fig.tight_layout()
    return fig


def plot_association_times(times: pd.DataFrame, width: float = 6.4, height: float = 3.4):
    """Seconds per scan against the largest cluster of the scan, both exact associations.

    ``times`` holds the rows of :func:`projtrack.experiments.jpda.time_association` with a
    ``scans`` column naming where each scan comes from (names starting with ``"crowd"``
    are drawn apart from the real sequences); a scan the sweep was not run on (NaN) is
    drawn at the top edge.
    """
    fig, ax = plt.subplots(figsize=(width, height))
    jitter = np.random.default_rng(0).uniform(-0.15, 0.15, len(times))
    x = times["largest cluster"].to_numpy(float) + jitter
    b = times["beta [s]"].to_numpy(float)
    e = times["Stone Soup EHM [s]"].to_numpy(float)
    crowd = times["scans"].str.startswith("crowd").to_numpy()
    top = np.nanmax(np.r_[b, e]) * 2
    for sel, where, mk in ((~crowd, "real scans", "o"), (crowd, "crowd of 100", "s")):
        ax.semilogy(x[sel], e[sel], mk, ms=4, mfc="none", color="C1", label=f"Stone Soup EHM, {where}")
        ok = sel & np.isfinite(b)
        ax.semilogy(x[ok], b[ok], mk, ms=3.5, color="C0", label=f"beta (sweep), {where}")
    if np.any(~np.isfinite(b)):
        ax.semilogy(x[~np.isfinite(b)], np.full(int(np.sum(~np.isfinite(b))), top), "v", ms=5, color="C3",
                    label="sweep not run")
    ax.set_xlabel("largest cluster of the scan, min(m, T)")
    ax.set_ylabel("seconds per scan")
    ax.legend(frameon=False, loc="upper left", ncol=2)
    fig.tight_layout()
    return fig

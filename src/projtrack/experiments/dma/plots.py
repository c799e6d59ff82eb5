"""Figures of the DMA chapter drawn from experiment results (matplotlib)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["plot_fig9", "plot_harder"]


def plot_fig9(video: object, model: object, estimate: np.ndarray, train_videos: Sequence[object], t_occ: int):
    """Fig. 9 of Marques et al. on one test video: (a-d) four frames around the occlusion that
    starts at frame ``t_occ`` (red circle: the true car), (e) the training positions, local
    frames and centroids, (f) true and Viterbi positions through the occlusion.

    Frames (a-d) sit two by two beside (f), (e) below: at most three panels side by side.
    Returns the figure.
    """
    import matplotlib.pyplot as plt

    frames, pos, occ = video.frames, video.positions, video.occluded  # type: ignore[attr-defined]
    t_occ = int(t_occ)
    if not 2 <= t_occ < len(frames) - 4:
        raise ValueError(f"t_occ must leave two frames before and four after it, got {t_occ}")
    fig = plt.figure(figsize=(6.4, 5.6))
    gs = fig.add_gridspec(3, 4, height_ratios=[1, 1, 1.9], hspace=0.35, wspace=0.15)
    for i in range(4):
        ax = fig.add_subplot(gs[i // 2, i % 2])
        t = t_occ - 2 + i
        ax.imshow(frames[t], cmap="gray", vmin=0, vmax=1)
        ax.plot(pos[t, 1], pos[t, 0], "o", mfc="none", mec="C3", ms=9, mew=0.9)
        ax.set_title(f"({'abcd'[i]}) frame {t}" + (", hidden" if occ[t] else ""), fontsize=9)
        ax.set_xticks([]); ax.set_yticks([])
    ax = fig.add_subplot(gs[:2, 2:])
    win = slice(t_occ - 3, t_occ + 4)
    ax.imshow(frames[t_occ], cmap="gray", vmin=0, vmax=1, alpha=0.35)
    ax.plot(model.prototypes_[:, 1], model.prototypes_[:, 0], "k.", ms=3)  # type: ignore[attr-defined]
    ax.plot(pos[win, 1], pos[win, 0], "-o", color="C2", ms=4, label="true")
    ax.plot(estimate[win, 1], estimate[win, 0], "--s", color="C3", ms=4, mfc="none", label="Viterbi")
    centre = pos[win].mean(axis=0)
    ax.set_xlim(centre[1] - 14, centre[1] + 14); ax.set_ylim(centre[0] + 10, centre[0] - 10)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"(f) frames {t_occ - 3}-{t_occ + 3}", fontsize=9)
    ax.set_xticks([]); ax.set_yticks([])
    ax = fig.add_subplot(gs[2, :])
    ax.imshow(video.background, cmap="gray", vmin=0, vmax=1, alpha=0.35)  # type: ignore[attr-defined]
    for v in train_videos:
        ax.plot(v.positions[:, 1], v.positions[:, 0], ".", ms=1, color="C0")  # type: ignore[attr-defined]
    man = model.manifold_  # type: ignore[attr-defined]
    for k in range(man.n_regions):
        mu, V = man.means[k], man.bases[k][:, 0]
        half = 2 * np.sqrt(man.eigenvalues[k, 0])
        seg = np.array([mu - half * V, mu + half * V])
        ax.plot(seg[:, 1], seg[:, 0], color="C3", lw=1.5)
    ax.plot(model.prototypes_[:, 1], model.prototypes_[:, 0], "k.", ms=5)  # type: ignore[attr-defined]
    ax.set_title("(e) training positions, local frames (red) and centroids", fontsize=9)
    ax.set_xticks([]); ax.set_yticks([])
    return fig


def plot_harder(video: object, active: np.ndarray, estimate: np.ndarray, times: Sequence[int]):
    """Two frames of a harder-condition video and their active pixels, two rows of two panels,
    with the true car (red circle) and the Viterbi estimate (black square). Returns the figure."""
    import matplotlib.pyplot as plt

    times = [int(t) for t in times]
    if len(times) != 2:
        raise ValueError(f"times must name two frames, got {times}")
    frames, pos = video.frames, video.positions  # type: ignore[attr-defined]
    fig, axes = plt.subplots(2, 2, figsize=(6.4, 4.6))
    for j, t in enumerate(times):
        for k, (img, kw) in enumerate(((frames[t], dict(cmap="gray", vmin=0, vmax=1)),
                                       (active[t], dict(cmap="gray_r")))):
            ax = axes[j, k]
            ax.imshow(img, **kw)
            ax.plot(pos[t, 1], pos[t, 0], "o", mfc="none", mec="C3", ms=9, mew=0.9)
            ax.plot(estimate[t, 1], estimate[t, 0], "s", mfc="none", mec="k", ms=5, mew=0.9)
            ax.set_title(f"frame {t}: " + ("input" if k == 0 else "active pixels"), fontsize=9)
            ax.set_xticks([]); ax.set_yticks([])
    fig.tight_layout()
    return fig

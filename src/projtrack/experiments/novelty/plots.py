"""Plotting helpers of the KL novelty chapter (matplotlib): Fig. 1 and the Figs. 2-3 panels."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from projtrack.novelty import TABLE1_FLOW, TABLE1_STEPS

__all__ = ["plot_block_diagram", "plot_fig2_panels", "plot_fig3_panels"]


def plot_block_diagram(ax=None):
    """Draw Fig. 1 (block diagram of the adaptive recursive SVD) from ``projtrack.novelty.TABLE1_STEPS``.

    Steps are stacked top to bottom; decision steps (those with conditional exits in
    ``projtrack.novelty.TABLE1_FLOW``) are drawn as diamonds, loops as arrows on the sides.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch, Polygon

    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 7.2))
    steps = dict(TABLE1_STEPS)
    decisions = {a for a, _, c in TABLE1_FLOW if c}
    order = [s for s, _ in TABLE1_STEPS] + [0]
    ypos = {s: -k for k, s in enumerate(order)}
    w, h = 4.6, 0.62
    for s in order:
        y = ypos[s]
        label = "end" if s == 0 else f"{s}. {steps[s]}"
        if s in decisions:
            ax.add_patch(Polygon([(-w / 2, y), (0, y + h / 1.6), (w / 2, y), (0, y - h / 1.6)],
                                 closed=True, fc="#fdf3d8", ec="k", lw=0.8))
        else:
            ax.add_patch(FancyBboxPatch((-w / 2, y - h / 2), w, h,
                                        boxstyle="round,pad=0.02,rounding_size=0.12",
                                        fc="#e8eef7" if s else "#dddddd", ec="k", lw=0.8))
        ax.text(0, y, label, ha="center", va="center", fontsize=8.0)
    for a, b, cond in TABLE1_FLOW:
        ya, yb = ypos[a], ypos[b]
        if yb == ya - 1:     # straight down
            ax.annotate("", xy=(0, yb + h / 2 + 0.02), xytext=(0, ya - h / 2 - 0.02),
                        arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            if cond:
                ax.text(0.08, (ya + yb) / 2, cond, fontsize=7.5, va="center", style="italic")
        else:                # loop back on a side
            side = 1 if cond == "not novel" else -1
            x0 = side * w / 2
            xs = side * (w / 2 + 0.5)
            ax.annotate("", xy=(x0 if b not in decisions else side * w / 2, yb),
                        xytext=(xs, yb), arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            ax.plot([x0, xs, xs], [ya, ya, yb], color="k", lw=0.8)
            ax.text(xs + side * 0.08, (ya + yb) / 2, cond, fontsize=7.5, style="italic",
                    rotation=90, va="center", ha="left" if side > 0 else "right")
    ax.set_xlim(-w / 2 - 1.0, w / 2 + 1.0)
    ax.set_ylim(ypos[0] - 0.6, 0.6)
    ax.set_axis_off()
    return ax


def plot_fig2_panels(records: Sequence, frames, picks: Sequence[int]):
    """Fig. 2 as panels: the input frames ``picks`` (top row) and their novel pixels (bottom row).

    Parameters
    ----------
    records : sequence of :class:`~projtrack.novelty.FrameRecord`
        What :func:`~projtrack.novelty.process_sequence` returned for ``frames``.
    frames : array_like, shape (I, H, W)
        The sequence, in grey levels.
    picks : sequence of int
        At most three 1-based frame numbers, one column each; the column's title gives the
        novelty ``n_i`` and the detector's decision.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    picks = _picks(picks, len(records))
    top = float(np.max(frames))                  # one grey scale for the whole sequence
    fig, axes = plt.subplots(2, len(picks), figsize=(6.4, 4.6), squeeze=False)
    for col, j in enumerate(picks):
        rec = records[j - 1]
        axes[0, col].imshow(frames[j - 1], cmap="gray", vmin=0, vmax=top)
        axes[1, col].imshow(rec.novel_pixels, cmap="gray_r", vmin=0, vmax=1)
        axes[0, col].set_title(f"frame {j}: $n$ = {rec.novelty:.4f}\n"
                               + ("novel: update" if rec.novel else "not novel"), fontsize=9.5)
    axes[0, 0].set_ylabel("input", fontsize=9.5)
    axes[1, 0].set_ylabel(r"novel pixels ($|x - \hat{x}| > T_f$)", fontsize=9.5)
    for ax in axes.flat:
        ax.set_xticks([]); ax.set_yticks([])
    return fig


def plot_fig3_panels(records: Sequence, frames, picks: Sequence[int]):
    """Fig. 3 as panels: for each frame of ``picks`` (one row each), the input, its novel pixels and
    the first eigenimage after the frame (weighted by the square root of its eigenvalue)."""
    import matplotlib.pyplot as plt

    picks = _picks(picks, len(records), most=4)
    top = float(np.max(frames))
    fig, axes = plt.subplots(len(picks), 3, figsize=(5.4, 1.75 * len(picks) + 0.4), squeeze=False)
    for row, j in zip(axes, picks):
        rec = records[j - 1]
        row[0].imshow(frames[j - 1], cmap="gray", vmin=0, vmax=top)
        row[1].imshow(rec.novel_pixels, cmap="gray_r", vmin=0, vmax=1)
        row[2].imshow(rec.first_eigenimage, cmap="gray", vmin=0, vmax=top)
        row[0].set_ylabel(f"frame {j}\n{rec.rank} kept", fontsize=9.5)
    for ax, h in zip(axes[0], ("input", "novel pixels", "first eigenimage")):
        ax.set_title(h, fontsize=9.5)
    for ax in axes.flat:
        ax.set_xticks([]); ax.set_yticks([])
    return fig


def _picks(picks: Sequence[int], n: int, most: int = 3) -> list[int]:
    picks = [int(j) for j in picks]
    if not picks or len(picks) > most or any(j < 1 or j > n for j in picks):
        raise ValueError(f"picks must be 1 to {most} frame numbers in 1..{n}, got {picks}")
    return picks

"""Plotting helpers of the KL novelty chapter (matplotlib): Fig. 1 and the Figs. 2-3 panels."""
from __future__ import annotations

from collections.abc import Sequence

from projtrack.novelty import TABLE1_FLOW, TABLE1_STEPS

__all__ = ["plot_block_diagram", "plot_frame_panels"]


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
        ax.text(0, y, label, ha="center", va="center", fontsize=7.2)
    for a, b, cond in TABLE1_FLOW:
        ya, yb = ypos[a], ypos[b]
        if yb == ya - 1:     # straight down
            ax.annotate("", xy=(0, yb + h / 2 + 0.02), xytext=(0, ya - h / 2 - 0.02),
                        arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            if cond:
                ax.text(0.08, (ya + yb) / 2, cond, fontsize=6.5, va="center", style="italic")
        else:                # loop back on a side
            side = 1 if cond == "not novel" else -1
            x0 = side * w / 2
            xs = side * (w / 2 + 0.5)
            ax.annotate("", xy=(x0 if b not in decisions else side * w / 2, yb),
                        xytext=(xs, yb), arrowprops=dict(arrowstyle="-|>", lw=0.8, color="k"))
            ax.plot([x0, xs, xs], [ya, ya, yb], color="k", lw=0.8)
            ax.text(xs + side * 0.08, (ya + yb) / 2, cond, fontsize=6.5, style="italic",
                    rotation=90, va="center", ha="left" if side > 0 else "right")
    ax.set_xlim(-w / 2 - 1.0, w / 2 + 1.0)
    ax.set_ylim(ypos[0] - 0.6, 0.6)
    ax.set_axis_off()
    return ax


def plot_frame_panels(records: Sequence, frames, picks: Sequence[int], title: str,
                      show_eigenimage: bool = False):
    """The panels of Figs. 2-3: for each picked frame, the input, its novel pixels and the readings.

    Parameters
    ----------
    records : sequence of :class:`~projtrack.novelty.FrameRecord`
        What :func:`~projtrack.novelty.process_sequence` returned for ``frames``.
    frames : array_like, shape (I, H, W)
        The sequence, in grey levels 0-255.
    picks : sequence of int
        1-based frame numbers, one row each.
    title : str
        The figure's title.
    show_eigenimage : bool
        Add a column with the first (weighted) eigenimage after the frame (Fig. 3).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    picks = [int(j) for j in picks]
    if not picks or any(j < 1 or j > len(records) for j in picks):
        raise ValueError(f"picks must be frame numbers in 1..{len(records)}, got {picks}")
    ncol = 3 if show_eigenimage else 2
    fig, axes = plt.subplots(len(picks), ncol + 1, figsize=(5.2, 1.15 * len(picks)),
                             gridspec_kw={"width_ratios": [1] * ncol + [1.5]}, squeeze=False)
    for row, j in zip(axes, picks):
        rec = records[j - 1]
        row[0].imshow(frames[j - 1], cmap="gray", vmin=0, vmax=255)
        row[1].imshow(rec.novel_pixels, cmap="gray_r", vmin=0, vmax=1)
        if show_eigenimage:
            row[2].imshow(rec.first_eigenimage, cmap="gray", vmin=0, vmax=255)
        text = [f"frame {j}", f"$n_i$ = {rec.novelty:.4f}", "novel: update" if rec.novel else "not novel"]
        if rec.fractions is not None and j > 1:
            text.append("F = [" + ", ".join(f"{v:.4f}" for v in rec.fractions[:3]) + "]")
        text.append(f"eigenimages kept: {rec.rank}")
        row[-1].text(0.0, 0.5, "\n".join(text), fontsize=7, va="center")
        row[-1].axis("off")
        for ax in row[:-1]:
            ax.set_xticks([]); ax.set_yticks([])
    heads = ["input", "novel pixels"] + (["first eigenimage"] if show_eigenimage else [])
    for ax, h in zip(axes[0], heads):
        ax.set_title(h, fontsize=8)
    fig.suptitle(title, fontsize=9)
    return fig

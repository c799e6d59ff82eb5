"""Plotting helpers of the projection-correlation pages (matplotlib)."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

from projtrack import correlators as C

__all__ = ["DIAGONAL_PANELS", "auto_cross_figure"]

#: (angle, title) of the three correlation panels of Figs. 6-7: horizontal and both readings of 45 degrees.
DIAGONAL_PANELS: tuple[tuple[float, str], ...] = ((90, "(b) horizontal"), (45, "(c) 45 deg, y up"),
                                                  (135, "(c') 45 deg, y down"))


def auto_cross_figure(shown: Sequence[tuple[np.ndarray, str]], inputs: Sequence[tuple[np.ndarray, str, str]],
                      reference: np.ndarray, *, cmap: str, suptitle: str, normalize: bool = False,
                      panels: Sequence[tuple[float, str]] = DIAGONAL_PANELS, xlim: float = 25):
    """Two input images and their projection correlations with one filter, panel by angle (Figs. 6-7).

    Parameters
    ----------
    shown : two (image, title) pairs
        The images drawn in the first two panels.
    inputs : sequence of (image, label, color)
        The inputs correlated with ``reference`` at every angle of ``panels``.
    reference : array_like
        The filter.
    cmap, suptitle : str
        Colour map of the images and title of the figure.
    normalize : bool, default False
        Divide every curve of a panel by the peak of the first input's correlation
        (auto peak = 1) and label the y axis accordingly.
    panels : sequence of (angle, title)
        One correlation panel per entry (three, by default :data:`DIAGONAL_PANELS`).
    xlim : float, default 25
        Half-width of the ``r`` axis shown.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if len(shown) != 2 or len(panels) != 3:
        raise ValueError(f"auto_cross_figure draws 2 images and 3 panels, got {len(shown)} and {len(panels)}")
    fig, axes = plt.subplots(1, 5, figsize=(11.0, 2.4), gridspec_kw={"width_ratios": [0.8, 0.8, 1.3, 1.3, 1.3]})
    for ax, (img, title) in zip(axes[:2], shown):
        ax.imshow(img, cmap=cmap); ax.set_title(title); ax.axis("off")
    for ax, (theta, title) in zip(axes[2:], panels):
        scale = float(C.projection_correlation(inputs[0][0], reference, theta).max()) if normalize else None
        for x, name, color in inputs:
            pc, r = C.projection_correlation(x, reference, theta, return_r=True)
            ax.plot(r, pc if scale is None else pc / scale, color=color, label=name)
        ax.set_title(title, fontsize=9); ax.set_xlabel("$r$"); ax.set_xlim(-xlim, xlim)
    axes[2].legend(frameon=False, fontsize=7)
    if normalize:
        axes[2].set_ylabel("corr. / auto peak")
    fig.suptitle(suptitle, fontsize=9)
    fig.tight_layout()
    return fig

"""Drawing helpers shared by the cells of the ellipsoid pages (matplotlib).

Each figure helper returns the :class:`matplotlib.figure.Figure`; the notebooks save it with
:func:`projtrack.figures.save`.
"""

from __future__ import annotations

from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np

from projtrack import ellipsoids as E

__all__ = ["draw_ellipse", "frame", "support_plot", "four_panels", "strip", "tracking_figure"]


def draw_ellipse(ax, X: object, **kw) -> None:
    """Draw the ellipse of a PSD ``X`` (a segment if singular), or the conic of eq. (2) otherwise."""
    if E.is_psd(X):
        ax.plot(*E.boundary_points(X, 300).T, **kw)
    else:
        for k, b in enumerate(E.conic_points(X, 300, extent=6.0)):
            ax.plot(*b.T, **({**kw, "label": None} if k else kw))


def frame(ax, lim: float = 3.2) -> None:
    """Equal-aspect square axes ``[-lim, lim]^2`` with light coordinate axes."""
    ax.set_aspect("equal")
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.axhline(0, color="0.85", lw=0.6, zorder=-1)
    ax.axvline(0, color="0.85", lw=0.6, zorder=-1)


def support_plot(X: object, data: tuple, title: str):
    """Figs. 6 and 8: the true ellipse and the perturbed support lines of a static data set.

    ``data`` is ``(ideal, W, Ys, Cs)`` as :func:`projtrack.scenes.ellipses.static_observations` gives it.
    """
    fig, ax = plt.subplots(figsize=(4.2, 4.2))
    draw_ellipse(ax, X, color="k", lw=1.2, label="true ellipse")
    for k, (C, Y) in enumerate(zip(data[3], data[2])):
        u = C[:, 0]
        w = np.array([-u[1], u[0]])
        h = np.sqrt(Y[0, 0])
        for sgn in (1, -1):
            p = sgn * h * u
            seg = np.array([p - 1.6 * w, p + 1.6 * w])
            ax.plot(*seg.T, color="C3", lw=0.9, label="perturbed support lines" if k == 0 and sgn == 1 else None)
            ax.plot(*p, "o", color="C3", ms=3)
        ax.plot([-4 * u[0], 4 * u[0]], [-4 * u[1], 4 * u[1]], color="0.8", lw=0.5, zorder=-1)
    frame(ax, 4.0)
    ax.legend(loc="upper left", fontsize=7.5)
    ax.set_title(title)
    return fig


def four_panels(X: object, est: dict, X_lo: object, X_hi: object, title: str):
    """Figs. 7 and 9: the LS, PSD and interval estimates against the truth, and the interval bounds."""
    fig, axs = plt.subplots(2, 2, figsize=(6.4, 6.4))
    panels = [(axs[0, 0], "LS", "unconstrained LS (eq. 15)"), (axs[0, 1], "PSD", "PSD constrained"),
              (axs[1, 0], "interval", "interval constrained")]
    for ax, key, t in panels:
        draw_ellipse(ax, X, color="0.5", lw=1.0, ls=":", label="true")
        draw_ellipse(ax, est[key], color="k", lw=1.4, label="estimate")
        frame(ax)
        ax.set_title(t)
    ax = axs[1, 1]
    draw_ellipse(ax, X_lo, color="C0", lw=1.2, label="inner bound")
    draw_ellipse(ax, X_hi, color="C3", lw=1.2, label="outer bound")
    draw_ellipse(ax, X, color="0.5", lw=1.0, ls=":", label="true")
    frame(ax)
    ax.set_title("interval bounds")
    ax.legend(loc="lower right", fontsize=7)
    axs[0, 0].legend(loc="lower right", fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def strip(ax, Xs: Sequence[np.ndarray], steps: Sequence[int], dx: float, style: dict | None = None,
          label: str | None = None) -> None:
    """Ellipses of a sequence side by side, displaced by ``dx`` for display (they are all centered at 0).

    A non-PSD matrix is drawn as its nearest PSD matrix.
    """
    style = style or {"color": "k", "lw": 1.0}
    for i, k in enumerate(steps):
        pts = E.boundary_points(Xs[k], 200) if E.is_psd(Xs[k]) else E.boundary_points(E.nearest_psd(Xs[k]), 200)
        ax.plot(pts[:, 0] + i * dx, pts[:, 1], label=label if i == 0 else None, **style)
    ax.set_aspect("equal")
    ax.set_yticks([])
    ax.set_xticks([i * dx for i in range(len(steps))])
    ax.set_xticklabels([str(k) for k in steps])
    ax.set_xlabel("time step $k$ (ellipses displaced for display)")
    for side in ("left",):
        ax.spines[side].set_visible(False)


def tracking_figure(Xs: np.ndarray, X_est: np.ndarray, Ys: Sequence[np.ndarray], title: str):
    """Figs. 12 and 13: true and estimated ellipses with the measured supports, every other step, two rows."""
    K = len(Xs)
    # two rows of every other step (0..10 and 12..22), so that the strip is not too flat
    rows = [range(0, K // 2, 2), range(K // 2, K, 2)]
    steps = range(0, K, 2)
    # frame and spacing large enough for every ellipse drawn (estimates of the first steps can be large)
    shown_est = [E.nearest_psd(X_est[k]) for k in steps]
    ext = max(float(np.sqrt(max(M[1, 1], 0))) for M in list(shown_est) + [Xs[k] for k in steps])
    wid = max(float(np.sqrt(max(M[0, 0], 0))) for M in list(shown_est) + [Xs[k] for k in steps] + [Ys[k] for k in steps])
    dx = max(4.6, 2.2 * wid)
    ylim = max(3.2, 1.15 * ext)
    row_h = 5.9 * 2 * ylim / (len(rows[0]) * dx)  # height of an equal-aspect row 5.9 inches wide
    fig, axs = plt.subplots(2, 1, figsize=(6.4, 2 * (max(1.3, row_h) + 0.5) + 1.0))
    for r, (ax, row) in enumerate(zip(axs, rows)):
        strip(ax, Xs, row, dx, {"color": "0.45", "lw": 1.0, "ls": ":"}, "true")
        strip(ax, X_est, row, dx, {"color": "k", "lw": 1.2}, "estimate")
        for i, k in enumerate(row):
            h = np.sqrt(Ys[k][0, 0])
            for s in (-1, 1):
                ax.plot([i * dx + s * h] * 2, [-0.7 * ylim, 0.7 * ylim], color="C3", lw=0.8,
                        label="measured support" if i == 0 and s == 1 else None)
        ax.set_ylim(-ylim, ylim)
        ax.set_xlim(-0.6 * dx, (len(row) - 0.4) * dx)
        if r == 0:
            ax.set_xlabel("")
    handles, labels = axs[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7.5, frameon=False)
    fig.suptitle(title)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return fig

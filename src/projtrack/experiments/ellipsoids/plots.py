"""Drawing helpers shared by the cells of the ellipsoid pages (matplotlib).

Each figure helper returns the :class:`matplotlib.figure.Figure`; the notebooks save it with
:func:`projtrack.figures.save`.
"""

from __future__ import annotations

from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np

from projtrack import ellipsoids as E

__all__ = ["draw_ellipse", "frame", "silhouette_figure", "interval_figure", "support_lines", "support_plot",
           "truth_and_supports", "four_panels", "strip", "tracking_figure", "error_bands", "shaping_figure",
           "drive_and_state"]


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


def silhouette_figure(X3: np.ndarray, C: np.ndarray, Y: np.ndarray, shift_by: float = 3.0):
    """Fig. 1: a 3-D ellipsoid, the plane spanned by ``C`` (drawn shifted by ``shift_by`` along
    its normal, as in the paper) with the shadow ``Y = C^T X C``, and rays from the silhouette
    curve on the ellipsoid to the shadow."""
    fig = plt.figure(figsize=(5.6, 5.0))
    ax = fig.add_subplot(projection="3d")
    grid = E.boundary_points(X3, 40)
    ax.plot_surface(grid[..., 0], grid[..., 1], grid[..., 2], color="0.75", alpha=0.55, linewidth=0.2,
                    edgecolor="0.45", rcount=30, ccount=30)
    shift = -shift_by * np.cross(C[:, 0], C[:, 1])  # along the normal: projection rays stay orthogonal
    corners = np.array([[-3, -3], [3, -3], [3, 3], [-3, 3], [-3, -3]], float)
    ax.plot(*(corners @ C.T + shift).T, color="0.4", lw=0.8)
    ax.plot(*(E.boundary_points(Y, 200) @ C.T + shift).T, color="k", lw=1.6,
            label=r"shadow $Y = C^T X C$ on $\mathcal{S}$")
    for t in np.linspace(0, 2 * np.pi, 13)[:-1]:
        v = np.array([np.cos(t), np.sin(t)])
        w = np.linalg.solve(Y, v) / np.sqrt(v @ np.linalg.solve(Y, v))
        seg = np.array([X3 @ C @ w, C @ (Y @ w) + shift])  # silhouette point -> its shadow point
        ax.plot(*seg.T, color="0.55", lw=0.5, ls=":")
    ax.set_xlabel("$z_1$")
    ax.set_ylabel("$z_2$")
    ax.set_zlabel("$z_3$")
    ax.set_box_aspect((1, 1, 0.9))
    ax.view_init(elev=18, azim=-60)
    ax.legend(loc="upper left")
    return fig


def interval_figure(Lo: np.ndarray, Hi: np.ndarray, outer: Sequence[np.ndarray], inner: Sequence[np.ndarray]):
    """Fig. 2: the allowed region between the bounds (white), ellipses touching the outer bound
    (blue) and the inner bound (red)."""
    fig, ax = plt.subplots(figsize=(4.6, 4.6))
    ax.set_facecolor("0.85")
    ax.fill(*E.boundary_points(Hi, 300).T, color="white", zorder=0)
    ax.fill(*E.boundary_points(Lo, 300).T, color="0.85", zorder=1)
    ax.plot(*E.boundary_points(Hi, 300).T, "k", lw=1.4, label=r"outer bound $\bar X$")
    ax.plot(*E.boundary_points(Lo, 300).T, "k--", lw=1.4, label=r"inner bound $\underline{X}$")
    for k, X in enumerate(outer):
        ax.plot(*E.boundary_points(X, 300).T, color="C0", lw=1.0, label="touching $\\bar X$" if k == 0 else None)
    for k, X in enumerate(inner):
        ax.plot(*E.boundary_points(X, 300).T, color="C3", lw=1.0, label="touching $\\underline{X}$" if k == 0 else None)
    ax.set_aspect("equal")
    ax.set_xlim(-3, 3)
    ax.set_ylim(-3, 3)
    ax.legend(loc="upper right", fontsize=7.5)
    ax.set_title("Fig. 2: the matrix interval $\\underline{X} \\leq X \\leq \\bar X$")
    return fig


def support_lines(ax, data: tuple, label: str | None = "perturbed support lines") -> None:
    """The perturbed support lines of a static data set ``(ideal, W, Ys, Cs)`` (Figs. 6 and 8).

    Each direction ``C_k`` (grey ray) carries two lines at distance ``sqrt(Y_k)`` on both sides of
    the origin: the 1-D shadow is the segment between them.
    """
    for k, (C, Y) in enumerate(zip(data[3], data[2])):
        u = C[:, 0]
        w = np.array([-u[1], u[0]])
        h = np.sqrt(Y[0, 0])
        for sgn in (1, -1):
            p = sgn * h * u
            seg = np.array([p - 1.6 * w, p + 1.6 * w])
            ax.plot(*seg.T, color="C3", lw=0.9, label=label if k == 0 and sgn == 1 else None)
            ax.plot(*p, "o", color="C3", ms=3)
        ax.plot([-4 * u[0], 4 * u[0]], [-4 * u[1], 4 * u[1]], color="0.8", lw=0.5, zorder=-1)


def support_plot(X: object, data: tuple, title: str):
    """Figs. 6 and 8: the true ellipse and the perturbed support lines of a static data set.

    ``data`` is ``(ideal, W, Ys, Cs)`` as :func:`projtrack.scenes.ellipses.static_observations` gives it.
    """
    fig, ax = plt.subplots(figsize=(4.2, 4.2))
    draw_ellipse(ax, X, color="k", lw=1.2, label="true ellipse")
    support_lines(ax, data)
    frame(ax, 4.0)
    ax.legend(loc="upper left", fontsize=7.5)
    ax.set_title(title)
    return fig


def truth_and_supports(X: object, small: tuple, large: tuple, snrs: tuple[float, float]):
    """Figs. 5, 6 and 8 in one row: the ellipse of eq. (26) with its axes, and the perturbed
    supports of the two shown draws (nominal SNRs ``snrs``) against it."""
    fig, axs = plt.subplots(1, 3, figsize=(6.4, 2.55))
    lengths, dirs = E.axes(X)
    draw_ellipse(axs[0], X, color="k", lw=1.2)
    for j in range(2):
        axs[0].plot([0, lengths[j] * dirs[0, j]], [0, lengths[j] * dirs[1, j]], color="0.4", lw=0.8)
    axs[0].set_title("Fig. 5: eq. (26)")
    for ax, data, snr, fig_no in ((axs[1], small, snrs[0], 6), (axs[2], large, snrs[1], 8)):
        draw_ellipse(ax, X, color="k", lw=1.2)
        support_lines(ax, data, None)
        ax.set_title(f"Fig. {fig_no}: SNR {snr:.1f}")
    for ax in axs:
        frame(ax, 3.2)
        ax.set_xticks([-3, 0, 3])
        ax.set_yticks([-3, 0, 3])
    fig.tight_layout()
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
    ax.legend(loc="lower right", fontsize=7.5)
    axs[0, 0].legend(loc="lower right", fontsize=7.5)
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
    # the frame fits the truth and the supports, and estimates up to twice the truth's size (larger ones are cut)
    shown_est = [E.nearest_psd(X_est[k]) for k in steps]
    true_ext = max(float(np.sqrt(Xs[k][1, 1])) for k in steps)
    true_wid = max(float(np.sqrt(Xs[k][0, 0])) for k in steps)
    ext = min(2 * true_ext, max(float(np.sqrt(max(M[1, 1], 0))) for M in list(shown_est) + [Xs[k] for k in steps]))
    wid = min(2 * true_wid, max(float(np.sqrt(max(M[0, 0], 0))) for M in list(shown_est) + [Xs[k] for k in steps]))
    wid = max(wid, max(float(np.sqrt(Ys[k][0, 0])) for k in steps))
    dx = max(4.6, 2.2 * wid)
    ylim = max(3.2, 1.15 * ext)
    row_h = 5.9 * 2 * ylim / (len(rows[0]) * dx)  # height of an equal-aspect row 5.9 inches wide
    fig, axs = plt.subplots(2, 1, figsize=(6.4, 2 * (max(1.3, row_h) + 0.5) + 1.0))
    for r, (ax, row) in enumerate(zip(axs, rows)):
        strip(ax, Xs, row, dx, {"color": "0.45", "lw": 1.0, "ls": ":"}, "true")
        strip(ax, X_est, row, dx, {"color": "k", "lw": 1.2, "clip_on": True}, "estimate")
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


def error_bands(k: np.ndarray, curves: dict, baseline: np.ndarray, title: str, window: tuple = (3, 11)):
    """Relative error over time: median and 10-90% band over the draws of each estimator, the
    no-data baseline, the 10% settling line and the paper's window ``window`` of steps.

    ``curves`` maps a label to an array ``(D, K)`` of relative errors.
    """
    fig, ax = plt.subplots(figsize=(6.4, 3.0))
    ax.axvspan(window[0], window[1], color="0.93", zorder=-2, label="about seven steps (3..11)")
    for (label, err), color in zip(curves.items(), ("C0", "C3", "C2")):
        lo, med, hi = np.percentile(err, [10, 50, 90], axis=0)
        ax.fill_between(k, lo, hi, color=color, alpha=0.18, lw=0)
        ax.semilogy(k, med, "-", color=color, lw=1.4, label=f"{label}: median, 10-90%")
    ax.semilogy(k, baseline, "k:", lw=1.4, label="no data ($X_0 = 0$, exact model)")
    ax.axhline(0.1, color="0.5", lw=0.8, ls="--")
    ax.set_ylim(1e-3, 20)
    ax.set_xlabel("time step $k$")
    ax.set_ylabel(r"$\|\hat X_k - X_k\|_F / \|X_k\|_F$")
    ax.legend(fontsize=7.5, loc="upper right", frameon=False)
    ax.set_title(title)
    return fig


def shaping_figure(X_rot: np.ndarray, X_def: np.ndarray, X_env: np.ndarray):
    """Figs. 3 and 4: the rotating ellipse every other step (top); the deforming ellipse every
    other step and all its steps centered inside the envelope ellipse ``X_env`` (bottom)."""
    fig = plt.figure(figsize=(6.4, 4.1))
    gs = fig.add_gridspec(2, 2, width_ratios=[2.2, 1], height_ratios=[1, 1.45])
    ax3 = fig.add_subplot(gs[0, :])
    strip(ax3, X_rot, range(0, 17, 2), 4.4)
    ax3.set_title(r"Fig. 3: rotating ellipse ($\alpha = \tau = 1, \psi = 0, \phi = \pi/8$)")
    ax4 = fig.add_subplot(gs[1, 0])
    strip(ax4, X_def, range(0, 17, 2), 6.0)
    ax4.set_title(r"Fig. 4: deforming ellipse ($\alpha=3/4, \tau=1, \phi=\pi/8$)")
    axe = fig.add_subplot(gs[1, 1])
    for Xk in X_def:
        axe.plot(*E.boundary_points(Xk, 200).T, color="0.6", lw=0.6)
    axe.plot(*E.boundary_points(X_env, 300).T, "k--", lw=1.2, label="envelope $cZ$")
    axe.set_aspect("equal")
    axe.set_xticks([])
    axe.set_yticks([])
    axe.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02), fontsize=7.5, frameon=False)
    axe.set_title("all steps, centered")
    fig.tight_layout()
    return fig


def drive_and_state(Bs: np.ndarray, Xs: np.ndarray):
    """Figs. 10 and 11: the drive ``B_k`` through half of its cycle (a dot where ``B_k = 0``) and
    the ellipse state ``X_k`` every other step."""
    fig, axs = plt.subplots(2, 1, figsize=(6.4, 3.3), gridspec_kw={"height_ratios": [1, 1.1]})
    dx = 1.15 * 2 * max(float(np.sqrt(np.linalg.eigvalsh(B)[-1])) for B in Bs[:7])  # no overlap
    strip(axs[0], Bs, range(0, 7), dx)
    for k in range(7):
        if np.abs(Bs[k]).max() < 1e-12:
            axs[0].plot(k * dx, 0, "k.", ms=4)
            axs[0].annotate(f"$B_{k} = 0$", (k * dx, 0), xytext=(0, 8), textcoords="offset points", ha="center",
                            fontsize=7.5)
    axs[0].set_title("Fig. 10: driving term $B_k$ through half of its cycle")
    strip(axs[1], Xs, range(0, len(Xs), 2), 4.2)
    axs[1].set_title("Fig. 11: ellipse state $X_k$, every other time step")
    fig.tight_layout()
    return fig

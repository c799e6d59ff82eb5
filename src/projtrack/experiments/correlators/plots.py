"""Plotting helpers of the projection-correlation pages (matplotlib).

Data are rounded to 9 decimals (:func:`_s`) before they are drawn, so that the last bits in
which CPUs differ (FFT correlations, Monte Carlo sums) do not change the pixels of a figure
that a page glues, and nbval compares exactly.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

from projtrack import correlators as C

def _s(a):
    """Data as drawn: rounded to 9 decimals (see the module docstring)."""
    return np.round(np.asarray(a, dtype=float), 9)


__all__ = ["DIAGONAL_PANELS", "auto_cross_figure", "sweep_figure", "projections_figure", "central_slice_figure",
           "eq3_figure", "letters_montage", "fig3_figure", "fig4_figure", "fig5_figure", "extent_figure", "snr_loss_figure", "fig10_figure",
           "architectures_figure", "time_integrating_figure"]

#: (angle, title) of the four correlation panels of Figs. 6-7: horizontal, vertical and both readings of 45 degrees.
DIAGONAL_PANELS: tuple[tuple[float, str], ...] = ((90, "(b) horizontal"), (0, "vertical"), (45, "(c) 45 deg, y up"),
                                                  (135, "(c') 45 deg, y down"))


def auto_cross_figure(shown: Sequence[tuple[np.ndarray, str]], inputs: Sequence[tuple[np.ndarray, str, str]],
                      reference: np.ndarray, *, cmap: str, normalize: bool = False,
                      panels: Sequence[tuple[float, str]] = DIAGONAL_PANELS, xlim: float = 25):
    """Two input images and their projection correlations with one filter, one panel per angle (Figs. 6-7).

    Two rows of three panels: the two images and the first correlation panel, then the
    other three.

    Parameters
    ----------
    shown : two (image, title) pairs
        The images drawn in the first two panels.
    inputs : sequence of (image, label, color)
        The inputs correlated with ``reference`` at every angle of ``panels``.
    reference : array_like
        The filter.
    cmap : str
        Colour map of the images.
    normalize : bool, default False
        Divide every curve of a panel by the peak of the first input's correlation
        (auto peak = 1) and label the y axis accordingly.
    panels : sequence of (angle, title)
        Four correlation panels (by default :data:`DIAGONAL_PANELS`).
    xlim : float, default 25
        Half-width of the ``r`` axis shown.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if len(shown) != 2 or len(panels) != 4:
        raise ValueError(f"auto_cross_figure draws 2 images and 4 panels, got {len(shown)} and {len(panels)}")
    fig, axes = plt.subplots(2, 3, figsize=(6.4, 4.2))
    for ax, (img, title) in zip(axes[0, :2], shown):
        ax.imshow(_s(img), cmap=cmap); ax.set_title(title); ax.axis("off")
    for ax, (theta, title) in zip([axes[0, 2], *axes[1]], panels):
        scale = float(C.projection_correlation(inputs[0][0], reference, theta).max()) if normalize else None
        for x, name, color in inputs:
            pc, r = C.projection_correlation(x, reference, theta, return_r=True)
            ax.plot(_s(r), _s(pc if scale is None else pc / scale), color=color, label=name)
        ax.set_title(title); ax.set_xlabel("$r$"); ax.set_xlim(-xlim, xlim)
    axes[0, 2].legend(frameon=False, fontsize=7.5)
    if normalize:
        axes[1, 0].set_ylabel("corr. / auto peak")
    fig.tight_layout()
    return fig


def sweep_figure(sweep, baselines, paper: Sequence[tuple[float, float]] = ((0.44, 1.0), (0.45, 24 / 26))):
    """Fraction of letters classified correctly against the noise level: projection banks (left),
    the paper's bank against 2-D correlation and pixel-space baselines (right)."""
    fig, axes = plt.subplots(1, 2, figsize=(6.4, 3.6), sharey=True)
    for k in sweep.columns[1:]:
        axes[0].plot(_s(sweep["sigma"]), _s(sweep[k]), marker="o", ms=3, label=k)
    axes[0].plot(*zip(*paper), ls="none", marker="*", ms=9, color="k", label="paper")
    for k in baselines.columns[1:]:
        axes[1].plot(_s(baselines["sigma"]), _s(baselines[k]), marker="o", ms=3, label=k)
    for ax, title in zip(axes, ("projection banks", "against 2-D and baselines")):
        ax.axvline(0.44, color="0.5", lw=0.8, ls=":")
        ax.set_xlabel(r"noise $\sigma$"); ax.set_title(title)
        ax.legend(frameon=False, fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=2)
    axes[0].set_ylabel("fraction correct")
    fig.tight_layout()
    return fig


def projections_figure(image: np.ndarray, angles: Sequence[float] = (0, 90, 45, 30)):
    """The letter and its projections at four angles, in two rows of three panels."""
    if len(angles) != 4:
        raise ValueError(f"projections_figure draws 4 angles, got {len(angles)}")
    fig, axes = plt.subplots(2, 3, figsize=(6.4, 3.8))
    ax0 = axes[0, 0]
    ax0.imshow(image[6:26, 6:26], cmap="gray_r")
    ax0.set_title("input C (central 20x20)")
    ax0.set_xticks([]); ax0.set_yticks([])
    for ax, theta in zip([axes[0, 1], axes[0, 2], axes[1, 0], axes[1, 1]], angles):
        p, r = C.project(image, theta, return_r=True)
        ax.bar(_s(r), _s(p), width=float(_s(r[1] - r[0])) * 0.9, color="C0")
        ax.set_xlim(-12, 12)
        ax.set_title(rf"$\theta = {theta:g}^\circ$")
        ax.set_xlabel("$r$ (pixels)")
    axes[1, 2].set_visible(False)
    fig.tight_layout()
    return fig


def central_slice_figure(image: np.ndarray, rho: np.ndarray, angles: Sequence[float] = (0, 45, 30)):
    """|1-D FT of the projection| over |slice of the 2-D FT| at three angles (Fig. 1, eq. (2))."""
    fig, axes = plt.subplots(1, len(angles), figsize=(6.4, 2.5), sharey=True)
    for ax, theta in zip(np.atleast_1d(axes), angles):
        ax.plot(rho, _s(np.abs(C.fourier_slice(image, theta, rho))), lw=2.5, color="0.75", label="slice of 2-D FT")
        ax.plot(rho, _s(np.abs(C.projection_spectrum(image, theta, rho))), lw=1.0, color="C3", label="FT of projection")
        ax.set_title(rf"$\theta = {theta:g}^\circ$")
        ax.set_xlabel(r"$\rho$ (cycles/pixel)")
    axes[0].set_ylabel("magnitude")
    axes[0].legend(frameon=False, fontsize=7.5, loc="upper left")
    fig.tight_layout()
    return fig


def eq3_figure(image: np.ndarray):
    """Eq. (3) for the autocorrelation of ``image``: the bipolar 2-D plane, its vertical and
    horizontal projections against the projection correlations, and intensity detection."""
    plane = C.correlate2d(image, image)
    fig, axes = plt.subplots(2, 2, figsize=(6.4, 4.6))
    lim = float(np.max(np.abs(plane)))
    h = (plane.shape[0] - 1) / 2
    axes[0, 0].imshow(_s(plane), cmap="RdBu_r", vmin=-float(_s(lim)), vmax=float(_s(lim)), extent=(-h, h, -h, h))
    axes[0, 0].set_title("(a) 2-D bipolar autocorrelation")
    axes[0, 0].set_xlim(-16, 16); axes[0, 0].set_ylim(-16, 16)
    for ax, theta, name in ((axes[0, 1], 0, "(b) vertical"), (axes[1, 0], 90, "(c) horizontal")):
        pc, r = C.projection_correlation(image, image, theta, return_r=True)
        ax.plot(_s(r), _s(pc), color="C0", label="projection correlation")
        ax.plot(_s(r), _s(C.integrated_correlation(image, image, theta)), ".", ms=3, color="C3", label="projected 2-D plane")
        ax.set_xlim(-20, 20); ax.set_title(rf"{name} ($\theta = {theta}^\circ$)"); ax.set_xlabel("$r$ (pixels)")
    axes[0, 1].legend(frameon=False, fontsize=7.5)
    pc, r = C.projection_correlation(image, image, 0, return_r=True)
    inten = C.project(plane ** 2, 0)
    axes[1, 1].plot(_s(r), _s(pc ** 2 / np.max(pc ** 2)), color="C0", label="(projection corr.)$^2$")
    axes[1, 1].plot(_s(r), _s(inten / inten.max()), color="C2", label="projected $|c|^2$")
    axes[1, 1].set_xlim(-20, 20); axes[1, 1].set_title("(d) intensity detection")
    axes[1, 1].legend(frameon=False, fontsize=7.5); axes[1, 1].set_xlabel("$r$ (pixels)")
    fig.tight_layout()
    return fig


def letters_montage(images: np.ndarray, labels: Sequence[str], *, crop: int = 6, per_row: int = 13):
    """The letters tiled in one panel (central part of each image), each labelled below."""
    images = np.asarray(images)
    n, size = len(images), images.shape[1] - 2 * crop
    rows = -(-n // per_row)
    tile = np.zeros((rows * (size + 8), per_row * (size + 2)))
    fig, ax = plt.subplots(figsize=(6.4, 1.25 * rows + 0.2))
    for k, (img, lab) in enumerate(zip(images, labels)):
        r, c = divmod(k, per_row)
        y0, x0 = r * (size + 8), c * (size + 2)
        tile[y0:y0 + size, x0:x0 + size] = img[crop:crop + size, crop:crop + size]
        ax.text(x0 + size / 2, y0 + size + 4, lab, ha="center", va="center", fontsize=8)
    ax.imshow(tile, cmap="gray_r", vmin=0, vmax=1)
    ax.axis("off")
    fig.tight_layout()
    return fig


def fig3_figure(image: np.ndarray):
    """Fig. 3: the binary letter, its 2-D autocorrelation, the vertical projection correlation
    and the vertically integrated 2-D correlation."""
    plane = C.correlate2d(image, image)
    h = (plane.shape[0] - 1) // 2
    fig, axes = plt.subplots(2, 2, figsize=(6.4, 4.4))
    axes[0, 0].imshow(image[6:26, 6:26], cmap="gray_r"); axes[0, 0].set_title("(a) input C")
    axes[0, 1].imshow(_s(plane[h - 16:h + 17, h - 16:h + 17]), cmap="viridis"); axes[0, 1].set_title("(b) 2-D correlation")
    for ax in axes[0]:
        ax.axis("off")
    pc, r = C.projection_correlation(image, image, 0, return_r=True)
    axes[1, 0].plot(_s(r), _s(pc)); axes[1, 0].set_title("(c) vertical projection corr.")
    axes[1, 1].plot(_s(r), _s(C.integrated_correlation(image, image, 0)), color="C3")
    axes[1, 1].set_title("(d) vertically integrated 2-D corr.")
    for ax in axes[1]:
        ax.set_xlabel("$r$ (pixels)"); ax.set_xlim(-32, 32)
    fig.tight_layout()
    return fig


def fig4_figure(image: np.ndarray):
    """Fig. 4: vertical and horizontal projection autocorrelations of a zero-mean letter."""
    fig, axes = plt.subplots(1, 2, figsize=(6.4, 2.4), sharey=True)
    for ax, theta, name in ((axes[0], 0, "(a) vertical"), (axes[1], 90, "(b) horizontal")):
        pc, r = C.projection_correlation(image, image, theta, return_r=True)
        ax.plot(_s(r), _s(pc)); ax.axhline(0, color="0.6", lw=0.6)
        ax.set_title(f"{name} projection corr."); ax.set_xlabel("$r$ (pixels)"); ax.set_xlim(-32, 32)
    fig.tight_layout()
    return fig


def fig5_figure(x: np.ndarray, reference: np.ndarray, *, crop: int = 16):
    """Fig. 5: magnitude of a noisy input, magnitude of its cyclic 2-D bipolar correlation with
    ``reference`` and its cyclic horizontal projection correlation."""
    plane = C.circular_correlate(x, reference)
    hp = C.circular_correlate(C.project(x, 90), C.project(reference, 90))
    r = np.arange(len(hp)) - len(hp) // 2
    fig, axes = plt.subplots(1, 3, figsize=(6.4, 2.3), gridspec_kw={"width_ratios": [1, 1, 1.3]})
    axes[0].imshow(_s(np.abs(x[crop:-crop, crop:-crop])), cmap="gray_r"); axes[0].set_title("(a) noisy input, magnitude")
    axes[1].imshow(_s(np.abs(plane)), cmap="viridis"); axes[1].set_title("(b) 2-D corr., magnitude")
    for ax in axes[:2]:
        ax.axis("off")
    axes[2].plot(r, _s(hp)); axes[2].axhline(0, color="0.6", lw=0.6)
    axes[2].set_title("(c) horizontal proj. corr."); axes[2].set_xlabel("$r$ (pixels)")
    fig.tight_layout()
    return fig


def extent_figure(table, printed: dict[str, float], chosen: dict[str, int]):
    """Median eq. (5a) SNRs against the noise extent, one line per plane (from
    :func:`projtrack.experiments.correlators.snr_by_extent`), with the printed values and the
    extent calibrated on the 2-D SNR of each plane."""
    fig, axes = plt.subplots(1, 2, figsize=(6.4, 2.8), sharex=True)
    for ax, col in zip(axes, ("2-D SNR", "horizontal SNR")):
        for k, (plane, sub) in enumerate(table.groupby("plane", sort=False)):
            ax.semilogy(sub["noise extent"], _s(sub[col]), color=f"C{k}", label=plane)
            e = chosen[plane]
            ax.semilogy([e], _s(sub.loc[sub["noise extent"] == e, col]), "o", color=f"C{k}", ms=5)
        ax.axhline(printed[col], color="k", lw=0.8, ls="--")
        ax.set_xlabel("noise extent (pixels)"); ax.set_title(f"{col} (median; dashed: paper)")
    axes[0].legend(frameon=False, fontsize=7.5)
    fig.tight_layout()
    return fig


def snr_loss_figure(table):
    """SNR loss of the projection correlation against N: Monte Carlo (markers) and closed form
    (black ticks) for the signals of :func:`projtrack.experiments.correlators.snr_signals`, with
    the no-loss and worst-case ``N^1/2`` lines."""
    fig, ax = plt.subplots(figsize=(6.4, 3.4))
    markers = {"uniform (paper's white)": "o", "single pixel": "s", "random +-1 texture": "^", "letter C": "*"}
    for name, marker in markers.items():
        sub = table[table["signal"] == name]
        ax.loglog(sub["N"], _s(sub["loss factor"]), marker=marker, ms=7, ls="none", label=f"Monte Carlo: {name}")
        ax.loglog(sub["N"], _s(sub["loss, closed form"]), marker="_", ms=14, ls="none", color="k")
    ns = np.array([12, 80])
    ax.loglog(ns, np.ones_like(ns, dtype=float), color="0.5", lw=0.8, label="no loss")
    ax.loglog(ns, np.sqrt(ns), color="0.2", lw=0.8, ls="--", label=r"worst case $N^{1/2}$")
    ax.plot([], [], marker="_", ms=14, ls="none", color="k", label="closed form")
    ax.set_xticks([16, 32, 64], labels=["16", "32", "64"])
    ax.set_yticks([1, 2, 4, 8], labels=["1", "2", "4", "8"])
    ax.minorticks_off()
    ax.set_xlabel(r"$N$ (image is $N \times N$)"); ax.set_ylabel("SNR$_o$ 2-D / projection")
    ax.legend(frameon=False, fontsize=7.5, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    return fig


def fig10_figure(scene: np.ndarray, truth: Sequence[tuple[int, int]], template: np.ndarray, results: dict,
                 angles: Sequence[float] = (0, 90, 45), threshold: float = 0.8):
    """Fig. 10: the scene, its normalized projection correlations, and the candidates of two and
    of three projections (``results``: name -> output of :func:`projtrack.correlators.locate_objects`,
    the first with two projections, the second with ``angles``)."""
    fig, axes = plt.subplots(2, 2, figsize=(6.4, 5.6))
    ax = axes[0, 0]
    ax.imshow(scene, cmap="gray_r"); ax.set_title(f"scene ({len(truth)} objects)")
    for r, q in truth:
        ax.plot(q, r, "+", color="C3", ms=7)
    names = list(results)
    res3 = results[names[1]]
    for p, r, theta, color in zip(res3["projections"], res3["r"], angles, ("C0", "C1", "C2", "C4")):
        axes[0, 1].plot(_s(r), _s(p), color=color, label=rf"$\theta = {theta:g}^\circ$")
    axes[0, 1].axhline(threshold, color="0.5", lw=0.7, ls=":"); axes[0, 1].set_xlabel("$r$ (pixels)")
    axes[0, 1].set_title("normalized projection corr."); axes[0, 1].legend(frameon=False, fontsize=7.5)
    hg, wg = template.shape
    h, w = scene.shape
    ext = (-(wg - 1) / 2 - 0.5, w + (wg - 1) / 2 - 0.5, h + (hg - 1) / 2 - 0.5, -(hg - 1) / 2 - 0.5)
    for ax, name in zip(axes[1], names[:2]):
        res = results[name]
        ax.imshow(_s(np.clip(res["map"], 0, 2)), cmap="magma", extent=ext)
        for r, q in res["positions"]:
            ax.plot(float(_s(q)), float(_s(r)), "o", mfc="none", mec="cyan", ms=8)
        ax.set_xlim(-0.5, w - 0.5); ax.set_ylim(h - 0.5, -0.5)
        ax.set_title(f"{name}: {len(res['positions'])} candidates")
    for ax in (axes[0, 0], *axes[1]):
        ax.axis("off")
    fig.tight_layout()
    return fig


def _block(ax, x, y, w, h, text):
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((x, y), w, h, fill=False, lw=1.0))
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=8)


def _arrow(ax, x0, y0, x1, y1):
    from matplotlib.patches import FancyArrowPatch

    ax.add_patch(FancyArrowPatch((x0, y0), (x1, y1), arrowstyle="->", mutation_scale=9, lw=0.9))


def architectures_figure():
    """Block diagrams of the multichannel acousto-optic correlators of Figs. 8 and 9."""
    fig, axes = plt.subplots(2, 1, figsize=(6.4, 4.4))
    ax = axes[0]
    _block(ax, 0.0, 0.3, 0.25, 0.4, "P1: AO cell\nprojections on\ncarriers $f_1, f_2$")
    _block(ax, 0.37, 0.05, 0.26, 0.9, "P2: N fixed masks\n(class n: H and V\nreferences on\n$f_1, f_2$)")
    _block(ax, 0.75, 0.05, 0.25, 0.9, "P3: N detectors\n(space integration)\n$\\sum_k$ corr$_k$(t)")
    _arrow(ax, 0.25, 0.5, 0.37, 0.5); _arrow(ax, 0.63, 0.5, 0.75, 0.5)
    ax.set_title("Fig. 8: multichannel space-integrating correlator")
    ax = axes[1]
    _block(ax, 0.0, 0.05, 0.25, 0.9, "P1: N point\nmodulators\n(references\n$h_n(t)$)")
    _block(ax, 0.37, 0.3, 0.26, 0.4, "P2: one AO cell\ntest projection\n$s(t - x)$")
    _block(ax, 0.75, 0.05, 0.25, 0.9, "P3: N x X\ndetector array\n(time integration)\ncorr$_n(x)$")
    _arrow(ax, 0.25, 0.5, 0.37, 0.5); _arrow(ax, 0.63, 0.5, 0.75, 0.5)
    ax.set_title("Fig. 9: multichannel time-integrating correlator")
    for ax in axes:
        ax.set_xlim(-0.02, 1.02); ax.set_ylim(0, 1); ax.axis("off")
    fig.tight_layout()
    return fig


def time_integrating_figure(output: np.ndarray, labels: Sequence[str], title: str):
    """The P3 output of the time-integrating correlator (channels x lags) and its largest value per channel."""
    fig, axes = plt.subplots(2, 1, figsize=(6.4, 4.6))
    im = axes[0].imshow(_s(output), aspect="auto", cmap="RdBu_r", vmin=-1, vmax=1)
    fig.colorbar(im, ax=axes[0], fraction=0.05, pad=0.02, label="bipolar correlation")
    axes[0].set_xlabel("detector column (lag)"); axes[0].set_ylabel("channel (class)")
    axes[0].set_yticks(range(0, len(labels), 5), labels=[labels[i] for i in range(0, len(labels), 5)])
    axes[0].set_title(title)
    axes[1].plot(_s(output.max(axis=1)), "o", ms=4)
    axes[1].set_xticks(range(len(labels)), labels=list(labels), fontsize=7.5)
    axes[1].set_title("largest output per channel"); axes[1].set_ylabel("peak")
    fig.tight_layout()
    return fig

"""The real plaza video: where its residual sits, its calibration, and two readings beyond the panels.

Where the residual energy of the real frames sits and how large the camera noise is
(:func:`residual_location`), the video with the people's contrast scaled
(:func:`contrast_scaled`) and calibrated to the printed brightness and ``n_2``
(:func:`calibrate_real`), the margin of the one-eigenimage count of Fig. 2
(:func:`rank_margin`) and the energy the final eigenimages keep (:func:`energy_kept_table`).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from projtrack._validation import as_array, as_real, as_rng
from projtrack.novelty import FrameRecord, NoveltyFilter, batch_kl, process_sequence

from .street import FIG2_SETTINGS, PIXEL_THRESHOLD, novelty_against_first

__all__ = ["median_background", "residual_location", "contrast_scaled", "calibrate_real",
           "max_second_fraction", "rank_margin", "energy_kept_table"]


def median_background(frames: Any) -> tuple[np.ndarray, np.ndarray]:
    """The per-pixel median of ``frames`` (the background estimate ``B``) and ``frames - B``."""
    f = as_array(frames, "frames", ndim=3, allow_empty=False)
    background = np.median(f, axis=0)
    return background, f - background


def residual_location(dev: Any, thresholds: Sequence[float] = (8.0, 30.0),
                      still_threshold: float = PIXEL_THRESHOLD) -> tuple[pd.DataFrame, float, np.ndarray]:
    """Where the residual ``x - B`` sits: on the pixels above each threshold (the people) or not.

    Parameters
    ----------
    dev : array_like (I, H, W)
        Frames minus the background (:func:`median_background`).
    thresholds : sequence of float
        Grey-level thresholds ``|x - B| > t`` that mark people pixels.
    still_threshold : float
        Pixels never above it in any frame are *still*; their spread is the pixel noise.

    Returns
    -------
    table : pandas.DataFrame
        Per threshold: the range over frames of the covered fraction and of the share of the
        residual energy on those pixels.
    noise_sd : float
        Standard deviation of ``x - B`` on the still pixels.
    still : ndarray (H, W) bool
    """
    dev = as_array(dev, "dev", ndim=3, allow_empty=False)
    still_threshold = as_real(still_threshold, "still_threshold", 0.0)
    rows = []
    for thr in thresholds:
        thr = as_real(thr, "thresholds", 0.0)
        mask = np.abs(dev) > thr
        share = (np.where(mask, dev, 0) ** 2).sum(axis=(1, 2)) / (dev ** 2).sum(axis=(1, 2))
        rows.append({"people pixels: |x - B| >": f"{thr:.0f} grey levels",
                     "pixels covered per frame (range)": f"{mask.mean(axis=(1, 2)).min():.1%} - {mask.mean(axis=(1, 2)).max():.1%}",
                     "share of residual energy on them (range)": f"{share.min():.1%} - {share.max():.1%}"})
    still = ~(np.abs(dev) > still_threshold).any(axis=0)
    noise_sd = float(dev[:, still].std())
    return pd.DataFrame(rows).set_index("people pixels: |x - B| >"), noise_sd, still


def contrast_scaled(background: Any, dev: Any, alpha: float) -> np.ndarray:
    """The video with the people's contrast scaled: ``B + alpha (x - B)``."""
    alpha = as_real(alpha, "alpha", 0.0)
    return np.asarray(background, dtype=float) + alpha * np.asarray(dev, dtype=float)





def max_second_fraction(recs: Sequence[FrameRecord]) -> float:
    """The largest second information fraction ``F_i,2`` over the updates of a sequence (0 if none)."""
    return max((float(r.fractions[1]) for r in recs if r.fractions is not None and len(r.fractions) > 1),
               default=0.0)


def rank_margin(background: Any, dev: Any, alphas: Sequence[float] = (1, 2, 3, 4, 6),
                pixel_threshold: float = PIXEL_THRESHOLD) -> pd.DataFrame:
    """The rank-1 claim of Fig. 2 against the people's contrast ``alpha``.

    Returns
    -------
    pandas.DataFrame
        Index ``alpha``; the largest number of eigenimages kept and the largest ``F_i,2``
        under the Fig. 2 settings.
    """
    rows = []
    for alpha in alphas:
        recs = process_sequence(contrast_scaled(background, dev, alpha), *FIG2_SETTINGS,
                                pixel_threshold=pixel_threshold)
        rows.append({"alpha": alpha, "max eigenimages kept": max(r.rank for r in recs),
                     "largest F_i,2": max_second_fraction(recs)})
    return pd.DataFrame(rows).set_index("alpha")


def energy_kept_table(sequences: Mapping[str, Any],
                      settings: Sequence[tuple[float, float]] = ((0.002, 0.95), (0.001, 0.9995))
                      ) -> pd.DataFrame:
    """Energy the final eigenimages keep, against ``1 - T_I`` and the batch optimum.

    Parameters
    ----------
    sequences : mapping
        Name -> frames ``(I, H, W)``.
    settings : sequence of (T_d, T_I)

    Returns
    -------
    pandas.DataFrame
        Per sequence and ``T_I``: eigenimages kept, the share of the energy kept (percent),
        ``loss / (1 - T_I)`` and the share the batch KL keeps with as many eigenimages.
    """
    rows = []
    for name, frames in sequences.items():
        X = np.asarray(frames).reshape(len(frames), -1).astype(float)
        total = float(np.sum(X ** 2))
        for td, ti in settings:
            filt = NoveltyFilter(td, ti).fit(frames)
            kept = float(np.sum((X @ filt.components_.T) ** 2) / total)
            best = float(batch_kl(frames, n_components=filt.rank_).eigenvalues.sum() * len(X) / total)
            rows.append({"sequence": name, "T_I": ti, "eigenimages kept": filt.rank_,
                         "energy kept (%)": 100 * kept, "loss / (1 - T_I)": (1 - kept) / (1 - ti),
                         "batch optimum (%)": 100 * best})
    return pd.DataFrame(rows)



def calibrate_real(frames: Any, rng: np.random.Generator, target_rms: float = 67.0,
                   people_threshold: float = 30.0) -> dict[str, Any]:
    """The real video at the paper's exposure and with its people's contrast calibrated.

    The printed ``V_1`` fixes the paper's frame-1 RMS grey level (``target_rms``).  The video
    is darkened by ``gain = target_rms / RMS(frame 1)``; since its camera noise (the temporal
    standard deviation on the pixels no person covers, :func:`residual_location`) would shrink
    with it, independent noise of standard deviation ``noise sqrt(1 - gain^2)`` is added
    (drawn once from ``rng``) so that the darker video has the camera's noise again.  Then the
    people's contrast ``alpha`` of ``B + alpha (x - B)`` (before the exposure change) is
    calibrated twice: on ``n_2 = 0.0018`` (frame 2 against frame 1) and on ``n_4 = 0.0025``
    (frame 4 against frame 1).

    Returns
    -------
    dict
        ``gain``, ``camera noise`` (grey levels), ``added noise``, ``contrast (n_2)``,
        ``contrast (n_4)``, ``frames`` (the video calibrated on ``n_2``), ``frames (n_4)``,
        ``background`` (the darkened median background), ``masks`` (pixels more than
        ``people_threshold`` grey levels from the median background, the people).
    """
    f = as_array(frames, "frames", ndim=3, allow_empty=False)
    target_rms = as_real(target_rms, "target_rms", 0.0, low_open=True)
    background, dev = median_background(f)
    _, noise_sd, _ = residual_location(dev)
    gain = target_rms / float(np.sqrt(np.mean(f[0] ** 2)))
    if gain >= 1:
        raise ValueError(f"the video is darker than target_rms = {target_rms} already")
    added = noise_sd * float(np.sqrt(1 - gain ** 2))
    noise = added * as_rng(rng).standard_normal(f.shape)

    def video(alpha: float) -> np.ndarray:
        return gain * contrast_scaled(background, dev, alpha) + noise

    a2 = brentq(lambda a: novelty_against_first(video(a), 2) - 0.0018, 0.01, 1.0, xtol=1e-8)
    a4 = brentq(lambda a: novelty_against_first(video(a), 4) - 0.0025, 0.01, 1.0, xtol=1e-8)
    return {"gain": gain, "camera noise": noise_sd, "added noise": added, "contrast (n_2)": a2,
            "contrast (n_4)": a4, "frames": video(a2), "frames (n_4)": video(a4),
            "background": gain * background, "masks": np.abs(dev) > people_threshold}

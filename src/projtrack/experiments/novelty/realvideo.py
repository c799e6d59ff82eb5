"""Readings of the real plaza video (and of the synthetic stand-in) beyond the paper's panels.

Where the residual energy of the real frames sits (:func:`residual_location`), the video with
the people's contrast scaled by ``alpha`` (:func:`contrast_scaled`, :func:`calibrate_contrast`
on the printed ``n_2``), the Fig. 2 pattern of a sequence (:func:`fig2_pattern`), the margin of
the rank-1 claim (:func:`rank_margin`) and the energy the final eigenimages keep
(:func:`energy_kept_table`).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from projtrack._validation import as_array, as_int, as_real
from projtrack.novelty import FrameRecord, NoveltyFilter, batch_kl, process_sequence
from projtrack.stable import fmt

from .street import FIG2_SETTINGS, PIXEL_THRESHOLD, entry_marked

__all__ = ["median_background", "residual_location", "contrast_scaled", "first_novelty",
           "calibrate_contrast", "fig2_pattern", "max_second_fraction", "rank_margin",
           "energy_kept_table", "rms_ratio"]


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


def first_novelty(frames: Any, j: int = 2, novelty_threshold: float = FIG2_SETTINGS[0],
                  information_threshold: float = FIG2_SETTINGS[1]) -> float:
    """The novelty (Eq. (7)) of frame ``j`` against the model built from frame 1 alone."""
    j = as_int(j, "j", minimum=2, maximum=len(frames))
    f = NoveltyFilter(novelty_threshold, information_threshold)
    f.partial_fit(frames[0])
    return f.novelty(frames[j - 1])


def calibrate_contrast(background: Any, dev: Any, target: float = 0.0018, lo: float = 0.01,
                       hi: float = 1.0, xtol: float = 1e-8) -> float:
    """The contrast scale ``alpha`` in ``[lo, hi]`` at which frame 2's novelty is ``target``.

    Solved with :func:`scipy.optimize.brentq` on :func:`first_novelty` of
    :func:`contrast_scaled`; ``target`` must be bracketed by the novelties at ``lo`` and ``hi``.
    """
    target = as_real(target, "target", 0.0, 1.0)
    return brentq(lambda a: first_novelty(contrast_scaled(background, dev, a)) - target,
                  lo, hi, xtol=xtol)


def fig2_pattern(frames: Any, pixel_threshold: float = PIXEL_THRESHOLD
                 ) -> tuple[list[FrameRecord], dict[str, Any]]:
    """The Fig. 2 readings of a sequence as the text states them (frames 2, 3, 4, 8).

    Returns
    -------
    recs : list of FrameRecord
        :func:`~projtrack.novelty.process_sequence` with the Fig. 2 settings.
    row : dict
        ``n_2``, ``n_3``, ``n_4``, ``F_4,2``, novel frames among 2-7, ``n_8``, ``F_8,2``, the
        update number of frame 8 and :func:`~projtrack.experiments.novelty.entry_marked`
        (numbers as strings, as printed).
    """
    recs = process_sequence(frames, *FIG2_SETTINGS, pixel_threshold=pixel_threshold)
    if len(recs) < 8:
        raise ValueError(f"frames must hold at least 8 frames, got {len(recs)}")

    def f_of(r):
        return fmt(r.fractions[1], ".6f") if r.fractions is not None else "not novel"

    return recs, {"n_2": fmt(recs[1].novelty, ".4f"), "n_3": fmt(recs[2].novelty, ".4f"),
                  "n_4": fmt(recs[3].novelty, ".4f"), "F_4,2": f_of(recs[3]),
                  "novel among frames 2-7": f"{sum(r.novel for r in recs[1:7])} of 6",
                  "n_8": fmt(recs[7].novelty, ".4f"), "F_8,2": f_of(recs[7]),
                  "frame 8 is update number": f"{sum(r.novel for r in recs[:8])}" if recs[7].novel else "not novel",
                  "entry marked": entry_marked(recs)}


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
        (4 decimals) under the Fig. 2 settings.
    """
    rows = []
    for alpha in alphas:
        recs = process_sequence(contrast_scaled(background, dev, alpha), *FIG2_SETTINGS,
                                pixel_threshold=pixel_threshold)
        rows.append({"alpha": alpha, "max eigenimages kept": max(r.rank for r in recs),
                     "largest F_i,2": fmt(max_second_fraction(recs), ".4f")})
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
        Per sequence and setting: eigenimages kept, energy kept, ``loss / (1 - T_I)`` and the
        energy the batch KL keeps with as many eigenimages.
    """
    rows = []
    for name, frames in sequences.items():
        X = np.asarray(frames).reshape(len(frames), -1).astype(float)
        total = float(np.sum(X ** 2))
        for td, ti in settings:
            filt = NoveltyFilter(td, ti).fit(frames)
            kept = float(np.sum((X @ filt.components_.T) ** 2) / total)
            best = float(batch_kl(frames, n_components=filt.rank_).eigenvalues.sum() * len(X) / total)
            rows.append({"sequence": name, "T_d": td, "T_I": ti, "eigenimages kept": filt.rank_,
                         "energy kept": fmt(kept, ".4%"), "loss / (1 - T_I)": fmt((1 - kept) / (1 - ti), ".2f"),
                         "batch optimum, same number": fmt(best, ".4%")})
    return pd.DataFrame(rows)


def rms_ratio(img: Any, frames: Any, background: Any) -> float:
    """RMS of ``img - B`` over the mean per-frame RMS of ``frames - B`` (1: no better than a frame)."""
    f = as_array(frames, "frames", ndim=3)
    img = as_array(img, "img", shape=f.shape[1:])
    return float(np.sqrt(np.mean((img - background) ** 2))
                 / np.mean(np.sqrt(np.mean((f - background) ** 2, axis=(1, 2)))))

"""A novelty filter run over a whole sequence, every frame recorded as in Figs. 2-3."""
from __future__ import annotations

from typing import Any

import numpy as np

from ._checks import as_frames
from .filter import NoveltyFilter
from .results import FrameRecord

__all__ = ["process_sequence"]


def process_sequence(frames: Any, novelty_threshold: float, information_threshold: float,
                     pixel_threshold: float = 8.0, method: str = "qr") -> list[FrameRecord]:
    """Run a :class:`NoveltyFilter` over ``frames`` and record every frame (Figures 2-3).

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
    novelty_threshold, information_threshold : float
        ``T_d`` and ``T_I``.
    pixel_threshold : float
        ``T_f`` of the novel-pixel image (8 grey levels in the paper).
    method : {"qr", "vip"}
        Numerical route of the update (:class:`NoveltyFilter`).

    Returns
    -------
    list of FrameRecord
    """
    x = as_frames(frames)
    filt = NoveltyFilter(novelty_threshold, information_threshold, method)
    out = []
    for j, frame in enumerate(x, start=1):
        if j == 1:
            mask = np.ones(frame.shape, dtype=bool)
        else:
            mask = filt.novel_pixels(frame, pixel_threshold)
        iteration = filt.n_updates_ + 1 if j > 1 else 1
        n, novel = filt.partial_fit(frame)
        out.append(FrameRecord(
            frame=j, iteration=iteration, novelty=n, novel=novel,
            vip=filt.vip_matrix_.copy(),
            fractions=filt.information_fractions_.copy() if novel else None,
            rank=filt.rank_, novel_pixels=mask, eigenvalues=filt.eigenvalues_,
            first_eigenimage=filt.weighted_eigenimages()[0]))
    return out


"""Example 3 of Marques et al. (2002), Fig. 9: slot-car video tracking.

Background subtraction (:func:`active_pixels`, :func:`training_background`) and the
training of the DMA model and of the active-pixel sensor of eq. (15) from annotated
training runs (:func:`fit_slotcar`).
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array
from projtrack.dma import DMA, ActivePixelSensor

__all__ = ["active_pixels", "training_background", "fit_slotcar"]


def active_pixels(frames: np.ndarray, threshold: float, background: np.ndarray | None = None) -> np.ndarray:
    """Background subtraction and thresholding (Sec. 4.3): ``|frame - background| > threshold``.

    The background defaults to the per-pixel median of the frames (the car moves, so the
    median is the empty scene)."""
    F = as_array(frames, "frames", ndim=3)
    bg = np.median(F, axis=0) if background is None else np.asarray(background, dtype=float)
    if bg.shape != F.shape[1:]:
        raise ValueError(f"background must have shape {F.shape[1:]}, got {bg.shape}")
    return np.abs(F - bg) > threshold


def training_background(train_videos: list) -> np.ndarray:
    """The background image of Example 3 from the training runs only: the per-pixel
    median of all their frames (the car moves, so the median is the empty scene).

    ``train_videos`` is a non-empty list of objects with a ``frames`` array ``(N, H, W)``
    (e.g. :class:`projtrack.scenes.slotcar.SlotCarVideo`) of one frame size
    (ValueError otherwise)."""
    if not isinstance(train_videos, (list, tuple)) or not train_videos:
        raise ValueError("train_videos must be a non-empty list of videos")
    frames = [np.asarray(getattr(v, "frames", None), dtype=float) for v in train_videos]
    if any(f.ndim != 3 for f in frames) or len({f.shape[1:] for f in frames}) != 1:
        raise ValueError("every training video must have frames of shape (N, H, W) with one frame size")
    return np.median(np.concatenate(frames), axis=0)


def fit_slotcar(
    train_videos: list,
    rng: np.random.Generator,
    *,
    n_regions: int = 8,
    n_prototypes: int = 8,
    box: int = 5,
    threshold: float = 0.15,
    annotation_std: float = 0.5,
    background: np.ndarray | None = None,
) -> tuple[DMA, ActivePixelSensor]:
    """Example 3 training: DMA on hand-annotated car positions, ``c`` of eq. (15) from frames.

    The paper annotated the training runs by hand; here the generator's true positions
    plus ``N(0, annotation_std^2)`` pixel noise stand in for the annotation. The
    manifold (1-D local frames), the transition matrix, the start distribution (state
    frequencies of the training runs, :func:`projtrack.dma.estimate_start`) and ``c``
    (see :meth:`ActivePixelSensor.fit_c`) are all learned from the training runs only.
    The active pixels of the training frames are taken against ``background``
    (default: :func:`training_background` of ``train_videos``); use the same image for
    the test video.
    """
    trajs = [v.positions + annotation_std * rng.standard_normal(v.positions.shape) for v in train_videos]
    model = DMA(n_regions=n_regions, n_prototypes=n_prototypes, dim=1, rng=rng).fit(trajs)
    bg = training_background(train_videos) if background is None else background
    act = np.concatenate([active_pixels(v.frames, threshold, bg) for v in train_videos])
    pos = np.concatenate(trajs)
    c = ActivePixelSensor.fit_c(act, pos, box)
    return model, ActivePixelSensor(model.prototypes_, box, c)

"""Example 3 of Marques et al. (2002), Fig. 9: slot-car video tracking.

Background subtraction (:func:`active_pixels`, :func:`training_background`) and the
training of the DMA model and of the active-pixel sensor of eq. (15) from annotated
training runs (:func:`fit_slotcar`).
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_count, as_int, as_real
from projtrack.dma import DMA, ActivePixelSensor
from projtrack.montecarlo import run
from projtrack.scenes.slotcar import make_slotcar_video
from projtrack.tolerance import Tolerance, mean_over, numerical, statistical

__all__ = [
    "active_pixels",
    "training_background",
    "fit_slotcar",
    "track_video",
    "tracking_study",
    "tracking_error_rows",
    "tracking_error_table",
    "training_summary",
    "path_step",
    "sensitivity_study",
]


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


def track_video(
    rng: np.random.Generator,
    model: DMA,
    sensor: ActivePixelSensor,
    background: np.ndarray,
    *,
    n_frames: int = 593,
    threshold: float = 0.15,
    **video_options: object,
) -> dict[str, np.ndarray]:
    """One test video of Example 3 tracked by a fitted model; errors in pixels per frame.

    Renders :func:`projtrack.scenes.slotcar.make_slotcar_video` (``n_frames``,
    ``video_options``) from ``rng``, takes its active pixels against ``background`` and
    returns the errors of the DMA Viterbi estimate (``"viterbi"``), of the per-frame
    detector (the centroid whose box holds the most active pixels, ``"per-frame"``), of
    the nearest centroid to the truth (the floor set by the centroids, ``"floor"``) and
    the ``"occluded"`` flags of the frames.
    """
    video = make_slotcar_video(n_frames, rng, **video_options)
    active = active_pixels(video.frames, threshold, background)
    est = model.predict(active, sensor)
    naive = model.prototypes_[np.argmax(sensor.counts(active), axis=1)]
    quant = model.prototypes_[model.quantize(video.positions)]
    return {"viterbi": np.linalg.norm(est - video.positions, axis=1),
            "per-frame": np.linalg.norm(naive - video.positions, axis=1),
            "floor": np.linalg.norm(quant - video.positions, axis=1), "occluded": video.occluded}


def tracking_study(
    model: DMA,
    sensor: ActivePixelSensor,
    background: np.ndarray,
    n_videos: int,
    rng: np.random.Generator,
    **options: object,
) -> list[dict[str, np.ndarray]]:
    """:func:`track_video` on ``n_videos`` test videos through :func:`projtrack.montecarlo.run`.

    Video ``i`` is drawn from the ``i``-th child of ``rng``; ``options`` go to
    :func:`track_video`. ``n_videos`` must be an int >= 1 (ValueError otherwise).
    """
    n_videos = as_count(n_videos, "n_videos")
    return run(track_video, n_videos, rng, model, sensor, background, **options)


def tracking_error_rows(condition: str, trials: list[dict[str, np.ndarray]]) -> list[dict[str, object]]:
    """Mean errors (px) of :func:`tracking_study` trials on all frames, visible and hidden frames.

    One row per frame set (``"all"``, ``"car visible"``, ``"car under the bridge"``) with
    the frame count and the mean error of the Viterbi estimate, the per-frame detector and
    the nearest-centroid floor. ``trials`` must be a non-empty list (ValueError otherwise).
    """
    if not isinstance(trials, (list, tuple)) or not trials:
        raise ValueError("trials must be a non-empty list of track_video results")
    occ = np.concatenate([t["occluded"] for t in trials])
    rows: list[dict[str, object]] = []
    for frames, sel in (("all", np.ones_like(occ)), ("car visible", ~occ), ("car under the bridge", occ)):
        e = {m: np.concatenate([t[m] for t in trials])[sel] for m in ("viterbi", "per-frame", "floor")}
        rows.append({"condition": condition, "frames": frames, "count": int(sel.sum()),
                     "DMA Viterbi error [px]": float(e["viterbi"].mean()),
                     "per-frame detector error [px]": float(e["per-frame"].mean()),
                     "nearest-centroid floor [px]": float(e["floor"].mean())})
    return rows


def path_step(model: DMA) -> float:
    """The longest step of the learned motion model in pixels: the largest distance between two
    centroids joined by a non-zero transition. One flipped Viterbi decision moves the decoded
    position of a frame by at most about this much (the path then runs through a neighbour)."""
    A = model.transitions_.tocoo() if hasattr(model.transitions_, "tocoo") else None
    P = np.asarray(model.prototypes_, dtype=float)
    if A is None:
        i, j = np.nonzero(np.asarray(model.transitions_))
    else:
        i, j = A.row, A.col
    if len(i) == 0:
        raise ValueError("the model has no transition")
    return float(np.max(np.linalg.norm(P[i] - P[j], axis=1)))


def tracking_error_table(runs: dict[str, list[dict[str, np.ndarray]]], models: dict[str, tuple],
                         frame_shape: tuple[int, int] = (48, 64)):
    """The Fig. 9 error table (mean error in px per condition and frame set) and its tolerances.

    Parameters
    ----------
    runs : dict
        Condition -> the :func:`tracking_study` trials.
    models : dict
        Condition -> ``(model, sensor)`` of :func:`fit_slotcar` (for :func:`path_step`).
    frame_shape : (int, int)
        Video frame size, whose diagonal bounds one per-frame detection's error.

    Returns
    -------
    table : pandas.DataFrame
        Columns ``condition``, ``frames``, ``count``, ``DMA Viterbi [px]``,
        ``per-frame detector [px]``, ``nearest-centroid floor [px]``.
    tolerance : dict of str to Tolerance
        Each error column is a mean over at least ``min(count)`` frames. One flipped Viterbi
        decision re-routes a short stretch of the path through neighbouring centroids: three
        frames, each off by up to :func:`path_step`. One flipped per-frame detection (a tie
        between two boxes' active-pixel counts broken by one pixel at the threshold) can land
        anywhere in the frame: one frame off by up to the frame diagonal. The floor depends
        only on the k-means centroids, which converge far from ties: numerical.
    """
    import pandas as pd

    if not isinstance(runs, dict) or not runs:
        raise ValueError("runs must be a non-empty dict of condition -> trials")
    missing = sorted(set(runs) - set(models))
    if missing:
        raise ValueError(f"models has no model for the conditions {missing}")
    rows = [row for k, trials in runs.items() for row in tracking_error_rows(k, trials)]
    table = pd.DataFrame(rows).rename(columns={"DMA Viterbi error [px]": "DMA Viterbi [px]",
                                               "per-frame detector error [px]": "per-frame detector [px]",
                                               "nearest-centroid floor [px]": "nearest-centroid floor [px]"})
    n = int(table["count"].min())
    step = max(path_step(m) for m, _ in models.values())
    diag = float(np.hypot(*frame_shape))
    tolerance: dict[str, Tolerance] = {
        "DMA Viterbi [px]": mean_over(n, round(step, 1), flips=3, what="frame"),
        "per-frame detector [px]": mean_over(n, round(diag, 1), flips=1, what="frame"),
        "nearest-centroid floor [px]": numerical(rtol=1e-6, why="distances to k-means centroids, which "
                                                 "converge to 1e-8 far from ties"),
    }
    return table, tolerance


def training_summary(models: dict[str, tuple], train: dict[str, list], background: dict[str, np.ndarray],
                     threshold: float = 0.15):
    """What Example 3 learned in each condition, and its tolerances.

    Returns
    -------
    table : pandas.DataFrame
        Per condition: regions, centroids, non-zero transitions, ``c`` of eq. (15), ``log c``
        and the median number of active pixels per training frame.
    tolerance : dict of str to Tolerance
        ``c`` is a ratio of active-pixel counts over every training frame: a pixel flipping
        across the threshold moves it by far less than 1%.
    """
    import pandas as pd

    rows = []
    for k, (model, sensor) in models.items():
        act = active_pixels(np.concatenate([v.frames for v in train[k]]), threshold, background[k])
        rows.append({"condition": k, "regions": model.manifold_.n_regions, "centroids": model.manifold_.n_prototypes,
                     "non-zero transitions": int(model.transitions_.nnz), "c of eq. (15)": float(sensor.c),
                     "log c": float(np.log(sensor.c)),
                     "median active pixels": int(np.median(act.sum(axis=(1, 2))))})
    tol = statistical(rtol=0.005, why="a ratio of active-pixel counts over every training frame: a few pixels "
                                      "crossing the threshold move it by far less than 0.5%")
    return pd.DataFrame(rows), {"c of eq. (15)": tol, "log c": statistical(atol=0.005, why="log of c (see c)")}


def sensitivity_study(
    train_videos: list,
    video: object,
    background: np.ndarray,
    regions: tuple[int, ...],
    prototypes: tuple[int, ...],
    seed: int,
    *,
    base: tuple[int, int] = (8, 8),
    threshold: float = 0.15,
) -> tuple[list[dict[str, object]], dict[str, float]]:
    """Viterbi error on one test ``video`` versus the numbers of regions and centroids.

    For every ``M`` in ``regions`` and ``K`` in ``prototypes``, :func:`fit_slotcar` (from
    a fresh ``numpy.random.default_rng(seed)``) and the mean error (px) over all frames
    and over the hidden ones. Also returns, for ``(M, K) = base``, the mean error of the
    three decoders (``"viterbi"``, ``"smooth"``, ``"filter"``; empty if ``base`` is not in
    the grid). ``regions`` and ``prototypes`` must be non-empty (ValueError otherwise).
    """
    Ms = [as_int(m, "regions[i]", minimum=1) for m in regions]
    Ks = [as_int(k, "prototypes[i]", minimum=1) for k in prototypes]
    if not Ms or not Ks:
        raise ValueError("regions and prototypes must not be empty")
    threshold = as_real(threshold, "threshold")
    active = active_pixels(video.frames, threshold, background)  # type: ignore[attr-defined]
    truth, occ = video.positions, video.occluded  # type: ignore[attr-defined]
    rows: list[dict[str, object]] = []
    at_base: dict[str, float] = {}
    for M in Ms:
        for K in Ks:
            model, sensor = fit_slotcar(train_videos, np.random.default_rng(seed), n_regions=M, n_prototypes=K,
                                        threshold=threshold, background=background)
            e = np.linalg.norm(model.predict(active, sensor) - truth, axis=1)
            rows.append({"regions": M, "centroids per region": K, "centroids": model.manifold_.n_prototypes,
                         "viterbi error [px]": float(e.mean()), "viterbi error, hidden [px]": float(e[occ].mean())})
            if (M, K) == tuple(base):
                at_base = {m: float(np.linalg.norm(model.predict(active, sensor, method=m) - truth, axis=1).mean())
                           for m in ("viterbi", "smooth", "filter")}
    return rows, at_base

"""Example 3 of Marques et al. (2002), Fig. 9: slot-car video tracking.

Background subtraction (:func:`active_pixels`, :func:`training_background`) and the
training of the DMA model and of the active-pixel sensor of eq. (15) from annotated
training runs (:func:`fit_slotcar`); the tracking study (:func:`tracking_study`) and two
trackers that do without the learned manifold (:func:`detect_and_interpolate`,
:class:`GridHMM`), for the paper's claim that none of its problems can be solved without it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_array, as_count, as_int, as_real
from projtrack.dma import DMA, ActivePixelSensor, log_transitions, viterbi
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
    "box_counts",
    "detector_threshold",
    "detect_and_interpolate",
    "longest_gap",
    "GridHMM",
    "fit_grid_hmm",
    "MapFree",
    "map_free_table",
    "sensitivity_table",
    "covering_tolerance",
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
    map_free: "MapFree | None" = None,
    **video_options: object,
) -> dict[str, np.ndarray]:
    """One test video of Example 3 tracked by a fitted model; errors in pixels per frame.

    Renders :func:`projtrack.scenes.slotcar.make_slotcar_video` (``n_frames``,
    ``video_options``) from ``rng``, takes its active pixels against ``background`` and
    returns the errors of the DMA Viterbi estimate (``"viterbi"``), of DMA's per-instant
    forward-backward estimate (``"smooth"``), of the per-frame
    detector (the centroid whose box holds the most active pixels, ``"per-frame"``), of
    the nearest centroid to the truth (the floor set by the centroids, ``"floor"``) and
    the ``"occluded"`` flags of the frames. With ``map_free`` (:class:`MapFree`), also the
    errors of the two trackers without the manifold (``"detector"``:
    :func:`detect_and_interpolate`; ``"grid"``: :class:`GridHMM`) and the detector's longest
    run of frames without a detection (``"gap"``).
    """
    video = make_slotcar_video(n_frames, rng, **video_options)
    active = active_pixels(video.frames, threshold, background)
    est = model.predict(active, sensor)
    naive = model.prototypes_[np.argmax(sensor.counts(active), axis=1)]
    quant = model.prototypes_[model.quantize(video.positions)]
    smooth = model.predict(active, sensor, method="smooth")
    out = {"viterbi": np.linalg.norm(est - video.positions, axis=1),
           "smooth": np.linalg.norm(smooth - video.positions, axis=1),
           "per-frame": np.linalg.norm(naive - video.positions, axis=1),
           "floor": np.linalg.norm(quant - video.positions, axis=1), "occluded": video.occluded}
    if map_free is not None:
        det, found = detect_and_interpolate(active, map_free.n_min, box=map_free.box)
        out["detector"] = np.linalg.norm(det - video.positions, axis=1)
        out["gap"] = np.array(longest_gap(found))
        out["grid"] = np.linalg.norm(map_free.grid.predict(active) - video.positions, axis=1)
        for label, g in map_free.variants.items():
            out[f"grid {label}"] = np.linalg.norm(g.predict(active) - video.positions, axis=1)
    return out


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
    a fresh ``numpy.random.default_rng(seed)``), the mean error (px) over all frames
    and over the hidden ones, and the model's :func:`path_step`. Also returns, for ``(M, K) = base``, the mean error of the
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
                         "viterbi error [px]": float(e.mean()), "viterbi error, hidden [px]": float(e[occ].mean()),
                         "path step [px]": path_step(model)})
            if (M, K) == tuple(base):
                at_base = {m: float(np.linalg.norm(model.predict(active, sensor, method=m) - truth, axis=1).mean())
                           for m in ("viterbi", "smooth", "filter")}
    return rows, at_base


# -- estimators without the manifold (DMA-S4: "none of the problems can be solved without the geometric information")


def box_counts(active: np.ndarray, box: int) -> np.ndarray:
    """Active pixels in the ``box x box`` square centred at every pixel of every frame
    (zero padding at the borders), as integers ``(N, H, W)``."""
    A = np.asarray(active)
    if A.ndim != 3:
        raise ValueError(f"active must be a stack of binary images (N, H, W), got shape {A.shape}")
    L = as_int(box, "box", minimum=1)
    h = L // 2
    N, H, W = A.shape
    I = np.zeros((N, H + L, W + L), dtype=np.int64)
    I[:, h + 1:h + 1 + H, h + 1:h + 1 + W] = A.astype(np.int64)
    I = I.cumsum(axis=1).cumsum(axis=2)
    return I[:, L:, L:] - I[:, :H, L:] - I[:, L:, :W] + I[:, :H, :W]


def detector_threshold(train_videos: list, background: np.ndarray, *, box: int = 5, threshold: float = 0.15) -> float:
    """The detection threshold of :func:`detect_and_interpolate`, from the training frames only:
    half the median, over the training frames, of the largest ``box x box`` active-pixel count
    of the frame (the car is visible in most frames, so that median is the car's typical count;
    half of it still detects a car that is partly hidden). No position is used."""
    act = np.concatenate([active_pixels(np.asarray(v.frames), threshold, background) for v in train_videos])
    n = box_counts(act, box)
    return 0.5 * float(np.median(n.reshape(len(n), -1).max(axis=1)))


def detect_and_interpolate(active: np.ndarray, n_min: float, *, box: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """A tracker without the manifold: a blob detector, with linear interpolation over the frames
    where it finds nothing.

    In each frame, the ``box x box`` square with the most active pixels (the first one in raster
    order on a tie) is a detection if it holds at least ``n_min`` of them; the detected position
    is the mean position of the active pixels in that square. Frames without a detection get the
    position linearly interpolated in time between the detections around them (the first or last
    detection before the first or after the last one): an off-line estimate, like Viterbi, that
    knows neither the track nor a motion model beyond "straight between sightings".

    Returns the positions ``(N, 2)`` (row, col) and the detection flags ``(N,)``. At least one
    frame must have a detection (ValueError otherwise).
    """
    A = np.asarray(active).astype(bool)
    n = box_counts(A, box)
    N, H, W = A.shape
    flat = n.reshape(N, -1)
    idx = np.argmax(flat, axis=1)
    found = flat[np.arange(N), idx] >= as_real(n_min, "n_min", 0, low_open=True)
    if not found.any():
        raise ValueError("no frame has a detection: lower n_min")
    r, c = np.unravel_index(idx, (H, W))
    h = box // 2
    pos = np.full((N, 2), np.nan)
    for t in np.flatnonzero(found):
        r0, c0 = max(r[t] - h, 0), max(c[t] - h, 0)
        rr, cc = np.nonzero(A[t, r0:r[t] + h + 1, c0:c[t] + h + 1])
        pos[t] = (rr.mean() + r0, cc.mean() + c0)
    t = np.arange(N)
    est = np.column_stack([np.interp(t, t[found], pos[found, j]) for j in range(2)])
    return est, found


def longest_gap(found: np.ndarray) -> int:
    """The longest run of consecutive ``False`` in a boolean sequence."""
    f = np.asarray(found, dtype=bool)
    d = np.diff(np.concatenate([[0], (~f).astype(np.int64), [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    return int((ends - starts).max()) if starts.size else 0


@dataclass
class GridHMM:
    """A hidden Markov model on every pixel with a generic random-walk motion model: DMA without
    the learned manifold (:func:`fit_grid_hmm`).

    Attributes
    ----------
    points : ndarray, shape (S, 2)
        The states: every pixel ``(row, col)`` of the frame.
    transitions : scipy.sparse.csr_array, shape (S, S)
        Isotropic Gaussian random walk, truncated at :attr:`max_step`, rows = from.
    sensor : projtrack.dma.ActivePixelSensor
        Eq. (15) on the pixel grid, ``c`` fitted on the training frames.
    step : float
        RMS frame-to-frame displacement of the annotated training positions (px).
    sigma : float
        Per-axis standard deviation of the random walk (px).
    """

    points: np.ndarray
    transitions: sp.csr_array
    sensor: ActivePixelSensor
    step: float
    sigma: float

    @property
    def max_step(self) -> float:
        """The longest move the random walk allows (px)."""
        return 3.0 * self.sigma

    def predict(self, active: np.ndarray) -> np.ndarray:
        """Viterbi positions ``(N, 2)`` for a stack of active-pixel images (uniform start)."""
        S = len(self.points)
        path = viterbi(np.full(S, -np.log(S)), log_transitions(self.transitions), self.sensor.log_likelihoods(active))
        return self.points[path]


def fit_grid_hmm(
    train_videos: list,
    rng: np.random.Generator,
    *,
    box: int = 5,
    threshold: float = 0.15,
    annotation_std: float = 0.5,
    background: np.ndarray | None = None,
    spread: float = 2 ** -0.5,
) -> GridHMM:
    """The random-walk HMM of :class:`GridHMM`, from the training runs.

    The annotations are the true positions plus ``N(0, annotation_std^2)`` px, drawn first from
    ``rng`` exactly as :func:`fit_slotcar` draws them (the same ``rng`` seed gives the same
    annotations). The only things learned are the RMS step of the annotated positions and ``c``
    of eq. (15) (:meth:`ActivePixelSensor.fit_c`); no track, no centroid, no direction of
    motion. The random walk's per-axis standard deviation is ``spread`` times that step (> 0;
    the default ``1/sqrt 2`` makes the walk's RMS step the training one), truncated at three
    of those standard deviations (``3 spread`` steps).
    """
    spread = as_real(spread, "spread", 0, low_open=True)
    trajs = [v.positions + annotation_std * rng.standard_normal(v.positions.shape) for v in train_videos]
    step = float(np.sqrt(np.mean(np.concatenate([(np.diff(t, axis=0) ** 2).sum(axis=1) for t in trajs]))))
    H, W = np.asarray(train_videos[0].frames).shape[1:]
    r, c = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    P = np.column_stack([r.ravel(), c.ravel()]).astype(float)
    from scipy.spatial import cKDTree

    tree = cKDTree(P)
    sigma = spread * step
    D = tree.sparse_distance_matrix(tree, 3.0 * sigma, output_type="coo_matrix")
    S = len(P)
    i, j, d = (np.concatenate([D.row, np.arange(S)]), np.concatenate([D.col, np.arange(S)]),
               np.concatenate([D.data, np.zeros(S)]))
    w = np.exp(-0.5 * (d / sigma) ** 2)
    A = sp.csr_array((w, (i, j)), shape=(S, S))
    A = sp.csr_array(sp.diags_array(1.0 / np.asarray(A.sum(axis=1)).ravel()) @ A)
    A.sort_indices()
    bg = training_background(train_videos) if background is None else background
    act = np.concatenate([active_pixels(v.frames, threshold, bg) for v in train_videos])
    c_hat = ActivePixelSensor.fit_c(act, np.concatenate(trajs), box)
    return GridHMM(P, A, ActivePixelSensor(P, box, c_hat), step, float(sigma))


@dataclass
class MapFree:
    """The trackers without the manifold of one condition: the detection threshold of
    :func:`detect_and_interpolate` (from :func:`detector_threshold`), the box side and the
    :class:`GridHMM` (``grid``) with, optionally, variants of other random-walk widths
    (``variants``: label -> GridHMM, run on the same videos for a sensitivity table)."""

    n_min: float
    box: int
    grid: GridHMM
    variants: dict = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        self.variants = dict(self.variants or {})


def map_free_table(runs: dict[str, list[dict[str, np.ndarray]]], models: dict[str, tuple],
                   map_free: dict[str, MapFree], frame_shape: tuple[int, int] = (48, 64)):
    """Hidden- and visible-frame errors of DMA and of the two trackers without the manifold.

    Parameters
    ----------
    runs : dict
        Condition -> :func:`tracking_study` trials run with ``map_free=``.
    models : dict
        Condition -> ``(model, sensor)`` of :func:`fit_slotcar`.
    map_free : dict
        Condition -> its :class:`MapFree`.
    frame_shape : (int, int)
        Frame size, whose diagonal bounds how far one flipped detection moves an estimate.

    Returns
    -------
    table : pandas.DataFrame
        Columns ``condition``, ``frames`` (``"car visible"``, ``"car under the bridge"``),
        ``DMA Viterbi [px]``, ``detector + interpolation [px]``, ``random-walk grid HMM [px]``.
    tolerance : dict of str to Tolerance
        Each a mean over at least the smallest frame count of the table. DMA: three frames off
        by up to :func:`path_step` (as in :func:`tracking_error_table`). Grid HMM: the same with
        its longest allowed move. Detector: one flipped detection (a box count crossing the
        threshold, or a tie between two boxes) moves that frame's estimate by up to the frame
        diagonal and re-draws the interpolation of the gap beside it: up to ``1 + longest gap``
        frames, each off by up to the diagonal.
    """
    import pandas as pd

    if not isinstance(runs, dict) or not runs:
        raise ValueError("runs must be a non-empty dict of condition -> trials")
    missing = sorted((set(runs) - set(models)) | (set(runs) - set(map_free)))
    if missing:
        raise ValueError(f"models or map_free has nothing for the conditions {missing}")
    rows, counts = [], []
    for k, trials in runs.items():
        if any("detector" not in t for t in trials):
            raise ValueError(f"the trials of {k!r} were run without map_free=")
        occ = np.concatenate([t["occluded"] for t in trials])
        for frames, sel in (("car visible", ~occ), ("car under the bridge", occ)):
            e = {m: np.concatenate([t[m] for t in trials])[sel] for m in ("viterbi", "detector", "grid")}
            counts.append(int(sel.sum()))
            rows.append({"condition": k, "frames": frames, "DMA Viterbi [px]": float(e["viterbi"].mean()),
                         "detector + interpolation [px]": float(e["detector"].mean()),
                         "random-walk grid HMM [px]": float(e["grid"].mean())})
    n = min(counts)
    diag = float(np.hypot(*frame_shape))
    gap = max(int(t["gap"]) for trials in runs.values() for t in trials)
    tolerance: dict[str, Tolerance] = {
        "DMA Viterbi [px]": mean_over(n, round(max(path_step(m) for m, _ in models.values()), 1), flips=3,
                                      what="frame"),
        "detector + interpolation [px]": mean_over(n, round(diag, 1), flips=1 + gap, what="frame"),
        "random-walk grid HMM [px]": mean_over(n, round(max(f.grid.max_step for f in map_free.values()), 1),
                                               flips=3, what="frame"),
    }
    return pd.DataFrame(rows), tolerance


def covering_tolerance(required: object, values: object, why: str) -> Tolerance:
    """The tightest ``atol + rtol |value|`` that allows at least ``required[i]`` at ``values[i]``
    in every row: ``atol`` the smallest requirement, ``rtol`` the largest share of a value the
    rest of its requirement takes. ``required`` and ``values`` are equal-length sequences of
    finite numbers > 0 (ValueError otherwise)."""
    req = as_array(required, "required", ndim=1, allow_empty=False)
    val = as_array(values, "values", ndim=1, shape=req.shape)
    if (req <= 0).any() or (val <= 0).any():
        raise ValueError("required and values must be > 0")
    atol = float(req.min())
    rtol = float(np.max((req - atol) / val))
    return statistical(atol=atol, rtol=rtol, why=why)


def sensitivity_table(rows: list[dict[str, object]], n_frames: int, n_hidden: int):
    """The rows of :func:`sensitivity_study` as a table, with the tolerances of its columns.

    Each error is a mean over one video's ``n_frames`` frames (or its ``n_hidden`` hidden
    ones) after a Viterbi decoding: a flipped decision re-routes a short stretch of the path
    through neighbouring centroids, three frames each off by up to the row's :func:`path_step`,
    so a row may move by ``3 step / n`` (:func:`projtrack.tolerance.mean_over`). The column's
    tolerance covers every row's allowance (:func:`covering_tolerance`). The path steps come
    from EM and k-means: numerical. ``rows`` must not be empty and the counts must be ints
    >= 1 (ValueError otherwise).
    """
    import pandas as pd

    if not rows:
        raise ValueError("rows must not be empty")
    n_frames = as_count(n_frames, "n_frames")
    n_hidden = as_count(n_hidden, "n_hidden")
    table = pd.DataFrame(rows)
    step = table["path step [px]"].to_numpy(dtype=float)
    tol: dict[str, Tolerance] = {}
    for col, n in (("viterbi error [px]", n_frames), ("viterbi error, hidden [px]", n_hidden)):
        tol[col] = covering_tolerance(3 * step / n, table[col].to_numpy(dtype=float),
                                      f"a mean over {n} frames: a flipped Viterbi decision moves three frames by up "
                                      "to the model's path step, 3 x step / n in each row, covered row by row")
    tol["path step [px]"] = numerical(rtol=1e-6, why="distances between k-means centroids, which converge to 1e-8 "
                                                     "far from ties")
    return table, tol

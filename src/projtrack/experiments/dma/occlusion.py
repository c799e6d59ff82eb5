"""Example 3 of Marques et al. (2002): how long the bridge hides the car.

The paper's video is not published and its occlusion length is not given. The synthetic
video hides the car under a deck ``bridge_width`` px wide; :func:`bridge_width_study`
repeats the Fig. 9 study and the trackers without the manifold (DMA-S4) at other widths,
and :func:`bridge_width_tables` tabulates the hidden-frame errors and the share of the test
videos that stay within the Fig. 9 limit. :func:`fit_seed_study` refits the model with other
seeds (the EM regions and the prototypes move), to show how much one fit decides.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_real
from projtrack.experiments.dma.slotcar import (
    MapFree,
    detector_threshold,
    fit_grid_hmm,
    fit_slotcar,
    longest_gap,
    path_step,
    tracking_study,
    training_background,
)
from projtrack.scenes.slotcar import make_slotcar_video
from projtrack.tolerance import EXACT, Tolerance, mean_over, share, statistical

__all__ = ["bridge_width_study", "hidden_stretch", "bridge_width_tables", "fit_seed_study"]


def bridge_width_study(widths: tuple[float, ...], conditions: dict, n_videos: int, *, train_seeds=(31, 32, 33),
                       model_seed: int = 34, test_seed: int = 30, spreads: dict | None = None, n_train: int = 300,
                       n_frames: int = 593) -> dict:
    """The Fig. 9 and no-manifold study of one condition repeated for other bridge widths.

    Parameters
    ----------
    widths : tuple of float
        Bridge deck widths (px) of :func:`projtrack.scenes.slotcar.make_slotcar_video`; a wider
        deck hides the car for longer.
    conditions : dict
        Condition -> ``(video options, annotation std)``, as on the Example 3 page.
    n_videos : int
        Test videos per width and condition (>= 1), from the children of ``test_seed``.
    train_seeds, model_seed, test_seed : int
        The seeds of the training runs, of the fits and of the test videos (those of the page,
        so the page's own width gives the page's own runs).
    spreads : dict, optional
        Label -> random-walk width of extra :class:`~projtrack.experiments.dma.GridHMM` variants (:func:`~projtrack.experiments.dma.fit_grid_hmm`).
    n_train, n_frames : int
        Frames of each training run and of each test video (the page's 300 and 593).

    Returns
    -------
    dict
        ``(width, condition)`` -> ``(trials, (model, sensor), map_free)``: the trials of
        :func:`~projtrack.experiments.dma.tracking_study` (run with ``map_free``), for :func:`bridge_width_rows`.
    """
    out = {}
    for w in widths:
        w = as_real(w, "widths[i]", 0, low_open=True)
        for k, (opts, ann) in conditions.items():
            train, bg = _training_runs(w, opts, train_seeds, n_train)
            fitted = fit_slotcar(train, np.random.default_rng(model_seed), annotation_std=ann, background=bg)
            variants = {label: fit_grid_hmm(train, np.random.default_rng(model_seed), annotation_std=ann,
                                            background=bg, spread=s) for label, s in (spreads or {}).items()}
            mf = MapFree(detector_threshold(train, bg), 5,
                         fit_grid_hmm(train, np.random.default_rng(model_seed), annotation_std=ann, background=bg),
                         variants)
            trials = tracking_study(*fitted, bg, n_videos, np.random.default_rng(test_seed), map_free=mf,
                                    n_frames=n_frames, bridge_width=w, **opts)
            out[w, k] = (trials, fitted, mf)
    return out



def _training_runs(width: float, opts: dict, train_seeds, n_train: int) -> tuple[list, np.ndarray]:
    """The training videos of one bridge width and condition, and their background image."""
    train = [make_slotcar_video(n_train, np.random.default_rng(s), bridge_width=width, **opts) for s in train_seeds]
    return train, training_background(train)


def hidden_stretch(occluded: np.ndarray) -> int:
    """The longest run of consecutive hidden frames (``True``) of one video."""
    return longest_gap(~np.asarray(occluded, dtype=bool))


def bridge_width_tables(study: dict, limit: float = 3.0, frame_shape: tuple[int, int] = (48, 64)):
    """The hidden-frame errors of :func:`bridge_width_study` and the share of videos that pass.

    Parameters
    ----------
    study : dict
        ``(width, condition)`` -> ``(trials, (model, sensor), map_free)``, as
        :func:`bridge_width_study` returns (the trials run with ``map_free=``).
    limit : float
        The error (px) a video's hidden-frame mean must stay below to pass.
    frame_shape : (int, int)
        Frame size, whose diagonal bounds how far one flipped detection moves an estimate.

    Returns
    -------
    tables : dict of str to pandas.DataFrame
        ``"errors"``: per width and condition, ``bridge [px]``, ``condition``,
        ``longest hidden stretch`` (frames, mean over the videos) and the mean error [px] over
        every hidden frame of ``DMA``, ``interpolation`` (:func:`~projtrack.experiments.dma.detect_and_interpolate`) and
        ``grid HMM`` (:class:`~projtrack.experiments.dma.GridHMM`). ``"passing"``: the same keys and, for these, DMA's
        per-instant forward-backward estimate (``DMA smoother``) and the ``per-frame`` detector, the share of the videos whose own hidden-frame mean is below
        ``limit`` (the book's reading of a single shown run: a share of the draws).
        ``"walk"``: for the grid variants of the trials (``grid <label>``), their mean error
        and their share of passing videos (empty if there are none).
    tolerances : dict of str to dict
        The column tolerances of each table. Errors: a mean over at least the smallest
        hidden-frame count, three frames off by up to the longest model step for DMA and the
        grid HMMs, ``1 + longest gap`` frames off by up to the frame diagonal for the detector
        (as in :func:`~projtrack.experiments.dma.map_free_table`). Shares: one video flipping. The stretch: a car position
        rounded on a pixel edge moves one video's stretch by one frame.
    """
    import pandas as pd

    if not isinstance(study, dict) or not study:
        raise ValueError("study must be a non-empty dict of (width, condition) -> (trials, fitted, map_free)")
    limit = as_real(limit, "limit", 0, low_open=True)
    rows: dict[str, list] = {"errors": [], "passing": [], "walk": []}
    counts, steps, grid_steps, gaps, n_videos = [], [], [], [], []
    for (w, k), (trials, (model, _), mf) in study.items():
        if not trials or any("grid" not in t for t in trials):
            raise ValueError(f"the trials of {(w, k)!r} were run without map_free=")
        occ = [np.asarray(t["occluded"], dtype=bool) for t in trials]
        if not all(o.any() for o in occ):
            raise ValueError(f"every video of {(w, k)!r} must have hidden frames")

        def pooled(key):
            return float(np.concatenate([t[key][o] for t, o in zip(trials, occ)]).mean())

        def passing(key):
            return float(np.mean([t[key][o].mean() < limit for t, o in zip(trials, occ)]))

        key = {"bridge [px]": float(w), "condition": k}
        rows["errors"].append({**key, "longest hidden stretch": float(np.mean([hidden_stretch(o) for o in occ])),
                               "DMA": pooled("viterbi"), "interpolation": pooled("detector"),
                               "grid HMM": pooled("grid")})
        rows["passing"].append({**key, "DMA": passing("viterbi"), "DMA smoother": passing("smooth"),
                                "per-frame": passing("per-frame"),
                                "interpolation": passing("detector"), "grid HMM": passing("grid")})
        for label in sorted(mf.variants):
            rows["walk"].append({**key, "walk width": label, "grid HMM [px]": pooled(f"grid {label}"),
                                 f"videos < {limit:g} px": passing(f"grid {label}")})
        counts.append(int(sum(int(o.sum()) for o in occ)))
        steps.append(path_step(model))
        grid_steps.extend([mf.grid.max_step, *(g.max_step for g in mf.variants.values())])
        gaps.append(max(int(t["gap"]) for t in trials))
        n_videos.append(len(trials))
    n, diag = min(counts), float(np.hypot(*frame_shape))
    grid_tol = mean_over(n, round(max(grid_steps), 1), flips=3, what="frame")
    tol: dict[str, dict[str, Tolerance]] = {
        "errors": {"bridge [px]": EXACT, "DMA": mean_over(n, round(max(steps), 1), flips=3, what="frame"),
                   "longest hidden stretch": statistical(atol=1.0 / min(n_videos), why="a mean over the videos: "
                                                         "a car position rounded on a pixel edge moves one video's "
                                                         "stretch by one frame"),
                   "interpolation": mean_over(n, round(diag, 1), flips=1 + max(gaps), what="frame"),
                   "grid HMM": grid_tol},
        "passing": {"bridge [px]": EXACT, "*": share(min(n_videos))},
        "walk": {"bridge [px]": EXACT, "grid HMM [px]": grid_tol, "*": share(min(n_videos))},
    }
    return {name: pd.DataFrame(r) for name, r in rows.items()}, tol


def fit_seed_study(widths: tuple[float, ...], conditions: dict, model_seeds: tuple[int, ...], n_videos: int, *,
                   train_seeds=(31, 32, 33), test_seed: int = 30, n_train: int = 300, n_frames: int = 593,
                   limit: float = 3.0):
    """The share of test videos DMA keeps within ``limit`` under the bridge, per model fit.

    The training runs and the test videos are those of :func:`bridge_width_study` (same seeds);
    only the seed of the fit (EM regions, local PCA, k-means prototypes) changes, so the spread
    over ``model_seeds`` is the part of a result that one fit decides.

    Parameters
    ----------
    widths : tuple of float
        Bridge deck widths (px), each > 0.
    conditions : dict
        Condition -> ``(video options, annotation std)``, as on the Example 3 page.
    model_seeds : tuple of int
        Seeds of :func:`~projtrack.experiments.dma.fit_slotcar` (at least one).
    n_videos : int
        Test videos per width and condition (>= 1).
    train_seeds, test_seed, n_train, n_frames
        As in :func:`bridge_width_study`.
    limit : float
        The error (px) a video's hidden-frame mean must stay below to pass (> 0).

    Returns
    -------
    table : pandas.DataFrame
        ``bridge [px]``, ``condition``, ``model seed`` and the shares of passing videos for the
        Viterbi path (``DMA``) and the per-instant forward-backward estimate (``DMA smoother``).
    tolerance : dict
        Column tolerances (a share moves by one video).
    """
    import pandas as pd

    if not isinstance(conditions, dict) or not conditions:
        raise ValueError("conditions must be a non-empty dict of condition -> (video options, annotation std)")
    seeds = [int(s) for s in model_seeds]
    if not seeds:
        raise ValueError("model_seeds must hold at least one seed")
    limit = as_real(limit, "limit", 0, low_open=True)
    rows = []
    for w in widths:
        w = as_real(w, "widths[i]", 0, low_open=True)
        for k, (opts, ann) in conditions.items():
            train, bg = _training_runs(w, opts, train_seeds, n_train)
            for seed in seeds:
                fitted = fit_slotcar(train, np.random.default_rng(seed), annotation_std=ann, background=bg)
                trials = tracking_study(*fitted, bg, n_videos, np.random.default_rng(test_seed), n_frames=n_frames,
                                        bridge_width=w, **opts)
                occ = [np.asarray(t["occluded"], dtype=bool) for t in trials]
                if not all(o.any() for o in occ):
                    raise ValueError(f"every video of {(w, k)!r} must have hidden frames")
                rows.append({"bridge [px]": w, "condition": k, "model seed": seed,
                             **{label: float(np.mean([t[key][o].mean() < limit for t, o in zip(trials, occ)]))
                                for label, key in (("DMA", "viterbi"), ("DMA smoother", "smooth"))}})
    return pd.DataFrame(rows), {"bridge [px]": EXACT, "*": share(n_videos)}

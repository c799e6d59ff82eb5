"""Tracks scored with the field's own metrics: CLEAR MOT and identity scores through ``motmetrics``.

Multi-object tracking is compared with the CLEAR MOT metrics (Bernardin & Stiefelhagen
2008: MOTA, MOTP, identity switches, false positives, misses) and the identity F1 score
(IDF1, Ristani et al. 2016). ``motmetrics`` computes them from per-frame distance
matrices between the annotated objects and a tracker's hypotheses
(:class:`motmetrics.MOTAccumulator`); this module builds those matrices:

* :func:`score_points` scores tracks that are points (box centres) against annotated
  boxes. A hypothesis point may match a box when a box of the same size centred on the
  point overlaps it with an intersection over union of at least ``min_overlap``
  (0.5, the MOTChallenge rule for boxes); the distance is one minus that overlap, so
  MOTP is the mean ``1 - IoU`` of the matches, lower is better, as ``motmetrics``
  reports it for boxes. The overlaps are computed here (:func:`box_iou`):
  ``motmetrics``' own IoU helper calls ``np.asfarray``, which numpy 2 removed.
* :func:`score_arrays` scores state arrays ``(n_steps, n_targets, 4)`` against the true
  states (the synthetic crossing scenes of the chapter) with the Euclidean distance and a
  match radius: the same counts as :func:`projtrack.experiments.jpda.score_tracks`
  asks for by hand (tracks lost or swapped), here as misses and identity switches over
  every step.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from projtrack._validation import as_array, as_real

__all__ = ["MOT_METRICS", "box_iou", "centred_overlap", "mot_summary", "score_points", "score_arrays",
           "crossing_mot_trial", "crossing_mot_table"]

#: The ``motmetrics`` metrics reported, in this order (``mh.compute(..., metrics=...)``).
MOT_METRICS: tuple[str, ...] = ("mota", "motp", "idf1", "num_switches", "num_false_positives",
                                "num_misses", "num_objects", "num_matches")


def _motmetrics():
    try:
        import motmetrics
    except ModuleNotFoundError as exc:
        raise ImportError(f"scoring with the CLEAR MOT metrics needs the 'motmetrics' package ({exc}); "
                          "install it with 'pip install motmetrics'") from None
    return motmetrics


def box_iou(a: object, b: object) -> np.ndarray:
    """Intersection over union of every box of ``a`` with every box of ``b``.

    Boxes are rows ``(left, top, width, height)`` with positive width and height.

    Returns
    -------
    ndarray, shape (len(a), len(b))
    """
    a = as_array(a, "a", ndim=2).reshape(-1, 4)
    b = as_array(b, "b", ndim=2).reshape(-1, 4)
    if np.any(a[:, 2:] <= 0) or np.any(b[:, 2:] <= 0):
        raise ValueError("box widths and heights must be > 0")
    lo = np.maximum(a[:, None, :2], b[None, :, :2])
    hi = np.minimum(a[:, None, :2] + a[:, None, 2:], b[None, :, :2] + b[None, :, 2:])
    inter = np.prod(np.clip(hi - lo, 0.0, None), axis=-1)
    area_a = a[:, 2] * a[:, 3]
    area_b = b[:, 2] * b[:, 3]
    return inter / (area_a[:, None] + area_b[None, :] - inter)


def centred_overlap(boxes: object, points: object) -> np.ndarray:
    """IoU of each box with a copy of itself centred on each point, shape ``(n_boxes, n_points)``.

    For a box of width ``w`` and height ``h`` and a point offset by ``(dx, dy)`` from its
    centre this is ``a / (2 w h - a)`` with ``a = (w - |dx|)+ (h - |dy|)+``; it is 0.5
    when ``a = 2 w h / 3``, e.g. ``|dx| = w / 3`` with ``dy = 0``.
    """
    boxes = as_array(boxes, "boxes", ndim=2).reshape(-1, 4)
    points = as_array(points, "points", ndim=2).reshape(-1, 2)
    if np.any(boxes[:, 2:] <= 0):
        raise ValueError("box widths and heights must be > 0")
    wh = boxes[:, None, 2:]
    off = np.abs(points[None, :, :] - (boxes[:, None, :2] + wh / 2))
    a = np.prod(np.clip(wh - off, 0.0, None), axis=-1)
    full = boxes[:, 2] * boxes[:, 3]
    return a / (2 * full[:, None] - a)


def mot_summary(frames: Iterable[tuple[Sequence[int], Sequence[int], np.ndarray]]) -> dict:
    """CLEAR MOT and identity scores of per-frame ``(object_ids, hypothesis_ids, distances)``.

    ``distances`` has shape ``(n_objects, n_hypotheses)`` with NaN where a pair may not be
    matched. Returns the ``MOT_METRICS`` as a dict (``mota``, ``motp``, ``idf1`` as
    floats; ``motp`` is NaN when nothing matched; the counts as ints).
    """
    mm = _motmetrics()
    acc = mm.MOTAccumulator(auto_id=True)
    for oids, hids, dist in frames:
        dist = np.asarray(dist, float).reshape(len(oids), len(hids))
        acc.update(list(oids), list(hids), dist)
    out = mm.metrics.create().compute(acc, metrics=list(MOT_METRICS), name="run")
    row = out.loc["run"]
    return {k: (float(row[k]) if k in ("mota", "motp", "idf1") else int(row[k])) for k in MOT_METRICS}


def score_points(gt, frame: object, ident: object, points: object, *, min_overlap: float = 0.5) -> dict:
    """Score point tracks against the annotated boxes of a sequence (:func:`mot_summary`).

    Parameters
    ----------
    gt : MOTBoxes
        The ground truth, a ``projtrack.datasets.MOTBoxes`` (every frame ``1..gt.n_frames``
        is scored, also frames without an annotated person or without a hypothesis).
    frame, ident : array_like of int, shape (n,)
        Frame (1-based) and track identity of each reported point.
    points : array_like, shape (n, 2)
        The tracks' positions (box centres).
    min_overlap : float
        Smallest :func:`centred_overlap` of a match (0.5, the MOTChallenge IoU rule).

    Returns
    -------
    dict
        ``MOT_METRICS``; MOTP is the mean ``1 - overlap`` of the matches.
    """
    frame = as_array(frame, "frame", ndim=1, dtype=np.int64)
    ident = as_array(ident, "ident", ndim=1, dtype=np.int64)
    points = as_array(points, "points", ndim=2).reshape(-1, 2)
    if not (len(frame) == len(ident) == len(points)):
        raise ValueError(f"frame, ident and points must have the same length, got {len(frame)}, "
                         f"{len(ident)} and {len(points)}")
    min_overlap = as_real(min_overlap, "min_overlap", 0.0, 1.0, low_open=True)

    def frames():
        for k in range(1, gt.n_frames + 1):
            gi, hi = gt.in_frame(k), np.flatnonzero(frame == k)
            ov = centred_overlap(gt.box[gi], points[hi])
            yield gt.ident[gi], ident[hi], np.where(ov >= min_overlap, 1.0 - ov, np.nan)

    return mot_summary(frames())


def _array_frames(estimates: object, truth: object, max_distance: float, first_id: int = 0) -> list:
    est = as_array(estimates, "estimates", ndim=3)[..., [0, 2]]
    tru = as_array(truth, "truth", ndim=3)[..., [0, 2]]
    if est.shape != tru.shape:
        raise ValueError(f"estimates and truth must have the same shape, got {est.shape} and {tru.shape}")
    max_distance = as_real(max_distance, "max_distance", 0.0, low_open=True)
    ids = first_id + np.arange(est.shape[1])
    frames = []
    for e, t in zip(est, tru):
        d = np.linalg.norm(t[:, None, :] - e[None, :, :], axis=-1)
        frames.append((ids, ids, np.where(d <= max_distance, d, np.nan)))
    return frames


def score_arrays(estimates: object, truth: object, max_distance: float) -> dict:
    """Score fixed tracks ``(n_steps, n_targets, 4)`` against true states of the same shape.

    State ``(x, vx, y, vy)``; track ``t`` is hypothesis ``t`` and target ``t`` object ``t``.
    A pair may match when its position distance is at most ``max_distance``; the
    distance reported (MOTP) is the Euclidean position error of the matches.
    """
    return mot_summary(_array_frames(estimates, truth, max_distance))


def crossing_mot_trial(rng: np.random.Generator, lost_distance: float = 3.0, **scene_kw) -> dict:
    """One crossing scene of :func:`projtrack.experiments.jpda.tracking_trial`, kept for scoring.

    The scene (:func:`projtrack.scenes.jpda.crossing_targets`) and the trackers
    (:func:`projtrack.experiments.jpda.run_trackers`) are those of the chapter's crossing
    study. Returns ``truth`` (steps 1..n) and, per tracker, its ``estimates`` with
    :func:`projtrack.experiments.jpda.score_tracks`' counts at the last scan.
    """
    from projtrack.scenes.jpda import crossing_targets

    from .tracking import run_trackers, score_tracks

    sc = crossing_targets(rng, **scene_kw)
    est = dict(zip(("jpda", "gnn"), run_trackers(sc, p_detect=scene_kw.get("p_detect", 0.9))))
    out: dict = {"truth": sc.truth[1:]}
    for k, e in est.items():
        out[k] = {"estimates": e, **score_tracks(e, sc.truth[1:], lost_distance)}
    return out


def crossing_mot_table(results: Sequence[dict], max_distance: float = 3.0) -> tuple:
    """Table of :func:`crossing_mot_trial` results (one row per tracker) and its tolerances.

    The runs of each tracker are scored with ``motmetrics`` as one sequence, their targets
    and tracks kept apart (a match within ``max_distance``): MOTA and IDF1 over all runs, ID
    switches per run; beside them the share of tracks swapped or lost at the last scan (the
    chapter's own count, :func:`projtrack.experiments.jpda.score_tracks`). One flipped
    decision (one step of one track) moves MOTA and IDF1 by at most ``3 / boxes`` and the
    counts by one.
    """
    import pandas as pd

    from projtrack.tolerance import statistical

    if not results:
        raise ValueError("results must hold at least one trial")
    n = len(results)
    n_targets = results[0]["truth"].shape[1]
    rows, boxes = [], 0
    for key, name in (("jpda", "JPDA (book)"), ("gnn", "GNN (book)")):
        frames = [f for i, r in enumerate(results)
                  for f in _array_frames(r[key]["estimates"], r["truth"], max_distance, i * n_targets)]
        s = mot_summary(frames)
        boxes = s["num_objects"]
        rows.append({"tracker": name, "MOTA": s["mota"], "IDF1": s["idf1"], "ID switches per run": s["num_switches"] / n,
                     "tracks swapped or lost": sum(r[key]["swapped"] + r[key]["lost"] for r in results)
                     / (n * n_targets)})
    why = f"one step of one track flipped in one of {n} runs ({boxes} target-steps in all)"
    tol = {"MOTA": statistical(atol=3 / boxes, why=why), "IDF1": statistical(atol=3 / boxes, why=why),
           "ID switches per run": statistical(atol=1 / n, why=f"one switch more or less in one of {n} runs"),
           "tracks swapped or lost": statistical(atol=1 / n, why=f"one of {n} runs changing outcome")}
    return pd.DataFrame(rows), tol

"""The chapter's trackers on real pedestrians (TUD-Campus, TUD-Stadtmitte), beside Stone Soup.

Beyond the paper, which runs no tracker: the book's JPDA tracker (exact beta), its GNN
tracker and Stone Soup's JPDA with EHM track the people of the two real sequences that
``motmetrics`` ships (``projtrack.datasets``), inside one track management
(:func:`projtrack.experiments.jpda.track_sequence`), and are scored with ``motmetrics``
(:func:`projtrack.experiments.jpda.score_points`). Two detection sources:

* ``"gt"``: the annotated box centres, each kept with probability ``p_detect``, moved by
  Gaussian noise of ``noise_std`` pixels per axis, plus a Poisson number of false
  detections (mean ``false_per_frame``) uniform over the image
  (:func:`synthetic_detections`);
* ``"test"``: the box centres of the shipped ``test.txt`` (a real tracker's output) with
  their identities removed, sorted by position (:func:`shipped_detections`).

Every parameter comes from the data's own statistics, never from the scores:

* the motion model (:func:`motion_statistics`): constant velocity with white
  acceleration of density ``q`` per axis, and white annotation jitter of variance ``s``,
  both from the second differences of the annotated centres: for that model their
  variance is ``2 q / 3 + 6 s`` and their lag-1 covariance ``q / 6 - 4 s`` (method of
  moments); new tracks get the velocity variance of the annotated tracks;
* the detections' noise, detection probability and false-detection rate: the chosen
  values for ``"gt"``; for ``"test"``, measured against the annotations
  (:func:`detector_statistics`: a test box detects the person whose box it overlaps
  best, one to one, with IoU >= 0.5); ``R`` adds the jitter ``s`` to the detections'
  covariance about the annotated centres;
* the clutter density is the false-detection rate over the image area; the gate
  probability is 0.99 (its size in pixels follows from ``S``); a confirmed track is
  deleted after the fewest scans ``k`` with ``(1 - P_D)^k <= 0.01``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from projtrack import montecarlo
from projtrack._validation import as_int, as_probability, as_real, as_rng
from projtrack.datasets import MOTBoxes, load_mot_sequence
from projtrack.tolerance import statistical

from .motscore import box_iou, score_points
from .pedtracking import PedestrianModel, TrackRun, track_sequence

__all__ = ["SETTINGS", "TRACKER_NAMES", "motion_statistics", "detector_statistics", "cv_matrices",
           "pedestrian_model", "gt_model", "shipped_model", "synthetic_detections", "shipped_detections",
           "run_difference", "run_trackers_on", "pedestrian_trial", "shipped_trial", "pedestrian_study",
           "pedestrian_table", "pedestrian_tolerances", "draw_spread_tolerances", "paired_mota_table"]

#: Detection settings of the ``"gt"`` source, stated before any run: detection probability,
#: noise standard deviation per axis (pixels), mean false detections per frame.
SETTINGS: dict[str, dict[str, float]] = {
    "base": dict(p_detect=0.9, noise_std=3.0, false_per_frame=2.0),
    "more misses": dict(p_detect=0.7, noise_std=3.0, false_per_frame=2.0),
    "more noise": dict(p_detect=0.9, noise_std=8.0, false_per_frame=2.0),
    "more clutter": dict(p_detect=0.9, noise_std=3.0, false_per_frame=30.0),
}

GATE_PROB = 0.99
MIN_OVERLAP = 0.5
CONFIRM_AFTER = 3


def _tracks(gt: MOTBoxes):
    for i in gt.identities:
        idx = np.flatnonzero(gt.ident == i)
        yield gt.frame[idx], gt.centres[idx]


def motion_statistics(gt: MOTBoxes) -> dict:
    """Motion statistics of the annotated centres, per axis ``(x, y)``.

    Returns a dict with ``q`` (white-acceleration density, px^2/frame^3), ``jitter``
    (annotation noise variance ``s``, px^2), ``velocity_var`` (variance of the one-frame
    displacements, px^2/frame^2) and ``n`` (number of second differences used). ``q`` and
    ``s`` solve ``var(d2) = 2 q / 3 + 6 s`` and ``cov(d2_k, d2_k+1) = q / 6 - 4 s`` for the
    second differences ``d2`` of runs of consecutive frames (a negative solution is set
    to 1 % of ``var(d2)``, and stated by ``clipped``).
    """
    if not isinstance(gt, MOTBoxes) or gt.source != "gt":
        raise TypeError("gt must be the MOTBoxes of an annotated sequence (source 'gt')")
    d1, d2, lag = [], [], []
    for f, c in _tracks(gt):
        if len(f) < 2 or np.any(np.diff(f) != 1):
            raise ValueError(f"{gt.name}: the annotated tracks must cover consecutive frames")
        d1.append(np.diff(c, axis=0))
        if len(f) >= 3:
            dd = np.diff(c, 2, axis=0)
            d2.append(dd)
            if len(dd) >= 2:
                lag.append(dd[:-1] * dd[1:])
    d1, d2, lag = np.vstack(d1), np.vstack(d2), np.vstack(lag)
    mean = d2.mean(axis=0)
    v = d2.var(axis=0)
    c = lag.mean(axis=0) - mean ** 2
    # [[2/3, 6], [1/6, -4]] @ [q, s] = [v, c]
    A = np.array([[2 / 3, 6.0], [1 / 6, -4.0]])
    qs = np.linalg.solve(A, np.vstack([v, c]))
    q, s = qs[0], qs[1]
    clipped = (q <= 0) | (s <= 0)
    q = np.where(q > 0, q, 0.01 * v)
    s = np.where(s > 0, s, 0.01 * v)
    return {"q": q, "jitter": s, "velocity_var": d1.var(axis=0), "n": len(d2), "clipped": clipped}


def detector_statistics(gt: MOTBoxes, det: MOTBoxes, min_overlap: float = MIN_OVERLAP) -> dict:
    """How a detection source compares with the annotations, frame by frame.

    Detections and annotated boxes are matched one to one by the Hungarian method on IoU,
    a match needing ``IoU >= min_overlap``. Returns ``p_detect`` (share of annotated boxes
    matched), ``false_per_frame`` (unmatched detections per frame), ``offset_mean`` and
    ``offset_cov`` (centre of detection minus annotated centre over the matches, px).
    """
    min_overlap = as_real(min_overlap, "min_overlap", 0.0, 1.0, low_open=True)
    offsets, n_false = [], 0
    for k in range(1, gt.n_frames + 1):
        gi, di = gt.in_frame(k), det.in_frame(k)
        if len(di) == 0:
            continue
        ok_pairs = np.zeros(0, int), np.zeros(0, int)
        if len(gi):
            iou = box_iou(gt.box[gi], det.box[di])
            r, c = linear_sum_assignment(-iou)
            ok = iou[r, c] >= min_overlap
            ok_pairs = r[ok], c[ok]
        offsets.append(det.centres[di[ok_pairs[1]]] - gt.centres[gi[ok_pairs[0]]])
        n_false += len(di) - len(ok_pairs[0])
    off = np.vstack(offsets) if offsets else np.zeros((0, 2))
    return {"p_detect": len(off) / len(gt.frame), "false_per_frame": n_false / gt.n_frames,
            "offset_mean": off.mean(axis=0), "offset_cov": np.cov(off.T), "n_matched": len(off)}


def cv_matrices(q: Sequence[float], R: np.ndarray) -> tuple[np.ndarray, ...]:
    """``(F, Q, H)`` of the constant-velocity model in state ``(x, vx, y, vy)``, one frame per step.

    ``Q`` is the continuous white-acceleration model per axis,
    ``q [[1/3, 1/2], [1/2, 1]]`` (Stone Soup's ``ConstantVelocity`` with ``dt = 1``).
    """
    q = np.asarray(q, float)
    F = np.kron(np.eye(2), np.array([[1.0, 1.0], [0.0, 1.0]]))
    Q = np.zeros((4, 4))
    for a in range(2):
        Q[2 * a:2 * a + 2, 2 * a:2 * a + 2] = q[a] * np.array([[1 / 3, 1 / 2], [1 / 2, 1.0]])
    H = np.zeros((2, 4))
    H[0, 0] = H[1, 2] = 1.0
    return F, Q, H


def pedestrian_model(motion: dict, noise_cov: np.ndarray, p_detect: float, false_per_frame: float,
                     image_size: tuple[int, int], gate_prob: float = GATE_PROB) -> PedestrianModel:
    """The tracker model from the data's statistics (see the module docstring).

    ``noise_cov`` is the detections' covariance about the annotated centres (2 x 2); ``R``
    adds the annotation jitter of ``motion``. The clutter density is ``false_per_frame``
    over the image area (at least 0.01 per frame, so it stays positive).
    """
    p_detect = as_probability(p_detect, "p_detect", low_open=True)
    false_per_frame = as_real(false_per_frame, "false_per_frame", 0.0)
    R = np.asarray(noise_cov, float) + np.diag(motion["jitter"])
    F, Q, H = cv_matrices(motion["q"], R)
    P0 = np.diag([R[0, 0], motion["velocity_var"][0], R[1, 1], motion["velocity_var"][1]])
    delete_after = 1 if p_detect >= 1 else max(1, math.ceil(math.log(0.01) / math.log(1 - p_detect)))
    area = float(image_size[0] * image_size[1])
    return PedestrianModel(F=F, Q=Q, H=H, R=R, P0=P0, q=(float(motion["q"][0]), float(motion["q"][1])),
                           p_detect=p_detect, clutter_density=max(false_per_frame, 0.01) / area,
                           gate_prob=gate_prob, confirm_after=CONFIRM_AFTER, delete_after=delete_after,
                           image_size=tuple(image_size))


def synthetic_detections(gt: MOTBoxes, rng: np.random.Generator, p_detect: float, noise_std: float,
                         false_per_frame: float) -> list[np.ndarray]:
    """Detections of every frame from the annotated centres: misses, noise and clutter.

    Each annotated person is detected with probability ``p_detect`` at its centre plus
    ``N(0, noise_std^2)`` per axis; a Poisson number (mean ``false_per_frame``) of false
    detections is uniform over the image. Each frame's detections are shuffled.
    """
    rng = as_rng(rng)
    p_detect = as_probability(p_detect, "p_detect")
    noise_std = as_real(noise_std, "noise_std", 0.0)
    false_per_frame = as_real(false_per_frame, "false_per_frame", 0.0)
    w, h = gt.image_size
    scans = []
    for k in range(1, gt.n_frames + 1):
        c = gt.centres[gt.in_frame(k)]
        c = c[rng.random(len(c)) < p_detect]
        c = c + noise_std * rng.standard_normal(c.shape)
        n_false = rng.poisson(false_per_frame)
        clutter = rng.uniform(0, 1, (n_false, 2)) * np.array([w, h])
        z = np.vstack([c, clutter])
        scans.append(z[rng.permutation(len(z))])
    return scans


def shipped_detections(test: MOTBoxes) -> list[np.ndarray]:
    """The shipped tracker output as a detector's: box centres per frame, identities removed
    (each frame's centres sorted by x, then y)."""
    if not isinstance(test, MOTBoxes) or test.source != "test":
        raise TypeError("test must be the MOTBoxes of a shipped test.txt (source 'test')")
    scans = []
    for k in range(1, test.n_frames + 1):
        c = test.centres[test.in_frame(k)]
        scans.append(c[np.lexsort((c[:, 1], c[:, 0]))])
    return scans


TRACKER_NAMES: dict[str, str] = {"jpda": "JPDA (book)", "gnn": "GNN (book)", "stonesoup": "JPDA-EHM (Stone Soup)"}


def run_difference(a: TrackRun, b: TrackRun) -> float:
    """Largest distance (px) between the reported positions of two runs that report the same
    tracks at the same frames; ``inf`` when they report different tracks."""
    if not (np.array_equal(a.frame, b.frame) and np.array_equal(a.ident, b.ident)):
        return float("inf")
    return float(np.abs(a.point - b.point).max()) if len(a.point) else 0.0


def run_trackers_on(scans: list, model: PedestrianModel, gt: MOTBoxes,
                    trackers: Sequence[str] = ("jpda", "gnn", "stonesoup"), keep_runs: bool = False) -> dict:
    """Track ``scans`` with each tracker and score it (:func:`score_points`).

    Returns ``{tracker: score dict}`` (each with ``tracks_started`` too) and, when both
    ``"jpda"`` and ``"stonesoup"`` ran, ``"jpda_vs_stonesoup"``: :func:`run_difference`
    of their runs. With ``keep_runs``, also ``"runs"``: ``{tracker: TrackRun}``.
    """
    runs = {name: track_sequence(scans, model, name) for name in trackers}
    out: dict = {}
    for name, run in runs.items():
        s = score_points(gt, run.frame, run.ident, run.point, min_overlap=MIN_OVERLAP)
        s["tracks_started"] = run.n_tracks_started
        out[name] = s
    if "jpda" in runs and "stonesoup" in runs:
        out["jpda_vs_stonesoup"] = run_difference(runs["jpda"], runs["stonesoup"])
    if keep_runs:
        out["runs"] = runs
    return out


def gt_model(gt: MOTBoxes, setting: str) -> PedestrianModel:
    """The tracker model for ``"gt"`` detections under ``SETTINGS`` ``[setting]``."""
    st = SETTINGS[setting]
    return pedestrian_model(motion_statistics(gt), st["noise_std"] ** 2 * np.eye(2), st["p_detect"],
                            st["false_per_frame"], gt.image_size)


def shipped_model(gt: MOTBoxes, test: MOTBoxes) -> PedestrianModel:
    """The tracker model for the shipped ``test.txt`` detections (:func:`detector_statistics`)."""
    ds = detector_statistics(gt, test)
    return pedestrian_model(motion_statistics(gt), ds["offset_cov"], ds["p_detect"], ds["false_per_frame"],
                            gt.image_size)


def pedestrian_trial(rng: np.random.Generator, name: str, setting: str,
                     trackers: Sequence[str] = ("jpda", "gnn"), keep_runs: bool = False) -> dict:
    """One draw of ``"gt"`` detections of sequence ``name`` under ``SETTINGS`` ``[setting]``,
    tracked and scored by each tracker (:func:`run_trackers_on`)."""
    if setting not in SETTINGS:
        raise ValueError(f"setting must be one of {', '.join(SETTINGS)}, got {setting!r}")
    gt = load_mot_sequence(name, "gt")
    scans = synthetic_detections(gt, rng, **SETTINGS[setting])
    return run_trackers_on(scans, gt_model(gt, setting), gt, trackers, keep_runs)


def shipped_trial(name: str, trackers: Sequence[str] = ("jpda", "gnn", "stonesoup"),
                  keep_runs: bool = False) -> dict:
    """The shipped ``test.txt`` of sequence ``name`` as detections (no randomness), tracked
    and scored by each tracker (:func:`run_trackers_on`)."""
    gt, test = load_mot_sequence(name, "gt"), load_mot_sequence(name, "test")
    return run_trackers_on(shipped_detections(test), shipped_model(gt, test), gt, trackers, keep_runs)


def pedestrian_study(name: str, setting: str, n_draws: int, seed: int,
                     trackers: Sequence[str] = ("jpda", "gnn")) -> list[dict]:
    """``n_draws`` :func:`pedestrian_trial` results through :func:`projtrack.montecarlo.run`
    (draw ``i`` uses the ``i``-th child of ``default_rng(seed)``)."""
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    if setting not in SETTINGS:
        raise ValueError(f"setting must be one of {', '.join(SETTINGS)}, got {setting!r}")
    return montecarlo.run(pedestrian_trial, n_draws, np.random.default_rng(seed), name, setting,
                          tuple(trackers))


_COLUMNS = {"MOTA": "mota", "MOTP": "motp", "IDF1": "idf1", "ID switches": "num_switches",
            "false positives": "num_false_positives", "misses": "num_misses"}


def pedestrian_table(draws: Sequence[dict], **labels: str) -> pd.DataFrame:
    """One row per tracker: the means over ``draws`` (:func:`pedestrian_trial` or
    :func:`shipped_trial` results) of MOTA, MOTP, IDF1, ID switches, false positives and
    misses; ``labels`` become leading columns (e.g. ``sequence=..., detections=...``)."""
    if not draws:
        raise ValueError("draws must hold at least one result")
    rows = []
    for tr, name in TRACKER_NAMES.items():
        if tr not in draws[0]:
            continue
        row = dict(labels)
        row["tracker"] = name
        for col, key in _COLUMNS.items():
            row[col] = float(np.mean([d[tr][key] for d in draws]))
        rows.append(row)
    return pd.DataFrame(rows)


def pedestrian_tolerances(n_draws: int, n_objects: int) -> dict:
    """Tolerances of :func:`pedestrian_table` columns: one box's outcome flipped in one draw.

    A flipped decision (a gate, an assignment, a track confirmed or deleted one scan
    earlier or later, a match at the overlap threshold) changes, in one draw, at least one
    annotated box from matched to missed (and its hypothesis to a false positive) or adds
    one identity switch: MOTA moves by ``2 / n_objects``, IDF1 by at most
    ``3 / n_objects`` (its true positives and hypotheses by one each), MOTP (a mean of
    ``1 - IoU`` below 0.5 over at least ``n_objects / 2`` matches) by ``1 / n_objects``,
    and each count by 1; a mean over ``n_draws`` draws moves by that over ``n_draws``.
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    n_objects = as_int(n_objects, "n_objects", minimum=1)
    what = (f"one box's outcome flipped in a run over {n_objects} annotated boxes" if n_draws == 1 else
            f"one box's outcome flipped in one of {n_draws} draws of {n_objects} annotated boxes")
    per = {"MOTA": 2 / n_objects, "IDF1": 3 / n_objects, "MOTP": 1 / n_objects,
           "ID switches": 1.0, "false positives": 1.0, "misses": 1.0}
    return {col: statistical(atol=v / n_draws, why=f"{what}: {col} moves by {v:.3g} in that run")
            for col, v in per.items()}


def _up_one_digit(x: float) -> float:
    """``x > 0`` rounded up to one significant digit (``0.061 -> 0.07``): a tolerance computed
    from the data stays put unless one draw's change moves it across a digit."""
    e = 10.0 ** math.floor(math.log10(x))
    return float(f"{math.ceil(round(x / e, 9)) * e:.1g}")


def draw_spread_tolerances(groups: Sequence[Sequence[dict]], one_run: dict | None = None) -> dict:
    """Tolerances of means over draws of :func:`pedestrian_table` columns: one draw's run changed.

    A flipped decision (a gate, a track confirmed one scan later) can change the rest of a
    draw's run, so the draw's value may move by as much as draws differ from one another:
    four standard deviations over the draws (the largest over the ``groups``, each a list of
    :func:`pedestrian_trial` results of one setting and sequence, and over the trackers),
    rounded up to one digit. A mean over ``n`` draws moves by that over ``n`` (about one
    standard error, ``sd / sqrt(n)``, for ``n`` near 16). ``one_run`` (:func:`pedestrian_tolerances` of a single deterministic
    run in the same table) raises a column's tolerance to at least its own.

    Also returns, under ``"MOTA JPDA - GNN"`` and ``"standard error (draws)"`` and
    ``"GNN better (share of draws)"``, the tolerances of :func:`paired_mota_table`.
    """
    if not groups or any(len(g) < 2 for g in groups):
        raise ValueError("groups must hold lists of at least two draws each")
    n = min(len(g) for g in groups)
    trackers = [t for t in TRACKER_NAMES if all(t in g[0] for g in groups)]
    out = {}
    for col, key in _COLUMNS.items():
        sd = max(float(np.std([d[t][key] for d in g], ddof=1)) for g in groups for t in trackers)
        per = _up_one_digit(max(4 * sd, 1e-9))
        atol, why = per / n, (f"a flipped decision can change the rest of one draw's run, by up to 4 sd over "
                              f"the draws ({per:g} in {col}); the mean over {n} draws moves by {per:g}/{n}")
        if one_run is not None and one_run[col].atol > atol:
            atol = one_run[col].atol
            why += f"; the single test.txt run by one box's outcome, {atol:.3g}"
        out[col] = statistical(atol=atol, why=why)
        if col == "MOTA":
            out["MOTA JPDA - GNN"] = statistical(atol=per / n, why=(
                f"one draw's run of either tracker changed moves the paired difference of that draw by up to "
                f"{per:g} (4 sd of MOTA over the draws), the mean over {n} draws by {per:g}/{n}"))
            out["standard error (draws)"] = statistical(atol=per / math.sqrt(n * (n - 1)), why=(
                f"one of {n} values changing by {per:g} moves a standard deviation by at most {per:g}/sqrt({n - 1}), "
                f"the standard error by {per:g}/sqrt({n} x {n - 1})"))
    out["GNN better (share of draws)"] = statistical(atol=1 / n, why=f"one of {n} draws changing sides moves "
                                                                     f"the share by 1/{n}")
    return out


def paired_mota_table(studies: dict) -> pd.DataFrame:
    """MOTA of the book's JPDA minus GNN's, draw by draw (both track the same detections).

    ``studies`` maps ``(setting, sequence)`` to a list of :func:`pedestrian_trial` results.
    One row per key: ``setting``, ``sequence``, ``MOTA JPDA - GNN`` (mean of the paired
    differences), ``standard error (draws)`` (their standard deviation over ``sqrt(n)``) and
    ``GNN better (share of draws)``.
    """
    rows = []
    for (setting, name), draws in studies.items():
        if len(draws) < 2:
            raise ValueError("each study needs at least two draws (a standard error needs two)")
        d = np.array([r["jpda"]["mota"] - r["gnn"]["mota"] for r in draws])
        rows.append({"setting": setting, "sequence": name, "MOTA JPDA - GNN": float(d.mean()),
                     "standard error (draws)": float(d.std(ddof=1) / math.sqrt(len(d))),
                     "GNN better (share of draws)": float((d < 0).mean())})
    return pd.DataFrame(rows)

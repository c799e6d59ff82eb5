"""Crossing-target tracking study of the JPDA chapter: JPDA against GNN on the same scenes.

A trial draws one :func:`projtrack.scenes.jpda.crossing_targets` scene, tracks it with
:class:`projtrack.jpda.JPDATracker` and :class:`projtrack.jpda.GNNTracker` started on the
true initial states, and scores both against the ground truth (:func:`score_tracks`).
:func:`tracking_study` runs the trials through :func:`projtrack.montecarlo.run` and
:func:`tracking_summary` tabulates them with their tolerances; :func:`tracking_sampling` gives
the sampling error of the share of tracks swapped or lost.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.jpda import GNNTracker, JPDATracker
from projtrack.scenes.jpda import CrossingScene, crossing_targets
from projtrack.tolerance import Tolerance, mean_over, statistical

__all__ = ["score_tracks", "run_trackers", "tracking_trial", "tracking_study", "tracking_summary",
           "tracking_sampling"]


def score_tracks(estimates: np.ndarray, truth: np.ndarray, lost_distance: float = 3.0) -> dict:
    """Position RMSE, swaps and losses of tracks started on their own targets.

    ``estimates`` and ``truth`` have shape ``(n_steps, n_targets, 4)`` (state
    ``(x, vx, y, vy)``). At the last step a track is *lost* when no true target is
    within ``lost_distance``, and *swapped* when the nearest true target is not its
    own. ``rmse`` is the root mean square position error of every track against its
    own target over all steps; ``tracks`` is the number of tracks.
    """
    est = as_array(estimates, "estimates", ndim=3)[..., [0, 2]]
    tru = as_array(truth, "truth", ndim=3)[..., [0, 2]]
    lost_distance = as_real(lost_distance, "lost_distance", 0.0, low_open=True)
    if est.shape != tru.shape:
        raise ValueError(f"estimates and truth must have the same shape, got {est.shape} and "
                         f"{tru.shape}")
    rmse = float(np.sqrt(np.mean(np.sum((est - tru) ** 2, axis=-1))))
    d = np.linalg.norm(est[-1][:, None, :] - tru[-1][None, :, :], axis=-1)
    nearest = d.argmin(axis=1)
    lost = d.min(axis=1) > lost_distance
    swapped = (~lost) & (nearest != np.arange(len(nearest)))
    return {"rmse": rmse, "swapped": int(swapped.sum()), "lost": int(lost.sum()), "tracks": len(nearest)}


def run_trackers(scene: CrossingScene, p_detect: float = 0.9) -> tuple[np.ndarray, np.ndarray]:
    """Track one scene with JPDA and with GNN; returns their state estimates.

    Both trackers start from the true initial states with covariance ``0.5 I`` (track
    initiation is chapter 3's job) and use the simulation model; JPDA uses ``p_detect``
    and the scene's clutter density, both use a 0.99 gate.

    Returns
    -------
    (est_jpda, est_gnn) : ndarray, each of shape ``(n_steps, n_targets, 4)``
    """
    if not isinstance(scene, CrossingScene):
        raise TypeError(f"scene must be a CrossingScene, got {type(scene).__name__}")
    args = (scene.truth[0], 0.5 * np.eye(4), scene.F, scene.Q, scene.H, scene.R)
    jp = JPDATracker(*args, p_detect=p_detect, clutter_density=scene.clutter_density, gate_prob=0.99)
    gn = GNNTracker(*args, gate_prob=0.99)
    est_j = np.array([jp.step(z) for z in scene.scans])
    est_g = np.array([gn.step(z) for z in scene.scans])
    return est_j, est_g


def tracking_trial(rng: np.random.Generator, **scene_kw) -> dict:
    """One crossing scene tracked by JPDA and by GNN; returns their :func:`score_tracks`.

    ``scene_kw`` goes to :func:`projtrack.scenes.jpda.crossing_targets`; JPDA uses the
    scene's ``p_detect`` (see :func:`run_trackers`).
    """
    rng = as_rng(rng)
    sc = crossing_targets(rng, **scene_kw)
    est_j, est_g = run_trackers(sc, p_detect=scene_kw.get("p_detect", 0.9))
    return {"jpda": score_tracks(est_j, sc.truth[1:]), "gnn": score_tracks(est_g, sc.truth[1:])}


def tracking_study(n_runs: int, seed: int, **scene_kw) -> list[dict]:
    """``n_runs`` :func:`tracking_trial` results, run i on the i-th child of ``default_rng(seed)``.

    Goes through :func:`projtrack.montecarlo.run`, so the results do not depend on the
    number of worker processes; run ``i``'s scene is
    ``crossing_targets(np.random.default_rng(seed).spawn(n_runs)[i], **scene_kw)``.
    """
    n_runs = as_int(n_runs, "n_runs", minimum=0)
    seed = as_int(seed, "seed", minimum=0)
    return montecarlo.run(tracking_trial, n_runs, np.random.default_rng(seed), **scene_kw)


def tracking_summary(results: Sequence[dict]) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """Table of a tracking study (one row per tracker, JPDA and GNN) and its tolerances.

    Columns: ``tracker``, the mean RMSE over runs, and the shares of tracks
    swapped, of tracks lost (over all tracks of all runs) and of runs in which every track
    ended on its own target.

    The numbers come after discrete decisions (gating, GNN's assignment, the end-of-run
    swap and loss tests), which the last bits of a floating-point computation can flip.
    The tolerances are one flipped run: a run holds ``n_targets`` tracks, so a flip moves
    each share by at most ``1 / n_runs``, and the mean RMSE by at most the largest run
    RMSE over ``n_runs``.

    Returns
    -------
    table : pandas.DataFrame
    tolerance : dict of str to Tolerance
        For :func:`projtrack.figures.save_table` (column name -> tolerance).
    """
    if len(results) == 0:
        raise ValueError("results must hold at least one trial")
    for r in results:
        if not isinstance(r, dict) or set(r) != {"jpda", "gnn"} or any(
                not isinstance(r[k], dict) or "tracks" not in r[k] for k in r):
            raise ValueError("results must be tracking_trial outputs "
                             "(dicts with keys 'jpda' and 'gnn', each a score_tracks result)")
    n_runs = len(results)
    n_targets = int(results[0]["jpda"]["tracks"])
    rows, worst = [], 0.0
    for key, name in (("jpda", "JPDA"), ("gnn", "GNN")):
        rmse = np.sort([r[key]["rmse"] for r in results])
        n_tracks = n_runs * n_targets
        worst = max(worst, float(rmse[-1]))
        rows.append({"tracker": name, "mean RMSE": float(rmse.mean()),
                     "tracks swapped": sum(r[key]["swapped"] for r in results) / n_tracks,
                     "tracks lost": sum(r[key]["lost"] for r in results) / n_tracks,
                     "runs all correct": sum(r[key]["swapped"] + r[key]["lost"] == 0
                                             for r in results) / n_runs})
    flip = statistical(atol=1 / n_runs, why=f"one of {n_runs} runs changing outcome moves a share "
                                              f"of its runs, or of its {n_targets} tracks per run, "
                                              f"by at most 1/{n_runs}")
    tolerance = {"mean RMSE": mean_over(n_runs, max(worst, 1e-12), what="run"),
                 "tracks swapped": flip, "tracks lost": flip, "runs all correct": flip}
    return pd.DataFrame(rows), tolerance


def tracking_sampling(results: Sequence[dict]) -> tuple[pd.DataFrame, dict[str, Tolerance]]:
    """Share of tracks swapped or lost, with its standard error over runs, and the paired difference.

    The runs are the independent units (the tracks of one run share a scene), so the
    standard error is the standard deviation over runs of the per-run share, over
    ``sqrt(n_runs)``. Both trackers see the same scenes, so their difference is taken run by
    run (paired). Rows: ``JPDA``, ``GNN`` and ``JPDA - GNN (paired)``; columns ``tracker``,
    ``swapped or lost`` and ``standard error (runs)``.

    The tolerances are one run changing outcome: it moves a run's share by at most 1 (2 for
    the difference, when both trackers change), the mean by that over ``n_runs`` and the
    standard error by at most that over ``sqrt(n_runs (n_runs - 1))`` (a standard deviation
    moves by at most the change of one value over ``sqrt(n_runs - 1)``).

    Returns
    -------
    table : pandas.DataFrame
    tolerance : dict of str to Tolerance
    """
    if len(results) < 2:
        raise ValueError("results must hold at least two trials (a standard error needs two)")
    tracking_summary(results)  # the same checks of the results' form
    bad = {k: np.array([(r[k]["swapped"] + r[k]["lost"]) / r[k]["tracks"] for r in results])
           for k in ("jpda", "gnn")}
    n = len(results)
    rows = []
    for name, x in (("JPDA", bad["jpda"]), ("GNN", bad["gnn"]), ("JPDA - GNN (paired)", bad["jpda"] - bad["gnn"])):
        rows.append({"tracker": name, "swapped or lost": float(x.mean()),
                     "standard error (runs)": float(x.std(ddof=1) / np.sqrt(n))})
    tolerance = {"swapped or lost": statistical(atol=2 / n, why=(
        f"one of {n} runs changing outcome moves its share of bad tracks by at most 1 (2 for the "
        f"difference of the two trackers), the mean by at most 2/{n}")),
        "standard error (runs)": statistical(atol=2 / np.sqrt(n * (n - 1)), why=(
            f"one run changing outcome (a change of at most 2 in one of {n} values) moves a standard "
            f"deviation over runs by at most 2/sqrt({n - 1}), the standard error by 2/sqrt({n} x {n - 1})"))}
    return pd.DataFrame(rows), tolerance

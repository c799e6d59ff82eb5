"""The salvo of Figs. 2-3: six boost-phase launches in one 5-s stack of frames, scored.

:func:`salvo_scene` draws one scene from a seed, :func:`salvo_trial` runs the initiator
on it and counts found and false tracks (optionally with the diagnosis of why targets
are missed and the speeds at ``P_D = 0.9``), :func:`reading_trial` scores one scene
drawn with other launch parameters. Each trial takes a generator first, so that a study
is ``projtrack.montecarlo.run(salvo_trial, n, rng, ...)``.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_int, as_probability, as_real, as_rng
from projtrack.experiments.hough.scoring import evaluate_initiation
from projtrack.hough import TrackInitiator, line_through, local_average, window_neighbours
from projtrack.scenes.boost import BoostTrajectory, Frames, frame_times, in_view_launches, render_frames

__all__ = ["SALVO_TIMES", "salvo_scene", "speeds_by_target", "salvo_trial", "reading_trial"]

#: The frame times of one stack: 21 frames, ``T = 0.25`` s (5 s, as in the paper).
SALVO_TIMES = frame_times(21, 0.25)


def salvo_scene(seed: int, p_detect: float, *, n_targets: int = 6,
                n_noise: int = 5) -> tuple[list[BoostTrajectory], Frames]:
    """The scene of ``seed``: ``n_targets`` launches in view over :data:`SALVO_TIMES`, rendered.

    The same ``seed`` with another ``p_detect`` gives the same trajectories (and, for
    ``P_D = 1`` and ``P_D < 1``, the same jitter and false pixels): only which detections
    are dropped changes.
    """
    seed = as_int(seed, "seed", minimum=0)
    p_detect = as_probability(p_detect, "p_detect")
    rng = np.random.default_rng(seed)
    trajs = in_view_launches(rng, n_targets, SALVO_TIMES)
    return trajs, render_frames(trajs, SALVO_TIMES, rng, p_detect=p_detect, n_noise=n_noise)


def speeds_by_target(result: dict) -> dict[int, float]:
    """``{target: estimated speed}`` of the true tracks of an :func:`evaluate_initiation` result."""
    if not isinstance(result, dict) or "tracks" not in result:
        raise TypeError("result must be the dict returned by evaluate_initiation")
    return {t["target"]: t["speed"] for t in result["tracks"]}


def salvo_trial(rng: np.random.Generator, ratio: float = 3.0, extra: bool = False) -> dict[str, object]:
    """One salvo scene at ``P_D = 1`` scored with a :class:`~projtrack.hough.TrackInitiator`.

    Returns the scene's ``seed`` and the counts ``targets``, ``true lines``, ``found``,
    ``false lines``, ``false confirmed``, ``perfect`` (all found, no false track), ``n
    short`` (2-s predictions short of the truth), ``n tracks`` and ``n not short,
    position ahead``. With ``extra`` also ``diag``, per target ``(found, another line in
    its 5 x 5 window, best ratio near its true line)``, and ``speeds``, per target found
    in both ``(target, speed at P_D = 1, uncorrected speed at P_D = 0.9)`` on the same scene.
    """
    rng = as_rng(rng)
    ratio = as_real(ratio, "ratio", 0, low_open=True)
    seed = int(rng.integers(2 ** 62))
    tr, fr = salvo_scene(seed, 1.0)
    init = TrackInitiator(ratio=ratio)
    r = evaluate_initiation(init, fr, tr)
    out = {"seed": seed, "targets": r["n_targets"], "true lines": r["n_true_lines"], "found": r["n_found"],
           "false lines": r["n_false_lines"], "false confirmed": r["n_false_confirmed"],
           "perfect": r["n_found"] == r["n_targets"] and r["n_false_confirmed"] == 0,
           "n short": sum(t["shortfall"] > 0 for t in r["tracks"]), "n tracks": len(r["tracks"]),
           "n not short, position ahead": sum(t["pos_err_along"] > 0 for t in r["tracks"] if t["shortfall"] <= 0)}
    if extra:
        H, rhos, thetas = init.H_, init.rhos_, init.thetas_deg_
        A = local_average(H, 5, rhos=rhos, thetas_deg=thetas)
        R = np.where(A > 0, H / np.where(A > 0, A, 1), 0)
        lines = [line_through(fr.truth[:, k], fr.shape) for k in range(len(tr))]
        crowded = window_neighbours(lines)
        diag = []
        for k, (rho, th) in enumerate(lines):
            i = int(np.argmin(np.abs(rhos - rho)))
            j = int(round(th)) % 180
            cols = [(j + d) % 180 for d in (-1, 0, 1)]
            diag.append((k in r["found"], bool(crowded[k]), float(R[max(i - 1, 0):i + 2][:, cols].max())))
        out["diag"] = diag
        _, f9 = salvo_scene(seed, 0.9)
        a, b = speeds_by_target(r), speeds_by_target(evaluate_initiation(TrackInitiator(), f9, tr))
        out["speeds"] = [(k, a[k], b[k]) for k in sorted(set(a) & set(b))]
    return out


def reading_trial(rng: np.random.Generator, launch_kw: dict) -> tuple[int, int, int]:
    """One salvo drawn with the launch parameters ``launch_kw`` (of
    :func:`~projtrack.scenes.boost.random_launches`): ``(found, targets, false confirmed)``."""
    rng = as_rng(rng)
    if not isinstance(launch_kw, dict):
        raise TypeError(f"launch_kw must be a dict of random_launches arguments, got {type(launch_kw).__name__}")
    tr = in_view_launches(rng, 6, SALVO_TIMES, **launch_kw)
    fr = render_frames(tr, SALVO_TIMES, rng, n_noise=5)
    r = evaluate_initiation(TrackInitiator(), fr, tr)
    return r["n_found"], r["n_targets"], r["n_false_confirmed"]

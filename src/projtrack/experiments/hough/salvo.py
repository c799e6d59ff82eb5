"""The salvo of Figs. 2-3, and the crossing and closely spaced tracks of Sec. V.

:func:`salvo_scene` draws one six-launch scene from a seed, :func:`salvo_trial` runs the
initiator on it and counts found and false tracks (optionally with the diagnosis of why
targets are missed and the speeds at ``P_D = 0.9``), :func:`reading_trial` scores one
scene drawn under another reading of the open choices at several vote floors.
:func:`pair_trial` puts two straight tracks that cross or run side by side (or one track
with false pixels close to it) in the settings of Fig. 2 and scores each target with and
without the other. Each trial takes a generator first, so that a study is
``projtrack.montecarlo.run(salvo_trial, n, rng, ...)``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from projtrack._validation import as_choice, as_int, as_probability, as_real, as_rng
from projtrack.experiments.hough.scoring import evaluate_initiation, fraction_needed, match_lines
from projtrack.hough import TrackInitiator, hough_transform, line_through, local_average, window_neighbours
from projtrack.scenes.boost import BoostTrajectory, Frames, frame_times, in_view_launches, render_frames

__all__ = ["SALVO_TIMES", "salvo_scene", "speeds_by_target", "salvo_trial", "reading_trial", "PAIR_KINDS",
           "pair_scene", "pair_trial", "pair_summary", "clutter_summary"]

#: The frame times of one stack: 21 frames, ``T = 0.25`` s (5 s, as in the paper).
SALVO_TIMES = frame_times(21, 0.25)


def _initiator(min_votes: float | None = None, ratio: float = 3.0) -> TrackInitiator:
    """The paper's peak rule (ratio 3, bridged at 1.5), with the vote floor ``min_votes``."""
    return TrackInitiator(ratio=ratio, bridge=1.5, min_votes=min_votes)


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


def _diagnosis(frames: Frames, trajs: list, init: TrackInitiator, found: set) -> list[tuple]:
    """Per target: found, another target's line in its 5 x 5 window, and how its own best
    cell stands against the ratio rule (``N``, the share ``f`` of its votes in that cell,
    the mean bias ``b`` of the other votes over the cell's window, the share needed by the
    mean field, ``0.6 + 2 b / N``, and the real ratio at the cell)."""
    H, rhos, thetas = init.H_, init.rhos_, init.thetas_deg_
    A = local_average(H, 5, rhos=rhos, thetas_deg=thetas)
    comp, lab = frames.composite(), np.concatenate(frames.labels)
    lines = [line_through(frames.truth[:, k], frames.shape) for k in range(len(trajs))]
    crowded = window_neighbours(lines)
    out = []
    for k in range(len(trajs)):
        own = comp[lab == k]
        n = len(own)
        if n < 2:
            continue
        Hk = hough_transform(own, frames.shape)[0]
        i, j = np.unravel_index(int(np.argmax(Hk)), Hk.shape)
        Ak = local_average(Hk, 5, rhos=rhos, thetas_deg=thetas)[i, j]
        b = float(max(A[i, j] - Ak, 0.0))  # the others' mean votes per cell over the window
        out.append((k in found, bool(crowded[k]), n, float(Hk[i, j] / n), b, fraction_needed(n, b),
                    float(H[i, j] / A[i, j])))
    return out


def salvo_trial(rng: np.random.Generator, ratio: float = 3.0, extra: bool = False,
                min_votes: float | None = None) -> dict[str, object]:
    """One salvo scene at ``P_D = 1`` scored with the paper's peak rule at ``ratio``.

    The initiator bridges split peaks at 1.5 and uses the vote floor ``min_votes``
    (``None``: a quarter of the frames). The scene depends only on ``rng`` (a seed drawn
    from it), so runs with other ``ratio`` or ``min_votes`` see the same scenes.

    Returns the scene's ``seed`` and the counts ``targets``, ``true lines``, ``found``,
    ``false lines``, ``false confirmed``, ``perfect`` (all found, no false track), ``n
    short`` (2-s predictions short of the truth), ``n tracks`` and ``n not short,
    position ahead``. With ``extra`` also ``diag``, per target ``(found, another line in
    its 5 x 5 window, N, f, b, needed, real ratio)`` (see the chapter's bound), and
    ``speeds``, per target found in both ``(target, speed at P_D = 1, uncorrected speed
    at P_D = 0.9)`` on the same scene.
    """
    rng = as_rng(rng)
    ratio = as_real(ratio, "ratio", 0, low_open=True)
    seed = int(rng.integers(2 ** 62))
    tr, fr = salvo_scene(seed, 1.0)
    init = _initiator(min_votes, ratio)
    r = evaluate_initiation(init, fr, tr)
    out = {"seed": seed, "targets": r["n_targets"], "true lines": r["n_true_lines"], "found": r["n_found"],
           "false lines": r["n_false_lines"], "false confirmed": r["n_false_confirmed"],
           "perfect": r["n_found"] == r["n_targets"] and r["n_false_confirmed"] == 0,
           "n short": sum(t["shortfall"] > 0 for t in r["tracks"]), "n tracks": len(r["tracks"]),
           "n not short, position ahead": sum(t["pos_err_along"] > 0 for t in r["tracks"] if t["shortfall"] <= 0)}
    if extra:
        out["diag"] = _diagnosis(fr, tr, init, r["found"])
        _, f9 = salvo_scene(seed, 0.9)
        a, b = speeds_by_target(r), speeds_by_target(evaluate_initiation(_initiator(min_votes, ratio), f9, tr))
        out["speeds"] = [(k, a[k], b[k]) for k in sorted(set(a) & set(b))]
    return out


def reading_trial(rng: np.random.Generator, launch_kw: dict, floors: Sequence[float] = (6.0,),
                  ) -> dict[float, tuple[int, int, int, bool]]:
    """One salvo drawn with the launch parameters ``launch_kw`` (of
    :func:`~projtrack.scenes.boost.random_launches`), initiated with the paper's peak rule at
    each vote floor of ``floors`` on the same frames: ``{floor: (found, targets, false
    confirmed, all found and no false track)}``, and ``"extent"``: the largest distance any
    target covers over the 21 frames (Sec. II.B wants the fastest to cover half the frame)."""
    rng = as_rng(rng)
    if not isinstance(launch_kw, dict):
        raise TypeError(f"launch_kw must be a dict of random_launches arguments, got {type(launch_kw).__name__}")
    floors = [as_real(f, "floors", 0) for f in floors]
    if not floors:
        raise ValueError("floors must not be empty")
    tr = in_view_launches(rng, 6, SALVO_TIMES, **launch_kw)
    fr = render_frames(tr, SALVO_TIMES, rng, n_noise=5)
    out: dict = {}
    for f in floors:
        r = evaluate_initiation(_initiator(f), fr, tr)
        out[f] = (r["n_found"], r["n_targets"], r["n_false_confirmed"],
                  r["n_found"] == r["n_targets"] and r["n_false_confirmed"] == 0)
    out["extent"] = float(max(np.linalg.norm(fr.truth[-1, k] - fr.truth[0, k]) for k in range(len(tr))))
    return out


#: The scenarios of :func:`pair_trial` and what their ``value`` is.
PAIR_KINDS = {"crossing": "crossing angle (degrees)", "parallel": "separation across the tracks (pixels)",
              "clutter": "false pixels close to the track"}


def _straight(centre: np.ndarray, velocity: np.ndarray, t_mid: float) -> BoostTrajectory:
    """A constant-velocity target at ``centre`` at time ``t_mid`` (launched long before)."""
    t0 = -10.0
    return BoostTrajectory(t0, centre - velocity * (t_mid - t0), velocity, np.zeros(2))


def pair_scene(rng: np.random.Generator, kind: str, value: float, *, speed: float = 20.0,
               n_noise: int = 5, jitter_sigma: float = 0.5,
               clutter_radius: tuple[float, float] = (1.0, 3.0)) -> tuple[list[BoostTrajectory], Frames]:
    """A scenario of Sec. V in the settings of Fig. 2 (21 frames of 0.25 s, jitter, false pixels).

    Target 0 moves at ``speed`` pixels/s in a uniform random direction and passes a centre
    drawn uniformly in the middle of the frame (96-160 pixels on each axis) at the middle
    frame. ``kind``:

    * ``"crossing"``: target 1 passes the same centre at the same time, its heading turned
      by ``value`` degrees (the two tracks cross mid-window);
    * ``"parallel"``: target 1 has the same velocity, ``value`` pixels to the side of
      target 0 (two closely spaced tracks);
    * ``"clutter"``: no second target; ``int(value)`` false pixels are put at a distance
      drawn uniformly in ``clutter_radius`` (default 1-3 pixels) from target 0's true
      position, in a uniform direction, in randomly chosen frames (random observations close
      to the actual ones), besides the ``n_noise`` uniform ones per frame; a pixel that
      falls on an existing detection is not added (a frame is a binary image).
    """
    rng = as_rng(rng)
    as_choice(kind, "kind", tuple(PAIR_KINDS))
    value = as_real(value, "value", 0)
    speed = as_real(speed, "speed", 0, low_open=True)
    t_mid = float(SALVO_TIMES[len(SALVO_TIMES) // 2])
    centre = rng.uniform(96.0, 160.0, size=2)
    phi = rng.uniform(0.0, 2 * np.pi)
    u = np.array([np.cos(phi), np.sin(phi)])
    trajs = [_straight(centre, speed * u, t_mid)]
    if kind == "crossing":
        psi = phi + np.deg2rad(value)
        trajs.append(_straight(centre, speed * np.array([np.cos(psi), np.sin(psi)]), t_mid))
    elif kind == "parallel":
        trajs.append(_straight(centre + value * np.array([-u[1], u[0]]), speed * u, t_mid))
    frames = render_frames(trajs, SALVO_TIMES, rng, n_noise=as_int(n_noise, "n_noise", minimum=0),
                           jitter_sigma=as_real(jitter_sigma, "jitter_sigma", 0))
    if kind == "clutter":
        k = as_int(int(value), "value", minimum=0)
        r_lo, r_hi = (as_real(r, "clutter_radius", 0) for r in clutter_radius)
        if r_hi < r_lo:
            raise ValueError(f"clutter_radius must be (low, high) with low <= high, got {clutter_radius!r}")
        picks = rng.choice(len(SALVO_TIMES), size=min(k, len(SALVO_TIMES)), replace=False)
        pts, labs = list(frames.points), list(frames.labels)
        for f in sorted(int(p) for p in picks):
            ang, r = rng.uniform(0.0, 2 * np.pi), rng.uniform(r_lo, r_hi)
            q = np.rint(frames.truth[f, 0] + r * np.array([np.cos(ang), np.sin(ang)]))
            if np.any(np.all(pts[f] == q, axis=1)):
                continue  # already a detection there (a frame is a binary image)
            pts[f] = np.vstack([pts[f], q])
            labs[f] = np.append(labs[f], -1)
        frames = Frames(pts, labs, frames.times, frames.truth, frames.shape)
    return trajs, frames


def _without(frames: Frames, target: int) -> Frames:
    """The same frames without the detections of ``target`` (the other target alone)."""
    keep = [lab != target for lab in frames.labels]
    return Frames([p[k] for p, k in zip(frames.points, keep)], [lab[k] for lab, k in zip(frames.labels, keep)],
                  frames.times, frames.truth, frames.shape)


def _without_clutter(frames: Frames, n_noise: int) -> Frames:
    """The frames without the close false pixels :func:`pair_scene` appended after the uniform ones."""
    pts, labs = [], []
    for p, lab in zip(frames.points, frames.labels):
        n_keep = int(np.sum(lab >= 0)) + n_noise
        pts.append(p[:n_keep])
        labs.append(lab[:n_keep])
    return Frames(pts, labs, frames.times, frames.truth, frames.shape)


def _ratio_at(frames: Frames, cell: tuple[int, int]) -> float:
    """Ratio of the exact to the 5 x 5 averaged HT of the composite of ``frames`` at ``cell``."""
    H, rh, th = hough_transform(frames.composite(), frames.shape)
    A = local_average(H, 5, rhos=rh, thetas_deg=th)
    return float(H[cell] / A[cell])


def pair_trial(rng: np.random.Generator, kind: str, value: float, *, min_votes: float | None = None,
               n_noise: int = 5, **scene_kw: object) -> dict[str, object]:
    """One :func:`pair_scene`, initiated with the paper's peak rule, with and without the other target.

    Returns ``together`` and ``alone``: per target (0, 1), whether a confirmed line lies on
    it (at least half of its detections in the line's strip, as in
    :func:`~projtrack.experiments.hough.match_lines`) when both are in the frames, and
    when only that target is (the other's detections removed, everything else the same);
    ``lines on pair``: the confirmed lines on which at least half of the detections of
    target 0 or of target 1 lie (one line for two tracks closer than the strip);
    ``ratio alone`` and ``ratio together``: the ratio of exact to averaged HT at target 0's
    best cell without and with the other target. For ``"clutter"`` ``alone`` is target 0
    without the close false pixels and target 1 is absent (``False``).
    """
    tr, fr = pair_scene(rng, kind, value, n_noise=n_noise, **scene_kw)  # type: ignore[arg-type]
    init = _initiator(min_votes)
    init.initiate(fr.points, fr.times, fr.shape)
    comp, lab = fr.composite(), np.concatenate(fr.labels)
    confirmed = [(t.rho, t.theta_deg) for t in init.tracks_ if t.confirmed]
    on = [match_lines(confirmed, comp, np.where(lab == k, 0, -1), fr.shape) >= 0 for k in range(len(tr))]
    together = tuple(bool(on[k].any()) if k < len(tr) else False for k in (0, 1))
    pair_lines = int(np.sum(np.any(on, axis=0))) if confirmed else 0
    if kind == "clutter":
        alone_frames = [_without_clutter(fr, n_noise)]
    else:
        alone_frames = [_without(fr, 1 - k) for k in (0, 1)]
    alone = tuple(k in evaluate_initiation(_initiator(min_votes), f)["found"] for k, f in enumerate(alone_frames))
    alone = (alone + (False,))[:2]
    Hk = hough_transform(comp[lab == 0], fr.shape)[0]
    cell = tuple(int(v) for v in np.unravel_index(int(np.argmax(Hk)), Hk.shape))
    return {"together": together, "alone": tuple(bool(a) for a in alone), "lines on pair": pair_lines,
            "ratio alone": _ratio_at(alone_frames[0], cell), "ratio together": _ratio_at(fr, cell)}


def pair_summary(kind: str, value: float, trials: Sequence[Mapping]) -> dict[str, object]:
    """One row of the Sec. V table from :func:`pair_trial` results of one scenario.

    ``found together`` and ``found alone``: the share of the targets (both of each draw,
    target 0 only for ``"clutter"``) on which a confirmed line lies with and without the
    other target; ``change``: their paired difference (together minus alone) and ``2 SE``
    twice its standard error over the draws; ``no line``, ``one line``, ``two lines``: the
    shares of draws with that many confirmed lines on the pair; ``ratio change``: the median
    change of target 0's ratio at its best cell (together minus alone).
    """
    as_choice(kind, "kind", tuple(PAIR_KINDS))
    if len(trials) < 2:
        raise ValueError(f"trials must hold at least 2 results of pair_trial, got {len(trials)}")
    m = 1 if kind == "clutter" else 2
    tog = np.array([t["together"][:m] for t in trials], dtype=float)
    alo = np.array([t["alone"][:m] for t in trials], dtype=float)
    d = (tog - alo).mean(axis=1)
    lines = np.array([t["lines on pair"] for t in trials])
    value = value if isinstance(value, int) and not isinstance(value, bool) else as_real(value, "value", 0)
    return {"scenario": kind, "value": value, "draws": len(trials), "found together": float(tog.mean()),
            "found alone": float(alo.mean()), "change": float(d.mean()),
            "2 SE": float(2 * d.std(ddof=1) / np.sqrt(len(d))),
            "no line": float(np.mean(lines == 0)), "one line": float(np.mean(lines == 1)),
            "two lines": float(np.mean(lines >= 2)),
            "ratio change": float(np.median([t["ratio together"] - t["ratio alone"] for t in trials]))}


def clutter_summary(value: int, trials: Sequence[Mapping]) -> dict[str, object]:
    """One row of the close-clutter dose table from :func:`pair_trial` results of ``"clutter"``.

    ``found alone`` and ``found with``: the shares of draws whose target is found without and
    with the ``value`` close false pixels (same frames otherwise); ``kept``: the share of
    the targets found alone that are still found with them, and ``kept low``, ``kept high``
    its 95 % Clopper-Pearson interval; ``gained``: the share of draws found only
    with them; ``change`` (with minus alone) and ``2 SE``, twice the standard error of that
    paired difference over the draws.
    """
    from projtrack.experiments.hough.scoring import rate_ci

    if len(trials) < 2:
        raise ValueError(f"trials must hold at least 2 results of pair_trial, got {len(trials)}")
    tog = np.array([t["together"][0] for t in trials], dtype=bool)
    alo = np.array([t["alone"][0] for t in trials], dtype=bool)
    n_alone = int(alo.sum())
    kept = int((tog & alo).sum())
    d = tog.astype(float) - alo.astype(float)
    return {"close false pixels": as_int(value, "value", minimum=0), "draws": len(trials),
            "found alone": float(alo.mean()), "found with": float(tog.mean()),
            "kept": kept / n_alone if n_alone else float("nan"),
            "kept low": rate_ci(kept, n_alone)[0] if n_alone else float("nan"),
            "kept high": rate_ci(kept, n_alone)[1] if n_alone else float("nan"),
            "gained": float((tog & ~alo).mean()), "change": float(d.mean()),
            "2 SE": float(2 * d.std(ddof=1) / np.sqrt(d.size))}

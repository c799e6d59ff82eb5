"""The plain against the thresholded HT (Figs. 5-6): five launches among many false pixels.

:func:`noisy_scene` draws a scene over the 21 frames of ``SALVO_TIMES``,
:func:`plain_and_thresholded` runs both initiators on it. How far the printed ratio-3
peak rule can reach on a biased plane: the mean-field ratio of a line and the share of its
votes its cell must hold (:func:`~projtrack.experiments.hough.mean_field_ratio`,
:func:`~projtrack.experiments.hough.fraction_needed`), checked against simulations of a
perfect line (:func:`perfect_line_trial`) and of the targets' own lines
(:func:`target_peaks`), with :func:`noise_plane` for the bias; :func:`bound_tables` puts
the check in tables. :func:`reading_counts` and :func:`rule_counts` are the Monte Carlo
trials of the chapter's tables (generator first, for ``projtrack.montecarlo.run``);
:func:`rule_summary` turns the trials of :func:`rule_counts` into per-rule statistics over
the scenes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.experiments.hough.salvo import SALVO_TIMES
from projtrack.experiments.hough.scoring import evaluate_initiation, fraction_needed
from projtrack.hough import TrackInitiator, hough_transform, local_average
from projtrack.scenes.boost import BoostTrajectory, Frames, in_view_launches, render_frames

__all__ = ["noisy_scene", "plain_and_thresholded", "noise_plane", "perfect_line_trial", "target_peaks", "reading_counts",
           "rule_counts", "rule_summary", "bound_tables", "floor_tradeoff", "tradeoff_tables"]


def noisy_scene(rng: np.random.Generator, n_noise: int = 20, n_targets: int = 5, *, jitter_sigma: float = 0.5,
                **launch_kw: object) -> tuple[list[BoostTrajectory], Frames]:
    """``n_targets`` launches in view over the 21 frames, with ``n_noise`` false pixels per frame.

    ``jitter_sigma`` goes to :func:`~projtrack.scenes.boost.render_frames`, ``launch_kw`` to
    :func:`~projtrack.scenes.boost.in_view_launches` (the readings of the scene).
    """
    rng = as_rng(rng)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    n_targets = as_int(n_targets, "n_targets", minimum=0)
    trajs = in_view_launches(rng, n_targets, SALVO_TIMES, **launch_kw)
    return trajs, render_frames(trajs, SALVO_TIMES, rng, n_noise=n_noise,
                                jitter_sigma=as_real(jitter_sigma, "jitter_sigma", 0))


def plain_and_thresholded(frames: Frames, trajs: list[BoostTrajectory], ratio: float = 3.0,
                          **kw: object) -> dict[str, tuple[TrackInitiator, dict]]:
    """``{"plain": (initiator, result), "thresholded": (initiator, result)}`` on one scene.

    Both initiators use the peak ``ratio`` and the other :class:`~projtrack.hough.TrackInitiator`
    arguments ``kw``; ``result`` is :func:`~projtrack.experiments.hough.evaluate_initiation`'s.
    """
    if not isinstance(frames, Frames):
        raise TypeError(f"frames must be a projtrack.scenes.boost.Frames, got {type(frames).__name__}")
    ratio = as_real(ratio, "ratio", 0, low_open=True)
    out = {}
    for name, thr in (("plain", False), ("thresholded", True)):
        opts = {"bridge": 1.5, **kw}  # the paper's bridging unless a rule says otherwise
        init = TrackInitiator(thresholded=thr, ratio=ratio, dx_max=16, **opts)  # type: ignore[arg-type]
        out[name] = (init, evaluate_initiation(init, frames, trajs))
    return out


def rule_counts(rng: np.random.Generator, rules: Mapping[str, Mapping[str, object]]) -> dict:
    """One noisy scene scored under several peak rules.

    ``rules`` maps a rule's name to its :class:`~projtrack.hough.TrackInitiator` arguments.
    Returns ``{rule: {"plain" | "thresholded": (found, false lines, false confirmed)}}``.
    """
    if not isinstance(rules, Mapping):
        raise TypeError(f"rules must be a mapping of rule name to initiator arguments, got {type(rules).__name__}")
    tr, fr = noisy_scene(rng)
    out = {}
    for rule, kw in rules.items():
        out[rule] = {name: (r["n_found"], r["n_false_lines"], r["n_false_confirmed"])
                     for name, (_, r) in plain_and_thresholded(fr, tr, **kw).items()}
    return out


def noise_plane(rng: np.random.Generator, n_noise: int = 20, n_frames: int = 21) -> np.ndarray:
    """The HT plane (``drho = 2``, 1 deg) of ``n_noise`` uniform false pixels in each of
    ``n_frames`` 256 x 256 frames and nothing else: one draw of the noise-only bias."""
    rng = as_rng(rng)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    n_frames = as_int(n_frames, "n_frames", minimum=1)
    frames = [np.column_stack([rng.integers(0, 256, n_noise), rng.integers(0, 256, n_noise)]) for _ in range(n_frames)]
    return hough_transform(np.concatenate(frames).astype(float), (256, 256), allow_empty=True)[0]


def perfect_line_trial(rng: np.random.Generator, n_points: int = 21, n_noise: int = 20, *,
                       rho_range: tuple[float, float] = (0.0, 100.0), spacing: float = 5.0,
                       shape: tuple[int, int] = (256, 256)) -> dict[str, float]:
    """One perfect line on the composite of ``n_noise`` false pixels in each of ``n_points`` frames.

    The line has ``n_points`` points exactly on it, ``spacing`` pixels apart and centred on
    its foot point, at an integer angle ``theta`` (uniform over 0-179 degrees) and a
    ``rho`` on a bin centre (uniform over the bin centres in ``rho_range``, drawn again
    until every point lies in the frame): all its votes fall in its own cell, the best
    case of the ratio rule. The false pixels are uniform over the frame. Returns the
    line's ``rho``, the ratio of the exact to the 5 x 5 averaged HT at its cell
    (``ratio``), the false pixels' votes in that cell (``bias_cell``) and their mean over
    its window (``bias_window``), and whether all the line's votes fell in its cell
    (``all_in_cell``; always true by construction, kept as a check).
    """
    rng = as_rng(rng)
    n_points = as_int(n_points, "n_points", minimum=2)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    lo, hi = (as_real(v, "rho_range", 0) for v in rho_range)
    spacing = as_real(spacing, "spacing", 0, low_open=True)
    h, w = shape
    centres = 2.0 * np.arange(int(np.ceil(lo / 2.0)), int(np.floor(hi / 2.0)) + 1)
    if centres.size == 0:
        raise ValueError(f"rho_range must contain a bin centre (a multiple of 2), got {rho_range!r}")
    s = np.arange(n_points) - (n_points - 1) / 2.0
    for _ in range(10_000):
        rho, th = float(rng.choice(centres)), float(rng.integers(0, 180))
        t = np.deg2rad(th)
        n, d = np.array([np.cos(t), np.sin(t)]), np.array([-np.sin(t), np.cos(t)])
        pts = np.array([w / 2, h / 2]) + rho * n + spacing * s[:, None] * d
        if np.all((pts >= 0) & (pts <= np.array([w - 1, h - 1]))):
            break
    else:  # pragma: no cover - the default ranges always fit
        raise RuntimeError("no line of this length fits in the frame")
    noise = np.column_stack([rng.integers(0, w, n_noise * n_points), rng.integers(0, h, n_noise * n_points)])
    Hl, rh, tt = hough_transform(pts, shape)
    Hn = hough_transform(noise.astype(float), shape, allow_empty=True)[0]
    i, j = np.unravel_index(int(np.argmax(Hl)), Hl.shape)
    H = Hl + Hn
    A = local_average(H, 5, rhos=rh, thetas_deg=tt)
    An = local_average(Hn, 5, rhos=rh, thetas_deg=tt)
    return {"rho": rho, "ratio": float(H[i, j] / A[i, j]), "bias_cell": float(Hn[i, j]),
            "bias_window": float(An[i, j]), "all_in_cell": bool(Hl[i, j] == n_points)}


def target_peaks(rng: np.random.Generator, window_bias: object, *, min_votes: float | None = None,
                 **scene_kw: object) -> list[dict[str, object]]:
    """How each target of one :func:`noisy_scene` stands against the ratio rule.

    ``window_bias`` is the mean noise-only plane averaged over the 5 x 5 window (the bias
    ``b`` of :func:`mean_field_ratio`, on the axes of
    :func:`~projtrack.hough.hough_transform`'s default); ``scene_kw`` goes to
    :func:`noisy_scene`. For every target with detections returns ``N`` (its detections),
    ``fraction`` (the share of its own votes in its best cell: 1 for a perfect line; the
    jitter, the rounding to the pixel and the curvature spread them), ``bias`` (the window
    bias at that cell), ``needed`` (:func:`fraction_needed` there), ``|rho| <= 64``
    (whether the cell lies in the central plane), ``real ratio`` (the ratio of the real
    composite's plane at that cell) and ``found`` (whether the printed rule, ratio 3 with
    bridging at 1.5 and the vote floor ``min_votes``, confirms a track on the target).
    """
    tr, frames = noisy_scene(rng, **scene_kw)  # type: ignore[arg-type]
    comp, lab = frames.composite(), np.concatenate(frames.labels)
    H, rh, th = hough_transform(comp, frames.shape)
    B = as_array(window_bias, "window_bias", shape=H.shape)
    A = local_average(H, 5, rhos=rh, thetas_deg=th)
    init = TrackInitiator(ratio=3.0, bridge=1.5, min_votes=min_votes)
    found = evaluate_initiation(init, frames, tr)["found"]
    out = []
    for k in range(len(tr)):
        own = comp[lab == k]
        if len(own) < 2:
            continue
        Hk = hough_transform(own, frames.shape)[0]
        i, j = np.unravel_index(int(np.argmax(Hk)), Hk.shape)
        n = len(own)
        out.append({"N": n, "fraction": float(Hk[i, j] / n), "bias": float(B[i, j]),
                    "needed": fraction_needed(n, float(B[i, j])), "|rho| <= 64": bool(abs(rh[i]) <= 64),
                    "real ratio": float(H[i, j] / A[i, j]) if A[i, j] > 0 else float("inf"),
                    "found": k in found})
    return out


def reading_counts(rng: np.random.Generator, floors: Sequence[float], *, n_targets: int = 5, n_noise: int = 20,
                   jitter_sigma: float = 0.5, **launch_kw: object) -> dict[float, tuple[int, int, bool, int, int]]:
    """One scene under a reading of the open choices, scored with the printed rule at several vote floors.

    ``n_targets`` launches in view over the 21 frames (:func:`~projtrack.scenes.boost.in_view_launches`
    with ``launch_kw``), rendered with ``jitter_sigma`` and ``n_noise`` false pixels per
    frame, initiated with the paper's peak rule (ratio 3, bridge 1.5) at each vote floor
    of ``floors`` on the same frames. Returns ``{floor: (targets found, targets, all found,
    false lines, false tracks confirmed)}``.
    """
    rng = as_rng(rng)
    floors = [as_real(f, "floors", 0) for f in floors]
    if not floors:
        raise ValueError("floors must not be empty")
    trajs = in_view_launches(rng, as_int(n_targets, "n_targets", minimum=1), SALVO_TIMES, **launch_kw)
    frames = render_frames(trajs, SALVO_TIMES, rng, n_noise=as_int(n_noise, "n_noise", minimum=0),
                           jitter_sigma=as_real(jitter_sigma, "jitter_sigma", 0))
    out = {}
    for f in floors:
        r = evaluate_initiation(TrackInitiator(ratio=3.0, bridge=1.5, min_votes=f), frames, trajs)
        out[f] = (r["n_found"], r["n_targets"], r["n_found"] == r["n_targets"], r["n_false_lines"],
                  r["n_false_confirmed"])
    return out


def rule_summary(groups: Sequence[tuple[Sequence[Mapping], Sequence[str]]],
                 hts: Sequence[str] = ("plain", "thresholded"), n_targets: int = 5) -> tuple[list[dict], dict, dict]:
    """Per-rule statistics over scenes of :func:`rule_counts` trials.

    ``groups`` is a sequence of ``(results, rules)`` pairs: ``results`` a list of
    :func:`rule_counts` outputs (one per scene), ``rules`` the names of the rules of those
    results to summarize. For each rule and each HT of ``hts``, in that order:

    Returns
    -------
    rows : list of dict
        ``rule``, ``scenes`` (their number), ``HT``, ``targets found`` (share of the
        ``n_targets`` targets of every scene), ``scenes with all found`` (share of the
        scenes), ``false lines`` and ``false confirmed`` (means per scene).
    means : dict
        ``(rule, HT) -> array([found, false lines, false confirmed])``, means over the scenes.
    dist : dict
        ``(rule, HT) -> (n_scenes, 3)`` array of those counts, one row per scene.
    """
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    rows, means, dist = [], {}, {}
    for group in groups:
        if not isinstance(group, tuple) or len(group) != 2:
            raise ValueError(f"groups must hold (results, rules) pairs, got {group!r}")
        res, rules = group
        if isinstance(rules, str):
            raise TypeError(f"rules must be a sequence of rule names, not the string {rules!r}")
        if len(res) < 2:
            raise ValueError(f"each group needs at least 2 scenes, got {len(res)}")
        for rule in rules:
            for name in hts:
                try:
                    a = np.array([r[rule][name] for r in res], dtype=float)
                except KeyError as exc:
                    raise ValueError(f"rule {rule!r} or HT {name!r} is not in the results") from exc
                if a.ndim != 2 or a.shape[1] != 3:
                    raise ValueError(f"results must hold (found, false lines, false confirmed) triples, got shape {a.shape}")
                means[(rule, name)] = a.mean(axis=0)
                dist[(rule, name)] = a
                rows.append({"rule": rule, "scenes": len(res), "HT": name,
                             "targets found": float(a[:, 0].sum() / (n_targets * len(res))),
                             "scenes with all found": float((a[:, 0] == n_targets).mean()),
                             "false lines": float(a[:, 1].mean()), "false confirmed": float(a[:, 2].mean())})
    return rows, means, dist


def bound_tables(perfect: Sequence[Mapping], targets: Sequence[Mapping], n_votes: int = 21):
    """The chapter's check of the ratio bound against simulation, as two tables with tolerances.

    ``perfect`` are :func:`perfect_line_trial` results, ``targets`` the rows of
    :func:`target_peaks` over many scenes.

    Returns
    -------
    mean_field : pandas.DataFrame
        One row per case (a perfect line; our targets): the mean bias ``b`` at the line's
        cell (votes per cell), the share ``f`` of the line's votes in that cell (mean), the
        mean-field ratio :func:`~projtrack.experiments.hough.mean_field_ratio` at the mean
        ``b`` and ``f``, the simulated ratio (median) and the share of simulated ratios above 3.
    votes : pandas.DataFrame
        Our targets: the share of its votes a target's best cell must hold (median of
        :func:`~projtrack.experiments.hough.fraction_needed`), the share it holds (median),
        the share of targets holding enough, and the share found by the printed rule among
        those that hold enough and those that do not.
    tolerances : (dict, dict)
        For each table. Means, medians and shares over the draws, after the discrete votes
        and peak decisions: a share of ``n`` draws moves by ``1/n``; a median moves to a
        neighbouring order statistic (the largest gap between the order statistics around
        each median is measured and used); the mean bias by one vote in one draw.
    """
    import pandas as pd

    from projtrack.experiments.hough.scoring import mean_field_ratio
    from projtrack.tolerance import mean_over, share, statistical

    if not perfect or not targets:
        raise ValueError("perfect and targets must not be empty")
    P = pd.DataFrame(list(perfect))
    T = pd.DataFrame(list(targets))

    def med_gap(x: np.ndarray) -> float:
        x = np.sort(np.asarray(x, dtype=float))
        m = x.size // 2
        window = x[max(m - 3, 0):m + 4]
        return float(max(np.diff(window).max(initial=0.0), 1e-6))

    rows = []
    for name, b, f, n, sim in (("perfect line, rho 0-100", P["bias_window"].mean(), 1.0, n_votes, P["ratio"]),
                               ("our targets (measured f)", T["bias"].mean(), T["fraction"].mean(),
                                float(T["N"].mean()), T["real ratio"])):
        rows.append({"case": name, "bias b": float(b), "share f in cell": float(f),
                     "mean-field ratio": mean_field_ratio(n, float(b), float(f)),
                     "simulated ratio (median)": float(np.median(sim)), "simulated > 3": float((sim > 3).mean())})
    mf = pd.DataFrame(rows)
    n_p, n_t = len(P), len(T)
    gap = max(med_gap(P["ratio"]), med_gap(T["real ratio"]))
    tol_mf = {"bias b": mean_over(min(n_p, n_t), 1.0, what="draw"),
              "share f in cell": mean_over(n_t, 1.0 / n_votes, what="target"),
              "mean-field ratio": statistical(atol=0.01, why="a function of the mean bias and share: one vote "
                                              "more in one of the draws moves it by far less than 0.01"),
              "simulated ratio (median)": statistical(atol=round(gap, 3) + 1e-3,
                                                      why="a median: one draw that changes moves it to a "
                                                          "neighbouring order statistic (largest gap measured "
                                                          "around the medians)"),
              "simulated > 3": share(min(n_p, n_t))}
    ok = T["fraction"] >= T["needed"]
    votes = pd.DataFrame([{"share needed (median)": float(T["needed"].median()),
                           "share held (median)": float(T["fraction"].median()),
                           "targets holding enough": float(ok.mean()),
                           "found, holding enough": float(T.loc[ok, "found"].mean()) if ok.any() else float("nan"),
                           "found, not holding enough": float(T.loc[~ok, "found"].mean()) if (~ok).any()
                           else float("nan")}])
    k = max(int(min(ok.sum(), (~ok).sum())), 1)
    tol_v = {"share needed (median)": statistical(atol=0.01, why="a median of 0.6 + 2 b / N over the targets: "
                                                  "a neighbouring order statistic"),
             "share held (median)": statistical(atol=1.0 / n_votes, why="a median of vote shares: one vote of one "
                                                "target moves it by 1/N"),
             "targets holding enough": share(n_t), "found, holding enough": share(k),
             "found, not holding enough": share(k)}
    return mf, votes, (tol_mf, tol_v)


def floor_tradeoff(rng: np.random.Generator, plain_floors: Sequence[float], thresholded_floors: Sequence[float],
                   **scene_kw: object) -> dict[str, object]:
    """One :func:`noisy_scene` (``scene_kw``) under the plain HT at several vote floors and the thresholded HT at others.

    The baseline the thresholded HT must beat: raising the plain HT's vote floor also cuts
    false lines. Both use the paper's peak rule (ratio 3, bridging at 1.5). Returns
    ``counts``: ``{("plain" | "thresholded", floor): (targets found, false lines, false
    tracks confirmed)}``, and ``targets``: for every target with at least two detections,
    at its own best cell (the argmax of the HT of its detections alone) the ratio of the
    exact to the 5 x 5 averaged plane and the other detections' votes in that cell, under
    the plain (``ratio plain``, ``others plain``) and the thresholded HT (``ratio
    thresholded``, ``others thresholded``). Clipping each frame's HT at one vote removes
    the false pixels' votes that share the target's cell in a frame with it.
    """
    from projtrack.hough import thresholded_hough_transform

    plain_floors = [as_real(f, "plain_floors", 0) for f in plain_floors]
    thresholded_floors = [as_real(f, "thresholded_floors", 0) for f in thresholded_floors]
    if not plain_floors or not thresholded_floors:
        raise ValueError("plain_floors and thresholded_floors must not be empty")
    tr, fr = noisy_scene(rng, **scene_kw)  # type: ignore[arg-type]
    counts = {}
    for name, floors in (("plain", plain_floors), ("thresholded", thresholded_floors)):
        for f in floors:
            init = TrackInitiator(thresholded=name == "thresholded", ratio=3.0, bridge=1.5, dx_max=16, min_votes=f)
            r = evaluate_initiation(init, fr, tr)
            counts[(name, f)] = (r["n_found"], r["n_false_lines"], r["n_false_confirmed"])
    comp, lab = fr.composite(), np.concatenate(fr.labels)
    Hp, rh, th = hough_transform(comp, fr.shape)
    Ht = thresholded_hough_transform(list(fr.points), fr.shape)[0]
    Ap, At = (local_average(H, 5, rhos=rh, thetas_deg=th) for H in (Hp, Ht))
    targets = []
    for k in range(len(tr)):
        own = comp[lab == k]
        if len(own) < 2:
            continue
        Hk = hough_transform(own, fr.shape)[0]
        c = np.unravel_index(int(np.argmax(Hk)), Hk.shape)
        targets.append({"ratio plain": float(Hp[c] / Ap[c]), "ratio thresholded": float(Ht[c] / At[c]),
                        "others plain": float(Hp[c] - Hk[c]), "others thresholded": float(Ht[c] - min(Hk[c], Ht[c]))})
    return {"counts": counts, "targets": targets}


def tradeoff_tables(trials: Sequence[Mapping], n_targets: int = 5):
    """The thresholded HT against the plain HT at a matched false-line rate, from :func:`floor_tradeoff` trials.

    Returns
    -------
    curve : pandas.DataFrame
        One row per HT and vote floor: ``targets found`` (share of the ``n_targets`` of
        every scene), ``false lines`` and ``false confirmed`` (means per scene).
    matched : pandas.DataFrame
        One row per floor of the thresholded HT: ``plain floor``, the lowest plain floor
        whose false lines per scene are no more than the thresholded HT's (the highest
        floor when none is that low; ``false lines, plain`` then shows it), both found shares and false-line means, and
        ``found change`` (thresholded minus plain, targets per scene, paired over the same
        scenes) with ``2 SE``.
    mechanism : pandas.DataFrame
        Over all targets: the median ratio at the target's own cell and the mean of the other
        votes in that cell, plain and thresholded, and the share of targets whose ratio is
        lower thresholded.
    """
    import pandas as pd

    n_targets = as_int(n_targets, "n_targets", minimum=1)
    if len(trials) < 2:
        raise ValueError(f"trials must hold at least 2 results of floor_tradeoff, got {len(trials)}")
    keys = list(trials[0]["counts"])
    a = {k: np.array([t["counts"][k] for t in trials], dtype=float) for k in keys}
    def _n(f: float) -> float | int:
        return int(f) if float(f).is_integer() else f

    curve = pd.DataFrame([{"HT": ht, "floor": _n(f), "targets found": float(v[:, 0].mean() / n_targets),
                           "false lines": float(v[:, 1].mean()), "false confirmed": float(v[:, 2].mean())}
                          for (ht, f), v in a.items()])
    plain = sorted(f for ht, f in keys if ht == "plain")
    rows = []
    for ht, f in keys:
        if ht != "thresholded":
            continue
        t = a[(ht, f)]
        ok = [p for p in plain if a[("plain", p)][:, 1].mean() <= t[:, 1].mean()]
        p = ok[0] if ok else plain[-1]
        d = t[:, 0] - a[("plain", p)][:, 0]
        rows.append({"thresholded floor": _n(f), "plain floor": _n(p),
                     "found, thresholded": float(t[:, 0].mean() / n_targets),
                     "found, plain": float(a[("plain", p)][:, 0].mean() / n_targets),
                     "false lines, thresholded": float(t[:, 1].mean()),
                     "false lines, plain": float(a[("plain", p)][:, 1].mean()),
                     "found change": float(d.mean()), "2 SE": float(2 * d.std(ddof=1) / np.sqrt(d.size))})
    matched = pd.DataFrame(rows)
    T = pd.DataFrame([r for t in trials for r in t["targets"]])
    mechanism = pd.DataFrame([{"HT": ht, "ratio at own cell (median)": float(T[f"ratio {ht}"].median()),
                               "other votes in own cell (mean)": float(T[f"others {ht}"].mean()),
                               "ratio lower than plain": float((T[f"ratio {ht}"] < T["ratio plain"]).mean())}
                              for ht in ("plain", "thresholded")])
    return curve, matched, mechanism

"""The plain against the thresholded HT (Figs. 5-6): five launches among many false pixels.

:func:`noisy_scene` draws a scene over the 21 frames of
``SALVO_TIMES``, :func:`plain_and_thresholded`
runs both initiators on it; :func:`noise_plane` (the bias of a noise-only plane),
:func:`target_peaks` (how the targets' peaks stand against that bias), :func:`rule_counts`
and :func:`roc_trial` are the Monte Carlo trials of the chapter's tables (generator
first, for ``projtrack.montecarlo.run``); :func:`rule_summary` turns the trials of
:func:`rule_counts` into per-rule statistics over the scenes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.experiments.hough.salvo import SALVO_TIMES
from projtrack.experiments.hough.scoring import evaluate_initiation
from projtrack.hough import TrackInitiator, hough_transform, line_through, local_average
from projtrack.scenes.boost import BoostTrajectory, Frames, in_view_launches, render_frames
from projtrack.stable import fmt

__all__ = ["noisy_scene", "plain_and_thresholded", "noise_plane", "target_peaks", "rule_counts", "roc_trial",
           "rule_summary"]


def noisy_scene(rng: np.random.Generator, n_noise: int = 20,
                n_targets: int = 5) -> tuple[list[BoostTrajectory], Frames]:
    """``n_targets`` launches in view over the 21 frames, with ``n_noise`` false pixels per frame."""
    rng = as_rng(rng)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    n_targets = as_int(n_targets, "n_targets", minimum=0)
    trajs = in_view_launches(rng, n_targets, SALVO_TIMES)
    return trajs, render_frames(trajs, SALVO_TIMES, rng, n_noise=n_noise)


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
        init = TrackInitiator(thresholded=thr, ratio=ratio, dx_max=16, **kw)  # type: ignore[arg-type]
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


def roc_trial(rng: np.random.Generator, n_noise: int, ratio: float) -> dict[str, tuple[float, int, int]]:
    """One scene with ``n_noise`` false pixels per frame at peak ratio ``ratio``:
    ``{"plain" | "thresholded": (fraction of the 5 targets found, false tracks, false lines)}``."""
    tr, fr = noisy_scene(rng, n_noise=n_noise)
    return {name: (r["n_found"] / 5, r["n_false_confirmed"], r["n_false_lines"])
            for name, (_, r) in plain_and_thresholded(fr, tr, ratio).items()}


def noise_plane(rng: np.random.Generator, n_noise: int = 20, n_frames: int = 21) -> np.ndarray:
    """The HT plane (``drho = 2``, 1 deg) of ``n_noise`` uniform false pixels in each of
    ``n_frames`` 256 x 256 frames and nothing else: one draw of the noise-only bias."""
    rng = as_rng(rng)
    n_noise = as_int(n_noise, "n_noise", minimum=0)
    n_frames = as_int(n_frames, "n_frames", minimum=1)
    frames = [np.column_stack([rng.integers(0, 256, n_noise), rng.integers(0, 256, n_noise)]) for _ in range(n_frames)]
    return hough_transform(np.concatenate(frames).astype(float), (256, 256), allow_empty=True)[0]


def target_peaks(rng: np.random.Generator, window_bias: object) -> list[dict[str, object]]:
    """How each target's peak of one :func:`noisy_scene` stands against the noise bias.

    ``window_bias`` is the mean noise-only plane averaged over the 5 x 5 window (the bias
    of the window mean, same axes as :func:`~projtrack.hough.hough_transform`'s default).
    For every target returns ``|rho| <= 64`` (whether its line lies in the central plane),
    ``spills`` (whether its noise-free votes, projected onto the line, spill out of the
    window), ``bias`` (the window bias at its cell), ``perfect ratio on bias`` (``N``
    votes over the window mean of the perfect line plus the bias) and ``real best ratio``
    (the best peak-to-window ratio of the real plane within one cell of the line).
    """
    tr, frames = noisy_scene(rng)
    H, rh, th = hough_transform(frames.composite(), frames.shape)
    B = as_array(window_bias, "window_bias", shape=H.shape)
    A_real = local_average(H, 5, rhos=rh, thetas_deg=th)
    R = H / np.where(A_real > 0, A_real, 1)
    out = []
    for t in range(frames.truth.shape[1]):
        pts = frames.truth[:, t]
        rho, theta = line_through(pts, frames.shape)
        n = np.array([np.cos(np.deg2rad(theta)), np.sin(np.deg2rad(theta))])
        proj = np.clip(pts - ((pts - 128.0) @ n - rho)[:, None] * n, 0, 255.999)
        Hp, _, _ = hough_transform(proj, frames.shape)
        ii, j = int(np.argmin(np.abs(rh - rho))), int(round(theta)) % 180  # the line's own cell
        A = local_average(Hp, 5, rhos=rh, thetas_deg=th)[ii, j]  # its votes in the window / 25
        N = len(pts)
        cols = [(j + d) % 180 for d in (-1, 0, 1)]
        out.append({"|rho| <= 64": abs(rho) <= 64, "spills": 25 * A < 5 * N - 0.5, "bias": B[ii, j],
                    "perfect ratio on bias": N / (A + B[ii, j]),
                    "real best ratio": float(R[max(ii - 1, 0):ii + 2][:, cols].max())})
    return out


def rule_summary(groups: Sequence[tuple[Sequence[Mapping], Sequence[str]]],
                 hts: Sequence[str] = ("plain", "thresholded")) -> tuple[list[dict], dict, dict]:
    """Per-rule statistics over scenes of :func:`rule_counts` trials.

    ``groups`` is a sequence of ``(results, rules)`` pairs: ``results`` a list of
    :func:`rule_counts` outputs (one per scene), ``rules`` the names of the rules of those
    results to summarize. For each rule and each HT of ``hts``, in that order:

    Returns
    -------
    rows : list of dict
        ``rule``, ``scenes`` (their number), ``HT``, ``true found (of 5)``, ``false lines``,
        ``false confirmed`` as ``"mean +- std"`` over the scenes (sample std, two decimals)
        and ``scenes with 5 of 5`` (a percentage).
    means : dict
        ``(rule, HT) -> array([found, false lines, false confirmed])``, means over the scenes.
    dist : dict
        ``(rule, HT) -> (n_scenes, 3)`` array of those counts, one row per scene.
    """
    rows, means, dist = [], {}, {}
    for group in groups:
        if not isinstance(group, tuple) or len(group) != 2:
            raise ValueError(f"groups must hold (results, rules) pairs, got {group!r}")
        res, rules = group
        if isinstance(rules, str):
            raise TypeError(f"rules must be a sequence of rule names, not the string {rules!r}")
        if len(res) < 2:
            raise ValueError(f"each group needs at least 2 scenes for a std, got {len(res)}")
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
                             "true found (of 5)": f"{fmt(a[:, 0].mean(), '.2f')} +- {fmt(a[:, 0].std(ddof=1), '.2f')}",
                             "scenes with 5 of 5": f"{fmt((a[:, 0] == 5).mean(), '.0%')}",
                             "false lines": f"{fmt(a[:, 1].mean(), '.2f')} +- {fmt(a[:, 1].std(ddof=1), '.2f')}",
                             "false confirmed": f"{fmt(a[:, 2].mean(), '.2f')} +- {fmt(a[:, 2].std(ddof=1), '.2f')}"})
    return rows, means, dist

"""The plain against the thresholded HT (Figs. 5-6): five launches among many false pixels.

:func:`noisy_scene` draws a scene over the 21 frames of
``SALVO_TIMES``, :func:`plain_and_thresholded`
runs both initiators on it, :func:`rule_counts` and :func:`roc_trial` are the Monte Carlo
trials of the chapter's tables (generator first, for ``projtrack.montecarlo.run``).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from projtrack._validation import as_int, as_real, as_rng
from projtrack.experiments.hough.salvo import SALVO_TIMES
from projtrack.experiments.hough.scoring import evaluate_initiation
from projtrack.hough import TrackInitiator
from projtrack.scenes.boost import BoostTrajectory, Frames, in_view_launches, render_frames

__all__ = ["noisy_scene", "plain_and_thresholded", "rule_counts", "roc_trial"]


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

"""The continuous run of Fig. 4: 120 s of launches cut into 5-s segments, each initiated alone.

:func:`continuous_run` scores every segment against the targets that could be detected
in it; :func:`never_detected` counts the targets that crossed the field without ever
being detected (the same draws, faster). Both take a generator first, for
``projtrack.montecarlo.run``.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_int, as_real, as_rng
from projtrack.experiments.hough.scoring import evaluate_initiation
from projtrack.hough import TrackInitiator
from projtrack.scenes.boost import Frames, continuous_launches, frame_times, render_frames

__all__ = ["continuous_run", "never_detected"]


def _scene(rng: np.random.Generator, n_targets: int, duration: float,
           frame_time: float) -> tuple[list, Frames, np.ndarray]:
    trajs = continuous_launches(rng, n_targets, duration, frame_time=frame_time)
    fr = render_frames(trajs, frame_times(int(round(duration / frame_time)), frame_time), rng, n_noise=5)
    h, w = fr.shape
    inview = ((fr.truth[..., 0] >= 0) & (fr.truth[..., 0] <= w - 1) & (fr.truth[..., 1] >= 0)
              & (fr.truth[..., 1] <= h - 1))
    return trajs, fr, inview


def _check(rng: object, n_targets: object, duration: object, frame_time: object, segment: object,
           ) -> tuple[np.random.Generator, int, float, float, int]:
    return (as_rng(rng), as_int(n_targets, "n_targets", minimum=1),
            as_real(duration, "duration", 0, low_open=True), as_real(frame_time, "frame_time", 0, low_open=True),
            as_int(segment, "segment", minimum=2))


def continuous_run(rng: np.random.Generator, min_votes: float | None = None, *, n_targets: int = 15,
                   duration: float = 120.0, frame_time: float = 0.25, segment: int = 20,
                   min_in_view: int = 15) -> dict[str, object]:
    """One run of Fig. 4: ``n_targets`` launches over ``duration`` s, initiated per segment.

    The frames are cut into segments of ``segment`` frames (5 s); each is given to its own
    :class:`~projtrack.hough.TrackInitiator` (vote floor ``min_votes``, ``None``: the
    default rule). A detection is *possible* for a target in view in at least
    ``min_in_view`` frames of a segment.

    Returns
    -------
    dict
        ``trajs`` and ``fr`` (the scene), ``crossed`` (targets ever in view), ``seen``
        (of those, detected at least once), ``possible``, ``detected`` (possible ones
        found), ``extra`` (found in a segment where they were not possible), ``false``
        (confirmed false tracks), ``arrows`` (``(position, velocity, owner)`` of every
        confirmed track), ``unseen_possible`` (sorted numbers of possible detections of
        the targets never detected) and ``false_ones`` (strip points of each false track).
    """
    rng, n_targets, duration, frame_time, segment = _check(rng, n_targets, duration, frame_time, segment)
    min_in_view = as_int(min_in_view, "min_in_view", minimum=1, maximum=segment)
    trajs, fr, inview = _scene(rng, n_targets, duration, frame_time)
    n_seg = len(fr.points) // segment
    possible = detected = extra = false = 0
    seen, arrows, false_ones = set(), [], []
    for s in range(n_seg):
        seg = fr.segment(segment * s, segment * s + segment)
        init = TrackInitiator(min_votes=min_votes)
        r = evaluate_initiation(init, seg)
        poss = {int(i) for i in np.flatnonzero(inview[segment * s:segment * s + segment].sum(axis=0) >= min_in_view)}
        possible += len(poss)
        detected += len(r["found"] & poss)
        extra += len(r["found"] - poss)
        false += r["n_false_confirmed"]
        seen |= r["found"]
        arrows += [(tr.position, tr.velocity, o) for tr, o in zip(init.tracks_, r["owner"]) if tr.confirmed]
        false_ones += [tr.projection.n_ones for tr, o in zip(init.tracks_, r["owner"]) if tr.confirmed and o < 0]
    crossed = {int(i) for i in np.flatnonzero(inview.any(axis=0))}
    n_poss = [sum(int(inview[segment * s:segment * s + segment, i].sum() >= min_in_view) for s in range(n_seg))
              for i in range(len(trajs))]
    unseen_possible = sorted(n_poss[i] for i in crossed - seen)
    return dict(trajs=trajs, fr=fr, crossed=len(crossed), seen=len(seen & crossed), possible=possible,
                detected=detected, extra=extra, false=false, arrows=arrows, unseen_possible=unseen_possible,
                false_ones=false_ones)


def never_detected(rng: np.random.Generator, *, n_targets: int = 15, duration: float = 120.0,
                   frame_time: float = 0.25, segment: int = 20) -> int:
    """Targets of one run (the draws of :func:`continuous_run`) that crossed the field undetected.

    A segment in which every target in view has already been detected cannot change the
    answer and is skipped, so this is much faster than :func:`continuous_run`;
    ``crossed - seen`` of the same generator's :func:`continuous_run` is the same number.
    """
    rng, n_targets, duration, frame_time, segment = _check(rng, n_targets, duration, frame_time, segment)
    _, fr, inview = _scene(rng, n_targets, duration, frame_time)
    seen: set[int] = set()
    for s in range(len(fr.points) // segment):
        if {int(i) for i in np.flatnonzero(inview[segment * s:segment * s + segment].any(axis=0))} <= seen:
            continue
        seen |= evaluate_initiation(TrackInitiator(), fr.segment(segment * s, segment * s + segment))["found"]
    crossed = {int(i) for i in np.flatnonzero(inview.any(axis=0))}
    return len(crossed - seen)

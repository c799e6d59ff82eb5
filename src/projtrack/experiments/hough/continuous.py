"""The continuous run of Fig. 4: 120 s of launches cut into 5-s segments, each initiated alone.

:func:`continuous_run` records, segment by segment, which targets were in view and which
were found; :func:`possible_detections` counts the possible and the made detections under a
reading of the paper's "one [possible detection] for each 5 s" (:data:`POSSIBLE_READINGS`);
:func:`never_detected` counts the targets that crossed the field without ever being
detected (the same draws, faster). The trials take a generator first, for
``projtrack.montecarlo.run``.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_choice, as_int, as_real, as_rng
from projtrack.experiments.hough.scoring import evaluate_initiation
from projtrack.hough import TrackInitiator
from projtrack.scenes.boost import Frames, continuous_launches, frame_times, render_frames

__all__ = ["continuous_run", "never_detected", "POSSIBLE_READINGS", "possible_detections", "run_outcome"]

#: Readings of "one possible detection for each 5 s": a segment is a possible detection of a
#: target in view in at least k of its frames (``"k of 20 frames"``), or a target has
#: ``round(frames in view / 20)`` possible detections, matched by the segments in which it
#: was found (``"one per 5 s in view"``).
POSSIBLE_READINGS = ("1 of 20 frames", "10 of 20 frames", "15 of 20 frames", "20 of 20 frames",
                     "one per 5 s in view")


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


def _initiator(min_votes: float | None) -> TrackInitiator:
    return TrackInitiator(ratio=3.0, bridge=1.5, min_votes=min_votes)


def continuous_run(rng: np.random.Generator, min_votes: float | None = None, *, n_targets: int = 15,
                   duration: float = 120.0, frame_time: float = 0.25, segment: int = 20) -> dict[str, object]:
    """One run of Fig. 4: ``n_targets`` launches over ``duration`` s, initiated per segment.

    The frames are cut into segments of ``segment`` frames (5 s); each is given to its own
    :class:`~projtrack.hough.TrackInitiator` with the paper's peak rule (ratio 3, bridge
    1.5) and the vote floor ``min_votes`` (``None``: a quarter of the frames).

    Returns
    -------
    dict
        ``trajs`` and ``fr`` (the scene), ``in_view`` (frames in view per segment and
        target, shape ``(segments, targets)``), ``found`` (whether a confirmed line lay on
        the target in the segment, same shape), ``false`` (confirmed false tracks per
        segment), ``arrows`` (``(position, velocity, owner)`` of every confirmed track),
        ``false_ones`` (strip points of each false track), ``crossed`` (targets ever in
        view) and ``seen`` (of those, found at least once).
    """
    rng, n_targets, duration, frame_time, segment = _check(rng, n_targets, duration, frame_time, segment)
    trajs, fr, inview = _scene(rng, n_targets, duration, frame_time)
    n_seg = len(fr.points) // segment
    in_view = np.zeros((n_seg, len(trajs)), dtype=int)
    found = np.zeros((n_seg, len(trajs)), dtype=bool)
    false = np.zeros(n_seg, dtype=int)
    arrows, false_ones = [], []
    for s in range(n_seg):
        init = _initiator(min_votes)
        r = evaluate_initiation(init, fr.segment(segment * s, segment * s + segment))
        in_view[s] = inview[segment * s:segment * s + segment].sum(axis=0)
        found[s, sorted(r["found"])] = True
        false[s] = r["n_false_confirmed"]
        arrows += [(tr.position, tr.velocity, o) for tr, o in zip(init.tracks_, r["owner"]) if tr.confirmed]
        false_ones += [tr.projection.n_ones for tr, o in zip(init.tracks_, r["owner"]) if tr.confirmed and o < 0]
    crossed = in_view.sum(axis=0) > 0
    return dict(trajs=trajs, fr=fr, in_view=in_view, found=found, false=false, arrows=arrows,
                false_ones=false_ones, crossed=int(crossed.sum()), seen=int((crossed & found.any(axis=0)).sum()))


def possible_detections(run: dict, reading: str = "15 of 20 frames", segment: int = 20) -> tuple[int, int]:
    """``(possible, detected)`` detections of one :func:`continuous_run` under ``reading``.

    ``"k of 20 frames"``: every segment in which a target is in view in at least ``k`` of
    its ``segment`` frames is a possible detection, made when the target was found there.
    ``"one per 5 s in view"``: a target in view in ``n`` frames has ``round(n / segment)``
    possible detections (halves round up) and makes as many of them as the segments in
    which it was found, at most that number.
    """
    if not isinstance(run, dict) or "in_view" not in run or "found" not in run:
        raise TypeError("run must be the dict returned by continuous_run")
    as_choice(reading, "reading", POSSIBLE_READINGS)
    segment = as_int(segment, "segment", minimum=1)
    in_view, found = np.asarray(run["in_view"]), np.asarray(run["found"], dtype=bool)
    if reading == "one per 5 s in view":
        poss = np.floor(in_view.sum(axis=0) / segment + 0.5).astype(int)
        return int(poss.sum()), int(np.minimum(found.sum(axis=0), poss).sum())
    k = int(reading.split(" of ")[0])
    if k > segment:
        raise ValueError(f"reading {reading!r} needs segments of at least {k} frames, got {segment}")
    ok = in_view >= k
    return int(ok.sum()), int((ok & found).sum())


def run_outcome(run: dict, reading: str, interval: tuple[float, float]) -> dict[str, object]:
    """The single-run outcomes of Fig. 4 for one :func:`continuous_run`.

    ``rate``: detected over possible detections under ``reading`` (see
    :func:`possible_detections`); ``matched``: whether it lies in ``interval`` (ends
    included), for example the exact 95 % interval of the paper's 45 of 49; ``all seen``:
    every target that crossed the field found at least once; ``no false``: no confirmed
    false track in any segment.
    """
    lo, hi = (as_real(v, "interval") for v in interval)
    if hi < lo:
        raise ValueError(f"interval must be (low, high) with low <= high, got {interval!r}")
    possible, detected = possible_detections(run, reading)
    rate = detected / possible if possible else float("nan")
    return {"rate": rate, "matched": bool(possible and lo <= rate <= hi),
            "all seen": bool(run["seen"] == run["crossed"]), "no false": bool(np.sum(run["false"]) == 0)}


def never_detected(rng: np.random.Generator, min_votes: float | None = None, *, n_targets: int = 15,
                   duration: float = 120.0, frame_time: float = 0.25, segment: int = 20) -> int:
    """Targets of one run (the draws of :func:`continuous_run`) that crossed the field undetected.

    A segment in which every target in view has already been detected cannot change the
    answer and is skipped, so this is much faster than :func:`continuous_run`;
    ``crossed - seen`` of the same generator's :func:`continuous_run` (same ``min_votes``)
    is the same number.
    """
    rng, n_targets, duration, frame_time, segment = _check(rng, n_targets, duration, frame_time, segment)
    _, fr, inview = _scene(rng, n_targets, duration, frame_time)
    seen: set[int] = set()
    for s in range(len(fr.points) // segment):
        if {int(i) for i in np.flatnonzero(inview[segment * s:segment * s + segment].any(axis=0))} <= seen:
            continue
        seen |= evaluate_initiation(_initiator(min_votes), fr.segment(segment * s, segment * s + segment))["found"]
    crossed = {int(i) for i in np.flatnonzero(inview.any(axis=0))}
    return len(crossed - seen)

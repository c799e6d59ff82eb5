"""The street-scene study of Figs. 2-3: its rules, the calibrated synthetic scene and its readings.

The rules read on the records of one sequence: :func:`order_2_4` (frames 2 and 3 not novel,
then frame 4 novel with one eigenimage: the text's order of events), :func:`entry_marked` (the
entering person's frame and every later one novel, fewer than half of the frames before it),
:func:`ghost_area` (how much of the people's paths an image still shows above the display
threshold ``T_f``) and :func:`record_table` (the panels of Figs. 2-3 as a table).

The calibrated scene.  The printed ``V_1 = 73544016`` is the energy of the paper's 128 x 128
frame 1, so its RMS grey level is ``sqrt(V_1 / 16384) = 67.0`` (:data:`PRINTED_RMS`); the
printed ``n_2 = 0.0018`` is the novelty of frame 2 against frame 1 alone.
:func:`calibrate_gain` sets the exposure of
:func:`projtrack.scenes.sequences.walking_sequence` so that the median frame-1 RMS of a set of
calibration draws is the printed one; :func:`calibrate_contrast` then sets the people's
contrast so that the median novelty of frame ``j`` against frame 1 is a printed value (frame 2
and ``n_2``, or frame 4 and ``n_4``).  The calibration draws are never the draws the claims
are judged on.  The choices the text does not pin are *readings* (:data:`READINGS`): the
walkers' speed (the text says their old and new areas overlap at frame 2 and overlap "much
less" at frame 4) and the camera's synchronization (frame 2 is out of sync with frame 1, frame
3 in sync; the later frames are not described, so the two extremes are read: all in sync, all
out of sync).  :func:`sequence_readings` returns, for one sequence, every quantity the
chapter's claims are judged on; :func:`reading_draws` runs it over the draws of a reading.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.novelty import FrameRecord, NoveltyFilter, process_sequence
from projtrack.scenes.sequences import walking_layers, walking_sequence

__all__ = ["FIG2_SETTINGS", "FIG3_SETTINGS", "PIXEL_THRESHOLD", "ghost_area", "order_2_4", "entry_marked",
           "record_table", "PRINTED_RMS", "NOISE_STD", "READINGS", "CONTRARY_READINGS", "VISIBILITY_THRESHOLDS",
           "novelty_against_first", "calibrate_gain", "calibrate_contrast", "calibrate_person", "calibrate_readings",
           "frame2_quiet", "ghost_rms", "memory_updates", "novel_pixel_quality", "sequence_readings",
           "reading_draw", "reading_draws", "threshold_sweep", "ghost_decay"]

#: ``(T_d, T_I)`` of Fig. 2 and of Fig. 3.
FIG2_SETTINGS: tuple[float, float] = (0.002, 0.95)
FIG3_SETTINGS: tuple[float, float] = (0.001, 0.9995)
#: ``T_f``: the paper's display threshold of the novel-pixel image (grey levels).
PIXEL_THRESHOLD: float = 8.0


def _records(recs: Any, name: str = "recs") -> Sequence[FrameRecord]:
    if not isinstance(recs, (list, tuple)) or not recs or not all(
            isinstance(r, FrameRecord) for r in recs):
        raise TypeError(f"{name} must be a non-empty list of FrameRecord (process_sequence)")
    return recs


def ghost_area(img: Any, background: Any, paths: Any, people_per_frame: float,
               pixel_threshold: float = PIXEL_THRESHOLD) -> float:
    """Visible-ghost area: pixels on the people's ``paths`` with ``|img - B| > T_f``, per person area.

    Parameters
    ----------
    img, background : array_like (H, W)
        The image judged (a first eigenimage, a mean, a frame) and the true background ``B``.
    paths : array_like (H, W) bool
        Pixels any person has covered so far.
    people_per_frame : float
        Mean number of pixels the people cover in one frame (> 0).
    pixel_threshold : float
        ``T_f`` in grey levels.
    """
    img = as_array(img, "img", ndim=2)
    background = as_array(background, "background", shape=img.shape)
    paths = np.asarray(paths, dtype=bool)
    if paths.shape != img.shape:
        raise ValueError(f"paths must have shape {img.shape}, got {paths.shape}")
    people_per_frame = as_real(people_per_frame, "people_per_frame", 0.0, low_open=True)
    pixel_threshold = as_real(pixel_threshold, "pixel_threshold", 0.0)
    return float(np.sum(np.abs(img - background)[paths] > pixel_threshold) / people_per_frame)



def order_2_4(recs: Sequence[FrameRecord]) -> bool:
    """The text's order of events: frames 2 and 3 not novel, frame 4 novel with one eigenimage kept."""
    recs = _records(recs)
    if len(recs) < 4:
        raise ValueError(f"recs must hold at least 4 frames, got {len(recs)}")
    return (not recs[1].novel) and (not recs[2].novel) and recs[3].novel and recs[3].rank == 1


def entry_marked(recs: Sequence[FrameRecord], entry: int = 8) -> bool:
    """The entry rule: frame ``entry`` and all later frames novel, fewer than half of frames 2..entry-1."""
    recs = _records(recs)
    entry = as_int(entry, "entry", minimum=3, maximum=len(recs))
    early = sum(r.novel for r in recs[1:entry - 1])
    return all(r.novel for r in recs[entry - 1:]) and early < (entry - 2) / 2





def record_table(frames: Any, novelty_threshold: float, information_threshold: float,
                 pixel_threshold: float = 8) -> tuple[list[FrameRecord], pd.DataFrame]:
    """Run the filter over ``frames`` and tabulate every frame as the panels of Figs. 2-3 do.

    Returns
    -------
    recs : list of FrameRecord
    table : pandas.DataFrame
        Index ``frame``; columns ``n_i`` (6 digits), ``novel``, ``F (candidates)`` (the first
        three fractions of a novel frame), ``eigenimages kept``, ``novel pixels``.
    """
    recs = process_sequence(frames, novelty_threshold=novelty_threshold,
                            information_threshold=information_threshold, pixel_threshold=pixel_threshold)
    table = pd.DataFrame({
        "frame": [r.frame for r in recs],
        "n_i": [round(r.novelty, 6) for r in recs],
        "novel": [r.novel for r in recs],
        "F (candidates)": ["" if r.fractions is None else " ".join(f"{v:.6f}" for v in r.fractions[:3])
                           for r in recs],
        "eigenimages kept": [r.rank for r in recs],
        "novel pixels": [int(r.novel_pixels.sum()) for r in recs],
    }).set_index("frame")
    return recs, table


#: RMS grey level of the paper's frame 1: ``sqrt(73544016 / (128 * 128))``.
PRINTED_RMS: float = float(np.sqrt(73544016.0 / 128 ** 2))
#: Sensor noise of the calibrated scene (grey levels): the temporal standard deviation of the
#: real plaza video on the pixels no person covers (1.16), rounded.
NOISE_STD: float = 1.2

_LATER = tuple(range(4, 25))
#: The readings of what the text leaves open (keyword arguments of ``walking_sequence``), named
#: by the walkers' speed (px per frame) and the frames after frame 3 (all in sync with frame 1,
#: or all out of sync; frame 2 is always out of sync, frame 3 never).
READINGS: dict[str, dict[str, Any]] = {
    "1 px, later in sync": dict(background_speed=1.0, jitter_frames=(2,)),
    "2 px, later in sync": dict(background_speed=2.0, jitter_frames=(2,)),
    "1 px, later out of sync": dict(background_speed=1.0, jitter_frames=(2, *_LATER)),
    "2 px, later out of sync": dict(background_speed=2.0, jitter_frames=(2, *_LATER)),
}
#: Readings that contradict a sentence of the text, shown as a sensitivity and not judged on: no
#: frame out of sync (the text blames frame 2's novel background pixels on a synchronization
#: difference) or every frame out of sync (frame 3 "was synchronized with frame 1").
CONTRARY_READINGS: dict[str, dict[str, Any]] = {
    "1 px, none out of sync": dict(background_speed=1.0, jitter=0.0),
    "2 px, none out of sync": dict(background_speed=2.0, jitter=0.0),
    "1 px, all out of sync": dict(background_speed=1.0),
    "2 px, all out of sync": dict(background_speed=2.0),
}


def novelty_against_first(frames: Any, j: int = 2) -> float:
    """Eq. (7): the novelty of frame ``j`` (1-based) against the model of frame 1 alone."""
    frames = as_array(frames, "frames", allow_empty=False)
    j = as_int(j, "j", minimum=2, maximum=len(frames))
    f = NoveltyFilter(*FIG2_SETTINGS)
    f.partial_fit(frames[0])
    return f.novelty(frames[j - 1])


def _children(rng: np.random.Generator, n: int) -> list[np.random.Generator]:
    return as_rng(rng).spawn(as_int(n, "n", minimum=1))


def calibrate_gain(n: int, rng: np.random.Generator, target_rms: float = PRINTED_RMS,
                   **scene: Any) -> float:
    """The exposure ``gain`` at which the median frame-1 RMS of ``n`` draws is ``target_rms``.

    ``scene`` holds other keyword arguments of
    :func:`~projtrack.scenes.sequences.walking_sequence`; only frame 1 of each draw is made.
    """
    target_rms = as_real(target_rms, "target_rms", 0.0, low_open=True)
    draws = _children(rng, n)

    def median_rms(g: float) -> float:
        return float(np.median([np.sqrt(np.mean(walking_sequence(r, n_frames=1, gain=g, **scene)
                                                .frames[0].astype(float) ** 2)) for r in draws]))
    return float(brentq(lambda g: median_rms(g) - target_rms, 0.05, 2.0, xtol=1e-5))


def calibrate_contrast(n: int, rng: np.random.Generator, target: float = 0.0018, j: int = 2,
                       hi: float = 4.0, **scene: Any) -> tuple[float, float]:
    """The people's contrast at which the median novelty of frame ``j`` against frame 1 is ``target``.

    Parameters
    ----------
    n : int
        Calibration draws (children of ``rng``; only their first ``j`` frames are made, once,
        with :func:`~projtrack.scenes.sequences.walking_layers`, then read at each contrast).
    rng : numpy.random.Generator
    target : float
        The printed novelty (0.0018 for frame 2, 0.0025 for frame 4).
    j : int
        The frame (1-based).
    hi : float
        Largest contrast tried.
    scene
        Other keyword arguments of :func:`~projtrack.scenes.sequences.walking_sequence`
        (not the contrasts).

    Returns
    -------
    (contrast, floor)
        The contrast (``nan`` when contrast 0 already gives a median above ``target``: sensor
        noise and synchronization differences alone are too novel) and that median at
        contrast 0 (the floor without people).
    """
    target = as_real(target, "target", 0.0, 1.0)
    j = as_int(j, "j", minimum=2)
    layers = [walking_layers(r, n_frames=j, **scene) for r in _children(rng, n)]   # each draw made once

    def median_novelty(a: float) -> float:
        return float(np.median([novelty_against_first(lay.frames(a), j) for lay in layers]))
    floor = median_novelty(0.0)
    if floor >= target:
        return float("nan"), floor
    # the people add novelty about in proportion to the contrast squared: start brentq from that guess
    at_one = median_novelty(1.0)
    guess = float(np.sqrt((target - floor) / (at_one - floor))) if at_one > floor else 1.0
    lo, hi_b = 0.85 * min(guess, hi), min(1.15 * guess, hi)
    f_lo, f_hi = median_novelty(lo) - target, median_novelty(hi_b) - target
    if f_lo > 0 or f_hi < 0:                      # the guess missed: the whole range
        lo, hi_b, f_lo, f_hi = 0.0, hi, floor - target, median_novelty(hi) - target
    if f_hi < 0:
        raise ValueError(f"contrast {hi} does not reach the target novelty {target}")
    return float(brentq(lambda a: median_novelty(a) - target, lo, hi_b, xtol=1e-3)), floor


def calibrate_person(n: int, rng: np.random.Generator, target: float = 0.0058, people_contrast: float = 1.0,
                     hi: float = 3.0, **scene: Any) -> float:
    """The entering person's contrast at which the median ``n_8`` under Fig. 2's settings is ``target``.

    ``n_8`` is the novelty of the entry frame against the model the filter holds before it
    (``T_d = 0.002``, ``T_I = 0.95``), so the walkers' contrast ``people_contrast`` (which
    decides the updates before the entry) is fixed first.  ``n`` calibration draws (children of
    ``rng``) are made once, up to the entry frame, with
    :func:`~projtrack.scenes.sequences.walking_layers`; ``scene`` holds the other keyword
    arguments of :func:`~projtrack.scenes.sequences.walking_sequence`.
    """
    target = as_real(target, "target", 0.0, 1.0)
    entry = as_int(scene.pop("entry_frame", 8), "entry_frame", minimum=2)
    layers = [walking_layers(r, n_frames=entry, entry_frame=entry, **scene) for r in _children(rng, n)]

    def median_n8(a: float) -> float:
        return float(np.median([process_sequence(lay.frames(people_contrast, a), *FIG2_SETTINGS)[entry - 1].novelty
                                for lay in layers]))
    f0, f1 = median_n8(0.0) - target, median_n8(hi) - target
    if f0 >= 0 or f1 <= 0:
        raise ValueError(f"no person contrast in [0, {hi}] gives the median n_{entry} = {target}")
    return float(brentq(lambda a: median_n8(a) - target, 0.0, hi, xtol=1e-3))


def calibrate_readings(readings: Mapping[str, Mapping[str, Any]], n: int, seed: int,
                       noise_std: float = NOISE_STD, with_n4: bool = True, with_n8: bool = False) -> pd.DataFrame:
    """Calibrate every reading: one exposure for all, then the people's contrast on ``n_2`` (and ``n_4``).

    Every calibration uses the same ``n`` draws, the children of
    ``numpy.random.default_rng(seed)``.  The exposure is calibrated on frame 1 of the default
    scene (frame 1 depends neither on the speed nor on the synchronization).

    Returns
    -------
    pandas.DataFrame
        One row per reading: ``reading``, ``gain``, ``contrast (n_2)``, ``floor`` (median
        novelty of frame 2 without people), with ``with_n4``, ``contrast (n_4)``, and with
        ``with_n8``, ``person (n_8)``: the entering person's contrast
        (:func:`calibrate_person`, printed ``n_8 = 0.0058``) with the walkers at ``contrast (n_2)``.
    """
    seed = as_int(seed, "seed", minimum=0)
    gain = calibrate_gain(n, np.random.default_rng(seed), noise_std=noise_std)
    done: dict[tuple, tuple[float, float]] = {}

    def solve(target: float, j: int, kw: dict[str, Any]) -> tuple[float, float]:
        # frames 1..j depend only on the synchronization of frames 1..j: readings that agree there share it
        sync = kw.get("jitter_frames")
        key = (target, j, tuple(sorted((k, v) for k, v in kw.items() if k != "jitter_frames")),
               None if sync is None else tuple(sorted(f for f in sync if f <= j)))
        if key not in done:
            done[key] = calibrate_contrast(n, np.random.default_rng(seed), target, j, **kw)
        return done[key]

    rows = []
    for name, scene in readings.items():
        kw = dict(scene, gain=gain, noise_std=noise_std)
        a2, floor = solve(0.0018, 2, kw)
        a4 = solve(0.0025, 4, kw)[0] if with_n4 else float("nan")
        a8 = (calibrate_person(n, np.random.default_rng(seed), 0.0058, a2, **kw) if with_n8 else float("nan"))
        rows.append({"reading": name, "gain": gain, "contrast (n_2)": a2, "floor": floor,
                     **({"contrast (n_4)": a4} if with_n4 else {}), **({"person (n_8)": a8} if with_n8 else {})})
    return pd.DataFrame(rows)


def frame2_quiet(n: int, rng: np.random.Generator, **scene: Any) -> tuple[float, float]:
    """Share of ``n`` draws whose frame 2 is not novel against frame 1 (``n_2 <= T_d``), and the median ``n_2``.

    Only the first two frames of each draw are made: with the same ``rng`` these are the
    draws of :func:`reading_draws`.
    """
    nov = np.array([novelty_against_first(walking_sequence(r, n_frames=2, **scene).frames, 2)
                    for r in _children(rng, n)])
    return float(np.mean(nov <= FIG2_SETTINGS[0])), float(np.median(nov))


def ghost_rms(img: Any, background: Any, paths: Any) -> float:
    """RMS of ``img - background`` over the pixels ``paths`` (where people have walked so far)."""
    paths = np.asarray(paths, dtype=bool)
    d = np.asarray(img, dtype=float) - np.asarray(background, dtype=float)
    if d.shape != paths.shape:
        raise ValueError(f"img, background and paths must have one shape, got {d.shape} and {paths.shape}")
    return float(np.sqrt(np.mean(d[paths] ** 2))) if paths.any() else 0.0


def memory_updates(recs: Sequence[FrameRecord], object_masks: Any, all_masks: Any, background: Any,
                   pixel_threshold: float = PIXEL_THRESHOLD) -> float:
    """For how many later updates a moving object's ghost stays visible in the first eigenimage.

    For each frame ``u`` in which the object is present, the pixels it covers at ``u`` and that
    no figure covers afterwards are *left behind*; its ghost after a later frame ``t`` is the
    mean of ``|first eigenimage - background|`` over them.  The memory at ``u`` is the number of
    novel frames (updates) after ``u`` before the ghost first drops to ``T_f`` or below.

    Returns
    -------
    float
        The mean memory over the frames ``u`` that leave pixels behind (``nan`` if none does).
    """
    obj = np.asarray(object_masks, dtype=bool)
    cover = np.asarray(all_masks, dtype=bool)
    if obj.shape != cover.shape or obj.shape[0] != len(recs):
        raise ValueError(f"object_masks and all_masks must have shape ({len(recs)}, H, W), "
                         f"got {obj.shape} and {cover.shape}")
    pixel_threshold = as_real(pixel_threshold, "pixel_threshold", 0.0)
    bg = np.asarray(background, dtype=float)
    later = np.zeros_like(cover)                  # covered by some figure after frame u
    acc = np.zeros(cover.shape[1:], dtype=bool)
    for t in range(len(cover) - 1, 0, -1):
        acc |= cover[t]
        later[t - 1] = acc
    updates = [t for t in range(len(recs)) if recs[t].novel]
    dev = np.abs(np.stack([recs[t].first_eigenimage for t in updates]) - bg)   # (updates, H, W)
    out = []
    for u in range(len(recs) - 1):
        left = obj[u] & ~later[u]
        if not left.any():
            continue
        after = [k for k, t in enumerate(updates) if t > u]
        visible = dev[after][:, left].mean(axis=1) > pixel_threshold
        out.append(int(np.argmin(visible)) if not visible.all() else len(after))
    return float(np.mean(out)) if out else float("nan")


def novel_pixel_quality(recs: Sequence[FrameRecord], masks: Any, start: int) -> float:
    """F1 score of the novel-pixel images against the figures really there, frames ``start`` on.

    Precision is the share of novel pixels that lie on a figure of the current frame (a novel
    pixel elsewhere is background smeared into the novelty data: a ghost of an earlier
    position, or noise); recall, the share of the current figures' pixels marked novel.
    Pooled over the frames.
    """
    m = np.asarray(masks, dtype=bool)
    if m.ndim != 3 or m.shape[0] != len(recs):
        raise ValueError(f"masks must have shape ({len(recs)}, H, W), got {m.shape}")
    start = as_int(start, "start", minimum=2, maximum=len(recs))
    tp = fp = fn = 0
    for r in recs[start - 1:]:
        nov, fig = r.novel_pixels, m[r.frame - 1]
        tp += int(np.sum(nov & fig))
        fp += int(np.sum(nov & ~fig))
        fn += int(np.sum(~nov & fig))
    return 2 * tp / (2 * tp + fp + fn) if tp else 0.0


_GHOST_FRAMES = (10, 20)
#: Higher thresholds than ``T_f`` at which a ghost in the first eigenimage may count as visible
#: (``T_f`` is the paper's threshold for the novel-pixel display, not for the eigenimage itself).
VISIBILITY_THRESHOLDS: tuple[float, ...] = (12.0, 16.0)


def sequence_readings(frames: Any, background: Any, masks: Any, entry: int = 8,
                      person_masks: Any = None, pixel_threshold: float = PIXEL_THRESHOLD
                      ) -> dict[str, Any]:
    """Every quantity the street-scene claims are judged on, for one sequence.

    Parameters
    ----------
    frames : array_like (I, H, W)
    background : array_like (H, W)
        The true background (synthetic) or its estimate (real).
    masks : array_like (I, H, W) bool
        Pixels covered by people in each frame (true or estimated).
    entry : int
        1-based frame in which the person enters.
    person_masks : array_like (I, H, W) bool, optional
        The entering person's pixels (ground truth; without it the memories and the scores
        against the figures are ``nan``).

    Returns
    -------
    dict
        Fig. 2 settings: ``novelty`` (every frame's, an array), ``mean novelty`` (frames 2 on),
        ``n_2``, ``n_4``, ``n_8``, ``order 2-4``
        (:func:`~projtrack.experiments.novelty.order_2_4`), ``entry marked``, ``max kept
        (Fig. 2)``, ``updates (Fig. 2)``; Fig. 3 settings: ``max kept (Fig. 3)``, ``second at 8``
        (one eigenimage at every frame before the entry, two at it), ``updates (Fig. 3)``; the
        visible-ghost areas (:func:`~projtrack.experiments.novelty.ghost_area`) of the first
        eigenimage under both settings and of frame 1 at frames 10 and 20 (and, with the suffix
        ``T_f 12`` or ``T_f 16``, at the :data:`VISIBILITY_THRESHOLDS`); the background error
        (:func:`ghost_rms` on the people's paths) of the first eigenimage under both settings
        there; the memories (:func:`memory_updates`, Fig. 2 settings) of the entering person and
        of the other walkers (also at the :data:`VISIBILITY_THRESHOLDS`); the F1 scores (:func:`novel_pixel_quality`) from the entry on.
    """
    f = as_array(frames, "frames", ndim=3)
    bg = as_array(background, "background", shape=f.shape[1:])
    m = np.asarray(masks, dtype=bool)
    if m.shape != f.shape:
        raise ValueError(f"masks must have shape {f.shape}, got {m.shape}")
    if len(f) < max(_GHOST_FRAMES):
        raise ValueError(f"frames must hold at least {max(_GHOST_FRAMES)} frames (the ghosts are read at frames "
                         f"{_GHOST_FRAMES}), got {len(f)}")
    entry = as_int(entry, "entry", minimum=5, maximum=len(f))
    r2 = process_sequence(f, *FIG2_SETTINGS, pixel_threshold=pixel_threshold)
    r3 = process_sequence(f, *FIG3_SETTINGS, pixel_threshold=pixel_threshold)
    out: dict[str, Any] = {
        "n_2": r2[1].novelty, "n_4": r2[3].novelty, "n_8": r2[entry - 1].novelty,
        "order 2-4": order_2_4(r2), "entry marked": entry_marked(r2, entry),
        "max kept (Fig. 2)": max(r.rank for r in r2), "updates (Fig. 2)": sum(r.novel for r in r2),
        "max kept (Fig. 3)": max(r.rank for r in r3),
        "second at 8": max(r.rank for r in r3[:entry - 1]) == 1 and r3[entry - 1].rank == 2,
        "updates (Fig. 3)": sum(r.novel for r in r3),
        "mean novelty": float(np.mean([r.novelty for r in r2[1:]])),
        "novelty": np.array([r.novelty for r in r2])}
    for j in _GHOST_FRAMES:
        paths = m[:j].any(axis=0)
        area = float(m[:j].sum(axis=(1, 2)).mean())
        for label, img in (("Fig. 3", r3[j - 1].first_eigenimage), ("Fig. 2", r2[j - 1].first_eigenimage),
                           ("frame 1", f[0])):
            out[f"ghost {j}, {label}"] = ghost_area(img, bg, paths, area, pixel_threshold)
        mean_j = f[:j].astype(float).mean(axis=0)   # the trivial baseline: the plain mean of frames 1..j
        out[f"ghost {j}, mean"] = ghost_area(mean_j, bg, paths, area, pixel_threshold)
        for t in VISIBILITY_THRESHOLDS:           # how visible a ghost must be: higher thresholds
            for label, img in (("Fig. 3", r3[j - 1].first_eigenimage), ("frame 1", f[0]), ("mean", mean_j)):
                out[f"ghost {j}, {label}, T_f {t:g}"] = ghost_area(img, bg, paths, area, t)
        for label, recs in (("Fig. 3", r3), ("Fig. 2", r2)):
            out[f"background error {j}, {label}"] = ghost_rms(recs[j - 1].first_eigenimage, bg, paths)
    if person_masks is None:
        out.update({"memory, person": np.nan, "memory, walkers": np.nan, "F1 (Fig. 2)": np.nan,
                    "F1 (Fig. 3)": np.nan, **{f"memory, {who}, T_f {t:g}": np.nan for t in VISIBILITY_THRESHOLDS
                                              for who in ("person", "walkers")}})
    else:
        pm = np.asarray(person_masks, dtype=bool)
        out.update({"memory, person": memory_updates(r2, pm, m, bg, pixel_threshold),
                    "memory, walkers": memory_updates(r2, m & ~pm, m, bg, pixel_threshold),
                    **{f"memory, {who}, T_f {t:g}": memory_updates(r2, mask, m, bg, t)
                       for t in VISIBILITY_THRESHOLDS for who, mask in (("person", pm), ("walkers", m & ~pm))},
                    "F1 (Fig. 2)": novel_pixel_quality(r2, m, entry),
                    "F1 (Fig. 3)": novel_pixel_quality(r3, m, entry)})
    return out


def reading_draw(rng: np.random.Generator, pixel_threshold: float = PIXEL_THRESHOLD,
                 **scene: Any) -> dict[str, Any]:
    """:func:`sequence_readings` of one draw of ``walking_sequence(rng, **scene)`` (ground truth known)."""
    q = walking_sequence(as_rng(rng), **scene)
    return sequence_readings(q.frames, q.background * scene.get("gain", 1.0), q.masks, q.entry_frame,
                             q.foreground_masks, pixel_threshold)


def reading_draws(n_draws: int, rng: np.random.Generator, *, n_jobs: int | None = None,
                  **scene: Any) -> tuple[pd.DataFrame, np.ndarray]:
    """``n_draws`` :func:`reading_draw` runs through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    table : pandas.DataFrame
        One row per draw (index ``draw``), the scalar readings.
    novelty : ndarray (n_draws, n_frames)
        Every frame's novelty (Fig. 2 settings) in every draw.
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    draws = montecarlo.run(reading_draw, n_draws, as_rng(rng), n_jobs=n_jobs, **scene)
    nov = np.array([d.pop("novelty") for d in draws])
    return pd.DataFrame(draws).rename_axis("draw"), nov


def threshold_sweep(n: int, rng: np.random.Generator, thresholds: Sequence[float],
                    information_threshold: float = FIG2_SETTINGS[1], **scene: Any) -> pd.DataFrame:
    """Which frames are novel for several ``T_d`` on ``n`` draws of ``walking_sequence(**scene)``.

    Returns
    -------
    pandas.DataFrame
        Per ``T_d``: the shares of the draws whose frame 2, frame 4 and frame 8 are novel (each
        against the model current at that frame), whose entry is marked
        (:func:`~projtrack.experiments.novelty.entry_marked`), and the mean number of updates
        among frames 2-7.
    """
    seqs = [walking_sequence(r, **scene).frames for r in _children(rng, n)]
    rows = []
    for td in thresholds:
        recs = [process_sequence(f, td, information_threshold) for f in seqs]
        rows.append({"T_d": float(td),
                     **{f"frame {j} novel": float(np.mean([r[j - 1].novel for r in recs])) for j in (2, 4, 8)},
                     "entry marked": float(np.mean([entry_marked(r) for r in recs])),
                     "updates, frames 2-7": float(np.mean([sum(x.novel for x in r[1:7]) for r in recs]))})
    return pd.DataFrame(rows)


def ghost_decay(background: Any, contrasts: Sequence[float], dwell: int = 1, n_frames: int = 12,
                patch: tuple[slice, slice] = (slice(10, 20), slice(10, 20))) -> pd.DataFrame:
    """The ghost of a moving part in the first eigenimage against its closed form ``c d / N``.

    A static ``background`` with a patch changed by ``c`` grey levels in the first ``dwell``
    frames (then gone) is fed, every frame novel (``T_d = 0``) and one eigenimage kept
    (``T_I = 0.95``), to :class:`~projtrack.novelty.NoveltyFilter`.  While the background
    dominates the energy the first eigenimage is close to the mean of the frames used, so the
    patch's ghost after ``N`` updates is about ``c d / N``: it fades like ``1 / N`` (not
    geometrically), and a part is remembered for about ``c d / T_f`` updates in all.

    Returns
    -------
    pandas.DataFrame
        Per contrast and update ``N``: the mean ``|first eigenimage - background|`` over the
        patch and ``c d / N``.
    """
    bg = as_array(background, "background", ndim=2)
    dwell = as_int(dwell, "dwell", minimum=1)
    n_frames = as_int(n_frames, "n_frames", minimum=dwell + 1)
    rows = []
    for c in contrasts:
        c = as_real(c, "contrasts")
        f = NoveltyFilter(0.0, 0.95)
        for t in range(n_frames):
            frame = bg.copy()
            if t < dwell:
                frame[patch] += c
            f.partial_fit(frame)
            e1 = f.weighted_eigenimages()[0]
            rows.append({"contrast": c, "updates N": t + 1, "ghost": float(np.mean(np.abs(e1 - bg)[patch])),
                         "c d / N": abs(c) * min(t + 1, dwell) / (t + 1)})
    return pd.DataFrame(rows)

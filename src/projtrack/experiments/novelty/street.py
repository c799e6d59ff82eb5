"""The street-scene study of Figs. 2-3: the novelty filter on a real and a synthetic sequence.

Each function runs :func:`projtrack.novelty.process_sequence` (or a :class:`NoveltyFilter`)
on a sequence and reads what the paper's Figs. 2-3 and their text claim: which frames are
novel, how many eigenimages are kept, the information fractions of frames 4 and 8, and
whether the first eigenimage forgets the moving people (its *ghost area*).  The synthetic
draws come from :func:`projtrack.scenes.sequences.walking_sequence` and run through
:func:`projtrack.montecarlo.run`.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.novelty import FrameRecord, process_sequence
from projtrack.scenes.sequences import walking_sequence

__all__ = [
    "FIG2_SETTINGS",
    "FIG3_SETTINGS",
    "PIXEL_THRESHOLD",
    "ghost_area",
    "ghost_study",
    "order_2_4",
    "entry_marked",
    "fig2_stats",
    "synthetic_draw",
    "synthetic_draws",
    "record_table",
    "jitter_draw",
    "jitter_sensitivity",
    "novel_pixel_scores",
]

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


def ghost_study(frames: Any, background: Any, people_masks: Any, recs2: Sequence[FrameRecord],
                recs3: Sequence[FrameRecord], at: Sequence[int] = (10, 20),
                pixel_threshold: float = PIXEL_THRESHOLD) -> dict[int, dict[str, float]]:
    """Visible-ghost areas at the frames ``at``: the first eigenimage (both settings) and baselines.

    Parameters
    ----------
    frames : array_like (I, H, W)
    background : array_like (H, W)
        The true (or estimated) background.
    people_masks : array_like (I, H, W) bool
        Pixels covered by people in each frame.
    recs2, recs3 : list of FrameRecord
        :func:`~projtrack.novelty.process_sequence` under the Fig. 2 and Fig. 3 settings.
    at : sequence of int
        1-based frame numbers.

    Returns
    -------
    dict
        ``{j: {"first eigenimage, Fig. 3 settings": area, "first eigenimage, Fig. 2 settings": area,
        "running temporal mean": area, "frame 1": area}}``.
    """
    f = as_array(frames, "frames", ndim=3)
    masks = np.asarray(people_masks, dtype=bool)
    if masks.shape != f.shape:
        raise ValueError(f"people_masks must have shape {f.shape}, got {masks.shape}")
    recs2, recs3 = _records(recs2, "recs2"), _records(recs3, "recs3")
    out = {}
    for j in at:
        j = as_int(j, "at", minimum=1, maximum=min(len(f), len(recs2), len(recs3)))
        paths = masks[:j].any(axis=0)
        area = float(masks[:j].sum(axis=(1, 2)).mean())
        out[j] = {"first eigenimage, Fig. 3 settings": ghost_area(recs3[j - 1].first_eigenimage, background, paths, area, pixel_threshold),
                  "first eigenimage, Fig. 2 settings": ghost_area(recs2[j - 1].first_eigenimage, background, paths, area, pixel_threshold),
                  "running temporal mean": ghost_area(f[:j].mean(axis=0), background, paths, area, pixel_threshold),
                  "frame 1": ghost_area(f[0], background, paths, area, pixel_threshold)}
    return out


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


def fig2_stats(recs: Sequence[FrameRecord], entry: int) -> dict[str, Any]:
    """The Fig. 2 readings of one sequence: novelty and decision at frames 2, 3, 4 and ``entry``.

    Returns
    -------
    dict
        ``n_2``, ``n_4``, ``n_8`` (rounded to 4 digits), the novel flags, ``F_4,1`` (NaN when
        frame 4 is not novel), the rank at frame 4, the updates among frames 2..entry-1, whether
        every frame from ``entry`` on is novel, the largest rank and :func:`order_2_4`.
    """
    recs = _records(recs)
    entry = as_int(entry, "entry", minimum=5, maximum=len(recs))
    r2, r4, r8 = recs[1], recs[3], recs[entry - 1]
    return {"n_2": round(r2.novelty, 4), "frame 2 novel": r2.novel,
            "frame 3 novel": recs[2].novel,
            "n_4": round(r4.novelty, 4), "frame 4 novel": r4.novel,
            "F_4,1": round(float(r4.fractions[0]), 6) if r4.fractions is not None else np.nan,
            "rank at 4": r4.rank,
            "updates, frames 2-7": sum(r.novel for r in recs[1:entry - 1]),
            "n_8": round(r8.novelty, 4), "every frame >= 8 novel": all(r.novel for r in recs[entry - 1:]),
            "max eigenimages kept": max(r.rank for r in recs),
            "paper's order at 2-4": order_2_4(recs)}


def synthetic_draw(rng: np.random.Generator, pixel_threshold: float = PIXEL_THRESHOLD,
                   **scene: Any) -> dict[str, Any]:
    """One synthetic sequence under both settings, with every reading of Figs. 2-3.

    Draws :func:`~projtrack.scenes.sequences.walking_sequence` (``scene`` passes its keyword
    arguments), runs the filter with the Fig. 2 and the Fig. 3 settings and returns
    :func:`fig2_stats`, :func:`entry_marked`, the ranks of Fig. 3, the background RMS ratio of
    the last first eigenimage, whether both settings update on the same frames, the ghost
    areas at frames 10 and 20 (:func:`ghost_study`) and, under ``"novelty"``, the Fig. 2
    novelty of every frame.
    """
    rng = as_rng(rng)
    pixel_threshold = as_real(pixel_threshold, "pixel_threshold", 0.0)
    q = walking_sequence(rng, **scene)
    recs2 = process_sequence(q.frames, *FIG2_SETTINGS, pixel_threshold=pixel_threshold)
    recs3 = process_sequence(q.frames, *FIG3_SETTINGS, pixel_threshold=pixel_threshold)
    e = q.entry_frame
    eig_rms = float(np.sqrt(np.mean((recs3[-1].first_eigenimage - q.background) ** 2)))
    frame_rms = float(np.mean(np.sqrt(np.mean((q.frames.astype(float) - q.background) ** 2, axis=(1, 2)))))
    ghosts = ghost_study(q.frames, q.background, q.masks, recs2, recs3, pixel_threshold=pixel_threshold)
    return {**fig2_stats(recs2, e), "entry marked": entry_marked(recs2, e),
            "max eigenimages kept (Fig. 3)": max(r.rank for r in recs3),
            "max kept before frame 8": max(r.rank for r in recs3[:e - 1]), "kept at frame 8": recs3[e - 1].rank,
            "background RMS ratio at frame 24": round(eig_rms / frame_rms, 3),
            "same updates under both settings": [r.novel for r in recs2] == [r.novel for r in recs3],
            **{f"ghost {j}: {k}": round(v, 3) for j, d in ghosts.items() for k, v in d.items()},
            "novelty": np.array([r.novelty for r in recs2])}


def synthetic_draws(n_draws: int, rng: np.random.Generator, *, n_jobs: int | None = None,
                    **kwargs: Any) -> tuple[pd.DataFrame, np.ndarray]:
    """``n_draws`` independent :func:`synthetic_draw` runs through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    seeds : pandas.DataFrame
        One row per draw (index ``draw``), the readings of :func:`synthetic_draw`.
    novelty : ndarray (n_draws, n_frames)
        The Fig. 2 novelty of every frame of every draw.
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    draws = montecarlo.run(synthetic_draw, n_draws, as_rng(rng), n_jobs=n_jobs, **kwargs)
    nov = np.array([d.pop("novelty") for d in draws])
    return pd.DataFrame(draws).rename_axis("draw"), nov


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


def jitter_draw(rng: np.random.Generator, jitter: float) -> dict[str, Any]:
    """One synthetic sequence with camera jitter ``jitter`` (px) under the Fig. 2 settings.

    Returns ``n_2``, whether frame 2 is quiet, the updates among frames 2-7, whether every
    frame from 8 on is novel, :func:`entry_marked` and :func:`order_2_4`.
    """
    jitter = as_real(jitter, "jitter", 0.0)
    recs = process_sequence(walking_sequence(as_rng(rng), jitter=jitter).frames, *FIG2_SETTINGS)
    return {"n_2": recs[1].novelty, "quiet 2": not recs[1].novel,
            "early": sum(r.novel for r in recs[1:7]), "late": all(r.novel for r in recs[7:]),
            "entry": entry_marked(recs), "order": order_2_4(recs)}


def jitter_sensitivity(n_draws: int, seed: int, jitters: Sequence[float] = (0.0, 0.25, 0.5),
                       *, n_jobs: int | None = None) -> pd.DataFrame:
    """Fig. 2's readings against the camera jitter: ``n_draws`` draws per level (same seeds).

    Every jitter level uses the children of ``numpy.random.default_rng(seed)``, so the levels
    differ by the jitter only (common random numbers).

    Returns
    -------
    pandas.DataFrame
        One row per level: median ``n_2``, fraction of draws with frame 2 not novel, median
        updates among frames 2-7, fractions with every frame >= 8 novel, entry marked, and the
        text's order at frames 2-4.
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    rows = []
    for jitter in jitters:
        d = pd.DataFrame(montecarlo.run(jitter_draw, n_draws, np.random.default_rng(seed),
                                        jitter=jitter, n_jobs=n_jobs))
        rows.append({"jitter (px)": jitter, "median n_2": round(float(d["n_2"].median()), 4),
                     "frame 2 not novel (fraction)": float(d["quiet 2"].mean()),
                     "median updates, frames 2-7": float(d["early"].median()),
                     "every frame >= 8 novel (fraction)": float(d["late"].mean()),
                     "entry marked (fraction)": float(d["entry"].mean()),
                     "frames 2-3 quiet, 4 novel (fraction)": float(d["order"].mean())})
    return pd.DataFrame(rows)


def novel_pixel_scores(recs: Sequence[FrameRecord], masks: Any, foreground_masks: Any,
                       entry: int) -> list[dict[str, float]]:
    """Novel pixels scored against the ground truth, from the entry frame on.

    Parameters
    ----------
    recs : list of FrameRecord
    masks, foreground_masks : array_like (I, H, W) bool
        Pixels covered by any figure, and by the entering person, in each frame.
    entry : int
        1-based entry frame of the person.

    Returns
    -------
    list of dict
        Per frame: ``frame``, ``person pixels detected`` (fraction of the entering person's
        pixels marked novel) and ``false alarms on background`` (fraction of the pixels no
        figure has covered yet that are marked novel).
    """
    recs = _records(recs)
    masks = np.asarray(masks, dtype=bool)
    fgm = np.asarray(foreground_masks, dtype=bool)
    if masks.shape != fgm.shape or masks.shape[0] != len(recs):
        raise ValueError(f"masks and foreground_masks must have shape ({len(recs)}, H, W), "
                         f"got {masks.shape} and {fgm.shape}")
    entry = as_int(entry, "entry", minimum=1, maximum=len(recs))
    covered = np.cumsum(masks, axis=0) > 0
    rows = []
    for rec in recs[entry - 1:]:
        k = rec.frame - 1
        fg = fgm[k]
        rows.append({"frame": rec.frame,
                     "person pixels detected": float(rec.novel_pixels[fg].mean()),
                     "false alarms on background": float(rec.novel_pixels[~covered[k]].mean())})
    return rows

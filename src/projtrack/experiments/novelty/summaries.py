"""Summary tables of the street-scene study: the synthetic draws and the real video side by side.

The per-draw readings come from :func:`~projtrack.experiments.novelty.synthetic_draws`
(one row per draw); the real video's ghost areas from
:func:`~projtrack.experiments.novelty.ghost_study`.  These functions turn them into
the tables and fractions the chapter prints and its scorecard reads, and state the rule by
which a claim counts as seen: on the real video and in at least half of the draws.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_int, as_probability, as_real
from projtrack.novelty import FrameRecord
from projtrack.stable import fmt

from .realvideo import rms_ratio
from .street import _records, ghost_area

__all__ = [
    "quartiles",
    "fractions_text",
    "fig2_fractions",
    "fig2_seed_summary",
    "ghost_table",
    "cleaner_fraction",
    "threshold_sensitivity",
    "draw_verdict",
    "verdict_note",
]

#: Columns of the per-draw table that :func:`fig2_fractions` and :func:`fig2_seed_summary` read.
_FIG2_COLUMNS = ("n_2", "frame 2 novel", "n_4", "frame 4 novel", "F_4,1", "rank at 4",
                 "paper's order at 2-4", "updates, frames 2-7", "every frame >= 8 novel",
                 "entry marked", "n_8", "max eigenimages kept")
#: The images whose ghost areas :func:`~projtrack.experiments.novelty.ghost_study` reports.
_GHOST_IMAGES = ("first eigenimage, Fig. 3 settings", "first eigenimage, Fig. 2 settings",
                 "running temporal mean", "frame 1")


def _seeds(seeds: Any, columns: Sequence[str]) -> pd.DataFrame:
    if not isinstance(seeds, pd.DataFrame):
        raise TypeError("seeds must be a pandas DataFrame (synthetic_draws)")
    if len(seeds) == 0:
        raise ValueError("seeds must have at least one row (draw)")
    missing = [c for c in columns if c not in seeds.columns]
    if missing:
        raise ValueError(f"seeds lacks the columns {missing}")
    return seeds


def quartiles(values: Any, digits: int = 4) -> str:
    """``"median [lower quartile, upper quartile]"`` of ``values`` (NaNs dropped), ``digits`` decimals."""
    digits = as_int(digits, "digits", minimum=0)
    q = pd.Series(np.asarray(values, dtype=float)).dropna().quantile([0.25, 0.5, 0.75])
    spec = f".{digits}f"
    return f"{fmt(q[0.5], spec)} [{fmt(q[0.25], spec)}, {fmt(q[0.75], spec)}]"


def fractions_text(rec: FrameRecord) -> str:
    """A record's information fractions ``F`` as ``"[f1, f2, ...]"`` (6 decimals), or ``"none (not novel)"``."""
    if not isinstance(rec, FrameRecord):
        raise TypeError("rec must be a FrameRecord (process_sequence)")
    if rec.fractions is None:
        return "none (not novel)"
    return "[" + ", ".join(fmt(v, ".6f") for v in rec.fractions) + "]"


def fig2_fractions(seeds: pd.DataFrame) -> dict[str, float]:
    """Fractions of the synthetic draws that show each Fig. 2 claim.

    Parameters
    ----------
    seeds : DataFrame
        One row per draw, as returned by
        :func:`~projtrack.experiments.novelty.synthetic_draws`.

    Returns
    -------
    dict
        ``"frame 2 not novel"``, ``"frame 4 novel, one eigenimage"``, ``"paper's order at 2-4"``
        (frames 2-3 not novel, then 4 novel with one eigenimage), ``"every frame >= 8 novel"``
        and ``"entry marked"``: fractions of the draws.
    """
    s = _seeds(seeds, _FIG2_COLUMNS)
    return {"frame 2 not novel": float((~s["frame 2 novel"]).mean()),
            "frame 4 novel, one eigenimage": float((s["frame 4 novel"] & (s["rank at 4"] == 1)).mean()),
            "paper's order at 2-4": int(s["paper's order at 2-4"].sum()) / len(s),
            "every frame >= 8 novel": float(s["every frame >= 8 novel"].mean()),
            "entry marked": float(s["entry marked"].mean())}


def fig2_seed_summary(seeds: pd.DataFrame) -> pd.DataFrame:
    """The Fig. 2 readings over the synthetic draws next to the paper's values.

    Parameters
    ----------
    seeds : DataFrame
        One row per draw (:func:`~projtrack.experiments.novelty.synthetic_draws`).

    Returns
    -------
    DataFrame
        Indexed by ``quantity``; columns ``"synthetic, N draws"`` (text) and ``"paper"``.
    """
    s = _seeds(seeds, _FIG2_COLUMNS)
    fr = fig2_fractions(s)
    upd = s["updates, frames 2-7"]
    order = fr["paper's order at 2-4"]
    rows = [
        ("frame 2 not novel (fraction of draws)", f"{fr['frame 2 not novel']:.2f}", "yes"),
        ("n_2, median [quartiles]", quartiles(s["n_2"]), "0.0018"),
        ("frame 4 novel, one eigenimage kept (fraction)", f"{fr['frame 4 novel, one eigenimage']:.2f}", "yes"),
        ("frames 2-3 not novel, then frame 4 novel with one eigenimage (fraction)",
         f"{order:.2f}", "yes"),
        ("n_4, median [quartiles]", quartiles(s["n_4"]), "0.0025"),
        (f"F_4,1 where frame 4 is novel ({int(s['frame 4 novel'].sum())} draws), median [quartiles]",
         quartiles(s["F_4,1"], 6), "0.999375"),
        ("updates among frames 2-7, median [range]", f"{upd.median():.1f} [{upd.min()}, {upd.max()}]",
         "none (text) / every few frames"),
        ("every frame from 8 on novel (fraction)", f"{fr['every frame >= 8 novel']:.2f}", "yes"),
        ("entry marked (fraction)", f"{fr['entry marked']:.2f}", "yes"),
        ("n_8, median [quartiles]", quartiles(s["n_8"]), "0.0058"),
        ("max eigenimages kept (largest over draws)", f"{s['max eigenimages kept'].max()}", "1"),
    ]
    return pd.DataFrame(rows, columns=["quantity", f"synthetic, {len(s)} draws", "paper"]).set_index("quantity")


def ghost_table(real_ghosts: Mapping[int, Mapping[str, float]], frames: Any, background: Any,
                recs2: Sequence[FrameRecord], recs3: Sequence[FrameRecord], seeds: pd.DataFrame,
                real_at: Sequence[int] = (10, 20, 24), synthetic_at: Sequence[int] = (10, 20),
                pass_area: float = 0.25) -> pd.DataFrame:
    """Ghost areas of the first eigenimage and its baselines: real video and synthetic draws.

    Parameters
    ----------
    real_ghosts : mapping
        :func:`~projtrack.experiments.novelty.ghost_study` on the real video; must hold
        every frame of ``real_at``.
    frames : array_like (I, H, W)
        The real video.
    background : array_like (H, W)
        Its background estimate.
    recs2, recs3 : list of FrameRecord
        The real video under the Fig. 2 and Fig. 3 settings (the last records give the
        images whose RMS ratio is reported).
    seeds : DataFrame
        Per-draw readings with the columns ``"ghost j: <image>"`` for ``j`` in ``synthetic_at``.
    real_at, synthetic_at : sequence of int
        Frames (1-based) reported for the real video and for the draws.
    pass_area : float
        The pass threshold of the ghost area (a draw passes when its area is at most this at
        every frame of ``synthetic_at``).

    Returns
    -------
    DataFrame
        One row per image (index ``image``): the real ghost areas (2 decimals), the real RMS
        ratio at the last frame (3 decimals), the synthetic median [10-90 %] per frame and the
        fraction of draws that pass.
    """
    f = as_array(frames, "frames", ndim=3)
    recs2, recs3 = _records(recs2, "recs2"), _records(recs3, "recs3")
    pass_area = as_real(pass_area, "pass_area", 0.0)
    real_at = [as_int(j, "real_at", minimum=1) for j in real_at]
    synthetic_at = [as_int(j, "synthetic_at", minimum=1) for j in synthetic_at]
    if not synthetic_at:
        raise ValueError("synthetic_at must name at least one frame")
    missing = [j for j in real_at if j not in real_ghosts]
    if missing:
        raise ValueError(f"real_ghosts lacks the frames {missing}")
    names = list(real_ghosts[real_at[0]]) if real_at else list(_GHOST_IMAGES)
    unknown = [n for n in names if n not in _GHOST_IMAGES]
    if unknown:
        raise ValueError(f"real_ghosts names unknown images {unknown}; known: {list(_GHOST_IMAGES)}")
    _seeds(seeds, [f"ghost {j}: {n}" for j in synthetic_at for n in names])
    last = {"first eigenimage, Fig. 3 settings": recs3[-1].first_eigenimage,
            "first eigenimage, Fig. 2 settings": recs2[-1].first_eigenimage,
            "running temporal mean": f.mean(axis=0), "frame 1": f[0]}
    rows = []
    for name in names:
        col = {j: seeds[f"ghost {j}: {name}"] for j in synthetic_at}
        passes = np.logical_and.reduce([col[j] <= pass_area for j in synthetic_at])
        rows.append({"image": name,
                     **{f"real: ghost area, frame {j}": round(real_ghosts[j][name], 2) for j in real_at},
                     f"real: RMS ratio at {len(f)}": round(rms_ratio(last[name], frames, background), 3),
                     **{f"synthetic: ghost area, frame {j}, median [10-90 %]":
                        f"{col[j].median():.2f} [{col[j].quantile(0.1):.2f}, {col[j].quantile(0.9):.2f}]"
                        for j in synthetic_at},
                     f"synthetic: passes at {' and '.join(map(str, synthetic_at))} (fraction)":
                     float(np.mean(passes))})
    return pd.DataFrame(rows).set_index("image")


def cleaner_fraction(seeds: pd.DataFrame, at: Sequence[int] = (10, 20)) -> tuple[float, int]:
    """Among the draws whose updates differ under the two settings: fraction where Fig. 3's is cleaner.

    Cleaner: the first eigenimage under the Fig. 3 settings has a smaller ghost area than under
    the Fig. 2 settings at every frame of ``at``.

    Returns
    -------
    (fraction, n_differ)
        The fraction (NaN when no draw's updates differ) and the number of such draws.
    """
    at = [as_int(j, "at", minimum=1) for j in at]
    if not at:
        raise ValueError("at must name at least one frame")
    g3, g2 = "first eigenimage, Fig. 3 settings", "first eigenimage, Fig. 2 settings"
    s = _seeds(seeds, ["same updates under both settings",
                       *[f"ghost {j}: {g}" for j in at for g in (g3, g2)]])
    differ = s[~s["same updates under both settings"]]
    cleaner = np.logical_and.reduce([differ[f"ghost {j}: {g3}"] < differ[f"ghost {j}: {g2}"] for j in at])
    return (float(np.mean(cleaner)) if len(differ) else float("nan")), len(differ)


def threshold_sensitivity(images: Mapping[str, Any], background: Any, people_masks: Any,
                          at: Sequence[int] = (10, 20),
                          thresholds: Sequence[float] = (8, 16, 32)) -> pd.DataFrame:
    """Ghost areas for several display thresholds ``T_f``.

    Parameters
    ----------
    images : mapping of str to array_like
        Each value either one image ``(H, W)`` (judged at every frame) or one image per frame
        ``(I, H, W)`` or a list of them (the image of frame ``j`` is item ``j - 1``).
    background : array_like (H, W)
    people_masks : array_like (I, H, W) bool
        Pixels covered by people in each frame.
    at : sequence of int
        1-based frames.
    thresholds : sequence of float
        The ``T_f`` values (grey levels).

    Returns
    -------
    DataFrame
        Indexed by ``T_f``; a column ``"<name>, frame j"`` per frame and image (2 decimals).
    """
    masks = np.asarray(people_masks, dtype=bool)
    if masks.ndim != 3:
        raise ValueError(f"people_masks must be 3-D (frames, H, W), got shape {masks.shape}")
    background = as_array(background, "background", shape=masks.shape[1:])
    if not isinstance(images, Mapping) or not images:
        raise TypeError("images must be a non-empty mapping of name to image(s)")
    at = [as_int(j, "at", minimum=1, maximum=len(masks)) for j in at]
    per_frame = {}
    for name, img in images.items():
        arr = np.asarray(img, dtype=float)
        if arr.ndim == 2:
            per_frame[name] = lambda j, a=arr: a
        elif arr.ndim == 3 and len(arr) >= max(at, default=0):
            per_frame[name] = lambda j, a=arr: a[j - 1]
        else:
            raise ValueError(f"images[{name!r}] must be one image (H, W) or one per frame up to "
                             f"frame {max(at, default=0)}, got shape {arr.shape}")
    thresholds = list(thresholds)
    for t in thresholds:
        as_real(t, "thresholds", 0.0)
    rows = []
    for thr in thresholds:          # the index shows each T_f as given (8, not 8.0)
        row: dict[str, Any] = {"T_f": thr}
        for j in at:
            paths = masks[:j].any(axis=0)
            area = float(masks[:j].sum(axis=(1, 2)).mean())
            for name, img_at in per_frame.items():
                row[f"{name}, frame {j}"] = round(ghost_area(img_at(j), background, paths, area, thr), 2)
        rows.append(row)
    return pd.DataFrame(rows).set_index("T_f")


def draw_verdict(real_ok: bool, fraction: float, min_fraction: float = 0.5) -> str:
    """The chapter's rule: ``"qualitative"`` when seen on the real video and in at least half the draws, else ``"differs"``."""
    fraction = as_probability(fraction, "fraction")
    min_fraction = as_probability(min_fraction, "min_fraction")
    return "qualitative" if bool(real_ok) and fraction >= min_fraction else "differs"


def verdict_note(real_ok: bool, fraction: float, min_fraction: float = 0.5) -> str:
    """Where the claim is seen or fails, in words (the companion of :func:`draw_verdict`)."""
    fraction = as_probability(fraction, "fraction")
    min_fraction = as_probability(min_fraction, "min_fraction")
    fails = ([] if real_ok else ["not on the real video"]) + (
        [] if fraction >= min_fraction else
        ["in none of the draws" if fraction == 0 else f"only in {fraction:.0%} of the draws"])
    return "seen on both stand-ins" if not fails else "not seen: " + ", ".join(fails)


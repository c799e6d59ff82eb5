"""Summaries of the street-scene study: the claims judged over the readings, the verdict rule, its tolerance.

Each claim of Figs. 2-3 is a behaviour of one shown sequence.  It counts as *seen* on a
synthetic reading when it holds in at least half of that reading's draws, and on the real
video when it holds there.  The verdict follows the chapter's rule (CONTRIBUTING, "Resolving
what a paper leaves open", 3): ``qualitative`` when it is seen on at least one plausible
reading (the number itself is not comparable on a stand-in), ``differs`` when it is seen on
none; the table names the readings that decide.  A share of ``N`` draws moves by ``1/N`` when
one draw changes its outcome on another machine (:func:`projtrack.tolerance.share`), so a
reading within one draw of one half is on the edge of the rule, and :func:`verdict` says so.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pandas as pd

from projtrack._validation import as_int, as_probability
from projtrack.tolerance import Tolerance, share

__all__ = ["CLAIMS", "claim_shares", "claim_table", "medians", "real_claims", "real_table", "shares_text",
           "verdict", "share_tolerance"]


def _clean_first(suffix: str = "", image: str = "Fig. 3") -> Callable[[pd.DataFrame], pd.Series]:
    """The first eigenimage (or the baseline ``image``) passes the ghost test at frames 10 and 20 while frame 1 does not."""
    def test(d: pd.DataFrame) -> pd.Series:
        e1 = np.logical_and(d[f"ghost 10, {image}{suffix}"] <= 0.25, d[f"ghost 20, {image}{suffix}"] <= 0.25)
        f1 = np.logical_and(d[f"ghost 10, frame 1{suffix}"] <= 0.25, d[f"ghost 20, frame 1{suffix}"] <= 0.25)
        return e1 & ~f1
    return test


#: Each claim as a test of one row of :func:`~projtrack.experiments.novelty.sequence_readings`.
CLAIMS: dict[str, Callable[[pd.DataFrame], pd.Series]] = {
    "frames 2-3 quiet, 4 novel": lambda d: d["order 2-4"].astype(bool),
    "entry marked": lambda d: d["entry marked"].astype(bool),
    "one eigenimage throughout": lambda d: d["max kept (Fig. 2)"] == 1,
    "at most 3 kept (Fig. 3)": lambda d: d["max kept (Fig. 3)"] <= 3,
    "second from frame 8": lambda d: d["second at 8"].astype(bool),
    "up to 3, second from 8": lambda d: (d["max kept (Fig. 3)"] <= 3) & d["second at 8"].astype(bool),
    "first eigenimage clean": _clean_first(),
    "first eigenimage clean (T_f 12)": _clean_first(", T_f 12"),
    "first eigenimage clean (T_f 16)": _clean_first(", T_f 16"),
    "mean of the frames clean": _clean_first("", "mean"),
    "mean of the frames clean (T_f 12)": _clean_first(", T_f 12", "mean"),
    "mean of the frames clean (T_f 16)": _clean_first(", T_f 16", "mean"),
    "more updates": lambda d: d["updates (Fig. 3)"] > d["updates (Fig. 2)"],
    "cleaner first eigenimage": lambda d: (d["background error 10, Fig. 3"] < d["background error 10, Fig. 2"])
    & (d["background error 20, Fig. 3"] < d["background error 20, Fig. 2"]),
    "better novelty data": lambda d: d["F1 (Fig. 3)"] > d["F1 (Fig. 2)"],
    "person remembered longer": lambda d: d["memory, person"] > d["memory, walkers"],
    "person remembered longer (T_f 12)": lambda d: d["memory, person, T_f 12"] > d["memory, walkers, T_f 12"],
    "person remembered longer (T_f 16)": lambda d: d["memory, person, T_f 16"] > d["memory, walkers, T_f 16"],
}


_NEED_TRUTH = ("better novelty data", "person remembered longer", "person remembered longer (T_f 12)",
               "person remembered longer (T_f 16)")


def claim_shares(draws: pd.DataFrame, claims: Any = None) -> dict[str, float]:
    """The share of the draws (rows of :func:`~projtrack.experiments.novelty.reading_draws`) that show each claim."""
    if not isinstance(draws, pd.DataFrame) or len(draws) == 0:
        raise ValueError("draws must be a non-empty DataFrame (reading_draws)")
    names = list(CLAIMS) if claims is None else list(claims)
    unknown = [c for c in names if c not in CLAIMS]
    if unknown:
        raise ValueError(f"unknown claims {unknown}; known: {list(CLAIMS)}")
    return {c: float(np.mean(CLAIMS[c](draws))) for c in names}


def real_claims(readings: Mapping[str, Any], claims: Any = None) -> dict[str, bool]:
    """Whether one real sequence (a dict of :func:`~projtrack.experiments.novelty.sequence_readings`)
    shows each claim; claims that need ground truth (the memories, the F1 scores) are left out."""
    d = pd.DataFrame([{k: v for k, v in dict(readings).items() if np.ndim(v) == 0}])
    names = [c for c in (CLAIMS if claims is None else claims) if c not in _NEED_TRUTH]
    return {c: bool(CLAIMS[c](d).iloc[0]) for c in names}


def claim_table(shares: Mapping[str, Mapping[str, float]], claims: Any,
                extra: Mapping[str, Mapping[str, Any]] | None = None, readings: Any = None) -> pd.DataFrame:
    """One row per reading: the share of its draws showing each claim, then any ``extra`` columns.

    Parameters
    ----------
    shares : mapping
        Reading -> :func:`claim_shares`.
    claims : sequence of str
        The claims, one column each.
    extra : mapping, optional
        Column name -> (reading -> value), e.g. from :func:`medians`.
    readings : sequence of str, optional
        The readings to show, in order (default: all of ``shares``).
    """
    names = list(shares) if readings is None else list(readings)
    return pd.DataFrame([{"reading": r, **{c: shares[r][c] for c in claims},
                          **{col: vals[r] for col, vals in (extra or {}).items()}} for r in names])


def medians(draws: Mapping[str, pd.DataFrame], columns: Mapping[str, str], readings: Any = None
            ) -> dict[str, dict[str, float]]:
    """Column label -> (reading -> the median over the reading's draws of a column of its draws)."""
    names = list(draws) if readings is None else list(readings)
    return {label: {r: float(draws[r][col].median()) for r in names} for label, col in columns.items()}


def real_table(runs: Mapping[str, Mapping[str, Any]], claims: Any,
               extra: Mapping[str, Mapping[str, Any]] | None = None) -> pd.DataFrame:
    """One row per real video: whether it shows each claim ("yes"/"no"; claims that need ground truth are
    left out, see :func:`real_claims`), then any ``extra`` columns."""
    rows = []
    for name, run in runs.items():
        seen = real_claims(run, claims)
        rows.append({"video": name, **{c: "yes" if seen[c] else "no" for c in claims if c in seen},
                     **{col: vals[name] for col, vals in (extra or {}).items()}})
    return pd.DataFrame(rows)


def shares_text(shares: Mapping[str, float], readings: Any = None) -> str:
    """The shares of several readings as ``"0.700 / 0.300 / ..."`` (three decimals), in reading order."""
    names = list(shares) if readings is None else list(readings)
    return " / ".join(f"{shares[r]:.3f}" for r in names)


def verdict(synthetic: Mapping[str, float], real: Mapping[str, bool] | None = None, n_draws: int = 1,
            min_share: float = 0.5) -> tuple[str, list[str], list[str]]:
    """The chapter's rule over the plausible readings of one claim.

    Parameters
    ----------
    synthetic : mapping
        Reading -> share of its draws showing the claim.
    real : mapping, optional
        Real-video reading -> whether it shows the claim.
    n_draws : int
        Draws per synthetic reading (a share within ``1/n_draws`` of ``min_share`` is on the
        edge: one draw changing its outcome would move it across).
    min_share : float

    Returns
    -------
    (verdict, seen, edge)
        ``"qualitative"`` when the claim is seen on at least one reading, ``"differs"``
        otherwise; the readings where it is seen; and the synthetic readings on the edge whose
        status the verdict depends on (empty when the verdict does not hinge on an edge).
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    min_share = as_probability(min_share, "min_share")
    seen = [k for k, v in synthetic.items() if v >= min_share] + [k for k, v in (real or {}).items() if v]
    eps = 1e-9 / n_draws
    # one draw changing its outcome moves a share by 1 / n_draws: these readings would change status
    near = [k for k, v in synthetic.items() if min_share - 1 / n_draws - eps <= v < min_share + 1 / n_draws - eps]
    firm = [k for k in seen if k not in near]
    edge = [] if firm else [k for k in near]
    return ("qualitative" if seen else "differs"), seen, edge


def share_tolerance(n_draws: int) -> Tolerance:
    """:func:`projtrack.tolerance.share` of the draws of a reading."""
    return share(as_int(n_draws, "n_draws", minimum=1))

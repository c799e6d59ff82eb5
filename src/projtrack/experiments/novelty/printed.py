"""The report's printed numbers of Fig. 2 recomputed from its printed novelties (Eqs. (4)-(10)).

The text prints, for frames 2, 4 and 8, the novelty ``n_i`` and the information fractions
``F_i``.  Two frames with a given novelty and energy ratio (:func:`frame_pair`) fed to a
:class:`~projtrack.novelty.NoveltyFilter` after ``prior`` earlier updates give the fractions
the equations imply (:func:`second_fraction`); :func:`frame4_table` and :func:`frame8_table`
tabulate them for the energy ratios 0.9-1.1 and for the possible numbers of earlier updates.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from projtrack._validation import as_choice, as_int, as_probability, as_real
from projtrack.novelty import METHODS, NoveltyFilter
from projtrack.stable import fmt

__all__ = ["PRINTED_V1", "PRINTED_V2", "frame_pair", "second_fraction", "novelty_from_vip",
           "frame4_table", "frame8_table"]

#: The report's printed ``V_1`` (frame 1's energy) and ``V_2`` (the VIP matrix at frame 2).
PRINTED_V1: float = 73544016.0
PRINTED_V2: np.ndarray = np.array([[36772008.0, 36772052.0], [36772052.0, 36838816.0]])


def frame_pair(n: float, r: float = 1.0, p: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """Frame ``a`` (energy 1e4) and frame ``b`` with ``|b|^2 = r |a|^2`` and novelty ``n`` w.r.t. ``a``.

    Both are vectors of ``p`` pixels built from two orthonormal directions (a fixed draw).
    """
    n = as_probability(n, "n")
    r = as_real(r, "r", 0.0, low_open=True)
    p = as_int(p, "p", minimum=2)
    q, _ = np.linalg.qr(np.random.default_rng(0).standard_normal((p, 2)))
    a, e = 100 * q[:, 0], 100 * q[:, 1]
    return a, np.sqrt(r) * (np.sqrt(1 - n) * a + np.sqrt(n) * e)


def second_fraction(n: float, prior: int, r: float = 1.0, method: str = "qr",
                    information_threshold: float = 0.95) -> tuple[float, np.ndarray]:
    """Feed frame ``a`` ``prior`` times, then ``b`` (:func:`frame_pair`); return ``(n_i, F_i)``.

    ``n_i`` is the novelty the filter measures for ``b`` (Eq. (7)) and ``F_i`` the information
    fractions of its update (Eq. (10)), with ``T_d = 0`` so that every frame updates.
    """
    prior = as_int(prior, "prior", minimum=1)
    method = as_choice(method, "method", METHODS)
    a, b = frame_pair(n, r)
    f = NoveltyFilter(0.0, information_threshold, method=method)
    for _ in range(prior):
        f.partial_fit(a)
    got_n, _ = f.partial_fit(b)
    return got_n, f.information_fractions_


def novelty_from_vip(v: Any) -> float:
    """Eq. (7) on a printed 2 x 2 VIP matrix: ``1 - v(1,2)^2 / (v(1,1) v(2,2))`` (not clipped)."""
    v = np.asarray(v, dtype=float)
    if v.shape != (2, 2):
        raise ValueError(f"v must be a 2 x 2 matrix, got shape {v.shape}")
    return 1 - v[0, 1] ** 2 / (v[0, 0] * v[1, 1])


def frame4_table(n4: float = 0.002498, ratios: Sequence[float] = (0.9, 1.0, 1.1)) -> pd.DataFrame:
    """Frame 4 (one earlier update): ``n_4`` and ``F_4`` by both routes for each energy ratio."""
    rows = []
    for method in METHODS:
        for r in ratios:
            got_n, fr = second_fraction(n4, 1, r, method)
            rows.append({"route": method, "energy ratio r": r, "n_4": fmt(got_n, ".6f"),
                         "F_4": f"[{fmt(fr[0], '.6f')}, {fmt(fr[1], '.6f')}]"})
    return pd.DataFrame(rows)


def frame8_table(n8: float = 0.005841, priors: Sequence[int] = (1, 2, 3, 4),
                 ratios: Sequence[float] = (0.9, 1.0, 1.1)) -> pd.DataFrame:
    """Frame 8: ``F_8,2`` for each number of earlier updates ``m`` and energy ratio ``r``.

    Returns
    -------
    pandas.DataFrame
        Index ``earlier updates m``; a column ``novel frames so far`` and one ``F_8,2 at r = ...``
        column per ratio (strings with 6 decimals).
    """
    rows = []
    for prior in priors:
        rows.append({"earlier updates m": prior, "novel frames so far": f"{prior + 1}",
                     **{f"F_8,2 at r = {r}": fmt(second_fraction(n8, prior, r)[1][1], ".6f")
                        for r in ratios}})
    return pd.DataFrame(rows).set_index("earlier updates m")

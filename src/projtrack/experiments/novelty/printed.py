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
    """Frame 4 (one earlier update): the measured ``n_4`` and ``F_4`` by both routes for each energy ratio.

    Returns
    -------
    pandas.DataFrame
        Columns ``route``, ``energy ratio r``, ``n_4``, ``F_4,1``, ``F_4,2`` (floats).
    """
    rows = []
    for method in METHODS:
        for r in ratios:
            got_n, fr = second_fraction(n4, 1, r, method)
            rows.append({"route": method, "energy ratio r": float(r), "n_4": got_n,
                         "F_4,1": float(fr[0]), "F_4,2": float(fr[1])})
    return pd.DataFrame(rows)


def frame8_table(n8: float = 0.005841, f8: float = 0.001090, priors: Sequence[int] = (1, 2, 3, 4),
                 ratios: Sequence[float] = (0.9, 1.0, 1.1)) -> pd.DataFrame:
    """Frame 8: ``F_8,2`` from the printed ``n_8`` for each number of earlier updates ``m`` and energy ratio ``r``.

    Returns
    -------
    pandas.DataFrame
        One row per ``m`` (column ``earlier updates m``): ``F_8,2 at r = ...`` for each ratio
        (the library's filter, :func:`second_fraction`) and ``r for the printed F_8,2`` (the
        smallest root of :func:`energy_ratios_needed`, ``nan`` if none).
    """
    rows = []
    for prior in priors:
        need = energy_ratios_needed(n8, f8, prior)
        rows.append({"earlier updates m": int(prior),
                     **{f"F_8,2 at r = {r}": float(second_fraction(n8, prior, r)[1][1]) for r in ratios},
                     "r for the printed F_8,2": need[0] if need else float("nan")})
    return pd.DataFrame(rows)


def second_fraction_closed_form(n: float, prior: int, r: float = 1.0) -> float:
    """``F_{i,2}`` of Eq. (10) in closed form for one eigenimage after ``prior`` equal updates.

    After ``m = prior`` updates with frames of energy ``e`` along one direction, a frame of
    energy ``r e`` and novelty ``n`` gives the bordered VIP matrix
    ``[[m e, sqrt(m r (1 - n)) e], [., r e]] / (m + 1)`` (Eqs. (4)-(5)); its eigenvalues have
    ``F_1 F_2 = m r n / (m + r)^2``, so ``F_2 = (1 - sqrt(1 - 4 m r n / (m + r)^2)) / 2``.
    """
    n = as_probability(n, "n")
    m = as_int(prior, "prior", minimum=1)
    r = as_real(r, "r", 0.0, low_open=True)
    p = m * r * n / (m + r) ** 2
    return float((1 - np.sqrt(1 - 4 * p)) / 2)


def energy_ratios_needed(n: float, f2: float, prior: int) -> list[float]:
    """The frame energy ratios ``r`` at which ``prior`` earlier updates give ``F_{i,2} = f2`` from novelty ``n``.

    Solves :func:`second_fraction_closed_form` for ``r`` (a quadratic: ``F_1 F_2 (m + r)^2 = m r n``);
    returns its positive roots, smallest first (empty when there is none).
    """
    n = as_probability(n, "n", low_open=True)
    f2 = as_probability(f2, "f2", low_open=True)
    m = as_int(prior, "prior", minimum=1)
    q = f2 * (1 - f2)
    # q r^2 + (2 q m - m n) r + q m^2 = 0
    roots = np.roots([q, 2 * q * m - m * n, q * m * m])
    return sorted(float(x.real) for x in roots if abs(x.imag) < 1e-12 and x.real > 0)


def local_change_novelty_bound(p: float, r: float) -> float:
    """The smallest novelty of a frame that differs from the model frame only on a region holding a share ``p`` of its energy.

    With ``a`` the model frame and ``b = b_S + a_R`` (``a = a_S + a_R``, ``|a_S|^2 = p |a|^2``)
    and ``|b|^2 = r |a|^2``, Cauchy-Schwarz on ``a_S . b_S`` gives
    ``n >= 1 - ((1 - p) + sqrt(p (p + r - 1)))^2 / r``, reached when ``b_S`` is parallel to
    ``a_S`` (the region only brightened or darkened).  Defined for ``p >= 1 - r``: a smaller
    region cannot lose that much energy at all (``inf``).
    """
    p = as_probability(p, "p")
    r = as_real(r, "r", 0.0, low_open=True)
    if p + r - 1 < 0:
        return float("inf")
    return float(max(0.0, 1 - ((1 - p) + np.sqrt(p * (p + r - 1))) ** 2 / r))


def min_energy_share(n: float, r: float) -> float:
    """The smallest share ``p`` of the frame's energy a local change must hold to reach energy ratio ``r`` with novelty ``n``.

    Inverts :func:`local_change_novelty_bound` (decreasing in ``p``) by bisection.
    """
    from scipy.optimize import brentq

    n = as_probability(n, "n", low_open=True)
    r = as_real(r, "r", 0.0, low_open=True)
    lo = max(0.0, 1 - r) + 1e-15
    if local_change_novelty_bound(lo, r) <= n:
        return lo
    return float(brentq(lambda p: local_change_novelty_bound(p, r) - n, lo, 1.0, xtol=1e-12))


def local_change_novelty(a: Any, region: Any, r: float, rng: np.random.Generator | None = None) -> float:
    """The novelty of ``b``: ``a`` with ``region`` rescaled (or, with ``rng``, replaced by a random
    pattern) so that ``|b|^2 = r |a|^2`` — the simulation of :func:`local_change_novelty_bound`."""
    a = np.asarray(a, dtype=float).ravel()
    region = np.asarray(region, dtype=bool).ravel()
    if region.shape != a.shape:
        raise ValueError("region must have the shape of a")
    r = as_real(r, "r", 0.0, low_open=True)
    e_s, e = float(a[region] @ a[region]), float(a @ a)
    need = e_s - (1 - r) * e                      # |b_S|^2
    if need < 0:
        raise ValueError("the region holds too little energy to reach the energy ratio r")
    b = a.copy()
    if rng is None:
        b[region] = a[region] * np.sqrt(need / e_s)
    else:
        z = np.abs(np.random.default_rng(rng).standard_normal(int(region.sum())))
        b[region] = z * np.sqrt(need / float(z @ z))
    return float(1 - (a @ b) ** 2 / (e * float(b @ b)))

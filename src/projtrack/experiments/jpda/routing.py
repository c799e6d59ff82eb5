"""Can one chirp route the products of Fig. 5? A check of a schedule's optics (JPDA chapter).

The model of Fig. 5 (:func:`projtrack.jpda.optical_vip_schedule`,
:func:`projtrack.jpda.optical_vip_stage`) sends every product of a stage of inner products to
its detector without collisions and sums the right products by construction: any schedule
built from the XOR rule does. What the architecture adds is a physical constraint (Sec. IV):
at each time the pulsed laser diodes (P1) are imaged onto AO1 (P2), which multiplies them
by the MVM entry it holds, and a *single* linear-FM chirp in AO2 (P3) steers each product to
a detector. A linear chirp has a local frequency linear in position, so at one time it maps
a spot at position ``x`` to the detector at ``a x + b`` with one slope ``a`` (the chirp rate
and the optics, the same at every time) and an offset ``b`` that moves as the chirp travels.

:func:`chirp_routing` checks a schedule against that, for a placement of the diodes and
detectors on lines: at most one product per diode per time slot (a spot sees one AO1 entry
and one frequency at a time), one AO1 entry per slot (the model presents one entry to every
diode), no two products on one detector in a slot, and detector position = ``a`` x diode
position + ``b_slot`` for every product, with one ``a != 0``. :func:`slot_by_diode` builds the
alternative schedule that also has no collisions (one diode per slot) as a baseline, and
:func:`routing_table` runs the checks for schedules and placements side by side.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_int
from projtrack.jpda import mu_words, optical_vip_schedule

__all__ = ["chirp_routing", "slot_by_diode", "routing_table"]


def _schedule(schedule: object) -> np.ndarray:
    sch = np.asarray(schedule)
    if sch.ndim != 2 or sch.shape[1] != 4:
        raise ValueError(f"schedule must be an (n, 4) array of (slot, diode, ao1_cell, detector) rows, "
                         f"got shape {sch.shape}")
    if sch.size and not np.issubdtype(sch.dtype, np.integer):
        raise TypeError(f"schedule must hold integers, got dtype {sch.dtype}")
    if sch.size and sch.min() < 0:
        raise ValueError("schedule entries must be >= 0")
    return sch.astype(np.int64)


def chirp_routing(schedule: object, diode_pos: object, detector_pos: object) -> dict:
    """Check a Fig. 5 schedule against one linear chirp, for given diode and detector positions.

    Parameters
    ----------
    schedule : array_like of int, shape (k, 4)
        Rows ``(slot, diode, ao1_cell, detector)``, as :func:`projtrack.jpda.optical_vip_schedule`.
    diode_pos, detector_pos : array_like of int
        Position on its line of each diode and of each detector (integers: exact arithmetic).

    Returns
    -------
    dict
        ``collisions`` (products sharing a detector in a slot), ``products per diode``
        (the most one diode makes in a slot), ``AO1 entries per slot`` (the most distinct MVM
        entries one slot uses), ``slope`` (the common ``a`` as a Fraction, or None when the
        products do not fit one), ``offsets`` (``{slot: b}``, empty without a slope) and
        ``one chirp`` (all four conditions hold: no collision, one product per diode and one
        entry per slot, and one slope ``a != 0``).
    """
    sch = _schedule(schedule)
    xd = as_array(diode_pos, "diode_pos", ndim=1)
    yd = as_array(detector_pos, "detector_pos", ndim=1)
    if len(sch) and (sch[:, 1].max() >= len(xd) or sch[:, 3].max() >= len(yd)):
        raise ValueError("diode_pos and detector_pos must give a position for every diode and detector "
                         "of the schedule")
    if np.any(xd != np.round(xd)) or np.any(yd != np.round(yd)):
        raise ValueError("positions must be integers")
    collisions = per_diode = per_slot = 0
    slope: Fraction | None = None
    fits = True
    pairs = {}
    for s in np.unique(sch[:, 0]).tolist():
        r = sch[sch[:, 0] == s]
        collisions += len(r) - len(np.unique(r[:, 3]))
        per_diode = max(per_diode, int(np.unique(r[:, 1], return_counts=True)[1].max()))
        per_slot = max(per_slot, len(np.unique(r[:, 2])))
        pairs[s] = sorted({(int(xd[d]), int(yd[e])) for d, e in zip(r[:, 1], r[:, 3])})
    for pts in pairs.values():  # one slope from every slot with two distinct diode positions
        for (x0, y0), (x1, y1) in zip(pts[:-1], pts[1:]):
            if x1 == x0:
                fits = fits and y1 == y0
                continue
            a = Fraction(y1 - y0, x1 - x0)
            if slope is None:
                slope = a
            fits = fits and a == slope
    if slope is None:
        fits = False  # no slot constrains a slope: nothing to check, nothing shown
    offsets = ({s: pts[0][1] - slope * pts[0][0] for s, pts in pairs.items()}
               if fits and slope is not None else {})
    if fits:  # every product on its slot's line (pairs on one line by consecutive slopes)
        fits = all(y == slope * x + offsets[s] for s, pts in pairs.items() for x, y in pts)
    one = bool(fits and slope != 0 and collisions == 0 and per_diode <= 1 and per_slot <= 1)
    return {"collisions": int(collisions), "products per diode": int(per_diode),
            "AO1 entries per slot": int(per_slot), "slope": slope if fits else None,
            "offsets": offsets, "one chirp": one}


def slot_by_diode(schedule: object) -> np.ndarray:
    """The same products scheduled one diode per time slot (slot = diode index).

    It has no collisions either (each diode's products go to distinct detectors), so the
    collision count alone does not tell it from the XOR schedule; a diode then makes several
    products in one slot, which one spot on AO1 and AO2 cannot.
    """
    sch = _schedule(schedule).copy()
    sch[:, 0] = sch[:, 1]
    return sch


def routing_table(m: int, T: int, q: int) -> pd.DataFrame:
    """:func:`chirp_routing` of one Fig. 5 stage for two schedules and two placements.

    Schedules: the model's (:func:`projtrack.jpda.optical_vip_schedule`: slot ``s`` uses MVM
    entry ``p_s``) and :func:`slot_by_diode`. Placements of the diodes (old words) and the
    detectors (new words): by *word value* (position = the MU word read as a binary number,
    ``2^m`` places with gaps) and in *Table II order* (consecutive places in the order of
    :func:`projtrack.jpda.mu_words`). One row per combination, with the checks' results.
    """
    m = as_int(m, "m", minimum=1, maximum=20)
    T = as_int(T, "T", minimum=3)
    q = as_int(q, "q", minimum=1, maximum=T - 2)
    new_w, old_w = mu_words(m, max(0, m - q)), mu_words(m, max(0, m - q - 1))
    xor = optical_vip_schedule(m, T, q)
    rows = []
    for sname, sch in (("one MVM entry per slot (the model)", xor), ("one diode per slot", slot_by_diode(xor))):
        for lname, xd, yd in (("word value", old_w, new_w),
                              ("Table II order", np.arange(len(old_w)), np.arange(len(new_w)))):
            r = chirp_routing(sch, xd, yd)
            rows.append({"schedule": sname, "placement": lname, "collisions": r["collisions"],
                         "products per diode and slot": r["products per diode"],
                         "one slope": "—" if r["slope"] is None else str(r["slope"]),
                         "one chirp can route it": r["one chirp"]})
    return pd.DataFrame(rows)

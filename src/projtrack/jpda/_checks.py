"""Checks of a modified validation matrix shared by the beta methods of this package.

:func:`_check_mvm` validates an MVM (shape ``(m + 1, T)``, finite, nonnegative, row 0 in
``[0, 1)``), :func:`_normalize_columns` rescales its target columns (beta is invariant)
and :func:`_fail_no_event` explains why no feasible event has positive probability.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array


def _check_mvm(mvm: object) -> np.ndarray:
    """``mvm`` as a float ``(m + 1, T)`` array: finite, nonnegative, row 0 in ``[0, 1)``."""
    w = as_array(mvm, "mvm", ndim=2)
    if w.shape[0] < 1:
        raise ValueError("mvm must have a row 0 (holding 1 - P_D,t); got 0 rows")
    if np.any(w < 0):
        raise ValueError("mvm entries must be >= 0 (they are probabilities and densities)")
    if np.any(w[0] >= 1):
        raise ValueError(
            "row 0 of mvm must hold 1 - P_D,t in [0, 1) (P_D,t in (0, 1]); "
            "was row 0 omitted?")
    return w


def _normalize_columns(w: np.ndarray) -> np.ndarray:
    """Scale every target column to maximum 1 (beta is invariant: each event uses one entry per column)."""
    mx = w.max(axis=0) if w.size else np.ones(w.shape[1])
    return w / np.where(mx > 0, mx, 1.0)


def _fail_no_event(w: np.ndarray) -> None:
    dead = np.flatnonzero(w.max(axis=0, initial=0.0) <= 0)
    if dead.size:
        raise ValueError(
            f"target column(s) {dead.tolist()} of mvm have P_D = 1 (row 0 is 0) and no "
            "validated measurement: no feasible event has positive probability")
    raise ValueError("no feasible joint event of mvm has positive probability "
                     "(targets with P_D = 1 compete for too few measurements)")

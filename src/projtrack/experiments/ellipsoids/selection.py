"""How the book picks the draw a figure shows, and times the tracking of Sec. 7.2.

:func:`median_draw` is the rule stated before the draws are made: the (upper) median of a
stated error; :func:`settling_step` is the first time step from which a tracking error
stays small. Both score estimates, so they belong to the experiments, not to the scenes.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_real, only_value_errors

__all__ = ["median_draw", "settling_step"]


def median_draw(errors: object, tiebreak: object = None, pool: object = None) -> int:
    """Index of the draw shown in a figure: the (upper) median of ``errors`` over ``pool``.

    The draws of ``pool`` (all draws by default) are sorted by ``errors`` (stable sort),
    ties broken by ``tiebreak`` when given, and the draw at position ``len(pool) // 2``
    (rank ``len(pool) // 2 + 1`` in increasing order) is returned.

    Parameters
    ----------
    errors : array_like, shape (D,)
        The error (or any score) of each draw; finite.
    tiebreak : array_like, shape (D,), optional
        Secondary key for draws with equal ``errors``.
    pool : array_like of int or bool, optional
        Indices (or a boolean mask of length D) of the draws eligible to be shown.

    Returns
    -------
    int
        The index (into ``errors``) of the draw shown.
    """
    e = np.asarray(errors, dtype=float)
    if e.ndim != 1 or len(e) == 0 or not np.all(np.isfinite(e)):
        raise ValueError(f"errors must be a non-empty 1-D array of finite numbers, got shape {e.shape}")
    keys = [e]
    if tiebreak is not None:
        t = np.asarray(tiebreak, dtype=float)
        if t.shape != e.shape or not np.all(np.isfinite(t)):
            raise ValueError(f"tiebreak must be finite with the shape of errors {e.shape}, got {t.shape}")
        keys = [t, e]
    if pool is None:
        idx = np.arange(len(e))
    else:
        p = np.asarray(pool)
        if p.dtype == bool:
            if p.shape != e.shape:
                raise ValueError(f"a boolean pool must have the shape of errors {e.shape}, got {p.shape}")
            idx = np.nonzero(p)[0]
        elif p.ndim == 1 and p.dtype.kind in "iu":
            if np.any(p < 0) or np.any(p >= len(e)):
                raise ValueError("pool indices must lie in 0..len(errors)-1")
            idx = p
        else:
            raise ValueError("pool must be a 1-D array of indices or a boolean mask")
        if len(idx) == 0:
            raise ValueError("pool is empty")
    order = idx[np.lexsort(tuple(k[idx] for k in keys))]
    return int(order[len(order) // 2])


def settling_step(errors: object, tol: float = 0.1) -> np.ndarray | int:
    """First time step from which the error stays at or below ``tol`` until the end.

    Parameters
    ----------
    errors : array_like, shape (K,) or (D, K)
        Errors over time steps ``0..K-1`` (one row per draw); finite.
    tol : float, default 0.1
        Positive threshold.

    Returns
    -------
    int or numpy.ndarray of int
        ``K`` if the last error exceeds ``tol``, 0 if none does; one value per row for 2-D input.
    """
    e = np.asarray(errors, dtype=float)
    if e.ndim not in (1, 2) or e.shape[-1] == 0 or not np.all(np.isfinite(e)):
        raise ValueError(f"errors must be a finite array of shape (K,) or (D, K), got shape {e.shape}")
    tol = only_value_errors(as_real, tol, "tol", 0, low_open=True, finite=False)
    bad = np.atleast_2d(e) > tol
    K = bad.shape[1]
    out = np.where(bad.any(axis=1), K - np.argmax(bad[:, ::-1], axis=1), 0)
    return int(out[0]) if e.ndim == 1 else out

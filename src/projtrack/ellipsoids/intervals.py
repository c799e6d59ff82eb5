"""Sec. 5.2 of KVW: matrix intervals ``lower <= X <= upper`` in the PSD order."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from projtrack._validation import as_array, as_choice

from .checks import check_symmetric
from .geometry import is_psd

__all__ = ["interval_bounds", "interval_boundary_point", "in_interval"]


def _bound(b: object, n: int, name: str) -> np.ndarray | None:
    if b is None:
        return None
    if np.ndim(b) == 0:
        val = as_array(b, name)
        return float(val) * np.eye(n)
    return check_symmetric(b, name, n)


def interval_bounds(lower: object, upper: object, n: int, tol: float = 1e-9) -> tuple[np.ndarray | None, np.ndarray | None]:
    r"""Validate interval bounds :math:`L \le X \le U` (Section 5.2); a scalar
    :math:`\alpha` means :math:`\alpha I`.

    Parameters
    ----------
    lower, upper : array_like, float or None
        The bounds: ``n x n`` symmetric matrices, scalars (multiples of the identity) or
        None (no bound on that side).
    n : int
        Size of ``X``.
    tol : float, default 1e-9
        Tolerance of the check that ``upper - lower`` is PSD.

    Returns
    -------
    (lower, upper) : (numpy.ndarray or None, numpy.ndarray or None)
        The bounds as ``n x n`` arrays.

    Raises
    ------
    ValueError
        If a bound is not a finite symmetric ``n x n`` matrix or scalar, or ``upper - lower``
        is not PSD.
    """
    L, U = _bound(lower, n, "lower"), _bound(upper, n, "upper")
    if L is not None and U is not None:
        gap = np.linalg.eigvalsh(U - L)[0]
        if gap < -tol * max(1.0, float(np.max(np.abs(U)) + np.max(np.abs(L)))):
            raise ValueError(f"lower must be <= upper in the PSD order (lambda_min(upper - lower) = {gap:.3g})")
    return L, U


def in_interval(X: object, lower: object = None, upper: object = None, tol: float = 1e-8) -> bool:
    r"""True when :math:`L - \mathrm{tol}\, I \le X \le U + \mathrm{tol}\, I` in the PSD
    order.

    Parameters
    ----------
    X : array_like, shape (n, n)
        A symmetric matrix.
    lower, upper : array_like, float or None
        The bounds, as in :func:`interval_bounds`.
    tol : float, default 1e-8
        Tolerance on the smallest eigenvalues of ``X - lower`` and ``upper - X``.

    Returns
    -------
    bool
    """
    Xm = check_symmetric(X)
    L, U = interval_bounds(lower, upper, Xm.shape[0])
    ok = True
    if L is not None:
        ok &= bool(np.linalg.eigvalsh(Xm - L)[0] >= -tol)
    if U is not None:
        ok &= bool(np.linalg.eigvalsh(U - Xm)[0] >= -tol)
    return ok


def interval_boundary_point(lower: object, upper: object, direction: object, side: str = "upper") -> np.ndarray:
    """An element of the matrix interval that touches one of its bounds (Figure 2 of KVW).

    Starting from the bound opposite to ``side``, moves along ``direction`` (a symmetric
    matrix, PSD for ``side="upper"``, so that the path stays above ``lower``) until the
    other bound is reached: the result ``X`` has ``upper - X`` (or ``X - lower``) singular,
    so its ellipse is tangent to the outer (inner) bound ellipse.

    Parameters
    ----------
    lower, upper : array_like
        The interval's bounds (``n x n`` symmetric, ``upper - lower`` PSD).
    direction : array_like, shape (n, n)
        Symmetric direction of the path (PSD for ``side="upper"``).
    side : {"upper", "lower"}
        Which bound the result touches.

    Returns
    -------
    numpy.ndarray, shape (n, n)
    """
    side = as_choice(side, "side", ("upper", "lower"))
    Lm = check_symmetric(lower, "lower")
    n = Lm.shape[0]
    L, U = interval_bounds(Lm, upper, n)
    assert L is not None
    if U is None:
        raise ValueError("upper must be given")
    D = check_symmetric(direction, "direction", n)
    start, gap, sgn = (L, U - L, 1.0) if side == "upper" else (U, U - L, -1.0)
    if not is_psd(D):
        raise ValueError("direction must be PSD")
    # largest t with gap - t D >= 0: t = 1 / lambda_max(gap^{-1/2} D gap^{-1/2})
    lam = scipy.linalg.eigh(D, gap, eigvals_only=True)
    if lam[-1] <= 0:
        raise ValueError("direction never reaches the other bound")
    return start + sgn * D / lam[-1]

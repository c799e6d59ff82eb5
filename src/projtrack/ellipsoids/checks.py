"""Argument checks of the ellipsoid package: symmetric matrices, projections, observation lists.

Also the size helpers of the symmetric-matrix coordinates (``n(n+1)/2``) and the matrix-sequence
checks of the dynamics (Sec. 6 of KVW).
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_int, as_real, only_value_errors

__all__ = ["check_symmetric", "check_orthonormal"]

_SYM_TOL = 1e-9


def check_symmetric(X: object, name: str = "X", n: int | None = None) -> np.ndarray:
    """Return :math:`X` as a float array after checking it is a finite symmetric square
    matrix.

    Parameters
    ----------
    X : array_like
        The matrix.
    name : str
        Name used in error messages.
    n : int, optional
        Required size.

    Raises
    ------
    TypeError, ValueError
        If ``X`` is not numeric, not 2-D square (of size ``n``), not finite or not symmetric
        (relative tolerance 1e-9).
    """
    A = as_array(X, name)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty square 2-D matrix, got shape {A.shape}")
    if n is not None and A.shape[0] != n:
        raise ValueError(f"{name} must be {n} x {n}, got shape {A.shape}")
    scale = max(1.0, float(np.max(np.abs(A))))
    if np.max(np.abs(A - A.T)) > _SYM_TOL * scale:
        raise ValueError(f"{name} must be symmetric (max |{name} - {name}^T| = {np.max(np.abs(A - A.T)):.3g})")
    return (A + A.T) / 2


def check_orthonormal(C: object, name: str = "C", n: int | None = None, tol: float = 1e-8) -> np.ndarray:
    """Return :math:`C` as a 2-D float array after checking its columns are orthonormal.

    A 1-D array is taken as a single column (an ``n x 1`` projection, KVW Sec. 3).

    Parameters
    ----------
    C : array_like, shape (n, m) or (n,)
        The matrix to check.
    name : str, default "C"
        Name used in error messages.
    n : int, optional
        Required number of rows.
    tol : float, default 1e-8
        Largest entry allowed in ``C^T C - I``.

    Returns
    -------
    numpy.ndarray, shape (n, m)

    Raises
    ------
    TypeError, ValueError
        If ``C`` is not numeric/finite, has more columns than rows, has ``n`` rows when
        another ``n`` was required, or ``C^T C`` differs from the identity by more than ``tol``.
    """
    A = as_array(C, name)
    if A.ndim == 1:
        A = A[:, None]
    if A.ndim != 2 or A.shape[1] == 0 or A.shape[1] > A.shape[0]:
        raise ValueError(f"{name} must be an n x m matrix with 1 <= m <= n, got shape {A.shape}")
    if n is not None and A.shape[0] != n:
        raise ValueError(f"{name} must have {n} rows (the dimension of X), got shape {A.shape}")
    err = np.max(np.abs(A.T @ A - np.eye(A.shape[1])))
    if err > tol:
        raise ValueError(f"{name} must have orthonormal columns (max |{name}^T {name} - I| = {err:.3g})")
    return A


def _as_size(value: object, name: str, minimum: int) -> int:
    """A size or count (an int >= ``minimum``); a value of the wrong type is a ValueError too, as documented."""
    return only_value_errors(as_int, value, name, minimum=minimum)


def _as_positive(value: object, name: str) -> float:
    """A finite number > 0; a value of the wrong type is a ValueError too, as documented."""
    return only_value_errors(as_real, value, name, 0.0, low_open=True)


def _dim(n: int) -> int:
    return n * (n + 1) // 2


def _n_from_dim(N: int) -> int:
    n = int(round((np.sqrt(8 * N + 1) - 1) / 2))
    if _dim(n) != N:
        raise ValueError(f"a symmetric-matrix coordinate vector has length n(n+1)/2, got {N}")
    return n


def _matrix_list(items: object, name: str, what: str, single: str, empty: str) -> list:
    """``items`` as a non-empty list; one 2-D array is refused (it would iterate over rows)."""
    if isinstance(items, np.ndarray) and items.ndim == 2:
        if single == "C":
            k, n = items.shape
            raise TypeError(
                f"{name} must be a sequence of {what} matrices, got one 2-D array of shape {items.shape}: "
                f"for {k} projection directions in {n} dimensions pass one unit vector per view, "
                f"e.g. list(directions) (each row becomes a view of one column); for a single "
                f"n x m view pass [C]")
        raise TypeError(f"{name} must be a sequence of {what} matrices, got one 2-D array of shape "
                        f"{items.shape}: pass one matrix per view (list(...) of 1 x 1 values for "
                        f"1-D views, [Y] for a single view)")
    try:
        out = list(items)  # type: ignore[call-overload]
    except TypeError:
        raise TypeError(f"{name} must be a sequence of {what} matrices, got {type(items).__name__}") from None
    if not out:
        raise ValueError(f"{name} must contain at least one {empty}")
    return out


def _check_Cs(Cs: object, n: int | None = None, name: str = "Cs") -> list[np.ndarray]:
    items = _matrix_list(Cs, name, "n x m_i", "C", "projection matrix")
    out = []
    for k, C in enumerate(items):
        Cm = check_orthonormal(C, f"{name}[{k}]", n)
        if n is None:
            n = Cm.shape[0]
        out.append(Cm)
    return out


def _check_Ys(Ys: object, Cs: list[np.ndarray], name: str = "Ys") -> list[np.ndarray]:
    items = _matrix_list(Ys, name, "m_i x m_i", "Y", "observation")
    if len(items) != len(Cs):
        raise ValueError(f"{name} and Cs must have the same length, got {len(items)} and {len(Cs)}")
    out = []
    for k, (Y, C) in enumerate(zip(items, Cs)):
        m = C.shape[1]
        Ym = np.atleast_2d(as_array(Y, f"{name}[{k}]")) if np.ndim(Y) == 0 else Y
        out.append(check_symmetric(Ym, f"{name}[{k}]", m))
    return out


def _rank(A: np.ndarray) -> int:
    return int(np.linalg.matrix_rank(A))


def _seq(M: object, K: int, name: str, n: int, square: bool, symmetric: bool,
         exact: bool = False) -> list[np.ndarray]:
    arr = as_array(M, name)
    if arr.ndim == 2:
        arr = np.broadcast_to(arr, (K,) + arr.shape)
    if exact and arr.ndim == 3 and arr.shape[0] != K:
        raise ValueError(f"{name} must be one {n} x {n} matrix or a sequence of exactly {K} of them "
                         f"(one per transition between the given views), got {arr.shape[0]}")
    if arr.ndim != 3 or arr.shape[0] < K or arr.shape[1:] != (n, n):
        raise ValueError(f"{name} must be an {n} x {n} matrix or a sequence of at least {K} of them, got shape {arr.shape}")
    out = [np.array(a) for a in arr[:K]]
    if symmetric:
        out = [check_symmetric(a, f"{name}[{k}]", n) for k, a in enumerate(out)]
    return out


def _mats(M: object, name: str, n: int) -> np.ndarray:
    """A matrix or a sequence of matrices as a float array; an empty sequence as shape (0, n, n)."""
    if isinstance(M, (list, tuple)) and len(M) == 0:
        return np.zeros((0, n, n))
    return as_array(M, name)

"""Ellipsoids as symmetric matrices: projection, reconstruction and dynamics.

Implements W. C. Karl, G. C. Verghese and A. S. Willsky, "Reconstructing ellipsoids from
projections", CVGIP: Graphical Models and Image Processing 56(2), 1994 (KVW):

* representation (Sec. 2): a positive semidefinite (PSD) matrix ``X`` is the ellipsoid
  ``{z : z^T u <= h(u) = sqrt(u^T X u) for all unit u}`` (eq. 1), equivalently
  ``{z : z^T X^{-1} z <= 1}`` when ``X`` is invertible (eq. 2); axes, orientation,
  boundary points, support function and volume (:func:`axes`, :func:`boundary_points`,
  :func:`support`, :func:`volume`, :func:`conic_points`);
* projection (Sec. 3): ``Y = C^T X C`` (eq. 4, :func:`project`);
* matrix-vector form (Sec. 4): the standard symmetric basis (eq. 9, :func:`symmetric_basis`),
  coordinates ``svec``/``smat`` (eqs. 7-8), the operator ``C~`` of eq. (10)
  (:func:`ctilde`), the Kronecker form of eq. (6) (:func:`kron_operator`) and the stacked
  operator of eq. (14) (:func:`stacked_operator`);
* reconstruction (Sec. 5): least squares via the Moore-Penrose inverse (eqs. 15-18) with
  the rank test of Sec. 5.1, interval-constrained least squares ``lower <= X <= upper``
  (Sec. 5.2) by Algorithm 1 of the Appendix (successive rank-one halfspaces, eqs. 27-30,
  :func:`halfspace_reconstruct`) and by a semidefinite program (cvxpy with Clarabel) as the
  modern reference (:func:`reconstruct`); the sufficient condition (19) for a PSD least
  squares estimate (:func:`condition19`);
* dynamics (Sec. 6): the shaping matrix of eq. (23) (:func:`shaping_matrix`), simulation
  of eq. (20) (:func:`simulate`), the state-space form (21) (:func:`state_space`), the
  observability matrix and batch estimate of eqs. (24)-(25) (:func:`observability_matrix`,
  :func:`batch_estimate`, :func:`is_observable`) and a recursive Kalman estimator built on
  :class:`filterpy.kalman.KalmanFilter` (:func:`kalman_estimate`).

Coordinates: ``svec(X)`` lists the upper triangle of ``X`` row by row, off-diagonal
entries multiplied by ``sqrt(2)``; this is exactly the ordering ``l`` of eq. (9), and it
makes ``svec`` an isometry: ``<A, B> = tr(A^T B) = svec(A) . svec(B)``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import scipy.linalg
import scipy.optimize

__all__ = [
    "RankDeficientWarning", "check_symmetric", "check_orthonormal",
    "svec", "smat", "symmetric_basis", "ctilde", "congruence_operator", "kron_operator",
    "svec_basis_matrix", "stacked_operator", "project",
    "axes", "support", "volume", "boundary_points", "conic_points", "is_psd", "nearest_psd",
    "interval_bounds", "interval_boundary_point", "in_interval",
    "reconstruct", "halfspace_reconstruct", "HalfspaceResult", "sdp_reconstruct", "lsi",
    "condition19", "fit_centered_ellipse",
    "shaping_matrix", "simulate", "state_space", "observability_matrix", "batch_rhs", "batch_estimate_many", "reconstruct_many",
    "batch_estimate", "is_observable", "kalman_estimate", "KalmanResult",
]

_SYM_TOL = 1e-9


class RankDeficientWarning(UserWarning):
    """The stacked operator of eq. (14) (or (25)) does not have full column rank."""


# ---------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------
def _as_float_array(a: object, name: str) -> np.ndarray:
    if isinstance(a, (str, bytes)) or a is None:
        raise TypeError(f"{name} must be an array of numbers, got {type(a).__name__}")
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be an array of real numbers ({exc})") from None
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values")
    return arr


def check_symmetric(X: object, name: str = "X", n: int | None = None) -> np.ndarray:
    """Return ``X`` as a float array after checking it is a finite symmetric square matrix.

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
    A = _as_float_array(X, name)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty square 2-D matrix, got shape {A.shape}")
    if n is not None and A.shape[0] != n:
        raise ValueError(f"{name} must be {n} x {n}, got shape {A.shape}")
    scale = max(1.0, float(np.max(np.abs(A))))
    if np.max(np.abs(A - A.T)) > _SYM_TOL * scale:
        raise ValueError(f"{name} must be symmetric (max |{name} - {name}^T| = {np.max(np.abs(A - A.T)):.3g})")
    return (A + A.T) / 2


def check_orthonormal(C: object, name: str = "C", n: int | None = None, tol: float = 1e-8) -> np.ndarray:
    """Return ``C`` as a 2-D float array after checking its columns are orthonormal.

    A 1-D array is taken as a single column (an ``n x 1`` projection, KVW Sec. 3).

    Raises
    ------
    TypeError, ValueError
        If ``C`` is not numeric/finite, has more columns than rows, has ``n`` rows when
        another ``n`` was required, or ``C^T C`` differs from the identity by more than ``tol``.
    """
    A = _as_float_array(C, name)
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


# ---------------------------------------------------------------------------------------
# Sec. 4: the standard symmetric basis and the operators
# ---------------------------------------------------------------------------------------
def _dim(n: int) -> int:
    return n * (n + 1) // 2


def _n_from_dim(N: int) -> int:
    n = int(round((np.sqrt(8 * N + 1) - 1) / 2))
    if _dim(n) != N:
        raise ValueError(f"a symmetric-matrix coordinate vector has length n(n+1)/2, got {N}")
    return n


def svec(X: object) -> np.ndarray:
    """Coordinates of a symmetric matrix in the standard symmetric basis (eqs. 7 and 9).

    ``(x)_l = <X, M_l>``: the upper triangle row by row, off-diagonal entries times sqrt(2).
    Accepts a stack ``(..., n, n)`` of symmetric matrices.
    """
    A = _as_float_array(X, "X")
    if A.ndim < 2 or A.shape[-1] != A.shape[-2]:
        raise ValueError(f"X must be a square matrix or a stack of them, got shape {A.shape}")
    if np.max(np.abs(A - np.swapaxes(A, -1, -2)), initial=0.0) > _SYM_TOL * max(1.0, float(np.max(np.abs(A), initial=0.0))):
        raise ValueError("X must be symmetric")
    n = A.shape[-1]
    i, j = np.triu_indices(n)
    w = np.where(i == j, 1.0, np.sqrt(2.0))
    return A[..., i, j] * w


def smat(x: object) -> np.ndarray:
    """Inverse of :func:`svec`: the symmetric matrix ``sum_l x_l M_l`` (eq. 9).

    Accepts a stack ``(..., n(n+1)/2)`` of coordinate vectors.
    """
    v = _as_float_array(x, "x")
    if v.ndim < 1:
        raise ValueError("x must be a vector of length n(n+1)/2")
    n = _n_from_dim(v.shape[-1])
    i, j = np.triu_indices(n)
    w = np.where(i == j, 1.0, 1.0 / np.sqrt(2.0))
    out = np.zeros(v.shape[:-1] + (n, n))
    out[..., i, j] = v * w
    out[..., j, i] = v * w
    return out


def symmetric_basis(n: int) -> np.ndarray:
    """The standard symmetric basis ``{M_l^(n)}`` of eq. (9), shape ``(n(n+1)/2, n, n)``."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    return smat(np.eye(_dim(int(n))))


def congruence_operator(A: object) -> np.ndarray:
    """Matrix of the linear map ``X -> A^T X A`` in standard symmetric coordinates.

    ``A`` is any real ``n x m`` matrix; the result is ``m(m+1)/2 x n(n+1)/2`` with entries
    ``<M_i^(m), A^T M_j^(n) A>`` (eq. 10). Used for ``C~`` (orthonormal ``C``) and for the
    dynamics ``A~`` of eq. (21).
    """
    M = _as_float_array(A, "A")
    if M.ndim == 1:
        M = M[:, None]
    if M.ndim != 2 or 0 in M.shape:
        raise ValueError(f"A must be a non-empty 2-D matrix, got shape {M.shape}")
    basis = symmetric_basis(M.shape[0])
    images = np.einsum("ai,lab,bj->lij", M, basis, M)
    return svec(images).T


def ctilde(C: object) -> np.ndarray:
    """The operator ``C~`` of eq. (10): ``svec(C^T X C) = C~ svec(X)`` (eq. 11).

    ``C`` must have orthonormal columns (an ``n x m`` projection, KVW Sec. 3).
    """
    return congruence_operator(check_orthonormal(C))


def svec_basis_matrix(n: int) -> np.ndarray:
    """``n^2 x n(n+1)/2`` matrix ``P`` with ``vec(X) = P svec(X)``: its columns are ``vec(M_l)``.

    The columns are the standard symmetric basis of eq. (9), so ``P`` has orthonormal columns
    and entries ``0``, ``1`` and ``1/sqrt(2)``; ``P^T vec(X) = svec(X)``. It is *not* the
    Magnus-Neudecker duplication matrix ``D_n`` (entries 0 and 1, ``vec(X) = D_n vech(X)``):
    ``P = D_n diag(w)^{-1}`` with ``w = 1`` on the diagonal entries and ``sqrt(2)`` off it.

    Raises
    ------
    ValueError
        If ``n`` is not a positive int.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    B = symmetric_basis(int(n))
    return B.reshape(B.shape[0], -1).T  # row-major vec equals column-major for symmetric M


def kron_operator(C: object) -> np.ndarray:
    """The Kronecker form of eq. (6): ``vec(C^T X C) = (C^T kron C^T) vec(X)``."""
    Cm = check_orthonormal(C)
    return np.kron(Cm.T, Cm.T)


def _check_Cs(Cs: object, n: int | None = None, name: str = "Cs") -> list[np.ndarray]:
    if isinstance(Cs, np.ndarray) and Cs.ndim == 2:
        raise TypeError(f"{name} must be a sequence of n x m_i matrices (wrap a single C in a list)")
    try:
        items = list(Cs)  # type: ignore[arg-type]
    except TypeError:
        raise TypeError(f"{name} must be a sequence of n x m_i matrices, got {type(Cs).__name__}") from None
    if not items:
        raise ValueError(f"{name} must contain at least one projection matrix")
    out = []
    for k, C in enumerate(items):
        Cm = check_orthonormal(C, f"{name}[{k}]", n)
        if n is None:
            n = Cm.shape[0]
        out.append(Cm)
    return out


def stacked_operator(Cs: Sequence[object]) -> np.ndarray:
    """The stacked operator ``C`` of eq. (14): the ``C~_i`` of eq. (10) one above the other."""
    return np.vstack([congruence_operator(C) for C in _check_Cs(Cs)])


def project(X: object, C: object) -> np.ndarray:
    """Orthogonal (silhouette) projection of the ellipsoid ``X`` onto ``range(C)`` (eq. 4).

    Parameters
    ----------
    X : array_like, shape (n, n)
        Symmetric matrix of the ellipsoid (eq. 1).
    C : array_like, shape (n, m) or (n,)
        Orthonormal basis of the projection subspace.

    Returns
    -------
    numpy.ndarray, shape (m, m)
        ``Y = C^T X C``, the matrix of the shadow ellipsoid in the coordinates of ``C``.
    """
    Xm = check_symmetric(X)
    Cm = check_orthonormal(C, "C", Xm.shape[0])
    Y = Cm.T @ Xm @ Cm
    return (Y + Y.T) / 2


# ---------------------------------------------------------------------------------------
# Sec. 2: geometry
# ---------------------------------------------------------------------------------------
def is_psd(X: object, tol: float = 1e-10) -> bool:
    """True when the smallest eigenvalue of the symmetric ``X`` is >= ``-tol * max(1, ||X||)``."""
    Xm = check_symmetric(X)
    return bool(np.linalg.eigvalsh(Xm)[0] >= -tol * max(1.0, float(np.linalg.norm(Xm, 2))))


def nearest_psd(X: object) -> np.ndarray:
    """Frobenius-nearest PSD matrix (negative eigenvalues set to zero)."""
    Xm = check_symmetric(X)
    lam, V = np.linalg.eigh(Xm)
    out = (V * np.clip(lam, 0.0, None)) @ V.T
    return (out + out.T) / 2


def axes(X: object) -> tuple[np.ndarray, np.ndarray]:
    """Semi-axis lengths ``sqrt(lambda_i)`` and axis directions ``v_i`` (KVW Sec. 2).

    Returns ``(lengths, directions)`` sorted by decreasing length; ``directions[:, i]`` is
    the unit vector of the i-th axis.

    Raises
    ------
    ValueError
        If ``X`` is not PSD (then it is not an ellipsoid).
    """
    Xm = check_symmetric(X)
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite to have semi-axes")
    lam, V = np.linalg.eigh(Xm)
    order = np.argsort(lam)[::-1]
    return np.sqrt(np.clip(lam[order], 0.0, None)), V[:, order]


def support(X: object, u: object) -> np.ndarray:
    """Support function ``h(u) = sqrt(u^T X u)`` of eq. (1) for unit vector(s) ``u``.

    ``u`` has shape ``(n,)`` or ``(k, n)``; rows are normalized.
    """
    Xm = check_symmetric(X)
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite for a support function")
    U = _as_float_array(u, "u")
    single = U.ndim == 1
    U = np.atleast_2d(U)
    if U.shape[-1] != Xm.shape[0]:
        raise ValueError(f"u must have {Xm.shape[0]} components, got shape {U.shape}")
    norms = np.linalg.norm(U, axis=1)
    if np.any(norms == 0):
        raise ValueError("u must be non-zero")
    U = U / norms[:, None]
    h = np.sqrt(np.clip(np.einsum("ki,ij,kj->k", U, Xm, U), 0.0, None))
    return h[0] if single else h


def volume(X: object) -> float:
    """Volume of the ellipsoid: ``V_n sqrt(det X)``, ``V_n`` the volume of the unit n-ball."""
    from scipy.special import gamma

    Xm = check_symmetric(X)
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite to have a volume")
    n = Xm.shape[0]
    return float(np.pi ** (n / 2) / gamma(n / 2 + 1) * np.sqrt(max(np.linalg.det(Xm), 0.0)))


def boundary_points(X: object, n_points: int = 200) -> np.ndarray:
    """Boundary of a planar ellipse ``X^{1/2} u(t)`` (eq. 1; a segment if ``X`` is singular).

    For ``n = 3`` returns a grid of surface points ``(k, k, 3)`` with ``k = n_points``.
    """
    Xm = check_symmetric(X)
    if Xm.shape[0] not in (2, 3):
        raise ValueError("boundary_points supports n = 2 (curve) and n = 3 (surface grid)")
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite; use conic_points for indefinite X")
    if not isinstance(n_points, (int, np.integer)) or n_points < 3:
        raise ValueError("n_points must be an int >= 3")
    lam, V = np.linalg.eigh(Xm)
    root = (V * np.sqrt(np.clip(lam, 0, None))) @ V.T
    if Xm.shape[0] == 2:
        t = np.linspace(0.0, 2 * np.pi, n_points)
        return np.stack([np.cos(t), np.sin(t)], axis=1) @ root.T
    th, ph = np.meshgrid(np.linspace(0, np.pi, n_points), np.linspace(0, 2 * np.pi, n_points), indexing="ij")
    U = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    return U @ root.T


def conic_points(X: object, n_points: int = 200, extent: float = 3.0) -> list[np.ndarray]:
    """Curve(s) ``z^T X^{-1} z = 1`` of eq. (2) for an invertible planar ``X`` of any signature.

    A PSD ``X`` gives its ellipse; an indefinite ``X`` (a non-PSD least squares estimate)
    gives the two branches of a hyperbola, which is how KVW draw such estimates (Fig. 9).
    ``extent`` limits the hyperbola parameter so the branches reach about that distance.
    Returns a list of ``(k, 2)`` arrays.
    """
    Xm = check_symmetric(X, n=2)
    lam, V = np.linalg.eigh(Xm)
    if np.any(np.abs(lam) < 1e-12 * max(1.0, float(np.max(np.abs(lam))))):
        raise ValueError("X must be invertible for the conic of eq. (2)")
    if lam[0] > 0:
        return [boundary_points(Xm, n_points)]
    if lam[1] < 0:
        return []  # negative definite: the conic is empty
    a, b = np.sqrt(-lam[0]), np.sqrt(lam[1])  # z1'^2 / -lam0 ... : z2'^2/b^2 - z1'^2/a^2 = 1
    tmax = np.arcsinh(extent / min(a, b))
    t = np.linspace(-tmax, tmax, n_points)
    branches = []
    for sgn in (1.0, -1.0):
        local = np.stack([a * np.sinh(t), sgn * b * np.cosh(t)], axis=1)
        branches.append(local @ V.T)
    return branches


# ---------------------------------------------------------------------------------------
# Sec. 5.2: interval bounds
# ---------------------------------------------------------------------------------------
def _bound(b: object, n: int, name: str) -> np.ndarray | None:
    if b is None:
        return None
    if np.ndim(b) == 0:
        val = _as_float_array(b, name)
        return float(val) * np.eye(n)
    return check_symmetric(b, name, n)


def interval_bounds(lower: object, upper: object, n: int, tol: float = 1e-9) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Validate interval bounds ``lower <= X <= upper`` (Sec. 5.2); scalars mean ``alpha I``.

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
    """True when ``lower - tol <= X <= upper + tol`` in the PSD order."""
    Xm = check_symmetric(X)
    L, U = interval_bounds(lower, upper, Xm.shape[0])
    ok = True
    if L is not None:
        ok &= bool(np.linalg.eigvalsh(Xm - L)[0] >= -tol)
    if U is not None:
        ok &= bool(np.linalg.eigvalsh(U - Xm)[0] >= -tol)
    return ok


def interval_boundary_point(lower: object, upper: object, direction: object, side: str = "upper") -> np.ndarray:
    """An element of the matrix interval that touches one of its bounds (Fig. 2 of KVW).

    Starting from the bound opposite to ``side``, moves along ``direction`` (a symmetric
    matrix, PSD for ``side="upper"``, so that the path stays above ``lower``) until the
    other bound is reached: the result ``X`` has ``upper - X`` (or ``X - lower``) singular,
    so its ellipse is tangent to the outer (inner) bound ellipse.
    """
    if side not in ("upper", "lower"):
        raise ValueError(f"side must be 'upper' or 'lower', got {side!r}")
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


# ---------------------------------------------------------------------------------------
# Sec. 5: reconstruction
# ---------------------------------------------------------------------------------------
def _check_Ys(Ys: object, Cs: list[np.ndarray], name: str = "Ys") -> list[np.ndarray]:
    if isinstance(Ys, np.ndarray) and Ys.ndim == 2:
        raise TypeError(f"{name} must be a sequence of m_i x m_i matrices (wrap a single Y in a list)")
    try:
        items = list(Ys)  # type: ignore[arg-type]
    except TypeError:
        raise TypeError(f"{name} must be a sequence of m_i x m_i matrices, got {type(Ys).__name__}") from None
    if not items:
        raise ValueError(f"{name} must contain at least one observation")
    if len(items) != len(Cs):
        raise ValueError(f"{name} and Cs must have the same length, got {len(items)} and {len(Cs)}")
    out = []
    for k, (Y, C) in enumerate(zip(items, Cs)):
        m = C.shape[1]
        Ym = np.atleast_2d(_as_float_array(Y, f"{name}[{k}]")) if np.ndim(Y) == 0 else Y
        out.append(check_symmetric(Ym, f"{name}[{k}]", m))
    return out


def _rank(A: np.ndarray) -> int:
    return int(np.linalg.matrix_rank(A))


class _LSI:
    """Lawson-Hanson LSI solver for a fixed ``(E, f)``: the QR factorization is computed once."""

    #: relative size below which a constraint row of ``G R^{-1}`` counts as zero
    INFEASIBLE_RTOL = 100 * np.finfo(float).eps
    #: relative violation of the normalized constraints above which they are declared infeasible
    FEASIBILITY_RTOL = 1e-8

    def __init__(self, E: np.ndarray, f: np.ndarray):
        E = np.asarray(E, float)
        f = np.asarray(f, float)
        if E.ndim != 2 or f.shape != (E.shape[0],):
            raise ValueError(f"E must be 2-D and f a vector of length E.shape[0], got {E.shape} and {f.shape}")
        Q, R = np.linalg.qr(E)
        d = np.abs(np.diag(R))
        if E.shape[0] < E.shape[1] or d.min() <= 1e-12 * max(1.0, float(d.max())):
            raise ValueError("E must have full column rank for the LSI reduction")
        # R is small (n(n+1)/2 square): keep its inverse so that each solve is matrix products
        self.Rinv = scipy.linalg.solve_triangular(R, np.eye(R.shape[0]))
        self.x_ls = self.Rinv @ (Q.T @ f)

    def solve(self, G: np.ndarray, h: np.ndarray) -> np.ndarray:
        if G.shape[0] == 0:
            return self.x_ls
        ht = h - G @ self.x_ls
        if np.all(ht <= 0):
            return self.x_ls
        Gt = G @ self.Rinv
        p = Gt.shape[1]
        # LDP (min ||z|| s.t. Gt z >= ht), made scale-free: every constraint row is divided by
        # the norm of its Gt row and the right-hand side by max |ht| (this scales z), so the
        # NNLS below and the infeasibility test do not depend on the scale of E, f, G or h
        gnorm = np.linalg.norm(Gt, axis=1)
        zero = gnorm <= self.INFEASIBLE_RTOL * max(1.0, float(gnorm.max()))
        if np.any(ht[zero] > 0):  # 0 >= ht_i > 0
            raise ValueError("the linear inequality constraints are infeasible")
        Gn, hn = Gt[~zero] / gnorm[~zero, None], ht[~zero] / gnorm[~zero]
        scale = float(np.max(np.abs(hn)))
        Emat = np.vstack([Gn.T, hn[None, :] / scale])
        fvec = np.zeros(p + 1)
        fvec[-1] = 1.0
        u, _ = scipy.optimize.nnls(Emat, fvec, maxiter=50 * Emat.shape[1] + 100)
        r = Emat @ u - fvec
        # Lawson & Hanson: infeasible iff the residual vanishes. Instead of an absolute cutoff
        # on r[-1], take the candidate and check it against the normalized constraints with a
        # relative tolerance
        zs = -r[:-1] / r[-1] if r[-1] != 0 else None
        if zs is None or not np.all(np.isfinite(zs)) or \
                np.max(hn / scale - Gn @ zs) > self.FEASIBILITY_RTOL * (1.0 + np.linalg.norm(zs)):
            raise ValueError("the linear inequality constraints are infeasible")
        z = zs * scale
        return self.x_ls + self.Rinv @ z


def lsi(E: np.ndarray, f: np.ndarray, G: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Least squares with linear inequality constraints: ``min ||E x - f|| s.t. G x >= h``.

    Lawson & Hanson's reduction LSI -> LDP -> NNLS (ch. 23 of "Solving Least Squares
    Problems", the standard method KVW point to for eq. 30), with the NNLS solved by
    :func:`scipy.optimize.nnls`. ``E`` must have full column rank.

    Raises
    ------
    ValueError
        If ``E`` is rank deficient or the constraints are infeasible.
    """
    G = np.asarray(G, float)
    h = np.asarray(h, float)
    return _LSI(E, f).solve(G.reshape(-1, np.shape(E)[1]), h.reshape(-1))


@dataclass
class HalfspaceResult:
    """Outcome of Algorithm 1 (:func:`halfspace_reconstruct`).

    Attributes
    ----------
    X : ndarray
        The estimate ``X(k)`` at termination.
    n_iter : int
        Number of constrained least squares solves (eq. 30) performed.
    converged : bool
        Whether Steps 3-4 found no eigenvalue below ``-tol``.
    normals_lower, normals_upper : list of ndarray
        Unit vectors ``v`` of the rank-one normals ``v v^T`` added for the lower and upper
        bounds (Step 5), in the order they were added.
    history : list of dict
        Per iteration: ``iter``, ``objective``, ``min_eig_lower``, ``min_eig_upper``,
        ``n_cuts``.
    """

    X: np.ndarray
    n_iter: int
    converged: bool
    normals_lower: list = field(default_factory=list)
    normals_upper: list = field(default_factory=list)
    history: list = field(default_factory=list)


def _objective(A: np.ndarray, y: np.ndarray, x: np.ndarray) -> float:
    return float(np.sum((A @ x - y) ** 2))


def halfspace_reconstruct(Ys: Sequence[object], Cs: Sequence[object], lower: object = None, upper: object = None,
                          *, tol: float = 1e-9, max_iter: int = 500, initial_normals: object = None,
                          A: np.ndarray | None = None, y: np.ndarray | None = None) -> HalfspaceResult:
    """Algorithm 1 of the Appendix of KVW: successive rank-one halfspace approximation.

    Solves eq. (27) ``min sum ||Y_i - C_i^T X C_i||_F^2`` subject to ``lower <= X <= upper``
    (eq. 28) by replacing the interval set with the halfspaces (eq. 29) of a growing set of
    rank-one normals ``N = v v^T``: ``<N, X> >= <N, lower>`` and ``<N, X> <= <N, upper>``.
    Each step (eq. 30) is a linear-inequality-constrained least squares problem solved
    exactly by :func:`lsi`; Steps 3-4 add the eigenvectors of ``X(k) - lower`` and
    ``upper - X(k)`` whose eigenvalues are below ``-tol * max(1, ||X(k)||)``.

    Parameters
    ----------
    Ys, Cs : sequences of arrays
        Observations ``Y_i`` (``m_i x m_i``) and projections ``C_i`` (``n x m_i``).
    lower, upper : array_like or float, optional
        Interval bounds (a scalar ``a`` means ``a I``); ``None`` means no bound.
    tol : float
        Relative eigenvalue tolerance of the stopping test.
    max_iter : int
        Maximum number of constrained LS solves; the algorithm is not finite (KVW).
    initial_normals : array_like, optional
        Unit vectors (rows) for Step 1, used for both bounds; default none (so ``X(0)``
        is the unconstrained LS estimate).
    A, y : ndarray, optional
        A ready stacked operator and right-hand side (used by :func:`batch_estimate`);
        then ``Ys``/``Cs`` are ignored and may be ``None``.

    Returns
    -------
    HalfspaceResult
    """
    if A is None:
        Cl = _check_Cs(Cs)
        Yl = _check_Ys(Ys, Cl)
        A = np.vstack([congruence_operator(C) for C in Cl])
        y = np.concatenate([svec(Y) for Y in Yl])
    else:
        A = np.asarray(A, float)
        y = np.asarray(y, float)
    n = _n_from_dim(A.shape[1])
    L, U = interval_bounds(lower, upper, n)
    if not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise ValueError(f"max_iter must be a positive int, got {max_iter!r}")
    if not (isinstance(tol, (int, float)) and tol > 0):
        raise ValueError(f"tol must be a positive float, got {tol!r}")
    if _rank(A) < A.shape[1]:
        raise ValueError(
            f"the stacked operator has rank {_rank(A)} < n(n+1)/2 = {A.shape[1]}: the constrained "
            "problem has no unique solution; use method='sdp' or add observations")
    vl: list[np.ndarray] = []
    vu: list[np.ndarray] = []
    if initial_normals is not None:
        V0 = np.atleast_2d(_as_float_array(initial_normals, "initial_normals"))
        if V0.shape[1] != n:
            raise ValueError(f"initial_normals must have rows of length {n}")
        V0 = V0 / np.linalg.norm(V0, axis=1, keepdims=True)
        if L is not None:
            vl += list(V0)
        if U is not None:
            vu += list(V0)
    history = []
    X = None
    converged = False
    solver = _LSI(A, y)
    G_rows: list[np.ndarray] = []
    h_rows: list[float] = []

    def add_lower(v: np.ndarray) -> None:
        G_rows.append(svec(np.outer(v, v)))
        h_rows.append(float(v @ L @ v))

    def add_upper(v: np.ndarray) -> None:
        G_rows.append(-svec(np.outer(v, v)))
        h_rows.append(-float(v @ U @ v))

    for v in vl:
        add_lower(v)
    for v in vu:
        add_upper(v)
    for it in range(1, max_iter + 1):
        G = np.array(G_rows).reshape(-1, A.shape[1])
        x = solver.solve(G, np.array(h_rows))
        X = smat(x)
        scale = tol * max(1.0, float(np.linalg.norm(X, 2)))
        new_l, new_u = [], []
        rec = {"iter": it, "objective": _objective(A, y, x), "min_eig_lower": np.nan,
               "min_eig_upper": np.nan, "n_cuts": len(vl) + len(vu)}
        if L is not None:
            lam, V = np.linalg.eigh(X - L)
            rec["min_eig_lower"] = float(lam[0])
            new_l = [V[:, j] for j in range(n) if lam[j] < -scale]
        if U is not None:
            lam, V = np.linalg.eigh(U - X)
            rec["min_eig_upper"] = float(lam[0])
            new_u = [V[:, j] for j in range(n) if lam[j] < -scale]
        history.append(rec)
        if not new_l and not new_u:
            converged = True
            break
        for v in new_l:
            vl.append(v)
            add_lower(v)
        for v in new_u:
            vu.append(v)
            add_upper(v)
    assert X is not None
    return HalfspaceResult(X=X, n_iter=len(history), converged=converged, normals_lower=vl,
                           normals_upper=vu, history=history)


def sdp_reconstruct(A: np.ndarray, y: np.ndarray, lower: np.ndarray | None, upper: np.ndarray | None,
                    solver: str = "CLARABEL", info: dict | None = None, **solver_options: object) -> np.ndarray:
    """Interval-constrained least squares ``min ||A svec(X) - y||^2, lower <= X <= upper`` by cvxpy.

    The modern reference for Sec. 5.2 / eq. (27): a semidefinite program solved by
    Clarabel (interior point, default tolerances ~1e-8). SCS at its default tolerance can
    violate the PSD constraints by ~1e-5 (cvxpy issues #262, #1603); pass
    ``solver="SCS", eps=1e-9`` if SCS is wanted.

    If a dict ``info`` is given, it receives ``"setup_time"`` (seconds spent building the
    cvxpy problem and compiling it for the solver) and ``"solve_time"`` (the solver's own
    time as it reports it), so that timings can be given with and without cvxpy's set-up.

    Raises
    ------
    RuntimeError
        If the solver does not report an optimal solution.
    TypeError
        If ``info`` is neither None nor a dict.
    """
    import time

    import cvxpy as cp

    if info is not None and not isinstance(info, dict):
        raise TypeError(f"info must be a dict or None, got {type(info).__name__}")
    t_start = time.perf_counter()

    N = A.shape[1]
    n = _n_from_dim(N)
    X = cp.Variable((n, n), symmetric=True)
    i, j = np.triu_indices(n)
    w = np.where(i == j, 1.0, np.sqrt(2.0))
    x = cp.hstack([w[k] * X[i[k], j[k]] for k in range(N)])
    cons = []
    if lower is not None:
        cons.append(X - lower >> 0)
    if upper is not None:
        cons.append(upper - X >> 0)
    prob = cp.Problem(cp.Minimize(cp.sum_squares(A @ x - y)), cons)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            prob.solve(solver=solver, **solver_options)
        except cp.error.SolverError as exc:
            raise RuntimeError(f"the SDP solver {solver} failed: {exc}") from None
    # an inaccurate solution must not pass silently: anything but OPTIMAL is an error
    if prob.status != cp.OPTIMAL:
        raise RuntimeError(f"the SDP solver {solver} returned status {prob.status!r}; tighten or change the solver")
    for w in caught:  # other warnings (none expected) are passed on to the caller
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if info is not None:
        total = time.perf_counter() - t_start
        solve = prob.solver_stats.solve_time if prob.solver_stats is not None else None
        solve = float(solve) if solve is not None else float("nan")
        info["solve_time"] = solve
        info["setup_time"] = total - solve if np.isfinite(solve) else float("nan")
        info["total_time"] = total
    Xv = np.asarray(X.value, float)
    return (Xv + Xv.T) / 2


def reconstruct(Ys: Sequence[object], Cs: Sequence[object], lower: object = None, upper: object = None,
                method: str = "ls", *, rank_deficient: str = "raise", **options: object) -> np.ndarray:
    """Reconstruct an ellipsoid ``X`` (``n x n``) from its projections ``Y_i = C_i^T X C_i``.

    Parameters
    ----------
    Ys : sequence of (m_i, m_i) arrays
        Observed projections (eq. 16); scalars are accepted for ``m_i = 1``.
    Cs : sequence of (n, m_i) arrays
        Orthonormal bases of the projection subspaces (1-D arrays are single columns).
    lower, upper : array_like or float, optional
        Interval bounds ``lower <= X <= upper`` (Sec. 5.2); a scalar ``a`` means ``a I``.
        ``lower=0`` with no upper is the PSD constraint. Ignored by ``method="ls"`` (which
        raises if bounds are given).
    method : {"ls", "halfspace", "sdp"}
        ``"ls"``: unconstrained least squares ``x = C^+ y`` (eqs. 15, 17-18);
        ``"halfspace"``: Algorithm 1 of the Appendix (see :func:`halfspace_reconstruct`
        for the iteration history); ``"sdp"``: the same problem by cvxpy/Clarabel
        (:func:`sdp_reconstruct`). With no bound the constrained methods equal ``"ls"``.
        The two constrained methods agree to a relative Frobenius distance of 1e-3 and a
        relative objective gap of 1e-6 (tested; typically 1e-5 and 1e-8): Algorithm 1
        stops slightly outside the interval (eigenvalues >= -1e-9 ||X||), the interior
        point solution lies slightly inside it.
    rank_deficient : {"raise", "warn"}
        What ``"ls"`` does when the stacked operator of eq. (14) has rank below
        ``n(n+1)/2`` (Sec. 5.1: no unique solution): raise ``ValueError`` (default) or emit
        :class:`RankDeficientWarning` and return the minimum-norm solution.
    **options
        Passed to :func:`halfspace_reconstruct` (``tol``, ``max_iter``...) or to the cvxpy
        solver (``solver``, solver tolerances).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric estimate (not necessarily PSD for ``"ls"``).
    """
    if method not in ("ls", "halfspace", "sdp"):
        raise ValueError(f"method must be 'ls', 'halfspace' or 'sdp', got {method!r}")
    if rank_deficient not in ("raise", "warn"):
        raise ValueError(f"rank_deficient must be 'raise' or 'warn', got {rank_deficient!r}")
    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    L, U = interval_bounds(lower, upper, n)
    A = np.vstack([congruence_operator(C) for C in Cl])
    y = np.concatenate([svec(Y) for Y in Yl])
    if method == "ls":
        if L is not None or U is not None:
            raise ValueError("method='ls' is unconstrained: use method='halfspace' or 'sdp' with bounds")
        if options:
            raise TypeError(f"method='ls' takes no options, got {sorted(options)}")
        r = _rank(A)
        if r < A.shape[1]:
            msg = (f"the stacked operator of eq. (14) has rank {r} < n(n+1)/2 = {A.shape[1]}: the "
                   "projections do not determine X uniquely (Sec. 5.1 of KVW)")
            if rank_deficient == "raise":
                raise ValueError(msg + "; pass rank_deficient='warn' for the minimum-norm solution")
            warnings.warn(msg + "; returning the minimum-norm solution", RankDeficientWarning, stacklevel=2)
        return smat(np.linalg.pinv(A) @ y)
    if method == "halfspace":
        return halfspace_reconstruct(None, None, L, U, A=A, y=y, **options).X  # type: ignore[arg-type]
    return sdp_reconstruct(A, y, L, U, **options)  # type: ignore[arg-type]


def condition19(Cs: Sequence[object], Ws: Sequence[object], X: object) -> tuple[bool, float, float]:
    """Sufficient condition (19) of KVW for the LS estimate to be PSD.

    ``sigma_min(C)^{-1} sqrt(sum ||W_i||_F^2) <= lambda_min(X)`` with ``C`` the stacked
    operator of eq. (14) and ``W_i`` the perturbations of the observations (eq. 16).

    ``X`` is the true ellipsoid, so it must be PSD. For a *singular* ``X`` (a degenerate
    ellipsoid, ``lambda_min(X) = 0``; eigenvalues within the PSD tolerance of
    :func:`is_psd` below zero are read as 0) the right-hand side is 0 and the condition
    holds only for noise-free data, where the LS estimate is ``X`` itself: any
    perturbation can make the estimate of a degenerate ellipsoid indefinite. When the
    stacked operator is rank deficient (``sigma_min = 0``) ``lhs`` is ``inf`` and the
    condition does not hold.

    Returns
    -------
    (holds, lhs, rhs) : (bool, float, float)

    Raises
    ------
    ValueError
        If ``X`` is not PSD, or ``Cs``/``Ws`` are inconsistent (see :func:`reconstruct`).
    """
    Cl = _check_Cs(Cs)
    Xm = check_symmetric(X, "X", Cl[0].shape[0])
    if not is_psd(Xm):
        raise ValueError("X (the true ellipsoid) must be positive semidefinite for condition (19)")
    Wl = _check_Ys(Ws, Cl, "Ws")
    s = np.linalg.svd(np.vstack([congruence_operator(C) for C in Cl]), compute_uv=False)
    smin = float(s[-1]) if len(s) >= _dim(Xm.shape[0]) else 0.0
    noise = float(np.sqrt(sum(np.sum(W**2) for W in Wl)))
    lhs = np.inf if smin <= 1e-14 else noise / smin
    rhs = max(float(np.linalg.eigvalsh(Xm)[0]), 0.0)
    return bool(lhs <= rhs), float(lhs), rhs


def fit_centered_ellipse(points: object) -> np.ndarray:
    """Fit a centered ellipsoid ``{z : z^T Y^{-1} z <= 1}`` to boundary points (ellipsoid extraction).

    KVW (Sec. 5) assume the projected ellipsoids ``Y_i`` are extracted from the raw data
    first. This is the simplest such step: linear least squares for ``Q = Y^{-1}`` in
    ``p^T Q p = 1`` over the points ``p`` (rows), then ``Y = Q^{-1}``.

    Parameters
    ----------
    points : array_like, shape (k, m)
        At least ``m(m+1)/2`` points spread around the boundary.

    Returns
    -------
    numpy.ndarray, shape (m, m)

    Raises
    ------
    ValueError
        If there are too few points, the points do not determine a conic (collinear
        points, points on fewer than ``m`` lines through the origin...: the design matrix
        of the linear LS problem is rank deficient, relative condition below 1e-10), or
        the fitted conic is not an ellipse.
    """
    P = _as_float_array(points, "points")
    if P.ndim != 2 or P.shape[1] < 1:
        raise ValueError(f"points must be a (k, m) array, got shape {P.shape}")
    m = P.shape[1]
    if P.shape[0] < _dim(m):
        raise ValueError(f"need at least {_dim(m)} points for an ellipse in {m} dimensions, got {P.shape[0]}")
    G = svec(np.einsum("ki,kj->kij", P, P))  # <p p^T, Q> = svec(p p^T) . svec(Q)
    sv = np.linalg.svd(G, compute_uv=False)
    if sv[0] == 0 or sv[-1] <= 1e-10 * sv[0]:
        raise ValueError("points are degenerate (e.g. collinear or at the origin): they do not determine "
                         f"a centered ellipse in {m} dimensions (design matrix rank deficient)")
    q, *_ = np.linalg.lstsq(G, np.ones(P.shape[0]), rcond=None)
    Q = smat(q)
    lam = np.linalg.eigvalsh(Q)
    if lam[0] <= 1e-10 * abs(lam[-1]):
        raise ValueError("the fitted conic is not an ellipse (points too noisy or degenerate, e.g. "
                         "on a line: the fitted Q = Y^{-1} is indefinite or singular)")
    Y = np.linalg.inv(Q)
    return (Y + Y.T) / 2


# ---------------------------------------------------------------------------------------
# Sec. 6: dynamics
# ---------------------------------------------------------------------------------------
def _rot_t(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, s], [-s, c]])


def shaping_matrix(tau: float, alpha: float, psi: float, phi: float) -> np.ndarray:
    """The planar shaping matrix ``A`` of eq. (23).

    ``A = R^T(psi) diag(tau, tau) diag(alpha, 1/alpha) R^T(phi)`` with ``R`` the rotation
    matrix; ``X -> A^T X A`` rotates the ellipse by ``psi``, magnifies it by ``tau``,
    stretches axis 1 by ``alpha`` and axis 2 by ``1/alpha``, then rotates by ``phi``
    (eq. 22 applied through eq. 3).
    """
    vals = {"tau": tau, "alpha": alpha, "psi": psi, "phi": phi}
    for k, v in vals.items():
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not np.isfinite(v):
            raise ValueError(f"{k} must be a finite real number, got {v!r}")
    if alpha == 0:
        raise ValueError("alpha must be non-zero (the stretch is diag(alpha, 1/alpha))")
    return _rot_t(psi) @ (tau * np.eye(2)) @ np.diag([alpha, 1.0 / alpha]) @ _rot_t(phi)


def _seq(M: object, K: int, name: str, n: int, square: bool, symmetric: bool,
         exact: bool = False) -> list[np.ndarray]:
    arr = _as_float_array(M, name)
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
    return _as_float_array(M, name)


def simulate(X0: object, As: object, Bs: object = None, n_steps: int | None = None) -> np.ndarray:
    """Simulate eq. (20): ``X_{k+1} = A_k^T X_k A_k + B_k``; returns ``(n_steps + 1, n, n)``.

    ``As`` (and ``Bs``) are one matrix (constant) or a sequence; ``n_steps`` defaults to
    ``len(As)``. ``Bs=None`` means no drive.
    """
    X = check_symmetric(X0, "X0")
    n = X.shape[0]
    if n_steps is None:
        if np.ndim(As) != 3:
            raise ValueError("n_steps is required when As is a single matrix")
        n_steps = len(As)  # type: ignore[arg-type]
    if not isinstance(n_steps, (int, np.integer)) or n_steps < 0:
        raise ValueError(f"n_steps must be a non-negative int, got {n_steps!r}")
    Al = _seq(As, n_steps, "As", n, True, False) if n_steps else []
    Bl = _seq(np.zeros((n, n)) if Bs is None else Bs, n_steps, "Bs", n, True, True) if n_steps else []
    out = [X]
    for k in range(n_steps):
        X = Al[k].T @ X @ Al[k] + Bl[k]
        out.append((X + X.T) / 2)
    return np.array(out)


def state_space(As: Sequence[np.ndarray], Bs: Sequence[np.ndarray] | None = None) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The vector form (21): ``A~_k`` (matrix of ``X -> A_k^T X A_k``) and ``b_k = svec(B_k)``."""
    At = [congruence_operator(A) for A in As]
    if Bs is None:
        bt = [np.zeros(At[0].shape[0]) for _ in At]
    else:
        bt = [svec(check_symmetric(B, f"Bs[{k}]")) for k, B in enumerate(Bs)]
    return At, bt


def observability_matrix(Cs: Sequence[object], As: Sequence[object]) -> np.ndarray:
    """The batch (observability) matrix of eq. (25): rows ``C~_k A~_{k-1} ... A~_0``.

    ``Cs`` has ``r + 1`` projections (times ``0..r``); ``As`` is one ``n x n`` matrix (a
    constant dynamics) or a sequence of exactly ``r`` matrices ``A_0..A_{r-1}``.

    Raises
    ------
    ValueError
        If ``As`` is a sequence whose length is not ``len(Cs) - 1`` (extra matrices are
        not silently ignored: they would belong to views that were not given).
    """
    Cl = _check_Cs(Cs)
    n = Cl[0].shape[0]
    As_arr = _mats(As, "As", n)
    Al = _seq(As_arr, len(Cl) - 1, "As", n, True, False, exact=True)
    Phi = np.eye(_dim(n))
    rows = []
    for k, C in enumerate(Cl):
        rows.append(congruence_operator(C) @ Phi)
        if k < len(Al):
            Phi = congruence_operator(Al[k]) @ Phi
    return np.vstack(rows)


def batch_rhs(Ys: Sequence[object], Cs: Sequence[object], As: Sequence[object], Bs: Sequence[object] | None = None) -> np.ndarray:
    """The corrected observation vector ``y`` of eq. (25) (known drive removed).

    ``As`` and ``Bs`` are one matrix each (constant) or sequences of exactly
    ``len(Cs) - 1`` matrices (ValueError otherwise).
    """
    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    K = len(Cl)
    Al = _seq(_mats(As, "As", n), K - 1, "As", n, True, False, exact=True)
    Bl = _seq(np.zeros((n, n)) if Bs is None else _mats(Bs, "Bs", n),
              K - 1, "Bs", n, True, True, exact=True)
    forced = np.zeros(_dim(n))  # response at time k to the drive alone, zero initial state
    out = []
    for k, (C, Y) in enumerate(zip(Cl, Yl)):
        out.append(svec(Y) - congruence_operator(C) @ forced)
        if k < len(Al):
            forced = congruence_operator(Al[k]) @ forced + svec(Bl[k])
    return np.concatenate(out)


def is_observable(Cs: Sequence[object], As: Sequence[object]) -> bool:
    """True when the observability matrix of eq. (25) has full column rank ``n(n+1)/2``."""
    O = observability_matrix(Cs, As)
    return _rank(O) == O.shape[1]


def batch_estimate(Ys: Sequence[object], Cs: Sequence[object], As: Sequence[object], Bs: Sequence[object] | None = None,
                   lower: object = None, upper: object = None, method: str = "ls",
                   **options: object) -> np.ndarray:
    """Batch estimate of ``X_0`` from ``Y_0..Y_r`` (eq. 24) and its propagation (eq. 20).

    ``method="ls"`` is ``x_0 = C^+ y`` (Sec. 6.2); ``"halfspace"``/``"sdp"`` impose
    ``lower <= X_0 <= upper``. Raises ``ValueError`` if the system is not observable
    (rank of eq. 25 below ``n(n+1)/2``) and ``method="ls"``.

    Returns
    -------
    numpy.ndarray, shape (r + 1, n, n)
        The estimated states ``X_0 .. X_r``.
    """
    if method not in ("ls", "halfspace", "sdp"):
        raise ValueError(f"method must be 'ls', 'halfspace' or 'sdp', got {method!r}")
    O = observability_matrix(Cs, As)
    y = batch_rhs(Ys, Cs, As, Bs)
    n = _n_from_dim(O.shape[1])
    L, U = interval_bounds(lower, upper, n)
    K = len(list(Cs))
    if method == "ls":
        if L is not None or U is not None:
            raise ValueError("method='ls' is unconstrained: use 'halfspace' or 'sdp' with bounds")
        r = _rank(O)
        if r < O.shape[1]:
            raise ValueError(f"not observable: the observability matrix (eq. 25) has rank {r} < {O.shape[1]}")
        X0 = smat(np.linalg.lstsq(O, y, rcond=None)[0])
    elif method == "halfspace":
        X0 = halfspace_reconstruct(None, None, L, U, A=O, y=y, **options).X  # type: ignore[arg-type]
    else:
        X0 = sdp_reconstruct(O, y, L, U, **options)  # type: ignore[arg-type]
    return simulate(X0, _mats(As, "As", n), None if Bs is None else _mats(Bs, "Bs", n), K - 1)


def batch_estimate_many(Ys: object, Cs: Sequence[object], As: Sequence[object] | object,
                        Bs: Sequence[object] | object | None = None) -> np.ndarray:
    """Unconstrained batch LS estimate (eqs. 24-25) for many data sets at once, propagated by eq. (20).

    The estimate ``x_0 = C^+ (y - forced)`` is linear in the data, so the observability
    matrix, the drive's response and the propagation are computed once and applied to all
    data sets by matrix products (Monte Carlo studies over thousands of noise draws).
    For one data set it equals :func:`batch_estimate` with ``method="ls"``.

    Parameters
    ----------
    Ys : array_like
        The observations of ``D`` data sets: shape ``(D, K, m, m)`` (symmetric ``m x m``
        observations), or ``(D, K)`` when every view is a single direction (``m = 1``).
    Cs : sequence of K arrays (n, m)
        The views (orthonormal columns).
    As : array (n, n) or sequence of K - 1 arrays
        The dynamics ``A_k`` (one matrix: constant).
    Bs : array (n, n), sequence of K - 1 symmetric arrays, or None
        The known drive ``B_k`` (None: no drive).

    Returns
    -------
    numpy.ndarray, shape (D, K, n, n)
        The estimated states ``X_0 .. X_{K-1}`` of every data set.

    Raises
    ------
    ValueError
        If the shapes do not match, the data are not finite, or the system is not
        observable (rank of eq. 25 below ``n(n+1)/2``).
    """
    Cl = _check_Cs(Cs)
    n, m, K = Cl[0].shape[0], Cl[0].shape[1], len(Cl)
    if any(C.shape[1] != m for C in Cl):
        raise ValueError("batch_estimate_many needs views of one size m (all Cs of shape (n, m))")
    Y = _as_float_array(Ys, "Ys")
    if m == 1 and Y.ndim == 2:
        Y = Y[:, :, None, None]
    if Y.ndim != 4 or Y.shape[1:] != (K, m, m):
        raise ValueError(f"Ys must have shape (D, {K}, {m}, {m})" + (f" or (D, {K})" if m == 1 else "")
                         + f", got {np.shape(Ys)}")
    if not np.allclose(Y, np.swapaxes(Y, 2, 3)):
        raise ValueError("every observation in Ys must be symmetric")
    Al = _seq(_mats(As, "As", n), K - 1, "As", n, True, False, exact=True) if K > 1 else []
    Bl = (_seq(np.zeros((n, n)) if Bs is None else _mats(Bs, "Bs", n), K - 1, "Bs", n, True, True, exact=True)
          if K > 1 else [])
    cache: dict[bytes, np.ndarray] = {}

    def op(M: np.ndarray) -> np.ndarray:
        # congruence operators of repeated views and dynamics are computed once
        key = M.tobytes() + bytes(M.shape)
        if key not in cache:
            cache[key] = congruence_operator(M)
        return cache[key]

    # response to the drive alone (zero initial state) and transition matrices Phi_k = A~_{k-1} ... A~_0
    N = _dim(n)
    iu = np.triu_indices(n)
    bscale = np.where(iu[0] == iu[1], 1.0, np.sqrt(2.0))
    forced, Phi = [np.zeros(N)], [np.eye(N)]
    for k in range(K - 1):
        At = op(Al[k])
        forced.append(At @ forced[-1] + Bl[k][iu] * bscale)
        Phi.append(At @ Phi[-1])
    forced_a, Phi_a = np.array(forced), np.array(Phi)
    O = np.vstack([op(C) @ P for C, P in zip(Cl, Phi_a)])  # eq. (25)
    r = _rank(O)
    if r < O.shape[1]:
        raise ValueError(f"not observable: the observability matrix (eq. 25) has rank {r} < {O.shape[1]}")
    iu = np.triu_indices(m)
    scale = np.where(iu[0] == iu[1], 1.0, np.sqrt(2.0))
    y = (Y[:, :, iu[0], iu[1]] * scale).reshape(len(Y), -1)  # svec of every observation, stacked
    off = np.concatenate([op(C) @ f for C, f in zip(Cl, forced_a)])
    x0 = np.linalg.lstsq(O, (y - off).T, rcond=None)[0].T  # (D, N)
    states = np.einsum("kij,dj->dki", Phi_a, x0) + forced_a[None]
    return smat(states.reshape(-1, N)).reshape(len(Y), K, n, n)


def reconstruct_many(Ys: object, Cs: Sequence[object]) -> np.ndarray:
    """Unconstrained LS estimates ``x = C^+ y`` (eq. 15) of many data sets at once.

    The static problem is the dynamic one with ``A = I`` and no drive, so this is
    :func:`batch_estimate_many` at time 0; for one data set it equals :func:`reconstruct`.

    Parameters
    ----------
    Ys : array_like
        Observations of ``D`` data sets, shape ``(D, q, m, m)`` or ``(D, q)`` for ``m = 1``.
    Cs : sequence of q arrays (n, m)
        The views.

    Returns
    -------
    numpy.ndarray, shape (D, n, n)

    Raises
    ------
    ValueError
        If the shapes do not match or the stacked operator (eq. 14) is rank deficient.
    """
    Cl = _check_Cs(Cs)
    return batch_estimate_many(Ys, Cl, np.eye(Cl[0].shape[0]))[:, 0]


@dataclass
class KalmanResult:
    """Output of :func:`kalman_estimate`.

    Attributes
    ----------
    X : ndarray (K, n, n)
        Filtered estimates ``E[X_k | Y_0..Y_k]`` (symmetric, possibly not PSD).
    X_psd : ndarray (K, n, n)
        The same projected onto the PSD cone (negative eigenvalues clipped); the
        projection is for reporting only and is not fed back into the filter.
    P : ndarray (K, N, N)
        Filtered covariances of ``svec(X_k)``.
    n_not_psd : int
        Number of time steps whose filtered estimate was not PSD.
    """

    X: np.ndarray
    X_psd: np.ndarray
    P: np.ndarray
    n_not_psd: int


def kalman_estimate(Ys: Sequence[object], Cs: Sequence[object], As: Sequence[object], Bs: Sequence[object] | None = None,
                    *, x0_mean: object = None, P0: object = 1e4, R: object = 1.0, Q: object = 0.0) -> KalmanResult:
    """Recursive estimate of the dynamic ellipsoid with :class:`filterpy.kalman.KalmanFilter`.

    Runs the Kalman filter on the state-space form (21): state ``x_k = svec(X_k)``,
    transition ``A~_k``, known input ``b_k = svec(B_k)``, measurement matrix ``C~_k``.
    With ``Q = 0`` and a diffuse prior (large ``P0``) the filtered estimate at time ``k``
    tends to the batch LS estimate of eq. (24) from ``Y_0..Y_k``, propagated to ``k``.

    The filter's estimate is a symmetric matrix that need not be PSD (the Kalman update is
    unconstrained, Sec. 6.2 of KVW); :class:`KalmanResult` reports how often and gives the
    Frobenius-nearest PSD matrices (the ad hoc projection KVW mention) alongside.

    Parameters
    ----------
    x0_mean : array_like (n, n), optional
        Prior mean of ``X_0``; default zero.
    P0, R, Q : float or array_like
        Prior covariance of ``svec(X_0)``, measurement noise covariance of ``svec(W_k)``
        and process noise covariance; scalars mean multiples of the identity.
    """
    from filterpy.kalman import KalmanFilter

    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    N = _dim(n)
    K = len(Cl)
    Al = _seq(_mats(As, "As", n), K - 1, "As", n, True, False, exact=True)
    Bl = _seq(np.zeros((n, n)) if Bs is None else _mats(Bs, "Bs", n),
              K - 1, "Bs", n, True, True, exact=True)
    m = Cl[0].shape[1]
    if any(C.shape[1] != m for C in Cl):
        raise ValueError("kalman_estimate needs projections of one dimension m for all times")
    M = _dim(m)

    def cov(v: object, d: int, name: str) -> np.ndarray:
        a = _as_float_array(v, name)
        if a.ndim == 0:
            if a < 0:
                raise ValueError(f"{name} must be non-negative")
            return float(a) * np.eye(d)
        return check_symmetric(a, name, d)

    kf = KalmanFilter(dim_x=N, dim_z=M, dim_u=N)
    kf.x = np.zeros((N, 1)) if x0_mean is None else svec(check_symmetric(x0_mean, "x0_mean", n))[:, None]
    kf.P = cov(P0, N, "P0")
    kf.R = cov(R, M, "R")
    kf.Q = cov(Q, N, "Q")
    kf.B = np.eye(N)
    xs, Ps = [], []
    for k in range(K):
        if k > 0:
            kf.F = congruence_operator(Al[k - 1])
            kf.predict(u=svec(Bl[k - 1])[:, None])
        kf.H = congruence_operator(Cl[k])
        kf.update(svec(Yl[k])[:, None])
        xs.append(kf.x[:, 0].copy())
        Ps.append(kf.P.copy())
    X = smat(np.array(xs))
    X_psd = np.array([nearest_psd(Xk) for Xk in X])
    n_not = int(sum(not is_psd(Xk) for Xk in X))
    return KalmanResult(X=X, X_psd=X_psd, P=np.array(Ps), n_not_psd=n_not)

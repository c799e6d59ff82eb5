"""Sec. 2 of KVW: axes, support function, volume, boundary points and the PSD cone."""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array

from .checks import _as_size, check_symmetric

__all__ = ["axes", "support", "volume", "boundary_points", "conic_points", "is_psd", "nearest_psd"]


def is_psd(X: object, tol: float = 1e-10) -> bool:
    r"""True when the smallest eigenvalue of the symmetric :math:`X` is at least
    :math:`-\mathrm{tol} \max(1, \|X\|)`.

    Parameters
    ----------
    X : array_like, shape (n, n)
        A symmetric matrix.
    tol : float, default 1e-10
        Relative tolerance on the smallest eigenvalue (:math:`\|X\|` is the spectral norm).

    Returns
    -------
    bool
    """
    Xm = check_symmetric(X)
    return bool(np.linalg.eigvalsh(Xm)[0] >= -tol * max(1.0, float(np.linalg.norm(Xm, 2))))


def nearest_psd(X: object) -> np.ndarray:
    """Frobenius-nearest PSD matrix (negative eigenvalues set to zero).

    Parameters
    ----------
    X : array_like, shape (n, n)
        A symmetric matrix, e.g. an indefinite least-squares estimate.

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric PSD matrix closest to ``X`` in the Frobenius norm.
    """
    Xm = check_symmetric(X)
    lam, V = np.linalg.eigh(Xm)
    out = (V * np.clip(lam, 0.0, None)) @ V.T
    return (out + out.T) / 2


def axes(X: object) -> tuple[np.ndarray, np.ndarray]:
    r"""Semi-axis lengths :math:`\sqrt{\lambda_i}` and axis directions :math:`v_i` (KVW
    Section 2).

    Parameters
    ----------
    X : array_like, shape (n, n)
        The ellipsoid's symmetric PSD matrix.

    Returns
    -------
    lengths : numpy.ndarray, shape (n,)
        Semi-axis lengths, decreasing.
    directions : numpy.ndarray, shape (n, n)
        ``directions[:, i]`` is the unit vector of the i-th axis.

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
    r"""Support function :math:`h(u) = \sqrt{u^T X u}` of equation (1) for unit vector(s)
    :math:`u`.

    Parameters
    ----------
    X : array_like, shape (n, n)
        The ellipsoid's symmetric PSD matrix.
    u : array_like, shape (n,) or (k, n)
        Direction(s), non-zero; rows are normalized.

    Returns
    -------
    float or numpy.ndarray, shape (k,)
        :math:`h(u)`, the largest :math:`z^T u` over the ellipsoid (a float for one
        direction).
    """
    Xm = check_symmetric(X)
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite for a support function")
    U = as_array(u, "u")
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
    r"""Volume of the ellipsoid: :math:`V_n \sqrt{\det X}`, :math:`V_n` the volume of the
    unit n-ball.

    Parameters
    ----------
    X : array_like, shape (n, n)
        The ellipsoid's symmetric PSD matrix.

    Returns
    -------
    float
        Its volume (area for :math:`n = 2`); 0 for a degenerate ellipsoid.
    """
    from scipy.special import gamma

    Xm = check_symmetric(X)
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite to have a volume")
    n = Xm.shape[0]
    return float(np.pi ** (n / 2) / gamma(n / 2 + 1) * np.sqrt(max(np.linalg.det(Xm), 0.0)))


def boundary_points(X: object, n_points: int = 200) -> np.ndarray:
    """Boundary of a planar ellipse, :math:`X^{1/2} u(t)` (equation 1; a segment if
    :math:`X` is singular).

    Parameters
    ----------
    X : array_like, shape (2, 2) or (3, 3)
        The ellipsoid's symmetric PSD matrix.
    n_points : int, default 200
        Points along the curve (``n = 2``) or per side of the surface grid (``n = 3``).

    Returns
    -------
    numpy.ndarray, shape (n_points, 2) or (n_points, n_points, 3)
        The closed boundary curve, or a grid of surface points for ``n = 3``.
    """
    Xm = check_symmetric(X)
    if Xm.shape[0] not in (2, 3):
        raise ValueError("boundary_points supports n = 2 (curve) and n = 3 (surface grid)")
    if not is_psd(Xm):
        raise ValueError("X must be positive semidefinite; use conic_points for indefinite X")
    n_points = _as_size(n_points, "n_points", 3)
    lam, V = np.linalg.eigh(Xm)
    root = (V * np.sqrt(np.clip(lam, 0, None))) @ V.T
    if Xm.shape[0] == 2:
        t = np.linspace(0.0, 2 * np.pi, n_points)
        return np.stack([np.cos(t), np.sin(t)], axis=1) @ root.T
    th, ph = np.meshgrid(np.linspace(0, np.pi, n_points), np.linspace(0, 2 * np.pi, n_points), indexing="ij")
    U = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    return U @ root.T


def conic_points(X: object, n_points: int = 200, extent: float = 3.0) -> list[np.ndarray]:
    """Curve(s) :math:`z^T X^{-1} z = 1` of equation (2) for an invertible planar :math:`X`
    of any signature.

    A PSD ``X`` gives its ellipse; an indefinite ``X`` (a non-PSD least squares estimate)
    gives the two branches of a hyperbola, which is how KVW draw such estimates (Fig. 9).
    ``extent`` limits the hyperbola parameter so the branches reach about that distance.
    Returns a list of ``(k, 2)`` arrays.

    Parameters
    ----------
    X : array_like, shape (2, 2)
        An invertible symmetric matrix.
    n_points : int, default 200
        Points per curve.
    extent : float, default 3
        Reach of the hyperbola's branches (indefinite ``X``).

    Returns
    -------
    list of numpy.ndarray, shape (k, 2)
        One curve for an ellipse, two branches for a hyperbola, none for a negative
        definite ``X``.
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

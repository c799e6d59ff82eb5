"""Sec. 3-4 of KVW: the standard symmetric basis, ``svec``/``smat`` and the projection operators."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack._validation import as_array

from .checks import _SYM_TOL, _as_size, _check_Cs, _dim, _n_from_dim, check_orthonormal, check_symmetric

__all__ = ["svec", "smat", "symmetric_basis", "ctilde", "congruence_operator", "kron_operator",
           "svec_basis_matrix", "stacked_operator", "project"]


def svec(X: object) -> np.ndarray:
    """Coordinates of a symmetric matrix in the standard symmetric basis (equations 7 and
    9).

    ``(x)_l = <X, M_l>``: the upper triangle row by row, off-diagonal entries times sqrt(2).

    Parameters
    ----------
    X : array_like, shape (n, n) or (..., n, n)
        A symmetric matrix, or a stack of them.

    Returns
    -------
    numpy.ndarray, shape (n(n+1)/2,) or (..., n(n+1)/2)
    """
    A = as_array(X, "X")
    if A.ndim < 2 or A.shape[-1] != A.shape[-2]:
        raise ValueError(f"X must be a square matrix or a stack of them, got shape {A.shape}")
    if np.max(np.abs(A - np.swapaxes(A, -1, -2)), initial=0.0) > _SYM_TOL * max(1.0, float(np.max(np.abs(A), initial=0.0))):
        raise ValueError("X must be symmetric")
    n = A.shape[-1]
    i, j = np.triu_indices(n)
    w = np.where(i == j, 1.0, np.sqrt(2.0))
    return A[..., i, j] * w


def smat(x: object) -> np.ndarray:
    r"""Inverse of :func:`svec`: the symmetric matrix :math:`\sum_l x_l M_l` (equation 9).

    Parameters
    ----------
    x : array_like, shape (n(n+1)/2,) or (..., n(n+1)/2)
        Coordinates, or a stack of them.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (..., n, n)
    """
    v = as_array(x, "x")
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
    r"""The standard symmetric basis :math:`\{M_l^{(n)}\}` of equation (9), shape
    ``(n(n+1)/2, n, n)``.

    Parameters
    ----------
    n : int
        Size of the matrices (>= 1).

    Returns
    -------
    numpy.ndarray, shape (n(n+1)/2, n, n)
        The basis matrices ``M_l`` in the order of :func:`svec`.
    """
    n = _as_size(n, "n", 1)
    return smat(np.eye(_dim(int(n))))


def congruence_operator(A: object) -> np.ndarray:
    r"""Matrix of the linear map :math:`X \mapsto A^T X A` in standard symmetric
    coordinates.

    ``A`` is any real ``n x m`` matrix; the result is ``m(m+1)/2 x n(n+1)/2`` with entries
    ``<M_i^(m), A^T M_j^(n) A>`` (eq. 10). Used for ``C~`` (orthonormal ``C``) and for the
    dynamics ``A~`` of eq. (21).

    Parameters
    ----------
    A : array_like, shape (n, m)
        Any real matrix.

    Returns
    -------
    numpy.ndarray, shape (m(m+1)/2, n(n+1)/2)
    """
    M = as_array(A, "A")
    if M.ndim == 1:
        M = M[:, None]
    if M.ndim != 2 or 0 in M.shape:
        raise ValueError(f"A must be a non-empty 2-D matrix, got shape {M.shape}")
    basis = symmetric_basis(M.shape[0])
    images = np.einsum("ai,lab,bj->lij", M, basis, M)
    return svec(images).T


def ctilde(C: object) -> np.ndarray:
    r"""The operator :math:`\tilde C` of equation (10): :math:`\operatorname{svec}(C^T X C)
    = \tilde C \operatorname{svec}(X)` (equation 11).

    Parameters
    ----------
    C : array_like, shape (n, m) or (n,)
        Orthonormal columns (an ``n x m`` projection, KVW Sec. 3; a 1-D array is one
        column).

    Returns
    -------
    numpy.ndarray, shape (m(m+1)/2, n(n+1)/2)
    """
    return congruence_operator(check_orthonormal(C))


def svec_basis_matrix(n: int) -> np.ndarray:
    r"""The :math:`n^2 \times n(n+1)/2` matrix :math:`P` with :math:`\operatorname{vec}(X) =
    P \operatorname{svec}(X)`: its columns are :math:`\operatorname{vec}(M_l)`.

    The columns are the standard symmetric basis of eq. (9), so ``P`` has orthonormal columns
    and entries ``0``, ``1`` and ``1/sqrt(2)``; ``P^T vec(X) = svec(X)``. It is *not* the
    Magnus-Neudecker duplication matrix ``D_n`` (entries 0 and 1, ``vec(X) = D_n vech(X)``):
    ``P = D_n diag(w)^{-1}`` with ``w = 1`` on the diagonal entries and ``sqrt(2)`` off it.

    Parameters
    ----------
    n : int
        Size of the matrices (>= 1).

    Returns
    -------
    numpy.ndarray, shape (n*n, n(n+1)/2)

    Raises
    ------
    ValueError
        If ``n`` is not a positive int.
    """
    n = _as_size(n, "n", 1)
    B = symmetric_basis(int(n))
    return B.reshape(B.shape[0], -1).T  # row-major vec equals column-major for symmetric M


def kron_operator(C: object) -> np.ndarray:
    r"""The Kronecker form of equation (6): :math:`\operatorname{vec}(C^T X C) = (C^T
    \otimes C^T) \operatorname{vec}(X)`.

    Parameters
    ----------
    C : array_like, shape (n, m) or (n,)
        Orthonormal columns.

    Returns
    -------
    numpy.ndarray, shape (m*m, n*n)
        The matrix ``C^T kron C^T``.
    """
    Cm = check_orthonormal(C)
    return np.kron(Cm.T, Cm.T)


def stacked_operator(Cs: Sequence[object]) -> np.ndarray:
    r"""The stacked operator :math:`\mathcal{C}` of equation (14): the :math:`\tilde C_i` of
    equation (10) one above the other.

    Parameters
    ----------
    Cs : sequence of (n, m_i) arrays
        The orthonormal views (1-D arrays are single columns).

    Returns
    -------
    numpy.ndarray, shape (sum of m_i(m_i+1)/2, n(n+1)/2)
    """
    return np.vstack([congruence_operator(C) for C in _check_Cs(Cs)])


def project(X: object, C: object) -> np.ndarray:
    """Orthogonal (silhouette) projection of the ellipsoid ``X`` onto ``range(C)``
    (equation 4).

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

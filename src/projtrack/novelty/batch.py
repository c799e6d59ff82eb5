"""Batch KL expansion through the small VIP matrix (Eqs. (2)-(3)) and the large-matrix oracle."""
from __future__ import annotations

from typing import Any

import numpy as np

from projtrack._validation import as_bool

from ._checks import as_frames, as_positive_count, as_tolerance
from ._linalg import _eigh_desc, _sign_fix
from .results import KLBasis

__all__ = ["vip_matrix", "correlation_matrix", "batch_kl"]


def vip_matrix(frames: Any, center: bool = False) -> np.ndarray:
    r"""The :math:`I \times I` matrix of vector inner products, Equation (2) of Vermeulen &
    Casasent.

    ``v(l, m) = (1/I) (x_l - m)^T (x_m - m)`` with ``m`` the sample mean if ``center`` else 0.

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
        The image sequence (any real dtype).
    center : bool
        Subtract the mean image (covariance, KL proper) or not (correlation, Section 3).

    Returns
    -------
    numpy.ndarray, shape (I, I)
    """
    center = as_bool(center, "center")
    x = as_frames(frames).reshape(len(frames), -1)
    if center:
        x = x - x.mean(axis=0)
    return x @ x.T / x.shape[0]


def correlation_matrix(frames: Any, center: bool = False) -> np.ndarray:
    r"""The large :math:`P \times P` matrix :math:`\frac{1}{I} \sum_i (x_i - m)(x_i - m)^T`
    (only for small images).

    This is the matrix whose eigen-decomposition Eqs. (2)-(3) avoid; it serves as the oracle.

    Parameters
    ----------
    frames : array_like, shape (I, ...)
        The frames (at most 4096 pixels each).
    center : bool, default False
        Subtract the mean frame :math:`m` first (otherwise :math:`m = 0`).

    Returns
    -------
    numpy.ndarray, shape (P, P)
    """
    center = as_bool(center, "center")
    x = as_frames(frames).reshape(len(frames), -1)
    if x.shape[1] > 4096:
        raise ValueError(f"frames: {x.shape[1]} pixels per frame would give a "
                         f"{x.shape[1]}x{x.shape[1]} matrix; use vip_matrix/batch_kl instead")
    if center:
        x = x - x.mean(axis=0)
    return x.T @ x / x.shape[0]


def batch_kl(frames: Any, center: bool = False, n_components: int | None = None,
             rtol: float = 1e-12) -> KLBasis:
    """Batch KL expansion through the small VIP matrix, Equations (2)-(3) of Vermeulen &
    Casasent.

    The eigenvectors ``theta_k`` and eigenvalues ``gamma_k`` of the VIP matrix ``V`` (Eq. (2))
    give the eigenimages ``Phi_k = sum_l theta_k^l x_l / sqrt(I gamma_k)`` (Eq. (3), normalized
    to unit norm; the ``1/I`` of Eq. (2) appears as the ``I`` in the square root) with
    eigenvalues ``lambda_k = gamma_k``, which are the non-zero eigenvalues of the correlation
    (``center=False``) or covariance (``center=True``) matrix.

    Parameters
    ----------
    frames : array_like, shape (I, H, W) or (I, ...)
    center : bool
        Remove the sample mean first (covariance matrix ``C``) or not (correlation ``R``).
    n_components : int, optional
        Keep only the largest ``n_components`` (default: all numerically non-zero ones).
    rtol : float
        Eigenvalues below ``rtol * max(eigenvalue)`` are numerically zero and dropped.

    Returns
    -------
    KLBasis
        ``eigenvalues`` (descending, positive) and unit-norm ``eigenimages`` ``(K, *shape)``.
    """
    center = as_bool(center, "center")
    a = as_frames(frames)
    shape = a.shape[1:]
    x = a.reshape(a.shape[0], -1)
    if center:
        x = x - x.mean(axis=0)
    if n_components is not None:
        n_components = as_positive_count(n_components, "n_components")
    rtol = as_tolerance(rtol, "rtol")
    n = x.shape[0]
    g, th = _eigh_desc(x @ x.T / n)
    top = g[0] if g.size else 0.0
    if top <= 0:
        raise ValueError("frames: every frame is zero (after centering); no eigenimage exists")
    keep = g > rtol * top
    if n_components is not None:
        keep &= np.arange(g.size) < n_components
    g, th = g[keep], th[:, keep]
    phi = (th.T @ x) / np.sqrt(n * g)[:, None]
    phi /= np.linalg.norm(phi, axis=1, keepdims=True)
    return KLBasis(g.copy(), _sign_fix(phi).reshape((-1,) + shape))


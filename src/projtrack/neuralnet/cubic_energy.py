"""The energy of eq. (8) and its derivative eq. (9): vectorized, and as the paper's nested sums."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ._checks import _check_D, _check_states
from .coefficients import Coefficients, _as_coefficients

__all__ = ["energy", "energy_gradient", "energy_gradient_loops"]


def _term4_parts(X: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Term 4 of eq. (9) without A4, for all neurons; X (..., N_T, N_M, N_P)."""
    out = np.zeros_like(X)
    # X[..., i, :, a] as (..., N_T, N_P, N_M) for convenient slicing by frame.
    Xt = np.moveaxis(X, -1, -2)
    x0, x1, x2 = Xt[..., :-2, :], Xt[..., 1:-1, :], Xt[..., 2:, :]  # (..., N_T, N_P-2, N_M)
    Db = D[..., None, :, :, :, :]  # broadcast over targets
    first = np.einsum("...abcd,...ac,...ad->...ab", Db, x1, x2)   # neuron (i, alpha, a)
    middle = np.einsum("...abcd,...ab,...ad->...ac", Db, x0, x2)  # neuron (i, beta, a+1)
    last = np.einsum("...abcd,...ab,...ac->...ad", Db, x0, x1)    # neuron (i, gamma, a+2)
    outt = np.moveaxis(out, -1, -2)
    outt[..., :-2, :] += first
    outt[..., 1:-1, :] += middle
    outt[..., 2:, :] += last
    return np.moveaxis(outt, -2, -1)


def energy(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None
           ) -> np.ndarray | float:
    """The energy of equation (8).

    ``E = A1 sum_{alpha,a} sum_{i != j} X_iaa X_jaa + A2 sum_{i,a} sum_{alpha != beta} X_iaa X_iba
    + A3 sum_a (sum_{i,alpha} X_iaa - N_T)^2
    + A4 sum_{a,i,alpha,beta,gamma} D^a_abg X_{i alpha a} X_{i beta a+1} X_{i gamma a+2}``.

    Term 3 is written with the sum over targets and measurements inside the square, as
    the paper's text and its derivative eq. (9) require (the printed eq. (8) lost the
    sum over ``a``). Defined for real-valued ``X`` as well (it is a polynomial).

    Parameters
    ----------
    X : array_like, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    float or ndarray of shape X.shape[:-3]
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D, batched=True)
    X = _check_states(X, D)
    n_t = X.shape[-3]
    col = X.sum(axis=-3)       # (..., N_M, N_P)
    row = X.sum(axis=-2)       # (..., N_T, N_P)
    sq = (X * X)
    e1 = (col ** 2).sum(axis=(-2, -1)) - sq.sum(axis=(-3, -2, -1))
    e2 = (row ** 2).sum(axis=(-2, -1)) - sq.sum(axis=(-3, -2, -1))
    frame = X.sum(axis=(-3, -2))  # (..., N_P)
    e3 = ((frame - n_t) ** 2).sum(axis=-1)
    Xt = np.moveaxis(X, -1, -2)
    e4 = np.einsum("...abcd,...iab,...iac,...iad->...", D, Xt[..., :-2, :], Xt[..., 1:-1, :], Xt[..., 2:, :])
    E = c.A1 * e1 + c.A2 * e2 + c.A3 * e3 + c.A4 * e4
    return float(E) if np.ndim(E) == 0 else E


def energy_gradient(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None
                    ) -> np.ndarray:
    r"""The derivative :math:`\partial E / \partial X_{i\alpha a}` of equation (9), for all
    neurons at once.

    ``2 A1 sum_{j != i} X_{j alpha a} + 2 A2 sum_{beta != alpha} X_{i beta a}
    + 2 A3 (sum_{j, beta} X_{j beta a} - N_T) + A4 (the three D-terms)``; the D-terms that
    would need frames outside ``0..N_P-1`` are absent. This is the exact partial
    derivative of the polynomial :func:`energy`.

    Parameters
    ----------
    X : array_like, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    ndarray, same shape as X
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D, batched=True)
    X = _check_states(X, D)
    n_t = X.shape[-3]
    col = X.sum(axis=-3, keepdims=True) - X
    row = X.sum(axis=-2, keepdims=True) - X
    frame = X.sum(axis=(-3, -2), keepdims=True)
    return (2 * c.A1 * col + 2 * c.A2 * row + 2 * c.A3 * (frame - n_t)
            + c.A4 * _term4_parts(X, D))


def energy_gradient_loops(X: np.ndarray, D: np.ndarray,
                          coefficients: Coefficients | Sequence[float] | None = None) -> np.ndarray:
    """Equation (9) written as the paper's nested sums, with plain Python loops.

    The straightforward reference for :func:`energy_gradient` (tests and benchmarks).

    Parameters
    ----------
    X : array_like, shape (N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    ndarray, shape (N_T, N_M, N_P)
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D)
    X = _check_states(X, D)
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    n_t, n_m, n_p = X.shape
    g = np.zeros_like(X)
    for i in range(n_t):
        for al in range(n_m):
            for a in range(n_p):
                t1 = sum(X[j, al, a] for j in range(n_t) if j != i)
                t2 = sum(X[i, b, a] for b in range(n_m) if b != al)
                t3 = sum(X[j, b, a] for j in range(n_t) for b in range(n_m)) - n_t
                t4 = 0.0
                for b in range(n_m):
                    for gm in range(n_m):
                        if a + 2 < n_p:
                            t4 += D[a, al, b, gm] * X[i, b, a + 1] * X[i, gm, a + 2]
                        if 1 <= a <= n_p - 2:
                            t4 += D[a - 1, b, al, gm] * X[i, b, a - 1] * X[i, gm, a + 1]
                        if a >= 2:
                            t4 += D[a - 2, b, gm, al] * X[i, b, a - 2] * X[i, gm, a - 1]
                g[i, al, a] = 2 * c.A1 * t1 + 2 * c.A2 * t2 + 2 * c.A3 * t3 + c.A4 * t4
    return g

"""Sec. 6.2 of KVW: recursive estimate of a dynamic ellipsoid by a Kalman filter (filterpy)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from projtrack._validation import as_array, optional_import

from .checks import _check_Cs, _check_Ys, _dim, _mats, _seq, check_symmetric
from .geometry import is_psd, nearest_psd
from .operators import congruence_operator, smat, svec

__all__ = ["kalman_estimate", "KalmanResult"]


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

    Needs the optional dependency filterpy (``pip install "projtrack[kalman]"``).

    Parameters
    ----------
    Ys : sequence of (m_k, m_k) arrays
        Observed projections at times ``0..r``.
    Cs : sequence of (n, m_k) arrays
        Their orthonormal views.
    As : array_like, shape (n, n) or (r, n, n)
        Transition matrices of eq. (20).
    Bs : array_like, optional
        Known drive of eq. (20); None means no drive.
    x0_mean : array_like (n, n), optional
        Prior mean of ``X_0``; default zero.
    P0, R, Q : float or array_like
        Prior covariance of ``svec(X_0)``, measurement noise covariance of ``svec(W_k)``
        and process noise covariance; scalars mean multiples of the identity.

    Returns
    -------
    KalmanResult
    """
    KalmanFilter = optional_import("filterpy.kalman", "kalman", "kalman_estimate").KalmanFilter

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
        a = as_array(v, name)
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

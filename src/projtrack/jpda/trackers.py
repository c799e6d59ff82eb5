"""Trackers on ``filterpy`` Kalman filters: JPDA (beta-weighted updates) and a GNN baseline."""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_probability, as_real

from .association import beta
from .validation import gate_threshold, mahalanobis_sq, modified_validation_matrix

__all__ = ["JPDATracker", "GNNTracker"]


class _KFBank:
    def __init__(self, x0, P0, F, Q, H, R):
        from filterpy.kalman import KalmanFilter

        x0 = as_array(x0, "x0", ndim=2)
        F_ = as_array(F, "F", ndim=2)
        H_ = as_array(H, "H", ndim=2)
        n = x0.shape[1]
        if F_.shape != (n, n):
            raise ValueError(f"F must have shape ({n}, {n}), got {F_.shape}")
        if H_.shape[1] != n:
            raise ValueError(f"H must have {n} columns, got shape {H_.shape}")
        d = H_.shape[0]
        P0_ = as_array(P0, "P0", ndim=2)
        Q_ = as_array(Q, "Q", ndim=2)
        R_ = as_array(R, "R", ndim=2)
        for name, M, k in (("P0", P0_, n), ("Q", Q_, n), ("R", R_, d)):
            if M.shape != (k, k):
                raise ValueError(f"{name} must have shape ({k}, {k}), got {M.shape}")
        self.filters = []
        for x in x0:
            kf = KalmanFilter(dim_x=n, dim_z=d)
            kf.x = x.reshape(n, 1).copy()
            kf.P = P0_.copy()
            kf.F = F_.copy()
            kf.Q = Q_.copy()
            kf.H = H_.copy()
            kf.R = R_.copy()
            self.filters.append(kf)
        self.d = d

    def predict(self):
        zp, S = [], []
        for kf in self.filters:
            kf.predict()
            zp.append((kf.H @ kf.x).ravel())
            S.append(kf.H @ kf.P @ kf.H.T + kf.R)
        return np.array(zp).reshape(-1, self.d), np.array(S).reshape(-1, self.d, self.d)

    def measurements(self, measurements: object) -> np.ndarray:
        """One scan as a finite ``(m, d)`` float array (an empty scan may be ``[]``)."""
        z = as_array(measurements, "measurements", finite=False)
        if z.size == 0:
            return np.zeros((0, self.d))
        if self.d == 1 and z.ndim == 1:
            z = z[:, None]
        if z.ndim != 2 or z.shape[1] != self.d:
            raise ValueError(f"measurements must have shape (m, {self.d}) (d = rows of H), "
                             f"got shape {z.shape}")
        if not np.all(np.isfinite(z)):
            raise ValueError("measurements must be finite")
        return z

    @property
    def states(self) -> np.ndarray:
        return np.array([kf.x.ravel() for kf in self.filters])


class JPDATracker:
    """JPDA tracker: per-target ``filterpy`` Kalman filters with beta-weighted updates.

    Each step predicts every target, builds the MVM (:func:`modified_validation_matrix`
    with row 0 = ``1 - P_D P_G`` and rows ``P_D N(z_j; z_hat_t, S_t) / lambda``
    inside the gate), computes ``beta`` and updates each target with the combined
    innovation ``nu_t = sum_j beta_jt nu_jt``::

        x = x + K nu_t
        P = beta_0t P_pred + (1 - beta_0t) (I - K H) P_pred
            + K (sum_j beta_jt nu_jt nu_jt^T - nu_t nu_t^T) K^T

    the last term being the spread of the innovations (Fortmann, Bar-Shalom & Scheffe
    1983). The paper treats these covariance and state updates as standard (Sec. II).

    Parameters
    ----------
    x0 : array_like, shape (T, n)
        Initial states (track initiation is not part of JPDA, chapter 3 does it).
    P0, F, Q, H, R : array_like
        Initial covariance, transition, process noise, measurement and noise matrices.
    p_detect : float
        ``P_D`` in (0, 1].
    clutter_density : float
        Spatial density ``lambda`` of false measurements (> 0).
    gate_prob : float
        Gate probability ``P_G`` in (0, 1).
    """

    def __init__(self, x0, P0, F, Q, H, R, p_detect: float = 0.9,
                 clutter_density: float = 1e-3, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R)
        self.p_detect = as_probability(p_detect, "p_detect", low_open=True)
        self.clutter_density = as_real(clutter_density, "clutter_density", 0.0, low_open=True)
        self.gate_prob = as_probability(gate_prob, "gate_prob", low_open=True, high_open=True)
        gate_threshold(self.gate_prob, self.bank.d)
        self.last_beta_: np.ndarray | None = None

    def step(self, measurements: object) -> np.ndarray:
        """Predict, associate and update with one scan of measurements ``(m, d)``; returns states."""
        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        T = len(zp)
        mvm = modified_validation_matrix(z, zp, S, self.p_detect, self.gate_prob,
                                         self.clutter_density)
        mvm[0] = 1.0 - self.p_detect * self.gate_prob
        b = beta(mvm)
        self.last_beta_ = b
        for t, kf in enumerate(self.bank.filters):
            nu_j = z - zp[t][None, :]
            bj = b[1:, t]
            nu = bj @ nu_j
            Si = np.linalg.inv(S[t])
            K = kf.P @ kf.H.T @ Si
            spread = (nu_j * bj[:, None]).T @ nu_j - np.outer(nu, nu)
            Pc = (np.eye(kf.P.shape[0]) - K @ kf.H) @ kf.P
            kf.x = kf.x + K @ nu.reshape(-1, 1)
            P = b[0, t] * kf.P + (1 - b[0, t]) * Pc + K @ spread @ K.T
            kf.P = 0.5 * (P + P.T)
        return self.bank.states


class GNNTracker:
    """Global nearest neighbour tracker (a baseline for :class:`JPDATracker`).

    Each scan, measurements are assigned one-to-one to targets by
    ``scipy.optimize.linear_sum_assignment`` on the squared Mahalanobis distance, with a dummy "no measurement" option at the gate threshold; each
    target is updated with its assigned measurement (standard Kalman update) or only
    predicted. Same parameters as :class:`JPDATracker` (``P_D``, ``lambda`` unused).
    """

    def __init__(self, x0, P0, F, Q, H, R, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R)
        self.gate = gate_threshold(gate_prob, self.bank.d)

    def step(self, measurements: object) -> np.ndarray:
        """Predict, assign and update with one scan ``(m, d)``; returns the states."""
        from scipy.optimize import linear_sum_assignment

        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        T, m = len(zp), len(z)
        if m:
            d2 = mahalanobis_sq(z, zp, S).T  # (T, m)
            big = 1e12
            cost = np.where(d2 <= self.gate, d2, big)
            dummy = np.full((T, T), big)
            np.fill_diagonal(dummy, self.gate)
            r, c = linear_sum_assignment(np.hstack([cost, dummy]))
            for t, j in zip(r, c):
                if j < m and cost[t, j] < big:
                    self.bank.filters[t].update(z[j].reshape(-1, 1))
        return self.bank.states

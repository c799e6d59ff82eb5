"""Trackers on ``filterpy`` Kalman filters: JPDA (beta-weighted updates) and a GNN baseline.

Both need the optional dependency ``filterpy`` (``pip install "projtrack[kalman]"``).
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_covariance, as_covariances, as_probability, as_real, optional_import

from .association import beta
from .validation import gate_threshold, mahalanobis_sq, mvm_from_positions

__all__ = ["JPDATracker", "GNNTracker"]


class _KFBank:
    """One ``filterpy`` Kalman filter per target, built from checked matrices."""

    def __init__(self, x0, P0, F, Q, H, R, owner: str):
        kalman = optional_import("filterpy.kalman", "kalman", owner)
        x0 = as_array(x0, "x0", ndim=2)
        F_ = as_array(F, "F", ndim=2)
        H_ = as_array(H, "H", ndim=2)
        T, n = x0.shape
        if n == 0:
            raise ValueError(f"x0 must have shape (T, n) with n >= 1 state variables, got {x0.shape}")
        if F_.shape != (n, n):
            raise ValueError(f"F must have shape ({n}, {n}), got {F_.shape}")
        if H_.shape[1] != n or H_.shape[0] == 0:
            raise ValueError(f"H must have {n} columns, got shape {H_.shape}")
        d = H_.shape[0]
        for name, M, k in (("P0", P0, n), ("Q", Q, n), ("R", R, d)):
            shape = np.shape(M)
            if name != "P0" and shape != (k, k):
                raise ValueError(f"{name} must have shape ({k}, {k}), got {shape}")
        P0_ = as_covariances(P0, "P0", T, n)
        Q_ = as_covariance(Q, "Q", n)
        R_ = as_covariance(R, "R", d)
        self.filters = []
        for x, P in zip(x0, P0_):
            kf = kalman.KalmanFilter(dim_x=n, dim_z=d)
            kf.x = x.reshape(n, 1).copy()
            kf.P = P.copy()
            kf.F = F_.copy()
            kf.Q = Q_.copy()
            kf.H = H_.copy()
            kf.R = R_.copy()
            self.filters.append(kf)
        self.n, self.d = n, d

    def predict(self):
        zp, S = [], []
        for kf in self.filters:
            kf.predict()
            zp.append((kf.H @ kf.x).ravel())
            S.append(kf.H @ kf.P @ kf.H.T + kf.R)
        zp_, S_ = np.array(zp).reshape(-1, self.d), np.array(S).reshape(-1, self.d, self.d)
        for t, St in enumerate(S_):
            if np.linalg.eigvalsh(St)[0] <= 1e-12 * max(1.0, float(np.abs(St).max())):
                raise ValueError(
                    f"the innovation covariance H P H^T + R of target {t} is singular: with a "
                    "singular R (noise-free measurements) the state covariance must keep "
                    "H P H^T positive definite; use a positive definite R")
        return zp_, S_

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
        return np.array([kf.x.ravel() for kf in self.filters]).reshape(-1, self.n)

    @property
    def covariances(self) -> np.ndarray:
        return np.array([kf.P for kf in self.filters]).reshape(-1, self.n, self.n)


class JPDATracker:
    r"""JPDA tracker: one Kalman filter per target, updated with the association probabilities.

    Each :meth:`step` predicts every target, builds the MVM with
    :func:`mvm_from_positions` (row 0 :math:`1 - P_D P_G`, row :math:`j` the gated
    likelihood :math:`P_D\,\mathcal{N}(z_j; \hat z_t, S_t) / \lambda`), computes
    :func:`beta` and updates each target with the combined innovation
    :math:`\nu_t = \sum_j \beta_{jt} \nu_{jt}`:

    .. math::

        x &\leftarrow x + K \nu_t, \\
        P &\leftarrow \beta_{0t} P^- + (1 - \beta_{0t}) (I - K H) P^-
             + K \Big(\sum_j \beta_{jt} \nu_{jt} \nu_{jt}^T - \nu_t \nu_t^T\Big) K^T,

    the last term being the spread of the innovations (Fortmann, Bar-Shalom & Scheffe
    1983). The paper treats these covariance and state updates as standard (Sec. II).
    Track initiation is not part of JPDA: start the tracker from known states, or from
    :class:`projtrack.hough.TrackInitiator`.

    Needs the optional dependency ``filterpy`` (``pip install "projtrack[kalman]"``).

    Parameters
    ----------
    x0 : array_like, shape (T, n)
        Initial states, one row per target (``T = 0`` is allowed: :meth:`step` then
        returns shape ``(0, n)``).
    P0 : array_like, shape (n, n) or (T, n, n)
        Initial covariance: one matrix for every target, or one per target. Symmetric
        positive semidefinite.
    F : array_like, shape (n, n)
        State transition matrix.
    Q : array_like, shape (n, n)
        Process noise covariance (symmetric positive semidefinite).
    H : array_like, shape (d, n)
        Measurement matrix.
    R : array_like, shape (d, d)
        Measurement noise covariance (symmetric positive semidefinite; positive definite
        unless :math:`H P H^T` stays positive definite).
    p_detect : float, default 0.9
        Detection probability :math:`P_D` in (0, 1].
    clutter_density : float, default 1e-3
        Spatial density :math:`\lambda` of false measurements (> 0), per unit of
        measurement space.
    gate_prob : float, default 0.99
        Gate probability :math:`P_G` in (0, 1).

    Attributes
    ----------
    states : numpy.ndarray, shape (T, n)
        The current state estimates (after the last :meth:`step`).
    covariances : numpy.ndarray, shape (T, n, n)
        Their covariances.
    last_mvm_ : numpy.ndarray, shape (m + 1, T), or None
        The MVM of the last scan (``None`` before the first step).
    last_beta_ : numpy.ndarray, shape (m + 1, T), or None
        The association probabilities of the last scan: ``last_beta_[j, t]`` that
        measurement ``j`` (rows from 1) came from target ``t``, row 0 that target ``t``
        has no measurement in the scan.

    Raises
    ------
    ValueError
        When a matrix has the wrong shape, a covariance is not symmetric positive
        semidefinite (the message names it: ``R must be positive semidefinite``), or a
        probability or density is out of range.

    See Also
    --------
    GNNTracker : the global-nearest-neighbour baseline.
    beta : the association probabilities alone.

    Examples
    --------
    Two targets crossing at the origin, a constant-velocity model (state
    :math:`(x, v_x, y, v_y)`), ten scans of noisy measurements with two clutter points
    each:

    >>> import numpy as np
    >>> from projtrack.jpda import JPDATracker
    >>> F = np.array([[1., 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1], [0, 0, 0, 1]])
    >>> H = np.array([[1., 0, 0, 0], [0, 0, 1, 0]])
    >>> truth = np.array([[-5., 1, -5, 1], [-5., 1, 5, -1]])
    >>> trk = JPDATracker(truth, np.eye(4), F, 0.01 * np.eye(4), H, 0.1 * np.eye(2),
    ...                   p_detect=0.9, clutter_density=1e-3)
    >>> rng = np.random.default_rng(1)
    >>> for k in range(10):
    ...     truth = truth @ F.T
    ...     z = truth[:, [0, 2]] + rng.normal(0, 0.3, (2, 2))     # one per target
    ...     z = np.vstack([z, rng.uniform(-8, 8, (2, 2))])        # and clutter
    ...     x = trk.step(z)
    >>> np.round(x[:, [0, 2]], 1)            # the targets end at (5, 5) and (5, -5)
    array([[ 4.8,  5.1],
           [ 5.1, -5. ]])
    >>> trk.covariances.shape, np.round(np.sqrt(trk.covariances[:, 0, 0]), 2)
    ((2, 4, 4), array([0.25, 0.24]))
    >>> trk.last_beta_.shape   # rows: no measurement, then 4 measurements
    (5, 2)
    """

    def __init__(self, x0, P0, F, Q, H, R, p_detect: float = 0.9,
                 clutter_density: float = 1e-3, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R, "JPDATracker")
        self.p_detect = as_probability(p_detect, "p_detect", low_open=True)
        self.clutter_density = as_real(clutter_density, "clutter_density", 0.0, low_open=True)
        self.gate_prob = as_probability(gate_prob, "gate_prob", low_open=True, high_open=True)
        gate_threshold(self.gate_prob, self.bank.d)
        self.last_beta_: np.ndarray | None = None
        self.last_mvm_: np.ndarray | None = None

    @property
    def states(self) -> np.ndarray:
        """The current state estimates, shape ``(T, n)``."""
        return self.bank.states

    @property
    def covariances(self) -> np.ndarray:
        """The current state covariances, shape ``(T, n, n)``."""
        return self.bank.covariances

    def step(self, measurements: object) -> np.ndarray:
        """Predict, associate and update with one scan of measurements.

        Parameters
        ----------
        measurements : array_like, shape (m, d)
            The scan's measurements (``[]`` or shape ``(0, d)`` for an empty scan:
            the targets are only predicted).

        Returns
        -------
        numpy.ndarray, shape (T, n)
            The updated states (the same as :attr:`states`; their covariances are
            :attr:`covariances`).
        """
        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        if len(zp) == 0:
            self.last_mvm_ = self.last_beta_ = np.zeros((len(z) + 1, 0))
            return self.bank.states
        mvm = mvm_from_positions(z, zp, S, p_detect=self.p_detect, gate_prob=self.gate_prob,
                                 clutter_density=self.clutter_density)
        b = beta(mvm)
        self.last_mvm_, self.last_beta_ = mvm, b
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
    ``scipy.optimize.linear_sum_assignment`` on the squared Mahalanobis distance, with
    a dummy "no measurement" option at the gate threshold; each target is updated with
    its assigned measurement (standard Kalman update) or only predicted.

    Needs the optional dependency ``filterpy`` (``pip install "projtrack[kalman]"``).

    Parameters
    ----------
    x0, P0, F, Q, H, R : array_like
        As for :class:`JPDATracker` (``P0`` one matrix or one per target).
    gate_prob : float, default 0.99
        Gate probability :math:`P_G` in (0, 1).

    Attributes
    ----------
    states : numpy.ndarray, shape (T, n)
        The current state estimates.
    covariances : numpy.ndarray, shape (T, n, n)
        Their covariances.
    """

    def __init__(self, x0, P0, F, Q, H, R, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R, "GNNTracker")
        self.gate = gate_threshold(gate_prob, self.bank.d)

    @property
    def states(self) -> np.ndarray:
        """The current state estimates, shape ``(T, n)``."""
        return self.bank.states

    @property
    def covariances(self) -> np.ndarray:
        """The current state covariances, shape ``(T, n, n)``."""
        return self.bank.covariances

    def step(self, measurements: object) -> np.ndarray:
        """Predict, assign and update with one scan ``(m, d)``; returns the states ``(T, n)``."""
        from scipy.optimize import linear_sum_assignment

        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        T, m = len(zp), len(z)
        if m and T:
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

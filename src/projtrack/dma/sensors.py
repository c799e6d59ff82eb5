"""Sensor models ``p(y(t) | u(t))`` over a fixed set of prototypes.

:class:`SensorModel` is the interface; :class:`LinearGaussianSensor` (Example 1 of
Marques et al., 2002), :class:`RangeCosineSensor` (eq. (14), Example 2) and
:class:`ActivePixelSensor` (eq. (15), Example 3) implement it.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_int, as_odd_window, as_real

__all__ = ["SensorModel", "LinearGaussianSensor", "RangeCosineSensor", "ActivePixelSensor"]


class SensorModel:
    r"""Interface of a sensor model :math:`p(y \mid u_k)` over a fixed set of prototypes.

    Subclasses implement :meth:`log_likelihood` (one observation -> ``(S,)`` array of
    ``log p(y | u_k)``); :meth:`log_likelihoods` stacks it over a sequence (override it
    to vectorise). ``n_states`` is the number of prototypes. User models only need these
    two members.
    """

    n_states: int

    def log_likelihood(self, observation: object) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def log_likelihoods(self, observations: object) -> np.ndarray:
        """``(N, S)`` log-likelihoods of a sequence of observations."""
        obs = list(observations)  # type: ignore[call-overload]
        if not obs:
            raise ValueError("observations is empty")
        return np.vstack([self.log_likelihood(o) for o in obs])


def _check_points_arg(points: object, name: str = "points", ncols: int | None = None) -> np.ndarray:
    P = as_array(points, name, ndim=2, allow_empty=False)
    if ncols is not None and P.shape[1] != ncols:
        raise ValueError(f"{name} must have {ncols} columns, got shape {P.shape}")
    return P


class LinearGaussianSensor(SensorModel):
    r""":math:`y = H x + v`, :math:`v \sim \mathcal{N}(0, R)` (Example 1: :math:`H = [1\
    {-1}\ 1]`).

    Parameters
    ----------
    points : array_like, shape (S, n)
        Prototypes.
    H : array_like, shape (p, n)
        Observation matrix.
    noise_cov : float or array_like, shape (p, p)
        Covariance ``R`` (a float means ``R = noise_cov * I``).
    """

    def __init__(self, points: object, H: object, noise_cov: object):
        self.points = _check_points_arg(points)
        H = np.atleast_2d(np.asarray(H, dtype=float))
        if H.ndim != 2 or H.shape[1] != self.points.shape[1]:
            raise ValueError(f"H must have shape (p, {self.points.shape[1]}), got {H.shape}")
        p = H.shape[0]
        R = np.asarray(noise_cov, dtype=float)
        R = R * np.eye(p) if R.ndim == 0 else R
        if R.shape != (p, p) or not np.allclose(R, R.T) or np.linalg.eigvalsh(R).min() <= 0:
            raise ValueError(f"noise_cov must be a positive float or a ({p}, {p}) SPD matrix")
        self.H, self.R = H, R
        self.n_states = len(self.points)
        self._mean = self.points @ H.T
        self._Rinv = np.linalg.inv(R)
        self._const = -0.5 * (p * np.log(2 * np.pi) + np.linalg.slogdet(R)[1])

    def _obs(self, observations: object) -> np.ndarray:
        Y = np.asarray(observations, dtype=float)
        p = self.H.shape[0]
        if Y.ndim == 1 and p == 1:
            Y = Y[:, None]
        if Y.ndim != 2 or Y.shape[1] != p:
            raise ValueError(f"observations must have shape (N, {p}), got {np.shape(observations)}")
        if not np.isfinite(Y).all():
            raise ValueError("observations must be finite (no NaN)")
        return Y

    def log_likelihoods(self, observations: object) -> np.ndarray:
        Y = self._obs(observations)
        D = Y[:, None, :] - self._mean[None]
        return self._const - 0.5 * np.einsum("nki,ij,nkj->nk", D, self._Rinv, D)

    def log_likelihood(self, observation: object) -> np.ndarray:
        return self.log_likelihoods(np.atleast_1d(np.asarray(observation, dtype=float))[None])[0]


class RangeCosineSensor(SensorModel):
    r"""Range radar :math:`y_t = \cos(\omega d_t) + w_t`, :math:`w_t \sim \mathcal{N}(0,
    \sigma^2)` (equation (14)).

    ``d_t`` is the distance from the prototype to the receiver (Example 2:
    ``omega = 0.02`` rad/m, ``noise_var = 0.05``).

    Parameters
    ----------
    points : array_like, shape (K, n)
        The prototypes (states).
    receiver : array_like, shape (n,)
        Position of the receiver.
    omega : float
        Angular frequency of the range response, rad per unit of distance.
    noise_var : float
        Variance of the measurement noise (> 0).
    """

    def __init__(self, points: object, receiver: object, omega: float, noise_var: float):
        self.points = _check_points_arg(points)
        r = np.asarray(receiver, dtype=float)
        if r.shape != (self.points.shape[1],) or not np.isfinite(r).all():
            raise ValueError(f"receiver must be a finite point of shape ({self.points.shape[1]},)")
        omega = as_real(omega, "omega", 0, low_open=True)
        noise_var = as_real(noise_var, "noise_var", 0, low_open=True)
        self.receiver, self.omega, self.noise_var = r, float(omega), float(noise_var)
        self.n_states = len(self.points)
        self.distances = np.linalg.norm(self.points - r, axis=1)
        self._mean = np.cos(self.omega * self.distances)

    def log_likelihoods(self, observations: object) -> np.ndarray:
        y = np.asarray(observations, dtype=float)
        if y.ndim != 1 or y.size == 0:
            raise ValueError(f"observations must be a non-empty 1-D array, got shape {y.shape}")
        if not np.isfinite(y).all():
            raise ValueError("observations must be finite (no NaN)")
        r = y[:, None] - self._mean[None]
        return -0.5 * r**2 / self.noise_var - 0.5 * np.log(2 * np.pi * self.noise_var)

    def log_likelihood(self, observation: object) -> np.ndarray:
        return self.log_likelihoods(np.array([observation], dtype=float).ravel())[0]


class ActivePixelSensor(SensorModel):
    r"""Active-pixel count model :math:`p(y_t \mid u_k) \propto c^{n_k}` (equation (15),
    Example 3).

    ``n_k`` is the number of active pixels (``|frame - background| > threshold``) in the
    ``L x L`` box centred at prototype ``u_k`` (pixel coordinates ``(row, col)``).
    ``log p = n_k log c`` up to a constant common to all prototypes, so ``c`` only acts
    through ``log c`` (it is the likelihood ratio of a pixel being active on the car
    versus off it; see :meth:`fit_c`).

    Parameters
    ----------
    points : array_like, shape (S, 2)
        Prototype centres in pixel coordinates (row, col).
    box : int
        Box side ``L`` (odd).
    c : float
        Base of eq. (15), > 1.
    """

    def __init__(self, points: object, box: int, c: float):
        self.points = _check_points_arg(points, ncols=2)
        L = as_odd_window(box, "box")
        c = as_real(c, "c", 0, low_open=True)
        self.box, self.c = L, float(c)
        self.n_states = len(self.points)
        self._rc = np.rint(self.points).astype(np.int64)

    def counts(self, active: object) -> np.ndarray:
        """Active-pixel counts ``n_k`` for a binary image or a stack ``(N, H, W)``."""
        A = np.asarray(active)
        single = A.ndim == 2
        if single:
            A = A[None]
        if A.ndim != 3:
            raise ValueError(f"active must be a binary image (H, W) or stack (N, H, W), got shape {np.shape(active)}")
        N, Hh, W = A.shape
        h = self.box // 2
        I = np.zeros((N, Hh + 1, W + 1))
        I[:, 1:, 1:] = np.cumsum(np.cumsum(A.astype(float), axis=1), axis=2)
        r0 = np.clip(self._rc[:, 0] - h, 0, Hh)
        r1 = np.clip(self._rc[:, 0] + h + 1, 0, Hh)
        c0 = np.clip(self._rc[:, 1] - h, 0, W)
        c1 = np.clip(self._rc[:, 1] + h + 1, 0, W)
        n = I[:, r1, c1] - I[:, r0, c1] - I[:, r1, c0] + I[:, r0, c0]
        return n[0] if single else n

    def log_likelihoods(self, observations: object) -> np.ndarray:
        """``n_k log c`` for a stack of binary (active-pixel) images ``(N, H, W)``."""
        A = np.asarray(observations)
        if A.ndim != 3 or A.shape[0] == 0:
            raise ValueError(f"observations must be a non-empty stack of binary images (N, H, W), got shape {A.shape}")
        return self.counts(A) * np.log(self.c)

    def log_likelihood(self, observation: object) -> np.ndarray:
        A = np.asarray(observation)
        if A.ndim != 2:
            raise ValueError(f"observation must be a binary image (H, W), got shape {A.shape}")
        return self.log_likelihoods(A[None])[0]

    @staticmethod
    def fit_c(active: object, positions: object, box: int) -> float:
        """Estimate ``c`` of eq. (15) from training frames with known car positions.

        With pixels active independently with probability ``q1`` inside the car box and
        ``q0`` elsewhere, the likelihood ratio of a box position is proportional to
        ``c^{n_k}`` with ``c = q1 (1 - q0) / (q0 (1 - q1))``; ``q1`` and ``q0`` are
        relative frequencies (strong law of large numbers, as in the paper).
        """
        A = np.asarray(active).astype(bool)
        P = np.asarray(positions, dtype=float)
        if A.ndim != 3 or P.shape != (A.shape[0], 2):
            raise ValueError("active must be (N, H, W) and positions (N, 2)")
        if A.shape[0] == 0:
            raise ValueError("fit_c needs at least one training frame")
        L = as_int(box, "box", minimum=1)
        N, Hh, W = A.shape
        h = L // 2
        I = np.zeros((N, Hh + 1, W + 1))
        I[:, 1:, 1:] = np.cumsum(np.cumsum(A, axis=1, dtype=float), axis=2)
        rc = np.rint(P).astype(np.int64)
        r0, r1 = np.clip(rc[:, 0] - h, 0, Hh), np.clip(rc[:, 0] + h + 1, 0, Hh)
        c0, c1 = np.clip(rc[:, 1] - h, 0, W), np.clip(rc[:, 1] + h + 1, 0, W)
        t = np.arange(N)
        inside = float((I[t, r1, c1] - I[t, r0, c1] - I[t, r1, c0] + I[t, r0, c0]).sum())
        n_in = L * L * len(A)
        n_out = A[0].size * len(A) - n_in
        q1 = (inside + 1) / (n_in + 2)
        q0 = (A.sum() - inside + 1) / (n_out + 2)
        return float(q1 * (1 - q0) / (q0 * (1 - q1)))

"""Measurement validation (Sec. II.A) and the modified validation matrix (Sec. III.A).

Chi-square gates around the predicted measurements, the binary validation matrix of
shape ``(m, T + 1)`` (column 0, clutter, all ones) and the MVM of eqs. (3)-(4), shape
``(m + 1, T)``: row ``j`` holds ``f_t(z_j) P_D,t / lambda``; row 0 holds ``1 - P_D,t P_G``
(:func:`mvm_from_positions`, the package's convention, used by the tracker) or the paper's
``1 - P_D,t`` (:func:`modified_validation_matrix`, eq. 3).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from projtrack._validation import as_array, as_covariance, as_int, as_probabilities, as_probability, as_real

from ._checks import _check_mvm

__all__ = ["gate_threshold", "mahalanobis_sq", "validation_matrix", "modified_validation_matrix",
           "mvm_from_positions", "mvm_to_validation"]


def gate_threshold(gate_prob: float, dim: int) -> float:
    r"""Chi-square gate threshold :math:`d` with :math:`P(\chi^2_{\mathrm{dim}} \le d) =
    P_G` (Section II.A).

    A measurement :math:`z` is validated for a target when its squared Mahalanobis
    distance :math:`(z - \hat z)^T S^{-1} (z - \hat z)` to the predicted measurement
    :math:`\hat z` (innovation covariance :math:`S`) does not exceed :math:`d`.

    Parameters
    ----------
    gate_prob : float
        Gate probability :math:`P_G` in (0, 1).
    dim : int
        Dimension of the measurements (degrees of freedom of the chi-square law).

    Returns
    -------
    float
        The threshold :math:`d`.
    """
    g = as_probability(gate_prob, "gate_prob", low_open=True, high_open=True)
    dim = as_int(dim, "dim", minimum=1)
    return _chi2_ppf(g, dim)


@lru_cache(maxsize=64)
def _chi2_ppf(g: float, dim: int) -> float:
    from scipy.stats import chi2

    return float(chi2.ppf(g, dim))


def mahalanobis_sq(measurements: object, z_pred: object, S: object) -> np.ndarray:
    """Squared Mahalanobis distances of every measurement to every predicted measurement.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
    z_pred : array_like, shape (T, d)
        Predicted measurements ``z_hat_t(k|k-1)``.
    S : array_like, shape (T, d, d)
        Innovation covariances ``S_t(k)`` (symmetric positive definite).

    Returns
    -------
    numpy.ndarray, shape (m, T)
    """
    z = as_array(measurements, "measurements", ndim=2)
    zp = as_array(z_pred, "z_pred", ndim=2)
    S_ = as_array(S, "S", ndim=3)
    T, d = zp.shape
    if z.shape[1] != d and z.shape[0] > 0:
        raise ValueError(f"measurements must have {d} columns like z_pred, got {z.shape[1]}")
    if S_.shape != (T, d, d):
        raise ValueError(f"S must have shape ({T}, {d}, {d}), got {S_.shape}")
    if not np.allclose(S_, np.swapaxes(S_, 1, 2)):
        raise ValueError("S must be symmetric")
    try:
        L = np.linalg.cholesky(S_)
    except np.linalg.LinAlgError as exc:
        raise ValueError("S must be positive definite") from exc
    z = z.reshape(-1, d)
    nu = z[:, None, :] - zp[None, :, :]  # (m, T, d)
    y = np.linalg.solve(L[None], nu[..., None])[..., 0] if len(z) else nu
    return np.sum(y * y, axis=-1)


def _gauss_density(d2: np.ndarray, S: np.ndarray) -> np.ndarray:
    d = S.shape[-1]
    _, logdet = np.linalg.slogdet(S)
    return np.exp(-0.5 * d2 - 0.5 * (d * np.log(2 * np.pi) + logdet)[None, :])


def validation_matrix(measurements: object, z_pred: object, S: object,
                      gate_prob: float = 0.99) -> np.ndarray:
    """Binary validation matrix of Section II.A, shape :math:`(m, T + 1)`.

    Column 0 (the false-measurement "target" ``t = 0``) is all ones; entry ``(j, t)``
    is 1 when measurement ``j`` lies inside the chi-square gate of target ``t``
    (threshold :func:`gate_threshold`). Fig. 1 of the paper has rows 110, 111, 101.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
        The scan's measurements.
    z_pred : array_like, shape (T, d)
        Predicted measurements of the targets.
    S : array_like, shape (T, d, d)
        Innovation covariances (symmetric positive definite).
    gate_prob : float, default 0.99
        Gate probability :math:`P_G` in (0, 1).

    Returns
    -------
    numpy.ndarray of int8, shape (m, T + 1)
    """
    d2 = mahalanobis_sq(measurements, z_pred, S)
    dim = np.asarray(z_pred).shape[1]
    inside = d2 <= gate_threshold(gate_prob, dim)
    return np.hstack([np.ones((d2.shape[0], 1), dtype=np.int8), inside.astype(np.int8)])


def modified_validation_matrix(measurements: object, z_pred: object, S: object,
                               p_detect: object, gate_prob: float = 0.99,
                               clutter_density: float = 1.0) -> np.ndarray:
    r"""Modified validation matrix (MVM) exactly as the paper writes it, equations (3)-(4).

    Row 0 holds :math:`1 - P_{D,t}` (eq. 3); row :math:`j` holds
    :math:`f_t(z_j) P_{D,t} / \lambda` (eq. 4 divided by the clutter density
    :math:`\lambda`; the paper's form is :math:`\lambda = 1`) where measurement
    :math:`j` passes target :math:`t`'s gate, else 0. :math:`f_t` is the normal density
    :math:`\mathcal{N}(z_j; \hat z_t, S_t)`.

    The gate probability :math:`P_G` sets only the gate here; row 0 does not count the
    detections that fall outside the gate. :func:`mvm_from_positions` builds the MVM in
    the package's convention, row 0 :math:`= 1 - P_D P_G` (what :class:`JPDATracker`
    uses); with :math:`P_G` close to 1 the two agree.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
        The scan's measurements.
    z_pred : array_like, shape (T, d)
        Predicted measurements :math:`\hat z_t`.
    S : array_like, shape (T, d, d)
        Innovation covariances :math:`S_t` (symmetric positive definite).
    p_detect : float or array_like of shape (T,)
        Detection probabilities :math:`P_{D,t}` in (0, 1].
    gate_prob : float
        Gate probability :math:`P_G` in (0, 1) that sets the chi-square threshold.
    clutter_density : float
        Spatial density :math:`\lambda > 0` of false measurements.

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)
    """
    d2 = mahalanobis_sq(measurements, z_pred, S)
    S_ = np.asarray(S, dtype=float)
    T = d2.shape[1]
    pd = as_probabilities(p_detect, "p_detect", T, low_open=True)
    lam = as_real(clutter_density, "clutter_density", 0.0, low_open=True)
    inside = d2 <= gate_threshold(gate_prob, S_.shape[-1])
    dens = np.where(inside, _gauss_density(d2, S_), 0.0) if d2.size else d2
    return np.vstack([1.0 - pd[None, :], dens * pd[None, :] / lam])


def mvm_from_positions(measurements: object, positions: object, covariances: object, *,
                       p_detect: object, gate_prob: float = 0.99,
                       clutter_density: float = 1.0) -> np.ndarray:
    r"""The MVM of a scan from the targets' predicted positions and covariances.

    The package's convention for row 0, the one :class:`JPDATracker` uses: a target
    has no validated measurement when it is not detected or its detection falls
    outside its gate, so

    .. math::

        w_{0t} = 1 - P_{D,t} P_G, \qquad
        w_{jt} = \frac{P_{D,t}\, \mathcal{N}(z_j; \hat z_t, S_t)}{\lambda}
        \ \text{inside the gate, else } 0,

    the standard JPDA weights (Fortmann, Bar-Shalom & Scheffe 1983). The paper's eq. (3),
    :math:`1 - P_{D,t}`, is the case :math:`P_G = 1` in row 0
    (:func:`modified_validation_matrix`). Pass the result to :func:`beta`.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
        The scan's measurements (``m = 0`` gives a single row).
    positions : array_like, shape (T, d)
        Predicted measurement of each target, :math:`\hat z_t = H x_t^-`.
    covariances : array_like, shape (T, d, d)
        Innovation covariance of each target, :math:`S_t = H P_t^- H^T + R`
        (symmetric positive definite).
    p_detect : float or array_like of shape (T,), keyword-only
        Detection probabilities :math:`P_{D,t}` in (0, 1].
    gate_prob : float, keyword-only, default 0.99
        Gate probability :math:`P_G` in (0, 1); the gate is the chi-square threshold of
        :func:`gate_threshold`.
    clutter_density : float, keyword-only, default 1
        Spatial density :math:`\lambda > 0` of false measurements, per unit of
        measurement space (the likelihoods are densities in the same units).

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)

    Examples
    --------
    >>> import numpy as np
    >>> from projtrack.jpda import beta, mvm_from_positions
    >>> w = mvm_from_positions([[0.1, 0.0], [2.9, 0.2]], [[0., 0.], [3., 0.]],
    ...                        np.stack([np.eye(2), np.eye(2)]), p_detect=0.9,
    ...                        clutter_density=0.01)
    >>> w.shape
    (3, 2)
    >>> round(float(w[0, 0]), 3)     # 1 - P_D P_G
    0.109
    """
    zp = as_array(positions, "positions", ndim=2)
    T, d = zp.shape
    S = as_array(covariances, "covariances", ndim=3)
    if S.shape != (T, d, d):
        raise ValueError(f"covariances must have shape ({T}, {d}, {d}) (one d x d matrix per row of "
                         f"positions), got {S.shape}")
    for t in range(T):
        as_covariance(S[t], f"covariances[{t}]", d, definite=True)
    z = as_array(measurements, "measurements")
    if z.size == 0:
        z = np.zeros((0, d))
    elif z.ndim != 2 or z.shape[1] != d:
        raise ValueError(f"measurements must have shape (m, {d}) like positions, got {z.shape}")
    w = modified_validation_matrix(z, zp, S, p_detect, gate_prob, clutter_density)
    pd = as_probabilities(p_detect, "p_detect", zp.shape[0], low_open=True)
    w[0] = 1.0 - pd * as_probability(gate_prob, "gate_prob", low_open=True, high_open=True)
    return w


def mvm_to_validation(mvm: object) -> np.ndarray:
    """Binary validation matrix, shape :math:`(m, T + 1)`, of an MVM (Section III.A: zeros
    coincide).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix.

    Returns
    -------
    numpy.ndarray of int8, shape (m, T + 1)
    """
    w = _check_mvm(mvm)
    return np.hstack([np.ones((w.shape[0] - 1, 1), dtype=np.int8), (w[1:] > 0).astype(np.int8)])

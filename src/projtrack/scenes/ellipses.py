"""Synthetic ellipses and projection data for Part I (Karl, Verghese & Willsky 1994, KVW).

KVW publish the ellipse of eq. (26), the projection geometry and the noise family of
their experiments (Sec. 7), but not their random draws nor the periodic drive ``B_k`` of
Sec. 7.2. This module makes:

* :data:`X26` and :func:`paper_projections` - the ellipse of eq. (26) and the five
  support directions ``theta_k = (k-1) pi / 5`` of Sec. 7.1;
* :func:`lognormal_noise` - the one-sided, zero-mean log-normal perturbation of Sec. 7:
  ``Y = c + W`` with ``Y`` log-normal of mean ``c`` and the given variance, so the left
  support point of ``W`` is ``-c`` and ``Y`` is never negative;
* :func:`snr_static`, :func:`snr_dynamic` - the two SNR definitions of Sec. 7.1 and 7.2
  (with the nominal noise standard deviation), and :func:`realized_snr_static` - the SNR of
  Sec. 7.1 with the root-mean-square of the perturbations actually drawn;
* :func:`periodic_drive` - a documented choice of periodic PSD drive for Sec. 7.2 (the
  paper shows it only as a picture, Fig. 10): ``B_k = beta s_k R(pi k / P) diag(1, rho)
  R(pi k / P)^T`` with ``s_k = (1 + cos(2 pi k / P)) / 2``; it pulses (period ``P``) and
  its orientation turns by ``pi`` per period, so it is periodic with period ``P``;
* :func:`random_ellipsoid`, :func:`random_projection` - random test problems;

Nothing here is tuned to reproduce a number of the paper.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_count, as_int, as_real, as_rng, only_value_errors

__all__ = ["X26", "paper_projections", "static_observations", "dynamic_experiment", "lognormal_noise", "snr_static", "snr_dynamic", "realized_snr_static", "periodic_drive",
           "random_ellipsoid", "random_projection", "rotation", "silhouette_points"]

#: The underlying ellipse of eq. (26) of KVW: semi-axes 2 and 1, major axis at pi/4.
X26: np.ndarray = 0.5 * np.array([[5.0, 3.0], [3.0, 5.0]])


def rotation(angle: float) -> np.ndarray:
    """The planar rotation matrix by ``angle`` (counter-clockwise)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def paper_projections(q: int = 5) -> list[np.ndarray]:
    """The 1-D projections ``C_k = [cos theta_k, sin theta_k]^T``, ``theta_k = (k-1) pi / q`` (Sec. 7.1)."""
    q = as_count(q, "q")
    th = np.arange(q) * np.pi / q
    return [np.array([[np.cos(t)], [np.sin(t)]]) for t in th]


def lognormal_noise(ideal: object, variance: float, rng: np.random.Generator) -> np.ndarray:
    """One-sided zero-mean log-normal perturbations ``W`` of positive ideal values ``c`` (Sec. 7).

    ``c + W`` is log-normal with mean ``c`` and variance ``variance``:
    ``sigma_ln^2 = log(1 + variance / c^2)``, ``mu_ln = log(c) - sigma_ln^2 / 2``.
    ``W`` therefore has mean 0, variance ``variance`` and left support point ``-c``.

    Parameters
    ----------
    ideal : array_like
        Positive ideal scalar observations ``c = C_k^T X C_k``.
    variance : float
        Variance of each perturbation (KVW use 0.3, 9 and 4).
    rng : numpy.random.Generator

    Returns
    -------
    numpy.ndarray
        ``W``, same shape as ``ideal``.
    """
    c = np.asarray(ideal, dtype=float)
    if not np.all(np.isfinite(c)) or np.any(c <= 0):
        raise ValueError("ideal must contain finite positive values")
    if not (np.isfinite(variance) and variance > 0):
        raise ValueError(f"variance must be a positive number, got {variance!r}")
    as_rng(rng)
    s2 = np.log1p(variance / c**2)
    mu = np.log(c) - s2 / 2
    return rng.lognormal(mu, np.sqrt(s2)) - c


def _ideal(ideal: object) -> np.ndarray:
    return as_array(ideal, "ideal", allow_empty=False)


def _sigma(sigma: float) -> float:
    # the noise standard deviation
    return as_real(sigma, "sigma", 0.0, low_open=True)


def snr_static(ideal: object, sigma: float) -> float:
    """SNR of Sec. 7.1: ``sqrt(sum c_k^2) / (sigma sqrt(n))``, ``n`` the number of observations.

    Raises ``ValueError`` unless ``sigma > 0`` and ``ideal`` is non-empty and finite.
    """
    c = _ideal(ideal).ravel()
    return float(np.sqrt(np.sum(c**2)) / (_sigma(sigma) * np.sqrt(c.size)))


def realized_snr_static(ideal: object, W: object) -> np.ndarray | float:
    """The SNR of Sec. 7.1 with ``sigma`` replaced by the RMS of the drawn perturbations ``W``.

    Parameters
    ----------
    ideal : array_like, shape (n,)
        Ideal observations ``c_k``.
    W : array_like, shape (n,) or (n_draws, n)
        One draw or a stack of draws of the perturbations (last axis: the observations).

    Returns
    -------
    float or numpy.ndarray
        ``sqrt(sum c_k^2) / (rms(W) sqrt(n))`` per draw.

    Raises
    ------
    ValueError
        If the shapes disagree, values are not finite or a draw is all zeros (infinite SNR).
    """
    c = _ideal(ideal).ravel()
    w = as_array(W, "W", finite=False)
    if w.ndim not in (1, 2) or w.shape[-1] != c.size:
        raise ValueError(f"W must have shape ({c.size},) or (n_draws, {c.size}), got {w.shape}")
    if not np.all(np.isfinite(w)):
        raise ValueError("W must contain only finite values")
    rms = np.sqrt(np.mean(w**2, axis=-1))
    if np.any(rms == 0):
        raise ValueError("W has a draw of all zeros: the realized SNR is infinite")
    out = np.sqrt(np.sum(c**2)) / (rms * np.sqrt(c.size))
    return float(out) if w.ndim == 1 else out


def snr_dynamic(ideal: object, sigma: float) -> float:
    """Average SNR of Sec. 7.2: the mean of the ideal scalar observations divided by ``sigma``.

    Raises ``ValueError`` unless ``sigma > 0`` and ``ideal`` is non-empty and finite.
    """
    return float(np.mean(_ideal(ideal)) / _sigma(sigma))


def periodic_drive(n_steps: int, beta: float = 2.0, period: int = 12, rho: float = 0.25) -> np.ndarray:
    """A periodic PSD drive ``B_0..B_{n_steps-1}`` for Sec. 7.2 (choice documented above).

    ``beta = 2`` makes the average ideal observation of the simulated ellipse of Sec. 7.2
    about 2, i.e. an average SNR about 1 with noise variance 4, as the paper states.

    Raises
    ------
    ValueError
        Unless ``n_steps`` and ``period`` are positive ints and ``beta``, ``rho`` are
        finite and non-negative.
    """
    n_steps = as_count(n_steps, "n_steps")
    period = as_count(period, "period")
    beta = only_value_errors(as_real, beta, "beta", 0)
    rho = only_value_errors(as_real, rho, "rho", 0)
    out = []
    for k in range(n_steps):
        s = (1 + np.cos(2 * np.pi * k / period)) / 2
        R = rotation(np.pi * k / period)
        B = beta * s * R @ np.diag([1.0, rho]) @ R.T
        out.append((B + B.T) / 2)
    return np.array(out).reshape(n_steps, 2, 2)


def random_ellipsoid(n: int, rng: np.random.Generator, min_axis: float = 0.5, max_axis: float = 2.0) -> np.ndarray:
    """A random ``n x n`` positive definite matrix: Haar-random axes, semi-axes uniform in [min, max].

    Raises ``ValueError`` unless ``n`` is a positive int and ``0 < min_axis <= max_axis``
    (finite); ``TypeError`` if ``rng`` is not a ``numpy.random.Generator``.
    """
    from scipy.stats import special_ortho_group

    n = as_count(n, "n")
    if not (np.isfinite(min_axis) and np.isfinite(max_axis) and 0 < min_axis <= max_axis):
        raise ValueError(f"need finite 0 < min_axis <= max_axis, got {min_axis!r}, {max_axis!r}")
    as_rng(rng)
    if n == 1:
        return np.array([[rng.uniform(min_axis, max_axis) ** 2]])
    Q = special_ortho_group.rvs(n, random_state=rng)
    ax = rng.uniform(min_axis, max_axis, size=n)
    X = (Q * ax**2) @ Q.T
    return (X + X.T) / 2


def random_projection(n: int, m: int, rng: np.random.Generator) -> np.ndarray:
    """A Haar-random ``n x m`` matrix with orthonormal columns (an m-dimensional view)."""
    n = only_value_errors(as_int, n, "n")
    m = only_value_errors(as_int, m, "m")
    if not (1 <= m <= n):
        raise ValueError(f"need 1 <= m <= n, got n={n}, m={m}")
    as_rng(rng)
    Q, R = np.linalg.qr(rng.normal(size=(n, m)))
    return Q * np.sign(np.diag(R))


def static_observations(variance: float, rng: np.random.Generator, X: np.ndarray | None = None,
                        q: int = 5) -> tuple[np.ndarray, np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """One draw of the static experiment of Sec. 7.1 of KVW.

    Ideal squared supports ``c_k = C_k^T X C_k`` of ``X`` (default eq. 26) in the ``q``
    directions of :func:`paper_projections`, perturbed by :func:`lognormal_noise`.

    Returns
    -------
    ideal : ndarray (q,)
    W : ndarray (q,)
        The perturbations drawn.
    Ys : list of (1, 1) arrays
        The observations ``c_k + W_k``.
    Cs : list of (2, 1) arrays
    """
    X = X26 if X is None else np.asarray(X, float)
    Cs = paper_projections(q)
    ideal = np.array([float(C[:, 0] @ X @ C[:, 0]) for C in Cs])
    W = lognormal_noise(ideal, variance, rng)
    return ideal, W, [np.array([[v]]) for v in ideal + W], Cs


def dynamic_experiment(rng: np.random.Generator, n_steps: int = 24, variance: float = 4.0,
                       tau: float = 0.8, alpha: float = 0.9, psi: float = 0.0, phi: float = np.pi / 15,
                       drive: object = None) -> dict:
    """The dynamic ellipse of Sec. 7.2 of KVW and its noisy single-view observations.

    ``X_0`` is eq. (26), ``A_k = A(tau, alpha, psi, phi)`` of eq. (23) (imported lazily from
    :mod:`projtrack.ellipsoids`), ``C_k = [1, 0]^T`` and log-normal noise of the given
    variance on ``C_k^T X_k C_k``. ``drive`` is the sequence ``B_0..B_{n_steps-2}`` (shape
    ``(n_steps - 1, 2, 2)``, symmetric PSD); ``None`` means ``periodic_drive(n_steps - 1)``,
    our documented choice (the paper shows its drive only as a picture).

    Raises
    ------
    ValueError
        If ``n_steps < 2`` or ``drive`` has the wrong shape, is not finite, symmetric or PSD.

    Returns
    -------
    dict with keys ``A`` (2x2), ``As`` (list), ``Bs`` (n_steps-1, 2, 2), ``Xs``
    (n_steps, 2, 2), ``C``, ``Cs`` (list), ``ideal``, ``W``, ``Ys`` (list of 1x1).
    """
    from projtrack import ellipsoids as E

    n_steps = as_count(n_steps, "n_steps", minimum=2)  # at least one transition
    A = E.shaping_matrix(tau, alpha, psi, phi)
    if drive is None:
        Bs = periodic_drive(n_steps - 1)
    else:
        try:
            Bs = np.array(drive, dtype=float)
        except (TypeError, ValueError):
            raise ValueError("drive must be an array of shape (n_steps - 1, 2, 2)") from None
        if Bs.shape != (n_steps - 1, 2, 2):
            raise ValueError(f"drive must have shape ({n_steps - 1}, 2, 2) for n_steps={n_steps}, got {Bs.shape}")
        if not np.all(np.isfinite(Bs)):
            raise ValueError("drive must be finite")
        if np.max(np.abs(Bs - Bs.transpose(0, 2, 1))) > 1e-9 * max(1.0, float(np.max(np.abs(Bs)))):
            raise ValueError("every drive matrix B_k must be symmetric")
        Bs = (Bs + Bs.transpose(0, 2, 1)) / 2
        if np.min(np.linalg.eigvalsh(Bs)) < -1e-9 * max(1.0, float(np.max(np.abs(Bs)))):
            raise ValueError("every drive matrix B_k must be positive semidefinite")
    As = [A] * (n_steps - 1)
    Xs = E.simulate(X26, As, Bs)
    C = np.array([[1.0], [0.0]])
    ideal = Xs[:, 0, 0].copy()
    W = lognormal_noise(ideal, variance, rng)
    return {"A": A, "As": As, "Bs": Bs, "Xs": Xs, "C": C, "Cs": [C] * n_steps, "ideal": ideal, "W": W,
            "Ys": [np.array([[v]]) for v in ideal + W]}


def silhouette_points(X: np.ndarray, C: np.ndarray, n_points: int, noise: float,
                      rng: np.random.Generator) -> np.ndarray:
    """Noisy boundary points of the silhouette of ellipsoid ``X`` in the view ``C`` (m = 2).

    The exact shadow ``Y = C^T X C`` (eq. 4 of KVW) is sampled at ``n_points`` angles chosen
    uniformly at random; each point is moved along the boundary normal by Gaussian noise of
    standard deviation ``noise`` (an edge detector's error), in the coordinates of ``C``.

    Raises
    ------
    ValueError
        If ``X`` is not a symmetric positive definite-in-the-view matrix, ``C`` is not an
        ``n x 2`` matrix with orthonormal columns, ``n_points`` is not a positive int or
        ``noise`` is negative or not finite.
    TypeError
        If ``rng`` is not a ``numpy.random.Generator``.
    """
    from projtrack import ellipsoids as E

    Xm = E.check_symmetric(X, "X")
    Cm = E.check_orthonormal(C, "C", Xm.shape[0])
    if Cm.shape[1] != 2:
        raise ValueError(f"silhouette_points makes 2-D silhouettes: C must be n x 2, got shape {Cm.shape}")
    n_points = as_count(n_points, "n_points")
    noise = only_value_errors(as_real, noise, "noise", 0)  # a standard deviation
    as_rng(rng)
    Y = E.project(Xm, Cm)
    lam, V = np.linalg.eigh(Y)
    if lam[0] <= 1e-12 * max(1.0, lam[1]):
        raise ValueError("the silhouette of X in the view C is degenerate (X must be positive definite in the view)")
    t = rng.uniform(0, 2 * np.pi, n_points)
    u = np.stack([np.cos(t), np.sin(t)], axis=1)
    p = (u * np.sqrt(lam)) @ V.T  # boundary points
    normal = (u / np.sqrt(lam)) @ V.T
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return p + noise * rng.normal(size=(n_points, 1)) * normal

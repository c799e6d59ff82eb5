"""Sec. 6 of KVW: dynamic ellipsoids, eq. (20)-(25): simulation, observability, batch estimates."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack._validation import as_array, as_choice, as_real, only_value_errors

from .checks import _as_size, _check_Cs, _check_Ys, _dim, _mats, _n_from_dim, _rank, _seq, check_symmetric
from .halfspace import halfspace_reconstruct
from .intervals import interval_bounds
from .operators import congruence_operator, smat, svec
from .sdp import sdp_reconstruct

__all__ = ["shaping_matrix", "simulate", "state_space", "observability_matrix", "batch_rhs",
           "batch_estimate_many", "reconstruct_many", "batch_estimate", "is_observable"]


def _rot_t(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, s], [-s, c]])


def shaping_matrix(tau: float, alpha: float, psi: float, phi: float) -> np.ndarray:
    """The planar shaping matrix ``A`` of equation (23).

    ``A = R^T(psi) diag(tau, tau) diag(alpha, 1/alpha) R^T(phi)`` with ``R`` the rotation
    matrix; ``X -> A^T X A`` rotates the ellipse by ``psi``, magnifies it by ``tau``,
    stretches axis 1 by ``alpha`` and axis 2 by ``1/alpha``, then rotates by ``phi``
    (eq. 22 applied through eq. 3).

    Parameters
    ----------
    tau : float
        Magnification (> 0).
    alpha : float
        Stretch of axis 1 (axis 2 by ``1/alpha``), > 0.
    psi, phi : float
        Rotation angles, radians.

    Returns
    -------
    numpy.ndarray, shape (2, 2)
    """
    # any bad value is a ValueError here, a wrong kind included
    tau, alpha, psi, phi = (only_value_errors(as_real, v, k)
                            for k, v in (("tau", tau), ("alpha", alpha), ("psi", psi), ("phi", phi)))
    if alpha == 0:
        raise ValueError("alpha must be non-zero (the stretch is diag(alpha, 1/alpha))")
    return _rot_t(psi) @ (tau * np.eye(2)) @ np.diag([alpha, 1.0 / alpha]) @ _rot_t(phi)


def simulate(X0: object, As: object, Bs: object = None, n_steps: int | None = None) -> np.ndarray:
    """Simulate equation (20), :math:`X_{k+1} = A_k^T X_k A_k + B_k`; returns ``(n_steps +
    1, n, n)``.

    Parameters
    ----------
    X0 : array_like, shape (n, n)
        The initial ellipsoid (symmetric).
    As : array_like, shape (n, n) or (K, n, n)
        One transition matrix (constant dynamics) or a sequence of them.
    Bs : array_like, shape (n, n) or (K, n, n), optional
        The drive, symmetric; ``None`` (default) means no drive.
    n_steps : int, optional
        Number of steps; default ``len(As)`` for a sequence (required for one matrix).

    Returns
    -------
    numpy.ndarray, shape (n_steps + 1, n, n)
        The ellipsoids from :math:`X_0` to the last step.
    """
    X = check_symmetric(X0, "X0")
    n = X.shape[0]
    if n_steps is None:
        if np.ndim(As) != 3:
            raise ValueError("n_steps is required when As is a single matrix")
        n_steps = len(As)  # type: ignore[arg-type]
    n_steps = _as_size(n_steps, "n_steps", 0)
    Al = _seq(As, n_steps, "As", n, True, False) if n_steps else []
    Bl = _seq(np.zeros((n, n)) if Bs is None else Bs, n_steps, "Bs", n, True, True) if n_steps else []
    out = [X]
    for k in range(n_steps):
        X = Al[k].T @ X @ Al[k] + Bl[k]
        out.append((X + X.T) / 2)
    return np.array(out)


def state_space(As: Sequence[np.ndarray], Bs: Sequence[np.ndarray] | None = None) -> tuple[list[np.ndarray], list[np.ndarray]]:
    r"""The vector form (21): :math:`\tilde A_k` (the matrix of :math:`X \mapsto A_k^T X
    A_k`) and :math:`b_k = \operatorname{svec}(B_k)`.

    Parameters
    ----------
    As : sequence of (n, n) arrays
        Transition matrices of eq. (20).
    Bs : sequence of (n, n) arrays, optional
        Drive of eq. (20); None means no drive.

    Returns
    -------
    (A_tilde, b) : (list of numpy.ndarray, list of numpy.ndarray)
        The ``n(n+1)/2`` square matrices and the drive vectors.
    """
    At = [congruence_operator(A) for A in As]
    if Bs is None:
        bt = [np.zeros(At[0].shape[0]) for _ in At]
    else:
        bt = [svec(check_symmetric(B, f"Bs[{k}]")) for k, B in enumerate(Bs)]
    return At, bt


def observability_matrix(Cs: Sequence[object], As: Sequence[object]) -> np.ndarray:
    r"""The batch (observability) matrix of equation (25): rows :math:`\tilde C_k \tilde
    A_{k-1} \cdots \tilde A_0`.

    ``Cs`` has ``r + 1`` projections (times ``0..r``); ``As`` is one ``n x n`` matrix (a
    constant dynamics) or a sequence of exactly ``r`` matrices ``A_0..A_{r-1}``.

    Parameters
    ----------
    Cs : sequence of (n, m_k) arrays
        The views at times ``0..r``.
    As : array_like, shape (n, n) or (r, n, n)
        The transition matrices.

    Returns
    -------
    numpy.ndarray, shape (sum of m_k(m_k+1)/2, n(n+1)/2)

    Raises
    ------
    ValueError
        If ``As`` is a sequence whose length is not ``len(Cs) - 1`` (extra matrices are
        not silently ignored: they would belong to views that were not given).
    """
    Cl = _check_Cs(Cs)
    n = Cl[0].shape[0]
    As_arr = _mats(As, "As", n)
    Al = _seq(As_arr, len(Cl) - 1, "As", n, True, False, exact=True)
    Phi = np.eye(_dim(n))
    rows = []
    for k, C in enumerate(Cl):
        rows.append(congruence_operator(C) @ Phi)
        if k < len(Al):
            Phi = congruence_operator(Al[k]) @ Phi
    return np.vstack(rows)


def batch_rhs(Ys: Sequence[object], Cs: Sequence[object], As: Sequence[object], Bs: Sequence[object] | None = None) -> np.ndarray:
    """The corrected observation vector ``y`` of equation (25) (known drive removed).

    ``As`` and ``Bs`` are one matrix each (constant) or sequences of exactly
    ``len(Cs) - 1`` matrices (ValueError otherwise).

    Parameters
    ----------
    Ys : sequence of (m_k, m_k) arrays
        The observed projections.
    Cs : sequence of (n, m_k) arrays
        Their views.
    As, Bs : array_like
        Transition matrices and drive of eq. (20) (``Bs=None``: no drive).

    Returns
    -------
    numpy.ndarray
        The stacked corrected observations.
    """
    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    K = len(Cl)
    Al = _seq(_mats(As, "As", n), K - 1, "As", n, True, False, exact=True)
    Bl = _seq(np.zeros((n, n)) if Bs is None else _mats(Bs, "Bs", n),
              K - 1, "Bs", n, True, True, exact=True)
    forced = np.zeros(_dim(n))  # response at time k to the drive alone, zero initial state
    out = []
    for k, (C, Y) in enumerate(zip(Cl, Yl)):
        out.append(svec(Y) - congruence_operator(C) @ forced)
        if k < len(Al):
            forced = congruence_operator(Al[k]) @ forced + svec(Bl[k])
    return np.concatenate(out)


def is_observable(Cs: Sequence[object], As: Sequence[object]) -> bool:
    """True when the observability matrix of equation (25) has full column rank
    :math:`n(n+1)/2`.

    Parameters
    ----------
    Cs : sequence of (n, m_k) arrays
        The views at times ``0..r``.
    As : array_like, shape (n, n) or (r, n, n)
        The transition matrices.

    Returns
    -------
    bool
    """
    O = observability_matrix(Cs, As)
    return _rank(O) == O.shape[1]


def batch_estimate(Ys: Sequence[object], Cs: Sequence[object], As: Sequence[object], Bs: Sequence[object] | None = None,
                   lower: object = None, upper: object = None, method: str = "ls",
                   **options: object) -> np.ndarray:
    r"""Batch estimate of :math:`X_0` from :math:`Y_0, \dots, Y_r` (equation 24) and its
    propagation (equation 20).

    ``method="ls"`` is ``x_0 = C^+ y`` (Sec. 6.2); ``"halfspace"``/``"sdp"`` impose
    ``lower <= X_0 <= upper``. Raises ``ValueError`` if the system is not observable
    (rank of eq. 25 below ``n(n+1)/2``) and ``method="ls"``.

    Parameters
    ----------
    Ys : sequence of (m_k, m_k) arrays
        Observed projections :math:`Y_0, \dots, Y_r`.
    Cs : sequence of (n, m_k) arrays
        Their orthonormal views.
    As : array_like, shape (n, n) or (r, n, n)
        Transition matrices of eq. (20), one per step between views (or one for all).
    Bs : array_like, optional
        Known drive of eq. (20), like ``As``; ``None`` means no drive.
    lower, upper : array_like or float, optional
        Interval bounds on :math:`X_0`, as in :func:`reconstruct`.
    method : {"ls", "halfspace", "sdp"}
        As in :func:`reconstruct`.
    **options
        Passed to the constrained solver.

    Returns
    -------
    numpy.ndarray, shape (r + 1, n, n)
        The estimated states ``X_0 .. X_r``.
    """
    method = as_choice(method, "method", ("ls", "halfspace", "sdp"))
    O = observability_matrix(Cs, As)
    y = batch_rhs(Ys, Cs, As, Bs)
    n = _n_from_dim(O.shape[1])
    L, U = interval_bounds(lower, upper, n)
    K = len(list(Cs))
    if method == "ls":
        if L is not None or U is not None:
            raise ValueError("method='ls' is unconstrained: use 'halfspace' or 'sdp' with bounds")
        r = _rank(O)
        if r < O.shape[1]:
            raise ValueError(f"not observable: the observability matrix (eq. 25) has rank {r} < {O.shape[1]}")
        X0 = smat(np.linalg.lstsq(O, y, rcond=None)[0])
    elif method == "halfspace":
        X0 = halfspace_reconstruct(None, None, L, U, A=O, y=y, **options).X  # type: ignore[arg-type]
    else:
        X0 = sdp_reconstruct(O, y, L, U, **options)  # type: ignore[arg-type]
    return simulate(X0, _mats(As, "As", n), None if Bs is None else _mats(Bs, "Bs", n), K - 1)


def batch_estimate_many(Ys: object, Cs: Sequence[object], As: Sequence[object] | object,
                        Bs: Sequence[object] | object | None = None) -> np.ndarray:
    """Unconstrained batch LS estimate (equations 24-25) for many data sets at once,
    propagated by equation (20).

    The estimate ``x_0 = C^+ (y - forced)`` is linear in the data, so the observability
    matrix, the drive's response and the propagation are computed once and applied to all
    data sets by matrix products (Monte Carlo studies over thousands of noise draws).
    For one data set it equals :func:`batch_estimate` with ``method="ls"``.

    Parameters
    ----------
    Ys : array_like
        The observations of ``D`` data sets: shape ``(D, K, m, m)`` (symmetric ``m x m``
        observations), or ``(D, K)`` when every view is a single direction (``m = 1``).
    Cs : sequence of K arrays (n, m)
        The views (orthonormal columns).
    As : array (n, n) or sequence of K - 1 arrays
        The dynamics ``A_k`` (one matrix: constant).
    Bs : array (n, n), sequence of K - 1 symmetric arrays, or None
        The known drive ``B_k`` (None: no drive).

    Returns
    -------
    numpy.ndarray, shape (D, K, n, n)
        The estimated states ``X_0 .. X_{K-1}`` of every data set.

    Raises
    ------
    ValueError
        If the shapes do not match, the data are not finite, or the system is not
        observable (rank of eq. 25 below ``n(n+1)/2``).
    """
    Cl = _check_Cs(Cs)
    n, m, K = Cl[0].shape[0], Cl[0].shape[1], len(Cl)
    if any(C.shape[1] != m for C in Cl):
        raise ValueError("batch_estimate_many needs views of one size m (all Cs of shape (n, m))")
    Y = as_array(Ys, "Ys")
    if m == 1 and Y.ndim == 2:
        Y = Y[:, :, None, None]
    if Y.ndim != 4 or Y.shape[1:] != (K, m, m):
        raise ValueError(f"Ys must have shape (D, {K}, {m}, {m})" + (f" or (D, {K})" if m == 1 else "")
                         + f", got {np.shape(Ys)}")
    if not np.allclose(Y, np.swapaxes(Y, 2, 3)):
        raise ValueError("every observation in Ys must be symmetric")
    Al = _seq(_mats(As, "As", n), K - 1, "As", n, True, False, exact=True) if K > 1 else []
    Bl = (_seq(np.zeros((n, n)) if Bs is None else _mats(Bs, "Bs", n), K - 1, "Bs", n, True, True, exact=True)
          if K > 1 else [])
    cache: dict[bytes, np.ndarray] = {}

    def op(M: np.ndarray) -> np.ndarray:
        # congruence operators of repeated views and dynamics are computed once
        key = M.tobytes() + bytes(M.shape)
        if key not in cache:
            cache[key] = congruence_operator(M)
        return cache[key]

    # response to the drive alone (zero initial state) and transition matrices Phi_k = A~_{k-1} ... A~_0
    N = _dim(n)
    iu = np.triu_indices(n)
    bscale = np.where(iu[0] == iu[1], 1.0, np.sqrt(2.0))
    forced, Phi = [np.zeros(N)], [np.eye(N)]
    for k in range(K - 1):
        At = op(Al[k])
        forced.append(At @ forced[-1] + Bl[k][iu] * bscale)
        Phi.append(At @ Phi[-1])
    forced_a, Phi_a = np.array(forced), np.array(Phi)
    O = np.vstack([op(C) @ P for C, P in zip(Cl, Phi_a)])  # eq. (25)
    r = _rank(O)
    if r < O.shape[1]:
        raise ValueError(f"not observable: the observability matrix (eq. 25) has rank {r} < {O.shape[1]}")
    iu = np.triu_indices(m)
    scale = np.where(iu[0] == iu[1], 1.0, np.sqrt(2.0))
    y = (Y[:, :, iu[0], iu[1]] * scale).reshape(len(Y), -1)  # svec of every observation, stacked
    off = np.concatenate([op(C) @ f for C, f in zip(Cl, forced_a)])
    x0 = np.linalg.lstsq(O, (y - off).T, rcond=None)[0].T  # (D, N)
    states = np.einsum("kij,dj->dki", Phi_a, x0) + forced_a[None]
    return smat(states.reshape(-1, N)).reshape(len(Y), K, n, n)


def reconstruct_many(Ys: object, Cs: Sequence[object]) -> np.ndarray:
    r"""Unconstrained LS estimates :math:`x = \mathcal{C}^+ y` (equation 15) of many data
    sets at once.

    The static problem is the dynamic one with ``A = I`` and no drive, so this is
    :func:`batch_estimate_many` at time 0; for one data set it equals :func:`reconstruct`.

    Parameters
    ----------
    Ys : array_like
        Observations of ``D`` data sets, shape ``(D, q, m, m)`` or ``(D, q)`` for ``m = 1``.
    Cs : sequence of q arrays (n, m)
        The views.

    Returns
    -------
    numpy.ndarray, shape (D, n, n)

    Raises
    ------
    ValueError
        If the shapes do not match or the stacked operator (eq. 14) is rank deficient.
    """
    Cl = _check_Cs(Cs)
    return batch_estimate_many(Ys, Cl, np.eye(Cl[0].shape[0]))[:, 0]

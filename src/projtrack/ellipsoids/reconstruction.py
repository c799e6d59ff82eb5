"""Sec. 5 of KVW: reconstruction from projections, condition (19) and ellipse extraction."""

from __future__ import annotations

import warnings
from typing import Sequence

import numpy as np

from projtrack._validation import as_array, as_choice

from .checks import _check_Cs, _check_Ys, _dim, _rank, check_symmetric
from .geometry import is_psd
from .halfspace import halfspace_reconstruct
from .intervals import interval_bounds
from .operators import congruence_operator, smat, svec
from .sdp import sdp_reconstruct

__all__ = ["RankDeficientWarning", "reconstruct", "condition19", "fit_centered_ellipse"]


class RankDeficientWarning(UserWarning):
    """The stacked operator of eq. (14) (or (25)) does not have full column rank."""


def reconstruct(Ys: Sequence[object], Cs: Sequence[object], lower: object = None, upper: object = None,
                method: str = "ls", *, rank_deficient: str = "raise", **options: object) -> np.ndarray:
    """Reconstruct an ellipsoid ``X`` (``n x n``) from its projections ``Y_i = C_i^T X C_i``.

    Parameters
    ----------
    Ys : sequence of (m_i, m_i) arrays
        Observed projections (eq. 16); scalars are accepted for ``m_i = 1``.
    Cs : sequence of (n, m_i) arrays
        Orthonormal bases of the projection subspaces (1-D arrays are single columns).
    lower, upper : array_like or float, optional
        Interval bounds ``lower <= X <= upper`` (Sec. 5.2); a scalar ``a`` means ``a I``.
        ``lower=0`` with no upper is the PSD constraint. Ignored by ``method="ls"`` (which
        raises if bounds are given).
    method : {"ls", "halfspace", "sdp"}
        ``"ls"``: unconstrained least squares ``x = C^+ y`` (eqs. 15, 17-18);
        ``"halfspace"``: Algorithm 1 of the Appendix (see :func:`halfspace_reconstruct`
        for the iteration history); ``"sdp"``: the same problem by cvxpy/Clarabel
        (:func:`sdp_reconstruct`). With no bound the constrained methods equal ``"ls"``.
        The two constrained methods agree to a relative Frobenius distance of 1e-3 and a
        relative objective gap of 1e-6 (tested; typically 1e-5 and 1e-8): Algorithm 1
        stops slightly outside the interval (eigenvalues >= -1e-9 ||X||), the interior
        point solution lies slightly inside it.
    rank_deficient : {"raise", "warn"}
        What ``"ls"`` does when the stacked operator of eq. (14) has rank below
        ``n(n+1)/2`` (Sec. 5.1: no unique solution): raise ``ValueError`` (default) or emit
        :class:`RankDeficientWarning` and return the minimum-norm solution.
    **options
        Passed to :func:`halfspace_reconstruct` (``tol``, ``max_iter``...) or to the cvxpy
        solver (``solver``, solver tolerances).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric estimate (not necessarily PSD for ``"ls"``).
    """
    method = as_choice(method, "method", ("ls", "halfspace", "sdp"))
    rank_deficient = as_choice(rank_deficient, "rank_deficient", ("raise", "warn"))
    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    L, U = interval_bounds(lower, upper, n)
    A = np.vstack([congruence_operator(C) for C in Cl])
    y = np.concatenate([svec(Y) for Y in Yl])
    if method == "ls":
        if L is not None or U is not None:
            raise ValueError("method='ls' is unconstrained: use method='halfspace' or 'sdp' with bounds")
        if options:
            raise TypeError(f"method='ls' takes no options, got {sorted(options)}")
        r = _rank(A)
        if r < A.shape[1]:
            msg = (f"the stacked operator of eq. (14) has rank {r} < n(n+1)/2 = {A.shape[1]}: the "
                   "projections do not determine X uniquely (Sec. 5.1 of KVW)")
            if rank_deficient == "raise":
                raise ValueError(msg + "; pass rank_deficient='warn' for the minimum-norm solution")
            warnings.warn(msg + "; returning the minimum-norm solution", RankDeficientWarning, stacklevel=2)
        return smat(np.linalg.pinv(A) @ y)
    if method == "halfspace":
        return halfspace_reconstruct(None, None, L, U, A=A, y=y, **options).X  # type: ignore[arg-type]
    return sdp_reconstruct(A, y, L, U, **options)  # type: ignore[arg-type]


def condition19(Cs: Sequence[object], Ws: Sequence[object], X: object) -> tuple[bool, float, float]:
    """Sufficient condition (19) of KVW for the LS estimate to be PSD.

    ``sigma_min(C)^{-1} sqrt(sum ||W_i||_F^2) <= lambda_min(X)`` with ``C`` the stacked
    operator of eq. (14) and ``W_i`` the perturbations of the observations (eq. 16).

    ``X`` is the true ellipsoid, so it must be PSD. For a *singular* ``X`` (a degenerate
    ellipsoid, ``lambda_min(X) = 0``; eigenvalues within the PSD tolerance of
    :func:`is_psd` below zero are read as 0) the right-hand side is 0 and the condition
    holds only for noise-free data, where the LS estimate is ``X`` itself: any
    perturbation can make the estimate of a degenerate ellipsoid indefinite. When the
    stacked operator is rank deficient (``sigma_min = 0``) ``lhs`` is ``inf`` and the
    condition does not hold.

    Returns
    -------
    (holds, lhs, rhs) : (bool, float, float)

    Raises
    ------
    ValueError
        If ``X`` is not PSD, or ``Cs``/``Ws`` are inconsistent (see :func:`reconstruct`).
    """
    Cl = _check_Cs(Cs)
    Xm = check_symmetric(X, "X", Cl[0].shape[0])
    if not is_psd(Xm):
        raise ValueError("X (the true ellipsoid) must be positive semidefinite for condition (19)")
    Wl = _check_Ys(Ws, Cl, "Ws")
    s = np.linalg.svd(np.vstack([congruence_operator(C) for C in Cl]), compute_uv=False)
    smin = float(s[-1]) if len(s) >= _dim(Xm.shape[0]) else 0.0
    noise = float(np.sqrt(sum(np.sum(W**2) for W in Wl)))
    lhs = np.inf if smin <= 1e-14 else noise / smin
    rhs = max(float(np.linalg.eigvalsh(Xm)[0]), 0.0)
    return bool(lhs <= rhs), float(lhs), rhs


def fit_centered_ellipse(points: object) -> np.ndarray:
    """Fit a centered ellipsoid ``{z : z^T Y^{-1} z <= 1}`` to boundary points (ellipsoid extraction).

    KVW (Sec. 5) assume the projected ellipsoids ``Y_i`` are extracted from the raw data
    first. This is the simplest such step: linear least squares for ``Q = Y^{-1}`` in
    ``p^T Q p = 1`` over the points ``p`` (rows), then ``Y = Q^{-1}``.

    Parameters
    ----------
    points : array_like, shape (k, m)
        At least ``m(m+1)/2`` points spread around the boundary.

    Returns
    -------
    numpy.ndarray, shape (m, m)

    Raises
    ------
    ValueError
        If there are too few points, the points do not determine a conic (collinear
        points, points on fewer than ``m`` lines through the origin...: the design matrix
        of the linear LS problem is rank deficient, relative condition below 1e-10), or
        the fitted conic is not an ellipse.
    """
    P = as_array(points, "points")
    if P.ndim != 2 or P.shape[1] < 1:
        raise ValueError(f"points must be a (k, m) array, got shape {P.shape}")
    m = P.shape[1]
    if P.shape[0] < _dim(m):
        raise ValueError(f"need at least {_dim(m)} points for an ellipse in {m} dimensions, got {P.shape[0]}")
    G = svec(np.einsum("ki,kj->kij", P, P))  # <p p^T, Q> = svec(p p^T) . svec(Q)
    sv = np.linalg.svd(G, compute_uv=False)
    if sv[0] == 0 or sv[-1] <= 1e-10 * sv[0]:
        raise ValueError("points are degenerate (e.g. collinear or at the origin): they do not determine "
                         f"a centered ellipse in {m} dimensions (design matrix rank deficient)")
    q, *_ = np.linalg.lstsq(G, np.ones(P.shape[0]), rcond=None)
    Q = smat(q)
    lam = np.linalg.eigvalsh(Q)
    if lam[0] <= 1e-10 * abs(lam[-1]):
        raise ValueError("the fitted conic is not an ellipse (points too noisy or degenerate, e.g. "
                         "on a line: the fitted Q = Y^{-1} is indefinite or singular)")
    Y = np.linalg.inv(Q)
    return (Y + Y.T) / 2

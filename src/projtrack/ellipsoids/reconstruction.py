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

__all__ = ["RankDeficientWarning", "IndefiniteDataWarning", "reconstruct", "condition19",
           "fit_centered_ellipse"]


class RankDeficientWarning(UserWarning):
    """The stacked operator of equation (14) (or (25)) does not have full column rank."""


class IndefiniteDataWarning(UserWarning):
    """An observed projection is not positive semidefinite (a negative squared support value).

    No ellipsoid projects to such data: the unconstrained estimate may be indefinite,
    i.e. not an ellipsoid. The interval-constrained methods (``lower=0``) return a PSD
    estimate from the same data.
    """


def _warn_indefinite(Yl: list[np.ndarray]) -> None:
    for k, Y in enumerate(Yl):
        lam = float(np.linalg.eigvalsh(Y)[0])
        if lam < -1e-12 * max(1.0, float(np.abs(Y).max())):
            what = (f"a negative squared support value {Y[0, 0]:.3g}" if Y.shape == (1, 1)
                    else f"smallest eigenvalue {lam:.3g}")
            warnings.warn(f"Ys[{k}] is not positive semidefinite ({what}): no ellipsoid projects to it, "
                          "and the unconstrained estimate may be indefinite; use lower=0 with "
                          "method='halfspace' or 'sdp' for a PSD estimate", IndefiniteDataWarning,
                          stacklevel=3)
            return


def reconstruct(Ys: Sequence[object], Cs: Sequence[object], lower: object = None, upper: object = None,
                method: str = "ls", *, rank_deficient: str = "raise", indefinite: str = "warn",
                **options: object) -> np.ndarray:
    r"""Reconstruct an ellipsoid :math:`X` (``n x n``) from its projections :math:`Y_i = C_i^T X C_i`.

    The ellipsoid is :math:`\{z : z^T X^{-1} z \le 1\}` (KVW eq. 2); a 1-D projection on
    a unit vector :math:`c` is the squared support value :math:`Y = c^T X c = h(c)^2`.
    The least-squares estimate is :math:`\operatorname{svec}(\hat X) = \mathcal{C}^+ y`
    with :math:`\mathcal{C}` the stacked operator of eq. (14) and :math:`y` the stacked
    :math:`\operatorname{svec}(Y_i)` (eqs. 15-18).

    Parameters
    ----------
    Ys : sequence of (m_i, m_i) arrays
        Observed projections (eq. 16); scalars are accepted for :math:`m_i = 1`
        (squared support values).
    Cs : sequence of (n, m_i) arrays
        Orthonormal bases of the projection subspaces (1-D arrays are single columns:
        for unit directions stored as the rows of a ``(k, n)`` array pass
        ``list(directions)``).
    lower, upper : array_like or float, optional
        Interval bounds :math:`L \le X \le U` (Sec. 5.2); a scalar :math:`a` means
        :math:`a I`. ``lower=0`` with no upper is the PSD constraint. Not allowed with
        ``method="ls"``.
    method : {"ls", "halfspace", "sdp"}
        ``"ls"``: unconstrained least squares (eqs. 15, 17-18);
        ``"halfspace"``: Algorithm 1 of the Appendix (see :func:`halfspace_reconstruct`
        for the iteration history); ``"sdp"``: the same problem by cvxpy/Clarabel
        (:func:`sdp_reconstruct`, needs ``pip install "projtrack[sdp]"``). With no bound
        the constrained methods equal ``"ls"``. The two constrained methods agree to a
        relative Frobenius distance of 1e-3 and a relative objective gap of 1e-6
        (tested; typically 1e-5 and 1e-8): Algorithm 1 stops slightly outside the
        interval (eigenvalues :math:`\ge -10^{-9} \|X\|`), the interior point solution
        lies slightly inside it.
    rank_deficient : {"raise", "warn"}
        What ``"ls"`` does when the stacked operator of eq. (14) has rank below
        :math:`n(n+1)/2` (Sec. 5.1: no unique solution): raise ``ValueError`` (default) or
        emit :class:`RankDeficientWarning` and return the minimum-norm solution.
    indefinite : {"warn", "ignore"}
        What an unconstrained estimate (no ``lower`` bound) does with an observation
        :math:`Y_i` that is not positive semidefinite: emit
        :class:`IndefiniteDataWarning` (default) or nothing (for studies that perturb the
        data on purpose, as the book's Sec. 5 experiments do).
    **options
        Passed to :func:`halfspace_reconstruct` (``tol``, ``max_iter``...) or to the cvxpy
        solver (``solver``, solver tolerances).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric estimate (not necessarily PSD for ``"ls"``).

    Raises
    ------
    TypeError, ValueError
        If ``Cs`` or ``Ys`` are malformed (the message names the item, e.g.
        ``Cs[2] must have orthonormal columns``), or the projections do not determine
        :math:`X` (``rank_deficient="raise"``).

    Warns
    -----
    IndefiniteDataWarning
        When an unconstrained estimate (no ``lower`` bound) is computed from an
        observation :math:`Y_i` that is not positive semidefinite, e.g. a negative
        squared support value: no ellipsoid has such a projection and the estimate may
        be indefinite (``indefinite="ignore"`` silences it).

    Examples
    --------
    An ellipse with semi-axes 3 and 1, rotated by 30 degrees, seen through the squared
    support values of 12 directions with noise:

    >>> import numpy as np
    >>> from projtrack.ellipsoids import axes, project, reconstruct
    >>> R = np.array([[np.cos(np.pi / 6), -np.sin(np.pi / 6)],
    ...               [np.sin(np.pi / 6), np.cos(np.pi / 6)]])
    >>> X = R @ np.diag([9.0, 1.0]) @ R.T                 # semi-axes 3 and 1
    >>> phi = np.linspace(0, np.pi, 12, endpoint=False)
    >>> Cs = [np.array([np.cos(p), np.sin(p)]) for p in phi]
    >>> rng = np.random.default_rng(0)
    >>> Ys = [project(X, C) + rng.normal(0, 0.05) for C in Cs]
    >>> X_hat = reconstruct(Ys, Cs)
    >>> lengths, _ = axes(X_hat)
    >>> np.round(lengths, 2)
    array([3., 1.])
    """
    method = as_choice(method, "method", ("ls", "halfspace", "sdp"))
    rank_deficient = as_choice(rank_deficient, "rank_deficient", ("raise", "warn"))
    indefinite = as_choice(indefinite, "indefinite", ("warn", "ignore"))
    Cl = _check_Cs(Cs)
    Yl = _check_Ys(Ys, Cl)
    n = Cl[0].shape[0]
    L, U = interval_bounds(lower, upper, n)
    if L is None and indefinite == "warn":
        _warn_indefinite(Yl)
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
    r"""Sufficient condition (19) of KVW for the LS estimate to be PSD.

    :math:`\sigma_{\min}(\mathcal{C})^{-1} \sqrt{\sum_i \|W_i\|_F^2} \le \lambda_{\min}(X)`
    with :math:`\mathcal{C}` the stacked
    operator of eq. (14) and ``W_i`` the perturbations of the observations (eq. 16).

    ``X`` is the true ellipsoid, so it must be PSD. For a *singular* ``X`` (a degenerate
    ellipsoid, ``lambda_min(X) = 0``; eigenvalues within the PSD tolerance of
    :func:`is_psd` below zero are read as 0) the right-hand side is 0 and the condition
    holds only for noise-free data, where the LS estimate is ``X`` itself: any
    perturbation can make the estimate of a degenerate ellipsoid indefinite. When the
    stacked operator is rank deficient (``sigma_min = 0``) ``lhs`` is ``inf`` and the
    condition does not hold.

    Parameters
    ----------
    Cs : sequence of (n, m_i) arrays
        The orthonormal views.
    Ws : sequence of (m_i, m_i) arrays
        The perturbations of the observations, one per view (symmetric).
    X : array_like, shape (n, n)
        The true ellipsoid (PSD).

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
    r"""Fit a centered ellipsoid :math:`\{z : z^T Y^{-1} z \le 1\}` to boundary points
    (ellipsoid extraction).

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

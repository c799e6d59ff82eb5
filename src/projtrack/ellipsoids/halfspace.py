"""Algorithm 1 of the Appendix of KVW: interval-constrained least squares by rank-one halfspaces."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from projtrack._validation import as_array

from .checks import _as_positive, _as_size, _check_Cs, _check_Ys, _n_from_dim, _rank
from .intervals import interval_bounds
from .lsi_solver import _LSI
from .operators import congruence_operator, smat, svec

__all__ = ["halfspace_reconstruct", "HalfspaceResult"]


@dataclass
class HalfspaceResult:
    """Outcome of Algorithm 1 (:func:`halfspace_reconstruct`).

    Attributes
    ----------
    X : ndarray
        The estimate ``X(k)`` at termination.
    n_iter : int
        Number of constrained least squares solves (eq. 30) performed.
    converged : bool
        Whether Steps 3-4 found no eigenvalue below ``-tol``.
    normals_lower, normals_upper : list of ndarray
        Unit vectors ``v`` of the rank-one normals ``v v^T`` added for the lower and upper
        bounds (Step 5), in the order they were added.
    history : list of dict
        Per iteration: ``iter``, ``objective``, ``min_eig_lower``, ``min_eig_upper``,
        ``n_cuts``.
    """

    X: np.ndarray
    n_iter: int
    converged: bool
    normals_lower: list = field(default_factory=list)
    normals_upper: list = field(default_factory=list)
    history: list = field(default_factory=list)


def _objective(A: np.ndarray, y: np.ndarray, x: np.ndarray) -> float:
    return float(np.sum((A @ x - y) ** 2))


def halfspace_reconstruct(Ys: Sequence[object], Cs: Sequence[object], lower: object = None, upper: object = None,
                          *, tol: float = 1e-9, max_iter: int = 500, initial_normals: object = None,
                          A: np.ndarray | None = None, y: np.ndarray | None = None) -> HalfspaceResult:
    """Algorithm 1 of the Appendix of KVW: successive rank-one halfspace approximation.

    Solves eq. (27) ``min sum ||Y_i - C_i^T X C_i||_F^2`` subject to ``lower <= X <= upper``
    (eq. 28) by replacing the interval set with the halfspaces (eq. 29) of a growing set of
    rank-one normals ``N = v v^T``: ``<N, X> >= <N, lower>`` and ``<N, X> <= <N, upper>``.
    Each step (eq. 30) is a linear-inequality-constrained least squares problem solved
    exactly by :func:`lsi`; Steps 3-4 add the eigenvectors of ``X(k) - lower`` and
    ``upper - X(k)`` whose eigenvalues are below ``-tol * max(1, ||X(k)||)``.

    Parameters
    ----------
    Ys, Cs : sequences of arrays
        Observations ``Y_i`` (``m_i x m_i``) and projections ``C_i`` (``n x m_i``).
    lower, upper : array_like or float, optional
        Interval bounds (a scalar ``a`` means ``a I``); ``None`` means no bound.
    tol : float
        Relative eigenvalue tolerance of the stopping test.
    max_iter : int
        Maximum number of constrained LS solves; the algorithm is not finite (KVW).
    initial_normals : array_like, optional
        Unit vectors (rows) for Step 1, used for both bounds; default none (so ``X(0)``
        is the unconstrained LS estimate).
    A, y : ndarray, optional
        A ready stacked operator and right-hand side (used by :func:`batch_estimate`);
        then ``Ys``/``Cs`` are ignored and may be ``None``.

    Returns
    -------
    HalfspaceResult
    """
    if A is None:
        Cl = _check_Cs(Cs)
        Yl = _check_Ys(Ys, Cl)
        A = np.vstack([congruence_operator(C) for C in Cl])
        y = np.concatenate([svec(Y) for Y in Yl])
    else:
        A = np.asarray(A, float)
        y = np.asarray(y, float)
    n = _n_from_dim(A.shape[1])
    L, U = interval_bounds(lower, upper, n)
    max_iter = _as_size(max_iter, "max_iter", 1)
    tol = _as_positive(tol, "tol")
    if _rank(A) < A.shape[1]:
        raise ValueError(
            f"the stacked operator has rank {_rank(A)} < n(n+1)/2 = {A.shape[1]}: the constrained "
            "problem has no unique solution; use method='sdp' or add observations")
    vl: list[np.ndarray] = []
    vu: list[np.ndarray] = []
    if initial_normals is not None:
        V0 = np.atleast_2d(as_array(initial_normals, "initial_normals"))
        if V0.shape[1] != n:
            raise ValueError(f"initial_normals must have rows of length {n}")
        V0 = V0 / np.linalg.norm(V0, axis=1, keepdims=True)
        if L is not None:
            vl += list(V0)
        if U is not None:
            vu += list(V0)
    history = []
    X = None
    converged = False
    solver = _LSI(A, y)
    G_rows: list[np.ndarray] = []
    h_rows: list[float] = []

    def add_lower(v: np.ndarray) -> None:
        G_rows.append(svec(np.outer(v, v)))
        h_rows.append(float(v @ L @ v))

    def add_upper(v: np.ndarray) -> None:
        G_rows.append(-svec(np.outer(v, v)))
        h_rows.append(-float(v @ U @ v))

    for v in vl:
        add_lower(v)
    for v in vu:
        add_upper(v)
    for it in range(1, max_iter + 1):
        G = np.array(G_rows).reshape(-1, A.shape[1])
        x = solver.solve(G, np.array(h_rows))
        X = smat(x)
        scale = tol * max(1.0, float(np.linalg.norm(X, 2)))
        new_l, new_u = [], []
        rec = {"iter": it, "objective": _objective(A, y, x), "min_eig_lower": np.nan,
               "min_eig_upper": np.nan, "n_cuts": len(vl) + len(vu)}
        if L is not None:
            lam, V = np.linalg.eigh(X - L)
            rec["min_eig_lower"] = float(lam[0])
            new_l = [V[:, j] for j in range(n) if lam[j] < -scale]
        if U is not None:
            lam, V = np.linalg.eigh(U - X)
            rec["min_eig_upper"] = float(lam[0])
            new_u = [V[:, j] for j in range(n) if lam[j] < -scale]
        history.append(rec)
        if not new_l and not new_u:
            converged = True
            break
        for v in new_l:
            vl.append(v)
            add_lower(v)
        for v in new_u:
            vu.append(v)
            add_upper(v)
    assert X is not None
    return HalfspaceResult(X=X, n_iter=len(history), converged=converged, normals_lower=vl,
                           normals_upper=vu, history=history)

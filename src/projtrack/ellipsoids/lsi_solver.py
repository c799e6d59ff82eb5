"""Least squares with linear inequality constraints (Lawson & Hanson's LSI -> LDP -> NNLS)."""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.optimize

__all__ = ["lsi"]


class _LSI:
    """Lawson-Hanson LSI solver for a fixed ``(E, f)``: the QR factorization is computed once."""

    #: relative size below which a constraint row of ``G R^{-1}`` counts as zero
    INFEASIBLE_RTOL = 100 * np.finfo(float).eps
    #: relative violation of the normalized constraints above which they are declared infeasible
    FEASIBILITY_RTOL = 1e-8

    def __init__(self, E: np.ndarray, f: np.ndarray):
        E = np.asarray(E, float)
        f = np.asarray(f, float)
        if E.ndim != 2 or f.shape != (E.shape[0],):
            raise ValueError(f"E must be 2-D and f a vector of length E.shape[0], got {E.shape} and {f.shape}")
        Q, R = np.linalg.qr(E)
        d = np.abs(np.diag(R))
        if E.shape[0] < E.shape[1] or d.min() <= 1e-12 * max(1.0, float(d.max())):
            raise ValueError("E must have full column rank for the LSI reduction")
        # R is small (n(n+1)/2 square): keep its inverse so that each solve is matrix products
        self.Rinv = scipy.linalg.solve_triangular(R, np.eye(R.shape[0]))
        self.x_ls = self.Rinv @ (Q.T @ f)

    def solve(self, G: np.ndarray, h: np.ndarray) -> np.ndarray:
        if G.shape[0] == 0:
            return self.x_ls
        ht = h - G @ self.x_ls
        if np.all(ht <= 0):
            return self.x_ls
        Gt = G @ self.Rinv
        p = Gt.shape[1]
        # LDP (min ||z|| s.t. Gt z >= ht), made scale-free: every constraint row is divided by
        # the norm of its Gt row and the right-hand side by max |ht| (this scales z), so the
        # NNLS below and the infeasibility test do not depend on the scale of E, f, G or h
        gnorm = np.linalg.norm(Gt, axis=1)
        zero = gnorm <= self.INFEASIBLE_RTOL * max(1.0, float(gnorm.max()))
        if np.any(ht[zero] > 0):  # 0 >= ht_i > 0
            raise ValueError("the linear inequality constraints are infeasible")
        Gn, hn = Gt[~zero] / gnorm[~zero, None], ht[~zero] / gnorm[~zero]
        scale = float(np.max(np.abs(hn)))
        Emat = np.vstack([Gn.T, hn[None, :] / scale])
        fvec = np.zeros(p + 1)
        fvec[-1] = 1.0
        u, _ = scipy.optimize.nnls(Emat, fvec, maxiter=50 * Emat.shape[1] + 100)
        r = Emat @ u - fvec
        # Lawson & Hanson: infeasible iff the residual vanishes. Instead of an absolute cutoff
        # on r[-1], take the candidate and check it against the normalized constraints with a
        # relative tolerance
        zs = -r[:-1] / r[-1] if r[-1] != 0 else None
        if zs is None or not np.all(np.isfinite(zs)) or \
                np.max(hn / scale - Gn @ zs) > self.FEASIBILITY_RTOL * (1.0 + np.linalg.norm(zs)):
            raise ValueError("the linear inequality constraints are infeasible")
        z = zs * scale
        return self.x_ls + self.Rinv @ z


def lsi(E: np.ndarray, f: np.ndarray, G: np.ndarray, h: np.ndarray) -> np.ndarray:
    r"""Least squares with linear inequality constraints: :math:`\min \|E x - f\|` subject
    to :math:`G x \ge h`.

    Lawson & Hanson's reduction LSI -> LDP -> NNLS (ch. 23 of "Solving Least Squares
    Problems", the standard method KVW point to for eq. 30), with the NNLS solved by
    :func:`scipy.optimize.nnls`. ``E`` must have full column rank.

    Parameters
    ----------
    E : numpy.ndarray, shape (p, k)
        Least-squares matrix (full column rank).
    f : numpy.ndarray, shape (p,)
        Right-hand side.
    G : numpy.ndarray, shape (q, k)
        Constraint matrix.
    h : numpy.ndarray, shape (q,)
        Constraint bounds.

    Returns
    -------
    numpy.ndarray, shape (k,)
        The minimizer ``x``.

    Raises
    ------
    ValueError
        If ``E`` is rank deficient or the constraints are infeasible.
    """
    G = np.asarray(G, float)
    h = np.asarray(h, float)
    return _LSI(E, f).solve(G.reshape(-1, np.shape(E)[1]), h.reshape(-1))

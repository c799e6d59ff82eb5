"""One update of the recursive KL basis by a new frame: the paper's VIP route and the QR route.

The bordered VIP matrix (Eqs. (4)-(5)), the novelty from it (Eqs. (6)-(7)), the eigenimage
update (Eq. (9)) from its eigen-decomposition (``"vip"``) or from the SVD of a small triangular
factor (``"qr"``), and the rounding levels of both routes.
"""
from __future__ import annotations

import warnings

import numpy as np

from ._linalg import _eigh_desc, _sign_fix
from .results import EigenvalueDroppedWarning

__all__ = ["METHODS"]

#: The numerical routes of the eigenimage update: ``"qr"`` (residual-based, the default) and
#: ``"vip"`` (the paper's bordered VIP matrix, Eqs. (4)-(9)).
METHODS: tuple[str, ...] = ("qr", "vip")

# Relative tolerance below which an information fraction counts as numerically zero in the
# rank estimate (Eq. (11)); it lets T_I = 1 keep every eigenimage that carries information.
_FRACTION_TOL = 1e-12


def _bordered_vip(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray) -> np.ndarray:
    """VIP matrix V_i of Eqs. (4)-(5) for prior unit eigenimages ``u`` and new frame ``x``.

    The weighted eigenimages are ``Phi_{i-1,l} = sqrt((i-1) lambda_l) u_l``, so
    ``v(l,l) = (i-1)/i lambda_l`` (Eq. (4)), ``v(l,K) = x^T Phi_{i-1,l} / i`` and
    ``v(K,K) = x^T x / i`` (Eq. (5)).
    """
    i = i_prev + 1
    k = lam.size
    w = np.sqrt(i_prev * lam)
    v = np.empty((k + 1, k + 1))
    v[:k, :k] = np.diag(i_prev * lam / i)
    border = w * (u @ x) / i
    v[:k, k] = border
    v[k, :k] = border
    v[k, k] = float(x @ x) / i
    return v


def _novelty_from_vip(v: np.ndarray) -> float:
    """Eqs. (6)-(7): ``n = 1 - sum_k v(k,K)^2 / (v(k,k) v(K,K))``, clipped to [0, 1]."""
    k = v.shape[0] - 1
    vkk = v[k, k]
    if vkk <= 0:  # an all-zero frame lies in every subspace: nothing new
        return 0.0
    alpha2 = v[:k, k] ** 2 / (np.diag(v)[:k] * vkk)   # squared direction cosines, Eq. (6)
    return float(np.clip(1.0 - alpha2.sum(), 0.0, 1.0))


def _rounding_floor(method: str, k: int) -> float:
    """Information fraction below which an eigenvalue is rounding noise for ``method``.

    The ``"qr"`` route computes singular values to about ``eps`` of the largest, so
    eigenvalues (their squares) to about ``eps**2`` of the largest; the ``"vip"`` route
    eigen-decomposes the Gram matrix itself, so its eigenvalues are only known to about ``eps``.
    """
    eps = np.finfo(float).eps * 8 * (k + 1)
    return eps ** 2 if method == "qr" else eps


def _update_eigenimages(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray,
                        v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (9) (the ``"vip"`` route): eigen-decompose V_i and form the new unit eigenimages.

    Eigenvalues that are not positive cannot give an eigenimage and are dropped; a
    :class:`EigenvalueDroppedWarning` is issued when one of them is larger in magnitude than
    the rounding level of the VIP matrix.
    """
    g, th = _eigh_desc(v)
    w = np.sqrt(i_prev * lam)
    phi = (th[:-1].T * w) @ u + np.outer(th[-1], x)      # Eq. (9), weighted eigenimages
    norms = np.linalg.norm(phi, axis=1)
    good = (g > 0) & (norms > 0)
    bad = g[~good]
    floor = _rounding_floor("vip", lam.size) * float(np.abs(g).sum())
    if bad.size and np.max(np.abs(bad)) > floor:
        warnings.warn(f"the VIP route dropped {bad.size} non-positive eigenvalue(s) down to "
                      f"{float(bad.min()):.3g}, above its rounding level {floor:.3g}; "
                      "use method='qr'", EigenvalueDroppedWarning, stacklevel=4)
    phi = phi[good] / norms[good, None]
    return g[good], _sign_fix(phi)


def _residual_split(u: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Coefficients ``c = U x``, residual ``r = x - U^T c`` and ``|r|`` (Gram-Schmidt twice)."""
    c = u @ x
    r = x - u.T @ c
    c2 = u @ r                     # re-orthogonalization: "twice is enough"
    r = r - u.T @ c2
    return c + c2, r, float(np.linalg.norm(r))


def _qr_update(u: np.ndarray, lam: np.ndarray, i_prev: int, x: np.ndarray,
               split: tuple[np.ndarray, np.ndarray, float] | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    """The ``"qr"`` route of the update: same result as Eqs. (4)-(9), without the Gram matrix.

    The weighted eigenimages and the new frame are ``A = [sqrt(i_prev lam) u ; x] = B^T Q``
    with ``Q = [u ; r/|r|]`` orthonormal and ``B`` upper triangular,
    ``B = [[diag(sqrt(i_prev lam)), c], [0, |r|]]``.  With ``B = W S Z^T`` (SVD) the new unit
    eigenimages are ``W^T Q`` and the eigenvalues of ``V_i = A A^T / i`` are ``S^2 / i``.
    Returns all ``K_i`` eigenvalues (descending; the last is 0 when the frame lies in the span)
    and the eigenimages of the positive ones.
    """
    i = i_prev + 1
    k = lam.size
    c, r, rho = split if split is not None else _residual_split(u, x)
    b = np.zeros((k + 1, k + 1))
    b[np.arange(k), np.arange(k)] = np.sqrt(i_prev * lam)
    b[:k, k] = c
    b[k, k] = rho
    if rho > 0:
        q = np.vstack([u, r[None, :] / rho])
        wl, sv, _ = np.linalg.svd(b)
    else:                          # the frame lies in the span: rank cannot grow
        q = u
        wl, sv, _ = np.linalg.svd(b[:k])
        sv = np.concatenate([sv, [0.0]])
    g = sv ** 2 / i
    phi = wl.T @ q
    phi /= np.linalg.norm(phi, axis=1, keepdims=True)
    return g, _sign_fix(phi)


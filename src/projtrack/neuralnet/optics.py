"""The linear-algebra form of the optical architecture (Sec. IV-V): ``T1``-``T3``, the rank-3 tensor, SLM sizes."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy import sparse

from projtrack._validation import as_bool, as_int

from ._checks import _check_D
from .coefficients import Coefficients, _as_coefficients

__all__ = ["connection_matrices", "full_tensor", "tensor_matrix_product", "reduced_tensor",
           "reduced_tensor_product", "gradient_linear_algebra", "slm_sizes"]


def _flat_index(n_t: int, n_m: int, n_p: int) -> np.ndarray:
    return np.arange(n_t * n_m * n_p).reshape(n_t, n_m, n_p)


def connection_matrices(n_targets: int, n_measurements: int, n_frames: int
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fixed connection matrices :math:`T_1, T_2, T_3` of Section IV (equation (10)).

    With ``k = (i, alpha, a)`` and ``l = (j, beta, b)``:
    ``T1_kl = delta_{alpha beta} delta_ab (1 - delta_ij)`` (eq. (10)),
    ``T2_kl = delta_ij delta_ab (1 - delta_{alpha beta})`` and ``T3_kl = delta_ab``, so that
    eq. (9) is ``2 A1 T1 x + 2 A2 T2 x + 2 A3 (T3 x - N_T) + y4``.

    Parameters
    ----------
    n_targets, n_measurements, n_frames : int
        ``N_T``, ``N_M`` and ``N_P``.

    Returns
    -------
    T1, T2, T3 : ndarray of int8, shape (K, K), ``K = N_T N_M N_P``
    """
    n_t = as_int(n_targets, "n_targets", 1)
    n_m = as_int(n_measurements, "n_measurements", 1)
    n_p = as_int(n_frames, "n_frames", 1)
    i, al, a = (g.reshape(-1) for g in np.meshgrid(np.arange(n_t), np.arange(n_m), np.arange(n_p), indexing="ij"))
    same_i = i[:, None] == i[None, :]
    same_al = al[:, None] == al[None, :]
    same_a = a[:, None] == a[None, :]
    T1 = (same_al & same_a & ~same_i).astype(np.int8)
    T2 = (same_i & same_a & ~same_al).astype(np.int8)
    T3 = same_a.astype(np.int8)
    return T1, T2, T3


def full_tensor(D: np.ndarray, n_targets: int) -> sparse.csr_matrix:
    r"""The rank-3 tensor of equation (11) as the :math:`K \times K^2` matrix written on
    SLM2.

    Row ``j`` holds ``D_{jkl}`` for all ``(k, l)`` (column ``k K + l``), so that
    ``y4 = A4 * D_full @ vec(x x^T)`` is term 4 of eq. (9) (eq. (12)). Stored sparse: only
    pairs of neurons of the same target in the right frames are non-zero.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    n_targets : int

    Returns
    -------
    scipy.sparse.csr_matrix, shape (K, K^2), ``K = N_T N_M N_P``
    """
    D = _check_D(D)
    n_t = as_int(n_targets, "n_targets", 1)
    n_q, n_m = D.shape[0], D.shape[1]
    n_p = n_q + 2
    idx = _flat_index(n_t, n_m, n_p)
    K = idx.size
    i, a, al, be, ga = (g.reshape(-1) for g in np.meshgrid(
        np.arange(n_t), np.arange(n_q), np.arange(n_m), np.arange(n_m), np.arange(n_m), indexing="ij"))
    vals = D[a, al, be, ga]
    n0, n1, n2 = idx[i, al, a], idx[i, be, a + 1], idx[i, ga, a + 2]
    rows = np.concatenate([n0, n1, n2])
    cols = np.concatenate([n1 * K + n2, n0 * K + n2, n0 * K + n1])
    data = np.concatenate([vals, vals, vals])
    return sparse.csr_matrix((data, (rows, cols)), shape=(K, K * K))


def tensor_matrix_product(D_full: sparse.spmatrix | np.ndarray, x: np.ndarray) -> np.ndarray:
    r"""The tensor-matrix inner product :math:`y_{4,j} = \sum_{k,l} D_{jkl} x_k x_l`
    (equations (11)-(12)).

    Parameters
    ----------
    D_full : (K, K^2) matrix from :func:`full_tensor` (or a dense (K, K, K) array)
    x : array_like, shape (K,)

    Returns
    -------
    ndarray, shape (K,)
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    K = x.size
    if sparse.issparse(D_full):
        if D_full.shape != (K, K * K):
            raise ValueError(f"D_full must have shape (K, K^2) = ({K}, {K * K}), got {D_full.shape}")
        return np.asarray(D_full @ np.outer(x, x).reshape(-1)).reshape(-1)
    Dd = np.asarray(D_full, dtype=float)
    if Dd.shape != (K, K, K):
        raise ValueError(f"D_full must have shape (K, K, K) = ({K}, {K}, {K}), got {Dd.shape}")
    return np.einsum("jkl,k,l->j", Dd, x, x)


def reduced_tensor(D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The paper's reduced SLM2 content: :math:`N_M` matrices of size :math:`(N_M N_P)^2`
    (Section V).

    Only products ``X_{i beta b} X_{i gamma c}`` of the same target enter eq. (9), and D does
    not depend on the target, so one set of matrices serves all targets. Matrix ``alpha``
    holds, at position ``(k, l)`` with ``k = (beta, b)`` and ``l = (gamma, c)`` of the
    per-target vector ``z``, the D value that multiplies ``z_k z_l`` in the derivative
    for neuron ``(alpha, a)``; the output frame ``a`` is fixed by the position alone
    (``route``), which is what the fixed CGH does: ``c = b + 1`` above the diagonal feeds
    ``a = b - 1`` (first part of term 4), ``c = b + 2`` feeds ``a = b + 1`` (middle part)
    and ``k`` one frame after ``l`` (below the diagonal) feeds ``a = b + 1`` (last part).

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)

    Returns
    -------
    R : ndarray, shape (N_M, N_M N_P, N_M N_P)
    route : ndarray of int, shape (N_M N_P, N_M N_P)
        Output frame of each position, -1 where ``R`` is always zero.
    """
    D = _check_D(D)
    n_q, n_m = D.shape[0], D.shape[1]
    n_p = n_q + 2
    L = n_m * n_p
    z = np.arange(L).reshape(n_m, n_p)  # z index of (measurement, frame)
    R = np.zeros((n_m, L, L))
    route = np.full((L, L), -1, dtype=np.intp)
    a, al, be, ga = (g.reshape(-1) for g in np.meshgrid(
        np.arange(n_q), np.arange(n_m), np.arange(n_m), np.arange(n_m), indexing="ij"))
    vals = D[a, al, be, ga]
    # first part: output (alpha, a), product z(beta, a+1) z(gamma, a+2)
    R[al, z[be, a + 1], z[ga, a + 2]] = vals
    route[z[be, a + 1], z[ga, a + 2]] = a
    # middle part: output (beta, a+1), product z(alpha, a) z(gamma, a+2)
    R[be, z[al, a], z[ga, a + 2]] = vals
    route[z[al, a], z[ga, a + 2]] = a + 1
    # last part: output (gamma, a+2), product z(beta, a+1) z(alpha, a) (below the diagonal)
    R[ga, z[be, a + 1], z[al, a]] = vals
    route[z[be, a + 1], z[al, a]] = a + 2
    return R, route


def reduced_tensor_product(R: np.ndarray, route: np.ndarray, x: np.ndarray, n_targets: int) -> np.ndarray:
    """:math:`y_4` from the reduced form: :math:`N_T` per-target outer products :math:`z_i
    z_i^T` times the :math:`N_M` matrices.

    Parameters
    ----------
    R, route : from :func:`reduced_tensor`
    x : array_like, shape (N_T N_M N_P,)
        The neuron vector ``(z_1, ..., z_NT)``.
    n_targets : int

    Returns
    -------
    ndarray, shape (N_T N_M N_P,)
        Term 4 of eq. (9) without ``A4``, in the order of ``x``.
    """
    R = np.asarray(R, dtype=float)
    route = np.asarray(route)
    n_t = as_int(n_targets, "n_targets", 1)
    if R.ndim != 3 or R.shape[1] != R.shape[2] or route.shape != R.shape[1:]:
        raise ValueError(f"R must be (N_M, L, L) with route (L, L), got {R.shape} and {route.shape}")
    n_m, L = R.shape[0], R.shape[1]
    if L % n_m:
        raise ValueError(f"L = {L} must be N_M N_P with N_M = {n_m}")
    n_p = L // n_m
    x = np.asarray(x, dtype=float).reshape(-1)
    if x.size != n_t * L:
        raise ValueError(f"x must have N_T N_M N_P = {n_t * L} entries, got {x.size}")
    Z = x.reshape(n_t, L)
    vop = Z[:, :, None] * Z[:, None, :]                    # N_T VOPs (B2)
    onehot = (route[None, :, :] == np.arange(n_p)[:, None, None]).astype(float)  # CGH
    y = np.einsum("mkl,ikl,akl->ima", R, vop, onehot)      # (N_T, N_M, N_P)
    return y.reshape(-1)


def gradient_linear_algebra(x: np.ndarray, D: np.ndarray, n_targets: int,
                            coefficients: Coefficients | Sequence[float] | None = None,
                            reduced: bool = False) -> np.ndarray:
    """Equation (9) as :math:`T x + A_4 y_4 - 2 A_3 N_T` with the matrices of equations
    (10)-(12).

    Parameters
    ----------
    x : array_like, shape (K,)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    n_targets : int
    coefficients : default the paper's
    reduced : bool
        Use the reduced per-target tensor instead of the full one.

    Returns
    -------
    ndarray, shape (K,)
    """
    reduced = as_bool(reduced, "reduced")
    c = _as_coefficients(coefficients)
    D = _check_D(D)
    n_t = as_int(n_targets, "n_targets", 1)
    n_m, n_p = D.shape[1], D.shape[0] + 2
    x = np.asarray(x, dtype=float).reshape(-1)
    if x.size != n_t * n_m * n_p:
        raise ValueError(f"x must have {n_t * n_m * n_p} entries, got {x.size}")
    T1, T2, T3 = connection_matrices(n_t, n_m, n_p)
    T = 2 * c.A1 * T1 + 2 * c.A2 * T2 + 2 * c.A3 * T3
    if reduced:
        y4 = reduced_tensor_product(*reduced_tensor(D), x, n_t)
    else:
        y4 = tensor_matrix_product(full_tensor(D, n_t), x)
    return T @ x + c.A4 * y4 - 2 * c.A3 * n_t


def slm_sizes(n_targets: int, n_measurements: int, n_frames: int) -> dict[str, int]:
    """Pixel counts of the optical architecture of Section V.

    Parameters
    ----------
    n_targets, n_measurements, n_frames : int
        ``N_T``, ``N_M`` and ``N_P``.

    Returns
    -------
    dict with ``neurons`` (``K = N_T N_M N_P``, B1), ``vop_full`` (``K^2``, B2),
    ``slm2_full`` (``K^3``), ``vop_reduced`` (``N_T (N_M N_P)^2``),
    ``slm2_reduced`` (``N_M (N_M N_P)^2``) and ``reduction`` (``slm2_full // slm2_reduced``).
    """
    n_t = as_int(n_targets, "n_targets", 1)
    n_m = as_int(n_measurements, "n_measurements", 1)
    n_p = as_int(n_frames, "n_frames", 1)
    K = n_t * n_m * n_p
    L = n_m * n_p
    out = {"neurons": K, "vop_full": K * K, "slm2_full": K ** 3,
           "vop_reduced": n_t * L * L, "slm2_reduced": n_m * L * L}
    out["reduction"] = out["slm2_full"] // out["slm2_reduced"]
    return out

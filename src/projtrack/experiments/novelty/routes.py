"""Checks of the KL algorithms against exact oracles and streaming baselines (Eqs. (2)-(9)).

The VIP-matrix eigen-decomposition against the large correlation/covariance matrix
(:func:`vip_vs_large`), the recursion with ``T_d = 0``, ``T_I = 1`` against the batch
decomposition by both update routes (:func:`route_errors`), the routes on near-duplicate
frames (:func:`near_duplicate_study`) and the adaptive filter against batch SVD/PCA and
scikit-learn's IncrementalPCA (:func:`streaming_comparison`); Eq. (12) in its two printed
forms against the projection the package computes (:func:`eq12_forms`), and the ranks of the
correlation matrix ``R`` and the covariance matrix ``C`` from their ``I x I`` VIP matrices
(:func:`vip_ranks`; Section 3: "the rank of R is one more than the rank of C").
"""
from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
from scipy.linalg import subspace_angles
from sklearn.decomposition import PCA, IncrementalPCA

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.novelty import (METHODS, EigenvalueDroppedWarning, NoveltyFilter, batch_kl,
                               correlation_matrix)

__all__ = ["vip_vs_large", "route_errors", "near_duplicate_study", "streaming_comparison", "eq12_forms",
           "vip_ranks", "mean_outside_span"]


def vip_vs_large(frames: Any) -> pd.DataFrame:
    """Eqs. (2)-(3): the VIP-matrix eigen-decomposition against that of the large ``P x P`` matrix.

    For the correlation (``center=False``) and the covariance (``center=True``) matrix: the
    largest relative eigenvalue error and the largest principal angle between the spanned
    subspaces (``frames`` must be small: at most 4096 pixels per frame).
    """
    small = as_array(frames, "frames", ndim=3, allow_empty=False)
    rows = []
    for center in (False, True):
        basis = batch_kl(small, center=center)
        lam, vec = np.linalg.eigh(correlation_matrix(small, center=center))
        lam, vec = lam[::-1], vec[:, ::-1]
        k = basis.eigenvalues.size
        e = basis.eigenimages.reshape(k, -1)
        rows.append({
            "matrix": "covariance C" if center else "correlation R",
            "VIP size": f"{len(small)}x{len(small)}",
            "large size": f"{e.shape[1]}x{e.shape[1]}",
            "non-zero eigenvalues": k,
            "max rel. eigenvalue error": float(np.max(np.abs(basis.eigenvalues - lam[:k]) / lam[:k])),
            "max principal angle (rad)": float(np.max(subspace_angles(e.T, vec[:, :k]))),
        })
    return pd.DataFrame(rows)


def route_errors(frames: Any) -> tuple[pd.DataFrame, dict[str, NoveltyFilter]]:
    """The recursion with ``T_d = 0``, ``T_I = 1`` against the batch KL, for each update route.

    Returns
    -------
    errors : pandas.DataFrame
        Index ``route``: updates, eigenimages kept, the batch's non-zero eigenvalues, the
        largest relative eigenvalue error, the largest principal angle between the leading
        ``m`` eigenimages of both, over ``m < k`` (the full span is the frames' span for both), and the
        orthonormality error of the eigenimages.
    filters : dict
        Route -> the fitted :class:`~projtrack.novelty.NoveltyFilter`.
    """
    frames = as_array(frames, "frames", allow_empty=False)
    batch = batch_kl(frames)
    k = batch.eigenvalues.size
    route_err, filters = {}, {}
    for method in METHODS:
        f = NoveltyFilter(novelty_threshold=0.0, information_threshold=1.0, method=method).fit(frames)
        route_err[method] = {
            "updates": f.n_updates_, "eigenimages kept": f.rank_, "batch non-zero eigenvalues": k,
            "max rel. eigenvalue error": float(np.max(np.abs(f.eigenvalues_[:k] - batch.eigenvalues) / batch.eigenvalues)),
            # the leading-m subspaces for m < k: the full span (m = k) is the frames' span for both, equal by construction
            "largest principal angle (rad)": float(max(
                np.max(subspace_angles(f.components_[:m].T, batch.eigenimages.reshape(k, -1)[:m].T))
                for m in range(1, max(k, 2)))),
            "orthonormality error": float(np.max(np.abs(f.components_ @ f.components_.T - np.eye(f.rank_))))}
        filters[method] = f
    return pd.DataFrame.from_dict(route_err, orient="index").rename_axis("route"), filters


def near_duplicate_study(frame: Any, rng: np.random.Generator,
                         deltas: Sequence[float] = (1.0, 1e-3, 1e-4), n_copies: int = 6) -> pd.DataFrame:
    """Both routes on ``n_copies`` copies of ``frame`` plus white noise of std ``delta``.

    With ``T_d = 0`` and ``T_I = 1`` every copy updates and every eigenimage should be kept;
    the oracle is the SVD of the copies.  One noise draw per ``delta`` (from ``rng``), shared
    by both routes.

    Returns
    -------
    pandas.DataFrame
        Per ``delta`` and route: eigenimages kept, the number of
        :class:`~projtrack.novelty.EigenvalueDroppedWarning`, the largest relative eigenvalue
        error and the orthonormality error.
    """
    rng = as_rng(rng)
    n_copies = as_int(n_copies, "n_copies", minimum=2)
    base = as_array(frame, "frame", allow_empty=False).ravel()
    rows = []
    for delta in deltas:
        dup = base + delta * rng.standard_normal((n_copies, base.size))
        s2 = np.linalg.svd(dup, compute_uv=False) ** 2 / len(dup)         # the oracle
        for method in METHODS:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", EigenvalueDroppedWarning)
                f = NoveltyFilter(0.0, 1.0, method=method).fit(dup)
            kk = f.rank_
            rows.append({"delta (grey levels)": delta, "route": method, f"eigenimages kept (of {n_copies})": kk,
                         "dropped-eigenvalue warnings": sum(issubclass(w.category, EigenvalueDroppedWarning) for w in caught),
                         "max rel. eigenvalue error": float(np.max(np.abs(f.eigenvalues_ - s2[:kk]) / s2[:kk])),
                         "orthonormality error": float(np.max(np.abs(f.components_ @ f.components_.T - np.eye(kk))))})
    return pd.DataFrame(rows)


def streaming_comparison(seq: Any, novelty_threshold: float = 0.001,
                         information_threshold: float = 0.9995, batch_size: int = 10) -> dict[str, Any]:
    """The adaptive filter against batch SVD/PCA and IncrementalPCA with as many stored images.

    The filter chooses ``K``; the linear baselines keep ``K`` eigenimages, the affine ones
    (PCA, IncrementalPCA fed ``batch_size`` frames at a time) a mean and ``K - 1``
    components.

    Returns
    -------
    dict
        ``table`` (pandas.DataFrame: per method the stored images, frames used, energy missed,
        its ratio to the best batch method and the floats kept), ``K``, ``best`` (the best
        batch energy missed) and the fitted models ``adaptive``, ``ipca``, ``pca``.
    """
    seq = as_array(seq, "seq", allow_empty=False)
    batch_size = as_int(batch_size, "batch_size", minimum=1)
    X = seq.reshape(len(seq), -1)
    ada = NoveltyFilter(novelty_threshold=novelty_threshold,
                        information_threshold=information_threshold).fit(seq)
    K = ada.rank_
    if K < 2:
        raise ValueError("the adaptive filter kept one eigenimage: nothing to compare with K - 1 components")
    ipca = IncrementalPCA(n_components=K - 1)
    for start in range(0, len(X), batch_size):
        ipca.partial_fit(X[start:start + batch_size])
    pca = PCA(n_components=K - 1, svd_solver="full").fit(X)

    def missed(recon):
        return float(np.sum((X - recon) ** 2) / np.sum(X ** 2))

    def affine(model):
        return model.mean_ + (X - model.mean_) @ model.components_.T @ model.components_

    top = batch_kl(seq, n_components=K).eigenimages.reshape(K, -1)
    res = {
        "adaptive recursive SVD (linear, K eigenimages)": (missed(X @ ada.components_.T @ ada.components_), ada.n_updates_,
                                                           ada.components_.size + K),
        "batch SVD of R, top K (linear optimum)": (missed(X @ top.T @ top), len(X), X.size),
        "IncrementalPCA, mean + K-1 components (affine)": (missed(affine(ipca)), len(X),
                                                           ipca.components_.size + 2 * X.shape[1] + K - 1),
        "batch PCA, mean + K-1 components (affine optimum)": (missed(affine(pca)), len(X), X.size),
    }
    best = min(res["batch SVD of R, top K (linear optimum)"][0], res["batch PCA, mean + K-1 components (affine optimum)"][0])
    table = pd.DataFrame([{"method": m, "stored images": K, "frames used": n, "energy missed": r,
                           "missed / best batch": r / best, "floats kept": fl}
                          for m, (r, n, fl) in res.items()])
    return {"table": table, "K": K, "best": best, "adaptive": ada, "ipca": ipca, "pca": pca}


def eq12_forms(frames: Any, test: Any, method: str = "vip") -> dict[str, float]:
    """Eq. (12) in its two printed forms after the frames ``frames`` (``T_d = 0``, ``T_I = 1``).

    After ``i - 1`` updates the paper's eigenimages ``Phi_k`` have ``|Phi_k|^2 = (i - 1)
    lambda_k`` (Eq. (4): ``v_i(k, k) = ((i - 1) / i) lambda_{i-1,k}`` is ``|Phi_k|^2 / i``), and
    Eq. (5) gives ``v_i(k, K_i) = x_j^T Phi_k / i``.  With ``x = test``:

    - form 1: ``sum_k (x^T Phi_k / lambda_k) Phi_k``;
    - form 2: ``sum_k (V(k, K_i) / V(k, k)) Phi_k``, summed over the ``K_i - 1`` prior eigenimages;
    - the projection ``sum_k (x^T u_k) u_k`` on the unit eigenimages (the package's
      :meth:`~projtrack.novelty.NoveltyFilter.reconstruct`).

    Returns
    -------
    dict
        ``i`` (the iteration of the test frame), ``K`` (prior eigenimages), ``form 2 vs projection``
        (largest difference relative to the projection's largest value), ``form 1 / form 2`` (ratio
        of their norms), ``n (Eq. 7)`` from the VIP matrix, ``|x - x_hat|^2 / |x|^2`` with form 2.
    """
    f = NoveltyFilter(0.0, 1.0, method=method)
    f.fit(as_array(frames, "frames", allow_empty=False))
    x = as_array(test, "test", shape=f.frame_shape_).ravel()
    i = f.n_updates_ + 1
    lam, u = f.eigenvalues_, f.components_
    phi = np.sqrt((i - 1) * lam)[:, None] * u
    k = lam.size
    v = np.zeros((k + 1, k + 1))
    v[:k, :k] = np.diag((i - 1) / i * lam)
    v[:k, k] = v[k, :k] = phi @ x / i
    v[k, k] = x @ x / i
    form1 = ((phi @ x) / lam) @ phi
    form2 = (v[:k, k] / np.diag(v)[:k]) @ phi
    proj = u.T @ (u @ x)
    n7 = 1 - float(np.sum(v[:k, k] ** 2 / (np.diag(v)[:k] * v[k, k])))
    return {"i": i, "K": k,
            "form 2 vs projection": float(np.abs(form2 - proj).max() / np.abs(proj).max()),
            "form 1 / form 2": float(np.linalg.norm(form1) / np.linalg.norm(form2)),
            "n (Eq. 7)": n7, "|x - x_hat|^2 / |x|^2": float(np.sum((x - form2) ** 2) / (x @ x))}


def mean_outside_span(frames: Any, rtol: float = 1e-10) -> bool:
    """Whether the mean frame lies outside the span of the centred frames (``R`` then has one rank more than ``C``).

    Ranks from the ``I x I`` (and ``(I+1) x (I+1)``) Gram matrices, with an eigenvalue counting
    when it exceeds ``rtol`` times the largest.
    """
    x = as_array(frames, "frames", allow_empty=False)
    x = x.reshape(len(x), -1).astype(float)
    rtol = as_real(rtol, "rtol", 0.0, low_open=True)
    xc = x - x.mean(axis=0)
    with_mean = np.vstack([xc, x.mean(axis=0)])
    e_all, e_c = np.linalg.eigvalsh(with_mean @ with_mean.T), np.linalg.eigvalsh(xc @ xc.T)
    tol = rtol * e_all.max()                       # one threshold for both ranks
    return int(np.sum(e_all > tol)) > int(np.sum(e_c > tol))


def vip_ranks(frames: Any, rtol: float = 1e-10) -> tuple[int, int]:
    """Numerical ranks of ``R`` and ``C`` of a sequence, from their ``I x I`` VIP matrices (Eq. (2)).

    ``R`` keeps the mean (``v(l, m) = x_l^T x_m / I``), ``C`` removes it; an eigenvalue counts
    when it exceeds ``rtol`` times the largest eigenvalue of ``R``.
    """
    x = as_array(frames, "frames", allow_empty=False)
    x = x.reshape(len(x), -1)
    rtol = as_real(rtol, "rtol", 0.0, low_open=True)
    xc = x - x.mean(axis=0)
    er = np.linalg.eigvalsh(x @ x.T / len(x))
    ec = np.linalg.eigvalsh(xc @ xc.T / len(x))
    tol = rtol * er.max()
    return int(np.sum(er > tol)), int(np.sum(ec > tol))

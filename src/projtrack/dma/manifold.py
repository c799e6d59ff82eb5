"""Manifold learning (Sec. 3.1 of Marques et al., 2002): regions, local frames, prototypes.

A Gaussian mixture fitted by EM (eqs. (1)-(5), :class:`sklearn.mixture.GaussianMixture`)
splits the manifold into regions; a point belongs to the region of smallest squared
Mahalanobis distance (eq. (6)); local PCA frames (eqs. (7)-(8)) have a given dimension or
one chosen from the discarded-eigenvalue error (eq. (9)); k-means gives the prototypes of
each region in local coordinates (:func:`learn_manifold`, :class:`DiscreteManifold`). The
number of regions can be chosen by BIC, an MDL-type criterion (:func:`select_n_regions`).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng, optional_import

__all__ = ["DiscreteManifold", "learn_manifold", "select_n_regions"]


@dataclass
class DiscreteManifold:
    """A manifold split into regions, each with a local frame and prototypes (Section 3.1).

    Attributes
    ----------
    means : ndarray, shape (M, n)
        Region means ``mu_i`` (eq. (4)).
    covariances : ndarray, shape (M, n, n)
        Region covariances ``R_i`` (eq. (5)).
    weights : ndarray, shape (M,)
        Mixture weights ``c_i`` (eq. (3)).
    bases : list of ndarray, each (n, m_i)
        Orthonormal local frames ``V_i`` (eq. (7)), columns by decreasing eigenvalue.
    eigenvalues : ndarray, shape (M, n)
        Eigenvalues of each ``R_i``, decreasing.
    dims : ndarray of int, shape (M,)
        Hyperplane dimension ``m_i`` of each region.
    local_prototypes : list of ndarray, each (k_i, m_i)
        Prototypes ``U_i`` in local coordinates.
    prototypes : ndarray, shape (K, n)
        All prototypes mapped back to R^n by eq. (7), region by region.
    prototype_region : ndarray of int, shape (K,)
        Region of each prototype.
    """

    means: np.ndarray
    covariances: np.ndarray
    weights: np.ndarray
    bases: list[np.ndarray]
    eigenvalues: np.ndarray
    dims: np.ndarray
    local_prototypes: list[np.ndarray]
    prototypes: np.ndarray = field(init=False)
    prototype_region: np.ndarray = field(init=False)
    _prec: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pts, reg = [], []
        for i, (V, U) in enumerate(zip(self.bases, self.local_prototypes)):
            pts.append(self.means[i] + U @ V.T)
            reg.append(np.full(len(U), i))
        self.prototypes = np.vstack(pts)
        self.prototype_region = np.concatenate(reg).astype(np.int64)
        self._prec = np.linalg.pinv(self.covariances, hermitian=True)

    @property
    def n_regions(self) -> int:
        return self.means.shape[0]

    @property
    def n_prototypes(self) -> int:
        return self.prototypes.shape[0]

    @property
    def ambient_dim(self) -> int:
        return self.means.shape[1]

    def _check_points(self, X: object, name: str = "X") -> np.ndarray:
        X = as_array(X, name, ndim=2)
        if X.shape[1] != self.ambient_dim:
            raise ValueError(f"{name} must have {self.ambient_dim} columns, got shape {X.shape}")
        return X

    def mahalanobis(self, X: object) -> np.ndarray:
        """Squared Mahalanobis distances ``d(x, mu_i)^2`` of eq. (6), shape (N, M)."""
        X = self._check_points(X)
        D = X[:, None, :] - self.means[None, :, :]
        return np.einsum("nmi,mij,nmj->nm", D, self._prec, D)

    def assign(self, X: object) -> np.ndarray:
        """Region of each point: smallest squared Mahalanobis distance (eq. (6))."""
        return np.argmin(self.mahalanobis(X), axis=1)

    def local_coordinates(self, X: object, regions: object | None = None) -> list[np.ndarray] | np.ndarray:
        """Local coordinates ``x_i = V_i^T (x - mu_i)`` (eq. (8)).

        With ``regions`` None, each point uses its own region (eq. (6)) and a list with
        one ``(m_i,)`` array per point is returned; with an int region, an
        ``(N, m_i)`` array in that region's frame.
        """
        X = self._check_points(X)
        if regions is None:
            r = self.assign(X)
            return [self.bases[k].T @ (x - self.means[k]) for x, k in zip(X, r)]
        k = as_int(regions, "regions", minimum=0)
        if k >= self.n_regions:
            raise ValueError(f"regions must be < {self.n_regions}, got {k}")
        return (X - self.means[k]) @ self.bases[k]

    def project(self, X: object) -> np.ndarray:
        """Orthogonal projection of each point on its region's hyperplane (eq. (7) with ``V_i`` truncated)."""
        X = self._check_points(X)
        r = self.assign(X)
        out = np.empty_like(X)
        for k in range(self.n_regions):
            m = r == k
            if m.any():
                V = self.bases[k]
                out[m] = self.means[k] + ((X[m] - self.means[k]) @ V) @ V.T
        return out

    def quantize(self, X: object) -> np.ndarray:
        """Index of the prototype of each point (Fig. 5): the region by eq. (6), then the
        nearest prototype of that region in local coordinates."""
        X = self._check_points(X)
        r = self.assign(X)
        out = np.empty(len(X), dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum([len(U) for U in self.local_prototypes])])
        for k in range(self.n_regions):
            m = r == k
            if m.any():
                loc = (X[m] - self.means[k]) @ self.bases[k]
                d = ((loc[:, None, :] - self.local_prototypes[k][None]) ** 2).sum(-1)
                out[m] = offsets[k] + np.argmin(d, axis=1)
        return out

    def projection_mse(self) -> np.ndarray:
        """Mean square error of each region's hyperplane approximation, eq. (9)."""
        return np.array([self.eigenvalues[i, self.dims[i]:].sum() for i in range(self.n_regions)])


def _fit_gmm(X: np.ndarray, n_regions: int, rng: np.random.Generator, reg_covar: float):
    GaussianMixture = optional_import("sklearn.mixture", "learn", "learning a manifold by EM").GaussianMixture

    seed = int(rng.integers(0, 2**31 - 1))
    gmm = GaussianMixture(
        n_components=n_regions, covariance_type="full", reg_covar=reg_covar,
        random_state=seed, n_init=1, init_params="k-means++", max_iter=500,
    )
    gmm.fit(X)
    return gmm


def _check_training_points(X: object) -> np.ndarray:
    return as_array(X, "X", ndim=2, allow_empty=False)


def select_n_regions(X: object, candidates: Sequence[int], rng: np.random.Generator, *, reg_covar: float = 1e-6) -> tuple[int, np.ndarray]:
    """Choose the number of regions :math:`M` by the Bayesian information criterion.

    Sec. 3.1: "M is either assumed a priori known or estimated from the data by a
    suitable method, e.g., minimum description length (MDL)". BIC has the same form as
    the two-part MDL code length of a Gaussian mixture.

    Parameters
    ----------
    X : array_like, shape (N, n)
        Training points.
    candidates : sequence of int
        Numbers of regions to try (each >= 1).
    rng : numpy.random.Generator
        Randomness of EM.
    reg_covar : float, keyword-only, default 1e-6
        Added to the covariance diagonals by EM.

    Returns
    -------
    best : int
        The candidate with the smallest BIC.
    bic : numpy.ndarray
        BIC of every candidate.
    """
    X = _check_training_points(X)
    rng = as_rng(rng)
    cands = [as_int(c, "candidates", minimum=1) for c in candidates]
    if not cands:
        raise ValueError("candidates must not be empty")
    if max(cands) > len(X):
        raise ValueError(f"candidates must not exceed the number of points ({len(X)})")
    bic = np.array([_fit_gmm(X, c, rng, reg_covar).bic(X) for c in cands])
    return cands[int(np.argmin(bic))], bic


def learn_manifold(
    X: object,
    n_regions: int,
    n_prototypes: int,
    rng: np.random.Generator,
    *,
    dim: int | None = None,
    max_mse: float | None = None,
    reg_covar: float = 1e-6,
) -> DiscreteManifold:
    """Learn a discrete manifold model from points (Section 3.1 of Marques et al.).

    1. EM for a Gaussian mixture with ``n_regions`` full-covariance modes (eqs. (1)-(5)).
    2. Hard regions by the smallest squared Mahalanobis distance (eq. (6)).
    3. Local PCA frames from each mode's ``mu_i, R_i`` (eqs. (7)-(8)); the dimension is
       ``dim`` if given, else the smallest ``m`` whose discarded-eigenvalue error
       ``E^2 = sum_{i>m} lambda_i`` (eq. (9)) is at most ``max_mse``.
    4. ``n_prototypes`` k-means centroids per region in local coordinates (fewer if the
       region has fewer distinct points; regions that receive no point are dropped).
       Prototypes are sorted by their first local coordinate.

    .. warning::
       The model can therefore have **fewer regions or prototypes than asked**. When that
       happens a :class:`UserWarning` says how many were kept; check
       ``DiscreteManifold.n_regions`` and ``n_prototypes`` of the result.

    Parameters
    ----------
    X : array_like, shape (N, n)
        Training points on the manifold.
    n_regions : int
        Number of mixture modes ``M`` (see :func:`select_n_regions`).
    n_prototypes : int
        Prototypes per region.
    rng : numpy.random.Generator
        Seeds EM and k-means; the result is deterministic for a given generator state.
    dim : int, optional
        Hyperplane dimension (1 <= dim <= n). Exactly one of ``dim`` and ``max_mse``.
    max_mse : float, optional
        Largest allowed eq. (9) error per region.
    reg_covar : float
        Added to covariance diagonals by EM (keeps flat regions invertible).

    Returns
    -------
    DiscreteManifold
    """
    KMeans = optional_import("sklearn.cluster", "learn", "learning a discrete manifold").KMeans

    X = _check_training_points(X)
    rng = as_rng(rng)
    M = as_int(n_regions, "n_regions", minimum=1)
    K = as_int(n_prototypes, "n_prototypes", minimum=1)
    n = X.shape[1]
    if M > len(X):
        raise ValueError(f"n_regions ({M}) must not exceed the number of points ({len(X)})")
    if (dim is None) == (max_mse is None):
        raise ValueError("give exactly one of dim and max_mse")
    if dim is not None:
        dim = as_int(dim, "dim", minimum=1)
        if dim > n:
            raise ValueError(f"dim must be <= the ambient dimension {n}, got {dim}")
    else:
        max_mse = as_real(max_mse, "max_mse", 0)
    gmm = _fit_gmm(X, M, rng, reg_covar)
    means, covs, weights = gmm.means_, gmm.covariances_, gmm.weights_
    prec = np.linalg.pinv(covs, hermitian=True)
    D = X[:, None, :] - means[None]
    regions = np.argmin(np.einsum("nmi,mij,nmj->nm", D, prec, D), axis=1)
    keep = [k for k in range(M) if (regions == k).any()]
    bases, eigs, dims, protos = [], [], [], []
    for k in keep:
        lam, V = np.linalg.eigh(covs[k])
        order = np.argsort(lam)[::-1]
        lam, V = np.clip(lam[order], 0.0, None), V[:, order]
        # fix eigenvector signs deterministically (largest |component| positive)
        V = V * np.where(V[np.argmax(np.abs(V), axis=0), np.arange(n)] < 0, -1.0, 1.0)
        if dim is not None:
            m = dim
        else:
            tails = np.concatenate([np.cumsum(lam[::-1])[::-1][1:], [0.0]])  # E^2 for m = 1..n
            m = int(np.argmax(tails <= max_mse)) + 1
        Vm = V[:, :m]
        loc = (X[regions == k] - means[k]) @ Vm
        k_eff = min(K, len(np.unique(np.round(loc, 12), axis=0)))
        km = KMeans(n_clusters=k_eff, n_init=2, random_state=int(rng.integers(0, 2**31 - 1)))
        km.fit(loc)
        C = km.cluster_centers_
        C = C[np.lexsort(C.T[::-1])]
        bases.append(Vm)
        eigs.append(lam)
        dims.append(m)
        protos.append(C)
    n_kept = sum(len(C) for C in protos)
    if len(keep) < M or n_kept < M * K:
        warnings.warn(
            f"learn_manifold kept {len(keep)} of n_regions={M} regions and {n_kept} of "
            f"{M * K} prototypes (n_regions x n_prototypes): empty regions are dropped and a "
            "region with fewer distinct points than n_prototypes gets fewer prototypes",
            UserWarning, stacklevel=2,
        )
    return DiscreteManifold(
        means=means[keep], covariances=covs[keep], weights=weights[keep] / weights[keep].sum(),
        bases=bases, eigenvalues=np.array(eigs), dims=np.array(dims, dtype=np.int64), local_prototypes=protos,
    )

"""Trajectory estimation on manifolds: the DMA algorithm of Marques et al. (2002).

Implements J. S. Marques et al., "Trajectory estimation on manifolds", Signal
Processing, 2002 (the *discrete manifold analysis*, DMA, algorithm):

* **Manifold learning** (Sec. 3.1): a Gaussian mixture fitted by EM (eqs. (1)-(5),
  :class:`sklearn.mixture.GaussianMixture`) splits the manifold into regions; a point
  belongs to the region of smallest squared Mahalanobis distance (eq. (6)); local PCA
  frames (eqs. (7)-(8)) whose dimension is given or chosen from the discarded-eigenvalue
  error (eq. (9)); prototypes per region by k-means in local coordinates. The number of
  regions can be chosen by BIC (an MDL-type criterion). See :func:`learn_manifold`.
* **Motion model** (Sec. 3.2): the global transition matrix ``A`` of eq. (13), made of
  local blocks ``A_ii`` (eq. (11)) and cross-region blocks ``A_ij`` (eq. (12)), estimated
  by relative frequencies of prototype transitions (eq. (10)) and kept as a
  :mod:`scipy.sparse` matrix (:func:`estimate_transitions`); or built from a known
  velocity field as in Example 1 (:func:`transitions_from_velocity_field`).
* **Sensor models** ``p(y(t) | u(t))``: :class:`LinearGaussianSensor` (Example 1),
  :class:`RangeCosineSensor` (eq. (14), Example 2), :class:`ActivePixelSensor`
  (eq. (15), Example 3), all subclasses of :class:`SensorModel`.
* **Trajectory retrieval** (Sec. 3.3): :func:`viterbi`, :func:`forward_filter` and
  :func:`forward_backward`, all in log space and working with dense or sparse transition
  matrices; the :class:`DMA` estimator ties everything together.

**Log-probability conventions.** Transition matrices passed to the retrieval functions hold *log*-probabilities. A dense
array uses ``-inf`` for impossible transitions. For a :mod:`scipy.sparse` matrix only
the *stored* entries are transitions: an absent (implicit) entry means an impossible
transition (log-probability ``-inf``), while an explicitly stored ``0.0`` means
log-probability 0, i.e. probability one. :func:`log_transitions` converts a (sparse or
dense) probability matrix into this form without losing the sparsity pattern.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.special import logsumexp

__all__ = [
    "viterbi",
    "forward_filter",
    "forward_backward",
    "path_log_probability",
    "log_transitions",
    "check_row_stochastic",
    "DiscreteManifold",
    "learn_manifold",
    "select_n_regions",
    "estimate_transitions",
    "estimate_start",
    "neighbor_graph",
    "transitions_from_velocity_field",
    "SensorModel",
    "LinearGaussianSensor",
    "RangeCosineSensor",
    "ActivePixelSensor",
    "DMA",
]

_STOCH_TOL = 1e-6


# ----------------------------------------------------------------------------------
# input validation
# ----------------------------------------------------------------------------------
def _as_float_array(x: object, name: str, ndim: int) -> np.ndarray:
    if sp.issparse(x):
        raise TypeError(f"{name} must be a dense array, got a scipy.sparse matrix")
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array") from exc
    if a.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {a.shape}")
    return a


def _check_log_probs(a: np.ndarray, name: str) -> None:
    if np.isnan(a).any():
        raise ValueError(f"{name} contains NaN")
    if (a > 1e-9).any():
        raise ValueError(f"{name} must hold log-probabilities (<= 0, -inf for impossible), found {a.max():.3g}")


def _check_int(value: object, name: str, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _check_rng(rng: object) -> np.random.Generator:
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    return rng


@dataclass(frozen=True)
class _Chain:
    """Validated HMM in log space; ``csc`` (sparse) or ``dense`` transitions."""

    log_start: np.ndarray
    log_emission: np.ndarray
    dense: np.ndarray | None
    # sparse: for each destination state j, its predecessors indices[indptr[j]:indptr[j+1]]
    indptr: np.ndarray | None = None
    indices: np.ndarray | None = None
    data: np.ndarray | None = None

    @property
    def n_states(self) -> int:
        return self.log_start.shape[0]


def _validate(log_start: object, log_trans: object, log_emission: object) -> _Chain:
    ls = _as_float_array(log_start, "log_start", 1)
    le = _as_float_array(log_emission, "log_emission", 2)
    S = ls.shape[0]
    if S == 0:
        raise ValueError("log_start must have at least one state")
    if le.shape[0] == 0:
        raise ValueError("log_emission must have at least one time step (shape (N, S) with N >= 1)")
    if le.shape[1] != S:
        raise ValueError(f"log_emission must have shape (N, {S}) to match log_start, got {le.shape}")
    _check_log_probs(ls, "log_start")
    if np.isnan(le).any():
        raise ValueError("log_emission contains NaN (a NaN observation?)")
    if np.isposinf(le).any():
        raise ValueError("log_emission contains +inf")
    if abs(logsumexp(ls)) > _STOCH_TOL:
        raise ValueError(f"log_start must be a log-probability vector (sum of exp = 1), got sum {np.exp(logsumexp(ls)):.6g}")
    if sp.issparse(log_trans):
        if log_trans.shape != (S, S):
            raise ValueError(f"log_trans must have shape ({S}, {S}), got {log_trans.shape}")
        csc = sp.csc_array(log_trans, dtype=float, copy=True)
        csc.sum_duplicates()
        csc.sort_indices()
        _check_log_probs(csc.data, "log_trans")
        check_row_stochastic(csc, log=True, name="log_trans")
        return _Chain(ls, le, None, csc.indptr.astype(np.int64), csc.indices.astype(np.int64), csc.data)
    lt = _as_float_array(log_trans, "log_trans", 2)
    if lt.shape != (S, S):
        raise ValueError(f"log_trans must have shape ({S}, {S}), got {lt.shape}")
    _check_log_probs(lt, "log_trans")
    check_row_stochastic(lt, log=True, name="log_trans")
    return _Chain(ls, le, lt)


def check_row_stochastic(matrix: object, *, log: bool = False, name: str = "matrix", atol: float = _STOCH_TOL) -> None:
    """Raise ``ValueError`` unless every row of ``matrix`` sums to one.

    Parameters
    ----------
    matrix : array_like or scipy.sparse matrix, shape (S, S)
        Probabilities, or log-probabilities if ``log`` (for sparse log matrices only the
        stored entries count; absent entries are impossible transitions).
    log : bool, default False
        Whether ``matrix`` holds log-probabilities.
    name : str
        Name used in the error message.
    atol : float
        Tolerance on each row sum.
    """
    if sp.issparse(matrix):
        csr = sp.csr_array(matrix, dtype=float)
        vals = np.exp(csr.data) if log else csr.data
        if not log and (np.isnan(vals).any() or (vals < 0).any()):
            raise ValueError(f"{name} must hold probabilities in [0, 1]")
        rows = np.repeat(np.arange(csr.shape[0]), np.diff(csr.indptr))
        sums = np.bincount(rows, weights=vals, minlength=csr.shape[0])
    else:
        a = np.asarray(matrix, dtype=float)
        if a.ndim != 2 or a.shape[0] != a.shape[1]:
            raise ValueError(f"{name} must be a square matrix, got shape {a.shape}")
        if not log and (np.isnan(a).any() or (a < 0).any()):
            raise ValueError(f"{name} must hold probabilities in [0, 1]")
        sums = np.exp(a).sum(axis=1) if log else a.sum(axis=1)
    bad = np.flatnonzero(np.abs(sums - 1.0) > atol)
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"{name} must be row-stochastic: {bad.size} row(s) do not sum to 1 "
            f"(row {i} sums to {sums[i]:.6g}; an all-zero row is a state never left in training, "
            "use smoothing in estimate_transitions)"
        )


def log_transitions(probabilities: object) -> np.ndarray | sp.csr_array:
    """Log of a transition matrix, keeping the sparsity pattern of a sparse input.

    Parameters
    ----------
    probabilities : array_like or scipy.sparse matrix, shape (S, S)
        Row-stochastic transition probabilities.

    Returns
    -------
    numpy.ndarray or scipy.sparse.csr_array
        Dense input: ``log(P)`` with ``-inf`` where ``P == 0``. Sparse input: a CSR
        array whose stored entries are ``log`` of the stored positive probabilities
        (stored zeros are dropped, so absent = impossible).
    """
    if sp.issparse(probabilities):
        csr = sp.csr_array(probabilities, dtype=float, copy=True)
        csr.eliminate_zeros()
        check_row_stochastic(csr, name="probabilities")
        csr.data = np.log(csr.data)
        return csr
    a = np.asarray(probabilities, dtype=float)
    check_row_stochastic(a, name="probabilities")
    with np.errstate(divide="ignore"):
        return np.log(a)


# ----------------------------------------------------------------------------------
# retrieval: Viterbi, forward filtering, forward-backward (Sec. 3.3)
# ----------------------------------------------------------------------------------
def _segment_max(vals: np.ndarray, indptr: np.ndarray, nonempty: np.ndarray, S: int) -> np.ndarray:
    out = np.full(S, -np.inf)
    if vals.size:
        red = np.maximum.reduceat(vals, indptr[:-1][nonempty])
        out[nonempty] = red
    return out


def _segment_logsumexp(vals: np.ndarray, indptr: np.ndarray, nonempty: np.ndarray, counts: np.ndarray, S: int) -> np.ndarray:
    m = _segment_max(vals, indptr, nonempty, S)
    shift = np.where(np.isfinite(m), m, 0.0)
    e = np.exp(vals - np.repeat(shift, counts))
    out = np.full(S, -np.inf)
    if vals.size:
        s = np.add.reduceat(e, indptr[:-1][nonempty])
        with np.errstate(divide="ignore"):
            out[nonempty] = np.log(s) + shift[nonempty]
    return out


def viterbi(log_start: object, log_trans: object, log_emission: object) -> np.ndarray:
    """Most likely state path of a hidden Markov model (Viterbi, in log space).

    Sec. 3.3 of Marques et al.: the discrete state sequence ``u`` maximising
    ``P(u | y)`` given the motion model (eq. (13)) and the sensor model
    ``p(y(t) | u(t))``.

    Parameters
    ----------
    log_start : array_like, shape (S,)
        Log-probabilities of the initial state (``-inf`` for impossible).
    log_trans : array_like or scipy.sparse matrix, shape (S, S)
        Log transition probabilities, row ``i`` = from state ``i``. Dense: ``-inf`` for
        impossible transitions. Sparse: stored entries are the log-probabilities of the
        allowed transitions; **absent (implicit) entries are impossible transitions**
        (not log-probability 0). Every row must be stochastic.
    log_emission : array_like, shape (N, S)
        ``log p(y(t) | state)`` for every time ``t`` and state (log-densities may be > 0).

    Returns
    -------
    numpy.ndarray of int, shape (N,)
        The most likely state path (ties broken towards the lowest state index).

    Raises
    ------
    ValueError
        On shape mismatch, NaN, non-stochastic rows, or if every path has probability 0.
    TypeError
        On non-numeric input.

    Notes
    -----
    The dense recursion costs ``O(N S^2)``, the sparse one ``O(N nnz)``. The scores of
    every step are kept (``N x S`` floats) and back-pointers are recovered during the
    traceback, one column at a time.
    """
    ch = _validate(log_start, log_trans, log_emission)
    le = ch.log_emission
    N, S = le.shape
    delta = np.empty((N, S))
    delta[0] = ch.log_start + le[0]
    if ch.dense is not None:
        A = ch.dense
        back = np.empty((N, S), dtype=np.int64)
        for t in range(1, N):
            scores = delta[t - 1][:, None] + A
            back[t] = np.argmax(scores, axis=0)
            delta[t] = scores[back[t], np.arange(S)] + le[t]
    else:
        indptr, indices, data = ch.indptr, ch.indices, ch.data
        counts = np.diff(indptr)
        nonempty = counts > 0
        for t in range(1, N):
            vals = delta[t - 1][indices] + data
            delta[t] = _segment_max(vals, indptr, nonempty, S) + le[t]
    last = int(np.argmax(delta[-1]))
    if not np.isfinite(delta[-1, last]):
        raise ValueError("every state path has probability 0 under log_start, log_trans and log_emission")
    path = np.empty(N, dtype=np.int64)
    path[-1] = last
    for t in range(N - 1, 0, -1):
        j = path[t]
        if ch.dense is not None:
            path[t - 1] = back[t, j]
        else:
            lo, hi = ch.indptr[j], ch.indptr[j + 1]
            cand = delta[t - 1][ch.indices[lo:hi]] + ch.data[lo:hi]
            # ties: lowest predecessor index (indices are sorted)
            path[t - 1] = ch.indices[lo + int(np.argmax(cand))]
    return path


def _forward(ch: _Chain) -> tuple[np.ndarray, float]:
    le = ch.log_emission
    N, S = le.shape
    alpha = np.empty((N, S))
    alpha[0] = ch.log_start + le[0]
    if ch.dense is None:
        counts = np.diff(ch.indptr)
        nonempty = counts > 0
    for t in range(1, N):
        if ch.dense is not None:
            pred = logsumexp(alpha[t - 1][:, None] + ch.dense, axis=0)
        else:
            vals = alpha[t - 1][ch.indices] + ch.data
            pred = _segment_logsumexp(vals, ch.indptr, nonempty, counts, S)
        alpha[t] = pred + le[t]
    loglik = float(logsumexp(alpha[-1]))
    if not np.isfinite(loglik):
        raise ValueError("the observation sequence has probability 0 under the model")
    return alpha, loglik


def forward_filter(log_start: object, log_trans: object, log_emission: object) -> np.ndarray:
    """Filtered (on-line) log posteriors ``log P(u(t) | y(1..t))``.

    The forward pass of the forward-backward algorithm (Sec. 3.3: "used when an on-line
    estimate of the state variable is required"), in log space. Arguments as in
    :func:`viterbi`.

    Returns
    -------
    numpy.ndarray, shape (N, S)
        Normalised log posteriors; ``argmax`` along axis 1 is the on-line estimate.
    """
    ch = _validate(log_start, log_trans, log_emission)
    alpha, _ = _forward(ch)
    return alpha - logsumexp(alpha, axis=1, keepdims=True)


def forward_backward(log_start: object, log_trans: object, log_emission: object) -> tuple[np.ndarray, float]:
    """Smoothed log posteriors ``log P(u(t) | y(1..N))`` and the log-likelihood.

    The forward-backward algorithm in log space (no underflow on long sequences).
    Arguments as in :func:`viterbi`.

    Returns
    -------
    log_posterior : numpy.ndarray, shape (N, S)
        Normalised log posterior of each state at each time.
    log_likelihood : float
        ``log p(y(1..N))``.
    """
    ch = _validate(log_start, log_trans, log_emission)
    alpha, loglik = _forward(ch)
    le = ch.log_emission
    N, S = le.shape
    beta = np.zeros((N, S))
    if ch.dense is None:
        # backward needs, for each source i, its successors: use CSR of the same matrix
        csc = sp.csc_array((ch.data, ch.indices, ch.indptr), shape=(S, S))
        csr = csc.tocsr()
        csr.sort_indices()
        r_indptr, r_indices, r_data = csr.indptr, csr.indices, csr.data
        r_counts = np.diff(r_indptr)
        r_nonempty = r_counts > 0
    for t in range(N - 2, -1, -1):
        nxt = le[t + 1] + beta[t + 1]
        if ch.dense is not None:
            beta[t] = logsumexp(ch.dense + nxt[None, :], axis=1)
        else:
            vals = nxt[r_indices] + r_data
            beta[t] = _segment_logsumexp(vals, r_indptr, r_nonempty, r_counts, S)
    post = alpha + beta
    post = post - logsumexp(post, axis=1, keepdims=True)
    return post, loglik


def path_log_probability(path: object, log_start: object, log_trans: object, log_emission: object) -> float:
    """Joint log-probability ``log P(u, y)`` of a state path (the Viterbi objective).

    Parameters
    ----------
    path : array_like of int, shape (N,)
        State path.
    log_start, log_trans, log_emission
        As in :func:`viterbi`.
    """
    ch = _validate(log_start, log_trans, log_emission)
    p = np.asarray(path)
    N, S = ch.log_emission.shape
    if p.shape != (N,) or not np.issubdtype(p.dtype, np.integer):
        raise ValueError(f"path must be an int array of shape ({N},), got {p.dtype} {p.shape}")
    if (p < 0).any() or (p >= S).any():
        raise ValueError(f"path states must lie in [0, {S})")
    total = ch.log_start[p[0]] + ch.log_emission[np.arange(N), p].sum()
    if ch.dense is not None:
        total += ch.dense[p[:-1], p[1:]].sum()
    else:
        for i, j in zip(p[:-1], p[1:]):
            lo, hi = ch.indptr[j], ch.indptr[j + 1]
            k = np.searchsorted(ch.indices[lo:hi], i)
            if k < hi - lo and ch.indices[lo + k] == i:
                total += ch.data[lo + k]
            else:
                return -np.inf
    return float(total)


# ----------------------------------------------------------------------------------
# manifold learning (Sec. 3.1)
# ----------------------------------------------------------------------------------
@dataclass
class DiscreteManifold:
    """A manifold split into regions, each with a local frame and prototypes (Sec. 3.1).

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
        X = _as_float_array(X, name, 2)
        if X.shape[1] != self.ambient_dim:
            raise ValueError(f"{name} must have {self.ambient_dim} columns, got shape {X.shape}")
        if not np.isfinite(X).all():
            raise ValueError(f"{name} must be finite")
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
        k = _check_int(regions, "regions", 0)
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
    from sklearn.mixture import GaussianMixture

    seed = int(rng.integers(0, 2**31 - 1))
    gmm = GaussianMixture(
        n_components=n_regions, covariance_type="full", reg_covar=reg_covar,
        random_state=seed, n_init=1, init_params="k-means++", max_iter=500,
    )
    gmm.fit(X)
    return gmm


def _check_training_points(X: object) -> np.ndarray:
    X = _as_float_array(X, "X", 2)
    if X.shape[0] == 0:
        raise ValueError("X is empty: manifold learning needs training points")
    if not np.isfinite(X).all():
        raise ValueError("X must be finite (no NaN or inf)")
    return X


def select_n_regions(X: object, candidates: Sequence[int], rng: np.random.Generator, *, reg_covar: float = 1e-6) -> tuple[int, np.ndarray]:
    """Choose the number of regions ``M`` by the Bayesian information criterion.

    Sec. 3.1: "M is either assumed a priori known or estimated from the data by a
    suitable method, e.g., minimum description length (MDL)". BIC has the same form as
    the two-part MDL code length of a Gaussian mixture.

    Returns
    -------
    best : int
        The candidate with the smallest BIC.
    bic : numpy.ndarray
        BIC of every candidate.
    """
    X = _check_training_points(X)
    rng = _check_rng(rng)
    cands = [_check_int(c, "candidates") for c in candidates]
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
    """Learn a discrete manifold model from points (Sec. 3.1 of Marques et al.).

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
    from sklearn.cluster import KMeans

    X = _check_training_points(X)
    rng = _check_rng(rng)
    M = _check_int(n_regions, "n_regions")
    K = _check_int(n_prototypes, "n_prototypes")
    n = X.shape[1]
    if M > len(X):
        raise ValueError(f"n_regions ({M}) must not exceed the number of points ({len(X)})")
    if (dim is None) == (max_mse is None):
        raise ValueError("give exactly one of dim and max_mse")
    if dim is not None:
        dim = _check_int(dim, "dim")
        if dim > n:
            raise ValueError(f"dim must be <= the ambient dimension {n}, got {dim}")
    elif not (np.isfinite(max_mse) and max_mse >= 0):
        raise ValueError(f"max_mse must be a finite number >= 0, got {max_mse}")
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


# ----------------------------------------------------------------------------------
# motion model (Sec. 3.2)
# ----------------------------------------------------------------------------------
def _check_sequences(sequences: object, n_states: int) -> list[np.ndarray]:
    if isinstance(sequences, np.ndarray) and sequences.ndim == 1:
        sequences = [sequences]
    try:
        seqs = [np.asarray(s) for s in sequences]  # type: ignore[union-attr]
    except TypeError as exc:
        raise TypeError("sequences must be a list of 1-D int arrays") from exc
    if not seqs:
        raise ValueError("sequences is empty: the motion model needs training sequences")
    for s in seqs:
        if s.ndim != 1 or not (np.issubdtype(s.dtype, np.integer) or s.size == 0):
            raise ValueError("sequences must be 1-D int arrays of state indices")
        if s.size and ((s < 0).any() or (s >= n_states).any()):
            raise ValueError(f"sequences contain states outside [0, {n_states})")
    if sum(s.size for s in seqs) == 0:
        raise ValueError("sequences are all empty")
    return seqs


def estimate_transitions(
    sequences: object,
    n_states: int,
    *,
    alpha: float = 1e-3,
    neighbors: object | None = None,
) -> sp.csr_array:
    """Transition matrix ``A`` (eq. (13)) by relative frequencies, sparse.

    ``a_kl = P(u(t) = u_k | u(t-1) = u_l)`` (eqs. (10)-(12); here stored row ``l``,
    column ``k``, so rows sum to one) is the number of observed ``l -> k`` transitions
    divided by the number of transitions out of ``l``.

    **Smoothing.** A state never left in training would give an all-zero row (and a
    state never seen, an empty one), which breaks retrieval. A pseudo-count ``alpha``
    is added to every self-transition and to every entry of the optional ``neighbors``
    pattern (e.g. :func:`neighbor_graph`) before normalising. With the default
    ``alpha = 1e-3`` and no neighbours, rows seen in training are changed by less than
    ``alpha / count`` and unseen states become absorbing (stay put). The result is
    sparse: only observed transitions, self-loops and neighbour entries are stored.

    Parameters
    ----------
    sequences : list of 1-D int arrays
        Training state (prototype) sequences.
    n_states : int
        Number of states ``S``.
    alpha : float, default 1e-3
        Pseudo-count (> 0).
    neighbors : scipy.sparse matrix or array, shape (S, S), optional
        Pattern of extra allowed transitions (non-zero = allowed).

    Returns
    -------
    scipy.sparse.csr_array, shape (S, S)
        Row-stochastic transition probabilities.
    """
    S = _check_int(n_states, "n_states")
    seqs = _check_sequences(sequences, S)
    if not (np.isfinite(alpha) and alpha > 0):
        raise ValueError(f"alpha must be > 0 so that no row is all zeros, got {alpha}")
    src = np.concatenate([s[:-1] for s in seqs]).astype(np.int64)
    dst = np.concatenate([s[1:] for s in seqs]).astype(np.int64)
    C = sp.coo_array((np.ones(src.size), (src, dst)), shape=(S, S)).tocsr()
    C = C + alpha * sp.eye_array(S, format="csr")
    if neighbors is not None:
        if neighbors.shape != (S, S):
            raise ValueError(f"neighbors must have shape ({S}, {S}), got {neighbors.shape}")
        Nb = sp.csr_array(neighbors, dtype=float)
        Nb.data = np.ones_like(Nb.data)
        Nb.eliminate_zeros()
        C = C + alpha * Nb
    C = sp.csr_array(C)
    C.sum_duplicates()
    rows = np.asarray(C.sum(axis=1)).ravel()
    C = sp.csr_array(sp.diags_array(1.0 / rows) @ C)
    C.sort_indices()
    return C


def estimate_start(sequences: object, n_states: int, *, alpha: float = 1.0) -> np.ndarray:
    """Initial-state probabilities: state frequencies of the training sequences plus a
    pseudo-count ``alpha`` per state (so that every state may start a trajectory)."""
    S = _check_int(n_states, "n_states")
    seqs = _check_sequences(sequences, S)
    if not (np.isfinite(alpha) and alpha > 0):
        raise ValueError(f"alpha must be > 0, got {alpha}")
    counts = np.bincount(np.concatenate(seqs).astype(np.int64), minlength=S) + alpha
    return counts / counts.sum()


def neighbor_graph(points: object, radius: float) -> sp.csr_array:
    """Sparse 0/1 pattern of prototype pairs closer than ``radius`` (self excluded),
    for smoothing in :func:`estimate_transitions`."""
    from scipy.spatial import cKDTree

    P = _as_float_array(points, "points", 2)
    if not np.isfinite(P).all():
        raise ValueError("points must be finite")
    if not (np.isfinite(radius) and radius > 0):
        raise ValueError(f"radius must be > 0, got {radius}")
    pairs = cKDTree(P).query_pairs(radius, output_type="ndarray")
    S = len(P)
    i = np.concatenate([pairs[:, 0], pairs[:, 1]])
    j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    return sp.csr_array((np.ones(i.size), (i, j)), shape=(S, S))


def transitions_from_velocity_field(
    points: object,
    velocity: object,
    dt: float,
    *,
    n_next: int = 2,
    project: object | None = None,
    exclude_self: bool = False,
) -> sp.csr_array:
    """Markov chain on prototypes from a known velocity field (Example 1, Fig. 6a).

    From each prototype ``u_l`` the point moves to ``p_l = u_l + dt * v(u_l)`` (then
    mapped by ``project``, e.g. back onto the sphere). The allowed transitions go to the
    ``n_next`` prototypes nearest to ``p_l`` (with ``n_next = 2``, "transitions to one
    of two consecutive states" as in Fig. 3), with probabilities proportional to
    ``exp(-d^2 / (2 s^2))``, ``d`` the distance to ``p_l`` and ``s`` the median
    nearest-neighbour spacing of the prototypes.

    With ``exclude_self`` the prototype ``u_l`` itself is never a successor (no
    self-loops: the point always moves). ``n_next = 1, exclude_self = True`` gives the
    *deterministic* chain "each centroid to the nearest other centroid along the field"
    (one arrow per centroid).

    Parameters
    ----------
    points : array_like, shape (S, n)
        Prototypes on the manifold.
    velocity : callable
        ``velocity(points) -> (S, n)`` velocity field.
    dt : float
        Time step (> 0).
    n_next : int
        Number of successors per state.
    project : callable, optional
        ``project(points) -> points`` applied to the predicted points.
    exclude_self : bool, default False
        Leave each prototype out of its own successors.

    Returns
    -------
    scipy.sparse.csr_array, shape (S, S)
        Row-stochastic transition probabilities.
    """
    from scipy.spatial import cKDTree

    P = _as_float_array(points, "points", 2)
    S = len(P)
    k = _check_int(n_next, "n_next")
    if not isinstance(exclude_self, (bool, np.bool_)):
        raise TypeError(f"exclude_self must be a bool, got {type(exclude_self).__name__}")
    if k > S - int(exclude_self):
        raise ValueError(f"n_next must be <= the number of candidate successors ({S - int(exclude_self)})")
    if not callable(velocity):
        raise TypeError("velocity must be callable: velocity(points) -> array of the same shape")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be > 0, got {dt}")
    V = np.asarray(velocity(P), dtype=float)
    if V.shape != P.shape or not np.isfinite(V).all():
        raise ValueError(f"velocity(points) must return finite values of shape {P.shape}")
    pred = P + dt * V
    if project is not None:
        pred = np.asarray(project(pred), dtype=float)
    tree = cKDTree(P)
    spacing = float(np.median(tree.query(P, k=2)[0][:, 1]))
    if exclude_self:
        d, idx = tree.query(pred, k=k + 1)
        d, idx = d.reshape(S, k + 1), idx.reshape(S, k + 1)
        keep = idx != np.arange(S)[:, None]
        # drop the point itself if it is among the k + 1 nearest, else the farthest one
        keep[keep.all(axis=1), -1] = False
        d, idx = d[keep].reshape(S, k), idx[keep].reshape(S, k)
    else:
        d, idx = tree.query(pred, k=k)
        d, idx = d.reshape(S, k), idx.reshape(S, k)
    w = np.exp(-0.5 * (d / spacing) ** 2)
    w = np.where(w.sum(axis=1, keepdims=True) > 0, w, 1.0)
    w = w / w.sum(axis=1, keepdims=True)
    A = sp.csr_array((w.ravel(), (np.repeat(np.arange(S), k), idx.ravel())), shape=(S, S))
    A.sum_duplicates()
    A.sort_indices()
    return A


# ----------------------------------------------------------------------------------
# sensor models p(y(t) | u(t))
# ----------------------------------------------------------------------------------
class SensorModel:
    """Interface of a sensor model ``p(y | u_k)`` over a fixed set of prototypes.

    Subclasses implement :meth:`log_likelihood` (one observation -> ``(S,)`` array of
    ``log p(y | u_k)``); :meth:`log_likelihoods` stacks it over a sequence (override it
    to vectorise). ``n_states`` is the number of prototypes. User models only need these
    two members.
    """

    n_states: int

    def log_likelihood(self, observation: object) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def log_likelihoods(self, observations: object) -> np.ndarray:
        """``(N, S)`` log-likelihoods of a sequence of observations."""
        obs = list(observations)  # type: ignore[call-overload]
        if not obs:
            raise ValueError("observations is empty")
        return np.vstack([self.log_likelihood(o) for o in obs])


def _check_points_arg(points: object, name: str = "points", ncols: int | None = None) -> np.ndarray:
    P = _as_float_array(points, name, 2)
    if len(P) == 0:
        raise ValueError(f"{name} must not be empty")
    if not np.isfinite(P).all():
        raise ValueError(f"{name} must be finite")
    if ncols is not None and P.shape[1] != ncols:
        raise ValueError(f"{name} must have {ncols} columns, got shape {P.shape}")
    return P


class LinearGaussianSensor(SensorModel):
    """``y = H x + v``, ``v ~ N(0, R)`` (Example 1: ``H = [1 -1 1]``).

    Parameters
    ----------
    points : array_like, shape (S, n)
        Prototypes.
    H : array_like, shape (p, n)
        Observation matrix.
    noise_cov : float or array_like, shape (p, p)
        Covariance ``R`` (a float means ``R = noise_cov * I``).
    """

    def __init__(self, points: object, H: object, noise_cov: object):
        self.points = _check_points_arg(points)
        H = np.atleast_2d(np.asarray(H, dtype=float))
        if H.ndim != 2 or H.shape[1] != self.points.shape[1]:
            raise ValueError(f"H must have shape (p, {self.points.shape[1]}), got {H.shape}")
        p = H.shape[0]
        R = np.asarray(noise_cov, dtype=float)
        R = R * np.eye(p) if R.ndim == 0 else R
        if R.shape != (p, p) or not np.allclose(R, R.T) or np.linalg.eigvalsh(R).min() <= 0:
            raise ValueError(f"noise_cov must be a positive float or a ({p}, {p}) SPD matrix")
        self.H, self.R = H, R
        self.n_states = len(self.points)
        self._mean = self.points @ H.T
        self._Rinv = np.linalg.inv(R)
        self._const = -0.5 * (p * np.log(2 * np.pi) + np.linalg.slogdet(R)[1])

    def _obs(self, observations: object) -> np.ndarray:
        Y = np.asarray(observations, dtype=float)
        p = self.H.shape[0]
        if Y.ndim == 1 and p == 1:
            Y = Y[:, None]
        if Y.ndim != 2 or Y.shape[1] != p:
            raise ValueError(f"observations must have shape (N, {p}), got {np.shape(observations)}")
        if not np.isfinite(Y).all():
            raise ValueError("observations must be finite (no NaN)")
        return Y

    def log_likelihoods(self, observations: object) -> np.ndarray:
        Y = self._obs(observations)
        D = Y[:, None, :] - self._mean[None]
        return self._const - 0.5 * np.einsum("nki,ij,nkj->nk", D, self._Rinv, D)

    def log_likelihood(self, observation: object) -> np.ndarray:
        return self.log_likelihoods(np.atleast_1d(np.asarray(observation, dtype=float))[None])[0]


class RangeCosineSensor(SensorModel):
    """Range radar ``y_t = cos(omega d_t) + w_t``, ``w_t ~ N(0, noise_var)`` (eq. (14)).

    ``d_t`` is the distance from the prototype to the receiver (Example 2:
    ``omega = 0.02`` rad/m, ``noise_var = 0.05``).
    """

    def __init__(self, points: object, receiver: object, omega: float, noise_var: float):
        self.points = _check_points_arg(points)
        r = np.asarray(receiver, dtype=float)
        if r.shape != (self.points.shape[1],) or not np.isfinite(r).all():
            raise ValueError(f"receiver must be a finite point of shape ({self.points.shape[1]},)")
        if not (np.isfinite(omega) and omega > 0):
            raise ValueError(f"omega must be > 0, got {omega}")
        if not (np.isfinite(noise_var) and noise_var > 0):
            raise ValueError(f"noise_var must be > 0, got {noise_var}")
        self.receiver, self.omega, self.noise_var = r, float(omega), float(noise_var)
        self.n_states = len(self.points)
        self.distances = np.linalg.norm(self.points - r, axis=1)
        self._mean = np.cos(self.omega * self.distances)

    def log_likelihoods(self, observations: object) -> np.ndarray:
        y = np.asarray(observations, dtype=float)
        if y.ndim != 1 or y.size == 0:
            raise ValueError(f"observations must be a non-empty 1-D array, got shape {y.shape}")
        if not np.isfinite(y).all():
            raise ValueError("observations must be finite (no NaN)")
        r = y[:, None] - self._mean[None]
        return -0.5 * r**2 / self.noise_var - 0.5 * np.log(2 * np.pi * self.noise_var)

    def log_likelihood(self, observation: object) -> np.ndarray:
        return self.log_likelihoods(np.array([observation], dtype=float).ravel())[0]


class ActivePixelSensor(SensorModel):
    """Active-pixel count model ``p(y_t | u_k) ∝ c^{n_k}`` (eq. (15), Example 3).

    ``n_k`` is the number of active pixels (``|frame - background| > threshold``) in the
    ``L x L`` box centred at prototype ``u_k`` (pixel coordinates ``(row, col)``).
    ``log p = n_k log c`` up to a constant common to all prototypes, so ``c`` only acts
    through ``log c`` (it is the likelihood ratio of a pixel being active on the car
    versus off it; see :meth:`fit_c`).

    Parameters
    ----------
    points : array_like, shape (S, 2)
        Prototype centres in pixel coordinates (row, col).
    box : int
        Box side ``L`` (odd).
    c : float
        Base of eq. (15), > 1.
    """

    def __init__(self, points: object, box: int, c: float):
        self.points = _check_points_arg(points, ncols=2)
        L = _check_int(box, "box")
        if L % 2 == 0:
            raise ValueError(f"box must be odd, got {L}")
        if not (np.isfinite(c) and c > 0):
            raise ValueError(f"c must be > 0, got {c}")
        self.box, self.c = L, float(c)
        self.n_states = len(self.points)
        self._rc = np.rint(self.points).astype(np.int64)

    def counts(self, active: object) -> np.ndarray:
        """Active-pixel counts ``n_k`` for a binary image or a stack ``(N, H, W)``."""
        A = np.asarray(active)
        single = A.ndim == 2
        if single:
            A = A[None]
        if A.ndim != 3:
            raise ValueError(f"active must be a binary image (H, W) or stack (N, H, W), got shape {np.shape(active)}")
        N, Hh, W = A.shape
        h = self.box // 2
        I = np.zeros((N, Hh + 1, W + 1))
        I[:, 1:, 1:] = np.cumsum(np.cumsum(A.astype(float), axis=1), axis=2)
        r0 = np.clip(self._rc[:, 0] - h, 0, Hh)
        r1 = np.clip(self._rc[:, 0] + h + 1, 0, Hh)
        c0 = np.clip(self._rc[:, 1] - h, 0, W)
        c1 = np.clip(self._rc[:, 1] + h + 1, 0, W)
        n = I[:, r1, c1] - I[:, r0, c1] - I[:, r1, c0] + I[:, r0, c0]
        return n[0] if single else n

    def log_likelihoods(self, observations: object) -> np.ndarray:
        """``n_k log c`` for a stack of binary (active-pixel) images ``(N, H, W)``."""
        A = np.asarray(observations)
        if A.ndim != 3 or A.shape[0] == 0:
            raise ValueError(f"observations must be a non-empty stack of binary images (N, H, W), got shape {A.shape}")
        return self.counts(A) * np.log(self.c)

    def log_likelihood(self, observation: object) -> np.ndarray:
        A = np.asarray(observation)
        if A.ndim != 2:
            raise ValueError(f"observation must be a binary image (H, W), got shape {A.shape}")
        return self.log_likelihoods(A[None])[0]

    @staticmethod
    def fit_c(active: object, positions: object, box: int) -> float:
        """Estimate ``c`` of eq. (15) from training frames with known car positions.

        With pixels active independently with probability ``q1`` inside the car box and
        ``q0`` elsewhere, the likelihood ratio of a box position is proportional to
        ``c^{n_k}`` with ``c = q1 (1 - q0) / (q0 (1 - q1))``; ``q1`` and ``q0`` are
        relative frequencies (strong law of large numbers, as in the paper).
        """
        A = np.asarray(active).astype(bool)
        P = np.asarray(positions, dtype=float)
        if A.ndim != 3 or P.shape != (A.shape[0], 2):
            raise ValueError("active must be (N, H, W) and positions (N, 2)")
        if A.shape[0] == 0:
            raise ValueError("fit_c needs at least one training frame")
        L = _check_int(box, "box")
        N, Hh, W = A.shape
        h = L // 2
        I = np.zeros((N, Hh + 1, W + 1))
        I[:, 1:, 1:] = np.cumsum(np.cumsum(A, axis=1, dtype=float), axis=2)
        rc = np.rint(P).astype(np.int64)
        r0, r1 = np.clip(rc[:, 0] - h, 0, Hh), np.clip(rc[:, 0] + h + 1, 0, Hh)
        c0, c1 = np.clip(rc[:, 1] - h, 0, W), np.clip(rc[:, 1] + h + 1, 0, W)
        t = np.arange(N)
        inside = float((I[t, r1, c1] - I[t, r0, c1] - I[t, r1, c0] + I[t, r0, c0]).sum())
        n_in = L * L * len(A)
        n_out = A[0].size * len(A) - n_in
        q1 = (inside + 1) / (n_in + 2)
        q0 = (A.sum() - inside + 1) / (n_out + 2)
        return float(q1 * (1 - q0) / (q0 * (1 - q1)))


# ----------------------------------------------------------------------------------
# the DMA estimator
# ----------------------------------------------------------------------------------
class DMA:
    """Discrete manifold analysis: learn a manifold and a motion model, retrieve trajectories.

    ``fit`` runs the off-line steps of Marques et al. on training trajectories (manifold
    learning, Sec. 3.1; motion model, Sec. 3.2); ``predict_path`` / ``predict`` retrieve
    the prototype sequence from observations with a sensor model (Sec. 3.3) and map it to
    the manifold with eq. (7).

    Parameters
    ----------
    n_regions : int
        Number of regions ``M``.
    n_prototypes : int
        Prototypes per region.
    dim : int, optional
        Local hyperplane dimension (default: chosen by ``max_mse``; if both are None,
        ``dim = 1``).
    max_mse : float, optional
        Eq. (9) error bound that chooses the dimension per region.
    alpha : float
        Smoothing pseudo-count of :func:`estimate_transitions`.
    neighbor_radius : float, optional
        If given, smoothing also allows transitions between prototypes closer than this.
    rng : numpy.random.Generator, optional
        Randomness for EM and k-means (default ``numpy.random.default_rng(0)``).

    Attributes
    ----------
    manifold_ : DiscreteManifold
    transitions_ : scipy.sparse.csr_array, shape (K, K)
    start_ : numpy.ndarray, shape (K,)
    prototypes_ : numpy.ndarray, shape (K, n)
    """

    def __init__(
        self,
        n_regions: int = 8,
        n_prototypes: int = 8,
        *,
        dim: int | None = None,
        max_mse: float | None = None,
        alpha: float = 1e-3,
        neighbor_radius: float | None = None,
        rng: np.random.Generator | None = None,
    ):
        self.n_regions = n_regions
        self.n_prototypes = n_prototypes
        self.dim = dim
        self.max_mse = max_mse
        self.alpha = alpha
        self.neighbor_radius = neighbor_radius
        self.rng = rng

    def fit(self, trajectories: Sequence[object]) -> "DMA":
        """Learn the manifold (Sec. 3.1) and the motion model (Sec. 3.2).

        Parameters
        ----------
        trajectories : list of array_like, each (T_i, n)
            Training trajectories (points on the manifold, in time order).
        """
        if isinstance(trajectories, np.ndarray) and trajectories.ndim == 2:
            trajectories = [trajectories]
        trajs = [_as_float_array(t, "trajectories[i]", 2) for t in trajectories]
        if not trajs or sum(len(t) for t in trajs) == 0:
            raise ValueError("trajectories is empty: fit needs training trajectories")
        if len({t.shape[1] for t in trajs}) != 1:
            raise ValueError("all trajectories must have the same number of columns")
        X = np.vstack(trajs)
        rng = np.random.default_rng(0) if self.rng is None else _check_rng(self.rng)
        dim = self.dim if (self.dim is not None or self.max_mse is not None) else 1
        self.manifold_ = learn_manifold(X, self.n_regions, self.n_prototypes, rng, dim=dim, max_mse=self.max_mse)
        self.prototypes_ = self.manifold_.prototypes
        S = self.manifold_.n_prototypes
        seqs = [self.manifold_.quantize(t) for t in trajs if len(t)]
        nb = None if self.neighbor_radius is None else neighbor_graph(self.prototypes_, self.neighbor_radius)
        self.transitions_ = estimate_transitions(seqs, S, alpha=self.alpha, neighbors=nb)
        self.start_ = estimate_start(seqs, S)
        self.training_sequences_ = seqs
        return self

    def _check_fitted(self) -> None:
        if not hasattr(self, "transitions_"):
            raise ValueError("this DMA instance is not fitted yet: call fit first")

    def log_emission(self, observations: object, sensor: SensorModel) -> np.ndarray:
        """``(N, K)`` sensor log-likelihoods, checked against the prototypes."""
        self._check_fitted()
        if not isinstance(sensor, SensorModel):
            raise TypeError("sensor must be a projtrack.dma.SensorModel")
        if sensor.n_states != self.manifold_.n_prototypes:
            raise ValueError(f"sensor has {sensor.n_states} states, the model {self.manifold_.n_prototypes} prototypes")
        return sensor.log_likelihoods(observations)

    def predict_path(self, observations: object, sensor: SensorModel, *, method: str = "viterbi") -> np.ndarray:
        """Prototype index sequence from observations.

        ``method``: ``"viterbi"`` (off-line MAP path), ``"smooth"`` (per-instant argmax of
        forward-backward posteriors) or ``"filter"`` (on-line argmax of forward posteriors).
        """
        le = self.log_emission(observations, sensor)
        with np.errstate(divide="ignore"):
            ls = np.log(self.start_)
        lt = log_transitions(self.transitions_)
        if method == "viterbi":
            return viterbi(ls, lt, le)
        if method == "smooth":
            return np.argmax(forward_backward(ls, lt, le)[0], axis=1)
        if method == "filter":
            return np.argmax(forward_filter(ls, lt, le), axis=1)
        raise ValueError(f"method must be 'viterbi', 'smooth' or 'filter', got {method!r}")

    def predict(self, observations: object, sensor: SensorModel, *, method: str = "viterbi") -> np.ndarray:
        """Points on the manifold (eq. (7)) of the retrieved prototype sequence, ``(N, n)``."""
        return self.prototypes_[self.predict_path(observations, sensor, method=method)]

    def quantize(self, X: object) -> np.ndarray:
        """Prototype index of each point (Fig. 5)."""
        self._check_fitted()
        return self.manifold_.quantize(X)

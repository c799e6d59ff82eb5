"""Hidden Markov model retrieval in log space, with dense or sparse transitions.

Sec. 3.3 of Marques et al. (2002): :func:`viterbi` (the MAP state path),
:func:`forward_filter` (on-line posteriors), :func:`forward_backward` (smoothed
posteriors and the log-likelihood) and :func:`path_log_probability` (the Viterbi
objective of a given path); :func:`log_transitions` and :func:`check_row_stochastic`
prepare and check transition matrices. Nothing here is specific to manifolds.

**Log-probability conventions.** Transition matrices passed to the retrieval functions
hold *log*-probabilities. A dense array uses ``-inf`` for impossible transitions. For a
:mod:`scipy.sparse` matrix only the *stored* entries are transitions: an absent
(implicit) entry means an impossible transition (log-probability ``-inf``), while an
explicitly stored ``0.0`` means log-probability 0, i.e. probability one.
:func:`log_transitions` converts a (sparse or dense) probability matrix into this form
without losing the sparsity pattern.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.special import logsumexp

from projtrack._validation import as_array, as_bool

__all__ = [
    "viterbi",
    "forward_filter",
    "forward_backward",
    "path_log_probability",
    "log_transitions",
    "check_row_stochastic",
]

#: Tolerance on the row sums of a transition matrix (and on the start vector's sum).
_STOCH_TOL = 1e-6


def _check_log_probs(a: np.ndarray, name: str) -> None:
    if np.isnan(a).any():
        raise ValueError(f"{name} contains NaN")
    if (a > 1e-9).any():
        raise ValueError(f"{name} must hold log-probabilities (<= 0, -inf for impossible), found {a.max():.3g}")


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
    ls = as_array(log_start, "log_start", ndim=1, finite=False)
    le = as_array(log_emission, "log_emission", ndim=2, finite=False)
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
    lt = as_array(log_trans, "log_trans", ndim=2, finite=False)
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
    log = as_bool(log, "log")
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
    r"""Most likely state path of a hidden Markov model (Viterbi, in log space).

    Sec. 3.3 of Marques et al.: the discrete state sequence :math:`u` maximising
    :math:`P(u \mid y)` given the motion model (eq. (13)) and the sensor model
    :math:`p(y(t) \mid u(t))`.

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
    The dense recursion costs :math:`O(N S^2)`, the sparse one :math:`O(N\,\mathrm{nnz})`.
    The scores of every step are kept (:math:`N \times S` floats) and back-pointers are
    recovered during the traceback, one column at a time.

    Examples
    --------
    Three states on a line, each step staying or moving one state to the right; the
    noisy readings suggest 0, 0, 2, 2 but the path may not jump two states at once:

    >>> import numpy as np
    >>> from projtrack.dma import viterbi
    >>> with np.errstate(divide="ignore"):
    ...     log_trans = np.log([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.0, 0.0, 1.0]])
    ...     log_start = np.log([1.0, 0.0, 0.0])
    >>> states = np.arange(3.0)
    >>> y = np.array([0.1, 0.2, 1.9, 2.1])
    >>> log_emission = -0.5 * (y[:, None] - states[None, :]) ** 2 / 0.5 ** 2
    >>> viterbi(log_start, log_trans, log_emission)
    array([0, 1, 2, 2])
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
    r"""Filtered (on-line) log posteriors :math:`\log P(u(t) \mid y(1..t))`.

    The forward pass of the forward-backward algorithm (Sec. 3.3: "used when an on-line
    estimate of the state variable is required"), in log space. Arguments as in
    :func:`viterbi`.

    Parameters
    ----------
    log_start : array_like, shape (S,)
        Log-probabilities of the initial state.
    log_trans : array_like or scipy.sparse matrix, shape (S, S)
        Log transition probabilities (see :func:`viterbi` for the sparse convention).
    log_emission : array_like, shape (N, S)
        :math:`\log p(y(t) \mid \text{state})` for every time and state.

    Returns
    -------
    numpy.ndarray, shape (N, S)
        Normalised log posteriors; ``argmax`` along axis 1 is the on-line estimate.
    """
    ch = _validate(log_start, log_trans, log_emission)
    alpha, _ = _forward(ch)
    return alpha - logsumexp(alpha, axis=1, keepdims=True)


def forward_backward(log_start: object, log_trans: object, log_emission: object) -> tuple[np.ndarray, float]:
    r"""Smoothed log posteriors :math:`\log P(u(t) \mid y(1..N))` and the log-likelihood.

    The forward-backward algorithm in log space (no underflow on long sequences).
    Arguments as in :func:`viterbi`.

    Parameters
    ----------
    log_start : array_like, shape (S,)
        Log-probabilities of the initial state.
    log_trans : array_like or scipy.sparse matrix, shape (S, S)
        Log transition probabilities (see :func:`viterbi` for the sparse convention).
    log_emission : array_like, shape (N, S)
        :math:`\log p(y(t) \mid \text{state})` for every time and state.

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
    r"""Joint log-probability :math:`\log P(u, y)` of a state path (the Viterbi objective).

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

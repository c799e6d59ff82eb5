"""Joint probabilistic data association (JPDA): Fisher & Casasent (1989).

Implements chapter 4 of Casasent's 1989 report (J. L. Fisher and D. P. Casasent,
"Fast JPDA multitarget tracking algorithm", Appl. Opt. 28, 1989): measurement
validation (Sec. II.A), feasibility matrices and eq. (1) (Sec. II.B), the conventional
computation of the association probabilities beta_jt and eq. (2) (Sec. II.C), the
modified validation matrix (MVM) of eqs. (3)-(4) (Sec. III.A), the fast algorithm with
measurements-used (MU) bit words and eq. (6) (Secs. III.B-D) with the operation counts
of Tables IV-V, a numerical model of the frequency-multiplexed vector-inner-product
processor of Fig. 5 (Sec. IV), and a JPDA tracker built on ``filterpy`` Kalman filters.

Notation follows the paper: ``m`` measurements, ``T`` targets, a binary validation
matrix of shape ``(m, T + 1)`` whose column 0 (the "no target", i.e. clutter, column)
is all ones, and feasibility matrices that pick exactly one 1 per row with at most one
1 per target column (Sec. II.B). The MVM has shape ``(m + 1, T)``: row 0 holds
``1 - P_D,t`` (eq. 3) and row ``j`` holds ``f_t(z_j) P_D,t`` (eq. 4), zero where
measurement ``j`` is not validated for target ``t``.

Probability model
-----------------
A feasible joint event assigns each target either "not detected" or a distinct
validated measurement; its weight is the product over targets of the MVM entry it
uses (row 0 for an undetected target), i.e. the product of the individual event
probabilities of Sec. II.C. With a clutter (false-measurement) density ``lambda``
the standard JPDA weights (Fortmann, Bar-Shalom & Scheffe 1983, in the form with
``1 - P_D`` for an undetected target) are recovered by dividing rows ``j >= 1`` by
``lambda`` (see :func:`modified_validation_matrix`); the paper's form is ``lambda = 1``.
``beta[j, t]`` is the probability of the events in which measurement ``j`` is
associated with target ``t`` and ``beta[0, t]`` that target ``t`` was not detected,
eq. (2); every column sums to 1.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import lru_cache
from math import comb, factorial

import numpy as np

from projtrack import _fast_jpda

__all__ = [
    "count_feasible_events",
    "iter_feasibility_matrices",
    "feasibility_matrices",
    "gate_threshold",
    "mahalanobis_sq",
    "validation_matrix",
    "modified_validation_matrix",
    "mvm_to_validation",
    "OpCount",
    "beta",
    "beta_enumerated",
    "beta_paper",
    "beta_forward_backward",
    "clusters",
    "mu_words",
    "vector_size",
    "vector_size_text_formula",
    "stage_expressions",
    "conventional_op_count",
    "fast_op_count",
    "optical_vip_schedule",
    "optical_vip_stage",
    "stage_update",
    "JPDATracker",
    "GNNTracker",
]

def _check_count(value: object, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value}")
    return int(value)


def count_feasible_events(m: int, T: int) -> int:
    """Number of feasibility matrices of an all-ones ``m x T`` validation matrix, eq. (1).

    Eq. (1) of Fisher & Casasent, for ``m >= T`` (the paper swaps ``m`` and ``T``
    otherwise, and the count is symmetric)::

        1 + sum_{k=0}^{T-1} C(T, k) * m! / (m - T + k)!

    The term ``k`` counts the events in which ``T - k`` targets are detected: choose
    which targets (``C(T, k)``) and give them distinct measurements in order
    (``m (m-1) ... (m - T + k + 1)``); the leading 1 is the event with no target
    detected. The result is an exact Python integer.

    Parameters
    ----------
    m : int
        Number of measurements, >= 0.
    T : int
        Number of targets, >= 0.

    Returns
    -------
    int
        The number of feasible joint events (Table I of the paper for m, T = 1..10).

    Examples
    --------
    >>> count_feasible_events(3, 2)
    13
    >>> count_feasible_events(10, 10)
    234662231
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    if m < T:
        m, T = T, m
    return 1 + sum(
        comb(T, k) * factorial(m) // factorial(m - T + k) for k in range(T)
    )


def iter_feasibility_matrices(validation: np.ndarray,
                              order: str = "lexicographic") -> Iterator[np.ndarray]:
    """Enumerate the feasibility matrices of a validation matrix (Sec. II.B).

    Parameters
    ----------
    validation : array_like of 0/1, shape (m, T + 1)
        Binary validation matrix; column 0 (clutter) must be all ones, column ``t``
        marks the measurements inside target ``t``'s gate.
    order : {"lexicographic", "colexicographic"}
        Order of the matrices, as an odometer over the target chosen for each
        measurement (target 0 first). ``"lexicographic"`` (default): measurement 1's
        target changes slowest, measurement ``m``'s fastest. ``"colexicographic"``:
        measurement 1's target changes fastest, measurement ``m``'s slowest; for
        the validation matrix of Fig. 1 this puts the paper's case 1 (nothing
        detected) first and its case 5 (events ``chi_11, chi_22, chi_30``) fifth, as
        in Fig. 2.

    Yields
    ------
    numpy.ndarray of int8, shape (m, T + 1)
        Each feasibility matrix: one 1 per row, at most one 1 in each column
        ``t >= 1``.

    Raises
    ------
    ValueError
        If ``validation`` is not a 2-D 0/1 array with an all-ones column 0, or
        ``order`` is not one of the two names.
    """
    if order not in ("lexicographic", "colexicographic"):
        raise ValueError(f"order must be 'lexicographic' or 'colexicographic', got {order!r}")
    v = np.asarray(validation)
    if v.ndim != 2 or v.shape[1] < 1:
        raise ValueError(f"validation must be a 2-D (m, T + 1) array, got shape {v.shape}")
    if not np.all(np.isin(v, (0, 1))):
        raise ValueError("validation must contain only 0 and 1")
    if v.shape[0] and not np.all(v[:, 0] == 1):
        raise ValueError("column 0 of validation (the clutter column) must be all ones")
    m, n_cols = v.shape
    choices = [np.flatnonzero(v[j]).tolist() for j in range(m)]
    assign = [0] * m
    # rows from the slowest-changing to the fastest-changing digit of the odometer
    rows = list(range(m)) if order == "lexicographic" else list(range(m - 1, -1, -1))

    def rec(depth: int, used: set[int]) -> Iterator[np.ndarray]:
        if depth == m:
            out = np.zeros((m, n_cols), dtype=np.int8)
            out[np.arange(m), assign] = 1
            yield out
            return
        j = rows[depth]
        for t in choices[j]:
            if t and t in used:
                continue
            assign[j] = t
            yield from rec(depth + 1, used | {t} if t else used)

    yield from rec(0, set())


# --------------------------------------------------------------------------------------
# Validation (Sec. II.A) and the modified validation matrix (Sec. III.A)
# --------------------------------------------------------------------------------------


def _as_float_array(x: object, name: str, ndim: int) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array") from exc
    if a.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must contain only finite values")
    return a


def _check_prob(p: object, name: str, n: int, low_open: bool = True) -> np.ndarray:
    a = np.broadcast_to(np.asarray(p, dtype=float), (n,)) if np.ndim(p) == 0 else np.asarray(p, dtype=float)
    if a.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {a.shape}")
    if not np.all(np.isfinite(a)) or np.any(a > 1) or np.any(a <= 0 if low_open else a < 0):
        lo = "(0, 1]" if low_open else "[0, 1]"
        raise ValueError(f"{name} must lie in {lo}, got {a}")
    return a.astype(float)


def gate_threshold(gate_prob: float, dim: int) -> float:
    """Chi-square gate threshold ``d`` with ``P(chi2_dim <= d) = gate_prob`` (Sec. II.A).

    A measurement ``z`` is validated for a target when its squared Mahalanobis
    distance ``(z - z_hat)^T S^{-1} (z - z_hat)`` to the predicted measurement
    ``z_hat`` (innovation covariance ``S``) does not exceed ``d``.
    """
    g = float(gate_prob)
    if not 0 < g < 1:
        raise ValueError(f"gate_prob must lie in (0, 1), got {gate_prob}")
    dim = _check_count(dim, "dim")
    if dim < 1:
        raise ValueError("dim must be >= 1")
    return _chi2_ppf(g, dim)


@lru_cache(maxsize=64)
def _chi2_ppf(g: float, dim: int) -> float:
    from scipy.stats import chi2

    return float(chi2.ppf(g, dim))


def mahalanobis_sq(measurements: object, z_pred: object, S: object) -> np.ndarray:
    """Squared Mahalanobis distances of every measurement to every predicted measurement.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
    z_pred : array_like, shape (T, d)
        Predicted measurements ``z_hat_t(k|k-1)``.
    S : array_like, shape (T, d, d)
        Innovation covariances ``S_t(k)`` (symmetric positive definite).

    Returns
    -------
    numpy.ndarray, shape (m, T)
    """
    z = _as_float_array(measurements, "measurements", 2)
    zp = _as_float_array(z_pred, "z_pred", 2)
    S_ = _as_float_array(S, "S", 3)
    T, d = zp.shape
    if z.shape[1] != d and z.shape[0] > 0:
        raise ValueError(f"measurements must have {d} columns like z_pred, got {z.shape[1]}")
    if S_.shape != (T, d, d):
        raise ValueError(f"S must have shape ({T}, {d}, {d}), got {S_.shape}")
    if not np.allclose(S_, np.swapaxes(S_, 1, 2)):
        raise ValueError("S must be symmetric")
    try:
        L = np.linalg.cholesky(S_)
    except np.linalg.LinAlgError as exc:
        raise ValueError("S must be positive definite") from exc
    z = z.reshape(-1, d)
    nu = z[:, None, :] - zp[None, :, :]  # (m, T, d)
    y = np.linalg.solve(L[None], nu[..., None])[..., 0] if len(z) else nu
    return np.sum(y * y, axis=-1)


def _gauss_density(d2: np.ndarray, S: np.ndarray) -> np.ndarray:
    d = S.shape[-1]
    _, logdet = np.linalg.slogdet(S)
    return np.exp(-0.5 * d2 - 0.5 * (d * np.log(2 * np.pi) + logdet)[None, :])


def validation_matrix(measurements: object, z_pred: object, S: object,
                      gate_prob: float = 0.99) -> np.ndarray:
    """Binary validation matrix of Sec. II.A, shape ``(m, T + 1)``.

    Column 0 (the false-measurement "target" ``t = 0``) is all ones; entry ``(j, t)``
    is 1 when measurement ``j`` lies inside the chi-square gate of target ``t``
    (threshold :func:`gate_threshold`). Fig. 1 of the paper has rows 110, 111, 101.
    """
    d2 = mahalanobis_sq(measurements, z_pred, S)
    dim = np.asarray(z_pred).shape[1]
    inside = d2 <= gate_threshold(gate_prob, dim)
    return np.hstack([np.ones((d2.shape[0], 1), dtype=np.int8), inside.astype(np.int8)])


def modified_validation_matrix(measurements: object, z_pred: object, S: object,
                               p_detect: object, gate_prob: float = 0.99,
                               clutter_density: float = 1.0) -> np.ndarray:
    """Modified validation matrix (MVM), eqs. (3)-(4), shape ``(m + 1, T)``.

    Row 0 holds ``1 - P_D,t`` (eq. 3); row ``j`` holds ``f_t(z_j) P_D,t / lambda``
    (eq. 4 divided by the clutter density ``lambda``; the paper's form is
    ``lambda = 1``) where measurement ``j`` passes target ``t``'s gate, else 0.
    ``f_t`` is the normal density ``N(z_j; z_hat_t, S_t)``.

    Parameters
    ----------
    measurements : array_like, shape (m, d)
    z_pred : array_like, shape (T, d)
    S : array_like, shape (T, d, d)
    p_detect : float or array_like of shape (T,)
        Detection probabilities ``P_D,t`` in (0, 1].
    gate_prob : float
        Gate probability ``P_G`` in (0, 1) that sets the chi-square threshold.
    clutter_density : float
        Spatial density ``lambda > 0`` of false measurements.
    """
    d2 = mahalanobis_sq(measurements, z_pred, S)
    S_ = np.asarray(S, dtype=float)
    T = d2.shape[1]
    pd = _check_prob(p_detect, "p_detect", T)
    lam = float(clutter_density)
    if not np.isfinite(lam) or lam <= 0:
        raise ValueError(f"clutter_density must be a positive finite number, got {clutter_density}")
    inside = d2 <= gate_threshold(gate_prob, S_.shape[-1])
    dens = np.where(inside, _gauss_density(d2, S_), 0.0) if d2.size else d2
    return np.vstack([1.0 - pd[None, :], dens * pd[None, :] / lam])


def mvm_to_validation(mvm: object) -> np.ndarray:
    """Binary validation matrix ``(m, T + 1)`` of an MVM (Sec. III.A: zeros coincide)."""
    w = _check_mvm(mvm)
    return np.hstack([np.ones((w.shape[0] - 1, 1), dtype=np.int8), (w[1:] > 0).astype(np.int8)])


def _check_mvm(mvm: object) -> np.ndarray:
    try:
        w = np.asarray(mvm, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError("mvm must be a numeric (m + 1, T) array") from exc
    if w.ndim != 2:
        raise ValueError(f"mvm must be a 2-D (m + 1, T) array, got shape {w.shape}")
    if w.shape[0] < 1:
        raise ValueError("mvm must have a row 0 (holding 1 - P_D,t); got 0 rows")
    if not np.all(np.isfinite(w)):
        raise ValueError("mvm must contain only finite values")
    if np.any(w < 0):
        raise ValueError("mvm entries must be >= 0 (they are probabilities and densities)")
    if np.any(w[0] >= 1):
        raise ValueError(
            "row 0 of mvm must hold 1 - P_D,t in [0, 1) (P_D,t in (0, 1]); "
            "was row 0 omitted?")
    return w


# --------------------------------------------------------------------------------------
# Operation counting (Tables IV-V)
# --------------------------------------------------------------------------------------


@dataclass
class OpCount:
    """Additions and multiplications counted by an instrumented beta computation.

    Counting convention (the one that reproduces Tables IV-V of the paper exactly):
    a sum of ``n`` terms costs ``n - 1`` additions, a product of ``n`` factors
    ``n - 1`` multiplications; the final normalization (divisions) and eq. (2)
    are not counted.
    """

    additions: int = 0
    multiplications: int = 0
    detail: dict = field(default_factory=dict)

    def add(self, n_add: int = 0, n_mul: int = 0) -> None:
        self.additions += int(n_add)
        self.multiplications += int(n_mul)

    def __str__(self) -> str:
        return f"{self.additions}/{self.multiplications}"


# --------------------------------------------------------------------------------------
# The conventional method (Secs. II.B-C)
# --------------------------------------------------------------------------------------


def _assignments(w: np.ndarray) -> np.ndarray:
    """All feasible events as an (n_events, T) array of measurement rows (0 = undetected)."""
    m1, T = w.shape
    events = np.zeros((1, 0), dtype=np.int64)
    for t in range(T):
        rows = np.flatnonzero(w[:, t] > 0)
        if rows.size == 0:
            return np.zeros((0, T), dtype=np.int64)
        new = []
        for r in rows:
            if r == 0:
                keep = events
            else:
                keep = events[~np.any(events == r, axis=1)]
            if len(keep):
                new.append(np.hstack([keep, np.full((len(keep), 1), r, dtype=np.int64)]))
        events = np.vstack(new) if new else np.zeros((0, t + 1), dtype=np.int64)
    return events


def _normalize_columns(w: np.ndarray) -> np.ndarray:
    """Scale every target column to maximum 1 (beta is invariant: each event uses one entry per column)."""
    mx = w.max(axis=0) if w.size else np.ones(w.shape[1])
    return w / np.where(mx > 0, mx, 1.0)


def _fail_no_event(w: np.ndarray) -> None:
    dead = np.flatnonzero(w.max(axis=0, initial=0.0) <= 0)
    if dead.size:
        raise ValueError(
            f"target column(s) {dead.tolist()} of mvm have P_D = 1 (row 0 is 0) and no "
            "validated measurement: no feasible event has positive probability")
    raise ValueError("no feasible joint event of mvm has positive probability "
                     "(targets with P_D = 1 compete for too few measurements)")


def beta_enumerated(mvm: object, *, ops: OpCount | None = None) -> np.ndarray:
    """Association probabilities by enumerating every feasible event (Secs. II.B-C).

    The conventional method: every feasibility matrix of the validation matrix
    (``mvm > 0``) is generated, its probability is the product of the individual
    event probabilities (one MVM entry per target), and ``beta[j, t]`` sums the
    probabilities of the events containing ``chi_{j,t}``, normalized by the sum over
    all events. Row 0 is eq. (2), ``beta_0t = 1 - sum_j beta_jt``, computed directly
    as the probability of the events in which target ``t`` is not detected.
    Cost: the number of feasible events, up to eq. (1) (Table I) times ``T``.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix, eqs. (3)-(4).
    ops : OpCount, optional
        If given, counts the operations of the method as in Table IV: ``T - 1``
        multiplications per feasible event and ``n - 1`` additions for each
        ``beta_jt`` (``j >= 1``) that sums ``n`` event probabilities.

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)
    """
    w = _check_mvm(mvm)
    m1, T = w.shape
    if T == 0:
        return np.zeros((m1, 0))
    wn = _normalize_columns(w)
    ev = _assignments(wn)
    if len(ev) == 0:
        _fail_no_event(w)
    p = np.prod(wn[ev, np.arange(T)[None, :]], axis=1)
    Z = p.sum()
    if not Z > 0:
        _fail_no_event(w)
    out = np.zeros((m1, T))
    for t in range(T):
        np.add.at(out[:, t], ev[:, t], p)
    if ops is not None:
        counts = np.zeros((m1, T), dtype=np.int64)
        for t in range(T):
            np.add.at(counts[:, t], ev[:, t], 1)
        c = counts[1:]
        ops.add(n_add=int(np.sum(np.maximum(c - 1, 0))), n_mul=len(ev) * (T - 1))
        ops.detail["events"] = len(ev)
    return out / Z


def feasibility_matrices(mvm: object, order: str = "lexicographic") -> list[np.ndarray]:
    """The feasibility matrices ``Omega_i`` of an MVM's validation matrix (Fig. 2).

    ``order`` is passed to :func:`iter_feasibility_matrices`.
    """
    return list(iter_feasibility_matrices(mvm_to_validation(mvm), order=order))


# --------------------------------------------------------------------------------------
# The fast algorithm of the paper (Secs. III.B-D): MU words, in-situ vectors, eq. (6)
# --------------------------------------------------------------------------------------


def _popcount(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.int64)
    return np.bitwise_count(x).astype(np.int64)


def mu_words(m: int, min_count: int = 0) -> np.ndarray:
    """Measurements-used (MU) bit words of Table II, in the paper's order.

    Bit ``j - 1`` of a word is set when measurement ``j`` is used (written
    ``j_m ... j_1`` as in Table II). Words are grouped by decreasing bit count and,
    within a group, ordered as in Table II (the set not using the highest
    measurements first), and only bit counts ``>= min_count`` are kept.
    """
    m = _check_count(m, "m")
    min_count = _check_count(min_count, "min_count")
    if m > 30:
        raise ValueError(f"m must be <= 30 for MU words, got {m}")
    return _mu_words_cached(m, min_count).copy()


@lru_cache(maxsize=256)
def _mu_words_cached(m: int, min_count: int) -> np.ndarray:
    w = np.arange(2**m, dtype=np.int64)
    pc = _popcount(w)
    # Table II order: decreasing bit count, then increasing word (0111, 1011, 1101, 1110)
    order = np.lexsort((w, -pc))
    out = w[order][pc[order] >= min_count]
    out.flags.writeable = False
    return out


def _check_vector_args(m: object, T: object) -> tuple[int, int]:
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    if T < 1:
        raise ValueError(f"T must be >= 1 (the vectors belong to targets), got {T}")
    if m > 30:
        raise ValueError(f"m must be <= 30 for MU words, got {m}")
    return m, T


def vector_size(m: int, T: int) -> int:
    """Length of the target vectors of the fast algorithm (Table III).

    ``sum_{j = max(0, m - T + 1)}^{m} C(m, j)``: the words whose bit count is at
    least ``m - T + 1`` (the other ``T - 1`` targets can use at most ``T - 1``
    measurements, and eq. (6) needs the words of bit counts ``m`` and ``m - 1``).
    The lower limit ``max(0, .)`` reproduces Table III; the text prints
    ``max(1, .)`` (see :func:`vector_size_text_formula`), which drops the empty word
    and disagrees with the table whenever ``m < T``.
    """
    m, T = _check_vector_args(m, T)
    return sum(comb(m, j) for j in range(max(0, m - T + 1), m + 1))


def vector_size_text_formula(m: int, T: int) -> int:
    """The vector length as printed in Sec. III: ``sum_{j=max(1, m-T+1)}^m C(m, j)``."""
    m, T = _check_vector_args(m, T)
    return sum(comb(m, j) for j in range(max(1, m - T + 1), m + 1))


def stage_update(vec: np.ndarray, words: np.ndarray, prev_words: np.ndarray,
                 column: np.ndarray, ops: OpCount | None = None) -> np.ndarray:
    """One in-situ stage of Sec. III.C: the vector ``T - 1`` from the vector ``T``.

    ``new[w] = p_0 * old[w] + sum_{j in w} p_j * old[w XOR bit_j]`` for every MU word
    ``w`` of ``words``: the XOR of ``w`` with a word of one fewer bit that leaves a
    single 1 selects the old element and the MVM entry ``p_j`` that multiplies it
    (a vector inner product per element, Fig. 4). ``vec`` is indexed like
    ``prev_words``; ``column`` is the MVM column ``(p_0, p_1, ..., p_m)``.

    Raises
    ------
    ValueError
        If ``vec`` and ``prev_words`` differ in length, ``column`` is empty, a word is
        not an ``m``-bit word (``0 <= w < 2^m``), ``prev_words`` repeats a word, or a
        predecessor word (``w`` itself or ``w XOR bit_j`` for a set bit ``j``) of some
        word of ``words`` is missing from ``prev_words``.
    """
    column = _as_float_array(column, "column", 1)
    if len(column) < 1:
        raise ValueError("column must hold (p_0, p_1, ..., p_m): at least p_0")
    m = len(column) - 1
    if m > 30:
        raise ValueError(f"column has m = {m} measurement entries; at most 30 are supported")
    words = _check_words(words, "words", m)
    prev_words = _check_words(prev_words, "prev_words", m)
    if len(np.unique(prev_words)) != len(prev_words):
        raise ValueError("prev_words must not repeat a word")
    vec = _as_float_array(vec, "vec", 1)
    if len(vec) != len(prev_words):
        raise ValueError(f"vec must have one element per word of prev_words "
                         f"({len(prev_words)}), got {len(vec)}")
    have = np.zeros(2**m, dtype=bool)
    have[prev_words] = True
    need = [words] + [words[(words >> j) & 1 == 1] ^ (1 << j) for j in range(m)]
    missing = np.unique(np.concatenate(need)[~have[np.concatenate(need)]])
    if missing.size:
        shown = ", ".join(f"{x:0{m}b}" if m else "(empty)" for x in missing[:5].tolist())
        raise ValueError(f"prev_words lacks {missing.size} predecessor word(s) the new "
                         f"words need (e.g. {shown})")
    return _stage_update(vec, words, prev_words, column, ops)


def _check_words(words: object, name: str, m: int) -> np.ndarray:
    a = np.asarray(words)
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of MU words, got shape {a.shape}")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise TypeError(f"{name} must hold integer MU words, got dtype {a.dtype}")
    a = a.astype(np.int64)
    if a.size and (a.min() < 0 or a.max() >= 2**m):
        raise ValueError(f"{name} must hold {m}-bit words in [0, {2**m}) "
                         f"(m = len(column) - 1), got values in [{a.min()}, {a.max()}]")
    return a


def _stage_update(vec: np.ndarray, words: np.ndarray, prev_words: np.ndarray,
                  column: np.ndarray, ops: OpCount | None = None) -> np.ndarray:
    """:func:`stage_update` without input checks (the inner loop of :func:`beta_paper`)."""
    m = len(column) - 1
    pos = np.full(2**m, -1, dtype=np.int64)
    pos[prev_words] = np.arange(len(prev_words))
    new = column[0] * vec[pos[words]]
    n_terms = len(words)
    for j in range(m):
        bit = 1 << j
        sel = (words & bit) != 0
        idx = pos[words[sel] ^ bit]
        new[sel] += column[j + 1] * vec[idx]
        n_terms += int(sel.sum())
    if ops is not None:
        ops.add(n_add=n_terms - len(words), n_mul=n_terms)
    return new


def stage_expressions(m: int, T: int, new: str = "e", old: str = "f") -> list[tuple[int, str, str]]:
    """Table II regenerated: for each MU word of the vector ``e``, the VIP expression.

    Returns ``(word, binary, expression)`` rows in the paper's order, e.g. for
    ``m = 4`` the word ``1111`` gives ``e0(f1111) + e4(f0111) + e3(f1011) + ...``:
    the old-vector elements are named by their own MU words, as the XOR rule of
    Sec. III.C selects them.
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    rows = []
    for w in mu_words(m, max(0, m - T + 1)).tolist():
        terms = [f"{new}0({old}{w:0{m}b})"]
        for j in range(m, 0, -1):
            if (w >> (j - 1)) & 1:
                terms.append(f"{new}{j}({old}{w ^ (1 << (j - 1)):0{m}b})")
        rows.append((w, f"{w:0{m}b}", " + ".join(terms)))
    return rows


def beta_paper(mvm: object, *, ops: OpCount | None = None,
               store_intermediates: bool = False, vip_noise: float = 0.0,
               rng: np.random.Generator | None = None) -> np.ndarray:
    """Association probabilities by the paper's fast algorithm (Secs. III.B-D, Fig. 4).

    For target ``t``, columns 1 and ``t`` of the MVM are interchanged; the vector of
    the last target (``T``, Sec. III.B: ``f[w] = f_0 + sum_{j in w} f_j`` over MU
    words ``w`` of bit count ``>= m - T + 1``) is formed, then targets ``T - 1`` down
    to 2 are folded in by :func:`stage_update` (Sec. III.C; only the bit counts still
    needed are kept, so the vector shrinks towards bit counts ``m`` and ``m - 1``),
    and eq. (6) ``beta_{.,t} = A b'`` with ``A = diag(a_0, ..., a_m)`` and
    ``b' = (b_{1..m}, b_{without m}, ..., b_{without 1})`` gives the unnormalized
    column. Columns are then normalized (Sec. III.D).

    Complexity: ``O(T^2 m 2^m)`` without stored intermediates (``T`` chains of
    ``T - 2`` stages over at most ``2^m`` words, ``|w| + 1`` products each).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
    ops : OpCount, optional
        Counts additions and multiplications as executed (Table V when
        ``store_intermediates`` is False).
    store_intermediates : bool
        Keep the vectors of target 1's chain and reuse their common suffix in the
        chains of the other targets: one storage scheme of this package for the
        remark after Table VI ("when intermediate vectors are stored"), which does
        not say how the paper stored them.
    vip_noise : float
        Models the analog processor of Sec. IV: every vector produced by a stage of
        inner products gets additive Gaussian noise of standard deviation
        ``vip_noise`` times the vector's largest element (detector noise relative
        to full scale), clipped at 0 (intensities). 0 (default) is exact arithmetic.
    rng : numpy.random.Generator, optional
        Required when ``vip_noise > 0``.
    """
    w = _check_mvm(mvm)
    m1, T = w.shape
    m = m1 - 1
    vip_noise = float(vip_noise)
    if not np.isfinite(vip_noise) or vip_noise < 0:
        raise ValueError(f"vip_noise must be a finite number >= 0, got {vip_noise}")
    if vip_noise > 0 and not isinstance(rng, np.random.Generator):
        raise TypeError("rng must be a numpy.random.Generator when vip_noise > 0")
    if m > 22:
        raise ValueError(f"beta_paper needs 2^m words; m = {m} is too large (use beta)")
    if T == 0:
        return np.zeros((m1, 0))
    wn = _normalize_columns(w)
    full = (1 << m) - 1
    out = np.zeros((m1, T))
    cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for t in range(T):
        cols = list(range(T))
        cols[0], cols[t] = cols[t], cols[0]
        if T == 1:
            vec_words = np.array([full, *[full ^ (1 << j) for j in range(m)]], dtype=np.int64)
            vec = np.ones(len(vec_words))
        else:
            p = T - 1
            if store_intermediates and t > 0 and p > t:
                # the suffix of the chain (positions > t) is the same as target 1's
                while p > t + 1 and p - 1 in cache:
                    p -= 1
                vec_words, vec = cache[p]
            else:
                vec_words = _mu_words_cached(m, max(0, m - p))
                col = wn[:, cols[p]]
                vec = np.full(len(vec_words), col[0])
                for j in range(m):
                    vec += col[j + 1] * ((vec_words >> j) & 1)
                if ops is not None:
                    ops.add(n_add=int(_popcount(vec_words).sum()))
                if store_intermediates and t == 0:
                    cache[p] = (vec_words, vec)
            for q in range(p - 1, 0, -1):
                new_words = _mu_words_cached(m, max(0, m - q))
                vec = _stage_update(vec, new_words, vec_words, wn[:, cols[q]], ops)
                if vip_noise > 0:
                    vec = vec + rng.normal(0.0, vip_noise * np.abs(vec).max(), len(vec))
                    np.maximum(vec, 0.0, out=vec)  # detected intensities are >= 0
                vec_words = new_words
                if store_intermediates and t == 0:
                    cache[q] = (vec_words, vec)
        pos = {int(x): i for i, x in enumerate(vec_words.tolist())}
        b_prime = np.array([vec[pos[full]]] + [vec[pos[full ^ (1 << j)]] for j in range(m)])
        out[:, t] = wn[:, cols[0]] * b_prime  # eq. (6)
        if ops is not None:
            ops.add(n_mul=m1)
    Z = out.sum(axis=0)
    if not np.all(Z > 0):
        _fail_no_event(w)
    return out / Z


def conventional_op_count(m: int, T: int) -> OpCount:
    """Operation count of the conventional method for an all-ones validation matrix (Table IV).

    Closed form of what :func:`beta_enumerated` counts on an all-ones MVM:

    * multiplications: ``N (T - 1)``, where ``N`` is the number of feasible events
      of eq. (1) (:func:`count_feasible_events`) and each event's probability is
      the product of ``T`` MVM entries, one per target;
    * additions: ``sum_{j >= 1, t} (n_jt - 1)``, where ``n_jt`` is the number of
      events that contain the pairing ``chi_jt`` (``beta_jt`` sums their ``n_jt``
      probabilities). Summed over ``j`` and ``t``, ``n_jt`` counts every detection
      of every event, ``D = sum_{k >= 1} k C(m, k) C(T, k) k!`` (``k`` detections:
      choose ``k`` measurements, ``k`` targets and a matching), so the additions are
      ``D - m T``. For an all-ones matrix every ``n_jt`` equals the eq. (1) count of
      the remaining ``m - 1`` measurements and ``T - 1`` targets, i.e. the
      additions are ``m T (N(m - 1, T - 1) - 1)``.

    Neither the final normalization nor eq. (2) is counted (see :class:`OpCount`).

    Parameters
    ----------
    m, T : int
        Numbers of measurements and targets, ``>= 0``.

    Returns
    -------
    OpCount

    Examples
    --------
    >>> str(conventional_op_count(7, 7))  # Table IV, m = T = 7
    '652974/785532'
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    N = count_feasible_events(m, T)
    det = sum(comb(m, k) * comb(T, k) * factorial(k) * k for k in range(1, min(m, T) + 1))
    return OpCount(additions=det - m * T if m * T else 0, multiplications=N * max(T - 1, 0))


def fast_op_count(m: int, T: int, store_intermediates: bool = False) -> OpCount:
    """Operation count of :func:`beta_paper` (Table V) by running it on an all-ones MVM.

    Parameters
    ----------
    m, T : int
        Numbers of measurements (``0..22``) and targets (``>= 0``).
    store_intermediates : bool
        Count the variant that reuses target 1's chain (see :func:`beta_paper`).
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    if m > 22:
        raise ValueError(f"m must be <= 22 (beta_paper needs 2^m words), got {m}")
    if not isinstance(store_intermediates, (bool, np.bool_)):
        raise TypeError(f"store_intermediates must be a bool, got {type(store_intermediates).__name__}")
    ops = OpCount()
    mvm = np.vstack([np.full((1, T), 0.5), np.ones((m, T))])
    beta_paper(mvm, ops=ops, store_intermediates=store_intermediates)
    return ops


# --------------------------------------------------------------------------------------
# Beyond the paper: exact forward-backward over subsets of min(m, T), clusters
# --------------------------------------------------------------------------------------


_THREAD_MIN_BITS = 14  # overlap gradients and backward messages from 2^14 states on
_SPARSE_MAX_HIGH_BITS = 16  # up to 2^16 rows the high bits use one sparse product
_LOW_BITS = 5  # the lowest bits of a subset index are handled by a small dense matrix (BLAS)
_FAST_MIN_SLOTS = 8  # from 2^8 states on, the compiled sweep of projtrack._fast_jpda (if numba)


def _low_matrix(u: float, w: np.ndarray, n_low: int) -> np.ndarray:
    """Matrix ``M`` of one item restricted to the low bits: ``(x @ M)[S] = u x[S] + sum w_k x[S - k]``."""
    B = 1 << n_low
    M = np.eye(B) * u
    s = np.arange(B)
    for k in range(n_low):
        if w[k]:
            lacks = s[(s >> k) & 1 == 0]
            M[lacks, lacks | (1 << k)] = w[k]
    return M


def _fb_sweep_reference(W: np.ndarray, u: np.ndarray, v: np.ndarray,
                        ops: OpCount | None = None) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Reference implementation of :func:`_fb_sweep`: the recursions written out plainly.

    Items ``i = 0..n_it-1`` (rows of ``W``) are either unmatched (weight ``u[i]``) or
    matched to a distinct slot ``k`` (weight ``W[i, k]``); a slot left unmatched
    weighs ``v[k]``. ``Z`` is the sum, over all such partial matchings, of the
    product of their weights (for JPDA: the sum of the probabilities of all
    feasible events). States ``S`` are subsets of the ``n`` slots, coded as bit
    words (the paper's MU words when the slots are measurements).

    * Forward: ``F_0 = [S == {}]`` and
      ``F_{i+1}[S] = u_i F_i[S] + sum_{k in S} W[i, k] F_i[S - {k}]``
      (items ``< i + 1`` use exactly the slots ``S``).
    * ``V[S] = prod_{k not in S} v_k`` and ``Z = sum_S F_{n_it}[S] V[S]``.
    * Backward: ``G_{n_it} = V`` and
      ``G_i[S] = u_i G_{i+1}[S] + sum_{k not in S} W[i, k] G_{i+1}[S + {k}]``
      (completions of items ``>= i`` given the slots ``S`` already used: the
      paper's target vectors of Sec. III.C are these messages).
    * Gradients: ``u_i dZ/du_i = u_i sum_S F_i[S] G_{i+1}[S]`` and
      ``W[i, k] dZ/dW[i, k] = W[i, k] sum_{S not containing k} F_i[S] G_{i+1}[S + {k}]``,
      the total weight of the matchings in which item ``i`` is unmatched, or
      matched to slot ``k``; ``unmatched[k] = sum_{S not containing k} F_{n_it}[S] V[S]``
      is the weight of those in which slot ``k`` stays unmatched.

    Returns ``(Z, W * dZ/dW, u * dZ/du, unmatched)``. Cost ``O(n_it n 2^n)``; the
    operation count (``ops``) is the one :func:`_fb_sweep` records for the same
    recursions. :func:`_fb_sweep` computes the same numbers with blocked and sparse
    products and is tested against this function on every one of its code paths.
    """
    n_it, n = W.shape
    N = 1 << n
    S = np.arange(N)
    has = [((S >> k) & 1) == 1 for k in range(n)]  # has[k][S]: slot k is in S
    F = np.zeros((n_it + 1, N))
    F[0, 0] = 1.0
    n_mul = n_add = 0
    for i in range(n_it):
        F[i + 1] = u[i] * F[i]
        n_mul += N
        for k in range(n):
            if W[i, k]:
                with_k = S[has[k]]
                F[i + 1, with_k] += W[i, k] * F[i, with_k ^ (1 << k)]
                n_mul += N >> 1
                n_add += N >> 1
    V = np.ones(N)
    for k in range(n):
        V[~has[k]] *= v[k]
    FV = F[n_it] * V
    Z = float(FV.sum())
    unmatched = np.array([FV[~has[k]].sum() for k in range(n)])
    gW = np.zeros_like(W, dtype=float)
    gu = np.zeros(n_it)
    G = V
    for i in range(n_it - 1, -1, -1):
        gu[i] = u[i] * float(F[i] @ G)
        Gn = u[i] * G
        n_mul += 2 * N
        n_add += N
        for k in range(n):
            if W[i, k]:
                without_k = S[~has[k]]
                gW[i, k] = W[i, k] * float(F[i, without_k] @ G[without_k | (1 << k)])
                Gn[without_k] += W[i, k] * G[without_k | (1 << k)]
                n_mul += 2 * (N >> 1)
                n_add += 2 * (N >> 1)
        G = Gn
    if ops is not None:
        ops.add(n_add=n_add, n_mul=n_mul)
    return Z, gW, gu, unmatched


def _fb_core(W: np.ndarray, u: np.ndarray, v: np.ndarray,
             ops: OpCount | None = None,
             reference: bool = False) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_fb_sweep` with BLAS limited to one thread for large state spaces.

    The small dense products of the sweep gain nothing from BLAS threads, and idle
    BLAS threads spin-wait, which costs several times the work on a busy machine.
    With ``reference=True`` the plain :func:`_fb_sweep_reference` runs instead; from
    ``_FAST_MIN_SLOTS`` slots on, the compiled sweep of :mod:`projtrack._fast_jpda` runs
    when numba is available (``PROJTRACK_NO_NUMBA=1`` keeps this numpy sweep).
    """
    if reference:
        return _fb_sweep_reference(W, u, v, ops)
    if W.shape[1] >= _FAST_MIN_SLOTS and _fast_jpda.numba_enabled():
        return _fast_jpda.fb_sweep(W, u, v, ops)  # compiled, same recursions (numba)
    if W.shape[1] < 12:
        return _fb_sweep(W, u, v, ops)
    from threadpoolctl import threadpool_limits  # a dependency of scikit-learn

    with threadpool_limits(limits=1, user_api="blas"):
        return _fb_sweep(W, u, v, ops)


def _fb_sweep(W: np.ndarray, u: np.ndarray, v: np.ndarray,
              ops: OpCount | None = None) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Sum over partial matchings and its gradient (the engine of :func:`beta_forward_backward`).

    The same recursions, inputs and outputs as :func:`_fb_sweep_reference` (read that
    one first: it states them plainly); this is its fast form, tested against it on
    every code path (dense low bits only, sparse high bits, strided high bits, the
    threaded backward sweep) in ``tests/test_jpda_beta.py``.

    Items ``i`` (rows of ``W``, processed one by one) are either unmatched (weight
    ``u_i``) or matched to a distinct slot ``k`` (weight ``W[i, k]``); unmatched slots
    weigh ``v_k``. Returns ``Z``, ``W * dZ/dW``, ``u * dZ/du`` and the vector
    ``P(slot k unmatched) * Z``. States are subsets of slots (``2^n`` of them).
    Forward ``F_i[S]`` (slots used exactly ``S`` by items ``< i``) and backward
    ``G_{i+1}[S]`` (sum over the completions of items ``> i`` avoiding ``S``, the
    paper's target vectors) give the gradient as inner products
    ``dZ/dW[i, k] = sum_{S not containing k} F_i[S] G_{i+1}[S + k]``.
    The lowest ``_LOW_BITS`` bits of every item are applied as one small dense
    matrix product (BLAS) on a ``(2^n / 32, 32)`` view, the others as one sparse
    product on its rows (or as strided vector updates when there are too many rows).
    """
    n_it, n = W.shape
    N = 1 << n
    nl = min(_LOW_BITS, n)
    B = 1 << nl
    rows = N // B
    F = np.empty((n_it + 1, N))
    buf = np.empty(N >> 1)
    F[0] = 0.0
    F[0, 0] = 1.0
    n_mul = n_add = 0
    high = [np.flatnonzero(W[i, nl:]) + nl for i in range(n_it)]
    Ms = [_low_matrix(u[i], W[i], nl) for i in range(n_it)]
    raise_high = lower_high = None
    if 0 < n - nl <= _SPARSE_MAX_HIGH_BITS:
        # the high bits as one sparse "raising" matrix on the rows of the (rows, B)
        # layout: row h | bit gets row h (h without the bit) times W[i, bit]
        from scipy.sparse import csr_matrix

        h = np.arange(rows)
        src = np.concatenate([h[(h >> b) & 1 == 0] for b in range(n - nl)])
        bit = np.concatenate([np.full(rows >> 1, b) for b in range(n - nl)])
        pat = csr_matrix((bit + 1.0, (src | (1 << bit), src)), shape=(rows, rows))
        bit_of_nnz = pat.data.astype(np.int64) - 1
        raise_high = pat
        lower_high = csr_matrix((bit + 1.0, (src, src | (1 << bit))), shape=(rows, rows))
        bit_of_nnz_T = lower_high.data.astype(np.int64) - 1
    for i in range(n_it):
        Fi = F[i]
        new = F[i + 1]
        np.matmul(Fi.reshape(rows, B), Ms[i], out=new.reshape(rows, B))
        if raise_high is not None and len(high[i]):
            raise_high.data = W[i, nl + bit_of_nnz]
            new.reshape(rows, B)[...] += raise_high @ Fi.reshape(rows, B)
        else:
            for k in high[i]:
                shp = (N >> (k + 1), 2, 1 << k)
                tmp = buf.reshape(N >> (k + 1), 1 << k)
                np.multiply(Fi.reshape(shp)[:, 0, :], W[i, k], out=tmp)
                dst = new.reshape(shp)[:, 1, :]
                np.add(dst, tmp, out=dst)
        nz = int(np.count_nonzero(W[i]))
        n_mul += N + nz * (N >> 1)
        n_add += nz * (N >> 1)
    # V[S] = prod_{k not in S} v_k
    V = np.ones(N)
    for k in range(n):
        V.reshape(N >> (k + 1), 2, 1 << k)[:, 0, :] *= v[k]
    FV = F[n_it] * V
    Z = float(FV.sum())
    un = np.empty(n)
    for k in range(n):
        un[k] = FV.reshape(N >> (k + 1), 2, 1 << k)[:, 0, :].sum()
    gW = np.zeros_like(W)
    gu = np.zeros(n_it)
    G = V
    Gn = np.empty(N)
    s = np.arange(B)
    low_pairs = [(s[(s >> k) & 1 == 0], s[(s >> k) & 1 == 0] | (1 << k)) for k in range(nl)]

    def gradients(i: int, G: np.ndarray) -> None:
        Fi = F[i]
        gu[i] = u[i] * float(Fi @ G)
        C = Fi.reshape(rows, B).T @ G.reshape(rows, B)
        for k in range(nl):
            if W[i, k]:
                gW[i, k] = W[i, k] * float(C[low_pairs[k]].sum())
        for k in high[i]:
            shp = (N >> (k + 1), 2, 1 << k)
            gW[i, k] = W[i, k] * float(np.einsum("ij,ij->", Fi.reshape(shp)[:, 0, :],
                                                 G.reshape(shp)[:, 1, :]))

    # The gradients of item i (read-only inner products) run in a second thread while
    # the backward message of item i is formed; numpy releases the GIL in both.
    pool = ThreadPoolExecutor(max_workers=1) if n >= _THREAD_MIN_BITS else None
    try:
        for i in range(n_it - 1, -1, -1):
            job = pool.submit(gradients, i, G) if pool else gradients(i, G)
            np.matmul(G.reshape(rows, B), Ms[i].T, out=Gn.reshape(rows, B))
            if lower_high is not None and len(high[i]):
                lower_high.data = W[i, nl + bit_of_nnz_T]
                Gn.reshape(rows, B)[...] += lower_high @ G.reshape(rows, B)
            else:
                for k in high[i]:
                    shp = (N >> (k + 1), 2, 1 << k)
                    tmp = buf.reshape(N >> (k + 1), 1 << k)
                    np.multiply(G.reshape(shp)[:, 1, :], W[i, k], out=tmp)
                    dst = Gn.reshape(shp)[:, 0, :]
                    np.add(dst, tmp, out=dst)
            if pool:
                job.result()
            nz = int(np.count_nonzero(W[i]))
            n_mul += 2 * N + 2 * nz * (N >> 1)
            n_add += N + 2 * nz * (N >> 1)
            G, Gn = Gn, G
    finally:
        if pool:
            pool.shutdown()
    if ops is not None:
        ops.add(n_add=n_add, n_mul=n_mul)
    return Z, gW, gu, un


def beta_forward_backward(mvm: object, *, ops: OpCount | None = None,
                          reference: bool = False) -> np.ndarray:
    """Exact beta by a forward-backward pass over subsets of ``min(m, T)`` (one cluster).

    The paper's target vectors (Sec. III.C) are the backward messages of a dynamic
    program over targets whose state is the set of measurements used; storing the
    forward messages as well gives every ``beta_jt`` as ``a_jt * dZ/da_jt / Z`` in one
    forward and one backward sweep, instead of one chain per target: the reuse of
    intermediate vectors the paper alludes to, taken to its end. When ``T < m`` the
    roles swap (measurements are processed one by one and the state is the set of
    targets used), so the cost is ``O(max(m, T) min(m, T) 2^min(m, T))`` time and
    ``O(max(m, T) 2^min(m, T))`` memory.

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix, eqs. (3)-(4).
    ops : OpCount, optional
        Counts the additions and multiplications of the sweep.
    reference : bool
        Run the plain reference sweep (``_fb_sweep_reference``, the recursions as
        written in its docstring) instead of the blocked fast one; the two agree to
        rounding. For auditing and tests.
    """
    if not isinstance(reference, (bool, np.bool_)):
        raise TypeError(f"reference must be a bool, got {type(reference).__name__}")
    w = _check_mvm(mvm)
    m1, T = w.shape
    m = m1 - 1
    if T == 0:
        return np.zeros((m1, 0))
    if min(m, T) > 26:
        raise ValueError(f"min(m, T) = {min(m, T)} is too large for exact JPDA (2^min states)")
    wn = _normalize_columns(w)
    out = np.zeros((m1, T))
    if T <= m:
        # items = measurements (unmatched weight 1), slots = targets (unmatched weight a0_t)
        Z, gW, gu, un = _fb_core(wn[1:], np.ones(m), wn[0], ops, reference)
        if not Z > 0:
            _fail_no_event(w)
        out[1:] = gW / Z
        out[0] = un / Z
    else:
        # items = targets (unmatched weight a0_t), slots = measurements (weight 1)
        Z, gW, gu, un = _fb_core(wn[1:].T.copy(), wn[0], np.ones(m), ops, reference)
        if not Z > 0:
            _fail_no_event(w)
        out[1:] = gW.T / Z
        out[0] = gu / Z
    return out


def clusters(mvm: object) -> list[tuple[np.ndarray, np.ndarray]]:
    """Independent clusters of an MVM: connected components of its validation graph.

    Returns a list of ``(measurements, targets)`` index arrays (measurements numbered
    1..m as MVM rows). Targets with no validated measurement form singleton
    clusters with no measurement; measurements validated by no target are dropped.
    Joint events factor over clusters, so beta can be computed cluster by cluster.
    """
    w = _check_mvm(mvm)
    A = w[1:] > 0
    T = A.shape[1]
    if T == 0:
        return []
    # label propagation over the target-target graph (targets sharing a measurement)
    adj = (A.T.astype(np.int64) @ A.astype(np.int64) > 0) | np.eye(T, dtype=bool)
    lab = np.arange(T)
    while True:
        new = np.where(adj, lab[None, :], T).min(axis=1)
        if np.array_equal(new, lab):
            break
        lab = new
    meas_lab = np.where(A.any(axis=1), np.where(A, lab[None, :], T).min(axis=1), -1)
    out = []
    for c in np.unique(lab):
        out.append((np.flatnonzero(meas_lab == c) + 1, np.flatnonzero(lab == c)))
    return out


def beta(mvm: object, *, method: str = "auto", ops: OpCount | None = None) -> np.ndarray:
    """Exact JPDA association probabilities ``beta_jt`` from the MVM (Secs. III.B-D).

    Parameters
    ----------
    mvm : array_like, shape (m + 1, T)
        Modified validation matrix: row 0 holds ``1 - P_D,t`` (eq. 3), row ``j`` holds
        ``f_t(z_j) P_D,t`` (eq. 4, optionally divided by the clutter density), zero
        where measurement ``j`` is not validated for target ``t``.
    method : {"auto", "forward-backward", "paper", "enumerate"}
        ``"paper"`` is the algorithm exactly as published (:func:`beta_paper`,
        ``O(T^2 m 2^m)``); ``"enumerate"`` the conventional method
        (:func:`beta_enumerated`); ``"forward-backward"`` the single-sweep exact
        method (:func:`beta_forward_backward`); ``"auto"`` (default) splits the MVM
        into independent clusters (:func:`clusters`) and runs the forward-backward
        method on each, iterating over subsets of whichever is smaller of the
        cluster's measurements and targets.
    ops : OpCount, optional
        Operation counter passed to the chosen method.

    Returns
    -------
    numpy.ndarray, shape (m + 1, T)
        ``beta[j, t]``: probability that measurement ``j`` originated from target
        ``t``; ``beta[0, t] = 1 - sum_j beta[j, t]`` (eq. 2) the probability that target
        ``t`` was not detected. Every column sums to 1.

    Notes
    -----
    Complexity of ``"auto"``: ``O(sum_c max(m_c, T_c) min(m_c, T_c) 2^min(m_c, T_c))``
    over clusters ``c``, and ``O(max(m_c, T_c) 2^min(m_c, T_c))`` memory: exponential in
    ``min(m, T)`` for a fully gated problem. Exact JPDA computes matrix permanents, which
    is #P-hard already for 0-1 matrices, so no polynomial-time exact method exists unless
    FP = #P. On the 2-core
    machine of ``benchmarks/bench_jpda.py`` a fully gated ``m = T = 16`` takes about
    0.02 s and ``m = T = 20`` 0.5 to 1.2 s (measured while the machine ran other jobs).
    """
    if method == "paper":
        return beta_paper(mvm, ops=ops)
    if method == "enumerate":
        return beta_enumerated(mvm, ops=ops)
    if method == "forward-backward":
        return beta_forward_backward(mvm, ops=ops)
    if method != "auto":
        raise ValueError(
            f"method must be 'auto', 'forward-backward', 'paper' or 'enumerate', got {method!r}")
    w = _check_mvm(mvm)
    m1, T = w.shape
    out = np.zeros((m1, T))
    for meas, targ in clusters(w):
        if meas.size == 0:
            if np.any(w[0, targ] <= 0):
                _fail_no_event(w[:, targ])
            out[0, targ] = 1.0
            continue
        sub = w[np.r_[0, meas]][:, targ]
        b = beta_forward_backward(sub, ops=ops)
        out[np.ix_(np.r_[0, meas], targ)] = b
    return out


# --------------------------------------------------------------------------------------
# Fig. 5: frequency-multiplexed vector-inner-product processor (numerical model)
# --------------------------------------------------------------------------------------


def optical_vip_schedule(m: int, T: int, q: int) -> np.ndarray:
    """Time schedule of the Fig. 5 processor for one stage (vector ``q + 1`` to ``q``).

    Every product ``p_j * t_n`` of a stage is one (time slot, laser diode, AO1 cell,
    detector) event: at each time slot the laser diodes (P1) of the old vector
    elements ``t_n`` are pulsed, AO1 (P2) holds the MVM column ``p``, and the LFM
    chirp in AO2 (P3) steers the product to the detector of the new element. Time
    slot ``s`` handles the products with AO1 cell ``s`` (``p_s``), so each detector
    receives at most one product per slot and accumulates (integrates) over slots.

    Returns an int array with columns ``(slot, diode, ao1_cell, detector)`` where
    diode/detector index the old/new word lists of :func:`mu_words` with bit counts
    ``>= m - q - 1`` / ``>= m - q``.

    Parameters
    ----------
    m : int
        Number of measurements, ``1..20``.
    T : int
        Number of targets, ``>= 3`` (with fewer targets there is no stage).
    q : int
        Stage index as in :func:`beta_paper` (0-based target columns): the vector of
        column ``q + 1`` becomes that of column ``q``, ``1 <= q <= T - 2`` (column
        ``T - 1`` is the starting vector, column 0 is eq. (6)).
    """
    m = _check_count(m, "m")
    T = _check_count(T, "T")
    q = _check_count(q, "q")
    if not 1 <= m <= 20:
        raise ValueError(f"m must lie in 1..20, got {m}")
    if T < 3:
        raise ValueError(f"T must be >= 3 for a stage of inner products to exist, got {T}")
    if not 1 <= q <= T - 2:
        raise ValueError(f"q must lie in 1..T-2 = 1..{T - 2} (stage from column q + 1 to q), got {q}")
    new_words = mu_words(m, max(0, m - q))
    old_words = mu_words(m, max(0, m - q - 1))
    pos = np.full(2**m, -1, dtype=np.int64)
    pos[old_words] = np.arange(len(old_words))
    rows = [np.column_stack([np.zeros(len(new_words), dtype=np.int64), pos[new_words],
                             np.zeros(len(new_words), dtype=np.int64), np.arange(len(new_words))])]
    for j in range(1, m + 1):
        bit = 1 << (j - 1)
        det = np.flatnonzero(new_words & bit)
        rows.append(np.column_stack([np.full(len(det), j), pos[new_words[det] ^ bit],
                                     np.full(len(det), j), det]))
    return np.vstack(rows)


def optical_vip_stage(vec: np.ndarray, column: np.ndarray, schedule: np.ndarray,
                      n_out: int, *, noise_std: float = 0.0,
                      rng: np.random.Generator | None = None) -> np.ndarray:
    """Simulate Fig. 5: space-integrated products time-integrated on the P3 detectors.

    Each schedule row multiplies the laser-diode amplitude ``vec[diode]`` (P1) by the
    AO1 transmittance ``column[cell]`` (P2), and the chirp routes the product to
    ``detector``; detectors integrate over the time slots. With ``noise_std > 0``
    each detector reading gets additive Gaussian noise (analog accuracy), drawn from
    ``rng``.
    """
    vec = _as_float_array(vec, "vec", 1)
    column = _as_float_array(column, "column", 1)
    n_out = _check_count(n_out, "n_out")
    sch = np.asarray(schedule)
    if sch.ndim != 2 or sch.shape[1] != 4:
        raise ValueError("schedule must be an (n, 4) array of (slot, diode, ao1_cell, detector) "
                         f"rows, got shape {sch.shape}")
    if sch.size and not np.issubdtype(sch.dtype, np.integer):
        raise TypeError(f"schedule must hold integers, got dtype {sch.dtype}")
    schedule = sch.astype(np.int64)
    if np.any(schedule < 0):
        raise ValueError("schedule entries must be >= 0")
    for col, name, size in ((1, "vec", len(vec)), (2, "column", len(column)), (3, "n_out", n_out)):
        if len(schedule) and schedule[:, col].max() >= size:
            what = ("diode", "AO1 cell", "detector")[col - 1]
            raise ValueError(f"schedule uses {what} {schedule[:, col].max()} but {name} has "
                             f"only {size} {'detectors' if col == 3 else 'elements'}")
    noise_std = float(noise_std)
    if not np.isfinite(noise_std) or noise_std < 0:
        raise ValueError(f"noise_std must be a finite number >= 0, got {noise_std}")
    out = np.zeros(n_out)
    for s in np.unique(schedule[:, 0]):
        r = schedule[schedule[:, 0] == s]
        # within one slot every detector receives at most one product
        out[r[:, 3]] += vec[r[:, 1]] * column[r[:, 2]]
    if noise_std > 0:
        if not isinstance(rng, np.random.Generator):
            raise ValueError("rng (a numpy.random.Generator) is required when noise_std > 0")
        out = out + rng.normal(0.0, noise_std, n_out)
    return out


# --------------------------------------------------------------------------------------
# Trackers
# --------------------------------------------------------------------------------------


class _KFBank:
    def __init__(self, x0, P0, F, Q, H, R):
        from filterpy.kalman import KalmanFilter

        x0 = _as_float_array(x0, "x0", 2)
        F_ = _as_float_array(F, "F", 2)
        H_ = _as_float_array(H, "H", 2)
        n = x0.shape[1]
        if F_.shape != (n, n):
            raise ValueError(f"F must have shape ({n}, {n}), got {F_.shape}")
        if H_.shape[1] != n:
            raise ValueError(f"H must have {n} columns, got shape {H_.shape}")
        d = H_.shape[0]
        P0_ = _as_float_array(P0, "P0", 2)
        Q_ = _as_float_array(Q, "Q", 2)
        R_ = _as_float_array(R, "R", 2)
        for name, M, k in (("P0", P0_, n), ("Q", Q_, n), ("R", R_, d)):
            if M.shape != (k, k):
                raise ValueError(f"{name} must have shape ({k}, {k}), got {M.shape}")
        self.filters = []
        for x in x0:
            kf = KalmanFilter(dim_x=n, dim_z=d)
            kf.x = x.reshape(n, 1).copy()
            kf.P = P0_.copy()
            kf.F = F_.copy()
            kf.Q = Q_.copy()
            kf.H = H_.copy()
            kf.R = R_.copy()
            self.filters.append(kf)
        self.d = d

    def predict(self):
        zp, S = [], []
        for kf in self.filters:
            kf.predict()
            zp.append((kf.H @ kf.x).ravel())
            S.append(kf.H @ kf.P @ kf.H.T + kf.R)
        return np.array(zp).reshape(-1, self.d), np.array(S).reshape(-1, self.d, self.d)

    def measurements(self, measurements: object) -> np.ndarray:
        """One scan as a finite ``(m, d)`` float array (an empty scan may be ``[]``)."""
        try:
            z = np.asarray(measurements, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError("measurements must be a numeric (m, d) array") from exc
        if z.size == 0:
            return np.zeros((0, self.d))
        if self.d == 1 and z.ndim == 1:
            z = z[:, None]
        if z.ndim != 2 or z.shape[1] != self.d:
            raise ValueError(f"measurements must have shape (m, {self.d}) (d = rows of H), "
                             f"got shape {z.shape}")
        if not np.all(np.isfinite(z)):
            raise ValueError("measurements must be finite")
        return z

    @property
    def states(self) -> np.ndarray:
        return np.array([kf.x.ravel() for kf in self.filters])


class JPDATracker:
    """JPDA tracker: per-target ``filterpy`` Kalman filters with beta-weighted updates.

    Each step predicts every target, builds the MVM (:func:`modified_validation_matrix`
    with row 0 = ``1 - P_D P_G`` and rows ``P_D N(z_j; z_hat_t, S_t) / lambda``
    inside the gate), computes ``beta`` and updates each target with the combined
    innovation ``nu_t = sum_j beta_jt nu_jt``::

        x = x + K nu_t
        P = beta_0t P_pred + (1 - beta_0t) (I - K H) P_pred
            + K (sum_j beta_jt nu_jt nu_jt^T - nu_t nu_t^T) K^T

    the last term being the spread of the innovations (Fortmann, Bar-Shalom & Scheffe
    1983). The paper treats these covariance and state updates as standard (Sec. II).

    Parameters
    ----------
    x0 : array_like, shape (T, n)
        Initial states (track initiation is not part of JPDA, chapter 3 does it).
    P0, F, Q, H, R : array_like
        Initial covariance, transition, process noise, measurement and noise matrices.
    p_detect : float
        ``P_D`` in (0, 1].
    clutter_density : float
        Spatial density ``lambda`` of false measurements (> 0).
    gate_prob : float
        Gate probability ``P_G`` in (0, 1).
    """

    def __init__(self, x0, P0, F, Q, H, R, p_detect: float = 0.9,
                 clutter_density: float = 1e-3, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R)
        self.p_detect = float(_check_prob(p_detect, "p_detect", 1)[0])
        lam = float(clutter_density)
        if not np.isfinite(lam) or lam <= 0:
            raise ValueError(f"clutter_density must be positive, got {clutter_density}")
        self.clutter_density = lam
        self.gate_prob = float(gate_prob)
        gate_threshold(self.gate_prob, self.bank.d)
        self.last_beta_: np.ndarray | None = None

    def step(self, measurements: object) -> np.ndarray:
        """Predict, associate and update with one scan of measurements ``(m, d)``; returns states."""
        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        T = len(zp)
        mvm = modified_validation_matrix(z, zp, S, self.p_detect, self.gate_prob,
                                         self.clutter_density)
        mvm[0] = 1.0 - self.p_detect * self.gate_prob
        b = beta(mvm)
        self.last_beta_ = b
        for t, kf in enumerate(self.bank.filters):
            nu_j = z - zp[t][None, :]
            bj = b[1:, t]
            nu = bj @ nu_j
            Si = np.linalg.inv(S[t])
            K = kf.P @ kf.H.T @ Si
            spread = (nu_j * bj[:, None]).T @ nu_j - np.outer(nu, nu)
            Pc = (np.eye(kf.P.shape[0]) - K @ kf.H) @ kf.P
            kf.x = kf.x + K @ nu.reshape(-1, 1)
            P = b[0, t] * kf.P + (1 - b[0, t]) * Pc + K @ spread @ K.T
            kf.P = 0.5 * (P + P.T)
        return self.bank.states


class GNNTracker:
    """Global nearest neighbour tracker (a baseline for :class:`JPDATracker`).

    Each scan, measurements are assigned one-to-one to targets by
    ``scipy.optimize.linear_sum_assignment`` on the squared Mahalanobis distance, with a dummy "no measurement" option at the gate threshold; each
    target is updated with its assigned measurement (standard Kalman update) or only
    predicted. Same parameters as :class:`JPDATracker` (``P_D``, ``lambda`` unused).
    """

    def __init__(self, x0, P0, F, Q, H, R, gate_prob: float = 0.99):
        self.bank = _KFBank(x0, P0, F, Q, H, R)
        self.gate = gate_threshold(gate_prob, self.bank.d)

    def step(self, measurements: object) -> np.ndarray:
        """Predict, assign and update with one scan ``(m, d)``; returns the states."""
        from scipy.optimize import linear_sum_assignment

        z = self.bank.measurements(measurements)
        zp, S = self.bank.predict()
        T, m = len(zp), len(z)
        if m:
            d2 = mahalanobis_sq(z, zp, S).T  # (T, m)
            big = 1e12
            cost = np.where(d2 <= self.gate, d2, big)
            dummy = np.full((T, T), big)
            np.fill_diagonal(dummy, self.gate)
            r, c = linear_sum_assignment(np.hstack([cost, dummy]))
            for t, j in zip(r, c):
                if j < m and cost[t, j] < big:
                    self.bank.filters[t].update(z[j].reshape(-1, 1))
        return self.bank.states

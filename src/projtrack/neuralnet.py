"""Multitarget tracking with a cubic-energy binary Hopfield net: Barnard & Casasent (1988).

Implements chapter 5 of Casasent's 1989 report (E. Barnard and D. Casasent,
"Multitarget tracking with cubic energy optical neural nets", Appl. Opt. 1989).

Neuron ``X[i, alpha, a]`` is 1 when target ``i`` is assigned measurement ``alpha`` of
time step (frame) ``a``; a net has ``N_T x N_M x N_P`` neurons. Implemented:

* the distance tensor ``D[a, alpha, beta, gamma] = |r_alpha^a - 2 r_beta^{a+1} + r_gamma^{a+2}|``
  of eq. (7) (:func:`distance_tensor`), with zero-vector padding of missing measurements
  (:func:`pad_measurements`);
* the energy of eq. (8) (:func:`energy`) and its derivative eq. (9)
  (:func:`energy_gradient`);
* binary neurons updated by eq. (4) with the paper's raised threshold
  ``2 A3 N_T + 0.035``, serial (asynchronous) or parallel sweeps, an iteration limit and
  detection of convergence and oscillation (:func:`run_net`, batched over many nets),
  with two other readings of the update (no self term in term 3, exact energy change;
  :func:`update_inputs`);
* the fixed points of one-to-one assignments: an active neuron's input is exactly
  ``A4`` times the sum of its D terms (:func:`neuron_distance_sums`), so an assignment
  is a fixed point if and only if that stays below a limit set by the offset and the
  update rule (:func:`fixed_point_limit`, :func:`is_fixed_point`), checked over all
  assignments at once by :func:`assignment_max_sums`;
* the linear-algebra form of the optical architecture (Sec. IV-V): the fixed connection
  matrices ``T1``-``T3`` of eq. (10) (:func:`connection_matrices`), the full rank-3 tensor
  and the tensor-matrix inner product ``y4 = D . x x^T`` of eqs. (11)-(12)
  (:func:`full_tensor`, :func:`tensor_matrix_product`) and the paper's reduced per-target
  form with ``N_M`` matrices of size ``(N_M N_P)^2`` (:func:`reduced_tensor`,
  :func:`reduced_tensor_product`), and the SLM sizes of both (:func:`slm_sizes`);
* reference solutions of the same assignment problem: the exact optimum of the summed
  eq. (7) cost by dynamic programming over frame assignments (:func:`optimal_assignment`),
  frame-to-frame :func:`scipy.optimize.linear_sum_assignment` on Euclidean distance
  (:func:`nearest_neighbour_assignment`), a greedy frame-by-frame assignment on eq. (7)
  (:func:`greedy_assignment`) and its block-coordinate improvement in which every frame
  is re-solved exactly by a linear assignment with the other frames fixed
  (:func:`coordinate_descent_assignment`).

Indexing conventions: ``positions`` has shape ``(N_P, N_M, dim)``; ``D`` has shape
``(N_P - 2, N_M, N_M, N_M)``; states ``X`` have shape ``(..., N_T, N_M, N_P)``; the
neuron vector ``x`` of Sec. IV is ``X.reshape(-1)`` (target slowest, so that
``x = (z_1, ..., z_NT)`` with ``z_i = X[i].reshape(-1)`` as in Sec. V). An assignment is
an int array ``(N_T, N_P)`` of measurement indices.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import sparse
from scipy.optimize import linear_sum_assignment

__all__ = [
    "PAPER_COEFFICIENTS",
    "PAPER_OFFSET",
    "Coefficients",
    "NetResult",
    "pad_measurements",
    "distance_tensor",
    "energy",
    "energy_gradient",
    "energy_gradient_loops",
    "initial_states",
    "run_net",
    "update_inputs",
    "is_fixed_point",
    "fixed_point_limit",
    "neuron_distance_sums",
    "assignment_max_sums",
    "states_to_assignment",
    "assignment_to_states",
    "is_correct_assignment",
    "assignment_cost",
    "connection_matrices",
    "full_tensor",
    "tensor_matrix_product",
    "reduced_tensor",
    "reduced_tensor_product",
    "gradient_linear_algebra",
    "slm_sizes",
    "optimal_assignment",
    "nearest_neighbour_assignment",
    "greedy_assignment",
    "coordinate_descent_assignment",
    "simulate",
]


@dataclass(frozen=True)
class Coefficients:
    """The positive weights ``A1``-``A4`` of eq. (8)."""

    A1: float = 15.0
    A2: float = 15.0
    A3: float = 15.0
    A4: float = 1.8

    def __post_init__(self) -> None:
        for name in ("A1", "A2", "A3", "A4"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
                raise TypeError(f"coefficient {name} must be a number, got {type(v).__name__}")
            if not np.isfinite(v) or v < 0:
                raise ValueError(f"coefficient {name} must be finite and >= 0, got {v}")


#: Sec. VI: A1 = A2 = A3 = 15, A4 = 1.8.
PAPER_COEFFICIENTS = Coefficients(15.0, 15.0, 15.0, 1.8)
#: Sec. VI: the threshold 2 A3 N_T is raised by 0.035.
PAPER_OFFSET = 0.035


# ----------------------------------------------------------------------------- validation
def _as_coefficients(coefficients: object) -> Coefficients:
    if coefficients is None:
        return PAPER_COEFFICIENTS
    if isinstance(coefficients, Coefficients):
        return coefficients
    if isinstance(coefficients, (tuple, list, np.ndarray)) and len(coefficients) == 4:
        return Coefficients(*[float(c) for c in coefficients])
    raise TypeError("coefficients must be a Coefficients or a sequence (A1, A2, A3, A4)")


def _check_int(value: object, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _check_D(D: object, batched: bool = False) -> np.ndarray:
    D = np.asarray(D, dtype=float)
    if D.ndim not in ((4, 5) if batched else (4,)):
        raise ValueError(f"D must have shape {'(B,) ' if batched else ''}(N_P - 2, N_M, N_M, N_M), got {D.shape}")
    if not (D.shape[-1] == D.shape[-2] == D.shape[-3]) or D.shape[-4] < 1 or D.shape[-1] < 1:
        raise ValueError(f"D must have shape (..., N_P - 2, N_M, N_M, N_M) with N_P >= 3, got {D.shape}")
    if not np.all(np.isfinite(D)):
        raise ValueError("D must be finite")
    if np.any(D < 0):
        raise ValueError("D must be >= 0 (it is a norm, eq. (7))")
    return D


def _check_states(X: object, D: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    X = np.asarray(X, dtype=float)
    n_frames = D.shape[-4] + 2
    n_meas = D.shape[-1]
    if X.ndim < 3 or X.shape[-2:] != (n_meas, n_frames):
        raise ValueError(
            f"X must have shape (..., N_T, N_M, N_P) = (..., N_T, {n_meas}, {n_frames}) to match D, got {X.shape}")
    if n_targets is not None and X.shape[-3] != n_targets:
        raise ValueError(f"X must have N_T = {n_targets} targets, got {X.shape[-3]}")
    if X.shape[-3] > n_meas:
        raise ValueError(f"N_T = {X.shape[-3]} targets need at least as many measurements, got N_M = {n_meas}")
    if not np.all(np.isfinite(X)):
        raise ValueError("X must be finite")
    return X


# ----------------------------------------------------------------------------- data
def pad_measurements(frames: Sequence[np.ndarray], n_measurements: int | None = None,
                     n_targets: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Pad frames with zero vectors to ``N_M`` measurements each (Sec. IV).

    A frame with ``M < N_M`` measurements gets ``N_M - M`` zero vectors (the centre of the
    space), as the paper does for missing measurements.

    Parameters
    ----------
    frames : sequence of array_like, each (M_a, dim)
        Measurements of each time step, positions relative to the centre.
    n_measurements : int, optional
        ``N_M``; defaults to the largest ``M_a`` (and to at least ``n_targets``).
    n_targets : int, optional
        ``N_T``; if given, ``N_M >= N_T`` is enforced (padding up to ``N_T``).

    Returns
    -------
    positions : ndarray, shape (N_P, N_M, dim)
    real : ndarray of bool, shape (N_P, N_M)
        False for the padding.
    """
    if isinstance(frames, np.ndarray) and frames.ndim == 3:
        frames = list(frames)
    if not isinstance(frames, (list, tuple)) or len(frames) == 0:
        raise TypeError("frames must be a non-empty sequence of (M_a, dim) arrays")
    arrs = []
    for a, f in enumerate(frames):
        f = np.asarray(f, dtype=float)
        if f.ndim == 1 and f.size == 0:
            f = f.reshape(0, -1) if arrs == [] else f.reshape(0, arrs[0].shape[1])
        if f.ndim != 2:
            raise ValueError(f"frames[{a}] must be a 2-D (M, dim) array, got shape {f.shape}")
        if not np.all(np.isfinite(f)):
            raise ValueError(f"frames[{a}] contains non-finite positions")
        arrs.append(f)
    dims = {f.shape[1] for f in arrs if f.shape[0] > 0}
    if len(dims) > 1:
        raise ValueError(f"all frames must have the same dimension, got {sorted(dims)}")
    dim = dims.pop() if dims else 3
    largest = max(f.shape[0] for f in arrs)
    if n_targets is not None:
        n_targets = _check_int(n_targets, "n_targets", 1)
        largest = max(largest, n_targets)
    if n_measurements is None:
        n_measurements = largest
    n_measurements = _check_int(n_measurements, "n_measurements", 1)
    if n_measurements < largest:
        raise ValueError(f"n_measurements = {n_measurements} is smaller than a frame's {largest} measurements"
                         + (f" or n_targets = {n_targets}" if n_targets is not None else ""))
    positions = np.zeros((len(arrs), n_measurements, dim))
    real = np.zeros((len(arrs), n_measurements), dtype=bool)
    for a, f in enumerate(arrs):
        positions[a, :f.shape[0]] = f.reshape(-1, dim) if f.size else 0.0
        real[a, :f.shape[0]] = True
    return positions, real


def distance_tensor(positions: np.ndarray) -> np.ndarray:
    """The distance tensor of eq. (7) for every three consecutive frames.

    ``D[a, alpha, beta, gamma] = | d^a_{alpha beta} - d^{a+1}_{beta gamma} |`` with
    ``d^a_{alpha beta} = r^a_alpha - r^{a+1}_beta``, i.e. the norm of the second difference
    ``r^a_alpha - 2 r^{a+1}_beta + r^{a+2}_gamma``: zero for three collinear, evenly spaced
    measurements.

    Parameters
    ----------
    positions : array_like, shape (N_P, N_M, dim) or (B, N_P, N_M, dim)
        Measurements (padded to ``N_M`` per frame, see :func:`pad_measurements`).

    Returns
    -------
    ndarray, shape ([B,] N_P - 2, N_M, N_M, N_M)
    """
    r = np.asarray(positions, dtype=float)
    if r.ndim not in (3, 4):
        raise ValueError(f"positions must have shape ([B,] N_P, N_M, dim), got {r.shape}")
    if r.shape[-3] < 3:
        raise ValueError(f"positions need at least 3 frames (N_P >= 3) for eq. (7), got {r.shape[-3]}")
    if r.shape[-2] < 1 or r.shape[-1] < 1:
        raise ValueError(f"positions need N_M >= 1 measurements of dim >= 1, got {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ValueError("positions must be finite")
    r0 = r[..., :-2, :, None, None, :]
    r1 = r[..., 1:-1, None, :, None, :]
    r2 = r[..., 2:, None, None, :, :]
    return np.linalg.norm(r0 - 2.0 * r1 + r2, axis=-1)


# ----------------------------------------------------------------------------- energy
def _term4_parts(X: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Term 4 of eq. (9) without A4, for all neurons; X (..., N_T, N_M, N_P)."""
    out = np.zeros_like(X)
    # X[..., i, :, a] as (..., N_T, N_P, N_M) for convenient slicing by frame.
    Xt = np.moveaxis(X, -1, -2)
    x0, x1, x2 = Xt[..., :-2, :], Xt[..., 1:-1, :], Xt[..., 2:, :]  # (..., N_T, N_P-2, N_M)
    Db = D[..., None, :, :, :, :]  # broadcast over targets
    first = np.einsum("...abcd,...ac,...ad->...ab", Db, x1, x2)   # neuron (i, alpha, a)
    middle = np.einsum("...abcd,...ab,...ad->...ac", Db, x0, x2)  # neuron (i, beta, a+1)
    last = np.einsum("...abcd,...ab,...ac->...ad", Db, x0, x1)    # neuron (i, gamma, a+2)
    outt = np.moveaxis(out, -1, -2)
    outt[..., :-2, :] += first
    outt[..., 1:-1, :] += middle
    outt[..., 2:, :] += last
    return np.moveaxis(outt, -2, -1)


def energy(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None
           ) -> np.ndarray | float:
    """The energy of eq. (8).

    ``E = A1 sum_{alpha,a} sum_{i != j} X_iaa X_jaa + A2 sum_{i,a} sum_{alpha != beta} X_iaa X_iba
    + A3 sum_a (sum_{i,alpha} X_iaa - N_T)^2
    + A4 sum_{a,i,alpha,beta,gamma} D^a_abg X_{i alpha a} X_{i beta a+1} X_{i gamma a+2}``.

    Term 3 is written with the sum over targets and measurements inside the square, as
    the paper's text and its derivative eq. (9) require (the printed eq. (8) lost the
    sum over ``a``). Defined for real-valued ``X`` as well (it is a polynomial).

    Parameters
    ----------
    X : array_like, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    float or ndarray of shape X.shape[:-3]
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D, batched=True)
    X = _check_states(X, D)
    n_t = X.shape[-3]
    col = X.sum(axis=-3)       # (..., N_M, N_P)
    row = X.sum(axis=-2)       # (..., N_T, N_P)
    sq = (X * X)
    e1 = (col ** 2).sum(axis=(-2, -1)) - sq.sum(axis=(-3, -2, -1))
    e2 = (row ** 2).sum(axis=(-2, -1)) - sq.sum(axis=(-3, -2, -1))
    frame = X.sum(axis=(-3, -2))  # (..., N_P)
    e3 = ((frame - n_t) ** 2).sum(axis=-1)
    Xt = np.moveaxis(X, -1, -2)
    e4 = np.einsum("...abcd,...iab,...iac,...iad->...", D, Xt[..., :-2, :], Xt[..., 1:-1, :], Xt[..., 2:, :])
    E = c.A1 * e1 + c.A2 * e2 + c.A3 * e3 + c.A4 * e4
    return float(E) if np.ndim(E) == 0 else E


def energy_gradient(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None
                    ) -> np.ndarray:
    """The derivative ``dE/dX_{i alpha a}`` of eq. (9), for all neurons at once.

    ``2 A1 sum_{j != i} X_{j alpha a} + 2 A2 sum_{beta != alpha} X_{i beta a}
    + 2 A3 (sum_{j, beta} X_{j beta a} - N_T) + A4 (the three D-terms)``; the D-terms that
    would need frames outside ``0..N_P-1`` are absent. This is the exact partial
    derivative of the polynomial :func:`energy`.

    Parameters
    ----------
    X : array_like, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    ndarray, same shape as X
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D, batched=True)
    X = _check_states(X, D)
    n_t = X.shape[-3]
    col = X.sum(axis=-3, keepdims=True) - X
    row = X.sum(axis=-2, keepdims=True) - X
    frame = X.sum(axis=(-3, -2), keepdims=True)
    return (2 * c.A1 * col + 2 * c.A2 * row + 2 * c.A3 * (frame - n_t)
            + c.A4 * _term4_parts(X, D))


def energy_gradient_loops(X: np.ndarray, D: np.ndarray,
                          coefficients: Coefficients | Sequence[float] | None = None) -> np.ndarray:
    """Eq. (9) written as the paper's nested sums, with plain Python loops.

    The straightforward reference for :func:`energy_gradient` (tests and benchmarks).

    Parameters
    ----------
    X : array_like, shape (N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's

    Returns
    -------
    ndarray, shape (N_T, N_M, N_P)
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D)
    X = _check_states(X, D)
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    n_t, n_m, n_p = X.shape
    g = np.zeros_like(X)
    for i in range(n_t):
        for al in range(n_m):
            for a in range(n_p):
                t1 = sum(X[j, al, a] for j in range(n_t) if j != i)
                t2 = sum(X[i, b, a] for b in range(n_m) if b != al)
                t3 = sum(X[j, b, a] for j in range(n_t) for b in range(n_m)) - n_t
                t4 = 0.0
                for b in range(n_m):
                    for gm in range(n_m):
                        if a + 2 < n_p:
                            t4 += D[a, al, b, gm] * X[i, b, a + 1] * X[i, gm, a + 2]
                        if 1 <= a <= n_p - 2:
                            t4 += D[a - 1, b, al, gm] * X[i, b, a - 1] * X[i, gm, a + 1]
                        if a >= 2:
                            t4 += D[a - 2, b, gm, al] * X[i, b, a - 2] * X[i, gm, a - 1]
                g[i, al, a] = 2 * c.A1 * t1 + 2 * c.A2 * t2 + 2 * c.A3 * t3 + c.A4 * t4
    return g


# ----------------------------------------------------------------------------- dynamics
@dataclass(frozen=True)
class NetResult:
    """Outcome of :func:`run_net` for a batch of ``B`` nets.

    Attributes
    ----------
    states : ndarray of int8, shape (B, N_T, N_M, N_P)
        Final binary states.
    status : ndarray of str, shape (B,)
        ``"converged"`` (a sweep changed nothing), ``"oscillating"`` (the last state
        recurred with period ``period``) or ``"wandering"`` (neither, within the limit).
    iterations : ndarray of int, shape (B,)
        For converged nets, the number of sweeps that led to the fixed point (the
        confirming sweep that changed nothing is not counted); otherwise ``max_iter``.
    period : ndarray of int, shape (B,)
        Cycle length for oscillating nets, 1 for converged, 0 for wandering.
    history : ndarray of float, shape (n_sweeps + 1, B, N_T, N_M, N_P) or None
        If recorded: ``history[0]`` is the start state exactly as the net used it (the
        analog values of :func:`initial_states`, not thresholded), ``history[s]`` the
        binary state after sweep ``s``.
    """

    states: np.ndarray
    status: np.ndarray
    iterations: np.ndarray
    period: np.ndarray
    history: np.ndarray | None = None

    @property
    def converged(self) -> np.ndarray:
        """Boolean mask of converged nets."""
        return self.status == "converged"


def initial_states(rng: np.random.Generator, n_runs: int, n_targets: int, n_measurements: int,
                   n_frames: int, perturbation: float = 0.1) -> np.ndarray:
    """Randomly perturbed all-equal start (Sec. VI, after Hopfield and Tank).

    The all-equal state gives every neuron ``1 / N_M`` (every measurement equally likely
    for every target, so that each frame sums to ``N_T``); each neuron is multiplied by
    ``1 + u`` with ``u`` uniform in ``[-perturbation, perturbation]`` (Hopfield & Tank used
    10%). The first sweep thresholds these analog values to binary ones.

    Returns
    -------
    ndarray, shape (n_runs, N_T, N_M, N_P)
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    n_runs = _check_int(n_runs, "n_runs", 0)
    n_targets = _check_int(n_targets, "n_targets", 1)
    n_measurements = _check_int(n_measurements, "n_measurements", 1)
    n_frames = _check_int(n_frames, "n_frames", 3)
    if n_measurements < n_targets:
        raise ValueError(f"n_measurements ({n_measurements}) must be >= n_targets ({n_targets})")
    if not (np.isfinite(perturbation) and 0 <= perturbation < 1):
        raise ValueError(f"perturbation must be in [0, 1), got {perturbation}")
    shape = (n_runs, n_targets, n_measurements, n_frames)
    return (1.0 + rng.uniform(-perturbation, perturbation, shape)) / n_measurements


def run_net(D: np.ndarray, X0: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None, *,
            offset: float = PAPER_OFFSET, max_iter: int = 50, mode: str = "serial",
            self_coupling: bool = True, exact_energy: bool = False, record: bool = False) -> NetResult:
    """Evolve binary neurons by eqs. (4) and (9) until convergence, a cycle or ``max_iter``.

    Neuron ``k`` is set to 1 when ``dE/dX_k < offset`` and to 0 otherwise: the neuron's
    non-negative input ``dE/dX_k + 2 A3 N_T`` is compared with the raised threshold
    ``2 A3 N_T + offset`` of Sec. VI. In ``"serial"`` mode (the paper's simulations) the
    neurons are visited in the order of the vector ``x`` (target, measurement, frame) and
    each new state is used at once; in ``"parallel"`` mode all neurons are updated from
    the same old state. All ``B`` nets of the batch are run together (vectorized over B).

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or (B, N_P - 2, N_M, N_M, N_M)
        Distance tensors, eq. (7) (one shared by all nets, or one per net).
    X0 : array_like, shape (B, N_T, N_M, N_P) or (N_T, N_M, N_P)
        Start states (analog values are allowed, see :func:`initial_states`).
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's (15, 15, 15, 1.8)
    offset : float, default 0.035
        Threshold increase of Sec. VI.
    max_iter : int, default 50
        Largest number of sweeps.
    mode : {"serial", "parallel"}
    self_coupling : bool, default True
        Eq. (9) as printed: the frame sum of term 3 includes the neuron itself. With
        False it is left out (the usual Hopfield convention of no self-connection).
    exact_energy : bool, default False
        Instead of the first-order rule of eqs. (4)-(6), compare the exact energy change
        ``E(X_k = 1) - E(X_k = 0)`` with ``offset`` (see :func:`update_inputs`); this
        ignores ``self_coupling``.
    record : bool, default False
        Keep the start and the state after every sweep in ``NetResult.history``.

    Returns
    -------
    NetResult
    """
    c = _as_coefficients(coefficients)
    D = _check_D(D, batched=True)
    X = _check_states(X0, D)
    single = X.ndim == 3
    if single:
        X = X[None]
    if X.ndim != 4:
        raise ValueError(f"X0 must have shape ([B,] N_T, N_M, N_P), got {X.shape}")
    B, n_t, n_m, n_p = X.shape
    if D.ndim == 5 and D.shape[0] != B:
        raise ValueError(f"D has {D.shape[0]} tensors for {B} start states")
    if not np.isfinite(offset):
        raise ValueError(f"offset must be finite, got {offset}")
    max_iter = _check_int(max_iter, "max_iter", 1)
    if mode not in ("serial", "parallel"):
        raise ValueError(f"mode must be 'serial' or 'parallel', got {mode!r}")
    if not isinstance(self_coupling, (bool, np.bool_)) or not isinstance(exact_energy, (bool, np.bool_)):
        raise TypeError("self_coupling and exact_energy must be bools")
    Db = np.broadcast_to(D, (B,) + D.shape[-4:]) if D.ndim == 4 else D
    X = X.copy()
    col = X.sum(axis=1)          # (B, N_M, N_P)
    row = X.sum(axis=2)          # (B, N_T, N_P)
    frame = X.sum(axis=(1, 2))   # (B, N_P)
    a1, a2, a3, a4 = 2 * c.A1, 2 * c.A2, 2 * c.A3, c.A4
    # Pre-sliced tensors: D[a, alpha] (B, N_M, N_M), D[a-1, :, alpha] and D[a-2, :, :, alpha].
    D_first = [[np.ascontiguousarray(Db[:, a, al]) for al in range(n_m)] for a in range(n_p - 2)]
    D_mid = [[np.ascontiguousarray(Db[:, a, :, al]) for al in range(n_m)] for a in range(n_p - 2)]
    D_last = [[np.ascontiguousarray(Db[:, a, :, :, al]) for al in range(n_m)] for a in range(n_p - 2)]

    # history[0] is the start exactly as the net used it (analog values allowed).
    history = [X.copy()] if record else []
    converged_at = np.full(B, -1)
    snapshots = []
    for sweep in range(1, max_iter + 1):
        old = X.copy()
        if mode == "parallel":
            g = update_inputs(X, Db, c, self_coupling=self_coupling, exact_energy=exact_energy)
            X = (g < offset).astype(float)
        else:
            for i in range(n_t):
                for al in range(n_m):
                    for a in range(n_p):
                        xk = X[:, i, al, a]
                        s = frame[:, a] if (self_coupling and not exact_energy) else frame[:, a] - xk
                        g = a1 * (col[:, al, a] - xk) + a2 * (row[:, i, a] - xk) + a3 * (s - n_t)
                        if exact_energy:
                            g = g + c.A3
                        if n_p >= 3:
                            t4 = 0.0
                            if a + 2 < n_p:
                                t4 = t4 + np.einsum("bqr,bq,br->b", D_first[a][al], X[:, i, :, a + 1], X[:, i, :, a + 2])
                            if 1 <= a <= n_p - 2:
                                t4 = t4 + np.einsum("bqr,bq,br->b", D_mid[a - 1][al], X[:, i, :, a - 1], X[:, i, :, a + 1])
                            if a >= 2:
                                t4 = t4 + np.einsum("bqr,bq,br->b", D_last[a - 2][al], X[:, i, :, a - 2], X[:, i, :, a - 1])
                            g = g + a4 * t4
                        new = (g < offset).astype(float)
                        delta = new - xk
                        X[:, i, al, a] = new
                        col[:, al, a] += delta
                        row[:, i, a] += delta
                        frame[:, a] += delta
        if mode == "parallel":
            col = X.sum(axis=1)
            row = X.sum(axis=2)
            frame = X.sum(axis=(1, 2))
        binary = X.astype(np.int8)
        if record:
            history.append(X.copy())
        unchanged = np.all(X == old, axis=(1, 2, 3))
        newly = unchanged & (converged_at < 0)
        converged_at[newly] = sweep - 1
        snapshots.append(binary.reshape(B, -1))
        if np.all(converged_at >= 0):
            break
    status = np.where(converged_at >= 0, "converged", "wandering").astype(object)
    iterations = np.where(converged_at >= 0, converged_at, max_iter)
    period = np.where(converged_at >= 0, 1, 0)
    if np.any(converged_at < 0):
        last = snapshots[-1]
        for p in range(2, len(snapshots)):
            same = np.all(snapshots[-1 - p] == last, axis=1) & (period == 0)
            period[same] = p
        status[(converged_at < 0) & (period > 0)] = "oscillating"
    status = status.astype(str)
    hist = np.stack(history) if record else None
    if single:
        return NetResult(X[0].astype(np.int8), status[:1], iterations[:1], period[:1],
                         hist[:, 0] if hist is not None else None)
    return NetResult(X.astype(np.int8), status, iterations, period, hist)


def update_inputs(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None, *,
                  self_coupling: bool = True, exact_energy: bool = False) -> np.ndarray:
    """The quantity each neuron compares with the offset, under three readings of eq. (4).

    A neuron is switched on when its value here is below ``offset`` (0.035 in Sec. VI).

    * ``self_coupling=True`` (eq. (9) as printed): ``dE/dX`` of :func:`energy_gradient`,
      whose term 3 counts the neuron itself in the frame sum.
    * ``self_coupling=False``: the same without the neuron in the frame sum,
      ``dE/dX - 2 A3 X``.
    * ``exact_energy=True``: the exact change of eq. (8) when the neuron goes from 0 to 1,
      ``E(X_k = 1) - E(X_k = 0) = dE/dX - 2 A3 X + A3`` (terms 1, 2 and 4 do not contain
      ``X_k`` twice; term 3 adds ``A3 ((s + 1 - N_T)^2 - (s - N_T)^2)``, ``s`` the frame sum
      without the neuron). Overrides ``self_coupling``.

    Parameters
    ----------
    X : array_like, shape (..., N_T, N_M, N_P)
        Binary (or analog) states.
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients : Coefficients or (A1, A2, A3, A4), default the paper's
    self_coupling, exact_energy : bool

    Returns
    -------
    ndarray, same shape as X
    """
    if not isinstance(self_coupling, (bool, np.bool_)) or not isinstance(exact_energy, (bool, np.bool_)):
        raise TypeError("self_coupling and exact_energy must be bools")
    c = _as_coefficients(coefficients)
    g = energy_gradient(X, D, c)
    X = np.asarray(X, dtype=float)
    if exact_energy:
        return g - 2 * c.A3 * X + c.A3
    if not self_coupling:
        return g - 2 * c.A3 * X
    return g


def is_fixed_point(X: np.ndarray, D: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None, *,
                   offset: float = PAPER_OFFSET, self_coupling: bool = True,
                   exact_energy: bool = False) -> np.ndarray | bool:
    """Whether binary states are fixed points of the update rule (no neuron would change).

    A state is a fixed point when every neuron already equals ``[input < offset]`` with
    the input of :func:`update_inputs`; then serial and parallel sweeps both leave it
    unchanged.

    Parameters
    ----------
    X : array_like of 0/1, shape (..., N_T, N_M, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M) or broadcastable batch
    coefficients, offset, self_coupling, exact_energy
        As in :func:`run_net`.

    Returns
    -------
    bool or ndarray of bool, shape X.shape[:-3]
    """
    Xa = np.asarray(X)
    if not np.all(np.isin(Xa, (0, 1))):
        raise ValueError("X must be binary (0/1)")
    if not np.isfinite(offset):
        raise ValueError(f"offset must be finite, got {offset}")
    g = update_inputs(Xa, D, coefficients, self_coupling=self_coupling, exact_energy=exact_energy)
    out = np.all((g < offset) == (Xa == 1), axis=(-3, -2, -1))
    return bool(out) if np.ndim(out) == 0 else out


def fixed_point_limit(coefficients: Coefficients | Sequence[float] | None = None, *, offset: float = PAPER_OFFSET,
                      self_coupling: bool = True, exact_energy: bool = False) -> float:
    """Largest summed distance an active neuron of a one-to-one assignment may carry.

    In a one-to-one assignment state (``N_T = N_M``: every target one measurement and every
    measurement one target in every frame) terms 1 and 2 of eq. (9) vanish for an active
    neuron and term 3 is 0 (as printed), ``-2 A3`` (without the self term) or ``-A3``
    (exact energy change), so its input is ``A4 S`` plus that constant, where ``S`` is the
    sum of its D terms (:func:`neuron_distance_sums`). An inactive neuron sees at least
    ``2 A1 + 2 A2`` and stays off. The assignment is therefore a fixed point if and only if
    ``max S < limit`` with ``limit = (offset + {0, 2 A3, A3}) / A4``, returned here (in the
    unit of D; ``-inf`` when no assignment can be a fixed point).

    Raises
    ------
    ValueError
        If ``2 A1 + 2 A2`` plus the inactive neuron's term 3 does not exceed ``offset``
        (then inactive neurons could switch on and the statement above does not hold).
    """
    c = _as_coefficients(coefficients)
    if not np.isfinite(offset):
        raise ValueError(f"offset must be finite, got {offset}")
    if not isinstance(self_coupling, (bool, np.bool_)) or not isinstance(exact_energy, (bool, np.bool_)):
        raise TypeError("self_coupling and exact_energy must be bools")
    shift = c.A3 if exact_energy else (0.0 if self_coupling else 2 * c.A3)
    inactive = 2 * c.A1 + 2 * c.A2 + (c.A3 if exact_energy else 0.0)
    if inactive < offset:
        raise ValueError(f"offset {offset} is not below 2 A1 + 2 A2 (+ A3) = {inactive}: inactive neurons "
                         "of an assignment could switch on")
    if c.A4 == 0:
        return float("inf") if offset + shift > 0 else float("-inf")
    limit = (offset + shift) / c.A4
    return float(limit) if limit > 0 else float("-inf")


def neuron_distance_sums(assignment: np.ndarray, D: np.ndarray) -> np.ndarray:
    """``S[i, a]``: the summed eq. (7) distances that neuron ``(i, assignment[i, a], a)`` sees.

    In the assignment state, term 4 of eq. (9) for the active neuron of target ``i`` in
    frame ``a`` is ``A4 S[i, a]``: the D values of the (up to three) triples of frames of
    target ``i``'s track that contain frame ``a``.

    Parameters
    ----------
    assignment : array_like of int, shape (N_T, N_P)
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)

    Returns
    -------
    ndarray, shape (N_T, N_P)
    """
    D = _check_D(D)
    A = np.asarray(assignment)
    assignment_cost(A, D)  # validates shape, dtype and range
    n_q = D.shape[0]
    a = np.arange(n_q)
    trip = D[a[None, :], A[:, :-2], A[:, 1:-1], A[:, 2:]]  # (N_T, N_P - 2)
    S = np.zeros(A.shape)
    S[:, :-2] += trip
    S[:, 1:-1] += trip
    S[:, 2:] += trip
    return S


def assignment_max_sums(D: np.ndarray, n_targets: int | None = None, max_assignments: int = 2_000_000
                        ) -> np.ndarray:
    """``max_{i,a} S[i, a]`` (:func:`neuron_distance_sums`) for every one-to-one assignment.

    Exhaustive over all ``(N_T!)^(N_P - 1)`` assignments with frame 0 labelled by the
    identity (targets are interchangeable): ``24^4 = 331776`` for the paper's case.
    With :func:`fixed_point_limit` this says exactly which assignments are fixed points.

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M), ``N_M = N_T``
    n_targets : int, optional
    max_assignments : int
        Refuse larger enumerations.

    Returns
    -------
    ndarray, shape (N_T!,) * (N_P - 1)
        Entry ``[p_1, ..., p_{N_P-1}]``: frame ``a`` assigns measurement
        ``perms[p_a][i]`` to target ``i``, ``perms`` the permutations of ``range(N_T)`` in
        lexicographic order (:func:`itertools.permutations`).
    """
    D, n = _check_square(D, n_targets)
    P = math.factorial(n)
    n_q = D.shape[0]
    n_p = n_q + 2
    max_assignments = _check_int(max_assignments, "max_assignments", 1)
    if P ** (n_p - 1) > max_assignments:
        raise ValueError(f"{P}^{n_p - 1} assignments exceed max_assignments = {max_assignments}")
    perms, flat = _permutation_triples(n)
    # trip[a, i]: D of triple a for target i under the permutations of frames a..a+2 (target axis first,
    # so that the maximum over targets is an elementwise maximum of contiguous arrays)
    trip = np.moveaxis(D.reshape(n_q, -1)[:, flat], -1, 1)  # (N_P - 2, N_T, P, P, P)
    # S of frame f for target i: sum of the triples a with a <= f <= a + 2; frame 0 is the identity.

    def triple(a: int) -> np.ndarray:
        t = trip[a][:, 0] if a == 0 else trip[a]     # frame 0 fixed: drop its axis
        first = max(a - 1, 0)                         # first free frame axis it spans
        idx = [None] * (n_p - 1)
        for k in range(first, a + 2):
            idx[k] = slice(None)
        return t[(slice(None),) + tuple(idx)]

    # D >= 0, so a frame whose triples are a subset of another frame's never holds the maximum:
    # only the maximal windows of triples need summing (one window for N_P = 5).
    windows = {tuple(range(max(0, f - 2), min(f, n_q - 1) + 1)) for f in range(n_p)}
    windows = [w for w in windows if not any(set(w) < set(v) for v in windows)]
    best = np.zeros((P,) * (n_p - 1))
    for w in sorted(windows):
        S = triple(w[0])
        for a in w[1:]:
            S = S + triple(a)
        S = np.broadcast_to(S, (n,) + best.shape)
        best = np.maximum(best, S.max(axis=0))
    return best


# ----------------------------------------------------------------------------- assignments
def states_to_assignment(X: np.ndarray) -> np.ndarray | None:
    """Read an assignment from binary states, or None if the states are not admissible.

    Admissible (conditions 4-6 of Sec. III): in every frame every target has exactly one
    active neuron and every measurement at most one.

    Parameters
    ----------
    X : array_like of 0/1, shape (N_T, N_M, N_P)

    Returns
    -------
    ndarray of int, shape (N_T, N_P), or None
    """
    X = np.asarray(X)
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    if not np.all(np.isin(X, (0, 1))):
        raise ValueError("X must be binary (0/1)")
    if np.any(X.sum(axis=1) != 1) or np.any(X.sum(axis=0) > 1):
        return None
    return np.argmax(X, axis=1)


def assignment_to_states(assignment: np.ndarray, n_measurements: int) -> np.ndarray:
    """Binary states ``(N_T, N_M, N_P)`` of an assignment ``(N_T, N_P)``."""
    A = np.asarray(assignment)
    if A.ndim != 2 or not np.issubdtype(A.dtype, np.integer):
        raise ValueError(f"assignment must be an int array (N_T, N_P), got {A.dtype} {A.shape}")
    n_measurements = _check_int(n_measurements, "n_measurements", 1)
    if A.size and (A.min() < 0 or A.max() >= n_measurements):
        raise ValueError(f"assignment entries must be in [0, {n_measurements})")
    n_t, n_p = A.shape
    X = np.zeros((n_t, n_measurements, n_p), dtype=np.int8)
    X[np.arange(n_t)[:, None], A, np.arange(n_p)[None, :]] = 1
    return X


def is_correct_assignment(assignment: np.ndarray | None, labels: np.ndarray) -> bool:
    """True when every target follows one true track through all frames.

    Parameters
    ----------
    assignment : int array (N_T, N_P) or None
        Measurement of each target in each frame (None: not admissible, so not correct).
    labels : int array (N_P, N_M)
        True track of each measurement (negative for spurious or padded measurements).
    """
    labels = np.asarray(labels)
    if labels.ndim != 2:
        raise ValueError(f"labels must have shape (N_P, N_M), got {labels.shape}")
    if assignment is None:
        return False
    A = np.asarray(assignment)
    if A.ndim != 2 or A.shape[1] != labels.shape[0]:
        raise ValueError(f"assignment must have shape (N_T, N_P = {labels.shape[0]}), got {A.shape}")
    tracks = labels[np.arange(labels.shape[0])[None, :], A]  # (N_T, N_P)
    if np.any(tracks < 0):
        return False
    if np.any(tracks != tracks[:, :1]):
        return False
    return len(set(tracks[:, 0].tolist())) == A.shape[0] and all(
        len(set(A[:, a].tolist())) == A.shape[0] for a in range(A.shape[1]))


def assignment_cost(assignment: np.ndarray, D: np.ndarray) -> float:
    """Summed eq. (7) distance of an assignment: term 4 of eq. (8) without ``A4``.

    Parameters
    ----------
    assignment : array_like of int, shape (N_T, N_P)
        Measurement index of each target in each frame, every entry in ``0..N_M-1``.
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)

    Returns
    -------
    float
    """
    D = _check_D(D)
    A = np.asarray(assignment)
    if A.ndim != 2 or A.shape[1] != D.shape[0] + 2:
        raise ValueError(f"assignment must have shape (N_T, N_P = {D.shape[0] + 2}), got {A.shape}")
    if A.dtype == bool or not np.issubdtype(A.dtype, np.integer):
        raise TypeError(f"assignment must hold integer measurement indices, got dtype {A.dtype}")
    n_m = D.shape[-1]
    if A.size and (A.min() < 0 or A.max() >= n_m):
        raise ValueError(f"assignment entries must be measurement indices in 0..{n_m - 1} (N_M = {n_m}), "
                         f"got values in {int(A.min())}..{int(A.max())}")
    a = np.arange(D.shape[0])
    return float(D[a[None, :], A[:, :-2], A[:, 1:-1], A[:, 2:]].sum())


# ----------------------------------------------------------------------------- linear algebra
def _flat_index(n_t: int, n_m: int, n_p: int) -> np.ndarray:
    return np.arange(n_t * n_m * n_p).reshape(n_t, n_m, n_p)


def connection_matrices(n_targets: int, n_measurements: int, n_frames: int
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fixed connection matrices ``T1``, ``T2``, ``T3`` of Sec. IV (eq. (10)).

    With ``k = (i, alpha, a)`` and ``l = (j, beta, b)``:
    ``T1_kl = delta_{alpha beta} delta_ab (1 - delta_ij)`` (eq. (10)),
    ``T2_kl = delta_ij delta_ab (1 - delta_{alpha beta})`` and ``T3_kl = delta_ab``, so that
    eq. (9) is ``2 A1 T1 x + 2 A2 T2 x + 2 A3 (T3 x - N_T) + y4``.

    Returns
    -------
    T1, T2, T3 : ndarray of int8, shape (K, K), ``K = N_T N_M N_P``
    """
    n_t = _check_int(n_targets, "n_targets", 1)
    n_m = _check_int(n_measurements, "n_measurements", 1)
    n_p = _check_int(n_frames, "n_frames", 1)
    i, al, a = (g.reshape(-1) for g in np.meshgrid(np.arange(n_t), np.arange(n_m), np.arange(n_p), indexing="ij"))
    same_i = i[:, None] == i[None, :]
    same_al = al[:, None] == al[None, :]
    same_a = a[:, None] == a[None, :]
    T1 = (same_al & same_a & ~same_i).astype(np.int8)
    T2 = (same_i & same_a & ~same_al).astype(np.int8)
    T3 = same_a.astype(np.int8)
    return T1, T2, T3


def full_tensor(D: np.ndarray, n_targets: int) -> sparse.csr_matrix:
    """The rank-3 tensor of eq. (11) as the ``K x K^2`` matrix written on SLM2.

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
    n_t = _check_int(n_targets, "n_targets", 1)
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
    """The tensor-matrix inner product ``y4_j = sum_{k,l} D_jkl x_k x_l`` (eqs. (11)-(12)).

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
    """The paper's reduced SLM2 content: ``N_M`` matrices of size ``(N_M N_P)^2`` (Sec. V).

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
    """``y4`` from the reduced form: ``N_T`` per-target VOPs ``z_i z_i^T`` times the ``N_M`` matrices.

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
    n_t = _check_int(n_targets, "n_targets", 1)
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
    """Eq. (9) as ``T x + A4 y4 - 2 A3 N_T`` with the matrices of eqs. (10)-(12).

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
    c = _as_coefficients(coefficients)
    D = _check_D(D)
    n_t = _check_int(n_targets, "n_targets", 1)
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
    """Pixel counts of the optical architecture of Sec. V.

    Returns
    -------
    dict with ``neurons`` (``K = N_T N_M N_P``, B1), ``vop_full`` (``K^2``, B2),
    ``slm2_full`` (``K^3``), ``vop_reduced`` (``N_T (N_M N_P)^2``),
    ``slm2_reduced`` (``N_M (N_M N_P)^2``) and ``reduction`` (``slm2_full // slm2_reduced``).
    """
    n_t = _check_int(n_targets, "n_targets", 1)
    n_m = _check_int(n_measurements, "n_measurements", 1)
    n_p = _check_int(n_frames, "n_frames", 1)
    K = n_t * n_m * n_p
    L = n_m * n_p
    out = {"neurons": K, "vop_full": K * K, "slm2_full": K ** 3,
           "vop_reduced": n_t * L * L, "slm2_reduced": n_m * L * L}
    out["reduction"] = out["slm2_full"] // out["slm2_reduced"]
    return out


# ----------------------------------------------------------------------------- references
def _check_square(D: np.ndarray, n_targets: int | None) -> tuple[np.ndarray, int]:
    D = _check_D(D)
    n_m = D.shape[1]
    n_t = n_m if n_targets is None else _check_int(n_targets, "n_targets", 1)
    if n_t != n_m:
        raise ValueError(f"the reference assignments need N_T == N_M, got N_T = {n_t}, N_M = {n_m}")
    return D, n_t


@functools.lru_cache(maxsize=8)
def _permutation_triples(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Permutations of ``range(n)`` and flat indices into ``D[a]`` of every triple of them."""
    perms = np.array(list(itertools.permutations(range(n))), dtype=np.intp)  # (P, n); perms[0] = identity
    p0 = perms[:, None, None, :]
    p1 = perms[None, :, None, :]
    p2 = perms[None, None, :, :]
    flat = (p0 * n + p1) * n + p2                                            # (P, P, P, n)
    flat.setflags(write=False)
    perms.setflags(write=False)
    return perms, flat


def optimal_assignment(D: np.ndarray, n_targets: int | None = None, max_states: int = 20_000_000
                       ) -> tuple[np.ndarray, float]:
    """Exact minimum of the summed eq. (7) cost over one-to-one assignments (``N_T = N_M``).

    Dynamic programming (Viterbi) over pairs of consecutive frame permutations: the cost
    ``sum_i sum_a D^a(pi_a(i), pi_{a+1}(i), pi_{a+2}(i))`` couples only three consecutive
    frames. Frame 0 is labelled by the identity (targets are interchangeable). Work is
    ``N_P (N_T!)^3``: fine up to ``N_T = 5``.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
    cost : float
    """
    D, n = _check_square(D, n_targets)
    P = math.factorial(n)
    if P ** 3 > max_states:
        raise ValueError(f"N_T = {n} is too large for the exact search ({P}^3 states per frame)")
    perms, flat = _permutation_triples(n)
    n_q = D.shape[0]
    # cost[a, p0, p1, p2]: summed D of frames (a, a+1, a+2) under permutations p0, p1, p2
    cost = D.reshape(n_q, -1)[:, flat].sum(axis=-1)
    # V[p1, p2]: best cost with frame 0 = identity, frame a+1 = perms[p1], frame a+2 = perms[p2]
    V = cost[0, 0]  # perms[0] is the identity
    back = []
    for a in range(1, n_q):
        tot = V[:, :, None] + cost[a]
        arg = np.argmin(tot, axis=0)   # over p0 -> (p1, p2)
        back.append(arg)
        V = np.take_along_axis(tot, arg[None], axis=0)[0]
    p1, p2 = np.unravel_index(np.argmin(V), V.shape)
    best = float(V[p1, p2])
    seq = [p2, p1]
    for arg in reversed(back):
        p0 = arg[seq[-1], seq[-2]]
        seq.append(p0)
    seq = seq[::-1]  # perms for frames 1..N_P-1
    A = np.empty((n, n_q + 2), dtype=np.intp)
    A[:, 0] = np.arange(n)
    for f, p in enumerate(seq, start=1):
        A[:, f] = perms[p]
    return A, best


def nearest_neighbour_assignment(positions: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    """Frame-to-frame :func:`scipy.optimize.linear_sum_assignment` on Euclidean distance.

    Targets are the measurements of frame 0; each next frame is matched one-to-one to the
    previous one by minimum summed distance (no motion model).

    Parameters
    ----------
    positions : array_like, shape (N_P, N_M, dim), ``N_M = N_T``

    Returns
    -------
    ndarray of int, shape (N_T, N_P)
    """
    r = np.asarray(positions, dtype=float)
    if r.ndim != 3 or r.shape[0] < 2:
        raise ValueError(f"positions must have shape (N_P >= 2, N_M, dim), got {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ValueError("positions must be finite")
    n = r.shape[1] if n_targets is None else _check_int(n_targets, "n_targets", 1)
    if n != r.shape[1]:
        raise ValueError(f"the reference assignments need N_T == N_M, got {n} and {r.shape[1]}")
    A = np.empty((n, r.shape[0]), dtype=np.intp)
    A[:, 0] = np.arange(n)
    for a in range(1, r.shape[0]):
        prev = r[a - 1][A[:, a - 1]]
        cost = np.linalg.norm(prev[:, None, :] - r[a][None, :, :], axis=-1)
        _, cols = linear_sum_assignment(cost)
        A[:, a] = cols
    return A


def greedy_assignment(D: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    """Frame-by-frame linear assignment on the eq. (7) cost.

    Frame 0 is the identity; frame 1 is matched by ``min_gamma D^0_{alpha beta gamma}``
    (the best continuation of each pair); every later frame ``a + 2`` is matched to the
    tracks fixed so far by ``D^a(track(a), track(a+1), gamma)``, each by
    :func:`scipy.optimize.linear_sum_assignment`.

    Returns
    -------
    ndarray of int, shape (N_T, N_P)
    """
    D, n = _check_square(D, n_targets)
    n_p = D.shape[0] + 2
    A = np.empty((n, n_p), dtype=np.intp)
    A[:, 0] = np.arange(n)
    _, A[:, 1] = linear_sum_assignment(D[0].min(axis=2))
    for a in range(n_p - 2):
        _, A[:, a + 2] = linear_sum_assignment(D[a][A[:, a], A[:, a + 1], :])
    return A


def coordinate_descent_assignment(D: np.ndarray, initial: np.ndarray | None = None,
                                  n_targets: int | None = None, max_rounds: int = 100) -> tuple[np.ndarray, float]:
    """Block-coordinate descent on the summed eq. (7) cost (a linear-assignment heuristic).

    With all frames but ``a`` fixed, the cost is linear in frame ``a``'s assignment
    (the three triples containing ``a``), so each frame is re-solved exactly by
    :func:`scipy.optimize.linear_sum_assignment`; rounds over all frames repeat until the
    cost stops decreasing. Starts from :func:`greedy_assignment` unless ``initial`` is given.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
    cost : float
    """
    D, n = _check_square(D, n_targets)
    n_q = D.shape[0]
    n_p = n_q + 2
    A = greedy_assignment(D) if initial is None else np.array(initial, dtype=np.intp, copy=True)
    if A.shape != (n, n_p):
        raise ValueError(f"initial must have shape ({n}, {n_p}), got {A.shape}")
    max_rounds = _check_int(max_rounds, "max_rounds", 1)
    cost = assignment_cost(A, D)
    for _ in range(max_rounds):
        for f in range(n_p):
            M = np.zeros((n, n))
            if f + 2 < n_p:
                M += D[f][:, A[:, f + 1], A[:, f + 2]].T
            if 1 <= f <= n_p - 2:
                M += D[f - 1][A[:, f - 1], :, A[:, f + 1]]
            if f >= 2:
                M += D[f - 2][A[:, f - 2], A[:, f - 1], :]
            _, A[:, f] = linear_sum_assignment(M)
        new = assignment_cost(A, D)
        if new >= cost - 1e-12:
            cost = min(cost, new)
            break
        cost = new
    return A, cost


# ----------------------------------------------------------------------------- experiments
def simulate(rng: np.random.Generator, n_datasets: int, n_starts: int, noise_percent: float, *,
             noise_law: str = "ball", n_targets: int = 4, n_frames: int = 5, unit: float = 256.0,
             coefficients: Coefficients | Sequence[float] | None = None, offset: float = PAPER_OFFSET,
             max_iter: int = 50, mode: str = "serial", self_coupling: bool = True, exact_energy: bool = False,
             perturbation: float = 0.1, references: bool = True,
             exact_max_targets: int = 4) -> dict[str, np.ndarray]:
    """The Sec. VI experiment: ``n_datasets`` track sets, ``n_starts`` net starts each.

    Data sets come from :func:`projtrack.scenes.tracks3d.make_tracks` (``N_M = N_T``);
    positions are divided by ``unit`` before eq. (7) (the paper does not say in which
    unit D was computed; ``unit = 256`` measures positions in field widths). Every net
    starts from :func:`initial_states` and runs :func:`run_net`. All nets are run as one
    vectorized batch.

    Parameters
    ----------
    rng : numpy.random.Generator
    n_datasets, n_starts : int
        Number of track sets and of random net starts per set (>= 1).
    noise_percent : float
        Position noise ``n >= 0`` (% of the distance from the centre), see
        :func:`projtrack.scenes.tracks3d.perturb`.
    noise_law : {"ball", "radial", "coordinate"}, default "ball"
        How the noise is drawn, see :func:`projtrack.scenes.tracks3d.perturb`.
    n_targets, n_frames, unit, coefficients, offset, max_iter, mode, self_coupling, exact_energy, perturbation
        As in :func:`projtrack.scenes.tracks3d.make_tracks`, :func:`initial_states` and
        :func:`run_net`.
    references : bool
        Also solve every data set with the reference methods.
    exact_max_targets : int
        Largest ``N_T`` for which the exact optimum is computed.

    Returns
    -------
    dict of arrays
        Per run (length ``n_datasets * n_starts``, data set major): ``dataset``, ``status``,
        ``iterations``, ``converged``, ``correct`` (converged and correct assignment,
        the paper's success). Per data set (length ``n_datasets``), when ``references``:
        ``optimal_correct``, ``optimal_cost``, ``true_cost``, ``nn_correct``
        (:func:`nearest_neighbour_assignment`), ``greedy_correct``, ``cd_correct``
        (:func:`coordinate_descent_assignment`); the exact optimum only for
        ``N_T <= exact_max_targets`` (NaN otherwise; it costs about 0.5 s per data set at
        ``N_T = 5``).
    """
    from projtrack.scenes.tracks3d import make_tracks

    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    n_datasets = _check_int(n_datasets, "n_datasets", 1)
    n_starts = _check_int(n_starts, "n_starts", 1)
    if not (np.isfinite(unit) and unit > 0):
        raise ValueError(f"unit must be > 0, got {unit}")
    if isinstance(noise_percent, bool) or not isinstance(noise_percent, (int, float, np.integer, np.floating)):
        raise TypeError(f"noise_percent must be a number, got {type(noise_percent).__name__}")
    if not (np.isfinite(noise_percent) and noise_percent >= 0):
        raise ValueError(f"noise_percent must be a finite number >= 0, got {noise_percent}")
    scenes = [make_tracks(rng, n_targets, n_frames, noise_percent=noise_percent, noise_law=noise_law)
              for _ in range(n_datasets)]
    pos = np.stack([s.positions for s in scenes]) / unit
    D = distance_tensor(pos)
    X0 = initial_states(rng, n_datasets * n_starts, n_targets, n_targets, n_frames, perturbation)
    res = run_net(np.repeat(D, n_starts, axis=0), X0, coefficients, offset=offset, max_iter=max_iter,
                  mode=mode, self_coupling=self_coupling, exact_energy=exact_energy)
    dataset = np.repeat(np.arange(n_datasets), n_starts)
    correct = np.array([res.status[k] == "converged" and
                        is_correct_assignment(states_to_assignment(res.states[k]), scenes[dataset[k]].labels)
                        for k in range(len(dataset))])
    out: dict[str, np.ndarray] = {
        "dataset": dataset, "status": res.status, "iterations": res.iterations,
        "converged": res.converged, "correct": correct,
    }
    if references:
        opt_ok, opt_cost, true_cost, nn_ok, gr_ok, cd_ok = [], [], [], [], [], []
        for s, d, r in zip(scenes, D, pos):
            truth = np.argsort(s.labels, axis=1).T  # measurement of target i in frame a
            true_cost.append(assignment_cost(truth, d))
            if n_targets <= exact_max_targets:
                A, c = optimal_assignment(d)
                opt_ok.append(is_correct_assignment(A, s.labels))
                opt_cost.append(c)
            else:
                opt_ok.append(np.nan)
                opt_cost.append(np.nan)
            nn_ok.append(is_correct_assignment(nearest_neighbour_assignment(r), s.labels))
            gr_ok.append(is_correct_assignment(greedy_assignment(d), s.labels))
            cd_ok.append(is_correct_assignment(coordinate_descent_assignment(d)[0], s.labels))
        out.update(optimal_correct=np.array(opt_ok, dtype=float), optimal_cost=np.array(opt_cost),
                   true_cost=np.array(true_cost), nn_correct=np.array(nn_ok),
                   greedy_correct=np.array(gr_ok), cd_correct=np.array(cd_ok))
    return out

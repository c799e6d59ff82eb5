"""The binary neurons of eq. (4): random starts, serial or parallel sweeps of a batch of nets."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from projtrack._validation import as_bool, as_int, as_real, as_rng

from ._checks import _check_D, _check_states
from .coefficients import PAPER_OFFSET, Coefficients, _as_coefficients
from .cubic_energy import energy_gradient

__all__ = ["NetResult", "initial_states", "run_net", "update_inputs"]


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
    """Randomly perturbed all-equal start (Section VI, after Hopfield and Tank).

    The all-equal state gives every neuron ``1 / N_M`` (every measurement equally likely
    for every target, so that each frame sums to ``N_T``); each neuron is multiplied by
    ``1 + u`` with ``u`` uniform in ``[-perturbation, perturbation]`` (Hopfield & Tank used
    10%). The first sweep thresholds these analog values to binary ones.

    Parameters
    ----------
    rng : numpy.random.Generator
        Randomness of the perturbation.
    n_runs : int
        Number of starts (nets run side by side).
    n_targets, n_measurements, n_frames : int
        ``N_T``, ``N_M`` and ``N_P``.
    perturbation : float, default 0.1
        Half-width of the relative uniform perturbation.

    Returns
    -------
    ndarray, shape (n_runs, N_T, N_M, N_P)
    """
    rng = as_rng(rng)
    n_runs = as_int(n_runs, "n_runs", 0)
    n_targets = as_int(n_targets, "n_targets", 1)
    n_measurements = as_int(n_measurements, "n_measurements", 1)
    n_frames = as_int(n_frames, "n_frames", 3)
    if n_measurements < n_targets:
        raise ValueError(f"n_measurements ({n_measurements}) must be >= n_targets ({n_targets})")
    perturbation = as_real(perturbation, "perturbation", 0, 1, high_open=True)
    shape = (n_runs, n_targets, n_measurements, n_frames)
    return (1.0 + rng.uniform(-perturbation, perturbation, shape)) / n_measurements


def run_net(D: np.ndarray, X0: np.ndarray, coefficients: Coefficients | Sequence[float] | None = None, *,
            offset: float = PAPER_OFFSET, max_iter: int = 50, mode: str = "serial",
            self_coupling: bool = True, exact_energy: bool = False, record: bool = False) -> NetResult:
    """Evolve binary neurons by equations (4) and (9) until convergence, a cycle or
    ``max_iter`` steps.

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
    record = as_bool(record, "record")
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
    offset = as_real(offset, "offset")
    max_iter = as_int(max_iter, "max_iter", 1)
    if mode not in ("serial", "parallel"):
        raise ValueError(f"mode must be 'serial' or 'parallel', got {mode!r}")
    as_bool(self_coupling, "self_coupling")
    as_bool(exact_energy, "exact_energy")
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
    """The quantity each neuron compares with the offset, under three readings of equation
    (4).

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
    as_bool(self_coupling, "self_coupling")
    as_bool(exact_energy, "exact_energy")
    c = _as_coefficients(coefficients)
    g = energy_gradient(X, D, c)
    X = np.asarray(X, dtype=float)
    if exact_energy:
        return g - 2 * c.A3 * X + c.A3
    if not self_coupling:
        return g - 2 * c.A3 * X
    return g

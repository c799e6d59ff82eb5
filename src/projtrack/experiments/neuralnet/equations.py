"""Eq. (9) against eq. (8) as printed, and the connection matrices of eq. (10) (Sec. IV).

Term 3 of eq. (8) is printed ``A3 sum_i (sum_alpha X_{i alpha a} - N_T)^2``: the frame index
``a`` is left free, and the square is taken per target. Its derivative is
``2 A3 (sum_beta X_{i beta a} - N_T)``, not eq. (9)'s ``2 A3 (sum_j sum_beta X_{j beta a} - N_T)``,
and it is smallest when every target holds ``N_T`` measurements in every frame, against
condition 4 of Sec. III. The text ("``sum_i sum_alpha X_{i alpha a}`` for a fixed time ``a`` ...
equals ``N_T``") and eq. (9) both need ``A3 sum_a (sum_i sum_alpha X_{i alpha a} - N_T)^2``, which
:func:`projtrack.neuralnet.energy` implements.

* :func:`term3_printed`, :func:`term3_read`: the two forms (the printed one summed over the
  free ``a``, the only way to make it a number);
* :func:`term3_eq9`: term 3 of eq. (9);
* :func:`central_differences`: the derivative of any energy by central differences;
* :func:`eq8_term3_check`: the three compared on one state;
* :func:`connection_check`: eq. (10) and its two companions built for a net, checked against
  terms 1-3 of eq. (9).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.neuralnet import PAPER_COEFFICIENTS, connection_matrices, energy_gradient

__all__ = ["term3_printed", "term3_read", "term3_eq9", "central_differences", "eq8_term3_check",
           "connection_check"]


def _states(X: object) -> np.ndarray:
    X = as_array(X, "X")
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    return X


def term3_printed(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> float:
    """Term 3 of eq. (8) as printed, summed over the frame index it leaves free:
    ``A3 sum_a sum_i (sum_alpha X_{i alpha a} - N_T)^2``."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return float(A3 * ((X.sum(axis=1) - X.shape[0]) ** 2).sum())


def term3_read(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> float:
    """Term 3 as the text and eq. (9) need it: ``A3 sum_a (sum_i sum_alpha X_{i alpha a} - N_T)^2``."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return float(A3 * ((X.sum(axis=(0, 1)) - X.shape[0]) ** 2).sum())


def term3_eq9(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> np.ndarray:
    """Term 3 of eq. (9): ``2 A3 (sum_j sum_beta X_{j beta a} - N_T)`` for every neuron."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return np.broadcast_to(2 * A3 * (X.sum(axis=(0, 1)) - X.shape[0]), X.shape).copy()


def central_differences(f: Callable[[np.ndarray], float], X: np.ndarray, h: float = 1e-4) -> np.ndarray:
    """``(f(X + h e_k) - f(X - h e_k)) / 2h`` for every entry ``k`` of ``X``."""
    if not callable(f):
        raise TypeError("f must be callable")
    X = as_array(X, "X")
    h = as_real(h, "h", 0.0, low_open=True)
    out = np.zeros_like(X)
    for k in np.ndindex(X.shape):
        p, m = X.copy(), X.copy()
        p[k] += h
        m[k] -= h
        out[k] = (f(p) - f(m)) / (2 * h)
    return out


def eq8_term3_check(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3, h: float = 1e-4) -> dict[str, float]:
    """Term 3 of eq. (9) against the derivative of both forms of term 3 of eq. (8), on one state.

    Term 3 is quadratic, so central differences are exact up to rounding.

    Returns
    -------
    dict
        ``read``: largest ``|d term3_read / dX - term3_eq9|``; ``printed``: the same for
        :func:`term3_printed`.
    """
    X = _states(X)
    want = term3_eq9(X, A3)
    return {"read": float(np.abs(central_differences(lambda Y: term3_read(Y, A3), X, h) - want).max()),
            "printed": float(np.abs(central_differences(lambda Y: term3_printed(Y, A3), X, h) - want).max())}


def connection_check(n_targets: int, n_measurements: int, n_frames: int, rng: np.random.Generator
                     ) -> dict[str, float | int]:
    """Eq. (10) and its companions for one net, against terms 1-3 of eq. (9).

    Builds ``T1``, ``T2``, ``T3`` (:func:`projtrack.neuralnet.connection_matrices`) and
    compares ``(2 A1 T1 + 2 A2 T2 + 2 A3 T3) x - 2 A3 N_T`` with terms 1-3 of eq. (9)
    (:func:`projtrack.neuralnet.energy_gradient` with ``A4 = 0``) on a random binary state
    drawn from ``rng``, and evaluates it on an assignment state (every target one measurement
    in every frame), whose active neurons it leaves at zero.

    Returns
    -------
    dict
        ``neurons`` (size of ``x``), ``T1 ones``, ``T2 ones``, ``T3 ones``, ``max difference``
        (largest ``|T x - 2 A3 N_T - terms 1-3|``), ``assignment ones`` (active neurons of an
        assignment state) and ``assignment, active max`` (largest ``|T x - 2 A3 N_T|`` over
        its active neurons).
    """
    n_t = as_int(n_targets, "n_targets", minimum=1)
    n_m = as_int(n_measurements, "n_measurements", minimum=n_t)
    n_p = as_int(n_frames, "n_frames", minimum=3)
    rng = as_rng(rng)
    c = PAPER_COEFFICIENTS
    T1, T2, T3 = connection_matrices(n_t, n_m, n_p)
    T = 2 * c.A1 * T1.astype(float) + 2 * c.A2 * T2.astype(float) + 2 * c.A3 * T3.astype(float)
    D0 = np.zeros((n_p - 2, n_m, n_m, n_m))
    x = rng.integers(0, 2, n_t * n_m * n_p).astype(float)
    want = energy_gradient(x.reshape(n_t, n_m, n_p), D0, (c.A1, c.A2, c.A3, 0.0)).reshape(-1)
    X = np.zeros((n_t, n_m, n_p))
    for a in range(n_p):
        X[np.arange(n_t), rng.permutation(n_m)[:n_t], a] = 1.0
    xa = X.reshape(-1)
    ya = T @ xa - 2 * c.A3 * n_t
    return {"neurons": int(x.size), "T1 ones": int(T1.sum()), "T2 ones": int(T2.sum()), "T3 ones": int(T3.sum()),
            "max difference": float(np.abs(T @ x - 2 * c.A3 * n_t - want).max()),
            "assignment ones": int(xa.sum()), "assignment, active max": float(np.abs(ya[xa == 1]).max())}

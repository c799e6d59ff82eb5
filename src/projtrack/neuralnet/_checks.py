"""Argument checks that only the neural-net modules need (distance tensors, states)."""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_int


def _check_D(D: object, batched: bool = False) -> np.ndarray:
    D = as_array(D, "D")
    if D.ndim not in ((4, 5) if batched else (4,)):
        raise ValueError(f"D must have shape {'(B,) ' if batched else ''}(N_P - 2, N_M, N_M, N_M), got {D.shape}")
    if not (D.shape[-1] == D.shape[-2] == D.shape[-3]) or D.shape[-4] < 1 or D.shape[-1] < 1:
        raise ValueError(f"D must have shape (..., N_P - 2, N_M, N_M, N_M) with N_P >= 3, got {D.shape}")
    if np.any(D < 0):
        raise ValueError("D must be >= 0 (it is a norm, eq. (7))")
    return D


def _check_states(X: object, D: np.ndarray, n_targets: int | None = None) -> np.ndarray:
    X = as_array(X, "X")
    n_frames = D.shape[-4] + 2
    n_meas = D.shape[-1]
    if X.ndim < 3 or X.shape[-2:] != (n_meas, n_frames):
        raise ValueError(
            f"X must have shape (..., N_T, N_M, N_P) = (..., N_T, {n_meas}, {n_frames}) to match D, got {X.shape}")
    if n_targets is not None and X.shape[-3] != n_targets:
        raise ValueError(f"X must have N_T = {n_targets} targets, got {X.shape[-3]}")
    if X.shape[-3] > n_meas:
        raise ValueError(f"N_T = {X.shape[-3]} targets need at least as many measurements, got N_M = {n_meas}")
    return X


def _check_square(D: np.ndarray, n_targets: int | None) -> tuple[np.ndarray, int]:
    D = _check_D(D)
    n_m = D.shape[1]
    n_t = n_m if n_targets is None else as_int(n_targets, "n_targets", 1)
    if n_t != n_m:
        raise ValueError(f"the reference assignments need N_T == N_M, got N_T = {n_t}, N_M = {n_m}")
    return D, n_t

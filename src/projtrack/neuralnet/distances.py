"""Measurements and the distance tensor of eq. (7): zero-vector padding and ``D``."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack._validation import as_int

__all__ = ["pad_measurements", "distance_tensor"]


def pad_measurements(frames: Sequence[np.ndarray], n_measurements: int | None = None,
                     n_targets: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Pad frames with zero vectors to :math:`N_M` measurements each (Section IV).

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
        n_targets = as_int(n_targets, "n_targets", 1)
        largest = max(largest, n_targets)
    if n_measurements is None:
        n_measurements = largest
    n_measurements = as_int(n_measurements, "n_measurements", 1)
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
    """The distance tensor of equation (7) for every three consecutive frames.

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

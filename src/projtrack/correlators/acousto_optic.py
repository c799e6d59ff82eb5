"""Numerical models of the multichannel acousto-optic correlators of Figs. 8 and 9 (Sec. IV)."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from projtrack._validation import as_array, as_int

from ._checks import as_signal

__all__ = ["space_integrating_correlator", "time_integrating_correlator"]


def space_integrating_correlator(inputs: np.ndarray, references: np.ndarray, *,
                                 carriers: Sequence[int] | None = None, oversample: int = 8) -> np.ndarray:
    """Multichannel acousto-optic space-integrating correlator with frequency multiplexing
    (Figure 8).

    Numerical model of Sec. IV. ``K`` 1-D input signals (e.g. the horizontal and vertical
    projections of one test image) are written on ``K`` carriers of ``carriers[k]``
    cycles per sample and summed into one AO cell at P1; the cell's light amplitude is
    sampled ``oversample`` times per signal sample and travels one sample per time step.
    At P2, channel ``n`` holds a fixed mask: the sum over ``k`` of the time-reversed
    reference ``references[n, k]`` on the conjugate carrier. Detector ``n`` at P3
    integrates the product over the aperture. Products of different carriers integrate
    to zero over each sample (they are diffracted off the detector), so detector ``n``
    receives the **sum over k of the correlations** of input ``k`` with reference
    ``(n, k)``, divided here by ``oversample``.

    Parameters
    ----------
    inputs : array_like, shape (K, L)
        Bipolar input signals.
    references : array_like, shape (N, K, M)
        Reference signals of N channels, K per channel.
    carriers : sequence of K distinct ints, optional
        Carrier frequencies in cycles per sample (default ``1, 2, ..., K``); their
        differences must not be multiples of ``oversample``.
    oversample : int, default 8
        Optical samples per signal sample.

    Returns
    -------
    numpy.ndarray, shape (N, L + M - 1)
        Detector outputs at the time steps ``t = 0 .. L + M - 2``; equal to
        ``sum_k correlate1d(inputs[k], references[n, k])``.
    """
    # converted first so that text input stays a ValueError, as np.asarray(..., float) raises
    x = as_array(np.asarray(inputs, dtype=float), "inputs", ndim=2, allow_empty=False)
    h = as_array(np.asarray(references, dtype=float), "references", ndim=3, allow_empty=False)
    if h.shape[1] != x.shape[0]:
        raise ValueError(f"references must have shape (N, K={x.shape[0]}, M), got {h.shape}")
    K, L = x.shape
    N, _, M = h.shape
    oversample = as_int(oversample, "oversample", minimum=1)
    car = np.arange(1, K + 1) if carriers is None else np.asarray(carriers)
    if car.shape != (K,) or car.dtype.kind not in "iu":
        raise ValueError(f"carriers must be {K} integers (cycles per sample)")
    diff = car[:, None] - car[None, :]
    if np.any((diff % oversample == 0) & ~np.eye(K, dtype=bool)):
        raise ValueError("carriers must differ by a non-multiple of oversample")
    if np.any(2 * np.abs(car) >= oversample):
        raise ValueError("oversample must exceed twice the largest carrier (no aliasing)")
    xi = np.arange(M * oversample) / oversample  # aperture positions in samples
    cell = np.floor(xi).astype(int)
    mask = np.einsum("nkm,km->nm", h[:, :, ::-1][:, :, cell],
                     np.exp(-2j * np.pi * car[:, None] * xi[None, :]))  # (N, M*oversample)
    T = L + M - 1
    padded = np.concatenate([np.zeros((K, M - 1)), x, np.zeros((K, M - 1))], axis=1)
    carrier = np.exp(2j * np.pi * car[:, None] * xi[None, :])  # (K, M*oversample)
    # at time step t the cell holds s_k(t - xi) on its carrier exp(2 pi i c_k (xi - t)),
    # and exp(-2 pi i c_k t) = 1 at integer t: one row of `field` per time step
    samples = padded[:, np.arange(T)[:, None] + (M - 1) - cell[None, :]]  # (K, T, M*oversample)
    field = np.einsum("ktm,km->tm", samples, carrier)
    return np.real(field @ mask.T).T / oversample


def time_integrating_correlator(test: np.ndarray, references: np.ndarray, *, bias: float | None = None) -> np.ndarray:
    """Multichannel acousto-optic time-integrating correlator (Figure 9), with intensity
    bias.

    Numerical model of Sec. IV. Point modulator ``n`` at P1 is driven by reference
    ``references[n](t)``; the test projection ``test(t)`` travels through one AO cell at
    P2 (delayed so that all lags fit the aperture); P3 is an ``(N + 1) x (L + M - 1)``
    detector array that accumulates light **intensity** over time. Optical intensities
    cannot be negative, so both signals ride on a ``bias`` (default: the largest absolute
    value of either); an extra reference-free row measures the bias terms, which are
    subtracted to recover the bipolar correlations.

    Parameters
    ----------
    test : array_like, 1-D
        The test projection, length ``L``.
    references : array_like, shape (N, M)
        One reference projection per row.
    bias : float or None, keyword-only
        Intensity bias added to both signals; default the largest absolute value of either.

    Returns
    -------
    numpy.ndarray, shape (N, L + M - 1)
        Equal to ``correlate1d(test, references[n])`` for each channel ``n``.
    """
    s = as_signal(test, "test")
    h = as_array(np.asarray(references, dtype=float), "references", ndim=2, allow_empty=False)
    N, M = h.shape
    L = len(s)
    b = float(max(np.abs(s).max(), np.abs(h).max())) if bias is None else float(bias)
    if not np.isfinite(b) or b < max(np.abs(s).max(), np.abs(h).max()):
        raise ValueError("bias must be finite and at least the largest |signal| (intensities are >= 0)")
    X = L + M - 1  # detector columns = AO-cell positions
    T = L + 2 * M - 2  # time steps
    # P1 drives: reference n delayed by L - 1 steps; row N is the bias-only channel
    drive = np.zeros((N + 1, T))
    drive[:N, L - 1:L - 1 + M] = h
    cell_in = np.zeros(T + X)
    cell_in[X - 1:X - 1 + L] = s  # test enters the cell at position 0 at time t
    acc = np.zeros((N + 1, X))
    for t in range(T):
        window = cell_in[t + X - 1 - np.arange(X)]  # cell position x holds test(t - x)
        acc += (b + drive[:, t])[:, None] * (b + window)[None, :]  # intensity >= 0
    ref_sums = drive[:N].sum(axis=1)
    out = acc[:N] - acc[N][None, :] - b * ref_sums[:, None]
    # column x holds sum_u h[u] s[u + L - 1 - x], the full-correlation lag m = L + M - 2 - x
    return out[:, ::-1]

"""Output SNR of 2-D and projection correlations under white noise (Sec. II.C), by Monte Carlo.

* :func:`snr_signals`: the test signals of the SNR page (uniform, single pixel, random
  +-1 texture, and the letter C at N = 32);
* :func:`output_snr_study`: 2-D and projection output SNR of a matched filter for one
  signal, their ratio (the SNR loss of projections) against its closed form, and the
  input SNRs of Sec. II.C.
"""

from __future__ import annotations

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng, as_square
from projtrack.scenes import letters

__all__ = ["snr_signals", "output_snr_study"]


def snr_signals(n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Test signals of size ``n x n``: uniform (the paper's "white" signal), a single
    centre pixel, a random +-1 texture (drawn from ``rng``) and, for ``n = 32``, the letter C."""
    n = as_int(n, "n", minimum=1)
    rng = as_rng(rng)
    out = {"uniform (paper's white)": np.ones((n, n)),
           "single pixel": np.zeros((n, n)),
           "random +-1 texture": rng.choice([-1.0, 1.0], size=(n, n))}
    out["single pixel"][n // 2, n // 2] = 1.0
    if n == 32:
        out["letter C"] = letters.render_letter("C")
    return out


def _batch(rng, s, n_draws, sigma):
    # noise outputs at the peak location for a batch of noise images
    noise = rng.normal(0.0, sigma, size=(n_draws,) + s.shape)
    out2d = np.einsum("kij,ij->k", noise, s)
    out1d = noise.sum(axis=1) @ s.sum(axis=0)
    return np.column_stack([out2d, out1d])


def output_snr_study(signal: np.ndarray, n_batches: int, batch_size: int, rng: np.random.Generator,
                     sigma: float = 1.0) -> dict[str, float]:
    """Output SNR of the matched 2-D and vertical-projection correlations of an ``N x N`` signal.

    The noise output at the correlation peak is drawn for ``n_batches * batch_size``
    white Gaussian noise images of standard deviation ``sigma`` (batches through
    :func:`projtrack.montecarlo.run`); the output SNR is the noise-free peak over the
    standard deviation of that output.

    Returns
    -------
    dict
        ``"SNR_o 2-D"``, ``"SNR_o projection"``, ``"loss factor"`` (their ratio),
        ``"loss, closed form"`` (``sqrt(N E_s / sum p_s^2)``), ``"sqrt(N)"`` (the worst
        case), ``"SNR_i 2-D"``, ``"SNR_i projection"`` (input SNRs of Sec. II.C) and
        ``"SNR_i ratio"``.
    """
    s = as_square(signal, "signal")
    n = s.shape[0]
    n_batches = as_int(n_batches, "n_batches", minimum=1)
    batch_size = as_int(batch_size, "batch_size", minimum=1)
    sigma = as_real(sigma, "sigma", 0.0, low_open=True)
    if n_batches * batch_size < 2:
        raise ValueError("at least 2 noise draws are needed for a standard deviation")
    if not np.any(s.sum(axis=0)):
        raise ValueError("signal must have a nonzero vertical projection")
    draws = np.concatenate(montecarlo.run(_batch, n_batches, as_rng(rng), s, batch_size, sigma))
    peak2d = float(np.sum(s * s))
    peak1d = float(np.sum(s.sum(axis=0) ** 2))
    snr2d, snr1d = peak2d / draws[:, 0].std(), peak1d / draws[:, 1].std()
    proj = s.sum(axis=0)
    snri_2d = np.sqrt(np.mean(s * s)) / sigma
    snri_1d = np.sqrt(np.mean(proj * proj)) / (np.sqrt(n) * sigma)
    return {"SNR_o 2-D": snr2d, "SNR_o projection": snr1d, "loss factor": snr2d / snr1d,
            "loss, closed form": float(np.sqrt(n * np.sum(s * s) / np.sum(s.sum(axis=0) ** 2))),
            "sqrt(N)": np.sqrt(n), "SNR_i 2-D": snri_2d, "SNR_i projection": snri_1d,
            "SNR_i ratio": snri_1d / snri_2d}

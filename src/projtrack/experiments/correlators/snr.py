"""Output SNR of 2-D and projection correlations under white noise (Sec. II.C), by Monte Carlo.

* :func:`snr_signals`: the test signals of the SNR page (uniform, single pixel, random
  +-1 texture, and the letter C at N = 32);
* :func:`output_snr_study`: 2-D and projection output SNR of a matched filter for one
  signal, their ratio (the SNR loss of projections) against its closed form, and the
  input SNRs of Sec. II.C;
* :func:`loss_closed_form` and :func:`input_snr_ratio`: the SNR loss and the input-SNR gain
  of a projection, in closed form;
* :func:`texture_losses`: the closed-form loss of many random +-1 textures;
* :func:`signal_1d_study`: output SNR of a 1-D signal correlation (Sec. II.C);
* :func:`combine_study`: output SNR when several projection correlations of one noisy
  image are added, and how correlated their noise terms are.
"""

from __future__ import annotations

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_array, as_choice, as_int, as_real, as_rng, as_square
from projtrack.scenes import letters

__all__ = ["snr_signals", "output_snr_study", "loss_closed_form", "input_snr_ratio", "texture_losses",
           "signal_1d_study", "combine_study"]


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


def loss_closed_form(signal: np.ndarray) -> float:
    """SNR loss of the vertical projection correlation against the 2-D one, ``sqrt(N E_s / sum p_s^2)``.

    For a matched filter and white noise over all ``N`` rows of an ``N x M`` signal ``s``
    (``E_s`` its energy, ``p_s`` its vertical projection). By Cauchy-Schwarz it is at least 1;
    for a nonnegative signal ``sum p_s^2 >= E_s`` and it is at most ``N^1/2``, a bound a
    signed signal can exceed.
    """
    s = as_array(signal, "signal", ndim=2, allow_empty=False)
    p2 = float(np.sum(s.sum(axis=0) ** 2))
    if p2 == 0:
        raise ValueError("signal must have a nonzero vertical projection")
    return float(np.sqrt(s.shape[0] * np.sum(s * s) / p2))


def input_snr_ratio(signal: np.ndarray) -> float:
    """Input SNR of the vertical projection over that of the 2-D image (Sec. II.C definitions).

    SNR_i is the root mean square signal per pixel over the noise standard deviation; a
    projection bin of an ``N``-row image carries noise ``N^1/2 sigma``. The ratio is
    ``sqrt(sum p_s^2 / E_s)``: ``N^1/2`` for a constant image, 1 for a single pixel, and at
    least 1 for any nonnegative image.
    """
    s = as_array(signal, "signal", ndim=2, allow_empty=False)
    e = float(np.sum(s * s))
    if e == 0:
        raise ValueError("signal must not be zero")
    return float(np.sqrt(np.sum(s.sum(axis=0) ** 2) / e))


def _texture_loss(rng, n):
    return loss_closed_form(rng.choice([-1.0, 1.0], size=(n, n)))


def texture_losses(n: int, n_textures: int, rng: np.random.Generator) -> np.ndarray:
    """Closed-form losses (:func:`loss_closed_form`) of ``n_textures`` random +-1 textures ``n x n``.

    Draws run through :func:`projtrack.montecarlo.run`; a texture whose vertical projection
    is zero everywhere is redrawn.
    """
    n = as_int(n, "n", minimum=2)
    n_textures = as_int(n_textures, "n_textures", minimum=1)

    def draw(r, size):
        while True:
            s = r.choice([-1.0, 1.0], size=(size, size))
            if np.any(s.sum(axis=0)):
                return loss_closed_form(s)

    return np.array(montecarlo.run(draw, n_textures, as_rng(rng), n))


def _signal_1d_batch(rng, n, n_draws, sigma):
    return rng.normal(0.0, sigma, size=(n_draws, n)).sum(axis=1)  # matched filter of n ones, at the peak


def signal_1d_study(n: int, n_batches: int, batch_size: int, rng: np.random.Generator,
                    sigma: float = 1.0) -> dict[str, float]:
    """Output SNR of a 1-D correlation of ``n`` unit samples in white Gaussian noise (Sec. II.C).

    The signal's matched-filter peak is ``n``; the noise output at the peak is drawn
    ``n_batches * batch_size`` times (batches through :func:`projtrack.montecarlo.run`).

    Returns
    -------
    dict
        ``"SNR_o 1-D signal"`` (peak over the standard deviation of the noise output),
        ``"theory"`` (``n^1/2 / sigma``) and ``"SNR_i"`` (``1 / sigma``).
    """
    n = as_int(n, "n", minimum=1)
    n_batches = as_int(n_batches, "n_batches", minimum=1)
    batch_size = as_int(batch_size, "batch_size", minimum=1)
    sigma = as_real(sigma, "sigma", 0.0, low_open=True)
    if n_batches * batch_size < 2:
        raise ValueError("at least 2 noise draws are needed for a standard deviation")
    out = np.concatenate(montecarlo.run(_signal_1d_batch, n_batches, as_rng(rng), n, batch_size, sigma))
    return {"SNR_o 1-D signal": float(n / out.std()), "theory": float(np.sqrt(n) / sigma), "SNR_i": 1.0 / sigma}


#: Sums that give each pixel's index along a projection: angle -> function of (row, col) arrays.
_LINES = {0: lambda r, c: c, 90: lambda r, c: r, 45: lambda r, c: c - r, 135: lambda r, c: c + r}


def _line_sums(x: np.ndarray, angle: int) -> np.ndarray:
    r, c = np.indices(x.shape[-2:])
    key = _LINES[angle](r, c).ravel()
    key = key - key.min()
    flat = x.reshape(x.shape[:-2] + (-1,))
    out = np.zeros(x.shape[:-2] + (int(key.max()) + 1,))
    np.add.at(out, (..., key), flat) if flat.ndim > 1 else np.add.at(out, key, flat)
    return out


def _combine_batch(rng, s, angles, n_draws, sigma):
    noise = rng.normal(0.0, sigma, size=(n_draws,) + s.shape)
    return np.stack([_line_sums(noise, a) @ _line_sums(s, a) for a in angles], axis=1)


def combine_study(signal: np.ndarray, angles: tuple[int, ...], n_batches: int, batch_size: int,
                  rng: np.random.Generator, sigma: float = 1.0) -> dict[str, object]:
    """Output SNR of single projection correlations and of their sum, for one noisy image.

    All projection correlations (matched filters, at the peak lag) see the **same** white
    Gaussian noise image; the projections are exact line sums at 0, 90, 45 or 135 degrees.
    The sum adds the peaks and the noise outputs of all ``angles``.

    Returns
    -------
    dict
        ``"single"``: SNR_o of each angle (list); ``"sum"``: SNR_o of the sum;
        ``"noise correlation"``: the correlation coefficient matrix of the noise outputs
        (from the draws); ``"noise correlation, closed form"``: ``sum_i sum_j p_i q_j /
        sqrt(N_p sum p^2 N_q sum q^2)`` generalized to line sums, as a matrix.
    """
    s = as_array(signal, "signal", ndim=2, allow_empty=False)
    angles = tuple(as_choice(a, "angles", tuple(_LINES)) for a in angles)
    if not angles:
        raise ValueError("angles must not be empty")
    n_batches = as_int(n_batches, "n_batches", minimum=1)
    batch_size = as_int(batch_size, "batch_size", minimum=1)
    sigma = as_real(sigma, "sigma", 0.0, low_open=True)
    if n_batches * batch_size < 2:
        raise ValueError("at least 2 noise draws are needed for a standard deviation")
    draws = np.concatenate(montecarlo.run(_combine_batch, n_batches, as_rng(rng), s, angles, batch_size, sigma))
    peaks = np.array([float(np.sum(_line_sums(s, a) ** 2)) for a in angles])
    # closed form: the noise output of angle a is sum_pixels n(x) w_a(x), w_a = the line sum of s through x
    r, c = np.indices(s.shape)
    weights = []
    for a in angles:
        key = _LINES[a](r, c)
        weights.append(_line_sums(s, a)[key - key.min()])
    w = np.array([x.ravel() for x in weights])
    cov = w @ w.T
    closed = cov / np.sqrt(np.outer(np.diag(cov), np.diag(cov)))
    return {"single": list(peaks / draws.std(axis=0)), "sum": float(peaks.sum() / draws.sum(axis=1).std()),
            "noise correlation": np.corrcoef(draws.T) if len(angles) > 1 else np.ones((1, 1)),
            "noise correlation, closed form": closed}

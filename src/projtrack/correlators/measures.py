"""Correlation-plane measures: PSR, Eq. (5b), and SNR, Eq. (5a), with the windows of Sec. III.A."""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_choice, as_int, as_odd_window, as_real

from ._checks import as_plane

__all__ = ["psr", "snr", "snr_db", "peak_stats"]


def _window(arr: np.ndarray, centre: tuple[int, ...], size: int) -> tuple[slice, ...]:
    half = size // 2
    return tuple(slice(max(c - half, 0), min(c - half + size, n)) for c, n in zip(centre, arr.shape))


def psr(plane: np.ndarray, window: int = 11) -> float:
    """Peak-to-sidelobe ratio, Equation (5b), with the window of Section III.A.

    The peak is the largest (signed) value; the sidelobe level is the mean of the
    ``window x window`` region (``window`` samples for a 1-D plane) centred on the peak,
    excluding the peak itself, clipped at the edges of the plane.

    Parameters
    ----------
    plane : array_like, 1-D or 2-D
        Correlation plane (or 1-D correlation).
    window : int, default 11
        Odd side of the window centred on the peak (the paper's 11 x 11 region).

    Raises
    ------
    TypeError
        If ``window`` is not an int.
    ValueError
        If the plane is empty, non-finite, or the window holds only the peak; if
        ``window`` is not a positive odd int (an even window cannot be centred on the
        peak); or if the sidelobe mean is zero (the ratio is undefined).
    """
    arr = as_plane(plane)
    window = as_odd_window(window, "window")
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    region = arr[_window(arr, loc, window)]
    if region.size < 2:
        raise ValueError("window must contain samples besides the peak")
    side = (region.sum() - arr[loc]) / (region.size - 1)
    if side == 0.0:
        raise ValueError("the sidelobe mean is zero: PSR is undefined")
    return float(arr[loc] / side)


def snr(plane: np.ndarray, exclude: int = 32) -> float:
    """Correlation-plane SNR, Equation (5a), with the region of Section III.A.

    Peak value divided by the standard deviation of the plane outside the
    ``exclude x exclude`` region (``exclude`` samples in 1-D) centred on the peak.

    Parameters
    ----------
    plane : array_like, 1-D or 2-D
        Correlation plane (or 1-D correlation).
    exclude : int, default 32
        Side of the excluded region (the paper's 32 x 32). An even region has no centre
        sample: it then covers ``exclude // 2`` samples before the peak and
        ``exclude // 2 - 1`` after it along every axis (for the default, lags -16 to +15
        relative to the peak); an odd one is symmetric. Clipped at the plane's edges.

    Raises
    ------
    TypeError
        If ``exclude`` is not an int.
    ValueError
        If ``exclude`` < 1, if fewer than two samples remain outside the excluded region
        or if their standard deviation is zero.
    """
    arr = as_plane(plane)
    exclude = as_int(exclude, "exclude", minimum=1)
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    mask = np.ones(arr.shape, dtype=bool)
    mask[_window(arr, loc, exclude)] = False
    rest = arr[mask]
    if rest.size < 2:
        raise ValueError(f"the plane has fewer than 2 samples outside the {exclude}-wide region around the peak")
    sd = float(rest.std())
    if sd == 0.0:
        raise ValueError("the plane is constant away from the peak: SNR is undefined")
    return float(arr[loc] / sd)


def snr_db(ratio: float, *, convention: str = "amplitude") -> float:
    """An SNR ratio in decibels.

    Parameters
    ----------
    ratio : float
        A positive ratio, for example the amplitude SNR of Eq. (5a) (peak over the standard
        deviation of the plane).
    convention : {"amplitude", "paper"}
        ``"amplitude"`` (default): ``20 log10(ratio)``, the usual decibels of an amplitude
        ratio. ``"paper"``: ``10 log10(ratio)``, the convention of Casasent and Song, who quote
        10 log10 of their amplitude SNR (26.2 as 14.2 dB, 100.8 as 20 dB, N^1/2 = 8 as 9 dB).

    Returns
    -------
    float
        The ratio in decibels under the chosen convention.
    """
    ratio = as_real(ratio, "ratio", 0.0, low_open=True)
    factors = {"amplitude": 20.0, "paper": 10.0}
    convention = as_choice(convention, "convention", tuple(factors))
    return float(factors[convention] * np.log10(ratio))


def peak_stats(plane: np.ndarray, *, window: int = 11, exclude: int | None = 32) -> dict[str, object]:
    """Peak value and location, PSR (Equation 5b) and, if ``exclude`` is given, SNR
    (Equation 5a).

    Parameters
    ----------
    plane : array_like, 2-D
        A correlation plane.
    window : int, keyword-only, default 11
        Window of the PSR, as :func:`psr`.
    exclude : int or None, keyword-only, default 32
        Region excluded around the peak for the SNR, as :func:`snr`; ``None`` skips the SNR.

    Returns
    -------
    dict
        ``peak`` (float), ``location`` (row, column), ``psr`` and, unless ``exclude`` is
        None, ``snr``.
    """
    arr = as_plane(plane)
    loc = np.unravel_index(int(np.argmax(arr)), arr.shape)
    out: dict[str, object] = {"peak": float(arr[loc]), "location": tuple(int(v) for v in loc),
                              "psr": psr(arr, window)}
    if exclude is not None:
        out["snr"] = snr(arr, exclude)
    return out


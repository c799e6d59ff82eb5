"""Image preparation of Sec. III.B-C: remove the mean (block dc) and scale to unit energy."""

from __future__ import annotations

import numpy as np

from ._checks import as_image

__all__ = ["zero_mean", "normalize_energy"]


def zero_mean(image: np.ndarray) -> np.ndarray:
    """Subtract the mean of an image (block the dc spatial frequency), Section III.B.

    Parameters
    ----------
    image : array_like, 2-D
        A finite real image.

    Returns
    -------
    numpy.ndarray
        The image minus its mean.

    Raises
    ------
    ValueError, TypeError
        If ``image`` is not a non-empty, finite 2-D real array.
    """
    arr = as_image(image, "image")
    return arr - arr.mean()


def normalize_energy(image: np.ndarray) -> np.ndarray:
    """Scale an image to unit energy (sum of squares 1), Section III.C.

    Parameters
    ----------
    image : array_like, 2-D
        A finite real image, not all zero.

    Returns
    -------
    numpy.ndarray
        The image divided by the square root of its energy.

    Raises
    ------
    ValueError
        If the image has zero energy (all zeros), or is not a finite 2-D array.
    """
    arr = as_image(image, "image")
    energy = float(np.sum(arr * arr))
    if energy == 0.0:
        raise ValueError("image has zero energy and cannot be normalized")
    return arr / np.sqrt(energy)


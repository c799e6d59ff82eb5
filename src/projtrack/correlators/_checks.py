"""Argument checks only the correlator modules need (images, signals, stacks, angles, planes).

They are thin wrappers of ``projtrack._validation`` that fix the dimension each kind of
array has; the general checks (ints, windows, shapes, probabilities) come from there.
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_real, only_value_errors


def as_image(x: object, name: str) -> np.ndarray:
    """A finite, non-empty 2-D float image."""
    return as_array(x, name, ndim=2, allow_empty=False)


def as_signal(x: object, name: str) -> np.ndarray:
    """A finite, non-empty 1-D float signal."""
    return as_array(x, name, ndim=1, allow_empty=False)


def as_stack(x: object, name: str) -> np.ndarray:
    """A finite, non-empty stack of images ``(n, H, W)``; one image ``(H, W)`` becomes ``(1, H, W)``."""
    arr = as_array(x, name, ndim=(2, 3), allow_empty=False)
    return arr[None] if arr.ndim == 2 else arr


def as_plane(plane: object, name: str = "plane") -> np.ndarray:
    """A finite, non-empty 1-D or 2-D correlation plane."""
    return as_array(plane, name, ndim=(1, 2), allow_empty=False)


def as_angle(theta_deg: object, name: str = "theta_deg") -> float:
    """A finite angle in degrees."""
    return as_real(theta_deg, name)


def as_angles(angles: object, name: str = "angles") -> tuple[float, ...]:
    """One angle or a non-empty sequence of finite angles in degrees, as a tuple of floats."""
    if np.ndim(angles) == 0 and not isinstance(angles, (str, bytes)):
        angles = (angles,)
    if isinstance(angles, (str, bytes)):
        raise TypeError(f"{name} must be a sequence of numbers of degrees, got {type(angles).__name__}")
    try:
        out = tuple(as_real(a, name) for a in angles)  # type: ignore[union-attr]
    except TypeError as exc:
        raise TypeError(f"{name} must be a sequence of numbers of degrees: {exc}") from None
    if not out:
        raise ValueError(f"{name} must not be empty")
    return out


def as_freqs(rho: object) -> np.ndarray:
    """A non-empty 1-D array of finite frequencies (cycles per pixel); a scalar becomes one frequency."""
    return np.atleast_1d(only_value_errors(as_array, rho, "rho (cycles per pixel)", ndim=(0, 1), allow_empty=False))

"""Argument checks that only the novelty package needs (frames and frame stacks).

The general checks come from :mod:`projtrack._validation`; the wrappers here keep the error
types this package has always raised (a wrong kind of count or tolerance is a
:class:`ValueError` here, not a :class:`TypeError`).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from projtrack._validation import (as_array, as_choice, as_int, as_probability, as_real,
                                   only_value_errors)

from .updates import METHODS


def as_fraction(value: Any, name: str) -> float:
    """A threshold in ``[0, 1]`` (``T_d``, ``T_I``): TypeError for a non-number, else ValueError."""
    return as_probability(value, name)


def as_method(method: Any) -> str:
    """One of :data:`METHODS` (ValueError otherwise, whatever the type)."""
    return as_choice(method, "method", METHODS)


def as_positive_count(value: Any, name: str) -> int:
    """An int >= 1 (a bool or a float is refused with a ValueError)."""
    return only_value_errors(as_int, value, name, minimum=1)


def as_tolerance(value: Any, name: str) -> float:
    """A relative tolerance in ``[0, 1)`` (anything else is a ValueError)."""
    return only_value_errors(as_real, value, name, 0.0, 1.0, high_open=True)


def as_grey_threshold(value: Any, name: str) -> float:
    """A finite threshold >= 0 in grey levels (anything else is a ValueError)."""
    return only_value_errors(as_real, value, name, 0.0)


def as_frame(frame: Any, name: str = "frame") -> np.ndarray:
    """One frame: real (not bool), finite, non-empty, at least 1-D; a float64 copy, same shape."""
    a = as_array(frame, name, finite=False, allow_bool=False, dtype=np.float64)
    if a.ndim == 0 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty array with at least one dimension, "
                         f"got shape {a.shape}")
    if isinstance(frame, np.ndarray) and np.may_share_memory(a, frame):
        a = a.copy()               # the caller's array is never aliased by a fitted model
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


def as_frames(frames: Any, name: str = "frames") -> np.ndarray:
    """A stack of frames ``(I, *shape)`` with ``I >= 1``; a float64 array."""
    if isinstance(frames, (list, tuple)):
        if len(frames) == 0:
            raise ValueError(f"{name} must contain at least one frame")
        shapes = {np.shape(f) for f in frames}
        if len(shapes) != 1:
            raise ValueError(f"{name}: all frames must have the same shape, got {sorted(shapes)}")
    a = as_frame(frames, name)
    if a.ndim < 2:
        raise ValueError(f"{name} must have shape (n_frames, *frame_shape), got {a.shape}")
    if a[0].size == 0:
        raise ValueError(f"{name}: frames must be non-empty, got shape {a.shape}")
    return a

"""Argument checks shared by every module of the package.

Each check takes the value and the argument's ``name`` (used in the message), returns the
value in a canonical type (``int``, ``float``, a float ``ndarray``, ...) and raises

* :class:`TypeError` when the value has the wrong kind (a string for a number, a bool for
  an int, a complex or object array for a real one, a sparse matrix for a dense one);
* :class:`ValueError` when it has the right kind but a wrong value (out of range, NaN or
  inf, wrong shape, empty, an even window).

Messages name the argument and say what was expected and what was given, for example
``n_frames must be an int >= 1, got 0``. Checks that only one module needs stay in that
module; the ones here are those that at least two modules would otherwise write again.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from numbers import Integral, Real
from typing import Any

import numpy as np

__all__ = [
    "as_bool",
    "as_int",
    "as_count",
    "only_value_errors",
    "as_real",
    "as_probability",
    "as_probabilities",
    "as_odd_window",
    "as_choice",
    "as_rng",
    "as_shape2",
    "as_array",
    "as_square",
    "as_covariance",
    "as_covariances",
    "optional_import",
]


def _kind(value: object) -> str:
    return type(value).__name__


def _is_int(value: object) -> bool:
    return isinstance(value, Integral) and not isinstance(value, (bool, np.bool_))


def as_bool(value: object, name: str) -> bool:
    """A flag: ``True`` or ``False`` (a numpy bool too; 0 and 1 are not flags)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {_kind(value)}")
    return bool(value)


def as_int(value: object, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """``value`` as a Python ``int`` (a bool is not an int), within ``[minimum, maximum]``."""
    if not _is_int(value):
        raise TypeError(f"{name} must be an int, got {_kind(value)}")
    v = int(value)  # type: ignore[arg-type]
    if minimum is not None and v < minimum:
        raise ValueError(f"{name} must be an int >= {minimum}, got {v}")
    if maximum is not None and v > maximum:
        raise ValueError(f"{name} must be an int <= {maximum}, got {v}")
    return v


def as_count(value: object, name: str, minimum: int = 1) -> int:
    """A count: an int >= ``minimum``, with ValueError for *any* bad value.

    For sizes (numbers of steps, trials, frames, points) whose documented error is a
    ValueError whatever is wrong, a float or a bool included; elsewhere use :func:`as_int`,
    which reports a wrong kind as TypeError.
    """
    if not _is_int(value) or int(value) < minimum:  # type: ignore[call-overload]
        raise ValueError(f"{name} must be an int >= {minimum}, got {value!r}")
    return int(value)  # type: ignore[call-overload]


def only_value_errors(check: Callable[..., Any], value: object, name: str, *args: Any, **kwargs: Any) -> Any:
    """``check(value, name, *args, **kwargs)`` with a wrong kind reported as ValueError too.

    For arguments whose documented error is a ValueError whatever is wrong (a string for a
    number included), e.g. ``only_value_errors(as_real, speed, "speed", 0, low_open=True)``.
    The message is the check's own.
    """
    try:
        return check(value, name, *args, **kwargs)
    except TypeError as exc:
        raise ValueError(str(exc)) from None


def as_real(
    value: object,
    name: str,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
    finite: bool = True,
) -> float:
    """``value`` as a Python ``float`` (a bool is not a number) in the given interval.

    ``low``/``high`` bound the interval (``None``: unbounded), closed unless ``low_open`` /
    ``high_open``. NaN is always refused; infinities unless ``finite=False``.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number, got {_kind(value)}")
    v = float(value)
    if np.isnan(v) or (finite and not np.isfinite(v)):
        raise ValueError(f"{name} must be a finite number, got {v}")
    too_low = low is not None and (v <= low if low_open else v < low)
    too_high = high is not None and (v >= high if high_open else v > high)
    if too_low or too_high:
        lo = "-inf" if low is None else f"{low:g}"
        hi = "inf" if high is None else f"{high:g}"
        interval = ("(" if low_open or low is None else "[") + f"{lo}, {hi}" + (
            ")" if high_open or high is None else "]")
        if low == 0 and high is None:
            what = "> 0" if low_open else ">= 0"
            raise ValueError(f"{name} must be {what}, got {v}")
        raise ValueError(f"{name} must lie in {interval}, got {v}")
    return v


def as_probability(value: object, name: str, *, low_open: bool = False, high_open: bool = False) -> float:
    """A probability: a real number in ``[0, 1]`` (ends open on request)."""
    return as_real(value, name, 0.0, 1.0, low_open=low_open, high_open=high_open)


def as_probabilities(
    p: object, name: str, n: int, *, low_open: bool = False, high_open: bool = False
) -> np.ndarray:
    """A scalar or length-``n`` vector of probabilities, returned as a float array of shape ``(n,)``."""
    if np.ndim(p) == 0:
        return np.full(n, as_probability(p, name, low_open=low_open, high_open=high_open))
    a = as_array(p, name, ndim=1, finite=False)
    if a.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {a.shape}")
    bad = np.isnan(a) | (a <= 0 if low_open else a < 0) | (a >= 1 if high_open else a > 1)
    if bad.any():
        lo, hi = ("(" if low_open else "["), (")" if high_open else "]")
        raise ValueError(f"{name} must lie in {lo}0, 1{hi}, got {a}")
    return a


def as_odd_window(value: object, name: str) -> int:
    """A window size centred on a sample: an odd int >= 1."""
    v = as_int(value, name, minimum=1)
    if v % 2 == 0:
        # an even size has no centre sample: one side would get one sample more
        raise ValueError(f"{name} must be odd (a window centred on a sample), got {v}")
    return v


def as_choice(value: object, name: str, choices: Sequence[Any]) -> Any:
    """The member of ``choices`` equal to ``value``.

    Strings match only strings (a ``numpy.str_`` is a string), and bools only bools, so
    ``1`` does not pass for ``"1"`` nor ``True`` for ``1``. Returns the choice itself.
    """
    for c in choices:
        if isinstance(c, str) != isinstance(value, str):
            continue
        if isinstance(c, (bool, np.bool_)) != isinstance(value, (bool, np.bool_)):
            continue
        try:
            if bool(value == c):
                return c
        except (TypeError, ValueError):
            continue
    listed = ", ".join(repr(c) for c in choices)
    raise ValueError(f"{name} must be one of {listed}, got {value!r}")


def as_rng(rng: object, name: str = "rng") -> np.random.Generator:
    """A :class:`numpy.random.Generator` (no global seeds anywhere in the package)."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"{name} must be a numpy.random.Generator (np.random.default_rng(seed)), "
                        f"got {_kind(rng)}")
    return rng


def as_shape2(shape: object, name: str = "shape") -> tuple[int, int]:
    """A ``(height, width)`` pair of positive ints."""
    if not isinstance(shape, (tuple, list)) or len(shape) != 2 or not all(
            _is_int(s) and s > 0 for s in shape):
        raise ValueError(f"{name} must be a (height, width) pair of positive ints, got {shape!r}")
    return int(shape[0]), int(shape[1])


def as_array(
    x: object,
    name: str,
    *,
    ndim: int | Sequence[int] | None = None,
    shape: Sequence[int | None] | None = None,
    finite: bool = True,
    allow_empty: bool = True,
    allow_bool: bool = True,
    dtype: type = float,
) -> np.ndarray:
    """``x`` as a real array of ``dtype`` (float by default), checked.

    Refuses strings, ``None``, sparse matrices, object/complex/text arrays (TypeError), and
    (ValueError) a wrong number of dimensions (``ndim``: one int or several allowed), a
    wrong ``shape`` (``None`` entries match any length), an empty array unless
    ``allow_empty``, and NaN or inf unless ``finite=False``. Bool arrays are accepted
    (as 0/1) unless ``allow_bool=False``.
    """
    if x is None or isinstance(x, (str, bytes)):
        raise TypeError(f"{name} must be a numeric array, got {_kind(x)}")
    if hasattr(x, "tocsr") and hasattr(x, "nnz"):
        raise TypeError(f"{name} must be a dense array, got a scipy.sparse matrix")
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array ({exc})") from None
    kinds = "biuf" if allow_bool else "iuf"
    if a.dtype.kind not in kinds:
        if a.dtype.kind == "O":
            try:
                a = np.asarray(x, dtype=float)
            except (TypeError, ValueError) as exc:
                raise TypeError(f"{name} must be a numeric array ({exc})") from None
        else:
            what = "a bool" if a.dtype.kind == "b" else f"dtype {a.dtype}"
            raise TypeError(f"{name} must be a real numeric array, got {what}")
    if ndim is not None:
        allowed = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if a.ndim not in allowed:
            want = " or ".join(f"{d}-D" for d in allowed)
            raise ValueError(f"{name} must be a {want} array, got shape {a.shape}")
    if shape is not None:
        if a.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, a.shape)):
            want = "(" + ", ".join("any" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
            raise ValueError(f"{name} must have shape {want}, got {a.shape}")
    if not allow_empty and a.size == 0:
        raise ValueError(f"{name} must not be empty, got shape {a.shape}")
    a = a.astype(dtype, copy=False)
    if finite and a.dtype.kind == "f" and not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite (it contains NaN or inf)")
    return a


def as_square(x: object, name: str, n: int | None = None, *, finite: bool = True) -> np.ndarray:
    """A square float matrix (``n x n`` when ``n`` is given)."""
    a = as_array(x, name, ndim=2, finite=finite)
    if a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        want = f"{n} x {n}" if n is not None else "square"
        raise ValueError(f"{name} must be a {want} matrix, got shape {a.shape}")
    return a


def _psd_tolerance(a: np.ndarray) -> float:
    return 1e-10 * max(1.0, float(np.max(np.abs(a), initial=0.0)))


def as_covariance(x: object, name: str, n: int | None = None, *, definite: bool = False) -> np.ndarray:
    """A covariance matrix: square (``n x n`` when given), finite, symmetric and PSD.

    Symmetry is checked to a relative tolerance of 1e-9 and positive semidefiniteness
    (positive definiteness with ``definite=True``) to 1e-10 of the largest entry. The
    matrix is returned as a float array with its values unchanged (not symmetrized).
    """
    a = as_square(x, name, n)
    if a.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty square matrix, got shape {a.shape}")
    scale = max(1.0, float(np.max(np.abs(a))))
    asym = float(np.max(np.abs(a - a.T)))
    if asym > 1e-9 * scale:
        raise ValueError(f"{name} must be symmetric (a covariance), max |{name} - {name}^T| = {asym:.3g}")
    lam = float(np.linalg.eigvalsh(0.5 * (a + a.T))[0])
    tol = _psd_tolerance(a)
    if definite and lam <= tol:
        raise ValueError(f"{name} must be positive definite (a covariance), smallest eigenvalue {lam:.3g}")
    if lam < -tol:
        raise ValueError(f"{name} must be positive semidefinite (a covariance), smallest eigenvalue {lam:.3g}")
    return a


def as_covariances(x: object, name: str, k: int, n: int, *, definite: bool = False) -> np.ndarray:
    """One ``n x n`` covariance for all ``k`` items, or one per item: returns shape ``(k, n, n)``.

    Each matrix is checked by :func:`as_covariance`; the message names the item
    (``P0[2] must be positive semidefinite ...``).
    """
    a = as_array(x, name, ndim=(2, 3))
    if a.ndim == 2:
        c = as_covariance(a, name, n, definite=definite)
        return np.broadcast_to(c, (k, n, n)).copy()
    if a.shape != (k, n, n):
        raise ValueError(f"{name} must be one {n} x {n} matrix or {k} of them (shape ({k}, {n}, {n})), "
                         f"got shape {a.shape}")
    return np.array([as_covariance(c, f"{name}[{i}]", n, definite=definite) for i, c in enumerate(a)])


def optional_import(module: str, extra: str, purpose: str) -> Any:
    """Import an optional dependency, or raise ImportError naming the extra that installs it.

    ``optional_import("cvxpy", "sdp", "method='sdp'")`` returns the module, or raises
    ``ImportError: method='sdp' needs cvxpy: pip install "projtrack[sdp]"``.
    """
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        raise ImportError(f"{purpose} needs {top}, an optional dependency of projtrack: "
                          f'pip install "projtrack[{extra}]"') from exc

"""Numbers that print the same on every CPU and BLAS kernel.

A value computed through BLAS, LAPACK or an iterative solver can differ in its last bits
from one CPU (or OpenBLAS kernel: ``OPENBLAS_CORETYPE``) to another. Whatever the book
prints, stores in a CSV or compares under nbval must therefore be rounded well above
those bits, and must never show a negative zero (``-0.000``), which a sign flip in the
last bit of a value that is zero up to rounding produces.

:func:`tidy` rounds numbers (scalars, arrays, pandas objects) to a number of decimals or
significant digits, sets values below an absolute tolerance to zero and removes negative
zeros; :func:`fmt` formats one number with a format spec and never returns a negative
zero. Use the solver's tolerance to choose ``atol`` and the printed precision: a value
known to about ``1e-8`` is printed with at most 6 decimals.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from projtrack._validation import as_int, as_real, only_value_errors

__all__ = ["tidy", "fmt", "tiny", "below"]


def _check(decimals: object, sig: object, atol: object) -> None:
    if decimals is not None and sig is not None:
        raise ValueError("give decimals or sig, not both")
    if decimals is not None:
        as_int(decimals, "decimals")
    if sig is not None:
        as_int(sig, "sig", minimum=1)
    only_value_errors(as_real, atol, "atol", 0)


def _as_number(x: object, name: str = "x") -> float:
    """``x`` as a float; NaN and infinities pass (they are printed as such)."""
    try:
        return as_real(x, name, finite=False)
    except ValueError:  # without bounds, as_real refuses a real number only when it is NaN
        return math.nan


def _round_array(a: np.ndarray, decimals: int | None, sig: int | None, atol: float) -> np.ndarray:
    a = np.array(a, dtype=float)  # a copy
    finite = np.isfinite(a)
    if atol > 0:
        a[finite & (np.abs(a) <= atol)] = 0.0
    if decimals is not None:
        a[finite] = np.round(a[finite], decimals)
    elif sig is not None:
        nz = finite & (a != 0)
        exp = np.floor(np.log10(np.abs(a[nz])))
        scale = 10.0 ** (sig - 1 - exp)
        a[nz] = np.round(a[nz] * scale) / scale
    return a + 0.0  # -0.0 + 0.0 == +0.0


def tidy(x: Any, decimals: int | None = None, *, sig: int | None = None, atol: float = 0.0) -> Any:
    """Round numbers so they do not depend on the last bits of floating point.

    Parameters
    ----------
    x : float, int, array-like, pandas.Series or pandas.DataFrame
        The numbers. Integers, booleans, strings and other non-float entries (and
        non-float columns of a DataFrame) are returned unchanged.
    decimals : int, optional
        Round to this many decimals (negative rounds to tens, hundreds, ...).
    sig : int, optional
        Round to this many significant digits instead (not with ``decimals``).
    atol : float, default 0
        Values with ``abs(value) <= atol`` become exactly ``0.0`` (use the solver's or
        iteration's tolerance).

    Returns
    -------
    Same kind as ``x``
        A float for a scalar, a float array for an array, a copy for pandas objects.
        Negative zeros are always replaced by ``0.0``; NaN and infinities are kept.

    Examples
    --------
    >>> tidy(-1e-17, 6)
    0.0
    >>> tidy([0.1234567, -2.5e-12], sig=3, atol=1e-9).tolist()
    [0.123, 0.0]
    """
    _check(decimals, sig, atol)
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - pandas is a dependency
        pd = None
    if pd is not None and isinstance(x, pd.DataFrame):
        out = x.copy()
        for col in out.columns:
            if pd.api.types.is_float_dtype(out[col]):
                out[col] = _round_array(out[col].to_numpy(), decimals, sig, atol)
        return out
    if pd is not None and isinstance(x, pd.Series):
        if not pd.api.types.is_float_dtype(x):
            return x.copy()
        return pd.Series(_round_array(x.to_numpy(), decimals, sig, atol), index=x.index, name=x.name)
    if isinstance(x, (bool, np.bool_, numbers.Integral, str)):
        return x
    if isinstance(x, numbers.Real):
        return float(_round_array(np.array([float(x)]), decimals, sig, atol)[0])
    a = np.asarray(x)
    if a.dtype.kind in "iub":
        return a.copy()
    if a.dtype.kind != "f":
        raise TypeError(f"x must hold real numbers, got an array of dtype {a.dtype}")
    return _round_array(a, decimals, sig, atol)


def fmt(x: Any, spec: str = ".6g", *, atol: float = 0.0) -> str:
    """Format one number with ``format(x, spec)``, never giving a negative zero.

    Parameters
    ----------
    x : real number
        The value.
    spec : str, default ``".6g"``
        A format spec (``".3f"``, ``".2e"``, ``".1%"``, ``"+.4f"``, ...).
    atol : float, default 0
        Values with ``abs(x) <= atol`` are formatted as zero.

    Returns
    -------
    str
        The formatted value; a result that reads as zero carries no minus sign.

    Examples
    --------
    >>> fmt(-1e-12, ".6f")
    '0.000000'
    >>> fmt(-0.25, ".1f")
    '-0.2'
    """
    v = _as_number(x)
    if not isinstance(spec, str):
        raise TypeError(f"spec must be a str, got {type(spec).__name__}")
    _check(None, None, atol)
    if atol > 0 and abs(v) <= atol:
        v = 0.0
    s = format(v + 0.0 if v == 0 else v, spec)
    if s.lstrip().startswith("-") and "inf" not in s and "nan" not in s:
        mantissa = s.split("e")[0].split("E")[0]
        if not any(c in "123456789" for c in mantissa):
            s = s.replace("-", "+" if "+" in spec else "", 1)
    return s


def tiny(x: Any, floor: float = 1e-12, spec: str = ".1e") -> str:
    """Format a value that should be zero up to rounding: ``"< floor"`` if ``|x| < floor``.

    Values at rounding-error level (a deviation from an identity, a residual of an exact
    formula) differ in their last bits between machines; below ``floor`` they are printed
    as the bound, above it with two significant digits (``"3.1e-05"``).

    Parameters
    ----------
    x : real number
        The value.
    floor : float, default 1e-12
        Positive bound below which only the bound is printed.
    spec : str, default ".1e"
        Format of values at or above ``floor`` (through :func:`fmt`).

    Examples
    --------
    >>> tiny(3e-16)
    '< 1e-12'
    >>> tiny(-2.5e-5)
    '-2.5e-05'
    """
    v = _as_number(x)
    only_value_errors(as_real, floor, "floor", 0, low_open=True)
    if not math.isfinite(v):
        return str(v)
    return f"< {floor:.0e}".replace("e-0", "e-") if abs(v) < floor else fmt(v, spec)


def below(x: Any, tol: float) -> str:
    """Pass/fail of a solver-accuracy value against a fixed tolerance stated in advance.

    Returns ``"< tol"`` when ``|x| < tol`` and ``"FAIL: <value>"`` otherwise. The printed
    text changes only when the value crosses ``tol``, a bound chosen before the numbers and
    far from them, never at a boundary set by the data (as power-of-ten buckets would be).

    Parameters
    ----------
    x : real number
        The value (its absolute value is compared).
    tol : float
        The positive tolerance.

    Examples
    --------
    >>> below(1.0096e-5, 1e-3)
    '< 1e-3'
    >>> below(0.02, 1e-3)
    'FAIL: 2.0e-02'
    """
    v = abs(_as_number(x))
    only_value_errors(as_real, tol, "tol", 0, low_open=True)
    if v < tol:
        return f"< {tol:.0e}".replace("e-0", "e-").replace("e+0", "e")
    return f"FAIL: {v:.1e}"

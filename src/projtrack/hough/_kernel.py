"""Voting kernel of the straight-line Hough transform (Eq. (1) of Casasent & Slaski).

:func:`vote` accumulates ``rho = (x - cx) cos(theta) + (y - cy) sin(theta)`` for every
point and angle into ``(rho, theta)`` bins. Integer pixels land exactly on bin boundaries
(at 30, 60, 120, 150 degrees, for example), so the bin coordinate is rounded to 9 decimals
before the half-up rounding: the side a tie falls on then does not depend on the last bit
of ``cos``/``sin`` (which differs between CPU math libraries), and ties go up.

Two implementations give the same votes, cell for cell:

* a compiled loop (numba, when it is installed and ``PROJTRACK_NO_NUMBA`` is not ``1``)
  that performs exactly the floating-point operations of the array version, element by
  element, with no temporaries;
* the array version (:func:`vote_numpy`, numpy only), also the reference of the tests.

The ``cos``/``sin`` tables are computed once per set of angles and cached.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from projtrack import _numba

__all__ = ["vote", "vote_numpy", "numba_enabled"]

_HAVE_NUMBA = _numba.HAVE_NUMBA


def numba_enabled() -> bool:
    """True when the compiled kernel is used: numba importable and ``PROJTRACK_NO_NUMBA != 1``."""
    return _HAVE_NUMBA and _numba.switched_on()


@lru_cache(maxsize=64)
def _trig(thetas_key: bytes) -> tuple[np.ndarray, np.ndarray]:
    t = np.deg2rad(np.frombuffer(thetas_key, dtype=float))
    c, s = np.cos(t), np.sin(t)
    c.flags.writeable = False
    s.flags.writeable = False
    return c, s


def _tables(thetas_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _trig(np.ascontiguousarray(thetas_deg, dtype=float).tobytes())


def vote_numpy(pts: np.ndarray, cx: float, cy: float, rho0: float, n_rho: int,
               thetas_deg: np.ndarray, drho: float,
               weights: np.ndarray | None = None) -> np.ndarray:
    """Votes of ``pts`` (N, 2) in the ``(n_rho, len(thetas_deg))`` plane, numpy only.

    ``rho0`` is the centre of the first ``rho`` bin, ``drho`` the bin width, ``(cx, cy)``
    the origin of ``rho``; ``weights`` (N,) replaces the unit vote of each point. Inputs
    are assumed checked. Returns a float array.
    """
    n_theta = thetas_deg.size
    if pts.shape[0] == 0:
        return np.zeros((n_rho, n_theta))
    c, s = _tables(thetas_deg)
    rho = (pts[:, 0:1] - cx) * c + (pts[:, 1:2] - cy) * s  # (N, n_theta), Eq. (1)
    idx = np.floor(np.round((rho - rho0) / drho, 9) + 0.5).astype(np.int64)
    np.clip(idx, 0, n_rho - 1, out=idx)
    flat = idx * n_theta + np.arange(n_theta)
    w = None if weights is None else np.repeat(weights[:, None], n_theta, axis=1).ravel()
    acc = np.bincount(flat.ravel(), weights=w, minlength=n_rho * n_theta)
    return acc.reshape(n_rho, n_theta).astype(float)


_kernel = None


def _get_kernel():
    """The compiled loop (compiled on first use; cached on disk where numba can write)."""
    global _kernel
    if _kernel is None:
        @_numba.import_numba().njit(cache=True, nogil=True)
        def kernel(x, y, cx, cy, c, s, rho0, drho, pow2, weights, acc):  # pragma: no cover - compiled
            # angle by angle (the inner loops over the points vectorize); every cell still
            # receives its votes in the order of the points
            n_rho, n_theta = acc.shape
            n = x.shape[0]
            inv = 1.0 / drho
            dx = x - cx
            dy = y - cy
            kf = np.empty(n)
            for t in range(n_theta):
                ct = c[t]
                st = s[t]
                for p in range(n):
                    d = (dx[p] * ct + dy[p] * st) - rho0
                    # (rho - rho0) / drho; a power of two divides exactly as a product
                    q = d * inv if pow2 else d / drho
                    # numpy's round(q, 9) is rint(q * 1e9) / 1e9, and floor(that + 0.5) is
                    # floor((Y + 5e8) / 1e9) for the integer Y = rint(q * 1e9); with Y + 5e8
                    # an integer, adding 0.5 before the (inexact) scaling by 1e-9 keeps the
                    # floor exact (|Y| < 2^51 is checked by the caller)
                    kf[p] = np.floor((np.rint(q * 1e9) + 500000000.5) * 1e-9)
                for p in range(n):
                    k = int(kf[p])
                    if k < 0:
                        k = 0
                    elif k > n_rho - 1:
                        k = n_rho - 1
                    acc[k, t] += weights[p] if weights.shape[0] else 1.0

        _kernel = kernel
    return _kernel


_NO_WEIGHTS = np.zeros(0)


def vote(pts: np.ndarray, cx: float, cy: float, rho0: float, n_rho: int,
         thetas_deg: np.ndarray, drho: float, weights: np.ndarray | None = None,
         *, use_numba: bool | None = None) -> np.ndarray:
    """Same as :func:`vote_numpy` (the same votes, cell for cell), compiled when possible.

    ``use_numba=None`` follows :func:`numba_enabled`; ``False`` forces the array version.
    """
    if use_numba is None:
        use_numba = numba_enabled()
    if not use_numba or not _HAVE_NUMBA or pts.shape[0] == 0 or n_rho > 1_000_000:
        return vote_numpy(pts, cx, cy, rho0, n_rho, thetas_deg, drho, weights)
    c, s = _tables(thetas_deg)
    acc = np.zeros((n_rho, thetas_deg.size))
    w = _NO_WEIGHTS if weights is None else np.ascontiguousarray(weights, dtype=float)
    m, e = np.frexp(float(drho))
    _get_kernel()(np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1]), float(cx),
                  float(cy), c, s, float(rho0), float(drho), bool(m == 0.5), w, acc)
    return acc

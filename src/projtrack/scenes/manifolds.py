"""Synthetic manifolds and trajectories for the DMA chapter (Marques et al. 2002).

The paper's Figs. 1-6 show points and trajectories on simple manifolds but publish no
data; these generators make equivalent ones:

* :func:`parabolic_surface` - points on ``z = a (x^2 + y^2)`` (Fig. 4);
* :func:`closed_curve` / :func:`curve_trajectory` - a smooth closed curve in the plane
  and a clockwise trajectory on it (Figs. 2, 3, 5);
* :func:`sphere_points`, :func:`sphere_velocity`, :func:`sphere_trajectory` - the unit
  sphere, a velocity field on it and continuous trajectories that follow it (Example 1,
  Fig. 6);
* :func:`sample_markov_chain` - a state sequence drawn from a (sparse) Markov chain.

Every function draws only from the ``rng`` it is given; nothing is tuned to a paper value.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_count, as_rng

__all__ = [
    "parabolic_surface",
    "closed_curve",
    "curve_trajectory",
    "sphere_points",
    "fibonacci_sphere",
    "sphere_velocity",
    "project_to_sphere",
    "sphere_trajectory",
    "sample_markov_chain",
]


def parabolic_surface(n: int, rng: np.random.Generator, *, a: float = 1.0, noise: float = 0.0) -> np.ndarray:
    """``n`` points uniform in ``[-1, 1]^2`` lifted to ``z = a (x^2 + y^2)`` (+ N(0, noise^2) in z).

    Returns an ``(n, 3)`` array (Fig. 4a of Marques et al.)."""
    rng = as_rng(rng)
    n = as_count(n, "n")
    xy = rng.uniform(-1.0, 1.0, size=(n, 2))
    z = a * (xy**2).sum(axis=1) + noise * rng.standard_normal(n)
    return np.column_stack([xy, z])


def closed_curve(t: np.ndarray) -> np.ndarray:
    """A smooth closed curve in the plane, ``t`` in ``[0, 2 pi)`` (a lobed circle):
    ``r(t) = 1 + 0.25 cos(3 t)``, points ``(r cos t, r sin t)``. Returns ``(len(t), 2)``."""
    t = np.asarray(t, dtype=float)
    r = 1.0 + 0.25 * np.cos(3 * t)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def curve_trajectory(n_steps: int, rng: np.random.Generator, *, mean_step: float = 0.05, jitter: float = 0.5, noise: float = 0.0) -> np.ndarray:
    """Clockwise motion on :func:`closed_curve` with a limited, random speed.

    The parameter decreases by ``mean_step * U(1 - jitter, 1 + jitter)`` radians per step
    from a uniform random start; points get isotropic N(0, noise^2) noise.
    Returns ``(n_steps, 2)``."""
    rng = as_rng(rng)
    n = as_count(n_steps, "n_steps")
    steps = mean_step * rng.uniform(1 - jitter, 1 + jitter, size=n)
    t = rng.uniform(0, 2 * np.pi) - np.concatenate([[0.0], np.cumsum(steps[1:])])
    return closed_curve(t) + noise * rng.standard_normal((n, 2))


def sphere_points(n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` points uniform on the unit sphere, ``(n, 3)``."""
    rng = as_rng(rng)
    n = as_count(n, "n")
    return project_to_sphere(rng.standard_normal((n, 3)))


def fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` nearly evenly spread points on the unit sphere (golden-angle spiral), ``(n, 3)``.

    Point ``i`` has height ``z = 1 - 2 (i + 1/2) / n`` and longitude ``pi (1 + sqrt 5) (i + 1/2)``:
    a regular layout to compare with centroids learned from random points.
    ``n`` must be an int >= 1 (ValueError otherwise).
    """
    n = as_count(n, "n")
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    phi = np.pi * (1 + 5 ** 0.5) * i
    r = np.sqrt(1 - z ** 2)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def project_to_sphere(x: np.ndarray) -> np.ndarray:
    """Radial projection of points onto the unit sphere."""
    x = np.asarray(x, dtype=float)
    r = np.linalg.norm(x, axis=-1, keepdims=True)
    if (r == 0).any():
        raise ValueError("cannot project the origin onto the sphere")
    return x / r


def sphere_velocity(x: np.ndarray, *, omega: float = 1.0, axis: tuple[float, float, float] = (0.0, 0.0, 1.0), drift: float = 0.3) -> np.ndarray:
    """A velocity field on the unit sphere (Example 1 of Marques et al.).

    A rotation ``omega * k x x`` about the unit axis ``k`` plus a poleward drift
    ``drift * (k - (k . x) x)`` (tangent, pushes points towards the pole ``+k``), so that
    trajectories spiral instead of repeating circles. Returns an array shaped like ``x``.
    """
    x = np.asarray(x, dtype=float)
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    kx = x @ k
    return omega * np.cross(k, x) + drift * (k - kx[..., None] * x)


def sphere_trajectory(n_steps: int, dt: float, rng: np.random.Generator, *, noise: float = 0.0, start: np.ndarray | None = None, **field: float) -> np.ndarray:
    """A continuous trajectory following :func:`sphere_velocity` (Euler steps of ``dt``
    with isotropic tangent-ish N(0, noise^2 dt) perturbations, re-projected on the sphere).
    Starts at ``start`` or a uniform random point. Returns ``(n_steps, 3)``."""
    rng = as_rng(rng)
    n = as_count(n_steps, "n_steps")
    x = sphere_points(1, rng)[0] if start is None else project_to_sphere(np.asarray(start, dtype=float))
    out = np.empty((n, 3))
    for t in range(n):
        out[t] = x
        x = project_to_sphere(x + dt * sphere_velocity(x, **field) + noise * np.sqrt(dt) * rng.standard_normal(3))
    return out


def sample_markov_chain(start: np.ndarray, transitions: object, n_steps: int, rng: np.random.Generator) -> np.ndarray:
    """Draw a state sequence of length ``n_steps`` from a Markov chain.

    Parameters
    ----------
    start : array_like, shape (S,)
        Initial probabilities.
    transitions : array_like or scipy.sparse matrix, shape (S, S)
        Row-stochastic transition probabilities.
    """
    rng = as_rng(rng)
    n = as_count(n_steps, "n_steps")
    p0 = np.asarray(start, dtype=float)
    P = sp.csr_array(transitions, dtype=float)
    S = p0.shape[0]
    if P.shape != (S, S):
        raise ValueError(f"transitions must have shape ({S}, {S}), got {P.shape}")
    if abs(p0.sum() - 1) > 1e-9 or (p0 < 0).any():
        raise ValueError("start must be a probability vector")
    path = np.empty(n, dtype=np.int64)
    path[0] = rng.choice(S, p=p0)
    for t in range(1, n):
        lo, hi = P.indptr[path[t - 1]], P.indptr[path[t - 1] + 1]
        w = P.data[lo:hi]
        path[t] = P.indices[lo + rng.choice(hi - lo, p=w / w.sum())]
    return path

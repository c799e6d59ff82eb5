"""Crossing targets in uniform clutter: synthetic scans for the JPDA chapter (Fisher & Casasent 1989).

The paper (chapter 4 of Casasent's 1989 report) publishes no tracking data; this module
makes the standard test case of the JPDA literature instead: ``n_targets`` targets on
nearly constant-velocity paths that all pass through a common crossing point half way
through the run, detected with probability ``p_detect`` with Gaussian position noise,
plus a Poisson number of false measurements spread uniformly over the surveillance
square. Nothing here is tuned to any number of the paper.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class CrossingScene:
    """Output of :func:`crossing_targets`.

    Attributes
    ----------
    truth : ndarray, shape (n_steps + 1, n_targets, 4)
        True states ``(x, vx, y, vy)`` at times ``0..n_steps`` (row 0 is the
        initial state, known to the tracker as track initiation).
    scans : list of ndarray, each (m_k, 2)
        Measurements of steps ``1..n_steps`` (detections then clutter, shuffled).
    origin : list of ndarray, each (m_k,)
        Target index of each measurement, ``-1`` for clutter.
    F, Q, H, R : ndarray
        The model used to simulate (constant velocity, white-acceleration noise).
    clutter_density : float
        Expected false measurements per unit area.
    area : float
        Area of the surveillance square.
    """

    truth: np.ndarray
    scans: list
    origin: list
    F: np.ndarray
    Q: np.ndarray
    H: np.ndarray
    R: np.ndarray
    clutter_density: float
    area: float


def cv_model(dt: float = 1.0, q: float = 0.01, r: float = 0.25) -> tuple[np.ndarray, ...]:
    """Constant-velocity model ``(F, Q, H, R)`` in state ``(x, vx, y, vy)``.

    ``q`` is the white-acceleration spectral density, ``r`` the position noise
    variance of each coordinate.
    """
    if dt <= 0 or q < 0 or r <= 0:
        raise ValueError("dt and r must be > 0 and q >= 0")
    f = np.array([[1.0, dt], [0.0, 1.0]])
    qb = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    F = np.kron(np.eye(2), f)
    Q = np.kron(np.eye(2), qb)
    H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    R = r * np.eye(2)
    return F, Q, H, R


def crossing_targets(rng: np.random.Generator, n_targets: int = 3, n_steps: int = 30,
                     speed: float = 1.0, p_detect: float = 0.9, clutter_per_scan: float = 10.0,
                     size: float = 40.0, q: float = 0.01, r: float = 0.25) -> CrossingScene:
    """Targets that cross at the centre of a ``size x size`` square, in uniform clutter.

    Target ``i`` starts on a circle of radius ``speed * n_steps / 2`` around the
    centre at angle ``pi i / n_targets`` (so all paths cross at the centre at step
    ``n_steps / 2``), moving towards the centre with speed ``speed``, and then
    follows the noisy constant-velocity model of :func:`cv_model`.

    Parameters
    ----------
    rng : numpy.random.Generator
    n_targets, n_steps : int
    speed : float
        Initial speed (units per step).
    p_detect : float
        Detection probability in (0, 1].
    clutter_per_scan : float
        Mean number of false measurements per scan (Poisson).
    size : float
        Side of the surveillance square centred on the crossing point.
    q, r : float
        Process and measurement noise (see :func:`cv_model`).
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError("rng must be a numpy.random.Generator")
    if n_targets < 1 or n_steps < 1:
        raise ValueError("n_targets and n_steps must be >= 1")
    if not 0 < p_detect <= 1:
        raise ValueError(f"p_detect must lie in (0, 1], got {p_detect}")
    if clutter_per_scan < 0 or size <= 0 or speed <= 0:
        raise ValueError("clutter_per_scan must be >= 0, size and speed > 0")
    F, Q, H, R = cv_model(1.0, q, r)
    rad = speed * n_steps / 2
    ang = np.pi * np.arange(n_targets) / n_targets
    x0 = np.column_stack([-rad * np.cos(ang), speed * np.cos(ang),
                          -rad * np.sin(ang), speed * np.sin(ang)])
    truth = np.empty((n_steps + 1, n_targets, 4))
    truth[0] = x0
    Lq = np.linalg.cholesky(Q + 1e-15 * np.eye(4))
    for k in range(1, n_steps + 1):
        truth[k] = truth[k - 1] @ F.T + rng.standard_normal((n_targets, 4)) @ Lq.T
    scans, origin = [], []
    for k in range(1, n_steps + 1):
        det = rng.random(n_targets) < p_detect
        pos = truth[k][det][:, [0, 2]] + rng.normal(0, np.sqrt(r), (int(det.sum()), 2))
        nc = rng.poisson(clutter_per_scan)
        clut = rng.uniform(-size / 2, size / 2, (nc, 2))
        z = np.vstack([pos, clut])
        o = np.concatenate([np.flatnonzero(det), -np.ones(nc, dtype=int)])
        perm = rng.permutation(len(z))
        scans.append(z[perm])
        origin.append(o[perm])
    return CrossingScene(truth, scans, origin, F, Q, H, R, clutter_per_scan / size**2, size**2)

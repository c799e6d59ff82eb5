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

from projtrack._validation import as_int, as_probability, as_real, as_rng

__all__ = ["CrossingScene", "cv_model", "crossing_targets", "random_mvm"]


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
    dt = as_real(dt, "dt", 0.0, low_open=True)
    q = as_real(q, "q", 0.0)
    r = as_real(r, "r", 0.0, low_open=True)
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
    rng = as_rng(rng)
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    n_steps = as_int(n_steps, "n_steps", minimum=1)
    speed = as_real(speed, "speed", 0.0, low_open=True)
    p_detect = as_probability(p_detect, "p_detect", low_open=True)
    clutter_per_scan = as_real(clutter_per_scan, "clutter_per_scan", 0.0)
    size = as_real(size, "size", 0.0, low_open=True)
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


def random_mvm(rng: np.random.Generator, m: int, T: int, *, cluster_size: int | None = None,
               p_detect: float = 0.9) -> np.ndarray:
    """A random modified validation matrix (eqs. (3)-(4) of the JPDA chapter).

    Row 0 is ``1 - p_detect``; the other entries are uniform in ``(0.05, 1)``. With
    ``cluster_size=None`` every measurement is validated for every target (fully
    gated, the worst case of Table I); otherwise targets and measurements are cut
    into consecutive groups of ``cluster_size`` and only entries within a group are
    nonzero (independent clusters, the common case of well separated targets).
    """
    rng = as_rng(rng)
    m = as_int(m, "m", minimum=0)
    T = as_int(T, "T", minimum=1)
    p_detect = as_probability(p_detect, "p_detect", low_open=True)
    w = rng.uniform(0.05, 1.0, (m + 1, T))
    if cluster_size is not None:
        cluster_size = as_int(cluster_size, "cluster_size", minimum=1)
        gm = np.arange(m) // cluster_size
        gt = np.arange(T) // cluster_size
        w[1:] *= gm[:, None] == gt[None, :]
    w[0] = 1.0 - p_detect
    return w


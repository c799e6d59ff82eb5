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


def random_mvm(rng: np.random.Generator, m: int, T: int, *, cluster_size: int | None = None,
               p_detect: float = 0.9) -> np.ndarray:
    """A random modified validation matrix (eqs. (3)-(4) of the JPDA chapter).

    Row 0 is ``1 - p_detect``; the other entries are uniform in ``(0.05, 1)``. With
    ``cluster_size=None`` every measurement is validated for every target (fully
    gated, the worst case of Table I); otherwise targets and measurements are cut
    into consecutive groups of ``cluster_size`` and only entries within a group are
    nonzero (independent clusters, the common case of well separated targets).
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError("rng must be a numpy.random.Generator")
    if m < 0 or T < 1:
        raise ValueError("m must be >= 0 and T >= 1")
    if not 0 < p_detect <= 1:
        raise ValueError(f"p_detect must lie in (0, 1], got {p_detect}")
    w = rng.uniform(0.05, 1.0, (m + 1, T))
    if cluster_size is not None:
        if cluster_size < 1:
            raise ValueError("cluster_size must be >= 1")
        gm = np.arange(m) // cluster_size
        gt = np.arange(T) // cluster_size
        w[1:] *= gm[:, None] == gt[None, :]
    w[0] = 1.0 - p_detect
    return w


def score_tracks(estimates: np.ndarray, truth: np.ndarray, lost_distance: float = 3.0) -> dict:
    """Position RMSE, swaps and losses of tracks started on their own targets.

    ``estimates`` and ``truth`` have shape ``(n_steps, n_targets, 4)`` (state
    ``(x, vx, y, vy)``). At the last step a track is *lost* when no true target is
    within ``lost_distance``, and *swapped* when the nearest true target is not its
    own. ``rmse`` is the root mean square position error of every track against its
    own target over all steps.
    """
    est = np.asarray(estimates)[..., [0, 2]]
    tru = np.asarray(truth)[..., [0, 2]]
    if est.shape != tru.shape:
        raise ValueError(f"estimates and truth must have the same shape, got {est.shape} and {tru.shape}")
    rmse = float(np.sqrt(np.mean(np.sum((est - tru) ** 2, axis=-1))))
    d = np.linalg.norm(est[-1][:, None, :] - tru[-1][None, :, :], axis=-1)
    nearest = d.argmin(axis=1)
    lost = d.min(axis=1) > lost_distance
    swapped = (~lost) & (nearest != np.arange(len(nearest)))
    return {"rmse": rmse, "swapped": int(swapped.sum()), "lost": int(lost.sum())}


def tracking_trial(rng: np.random.Generator, **scene_kw) -> dict:
    """One crossing scene tracked by JPDA and by GNN; returns their :func:`score_tracks`.

    Both trackers start from the true initial states with covariance ``0.5 I`` (track
    initiation is chapter 3's job) and use the simulation model; JPDA uses the
    scene's ``p_detect`` and clutter density, both use a 0.99 gate.
    """
    from projtrack.jpda import GNNTracker, JPDATracker

    sc = crossing_targets(rng, **scene_kw)
    p_detect = scene_kw.get("p_detect", 0.9)
    args = (sc.truth[0], 0.5 * np.eye(4), sc.F, sc.Q, sc.H, sc.R)
    jp = JPDATracker(*args, p_detect=p_detect, clutter_density=sc.clutter_density)
    gn = GNNTracker(*args)
    est_j = np.array([jp.step(z) for z in sc.scans])
    est_g = np.array([gn.step(z) for z in sc.scans])
    return {"jpda": score_tracks(est_j, sc.truth[1:]), "gnn": score_tracks(est_g, sc.truth[1:])}

"""Example 1 of Marques et al. (2002), Fig. 6: a Markov chain on the unit sphere.

The chain of a velocity field on centroids learned on the sphere, observed through
``y = [1 -1 1] x + v`` (:func:`make_sphere_example`), its Monte Carlo study
(:func:`sphere_trials`) and the manifold-ignoring Kalman baseline (:func:`kalman_sphere`).
The paper leaves open the observation noise and the construction of the chain
(:data:`SPHERE_CHAINS`); the choices are documented per function.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_array, as_choice, as_count, as_real
from projtrack.dma import (
    DiscreteManifold,
    LinearGaussianSensor,
    learn_manifold,
    log_transitions,
    transitions_from_velocity_field,
    viterbi,
)
from projtrack.experiments.dma.decoding import decode_all
from projtrack.montecarlo import run
from projtrack.scenes import manifolds as mf

__all__ = [
    "H_SPHERE",
    "SPHERE_CHAINS",
    "SphereExample",
    "make_sphere_example",
    "with_centroids",
    "sphere_trials",
    "accuracy_summary",
    "noise_study",
    "kalman_sphere",
]

#: Observation row of Example 1.
H_SPHERE = np.array([[1.0, -1.0, 1.0]])

#: Constructions of the Example 1 chain: name -> (successors per centroid, exclude the centroid itself).
SPHERE_CHAINS: dict[str, tuple[int, bool]] = {
    "two-nearest": (2, False),
    "two-others": (2, True),
    "nearest-other": (1, True),
}


@dataclass
class SphereExample:
    """Set-up of Example 1: centroids on the sphere and the chain of the velocity field."""

    manifold: DiscreteManifold
    centroids: np.ndarray
    transitions: sp.csr_array
    start: np.ndarray
    noise_std: float
    dt: float

    @property
    def n_states(self) -> int:
        return len(self.centroids)

    def sensor(self) -> LinearGaussianSensor:
        return LinearGaussianSensor(self.centroids, H_SPHERE, self.noise_std**2)

    def with_noise(self, noise_std: float) -> "SphereExample":
        """The same centroids and chain with another observation noise level."""
        return replace(self, noise_std=as_real(noise_std, "noise_std", 0, low_open=True))

    def simulate(self, n_steps: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """A state path drawn from the chain and its observations ``y = H u + v``."""
        path = mf.sample_markov_chain(self.start, self.transitions, n_steps, rng)
        y = self.centroids[path] @ H_SPHERE.T + self.noise_std * rng.standard_normal((n_steps, 1))
        return path, y


def make_sphere_example(
    rng: np.random.Generator,
    *,
    n_points: int = 2000,
    n_regions: int = 12,
    n_prototypes: int = 8,
    dt: float = 0.3,
    noise_std: float = 0.1,
    chain: str = "two-nearest",
) -> SphereExample:
    """Example 1: learn centroids on the sphere (Sec. 3.1) and the chain of a velocity field.

    ``n_points`` uniform points on the unit sphere are split into ``n_regions`` regions
    with 2-D local planes and ``n_prototypes`` k-means centroids each (then pushed
    radially onto the sphere). Transitions follow :func:`projtrack.scenes.manifolds.sphere_velocity`
    with time step ``dt`` (:func:`projtrack.dma.transitions_from_velocity_field`); the
    paper does not say how, and ``chain`` chooses the construction:

    ``"two-nearest"``
        the two centroids nearest the predicted point, weighted by a Gaussian as wide
        as the centroid spacing (the centroid itself may be one of them: a self-loop);
    ``"two-others"``
        the same without the centroid itself (the point always moves);
    ``"nearest-other"``
        a deterministic chain: each centroid goes to the other centroid nearest the
        predicted point (one arrow per centroid).

    The start is uniform. ``noise_std`` is the standard deviation of ``v`` (the paper
    does not give it); it and ``dt`` must be > 0 (ValueError otherwise); an unknown
    ``chain`` is a ValueError.
    """
    noise_std = as_real(noise_std, "noise_std", 0, low_open=True)
    dt = as_real(dt, "dt", 0, low_open=True)
    if chain not in SPHERE_CHAINS:
        raise ValueError(f"chain must be one of {', '.join(SPHERE_CHAINS)}; got {chain!r}")
    n_next, exclude_self = SPHERE_CHAINS[chain]
    X = mf.sphere_points(n_points, rng)
    man = learn_manifold(X, n_regions, n_prototypes, rng, dim=2)
    C = mf.project_to_sphere(man.prototypes)
    A = transitions_from_velocity_field(C, mf.sphere_velocity, dt, n_next=n_next, project=mf.project_to_sphere,
                                        exclude_self=exclude_self)
    S = len(C)
    return SphereExample(man, C, A, np.full(S, 1.0 / S), float(noise_std), float(dt))


def with_centroids(ex: SphereExample, centroids: object, chain: str) -> SphereExample:
    """``ex`` with other centroids on the sphere and the chain ``chain`` built on them.

    The velocity field, ``dt``, the start distribution's size rule (uniform) and the noise
    are those of ``ex``; the transitions are rebuilt as in :func:`make_sphere_example`
    (``chain`` one of :data:`SPHERE_CHAINS`). ``centroids`` must be a finite ``(S, 3)``
    array with ``S`` equal to ``ex.n_states`` (the start vector is kept; ValueError otherwise).
    """
    chain = as_choice(chain, "chain", tuple(SPHERE_CHAINS))
    C = as_array(centroids, "centroids", ndim=2, shape=(ex.n_states, 3))
    n_next, exclude_self = SPHERE_CHAINS[chain]
    A = transitions_from_velocity_field(C, mf.sphere_velocity, ex.dt, n_next=n_next, project=mf.project_to_sphere,
                                        exclude_self=exclude_self)
    return replace(ex, centroids=C, transitions=A)


def _sphere_trial(rng: np.random.Generator, ex: SphereExample, n_steps: int, methods: tuple[str, ...],
                  with_kalman: bool) -> dict[str, np.ndarray]:
    """One trial of :func:`sphere_trials` (the unit of :func:`projtrack.montecarlo.run`)."""
    sensor = ex.sensor()
    ls, lt = np.log(ex.start), log_transitions(ex.transitions)
    path, y = ex.simulate(n_steps, rng)
    le = sensor.log_likelihoods(y)
    dec = decode_all(ls, lt, le) if set(methods) - {"viterbi"} else {"viterbi": viterbi(ls, lt, le)}
    out = {k: dec[k] == path for k in methods}
    out.update(path=path, y=y[:, 0], viterbi_path=dec["viterbi"])
    ml = np.argmax(le, axis=1)  # per-instant maximum likelihood over the centroids, no motion model
    out["frame_ml"] = ml == path
    out["frame_ml_err"] = np.linalg.norm(ex.centroids[ml] - ex.centroids[path], axis=1)
    out["viterbi_err"] = np.linalg.norm(ex.centroids[dec["viterbi"]] - ex.centroids[path], axis=1)
    out["chance"] = rng.integers(0, ex.n_states, n_steps) == path
    if with_kalman:
        xk = kalman_sphere(y, ex.noise_std, q=ex.dt)
        nearest = np.argmin(((xk[:, None, :] - ex.centroids[None]) ** 2).sum(-1), axis=1)
        out["kalman"] = nearest == path
        out["kalman_err"] = np.linalg.norm(xk - ex.centroids[path], axis=1)
    return out


def sphere_trials(
    ex: SphereExample,
    n_trials: int,
    n_steps: int,
    rng: np.random.Generator,
    *,
    methods: tuple[str, ...] = ("viterbi", "smooth", "filter"),
    with_kalman: bool = False,
) -> dict[str, np.ndarray]:
    """Monte Carlo of Example 1 through :func:`projtrack.montecarlo.run`.

    Each trial draws a state path of ``n_steps`` from the chain and its observations and
    decodes them. Returns ``(n_trials, n_steps)`` arrays:

    * for each of ``methods`` (``"viterbi"``, ``"smooth"``, ``"filter"``), booleans
      "right centroid";
    * ``"frame_ml"``: the same for the per-instant maximum-likelihood centroid (the
      manifold without the motion model) and ``"chance"`` for a uniformly drawn
      centroid (the no-data estimate);
    * ``"viterbi_err"``, ``"frame_ml_err"``: distances to the true centroid;
    * ``"path"``, ``"viterbi_path"`` (ints) and ``"y"`` (observations), to show a draw;
    * with ``with_kalman``, the Kalman baseline's nearest-centroid hits (``"kalman"``)
      and distance errors (``"kalman_err"``).

    ``n_trials`` and ``n_steps`` must be positive ints; ``methods`` a non-empty subset of
    the three decoders (ValueError otherwise). Trial ``i`` uses the ``i``-th child of
    ``rng``, so results do not depend on the number of worker processes.
    """
    n_steps = as_count(n_steps, "n_steps")
    n_trials = as_count(n_trials, "n_trials")
    methods = tuple(methods)
    if not methods or set(methods) - {"viterbi", "smooth", "filter"}:
        raise ValueError(f"methods must be a non-empty subset of ('viterbi', 'smooth', 'filter'), got {methods!r}")
    trials = run(_sphere_trial, int(n_trials), rng, ex, int(n_steps), methods, bool(with_kalman))
    return {k: np.array([t[k] for t in trials]) for k in trials[0]}


def accuracy_summary(right: object) -> dict[str, float]:
    """Reading of a ``(n_trials, n_steps)`` boolean "right centroid" array (Fig. 6's claim).

    Returns the fraction of right centroids at ``t = 1-2``, at ``t >= 3`` and at the last
    two instants (key ``"right, t = {n-1}-{n}"``), and the fraction of trials right at every
    instant after ``t = 2`` (``"perfect after t = 2"``) and at every instant (``"perfect"``).
    ``right`` must be a 2-D array with at least three instants (ValueError otherwise).
    """
    ok = as_array(right, "right", ndim=2, allow_empty=False, dtype=bool)
    n = ok.shape[1]
    if n < 3:
        raise ValueError(f"right must have at least 3 instants (columns), got shape {ok.shape}")
    return {
        "right, t = 1-2": float(ok[:, :2].mean()),
        "right, t >= 3": float(ok[:, 2:].mean()),
        f"right, t = {n - 1}-{n}": float(ok[:, -2:].mean()),
        "perfect after t = 2": float(ok[:, 2:].all(axis=1).mean()),
        "perfect": float(ok.all(axis=1).mean()),
    }


def noise_study(
    models: dict[str, SphereExample],
    noise_stds: tuple[float, ...],
    n_trials: int,
    n_steps: int,
    seed: int,
) -> tuple[list[dict[str, object]], dict[tuple[str, float], dict[str, np.ndarray]]]:
    """Viterbi accuracy of Example 1 for every chain of ``models`` and noise level.

    For each ``(chain, sigma)`` runs :func:`sphere_trials` (Viterbi only) on
    ``models[chain].with_noise(sigma)`` with ``n_trials`` draws of ``n_steps`` from a fresh
    ``numpy.random.default_rng(seed)`` (the same draws of the chain for every noise level).
    Returns the table rows (``chain``, ``sigma`` and :func:`accuracy_summary`) and the raw
    runs keyed by ``(chain, sigma)``. ``models`` and ``noise_stds`` must not be empty.
    """
    if not isinstance(models, dict) or not models:
        raise ValueError("models must be a non-empty dict chain -> SphereExample")
    sigmas = tuple(as_real(s, "noise_stds[i]", 0, low_open=True) for s in noise_stds)
    if not sigmas:
        raise ValueError("noise_stds must not be empty")
    rows: list[dict[str, object]] = []
    runs: dict[tuple[str, float], dict[str, np.ndarray]] = {}
    for chain, model in models.items():
        for sigma, given in zip(sigmas, noise_stds):
            res = sphere_trials(model.with_noise(sigma), n_trials, n_steps, np.random.default_rng(seed),
                                methods=("viterbi",))
            runs[chain, given] = res
            rows.append({"chain": chain, "sigma": given, **accuracy_summary(res["viterbi"])})
    return rows, runs


def kalman_sphere(y: np.ndarray, noise_std: float, *, q: float = 0.3, smooth: bool = True) -> np.ndarray:
    """Baseline that ignores the manifold: a random-walk Kalman filter in R^3.

    State ``x_t = x_{t-1} + w_t``, ``w_t ~ N(0, q^2 I)`` (``q`` about the distance moved per
    step), ``y_t = [1 -1 1] x_t + v_t``; prior ``N(0, I/3)`` (the moments of a uniform
    point on the sphere). With ``smooth`` the RTS smoother is applied (an off-line
    estimator, like Viterbi). Uses :class:`filterpy.kalman.KalmanFilter`.

    ``y`` must be finite (a missing observation is not supported: ValueError rather than a
    silent NaN estimate), ``noise_std`` and ``q`` finite and > 0 (a zero observation
    noise makes the innovation covariance singular at the first step).
    """
    from filterpy.kalman import KalmanFilter

    noise_std = as_real(noise_std, "noise_std", 0, low_open=True)
    q = as_real(q, "q", 0, low_open=True)
    y = np.asarray(y, dtype=float)
    if y.ndim not in (1, 2) or (y.ndim == 2 and y.shape[1] != 1) or y.size == 0:
        raise ValueError(f"y must have shape (N,) or (N, 1) with N >= 1, got {y.shape}")
    if not np.isfinite(y).all():
        raise ValueError("y must be finite (no NaN or inf)")
    y = y.reshape(-1, 1)
    kf = KalmanFilter(dim_x=3, dim_z=1)
    kf.x = np.zeros(3)
    kf.P = np.eye(3) / 3.0
    kf.F = np.eye(3)
    kf.H = H_SPHERE.copy()
    kf.R = np.array([[noise_std**2]])
    kf.Q = q**2 * np.eye(3)
    mu, cov, _, _ = kf.batch_filter(y)
    if smooth:
        mu, _, _, _ = kf.rts_smoother(mu, cov)
    return np.asarray(mu).reshape(len(y), 3)

"""The three examples of Marques et al. (2002), Sec. 4, and baselines that ignore the manifold.

* Example 1 (Fig. 6): a Markov chain on the unit sphere built from a velocity field,
  observed through ``y = [1 -1 1] x + v`` (:func:`make_sphere_example`,
  :func:`sphere_trials`, :func:`kalman_sphere`).
* Example 2 (Figs. 7-8): a car on a road network observed by a range radar
  ``y = cos(omega d) + w`` (eq. (14)) (:func:`make_road_example`,
  :func:`road_trials`, :func:`ekf_range`).
* Example 3 (Fig. 9): slot-car video tracking with the active-pixel sensor of
  eq. (15) (:func:`active_pixels`, :func:`fit_slotcar`).

The paper leaves open the observation noise and the construction of the chain of
Example 1 (:data:`SPHERE_CHAINS`), the road map, receiver, state and noise reading of
Example 2 and the video of Example 3; the choices are documented per function. Every
Monte Carlo study (:func:`sphere_trials`, :func:`road_trials`) runs through
:func:`projtrack.montecarlo.run`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from projtrack.dma.core import (
    DMA,
    ActivePixelSensor,
    DiscreteManifold,
    LinearGaussianSensor,
    RangeCosineSensor,
    estimate_transitions,
    forward_backward,
    forward_filter,
    learn_manifold,
    log_transitions,
    neighbor_graph,
    transitions_from_velocity_field,
    viterbi,
)
from projtrack.scenes import manifolds as mf
from projtrack.scenes.roads import DirectedStates, RoadScene, make_road_scene

__all__ = [
    "H_SPHERE",
    "SPHERE_CHAINS",
    "SphereExample",
    "make_sphere_example",
    "decode_all",
    "sphere_trials",
    "kalman_sphere",
    "RoadExample",
    "make_road_example",
    "road_trials",
    "lost_drives",
    "ekf_range",
    "active_pixels",
    "fit_slotcar",
    "training_background",
]

#: Observation row of Example 1.
H_SPHERE = np.array([[1.0, -1.0, 1.0]])

#: Constructions of the Example 1 chain: name -> (successors per centroid, exclude the centroid itself).
SPHERE_CHAINS: dict[str, tuple[int, bool]] = {
    "two-nearest": (2, False),
    "two-others": (2, True),
    "nearest-other": (1, True),
}


def _positive(value: object, name: str) -> float:
    """``value`` as a float, or ValueError naming ``name`` unless finite and > 0."""
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a number, got {type(value).__name__}") from exc
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def decode_all(log_start: np.ndarray, log_trans: object, log_emission: np.ndarray) -> dict[str, np.ndarray]:
    """Viterbi path, smoothed (forward-backward) and filtered (on-line) argmax paths."""
    post, _ = forward_backward(log_start, log_trans, log_emission)
    return {
        "viterbi": viterbi(log_start, log_trans, log_emission),
        "smooth": np.argmax(post, axis=1),
        "filter": np.argmax(forward_filter(log_start, log_trans, log_emission), axis=1),
    }


# ----------------------------------------------------------------------------------
# Example 1: the sphere
# ----------------------------------------------------------------------------------
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
        from dataclasses import replace

        return replace(self, noise_std=_positive(noise_std, "noise_std"))

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
    noise_std = _positive(noise_std, "noise_std")
    dt = _positive(dt, "dt")
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
    from projtrack.montecarlo import run

    if isinstance(n_steps, bool) or not isinstance(n_steps, (int, np.integer)) or n_steps < 1:
        raise ValueError(f"n_steps must be a positive int, got {n_steps!r}")
    if isinstance(n_trials, bool) or not isinstance(n_trials, (int, np.integer)) or n_trials < 1:
        raise ValueError(f"n_trials must be a positive int, got {n_trials!r}")
    methods = tuple(methods)
    if not methods or set(methods) - {"viterbi", "smooth", "filter"}:
        raise ValueError(f"methods must be a non-empty subset of ('viterbi', 'smooth', 'filter'), got {methods!r}")
    trials = run(_sphere_trial, int(n_trials), rng, ex, int(n_steps), methods, bool(with_kalman))
    return {k: np.array([t[k] for t in trials]) for k in trials[0]}


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

    noise_std = _positive(noise_std, "noise_std")
    q = _positive(q, "q")
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


# ----------------------------------------------------------------------------------
# Example 2: roads
# ----------------------------------------------------------------------------------
@dataclass
class RoadExample:
    """Set-up of Example 2."""

    scene: RoadScene
    states: DirectedStates | None
    points: np.ndarray
    transitions: sp.csr_array
    start: np.ndarray
    receiver: np.ndarray
    omega: float
    noise_var: float

    def sensor(self) -> RangeCosineSensor:
        return RangeCosineSensor(self.points, self.receiver, self.omega, self.noise_var)

    def observe(self, x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Eq. (14): ``y_t = cos(omega d_t) + w_t``."""
        d = np.linalg.norm(x - self.receiver, axis=1)
        return np.cos(self.omega * d) + np.sqrt(self.noise_var) * rng.standard_normal(len(x))


def make_road_example(
    rng: np.random.Generator,
    *,
    directed: bool = True,
    n_train: int = 40,
    train_steps: int = 200,
    heading_scale: float = 30.0,
    receiver_xy: tuple[float, float] = (700.0, 1300.0),
    mast: float = 10.0,
    omega: float = 0.02,
    noise_var: float = 0.05,
    scene_seed: int = 7,
) -> RoadExample:
    """Example 2: a road map, a motion model learned from training drives, a receiver.

    The map is :func:`projtrack.scenes.roads.make_road_scene` with ``scene_seed``. As in
    the paper the map is known, so manifold learning is skipped: the states are road
    points every 10 m. With ``directed`` (default) a state is a road point *and* a
    direction of travel (:meth:`RoadScene.directed_states`); otherwise position only.
    The transition matrix is the relative frequency of state transitions in ``n_train``
    training drives of ``train_steps`` s (eqs. (10)-(13)), smoothed with pseudo-count
    1e-3 on neighbouring states (same direction within 25 m; for position-only states,
    road neighbours up to two hops). The receiver stands ``mast`` m above the ground at
    ``receiver_xy``. ``omega = 0.02`` and ``noise_var = 0.05`` as in eq. (14) (the
    paper's ``sigma^2 = 0.05`` read as the variance).
    """
    scene = make_road_scene(np.random.default_rng(scene_seed))
    train = [scene.drive(train_steps, rng) for _ in range(n_train)]
    if directed:
        states = scene.directed_states(heading_scale)
        points = states.positions
        seqs = [states.quantize(t) for t in train]
        nb = neighbor_graph(states.features, 25.0)
    else:
        from scipy.spatial import cKDTree

        states = None
        points = scene.prototypes
        tree = cKDTree(points)
        seqs = [tree.query(t)[1] for t in train]
        adj = scene.adjacency
        nb = adj + adj @ adj
    S = len(points)
    A = estimate_transitions(seqs, S, alpha=1e-3, neighbors=nb)
    rxy = np.asarray(receiver_xy, dtype=float)
    receiver = np.array([rxy[0], rxy[1], float(scene.elevation(rxy)) + mast])
    return RoadExample(scene, states, points, A, np.full(S, 1.0 / S), receiver, float(omega), float(noise_var))


def _road_trial(rng: np.random.Generator, ex: RoadExample, n_steps: int, with_ekf: bool) -> dict[str, np.ndarray]:
    """One drive of :func:`road_trials` (the unit of :func:`projtrack.montecarlo.run`)."""
    sensor = ex.sensor()
    ls, lt = np.log(ex.start), log_transitions(ex.transitions)
    x = ex.scene.drive(n_steps, rng)
    y = ex.observe(x, rng)
    dec = decode_all(ls, lt, sensor.log_likelihoods(y))
    out = {k: np.linalg.norm(ex.points[v] - x, axis=1) for k, v in dec.items()}
    if with_ekf:
        est = ekf_range(y, ex.receiver, ex.omega, ex.noise_var, x0=x[0, :2], v0=(x[1, :2] - x[0, :2]),
                        height=float(ex.receiver[2] - x[:, 2].mean()))
        out["ekf"] = np.linalg.norm(est - x[:, :2], axis=1)
    return out


def road_trials(ex: RoadExample, n_trials: int, n_steps: int, rng: np.random.Generator, *, with_ekf: bool = False) -> dict[str, np.ndarray]:
    """Monte Carlo of Example 2 through :func:`projtrack.montecarlo.run`.

    Each trial is a new drive of ``n_steps`` seconds and its observations (eq. (14)),
    decoded by Viterbi, smoothing and filtering (and the road-ignoring EKF if
    ``with_ekf``). Returns position errors in m, ``(n_trials, n_steps)``, per method.
    ``n_trials`` and ``n_steps`` (>= 2) must be positive ints (ValueError otherwise).
    """
    from projtrack.montecarlo import run

    if isinstance(n_trials, bool) or not isinstance(n_trials, (int, np.integer)) or n_trials < 1:
        raise ValueError(f"n_trials must be a positive int, got {n_trials!r}")
    if isinstance(n_steps, bool) or not isinstance(n_steps, (int, np.integer)) or n_steps < 2:
        raise ValueError(f"n_steps must be an int >= 2, got {n_steps!r}")
    trials = run(_road_trial, int(n_trials), rng, ex, int(n_steps), bool(with_ekf))
    return {k: np.array([t[k] for t in trials]) for k in trials[0]}


def lost_drives(errors: np.ndarray, *, distance: float = 50.0, fraction: float = 0.1) -> np.ndarray:
    """Which drives lock onto a wrong road: more than ``fraction`` of their instants
    farther than ``distance`` (m) from the truth.

    ``errors`` is an ``(n_drives, n_steps)`` array of position errors (as returned by
    :func:`road_trials`); returns an ``(n_drives,)`` boolean array. ``distance`` must be
    > 0 and ``fraction`` in [0, 1) (ValueError otherwise).
    """
    e = np.asarray(errors, dtype=float)
    if e.ndim != 2 or e.size == 0:
        raise ValueError(f"errors must be a non-empty (n_drives, n_steps) array, got shape {e.shape}")
    if not np.isfinite(e).all() or (e < 0).any():
        raise ValueError("errors must be finite and >= 0")
    distance = _positive(distance, "distance")
    if not (0 <= fraction < 1):
        raise ValueError(f"fraction must be in [0, 1), got {fraction!r}")
    return (e > distance).mean(axis=1) > fraction


def ekf_range(
    y: np.ndarray,
    receiver: np.ndarray,
    omega: float,
    noise_var: float,
    *,
    x0: np.ndarray,
    v0: np.ndarray,
    height: float,
    accel_std: float = 1.0,
    dt: float = 1.0,
) -> np.ndarray:
    """Baseline that ignores the roads: an extended Kalman filter in the plane.

    Constant-velocity model (state ``x, y, vx, vy``, white acceleration ``accel_std``
    m/s^2), measurement ``cos(omega sqrt((x - rx)^2 + (y - ry)^2 + height^2))`` with
    variance ``noise_var``. It is *given the true initial position and velocity*
    (``x0``, ``v0``, small initial covariance): a generous start, so a failure is not
    due to initialisation. Uses :class:`filterpy.kalman.ExtendedKalmanFilter`.
    Returns ``(N, 2)`` filtered positions.
    """
    from filterpy.common import Q_discrete_white_noise
    from filterpy.kalman import ExtendedKalmanFilter

    r = np.asarray(receiver, dtype=float)[:2]

    def dist(s: np.ndarray) -> float:
        return float(np.sqrt((s[0] - r[0]) ** 2 + (s[1] - r[1]) ** 2 + height**2))

    def hx(s: np.ndarray) -> np.ndarray:
        return np.array([np.cos(omega * dist(s))])

    def jac(s: np.ndarray) -> np.ndarray:
        d = dist(s)
        g = -np.sin(omega * d) * omega / d
        return np.array([[g * (s[0] - r[0]), g * (s[1] - r[1]), 0.0, 0.0]])

    ekf = ExtendedKalmanFilter(dim_x=4, dim_z=1)
    ekf.x = np.array([x0[0], x0[1], v0[0], v0[1]], dtype=float)
    ekf.P = np.diag([25.0, 25.0, 4.0, 4.0])
    ekf.F = np.array([[1, 0, dt, 0], [0, 1, 0, dt], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)
    q = Q_discrete_white_noise(dim=2, dt=dt, var=accel_std**2)
    ekf.Q = np.zeros((4, 4))
    ekf.Q[np.ix_([0, 2], [0, 2])] = q
    ekf.Q[np.ix_([1, 3], [1, 3])] = q
    ekf.R = np.array([[noise_var]])
    out = np.empty((len(y), 2))
    for t, yt in enumerate(np.asarray(y, dtype=float)):
        if t > 0:
            ekf.predict()
        ekf.update(np.array([yt]), jac, hx)
        out[t] = ekf.x[:2]
    return out


# ----------------------------------------------------------------------------------
# Example 3: slot-car video
# ----------------------------------------------------------------------------------
def active_pixels(frames: np.ndarray, threshold: float, background: np.ndarray | None = None) -> np.ndarray:
    """Background subtraction and thresholding (Sec. 4.3): ``|frame - background| > threshold``.

    The background defaults to the per-pixel median of the frames (the car moves, so the
    median is the empty scene)."""
    F = np.asarray(frames, dtype=float)
    if F.ndim != 3:
        raise ValueError(f"frames must have shape (N, H, W), got {F.shape}")
    if not np.isfinite(F).all():
        raise ValueError("frames must be finite")
    bg = np.median(F, axis=0) if background is None else np.asarray(background, dtype=float)
    if bg.shape != F.shape[1:]:
        raise ValueError(f"background must have shape {F.shape[1:]}, got {bg.shape}")
    return np.abs(F - bg) > threshold


def training_background(train_videos: list) -> np.ndarray:
    """The background image of Example 3 from the training runs only: the per-pixel
    median of all their frames (the car moves, so the median is the empty scene).

    ``train_videos`` is a non-empty list of objects with a ``frames`` array ``(N, H, W)``
    (e.g. :class:`projtrack.scenes.slotcar.SlotCarVideo`) of one frame size
    (ValueError otherwise)."""
    if not isinstance(train_videos, (list, tuple)) or not train_videos:
        raise ValueError("train_videos must be a non-empty list of videos")
    frames = [np.asarray(getattr(v, "frames", None), dtype=float) for v in train_videos]
    if any(f.ndim != 3 for f in frames) or len({f.shape[1:] for f in frames}) != 1:
        raise ValueError("every training video must have frames of shape (N, H, W) with one frame size")
    return np.median(np.concatenate(frames), axis=0)


def fit_slotcar(
    train_videos: list,
    rng: np.random.Generator,
    *,
    n_regions: int = 8,
    n_prototypes: int = 8,
    box: int = 5,
    threshold: float = 0.15,
    annotation_std: float = 0.5,
    background: np.ndarray | None = None,
) -> tuple[DMA, ActivePixelSensor]:
    """Example 3 training: DMA on hand-annotated car positions, ``c`` of eq. (15) from frames.

    The paper annotated the training runs by hand; here the generator's true positions
    plus ``N(0, annotation_std^2)`` pixel noise stand in for the annotation. The
    manifold (1-D local frames), the transition matrix, the start distribution (state
    frequencies of the training runs, :func:`projtrack.dma.estimate_start`) and ``c``
    (see :meth:`ActivePixelSensor.fit_c`) are all learned from the training runs only.
    The active pixels of the training frames are taken against ``background``
    (default: :func:`training_background` of ``train_videos``); use the same image for
    the test video.
    """
    trajs = [v.positions + annotation_std * rng.standard_normal(v.positions.shape) for v in train_videos]
    model = DMA(n_regions=n_regions, n_prototypes=n_prototypes, dim=1, rng=rng).fit(trajs)
    bg = training_background(train_videos) if background is None else background
    act = np.concatenate([active_pixels(v.frames, threshold, bg) for v in train_videos])
    pos = np.concatenate(trajs)
    c = ActivePixelSensor.fit_c(act, pos, box)
    return model, ActivePixelSensor(model.prototypes_, box, c)

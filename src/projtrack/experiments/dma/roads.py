"""Example 2 of Marques et al. (2002), Figs. 7-8: a car on a road network and a range radar.

The road map, the motion model learned from training drives and the receiver of eq. (14)
``y = cos(omega d) + w`` (:func:`make_road_example`), the Monte Carlo of drives
(:func:`road_trials`), the lost-drive reading (:func:`lost_drives`) and the road-ignoring
EKF baseline (:func:`ekf_range`). The paper leaves open the road map, the receiver, the
state and the noise reading; the choices are documented per function.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_array, as_count, as_int, as_real
from projtrack.dma import RangeCosineSensor, estimate_transitions, log_transitions, neighbor_graph, viterbi
from projtrack.experiments.dma.decoding import decode_all
from projtrack.montecarlo import run
from projtrack.stable import fmt
from projtrack.tolerance import Tolerance, statistical
from projtrack.scenes.roads import DirectedStates, RoadScene, make_road_scene

__all__ = [
    "RoadExample",
    "make_road_example",
    "road_trials",
    "lost_drives",
    "error_summary",
    "block_summary",
    "no_data_errors",
    "ekf_range",
    "ROAD_STATES",
    "ROAD_NOISE",
    "median_shift_bound",
    "median_tolerance",
    "reading_study",
    "share_interval",
]


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
    speed: float = 12.0
    dt: float = 1.0

    def drive(self, n_steps: int, rng: np.random.Generator) -> np.ndarray:
        """A test drive of ``n_steps`` positions at this example's speed and sampling interval."""
        return self.scene.drive(n_steps, rng, speed=self.speed, dt=self.dt)

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
    speed: float = 12.0,
    dt: float = 1.0,
) -> RoadExample:
    """Example 2: a road map, a motion model learned from training drives, a receiver.

    The map is :func:`projtrack.scenes.roads.make_road_scene` with ``scene_seed``. As in
    the paper the map is known, so manifold learning is skipped: the states are road
    points every 10 m. With ``directed`` (default) a state is a road point *and* a
    direction of travel (:meth:`RoadScene.directed_states`); otherwise position only.
    The transition matrix is the relative frequency of state transitions in ``n_train``
    training drives of ``train_steps`` samples (eqs. (10)-(13)) at the mean ``speed`` (m/s)
    and sampling interval ``dt`` (s) of the test drives (:meth:`RoadExample.drive`), smoothed with pseudo-count
    1e-3 on neighbouring states (same direction within 25 m; for position-only states,
    road neighbours up to two hops). The receiver stands ``mast`` m above the ground at
    ``receiver_xy``. ``omega = 0.02`` and ``noise_var = 0.05`` as in eq. (14) (the
    paper's ``sigma^2 = 0.05`` read as the variance). ``speed``, ``dt`` and ``noise_var``
    must be > 0 (ValueError otherwise).
    """
    speed = as_real(speed, "speed", 0, low_open=True)
    dt = as_real(dt, "dt", 0, low_open=True)
    noise_var = as_real(noise_var, "noise_var", 0, low_open=True)
    scene = make_road_scene(np.random.default_rng(scene_seed))
    train = [scene.drive(train_steps, rng, speed=speed, dt=dt) for _ in range(n_train)]
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
    return RoadExample(scene, states, points, A, np.full(S, 1.0 / S), receiver, float(omega), float(noise_var),
                       float(speed), float(dt))


def _road_trial(rng: np.random.Generator, ex: RoadExample, n_steps: int, with_ekf: bool,
                methods: tuple[str, ...]) -> dict[str, np.ndarray]:
    """One drive of :func:`road_trials` (the unit of :func:`projtrack.montecarlo.run`)."""
    sensor = ex.sensor()
    ls, lt = np.log(ex.start), log_transitions(ex.transitions)
    x = ex.drive(n_steps, rng)
    y = ex.observe(x, rng)
    le = sensor.log_likelihoods(y)
    if not methods:
        dec = {}
    elif set(methods) - {"viterbi"}:
        dec = decode_all(ls, lt, le)
    else:
        dec = {"viterbi": viterbi(ls, lt, le)}
    out = {k: np.linalg.norm(ex.points[dec[k]] - x, axis=1) for k in methods}
    if with_ekf:
        est = ekf_range(y, ex.receiver, ex.omega, ex.noise_var, x0=x[0, :2], v0=(x[1, :2] - x[0, :2]) / ex.dt,
                        height=float(ex.receiver[2] - x[:, 2].mean()), dt=ex.dt)
        out["ekf"] = np.linalg.norm(est - x[:, :2], axis=1)
    return out


def road_trials(ex: RoadExample, n_trials: int, n_steps: int, rng: np.random.Generator, *, with_ekf: bool = False,
                methods: tuple[str, ...] = ("viterbi", "smooth", "filter")) -> dict[str, np.ndarray]:
    """Monte Carlo of Example 2 through :func:`projtrack.montecarlo.run`.

    Each trial is a new drive of ``n_steps`` samples (:meth:`RoadExample.drive`) and its
    observations (eq. (14)), decoded by ``methods`` (Viterbi, smoothing, filtering; and the
    road-ignoring EKF if ``with_ekf``). Returns position errors in m,
    ``(n_trials, n_steps)``, per method. ``n_trials`` and ``n_steps`` (>= 2) must be
    positive ints and ``methods`` a subset of the three decoders, empty only with
    ``with_ekf`` (the EKF alone; ValueError otherwise).
    """
    n_trials = as_count(n_trials, "n_trials")
    n_steps = as_count(n_steps, "n_steps", minimum=2)
    methods = tuple(methods)
    if set(methods) - {"viterbi", "smooth", "filter"} or not (methods or with_ekf):
        raise ValueError(f"methods must be a subset of ('viterbi', 'smooth', 'filter'), empty only with with_ekf, "
                         f"got {methods!r}")
    trials = run(_road_trial, int(n_trials), rng, ex, int(n_steps), bool(with_ekf), methods)
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
    distance = as_real(distance, "distance", 0, low_open=True)
    fraction = as_real(fraction, "fraction", 0, 1, high_open=True)
    return (e > distance).mean(axis=1) > fraction


def _errors(errors: object) -> np.ndarray:
    e = as_array(errors, "errors", ndim=2, allow_empty=False)
    if (e < 0).any():
        raise ValueError("errors must be >= 0")
    return e


def error_summary(errors: object) -> dict[str, object]:
    """Reading of Fig. 8's claim on ``(n_drives, n_steps)`` position errors (m).

    Median and mean error, mean error of the drives not lost, the number and fraction of
    lost drives (:func:`lost_drives`) and a 95% Clopper-Pearson interval of that fraction
    (formatted ``"low-high"``). ``errors`` must be a non-empty finite 2-D array >= 0.
    """
    from scipy.stats import binomtest

    e = _errors(errors)
    lost = lost_drives(e)
    n = len(e)
    ci = binomtest(int(lost.sum()), n).proportion_ci(0.95)
    return {"median error [m]": float(np.median(e)), "mean error [m]": float(e.mean()),
            "mean error, drives not lost [m]": float(e[~lost].mean()) if (~lost).any() else np.nan,
            "lost drives": int(lost.sum()), "lost fraction": float(lost.mean()),
            "lost, 95% CI": f"{fmt(ci.low, '.2f')}-{fmt(ci.high, '.2f')}"}


def block_summary(errors: object, block: int = 100) -> list[dict[str, object]]:
    """Lost drives, median and mean error per block of ``block`` consecutive drives.

    Shows how much the lost count of Fig. 8 varies between draws. The number of drives
    must be a multiple of ``block`` (an int >= 1; ValueError otherwise).
    """
    e = _errors(errors)
    block = as_count(block, "block")
    if len(e) % block:
        raise ValueError(f"the number of drives ({len(e)}) must be a multiple of block ({block})")
    lost = lost_drives(e)
    rows = []
    for a in range(0, len(e), block):
        blk = slice(a, a + block)
        rows.append({"drives": f"{a + 1}-{a + block}", "lost drives": int(lost[blk].sum()),
                     "median error [m]": float(np.median(e[blk])), "mean error [m]": float(e[blk].mean())})
    return rows


def _no_data_trial(rng: np.random.Generator, ex: RoadExample, n_steps: int, guess: np.ndarray) -> np.ndarray:
    """One drive of :func:`no_data_errors` (the unit of :func:`projtrack.montecarlo.run`)."""
    return np.linalg.norm(ex.drive(n_steps, rng) - guess, axis=1)


def no_data_errors(ex: RoadExample, n_trials: int, n_steps: int, rng: np.random.Generator) -> np.ndarray:
    """Errors (m) of the no-data estimate of Example 2: always the state nearest the receiver.

    The drives are those of :func:`road_trials` with the same ``rng`` (trial ``i`` draws
    its drive first from the ``i``-th child of ``rng``). Returns ``(n_trials, n_steps)``.
    ``n_trials`` must be an int >= 1 and ``n_steps`` >= 2 (ValueError otherwise).
    """
    n_trials = as_count(n_trials, "n_trials")
    n_steps = as_count(n_steps, "n_steps", minimum=2)
    guess = ex.points[np.argmin(np.linalg.norm(ex.points - ex.receiver, axis=1))]
    return np.array(run(_no_data_trial, n_trials, rng, ex, n_steps, guess))


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


#: The readings of Example 2 that the speed and sampling study compares: label -> options of
#: :func:`make_road_example`. "position" is the literal method (a state per road point).
ROAD_STATES: dict[str, dict[str, object]] = {"position": {"directed": False},
                                             "position and heading": {"directed": True}}
#: The two readings of the paper's noise "w ~ N(0, omega^2 = 0.05)" (a variance or, the exponent a slip, a
#: standard deviation): label -> noise variance.
ROAD_NOISE: dict[str, float] = {"variance 0.05": 0.05, "std 0.05": 0.05**2}


def median_shift_bound(errors: object) -> float:
    """How far the median of all errors can move when one drive's errors change arbitrarily.

    ``errors`` is ``(n_drives, n_steps)``; replacing one drive's ``n_steps`` values moves the
    median of all values by at most ``n_steps`` order statistics, so by at most the larger of
    the gaps between the median and the order statistics ``n_steps`` below and above it.
    This is the size of one flipped Viterbi path (one drive) for the median error.
    """
    e = _errors(errors)
    q = np.sort(e.ravel())
    k, m = (len(q) - 1) // 2, e.shape[1]
    lo, hi = q[max(k - m, 0)], q[min(k + m + 1, len(q) - 1)]
    return float(max(q[k] - lo, hi - q[k]))


def _reading_trial(rng: np.random.Generator, ex: RoadExample, n_steps: int) -> np.ndarray:
    return _road_trial(rng, ex, n_steps, False, ("viterbi",))["viterbi"]


def reading_study(
    readings: list[tuple[str, str, float, float]],
    n_drives: int,
    duration: float,
    *,
    train_seed: int = 20,
    drive_seed: int = 22,
) -> tuple[list[dict[str, object]], dict[tuple[str, str, float, float], np.ndarray]]:
    """Example 2 under several readings of what the paper leaves open (Fig. 8).

    Each reading is ``(states, noise, speed, dt)``: ``states`` a key of :data:`ROAD_STATES`,
    ``noise`` a key of :data:`ROAD_NOISE`, the mean ``speed`` (m/s) and the sampling interval
    ``dt`` (s). For each, :func:`make_road_example` (training drives from
    ``numpy.random.default_rng(train_seed)``) and ``n_drives`` test drives of ``duration``
    seconds (``round(duration / dt)`` samples, from ``numpy.random.default_rng(drive_seed)``),
    decoded by Viterbi. Returns the table rows (the reading, the travel per sample, the
    median error, the share of lost drives, :func:`lost_drives`, whether at least half of the
    drives follow the route (``"most follow"``: lost share at most 0.5, the book's reading of
    a single shown run) and whether the reading passes the stricter first criterion of the
    Example 2 page (``"follows"``: median below 20 m and at most 10% of the drives lost)) and
    the errors per reading. Unknown labels, an empty list, ``n_drives < 1`` or a ``duration`` shorter
    than two samples are a ValueError.
    """
    n_drives = as_count(n_drives, "n_drives")
    duration = as_real(duration, "duration", 0, low_open=True)
    if not readings:
        raise ValueError("readings must not be empty")
    rows: list[dict[str, object]] = []
    errors: dict[tuple[str, str, float, float], np.ndarray] = {}
    for states, noise, speed, dt in readings:
        if states not in ROAD_STATES or noise not in ROAD_NOISE:
            raise ValueError(f"unknown reading {(states, noise)}: states in {list(ROAD_STATES)}, "
                             f"noise in {list(ROAD_NOISE)}")
        n_steps = int(round(duration / as_real(dt, "dt", 0, low_open=True)))
        if n_steps < 2:
            raise ValueError(f"duration {duration} s gives fewer than two samples at dt = {dt} s")
        model = make_road_example(np.random.default_rng(train_seed), noise_var=ROAD_NOISE[noise], speed=speed, dt=dt,
                                  **ROAD_STATES[states])  # type: ignore[arg-type]
        e = np.array(run(_reading_trial, n_drives, np.random.default_rng(drive_seed), model, n_steps))
        errors[states, noise, speed, dt] = e
        lost = lost_drives(e)
        med = float(np.median(e))
        rows.append({"states": states, "noise": noise, "speed [m/s]": float(speed), "interval [s]": float(dt),
                     "m per sample": float(speed * dt), "median error [m]": med, "lost share": float(lost.mean()),
                     "most follow": bool(lost.mean() <= 0.5), "follows": bool(med < 20 and lost.mean() <= 0.1)})
    return rows, errors


def median_tolerance(errors: list) -> Tolerance:
    """The tolerance of a column of median errors, one ``(n_drives, n_steps)`` array per row.

    One drive whose Viterbi path changes moves a row's median by at most
    :func:`median_shift_bound`; the tolerance is that bound relative to the row's median, the
    largest over the rows (rounded up to a whole percent), so every row is covered and rows
    with small medians keep a small allowance. ``errors`` must not be empty and no median may
    be zero (ValueError otherwise).
    """
    if not errors:
        raise ValueError("errors must hold one (n_drives, n_steps) array per row")
    ratios = []
    for e in errors:
        med = float(np.median(_errors(e)))
        if med <= 0:
            raise ValueError("a median error of zero cannot carry a relative tolerance")
        ratios.append(median_shift_bound(e) / med)
    rtol = float(np.ceil(100 * max(ratios)) / 100)
    return statistical(rtol=rtol, why=f"one drive's Viterbi path changing moves a median of all its instants by at "
                                      f"most n_steps order statistics: at most {rtol:.0%} of the median in every row")


def share_interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper-Pearson) ``level`` interval of a share of ``k`` successes in ``n`` trials.

    ``k`` and ``n`` are ints with ``0 <= k <= n`` and ``n >= 1``, ``level`` in (0, 1)
    (ValueError otherwise). For example 0 lost drives of 15 give (0, 0.218): a share of
    zero from 15 drives cannot tell a 10% threshold apart.
    """
    from scipy.stats import beta

    n = as_count(n, "n")
    k = as_int(k, "k", minimum=0)
    if k > n:
        raise ValueError(f"k must be at most n = {n}, got {k}")
    level = as_real(level, "level", 0, low_open=True)
    if level >= 1:
        raise ValueError(f"level must be < 1, got {level}")
    a = 1 - level
    low = 0.0 if k == 0 else float(beta.ppf(a / 2, k, n - k + 1))
    high = 1.0 if k == n else float(beta.ppf(1 - a / 2, k + 1, n - k))
    return low, high

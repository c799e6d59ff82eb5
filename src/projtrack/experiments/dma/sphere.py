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
    "chain_stats",
    "chain_sensitivity",
    "chain_process_std",
    "field_smoother",
    "baseline_trials",
    "rate_spread",
    "f6_verdict",
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
    drift: float = 0.3
    width: float = 1.0

    @property
    def n_states(self) -> int:
        return len(self.centroids)

    def velocity(self, x: np.ndarray) -> np.ndarray:
        """The velocity field of the example (:func:`projtrack.scenes.manifolds.sphere_velocity`
        with this example's ``drift``)."""
        return mf.sphere_velocity(x, drift=self.drift)

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
    drift: float = 0.3,
    width: float = 1.0,
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
    does not give it); ``drift`` the poleward drift of the field (>= 0) and ``width`` the
    width of the transition weights in centroid spacings (> 0), both open choices too.
    ``noise_std`` and ``dt`` must be > 0 (ValueError otherwise); an unknown ``chain`` is a
    ValueError.
    """
    noise_std = as_real(noise_std, "noise_std", 0, low_open=True)
    dt = as_real(dt, "dt", 0, low_open=True)
    drift = as_real(drift, "drift", 0)
    width = as_real(width, "width", 0, low_open=True)
    if chain not in SPHERE_CHAINS:
        raise ValueError(f"chain must be one of {', '.join(SPHERE_CHAINS)}; got {chain!r}")
    X = mf.sphere_points(n_points, rng)
    man = learn_manifold(X, n_regions, n_prototypes, rng, dim=2)
    C = mf.project_to_sphere(man.prototypes)
    S = len(C)
    ex = SphereExample(man, C, sp.csr_array((S, S)), np.full(S, 1.0 / S), float(noise_std), float(dt),
                       float(drift), float(width))
    return replace(ex, transitions=_chain(ex, C, chain))


def _chain(ex: SphereExample, C: np.ndarray, chain: str) -> sp.csr_array:
    """The transitions of construction ``chain`` on centroids ``C`` with the field, ``dt`` and
    weight width of ``ex``."""
    from scipy.spatial import cKDTree

    n_next, exclude_self = SPHERE_CHAINS[chain]
    spacing = float(np.median(cKDTree(C).query(C, k=2)[0][:, 1]))
    return transitions_from_velocity_field(C, ex.velocity, ex.dt, n_next=n_next, project=mf.project_to_sphere,
                                           exclude_self=exclude_self, width=ex.width * spacing)


def with_centroids(ex: SphereExample, centroids: object, chain: str) -> SphereExample:
    """``ex`` with other centroids on the sphere and the chain ``chain`` built on them.

    The velocity field, ``dt``, the weight width, the start distribution's size rule
    (uniform) and the noise are those of ``ex``; the transitions are rebuilt as in :func:`make_sphere_example`
    (``chain`` one of :data:`SPHERE_CHAINS`). ``centroids`` must be a finite ``(S, 3)``
    array with ``S`` equal to ``ex.n_states`` (the start vector is kept; ValueError otherwise).
    """
    chain = as_choice(chain, "chain", tuple(SPHERE_CHAINS))
    C = as_array(centroids, "centroids", ndim=2, shape=(ex.n_states, 3))
    return replace(ex, centroids=C, transitions=_chain(ex, C, chain))


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


def chain_stats(ex: SphereExample) -> dict[str, float]:
    """How much the chain of ``ex`` branches: the mean self-loop probability, the mean largest
    transition probability of a state (1 for a deterministic chain, 0.5 for two equal
    successors) and the mean number of successors."""
    A = sp.csr_array(ex.transitions)
    rows = [A.data[A.indptr[i]:A.indptr[i + 1]] for i in range(A.shape[0])]
    return {"self-loop": float(A.diagonal().mean()),
            "largest transition": float(np.mean([r.max() for r in rows])),
            "successors": float(np.mean([len(r) for r in rows]))}


def chain_sensitivity(
    variants: dict[str, dict[str, float]],
    n_trials: int,
    n_steps: int,
    *,
    seed: int = 12,
    model_seed: int = 10,
    chain: str = "two-nearest",
    noise_std: float = 0.1,
) -> list[dict[str, object]]:
    """Viterbi accuracy of Example 1 when the open choices of the chain change.

    ``variants`` maps a label to options of :func:`make_sphere_example` (``dt``, ``drift``,
    ``width``; the others default). Each variant is built from
    ``numpy.random.default_rng(model_seed)`` (the same centroids) with chain ``chain`` and
    decoded on ``n_trials`` draws of ``n_steps`` from ``numpy.random.default_rng(seed)``.
    Each row gives the label, :func:`chain_stats` and the ``"right, t >= 3"`` and
    ``"perfect after t = 2"`` fractions of :func:`accuracy_summary`. ``variants`` must not
    be empty (ValueError otherwise).
    """
    if not isinstance(variants, dict) or not variants:
        raise ValueError("variants must be a non-empty dict label -> options of make_sphere_example")
    rows: list[dict[str, object]] = []
    for label, opts in variants.items():
        m = make_sphere_example(np.random.default_rng(model_seed), noise_std=noise_std, chain=chain, **opts)
        s = accuracy_summary(sphere_trials(m, n_trials, n_steps, np.random.default_rng(seed),
                                           methods=("viterbi",))["viterbi"])
        st = chain_stats(m)
        rows.append({"variant": label, "self-loop": st["self-loop"], "largest transition": st["largest transition"],
                     "right, t >= 3": s["right, t >= 3"], "perfect after t = 2": s["perfect after t = 2"]})
    return rows


def chain_process_std(ex: SphereExample) -> float:
    """Per-axis standard deviation of the chain's step around the field's prediction.

    For each centroid ``u_l`` the chain moves to ``u_k`` with probability ``a_lk``; the field
    predicts ``u_l + dt v(u_l)``. Returns ``sqrt(mean_l sum_k a_lk |u_k - pred_l|^2 / 3)``:
    the process noise a Kalman smoother that knows the field needs to describe the chain.
    """
    A = sp.coo_array(ex.transitions)
    C = ex.centroids
    pred = C + ex.dt * ex.velocity(C)
    d2 = ((C[A.col] - pred[A.row]) ** 2).sum(axis=1)
    per_state = np.bincount(A.row, weights=A.data * d2, minlength=len(C))
    return float(np.sqrt(per_state.mean() / 3.0))


def field_smoother(y: np.ndarray, noise_std: float, dt: float, *, drift: float = 0.3, q: float = 0.1,
                   x0: np.ndarray | None = None) -> np.ndarray:
    """A baseline that knows the exact velocity field but not the sphere: an extended Kalman
    filter and Rauch-Tung-Striebel smoother in R^3.

    State ``x_t = x_{t-1} + dt v(x_{t-1}) + w_t`` with ``v`` of
    :func:`projtrack.scenes.manifolds.sphere_velocity` (``drift``; rotation about ``z``) and
    ``w_t ~ N(0, q^2 I)``; ``y_t = [1 -1 1] x_t + v_t``, ``v_t ~ N(0, noise_std^2)``. The prior is
    ``N(0, I/3)`` (a uniform point on the sphere), or, with ``x0``, the true start with a
    covariance of ``1e-4 I`` (a generous start). Nothing keeps the estimate on the sphere.
    Returns the smoothed states ``(N, 3)``. ``y`` must be finite and ``noise_std``, ``dt`` and
    ``q`` > 0 (ValueError otherwise).
    """
    noise_std = as_real(noise_std, "noise_std", 0, low_open=True)
    dt = as_real(dt, "dt", 0, low_open=True)
    q = as_real(q, "q", 0, low_open=True)
    drift = as_real(drift, "drift", 0)
    y = as_array(y, "y", allow_empty=False).reshape(-1)
    H = H_SPHERE[0]
    k = np.array([0.0, 0.0, 1.0])
    Kx = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])  # x -> k cross x
    Q, R, eye = q**2 * np.eye(3), noise_std**2, np.eye(3)
    if x0 is None:
        x, P = np.zeros(3), eye / 3.0
    else:
        x, P = as_array(x0, "x0", ndim=1, shape=(3,)).copy(), 1e-4 * eye
    n = len(y)
    xf, Pf, xp, Pp, Fs = np.empty((n, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, 3, 3)), []
    for t in range(n):
        if t > 0:
            F = eye + dt * (Kx - drift * (np.outer(x, k) + (k @ x) * eye))
            x = x + dt * mf.sphere_velocity(x, drift=drift)
            P = F @ P @ F.T + Q
            Fs.append(F)
        xp[t], Pp[t] = x, P
        S = float(H @ P @ H) + R
        G = P @ H / S
        x = x + G * (y[t] - float(H @ x))
        P = (eye - np.outer(G, H)) @ P
        xf[t], Pf[t] = x, P
    xs = xf.copy()
    for t in range(n - 2, -1, -1):
        C = Pf[t] @ Fs[t].T @ np.linalg.inv(Pp[t + 1])
        xs[t] = xf[t] + C @ (xs[t + 1] - xp[t + 1])
    return xs


def _baseline_trial(rng: np.random.Generator, ex: SphereExample, n_steps: int, q: float) -> dict[str, np.ndarray]:
    """One trial of :func:`baseline_trials`."""
    out = _sphere_trial(rng, ex, n_steps, ("viterbi", "smooth", "filter"), True)
    path, y = out["path"], out["y"]
    C = ex.centroids

    def hits(X: np.ndarray) -> np.ndarray:
        return np.argmin(((X[:, None, :] - C[None]) ** 2).sum(-1), axis=1) == path

    out["field"] = hits(field_smoother(y, ex.noise_std, ex.dt, drift=ex.drift, q=q))
    out["field_start"] = hits(field_smoother(y, ex.noise_std, ex.dt, drift=ex.drift, q=q, x0=C[path[0]]))
    return out


def baseline_trials(ex: SphereExample, n_trials: int, n_steps: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Example 1 with every estimator: :func:`sphere_trials` (the three DMA decoders, the
    per-instant maximum-likelihood centroid, chance and the random-walk Kalman smoother,
    :func:`kalman_sphere`) plus the smoother that knows the field (:func:`field_smoother`,
    with ``q`` from :func:`chain_process_std`), without (``"field"``) and with
    (``"field_start"``) the true start. Returns ``(n_trials, n_steps)`` arrays as
    :func:`sphere_trials`; trial ``i`` uses the ``i``-th child of ``rng``."""
    n_trials = as_count(n_trials, "n_trials")
    n_steps = as_count(n_steps, "n_steps")
    trials = run(_baseline_trial, n_trials, rng, ex, n_steps, chain_process_std(ex))
    return {k: np.array([t[k] for t in trials]) for k in trials[0]}


def rate_spread(right: object, *, batch: int = 100, first: int = 2) -> dict[str, float]:
    """The share of right centroids after the first ``first`` instants and how it varies.

    ``right`` is an ``(n_trials, n_steps)`` boolean array. Returns the share (``"mean"``), a
    95% interval from the spread of the per-trial shares (normal approximation,
    ``"low"``/``"high"``) and the smallest and largest share over consecutive batches of
    ``batch`` trials (``"batch min"``/``"batch max"``). The number of trials must be a
    multiple of ``batch`` (ValueError otherwise).
    """
    ok = as_array(right, "right", ndim=2, allow_empty=False, dtype=bool)
    batch = as_count(batch, "batch")
    if len(ok) % batch:
        raise ValueError(f"the number of trials ({len(ok)}) must be a multiple of batch ({batch})")
    per = ok[:, first:].mean(axis=1)
    half = 1.96 * per.std(ddof=1) / np.sqrt(len(per)) if len(per) > 1 else 0.0
    b = per.reshape(-1, batch).mean(axis=1)
    return {"mean": float(per.mean()), "low": float(per.mean() - half), "high": float(per.mean() + half),
            "batch min": float(b.min()), "batch max": float(b.max())}


def f6_verdict(row: object, *, first: bool = False) -> str:
    """The Fig. 6 criterion on one reading of :func:`accuracy_summary` (a dict or a table row).

    Fig. 6 is one shown trajectory, so (CONTRIBUTING rule 7) the behaviour must occur in at
    least half of the draws: ``qualitative`` if at least 50% of the runs are perfect after
    ``t = 2`` and the first two instants are right less often than the later ones (errors
    concentrate at the start, as the paper says), ``differs`` otherwise. The paper prints no
    number, so ``qualitative`` is the most this figure can get. With ``first=True``, the page's
    first criterion, which demanded more: ``within-tolerance`` from 90% of the runs on.
    """
    p = float(row["perfect after t = 2"])  # type: ignore[index]
    if first and p >= 0.9:
        return "within-tolerance"
    if p >= 0.5 and float(row["right, t = 1-2"]) < float(row["right, t >= 3"]):  # type: ignore[index]
        return "qualitative"
    return "differs"

"""Association time per scan: the package's exact beta against Stone Soup's JPDA with EHM.

An association problem is one scan's detections ``z (m, 2)``, the tracks' predicted
measurements ``zp (T, 2)`` and innovation covariances ``S (T, 2, 2)``, with a model's
``P_D``, gate probability and clutter density. :func:`time_association` times, on the
same problems, :func:`projtrack.jpda.beta` on the MVM (``method="auto"``: independent
clusters, the forward-backward sweep on each) and Stone Soup's ``JPDAwithEHM``
(efficient hypothesis management) on hypotheses generated beforehand, so that both
times cover the association only, not the likelihoods; it also checks that both give
the same beta. The problems come from a tracker run on the real sequences
(``TrackRun.problems``) or from :func:`crowd_scan`, a dense synthetic crowd.
"""

from __future__ import annotations

import datetime
import time
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from projtrack._validation import as_int, as_real, as_rng
from projtrack.jpda import beta, clusters, modified_validation_matrix

from .pedtracking import PedestrianModel

#: The largest ``min(m, T)`` of a cluster that :func:`projtrack.jpda.beta_forward_backward` accepts.
MAX_CLUSTER = 26

__all__ = ["MAX_CLUSTER", "steady_state_innovation", "crowd_scan", "stonesoup_ehm_beta", "scan_clusters",
           "time_association"]


def steady_state_innovation(model: PedestrianModel, n_iter: int = 200) -> np.ndarray:
    """Innovation covariance ``S`` (2 x 2) of a track updated at every scan, in steady state
    (the Kalman filter's Riccati recursion iterated ``n_iter`` times from ``model.P0``)."""
    n_iter = as_int(n_iter, "n_iter", minimum=1)
    F, Q, H, R = model.F, model.Q, model.H, model.R
    P = model.P0.copy()
    for _ in range(n_iter):
        Pp = F @ P @ F.T + Q
        S = H @ Pp @ H.T + R
        K = Pp @ H.T @ np.linalg.inv(S)
        P = (np.eye(4) - K @ H) @ Pp
    return 0.5 * (S + S.T)


def crowd_scan(rng: np.random.Generator, model: PedestrianModel, n_targets: int, region: tuple[float, float],
               false_per_frame: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One scan of a synthetic crowd: ``(z, zp, S)``.

    ``n_targets`` predicted positions uniform in a ``region = (width, height)`` rectangle
    at the centre of the image, all with the steady-state innovation covariance of
    ``model`` (:func:`steady_state_innovation`); each target is detected with probability
    ``model.p_detect`` at a draw from ``N(zp, S)``; a Poisson number (mean
    ``false_per_frame``) of false detections is uniform over the image.
    """
    rng = as_rng(rng)
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    false_per_frame = as_real(false_per_frame, "false_per_frame", 0.0)
    W, Hh = model.image_size
    rw, rh = (as_real(region[0], "region[0]", 0.0, low_open=True), as_real(region[1], "region[1]", 0.0, low_open=True))
    S0 = steady_state_innovation(model)
    zp = np.array([(W - rw) / 2, (Hh - rh) / 2]) + rng.uniform(0, 1, (n_targets, 2)) * np.array([rw, rh])
    det = rng.random(n_targets) < model.p_detect
    z_true = zp[det] + rng.multivariate_normal(np.zeros(2), S0, size=int(det.sum()))
    clutter = rng.uniform(0, 1, (rng.poisson(false_per_frame), 2)) * np.array([W, Hh])
    z = np.vstack([z_true, clutter])
    return z[rng.permutation(len(z))], zp, np.repeat(S0[None], n_targets, axis=0)


def _mvm(z, zp, S, model: PedestrianModel) -> np.ndarray:
    mvm = modified_validation_matrix(z, zp, S, model.p_detect, model.gate_prob, model.clutter_density)
    mvm[0] = 1.0 - model.p_detect * model.gate_prob  # Stone Soup's missed-detection weight
    return mvm


def stonesoup_ehm_beta(z: np.ndarray, zp: np.ndarray, S: np.ndarray, model: PedestrianModel) -> Callable[[], np.ndarray]:
    """A function computing beta ``(m + 1, T)`` with Stone Soup's ``JPDAwithEHM`` on one problem.

    Each track is a two-dimensional state at ``zp[t]`` with covariance ``S[t] - model.R``
    and no motion, measured with noise ``model.R``, so its predicted measurement is
    ``N(zp[t], S[t])``; the hypotheses (Stone Soup's ``PDAHypothesiser`` with the model's
    ``P_D``, gate and clutter density) are generated once, here, and the returned function
    runs only the association.
    """
    from stonesoup.dataassociator.probability import JPDAwithEHM
    from stonesoup.hypothesiser.probability import PDAHypothesiser
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, RandomWalk
    from stonesoup.predictor.kalman import KalmanPredictor
    from stonesoup.types.detection import Detection
    from stonesoup.types.state import GaussianState
    from stonesoup.types.track import Track
    from stonesoup.updater.kalman import KalmanUpdater

    t0 = datetime.datetime(2000, 1, 1)
    trans = CombinedLinearGaussianTransitionModel([RandomWalk(0.0), RandomWalk(0.0)])
    meas = LinearGaussian(ndim_state=2, mapping=(0, 1), noise_covar=model.R)
    tracks = [Track([GaussianState(p.reshape(2, 1), s - model.R, timestamp=t0)]) for p, s in zip(zp, S)]
    dets = [Detection(x.reshape(2, 1), timestamp=t0, measurement_model=meas) for x in z]
    hyp = PDAHypothesiser(KalmanPredictor(trans), KalmanUpdater(meas), clutter_spatial_density=model.clutter_density,
                          prob_detect=model.p_detect, prob_gate=model.gate_prob)
    assoc = JPDAwithEHM(hyp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        hyps = assoc.generate_hypotheses(set(tracks), set(dets), t0)
    assoc.generate_hypotheses = lambda *a, **k: hyps
    index = {id(d): j for j, d in enumerate(dets)}

    def run() -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = assoc.associate(set(tracks), set(dets), t0)
        b = np.zeros((len(z) + 1, len(zp)))
        for t, tr in enumerate(tracks):
            for h in out[tr]:
                j = 0 if not h else 1 + index[id(h.measurement)]
                b[j, t] = float(h.probability)
        return b / b.sum(axis=0)

    return run


def scan_clusters(problems: Sequence[tuple], model: PedestrianModel) -> pd.DataFrame:
    """The independent clusters of each association problem ``(z, zp, S)``.

    One row per problem: ``m``, ``T``, ``largest cluster`` (the largest ``min(m_c, T_c)``
    over the clusters of :func:`projtrack.jpda.clusters`, which sets the sweep's ``2^min``
    cost) and ``shared`` (whether some detection lies in the gates of two tracks or more,
    i.e. a cluster holds two targets or more and a detection).
    """
    rows = []
    for z, zp, S in problems:
        cl = clusters(_mvm(z, zp, S, model))
        rows.append({"m": len(z), "T": len(zp),
                     "largest cluster": max((min(len(a), len(b)) for a, b in cl), default=0),
                     "shared": any(len(a) > 0 and len(b) > 1 for a, b in cl)})
    return pd.DataFrame(rows)


def _best(fn: Callable[[], object], repeats: int) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return float(best), out


def time_association(problems: Sequence[tuple], model: PedestrianModel, repeats: int = 3,
                     max_cluster: int = MAX_CLUSTER) -> pd.DataFrame:
    """Best-of-``repeats`` wall-clock seconds of both exact associations on each problem.

    Returns one row per problem: ``m``, ``T``, ``largest cluster`` (the largest
    ``min(m_c, T_c)`` over the independent clusters, which sets the sweep's
    ``2^min`` cost), ``beta [s]``, ``Stone Soup EHM [s]`` and ``max |diff|`` (the
    largest difference of the two betas). The sweep is not run (NaN) on a problem whose
    largest cluster exceeds ``max_cluster``: :func:`projtrack.jpda.beta_forward_backward`
    refuses more than ``MAX_CLUSTER`` (its ``2^min`` messages would not fit in memory).
    """
    repeats = as_int(repeats, "repeats", minimum=1)
    beta(np.vstack([np.full((1, 10), 0.1), np.ones((10, 10))]), method="auto")  # compiled sweep: load it now
    rows = []
    for z, zp, S in problems:
        mvm = _mvm(z, zp, S, model)
        cl = clusters(mvm)
        largest = max((min(len(a), len(b)) for a, b in cl), default=0)
        t_ss, theirs = _best(stonesoup_ehm_beta(z, zp, S, model), repeats)
        if largest <= max_cluster:
            t_ours, ours = _best(lambda: beta(mvm, method="auto"), repeats)
            diff = float(np.abs(ours - theirs).max())
        else:
            t_ours = diff = float("nan")
        rows.append({"m": len(z), "T": len(zp), "largest cluster": largest, "beta [s]": t_ours,
                     "Stone Soup EHM [s]": t_ss, "max |diff|": diff})
    return pd.DataFrame(rows)

"""Adapters driving peer libraries on the package's own problems (tests and benchmarks only).

Not part of the public API: the peers are optional dependencies, imported only when an
adapter is called.
"""

from __future__ import annotations

import datetime
import warnings
from collections.abc import Callable

import numpy as np

__all__ = ["stonesoup_jpda"]


def stonesoup_jpda(z: np.ndarray, zp: np.ndarray, S: np.ndarray, *, ehm: bool, p_detect: float,
                   p_gate: float, clutter_density: float,
                   precompute_hypotheses: bool = False) -> Callable[[], np.ndarray]:
    """Return a function computing JPDA beta with Stone Soup's exact associators.

    The tracks are zero-noise random walks whose predicted measurement is ``zp[t]`` with
    innovation covariance ``S[0]`` (H = I, P = I, R = S[0] - I), so the association is the
    same problem as :func:`projtrack.jpda.modified_validation_matrix` with row 0 set to
    ``1 - p_detect * p_gate`` (Stone Soup's missed-detection weight).

    Parameters
    ----------
    z : (m, 2) measurements; zp : (T, 2) predicted measurements; S : (T, 2, 2) covariances.
    ehm : use ``JPDAwithEHM`` instead of ``JPDA``.
    p_detect, p_gate, clutter_density : the hypothesiser's parameters.
    precompute_hypotheses : generate the hypotheses once now, so that calling the returned
        function times only the association (benchmarks).

    Returns
    -------
    callable
        ``run() -> beta`` of shape (m + 1, T), row 0 the missed-detection probability.
    """
    from stonesoup.dataassociator.probability import JPDA, JPDAwithEHM
    from stonesoup.hypothesiser.probability import PDAHypothesiser
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, RandomWalk
    from stonesoup.predictor.kalman import KalmanPredictor
    from stonesoup.types.detection import Detection
    from stonesoup.types.state import GaussianState
    from stonesoup.types.track import Track
    from stonesoup.updater.kalman import KalmanUpdater

    z, zp, S = np.asarray(z, float), np.asarray(zp, float), np.asarray(S, float)
    if z.ndim != 2 or zp.ndim != 2 or z.shape[1] != 2 or zp.shape[1] != 2:
        raise ValueError(f"z and zp must have shapes (m, 2) and (T, 2), got {z.shape} and {zp.shape}")
    if S.ndim != 3 or S.shape[1:] != (2, 2) or len(S) == 0:
        raise ValueError(f"S must have shape (T, 2, 2), got {S.shape}")
    t0 = datetime.datetime(2000, 1, 1)
    trans = CombinedLinearGaussianTransitionModel([RandomWalk(0.0), RandomWalk(0.0)])
    meas = LinearGaussian(ndim_state=2, mapping=(0, 1), noise_covar=S[0] - np.eye(2))
    tracks = [Track([GaussianState(p.reshape(2, 1), np.eye(2), timestamp=t0)]) for p in zp]
    dets = [Detection(x.reshape(2, 1), timestamp=t0, measurement_model=meas) for x in z]
    hyp = PDAHypothesiser(KalmanPredictor(trans), KalmanUpdater(meas),
                          clutter_spatial_density=clutter_density, prob_detect=p_detect,
                          prob_gate=p_gate)
    assoc = (JPDAwithEHM if ehm else JPDA)(hyp)
    if precompute_hypotheses:
        hyps = assoc.generate_hypotheses(set(tracks), set(dets), t0)
        assoc.generate_hypotheses = lambda *a, **k: hyps

    def run() -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = assoc.associate(set(tracks), set(dets), t0)
        b = np.zeros((len(z) + 1, len(zp)))
        for t, tr in enumerate(tracks):
            for h in out[tr]:
                if h.measurement.__class__.__name__ == "MissedDetection":
                    b[0, t] = float(h.probability)
                else:
                    b[1 + dets.index(h.measurement), t] = float(h.probability)
        return b / b.sum(axis=0)

    return run

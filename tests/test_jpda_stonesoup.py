"""beta against an independent library: Stone Soup's exact JPDA associators."""

import datetime
import warnings

import numpy as np
import pytest

from projtrack import jpda

pytest.importorskip("stonesoup")

P_D, P_G, LAM = 0.85, 0.999, 0.02


def _stonesoup_beta(z, zp, S, ehm):
    from stonesoup.dataassociator.probability import JPDA, JPDAwithEHM
    from stonesoup.hypothesiser.probability import PDAHypothesiser
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.transition.linear import (
        CombinedLinearGaussianTransitionModel, RandomWalk)
    from stonesoup.predictor.kalman import KalmanPredictor
    from stonesoup.types.detection import Detection
    from stonesoup.types.state import GaussianState
    from stonesoup.types.track import Track
    from stonesoup.updater.kalman import KalmanUpdater

    t0 = datetime.datetime(2000, 1, 1)
    trans = CombinedLinearGaussianTransitionModel([RandomWalk(0.0), RandomWalk(0.0)])
    meas = LinearGaussian(ndim_state=2, mapping=(0, 1), noise_covar=S[0] - np.eye(2))
    tracks = [Track([GaussianState(p.reshape(2, 1), np.eye(2), timestamp=t0)]) for p in zp]
    dets = [Detection(x.reshape(2, 1), timestamp=t0, measurement_model=meas) for x in z]
    hyp = PDAHypothesiser(KalmanPredictor(trans), KalmanUpdater(meas),
                          clutter_spatial_density=LAM, prob_detect=P_D, prob_gate=P_G)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = (JPDAwithEHM if ehm else JPDA)(hyp).associate(set(tracks), set(dets), t0)
    b = np.zeros((len(z) + 1, len(zp)))
    for t, tr in enumerate(tracks):
        for h in out[tr]:
            if h.measurement.__class__.__name__ == "MissedDetection":
                b[0, t] = float(h.probability)
            else:
                b[1 + dets.index(h.measurement), t] = float(h.probability)
    return b / b.sum(axis=0)


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("ehm", [False, True])
def test_beta_equals_stonesoup_jpda(seed, ehm):
    rng = np.random.default_rng(seed)
    zp = rng.uniform(-3, 3, (3, 2))
    z = rng.uniform(-4, 4, (5, 2))
    S = np.repeat((2.0 * np.eye(2))[None], 3, axis=0)
    mvm = jpda.modified_validation_matrix(z, zp, S, P_D, gate_prob=P_G, clutter_density=LAM)
    mvm[0] = 1 - P_D * P_G  # Stone Soup's missed-detection weight
    ours = jpda.beta(mvm)
    np.testing.assert_allclose(_stonesoup_beta(z, zp, S, ehm), ours, atol=1e-9)

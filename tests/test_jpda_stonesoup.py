"""beta against an independent library: Stone Soup's exact JPDA associators."""

import numpy as np
import pytest

from projtrack import jpda
from projtrack._peers import stonesoup_jpda

pytest.importorskip("stonesoup")

P_D, P_G, LAM = 0.85, 0.999, 0.02


def _stonesoup_beta(z, zp, S, ehm):
    return stonesoup_jpda(z, zp, S, ehm=ehm, p_detect=P_D, p_gate=P_G, clutter_density=LAM)()


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

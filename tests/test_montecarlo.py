"""projtrack.montecarlo: independent child streams, results independent of n_jobs."""

import numpy as np
import pytest

from projtrack import montecarlo


def _trial(rng, scale=1.0):
    return float(rng.normal() * scale), int(rng.integers(1_000_000))


def test_results_do_not_depend_on_n_jobs():
    serial = montecarlo.run(_trial, 6, np.random.default_rng(7), n_jobs=1)
    parallel = montecarlo.run(_trial, 6, np.random.default_rng(7), n_jobs=2)
    assert serial == parallel
    assert len(set(serial)) == 6  # the trials see different streams


def test_args_and_kwargs_are_passed_and_seed_matters():
    a = montecarlo.run(_trial, 3, np.random.default_rng(1), scale=0.0)
    assert all(x == 0.0 for x, _ in a)
    b1 = montecarlo.run(_trial, 3, np.random.default_rng(1))
    b2 = montecarlo.run(_trial, 3, np.random.default_rng(2))
    assert b1 != b2


def test_trial_i_is_stable_when_n_trials_grows():
    short = montecarlo.run(_trial, 3, np.random.default_rng(5))
    long = montecarlo.run(_trial, 5, np.random.default_rng(5))
    assert long[:3] == short


def test_zero_trials():
    assert montecarlo.run(_trial, 0, np.random.default_rng(0)) == []


def test_env_default_n_jobs(monkeypatch):
    monkeypatch.setenv("PROJTRACK_N_JOBS", "2")
    assert montecarlo.default_n_jobs() == 2
    monkeypatch.setenv("PROJTRACK_N_JOBS", "many")
    with pytest.raises(ValueError, match="PROJTRACK_N_JOBS"):
        montecarlo.default_n_jobs()


@pytest.mark.parametrize(
    "kwargs,exc,match",
    [
        (dict(fn=3, n_trials=2, rng=np.random.default_rng()), TypeError, "fn"),
        (dict(fn=_trial, n_trials=-1, rng=np.random.default_rng()), ValueError, "n_trials"),
        (dict(fn=_trial, n_trials=2.0, rng=np.random.default_rng()), TypeError, "n_trials"),
        (dict(fn=_trial, n_trials=2, rng=np.random.RandomState(0)), TypeError, "Generator"),
        (dict(fn=_trial, n_trials=2, rng=np.random.default_rng(), n_jobs=0), ValueError, "n_jobs"),
    ],
)
def test_bad_inputs(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        montecarlo.run(**kwargs)

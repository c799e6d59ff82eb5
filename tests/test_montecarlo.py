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


def test_size_switch(monkeypatch):
    monkeypatch.delenv("PROJTRACK_FULL", raising=False)
    assert montecarlo.size(100, 1000) == 100
    monkeypatch.setenv("PROJTRACK_FULL", "1")
    assert montecarlo.size(100, 1000) == 1000
    monkeypatch.setenv("PROJTRACK_FULL", "off")
    assert montecarlo.size(100, 1000) == 100
    monkeypatch.setenv("PROJTRACK_FULL", "maybe")
    with pytest.raises(ValueError, match="PROJTRACK_FULL"):
        montecarlo.size(100, 1000)


@pytest.mark.parametrize("book,full,exc", [(0, 10, ValueError), (10, 5, ValueError), (1.5, 10, TypeError),
                                           (True, 10, TypeError), (10, "20", TypeError)])
def test_size_bad_inputs(book, full, exc, monkeypatch):
    monkeypatch.delenv("PROJTRACK_FULL", raising=False)
    with pytest.raises(exc):
        montecarlo.size(book, full)


def test_bad_scheduler():
    with pytest.raises(TypeError, match="scheduler"):
        montecarlo.run(_trial, 2, np.random.default_rng(0), scheduler=42)


def test_dask_local_cluster_gives_the_serial_results():
    """Two Dask workers (separate processes) reproduce the serial run trial for trial,
    on one of the book's studies (the noise draws of a static ellipse reconstruction)."""
    distributed = pytest.importorskip("dask.distributed")
    from projtrack import ellipsoids
    from projtrack.scenes import ellipses

    def study(rng):
        Ys, Cs = ellipses.static_observations(0.3, rng)[2:4]
        return np.round(ellipsoids.reconstruct(Ys, Cs), 9).tolist()

    serial = montecarlo.run(study, 8, np.random.default_rng(3), n_jobs=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        via_address = montecarlo.run(study, 8, np.random.default_rng(3), scheduler=cluster.scheduler_address)
        with distributed.Client(cluster) as client:
            via_client = montecarlo.run(study, 8, np.random.default_rng(3), scheduler=client)
            workers = client.run(lambda: 1)
    assert len(workers) == 2
    assert via_address == serial and via_client == serial
    assert len({str(r) for r in serial}) == 8

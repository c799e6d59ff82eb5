"""Tests of projtrack.dma.examples: the set-ups of the three examples and the baselines."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack import dma
from projtrack.dma import examples as ex
from projtrack.scenes.slotcar import make_slotcar_video


@pytest.fixture(scope="module")
def sphere():
    return ex.make_sphere_example(np.random.default_rng(0), n_points=800, n_regions=6, n_prototypes=6)


def test_sphere_example_chain_and_trials(sphere):
    assert np.allclose(np.linalg.norm(sphere.centroids, axis=1), 1.0)
    assert np.allclose(sphere.transitions.sum(axis=1), 1.0)
    res = sphere.with_noise(0.01)
    out = ex.sphere_trials(res, 20, 10, np.random.default_rng(1), with_kalman=True)
    assert out["viterbi"].shape == (20, 10) and out["viterbi"].dtype == bool
    # near noise-free observations: DMA beats the Kalman baseline by far
    assert out["viterbi"].mean() > 0.7 > 3 * out["kalman"].mean()
    assert out["viterbi_err"].mean() < out["kalman_err"].mean()


def test_kalman_sphere_shapes():
    y = np.zeros((5, 1))
    est = ex.kalman_sphere(y, 0.1)
    assert est.shape == (5, 3) and np.allclose(est, 0.0)


def test_road_example_directed_states_small_error():
    road = ex.make_road_example(np.random.default_rng(0))
    assert np.allclose(road.transitions.sum(axis=1), 1.0)
    out = ex.road_trials(road, 3, 120, np.random.default_rng(1), with_ekf=True)
    assert set(out) == {"viterbi", "smooth", "filter", "ekf"}
    # most drives are followed to within the 10 m state spacing (the map has symmetric ambiguities)
    assert (np.median(out["viterbi"], axis=1) < 20.0).sum() >= 2


def test_ekf_range_follows_noise_free_start():
    rx = np.array([0.0, 0.0, 10.0])
    x = np.column_stack([300 + 10 * np.arange(5.0), np.full(5, 200.0)])
    d = np.sqrt(((x - rx[:2]) ** 2).sum(axis=1) + 100.0)
    est = ex.ekf_range(np.cos(0.02 * d), rx, 0.02, 0.05, x0=x[0], v0=np.array([10.0, 0.0]), height=10.0)
    assert est.shape == (5, 2)
    assert np.linalg.norm(est - x, axis=1).max() < 15.0


def test_active_pixels_and_bad_inputs():
    v = make_slotcar_video(40, np.random.default_rng(0))
    act = ex.active_pixels(v.frames, 0.15)
    assert act.shape == v.frames.shape and act.dtype == bool
    with pytest.raises(ValueError, match="frames"):
        ex.active_pixels(v.frames[0], 0.15)
    with pytest.raises(ValueError, match="background"):
        ex.active_pixels(v.frames, 0.15, background=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="finite"):
        ex.active_pixels(np.full((2, 4, 4), np.nan), 0.15)


def test_fit_slotcar_tracks():
    train = [make_slotcar_video(150, np.random.default_rng(s)) for s in (1, 2)]
    test = make_slotcar_video(80, np.random.default_rng(3))
    model, sensor = ex.fit_slotcar(train, np.random.default_rng(4))
    assert isinstance(sensor, dma.ActivePixelSensor) and sensor.c > 1
    est = model.predict(ex.active_pixels(test.frames, 0.15), sensor)
    assert np.linalg.norm(est - test.positions, axis=1).mean() < 3.0

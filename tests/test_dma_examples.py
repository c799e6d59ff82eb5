"""Tests of projtrack.experiments.dma: the set-ups of the three examples and the baselines."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack import dma
from projtrack.experiments import dma as ex
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


def _kalman_oracle(y, noise_std, q, smooth):
    """Random-walk Kalman filter + RTS smoother written out with numpy (textbook equations),
    the same model as ``kalman_sphere``: predict then update at every step from N(0, I/3)."""
    H = ex.H_SPHERE[0]
    R, Q = noise_std**2, q**2 * np.eye(3)
    x, P = np.zeros(3), np.eye(3) / 3.0
    xs, Ps, xp, Pp = [], [], [], []
    for yt in y:
        x, P = x, P + Q  # F = I
        xp.append(x); Pp.append(P)
        S = float(H @ P @ H) + R
        K = P @ H / S
        x = x + K * (yt - float(H @ x))
        P = (np.eye(3) - np.outer(K, H)) @ P
        xs.append(x); Ps.append(P)
    xs = np.array(xs)
    if smooth:
        for t in range(len(y) - 2, -1, -1):
            G = Ps[t] @ np.linalg.inv(Pp[t + 1])
            xs[t] = xs[t] + G @ (xs[t + 1] - xp[t + 1])
    return xs


@pytest.mark.parametrize("smooth", [False, True])
def test_kalman_sphere_matches_oracles_on_nonzero_data(smooth):
    from filterpy.kalman import KalmanFilter

    rng = np.random.default_rng(5)
    y = rng.uniform(-1.5, 1.5, 12)
    est = ex.kalman_sphere(y, 0.2, q=0.25, smooth=smooth)
    assert np.abs(est).max() > 0.05  # non-trivial data, non-trivial estimate
    # oracle 1: numpy textbook filter / RTS smoother
    assert np.allclose(est, _kalman_oracle(y, 0.2, 0.25, smooth), atol=1e-10)
    # oracle 2: filterpy KalmanFilter driven step by step with predict()/update()
    kf = KalmanFilter(dim_x=3, dim_z=1)
    kf.x, kf.P, kf.F, kf.H = np.zeros(3), np.eye(3) / 3.0, np.eye(3), ex.H_SPHERE.copy()
    kf.R, kf.Q = np.array([[0.04]]), 0.0625 * np.eye(3)
    mus, covs = [], []
    for yt in y:
        kf.predict()
        kf.update(np.array([yt]))
        mus.append(kf.x.copy()); covs.append(kf.P.copy())
    mus, covs = np.array(mus), np.array(covs)
    if smooth:
        mus = kf.rts_smoother(mus, covs)[0]
    assert np.allclose(est, mus, atol=1e-10)
    # the estimate explains the observations (residual well below their spread)
    assert np.std(est @ ex.H_SPHERE[0] - y) < 0.5 * np.std(y)


def test_kalman_sphere_bad_inputs():
    y = np.ones(4)
    with pytest.raises(ValueError, match="finite"):
        ex.kalman_sphere(np.array([0.1, np.nan, 0.2]), 0.1)
    with pytest.raises(ValueError, match="noise_std"):
        ex.kalman_sphere(y, 0.0)
    with pytest.raises(ValueError, match="noise_std"):
        ex.kalman_sphere(y, -0.1)
    with pytest.raises(ValueError, match="q"):
        ex.kalman_sphere(y, 0.1, q=0.0)
    with pytest.raises(ValueError, match="y must have shape"):
        ex.kalman_sphere(np.ones((4, 2)), 0.1)
    with pytest.raises(ValueError, match="y must have shape"):
        ex.kalman_sphere(np.ones(0), 0.1)


def test_make_sphere_example_bad_inputs(sphere):
    rng = np.random.default_rng(0)
    for kwargs, name in [({"noise_std": -1.0}, "noise_std"), ({"noise_std": 0.0}, "noise_std"),
                         ({"noise_std": np.nan}, "noise_std"), ({"dt": 0.0}, "dt")]:
        with pytest.raises(ValueError, match=name):
            ex.make_sphere_example(rng, n_points=200, n_regions=2, n_prototypes=2, **kwargs)
    with pytest.raises(ValueError, match="noise_std"):
        sphere.with_noise(-0.5)


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


def test_sphere_chains_and_trial_outputs():
    rng = np.random.default_rng(3)
    det = ex.make_sphere_example(rng, n_points=600, n_regions=6, n_prototypes=8, chain="nearest-other", noise_std=0.05)
    assert (np.diff(det.transitions.indptr) == 1).all() and (det.transitions.diagonal() == 0).all()
    out = ex.sphere_trials(det, 12, 10, np.random.default_rng(4), methods=("viterbi",))
    assert out["viterbi"].shape == out["frame_ml"].shape == out["chance"].shape == (12, 10)
    assert out["path"].shape == out["viterbi_path"].shape == out["y"].shape == (12, 10)
    assert ((out["viterbi_path"] == out["path"]) == out["viterbi"]).all()
    # deterministic chain, small noise: Viterbi right after the start in (almost) every run,
    # the estimators without the motion model are not
    assert out["viterbi"][:, 2:].mean() > 0.95
    assert out["frame_ml"][:, 2:].mean() < out["viterbi"][:, 2:].mean() - 0.2
    assert out["chance"].mean() < 0.3
    # the same results whatever the number of worker processes
    again = ex.sphere_trials(det, 12, 10, np.random.default_rng(4), methods=("viterbi",))
    assert (again["path"] == out["path"]).all()
    with pytest.raises(ValueError, match="chain"):
        ex.make_sphere_example(rng, n_points=300, n_regions=2, n_prototypes=4, chain="three")
    with pytest.raises(ValueError, match="methods"):
        ex.sphere_trials(det, 2, 5, np.random.default_rng(0), methods=("kalman",))
    with pytest.raises(ValueError, match="n_trials"):
        ex.sphere_trials(det, 0, 5, np.random.default_rng(0))


def test_lost_drives():
    e = np.array([[1.0] * 10, [60.0] * 2 + [1.0] * 8, [60.0] * 1 + [1.0] * 9])
    assert ex.lost_drives(e).tolist() == [False, True, False]
    assert ex.lost_drives(e, fraction=0.0).tolist() == [False, True, True]
    assert ex.lost_drives(e, distance=100.0).tolist() == [False, False, False]
    for bad in (np.zeros(3), np.array([[np.nan]]), -np.ones((2, 2))):
        with pytest.raises(ValueError, match="errors"):
            ex.lost_drives(bad)
    with pytest.raises(ValueError, match="fraction"):
        ex.lost_drives(e, fraction=1.0)
    with pytest.raises(ValueError, match="distance"):
        ex.lost_drives(e, distance=0.0)


def test_road_trials_bad_sizes():
    road = ex.make_road_example(np.random.default_rng(0), n_train=2, train_steps=50)
    with pytest.raises(ValueError, match="n_steps"):
        ex.road_trials(road, 1, 1, np.random.default_rng(0))
    with pytest.raises(ValueError, match="n_trials"):
        ex.road_trials(road, 0, 10, np.random.default_rng(0))


def test_training_background_is_the_empty_scene():
    train = [make_slotcar_video(120, np.random.default_rng(s), noise=0.0) for s in (1, 2)]
    bg = ex.training_background(train)
    # the car moves, so the median of the training frames is the noise-free empty scene
    assert np.abs(bg - train[0].background).max() < 1e-6
    with pytest.raises(ValueError, match="train_videos"):
        ex.training_background([])
    with pytest.raises(ValueError, match="frame"):
        ex.training_background([train[0], make_slotcar_video(5, np.random.default_rng(0), shape=(32, 32))])


def test_slotcar_harder_conditions():
    easy = make_slotcar_video(30, np.random.default_rng(5))
    again = make_slotcar_video(30, np.random.default_rng(5), illumination=0.0, car_peak=0.95, clutter=0.0)
    assert np.array_equal(easy.frames, again.frames)  # the defaults are the easy video
    dim = make_slotcar_video(30, np.random.default_rng(5), car_peak=0.5, noise=0.0)
    bright = make_slotcar_video(30, np.random.default_rng(5), noise=0.0)
    r, c = np.round(bright.positions[~bright.occluded][0]).astype(int)
    i = int(np.flatnonzero(~bright.occluded)[0])
    assert dim.frames[i, r, c] < bright.frames[i, r, c] - 0.2
    lit = make_slotcar_video(240, np.random.default_rng(6), illumination=0.2, noise=0.0)
    level = lit.frames.reshape(240, -1).mean(axis=1)
    assert level.max() / level.min() > 1.3  # the illumination drifts
    clut = make_slotcar_video(50, np.random.default_rng(7), clutter=3.0, noise=0.0)
    base = make_slotcar_video(50, np.random.default_rng(7), noise=0.0)
    assert (np.abs(clut.frames - clut.background) > 0.15).sum() > (np.abs(base.frames - base.background) > 0.15).sum()
    for kw, name in ((dict(illumination=1.0), "illumination"), (dict(car_peak=0.0), "car_peak"),
                     (dict(clutter=-1.0), "clutter"), (dict(car_peak=1.5), "car_peak")):
        with pytest.raises(ValueError, match=name):
            make_slotcar_video(5, np.random.default_rng(0), **kw)

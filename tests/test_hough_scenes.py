"""Tests of projtrack.scenes.boost (boost-phase scenes for the Hough track initiator)."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack.scenes.boost import (
    BoostTrajectory, continuous_launches, frame_times, in_view_launches, random_launches, render_frames,
    straight_targets,
)


def test_trajectory_is_constant_acceleration():
    tr = BoostTrajectory(1.0, np.array([10.0, 0.0]), np.array([0.0, 3.0]), np.array([1.0, 2.0]))
    t = np.array([0.0, 1.0, 3.0])
    p = tr.position(t)
    assert np.isnan(p[0]).all()
    assert np.allclose(p[1], [10, 0]) and np.allclose(p[2], [10 + 2, 6 + 4])
    assert np.allclose(tr.velocity(3.0), [2, 7])
    # second differences are a * dt^2: constant acceleration
    q = tr.position(np.arange(2, 8, 0.5))
    assert np.allclose(np.diff(q, 2, axis=0), 0.25 * tr.acceleration)


def test_in_view_launches_stay_in_view_and_below_max_speed():
    rng = np.random.default_rng(0)
    times = frame_times(21, 0.25)
    trajs = in_view_launches(rng, 6, times)
    for tr in trajs:
        p = tr.position(times)
        assert np.all((p >= 2) & (p <= 253))
        assert np.all(np.linalg.norm(tr.velocity(times), axis=1) <= 30)


def test_tracks_are_nearly_straight_over_a_composite():
    rng = np.random.default_rng(1)
    times = frame_times(21, 0.25)
    for tr in in_view_launches(rng, 10, times):
        p = tr.position(times)
        d = (p[-1] - p[0]) / np.linalg.norm(p[-1] - p[0])
        dev = np.abs((p - p[0]) @ np.array([-d[1], d[0]]))
        assert dev.max() < 2.0  # the paper's drho exceeds the linearity error


def test_render_frames_counts_and_determinism():
    times = frame_times(10, 0.25)
    trajs = in_view_launches(np.random.default_rng(2), 3, times)
    a = render_frames(trajs, times, np.random.default_rng(3), n_noise=4)
    b = render_frames(trajs, times, np.random.default_rng(3), n_noise=4)
    assert all(np.array_equal(x, y) for x, y in zip(a.points, b.points))
    for p, lab in zip(a.points, a.labels):
        assert len(p) == len(lab) <= 7
        assert np.all(p == np.rint(p)) and np.all((p >= 0) & (p <= 255))
        assert len(np.unique(p, axis=0)) == len(p)
    assert a.truth.shape == (10, 3, 2) and a.composite().shape[1] == 2


def test_detection_probability_zero_leaves_only_noise():
    times = frame_times(5, 0.25)
    trajs = in_view_launches(np.random.default_rng(4), 3, times)
    fr = render_frames(trajs, times, np.random.default_rng(5), p_detect=0.0, n_noise=2)
    assert all(np.all(lab == -1) for lab in fr.labels)


def test_detection_probability_rate():
    times = frame_times(200, 0.25, start=0.0)
    tr = BoostTrajectory(-100.0, np.array([128.0, 128.0]), np.zeros(2), np.zeros(2))
    fr = render_frames([tr], times, np.random.default_rng(6), p_detect=0.9, n_noise=0, jitter_sigma=0.0)
    rate = np.mean([len(p) for p in fr.points])
    assert 0.84 < rate < 0.96


def test_continuous_launches_traverse():
    trajs = continuous_launches(np.random.default_rng(7), 5, 60.0)
    t = frame_times(240, 0.25)
    for tr in trajs:
        p = tr.position(t)
        inside = np.all((p >= 0) & (p <= 255), axis=1)
        assert inside.sum() * 0.25 >= 5.0


def test_straight_targets_geometry():
    trajs = straight_targets(5, 20.0, rng=np.random.default_rng(8))
    heads = [np.rad2deg(np.arctan2(tr.velocity0[1], tr.velocity0[0])) for tr in trajs]
    assert np.allclose(heads, [0, 22.5, 45, 67.5, 90])
    assert all(np.linalg.norm(tr.velocity0) == pytest.approx(20) for tr in trajs)
    assert all(0 <= tr.launch_xy[0] < 128 and 0 <= tr.launch_xy[1] < 128 for tr in trajs)


def test_bad_inputs():
    rng = np.random.default_rng(9)
    with pytest.raises(TypeError):
        random_launches(0, 3)
    with pytest.raises(ValueError):
        random_launches(rng, -1)
    with pytest.raises(ValueError):
        random_launches(rng, 2, accel_range=(0, 1))
    with pytest.raises(ValueError):
        render_frames([], [0.0], rng, p_detect=1.5)
    with pytest.raises(ValueError):
        render_frames([], [0.0], rng, n_noise=-1)
    with pytest.raises(ValueError):
        frame_times(0)
    with pytest.raises(ValueError):
        straight_targets(0, 5.0, rng=rng)
    with pytest.raises(RuntimeError):
        in_view_launches(rng, 3, frame_times(21, 0.25), max_tries=2, site_y_range=(-500, -400))
    with pytest.raises(ValueError, match="n must be an int >= 0"):
        in_view_launches(rng, -1, frame_times(21, 0.25))
    with pytest.raises(ValueError, match="n must be an int >= 0"):
        in_view_launches(rng, 2.5, frame_times(21, 0.25))
    with pytest.raises(TypeError, match="Generator"):
        in_view_launches(0, 2, frame_times(21, 0.25))
    with pytest.raises(ValueError, match="max_tries"):
        in_view_launches(rng, 2, frame_times(21, 0.25), max_tries=0)
    assert in_view_launches(rng, 0, frame_times(21, 0.25)) == []

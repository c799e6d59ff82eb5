"""Tests of the readings and studies of projtrack.experiments.dma that the notebooks call."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack import dma
from projtrack.experiments import dma as ex
from projtrack.scenes import manifolds as mf
from projtrack.scenes.slotcar import make_slotcar_video


@pytest.fixture(scope="module")
def sphere():
    return ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5)


# ---------------------------------------------------------------- Example 1
def test_accuracy_summary_reads_a_known_array():
    ok = np.ones((4, 5), dtype=bool)
    ok[0, 0] = False  # wrong at t = 1 only: still perfect after t = 2
    ok[1, 3] = False  # wrong at t = 4
    s = ex.accuracy_summary(ok)
    assert s["right, t = 1-2"] == pytest.approx(7 / 8)
    assert s["right, t >= 3"] == pytest.approx(11 / 12)
    assert s["right, t = 4-5"] == pytest.approx(7 / 8)
    assert s["perfect after t = 2"] == pytest.approx(3 / 4)
    assert s["perfect"] == pytest.approx(2 / 4)


def test_accuracy_summary_bad_inputs():
    with pytest.raises(ValueError, match="at least 3"):
        ex.accuracy_summary(np.ones((3, 2), dtype=bool))
    with pytest.raises(ValueError, match="right"):
        ex.accuracy_summary(np.ones(5, dtype=bool))


def test_fibonacci_sphere_is_on_the_sphere_and_spread():
    P = mf.fibonacci_sphere(50)
    assert P.shape == (50, 3) and np.allclose(np.linalg.norm(P, axis=1), 1.0)
    assert abs(P.mean(axis=0)).max() < 0.05  # balanced over the sphere
    d = np.linalg.norm(P[:, None] - P[None], axis=2) + 3 * np.eye(50)
    assert d.min() > 0.3  # no two points bunch up
    with pytest.raises(ValueError, match="n"):
        mf.fibonacci_sphere(0)


def test_with_centroids_rebuilds_the_chain(sphere):
    lattice = mf.fibonacci_sphere(sphere.n_states)
    m = ex.with_centroids(sphere, lattice, "nearest-other")
    assert np.array_equal(m.centroids, lattice) and m.noise_std == sphere.noise_std
    A = m.transitions
    assert np.allclose(A.sum(axis=1), 1.0) and A.nnz == sphere.n_states and (A.diagonal() == 0).all()
    ref = dma.transitions_from_velocity_field(lattice, mf.sphere_velocity, sphere.dt, n_next=1,
                                              project=mf.project_to_sphere, exclude_self=True)
    assert (A != ref).nnz == 0
    with pytest.raises(ValueError, match="chain"):
        ex.with_centroids(sphere, lattice, "three")
    with pytest.raises(ValueError, match="centroids"):
        ex.with_centroids(sphere, lattice[:-1], "two-nearest")


def test_noise_study_rows_and_runs(sphere):
    rows, runs = ex.noise_study({"two-nearest": sphere}, (0.01, 0.5), 6, 5, seed=3)
    assert [(r["chain"], r["sigma"]) for r in rows] == [("two-nearest", 0.01), ("two-nearest", 0.5)]
    low, high = (runs["two-nearest", s]["viterbi"] for s in (0.01, 0.5))
    assert np.array_equal(runs["two-nearest", 0.01]["path"], runs["two-nearest", 0.5]["path"])  # same draws
    assert rows[0]["right, t >= 3"] == pytest.approx(low[:, 2:].mean())
    assert low.mean() > high.mean()  # less noise, more right centroids
    with pytest.raises(ValueError, match="models"):
        ex.noise_study({}, (0.1,), 2, 3, seed=0)
    with pytest.raises(ValueError, match="noise_stds"):
        ex.noise_study({"a": sphere}, (), 2, 3, seed=0)


# ---------------------------------------------------------------- Example 2
def test_error_summary_and_blocks():
    e = np.full((4, 10), 5.0)
    e[1] = 100.0  # one drive far off all the time: lost
    s = ex.error_summary(e)
    assert s["lost drives"] == 1 and s["lost fraction"] == 0.25
    assert s["median error [m]"] == 5.0 and s["mean error [m]"] == pytest.approx(28.75)
    assert s["mean error, drives not lost [m]"] == 5.0
    lo, hi = (float(v) for v in s["lost, 95% CI"].split("-"))
    assert lo < 0.25 < hi
    b = ex.block_summary(e, 2)
    assert [r["drives"] for r in b] == ["1-2", "3-4"] and [r["lost drives"] for r in b] == [1, 0]
    assert b[0]["mean error [m]"] == pytest.approx(52.5)
    with pytest.raises(ValueError, match="multiple"):
        ex.block_summary(e, 3)
    with pytest.raises(ValueError, match="errors"):
        ex.error_summary(-e)
    with pytest.raises(ValueError, match="errors"):
        ex.error_summary(np.array([[np.nan]]))


def test_no_data_errors_replays_the_drives_of_road_trials():
    road = ex.make_road_example(np.random.default_rng(1), n_train=3, train_steps=30)
    e0 = ex.no_data_errors(road, 3, 8, np.random.default_rng(5))
    assert e0.shape == (3, 8)
    child = np.random.default_rng(5).spawn(3)[2]
    x = road.scene.drive(8, child)
    near = road.points[np.argmin(np.linalg.norm(road.points - road.receiver, axis=1))]
    assert np.allclose(e0[2], np.linalg.norm(x - near, axis=1))
    with pytest.raises(ValueError, match="n_steps"):
        ex.no_data_errors(road, 3, 1, np.random.default_rng(5))


# ---------------------------------------------------------------- Example 3
@pytest.fixture(scope="module")
def slotcar():
    train = [make_slotcar_video(60, np.random.default_rng(s)) for s in (1, 2)]
    bg = ex.training_background(train)
    model, sensor = ex.fit_slotcar(train, np.random.default_rng(3), n_regions=4, n_prototypes=4, background=bg)
    return train, bg, model, sensor


def test_tracking_study_and_rows(slotcar):
    train, bg, model, sensor = slotcar
    trials = ex.tracking_study(model, sensor, bg, 2, np.random.default_rng(8), n_frames=40)
    assert len(trials) == 2 and trials[0]["viterbi"].shape == (40,)
    again = ex.track_video(np.random.default_rng(8).spawn(2)[1], model, sensor, bg, n_frames=40)
    assert np.allclose(again["viterbi"], trials[1]["viterbi"])
    video = make_slotcar_video(40, np.random.default_rng(8).spawn(2)[0])  # the draw of trial 0
    floor = np.linalg.norm(model.prototypes_[model.quantize(video.positions)] - video.positions, axis=1)
    assert np.allclose(trials[0]["floor"], floor) and np.array_equal(trials[0]["occluded"], video.occluded)
    rows = ex.tracking_error_rows("easy", trials)
    assert [r["frames"] for r in rows] == ["all", "car visible", "car under the bridge"]
    assert rows[0]["count"] == 80 == rows[1]["count"] + rows[2]["count"] and rows[2]["count"] == 6
    allv = np.concatenate([t["viterbi"] for t in trials]).mean()
    assert rows[0]["DMA Viterbi error [px]"] == pytest.approx(allv)
    with pytest.raises(ValueError, match="trials"):
        ex.tracking_error_rows("easy", [])
    with pytest.raises(ValueError, match="n_videos"):
        ex.tracking_study(model, sensor, bg, 0, np.random.default_rng(8))


def test_sensitivity_study_grid(slotcar):
    train, bg, _, _ = slotcar
    video = make_slotcar_video(60, np.random.default_rng(8))
    rows, base = ex.sensitivity_study(train, video, bg, (2, 4), (3,), seed=3, base=(4, 3))
    assert [(r["regions"], r["centroids per region"]) for r in rows] == [(2, 3), (4, 3)]
    assert set(base) == {"viterbi", "smooth", "filter"} and base["viterbi"] == pytest.approx(rows[1]["viterbi error [px]"])
    rows2, base2 = ex.sensitivity_study(train, video, bg, (2,), (3,), seed=3, base=(8, 8))
    assert rows2 == rows[:1] and base2 == {}
    assert rows[0]["viterbi error, hidden [px]"] >= 0  # the video has hidden frames
    with pytest.raises(ValueError, match="empty"):
        ex.sensitivity_study(train, video, bg, (), (3,), seed=3)


# ---------------------------------------------------------------- Figs. 2-3: the curve
@pytest.fixture(scope="module")
def curve_model():
    t = np.random.default_rng(4).uniform(0, 2 * np.pi, 600)
    return dma.learn_manifold(mf.closed_curve(t), 3, 4, np.random.default_rng(5), dim=1)


def test_clockwise_order_is_a_clockwise_permutation(curve_model):
    order, inv = ex.clockwise_order(curve_model)
    S = curve_model.n_prototypes
    assert sorted(order.tolist()) == list(range(S)) and np.array_equal(inv[order], np.arange(S))
    angle = np.unwrap(np.arctan2(*curve_model.prototypes[order][:, ::-1].T))
    assert (np.diff(angle) < 0).all()  # clockwise all the way round
    reg = curve_model.prototype_region[order]
    assert reg[0] != reg[-1]  # rank 0 starts a region
    with pytest.raises(ValueError, match="plane"):
        ex.clockwise_order(dma.learn_manifold(mf.sphere_points(200, np.random.default_rng(0)), 2, 2,
                                              np.random.default_rng(1), dim=2))


def test_other_moves_counts_skips_and_backward_moves():
    A = np.eye(4) * 0.5 + np.roll(np.eye(4), 1, axis=1) * 0.5  # stay or advance: none
    assert ex.other_moves(A) == 0
    A[2] = [0.2, 0.0, 0.4, 0.4]  # state 2 may jump back to 0
    assert ex.other_moves(A) == 1 and ex.other_moves(A, 0.3) == 0
    with pytest.raises(ValueError, match="square"):
        ex.other_moves(np.ones((2, 3)))


def test_speed_sensitivity_faster_motion_gives_more_skips(curve_model):
    _, inv = ex.clockwise_order(curve_model)
    rows = ex.speed_sensitivity(curve_model, inv, (0.02, 0.6), n_runs=3, n_steps=120)
    assert [r["mean step [rad]"] for r in rows] == [0.02, 0.6]
    slow, fast = rows
    assert slow["largest step"] < fast["largest step"]
    assert slow["rows with other moves"] <= fast["rows with other moves"] and fast["rows with other moves"] > 0
    with pytest.raises(ValueError, match="inv"):
        ex.speed_sensitivity(curve_model, inv[:-1], (0.1,))
    with pytest.raises(ValueError, match="mean_steps"):
        ex.speed_sensitivity(curve_model, inv, ())


def test_tracking_error_table_declares_one_flip_tolerances(slotcar):
    train, bg, model, sensor = slotcar
    trials = ex.tracking_study(model, sensor, bg, 2, np.random.default_rng(8), n_frames=40)
    table, tol = ex.tracking_error_table({"easy": trials}, {"easy": (model, sensor)})
    assert list(table["frames"]) == ["all", "car visible", "car under the bridge"]
    n = int(table["count"].min())
    step = ex.path_step(model)
    assert 0 < step < 64
    assert tol["DMA Viterbi [px]"].kind == "statistical"
    assert tol["DMA Viterbi [px]"].atol == pytest.approx(3 * round(step, 1) / n)
    assert tol["per-frame detector [px]"].atol == pytest.approx(round(np.hypot(48, 64), 1) / n)
    assert tol["nearest-centroid floor [px]"].kind == "numerical"
    with pytest.raises(ValueError, match="no model for the conditions"):
        ex.tracking_error_table({"easy": trials}, {})
    with pytest.raises(ValueError, match="non-empty dict"):
        ex.tracking_error_table({}, {})


def test_training_summary_and_fig9(slotcar):
    import matplotlib.pyplot as plt

    train, bg, model, sensor = slotcar
    table, tol = ex.training_summary({"easy": (model, sensor)}, {"easy": train}, {"easy": bg})
    row = table.iloc[0]
    assert row["regions"] == 4 and row["c of eq. (15)"] == pytest.approx(sensor.c)
    assert set(tol) == {"c of eq. (15)", "log c"}
    video = make_slotcar_video(60, np.random.default_rng(9))
    est = model.predict(ex.active_pixels(video.frames, 0.15, bg), sensor)
    fig = ex.plot_fig9(video, model, est, train, 10)
    assert len(fig.axes) == 6
    plt.close(fig)
    with pytest.raises(ValueError, match="t_occ must leave"):
        ex.plot_fig9(video, model, est, train, 1)
    with pytest.raises(ValueError, match="times must name two frames"):
        ex.plot_harder(video, ex.active_pixels(video.frames, 0.15, bg), est, (1, 2, 3))

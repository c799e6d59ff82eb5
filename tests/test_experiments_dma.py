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


# ---------------------------------------------------------------- Example 1: chain readings and baselines
def test_chain_stats_and_process_std():
    det = ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5,
                                 chain="nearest-other")
    st = ex.chain_stats(det)
    assert st == {"self-loop": 0.0, "largest transition": 1.0, "successors": 1.0}
    two = ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5)
    s2 = ex.chain_stats(two)
    assert s2["successors"] == 2.0 and 0.5 <= s2["largest transition"] < 1.0
    # the process noise of the deterministic chain, by hand: its one successor against the field's prediction
    C = det.centroids
    nxt = det.transitions.indices
    pred = C + det.dt * det.velocity(C)
    assert ex.chain_process_std(det) == pytest.approx(np.sqrt(((C[nxt] - pred) ** 2).sum(axis=1).mean() / 3))
    # drift and width reach the chain
    still = ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5, drift=0.0)
    assert np.allclose(still.velocity(C), mf.sphere_velocity(C, drift=0.0))
    sharp = ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5, width=0.3)
    assert ex.chain_stats(sharp)["largest transition"] > s2["largest transition"]
    for kw, name in ((dict(drift=-1.0), "drift"), (dict(width=0.0), "width")):
        with pytest.raises(ValueError, match=name):
            ex.make_sphere_example(np.random.default_rng(0), n_points=200, n_regions=2, n_prototypes=2, **kw)


def test_chain_sensitivity_rows():
    rows = ex.chain_sensitivity({"base": {}, "dt 0.6": {"dt": 0.6}}, 5, 6, model_seed=0, seed=1)
    assert [r["variant"] for r in rows] == ["base", "dt 0.6"]
    assert rows[1]["self-loop"] < rows[0]["self-loop"]  # a longer step leaves fewer self-loops
    assert all(0 <= r["perfect after t = 2"] <= r["right, t >= 3"] <= 1 for r in rows)
    with pytest.raises(ValueError, match="variants"):
        ex.chain_sensitivity({}, 5, 6)


def test_field_smoother_is_the_kalman_smoother_of_the_linear_field():
    from filterpy.kalman import KalmanFilter

    # without drift the field is the rotation k x x: linear, so the extended smoother is the Kalman one
    rng = np.random.default_rng(3)
    y = rng.normal(size=12)
    dt, q, sd = 0.3, 0.1, 0.2
    est = ex.field_smoother(y, sd, dt, drift=0.0, q=q)
    kf = KalmanFilter(dim_x=3, dim_z=1)
    kf.x, kf.P = np.zeros(3), np.eye(3) / 3.0
    kf.F = np.eye(3) + dt * np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    kf.H, kf.R, kf.Q = ex.H_SPHERE.copy(), np.array([[sd**2]]), q**2 * np.eye(3)
    # filterpy predicts before every update; the first step of field_smoother updates the prior directly
    mu, cov = [], []
    for t, yt in enumerate(y):
        if t:
            kf.predict()
        kf.update(np.array([yt]))
        mu.append(kf.x.copy()); cov.append(kf.P.copy())
    mu, cov = np.array(mu), np.array(cov)
    xs = mu.copy()
    for t in range(len(y) - 2, -1, -1):
        Pp = kf.F @ cov[t] @ kf.F.T + kf.Q
        G = cov[t] @ kf.F.T @ np.linalg.inv(Pp)
        xs[t] = mu[t] + G @ (xs[t + 1] - kf.F @ mu[t])
    assert np.allclose(est, xs)
    # a known start pins the first estimate
    x0 = np.array([0.6, 0.0, 0.8])
    assert np.allclose(ex.field_smoother(y, sd, dt, q=q, x0=x0)[0], x0, atol=0.05)
    with pytest.raises(ValueError, match="q"):
        ex.field_smoother(y, sd, dt, q=0.0)
    with pytest.raises(ValueError, match="y"):
        ex.field_smoother(np.array([np.nan]), sd, dt)


def test_baseline_trials_and_rate_spread():
    det = ex.make_sphere_example(np.random.default_rng(0), n_points=600, n_regions=4, n_prototypes=5,
                                 chain="nearest-other", noise_std=0.05)
    r = ex.baseline_trials(det, 6, 10, np.random.default_rng(2))
    for k in ("viterbi", "smooth", "filter", "frame_ml", "chance", "kalman", "field", "field_start"):
        assert r[k].shape == (6, 10) and r[k].dtype == bool
    same = ex.sphere_trials(det, 6, 10, np.random.default_rng(2), with_kalman=True)
    assert np.array_equal(r["path"], same["path"]) and np.array_equal(r["kalman"], same["kalman"])
    assert r["viterbi"][:, 2:].mean() > r["field"][:, 2:].mean()
    ok = np.zeros((4, 5), dtype=bool)
    ok[:2, 2:] = True  # two trials right after t = 2, two never
    s = ex.rate_spread(ok, batch=2)
    assert s["mean"] == 0.5 and s["batch min"] == 0.0 and s["batch max"] == 1.0
    assert s["low"] < 0.5 < s["high"]
    with pytest.raises(ValueError, match="multiple"):
        ex.rate_spread(ok, batch=3)


# ---------------------------------------------------------------- Example 2: readings
def test_road_example_speed_and_interval():
    road = ex.make_road_example(np.random.default_rng(1), n_train=2, train_steps=30, speed=20.0, dt=0.5)
    assert road.speed == 20.0 and road.dt == 0.5
    x = road.drive(40, np.random.default_rng(2))
    step = np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1)
    assert 0.4 * 10 <= np.median(step) <= 1.6 * 10  # 20 m/s for half a second, speed noise 15%
    out = ex.road_trials(road, 2, 20, np.random.default_rng(3), methods=("viterbi",))
    assert set(out) == {"viterbi"} and out["viterbi"].shape == (2, 20)
    with pytest.raises(ValueError, match="methods"):
        ex.road_trials(road, 2, 20, np.random.default_rng(3), methods=("ekf",))
    with pytest.raises(ValueError, match="methods"):
        ex.road_trials(road, 2, 20, np.random.default_rng(3), methods=())
    # the EKF alone replays the EKF of a full run on the same drives
    alone = ex.road_trials(road, 2, 20, np.random.default_rng(3), methods=(), with_ekf=True)
    both = ex.road_trials(road, 2, 20, np.random.default_rng(3), methods=("viterbi",), with_ekf=True)
    assert set(alone) == {"ekf"} and np.allclose(alone["ekf"], both["ekf"])
    with pytest.raises(ValueError, match="speed"):
        ex.make_road_example(np.random.default_rng(1), speed=0.0)


def test_median_shift_bound():
    e = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]])
    # median of 6 values (lower middle) 3; one drive (two values) can move it two order statistics
    assert ex.median_shift_bound(e) == pytest.approx(max(3.0 - 1.0, 6.0 - 3.0))
    rng = np.random.default_rng(0)
    e = rng.exponential(10, size=(20, 15))
    bound = ex.median_shift_bound(e)
    for i in range(20):  # replacing any one drive by anything moves the median by at most the bound
        for fill in (0.0, 1e6):
            f = e.copy()
            f[i] = fill
            assert abs(np.median(f) - np.median(e)) <= bound + 1e-12


def test_reading_study_rows():
    rows, errs = ex.reading_study([("position and heading", "variance 0.05", 12.0, 1.0),
                                   ("position", "std 0.05", 12.0, 2.0)], 2, 20)
    assert [(r["states"], r["interval [s]"]) for r in rows] == [("position and heading", 1.0), ("position", 2.0)]
    assert errs["position", "std 0.05", 12.0, 2.0].shape == (2, 10)  # 20 s at 2 s per sample
    assert rows[0]["m per sample"] == 12.0
    assert rows[0]["follows"] == (rows[0]["median error [m]"] < 20 and rows[0]["lost share"] <= 0.1)
    assert all(r["most follow"] == (r["lost share"] <= 0.5) for r in rows)
    with pytest.raises(ValueError, match="reading"):
        ex.reading_study([("heading", "variance 0.05", 12.0, 1.0)], 2, 20)
    with pytest.raises(ValueError, match="samples"):
        ex.reading_study([("position", "std 0.05", 12.0, 2.0)], 2, 2)


# ---------------------------------------------------------------- Example 3: without the manifold
def test_box_counts_against_brute_force():
    rng = np.random.default_rng(0)
    A = rng.random((2, 9, 11)) < 0.3
    n = ex.box_counts(A, 3)
    brute = np.zeros_like(n)
    for t in range(2):
        for r in range(9):
            for c in range(11):
                brute[t, r, c] = A[t, max(r - 1, 0):r + 2, max(c - 1, 0):c + 2].sum()
    assert np.array_equal(n, brute)


def test_detect_and_interpolate_fills_the_gap_linearly():
    A = np.zeros((7, 20, 20), dtype=bool)
    for t in range(7):
        if t not in (2, 3, 4):  # hidden in frames 2-4
            A[t, 10, 2 + 2 * t:5 + 2 * t] = True  # a 3-pixel blob moving 2 px per frame
    est, found = ex.detect_and_interpolate(A, 2.5, box=5)
    assert found.tolist() == [True, True, False, False, False, True, True]
    assert np.allclose(est[:, 0], 10.0) and np.allclose(est[:, 1], 3 + 2 * np.arange(7))
    assert ex.longest_gap(found) == 3 and ex.longest_gap(np.ones(4, bool)) == 0
    with pytest.raises(ValueError, match="no frame"):
        ex.detect_and_interpolate(A, 99.0)


def test_grid_hmm_and_map_free_table(slotcar):
    train, bg, model, sensor = slotcar
    n_min = ex.detector_threshold(train, bg)
    assert n_min > 0 and (2 * n_min).is_integer()
    grid = ex.fit_grid_hmm(train, np.random.default_rng(3), background=bg)
    assert np.allclose(grid.transitions.sum(axis=1), 1.0) and len(grid.points) == 48 * 64
    assert grid.sigma == pytest.approx(grid.step / np.sqrt(2)) and grid.max_step == pytest.approx(3 * grid.sigma)
    A = grid.transitions.tocoo()
    assert np.linalg.norm(grid.points[A.row] - grid.points[A.col], axis=1).max() <= grid.max_step
    wide = ex.fit_grid_hmm(train, np.random.default_rng(3), background=bg, spread=1.0)
    assert wide.sigma == pytest.approx(grid.step) and wide.transitions.nnz > grid.transitions.nnz
    mfree = ex.MapFree(n_min, 5, grid, {"wide": wide})
    trials = ex.tracking_study(model, sensor, bg, 2, np.random.default_rng(8), n_frames=40, map_free=mfree)
    for k in ("detector", "grid", "grid wide"):
        assert trials[0][k].shape == (40,)
    table, tol = ex.map_free_table({"easy": trials}, {"easy": (model, sensor)}, {"easy": mfree})
    assert list(table["frames"]) == ["car visible", "car under the bridge"]
    occ = np.concatenate([t["occluded"] for t in trials])
    grid_err = np.concatenate([t["grid"] for t in trials])
    assert table.iloc[1]["random-walk grid HMM [px]"] == pytest.approx(grid_err[occ].mean())
    n = int(occ.sum())
    gap = max(int(t["gap"]) for t in trials)
    assert tol["detector + interpolation [px]"].atol == pytest.approx((1 + gap) * round(np.hypot(48, 64), 1) / n)
    assert tol["random-walk grid HMM [px]"].atol == pytest.approx(3 * round(grid.max_step, 1) / n)
    plain = ex.tracking_study(model, sensor, bg, 1, np.random.default_rng(8), n_frames=40)
    with pytest.raises(ValueError, match="without map_free"):
        ex.map_free_table({"easy": plain}, {"easy": (model, sensor)}, {"easy": mfree})
    with pytest.raises(ValueError, match="nothing for the conditions"):
        ex.map_free_table({"easy": trials}, {"easy": (model, sensor)}, {})


# ---------------------------------------------------------------- Sec. 3: eq. (9) and the convergence of A
def test_eq9_table_holds_for_the_weighted_statistics():
    X = mf.parabolic_surface(600, np.random.default_rng(0))
    model = dma.learn_manifold(X, 3, 4, np.random.default_rng(1), dim=2)
    g = ex.responsibilities(model, X)
    assert g.shape == (600, 3) and np.allclose(g.sum(axis=1), 1.0)
    t = ex.eq9_table(model, X)
    assert list(t["points"]) == np.bincount(model.assign(X), minlength=3).tolist()
    assert np.allclose(t["E2 of eq. (9)"], t["weighted MSE"], rtol=1e-9)
    # the model's own covariance describes the weighted points up to EM's stopping tolerance
    assert np.allclose(t["E2 of the model"], t["weighted MSE"], rtol=0.2)
    with pytest.raises(ValueError, match="columns"):
        ex.responsibilities(model, X[:, :2])


def test_stationary_and_sample_path():
    A = np.array([[0.9, 0.1, 0.0], [0.0, 0.5, 0.5], [0.2, 0.0, 0.8]])
    pi = ex.stationary(A)
    assert np.allclose(pi @ A, pi) and pi.sum() == pytest.approx(1.0)
    path = ex.sample_path(A, 60000, np.random.default_rng(0), start=1)
    assert path[0] == 1
    assert np.allclose(np.bincount(path, minlength=3) / len(path), pi, atol=0.02)
    nxt = path[1:][path[:-1] == 1]
    assert set(nxt.tolist()) <= {1, 2} and abs((nxt == 2).mean() - 0.5) < 0.03
    with pytest.raises(ValueError, match="square"):
        ex.stationary(np.ones((2, 3)))


def test_transition_convergence_follows_the_prediction():
    A = np.array([[0.6, 0.4, 0.0], [0.0, 0.3, 0.7], [0.5, 0.0, 0.5]])
    t = ex.transition_convergence(A, (300, 30000), 8, np.random.default_rng(2))
    assert list(t["transitions N"]) == [300, 30000]
    err, pred = t["Frobenius error"].to_numpy(), t["predicted"].to_numpy()
    assert err[1] < err[0] / 5  # 100 times the data, about 10 times less error
    assert np.allclose(err, pred, rtol=0.5)
    assert pred[0] / pred[1] == pytest.approx(10.0)
    assert (t["unvisited states"] == 0).all()
    with pytest.raises(ValueError, match="sizes"):
        ex.transition_convergence(A, (), 2, np.random.default_rng(0))


def test_sensitivity_table_tolerances(slotcar):
    train, bg, _, _ = slotcar
    video = make_slotcar_video(60, np.random.default_rng(8))
    rows, _ = ex.sensitivity_study(train, video, bg, (2, 4), (3,), seed=3)
    model, _ = ex.fit_slotcar(train, np.random.default_rng(3), n_regions=2, n_prototypes=3, background=bg)
    assert rows[0]["path step [px]"] == pytest.approx(ex.path_step(model))
    table, tol = ex.sensitivity_table(rows, 60, 6)
    for col, n in (("viterbi error [px]", 60), ("viterbi error, hidden [px]", 6)):
        t = tol[col]
        for r in rows:  # every row's one-flip allowance is covered
            if r[col] > 0:
                assert t.atol + t.rtol * r[col] >= 3 * r["path step [px]"] / n - 1e-12
    assert list(table.columns)[-1] == "path step [px]"
    with pytest.raises(ValueError, match="rows"):
        ex.sensitivity_table([], 60, 6)


def test_median_tolerance_covers_every_row():
    rng = np.random.default_rng(1)
    rows = [rng.exponential(scale, size=(12, 20)) for scale in (5.0, 300.0)]
    tol = ex.median_tolerance(rows)
    assert tol.kind == "statistical" and tol.atol == 0
    for e in rows:  # the allowance covers one drive changing arbitrarily, in every row
        assert tol.rtol * np.median(e) >= ex.median_shift_bound(e)
    assert (100 * tol.rtol).is_integer()
    with pytest.raises(ValueError, match="one"):
        ex.median_tolerance([])
    with pytest.raises(ValueError, match="zero"):
        ex.median_tolerance([np.zeros((3, 4))])


def test_covering_tolerance():
    t = ex.covering_tolerance([0.1, 0.5], [1.0, 8.0], "why")
    assert t.atol == pytest.approx(0.1) and t.rtol == pytest.approx(0.05)
    assert t.atol + t.rtol * 8.0 >= 0.5 and t.atol + t.rtol * 1.0 >= 0.1
    with pytest.raises(ValueError, match="> 0"):
        ex.covering_tolerance([0.1], [0.0], "why")
    with pytest.raises(ValueError, match="values"):
        ex.covering_tolerance([0.1, 0.2], [1.0], "why")


def test_bridge_width_study_hides_longer_and_replays_the_page_runs():
    train = [make_slotcar_video(60, np.random.default_rng(s), bridge_width=7.0) for s in (1, 2)]
    bg = ex.training_background(train)
    study = ex.bridge_width_study((7.0, 20.0), {"easy": ({}, 0.5)}, 2, train_seeds=(1, 2), model_seed=3, test_seed=8,
                                  spreads={"1": 1.0}, n_train=60, n_frames=120)
    assert set(study) == {(7.0, "easy"), (20.0, "easy")}
    # the page's own width gives the runs of the page's own study (same seeds, same fits)
    model, sensor = ex.fit_slotcar(train, np.random.default_rng(3), background=bg)
    mfree = ex.MapFree(ex.detector_threshold(train, bg), 5, ex.fit_grid_hmm(train, np.random.default_rng(3),
                                                                               background=bg))
    direct = ex.tracking_study(model, sensor, bg, 2, np.random.default_rng(8), n_frames=120, map_free=mfree)
    for a, b in zip(study[7.0, "easy"][0], direct):
        assert np.allclose(a["viterbi"], b["viterbi"]) and np.allclose(a["grid"], b["grid"])
        assert "grid 1" in a
    tables, tol = ex.bridge_width_tables(study)
    err, passing, walk = tables["errors"], tables["passing"], tables["walk"]
    assert list(err["bridge [px]"]) == [7.0, 20.0] and len(walk) == 2
    s7, s20 = err["longest hidden stretch"]
    assert s20 > s7 >= 1  # a wider deck hides the car for longer
    for col in ("DMA", "DMA smoother", "per-frame", "interpolation", "grid HMM"):
        assert ((passing[col] >= 0) & (passing[col] <= 1)).all()
    assert set(tol) == {"errors", "passing", "walk"} and tol["passing"]["*"].atol == pytest.approx(0.5)
    assert tol["errors"]["DMA"].kind == "statistical"


def test_bridge_width_tables_counts_videos_below_the_limit(slotcar):
    _, _, model, _ = slotcar
    occ = np.array([False, True, True, False])
    trials = [{"viterbi": np.array([9.0, 1.0, 2.0, 9.0]), "smooth": np.full(4, 1.0), "per-frame": np.full(4, 9.0), "detector": np.full(4, 9.0),
               "grid": np.array([0.0, 4.0, 4.0, 0.0]), "gap": np.array(1), "occluded": occ},
              {"viterbi": np.array([0.0, 5.0, 5.0, 0.0]), "smooth": np.full(4, 4.0), "per-frame": np.full(4, 1.0), "detector": np.full(4, 9.0),
               "grid": np.array([0.0, 2.0, 2.0, 0.0]), "gap": np.array(1), "occluded": occ}]
    mfree = ex.MapFree(1.0, 5, type("G", (), {"max_step": 3.0})())
    tables, _ = ex.bridge_width_tables({(7.0, "easy"): (trials, (model, None), mfree)})
    row = tables["passing"].iloc[0]
    assert (row["DMA"], row["per-frame"], row["interpolation"], row["grid HMM"]) == (0.5, 0.5, 0.0, 0.5)
    assert row["DMA smoother"] == 0.5
    err = tables["errors"].iloc[0]
    assert err["DMA"] == pytest.approx(3.25) and err["longest hidden stretch"] == 2.0
    with pytest.raises(ValueError):
        ex.bridge_width_tables({})
    with pytest.raises(ValueError):
        ex.bridge_width_tables({(7.0, "easy"): ([{k: v for k, v in trials[0].items() if k != "grid"}], (model, None),
                                                 mfree)})


def test_fit_seed_study_repeats_the_bridge_study_per_fit():
    opts = dict(train_seeds=(1, 2), test_seed=8, n_train=60, n_frames=120)
    table, tol = ex.fit_seed_study((7.0,), {"easy": ({}, 0.5)}, (3, 4), 2, **opts)
    assert list(table.columns) == ["bridge [px]", "condition", "model seed", "DMA", "DMA smoother"]
    assert list(table["model seed"]) == [3, 4] and tol["*"].atol == pytest.approx(0.5)
    # the seed of the bridge-width study gives that study's share
    study = ex.bridge_width_study((7.0,), {"easy": ({}, 0.5)}, 2, model_seed=3, **opts)
    passing = ex.bridge_width_tables(study)[0]["passing"].iloc[0]
    assert table.iloc[0]["DMA"] == passing["DMA"] and table.iloc[0]["DMA smoother"] == passing["DMA smoother"]
    with pytest.raises(ValueError, match="model_seeds"):
        ex.fit_seed_study((7.0,), {"easy": ({}, 0.5)}, (), 2, **opts)
    with pytest.raises(ValueError, match="conditions"):
        ex.fit_seed_study((7.0,), {}, (3,), 2, **opts)
    with pytest.raises(ValueError, match="widths"):
        ex.fit_seed_study((0.0,), {"easy": ({}, 0.5)}, (3,), 2, **opts)


def test_share_interval_is_clopper_pearson():
    lo, hi = ex.share_interval(0, 15)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 15))
    lo, hi = ex.share_interval(15, 15)
    assert hi == 1.0 and lo == pytest.approx(0.025 ** (1 / 15))
    lo, hi = ex.share_interval(11, 100)
    assert 0.05 < lo < 0.11 < hi < 0.2
    for bad in ((16, 15), (-1, 15), (1, 0)):
        with pytest.raises(ValueError):
            ex.share_interval(*bad)


def test_loglog_slopes_per_path_and_pooled():
    N = np.array([100, 1_000, 10_000, 100_000])
    E = np.vstack([N ** -0.5, np.full(4, 0.3), 2.0 * N ** -1.0])
    assert np.allclose(ex.loglog_slopes(N, E, 1_000), [-0.5, 0.0, -1.0])
    assert np.allclose(ex.loglog_slopes(N, N ** -0.5, 100), [-0.5])
    with pytest.raises(ValueError):
        ex.loglog_slopes(N, E, 100_000)  # one size only
    with pytest.raises(ValueError):
        ex.loglog_slopes(N, E[:, :3], 100)


def test_transition_convergence_per_path_matches_the_table():
    A = np.array([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]])
    table, per = ex.transition_convergence(A, (100, 1_000), 4, np.random.default_rng(0), per_path=True)
    assert per.shape == (4, 2)
    assert np.allclose(np.sqrt((per ** 2).mean(axis=0)), table["Frobenius error"])


def test_f6_verdict_rule_seven_and_first_criterion():
    row = {"perfect after t = 2": 0.95, "right, t = 1-2": 0.9, "right, t >= 3": 0.99}
    assert ex.f6_verdict(row) == "qualitative" and ex.f6_verdict(row, first=True) == "within-tolerance"
    assert ex.f6_verdict({**row, "perfect after t = 2": 0.5}) == "qualitative"
    assert ex.f6_verdict({**row, "perfect after t = 2": 0.49}) == "differs"
    assert ex.f6_verdict({**row, "right, t = 1-2": 0.995}) == "differs"  # errors not at the start

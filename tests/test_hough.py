"""Tests of projtrack.hough (Casasent & Slaski's Hough track initiator)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from projtrack.hough import (
    PULSE_ZERO_VALUE, TrackInitiator, detect_peaks, estimate_track, find_peaks, hough_axes,
    line_through, window_neighbours, hough_transform, hough_transform_image, local_average,
    project_and_correlate, pulse_correlation, rotate_integrate_hough, strip_projection,
    thresholded_hough_transform, track_covariance,
)
from projtrack.experiments.hough import accuracy_experiment, evaluate_initiation, match_lines
from projtrack.scenes.boost import frame_times, in_view_launches, render_frames

SHAPE = (256, 256)


def line_points(rho, theta_deg, ts, shape=SHAPE):
    """Points of the line (rho, theta) (rho from the image centre) at abscissae ts."""
    t = np.deg2rad(theta_deg)
    n = np.array([np.cos(t), np.sin(t)])
    d = np.array([-np.sin(t), np.cos(t)])
    c = np.array([shape[1] / 2, shape[0] / 2]) + rho * n
    return c + np.outer(ts, d)


def same_line(a, b, drho=2.0, dtheta=1.0):
    (r1, t1), (r2, t2) = a, b
    if abs(t1 - t2) <= dtheta and abs(r1 - r2) <= drho:
        return True
    return abs(abs(t1 - t2) - 180) <= dtheta and abs(r1 + r2) <= drho


def brute_force_hough(points, shape, drho, dtheta, origin="center"):
    rhos, thetas = hough_axes(shape, drho, dtheta, origin)
    H = np.zeros((rhos.size, thetas.size))
    cx, cy = (shape[1] / 2, shape[0] / 2) if origin == "center" else (0, 0)
    for x, y in points:
        for j, th in enumerate(thetas):
            rho = (x - cx) * np.cos(np.deg2rad(th)) + (y - cy) * np.sin(np.deg2rad(th))
            i = int(np.argmin(np.abs(rhos - rho)))
            H[i, j] += 1
    return H


# ---------------------------------------------------------------------------------
# the transform
# ---------------------------------------------------------------------------------
def test_axes_match_the_paper():
    rhos, thetas = hough_axes(SHAPE)
    assert rhos[0] == -182 and rhos[-1] == 182 and np.allclose(np.diff(rhos), 2)
    assert thetas.size == 180 and thetas[0] == 0 and thetas[-1] == 179


def test_hough_transform_shapes_and_total_votes():
    rng = np.random.default_rng(0)
    pts = rng.uniform(0, 255, size=(40, 2))
    H, rhos, thetas = hough_transform(pts, SHAPE)
    assert H.shape == (rhos.size, thetas.size)
    assert np.allclose(H.sum(axis=0), 40)  # every point votes once per angle


def test_hough_transform_matches_brute_force():
    rng = np.random.default_rng(1)
    pts = rng.uniform(0, 63.9, size=(15, 2))
    H, _, _ = hough_transform(pts, (64, 64), 2.0, 3.0)
    Hb = brute_force_hough(pts, (64, 64), 2.0, 3.0)
    # ties at exact half-bins may be broken differently
    assert np.count_nonzero(H != Hb) <= 0.01 * H.size


def test_hough_transform_matches_skimage_hough_line():
    skt = pytest.importorskip("skimage.transform")
    rng = np.random.default_rng(2)
    img = np.zeros((96, 128), dtype=bool)
    img[rng.integers(0, 96, 60), rng.integers(0, 128, 60)] = True
    Hs, _, ds = skt.hough_line(img, theta=np.deg2rad(np.arange(180.0)))
    H, rhos, _ = hough_transform_image(img, drho=1.0, origin="corner")
    assert np.allclose(rhos, ds)
    assert np.count_nonzero(Hs != H) <= 0.001 * H.size


def test_hough_image_equals_point_list():
    rng = np.random.default_rng(3)
    img = rng.uniform(size=(50, 70)) < 0.02
    ys, xs = np.nonzero(img)
    H1, _, _ = hough_transform_image(img.astype(int))
    H2, _, _ = hough_transform(np.column_stack([xs, ys]), img.shape)
    assert np.array_equal(H1, H2)


@settings(max_examples=40, deadline=None)
@given(k=st.integers(-40, 40), u=st.floats(-0.5, 0.5), j=st.integers(0, 179), v=st.floats(-0.3, 0.3),
       n=st.integers(12, 30))
def test_collinear_points_give_one_peak_at_their_line(k, u, j, v, n):
    # rho within half a bin of a bin centre (see test_line_split_between_rho_bins for the other case)
    rho, theta = 2 * k + u, (j + v) % 180
    pts = line_points(rho, theta, np.linspace(-60, 60, n))
    H, rhos, thetas = hough_transform(pts, SHAPE)
    peaks = find_peaks(H, rhos, thetas, method="ratio")
    assert len(peaks) == 1
    assert same_line(peaks[0], (rho, theta), drho=2.0, dtheta=1.0)


def test_line_split_between_rho_bins_defeats_the_ratio_rule():
    """A documented property of the paper's rule: a line whose votes split evenly between
    two rho bins has at most half its votes in a cell, so its ratio stays near 2.5 < 3."""
    pts = line_points(1.0, 0.5, np.linspace(-60, 60, 12))
    H, rhos, thetas = hough_transform(pts, SHAPE)
    assert find_peaks(H, rhos, thetas, method="ratio") == []
    assert len(find_peaks(H, rhos, thetas, method="ratio", ratio=2.4)) == 1


@settings(max_examples=25, deadline=None)
@given(rho=st.floats(-50, 50), theta=st.floats(0, 179), sx=st.integers(-30, 30), sy=st.integers(-30, 30))
def test_translation_shifts_rho_by_the_projection_of_the_shift(rho, theta, sx, sy):
    pts = line_points(rho, theta, np.linspace(-40, 40, 25))
    H, rhos, thetas = hough_transform(pts, SHAPE)
    H2, _, _ = hough_transform(pts + [sx, sy], SHAPE)
    i, j = np.unravel_index(np.argmax(H), H.shape)
    shift = sx * np.cos(np.deg2rad(thetas[j])) + sy * np.sin(np.deg2rad(thetas[j]))
    # the column at theta_j is the same histogram moved by the shift along rho
    col = np.flatnonzero(H2[:, j])
    moved = rhos[np.flatnonzero(H[:, j])] + shift
    assert abs(np.average(rhos[col], weights=H2[col, j]) - np.average(moved, weights=H[H[:, j] > 0, j])) <= 2.0


def test_rotation_by_90_degrees_shifts_theta():
    rng = np.random.default_rng(4)
    pts = rng.integers(20, 236, size=(50, 2)).astype(float)
    c = 128.0
    rot = np.column_stack([c - (pts[:, 1] - c), c + (pts[:, 0] - c)])
    H, _, _ = hough_transform(pts, SHAPE)
    Hr, _, _ = hough_transform(rot, SHAPE)
    assert np.count_nonzero(Hr[:, 90:] != H[:, :90]) <= 0.005 * H[:, :90].size


def test_thresholded_counts_frames_not_points():
    within = line_points(10, 30, [-30, -10, 10, 30])  # 4 collinear points in one frame
    frames = [within, np.zeros((0, 2))]
    H, rhos, thetas = thresholded_hough_transform(frames, SHAPE)
    Hp, _, _ = hough_transform(within, SHAPE)
    assert Hp.max() == 4 and H.max() == 1
    assert np.array_equal(H, (Hp >= 1).astype(float))


def test_thresholded_track_keeps_one_vote_per_frame():
    pts = line_points(-20, 120, np.arange(-50, 51, 5.0))
    H, _, _ = thresholded_hough_transform([p[None, :] for p in pts], SHAPE)
    Hp, _, _ = hough_transform(pts, SHAPE)
    assert np.array_equal(H, Hp)


def test_rotate_and_integrate_equals_voting_hough():
    img = np.zeros(SHAPE, dtype=bool)
    pts = np.rint(line_points(30, 60, np.arange(-60, 61, 6.0))).astype(int)
    img[pts[:, 1], pts[:, 0]] = True
    Hv, rhos, thetas = hough_transform_image(img, dtheta_deg=5.0)
    Hr, _, _ = rotate_integrate_hough(img, dtheta_deg=5.0)
    assert abs(Hr.sum() - Hv.sum()) <= 0.02 * Hv.sum()  # bilinear rotation nearly conserves mass
    assert np.corrcoef(Hr.ravel(), Hv.ravel())[0, 1] > 0.9
    assert np.unravel_index(np.argmax(Hr), Hr.shape) == np.unravel_index(np.argmax(Hv), Hv.shape)


# ---------------------------------------------------------------------------------
# peaks
# ---------------------------------------------------------------------------------
def test_local_average_of_constant_plane_and_wrap():
    rhos, thetas = hough_axes((64, 64))
    H = np.ones((rhos.size, thetas.size))
    A = local_average(H, 5, rhos=rhos, thetas_deg=thetas)
    assert np.allclose(A[2:-2, :], 1.0)  # theta wraps, so no edge loss in theta
    A0 = local_average(H, 5)
    assert A0[10, 0] == pytest.approx(15 / 25)


def test_peak_floor_suppresses_sparse_cells():
    rhos, thetas = hough_axes((64, 64))
    H = np.zeros((rhos.size, thetas.size))
    H[10, 20] = 2  # ratio 25 but only two votes: no evidence of collinearity
    assert find_peaks(H, rhos, thetas, method="ratio") == []
    assert len(find_peaks(H, rhos, thetas, method="ratio", min_votes=1)) == 1


def test_bridge_joins_split_peak_and_requires_one_strong_cell():
    rhos, thetas = hough_axes((64, 64))
    H = np.zeros((rhos.size, thetas.size))
    H[20, 40] = 20
    H[20, 41] = 6  # weaker neighbour, ratio between 1.5 and 3: joined to the same peak
    peaks = detect_peaks(H, rhos, thetas)
    assert len(peaks) == 1 and peaks[0].n_cells == 2
    assert thetas[40] < peaks[0].theta_deg < thetas[41]


def test_two_lines_two_peaks():
    pts = np.vstack([line_points(-40, 30, np.linspace(-70, 70, 25)), line_points(50, 120, np.linspace(-70, 70, 25))])
    H, rhos, thetas = hough_transform(pts, SHAPE)
    peaks = find_peaks(H, rhos, thetas, method="ratio")
    assert len(peaks) == 2
    assert any(same_line(p, (-40, 30), 2, 1.5) for p in peaks)
    assert any(same_line(p, (50, 120), 2, 1.5) for p in peaks)


def test_no_duplicate_peak_across_theta_wrap():
    pts = line_points(20, 0.3, np.linspace(-80, 80, 30))
    H, rhos, thetas = hough_transform(pts, SHAPE)
    assert len(find_peaks(H, rhos, thetas, method="ratio")) == 1


# ---------------------------------------------------------------------------------
# projection and estimation
# ---------------------------------------------------------------------------------
def brute_pulse(P, zero=PULSE_ZERO_VALUE):
    q = np.where(np.asarray(P) > 0, P, zero)
    return max(q[a:b + 1].sum() for a in range(len(q)) for b in range(a, len(q)))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(0, 3), min_size=1, max_size=40))
def test_pulse_correlation_is_the_best_pulse(P):
    I, start, L = pulse_correlation(P)
    if not any(P):
        assert I == 0
        return
    assert I == pytest.approx(brute_pulse(P))
    q = np.where(np.asarray(P) > 0, P, PULSE_ZERO_VALUE)
    assert q[start:start + L].sum() == pytest.approx(I)


def test_worked_example_of_fig1():
    P = np.zeros(32, dtype=int)
    P[[1, 3, 6, 9, 30]] = 1
    r = project_and_correlate(P)
    assert (r.n_ones, r.dx, r.L, r.I, r.j, r.P_j, r.confirmed) == (5, 4, 3, 4.0, 2, 1.0, True)
    assert r.x_prime == pytest.approx(4 * (2 + 0.5 * 3 / 4))  # Eq. (5)


def test_unconfirmed_when_no_run_reaches_75_percent():
    P = np.zeros(200, dtype=int)
    P[::20] = 1  # ten isolated ones, 20 apart: dx' = 16 still leaves gaps
    r = project_and_correlate(P, dx_max=16)
    assert not r.confirmed and r.dx == 16


def test_strip_projection_counts_points_in_the_strip():
    pts = np.vstack([line_points(0, 90, np.arange(-20, 21, 4.0)), [[10, 200]]])
    counts, x0, d = strip_projection(pts, SHAPE, 0.0, 90.0, heading_hint=(1, 0))
    assert counts.sum() == 11 and np.allclose(d, [1, 0], atol=1e-12)


def test_estimate_track_on_a_clean_constant_velocity_track():
    T, n, speed = 0.25, 21, 12.0
    d = np.array([np.cos(0.9), np.sin(0.9)])
    pts = np.array([60, 40]) + np.outer(np.arange(n) * speed * T, d)
    H, rhos, thetas = hough_transform(pts, SHAPE)
    rho, th = find_peaks(H, rhos, thetas, method="ratio", min_votes=6)[0]
    est = estimate_track(pts, SHAPE, rho, th, frame_time=T, n_frames=n, jitter_sigma=0.0)
    assert est.confirmed
    assert np.linalg.norm(est.position - pts[-1]) < 3.0
    assert abs(est.speed - speed) < 1.5
    assert est.velocity @ d > 0
    assert np.allclose(est.predict(8), est.position + 8 * T * est.velocity)
    assert np.allclose(est.covariance, est.covariance.T) and np.all(np.linalg.eigvalsh(est.covariance) > 0)


def test_pd_compensation_scales_speed():
    pts = line_points(0, 45, np.arange(-40, 41, 3.0))
    a = estimate_track(pts, SHAPE, 0.0, 45.0, frame_time=0.25, n_frames=27)
    b = estimate_track(pts, SHAPE, 0.0, 45.0, frame_time=0.25, n_frames=27, p_detect=0.8)
    assert b.speed == pytest.approx(0.8 * a.speed)  # Eq. (7)


def test_noise_free_tracks_within_predicted_covariance():
    """Across-track errors always inside 3 sigma of Eqs. (9), (13); along-track ones in most cases."""
    rng = np.random.default_rng(5)
    inside_x = inside_vx = total = 0
    for _ in range(120):
        speed, head, T, n = rng.uniform(2, 30), rng.uniform(10, 170), 0.25, 21
        d = np.array([np.cos(np.deg2rad(head)), np.sin(np.deg2rad(head))])
        nn = np.array([-d[1], d[0]])
        pts = np.array([128, 128]) - d * speed * T * n / 2 + rng.uniform(-20, 20, 2) + np.outer(np.arange(n) * speed * T, d)
        H, rhos, thetas = hough_transform(pts, SHAPE)
        peaks = detect_peaks(H, rhos, thetas, min_votes=6)
        if not peaks:
            continue
        est = estimate_track(pts, SHAPE, peaks[0].rho, peaks[0].theta_deg, frame_time=T, n_frames=n,
                             jitter_sigma=0.0, heading_hint=d)
        sig = {k: np.sqrt(v) for k, v in track_covariance(speed, T, n, jitter_sigma=0.0).items()}
        e, ev = est.position - pts[-1], est.velocity - speed * d
        assert abs(e @ nn) <= 3 * sig["var_y"]
        assert abs(ev @ nn) <= 3 * sig["var_vy"]
        total += 1
        inside_x += abs(e @ d) <= 3 * sig["var_x"]
        inside_vx += abs(ev @ d) <= 3 * sig["var_vx"]
    assert total >= 100
    assert inside_x / total >= 0.9 and inside_vx / total >= 0.9


def test_track_covariance_formulas():
    c = track_covariance(30.0, 0.25, 20, drho=2.0, jitter_sigma=0.5, total_time=5.0)
    assert c["var_x"] == pytest.approx((30 * 0.25) ** 2 / 12 + 0.25)
    assert c["var_y"] == pytest.approx(4 / 3)
    assert c["var_vx"] == pytest.approx(900 / (3 * 400) + 0.25 / (400 * 0.0625))
    assert c["var_vy"] == pytest.approx(16 / (3 * 25))
    assert np.sqrt(c["var_x"] + c["var_y"]) == pytest.approx(2.5, abs=0.01)  # the paper's worst case


# ---------------------------------------------------------------------------------
# the initiator
# ---------------------------------------------------------------------------------
def test_initiator_finds_separated_straight_tracks():
    times = frame_times(21, 0.25)
    starts = [(30, 20), (120, 10), (200, 30)]
    vels = [(8, 26), (0, 28), (-12, 24)]  # below the design maximum of 7.5 px/frame
    frames = [np.array([np.rint(np.add(s, np.multiply(v, t))) for s, v in zip(starts, vels)]) for t in times]
    init = TrackInitiator()
    tracks = init.initiate(frames, times, SHAPE)
    assert len(tracks) == 3
    last = np.array([np.add(s, np.multiply(v, times[-1])) for s, v in zip(starts, vels)])
    for tr in tracks:
        assert np.min(np.linalg.norm(last - tr.position, axis=1)) < 6.0
    assert init.empty_peaks_ == [] and len(init.tracks_) == len(init.peaks_)
    assert all(np.all(np.isfinite(t.position)) for t in init.tracks_)


def test_evaluate_initiation_counts_false_and_true_lines():
    rng = np.random.default_rng(6)
    times = frame_times(21, 0.25)
    trajs = in_view_launches(rng, 4, times)
    frames = render_frames(trajs, times, rng, n_noise=5)
    r = evaluate_initiation(TrackInitiator(ratio=2.5), frames, trajs)
    assert r["n_lines"] == r["n_true_lines"] + r["n_false_lines"]
    assert r["n_found"] <= r["n_targets"] <= 4
    assert all(t["target"] in r["found"] for t in r["tracks"])
    assert all(abs(t["pos_err_along"]) <= t["pos_err"] + 1e-9 for t in r["tracks"])


def test_match_lines():
    pts = line_points(10, 40, np.arange(-30, 31, 5.0))
    lab = np.zeros(len(pts), dtype=int)
    assert list(match_lines([(10, 40), (-60, 100)], pts, lab, SHAPE)) == [0, -1]


def test_accuracy_experiment_keys_and_predictions():
    r = accuracy_experiment(np.random.default_rng(7), 10.0, 0.25, n_targets=5)
    assert r["n_p"] == 20 and r["pred_y"] == pytest.approx(2 / np.sqrt(3))
    assert r["std_y"] < 2 * r["pred_y"]


# ---------------------------------------------------------------------------------
# bad inputs
# ---------------------------------------------------------------------------------
@pytest.mark.parametrize("pts", [[[300.0, 10.0]], [[-1.0, 5.0]], [[10.0, 256.0]], [[np.nan, 3.0]]])
def test_points_outside_image_or_not_finite(pts):
    with pytest.raises(ValueError):
        hough_transform(pts, SHAPE)


def test_bad_point_arrays_and_shapes():
    with pytest.raises(ValueError, match="empty"):
        hough_transform(np.zeros((0, 2)), SHAPE)
    H, _, _ = hough_transform(np.zeros((0, 2)), SHAPE, allow_empty=True)
    assert not H.any()
    with pytest.raises(ValueError):
        hough_transform(np.zeros((3, 3)), SHAPE)
    with pytest.raises(ValueError):
        hough_transform([[1, 2]], (256,))
    with pytest.raises(ValueError):
        hough_transform([[1, 2]], (0, 10))
    with pytest.raises(ValueError):
        hough_transform([[1, 2]], SHAPE, drho=0)
    with pytest.raises(TypeError):
        hough_transform([[1, 2]], SHAPE, drho="2")
    with pytest.raises(ValueError):
        hough_transform([[1, 2]], SHAPE, origin="middle")


def test_non_binary_image():
    img = np.zeros((10, 10))
    img[2, 3] = 2
    with pytest.raises(ValueError, match="binary"):
        hough_transform_image(img)
    with pytest.raises(ValueError, match="binary"):
        rotate_integrate_hough(img)
    with pytest.raises(ValueError):
        hough_transform_image(np.zeros(5))


def test_empty_frames():
    with pytest.raises(ValueError, match="empty"):
        thresholded_hough_transform([], SHAPE)
    with pytest.raises(ValueError, match="empty"):
        thresholded_hough_transform([np.zeros((0, 2)), np.zeros((0, 2))], SHAPE)
    with pytest.raises(ValueError, match="empty"):
        TrackInitiator().initiate([np.zeros((0, 2))] * 3, [0, 1, 2], SHAPE)


def test_inconsistent_frame_times():
    frames = [np.array([[10.0 + k, 10.0 + k]]) for k in range(4)]
    init = TrackInitiator()
    with pytest.raises(ValueError, match="evenly spaced"):
        init.initiate(frames, [0, 0.25, 0.5, 1.0], SHAPE)
    with pytest.raises(ValueError, match="increasing"):
        init.initiate(frames, [0, 0.25, 0.25, 0.5], SHAPE)
    with pytest.raises(ValueError, match="one time per frame"):
        init.initiate(frames, [0, 0.25], SHAPE)
    with pytest.raises(ValueError, match="frames"):
        init.initiate([[[300.0, 1.0]]] * 4, [0, 0.25, 0.5, 0.75], SHAPE)


def test_bad_peak_inputs():
    rhos, thetas = hough_axes((32, 32))
    with pytest.raises(ValueError, match="shape"):
        find_peaks(np.zeros((3, 3)), rhos, thetas)
    with pytest.raises(ValueError, match="non-negative"):
        find_peaks(-np.ones((rhos.size, thetas.size)), rhos, thetas)
    with pytest.raises(ValueError, match="finite"):
        find_peaks(np.full((rhos.size, thetas.size), np.nan), rhos, thetas)
    with pytest.raises(ValueError, match="bridge"):
        find_peaks(np.zeros((rhos.size, thetas.size)), rhos, thetas, method="ratio", ratio=1.0, bridge=2.0)
    with pytest.raises(ValueError, match="min_votes"):
        find_peaks(np.zeros((rhos.size, thetas.size)), rhos, thetas, min_votes=-1)
    with pytest.raises(ValueError, match="odd"):
        local_average(np.zeros((5, 5)), 4)


def test_bad_projection_and_estimation_inputs():
    with pytest.raises(ValueError):
        pulse_correlation([])
    with pytest.raises(ValueError):
        pulse_correlation([1, -1])
    with pytest.raises(ValueError, match="power of two"):
        project_and_correlate([1, 0, 1], dx_max=12)
    with pytest.raises(ValueError, match="confirm_fraction"):
        project_and_correlate([1, 0, 1], confirm_fraction=1.5)
    with pytest.raises(ValueError, match="p_detect"):
        estimate_track([[10, 10]], SHAPE, 0.0, 0.0, frame_time=0.25, n_frames=3, p_detect=0)
    with pytest.raises(ValueError, match="frame_time"):
        estimate_track([[10, 10]], SHAPE, 0.0, 0.0, frame_time=-1, n_frames=3)
    with pytest.raises(ValueError, match="heading_hint"):
        strip_projection([[10, 10]], SHAPE, 0.0, 0.0, heading_hint=(0, 0))
    with pytest.raises(ValueError, match="n_frames"):
        track_covariance(1.0, 0.25, 0)
    with pytest.raises(ValueError, match="speed"):
        track_covariance(-1.0, 0.25, 3)
    with pytest.raises(ValueError, match="labels"):
        match_lines([(0, 0)], [[1, 1], [2, 2]], [0], SHAPE)
    with pytest.raises(ValueError, match="p_detect"):
        TrackInitiator(p_detect=1.5)
    with pytest.raises(ValueError, match="dx_max"):
        TrackInitiator(dx_max=10)
    with pytest.raises(ValueError, match="confirm_fraction"):
        TrackInitiator(confirm_fraction=0)


@settings(max_examples=30, deadline=None)
@given(rho=st.floats(-80, 80), theta=st.floats(0, 179.9))
def test_line_through_recovers_the_line(rho, theta):
    pts = line_points(rho, theta, np.linspace(-50, 50, 11))
    r, t = line_through(pts, SHAPE)
    assert same_line((r, t), (rho, theta), drho=1e-6, dtheta=1e-6) or same_line((r, t), (rho, theta), 1e-3, 1e-3)


def test_window_neighbours():
    assert list(window_neighbours([(0, 10), (3, 11), (40, 0.5), (-40, 179)])) == [True, True, True, True]
    assert list(window_neighbours([(0, 10), (10, 10), (0, 20)])) == [False, False, False]
    with pytest.raises(ValueError):
        line_through([[1.0, 1.0]], SHAPE)


def test_empty_strip_raises_instead_of_nan():
    with pytest.raises(ValueError, match="all zero"):
        project_and_correlate(np.zeros(40, dtype=int))
    # one point far from the line y = 0 (theta = 90 deg): the strip |y'| <= 2 is empty
    with pytest.raises(ValueError, match="holds none of the points"):
        estimate_track([[10.0, 200.0]], SHAPE, 0.0, 90.0, frame_time=0.25, n_frames=3)
    with pytest.raises(ValueError, match="holds none of the points"):
        estimate_track(np.zeros((0, 2)), SHAPE, 0.0, 90.0, frame_time=0.25, n_frames=3)


def test_nonempty_strip_gives_finite_estimate():
    r = project_and_correlate([0, 0, 1, 0])
    assert np.isfinite(r.x_prime) and r.confirmed
    est = estimate_track([[128.0, 130.0]], SHAPE, 0.0, 0.0, frame_time=0.25, n_frames=1)
    assert np.all(np.isfinite(est.position)) and np.isfinite(est.speed)


def test_line_through_rejects_identical_points():
    with pytest.raises(ValueError, match="distinct"):
        line_through([[5.0, 7.0], [5.0, 7.0], [5.0, 7.0]], SHAPE)
    rho, theta = line_through([[5.0, 7.0], [5.0, 7.0], [6.0, 7.0]], SHAPE)
    assert theta == pytest.approx(90.0)



class _PerturbedTrig:
    """numpy with cos/sin moved by a relative ``eps`` (another CPU's last bit)."""

    def __init__(self, eps):
        self.eps = eps

    def __getattr__(self, name):
        return getattr(np, name)

    def cos(self, x):
        return np.cos(x) * (1.0 + self.eps)

    def sin(self, x):
        return np.sin(x) * (1.0 + self.eps)


@pytest.mark.parametrize("eps", [0.0, -1e-13, 1e-13])
@pytest.mark.parametrize("theta", [30, 60, 120, 150])
def test_points_on_a_rho_bin_boundary_vote_the_same_on_every_cpu(theta, eps, monkeypatch):
    # corner origin, drho = 1: a pixel at odd x (60/120 deg) or odd y (30/150 deg) has
    # rho = +-k/2 exactly, on a bin boundary; cos/sin may be off in the last bits, and the
    # bin must not depend on that: ties go up.
    from projtrack.hough import transform as hmod
    monkeypatch.setattr(hmod, "np", _PerturbedTrig(eps))
    rhos, _ = hough_axes((16, 16), 1.0, 1.0, origin="corner")
    for k in (1, 3, 5, 7):
        if theta in (60, 120):
            pt, exact = [[float(k), 0.0]], (k if theta == 60 else -k) / 2.0
        else:
            pt, exact = [[0.0, float(k)]], k / 2.0
        want = int(np.flatnonzero(np.isclose(rhos, exact + 0.5))[0])
        H, _, _ = hough_transform(np.array(pt), (16, 16), 1.0, 1.0, origin="corner")
        assert H[want, theta] == 1.0, (theta, eps, k)


def test_step_schedule_of_dx_on_the_fig1_example():
    # stepping dx' by one stops at dx' = 3 (samples 0-2, 3-5, 6-8, 9-11 each hold one point),
    # where doubling stops at 4
    P = np.zeros(32, dtype=int)
    P[[1, 3, 6, 9, 30]] = 1
    r = project_and_correlate(P, dx_schedule="step")
    assert (r.dx, r.L, r.I, r.j, r.P_j, r.confirmed) == (3, 4, 4.0, 3, 1.0, True)
    assert [h[0] for h in r.history] == [1, 2, 3]
    assert r.x_prime == pytest.approx(3 * (3 + 0.5 * 4 / 4))  # Eq. (5)
    assert project_and_correlate(P, dx_schedule="step", dx_max=3).dx == 3
    with pytest.raises(ValueError, match="dx_schedule"):
        project_and_correlate(P, dx_schedule="halve")
    with pytest.raises(ValueError, match="power of two"):
        project_and_correlate(P, dx_max=3)

"""The bad inputs an outside user met (the library issue), each with a clear error naming the argument.

Also the behaviour added for library users: per-target ``P0``, states and covariances of the
trackers, the MVM convention and its helper, the local-maximum peak finder (the default of
``hough.find_peaks``) and the least-squares refinement of the Hough initiator.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from projtrack import ellipsoids as E
from projtrack import hough, jpda

pytest.importorskip("filterpy")

F = np.array([[1.0, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1], [0, 0, 0, 1]])
H = np.array([[1.0, 0, 0, 0], [0, 0, 1, 0]])
Q = 0.01 * np.eye(4)
R = 0.1 * np.eye(2)
X0 = [[-5.0, 1, -5, 1], [-5.0, 1, 5, -1]]


def _tracker(cls=jpda.JPDATracker, **kw):
    args = dict(x0=X0, P0=np.eye(4), F=F, Q=Q, H=H, R=R)
    args.update(kw)
    return cls(**args)


# --- covariances checked at the door, the message names the argument -------------------------

@pytest.mark.parametrize("cls", [jpda.JPDATracker, jpda.GNNTracker])
@pytest.mark.parametrize("name,value,msg", [
    ("R", -0.1 * np.eye(2), "R must be positive semidefinite"),
    ("Q", -0.01 * np.eye(4), "Q must be positive semidefinite"),
    ("P0", -np.eye(4), "P0 must be positive semidefinite"),
    ("R", np.array([[0.1, 0.05], [0.0, 0.1]]), "R must be symmetric"),
    ("Q", np.triu(np.ones((4, 4))), "Q must be symmetric"),
    ("P0", np.array([np.eye(4), -np.eye(4)]), r"P0\[1\] must be positive semidefinite"),
    ("P0", np.ones((3, 4, 4)), r"P0 must be one 4 x 4 matrix or 2 of them"),
])
def test_tracker_refuses_bad_covariances_naming_them(cls, name, value, msg):
    with pytest.raises(ValueError, match=msg):
        _tracker(cls, **{name: value})


def test_singular_innovation_covariance_names_R():
    trk = _tracker(P0=np.zeros((4, 4)), Q=np.zeros((4, 4)), R=np.zeros((2, 2)))
    with pytest.raises(ValueError, match="positive definite R"):
        trk.step([[0.0, 0.0]])


@pytest.mark.parametrize("cls", [jpda.JPDATracker, jpda.GNNTracker])
def test_no_targets_give_well_shaped_empty_outputs(cls):
    trk = cls(np.zeros((0, 4)), np.eye(4), F, Q, H, R)
    x = trk.step([[1.0, 2.0], [3.0, 4.0]])
    assert x.shape == (0, 4)
    assert trk.states.shape == (0, 4) and trk.covariances.shape == (0, 4, 4)
    assert trk.step([]).shape == (0, 4)
    if cls is jpda.JPDATracker:
        assert trk.last_beta_.shape == (1, 0)


# --- per-target P0, states and covariances exposed ------------------------------------------

def test_per_target_P0_and_exposed_covariances():
    P0 = np.array([np.eye(4), 4 * np.eye(4)])
    trk = _tracker(P0=P0)
    np.testing.assert_array_equal(trk.covariances, P0)
    np.testing.assert_array_equal(trk.states, np.asarray(X0))
    x = trk.step([[-4.0, -4.0], [-4.0, 4.0]])
    np.testing.assert_array_equal(x, trk.states)
    P = trk.covariances
    assert P.shape == (2, 4, 4)
    np.testing.assert_allclose(P, np.swapaxes(P, 1, 2))
    assert np.all(np.linalg.eigvalsh(P) > 0)
    # the target started less certain keeps the larger covariance
    assert np.trace(P[1]) > np.trace(P[0])


def test_one_P0_for_all_is_the_same_as_one_per_target():
    a, b = _tracker(P0=np.eye(4)), _tracker(P0=np.array([np.eye(4), np.eye(4)]))
    scan = [[-4.1, -3.9], [-3.9, 4.1], [10.0, 10.0]]
    np.testing.assert_array_equal(a.step(scan), b.step(scan))
    np.testing.assert_array_equal(a.covariances, b.covariances)


# --- the MVM convention and its helper --------------------------------------------------------

def test_mvm_from_positions_row0_is_one_minus_pd_pg_and_the_tracker_uses_it():
    z = np.array([[-4.1, -3.9], [-3.9, 4.1], [10.0, 10.0]])
    trk = _tracker(p_detect=0.8, gate_prob=0.95, clutter_density=0.01)
    trk.step(z)
    np.testing.assert_allclose(trk.last_mvm_[0], 1 - 0.8 * 0.95)
    # rebuilt from the predicted positions and innovation covariances of the same scan
    x_pred = np.asarray(X0) @ F.T
    P_pred = F @ np.eye(4) @ F.T + Q
    S = np.array([H @ P_pred @ H.T + R] * 2)
    w = jpda.mvm_from_positions(z, x_pred @ H.T, S, p_detect=0.8, gate_prob=0.95,
                                clutter_density=0.01)
    np.testing.assert_allclose(w, trk.last_mvm_, rtol=1e-12)
    np.testing.assert_allclose(jpda.beta(w), trk.last_beta_, rtol=1e-12)
    # the paper's eq. (3) differs only in row 0
    paper = jpda.modified_validation_matrix(z, x_pred @ H.T, S, 0.8, 0.95, 0.01)
    np.testing.assert_allclose(paper[0], 1 - 0.8)
    np.testing.assert_array_equal(paper[1:], w[1:])


@pytest.mark.parametrize("kw,err,msg", [
    (dict(covariances=np.array([-np.eye(2), np.eye(2)])), ValueError, r"covariances\[0\] must be positive"),
    (dict(covariances=np.eye(2)), ValueError, "covariances must be a 3-D array"),
    (dict(positions=[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]), ValueError, r"covariances must have shape \(2, 3, 3\)"),
    (dict(measurements=[[1.0, 2.0, 3.0]]), ValueError, r"measurements must have shape \(m, 2\)"),
    (dict(p_detect=0.0), ValueError, "p_detect"),
])
def test_mvm_from_positions_names_bad_arguments(kw, err, msg):
    args = dict(measurements=[[0.0, 0.0]], positions=[[0.0, 0.0], [3.0, 0.0]],
                covariances=np.array([np.eye(2), np.eye(2)]), p_detect=0.9)
    args.update(kw)
    with pytest.raises(err, match=msg):
        jpda.mvm_from_positions(**args)


# --- flags must be bools ----------------------------------------------------------------------

@pytest.mark.parametrize("flag", ["thresholded", "refine"])
@pytest.mark.parametrize("value", ["no", 0, 1, None])
def test_initiator_flags_must_be_bools(flag, value):
    with pytest.raises(TypeError, match=f"{flag} must be a bool"):
        hough.TrackInitiator(**{flag: value})


# --- ellipsoids: the view hint and negative support data -------------------------------------

def test_directions_as_one_array_get_the_right_hint():
    dirs = np.array([[1.0, 0.0], [0.0, 1.0], [np.sqrt(0.5), np.sqrt(0.5)]])
    with pytest.raises(TypeError, match=r"list\(directions\)") as info:
        E.reconstruct([1.0, 2.0, 1.5], dirs)
    assert "wrap a single" not in str(info.value)
    X = E.reconstruct([1.0, 2.0, 1.5], list(dirs))   # the hint works
    assert X.shape == (2, 2)


def test_negative_support_values_warn_and_the_constrained_estimate_does_not():
    dirs = [np.array([np.cos(p), np.sin(p)]) for p in np.linspace(0, np.pi, 6, endpoint=False)]
    Ys = [E.project(np.diag([4.0, 0.01]), c) for c in dirs]
    Ys[3] = -0.5                                       # an impossible squared support value
    with pytest.warns(E.IndefiniteDataWarning, match=r"Ys\[3\].*negative squared support value"):
        X = E.reconstruct(Ys, dirs)
    assert np.linalg.eigvalsh(X)[0] < 0                # the estimate is indeed not an ellipse
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Xc = E.reconstruct(Ys, dirs, lower=0, method="halfspace")
    assert np.linalg.eigvalsh(Xc)[0] > -1e-6


def test_psd_data_do_not_warn():
    dirs = [np.array([np.cos(p), np.sin(p)]) for p in np.linspace(0, np.pi, 6, endpoint=False)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        E.reconstruct([E.project(np.diag([4.0, 1.0]), c) for c in dirs], dirs)


# --- the peak finder a user gets by default ---------------------------------------------------

def _lines_in_noise(rng, n_noise):
    t = np.linspace(-60, 60, 40)
    lines = [np.c_[t, 0.5 * t], np.c_[t, -t + 20], np.c_[30 + 0 * t, t], np.c_[0.5 * t - 40, t]]
    noise = rng.uniform(-110, 110, (n_noise, 2))
    return np.vstack(lines + [noise]) + 128


@pytest.mark.parametrize("seed", range(5))
def test_local_max_finds_clear_lines_in_uniform_noise(seed):
    pts = _lines_in_noise(np.random.default_rng(seed), 300)
    H_, rhos, thetas = hough.hough_transform(pts, (256, 256))
    found = hough.find_peaks(H_, rhos, thetas)
    assert len(found) == 4
    np.testing.assert_allclose(sorted(th for _, th in found), [0, 45, 116.6, 153.4], atol=1.5)


@pytest.mark.parametrize("seed", range(3))
def test_local_max_on_128_points_gives_the_lines_not_dozens_of_peaks(seed):
    rng = np.random.default_rng(seed)
    t = np.linspace(-50, 50, 30)
    lines = [np.c_[t, 0.5 * t], np.c_[t, -t + 20], np.c_[30 + 0 * t, t]]
    pts = np.vstack(lines + [rng.uniform(-100, 100, (38, 2))]) + 128   # 128 points
    H_, rhos, thetas = hough.hough_transform(pts, (256, 256))
    assert len(hough.find_peaks(H_, rhos, thetas)) == 3
    assert len(hough.find_peaks(H_, rhos, thetas, method="ratio")) > 10   # the paper's rule
    assert len(hough.find_peaks(H_, rhos, thetas, threshold=3, num_peaks=5)) == 5


def test_local_max_wraps_theta():
    # a horizontal line: its peak sits at theta = 90, and a near-vertical one near 0 / 180
    t = np.linspace(-60, 60, 50)
    pts = np.vstack([np.c_[0.01 * t + 20, t]]) + 128
    H_, rhos, thetas = hough.hough_transform(pts, (256, 256))
    found = hough.find_peaks(H_, rhos, thetas, threshold=10)
    assert len(found) == 1


@pytest.mark.parametrize("kw,err,msg", [
    (dict(method="max"), ValueError, "method must be one of"),
    (dict(min_distance=-1), ValueError, "min_distance"),
    (dict(min_angle=1.5), TypeError, "min_angle"),
    (dict(num_peaks=0), ValueError, "num_peaks"),
    (dict(threshold=-1.0), ValueError, "threshold"),
])
def test_find_peaks_names_bad_arguments(kw, err, msg):
    H_, rhos, thetas = hough.hough_transform(np.array([[10.0, 10.0], [20.0, 20.0]]), (64, 64))
    with pytest.raises(err, match=msg):
        hough.find_peaks(H_, rhos, thetas, **kw)


# --- the initiator's accuracy, and the refinement -----------------------------------------

def _straight_tracks(n_frames, speed):
    times = np.arange(n_frames) * 0.1
    start = np.array([[40.0, 30.0], [200.0, 40.0], [120.0, 20.0]])
    dirs = np.array([[0.6, 0.8], [-0.5, 0.866], [0.1, 0.995]])
    vel = speed / 0.1 * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    truth_last = start + vel * times[-1]
    return [start + vel * t for t in times], times, truth_last, vel


@pytest.mark.parametrize("n_frames,speed", [(16, 4.0), (24, 3.0), (12, 8.0)])
def test_refinement_recovers_noise_free_tracks(n_frames, speed):
    frames, times, truth, vel = _straight_tracks(n_frames, speed)
    paper = hough.TrackInitiator().initiate(frames, times, (256, 256))
    refined = hough.TrackInitiator(refine=True).initiate(frames, times, (256, 256))
    assert len(refined) == len(paper) == 3
    for tr in refined:
        k = int(np.argmin(np.linalg.norm(truth - tr.position, axis=1)))
        assert tr.refined
        assert np.linalg.norm(tr.position - truth[k]) < 1.0
        assert abs(tr.speed / np.linalg.norm(vel[k]) - 1) < 0.01
        assert np.all(np.linalg.eigvalsh(tr.covariance) > 0)
    for tr in paper:
        assert not tr.refined


def _climbing_tracks(rng, rounded=False):
    n = int(rng.integers(8, 33))
    speed = rng.uniform(1.5, 8)
    times = np.arange(n) * 0.1
    ang = rng.uniform(0.15 * np.pi, 0.85 * np.pi, 3)          # moving along heading_hint (+y)
    start = rng.uniform(30, 226, (3, 2))
    vel = speed / 0.1 * np.c_[np.cos(ang), np.sin(ang)]
    truth = start + vel * times[-1]
    frames = [start + vel * t for t in times]
    return frames, times, truth, vel


def _errors(refine):
    rng = np.random.default_rng(3)
    out = []
    for _ in range(60):
        frames, times, truth, vel = _climbing_tracks(rng)
        if np.any(truth < 5) or np.any(truth > 250):
            continue
        for tr in hough.TrackInitiator(refine=refine).initiate(frames, times, (256, 256)):
            k = int(np.argmin(np.linalg.norm(truth - tr.position, axis=1)))
            out.append((np.linalg.norm(tr.position - truth[k]), tr.speed / np.linalg.norm(vel[k])))
    return np.array(out)


def test_documented_accuracy_of_the_papers_estimator_and_of_the_refinement():
    # the figures quoted in the docstring of TrackInitiator ("Expected accuracy")
    e = _errors(refine=False)
    assert len(e) == 86
    assert np.median(e[:, 0]) < 1.0 and np.percentile(e[:, 0], 90) < 2.5 and e[:, 0].max() < 3.5
    lo, hi = np.percentile(e[:, 1], [5, 95])
    assert 0.93 < lo < 1.0 < hi < 1.16 and e[:, 1].min() > 0.94 and e[:, 1].max() < 1.23
    r = _errors(refine=True)
    assert len(r) == 86 and r[:, 0].max() < 1e-6 and np.abs(r[:, 1] - 1).max() < 1e-6


def test_refinement_takes_the_direction_from_the_times():
    times = np.arange(16) * 0.1
    start, vel = np.array([[128.0, 200.0]]), np.array([[10.0, -40.0]])   # moving down, against the hint
    frames = [start + vel * t for t in times]
    paper = hough.TrackInitiator().initiate(frames, times, (256, 256))[0]
    refined = hough.TrackInitiator(refine=True).initiate(frames, times, (256, 256))[0]
    np.testing.assert_allclose(refined.position, start[0] + vel[0] * times[-1], atol=1e-6)
    np.testing.assert_allclose(refined.velocity, vel[0], atol=1e-6)
    assert np.linalg.norm(paper.position - start[0]) < 4          # the oldest end, as documented


def test_indefinite_data_warning_can_be_silenced_for_studies():
    dirs = [np.array([np.cos(p), np.sin(p)]) for p in np.linspace(0, np.pi, 6, endpoint=False)]
    Ys = [E.project(np.diag([4.0, 0.01]), c) for c in dirs]
    Ys[3] = -0.5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        X = E.reconstruct(Ys, dirs, indefinite="ignore")
    np.testing.assert_array_equal(X, E.reconstruct(Ys, dirs, indefinite="ignore"))
    with pytest.raises(ValueError, match="indefinite must be one of"):
        E.reconstruct(Ys, dirs, indefinite="no")


@pytest.mark.parametrize("call", [
    lambda: __import__("projtrack.correlators", fromlist=["x"]).ProjectionCorrelationClassifier(zero_mean="no"),
    lambda: __import__("projtrack.correlators", fromlist=["x"]).ProjectionCorrelationClassifier(
        normalize_projections=1),
    lambda: __import__("projtrack.correlators", fromlist=["x"]).Correlation2DClassifier(normalize="yes"),
    lambda: __import__("projtrack.correlators", fromlist=["x"]).project(np.ones((8, 8)), 0.0, return_r="no"),
    lambda: hough.hough_transform(np.zeros((0, 2)), (16, 16), allow_empty="no"),
    lambda: jpda.beta_paper([[0.1, 0.1], [0.5, 0.2]], store_intermediates="no"),
    lambda: __import__("projtrack.novelty", fromlist=["x"]).vip_matrix([np.ones((4, 4))] * 2, center="no"),
    lambda: __import__("projtrack.dma", fromlist=["x"]).check_row_stochastic(np.eye(2), log="no"),
])
def test_flags_must_be_bools_everywhere(call):
    with pytest.raises(TypeError, match="must be a bool"):
        call()


@pytest.mark.parametrize("kw,err,msg", [
    (dict(n_regions="8"), TypeError, "n_regions must be an int"),
    (dict(n_prototypes=0), ValueError, "n_prototypes must be an int >= 1"),
    (dict(dim=1.5), TypeError, "dim must be an int"),
    (dict(max_mse=-1.0), ValueError, "max_mse must be > 0"),
    (dict(alpha=0.0), ValueError, "alpha must be > 0"),
    (dict(neighbor_radius=np.nan), ValueError, "neighbor_radius"),
    (dict(rng=3), TypeError, "rng must be a numpy.random.Generator"),
])
def test_dma_constructor_checks_at_the_door(kw, err, msg):
    from projtrack import dma

    with pytest.raises(err, match=msg):
        dma.DMA(**kw)

"""Validation (Sec. II.A), the MVM (Sec. III.A), the JPDA and GNN trackers, the crossing scene."""

import numpy as np
import pytest
from scipy.stats import chi2, multivariate_normal

from projtrack import jpda
from projtrack.scenes import jpda as scene


def _fig1_like():
    z_pred = np.array([[0.0, 0.0], [3.0, 0.0]])
    S = np.array([np.eye(2), np.eye(2)])
    z = np.array([[-1.0, 0.5], [1.5, 0.0], [4.0, 0.5], [8.0, 8.0], [-8.0, 6.0]])
    return z, z_pred, S


def test_validation_matrix_fig1_rows():
    z, zp, S = _fig1_like()
    v = jpda.validation_matrix(z, zp, S, gate_prob=0.99)
    np.testing.assert_array_equal(v[:3], [[1, 1, 0], [1, 1, 1], [1, 0, 1]])
    np.testing.assert_array_equal(v[3:], [[1, 0, 0], [1, 0, 0]])


def test_mahalanobis_against_scipy_and_gate():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(3, 2, 2))
    S = A @ np.swapaxes(A, 1, 2) + np.eye(2)
    zp = rng.normal(size=(3, 2))
    z = rng.normal(size=(4, 2))
    d2 = jpda.mahalanobis_sq(z, zp, S)
    for j in range(4):
        for t in range(3):
            nu = z[j] - zp[t]
            assert d2[j, t] == pytest.approx(nu @ np.linalg.solve(S[t], nu))
    assert jpda.gate_threshold(0.99, 2) == pytest.approx(chi2.ppf(0.99, 2))


def test_mvm_entries_are_eqs_3_and_4():
    z, zp, S = _fig1_like()
    pd = np.array([0.9, 0.7])
    mvm = jpda.modified_validation_matrix(z, zp, S, pd, gate_prob=0.99, clutter_density=0.5)
    np.testing.assert_allclose(mvm[0], 1 - pd)
    assert mvm[2, 1] == pytest.approx(0.7 * multivariate_normal(zp[1], S[1]).pdf(z[1]) / 0.5)
    assert mvm[1, 1] == 0 and mvm[4, 0] == 0
    np.testing.assert_array_equal(jpda.mvm_to_validation(mvm), jpda.validation_matrix(z, zp, S))


@pytest.mark.parametrize("kw,msg", [
    (dict(p_detect=1.5), "p_detect"), (dict(p_detect=0.0), "p_detect"),
    (dict(p_detect=[0.5, 0.5, 0.5]), "p_detect"), (dict(gate_prob=1.0), "gate_prob"),
    (dict(clutter_density=0.0), "clutter_density"), (dict(clutter_density=np.nan), "clutter"),
])
def test_mvm_bad_parameters(kw, msg):
    z, zp, S = _fig1_like()
    args = dict(p_detect=0.9)
    args.update(kw)
    with pytest.raises(ValueError, match=msg):
        jpda.modified_validation_matrix(z, zp, S, **args)


def test_validation_bad_shapes():
    z, zp, S = _fig1_like()
    with pytest.raises(ValueError, match="S must have shape"):
        jpda.mahalanobis_sq(z, zp, S[:1])
    with pytest.raises(ValueError, match="columns"):
        jpda.mahalanobis_sq(z[:, :1], zp, S)
    with pytest.raises(ValueError, match="positive definite"):
        jpda.mahalanobis_sq(z, zp, -S)
    with pytest.raises(ValueError, match="symmetric"):
        jpda.mahalanobis_sq(z, zp, S + np.array([[0, 1.0], [0, 0]]))
    with pytest.raises(ValueError, match="finite"):
        jpda.mahalanobis_sq(z * np.nan, zp, S)


def test_fig2_feasibility_matrices_from_mvm():
    w = np.array([[0.1, 0.2], [0.5, 0.0], [0.3, 0.6], [0.0, 0.4]])
    mats = jpda.feasibility_matrices(w)
    assert len(mats) == 8


def _run(tracker_cls, sc, **kw):
    x0 = sc.truth[0]
    trk = tracker_cls(x0, np.eye(4) * 0.5, sc.F, sc.Q, sc.H, sc.R, **kw)
    est = np.array([trk.step(z) for z in sc.scans])
    return est, trk


def test_jpda_tracker_follows_targets_in_clutter():
    sc = scene.crossing_targets(np.random.default_rng(3), n_targets=2, n_steps=20)
    est, trk = _run(jpda.JPDATracker, sc, p_detect=0.9, clutter_density=sc.clutter_density)
    err = np.linalg.norm(est[:, :, [0, 2]] - sc.truth[1:, :, [0, 2]], axis=-1)
    assert np.sqrt(np.mean(err**2)) < 1.5
    np.testing.assert_allclose(trk.last_beta_.sum(axis=0), 1.0)
    for kf in trk.bank.filters:
        assert np.all(np.linalg.eigvalsh(kf.P) > 0)


def test_jpda_update_without_measurements_is_prediction():
    F, Q, H, R = scene.cv_model()
    trk = jpda.JPDATracker([[0, 1, 0, 1]], np.eye(4), F, Q, H, R)
    x = trk.step(np.zeros((0, 2)))
    np.testing.assert_allclose(x[0], [1, 1, 1, 1])
    np.testing.assert_allclose(trk.bank.filters[0].P, F @ np.eye(4) @ F.T + Q)


def test_jpda_with_one_target_and_one_sure_measurement_is_kalman():
    from filterpy.kalman import KalmanFilter

    F, Q, H, R = scene.cv_model()
    trk = jpda.JPDATracker([[0, 1, 0, 1]], np.eye(4), F, Q, H, R, p_detect=1.0,
                           gate_prob=0.999999)
    kf = KalmanFilter(4, 2)
    kf.x = np.array([[0, 1, 0, 1.0]]).T
    kf.P, kf.F, kf.Q, kf.H, kf.R = np.eye(4), F, Q, H, R
    # P_D P_G close to 1 and a single measurement: beta_1 ~ 1
    x = trk.step([[1.2, 0.9]])
    kf.predict()
    kf.update(np.array([[1.2], [0.9]]))
    np.testing.assert_allclose(x[0], kf.x.ravel(), atol=1e-4)


def test_gnn_tracker_runs_and_tracks():
    sc = scene.crossing_targets(np.random.default_rng(4), n_targets=2, n_steps=20,
                                clutter_per_scan=2)
    est, _ = _run(jpda.GNNTracker, sc)
    err = np.linalg.norm(est[:, :, [0, 2]] - sc.truth[1:, :, [0, 2]], axis=-1)
    assert np.median(err) < 1.5


def test_tracker_bad_inputs():
    F, Q, H, R = scene.cv_model()
    with pytest.raises(ValueError, match="F must have shape"):
        jpda.JPDATracker([[0, 0, 0, 0]], np.eye(4), F[:2], Q, H, R)
    with pytest.raises(ValueError, match="R must have shape"):
        jpda.JPDATracker([[0, 0, 0, 0]], np.eye(4), F, Q, H, np.eye(3))
    with pytest.raises(ValueError, match="p_detect"):
        jpda.JPDATracker([[0, 0, 0, 0]], np.eye(4), F, Q, H, R, p_detect=0)
    with pytest.raises(ValueError, match="clutter_density"):
        jpda.JPDATracker([[0, 0, 0, 0]], np.eye(4), F, Q, H, R, clutter_density=-1)
    trk = jpda.JPDATracker([[0, 0, 0, 0]], np.eye(4), F, Q, H, R)
    with pytest.raises(ValueError, match="finite"):
        trk.step([[np.nan, 0]])


@pytest.mark.parametrize("tracker", [jpda.JPDATracker, jpda.GNNTracker])
def test_tracker_step_names_the_measurement_shape(tracker):
    F, Q, H, R = scene.cv_model()
    trk = tracker([[0, 0, 0, 0]], np.eye(4), F, Q, H, R)
    for bad in ([[1.0, 2.0, 3.0]], [1.0, 2.0, 3.0], np.ones((2, 2, 2))):
        with pytest.raises(ValueError, match=r"measurements must have shape \(m, 2\)"):
            trk.step(bad)
    with pytest.raises(TypeError, match="measurements must be a real numeric"):
        trk.step([["a", "b"]])
    # an empty scan (no detections) is valid and only predicts
    assert trk.step([]).shape == (1, 4)
    assert trk.step(np.zeros((0, 2))).shape == (1, 4)


def test_scene_is_deterministic_and_validates():
    a = scene.crossing_targets(np.random.default_rng(7), n_targets=3, n_steps=10)
    b = scene.crossing_targets(np.random.default_rng(7), n_targets=3, n_steps=10)
    np.testing.assert_array_equal(a.truth, b.truth)
    assert all(np.array_equal(x, y) for x, y in zip(a.scans, b.scans))
    # all targets pass near the centre half way
    assert np.all(np.linalg.norm(a.truth[5][:, [0, 2]], axis=1) < 3)
    with pytest.raises(TypeError):
        scene.crossing_targets(7)
    with pytest.raises(ValueError):
        scene.crossing_targets(np.random.default_rng(0), p_detect=0)


def test_random_mvm_full_and_clustered():
    w = scene.random_mvm(np.random.default_rng(0), 8, 8)
    assert w.shape == (9, 8) and np.all(w[1:] > 0) and np.allclose(w[0], 0.1)
    wc = scene.random_mvm(np.random.default_rng(0), 8, 8, cluster_size=4)
    assert len(jpda.clusters(wc)) == 2
    np.testing.assert_allclose(jpda.beta(wc), jpda.beta_paper(wc), atol=1e-12)
    with pytest.raises(ValueError):
        scene.random_mvm(np.random.default_rng(0), 3, 0)
    with pytest.raises(ValueError):
        scene.random_mvm(np.random.default_rng(0), 3, 3, cluster_size=0)


def test_fig2_order_is_passed_through_from_the_mvm():
    w = np.array([[0.1, 0.2], [0.5, 0.0], [0.3, 0.6], [0.0, 0.4]])
    case5 = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    assert np.array_equal(jpda.feasibility_matrices(w, order="colexicographic")[4], case5)
    with pytest.raises(ValueError, match="order must be"):
        jpda.feasibility_matrices(w, order="by probability")


def test_paper_mvm_is_clutter_density_one_in_the_units_of_the_likelihoods():
    # coordinates s times finer: densities shrink by s^d, i.e. lambda = s^d in the old units
    rng = np.random.default_rng(11)
    zp = rng.uniform(-2, 2, (3, 2))
    z = zp[[0, 1, 2, 0]] + rng.normal(0, 0.5, (4, 2))
    S = np.repeat(np.eye(2)[None] * 0.6, 3, axis=0)
    s = 10.0
    fine = jpda.beta(jpda.modified_validation_matrix(s * z, s * zp, s**2 * S, 0.85))
    old = jpda.beta(jpda.modified_validation_matrix(z, zp, S, 0.85, clutter_density=s**2))
    np.testing.assert_allclose(fine, old, atol=1e-13)
    paper = jpda.beta(jpda.modified_validation_matrix(z, zp, S, 0.85))
    assert np.abs(paper - old).max() > 1e-3  # the density does change beta


def test_false_measurement_rule_equals_mvm_for_a_common_p_detect():
    # Sec. II.C weighs each false measurement by 1 - P_D; the MVM each undetected target
    rng = np.random.default_rng(5)
    p = 0.8
    for m, T in ((4, 2), (2, 4), (3, 3)):
        w = rng.uniform(0.05, 1.0, (m + 1, T)) * (rng.random((m + 1, T)) < 0.8)
        w[0] = 1 - p
        lit = np.zeros_like(w)
        for om in jpda.feasibility_matrices(w):
            t_of_j = om[:, 1:].argmax(axis=1) * om[:, 1:].any(axis=1) + om[:, 1:].any(axis=1)
            weight = np.prod([w[j + 1, t_of_j[j] - 1] if t_of_j[j] else 1 - p for j in range(m)])
            for t in range(T):
                rows = np.flatnonzero(t_of_j == t + 1)
                lit[rows[0] + 1 if rows.size else 0, t] += weight
        np.testing.assert_allclose(lit / lit.sum(axis=0), jpda.beta(w), atol=1e-13)


def test_beta_from_matrix_permanents():
    import itertools

    def per(M):
        r, c = M.shape
        return sum(np.prod(M[np.arange(r), list(cols)]) for cols in itertools.permutations(range(c), r))

    rng = np.random.default_rng(2)
    for m, T in ((3, 2), (2, 3), (3, 3)):
        w = scene.random_mvm(rng, m, T)
        M = np.hstack([w[1:] / w[0][None, :], np.eye(m)])
        b = jpda.beta(w)
        for j in range(m):
            for t in range(T):
                minor = np.delete(np.delete(M, j, axis=0), t, axis=1)
                assert b[j + 1, t] == pytest.approx(M[j, t] * per(minor) / per(M), abs=1e-13)

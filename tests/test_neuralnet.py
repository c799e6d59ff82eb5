"""Tests of projtrack.neuralnet (Barnard & Casasent, chapter 5) and scenes.tracks3d."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from projtrack import neuralnet as nn
from projtrack.scenes.tracks3d import make_tracks, perturb


def _random_problem(seed, n_t=3, n_m=4, n_p=5, binary=True):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(-1, 1, (n_p, n_m, 3))
    D = nn.distance_tensor(pos)
    X = rng.integers(0, 2, (n_t, n_m, n_p)).astype(float) if binary else rng.random((n_t, n_m, n_p))
    return D, X


# ----------------------------------------------------------------------------- eq. (7), (8)
def test_energy_zero_for_correct_noise_free_straight_tracks():
    rng = np.random.default_rng(0)
    scene = make_tracks(rng, 4, 5, noise_percent=0.0)
    D = nn.distance_tensor(scene.positions / 256)
    truth = np.argsort(scene.labels, axis=1).T
    X = nn.assignment_to_states(truth, 4)
    assert nn.energy(X, D) == pytest.approx(0.0, abs=1e-10)
    # a wrong but admissible assignment has positive energy
    wrong = truth.copy()
    wrong[[0, 1], 2] = wrong[[1, 0], 2]
    assert nn.energy(nn.assignment_to_states(wrong, 4), D) > 1e-3


def test_distance_tensor_matches_definition():
    rng = np.random.default_rng(1)
    r = rng.normal(size=(4, 3, 2))
    D = nn.distance_tensor(r)
    assert D.shape == (2, 3, 3, 3)
    for a, al, be, ga in itertools.product(range(2), range(3), range(3), range(3)):
        d1 = r[a, al] - r[a + 1, be]
        d2 = r[a + 1, be] - r[a + 2, ga]
        assert D[a, al, be, ga] == pytest.approx(np.linalg.norm(d1 - d2))


def test_energy_brute_force_terms():
    D, X = _random_problem(2, binary=True)
    c = nn.Coefficients(1.0, 2.0, 3.0, 0.5)
    n_t, n_m, n_p = X.shape
    e1 = sum(X[i, al, a] * X[j, al, a] for al in range(n_m) for a in range(n_p)
             for i in range(n_t) for j in range(n_t) if j != i)
    e2 = sum(X[i, al, a] * X[i, b, a] for i in range(n_t) for a in range(n_p)
             for al in range(n_m) for b in range(n_m) if b != al)
    e3 = sum((X[:, :, a].sum() - n_t) ** 2 for a in range(n_p))
    e4 = sum(D[a, al, b, g] * X[i, al, a] * X[i, b, a + 1] * X[i, g, a + 2]
             for a in range(n_p - 2) for i in range(n_t)
             for al in range(n_m) for b in range(n_m) for g in range(n_m))
    assert nn.energy(X, D, c) == pytest.approx(1 * e1 + 2 * e2 + 3 * e3 + 0.5 * e4)


# ----------------------------------------------------------------------------- eq. (9)
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), n_t=st.integers(1, 3), extra=st.integers(0, 2), n_p=st.integers(3, 5))
def test_gradient_matches_finite_differences_on_binary_states(seed, n_t, extra, n_p):
    D, X = _random_problem(seed, n_t, n_t + extra, n_p, binary=True)
    g = nn.energy_gradient(X, D)
    for k in np.ndindex(X.shape):
        on, off = X.copy(), X.copy()
        on[k], off[k] = 1.0, 0.0
        secant = nn.energy(on, D) - nn.energy(off, D)
        # E is quadratic in one neuron (only term 3 has X_k^2): the secant between the
        # two binary values is the mean of the derivative at X_k = 0 and X_k = 1.
        mid = 0.5 * (nn.energy_gradient(on, D)[k] + nn.energy_gradient(off, D)[k])
        assert secant == pytest.approx(mid, rel=1e-9, abs=1e-9)
        # central difference of the polynomial is exact at the binary point too
        h = 1e-3
        p, m = X.copy(), X.copy()
        p[k] += h
        m[k] -= h
        assert (nn.energy(p, D) - nn.energy(m, D)) / (2 * h) == pytest.approx(g[k], rel=1e-6, abs=1e-6)


def test_vectorized_gradient_equals_loops_and_linear_algebra():
    D, X = _random_problem(3, 3, 4, 5, binary=False)
    g = nn.energy_gradient(X, D)
    np.testing.assert_allclose(g, nn.energy_gradient_loops(X, D), atol=1e-10)
    x = X.reshape(-1)
    np.testing.assert_allclose(nn.gradient_linear_algebra(x, D, 3), g.reshape(-1), atol=1e-10)
    np.testing.assert_allclose(nn.gradient_linear_algebra(x, D, 3, reduced=True), g.reshape(-1), atol=1e-10)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), n_t=st.integers(1, 4), extra=st.integers(0, 2), n_p=st.integers(3, 6))
def test_reduced_and_full_tensor_forms_agree(seed, n_t, extra, n_p):
    D, X = _random_problem(seed, n_t, n_t + extra, n_p, binary=False)
    x = X.reshape(-1)
    y_full = nn.tensor_matrix_product(nn.full_tensor(D, n_t), x)
    y_red = nn.reduced_tensor_product(*nn.reduced_tensor(D), x, n_t)
    np.testing.assert_allclose(y_full, y_red, atol=1e-10)
    # term 4 alone: coefficients (0, 0, 0, 1) leave 2 A3 (S - N_T) = 0
    np.testing.assert_allclose(y_full, nn.energy_gradient(X, D, (0, 0, 0, 1)).reshape(-1), atol=1e-10)


def test_dense_tensor_form_and_connection_matrices():
    D, X = _random_problem(4, 2, 3, 4, binary=True)
    Df = nn.full_tensor(D, 2)
    K = X.size
    dense = Df.toarray().reshape(K, K, K)
    x = X.reshape(-1)
    np.testing.assert_allclose(nn.tensor_matrix_product(dense, x), nn.tensor_matrix_product(Df, x))
    T1, T2, T3 = nn.connection_matrices(2, 3, 4)
    assert T1.shape == (K, K) and np.all(np.diag(T1) == 0) and np.all(np.diag(T2) == 0) and np.all(np.diag(T3) == 1)
    np.testing.assert_array_equal(T1, T1.T)
    # T1 x counts the other targets on the same measurement and frame
    np.testing.assert_array_equal((T1 @ x).reshape(X.shape), X.sum(axis=0, keepdims=True) - X)


def test_slm_sizes_paper_example():
    s = nn.slm_sizes(6, 7, 5)
    assert s["neurons"] == 210 and s["slm2_full"] == 210 ** 3
    assert s["slm2_reduced"] == 7 * 35 * 35 and s["vop_reduced"] == 6 * 35 * 35 == 7350
    assert s["reduction"] > 1000
    R, route = nn.reduced_tensor(np.ones((3, 7, 7, 7)))
    assert R.shape == (7, 35, 35)


# ----------------------------------------------------------------------------- dynamics
def test_run_net_deterministic_and_correct_state_is_fixed_point():
    rng = np.random.default_rng(5)
    scene = make_tracks(rng, 4, 5)
    D = nn.distance_tensor(scene.positions / 256)
    truth = np.argsort(scene.labels, axis=1).T
    res = nn.run_net(D, nn.assignment_to_states(truth, 4))
    assert res.status[0] == "converged" and res.iterations[0] == 0
    np.testing.assert_array_equal(res.states, nn.assignment_to_states(truth, 4))
    X0a = nn.initial_states(np.random.default_rng(9), 6, 4, 4, 5)
    X0b = nn.initial_states(np.random.default_rng(9), 6, 4, 4, 5)
    np.testing.assert_array_equal(X0a, X0b)
    ra, rb = nn.run_net(D, X0a, record=True), nn.run_net(D, X0b)
    np.testing.assert_array_equal(ra.states, rb.states)
    np.testing.assert_array_equal(ra.iterations, rb.iterations)
    assert ra.history.shape[1:] == (6, 4, 4, 5)
    # the batch equals one net at a time
    for k in range(6):
        single = nn.run_net(D, X0a[k])
        np.testing.assert_array_equal(single.states, ra.states[k])
        assert single.status[0] == ra.status[k]


def test_serial_update_follows_eq4_for_one_neuron():
    D, X = _random_problem(6, 2, 2, 3, binary=True)
    # one sweep by hand: visit neurons in x order, set to (dE/dX < offset)
    Y = X.copy()
    for k in np.ndindex(Y.shape):
        Y[k] = float(nn.energy_gradient(Y, D)[k] < nn.PAPER_OFFSET)
    res = nn.run_net(D, X, max_iter=1)
    np.testing.assert_array_equal(res.states, Y.astype(np.int8))


def test_oscillation_is_detected_in_parallel_mode():
    # two targets, two measurements, no data term: parallel updates from all-zero
    # switch every neuron on, then all off, forever (period 2).
    D = np.zeros((1, 2, 2, 2))
    res = nn.run_net(D, np.zeros((1, 2, 2, 3)), mode="parallel", max_iter=10)
    assert res.status[0] == "oscillating" and res.period[0] == 2


def test_assignment_helpers():
    labels = np.array([[1, 0], [0, 1], [0, 1]])
    assert nn.is_correct_assignment(np.array([[1, 0, 0], [0, 1, 1]]), labels)
    assert not nn.is_correct_assignment(np.array([[1, 1, 0], [0, 0, 1]]), labels)
    assert not nn.is_correct_assignment(None, labels)
    X = nn.assignment_to_states(np.array([[1, 0, 0], [0, 1, 1]]), 2)
    np.testing.assert_array_equal(nn.states_to_assignment(X), [[1, 0, 0], [0, 1, 1]])
    X[0, 0, 0] = 1
    assert nn.states_to_assignment(X) is None


# ----------------------------------------------------------------------------- references
@pytest.mark.parametrize("seed", range(4))
def test_optimal_assignment_equals_exhaustive_search(seed):
    rng = np.random.default_rng(seed)
    n, n_p = 3, 5
    D = nn.distance_tensor(rng.uniform(-1, 1, (n_p, n, 2)))
    best = np.inf
    for perms in itertools.product(itertools.permutations(range(n)), repeat=n_p - 1):
        A = np.column_stack([np.arange(n)] + [np.array(p) for p in perms])
        best = min(best, nn.assignment_cost(A, D))
    A, cost = nn.optimal_assignment(D)
    assert cost == pytest.approx(best)
    assert nn.assignment_cost(A, D) == pytest.approx(cost)
    _, cd = nn.coordinate_descent_assignment(D)
    assert cd >= cost - 1e-12


def test_references_find_noise_free_tracks():
    rng = np.random.default_rng(11)
    scene = make_tracks(rng, 4, 5)
    D = nn.distance_tensor(scene.positions)
    assert nn.is_correct_assignment(nn.optimal_assignment(D)[0], scene.labels)
    assert nn.is_correct_assignment(nn.coordinate_descent_assignment(D)[0], scene.labels)
    A = nn.nearest_neighbour_assignment(scene.positions)
    assert A.shape == (4, 5) and all(sorted(A[:, a]) == [0, 1, 2, 3] for a in range(5))


# ----------------------------------------------------------------------------- padding, scenes
def test_pad_measurements_zero_vectors():
    frames = [np.ones((3, 3)), np.ones((2, 3)), np.ones((3, 3))]
    pos, real = nn.pad_measurements(frames, n_targets=3)
    assert pos.shape == (3, 3, 3)
    np.testing.assert_array_equal(pos[1, 2], 0.0)
    assert real.sum() == 8
    pos, real = nn.pad_measurements(frames, n_measurements=5)
    assert pos.shape == (3, 5, 3) and not real[:, 3:].any()


def test_make_tracks_properties():
    rng = np.random.default_rng(7)
    s = make_tracks(rng, 4, 5)
    assert np.all(np.abs(s.truth) <= 128 + 1e-9)
    second = s.truth[:-2] - 2 * s.truth[1:-1] + s.truth[2:]
    np.testing.assert_allclose(second, 0.0, atol=1e-9)
    xy = np.linalg.norm(s.truth[-1, :, :2] - s.truth[0, :, :2], axis=1)
    assert np.all(xy <= 0.7 * 256 + 1e-9) and np.all(xy >= 0.7 * 256 / 5 - 1e-9)
    np.testing.assert_array_equal(np.take_along_axis(s.truth, s.labels[:, :, None], 1), s.positions)
    r = rng.normal(size=(1000, 3)) * 50
    moved = perturb(rng, r, 5.0)
    assert np.all(np.linalg.norm(moved - r, axis=1) <= 0.05 * np.linalg.norm(r, axis=1) + 1e-12)


# ----------------------------------------------------------------------------- bad inputs
def test_bad_inputs():
    rng = np.random.default_rng(0)
    D = nn.distance_tensor(rng.normal(size=(5, 4, 3)))
    with pytest.raises(ValueError, match="at least 3 frames"):
        nn.distance_tensor(np.zeros((2, 4, 3)))
    bad = np.zeros((5, 4, 3))
    bad[1, 1, 1] = np.nan
    with pytest.raises(ValueError, match="finite"):
        nn.distance_tensor(bad)
    with pytest.raises(ValueError, match="at least as many measurements"):
        nn.energy(np.zeros((5, 4, 5)), D)
    with pytest.raises(ValueError, match="n_measurements"):
        nn.initial_states(rng, 2, 5, 4, 5)
    with pytest.raises(ValueError, match="n_frames"):
        nn.initial_states(rng, 2, 4, 4, 2)
    with pytest.raises(ValueError, match="A4"):
        nn.Coefficients(15, 15, 15, -1.8)
    with pytest.raises(ValueError, match="A1"):
        nn.energy_gradient(np.zeros((4, 4, 5)), D, (-1, 15, 15, 1.8))
    with pytest.raises(TypeError):
        nn.energy(np.zeros((4, 4, 5)), D, "paper")
    with pytest.raises(ValueError, match="shape"):
        nn.energy_gradient(np.zeros((4, 4, 4)), D)
    with pytest.raises(ValueError, match="mode"):
        nn.run_net(D, np.zeros((4, 4, 5)), mode="random")
    with pytest.raises(ValueError, match="max_iter"):
        nn.run_net(D, np.zeros((4, 4, 5)), max_iter=0)
    with pytest.raises(ValueError, match=">= 0"):
        nn.run_net(-D, np.zeros((4, 4, 5)))
    with pytest.raises(ValueError, match="n_measurements"):
        nn.pad_measurements([np.ones((3, 3))], n_measurements=2)
    with pytest.raises(ValueError, match="non-finite"):
        nn.pad_measurements([np.full((2, 3), np.inf)])
    with pytest.raises(ValueError, match="N_T == N_M"):
        nn.optimal_assignment(D, n_targets=3)
    with pytest.raises(ValueError, match="too large"):
        nn.optimal_assignment(nn.distance_tensor(rng.normal(size=(3, 7, 2))))
    with pytest.raises(ValueError, match="entries"):
        nn.reduced_tensor_product(*nn.reduced_tensor(D), np.zeros(7), 4)
    with pytest.raises(TypeError, match="rng"):
        make_tracks(0, 4, 5)
    with pytest.raises(ValueError, match="noise_percent"):
        perturb(rng, np.ones((2, 3)), -1.0)
    with pytest.raises(ValueError, match="n_frames"):
        make_tracks(rng, 4, 1)


def test_degrade_labels_and_padding():
    from projtrack.scenes.tracks3d import degrade

    rng = np.random.default_rng(8)
    s = make_tracks(rng, 4, 5)
    pos, lab = degrade(rng, s, n_spurious=2, n_missing=3)
    assert pos.shape == (5, 6, 3) and lab.shape == (5, 6)
    assert (lab == -1).sum() == 10
    # every target appears once per frame; exactly 3 of those entries are zero vectors
    for a in range(5):
        assert sorted(lab[a][lab[a] >= 0].tolist()) == [0, 1, 2, 3]
    zero = np.all(pos == 0.0, axis=-1) & (lab >= 0)
    assert zero.sum() == 3
    # the intended assignment is admissible and judged correct
    want = np.array([[int(np.flatnonzero(lab[a] == i)[0]) for a in range(5)] for i in range(4)])
    assert nn.is_correct_assignment(want, lab)
    with pytest.raises(ValueError, match="n_missing"):
        degrade(rng, s, n_missing=21)
    with pytest.raises(TypeError, match="TrackScene"):
        degrade(rng, pos)


def test_assignment_cost_rejects_bad_indices():
    rng = np.random.default_rng(3)
    D = nn.distance_tensor(rng.normal(size=(5, 4, 3)))
    ok = np.tile(np.arange(4)[:, None], (1, 5))
    assert nn.assignment_cost(ok, D) >= 0.0
    too_big = ok.copy()
    too_big[2, 3] = 4
    with pytest.raises(ValueError, match="assignment entries"):
        nn.assignment_cost(too_big, D)
    negative = ok.copy()
    negative[0, 0] = -1
    with pytest.raises(ValueError, match="assignment entries"):
        nn.assignment_cost(negative, D)
    with pytest.raises(TypeError, match="assignment"):
        nn.assignment_cost(ok.astype(float), D)
    with pytest.raises(ValueError, match="assignment entries"):
        nn.coordinate_descent_assignment(D, initial=too_big)


def test_make_tracks_rejects_negative_noise():
    rng = np.random.default_rng(4)
    with pytest.raises(ValueError, match="noise_percent"):
        make_tracks(rng, 4, 5, noise_percent=-0.5)


# ----------------------------------------------------------------------------- recording, fixed points
def test_record_keeps_the_start_the_net_used():
    rng = np.random.default_rng(3)
    D = nn.distance_tensor(make_tracks(rng, 4, 5).positions / 256)
    X0 = nn.initial_states(rng, 3, 4, 4, 5)
    res = nn.run_net(D, X0, record=True, max_iter=5)
    # history[0] is the analog start itself, not a thresholded copy (which would be all zero here)
    np.testing.assert_array_equal(res.history[0], X0)
    assert np.all(X0 < 0.5)
    # history[s] is the state after sweep s: a one-sweep run from the same start ends at history[1]
    one = nn.run_net(D, X0, max_iter=1)
    np.testing.assert_array_equal(res.history[1], one.states)
    np.testing.assert_array_equal(res.history[-1], res.states)


def _all_assignments(n_t, n_p):
    perms = list(itertools.permutations(range(n_t)))
    for rest in itertools.product(range(len(perms)), repeat=n_p - 1):
        yield rest, np.array([perms[0]] + [perms[k] for k in rest]).T


@pytest.mark.parametrize("n_p", [3, 4, 5, 6])
def test_assignment_max_sums_equals_brute_force(n_p):
    rng = np.random.default_rng(n_p)
    D = nn.distance_tensor(rng.uniform(-1, 1, (n_p, 3, 3)))
    M = nn.assignment_max_sums(D)
    assert M.shape == (6,) * (n_p - 1)
    for rest, A in _all_assignments(3, n_p):
        S = nn.neuron_distance_sums(A, D)
        # S[i, a] is the term 4 input of target i's active neuron in frame a
        X = nn.assignment_to_states(A, 3)
        g4 = nn.energy_gradient(X, D, (0, 0, 0, 1))
        np.testing.assert_allclose(g4[np.arange(3)[:, None], A, np.arange(n_p)[None, :]], S, atol=1e-12)
        assert M[rest] == pytest.approx(S.max(), abs=1e-12)


@pytest.mark.parametrize("rule", [dict(), dict(self_coupling=False), dict(exact_energy=True),
                                  dict(offset=-0.035), dict(self_coupling=False, offset=-0.035)])
def test_fixed_point_limit_decides_fixed_points_of_the_net(rule):
    rng = np.random.default_rng(11)
    scene = make_tracks(rng, 4, 5, noise_percent=5.0)
    D = nn.distance_tensor(scene.positions / 2048)
    lim = nn.fixed_point_limit(**rule)
    M = nn.assignment_max_sums(D)
    perms = list(itertools.permutations(range(4)))
    picks = [tuple(rng.integers(0, 24, 4)) for _ in range(40)]
    picks += [tuple(int(v) for v in np.unravel_index(np.argmin(M), M.shape))]  # most stable one
    seen = set()
    for p in picks:
        A = np.array([perms[0]] + [perms[k] for k in p]).T
        X = nn.assignment_to_states(A, 4)
        expected = bool(M[p] < lim)
        seen.add(expected)
        assert nn.is_fixed_point(X, D, **rule) == expected
        r = nn.run_net(D, X, max_iter=2, **rule)
        assert (r.status[0] == "converged") == expected
    if not rule:  # eq. (9) as printed: both cases occur at this unit, so the test can fail either way
        assert seen == {True, False}


def test_update_inputs_exact_energy_change():
    D, X = _random_problem(21, 3, 4, 5)
    g = nn.update_inputs(X, D, exact_energy=True)
    for k in list(np.ndindex(X.shape))[::7]:
        on, off = X.copy(), X.copy()
        on[k], off[k] = 1, 0
        assert g[k] == pytest.approx(nn.energy(on, D) - nn.energy(off, D), abs=1e-9)
    no_self = nn.update_inputs(X, D, self_coupling=False)
    np.testing.assert_allclose(no_self, nn.energy_gradient(X, D) - 30 * X)


def test_no_self_term_has_inadmissible_fixed_points():
    # noise-free tracks; target 0 also takes target 1's measurement in frame 0, target 1 has none there:
    # the row conflict (+2 A2) is cancelled by the frame deficit seen without the self term (-2 A3)
    rng = np.random.default_rng(2)
    scene = make_tracks(rng, 4, 5, shuffle=False)
    D = nn.distance_tensor(scene.positions / 256)
    truth = np.tile(np.arange(4)[:, None], (1, 5))
    X = nn.assignment_to_states(truth, 4)
    X[1, 1, 0], X[0, 1, 0] = 0, 1
    assert nn.states_to_assignment(X) is None
    extra = D[0, 1, 0, 0]  # the new triple of target 0
    big = 2 * 1.8 * extra / 0.035  # a unit large enough for the conflict to stay
    Db = D / big
    assert nn.is_fixed_point(X, Db, self_coupling=False)
    assert not nn.is_fixed_point(X, Db)  # eq. (9) as printed removes the conflict
    assert not nn.is_fixed_point(X, Db, exact_energy=True)


def test_fixed_point_inputs_are_validated():
    D, X = _random_problem(1, 3, 4, 5)
    with pytest.raises(ValueError, match="binary"):
        nn.is_fixed_point(X + 0.5, D)
    with pytest.raises(ValueError, match="offset"):
        nn.is_fixed_point(X, D, offset=np.nan)
    with pytest.raises(TypeError, match="must be a bool"):
        nn.update_inputs(X, D, self_coupling="no")
    with pytest.raises(TypeError, match="must be a bool"):
        nn.run_net(D, X, exact_energy=1)
    with pytest.raises(ValueError, match="inactive"):
        nn.fixed_point_limit(offset=100.0)
    assert nn.fixed_point_limit(offset=-0.035) == -np.inf
    assert nn.fixed_point_limit() == pytest.approx(0.035 / 1.8)
    assert nn.fixed_point_limit(self_coupling=False) == pytest.approx(30.035 / 1.8)
    assert nn.fixed_point_limit(exact_energy=True) == pytest.approx(15.035 / 1.8)
    with pytest.raises(ValueError, match="N_T == N_M"):
        nn.assignment_max_sums(D, n_targets=3)
    with pytest.raises(ValueError, match="max_assignments"):
        nn.assignment_max_sums(nn.distance_tensor(np.zeros((5, 4, 3))), max_assignments=1000)
    with pytest.raises(ValueError, match="measurement indices"):
        nn.neuron_distance_sums(np.full((4, 5), 7), nn.distance_tensor(np.zeros((5, 4, 3))))


# ----------------------------------------------------------------------------- noise laws
@pytest.mark.parametrize("law", ["ball", "radial", "coordinate"])
def test_noise_laws_stay_within_n_percent_and_differ_in_spread(law):
    rng = np.random.default_rng(11)
    r = rng.normal(size=(20000, 3)) * 50
    d = perturb(rng, r, 5.0, law) - r
    norm_r = np.linalg.norm(r, axis=1)
    assert np.all(np.linalg.norm(d, axis=1) <= 0.05 * norm_r + 1e-12)
    rms = np.sqrt(np.mean((np.linalg.norm(d, axis=1) / (0.05 * norm_r)) ** 2))
    # ball: sqrt(3/5) = 0.775; radial and per-coordinate: 1/sqrt(3) = 0.577
    assert rms == pytest.approx(np.sqrt(0.6) if law == "ball" else 1 / np.sqrt(3), abs=0.01)
    if law == "radial":      # moved along r only
        np.testing.assert_allclose(np.cross(d, r), 0.0, atol=1e-9)
    if law == "coordinate":  # every coordinate moved by at most n% of itself
        assert np.all(np.abs(d) <= 0.05 * np.abs(r) + 1e-12)


def test_noise_law_reaches_make_tracks():
    a = make_tracks(np.random.default_rng(3), 4, 5, noise_percent=5.0, noise_law="radial")
    b = make_tracks(np.random.default_rng(3), 4, 5, noise_percent=5.0, noise_law="coordinate")
    np.testing.assert_array_equal(a.truth, b.truth)
    assert not np.allclose(a.positions, b.positions)
    ta = np.take_along_axis(a.truth, a.labels[:, :, None], 1)
    ratio = np.linalg.norm(a.positions, axis=2) / np.linalg.norm(ta, axis=2)
    np.testing.assert_allclose(np.cross(a.positions, ta), 0.0, atol=1e-8)
    assert np.all(np.abs(ratio - 1) <= 0.05 + 1e-12)


def test_noise_law_is_validated():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="noise_law"):
        perturb(rng, np.ones((2, 3)), 1.0, "gaussian")
    with pytest.raises(TypeError, match="noise_law"):
        perturb(rng, np.ones((2, 3)), 1.0, 1)
    with pytest.raises(ValueError, match="noise_law"):
        make_tracks(rng, 4, 5, noise_percent=1.0, noise_law="uniform")

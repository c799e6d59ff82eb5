"""Tests of projtrack.dma (Marques et al. 2002) and its scene generators."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from projtrack import dma
from projtrack.scenes import manifolds as mf
from projtrack.scenes.roads import make_road_scene
from projtrack.scenes.slotcar import make_slotcar_video


# ----------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------
def random_chain(rng: np.random.Generator, S: int, N: int, density: float = 0.5):
    A = rng.random((S, S))
    A[rng.random((S, S)) > density] = 0.0
    A[np.arange(S), rng.integers(0, S, S)] += 0.2  # no empty row
    A /= A.sum(axis=1, keepdims=True)
    p0 = rng.dirichlet(np.ones(S))
    le = rng.normal(size=(N, S)) * 2
    return np.log(p0), dma.log_transitions(A), dma.log_transitions(sp.csr_array(A)), le


def brute_force(ls, lt, le):
    N, S = le.shape
    best, arg = -np.inf, None
    for path in itertools.product(range(S), repeat=N):
        p = np.array(path)
        v = ls[p[0]] + lt[p[:-1], p[1:]].sum() + le[np.arange(N), p].sum()
        if v > best:
            best, arg = v, p
    return best, arg


def hmmlearn_model(ls, lt, le):
    from hmmlearn.base import BaseHMM

    class Fixed(BaseHMM):
        def _compute_log_likelihood(self, X):
            return le

        def _init(self, X, lengths=None):
            pass

        def _check(self):
            pass

        def _get_n_fit_scalars_per_param(self):
            return {}

        def _generate_sample_from_state(self, state, random_state=None):
            return np.zeros(1)

    m = Fixed(n_components=le.shape[1])
    m.startprob_ = np.exp(ls)
    m.transmat_ = np.exp(lt)
    return m


# ----------------------------------------------------------------------------------
# retrieval against oracles
# ----------------------------------------------------------------------------------
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), S=st.integers(1, 4), N=st.integers(1, 5))
def test_viterbi_matches_brute_force(seed, S, N):
    rng = np.random.default_rng(seed)
    ls, lt, lts, le = random_chain(rng, S, N)
    best, _ = brute_force(ls, lt, le)
    for trans in (lt, lts):
        path = dma.viterbi(ls, trans, le)
        assert path.shape == (N,) and np.issubdtype(path.dtype, np.integer)
        assert np.isclose(dma.path_log_probability(path, ls, trans, le), best)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), S=st.integers(1, 3), N=st.integers(1, 5))
def test_forward_backward_matches_brute_force(seed, S, N):
    rng = np.random.default_rng(seed)
    ls, lt, lts, le = random_chain(rng, S, N)
    joint = {}
    for path in itertools.product(range(S), repeat=N):
        p = np.array(path)
        joint[path] = ls[p[0]] + lt[p[:-1], p[1:]].sum() + le[np.arange(N), p].sum()
    vals = np.array(list(joint.values()))
    from scipy.special import logsumexp

    loglik = logsumexp(vals)
    marg = np.zeros((N, S))
    for path, v in joint.items():
        marg[np.arange(N), list(path)] += np.exp(v - loglik)
    for trans in (lt, lts):
        post, ll = dma.forward_backward(ls, trans, le)
        assert np.isclose(ll, loglik)
        assert np.allclose(np.exp(post), marg, atol=1e-10)
    # filtering at the last instant equals smoothing at the last instant
    filt = dma.forward_filter(ls, lts, le)
    assert np.allclose(filt[-1], post[-1])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_viterbi_and_posteriors_match_hmmlearn(seed):
    rng = np.random.default_rng(seed)
    ls, lt, lts, le = random_chain(rng, 12, 300, density=0.3)
    model = hmmlearn_model(ls, lt, le)
    X = np.zeros((300, 1))
    lp, ref_path = model.decode(X, algorithm="viterbi")
    ours = dma.viterbi(ls, lts, le)
    assert np.isclose(dma.path_log_probability(ours, ls, lt, le), lp)
    assert (ours == ref_path).mean() > 0.99
    ll_ref, post_ref = model.score_samples(X)
    post, ll = dma.forward_backward(ls, lts, le)
    assert np.isclose(ll, ll_ref)
    assert np.allclose(np.exp(post), post_ref, atol=1e-8)


def test_long_sequence_no_underflow():
    rng = np.random.default_rng(3)
    ls, lt, lts, le = random_chain(rng, 20, 5000)
    le = le - 30.0  # tiny likelihoods: probabilities would underflow after ~25 steps
    post, ll = dma.forward_backward(ls, lts, le)
    assert np.isfinite(ll) and ll < -100000
    assert np.allclose(np.exp(post).sum(axis=1), 1.0)
    path = dma.viterbi(ls, lts, le)
    assert np.isfinite(dma.path_log_probability(path, ls, lts, le))


def test_sparse_absent_entries_are_impossible():
    # a 3-cycle: 0 -> 1 -> 2 -> 0; emissions favour staying at 0, impossible under A
    data = np.zeros(3)  # log 1 = 0, stored explicitly
    lt = sp.csr_array((data, ([0, 1, 2], [1, 2, 0])), shape=(3, 3))
    le = np.log(np.array([[0.9, 0.05, 0.05]] * 4))
    path = dma.viterbi(np.log(np.ones(3) / 3), lt, le)
    assert list(np.diff(path) % 3) == [1, 1, 1]


def test_dense_and_sparse_identical_paths():
    rng = np.random.default_rng(9)
    ls, lt, lts, le = random_chain(rng, 30, 200, density=0.1)
    assert (dma.viterbi(ls, lt, le) == dma.viterbi(ls, lts, le)).all()
    assert np.allclose(dma.forward_filter(ls, lt, le), dma.forward_filter(ls, lts, le))


# ----------------------------------------------------------------------------------
# bad inputs of the retrieval functions
# ----------------------------------------------------------------------------------
@pytest.mark.parametrize("fn", [dma.viterbi, dma.forward_backward, dma.forward_filter])
def test_retrieval_bad_inputs(fn):
    rng = np.random.default_rng(0)
    ls, lt, lts, le = random_chain(rng, 3, 4)
    with pytest.raises(ValueError, match="log_emission"):
        fn(ls, lt, le[:, :2])
    with pytest.raises(ValueError, match="log_trans"):
        fn(ls, lt[:2], le)
    with pytest.raises(ValueError, match="log_trans"):
        fn(ls, sp.csr_array(lts[:, :2]), le)
    with pytest.raises(ValueError, match="row-stochastic"):
        fn(ls, lt + np.log(0.5), le)
    with pytest.raises(ValueError, match="row-stochastic"):
        bad = lts.copy()
        bad.data[:] = np.log(0.1)
        fn(ls, bad, le)
    with pytest.raises(ValueError, match="NaN"):
        fn(ls, lt, np.where(np.arange(3) == 1, np.nan, le))
    with pytest.raises(ValueError, match="log_start"):
        fn(ls + 1.0, lt, le)
    with pytest.raises(ValueError, match="log_start"):
        fn(ls[:, None], lt, le)
    with pytest.raises(ValueError, match="log_trans"):
        fn(ls, -lt + 1.0, le)  # positive "log-probabilities"
    with pytest.raises(TypeError):
        fn(ls, lt, "abc")
    with pytest.raises(ValueError, match="at least one time step"):
        fn(ls, lt, np.zeros((0, 3)))
    with pytest.raises(ValueError, match="probability 0"):
        fn(ls, lt, np.full((4, 3), -np.inf))


def test_state_never_left_breaks_without_smoothing():
    # state 2 never left in training: its row is empty without smoothing
    C = sp.csr_array(np.array([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.0, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="never left"):
        dma.log_transitions(C)
    A = dma.estimate_transitions([np.array([0, 0, 1, 1, 2])], 3)
    assert np.allclose(A.sum(axis=1), 1.0)
    assert A[2, 2] == pytest.approx(1.0)


# ----------------------------------------------------------------------------------
# motion model
# ----------------------------------------------------------------------------------
def test_estimate_transitions_relative_frequencies():
    seqs = [np.array([0, 1, 1, 2, 0, 1]), np.array([2, 2, 0])]
    A = dma.estimate_transitions(seqs, 4, alpha=1e-9)
    assert sp.issparse(A)
    dense = A.toarray()
    assert np.allclose(dense.sum(axis=1), 1.0)
    assert dense[0, 1] == pytest.approx(1.0, abs=1e-6)
    assert dense[1, 1] == pytest.approx(0.5, abs=1e-6) and dense[1, 2] == pytest.approx(0.5, abs=1e-6)
    assert dense[2, 0] == pytest.approx(2 / 3, abs=1e-6) and dense[2, 2] == pytest.approx(1 / 3, abs=1e-6)
    assert dense[3, 3] == pytest.approx(1.0)  # unseen state: self loop
    assert A.nnz == 7


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), S=st.integers(2, 15))
def test_estimated_transitions_row_stochastic(seed, S):
    rng = np.random.default_rng(seed)
    seqs = [rng.integers(0, S, rng.integers(1, 30)) for _ in range(3)]
    nb = dma.neighbor_graph(rng.random((S, 2)), 0.3)
    A = dma.estimate_transitions(seqs, S, alpha=0.01, neighbors=nb)
    assert np.allclose(A.sum(axis=1), 1.0)
    assert (A.data > 0).all()
    dma.check_row_stochastic(A)


def test_estimate_transitions_bad_inputs():
    with pytest.raises(ValueError, match="empty"):
        dma.estimate_transitions([], 3)
    with pytest.raises(ValueError, match="outside"):
        dma.estimate_transitions([np.array([0, 5])], 3)
    with pytest.raises(ValueError, match="alpha"):
        dma.estimate_transitions([np.array([0, 1])], 3, alpha=0.0)
    with pytest.raises(ValueError, match="neighbors"):
        dma.estimate_transitions([np.array([0, 1])], 3, neighbors=sp.eye_array(4))
    with pytest.raises(TypeError, match="n_states"):
        dma.estimate_transitions([np.array([0, 1])], 3.0)
    with pytest.raises(ValueError, match="sequences"):
        dma.estimate_transitions([np.array([0.5, 1.0])], 3)


def test_velocity_field_chain():
    rng = np.random.default_rng(0)
    P = mf.sphere_points(200, rng)
    A = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.2, n_next=2, project=mf.project_to_sphere)
    assert np.allclose(A.sum(axis=1), 1.0)
    assert (np.diff(A.indptr) <= 2).all()
    # the chain moves along the field: mean displacement has positive dot with velocity
    nxt = np.asarray(A.argmax(axis=1)).ravel()
    disp = P[nxt] - P
    moved = nxt != np.arange(len(P))
    assert moved.mean() > 0.5
    assert (np.einsum("ij,ij->i", disp, mf.sphere_velocity(P))[moved] > 0).mean() > 0.9
    with pytest.raises(TypeError, match="velocity"):
        dma.transitions_from_velocity_field(P, None, 0.2)
    with pytest.raises(ValueError, match="dt"):
        dma.transitions_from_velocity_field(P, mf.sphere_velocity, -1.0)
    with pytest.raises(ValueError, match="n_next"):
        dma.transitions_from_velocity_field(P[:1], mf.sphere_velocity, 0.1, n_next=2)


# ----------------------------------------------------------------------------------
# manifold learning
# ----------------------------------------------------------------------------------
def test_learn_manifold_parabola_planes_are_tangent():
    X = mf.parabolic_surface(1500, np.random.default_rng(0))
    man = dma.learn_manifold(X, 8, 6, np.random.default_rng(1), dim=2)
    assert man.n_regions <= 8 and man.n_prototypes <= 48
    # local planes: the residual off the plane is much smaller than the spread in it
    assert (man.projection_mse() < 0.05 * man.eigenvalues[:, :2].sum(axis=1)).all()
    # orthonormal frames
    for V in man.bases:
        assert np.allclose(V.T @ V, np.eye(2))
    # prototypes lie close to the surface
    P = man.prototypes
    assert np.abs(P[:, 2] - (P[:, :2] ** 2).sum(axis=1)).max() < 0.15
    # eq. (6): assign = argmin Mahalanobis; quantize gives prototypes of the assigned region
    r = man.assign(X[:50])
    assert (r == np.argmin(man.mahalanobis(X[:50]), axis=1)).all()
    assert (man.prototype_region[man.quantize(X[:50])] == r).all()
    # eq. (7)-(8): local coordinates of a projected point reproduce the projection
    proj = man.project(X[:5])
    loc = man.local_coordinates(X[:5])
    for x, k, l in zip(proj, r[:5], loc):
        assert np.allclose(man.means[k] + man.bases[k] @ l, x)


def test_learn_manifold_deterministic_for_rng():
    X = mf.parabolic_surface(600, np.random.default_rng(0))
    a = dma.learn_manifold(X, 4, 5, np.random.default_rng(7), dim=2)
    b = dma.learn_manifold(X, 4, 5, np.random.default_rng(7), dim=2)
    assert np.array_equal(a.prototypes, b.prototypes)


def test_learn_manifold_error_driven_dimension():
    t = np.random.default_rng(0).uniform(0, 2 * np.pi, 800)
    X = np.column_stack([mf.closed_curve(t), np.zeros(800)])
    man = dma.learn_manifold(X, 10, 4, np.random.default_rng(0), max_mse=5e-3)
    assert (man.dims == 1).all()
    man3 = dma.learn_manifold(X, 10, 4, np.random.default_rng(0), max_mse=0.0)
    assert (man3.dims >= 2).all()


def test_select_n_regions_prefers_more_than_one_on_curve():
    t = np.random.default_rng(0).uniform(0, 2 * np.pi, 600)
    X = mf.closed_curve(t)
    best, bic = dma.select_n_regions(X, [1, 2, 8], np.random.default_rng(0))
    assert best == 8 and bic.shape == (3,)


def test_learn_manifold_bad_inputs():
    rng = np.random.default_rng(0)
    X = mf.parabolic_surface(100, rng)
    with pytest.raises(ValueError, match="empty"):
        dma.learn_manifold(np.zeros((0, 3)), 2, 2, rng, dim=2)
    with pytest.raises(ValueError, match="finite"):
        dma.learn_manifold(np.where(X == X[0, 0], np.nan, X), 2, 2, rng, dim=2)
    with pytest.raises(ValueError, match="exactly one"):
        dma.learn_manifold(X, 2, 2, rng)
    with pytest.raises(ValueError, match="dim"):
        dma.learn_manifold(X, 2, 2, rng, dim=4)
    with pytest.raises(ValueError, match="n_regions"):
        dma.learn_manifold(X, 200, 2, rng, dim=2)
    with pytest.raises(TypeError, match="rng"):
        dma.learn_manifold(X, 2, 2, 0, dim=2)
    with pytest.raises(ValueError, match="X"):
        dma.learn_manifold(X[:, 0], 2, 2, rng, dim=2)
    man = dma.learn_manifold(X, 2, 2, rng, dim=2)
    with pytest.raises(ValueError, match="columns"):
        man.quantize(np.zeros((3, 2)))


# ----------------------------------------------------------------------------------
# sensor models
# ----------------------------------------------------------------------------------
def test_linear_gaussian_sensor_matches_scipy():
    from scipy.stats import multivariate_normal

    P = np.random.default_rng(0).normal(size=(5, 3))
    H = np.array([[1.0, -1.0, 1.0]])
    s = dma.LinearGaussianSensor(P, H, 0.04)
    y = np.array([[0.3], [-1.0]])
    ll = s.log_likelihoods(y)
    ref = np.array([[multivariate_normal(P[k] @ H.T, 0.04).logpdf(yy) for k in range(5)] for yy in y])
    assert np.allclose(ll, ref)
    assert np.allclose(s.log_likelihood([0.3]), ref[0])
    with pytest.raises(ValueError, match="NaN"):
        s.log_likelihoods([[np.nan]])
    with pytest.raises(ValueError, match="H"):
        dma.LinearGaussianSensor(P, np.ones((1, 2)), 0.1)
    with pytest.raises(ValueError, match="noise_cov"):
        dma.LinearGaussianSensor(P, H, -1.0)


def test_range_cosine_sensor():
    P = np.array([[0.0, 0.0], [100.0, 0.0], [0.0, 50.0]])
    s = dma.RangeCosineSensor(P, [0.0, 0.0], 0.02, 0.05)
    assert np.allclose(s.distances, [0, 100, 50])
    ll = s.log_likelihoods([np.cos(0.02 * 100)])
    assert np.argmax(ll[0]) == 1
    with pytest.raises(ValueError, match="NaN"):
        s.log_likelihoods([np.nan])
    with pytest.raises(ValueError, match="receiver"):
        dma.RangeCosineSensor(P, [0.0], 0.02, 0.05)
    with pytest.raises(ValueError, match="noise_var"):
        dma.RangeCosineSensor(P, [0.0, 0.0], 0.02, 0.0)


def test_active_pixel_sensor_counts_match_loop():
    rng = np.random.default_rng(0)
    img = rng.random((20, 30)) > 0.7
    P = np.array([[0, 0], [10, 15], [19, 29], [5.2, 7.8]])
    s = dma.ActivePixelSensor(P, 5, 3.0)
    n = s.counts(img)
    for k, (r, c) in enumerate(np.rint(P).astype(int)):
        assert n[k] == img[max(r - 2, 0):r + 3, max(c - 2, 0):c + 3].sum()
    assert np.allclose(s.log_likelihood(img), n * np.log(3.0))
    with pytest.raises(ValueError, match="odd"):
        dma.ActivePixelSensor(P, 4, 3.0)
    with pytest.raises(ValueError, match="observation"):
        s.log_likelihood(img[0])


def test_fit_c_greater_than_one_when_car_is_active():
    frames = np.zeros((4, 20, 20), dtype=bool)
    pos = np.array([[5, 5], [6, 6], [10, 10], [12, 8]])
    for t, (r, c) in enumerate(pos):
        frames[t, r - 1:r + 2, c - 1:c + 2] = True
    frames[:, 0, 0] = True  # a little clutter
    assert dma.ActivePixelSensor.fit_c(frames, pos, 5) > 10


# ----------------------------------------------------------------------------------
# the estimator end to end
# ----------------------------------------------------------------------------------
def test_dma_estimator_tracks_noisy_curve():
    rng = np.random.default_rng(0)
    train = [mf.curve_trajectory(300, rng) for _ in range(5)]
    model = dma.DMA(n_regions=6, n_prototypes=6, dim=1, rng=np.random.default_rng(1)).fit(train)
    assert np.allclose(model.transitions_.sum(axis=1), 1.0)
    truth = mf.curve_trajectory(80, rng)
    sensor = dma.LinearGaussianSensor(model.prototypes_, np.eye(2), 0.3**2)
    y = truth + 0.3 * rng.standard_normal(truth.shape)
    est = model.predict(y, sensor)
    raw = np.linalg.norm(y - truth, axis=1).mean()
    err = np.linalg.norm(est - truth, axis=1).mean()
    assert est.shape == truth.shape and err < 0.5 * raw
    for method in ("smooth", "filter"):
        assert model.predict_path(y, sensor, method=method).shape == (80,)
    with pytest.raises(ValueError, match="method"):
        model.predict_path(y, sensor, method="magic")
    with pytest.raises(ValueError, match="states"):
        model.predict(y, dma.LinearGaussianSensor(np.zeros((3, 2)), np.eye(2), 1.0))


def test_dma_estimator_bad_inputs():
    with pytest.raises(ValueError, match="empty"):
        dma.DMA().fit([])
    with pytest.raises(ValueError, match="not fitted"):
        dma.DMA().predict_path(np.zeros((3, 2)), dma.LinearGaussianSensor(np.zeros((1, 2)), np.eye(2), 1.0))


# ----------------------------------------------------------------------------------
# scenes
# ----------------------------------------------------------------------------------
def test_sample_markov_chain_follows_support():
    A = sp.csr_array(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    path = mf.sample_markov_chain(np.array([1.0, 0, 0]), A, 7, np.random.default_rng(0))
    assert list(path) == [0, 1, 2, 0, 1, 2, 0]


def test_road_scene_cars_stay_on_roads():
    scene = make_road_scene(np.random.default_rng(0))
    x = scene.drive(100, np.random.default_rng(1))
    from scipy.spatial import cKDTree

    d = cKDTree(scene.prototypes).query(x)[0]
    assert d.max() <= scene.spacing
    assert np.allclose(x[:, 2], scene.elevation(x[:, :2]))
    step = np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1)
    assert step.max() < 1.6 * 12.0 + 1e-6
    states = scene.directed_states()
    q = states.quantize(x)
    v = np.diff(x[:, :2], axis=0)
    assert (np.einsum("ij,ij->i", states.headings[q[1:]], v) > 0).mean() > 0.95


def test_slotcar_video_shapes_and_occlusion():
    v = make_slotcar_video(120, np.random.default_rng(0))
    assert v.frames.shape == (120, 48, 64) and v.positions.shape == (120, 2)
    assert v.occluded.any() and not v.occluded.all()
    # a visible car is brighter than the background at its position
    t = np.flatnonzero(~v.occluded)[0]
    r, c = np.rint(v.positions[t]).astype(int)
    assert v.frames[t, r, c] - v.background[r, c] > 0.2
    # an occluded car is not visible
    t = np.flatnonzero(v.occluded)[0]
    r, c = np.rint(v.positions[t]).astype(int)
    assert abs(v.frames[t, r, c] - v.background[r, c]) < 0.25


def test_learn_manifold_warns_when_it_keeps_fewer_prototypes():
    X = mf.parabolic_surface(10, np.random.default_rng(0))
    with pytest.warns(UserWarning, match=r"kept \d+ of n_regions=2 regions and \d+ of 16 prototypes"):
        man = dma.learn_manifold(X, 2, 8, np.random.default_rng(1), dim=2)
    assert man.n_prototypes < 16


def test_learn_manifold_silent_when_everything_is_kept():
    import warnings

    X = mf.parabolic_surface(400, np.random.default_rng(0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        man = dma.learn_manifold(X, 3, 4, np.random.default_rng(1), dim=2)
    assert man.n_regions == 3 and man.n_prototypes == 12


def test_road_scene_bad_inputs():
    rng = np.random.default_rng(0)
    for kwargs, name in [({"extent": 0.0}, "extent"), ({"extent": np.nan}, "extent"),
                         ({"spacing": -1.0}, "spacing"), ({"grid": 1}, "grid"),
                         ({"n_hills": -1}, "n_hills"), ({"n_hills": 2.5}, "n_hills")]:
        with pytest.raises(ValueError, match=name):
            make_road_scene(rng, **kwargs)
    with pytest.raises(TypeError, match="rng"):
        make_road_scene(0)
    scene = make_road_scene(np.random.default_rng(0))
    for kwargs, name in [({"speed": 0.0}, "speed"), ({"speed": -3.0}, "speed"),
                         ({"dt": 0.0}, "dt"), ({"dt": np.inf}, "dt")]:
        with pytest.raises(ValueError, match=name):
            scene.drive(10, np.random.default_rng(1), **kwargs)
    with pytest.raises(ValueError, match="n_steps"):
        scene.drive(0, np.random.default_rng(1))
    with pytest.raises(ValueError, match="heading_scale"):
        scene.directed_states(0.0)
    with pytest.raises(ValueError, match="xy"):
        scene.elevation(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="xy"):
        scene.elevation(np.array([[np.nan, 1.0]]))
    with pytest.raises(ValueError, match="n must"):
        scene.elevation_grid(1)
    states = scene.directed_states()
    with pytest.raises(ValueError, match="finite"):
        states.quantize(np.array([[0.0, 0.0], [np.nan, 1.0]]))
    with pytest.raises(ValueError, match="trajectory"):
        states.quantize(np.zeros((5, 4)))


def test_slotcar_video_bad_inputs():
    rng = np.random.default_rng(0)
    for kwargs, name in [({"noise": -0.1}, "noise"), ({"noise": np.nan}, "noise"),
                         ({"fps": 0.0}, "fps"), ({"fps": -12.0}, "fps"),
                         ({"speed": 0.0}, "speed"), ({"speed": -1.0}, "speed"),
                         ({"bridge_width": 0.0}, "bridge_width"),
                         ({"shape": (8, 64)}, "shape"), ({"shape": (48.0, 64)}, "shape"),
                         ({"shape": 48}, "shape")]:
        with pytest.raises(ValueError, match=name):
            make_slotcar_video(5, rng, **kwargs)
    with pytest.raises(ValueError, match="n_frames"):
        make_slotcar_video(0, rng)
    with pytest.raises(TypeError, match="rng"):
        make_slotcar_video(5, 0)
    # noise = 0 is allowed and gives the clean scene away from the car
    v = make_slotcar_video(2, np.random.default_rng(0), noise=0.0)
    far = np.linalg.norm(np.indices(v.background.shape).reshape(2, -1).T - v.positions[0], axis=1) > 6
    assert np.allclose(v.frames[0].ravel()[far], v.background.ravel()[far], atol=1e-6)


def test_velocity_field_chain_exclude_self():
    rng = np.random.default_rng(1)
    P = mf.sphere_points(150, rng)
    # deterministic chain: one successor per state, never the state itself
    A = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.05, n_next=1, project=mf.project_to_sphere,
                                            exclude_self=True)
    assert (np.diff(A.indptr) == 1).all() and np.allclose(A.data, 1.0)
    assert (A.diagonal() == 0).all()
    # the successor is the nearest other point to the predicted point (brute force)
    pred = mf.project_to_sphere(P + 0.05 * mf.sphere_velocity(P))
    d = np.linalg.norm(pred[:, None] - P[None], axis=2)
    np.fill_diagonal(d, np.inf)
    assert (A.indices == d.argmin(axis=1)).all()
    # with a short step most states would keep a self-loop without exclude_self
    B = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.05, n_next=2, project=mf.project_to_sphere)
    assert (B.diagonal() > 0).mean() > 0.5
    C2 = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.05, n_next=2, exclude_self=True)
    assert (C2.diagonal() == 0).all() and (np.diff(C2.indptr) == 2).all()
    with pytest.raises(TypeError, match="exclude_self"):
        dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.1, exclude_self="yes")
    with pytest.raises(ValueError, match="n_next"):
        dma.transitions_from_velocity_field(P[:2], mf.sphere_velocity, 0.1, n_next=2, exclude_self=True)


def test_velocity_field_chain_width():
    rng = np.random.default_rng(2)
    P = mf.sphere_points(120, rng)
    pred = mf.project_to_sphere(P + 0.2 * mf.sphere_velocity(P))
    default = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.2, project=mf.project_to_sphere)
    spacing = float(np.median(np.sort(np.linalg.norm(P[:, None] - P[None], axis=2), axis=1)[:, 1]))
    same = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.2, project=mf.project_to_sphere,
                                               width=spacing)
    assert np.allclose(default.toarray(), same.toarray())  # the default width is the median spacing
    narrow = dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.2, project=mf.project_to_sphere,
                                                 width=0.3 * spacing)
    # the weights are Gaussian in the distance to the predicted point: check one row by hand
    i = 0
    j = narrow.indices[narrow.indptr[i]:narrow.indptr[i + 1]]
    w = np.exp(-0.5 * (np.linalg.norm(P[j] - pred[i], axis=1) / (0.3 * spacing)) ** 2)
    assert np.allclose(narrow.data[narrow.indptr[i]:narrow.indptr[i + 1]], w / w.sum())
    # narrower weights make the chain closer to deterministic
    assert np.asarray(narrow.max(axis=1).todense()).mean() > np.asarray(default.max(axis=1).todense()).mean()
    for bad in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="width"):
            dma.transitions_from_velocity_field(P, mf.sphere_velocity, 0.2, width=bad)
def test_viterbi_spends_an_unobserved_stretch_in_the_stickiest_state():
    # A left-to-right chain observed only at its two ends: every path through the hidden
    # frames makes the same moves, so the MAP path puts all its waiting in the state with
    # the largest self-loop (state 3, 0.8) and runs ahead of a car that moves steadily.
    # This is why the slot-car Viterbi estimate leads the car under a wide bridge; the
    # per-instant posterior spreads the waiting instead.
    stay = np.array([0.5, 0.2, 0.2, 0.8, 0.5])
    P = np.diag(stay) + np.diag(1 - stay[:-1], 1)
    P[-1, 0] = 0.5  # a closed track, like the slot-car loop
    n = 9
    le = np.zeros((n, 5))
    le[0] = [0.0, -50, -50, -50, -50]
    le[-1] = [-50, -50, -50, -50, 0.0]
    with np.errstate(divide="ignore"):
        ls, lt = np.log([1.0, 0, 0, 0, 0]), np.log(P)
    path = dma.viterbi(ls, lt, le)
    assert list(path) == [0, 1, 2, 3, 3, 3, 3, 3, 4]
    post = np.exp(dma.forward_backward(ls, lt, le)[0])
    assert post[2, 1:3].sum() > post[2, 3]  # the posterior has not yet moved on at frame 2

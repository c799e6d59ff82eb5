"""Tests of projtrack.novelty (Vermeulen & Casasent 1988, Eqs. (2)-(12))."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.linalg import subspace_angles
from sklearn.decomposition import PCA

from projtrack import novelty as nv


def _frames(rng, n=10, shape=(6, 7)):
    return rng.random((n,) + shape) * 255


# --- batch KL (Eqs. (2)-(3)) -------------------------------------------------------------------
@pytest.mark.parametrize("center", [False, True])
def test_batch_kl_matches_large_correlation_matrix(center):
    rng = np.random.default_rng(1)
    x = _frames(rng, 9, (5, 6))
    basis = nv.batch_kl(x, center=center)
    big = nv.correlation_matrix(x, center=center)
    lam, vec = np.linalg.eigh(big)
    lam, vec = lam[::-1], vec[:, ::-1]
    k = basis.eigenvalues.size
    assert k == (8 if center else 9)
    np.testing.assert_allclose(basis.eigenvalues, lam[:k], rtol=1e-9)
    e = basis.eigenimages.reshape(k, -1)
    assert np.max(subspace_angles(e.T, vec[:, :k])) < 1e-7
    # each eigenimage is an eigenvector of the big matrix with its eigenvalue
    np.testing.assert_allclose(e @ big, basis.eigenvalues[:, None] * e, atol=1e-6 * lam[0])


def test_batch_kl_centered_matches_sklearn_pca():
    rng = np.random.default_rng(2)
    x = _frames(rng, 12, (4, 5))
    basis = nv.batch_kl(x, center=True, n_components=4)
    pca = PCA(n_components=4, svd_solver="full").fit(x.reshape(12, -1))
    # PCA uses 1/(n-1); Eq. (2) uses 1/I
    np.testing.assert_allclose(basis.eigenvalues, pca.explained_variance_ * 11 / 12, rtol=1e-9)
    np.testing.assert_allclose(np.abs(basis.eigenimages.reshape(4, -1) @ pca.components_.T),
                               np.eye(4), atol=1e-8)


def test_vip_matrix_is_eq2():
    rng = np.random.default_rng(3)
    x = _frames(rng, 4, (3, 3))
    v = nv.vip_matrix(x)
    f = x.reshape(4, -1)
    assert v[1, 2] == pytest.approx(f[1] @ f[2] / 4)
    vc = nv.vip_matrix(x, center=True)
    fc = f - f.mean(0)
    assert vc[0, 3] == pytest.approx(fc[0] @ fc[3] / 4)


@pytest.mark.parametrize("bad,err", [
    ([], ValueError), (np.zeros((3, 4, 4)), ValueError), (np.ones(5), ValueError),
    (np.array([[1.0, np.nan]]), ValueError), (np.ones((2, 2), dtype=bool), TypeError),
    (np.ones((2, 2), dtype=complex), TypeError), ([np.ones((2, 2)), np.ones((3, 3))], ValueError),
])
def test_batch_kl_bad_inputs(bad, err):
    with pytest.raises(err):
        nv.batch_kl(bad)


def test_batch_kl_bad_n_components_and_large_matrix():
    with pytest.raises(ValueError, match="n_components"):
        nv.batch_kl(np.ones((2, 3, 3)), n_components=0)
    with pytest.raises(ValueError, match="pixels"):
        nv.correlation_matrix(np.ones((2, 100, 100)))


# --- NoveltyFilter --------------------------------------------------------------------------
def test_first_frame_is_first_eigenimage():
    rng = np.random.default_rng(4)
    x = _frames(rng, 1, (8, 8))[0]
    f = nv.NoveltyFilter(0.01, 0.95)
    assert f.partial_fit(x) == (1.0, True)
    assert f.eigenvalues_[0] == pytest.approx(np.sum(x ** 2))   # V_1 = energy (Fig. 2a)
    np.testing.assert_allclose(f.eigenimages_[0], x / np.linalg.norm(x))
    np.testing.assert_allclose(f.information_fractions_, [1.0])
    assert f.eigenimages_.shape == (1, 8, 8)


def test_vip_matrix_eqs_4_5_and_novelty_eq7():
    rng = np.random.default_rng(5)
    x1, x2 = _frames(rng, 2, (5, 5))
    f = nv.NoveltyFilter(0.9, 0.95)
    f.partial_fit(x1)
    n, novel = f.partial_fit(x2)
    v = f.vip_matrix_
    e1, e2 = np.sum(x1 ** 2), np.sum(x2 ** 2)
    np.testing.assert_allclose(v, [[e1 / 2, np.sum(x1 * x2) / 2], [np.sum(x1 * x2) / 2, e2 / 2]])
    assert n == pytest.approx(1 - np.sum(x1 * x2) ** 2 / (e1 * e2))
    assert novel is False  # n < 0.9
    # the paper's own numbers (Fig. 2b): V_2 entries give n_2 = 0.001811
    vp = np.array([[36772008.0, 36772052.0], [36772052.0, 36838816.0]])
    assert nv._novelty_from_vip(vp) == pytest.approx(0.001811, abs=5e-7)


@settings(max_examples=25, deadline=None)
@given(n=st.integers(2, 9), h=st.integers(2, 6), w=st.integers(2, 6), seed=st.integers(0, 10**6))
def test_td0_ti1_reproduces_batch_eigendecomposition(n, h, w, seed):
    rng = np.random.default_rng(seed)
    x = rng.random((n, h, w)) + 0.1
    f = nv.NoveltyFilter(novelty_threshold=0.0, information_threshold=1.0)
    for frame in x:
        f.partial_fit(frame)
    basis = nv.batch_kl(x, rtol=1e-10)
    k = basis.eigenvalues.size
    assert f.n_updates_ == n
    np.testing.assert_allclose(f.eigenvalues_[:k], basis.eigenvalues, rtol=1e-7,
                               atol=1e-9 * basis.eigenvalues[0])
    assert np.all(f.eigenvalues_[k:] < 1e-8 * basis.eigenvalues[0])
    e = f.components_
    np.testing.assert_allclose(e @ e.T, np.eye(len(e)), atol=1e-8)    # orthonormal
    angles = subspace_angles(e[:k].T, basis.eigenimages.reshape(k, -1).T)
    assert np.max(angles) < 1e-5


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), td=st.floats(0, 0.2), ti=st.floats(0.5, 1.0))
def test_novelty_in_unit_interval_and_orthogonal(seed, td, ti):
    rng = np.random.default_rng(seed)
    x = rng.random((8, 4, 4)) ** 3 + rng.random() * np.ones((8, 4, 4))
    f = nv.NoveltyFilter(td, ti)
    for frame in x:
        before = (f.eigenvalues_, f.eigenimages_, f.n_updates_) if f.n_frames_seen_ else None
        n, novel = f.partial_fit(frame)
        if not novel:       # a non-novel frame leaves the model unchanged
            np.testing.assert_array_equal(f.eigenvalues_, before[0])
            np.testing.assert_array_equal(f.eigenimages_, before[1])
            assert f.n_updates_ == before[2]
        assert 0.0 <= n <= 1.0
        assert novel == (n > td) or f.n_frames_seen_ == 1
        e = f.components_
        np.testing.assert_allclose(e @ e.T, np.eye(len(e)), atol=1e-8)
        assert np.all(f.eigenvalues_ > 0)
        assert np.all(np.diff(f.eigenvalues_) <= 1e-9 * f.eigenvalues_[0])
        assert f.information_fractions_.sum() == pytest.approx(1.0)
        assert f.rank_ == len(f.eigenvalues_)


def test_novelty_zero_in_span_one_orthogonal():
    f = nv.NoveltyFilter(0.01, 1.0)
    a = np.zeros((4, 4)); a[0] = 1.0
    b = np.zeros((4, 4)); b[1] = 2.0
    f.partial_fit(a)
    f.partial_fit(b)
    assert f.rank_ == 2
    assert f.novelty(3 * a - 0.5 * b) == pytest.approx(0.0, abs=1e-12)
    c = np.zeros((4, 4)); c[3, 2] = 5.0
    assert f.novelty(c) == pytest.approx(1.0)
    assert f.novelty(np.zeros((4, 4))) == 0.0
    np.testing.assert_allclose(f.reconstruct(3 * a - 0.5 * b), 3 * a - 0.5 * b, atol=1e-12)
    np.testing.assert_allclose(f.reconstruct(c), 0.0, atol=1e-12)
    assert f.novel_pixels(c + a, 4.0).sum() == 1
    # energies 4 (a) and 16 (b): b is the first eigenimage; coefficient of a is |a| = 2
    np.testing.assert_allclose(f.transform(a), [0.0, 2.0], atol=1e-12)


def test_td0_uses_frames_in_the_span():
    a = np.zeros((3, 3)); a[0] = 1.0
    f = nv.NoveltyFilter(0.0, 1.0)
    f.partial_fit(a)
    n, novel = f.partial_fit(2 * a)
    assert n == 0.0 and novel
    assert f.eigenvalues_ == pytest.approx([(3 + 12) / 2])   # (|a|^2 + |2a|^2) / 2
    assert f.rank_ == 1


def test_non_novel_frames_leave_model_unchanged():
    rng = np.random.default_rng(6)
    base = rng.random((6, 6)) * 100
    f = nv.NoveltyFilter(0.05, 0.95)
    f.partial_fit(base)
    lam, e, i = f.eigenvalues_, f.eigenimages_, f.n_updates_
    for _ in range(5):
        n, novel = f.partial_fit(base * rng.uniform(0.5, 2) + rng.normal(0, 0.5, (6, 6)))
        assert not novel and n < 0.05
    np.testing.assert_array_equal(f.eigenvalues_, lam)
    np.testing.assert_array_equal(f.eigenimages_, e)
    assert f.n_updates_ == i and f.n_frames_seen_ == 6


def test_rank_estimate_eq11_and_uint8_frames():
    # two orthogonal patterns with energies 9:1 -> F = [0.9, 0.1]
    a = np.zeros((4, 4), np.uint8); a[:2] = 3
    b = np.zeros((4, 4), np.uint8); b[2:] = 1
    for ti, k in [(0.85, 1), (0.95, 2), (0.9, 1)]:
        f = nv.NoveltyFilter(0.0, ti)
        f.partial_fit(a)
        f.partial_fit(b)
        np.testing.assert_allclose(f.information_fractions_, [0.9, 0.1])
        assert f.rank_ == k


def test_weighted_first_eigenimage_is_background_for_static_scene():
    rng = np.random.default_rng(7)
    bg = rng.random((10, 10)) * 200 + 20
    f = nv.NoveltyFilter(0.0, 0.95)
    for _ in range(6):
        f.partial_fit(bg + rng.normal(0, 1, bg.shape))
    assert np.max(np.abs(f.weighted_eigenimages()[0] - bg)) < 5


@pytest.mark.parametrize("kw", [dict(novelty_threshold=-0.1), dict(novelty_threshold=1.5),
                                dict(information_threshold=1.01), dict(information_threshold=-1)])
def test_thresholds_outside_unit_interval(kw):
    with pytest.raises(ValueError, match="must lie in"):
        nv.NoveltyFilter(**kw)


def test_threshold_types():
    with pytest.raises(TypeError):
        nv.NoveltyFilter(novelty_threshold="0.1")
    with pytest.raises(TypeError):
        nv.NoveltyFilter(information_threshold=True)


def test_bad_frames():
    f = nv.NoveltyFilter(0.01, 0.95)
    with pytest.raises(ValueError, match="first frame is all zero"):
        f.partial_fit(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="NaN"):
        f.partial_fit(np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="partial_fit first"):
        _ = f.eigenvalues_
    with pytest.raises(ValueError, match="partial_fit first"):
        f.novelty(np.ones((4, 4)))
    f.partial_fit(np.ones((4, 4)))
    with pytest.raises(ValueError, match="expected shape"):
        f.partial_fit(np.ones((4, 5)))
    with pytest.raises(ValueError, match="NaN or infinite"):
        f.partial_fit(np.array([[np.inf] * 4] * 4))
    with pytest.raises(TypeError):
        f.partial_fit(np.array([["a"] * 4] * 4))
    with pytest.raises(ValueError):
        f.partial_fit(np.float64(3.0))
    with pytest.raises(ValueError, match="pixel_threshold"):
        f.novel_pixels(np.ones((4, 4)), -1)


# --- fixed-rank recursive SVD ---------------------------------------------------------------
def test_recursive_svd_exact_for_low_rank_process():
    rng = np.random.default_rng(8)
    basis = rng.standard_normal((3, 50))
    x = rng.standard_normal((20, 3)) @ basis
    r = nv.RecursiveSVD(3).fit(x.reshape(20, 5, 10))
    b = nv.batch_kl(x.reshape(20, 5, 10), n_components=3)
    np.testing.assert_allclose(r.eigenvalues_, b.eigenvalues, rtol=1e-8)
    assert r.eigenimages_.shape == (3, 5, 10)


def test_recursive_svd_approximates_full_rank_process_worse_than_batch():
    rng = np.random.default_rng(9)
    x = rng.random((30, 40))
    r = nv.RecursiveSVD(2).fit(x.reshape(30, 4, 10))
    b = nv.batch_kl(x.reshape(30, 4, 10))
    assert r.eigenvalues_[1] < b.eigenvalues[1]      # information discarded at each step
    with pytest.raises(ValueError, match="n_components"):
        nv.RecursiveSVD(0)
    with pytest.raises(ValueError, match="at least"):
        _ = nv.RecursiveSVD(3).partial_fit(x[0]).eigenvalues_


# --- classifier and sequence driver --------------------------------------------------------
def test_classifier_smallest_novelty_wins():
    rng = np.random.default_rng(10)
    protos = rng.random((3, 8, 8))
    train = np.concatenate([p * rng.uniform(0.5, 1.5, (5, 1, 1)) + 0.01 * rng.random((5, 8, 8))
                            for p in protos])
    labels = np.repeat(["a", "b", "c"], 5)
    clf = nv.NoveltyClassifier(0.001, 0.99).fit(train, labels)
    test = protos * 2 + 0.01 * rng.random((3, 8, 8))
    nov = clf.novelties(test)
    assert nov.shape == (3, 3)
    assert list(clf.predict(test)) == ["a", "b", "c"]
    assert np.all(np.diag(nov) < 0.01)
    with pytest.raises(ValueError, match="labels"):
        clf.fit(train, labels[:-1])
    with pytest.raises(ValueError, match="not fitted"):
        nv.NoveltyClassifier().predict(test)


def test_process_sequence_records():
    rng = np.random.default_rng(11)
    x = (rng.random((5, 6, 6)) * 255).astype(np.uint8)
    recs = nv.process_sequence(x, 0.0, 1.0, pixel_threshold=8)
    assert [r.frame for r in recs] == [1, 2, 3, 4, 5]
    assert recs[0].novel_pixels.all() and recs[0].vip.shape == (1, 1)
    assert recs[3].vip.shape == (4, 4) and recs[3].fractions.size == 4
    assert recs[-1].rank == 5
    assert recs[-1].first_eigenimage.shape == (6, 6)
    with pytest.raises(ValueError, match="must lie in"):
        nv.process_sequence(x, 2.0, 0.5)


def test_table1_steps():
    assert [s for s, _ in nv.TABLE1_STEPS] == list(range(1, 12))

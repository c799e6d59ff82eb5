"""Tests of projtrack.novelty (Vermeulen & Casasent 1988, Eqs. (2)-(12))."""
from __future__ import annotations

import warnings
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.linalg import subspace_angles
from sklearn.decomposition import PCA

from projtrack import novelty as nv
from projtrack.novelty.updates import _novelty_from_vip


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
    assert _novelty_from_vip(vp) == pytest.approx(0.001811, abs=5e-7)


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


@pytest.mark.parametrize("method", nv.METHODS)
def test_td0_uses_frames_in_the_span(method):
    a = np.zeros((3, 3)); a[0] = 1.0
    f = nv.NoveltyFilter(0.0, 1.0, method=method)
    f.partial_fit(a)
    n, novel = f.partial_fit(2 * a)
    assert n == pytest.approx(0.0, abs=1e-20) and novel
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


# --- the two numerical routes, the dropped-eigenvalue warning, the report's printed numbers ---
def _near_duplicates(delta, n=6, p=400, seed=11):
    rng = np.random.default_rng(seed)
    base = rng.uniform(50, 200, p)
    return np.array([base + delta * rng.standard_normal(p) for _ in range(n)])


def _ortho_error(f):
    u = f.components_
    return float(np.max(np.abs(u @ u.T - np.eye(len(u)))))


def test_qr_route_keeps_orthonormality_on_near_duplicates_vip_does_not():
    frames = _near_duplicates(1e-3)          # frames differ by 1e-3 grey levels around 125
    s2 = np.linalg.svd(frames, compute_uv=False) ** 2 / len(frames)   # the oracle
    qr = nv.NoveltyFilter(0.0, 1.0, method="qr").fit(frames)
    vip = nv.NoveltyFilter(0.0, 1.0, method="vip").fit(frames)
    assert qr.rank_ == vip.rank_ == len(frames)
    assert _ortho_error(qr) < 1e-12
    assert _ortho_error(vip) > 1e-7          # the Gram matrix squares the condition number
    np.testing.assert_allclose(qr.eigenvalues_, s2, rtol=1e-9)
    assert np.max(np.abs(vip.eigenvalues_ - s2) / s2) > 1e-7


def test_vip_route_warns_when_ti1_drops_information_qr_keeps_it():
    frames = _near_duplicates(1e-4)          # new directions carry fractions ~1e-13
    with pytest.warns(nv.EigenvalueDroppedWarning, match="T_I = 1"):
        vip = nv.NoveltyFilter(0.0, 1.0, method="vip").fit(frames)
    assert vip.rank_ < len(frames)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        qr = nv.NoveltyFilter(0.0, 1.0, method="qr").fit(frames)
    assert qr.rank_ == len(frames)
    assert _ortho_error(qr) < 1e-12


def test_routes_agree_on_well_conditioned_frames():
    rng = np.random.default_rng(3)
    frames = rng.uniform(0, 255, (8, 10, 10))
    a = nv.process_sequence(frames, 0.01, 0.999, method="qr")
    b = nv.process_sequence(frames, 0.01, 0.999, method="vip")
    for ra, rb in zip(a, b):
        assert ra.novel == rb.novel and ra.rank == rb.rank
        assert ra.novelty == pytest.approx(rb.novelty, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(ra.vip, rb.vip, rtol=1e-10)
        np.testing.assert_allclose(ra.eigenvalues, rb.eigenvalues, rtol=1e-9)


def test_no_warning_when_the_rank_rule_or_a_zero_eigenvalue_drops():
    a = np.zeros(50); a[0] = 100.0
    b = np.zeros(50); b[1] = 100.0
    c = a.copy(); c[2] = 1e-4                # new direction with a fraction ~3e-13
    for method in nv.METHODS:
        # T_I < 1: dropping is the rank rule's own choice
        g = nv.NoveltyFilter(0.0, 0.999, method=method)
        g.partial_fit(a); g.partial_fit(b)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            g.partial_fit(c)
        assert g.rank_ == 2
        # a frame exactly in the span drops only a zero eigenvalue
        h = nv.NoveltyFilter(0.0, 1.0, method=method)
        h.partial_fit(a); h.partial_fit(b)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            h.partial_fit(a + b)
        assert h.rank_ == 2
    # T_I = 1: the qr route keeps the small direction, the vip route drops it and warns
    q = nv.NoveltyFilter(0.0, 1.0, method="qr")
    q.partial_fit(a); q.partial_fit(b); q.partial_fit(c)
    assert q.rank_ == 3
    v = nv.NoveltyFilter(0.0, 1.0, method="vip")
    v.partial_fit(a); v.partial_fit(b)
    with pytest.warns(nv.EigenvalueDroppedWarning):
        v.partial_fit(c)
    assert v.rank_ == 2


def test_bad_method():
    with pytest.raises(ValueError, match="method"):
        nv.NoveltyFilter(0.01, 0.9, method="svd")
    with pytest.raises(ValueError, match="method"):
        nv.NoveltyClassifier(method=None)
    with pytest.raises(ValueError, match="method"):
        nv.process_sequence(np.ones((2, 3, 3)), 0.1, 0.9, method="QR")


def _pair_with_novelty(n, energy_ratio=1.0, p=64, seed=0):
    """Unit frame ``a`` and a frame ``b`` with ``|b|^2 = energy_ratio`` and novelty ``n`` wrt ``a``."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((p, 2)))
    a, e = q[:, 0] * 100, q[:, 1] * 100
    b = np.sqrt(energy_ratio) * (np.sqrt(1 - n) * a + np.sqrt(n) * e)
    return a, b


@pytest.mark.parametrize("method", nv.METHODS)
def test_report_frame4_numbers(method):
    # Fig. 2c: two equal-energy frames with n_4 = 0.002498 give F = [0.999375, 0.000625]
    a, b = _pair_with_novelty(0.002498)
    f = nv.NoveltyFilter(0.002, 0.95, method=method)
    f.partial_fit(a)
    n, novel = f.partial_fit(b)
    assert novel and n == pytest.approx(0.002498, rel=1e-9)
    np.testing.assert_allclose(np.round(f.information_fractions_, 6), [0.999375, 0.000625])
    assert f.rank_ == 1


def test_report_frame8_fraction_needs_three_prior_updates():
    # Fig. 2e: n_8 = 0.005841 and F_8 = 0.001090; equal-energy frames give 0.0013 after two
    # prior updates (frames 1 and 4: "not until frame 8 ... another update") and 0.0011 only
    # after three ("every few frames, the process model is updated")
    out = {}
    for prior in (1, 2, 3, 4):
        a, b = _pair_with_novelty(0.005841)
        f = nv.NoveltyFilter(0.0, 0.95)
        for _ in range(prior):
            f.partial_fit(a)
        f.partial_fit(b)
        out[prior] = float(f.information_fractions_[1])
    assert round(out[2], 4) == 0.0013
    assert round(out[3], 4) == 0.0011
    assert abs(out[3] - 0.001090) < abs(out[2] - 0.001090) / 10



@pytest.mark.parametrize("prior", [1, 2, 3])
@pytest.mark.parametrize("energy_ratio", [0.9, 1.0, 1.1])
def test_report_frame8_closed_form(prior, energy_ratio):
    # one eigenimage holding r times the new frame's energy: F_1 F_2 = r n / (1 + r)^2
    n = 0.005841
    a, b = _pair_with_novelty(n, energy_ratio)
    f = nv.NoveltyFilter(0.0, 0.95)
    for _ in range(prior):
        f.partial_fit(a)
    f.partial_fit(b)
    r = prior / energy_ratio
    f2 = (1 - np.sqrt(1 - 4 * r * n / (1 + r) ** 2)) / 2
    assert float(f.information_fractions_[1]) == pytest.approx(f2, rel=1e-9)


def test_report_frame8_printed_fraction_within_fourth_update_range():
    # the printed 0.001090 lies inside the fourth update's range for energy ratios 0.9-1.1 and
    # outside the third update's
    def f2(prior, ratio):
        a, b = _pair_with_novelty(0.005841, ratio)
        f = nv.NoveltyFilter(0.0, 0.95)
        for _ in range(prior):
            f.partial_fit(a)
        f.partial_fit(b)
        return float(f.information_fractions_[1])
    assert f2(3, 0.9) < 0.001090 < f2(3, 1.1)
    assert not f2(2, 0.9) < 0.001090 < f2(2, 1.1)

def test_report_frame2_vip_numbers():
    # Fig. 2b: the printed V_2 gives the printed n_2 through Eq. (7), and v(1,1) = V_1 / 2 (Eq. 4)
    v = np.array([[36772008.0, 36772052.0], [36772052.0, 36838816.0]])
    assert _novelty_from_vip(v) == pytest.approx(0.001811, abs=5e-7)
    assert 73544016 / 2 == v[0, 0]

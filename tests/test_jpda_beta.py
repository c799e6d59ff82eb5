"""Beta of the JPDA chapter: fast (paper, forward-backward, clustered) versus enumeration."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from projtrack import jpda
from projtrack.jpda import forward_backward as sweep


def _brute_beta(w):
    """Oracle: loop over every assignment target -> {0 (undetected), distinct measurement}."""
    m1, T = w.shape
    out = np.zeros((m1, T))
    Z = 0.0
    for a in itertools.product(range(m1), repeat=T):
        used = [r for r in a if r]
        if len(used) != len(set(used)):
            continue
        p = np.prod([w[r, t] for t, r in enumerate(a)])
        Z += p
        for t, r in enumerate(a):
            out[r, t] += p
    return out / Z


@st.composite
def mvms(draw, max_m=7, max_T=7):
    m = draw(st.integers(0, max_m))
    T = draw(st.integers(1, max_T))
    seed = draw(st.integers(0, 2**32 - 1))
    density = draw(st.floats(0.1, 1.0))
    rng = np.random.default_rng(seed)
    w = rng.uniform(0.01, 1.0, (m + 1, T)) * (rng.random((m + 1, T)) < density)
    w[0] = rng.uniform(0.0, 0.95, T)
    w[0, w[1:].sum(axis=0) == 0] += 0.01  # every target needs a positive-probability event
    return w


def test_small_examples_against_brute_force():
    rng = np.random.default_rng(1)
    for _ in range(20):
        m, T = rng.integers(0, 5), rng.integers(1, 5)
        w = rng.uniform(0.05, 1, (m + 1, T)) * (rng.random((m + 1, T)) < 0.7)
        w[0] = rng.uniform(0.05, 0.9, T)
        ref = _brute_beta(w)
        for f in (jpda.beta, jpda.beta_enumerated, jpda.beta_paper, jpda.beta_forward_backward):
            np.testing.assert_allclose(f(w), ref, atol=1e-13)


@settings(max_examples=120, deadline=None)
@given(mvms())
def test_fast_equals_enumerated(w):
    ref = jpda.beta_enumerated(w)
    for method in ("auto", "forward-backward", "paper"):
        np.testing.assert_allclose(jpda.beta(w, method=method), ref, atol=1e-12, rtol=1e-10)
    np.testing.assert_allclose(jpda.beta_paper(w, store_intermediates=True), ref, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(mvms(), st.integers(0, 2**32 - 1))
def test_columns_sum_to_one_and_permutation_invariance(w, seed):
    b = jpda.beta(w)
    np.testing.assert_allclose(b.sum(axis=0), 1.0, atol=1e-12)
    assert np.all(b >= -1e-15)
    assert np.all(b[1:][w[1:] == 0] == 0)  # beta_jt = 0 outside the gate
    rng = np.random.default_rng(seed)
    pm = np.r_[0, 1 + rng.permutation(w.shape[0] - 1)]
    pt = rng.permutation(w.shape[1])
    np.testing.assert_allclose(jpda.beta(w[pm][:, pt]), b[pm][:, pt], atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(mvms(max_m=6, max_T=6), st.floats(0.01, 100.0))
def test_column_scaling_invariance(w, c):
    w2 = w.copy()
    w2[1:, 0] *= c  # scaling a whole column leaves beta unchanged ...
    w2[0, 0] *= c
    if w2[0, 0] >= 1:
        return
    np.testing.assert_allclose(jpda.beta(w2), jpda.beta(w), atol=1e-12)


def test_target_without_validated_measurement_is_undetected():
    w = np.array([[0.1, 0.3, 0.2], [0.5, 0.0, 0.4], [0.2, 0.0, 0.0]])
    for method in ("auto", "forward-backward", "paper", "enumerate"):
        b = jpda.beta(w, method=method)
        assert b[0, 1] == pytest.approx(1.0, abs=1e-15)
        assert np.all(b[1:, 1] == 0)


def test_single_target_is_pda():
    w = np.array([[0.2], [0.3], [0.5]])
    np.testing.assert_allclose(jpda.beta(w)[:, 0], w[:, 0] / w.sum())


def test_no_measurements_and_no_targets():
    np.testing.assert_array_equal(jpda.beta(np.array([[0.1, 0.4]])), [[1.0, 1.0]])
    assert jpda.beta(np.zeros((3, 0))).shape == (3, 0)
    assert jpda.beta_enumerated(np.zeros((3, 0))).shape == (3, 0)


def test_larger_clustered_problem_matches_paper_method():
    rng = np.random.default_rng(5)
    # two blocks of 6 x 5 and 4 x 6 plus an isolated target: exercises clusters and
    # the high-bit (strided) path of the forward-backward sweep
    w = np.zeros((11, 12))
    w[1:7, :5] = rng.uniform(0.1, 1, (6, 5))
    w[7:11, 5:11] = rng.uniform(0.1, 1, (4, 6))
    w[0] = rng.uniform(0.05, 0.5, 12)
    assert len(jpda.clusters(w)) == 3
    np.testing.assert_allclose(jpda.beta(w), jpda.beta_paper(w), atol=1e-12)
    w9 = np.vstack([rng.uniform(0.05, 0.5, (1, 9)), rng.uniform(0, 1, (10, 9))])
    np.testing.assert_allclose(jpda.beta_forward_backward(w9), jpda.beta_paper(w9), atol=1e-12)
    np.testing.assert_allclose(jpda.beta_forward_backward(w9.T[:, :9].T[:8]),
                               jpda.beta_paper(w9.T[:, :9].T[:8]), atol=1e-12)


def test_p_detect_one_is_allowed_when_feasible():
    w = np.array([[0.0, 0.3], [0.5, 0.2], [0.1, 0.0]])
    np.testing.assert_allclose(jpda.beta(w), jpda.beta_enumerated(w), atol=1e-14)
    assert jpda.beta(w)[0, 0] == 0


@pytest.mark.parametrize("bad,msg", [
    (np.array([[0.1, -0.2], [0.3, 0.4]]), ">= 0"),
    (np.array([[0.1, np.nan], [0.3, 0.4]]), "finite"),
    (np.array([[0.1, np.inf], [0.3, 0.4]]), "finite"),
    (np.array([[1.2, 0.1], [0.3, 0.4]]), "row 0"),
    (np.array([[3.0, 2.0], [0.3, 0.4]]), "row 0 omitted"),
    (np.ones(3) * 0.1, "2-D"),
    (np.zeros((0, 2)), "row 0"),
    (np.array([["a", "b"]]), "numeric"),
])
@pytest.mark.parametrize("f", [jpda.beta, jpda.beta_enumerated, jpda.beta_paper,
                               jpda.beta_forward_backward, jpda.clusters])
def test_bad_mvm(bad, msg, f):
    with pytest.raises((ValueError, TypeError), match=msg):
        f(bad)


def test_infeasible_mvm_raises():
    with pytest.raises(ValueError, match="no validated measurement"):
        jpda.beta(np.array([[0.0, 0.5], [0.0, 0.3]]))
    two_certain_one_meas = np.array([[0.0, 0.0], [0.5, 0.5]])
    for f in (jpda.beta, jpda.beta_enumerated, jpda.beta_paper, jpda.beta_forward_backward):
        with pytest.raises(ValueError, match="feasible"):
            f(two_certain_one_meas)
    with pytest.raises(ValueError, match="method"):
        jpda.beta(np.array([[0.5]]), method="magic")


# --- Tables II-VI ---------------------------------------------------------------------

TABLE_III = {3: [7, 8, 8, 8, 8], 4: [11, 15, 16, 16, 16], 5: [16, 26, 31, 32, 32],
             6: [22, 42, 57, 63, 64], 7: [29, 64, 99, 120, 127]}


def test_table3_vector_sizes():
    for m, row in TABLE_III.items():
        assert [jpda.vector_size(m, T) for T in range(3, 8)] == row
    # the printed max(1, .) formula differs exactly where m < T
    assert jpda.vector_size_text_formula(3, 4) == 7 != jpda.vector_size(3, 4)
    assert jpda.vector_size_text_formula(5, 3) == jpda.vector_size(5, 3)


def test_table2_words_and_expressions():
    rows = jpda.stage_expressions(4, 6)
    assert [r[1] for r in rows] == ["1111", "0111", "1011", "1101", "1110", "0011", "0101",
                                    "0110", "1001", "1010", "1100", "0001", "0010", "0100",
                                    "1000", "0000"]
    assert rows[0][2] == "e0(f1111) + e4(f0111) + e3(f1011) + e2(f1101) + e1(f1110)"
    assert rows[-1][2] == "e0(f0000)"


# Table IV prints 5200/8148 for m = T = 5; Table VI's savings factor there (5.9) implies
# 1045 * 5.9 = 6184 multiplications, the value every other cell's rule N (T - 1) gives.
TABLE_IV = {(3, 3): (54, 68), (3, 7): (882, 2148), (5, 5): (5200, 6184),
            (7, 3): (882, 716), (6, 7): (170100, 225798), (7, 7): (652974, 785532)}
TABLE_V = {(3, 3): (63, 51), (3, 7): (483, 672), (5, 5): (1175, 1045),
           (7, 3): (609, 195), (6, 7): (6006, 6048), (7, 7): (12495, 11655)}


@pytest.mark.parametrize("mT", list(TABLE_IV))
def test_tables4_5_operation_counts(mT):
    m, T = mT
    ops = jpda.OpCount()
    mvm = np.vstack([np.full((1, T), 0.5), np.ones((m, T))])
    if m * T <= 36:
        jpda.beta_enumerated(mvm, ops=ops)
        assert (ops.additions, ops.multiplications) == TABLE_IV[mT]
    c = jpda.conventional_op_count(m, T)
    assert (c.additions, c.multiplications) == TABLE_IV[mT]
    f = jpda.fast_op_count(m, T)
    assert (f.additions, f.multiplications) == TABLE_V[mT]


@pytest.mark.parametrize("m", range(1, 9))
@pytest.mark.parametrize("T", range(2, 9))
def test_fast_additions_follow_table3_rule(m, T):
    """Table V's additions are m T sum_{k=0}^{T-2} V(m - 1, T - k), V the Table III sizes.

    This is the rule that proves the printed 1968 at m = 7, T = 4 a misprint (1988).
    """
    rule = m * T * sum(jpda.vector_size(m - 1, T - k) for k in range(T - 1))
    assert jpda.fast_op_count(m, T).additions == rule
    if (m, T) == (7, 4):
        assert rule == 1988 and 1968 % (m * T) != 0


def test_stored_intermediates_save_more_than_110_multiplications():
    c = jpda.conventional_op_count(7, 7)
    s = jpda.fast_op_count(7, 7, store_intermediates=True)
    assert c.multiplications / s.multiplications > 110


def test_mu_words_and_sizes_bad_inputs():
    with pytest.raises(TypeError):
        jpda.vector_size(2.5, 3)
    with pytest.raises(ValueError):
        jpda.mu_words(-1)
    with pytest.raises(ValueError):
        jpda.mu_words(40)


# --- Fig. 5 ---------------------------------------------------------------------------


@pytest.mark.parametrize("m,T,q", [(4, 6, 4), (4, 6, 2), (5, 3, 1), (3, 3, 1)])
def test_optical_processor_equals_direct_stage(m, T, q):
    rng = np.random.default_rng(m * 10 + q)
    old_words = jpda.mu_words(m, max(0, m - q - 1))
    new_words = jpda.mu_words(m, max(0, m - q))
    vec = rng.random(len(old_words))
    col = rng.random(m + 1)
    sched = jpda.optical_vip_schedule(m, T, q)
    # one product per detector per time slot (frequency multiplexing)
    for s in np.unique(sched[:, 0]):
        d = sched[sched[:, 0] == s, 3]
        assert len(d) == len(np.unique(d))
    direct = jpda.stage_update(vec, new_words, old_words, col)
    optical = jpda.optical_vip_stage(vec, col, sched, len(new_words))
    np.testing.assert_allclose(optical, direct, rtol=1e-14)
    with pytest.raises(ValueError, match="rng"):
        jpda.optical_vip_stage(vec, col, sched, len(new_words), noise_std=0.1)


def test_threaded_backward_sweep_matches_paper_method(monkeypatch):
    rng = np.random.default_rng(9)
    w = np.vstack([rng.uniform(0.05, 0.5, (1, 11)), rng.uniform(0, 1, (12, 11))])
    serial = jpda.beta_forward_backward(w)
    monkeypatch.setattr(sweep, "_THREAD_MIN_BITS", 4)
    threaded = jpda.beta_forward_backward(w)
    np.testing.assert_array_equal(threaded, serial)
    np.testing.assert_allclose(threaded, jpda.beta_paper(w), atol=1e-12)


def test_operation_count_of_the_sweep_is_recorded():
    ops = jpda.OpCount()
    jpda.beta(np.vstack([np.full((1, 7), 0.5), np.ones((7, 7))]), ops=ops)
    assert ops.additions > 0 and ops.multiplications > 0
    assert ops.additions + ops.multiplications < sum(
        (lambda c: (c.additions, c.multiplications))(jpda.conventional_op_count(7, 7)))


def test_analog_noise_model_of_the_stages():
    rng = np.random.default_rng(4)
    w = np.vstack([np.full((1, 5), 0.2), rng.uniform(0.1, 1, (5, 5))])
    exact = jpda.beta_paper(w)
    np.testing.assert_array_equal(jpda.beta_paper(w, vip_noise=0.0), exact)
    small = jpda.beta_paper(w, vip_noise=1e-4, rng=np.random.default_rng(0))
    big = jpda.beta_paper(w, vip_noise=1e-1, rng=np.random.default_rng(0))
    e_small, e_big = np.abs(small - exact).max(), np.abs(big - exact).max()
    assert 0 < e_small < 1e-3 < e_big
    with pytest.raises(TypeError, match="rng"):
        jpda.beta_paper(w, vip_noise=0.1)
    with pytest.raises(ValueError, match="vip_noise"):
        jpda.beta_paper(w, vip_noise=-1.0, rng=rng)


# --- bad inputs of the stage, the Fig. 5 model and the counters ------------------------


def test_stage_update_rejects_missing_predecessor_words():
    # words with >= 3 bits only cannot feed the full word list (e.g. 0000 needs 0000)
    with pytest.raises(ValueError, match="predecessor"):
        jpda.stage_update(np.ones(5), jpda.mu_words(4, 0), jpda.mu_words(4, 3), np.ones(5))
    # a single missing one-bit-fewer word is found too
    prev = jpda.mu_words(4, 2)
    prev = prev[prev != 0b0111]
    with pytest.raises(ValueError, match="0111"):
        jpda.stage_update(np.ones(len(prev)), jpda.mu_words(4, 3), prev, np.ones(5))


@pytest.mark.parametrize("args,exc,msg", [
    ((np.ones(4), jpda.mu_words(4), jpda.mu_words(4), np.ones(5)), ValueError, "vec must have"),
    ((np.ones(16), jpda.mu_words(4), jpda.mu_words(4), np.ones(4)), ValueError, "3-bit words"),
    ((np.ones(16), jpda.mu_words(4), jpda.mu_words(4), np.ones(0)), ValueError, "p_0"),
    ((np.ones(16), jpda.mu_words(4), jpda.mu_words(4), np.ones((5, 1))), ValueError, "column"),
    ((np.ones(16), jpda.mu_words(4) + 0.5, jpda.mu_words(4), np.ones(5)), TypeError, "words"),
    ((np.ones(16), jpda.mu_words(4), np.r_[jpda.mu_words(4)[:-1], 1], np.ones(5)),
     ValueError, "repeat"),
    ((np.full(16, np.nan), jpda.mu_words(4), jpda.mu_words(4), np.ones(5)), ValueError, "finite"),
])
def test_stage_update_bad_inputs(args, exc, msg):
    with pytest.raises(exc, match=msg):
        jpda.stage_update(*args)


def test_stage_update_valid_subsets_still_work():
    # the stage of beta_paper: new words of >= m - q bits from old words of >= m - q - 1
    rng = np.random.default_rng(3)
    old, new = jpda.mu_words(5, 2), jpda.mu_words(5, 3)
    vec, col = rng.random(len(old)), rng.random(6)
    out = jpda.stage_update(vec, new, old, col)
    pos = {int(w): i for i, w in enumerate(old)}
    ref = [col[0] * vec[pos[int(w)]] + sum(col[j + 1] * vec[pos[int(w) ^ (1 << j)]]
                                           for j in range(5) if (w >> j) & 1) for w in new]
    np.testing.assert_allclose(out, ref, rtol=1e-14)


def test_optical_vip_bad_inputs():
    sched = jpda.optical_vip_schedule(4, 6, 4)
    vec, col = np.ones(16), np.ones(5)
    with pytest.raises(ValueError, match="vec has only 3"):
        jpda.optical_vip_stage(np.ones(3), col, sched, 16)
    with pytest.raises(ValueError, match="column has only 2"):
        jpda.optical_vip_stage(vec, np.ones(2), sched, 16)
    with pytest.raises(ValueError, match="n_out has only 4"):
        jpda.optical_vip_stage(vec, col, sched, 4)
    with pytest.raises(ValueError, match="schedule must be an"):
        jpda.optical_vip_stage(vec, col, sched[:, :3], 16)
    with pytest.raises(ValueError, match="noise_std"):
        jpda.optical_vip_stage(vec, col, sched, 16, noise_std=-1.0)
    with pytest.raises(ValueError, match="vec must be a 1-D"):
        jpda.optical_vip_stage(np.ones((4, 4)), col, sched, 16)
    with pytest.raises(ValueError, match="rng"):  # noise needs a generator
        jpda.optical_vip_stage(vec, col, sched, 16, noise_std=0.1)
    with pytest.raises(TypeError, match="rng"):  # a legacy RandomState is the wrong kind
        jpda.optical_vip_stage(vec, col, sched, 16, noise_std=0.1, rng=np.random.RandomState(0))
    for bad_q in (0, 5, 7):
        with pytest.raises(ValueError, match="q must lie"):
            jpda.optical_vip_schedule(4, 6, bad_q)
    with pytest.raises(ValueError, match="T must be >= 3"):
        jpda.optical_vip_schedule(4, 2, 1)
    with pytest.raises(ValueError, match="m must be an int >= 1"):
        jpda.optical_vip_schedule(0, 6, 1)
    with pytest.raises(ValueError, match="q must be an int >= 0"):
        jpda.optical_vip_schedule(4, 6, -1)


def test_counters_and_sizes_name_the_bad_argument():
    with pytest.raises(ValueError, match="m must be an int >= 0"):
        jpda.fast_op_count(-1, 3)
    with pytest.raises(ValueError, match="T must be an int >= 0"):
        jpda.fast_op_count(3, -2)
    with pytest.raises(TypeError, match="T must be an int"):
        jpda.fast_op_count(3, 2.0)
    with pytest.raises(ValueError, match="m must be an int <= 22"):
        jpda.fast_op_count(23, 2)
    with pytest.raises(TypeError, match="store_intermediates"):
        jpda.fast_op_count(3, 3, store_intermediates="yes")
    for f in (jpda.vector_size, jpda.vector_size_text_formula):
        with pytest.raises(ValueError, match="T must be an int >= 1"):
            f(0, 0)
        with pytest.raises(ValueError, match="T must be an int >= 1"):
            f(4, 0)
        with pytest.raises(ValueError, match="m must be an int <= 30"):
            f(31, 2)
    assert jpda.vector_size(0, 1) == 1  # no measurement: only the empty word


# --- the forward-backward sweep: fast path against the plain reference ----------------


def _sweep_inputs(seed, n_it, n, density=0.6):
    rng = np.random.default_rng(seed)
    W = rng.uniform(0.05, 1.0, (n_it, n)) * (rng.random((n_it, n)) < density)
    return W, rng.uniform(0.05, 1.0, n_it), rng.uniform(0.05, 1.0, n)


def _brute_sweep(W, u, v):
    """Oracle for the sweep: enumerate every partial matching of items to slots."""
    n_it, n = W.shape
    Z, gW, gu, un = 0.0, np.zeros_like(W), np.zeros(n_it), np.zeros(n)
    for a in itertools.product(range(-1, n), repeat=n_it):
        used = [k for k in a if k >= 0]
        if len(used) != len(set(used)) or any(k >= 0 and W[i, k] == 0 for i, k in enumerate(a)):
            continue
        p = np.prod([u[i] if k < 0 else W[i, k] for i, k in enumerate(a)])
        p *= np.prod([v[k] for k in range(n) if k not in used])
        Z += p
        for i, k in enumerate(a):
            if k < 0:
                gu[i] += p
            else:
                gW[i, k] += p
        for k in range(n):
            if k not in used:
                un[k] += p
    return Z, gW, gu, un


@pytest.mark.parametrize("n_it,n", [(0, 0), (3, 0), (0, 3), (1, 1), (3, 4), (5, 3), (4, 5)])
def test_reference_sweep_equals_brute_force(n_it, n):
    W, u, v = _sweep_inputs(n_it * 7 + n, n_it, n)
    for got, want in zip(sweep._fb_sweep_reference(W, u, v), _brute_sweep(W, u, v)):
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-300)


PATHS = {
    "default": {},
    "dense low bits only": {"_LOW_BITS": 30},
    "sparse high bits": {"_LOW_BITS": 2},
    "strided high bits": {"_LOW_BITS": 2, "_SPARSE_MAX_HIGH_BITS": 0},
    "threaded backward": {"_LOW_BITS": 3, "_THREAD_MIN_BITS": 1},
}


@pytest.mark.parametrize("path", list(PATHS))
@pytest.mark.parametrize("n_it,n,seed", [(1, 1, 0), (4, 3, 1), (7, 6, 2), (9, 9, 3), (6, 10, 4)])
def test_fast_sweep_equals_reference_on_every_path(monkeypatch, path, n_it, n, seed):
    for name, value in PATHS[path].items():
        monkeypatch.setattr(sweep, name, value)
    W, u, v = _sweep_inputs(seed, n_it, n)
    ops_fast, ops_ref = jpda.OpCount(), jpda.OpCount()
    fast = sweep._fb_sweep(W, u, v, ops_fast)
    ref = sweep._fb_sweep_reference(W, u, v, ops_ref)
    for got, want in zip(fast, ref):
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-300)
    assert (ops_fast.additions, ops_fast.multiplications) == (ops_ref.additions, ops_ref.multiplications)


@settings(max_examples=60, deadline=None)
@given(mvms())
def test_beta_forward_backward_reference_flag(w):
    np.testing.assert_allclose(jpda.beta_forward_backward(w, reference=True),
                               jpda.beta_enumerated(w), atol=1e-12)
    np.testing.assert_allclose(jpda.beta_forward_backward(w, reference=True),
                               jpda.beta_forward_backward(w), atol=1e-13)


def test_beta_forward_backward_reference_must_be_bool():
    with pytest.raises(TypeError, match="reference must be a bool"):
        jpda.beta_forward_backward(np.array([[0.5], [1.0]]), reference="yes")


@pytest.mark.parametrize("mT", [(1, 1), (3, 3), (4, 6), (7, 7), (5, 2)])
def test_conventional_op_count_closed_forms(mT):
    m, T = mT
    c = jpda.conventional_op_count(m, T)
    N = jpda.count_feasible_events
    assert c.multiplications == N(m, T) * (T - 1)
    assert c.additions == m * T * (N(m - 1, T - 1) - 1)


def test_without_numba_large_sweeps_use_the_numpy_sweep(monkeypatch):
    """With numba missing, a sweep above the compiled kernel's threshold runs the numpy sweep,
    which must equal the plain reference recursions (this test runs with or without numba)."""
    from projtrack.jpda import _kernel
    from projtrack.jpda import forward_backward as fbm

    monkeypatch.setattr(_kernel, "_HAVE_NUMBA", False)
    rng = np.random.default_rng(5)
    W = rng.random((10, 10)) * (rng.random((10, 10)) < 0.7)
    u, v = rng.random(10) + 0.1, rng.random(10) + 0.1
    called = []
    monkeypatch.setattr(_kernel, "fb_sweep", lambda *a, **k: called.append(1))
    got = fbm._fb_core(W, u, v)
    want = fbm._fb_sweep_reference(W, u, v)
    assert not called
    assert abs(got[0] - want[0]) <= 1e-12 * want[0]
    for g, r in zip(got[1:], want[1:]):
        np.testing.assert_allclose(g, r, rtol=1e-12, atol=1e-300)

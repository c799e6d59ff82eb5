"""The compiled forward-backward sweep (projtrack.jpda._kernel) against the numpy sweeps and enumeration."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack import jpda
from projtrack.jpda import _kernel as _fast_jpda
from projtrack.jpda import forward_backward as fbm

pytestmark = pytest.mark.skipif(not _fast_jpda._HAVE_NUMBA, reason="numba is not installed")


def _rel(a, b):
    a, b = np.atleast_1d(np.asarray(a, float)), np.atleast_1d(np.asarray(b, float))
    assert a.shape == b.shape
    if a.size == 0:
        return 0.0
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


def _problem(rng, n_it, n, density=1.0):
    W = rng.uniform(0.05, 1.0, (n_it, n)) * (rng.uniform(size=(n_it, n)) < density)
    return W, rng.uniform(0.1, 1.0, n_it), rng.uniform(0.1, 1.0, n)


# every code path: one bit, two bits (no in-block strided bits), blocks of 2, 4 and 16
# states (high bits), all forward messages kept or checkpoints with recomputed segments
CASES = [(1, 1, None, None), (3, 1, None, None), (2, 2, None, None), (4, 3, 2, None),
         (5, 5, 2, 0), (7, 6, 3, None), (6, 8, 4, 0), (9, 7, 2, 0), (12, 9, 4, 0),
         (3, 10, 3, 0), (10, 10, None, None)]


@pytest.mark.parametrize("n_it,n,low_bits,store", CASES)
@pytest.mark.parametrize("density,parallel", [(1.0, False), (0.6, True)])
def test_sweep_matches_reference(n_it, n, low_bits, store, density, parallel):
    rng = np.random.default_rng(100 * n_it + n)
    W, u, v = _problem(rng, n_it, n, density)
    ops_fast, ops_ref = jpda.OpCount(), jpda.OpCount()
    got = _fast_jpda.fb_sweep(W, u, v, ops_fast, low_bits=low_bits, store_all_bytes=store,
                              parallel=parallel)
    ref = fbm._fb_sweep_reference(W, u, v, ops_ref)
    for g, r in zip(got, ref):
        assert _rel(g, r) < 1e-12
    assert (ops_fast.additions, ops_fast.multiplications) == (ops_ref.additions, ops_ref.multiplications)


def test_sweep_zero_rows_and_columns():
    rng = np.random.default_rng(5)
    W, u, v = _problem(rng, 6, 9)
    W[2] = 0.0
    W[:, 4] = 0.0
    got = _fast_jpda.fb_sweep(W, u, v, low_bits=2, store_all_bytes=0)
    again = _fast_jpda.fb_sweep(W, u, v, low_bits=2, store_all_bytes=0, parallel=True)
    for g, a in zip(got, again):  # fixed chunks: the same sums with and without threads
        np.testing.assert_array_equal(g, a)
    for g, r in zip(got, fbm._fb_sweep_reference(W, u, v)):
        assert _rel(g, r) < 1e-12
    assert np.all(got[1][2] == 0) and np.all(got[1][:, 4] == 0)


def _mvm(rng, m, T, density=1.0):
    mvm = rng.uniform(0.05, 1.0, (m + 1, T))
    mvm[1:] *= rng.uniform(size=(m, T)) < density
    mvm[0] = rng.uniform(0.05, 0.5, T)
    return mvm


@pytest.mark.parametrize("m,T", [(3, 3), (4, 2), (2, 5), (5, 4)])
def test_beta_matches_enumeration(monkeypatch, m, T):
    monkeypatch.setattr(fbm, "_FAST_MIN_SLOTS", 1)
    mvm = _mvm(np.random.default_rng(m * 10 + T), m, T, 0.8)
    want = jpda.beta_enumerated(mvm)
    got = jpda.beta_forward_backward(mvm)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)


def test_beta_at_16_matches_numpy_sweep(monkeypatch):
    mvm = _mvm(np.random.default_rng(16), 16, 16)
    monkeypatch.setenv("PROJTRACK_NO_NUMBA", "0")
    got = jpda.beta_forward_backward(mvm)
    monkeypatch.setenv("PROJTRACK_NO_NUMBA", "1")
    want = jpda.beta_forward_backward(mvm)
    assert _rel(got, want) < 1e-12


@pytest.mark.parametrize("m,T", [(9, 11), (12, 8)])
def test_beta_both_paths_rectangular(monkeypatch, m, T):
    mvm = _mvm(np.random.default_rng(m + T), m, T, 0.7)
    monkeypatch.setenv("PROJTRACK_NO_NUMBA", "1")
    want = jpda.beta_forward_backward(mvm)
    monkeypatch.delenv("PROJTRACK_NO_NUMBA")
    got = jpda.beta_forward_backward(mvm)
    assert _rel(got, want) < 1e-12
    np.testing.assert_allclose(got.sum(axis=0), 1.0, rtol=1e-12)  # columns are distributions


def test_numba_switch(monkeypatch):
    monkeypatch.setenv("PROJTRACK_NO_NUMBA", "1")
    assert not _fast_jpda.numba_enabled()
    monkeypatch.delenv("PROJTRACK_NO_NUMBA")
    assert _fast_jpda.numba_enabled()


def test_without_numba_the_numpy_sweep_runs(monkeypatch):
    monkeypatch.setattr(_fast_jpda, "_HAVE_NUMBA", False)
    assert not _fast_jpda.numba_enabled()
    mvm = _mvm(np.random.default_rng(3), 9, 9)
    with pytest.raises(RuntimeError):
        _fast_jpda.fb_sweep(mvm[1:], np.ones(9), mvm[0])
    want = jpda.beta_forward_backward(mvm)  # dispatches to the numpy sweep
    monkeypatch.setattr(_fast_jpda, "_HAVE_NUMBA", True)
    assert _rel(jpda.beta_forward_backward(mvm), want) < 1e-12


def test_threads_give_identical_results_at_threaded_size():
    # from _PARALLEL_MIN_SLOTS slots on the sweep runs on two threads by default: the chunks
    # and their order of summation are fixed, so the numbers are the same bit for bit
    rng = np.random.default_rng(18)
    W, u, v = _problem(rng, 20, _fast_jpda._PARALLEL_MIN_SLOTS, 0.9)
    one = _fast_jpda.fb_sweep(W, u, v, parallel=False, store_all_bytes=0)
    two = _fast_jpda.fb_sweep(W, u, v, parallel=True, store_all_bytes=0)
    for a, b in zip(one, two):
        np.testing.assert_array_equal(a, b)
    for a, b in zip(two, fbm._fb_sweep(W, u, v)):  # the threaded in-place steps are right
        assert _rel(a, b) < 1e-12


@pytest.mark.parametrize("n_it", [1, 2, 5, 24, 100])
def test_schedule_covers_every_item_within_its_buffers(n_it):
    cost = np.linspace(0.1, 1.0, n_it)
    starts = _fast_jpda._schedule(n_it, cost)
    assert starts[0] == 0 and starts == sorted(set(starts)) and starts[-1] < n_it
    lengths = np.diff(starts + [n_it])
    # segment j is recomputed while the j checkpoints before it are kept: the peak number of
    # messages (j checkpoints, the segment, the backward message) stays near sqrt(2 n_it)
    peak = max(j + length + (j == 0) for j, length in enumerate(lengths))
    peak = max(peak, len(starts) + 1)  # forward sweep: checkpoints and two scratch buffers
    assert peak <= max(5, int(np.ceil(np.sqrt(2 * n_it))) + 4)


@pytest.mark.parametrize("n_it,n,store", [(4, 9, None), (6, 8, 0), (12, 7, 0)])
def test_blocks_beyond_the_support_are_never_read(monkeypatch, n_it, n, store):
    # message buffers are taken uninitialized (or from an earlier sweep): fill them with NaN,
    # which would reach the result if a block outside the support of a message were read
    monkeypatch.setattr(_fast_jpda, "_take", lambda N: np.full(N, np.nan))
    rng = np.random.default_rng(n_it + n)
    W, u, v = _problem(rng, n_it, n)
    got = _fast_jpda.fb_sweep(W, u, v, low_bits=2, store_all_bytes=store)
    for g, r in zip(got, fbm._fb_sweep_reference(W, u, v)):
        assert _rel(g, r) < 1e-12

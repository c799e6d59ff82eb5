"""The voting kernel of projtrack.hough._kernel gives exactly the votes of the original voting code."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack.hough import _kernel as _fast_hough
from projtrack.hough import hough_axes, hough_transform, thresholded_hough_transform

needs_numba = pytest.mark.skipif(not _fast_hough._HAVE_NUMBA, reason="numba is not installed")


def _vote_original(pts, cx, cy, rho0, n_rho, thetas_deg, drho, weights=None):
    """The voting code of projtrack.hough before the kernel (kept verbatim as the reference)."""
    n_theta = thetas_deg.size
    if pts.shape[0] == 0:
        return np.zeros((n_rho, n_theta))
    t = np.deg2rad(thetas_deg)
    rho = (pts[:, 0:1] - cx) * np.cos(t) + (pts[:, 1:2] - cy) * np.sin(t)
    idx = np.floor(np.round((rho - rho0) / drho, 9) + 0.5).astype(np.int64)
    np.clip(idx, 0, n_rho - 1, out=idx)
    flat = idx * n_theta + np.arange(n_theta)
    w = None if weights is None else np.repeat(weights[:, None], n_theta, axis=1).ravel()
    acc = np.bincount(flat.ravel(), weights=w, minlength=n_rho * n_theta)
    return acc.reshape(n_rho, n_theta).astype(float)


def _point_sets(rng):
    """Random integer pixels, random real points, and points on exact ties at 30/60/120/150 deg."""
    yield rng.integers(0, 256, (300, 2)).astype(float), (256, 256)
    yield rng.uniform(0, 100, (200, 2)), (100, 130)
    # x - cx and y - cy on a lattice where rho / drho is a half-integer at 30, 60, 120, 150
    # degrees (cos 60 = 1/2): ties in every one of those columns
    g = np.arange(0, 256, 1.0)
    yield np.array([(x, 128.0) for x in g] + [(128.0, y) for y in g]), (256, 256)
    yield np.array([(x, y) for x in range(0, 64, 3) for y in range(0, 64, 5)], float), (64, 64)
    yield np.zeros((0, 2)), (32, 32)


@pytest.mark.parametrize("use_numba", [False, pytest.param(True, marks=needs_numba)])
@pytest.mark.parametrize("drho,dtheta,origin", [(2.0, 1.0, "center"), (1.0, 1.0, "corner"),
                                                (1.5, 2.5, "center"), (0.5, 7.5, "corner")])
def test_vote_equals_original_cell_for_cell(use_numba, drho, dtheta, origin):
    rng = np.random.default_rng(7)
    for pts, shape in _point_sets(rng):
        rhos, thetas = hough_axes(shape, drho, dtheta, origin)
        h, w = shape
        cx, cy = (w / 2.0, h / 2.0) if origin == "center" else (0.0, 0.0)
        args = (pts, cx, cy, float(rhos[0]), rhos.size, thetas, drho)
        ref = _vote_original(*args)
        got = _fast_hough.vote(*args, use_numba=use_numba)
        assert got.dtype == ref.dtype and got.shape == ref.shape
        np.testing.assert_array_equal(got, ref)
        wts = rng.uniform(0.1, 3.0, pts.shape[0])
        np.testing.assert_array_equal(_fast_hough.vote(*args, wts, use_numba=use_numba),
                                      _vote_original(*args, wts))


def test_ties_are_present_in_the_test_points():
    """The tie lattice does put points on bin boundaries (otherwise the test above is weaker)."""
    pts = np.array([(x, 128.0) for x in np.arange(0, 256, 1.0)])
    t = np.deg2rad(60.0)
    q = ((pts[:, 0] - 128.0) * np.cos(t) + 0.0 * np.sin(t) + 182.0) / 2.0
    assert np.any(np.abs(np.round(q, 9) % 1.0 - 0.5) < 1e-12)


def test_hough_transform_unchanged_on_both_paths(monkeypatch):
    rng = np.random.default_rng(3)
    pts = rng.integers(0, 256, (150, 2)).astype(float)
    rhos, thetas = hough_axes((256, 256))
    ref = _vote_original(pts, 128.0, 128.0, float(rhos[0]), rhos.size, thetas, 2.0)
    for flag in ("1", "0"):
        monkeypatch.setenv("PROJTRACK_NO_NUMBA", flag)
        H, _, _ = hough_transform(pts, (256, 256))
        np.testing.assert_array_equal(H, ref)
        frames = [pts[:50], pts[50:], np.zeros((0, 2))]
        Ht, _, _ = thresholded_hough_transform(frames, (256, 256))
        exp = sum(_vote_original(f, 128.0, 128.0, float(rhos[0]), rhos.size, thetas, 2.0) >= 1
                  for f in frames)
        np.testing.assert_array_equal(Ht, exp)


def test_numba_switch(monkeypatch):
    monkeypatch.setenv("PROJTRACK_NO_NUMBA", "1")
    assert not _fast_hough.numba_enabled()
    monkeypatch.delenv("PROJTRACK_NO_NUMBA")
    assert _fast_hough.numba_enabled() == _fast_hough._HAVE_NUMBA

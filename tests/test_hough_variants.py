"""Tests of the two departures from the paper's rules used in the book's Hough chapter.

The ridge-free neighbourhood of the peak detector (``exclude_ridge``) and the
all-points stopping rule of the projection procedure (``stop_fraction``).
"""

from __future__ import annotations

import numpy as np
import pytest

from projtrack.hough import (
    TrackInitiator, detect_peaks, estimate_track, hough_transform, local_average,
    project_and_correlate,
)
from projtrack.experiments.hough import accuracy_experiment


def _ideal_line_plane(bias: float = 0.0):
    pts = np.column_stack([np.full(21, 128.0), 60 + 5.0 * np.arange(21)])  # rho = 0, theta = 0
    H, rhos, thetas = hough_transform(pts, (256, 256))
    return H + bias, rhos, thetas


def test_ideal_line_ratio_is_exactly_five():
    H, rhos, thetas = _ideal_line_plane()
    i, j = np.unravel_index(np.argmax(H), H.shape)
    A = local_average(H, 5, rhos=rhos, thetas_deg=thetas)
    assert H[i, j] == 21 and H[i, j] / A[i, j] == pytest.approx(5.0)


def test_ridge_free_average_of_a_constant_plane_is_the_constant():
    H = np.full((40, 30), 3.0)
    A = local_average(H, 5, exclude_ridge=1)
    assert np.allclose(A[2:-2, 2:-2], 3.0)
    assert np.allclose(local_average(H, 5, exclude_ridge=0)[2:-2, 2:-2], 3.0)


def test_ridge_free_average_ignores_the_ridge_rows():
    H = np.zeros((40, 30))
    H[20, :] = 50.0  # a ridge along theta at one rho
    A = local_average(H, 5, exclude_ridge=1)
    full = local_average(H, 5)
    assert np.allclose(A[20, 2:-2], 0.0)  # the ridge itself is left out
    assert np.allclose(full[20, 2:-2], 10.0)  # the paper's window sees 5 of its 25 cells
    assert np.allclose(A[22, 2:-2], 50.0 / 2)  # two rows away the ridge is one of the two kept rows


def test_biased_plane_defeats_the_printed_rule_but_not_the_ridge_free_one():
    H, rhos, thetas = _ideal_line_plane(bias=5.0)  # 26 / (21/5 + 5) = 2.83 < 3
    assert detect_peaks(H, rhos, thetas, min_votes=6) == []
    peaks = detect_peaks(H, rhos, thetas, min_votes=11, exclude_ridge=1)
    assert len(peaks) == 1
    p = peaks[0]
    assert abs(p.rho) <= 2.0 and min(p.theta_deg, 180.0 - p.theta_deg) <= 2.0


@pytest.mark.parametrize("bad", [2, -1, True, 1.0, "1"])
def test_bad_exclude_ridge(bad):
    H = np.ones((20, 20))
    with pytest.raises(ValueError, match="exclude_ridge"):
        local_average(H, 5, exclude_ridge=bad)


@pytest.mark.parametrize("bad", [2, -1, True, 0.5])
def test_initiator_rejects_bad_exclude_ridge(bad):
    with pytest.raises(ValueError, match="exclude_ridge"):
        TrackInitiator(exclude_ridge=bad)


def test_all_points_stop_reaches_the_newest_sample():
    P = np.zeros(16, dtype=int)
    P[:8] = 1  # eight ones, a gap of two samples, then the two newest ones
    P[[10, 11]] = 1
    paper = project_and_correlate(P)
    assert (paper.dx, paper.I, paper.L, paper.j) == (1, 8.0, 8, 7)  # 80 %: stops on the older run
    assert paper.x_prime == pytest.approx(7.5)
    allp = project_and_correlate(P, stop_fraction=1.0)
    assert (allp.dx, allp.I, allp.L, allp.j) == (4, 10.0, 3, 2)
    assert allp.x_prime == pytest.approx(4 * (2 + 1.5 * 3 / 10))  # Eq. (5) on the run holding every point
    assert allp.confirmed and paper.confirmed
    assert allp.x_prime > 9.0 > paper.x_prime


def test_stop_fraction_none_is_the_paper_rule():
    P = np.zeros(32, dtype=int)
    P[[1, 3, 6, 9, 30]] = 1
    assert project_and_correlate(P, stop_fraction=None) == project_and_correlate(P)


@pytest.mark.parametrize("bad", [0.0, 1.5, -0.2, True, "1"])
def test_bad_stop_fraction(bad):
    with pytest.raises(ValueError, match="stop_fraction"):
        project_and_correlate(np.ones(5), stop_fraction=bad)
    with pytest.raises(ValueError, match="stop_fraction"):
        estimate_track(np.array([[128.0, 100.0], [128.0, 110.0]]), (256, 256), 0.0, 0.0, frame_time=0.25,
                       n_frames=2, stop_fraction=bad)


def test_accuracy_experiment_reports_targets_leaving_and_frames_seen():
    r = accuracy_experiment(np.random.default_rng(3), 30.0, 0.25, n_targets=4, return_errors=True, stop_fraction=1.0)
    assert r["n_seen"].shape == (4,) and np.all((r["n_seen"] >= 1) & (r["n_seen"] <= r["n_p"]))
    assert r["n_left"] == int(np.sum(r["n_seen"] < r["n_p"]))
    assert r["errors"].shape == (4, 4) and np.all(np.isfinite(r["errors"]))

"""Tests of projtrack.correlators (Casasent & Song, optical projection correlations)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from projtrack import correlators as C
from projtrack.scenes import letters

LATTICE = [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0, -45.0, 360.0]

images = st.tuples(st.integers(1, 9), st.integers(1, 9)).flatmap(
    lambda s: arrays(np.float64, s, elements=st.floats(-5, 5, allow_nan=False, width=64)))


# ----------------------------------------------------------------------- projections
def brute_project(image: np.ndarray, theta: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact lattice binning by explicit dictionary accumulation on r (oracle)."""
    H, W = image.shape
    t = np.deg2rad(theta)
    acc: dict[float, float] = {}
    for i in range(H):
        for j in range(W):
            r = round((j - (W - 1) / 2) * np.cos(t) + ((H - 1) / 2 - i) * np.sin(t), 6)
            acc[r] = acc.get(r, 0.0) + image[i, j]
    keys = sorted(acc)
    return np.array(keys), np.array([acc[k] for k in keys])


@pytest.mark.parametrize("theta", [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0, -90.0])
def test_project_matches_bruteforce_lattice(theta):
    rng = np.random.default_rng(1)
    img = rng.normal(size=(5, 7))
    p, r = C.project(img, theta, return_r=True)
    r_bf, p_bf = brute_project(img, theta)
    assert np.allclose(r, r_bf, atol=1e-9)
    assert np.allclose(p, p_bf, atol=1e-12)


def test_project_known_values_and_orientation():
    img = np.arange(12.0).reshape(3, 4)
    assert np.array_equal(C.project(img, 0), img.sum(axis=0))  # vertical integration: function of x
    assert np.array_equal(C.project(img, 90), img.sum(axis=1)[::-1])  # bottom row first (y up)
    assert np.array_equal(C.project(img, 180), img.sum(axis=0)[::-1])
    p45 = C.project(img, 45)
    assert len(p45) == 3 + 4 - 1
    # theta = 45: r along (1, 1)/sqrt2 with y up: the bottom-left pixel has the smallest r
    assert p45[0] == img[2, 0] and p45[-1] == img[0, 3]


def test_projection_axis_spacing_and_centre():
    r0 = C.projection_axis((4, 6), 0)
    assert np.allclose(np.diff(r0), 1.0) and np.isclose(r0.mean(), 0.0)
    r45 = C.projection_axis((5, 5), 45)
    assert np.allclose(np.diff(r45), 1 / np.sqrt(2)) and np.isclose(r45[len(r45) // 2], 0.0)
    r30 = C.projection_axis((5, 5), 30)
    assert np.allclose(np.diff(r30), 1.0) and np.allclose(r30, np.round(r30))


@settings(max_examples=40, deadline=None)
@given(images, st.floats(-360, 360, allow_nan=False))
def test_project_preserves_sum(img, theta):
    assert np.isclose(C.project(img, theta).sum(), img.sum(), atol=1e-9 * (1 + np.abs(img).sum()))


def test_project_stack_equals_loop():
    rng = np.random.default_rng(2)
    stack = rng.normal(size=(4, 6, 5))
    for t in (0, 45, 90, 180, 270, 33.3):
        assert np.allclose(C.project_stack(stack, t), [C.project(s, t) for s in stack])


@pytest.mark.parametrize("theta", [0.0, 45.0, 90.0, 135.0])
def test_central_slice_theorem_exact_on_lattice(theta):
    rng = np.random.default_rng(3)
    img = rng.normal(size=(6, 9))
    rho = np.linspace(-0.7, 0.7, 29)
    assert np.allclose(C.projection_spectrum(img, theta, rho), C.fourier_slice(img, theta, rho), atol=1e-10)


def test_fourier_slice_matches_fft2_at_zero_angle():
    rng = np.random.default_rng(4)
    img = rng.normal(size=(8, 8))
    rho = np.fft.fftfreq(8)
    # F(u, 0) of the centred image = fft2 row 0 times the phase of the centre shift
    expected = np.fft.fft2(img)[0] * np.exp(2j * np.pi * rho * 3.5)
    assert np.allclose(C.fourier_slice(img, 0, rho), expected)


# ---------------------------------------------------------------------- correlations
def test_correlate2d_matches_direct_oracle():
    rng = np.random.default_rng(5)
    f, g = rng.normal(size=(7, 5)), rng.normal(size=(3, 4))
    assert np.allclose(C.correlate2d(f, g), scipy.signal.correlate2d(f, g, mode="full"))


def test_correlate1d_matches_numpy():
    rng = np.random.default_rng(6)
    f, g = rng.normal(size=11), rng.normal(size=4)
    assert np.allclose(C.correlate1d(f, g), np.correlate(f, g, mode="full"))


@settings(max_examples=60, deadline=None)
@given(images, images, st.sampled_from(LATTICE))
def test_projection_correlation_equals_integrated_on_lattice(f, g, theta):
    """Eq. (3): projection correlation == projection of the bipolar 2-D correlation."""
    a = C.projection_correlation(f, g, theta)
    b = C.project(C.correlate2d(f, g), theta)
    scale = 1.0 + np.abs(f).sum() * np.abs(g).sum()
    assert a.shape == b.shape
    assert np.max(np.abs(a - b)) <= 1e-10 * scale


@pytest.mark.parametrize("theta", [10.0, 30.0, 60.0, 100.0, 157.0])
def test_projection_correlation_tolerance_off_lattice_letters(theta):
    c = C.zero_mean(letters.render_letter("C"))
    p = C.zero_mean(letters.render_letter("P"))
    a, ra = C.projection_correlation(c, p, theta, return_r=True)
    b, rb = C.project(C.correlate2d(c, p), theta, return_r=True)
    assert np.array_equal(ra, rb)
    assert np.max(np.abs(a - b)) <= 0.15 * np.max(np.abs(b))


def test_shifted_input_shifts_peak():
    img = letters.render_letter("K")
    shifted = np.roll(np.roll(img, 3, axis=0), -5, axis=1)  # down 3 rows, left 5 columns
    c = C.correlate2d(shifted, img)
    p, q = np.unravel_index(np.argmax(c), c.shape)
    assert (p - 31, q - 31) == (3, -5)
    pv, rv = C.projection_correlation(shifted, img, 0, return_r=True)
    ph, rh = C.projection_correlation(shifted, img, 90, return_r=True)
    assert rv[np.argmax(pv)] == -5.0  # x shift
    assert rh[np.argmax(ph)] == -3.0  # y is up: moving down is negative r


def test_autocorrelation_peak_is_pixel_count():
    img = letters.render_letter("C")
    assert np.isclose(C.correlate2d(img, img).max(), img.sum())
    v = C.projection_correlation(img, img, 0)
    assert np.isclose(v.max(), np.sum(img.sum(axis=0) ** 2))


# -------------------------------------------------------------------------- measures
def test_psr_known_plane():
    plane = np.ones((21, 21))
    plane[10, 10] = 9.0
    assert np.isclose(C.psr(plane), 9.0)
    plane[5:16, 5:16] += 1.0  # window mean (excluding the peak) becomes 2
    plane[10, 10] = 10.0
    assert np.isclose(C.psr(plane), 5.0)
    assert np.isclose(C.psr(np.array([0.0, 2.0, 8.0, 2.0, 0.0]), window=5), 8.0 / 1.0)


def test_psr_window_clipped_at_edge():
    plane = np.zeros(10)
    plane[0], plane[1:6] = 6.0, 1.0
    assert np.isclose(C.psr(plane, window=11), 6.0 / 1.0)


def test_psr_rejects_even_and_bad_windows():
    plane = np.zeros(21)
    plane[8:13] = 0.5
    plane[10] = 2.0
    for w in (2, 4, 10):
        with pytest.raises(ValueError, match="odd"):
            C.psr(plane, window=w)
        with pytest.raises(ValueError, match="odd"):
            C.peak_stats(plane, window=w, exclude=None)
    with pytest.raises(ValueError, match=">= 1"):
        C.psr(plane, window=0)
    with pytest.raises(TypeError, match="int"):
        C.psr(plane, window=5.0)
    with pytest.raises(TypeError, match="int"):
        C.psr(plane, window=True)


def test_psr_odd_window_is_symmetric_about_the_peak():
    # a symmetric plane and its mirror image have the same PSR for every odd window
    rng = np.random.default_rng(3)
    half = rng.uniform(0.0, 1.0, size=12)
    plane = np.concatenate([half, [5.0], half[::-1] + 0.3])
    for w in (3, 5, 9, 21):
        assert np.isclose(C.psr(plane, window=w), C.psr(plane[::-1], window=w))


def test_snr_even_exclusion_region_is_documented_asymmetric():
    # exclude=4 removes lags -2..+1 around the peak; exclude=5 removes -2..+2
    plane = np.zeros(21)
    plane[10] = 10.0
    plane[[8, 9, 11, 12]] = 1.0
    plane[0] = -1.0
    rest4 = np.delete(plane, [8, 9, 10, 11])
    rest5 = np.delete(plane, [8, 9, 10, 11, 12])
    assert np.isclose(C.snr(plane, exclude=4), 10.0 / rest4.std())
    assert np.isclose(C.snr(plane, exclude=5), 10.0 / rest5.std())
    with pytest.raises(ValueError, match=">= 1"):
        C.snr(plane, exclude=0)
    with pytest.raises(TypeError, match="int"):
        C.snr(plane, exclude=3.5)


def test_snr_known_plane():
    rng = np.random.default_rng(7)
    plane = rng.normal(0, 2.0, size=(64, 64))
    plane[32, 32] = 100.0
    mask = np.ones_like(plane, dtype=bool)
    mask[16:48, 16:48] = False
    assert np.isclose(C.snr(plane), 100.0 / plane[mask].std())
    assert abs(C.snr(plane) - 50.0) < 5.0
    assert np.isclose(C.snr_db(10.0), 20.0)


def test_snr_db_paper_convention_matches_printed_pairs():
    # the paper's own pairs: 26.2 -> 14.2 dB, 100.8 -> 20 dB, 8 -> 9 dB
    for ratio, printed in ((26.2, 14.2), (100.8, 20.0), (8.0, 9.0)):
        assert abs(C.snr_db(ratio, convention="paper") - printed) < 0.1
        assert abs(C.snr_db(ratio) - printed) > 5.0
    assert np.isclose(C.snr_db(10.0, convention="paper"), 10.0)
    with pytest.raises(ValueError):
        C.snr_db(10.0, convention="power")


def test_peak_stats_keys():
    plane = np.ones((40, 40))
    plane[20, 20] = 5.0
    plane[0, 0] = 2.0
    out = C.peak_stats(plane, exclude=32)
    assert out["location"] == (20, 20) and out["peak"] == 5.0 and "snr" in out


def test_zero_mean_and_normalize():
    img = letters.render_letter("A")
    z = C.zero_mean(img)
    assert abs(z.mean()) < 1e-12
    n = C.normalize_energy(z)
    assert np.isclose(np.sum(n * n), 1.0)


# ------------------------------------------------------------------------ classifiers
def test_classifiers_recognize_clean_letters():
    alpha = letters.alphabet()
    labels = list(letters.LETTERS)
    for clf in (C.ProjectionCorrelationClassifier(), C.ProjectionCorrelationClassifier(angles=(0, 90, 45)),
                C.Correlation2DClassifier()):
        clf.fit(alpha, labels)
        assert clf.score(alpha, labels) == 1.0


def test_projection_classifier_scores_match_direct_computation():
    alpha = letters.alphabet()
    clf = C.ProjectionCorrelationClassifier(angles=(0, 90)).fit(alpha, list(letters.LETTERS))
    x = C.normalize_energy(C.zero_mean(alpha[7]))
    scores = clf.decision_function(alpha[7:8])[0]
    assert np.isclose(scores[7], 2.0)  # unit-energy projections: each auto peak is 1
    for k in (0, 7, 20):
        f = C.normalize_energy(C.zero_mean(alpha[k]))
        direct = 0.0
        for t in (0, 90):
            px, pf = C.project(x, t), C.project(f, t)
            direct += C.correlate1d(px / np.linalg.norm(px), pf / np.linalg.norm(pf)).max()
        assert np.isclose(scores[k], direct)
    raw = C.ProjectionCorrelationClassifier(normalize_projections=False).fit(alpha, list(letters.LETTERS))
    s_raw = raw.decision_function(alpha[7:8])[0]
    assert np.isclose(s_raw[20], sum(C.projection_correlation(x, C.normalize_energy(C.zero_mean(alpha[20])), t).max()
                                     for t in (0, 90)))


def test_classifier_2d_scores_match_direct():
    alpha = letters.alphabet()
    clf = C.Correlation2DClassifier(chunk=3).fit(alpha, np.arange(26))
    x = C.normalize_energy(C.zero_mean(alpha[4]))
    s = clf.decision_function(alpha[4:5])[0]
    f = C.normalize_energy(C.zero_mean(alpha[11]))
    assert np.isclose(s[11], C.correlate2d(x, f).max())


def test_classifier_bad_inputs():
    clf = C.ProjectionCorrelationClassifier()
    with pytest.raises(ValueError, match="not fitted"):
        clf.predict(np.zeros((1, 4, 4)) + np.eye(4))
    alpha = letters.alphabet()
    with pytest.raises(ValueError, match="one label per image"):
        clf.fit(alpha, ["A"])
    clf.fit(alpha, list(letters.LETTERS))
    with pytest.raises(ValueError, match="shape"):
        clf.predict(np.ones((1, 8, 8)))
    with pytest.raises(ValueError, match="zero energy"):
        clf.predict(np.ones((1, 32, 32)))
    with pytest.raises(TypeError):
        C.ProjectionCorrelationClassifier(angles=("a",))


@pytest.mark.parametrize("bank", [C.ProjectionCorrelationClassifier, C.Correlation2DClassifier])
def test_classifier_needs_two_classes(bank):
    alpha = letters.alphabet()
    with pytest.raises(ValueError, match="at least 2 classes"):
        bank().fit(alpha[:3], ["A", "A", "A"])
    with pytest.raises(ValueError, match="at least 2 classes"):
        bank().fit(alpha[:1], [0])
    clf = bank().fit(alpha[:2], ["A", "B"])  # two classes are enough
    assert list(clf.predict(alpha[:2])) == ["A", "B"]


def test_classifier_bad_chunk():
    with pytest.raises(ValueError, match=">= 1"):
        C.Correlation2DClassifier(chunk=0)
    with pytest.raises(TypeError, match="int"):
        C.Correlation2DClassifier(chunk=2.5)
    assert C.Correlation2DClassifier(chunk=2).chunk == 2  # chunk sizes need not be odd


# ------------------------------------------------------------------ multiple objects
def test_locate_objects_three_projections_resolve_ghosts():
    yy, xx = np.mgrid[-4:5, -4:5]
    disk = ((xx ** 2 + yy ** 2) <= 12).astype(float)
    truth = [(12, 12), (12, 40), (36, 12), (50, 30)]
    scene = np.zeros((64, 64))
    for r, q in truth:
        scene[r - 4:r + 5, q - 4:q + 5] += disk
    two = C.locate_objects(scene, disk, (0, 90))["positions"]
    three = C.locate_objects(scene, disk, (0, 90, 45))["positions"]
    assert sorted(three) == sorted((float(r), float(q)) for r, q in truth)
    assert len(two) > len(truth) and set(map(tuple, three)) <= set(map(tuple, two))


def test_backprojection_min_bad_inputs():
    with pytest.raises(ValueError, match="same length"):
        C.backprojection_min([np.ones(3)], [np.arange(3.0)], (0, 90), (4, 4))
    with pytest.raises(ValueError, match="increasing"):
        C.backprojection_min([np.ones(3)], [np.array([0.0, 0.0, 1.0])], (0,), (4, 4))


# ------------------------------------------------------------- acousto-optic models
def test_space_integrating_correlator_equals_sum_of_correlations():
    rng = np.random.default_rng(8)
    x = rng.normal(size=(2, 20))
    h = rng.normal(size=(3, 2, 15))
    out = C.space_integrating_correlator(x, h)
    direct = np.array([sum(C.correlate1d(x[k], h[n, k]) for k in range(2)) for n in range(3)])
    assert np.allclose(out, direct, atol=1e-10)
    with pytest.raises(ValueError, match="carriers"):
        C.space_integrating_correlator(x, h, carriers=[1, 9], oversample=8)


def test_time_integrating_correlator_equals_correlations():
    rng = np.random.default_rng(9)
    s = rng.normal(size=17)
    h = rng.normal(size=(4, 9))
    out = C.time_integrating_correlator(s, h)
    assert np.allclose(out, [C.correlate1d(s, r) for r in h], atol=1e-10)
    with pytest.raises(ValueError, match="bias"):
        C.time_integrating_correlator(s, h, bias=0.1)


# ------------------------------------------------------------------------ bad inputs
@pytest.mark.parametrize("bad, exc", [
    (np.zeros(5), ValueError),  # 1-D
    (np.zeros((2, 2, 2)), ValueError),  # 3-D
    (np.zeros((0, 4)), ValueError),  # empty
    (np.array([[1.0, np.nan]]), ValueError),  # NaN
    (np.array([[1.0, np.inf]]), ValueError),
    ("image", TypeError),
    (np.array([["a", "b"]]), TypeError),
    (np.array([[1 + 1j]]), TypeError),
])
def test_bad_images(bad, exc):
    with pytest.raises(exc):
        C.project(bad, 0)
    with pytest.raises(exc):
        C.correlate2d(bad, np.ones((2, 2)))
    with pytest.raises(exc):
        C.projection_correlation(np.ones((2, 2)), bad, 45)


def test_bad_angles_and_measures():
    with pytest.raises(TypeError):
        C.project(np.ones((3, 3)), "0")
    with pytest.raises(ValueError):
        C.project(np.ones((3, 3)), np.nan)
    with pytest.raises(TypeError):
        C.project(np.ones((3, 3)), True)
    with pytest.raises(ValueError):
        C.psr(np.ones((1, 1)))
    with pytest.raises(ValueError, match="undefined"):
        C.psr(np.array([0.0, 1.0, 0.0]))
    with pytest.raises(ValueError):
        C.snr(np.ones((5, 5)))
    with pytest.raises(ValueError):
        C.normalize_energy(np.zeros((3, 3)))
    with pytest.raises(ValueError):
        C.snr_db(-1.0)
    with pytest.raises(ValueError):
        C.correlate1d(np.array([]), np.ones(3))
    with pytest.raises(ValueError):
        C.projection_axis((0, 3), 0)
    with pytest.raises(ValueError):
        C.projection_spectrum(np.ones((3, 3)), 0, [np.nan])


def test_mismatched_sizes_are_allowed_but_classifier_sizes_checked():
    # correlations accept different sizes (full output); equality still holds
    f, g = np.ones((3, 8)), np.ones((6, 2))
    assert np.allclose(C.projection_correlation(f, g, 90), C.integrated_correlation(f, g, 90))
    with pytest.raises(ValueError, match="references"):
        C.space_integrating_correlator(np.ones((2, 5)), np.ones((3, 3, 4)))


def test_circular_correlate_matches_direct_cyclic_sum_and_eq3():
    rng = np.random.default_rng(3)
    f, g = rng.normal(size=(6, 8)), rng.normal(size=(6, 8))
    direct = np.zeros((6, 8))
    for a in range(6):
        for b in range(8):
            direct[a, b] = np.sum(f * np.roll(g, (a, b), axis=(0, 1)))
    c = C.circular_correlate(f, g)
    assert np.allclose(c, np.fft.fftshift(direct))
    assert np.isclose(C.circular_correlate(f, f)[3, 4], np.sum(f * f))  # zero lag at the centre
    # Eq. (3) on the torus: projecting the cyclic plane = cyclic correlation of projections
    assert np.allclose(c.sum(axis=0), C.circular_correlate(f.sum(axis=0), g.sum(axis=0)))
    assert np.allclose(c.sum(axis=1), C.circular_correlate(f.sum(axis=1), g.sum(axis=1)))


@pytest.mark.parametrize("f, g, exc", [
    (np.ones((4, 4)), np.ones((4, 5)), ValueError), (np.ones(4), np.ones((4, 4)), ValueError),
    (np.ones((2, 2, 2)), np.ones((2, 2, 2)), ValueError), (np.array(["a", "b"]), np.ones(2), TypeError),
    (np.array([1.0, np.nan]), np.ones(2), ValueError)])
def test_circular_correlate_rejects_bad_inputs(f, g, exc):
    with pytest.raises(exc):
        C.circular_correlate(f, g)


def test_summed_output_scores_equal_peak_sum_only_when_peaks_coincide():
    from projtrack.scenes import letters
    alpha = letters.alphabet()
    labels = np.arange(26)
    bank = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(alpha, labels)
    peaks = bank.decision_function(alpha)
    summed = bank.summed_output_scores(alpha)
    assert summed.shape == peaks.shape == (26, 26)
    assert np.all(summed <= peaks + 1e-12)
    # own class of a centred letter: both peaks at zero lag, so the sum equals the peak sum
    assert np.allclose(np.diag(summed), np.diag(peaks))
    # shifting the letter so that the two peaks fall at opposite lags: the summed output drops
    shifted = np.roll(np.roll(alpha, 4, axis=1), 4, axis=2)  # r runs against the row index: opposite lags
    assert np.all(np.diag(bank.summed_output_scores(shifted)) < np.diag(bank.decision_function(shifted)) - 0.1)
    with pytest.raises(ValueError):
        C.ProjectionCorrelationClassifier(angles=(90, 0, 45)).fit(alpha, labels).summed_output_scores(alpha)
    with pytest.raises(ValueError):
        C.ProjectionCorrelationClassifier().summed_output_scores(alpha)

from __future__ import annotations

import numpy as np
import pytest

from projtrack import correlators as C
from projtrack.experiments import correlators as EX
from projtrack.scenes import letters

DISK = (np.add.outer(np.arange(-4, 5) ** 2, np.arange(-4, 5) ** 2) <= 12).astype(float)
PLUS = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], dtype=float)


# ------------------------------------------------------------------------------ scoring
def test_inside_widened():
    v = np.linspace(10.0, 20.0, 201)
    lo, hi = np.quantile(v, [0.025, 0.975])
    assert EX.inside_widened(v, 15.0)
    assert EX.inside_widened(v, 0.9 * lo) and EX.inside_widened(v, 1.1 * hi)
    assert not EX.inside_widened(v, 0.89 * lo) and not EX.inside_widened(v, 1.11 * hi)
    assert not EX.inside_widened(v, 0.95 * lo, widen=0.0)
    with pytest.raises(ValueError, match="values"):
        EX.inside_widened([], 1.0)
    with pytest.raises(TypeError, match="printed"):
        EX.inside_widened(v, "1")


def test_inside_share():
    v = np.linspace(10.0, 20.0, 201)
    assert EX.inside_share(v, 15.0, np.random.default_rng(0), n_boot=50) == 1.0
    assert EX.inside_share(v, 100.0, np.random.default_rng(0), n_boot=50) == 0.0
    hi = np.quantile(v, 0.975) * 1.1
    assert 0.05 < EX.inside_share(v, hi, np.random.default_rng(0), n_boot=200) < 0.95  # on the edge


def test_error_count_pmf_is_the_poisson_binomial():
    p = np.array([0.1, 0.5, 0.9])
    pmf = EX.error_count_pmf(p)
    brute = np.zeros(4)
    for bits in np.ndindex(2, 2, 2):
        b = np.array(bits)
        brute[b.sum()] += np.prod(np.where(b == 1, p, 1 - p))
    assert np.allclose(pmf, brute) and np.isclose(pmf.sum(), 1.0)
    assert np.array_equal(EX.error_count_pmf(np.zeros(3)), [1, 0, 0, 0])
    with pytest.raises(ValueError, match="error rates"):
        EX.error_count_pmf([0.2, 1.5])


def test_counts_consistent():
    # a chance classifier never gives 0 errors; a perfect one never gives 2
    assert EX.counts_consistent(np.full(26, 25 / 26), np.full(26, 25 / 26))[0] is False
    assert EX.counts_consistent(np.zeros(26), np.zeros(26))[0] is False
    ok, p0, p2 = EX.counts_consistent(np.full(26, 0.01), np.full(26, 0.06))
    assert ok and np.isclose(p0, 0.99 ** 26) and 0.025 < p2 < 1
    with pytest.raises(ValueError, match="level"):
        EX.counts_consistent(np.zeros(3), np.zeros(3), level=2.0)
    with pytest.raises(ValueError, match="at least 2"):
        EX.counts_consistent(np.zeros(3), np.zeros(1))


def test_last_perfect():
    levels = np.array([0.1, 0.2, 0.3, 0.4])
    assert EX.last_perfect([1.0, 1.0, 0.9, 1.0], levels) == 0.2
    assert EX.last_perfect([1.0] * 4, levels) == 0.4
    assert np.isnan(EX.last_perfect([0.5, 1.0, 1.0, 1.0], levels))
    with pytest.raises(ValueError, match="shape"):
        EX.last_perfect([1.0, 1.0], levels)


# -------------------------------------------------------------------------- recognition
@pytest.fixture(scope="module")
def small_bank():
    imgs = np.stack([letters.render_letter(c) for c in "CLO"])
    return imgs, np.arange(3), C.ProjectionCorrelationClassifier().fit(imgs, np.arange(3))


def test_noise_sweep_shape_and_noise_free_accuracy(small_bank):
    imgs, labels, bank = small_bank
    ok = EX.noise_sweep({"a": bank, "b": bank}, imgs, labels, [0.0, 3.0], 3, np.random.default_rng(0))
    assert ok.shape == (3, 2, 2, 3) and ok.dtype == bool
    assert ok[:, 0].all()  # no noise: the unit-energy bank is always right
    assert not ok[:, 1].all()  # heavy noise: some errors
    assert np.array_equal(ok[:, :, 0], ok[:, :, 1])  # both banks see the same noisy images
    again = EX.noise_sweep({"a": bank, "b": bank}, imgs, labels, [0.0, 3.0], 3, np.random.default_rng(0))
    assert np.array_equal(ok, again)
    # noise confined to a 2 x 2 centre hardly touches the letters
    centre = EX.noise_sweep({"a": bank}, imgs, labels, [3.0], 3, np.random.default_rng(0), extent=2)
    assert centre.mean() > ok[:, 1].mean()
    with pytest.raises(ValueError, match="labels"):
        EX.noise_sweep({"a": bank}, imgs, labels[:2], [0.1], 1, np.random.default_rng(0))
    with pytest.raises(TypeError, match="fitted classifier"):
        EX.noise_sweep({"a": object()}, imgs, labels, [0.1], 1, np.random.default_rng(0))
    with pytest.raises(ValueError, match="distribution"):
        EX.noise_sweep({"a": bank}, imgs, labels, [0.1], 1, np.random.default_rng(0), distribution="poisson")


def test_recognition_study_rules(small_bank):
    imgs, labels, _ = small_bank
    bank = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(imgs, labels)
    ok = EX.recognition_study([bank, bank], np.stack([imgs, imgs]), labels, [0.0, 2.0], ("gaussian", "uniform"), 3,
                              np.random.default_rng(1), extent=30)
    assert ok.shape == (3, 2, 2, 2, 2, 3) and ok.dtype == bool
    assert ok[:, :, :, 0].all()  # noise-free, centred letters: both rules right
    assert not ok[:, :, :, 1].all()
    assert EX.RULES == ("sum of peaks", "summed output")
    with pytest.raises(ValueError, match="one alphabet per bank"):
        EX.recognition_study([bank], np.stack([imgs, imgs]), labels, [0.1], ("gaussian",), 1, np.random.default_rng(0))
    with pytest.raises(ValueError, match="laws"):
        EX.recognition_study([bank], imgs[None], labels, [0.1], ("poisson",), 1, np.random.default_rng(0))
    with pytest.raises(TypeError, match="summed_output_scores"):
        EX.recognition_study([C.Correlation2DClassifier().fit(imgs, labels)], imgs[None], labels, [0.1],
                             ("gaussian",), 1, np.random.default_rng(0))


def test_margin_study(small_bank):
    imgs, labels, _ = small_bank
    two = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(imgs, labels)
    three = C.ProjectionCorrelationClassifier(angles=(90, 0, 45)).fit(imgs, labels)
    m = EX.margin_study([two, three], imgs, labels, [0.0, 1.5], 4, np.random.default_rng(2))
    assert m.shape == (4, 2, 2, 3)
    assert np.all(m[:, 0] > 0)  # noise-free: the true class wins (Cauchy-Schwarz on unit-energy projections)
    assert np.all(m <= 1.0)  # a margin per projection cannot exceed one unit-energy peak
    # the margin is the score gap: recompute it for one draw
    X = letters.noisy(imgs, 0.0, np.random.default_rng(0))[0]
    s = two.decision_function(X) / 2
    gap = [s[i, i] - np.max(np.delete(s[i], i)) for i in range(3)]
    assert np.allclose(m[0, 0, 0], gap)
    with pytest.raises(TypeError, match="angles"):
        EX.margin_study([C.Correlation2DClassifier().fit(imgs, labels)], imgs, labels, [0.1], 1,
                        np.random.default_rng(0))
    with pytest.raises(ValueError, match="classes"):
        EX.margin_study([two], imgs, labels + 5, [0.1], 1, np.random.default_rng(0))


# ------------------------------------------------------------------------------ objects
def test_place_objects_and_energy_count():
    scene = EX.place_objects(DISK, [(12, 12), (40, 40)])
    assert scene.shape == (64, 64) and scene.sum() == 2 * DISK.sum()
    assert np.array_equal(scene[8:17, 8:17], DISK)
    assert np.isclose(EX.energy_count(scene, DISK), 2.0, atol=0.05)
    assert np.isclose(EX.energy_count(EX.place_objects(DISK, [(20, 20)]), DISK), 1.0)
    with pytest.raises(ValueError, match="fit"):
        EX.place_objects(DISK, [(2, 30)])
    with pytest.raises(ValueError, match="odd"):
        EX.place_objects(np.ones((4, 4)), [(20, 20)])
    with pytest.raises(ValueError, match="constant"):
        EX.energy_count(scene, np.ones((3, 3)))


def test_match_positions():
    truth = [(10, 10), (30, 30)]
    assert EX.match_positions([(10.4, 9.6), (30, 31)], truth) == (0, 0)
    assert EX.match_positions([(10, 10)], truth) == (1, 0)
    assert EX.match_positions([(10, 10), (30, 30), (50, 50)], truth) == (0, 1)
    assert EX.match_positions([(12, 10)], truth[:1], tol=1) == (1, 1)
    with pytest.raises(ValueError, match="tol"):
        EX.match_positions([], truth, tol=-1)


def test_random_positions_are_separated_and_reproducible():
    pos = EX.random_positions(np.random.default_rng(3))
    assert len(pos) == 4 and pos == EX.random_positions(np.random.default_rng(3))
    assert all(5 <= v < 59 for p in pos for v in p)
    assert all(max(abs(a[0] - b[0]), abs(a[1] - b[1])) >= 10 for i, a in enumerate(pos) for b in pos[:i])
    with pytest.raises(TypeError, match="rng"):
        EX.random_positions(3)
    with pytest.raises(ValueError, match="apart"):
        EX.random_positions(np.random.default_rng(0), 2, low=0, high=3, min_separation=10)


def test_random_scene_study_small():
    trials, counts = EX.random_scene_study({"plus": PLUS}, [("H+V+45", (0, 90, 45))], 2, np.random.default_rng(10))
    assert len(trials) == 2 and len(counts) == 2
    assert set(trials.columns) >= {"object", "projections", "located", "missed", "spurious", "positions"}
    assert (trials["missed"] >= 0).all() and (counts["energy count"] > 0).all()
    with pytest.raises(ValueError, match="templates"):
        EX.random_scene_study({}, [("H+V", (0, 90))], 1, np.random.default_rng(0))


def test_switching_pair_shares_projections():
    a, b = EX.switching_pair()
    assert len(a) == len(b) == 4 and not set(a) & set(b)
    for key in (lambda p: p[0], lambda p: p[1], lambda p: p[1] - p[0]):
        assert sorted(map(key, a)) == sorted(map(key, b))
    assert not EX.unique_from_projections(a)
    assert EX.unique_from_projections([(10, 10), (20, 30)])


def test_ideal_ghosts_and_study():
    # two objects not sharing a row or column: two H+V crossings, neither on an object's diagonal
    assert EX.ideal_ghosts([(10, 10), (20, 30)]) == {"45": 0, "135": 0}
    # three objects on three corners: the fourth corner (20, 20) lies on the 45-degree diagonal of (10, 10)
    assert EX.ideal_ghosts([(10, 10), (10, 20), (20, 10)]) == {"45": 1, "135": 0}
    assert [EX.ideal_ghosts([(10, 10), (10, 21), (20, 10)], tol)["45"] for tol in (0, 1)] == [0, 1]
    r = EX.ideal_detector_study(5, np.random.default_rng(11))
    assert r.shape == (5, len(EX.IDEAL_KEYS) + 1) and r.dtype == bool
    assert np.array_equal(r, EX.ideal_detector_study(5, np.random.default_rng(11)))


def test_unique_from_lines_and_ghosts():
    a, b = EX.switching_pair()
    assert not EX.unique_from_lines(a, (0, 90, 45))  # a switching component: two sets share the three projections
    assert EX.unique_from_lines(a, (0, 90, 45, 135))
    rng = np.random.default_rng(4)
    for _ in range(20):  # agrees with the brute-force enumeration for H, V and 45 degrees
        pos = EX.random_positions(rng, 4)
        assert EX.unique_from_lines(pos, (0, 90, 45)) == EX.unique_from_projections(pos)
        assert EX.lines_ghost_free(pos, (0, 90, 45)) == (EX.ideal_ghosts(pos)["45"] == 0)
    # two objects on no common line: their swapped pair has the same rows and columns
    assert not EX.unique_from_lines([(10, 10), (20, 30)], (0, 90))
    assert EX.unique_from_lines([(10, 10), (10, 30)], (0, 90))  # a shared row: nothing to swap
    assert not EX.unique_from_lines([(10, 10)], (0,)) and not EX.lines_ghost_free([(10, 10)], (0,))
    assert not EX.lines_ghost_free([(10, 10), (20, 30)], (0, 90))
    assert EX.lines_ghost_free([(10, 10), (20, 30)], (0, 90, 45))
    with pytest.raises(ValueError, match="angles"):
        EX.unique_from_lines([(1, 1)], (0, 30))
    r = EX.ideal_count_study([2, 3], [(0, 90), (0, 90, 45)], 4, np.random.default_rng(5), tols=(0,))
    assert r.shape == (4, 2, 2, 2) and r.dtype == bool
    assert np.array_equal(r, EX.ideal_count_study([2, 3], [(0, 90), (0, 90, 45)], 4, np.random.default_rng(5),
                                                  tols=(0,)))


def test_energy_count_study():
    est = EX.energy_count_study(PLUS, [1, 3], 3, np.random.default_rng(6), angles=(90,))
    assert est.shape == (3, 2, 2)
    assert np.allclose(est[:, 0, :], 1.0)  # one object: its own energy
    assert np.allclose(est[:, 1, 0], 3.0, atol=0.05)  # non-overlapping copies: 2-D energies add
    noisy = EX.energy_count_study(PLUS, [2], 200, np.random.default_rng(7), sigma=0.3, angles=())
    assert abs(noisy.mean() - 2.0) < 0.2  # the expected noise energy is subtracted
    with pytest.raises(ValueError, match="odd"):
        EX.energy_count_study(np.ones((4, 4)), [1], 1, np.random.default_rng(0))
    with pytest.raises(ValueError, match="constant"):
        EX.energy_count_study(np.ones((3, 3)), [1], 1, np.random.default_rng(0))


# ---------------------------------------------------------------------- autocorrelation
C_BIN = letters.render_letter("C")


def test_in_frame_centres_the_image():
    f = EX.in_frame(C_BIN, 64)
    assert f.shape == (64, 64) and f.sum() == C_BIN.sum() and np.array_equal(f[16:48, 16:48], C_BIN)
    assert EX.in_frame(np.ones((3, 3)), 6)[1:4, 1:4].all()
    with pytest.raises(ValueError, match="size"):
        EX.in_frame(C_BIN, 16)


def test_peak_measures_of_a_binary_letter():
    m = EX.peak_measures(C_BIN, C_BIN)
    n = C_BIN.sum()
    assert m["2-D"][0] == pytest.approx(n)  # autocorrelation peak of a binary image = pixels on
    # a projection autocorrelation peak is the energy of the projection, above the 2-D peak
    for name, theta in (("vertical", 0), ("horizontal", 90)):
        assert m[name][0] == pytest.approx(np.sum(C.project(C_BIN, theta) ** 2)) and m[name][0] > n
        assert m[name][1] > 0


def test_psr_as_row_dilutes_the_sidelobes():
    c = np.array([1.0, 2.0, 10.0, 2.0, 1.0])
    # sidelobe mean (1 + 2 + 2 + 1) / 24 over the 5 x 5 window (peak excluded)
    assert EX.psr_as_row(c, 5) == pytest.approx(10.0 / (6.0 / 24))
    assert EX.psr_as_row(c, 5) > C.psr(c, 5)
    with pytest.raises(ValueError, match="odd"):
        EX.psr_as_row(c, 4)


def test_noisy_study_and_peak_at_centre():
    frame = EX.in_frame(C_BIN, 48)
    ref = C.zero_mean(frame)
    d = EX.noisy_study(frame, ref, 0.0, 2, np.random.default_rng(0), extent=None)
    assert list(d.columns) == list(EX.NOISY_QUANTITIES) and len(d) == 2
    clean = EX.noisy_measures(ref, ref)
    assert np.allclose(d.iloc[0].to_numpy(), clean)  # sigma 0: the zero-mean letter itself
    lin = EX.noisy_study(frame, ref, 0.3, 3, np.random.default_rng(1), extent=32, plane="linear 127x127")
    assert lin["2-D peak"].std() > 0
    rect = EX.noisy_study(frame, ref, 0.3, 3, np.random.default_rng(1), extent=32, rectify=True)
    assert rect.shape == (3, 2 * len(EX.NOISY_QUANTITIES))
    assert np.allclose(rect["rectified 2-D peak"], rect["2-D peak"])  # a positive peak survives rectification
    assert (rect["rectified 2-D SNR"] >= rect["2-D SNR"]).all()  # zeros instead of negatives: less spread
    hits = EX.peak_at_centre_study(frame, ref, 0.0, 2, np.random.default_rng(0))
    assert hits.shape == (2, 3) and hits.all()
    # a reference whose correlation has a deep negative lobe: the magnitude detector finds it
    dip = np.zeros((16, 16))
    dip[8, 8], dip[8, 11] = 1.0, -3.0
    seen = [EX.peak_at_centre_study(dip, np.where(dip > 0, 1.0, 0.0), 0.0, 1, np.random.default_rng(0),
                                    detect=d, tol=0)[0, 0] for d in ("bipolar", "magnitude")]
    assert seen == [True, False]
    with pytest.raises(ValueError, match="detect"):
        EX.peak_at_centre_study(frame, ref, 0.1, 1, np.random.default_rng(0), detect="intensity")
    with pytest.raises(ValueError, match="same shape"):
        EX.noisy_study(frame, C_BIN, 0.1, 1, np.random.default_rng(0), extent=None)
    with pytest.raises(ValueError, match="plane"):
        EX.noisy_study(frame, ref, 0.1, 1, np.random.default_rng(0), extent=None, plane="cyclic")
    with pytest.raises(ValueError, match="sigma"):
        EX.peak_at_centre_study(frame, ref, -1.0, 1, np.random.default_rng(0))


def test_planes_agree_where_they_should():
    frame = EX.in_frame(C_BIN, 64)
    ref = C.zero_mean(frame)
    full = C.correlate2d(ref, ref)
    cyc, crop, lin = (EX.noisy_measures(ref, ref, plane=p) for p in EX.PLANES)
    assert cyc[0] == pytest.approx(crop[0]) == pytest.approx(lin[0]) == pytest.approx(full.max())
    assert crop[3] == pytest.approx(lin[3])  # the cropped plane keeps the peak of the full one


def test_snr_by_extent_and_calibration():
    frame = EX.in_frame(C_BIN, 64)
    ref = C.zero_mean(frame)
    t = EX.snr_by_extent(frame, ref, 0.35, [26, 30, 34], 20, np.random.default_rng(3), planes=("cyclic 64x64",))
    assert list(t.columns) == ["plane", "noise extent", "2-D SNR", "horizontal SNR"] and len(t) == 3
    assert t["2-D SNR"].is_monotonic_decreasing  # more noise, lower SNR
    assert EX.calibrated_extent(t, float(t["2-D SNR"].iloc[1]), "cyclic 64x64") == 30
    assert EX.calibrated_extent(t, 1e6, "cyclic 64x64") == 26
    with pytest.raises(ValueError, match="no rows"):
        EX.calibrated_extent(t, 100.0, "linear 127x127")
    with pytest.raises(ValueError, match="extents"):
        EX.snr_by_extent(frame, ref, 0.35, [], 2, np.random.default_rng(0))
    assert EX.NOISE_EXTENT == 30


def test_zero_mean_psr_closed_form_matches_the_simulation():
    n = int(C_BIN.sum())
    psr_bin = EX.peak_measures(C_BIN, C_BIN)["2-D"][1]
    for size in (48, 64):
        z = C.zero_mean(EX.in_frame(C_BIN, size))
        assert EX.zero_mean_psr(n, psr_bin, size) == pytest.approx(EX.peak_measures(z, z)["2-D"][1], rel=1e-9)
        cyc = C.circular_correlate(z, z)
        assert EX.zero_mean_psr(n, psr_bin, size, cyclic=True) == pytest.approx(C.psr(cyc), rel=1e-9)
    # the paper's own numbers: 43 pixels and binary PSR 3.8 give 3.9 in a 64 frame, not in a 32 one
    assert round(EX.zero_mean_psr(43, 3.8, 64), 1) == 3.9 and round(EX.zero_mean_psr(43, 3.8, 32), 1) > 4.2
    with pytest.raises(ValueError, match="psr_binary"):
        EX.zero_mean_psr(43, 0.0, 64)


# ---------------------------------------------------------------------------------- snr
def test_snr_signals():
    s16 = EX.snr_signals(16, np.random.default_rng(0))
    assert set(s16) == {"uniform (paper's white)", "single pixel", "random +-1 texture"}
    assert s16["single pixel"].sum() == 1 and set(np.unique(s16["random +-1 texture"])) <= {-1.0, 1.0}
    assert "letter C" in EX.snr_signals(32, np.random.default_rng(0))


def test_output_snr_study_limits():
    n = 8
    uni = EX.output_snr_study(np.ones((n, n)), 4, 100, np.random.default_rng(0))
    assert uni["loss factor"] == pytest.approx(1.0)  # projection output = N x 2-D output, draw by draw
    assert uni["loss, closed form"] == pytest.approx(1.0)
    assert uni["SNR_o 2-D"] == pytest.approx(n, rel=0.15)  # N / sigma
    one = np.zeros((n, n))
    one[4, 4] = 1.0
    single = EX.output_snr_study(one, 4, 100, np.random.default_rng(1))
    assert single["loss, closed form"] == pytest.approx(np.sqrt(n))
    assert single["loss factor"] == pytest.approx(np.sqrt(n), rel=0.15)
    assert single["SNR_i ratio"] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="square"):
        EX.output_snr_study(np.ones((4, 5)), 2, 10, np.random.default_rng(0))
    with pytest.raises(ValueError, match="sigma"):
        EX.output_snr_study(np.ones((4, 4)), 2, 10, np.random.default_rng(0), sigma=0.0)


def test_closed_forms_of_sec_iic():
    n = 16
    one = np.zeros((n, n))
    one[3, 5] = 1.0
    assert EX.loss_closed_form(np.ones((n, n))) == pytest.approx(1.0)
    assert EX.loss_closed_form(one) == pytest.approx(np.sqrt(n))
    assert EX.input_snr_ratio(np.ones((n, n))) == pytest.approx(np.sqrt(n))
    assert EX.input_snr_ratio(one) == pytest.approx(1.0)
    # a signed image whose columns cancel almost everywhere loses more than N^1/2
    signed = np.tile([1.0, -1.0], (n, n // 2)).T.copy()
    signed[0, 0] = 3.0
    assert EX.loss_closed_form(signed) > np.sqrt(n)
    with pytest.raises(ValueError, match="zero"):
        EX.input_snr_ratio(np.zeros((3, 3)))
    t = EX.texture_losses(16, 50, np.random.default_rng(0))
    assert t.shape == (50,) and 0 < np.mean(t > np.sqrt(16)) < 1  # about half exceed the 'worst case'
    assert np.array_equal(t, EX.texture_losses(16, 50, np.random.default_rng(0)))


def test_signal_1d_study():
    r = EX.signal_1d_study(25, 4, 500, np.random.default_rng(1), sigma=0.5)
    assert r["theory"] == pytest.approx(10.0) and r["SNR_i"] == pytest.approx(2.0)
    assert r["SNR_o 1-D signal"] == pytest.approx(10.0, rel=0.08)
    with pytest.raises(ValueError, match="sigma"):
        EX.signal_1d_study(4, 1, 10, np.random.default_rng(0), sigma=0.0)


def test_combine_study_noise_correlations():
    white = EX.combine_study(np.ones((8, 8)), (90, 0), 4, 200, np.random.default_rng(2))
    assert white["noise correlation, closed form"][0, 1] == pytest.approx(1.0)  # identical noises
    assert white["noise correlation"][0, 1] == pytest.approx(1.0)
    assert white["sum"] == pytest.approx(white["single"][0], rel=1e-9)  # nothing gained
    zm = EX.combine_study(C.zero_mean(C_BIN), (90, 0, 45), 4, 200, np.random.default_rng(3))
    assert abs(zm["noise correlation, closed form"][0, 1]) < 1e-12  # zero-mean: H and V noises uncorrelated
    assert zm["sum"] > max(zm["single"])
    with pytest.raises(ValueError, match="angles"):
        EX.combine_study(C_BIN, (30,), 1, 10, np.random.default_rng(0))


# ---------------------------------------------------------------------------- detectors
def test_detector_rule_study(small_bank):
    imgs, labels, _ = small_bank
    bank = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(imgs, labels)
    r = EX.detector_rule_study(bank, imgs, labels, [(0.0, 0), (0.0, 3)], 3, np.random.default_rng(0))
    assert r.shape == (3, 2, 3)
    assert np.all(r[:, 0] == 1.0)  # centred, noise-free: both rules right and agreeing
    assert np.all(r[:, 1, 1] == 1.0)  # the sum of separate peaks is shift invariant (cyclic shifts)
    e = EX.detector_rule_study(bank, imgs, labels, [(0.5, 0)], 2, np.random.default_rng(0), extent=4)
    assert e.shape == (2, 1, 3)
    with pytest.raises(ValueError, match="shift"):
        EX.detector_rule_study(bank, imgs, labels, [(0.1, -1)], 1, np.random.default_rng(0))
    with pytest.raises(TypeError, match="ProjectionCorrelationClassifier"):
        EX.detector_rule_study(object(), imgs, labels, [(0.1, 0)], 1, np.random.default_rng(0))


# ----------------------------------------------------------------------- discrimination
def test_unit_image_and_correlation_peak():
    u = EX.unit_image(C_BIN)
    assert abs(u.mean()) < 1e-12 and np.isclose(np.sum(u * u), 1.0)
    # the autocorrelation peak of a unit-energy image is 1 in 2-D, and its projection energy in 1-D
    assert EX.correlation_peak(u, u, None) == pytest.approx(1.0)
    assert EX.correlation_peak(u, u, 90) == pytest.approx(np.sum(C.project(u, 90) ** 2))


def test_noisy_pair_study(small_bank):
    imgs, _, _ = small_bank
    filt = EX.unit_image(imgs[0])
    d = EX.noisy_pair_study(imgs[0], imgs[1], filt, [90, None], 0.0, 2, np.random.default_rng(0))
    assert d.shape == (2, 2, 2)
    assert np.allclose(d[:, 1, 0], 1.0) and np.all(d[:, :, 0] > d[:, :, 1])  # noise-free: auto beats cross
    noisy = EX.noisy_pair_study(imgs[0], imgs[1], filt, [90], 0.5, 3, np.random.default_rng(0))
    assert np.array_equal(noisy, EX.noisy_pair_study(imgs[0], imgs[1], filt, [90], 0.5, 3, np.random.default_rng(0)))
    assert noisy[:, 0, 0].std() > 0
    confined = EX.noisy_pair_study(imgs[0], imgs[1], filt, [90], 0.5, 3, np.random.default_rng(0), extent=8)
    assert not np.array_equal(confined, noisy)
    with pytest.raises(ValueError, match="angles"):
        EX.noisy_pair_study(imgs[0], imgs[1], filt, [], 0.1, 1, np.random.default_rng(0))


def test_binary_vs_zero_mean_and_magnitudes():
    imgs = np.stack([C_BIN, letters.render_letter("P")])
    t = EX.binary_vs_zero_mean(imgs, {"2-D": None, "horizontal": 90})
    assert len(t) == 4 and set(t["correlation"]) == {"2-D", "horizontal"}
    row = t[(t["filter"] == 0) & (t["correlation"] == "2-D")].iloc[0]
    u, p = C.normalize_energy(C_BIN), C.normalize_energy(imgs[1])
    assert row["binary ratio"] == pytest.approx(1.0 / EX.correlation_peak(p, u, None))
    assert row["zero-mean ratio"] > row["binary ratio"]
    assert (t["cross most negative / peak"] < 0).all() and (t["auto most negative / peak"] < 0).all()
    # magnitudes can only raise a cross peak: |c| >= c
    neg = t["cross most negative / peak"].abs() > 1.0 / t["zero-mean ratio"]
    assert np.allclose(t.loc[~neg, "magnitude ratio"], t.loc[~neg, "zero-mean ratio"], rtol=0, atol=1e-9) or neg.any()
    assert (t["magnitude ratio"] <= t["zero-mean ratio"] + 1e-12).all() or (t["auto most negative / peak"] < -1).any()
    bip, mag = EX.magnitude_mismatch(EX.unit_image(C_BIN), EX.unit_image(imgs[1]), 0)
    assert bip < 1e-12 < 0.1 < mag  # bipolar outputs obey eq. (3), their magnitudes do not
    with pytest.raises(ValueError, match="two images"):
        EX.binary_vs_zero_mean(imgs[:1], {"2-D": None})


def test_predictor_accuracy(small_bank):
    imgs, labels, bank = small_bank
    always_zero = lambda X: np.zeros(len(X), dtype=int)  # noqa: E731
    ok = EX.predictor_accuracy({"bank": bank.predict, "zero": always_zero}, imgs, labels, [0.0, 0.2], 2,
                               np.random.default_rng(0))
    assert ok.shape == (2, 2, 2, 3)
    assert ok[:, 0, 0].all()  # the bank on clean letters
    assert np.array_equal(ok[:, :, 1], np.broadcast_to(labels == 0, (2, 2, 3)))  # right only on class 0
    with pytest.raises(TypeError, match="callable"):
        EX.predictor_accuracy({"x": 1}, imgs, labels, [0.1], 1, np.random.default_rng(0))
    with pytest.raises(ValueError, match="sigmas"):
        EX.predictor_accuracy({"bank": bank.predict}, imgs, labels, [-0.1], 1, np.random.default_rng(0))


# -------------------------------------------------------------------------------- plots
def test_auto_cross_figure_and_legibility():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from projtrack import figures
    from projtrack.experiments.correlators import plots

    u = EX.unit_image(C_BIN)
    p = EX.unit_image(letters.render_letter("P"))
    fig = plots.auto_cross_figure([(u, "C"), (p, "P")], [(u, "auto", "C0"), (p, "cross", "C3")], u,
                                  cmap="gray", normalize=True)
    try:
        assert len(fig.axes) == 6 and fig.axes[3].get_ylabel() == "corr. / auto peak"
        assert max(fig.axes[2].lines[0].get_ydata()) == pytest.approx(1.0)  # auto peak = 1
        assert figures.legibility_problems(fig) == []
        with pytest.raises(ValueError, match="2 images"):
            plots.auto_cross_figure([(u, "C")], [(u, "auto", "C0")], u, cmap="gray")
        for f in (plots.eq3_figure(u), plots.fig3_figure(C_BIN), plots.fig4_figure(u), plots.architectures_figure()):
            assert figures.legibility_problems(f) == []
    finally:
        plt.close("all")


# ----------------------------------------------------------------------------- theorems
def test_central_slice_errors_exact_on_lattice_angles():
    rho = np.linspace(-0.5, 0.5, 21)
    t = EX.central_slice_errors(C_BIN, (0, 45, 30), rho)
    assert list(t["exact binning"]) == [True, True, False]
    assert t["max |diff| / |F(0)|"].iloc[:2].max() < 1e-10
    assert t["max |diff| / |F(0)|"].iloc[2] > 1e-6  # interpolated bins: not exact
    with pytest.raises(ValueError, match="zero frequency"):
        EX.central_slice_errors(C_BIN, (0,), np.array([0.1, 0.2]))


def test_eq3_errors_and_random_pairs():
    t = EX.eq3_errors(C_BIN, letters.render_letter("P"), (0, 90, 30))
    assert t["max |diff| / max |integrated|"].iloc[:2].max() < 1e-10
    assert 0 < t["max |diff| / max |integrated|"].iloc[2] < 0.15
    w = EX.eq3_random_pairs(5, np.random.default_rng(0), max_side=12)
    assert 0 <= w < 1e-10 and w == EX.eq3_random_pairs(5, np.random.default_rng(0), max_side=12)
    with pytest.raises(ValueError, match="max_side"):
        EX.eq3_random_pairs(2, np.random.default_rng(0), max_side=2)


def test_eq3_wrong_angle_is_a_baseline_that_fails():
    p = letters.render_letter("P")
    t = EX.eq3_wrong_angle(C.zero_mean(C_BIN), C.zero_mean(p), (0, 30), (1, 5))
    assert list(t.columns) == ["theta (deg)", "Eq. (3)", "theta +1 deg", "theta +5 deg"]
    assert t["Eq. (3)"].iloc[0] < 1e-10 < 0.05 < t["theta +5 deg"].iloc[0]  # exact at 0; a 5 deg error is visible
    assert t["theta +5 deg"].iloc[1] > t["Eq. (3)"].iloc[1]


# ------------------------------------------------------------------------------- scoring
def test_summarize_draws():
    import pandas as pd

    d = {"a": pd.DataFrame({"x": np.linspace(0.0, 10.0, 101)}), "b": pd.DataFrame({"x": np.full(5, 3.0)})}
    t = EX.summarize_draws(d, {"x": 5.0})
    assert list(t["reading"]) == ["a", "b"] and t["median"].iloc[0] == pytest.approx(5.0)
    assert list(t["paper inside"]) == [True, False]
    with pytest.raises(ValueError, match="column"):
        EX.summarize_draws(d, {"y": 1.0})


# -------------------------------------------------------------------------------- glyphs
def test_glyph_numbers_and_verdicts():
    import pandas as pd

    p = letters.render_letter("P")
    n = EX.letter_numbers(C_BIN, p)
    m = EX.peak_measures(C_BIN, C_BIN)
    assert n["pixels"] == 43 and n["vertical peak"] == pytest.approx(m["vertical"][0])
    assert n["cross/auto 2-D"] < n["cross/auto horizontal"] < 1.1
    table = EX.ensemble_table(fonts=("STIX",), cap_heights=(8.5, 11.0), offsets=(0.0, 0.5))
    assert len(table) >= 2 and set(table["font"]) == {"STIX"} and {"box", "fits", "fits_counts"} <= set(table)
    numbers = EX.ensemble_numbers(table)
    assert (numbers["pixels"] == 43).all() and (numbers["box"] <= 10).all()
    assert len(EX.ensemble_numbers(table, which="fits_counts")) >= len(numbers)
    assert len(EX.ensemble_numbers(table, which=None)) == len(table)
    with pytest.raises(ValueError, match="column"):
        EX.ensemble_numbers(table, which="nope")
    assert EX.share_within(np.array([1.0, 1.05, 1.2]), 1.0, 0.1) == pytest.approx(2 / 3)
    cmp = EX.compare_printed(numbers, n, {"2-D PSR": 3.8})
    assert cmp["ours"].iloc[0] == pytest.approx(m["2-D"][1]) and cmp["match"].iloc[0] == 0.0
    assert EX.glyph_verdict(n, numbers, {"vertical peak": n["vertical peak"]}) == "within-tolerance"
    assert EX.glyph_verdict(n, numbers, {"2-D PSR": 3.8}) == "differs"
    fake = pd.DataFrame({"x": [1.0, 2.0]})
    assert EX.glyph_verdict({"x": 5.0}, fake, {"x": 2.05}) == "qualitative"  # one glyph set reproduces it
    with pytest.raises(ValueError, match="columns"):
        EX.member_alphabet({"font": "STIX"})


def test_the_no_discrimination_baseline_cannot_pass():
    import pandas as pd

    # a cross/auto ratio of 1 is within 10 % of a printed 0.95, but not nearer it than to 1
    assert EX.close_to_printed([1.0], 0.95).all() and not EX.close_to_printed([1.0], 0.95, baseline=1.0).any()
    assert list(EX.close_to_printed([0.90, 0.97, 0.98, 0.85], 0.95, baseline=1.0)) == [True, True, False, False]
    fake = pd.DataFrame({"r": [1.0, 0.93]})
    assert EX.glyph_verdict({"r": 1.0}, fake, {"r": 0.95}) == "within-tolerance"
    assert EX.glyph_verdict({"r": 1.0}, fake, {"r": 0.95}, baseline={"r": 1.0}) == "qualitative"
    assert EX.glyph_verdict({"r": 1.0}, fake[:1], {"r": 0.95}, baseline={"r": 1.0}) == "differs"
    cmp = EX.compare_printed(fake, {"r": 1.0}, {"r": 0.95}, baseline={"r": 1.0})
    assert cmp["match"].iloc[0] == 0.5


def test_counts_consistent_mc():
    rng = np.random.default_rng(0)
    perfect = np.ones((50, 26), dtype=bool)
    r = EX.counts_consistent_mc(perfect, perfect, rng, n_boot=50)
    assert r["P0"] == 1.0 and not r["consistent"] and not r["edge"]  # never 2 errors at the second level
    # one error somewhere in 1 draw of 40 at the first level, about 2 per test at the second
    first = np.ones((40, 26), dtype=bool)
    first[0, 3] = False
    second = rng.random((40, 26)) > 2 / 26
    r = EX.counts_consistent_mc(first, second, np.random.default_rng(1), n_boot=200)
    assert r["consistent"] and r["P0"] == pytest.approx(1 - 1 / 40)
    assert r["P0 low"] <= r["P0"] <= r["P0 high"] and 0.0 <= r["share consistent"] <= 1.0
    same = EX.counts_consistent_mc(first, second, np.random.default_rng(1), n_boot=200)
    assert same == r
    with pytest.raises(ValueError, match="bool"):
        EX.counts_consistent_mc(first.astype(int), second, rng)
    with pytest.raises(ValueError, match="shape"):
        EX.counts_consistent_mc(first[:3], second, rng)


def test_detection_study(small_bank):
    imgs, labels, bank = small_bank
    ok = EX.detection_study(bank, imgs, labels, [0.0, 2.0], 3, np.random.default_rng(4), extent=30)
    assert ok.shape == (3, 2, 2, 3) and ok.dtype == bool
    assert ok[:, 0].all()  # noise-free: both detections right
    assert EX.DETECTIONS == ("rectified", "magnitude")
    # the rectified score is the bank's own (positive peaks are kept)
    from projtrack.experiments.correlators.recognition import _detected_scores
    X = letters.noisy(imgs, 0.3, np.random.default_rng(5))[0]
    assert np.allclose(_detected_scores(bank, X)[0], bank.decision_function(X))
    with pytest.raises(TypeError, match="ProjectionCorrelationClassifier"):
        EX.detection_study(C.Correlation2DClassifier().fit(imgs, labels), imgs, labels, [0.1], 1,
                           np.random.default_rng(0))

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
    ok = EX.noise_sweep({"a": bank, "b": bank}, imgs, labels, [0.0, 3.0], 3, np.random.default_rng(0), reference="a")
    assert ok.shape == (3, 2, 4, 3) and ok.dtype == bool
    assert ok[:, 0].all()  # no noise: the unit-energy bank is always right
    assert not ok[:, 1].all()  # heavy noise: some errors
    # identical results for any number of jobs and for the same seed
    again = EX.noise_sweep({"a": bank, "b": bank}, imgs, labels, [0.0, 3.0], 3, np.random.default_rng(0),
                           reference="a")
    assert np.array_equal(ok, again)
    with pytest.raises(ValueError, match="reference"):
        EX.noise_sweep({"a": bank}, imgs, labels, [0.1], 1, np.random.default_rng(0), reference="z")
    with pytest.raises(ValueError, match="labels"):
        EX.noise_sweep({"a": bank}, imgs, labels[:2], [0.1], 1, np.random.default_rng(0), reference="a")
    with pytest.raises(TypeError, match="fitted classifier"):
        EX.noise_sweep({"a": object()}, imgs, labels, [0.1], 1, np.random.default_rng(0), reference="a")


def test_noise_extent_study(small_bank):
    imgs, labels, bank = small_bank
    laws = {"g": ("gaussian", 1.0), "u": ("uniform", 1.0)}
    ok, summed = EX.noise_extent_study(bank, imgs, labels, [0.0, 0.4], (32, 8), laws, (0.0,), 2,
                                       np.random.default_rng(1))
    assert ok.shape == (2, 4, 2, 3) and summed.shape == (2, 2, 1, 3)
    assert ok[:, :, 0].all() and summed.all()  # noise-free: every rule right
    with pytest.raises(ValueError, match="laws"):
        EX.noise_extent_study(bank, imgs, labels, [0.1], (8,), {"x": ("poisson", 1.0)}, (), 1,
                              np.random.default_rng(1))
    with pytest.raises(ValueError, match="extents"):
        EX.noise_extent_study(bank, imgs, labels, [0.1], (0,), laws, (), 1, np.random.default_rng(1))


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
    d = EX.noisy_study(frame, ref, 0.0, 2, np.random.default_rng(0), extent=None, cyclic=True)
    assert list(d.columns) == list(EX.NOISY_QUANTITIES) and len(d) == 2
    clean = EX.noisy_measures(ref, ref, cyclic=True)
    assert np.allclose(d.iloc[0].to_numpy(), clean)  # sigma 0: the zero-mean letter itself
    lin = EX.noisy_study(frame, ref, 0.3, 3, np.random.default_rng(1), extent=32, cyclic=False)
    assert lin["2-D peak"].std() > 0
    hits = EX.peak_at_centre_study(frame, ref, 0.0, 2, np.random.default_rng(0))
    assert hits.shape == (2, 3) and hits.all()
    with pytest.raises(ValueError, match="same shape"):
        EX.noisy_study(frame, C_BIN, 0.1, 1, np.random.default_rng(0), extent=None, cyclic=True)
    with pytest.raises(ValueError, match="sigma"):
        EX.peak_at_centre_study(frame, ref, -1.0, 1, np.random.default_rng(0))


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


# ---------------------------------------------------------------------------- detectors
def test_detector_rule_study(small_bank):
    imgs, labels, _ = small_bank
    bank = C.ProjectionCorrelationClassifier(angles=(90, 0)).fit(imgs, labels)
    r = EX.detector_rule_study(bank, imgs, labels, [(0.0, 0), (0.0, 3)], 3, np.random.default_rng(0))
    assert r.shape == (3, 2, 3)
    assert np.all(r[:, 0] == 1.0)  # centred, noise-free: both rules right and agreeing
    assert np.all(r[:, 1, 1] == 1.0)  # the sum of separate peaks is shift invariant (cyclic shifts)
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
    with pytest.raises(ValueError, match="angles"):
        EX.noisy_pair_study(imgs[0], imgs[1], filt, [], 0.1, 1, np.random.default_rng(0))


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
def test_auto_cross_figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from projtrack.experiments.correlators import plots

    u = EX.unit_image(C_BIN)
    p = EX.unit_image(letters.render_letter("P"))
    fig = plots.auto_cross_figure([(u, "C"), (p, "P")], [(u, "auto", "C0"), (p, "cross", "C3")], u,
                                  cmap="gray", suptitle="t", normalize=True)
    try:
        assert len(fig.axes) == 5 and fig.axes[2].get_ylabel() == "corr. / auto peak"
        assert max(fig.axes[2].lines[0].get_ydata()) == pytest.approx(1.0)  # auto peak = 1
        with pytest.raises(ValueError, match="2 images"):
            plots.auto_cross_figure([(u, "C")], [(u, "auto", "C0")], u, cmap="gray", suptitle="t")
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

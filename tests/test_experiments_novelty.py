"""Tests of projtrack.experiments.novelty (the studies of the KL novelty chapter)."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from projtrack import novelty as nv  # noqa: E402
from projtrack.experiments import novelty as ex  # noqa: E402


def _recs(novel, ranks=None, shape=(4, 4)):
    """FrameRecords with the given novel flags (and ranks), the rest filler."""
    ranks = ranks or [1] * len(novel)
    return [nv.FrameRecord(frame=j + 1, iteration=1, novelty=0.5 if v else 0.0, novel=v,
                           vip=np.eye(1), fractions=np.array([0.9, 0.1]) if v else None,
                           rank=k, novel_pixels=np.zeros(shape, bool),
                           eigenvalues=np.ones(k), first_eigenimage=np.zeros(shape))
            for j, (v, k) in enumerate(zip(novel, ranks))]


def _toy_sequence(n=12, side=16, seed=0):
    rng = np.random.default_rng(seed)
    bg = rng.uniform(50, 200, (side, side))
    frames = np.repeat(bg[None], n, axis=0) + rng.normal(0, 1, (n, side, side))
    for t in range(n):          # a dark square walking right
        frames[t, 4:8, t % (side - 4):t % (side - 4) + 4] = 20.0
    return np.clip(np.rint(frames), 0, 255).astype(np.uint8), bg


# --- street -----------------------------------------------------------------------------------
def test_ghost_area_counts_path_pixels_above_threshold_per_person_area():
    bg = np.zeros((4, 4))
    img = bg.copy()
    img[0, :3] = 10.0           # three pixels differ by more than 8 ...
    img[3, 3] = 10.0            # ... and one off the paths
    paths = np.zeros((4, 4), bool)
    paths[0] = True
    assert ex.ghost_area(img, bg, paths, 2.0) == pytest.approx(1.5)
    assert ex.ghost_area(img, bg, paths, 2.0, pixel_threshold=10.0) == 0.0
    with pytest.raises(ValueError, match="people_per_frame"):
        ex.ghost_area(img, bg, paths, 0.0)
    with pytest.raises(ValueError, match="paths"):
        ex.ghost_area(img, bg, paths[:2], 1.0)


def test_order_and_entry_rules():
    quiet_then_entry = [True, False, False, True] + [False] * 3 + [True] * 5
    recs = _recs(quiet_then_entry)
    assert ex.order_2_4(recs)
    assert ex.entry_marked(recs)
    assert not ex.order_2_4(_recs([True] * 12))                  # every frame novel
    assert not ex.entry_marked(_recs([True] * 12))               # the early frames too
    assert not ex.order_2_4(_recs(quiet_then_entry, [1, 1, 1, 2] + [2] * 8))   # two kept at 4
    with pytest.raises(TypeError, match="FrameRecord"):
        ex.order_2_4([1, 2, 3, 4])


def test_record_table_matches_process_sequence():
    frames, _ = _toy_sequence(6)
    recs, table = ex.record_table(frames, 0.0, 1.0)
    assert list(table.index) == [1, 2, 3, 4, 5, 6]
    assert table["novel"].all() and table["eigenimages kept"].tolist() == [r.rank for r in recs]
    assert table.loc[2, "n_i"] == round(recs[1].novelty, 6)


# --- printed numbers ----------------------------------------------------------------------------
def test_frame_pair_has_the_asked_novelty_and_energy():
    a, b = ex.frame_pair(0.01, r=1.2)
    f = nv.NoveltyFilter(0.0, 1.0)
    f.partial_fit(a)
    assert f.novelty(b) == pytest.approx(0.01, rel=1e-9)
    assert b @ b == pytest.approx(1.2 * (a @ a))
    with pytest.raises(ValueError, match="n"):
        ex.frame_pair(1.5)


def test_printed_frame_2_and_4_arithmetic():
    assert ex.novelty_from_vip(ex.PRINTED_V2) == pytest.approx(0.001811, abs=5e-7)
    n4, f4 = ex.second_fraction(0.002498, 1)
    assert n4 == pytest.approx(0.002498) and f4 == pytest.approx([0.999375, 0.000625], abs=5e-7)
    t4 = ex.frame4_table()
    assert len(t4) == 6 and set(t4["route"]) == set(nv.METHODS)
    t8 = ex.frame8_table(priors=(2, 3), ratios=(1.0,))
    assert t8["earlier updates m"].tolist() == [2, 3]
    assert list(t8.columns) == ["earlier updates m", "F_8,2 at r = 1.0", "r for the printed F_8,2"]
    assert t8.loc[1, "r for the printed F_8,2"] == pytest.approx(0.988, abs=5e-4)
    with pytest.raises(ValueError, match="prior"):
        ex.second_fraction(0.01, 0)


# --- real video ---------------------------------------------------------------------------------
def test_residual_location_and_noise():
    rng = np.random.default_rng(0)
    frames = 100 + rng.normal(0, 1, (5, 8, 8))
    frames[2, 0, 0] += 50.0                     # one "person" pixel
    b, dev = ex.median_background(frames)
    np.testing.assert_allclose(b + dev, frames)
    table, noise_sd, still = ex.residual_location(dev, (8.0,), still_threshold=8.0)
    assert not still[0, 0] and still.sum() == 63
    assert 0.5 < noise_sd < 1.5
    assert table.index.tolist() == ["8 grey levels"]
    assert table.iloc[0, 0] == "0.0% - 1.6%"


def test_rank_margin_and_second_fraction():
    frames, _ = _toy_sequence(8)
    b, dev = ex.median_background(frames)
    assert ex.max_second_fraction(_recs([True, False])) == pytest.approx(0.1)
    assert ex.max_second_fraction(_recs([False])) == 0.0
    margin = ex.rank_margin(b, dev, (1, 4))
    assert list(margin.index) == [1, 4]
    assert margin.loc[4, "largest F_i,2"] >= margin.loc[1, "largest F_i,2"]


def test_calibrate_real_hits_both_printed_novelties():
    frames, _ = _toy_sequence(8, side=24)
    out = ex.calibrate_real(frames, np.random.default_rng(0), target_rms=40.0)
    assert ex.novelty_against_first(out["frames"], 2) == pytest.approx(0.0018, rel=1e-5)
    assert ex.novelty_against_first(out["frames (n_4)"], 4) == pytest.approx(0.0025, rel=1e-5)
    assert out["gain"] == pytest.approx(40.0 / np.sqrt(np.mean(frames[0].astype(float) ** 2)))
    assert out["added noise"] == pytest.approx(out["camera noise"] * np.sqrt(1 - out["gain"] ** 2))
    assert out["masks"].shape == frames.shape
    with pytest.raises(ValueError, match="darker"):
        ex.calibrate_real(frames, np.random.default_rng(0), target_rms=500.0)


def test_energy_kept_table():
    frames, _ = _toy_sequence(6)
    t = ex.energy_kept_table({"toy": frames}, settings=((0.0, 0.9999),))
    kept, best = t.loc[0, "energy kept (%)"], t.loc[0, "batch optimum (%)"]
    assert 99.99 - 1e-9 <= kept <= best + 1e-9 <= 100.0 + 1e-9
    assert t.loc[0, "loss / (1 - T_I)"] <= 1.0 + 1e-9


# --- aircraft -----------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def toy_classes():
    rng = np.random.default_rng(1)
    protos = {c: rng.random((6, 6)) for c in ("a", "b", "c")}
    train = {c: np.stack([p * s + 0.02 * rng.random((6, 6)) for s in np.linspace(0.6, 1.4, 8)])
             for c, p in protos.items()}
    tests = {c: np.stack([p * 1.1 + 0.02 * rng.random((6, 6)) for _ in range(4)]).reshape(4, -1)
             for c, p in protos.items()}
    bases = {c: nv.batch_kl(x) for c, x in train.items()}
    return train, tests, bases


def test_mean_image_and_subspace_recognition(toy_classes):
    train, tests, bases = toy_classes
    assert ex.mean_image_correct(train, tests) == 12
    assert ex.recognized(tests, bases, 1) == 12
    swapped = {"a": tests["b"]}
    assert ex.recognized(swapped, bases, 2) == 0 and ex.mean_image_correct(train, swapped) == 0
    table = ex.rank_claim_table(tests, bases, [1, 2])
    assert table["recognized (of 12)"].tolist() == [12, 12]
    assert (table["info a"] <= 1).all() and table.loc[2, "info a"] >= table.loc[1, "info a"]
    with pytest.raises(ValueError, match="class"):
        ex.recognized({"z": tests["a"]}, bases, 1)


def test_noisy_rates_and_effective_rank(toy_classes):
    _, tests, bases = toy_classes
    clean = ex.noisy_rates(np.random.default_rng(0), tests, bases, 0.0, 3)
    assert clean == [1.0, 1.0, 1.0]
    draws = ex.noise_rate_draws(tests, bases, 5.0, 3, np.random.default_rng(0), m_max=2)
    again = ex.noise_rate_draws(tests, bases, 5.0, 3, np.random.default_rng(0), m_max=2)
    assert draws.shape == (3, 2) and np.all(draws <= 1) and np.array_equal(draws, again)
    assert ex.effective_rank(np.array([0.5, 0.9, 1.0]), n_tests=48) == 3
    assert ex.effective_rank(np.array([0.5, 0.99, 1.0]), n_tests=48) == 2
    assert ex.info_rank([3.0, 1.0, 1.0], 0.6) == 1 and ex.info_rank([3.0, 1.0, 1.0], 0.7) == 2
    with pytest.raises(ValueError, match="sigma"):
        ex.noisy_rates(np.random.default_rng(0), tests, bases, -1.0, 3)


def test_classifier_tables(toy_classes):
    train, tests, _ = toy_classes
    x = np.concatenate([train[c] for c in train])
    y = np.repeat(list(train), 8)
    clf = nv.NoveltyClassifier(0.001, 0.99).fit(x, y)
    images = {c: tests[c].reshape(4, 6, 6) for c in tests}
    t2 = ex.novelty_table(clf, images, [0, 10, 20, 30], [10, 30], ["a", "b", "c"], ["c", "b", "a"])
    assert t2["Description"].tolist() == ["c 10°", "c 30°", "b 10°", "b 30°", "a 10°", "a 30°"]
    assert t2["Classification"].tolist() == ["c", "c", "b", "b", "a", "a"]
    clean = np.concatenate([images[c] for c in ("a", "b", "c")])
    truth = np.repeat(["a", "b", "c"], 4)
    rates = ex.classifier_noise_draw(np.random.default_rng(0), [clf, clf], clean, truth, [0.0, 1e3])
    assert rates[0] == (1.0, 1.0) and len(rates) == 2
    with pytest.raises(ValueError, match="test_rolls"):
        ex.novelty_table(clf, images, [0, 10], [5], ["a", "b", "c"])


# --- routes -------------------------------------------------------------------------------------
def test_vip_and_route_checks_are_exact_on_small_frames():
    rng = np.random.default_rng(2)
    frames = rng.random((5, 4, 4))
    eq3 = ex.vip_vs_large(frames)
    assert eq3["max rel. eigenvalue error"].max() < 1e-8
    assert eq3["non-zero eigenvalues"].tolist() == [5, 4]
    errs, filters = ex.route_errors(frames)
    assert set(filters) == set(nv.METHODS) and (errs["max rel. eigenvalue error"] < 1e-8).all()
    dups = ex.near_duplicate_study(frames[0], np.random.default_rng(0), deltas=(1.0,), n_copies=3)
    assert len(dups) == 2 and (dups["eigenimages kept (of 3)"] == 3).all()


def test_streaming_comparison_batch_is_best():
    frames, _ = _toy_sequence(20)
    out = ex.streaming_comparison(frames.astype(float), 0.0, 0.999)
    t = out["table"].set_index("method")
    assert out["K"] >= 2
    assert float(t.loc["batch SVD of R, top K (linear optimum)", "energy missed"]) <= \
        float(t.loc["adaptive recursive SVD (linear, K eigenimages)", "energy missed"]) * (1 + 1e-9)
    with pytest.raises(ValueError, match="one eigenimage"):
        ex.streaming_comparison(np.ones((4, 3, 3)))


# --- plots --------------------------------------------------------------------------------------
def test_plot_fig2_and_fig3_panels_layout():
    import matplotlib.pyplot as plt

    frames, _ = _toy_sequence(4)
    recs = nv.process_sequence(frames, 0.0, 1.0)
    fig = ex.plot_fig2_panels(recs, frames, [2, 3, 4])
    assert len(fig.axes) == 6 and fig.axes[0].get_title().startswith("frame 2: $n$ =")
    plt.close(fig)
    fig = ex.plot_fig3_panels(recs, frames, [3, 4])
    assert len(fig.axes) == 6 and fig.axes[2].get_title() == "first eigenimage"
    plt.close(fig)
    with pytest.raises(ValueError, match="picks"):
        ex.plot_fig2_panels(recs, frames, [9])
    with pytest.raises(ValueError, match="picks"):
        ex.plot_fig2_panels(recs, frames, [1, 2, 3, 4])


# --- printed numbers: the frame-8 closed form and the local-change bound -----------------------
def test_second_fraction_closed_form_matches_the_filter():
    for m, r in ((1, 1.0), (3, 0.9), (3, 1.1), (4, 0.5)):
        assert ex.second_fraction_closed_form(0.005841, m, r) == pytest.approx(
            float(ex.second_fraction(0.005841, m, r)[1][1]), rel=1e-7)
    roots = ex.energy_ratios_needed(0.005841, 0.001090, 2)
    assert len(roots) == 2 and roots[0] < 1 < roots[1]
    for r in roots:
        assert ex.second_fraction_closed_form(0.005841, 2, r) == pytest.approx(0.001090, rel=1e-9)
    assert ex.energy_ratios_needed(0.001, 0.4, 3) == []          # F_2 too large for that novelty
    with pytest.raises(ValueError, match="prior"):
        ex.second_fraction_closed_form(0.01, 0)


def test_local_change_bound_is_reached_by_rescaling_and_exceeded_otherwise():
    rng = np.random.default_rng(4)
    a = rng.uniform(20, 200, 400)
    region = np.zeros(400, bool)
    region[:300] = True
    p = float(a[region] @ a[region] / (a @ a))
    for r in (0.66, 0.95, 1.3):
        bound = ex.local_change_novelty_bound(p, r)
        assert ex.local_change_novelty(a, region, r) == pytest.approx(bound, abs=1e-12)
        assert ex.local_change_novelty(a, region, r, np.random.default_rng(1)) >= bound - 1e-12
    assert ex.local_change_novelty_bound(0.1, 0.5) == float("inf")     # too little energy to lose half
    p_star = ex.min_energy_share(0.005841, 0.659)
    assert ex.local_change_novelty_bound(p_star, 0.659) == pytest.approx(0.005841, rel=1e-6)
    assert 0.85 < p_star < 0.95
    with pytest.raises(ValueError, match="region"):
        ex.local_change_novelty(a, region[:10], 0.9)
    with pytest.raises(ValueError, match="too little"):
        ex.local_change_novelty(a, np.arange(400) < 5, 0.5)


# --- equations ----------------------------------------------------------------------------------
def test_eq12_first_form_is_i_minus_one_times_the_projection():
    frames, _ = _toy_sequence(6)
    for m in (1, 3, 5):
        out = ex.eq12_forms(frames[:m].astype(float), frames[m].astype(float))
        assert out["i"] == m + 1
        assert out["form 1 / form 2"] == pytest.approx(m, rel=1e-9)
        assert out["form 2 vs projection"] < 1e-9
        assert out["n (Eq. 7)"] == pytest.approx(out["|x - x_hat|^2 / |x|^2"], rel=1e-9)
    with pytest.raises(ValueError, match="test"):
        ex.eq12_forms(frames[:2], frames[0, :3])


def test_vip_ranks_of_r_and_c():
    rng = np.random.default_rng(0)
    bg, pats = rng.random(50), rng.random((2, 50))
    low = np.array([bg + rng.standard_normal(2) @ pats for _ in range(10)])
    assert ex.vip_ranks(low) == (3, 2)                            # the mean adds one
    assert ex.vip_ranks(np.array([c * bg for c in (1.0, 2.0, 3.0)])) == (1, 1)   # mean in the span
    assert ex.vip_ranks(rng.random((5, 30))) == (5, 4)


# --- the calibrated scene -------------------------------------------------------------------------
_SMALL = dict(shape=(48, 48), background_height=10.0, foreground_height=20.0, noise_std=1.2)


def test_novelty_against_first_is_the_filters():
    frames, _ = _toy_sequence(5)
    f = nv.NoveltyFilter(0.002, 0.95)
    f.partial_fit(frames[0])
    assert ex.novelty_against_first(frames, 4) == f.novelty(frames[3])
    with pytest.raises(ValueError, match="j"):
        ex.novelty_against_first(frames, 9)


def test_gain_and_contrast_calibrations_hit_their_targets():
    from projtrack.scenes.sequences import walking_sequence

    g = ex.calibrate_gain(9, np.random.default_rng(1), target_rms=60.0, **_SMALL)
    rms = [np.sqrt(np.mean(walking_sequence(r, n_frames=1, gain=g, **_SMALL).frames[0].astype(float) ** 2))
           for r in np.random.default_rng(1).spawn(9)]
    assert np.median(rms) == pytest.approx(60.0, abs=0.2)      # rounding to 8 bits makes it a fine staircase
    a, floor = ex.calibrate_contrast(9, np.random.default_rng(2), 0.004, 2, gain=g, **_SMALL)
    nov = [ex.novelty_against_first(walking_sequence(r, n_frames=2, people_contrast=a, gain=g, **_SMALL).frames, 2)
           for r in np.random.default_rng(2).spawn(9)]
    assert np.median(nov) == pytest.approx(0.004, rel=3e-2) and floor < 0.004   # a staircase on 48 x 48 px
    a, floor = ex.calibrate_contrast(9, np.random.default_rng(2), 1e-6, 2, gain=g, **_SMALL)
    assert np.isnan(a) and floor > 1e-6                           # noise alone is already more novel
    table = ex.calibrate_readings({"r": dict(background_speed=1.0)}, 5, 3, with_n4=False)
    assert list(table.columns) == ["reading", "gain", "contrast (n_2)", "floor"]


def test_frame2_quiet_reads_the_same_draws_as_reading_draws():
    kw = dict(_SMALL, gain=0.5, people_contrast=0.8, n_frames=20, entry_frame=6)
    table, nov = ex.reading_draws(4, np.random.default_rng(5), **kw)
    share, med = ex.frame2_quiet(4, np.random.default_rng(5), **{k: v for k, v in kw.items() if k != "n_frames"})
    assert share == float(np.mean(table["n_2"] <= 0.002)) and med == pytest.approx(float(np.median(table["n_2"])))
    again, _ = ex.reading_draws(4, np.random.default_rng(5), **kw)
    pd.testing.assert_frame_equal(table, again)
    assert nov.shape == (4, 20) and list(table.index) == [0, 1, 2, 3]


def test_sequence_readings_on_a_toy_sequence():
    frames, bg = _toy_sequence(20, side=24)
    masks = np.zeros(frames.shape, bool)
    masks[:, 4:8, :] = True
    out = ex.sequence_readings(frames, bg, masks, entry=8)
    assert out["updates (Fig. 3)"] >= out["updates (Fig. 2)"]
    assert np.isnan(out["memory, person"]) and np.isnan(out["F1 (Fig. 2)"])
    assert out["novelty"].shape == (20,) and out["novelty"][0] == 1.0
    assert {c for c in ex.CLAIMS if not c.startswith(("better novelty", "person remembered"))} == set(ex.real_claims(out))
    with pytest.raises(ValueError, match="masks"):
        ex.sequence_readings(frames, bg, masks[:3])
    with pytest.raises(ValueError, match="at least 20"):
        ex.sequence_readings(frames[:12], bg, masks[:12])


def test_ghost_rms_memory_and_novel_pixel_quality():
    bg = np.zeros((2, 2))
    paths = np.array([[True, False], [False, False]])
    assert ex.ghost_rms(np.full((2, 2), 3.0), bg, paths) == 3.0
    assert ex.ghost_rms(bg, bg, np.zeros((2, 2), bool)) == 0.0
    recs = _recs([True] * 5, shape=(2, 2))
    for r, g in zip(recs, (20.0, 12.0, 9.0, 7.0, 5.0)):     # the ghost fades below T_f = 8 at frame 4
        r.first_eigenimage[0, 0] = g
    obj = np.zeros((5, 2, 2), bool)
    obj[0, 0, 0] = True                                     # present in frame 1 only, left for good
    assert ex.memory_updates(recs, obj, obj, bg) == 2.0     # visible after the updates of frames 2, 3
    assert np.isnan(ex.memory_updates(recs, np.zeros_like(obj), obj, bg))
    figs = np.zeros((5, 2, 2), bool)
    figs[2:, 0, 0] = True
    recs[2].novel_pixels[0, 0] = recs[2].novel_pixels[1, 1] = True    # one hit, one smear
    recs[3].novel_pixels[0, 0] = True                                 # one hit; frame 5: one miss
    assert ex.novel_pixel_quality(recs, figs, 3) == pytest.approx(2 * 2 / (2 * 2 + 1 + 1))
    with pytest.raises(ValueError, match="masks"):
        ex.novel_pixel_quality(recs, figs[:2], 3)


def test_threshold_sweep_marks_fewer_frames_as_t_d_grows():
    t = ex.threshold_sweep(3, np.random.default_rng(0), (0.001, 0.01, 0.1), people_contrast=1.0, **_SMALL)
    assert list(t["T_d"]) == [0.001, 0.01, 0.1]
    assert t["updates, frames 2-7"].is_monotonic_decreasing and t["frame 8 novel"].is_monotonic_decreasing


def test_ghost_decay_follows_c_d_over_n():
    rng = np.random.default_rng(0)
    bg = 60.0 + 20.0 * rng.random((64, 64))
    d = ex.ghost_decay(bg, [-20.0, 30.0], dwell=2, n_frames=8, patch=(slice(5, 10), slice(5, 10)))
    assert len(d) == 16
    np.testing.assert_allclose(d["ghost"], d["c d / N"], rtol=0.02)


# --- readings and the verdict rule --------------------------------------------------------------
def _draw_rows():
    return pd.DataFrame({
        "order 2-4": [True, False, False, False], "entry marked": [True, True, False, False],
        "max kept (Fig. 2)": [1, 1, 1, 2], "max kept (Fig. 3)": [3, 4, 2, 3], "second at 8": [True, True, False, True],
        "ghost 10, Fig. 3": [0.1, 0.5, 0.2, 0.0], "ghost 20, Fig. 3": [0.1, 0.0, 0.2, 0.0],
        "ghost 10, frame 1": [0.5, 0.5, 0.5, 0.1], "ghost 20, frame 1": [0.5, 0.5, 0.5, 0.1],
        "ghost 10, mean": [0.1, 0.1, 0.3, 0.0], "ghost 20, mean": [0.1, 0.1, 0.1, 0.0],
        "updates (Fig. 3)": [24, 20, 22, 24], "updates (Fig. 2)": [20, 20, 21, 24],
        "background error 10, Fig. 3": [1.0, 2.0, 1.0, 1.0], "background error 10, Fig. 2": [2.0, 1.0, 2.0, 1.0],
        "background error 20, Fig. 3": [1.0, 1.0, 1.0, 1.0], "background error 20, Fig. 2": [2.0, 2.0, 2.0, 1.0],
        "F1 (Fig. 3)": [0.8, 0.7, 0.9, 0.5], "F1 (Fig. 2)": [0.7, 0.8, 0.8, 0.5],
        "memory, person": [2.0, 0.0, 1.0, np.nan], "memory, walkers": [1.0, 1.0, 1.0, 0.0],
        **{f"ghost {j}, {k}, T_f {t}": v for t, (e1, f1) in {12: ([0.1] * 4, [0.5] * 4), 16: ([0.1] * 4, [0.1] * 4)}.items()
           for j in (10, 20) for k, v in (("Fig. 3", e1), ("frame 1", f1), ("mean", e1))},
        **{f"memory, {w}, T_f {t}": [0.0] * 4 for t in (12, 16) for w in ("person", "walkers")}})


def test_claim_shares_and_tables():
    s = ex.claim_shares(_draw_rows())
    assert s["frames 2-3 quiet, 4 novel"] == 0.25 and s["entry marked"] == 0.5
    assert s["one eigenimage throughout"] == 0.75 and s["up to 3, second from 8"] == 0.5
    assert s["first eigenimage clean"] == 0.5            # draw 3 passes but so does its frame 1
    assert s["first eigenimage clean (T_f 12)"] == 1.0 and s["first eigenimage clean (T_f 16)"] == 0.0
    assert s["mean of the frames clean"] == 0.5           # draw 2 fails at frame 10, draw 3's frame 1 passes too
    assert s["more updates"] == 0.5 and s["cleaner first eigenimage"] == 0.5
    assert s["better novelty data"] == 0.5 and s["person remembered longer"] == 0.25
    t = ex.claim_table({"x": s, "y": s}, ["entry marked"], {"extra": {"x": 1.5}}, readings=["x"])
    assert t.to_dict("records") == [{"reading": "x", "entry marked": 0.5, "extra": 1.5}]
    assert ex.medians({"x": _draw_rows()}, {"F1": "F1 (Fig. 3)"}) == {"F1": {"x": 0.75}}
    assert ex.shares_text({"x": 0.5, "y": 0.25}) == "0.500 / 0.250"
    real = ex.real_table({"v": _draw_rows().iloc[0].to_dict()}, ["entry marked", "better novelty data"],
                         {"n": {"v": "0.1"}})
    assert real.to_dict("records") == [{"video": "v", "entry marked": "yes", "n": "0.1"}]
    with pytest.raises(ValueError, match="unknown claims"):
        ex.claim_shares(_draw_rows(), ["nope"])
    with pytest.raises(ValueError, match="non-empty"):
        ex.claim_shares(_draw_rows().iloc[:0])


def test_verdict_rule_and_its_edge():
    assert ex.verdict({"a": 0.3, "b": 0.6}, None, 40) == ("qualitative", ["b"], [])
    assert ex.verdict({"a": 0.3}, {"video": True}, 40) == ("qualitative", ["video"], [])
    assert ex.verdict({"a": 0.3, "b": 0.45}, {"video": False}, 40) == ("differs", [], [])
    assert ex.verdict({"a": 0.5}, None, 40) == ("qualitative", ["a"], ["a"])          # one draw from failing
    assert ex.verdict({"a": 0.475}, None, 40) == ("differs", [], ["a"])              # one draw from passing
    assert ex.verdict({"a": 0.5, "b": 0.9}, None, 40)[2] == []                        # b decides firmly
    assert ex.share_tolerance(40).atol == pytest.approx(0.025)


# --- aircraft additions -------------------------------------------------------------------------
def test_effective_rank_curve_and_threshold_sweep(toy_classes):
    train, tests, bases = toy_classes
    curve = ex.effective_rank_curve(tests, bases, (0.0, 50.0), 2, 0, m_max=3)
    pd.testing.assert_frame_equal(curve, ex.effective_rank_curve(tests, bases, (0.0, 50.0), 2, 0, m_max=3))
    assert list(curve["sigma"]) == [0.0, 50.0]
    assert curve.loc[0, "recognized, best m"] == 12.0 and curve.loc[0, "effective rank"] == 1
    assert curve["three suffice"].dtype == bool
    sweep = ex.aircraft_threshold_sweep(train, {c: tests[c].reshape(4, 6, 6) for c in tests}, (0.0, 0.5))
    assert list(sweep.columns) == ["T_d", "images used per class", "eigenimages per class", "recognized"]
    assert sweep.loc[0, "images used per class"] == "8 of 8" and sweep.loc[0, "recognized"].endswith("of 12")


def test_calibrate_person_hits_the_printed_n8_and_the_readings_carry_it():
    from projtrack.scenes.sequences import walking_sequence
    kw = dict(_SMALL, gain=0.5, entry_frame=6)
    a = ex.calibrate_person(9, np.random.default_rng(4), 0.01, 0.6, **kw)
    n8 = [nv.process_sequence(walking_sequence(r, n_frames=6, people_contrast=0.6, foreground_contrast=a, **kw).frames,
                              *ex.FIG2_SETTINGS)[5].novelty for r in np.random.default_rng(4).spawn(9)]
    assert np.median(n8) == pytest.approx(0.01, rel=3e-2)           # a staircase of rounded 48 x 48 frames
    with pytest.raises(ValueError, match="no person contrast"):
        ex.calibrate_person(5, np.random.default_rng(4), 0.9, 0.6, **kw)
    table = ex.calibrate_readings({"r": dict(background_speed=1.0)}, 3, 3, with_n4=False, with_n8=True)
    assert list(table.columns) == ["reading", "gain", "contrast (n_2)", "floor", "person (n_8)"]


def test_mean_of_the_frames_goes_through_the_ghost_test():
    frames, bg = _toy_sequence(20, side=24)
    masks = np.zeros(frames.shape, bool)
    masks[:, 4:8, :] = True
    out = ex.sequence_readings(frames, bg, masks, entry=8)
    paths, area = masks[:10].any(axis=0), float(masks[:10].sum(axis=(1, 2)).mean())
    assert out["ghost 10, mean"] == ex.ghost_area(frames[:10].astype(float).mean(axis=0), bg, paths, area)
    d = pd.DataFrame([{"ghost 10, mean": 0.1, "ghost 20, mean": 0.2, "ghost 10, frame 1": 0.9, "ghost 20, frame 1": 0.9},
                      {"ghost 10, mean": 0.3, "ghost 20, mean": 0.2, "ghost 10, frame 1": 0.9, "ghost 20, frame 1": 0.9}])
    assert ex.CLAIMS["mean of the frames clean"](d).tolist() == [True, False]


def test_route_angles_compare_leading_subspaces_not_the_full_span():
    rng = np.random.default_rng(3)
    frames = rng.random((4, 5, 5))
    errs, filters = ex.route_errors(frames)
    assert (errs["largest principal angle (rad)"] < 1e-8).all()


def test_centred_eigenvalues_are_those_of_c():
    rng = np.random.default_rng(6)
    x = rng.random((5, 3, 4)) + 2.0
    lam = ex.centred_eigenvalues(x)
    xc = x.reshape(5, -1) - x.reshape(5, -1).mean(axis=0)
    big = np.linalg.eigvalsh(xc.T @ xc / 5)[::-1][:5]
    assert lam == pytest.approx(big, abs=1e-12) and lam[-1] == pytest.approx(0.0, abs=1e-12)   # rank I - 1
    assert ex.info_rank(lam, 0.999999) == 4 < ex.info_rank(nv.batch_kl(x).eigenvalues, 0.999999) + 1


def test_mean_outside_span_decides_whether_r_has_one_rank_more():
    rng = np.random.default_rng(8)
    bg, pat = rng.random(64), rng.random((3, 64))
    with_bg = np.array([bg + rng.standard_normal(3) @ pat for _ in range(10)])
    no_bg = np.array([rng.standard_normal(3) @ pat for _ in range(10)])
    assert ex.mean_outside_span(with_bg) and ex.vip_ranks(with_bg) == (4, 3)
    assert not ex.mean_outside_span(no_bg) and ex.vip_ranks(no_bg) == (3, 3)

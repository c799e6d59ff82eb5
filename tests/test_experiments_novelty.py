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


def test_ghost_study_keys_and_frame_one_baseline():
    frames, bg = _toy_sequence()
    masks = np.zeros(frames.shape, bool)
    masks[:, 4:8, :] = True
    recs = nv.process_sequence(frames, 0.001, 0.9995)
    out = ex.ghost_study(frames, bg, masks, recs, recs, at=(5,))
    assert set(out) == {5}
    assert set(out[5]) == {"first eigenimage, Fig. 3 settings", "first eigenimage, Fig. 2 settings",
                           "running temporal mean", "frame 1"}
    assert out[5]["first eigenimage, Fig. 3 settings"] == out[5]["first eigenimage, Fig. 2 settings"]
    with pytest.raises(ValueError, match="at"):
        ex.ghost_study(frames, bg, masks, recs, recs, at=(99,))


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


def test_fig2_stats_reads_the_records():
    novel = [True, False, False, True] + [False] * 3 + [True] * 5
    s = ex.fig2_stats(_recs(novel), 8)
    assert s["frame 2 novel"] is False and s["frame 4 novel"] is True
    assert s["F_4,1"] == 0.9 and s["updates, frames 2-7"] == 1
    assert s["every frame >= 8 novel"] and s["paper's order at 2-4"]
    assert np.isnan(ex.fig2_stats(_recs([True] + [False] * 11), 8)["F_4,1"])


def test_synthetic_draws_are_reproducible_and_shaped():
    kw = dict(shape=(32, 32))
    seeds, nov = ex.synthetic_draws(2, np.random.default_rng(3), **kw)
    again, nov2 = ex.synthetic_draws(2, np.random.default_rng(3), **kw)
    assert nov.shape == (2, 24) and list(seeds.index) == [0, 1]
    pd.testing.assert_frame_equal(seeds, again)
    np.testing.assert_array_equal(nov, nov2)
    one = ex.synthetic_draw(np.random.default_rng(3).spawn(2)[1], **kw)
    np.testing.assert_array_equal(one.pop("novelty"), nov[1])
    assert one["n_2"] == seeds.loc[1, "n_2"]
    with pytest.raises(ValueError, match="n_draws"):
        ex.synthetic_draws(0, np.random.default_rng(3))


def test_record_table_matches_process_sequence():
    frames, _ = _toy_sequence(6)
    recs, table = ex.record_table(frames, 0.0, 1.0)
    assert list(table.index) == [1, 2, 3, 4, 5, 6]
    assert table["novel"].all() and table["eigenimages kept"].tolist() == [r.rank for r in recs]
    assert table.loc[2, "n_i"] == round(recs[1].novelty, 6)


def test_jitter_sensitivity_one_draw_per_level():
    sens = ex.jitter_sensitivity(1, 0, (0.0,))
    d = ex.jitter_draw(np.random.default_rng(0).spawn(1)[0], 0.0)
    assert sens.shape[0] == 1
    assert sens.loc[0, "median n_2"] == round(d["n_2"], 4)
    assert sens.loc[0, "entry marked (fraction)"] == float(d["entry"])
    with pytest.raises(ValueError, match="jitter"):
        ex.jitter_draw(np.random.default_rng(0), -1.0)


def test_novel_pixel_scores_against_ground_truth():
    recs = _recs([True, True, True], shape=(2, 2))
    recs[2].novel_pixels[0, 0] = True              # the person's pixel found, no false alarm
    masks = np.zeros((3, 2, 2), bool)
    fg = np.zeros((3, 2, 2), bool)
    fg[2, 0, 0] = masks[2, 0, 0] = True
    rows = ex.novel_pixel_scores(recs, masks, fg, 3)
    assert rows == [{"frame": 3, "person pixels detected": 1.0, "false alarms on background": 0.0}]
    with pytest.raises(ValueError, match="masks"):
        ex.novel_pixel_scores(recs, masks[:2], fg[:2], 3)


# --- summaries --------------------------------------------------------------------------------
G3, G2 = "first eigenimage, Fig. 3 settings", "first eigenimage, Fig. 2 settings"


def _seed_table():
    """Four hand-made draws with the columns synthetic_draws returns."""
    s = pd.DataFrame({
        "n_2": [0.001, 0.002, 0.003, 0.004], "frame 2 novel": [False, False, True, False],
        "n_4": [0.002, 0.003, 0.004, 0.005], "frame 4 novel": [True, True, True, False],
        "F_4,1": [0.99, 0.98, 0.97, np.nan], "rank at 4": [1, 2, 1, 1],
        "paper's order at 2-4": [True, False, False, False], "updates, frames 2-7": [0, 2, 3, 1],
        "every frame >= 8 novel": [True, True, False, True], "entry marked": [True, False, False, False],
        "n_8": [0.005, 0.006, 0.007, 0.008], "max eigenimages kept": [1, 2, 1, 1],
        "same updates under both settings": [True, False, False, False]})
    for j, (a3, a2) in {10: ([0.1, 0.1, 0.5, 0.2], [0.3, 0.2, 0.4, 0.3]),
                        20: ([0.2, 0.1, 0.3, 0.4], [0.1, 0.2, 0.4, 0.5])}.items():
        s[f"ghost {j}: {G3}"], s[f"ghost {j}: {G2}"] = a3, a2
        s[f"ghost {j}: running temporal mean"] = [0.0, 0.3, 0.3, 0.3]
        s[f"ghost {j}: frame 1"] = [1.0] * 4
    return s


def test_quartiles_and_fractions_text():
    assert ex.quartiles([1, 2, 3, 4, np.nan]) == "2.5000 [1.7500, 3.2500]"
    assert ex.quartiles([1.0], 1) == "1.0 [1.0, 1.0]"
    rec = _recs([True, False])
    assert ex.fractions_text(rec[0]) == "[0.900000, 0.100000]"
    assert ex.fractions_text(rec[1]) == "none (not novel)"
    with pytest.raises(TypeError, match="FrameRecord"):
        ex.fractions_text(0.5)
    with pytest.raises(ValueError, match="digits"):
        ex.quartiles([1.0], -1)


def test_fig2_fractions_and_summary():
    s = _seed_table()
    fr = ex.fig2_fractions(s)
    assert fr == {"frame 2 not novel": 0.75, "frame 4 novel, one eigenimage": 0.5,
                  "paper's order at 2-4": 0.25, "every frame >= 8 novel": 0.75, "entry marked": 0.25}
    table = ex.fig2_seed_summary(s)
    col = table["synthetic, 4 draws"]
    assert col["frame 2 not novel (fraction of draws)"] == "0.75"
    assert col["F_4,1 where frame 4 is novel (3 draws), median [quartiles]"] == "0.980000 [0.975000, 0.985000]"
    assert col["updates among frames 2-7, median [range]"] == "1.5 [0, 3]"
    assert col["max eigenimages kept (largest over draws)"] == "2"
    assert table.loc["n_8, median [quartiles]", "paper"] == "0.0058"
    with pytest.raises(ValueError, match="entry marked"):
        ex.fig2_fractions(s.drop(columns="entry marked"))
    with pytest.raises(TypeError, match="DataFrame"):
        ex.fig2_seed_summary(s.to_dict())
    with pytest.raises(ValueError, match="at least one"):
        ex.fig2_fractions(s.iloc[:0])


def test_cleaner_fraction_counts_only_draws_whose_updates_differ():
    frac, n = ex.cleaner_fraction(_seed_table())
    assert n == 3 and frac == pytest.approx(2 / 3)      # draws 1 and 3 (draw 0 updates the same)
    same = _seed_table().assign(**{"same updates under both settings": True})
    frac, n = ex.cleaner_fraction(same)
    assert n == 0 and np.isnan(frac)
    with pytest.raises(ValueError, match="ghost 30"):
        ex.cleaner_fraction(_seed_table(), at=(30,))


def test_ghost_table_matches_ghost_study_and_rms_ratio():
    frames, bg = _toy_sequence()
    masks = np.zeros(frames.shape, bool)
    masks[:, 4:8, :] = True
    recs = nv.process_sequence(frames, 0.001, 0.9995)
    real = ex.ghost_study(frames, bg, masks, recs, recs, at=(5, 12))
    t = ex.ghost_table(real, frames, bg, recs, recs, _seed_table(), real_at=(5, 12))
    assert list(t.index) == [G3, G2, "running temporal mean", "frame 1"]
    assert t.loc["frame 1", "real: ghost area, frame 12"] == round(real[12]["frame 1"], 2)
    assert t.loc["frame 1", "real: RMS ratio at 12"] == round(ex.rms_ratio(frames[0], frames, bg), 3)
    assert t.loc[G3, "synthetic: ghost area, frame 10, median [10-90 %]"] == "0.15 [0.10, 0.41]"
    assert list(t["synthetic: passes at 10 and 20 (fraction)"]) == [0.5, 0.25, 0.25, 0.0]
    with pytest.raises(ValueError, match="real_ghosts lacks"):
        ex.ghost_table(real, frames, bg, recs, recs, _seed_table(), real_at=(7,))
    with pytest.raises(ValueError, match="ghost 30"):
        ex.ghost_table(real, frames, bg, recs, recs, _seed_table(), real_at=(5,), synthetic_at=(30,))


def test_threshold_sensitivity_equals_ghost_area_per_threshold():
    bg = np.zeros((4, 4))
    masks = np.zeros((3, 4, 4), bool)
    masks[0, 0, :2] = True
    masks[1, 0, 2:] = True
    masks[2, 1, :2] = True
    img = np.zeros((4, 4))
    img[0] = [10.0, 20.0, 40.0, 0.0]
    per_frame = np.stack([img, img, 2 * img])
    t = ex.threshold_sensitivity({"one": img, "moving": per_frame}, bg, masks, at=(2, 3),
                                 thresholds=(8, 16, 32))
    assert list(t.index) == [8, 16, 32]
    assert list(t.columns) == ["one, frame 2", "moving, frame 2", "one, frame 3", "moving, frame 3"]
    assert t.loc[8.0, "one, frame 2"] == 1.5          # 3 pixels above 8 on the paths, 2 px per frame
    assert t.loc[32.0, "moving, frame 3"] == 1.0   # 2 * img: 40 and 80 above 32
    assert t.loc[16.0, "one, frame 3"] == round(ex.ghost_area(img, bg, masks[:3].any(axis=0), 2.0, 16), 2)
    with pytest.raises(ValueError, match="images"):
        ex.threshold_sensitivity({"short": per_frame[:1]}, bg, masks, at=(2,))
    with pytest.raises(ValueError, match="at"):
        ex.threshold_sensitivity({"one": img}, bg, masks, at=(4,))
    with pytest.raises(TypeError, match="mapping"):
        ex.threshold_sensitivity([img], bg, masks)


def test_draw_verdict_and_note_state_the_half_rule():
    assert ex.draw_verdict(True, 0.5) == "qualitative"
    assert ex.draw_verdict(True, 0.49) == "differs"
    assert ex.draw_verdict(False, 1.0) == "differs"
    assert ex.verdict_note(True, 0.6) == "seen on both stand-ins"
    assert ex.verdict_note(False, 0.0) == "not seen: not on the real video, in none of the draws"
    assert ex.verdict_note(True, 0.25) == "not seen: only in 25% of the draws"
    with pytest.raises(ValueError, match="fraction"):
        ex.draw_verdict(True, 1.5)


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
    assert list(t8.index) == [2, 3] and list(t8.columns) == ["novel frames so far", "F_8,2 at r = 1.0"]
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


def test_contrast_calibration_hits_the_target_novelty():
    frames, _ = _toy_sequence(8)
    b, dev = ex.median_background(frames)
    n_full = ex.first_novelty(ex.contrast_scaled(b, dev, 1.0))
    alpha = ex.calibrate_contrast(b, dev, target=n_full / 4, lo=0.01, hi=1.0)
    assert ex.first_novelty(ex.contrast_scaled(b, dev, alpha)) == pytest.approx(n_full / 4, rel=1e-5)
    recs, row = ex.fig2_pattern(frames)
    assert len(recs) == 8 and row["n_2"] == f"{recs[1].novelty:.4f}"
    assert ex.max_second_fraction(_recs([True, False])) == pytest.approx(0.1)
    assert ex.max_second_fraction(_recs([False])) == 0.0
    margin = ex.rank_margin(b, dev, (1, 4))
    assert list(margin.index) == [1, 4]
    with pytest.raises(ValueError, match="frames"):
        ex.fig2_pattern(frames[:5])


def test_energy_kept_and_rms_ratio():
    frames, bg = _toy_sequence(6)
    t = ex.energy_kept_table({"toy": frames}, settings=((0.0, 0.9999),))
    kept, best = (float(t.loc[0, c].rstrip("%")) for c in ("energy kept", "batch optimum, same number"))
    assert 99.99 - 1e-9 <= kept <= best <= 100.0
    assert float(t.loc[0, "loss / (1 - T_I)"]) <= 1.0 + 1e-9
    f = np.stack([bg + 2.0, bg - 2.0])
    assert ex.rms_ratio(bg + 1.0, f, bg) == pytest.approx(0.5)
    assert ex.rms_ratio(bg, f, bg) == 0.0


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
def test_plot_frame_panels_layout():
    import matplotlib.pyplot as plt

    frames, _ = _toy_sequence(4)
    recs = nv.process_sequence(frames, 0.0, 1.0)
    fig = ex.plot_frame_panels(recs, frames, [3], "t", show_eigenimage=True)
    assert len(fig.axes) == 4 and fig.axes[0].get_title() == "input"
    plt.close(fig)
    with pytest.raises(ValueError, match="picks"):
        ex.plot_frame_panels(recs, frames, [9], "t")

"""Tests of projtrack.experiments.hough (the studies of the Hough chapter)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import projtrack.hough as hough  # noqa: E402
from projtrack.experiments import hough as ex  # noqa: E402
from projtrack.experiments.hough.plots import draw_initiation  # noqa: E402
from projtrack.montecarlo import run as mc_run  # noqa: E402


def test_experiment_names_live_in_the_experiment_layer_only():
    for name in ("match_lines", "evaluate_initiation", "accuracy_experiment"):
        assert callable(getattr(ex, name)) and name in ex.__all__
        assert not hasattr(hough, name) and name not in hough.__all__


def test_match_lines_assigns_the_line_through_a_target_and_rejects_a_false_one():
    pts = np.array([[128.0, y] for y in range(60, 200, 10)] + [[10.0, 10.0], [240.0, 30.0]])
    lab = np.array([0] * 14 + [-1, -1])
    owner = ex.match_lines([(0.0, 0.0), (60.0, 90.0)], pts, lab, (256, 256))
    assert owner.tolist() == [0, -1]
    with pytest.raises(ValueError, match="min_fraction"):
        ex.match_lines([(0.0, 0.0)], pts, lab, (256, 256), min_fraction=0.0)
    with pytest.raises(ValueError, match="labels"):
        ex.match_lines([(0.0, 0.0)], pts, lab[:-1], (256, 256))


def test_salvo_scene_same_seed_same_trajectories_at_any_p_detect():
    t1, f1 = ex.salvo_scene(5, 1.0)
    t9, f9 = ex.salvo_scene(5, 0.9)
    assert len(t1) == 6 and [a.launch_time for a in t1] == [a.launch_time for a in t9]
    assert sum(map(len, f9.points)) < sum(map(len, f1.points))
    with pytest.raises(ValueError, match="p_detect"):
        ex.salvo_scene(5, 1.5)
    with pytest.raises(TypeError, match="seed"):
        ex.salvo_scene(5.0, 1.0)


def test_salvo_trial_counts_are_consistent_and_reproducible():
    a = mc_run(ex.salvo_trial, 1, np.random.default_rng(3), 3.0, True)[0]
    b = mc_run(ex.salvo_trial, 1, np.random.default_rng(3), 3.0, True)[0]
    assert a == b
    assert 0 <= a["found"] <= a["targets"] <= 6
    assert a["true lines"] + a["false lines"] >= a["found"]
    assert len(a["diag"]) == 6 and all(d[0] in (True, False) for d in a["diag"])
    assert all(s9 > 0 and s1 > 0 for _, s1, s9 in a["speeds"])
    with pytest.raises(TypeError, match="Generator"):
        ex.salvo_trial(3)
    with pytest.raises(ValueError, match="ratio"):
        ex.salvo_trial(np.random.default_rng(0), 0.0)


def test_speeds_by_target_and_reading_trial():
    assert ex.speeds_by_target({"tracks": [{"target": 2, "speed": 7.5}]}) == {2: 7.5}
    with pytest.raises(TypeError):
        ex.speeds_by_target([])
    out = ex.reading_trial(np.random.default_rng(1), {"accel_range": (0.3, 0.5)}, (6, 11))
    assert set(out) == {6.0, 11.0, "extent"} and 0 < out["extent"] <= 30 * 5 + 1e-9
    for f in (6.0, 11.0):
        found, targets, false, perfect = out[f]
        assert 0 <= found <= targets <= 6 and false >= 0 and perfect == (found == targets and false == 0)
    assert out[11.0][2] <= out[6.0][2]  # a higher floor cannot add false tracks on the same frames
    with pytest.raises(TypeError, match="launch_kw"):
        ex.reading_trial(np.random.default_rng(1), None)
    with pytest.raises(ValueError, match="floors"):
        ex.reading_trial(np.random.default_rng(1), {}, ())


def test_continuous_run_small_and_never_detected_agrees():
    kw = dict(n_targets=3, duration=20.0)
    for floor in (None, 10):
        r = ex.continuous_run(np.random.default_rng(7), floor, **kw)
        assert 0 <= r["seen"] <= r["crossed"] <= 3 and len(r["fr"].points) == 80
        assert r["in_view"].shape == r["found"].shape == (4, 3) and r["false"].shape == (4,)
        assert not np.any(r["found"] & (r["in_view"] == 0))  # found only where in view
        assert ex.never_detected(np.random.default_rng(7), floor, **kw) == r["crossed"] - r["seen"]
    with pytest.raises(ValueError, match="duration"):
        ex.never_detected(np.random.default_rng(7), duration=0.0)


def test_possible_detections_readings():
    in_view = np.array([[20, 1], [12, 0], [20, 20]])
    found = np.array([[True, False], [True, False], [False, True]])
    run = {"in_view": in_view, "found": found}
    assert ex.possible_detections(run, "1 of 20 frames") == (5, 3)
    assert ex.possible_detections(run, "15 of 20 frames") == (3, 2)
    assert ex.possible_detections(run, "20 of 20 frames") == (3, 2)
    # target 0: 52 frames in view -> round(2.6) = 3 possible, found in 2 segments; target 1: 21 -> 1, found once
    assert ex.possible_detections(run, "one per 5 s in view") == (4, 3)
    with pytest.raises(ValueError, match="reading"):
        ex.possible_detections(run, "half of the frames")
    with pytest.raises(TypeError, match="continuous_run"):
        ex.possible_detections({"in_view": in_view}, "1 of 20 frames")


def test_run_outcome_single_run():
    in_view = np.array([[20, 1], [12, 0], [20, 20]])
    found = np.array([[True, False], [True, False], [False, True]])
    run = {"in_view": in_view, "found": found, "false": np.array([0, 1, 0]), "crossed": 2, "seen": 2}
    o = ex.run_outcome(run, "1 of 20 frames", (0.5, 0.7))
    assert o["rate"] == pytest.approx(3 / 5) and o["matched"] and o["all seen"] and not o["no false"]
    o = ex.run_outcome({**run, "false": np.zeros(3), "seen": 1}, "one per 5 s in view", (0.8, 0.9))
    assert o["rate"] == pytest.approx(3 / 4) and not o["matched"] and not o["all seen"] and o["no false"]
    with pytest.raises(ValueError, match="interval"):
        ex.run_outcome(run, "1 of 20 frames", (0.9, 0.8))


def test_accuracy_experiment_small():
    r = ex.accuracy_experiment(np.random.default_rng(0), 10.0, 0.25, n_targets=4, return_errors=True)
    assert r["n_p"] == 20 and r["errors"].shape == (4, 4)
    assert r["std_y"] < 3 * r["pred_y"]
    with pytest.raises(ValueError, match="frame_time"):
        ex.accuracy_experiment(np.random.default_rng(0), 10.0, 0.0)


def test_draw_initiation_draws_lines_and_predictions():
    trajs, fr = ex.salvo_scene(11, 1.0)
    init = hough.TrackInitiator()
    res = ex.evaluate_initiation(init, fr, trajs)
    fig, ax = plt.subplots()
    draw_initiation(ax, fr, trajs, init, res, "t")
    n_conf = sum(t.confirmed for t in init.tracks_)
    assert len(ax.texts) == n_conf  # one prediction arrow per confirmed track
    assert ax.get_title() == "t" and ax.get_xlim() == (0, 256)
    plt.close(fig)


def test_noisy_scene_and_plain_and_thresholded():
    tr, fr = ex.noisy_scene(np.random.default_rng(2), n_noise=3, n_targets=2)
    assert len(tr) == 2 and len(fr.points) == 21
    both = ex.plain_and_thresholded(fr, tr)
    assert set(both) == {"plain", "thresholded"}
    assert both["thresholded"][0].thresholded and not both["plain"][0].thresholded
    with pytest.raises(TypeError, match="Frames"):
        ex.plain_and_thresholded(fr.points, tr)
    with pytest.raises(ValueError, match="n_noise"):
        ex.noisy_scene(np.random.default_rng(2), n_noise=-1)


def test_rule_counts():
    c = ex.rule_counts(np.random.default_rng(4), {"printed": {}, "ridge-free": {"exclude_ridge": 1}})
    assert set(c) == {"printed", "ridge-free"}
    for v in c.values():
        found, lines, conf = v["plain"]
        assert 0 <= found <= 5 and 0 <= conf <= lines
    with pytest.raises(TypeError, match="rules"):
        ex.rule_counts(np.random.default_rng(4), [("printed", {})])


def test_accuracy_sweep_rows_raw_and_within_counts():
    import pandas as pd

    stops = ex.STOPS[:2]
    rows, raw = ex.accuracy_sweep([10.0], [0.25], stops, n_targets=3)
    assert [r["stop"] for r in rows] == ["75 % rule", "all points"]
    assert set(raw) == {("75 % rule", 10.0, 0.25), ("all points", 10.0, 0.25)}
    assert rows[0]["predr_x"] > rows[0]["pred_x"]  # rounding adds variance
    table = pd.DataFrame(rows)
    w = ex.within_counts(raw, table, "75 % rule", False, False)
    assert set(w) == {"x", "y", "vx", "vy"} and all(v in (0, 1) for v in w.values())
    # a huge prediction: everything within
    big = table.assign(pred_x=1e9, pred_y=1e9, pred_vx=1e9, pred_vy=1e9)
    assert ex.within_counts(raw, big, "all points", False, False) == {"x": 1, "y": 1, "vx": 1, "vy": 1}
    with pytest.raises(ValueError, match="stop_name"):
        ex.within_counts(raw, table, "no such rule", False, False)
    with pytest.raises(ValueError, match="speeds"):
        ex.accuracy_sweep([0.0], [0.25])


def test_accuracy_target_one_trial_and_its_checks():
    r = ex.accuracy_target(np.random.default_rng(5), 10.0, 0.25)
    assert set(r) == {"errors", "confirmed", "fallback", "n_seen"}
    assert r["errors"].shape == (4,) and 1 <= r["n_seen"] <= 20
    assert abs(r["errors"][1]) < 4.0  # across the track: within the strip
    assert np.array_equal(r["errors"], ex.accuracy_target(np.random.default_rng(5), 10.0, 0.25)["errors"])
    with pytest.raises(TypeError, match="rng"):
        ex.accuracy_target(5, 10.0, 0.25)
    with pytest.raises(ValueError, match="theta_range_deg"):
        ex.accuracy_target(np.random.default_rng(5), 10.0, 0.25, theta_range_deg=(180.0, 90.0))
    with pytest.raises(ValueError, match="frames"):
        ex.accuracy_target(np.random.default_rng(5), 10.0, 4.0)
    with pytest.raises(ValueError, match="n_targets"):
        ex.accuracy_experiment(np.random.default_rng(0), 10.0, 0.25, n_targets=0)


def test_accuracy_experiment_same_result_serial_and_parallel():
    kw = dict(n_targets=4, return_errors=True)
    a = ex.accuracy_experiment(np.random.default_rng(11), 20.0, 0.25, n_jobs=1, **kw)
    b = ex.accuracy_experiment(np.random.default_rng(11), 20.0, 0.25, n_jobs=2, **kw)
    assert np.array_equal(a["errors"], b["errors"]) and np.array_equal(a["n_seen"], b["n_seen"])
    assert {k: v for k, v in a.items() if k not in ("errors", "n_seen")} == \
        {k: v for k, v in b.items() if k not in ("errors", "n_seen")}
    # target i is trial i: its errors are those of the i-th child generator
    child = np.random.default_rng(11).spawn(4)[2]
    assert np.array_equal(a["errors"][2], ex.accuracy_target(child, 20.0, 0.25)["errors"])


def test_exact_hough_point_voting_equals_the_voting_transform():
    img = ex.composite_image(np.random.default_rng(3))
    assert img.shape == (256, 256) and img.dtype == bool and img.sum() > 21
    H, rhos, thetas = hough.hough_transform_image(img)
    He, re = ex.exact_hough(img, rhos, thetas)
    assert np.array_equal(He, H) and np.array_equal(re, rhos)
    Hs, rs = ex.exact_hough(img, rhos, thetas, shift=1.0, sub=2)
    assert np.allclose(rs, rhos - 1.0) and abs(Hs.sum() - H.sum()) <= 1e-9 * H.sum() + 1
    with pytest.raises(ValueError, match="sub"):
        ex.exact_hough(img, rhos, thetas, sub=0)


def test_match_peaks_and_optics_trial():
    P = hough.detect_peaks
    H, rhos, thetas = hough.hough_transform_image(ex.composite_image(np.random.default_rng(4)))
    pk = P(H, rhos, thetas, min_votes=6)
    assert ex.match_peaks(pk, pk) == len(pk) and ex.match_peaks(pk, []) == 0
    o = mc_run(ex.optics_trial, 1, np.random.default_rng(4))[0]
    assert set(o) == {key for key, _ in ex.OPT_PLANES}
    for ok, k, n, mass, r in o.values():
        assert 0 <= k <= n and ok == (mass and k == n) and -1.0 <= r <= 1.0
    assert o[1][4] > 0.5  # the simulated optics follow point voting cell by cell
    assert o[1][3] and o["shift"][3]  # rotation and shifted bins keep the total votes


def test_skimage_cells_differ_only_at_ties_and_peer_trial():
    img = np.zeros((32, 32), dtype=bool)
    img[5, 3] = img[20, 17] = img[9, 30] = True
    cells, diff, ties = ex.skimage_cells(img)
    assert cells > 0 and 0 <= ties <= diff
    assert diff == ties
    rows = ex.peer_trial(np.random.default_rng(6), {"skimage (2, 2, 6 votes)": ex.SKIMAGE_RULES["skimage (2, 2, 6 votes)"]})
    assert [r[0] for r in rows] == ["ours, printed ratio 3 (floor 6)", "ours, ridge-free ratio 3 (floor 11)",
                                    "skimage (2, 2, 6 votes)"]
    assert all(0 <= found <= 6 and false >= 0 for _, found, false in rows)
    with pytest.raises(TypeError, match="skimage_rules"):
        ex.peer_trial(np.random.default_rng(6), [("a", {})])


def test_noise_plane_and_target_peaks():
    P = ex.noise_plane(np.random.default_rng(8), n_noise=4, n_frames=3)
    assert P.sum() == 12 * P.shape[1]  # every point votes once per theta
    assert ex.noise_plane(np.random.default_rng(8), n_noise=0).sum() == 0
    out = ex.target_peaks(np.random.default_rng(9), np.zeros_like(P))
    assert 1 <= len(out) <= 5
    for r in out:
        assert r["bias"] == 0 and r["needed"] == pytest.approx(0.6)  # no bias: 60 % of the votes
        assert 0 < r["fraction"] <= 1 and r["found"] in (True, False) and r["real ratio"] > 0
    with pytest.raises(ValueError, match="window_bias"):
        ex.target_peaks(np.random.default_rng(9), np.zeros((3, 3)))


def test_mean_field_ratio_and_fraction_needed():
    assert ex.mean_field_ratio(21, 0.0) == pytest.approx(5.0)  # a perfect line on an empty plane
    assert ex.mean_field_ratio(21, 3.56) == pytest.approx((21 + 3.56) / (21 / 5 + 3.56))  # the bias is in the cell too
    assert ex.fraction_needed(21, 3.56) == pytest.approx(0.6 + 2 * 3.56 / 21)  # 0.94
    for n, b in ((21, 0.0), (21, 3.5), (50, 7.0)):  # at the needed share the mean field sits on the threshold
        assert ex.mean_field_ratio(n, b, min(ex.fraction_needed(n, b), 1.0)) == pytest.approx(
            min(3.0, ex.mean_field_ratio(n, b)))
    with pytest.raises(ValueError, match="fraction"):
        ex.mean_field_ratio(21, 1.0, 1.5)
    with pytest.raises(ValueError, match="n_votes"):
        ex.fraction_needed(0, 1.0)


def test_perfect_line_trial_is_the_mean_field_case():
    r = ex.perfect_line_trial(np.random.default_rng(3))
    assert r["all_in_cell"] and 0 <= r["rho"] <= 100 and r["rho"] % 2 == 0
    # every vote in its cell and 5 N in its window: the ratio is the mean field at the draw's own bias
    assert r["ratio"] == pytest.approx((21 + r["bias_cell"]) / (21 / 5 + r["bias_window"]))
    clean = ex.perfect_line_trial(np.random.default_rng(3), n_noise=0)
    assert clean["ratio"] == pytest.approx(5.0) and clean["bias_cell"] == 0
    with pytest.raises(ValueError, match="bin centre"):
        ex.perfect_line_trial(np.random.default_rng(3), rho_range=(0.5, 1.5))


def test_bound_tables():
    perfect = [ex.perfect_line_trial(c) for c in np.random.default_rng(5).spawn(6)]
    targets = [r for c in np.random.default_rng(6).spawn(2) for r in ex.target_peaks(c, np.zeros((183, 180)))]
    mf, votes, (tol_mf, tol_v) = ex.bound_tables(perfect, targets)
    assert list(mf["case"]) == ["perfect line, rho 0-100", "our targets (measured f)"]
    assert mf["share f in cell"].iloc[0] == 1.0 and set(tol_mf) == set(mf.columns[1:])
    assert set(tol_v) == set(votes.columns) and 0 <= votes["targets holding enough"].iloc[0] <= 1
    with pytest.raises(ValueError, match="empty"):
        ex.bound_tables([], targets)


def test_pair_scene_geometry():
    tr, fr = ex.pair_scene(np.random.default_rng(1), "crossing", 30)
    mid = ex.SALVO_TIMES[10]
    p0, p1 = tr[0].position(mid), tr[1].position(mid)
    assert np.allclose(p0, p1)  # the tracks cross mid-window
    v0, v1 = tr[0].velocity(mid), tr[1].velocity(mid)
    ang = np.degrees(np.arccos(v0 @ v1 / np.linalg.norm(v0) / np.linalg.norm(v1)))
    assert ang == pytest.approx(30.0) and np.linalg.norm(v0) == pytest.approx(20.0)
    tr, fr = ex.pair_scene(np.random.default_rng(1), "parallel", 6)
    d = tr[1].position(mid) - tr[0].position(mid)
    assert np.linalg.norm(d) == pytest.approx(6.0) and abs(d @ tr[0].velocity(mid)) < 1e-9
    tr, fr = ex.pair_scene(np.random.default_rng(1), "clutter", 3)
    lab = np.concatenate(fr.labels)
    assert len(tr) == 1 and np.sum(lab < 0) <= 21 * 5 + 3 and np.sum(lab < 0) >= 21 * 5
    with pytest.raises(ValueError, match="kind"):
        ex.pair_scene(np.random.default_rng(1), "diverging", 3)


@pytest.mark.parametrize("radius", [(0.5, 1.5), (1.0, 3.0), (2.0, 4.0)])
def test_pair_scene_clutter_radius(radius):
    tr, fr = ex.pair_scene(np.random.default_rng(4), "clutter", 10, clutter_radius=radius)
    for f, (p, lab) in enumerate(zip(fr.points, fr.labels)):
        close = p[lab < 0][5:]  # the close false pixels follow the 5 uniform ones
        d = np.linalg.norm(close - fr.truth[f, 0], axis=1)
        assert np.all(d <= radius[1] + np.sqrt(0.5) + 1e-9) and np.all(d >= radius[0] - np.sqrt(0.5) - 1e-9)
    assert sum(int(np.sum(lab < 0)) - 5 for lab in fr.labels) <= 10
    with pytest.raises(ValueError, match="clutter_radius"):
        ex.pair_scene(np.random.default_rng(1), "clutter", 3, clutter_radius=(3.0, 1.0))


def test_pair_trial_and_summary():
    trials = mc_run(ex.pair_trial, 4, np.random.default_rng(2), "parallel", 16)
    for t in trials:
        assert len(t["together"]) == len(t["alone"]) == 2 and 0 <= t["lines on pair"] <= 2
        assert t["ratio alone"] > 0 and t["ratio together"] > 0
    row = ex.pair_summary("parallel", 16, trials)
    assert row["value"] == 16 and row["draws"] == 4
    assert row["no line"] + row["one line"] + row["two lines"] == pytest.approx(1.0)
    tog = np.mean([t["together"] for t in trials])
    assert row["found together"] == pytest.approx(tog)
    cl = ex.pair_trial(np.random.default_rng(3), "clutter", 3)
    assert cl["together"][1] is False and cl["alone"][1] is False
    with pytest.raises(ValueError, match="at least 2"):
        ex.pair_summary("parallel", 16, trials[:1])


def test_salvo_trial_diagnosis_and_floor():
    a = ex.salvo_trial(np.random.default_rng(3), 3.0, True)
    b = ex.salvo_trial(np.random.default_rng(3), 3.0, False, 11)
    assert a["seed"] == b["seed"]  # the same scene at another floor
    assert b["false confirmed"] <= a["false confirmed"]
    for found, crowded, n, f, bias, needed, ratio in a["diag"]:
        assert 0 < f <= 1 and bias >= 0 and needed == pytest.approx(0.6 + 2 * bias / n)


def test_eq4_readings():
    rows = ex.eq4_strip_counts()
    got = {(r["reading"], r["theta"]): r["in strip"] for r in rows}
    assert [got[("as printed", t)] for t in (0.0, 45.0, 90.0, 135.0)] == [0, 1, 21, 1]
    assert all(got[("consistent with Eqs. (1), (3)", t)] == 21 for t in (0.0, 45.0, 90.0, 135.0))
    printed = ex.EQ4_READINGS["as printed"]
    assert printed(30.0, 5.0, 1.0, 0.0, 30.0)[1] == -60.0  # theta = 0, the line x = rho: y' = -2 rho
    consistent = {r["theta"]: r["x' range"] for r in rows if r["reading"].startswith("consistent")}
    assert all(v == pytest.approx(100.0) for v in consistent.values())  # x' runs along the line


def test_geometry_plateau_and_stage_costs():
    geo = ex.geometry_trial(np.random.default_rng(4))
    assert len(geo) == 6 and all(0 <= e < x for e, x in geo)
    widths = [ex.plateau_width(e) for e in (5, 20, 80, 160)]
    assert widths == sorted(widths, reverse=True) and widths[-1] >= 1 and widths[0] > 5
    found, err = ex.plateau_trial(np.random.default_rng(5), 80.0)
    assert found in (True, False) and (np.isnan(err) or 0 <= err <= 90)
    c = ex.stage_costs(np.random.default_rng(6), 3)
    assert c["optical HT passes"] == 180 and c["plane comparisons"] == 183 * 180
    assert c["digital votes"] == c["points"] * 180 and c["digital strip points"] == c["lines"] * c["points"]
    assert c["optical estimation passes"] <= 6 * c["lines"]
    with pytest.raises(ValueError, match="extent"):
        ex.plateau_width(0.0)


def test_new_plots():
    from projtrack.experiments.hough.plots import plot_bound, plot_continuous, plot_pairs, plot_plain_vs_thresholded
    import pandas as pd

    fig = plot_bound([2.5, 3.2, 3.4], 3.2, [0.8, 0.9], [0.94, 0.9])
    assert len(fig.axes) == 2
    plt.close(fig)
    rows = [ex.pair_summary(k, v, mc_run(ex.pair_trial, 2, np.random.default_rng(1), k, v))
            for k, v in (("crossing", 30), ("crossing", 90), ("parallel", 2), ("parallel", 16))]
    fig = plot_pairs(pd.DataFrame(rows))
    assert len(fig.axes) == 2
    plt.close(fig)
    tr, fr = ex.noisy_scene(np.random.default_rng(2), n_noise=3, n_targets=2)
    fig = plot_plain_vs_thresholded(fr, ex.plain_and_thresholded(fr, tr), n_targets=2)
    assert len(fig.axes) == 2
    plt.close(fig)
    fig = plot_continuous(ex.continuous_run(np.random.default_rng(7), n_targets=2, duration=20.0), duration=20.0)
    assert len(fig.axes) == 1
    plt.close(fig)


def _synthetic_sweep():
    """A two-rule, two-setting sweep with known stds: errors +-1 (std ~1.15) in every column."""
    import pandas as pd

    E = np.array([[1.0] * 4, [-1.0] * 4, [1.0] * 4, [-1.0] * 4])
    full = np.array([True, True, False, True])
    raw, rows = {}, []
    for stop in ("75 % rule", "all points"):
        for T in (0.25, 0.1):
            raw[(stop, 10.0, T)] = (E, full)
            # pred below the std at T = 0.1 for x only; rounding lifts x' above it
            rows.append({"stop": stop, "speed": 10.0, "T": T, "pred_x": 2.0 if T == 0.25 else 1.0,
                         "predr_x": 2.0, "pred_y": 2.0, "pred_vx": 2.0, "predr_vx": 2.0, "pred_vy": 2.0})
    return raw, pd.DataFrame(rows)


def test_readings_table_counts_every_reading_and_the_claim():
    raw, table = _synthetic_sweep()
    stops = ex.STOPS[:2]
    rows = ex.readings_table(raw, table, stops, slack=0)
    assert len(rows) == 2 * 2 * 2
    assert [r["stopping rule"] for r in rows[:4]] == ["75 % rule"] * 4
    assert [(r["rounding in Eqs. (8), (12)"], r["targets"]) for r in rows[:4]] == [
        (False, "all 4"), (False, "seen in every frame"), (True, "all 4"), (True, "seen in every frame")]
    assert list(rows[0])[3:7] == ["within: y", "within: vy", "within: x", "within: vx"]
    # x' misses at T = 0.1 without rounding only
    assert rows[0]["within: x"] == 1 and rows[0]["within: y"] == 2 and not rows[0]["claim holds"]
    assert rows[2]["within: x"] == 2 and rows[2]["claim holds"]
    assert ex.readings_table(raw, table, stops, slack=1)[0]["claim holds"]
    with pytest.raises(ValueError, match="raw"):
        ex.readings_table({}, table, stops)
    with pytest.raises(ValueError, match="slack"):
        ex.readings_table(raw, table, stops, slack=-1)
    with pytest.raises(ValueError, match="stops"):
        ex.readings_table(raw, table, [("75 % rule",)])


def test_baseline_within_and_closest_margin():
    # Eq. (8): sqrt((v T)^2 / 12 + 0.25); a quarter of the track, v * 5 / 4, is far larger
    assert ex.baseline_within([5.0, 30.0], [0.25, 0.025]) == 0
    # a short track under a large jitter: the guess (1 px) is within sqrt(4 / 12 + 4)
    assert ex.baseline_within([1.0], [2.0], total_time=4.0) == 0
    assert ex.baseline_within([1.0], [2.0], total_time=4.0, jitter_sigma=2.0) == 1
    with pytest.raises(ValueError, match="speeds"):
        ex.baseline_within([0.0], [0.25])
    # the data-free guess at the centre of a 128-px start square: error std 128 / sqrt(12) = 36.95 px
    assert ex.baseline_within([5.0, 30.0], [0.25, 0.025], region=128.0) == 0
    assert ex.baseline_within([1.0], [2.0], total_time=4.0, jitter_sigma=40.0, region=128.0) == 1
    with pytest.raises(ValueError, match="region"):
        ex.baseline_within([5.0], [0.25], region=0.0)
    raw, table = _synthetic_sweep()
    s_all = np.array([1.0, -1.0, 1.0, -1.0]).std(ddof=1)
    s_full = np.array([1.0, -1.0, -1.0]).std(ddof=1)
    expected = min(abs(s / p - 1) for s in (s_all, s_full) for p in (1.0, 2.0))
    assert ex.closest_margin(raw, table, ex.STOPS[:2]) == pytest.approx(expected)
    with pytest.raises(ValueError, match="no setting"):
        ex.closest_margin(raw, table, ex.STOPS[2:])


def test_rule_summary_means_and_shares():
    res = [{"r": {"plain": (5, 2, 1), "thresholded": (4, 1, 0)}},
           {"r": {"plain": (3, 4, 1), "thresholded": (4, 1, 0)}}]
    rows, means, dist = ex.rule_summary([(res, ("r",))])
    assert [(r["rule"], r["HT"], r["scenes"]) for r in rows] == [("r", "plain", 2), ("r", "thresholded", 2)]
    assert np.array_equal(means[("r", "plain")], [4.0, 3.0, 1.0])
    assert dist[("r", "thresholded")].shape == (2, 3)
    assert rows[0]["targets found"] == 0.8 and rows[0]["scenes with all found"] == 0.5
    assert rows[0]["false lines"] == 3.0 and rows[1]["false confirmed"] == 0.0
    with pytest.raises(ValueError, match="not in the results"):
        ex.rule_summary([(res, ("other",))])
    with pytest.raises(ValueError, match="2 scenes"):
        ex.rule_summary([(res[:1], ("r",))])
    with pytest.raises(TypeError, match="rules"):
        ex.rule_summary([(res, "r")])


def test_rate_ci_exact_interval():
    lo, hi = ex.rate_ci(45, 49)
    assert lo == pytest.approx(0.80399, abs=1e-4) and hi == pytest.approx(0.97731, abs=1e-4)
    assert ex.rate_ci(0, 10)[0] == 0.0 and ex.rate_ci(10, 10)[1] == 1.0
    lo, hi = ex.rate_ci(5, 10)
    assert lo < 0.5 < hi and lo == pytest.approx(1 - hi)  # symmetric at k = n / 2
    with pytest.raises(ValueError, match="at most n"):
        ex.rate_ci(11, 10)


def test_tradeoff_tables_matches_the_false_line_rate():
    def trial(p6, p8, t6):
        return {"counts": {("plain", 6.0): p6, ("plain", 8.0): p8, ("thresholded", 6.0): t6},
                "targets": [{"ratio plain": 3.0, "ratio thresholded": 2.0, "others plain": 4.0, "others thresholded": 1.0}]}
    # plain at 6 has more false lines than thresholded, plain at 8 fewer: 8 is the matched floor
    trials = [trial((2, 6, 1), (2, 1, 0), (1, 3, 1)), trial((3, 4, 1), (3, 1, 0), (2, 3, 0))]
    curve, matched, mech = ex.tradeoff_tables(trials)
    assert list(curve["floor"]) == [6, 8, 6]
    row = matched.iloc[0]
    assert row["plain floor"] == 8 and row["found, plain"] == pytest.approx(0.5)
    assert row["found, thresholded"] == pytest.approx(0.3) and row["found change"] == pytest.approx(-1.0)
    assert row["2 SE"] == pytest.approx(0.0)
    assert mech.set_index("HT").loc["thresholded", "ratio lower than plain"] == 1.0
    with pytest.raises(ValueError, match="at least 2"):
        ex.tradeoff_tables(trials[:1])


def test_floor_tradeoff_same_scene_as_rule_counts():
    a = ex.floor_tradeoff(np.random.default_rng(7), (6,), (6,))
    b = ex.rule_counts(np.random.default_rng(7), {"f6": dict(min_votes=6)})
    assert a["counts"][("plain", 6.0)] == b["f6"]["plain"]
    assert a["counts"][("thresholded", 6.0)] == b["f6"]["thresholded"]
    for t in a["targets"]:
        assert t["others thresholded"] <= t["others plain"] + 1e-9
    with pytest.raises(ValueError, match="empty"):
        ex.floor_tradeoff(np.random.default_rng(7), (), (6,))


def test_clutter_summary_counts_kept_targets():
    trials = [{"together": (True, False), "alone": (True, False)}, {"together": (False, False), "alone": (True, False)},
              {"together": (True, False), "alone": (False, False)}, {"together": (False, False), "alone": (False, False)}]
    r = ex.clutter_summary(3, trials)
    assert r["found alone"] == 0.5 and r["found with"] == 0.5 and r["kept"] == 0.5 and r["gained"] == 0.25
    assert r["kept low"] < 0.5 < r["kept high"] and r["change"] == 0.0
    with pytest.raises(ValueError, match="at least 2"):
        ex.clutter_summary(3, trials[:1])

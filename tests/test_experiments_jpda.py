"""Experiments of the JPDA chapter: scoring, tracking study, equivalence, analog accuracy, op tables."""

import numpy as np
import pandas as pd
import pytest

from projtrack import jpda
from projtrack.experiments import jpda as ex
from projtrack.scenes import jpda as scene


def test_score_tracks_detects_swaps_and_losses():
    truth = np.zeros((5, 2, 4))
    truth[:, 1, 0] = 10.0
    est = truth.copy()
    assert ex.score_tracks(est, truth) == {"rmse": 0.0, "swapped": 0, "lost": 0, "tracks": 2}
    swapped = est[:, ::-1]
    s = ex.score_tracks(swapped, truth)
    assert s["swapped"] == 2 and s["lost"] == 0 and s["rmse"] == pytest.approx(10.0)
    far = est.copy()
    far[-1, 0, 2] = 50.0
    assert ex.score_tracks(far, truth)["lost"] == 1
    with pytest.raises(ValueError, match="same shape"):
        ex.score_tracks(est[:, :1], truth)
    with pytest.raises(ValueError, match="lost_distance"):
        ex.score_tracks(est, truth, lost_distance=0.0)


def test_tracking_trial_is_reproducible():
    a = ex.tracking_trial(np.random.default_rng(1), n_steps=8)
    b = ex.tracking_trial(np.random.default_rng(1), n_steps=8)
    assert a == b
    assert set(a) == {"jpda", "gnn"}
    with pytest.raises(TypeError, match="rng"):
        ex.tracking_trial(1, n_steps=8)


def test_run_trackers_follow_an_easy_scene():
    sc = scene.crossing_targets(np.random.default_rng(3), n_targets=2, n_steps=6, clutter_per_scan=0.5)
    est_j, est_g = ex.run_trackers(sc)
    assert est_j.shape == est_g.shape == sc.truth[1:].shape
    assert ex.score_tracks(est_j, sc.truth[1:])["lost"] == 0
    with pytest.raises(TypeError, match="CrossingScene"):
        ex.run_trackers(sc.truth)


def test_tracking_study_matches_its_trials_and_summary_counts():
    res = ex.tracking_study(3, 11, n_steps=6)
    children = np.random.default_rng(11).spawn(3)
    assert res == [ex.tracking_trial(c, n_steps=6) for c in children]
    summary, tol = ex.tracking_summary(res)
    assert summary["tracker"].tolist() == ["JPDA", "GNN"]
    n_tracks = 3 * res[0]["jpda"]["tracks"]
    assert summary.loc[0, "tracks lost"] == pytest.approx(sum(r["jpda"]["lost"] for r in res) / n_tracks)
    assert summary.loc[1, "mean RMSE"] == pytest.approx(np.mean([r["gnn"]["rmse"] for r in res]))
    # one flipped run moves a share by 1/3; the mean RMSE by the worst run's RMSE / 3
    assert tol["tracks swapped"].atol == pytest.approx(1 / 3) and tol["tracks swapped"].kind == "statistical"
    worst = max(r[k]["rmse"] for r in res for k in ("jpda", "gnn"))
    assert tol["mean RMSE"].atol == pytest.approx(worst / 3)
    with pytest.raises(ValueError, match="at least one"):
        ex.tracking_summary([])
    with pytest.raises(ValueError, match="tracking_trial outputs"):
        ex.tracking_summary([{"jpda": {}}])


def test_equivalence_trial_and_study():
    row = ex.equivalence_trial(np.random.default_rng(0))
    assert set(row) == {"paper", "fast", "sum", "pda", "size", "norm", "pda_norm"}
    assert row["paper"] < 1e-12 and row["fast"] < 1e-12 and row["sum"] < 1e-12
    eq = ex.equivalence_study(5, 2024)
    assert isinstance(eq, pd.DataFrame) and len(eq) == 5
    assert eq["fast"].max() < 1e-12
    summary = ex.equivalence_summary(eq)
    assert summary["below 1e-12"].tolist() == [True, True, False]  # the PDA baseline fails
    assert summary.iloc[2, 1] == eq["pda"].max()
    with pytest.raises(ValueError, match="equivalence_study"):
        ex.equivalence_summary(eq.drop(columns="pda"))
    with pytest.raises(ValueError, match="n_trials"):
        ex.equivalence_study(0, 1)


def test_analog_accuracy_grows_with_the_noise():
    table, err = ex.analog_accuracy((0.0, 1e-3, 1e-1), 4, 8, size=4)
    assert err.shape == (4, 3) and np.all(err[:, 0] == 0)
    med = table.iloc[:, 0].to_numpy()
    assert med[1] < med[2]
    with pytest.raises(ValueError, match="levels"):
        ex.analog_trial(np.random.default_rng(0), [-1.0])
    with pytest.raises(TypeError, match="rng"):
        ex.analog_trial(None, [0.1])


def test_instrumented_counts_reproduce_the_closed_forms():
    conv, fast, stored = ex.instrumented_counts([3, 4])
    for (m, T), c in conv.items():
        closed = jpda.conventional_op_count(m, T)
        assert c == (closed.additions, closed.multiplications)
        f = jpda.fast_op_count(m, T)
        assert fast[m, T] == (f.additions, f.multiplications)
        assert stored[m, T][1] <= fast[m, T][1]
    assert conv[3, 3] == (54, 68)  # Table IV, m = T = 3
    grid = ex.count_grid(conv, [3, 4])
    assert grid.loc[3, 3] == "54/68" and grid.shape == (2, 2)
    with pytest.raises(ValueError, match="no entry"):
        ex.count_grid(conv, [3, 5])


def test_paper_tables_are_parsed_and_rounded_like_the_paper():
    assert ex.parse_count_table("1/2 3/4\n5/6 7/8", [1, 2]) == {
        (1, 1): (1, 2), (1, 2): (3, 4), (2, 1): (5, 6), (2, 2): (7, 8)}
    with pytest.raises(ValueError, match="cells"):
        ex.parse_count_table("1/2 3/4", [1, 2])
    # "0 9/1 3" is 0.9/1.3 with the decimal points lost
    assert ex.parse_ratio_table("0 9/1 3", [7]) == {(7, 7): (0.9, 1.3)}
    with pytest.raises(ValueError, match="tokens"):
        ex.parse_ratio_table("0 9/1", [7])
    assert ex.half_up(300, 240) == 1.3 and ex.half_up(1, 3) == 0.3
    with pytest.raises(ValueError, match="den"):
        ex.half_up(1, 0)
    np.testing.assert_array_equal(ex.all_ones_mvm(2, 3)[0], 0.5)


def test_literature_rule_equals_the_mvm_for_a_common_p_detect():
    rng = np.random.default_rng(4)
    w = rng.uniform(0.1, 1.0, (4, 3))
    w[0] = 1 - 0.8
    np.testing.assert_allclose(ex.beta_literature_rule(w, 0.8), jpda.beta(w), atol=1e-12)
    # with target-dependent P_D the MVM's row 0 differs from the rule's constant: they differ
    w[0] = [0.1, 0.3, 0.5]
    assert np.abs(ex.beta_literature_rule(w, 0.8) - jpda.beta(w)).max() > 1e-3
    with pytest.raises(ValueError, match="p_detect"):
        ex.beta_literature_rule(w, 0.0)


def test_beta_by_permanents_equals_beta():
    assert ex.permanent_rect(np.array([[1.0, 2.0], [3.0, 4.0]])) == pytest.approx(10.0)
    with pytest.raises(ValueError, match="no more rows"):
        ex.permanent_rect(np.ones((3, 2)))
    w = scene.random_mvm(np.random.default_rng(31), 3, 2)
    np.testing.assert_allclose(ex.beta_by_permanents(w), jpda.beta(w), atol=1e-12)
    w[0, 0] = 0.0
    with pytest.raises(ValueError, match="row 0"):
        ex.beta_by_permanents(w)


def test_clutter_sensitivity_raises_beta0_with_the_density():
    zp = np.array([[0.0, 0.0], [2.0, 0.0]])
    S = np.repeat(np.eye(2)[None], 2, axis=0)
    z = np.array([[0.3, 0.1], [1.8, -0.2]])
    table = ex.clutter_sensitivity(z, zp, S, 0.9, (0.01, 1.0, 100.0))
    assert list(table.columns) == ["0.01", "1", "100"] and list(table.index) == ["a", "b"]
    assert np.all(np.diff(table.to_numpy(), axis=1) > 0)
    with pytest.raises(ValueError, match="lambdas"):
        ex.clutter_sensitivity(z, zp, S, 0.9, ())
    with pytest.raises(ValueError, match="lambdas"):
        ex.clutter_sensitivity(z, zp, S, 0.9, (0.0,))


def test_scaling_timings_table_shape_and_limits():
    calls = []
    assert ex.best_of(lambda: calls.append(1), 3) >= 0 and len(calls) == 3
    with pytest.raises(ValueError, match="repeats"):
        ex.best_of(lambda: None, 0)
    t = ex.scaling_timings([2, 3], 7, enumerate_max=2, paper_max=3, single_run_from=3)
    assert list(t.index) == [2, 3]
    assert t.loc[2, "events (Table I)"] == 7.0
    assert np.isnan(t.loc[3, "enumerate"]) and np.isfinite(t.loc[3, "paper"])
    assert np.all(t[["auto", "clustered: auto"]].to_numpy() > 0)
    with pytest.raises(ValueError, match="cluster_size"):
        ex.scaling_timings([2], 7, cluster_size=0)


def test_vector_growth_table():
    g = ex.vector_growth([3, 4])
    assert list(g.index) == [3, 4]
    assert g.loc[3, "vector length"] == jpda.vector_size(3, 3) == 7  # Table III
    f = jpda.fast_op_count(4, 4)
    assert g.loc[4, "fast algorithm adds + mults"] == f.additions + f.multiplications
    assert g.loc[3, "length / eq. (1)"] == pytest.approx(7 / 34)
    with pytest.raises(ValueError, match="22"):
        ex.vector_growth([23])


def test_multiplication_rules_are_pinned_and_judged_on_table_iv():
    rules = ex.multiplication_rules()
    assert rules["T - 1 (per target)"](7, 3) == 716 == 2 * jpda.count_feasible_events(7, 3)
    assert rules["m (the text)"](3, 3) == 3 * 34
    printed = {(3, 3): (54, 68), (7, 3): (882, 716), (3, 4): (144, 1)}  # (3, 4) misprinted
    assert ex.rule_fits(rules["T - 1 (per target)"], printed) == (2, [(3, 4)])
    assert ex.rule_fits(rules["T - 1 (per target)"], printed, exclude=[(7, 3)]) == (1, [(3, 4)])
    assert ex.rule_fits(rules["m (the text)"], printed)[0] == 0
    table = ex.multiplication_rule_table(printed)
    assert list(table.columns) == ["cells of Table IV equal", "m = 7, T = 3", "m = T = 7"]
    assert table.loc["T - 1 (per target)", "cells of Table IV equal"] == 2
    with pytest.raises(TypeError, match="rule"):
        ex.rule_fits(None, printed)
    with pytest.raises(ValueError, match="index"):
        ex.rule_fits(rules["m (the text)"], printed, index=2)


def test_table5_additions_rule_and_its_proof_of_a_misprint():
    # Table V's printed additions for m, T = 3, 4
    assert [ex.table5_additions_rule(m, T) for m in (3, 4) for T in (3, 4)] == [63, 132, 132, 304]
    ours = {(m, T): (ex.table5_additions_rule(m, T), 0) for m in (3, 4) for T in (3, 4)}
    printed = dict(ours)
    printed[4, 4] = (300, 0)  # not a multiple of m T = 16
    proven, text = ex.table5_additions_proof((4, 4), ours, printed)
    assert proven and "3/3 other" in text and "= 304" in text
    printed[4, 4] = (320, 0)  # a multiple of m T: the rule alone does not prove it
    assert not ex.table5_additions_proof((4, 4), ours, printed)[0]
    printed[4, 4], printed[3, 3] = (300, 0), (64, 0)  # another cell misfits the rule
    assert not ex.table5_additions_proof((4, 4), ours, printed)[0]
    with pytest.raises(ValueError, match="k = "):
        ex.table5_additions_proof((5, 5), ours, printed)
    with pytest.raises(ValueError, match="m"):
        ex.table5_additions_rule(1, 3)


def test_table6_ratio_decides_which_value_it_supports():
    # Table VI at m = T = 3 prints 0.9/1.3 = 54/63 and 68/51 rounded half-up
    assert ex.ratio_fits((0.9, 1.3), (54, 68), (63, 51))
    assert not ex.ratio_fits((0.9, 1.3), (54, 80), (63, 51))
    assert ex.ratio_fits((1.3, 1.0), (300, 5), (240, 5))  # 1.25 rounds up
    with pytest.raises(ValueError, match="pairs"):
        ex.ratio_fits((0.9,), (54, 68), (63, 51))
    assert [ex.supported_value(a, b) for a, b in
            ((True, False), (True, True), (False, True), (False, False))] == [
        "ours", "ours+paper", "paper", ""]
    with pytest.raises(TypeError, match="must be a bool"):
        ex.supported_value(1, 0)


def test_growth_readings_and_their_baselines():
    assert ex.grows_geometrically({n: 2**n for n in range(3, 9)})
    assert not ex.grows_geometrically({n: n + 1 for n in range(3, 9)})
    assert not ex.grows_geometrically({3: 1, 4: 1, 5: 2, 6: 3.7, 7: 8})  # one step < 1.9
    with pytest.raises(ValueError, match="two values"):
        ex.grows_geometrically({3: 1, 4: 2, 5: 4})
    growth = ex.vector_growth(range(3, 9))
    r = ex.growth_readings(growth, diag=range(3, 6))
    # the vector length grows geometrically (reading 1 fails) and falls fast against eq. (1)
    # (reading 2 holds)
    assert r["claim holds"].tolist() == [False, True]
    # each criterion can fail: reading 1's baseline (not growing) passes, reading 2's
    # combinatorial baseline fails
    assert r["baseline holds"].tolist() == [True, False]
    assert r.iloc[0]["values"].startswith("7, 15, 31 (m = T = 3..5); x")
    assert "from 7 to 8" in r.iloc[0]["values"]
    with pytest.raises(TypeError, match="vector_growth"):
        ex.growth_readings(growth["vector length"])
    with pytest.raises(ValueError, match="diag"):
        ex.growth_readings(growth, diag=[3])


def test_row_growth_of_table3():
    # along Table III's rows (T = 3 -> 7): m = 3 from 7 to 8, m = 7 from 29 to 127
    g = ex.row_growth(range(3, 8))
    assert g["low"] == pytest.approx(8 / 7)
    assert (g["m_high"], g["lengths"]) == (7, (29, 127))
    assert g["high"] == pytest.approx(127 / 29)
    with pytest.raises(ValueError, match="sizes"):
        ex.row_growth([3])


def test_relative_growth_table_separates_combinatorial_from_exponential():
    t = ex.relative_growth_table(range(3, 8)).set_index("size along m = T")
    passes = t[f"falls >= {ex.RELATIVE_FALL:g}x at every step"]
    assert passes.to_dict() == {"vector length (Table III)": True, "eq. (1) itself": False,
                                "eq. (1) of m - 1, T - 1": False, "n!": False, "n 2^n": True}
    # Table III's length falls 2.9x to 4.9x per step; eq. (1) of the smaller problem 1.14x to 1.27x
    assert t.loc["vector length (Table III)", "smallest fall per step"] == pytest.approx(
        (7 / 34) / (15 / 209))  # the step from m = T = 3 to 4
    assert 1.13 < t.loc["eq. (1) of m - 1, T - 1", "smallest fall per step"] < 1.15
    assert t.loc["eq. (1) itself", "largest fall per step"] == 1.0
    with pytest.raises(ValueError, match="diag"):
        ex.relative_growth_table([3])


def test_beta_in_situ_forms_t_squared_vectors_in_one_buffer():
    rng = np.random.default_rng(12)
    for m, T in ((0, 1), (2, 1), (3, 2), (4, 4), (5, 3), (3, 6)):
        w = scene.random_mvm(rng, m, T)
        run = ex.beta_in_situ(w)
        np.testing.assert_allclose(run.beta, jpda.beta_enumerated(w), atol=1e-12)
        assert run.vectors == T * T and run.vectors_per_target == (T,) * T
        assert run.buffer_length == jpda.vector_size(m, T)
        ops = jpda.OpCount()
        jpda.beta_paper(w, ops=ops)
        assert (run.ops.additions, run.ops.multiplications) == (ops.additions, ops.multiplications)
        # recomputing the whole vector at every stage gives the same beta, at a higher cost
        all_words = ex.beta_in_situ(w, words="all")
        np.testing.assert_allclose(all_words.beta, run.beta, atol=1e-12)
        assert all_words.ops.multiplications >= run.ops.multiplications
    # the reversed visiting order overwrites elements before they are read: wrong beta
    w = scene.random_mvm(rng, 4, 4)
    assert np.abs(ex.beta_in_situ(w, order="reversed").beta - jpda.beta_enumerated(w)).max() > 1e-3
    with pytest.raises(ValueError, match="order"):
        ex.beta_in_situ(w, order="backwards")
    with pytest.raises(ValueError, match="words"):
        ex.beta_in_situ(w, words="some")
    with pytest.raises(ValueError, match=">= 0"):
        ex.beta_in_situ(-w)
    with pytest.raises(ValueError, match="at least 16|at most 16"):
        ex.beta_in_situ(np.ones((18, 2)))
    with pytest.raises(ValueError, match="positive probability"):
        ex.beta_in_situ(np.array([[0.0, 0.0], [1.0, 0.0]]))


def test_in_situ_study_and_summary():
    study = ex.in_situ_study([3, 4], 5)
    assert len(study) == 4 and (study["vectors formed"] == study["T^2"]).all()
    assert study["beta exact"].all() and study["ops = Table V count"].all()
    assert (study["reversed order: max |beta error|"] > 1e-3).all()
    # the text's length loses the empty word: wrong beta exactly when m < T
    short = study["m"] < study["T"]
    assert (study.loc[short, "text's length: max |beta error|"] > 1e-3).all()
    assert (study.loc[~short, "text's length: max |beta error|"] < 1e-12).all()
    s = ex.in_situ_summary(study)
    assert s["T"].tolist() == [3, 4] and s["vectors formed"].tolist() == [9, 16]
    assert s.iloc[0]["working vector, m = 3..4"] == "7, 11" and s["one vector, exact"].all()
    assert np.isnan(s.iloc[0]["text's length: largest error (m < T)"])  # T = 3: no m < T
    assert s.iloc[1]["text's length: largest error (m < T)"] > 1e-3
    broken = study.copy()
    broken.loc[0, "vectors formed"] = 8
    assert ex.in_situ_summary(broken).loc[0, "vectors formed"] == -1
    with pytest.raises(ValueError, match="in_situ_study"):
        ex.in_situ_summary(study.drop(columns="T^2"))


def test_beta_in_situ_columns_share_one_sum_and_the_texts_length():
    rng = np.random.default_rng(3)
    w = scene.random_mvm(rng, 4, 5)
    run = ex.beta_in_situ(w)
    assert np.ptp(run.column_sums) <= 1e-12 * run.column_sums.max()
    text = ex.beta_in_situ(w, length="text")
    assert text.buffer_length == jpda.vector_size_text_formula(4, 5) == 15
    assert np.abs(text.beta - jpda.beta_enumerated(w)).max() > 1e-3
    w1 = scene.random_mvm(rng, 1, 3)  # m = 1: b' needs the empty word, which the text drops
    assert np.isfinite(ex.beta_in_situ(w1, length="text").beta).all()
    with pytest.raises(ValueError, match="length"):
        ex.beta_in_situ(w, length="paper")


def test_savings_and_their_paths():
    assert ex.savings(7, 7) == pytest.approx((652974 / 12495, 785532 / 11655))  # Tables IV-V, m = T = 7
    p = ex.savings_paths([3, 7, 13], fixed=3, diagonal_max=7)
    assert p.loc[1, "m = T = n"] == "52.3/67.4" and p.loc[2, "m = T = n"] == "—"
    assert p.loc[0, "T = 3, m = n"] == "0.9/1.3" == p.loc[0, "m = 3, T = n"]  # Table VI, m = T = 3
    # with T held at 3 the additions saving stays below 2
    assert all(ex.savings(m, 3)[0] < 2 for m in (7, 12, 20))
    with pytest.raises(ValueError, match="m"):
        ex.savings(23, 3)


def test_savings_orders_give_the_growth_exponents():
    o = ex.savings_orders([7, 11, 12, 19, 20]).set_index("path")
    assert o.loc["m = T = n", "n"] == "7 to 12" and o.loc["m = 3, T = n", "n"] == "7 to 20"
    assert o.loc["m = T = n", "additions saved"] == "52.3 to 255830.3"
    # m = 3: additions about linear in T, multiplications about quadratic
    assert 0.9 < o.loc["m = 3, T = n", "exponent (additions)"] < 1.0
    assert 1.8 < o.loc["m = 3, T = n", "exponent (multiplications)"] < 2.0
    # T = 3: the additions saving levels off, multiplications about linear in m
    assert o.loc["T = 3, m = n", "exponent (additions)"] < 0.2
    assert 1.0 < o.loc["T = 3, m = n", "exponent (multiplications)"] < 1.2
    assert o.loc["m = T = n", "exponent (additions)"] > 10  # faster than any low power
    with pytest.raises(ValueError, match="two sizes"):
        ex.savings_orders([7, 13, 20])


def test_fast_count_readings_pin_the_words_on_one_cell():
    printed = {(m, T): (jpda.fast_op_count(m, T).additions, jpda.fast_op_count(m, T).multiplications)
               for m in (3, 4) for T in (3, 4)}
    printed[4, 4] = (304, 280)  # Table V's misprint
    r = ex.fast_count_readings(printed, calibrate=(3, 4))
    assert r["words computed per stage"].tolist() == ["needed", "all"]
    assert r["equals the printed cell"].tolist() == [True, False]
    assert r["other cells equal"].tolist()[0] == 2  # (3, 3) and (4, 3); (4, 4) is misprinted
    with pytest.raises(ValueError, match="calibrate"):
        ex.fast_count_readings(printed, calibrate=(7, 7))


def test_misprint_evidence_proves_the_papers_three_misprints():
    sizes = range(3, 8)
    conv, fast, _ = ex.instrumented_counts(sizes)
    p4, p5 = dict(conv), dict(fast)
    p4[5, 5] = (5200, 8148)
    p5[4, 4], p5[7, 4] = (304, 280), (1968, 992)
    p6 = {k: (ex.half_up(conv[k][0], fast[k][0]), ex.half_up(conv[k][1], fast[k][1])) for k in conv}
    ev = ex.misprint_evidence(conv, fast, p4, p5, p6)
    assert ev[["table", "m", "T"]].values.tolist() == [["IV", 5, 5], ["V", 4, 4], ["V", 7, 4]]
    assert ev["decided by"].tolist() == ["Table VI", "Table VI", "Table III"] and ev["proven"].all()
    assert "4 x 1546 = 6184" in ev.loc[0, "proof"]
    assert ex.count_table_verdict(25, ev, "IV") == ("misprint", 24, 1)
    assert ex.count_table_verdict(25, ev, "V") == ("misprint", 23, 2)
    # a printed cell that Table VI supports is not a misprint: the table differs
    p6b = dict(p6)
    p6b[5, 5] = (p6[5, 5][0], ex.half_up(8148, fast[5, 5][1]))
    ev_b = ex.misprint_evidence(conv, fast, p4, p5, p6b)
    assert not ev_b.loc[0, "proven"] and ex.count_table_verdict(25, ev_b, "IV")[0] == "differs"
    assert ex.count_table_verdict(25, ev.iloc[0:0], "IV") == ("reproduced", 25, 0)
    with pytest.raises(ValueError, match="every cell"):
        ex.misprint_evidence(conv, fast, p4, {(3, 3): (0, 0)}, p6)
    with pytest.raises(TypeError, match="misprint_evidence"):
        ex.count_table_verdict(25, None, "IV")


def test_analog_tolerance_is_declared():
    assert ex.ANALOG_TOLERANCE.kind == "statistical" and 0 < ex.ANALOG_TOLERANCE.rtol < 1e-3


def test_sweep_over_reachable_words_is_exact_and_counts_the_paper_way():
    rng = np.random.default_rng(8)
    for m, T in ((0, 1), (1, 1), (2, 3), (3, 2), (4, 4), (5, 3), (3, 6)):
        w = scene.random_mvm(rng, m, T)
        w[1:] *= rng.random((m, T)) < 0.7  # partly gated
        run = ex.beta_sweep_reachable(w)
        np.testing.assert_allclose(run.beta, jpda.beta_enumerated(w), atol=1e-12)
        assert np.ptp(run.column_sums) <= 1e-12 * run.column_sums.max()
    # m = T = 7 on the all-ones MVM: below the all-words sweep of the package
    run = ex.beta_sweep_reachable(ex.all_ones_mvm(7, 7))
    assert (run.ops.additions, run.ops.multiplications) == (5187, 5027)
    # forward A_1..A_6 (|v| <= t) and backward B_6..B_1 (|v| <= t): Table III's lengths 8..127
    assert run.words == 2 * sum(jpda.vector_size(7, t + 1) for t in range(1, 7)) == 894
    extra = ex.beta_sweep_reachable(ex.all_ones_mvm(7, 7), last_forward=True).ops
    assert (extra.additions, extra.multiplications) == (5187 + 447, 5027 + 575)  # A_T: 128 words
    # m = T = 2 by hand: A_1 is the column itself (free); B_1[v] = a_01 + sum_{j not in v} a_j1
    # over |v| <= 1 (3 + 2 + 2 terms: 4 additions, B_2 = 1 so no product); beta of target 1
    # reads one element each (3 products a_j0 B_1), of target 2 sums A_1 over 3, 2, 2 words
    # (2 + 1 + 1 additions, 3 products a_j1)
    small = ex.beta_sweep_reachable(ex.all_ones_mvm(2, 2)).ops
    assert (small.additions, small.multiplications) == (4 + 2 + 1 + 1, 3 + 3)
    fb = jpda.OpCount()
    jpda.beta_forward_backward(ex.all_ones_mvm(7, 7), ops=fb)
    assert run.ops.additions < fb.additions and run.ops.multiplications < fb.multiplications
    t = ex.sweep_counts([3, 7])
    assert t["reachable-words sweep"].tolist()[1] == 5187 + 5027
    with pytest.raises(ValueError, match="at most 20"):
        ex.beta_sweep_reachable(np.ones((22, 2)))
    with pytest.raises(ValueError, match="positive probability"):
        ex.beta_sweep_reachable(np.array([[0.0, 0.0], [1.0, 0.0]]))
    with pytest.raises(ValueError, match=">= 0"):
        ex.beta_sweep_reachable(-np.ones((3, 2)))


def test_chirp_routing_can_fail():
    sched = jpda.optical_vip_schedule(4, 6, 4)
    words = jpda.mu_words(4)
    r = ex.chirp_routing(sched, words, words)
    assert r["one chirp"] and r["slope"] == 1 and r["offsets"] == {0: 0, 1: 1, 2: 2, 3: 4, 4: 8}
    # consecutive places in Table II order: no single slope
    r2 = ex.chirp_routing(sched, np.arange(16), np.arange(16))
    assert not r2["one chirp"] and r2["slope"] is None and r2["collisions"] == 0
    # one diode per slot: no collisions either, but one diode makes five products in a slot
    alt = ex.slot_by_diode(sched)
    r3 = ex.chirp_routing(alt, words, words)
    assert r3["collisions"] == 0 and r3["products per diode"] == 5 and not r3["one chirp"]
    # a collision is caught
    bad = sched.copy()
    bad[1, 3] = bad[0, 3]
    assert ex.chirp_routing(bad, words, words)["collisions"] >= 1
    t = ex.routing_table(4, 6, 4)
    assert t["one chirp can route it"].tolist() == [True, False, False, False]
    assert t["collisions"].tolist() == [0, 0, 0, 0]
    with pytest.raises(ValueError, match="position"):
        ex.chirp_routing(sched, words[:3], words)
    with pytest.raises(ValueError, match="integers"):
        ex.chirp_routing(sched, words + 0.5, words)
    with pytest.raises(ValueError, match="rows"):
        ex.chirp_routing(sched[:, :3], words, words)


def test_median_interval_is_distribution_free():
    assert ex.median_interval(np.arange(1, 201)) == (86.0, 115.0)  # the usual ranks for n = 200
    assert ex.median_interval(np.arange(6, 0, -1)) == (1.0, 6.0)
    with pytest.raises(ValueError, match="too few"):
        ex.median_interval(np.arange(5))
    table, err = ex.analog_accuracy((1e-3,), 20, 1)
    lo, hi = table.iloc[0]["median: 95% low"], table.iloc[0]["median: 95% high"]
    assert lo <= table.iloc[0]["median max |error| of beta"] <= hi


def test_tracking_sampling_errors():
    res = [{"jpda": {"rmse": 1.0, "swapped": s, "lost": 0, "tracks": 3},
            "gnn": {"rmse": 2.0, "swapped": g, "lost": 1, "tracks": 3}} for s, g in ((0, 0), (1, 2), (0, 1), (0, 0))]
    t, tol = ex.tracking_sampling(res)
    assert t["tracker"].tolist() == ["JPDA", "GNN", "JPDA - GNN (paired)"]
    x = np.array([0, 1, 0, 0]) / 3
    assert t.loc[0, "swapped or lost"] == pytest.approx(x.mean())
    assert t.loc[0, "standard error (runs)"] == pytest.approx(x.std(ddof=1) / 2)
    d = x - np.array([1, 3, 2, 1]) / 3
    assert t.loc[2, "swapped or lost"] == pytest.approx(d.mean())
    assert t.loc[2, "standard error (runs)"] == pytest.approx(d.std(ddof=1) / 2)
    assert tol["swapped or lost"].atol == pytest.approx(0.5)
    with pytest.raises(ValueError, match="two"):
        ex.tracking_sampling(res[:1])


def test_normalization_summary_and_the_equivalence_trial():
    study = ex.equivalence_study(20, 4)
    n = ex.normalization_summary(study)
    assert n["below 1e-12"].tolist() == [True, False]
    assert (study["norm"] < 1e-12).all()
    with pytest.raises(ValueError, match="equivalence_study"):
        ex.normalization_summary(study.drop(columns="norm"))


def test_permanent_by_interpolation_and_event_orders():
    rng = np.random.default_rng(2)
    for n in (1, 2, 3, 4, 5):
        A = (rng.random((n, n)) < 0.7).astype(float)
        assert ex.permanent_by_interpolation(A) == round(ex.permanent_rect(A))
    assert ex.permanent_by_interpolation(np.ones((4, 4))) == 24
    with pytest.raises(ValueError, match="0 and 1"):
        ex.permanent_by_interpolation(np.full((2, 2), 0.5))
    with pytest.raises(ValueError, match="square"):
        ex.permanent_by_interpolation(np.ones((2, 3)))
    v = np.array([[1, 1, 0], [1, 1, 1], [1, 0, 1]])  # Fig. 1
    orders = ex.event_orders(v)
    case5 = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    pos5 = {k: [i + 1 for i, om in enumerate(mats) if np.array_equal(om, case5)] for k, mats in orders.items()}
    assert pos5 == {"measurement 1 fastest": [5], "measurement 3 fastest": [8],
                    "by detections, then measurement 1 fastest": [6],
                    "by detections, then measurement 3 fastest": [8]}
    col = list(jpda.iter_feasibility_matrices(v, order="colexicographic"))
    assert all(np.array_equal(a, b) for a, b in zip(col, orders["measurement 1 fastest"]))

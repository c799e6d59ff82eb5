"""Tests of projtrack.experiments.neuralnet (the Sec. VI experiment of Barnard & Casasent)."""

import numpy as np
import pytest

from projtrack import neuralnet as nn
from projtrack.experiments.neuralnet import simulate
from projtrack.scenes.tracks3d import make_tracks


def test_simulate_small_is_deterministic():
    a = simulate(np.random.default_rng(2), 3, 2, 0.0)
    b = simulate(np.random.default_rng(2), 3, 2, 0.0)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    assert a["correct"].shape == (6,) and a["optimal_correct"].shape == (3,)
    np.testing.assert_array_equal(a["dataset"], [0, 0, 1, 1, 2, 2])


def test_simulate_scores_runs_against_the_scenes_it_draws():
    # the same draws by hand: data sets first, then the starts, then one batch of nets
    rng = np.random.default_rng(8)
    scenes = [make_tracks(rng, 4, 5, noise_percent=0.0) for _ in range(2)]
    D = nn.distance_tensor(np.stack([s.positions for s in scenes]) / 256.0)
    X0 = nn.initial_states(rng, 6, 4, 4, 5)
    res = nn.run_net(np.repeat(D, 3, axis=0), X0)
    want = [res.status[k] == "converged" and
            nn.is_correct_assignment(nn.states_to_assignment(res.states[k]), scenes[k // 3].labels)
            for k in range(6)]
    out = simulate(np.random.default_rng(8), 2, 3, 0.0)
    np.testing.assert_array_equal(out["correct"], want)
    np.testing.assert_array_equal(out["iterations"], res.iterations)
    # noise-free straight tracks: the exact optimum is the truth and costs nothing
    np.testing.assert_array_equal(out["optimal_correct"], [1.0, 1.0])
    np.testing.assert_allclose(out["true_cost"], 0.0, atol=1e-12)
    assert np.all(out["optimal_cost"] <= out["true_cost"] + 1e-12)


def test_simulate_without_references_and_beyond_the_exact_size():
    out = simulate(np.random.default_rng(5), 3, 1, 2.5, noise_law="coordinate", references=False)
    assert set(out) == {"dataset", "status", "iterations", "converged", "correct"}
    again = simulate(np.random.default_rng(5), 3, 1, 2.5, noise_law="coordinate", references=False)
    np.testing.assert_array_equal(out["iterations"], again["iterations"])
    big = simulate(np.random.default_rng(1), 1, 1, 0.0, n_targets=5, exact_max_targets=4, max_iter=2)
    assert np.isnan(big["optimal_correct"][0]) and np.isnan(big["optimal_cost"][0])


def test_simulate_validates_its_arguments():
    rng = np.random.default_rng(4)
    with pytest.raises(ValueError, match="noise_percent"):
        simulate(rng, 1, 1, -1.0)
    with pytest.raises(ValueError, match="noise_percent"):
        simulate(rng, 1, 1, float("nan"))
    with pytest.raises(TypeError, match="noise_percent"):
        simulate(rng, 1, 1, "5")
    with pytest.raises(ValueError, match="noise_law"):
        simulate(rng, 1, 1, 1.0, noise_law="Ball")
    with pytest.raises(TypeError, match="rng"):
        simulate(42, 1, 1, 0.0)
    with pytest.raises(ValueError, match="n_datasets"):
        simulate(rng, 0, 1, 0.0)
    with pytest.raises(TypeError, match="n_starts"):
        simulate(rng, 1, 1.5, 0.0)
    with pytest.raises(ValueError, match="unit"):
        simulate(rng, 1, 1, 0.0, unit=0.0)


# ----------------------------------------------------------------------------- studies
from projtrack import montecarlo  # noqa: E402
from projtrack.experiments.neuralnet import (MODES, TABLE1_KEYS, bound_direct_check, bound_trial,  # noqa: E402
                                             evolution_trial, fixed_point_bound, sensitivity_cell,
                                             sensitivity_trial, table1_study, table1_trial, truth_index)


def test_table1_study_concatenates_the_trials_of_each_level():
    out = table1_study([0.0, 2.5], 2, 1, 30)
    assert list(out) == [0.0, 2.5]
    for i, n in enumerate([0.0, 2.5]):
        parts = montecarlo.run(table1_trial, 2, np.random.default_rng(30 + i), n, 1)
        assert set(out[n]) == set(TABLE1_KEYS)
        for k in set(TABLE1_KEYS) - {"mode"}:
            np.testing.assert_array_equal(out[n][k], np.concatenate([p[k] for p in parts]))
        # a run is "correct" in its mode exactly when it is the paper's success
        np.testing.assert_array_equal(out[n]["mode"] == "correct", out[n]["correct"])
    with pytest.raises(ValueError, match="multiple"):
        table1_study([0.0], 5, 2, 0)
    with pytest.raises(ValueError, match="noise level"):
        table1_study([-1.0], 2, 2, 0)
    with pytest.raises(TypeError, match="noise_levels"):
        table1_study(0.0, 2, 2, 0)


def test_sensitivity_cell_counts_how_the_runs_end():
    counts = sensitivity_cell(0.0, 256, "ball", {}, [1, 2], 4, 2)
    parts = montecarlo.run(sensitivity_trial, 2, np.random.default_rng([1, 2]), 0.0, 256, "ball", 2, {})
    conv = np.concatenate([p["converged"] for p in parts])
    good = np.concatenate([p["correct"] for p in parts])
    assert list(counts) == list(MODES) and sum(counts.values()) == 4
    assert (counts["correct"], counts["wrong"]) == (int(good.sum()), int((conv & ~good).sum()))
    # parallel updates of the all-equal start flip whole frames together: every run ends in a 2-cycle
    par = sensitivity_cell(0.0, 256, "ball", {"mode": "parallel"}, 3, 2, 2)
    assert par["other cycle"] == 2
    with pytest.raises(TypeError, match="options"):
        sensitivity_trial(np.random.default_rng(0), 0.0, 256, "ball", 1, None)


def test_evolution_trial_records_every_sweep():
    runs = evolution_trial(np.random.default_rng(55), 2)
    assert len(runs) == 2
    for r in runs:
        h = r["history"]
        assert h.shape[1:] == (4, 4, 5) and h.shape[0] >= 2
        assert set(np.unique(h[1:])) <= {0.0, 1.0}
        if r["correct"]:
            A = nn.states_to_assignment(h[-1].astype(np.int8))
            assert nn.is_correct_assignment(A, r["scene"].labels)
            assert r["iterations"] <= h.shape[0] - 1
    with pytest.raises(ValueError, match="n_runs"):
        evolution_trial(np.random.default_rng(0), 0)


def test_truth_index_points_at_the_true_assignment():
    scene = make_tracks(np.random.default_rng(9), 4, 5, noise_percent=0.0)
    D = nn.distance_tensor(scene.positions)
    M = nn.assignment_max_sums(D)
    t = truth_index(scene.labels)
    assert len(t) == 4
    np.testing.assert_allclose(M[t], 0.0, atol=1e-9)       # straight, evenly spaced tracks
    assert np.sum(M < 1e-9) == 1                             # and no other assignment costs nothing
    with pytest.raises(ValueError, match="labels"):
        truth_index(np.zeros((5, 4), dtype=int))


def test_bound_trial_and_study():
    b = bound_trial(np.random.default_rng(1), 0.0)
    assert b["truth"] < 1e-9 < b["wrong"]
    noisy = fixed_point_bound([5.0], 2, 6001)
    assert list(noisy) == [5.0] and len(noisy[5.0]) == 2
    assert all(r["truth"] > 0 and r["wrong"] > 0 for r in noisy[5.0])
    assert noisy[5.0] == montecarlo.run(bound_trial, 2, np.random.default_rng(6001), 5.0)


def test_bound_direct_check_agrees_everywhere():
    scene = make_tracks(np.random.default_rng(6100), 4, 5, noise_percent=0.0)
    m, same, fixed = bound_direct_check(scene, 256)
    assert m == 24 ** 3 and same == m and fixed >= 1
    with pytest.raises(TypeError, match="TrackScene"):
        bound_direct_check(scene.positions, 256)


# ----------------------------------------------------------------------------- batched nets
from projtrack.experiments.neuralnet import (SimulationDraw, draw_simulation, run_draws,  # noqa: E402
                                             score_simulation, sensitivity_cells, simulate_trials)


def test_draw_run_score_is_simulate():
    draw = draw_simulation(np.random.default_rng(3), 2, 2, 2.5)
    assert isinstance(draw, SimulationDraw) and draw.X0.shape == (4, 4, 4, 5) and draw.D.shape == (2, 3, 4, 4, 4)
    res = nn.run_net(np.repeat(draw.D, 2, axis=0), draw.X0)
    got = score_simulation(draw, res)
    want = simulate(np.random.default_rng(3), 2, 2, 2.5)
    assert set(got) == set(want)
    for k in want:
        np.testing.assert_array_equal(got[k], want[k])
    with pytest.raises(TypeError, match="draw"):
        score_simulation(res, res)
    with pytest.raises(ValueError, match="shape"):
        score_simulation(draw_simulation(np.random.default_rng(3), 1, 1, 0.0), res)


def test_batched_trials_equal_trials_run_one_by_one():
    one_by_one = montecarlo.run(simulate, 3, np.random.default_rng(11), 2, 2, 5.0, references=False,
                                self_coupling=False)
    batched = simulate_trials(3, np.random.default_rng(11), 2, 2, 5.0, references=False, self_coupling=False)
    assert len(batched) == 3
    for a, b in zip(one_by_one, batched):
        for k in a:
            np.testing.assert_array_equal(a[k], b[k])
    assert simulate_trials(0, np.random.default_rng(0), 1, 1, 0.0) == []


def test_run_draws_splits_the_batch_back():
    draws = [draw_simulation(np.random.default_rng(s), 1 + s, 2, 0.0) for s in range(3)]
    results = run_draws(draws, max_iter=3)
    assert [len(r.states) for r in results] == [2, 4, 6]
    for d, r in zip(draws, results):
        alone = nn.run_net(np.repeat(d.D, 2, axis=0), d.X0, max_iter=3)
        np.testing.assert_array_equal(r.states, alone.states)
        np.testing.assert_array_equal(r.iterations, alone.iterations)
        np.testing.assert_array_equal(r.status, alone.status)
    with pytest.raises(TypeError, match="draws"):
        run_draws([])
    with pytest.raises(ValueError, match="share"):
        run_draws([draws[0], draw_simulation(np.random.default_rng(0), 1, 1, 0.0, n_targets=3)])


def test_sensitivity_cells_equal_single_cells_in_any_grouping():
    cells = [(0.0, 256, "ball", {}, [1]), (5.0, 2048, "radial", {"self_coupling": False}, [2]),
             (2.5, 1024, "ball", {}, [3])]
    many = sensitivity_cells(cells, 2, 1)
    assert many == [sensitivity_cell(*c, 2, 1) for c in cells]
    assert sensitivity_cells(cells[::-1], 2, 1) == many[::-1]
    with pytest.raises(ValueError, match="cells"):
        sensitivity_cells([(0.0, 256, "ball", {})], 2, 1)
    with pytest.raises(TypeError, match="options"):
        sensitivity_cells([(0.0, 256, "ball", None, 0)], 2, 1)


# ----------------------------------------------------------------------------- comparison with the references
from projtrack.experiments.neuralnet import (METHODS, accuracy, comparison_cells, comparison_trial,  # noqa: E402
                                             noise_sweep, size_sweep)


def _concat(parts):
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def test_comparison_cells_equal_trials_run_one_by_one():
    cells = [(0.0, 3, 41), (5.0, 4, [42, 1]), (2.5, 3, 43)]
    got = comparison_cells(cells, 2, 2)
    for (n, nt, seed), res in zip(cells, got):
        want = _concat(montecarlo.run(comparison_trial, 2, np.random.default_rng(seed), 2, n, nt))
        assert set(res) == set(want)
        for k in want:
            if k != "dataset":
                np.testing.assert_array_equal(res[k], want[k])
        np.testing.assert_array_equal(res["dataset"], [0, 0, 1, 1])
    with pytest.raises(ValueError, match="cells"):
        comparison_cells([(0.0, 4)], 1, 1)
    with pytest.raises(TypeError, match="cells"):
        comparison_cells([], 1, 1)
    with pytest.raises(ValueError, match="n_datasets"):
        comparison_cells([(0.0, 4, 0)], 0, 1)


def test_comparison_cells_do_not_depend_on_n_jobs():
    cells = [(5.0, 3, 7), (0.0, 3, 8)]
    serial = comparison_cells(cells, 3, 1, n_jobs=1)
    parallel = comparison_cells(cells, 3, 1, n_jobs=2)
    for a, b in zip(serial, parallel):
        assert set(a) == set(b)
        for k in a:
            np.testing.assert_array_equal(a[k], b[k])


def test_accuracy_averages_the_net_over_data_sets():
    res = {"dataset": np.array([0, 0, 0, 0, 1, 1]), "correct": np.array([1, 1, 1, 0, 0, 0], bool),
           "optimal_correct": np.array([1.0, 0.0]), "cd_correct": np.array([True, True]),
           "greedy_correct": np.array([False, True]), "nn_correct": np.array([False, False])}
    acc = accuracy(res)
    assert list(acc) == list(METHODS)
    assert acc["net"] == pytest.approx(37.5)        # mean of 75% and 0%, not 3 of 6 runs
    assert (acc["optimum"], acc["coordinate descent"], acc["greedy on eq. (7)"], acc["nearest neighbour"]) == (
        50.0, 100.0, 50.0, 0.0)
    assert np.isnan(accuracy({**res, "optimal_correct": np.array([np.nan, 1.0])})["optimum"])
    with pytest.raises(ValueError, match="reference"):
        accuracy({"dataset": res["dataset"], "correct": res["correct"]})
    with pytest.raises(TypeError, match="res"):
        accuracy([res])


def test_net_standard_error_is_over_data_sets():
    from projtrack.experiments.neuralnet import net_standard_error
    res = {"dataset": np.repeat(np.arange(4), 2), "correct": np.array([1, 1, 0, 0, 1, 0, 1, 0], bool)}
    per_set = np.array([1.0, 0.0, 0.5, 0.5])
    assert net_standard_error(res) == pytest.approx(100 * per_set.std(ddof=1) / 2)
    assert np.isnan(net_standard_error({"dataset": np.zeros(3, int), "correct": np.ones(3, bool)}))
    with pytest.raises(TypeError):
        net_standard_error([])


def test_noise_and_size_sweeps_are_rows_of_their_cells():
    rows = noise_sweep([0.0, 5.0], 2, 1, seed=90)
    assert [r["noise %"] for r in rows] == [0.0, 5.0]
    for i, r in enumerate(rows):
        res = comparison_cells([([0.0, 5.0][i], 4, 90 + i)], 2, 1)[0]
        assert r["net sweeps per run"] == float(res["iterations"].mean())
        assert r["net"] == accuracy(res)["net"]
        from projtrack.experiments.neuralnet import net_standard_error
        assert r["net s.e."] == pytest.approx(net_standard_error(res), nan_ok=True)
        assert 0 <= r["optimum cost <= true cost %"] <= 100
    size_rows = size_sweep([3], [0.0, 5.0], 2, 1, seed=95)
    assert [(r["targets"], r["noise %"]) for r in size_rows] == [(3, 0.0), (3, 5.0)]
    res = comparison_cells([(5.0, 3, 96)], 2, 1)[0]
    assert size_rows[1]["net converged %"] == 100 * float(res["converged"].mean())
    with pytest.raises(ValueError, match="10 noise levels"):
        size_sweep([3], [0.0] * 11, 1, 1, seed=0)
    with pytest.raises(TypeError, match="noise_levels"):
        noise_sweep(0.0, 1, 1, seed=0)


# ----------------------------------------------------------------------------- degraded data
from projtrack.experiments.neuralnet import (OUTCOMES, TOLERATED, degraded_outcome, degraded_study,  # noqa: E402
                                             draw_degraded)


def test_draw_degraded_keeps_the_intended_assignment():
    d = draw_degraded(np.random.default_rng(1), 1, 2, 3)
    assert d.positions.shape == (5, 5, 3) and d.X0.shape == (3, 4, 5, 5) and d.labels.shape == (5, 5)
    assert d.padded.sum() == 2 and np.all(d.positions[d.padded] == 0.0)
    assert nn.is_correct_assignment(d.intended, d.labels)
    with pytest.raises(ValueError, match="n_starts"):
        draw_degraded(np.random.default_rng(0), 0, 0, 0)


def test_degraded_outcome_classifies_each_ending():
    rng = np.random.default_rng(4)
    d = draw_degraded(rng, 1, 1, 1)
    n_m = d.labels.shape[1]
    X = nn.assignment_to_states(d.intended, n_m)
    assert degraded_outcome(X, True, d) == "intended"
    assert degraded_outcome(X, False, d) == "not converged"
    a = int(np.flatnonzero(d.padded.any(axis=1))[0])         # the frame with the missing detection
    i = int(d.labels[a, d.padded[a]][0])                      # whose detection is missing
    spur = int(np.flatnonzero(d.labels[a] < 0)[0])
    gap = d.intended.copy()
    gap[i, a] = spur
    assert degraded_outcome(nn.assignment_to_states(gap, n_m), True, d) == "gap filled by a spurious measurement"
    b = (a + 1) % 5                                           # a complete frame
    wrong = d.intended.copy()
    wrong[0, b] = int(np.flatnonzero(d.labels[b] < 0)[0])
    assert degraded_outcome(nn.assignment_to_states(wrong, n_m), True, d) == "spurious on a true track"
    swap = d.intended.copy()
    swap[[0, 1], b] = swap[[1, 0], b]
    assert degraded_outcome(nn.assignment_to_states(swap, n_m), True, d) == "other wrong"
    assert degraded_outcome(np.ones_like(X), True, d) == "other wrong"    # not admissible
    assert set(TOLERATED) < set(OUTCOMES)
    with pytest.raises(TypeError, match="DegradedDraw"):
        degraded_outcome(X, True, None)


def test_degraded_study_runs_every_reading_on_the_same_draws():
    conditions = [("spurious", 1, 0), ("missing", 0, 1)]
    readings = [("printed", 256, {}), ("large unit", 4096, {}), ("frames", 256, {"frame_rule": True})]
    rows = degraded_study(conditions, readings, 2, 2, seed=12)
    assert [(r["condition"], r["reading"]) for r in rows] == [(c[0], r[0]) for c in conditions for r in readings]
    for c, (label, n_sp, n_mi) in enumerate(conditions):
        draws = montecarlo.run(draw_degraded, 2, np.random.default_rng([12, c]), n_sp, n_mi, 2)
        D = np.stack([nn.distance_tensor(d.positions / 256.0) for d in draws])
        r = nn.run_net(np.repeat(D, 2, axis=0), np.concatenate([d.X0 for d in draws]))
        want = [degraded_outcome(r.states[k], bool(r.converged[k]), draws[k // 2]) for k in range(4)]
        row = rows[3 * c]
        assert row["tolerated %"] == 25 * sum(w in TOLERATED for w in want)
        assert sum(row[f"{o} %"] for o in OUTCOMES) == pytest.approx(100.0)
        assert np.isnan(rows[3 * c + 2]["intended is a fixed point %"])
    with pytest.raises(ValueError, match="conditions"):
        degraded_study([(1,)], readings, 1, 1, seed=0)
    with pytest.raises(TypeError, match="options"):
        degraded_study(conditions, [("x", 256, None)], 1, 1, seed=0)
    with pytest.raises(ValueError, match="unit"):
        degraded_study(conditions, [("x", 0, {})], 1, 1, seed=0)


def test_direct_check_trial_draws_its_own_data_set():
    from projtrack.experiments.neuralnet import direct_check_trial
    m, same, fixed = direct_check_trial(np.random.default_rng(6100), 0.0, 256)
    scene = make_tracks(np.random.default_rng(6100), 4, 5, noise_percent=0.0)
    assert (m, same, fixed) == bound_direct_check(scene, 256)


# ----------------------------------------------------------------------------- the Table 1 criterion
from projtrack.experiments.neuralnet import fmt_p, k_range, p_row, p_table, rate_ci  # noqa: E402


def test_rate_ci_is_the_exact_interval():
    lo, hi = rate_ci(0, 10)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** 0.1)
    lo, hi = rate_ci(10, 10)
    assert hi == 1.0 and lo == pytest.approx(0.025 ** 0.1)
    with pytest.raises(ValueError, match="k"):
        rate_ci(11, 10)
    with pytest.raises(ValueError, match="n"):
        rate_ci(0, 0)


def test_k_range_p_row_and_p_table():
    assert k_range(0.0, 0.0) == (0, 0) and k_range(1.0, 1.0) == (10, 10)
    lo, hi = k_range(0.5, 0.5)
    assert (lo, hi) == (2, 8)
    assert p_row(0.9, 10) == pytest.approx(0.9 ** 10)
    assert p_row(0.3, 0) == pytest.approx(1.0)
    # no wrong stops in ten runs and at least k successes
    assert p_row(0.5, 0, wrong=0.1) == pytest.approx(0.9 ** 10)
    assert p_row(0.5, 3, wrong=1.0) == 0.0
    assert p_table([0.9, 0.9], [10, 9]) == pytest.approx(p_row(0.9, 10) * p_row(0.9, 9))
    assert p_table([1.0] * 4, [10, 10, 9, 8], [0.0] * 4) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="rows"):
        p_table([0.9], [10, 9])
    with pytest.raises(ValueError, match="k_range|p_hi"):
        k_range(0.6, 0.5)
    with pytest.raises(ValueError, match="p"):
        p_row(1.5, 3)


def test_fmt_p_bounds_tiny_probabilities():
    assert fmt_p(1e-13) == "< 1e-12" and fmt_p(1e-13, eq=True) == "< 1e-12"
    assert fmt_p(0.0123) == "0.012" and fmt_p(0.0123, eq=True) == "= 0.012"


# ----------------------------------------------------------------------------- the sensitivity study
import pandas as pd  # noqa: E402

from projtrack.experiments.neuralnet import (SENSITIVITY_RULES, ci_step, mode_probability,  # noqa: E402
                                             sensitivity_readings, table1_readings, sensitivity_seed, sensitivity_study,
                                             sensitivity_table, sensitivity_verdicts, ten_run_replications)


def test_sensitivity_readings_grid():
    r = sensitivity_readings([64, 256], [300], ["ball", "radial"], coarse_units=[256], parallel_unit=64)
    labels = [x[0] for x in r]
    assert labels == ["as printed, ball, unit 64", "as printed, ball, unit 256", "as printed, ball, unit 300",
                      "as printed, radial, unit 256", "as printed, radial, unit 300",
                      "no self term, ball, unit 64", "no self term, ball, unit 256",
                      "exact energy change, ball, unit 64", "exact energy change, ball, unit 256",
                      "parallel updates, ball, unit 64"]
    assert r[5][1:] == (64, "ball", {"self_coupling": False}) and r[-1][3] == {"mode": "parallel"}
    with pytest.raises(ValueError, match="laws"):
        sensitivity_readings([64], [], ["ball", "ball"])
    with pytest.raises(ValueError, match="units"):
        sensitivity_readings([], [64], ["ball"])
    with pytest.raises(TypeError, match="laws"):
        sensitivity_readings([64], [64], "ball")


def test_sensitivity_seed_shares_noise_free_cells():
    assert list(SENSITIVITY_RULES)[1] == "no self term"
    assert sensitivity_seed("no self term", 256, 2, 3, 5.0) == [3000, 1, 256, 2, 3]
    assert sensitivity_seed("no self term", 256, 2, 3, 0.0) == [3000, 1, 256, 0, 0]
    with pytest.raises(ValueError, match="rule"):
        sensitivity_seed("other", 256, 0, 0, 0.0)
    with pytest.raises(ValueError, match="law_index"):
        sensitivity_seed("as printed", 256, -1, 0, 2.5)


def test_sensitivity_study_runs_each_cell_with_its_seed():
    laws = ["ball", "radial"]
    readings = [("as printed, ball, unit 256", 256, "ball", {}), ("as printed, radial, unit 256", 256, "radial", {}),
                ("no self term, ball, unit 1024", 1024, "ball", {"self_coupling": False})]
    sens = sensitivity_study(readings, [0.0, 2.5], laws, 2, 2)
    assert list(sens["reading"]) == [r[0] for r in readings for _ in range(2)]
    assert list(sens["noise %"]) == [0.0, 2.5] * 3
    for (label, u, law, kw), (_, s) in zip(readings, sens.groupby("reading", sort=False)):
        for i, (_, row) in enumerate(s.iterrows()):
            n = row["noise %"]
            seed = sensitivity_seed(label.split(",")[0], u, laws.index(law), i, n)
            assert {m: row[m] for m in MODES} == sensitivity_cell(n, u, "ball" if n == 0 else law, kw, seed, 2, 2)
    # the noise-free cell of a rule and unit is shared by the noise laws
    assert sens.iloc[0]["correct"] == sens.iloc[2]["correct"]
    assert (sens[list(MODES)].sum(axis=1) == sens["runs"]).all()
    table, tol = sensitivity_table(sens)
    assert list(table.columns) == ["reading", "noise %"] + [f"{m} %" for m in MODES]
    assert (table["correct %"] == 50 * sens["correct"]).all() and tol["*"].atol == 50.0
    with pytest.raises(ValueError, match="noise law"):
        sensitivity_study(readings, [0.0], ["ball"], 2, 1)
    with pytest.raises(ValueError, match="readings"):
        sensitivity_study([("as printed", 256)], [0.0], laws, 2, 1)


def _sens(rows):
    """A sensitivity table from (reading, noise, correct, wrong, cycle with the truth, wandering) rows of 4 runs."""
    out = []
    for r, n, c, w, q, wa in rows:
        out.append({"reading": r, "noise %": n, "runs": 4, "correct": c, "wrong": w, "cycle with the truth": q,
                    "other cycle": 4 - c - w - q - wa, "wandering": wa})
    return pd.DataFrame(out)


def test_sensitivity_verdicts_apply_the_criterion():
    sens = _sens([("a", 0.0, 4, 0, 0, 0), ("a", 5.0, 4, 0, 0, 0), ("b", 0.0, 4, 0, 0, 0), ("b", 5.0, 0, 2, 1, 1)])
    v, tol = sensitivity_verdicts(sens, [10, 9])
    assert list(v["reading"]) == ["a", "b"]
    assert v["P(table >= paper's)"].tolist() == pytest.approx([1.0, 0.0])
    assert v["reproduces Table 1"].tolist() == [True, False]
    assert v.loc[1, "at 95% high"] == pytest.approx(p_table([1.0, rate_ci(0, 4)[1]], [10, 9]))
    assert v.loc[1, "P(... and no wrong stop)"] == 0.0
    # reading a has no failures at the level where the paper has them; b has 4: 1 cycle, 1 wandering
    assert np.isnan(v.loc[0, "P(paper's failure modes)"]) and not v.loc[0, "failure modes seen"]
    assert v.loc[1, "P(paper's failure modes)"] == pytest.approx(mode_probability(0.25, 0.25))
    # the tolerance is the largest change one run makes: here a success more in b's noisy cell
    assert tol["P(table >= paper's)"].atol >= p_row(0.25, 9) - 1e-12
    with pytest.raises(ValueError, match="paper_k"):
        sensitivity_verdicts(sens, [10])
    with pytest.raises(TypeError, match="DataFrame"):
        sensitivity_verdicts(sens.to_dict(), [10, 9])
    with pytest.raises(ValueError, match="columns"):
        sensitivity_verdicts(sens.drop(columns="correct"), [10, 9])


def test_table1_readings_score_each_level():
    from projtrack.experiments.neuralnet import table1_readings
    res = {0.0: {"correct": np.array([True, True, False, False]), "converged": np.array([True, True, True, False]),
                 "iterations": np.array([10, 20, 30, 99]), "mode": np.array(["correct"] * 2 + ["wrong", "wandering"]),
                 "optimal_correct": np.array([True, False])},
           2.5: {"correct": np.zeros(4, bool), "converged": np.zeros(4, bool), "iterations": np.zeros(4, int),
                 "mode": np.array(["other cycle"] * 3 + ["cycle with the truth"]), "optimal_correct": np.array([True])}}
    t, tol = table1_readings(res, [10, 9], [19, 16])
    assert list(t["noise %"]) == [0.0, 2.5] and list(t["success %"]) == [50.0, 0.0]
    assert t.loc[0, "iterations"] == 20.0 and np.isnan(t.loc[1, "iterations"])
    assert t.loc[0, "wrong %"] == 25.0 and t.loc[0, "wandering %"] == 25.0 and t.loc[1, "other cycle %"] == 75.0
    assert t.loc[1, "cycle with the truth %"] == 25.0
    assert list(t["optimum correct %"]) == [50.0, 100.0]
    lo, hi = rate_ci(2, 4)
    assert (t.loc[0, "95% low %"], t.loc[0, "95% high %"]) == pytest.approx((100 * lo, 100 * hi))
    assert t.loc[0, "P(k >= paper's)"] == pytest.approx(p_row(hi, 10))
    assert tol["success %"].atol == 25.0 and tol["95% high %"].atol == pytest.approx(100 * ci_step(4))
    assert tol["iterations"].atol == pytest.approx(50 / 3)     # three converged runs at 0% noise
    with pytest.raises(ValueError, match="levels"):
        table1_readings(res, [10], [19])
    with pytest.raises(ValueError, match="lacks"):
        table1_readings({0.0: {"correct": np.ones(2, bool)}}, [10], [19])
    with pytest.raises(TypeError, match="mapping"):
        table1_readings([1, 2], [10, 9], [19, 16])


def test_ci_step_is_the_largest_move_of_a_bound():
    steps = [abs(rate_ci(k + 1, 20)[j] - rate_ci(k, 20)[j]) for k in range(20) for j in (0, 1)]
    assert ci_step(20) == pytest.approx(max(steps))
    assert 1 / 20 < ci_step(20) < 3 / 20


def test_ten_run_replications_cut_the_runs_in_tens():
    res = {0.0: {"correct": np.array([True] * 10 + [True] * 9 + [False])},
           5.0: {"correct": np.array([True] * 9 + [False] + [False] * 10)}}
    t, as_good, tol = ten_run_replications(res, [10, 9])
    assert list(t["median k/10"]) == [9.5, 4.5] and list(t["min k/10"]) == [9.0, 0.0]
    assert list(t["as good as the paper's %"]) == [50.0, 50.0]
    assert as_good == 1                                   # only the first ten of both levels
    assert tol["as good as the paper's %"].atol == 50.0 and tol["median k/10"].atol == 1.0
    with pytest.raises(ValueError, match="multiple"):
        ten_run_replications({0.0: {"correct": np.ones(5, bool)}}, [10])
    with pytest.raises(ValueError, match="paper_k"):
        ten_run_replications(res, [10])


# ----------------------------------------------------------------------------- failure modes
from projtrack.experiments.neuralnet import (FAILURE_MODES, draws_modes, mode_counts,  # noqa: E402
                                             one_pairing_away, run_modes)


def test_one_pairing_away_means_one_target_in_one_frame():
    truth = nn.assignment_to_states(np.array([[0, 0, 0], [1, 1, 1]]), 2)
    off = truth.copy(); off[0, 0, 1] = 0
    moved = truth.copy(); moved[0, :, 2] = [0, 1]
    swap = nn.assignment_to_states(np.array([[0, 1, 0], [1, 0, 1]]), 2)
    assert one_pairing_away(off, truth) and one_pairing_away(moved, truth)
    assert not one_pairing_away(swap, truth) and not one_pairing_away(truth, truth)
    with pytest.raises(ValueError, match="shape"):
        one_pairing_away(truth[0], truth)


def test_run_modes_finds_the_other_state_of_a_two_cycle():
    # parallel updates from the all-equal start: whole frames switch on and off together
    draw = draw_simulation(np.random.default_rng(2), 2, 1, 0.0)
    res = nn.run_net(draw.D, draw.X0, mode="parallel", max_iter=6)
    assert set(res.status) == {"oscillating"} and set(res.period) == {2}
    labels = [s.labels for s in draw.scenes]
    assert list(run_modes(draw.D, res, labels, mode="parallel")) == ["other cycle"] * 2
    # a made-up two-cycle between the truth and a state one pairing away is recognised as the paper's
    truth = nn.assignment_to_states(np.argsort(labels[0], axis=1).T, 4)
    near = truth.copy(); near[0, :, 2] = 0
    fake = nn.NetResult(np.stack([near, truth]), np.array(["oscillating", "converged"]), np.array([50, 3]),
                        np.array([2, 1]))
    D = np.repeat(draw.D[:1], 2, axis=0)
    modes = run_modes(D, fake, [labels[0]] * 2)
    assert modes[1] == "correct"
    # the first run's partner is one sweep away from `near`; it is the paper's mode only if that sweep gives the truth
    partner = nn.run_net(D[:1], near[None].astype(float), max_iter=1).states[0]
    assert modes[0] == ("cycle with the truth" if np.array_equal(partner, truth) else "other cycle")
    with pytest.raises(ValueError, match="labels"):
        run_modes(draw.D, res, labels[:1])
    with pytest.raises(TypeError, match="NetResult"):
        run_modes(draw.D, None, labels)


def test_draws_modes_equal_modes_run_draw_by_draw():
    draws = [draw_simulation(np.random.default_rng(s), 2, 2, 5.0, unit=2048.0) for s in range(3)]
    results = run_draws(draws)
    got = draws_modes(draws, results)
    for d, r, m in zip(draws, results, got):
        labels = [d.scenes[k // 2].labels for k in range(4)]
        np.testing.assert_array_equal(m, run_modes(np.repeat(d.D, 2, axis=0), r, labels))
        assert sum(mode_counts(m).values()) == 4
    with pytest.raises(ValueError, match="modes"):
        mode_counts(np.array(["sleeping"]))
    assert FAILURE_MODES == MODES[1:]


def test_mode_probability_needs_both_modes_among_three_failures():
    assert mode_probability(0.0, 1.0) == 0.0 and mode_probability(1.0, 0.0) == 0.0
    assert mode_probability(0.5, 0.5) == pytest.approx(1 - 2 / 8)
    assert mode_probability(0.2, 0.3) == pytest.approx(0.5 ** 3 - 0.2 ** 3 - 0.3 ** 3)
    assert mode_probability(0.0, 0.0) == 0.0
    with pytest.raises(ValueError, match="<= 1"):
        mode_probability(0.7, 0.7)


# ----------------------------------------------------------------------------- other update rules
import itertools  # noqa: E402

from projtrack.experiments.neuralnet import (frame_descent, frame_rule_study, nearest_admissible,  # noqa: E402
                                             update_order_study)


def test_nearest_admissible_takes_the_largest_start_values():
    X0 = np.zeros((2, 3, 3))
    X0[0, 2, :] = 1.0
    X0[1, 2, 0], X0[1, 1, 0] = 0.9, 0.5       # frame 0: target 1 cannot have measurement 2
    A = nearest_admissible(X0)
    assert A[0].tolist() == [2, 2, 2] and A[1, 0] == 1
    assert all(len(set(A[:, a])) == 2 for a in range(3))
    with pytest.raises(ValueError, match="N_T <= N_M"):
        nearest_admissible(np.zeros((3, 2, 3)))


def test_frame_descent_stops_where_no_frame_can_improve():
    scene = make_tracks(np.random.default_rng(21), 4, 5, noise_percent=5.0)
    D = nn.distance_tensor(scene.positions / 256)
    start = np.stack([np.random.default_rng(3).permutation(4) for _ in range(5)], axis=1)
    A, rounds, converged = frame_descent(D, start)
    assert converged and 0 <= rounds < 50
    cost = nn.assignment_cost(A, D)
    assert cost <= nn.assignment_cost(start, D) + 1e-12
    for f in range(5):                                   # brute force: no frame re-assignment is cheaper
        for p in itertools.permutations(range(4)):
            B = A.copy(); B[:, f] = p
            assert nn.assignment_cost(B, D) >= cost - 1e-9
    # noise-free data: started from the truth it stays there, in zero rounds
    clean = make_tracks(np.random.default_rng(22), 4, 5)
    truth = np.argsort(clean.labels, axis=1).T
    A, rounds, converged = frame_descent(nn.distance_tensor(clean.positions / 256), truth)
    assert rounds == 0 and converged and np.array_equal(A, truth)
    with pytest.raises(ValueError, match="admissible"):
        frame_descent(D, np.zeros((4, 5), dtype=int))
    with pytest.raises(ValueError, match="initial"):
        frame_descent(D, np.zeros((4, 4), dtype=int))


def test_frame_rule_study_runs_on_the_table1_draws():
    out = frame_rule_study([0.0, 5.0], 4, 2, seed=30)
    for i, n in enumerate([0.0, 5.0]):
        draws = montecarlo.run(draw_simulation, 2, np.random.default_rng(30 + i), 2, 1, n)
        want = [frame_descent(D, nearest_admissible(X0)) for d in draws for D, X0 in zip(d.D, d.X0)]
        np.testing.assert_array_equal(out[n]["rounds"], [r for _, r, _ in want])
        assert out[n]["correct"].dtype == bool and out[n]["correct"].shape == (4,)
    with pytest.raises(ValueError, match="multiple"):
        frame_rule_study([0.0], 3, 2, seed=0)


def test_update_order_study_runs_both_orders_on_the_same_draws():
    table, tol = update_order_study([0.0], [256], 4, 2, seed=8)
    assert list(table.columns) == ["unit (px)", "noise %", "serial converged %", "serial sweeps",
                                   "parallel converged %", "parallel sweeps"]
    draws = montecarlo.run(draw_simulation, 2, np.random.default_rng([8, 0, 0]), 2, 1, 0.0, unit=256.0)
    for mode in ["serial", "parallel"]:
        res = run_draws(draws, mode=mode)
        assert table.loc[0, f"{mode} sweeps"] == float(np.concatenate([r.iterations for r in res]).mean())
        assert table.loc[0, f"{mode} converged %"] == 100 * float(np.concatenate([r.converged for r in res]).mean())
    assert table.loc[0, "parallel converged %"] == 0.0 and table.loc[0, "parallel sweeps"] == 50.0
    assert tol["serial sweeps"].atol == 12.5 and tol["serial converged %"].atol == 25.0
    with pytest.raises(ValueError, match="empty"):
        update_order_study([], [256], 2, 2, seed=0)


def test_frame_rule_table_reads_the_study():
    from projtrack.experiments.neuralnet import frame_rule_table
    frames = {0.0: {"correct": np.array([True, False]), "converged": np.array([True, True]),
                    "rounds": np.array([2, 4])}}
    t, tol = frame_rule_table(frames, [10])
    assert t.loc[0, "correct %"] == 50.0 and t.loc[0, "stopped wrong %"] == 50.0 and t.loc[0, "rounds"] == 3.0
    assert tol["*"].atol == 50.0 and tol["rounds"].atol == 25.0
    with pytest.raises(ValueError, match="paper_k"):
        frame_rule_table(frames, [10, 9])


# ----------------------------------------------------------------------------- eq. (8) and eq. (10)
from projtrack.experiments.neuralnet import (central_differences, connection_check, eq8_term3_check,  # noqa: E402
                                             term3_eq9, term3_printed, term3_read)


def test_term3_as_printed_is_not_the_integral_of_eq9():
    X = np.random.default_rng(5).random((3, 3, 4))
    check = eq8_term3_check(X)
    assert check["read"] < 1e-7 < 1.0 < check["printed"]
    # the printed form puts N_T measurements on every target: the correct assignment does not minimise it
    A = nn.assignment_to_states(np.array([[0, 0, 0, 0], [1, 1, 1, 1], [2, 2, 2, 2]]), 3).astype(float)
    assert term3_read(A) == 0.0 and term3_printed(A) == 15 * 3 * 4 * (1 - 3) ** 2
    assert term3_printed(np.ones((3, 3, 4))) == 0.0
    np.testing.assert_allclose(term3_eq9(A), 0.0)
    np.testing.assert_allclose(central_differences(lambda Y: float((Y ** 2).sum()), X), 2 * X, atol=1e-7)
    with pytest.raises(ValueError, match="shape"):
        term3_read(np.zeros((3, 3)))
    with pytest.raises(TypeError, match="callable"):
        central_differences(None, X)


def test_connection_check_counts_and_compares():
    out = connection_check(3, 3, 3, np.random.default_rng(0))
    assert out["neurons"] == 27 and out["T1 ones"] == 27 * 2 and out["T2 ones"] == 27 * 2 and out["T3 ones"] == 27 * 9
    assert out["max difference"] < 1e-12 and out["assignment ones"] == 9 and out["assignment, active max"] < 1e-12
    big = connection_check(10, 10, 3, np.random.default_rng(1))
    assert big["neurons"] == 300 and big["assignment ones"] == 30
    with pytest.raises(ValueError, match="n_frames"):
        connection_check(3, 3, 2, np.random.default_rng(0))


def test_gradient_forms_agree_except_the_printed_term3():
    from projtrack.experiments.neuralnet import gradient_forms
    scene = make_tracks(np.random.default_rng(3), 3, 4)
    D = nn.distance_tensor(scene.positions / 256)
    table, exact_ok, fd_ok, printed = gradient_forms(np.random.default_rng(4).random((3, 3, 4)), D)
    assert exact_ok and fd_ok and printed > 1.0
    assert list(table["agrees"]) == [True, True, True, True, False]
    assert table["largest difference from eq. (9)"].iloc[0] == "< 1e-12"


def test_bound_text_hides_rounding_noise_only():
    from projtrack.experiments.neuralnet import bound_text
    assert bound_text(0.0) == "< 1e-12" and bound_text(2e-9, 1e-7) == "< 1e-7"
    assert bound_text(0.5) == "5.0e-01"
    with pytest.raises(ValueError, match="value"):
        bound_text(-1.0)


# ----------------------------------------------------------------------------- the bound, read at cuts
from projtrack.experiments.neuralnet import (bound_holds, bound_table, cut_for_rates, fixed_point_grid,  # noqa: E402
                                             stable_down, stable_up, table1_tables)

_BOUND = {0.0: [{"truth": 0.0, "wrong": 30.0}, {"truth": 1e-14, "wrong": 50.0}],
          5.0: [{"truth": 10.0, "wrong": 40.0}, {"truth": 60.0, "wrong": 70.0}]}


def test_bound_table_reads_the_enumeration_at_one_cut():
    t, tol = bound_table(_BOUND, 20.0)
    assert list(t["truth is a fixed point %"]) == [100.0, 50.0]
    assert list(t["a wrong one is a fixed point %"]) == [0.0, 0.0]
    assert t["median max S of the truth (px)"].tolist() == [0.0, 35.0]      # rounding noise of straight tracks is 0
    assert t.loc[1, "bound, 95% high %"] == pytest.approx(100 * rate_ci(1, 2)[1])
    assert tol["truth is a fixed point %"].atol == 50.0
    with pytest.raises(ValueError, match="0.0"):
        bound_table({5.0: _BOUND[5.0]}, 20.0)


def test_fixed_point_grid_scales_the_cut_with_rule_and_unit():
    rules = {"as printed": {}, "no self term": {"self_coupling": False}}
    g, tol = fixed_point_grid(_BOUND, rules, [256, 1])
    assert list(g.columns) == ["rule", "unit (px)", "truth fixed at 5% %", "wrong fixed at 0% %"]
    assert g["unit (px)"].tolist() == [256, 1, 256, 1]
    # as printed at 256 px the cut is 0.035 / 1.8 * 256 = 4.98 px; without the self term at 1 px it is 16.7 px
    assert g["truth fixed at 5% %"].tolist() == [0.0, 0.0, 100.0, 50.0]
    assert g["wrong fixed at 0% %"].tolist() == [0.0, 0.0, 100.0, 0.0]
    assert tol["*"].atol == 50.0


def test_cut_for_rates_and_bound_holds():
    assert cut_for_rates(_BOUND, {5.0: 0.5}) == pytest.approx(10.0, rel=1e-5)
    assert cut_for_rates(_BOUND, {5.0: 1.0}) == pytest.approx(60.0, rel=1e-5)
    assert cut_for_rates(_BOUND, {5.0: 0.0}) == 0.0
    grid = pd.DataFrame({"rule": ["as printed"], "unit (px)": [256], "truth fixed at 5% %": [0.0]})
    shares = pd.DataFrame({"reading": ["as printed, ball, unit 256"] * 2, "noise %": [0.0, 5.0],
                           "correct %": [80.0, 50.0]})
    h = bound_holds(grid, shares, runs=100, n_sets=100)
    assert len(h) == 1 and not h.loc[0, "holds"]          # 50 of 100 runs against a bound of 0 of 100 data sets
    assert bound_holds(grid, shares.assign(**{"correct %": [80.0, 1.0]}), 100, 100).loc[0, "holds"]
    with pytest.raises(ValueError, match="noise level"):
        cut_for_rates(_BOUND, {2.5: 0.5})


def test_stable_tolerances_do_not_move_with_one_run():
    assert stable_up(0.0061) == 0.007 == stable_up(0.0063) and stable_up(0.3) == 0.3
    assert stable_down(331) == stable_down(330) == 300 and stable_down(7) == 7
    with pytest.raises(ValueError, match="x"):
        stable_up(0.0)


def test_table1_tables_have_six_columns_at_most():
    res = {0.0: {"correct": np.array([True] * 10), "converged": np.ones(10, bool), "iterations": np.full(10, 20),
                 "mode": np.array(["correct"] * 10), "optimal_correct": np.array([True])},
           5.0: {"correct": np.zeros(10, bool), "converged": np.zeros(10, bool), "iterations": np.full(10, 50),
                 "mode": np.array(["wandering"] * 10), "optimal_correct": np.array([True])}}
    t1, t1_tol = table1_readings(res, [10, 9], [19, 20])
    reps, _, reps_tol = ten_run_replications(res, [10, 9])
    views = table1_tables(t1, reps, t1_tol, reps_tol)
    assert set(views) == {"table1", "outcomes", "intervals"}
    for table, tol in views.values():
        assert len(table.columns) <= 6 and set(tol) <= set(table.columns)
    assert views["table1"][0]["paper k/10 (it.)"].tolist() == ["10 (19)", "9 (20)"]
    assert views["outcomes"][0]["wandering %"].tolist() == [0.0, 100.0]
    with pytest.raises(ValueError, match="noise levels"):
        table1_tables(t1, reps.iloc[:1], t1_tol, reps_tol)


# ----------------------------------------------------------------------------- review fixes: energy minimum,
# first-sweep pattern, end states, operation counts


def _brute_minimum(D, n_t):
    import itertools
    n_q, n_m = D.shape[0], D.shape[1]
    inj = list(itertools.permutations(range(n_m), n_t))
    best = np.inf
    for p0 in itertools.combinations(range(n_m), n_t):
        for rest in itertools.product(inj, repeat=n_q + 1):
            frames = [p0, *rest]
            c = sum(D[a][frames[a][i], frames[a + 1][i], frames[a + 2][i]] for a in range(n_q) for i in range(n_t))
            best = min(best, c)
    return best


def test_degraded_optimum_matches_brute_force_and_the_square_optimum():
    from projtrack.experiments.neuralnet import degraded_optimum
    rng = np.random.default_rng(4)
    D = nn.distance_tensor(rng.random((4, 4, 3)))      # 4 frames, N_M = 4 (two triples)
    A, cost = degraded_optimum(D, 3)                  # N_T = 3 < N_M
    assert A.shape == (3, 4) and all(len(set(A[:, a])) == 3 for a in range(4))
    np.testing.assert_allclose(cost, nn.assignment_cost(A, D), rtol=1e-12)
    np.testing.assert_allclose(cost, _brute_minimum(D, 3), rtol=1e-12)
    D5 = nn.distance_tensor(rng.random((5, 4, 3)))     # N_T = N_M: same optimum as optimal_assignment
    np.testing.assert_allclose(degraded_optimum(D5, 4)[1], nn.optimal_assignment(D5)[1], rtol=1e-12)
    with pytest.raises(ValueError):
        degraded_optimum(D, 5)
    with pytest.raises(ValueError):
        degraded_optimum(np.zeros((2, 3, 3)), 2)


def test_degraded_optimum_study_keeps_clean_tracks_and_can_fail():
    from projtrack.experiments.neuralnet import degraded_optimum_study
    rows = degraded_optimum_study([("clean", 0, 0), ("both", 1, 1)], 3, 1, seed=5)
    assert [r["condition"] for r in rows] == ["clean", "both"]
    assert rows[0]["tolerated %"] == 100.0 and rows[0]["spurious measurement used %"] == 0.0
    for r in rows:
        assert r["global minimum"] is True
        shares = [r[k] for k in r if k.endswith(" %") and k not in ("tolerated %", "spurious measurement used %",
                                                                   "real measurements kept %",
                                                                   "spurious displacing a real %")]
        assert sum(shares) == pytest.approx(100.0)
    # with a spurious and a missing measurement the minimum is scored, not assumed to tolerate them
    assert 0.0 <= rows[1]["tolerated %"] <= 100.0


def test_degraded_optimum_puts_a_spurious_point_on_a_track_when_it_fits_better():
    from projtrack.experiments.neuralnet import DegradedDraw, degraded_optimum, degraded_outcome
    # two straight tracks; frame 2's real measurement of target 0 is off its line, a spurious one lies on it
    t = np.arange(5.0)[:, None]
    tracks = np.stack([np.hstack([t, 0 * t, 0 * t]), np.hstack([t, 10 + 0 * t, 0 * t])], axis=1)   # (5, 2, 3)
    pos = np.concatenate([tracks, np.full((5, 1, 3), 50.0)], axis=1)
    pos[2, 0] = [2.0, 4.0, 0.0]
    pos[2, 2] = [2.0, 0.0, 0.0]
    labels = np.tile([0, 1, -1], (5, 1))
    A, _ = degraded_optimum(nn.distance_tensor(pos), 2)
    assert A[0, 2] == 2
    draw = DegradedDraw(pos, labels, np.zeros((5, 3), bool), np.array([[0] * 5, [1] * 5]), np.zeros((1, 2, 3, 5)))
    assert degraded_outcome(nn.assignment_to_states(A, 3), True, draw) == "spurious on a true track"
    from projtrack.experiments.neuralnet import measurement_counts
    # 10 real measurements, one displaced by the spurious point; 5 spurious points, one displacing a real one
    np.testing.assert_array_equal(measurement_counts(A, draw), [9, 10, 1, 5])
    truth = np.array([[0] * 5, [1] * 5])
    np.testing.assert_array_equal(measurement_counts(truth, draw), [10, 10, 0, 5])


def test_tolerance_readings_pass_per_reading():
    import pandas as pd
    from projtrack.experiments.neuralnet import tolerance_readings
    o = pd.DataFrame({"tolerated %": [100.0, 96.0, 70.0], "real measurements kept %": [100.0, 100.0, 98.0],
                      "spurious displacing a real %": [0.0, np.nan, 8.0]}, index=["spurious", "missing", "both"])
    t = tolerance_readings(o).groupby("reading", sort=False)["passes"].all()
    assert t.to_dict() == {"each alone": True, "both, per data set": False, "both, per real measurement": True,
                           "both, per spurious measurement": False}
    o.loc["missing", "tolerated %"] = 90.0   # one condition failing fails the whole reading
    assert not tolerance_readings(o).groupby("reading", sort=False)["passes"].all()["each alone"]
    with pytest.raises(ValueError, match="conditions"):
        tolerance_readings(o.drop(index="both"))


def test_first_sweep_pattern_reads_rows_and_columns():
    from projtrack.experiments.neuralnet import first_sweep_pattern
    H = np.zeros((3, 4, 4, 5))
    H[1, 0, 0, 2] = H[1, 0, 1, 2] = 1          # sweep 1: target 0 holds two measurements in frame 2
    H[2, 1, 3, 0] = H[2, 2, 3, 0] = 1          # sweep 2: measurement 3 held by two targets in frame 0
    assert first_sweep_pattern(H) == {"active": 2, "target with several": True, "measurement with several": False,
                                      "conflict": True}
    assert first_sweep_pattern(H, 2)["measurement with several"] and not first_sweep_pattern(H, 2)["target with several"]
    assert not first_sweep_pattern(H, 0)["conflict"]
    with pytest.raises(ValueError):
        first_sweep_pattern(H, 3)


def test_end_states_partition_the_runs():
    from projtrack.experiments.neuralnet import end_states
    df = end_states({"as printed": {}, "no self term": {"self_coupling": False}}, [1, 256], [0.0], 6, seed=3)
    assert len(df) == 4
    parts = df[["correct %", "wrong admissible %", "inadmissible %", "not converged %"]].sum(axis=1)
    np.testing.assert_allclose(parts, 100.0)
    # D in pixels without the self term: conflicts stay on (the page's dropdown explains why)
    assert df.set_index(["rule", "unit (px)"]).loc[("no self term", 1.0), "inadmissible %"] == 100.0
    with pytest.raises(TypeError):
        end_states({}, [1], [0.0], 2, seed=1)


def test_operation_counts_by_hand_and_descent_rounds():
    from projtrack.experiments.neuralnet import descent_rounds, operation_counts
    c = operation_counts(4)
    # net: 16 neurons per frame, each 4 + 4 + 16 terms of terms 1-3 and 16 products per triple (1, 2, 3, 2, 1)
    assert c["net, one sweep"] == 16 * (5 * 24 + 16 * 9) == 4224
    assert c["net, one run"] == 19 * 4224
    assert c["exact optimum"] == 3 * 24 ** 3 * 4
    assert c["coordinate descent, one round"] == 16 * 9 + 5 * 64
    assert operation_counts(4, net_sweeps=1, descent_rounds=2)["coordinate descent, one run"] == 2 * 464
    with pytest.raises(ValueError):
        operation_counts(4, n_frames=2)
    r = descent_rounds(4, 0.0, 3, seed=1)
    assert r.shape == (3,) and np.all(r >= 1)


def test_optimum_net_ratios_by_hand():
    from projtrack.experiments.neuralnet import operation_counts, optimum_net_ratios
    r = optimum_net_ratios(4)
    c = operation_counts(4)
    assert r["book"] == pytest.approx(c["exact optimum"] / c["net, one run"])
    # lowest: frame 1 fixed (24^2 + 2 x 24^3 triples, 4 additions each) over the net with 3 operations per D X X
    assert r["lowest"] == pytest.approx((24 ** 2 + 2 * 24 ** 3) * 4 / (19 * 16 * (5 * 24 + 3 * 16 * 9)))
    assert r["highest"] == pytest.approx(3 * 24 ** 3 * 6 / c["net, one run"])
    assert r["lowest"] < r["book"] < r["highest"]

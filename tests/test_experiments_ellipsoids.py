"""Unit tests of the ellipsoid experiments (small sizes)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from projtrack import ellipsoids as E  # noqa: E402
from projtrack.experiments import ellipsoids as XP  # noqa: E402
from projtrack.experiments.ellipsoids import plots as P  # noqa: E402
from projtrack.scenes import ellipses as S  # noqa: E402


# --------------------------------------------------------------------------- static
def test_demo_interval_is_an_interval_containing_eq26():
    X_lo, X_hi = XP.demo_interval()
    assert E.in_interval(S.X26, X_lo, X_hi)
    assert np.allclose(E.axes(X_lo)[0], [1.4, 0.6]) and np.allclose(E.axes(X_hi)[0], [4.8, 2.4])
    # as in the paper, the outer bound leaves the plot area [-3.2, 3.2]^2 of the four-panel figures
    assert np.sqrt(X_hi[0, 0]) > 3.2 and np.sqrt(X_hi[1, 1]) > 3.2


def test_interval_readings_contain_eq26_and_start_with_ours():
    readings = XP.interval_readings()
    assert len(readings) == 5
    first = next(iter(readings.values()))
    assert all(np.array_equal(a, b) for a, b in zip(first, XP.demo_interval()))
    for lo, hi in readings.values():
        assert E.in_interval(S.X26, lo, hi)


def test_constraints_inactive_and_interval_bound_study():
    X_lo, X_hi = XP.demo_interval()
    Xl = np.stack([S.X26, -np.eye(2), 30 * np.eye(2)])
    assert XP.constraints_inactive(Xl, X_lo, X_hi).tolist() == [True, False, False]
    small = XP.shown_static_draw(0.3, np.random.default_rng(26), n_draws=20)
    large = XP.shown_static_draw(9.0, np.random.default_rng(1994), non_psd_only=True, n_draws=20)
    tab = XP.interval_bound_study(small["W"], large["W"], large["pool"], XP.interval_readings())
    assert list(tab["interval (semi-axes)"]) == list(XP.interval_readings())
    assert ((tab.iloc[:, 1:] >= 0) & (tab.iloc[:, 1:] <= 1)).all().all()
    lo, hi = XP.demo_interval()
    assert tab["F7: inactive"].iloc[0] == np.mean(XP.constraints_inactive(small["X_ls"], lo, hi))
    # the interval estimate cannot both equal its inner bound and beat it
    assert (tab["F9: interval = X_lo"] + tab["F9: interval beats X_lo"] <= 1).all()


def test_snr_readings_pin_the_noise_reading():
    tab = XP.snr_readings((0.3, 9.0))
    ours = tab[tab["reading"].str.endswith("(ours)")]
    alt = tab[~tab["reading"].str.endswith("(ours)")]
    assert ours["SNR"].round(2).tolist() == [4.96, 0.91]
    # read as the variance of log Y, the SNR is 1 / sqrt(exp(s2) - 1) whatever the ellipse
    assert np.allclose(alt["SNR"], 1 / np.sqrt(np.expm1([0.3, 9.0])))
    with pytest.raises(ValueError, match="variance"):
        XP.snr_readings((0.0,))


def test_ideal_supports_and_ls_estimates_recover_the_truth_without_noise():
    Cs = S.paper_projections()
    ideal = XP.ideal_supports(S.X26, Cs)
    assert np.allclose(ideal, [S.X26[0, 0]] + [float(C[:, 0] @ S.X26 @ C[:, 0]) for C in Cs[1:]])
    X = XP.ls_estimates(np.zeros((3, 5)), ideal, Cs)
    assert X.shape == (3, 2, 2) and np.allclose(X, S.X26)
    with pytest.raises(ValueError, match="W"):
        XP.ls_estimates(np.zeros((3, 4)), ideal, Cs)


def test_shown_static_draw_picks_the_median_of_its_pool():
    d = XP.shown_static_draw(9.0, np.random.default_rng(5), non_psd_only=True, n_draws=40)
    assert d["W"].shape == (40, 5) and d["X_ls"].shape == (40, 2, 2)
    assert np.array_equal(d["pool"], np.nonzero(d["not_psd"])[0])
    assert d["pick"] in d["pool"] and d["not_psd"][d["pick"]]
    below = np.sum(d["err"][d["pool"]] < d["err"][d["pick"]])
    assert below == len(d["pool"]) // 2
    ideal, W, Ys, Cs = d["data"]
    assert np.allclose([Y[0, 0] for Y in Ys], ideal + d["W"][d["pick"]])
    # the same draws whatever the number of worker processes (montecarlo.run)
    again = XP.shown_static_draw(9.0, np.random.default_rng(5), non_psd_only=True, n_draws=40)
    assert np.array_equal(again["W"], d["W"])
    with pytest.raises(ValueError, match="variance"):
        XP.shown_static_draw(0.0, np.random.default_rng(5))
    with pytest.raises(TypeError, match="rng"):
        XP.shown_static_draw(0.3, 5)


def test_three_estimates_agree_with_the_sdp_and_describe():
    Cs = S.paper_projections()
    _, _, Ys, _ = S.static_observations(9.0, np.random.default_rng(1994))
    X_lo, X_hi = XP.demo_interval()
    est, (res_psd, res_int), agree = XP.three_estimates(Ys, Cs, X_lo, X_hi)
    assert set(est) == {"LS", "PSD", "interval"} and agree < 1e-4
    assert E.is_psd(est["PSD"]) and res_psd.converged and res_int.converged
    tab = XP.describe_estimates(est, S.X26)
    assert list(tab["estimate"]) == ["LS", "PSD", "interval"]
    assert tab["PSD"].iloc[1]
    with pytest.raises(TypeError, match="estimates"):
        XP.describe_estimates({}, S.X26)


def test_non_psd_pool_study_scores_every_draw():
    d = XP.shown_static_draw(9.0, np.random.default_rng(3), non_psd_only=True, n_draws=30)
    pool = d["pool"][:3]
    X_lo, X_hi = XP.demo_interval()
    out = XP.non_psd_pool_study(d["W"], pool, X_lo, X_hi)
    assert all(len(out[k]) == len(pool) for k in ("closest", "singular", "lo_beats", "int_beats_lo", "int_is_lo"))
    assert set(out["closest"]) <= {"LS", "PSD", "interval"}
    # a non-PSD LS estimate projects onto the boundary of the PSD cone: a singular PSD estimate
    assert all(out["singular"])
    with pytest.raises(ValueError, match="pool"):
        XP.non_psd_pool_study(d["W"], [30], X_lo, X_hi)


def test_support_perturbation_measures_sqrt_distances():
    c = XP.ideal_supports(S.X26, S.paper_projections())
    W = np.array([np.zeros(5), c * 3.0, -c * 2.0])  # none, supports doubled, Y clipped to 0
    d = XP.support_perturbation(W, c)
    assert np.allclose(d["mean"][0], 0) and np.allclose(d["max"][1], np.sqrt(c).max())
    assert np.allclose(d["mean"][2], np.sqrt(c).mean()) and np.all(d["max"] >= d["mean"])
    with pytest.raises(ValueError, match="ideal"):
        XP.support_perturbation(W, c[:3])


def test_ls_psd_frequency_small_noise_is_almost_always_psd():
    tab = XP.ls_psd_frequency([(0.3, 7), (9.0, 8)], 2, 50)
    assert list(tab["noise variance"]) == [0.3, 9.0]
    assert tab["P(LS not PSD)"].iloc[0] < tab["P(LS not PSD)"].iloc[1]
    assert tab["P(LS not PSD)"].iloc[0] < 0.05
    assert (tab["realized SNR 10%"] <= tab["realized SNR median"]).all()
    assert (tab["P(both)"] <= tab["P(LS not PSD)"]).all() and (tab["P(both within a factor 2)"] <= tab["P(LS not PSD)"]).all()
    with pytest.raises(ValueError, match="n_blocks"):
        XP.ls_psd_frequency([(0.3, 7)], 0, 50)
    with pytest.raises(ValueError, match="levels"):
        XP.ls_psd_frequency([], 1, 50)


def test_hyperplane_ranks_three_views_suffice():
    tab = XP.hyperplane_ranks(np.random.default_rng(0), ns=[2, 3], qs=[2, 3], n_draws=2)
    assert list(tab["q=3"]) == list(tab["n(n+1)/2"])
    assert (tab["q=2"] < tab["n(n+1)/2"]).all()
    with pytest.raises(ValueError, match="n_draws"):
        XP.hyperplane_ranks(np.random.default_rng(0), n_draws=0)
    with pytest.raises(ValueError, match="q"):
        XP.hyperplane_ranks(np.random.default_rng(0), qs=[])


def test_hyperplane_rank_trial_gives_every_cell_and_the_study_takes_the_minimum():
    t = XP.hyperplane_rank_trial(np.random.default_rng(5), [2, 3], [1, 2])
    assert set(t) == {(2, 1), (2, 2), (3, 1), (3, 2)} and t[(2, 1)] == 1 and t[(3, 2)] == 5
    # the study's draws are the children of its generator, one trial each
    kids = np.random.default_rng(5).spawn(3)
    trials = [XP.hyperplane_rank_trial(k, [4], [2, 3]) for k in kids]
    tab = XP.hyperplane_ranks(np.random.default_rng(5), ns=[4], qs=[2, 3], n_draws=3)
    assert tab["q=2"].iloc[0] == min(t[(4, 2)] for t in trials) and tab["q=3"].iloc[0] == 10


def test_ctilde_identity_study_finds_the_identities_exact():
    out = XP.ctilde_identity_study(12, np.random.default_rng(4), n_max=4)
    assert out["count"] == 12 and out["err_kron"] < 1e-12 and out["err_proj"] < 1e-12
    assert max(XP.ctilde_identity_trial(np.random.default_rng(1), n_max=2)) < 1e-12
    with pytest.raises(ValueError, match="n_checks"):
        XP.ctilde_identity_study(0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="n_max"):
        XP.ctilde_identity_study(3, np.random.default_rng(0), n_max=1)


def test_projector_form_is_a_projector():
    t = XP.projector_form_trial(np.random.default_rng(1), n_max=4)
    assert max(v for k, v in t.items() if k not in ("rank", "expected_rank")) < 1e-12 and t["rank"] == t["expected_rank"]
    tab, n_rank = XP.projector_form_study(10, np.random.default_rng(5), n_max=5)
    assert n_rank == 10 and (tab["max deviation"] < 1e-12).all() and len(tab) == 6
    with pytest.raises(ValueError, match="n_checks"):
        XP.projector_form_study(0, np.random.default_rng(5))


# --------------------------------------------------------------------------- dynamic
@pytest.fixture(scope="module")
def exp():
    return S.dynamic_experiment(np.random.default_rng(1215), n_steps=24)


def test_relative_errors_and_no_data_baseline(exp):
    assert np.allclose(XP.relative_errors(exp["Xs"], exp["Xs"]), 0)
    base = XP.no_data_estimate(exp)
    err = XP.relative_errors(base, exp["Xs"])
    assert err[0] == pytest.approx(1.0) and err[-1] < err[0]  # the contracting model forgets X_0
    with pytest.raises(ValueError, match="X_est"):
        XP.relative_errors(base[:3], exp["Xs"])
    with pytest.raises(TypeError, match="exp"):
        XP.no_data_estimate({"Xs": exp["Xs"]})


def _kkt_residual(x, x_hat, M):
    # optimality of min (x - x_hat)^T M (x - x_hat) over PSD smat(x): X >= 0, G = smat(M (x - x_hat)) >= 0, <G, X> = 0
    X, G = E.smat(x), E.smat(M @ (x - x_hat))
    scale = max(1.0, np.abs(G).max() * max(1.0, np.abs(X).max()))
    return max(-np.linalg.eigvalsh(X)[0], -np.linalg.eigvalsh(G)[0] / max(1.0, np.abs(G).max()), abs(np.sum(G * X)) / scale)


def test_psd_project_2x2_meets_the_optimality_conditions():
    rng = np.random.default_rng(0)
    for _ in range(300):
        F = rng.normal(size=(6, 3))
        M, x_hat = F.T @ F, rng.normal(size=3) * 3
        x = XP.psd_project_2x2(x_hat, M)
        assert _kkt_residual(x, x_hat, M) < 1e-9
    # a PSD estimate is returned unchanged, a negative definite one goes to zero, many at once
    X = np.stack([E.svec(S.X26), E.svec(-np.eye(2))])
    out = XP.psd_project_2x2(X, np.eye(3))
    assert np.array_equal(out[0], X[0]) and np.allclose(out[1], 0)
    with pytest.raises(ValueError, match="M"):
        XP.psd_project_2x2(X[0], -np.eye(3))
    with pytest.raises(ValueError, match="x_hat"):
        XP.psd_project_2x2(np.zeros(4), np.eye(3))


def test_psd_project_2x2_agrees_with_algorithm_1_and_the_sdp():
    rng = np.random.default_rng(9)
    for _ in range(5):
        A = rng.normal(size=(5, 3))
        y = A @ E.svec(np.diag([1.0, -0.5])) + rng.normal(size=5)
        x_ls = np.linalg.lstsq(A, y, rcond=None)[0]
        ours = E.smat(XP.psd_project_2x2(x_ls, A.T @ A))
        alg1 = E.halfspace_reconstruct(None, None, np.zeros((2, 2)), None, A=A, y=y).X
        sdp = E.sdp_reconstruct(A, y, np.zeros((2, 2)), None)
        for other in (alg1, sdp):
            assert np.linalg.norm(other - ours) <= 1e-3 * max(1.0, np.linalg.norm(ours))
        f = lambda X: float(np.sum((A @ E.svec(X) - y) ** 2))  # noqa: E731
        assert f(ours) <= f(sdp) * (1 + 1e-9)  # feasible and at least as good as the interior point


def test_fig12_noise_study_matches_the_one_draw_estimates(exp):
    st = XP.fig12_noise_study(exp, 5, np.random.default_rng(2))
    assert st["X"].shape == (5, 24, 2, 2) and st["settle"].shape == (5,)
    k = 0
    Ys = [np.array([[v]]) for v in exp["ideal"] + st["W"][k]]
    assert np.allclose(st["X_ls"][k], E.batch_estimate(Ys, exp["Cs"], exp["As"], exp["Bs"]))
    psd = E.batch_estimate(Ys, exp["Cs"], exp["As"], exp["Bs"], lower=0, method="sdp")
    assert np.linalg.norm(st["X_psd"][k] - psd) <= 1e-3 * np.linalg.norm(psd)
    assert all(E.is_psd(X) for X in st["X_psd"][k])
    # constrained at time 0 is the PSD-constrained X_0; the shown draw is the median settling of the PSD estimate
    assert np.allclose(st["X_time_k"][:, 0], st["X_psd"][:, 0])
    assert st["pick"] == XP.median_draw(st["settle_psd"], tiebreak=st["err_psd"].mean(axis=1))
    assert np.array_equal(st["settle_psd"], XP.settling_step(st["err_psd"]))
    with pytest.raises(ValueError, match="n_draws"):
        XP.fig12_noise_study(exp, 0, np.random.default_rng(2))


def test_time_k_psd_estimates_solve_eq24_in_x_k(exp):
    st = XP.fig12_noise_study(exp, 2, np.random.default_rng(3))
    k = 2
    Ys = [np.array([[v]]) for v in exp["ideal"] + st["W"][0]]
    O = E.observability_matrix(exp["Cs"], exp["As"])
    y = E.batch_rhs(Ys, exp["Cs"], exp["As"], exp["Bs"])
    Phi = np.linalg.matrix_power(E.congruence_operator(exp["A"]), k)
    f = E.svec(E.simulate(np.zeros((2, 2)), exp["As"][:k], exp["Bs"][:k])[-1])
    Ok = O @ np.linalg.inv(Phi)
    sdp = E.sdp_reconstruct(Ok, y + Ok @ f, np.zeros((2, 2)), None)
    assert np.linalg.norm(st["X_time_k"][0, k] - sdp) <= 1e-3 * np.linalg.norm(sdp)
    tab = XP.time_k_study(exp, st, ks=(0, k))
    assert (tab["direct vs propagated"] < 1e-9).all()
    assert tab["constrained at k vs PSD X_0"].iloc[0] == 0
    with pytest.raises(ValueError, match="k must be"):
        XP.time_k_study(exp, st, ks=(24,))


def test_estimator_table_and_the_no_data_comparison(exp):
    st = XP.fig12_noise_study(exp, 6, np.random.default_rng(4))
    err0 = XP.relative_errors(XP.no_data_estimate(exp), exp["Xs"])
    tab = XP.estimator_table(st, err0)
    assert list(tab["estimate"]) == [name for _, name in XP.ESTIMATORS]
    assert tab["X_0 indefinite"].iloc[1] == 0  # PSD-constrained: never indefinite, even when of rank one
    assert tab["X_0 indefinite"].iloc[0] == np.mean(np.linalg.eigvalsh(st["X_ls"][:, 0])[:, 0] < 0)
    assert (tab["earlier than no data"] + tab["later than no data"] <= 1).all()
    # the baseline against itself: never earlier, never later, never better
    same = XP.estimator_table({**st, **{f"err_{k}": np.tile(err0, (6, 1)) for k, _ in XP.ESTIMATORS}}, err0)
    assert (same[["earlier than no data", "later than no data", "better than no data at step 7"]] == 0).all().all()
    with pytest.raises(ValueError, match="err_nodata"):
        XP.estimator_table(st, err0[:5])


def test_settling_study_of_our_drive_is_unscaled(exp):
    target = float(exp["ideal"].mean())
    out = XP.settling_study(S.periodic_drive(23, beta=1.0), target, 4, np.random.default_rng(1), exp["A"])
    assert out["scale"] == pytest.approx(2.0)  # our drive has beta = 2
    assert out["no-data settling"] == XP.settling_step(XP.relative_errors(XP.no_data_estimate(exp), exp["Xs"]))
    assert 0 <= out["earlier"] + out["later"] <= 1 and 0 <= out["median settling"] <= 24
    assert 0 <= out["earlier than one frame"] <= 1 and 0 <= out["better than one frame at step 7"] <= 1
    with pytest.raises(ValueError, match="drive_raw"):
        XP.settling_study(np.zeros((3, 2, 2)), target, 4, np.random.default_rng(1))


def test_one_frame_guess_is_the_circle_y0_I_propagated(exp):
    y0 = np.array([0.5, 2.0, 3.7])
    got = XP.one_frame_guess(y0, exp["A"], exp["Bs"])
    for v, g in zip(y0, got):
        assert np.allclose(g, E.simulate(v * np.eye(2), exp["A"], exp["Bs"], len(exp["Xs"]) - 1), atol=1e-12)


def test_trivial_baselines_and_the_criterion_against_them(exp):
    W = np.array([[0.0] * 24, [1.5] + [0.0] * 23])
    tb = XP.trivial_baselines(exp, W)
    e0 = XP.relative_errors(XP.no_data_estimate(exp), exp["Xs"])
    assert np.allclose(tb["no data, X_0 = 0"], e0) and tb["one frame, X_0 = y_0 I"].shape == (2, 24)
    y0 = exp["ideal"][0] + W[:, 0]
    assert np.allclose(tb["one frame, X_0 = y_0 I"][1],
                       XP.relative_errors(XP.one_frame_guess(y0, exp["A"], exp["Bs"])[1], exp["Xs"]))
    # an estimator equal to its baseline is never earlier, later or better: the criterion can fail
    same = XP.versus_baseline(tb["one frame, X_0 = y_0 I"], tb["one frame, X_0 = y_0 I"])
    assert same["strictly earlier"] == same["later"] == same["better at step 7"] == 0
    # the truth itself settles at step 0, earlier than the no-data run (which settles later)
    exact = XP.versus_baseline(np.zeros((2, 24)), e0)
    assert exact["strictly earlier"] == 1 and exact["better at step 7"] == 1 and exact["median settling step"] == 0
    tab = XP.threshold_table({"truth": np.zeros((2, 24)), "base": np.tile(e0, (2, 1))}, e0, tols=(0.1, 0.2))
    assert list(tab["truth"]) == [1.0, 1.0] and list(tab["base"]) == [0.0, 0.0]
    with pytest.raises(ValueError, match="W"):
        XP.trivial_baselines(exp, W[:, :5])
    with pytest.raises(ValueError, match="step"):
        XP.versus_baseline(np.zeros((2, 5)), np.zeros(5))


def test_best_constant_error_is_below_the_temporal_mean(exp):
    best, X = XP.best_constant_error(exp["Xs"], n_starts=4)
    assert best <= XP.constant_baseline_error(exp["Xs"]) + 1e-12
    assert np.linalg.eigvalsh(X)[0] >= 0
    rel = np.linalg.norm(X - exp["Xs"][8:], axis=(1, 2)) / np.linalg.norm(exp["Xs"][8:], axis=(1, 2))
    assert np.median(rel) == pytest.approx(best)
    still = np.array([S.X26] * 12)
    assert XP.best_constant_error(still, n_starts=2)[0] < 1e-6


def test_model_trial_without_errors_is_the_exact_model(exp):
    errs, (w, dA, dB) = XP.model_trial(np.random.default_rng(4), exp, sd=0.0)
    assert np.all(dA == 0) and np.all(dB == 0)
    assert errs["exact model"] == errs["A and B errors (Fig. 13)"] == errs["A error only"]
    assert errs["same, noise-free data"] < 1e-9  # exact model, exact data: the truth
    one = XP.trivial_baselines(exp, w[None])["one frame, X_0 = y_0 I"][0]  # the Fig. 12 baseline, same draw
    assert errs["one frame X_0 = y_0 I, A and B errors"] == pytest.approx(np.median(one[8:]), rel=1e-12)
    trials = XP.imperfect_model_study(exp, 3, np.random.default_rng(6))
    assert len(trials) == 3 and set(trials[0][0]) >= {"exact model", "rel. error of A", "rel. error of B",
                                                      "semi-axis error (Fig. 13)", "no data, A and B errors",
                                                      "no data X_0 = I, A and B errors",
                                                      "one frame X_0 = y_0 I, A and B errors"}
    with pytest.raises(ValueError, match="sd"):
        XP.model_trial(np.random.default_rng(4), exp, sd=-1.0)


def test_first_measure_table_divides_by_the_mean_size(exp):
    trials = XP.imperfect_model_study(exp, 3, np.random.default_rng(6))
    tab = XP.first_measure_table(exp, trials).set_index("estimate")
    Xs, (w, dA, dB) = exp["Xs"], trials[0][1]
    X0 = E.simulate(np.zeros((2, 2)), exp["A"] + dA, exp["Bs"] + dB, len(Xs) - 1)
    size = np.mean(np.linalg.norm(Xs, axis=(1, 2)))
    per_trial = [np.median(np.linalg.norm(E.simulate(np.zeros((2, 2)), exp["A"] + t[1][1], exp["Bs"] + t[1][2],
                                                      len(Xs) - 1)[8:] - Xs[8:], axis=(1, 2))) / size for t in trials]
    assert np.median(np.linalg.norm(X0[8:] - Xs[8:], axis=(1, 2))) / size == pytest.approx(per_trial[0])
    assert tab.loc["no data, X_0 = 0", "median error (first measure)"] == pytest.approx(np.median(per_trial), rel=1e-12)
    assert tab.loc["no data, X_0 = 0", "share below 0.25"] == pytest.approx(np.mean(np.array(per_trial) < 0.25))
    # without model errors and noise the LS and PSD estimates are the truth
    clean = [({}, (np.zeros_like(w), 0 * dA, 0 * dB))]
    assert XP.first_measure_table(exp, clean).iloc[:2]["median error (first measure)"].max() < 1e-9
    with pytest.raises(ValueError, match="threshold"):
        XP.first_measure_table(exp, trials, threshold=0.0)


def test_fig13_baselines_counts_strict_wins():
    t = pd.DataFrame({"A and B errors (Fig. 13)": [0.1, 0.3, 0.2], "same, noise-free data": [0.1, 0.1, 0.1],
                      "no data, A and B errors": [0.2, 0.2, 0.2], "no data X_0 = I, A and B errors": [0.1, 0.3, 0.2],
                      "one frame X_0 = y_0 I, A and B errors": [0.5, 0.5, 0.05]})
    tab = XP.fig13_baselines(t, 0.25).set_index("baseline")
    assert tab.loc["no data, X_0 = 0", "estimate beats it"] == pytest.approx(1 / 3)
    assert tab.loc["no data, X_0 = I", "estimate beats it"] == 0.0  # exact ties count for neither
    assert tab.loc["one frame, X_0 = y_0 I", "beats the mean ellipse"] == pytest.approx(1 / 3)
    assert tab.loc["no data, X_0 = 0", "noise-free data beat it"] == 1.0
    with pytest.raises(TypeError, match="DataFrame"):
        XP.fig13_baselines(t.to_dict(), 0.25)


def test_constant_baseline_and_model_error_scan(exp):
    assert XP.constant_baseline_error(np.stack([S.X26] * 12)) == 0.0
    base = XP.constant_baseline_error(exp["Xs"])
    assert 0.3 < base < 1
    scan = XP.model_error_scan(exp, (0.0, 0.5), 4, np.random.default_rng(1))
    assert scan["better than the mean ellipse"].iloc[0] == 1.0  # no model error: the estimate tracks
    assert scan["median error"].iloc[0] < scan["median error"].iloc[1]
    with pytest.raises(ValueError, match="steps"):
        XP.constant_baseline_error(exp["Xs"], slice(30, None))


def test_shaping_family_misses_reflections_but_not_their_effect():
    tab, dev = XP.shaping_family_study(200, np.random.default_rng(22))
    assert dev["n_pos"] + dev["n_neg"] == 200 and 0 < dev["n_neg"] < 200
    assert dev["rebuild"] < 1e-12 and dev["mirror"] < 1e-12 and dev["transpose"] < 1e-12
    assert dev["orthogonal"] < 1e-12  # with orthogonal factors every draw, reflections included, is rebuilt
    assert dev["limits"][0] > dev["limits"][1] > dev["limits"][2] > 0 and dev["limits"][2] < 1e-5
    assert tab["share of the draws"].sum() == pytest.approx(1.0)
    # every member of eq. (22) has det = tau^2 >= 0, so a reflection is out of reach
    rng = np.random.default_rng(0)
    for _ in range(20):
        tau, alpha, psi, phi = rng.normal(size=4)
        assert np.linalg.det(E.shaping_matrix(tau, alpha, psi, phi)) == pytest.approx(tau**2)


def test_kalman_vs_batch_filter_equals_growing_window(exp):
    Ys = [np.array([[v]]) for v in exp["ideal"] + exp["W"]]
    out = XP.kalman_vs_batch({**exp, "Ys": Ys})
    kf, window = out["kf"], out["window"]
    rel = np.abs(kf.X[2:] - window[2:]).max(axis=(1, 2)) / np.abs(window[2:]).max(axis=(1, 2))
    assert rel.max() < 1e-3
    assert list(out["err"].columns)[0] == "k" and len(out["err"]) == 24
    with pytest.raises(TypeError, match="Ys"):
        XP.kalman_vs_batch({k: v for k, v in exp.items() if k != "Ys"})


# --------------------------------------------------------------------------- beyond
def test_alg1_and_sdp_agree_on_random_problems():
    problems = XP.random_interval_problems(np.random.default_rng(2024), ns=[2, 3], per_n=3)
    assert len(problems) == 6 and [p[0].split(", ")[1] for p in problems[:3]] == ["PSD", "scalar", "matrix"]
    cmp, times = XP.compare_alg1_sdp(problems)
    assert cmp["converged"].all() and cmp["rel. distance"].max() < 1e-3
    assert (cmp["violation Alg. 1"] < 1e-6).all() and len(times) == 6
    with pytest.raises(ValueError, match="tuple"):
        XP.compare_alg1_sdp([("x", 2)])


def test_alg1_sdp_summary_judges_against_the_tolerances():
    problems = XP.random_interval_problems(np.random.default_rng(2024), ns=[2, 3], per_n=2)
    cmp, _ = XP.compare_alg1_sdp(problems)
    by_problem, by_n = XP.alg1_sdp_summary(cmp)
    assert by_problem["within tolerances"].all() and list(by_n["n"]) == [2, 3]
    assert by_n["problems"].sum() == 4 and (by_n["within tolerances"] == by_n["problems"]).all()
    strict, _ = XP.alg1_sdp_summary(cmp, dist_tol=0.0)
    assert not strict["within tolerances"].any()
    with pytest.raises(TypeError, match="comparison"):
        XP.alg1_sdp_summary([1, 2])


def test_constraint_violation():
    assert XP.constraint_violation(np.eye(2), np.zeros((2, 2))) == 0.0
    assert XP.constraint_violation(np.diag([1.0, -0.5]), np.zeros((2, 2))) == pytest.approx(0.5)
    assert XP.constraint_violation(3 * np.eye(2), np.zeros((2, 2)), 2 * np.eye(2)) == pytest.approx(1.0)


def test_silhouettes_3d_study_needs_three_views():
    tab, examples = XP.silhouettes_3d_study(np.random.default_rng(3), qs=[2, 3], n_trials=2)
    assert list(tab["rank (min over trials)"]) == [5, 6]
    assert np.isnan(tab["median rel. error"].iloc[0]) and tab["median rel. error"].iloc[1] < 0.5
    assert len(examples) == 2
    with pytest.raises(ValueError, match="n_points"):
        XP.silhouettes_3d_study(np.random.default_rng(3), n_points=2)


def test_silhouette_trial_estimates_only_with_full_rank():
    two = XP.silhouette_trial(np.random.default_rng(1), 2)
    assert two["rank"] == 5 and two["estimate"] is None and np.isnan(two["error"]) and len(two["views"]) == 2
    three = XP.silhouette_trial(np.random.default_rng(1), 3, n_points=40, noise=0.0)
    assert three["rank"] == 6 and three["error"] < 1e-6 and E.is_psd(three["estimate"])


def test_silhouettes_3d_study_is_the_same_serial_and_parallel():
    kw = {"qs": [2, 3], "n_trials": 3, "n_points": 12}
    tab1, ex1 = XP.silhouettes_3d_study(np.random.default_rng(3), n_jobs=1, **kw)
    tab2, ex2 = XP.silhouettes_3d_study(np.random.default_rng(3), n_jobs=2, **kw)
    assert tab1.equals(tab2) and len(ex1) == len(ex2) == 3
    for a, b in zip(ex1, ex2):
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) and a[3] == b[3]


def test_random_interval_problems_are_draws_of_random_interval_draw():
    X, A, y = XP.random_interval_draw(np.random.default_rng(0), 3, n_views=4, noise=0.0)
    assert A.shape == (12, 6) and np.allclose(A @ E.svec(X), y)
    problems = XP.random_interval_problems(np.random.default_rng(7), ns=[3], per_n=2)
    kid = np.random.default_rng(7).spawn(2)[1]
    _, A2, y2 = XP.random_interval_draw(kid, 3)
    assert np.array_equal(problems[1][2], A2) and np.array_equal(problems[1][3], y2)


def test_condition19_never_certifies_a_non_psd_estimate():
    mc = XP.condition19_study(S.paper_projections(), 40, np.random.default_rng(19))
    assert len(mc) == 40 and not (mc["holds"] & ~mc["psd"]).any()
    with pytest.raises(ValueError, match="2 x 1"):
        XP.condition19_study([np.eye(2)], 4, np.random.default_rng(0))


# --------------------------------------------------------------------------- plots
def test_page_figures_are_legible(exp):
    from projtrack import figures

    data = S.static_observations(0.3, np.random.default_rng(0))
    X_lo, X_hi = XP.demo_interval()
    err = np.abs(np.random.default_rng(1).normal(size=(5, 24)))
    made = [P.truth_and_supports(S.X26, data, data, (5.0, 0.9)),
            P.four_panels(S.X26, {"LS": S.X26, "PSD": S.X26, "interval": S.X26}, X_lo, X_hi, "t"),
            P.error_bands(np.arange(24), {"a": err, "b": err}, err[0], "t"),
            P.shaping_figure(exp["Xs"][:17], exp["Xs"][:17], 4 * np.eye(2)), P.drive_and_state(exp["Bs"], exp["Xs"]),
            P.interval_figure(0.64 * np.eye(2), 4.84 * np.eye(2), [np.eye(2)], [np.eye(2)])]
    for fig in made:
        assert figures.legibility_problems(fig) == []
        plt.close(fig)
    C = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    fig = P.silhouette_figure(np.diag([4.0, 1.0, 0.25]), C, np.diag([4.0, 1.0]))
    assert len(fig.axes) == 1
    plt.close(fig)


def test_plot_helpers_draw_conics_and_strips(exp):
    X_lo, X_hi = XP.demo_interval()
    est = {"LS": np.diag([2.0, -1.0]), "PSD": np.diag([2.0, 0.0]), "interval": X_lo}
    fig = P.four_panels(S.X26, est, X_lo, X_hi, "t")
    assert len(fig.axes) == 4 and len(fig.axes[0].lines) >= 3  # the hyperbola has two branches
    plt.close(fig)
    data = S.static_observations(0.3, np.random.default_rng(0))
    fig = P.support_plot(S.X26, data, "t")
    assert len(fig.axes[0].lines) == 1 + 5 * 5 + 2  # ellipse, 5 x (2 lines, 2 points, 1 ray), 2 axes
    plt.close(fig)
    Ys = [np.array([[v]]) for v in exp["ideal"]]
    fig = P.tracking_figure(exp["Xs"], exp["Xs"], Ys, "t")
    assert len(fig.axes) == 2
    plt.close(fig)

"""Unit tests of the ellipsoid experiments (small sizes)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from projtrack import ellipsoids as E  # noqa: E402
from projtrack.experiments import ellipsoids as XP  # noqa: E402
from projtrack.experiments.ellipsoids import plots as P  # noqa: E402
from projtrack.scenes import ellipses as S  # noqa: E402


# --------------------------------------------------------------------------- static
def test_demo_interval_is_an_interval_containing_eq26():
    X_lo, X_hi = XP.demo_interval()
    assert E.in_interval(S.X26, X_lo, X_hi)
    assert np.allclose(E.axes(X_lo)[0], [1.4, 0.6]) and np.allclose(E.axes(X_hi)[0], [3.2, 1.6])


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


def test_ls_psd_frequency_small_noise_is_almost_always_psd():
    tab = XP.ls_psd_frequency([(0.3, 7), (9.0, 8)], 2, 50)
    assert list(tab["noise variance"]) == [0.3, 9.0]
    assert tab["P(LS not PSD)"].iloc[0] < tab["P(LS not PSD)"].iloc[1]
    assert tab["P(LS not PSD)"].iloc[0] < 0.05
    assert (tab["realized SNR 10%"] <= tab["realized SNR median"]).all()
    with pytest.raises(ValueError, match="n_blocks"):
        XP.ls_psd_frequency([(0.3, 7)], 0, 50)
    with pytest.raises(ValueError, match="levels"):
        XP.ls_psd_frequency([], 1, 50)


def test_noise_reading_study_shares_our_draws():
    ours = XP.ls_psd_frequency([(9.0, 8)], 2, 30)
    tab = XP.noise_reading_study([(9.0, 8)], 2, 30)
    assert list(tab["reading"]) == ["variance of the noise W (ours)", "variance of log Y"]
    assert tab["P(LS not PSD)"].iloc[0] == ours["P(LS not PSD)"].iloc[0]


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


def test_fig12_noise_study_matches_the_one_draw_estimate(exp):
    st = XP.fig12_noise_study(exp, 5, np.random.default_rng(2))
    assert st["X"].shape == (5, 24, 2, 2) and st["settle"].shape == (5,)
    k = st["pick"]
    Ys = [np.array([[v]]) for v in exp["ideal"] + st["W"][k]]
    one = E.batch_estimate(Ys, exp["Cs"], exp["As"], exp["Bs"])
    assert np.allclose(st["X"][k], one)
    assert st["settle"][k] == XP.settling_step(st["err"][k])
    with pytest.raises(ValueError, match="n_draws"):
        XP.fig12_noise_study(exp, 0, np.random.default_rng(2))


def test_settling_study_of_our_drive_is_unscaled(exp):
    target = float(exp["ideal"].mean())
    out = XP.settling_study(S.periodic_drive(23, beta=1.0), target, 4, np.random.default_rng(1), exp["A"])
    assert out["scale"] == pytest.approx(2.0)  # our drive has beta = 2
    assert 0 <= out["share in 3..11"] <= 1 and 0 <= out["median settling"] <= 24
    with pytest.raises(ValueError, match="drive_raw"):
        XP.settling_study(np.zeros((3, 2, 2)), target, 4, np.random.default_rng(1))


def test_model_trial_without_errors_is_the_exact_model(exp):
    errs, (w, dA, dB) = XP.model_trial(np.random.default_rng(4), exp, sd=0.0)
    assert np.all(dA == 0) and np.all(dB == 0)
    assert errs["exact model"] == errs["A and B errors (Fig. 13)"] == errs["A error only"]
    trials = XP.imperfect_model_study(exp, 3, np.random.default_rng(6))
    assert len(trials) == 3 and set(trials[0][0]) >= {"exact model", "rel. error of A", "rel. error of B"}
    with pytest.raises(ValueError, match="sd"):
        XP.model_trial(np.random.default_rng(4), exp, sd=-1.0)


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

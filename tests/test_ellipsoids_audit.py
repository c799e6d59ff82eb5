"""Tests of the renamed basis matrix, the scale-free LSI, the SDP timing info and the drive parameter."""

import numpy as np
import pytest

from projtrack import ellipsoids as E
from projtrack.scenes import ellipses as S


def test_svec_basis_matrix_maps_svec_to_vec_and_is_not_the_duplication_matrix():
    rng = np.random.default_rng(0)
    for n in range(1, 6):
        P = E.svec_basis_matrix(n)
        X = rng.normal(size=(n, n))
        X = X + X.T
        np.testing.assert_allclose(P @ E.svec(X), X.reshape(-1), atol=1e-12)
        np.testing.assert_allclose(P.T @ P, np.eye(n * (n + 1) // 2), atol=1e-12)
    # the Magnus-Neudecker duplication matrix has only 0/1 entries; ours has 1/sqrt(2) off the diagonal
    assert np.isclose(np.max(E.svec_basis_matrix(2)[1]), 1 / np.sqrt(2))
    for bad in (0, -1, 2.0, True):
        with pytest.raises(ValueError, match="n must be"):
            E.svec_basis_matrix(bad)
    assert not hasattr(E, "duplication_matrix") and not hasattr(E, "propagate")


@pytest.mark.parametrize("s", [1e-9, 1e-3, 1.0, 1e4, 1e9])
def test_lsi_feasibility_is_scale_free(s):
    # feasible: min ||x - 1|| s.t. x_1 >= 2  ->  (2, 1), whatever the scale of E, f, G, h
    x = E.lsi(s * np.eye(2), s * np.ones(2), s * np.array([[1.0, 0.0]]), s * np.array([2.0]))
    np.testing.assert_allclose(x, [2.0, 1.0], rtol=1e-9)
    x = E.lsi(s * np.eye(2), s * np.ones(2), np.array([[1.0, 0.0]]), np.array([2.0]))
    np.testing.assert_allclose(x, [2.0, 1.0], rtol=1e-9)
    # infeasible: x_1 >= 1 and -x_1 >= 1
    with pytest.raises(ValueError, match="infeasible"):
        E.lsi(s * np.eye(2), np.zeros(2), s * np.array([[1.0, 0.0], [-1.0, 0.0]]), s * np.array([1.0, 1.0]))
    # a nearly empty but feasible slab (width 1e-6 relative) is still feasible
    x = E.lsi(s * np.eye(2), np.zeros(2), s * np.array([[1.0, 0.0], [-1.0, 0.0]]), s * np.array([1.0, -1.000001]))
    assert 1.0 - 1e-9 <= x[0] <= 1.000001 + 1e-9


def test_lsi_zero_row_with_positive_rhs_is_infeasible():
    with pytest.raises(ValueError, match="infeasible"):
        E.lsi(np.eye(2), np.zeros(2), np.zeros((1, 2)), np.array([1.0]))


def test_sdp_reconstruct_reports_setup_and_solve_time():
    info = {}
    X = E.sdp_reconstruct(np.eye(3), np.array([1.0, -1.0, 1.0]), np.zeros((2, 2)), None, info=info)
    assert np.linalg.eigvalsh(X)[0] >= -1e-7
    assert set(info) >= {"setup_time", "solve_time", "total_time"}
    assert 0 < info["solve_time"] <= info["total_time"]
    assert np.isclose(info["setup_time"] + info["solve_time"], info["total_time"])
    with pytest.raises(TypeError, match="info"):
        E.sdp_reconstruct(np.eye(3), np.ones(3), np.zeros((2, 2)), None, info=[])


def test_dynamic_experiment_takes_the_drive():
    rng = np.random.default_rng(1)
    default = S.dynamic_experiment(np.random.default_rng(1), n_steps=6)
    same = S.dynamic_experiment(rng, n_steps=6, drive=S.periodic_drive(5))
    np.testing.assert_allclose(same["Xs"], default["Xs"])
    none = S.dynamic_experiment(np.random.default_rng(1), n_steps=6, drive=np.zeros((5, 2, 2)))
    np.testing.assert_allclose(none["Xs"], E.simulate(S.X26, none["As"], None))
    assert not np.allclose(none["Xs"], default["Xs"])
    with pytest.raises(ValueError, match="shape"):
        S.dynamic_experiment(rng, n_steps=6, drive=np.zeros((4, 2, 2)))
    with pytest.raises(ValueError, match="symmetric"):
        S.dynamic_experiment(rng, n_steps=3, drive=[[[1.0, 1.0], [0.0, 1.0]]] * 2)
    with pytest.raises(ValueError, match="semidefinite"):
        S.dynamic_experiment(rng, n_steps=3, drive=[-np.eye(2)] * 2)
    with pytest.raises(ValueError, match="finite"):
        S.dynamic_experiment(rng, n_steps=3, drive=[np.full((2, 2), np.nan)] * 2)


def test_batch_estimate_many_equals_batch_estimate_per_draw():
    import numpy as np
    from projtrack import ellipsoids as E
    from projtrack.scenes import ellipses as S
    exp = S.dynamic_experiment(np.random.default_rng(5), n_steps=10)
    rng = np.random.default_rng(6)
    Y = np.array([exp["ideal"] + S.lognormal_noise(exp["ideal"], 4.0, rng) for _ in range(4)])
    many = E.batch_estimate_many(Y, exp["Cs"], exp["A"], exp["Bs"])
    assert many.shape == (4, 10, 2, 2)
    for d in range(4):
        one = E.batch_estimate([np.array([[v]]) for v in Y[d]], exp["Cs"], exp["As"], exp["Bs"])
        np.testing.assert_allclose(many[d], one, atol=1e-10)
    # general m: 3-D ellipsoid seen in 2-D views, no drive
    X = S.random_ellipsoid(3, rng)
    Cs = [S.random_projection(3, 2, rng) for _ in range(3)]
    A = 0.9 * np.eye(3)
    Xs = E.simulate(X, A, None, 2)
    Ys = np.array([[E.project(Xk, C) for Xk, C in zip(Xs, Cs)]])
    np.testing.assert_allclose(E.batch_estimate_many(Ys, Cs, A)[0], Xs, atol=1e-10)


def test_batch_estimate_many_validates():
    import numpy as np
    import pytest
    from projtrack import ellipsoids as E
    C = [np.array([[1.0], [0.0]])] * 3
    with pytest.raises(ValueError, match="shape"):
        E.batch_estimate_many(np.zeros((2, 4)), C, np.eye(2))
    with pytest.raises(ValueError, match="not observable"):
        E.batch_estimate_many(np.zeros((2, 3)), C, 0.8 * np.eye(2))


def test_median_draw_and_settling_step():
    import numpy as np
    import pytest
    from projtrack.experiments.ellipsoids import median_draw, settling_step
    assert median_draw([3.0, 1.0, 2.0, 5.0]) == 0  # sorted 1, 2, 3, 5: position 2
    assert median_draw([3.0, 1.0, 2.0, 5.0], pool=[1, 3]) == 3
    assert median_draw([3.0, 1.0, 2.0, 5.0], pool=np.array([True, True, False, False])) == 0
    assert median_draw([1.0, 1.0, 1.0], tiebreak=[3.0, 2.0, 1.0]) == 1
    with pytest.raises(ValueError):
        median_draw([])
    with pytest.raises(ValueError):
        median_draw([1.0, 2.0], pool=[])
    assert settling_step([0.5, 0.05, 0.2, 0.05, 0.01]) == 3
    assert settling_step([0.01, 0.01]) == 0
    assert settling_step([0.01, 0.5]) == 2
    np.testing.assert_array_equal(settling_step([[0.5, 0.01], [0.01, 0.2]]), [1, 2])
    with pytest.raises(ValueError):
        settling_step([0.1], tol=0)


def test_reconstruct_many_equals_reconstruct():
    import numpy as np
    import pytest
    from projtrack import ellipsoids as E
    from projtrack.scenes import ellipses as S
    rng = np.random.default_rng(9)
    Cs = S.paper_projections()
    W = rng.normal(0, 0.5, size=(3, 5))
    ideal = np.array([float(C[:, 0] @ S.X26 @ C[:, 0]) for C in Cs])
    many = E.reconstruct_many(ideal + W, Cs)
    for d in range(3):
        np.testing.assert_allclose(many[d], E.reconstruct([np.array([[v]]) for v in ideal + W[d]], Cs), atol=1e-12)
    with pytest.raises(ValueError):
        E.reconstruct_many(np.zeros((2, 2)), Cs[:2])

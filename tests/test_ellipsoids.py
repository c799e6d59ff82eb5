"""Tests of projtrack.ellipsoids (Karl, Verghese & Willsky 1994) and projtrack.scenes.ellipses."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from projtrack import ellipsoids as E
from projtrack.scenes import ellipses as S

SETTINGS = settings(max_examples=25, deadline=None)


def sym(rng, n, scale=1.0):
    M = rng.normal(size=(n, n)) * scale
    return (M + M.T) / 2


def problem(seed, n, m, q, noise=0.0):
    rng = np.random.default_rng(seed)
    X = S.random_ellipsoid(n, rng)
    Cs = [S.random_projection(n, m, rng) for _ in range(q)]
    Ys = [E.project(X, C) + noise * sym(rng, m) for C in Cs]
    return X, Cs, Ys


seeds = st.integers(0, 2**31 - 1)
dims = st.integers(2, 5)


# ---------------------------------------------------------------- representation (Sec. 2-4)
@SETTINGS
@given(seeds, dims)
def test_svec_smat_round_trip_and_isometry(seed, n):
    rng = np.random.default_rng(seed)
    A, B = sym(rng, n), sym(rng, n)
    np.testing.assert_allclose(E.smat(E.svec(A)), A, atol=1e-12)
    assert E.svec(A) @ E.svec(B) == pytest.approx(np.trace(A.T @ B), abs=1e-10)
    x = rng.normal(size=n * (n + 1) // 2)
    np.testing.assert_allclose(E.svec(E.smat(x)), x, atol=1e-12)


def test_symmetric_basis_matches_eq9_indexing():
    n = 4
    M = E.symmetric_basis(n)
    G = np.einsum("aij,bij->ab", M, M)
    np.testing.assert_allclose(G, np.eye(n * (n + 1) // 2), atol=1e-14)
    e = np.eye(n)
    for i in range(1, n + 1):  # 1-based indices of eq. (9)
        l = (i - 1) * (2 * n + 2 - i) // 2 + 1
        np.testing.assert_allclose(M[l - 1], np.outer(e[i - 1], e[i - 1]))
        for j in range(i + 1, n + 1):
            l = i * (2 * n + 1 - i) // 2 - n + j
            want = (np.outer(e[i - 1], e[j - 1]) + np.outer(e[j - 1], e[i - 1])) / np.sqrt(2)
            np.testing.assert_allclose(M[l - 1], want)


@SETTINGS
@given(seeds, dims, st.integers(1, 4))
def test_ctilde_equals_kronecker_form_restricted(seed, n, m):
    m = min(m, n)
    rng = np.random.default_rng(seed)
    C = S.random_projection(n, m, rng)
    Pn, Pm = E.svec_basis_matrix(n), E.svec_basis_matrix(m)
    # eq. (6) restricted to symmetric matrices, in orthonormal coordinates
    np.testing.assert_allclose(E.ctilde(C), Pm.T @ E.kron_operator(C) @ Pn, atol=1e-12)
    X = sym(rng, n)
    np.testing.assert_allclose(E.smat(E.ctilde(C) @ E.svec(X)), E.project(X, C), atol=1e-12)


@SETTINGS
@given(seeds, dims, st.floats(-3, 3), st.floats(-3, 3))
def test_project_is_linear(seed, n, a, b):
    rng = np.random.default_rng(seed)
    C = S.random_projection(n, max(1, n - 1), rng)
    X1, X2 = sym(rng, n), sym(rng, n)
    np.testing.assert_allclose(E.project(a * X1 + b * X2, C), a * E.project(X1, C) + b * E.project(X2, C),
                               atol=1e-10)


def test_projector_form_gives_projector_ctilde():
    rng = np.random.default_rng(0)
    C = S.random_projection(4, 2, rng)
    P = E.congruence_operator(C @ C.T)  # eq. (5)
    np.testing.assert_allclose(P @ P, P, atol=1e-12)
    np.testing.assert_allclose(P, P.T, atol=1e-12)


def test_geometry_of_eq26():
    lengths, V = E.axes(S.X26)
    np.testing.assert_allclose(lengths, [2.0, 1.0])
    assert abs(abs(V[0, 0]) - np.sqrt(0.5)) < 1e-12 and V[0, 0] * V[1, 0] > 0  # major axis at pi/4
    assert E.volume(S.X26) == pytest.approx(np.pi * 2.0)
    assert E.volume(np.diag([1.0, 4.0, 9.0])) == pytest.approx(4 / 3 * np.pi * 6)
    u = np.array([1.0, 1.0])
    assert E.support(S.X26, u) == pytest.approx(2.0)
    pts = E.boundary_points(S.X26, 50)
    q = np.einsum("ki,ij,kj->k", pts, np.linalg.inv(S.X26), pts)
    np.testing.assert_allclose(q, 1.0, atol=1e-12)  # eq. (2)


def test_support_of_projection_is_support_of_ellipsoid():
    rng = np.random.default_rng(3)
    X = S.random_ellipsoid(3, rng)
    C = S.random_projection(3, 1, rng)
    assert E.project(X, C)[0, 0] == pytest.approx(E.support(X, C[:, 0]) ** 2)


def test_conic_points_hyperbola():
    X = np.diag([-2.5, 19.2])
    branches = E.conic_points(X, 40)
    assert len(branches) == 2
    Xi = np.linalg.inv(X)
    for b in branches:
        np.testing.assert_allclose(np.einsum("ki,ij,kj->k", b, Xi, b), 1.0, atol=1e-9)
    assert E.conic_points(-np.eye(2)) == []


def test_interval_boundary_point_touches():
    L = np.diag([0.5, 0.2])
    U = np.diag([4.0, 2.0])
    D = np.array([[1.0, 0.3], [0.3, 0.5]])
    Xu = E.interval_boundary_point(L, U, D, "upper")
    assert np.linalg.eigvalsh(U - Xu)[0] == pytest.approx(0.0, abs=1e-10)
    assert E.in_interval(Xu, L, U)
    Xl = E.interval_boundary_point(L, U, D, "lower")
    assert np.linalg.eigvalsh(Xl - L)[0] == pytest.approx(0.0, abs=1e-10)
    assert E.in_interval(Xl, L, U)


# ---------------------------------------------------------------- reconstruction (Sec. 5)
@SETTINGS
@given(seeds, dims, st.integers(1, 4), st.integers(0, 4))
def test_exact_recovery_whenever_rank_condition_holds(seed, n, m, extra):
    m = min(m, n)
    rng = np.random.default_rng(seed)
    X = S.random_ellipsoid(n, rng)
    Cs = [S.random_projection(n, m, rng) for _ in range(extra + 1)]
    Ys = [E.project(X, C) for C in Cs]
    A = E.stacked_operator(Cs)
    if np.linalg.matrix_rank(A) == A.shape[1]:
        np.testing.assert_allclose(E.reconstruct(Ys, Cs), X, atol=1e-8)
    else:
        with pytest.raises(ValueError, match="rank"):
            E.reconstruct(Ys, Cs)


def test_rank_deficient_warn_gives_min_norm_consistent_solution():
    X, Cs, Ys = problem(1, 3, 2, 2)
    with pytest.warns(E.RankDeficientWarning):
        Xh = E.reconstruct(Ys, Cs, rank_deficient="warn")
    for C, Y in zip(Cs, Ys):
        np.testing.assert_allclose(E.project(Xh, C), Y, atol=1e-10)


def test_ls_equals_lstsq_oracle():
    X, Cs, Ys = problem(2, 3, 1, 9, noise=0.3)
    A = E.stacked_operator(Cs)
    y = np.concatenate([E.svec(Y) for Y in Ys])
    np.testing.assert_allclose(E.svec(E.reconstruct(Ys, Cs)), np.linalg.lstsq(A, y, rcond=None)[0], atol=1e-10)


@pytest.mark.parametrize("n", [2, 3])
def test_three_hyperplanes_necessary_and_sufficient(n):
    rng = np.random.default_rng(n)
    for _ in range(10):
        Cs = [S.random_projection(n, n - 1, rng) for _ in range(3)]
        assert np.linalg.matrix_rank(E.stacked_operator(Cs[:2])) < n * (n + 1) // 2
        assert np.linalg.matrix_rank(E.stacked_operator(Cs)) == n * (n + 1) // 2


def _constrained_case(seed, n, q, noise):
    rng = np.random.default_rng(seed)
    X = S.random_ellipsoid(n, rng)
    Cs = [S.random_projection(n, max(1, n - 1), rng) for _ in range(q)]
    Ys = [E.project(X, C) + noise * sym(rng, C.shape[1]) for C in Cs]
    kind = seed % 3
    if kind == 0:
        return Cs, Ys, 0.0, None
    if kind == 1:
        return Cs, Ys, 0.3 * X, 2.5 * X
    return Cs, Ys, 0.1, 6.0


@settings(max_examples=12, deadline=None)
@given(seeds, st.integers(2, 4))
def test_halfspace_equals_sdp_and_is_feasible_and_optimal(seed, n):
    Cs, Ys, L, U = _constrained_case(seed, n, 4, noise=2.0)
    res = E.halfspace_reconstruct(Ys, Cs, L, U)
    assert res.converged
    Xs = E.reconstruct(Ys, Cs, L, U, method="sdp")
    scale = max(1.0, np.linalg.norm(Xs))
    assert np.linalg.norm(res.X - Xs) <= 1e-3 * scale
    A = E.stacked_operator(Cs)
    y = np.concatenate([E.svec(Y) for Y in Ys])
    f = lambda X: float(np.sum((A @ E.svec(X) - y) ** 2))  # noqa: E731
    assert abs(f(res.X) - f(Xs)) <= 1e-6 * max(1.0, f(Xs))
    assert E.in_interval(res.X, L, U, tol=1e-7)
    # no worse than feasible points: random points of the interval
    rng = np.random.default_rng(seed + 1)
    Lm, Um = E.interval_bounds(L, U, n)
    for _ in range(5):
        Z = rng.normal(size=(n, n))
        P = Z @ Z.T / n
        if Um is None:
            cand = Lm + P
        else:  # a point of the segment from lower to a boundary point: inside the interval
            cand = Lm + rng.uniform() * (E.interval_boundary_point(Lm, Um, P + 1e-3 * np.eye(n)) - Lm)
        cand = (cand + cand.T) / 2
        assert E.in_interval(cand, Lm, Um, tol=1e-9)
        assert f(res.X) <= f(cand) + 1e-8


def test_constraints_inactive_give_ls():
    X, Cs, Ys = problem(5, 2, 1, 5, noise=0.01)
    Xls = E.reconstruct(Ys, Cs)
    for method in ("halfspace", "sdp"):
        np.testing.assert_allclose(E.reconstruct(Ys, Cs, lower=0, method=method), Xls, atol=1e-6)


def test_halfspace_history_and_cuts():
    Ys = [np.array([[v]]) for v in (9.0, 9.0, 0.1, 0.1, 0.1)]
    Cs = S.paper_projections()
    res = E.halfspace_reconstruct(Ys, Cs, lower=0)
    assert res.n_iter == len(res.history) >= 2
    assert res.normals_lower and not res.normals_upper
    objs = [h["objective"] for h in res.history]
    assert all(b >= a - 1e-9 for a, b in zip(objs, objs[1:]))  # relaxations shrink: objective non-decreasing
    assert np.linalg.eigvalsh(res.X)[0] >= -1e-8


def test_scalar_bounds_mean_multiples_of_identity():
    X, Cs, Ys = problem(7, 2, 1, 5, noise=1.5)
    a = E.reconstruct(Ys, Cs, lower=0.5, upper=3.0, method="halfspace")
    b = E.reconstruct(Ys, Cs, lower=0.5 * np.eye(2), upper=3.0 * np.eye(2), method="halfspace")
    np.testing.assert_allclose(a, b)
    lam = np.linalg.eigvalsh(a)
    assert lam[0] >= 0.5 - 1e-7 and lam[-1] <= 3.0 + 1e-7


@SETTINGS
@given(seeds)
def test_condition19_implies_psd(seed):
    rng = np.random.default_rng(seed)
    X = S.random_ellipsoid(2, rng, 0.8, 2.0)
    Cs = S.paper_projections()
    Ws = [rng.normal(scale=rng.uniform(0.01, 1.0), size=(1, 1)) for _ in Cs]
    holds, lhs, rhs = E.condition19(Cs, Ws, X)
    assert holds == (lhs <= rhs)
    if holds:
        Xls = E.reconstruct([E.project(X, C) + W for C, W in zip(Cs, Ws)], Cs)
        assert np.linalg.eigvalsh(Xls)[0] >= -1e-12


# ---------------------------------------------------------------- dynamics (Sec. 6)
def test_shaping_matrix_rotation_and_volume():
    A = E.shaping_matrix(1, 1, 0, np.pi / 8)
    X1 = E.simulate(S.X26, A, None, 1)[1]
    _, V0 = E.axes(S.X26)
    _, V1 = E.axes(X1)
    ang = lambda v: np.arctan2(v[1], v[0]) % np.pi  # noqa: E731
    assert (ang(V1[:, 0]) - ang(V0[:, 0])) % np.pi == pytest.approx(np.pi / 8)
    Xs = E.simulate(S.X26, E.shaping_matrix(1, 0.75, 0, np.pi / 8), None, 10)
    np.testing.assert_allclose(np.linalg.det(Xs), np.linalg.det(S.X26))
    Xs = E.simulate(S.X26, E.shaping_matrix(0.8, 1, 0, 0), None, 2)
    np.testing.assert_allclose(Xs[2], 0.8**4 * S.X26)


def test_state_space_matches_matrix_recursion():
    rng = np.random.default_rng(0)
    As = [rng.normal(size=(3, 3)) for _ in range(4)]
    Bs = [np.eye(3) * 0.1 * k for k in range(4)]
    X0 = S.random_ellipsoid(3, rng)
    Xs = E.simulate(X0, As, Bs)
    At, bt = E.state_space(As, Bs)
    x = E.svec(X0)
    for k in range(4):
        x = At[k] @ x + bt[k]
        np.testing.assert_allclose(E.smat(x), Xs[k + 1], atol=1e-10)


def test_observability_claims():
    C = np.array([[1.0], [0.0]])
    assert not E.is_observable([C] * 8, [0.8 * np.eye(2)] * 7)  # uniform shrink, fixed view
    assert E.is_observable([C] * 8, [E.shaping_matrix(0.8, 0.9, 0, np.pi / 15)] * 7)
    O = E.observability_matrix([C] * 3, [0.8 * np.eye(2)] * 2)
    assert np.linalg.matrix_rank(O) == 1


def _dyn_data(seed, K=16):
    A = E.shaping_matrix(0.8, 0.9, 0, np.pi / 15)
    Bs = S.periodic_drive(K - 1)
    Xs = E.simulate(S.X26, [A] * (K - 1), Bs)
    C = np.array([[1.0], [0.0]])
    rng = np.random.default_rng(seed)
    ideal = np.array([X[0, 0] for X in Xs])
    Ys = [np.array([[v]]) for v in ideal + S.lognormal_noise(ideal, 4.0, rng)]
    return A, Bs, Xs, C, Ys


def test_batch_exact_without_noise_and_kalman_matches_batch():
    A, Bs, Xs, C, _ = _dyn_data(0)
    K = len(Xs)
    Ys = [E.project(X, C) for X in Xs]
    np.testing.assert_allclose(E.batch_estimate(Ys, [C] * K, [A] * (K - 1), Bs), Xs, atol=1e-8)


@settings(max_examples=8, deadline=None)
@given(seeds, st.integers(4, 12))
def test_kalman_with_diffuse_prior_equals_batch(seed, K):
    A, Bs, Xs, C, Ys = _dyn_data(seed, 12)
    Ys, Bs = Ys[:K], Bs[:K - 1]
    kr = E.kalman_estimate(Ys, [C] * K, [A] * (K - 1), Bs, P0=1e7, R=4.0)
    Xb = E.batch_estimate(Ys, [C] * K, [A] * (K - 1), Bs)
    np.testing.assert_allclose(kr.X[-1], Xb[-1], atol=1e-3 * max(1.0, np.abs(Xb[-1]).max()))
    assert kr.n_not_psd == sum(np.linalg.eigvalsh(X)[0] < -1e-10 * max(1, np.linalg.norm(X, 2)) for X in kr.X)
    assert all(np.linalg.eigvalsh(X)[0] >= -1e-12 for X in kr.X_psd)


def test_constrained_batch_is_psd():
    A, Bs, Xs, C, Ys = _dyn_data(3, 10)
    X0h = E.batch_estimate(Ys, [C] * 10, [A] * 9, Bs, lower=0, method="halfspace")[0]
    X0s = E.batch_estimate(Ys, [C] * 10, [A] * 9, Bs, lower=0, method="sdp")[0]
    assert np.linalg.eigvalsh(X0h)[0] >= -1e-8 * max(1.0, np.linalg.norm(X0h, 2))
    np.testing.assert_allclose(X0h, X0s, atol=1e-3 * max(1, np.abs(X0s).max()))


def test_batch_not_observable_raises():
    C = np.array([[1.0], [0.0]])
    Ys = [np.array([[1.0]])] * 4
    with pytest.raises(ValueError, match="observable"):
        E.batch_estimate(Ys, [C] * 4, [0.8 * np.eye(2)] * 3)


# ---------------------------------------------------------------- scenes
def test_lognormal_noise_moments_and_support():
    rng = np.random.default_rng(0)
    c = np.full(200_000, 2.5)
    W = S.lognormal_noise(c, 9.0, rng)
    assert W.min() > -2.5
    assert abs(W.mean()) < 0.05
    assert W.var() == pytest.approx(9.0, rel=0.1)


def test_snr_of_paper_settings():
    c = np.array([E.project(S.X26, C)[0, 0] for C in S.paper_projections()])
    assert S.snr_static(c, np.sqrt(0.3)) == pytest.approx(4.96, abs=0.01)
    assert S.snr_static(c, 3.0) == pytest.approx(0.905, abs=0.01)


# ---------------------------------------------------------------- bad inputs
C1 = np.array([[1.0], [0.0]])


@pytest.mark.parametrize("X, C, err, match", [
    (np.array([[1.0, 2.0], [0.0, 1.0]]), C1, ValueError, "symmetric"),
    (np.array([[np.nan, 0.0], [0.0, 1.0]]), C1, ValueError, "finite"),
    (np.eye(2), np.array([[2.0], [0.0]]), ValueError, "orthonormal"),
    (np.eye(3), C1, ValueError, "rows"),
    (np.ones((2, 3)), C1, ValueError, "square"),
    ("abc", C1, TypeError, "array"),
])
def test_project_bad_inputs(X, C, err, match):
    with pytest.raises(err, match=match):
        E.project(X, C)


def test_reconstruct_bad_inputs():
    Cs = S.paper_projections()
    Ys = [E.project(S.X26, C) for C in Cs]
    with pytest.raises(ValueError, match="at least one"):
        E.reconstruct([], [])
    with pytest.raises(ValueError, match="same length"):
        E.reconstruct(Ys[:3], Cs)
    with pytest.raises(ValueError, match="method"):
        E.reconstruct(Ys, Cs, method="magic")
    with pytest.raises(ValueError, match="lower must be <= upper"):
        E.reconstruct(Ys, Cs, lower=2.0, upper=1.0, method="sdp")
    with pytest.raises(ValueError, match="unconstrained"):
        E.reconstruct(Ys, Cs, lower=0)
    with pytest.raises(ValueError, match="orthonormal"):
        E.reconstruct(Ys, [2 * C for C in Cs])
    with pytest.raises(ValueError, match="2 x 2|1 x 1"):
        E.reconstruct([np.eye(2)] * 5, Cs)
    with pytest.raises(ValueError, match="symmetric"):
        E.reconstruct(Ys, Cs, lower=np.array([[0, 1.0], [0, 0]]), method="halfspace")
    with pytest.raises(ValueError, match="finite"):
        E.reconstruct([np.array([[np.inf]])] + Ys[1:], Cs)
    with pytest.raises(TypeError):
        E.reconstruct(Ys, Cs[0])
    with pytest.raises(ValueError, match="rows"):
        E.reconstruct(Ys[:2] + [np.eye(1)], Cs[:2] + [np.array([[1.0], [0.0], [0.0]])])


def test_other_bad_inputs():
    with pytest.raises(ValueError):
        E.smat(np.ones(4))
    with pytest.raises(ValueError):
        E.symmetric_basis(0)
    with pytest.raises(ValueError, match="positive semidefinite"):
        E.axes(np.diag([1.0, -1.0]))
    with pytest.raises(ValueError, match="alpha"):
        E.shaping_matrix(1, 0, 0, 0)
    with pytest.raises(ValueError, match="finite"):
        E.shaping_matrix(np.nan, 1, 0, 0)
    with pytest.raises(ValueError, match="n_steps"):
        E.simulate(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="max_iter"):
        E.halfspace_reconstruct([np.eye(1)] * 3, S.paper_projections(3), lower=0, max_iter=0)
    with pytest.raises(ValueError, match="rank"):
        E.halfspace_reconstruct([np.eye(1)] * 2, S.paper_projections(2), lower=0)
    with pytest.raises(ValueError, match="positive"):
        S.lognormal_noise([1.0, -1.0], 1.0, np.random.default_rng(0))
    with pytest.raises(TypeError):
        S.lognormal_noise([1.0], 1.0, 0)
    with pytest.raises(ValueError, match="invertible"):
        E.conic_points(np.diag([1.0, 0.0]))
    with pytest.raises(ValueError, match="rank|infeasible"):
        E.lsi(np.zeros((3, 2)), np.zeros(3), np.zeros((0, 2)), np.zeros(0))
    with pytest.raises(ValueError, match="infeasible"):
        E.lsi(np.eye(2), np.zeros(2), np.array([[1.0, 0], [-1.0, 0]]), np.array([1.0, 1.0]))


def test_lsi_against_sdp_free_oracle():
    # tiny LSI solved by brute force over active sets
    import itertools
    rng = np.random.default_rng(4)
    Em, f = rng.normal(size=(6, 3)), rng.normal(size=6)
    G, h = rng.normal(size=(4, 3)), rng.normal(size=4)
    x = E.lsi(Em, f, G, h)
    assert np.all(G @ x >= h - 1e-9)
    best = np.inf
    for r in range(0, 4):
        for act in itertools.combinations(range(4), r):
            Ga = G[list(act)]
            K = np.block([[Em.T @ Em, Ga.T], [Ga, np.zeros((r, r))]])
            try:
                sol = np.linalg.solve(K, np.concatenate([Em.T @ f, h[list(act)]]))
            except np.linalg.LinAlgError:
                continue
            z = sol[:3]
            if np.all(G @ z >= h - 1e-9):
                best = min(best, np.sum((Em @ z - f) ** 2))
    assert np.sum((Em @ x - f) ** 2) == pytest.approx(best, rel=1e-8)


def test_no_warnings_from_sdp():
    Cs = S.paper_projections()
    Ys = [np.array([[v]]) for v in (9.0, 9.0, 0.1, 0.1, 0.1)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        X = E.reconstruct(Ys, Cs, lower=0, method="sdp")
    assert np.linalg.eigvalsh(X)[0] >= -1e-7


def test_fit_centered_ellipse_exact_and_bad():
    rng = np.random.default_rng(0)
    X = S.random_ellipsoid(3, rng)
    C = S.random_projection(3, 2, rng)
    pts = S.silhouette_points(X, C, 12, 0.0, rng)
    np.testing.assert_allclose(E.fit_centered_ellipse(pts), E.project(X, C), atol=1e-9)
    with pytest.raises(ValueError, match="at least"):
        E.fit_centered_ellipse(pts[:2])
    with pytest.raises(ValueError, match="not an ellipse"):
        t = np.array([0.0, 1.0, -1.0, 2.0, 0.5])
        E.fit_centered_ellipse(np.stack([np.cosh(t), np.sinh(t)], axis=1))  # points of a hyperbola


# ---------------------------------------------------------------- bad inputs (review round)
def test_fit_centered_ellipse_collinear_points_raise():
    t = np.linspace(-2.0, 2.0, 10)
    with pytest.raises(ValueError, match="degenerate"):
        E.fit_centered_ellipse(np.stack([t, 0.5 * t], axis=1))  # all on one line through 0
    with pytest.raises(ValueError, match="not an ellipse"):
        E.fit_centered_ellipse(np.stack([t + 1.0, 0.5 * t], axis=1))  # on a line off the origin: Q singular
    with pytest.raises(ValueError, match="degenerate"):
        E.fit_centered_ellipse(np.zeros((6, 2)))


def test_condition19_singular_and_non_psd_X():
    Cs = S.paper_projections()
    X_seg = np.diag([4.0, 0.0])  # a degenerate ellipse (segment)
    holds, lhs, rhs = E.condition19(Cs, [np.array([[0.0]])] * 5, X_seg)
    assert holds and lhs == 0.0 and rhs == 0.0  # noise-free data: LS is X itself
    holds, lhs, rhs = E.condition19(Cs, [np.array([[1e-6]])] * 5, X_seg)
    assert not holds and lhs > 0 and rhs == 0.0
    with pytest.raises(ValueError, match="positive semidefinite"):
        E.condition19(Cs, [np.array([[0.0]])] * 5, np.diag([1.0, -1.0]))


def test_observability_matrix_rejects_wrong_number_of_As():
    C = np.array([[1.0], [0.0]])
    A = E.shaping_matrix(0.8, 0.9, 0, np.pi / 15)
    with pytest.raises(ValueError, match="exactly 2"):
        E.observability_matrix([C] * 3, [A] * 5)  # extra matrices are not ignored
    with pytest.raises(ValueError, match="exactly 2"):
        E.observability_matrix([C] * 3, [A])
    with pytest.raises(ValueError, match="exactly 0"):
        E.observability_matrix([C], [A])
    # a single matrix is a constant dynamics and equals the explicit sequence
    np.testing.assert_array_equal(E.observability_matrix([C] * 3, A), E.observability_matrix([C] * 3, [A] * 2))
    Ys = [np.array([[1.0]])] * 3
    with pytest.raises(ValueError, match="exactly 2"):
        E.batch_rhs(Ys, [C] * 3, [A] * 2, [np.eye(2)] * 4)
    with pytest.raises(ValueError, match="exactly 2"):
        E.kalman_estimate(Ys, [C] * 3, [A] * 3)
    with pytest.raises(ValueError, match="exactly 2"):
        E.batch_estimate(Ys, [C] * 3, [A] * 4)


def test_batch_estimate_constant_A_equals_sequence():
    A, Bs, Xs, C, Ys = _dyn_data(5, 8)
    np.testing.assert_allclose(E.batch_estimate(Ys, [C] * 8, A, Bs), E.batch_estimate(Ys, [C] * 8, [A] * 7, Bs))


@pytest.mark.parametrize("sigma", [0, 0.0, -1.0, np.inf, np.nan])
def test_snr_rejects_bad_sigma(sigma):
    c = np.array([1.0, 2.0])
    with pytest.raises(ValueError, match="sigma"):
        S.snr_static(c, sigma)
    with pytest.raises(ValueError, match="sigma"):
        S.snr_dynamic(c, sigma)


def test_snr_rejects_bad_ideal():
    with pytest.raises(ValueError, match="ideal"):
        S.snr_static([], 1.0)
    with pytest.raises(ValueError, match="ideal"):
        S.snr_dynamic([1.0, np.nan], 1.0)
    with pytest.raises(TypeError, match="sigma"):
        S.snr_static([1.0], "1")


def test_realized_snr_static():
    c = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    sigma = 0.7
    W = np.array([sigma, -sigma, sigma, -sigma, sigma])  # RMS exactly sigma
    assert S.realized_snr_static(c, W) == pytest.approx(S.snr_static(c, sigma), rel=1e-12)
    stack = np.stack([W, 2 * W])
    np.testing.assert_allclose(S.realized_snr_static(c, stack), [S.snr_static(c, sigma), S.snr_static(c, 2 * sigma)])
    with pytest.raises(ValueError, match="shape"):
        S.realized_snr_static(c, W[:4])
    with pytest.raises(ValueError, match="infinite"):
        S.realized_snr_static(c, np.zeros(5))
    with pytest.raises(ValueError, match="finite"):
        S.realized_snr_static(c, np.full(5, np.nan))


@pytest.mark.parametrize("n", [0, -1, 2.0, True])
def test_random_ellipsoid_rejects_bad_n(n):
    with pytest.raises(ValueError, match="n must"):
        S.random_ellipsoid(n, np.random.default_rng(0))


def test_random_ellipsoid_and_projection_bad_args():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="min_axis"):
        S.random_ellipsoid(2, rng, 0.0, 1.0)
    with pytest.raises(ValueError, match="min_axis"):
        S.random_ellipsoid(2, rng, 2.0, 1.0)
    with pytest.raises(TypeError, match="rng"):
        S.random_ellipsoid(2, 0)
    with pytest.raises(ValueError, match="1 <= m <= n"):
        S.random_projection(2, 3, rng)
    with pytest.raises(TypeError, match="rng"):
        S.random_projection(3, 2, None)


@pytest.mark.parametrize("kwargs, match", [
    ({"n_steps": 0}, "n_steps"), ({"n_steps": -3}, "n_steps"), ({"n_steps": 2.5}, "n_steps"),
    ({"n_steps": 4, "period": 0}, "period"), ({"n_steps": 4, "beta": -1.0}, "beta"),
    ({"n_steps": 4, "beta": np.inf}, "beta"), ({"n_steps": 4, "rho": np.nan}, "rho"),
])
def test_periodic_drive_rejects_bad_inputs(kwargs, match):
    with pytest.raises(ValueError, match=match):
        S.periodic_drive(**kwargs)


def test_periodic_drive_is_periodic_and_psd():
    B = S.periodic_drive(25, period=12)
    np.testing.assert_allclose(B[12:24], B[:12], atol=1e-12)
    assert all(np.linalg.eigvalsh(b)[0] >= -1e-12 for b in B)


def test_dynamic_experiment_rejects_short_horizon():
    with pytest.raises(ValueError, match="n_steps"):
        S.dynamic_experiment(np.random.default_rng(0), n_steps=1)


@pytest.mark.parametrize("n_points, noise, match", [
    (0, 0.1, "n_points"), (-2, 0.1, "n_points"), (3.0, 0.1, "n_points"),
    (10, -0.1, "noise"), (10, np.nan, "noise"),
])
def test_silhouette_points_rejects_bad_inputs(n_points, noise, match):
    rng = np.random.default_rng(0)
    X = S.random_ellipsoid(3, rng)
    C = S.random_projection(3, 2, rng)
    with pytest.raises(ValueError, match=match):
        S.silhouette_points(X, C, n_points, noise, rng)


def test_silhouette_points_bad_geometry():
    rng = np.random.default_rng(1)
    X = S.random_ellipsoid(3, rng)
    with pytest.raises(ValueError, match="n x 2"):
        S.silhouette_points(X, S.random_projection(3, 1, rng), 10, 0.1, rng)
    with pytest.raises(ValueError, match="orthonormal"):
        S.silhouette_points(X, np.ones((3, 2)), 10, 0.1, rng)
    with pytest.raises(ValueError, match="degenerate"):
        S.silhouette_points(np.diag([1.0, 0.0, 1.0]), np.eye(3)[:, :2], 10, 0.1, rng)
    with pytest.raises(TypeError, match="rng"):
        S.silhouette_points(X, np.eye(3)[:, :2], 10, 0.1, 0)
    pts = S.silhouette_points(X, np.eye(3)[:, :2], 10, 0.0, rng)  # noise-free points lie on the shadow
    Y = E.project(X, np.eye(3)[:, :2])
    np.testing.assert_allclose(np.einsum("ki,ij,kj->k", pts, np.linalg.inv(Y), pts), 1.0, atol=1e-10)


@pytest.mark.parametrize("name, call", [
    ("n", lambda bad: E.symmetric_basis(bad)),
    ("n_points", lambda bad: E.boundary_points(np.eye(2), bad)),
    ("n_steps", lambda bad: E.simulate(np.eye(2), np.eye(2), None, bad)),
    ("max_iter", lambda bad: E.halfspace_reconstruct([np.eye(1)] * 3, S.paper_projections(3), lower=0, max_iter=bad)),
])
@pytest.mark.parametrize("bad", [True, "3", 2.5, -1])
def test_a_bad_size_is_a_value_error_naming_it(name, call, bad):
    with pytest.raises(ValueError, match=f"^{name} must be an int"):
        call(bad)


def test_a_bad_tolerance_of_algorithm_1_is_a_value_error():
    for bad in (0.0, -1.0, "small", np.nan):
        with pytest.raises(ValueError, match="tol"):
            E.halfspace_reconstruct([np.eye(1)] * 3, S.paper_projections(3), lower=0, tol=bad)

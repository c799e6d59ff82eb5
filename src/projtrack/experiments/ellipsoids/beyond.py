"""Studies beyond KVW: Algorithm 1 against an SDP solver, 3-D ellipsoids from silhouettes, condition (19)."""

from __future__ import annotations

import time
from typing import Sequence

import numpy as np
import pandas as pd

from projtrack import ellipsoids as E
from projtrack import montecarlo
from projtrack._validation import as_int, as_real, as_rng, as_square
from projtrack.scenes import ellipses as S

__all__ = ["random_interval_draw", "random_interval_problems", "constraint_violation", "compare_alg1_sdp", "alg1_sdp_summary",
           "silhouette_trial", "silhouettes_3d_study", "condition19_trial", "condition19_study"]


def random_interval_draw(rng: np.random.Generator, n: int, n_views: int = 4,
                         noise: float = 2.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One random problem of :func:`random_interval_problems`: a random ellipsoid of R^n in ``n_views`` noisy hyperplane views.

    Returns ``(X, A, y)``: the true ellipsoid, the stacked operator (eq. 14) and the stacked
    ``svec`` of the observations.
    """
    Xt = S.random_ellipsoid(n, rng)
    Cs = [S.random_projection(n, n - 1, rng) for _ in range(n_views)]
    Ys = []
    for C in Cs:
        Wn = rng.normal(0, noise, size=(n - 1, n - 1))
        Ys.append(E.project(Xt, C) + (Wn + Wn.T) / np.sqrt(2) / 2)
    return Xt, E.stacked_operator(Cs), np.concatenate([E.svec(Y) for Y in Ys])


def random_interval_problems(rng: np.random.Generator, ns: Sequence[int] = range(2, 7), per_n: int = 5,
                             n_views: int = 4, noise: float = 2.0, n_jobs: int | None = None) -> list[tuple]:
    """Random interval-constrained LS problems: a random ellipsoid seen in ``n_views`` hyperplanes.

    Symmetric Gaussian noise ``(W + W^T) / (2 sqrt 2)``, ``W`` with i.i.d. ``N(0, noise^2)``
    entries, perturbs each view; the constraint cycles through PSD
    (``lower = 0``), a scalar interval ``0.1 I <= X <= 6 I`` and a matrix interval
    ``0.3 X <= X_hat <= 2.5 X``. The ``per_n`` problems of each ``n`` are draws of
    :func:`random_interval_draw` through :func:`projtrack.montecarlo.run` (``n_jobs`` passed on;
    the problems do not depend on it).

    Returns
    -------
    list of (name, n, A, y, lower, upper)
        ``A`` the stacked operator (eq. 14), ``y`` the stacked ``svec`` of the observations.
    """
    rng = as_rng(rng)
    per_n = as_int(per_n, "per_n", minimum=1)
    n_views = as_int(n_views, "n_views", minimum=1)
    noise = as_real(noise, "noise", 0.0)
    problems = []
    for n in ns:
        n = as_int(n, "n", minimum=2)
        draws = montecarlo.run(random_interval_draw, per_n, rng, n, n_views, noise, n_jobs=n_jobs)
        for i, (Xt, A, y) in enumerate(draws):
            kind = ("PSD", "scalar", "matrix")[i % 3]
            lo, hi = {"PSD": (np.zeros((n, n)), None), "scalar": (0.1 * np.eye(n), 6.0 * np.eye(n)),
                      "matrix": (0.3 * Xt, 2.5 * Xt)}[kind]
            problems.append((f"random n={n} #{i + 1}, {kind}", n, A, y, lo, hi))
    return problems


def constraint_violation(X: object, lower: object, upper: object = None) -> float:
    """How far ``X`` lies outside ``lower <= X <= upper``: the largest negative eigenvalue, negated (0 inside)."""
    Xm = as_square(X, "X")
    v = max(0.0, -float(np.linalg.eigvalsh(Xm - lower)[0]))
    if upper is not None:
        v = max(v, -float(np.linalg.eigvalsh(upper - Xm)[0]))
    return v


def compare_alg1_sdp(problems: Sequence[tuple]) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Solve each problem by Algorithm 1 and by the SDP (Clarabel via cvxpy) and compare them.

    Parameters
    ----------
    problems : sequence of (name, n, A, y, lower, upper)
        As :func:`random_interval_problems` gives them.

    Returns
    -------
    (comparison, timings) : two pandas.DataFrame
        ``comparison``: per problem whether the constraint is active, iterations, convergence,
        relative distance, relative objective gap, whether Algorithm 1's objective is not
        larger, and both constraint violations. ``timings``: wall-clock milliseconds of
        Algorithm 1, of the SDP with cvxpy's set-up and of the solver alone (they vary from
        run to run).
    """
    if isinstance(problems, (str, bytes)) or not hasattr(problems, "__iter__"):
        raise TypeError("problems must be a sequence of (name, n, A, y, lower, upper) tuples")
    rows, times = [], []
    for item in problems:
        if not isinstance(item, tuple) or len(item) != 6:
            raise ValueError("every problem must be a (name, n, A, y, lower, upper) tuple")
        name, n, A, y, lo, hi = item
        t0 = time.perf_counter()
        res = E.halfspace_reconstruct(None, None, lo, hi, A=A, y=y)
        t1 = time.perf_counter()
        info: dict = {}
        Xs = E.sdp_reconstruct(A, y, lo, hi, info=info)
        t2 = time.perf_counter()
        Xls = E.smat(np.linalg.lstsq(A, y, rcond=None)[0])

        def f(Z):
            return float(np.sum((A @ E.svec(Z) - y) ** 2))

        rows.append({"problem": name, "n": n, "constraint active": bool(np.linalg.norm(res.X - Xls) > 1e-6),
                     "iterations": res.n_iter, "converged": res.converged,
                     "rel. distance": np.linalg.norm(res.X - Xs) / np.linalg.norm(Xs),
                     "rel. objective gap (SDP - Alg. 1)": (f(Xs) - f(res.X)) / f(Xs),
                     "Alg. 1 objective <= SDP (rel. 1e-12)": bool(f(res.X) <= f(Xs) * (1 + 1e-12)),
                     "violation Alg. 1": constraint_violation(res.X, lo, hi),
                     "violation SDP": constraint_violation(Xs, lo, hi)})
        times.append({"problem": name, "n": n, "Algorithm 1 [ms]": 1e3 * (t1 - t0),
                      "SDP with cvxpy set-up [ms]": 1e3 * (t2 - t1), "SDP solver only [ms]": 1e3 * info["solve_time"]})
    return pd.DataFrame(rows), pd.DataFrame(times)


def alg1_sdp_summary(comparison: pd.DataFrame, dist_tol: float = 1e-3, gap_tol: float = 1e-6,
                     viol_tol: float = 1e-6) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The comparison of :func:`compare_alg1_sdp` judged against stated tolerances, as two narrow tables.

    The distances, objective gaps and violations sit at the level of the solvers' stopping
    tolerances and move in their last digits between machines, so they are shown only as pass
    or fail against ``dist_tol`` (relative Frobenius distance), ``gap_tol`` (relative objective gap,
    in absolute value) and ``viol_tol`` (constraint violation of both solutions).

    Returns
    -------
    (by_problem, by_n)
        ``by_problem``: problem, n, iterations, constraint active, and whether it is within the
        tolerances; ``by_n``: per dimension the number of problems, of active constraints, the
        median and largest iteration count and the number within the tolerances.
    """
    if not isinstance(comparison, pd.DataFrame):
        raise TypeError("comparison must be the table of compare_alg1_sdp")
    ok = ((comparison["rel. distance"] < dist_tol) & (comparison["rel. objective gap (SDP - Alg. 1)"].abs() < gap_tol)
          & (comparison["violation Alg. 1"] < viol_tol) & (comparison["violation SDP"] < viol_tol) & comparison["converged"])
    by_problem = pd.DataFrame({"problem": comparison["problem"], "n": comparison["n"],
                               "iterations": comparison["iterations"], "constraint active": comparison["constraint active"],
                               "within tolerances": ok})
    by_n = by_problem.groupby("n").agg(problems=("problem", "size"), active=("constraint active", "sum"),
                                       **{"median iterations": ("iterations", "median"),
                                          "max iterations": ("iterations", "max"),
                                          "within tolerances": ("within tolerances", "sum")}).reset_index()
    by_n["active"] = by_n["active"].astype(int)
    by_n["within tolerances"] = by_n["within tolerances"].astype(int)
    return by_problem, by_n


def silhouette_trial(rng: np.random.Generator, q: int, n_points: int = 30, noise: float = 0.05) -> dict:
    """One trial of :func:`silhouettes_3d_study`: a random 3-D ellipsoid from ``q`` noisy 2-D silhouettes.

    Returns a dict: ``X`` the true ellipsoid, ``views`` the ``q`` views, ``rank`` of their
    stacked operator, and, when the rank is full (6), ``estimate`` (LS, replaced by the
    PSD-constrained estimate of Algorithm 1 when not PSD), ``psd_fix`` (whether it was) and
    ``error`` (relative Frobenius error); ``estimate`` None and ``error`` NaN otherwise.
    """
    X3 = S.random_ellipsoid(3, rng)
    Cs3 = [S.random_projection(3, 2, rng) for _ in range(q)]
    Ys3 = [E.fit_centered_ellipse(S.silhouette_points(X3, C, n_points, noise, rng)) for C in Cs3]
    r = int(np.linalg.matrix_rank(E.stacked_operator(Cs3)))
    out = {"X": X3, "views": Cs3, "rank": r, "estimate": None, "psd_fix": False, "error": np.nan}
    if r < 6:
        return out
    Xh = E.reconstruct(Ys3, Cs3, indefinite="ignore")  # noisy silhouettes: indefinite fits are expected
    if not E.is_psd(Xh):
        Xh = E.reconstruct(Ys3, Cs3, lower=0, method="halfspace")
        out["psd_fix"] = True
    out["estimate"], out["error"] = Xh, float(np.linalg.norm(Xh - X3) / np.linalg.norm(X3))
    return out


def silhouettes_3d_study(rng: np.random.Generator, qs: Sequence[int] = range(2, 9), n_trials: int = 25,
                         n_points: int = 30, noise: float = 0.05, example_q: int = 3,
                         n_jobs: int | None = None) -> tuple[pd.DataFrame, list[tuple]]:
    """A random 3-D ellipsoid from ``q`` noisy 2-D silhouettes, for each ``q`` of ``qs``.

    Each silhouette is ``n_points`` edge points with normal noise ``noise``
    (:func:`projtrack.scenes.ellipses.silhouette_points`), fitted by
    :func:`projtrack.ellipsoids.fit_centered_ellipse`; the LS estimate is replaced by the
    PSD-constrained one (Algorithm 1) when it is not PSD. For each ``q``, ``n_trials`` trials of
    :func:`silhouette_trial` run through :func:`projtrack.montecarlo.run` (``n_jobs`` passed on;
    the results do not depend on it); views with a rank-deficient stacked operator (rank < 6)
    are not estimated.

    Returns
    -------
    (table, examples)
        One row per ``q``: minimum rank over trials, median and 90% quantile of the relative
        error, number of PSD fixes; and the ``(X, estimate, views, relative error)`` of the
        full-rank trials with ``q = example_q``.
    """
    rng = as_rng(rng)
    n_trials = as_int(n_trials, "n_trials", minimum=1)
    n_points = as_int(n_points, "n_points", minimum=3)
    noise = as_real(noise, "noise", 0.0)
    rows, examples = [], []
    for q in qs:
        q = as_int(q, "q", minimum=1)
        trials = montecarlo.run(silhouette_trial, n_trials, rng, q, n_points, noise, n_jobs=n_jobs)
        errs = [t["error"] for t in trials if t["estimate"] is not None]
        if q == example_q:
            examples += [(t["X"], t["estimate"], t["views"], t["error"]) for t in trials if t["estimate"] is not None]
        rows.append({"views q": q, "rank (min over trials)": min(t["rank"] for t in trials),
                     "median rel. error": float(np.median(errs)) if errs else np.nan,
                     "90% quantile": float(np.quantile(errs, 0.9)) if errs else np.nan,
                     "PSD fixes": sum(t["psd_fix"] for t in trials)})
    return pd.DataFrame(rows), examples


def condition19_trial(rng: np.random.Generator, Cs: Sequence[np.ndarray]) -> dict:
    """One random ellipse, noise level (log-uniform in [0.01, 3]) and Gaussian perturbation of scalar views.

    Returns whether condition (19) holds, the ratio of its two sides and whether the LS
    estimate is PSD.
    """
    X2 = S.random_ellipsoid(2, rng)
    sd = float(np.exp(rng.uniform(np.log(0.01), np.log(3.0))))
    Ws = [np.array([[rng.normal(0, sd)]]) for _ in Cs]
    holds, lhs, rhs = E.condition19(Cs, Ws, X2)
    # the data are perturbed on purpose, sometimes to a negative squared support
    Xh = E.reconstruct([E.project(X2, C) + W for C, W in zip(Cs, Ws)], Cs, indefinite="ignore")
    return {"holds": holds, "ratio": lhs / rhs, "psd": bool(np.linalg.eigvalsh(Xh)[0] >= 0)}


def condition19_study(Cs: Sequence[np.ndarray], n_draws: int, rng: np.random.Generator) -> pd.DataFrame:
    """``n_draws`` trials of :func:`condition19_trial` through :func:`projtrack.montecarlo.run`."""
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    rng = as_rng(rng)
    Cl = [E.check_orthonormal(C, f"Cs[{k}]", 2) for k, C in enumerate(Cs)]
    if any(C.shape[1] != 1 for C in Cl):
        raise ValueError("Cs must be planar single-direction views (2 x 1)")
    return pd.DataFrame(montecarlo.run(condition19_trial, n_draws, rng, Cs))

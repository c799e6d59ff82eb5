"""Sec. 3 of Marques et al. (2002): the models learned on a closed curve (Figs. 2-3) and two checks.

* Prototypes of a learned curve model relabelled clockwise (:func:`clockwise_order`), the
  reading of a transition matrix as "stay or advance to the next state" (:func:`other_moves`)
  and the sensitivity of that structure to the training speed (:func:`speed_sensitivity`).
* :func:`eq9_table`: the mean square error of replacing a region's points by their projection
  on the local hyperplane, measured on the points, against eq. (9)'s sum of the discarded
  eigenvalues, under the two ways a point belongs to a region (the EM weights of eq. (2), or
  the hard regions of eq. (6)).
* :func:`transition_convergence`: the relative-frequency estimate of a known transition matrix
  from ``N`` simulated transitions (:func:`sample_path`), against the ``N^{-1/2}`` error the
  multinomial variance predicts (:func:`predicted_frobenius`), for the claim "the estimates
  converge almost surely to the true value as the number of points tends to infinity"
  (Sec. 3.2).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_array, as_count, as_int, as_real
from projtrack.dma import DiscreteManifold, estimate_transitions
from projtrack.montecarlo import run
from projtrack.scenes import manifolds as mf

__all__ = ["clockwise_order", "other_moves", "speed_sensitivity", "responsibilities", "eq9_table", "sample_path",
           "stationary", "predicted_frobenius", "transition_convergence",
           "loglog_slopes"]


def clockwise_order(model: DiscreteManifold) -> tuple[np.ndarray, np.ndarray]:
    """Prototypes of a 2-D curve model in clockwise order, starting at a region boundary.

    Returns ``order`` (``order[i]`` is the prototype of clockwise rank ``i``; by angle
    about the origin, decreasing, then rotated so that rank 0 is the first prototype of a
    region) and its inverse ``inv`` (the rank of each prototype), so that
    ``inv[model.quantize(x)]`` gives clockwise state indices. The model must live in the
    plane (ValueError otherwise).
    """
    if not isinstance(model, DiscreteManifold):
        raise TypeError(f"model must be a projtrack.dma.DiscreteManifold, got {type(model).__name__}")
    if model.ambient_dim != 2:
        raise ValueError(f"model must be a curve model in the plane (2-D points), got dimension {model.ambient_dim}")
    angle = np.arctan2(model.prototypes[:, 1], model.prototypes[:, 0])
    order = np.argsort(-angle)  # clockwise
    reg_sorted = model.prototype_region[order]
    changes = np.flatnonzero(reg_sorted != np.roll(reg_sorted, 1))
    first = int(changes[0]) if changes.size else 0  # start at a region boundary
    order = np.roll(order, -first)
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    return order, inv


def other_moves(transitions: object, threshold: float = 0.0) -> int:
    """Number of states with a move other than "stay" or "advance to the next state".

    ``transitions`` is a dense ``(S, S)`` matrix over states in cyclic order; an entry
    counts as a move when it is above ``threshold`` (>= 0). The chain of Fig. 3 has none.
    """
    D = as_array(transitions, "transitions", ndim=2)
    S = D.shape[0]
    if D.shape != (S, S) or S == 0:
        raise ValueError(f"transitions must be a non-empty square matrix, got shape {D.shape}")
    threshold = as_real(threshold, "threshold", 0)
    return int(sum(bool(set(np.flatnonzero(D[i] > threshold).tolist()) - {i, (i + 1) % S}) for i in range(S)))


def speed_sensitivity(
    model: DiscreteManifold,
    inv: object,
    mean_steps: tuple[float, ...],
    *,
    n_runs: int = 20,
    n_steps: int = 400,
    threshold: float = 0.01,
) -> list[dict[str, object]]:
    """The learned chain of Fig. 3 versus the speed of the training motion.

    For each ``mean_step`` (rad per step), ``n_runs`` clockwise trajectories of
    ``n_steps`` on :func:`projtrack.scenes.manifolds.closed_curve` (drawn from
    ``numpy.random.default_rng(int(mean_step * 1000))``) train a transition matrix
    (:func:`projtrack.dma.estimate_transitions`, pseudo-count 1e-3) over the clockwise
    states ``inv`` of :func:`clockwise_order`. Each row gives the largest step, the mean
    step over the median distance between consecutive centroids, the number of states
    with other moves than stay / advance (:func:`other_moves` above ``threshold``) and the
    largest number of successors of a state.
    """
    inv = as_array(inv, "inv", ndim=1, dtype=np.int64)
    S = model.n_prototypes
    if inv.shape != (S,):
        raise ValueError(f"inv must have shape ({S},), got {inv.shape}")
    steps = [as_real(m, "mean_steps[i]", 0, low_open=True) for m in mean_steps]
    if not steps:
        raise ValueError("mean_steps must not be empty")
    n_runs = as_count(n_runs, "n_runs")
    n_steps = as_count(n_steps, "n_steps", minimum=2)
    P = model.prototypes[np.argsort(inv)]
    gap = np.linalg.norm(P - np.roll(P, -1, axis=0), axis=1)
    rows: list[dict[str, object]] = []
    for mean_step in steps:
        rng = np.random.default_rng(int(mean_step * 1000))
        runs = [mf.curve_trajectory(n_steps, rng, mean_step=mean_step) for _ in range(n_runs)]
        step = np.concatenate([np.linalg.norm(np.diff(tr, axis=0), axis=1) for tr in runs])
        D = estimate_transitions([inv[model.quantize(tr)] for tr in runs], S, alpha=1e-3).toarray()
        rows.append({"mean step [rad]": mean_step, "largest step": round(float(step.max()), 3),
                     "mean step / median centroid distance": round(float(step.mean() / np.median(gap)), 2),
                     "rows with other moves": other_moves(D, threshold),
                     "largest successors per row": int((D > threshold).sum(axis=1).max())})
    return rows


def responsibilities(model: DiscreteManifold, X: object) -> np.ndarray:
    """The E-step weights of eq. (2), ``gamma_k(x) = c_k N(x; mu_k, R_k) / sum_i c_i N(x; mu_i, R_i)``,
    for the regions of ``model``, ``(N, M)``."""
    from scipy.special import logsumexp
    from scipy.stats import multivariate_normal

    P = as_array(X, "X", ndim=2, allow_empty=False)
    if P.shape[1] != model.ambient_dim:
        raise ValueError(f"X must have {model.ambient_dim} columns, got {P.shape[1]}")
    logp = np.column_stack([np.log(model.weights[k]) + multivariate_normal(model.means[k], model.covariances[k],
                                                                          allow_singular=True).logpdf(P)
                            for k in range(model.n_regions)])
    return np.exp(logp - logsumexp(logp, axis=1, keepdims=True))


def eq9_table(model: DiscreteManifold, X: object, *, reg_covar: float = 1e-6):
    """Eq. (9) against the points, region by region.

    The residual of a point ``x`` in region ``k`` is ``x - mu - V V^T (x - mu)``, ``V`` the ``m``
    leading eigenvectors of the region's covariance. Columns:

    ``region``, ``points``
        the region and the number of points in it by eq. (6);
    ``E2 of eq. (9)``, ``weighted MSE``
        eq. (9)'s sum of the discarded eigenvalues of the covariance of eqs. (4)-(5) computed
        with the weights of eq. (2) (:func:`responsibilities`), and the weighted mean squared
        residual of all points to the hyperplane of that mean and covariance: eq. (9) says
        they are equal;
    ``E2 of the model``, ``hard-region MSE``
        the same sum for the model's own ``R_k`` (EM stopped at scikit-learn's tolerance, less
        the ``reg_covar`` EM adds to each eigenvalue), and the mean squared residual of the
        points of the region of eq. (6) to the model's hyperplane: the way Fig. 4c uses them.
    """
    import pandas as pd

    P = as_array(X, "X", ndim=2, allow_empty=False)
    gamma = responsibilities(model, P)
    hard = model.assign(P)
    rows = []
    for k in range(model.n_regions):
        m = int(model.dims[k])
        w = gamma[:, k] / gamma[:, k].sum()
        mu = w @ P
        D = P - mu
        R = (D * w[:, None]).T @ D
        lam, V = np.linalg.eigh(R)  # ascending
        Vm = V[:, ::-1][:, :m]
        res_w = ((D - (D @ Vm) @ Vm.T) ** 2).sum(axis=1)
        Dm = P - model.means[k]
        Vk = model.bases[k]
        res_h = ((Dm - (Dm @ Vk) @ Vk.T) ** 2).sum(axis=1)
        rows.append({"region": k, "points": int((hard == k).sum()),
                     "E2 of eq. (9)": float(np.clip(lam[::-1][m:], 0.0, None).sum()),
                     "weighted MSE": float(w @ res_w),
                     "E2 of the model": float(model.eigenvalues[k, m:].sum() - (model.ambient_dim - m) * reg_covar),
                     "hard-region MSE": float(res_h[hard == k].mean()) if (hard == k).any() else np.nan})
    return pd.DataFrame(rows)


def stationary(transitions: object) -> np.ndarray:
    """The stationary distribution of an irreducible row-stochastic matrix (the left eigenvector
    of eigenvalue 1, by a linear solve), ``(S,)``."""
    A = sp.csr_array(transitions, dtype=float).toarray()
    S = A.shape[0]
    if A.shape != (S, S) or S == 0:
        raise ValueError(f"transitions must be a non-empty square matrix, got shape {A.shape}")
    M = A.T - np.eye(S)
    M[-1] = 1.0
    b = np.zeros(S)
    b[-1] = 1.0
    pi = np.linalg.solve(M, b)
    return np.clip(pi, 0.0, None) / np.clip(pi, 0.0, None).sum()


def sample_path(transitions: object, n_steps: int, rng: np.random.Generator, *, start: int | None = None) -> np.ndarray:
    """A state path of ``n_steps`` drawn from a sparse Markov chain (rows = from).

    Same law as :func:`projtrack.scenes.manifolds.sample_markov_chain`, faster for long paths:
    one uniform per step compared with the cumulative probabilities of the current row. The
    start is ``start`` or a draw from :func:`stationary`.
    """
    A = sp.csr_array(transitions, dtype=float)
    A.sort_indices()
    S = A.shape[0]
    n = as_count(n_steps, "n_steps")
    cdf = [np.cumsum(A.data[A.indptr[i]:A.indptr[i + 1]]).tolist() for i in range(S)]
    succ = [A.indices[A.indptr[i]:A.indptr[i + 1]].tolist() for i in range(S)]
    if any(not c for c in cdf):
        raise ValueError("every state needs at least one successor")
    s = int(rng.choice(S, p=stationary(A))) if start is None else as_int(start, "start", minimum=0)
    u = rng.random(n).tolist()  # the last successor takes what rounding leaves above the row's sum
    out = np.empty(n, dtype=np.int64)
    for t in range(n):
        out[t] = s
        c, j = cdf[s], 0
        while j < len(c) - 1 and u[t] > c[j]:
            j += 1
        s = succ[s][j]
    return out


def predicted_frobenius(transitions: object, n_transitions: int) -> float:
    """The Frobenius error the relative-frequency estimate should have after ``n_transitions``.

    A row ``l`` visited ``n_l = N pi_l`` times has multinomial counts, so its estimate has
    variance ``a_lk (1 - a_lk) / n_l`` per entry; summing gives
    ``E |A_hat - A|_F^2 ~ sum_l (1 - sum_k a_lk^2) / (N pi_l)``, i.e. an error ``~ N^{-1/2}``.
    """
    A = sp.csr_array(transitions, dtype=float)
    pi = stationary(A)
    n = as_count(n_transitions, "n_transitions")
    sq = np.asarray(A.multiply(A).sum(axis=1)).ravel()
    return float(np.sqrt(((1.0 - sq) / np.maximum(pi, 1e-300)).sum() / n))


def _convergence_trial(rng: np.random.Generator, A: sp.csr_array, sizes: tuple[int, ...], alpha: float) -> np.ndarray:
    path = sample_path(A, max(sizes) + 1, rng)
    out = []
    dense = A.toarray()
    for n in sizes:
        est = estimate_transitions([path[:n + 1]], A.shape[0], alpha=alpha).toarray()
        seen = np.bincount(path[:n], minlength=A.shape[0]) > 0
        err = (est - dense)[seen]
        out.append([np.abs(err).max(), np.sqrt((err ** 2).sum()), float((~seen).sum())])
    return np.array(out)


def transition_convergence(transitions: object, sizes: tuple[int, ...], n_paths: int, rng: np.random.Generator,
                           *, alpha: float = 1e-9, per_path: bool = False):
    """The relative-frequency estimate of a known chain against the number of transitions.

    ``n_paths`` paths of ``max(sizes)`` transitions from the stationary start (path ``i`` from
    the ``i``-th child of ``rng``, through :func:`projtrack.montecarlo.run`); for each ``N`` in
    ``sizes`` the chain is estimated from the first ``N`` transitions of each path
    (:func:`projtrack.dma.estimate_transitions` with pseudo-count ``alpha``) and compared with
    the truth on the rows visited. Columns: ``transitions N``, ``largest error`` (mean over the
    paths of ``max |a_hat - a|``), ``Frobenius error`` (root mean square over the paths),
    ``predicted`` (:func:`predicted_frobenius`) and ``unvisited states`` (mean over the paths:
    rows the estimate cannot define; they are left out of the errors). With ``per_path=True``
    also returns the Frobenius error of every path at every size, ``(n_paths, len(sizes))``,
    for :func:`loglog_slopes`.
    """
    import pandas as pd

    A = sp.csr_array(transitions, dtype=float)
    sizes = tuple(as_count(n, "sizes[i]") for n in sizes)
    if not sizes:
        raise ValueError("sizes must not be empty")
    n_paths = as_count(n_paths, "n_paths")
    res = np.array(run(_convergence_trial, n_paths, rng, A, sizes, alpha))  # (paths, sizes, 3)
    table = pd.DataFrame({"transitions N": list(sizes), "largest error": res[:, :, 0].mean(axis=0),
                          "Frobenius error": np.sqrt((res[:, :, 1] ** 2).mean(axis=0)),
                          "predicted": [predicted_frobenius(A, n) for n in sizes],
                          "unvisited states": res[:, :, 2].mean(axis=0)})
    return (table, res[:, :, 1]) if per_path else table


def loglog_slopes(sizes: object, errors: object, n_min: int) -> np.ndarray:
    """The least-squares slope of ``log error`` against ``log N`` over the sizes ``N >= n_min``.

    ``sizes`` is a 1-D sequence of ``N``, ``errors`` has shape ``(len(sizes),)`` (one slope) or
    ``(n_paths, len(sizes))`` (one slope per path); at least two sizes must reach ``n_min`` and
    every error used must be > 0 (ValueError otherwise). An error falling as ``N^{-1/2}`` gives
    -0.5; an estimate that stops using data gives 0.
    """
    N = as_array(sizes, "sizes", ndim=1, allow_empty=False)
    E = np.atleast_2d(np.asarray(errors, dtype=float))
    if E.shape[1] != len(N):
        raise ValueError(f"errors must have {len(N)} columns (one per size), got shape {E.shape}")
    big = N >= n_min
    if big.sum() < 2:
        raise ValueError(f"at least two sizes must be >= n_min = {n_min}")
    if (E[:, big] <= 0).any():
        raise ValueError("errors must be > 0")
    slopes = np.polyfit(np.log(N[big]), np.log(E[:, big]).T, 1)[0]
    return slopes if np.ndim(errors) == 2 else slopes[:1]

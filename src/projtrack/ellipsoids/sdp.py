"""Interval-constrained least squares as a semidefinite program (cvxpy with Clarabel)."""

from __future__ import annotations

import warnings

import numpy as np

from projtrack._validation import optional_import

from .checks import _n_from_dim

__all__ = ["sdp_reconstruct"]


def sdp_reconstruct(A: np.ndarray, y: np.ndarray, lower: np.ndarray | None, upper: np.ndarray | None,
                    solver: str = "CLARABEL", info: dict | None = None, **solver_options: object) -> np.ndarray:
    r"""Interval-constrained least squares :math:`\min \|A \operatorname{svec}(X) - y\|^2,\
    L \le X \le U` by cvxpy.

    The modern reference for Sec. 5.2 / eq. (27): a semidefinite program solved by
    Clarabel (interior point, default tolerances ~1e-8). SCS at its default tolerance can
    violate the PSD constraints by ~1e-5 (cvxpy issues #262, #1603); pass
    ``solver="SCS", eps=1e-9`` if SCS is wanted.

    If a dict ``info`` is given, it receives ``"setup_time"`` (seconds spent building the
    cvxpy problem and compiling it for the solver) and ``"solve_time"`` (the solver's own
    time as it reports it), so that timings can be given with and without cvxpy's set-up.

    Needs the optional dependency cvxpy (``pip install "projtrack[sdp]"``).

    Parameters
    ----------
    A : numpy.ndarray, shape (N, n(n+1)/2)
        The stacked operator of eq. (14) (:func:`stacked_operator`).
    y : numpy.ndarray, shape (N,)
        The stacked coordinates of the observations.
    lower, upper : numpy.ndarray, shape (n, n), or None
        Interval bounds (``None``: no bound on that side), as returned by
        :func:`interval_bounds`.
    solver : str, default "CLARABEL"
        A cvxpy solver name.
    info : dict, optional
        Receives the timings (above).
    **solver_options
        Passed to the solver.

    Returns
    -------
    numpy.ndarray, shape (n, n)

    Raises
    ------
    RuntimeError
        If the solver does not report an optimal solution.
    TypeError
        If ``info`` is neither None nor a dict.
    """
    import time

    cp = optional_import("cvxpy", "sdp", "the semidefinite program (method='sdp')")

    if info is not None and not isinstance(info, dict):
        raise TypeError(f"info must be a dict or None, got {type(info).__name__}")
    t_start = time.perf_counter()

    N = A.shape[1]
    n = _n_from_dim(N)
    X = cp.Variable((n, n), symmetric=True)
    i, j = np.triu_indices(n)
    w = np.where(i == j, 1.0, np.sqrt(2.0))
    x = cp.hstack([w[k] * X[i[k], j[k]] for k in range(N)])
    cons = []
    if lower is not None:
        cons.append(X - lower >> 0)
    if upper is not None:
        cons.append(upper - X >> 0)
    prob = cp.Problem(cp.Minimize(cp.sum_squares(A @ x - y)), cons)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            prob.solve(solver=solver, **solver_options)
        except cp.error.SolverError as exc:
            raise RuntimeError(f"the SDP solver {solver} failed: {exc}") from None
    # an inaccurate solution must not pass silently: anything but OPTIMAL is an error
    if prob.status != cp.OPTIMAL:
        raise RuntimeError(f"the SDP solver {solver} returned status {prob.status!r}; tighten or change the solver")
    for w in caught:  # other warnings (none expected) are passed on to the caller
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if info is not None:
        total = time.perf_counter() - t_start
        solve = prob.solver_stats.solve_time if prob.solver_stats is not None else None
        solve = float(solve) if solve is not None else float("nan")
        info["solve_time"] = solve
        info["setup_time"] = total - solve if np.isfinite(solve) else float("nan")
        info["total_time"] = total
    Xv = np.asarray(X.value, float)
    return (Xv + Xv.T) / 2

"""Trivial baselines of Fig. 12 (KVW Sec. 7.2) and the settling criterion judged against them.

The criterion of Fig. 12 compares an estimator's settling step (the first step from which the
relative error stays below a threshold, :func:`projtrack.experiments.ellipsoids.settling_step`)
with that of a baseline. Rule 5 of the book asks that the trivial baselines be run through the
criterion too: :func:`trivial_baselines` gives two of them, a round unit circle ``X_0 = I`` with
no data at all and the one-frame guess ``X_0 = y_0 I`` (only the first observation), both
propagated by the exact model; :func:`versus_baseline` gives the shares the criterion reads, and
:func:`threshold_table` repeats them at other settling thresholds. For Fig. 13,
:func:`best_constant_error` searches the constant ellipse with the smallest error.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from scipy.optimize import minimize

from projtrack import ellipsoids as E
from projtrack._validation import as_array, as_int, as_real
from projtrack.experiments.ellipsoids.selection import settling_step

__all__ = ["one_frame_guess", "trivial_baselines", "versus_baseline", "fig12_readings", "threshold_table",
           "best_constant_error", "fig13_baselines"]


def one_frame_guess(y0: object, A: object, drive: object) -> np.ndarray:
    """The one-frame guess ``X_0 = y_0 I`` propagated by eq. (20) with the exact model.

    ``y_0`` is the first squared support (view ``[1 0]^T``), one value per draw; the guess is the
    circle with that support, the only ellipse one frame can name without a prior on its shape.
    Returns ``(D, K, 2, 2)``: by linearity ``X_k = y_0 G_k + X_k^0`` with ``G_k`` the unit circle
    propagated without drive and ``X_k^0`` the no-data run from ``X_0 = 0``.
    """
    y0 = as_array(y0, "y0", ndim=1)
    A = as_array(A, "A", shape=(2, 2))
    drive = as_array(drive, "drive", ndim=3)
    K = len(drive) + 1
    G = E.simulate(np.eye(2), A, None, K - 1)
    X0 = E.simulate(np.zeros((2, 2)), A, drive, K - 1)
    return y0[:, None, None, None] * G[None] + X0[None]


def trivial_baselines(exp: dict, W: object) -> dict:
    """Relative errors of the trivial baselines of Fig. 12, ``{name: (D, K)}`` (one row per draw).

    ``no data, X_0 = 0`` (the page's first baseline) and ``no data, X_0 = I`` repeat one row for
    every draw; ``one frame, X_0 = y_0 I`` uses the first observation ``ideal[0] + W[:, 0]`` of
    each draw (:func:`one_frame_guess`).
    """
    if not isinstance(exp, dict) or any(k not in exp for k in ("Xs", "A", "Bs", "ideal")):
        raise TypeError("exp must be the dict of projtrack.scenes.ellipses.dynamic_experiment")
    W = as_array(W, "W", ndim=2)
    Xs, A, Bs = exp["Xs"], exp["A"], exp["Bs"]
    if W.shape[1] != len(Xs):
        raise ValueError(f"W must have {len(Xs)} steps, got {W.shape[1]}")
    size = np.linalg.norm(Xs, axis=(1, 2))
    rel = lambda X: np.linalg.norm(X - Xs, axis=(-2, -1)) / size  # noqa: E731
    D = len(W)
    zero = rel(E.simulate(np.zeros((2, 2)), A, Bs, len(Xs) - 1))
    unit = rel(E.simulate(np.eye(2), A, Bs, len(Xs) - 1))
    return {"no data, X_0 = 0": np.tile(zero, (D, 1)), "no data, X_0 = I": np.tile(unit, (D, 1)),
            "one frame, X_0 = y_0 I": rel(one_frame_guess(exp["ideal"][0] + W[:, 0], A, Bs))}


def versus_baseline(err: object, err_base: object, *, step: int = 7, tol: float = 0.1) -> dict:
    """The shares the Fig. 12 criterion reads, for an estimator against a baseline, draw by draw.

    ``err`` is ``(D, K)``; ``err_base`` ``(K,)`` (one baseline for every draw) or ``(D, K)``.
    Returns the median settling step of ``err`` (threshold ``tol``), the shares of draws settling
    strictly earlier and strictly later than the baseline (equal steps count for neither) and
    the share strictly more accurate than the baseline at ``step``.
    """
    err = as_array(err, "err", ndim=2)
    base = np.broadcast_to(as_array(err_base, "err_base"), err.shape)
    step = as_int(step, "step", minimum=0)
    if step >= err.shape[1]:
        raise ValueError(f"step must be below the number of steps {err.shape[1]}, got {step}")
    tol = as_real(tol, "tol", 0.0, low_open=True)
    st, st0 = settling_step(err, tol), settling_step(base, tol)
    return {"median settling step": float(np.median(st)), "strictly earlier": float(np.mean(st < st0)),
            "later": float(np.mean(st > st0)), "better at step 7": float(np.mean(err[:, step] < base[:, step]))}


def fig12_readings(study: dict, trivial: dict, base: str = "no data, X_0 = 0") -> pd.DataFrame:
    """The Fig. 12 criterion for every estimator of a noise study and for the other trivial baselines.

    ``study`` is :func:`projtrack.experiments.ellipsoids.fig12_noise_study`'s output, ``trivial``
    :func:`trivial_baselines`' for the same draws; each row is judged against ``trivial[base]``
    (:func:`versus_baseline`). ``X_0 indefinite`` is the share of draws whose estimate of ``X_0``
    has an eigenvalue below ``-1e-9`` times the largest (0 for the baselines, all PSD).
    """
    from projtrack.experiments.ellipsoids.dynamic import ESTIMATORS  # dynamic imports this module

    if base not in trivial:
        raise ValueError(f"base must be one of {sorted(trivial)}, got {base!r}")
    rows = []
    for key, name in ESTIMATORS:
        lam = np.linalg.eigvalsh(study[f"X_{key}"][:, 0])
        indefinite = lam[:, 0] < -1e-9 * np.maximum(1.0, np.abs(lam).max(axis=1))
        rows.append({"estimate": name, "X_0 indefinite": float(np.mean(indefinite)),
                     **versus_baseline(study[f"err_{key}"], trivial[base])})
    for name, err in trivial.items():
        if name != base:
            rows.append({"estimate": f"{name} (baseline)", "X_0 indefinite": 0.0, **versus_baseline(err, trivial[base])})
    return pd.DataFrame(rows)


def threshold_table(errs: dict, err_base: object, tols: object = (0.05, 0.1, 0.15, 0.2)) -> pd.DataFrame:
    """The share settling strictly earlier than ``err_base``, per estimator of ``errs`` and threshold.

    One row per threshold of ``tols``; one column per name of ``errs`` (each ``(D, K)``).
    """
    rows = []
    for tol in tols:
        tol = as_real(tol, "tol", 0.0, low_open=True)
        rows.append({"threshold": tol, **{name: versus_baseline(e, err_base, tol=tol)["strictly earlier"]
                                          for name, e in errs.items()}})
    return pd.DataFrame(rows)


def best_constant_error(Xs: object, steps: slice = slice(8, None), n_starts: int = 30,
                        rng: np.random.Generator | None = None) -> tuple[float, np.ndarray]:
    """The smallest Fig. 13 error of a constant ellipse: ``min_X median_k ||X - X_k||_F / ||X_k||_F``.

    The median over ``steps`` is not convex in ``X``, so Nelder-Mead is started ``n_starts`` times
    from the temporal mean (the page's stated baseline, first start) scaled and jittered; the
    best value found is an upper bound of the true minimum. ``X`` is parametrised as ``L L^T``
    (``L`` lower triangular), so every candidate is an ellipse. Returns the error and ``X``.
    """
    Xt = as_array(Xs, "Xs", ndim=3)[steps]
    if len(Xt) == 0:
        raise ValueError("steps selects no time step")
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    rng = np.random.default_rng(0) if rng is None else rng
    size = np.linalg.norm(Xt, axis=(1, 2))

    def mat(p):
        L = np.array([[p[0], 0.0], [p[1], p[2]]])
        return L @ L.T

    def cost(p):
        return float(np.median(np.linalg.norm(mat(p) - Xt, axis=(1, 2)) / size))

    L0 = np.linalg.cholesky(Xt.mean(axis=0))
    p0 = np.array([L0[0, 0], L0[1, 0], L0[1, 1]])
    best = None
    for i in range(n_starts):
        start = p0 if i == 0 else p0 * rng.uniform(0.5, 1.3) + rng.normal(0, 0.2, 3)
        res = minimize(cost, start, method="Nelder-Mead", options={"xatol": 1e-9, "fatol": 1e-12, "maxiter": 20000})
        if best is None or res.fun < best.fun:
            best = res
    return float(best.fun), mat(best.x)


#: The trivial baselines of Fig. 13 (columns of :func:`projtrack.experiments.ellipsoids.model_trial`), name on the page.
FIG13_BASELINES = (("no data, A and B errors", "no data, X_0 = 0"), ("no data X_0 = I, A and B errors", "no data, X_0 = I"),
                   ("one frame X_0 = y_0 I, A and B errors", "one frame, X_0 = y_0 I"))


def fig13_baselines(trials: pd.DataFrame, mean_error: float, *, rel: float = 1e-9) -> pd.DataFrame:
    """The trivial baselines of Fig. 13 under the perturbed model, and how often the estimate beats each.

    ``trials`` has one row per trial of :func:`projtrack.experiments.ellipsoids.model_trial` (its
    error dict); ``mean_error`` is the error of the mean ellipse
    (:func:`projtrack.experiments.ellipsoids.constant_baseline_error`). One row per baseline of
    :data:`FIG13_BASELINES`: its median error, the share of trials it beats the mean ellipse,
    and the shares in which the Fig. 13 estimate and the same estimate from noise-free data beat
    it by more than ``rel`` (relative; exact ties count for neither).
    """
    if not isinstance(trials, pd.DataFrame):
        raise TypeError("trials must be a pandas.DataFrame of model_trial error dicts")
    mean_error = as_real(mean_error, "mean_error", 0.0)
    rel = as_real(rel, "rel", 0.0)
    est, clean = trials["A and B errors (Fig. 13)"], trials["same, noise-free data"]
    rows = []
    for key, name in FIG13_BASELINES:
        b = trials[key] * (1 - rel)
        rows.append({"baseline": name, "median error": float(trials[key].median()),
                     "beats the mean ellipse": float(np.mean(trials[key] < mean_error)),
                     "estimate beats it": float(np.mean(est < b)), "noise-free data beat it": float(np.mean(clean < b))})
    return pd.DataFrame(rows)

"""Dynamic ellipse studies of Sec. 7.2 of KVW (Figs. 12-13, the drive sensitivity, the Kalman comparison).

The experiment of :func:`projtrack.scenes.ellipses.dynamic_experiment` is estimated by the
batch least squares of eqs. (24)-(25) over many noise draws (:func:`fig12_noise_study`), under
other periodic drives (:func:`settling_study`), with errors in the model (:func:`imperfect_model_study`)
and recursively (:func:`kalman_vs_batch`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from projtrack import ellipsoids as E
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.scenes import ellipses as S
from projtrack.experiments.ellipsoids.selection import median_draw, settling_step

__all__ = ["relative_errors", "no_data_estimate", "fig12_noise_study", "settling_study", "model_trial",
           "imperfect_model_study", "kalman_vs_batch"]


def _check_experiment(exp: object) -> dict:
    keys = ("Xs", "As", "Bs", "Cs", "ideal")
    if not isinstance(exp, dict) or any(k not in exp for k in keys):
        raise TypeError("exp must be the dict of projtrack.scenes.ellipses.dynamic_experiment "
                        f"(keys {', '.join(keys)})")
    return exp


def relative_errors(X_est: object, Xs: object) -> np.ndarray:
    """``||X_hat_k - X_k||_F / ||X_k||_F`` per time step (last two axes: the matrices)."""
    Xt = as_array(Xs, "Xs", ndim=3)
    Xe = as_array(X_est, "X_est", finite=False)
    if Xe.shape[-3:] != Xt.shape:
        raise ValueError(f"X_est must end with the shape of Xs {Xt.shape}, got {Xe.shape}")
    return np.linalg.norm(Xe - Xt, axis=(-2, -1)) / np.linalg.norm(Xt, axis=(1, 2))


def no_data_estimate(exp: dict) -> np.ndarray:
    """The no-data baseline: eq. (20) propagated from ``X_0 = 0`` with the exact model and drive."""
    exp = _check_experiment(exp)
    return E.simulate(np.zeros((2, 2)), exp["As"], exp["Bs"])


def _noise(rng: np.random.Generator, ideal: np.ndarray, variance: float) -> np.ndarray:
    # one draw of the log-normal perturbations of Sec. 7.2
    return S.lognormal_noise(ideal, variance, rng)


def fig12_noise_study(exp: dict, n_draws: int, rng: np.random.Generator, variance: float = 4.0) -> dict:
    """Batch LS (eqs. 24-25) of the Sec. 7.2 experiment over ``n_draws`` noise draws, and the draw shown.

    The rule of the dynamic page: the draw with the (upper) median settling step (error below
    10% from then on, :func:`projtrack.experiments.ellipsoids.settling_step`), ties broken by the mean
    error. Draws run through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    dict
        ``W`` (n_draws, K) perturbations, ``X`` (n_draws, K, 2, 2) estimates, ``err``
        (n_draws, K) relative errors, ``settle`` (n_draws,) settling steps, ``pick`` the draw shown.
    """
    exp = _check_experiment(exp)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    rng = as_rng(rng)
    variance = as_real(variance, "variance", 0.0, low_open=True)
    W = np.array(montecarlo.run(_noise, n_draws, rng, exp["ideal"], variance))
    X = E.batch_estimate_many(exp["ideal"] + W, exp["Cs"], exp["As"], exp["Bs"])
    err = relative_errors(X, exp["Xs"])
    settle = settling_step(err)
    pick = median_draw(settle, tiebreak=err.mean(axis=1))
    return {"W": W, "X": X, "err": err, "settle": settle, "pick": pick}


def settling_study(drive_raw: object, target: float, n_draws: int, rng: np.random.Generator,
                   A: object = None) -> dict:
    """Settling of the Fig. 12 batch estimate under another drive, rescaled to the same average SNR.

    The drive is scaled so that the average ideal observation of the simulated ellipse equals
    ``target`` (the SNR of our drive); the experiment is then redrawn over ``n_draws`` noise
    draws (variance 4) and compared with the no-data baseline.

    Parameters
    ----------
    drive_raw : array_like (K - 1, 2, 2)
        The drive's shape (symmetric PSD matrices); ``K = len(drive_raw) + 1`` steps.
    target : float
        Average ideal observation to match.
    n_draws : int
    rng : numpy.random.Generator
    A : array_like (2, 2), optional
        The dynamics; default that of :func:`projtrack.scenes.ellipses.dynamic_experiment`.

    Returns
    -------
    dict
        ``scale``, the settling-step median and 10/90% quantiles, the share inside 3..11, the
        no-data settling step, the share settling strictly earlier than no data and the share
        more accurate than no data at step 7.
    """
    drive_raw = as_array(drive_raw, "drive_raw", ndim=3)
    target = as_real(target, "target")
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    rng = as_rng(rng)
    K = len(drive_raw) + 1
    if K < 9:
        raise ValueError(f"drive_raw must have at least 8 steps (the study reads step 7), got {K - 1}")
    base = S.dynamic_experiment(np.random.default_rng(0), n_steps=K, drive=np.zeros((K - 1, 2, 2)))
    A = base["A"] if A is None else as_array(A, "A", shape=(2, 2))
    unit = S.dynamic_experiment(np.random.default_rng(0), n_steps=K, drive=drive_raw)
    a, b = base["ideal"].mean(), unit["ideal"].mean() - base["ideal"].mean()
    drive = drive_raw * (target - a) / b
    ex = S.dynamic_experiment(np.random.default_rng(0), n_steps=K, drive=drive)
    Xt, size = ex["Xs"], np.linalg.norm(ex["Xs"], axis=(1, 2))
    Wd = np.array(montecarlo.run(_noise, n_draws, rng, ex["ideal"], 4.0))
    est = E.batch_estimate_many(Wd + ex["ideal"], ex["Cs"], A, drive)  # batch LS of eq. (24) for every draw
    err = np.linalg.norm(est - Xt[None], axis=(2, 3)) / size
    st = settling_step(err)
    err0 = np.linalg.norm(E.simulate(np.zeros((2, 2)), A, drive, K - 1) - Xt, axis=(1, 2)) / size
    nodata = settling_step(err0)
    return {"scale": (target - a) / b, "median settling": np.median(st), "10%": np.percentile(st, 10),
            "90%": np.percentile(st, 90), "share in 3..11": np.mean((st >= 3) & (st <= 11)),
            "no-data settling": nodata, "share strictly earlier than no data": np.mean(st < nodata),
            "share more accurate at step 7": np.mean(err[:, 7] < err0[7])}


def model_trial(rng: np.random.Generator, exp: dict, sd: float = 0.06) -> tuple[dict, tuple]:
    """One trial of Fig. 13: new observation noise and N(0, sd) errors in ``A`` and in the ``B_k``.

    The errors hit the 4 entries of ``A`` and the 3 independent entries of each ``B_k``. The
    batch LS estimate is computed with the exact model, with either error and with both, and
    the no-data baseline under the perturbed model.

    Returns
    -------
    (errors, (w, dA, dB))
        ``errors`` maps each case to the median relative error over steps 8..K-1, plus the
        relative sizes of the errors of ``A`` and ``B``; then the draws themselves.
    """
    exp = _check_experiment(exp)
    sd = as_real(sd, "sd", 0.0)
    A, Bs, Cs, Xs = exp["A"], exp["Bs"], exp["Cs"], exp["Xs"]
    K = len(Xs)
    mean_abs_A = float(np.mean(np.abs(A)))
    mean_abs_B = float(np.mean(np.abs(E.svec(Bs) * [1, 1 / np.sqrt(2), 1])))

    def batch(y, A_use, B_use):
        return E.batch_estimate_many(np.atleast_2d(y), Cs, A_use, B_use)[0]

    w = S.lognormal_noise(exp["ideal"], 4.0, rng)
    dA = rng.normal(0, sd, size=(2, 2))
    dB = rng.normal(0, sd, size=(K - 1, 3))
    dBm = np.array([[[b[0], b[1]], [b[1], b[2]]] for b in dB])
    y = exp["ideal"] + w
    out = {"exact model": batch(y, A, Bs), "A error only": batch(y, A + dA, Bs),
           "B error only": batch(y, A, Bs + dBm), "A and B errors (Fig. 13)": batch(y, A + dA, Bs + dBm),
           "no data, A and B errors": E.simulate(np.zeros((2, 2)), A + dA, Bs + dBm, K - 1)}
    errs = {k: float(np.median(relative_errors(v, Xs)[8:])) for k, v in out.items()}
    errs["rel. error of A"] = float(np.mean(np.abs(dA))) / mean_abs_A
    errs["rel. error of B"] = float(np.mean(np.abs(dB))) / mean_abs_B
    return errs, (w, dA, dBm)


def imperfect_model_study(exp: dict, n_trials: int, rng: np.random.Generator, sd: float = 0.06) -> list:
    """``n_trials`` trials of :func:`model_trial` through :func:`projtrack.montecarlo.run` (Fig. 13)."""
    exp = _check_experiment(exp)
    n_trials = as_int(n_trials, "n_trials", minimum=1)
    rng = as_rng(rng)
    return montecarlo.run(model_trial, n_trials, rng, exp, sd)


def kalman_vs_batch(exp: dict, R: float = 4.0, P0: float = 1e8) -> dict:
    """Recursive Kalman estimate (filterpy) against the batch LS of eq. (24) on one data set of Sec. 7.2.

    ``exp`` must carry the observations ``Ys``. Returns ``batch``, ``kf`` (the
    :class:`~projtrack.ellipsoids.KalmanResult`), ``no_data``, ``window`` (the growing-window
    batch estimate at each step ``k >= 2``, NaN before) and ``err``, a table of relative errors.
    """
    exp = _check_experiment(exp)
    if "Ys" not in exp:
        raise TypeError("exp must carry the observations Ys")
    R = as_real(R, "R", 0.0, low_open=True)
    P0 = as_real(P0, "P0", 0.0, low_open=True)
    K = len(exp["Ys"])
    Xs = exp["Xs"]
    batch = E.batch_estimate(exp["Ys"], exp["Cs"], exp["As"], exp["Bs"])
    kf = E.kalman_estimate(exp["Ys"], exp["Cs"], exp["As"], exp["Bs"], R=R, P0=P0)
    no_data = E.simulate(np.zeros((2, 2)), exp["As"], exp["Bs"])
    # growing-window batch (data 0..k, evaluated at k): what the filter should equal for a diffuse prior
    window = np.full((K, 2, 2), np.nan)
    for k in range(2, K):
        window[k] = E.batch_estimate(exp["Ys"][:k + 1], exp["Cs"][:k + 1], exp["As"][:k], exp["Bs"][:k])[-1]
    size = np.linalg.norm(Xs, axis=(1, 2))
    err = pd.DataFrame({"k": np.arange(K),
                        "batch (all data)": np.linalg.norm(batch - Xs, axis=(1, 2)) / size,
                        "Kalman filter": np.linalg.norm(kf.X - Xs, axis=(1, 2)) / size,
                        "Kalman, PSD-projected": np.linalg.norm(kf.X_psd - Xs, axis=(1, 2)) / size,
                        "no data (X_0 = 0)": np.linalg.norm(no_data - Xs, axis=(1, 2)) / size})
    return {"batch": batch, "kf": kf, "no_data": no_data, "window": window, "err": err}

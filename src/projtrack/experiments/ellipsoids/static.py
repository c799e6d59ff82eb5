"""Static reconstruction studies of Sec. 7.1 of KVW (Figs. 5-9 and the book's Monte Carlo tables).

The book's static page and its "beyond the paper" page draw the noise of Sec. 7.1, pick the
draw they show by a stated rule (:func:`shown_static_draw`), compare the unconstrained,
PSD-constrained and interval-constrained estimates (:func:`three_estimates`) and measure how
often the least squares estimate leaves the PSD cone (:func:`ls_psd_frequency`,
:func:`non_psd_pool_study`), under several readings of the interval bounds the paper does not
give (:func:`interval_readings`, :func:`interval_bound_study`) and of its noise variance
(:func:`snr_readings`). The random checks of the operators behind them (the rank test of
Sec. 5.1, :func:`hyperplane_ranks`; eqs. 5, 6 and 10 on the representation page,
:func:`ctilde_identity_study`, :func:`projector_form_study`; what the shaping family of eq. 22
reaches, :func:`shaping_family_study`) live here too.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import pandas as pd

from projtrack import ellipsoids as E
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.scenes import ellipses as S
from projtrack.experiments.ellipsoids.selection import median_draw

__all__ = ["demo_interval", "interval_readings", "ideal_supports", "support_perturbation", "ls_estimates", "shown_static_draw",
           "three_estimates", "describe_estimates", "non_psd_pool_study", "constraints_inactive", "interval_bound_study",
           "ls_psd_frequency", "snr_readings", "hyperplane_rank_trial", "hyperplane_ranks",
           "ctilde_identity_trial", "ctilde_identity_study", "projector_form_trial", "projector_form_study",
           "shaping_family_study"]


def _at_pi4(a: float, b: float) -> np.ndarray:
    # the ellipse with semi-axes a, b and its first axis at pi/4, like eq. (26)
    R45 = S.rotation(np.pi / 4)
    return R45 @ np.diag([a, b]) ** 2 @ R45.T


def demo_interval() -> tuple[np.ndarray, np.ndarray]:
    """The interval bounds ``X_lo <= X <= X_hi`` of the book's Figs. 7 and 9 (our choice).

    Ellipses at ``pi/4`` like eq. (26), semi-axes 1.4 and 0.6 (inner) and 4.8 and 2.4 (outer):
    the paper does not give its interval, only that it encodes the orientation and that "the
    outer bounding ellipse leaves the plot area" (Sec. 7.1); this one leaves the book's
    ``[-3.2, 3.2]^2`` panels (its support along either axis is ``sqrt(14.4) = 3.79``).
    Other readings: :func:`interval_readings`.
    """
    return _at_pi4(1.4, 0.6), _at_pi4(4.8, 2.4)


def interval_readings() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Plausible interval bounds for Sec. 7.1, side by side (the paper's are "arbitrary" and not given).

    Returns ``{name: (X_lo, X_hi)}``: ours (:func:`demo_interval`); the same inner bound with an
    outer bound inside the plot area (semi-axes 3.2, 1.6); a looser (1.2, 0.4) and a tighter
    (1.6, 0.8) inner bound; and circles of radii 0.8 and 3.6, the eigenvalue constraint the paper
    names for a prior without orientation. Every pair contains eq. (26).
    """
    return {
        "ours: (1.4, 0.6) in (4.8, 2.4)": demo_interval(),
        "outer inside the plot: (1.4, 0.6) in (3.2, 1.6)": (_at_pi4(1.4, 0.6), _at_pi4(3.2, 1.6)),
        "looser inner: (1.2, 0.4) in (4.8, 2.4)": (_at_pi4(1.2, 0.4), _at_pi4(4.8, 2.4)),
        "tighter inner: (1.6, 0.8) in (4.8, 2.4)": (_at_pi4(1.6, 0.8), _at_pi4(4.8, 2.4)),
        "circles: radius 0.8 in 3.6": (0.64 * np.eye(2), 3.6**2 * np.eye(2)),
    }


def ideal_supports(X: object, Cs: Sequence[np.ndarray]) -> np.ndarray:
    """The ideal scalar observations ``c_k = C_k^T X C_k`` of single-direction views ``C_k`` (n x 1)."""
    Xm = E.check_symmetric(X)
    return np.array([float(C[:, 0] @ Xm @ C[:, 0]) for C in Cs])


def support_perturbation(W: object, ideal: object) -> dict:
    """How far the noisy supports lie from the true ones: ``|sqrt(Y_k) - sqrt(c_k)|``, ``Y_k = c_k + W_k``.

    ``W`` is ``(D, q)`` (one data set a row), ``ideal`` the ``q`` ideal observations ``c_k``
    (:func:`ideal_supports`); negative ``Y_k`` count as 0. Returns per data set the mean and the
    largest of the ``q`` support perturbations (``{"mean": (D,), "max": (D,)}``), lengths on the
    scale of the semi-axes.
    """
    w = as_array(W, "W", ndim=2)
    c = as_array(ideal, "ideal", ndim=1)
    if w.shape[1] != len(c) or np.any(c < 0):
        raise ValueError(f"ideal must hold {w.shape[1]} non-negative values, got {c}")
    d = np.abs(np.sqrt(np.clip(c + w, 0, None)) - np.sqrt(c))
    return {"mean": d.mean(axis=1), "max": d.max(axis=1)}


def ls_estimates(W: object, ideal: object, Cs: Sequence[np.ndarray]) -> np.ndarray:
    """The LS estimates (eq. 15) of the data sets ``ideal + W`` (one row of ``W`` per data set).

    Returns an array ``(D, n, n)``; ``W`` of shape ``(q,)`` is one data set.
    """
    w = as_array(W, "W", ndim=(1, 2))
    c = as_array(ideal, "ideal", ndim=1)
    if w.shape[-1] != c.size:
        raise ValueError(f"W must have {c.size} columns (one per observation), got shape {w.shape}")
    return E.reconstruct_many(c + np.atleast_2d(w), Cs)


def _static_noise(rng: np.random.Generator, variance: float) -> np.ndarray:
    # the perturbations W_k of one data set of Sec. 7.1
    return S.static_observations(variance, rng)[1]


def shown_static_draw(variance: float, rng: np.random.Generator, *, non_psd_only: bool = False,
                      n_draws: int = 1000) -> dict:
    """Draw ``n_draws`` data sets of Sec. 7.1 and pick the one a figure shows.

    The rule of the book: the draw with the (upper) median LS error (:func:`projtrack.experiments.ellipsoids.median_draw`), among all draws or, with ``non_psd_only``, among those whose LS
    estimate is not PSD (Fig. 9). The draws run through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    dict
        ``W`` (n_draws, q) perturbations, ``X_ls`` their LS estimates, ``err`` the Frobenius
        errors against eq. (26), ``not_psd`` (bool per draw), ``snr`` the realized SNRs,
        ``pool`` (indices eligible), ``pick`` (the index shown) and ``data`` the shown data set
        ``(ideal, W, Ys, Cs)`` as :func:`projtrack.scenes.ellipses.static_observations` gives it.
    """
    variance = as_real(variance, "variance", 0.0, low_open=True)
    rng = as_rng(rng)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    Cs = S.paper_projections()
    ideal = ideal_supports(S.X26, Cs)
    W = np.array(montecarlo.run(_static_noise, n_draws, rng, variance))
    X_ls = ls_estimates(W, ideal, Cs)
    err = np.linalg.norm(X_ls - S.X26, axis=(1, 2))
    not_psd = np.linalg.eigvalsh(X_ls)[:, 0] < 0
    pool = np.nonzero(not_psd)[0] if non_psd_only else np.arange(n_draws)
    pick = median_draw(err, pool=pool)
    data = (ideal, W[pick], [np.array([[v]]) for v in ideal + W[pick]], Cs)
    return {"W": W, "X_ls": X_ls, "err": err, "not_psd": not_psd, "snr": S.realized_snr_static(ideal, W),
            "pool": pool, "pick": pick, "data": data}


def three_estimates(Ys: Sequence[object], Cs: Sequence[np.ndarray], X_lo: object,
                    X_hi: object) -> tuple[dict, tuple, float]:
    """The LS, PSD-constrained and interval-constrained estimates of one data set (Figs. 7 and 9).

    The constrained ones by Algorithm 1 (:func:`projtrack.ellipsoids.halfspace_reconstruct`),
    checked against the SDP of :func:`projtrack.ellipsoids.reconstruct` (``method="sdp"``).

    Returns
    -------
    (estimates, (res_psd, res_interval), agreement)
        ``estimates`` maps ``"LS"``, ``"PSD"``, ``"interval"`` to matrices; the two
        :class:`~projtrack.ellipsoids.HalfspaceResult`; the largest Frobenius distance between
        Algorithm 1 and the SDP.
    """
    out = {"LS": E.reconstruct(Ys, Cs, indefinite="ignore")}  # noisy data: an indefinite LS estimate is the point
    res_psd = E.halfspace_reconstruct(Ys, Cs, lower=0)
    res_int = E.halfspace_reconstruct(Ys, Cs, lower=X_lo, upper=X_hi)
    out["PSD"], out["interval"] = res_psd.X, res_int.X
    sdp_psd = E.reconstruct(Ys, Cs, lower=0, method="sdp")
    sdp_int = E.reconstruct(Ys, Cs, lower=X_lo, upper=X_hi, method="sdp")
    agree = max(np.linalg.norm(res_psd.X - sdp_psd), np.linalg.norm(res_int.X - sdp_int))
    return out, (res_psd, res_int), float(agree)


def describe_estimates(estimates: dict, X: object) -> pd.DataFrame:
    """One row per estimate: eigenvalues, Frobenius error against the true ``X`` and PSD-ness (planar)."""
    if not isinstance(estimates, dict) or not estimates:
        raise TypeError("estimates must be a non-empty dict of name -> 2 x 2 matrix")
    Xm = E.check_symmetric(X, "X", 2)
    rows = []
    for k, Xe in estimates.items():
        lam = np.linalg.eigvalsh(Xe)
        rows.append({"estimate": k, "lambda_min": lam[0], "lambda_max": lam[1],
                     "||X_hat - X||_F": np.linalg.norm(Xe - Xm), "PSD": bool(E.is_psd(Xe))})
    return pd.DataFrame(rows)


def non_psd_pool_study(W: object, pool: object, X_lo: object, X_hi: object) -> dict:
    """Score the three estimates on every draw of ``pool`` (Fig. 9: the draws with a non-PSD LS estimate).

    Parameters
    ----------
    W : array_like (D, 5)
        Perturbations of the data sets of Sec. 7.1 (eq. 26, the five paper directions).
    pool : array_like of int
        The draws to score.
    X_lo, X_hi : array_like (2, 2)
        The interval bounds.

    Returns
    -------
    dict
        ``closest`` (name of the estimate closest to the truth, per draw), ``singular``
        (PSD estimate singular), ``lo_beats`` (the inner bound alone closer than LS and PSD),
        ``int_beats_lo`` (interval estimate strictly closer than ``X_lo``), ``int_is_lo``
        (interval estimate equal to ``X_lo`` within 1e-6), each a list over the pool, and
        ``e_lo`` the error of ``X_lo`` itself.
    """
    Cs = S.paper_projections()
    ideal = ideal_supports(S.X26, Cs)
    w = as_array(W, "W", shape=(None, len(Cs)))
    idx = as_array(pool, "pool", ndim=1, dtype=int)
    if np.any(idx < 0) or np.any(idx >= len(w)):
        raise ValueError(f"pool indices must lie in 0..{len(w) - 1}")
    X = S.X26
    out = {"closest": [], "singular": [], "lo_beats": [], "int_beats_lo": [], "int_is_lo": [], "err_interval": []}
    e_lo = float(np.linalg.norm(X_lo - X))  # the prior alone: no data
    for i in idx:
        Ys_i = [np.array([[v]]) for v in ideal + w[i]]
        cand = {"LS": ls_estimates(w[i], ideal, Cs)[0], "PSD": E.halfspace_reconstruct(Ys_i, Cs, lower=0).X,
                "interval": E.halfspace_reconstruct(Ys_i, Cs, lower=X_lo, upper=X_hi).X}
        e = {k: float(np.linalg.norm(v - X)) for k, v in cand.items()}
        out["closest"].append(min(e, key=e.get))
        out["lo_beats"].append(e_lo < min(e["LS"], e["PSD"]))
        out["int_beats_lo"].append(e["interval"] < e_lo - 1e-6)
        out["int_is_lo"].append(np.linalg.norm(cand["interval"] - X_lo) < 1e-6)
        out["err_interval"].append(e["interval"])
        out["singular"].append(abs(np.linalg.eigvalsh(cand["PSD"])[0]) <= 1e-8 * np.linalg.norm(cand["PSD"]))
    out["e_lo"] = e_lo
    return out


def constraints_inactive(X_ls: object, X_lo: object, X_hi: object) -> np.ndarray:
    """Whether the PSD and interval constraints are inactive for each LS estimate of ``X_ls`` (D, n, n):
    the estimate is PSD and ``X_lo <= X_ls <= X_hi``, so the constrained estimates equal it."""
    Xl = as_array(X_ls, "X_ls", ndim=3)
    return ((np.linalg.eigvalsh(Xl)[:, 0] >= 0) & (np.linalg.eigvalsh(Xl - X_lo)[:, 0] >= 0)
            & (np.linalg.eigvalsh(X_hi - Xl)[:, 0] >= 0))


def _lognormal_block(rng: np.random.Generator, ideal: np.ndarray, variance: float, size: int) -> np.ndarray:
    # a block of `size` data sets drawn with one child generator (vectorized)
    return S.lognormal_noise(np.broadcast_to(ideal, (size, len(ideal))), variance, rng)


def _blocks(gen, n_blocks: int, block: int, variance: float, seed: int, ideal: np.ndarray) -> np.ndarray:
    return np.concatenate(montecarlo.run(gen, n_blocks, np.random.default_rng(seed), ideal, variance, block))


def _check_study(levels: object, n_blocks: int, block: int) -> list[tuple[float, int]]:
    as_int(n_blocks, "n_blocks", minimum=1)
    as_int(block, "block", minimum=1)
    try:
        pairs = [(as_real(v, "variance", 0.0, low_open=True), as_int(s, "seed", minimum=0)) for v, s in levels]
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"levels must be (variance, seed) pairs: {exc}") from None
    if not pairs:
        raise ValueError("levels must contain at least one (variance, seed) pair")
    return pairs


def ls_psd_frequency(levels: Sequence[tuple[float, int]], n_blocks: int, block: int) -> pd.DataFrame:
    """How often the LS estimate of Sec. 7.1 is not PSD, leaves our interval, or is as extreme as the paper's.

    ``n_blocks`` blocks of ``block`` data sets per noise level, each block drawn by one child
    generator of :func:`projtrack.montecarlo.run` seeded by the level's seed.

    Parameters
    ----------
    levels : sequence of (variance, seed)
        Noise variances of the log-normal perturbation and the seed of each level.
    n_blocks, block : int
        Number of blocks and data sets per block.

    Returns
    -------
    pandas.DataFrame
        One row per level: shares of non-PSD and out-of-interval estimates, median eigenvalues,
        shares of eigenvalues as extreme as the paper's (-2.5 and 19.2), of both within a factor 2 of
        them (``lambda_min`` in [-5, -1.25], ``lambda_max`` in [9.6, 38.4]) and realized-SNR quantiles.
    """
    pairs = _check_study(levels, n_blocks, block)
    Cs = S.paper_projections()
    ideal = ideal_supports(S.X26, Cs)
    X_lo, X_hi = demo_interval()
    rows = []
    for var, seed in pairs:
        W = _blocks(_lognormal_block, n_blocks, block, var, seed, ideal)
        Xh = ls_estimates(W, ideal, Cs)
        lam = np.linalg.eigvalsh(Xh)
        lo = np.linalg.eigvalsh(Xh - X_lo)[:, 0]
        hi = np.linalg.eigvalsh(X_hi - Xh)[:, 0]
        rs = S.realized_snr_static(ideal, W)
        rows.append({"noise variance": var, "P(LS not PSD)": np.mean(lam[:, 0] < 0),
                     "P(LS outside interval)": np.mean((lo < 0) | (hi < 0)),
                     "median lambda_min": np.median(lam[:, 0]), "median lambda_max": np.median(lam[:, 1]),
                     "P(lambda_min <= -2.5)": np.mean(lam[:, 0] <= -2.5),
                     "P(lambda_max >= 19.2)": np.mean(lam[:, 1] >= 19.2),
                     "P(both)": np.mean((lam[:, 0] <= -2.5) & (lam[:, 1] >= 19.2)),
                     "P(both within a factor 2)": np.mean((lam[:, 0] <= -1.25) & (lam[:, 0] >= -5.0)
                                                          & (lam[:, 1] >= 9.6) & (lam[:, 1] <= 38.4)),
                     "realized SNR 10%": np.percentile(rs, 10), "realized SNR median": np.median(rs),
                     "realized SNR 90%": np.percentile(rs, 90)})
    return pd.DataFrame(rows)


def snr_readings(variances: Sequence[float] = (0.3, 9.0)) -> pd.DataFrame:
    """The SNR of Sec. 7.1 under two readings of the stated noise variance (closed forms).

    The paper defines ``SNR = sqrt(sum c_k^2) / (sigma sqrt(n))`` with ``sigma`` "the standard
    deviation of applied noise" and states variances 0.3 and 9 for SNRs "about 5" and "about 1".

    * *variance of the noise W* (ours, :func:`projtrack.scenes.ellipses.lognormal_noise`):
      ``sigma = sqrt(variance)``;
    * *variance of log Y* (``Y_k = c_k exp(Z_k)``, ``Z_k ~ N(-s^2/2, s^2)``, ``s^2`` the stated
      value): ``W_k`` then has standard deviation ``c_k sqrt(exp(s^2) - 1)``; with ``sigma``
      their root-mean-square the SNR is ``1 / sqrt(exp(s^2) - 1)``.

    Returns one row per reading and variance: ``sigma`` and the SNR.
    """
    Cs = S.paper_projections()
    ideal = ideal_supports(S.X26, Cs)
    rows = []
    for v in variances:
        v = as_real(v, "variance", 0.0, low_open=True)
        sd_log = ideal * np.sqrt(np.expm1(v))
        for reading, sigma in (("variance of the noise W (ours)", np.sqrt(v)),
                               ("variance of log Y", float(np.sqrt(np.mean(sd_log**2))))):
            rows.append({"reading": reading, "stated variance": v, "sigma": sigma,
                         "SNR": S.snr_static(ideal, sigma)})
    return pd.DataFrame(rows)


def interval_bound_study(W_small: object, W_large: object, pool: object,
                         readings: dict[str, tuple[np.ndarray, np.ndarray]]) -> pd.DataFrame:
    """The claims of Figs. 7 and 9 under several interval bounds (:func:`interval_readings`).

    Parameters
    ----------
    W_small : array_like (D, 5)
        Perturbations of the small-perturbation draws (variance 0.3).
    W_large : array_like (D', 5)
        Perturbations of the large-perturbation draws (variance 9).
    pool : array_like of int
        The draws of ``W_large`` whose LS estimate is not PSD.
    readings : dict
        ``{name: (X_lo, X_hi)}``.

    Returns
    -------
    pandas.DataFrame
        One row per reading: ``F7: inactive`` (share of the small draws whose LS estimate is PSD
        and inside the interval, so that both constraints are inactive), and over the pool: the
        share where the interval estimate is the closest of the three to the truth, where the
        inner bound alone is closer than LS and PSD, where the interval estimate is strictly
        closer than the inner bound (by more than 1e-6), and where it is the inner bound itself.
    """
    Cs = S.paper_projections()
    ideal = ideal_supports(S.X26, Cs)
    ws = as_array(W_small, "W_small", shape=(None, len(Cs)))
    X_small = ls_estimates(ws, ideal, Cs)
    rows = []
    for name, (lo, hi) in readings.items():
        inactive = constraints_inactive(X_small, lo, hi)
        st = non_psd_pool_study(W_large, pool, lo, hi)
        rows.append({"interval (semi-axes)": name, "F7: inactive": float(np.mean(inactive)),
                     "F9: interval closest": float(np.mean(np.array(st["closest"]) == "interval")),
                     "F9: X_lo alone closer than LS, PSD": float(np.mean(st["lo_beats"])),
                     "F9: interval beats X_lo": float(np.mean(st["int_beats_lo"])),
                     "F9: interval = X_lo": float(np.mean(st["int_is_lo"]))})
    return pd.DataFrame(rows)


def _as_sizes(values: Sequence[int], name: str, minimum: int) -> list[int]:
    # a non-empty list of ints >= minimum (the dimensions or view counts of a rank table)
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise TypeError(f"{name} must be a sequence of ints")
    out = [as_int(v, name, minimum=minimum) for v in values]
    if not out:
        raise ValueError(f"{name} must not be empty")
    return out


def hyperplane_rank_trial(rng: np.random.Generator, ns: Sequence[int], qs: Sequence[int]) -> dict:
    """One draw of :func:`hyperplane_ranks`: for every ``(n, q)``, ``q`` random hyperplane views of R^n.

    Returns ``{(n, q): rank of the stacked operator (eq. 14)}``.
    """
    return {(n, q): int(np.linalg.matrix_rank(E.stacked_operator([S.random_projection(n, n - 1, rng)
                                                                   for _ in range(q)])))
            for n in ns for q in qs}


def hyperplane_ranks(rng: np.random.Generator, ns: Sequence[int] = range(2, 7), qs: Sequence[int] = range(1, 5),
                     n_draws: int = 20, n_jobs: int | None = None) -> pd.DataFrame:
    """Rank of the stacked operator (eq. 14) for ``q`` random hyperplane views (m = n - 1), Sec. 5.1.

    The minimum over ``n_draws`` draws of :func:`hyperplane_rank_trial` per ``(n, q)``, run
    through :func:`projtrack.montecarlo.run` (``n_jobs`` passed on; the table does not depend on it).
    """
    rng = as_rng(rng)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    ns = _as_sizes(ns, "n", 2)
    qs = _as_sizes(qs, "q", 1)
    trials = montecarlo.run(hyperplane_rank_trial, n_draws, rng, ns, qs, n_jobs=n_jobs)
    rows = []
    for n in ns:
        row = {"n": n, "n(n+1)/2": n * (n + 1) // 2}
        for q in qs:
            row[f"q={q}"] = min(t[(n, q)] for t in trials)
        rows.append(row)
    return pd.DataFrame(rows)


def ctilde_identity_trial(rng: np.random.Generator, n_max: int = 8) -> tuple[float, float]:
    """One random check of eqs. (6) and (10): ``n`` in 2..n_max, ``m`` in 1..n, a random view and symmetric X.

    Returns the largest entry of ``|C~ - P_m^T (C^T kron C^T) P_n|`` and of
    ``|C~ svec(X) - svec(C^T X C)|``.
    """
    n = int(rng.integers(2, n_max + 1))
    m = int(rng.integers(1, n + 1))
    Cm = S.random_projection(n, m, rng)
    Xr = rng.normal(size=(n, n))
    Xr = (Xr + Xr.T) / 2
    Ct = E.ctilde(Cm)
    kron = E.svec_basis_matrix(m).T @ E.kron_operator(Cm) @ E.svec_basis_matrix(n)
    return float(np.abs(Ct - kron).max()), float(np.abs(Ct @ E.svec(Xr) - E.svec(E.project(Xr, Cm))).max())


def ctilde_identity_study(n_checks: int, rng: np.random.Generator, n_max: int = 8,
                          n_jobs: int | None = None) -> dict:
    """``n_checks`` trials of :func:`ctilde_identity_trial` through :func:`projtrack.montecarlo.run`.

    Returns ``count`` and the largest errors ``err_kron`` (C~ against the restricted Kronecker
    form of eq. 6) and ``err_proj`` (C~ svec(X) against svec(C^T X C), eq. 10) over the checks.
    """
    n_checks = as_int(n_checks, "n_checks", minimum=1)
    rng = as_rng(rng)
    n_max = as_int(n_max, "n_max", minimum=2)
    errs = np.array(montecarlo.run(ctilde_identity_trial, n_checks, rng, n_max, n_jobs=n_jobs))
    return {"count": len(errs), "err_kron": float(errs[:, 0].max()), "err_proj": float(errs[:, 1].max())}


def projector_form_trial(rng: np.random.Generator, n_max: int = 6) -> dict:
    """One random check of the projector form (5) of Sec. 3 and the remark closing Sec. 4.

    Draws ``n`` in 2..n_max, ``m`` in 1..n-1, a view ``C`` (n x m, orthonormal columns), an
    orthogonal ``Q`` (m x m) and a symmetric ``X``. With ``Cbar = C C^T``:

    Returns
    -------
    dict
        ``idempotent`` ``max|Cbar^2 - Cbar|``, ``symmetric`` ``max|Cbar - Cbar^T|``,
        ``basis`` ``max|Cbar X Cbar - Cbar' X Cbar'|`` with ``Cbar' = (CQ)(CQ)^T``,
        ``recover`` ``max|C^T (Cbar X Cbar) C - C^T X C|`` (eq. 4 from eq. 5), and for the
        matrix ``P`` of ``X -> Cbar X Cbar`` in the standard symmetric basis (eq. 9):
        ``P_symmetric`` ``max|P - P^T|``, ``P_idempotent`` ``max|P^2 - P|``, ``rank`` its rank
        and ``expected_rank`` ``m(m+1)/2``.
    """
    n = int(rng.integers(2, n_max + 1))
    m = int(rng.integers(1, n))
    Cm = S.random_projection(n, m, rng)
    Q = S.random_projection(m, m, rng)
    Xr = rng.normal(size=(n, n))
    Xr = (Xr + Xr.T) / 2
    Cb, Cb2 = Cm @ Cm.T, (Cm @ Q) @ (Cm @ Q).T
    P = E.congruence_operator(Cb)  # the matrix of X -> Cbar^T X Cbar = Cbar X Cbar (eq. 21's operator)
    return {"idempotent": float(np.abs(Cb @ Cb - Cb).max()), "symmetric": float(np.abs(Cb - Cb.T).max()),
            "basis": float(np.abs(Cb @ Xr @ Cb - Cb2 @ Xr @ Cb2).max()),
            "recover": float(np.abs(Cm.T @ (Cb @ Xr @ Cb) @ Cm - E.project(Xr, Cm)).max()),
            "P_symmetric": float(np.abs(P - P.T).max()), "P_idempotent": float(np.abs(P @ P - P).max()),
            "rank": int(np.linalg.matrix_rank(P)), "expected_rank": m * (m + 1) // 2}


def projector_form_study(n_checks: int, rng: np.random.Generator, n_max: int = 6,
                         n_jobs: int | None = None) -> tuple[pd.DataFrame, int]:
    """``n_checks`` trials of :func:`projector_form_trial` through :func:`projtrack.montecarlo.run`.

    Returns
    -------
    (table, n_rank)
        One row per identity of eq. (5): what is checked and its largest deviation over the
        trials; and the number of trials in which the matrix of ``X -> Cbar X Cbar`` has rank
        ``m(m+1)/2`` (an orthogonal projector onto the symmetric matrices of the subspace).
    """
    n_checks = as_int(n_checks, "n_checks", minimum=1)
    rng = as_rng(rng)
    n_max = as_int(n_max, "n_max", minimum=2)
    t = pd.DataFrame(montecarlo.run(projector_form_trial, n_checks, rng, n_max, n_jobs=n_jobs))
    checks = [("Cbar^2 = Cbar", "idempotent"), ("Cbar^T = Cbar", "symmetric"),
              ("Cbar X Cbar the same for C and CQ", "basis"), ("C^T (Cbar X Cbar) C = C^T X C", "recover"),
              ("C~ of eq. (5) symmetric", "P_symmetric"), ("C~ of eq. (5) idempotent", "P_idempotent")]
    rows = [{"check": name, "max deviation": float(t[key].max())} for name, key in checks]
    return pd.DataFrame(rows), int((t["rank"] == t["expected_rank"]).sum())


def _family(phi: float, alpha: float, tau: float, psi: float) -> np.ndarray:
    # the map of eq. (22): rotate by psi, magnify by tau, stretch by (alpha, 1/alpha), rotate by phi
    return S.rotation(phi) @ np.diag([alpha, 1 / alpha]) @ (tau * np.eye(2)) @ S.rotation(psi)


def _family_parameters(L: np.ndarray) -> tuple[float, float, float, float]:
    # (phi, alpha, tau, psi) of a 2 x 2 matrix with det > 0, from its SVD with both factors rotations
    U, sv, Vt = np.linalg.svd(L)
    if np.linalg.det(U) < 0:  # det L > 0: then det V < 0 too; flipping both keeps U diag(sv) V^T
        U, Vt = U * [1, -1], Vt * [[1], [-1]]
    return (float(np.arctan2(U[1, 0], U[0, 0])), float(np.sqrt(sv[0] / sv[1])), float(np.sqrt(sv[0] * sv[1])),
            float(np.arctan2(Vt[1, 0], Vt[0, 0])))


def shaping_family_study(n_draws: int, rng: np.random.Generator) -> tuple[pd.DataFrame, dict]:
    """What the family of eq. (22) reaches: "any linear transformation of the plane" (Sec. 6.1)?

    Every member has determinant ``tau^2 >= 0``. For ``n_draws`` Gaussian 2 x 2 matrices ``L``
    (and a random ellipse ``X`` each, :func:`projtrack.scenes.ellipses.random_ellipsoid`):
    those with ``det L > 0`` are decomposed by the SVD into ``(phi, alpha, tau, psi)`` and rebuilt;
    those with ``det L < 0`` (a reflection composed with a map of the family) cannot be, but their
    effect ``L X L^T`` (eq. 3) on the given ellipse is that of ``L S``, ``S`` the ellipse's own mirror
    symmetry, which has ``det > 0``; a rank-one map sends ``X`` to a segment, which no member with
    ``tau != 0`` does. Also checks that ``A`` of eq. (23) (:func:`projtrack.ellipsoids.shaping_matrix`)
    is the transpose of the map of eq. (22), so ``A^T X A = L X L^T``.

    Returns
    -------
    (table, checks)
        ``table``: one row per class of maps (share of the draws, whether the map itself and its
        effect on an ellipse are reached); ``checks``: the largest deviations ``rebuild``
        (``|L - L(phi, alpha, tau, psi)|``, det > 0), ``mirror`` (``|(LS) X (LS)^T - L X L^T|`` with
        ``LS`` rebuilt from its parameters, det < 0), ``transpose`` (``|A^T X A - L X L^T|``),
        ``orthogonal`` (``|L - U diag(alpha, 1/alpha) tau V^T|`` for every draw, the paper's n-D reading
        with ``U``, ``V`` orthogonal, reflections allowed), ``limits`` (the distance from a rank-one map
        to the member with its small singular value set to ``1e-2, 1e-4, 1e-6``) and the counts
        ``n_pos``, ``n_neg``.
    """
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    rng = as_rng(rng)
    dev = {"rebuild": 0.0, "mirror": 0.0, "transpose": 0.0, "orthogonal": 0.0}
    n_pos = 0
    for _ in range(n_draws):
        L = rng.normal(size=(2, 2))
        X = S.random_ellipsoid(2, rng)
        U, sv, Vt = np.linalg.svd(L)  # n-D reading: the rotations become orthogonal matrices
        Lo = U @ np.diag([np.sqrt(sv[0] / sv[1]), np.sqrt(sv[1] / sv[0])]) @ (np.sqrt(sv[0] * sv[1]) * Vt)
        dev["orthogonal"] = max(dev["orthogonal"], float(np.abs(Lo - L).max()))
        if np.linalg.det(L) > 0:
            n_pos += 1
            par = _family_parameters(L)
            dev["rebuild"] = max(dev["rebuild"], float(np.abs(_family(*par) - L).max()))
        else:
            V = np.linalg.eigh(X)[1]
            M = L @ (V @ np.diag([1.0, -1.0]) @ V.T)  # L composed with the ellipse's mirror symmetry
            par = _family_parameters(M)
            Mr = _family(*par)
            dev["mirror"] = max(dev["mirror"], float(np.abs(Mr @ X @ Mr.T - L @ X @ L.T).max()))
        A = E.shaping_matrix(par[2], par[1], par[3], par[0])  # eq. (23): (tau, alpha, psi, phi)
        Lr = _family(*par)
        dev["transpose"] = max(dev["transpose"], float(np.abs(A.T @ X @ A - Lr @ X @ Lr.T).max()))
    # a rank-one map u v^T is the limit of the members U diag(1, eps) V^T (det > 0 after a sign flip)
    u, v = S.rotation(0.3), S.rotation(-1.1)
    L1 = u @ np.diag([2.0, 0.0]) @ v
    limits = [float(np.abs(_family(*_family_parameters(u @ np.diag([2.0, eps]) @ v)) - L1).max())
              for eps in (1e-2, 1e-4, 1e-6)]
    table = pd.DataFrame([
        {"maps L": "det L > 0", "share of the draws": n_pos / n_draws, "L reached, as written": "yes",
         "L reached, n-D reading": "yes", "L X L^T reached": "yes"},
        {"maps L": "det L < 0 (with a reflection)", "share of the draws": 1 - n_pos / n_draws,
         "L reached, as written": "no: det = tau^2 >= 0", "L reached, n-D reading": "yes: orthogonal U, V",
         "L X L^T reached": "yes: L S, S the ellipse's mirror"},
        {"maps L": "rank one", "share of the draws": 0.0, "L reached, as written": "as limits only",
         "L reached, n-D reading": "as limits only", "L X L^T reached": "as limits only"},
    ])
    return table, {**dev, "limits": limits, "n_pos": n_pos, "n_neg": n_draws - n_pos}

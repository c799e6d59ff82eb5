"""Beta computed by other routes, as checks of the package's methods (JPDA chapter).

:func:`beta_literature_rule` enumerates the feasibility matrices with the weights of
Sec. II.C's text (``1 - P_D`` per false measurement); for a common ``P_D`` it equals the
MVM's beta. :func:`beta_by_permanents` writes beta as ratios of matrix permanents (exact
JPDA is a permanent computation), and :func:`permanent_by_interpolation` recovers the
permanent of a 0-1 matrix from exact JPDA normalizers at several clutter densities (why no
exact JPDA can run in polynomial time unless FP = #P). :func:`clutter_sensitivity`
tabulates ``beta_0`` over clutter densities. :func:`event_orders` lists the feasible events
of a validation matrix in four natural orders (which one Fig. 2 uses).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_probability, as_real
from projtrack.jpda import beta, feasibility_matrices, iter_feasibility_matrices, modified_validation_matrix

from .sweeps import beta_sweep_reachable

__all__ = ["beta_literature_rule", "permanent_rect", "beta_by_permanents", "permanent_by_interpolation",
           "clutter_sensitivity", "event_orders"]


def _mvm(mvm: object) -> np.ndarray:
    w = as_array(mvm, "mvm", ndim=2)
    if w.shape[0] < 1 or w.shape[1] < 1:
        raise ValueError(f"mvm must have a row 0 and at least one target, got shape {w.shape}")
    return w


def beta_literature_rule(mvm: object, p_detect: float) -> np.ndarray:
    """Beta from the weights of Sec. II.C's text, by enumerating the feasibility matrices.

    Each feasible event weighs the product over measurements of the MVM entry of its
    target, or ``1 - p_detect`` when it is a false measurement (the MVM instead charges
    ``1 - P_D`` to each undetected target). Columns are normalized to sum to 1. Cost:
    the number of feasible events; for small problems only.
    """
    w_c = _mvm(mvm)
    p_common = as_probability(p_detect, "p_detect", low_open=True)
    m, T = w_c.shape[0] - 1, w_c.shape[1]
    lit = np.zeros_like(w_c)
    for om in feasibility_matrices(w_c):
        j_of_t = {int(np.flatnonzero(om[:, t + 1])[0]) + 1: t for t in range(T) if om[:, t + 1].any()}
        weight = np.prod([w_c[j, j_of_t[j]] if j in j_of_t else 1 - p_common
                          for j in range(1, m + 1)])
        for t in range(T):
            lit[next((j for j, tt in j_of_t.items() if tt == t), 0), t] += weight
    lit /= lit.sum(axis=0)
    return lit


def permanent_rect(M: object) -> float:
    """Permanent of an ``m x n`` matrix (``m <= n``) by brute force over injective row -> column maps."""
    M = as_array(M, "M", ndim=2)
    m_, n_ = M.shape
    if m_ > n_:
        raise ValueError(f"M must have no more rows than columns, got shape {M.shape}")
    return sum(np.prod(M[np.arange(m_), list(cols)])
               for cols in itertools.permutations(range(n_), m_))


def beta_by_permanents(mvm: object) -> np.ndarray:
    """Beta as ratios of permanents: ``beta_jt = M_jt per(M without row j, column t) / per(M)``.

    ``M = [w[1:] / w[0], I_m]`` (row 0 of the MVM must be positive): the last ``m``
    columns let a measurement be clutter. ``beta_0t = 1 - sum_j beta_jt``. Brute force,
    for ``m, T <= 4`` or so.
    """
    w = _mvm(mvm)
    if np.any(w[0] <= 0):
        raise ValueError("row 0 of mvm (1 - P_D) must be positive for the permanent form")
    m_, T_ = w.shape[0] - 1, w.shape[1]
    M = np.hstack([w[1:] / w[0][None, :], np.eye(m_)])
    per = permanent_rect(M)
    b_perm = np.zeros_like(w)
    for j in range(m_):
        for t in range(T_):
            minor = np.delete(np.delete(M, j, axis=0), t, axis=1)
            b_perm[j + 1, t] = M[j, t] * permanent_rect(minor) / per
    b_perm[0] = 1 - b_perm[1:].sum(axis=0)
    return b_perm


def permanent_by_interpolation(A: object) -> int:
    """The permanent of a square 0-1 matrix from exact JPDA normalizers (polynomial interpolation).

    With ``A`` as the gating of ``n`` measurements (rows) and ``n`` targets, unit
    likelihoods scaled by ``x`` and row 0 of the MVM equal to 1, the JPDA normalizer (the sum
    over all feasible events, :func:`~projtrack.experiments.jpda.beta_sweep_reachable`'s
    ``column_sums``) is ``Z(x) = sum_k M_k x^k``, ``M_k`` the number of ``k``-edge matchings
    of the gating graph; ``M_n`` is the permanent of ``A``. ``Z`` at ``x = 0..n`` (``x`` is
    one over a clutter density) gives the ``M_k`` by exact interpolation. A polynomial-time
    exact normalizer would thus give the permanent of 0-1 matrices, which is #P-complete
    (Valiant 1979), in polynomial time.
    """
    from fractions import Fraction

    A = as_array(A, "A", ndim=2)
    n = A.shape[0]
    if A.shape != (n, n) or n < 1 or n > 12:
        raise ValueError(f"A must be a square matrix of size 1..12, got shape {A.shape}")
    if not np.all((A == 0) | (A == 1)):
        raise ValueError("A must hold only 0 and 1")
    xs = list(range(n + 1))
    Z = []
    for x in xs:
        mvm = np.vstack([np.ones((1, n)), x * A])
        z = float(beta_sweep_reachable(mvm).column_sums[0])
        Z.append(Fraction(round(z)))  # an integer (a count of weighted matchings) below 2^53
    # Newton's divided differences on x = 0..n: the leading coefficient is M_n
    coef = list(Z)
    for k in range(1, n + 1):
        for i in range(n, k - 1, -1):
            coef[i] = (coef[i] - coef[i - 1]) / (xs[i] - xs[i - k])
    lead = coef[n]
    if lead.denominator != 1:
        raise ArithmeticError("the interpolated leading coefficient is not an integer")
    return int(lead)


def event_orders(validation: object) -> dict[str, list[np.ndarray]]:
    """The feasibility matrices of a binary validation matrix in four natural orders.

    Each event is read as the tuple of the targets of measurements ``1..m`` (0: false);
    the orders are odometer orders with measurement 1 changing fastest or measurement ``m``
    changing fastest, each alone or after sorting by the number of detections. Returns
    ``{name: list of feasibility matrices}``.
    """
    v = as_array(validation, "validation", ndim=2)
    mats = list(iter_feasibility_matrices(v.astype(int)))
    key = {id(om): tuple(int(np.flatnonzero(r)[0]) for r in om) for om in mats}
    detections = {i: sum(t > 0 for t in a) for i, a in key.items()}
    return {"measurement 1 fastest": sorted(mats, key=lambda om: key[id(om)][::-1]),
            f"measurement {v.shape[0]} fastest": sorted(mats, key=lambda om: key[id(om)]),
            "by detections, then measurement 1 fastest":
                sorted(mats, key=lambda om: (detections[id(om)], key[id(om)][::-1])),
            f"by detections, then measurement {v.shape[0]} fastest":
                sorted(mats, key=lambda om: (detections[id(om)], key[id(om)]))}


def clutter_sensitivity(measurements: object, z_pred: object, S: object, p_detect: object,
                        lambdas: Sequence[float], gate_prob: float = 0.99) -> pd.DataFrame:
    """``beta_0`` (probability of no detection) of every target for each clutter density.

    One column per ``lambda`` of ``lambdas`` (named ``f"{lambda:g}"``), one row per
    target (named ``a``, ``b``, ... as in the paper's Fig. 3), from
    :func:`projtrack.jpda.beta` of :func:`projtrack.jpda.modified_validation_matrix`.
    """
    if len(lambdas) == 0:
        raise ValueError("lambdas must not be empty")
    for lam in lambdas:
        as_real(lam, "lambdas[]", 0.0, low_open=True)
    beta0 = {}
    for lam in lambdas:
        w_l = modified_validation_matrix(measurements, z_pred, S, p_detect, gate_prob=gate_prob,
                                         clutter_density=lam)
        beta0[f"{lam:g}"] = beta(w_l)[0]
    T = len(next(iter(beta0.values())))
    table = pd.DataFrame(beta0, index=pd.Index([chr(97 + t) for t in range(T)],
                                               name="beta_0 of target"))
    table.columns.name = "clutter density lambda"
    return table

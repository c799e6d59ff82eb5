"""The equations of Secs. III-IV: term 3 of eq. (8) against eq. (9), and the matrices of eq. (10).

**Eq. (8) and eq. (9).** Term 3 of eq. (8) is printed ``A3 sum_i (sum_alpha X_{i alpha a} - N_T)^2``:
the frame index ``a`` is left free, and the square is taken per target. Its derivative is
``2 A3 (sum_beta X_{i beta a} - N_T)``, not eq. (9)'s ``2 A3 (sum_j sum_beta X_{j beta a} - N_T)``,
and it is smallest when every target holds ``N_T`` measurements in every frame, against
condition 4 of Sec. III. The text ("``sum_i sum_alpha X_{i alpha a}`` for a fixed time ``a`` ...
equals ``N_T``") and eq. (9) both need ``A3 sum_a (sum_i sum_alpha X_{i alpha a} - N_T)^2``,
which :func:`projtrack.neuralnet.energy` implements. :func:`term3_printed` and :func:`term3_read`
are the two forms, :func:`term3_eq9` the term of eq. (9), :func:`central_differences` the
derivative of any energy, :func:`eq8_term3_check` and :func:`gradient_forms` the comparisons;
:func:`connection_check` builds eq. (10) and its two companions for a net and checks them against
terms 1-3 of eq. (9) (:func:`connection_table` beside the paper's numbers); :func:`bound_text`
shows a rounding-level difference as the bound it meets; :func:`plot_architecture` draws the
arithmetic of Figs. 2-3.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import pandas as pd

from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.neuralnet import (PAPER_COEFFICIENTS, connection_matrices, energy, energy_gradient,
                                 energy_gradient_loops, gradient_linear_algebra)
from projtrack.stable import fmt

__all__ = ["term3_printed", "term3_read", "term3_eq9", "central_differences", "eq8_term3_check", "bound_text",
           "connection_table", "gradient_forms", "connection_check", "plot_architecture"]


# ----------------------------------------------------------------------------- eq. (8), eq. (9) and eq. (10)


def _states(X: object) -> np.ndarray:
    X = as_array(X, "X")
    if X.ndim != 3:
        raise ValueError(f"X must have shape (N_T, N_M, N_P), got {X.shape}")
    return X


def term3_printed(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> float:
    """Term 3 of eq. (8) as printed, summed over the frame index it leaves free:
    ``A3 sum_a sum_i (sum_alpha X_{i alpha a} - N_T)^2``."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return float(A3 * ((X.sum(axis=1) - X.shape[0]) ** 2).sum())


def term3_read(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> float:
    """Term 3 as the text and eq. (9) need it: ``A3 sum_a (sum_i sum_alpha X_{i alpha a} - N_T)^2``."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return float(A3 * ((X.sum(axis=(0, 1)) - X.shape[0]) ** 2).sum())


def term3_eq9(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3) -> np.ndarray:
    """Term 3 of eq. (9): ``2 A3 (sum_j sum_beta X_{j beta a} - N_T)`` for every neuron."""
    X = _states(X)
    A3 = as_real(A3, "A3", 0.0)
    return np.broadcast_to(2 * A3 * (X.sum(axis=(0, 1)) - X.shape[0]), X.shape).copy()


def central_differences(f: Callable[[np.ndarray], float], X: np.ndarray, h: float = 1e-4) -> np.ndarray:
    """``(f(X + h e_k) - f(X - h e_k)) / 2h`` for every entry ``k`` of ``X``."""
    if not callable(f):
        raise TypeError("f must be callable")
    X = as_array(X, "X")
    h = as_real(h, "h", 0.0, low_open=True)
    out = np.zeros_like(X)
    for k in np.ndindex(X.shape):
        p, m = X.copy(), X.copy()
        p[k] += h
        m[k] -= h
        out[k] = (f(p) - f(m)) / (2 * h)
    return out


def eq8_term3_check(X: np.ndarray, A3: float = PAPER_COEFFICIENTS.A3, h: float = 1e-4) -> dict[str, float]:
    """Term 3 of eq. (9) against the derivative of both forms of term 3 of eq. (8), on one state.

    Term 3 is quadratic, so central differences are exact up to rounding.

    Returns
    -------
    dict
        ``read``: largest ``|d term3_read / dX - term3_eq9|``; ``printed``: the same for
        :func:`term3_printed`.
    """
    X = _states(X)
    want = term3_eq9(X, A3)
    return {"read": float(np.abs(central_differences(lambda Y: term3_read(Y, A3), X, h) - want).max()),
            "printed": float(np.abs(central_differences(lambda Y: term3_printed(Y, A3), X, h) - want).max())}


def bound_text(value: float, bound: float = 1e-12) -> str:
    """A difference that is rounding noise, shown as the bound it meets (``"< 1e-12"``), or its
    value when it does not meet it (its exact digits depend on the summation order)."""
    value = as_real(value, "value", 0.0)
    bound = as_real(bound, "bound", 0.0, low_open=True)
    return f"< {bound:.0e}".replace("e-0", "e-") if value < bound else f"{value:.1e}"


def connection_table(check: dict[str, float | int]) -> pd.DataFrame:
    """:func:`connection_check` beside the paper's numbers (``quantity``, ``ours``, ``paper``), every
    rounding-level difference shown as the bound it meets (:func:`bound_text`)."""
    need = {"neurons", "T1 ones", "max difference", "assignment ones", "assignment, active max"}
    if not isinstance(check, dict) or need - set(check):
        raise ValueError(f"check must be what connection_check returns, with {sorted(need)}")
    return pd.DataFrame({
        "quantity": ["neurons", "ones in T1 (eq. (10))", "max |T x - 2 A3 N_T - terms 1-3 of eq. (9)|",
                     "active neurons of an assignment state", "their input T x - 2 A3 N_T"],
        "ours": [str(check["neurons"]), str(check["T1 ones"]), bound_text(check["max difference"]),
                 str(check["assignment ones"]), bound_text(check["assignment, active max"])],
        "paper": ["300", "—", "—", "30", "0 (threshold 2 A3 N_T)"]})


def gradient_forms(X: np.ndarray, D: np.ndarray, h: float = 1e-4) -> tuple[pd.DataFrame, bool, bool, float]:
    """Eq. (9), vectorized, against its other forms on one analog state (the paper's coefficients).

    The exact forms (the nested sums of :func:`projtrack.neuralnet.energy_gradient_loops`, and
    ``T x + A4 y4 - 2 A3 N_T`` with the full and the reduced tensor,
    :func:`projtrack.neuralnet.gradient_linear_algebra`) must agree to ``1e-12``; central
    differences of eq. (8) (a cubic polynomial, step ``h``: truncation of order ``h^2`` plus
    rounding) to ``1e-7``, with term 3 read as :func:`term3_read` and as printed
    (:func:`term3_printed`). The differences are shown as the bound they meet, since their exact
    values are rounding noise that depends on the summation order.

    Parameters
    ----------
    X : array_like, shape (N_T, N_M, N_P)
        An analog state (so that no term hides behind a zero).
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
    h : float
        Step of the central differences.

    Returns
    -------
    table : pandas.DataFrame
        ``form``, ``largest difference from eq. (9)`` (text: the bound met, or the value to one
        decimal for the printed term 3), ``agrees``.
    exact_ok : bool
        Every exact form within ``1e-12``.
    differences_ok : bool
        Central differences of eq. (8), term 3 read from the text, within ``1e-7``.
    printed : float
        The largest difference for eq. (8) with term 3 as printed.
    """
    X = _states(X)
    c = PAPER_COEFFICIENTS
    g = energy_gradient(X, D)
    x = X.reshape(-1)
    n_t = X.shape[0]
    exact = {"nested sums (loops)": energy_gradient_loops(X, D),
             "T x + A4 D . x x^T, full tensor": gradient_linear_algebra(x, D, n_t).reshape(X.shape),
             "T x + A4 y4, reduced tensor": gradient_linear_algebra(x, D, n_t, reduced=True).reshape(X.shape)}
    read = central_differences(lambda Y: energy(Y, D), X, h)
    printed = central_differences(lambda Y: energy(Y, D) - term3_read(Y, c.A3) + term3_printed(Y, c.A3), X, h)
    rows = []
    for name, v in exact.items():
        d = float(np.abs(v - g).max())
        rows.append((name, bound_text(d), d < 1e-12))
    d_read = float(np.abs(read - g).max())
    rows.append(("central differences of eq. (8), term 3 read from the text", bound_text(d_read, 1e-7), d_read < 1e-7))
    d_printed = float(np.abs(printed - g).max())
    rows.append(("central differences of eq. (8), term 3 as printed", fmt(d_printed, ".1f"), d_printed < 1e-7))
    table = pd.DataFrame(rows, columns=["form", "largest difference from eq. (9)", "agrees"])
    return table, all(r[2] for r in rows[:3]), d_read < 1e-7, d_printed


def connection_check(n_targets: int, n_measurements: int, n_frames: int, rng: np.random.Generator
                     ) -> dict[str, float | int]:
    """Eq. (10) and its companions for one net, against terms 1-3 of eq. (9).

    Builds ``T1``, ``T2``, ``T3`` (:func:`projtrack.neuralnet.connection_matrices`) and
    compares ``(2 A1 T1 + 2 A2 T2 + 2 A3 T3) x - 2 A3 N_T`` with terms 1-3 of eq. (9)
    (:func:`projtrack.neuralnet.energy_gradient` with ``A4 = 0``) on a random binary state
    drawn from ``rng``, and evaluates it on an assignment state (every target one measurement
    in every frame), whose active neurons it leaves at zero.

    Returns
    -------
    dict
        ``neurons`` (size of ``x``), ``T1 ones``, ``T2 ones``, ``T3 ones``, ``max difference``
        (largest ``|T x - 2 A3 N_T - terms 1-3|``), ``assignment ones`` (active neurons of an
        assignment state) and ``assignment, active max`` (largest ``|T x - 2 A3 N_T|`` over
        its active neurons).
    """
    n_t = as_int(n_targets, "n_targets", minimum=1)
    n_m = as_int(n_measurements, "n_measurements", minimum=n_t)
    n_p = as_int(n_frames, "n_frames", minimum=3)
    rng = as_rng(rng)
    c = PAPER_COEFFICIENTS
    T1, T2, T3 = connection_matrices(n_t, n_m, n_p)
    T = 2 * c.A1 * T1.astype(float) + 2 * c.A2 * T2.astype(float) + 2 * c.A3 * T3.astype(float)
    D0 = np.zeros((n_p - 2, n_m, n_m, n_m))
    x = rng.integers(0, 2, n_t * n_m * n_p).astype(float)
    want = energy_gradient(x.reshape(n_t, n_m, n_p), D0, (c.A1, c.A2, c.A3, 0.0)).reshape(-1)
    X = np.zeros((n_t, n_m, n_p))
    for a in range(n_p):
        X[np.arange(n_t), rng.permutation(n_m)[:n_t], a] = 1.0
    xa = X.reshape(-1)
    ya = T @ xa - 2 * c.A3 * n_t
    return {"neurons": int(x.size), "T1 ones": int(T1.sum()), "T2 ones": int(T2.sum()), "T3 ones": int(T3.sum()),
            "max difference": float(np.abs(T @ x - 2 * c.A3 * n_t - want).max()),
            "assignment ones": int(xa.sum()), "assignment, active max": float(np.abs(ya[xa == 1]).max())}


# ----------------------------------------------------------------------------- figures


def plot_architecture(T: np.ndarray, route: np.ndarray, R0: np.ndarray):
    """The arithmetic of Figs. 2-3: the fixed matrix ``T`` of terms 1-3, the output frame that
    each position of a reduced SLM2 matrix feeds, and one reduced SLM2 matrix filled from data."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(6.4, 2.6))
    axes[0].imshow(T, cmap="Greys")
    axes[0].set_title("(a) $T$, 27 neurons")
    im = axes[1].imshow(np.ma.masked_less(route, 0), cmap="viridis")
    axes[1].set_title("(b) output frame")
    cb = fig.colorbar(im, ax=axes[1], shrink=0.7, ticks=range(int(route.max()) + 1))
    cb.ax.tick_params(labelsize=9)
    axes[2].imshow(np.ma.masked_equal(R0, 0.0), cmap="magma")
    axes[2].set_title(r"(c) SLM2, $\alpha = 1$")
    for ax in axes:
        ax.set_xticks([]); ax.set_yticks([])
        for sp in ax.spines.values():
            sp.set_visible(False)
    fig.tight_layout()
    return fig

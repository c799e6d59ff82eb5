"""The claims of Sec. IV: eq. (8) against eq. (9), the matrices of eq. (10), and degraded data.

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

**Degraded data** (spurious measurements, and missing ones padded with zero vectors).

The paper: "the energy function in (8) enables us to tolerate both spurious measurements and
the absence of measurements ... If a given frame has M < N_M target measurements we set
N_M - M measurements equal to the zero vector ... Spurious measurements ... will not be assigned
to true target tracks ... If both spurious and missing measurements are present, we have found
that the spurious measurements are assigned to the same tracks as the missing measurements
(zero vectors)."

A trial is one data set (four targets, five frames) degraded by
:func:`projtrack.scenes.tracks3d.degrade`, with ``n_starts`` net starts (:func:`draw_degraded`).
A run ends in one of :data:`OUTCOMES` (:func:`degraded_outcome`). The last sentence is read as:
a target whose detection is missing in a frame may take the frame's spurious measurement
instead of the zero vector ("assigned to the same tracks as the missing measurements"); both
leave every real measurement on its own track, and both count as tolerating the degradation.
:func:`degraded_study` runs every condition under several readings of the net (unit of D and
update rule) on the same data sets; :func:`degraded_optimum_study` finds the energy's own exact
minimum (:func:`degraded_optimum`) on them, the claim that "the energy function in (8) enables us
to tolerate" the degradations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng
from projtrack.neuralnet import (PAPER_COEFFICIENTS, assignment_to_states, connection_matrices, distance_tensor,
                                 energy, energy_gradient, energy_gradient_loops, gradient_linear_algebra,
                                 initial_states, is_correct_assignment,
                                 is_fixed_point, run_net, states_to_assignment)
from projtrack.scenes.tracks3d import degrade, make_tracks

from projtrack.stable import fmt

from .comparison import frame_descent, nearest_admissible

__all__ = ["OUTCOMES", "TOLERATED", "DegradedDraw", "draw_degraded", "degraded_outcome", "degraded_study",
           "degraded_optimum", "degraded_optimum_study", "measurement_counts", "tolerance_readings",
           "term3_printed", "term3_read", "term3_eq9", "central_differences", "eq8_term3_check", "bound_text",
           "connection_table", "gradient_forms", "connection_check", "plot_architecture"]

#: How a run on degraded data ends.
OUTCOMES: tuple[str, ...] = ("intended", "gap filled by a spurious measurement", "spurious on a true track",
                             "other wrong", "not converged")

#: The outcomes that tolerate the degradation: every real measurement on its own track.
TOLERATED: tuple[str, ...] = OUTCOMES[:2]


@dataclass(frozen=True)
class DegradedDraw:
    """One degraded data set and its net starts.

    Attributes
    ----------
    positions : ndarray, shape (5, N_M, 3)
        Measurements in pixels (origin at the centre; padding is the zero vector).
    labels : ndarray of int, shape (5, N_M)
        Target of each measurement: -1 for spurious ones; a zero vector standing for a missing
        detection of target ``i`` is labelled ``i``.
    padded : ndarray of bool, shape (5, N_M)
        Which measurements are zero-vector padding.
    intended : ndarray of int, shape (4, 5)
        Measurement of target ``i`` in frame ``a`` in the intended assignment (the zero vector
        where the detection is missing).
    X0 : ndarray, shape (n_starts, 4, N_M, 5)
        Net starts.
    """

    positions: np.ndarray
    labels: np.ndarray
    padded: np.ndarray
    intended: np.ndarray
    X0: np.ndarray


def draw_degraded(rng: np.random.Generator, n_spurious: int, n_missing: int, n_starts: int) -> DegradedDraw:
    """Draw one degraded data set (:func:`~projtrack.scenes.tracks3d.make_tracks`, then
    :func:`~projtrack.scenes.tracks3d.degrade`) and ``n_starts`` starts, in that order."""
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    scene = make_tracks(rng, 4, 5)
    pos, labels = degrade(rng, scene, n_spurious=n_spurious, n_missing=n_missing)
    padded = np.all(pos == 0.0, axis=-1) & (labels >= 0)
    intended = np.array([[int(np.flatnonzero(labels[a] == i)[0]) for a in range(5)] for i in range(4)])
    X0 = initial_states(rng, n_starts, 4, pos.shape[1], 5)
    return DegradedDraw(pos, labels, padded, intended, X0)


def degraded_outcome(X: np.ndarray, converged: bool, draw: DegradedDraw) -> str:
    """The :data:`OUTCOMES` label of one run's final state.

    ``intended``: every target follows its own track, with the zero vector where its detection
    is missing; ``gap filled by a spurious measurement``: the same, but in a frame where its
    detection is missing a target holds the frame's spurious measurement instead;
    ``spurious on a true track``: a spurious measurement is assigned in a frame where no
    detection is missing (so some real measurement lost its track); ``other wrong``: any other
    converged state; ``not converged``.
    """
    if not isinstance(draw, DegradedDraw):
        raise TypeError(f"draw must be a DegradedDraw, got {type(draw).__name__}")
    if not converged:
        return "not converged"
    A = states_to_assignment(np.asarray(X))
    if A is None:
        return "other wrong"
    labels = draw.labels
    if is_correct_assignment(A, labels):
        return "intended"
    gap = labels.copy()   # a spurious measurement may stand in for the frame's missing detection
    for a in range(labels.shape[0]):
        missing = labels[a, draw.padded[a]]
        if missing.size == 1:
            gap[a, labels[a] < 0] = missing[0]
    if is_correct_assignment(A, gap):
        return "gap filled by a spurious measurement"
    taken = labels[np.arange(labels.shape[0])[None, :], A]   # (N_T, N_P)
    complete = ~draw.padded.any(axis=1)
    if np.any((taken < 0) & complete[None, :]):
        return "spurious on a true track"
    return "other wrong"


def _as_pairs(values: object, name: str, size: int) -> list[tuple]:
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or not values:
        raise TypeError(f"{name} must be a non-empty sequence")
    out = []
    for v in values:
        if not isinstance(v, (tuple, list)) or len(v) != size:
            raise ValueError(f"each of {name} must have {size} entries, got {v!r}")
        out.append(tuple(v))
    return out


def degraded_study(conditions: Sequence[tuple[str, int, int]], readings: Sequence[tuple[str, float, dict[str, Any]]],
                   n_datasets: int, n_starts: int, seed: int, *, n_jobs: int | None = None) -> list[dict[str, Any]]:
    """Every condition under every reading, on the same data sets and starts.

    Condition ``c`` draws ``n_datasets`` trials of :func:`draw_degraded` from
    ``numpy.random.default_rng([seed, c])`` (:func:`projtrack.montecarlo.run`); every reading
    runs its nets on them, with D computed from the positions divided by the reading's unit.
    The nets of one reading and one ``N_M`` run as one batch.

    Parameters
    ----------
    conditions : sequence of (label, n_spurious, n_missing)
        Spurious measurements per frame and missing detections per data set.
    readings : sequence of (label, unit, options)
        Unit of D in pixels and options of :func:`projtrack.neuralnet.run_net` (``offset``,
        ``self_coupling``, ``exact_energy``, ``mode``); ``{"frame_rule": True}`` runs
        :func:`projtrack.experiments.neuralnet.frame_descent` from the
        :func:`~projtrack.experiments.neuralnet.nearest_admissible` state of each start instead
        (its ``intended is a fixed point %`` is NaN: the question is asked of the net's neurons).
    n_datasets, n_starts : int
        Data sets per condition and net starts per data set.
    seed : int
    n_jobs : int, optional
        For the drawing; results do not depend on it.

    Returns
    -------
    list of dict
        Per condition and reading: ``condition``, ``reading``, the percentage of runs in each of
        :data:`OUTCOMES`, ``tolerated %`` (the :data:`TOLERATED` outcomes) and ``intended is a
        fixed point %`` (share of data sets whose intended state no neuron would leave).
    """
    conditions = _as_pairs(conditions, "conditions", 3)
    readings = _as_pairs(readings, "readings", 3)
    n_datasets = as_int(n_datasets, "n_datasets", minimum=1)
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    for label, unit, options in readings:
        as_real(unit, "unit", 0.0, low_open=True)
        if not isinstance(options, dict):
            raise TypeError(f"the options of reading {label!r} must be a dict, got {type(options).__name__}")
    draws = [montecarlo.run(draw_degraded, n_datasets, np.random.default_rng([seed, c]), n_sp, n_mi, n_starts,
                            n_jobs=n_jobs) for c, (_, n_sp, n_mi) in enumerate(conditions)]
    rows = []
    for c, (cond, _, _) in enumerate(conditions):
        pos = np.stack([d.positions for d in draws[c]])
        n_m = pos.shape[2]
        intended = np.stack([assignment_to_states(d.intended, n_m) for d in draws[c]]).astype(float)
        X0 = np.concatenate([d.X0 for d in draws[c]])
        owner = np.repeat(np.arange(n_datasets), n_starts)
        for label, unit, options in readings:
            D = distance_tensor(pos / float(unit))
            if options.get("frame_rule"):
                fixed = np.full(n_datasets, np.nan)   # asked of the net's neurons only
                ends = [frame_descent(D[j], nearest_admissible(X0[k])) for k, j in enumerate(owner)]
                outcome = [degraded_outcome(assignment_to_states(A, n_m), conv, draws[c][j])
                           for (A, _, conv), j in zip(ends, owner)]
            else:
                fixed = is_fixed_point(intended, D, **{k: v for k, v in options.items() if k != "mode"})
                r = run_net(np.repeat(D, n_starts, axis=0), X0, **options)
                outcome = [degraded_outcome(r.states[k], bool(r.converged[k]), draws[c][owner[k]])
                           for k in range(len(owner))]
            share = {o: 100 * sum(x == o for x in outcome) / len(outcome) for o in OUTCOMES}
            rows.append({"condition": cond, "reading": label,
                         "tolerated %": sum(share[o] for o in TOLERATED),
                         **{f"{o} %": share[o] for o in OUTCOMES},
                         "intended is a fixed point %": 100 * float(np.mean(fixed))})
    return rows


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


# ----------------------------------------------------------------------------- the energy's own minimum


def degraded_optimum(D: np.ndarray, n_targets: int = 4) -> tuple[np.ndarray, float]:
    """Exact minimum of eq. (8) over the admissible states of a frame sequence with ``N_M >= N_T``.

    On an admissible state (each target holds one measurement per frame, each measurement at
    most one target) terms 1-3 of eq. (8) vanish and term 4 is ``A4`` times the summed D along
    the tracks, so the admissible state of least energy minimises that sum. Dynamic programming
    over pairs of consecutive frames, each frame's state an injection of the ``N_T`` targets
    into its ``N_M`` measurements; in frame 0 the targets are labelled in the order of their
    measurements (targets are interchangeable). Work is ``N_P`` times the cube of the number of
    injections (120 for ``N_M = 5``, ``N_T = 4``).

    Parameters
    ----------
    D : array_like, shape (N_P - 2, N_M, N_M, N_M)
        The distance tensor of eq. (7).
    n_targets : int, default 4
        ``N_T``, at most ``N_M``.

    Returns
    -------
    assignment : ndarray of int, shape (N_T, N_P)
        Measurement of each target in each frame.
    cost : float
        Its summed D (the energy is ``A4`` times this).
    """
    from itertools import combinations, permutations

    D = as_array(D, "D", ndim=4)
    n_q, n_m = D.shape[0], D.shape[1]
    n_t = as_int(n_targets, "n_targets", minimum=1, maximum=n_m)
    if D.shape != (n_q, n_m, n_m, n_m) or n_q < 1:
        raise ValueError(f"D must have shape (N_P - 2, N_M, N_M, N_M), got {D.shape}")
    first = np.array(list(combinations(range(n_m), n_t)), dtype=np.intp)    # frame 0 states
    inj = np.array(list(permutations(range(n_m), n_t)), dtype=np.intp)      # states of the other frames
    t = np.arange(n_t)

    def triple(a: int, p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
        return D[a][p0[:, None, None, t], p1[None, :, None, t], p2[None, None, :, t]].sum(axis=-1)

    tot = triple(0, first, inj, inj)                      # (frame 0, frame 1, frame 2)
    back = [np.argmin(tot, axis=0)]
    V = np.min(tot, axis=0)                               # V[p1, p2]
    for a in range(1, n_q):
        tot = V[:, :, None] + triple(a, inj, inj, inj)
        back.append(np.argmin(tot, axis=0))
        V = np.min(tot, axis=0)
    p_prev, p_last = np.unravel_index(int(np.argmin(V)), V.shape)
    best = float(V[p_prev, p_last])
    seq = [int(p_last), int(p_prev)]                      # frames N_P - 1, N_P - 2, ... backwards
    for arg in reversed(back):
        seq.append(int(arg[seq[-1], seq[-2]]))
    seq = seq[::-1]                                       # frame 0 (index into first), frames 1.. (into inj)
    A = np.empty((n_t, n_q + 2), dtype=np.intp)
    A[:, 0] = first[seq[0]]
    for f, p in enumerate(seq[1:], start=1):
        A[:, f] = inj[p]
    return A, best


def degraded_optimum_study(conditions: Sequence[tuple[str, int, int]], n_datasets: int, n_starts: int, seed: int,
                           *, unit: float = 256.0, n_jobs: int | None = None) -> list[dict[str, Any]]:
    """The exact minimum of eq. (8) (:func:`degraded_optimum`) on the data sets of :func:`degraded_study`.

    Condition ``c`` draws the same ``n_datasets`` trials of :func:`draw_degraded` as
    :func:`degraded_study` with the same ``seed`` and ``n_starts`` (the starts are drawn and not
    used). The minimiser does not depend on the unit of D (D is linear in the positions); the
    unit only scales the energy, used to check that no inadmissible state can beat the
    admissible minimum: every violated constraint of terms 1-3 costs at least
    ``min(A1, A2, A3) = 15``, so the admissible minimum is the global one when its energy
    ``A4 x cost`` is below that.

    Parameters
    ----------
    conditions : sequence of (label, n_spurious, n_missing)
    n_datasets, n_starts : int
    seed : int
    unit : float, default 256
        Unit of D in pixels, for the energy check only.
    n_jobs : int, optional
        For the drawing; results do not depend on it.

    Returns
    -------
    list of dict
        Per condition: ``condition``, the percentage of data sets in each of :data:`OUTCOMES`,
        ``tolerated %``, ``spurious measurement used %`` (the minimum holds some spurious
        measurement), ``global minimum`` (bool: the check above held for every data set), and per
        measurement (:func:`measurement_counts`, pooled over the data sets) ``real measurements
        kept %`` and ``spurious displacing a real %`` (NaN without spurious measurements).
    """
    conditions = _as_pairs(conditions, "conditions", 3)
    n_datasets = as_int(n_datasets, "n_datasets", minimum=1)
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    seed = as_int(seed, "seed", minimum=0)
    unit = as_real(unit, "unit", 0.0, low_open=True)
    c4 = PAPER_COEFFICIENTS
    rows = []
    for c, (cond, n_sp, n_mi) in enumerate(conditions):
        draws = montecarlo.run(draw_degraded, n_datasets, np.random.default_rng([seed, c]), n_sp, n_mi, n_starts,
                               n_jobs=n_jobs)
        outcome, used, ok, counts = [], [], True, np.zeros(4, dtype=np.int64)
        for d in draws:
            A, cost = degraded_optimum(distance_tensor(d.positions / unit), 4)
            n_m = d.positions.shape[1]
            outcome.append(degraded_outcome(assignment_to_states(A, n_m), True, d))
            used.append(bool(np.any(d.labels[np.arange(A.shape[1])[None, :], A] < 0)))
            ok = ok and c4.A4 * cost < min(c4.A1, c4.A2, c4.A3)
            counts += measurement_counts(A, d)
        share = {o: 100 * sum(x == o for x in outcome) / len(outcome) for o in OUTCOMES}
        rows.append({"condition": cond, "tolerated %": sum(share[o] for o in TOLERATED),
                     **{f"{o} %": share[o] for o in OUTCOMES},
                     "spurious measurement used %": 100 * float(np.mean(used)), "global minimum": bool(ok),
                     "real measurements kept %": 100 * float(counts[0] / counts[1]) if counts[1] else float("nan"),
                     "spurious displacing a real %": 100 * float(counts[2] / counts[3]) if counts[3] else float("nan")})
    return rows


def measurement_counts(A: np.ndarray, draw: DegradedDraw) -> np.ndarray:
    """Per-measurement counts of an assignment on degraded data: how many real measurements stay on their track.

    The track of a target is the true target most of its real (not padded, not spurious)
    measurements belong to (a true target claimed by two targets counts for the one holding more
    of it). A spurious measurement *displaces* a real one when the target holding it follows a
    track whose real detection in that frame exists (it does not merely fill a missing detection's
    gap).

    Parameters
    ----------
    A : array_like of int, shape (N_T, N_P)
        Measurement of each target in each frame.
    draw : DegradedDraw

    Returns
    -------
    ndarray of int, shape (4,)
        Real measurements on their own track, real measurements, spurious measurements that
        displace a real one, spurious measurements.
    """
    if not isinstance(draw, DegradedDraw):
        raise TypeError(f"draw must be a DegradedDraw, got {type(draw).__name__}")
    A = np.asarray(A)
    labels, padded = draw.labels, draw.padded
    if A.ndim != 2 or A.shape[1] != labels.shape[0]:
        raise ValueError(f"A must have shape (N_T, N_P = {labels.shape[0]}), got {A.shape}")
    frames = np.arange(labels.shape[0])[None, :]
    taken, pad = labels[frames, A], padded[frames, A]
    real = (taken >= 0) & ~pad
    best: dict[int, tuple[int, int]] = {}                       # true target -> (count, holding target)
    own = np.full(A.shape[0], -1)
    for k in range(A.shape[0]):
        if real[k].any():
            vals, cnt = np.unique(taken[k][real[k]], return_counts=True)
            own[k] = int(vals[np.argmax(cnt)])
            if own[k] not in best or best[own[k]][0] < cnt.max():
                best[int(own[k])] = (int(cnt.max()), k)
    kept = sum(c for c, _ in best.values())
    n_real = int(((labels >= 0) & ~padded).sum())
    displacing = 0
    for k, a in zip(*np.nonzero(taken < 0)):
        displacing += int(own[k] >= 0 and bool(np.any((labels[a] == own[k]) & ~padded[a])))
    return np.array([kept, n_real, displacing, int((labels < 0).sum())], dtype=np.int64)


def tolerance_readings(optimum: pd.DataFrame, threshold: float = 95.0) -> pd.DataFrame:
    """The readings of "enables us to tolerate both spurious measurements and the absence of measurements".

    Each degradation alone (the paper's paragraph treats them one at a time, and the combined case
    apart), or both at once, counted per data set (every real measurement on its own track), per
    real measurement (on its own track) or per spurious measurement (not displacing a real one,
    :func:`measurement_counts`).

    Parameters
    ----------
    optimum : DataFrame
        :func:`degraded_optimum_study` indexed by condition, with rows ``spurious``, ``missing``
        and ``both``.
    threshold : float, default 95
        The share (%) a general statement needs (rule 7).

    Returns
    -------
    DataFrame
        ``reading``, ``counted``, ``%`` and ``passes`` (the reading's every row reaches the
        threshold).
    """
    if not isinstance(optimum, pd.DataFrame):
        raise TypeError(f"optimum must be a DataFrame, got {type(optimum).__name__}")
    missing = [c for c in ("spurious", "missing", "both") if c not in optimum.index]
    if missing:
        raise ValueError(f"optimum lacks the conditions {missing}")
    o = optimum
    rows = [("each alone", "data sets, spurious", o.loc["spurious", "tolerated %"]),
            ("each alone", "data sets, missing", o.loc["missing", "tolerated %"]),
            ("both, per data set", "data sets", o.loc["both", "tolerated %"]),
            ("both, per real measurement", "real measurements kept", o.loc["both", "real measurements kept %"]),
            ("both, per spurious measurement", "spurious, displacing none",
             100.0 - o.loc["both", "spurious displacing a real %"])]
    out = pd.DataFrame(rows, columns=["reading", "counted", "%"])
    out["%"] = out["%"].astype(float)
    ok = out.groupby("reading", sort=False)["%"].transform("min") >= threshold
    out["passes"] = ok.astype(bool)
    return out

"""The claims of Sec. IV on degraded data (spurious measurements, and missing ones padded with zero vectors).

Eq. (8) against eq. (9) and the matrices of eq. (10) are in
:mod:`projtrack.experiments.neuralnet.equations`.

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
from typing import Any, Sequence

import numpy as np
import pandas as pd

from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real
from projtrack.neuralnet import (PAPER_COEFFICIENTS, assignment_to_states, distance_tensor, initial_states,
                                 is_correct_assignment, is_fixed_point, run_net, states_to_assignment)
from projtrack.scenes.tracks3d import degrade, make_tracks

from .comparison import frame_descent, nearest_admissible

__all__ = ["OUTCOMES", "TOLERATED", "DegradedDraw", "draw_degraded", "degraded_outcome", "degraded_study",
           "degraded_optimum", "degraded_optimum_study", "measurement_counts", "tolerance_readings"]

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

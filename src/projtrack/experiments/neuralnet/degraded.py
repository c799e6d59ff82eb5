"""The net on degraded data (Sec. IV): spurious measurements, and missing ones padded with zero vectors.

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
update rule) on the same data sets.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int, as_real
from projtrack.neuralnet import (assignment_to_states, distance_tensor, initial_states, is_correct_assignment,
                                 is_fixed_point, run_net, states_to_assignment)
from projtrack.scenes.tracks3d import degrade, make_tracks

from .updates import frame_descent, nearest_admissible

__all__ = ["OUTCOMES", "TOLERATED", "DegradedDraw", "draw_degraded", "degraded_outcome", "degraded_study"]

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

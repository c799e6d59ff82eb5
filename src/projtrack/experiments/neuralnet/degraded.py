"""The net on degraded data (Sec. IV): spurious measurements and missing detections padded with zeros.

A trial is one data set (four targets, five frames, D in field widths) degraded by
:func:`projtrack.scenes.tracks3d.degrade`, with the intended assignment (every target keeps its
measurements, a zero vector where its detection is missing) and ``n_starts`` net starts
(:func:`draw_degraded`). :func:`degraded_study` draws the trials of every condition through
:func:`projtrack.montecarlo.run` and runs the nets of one condition as one batch, with the
results of :func:`degraded_trial` run trial by trial.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from projtrack import montecarlo
from projtrack._validation import as_int
from projtrack.neuralnet import (assignment_to_states, distance_tensor, initial_states, is_correct_assignment,
                                 run_net, states_to_assignment)
from projtrack.scenes.tracks3d import degrade, make_tracks

__all__ = ["DegradedDraw", "draw_degraded", "degraded_trial", "degraded_study"]


@dataclass(frozen=True)
class DegradedDraw:
    """One degraded data set and its net starts.

    Attributes
    ----------
    D : ndarray, shape (3, N_M, N_M, N_M)
        Distance tensor of the degraded measurements (field widths).
    labels : ndarray of int, shape (5, N_M)
        Target of each measurement (-1 for spurious ones).
    intended : ndarray of int, shape (4, 5)
        Measurement of target ``i`` in frame ``a`` in the intended assignment.
    X0 : ndarray, shape (n_starts, 4, N_M, 5)
        Net starts.
    """

    D: np.ndarray
    labels: np.ndarray
    intended: np.ndarray
    X0: np.ndarray


def draw_degraded(rng: np.random.Generator, n_spurious: int, n_missing: int, n_starts: int) -> DegradedDraw:
    """Draw one degraded data set (:func:`~projtrack.scenes.tracks3d.make_tracks`, then
    :func:`~projtrack.scenes.tracks3d.degrade`) and ``n_starts`` starts, in that order."""
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    scene = make_tracks(rng, 4, 5)
    pos, labels = degrade(rng, scene, n_spurious=n_spurious, n_missing=n_missing)
    intended = np.array([[int(np.flatnonzero(labels[a] == i)[0]) for a in range(5)] for i in range(4)])
    X0 = initial_states(rng, n_starts, 4, pos.shape[1], 5)
    return DegradedDraw(distance_tensor(pos / scene.field), labels, intended, X0)


def _score(draws: list[DegradedDraw]) -> tuple[np.ndarray, np.ndarray]:
    """Per draw: is the intended state a fixed point; how many starts end at the correct assignment."""
    Ds = np.stack([d.D for d in draws])
    n_m = Ds.shape[-1]
    start = np.stack([assignment_to_states(d.intended, n_m) for d in draws]).astype(float)
    fixed = run_net(Ds, start, max_iter=2).converged
    n_starts = [len(d.X0) for d in draws]
    r = run_net(np.repeat(Ds, n_starts, axis=0), np.concatenate([d.X0 for d in draws]))
    owner = np.repeat(np.arange(len(draws)), n_starts)
    ok = np.zeros(len(draws), dtype=int)
    for k, j in enumerate(owner):
        if r.status[k] == "converged" and is_correct_assignment(states_to_assignment(r.states[k]), draws[j].labels):
            ok[j] += 1
    return np.asarray(fixed, dtype=bool), ok


def degraded_trial(rng: np.random.Generator, n_spurious: int, n_missing: int, n_starts: int) -> tuple[bool, int]:
    """One data set: whether its intended state is a fixed point, and how many of ``n_starts`` nets
    converge to the correct assignment."""
    fixed, ok = _score([draw_degraded(rng, n_spurious, n_missing, n_starts)])
    return bool(fixed[0]), int(ok[0])


def degraded_study(conditions: Sequence[tuple[int, int]], n_datasets: int, n_starts: int, seed: int, *,
                   n_jobs: int | None = None) -> list[dict[str, float]]:
    """:func:`degraded_trial` for ``n_datasets`` data sets per condition, the nets of a condition in one batch.

    The conditions draw their trials one after another from ``numpy.random.default_rng(seed)``
    (each :func:`projtrack.montecarlo.run` spawns new children of it).

    Parameters
    ----------
    conditions : sequence of (n_spurious, n_missing)
        Spurious measurements per frame and missing detections.
    n_datasets, n_starts : int
        Data sets per condition and net starts per data set.
    seed : int
    n_jobs : int, optional
        For the drawing; results do not depend on it.

    Returns
    -------
    list of dict
        Per condition: ``spurious per frame``, ``missing detections``, ``intended state is a
        fixed point %`` and ``net runs correct %``.
    """
    if isinstance(conditions, (str, bytes)) or not isinstance(conditions, Sequence) or not conditions:
        raise TypeError("conditions must be a non-empty sequence of (n_spurious, n_missing)")
    n_datasets = as_int(n_datasets, "n_datasets", minimum=1)
    n_starts = as_int(n_starts, "n_starts", minimum=1)
    rng = np.random.default_rng(as_int(seed, "seed", minimum=0))
    rows = []
    for c in conditions:
        if not isinstance(c, (tuple, list)) or len(c) != 2:
            raise ValueError(f"a condition must be (n_spurious, n_missing), got {c!r}")
        n_sp, n_mi = c
        draws = montecarlo.run(draw_degraded, n_datasets, rng, n_sp, n_mi, n_starts, n_jobs=n_jobs)
        fixed, ok = _score(draws)
        rows.append({"spurious per frame": n_sp, "missing detections": n_mi,
                     "intended state is a fixed point %": 100 * float(fixed.sum()) / n_datasets,
                     "net runs correct %": 100 * float(ok.sum()) / (n_datasets * n_starts)})
    return rows

"""Figs. 2-3 of Marques et al. (2002): the motion model learned on a closed curve.

Prototypes of a learned curve model relabelled clockwise (:func:`clockwise_order`), the
reading of a transition matrix as "stay or advance to the next state" (:func:`other_moves`)
and the sensitivity of that structure to the training speed (:func:`speed_sensitivity`).
"""

from __future__ import annotations

import numpy as np

from projtrack._validation import as_array, as_count, as_real
from projtrack.dma import DiscreteManifold, estimate_transitions
from projtrack.scenes import manifolds as mf

__all__ = ["clockwise_order", "other_moves", "speed_sensitivity"]


def clockwise_order(model: DiscreteManifold) -> tuple[np.ndarray, np.ndarray]:
    """Prototypes of a 2-D curve model in clockwise order, starting at a region boundary.

    Returns ``order`` (``order[i]`` is the prototype of clockwise rank ``i``; by angle
    about the origin, decreasing, then rotated so that rank 0 is the first prototype of a
    region) and its inverse ``inv`` (the rank of each prototype), so that
    ``inv[model.quantize(x)]`` gives clockwise state indices. The model must live in the
    plane (ValueError otherwise).
    """
    if not isinstance(model, DiscreteManifold):
        raise TypeError(f"model must be a projtrack.dma.DiscreteManifold, got {type(model).__name__}")
    if model.ambient_dim != 2:
        raise ValueError(f"model must be a curve model in the plane (2-D points), got dimension {model.ambient_dim}")
    angle = np.arctan2(model.prototypes[:, 1], model.prototypes[:, 0])
    order = np.argsort(-angle)  # clockwise
    reg_sorted = model.prototype_region[order]
    changes = np.flatnonzero(reg_sorted != np.roll(reg_sorted, 1))
    first = int(changes[0]) if changes.size else 0  # start at a region boundary
    order = np.roll(order, -first)
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    return order, inv


def other_moves(transitions: object, threshold: float = 0.0) -> int:
    """Number of states with a move other than "stay" or "advance to the next state".

    ``transitions`` is a dense ``(S, S)`` matrix over states in cyclic order; an entry
    counts as a move when it is above ``threshold`` (>= 0). The chain of Fig. 3 has none.
    """
    D = as_array(transitions, "transitions", ndim=2)
    S = D.shape[0]
    if D.shape != (S, S) or S == 0:
        raise ValueError(f"transitions must be a non-empty square matrix, got shape {D.shape}")
    threshold = as_real(threshold, "threshold", 0)
    return int(sum(bool(set(np.flatnonzero(D[i] > threshold).tolist()) - {i, (i + 1) % S}) for i in range(S)))


def speed_sensitivity(
    model: DiscreteManifold,
    inv: object,
    mean_steps: tuple[float, ...],
    *,
    n_runs: int = 20,
    n_steps: int = 400,
    threshold: float = 0.01,
) -> list[dict[str, object]]:
    """The learned chain of Fig. 3 versus the speed of the training motion.

    For each ``mean_step`` (rad per step), ``n_runs`` clockwise trajectories of
    ``n_steps`` on :func:`projtrack.scenes.manifolds.closed_curve` (drawn from
    ``numpy.random.default_rng(int(mean_step * 1000))``) train a transition matrix
    (:func:`projtrack.dma.estimate_transitions`, pseudo-count 1e-3) over the clockwise
    states ``inv`` of :func:`clockwise_order`. Each row gives the largest step, the mean
    step over the median distance between consecutive centroids, the number of states
    with other moves than stay / advance (:func:`other_moves` above ``threshold``) and the
    largest number of successors of a state.
    """
    inv = as_array(inv, "inv", ndim=1, dtype=np.int64)
    S = model.n_prototypes
    if inv.shape != (S,):
        raise ValueError(f"inv must have shape ({S},), got {inv.shape}")
    steps = [as_real(m, "mean_steps[i]", 0, low_open=True) for m in mean_steps]
    if not steps:
        raise ValueError("mean_steps must not be empty")
    n_runs = as_count(n_runs, "n_runs")
    n_steps = as_count(n_steps, "n_steps", minimum=2)
    P = model.prototypes[np.argsort(inv)]
    gap = np.linalg.norm(P - np.roll(P, -1, axis=0), axis=1)
    rows: list[dict[str, object]] = []
    for mean_step in steps:
        rng = np.random.default_rng(int(mean_step * 1000))
        runs = [mf.curve_trajectory(n_steps, rng, mean_step=mean_step) for _ in range(n_runs)]
        step = np.concatenate([np.linalg.norm(np.diff(tr, axis=0), axis=1) for tr in runs])
        D = estimate_transitions([inv[model.quantize(tr)] for tr in runs], S, alpha=1e-3).toarray()
        rows.append({"mean step [rad]": mean_step, "largest step": round(float(step.max()), 3),
                     "mean step / median centroid distance": round(float(step.mean() / np.median(gap)), 2),
                     "rows with other moves": other_moves(D, threshold),
                     "largest successors per row": int((D > threshold).sum(axis=1).max())})
    return rows

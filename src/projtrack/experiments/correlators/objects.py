"""Several objects located by projection correlations (Sec. V, Fig. 10): scenes, scoring, studies.

* :func:`place_objects` builds a scene of copies of a template; :func:`random_positions`
  draws well-separated object positions;
* :func:`energy_count` estimates the number of objects from the correlation-plane energy;
* :func:`match_positions` scores the candidates of :func:`projtrack.correlators.locate_objects`
  against the true positions (missed objects, spurious candidates);
* :func:`random_scene_study` runs the detector on random scenes (Monte Carlo);
* :func:`switching_pair`, :func:`ideal_ghosts`, :func:`unique_from_projections` and
  :func:`ideal_detector_study` ask the same question with an ideal detector (discrete
  tomography: which point sets do a few projections determine).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from itertools import combinations

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng, as_shape2

__all__ = ["place_objects", "energy_count", "match_positions", "random_positions", "random_scene_study",
           "switching_pair", "ideal_ghosts", "unique_from_projections", "ideal_detector_study",
           "IDEAL_KEYS"]

#: (tolerance in pixels, diagonal) of the columns of :func:`ideal_detector_study`.
IDEAL_KEYS: tuple[tuple[int, str], ...] = tuple((tol, k) for tol in (0, 1) for k in ("45", "135"))


def _as_positions(positions: object, name: str = "positions") -> list[tuple[int, int]]:
    arr = np.asarray(positions, dtype=float)
    if arr.size == 0:
        return []
    arr = as_array(arr, name, shape=(None, 2))
    if np.any(arr != np.round(arr)):
        raise ValueError(f"{name} must hold integer (row, col) pixel positions")
    return [(int(r), int(q)) for r, q in arr]


def place_objects(template: np.ndarray, positions: Sequence[tuple[int, int]],
                  shape: tuple[int, int] = (64, 64)) -> np.ndarray:
    """A scene of ``shape`` with a copy of the odd-sized square ``template`` centred on each position.

    Overlapping copies add. Raises ValueError if the template is not square with an odd
    side, or a copy does not fit the scene.
    """
    template = as_array(template, "template", ndim=2, allow_empty=False)
    if template.shape[0] != template.shape[1] or template.shape[0] % 2 == 0:
        raise ValueError(f"template must be square with an odd side, got shape {template.shape}")
    shape = as_shape2(shape)
    h = template.shape[0] // 2
    out = np.zeros(shape)
    for r, q in _as_positions(positions):
        if r - h < 0 or q - h < 0 or r + h >= shape[0] or q + h >= shape[1]:
            raise ValueError(f"an object at {(r, q)} does not fit a scene of shape {shape}")
        out[r - h:r + h + 1, q - h:q + h + 1] += template
    return out


def energy_count(scene: np.ndarray, template: np.ndarray) -> float:
    """Objects in ``scene`` estimated as its correlation-plane energy over that of one object.

    Both planes correlate with the zero-mean template; the estimate is exact for copies
    whose correlations do not overlap.
    """
    scene = as_array(scene, "scene", ndim=2, allow_empty=False)
    template = as_array(template, "template", ndim=2, allow_empty=False)
    t = template - template.mean()
    one = float(np.sum(C.correlate2d(template, t) ** 2))
    if one == 0.0:
        raise ValueError("template must not be constant")
    return float(np.sum(C.correlate2d(scene, t) ** 2) / one)


def match_positions(found: Sequence[tuple[float, float]], truth: Sequence[tuple[int, int]],
                    tol: float = 1) -> tuple[int, int]:
    """``(missed objects, spurious candidates)`` after greedy matching within ``tol`` pixels.

    Each true position, in order, takes the nearest remaining candidate (Chebyshev
    distance) if it is within ``tol``; unmatched true positions are missed and unmatched
    candidates spurious.
    """
    tol = as_real(tol, "tol", 0.0)
    found = list(found)
    missed = 0
    for p in truth:
        d = [max(abs(p[0] - f[0]), abs(p[1] - f[1])) for f in found]
        if not d or min(d) > tol:
            missed += 1
            continue
        found.pop(int(np.argmin(d)))
    return missed, len(found)


def random_positions(rng: np.random.Generator, n_objects: int = 4, *, low: int = 5, high: int = 59,
                     min_separation: int = 10) -> list[tuple[int, int]]:
    """``n_objects`` positions drawn uniformly in ``[low, high)`` per axis, at least ``min_separation``
    apart (Chebyshev distance), by rejection of each candidate that is too close."""
    rng = as_rng(rng)
    n_objects = as_int(n_objects, "n_objects", minimum=1)
    low = as_int(low, "low")
    high = as_int(high, "high", minimum=low + 1)
    min_separation = as_int(min_separation, "min_separation", minimum=0)
    if n_objects > 1 and (high - low - 1) // max(min_separation, 1) + 1 < 2:
        raise ValueError(f"no two positions in [{low}, {high}) are {min_separation} apart")
    pos: list[tuple[int, int]] = []
    while len(pos) < n_objects:
        cand = tuple(int(v) for v in rng.integers(low, high, size=2))
        if all(max(abs(cand[0] - a), abs(cand[1] - b)) >= min_separation for a, b in pos):
            pos.append(cand)  # type: ignore[arg-type]
    return pos


def _scene_trial(rng: np.random.Generator, templates: Mapping[str, np.ndarray],
                 configs: Sequence[tuple[str, tuple[float, ...]]]) -> tuple[list[dict], list[dict]]:
    pos = random_positions(rng)
    rows, counts = [], []
    for obj_name, template in templates.items():
        sc = place_objects(template, pos)
        counts.append({"object": obj_name, "energy count": energy_count(sc, template)})
        for name, angles in configs:
            missed, spurious = match_positions(C.locate_objects(sc, template, angles)["positions"], pos)
            rows.append({"object": obj_name, "projections": name, "located": missed == 0 and spurious == 0,
                         "missed": missed, "spurious": spurious, "positions": pos})
    return rows, counts


def random_scene_study(templates: Mapping[str, np.ndarray], configs: Sequence[tuple[str, Sequence[float]]],
                       n_scenes: int, rng: np.random.Generator) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Locate four objects at random positions (:func:`random_positions`) in 64 x 64 scenes.

    Every scene is built once per template (same positions) and searched with
    :func:`projtrack.correlators.locate_objects` (default threshold) for every set of
    projection angles; trials run through :func:`projtrack.montecarlo.run`.

    Parameters
    ----------
    templates : mapping of name to odd-sized square template
    configs : sequence of (name, angles)
    n_scenes : int
        Random scenes (>= 1).
    rng : numpy.random.Generator
        Parent generator of the scenes.

    Returns
    -------
    trials : pandas.DataFrame
        One row per scene, template and projection set: ``object``, ``projections``,
        ``located`` (no miss and no spurious candidate), ``missed``, ``spurious``, ``positions``.
    counts : pandas.DataFrame
        One row per scene and template: ``object`` and ``energy count`` (:func:`energy_count`).
    """
    if not templates:
        raise ValueError("templates must not be empty")
    templates = {str(k): as_array(v, f"templates[{k!r}]", ndim=2, allow_empty=False) for k, v in templates.items()}
    configs = [(str(name), tuple(angles)) for name, angles in configs]
    if not configs:
        raise ValueError("configs must not be empty")
    n_scenes = as_int(n_scenes, "n_scenes", minimum=1)
    out = montecarlo.run(_scene_trial, n_scenes, as_rng(rng), templates, configs)
    trials = pd.DataFrame([r for rows, _ in out for r in rows])
    counts = pd.DataFrame([c for _, cs in out for c in cs])
    return trials, counts


def switching_pair(origin: tuple[int, int] = (16, 16), steps: tuple[int, int, int] = (10, 14, 6)
                   ) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """Two 4-point sets with equal row, column and diagonal projections (a switching component).

    The 8 points ``origin + b (steps[1], 0) + a (0, steps[0]) + c (steps[2], steps[2])``
    (``a, b, c`` in {0, 1}, as (row, col)) split by the parity of ``a + b + c``.
    """
    r0, q0 = (as_int(v, "origin") for v in origin)
    s0, s1, s2 = (as_int(v, "steps", minimum=1) for v in steps)
    sets: tuple[list[tuple[int, int]], list[tuple[int, int]]] = ([], [])
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                sets[(a + b + c) % 2].append((r0 + b * s1 + c * s2, q0 + a * s0 + c * s2))
    return sets


def ideal_ghosts(positions: Sequence[tuple[int, int]], tol: int = 0) -> dict[str, int]:
    """Ghosts of an ideal detector: non-object row/column crossings whose diagonal also holds an object.

    Returns the count for the third projection at 45 degrees (``"45"``: the diagonal
    ``col - row`` constant) and at 135 degrees (``"135"``: ``col + row`` constant), a
    diagonal matching within ``tol`` pixels.
    """
    pos = _as_positions(positions)
    tol = as_int(tol, "tol", minimum=0)
    rows_, cols_ = {p[0] for p in pos}, {p[1] for p in pos}
    diags = [p[1] + p[0] for p in pos]
    antid = [p[1] - p[0] for p in pos]
    n = {"45": 0, "135": 0}
    for r in rows_:
        for q in cols_:
            if (r, q) in pos:
                continue
            n["45"] += any(abs((q - r) - d) <= tol for d in antid)
            n["135"] += any(abs((q + r) - d) <= tol for d in diags)
    return n


def unique_from_projections(positions: Sequence[tuple[int, int]]) -> bool:
    """Whether ``positions`` is the only point set of its size with its row, column and 45-degree counts."""
    pos = _as_positions(positions)
    rows_, cols_, anti = sorted(p[0] for p in pos), sorted(p[1] for p in pos), sorted(p[1] - p[0] for p in pos)
    cands = [(r, q) for r in set(rows_) for q in set(cols_) if (q - r) in anti]
    sols = [s for s in combinations(cands, len(pos))
            if sorted(p[0] for p in s) == rows_ and sorted(p[1] for p in s) == cols_
            and sorted(p[1] - p[0] for p in s) == anti]
    return len(sols) == 1


def _ideal_trial(rng: np.random.Generator) -> list[bool]:
    pos = random_positions(rng)
    return [ideal_ghosts(pos, tol)[k] == 0 for tol, k in IDEAL_KEYS] + [unique_from_projections(pos)]


def ideal_detector_study(n_scenes: int, rng: np.random.Generator) -> np.ndarray:
    """Random 4-object scenes (:func:`random_positions`) judged with an ideal detector.

    Returns a bool array ``(n_scenes, len(IDEAL_KEYS) + 1)``: ghost-free for each
    (tolerance, diagonal) of :data:`IDEAL_KEYS`, then unique from the 0/90/45-degree
    projections (:func:`unique_from_projections`). Trials run through
    :func:`projtrack.montecarlo.run`.
    """
    n_scenes = as_int(n_scenes, "n_scenes", minimum=1)
    return np.array(montecarlo.run(_ideal_trial, n_scenes, as_rng(rng)), dtype=bool)

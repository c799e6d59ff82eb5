"""Several objects located by projection correlations (Sec. V, Fig. 10): scenes, scoring, studies.

* :func:`place_objects` builds a scene of copies of a template; :func:`random_positions`
  draws well-separated object positions;
* :func:`energy_count` estimates the number of objects from the correlation-plane energy;
* :func:`match_positions` scores the candidates of :func:`projtrack.correlators.locate_objects`
  against the true positions (missed objects, spurious candidates);
* :func:`random_scene_study` runs the detector on random scenes (Monte Carlo);
* :func:`switching_pair`, :func:`ideal_ghosts`, :func:`unique_from_projections` and
  :func:`ideal_detector_study` ask the same question with an ideal detector (discrete
  tomography: which point sets do a few projections determine);
* :func:`lines_ghost_free`, :func:`unique_from_lines` and :func:`ideal_count_study` do it for
  any number of objects and any of the lattice directions 0, 90, 45 and 135 degrees;
* :func:`energy_count_study`: the object count from the energy of the 2-D and of the
  projection correlation planes, for 1 to 5 objects, with and without noise.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from itertools import combinations

import numpy as np
import pandas as pd

from projtrack import correlators as C
from projtrack import montecarlo
from projtrack._validation import as_array, as_int, as_real, as_rng, as_shape2

__all__ = ["place_objects", "energy_count", "match_positions", "random_positions", "random_scene_study",
           "switching_pair", "ideal_ghosts", "unique_from_projections", "ideal_detector_study",
           "IDEAL_KEYS", "LINE_KEYS", "lines_ghost_free", "unique_from_lines", "ideal_count_study",
           "energy_count_study"]

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


#: The line through pixel (row, col) along each lattice projection direction, as an integer key:
#: 0 degrees (vertical projection) the column, 90 the row, 45 ``col - row``, 135 ``col + row``
#: (rows counted downwards, so 45 degrees with y up runs along ``col - row`` constant).
LINE_KEYS = {0: lambda r, q: q, 90: lambda r, q: r, 45: lambda r, q: q - r, 135: lambda r, q: q + r}


def _as_directions(angles: object) -> tuple[int, ...]:
    try:
        out = tuple(int(a) for a in angles)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise TypeError(f"angles must be a sequence of lattice angles, got {angles!r}") from None
    if not out or any(a not in LINE_KEYS for a in out) or len(set(out)) != len(out):
        raise ValueError(f"angles must be distinct angles among {tuple(LINE_KEYS)}, got {angles!r}")
    return out


def lines_ghost_free(positions: Sequence[tuple[int, int]], angles: Sequence[int], tol: int = 0) -> bool:
    """Whether the backprojection of ideal projections (exact line positions) finds only the objects.

    A row/column crossing is a candidate when a line of every other direction of ``angles``
    through it holds an object (within ``tol``); the set is ghost-free when every candidate
    is an object. Rows (90) and columns (0) must both be among ``angles``; with fewer
    directions every point of an object's line is a candidate, so there are ghosts.
    """
    pos = _as_positions(positions)
    angles = _as_directions(angles)
    tol = as_int(tol, "tol", minimum=0)
    if not {0, 90} <= set(angles):
        return False
    rest = [a for a in angles if a not in (0, 90)]
    keys = {a: [LINE_KEYS[a](*p) for p in pos] for a in rest}
    objects = set(pos)
    for r in {p[0] for p in pos}:
        for q in {p[1] for p in pos}:
            if (r, q) not in objects and all(any(abs(LINE_KEYS[a](r, q) - k) <= tol for k in keys[a]) for a in rest):
                return False
    return True


def unique_from_lines(positions: Sequence[tuple[int, int]], angles: Sequence[int]) -> bool:
    """Whether ``positions`` is the only point set of its size with its line counts along ``angles``.

    The line counts are how many objects each line of each direction holds (what the
    amplitudes of the projection correlation peaks give). Rows (90) and columns (0) must
    both be among ``angles``; with fewer directions a point set is never determined.
    """
    pos = _as_positions(positions)
    angles = _as_directions(angles)
    if not {0, 90} <= set(angles):
        return False
    target = {a: Counter(LINE_KEYS[a](*p) for p in pos) for a in angles}
    cols = sorted(target[0])
    rows = sorted(target[90])
    solutions = 0

    def extend(i: int, counts: dict[int, Counter]) -> None:
        nonlocal solutions
        if solutions > 1:
            return
        if i == len(rows):
            if all(counts[a] == target[a] for a in angles):
                solutions += 1
            return
        r = rows[i]
        for chosen in combinations(cols, target[90][r]):
            new = {a: counts[a].copy() for a in angles}
            ok = True
            for q in chosen:
                for a in angles:
                    k = LINE_KEYS[a](r, q)
                    new[a][k] += 1
                    if new[a][k] > target[a].get(k, 0):
                        ok = False
            if ok:
                extend(i + 1, new)

    extend(0, {a: Counter() for a in angles})
    return solutions == 1


def _count_trial(rng, n_objects, angle_sets, tols):
    out = []
    for n in n_objects:
        pos = random_positions(rng, n)
        out.append([[unique_from_lines(pos, angles)] + [lines_ghost_free(pos, angles, t) for t in tols]
                     for angles in angle_sets])
    return out


def ideal_count_study(n_objects: Sequence[int], angle_sets: Sequence[Sequence[int]], n_scenes: int,
                      rng: np.random.Generator, *, tols: Sequence[int] = (0, 1)) -> np.ndarray:
    """Random scenes of several object counts judged with an ideal detector.

    Every trial draws, for every count of ``n_objects``, one scene of that many objects
    (:func:`random_positions`: at least 10 pixels apart in a 64-pixel field) and asks, for
    every set of directions of ``angle_sets``: is the point set the only one with its line
    counts (:func:`unique_from_lines`), and is the backprojection ghost-free for each
    tolerance of ``tols`` (:func:`lines_ghost_free`). Trials run through
    :func:`projtrack.montecarlo.run`.

    Returns
    -------
    numpy.ndarray of bool, shape (n_scenes, len(n_objects), len(angle_sets), 1 + len(tols))
    """
    n_objects = [as_int(n, "n_objects", minimum=1) for n in n_objects]
    angle_sets = [_as_directions(a) for a in angle_sets]
    tols = [as_int(t, "tols", minimum=0) for t in tols]
    if not n_objects or not angle_sets:
        raise ValueError("n_objects and angle_sets must not be empty")
    n_scenes = as_int(n_scenes, "n_scenes", minimum=1)
    return np.array(montecarlo.run(_count_trial, n_scenes, as_rng(rng), n_objects, angle_sets, tols), dtype=bool)


def _energy_trial(rng, template, counts, sigma, field, min_separation, angles, ones):
    h = template.shape[0] // 2
    t = template - template.mean()
    out = []
    for k in counts:
        pos = random_positions(rng, k, low=h, high=field - h, min_separation=min_separation)
        scene = place_objects(template, pos, (field, field))
        if sigma > 0:
            scene = scene + rng.normal(0.0, sigma, size=scene.shape)
        scene = scene - scene.mean()
        planes = [C.correlate2d(scene, t)] + [C.projection_correlation(scene, t, a) for a in angles]
        noise = [sigma ** 2 * field ** 2 * float(np.sum(t * t))]
        noise += [sigma ** 2 * field ** 2 * float(np.sum(C.project(t, a) ** 2)) for a in angles]
        out.append([(float(np.sum(p * p)) - nz) / e1 for p, nz, e1 in zip(planes, noise, ones)])
    return out


def energy_count_study(template: np.ndarray, counts: Sequence[int], n_scenes: int, rng: np.random.Generator, *,
                       sigma: float = 0.0, field: int = 64, min_separation: int | None = None,
                       angles: Sequence[float] = (90, 0)) -> np.ndarray:
    """Object counts estimated from correlation-plane energies (Sec. V), for scenes of 1 to K objects.

    Each scene holds ``k`` copies of the odd-sized square ``template`` at random positions
    at least ``min_separation`` apart (default: the template side, so that copies do not
    overlap) in a ``field x field`` frame, plus white Gaussian noise ``sigma``, made zero
    mean. The estimate is the energy of the scene's correlation plane with the zero-mean
    template, less the expected noise energy ``sigma^2 field^2 E`` (``E`` the energy of the
    zero-mean template or of its projection), over the energy of one noise-free copy's
    plane; for the 2-D plane and for the projection correlations at ``angles``.

    Returns
    -------
    numpy.ndarray, shape (n_scenes, len(counts), 1 + len(angles))
        The estimates: 2-D plane first, then one per angle.
    """
    template = as_array(template, "template", ndim=2, allow_empty=False)
    if template.shape[0] != template.shape[1] or template.shape[0] % 2 == 0:
        raise ValueError(f"template must be square with an odd side, got shape {template.shape}")
    counts = [as_int(k, "counts", minimum=1) for k in counts]
    if not counts:
        raise ValueError("counts must not be empty")
    n_scenes = as_int(n_scenes, "n_scenes", minimum=1)
    sigma = as_real(sigma, "sigma", 0.0)
    field = as_int(field, "field", minimum=template.shape[0])
    min_separation = template.shape[0] if min_separation is None else as_int(min_separation, "min_separation",
                                                                              minimum=0)
    angles = tuple(as_real(a, "angles") for a in angles)
    t = template - template.mean()
    if not np.any(t):
        raise ValueError("template must not be constant")
    h = template.shape[0] // 2
    one = place_objects(template, [(field // 2, field // 2)], (field, field))
    one = one - one.mean()
    ones = [float(np.sum(C.correlate2d(one, t) ** 2))]
    ones += [float(np.sum(C.projection_correlation(one, t, a) ** 2)) for a in angles]
    if (field - 2 * h - 1) // max(min_separation, 1) + 1 < 2 and max(counts) > 1:
        raise ValueError("the field is too small for two objects at the required separation")
    return np.array(montecarlo.run(_energy_trial, n_scenes, as_rng(rng), template, counts, sigma, field,
                                   min_separation, angles, ones))

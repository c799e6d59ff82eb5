"""A synthetic digital elevation map with a road network and cars driving on it.

Stands in for the unpublished map of Example 2 of Marques et al. (2002), Figs. 7-8.

Generator (:func:`make_road_scene`), all sizes in metres:

* **Elevation** ``z(x, y)`` on ``[0, extent]^2``: a base plane plus ``n_hills`` Gaussian
  hills with heights ``U(20, 80)``, widths ``U(150, 400)`` and uniform random centres,
  evaluated exactly (no grid) so road points lie on the surface.
* **Roads**: junctions on a ``grid x grid`` lattice spaced ``extent / (grid + 1)``, each
  moved by ``N(0, (0.08 spacing)^2)``; every pair of lattice neighbours is joined by a
  road, a quadratic Bezier curve whose control point is the midpoint moved sideways by
  ``N(0, (0.15 length)^2)``. Roads are 3-D curves ``(x, y, z(x, y))``: the manifold is
  the road network on the terrain.
* **Prototypes**: points every ``spacing`` metres (in arc length) along every road,
  junctions shared; :attr:`RoadScene.adjacency` links consecutive points of a road.
* **Cars** (:meth:`RoadScene.drive`): start at a random junction, drive along a road,
  at each junction take a uniformly random other road (a U-turn only at dead ends), with
  speed ``N(speed, (0.15 speed)^2)`` clipped to ``[0.4, 1.6] speed`` redrawn every step;
  positions sampled every ``dt`` seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from projtrack._validation import as_count, as_real, as_rng, only_value_errors

__all__ = ["RoadScene", "DirectedStates", "make_road_scene"]


@dataclass
class DirectedStates:
    """Road prototypes paired with a direction of travel (position-heading states).

    Every road is sampled every ``spacing`` m *including* its two end junctions, once
    per direction of travel, so a state is "at this point, driving this way". A
    trajectory is quantized to the nearest state in the feature space
    ``(x, y, heading_scale * unit heading)`` (:meth:`quantize`), the heading of a
    trajectory being its finite-difference direction.

    Attributes
    ----------
    positions : ndarray, shape (K, 3)
        State positions (x, y, z).
    headings : ndarray, shape (K, 2)
        Unit direction of travel in the plane.
    heading_scale : float
        Metres that a unit heading difference counts for in :meth:`quantize`.
    """

    positions: np.ndarray
    headings: np.ndarray
    heading_scale: float

    @property
    def features(self) -> np.ndarray:
        """``(K, 4)`` features ``(x, y, s hx, s hy)``."""
        return np.column_stack([self.positions[:, :2], self.heading_scale * self.headings])

    def quantize(self, trajectory: np.ndarray) -> np.ndarray:
        """Nearest state of each point of a trajectory ``(T, 2 or 3)``, ``T >= 2``."""
        from scipy.spatial import cKDTree

        x = np.asarray(trajectory, dtype=float)
        if x.ndim != 2 or x.shape[0] < 2 or x.shape[1] not in (2, 3):
            raise ValueError(f"trajectory must have shape (T >= 2, 2 or 3), got {x.shape}")
        if not np.isfinite(x).all():
            raise ValueError("trajectory must be finite (no NaN or inf)")
        v = np.gradient(x[:, :2], axis=0)
        v = v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-12)
        return cKDTree(self.features).query(np.column_stack([x[:, :2], self.heading_scale * v]))[1]


@dataclass
class RoadScene:
    """Output of :func:`make_road_scene`.

    Attributes
    ----------
    extent : float
        Side of the square map (m).
    hills : ndarray, shape (H, 4)
        Hill centres x, y, heights and widths.
    junctions : ndarray, shape (J, 2)
        Junction positions (x, y).
    roads : list of (int, int, ndarray)
        ``(junction_a, junction_b, polyline (P, 2))`` sampled every metre from a to b.
    prototypes : ndarray, shape (K, 3)
        Points every ``spacing`` m along the roads, with elevation.
    adjacency : scipy.sparse.csr_array, shape (K, K)
        1 between consecutive prototypes of a road (symmetric).
    """

    extent: float
    hills: np.ndarray
    base: float
    junctions: np.ndarray
    roads: list[tuple[int, int, np.ndarray]]
    spacing: float
    prototypes: np.ndarray = field(init=False)
    adjacency: sp.csr_array = field(init=False)

    def __post_init__(self) -> None:
        J = len(self.junctions)
        pts = [np.column_stack([self.junctions, self.elevation(self.junctions)])]
        rows, cols = [], []
        next_id = J
        for a, b, poly in self.roads:
            s = _arclength(poly)
            n_int = max(int(round(s[-1] / self.spacing)) - 1, 0)
            targets = np.linspace(0, s[-1], n_int + 2)[1:-1]
            xy = np.column_stack([np.interp(targets, s, poly[:, 0]), np.interp(targets, s, poly[:, 1])])
            ids = np.arange(next_id, next_id + n_int)
            next_id += n_int
            pts.append(np.column_stack([xy, self.elevation(xy)]))
            chain = np.concatenate([[a], ids, [b]])
            rows += list(chain[:-1]) + list(chain[1:])
            cols += list(chain[1:]) + list(chain[:-1])
        self.prototypes = np.vstack(pts)
        K = len(self.prototypes)
        A = sp.csr_array((np.ones(len(rows)), (rows, cols)), shape=(K, K))
        A.sum_duplicates()
        A.data[:] = 1.0
        self.adjacency = A

    def directed_states(self, heading_scale: float = 30.0) -> DirectedStates:
        """Position-heading states along every road (see :class:`DirectedStates`)."""
        heading_scale = only_value_errors(as_real, heading_scale, "heading_scale", 0, low_open=True)
        pos, head = [], []
        for _, _, poly in self.roads:
            s = _arclength(poly)
            n = max(int(round(s[-1] / self.spacing)), 1)
            tt = np.linspace(0, s[-1], n + 1)
            xy = np.column_stack([np.interp(tt, s, poly[:, 0]), np.interp(tt, s, poly[:, 1])])
            tg = np.gradient(xy, axis=0)
            tg = tg / np.linalg.norm(tg, axis=1, keepdims=True)
            for sign in (1.0, -1.0):
                pos.append(xy)
                head.append(sign * tg)
        xy = np.vstack(pos)
        return DirectedStates(np.column_stack([xy, self.elevation(xy)]), np.vstack(head), float(heading_scale))

    def elevation(self, xy: np.ndarray) -> np.ndarray:
        """Terrain height ``z(x, y)`` (m) at points ``(..., 2)``."""
        xy = np.asarray(xy, dtype=float)
        if xy.ndim == 0 or xy.shape[-1] != 2:
            raise ValueError(f"xy must have shape (..., 2), got {xy.shape}")
        if not np.isfinite(xy).all():
            raise ValueError("xy must be finite (no NaN or inf)")
        d2 = ((xy[..., None, :] - self.hills[:, :2]) ** 2).sum(-1)
        return self.base + (self.hills[:, 2] * np.exp(-0.5 * d2 / self.hills[:, 3] ** 2)).sum(-1)

    def elevation_grid(self, n: int = 101) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(X, Y, Z)`` on an ``n x n`` grid, for contour plots (``n`` an int >= 2)."""
        n = as_count(n, "n", minimum=2)
        g = np.linspace(0, self.extent, n)
        X, Y = np.meshgrid(g, g)
        return X, Y, self.elevation(np.stack([X, Y], axis=-1))

    def drive(self, n_steps: int, rng: np.random.Generator, *, speed: float = 12.0, dt: float = 1.0) -> np.ndarray:
        """A car trajectory of ``n_steps`` positions ``(x, y, z)`` sampled every ``dt`` s."""
        rng = as_rng(rng)
        n_steps = as_count(n_steps, "n_steps")
        speed = only_value_errors(as_real, speed, "speed", 0, low_open=True)
        dt = only_value_errors(as_real, dt, "dt", 0, low_open=True)
        incident: dict[int, list[tuple[int, bool]]] = {}
        for r, (a, b, _) in enumerate(self.roads):
            incident.setdefault(a, []).append((r, True))
            incident.setdefault(b, []).append((r, False))
        node = int(rng.integers(len(self.junctions)))
        road, forward = incident[node][rng.integers(len(incident[node]))]
        poly = self.roads[road][2] if forward else self.roads[road][2][::-1]
        s = _arclength(poly)
        pos = 0.0
        out = np.empty((n_steps, 2))
        for t in range(n_steps):
            out[t] = [np.interp(pos, s, poly[:, 0]), np.interp(pos, s, poly[:, 1])]
            v = speed * np.clip(1 + 0.15 * rng.standard_normal(), 0.4, 1.6)
            pos += v * dt
            while pos > s[-1]:
                pos -= s[-1]
                a, b, _ = self.roads[road]
                node = b if forward else a
                options = [o for o in incident[node] if o[0] != road] or incident[node]
                road, forward = options[rng.integers(len(options))]
                poly = self.roads[road][2] if forward else self.roads[road][2][::-1]
                s = _arclength(poly)
        return np.column_stack([out, self.elevation(out)])


def _arclength(poly: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(poly, axis=0), axis=1))])


def make_road_scene(
    rng: np.random.Generator,
    *,
    extent: float = 2000.0,
    grid: int = 3,
    n_hills: int = 6,
    spacing: float = 10.0,
) -> RoadScene:
    """Draw a synthetic elevation map with a road network (see the module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
    extent : float
        Map side (m).
    grid : int
        Junctions per side (``grid**2`` junctions, ``2 grid (grid - 1)`` roads).
    n_hills : int
        Number of Gaussian hills.
    spacing : float
        Prototype spacing along the roads (m).

    Raises
    ------
    TypeError
        If ``rng`` is not a Generator.
    ValueError
        If ``grid`` is not an int >= 2, ``n_hills`` not an int >= 0, or ``extent`` or
        ``spacing`` not a finite number > 0 (each message names the argument).
    """
    rng = as_rng(rng)
    grid = as_count(grid, "grid", minimum=2)
    extent = only_value_errors(as_real, extent, "extent", 0, low_open=True)
    spacing = only_value_errors(as_real, spacing, "spacing", 0, low_open=True)
    n_hills = as_count(n_hills, "n_hills", minimum=0)
    hills = np.column_stack([
        rng.uniform(0, extent, n_hills), rng.uniform(0, extent, n_hills),
        rng.uniform(20, 80, n_hills), rng.uniform(150, 400, n_hills),
    ])
    step = extent / (grid + 1)
    gi, gj = np.meshgrid(np.arange(1, grid + 1), np.arange(1, grid + 1), indexing="ij")
    junctions = np.column_stack([gj.ravel() * step, gi.ravel() * step]) + rng.normal(0, 0.08 * step, (grid * grid, 2))
    roads = []
    for i in range(grid):
        for j in range(grid):
            a = i * grid + j
            for b in ([a + 1] if j + 1 < grid else []) + ([a + grid] if i + 1 < grid else []):
                p0, p2 = junctions[a], junctions[b]
                d = p2 - p0
                normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
                p1 = 0.5 * (p0 + p2) + normal * rng.normal(0, 0.15 * np.linalg.norm(d))
                n = max(int(np.linalg.norm(d) * 1.3), 2)
                u = np.linspace(0, 1, n)[:, None]
                poly = (1 - u) ** 2 * p0 + 2 * u * (1 - u) * p1 + u**2 * p2
                roads.append((a, b, poly))
    return RoadScene(extent=float(extent), hills=hills, base=100.0, junctions=junctions, roads=roads, spacing=float(spacing))

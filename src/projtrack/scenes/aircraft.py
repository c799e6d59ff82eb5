"""Five aircraft built from simple 3-D geometry, rendered at any roll angle (no background).

Stand-in for the unpublished aircraft imagery of Vermeulen & Casasent (1988): Table 2 (five
aircraft, per-class novelty filters) and the rank claim of Section 2 (rolling aircraft, 36
training images at 10-degree roll steps).  Each model is a few parts:

- fuselage and engine nacelles: bodies of revolution (a radius profile along the axis);
- wings, tailplanes and fins: convex planform polygons extruded to a small thickness, with
  optional dihedral/anhedral (rotation about the part's root line).

Body axes: ``x`` forward (fuselage from ``x = -0.5`` to ``0.5``), ``y`` starboard wing, ``z``
up.  :func:`render` rolls the model by ``roll_deg`` about ``x`` and projects it
orthographically on an image seen from above (``-z``): roll 0 shows the planform, roll 90
the side view.  Faces are flat-shaded (ambient 0.25 + 0.75 ``|n . l|``, fixed light direction)
and z-buffered; the background is 0.  Images are rendered at ``supersample`` times the size
and block-averaged (anti-aliasing), then quantized to uint8.

The five planforms are coarse likenesses drawn from well-known three-view outlines (MiG-21:
delta wing with tailplane; DC-10: swept wing, two underwing engines and a tail engine;
Mirage III: tailless delta; F-4 Phantom: cranked wing with dihedral tips and anhedral
stabilator; Boeing 737: swept wing with engines close to the fuselage).  They were written
down once and not adjusted to reproduce any number of the paper.
"""
from __future__ import annotations

from dataclasses import dataclass, field
import numpy as np

from projtrack._validation import as_int, as_real, only_value_errors

__all__ = ["AIRCRAFT", "Aircraft", "aircraft_model", "render", "render_rolls"]

#: The five aircraft, in the column order of Table 2.
AIRCRAFT: tuple[str, ...] = ("Mig", "DC-10", "Mirage", "Phantom", "Boeing-737")


@dataclass(frozen=True)
class Aircraft:
    """A triangle mesh: ``triangles`` has shape ``(T, 3, 3)`` (vertex, xyz) in body axes."""

    name: str
    triangles: np.ndarray = field(repr=False)


# --- geometry builders ----------------------------------------------------------------------
def _revolve(stations, radii, centre=(0.0, 0.0, 0.0), n_seg=10) -> np.ndarray:
    """Triangles of a body of revolution about an axis parallel to x through ``centre``."""
    xs, rs = np.asarray(stations, float), np.asarray(radii, float)
    th = np.linspace(0, 2 * np.pi, n_seg + 1)
    cy, cz = np.cos(th), np.sin(th)
    ring = np.stack([np.repeat(xs[:, None], n_seg + 1, 1), rs[:, None] * cy, rs[:, None] * cz], -1)
    ring = ring + np.asarray(centre)
    a, b = ring[:-1, :-1], ring[:-1, 1:]
    c, d = ring[1:, :-1], ring[1:, 1:]
    tris = np.concatenate([np.stack([a, b, d], -2).reshape(-1, 3, 3),
                           np.stack([a, d, c], -2).reshape(-1, 3, 3)])
    caps = []
    for k in (0, -1):
        if rs[k] > 0:
            ctr = np.array([xs[k], 0.0, 0.0]) + np.asarray(centre)
            r = ring[k]
            caps.append(np.stack([np.broadcast_to(ctr, r[:-1].shape), r[:-1], r[1:]], 1))
    return np.concatenate([tris] + caps) if caps else tris


def _slab(polygon, plane="xy", thickness=0.01, offset=0.0, tilt_deg=0.0, pivot=(0.0, 0.0, 0.0),
          mirror=True) -> np.ndarray:
    """Extruded convex polygon (planform) in plane ``xy`` (wings) or ``xz`` (fins).

    ``offset`` is the position along the normal axis; ``tilt_deg`` rotates the part about the
    x axis through ``pivot`` (dihedral for positive angles on the starboard side); ``mirror``
    adds the port-side copy (y -> -y) for ``xy`` parts.
    """
    p = np.asarray(polygon, float)
    n = len(p)
    h = thickness / 2
    if plane == "xy":
        top = np.column_stack([p[:, 0], p[:, 1], np.full(n, offset + h)])
        bot = np.column_stack([p[:, 0], p[:, 1], np.full(n, offset - h)])
    else:
        top = np.column_stack([p[:, 0], np.full(n, offset + h), p[:, 1]])
        bot = np.column_stack([p[:, 0], np.full(n, offset - h), p[:, 1]])
    tris = []
    for face in (top, bot):
        tris += [np.stack([face[0], face[k], face[k + 1]]) for k in range(1, n - 1)]
    for k in range(n):
        k2 = (k + 1) % n
        tris += [np.stack([top[k], top[k2], bot[k2]]), np.stack([top[k], bot[k2], bot[k]])]
    t = np.stack(tris)
    if tilt_deg:
        a = np.deg2rad(tilt_deg)
        rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
        pv = np.asarray(pivot, float)
        t = (t - pv) @ rot.T + pv
    if mirror and plane == "xy":
        m = t * np.array([1.0, -1.0, 1.0])
        t = np.concatenate([t, m])
    return t


def _fuselage(radius, nose=0.18, tail=0.2, n_st=10, n_seg=10, length=1.0):
    x0, x1 = -length / 2, length / 2
    xs = np.concatenate([np.linspace(x1, x1 - nose, n_st // 2, endpoint=False),
                         np.linspace(x1 - nose, x0 + tail, 2, endpoint=False),
                         np.linspace(x0 + tail, x0, n_st // 2)])
    r = np.interp(xs, [x0, x0 + tail, x1 - nose, x1], [radius * 0.35, radius, radius, 0.0])
    nose_part = xs > x1 - nose
    r[nose_part] = radius * np.sqrt(np.clip((x1 - xs[nose_part]) / nose, 0, 1))
    return _revolve(xs, r, n_seg=n_seg)


def _nacelle(x_front, length, radius, y, z, n_seg=8):
    xs = np.array([x_front, x_front - 0.15 * length, x_front - length])
    rs = np.array([radius * 0.85, radius, radius * 0.7])
    parts = [_revolve(xs, rs, (0.0, y, z), n_seg)]
    return np.concatenate(parts)


def aircraft_model(name: str) -> Aircraft:
    """The mesh of one of :data:`AIRCRAFT` (``"Mig"``, ``"DC-10"``, ``"Mirage"``, ``"Phantom"``,
    ``"Boeing-737"``)."""
    if name not in AIRCRAFT:
        raise ValueError(f"name must be one of {AIRCRAFT}, got {name!r}")
    if name == "Mig":
        parts = [_fuselage(0.045, nose=0.2),
                 _slab([(-0.02, 0.04), (-0.36, 0.34), (-0.40, 0.34), (-0.40, 0.04)], offset=0.0),
                 _slab([(-0.36, 0.03), (-0.46, 0.16), (-0.50, 0.16), (-0.50, 0.03)], offset=0.0),
                 _slab([(-0.22, 0.03), (-0.42, 0.21), (-0.49, 0.21), (-0.49, 0.03)],
                       plane="xz", offset=0.0)]
    elif name == "DC-10":
        parts = [_fuselage(0.06, nose=0.12, tail=0.18, n_st=12),
                 _slab([(0.06, 0.05), (-0.22, 0.48), (-0.28, 0.48), (-0.16, 0.05)],
                       offset=-0.03, tilt_deg=5, pivot=(0, 0.05, -0.03)),
                 _nacelle(0.07, 0.15, 0.028, 0.17, -0.075),
                 _nacelle(0.07, 0.15, 0.028, -0.17, -0.075),
                 _nacelle(-0.30, 0.18, 0.032, 0.0, 0.095),
                 _slab([(-0.34, 0.12), (-0.44, 0.28), (-0.49, 0.28), (-0.47, 0.12)],
                       plane="xz", offset=0.0),
                 _slab([(-0.36, 0.04), (-0.46, 0.20), (-0.51, 0.20), (-0.48, 0.04)], offset=0.01)]
    elif name == "Mirage":
        parts = [_fuselage(0.045, nose=0.22),
                 _slab([(0.08, 0.04), (-0.40, 0.30), (-0.44, 0.30), (-0.44, 0.04)], offset=-0.01),
                 _slab([(-0.18, 0.03), (-0.40, 0.22), (-0.47, 0.22), (-0.47, 0.03)],
                       plane="xz", offset=0.0)]
    elif name == "Phantom":
        parts = [_fuselage(0.055, nose=0.2, tail=0.22),
                 _slab([(0.0, 0.05), (-0.15, 0.24), (-0.30, 0.24), (-0.28, 0.05)], offset=-0.02),
                 _slab([(-0.15, 0.24), (-0.23, 0.35), (-0.28, 0.35), (-0.30, 0.24)],
                       offset=-0.02, tilt_deg=12, pivot=(0, 0.24, -0.02)),
                 _slab([(-0.37, 0.03), (-0.47, 0.17), (-0.51, 0.17), (-0.50, 0.03)],
                       offset=0.02, tilt_deg=-23, pivot=(0, 0.03, 0.02)),
                 _slab([(-0.28, 0.04), (-0.44, 0.20), (-0.50, 0.20), (-0.49, 0.04)],
                       plane="xz", offset=0.0)]
    else:  # Boeing-737
        parts = [_fuselage(0.055, nose=0.12, tail=0.2),
                 _slab([(0.08, 0.05), (-0.12, 0.44), (-0.17, 0.44), (-0.12, 0.05)],
                       offset=-0.035, tilt_deg=6, pivot=(0, 0.05, -0.035)),
                 _nacelle(0.10, 0.12, 0.034, 0.15, -0.07),
                 _nacelle(0.10, 0.12, 0.034, -0.15, -0.07),
                 _slab([(-0.24, 0.05), (-0.42, 0.26), (-0.48, 0.26), (-0.47, 0.05)],
                       plane="xz", offset=0.0),
                 _slab([(-0.34, 0.04), (-0.45, 0.19), (-0.49, 0.19), (-0.47, 0.04)], offset=0.0)]
    return Aircraft(name, np.concatenate(parts))


# --- rendering ------------------------------------------------------------------------------
_LIGHT = np.array([0.35, 0.25, 1.0]) / np.linalg.norm([0.35, 0.25, 1.0])


def _rasterize(tris2: np.ndarray, depth: np.ndarray, shade: np.ndarray, size: int) -> np.ndarray:
    """Z-buffer flat-shaded triangles (pixel coords) on a ``size x size`` grid.

    Vectorized over chunks of triangles of similar size: each triangle's bounding box is
    scanned on a common ``B x B`` window; among the covering triangles of a pixel (pixel
    centre inside, barycentric coordinates >= 0) the nearest (largest depth) wins.
    """
    xs, ys = tris2[..., 0], tris2[..., 1]
    x0, y0, x1, y1, x2, y2 = xs[:, 0], ys[:, 0], xs[:, 1], ys[:, 1], xs[:, 2], ys[:, 2]
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    cmin = np.clip(np.floor(xs.min(1)), 0, size).astype(int)
    cmax = np.clip(np.ceil(xs.max(1)), 0, size).astype(int)
    rmin = np.clip(np.floor(ys.min(1)), 0, size).astype(int)
    rmax = np.clip(np.ceil(ys.max(1)), 0, size).astype(int)
    extent = np.maximum(cmax - cmin, rmax - rmin)
    keep = (np.abs(area) > 1e-12) & (cmax > cmin) & (rmax > rmin)
    order = np.flatnonzero(keep)[np.argsort(extent[keep], kind="stable")]
    all_idx, all_z, all_s = [], [], []
    for chunk in np.array_split(order, max(1, len(order) // 64)):
        if chunk.size == 0:
            continue
        b = int(extent[chunk].max())
        off = np.arange(b)
        rr = rmin[chunk, None, None] + off[None, :, None]          # (T, B, 1)
        cc = cmin[chunk, None, None] + off[None, None, :]          # (T, 1, B)
        qx, qy = cc + 0.5, rr + 0.5
        a = area[chunk, None, None]
        X0, Y0 = x0[chunk, None, None], y0[chunk, None, None]
        w1 = ((qx - X0) * (y2[chunk, None, None] - Y0) - (x2[chunk, None, None] - X0) * (qy - Y0)) / a
        w2 = ((x1[chunk, None, None] - X0) * (qy - Y0) - (qx - X0) * (y1[chunk, None, None] - Y0)) / a
        w0 = 1.0 - w1 - w2
        inside = (w0 >= 0) & (w1 >= 0) & (w2 >= 0) & (rr < size) & (cc < size)
        d = depth[chunk]
        z = w0 * d[:, 0, None, None] + w1 * d[:, 1, None, None] + w2 * d[:, 2, None, None]
        t_i, r_i, c_i = np.nonzero(inside)
        all_idx.append((rr[t_i, r_i, 0]) * size + cc[t_i, 0, c_i])
        all_z.append(z[t_i, r_i, c_i])
        all_s.append(shade[chunk][t_i])
    img = np.zeros(size * size)
    if all_idx:
        idx, z, sh = np.concatenate(all_idx), np.concatenate(all_z), np.concatenate(all_s)
        o = np.lexsort((z, idx))                    # by pixel, then depth ascending
        idx, sh = idx[o], sh[o]
        last = np.r_[idx[1:] != idx[:-1], True]    # nearest triangle of each pixel
        img[idx[last]] = sh[last]
    return img.reshape(size, size)


def render(aircraft: Aircraft | str, roll_deg: float, size: int = 64, supersample: int = 2,
           extent: float = 1.15) -> np.ndarray:
    """Render an aircraft rolled by ``roll_deg`` degrees, seen from above, on black.

    Parameters
    ----------
    aircraft : Aircraft or str
        A model from :func:`aircraft_model` or its name.
    roll_deg : float
        Roll angle about the fuselage (x) axis, degrees (0: planform view, 90: side view).
    size : int
        Output image side in pixels (the nose points to the right).
    supersample : int
        Render at ``supersample * size`` and block-average (anti-aliasing).
    extent : float
        Body-axis length that spans the image width (the fuselage has length 1).

    Returns
    -------
    ndarray (size, size) uint8
    """
    if isinstance(aircraft, str):
        aircraft = aircraft_model(aircraft)
    if not isinstance(aircraft, Aircraft):
        raise TypeError(f"aircraft must be an Aircraft or a name in {AIRCRAFT}")
    roll_deg = only_value_errors(as_real, roll_deg, "roll_deg")
    size = only_value_errors(as_int, size, "size", minimum=8)
    supersample = only_value_errors(as_int, supersample, "supersample", minimum=1)
    extent = only_value_errors(as_real, extent, "extent", 0.0, low_open=True)
    a = np.deg2rad(float(roll_deg))
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    t = aircraft.triangles @ rot.T
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    nn = np.linalg.norm(n, axis=1)
    good = nn > 0
    t, n = t[good], n[good] / nn[good, None]
    shade = 0.25 + 0.75 * np.abs(n @ _LIGHT)
    big = size * supersample
    scale = big / extent
    tris2 = np.stack([big / 2 + scale * t[..., 0], big / 2 - scale * t[..., 1]], -1)
    img = _rasterize(tris2, t[..., 2], shade, big)
    img = img.reshape(size, supersample, size, supersample).mean(axis=(1, 3))
    return np.clip(np.rint(255 * img), 0, 255).astype(np.uint8)


def render_rolls(name: str, rolls_deg, size: int = 64, supersample: int = 2) -> np.ndarray:
    """Render ``name`` at every roll of ``rolls_deg``; returns ``(len(rolls), size, size)`` uint8."""
    model = aircraft_model(name)
    rolls = np.atleast_1d(np.asarray(rolls_deg, dtype=float))
    if rolls.ndim != 1:
        raise ValueError(f"rolls_deg must be a scalar or 1-D, got shape {rolls.shape}")
    return np.stack([render(model, float(r), size, supersample) for r in rolls])

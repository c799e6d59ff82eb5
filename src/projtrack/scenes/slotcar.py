"""A synthetic slot-car video: a figure-eight track with a bridge that hides the car.

Stands in for the unpublished video of Example 3 of Marques et al. (2002), Fig. 9
(593 frames at 12 fps). Generator (:func:`make_slotcar_video`), image coordinates
``(row, col)`` in pixels, intensities in ``[0, 1]``:

* **Track**: the figure-eight (lemniscate of Gerono)
  ``col = W/2 + a cos(phi)``, ``row = H/2 + b sin(2 phi)`` with ``a = 0.38 W``,
  ``b = 0.36 H``, drawn as a dark band 4 px wide. The two branches cross at the centre.
* **Bridge**: the branch through ``phi = pi/2`` passes *over* the other one on a light
  deck (a band ``bridge_width`` px wide along that branch, with darker rails); a car on
  the other branch (``phi`` near ``3 pi/2``) is hidden while under the deck.
* **Background**: a fixed grass-like texture (white noise smoothed by a 3x3 box,
  std about 0.03, around 0.45), the same in every frame.
* **Car**: a bright blob (peak 0.95, Gaussian profile of std 0.9 px) averaged over 3
  sub-frame positions (motion blur). It drives with ``phi`` increasing; its speed along
  the track is ``speed (1 - 0.35 kappa / max kappa) (1 + e_t)`` px/frame, ``kappa`` the
  curvature and ``e_t`` an AR(1) process (coefficient 0.9, innovation std 0.05), so it
  slows in bends and varies from lap to lap.
* **Sensor noise**: i.i.d. ``N(0, noise^2)`` per pixel and frame (default 0.05).

Harder conditions (all off by default, so the default video is the easy case):

* **Illumination drift** (``illumination = a``): every frame is multiplied by a slowly
  varying gain ``1 + a sin(2 pi t / (20 fps) + phase)`` (a 20 s period, random phase), so
  a fixed background image no longer matches the scene;
* **Lower contrast** (``car_peak``): the car's peak intensity (default 0.95; the track is
  about 0.2 and the grass about 0.45);
* **Clutter** (``clutter = m``): a Poisson(``m``) number of car-like blobs per frame
  (peak ``0.8 car_peak``) at uniform random places, like reflections or people moving
  beside the track.

The true car positions and an ``occluded`` flag are returned with the frames.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from projtrack._validation import as_count, as_probability, as_real, as_rng, as_shape2, only_value_errors

__all__ = ["SlotCarVideo", "make_slotcar_video", "track_points"]


@dataclass
class SlotCarVideo:
    """Output of :func:`make_slotcar_video`.

    Attributes
    ----------
    frames : ndarray, shape (N, H, W), float32
    positions : ndarray, shape (N, 2)
        True car centre (row, col).
    occluded : ndarray of bool, shape (N,)
        True while the car is under the bridge.
    background : ndarray, shape (H, W)
        The noise-free empty scene (for reference; tracking estimates its own).
    fps : float
    """

    frames: np.ndarray
    positions: np.ndarray
    occluded: np.ndarray
    background: np.ndarray
    fps: float


def track_points(phi: np.ndarray, shape: tuple[int, int] = (48, 64)) -> np.ndarray:
    """Track centre-line points ``(row, col)`` at parameters ``phi`` for a frame ``shape``."""
    H, W = shape
    phi = np.asarray(phi, dtype=float)
    return np.column_stack([H / 2 + 0.36 * H * np.sin(2 * phi), W / 2 + 0.38 * W * np.cos(phi)])


def _dist_to_polyline(rr: np.ndarray, cc: np.ndarray, poly: np.ndarray) -> np.ndarray:
    P = np.stack([rr.ravel(), cc.ravel()], axis=1)
    d = np.min(((P[:, None, :] - poly[None]) ** 2).sum(-1), axis=1)
    return np.sqrt(d).reshape(rr.shape)


def _bridge_phi(phi: np.ndarray, half: float) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (np.asarray(phi) - np.pi / 2)))) < half


def make_slotcar_video(
    n_frames: int,
    rng: np.random.Generator,
    *,
    shape: tuple[int, int] = (48, 64),
    speed: float = 2.5,
    noise: float = 0.05,
    bridge_width: float = 7.0,
    fps: float = 12.0,
    scene_seed: int = 2002,
    illumination: float = 0.0,
    car_peak: float = 0.95,
    clutter: float = 0.0,
) -> SlotCarVideo:
    """Render a slot-car video (see the module docstring).

    Parameters
    ----------
    n_frames : int
        Number of frames (the paper's sequence has 593).
    rng : numpy.random.Generator
        Draws the start position, the speed fluctuations and the sensor noise.
    shape : (int, int)
        Frame size (H, W) in pixels.
    speed : float
        Mean speed on straight parts (px/frame), > 0.
    noise : float
        Std of the per-pixel sensor noise, >= 0.
    bridge_width : float
        Width of the bridge deck (px), > 0.
    fps : float
        Frame rate (only recorded), > 0.
    scene_seed : int
        Seed of the fixed background texture (the same scene for every run).
    illumination : float
        Amplitude of the illumination drift (relative gain), in [0, 1).
    car_peak : float
        Peak intensity of the car, in (0, 1].
    clutter : float
        Mean number of clutter blobs per frame, >= 0.

    Raises
    ------
    ValueError
        If ``n_frames`` is not a positive int, ``shape`` is not two ints >= 16, ``speed``,
        ``fps`` or ``bridge_width`` is not > 0, ``noise`` or ``clutter`` is negative,
        ``illumination`` is not in [0, 1) or ``car_peak`` not in (0, 1] (each message
        names the argument).
    """
    rng = as_rng(rng)
    n_frames = as_count(n_frames, "n_frames")
    H, W = as_shape2(shape)
    if H < 16 or W < 16:
        raise ValueError(f"shape must be at least 16 x 16, got {shape}")
    for name, value in (("speed", speed), ("fps", fps), ("bridge_width", bridge_width)):
        only_value_errors(as_real, value, name, 0, low_open=True)
    only_value_errors(as_real, noise, "noise", 0)
    only_value_errors(as_probability, illumination, "illumination", high_open=True)
    only_value_errors(as_probability, car_peak, "car_peak", low_open=True)
    only_value_errors(as_real, clutter, "clutter", 0)
    srng = np.random.default_rng(scene_seed)
    tex = srng.normal(0, 0.09, (H + 2, W + 2))
    tex = sum(tex[i:i + H, j:j + W] for i in range(3) for j in range(3)) / 9.0
    rr, cc = np.meshgrid(np.arange(H, dtype=float), np.arange(W, dtype=float), indexing="ij")
    bg = 0.45 + tex
    fine = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    poly = track_points(fine, shape)
    on_track = _dist_to_polyline(rr, cc, poly) < 2.0
    bg[on_track] = 0.2 + 0.3 * tex[on_track]
    # the bridge deck: a band along the over-branch (phi near pi/2)
    half = 0.9 * bridge_width / (0.38 * W)
    deck_line = poly[_bridge_phi(fine, half)]
    ddeck = _dist_to_polyline(rr, cc, deck_line)
    deck = ddeck < bridge_width / 2
    rails = deck & (ddeck > bridge_width / 2 - 1.0)
    deck_val = np.where(rails, 0.3, 0.7)
    under_half = 1.4 * bridge_width / (0.38 * W)
    # car motion along phi
    ds = np.gradient(poly, axis=0)
    dds = np.gradient(ds, axis=0)
    kappa = np.abs(ds[:, 0] * dds[:, 1] - ds[:, 1] * dds[:, 0]) / (np.linalg.norm(ds, axis=1) ** 3)
    speed_len = np.linalg.norm(ds, axis=1) / (fine[1] - fine[0])  # px per radian
    phi = rng.uniform(0, 2 * np.pi)
    e = 0.0
    light_phase = rng.uniform(0, 2 * np.pi) if illumination > 0 else 0.0
    frames = np.empty((n_frames, H, W), dtype=np.float32)
    pos = np.empty((n_frames, 2))
    occl = np.zeros(n_frames, dtype=bool)
    for t in range(n_frames):
        k = int(phi / (2 * np.pi) * len(fine)) % len(fine)
        v = speed * (1 - 0.35 * kappa[k] / kappa.max()) * (1 + e)
        dphi = v / speed_len[k]
        img = bg.copy()
        blob = np.zeros((H, W))
        for sub in (-1 / 3, 0.0, 1 / 3):
            p = track_points(np.array([phi + sub * dphi]), shape)[0]
            blob += np.exp(-0.5 * ((rr - p[0]) ** 2 + (cc - p[1]) ** 2) / 0.9**2) / 3
        p = track_points(np.array([phi]), shape)[0]
        under = bool(_bridge_phi(phi - np.pi, under_half))
        if under:
            img = img + blob * (car_peak - img)
            img = np.where(deck, deck_val, img)
            occl[t] = bool(deck[int(round(min(max(p[0], 0), H - 1))), int(round(min(max(p[1], 0), W - 1)))])
        else:
            # on the bridge or elsewhere the car is drawn on top of the deck
            img = np.where(deck, deck_val, img)
            img = img + blob * (car_peak - img)
        if clutter > 0:
            for _ in range(int(rng.poisson(clutter))):
                q = rng.uniform((0, 0), (H, W))
                spot = np.exp(-0.5 * ((rr - q[0]) ** 2 + (cc - q[1]) ** 2) / 0.9**2)
                img = img + spot * (0.8 * car_peak - img) * (0.8 * car_peak > img)
        if illumination > 0:
            img = img * (1 + illumination * np.sin(2 * np.pi * t / (20 * fps) + light_phase))
        frames[t] = img + noise * rng.standard_normal((H, W))
        pos[t] = p
        phi = (phi + dphi) % (2 * np.pi)
        e = 0.9 * e + 0.05 * rng.standard_normal()
    clean_bg = np.where(deck, deck_val, bg)
    return SlotCarVideo(frames=frames, positions=pos, occluded=occl, background=clean_bg, fps=float(fps))

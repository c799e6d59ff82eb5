"""Straight 3-D target tracks for the neural-net tracker (Barnard & Casasent, Sec. VI).

Chapter 5 of Casasent's 1989 report simulates ``N_T`` targets moving on straight,
constant-velocity tracks through ``N_P`` equally spaced time steps in a
``256 x 256 x 256`` space whose origin is the centre of the cube. The paper describes the
data only in words; :func:`make_tracks` follows that description:

* the target headings (in the x-y projection) are evenly spread over 360 degrees,
  ``phi_i = phi_0 + 2 pi i / N_T`` with a random ``phi_0``;
* the lengths of the tracks' x-y projections are uniform between ``max_length / 5`` and
  ``max_length`` (the paper's 5:1 ratio), with ``max_length = 0.7`` of the field (the
  longest track "occupying approximately 70% of the field of view");
* the z extent of each track, which the paper does not give, is uniform in
  ``[-z_ratio, z_ratio]`` times its x-y length (``z_ratio = 0.5``);
* each start point is uniform over the positions for which the whole track stays in the
  cube;
* measurement noise: "a uniformly distributed random number ... at most n% of its
  distance from the origin". Three readings (``noise_law``): ``"ball"`` (default) moves
  every position ``r`` by a vector uniform in the ball of radius ``n/100 * |r|``;
  ``"radial"`` scales it, ``r (1 + u)`` with ``u`` uniform in ``[-n/100, n/100]``;
  ``"coordinate"`` scales each coordinate on its own, ``r_k (1 + u_k)``. All three move
  a position by at most ``n% |r|``; the ball is the noisiest (root-mean-square
  displacement ``0.77 n% |r|`` against ``0.58 n% |r|`` for the other two).

Measurements of each frame are put in random order (``shuffle=True``); ``labels`` says
which target produced each one. Nothing here was tuned to any result of the paper.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from projtrack._validation import as_choice, as_count, as_int, as_real, as_rng

__all__ = ["TrackScene", "make_tracks", "perturb", "degrade", "NOISE_LAWS"]

#: The readings of the paper's noise, see :func:`perturb`.
NOISE_LAWS = ("ball", "radial", "coordinate")


@dataclass(frozen=True)
class TrackScene:
    """Synthetic measurements of straight 3-D tracks.

    Attributes
    ----------
    truth : ndarray, shape (n_frames, n_targets, 3)
        Noise-free positions, target ``i`` in row ``i`` of each frame (pixel units,
        origin at the centre of the cube).
    positions : ndarray, shape (n_frames, n_targets, 3)
        The measurements, in the (possibly shuffled) order of each frame.
    labels : ndarray of int, shape (n_frames, n_targets)
        ``labels[a, alpha]`` is the target that produced measurement ``alpha`` of frame ``a``.
    field : float
        Side of the cube (256 in the paper).
    """

    truth: np.ndarray
    positions: np.ndarray
    labels: np.ndarray
    field: float


def _check_noise_law(noise_law: object) -> str:
    if not isinstance(noise_law, str):
        raise TypeError(f"noise_law must be a str, got {type(noise_law).__name__}")
    return as_choice(noise_law, "noise_law", NOISE_LAWS)


def perturb(rng: np.random.Generator, positions: np.ndarray, noise_percent: float,
            noise_law: str = "ball") -> np.ndarray:
    """Move every position by at most ``n% * |r|``, by one of three laws.

    ``"ball"``: a vector uniform in the ball of radius ``n% * |r|``. ``"radial"``:
    ``r (1 + u)``, ``u`` uniform in ``[-n%, n%]``. ``"coordinate"``: ``r_k (1 + u_k)``,
    one independent ``u_k`` uniform in ``[-n%, n%]`` per coordinate.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness.
    positions : array_like, shape (..., 3)
        Positions relative to the centre of the space.
    noise_percent : float
        ``n`` in percent, >= 0.
    noise_law : {"ball", "radial", "coordinate"}, default "ball"
        How the noise is drawn (see :data:`NOISE_LAWS` and the module docstring).

    Returns
    -------
    ndarray
        Perturbed positions, same shape.
    """
    as_rng(rng)
    r = np.asarray(positions, dtype=float)
    if r.ndim < 1 or r.shape[-1] < 1:
        raise ValueError(f"positions must have shape (..., dim), got {r.shape}")
    if not np.all(np.isfinite(r)):
        raise ValueError("positions must be finite")
    noise_percent = as_real(noise_percent, "noise_percent", 0.0)
    _check_noise_law(noise_law)
    eps = noise_percent / 100.0
    if noise_law == "radial":
        return r * (1.0 + rng.uniform(-eps, eps, r.shape[:-1] + (1,)))
    if noise_law == "coordinate":
        return r * (1.0 + rng.uniform(-eps, eps, r.shape))
    dim = r.shape[-1]
    direction = rng.standard_normal(r.shape)
    direction /= np.linalg.norm(direction, axis=-1, keepdims=True)
    radius = rng.random(r.shape[:-1] + (1,)) ** (1.0 / dim)
    scale = eps * np.linalg.norm(r, axis=-1, keepdims=True)
    return r + scale * radius * direction


def make_tracks(rng: np.random.Generator, n_targets: int = 4, n_frames: int = 5, *,
                noise_percent: float = 0.0, noise_law: str = "ball", field: float = 256.0, max_length: float = 0.7,
                length_ratio: float = 5.0, z_ratio: float = 0.5,
                shuffle: bool = True) -> TrackScene:
    """Generate one data set of straight constant-velocity tracks (Sec. VI of the paper).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness.
    n_targets : int, default 4
        ``N_T`` (the paper: 4).
    n_frames : int, default 5
        ``N_P`` equally spaced time steps (the paper: 5), >= 2.
    noise_percent : float, default 0
        ``n``: each measurement moves by at most ``n%`` of its distance from the centre.
    noise_law : {"ball", "radial", "coordinate"}, default "ball"
        How that noise is drawn, see :func:`perturb`.
    field : float, default 256
        Side of the cube; coordinates lie in ``[-field/2, field/2]``.
    max_length : float, default 0.7
        Longest x-y track length as a fraction of ``field``.
    length_ratio : float, default 5
        Ratio of the longest to the shortest x-y track length.
    z_ratio : float, default 0.5
        Largest z extent of a track relative to its x-y length.
    shuffle : bool, default True
        Randomly order the measurements of each frame.

    Returns
    -------
    TrackScene
    """
    as_rng(rng)
    n_targets = as_int(n_targets, "n_targets", minimum=1)
    n_frames = as_int(n_frames, "n_frames", minimum=2)
    field = as_real(field, "field", 0.0, low_open=True)
    noise_percent = as_real(noise_percent, "noise_percent", 0.0)
    _check_noise_law(noise_law)
    if not (0 < max_length <= 1):
        raise ValueError(f"max_length must be in (0, 1], got {max_length}")
    if not (length_ratio >= 1):
        raise ValueError(f"length_ratio must be >= 1, got {length_ratio}")
    if not (z_ratio >= 0) or z_ratio * max_length > 1:
        raise ValueError(f"z_ratio must be >= 0 and keep tracks inside the cube, got {z_ratio}")
    phi = rng.uniform(0, 2 * np.pi) + 2 * np.pi * np.arange(n_targets) / n_targets
    length = field * max_length * rng.uniform(1.0 / length_ratio, 1.0, n_targets)
    dz = length * rng.uniform(-z_ratio, z_ratio, n_targets)
    extent = np.stack([length * np.cos(phi), length * np.sin(phi), dz], axis=1)  # (N_T, 3)
    half = field / 2.0
    lo = -half - np.minimum(extent, 0.0)
    hi = half - np.maximum(extent, 0.0)
    start = lo + (hi - lo) * rng.random((n_targets, 3))
    t = np.linspace(0.0, 1.0, n_frames)
    truth = start[None, :, :] + t[:, None, None] * extent[None, :, :]
    noisy = perturb(rng, truth, noise_percent, noise_law) if noise_percent > 0 else truth.copy()
    labels = np.tile(np.arange(n_targets), (n_frames, 1))
    if shuffle:
        labels = np.stack([rng.permutation(n_targets) for _ in range(n_frames)])
    positions = np.take_along_axis(noisy, labels[:, :, None], axis=1)
    return TrackScene(truth=truth, positions=positions, labels=labels, field=float(field))


def degrade(rng: np.random.Generator, scene: TrackScene, n_spurious: int = 0, n_missing: int = 0
            ) -> tuple[np.ndarray, np.ndarray]:
    """Add spurious measurements and delete detections, padding with zero vectors (Sec. IV).

    Every frame gets ``n_spurious`` extra measurements uniform over the cube. Then
    ``n_missing`` detections, chosen at random among the frames and targets, are removed;
    as in the paper, each frame is padded with zero vectors (the centre of the space) back
    to the common size ``N_M = N_T + n_spurious``.

    Returns
    -------
    positions : ndarray, shape (N_P, N_M, 3)
        Measurements in random order within each frame.
    labels : ndarray of int, shape (N_P, N_M)
        Target of each measurement; -1 for spurious ones. A zero vector that replaces a
        missing detection of target ``i`` is labelled ``i`` (assigning it to target ``i``
        is the right answer).
    """
    as_rng(rng)
    if not isinstance(scene, TrackScene):
        raise TypeError(f"scene must be a TrackScene, got {type(scene).__name__}")
    n_spurious = as_count(n_spurious, "n_spurious", minimum=0)
    n_missing = as_count(n_missing, "n_missing", minimum=0)
    n_p, n_t, _ = scene.positions.shape
    if n_missing > n_p * n_t:
        raise ValueError(f"n_missing must be <= N_P N_T = {n_p * n_t}, got {n_missing}")
    half = scene.field / 2
    order = np.argsort(scene.labels, axis=1)
    pos = np.take_along_axis(scene.positions, order[:, :, None], axis=1).copy()  # target order
    lab = np.tile(np.arange(n_t), (n_p, 1))
    miss = rng.choice(n_p * n_t, size=n_missing, replace=False)
    pos.reshape(-1, 3)[miss] = 0.0
    spur = rng.uniform(-half, half, (n_p, n_spurious, 3))
    pos = np.concatenate([pos, spur], axis=1)
    lab = np.concatenate([lab, np.full((n_p, n_spurious), -1)], axis=1)
    perm = np.stack([rng.permutation(n_t + n_spurious) for _ in range(n_p)])
    return np.take_along_axis(pos, perm[:, :, None], axis=1), np.take_along_axis(lab, perm, axis=1)

"""Synthetic image sequences with known ground truth, for the KL novelty chapter.

Stand-in for the controlled experiments of Vermeulen & Casasent (1988), whose 24-frame
sequence (two people in the background, one person entering the foreground) is not
published.  :func:`walking_sequence` makes such a sequence with everything known: a static
textured background, small "people" walking across the upper (far) half, a large person
entering the near half at a chosen frame, sub-pixel camera jitter and sensor noise, quantized
to 8 bits.  The ground truth (background, per-frame figure masks, jitter offsets) is returned
with the frames.  Nothing here is tuned to reproduce a number of the paper; the defaults are
round values chosen from the paper's description of its scene.
"""
from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
import numpy as np
from scipy import ndimage

from projtrack._validation import as_int, as_real, as_rng, as_shape2, only_value_errors

__all__ = ["WalkingSequence", "WalkingLayers", "PlazaExcerpt", "load_plaza_excerpt",
           "textured_background", "walking_layers", "walking_sequence"]


@dataclass(frozen=True)
class WalkingSequence:
    """A synthetic sequence and its ground truth.

    Attributes
    ----------
    frames : ndarray (n_frames, H, W) uint8
    masks : ndarray (n_frames, H, W) bool
        Pixels covered by a figure in each frame.
    foreground_masks : ndarray (n_frames, H, W) bool
        Pixels covered by the entering (foreground) person.
    background : ndarray (H, W) float
        The static background before jitter, noise and quantization.
    offsets : ndarray (n_frames, 2)
        Camera jitter (row, column) shift of each frame in pixels.
    entry_frame : int
        1-based frame in which the foreground person first appears.
    """

    frames: np.ndarray
    masks: np.ndarray
    foreground_masks: np.ndarray
    background: np.ndarray
    offsets: np.ndarray
    entry_frame: int


@dataclass(frozen=True)
class PlazaExcerpt:
    """The committed 24-frame excerpt of OpenCV's ``vtest.avi`` (see ``plaza-excerpt.md``).

    Attributes
    ----------
    frames : ndarray (24, 128, 128) uint8
        One frame per second, grey, centred square crop resized to 128x128.
    source_frame_index : ndarray (24,)
        Frame numbers in ``vtest.avi`` (10 fps).
    entry_position : int
        0-based index of the frame where the window rule detected a person entering the
        lower (near) half of the image.
    source : str
        Where the video came from (Debian package and version).
    """

    frames: np.ndarray
    source_frame_index: np.ndarray
    entry_position: int
    source: str


def load_plaza_excerpt() -> PlazaExcerpt:
    """Load ``projtrack/data/plaza-excerpt.npz`` (real stand-in for Figs. 2-3).

    Written by ``tools/fetch_plaza_video.py`` from Debian's ``opencv-doc``; provenance,
    licence and the rule that chose the window are in ``projtrack/data/plaza-excerpt.md``.
    """
    raw = resources.files("projtrack").joinpath("data/plaza-excerpt.npz").read_bytes()
    with np.load(io.BytesIO(raw)) as d:
        return PlazaExcerpt(d["frames"].copy(), d["source_frame_index"].copy(),
                            int(d["entry_position"]), str(d["source"]))


def _check_shape(shape) -> tuple[int, int]:
    """A ``(H, W)`` pair of ints, each at least 16 (room for the walking figures)."""
    h, w = as_shape2(shape, "shape")
    if h < 16 or w < 16:
        raise ValueError(f"shape must be at least (16, 16), got {shape!r}")
    return h, w


def _as_level(value, name: str) -> float:
    """A finite number >= 0 (a length, a speed, a grey level); any bad value is a ValueError."""
    return only_value_errors(as_real, value, name, 0.0)


def textured_background(shape: tuple[int, int], rng: np.random.Generator,
                        correlation_length: float = 3.0, mean: float = 120.0,
                        contrast: float = 35.0) -> np.ndarray:
    """A static textured background: smoothed white noise plus a vertical brightness ramp.

    Parameters
    ----------
    shape : (H, W)
    rng : numpy.random.Generator
    correlation_length : float
        Standard deviation (pixels) of the Gaussian smoothing of the noise.
    mean, contrast : float
        Mean grey level and standard deviation of the texture (grey levels); the ramp adds
        +-``contrast/2`` from top to bottom (a ground plane lit unevenly).

    Returns
    -------
    ndarray (H, W) float
    """
    h, w = _check_shape(shape)
    rng = as_rng(rng)
    for name, v in (("correlation_length", correlation_length), ("mean", mean),
                    ("contrast", contrast)):
        _as_level(v, name)
    tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), correlation_length, mode="wrap")
    tex = (tex - tex.mean()) / (tex.std() + 1e-12)
    ramp = np.linspace(-0.5, 0.5, h)[:, None]
    return mean + contrast * tex + contrast * ramp


def _person(rows: np.ndarray, cols: np.ndarray, r: float, c: float, height: float) -> np.ndarray:
    """Mask of a standing figure (ellipse body + round head) with feet at (r, c)."""
    bh, bw = 0.38 * height, 0.16 * height          # body half-height, half-width
    br = r - bh                                     # body centre row
    body = ((rows - br) / bh) ** 2 + ((cols - c) / bw) ** 2 <= 1.0
    hr = r - 2 * bh - 0.1 * height                  # head centre
    head = (rows - hr) ** 2 + (cols - c) ** 2 <= (0.11 * height) ** 2
    return body | head


@dataclass(frozen=True)
class WalkingLayers:
    """One draw of :func:`walking_sequence` before the people's contrasts are applied and it is rounded.

    ``frames(people_contrast, foreground_contrast)`` gives the 8-bit frames
    ``clip(rint(base + people_contrast walkers + foreground_contrast person))``: the draw of
    :func:`walking_sequence` with those contrasts, bit for bit, so a study can vary the
    contrasts of one draw without drawing it again.

    Attributes
    ----------
    base : ndarray (n_frames, H, W) float
        The exposed scene behind the people plus the sensor noise.
    walkers, person : ndarray (n_frames, H, W) float
        How far the background walkers and the entering person depart from the scene behind
        them at contrast 1 (exposed; zero elsewhere).
    masks, foreground_masks, background, offsets, entry_frame
        As in :class:`WalkingSequence`.
    """

    base: np.ndarray
    walkers: np.ndarray
    person: np.ndarray
    masks: np.ndarray
    foreground_masks: np.ndarray
    background: np.ndarray
    offsets: np.ndarray
    entry_frame: int

    def frames(self, people_contrast: float = 1.0, foreground_contrast: float | None = None) -> np.ndarray:
        """The 8-bit frames with the given contrasts (``foreground_contrast`` defaults to ``people_contrast``)."""
        _as_level(people_contrast, "people_contrast")
        if foreground_contrast is None:
            foreground_contrast = people_contrast
        _as_level(foreground_contrast, "foreground_contrast")
        x = self.base + people_contrast * self.walkers + foreground_contrast * self.person
        return np.clip(np.rint(x), 0, 255).astype(np.uint8)


def walking_layers(rng: np.random.Generator, n_frames: int = 24,
                   shape: tuple[int, int] = (128, 128), n_background_figures: int = 2,
                   entry_frame: int = 8, background_height: float = 14.0,
                   foreground_height: float = 48.0, background_speed: float = 2.0,
                   foreground_speed: float = 7.0, figure_grey: float = 45.0,
                   jitter: float = 0.25, noise_std: float = 2.0, gain: float = 1.0,
                   jitter_frames: Sequence[int] | None = None) -> WalkingLayers:
    """The layers of a :func:`walking_sequence` draw (its parameters but the contrasts; see there)."""
    rng = as_rng(rng)
    h, w = _check_shape(shape)
    n_frames = only_value_errors(as_int, n_frames, "n_frames", minimum=1)
    n_background_figures = only_value_errors(as_int, n_background_figures, "n_background_figures",
                                          minimum=0)
    entry_frame = only_value_errors(as_int, entry_frame, "entry_frame", minimum=0)
    for name, v in (("background_height", background_height),
                    ("foreground_height", foreground_height),
                    ("background_speed", background_speed),
                    ("foreground_speed", foreground_speed), ("figure_grey", figure_grey),
                    ("jitter", jitter), ("noise_std", noise_std), ("gain", gain)):
        _as_level(v, name)
    if jitter_frames is not None:
        try:
            jitter_frames = frozenset(only_value_errors(as_int, f, "jitter_frames", minimum=1)
                                      for f in jitter_frames)
        except TypeError:
            raise ValueError("jitter_frames must be a sequence of 1-based frame numbers") from None
    background = textured_background((h, w), rng)
    rows, cols = np.mgrid[0:h, 0:w].astype(float)
    # background walkers: feet row in the upper half, random start and direction
    feet = rng.uniform(0.25 * h, 0.5 * h, n_background_figures)
    start = rng.uniform(0.1 * w, 0.9 * w, n_background_figures)
    direction = rng.choice([-1.0, 1.0], n_background_figures)
    offsets = np.zeros((n_frames, 2))
    base = np.empty((n_frames, h, w))
    walkers = np.zeros((n_frames, h, w))
    person = np.zeros((n_frames, h, w))
    masks = np.zeros((n_frames, h, w), dtype=bool)
    fg_masks = np.zeros((n_frames, h, w), dtype=bool)
    for t in range(n_frames):
        # drawn frame by frame, always (even when jitter or noise_std is 0): the first k frames
        # are the same for any n_frames >= k, and for any jitter, noise, gain and contrasts
        offsets[t] = jitter * rng.standard_normal(2) * (jitter_frames is None or t + 1 in jitter_frames)
        noise = noise_std * rng.standard_normal((h, w))
        # an in-sync frame is the background itself (a zero bilinear shift changes no value)
        scene = (ndimage.shift(background, offsets[t], order=1, mode="nearest") if offsets[t].any()
                 else background)
        m = np.zeros((h, w), dtype=bool)
        for k in range(n_background_figures):
            c = (start[k] + direction[k] * background_speed * t) % w
            m |= _person(rows, cols, feet[k], c, background_height)
        fg = np.zeros((h, w), dtype=bool)
        if entry_frame >= 1 and t + 1 >= entry_frame:
            c = -0.1 * foreground_height + foreground_speed * (t + 1 - entry_frame) + 0.2 * foreground_height
            fg = _person(rows, cols, 0.92 * h, c, foreground_height)
        figure = gain * 0.8 * (figure_grey - scene)   # a figure's departure from the scene behind it
        base[t] = gain * scene + noise
        person[t] = np.where(fg, figure, 0.0)
        walkers[t] = np.where(m & ~fg, figure, 0.0)    # the person in front where they overlap
        masks[t], fg_masks[t] = m | fg, fg
    return WalkingLayers(base, walkers, person, masks, fg_masks, background, offsets, int(entry_frame))


def walking_sequence(rng: np.random.Generator, n_frames: int = 24,
                     shape: tuple[int, int] = (128, 128), n_background_figures: int = 2,
                     entry_frame: int = 8, background_height: float = 14.0,
                     foreground_height: float = 48.0, background_speed: float = 2.0,
                     foreground_speed: float = 7.0, figure_grey: float = 45.0,
                     jitter: float = 0.25, noise_std: float = 2.0, gain: float = 1.0,
                     people_contrast: float = 1.0, foreground_contrast: float | None = None,
                     jitter_frames: Sequence[int] | None = None) -> WalkingSequence:
    """A fixed-camera sequence of people walking, with ground truth (Figs. 2-3 stand-in).

    ``n_background_figures`` small figures (height ``background_height`` px) walk
    horizontally across the upper half at ``background_speed`` px/frame (random rows, start
    columns and directions drawn from ``rng``); from frame ``entry_frame`` (1-based) a large
    figure (``foreground_height`` px) enters the lower half from the left at
    ``foreground_speed`` px/frame.  Figures have grey level ``figure_grey`` with the
    background texture showing through at 20 %.  Every frame is shifted by an independent
    normal sub-pixel camera jitter (std ``jitter`` px, bilinear; with ``jitter_frames``, only
    those 1-based frames are shifted and the others are in sync) and Gaussian sensor noise
    (std ``noise_std`` grey levels) is added before rounding and clipping to uint8.  Jitter and
    noise are drawn frame by frame, so the first ``k`` frames of a draw do not depend on
    ``n_frames``.

    Three knobs change the scene without changing its random draw (the same ``rng`` gives the
    same texture, paths, jitter and noise whatever their values):

    - ``gain`` multiplies the scene's grey levels (background and figures) before the noise is
      added: a darker or brighter exposure of the same scene with the same sensor noise;
    - ``people_contrast`` scales how far the background walkers depart from the scene behind
      them (1: grey level ``figure_grey`` with 20 % of the texture showing through; 0:
      invisible), like ``B + alpha (x - B)`` on a recorded video;
    - ``foreground_contrast`` does the same for the entering person (default: the same as
      ``people_contrast``).

    Returns
    -------
    WalkingSequence
    """
    layers = walking_layers(rng, n_frames, shape, n_background_figures, entry_frame, background_height,
                            foreground_height, background_speed, foreground_speed, figure_grey, jitter,
                            noise_std, gain, jitter_frames)
    return WalkingSequence(layers.frames(people_contrast, foreground_contrast), layers.masks,
                           layers.foreground_masks, layers.background, layers.offsets, layers.entry_frame)

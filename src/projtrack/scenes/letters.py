"""Binary upper-case letters on a 32 x 32 grid, for Casasent & Song's projection correlations.

Chapter 2 of Casasent's 1989 report (D. Casasent and J.-H. Song, "Optical projection
correlations", Appl. Opt. 27, 1988), Sec. III.A, tests its correlators on "the 26
upper-case letters in the Times font ... digitized to 32 x 32 binary pixels. Most letters
occupied the central 10 x 10 pixels and had 40-75 nonzero pixels and all letters had
less than 110 nonzero pixels". The original bitmaps were not published. This module
synthesizes stand-ins from the Times-like STIX font that matplotlib ships
(``STIXGeneral.ttf``; nothing is downloaded), with one size rule for all letters:

* the glyph outline is scaled so that the font's **cap height** (the height of ``H``)
  is ``cap_height`` pixels (default 8.5, see below);
* each glyph's bounding box is centred on the centre of the frame;
* a pixel is on when at least a fraction ``min_coverage`` of its area lies inside the
  glyph, measured by ``supersample x supersample`` point sampling of the pixel.

The pair (``cap_height``, ``min_coverage``) is fixed once for all letters by
:func:`calibrate_rule` on what the paper says about its bitmaps: the letter C "has 43
nonzero pixels" (Sec. III.B), and the description of Sec. III.A (:func:`fits_description`:
every letter under 110 pixels, most in a 10 x 10 box). The candidates are the centred STIX
glyphs of the cap heights :data:`ENSEMBLE_CAP_HEIGHTS`, each with the coverage threshold
that gives C exactly 43 pixels; of those that fit the description, ties go to the most
letters with 40-75 pixels, then the smallest cap height, then the largest threshold. The
result, cap height 8.5 with a pixel on when 2 of its 64 sub-samples are inside the glyph
(``min_coverage = 1/32``), is the default: 23 of the 26 letters fit a 10 x 10 box and 21
have 40-75 pixels. :func:`choose_rule`, a rule picked from the pixel counts alone on a
coarser grid, gives a thicker 55-pixel C and is kept for comparison. No letter is
adjusted individually; glyphs wider than tall (``M``, ``W``) extend a little beyond the
box, as in any Times font.
"""

from __future__ import annotations

import string
from functools import lru_cache
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.font_manager import FontProperties
from matplotlib.path import Path as MplPath
from matplotlib.textpath import TextPath

from projtrack._validation import as_array, as_choice, as_int, as_probability, as_real, as_rng

__all__ = ["LETTERS", "CAP_HEIGHT", "MIN_COVERAGE", "FONTS", "font_path", "coverage_map", "render_letter",
           "alphabet", "noisy", "pixel_counts", "rule_grid", "choose_rule", "calibrate_rule", "coverage_for_count",
           "ENSEMBLE_CAP_HEIGHTS", "ENSEMBLE_OFFSETS", "glyph_ensemble", "MOST", "box_side", "fits_description",
           "calibration_grid"]

#: The 26 upper-case letters in alphabetical order.
LETTERS: str = string.ascii_uppercase

#: Default cap height in pixels (calibrated by :func:`calibrate_rule` on the 43-pixel C and
#: the description of Sec. III.A).
CAP_HEIGHT: float = 8.5

#: Default minimum covered fraction of a pixel's area for it to be on (calibrated likewise:
#: 2 of the 64 sub-samples of a pixel).
MIN_COVERAGE: float = 0.03125


#: Serif fonts that ship with matplotlib (files in its ``fonts/ttf`` folder), by name: the
#: Times-like STIX (the default) and, for glyph ensembles, DejaVu Serif and Computer Modern.
FONTS: dict[str, str] = {"STIX": "STIXGeneral.ttf", "DejaVu Serif": "DejaVuSerif.ttf",
                         "Computer Modern": "cmr10.ttf"}


def font_path(font: str = "STIX") -> Path:
    """Path of one of matplotlib's bundled fonts of :data:`FONTS` (default: STIX, ``STIXGeneral.ttf``)."""
    font = as_choice(font, "font", tuple(FONTS))
    path = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / FONTS[font]
    if not path.is_file():  # pragma: no cover - matplotlib always ships it
        raise FileNotFoundError(f"matplotlib's {font} font is missing: {path}")
    return path


@lru_cache(maxsize=None)
def _glyph(letter: str, font: str = "STIX") -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """Outline polygons of a glyph at font size 1 and the font's cap height."""
    prop = FontProperties(fname=str(font_path(font)))
    cap = TextPath((0, 0), "H", size=1.0, prop=prop).get_extents().height
    path = TextPath((0, 0), letter, size=1.0, prop=prop)
    polys = tuple(np.asarray(p, dtype=float) for p in path.to_polygons(closed_only=True))
    return np.array([cap]), polys


def _as_offset(offset: object) -> tuple[float, float]:
    if not isinstance(offset, (tuple, list)) or len(offset) != 2:
        raise ValueError(f"offset must be a pair (dx, dy) of pixel shifts, got {offset!r}")
    return as_real(offset[0], "offset[0]", -1.0, 1.0), as_real(offset[1], "offset[1]", -1.0, 1.0)


def coverage_map(letter: str, size: int = 32, cap_height: float = CAP_HEIGHT, supersample: int = 8, *,
                 font: str = "STIX", offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Fraction of each pixel's area inside the glyph of ``letter`` (see :func:`render_letter`).

    Parameters
    ----------
    letter, size, cap_height, supersample
        As for :func:`render_letter`.
    font : str, default "STIX"
        A name of :data:`FONTS`.
    offset : (float, float), default (0, 0)
        Sub-pixel shift ``(dx, dy)`` of the glyph, to the right and up, in pixels (each in
        [-1, 1]), from the position that centres its bounding box on the frame's centre.

    Returns
    -------
    numpy.ndarray
        ``(size, size)`` covered fractions, multiples of ``1 / supersample**2``; row 0 is
        the top.
    """
    if not isinstance(letter, str) or len(letter) != 1 or letter not in LETTERS:
        raise ValueError(f"letter must be one upper-case letter A-Z, got {letter!r}")
    size = as_int(size, "size", minimum=4)
    supersample = as_int(supersample, "supersample", minimum=1)
    cap_height = as_real(cap_height, "cap_height", 0.0, size, low_open=True, high_open=True)
    dx, dy = _as_offset(offset)
    return _block_mean(_mask(letter, size, cap_height, supersample, as_choice(font, "font", tuple(FONTS)), (dx, dy)),
                       supersample)


def _mask(letter: str, size: int, cap_height: float, supersample: int, font: str,
          offset: tuple[float, float]) -> np.ndarray:
    """Sub-samples (``size * supersample`` square, row 0 at the top) inside the glyph, as floats 0/1."""
    dx, dy = offset
    cap, polys = _glyph(letter, font)
    scale = float(cap_height) / float(cap[0])
    pts = np.concatenate(polys)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = (lo + hi) / 2
    if np.any((hi - lo) * scale > size - 2):
        raise ValueError(f"letter {letter!r} does not fit a {size}-pixel frame at cap_height={cap_height}")
    # The glyph's box in pixel units (x to the right, y up; the frame spans [0, size]): only
    # sub-samples of the pixels it touches can be inside the glyph.
    x_lo, y_lo = (lo - centre) * scale + size / 2 + (dx, dy)
    x_hi, y_hi = (hi - centre) * scale + size / 2 + (dx, dy)
    c0, c1 = max(int(np.floor(x_lo)), 0), min(int(np.ceil(x_hi)), size)
    r0, r1 = max(size - int(np.ceil(y_hi)), 0), min(size - int(np.floor(y_lo)), size)
    sx = c0 + (np.arange((c1 - c0) * supersample) + 0.5) / supersample
    sy = size - r0 - (np.arange((r1 - r0) * supersample) + 0.5) / supersample  # row r0 at the top
    xx, yy = np.meshgrid(sx, sy)
    points = np.column_stack([xx.ravel(), yy.ravel()])
    # Glyph coordinates of each sample point.
    glyph_pts = (points - size / 2 - (dx, dy)) / scale + centre
    box = np.all((glyph_pts >= lo) & (glyph_pts <= hi), axis=1)
    # Even-odd rule over all contours handles holes (A, B, D, O, P, Q, R).
    inside_box = np.zeros(int(box.sum()), dtype=bool)
    for poly in polys:
        inside_box ^= MplPath(poly).contains_points(glyph_pts[box])
    inside = np.zeros(len(points), dtype=bool)
    inside[box] = inside_box
    mask = np.zeros((size * supersample, size * supersample))
    mask[r0 * supersample:r1 * supersample, c0 * supersample:c1 * supersample] = inside.reshape(
        (r1 - r0) * supersample, (c1 - c0) * supersample)
    return mask


def render_letter(letter: str, size: int = 32, cap_height: float = CAP_HEIGHT,
                  min_coverage: float = MIN_COVERAGE, supersample: int = 8, *, font: str = "STIX",
                  offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Rasterize one upper-case letter to a binary ``size x size`` image.

    Parameters
    ----------
    letter : str
        One character of :data:`LETTERS`.
    size : int, default 32
        Side of the square frame in pixels (Sec. III.A uses 32).
    cap_height : float, default :data:`CAP_HEIGHT`
        Height in pixels of the font's cap height after scaling.
    min_coverage : float, default :data:`MIN_COVERAGE`
        A pixel is on when at least this fraction of its sub-samples is inside the glyph.
    supersample : int, default 8
        Sub-samples per pixel side used to measure the covered area.
    font : str, default "STIX"
        A name of :data:`FONTS`.
    offset : (float, float), default (0, 0)
        Sub-pixel shift of the glyph (see :func:`coverage_map`).

    Returns
    -------
    numpy.ndarray
        ``float`` array of shape ``(size, size)`` with values 0 and 1; row 0 is the top.

    Raises
    ------
    ValueError
        If ``letter`` is not one upper-case ASCII letter, the glyph does not fit (with a
        margin of one pixel), or an argument is out of range.
    """
    min_coverage = as_probability(min_coverage, "min_coverage", low_open=True)
    cover = coverage_map(letter, size, cap_height, supersample, font=font, offset=offset)
    return (cover >= min_coverage - 1e-12).astype(float)


def alphabet(size: int = 32, cap_height: float = CAP_HEIGHT, min_coverage: float = MIN_COVERAGE,
             supersample: int = 8, *, font: str = "STIX", offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """All 26 letters, :func:`render_letter` of ``A``..``Z``, shape ``(26, size, size)``."""
    return np.stack([render_letter(c, size, cap_height, min_coverage, supersample, font=font, offset=offset)
                     for c in LETTERS])


#: "Most letters" of Sec. III.A: at least this many of the 26.
MOST: int = 14


def box_side(images: np.ndarray, most: int = MOST) -> int:
    """Side of the smallest square box that holds the bounding box of at least ``most`` images.

    Sec. III.A: "Most letters occupied the central 10 x 10 pixels": the description holds
    when ``box_side(alphabet) <= 10``. Each image's bounding box is the rows and columns
    holding a nonzero pixel; its side is the larger of its height and width.
    """
    images = as_array(np.asarray(images, dtype=float), "images", ndim=3, allow_empty=False)
    most = as_int(most, "most", minimum=1)
    if most > len(images):
        raise ValueError(f"most must be at most the number of images {len(images)}, got {most}")
    on = images != 0
    if not np.all(on.any(axis=(1, 2))):
        raise ValueError("every image needs a nonzero pixel to have a bounding box")
    sides = []
    for m in on:
        r, c = np.nonzero(m.any(axis=1))[0], np.nonzero(m.any(axis=0))[0]
        sides.append(max(r[-1] - r[0] + 1, c[-1] - c[0] + 1))
    return int(np.sort(sides)[most - 1])


def fits_description(images: np.ndarray, *, box: int | None = 10) -> bool:
    """Whether 26 binary letters fit the description of Sec. III.A.

    "Most letters occupied the central 10 x 10 pixels and had 40-75 nonzero pixels and all
    letters had less than 110 nonzero pixels": every letter under 110 pixels, most (at
    least :data:`MOST` = 14) with 40-75, and most inside a ``box x box`` square
    (:func:`box_side`; ``box=None`` leaves the size part out, the pixel counts only).
    """
    images = as_array(np.asarray(images, dtype=float), "images", ndim=3, allow_empty=False)
    counts = pixel_counts(images)
    ok = bool(counts.max() < 110 and np.sum((counts >= 40) & (counts <= 75)) >= MOST)
    if box is not None:
        ok = ok and box_side(images) <= as_int(box, "box", minimum=1)
    return ok


def rule_grid(cap_heights: tuple[float, ...] = (10.0, 11.0, 12.0),
              min_coverages: tuple[float, ...] = (0.5, 0.25, 1.0 / 64.0)) -> list[dict[str, float]]:
    """Pixel-count statistics of the 26 letters for each candidate size rule.

    Returns
    -------
    list of dict
        One dict per (cap height, coverage) with keys ``cap_height``, ``min_coverage``,
        ``n_in_40_75`` (letters with 40-75 on-pixels), ``min``, ``median``, ``max``, ``box``
        (:func:`box_side`) and ``C`` (on-pixels of the letter C, the count Sec. III.B gives).
    """
    out = []
    for cap in cap_heights:
        for cov in min_coverages:
            a = alphabet(cap_height=cap, min_coverage=cov)
            counts = pixel_counts(a)
            out.append({"cap_height": float(cap), "min_coverage": float(cov),
                        "n_in_40_75": int(np.sum((counts >= 40) & (counts <= 75))),
                        "min": int(counts.min()), "median": float(np.median(counts)),
                        "max": int(counts.max()), "box": box_side(a), "C": int(counts[LETTERS.index("C")])})
    return out


def choose_rule(grid: list[dict[str, float]] | None = None) -> tuple[float, float]:
    """The size rule that best matches the pixel counts of Sec. III.A (its size part left out).

    Most letters with 40-75 on-pixels, all letters under 110, ties to the smallest cap
    height then the largest coverage threshold. Returns ``(cap_height, min_coverage)``.
    """
    grid = rule_grid() if grid is None else grid
    ok = [g for g in grid if g["max"] < 110]
    if not ok:
        raise ValueError("no candidate rule keeps every letter under 110 pixels")
    best = max(ok, key=lambda g: (g["n_in_40_75"], -g["cap_height"], g["min_coverage"]))
    return best["cap_height"], best["min_coverage"]


def calibration_grid(cap_heights: tuple[float, ...] | None = None, *, letter: str = "C", pixels: int = 43,
                     font: str = "STIX") -> list[dict[str, object]]:
    """The candidate size rules of :func:`calibrate_rule`: centred glyphs of one font, each cap
    height with the coverage threshold that gives ``letter`` exactly ``pixels`` pixels.

    The rows of :func:`glyph_ensemble` at offset (0, 0) for ``font`` and ``cap_heights``
    (default :data:`ENSEMBLE_CAP_HEIGHTS`), each with the key ``letter`` set to ``pixels``;
    a cap height at which no threshold gives the count is left out.
    """
    caps = ENSEMBLE_CAP_HEIGHTS if cap_heights is None else cap_heights
    rows = glyph_ensemble((font,), tuple(caps), (0.0,), letter=letter, pixels=pixels)
    return [r | {letter: pixels} for r in rows]


def calibrate_rule(grid: list[dict[str, float]] | None = None, *, letter: str = "C",
                   pixels: int = 43) -> tuple[float, float]:
    """The size rule calibrated on what the paper says about its bitmaps (Secs. III.A-B).

    Among the rules of ``grid`` that keep every letter under 110 pixels and, where a row has
    the key ``box`` (:func:`box_side`), put most letters in a 10 x 10 box (Sec. III.A),
    keep those whose ``letter`` has exactly ``pixels`` on-pixels (Sec. III.B: C has 43);
    ties go to the most letters in the 40-75 range, then the smallest cap height, then the
    largest coverage threshold.

    Parameters
    ----------
    grid : list of dict, optional
        Candidate rules, e.g. :func:`calibration_grid` (the default) or :func:`rule_grid`.
        Each dict needs ``cap_height``, ``min_coverage``, ``n_in_40_75``, ``max`` and the
        on-pixel count of ``letter`` under the key ``letter``.
    letter : str, default "C"
        The letter whose count pins the rule.
    pixels : int, default 43
        Its number of on-pixels.

    Returns
    -------
    tuple of float
        ``(cap_height, min_coverage)``.

    Raises
    ------
    ValueError
        If ``letter`` is not an upper-case letter, ``pixels`` is not a positive int, a
        dict lacks the letter's count, or no rule of the grid fits.
    """
    if not isinstance(letter, str) or len(letter) != 1 or letter not in LETTERS:
        raise ValueError(f"letter must be one upper-case letter A-Z, got {letter!r}")
    pixels = as_int(pixels, "pixels", minimum=1)
    grid = calibration_grid(letter=letter, pixels=pixels) if grid is None else grid
    if any(letter not in g for g in grid):
        raise ValueError(f"every rule of the grid needs the on-pixel count of {letter!r} (key {letter!r})")
    ok = [g for g in grid if g["max"] < 110 and int(g[letter]) == pixels and g.get("box", 0) <= 10]
    if not ok:
        raise ValueError(f"no candidate rule gives {letter!r} exactly {pixels} pixels and fits the description")
    best = max(ok, key=lambda g: (g["n_in_40_75"], -g["cap_height"], g["min_coverage"]))
    return float(best["cap_height"]), float(best["min_coverage"])


def coverage_for_count(cover: np.ndarray, pixels: int) -> float:
    """The coverage threshold that turns on exactly ``pixels`` pixels of a :func:`coverage_map`.

    The threshold is the ``pixels``-th largest covered fraction; it is NaN when no
    threshold in (0, 1] gives exactly that count (a tie at the boundary, or too few
    pixels touched by the glyph).
    """
    cover = as_array(cover, "cover", ndim=2, allow_empty=False)
    pixels = as_int(pixels, "pixels", minimum=1)
    v = np.sort(cover.ravel())[::-1]
    if pixels > v.size or v[pixels - 1] <= 0 or (pixels < v.size and v[pixels] == v[pixels - 1]):
        return float("nan")
    return float(v[pixels - 1])


#: Cap heights (pixels) of the default glyph ensemble: from the smallest at which a C of any
#: font can have 43 pixels to letters 12-13 pixels tall, around the "central 10 x 10 pixels".
ENSEMBLE_CAP_HEIGHTS: tuple[float, ...] = (8.0, 8.5, 9.0, 9.5, 10.0, 10.5, 11.0, 11.5, 12.0)

#: Sub-pixel shifts (pixels, along each axis) of the default glyph ensemble.
ENSEMBLE_OFFSETS: tuple[float, ...] = (0.0, 0.25, 0.5, 0.75)


def glyph_ensemble(fonts: tuple[str, ...] = tuple(FONTS), cap_heights: tuple[float, ...] = ENSEMBLE_CAP_HEIGHTS,
                   offsets: tuple[float, ...] = ENSEMBLE_OFFSETS, *, letter: str = "C", pixels: int = 43,
                   supersample: int = 8) -> list[dict[str, object]]:
    """Glyph sets that all give ``letter`` exactly ``pixels`` pixels (Sec. III.B: C has 43).

    The printed pixel count pins how many pixels the C has, not the font, its size or its
    position on the grid. For every font of ``fonts``, cap height and sub-pixel shift
    ``(dx, dy)`` (both from ``offsets``), the coverage threshold is the one that gives
    ``letter`` exactly ``pixels`` pixels (:func:`coverage_for_count`; a combination with
    no such threshold is left out), and the same rule renders all 26 letters.

    Returns
    -------
    list of dict
        One dict per combination with a threshold: ``font``, ``cap_height``, ``dx``,
        ``dy``, ``min_coverage``, ``n_in_40_75`` (letters with 40-75 pixels), ``max``
        (the largest count), ``box`` (:func:`box_side`: most letters fit a ``box x box``
        square), ``fits_counts`` (the pixel counts of Sec. III.A: every letter under 110
        pixels and most, at least 14 of 26, in 40-75) and ``fits`` (also most letters in
        a 10 x 10 box: the whole description, :func:`fits_description`).
    """
    if not fonts or not cap_heights or not offsets:
        raise ValueError("fonts, cap_heights and offsets must not be empty")
    fonts = tuple(as_choice(f, "fonts", tuple(FONTS)) for f in fonts)
    pixels = as_int(pixels, "pixels", minimum=1)
    supersample = as_int(supersample, "supersample", minimum=1)
    steps = [as_real(v, "offsets", -1.0, 1.0) * supersample for v in offsets]
    if any(abs(v - round(v)) > 1e-9 for v in steps):
        raise ValueError(f"offsets must be multiples of 1/supersample = {1 / supersample:g}, got {offsets!r}")
    out: list[dict[str, object]] = []
    for font in fonts:
        for cap in cap_heights:
            # sub-sample masks at offset (0, 0); a shift by whole sub-samples moves them exactly
            masks = {ch: _subsample_mask(ch, 32, float(cap), supersample, font) for ch in LETTERS}
            for dx, sx in zip(offsets, steps):
                for dy, sy in zip(offsets, steps):
                    covers = {ch: _block_mean(np.roll(m, (-int(round(sy)), int(round(sx))), axis=(0, 1)), supersample)
                              for ch, m in masks.items()}
                    t = coverage_for_count(covers[letter], pixels)
                    if not np.isfinite(t):
                        continue
                    images = np.stack([(covers[ch] >= t - 1e-12).astype(float) for ch in LETTERS])
                    counts = pixel_counts(images)
                    n_in = int(np.sum((counts >= 40) & (counts <= 75)))
                    box = box_side(images)
                    fits_counts = bool(counts.max() < 110 and n_in >= MOST)
                    out.append({"font": font, "cap_height": float(cap), "dx": float(dx), "dy": float(dy),
                                "min_coverage": t, "n_in_40_75": n_in, "max": int(counts.max()), "box": box,
                                "fits_counts": fits_counts, "fits": fits_counts and box <= 10})
    return out


def _subsample_mask(letter: str, size: int, cap_height: float, supersample: int, font: str) -> np.ndarray:
    """Which sub-samples of a ``size x size`` frame lie inside the glyph (offset 0), as floats 0/1."""
    return _mask(letter, size, cap_height, supersample, font, (0.0, 0.0))


def _block_mean(mask: np.ndarray, supersample: int) -> np.ndarray:
    n = mask.shape[0] // supersample
    return mask.reshape(n, supersample, n, supersample).mean(axis=(1, 3))


def pixel_counts(images: np.ndarray) -> np.ndarray:
    """Number of nonzero pixels of each image of a stack ``(n, H, W)``."""
    images = np.asarray(images)
    if images.ndim != 3:
        raise ValueError(f"images must be a stack of shape (n, H, W), got shape {images.shape}")
    return np.count_nonzero(images, axis=(1, 2))


def noisy(images: np.ndarray, sigma: float, rng: np.random.Generator, *, n_draws: int = 1,
          distribution: str = "gaussian", zero_mean: bool = True, extent: int | None = None) -> np.ndarray:
    """Add white noise of standard deviation ``sigma`` to images, as in Sec. III.B-C.

    Parameters
    ----------
    images : array_like
        One image ``(H, W)`` or a stack ``(n, H, W)``.
    sigma : float
        Noise standard deviation (>= 0).
    rng : numpy.random.Generator
        Source of the noise.
    n_draws : int, default 1
        Independent noisy copies of each image.
    distribution : {"gaussian", "uniform"}
        Gaussian noise (the model of Sec. II.C) or zero-mean uniform noise of the same
        standard deviation (the text also says "all signal and noise data are uniformly
        distributed").
    zero_mean : bool, default True
        Subtract from each noisy image its own mean ("the full image plus noise made to
        be zero mean. (This is what an optical system does.)", Sec. III.B).
    extent : int, optional
        Add noise only inside the central ``extent x extent`` pixels of each image (the
        report does not say how far its noise extends); ``None`` (default) fills the
        whole image. With ``zero_mean`` the mean is still removed over the whole image.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_draws, n, H, W)`` for a stack, ``(n_draws, H, W)`` for one image.
    """
    # converted first so that text input stays a ValueError, as np.asarray(..., float) raises
    arr = as_array(np.asarray(images, dtype=float), "images", ndim=(2, 3), allow_empty=False)
    sigma = as_real(sigma, "sigma", 0.0)
    rng = as_rng(rng)
    n_draws = as_int(n_draws, "n_draws", minimum=1)
    distribution = as_choice(distribution, "distribution", ("gaussian", "uniform"))
    shape = (n_draws,) + arr.shape
    if distribution == "gaussian":
        noise = rng.normal(0.0, float(sigma), size=shape)
    else:
        half = float(sigma) * np.sqrt(3.0)
        noise = rng.uniform(-half, half, size=shape)
    if extent is not None:
        extent = as_int(extent, "extent", minimum=1)
        H, W = arr.shape[-2:]
        if extent > min(H, W):
            raise ValueError(f"extent must be at most the image side {min(H, W)}, got {extent}")
        mask = np.zeros((H, W))
        r0, c0 = (H - extent) // 2, (W - extent) // 2
        mask[r0:r0 + extent, c0:c0 + extent] = 1.0
        noise = noise * mask
    out = arr[None] + noise
    if zero_mean:
        out -= out.mean(axis=(-2, -1), keepdims=True)
    return out

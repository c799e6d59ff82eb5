"""Tests of projtrack.scenes.letters (the 32 x 32 letter stand-ins of Casasent & Song)."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack.scenes import letters


def test_alphabet_shape_binary_and_deterministic():
    a = letters.alphabet()
    assert a.shape == (26, 32, 32)
    assert set(np.unique(a)) <= {0.0, 1.0}
    assert np.array_equal(a, letters.alphabet())
    assert len({a[k].tobytes() for k in range(26)}) == 26


def test_letters_are_central_and_within_paper_limits():
    a = letters.alphabet()
    counts = letters.pixel_counts(a)
    assert counts.max() < 110  # "all letters had less than 110 nonzero pixels"
    assert np.sum((counts >= 40) & (counts <= 75)) >= 13  # "most letters ... 40-75"
    rows = np.nonzero(a.any(axis=2))
    cols = np.nonzero(a.any(axis=1))
    assert rows[1].min() >= 10 and rows[1].max() <= 21  # cap height 8.5, centred; M and W are wider
    assert cols[1].min() >= 9 and cols[1].max() <= 22
    assert letters.box_side(a) <= 10 and letters.fits_description(a)  # "most ... the central 10 x 10 pixels"


def test_description_rule_is_the_thicker_one():
    assert letters.choose_rule() == (10.0, 1.0 / 64.0)


def test_choose_rule_logic():
    grid = [{"cap_height": 10.0, "min_coverage": 0.5, "n_in_40_75": 5, "max": 50},
            {"cap_height": 12.0, "min_coverage": 0.5, "n_in_40_75": 9, "max": 120},
            {"cap_height": 11.0, "min_coverage": 0.25, "n_in_40_75": 7, "max": 90},
            {"cap_height": 10.0, "min_coverage": 0.25, "n_in_40_75": 7, "max": 90}]
    assert letters.choose_rule(grid) == (10.0, 0.25)
    with pytest.raises(ValueError):
        letters.choose_rule([{"cap_height": 10.0, "min_coverage": 0.5, "n_in_40_75": 1, "max": 200}])


def test_holes_are_rendered():
    o = letters.render_letter("O")
    assert o[16, 16] == 0.0 and o.sum() > 20  # the counter of O is empty


def test_larger_cap_height_gives_more_pixels():
    small = letters.render_letter("E", cap_height=8).sum()
    large = letters.render_letter("E", cap_height=14).sum()
    assert large > small


def test_noisy_statistics_and_zero_mean():
    rng = np.random.default_rng(0)
    img = letters.render_letter("C")
    out = letters.noisy(img, 0.4, rng, n_draws=400, zero_mean=False)
    assert out.shape == (400, 32, 32)
    assert abs((out - img).std() - 0.4) < 0.01
    z = letters.noisy(letters.alphabet(), 0.4, rng, n_draws=3)
    assert z.shape == (3, 26, 32, 32)
    assert np.allclose(z.mean(axis=(-2, -1)), 0.0)
    u = letters.noisy(img, 0.4, rng, n_draws=400, distribution="uniform", zero_mean=False) - img
    assert abs(u.std() - 0.4) < 0.01 and np.abs(u).max() <= 0.4 * np.sqrt(3)


def test_noisy_reproducible():
    a = letters.noisy(np.ones((4, 4)), 1.0, np.random.default_rng(5))
    b = letters.noisy(np.ones((4, 4)), 1.0, np.random.default_rng(5))
    assert np.array_equal(a, b)


@pytest.mark.parametrize("kwargs, exc", [
    ({"letter": "a"}, ValueError), ({"letter": "AB"}, ValueError), ({"letter": 3}, ValueError),
    ({"letter": "A", "size": 2}, ValueError), ({"letter": "A", "cap_height": 40}, ValueError),
    ({"letter": "A", "cap_height": np.nan}, ValueError), ({"letter": "A", "min_coverage": 0}, ValueError),
    ({"letter": "A", "size": 3.5}, TypeError), ({"letter": "A", "cap_height": "10"}, TypeError),
    ({"letter": "W", "size": 16, "cap_height": 15}, ValueError),
])
def test_render_bad_inputs(kwargs, exc):
    with pytest.raises(exc):
        letters.render_letter(**kwargs)


def test_noisy_bad_inputs():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError):
        letters.noisy(np.ones(3), 0.1, rng)
    with pytest.raises(ValueError):
        letters.noisy(np.ones((3, 3)), -0.1, rng)
    with pytest.raises(TypeError):
        letters.noisy(np.ones((3, 3)), 0.1, 42)
    with pytest.raises(ValueError):
        letters.noisy(np.ones((3, 3)), 0.1, rng, distribution="cauchy")
    with pytest.raises(ValueError):
        letters.noisy(np.array([[np.nan]]), 0.1, rng)
    with pytest.raises(ValueError):
        letters.pixel_counts(np.ones((3, 3)))


def test_default_rule_is_calibrated_on_the_43_pixel_c():
    assert letters.calibrate_rule() == (letters.CAP_HEIGHT, letters.MIN_COVERAGE)
    assert letters.render_letter("C").sum() == 43
    # the calibrated alphabet is the centred STIX member of the glyph ensemble, bit for bit
    member = [e for e in letters.glyph_ensemble(fonts=("STIX",), cap_heights=(letters.CAP_HEIGHT,), offsets=(0.0,))]
    assert len(member) == 1 and member[0]["min_coverage"] == letters.MIN_COVERAGE and member[0]["fits"]
    # the old grid's rule (cap height 11, a quarter) gives 43 pixels too, but letters 12 pixels tall
    grid = letters.rule_grid()
    big = [g for g in grid if g["C"] == 43]
    assert big and all(g["box"] > 10 for g in big)
    with pytest.raises(ValueError, match="no candidate"):
        letters.calibrate_rule(grid)
    # the description-only rule differs: a thicker C
    cap, cov = letters.choose_rule()
    assert letters.render_letter("C", cap_height=cap, min_coverage=cov).sum() != 43


def test_calibrate_rule_logic_and_errors():
    grid = [{"cap_height": 10.0, "min_coverage": 0.5, "n_in_40_75": 20, "max": 90, "C": 50},
            {"cap_height": 11.0, "min_coverage": 0.25, "n_in_40_75": 9, "max": 90, "C": 43},
            {"cap_height": 12.0, "min_coverage": 0.25, "n_in_40_75": 12, "max": 95, "C": 43},
            {"cap_height": 12.0, "min_coverage": 0.5, "n_in_40_75": 25, "max": 130, "C": 43}]
    assert letters.calibrate_rule(grid) == (12.0, 0.25)
    assert letters.calibrate_rule(grid, pixels=50) == (10.0, 0.5)
    # with the size of Sec. III.A: most letters in a 10 x 10 box
    boxed = [g | {"box": b} for g, b in zip(grid, (10, 10, 12, 10))]
    assert letters.calibrate_rule(boxed) == (11.0, 0.25)
    with pytest.raises(ValueError, match="no candidate"):
        letters.calibrate_rule(grid, pixels=44)
    with pytest.raises(ValueError, match="letter"):
        letters.calibrate_rule(grid, letter="c")
    with pytest.raises(ValueError, match="key"):
        letters.calibrate_rule(grid, letter="P")
    with pytest.raises(TypeError):
        letters.calibrate_rule(grid, pixels=43.0)


def test_noise_extent_limits_the_noise_to_the_centre():
    rng = np.random.default_rng(0)
    img = np.zeros((32, 32))
    x = letters.noisy(img, 1.0, rng, n_draws=3, zero_mean=False, extent=10)
    assert np.all(x[:, :11, :] == 0) and np.all(x[:, 21:, :] == 0) and np.all(x[:, :, :11] == 0)
    assert np.all(x[:, 11:21, 11:21] != 0)
    full = letters.noisy(img, 1.0, np.random.default_rng(0), zero_mean=False, extent=32)
    assert np.array_equal(full, letters.noisy(img, 1.0, np.random.default_rng(0), zero_mean=False))
    with pytest.raises(ValueError, match="extent"):
        letters.noisy(img, 1.0, rng, extent=33)
    with pytest.raises(ValueError, match="extent"):
        letters.noisy(img, 1.0, rng, extent=0)


def test_fonts_ship_with_matplotlib_and_render():
    assert set(letters.FONTS) == {"STIX", "DejaVu Serif", "Computer Modern"}
    for font in letters.FONTS:
        assert letters.font_path(font).is_file()
        c = letters.render_letter("C", font=font)
        assert 20 < c.sum() < 110
    with pytest.raises(ValueError, match="font"):
        letters.render_letter("C", font="Times New Roman")


def test_coverage_map_matches_render_and_shifts_exactly():
    cover = letters.coverage_map("C")
    assert np.array_equal(letters.render_letter("C"), (cover >= letters.MIN_COVERAGE - 1e-12).astype(float))
    assert np.all((cover >= 0) & (cover <= 1)) and np.allclose(cover * 64, np.round(cover * 64))
    # a whole-pixel shift moves the image by one pixel (right and up)
    shifted = letters.coverage_map("C", offset=(1.0, 1.0))
    assert np.array_equal(shifted, np.roll(cover, (-1, 1), axis=(0, 1)))
    # a sub-pixel shift keeps the covered area (up to sampling)
    half = letters.coverage_map("C", offset=(0.5, 0.25))
    assert abs(half.sum() - cover.sum()) < 0.5
    with pytest.raises(ValueError, match="offset"):
        letters.coverage_map("C", offset=(0.5,))
    with pytest.raises(ValueError, match="offset"):
        letters.coverage_map("C", offset=(2.0, 0.0))


def test_coverage_for_count():
    cover = np.array([[0.9, 0.5], [0.5, 0.1]])
    assert letters.coverage_for_count(cover, 1) == 0.9
    assert np.isnan(letters.coverage_for_count(cover, 2))  # a tie at the boundary: no threshold gives 2
    assert letters.coverage_for_count(cover, 3) == 0.5
    assert np.isnan(letters.coverage_for_count(cover, 5))
    t = letters.coverage_for_count(letters.coverage_map("C"), 43)
    assert letters.render_letter("C", min_coverage=t).sum() == 43


def test_glyph_ensemble_gives_the_printed_c_and_matches_direct_rendering():
    ens = letters.glyph_ensemble(fonts=("STIX", "Computer Modern"), cap_heights=(10.5, 11.0),
                                 offsets=(0.0, 0.25, 0.5))
    assert ens and all(set(e) == {"font", "cap_height", "dx", "dy", "min_coverage", "n_in_40_75", "max", "box",
                                  "fits_counts", "fits"} for e in ens)
    for e in ens[:: max(1, len(ens) // 5)]:
        a = letters.alphabet(cap_height=e["cap_height"], min_coverage=e["min_coverage"], font=e["font"],
                             offset=(e["dx"], e["dy"]))
        counts = letters.pixel_counts(a)
        assert counts[letters.LETTERS.index("C")] == 43
        assert counts.max() == e["max"] and np.sum((counts >= 40) & (counts <= 75)) == e["n_in_40_75"]
        assert e["box"] == letters.box_side(a) and e["fits"] == letters.fits_description(a)
        assert e["fits_counts"] == letters.fits_description(a, box=None)
    with pytest.raises(ValueError, match="multiples"):
        letters.glyph_ensemble(offsets=(0.1,))
    with pytest.raises(ValueError, match="empty"):
        letters.glyph_ensemble(fonts=())


def test_box_side_and_description():
    a = np.zeros((3, 32, 32))
    a[0, 5:15, 5:12] = 1  # 10 x 7
    a[1, 0:12, 0:3] = 1  # 12 x 3
    a[2, 20:29, 20:29] = 1  # 9 x 9
    assert letters.box_side(a, most=1) == 9 and letters.box_side(a, most=2) == 10 and letters.box_side(a, most=3) == 12
    with pytest.raises(ValueError, match="most"):
        letters.box_side(a, most=4)
    with pytest.raises(ValueError, match="nonzero"):
        letters.box_side(np.zeros((2, 4, 4)), most=1)
    big = letters.alphabet(cap_height=11.0, min_coverage=0.25)
    assert letters.fits_description(big, box=None) and not letters.fits_description(big)
    assert letters.fits_description(big, box=12)


def test_calibration_grid():
    grid = letters.calibration_grid((8.5, 9.0, 11.0))
    assert [g["cap_height"] for g in grid] == [8.5, 11.0]  # no threshold gives a 43-pixel C at 9.0
    assert all(g["C"] == 43 and g["font"] == "STIX" and g["dx"] == g["dy"] == 0.0 for g in grid)
    assert letters.calibrate_rule(grid) == (8.5, 0.03125)

"""projtrack.stable: printed numbers that do not depend on the last bits."""

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from projtrack.stable import fmt, tidy


def test_negative_zero_is_removed_everywhere():
    assert math.copysign(1.0, tidy(-0.0)) == 1.0
    assert math.copysign(1.0, tidy(-1e-17, 6)) == 1.0
    a = tidy(np.array([-0.0, -1e-20, 2.0]), 3)
    assert np.all(np.signbit(a) == [False, False, False])
    df = tidy(pd.DataFrame({"x": [-1e-13, 1.23456], "n": [1, 2], "s": ["a", "b"]}), 4)
    assert df["x"].tolist() == [0.0, 1.2346] and not np.signbit(df["x"]).any()
    assert df["n"].tolist() == [1, 2] and df["s"].tolist() == ["a", "b"]
    assert str(df).count("-0") == 0


def test_atol_and_significant_digits():
    assert tidy([1e-9, -3e-10, 0.5], atol=1e-8).tolist() == [0.0, 0.0, 0.5]
    assert tidy([123456.0, 0.00123456, -7.777], sig=3).tolist() == [123000.0, 0.00123, -7.78]
    s = tidy(pd.Series([1.23456, np.nan], name="v"), sig=2)
    assert s.name == "v" and s.iloc[0] == 1.2 and np.isnan(s.iloc[1])
    assert tidy(7) == 7 and tidy(True) is True and tidy("x") == "x"
    assert tidy(np.array([1, 2])).dtype.kind == "i"


@given(st.floats(-1e6, 1e6, allow_nan=False), st.integers(0, 8))
def test_tidy_is_stable_under_last_bit_noise(x, d):
    # a value and its neighbour one ulp away round to the same printed text unless they
    # straddle a rounding boundary, which is measure-zero; the sign of zero never differs
    y = np.nextafter(x, np.inf)
    tx, ty = tidy(x, d), tidy(y, d)
    assert abs(tx - ty) <= 10.0 ** -d + 1e-9 * abs(x)
    assert not (tx == 0 and math.copysign(1.0, tx) < 0)


@pytest.mark.parametrize("x, spec, out", [
    (-1e-12, ".6f", "0.000000"), (-0.0, ".3f", "0.000"), (-0.0004, ".1%", "0.0%"),
    (-0.0, ".2e", "0.00e+00"), (-1e-30, ".2e", "-1.00e-30"), (-0.0001, "+.2f", "+0.00"), (-0.25, ".1f", "-0.2"),
    (-2.0, ".3g", "-2"), (float("-inf"), ".2f", "-inf"), (-0.004, ".2f", "0.00"),
])
def test_fmt_never_prints_negative_zero(x, spec, out):
    assert fmt(x, spec) == out


def test_fmt_atol():
    assert fmt(-3e-7, ".8f", atol=1e-6) == "0.00000000"
    assert fmt(-3e-7, ".8f") == "-0.00000030"


def test_bad_inputs_are_named():
    with pytest.raises(ValueError, match="not both"):
        tidy(1.0, 2, sig=2)
    with pytest.raises(TypeError, match="decimals"):
        tidy(1.0, 2.5)
    with pytest.raises(ValueError, match="sig"):
        tidy(1.0, sig=0)
    with pytest.raises(ValueError, match="atol"):
        tidy(1.0, atol=-1)
    with pytest.raises(TypeError, match="real numbers"):
        tidy(np.array(["a"]))
    with pytest.raises(TypeError, match="x must be a real number"):
        fmt("1.0")
    with pytest.raises(TypeError, match="spec"):
        fmt(1.0, 3)
    with pytest.raises(TypeError, match="x must be a real number"):
        fmt(True)
    # NaN and infinities are printed, not refused
    assert (fmt(float("nan")), fmt(-np.inf)) == ("nan", "-inf")


def test_tiny_prints_bound_below_floor_and_value_above():
    from projtrack.stable import tiny
    assert tiny(3e-16) == "< 1e-12"
    assert tiny(-3e-16) == "< 1e-12"
    assert tiny(2.5e-5) == "2.5e-05"
    assert tiny(5e-9, floor=1e-8) == "< 1e-8"
    assert tiny(5e-8, floor=1e-8) == "5.0e-08"
    with pytest.raises(ValueError):
        tiny(1.0, floor=0)
    with pytest.raises(TypeError):
        tiny("1")


def test_below_is_pass_fail_against_fixed_tolerance():
    from projtrack.stable import below
    # values on either side of a power of ten print the same: only the tolerance matters
    assert below(1.0096e-5, 1e-3) == below(9.9e-6, 1e-3) == "< 1e-3"
    assert below(-4.76e-5, 1e-3) == "< 1e-3"
    assert below(2e-3, 1e-3) == "FAIL: 2.0e-03"
    assert below(1e-3, 1e-3).startswith("FAIL")
    with pytest.raises(ValueError):
        below(1.0, -1e-3)
    with pytest.raises(TypeError):
        below(None, 1e-3)


def test_tiny_spec_formats_values_above_the_floor():
    from projtrack.stable import tiny

    assert tiny(0.012345, spec=".3g") == "0.0123"
    assert tiny(0.012345) == "1.2e-02"
    assert tiny(3e-16, spec=".3g") == "< 1e-12"

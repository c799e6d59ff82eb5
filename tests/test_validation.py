"""The shared argument checks: each accepts what it should and names the argument when not."""

import numpy as np
import pytest
import scipy.sparse

from projtrack import _validation as V


def test_as_int():
    assert V.as_int(np.int64(3), "n") == 3 and type(V.as_int(np.int64(3), "n")) is int
    for bad in (True, np.bool_(True), 2.0, "2", None):
        with pytest.raises(TypeError, match="n must be an int"):
            V.as_int(bad, "n")
    with pytest.raises(ValueError, match=r"n must be an int >= 1, got 0"):
        V.as_int(0, "n", minimum=1)
    with pytest.raises(ValueError, match=r"<= 5"):
        V.as_int(6, "n", maximum=5)


def test_as_real():
    assert V.as_real(np.float32(0.5), "x") == 0.5
    assert V.as_real(3, "x", 0, low_open=True) == 3.0
    for bad in (True, "1", None, 1j):
        with pytest.raises(TypeError, match="x must be a real number"):
            V.as_real(bad, "x")
    with pytest.raises(ValueError, match="finite"):
        V.as_real(np.nan, "x", finite=False)
    with pytest.raises(ValueError, match="finite"):
        V.as_real(np.inf, "x")
    assert V.as_real(np.inf, "x", finite=False) == np.inf
    with pytest.raises(ValueError, match=r"x must be > 0, got 0.0"):
        V.as_real(0.0, "x", 0.0, low_open=True)
    with pytest.raises(ValueError, match=r"x must be >= 0"):
        V.as_real(-1, "x", 0.0)
    with pytest.raises(ValueError, match=r"must lie in \(0, 1\]"):
        V.as_real(0, "x", 0, 1, low_open=True)


def test_probabilities():
    assert V.as_probability(1, "p") == 1.0
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        V.as_probability(1, "p", high_open=True)
    np.testing.assert_array_equal(V.as_probabilities(0.5, "p", 3), [0.5, 0.5, 0.5])
    np.testing.assert_array_equal(V.as_probabilities([0.1, 1.0], "p", 2), [0.1, 1.0])
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        V.as_probabilities([0.1, 0.2], "p", 3)
    with pytest.raises(ValueError, match="must lie in"):
        V.as_probabilities([0.0, 0.2], "p", 2, low_open=True)
    with pytest.raises(ValueError, match="must lie in"):
        V.as_probabilities([np.nan, 0.2], "p", 2)


def test_odd_window_choice_rng_shape():
    assert V.as_odd_window(5, "w") == 5
    with pytest.raises(ValueError, match="odd"):
        V.as_odd_window(4, "w")
    with pytest.raises(ValueError, match=">= 1"):
        V.as_odd_window(0, "w")
    assert V.as_choice("a", "m", ("a", "b")) == "a"
    with pytest.raises(ValueError, match=r"m must be one of 'a', 'b', got 'c'"):
        V.as_choice("c", "m", ("a", "b"))
    with pytest.raises(ValueError, match="one of"):
        V.as_choice(1, "m", ("1",))
    with pytest.raises(ValueError, match="one of"):
        V.as_choice(True, "m", (1, 2))
    with pytest.raises(ValueError, match="one of"):
        V.as_choice(np.array([1, 2]), "m", (1, 2))
    out = V.as_choice(np.str_("b"), "m", ("a", "b"))
    assert out == "b" and type(out) is str
    assert V.as_choice(np.int64(2), "m", (1, 2)) == 2
    rng = np.random.default_rng(0)
    assert V.as_rng(rng) is rng
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        V.as_rng(0)
    assert V.as_shape2([3, np.int64(4)]) == (3, 4)
    for bad in ((3,), (3, 0), (3, True), (3, 4.0), "ab", None):
        with pytest.raises(ValueError, match="shape must be a"):
            V.as_shape2(bad)


def test_as_array():
    a = V.as_array([[1, 2], [3, 4]], "a", ndim=2, shape=(None, 2))
    assert a.dtype == float and a.shape == (2, 2)
    assert V.as_array([True, False], "a").tolist() == [1.0, 0.0]
    with pytest.raises(TypeError, match="a bool"):
        V.as_array([True], "a", allow_bool=False)
    for bad in ("abc", None, [1j], scipy.sparse.eye(2)):
        with pytest.raises(TypeError, match="a must be a"):
            V.as_array(bad, "a")
    with pytest.raises(TypeError, match="numeric"):
        V.as_array([[1, 2], [3]], "a")
    with pytest.raises(ValueError, match="1-D or 2-D"):
        V.as_array(np.zeros((1, 1, 1)), "a", ndim=(1, 2))
    with pytest.raises(ValueError, match=r"shape \(any, 3\)"):
        V.as_array(np.zeros((2, 2)), "a", shape=(None, 3))
    with pytest.raises(ValueError, match="empty"):
        V.as_array([], "a", allow_empty=False)
    with pytest.raises(ValueError, match="finite"):
        V.as_array([1.0, np.nan], "a")
    assert np.isnan(V.as_array([np.nan], "a", finite=False)[0])
    assert V.as_array([1, 2], "a", dtype=int).dtype.kind == "i"


def test_as_square():
    assert V.as_square(np.eye(3), "S", 3).shape == (3, 3)
    with pytest.raises(ValueError, match="2 x 2"):
        V.as_square(np.eye(3), "S", 2)
    with pytest.raises(ValueError, match="square"):
        V.as_square(np.zeros((2, 3)), "S")


def test_as_count_reports_every_bad_value_as_value_error():
    assert V.as_count(3, "n") == 3 and type(V.as_count(np.int64(3), "n")) is int
    assert V.as_count(0, "n", minimum=0) == 0
    for bad in (0, -1, 2.0, 1.5, True, "3", None):
        with pytest.raises(ValueError, match=r"n_steps must be an int >= 1"):
            V.as_count(bad, "n_steps")
    with pytest.raises(ValueError, match=">= 2, got 1"):
        V.as_count(1, "n", minimum=2)


def test_only_value_errors_turns_a_wrong_kind_into_value_error():
    assert V.only_value_errors(V.as_real, 2, "speed", 0, low_open=True) == 2.0
    assert V.only_value_errors(V.as_int, 3, "n", minimum=1) == 3
    with pytest.raises(ValueError, match="speed must be a real number, got str"):
        V.only_value_errors(V.as_real, "2", "speed", 0, low_open=True)
    for bad in ("3", True, 2.5, None):
        with pytest.raises(ValueError, match="n must be an int"):
            V.only_value_errors(V.as_int, bad, "n", minimum=1)
    with pytest.raises(ValueError, match="n must be an int >= 1, got 0"):
        V.only_value_errors(V.as_int, 0, "n", minimum=1)


def test_as_bool():
    assert V.as_bool(np.bool_(True), "flag") is True and V.as_bool(False, "flag") is False
    for bad in (0, 1, "yes", None, np.array([True])):
        with pytest.raises(TypeError, match="flag must be a bool"):
            V.as_bool(bad, "flag")

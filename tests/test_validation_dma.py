"""Tests of the count check added to projtrack._validation for the manifold chapter."""

from __future__ import annotations

import numpy as np
import pytest

from projtrack._validation import as_count


def test_as_count_accepts_ints_and_numpy_ints():
    assert as_count(3, "n") == 3 and type(as_count(np.int64(3), "n")) is int
    assert as_count(0, "n", minimum=0) == 0


@pytest.mark.parametrize("bad", [0, -1, 2.0, 1.5, True, "3", None])
def test_as_count_reports_every_bad_value_as_value_error(bad):
    with pytest.raises(ValueError, match=r"n_steps must be an int >= 1"):
        as_count(bad, "n_steps")


def test_as_count_minimum():
    with pytest.raises(ValueError, match=">= 2, got 1"):
        as_count(1, "n", minimum=2)


def test_only_value_errors_turns_a_wrong_kind_into_value_error():
    from projtrack._validation import as_real, only_value_errors

    assert only_value_errors(as_real, 2, "speed", 0, low_open=True) == 2.0
    with pytest.raises(ValueError, match="speed must be a real number, got str"):
        only_value_errors(as_real, "2", "speed", 0, low_open=True)
    with pytest.raises(ValueError, match="speed must be > 0"):
        only_value_errors(as_real, 0.0, "speed", 0, low_open=True)

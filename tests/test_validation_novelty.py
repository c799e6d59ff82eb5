"""Tests of the check added to projtrack._validation for the novelty chapter."""
from __future__ import annotations

import pytest

from projtrack._validation import as_int, as_real, as_value_error


def test_as_value_error_passes_good_values_through():
    assert as_value_error(as_int, 3, "n", minimum=1) == 3
    assert as_value_error(as_real, 0.5, "x", 0.0, 1.0) == 0.5


@pytest.mark.parametrize("value", ["3", True, 2.5, None])
def test_as_value_error_turns_wrong_kinds_into_value_errors(value):
    with pytest.raises(ValueError, match="n must be an int"):
        as_value_error(as_int, value, "n", minimum=1)


def test_as_value_error_keeps_value_errors():
    with pytest.raises(ValueError, match="n must be an int >= 1, got 0"):
        as_value_error(as_int, 0, "n", minimum=1)

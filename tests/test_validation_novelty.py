"""Tests of the check added to projtrack._validation for the novelty chapter."""
from __future__ import annotations

import pytest

from projtrack._validation import as_int, as_real, only_value_errors


def test_only_value_errors_passes_good_values_through():
    assert only_value_errors(as_int, 3, "n", minimum=1) == 3
    assert only_value_errors(as_real, 0.5, "x", 0.0, 1.0) == 0.5


@pytest.mark.parametrize("value", ["3", True, 2.5, None])
def test_only_value_errors_turns_wrong_kinds_into_value_errors(value):
    with pytest.raises(ValueError, match="n must be an int"):
        only_value_errors(as_int, value, "n", minimum=1)


def test_only_value_errors_keeps_value_errors():
    with pytest.raises(ValueError, match="n must be an int >= 1, got 0"):
        only_value_errors(as_int, 0, "n", minimum=1)

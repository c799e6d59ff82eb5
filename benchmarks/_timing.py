"""Wall-clock timing shared by the benchmark scripts (imported as ``from _timing import ...``)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def best_of_result(fn: Callable[[], Any], repeats: int = 3) -> tuple[float, Any]:
    """Best wall-clock time of ``repeats`` calls of ``fn`` (seconds), and the last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def best_of(fn: Callable[[], Any], repeats: int = 3, number: int = 1) -> float:
    """Best, over ``repeats`` rounds, of the mean time of ``number`` calls of ``fn`` (seconds)."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best

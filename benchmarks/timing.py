"""Shared by the benchmark scripts: the best wall time of repeated runs."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(function: Callable[[], object], repeats: int) -> float:
    """The shortest of ``repeats`` runs of ``function()`` (s)."""
    return best_time_and_result(function, repeats)[0]


def best_time_and_result(function: Callable[[], object], repeats: int) -> tuple[float, object]:
    """The shortest of ``repeats`` runs of ``function()`` (s) and the last result."""
    best, result = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result

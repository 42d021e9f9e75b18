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


def interleaved(functions: dict[str, Callable[[], object]], items: int, repeats: int,
                per_repeat: int = 20_000) -> dict[str, float]:
    """Best time (s) per item of each ``functions[key]()``, each call handling ``items`` items (states,
    configurations). The candidates take turns within every one of ``repeats`` repeats, so a change of the
    machine's load hits them alike; a repeat calls each enough times for ~``per_repeat`` items."""
    calls = max(1, per_repeat // items)
    best = dict.fromkeys(functions, float("inf"))
    for _ in range(repeats):
        for key, function in functions.items():
            start = time.perf_counter()
            for _ in range(calls):
                function()
            best[key] = min(best[key], (time.perf_counter() - start) / calls)
    return {key: value / items for key, value in best.items()}


def cpu_medians(functions: dict[str, Callable[[], object]], repeats: int) -> dict[str, float]:
    """The median CPU time (s, ``time.process_time``: this process's own work, not the machine's other load) of
    each ``functions[key]()`` over ``repeats`` rounds; within every round the candidates take turns (interleaved),
    so a change of the machine's state hits them alike."""
    return cpu_medians_and_results(functions, repeats)[0]


def cpu_medians_and_results(functions: dict[str, Callable[[], object]], repeats: int
                            ) -> tuple[dict[str, float], dict[str, object]]:
    """:func:`cpu_medians` and the last result of each function."""
    import statistics

    times: dict[str, list[float]] = {key: [] for key in functions}
    results: dict[str, object] = {}
    for _ in range(repeats):
        for key, function in functions.items():
            start = time.process_time()
            results[key] = function()
            times[key].append(time.process_time() - start)
    return {key: statistics.median(values) for key, values in times.items()}, results

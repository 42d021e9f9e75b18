"""Bounded work: the memory a request implies, estimated before the work starts, and refused past a limit.

Every analysis whose memory grows with a count the user gives (samples of a trajectory, ``dt``, Monte Carlo
samples, grid points, rows of a trajectory file) calls :func:`require` at its top with that count and the bytes each
unit of it needs (measured with ``tracemalloc``, with a margin; ``tests/test_bounded.py`` checks that every estimate
bounds the measured peak). Past the limit it raises :class:`BudgetError` (an :class:`~mechatron.errors.InputError`)
with one line: what, the estimate, the limit and how to lower it::

    dt 1e-09 gives 5.0e+09 samples (37 GiB, limit 6 GiB): use a larger dt or a shorter move

On the command line the values are named as options (``--dt``, see :func:`command_line`).

The limit (GiB) is, in order: :func:`memory_limit` (``with memory_limit(2): ...``, the API's setting), the
environment variable ``MECHATRON_MEMORY_GB``, or :data:`DEFAULT_FRACTION` of the memory the machine has available
when the limit is asked for (``MemAvailable`` of ``/proc/meminfo``; 4 GiB where that cannot be read).

Where the work, not the memory, grows past reason (a closed loop assembled at millions of positions), :func:`seconds`
refuses an estimated run time above :func:`time_limit` (``with time_limit(600): ...``), ``MECHATRON_TIME_S`` or
:data:`DEFAULT_TIME_S`. Times per unit are lower bounds measured on a desktop machine: a refused run would take at
least the time shown.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from contextvars import ContextVar

from ..errors import InputError

GIB = 1024 ** 3
#: The share of the available memory an analysis may use by default.
DEFAULT_FRACTION = 0.5
#: The limit where the available memory cannot be read (GiB).
FALLBACK_GB = 4.0
ENVIRONMENT = "MECHATRON_MEMORY_GB"
#: The default bound on the estimated run time of one analysis (s), and the variable that sets another.
DEFAULT_TIME_S = 3600.0
TIME_ENVIRONMENT = "MECHATRON_TIME_S"

_limit: ContextVar[float | None] = ContextVar("mechatron_memory_limit", default=None)
_time: ContextVar[float | None] = ContextVar("mechatron_time_limit", default=None)
_options: ContextVar[bool] = ContextVar("mechatron_option_names", default=False)


class BudgetError(InputError):
    """A request whose estimated memory (or run time) exceeds the limit. ``estimate`` and ``limit`` are in bytes
    (seconds for a run time)."""

    def __init__(self, message: str, *, estimate: float, limit: float) -> None:
        self.estimate = estimate
        self.limit = limit
        super().__init__(message)


def available_cores() -> int:
    """The cores this process may run on: its CPU affinity where the system has one (``os.sched_getaffinity``: a
    container's or ``taskset``'s share), else every core (``os.cpu_count()``)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)  # pragma: no cover - macOS, Windows


def available_bytes() -> float | None:
    """The memory the machine has available now (bytes), or None where it cannot be read."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, OSError, ValueError):
        return None


def limit_bytes() -> float:
    """The memory limit now (bytes): :func:`memory_limit`, ``MECHATRON_MEMORY_GB`` or :data:`DEFAULT_FRACTION` of
    the available memory."""
    from .values import number

    gb = _limit.get()
    if gb is None and os.environ.get(ENVIRONMENT, "").strip():
        gb = number(f"the environment variable {ENVIRONMENT}", os.environ[ENVIRONMENT].strip(), positive=True,
                    unit="GiB")
    if gb is not None:
        return gb * GIB
    available = available_bytes()
    return DEFAULT_FRACTION * available if available else FALLBACK_GB * GIB


@contextlib.contextmanager
def _setting(variable: ContextVar, name: str, value: float | None, unit: str) -> Iterator[None]:
    """``variable`` set to ``value`` (checked: > 0, or None for the default) within the block."""
    from .values import number

    token = variable.set(number(name, value, positive=True, unit=unit, allow_none=True))
    try:
        yield
    finally:
        variable.reset(token)


def memory_limit(gb: float | None) -> contextlib.AbstractContextManager[None]:
    """Within the block, analyses may use up to ``gb`` GiB (None: the default, see the module docstring)."""
    return _setting(_limit, "memory_gb", gb, "GiB")


@contextlib.contextmanager
def command_line() -> Iterator[None]:
    """Within the block (the command line), values are named as options: ``dt`` → ``--dt``, ``grid_step`` →
    ``--grid-step``."""
    token = _options.set(True)
    try:
        yield
    finally:
        _options.reset(token)


def option(name: str) -> str:
    """``name`` as the user gave it: an API argument, or its option ``--name`` on the command line. Names with a
    space or an option already (``--task FILE``, ``the trajectory file``) are left as they are."""
    if _options.get() and name.isidentifier():
        return "--" + name.replace("_", "-")
    return name


def gib(nbytes: float) -> str:
    """``nbytes`` in GiB, two significant figures (``37 GiB``, ``0.52 GiB``, ``3.6e+302 GiB``)."""
    value = nbytes / GIB
    if value >= 1e6:
        return f"{value:.1e} GiB"
    return f"{value:.2g} GiB" if value < 10 else f"{value:.0f} GiB"


def count(value: float) -> str:
    """A count as the message shows it: exact below a million, ``5.0e+09`` above."""
    return f"{value:,.0f}" if value < 1e6 else f"{value:.1e}"


def require(what: str, units: float, bytes_per_unit: float, *, fixed: float = 0.0, advice: str) -> float:
    """The estimate ``fixed + units · bytes_per_unit`` (bytes), or :class:`BudgetError`
    ``{what} ({estimate}, limit {limit}): {advice}`` when it exceeds the limit. ``units`` may be a float (a count
    too large for an int, ``inf``)."""
    estimate = fixed + units * bytes_per_unit if math.isfinite(units) else math.inf
    limit = limit_bytes()
    if not estimate <= limit:
        shown = gib(estimate) if math.isfinite(estimate) else "more memory than there is"
        raise BudgetError(f"{what} ({shown}, limit {gib(limit)}): {advice}", estimate=estimate, limit=limit)
    return estimate


def samples(name: str, value: float, count_: float, bytes_per_sample: float, *, fixed: float = 0.0,
            advice: str) -> float:
    """:func:`require` for ``count_`` samples implied by the value ``value`` of ``name`` (``dt``, ``samples``):
    ``dt 1e-09 gives 5.0e+09 samples (37 GiB, limit 6 GiB): use a larger dt or a shorter move``. ``advice`` may
    name the value as ``{name}``."""
    shown = option(name)
    what = f"{shown} {value:g} gives {count(count_)} samples"
    return require(what, count_, bytes_per_sample, fixed=fixed, advice=advice.format(name=shown))


def time_limit_s() -> float:
    """The run-time limit now (s): :func:`time_limit`, ``MECHATRON_TIME_S`` or :data:`DEFAULT_TIME_S`."""
    from .values import number

    limit = _time.get()
    if limit is None and os.environ.get(TIME_ENVIRONMENT, "").strip():
        limit = number(f"the environment variable {TIME_ENVIRONMENT}", os.environ[TIME_ENVIRONMENT].strip(),
                       positive=True, unit="s")
    return DEFAULT_TIME_S if limit is None else limit


def time_limit(seconds_: float | None) -> contextlib.AbstractContextManager[None]:
    """Within the block, analyses whose estimated run time exceeds ``seconds_`` are refused (None: the default)."""
    return _setting(_time, "time_s", seconds_, "s")


def duration(value: float) -> str:
    """A run time as the message shows it: ``45 s``, ``12 min``, ``3.1 h``, ``2.0e+03 days``."""
    if value < 120:
        return f"{value:.0f} s"
    if value < 7200:
        return f"{value / 60:.0f} min"
    if value < 48 * 3600:
        return f"{value / 3600:.1f} h"
    return f"{value / 86400:.2g} days"


def seconds(what: str, units: float, seconds_per_unit: float, *, advice: str) -> float:
    """The estimated run time ``units · seconds_per_unit`` (s), or :class:`BudgetError`
    ``{what} (at least {time}, limit {limit}): {advice}`` when it exceeds the limit."""
    estimate = units * seconds_per_unit if math.isfinite(units) else math.inf
    limit = time_limit_s()
    if not estimate <= limit:
        raise BudgetError(f"{what} (at least {duration(estimate) if math.isfinite(estimate) else 'for ever'}, "
                          f"limit {duration(limit)}): {advice}", estimate=estimate, limit=limit)
    return estimate

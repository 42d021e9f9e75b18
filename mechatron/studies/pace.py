"""The pace of a study or an optimiser's designs: how many are done and failed, the rate, and the designs that take
far longer than the others.

A study's cost is set by its slowest designs (often those that fail: a geometry that does not assemble, an analysis
that refuses it), so :class:`Pace` keeps each design's time (s, measured where it ran: in this process or on a
worker) and its status. Its :meth:`~Pace.status` — ``"120 done, 3 failed, 41.2 designs/s"`` — goes to the progress
line, and a design that takes more than :data:`SLOW_FACTOR` times the median of the designs so far is named in one
warning line (:class:`~mechatron.errors.MechatronWarning`), with its reason when it failed.
"""

from __future__ import annotations

import statistics
import time
import warnings
from collections.abc import Callable, Sequence

from ..errors import MechatronWarning

#: A design taking more than this many times the median design's time is named in a warning.
SLOW_FACTOR = 10.0
#: The designs the median needs before a design is called slow.
MEDIAN_DESIGNS = 5


class Pace:
    """Designs done, failed and their times (see the module docstring); ``progress`` is the caller's
    ``progress(done, total)`` (a progress bar with a ``status`` attribute shows :meth:`status` beside it)."""

    def __init__(self, total: int, progress: Callable[[int, int], None] | None = None, done: int = 0) -> None:
        self.total, self.progress = total, progress
        self.done, self.failed = done, 0
        self.seconds: list[float] = []
        self._unchecked: list[tuple[int, float, str]] = []  # (design, seconds, reason) not yet held to the median
        self._start = time.perf_counter()
        self._timed = 0  # designs done in this run (the rate's)

    def add(self, designs: Sequence[int], seconds: Sequence[float], statuses: Sequence[str],
            reasons: Sequence[str]) -> None:
        """Count a batch of designs (their numbers, times in s, ``status`` and ``reason``), warn about the slow
        ones and report the progress."""
        for design, s, status, reason in zip(designs, seconds, statuses, reasons):
            self.failed += status != "ok"
            self.seconds.append(float(s))
            self._unchecked.append((int(design), float(s), "" if status == "ok" else str(reason)))
        self.done += len(designs)
        self._timed += len(designs)
        self._warn_slow()
        self.show()

    def show(self) -> None:
        """Report the progress (with :meth:`status` where the callback shows it)."""
        if self.progress is None:
            return
        status = getattr(self.progress, "status", None)
        if callable(status):
            status(self.status())
        self.progress(self.done, self.total)

    def finish(self, reason: str) -> None:
        """End the progress line (a progress bar's ``finish``: drawn a last time, then a newline) with ``reason``,
        why the run ended where it did; a callback without ``finish`` is left as it is."""
        finish = getattr(self.progress, "finish", None)
        if callable(finish):
            self.show()
            finish(reason)

    def status(self) -> str:
        """``"N done, M failed, R designs/s"`` (the rate of this run's designs, over its wall time)."""
        elapsed = time.perf_counter() - self._start
        rate = f", {self._timed / elapsed:.3g} designs/s" if self._timed and elapsed > 0 else ""
        return f"{self.done} done, {self.failed} failed{rate}"

    def median(self) -> float | None:
        """The median design's time (s), None before :data:`MEDIAN_DESIGNS` designs."""
        return statistics.median(self.seconds) if len(self.seconds) >= MEDIAN_DESIGNS else None

    def _warn_slow(self) -> None:
        median = self.median()
        if median is None:
            return
        for design, seconds, reason in self._unchecked:
            if seconds > SLOW_FACTOR * median:
                why = f"; it failed: {reason}" if reason else ""
                warnings.warn(f"design {design} took {seconds:.3g} s, {seconds / max(median, 1e-300):.0f}× the "
                              f"median design's {median:.3g} s{why}", MechatronWarning, stacklevel=3)
        self._unchecked.clear()

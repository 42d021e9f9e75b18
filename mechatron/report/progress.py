"""A minimal progress bar for long runs, written to stderr when it is a terminal."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO


def progress_bar(label: str, stream: TextIO | None = None, force: bool = False) -> Callable[[int, int], None] | None:
    """A callback ``(done, total)`` drawing ``label [#####.....] 52% 1.3 s``, followed by the text last given to
    its ``status(text)`` (a study's designs failed and their rate); ``None`` if the stream is not a terminal (no bar
    in logs and pipes) unless ``force``."""
    stream = stream or sys.stderr
    if not force and not (hasattr(stream, "isatty") and stream.isatty()):
        return None
    start = time.perf_counter()
    note = [""]

    def update(done: int, total: int) -> None:
        width = 30
        filled = int(width * done / max(total, 1))
        elapsed = time.perf_counter() - start
        shown = f"  {note[0]}" if note[0] else ""
        stream.write(f"\r{label} [{'#' * filled}{'.' * (width - filled)}] {100 * done / max(total, 1):3.0f}% "
                     f"{elapsed:.1f} s{shown}\x1b[K")
        if done >= total:
            stream.write("\n")
        stream.flush()

    def status(text: str) -> None:
        note[0] = text

    update.status = status  # type: ignore[attr-defined]
    return update

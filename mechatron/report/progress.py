"""A minimal progress bar for long runs, written to stderr when it is a terminal."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO


def progress_bar(label: str, stream: TextIO | None = None, force: bool = False) -> Callable[[int, int], None] | None:
    """A callback ``(done, total)`` drawing ``label [#####.....] 52% 1.3 s``, followed by the text last given to
    its ``status(text)`` (a study's designs failed and their rate); ``None`` if the stream is not a terminal (no bar
    in logs and pipes) unless ``force``. The line ends (a newline, so that what is printed next starts on its own
    line) when ``done`` reaches ``total`` or at ``finish(text)``, which draws it a last time with ``text`` — why it
    ended where it did (a search that converged, or spent its budget in whole generations) — after it; once ended
    it is not drawn again."""
    stream = stream or sys.stderr
    if not force and not (hasattr(stream, "isatty") and stream.isatty()):
        return None
    start = time.perf_counter()
    note = [""]
    last = [0, 0]
    ended = [False]

    def draw(done: int, total: int, end: bool) -> None:
        width = 30
        filled = min(width, int(width * done / max(total, 1)))
        elapsed = time.perf_counter() - start
        shown = f"  {note[0]}" if note[0] else ""
        stream.write(f"\r{label} [{'#' * filled}{'.' * (width - filled)}] {100 * done / max(total, 1):3.0f}% "
                     f"{elapsed:.1f} s{shown}\x1b[K")
        if end:
            stream.write("\n")
            ended[0] = True
        stream.flush()

    def update(done: int, total: int) -> None:
        if not ended[0]:
            last[:] = [done, total]
            draw(done, total, done >= total)

    def status(text: str) -> None:
        note[0] = text

    def finish(text: str = "") -> None:
        if not ended[0]:
            note[0] = "; ".join(filter(None, (note[0], text)))
            draw(*last, True)

    update.status = status  # type: ignore[attr-defined]
    update.finish = finish  # type: ignore[attr-defined]
    return update

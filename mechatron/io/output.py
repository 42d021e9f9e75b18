"""Writing output files whole or not at all.

Every file mechatron writes (CSV tables, JSON, charts) is first written to a temporary file beside its target and
then renamed over it, so a failed run never leaves a half-written file and never destroys the previous one.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.figure import Figure


def write_atomically(path: str | Path, write: Callable[[IO], None], *, binary: bool = False) -> Path:
    """Call ``write(file)`` on a temporary file in the folder of ``path``, then rename it to ``path``.

    Raises:
        InputError: naming ``path`` if it is a directory, its folder does not exist, or it cannot be written.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError("is a directory, not a file", file=path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"the folder {folder} does not exist", file=path)
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror}", file=path) from None
    try:
        with os.fdopen(handle, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8", "newline": ""})) \
                as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes the file private; an output gets the usual mode
        os.replace(temporary, path)
    except OSError as exc:
        _remove(temporary)
        raise InputError(f"cannot write: {exc.strerror}", file=path) from None
    except BaseException:
        _remove(temporary)
        raise
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all."""
    return write_atomically(path, lambda fh: fh.write(text))


def write_table(table: pd.DataFrame, path: str | Path) -> Path:
    """Write a DataFrame as CSV (no index, 10 significant digits) whole or not at all."""
    return write_atomically(path, lambda fh: table.to_csv(fh, index=False, float_format="%.10g"))


def save_figure(figure: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Save a matplotlib figure (format from the suffix: .png, .pdf, .svg) whole or not at all."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".") or "png"
    supported = figure.canvas.get_supported_filetypes()
    if fmt not in supported:
        raise InputError(f"cannot draw a .{fmt} file; use one of: {', '.join('.' + k for k in sorted(supported))}",
                         file=path)
    return write_atomically(path, lambda fh: figure.savefig(fh, dpi=dpi, format=fmt), binary=True)


def output_directory(directory: str | Path) -> Path:
    """``directory``, created if needed (an error naming it if it cannot be)."""
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise InputError("is a file, not a directory", file=directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the directory: {exc.strerror}", file=directory) from None
    return directory

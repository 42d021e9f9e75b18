"""Reading CSV files: one reader for every table a user writes (catalogs, trajectories, tolerances, poses).

Cells are read as text and converted field by field, so that a problem is reported with the file, the row and the
column. The row is the line number of the file (the first line is row 1, comment and blank lines count too), so that
an editor's line N is row N; :func:`read_csv` returns a frame whose index is that line number. Lines starting with
``#`` are comments, and so is what follows a ``#`` on a line.
"""

from __future__ import annotations

import csv
import io
import math
import re
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError
from .values import LARGEST

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd


def read_csv(path: str | Path, *, allow_empty: bool = False) -> pd.DataFrame:
    """The cells of a CSV file as stripped text (column names stripped too).

    Raises:
        InputError: naming the file when it is missing, a directory, unreadable, not CSV, or has no rows.
    """
    import pandas as pd

    path = Path(path)
    if path.is_dir():
        raise InputError("is a directory, not a file", file=path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not a readable CSV file (not UTF-8 text): {exc.reason}", file=path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", file=path) from None
    # A plain file (no comment, no blank line: the usual long trajectory) goes to pandas as it is, its rows on lines
    # 2, 3, …; otherwise the lines pandas reads (not a comment, not blank) are kept with their line numbers.
    plain = "#" not in text and not re.search(r"(^|\n)[ \t]*(\r?\n|$)", text.rstrip("\r\n"))
    lines = None if plain else [(n, line) for n, line in enumerate(text.splitlines(), start=1)
                                if line.strip() and not line.lstrip().startswith("#")]
    if lines is not None:
        text = "\n".join(line for _, line in lines)
    try:
        with warnings.catch_warnings(record=True) as caught:  # pandas drops cells beyond the header's columns
            warnings.simplefilter("always", pd.errors.ParserWarning)
            frame = pd.read_csv(io.StringIO(text), dtype=str, keep_default_na=False, comment="#",
                                skipinitialspace=True, skip_blank_lines=False, index_col=False)
    except pd.errors.EmptyDataError:
        raise InputError("not a readable CSV file: no header line", file=path) from None
    except pd.errors.ParserError as exc:
        raise _parser_error(path, lines or list(enumerate(text.splitlines(), start=1)), exc) from None
    if any(issubclass(w.category, pd.errors.ParserWarning) for w in caught):  # only empty cells may be dropped
        too_wide = _too_wide(path, lines or list(enumerate(text.splitlines(), start=1)))
        if too_wide is not None:
            raise too_wide
    header_line = 1 if lines is None else lines[0][0]
    if lines is None:
        frame.index = pd.RangeIndex(2, len(frame) + 2)
    elif len(frame) == len(lines) - 1:  # one row per line (no quoted line breaks): the index is the line number
        frame.index = pd.Index([n for n, _ in lines[1:]], dtype=int)
    else:
        frame.index = pd.RangeIndex(2, len(frame) + 2)
    names = [str(c).strip() for c in frame.columns]
    unnamed = [i for i, c in enumerate(names) if not c or c.startswith("Unnamed:")]
    if unnamed:
        raise InputError(f"column {unnamed[0] + 1} of the header has no name", file=path, row=header_line)

    def original(name: str) -> str:  # pandas renames a repeated column "a" to "a.1"
        base, _, number = name.rpartition(".")
        return base if number.isdigit() and base in names else name

    repeated = next((c for c in names if names.count(c) > 1 or original(c) != c), None)
    if repeated is not None:
        first = original(repeated)
        raise InputError(f"column {first!r} is given twice in the header", file=path, row=header_line, field=first)
    frame.columns = names
    frame = frame.fillna("").apply(lambda column: column.astype(str).str.strip())
    if frame.empty and not allow_empty:
        raise InputError("the file has no rows", file=path)
    return frame


def _too_wide(path: Path, lines: list[tuple[int, str]], empty: bool = False) -> InputError | None:
    """The error of the first row with more cells than the header (named by its line), if any; cells beyond the
    header that are empty count only with ``empty``."""
    rows = csv.reader(line.partition("#")[0] if "#" in line and '"' not in line else line for _, line in lines)
    width = None
    for (n, _), cells in zip(lines, rows):
        if width is None:
            width = len(cells)
        elif len(cells) > width and (empty or any(c.strip() for c in cells[width:])):
            return InputError(f"{len(cells)} cells but the header has {width} columns", file=path, row=n)
    return None


def _parser_error(path: Path, lines: list[tuple[int, str]], exc: Exception) -> InputError:
    """The error of a line pandas cannot split."""
    detail = str(exc).strip().splitlines()[0]
    return _too_wide(path, lines, empty=True) or InputError(f"not a readable CSV file: {detail}", file=path)


def number(text: str, *, file: str | Path, row: int, field: str) -> float:
    """``text`` as a finite float, or an :class:`InputError` naming the file, row and field."""
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"not a number: {text!r}", file=file, row=row, field=field) from None
    if not math.isfinite(value):
        raise InputError(f"not a finite number: {text!r}", file=file, row=row, field=field)
    if abs(value) > LARGEST:
        raise InputError(f"must be a finite number of magnitude <= {LARGEST:g} (in the column's unit), got {text}",
                         file=file, row=row, field=field)
    return value


def numbers(frame: pd.DataFrame, column: str, *, file: str | Path, factor: float = 1.0) -> list[float]:
    """Every cell of ``column`` as a finite float times ``factor`` (an error for an empty or bad cell)."""
    out = []
    for i, text in zip(frame.index, frame[column]):
        if not text:
            raise InputError("missing value", file=file, row=i, field=column)
        out.append(number(text, file=file, row=i, field=column) * factor)
    return out

"""Reading CSV files: one reader for every table a user writes (catalogs, trajectories, tolerances, poses).

Cells are read as text and converted field by field, so that a problem is reported with the file, the row (as in a
spreadsheet: the header is row 1) and the column. Lines starting with ``#`` are comments.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError

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
        frame = pd.read_csv(path, dtype=str, keep_default_na=False, comment="#", skipinitialspace=True)
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"not a readable CSV file: {str(exc).splitlines()[0]}", file=path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", file=path) from None
    frame.columns = [str(c).strip() for c in frame.columns]
    frame = frame.apply(lambda column: column.str.strip())
    if frame.empty and not allow_empty:
        raise InputError("the file has no rows", file=path)
    return frame


def number(text: str, *, file: str | Path, row: int, field: str) -> float:
    """``text`` as a finite float, or an :class:`InputError` naming the file, row and field."""
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"not a number: {text!r}", file=file, row=row, field=field) from None
    if not math.isfinite(value):
        raise InputError(f"not a finite number: {text!r}", file=file, row=row, field=field)
    return value


def numbers(frame: pd.DataFrame, column: str, *, file: str | Path, factor: float = 1.0) -> list[float]:
    """Every cell of ``column`` as a finite float times ``factor`` (an error for an empty or bad cell)."""
    out = []
    for i, text in enumerate(frame[column], start=2):
        if not text:
            raise InputError("missing value", file=file, row=i, field=column)
        out.append(number(text, file=file, row=i, field=column) * factor)
    return out

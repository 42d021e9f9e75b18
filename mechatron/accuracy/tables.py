"""The tolerance tables of [Egorov, chapter 8] as data: linear sizes IT2–IT17 ([Egorov, table 8.2], GOST 25346-82,
the IT grades of [ISO 286-1], sizes up to 2000 mm; over 2000 up to 3150 mm [ISO 286-1, table 1];
``catalogs/it_grades.csv``) and angles AT5–AT14 ([Egorov, table 8.1], GOST 8908-81;
``catalogs/angle_tolerances.csv``).

A grade's tolerance is the width of the tolerance zone (upper minus lower limit) for a size in the interval
over < size ≤ up_to (mm); the first row covers every size up to its upper end. Sizes beyond the last row are
outside the tables.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from typing import TYPE_CHECKING

from ..errors import InputError
from ..io.data import data_dir

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

LINEAR_FILE, ANGLE_FILE = "it_grades.csv", "angle_tolerances.csv"


@lru_cache(maxsize=2)
def _table(name: str) -> pd.DataFrame:
    import pandas as pd

    return pd.read_csv(data_dir("catalogs") / name, comment="#")


def _grades(table: pd.DataFrame, prefix: str) -> list[int]:
    return [int(re.match(rf"{prefix}(\d+)_", c).group(1)) for c in table.columns if c.startswith(prefix)]


def _lookup(name: str, prefix: str, unit: str, grade: str, size_mm: float, factor: float) -> float:
    table = _table(name)
    match = re.fullmatch(rf"{prefix}\s*(\d+)", grade.strip().upper())
    grades = _grades(table, prefix)
    if not match or int(match.group(1)) not in grades:
        raise InputError(f"unknown grade {grade!r}; the table has {prefix}{grades[0]}…{prefix}{grades[-1]}")
    if not (math.isfinite(size_mm) and size_mm > 0):
        raise InputError(f"a size for the {prefix} table must be > 0 mm, got {size_mm:g}")
    size_mm = round(size_mm, 9)  # metres → millimetres must not move 18 mm past the edge of its interval
    rows = table[(table["over_mm"] < size_mm) & (size_mm <= table["up_to_mm"])]
    if rows.empty:
        raise InputError(f"size {size_mm:g} mm is outside the {prefix} table ({table['over_mm'].iloc[0]:g} < size "
                         f"≤ {table['up_to_mm'].iloc[-1]:g} mm)")
    return float(rows[f"{prefix}{int(match.group(1))}_{unit}"].iloc[0]) * factor


def linear_tolerance(grade: str, size: float) -> float:
    """The IT tolerance zone width (m) of grade ``"IT7"``… for a size (m), [Egorov, table 8.2] ([ISO 286-1])."""
    return _lookup(LINEAR_FILE, "IT", "um", grade, size * 1e3, 1e-6)


def angle_tolerance(grade: str, length: float) -> float:
    """The AT tolerance zone width (rad) of degree ``"AT7"``… for an angle whose shorter side is ``length`` (m),
    [Egorov, table 8.1]."""
    return _lookup(ANGLE_FILE, "AT", "arcsec", grade, length * 1e3, math.pi / 648000)


def tolerance_from_grade(grade: str, size: float) -> float:
    """An IT (length, m) or AT (angle, rad) tolerance zone width by the grade's prefix."""
    text = grade.strip().upper()
    if text.startswith("IT"):
        return linear_tolerance(text, size)
    if text.startswith("AT"):
        return angle_tolerance(text, size)
    raise InputError(f"unknown grade {grade!r}: give ITn (lengths, ISO 286-1) or ATn (angles)")

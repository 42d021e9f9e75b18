"""Reading and validating structured input (TOML tables) with errors that name the file and the field.

A :class:`FieldReader` wraps one table of a parsed file. Every accessor checks the type and range of one field and
records that the field was used, so that :meth:`FieldReader.finish` can reject misspelt or unknown fields. Fields in
units other than SI say so in their name: ``alpha_deg`` (degrees) next to ``alpha`` (radians), ``a_mm`` (millimetres)
next to ``a`` (metres); a file gives one or the other.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..units import UNITS
from .values import LARGEST

_MISSING: Any = object()
#: Pass as ``default`` to make a field required.
REQUIRED: Any = _MISSING


def field_suffixes(kind: str, *only: str) -> dict[str, float]:
    """The endings a field name of ``kind`` may carry → the factor that converts its value to SI, from the one unit
    table :data:`mechatron.units.UNITS`: ``""`` (no suffix: SI) first, then ``"_mm"``, ``"_deg"``, …; a name of the
    SI unit itself is no ending (``a``, not ``a_m``). ``only``: just these units besides SI (``field_suffixes(
    "length", "mm")`` → ``{"": 1.0, "_mm": 0.001}``)."""
    return {("_" + s if s else ""): f for s, f in UNITS[kind].items()
            if not s or (f != 1.0 and (not only or s in only))}


#: Unit suffixes a field name may carry (``a_mm``, ``alpha_deg``), with the factor that converts to SI
#: (:func:`field_suffixes`).
LENGTH_UNITS = field_suffixes("length")
ANGLE_UNITS = field_suffixes("angle")


class FieldReader:
    """Typed, path-aware access to one table of an input file.

    Args:
        data: The parsed table.
        file: The file it came from (for error messages).
        path: The path of this table inside the file, e.g. ``links[2]``; empty for the top level.
    """

    def __init__(self, data: Mapping[str, Any], *, file: str | Path | None, path: str = "") -> None:
        if not isinstance(data, Mapping):
            raise InputError(f"expected a table, got {type(data).__name__}", file=file, field=path or None)
        self.data = data
        self.file = file
        self.path = path
        self._used: set[str] = set()

    # ----------------------------------------------------------------------------------------------- helpers
    def field(self, key: str) -> str:
        """Full name of a field, as shown in error messages."""
        return f"{self.path}.{key}" if self.path else key

    def error(self, key: str, message: str) -> InputError:
        return InputError(message, file=self.file, field=self.field(key))

    def has(self, key: str) -> bool:
        return key in self.data

    def _take(self, key: str, default: Any) -> Any:
        self._used.add(key)
        if key in self.data:
            return self.data[key]
        if default is _MISSING:
            raise self.error(key, "missing required field")
        return default

    def raw(self, key: str, default: Any = _MISSING) -> Any:
        """The field's value as parsed, unchecked (marked as used)."""
        return self._take(key, default)

    def to_float(self, key: str, value: Any) -> float:
        """``value`` (found under ``key``) as a finite float, or an error naming the field."""
        return self._as_float(key, value)

    def _as_float(self, key: str, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"expected a number, got {type(value).__name__} {value!r}")
        x = float(value)
        if not math.isfinite(x):
            raise self.error(key, f"expected a finite number, got {value!r}")
        if abs(x) > LARGEST:
            raise self.error(key, f"expected a finite number of magnitude <= {LARGEST:g} (in the field's unit), "
                                  f"got {value!r}")
        return x

    def _pick_unit(self, key: str, units: Mapping[str, float], default: Any) -> tuple[str, float]:
        """Find which of ``key``, ``key_deg``, ... is present; return (actual key, factor to SI)."""
        present = [(key + suffix, factor) for suffix, factor in units.items() if key + suffix in self.data]
        if len(present) > 1:
            names = " and ".join(k for k, _ in present)
            raise self.error(key, f"give only one of {names}")
        if present:
            return present[0]
        if default is _MISSING:
            names = " or ".join(key + s for s in units)
            raise self.error(key, f"missing required field (give {names})")
        return key, 1.0

    # ---------------------------------------------------------------------------------------------- scalars
    def number(
        self,
        key: str,
        default: Any = _MISSING,
        *,
        minimum: float | None = None,
        positive: bool = False,
        nonzero: bool = False,
    ) -> float:
        """A finite number, optionally bounded."""
        value = self._take(key, default)
        if value is default and key not in self.data:
            return value
        x = self._as_float(key, value)
        self._check_range(key, x, minimum=minimum, positive=positive, nonzero=nonzero)
        return x

    def whole(self, key: str, default: Any = _MISSING, *, minimum: int | None = None) -> int:
        """A whole number (a count), optionally bounded: ``2.5`` is an error, not 2."""
        value = self._take(key, default)
        if value is default and key not in self.data:
            return value
        x = self._as_float(key, value)
        if x != math.floor(x):
            raise self.error(key, f"expected a whole number, got {value!r}")
        self._check_range(key, x, minimum=minimum)
        return int(x)

    def _check_range(self, key: str, x: float, *, minimum=None, positive=False, nonzero=False) -> None:
        if positive and not x > 0:
            raise self.error(key, f"must be > 0, got {x:g}")
        if minimum is not None and x < minimum:
            raise self.error(key, f"must be >= {minimum:g}, got {x:g}")
        if nonzero and x == 0:
            raise self.error(key, "must not be zero")

    def _quantity(self, key: str, units: Mapping[str, float], default: Any, **bounds: Any) -> float:
        actual, factor = self._pick_unit(key, units, default)
        if actual not in self.data:
            self._used.add(key)
            return default
        x = self._as_float(actual, self._take(actual, _MISSING)) * factor
        self._check_range(actual, x, **bounds)
        return x

    def length(self, key: str, default: Any = _MISSING, **bounds: Any) -> float:
        """A length in metres, from ``key`` (m) or ``key_mm`` (mm)."""
        return self._quantity(key, LENGTH_UNITS, default, **bounds)

    def angle(self, key: str, default: Any = _MISSING, **bounds: Any) -> float:
        """An angle in radians, from ``key`` (rad) or ``key_deg`` (degrees)."""
        return self._quantity(key, ANGLE_UNITS, default, **bounds)

    def boolean(self, key: str, default: Any = _MISSING) -> bool:
        value = self._take(key, default)
        if not isinstance(value, bool):
            raise self.error(key, f"expected true or false, got {value!r}")
        return value

    def string(self, key: str, default: Any = _MISSING, *, choices: Sequence[str] | None = None) -> str:
        value = self._take(key, default)
        if value is default and key not in self.data:
            return value
        if not isinstance(value, str):
            raise self.error(key, f"expected a string, got {type(value).__name__} {value!r}")
        if choices is not None and value not in choices:
            raise self.error(key, f"unknown value {value!r}; expected one of: {', '.join(choices)}")
        return value

    # ---------------------------------------------------------------------------------------------- vectors
    def _vector(self, key: str, n: int, value: Any) -> np.ndarray:
        if not isinstance(value, (list, tuple)):
            raise self.error(key, f"expected a list of {n} numbers, got {type(value).__name__} {value!r}")
        if len(value) != n:
            raise self.error(key, f"expected a list of {n} numbers, got {len(value)}")
        return np.array([self._as_float(f"{key}[{i}]", v) for i, v in enumerate(value)])

    def vector(self, key: str, n: int, default: Any = _MISSING) -> np.ndarray:
        """A list of ``n`` finite numbers, as given."""
        value = self._take(key, default)
        if value is default and key not in self.data:
            return value
        return self._vector(key, n, value)

    def _quantity_vector(self, key: str, n: int, units: Mapping[str, float], default: Any) -> np.ndarray:
        actual, factor = self._pick_unit(key, units, default)
        if actual not in self.data:
            self._used.add(key)
            return default
        return self._vector(actual, n, self._take(actual, _MISSING)) * factor

    def lengths(self, key: str, n: int, default: Any = _MISSING) -> np.ndarray:
        """``n`` lengths in metres from ``key`` (m) or ``key_mm`` (mm)."""
        return self._quantity_vector(key, n, LENGTH_UNITS, default)

    def angles(self, key: str, n: int, default: Any = _MISSING) -> np.ndarray:
        """``n`` angles in radians from ``key`` (rad) or ``key_deg`` (degrees)."""
        return self._quantity_vector(key, n, ANGLE_UNITS, default)

    # ----------------------------------------------------------------------------------------------- tables
    def table(self, key: str, default: Any = _MISSING) -> FieldReader | Any:
        value = self._take(key, default)
        if value is default and key not in self.data:
            return value
        if not isinstance(value, Mapping):
            raise self.error(key, f"expected a table, got {type(value).__name__} {value!r}")
        return FieldReader(value, file=self.file, path=self.field(key))

    def tables(self, key: str) -> list[FieldReader]:
        """A non-empty array of tables (TOML ``[[key]]``)."""
        value = self._take(key, _MISSING)
        if not isinstance(value, list) or not value:
            raise self.error(key, "expected a non-empty array of tables ([[" + key + "]])")
        out = []
        for i, item in enumerate(value):
            if not isinstance(item, Mapping):
                raise self.error(f"{key}[{i + 1}]", f"expected a table, got {type(item).__name__}")
            out.append(FieldReader(item, file=self.file, path=f"{self.field(key)}[{i + 1}]"))
        return out

    def header(self, default_name: str) -> tuple[str, str, str]:
        """(name, description, source): the identifying fields every file format starts with (strings, optional;
        the name defaults to ``default_name``, usually the file's stem)."""
        return self.string("name", default_name), self.string("description", ""), self.string("source", "")

    def finish(self) -> None:
        """Reject fields that no accessor asked for (misspelt or unsupported)."""
        unknown = [k for k in self.data if k not in self._used]
        if unknown:
            raise self.error(unknown[0], "unknown field (misspelt, or not supported here)")

"""One validation of every number that enters mechatron: API arguments, command-line options and file fields.

A value is checked where it enters, against what it means: finite (no NaN, no ±inf; a value so large that the
analysis would overflow — ``1e308`` kg — is refused by ``maximum``), in range, a whole number where a count is
meant. The error names the value (``--dt``, ``dt``, ``links[2].mass``) and its unit, as one line.

``number("dt", dt, positive=True, unit="s")`` returns ``float(dt)`` or raises
:class:`~mechatron.errors.InputError` ``dt must be a finite number > 0 s, got -1``. ``numbers`` does the same for
arrays and names the first bad entry.
"""

from __future__ import annotations

import math
import numbers as _numbers
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

#: Magnitudes beyond this (in SI) are refused as physical inputs: squares and products of such values overflow
#: float64 (1e308); the largest realistic machine is many orders of magnitude below.
LARGEST = 1e12


def _requirement(*, minimum: float | None, maximum: float | None, positive: bool, integer: bool,
                 unit: str, exceeded: bool = False) -> str:
    """The words of a requirement; the default bounds ±:data:`LARGEST` are named only when one was exceeded."""
    if (maximum == LARGEST or minimum == -LARGEST) and not exceeded:
        maximum = None if maximum == LARGEST else maximum
        minimum = None if minimum == -LARGEST else minimum
    kind = "whole number" if integer else "finite number"
    parts = []
    if positive:
        parts.append("> 0")
    elif minimum is not None:
        parts.append(f">= {minimum:g}")
    if maximum is not None:
        parts.append(f"<= {maximum:g}")
    bound = " and ".join(parts)
    return f"a {kind}" + (f" {bound}" if bound else "") + (f" {unit}" if unit and bound else "")


def number(name: str, value: Any, *, unit: str = "", minimum: float | None = None, maximum: float | None = LARGEST,
           positive: bool = False, integer: bool = False, allow_none: bool = False) -> Any:
    """``value`` checked: a real number, finite, ``> 0`` with ``positive``, ``>= minimum``, ``<= maximum`` (default
    :data:`LARGEST`; ``None`` for no bound) and whole with ``integer`` (then returned as ``int``), else
    :class:`~mechatron.errors.InputError` naming ``name`` and ``unit``. ``None`` passes through with
    ``allow_none``."""
    if value is None and allow_none:
        return None
    need = _requirement(minimum=minimum, maximum=maximum, positive=positive, integer=integer, unit=unit)
    if isinstance(value, bool) or not isinstance(value, (_numbers.Real, np.number)):
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise InputError(f"{name} must be {need}, got {value!r}") from None
        else:
            raise InputError(f"{name} must be {need}, got {value!r}")
    x = float(value)
    bad = (not math.isfinite(x) or (positive and not x > 0) or (minimum is not None and x < minimum)
           or (maximum is not None and x > maximum) or (integer and x != math.floor(x)))
    if bad:
        need = _requirement(minimum=minimum, maximum=maximum, positive=positive, integer=integer, unit=unit,
                            exceeded=abs(x) > LARGEST)
        shown = value if isinstance(value, (int, np.integer)) else f"{x:g}"
        raise InputError(f"{name} must be {need}, got {shown}")
    return int(x) if integer else x


def numbers(name: str, values: ArrayLike, *, unit: str = "", shape: tuple[int | None, ...] | None = None,
            minimum: float | None = None, maximum: float | None = LARGEST, positive: bool = False
            ) -> NDArray[np.float64]:
    """``values`` as a float array, every entry checked as by :func:`number`; ``shape`` (``None`` for any length
    along an axis) is checked too. The error names the first bad entry (``q[3]``, ``t[12]``)."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers, got {values!r}") from None
    if shape is not None and (array.ndim != len(shape)
                              or any(n is not None and n != m for n, m in zip(shape, array.shape))):
        want = " × ".join("N" if n is None else str(n) for n in shape) or "a scalar"
        raise InputError(f"{name} must be {want} numbers, got shape {array.shape}")
    ok = np.isfinite(array)
    if positive:
        ok &= array > 0
    if minimum is not None:
        ok &= array >= minimum
    if maximum is not None:
        ok &= array <= maximum
    if not ok.all():
        index = tuple(int(i) for i in np.argwhere(~ok)[0])
        where = f"{name}[{', '.join(map(str, index))}]" if index else name
        need = _requirement(minimum=minimum, maximum=maximum, positive=positive, integer=False, unit=unit,
                            exceeded=bool(abs(array[index]) > LARGEST))
        raise InputError(f"{where} must be {need}, got {array[index]:g}")
    return array


def positives(**values: float) -> None:
    """Check that every value (name → value) is a finite Python number > 0, else an
    :class:`~mechatron.errors.InputError` naming the first that is not."""
    for name, value in values.items():
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0, got {value!r}")

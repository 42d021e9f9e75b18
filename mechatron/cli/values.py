"""Typed command-line values: ``type=Number(positive=True, unit="s")`` checks an option's value as it is parsed
(:func:`mechatron.io.values.number`), so that ``--dt -1`` ends in one line naming ``--dt`` and exit status 2;
``type=Numbers(...)`` does the same for a comma-separated list (``--vmax 1,2,3``) and ``type=InputFile()`` for the
path of a file to read (a missing file or a directory is refused, naming the option and the path)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..io.values import LARGEST, number


class Number:
    """An argparse ``type``: a real number with the bounds of :func:`~mechatron.io.values.number` (finite, ``>
    0`` with ``positive``, ``>= minimum``, ``<= maximum``, whole with ``integer``; ``unit`` names the unit)."""

    def __init__(self, *, unit: str = "", minimum: float | None = None, maximum: float | None = LARGEST,
                 positive: bool = False, integer: bool = False) -> None:
        self.bounds: dict[str, Any] = dict(unit=unit, minimum=minimum, maximum=maximum, positive=positive,
                                           integer=integer)
        self.__name__ = "whole number" if integer else "number"  # argparse's name for the type

    def __call__(self, text: str) -> Any:
        try:
            return number("value", text, **self.bounds)
        except InputError as exc:  # argparse prefixes "argument --dt: "
            raise argparse.ArgumentTypeError(exc.message.replace("value must be", "must be", 1)) from None

    def __repr__(self) -> str:
        return self.__name__


def number_list(text: str, what: str, *, unit: str = "", minimum: float | None = -LARGEST,
                maximum: float | None = LARGEST, positive: bool = False) -> tuple[float, ...]:
    """``"1, 2.5,3"`` → (1.0, 2.5, 3.0), every value checked as by :func:`~mechatron.io.values.number` (default:
    finite, |x| <= :data:`~mechatron.io.values.LARGEST`), else :class:`~mechatron.errors.InputError` naming
    ``what`` and the value's place (``--vmax value 2 must be …``)."""
    parts = [part for part in (p.strip() for p in str(text).split(",")) if part]
    if not parts:
        raise InputError(f"{what} must be comma-separated numbers, got {text!r}")
    try:
        [float(part) for part in parts]
    except ValueError:
        raise InputError(f"{what} must be comma-separated numbers, got {text!r}") from None
    out = []
    for k, part in enumerate(parts):
        where = what if len(parts) == 1 else f"{what} value {k + 1}"
        out.append(number(where, part, unit=unit, minimum=None if positive else minimum, maximum=maximum,
                          positive=positive))
    return tuple(out)


class Numbers(Number):
    """An argparse ``type``: comma-separated numbers, each with the bounds of :class:`Number` (how many is checked
    where the mechanism is known)."""

    def __init__(self, *, unit: str = "", minimum: float | None = -LARGEST, maximum: float | None = LARGEST,
                 positive: bool = False) -> None:
        super().__init__(unit=unit, minimum=minimum, maximum=maximum, positive=positive)
        self.bounds.pop("integer")
        self.__name__ = "numbers"

    def __call__(self, text: str) -> Any:
        try:
            return number_list(text, "value", **self.bounds)
        except InputError as exc:
            raise argparse.ArgumentTypeError(exc.message.replace("value ", "", 1)) from None


class InputFile:
    """An argparse ``type``: the path of a file to read; a path that does not exist or is not a file (a directory)
    is refused as the option is parsed: ``argument --task: no such file: 'x.toml'``."""

    __name__ = "file"

    def __call__(self, text: str) -> str:
        path = Path(text)
        if not text:
            raise argparse.ArgumentTypeError("needs a file name, got ''")
        if path.is_dir():
            raise argparse.ArgumentTypeError(f"{text!r} is a directory, not a file")
        if not path.is_file():
            raise argparse.ArgumentTypeError(f"no such file: {text!r}")
        return text

    def __repr__(self) -> str:
        return self.__name__


#: The usual kinds of option value.
POSITIVE = Number(positive=True)
COUNT = Number(integer=True, minimum=1)
FRACTION = Number(positive=True, maximum=1.0)
FILE = InputFile()


def NAME(text: str) -> str:  # noqa: N802 - an argparse type, named as the value it reads
    """An argparse ``type``: a non-empty name (a frame, a joint), without surrounding blanks."""
    if not text.strip():
        raise argparse.ArgumentTypeError("needs a name, got an empty one")
    return text.strip()

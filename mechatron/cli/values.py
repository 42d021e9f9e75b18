"""Typed command-line values: ``type=Number(positive=True, unit="s")`` checks an option's value as it is parsed
(:func:`mechatron.io.values.number`), so that ``--dt -1`` ends in one line naming ``--dt`` and exit status 2."""

from __future__ import annotations

import argparse
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


#: The usual kinds of option value.
POSITIVE = Number(positive=True)
COUNT = Number(integer=True, minimum=1)
FRACTION = Number(positive=True, maximum=1.0)

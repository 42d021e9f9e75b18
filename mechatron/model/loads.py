"""External loads on a mechanism: one type, :class:`Load`, wherever loads are given (dynamics, sizing, tasks)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError


@dataclass(frozen=True, init=False)
class Load:
    """A force (N) and a moment (N·m), both in world axes, applied at the origin of the frame ``frame``.

    ``Load("tool", [0, 0, -50])`` is a 50 N weight hanging at the tool; ``Load("V", [-5e4, 0, 0])`` the digging
    resistance at an excavator's tooth. Forces act on the mechanism (a reaction of the environment).
    """

    frame: str
    force: np.ndarray
    moment: np.ndarray

    def __init__(self, frame: str, force: ArrayLike, moment: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        if not isinstance(frame, str) or not frame:
            raise InputError(f"a load's frame must be a frame name, got {frame!r}")
        values = []
        for what, vector in (("force", force), ("moment", moment)):
            arr = np.asarray(vector, dtype=float).reshape(-1)
            if arr.shape == (2,):  # a planar mechanism: (x, y)
                arr = np.append(arr, 0.0)
            if arr.shape != (3,) or not np.all(np.isfinite(arr)):
                raise InputError(f"the {what} of a load at {frame} must be 3 finite numbers (world axes), "
                                 f"got {vector!r}")
            values.append(arr)
        object.__setattr__(self, "frame", frame)
        object.__setattr__(self, "force", values[0])
        object.__setattr__(self, "moment", values[1])


LoadLike = Load | tuple
#: What every ``loads`` argument takes: loads, or (frame, force[, moment]) tuples read as loads.
Loads = Iterable[LoadLike] | None


def as_loads(loads: Loads) -> tuple[Load, ...]:
    """``loads`` as a tuple of :class:`Load` (a ``(frame, force[, moment])`` tuple is read as a Load)."""
    if not loads:
        return ()
    out = []
    for item in loads:
        out.append(item if isinstance(item, Load) else _from_tuple(item))
    return tuple(out)


def _from_tuple(item: Any) -> Load:
    if not isinstance(item, (tuple, list)) or len(item) not in (2, 3):
        raise InputError(f"a load is Load(frame, force[, moment]) or (frame, force[, moment]), got {item!r}")
    return Load(*item)

"""A requirement at a design — a value against its limit, its margin and verdict — shared by every optimal-design
problem of :mod:`mechatron.optimal` (design files and named problems alike)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Vector = NDArray[np.float64]


#: mechatron's own rule, not a standard's: a requirement counts as met down to a margin of
#: −REQUIREMENT_SLACK × max(1, |limit|) (in the requirement's unit), so that an optimum on an active requirement,
#: which the solver and the re-evaluation on the Pinocchio model place only to their tolerances on either side of
#: the limit, is not declared infeasible for a rounding-size difference. Such a margin is reported "met within
#: slack", never "met" (:attr:`Requirement.verdict`).
REQUIREMENT_SLACK = 1e-6


@dataclass(frozen=True)
class Requirement:
    """One requirement at a design: ``value`` against ``limit`` (``kind`` "min": value ≥ limit, "max": value ≤
    limit), in ``unit``; ``margin`` = value − limit for "min", limit − value for "max" (≥ 0 when met)."""

    name: str
    value: float
    limit: float
    kind: str
    unit: str

    @property
    def margin(self) -> float:
        return self.value - self.limit if self.kind == "min" else self.limit - self.value

    def met(self, tolerance: float = REQUIREMENT_SLACK) -> bool:
        """margin ≥ −tolerance × max(1, |limit|) (:data:`REQUIREMENT_SLACK`); False for a NaN margin."""
        return bool(self.margin >= -tolerance * max(1.0, abs(self.limit)))

    @property
    def verdict(self) -> str:
        """``met`` (margin ≥ 0), ``met within slack`` (−:data:`REQUIREMENT_SLACK` × max(1, |limit|) ≤ margin < 0)
        or ``NOT MET``: the words of the reports."""
        return "met" if self.margin >= 0 else "met within slack" if self.met() else "NOT MET"

    def line(self, width: int) -> str:
        """The report's line: name (padded to ``width``), value, ≥ or ≤, limit, margin, unit and verdict."""
        sign = "≥" if self.kind == "min" else "≤"
        return (f"  {self.name:<{width}} {self.value:12.6g} {sign} {self.limit:<10.6g} margin {self.margin:10.3g} "
                f"{self.unit}  {self.verdict}")

"""Plausible ranges of the fields of a front-shovel design file and its ``[machine]`` table
(docs/front_shovel_design.md). They are mechatron's own bounds, not a standard's: wide enough for any excavator from a
mini excavator to a mining shovel, narrow enough that a value in another unit (a length in mm, a mass in g) or a
slip of the keyboard is refused naming its field and its range before the design is synthesised, rather than
surfacing later as a geometry that cannot be built."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError


@dataclass(frozen=True)
class Plausible:
    """The range ``low`` … ``high`` (in ``unit``; ``low`` excluded with ``low_open``) of a field, and ``why`` a value
    outside it is refused (what it suggests)."""

    low: float
    high: float
    unit: str
    why: str
    low_open: bool = False

    def check(self, name: str, value: float) -> float:
        """``value`` (float) if it lies in the range, else :class:`~mechatron.errors.InputError` naming the field
        ``name`` and the range (NaN and ±inf are outside every range)."""
        x = float(value)
        above = x > self.low if self.low_open else x >= self.low
        if not (math.isfinite(x) and above and x <= self.high):
            unit = f" {self.unit}" if self.unit else ""
            bounds = f"> {self.low:g} and <= {self.high:g}" if self.low_open else \
                f"from {self.low:g} to {self.high:g}"
            raise InputError(f"must be {bounds}{unit}, mechatron's plausible range ({self.why}), got {x:g}",
                             field=name)
        return x


#: Lengths of the working device and the machine (m): link lengths, levers, working dimensions, tracks.
LENGTH = Plausible(0.01, 100.0, "m", "a length in mm would be 1000 times larger")
#: Coordinates (m) of a pin, a centre of mass or the slew axis, and heights of the lift chart.
POSITION = Plausible(-100.0, 100.0, "m", "a coordinate in mm would be 1000 times larger")
#: Heights of a centre of mass above the ground (m).
HEIGHT = Plausible(0.0, 100.0, "m", "at or above the ground; a height in mm would be 1000 times larger")
#: Angles of the design (degrees, the fields named ``_deg``).
ANGLE = Plausible(-180.0, 180.0, "deg", "an angle in degrees, one turn at most")
#: The bucket's angles: ζ to the ground at R0min and R2max, and the dump angle δ (degrees).
BUCKET_ANGLE = Plausible(0.0, 90.0, "deg", "an angle between the bucket and the horizontal, in degrees")
#: The included angle of the bucket cylinder's triangle at the start of its stroke (degrees).
INCLUDED_ANGLE = Plausible(0.0, 180.0, "deg", "the angle between two sides of a triangle, in degrees", low_open=True)
#: Stroke ratios λ = L_max/L_min of the cylinders.
STROKE_RATIO = Plausible(1.1, 3.0, "", "λ = L_max/L_min: 1 is a cylinder without a stroke; a single-stage "
                                       "cylinder stays below 2, a telescopic one below 3")
#: k = e_start/e_end, the ratio of a cylinder's moment arms at the two ends of its stroke.
ARM_RATIO = Plausible(0.2, 5.0, "", "the moment arm at one end of the stroke more than 5 times the other's leaves "
                                    "the joint without force at that end")
#: Masses of the links (kg, 0 allowed: a massless link).
LINK_MASS = Plausible(0.0, 2e6, "kg", "2000 t is beyond the heaviest excavators; a mass in g would be 1000 times "
                                      "larger")
#: Masses of the upper structure and the undercarriage (kg).
BODY_MASS = Plausible(100.0, 2e6, "kg", "2000 t is beyond the heaviest excavators; a mass in t would be 1000 "
                                        "times smaller, one in g 1000 times larger")
#: Cylinder bores (m).
BORE = Plausible(0.01, 2.0, "m", "a bore in mm would be 1000 times larger")
#: Rod diameters (m).
ROD = Plausible(0.0, 2.0, "m", "a diameter in mm would be 1000 times larger", low_open=True)
#: Boom cylinders side by side.
BOOM_CYLINDERS = Plausible(1, 4, "", "excavators have one or two boom cylinders")

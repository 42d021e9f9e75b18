r"""Half of a two-rope rod (clamshell) grab while scooping (seed 003, Mikhailov 2006; notes seed-linkages.md).

Bodies (the paper's numbering): jaw 1 (m1, J1) with its hinge point 1 on the grab axis, its cutting edge 2 and its
ear 3; the rods 2 (two parallel rods: 2 m2, 2 J2) from the ear 3 to point 4 of the upper crosshead 3 (half of it:
m3/2), which slides on the axis. The lower crosshead carrying the jaw hinge slides on the axis too (massless here, as
in the paper, which has no body for it). The constraints of eq. (6):

- Φ1: jaw point 1 stays on the axis x = 0 (here: the jaw turns on the lower crosshead, a vertical slider);
- Φ2: the tip 2 stays on the scooping curve y = η(x) = −e + A (x + d)², A = (e − b)/(L/2 − d)², −L/2 ≤ x ≤ 0;
- Φ3, Φ4: revolute pair jaw–rods at point 3; Φ5, Φ6: revolute pair rods–upper crosshead at point 4.

The origin is on the material surface (η(−L/2) = −b: the tip starts at the initial penetration b) and the modelled
jaw is the left one: open at x_tip = −L/2, closed at x_tip = 0 where both tips meet. The paper gives no numbers; the
default geometry (a grab of about 1.4 m³) is the reconstruction of /work notes, see :func:`grab`. The jaw's shape is
given in its closed position relative to its hinge; its angle φ1 (the coordinate ``phi1``, the paper's φ10 with the
jaw frame parallel to the world when closed) is negative when open.

For any jaw angle φ the positions follow in closed form (used by the tests): x_tip = r sin φ (r = hinge–tip
length, the tip straight below the hinge when closed), y_hinge = η(x_tip) + r cos φ, and the upper crosshead height
from |P4 − P3| = rod length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Mechanism, Parameter
from ..planar import GROUND, PlanarBuilder


@dataclass(frozen=True)
class GrabGeometry:
    """Geometry and masses of the half grab (SI units)."""

    opening: float = 2.80  # L, tip-to-tip span of the open grab
    penetration: float = 0.25  # b, tip depth at x = −L/2
    depth: float = 0.75  # e = H, depth of the deepest point of the curve
    deepest_x: float = 0.50  # d, the deepest point is at x = −d
    tip_length: float = 1.70  # hinge to tip, vertical when closed
    ear: tuple[float, float] = (-1.00, 0.10)  # ear 3 relative to the hinge, closed
    jaw_centre: tuple[float, float] = (-0.55, -0.80)  # jaw centre of mass relative to the hinge, closed
    rod_length: float = 1.90
    crosshead_pin: tuple[float, float] = (-0.25, -0.10)  # point 4 relative to the upper crosshead's centre
    jaw_mass: float = 650.0  # m1
    jaw_inertia: float = 200.0  # J1 about its centre
    rod_mass: float = 60.0  # m2, one rod (the model carries 2 m2)
    upper_crosshead_mass: float = 450.0  # m3, whole (the model carries m3/2)

    @property
    def curvature(self) -> float:
        """A = (e − b)/(L/2 − d)² (1/m)."""
        return (self.depth - self.penetration) / (self.opening / 2 - self.deepest_x) ** 2

    def eta(self, x: float) -> float:
        return -self.depth + self.curvature * (x + self.deepest_x) ** 2

    def closed_form(self, phi: float) -> dict[str, np.ndarray | float]:
        """Hinge, tip, ear, point 4 and the upper crosshead height for the jaw angle φ (rad, ≤ 0 open)."""
        c, s = math.cos(phi), math.sin(phi)
        rotate = np.array([[c, -s], [s, c]])
        tip_x = self.tip_length * s
        hinge = np.array([0.0, self.eta(tip_x) + self.tip_length * c])
        ear = hinge + rotate @ np.asarray(self.ear)
        dx = self.crosshead_pin[0] - ear[0]
        if abs(dx) > self.rod_length:
            raise InputError("grab: the rod cannot reach the upper crosshead")
        pin4 = np.array([self.crosshead_pin[0], ear[1] + math.sqrt(self.rod_length**2 - dx * dx)])
        return {"hinge": hinge, "tip": hinge + rotate @ np.array([0.0, -self.tip_length]), "ear": ear, "pin4": pin4,
                "upper_crosshead": pin4[1] - self.crosshead_pin[1]}

    @property
    def open_angle(self) -> float:
        """φ1 with the tip at x = −L/2."""
        ratio = -self.opening / 2 / self.tip_length
        if not -1 <= ratio <= 1:
            raise InputError(f"grab: the jaw ({self.tip_length:g} m) cannot open to L = {self.opening:g} m")
        return math.asin(ratio)


def grab(**overrides: float) -> Mechanism:
    """Half of a rod (clamshell) grab scooping along a parabola (seed 003); input: the jaw angle ``phi1``."""
    g = GrabGeometry(**overrides)
    if not (0 <= g.deepest_x < g.opening / 2 and g.depth > g.penetration > 0):
        raise InputError("grab: the scooping curve needs 0 <= d < L/2 and e > b > 0")
    phi_open = g.open_angle
    pose = g.closed_form(phi_open)
    c, s = math.cos(phi_open), math.sin(phi_open)
    rotate = np.array([[c, -s], [s, c]])
    hinge, tip, ear, pin4 = pose["hinge"], pose["tip"], pose["ear"], pose["pin4"]
    crosshead = np.array([0.0, pose["upper_crosshead"]])

    b = PlanarBuilder("grab")
    b.point("axis_low", GROUND, (0.0, hinge[1]), report=False)
    b.point("axis_high", GROUND, crosshead, report=False)
    lower = b.prismatic("lower_crosshead", "axis_low", (0.0, 1.0), coordinate="y_lower")
    b.point("P1_lower", lower, hinge, report=False)
    jaw = b.revolute("jaw", "P1_lower", angle=phi_open, coordinate="phi1", limits=(phi_open, 0.0), mass=g.jaw_mass,
                     com=hinge + rotate @ np.asarray(g.jaw_centre), inertia=g.jaw_inertia)
    b.point("P1", jaw, hinge)
    b.point("P2", jaw, tip)
    b.point("P3", jaw, ear)
    b.point("C1", jaw, hinge + rotate @ np.asarray(g.jaw_centre))
    upper = b.prismatic("upper_crosshead", "axis_high", (0.0, 1.0), coordinate="y3", mass=g.upper_crosshead_mass / 2,
                        com=crosshead)
    b.point("C3", upper, crosshead)
    b.point("P4", upper, pin4)
    rods = b.revolute("rods", "P4", toward=ear, coordinate="rods_angle", mass=2 * g.rod_mass,
                      com=(ear + pin4) / 2, inertia=2 * g.rod_mass * g.rod_length**2 / 12)
    b.point("P3_rods", rods, ear, report=False)
    b.point("C2", rods, (ear + pin4) / 2)
    b.pin("P3_rods", "P3")
    A, d, e = g.curvature, g.deepest_x, g.depth
    b.on_curve("P2", lambda x: -e + A * (x + d) ** 2, lambda x: 2 * A * (x + d), lambda x: 2 * A,
               label=f"y = -{e:g} + {A:.6g} (x + {d:g})^2")
    b.line("jaw", "P1", "P3", "P2", "P1")
    b.line("rods", "P3", "P4")
    b.line("upper crosshead", "C3", "P4")
    params = {name: Parameter(name, float(value), "length", name)
              for name, value in (("opening", g.opening), ("penetration", g.penetration), ("depth", g.depth),
                                  ("deepest_x", g.deepest_x), ("tip_length", g.tip_length),
                                  ("rod_length", g.rod_length))}
    return b.build(actuated=["phi1"], parameters=params, tool="P2",
                   description=f"half of a rod grab (L = {g.opening:g} m opening, scooping depth {g.depth:g} m)",
                   rebuild=lambda v: grab(**{**overrides, **v}), input_rates={"phi1": 0.5},
                   notes=["geometry invented (the paper gives no numbers); see mechatron.machines.grab"])

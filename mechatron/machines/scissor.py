r"""Scissor lifts of any number of stages, as mechanism files.

A stage is two straight arms of length ℓ crossing at their middles K, each arm's foot, crossing pin and top drawn in
line; the stages stand on one another, every arm's top pinned to the foot of the next stage's other arm. The bottom
stage stands on the base frame — arm ``a0``'s foot on a fixed pin, arm ``b0``'s foot on a roller along the base —
and the platform sits on the top stage — pinned to the top of ``b{n-1}``, the top of ``a{n-1}`` rolling along its
rail. One hydraulic cylinder lifts it, from a pin P of the base frame to a bracket Q at ``fraction`` of arm ``a0``
from its foot (Q and every K are derived points). With every arm at the angle θ to the horizontal (drawn at θ₀),

.. math::

    c^2 = |Q − P|^2 = f^2 ℓ^2 + ρ^2 − 2 f ℓ ρ \cos(θ − α), \qquad h = n ℓ \sin θ + e,

for the cylinder length c (P at distance ρ and angle α from the fixed foot, f the bracket's fraction), the deck's
height h (e its height above the top pins) and n stages. The potential energy of the platform (mass M) and the arms
(mass m each, centres at the stages' middles (i + ½) ℓ sin θ) is V = g ℓ sin θ (n M + n² m) + const, so the
cylinder holds the lift at rest with F = dV/dc = g ℓ cos θ (dθ/dc)(n M + n² m) [virtual work].

:func:`scissor_lift_spec` builds the :class:`~mechatron.model.linkage.LinkageSpec`, :func:`write_scissor_lift` its
file. A one-stage lift like examples/data/scissor_lift.toml; many stages make a large mechanism (330 stages are a
file of 1,000 points).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..model.linkage import BodySpec, ClosureSpec, JointSpec, LengthSpec, LinkageSpec, PointSpec
from ..model.linkage_file import write_linkage_file
from ..model.planar import GROUND


@dataclass(frozen=True)
class ScissorLift:
    """A scissor lift (m, kg, rad): ``stages`` stages of arms of ``arm`` length drawn at ``angle`` to the
    horizontal, arms of ``arm_mass`` each, the platform's ``platform_mass`` (its centre ``deck`` above the top
    pins, I = ``platform_inertia``), the cylinder from P = ``base`` to the bracket at ``fraction`` of arm a0, its
    pin-to-pin ``stroke``; with ``edge_points``, each arm's outline drawn as that many points along each long edge,
    ``edge`` apart."""

    stages: int = 1
    arm: float = 1.2
    angle: float = math.asin(0.6)
    arm_mass: float = 30.0
    platform_mass: float = 500.0
    platform_inertia: float = 80.0
    deck: float = 0.08
    base: tuple[float, float] = (0.5, -0.15)
    fraction: float = 0.75
    stroke: tuple[float, float] = (0.5, 0.84)
    #: Points along each long edge of every arm (a bar ``edge`` wide), drawn and carried by the arm: its outline in
    #: the charts. A drawing of many points.
    edge_points: int = 0
    edge: float = 0.04

    @property
    def width(self) -> float:
        """The horizontal span of an arm, ℓ cos θ (m)."""
        return self.arm * math.cos(self.angle)

    def height(self, stage: int) -> float:
        """The height of the feet of ``stage`` (m; the top of the last stage is ``stages``)."""
        return stage * self.arm * math.sin(self.angle)


def scissor_lift_spec(lift: ScissorLift = ScissorLift()) -> LinkageSpec:
    """The mechanism file of ``lift`` (module docstring) as a spec: points ``L{i}`` (left, above the fixed foot) and
    ``R{i}`` (right) at the stages' heights, crossing pins ``K{i}``, arms ``a{i}`` = [L{i}, R{i+1}, K{i}] and
    ``b{i}`` = [R{i}, L{i+1}, K{i}], the platform [L{n}, rail, deck], the cylinder ``cyl`` from P to Q (a0's
    bracket); the arms' lengths ``a{i}``, ``b{i}`` are named lengths."""
    n, w = lift.stages, lift.width
    points = [PointSpec("P", lift.base), PointSpec("track", (w, 0.0), direction=(1.0, 0.0), report=False)]
    for i in range(n + 1):
        points += [PointSpec(f"L{i}", (0.0, lift.height(i))), PointSpec(f"R{i}", (w, lift.height(i)))]
    points += [PointSpec(f"K{i}", None, (f"L{i}", f"R{i + 1}")) for i in range(n)]
    points += [PointSpec("Q", None, ("L0", "R1"), lift.fraction),
               PointSpec("rail", (w, lift.height(n)), direction=(1.0, 0.0), report=False),
               PointSpec("deck", (w / 2, lift.height(n) + lift.deck))]
    bodies = [BodySpec(GROUND, ("L0", "P", "track"))]
    joints = [JointSpec("revolute", body="a0", at="L0", coordinate="theta", toward="R1")]
    closures = [ClosureSpec("slider", point="R0", line="track")]
    for i in range(n):
        a_points = ("L0", "R1", "K0", "Q") if i == 0 else (f"L{i}", f"R{i + 1}", f"K{i}")
        for name, ends in ((f"a{i}", a_points), (f"b{i}", (f"R{i}", f"L{i + 1}", f"K{i}"))):
            edges = _edges(lift, name, *(p.at for p in points if p.name in ends[:2]))
            points += edges
            outline = tuple(p.name for p in edges)
            bodies.append(BodySpec(name, ends + outline, lift.arm_mass, shape="bar",
                                   draw=outline + outline[:1] if outline else None))
        joints.append(JointSpec("revolute", body=f"b{i}", at=f"K{i}", coordinate=f"scissor{i}", toward=f"L{i + 1}"))
        if i + 1 < n:
            joints.append(JointSpec("revolute", body=f"a{i + 1}", at=f"L{i + 1}", coordinate=f"knee{i + 1}",
                                    toward=f"R{i + 2}"))
        if i > 0:
            closures.append(ClosureSpec("pin", point=f"R{i}", bodies=(f"a{i - 1}", f"b{i}")))
    bodies.append(BodySpec("platform", (f"L{n}", "rail", "deck"), lift.platform_mass, com="deck",
                           inertia=lift.platform_inertia))
    joints += [JointSpec("revolute", body="platform", at=f"L{n}", coordinate="tilt", toward="rail"),
               JointSpec("cylinder", name="cyl", base="P", eye="Q", stroke=lift.stroke)]
    closures.append(ClosureSpec("slider", point=f"R{n}", line="rail", body=f"a{n - 1}"))
    lengths = [LengthSpec(f"{kind}{i}", (f"L{i}", f"R{i + 1}") if kind == "a" else (f"R{i}", f"L{i + 1}"), lift.arm)
               for i in range(n) for kind in "ab"]
    return LinkageSpec(
        name=f"scissor_lift_{n}" if n > 1 else "scissor_lift", points=tuple(points),
        bodies=tuple(bodies), joints=tuple(joints), actuated=("cyl",), closures=tuple(closures),
        lengths=tuple(lengths), description=f"{n}-stage scissor lift: arms of {lift.arm:g} m, one cylinder, "
        f"{lift.platform_mass:g} kg platform", source="mechatron.machines.scissor", tool="deck",
        input_rates={"cyl": 0.05})


def _edges(lift: ScissorLift, arm: str, start: tuple[float, float], end: tuple[float, float]) -> list[PointSpec]:
    """``lift.edge_points`` points along each long edge of the arm from ``start`` to ``end`` (m), ``lift.edge``
    apart, in order round the outline; not reported in tables."""
    k = lift.edge_points
    if k == 0:
        return []
    (x0, y0), (x1, y1) = start, end
    length = math.hypot(x1 - x0, y1 - y0)
    nx, ny = -(y1 - y0) / length * lift.edge / 2, (x1 - x0) / length * lift.edge / 2
    ts = [j / (k - 1) if k > 1 else 0.5 for j in range(k)]
    out = [PointSpec(f"{arm}_edge{j}", (x0 + t * (x1 - x0) + nx, y0 + t * (y1 - y0) + ny), report=False)
           for j, t in enumerate(ts)]
    out += [PointSpec(f"{arm}_edge{k + j}", (x0 + t * (x1 - x0) - nx, y0 + t * (y1 - y0) - ny), report=False)
            for j, t in enumerate(reversed(ts))]
    return out


def write_scissor_lift(path: str | Path, lift: ScissorLift = ScissorLift()) -> Path:
    """Write the mechanism file of :func:`scissor_lift_spec` to ``path``."""
    return write_linkage_file(scissor_lift_spec(lift), path, f"A {lift.stages}-stage scissor lift, written by "
                              "mechatron.machines.scissor.write_scissor_lift()")

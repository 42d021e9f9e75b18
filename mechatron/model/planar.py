"""Building planar linkages as Pinocchio trees with closures, from a drawing of one assembled position.

A linkage is described the way it is drawn: the world coordinates (x, y, metres) of every pin in one assembled
reference position, which body each pin belongs to, the joints of a spanning tree (revolute joints at pins, prismatic
joints along a direction, hydraulic cylinders between two pins) and the closures that close the loops. The builder
turns world coordinates into body coordinates, so the reference configuration of the tree satisfies every closure by
construction (and :meth:`PlanarBuilder.build` checks that it does).

Conventions: the mechanism moves in the world xy plane, gravity is along −y; a revolute joint's coordinate is the
angle of its body relative to the parent body (the absolute angle for a body pinned to the ground); a prismatic
joint's coordinate is the displacement along its direction; a cylinder's coordinate is its pin-to-pin length.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import InputError
from .closures import Closure, OnCurve, Pin, Slider
from .mechanism import Cylinder, Measure, Mechanism, Parameter, SketchLine

GROUND = "ground"
Point2 = Sequence[float]


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _angle_of(vector: Point2) -> float:
    return math.atan2(vector[1], vector[0])


@dataclass
class _Body:
    joint_id: int
    origin: np.ndarray  # world position of the body frame in the reference drawing
    angle: float  # world angle of the body frame in the reference drawing
    frame_id: int

    def local(self, world: Point2) -> np.ndarray:
        """Body-frame coordinates (x, y, 0) of a world point of the reference drawing."""
        d = np.asarray(world, dtype=float) - self.origin
        c, s = math.cos(self.angle), math.sin(self.angle)
        return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], 0.0])


@dataclass
class _Point:
    body: str
    world: np.ndarray
    report: bool = True


class PlanarBuilder:
    """Collects bodies, joints, points and closures of a planar linkage drawn in one assembled position."""

    def __init__(self, name: str, gravity: float = 9.81) -> None:
        self.name = name
        self.model = pin.Model()
        self.model.name = name
        self.model.gravity = pin.Motion(np.array([0.0, -gravity, 0.0]), np.zeros(3))
        ground_frame = self.model.addFrame(pin.Frame(GROUND, 0, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
        self.bodies: dict[str, _Body] = {GROUND: _Body(0, np.zeros(2), 0.0, ground_frame)}
        self.points: dict[str, _Point] = {}
        self.reference: list[float] = []
        self.closures: list[Closure] = []
        self.sketch: list[SketchLine] = []
        self.measures: list[Measure] = []
        self.cylinders: dict[str, Cylinder] = {}

    # ---------------------------------------------------------------------------------------------- points
    def point(self, name: str, body: str, at: Point2, direction: Point2 | None = None, *, report: bool = True) -> str:
        """A named point (an operational frame) fixed to ``body`` at the world position ``at`` of the drawing; its x
        axis is along ``direction`` (world, drawing) if given, else along the body frame's x axis. Points with
        ``report`` false are helpers (guides, slider frames) left out of sweep tables."""
        if name in self.points or self.model.existFrame(name):
            raise InputError(f"{self.name}: point {name!r} defined twice")
        b = self._body(body)
        angle = b.angle if direction is None else _angle_of(direction)
        placement = pin.SE3(_rz(angle - b.angle), b.local(at))
        self.model.addFrame(pin.Frame(name, b.joint_id, b.frame_id, placement, pin.FrameType.OP_FRAME))
        self.points[name] = _Point(body, np.asarray(at, dtype=float), report)
        return name

    def where(self, point: str) -> np.ndarray:
        """World position of a point in the reference drawing."""
        return self._point(point).world.copy()

    def _point(self, name: str) -> _Point:
        if name not in self.points:
            raise InputError(f"{self.name}: unknown point {name!r}")
        return self.points[name]

    def _body(self, name: str) -> _Body:
        if name not in self.bodies:
            raise InputError(f"{self.name}: unknown body {name!r}")
        return self.bodies[name]

    # ---------------------------------------------------------------------------------------------- joints
    def _add_body(self, name: str, parent: _Body, joint_model: pin.JointModel, placement: pin.SE3,
                  coordinate: str, reference: float, limits: tuple[float, float], origin: np.ndarray,
                  angle: float, mass: float, com: Point2 | None, inertia: float) -> str:
        if name in self.bodies:
            raise InputError(f"{self.name}: body {name!r} defined twice")
        lower, upper = limits
        joint_id = self.model.addJoint(parent.joint_id, joint_model, placement, coordinate,
                                       np.array([np.inf]), np.array([np.inf]), np.array([lower]), np.array([upper]))
        frame_id = self.model.addFrame(pin.Frame(name, joint_id, self.model.nframes - 1, pin.SE3.Identity(),
                                                 pin.FrameType.BODY))
        body = _Body(joint_id, origin, angle, frame_id)
        self.bodies[name] = body
        if mass < 0 or inertia < 0:
            raise InputError(f"{self.name}: body {name}: mass and inertia must be >= 0")
        if mass > 0 or inertia > 0:
            c = body.local(com if com is not None else origin)
            # planar body: only I_zz matters; I_xx = I_yy = I_zz/2 makes the tensor physical (a thin plate)
            self.model.appendBodyToJoint(joint_id, pin.Inertia(mass, c, np.diag([inertia / 2, inertia / 2, inertia])),
                                         pin.SE3.Identity())
        self.reference.append(reference)
        return name

    def revolute(self, body: str, at: str, *, toward: str | Point2 | None = None, angle: float | None = None,
                 coordinate: str | None = None, limits: tuple[float, float] = (-np.inf, np.inf), mass: float = 0.0,
                 com: Point2 | None = None, inertia: float = 0.0) -> str:
        """A body turning about the point ``at`` (which belongs to the parent body).

        Args:
            toward: A point or world position the body frame's x axis points to in the drawing (default: along the
                parent's x axis). With a ground parent the coordinate is then the absolute angle of that line.
            angle: Instead of ``toward``, the world angle (rad) of the body frame's x axis in the drawing.
            coordinate: Name of the joint coordinate (default ``{body}_angle``).
            limits: Coordinate limits (rad).
            mass, com, inertia: Mass (kg), centre of mass (world point of the drawing) and I_zz about it (kg·m²).
        """
        pivot = self._point(at)
        parent = self._body(pivot.body)
        if toward is not None and angle is not None:
            raise InputError(f"{self.name}: body {body}: give toward or angle, not both")
        if angle is not None:
            pass
        elif toward is None:
            angle = parent.angle
        else:
            target = self._point(toward).world if isinstance(toward, str) else np.asarray(toward, dtype=float)
            angle = _angle_of(target - pivot.world)
        placement = pin.SE3(np.eye(3), parent.local(pivot.world))
        return self._add_body(body, parent, pin.JointModelRZ(), placement, coordinate or f"{body}_angle",
                              angle - parent.angle, limits, pivot.world.copy(), angle, mass, com, inertia)

    def prismatic(self, body: str, at: str, direction: Point2, *, reference: float = 0.0,
                  coordinate: str | None = None, limits: tuple[float, float] = (-np.inf, np.inf),
                  mass: float = 0.0, com: Point2 | None = None, inertia: float = 0.0) -> str:
        """A body sliding on the parent of point ``at`` along ``direction`` (world, drawing); its coordinate is the
        displacement of the body frame from ``at`` (m), equal to ``reference`` in the drawing. The body frame keeps
        the parent's orientation."""
        pivot = self._point(at)
        parent = self._body(pivot.body)
        unit = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
        local_axis = _rz(-parent.angle) @ np.array([unit[0], unit[1], 0.0])
        if abs(local_axis[0]) > 1 - 1e-15:
            joint_model = pin.JointModelPX() if local_axis[0] > 0 else pin.JointModelPrismaticUnaligned(local_axis)
        elif abs(local_axis[1]) > 1 - 1e-15 and local_axis[1] > 0:
            joint_model = pin.JointModelPY()
        else:
            joint_model = pin.JointModelPrismaticUnaligned(local_axis)
        placement = pin.SE3(np.eye(3), parent.local(pivot.world))
        return self._add_body(body, parent, joint_model, placement, coordinate or f"{body}_position",
                              reference, limits, pivot.world + reference * unit, parent.angle, mass, com, inertia)

    def cylinder(self, name: str, base: str, eye: str, *, stroke: tuple[float, float], count: int = 1,
                 barrel_mass: float = 0.0, rod_mass: float = 0.0) -> str:
        """A hydraulic cylinder from point ``base`` to point ``eye`` (on different bodies).

        The barrel turns about ``base`` (body ``{name}_barrel``), the rod slides in it (body ``{name}_rod``, joint
        coordinate ``name`` = the pin-to-pin length, limited to ``stroke`` = (L_min, L_max)), and a pin closure joins
        the rod eye (point ``{name}_eye``) to ``eye``. Barrel and rod masses sit at their middles as slender rods.
        ``count`` cylinders act side by side (e.g. a twin boom cylinder: one in the planar model, twice the force).
        """
        start, end = self._point(base).world, self._point(eye).world
        length = float(np.linalg.norm(end - start))
        if not stroke[0] - 1e-9 <= length <= stroke[1] + 1e-9:
            raise InputError(f"{self.name}: cylinder {name} is {length:.6g} m long in the drawing, outside its "
                             f"stroke [{stroke[0]:.6g}, {stroke[1]:.6g}] m")
        unit = (end - start) / length
        barrel_length = stroke[0]
        barrel = self.revolute(f"{name}_barrel", base, toward=eye, coordinate=f"{name}_angle", mass=barrel_mass,
                               com=start + 0.5 * barrel_length * unit, inertia=barrel_mass * barrel_length**2 / 12)
        self.point(f"{name}_base", barrel, start, report=False)
        rod_length = stroke[1] - stroke[0]
        rod = self.prismatic(f"{name}_rod", f"{name}_base", unit, reference=length, coordinate=name,
                             limits=stroke, mass=rod_mass, com=end - 0.5 * rod_length * unit,
                             inertia=rod_mass * rod_length**2 / 12)
        self.point(f"{name}_eye", rod, end, report=False)
        self.pin(f"{name}_eye", eye)
        self.sketch.append(SketchLine(name, (base, eye), "cylinder"))
        self.cylinders[name] = Cylinder(name, base, eye, (float(stroke[0]), float(stroke[1])), count)
        return name

    # -------------------------------------------------------------------------------------------- closures
    def pin(self, a: str, b: str) -> None:
        """Close a loop with a revolute pair: points ``a`` and ``b`` (on different bodies) coincide."""
        self._point(a), self._point(b)
        self.closures.append(Pin(f"{a}={b}", a=a, b=b))

    def slider(self, point: str, line: str, *, lock_angle: bool = False) -> None:
        """Point ``point`` slides on the line through point ``line`` along that point's x axis (give ``line`` a
        direction); with ``lock_angle`` the two bodies also keep their relative angle (a prismatic pair)."""
        self._point(point), self._point(line)
        offset = self._frame_angle(point) - self._frame_angle(line) if lock_angle else 0.0
        self.closures.append(Slider(f"{point} on {line}", point=point, line=line, lock_angle=lock_angle,
                                    angle_offset=offset))

    def _frame_angle(self, point: str) -> float:
        frame = self.model.frames[self.model.getFrameId(point)]
        body = self.bodies[self.points[point].body]
        rotation = frame.placement.rotation
        return body.angle + math.atan2(rotation[1, 0], rotation[0, 0])

    def gear(self, driver: str, driven: str, ratio: float, offset: float = 0.0) -> None:
        """Couple two bodies' joint coordinates: q_driven = ratio·q_driver + offset (a gear pair or a belt)."""
        from .closures import Gear

        for body in (driver, driven):
            self._body(body)
        self.closures.append(Gear(f"gear {driven}/{driver}", a=driver, b=driven, ratio=ratio, offset=offset))

    def on_curve(self, point: str, f: Callable[[float], float], df: Callable[[float], float],
                 d2f: Callable[[float], float], label: str = "y = f(x)", spline: object | None = None) -> None:
        """Point ``point`` stays on the world curve y = f(x) (with derivatives df, d2f; ``spline``: the same curve as
        a ``scipy.interpolate.PPoly``, if it is one)."""
        self._point(point)
        self.closures.append(OnCurve(f"{point} on curve", point=point, f=f, df=df, d2f=d2f, label=label,
                                     spline=spline))

    def line(self, name: str, *points: str, kind: str = "link") -> None:
        """Draw the body ``name`` as a polyline through ``points``."""
        for p in points:
            self._point(p)
        self.sketch.append(SketchLine(name, tuple(points), kind))

    def transmission_angle(self, name: str, a: str, b: str, c: str, d: str, minimum_deg: float | None = None) -> None:
        """Report the acute angle between lines ab (the driving coupler or cylinder) and cd (the driven lever)."""
        for p in (a, b, c, d):
            self._point(p)
        minimum = math.radians(minimum_deg) if minimum_deg is not None else None
        self.measures.append(Measure(name, "transmission_angle", (a, b, c, d), minimum))

    def lever_arm(self, name: str, base: str, eye: str, pivot: str) -> None:
        """Report the arm of the force along base–eye about ``pivot``."""
        for p in (base, eye, pivot):
            self._point(p)
        self.measures.append(Measure(name, "lever_arm", (base, eye, pivot)))

    def reference_configuration(self) -> np.ndarray:
        """The joint coordinates of the drawing."""
        return np.array(self.reference, dtype=float)

    # ---------------------------------------------------------------------------------------------- build
    def build(self, *, actuated: Sequence[str], description: str = "", parameters: dict[str, Parameter] | None = None,
              rebuild: Callable[[dict[str, float]], Mechanism] | None = None, notes: Sequence[str] = (),
              tool: str | None = None, check: bool = True, input_rates: dict[str, float] | None = None,
              branches: dict[str, np.ndarray] | None = None) -> Mechanism:
        """The :class:`Mechanism`; checks that the drawing satisfies every closure (to 1e-9 m)."""
        mech = Mechanism(
            name=self.name, model=self.model, parameters=dict(parameters or {}), description=description,
            closures=list(self.closures), actuated=list(actuated), tool_frame=tool or GROUND, rebuild=rebuild,
            reference_q=np.array(self.reference, dtype=float),
            points=[name for name, p in self.points.items() if p.report], sketch=list(self.sketch),
            notes=list(notes), measures=list(self.measures), input_rates=dict(input_rates or {}),
            cylinders=dict(self.cylinders), branches=dict(branches or {}),
        )
        if check and mech.closures:
            residual, _ = mech.closure_system().evaluate(mech.reference_q)
            if np.abs(residual).max() > 1e-9:
                labels = mech.closure_system().row_labels()
                worst = int(np.argmax(np.abs(residual)))
                raise InputError(f"{self.name}: the drawing does not close: residual {residual[worst]:.3g} at "
                                 f"{labels[worst]}")
        return mech

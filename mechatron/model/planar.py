"""Planar linkages as Pinocchio trees with closures, built from the layout of a mechanism file or drawn in Python.

The layout (:mod:`mechatron.model.shapes`) gives every joint's placement in its parent's frame, every point's frame
in its body's, and the bodies' masses in body coordinates; :class:`PlanarBuilder` adds them to a ``pinocchio.Model``
in order (:meth:`~PlanarBuilder.joint`, :meth:`~PlanarBuilder.frame`) and collects the closures, the drawing's sketch
and the measures. In Python a linkage can also be drawn directly in one assembled position, in world coordinates:
:meth:`~PlanarBuilder.point`, :meth:`~PlanarBuilder.revolute`, :meth:`~PlanarBuilder.prismatic` and
:meth:`~PlanarBuilder.add_cylinder` turn world positions of the drawing into the same layout records.

Conventions: the mechanism moves in the world xy plane, gravity is along −y; a revolute joint's coordinate is the
angle of its body relative to the parent body (the absolute angle for a body pinned to the ground); a prismatic
joint's coordinate is the displacement along its direction; a cylinder's coordinate is its pin-to-pin length.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import pinocchio as pin

from ..errors import InputError
from .closures import Closure, Gear, OnCurve, Pin, Slider
from .mechanism import Cylinder, Measure, Mechanism, Parameter, SketchLine
from .shapes import BodyFrame, FrameLayout, JointLayout, in_joint_frame

GROUND = "ground"
Point2 = Sequence[float] | np.ndarray  # (x, y) in metres


def rz(angle: float) -> np.ndarray:
    """The rotation by ``angle`` (rad) about z, 3 × 3."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class PlanarBuilder:
    """Collects the joints, point frames and closures of a planar linkage."""

    def __init__(self, name: str, gravity: float = 9.81) -> None:
        self.name = name
        self.model = pin.Model()
        self.model.name = name
        self.model.gravity = pin.Motion(np.array([0.0, -gravity, 0.0]), np.zeros(3))
        ground = self.model.addFrame(pin.Frame(GROUND, 0, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
        self.bodies: dict[str, tuple[int, int]] = {GROUND: (0, ground)}  # joint, body frame
        self.offsets: dict[str, float] = {GROUND: 0.0}  # angle of a body's frame in its joint's frame
        self.points: dict[str, bool] = {}  # frame name: reported
        self.drawn: dict[str, BodyFrame] = {GROUND: BodyFrame((0.0, 0.0), 0.0)}  # body frames in a world drawing
        self.world: dict[str, tuple[str, np.ndarray]] = {}  # point: (body, world position in the drawing)
        self.angles: dict[str, float] = {}  # point: world angle of its frame in the drawing
        self.reference: list[float] = []
        self.closures: list[Closure] = []
        self.sketch: list[SketchLine] = []
        self.measures: list[Measure] = []
        self.cylinders: dict[str, Cylinder] = {}

    def _body(self, name: str) -> tuple[int, int]:
        if name not in self.bodies:
            raise InputError(f"{self.name}: unknown body {name!r}")
        return self.bodies[name]

    def _point(self, name: str) -> None:
        if name not in self.points:
            raise InputError(f"{self.name}: unknown point {name!r}")

    def joint(self, j: JointLayout) -> None:
        """The joint of body ``j.body`` on its parent: placement ``j.xy`` (m), turned by ``j.angle`` (rad), in the
        parent's frame, revolute about z or prismatic along x; the body's mass at ``j.com`` with I_zz ``j.inertia``
        (a planar body: I_xx = I_yy = I_zz/2, a thin plate's, so that the tensor is physical)."""
        if j.body in self.bodies:
            raise InputError(f"{self.name}: body {j.body!r} defined twice")
        parent_joint, _ = self._body(j.parent)
        model = pin.JointModelRZ() if j.kind == "revolute" else pin.JointModelPX()
        placement = self._placement(j.parent, j.xy, j.angle)
        lower, upper = j.limits
        joint_id = self.model.addJoint(parent_joint, model, placement, j.coordinate, np.array([np.inf]),
                                       np.array([np.inf]), np.array([float(lower)]), np.array([float(upper)]))
        offset = -float(j.angle)
        frame = self.model.addFrame(pin.Frame(j.body, joint_id, self.model.nframes - 1, pin.SE3(rz(offset),
                                                                                               np.zeros(3)),
                                              pin.FrameType.BODY))
        self.bodies[j.body] = (joint_id, frame)
        self.offsets[j.body] = offset
        mass, inertia = float(j.mass), float(j.inertia)
        if mass > 0 or inertia > 0:
            centre = self._placement(j.body, j.com, 0.0).translation
            self.model.appendBodyToJoint(joint_id, pin.Inertia(mass, centre, np.diag([inertia / 2, inertia / 2,
                                                                                      inertia])), pin.SE3.Identity())
        self.reference.append(float(j.reference))

    def frame(self, f: FrameLayout) -> None:
        """A named point (an operational frame) of body ``f.body`` at ``f.xy`` (m), turned by ``f.angle`` (rad)."""
        if f.name in self.points or self.model.existFrame(f.name):
            raise InputError(f"{self.name}: point {f.name!r} defined twice")
        joint_id, body_frame = self._body(f.body)
        placement = self._placement(f.body, f.xy, f.angle)
        self.model.addFrame(pin.Frame(f.name, joint_id, body_frame, placement, pin.FrameType.OP_FRAME))
        self.points[f.name] = f.report

    def _placement(self, body: str, xy, angle) -> pin.SE3:
        """The placement in ``body``'s joint frame of (x, y, angle) given in its body frame."""
        x, y, turn = in_joint_frame((float(xy[0]), float(xy[1])), float(angle), self.offsets[body])
        return pin.SE3(rz(turn), np.array([x, y, 0.0]))

    # ---------------------------------------------------------------------------------- drawing in world axes
    def point(self, name: str, body: str, at: Point2, direction: Point2 | None = None, *, report: bool = True) -> str:
        """A named point of ``body`` at the world position ``at`` (m) of the drawing, its x axis along ``direction``
        (world) if given, else along the body's. Points with ``report`` false are helpers (guides, slider frames)
        left out of sweep tables."""
        frame = self.drawn[self._known_body(body)]
        xy = np.asarray(at, dtype=float)
        angle = 0.0 if direction is None else math.atan2(direction[1], direction[0]) - frame.angle
        self.frame(FrameLayout(name, body, frame.local(tuple(xy)), angle, report))
        self.world[name] = (body, xy)
        self.angles[name] = float(frame.angle + angle)
        return name

    def where(self, point: str) -> np.ndarray:
        """World position (m) of a point in the drawing."""
        self._point(point)
        return self.world[point][1].copy()

    def _drawn_point(self, name: str) -> tuple[str, np.ndarray]:
        """(body, world position) of a point drawn with :meth:`point`."""
        if name not in self.world:
            raise InputError(f"{self.name}: unknown point {name!r}")
        return self.world[name]

    def _known_body(self, name: str) -> str:
        self._body(name)
        return name

    def revolute(self, body: str, at: str, *, toward: str | Point2 | None = None, angle: float | None = None,
                 coordinate: str | None = None, limits: tuple[float, float] = (-np.inf, np.inf), mass: float = 0.0,
                 com: Point2 | None = None, inertia: float = 0.0) -> str:
        """``body`` turning about the point ``at`` of its parent; its x axis toward the point or world position
        ``toward`` in the drawing, or at the world ``angle`` (rad), or along the parent's; mass (kg), centre (world,
        m; default the pin) and I_zz about it (kg·m²). The coordinate (default ``{body}_angle``) is the angle from
        the parent's x axis."""
        if toward is not None and angle is not None:
            raise InputError(f"{self.name}: body {body}: give toward or angle, not both")
        parent, pivot = self._drawn_point(at)
        if angle is None:
            target = None if toward is None else self.where(toward) if isinstance(toward, str) else toward
            angle = self.drawn[parent].angle if target is None else math.atan2(target[1] - pivot[1],
                                                                               target[0] - pivot[0])
        return self._drawn_joint(body, parent, "revolute", coordinate or f"{body}_angle", pivot,
                                 BodyFrame(tuple(pivot), angle), angle - self.drawn[parent].angle, limits, 0.0,
                                 mass, com, inertia)

    def prismatic(self, body: str, at: str, direction: Point2, *, reference: float = 0.0,
                  coordinate: str | None = None, limits: tuple[float, float] = (-np.inf, np.inf),
                  mass: float = 0.0, com: Point2 | None = None, inertia: float = 0.0) -> str:
        """``body`` sliding on the parent of point ``at`` along the world ``direction`` of the drawing; its
        coordinate is the travel of the body frame from ``at`` (m), ``reference`` in the drawing; its x axis is along
        the guide."""
        parent, pivot = self._drawn_point(at)
        unit = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
        frame = self.drawn[parent]
        local = frame.direction((float(unit[0]), float(unit[1])))
        guide = math.atan2(local[1], local[0])
        return self._drawn_joint(body, parent, "prismatic", coordinate or f"{body}_position", pivot,
                                 BodyFrame(tuple(pivot + reference * unit), frame.angle + guide, tuple(unit)),
                                 reference, limits, guide, mass, com, inertia)

    def _drawn_joint(self, body, parent, kind, coordinate, pivot, frame, reference, limits, angle, mass, com, inertia
                     ) -> str:
        if mass < 0 or inertia < 0:
            raise InputError(f"{self.name}: body {body}: mass and inertia must be >= 0")
        centre = frame.local(pivot if com is None else com)
        self.joint(JointLayout(body, parent, kind, coordinate, self.drawn[parent].local(pivot), reference, limits,
                               angle, mass, centre, inertia))
        self.drawn[body] = frame
        return body

    def cylinder(self, name: str, base: str, eye: str, *, stroke: tuple[float, float], count: int = 1,
                     barrel_mass: float = 0.0, rod_mass: float = 0.0) -> str:
        """A hydraulic cylinder from point ``base`` to point ``eye`` of the drawing (on different bodies): a barrel
        turning about ``base`` (body ``{name}_barrel``), a rod sliding in it (body ``{name}_rod``, coordinate
        ``name`` = the pin-to-pin length within ``stroke``), the pin of its eye to ``eye``; barrel and rod masses
        (kg, of one cylinder) at their middles as slender rods; ``count`` cylinders side by side, moving as one: the
        model's barrel and rod carry ``count`` times the masses."""
        start, end = self.where(base), self.where(eye)
        barrel_mass, rod_mass = count * barrel_mass, count * rod_mass
        length = float(np.linalg.norm(end - start))
        if not stroke[0] - 1e-9 <= length <= stroke[1] + 1e-9:
            raise InputError(f"{self.name}: cylinder {name} is {length:.6g} m long in the drawing, outside its "
                             f"stroke [{stroke[0]:.6g}, {stroke[1]:.6g}] m")
        unit = (end - start) / length
        barrel = self.revolute(f"{name}_barrel", base, toward=eye, coordinate=f"{name}_angle", mass=barrel_mass,
                               com=start + 0.5 * stroke[0] * unit, inertia=barrel_mass * stroke[0] ** 2 / 12)
        self.point(f"{name}_base", barrel, start, report=False)
        rod = self.prismatic(f"{name}_rod", f"{name}_base", unit, reference=length, coordinate=name, limits=stroke,
                             mass=rod_mass, com=end - 0.5 * (stroke[1] - stroke[0]) * unit,
                             inertia=rod_mass * (stroke[1] - stroke[0]) ** 2 / 12)
        self.point(f"{name}_eye", rod, end, report=False)
        self.cylinder_closure(name, base, eye, stroke, count)
        return name

    def transmission_angle(self, name: str, a: str, b: str, c: str, d: str, minimum_deg: float | None = None) -> None:
        """Report the acute angle between lines ab (the driving coupler or cylinder) and cd (the driven lever)."""
        for p in (a, b, c, d):
            self._point(p)
        minimum = math.radians(minimum_deg) if minimum_deg is not None else None
        self.measures.append(Measure(name, "transmission_angle", (a, b, c, d), minimum))

    # -------------------------------------------------------------------------------------------- closures
    def cylinder_closure(self, name: str, base: str, eye: str, stroke: tuple[float, float], count: int = 1) -> None:
        """A hydraulic cylinder (its barrel and rod joints added already): the pin closure of its rod eye
        ``{name}_eye`` to the frame ``eye``, its sketch line and its record."""
        self.pin(f"{name}_eye", eye)
        self.sketch.append(SketchLine(name, (base, eye), "cylinder"))
        self.cylinders[name] = Cylinder(name, base, eye, (float(stroke[0]), float(stroke[1])), count)

    def pin(self, a: str, b: str) -> None:
        """Close a loop with a revolute pair: points ``a`` and ``b`` (on different bodies) coincide."""
        self._point(a)
        self._point(b)
        self.closures.append(Pin(f"{a}={b}", a=a, b=b))

    def slider(self, point: str, line: str, *, lock_angle: bool = False, angle_offset: float | None = None) -> None:
        """Point ``point`` slides on the line through point ``line`` along that point's x axis (give ``line`` a
        direction); with ``lock_angle`` the two frames also keep their relative angle ``angle_offset`` (rad; default
        the drawing's, for points drawn with :meth:`point`): a prismatic pair."""
        self._point(point)
        self._point(line)
        offset = 0.0
        if lock_angle:
            offset = self.angles[point] - self.angles[line] if angle_offset is None else angle_offset
        self.closures.append(Slider(f"{point} on {line}", point=point, line=line, lock_angle=lock_angle,
                                    angle_offset=offset))

    def gear(self, driver: str, driven: str, ratio: float, offset: float = 0.0) -> None:
        """Couple two bodies' joint coordinates: q_driven = ratio·q_driver + offset (a gear pair or a belt)."""
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

    # ---------------------------------------------------------------------------------------------- build
    def build(self, *, actuated: Sequence[str], reference: Sequence[float] | None = None, description: str = "",
              parameters: dict[str, Parameter] | None = None,
              rebuild: Callable[[dict[str, float]], Mechanism] | None = None, notes: Sequence[str] = (),
              tool: str | None = None, input_rates: dict[str, float] | None = None, check: bool = True) -> Mechanism:
        """The :class:`Mechanism`, its reference configuration ``reference`` (default the drawing's coordinates);
        with ``check``, the reference must satisfy every closure (to 1e-9 m)."""
        reference_q = np.array(self.reference if reference is None else reference, dtype=float)
        mech = Mechanism(
            name=self.name, model=self.model, parameters=dict(parameters or {}), description=description,
            closures=list(self.closures), actuated=list(actuated), tool_frame=tool or GROUND, rebuild=rebuild,
            reference_q=reference_q,
            points=[name for name, report in self.points.items() if report], sketch=list(self.sketch),
            notes=list(notes), measures=list(self.measures), input_rates=dict(input_rates or {}),
            cylinders=dict(self.cylinders),
        )
        if check and mech.closures:
            residual, _ = mech.closure_system().evaluate(reference_q)
            if np.abs(residual).max() > 1e-9:
                worst = int(np.argmax(np.abs(residual)))
                raise InputError(f"{self.name}: the drawing does not close: residual {residual[worst]:.3g} at "
                                 f"{mech.closure_system().row_labels()[worst]}")
        return mech

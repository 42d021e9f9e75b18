r"""Closed-loop planar mechanisms described as data: a :class:`LinkageSpec` (what a mechanism file holds) and
:func:`build_linkage`, which turns it into a :class:`~mechatron.model.Mechanism`.

A linkage is described the way it is drawn: the world coordinates (x, y, m) of its named points (pins) in one
assembled position, the bodies and the points each carries (a point carried by two bodies is a pin between them),
the joints of a spanning tree (revolute at a pin, prismatic along a direction, hydraulic cylinders between two pins)
and the closures of the loops (pins, sliders on a line, a point on a curve given as a table, gears). Named lengths
(the distance between two points of one body) are the geometric parameters; a length given a value is
authoritative, and the drawing is corrected to it.

A drawing read off paper rarely closes exactly. :func:`close_drawing` finds the consistent position nearest to the
drawing: the points P solve Φ(P) = 0 by minimum-norm Gauss–Newton steps from the drawn positions
(P ← P − J⁺ Φ), where Φ holds every body's rigidity (its distances as drawn, or as declared), the direction and offset
of every prismatic guide, every slider and curve closure, and the drawn values of the actuated inputs (so that an
input keeps its drawn angle, stroke or length). Each point's move is reported; beyond the file's tolerance the
loader refuses, naming the constraint that does not close.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .dh import Drive
from .mechanism import Measure, Mechanism, Parameter
from .planar import GROUND, PlanarBuilder

Vector = NDArray[np.float64]


# ------------------------------------------------------------------------------------------------ the data
@dataclass(frozen=True)
class PointSpec:
    """A named point. ``at``: its world position (m) in the drawing; or ``between`` two points at ``fraction`` of
    the way (a derived point, e.g. the middle of a rod, that follows them when the drawing is corrected).
    ``direction``: the x axis of the point's frame in the drawing (a slider's line); ``report``: listed in sweeps."""

    name: str
    at: tuple[float, ...] | None = None  # (x, y), or (x, y, z) in a spatial mechanism
    between: tuple[str, str] | None = None
    fraction: float = 0.5
    direction: tuple[float, float] | None = None
    report: bool = True


@dataclass(frozen=True)
class BodySpec:
    """A body and the points it carries (the first is its reference for drawing and orientation). Mass (kg), centre
    of mass (a point name or a world position in the drawing, m) and I_zz about it (kg·m²); ``shape = "bar"`` puts
    the centre in the middle of the first two points and I_zz = m L²/12 unless given."""

    name: str
    points: tuple[str, ...]
    mass: float = 0.0
    com: str | tuple[float, ...] | None = None
    inertia: float | tuple[float, ...] | None = None  # I_zz; spatial: (Ixx, Iyy, Izz[, Ixy, Ixz, Iyz])
    shape: str | None = None
    draw: tuple[str, ...] | None = None
    draw_kind: str = "link"


@dataclass(frozen=True)
class JointSpec:
    """A joint of the spanning tree. ``kind`` "revolute" (body turning about the pin ``at``, its x axis toward the
    point ``toward`` or at world angle ``angle`` in the drawing), "prismatic" (body sliding on its parent along the
    world ``direction`` of the drawing from the parent's point ``at``) or "cylinder" (``name`` from the point ``base``
    to the point ``eye``, length within ``stroke`` = (L_min, L_max), ``count`` side by side). ``limits`` in rad or m."""

    kind: str
    body: str = ""
    at: str = ""
    parent: str | None = None
    coordinate: str | None = None
    toward: str | None = None
    angle: float | None = None
    direction: tuple[float, float] | None = None
    limits: tuple[float, float] = (-math.inf, math.inf)
    name: str = ""
    base: str = ""
    eye: str = ""
    stroke: tuple[float, float] = (0.0, 0.0)
    count: int = 1
    barrel_mass: float = 0.0
    rod_mass: float = 0.0
    axis: tuple[float, float, float] | None = None  # spatial revolute: the world axis in the drawing
    axes: tuple[tuple[float, float, float], ...] | None = None  # spatial universal: parent's axis, cross's axis


@dataclass(frozen=True)
class ClosureSpec:
    """A loop closure. ``kind`` "pin" (``point`` carried by the two ``bodies``), "slider" (``point`` of ``body`` on
    the line through the point ``line`` of ``line_body`` along that point's direction; ``lock_angle`` for a prismatic
    pair), "curve" (``point`` of ``body`` on the world curve y(x) given by the table ``x``, ``y``, m, interpolated
    by a cubic spline) or "gear" (q_driven = ``ratio``·q_driver + ``offset``, the bodies' joint coordinates)."""

    kind: str
    point: str = ""
    bodies: tuple[str, ...] = ()
    body: str | None = None
    line: str = ""
    line_body: str | None = None
    lock_angle: bool = False
    x: tuple[float, ...] = ()
    y: tuple[float, ...] = ()
    label: str = ""
    driver: str = ""
    driven: str = ""
    ratio: float = 1.0
    offset: float | None = None


@dataclass(frozen=True)
class MeasureSpec:
    """A quantity reported along a motion: ``kind`` "transmission_angle" (points a, b, c, d; rad), "lever_arm"
    (base, eye, pivot; m) or "distance" (a, b; m), with an optional required ``minimum`` (same unit)."""

    kind: str
    name: str
    points: tuple[str, ...]
    minimum: float | None = None


@dataclass(frozen=True)
class LengthSpec:
    """A named length, the distance between two points of one body (m): a geometric parameter. With a ``value`` it
    is authoritative (the drawing is corrected to it); without, it is measured from the drawing."""

    name: str
    points: tuple[str, str]
    value: float | None = None


@dataclass(frozen=True)
class DriveSpec:
    """Where the motor and gearbox of an actuated coordinate sit (a ``[[drives]]`` table): on ``body``, at its point
    ``at``. The drive sizing puts the chosen drive's mass there; without a table it sits on the coordinate's parent
    body at the joint."""

    coordinate: str
    at: str
    body: str | None = None  # default: the first body carrying ``at`` (the ground first)


@dataclass(frozen=True)
class LinkageSpec:
    """Everything a mechanism file says (SI units). See docs/mechanism_file.md for the file format."""

    name: str
    points: tuple[PointSpec, ...]
    bodies: tuple[BodySpec, ...]
    joints: tuple[JointSpec, ...]
    actuated: tuple[str, ...]
    closures: tuple[ClosureSpec, ...] = ()
    measures: tuple[MeasureSpec, ...] = ()
    lengths: tuple[LengthSpec, ...] = ()
    branches: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    description: str = ""
    source: str = ""
    gravity: float = 9.81
    tool: str | None = None
    input_rates: Mapping[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    tolerance: float | None = None
    file: str | None = None
    #: False for a spatial mechanism (3D points, joint axes, point closures; :mod:`mechatron.model.spatial`).
    planar: bool = True
    #: Values (m, rad) at which to hold actuated inputs while closing the drawing instead of their drawn ones: a
    #: rebuild keeps the nominal drawing's inputs when it moves points (not part of a file).
    held_inputs: Mapping[str, float] = field(default_factory=dict)
    #: Where the motors of actuated coordinates sit (``[[drives]]``).
    drives: tuple[DriveSpec, ...] = ()

    # ----------------------------------------------------------------------------------------- look-ups
    def point(self, name: str) -> PointSpec:
        for p in self.points:
            if p.name == name:
                return p
        raise self.error(f"unknown point {name!r}", "points")

    def body(self, name: str) -> BodySpec:
        for b in self.bodies:
            if b.name == name:
                return b
        raise self.error(f"unknown body {name!r}", "bodies")

    def owners(self, point: str) -> list[str]:
        """The bodies carrying ``point``, ground first, then in the file's order."""
        return [b.name for b in self.bodies if point in b.points]

    def error(self, message: str, field: str | None = None) -> InputError:
        return InputError(message, file=self.file, field=field)

    def drawing(self) -> dict[str, Vector]:
        """The drawn world positions of the points given by coordinates (m)."""
        return {p.name: np.array(p.at, dtype=float) for p in self.points if p.at is not None}

    def with_positions(self, positions: Mapping[str, Vector]) -> LinkageSpec:
        """The same linkage drawn at other positions of its points (m)."""
        points = tuple(replace(p, at=tuple(float(v) for v in positions[p.name])) if p.name in positions else p
                       for p in self.points)
        return replace(self, points=points)


# ------------------------------------------------------------------------------------------------ checks
def check(spec: LinkageSpec) -> None:
    """Structural checks of a spec, each an :class:`InputError` naming the file and the field."""
    names = [p.name for p in spec.points]
    _no_duplicates(spec, names, "points", "point")
    _no_duplicates(spec, [b.name for b in spec.bodies], "bodies", "body")
    known = set(names)
    size = 2 if spec.planar else 3
    for p in spec.points:
        if p.at is not None and len(p.at) != size:
            raise spec.error(f"point {p.name}: give {size} coordinates in a {'planar' if spec.planar else 'spatial'} "
                             f"mechanism, got {len(p.at)}", f"points.{p.name}")
        if p.between is not None:
            for other in p.between:
                if other not in known or other == p.name:
                    raise spec.error(f"point {p.name} lies between unknown point {other!r}", f"points.{p.name}")
                if spec.point(other).between is not None:
                    raise spec.error(f"point {p.name}: a derived point lies between drawn points, not {other}",
                                     f"points.{p.name}")
    bodies = {b.name for b in spec.bodies}
    if GROUND not in bodies:
        raise spec.error("give the frame's points as a body named ground", "bodies")
    for i, b in enumerate(spec.bodies, start=1):
        where = f"bodies[{i}]"
        if not b.points:
            raise spec.error(f"body {b.name} carries no point", f"{where}.points")
        for p in b.points:
            if p not in known:
                raise spec.error(f"body {b.name} carries unknown point {p!r}", f"{where}.points")
        if len(set(b.points)) != len(b.points):
            raise spec.error(f"body {b.name} lists a point twice", f"{where}.points")
        if b.mass < 0:
            raise spec.error(f"body {b.name}: mass must be >= 0 kg, got {b.mass:g}", f"{where}.mass")
        if b.inertia is not None and np.any(np.asarray(b.inertia, dtype=float) < 0):
            raise spec.error(f"body {b.name}: inertia must be >= 0 kg·m², got {b.inertia}", f"{where}.inertia")
        if b.inertia is not None and np.any(np.asarray(b.inertia, dtype=float) != 0) and b.mass == 0:
            raise spec.error(f"body {b.name}: an inertia of {b.inertia} kg·m² without mass is not a body's",
                             f"{where}.inertia")
        if isinstance(b.com, str) and b.com not in b.points:
            raise spec.error(f"body {b.name}: its centre of mass {b.com!r} is not one of its points", f"{where}.com")
        if b.shape not in (None, "bar", "plate"):
            raise spec.error(f"body {b.name}: unknown shape {b.shape!r}; expected bar or plate", f"{where}.shape")
        if b.shape == "bar" and len(b.points) < 2:
            raise spec.error(f"body {b.name}: a bar needs two points", f"{where}.shape")
        if b.shape == "plate" and (len(b.points) < 3 or not spec.planar):
            raise spec.error(f"body {b.name}: a plate is the polygon of three or more points of a planar mechanism",
                             f"{where}.shape")
    coordinates: dict[str, str] = {}
    for i, j in enumerate(spec.joints, start=1):
        where = f"joints[{i}]"
        coordinate = joint_coordinate(j)
        if coordinate in coordinates:
            raise spec.error(f"coordinate {coordinate!r} is defined twice (also by {coordinates[coordinate]})",
                             f"{where}.{'name' if j.kind == 'cylinder' else 'coordinate'}")
        coordinates[coordinate] = where
        if j.kind == "cylinder":
            for role in ("base", "eye"):
                if getattr(j, role) not in known:
                    raise spec.error(f"cylinder {j.name}: unknown {role} point {getattr(j, role)!r}", f"{where}.{role}")
            if not 0 < j.stroke[0] < j.stroke[1]:
                raise spec.error(f"cylinder {j.name}: the stroke needs 0 < L_min < L_max, got "
                                 f"[{j.stroke[0]:g}, {j.stroke[1]:g}] m", f"{where}.stroke")
            if j.count < 1:
                raise spec.error(f"cylinder {j.name}: count must be >= 1", f"{where}.count")
            continue
        if j.body not in bodies or j.body == GROUND:
            raise spec.error(f"joint of unknown body {j.body!r}", f"{where}.body")
        if j.at not in known:
            raise spec.error(f"joint of {j.body} at unknown point {j.at!r}", f"{where}.at")
        if j.parent is not None and j.parent not in bodies:
            raise spec.error(f"joint of {j.body}: unknown parent body {j.parent!r}", f"{where}.parent")
        if j.toward is not None and j.toward not in known:
            raise spec.error(f"joint of {j.body}: unknown point {j.toward!r}", f"{where}.toward")
        if not j.limits[0] < j.limits[1]:
            raise spec.error(f"joint of {j.body}: lower limit {j.limits[0]:g} must be below the upper "
                             f"{j.limits[1]:g}", f"{where}.lower")
    for i, c in enumerate(spec.closures, start=1):
        where = f"closures[{i}]"
        for role in ("bodies", "body", "line_body", "driver", "driven"):
            named = getattr(c, role)
            for body in (named,) if isinstance(named, str) else named or ():
                if body and body not in bodies:
                    raise spec.error(f"{c.kind} of {c.point or c.driven}: unknown body {body!r}", f"{where}.{role}")
        if c.kind in ("pin", "slider", "curve") and c.point not in known:
            raise spec.error(f"{c.kind} of unknown point {c.point!r}", f"{where}.point")
        if c.kind == "pin":
            if len(c.bodies) == 2 and c.bodies[0] == c.bodies[1]:
                raise spec.error(f"pin {c.point} joins body {c.bodies[0]} to itself", f"{where}.bodies")
            for body in c.bodies:
                if c.point not in spec.body(body).points:
                    raise spec.error(f"pin {c.point}: body {body} does not carry {c.point}", f"{where}.bodies")
        if c.kind == "curve":
            x = np.asarray(c.x, dtype=float)
            if len(x) < 4 or len(c.y) != len(x):
                raise spec.error(f"curve of {c.point}: give x and y with the same number (at least 4) of values",
                                 f"{where}.x")
            if not np.all(np.diff(x) > 0):
                k = int(np.flatnonzero(np.diff(x) <= 0)[0])
                raise spec.error(f"curve of {c.point}: x must increase (x[{k + 2}] = {x[k + 1]:g} after "
                                 f"{x[k]:g})", f"{where}.x")
    _check_drives(spec)
    _no_duplicates(spec, [m.name for m in spec.measures], "measures", "measure")
    for i, m in enumerate(spec.measures, start=1):
        for p in m.points:
            if p not in known:
                raise spec.error(f"measure {m.name}: unknown point {p!r}", f"measures[{i}].points")
    for length in spec.lengths:
        a, b = length.points
        if not any(a in body.points and b in body.points for body in spec.bodies):
            raise spec.error(f"length {length.name}: {a} and {b} are not two points of one body",
                             f"lengths.{length.name}")
        if length.value is not None and not length.value > 0:
            raise spec.error(f"length {length.name} must be > 0 m, got {length.value:g}", f"lengths.{length.name}")


def _check_drives(spec: LinkageSpec) -> None:
    """Each ``[[drives]]`` table places the motor of one actuated coordinate (not a cylinder) on a known body, at
    one of its points."""
    cylinders = {j.name for j in spec.joints if j.kind == "cylinder"}
    seen: set[str] = set()
    for i, d in enumerate(spec.drives, start=1):
        where = f"drives[{i}]"
        if d.coordinate not in spec.actuated or d.coordinate in cylinders:
            motors = [c for c in spec.actuated if c not in cylinders]
            raise spec.error(f"{d.coordinate!r} is not an actuated coordinate driven by a motor (those are: "
                             f"{', '.join(motors) or 'none'})", f"{where}.coordinate")
        if d.coordinate in seen:
            raise spec.error(f"the drive of {d.coordinate} is placed twice", f"{where}.coordinate")
        seen.add(d.coordinate)
        if d.body is not None and d.body not in {b.name for b in spec.bodies}:
            raise spec.error(f"the drive of {d.coordinate}: unknown body {d.body!r} (known: "
                             f"{', '.join(b.name for b in spec.bodies)})", f"{where}.body")
        if d.at not in {p.name for p in spec.points}:
            raise spec.error(f"the drive of {d.coordinate}: unknown point {d.at!r}", f"{where}.at")
        if d.body is not None and d.at not in spec.body(d.body).points:
            raise spec.error(f"the drive of {d.coordinate}: {d.at} is not a point of body {d.body}", f"{where}.at")


def drive_placements(spec: LinkageSpec) -> dict[str, Drive]:
    """The :class:`~mechatron.model.dh.Drive` of every coordinate with a ``[[drives]]`` table: its placement is the
    frame of the point ``at`` on its body (:func:`frame_names`)."""
    frames = frame_names(spec)
    return {d.coordinate: Drive(placement=frames[(d.at, d.body or spec.owners(d.at)[0])]) for d in spec.drives}


def _no_duplicates(spec: LinkageSpec, names: Sequence[str], where: str, what: str) -> None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise spec.error(f"{what} {name!r} is defined twice", where)
        seen.add(name)


# ------------------------------------------------------------------------------------ closing the drawing
@dataclass(frozen=True)
class ClosedDrawing:
    """The consistent positions (m) of the drawn points, how far each moved (m) and the largest residual of the
    drawing as given, with the constraint it belongs to."""

    positions: dict[str, Vector]
    moves: dict[str, float]
    residual: float
    worst: str


def _orientation(spec: LinkageSpec, body: str) -> Callable[[Mapping[str, Vector]], float] | None:
    """The angle (rad) of a body's first two drawn points, as a function of the positions; ``None`` for the ground
    (fixed) and for a body with one drawn point (it carries no direction)."""
    if body == GROUND:
        return None
    drawn = [p for p in spec.body(body).points if spec.point(p).at is not None]
    if len(drawn) < 2:
        return None
    a, b = drawn[0], drawn[1]
    return lambda P: math.atan2(P[b][1] - P[a][1], P[b][0] - P[a][0])


def _angle_of(body_angle, P) -> float:
    return 0.0 if body_angle is None else body_angle(P)


def constraints(spec: LinkageSpec) -> list[tuple[str, Callable[[Mapping[str, Vector]], float]]]:
    """Φ(P) of :func:`close_drawing`, one (label, function) per equation (m or rad)."""
    drawn = spec.drawing()
    declared = {frozenset(length.points): length for length in spec.lengths if length.value is not None}
    out: list[tuple[str, Callable]] = []

    def distance(a: str, b: str, value: float) -> Callable:
        return lambda P: float(np.linalg.norm(P[b] - P[a]) - value)

    for body in spec.bodies:
        points = [p for p in body.points if p in drawn]
        for k, p in enumerate(points):
            if body.name == GROUND:
                continue
            # Henneberg: every point after the first is held by (up to) two distances to earlier points, declared
            # lengths first
            partners = [q for q in points[:k] if frozenset((p, q)) in declared]
            partners += [q for q in points[:k] if q not in partners][: max(0, min(2, k) - len(partners))]
            for q in partners[:2] if k >= 2 else partners[:1]:
                length = declared.get(frozenset((p, q)))
                value = length.value if length is not None else float(np.linalg.norm(drawn[p] - drawn[q]))
                label = f"length {length.name} = |{q}{p}|" if length is not None else f"body {body.name}: |{q}{p}|"
                out.append((label, distance(q, p, value)))
    ground = [p for p in spec.body(GROUND).points if p in drawn]
    for k, p in enumerate(ground):  # the frame does not move: its first point stays, the others stay as drawn unless
        # declared lengths to earlier ground points move them (one: along the line from that point; two: to where
        # both distances meet)
        partners = [q for q in ground[:k] if frozenset((q, p)) in declared][:2]
        if not partners:
            out += [(f"ground point {p}", lambda P, p=p: float(P[p][0] - drawn[p][0])),
                    (f"ground point {p}", lambda P, p=p: float(P[p][1] - drawn[p][1]))]
            continue
        for q in partners:
            length = declared[frozenset((q, p))]
            out.append((f"length {length.name} = |{q}{p}|", distance(q, p, length.value)))
        if len(partners) == 1:
            q = partners[0]
            a = drawn[p] - drawn[q]
            normal = np.array([-a[1], a[0]]) / np.linalg.norm(a)
            out.append((f"ground point {p}", lambda P, p=p, q=q, n=normal: float(n @ (P[p] - P[q]))))
    for j in spec.joints:
        if j.kind == "prismatic":
            out += _prismatic(spec, j, drawn)
    for name in spec.actuated:
        out += _input(spec, name, drawn)
    for c in spec.closures:
        if c.kind == "slider":
            out += _slider(spec, c, drawn)
        elif c.kind == "curve":
            f = curve_functions(c)[0]
            out.append((f"{c.point} on its curve", lambda P, c=c, f=f: float(P[c.point][1] - f(P[c.point][0]))))
    return out


def _relative_angle(spec: LinkageSpec, child: str, parent: str, drawn: Mapping[str, Vector], label: str) -> list:
    """The angle of ``child`` relative to ``parent`` held as drawn (nothing if the child carries no direction)."""
    child_angle, parent_angle = _orientation(spec, child), _orientation(spec, parent)
    if child_angle is None:
        return []
    value = child_angle(drawn) - _angle_of(parent_angle, drawn)
    return [(label, lambda P: math.remainder(child_angle(P) - _angle_of(parent_angle, P) - value, 2 * math.pi))]


def _direction(spec: LinkageSpec, body: str, drawn_direction: Vector, drawn: Mapping[str, Vector]) -> Callable:
    """The world direction (unit) of a line fixed to ``body``, given in the drawing, as a function of positions."""
    angle = _orientation(spec, body)
    base = math.atan2(drawn_direction[1], drawn_direction[0]) - _angle_of(angle, drawn)

    def direction(P: Mapping[str, Vector]) -> Vector:
        a = base + _angle_of(angle, P)
        return np.array([math.cos(a), math.sin(a)])

    return direction


def _prismatic(spec: LinkageSpec, j: JointSpec, drawn: Mapping[str, Vector]) -> list:
    """A body sliding on its parent: its first point keeps its offset from the guide line, its angle the parent's."""
    parent = joint_parent(spec, j)
    first = next(p for p in spec.body(j.body).points if p in drawn)
    direction = _direction(spec, parent, np.asarray(j.direction, dtype=float), drawn)

    def offset(P: Mapping[str, Vector]) -> float:
        d = direction(P)
        return float(np.array([-d[1], d[0]]) @ (P[first] - P[j.at]))

    value = offset(drawn)
    return [(f"prismatic guide of {j.body}", lambda P: offset(P) - value),
            *_relative_angle(spec, j.body, parent, drawn, f"prismatic guide of {j.body} (angle)")]


def input_measure(spec: LinkageSpec, name: str, drawn: Mapping[str, Vector]) -> tuple[Callable, bool] | None:
    """The function of the point positions that gives the actuated coordinate ``name`` (up to a constant): a
    cylinder's length, a revolute input's angle to its parent, a prismatic input's travel; and whether it is an
    angle. ``None`` for a revolute input whose body carries no direction."""
    for j in spec.joints:
        if j.kind == "cylinder" and j.name == name:
            return (lambda P: float(np.linalg.norm(P[j.eye] - P[j.base]))), False
        if j.kind != "cylinder" and joint_coordinate(j) == name:
            parent = joint_parent(spec, j)
            parent_angle = _orientation(spec, parent)
            if j.kind == "revolute":
                if j.toward is not None and j.toward in drawn:
                    def angle(P, j=j):
                        r = P[j.toward] - P[j.at]
                        return math.atan2(r[1], r[0]) - _angle_of(parent_angle, P)

                    return angle, True
                child_angle = _orientation(spec, j.body)
                if child_angle is None:
                    return None
                return (lambda P: child_angle(P) - _angle_of(parent_angle, P)), True
            first = next(p for p in spec.body(j.body).points if p in drawn)
            direction = _direction(spec, parent, np.asarray(j.direction, dtype=float), drawn)
            return (lambda P: float(direction(P) @ (P[first] - P[j.at]))), False
    raise spec.error(f"actuated coordinate {name!r} is not a joint coordinate or a cylinder", "actuated")


def input_values(spec: LinkageSpec) -> dict[str, float]:
    """The actuated coordinates' measures (:func:`input_measure`) in the drawing."""
    drawn = spec.drawing()
    out = {}
    for name in spec.actuated:
        found = input_measure(spec, name, drawn)
        if found is not None:
            out[name] = found[0](drawn)
    return out


def _input(spec: LinkageSpec, name: str, drawn: Mapping[str, Vector]) -> list:
    """The actuated coordinate ``name`` held at its drawn value (or the value ``spec.held_inputs`` gives)."""
    found = input_measure(spec, name, drawn)
    if found is None:
        return []
    measure, angular = found
    value = spec.held_inputs.get(name, measure(drawn))
    if angular:
        return [(f"input {name}", lambda P: math.remainder(measure(P) - value, 2 * math.pi))]
    return [(f"input {name}", lambda P: measure(P) - value)]


def _slider(spec: LinkageSpec, c: ClosureSpec, drawn: Mapping[str, Vector]) -> list:
    line_body = c.line_body or spec.owners(c.line)[0]
    point = spec.point(c.line)
    if point.direction is None:
        raise spec.error(f"slider of {c.point}: the line point {c.line} needs a direction", "closures")
    direction = _direction(spec, line_body, np.asarray(point.direction, dtype=float), drawn)

    def offset(P: Mapping[str, Vector]) -> float:
        d = direction(P)
        return float(np.array([-d[1], d[0]]) @ (P[c.point] - P[c.line]))

    out = [(f"slider {c.point} on {c.line}", offset)]
    if c.lock_angle:
        body = c.body or spec.owners(c.point)[0]
        out += _relative_angle(spec, body, line_body, drawn, f"slider {c.point} on {c.line} (angle)")
    return out


def curve_spline(c: ClosureSpec):
    """The curve of a curve closure's table: the not-a-knot cubic spline through it (a ``scipy.interpolate.
    CubicSpline``, a piecewise cubic), exact for polynomials up to degree 3 (a parabola given by 4 or more points is
    reproduced exactly)."""
    from scipy.interpolate import CubicSpline

    return CubicSpline(np.asarray(c.x, dtype=float), np.asarray(c.y, dtype=float), bc_type="not-a-knot")


def curve_functions(c: ClosureSpec) -> tuple[Callable[[float], float], Callable[[float], float],
                                              Callable[[float], float]]:
    """y(x), y′(x), y″(x) of a curve closure's table (:func:`curve_spline`)."""
    spline = curve_spline(c)
    first, second = spline.derivative(1), spline.derivative(2)
    return (lambda x: spline(x)[()], lambda x: first(x)[()], lambda x: second(x)[()])  # floats, or arrays for arrays


def _residual_text(spec: LinkageSpec, equation: str, value: float) -> str:
    """A constraint's residual with its unit: rad for an angle (a guide's angle, a revolute input), else mm."""
    angle = equation.endswith("(angle)")
    if equation.startswith("input "):
        name = equation[len("input "):]
        angle = any(j.kind == "revolute" and joint_coordinate(j) == name for j in spec.joints)
    return f"{value:.3g} rad" if angle else f"{value * 1e3:.3g} mm"


def close_drawing(spec: LinkageSpec, max_iterations: int = 60) -> ClosedDrawing:
    """The consistent position nearest to the drawing (minimum-norm Gauss–Newton, see the module docstring).

    Raises:
        InputError: naming the constraint with the largest residual if the equations have no solution near the
            drawing.
    """
    drawn = spec.drawing()
    names = list(drawn)
    equations = constraints(spec)
    x0 = np.concatenate([drawn[n] for n in names]) if names else np.zeros(0)
    scale = max(1.0, float(np.abs(x0).max(initial=0.0)))

    def unpack(x: Vector) -> dict[str, Vector]:
        return {n: x[2 * k:2 * k + 2] for k, n in enumerate(names)}

    def residual(x: Vector) -> Vector:
        P = unpack(x)
        return np.array([f(P) for _, f in equations]) if equations else np.zeros(0)

    x = x0.copy()
    phi = residual(x)
    start = np.abs(phi)
    worst = equations[int(np.argmax(start))][0] if len(start) else ""
    first_residual = float(start.max(initial=0.0))
    h = 1e-7 * scale
    for _ in range(max_iterations):
        if np.abs(phi).max(initial=0.0) < 1e-12 * scale:
            break
        J = np.empty((len(phi), len(x)))
        for k in range(len(x)):
            step = np.zeros_like(x)
            step[k] = h
            J[:, k] = (residual(x + step) - residual(x - step)) / (2 * h)
        x = x - np.linalg.lstsq(J, phi, rcond=None)[0]
        phi = residual(x)
    if np.abs(phi).max(initial=0.0) >= 1e-9 * scale:
        k = int(np.argmax(np.abs(phi)))
        raise spec.error(f"the drawing cannot be closed: {equations[k][0]} is off by "
                         f"{_residual_text(spec, equations[k][0], abs(float(phi[k])))} (the lengths, guides and "
                         "curves do not fit together near the drawing)", "points")
    P = unpack(np.where(np.abs(x - x0) < 1e-12 * scale, x0, x))  # what did not move keeps its drawn value
    moves = {n: float(np.linalg.norm(P[n] - drawn[n])) for n in names}
    return ClosedDrawing({n: P[n].copy() for n in names}, moves, first_residual, worst)


def drawing_size(spec: LinkageSpec) -> float:
    """The largest distance between two drawn points (m)."""
    xy = np.array(list(spec.drawing().values()))
    return float(np.ptp(xy, axis=0).max()) if len(xy) > 1 else 1.0


# ------------------------------------------------------------------------------------------------ building
#: The number of points each kind of measure takes.
MEASURE_POINTS = {"transmission_angle": 4, "lever_arm": 3, "distance": 2}


def joint_coordinate(j: JointSpec) -> str:
    """The name of a tree joint's coordinate (a cylinder's is its name)."""
    if j.kind == "cylinder":
        return j.name
    return j.coordinate or (f"{j.body}_angle" if j.kind == "revolute" else f"{j.body}_position")


def joint_parent(spec: LinkageSpec, j: JointSpec) -> str:
    """The parent body of a tree joint: given, or the body other than the joint's that carries its point."""
    if j.parent is not None:
        if j.parent != GROUND and j.parent not in {b.name for b in spec.bodies}:
            raise spec.error(f"joint of {j.body}: unknown parent body {j.parent!r}", "joints")
        return j.parent
    owners = [b for b in spec.owners(j.at) if b != j.body]
    if not owners:
        return GROUND
    return owners[0]


def frame_names(spec: LinkageSpec) -> dict[tuple[str, str], str]:
    """The frame of every (point, body): the point's own name on its first body, ``point@body`` on the others."""
    out: dict[tuple[str, str], str] = {}
    for point in spec.points:
        for k, body in enumerate(spec.owners(point.name)):
            out[(point.name, body)] = point.name if k == 0 else f"{point.name}@{body}"
    return out


def build_linkage(spec: LinkageSpec, *, check_tolerance: bool = True) -> Mechanism:
    """The :class:`~mechatron.model.Mechanism` of a linkage spec: the drawing closed (:func:`close_drawing`), the
    Pinocchio tree built by :class:`~mechatron.model.planar.PlanarBuilder`, parameters (every named length and every
    drawn point's ``_x``, ``_y``) that rebuild it, named branches assembled.

    Raises:
        InputError: for a structural problem, a drawing that does not close within the tolerance (default 2 % of the
            drawing's size), or actuated inputs that do not match the mobility.
    """
    if not spec.planar:
        raise spec.error("a spatial mechanism (planar = false): build it with mechatron.model.spatial.build_spatial "
                         "or build_mechanism", "planar")
    check(spec)
    try:
        closed = close_drawing(spec)
    except InputError:
        if spec.actuated:  # too many inputs held at their drawn values? the model names the mobility
            free = replace(spec, actuated=())
            _assemble_model(_moved(free, close_drawing(free).positions), actuated=spec.actuated)
        raise
    tolerance = spec.tolerance if spec.tolerance is not None else 0.02 * drawing_size(spec)
    moved = max(closed.moves.items(), key=lambda item: item[1], default=("", 0.0))
    if check_tolerance and moved[1] > tolerance:
        raise spec.error(f"the loops do not close within {tolerance * 1e3:.4g} mm: closing {closed.worst} (off by "
                         f"{closed.residual * 1e3:.4g} mm in the drawing) moves {moved[0]} by {moved[1] * 1e3:.4g} mm",
                         "points")
    nominal = _moved(spec, closed.positions)
    mech = _assemble_model(nominal)
    notes = list(spec.notes)
    shifted = {n: d for n, d in closed.moves.items() if d > 1e-9}
    if shifted:
        notes.append("the drawing was closed by moving " + ", ".join(
            f"{n} by {d * 1e3:.3g} mm" for n, d in sorted(shifted.items(), key=lambda item: -item[1])))
    mech.notes = notes
    return mech


def _rotate(vector, angle: float) -> tuple[float, float]:
    c, s = math.cos(angle), math.sin(angle)
    return (c * vector[0] - s * vector[1], s * vector[0] + c * vector[1])


def _moved(spec: LinkageSpec, positions: Mapping[str, Vector]) -> LinkageSpec:
    """The spec drawn at the closed ``positions``: what is fixed to a body (a centre of mass given by coordinates,
    the direction of a point's frame, a prismatic guide) follows the body's rigid motion from the drawing."""
    drawn = spec.drawing()
    turn, origin = {}, {}
    for body in spec.bodies:
        angle = _orientation(spec, body.name)
        turn[body.name] = 0.0 if angle is None else math.remainder(angle(positions) - angle(drawn), 2 * math.pi)
        first = next((p for p in body.points if p in drawn), None)
        origin[body.name] = (drawn[first], positions[first]) if first is not None else (np.zeros(2), np.zeros(2))
    bodies = []
    for body in spec.bodies:
        com = body.com
        if com is not None and not isinstance(com, str):
            start, end = origin[body.name]
            com = tuple(float(v) for v in end + np.array(_rotate(np.asarray(com) - start, turn[body.name])))
        bodies.append(replace(body, com=com))
    points = []
    for p in spec.points:
        owners = spec.owners(p.name)
        if p.direction is not None and owners:
            p = replace(p, direction=_rotate(p.direction, turn[owners[0]]))
        if p.at is not None:
            p = replace(p, at=tuple(float(v) for v in positions[p.name]))
        points.append(p)
    joints = tuple(replace(j, direction=_rotate(j.direction, turn.get(joint_parent(spec, j), 0.0)))
                   if j.kind == "prismatic" else j for j in spec.joints)
    return replace(spec, points=tuple(points), bodies=tuple(bodies), joints=joints)


def _positions(spec: LinkageSpec) -> dict[str, Vector]:
    """World positions of every point (the drawn ones and those derived from them)."""
    positions = spec.drawing()
    for p in spec.points:
        if p.between is not None:
            a, b = (positions[n] for n in p.between)
            positions[p.name] = a + p.fraction * (b - a)
    return positions


def plate_properties(corners: Sequence[Vector]) -> tuple[float, Vector, float]:
    """(area A (m²), centroid C (m), polar second moment J_C (m⁴) about C) of a plane polygon given by its corners
    in order: the shoelace sums A = ½ Σ c_i, C = Σ (p_i + p_{i+1}) c_i / (6A), J_O = Σ (|p_i|² + p_i·p_{i+1} +
    |p_{i+1}|²) c_i / 12 with c_i = x_i y_{i+1} − x_{i+1} y_i, and J_C = J_O − A |C|²."""
    p = np.asarray(corners, dtype=float)
    q = np.roll(p, -1, axis=0)
    c = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    area = 0.5 * float(c.sum())
    if abs(area) < 1e-15:
        raise InputError("a plate's corners enclose no area")
    centroid = ((p + q) * c[:, None]).sum(axis=0) / (6 * area)
    polar = float((((p**2).sum(axis=1) + (p * q).sum(axis=1) + (q**2).sum(axis=1)) * c).sum() / 12)
    return abs(area), centroid, abs(polar) - abs(area) * float(centroid @ centroid)


def _mass_properties(body: BodySpec, positions: Mapping[str, Vector]) -> tuple[float, Vector | None, float]:
    """(mass, centre, I_zz about the centre) of a planar body: as given, or from its shape — a uniform bar between
    its first two points (centre in the middle, I = m L²/12) or a uniform plate, the polygon of its points in order
    (centre at the centroid, I = m J_C / A, :func:`plate_properties`)."""
    com = body.com
    plate = plate_properties([positions[p] for p in body.points]) if body.shape == "plate" else None
    if isinstance(com, str):
        centre = positions[com]
    elif com is not None:
        centre = np.asarray(com, dtype=float)
    elif body.shape == "bar":
        centre = (positions[body.points[0]] + positions[body.points[1]]) / 2
    elif plate is not None:
        centre = plate[1]
    else:
        centre = None
    inertia = body.inertia
    if inertia is None and plate is not None:
        inertia = body.mass * plate[2] / plate[0]
    elif inertia is None:
        length = float(np.linalg.norm(positions[body.points[1]] - positions[body.points[0]])) \
            if body.shape == "bar" else 0.0
        inertia = body.mass * length**2 / 12
    return body.mass, centre, float(inertia)


def _assemble_model(spec: LinkageSpec, actuated: Sequence[str] | None = None) -> Mechanism:
    """Build the Pinocchio tree of a closed drawing (with ``actuated`` instead of the spec's inputs, if given)."""
    positions = _positions(spec)
    frames = frame_names(spec)
    b = PlanarBuilder(spec.name, gravity=spec.gravity)
    report = {p.name: p.report for p in spec.points}
    direction = {p.name: p.direction for p in spec.points}
    placed: set[str] = {GROUND}

    def add_points(body: str) -> None:
        for p in spec.body(body).points:
            name = frames[(p, body)]
            b.point(name, body, positions[p], direction[p], report=report[p] and name == p)

    add_points(GROUND)
    pending = [j for j in spec.joints if j.kind != "cylinder"]
    bodies = {x.name for x in spec.bodies} - {GROUND}
    joined = [j.body for j in pending]
    for name in bodies:
        if joined.count(name) > 1:
            raise spec.error(f"body {name} has more than one tree joint (close the other loop with a closure)",
                             "joints")
    while pending:  # in the file's order, each joint once its parent is placed
        ready = [j for j in pending if joint_parent(spec, j) in placed][:1]
        if not ready:
            orphans = ", ".join(sorted(j.body for j in pending))
            raise spec.error(f"bodies {orphans} are not connected to the ground by the tree joints",
                             f"joints[{spec.joints.index(pending[0]) + 1}]")
        for j in ready:
            parent = joint_parent(spec, j)
            body = spec.body(j.body)
            if j.at not in spec.body(parent).points:
                raise spec.error(f"joint of {j.body}: its point {j.at} is not a point of its parent {parent}",
                                 "joints")
            mass, com, inertia = _mass_properties(body, positions)
            at = frames[(j.at, parent)]
            if j.kind == "revolute":
                toward = j.toward or next((p for p in body.points if p != j.at), None)
                b.revolute(j.body, at, toward=None if j.angle is not None or toward is None else positions[toward],
                           angle=j.angle, coordinate=joint_coordinate(j), limits=j.limits, mass=mass, com=com,
                           inertia=inertia)
            elif j.kind == "prismatic":
                unit = np.asarray(j.direction, dtype=float)
                unit = unit / np.linalg.norm(unit)
                first = body.points[0]
                b.prismatic(j.body, at, unit, reference=float(unit @ (positions[first] - positions[j.at])),
                            coordinate=joint_coordinate(j), limits=j.limits, mass=mass, com=com, inertia=inertia)
            else:
                raise spec.error(f"unknown joint type {j.kind!r}; expected revolute, prismatic or cylinder", "joints")
            placed.add(j.body)
            add_points(j.body)
            pending.remove(j)
    missing = [(i, x.name) for i, x in enumerate(spec.bodies, start=1) if x.name not in placed]
    if missing:
        raise spec.error(f"body {missing[0][1]} has no joint: it is not connected to the tree (give it a revolute "
                         "or prismatic joint)", f"bodies[{missing[0][0]}]")
    for i, j in enumerate(spec.joints, start=1):
        if j.kind == "cylinder":
            base_body, eye_body = spec.owners(j.base), spec.owners(j.eye)
            if not base_body or not eye_body:
                raise spec.error(f"cylinder {j.name}: its base and eye must be points of bodies", f"joints[{i}]")
            length = float(np.linalg.norm(positions[j.eye] - positions[j.base]))
            if not j.stroke[0] - 1e-9 <= length <= j.stroke[1] + 1e-9:
                raise spec.error(f"cylinder {j.name}: its eye {j.eye} is {length * 1e3:.6g} mm from its base "
                                 f"{j.base} in the drawing, outside its stroke [{j.stroke[0] * 1e3:.6g}, "
                                 f"{j.stroke[1] * 1e3:.6g}] mm", f"joints[{i}].stroke")
            b.cylinder(j.name, frames[(j.base, base_body[0])], frames[(j.eye, eye_body[0])], stroke=j.stroke,
                       count=j.count, barrel_mass=j.barrel_mass, rod_mass=j.rod_mass)
    _closures(spec, b, frames, positions)
    for body in spec.bodies:
        draw = body.draw if body.draw is not None else body.points
        if len(draw) >= 2 or body.draw_kind == "slider":
            b.line(body.name, *(frames.get((p, body.name), p) for p in draw),
                   kind="ground" if body.name == GROUND else body.draw_kind)
    for m in spec.measures:
        if m.kind not in MEASURE_POINTS:
            raise spec.error(f"unknown measure type {m.kind!r}; expected one of: {', '.join(MEASURE_POINTS)}",
                             "measures")
        if len(m.points) != MEASURE_POINTS[m.kind]:
            raise spec.error(f"measure {m.name}: a {m.kind} takes {MEASURE_POINTS[m.kind]} points", "measures")
        b.measures.append(Measure(m.name, m.kind, tuple(m.points), m.minimum))
    actuated = list(spec.actuated if actuated is None else actuated)
    mech = b.build(actuated=actuated, description=spec.description, parameters=parameters(spec),
                   rebuild=lambda values: rebuild(spec, values), tool=spec.tool or spec.points[-1].name,
                   input_rates=dict(spec.input_rates), check=True)
    mobility = mech.mobility()
    if mobility != len(actuated):
        listed = f" ({', '.join(actuated)})" if actuated else ""
        raise spec.error(f"{len(actuated)} actuated input(s){listed} for a mechanism of mobility {mobility}: give "
                         f"{mobility}", "actuated")
    mech.source = spec.file or spec.source or None
    mech.branches.update(_branches(spec, mech))
    mech.drives.update(drive_placements(spec))
    return mech


def _closures(spec: LinkageSpec, b: PlanarBuilder, frames: Mapping[tuple[str, str], str],
              positions: Mapping[str, Vector]) -> None:
    for c in spec.closures:
        if c.kind == "pin":
            bodies = list(c.bodies) or [x for x in spec.owners(c.point)]
            if len(bodies) != 2:
                raise spec.error(f"pin {c.point}: carried by {len(bodies)} bodies ({', '.join(bodies)}); name the two "
                                 "it joins", "closures")
            for body in bodies:
                if (c.point, body) not in frames:
                    raise spec.error(f"pin {c.point}: not a point of body {body}", "closures")
            b.pin(frames[(c.point, bodies[0])], frames[(c.point, bodies[1])])
        elif c.kind == "slider":
            body = c.body or spec.owners(c.point)[0]
            line_body = c.line_body or spec.owners(c.line)[0]
            b.slider(frames[(c.point, body)], frames[(c.line, line_body)], lock_angle=c.lock_angle)
        elif c.kind == "curve":
            body = c.body or spec.owners(c.point)[0]
            f, df, d2f = curve_functions(c)
            b.on_curve(frames[(c.point, body)], f, df, d2f, label=c.label or f"the curve of {c.point}",
                       spline=curve_spline(c))
        elif c.kind == "gear":
            offset = c.offset
            if offset is None:
                index = {name: k for k, name in enumerate(b.model.names[1:])}
                qa = b.reference[index[_coordinate_of(spec, c.driver)]]
                qb = b.reference[index[_coordinate_of(spec, c.driven)]]
                offset = qb - c.ratio * qa
            b.gear(c.driver, c.driven, c.ratio, offset)
        else:
            raise spec.error(f"unknown closure type {c.kind!r}; expected pin, slider, curve or gear", "closures")


def _coordinate_of(spec: LinkageSpec, body: str) -> str:
    for j in spec.joints:
        if j.kind != "cylinder" and j.body == body:
            return joint_coordinate(j)
    raise spec.error(f"gear of body {body!r}, which has no joint", "closures")


def _branches(spec: LinkageSpec, mech: Mechanism) -> dict[str, Vector]:
    """Each named branch: the other dependent coordinates fitted to the given ones (Gauss–Newton steps with the
    given held), then every dependent one closed by minimum-norm Newton steps from there (the given values are
    approximate); the actuated inputs at their reference values."""
    out = {}
    system = mech.closure_system()
    index = {name: mech.model.joints[mech.joint_id(name)].idx_q for name in mech.joint_names}
    actuated = {index[n] for n in mech.actuated}
    for branch, values in spec.branches.items():
        q = np.array(mech.reference_q, dtype=float)
        for name, value in values.items():
            if name not in index:
                raise spec.error(f"branch {branch}: unknown coordinate {name!r}", f"branches.{branch}")
            q[index[name]] = value
        given = {index[name] for name in values}
        free = [k for k in range(mech.nq) if k not in actuated]
        for iterations, moving in ((20, [k for k in free if k not in given]), (50, free)):
            for _ in range(iterations if moving else 0):
                phi, J = system.evaluate(q)
                if np.abs(phi).max(initial=0.0) < 1e-13:
                    break
                q[moving] -= np.linalg.lstsq(J[:, moving], phi, rcond=None)[0]
        if np.abs(system.evaluate(q)[0]).max(initial=0.0) > 1e-9:
            raise spec.error(f"branch {branch}: the loops do not close near the given coordinates",
                             f"branches.{branch}")
        out[branch] = q
    return out


# ------------------------------------------------------------------------------------------------ parameters
def parameters(spec: LinkageSpec) -> dict[str, Parameter]:
    """Every named length (m) and the x, y of every drawn point (m), at their values in the closed drawing."""
    positions = spec.drawing()
    out = {}
    for length in spec.lengths:
        a, b = length.points
        value = float(np.linalg.norm(positions[b] - positions[a]))
        out[length.name] = Parameter(length.name, value, "length", f"length |{a}{b}|")
    for p in spec.points:
        if p.at is not None:
            for axis, value in zip("xy", positions[p.name]):
                name = f"{p.name}_{axis}"
                if name not in out:
                    out[name] = Parameter(name, float(value), "length", f"{axis} of point {p.name} in the drawing")
    return out


def rebuild(spec: LinkageSpec, values: Mapping[str, float]) -> Mechanism:
    """The linkage with other values of its parameters: lengths become declared (authoritative) lengths, point
    coordinates move the drawn points; the drawing is then closed again (without the tolerance: the change is
    asked for)."""
    lengths = {length.name: length for length in spec.lengths}
    moved = spec.drawing()
    new_lengths = []
    for length in spec.lengths:
        value = values.get(length.name)
        new_lengths.append(replace(length, value=float(value)) if value is not None else length)
    for name, value in values.items():
        if name in lengths:
            continue
        point, _, axis = name.rpartition("_")
        moved[point] = moved[point].copy()
        moved[point]["xy".index(axis)] = float(value)
    changed = replace(spec.with_positions(moved), lengths=tuple(new_lengths), held_inputs=input_values(spec))
    return build_linkage(changed, check_tolerance=False)

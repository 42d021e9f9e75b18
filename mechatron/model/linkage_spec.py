"""What a mechanism file says, as data: a :class:`LinkageSpec` (points, bodies, joints, closures, measures, named
lengths, branches, drives; SI units) with its look-ups and the structural checks of :func:`check`, each an
:class:`~mechatron.errors.InputError` naming the file and the field. docs/mechanism_file.md has the file format;
:mod:`mechatron.model.linkage_file` reads and writes the files, :mod:`mechatron.model.linkage` builds the mechanism.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError

GROUND = "ground"
Vector = NDArray[np.float64]

# ------------------------------------------------------------------------------------------------ the data
@dataclass(frozen=True)
class PointSpec:
    """A named point. ``at``: its world position (m) in the drawing; or ``between`` two points at ``fraction`` of
    the way (a derived point, e.g. the middle of a rod, that follows them when the drawing is corrected).
    ``direction``: the x axis of the point's frame in the drawing (a slider's line); ``report``: listed in sweeps;
    ``table``: the file's table it is given in (``points`` or ``points_mm``), for messages."""

    name: str
    at: tuple[float, ...] | None = None  # (x, y), or (x, y, z) in a spatial mechanism
    between: tuple[str, str] | None = None
    fraction: float = 0.5
    direction: tuple[float, float] | None = None
    report: bool = True
    table: str = field(default="points", compare=False)

    @property
    def field(self) -> str:
        """The point's field in the file: ``points.P`` or ``points_mm.P``."""
        return f"{self.table}.{self.name}"


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
    axis: tuple[float, ...] | None = None  # spatial revolute: the world axis in the drawing
    axes: tuple[tuple[float, ...], ...] | None = None  # spatial universal: parent's axis, cross's axis


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
    @cached_property
    def _points_by_name(self) -> dict[str, PointSpec]:
        return {p.name: p for p in self.points}

    @cached_property
    def _bodies_by_name(self) -> dict[str, BodySpec]:
        return {b.name: b for b in self.bodies}

    @cached_property
    def _owners(self) -> dict[str, list[str]]:
        out: dict[str, list[str]] = {}
        for b in self.bodies:
            for p in b.points:
                out.setdefault(p, []).append(b.name)
        return out

    def point(self, name: str) -> PointSpec:
        try:
            return self._points_by_name[name]
        except KeyError:
            raise self.error(f"unknown point {name!r}", "points") from None

    def body(self, name: str) -> BodySpec:
        try:
            return self._bodies_by_name[name]
        except KeyError:
            raise self.error(f"unknown body {name!r}", "bodies") from None

    def owners(self, point: str) -> list[str]:
        """The bodies carrying ``point``, in the file's order."""
        return list(self._owners.get(point, ()))

    def error(self, message: str, field: str | None = None) -> InputError:
        return InputError(message, file=self.file, field=field)

    def drawing(self) -> dict[str, Vector]:
        """The drawn world positions of the points given by coordinates (m)."""
        return {p.name: np.array(p.at, dtype=float) for p in self.points if p.at is not None and p.between is None}

    def with_positions(self, positions: Mapping[str, Vector]) -> LinkageSpec:
        """The same linkage drawn at other positions of its drawn points (m; derived points follow theirs)."""
        points = tuple(replace(p, at=tuple(float(v) for v in positions[p.name]))
                       if p.name in positions and p.between is None else p for p in self.points)
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
                             f"mechanism, got {len(p.at)}", p.field)
        if p.between is not None:
            for other in p.between:
                if other not in known or other == p.name:
                    raise spec.error(f"point {p.name} lies between unknown point {other!r}", p.field)
                if spec.point(other).between is not None:
                    raise spec.error(f"point {p.name}: a derived point lies between drawn points, not {other}",
                                     p.field)
    bodies = {b.name for b in spec.bodies}
    if GROUND not in bodies:
        raise spec.error("give the frame's points as a body named ground", "bodies")
    for i, b in enumerate(spec.bodies, start=1):
        where = f"bodies[{i}]"
        if not b.points:
            raise spec.error(f"body {b.name} carries no point", f"{where}.points")
        for name in b.points:
            if name not in known:
                raise spec.error(f"body {b.name} carries unknown point {name!r}", f"{where}.points")
        if len(set(b.points)) != len(b.points):
            raise spec.error(f"body {b.name} lists a point twice", f"{where}.points")
        if b.mass < 0:
            raise spec.error(f"body {b.name}: mass must be >= 0 kg, got {b.mass:g}", f"{where}.mass")
        if spec.planar and b.inertia is not None and np.any(np.asarray(b.inertia, dtype=float) < 0):
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
    _check_points_are_fixed(spec)
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
        for name in m.points:
            if name not in known:
                raise spec.error(f"measure {m.name}: unknown point {name!r}", f"measures[{i}].points")
    for length in spec.lengths:
        a, end = length.points
        if not any(a in body.points and end in body.points for body in spec.bodies):
            raise spec.error(f"length {length.name}: {a} and {end} are not two points of one body",
                             f"lengths.{length.name}")
        if length.value is not None and not length.value > 0:
            raise spec.error(f"length {length.name} must be > 0 m, got {length.value:g}", f"lengths.{length.name}")
        for end in length.points:
            if spec.point(end).between is not None:
                raise spec.error(f"length {length.name}: {end} is a derived point (it follows the points it lies "
                                 "between); a named length joins two drawn points", f"lengths.{length.name}")
    _check_declared_lengths(spec)


def _check_points_are_fixed(spec: LinkageSpec) -> None:
    """Every point is fixed by a body that carries it (a point of no body is undetermined), and a derived point
    lies between two points of one of the bodies that carry it (there it follows them; on its other bodies it stays
    where it is drawn)."""
    for p in spec.points:
        owners = spec.owners(p.name)
        if not owners:
            raise spec.error(f"point {p.name} is carried by no body, so nothing fixes it: list it in the points of "
                             "the body it belongs to", p.field)
        if p.between is not None and not any(all(end in spec.body(b).points for end in p.between) for b in owners):
            raise spec.error(f"point {p.name} lies between {p.between[0]} and {p.between[1]}, but none of the bodies "
                             f"carrying it ({', '.join(owners)}) carries both: a derived point follows two points of "
                             "its body", p.field)


def declared_partners(spec: LinkageSpec, body: BodySpec, lengths: Mapping[str, object]) -> dict[str, list]:
    """For every drawn point of ``body`` the declared lengths that place it: [(earlier point, length name)] for
    each named length in ``lengths`` between it and a point listed before it on the body."""
    drawn = [p for p in body.points if spec.point(p).at is not None]
    order = {p: k for k, p in enumerate(drawn)}
    ends: dict[str, dict[str, str]] = {}  # point → {other point: length name}; the last length of a pair counts
    for length in spec.lengths:
        if length.name in lengths and len(set(length.points)) == 2:
            a, b = length.points
            ends.setdefault(a, {})[b] = length.name
            ends.setdefault(b, {})[a] = length.name
    out: dict[str, list] = {}
    for k, p in enumerate(drawn):
        earlier = [(order[q], q, name) for q, name in ends.get(p, {}).items() if order.get(q, k) < k]
        out[p] = [(q, name) for _, q, name in sorted(earlier)]
    return out


def _check_declared_lengths(spec: LinkageSpec) -> None:
    """Two declared lengths to earlier points fix a point of a body; a third over-determines it."""
    declared = {length.name: length.value for length in spec.lengths if length.value is not None}
    for body in spec.bodies:
        for point, partners in declared_partners(spec, body, declared).items():
            if len(partners) > 2:
                names = ", ".join(name for _, name in partners)
                raise spec.error(f"point {point} of body {body.name} has {len(partners)} declared lengths to "
                                 f"points before it ({names}): two fix it", f"lengths.{partners[2][1]}")


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


def _no_duplicates(spec: LinkageSpec, names: Sequence[str], where: str, what: str) -> None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise spec.error(f"{what} {name!r} is defined twice", where)
        seen.add(name)



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


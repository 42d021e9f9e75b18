r"""Bodies held by their frames: the shape of every body of a planar mechanism file, and the placements of the
Pinocchio tree built on those shapes.

**Shapes.** Every point a body carries is fixed in that body, at its place in the drawing, so that points drawn in
line on a bar are as determined as any others. The shape of body b is the map point → position s_{p,b} (m, in the
drawing's axes: the body's coordinates when it sits where it is drawn). Exceptions to "as drawn":

- a declared length |PQ| = L between two drawn points of the body moves the point listed later in the body's
  ``points`` (Q) to the nearest position at distance L from the earlier one: s_Q = s_P + L (d_Q − s_P)/|d_Q − s_P|
  (d the drawing); a point with two declared lengths to earlier points P₁, P₂ goes where the two circles meet, on
  the side of the line P₁P₂ where it is drawn: with e = (s_{P₂} − s_{P₁})/d, d = |s_{P₂} − s_{P₁}|,

  .. math::

      x = \frac{L_1^2 - L_2^2 + d^2}{2d}, \qquad y = \pm\sqrt{L_1^2 - x^2}, \qquad
      s = s_{P_1} + x\,e + y\,e^{\perp};

  points are placed in the body's order, so a chain of declared lengths is measured from the moved points;
- a derived point (``between = [P, Q]``, ``fraction`` f) on a body that carries P and Q follows them,
  s = s_P + f (s_Q − s_P); on a body that does not carry both it is fixed where it is drawn.

The shape of a body is independent of the other bodies: the drawing need not close. A pin carried by two bodies may
sit at two places in their shapes; the tree's joints and the closures bring them together when the loops are closed
(:mod:`mechatron.model.linkage`).

**Frames and placements.** A body's frame has its origin at its joint's pin and, for a revolute joint, its x axis
toward the joint's ``toward`` point (or at the joint's ``angle``); a prismatic body keeps its parent's axes, its
origin on the guide where its first point projects. A point's frame on body b is at R(−θ_b)(s_{p,b} − o_b) in the body
frame (o_b, θ_b the frame's origin and angle in the drawing), turned to the point's ``direction`` if it has one; a
joint's placement in its parent is the parent's shape of the pin, R(−θ_λ)(s_{pin,λ} − o_λ), with no rotation for a
revolute joint (its coordinate is the angle from the parent's x axis) and turned to the guide for a prismatic one
(its coordinate is the travel along the guide).

Everything here is written on scalars with the functions of a namespace ``m`` (``math`` for numbers, ``casadi`` for
expressions: both have sqrt, atan2, cos, sin, fabs), so that the same code gives the model's numbers and, through
CasADi, their exact derivatives with respect to the named parameters (:mod:`mechatron.model.derivatives`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import InputError
from .linkage_spec import (
    GROUND,
    BodySpec,
    LinkageSpec,
    declared_partners,
    frame_names,
    joint_coordinate,
    joint_parent,
)

Vec = tuple[Any, ...]  # (x, y) in a planar mechanism; sub, add, scaled and dot take (x, y, z) too


# ------------------------------------------------------------------------------------------------ vectors
def sub(a: Vec, b: Vec) -> Vec:
    return tuple(x - y for x, y in zip(a, b))


def add(a: Vec, b: Vec) -> Vec:
    return tuple(x + y for x, y in zip(a, b))


def scaled(a: Vec, s: Any) -> Vec:
    return tuple(x * s for x in a)


def dot(a: Vec, b: Vec) -> Any:
    return sum((x * y for x, y in zip(a, b)), 0.0)


def cross(a: Vec, b: Vec) -> Any:
    return a[0] * b[1] - a[1] * b[0]


def turned(a: Vec, angle: Any, m=math) -> Vec:
    """``a`` turned by ``angle`` (rad): R(angle) a."""
    c, s = m.cos(angle), m.sin(angle)
    return (c * a[0] - s * a[1], s * a[0] + c * a[1])


def is_number(x: Any) -> bool:
    return isinstance(x, (int, float))


# ------------------------------------------------------------------------------------------------ shapes
def derived_position(spec: LinkageSpec, point: str, positions: Mapping[str, Vec]) -> Vec:
    """P + f (Q − P) of the derived point ``point`` from the positions of P and Q."""
    p = spec.point(point)
    assert p.between is not None  # a derived point
    a, b = positions[p.between[0]], positions[p.between[1]]
    return add(a, scaled(sub(b, a), p.fraction))


def with_derived(spec: LinkageSpec, drawing: Mapping[str, Vec]) -> dict[str, Vec]:
    """The drawn positions of the drawn points (``drawing``) and of the derived ones."""
    full = dict(drawing)
    for p in spec.points:
        if p.between is not None:
            full[p.name] = derived_position(spec, p.name, drawing)
    return full


def body_shape(spec: LinkageSpec, body: BodySpec, drawing: Mapping[str, Vec], lengths: Mapping[str, Any],
               m=math, sides: Mapping[str, float] | None = None) -> dict[str, Vec]:
    """The shape of ``body``: the position (m, drawing axes) of each of its points (module docstring), from the
    drawn positions ``drawing`` of every point (a derived one's from its points) and the values of the declared
    lengths ``lengths`` (by name).
    ``sides`` (±1 per point placed by two lengths) says on which side of the line of its two partners a point lies;
    by default the drawing's side.

    Raises:
        InputError: (for numbers) when a point is drawn where its declared length has no direction, or two declared
            lengths cannot meet.
    """
    placed: dict[str, Vec] = {}
    for point, partners in declared_partners(spec, body, lengths).items():
        drawn = drawing[point]
        if not partners:
            placed[point] = drawn
        elif len(partners) == 1:
            (q, name), = partners
            r = sub(drawn, placed[q])
            d = m.sqrt(dot(r, r))
            if is_number(d) and d == 0:
                raise spec.error(f"length {name}: {point} is drawn where {q} is, so the length has no direction",
                                 f"lengths.{name}")
            placed[point] = add(placed[q], scaled(r, lengths[name] / d))
        else:
            (p1, n1), (p2, n2) = partners[:2]
            side = sides[point] if sides is not None else _side(placed[p1], placed[p2], drawn)
            placed[point] = _circles_meet(spec, placed[p1], placed[p2], lengths[n1], lengths[n2], side, m,
                                          (point, n1, n2))
    for point in body.points:
        p = spec.point(point)
        if p.between is not None:
            carried = all(end in placed for end in p.between)
            placed[point] = derived_position(spec, point, placed) if carried else drawing[point]
    return {point: placed[point] for point in body.points}


def _side(a: Vec, b: Vec, p: Vec) -> float:
    """+1 if ``p`` lies left of the line a → b, else −1 (numbers)."""
    return math.copysign(1.0, cross(sub(b, a), sub(p, a)))


def _circles_meet(spec: LinkageSpec, a: Vec, b: Vec, r1: Any, r2: Any, side: float, m, names: tuple[str, str, str]
                  ) -> Vec:
    """The point at distance r1 from a and r2 from b, on the ``side`` (±1) of the line a→b (left is +1)."""
    ab = sub(b, a)
    d = m.sqrt(dot(ab, ab))
    x = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    square = r1 * r1 - x * x
    if is_number(square) and not square >= 0:
        point, first, second = names
        raise spec.error(f"point {point}: the declared lengths {first} and {second} cannot meet (their circles do not "
                         "cross)", f"lengths.{second}")
    y = m.sqrt(square) * side
    e = scaled(ab, 1 / d)
    return add(a, add(scaled(e, x), (-e[1] * y, e[0] * y)))


def circle_sides(spec: LinkageSpec, drawing: Mapping[str, Vec], lengths: Mapping[str, Any]) -> dict[str, float]:
    """For every point a body places by two declared lengths, the side (±1) of the line of its partners on which
    it is drawn (numbers only): what fixes the branch of :func:`body_shape` for symbolic drawings."""
    out: dict[str, float] = {}
    full = with_derived(spec, drawing)
    for body in spec.bodies:
        shape = body_shape(spec, body, full, lengths)
        for point, partners in declared_partners(spec, body, lengths).items():
            if len(partners) >= 2:
                (p1, _), (p2, _) = partners[:2]
                out[point] = _side(shape[p1], shape[p2], drawing[point])
    return out


def shapes(spec: LinkageSpec, drawing: Mapping[str, Vec], lengths: Mapping[str, Any], m=math,
           sides: Mapping[str, float] | None = None) -> dict[tuple[str, str], Vec]:
    """The shape of every body: (point, body) → position (m, drawing axes) (:func:`body_shape`). ``drawing`` has the
    drawn points; the derived points' drawn positions follow from them."""
    full = with_derived(spec, drawing)
    out: dict[tuple[str, str], Vec] = {}
    for body in spec.bodies:
        for point, position in body_shape(spec, body, full, lengths, m, sides).items():
            out[(point, body.name)] = position
    return out


# ------------------------------------------------------------------------------------------------ layout
@dataclass
class JointLayout:
    """One joint of the tree: ``kind`` "revolute" (about z) or "prismatic" (along its x axis), its ``coordinate``,
    its placement in the parent's body frame (``xy``, m, turned by ``angle``, rad: a prismatic joint's guide
    direction; 0 for a revolute joint), the coordinate's value in the drawing (``reference``, rad or m), its limits,
    and the body's mass (kg), centre (``com``, m, body frame) and I_zz about it (kg·m²). The body's frame is its
    joint's frame turned back by ``angle``: a prismatic body keeps its parent's axes."""

    body: str
    parent: str
    kind: str
    coordinate: str
    xy: Vec
    reference: Any
    limits: tuple[float, float] = (-math.inf, math.inf)
    angle: Any = 0.0
    mass: float = 0.0
    com: Vec = (0.0, 0.0)
    inertia: Any = 0.0


@dataclass
class FrameLayout:
    """A point's frame on ``body``: position ``xy`` (m) and ``angle`` (rad) in the body frame; ``report`` false for
    helper points (left out of sweep tables)."""

    name: str
    body: str
    xy: Vec
    angle: Any = 0.0
    report: bool = True


@dataclass
class BodyFrame:
    """A body frame in the drawing: its origin (m) and the angle (rad) of its x axis in world axes, where its body is
    drawn; ``axis`` is any vector along the x axis (default (cos θ, sin θ)): the frame's coordinates are taken
    with it, so that the point it was drawn toward lies exactly on the x axis."""

    origin: Vec
    angle: Any
    axis: Vec | None = None

    def local(self, point: Vec, m=math) -> Vec:
        """Body-frame coordinates of a point of the drawing: R(−θ)(p − o)."""
        return self.direction(sub(point, self.origin), m)

    def direction(self, d: Vec, m=math) -> Vec:
        """Body-frame components of a vector of the drawing: R(−θ) d = (a·d, a × d)/|a|."""
        a = self.axis if self.axis is not None else (m.cos(self.angle), m.sin(self.angle))
        n = m.sqrt(dot(a, a))
        return (dot(a, d) / n, cross(a, d) / n)


@dataclass
class Layout:
    """The tree of a planar mechanism file on its shapes: its joints in the order they are added (each body's joint
    before its children's; the cylinders' barrels and rods last), the point frames, and every body's frame in the
    drawing."""

    joints: list[JointLayout]
    frames: list[FrameLayout]
    bodies: dict[str, BodyFrame]


def in_joint_frame(xy: Vec, angle: Any, offset: Any, m=math) -> tuple[Any, Any, Any]:
    """A placement (x, y, angle) given in a body's frame, in its joint's frame: turned by ``offset`` (rad), the
    angle of the body frame in the joint frame (minus a prismatic joint's guide angle; 0 for a revolute joint)."""
    x, y = turned(xy, offset, m)
    return x, y, angle + offset


def _angle(v: Vec, m) -> Any:
    return m.atan2(v[1], v[0])


def layout(spec: LinkageSpec, shape: Mapping[tuple[str, str], Vec], drawing: Mapping[str, Vec], m=math) -> Layout:
    """The joints, frames and body frames of the tree of ``spec`` built on the body shapes ``shape``
    (:func:`shapes`) of the drawing ``drawing`` (the drawn points' positions). A body's frame is set by its own
    points, where it carries them, and by the drawing for the others (a ``toward`` point of another body, a
    cylinder's ends): so a body's frame, like its shape, does not depend on the other bodies. Structural problems
    raise :class:`InputError` naming the field."""
    drawn = with_derived(spec, drawing)
    frames = frame_names(spec)
    bodies: dict[str, BodyFrame] = {GROUND: BodyFrame((0.0, 0.0), 0.0)}
    joints: list[JointLayout] = []
    out_frames: list[FrameLayout] = []

    def position(point: str, body: str) -> Vec:
        """The point's position in the shape of ``body`` if it carries it, else as drawn."""
        return shape[(point, body)] if (point, body) in shape else drawn[point]

    def add_frames(body: str) -> None:
        frame = bodies[body]
        for point in spec.body(body).points:
            p = spec.point(point)
            name = frames[(point, body)]
            angle = 0.0 if p.direction is None else _angle(p.direction, m) - frame.angle
            out_frames.append(FrameLayout(name, body, frame.local(shape[(point, body)], m), angle,
                                          p.report and name == point))

    add_frames(GROUND)
    pending = [j for j in spec.joints if j.kind != "cylinder"]
    placed = {GROUND}
    for name in {j.body for j in pending}:
        if sum(j.body == name for j in pending) > 1:
            raise spec.error(f"body {name} has more than one tree joint (close the other loop with a closure)",
                             "joints")
    while pending:  # in the file's order, each joint once its parent is placed
        j = next((j for j in pending if joint_parent(spec, j) in placed), None)
        if j is None:
            orphans = ", ".join(sorted(j.body for j in pending))
            raise spec.error(f"bodies {orphans} are not connected to the ground by the tree joints",
                             f"joints[{spec.joints.index(pending[0]) + 1}]")
        parent = joint_parent(spec, j)
        if j.at not in spec.body(parent).points:
            raise spec.error(f"joint of {j.body}: its point {j.at} is not a point of its parent {parent}", "joints")
        body = spec.body(j.body)
        pin = shape[(j.at, parent)]
        xy = bodies[parent].local(pin, m)
        if j.kind == "revolute":
            origin = position(j.at, j.body)
            toward = j.toward or next((p for p in body.points if p != j.at), None)
            axis = None
            if j.angle is not None:
                angle = j.angle
            elif toward is not None:
                axis = sub(position(toward, j.body), origin)
                angle = _angle(axis, m)
            else:
                angle, axis = bodies[parent].angle, bodies[parent].axis
            bodies[j.body] = BodyFrame(origin, angle, axis)
            joint = JointLayout(j.body, parent, "revolute", joint_coordinate(j), xy, angle - bodies[parent].angle,
                                j.limits)
        elif j.kind == "prismatic":
            d = j.direction
            assert d is not None  # checked when the file was read: a prismatic joint has its direction
            unit = scaled(d, 1 / m.sqrt(dot(d, d)))
            travel = dot(unit, sub(shape[(body.points[0], j.body)], pin))
            guide = _angle(bodies[parent].direction(unit, m), m)
            bodies[j.body] = BodyFrame(add(pin, scaled(unit, travel)), bodies[parent].angle, bodies[parent].axis)
            joint = JointLayout(j.body, parent, "prismatic", joint_coordinate(j), xy, travel, j.limits, guide)
        else:
            raise spec.error(f"unknown joint type {j.kind!r}; expected revolute, prismatic or cylinder", "joints")
        joint.mass, joint.com, joint.inertia = _mass_properties(spec, body, shape, bodies[j.body], m)
        joints.append(joint)
        placed.add(j.body)
        add_frames(j.body)
        pending.remove(j)
    missing = [(i, x.name) for i, x in enumerate(spec.bodies, start=1) if x.name not in placed]
    if missing:
        raise spec.error(f"body {missing[0][1]} has no joint: it is not connected to the tree (give it a revolute "
                         "or prismatic joint)", f"bodies[{missing[0][0]}]")
    for j in spec.joints:
        if j.kind == "cylinder":
            _cylinder(spec, j, drawn, shape, bodies, joints, out_frames, m)
    return Layout(joints, out_frames, bodies)


def _cylinder(spec, j, drawn, shape, bodies, joints, out_frames, m) -> None:
    """A cylinder's barrel (turning about ``base``, x axis toward ``eye``, both as drawn) and rod (sliding along the
    barrel's x axis, coordinate = the pin-to-pin length), with the frames ``{name}_base`` and ``{name}_eye``; the
    barrel's and the rod's masses at their middles as slender rods (barrel L_min long, rod L_max − L_min), ``count``
    times those of one cylinder (the cylinders side by side are one in the plane). The barrel joint sits at the
    base pin of the body carrying it (its first owner)."""
    base_body = spec.owners(j.base)[0]
    start, end = drawn[j.base], drawn[j.eye]
    r = sub(end, start)
    length = m.sqrt(dot(r, r))
    angle = _angle(r, m)
    barrel, rod = f"{j.name}_barrel", f"{j.name}_rod"
    bodies[barrel] = BodyFrame(start, angle, r)
    barrel_length, rod_length = j.stroke[0], j.stroke[1] - j.stroke[0]
    barrel_mass, rod_mass = j.count * j.barrel_mass, j.count * j.rod_mass  # the count cylinders move as one
    joints.append(JointLayout(barrel, base_body, "revolute", f"{j.name}_angle",
                              bodies[base_body].local(shape[(j.base, base_body)], m), angle - bodies[base_body].angle,
                              mass=barrel_mass, com=(0.5 * barrel_length, 0.0),
                              inertia=barrel_mass * barrel_length**2 / 12))
    out_frames.append(FrameLayout(f"{j.name}_base", barrel, (0.0, 0.0), 0.0, False))
    bodies[rod] = BodyFrame(end, angle, r)
    joints.append(JointLayout(rod, barrel, "prismatic", j.name, (0.0, 0.0), length, j.stroke,
                              mass=rod_mass, com=(-0.5 * rod_length, 0.0), inertia=rod_mass * rod_length**2 / 12))
    out_frames.append(FrameLayout(f"{j.name}_eye", rod, (0.0, 0.0), 0.0, False))


def plate_properties(corners: list[Vec], m=math) -> tuple[Any, Vec, Any]:
    """(area A (m²), centroid C (m), polar second moment J_C (m⁴) about C) of a plane polygon given by its corners
    in order: the shoelace sums A = ½ Σ c_i, C = Σ (p_i + p_{i+1}) c_i / (6A), J_O = Σ (|p_i|² + p_i·p_{i+1} +
    |p_{i+1}|²) c_i / 12 with c_i = x_i y_{i+1} − x_{i+1} y_i, and J_C = J_O − A |C|²."""
    n = len(corners)
    area, cx, cy, polar = 0.0, 0.0, 0.0, 0.0
    for i in range(n):
        p, q = corners[i], corners[(i + 1) % n]
        c = cross(p, q)
        area = area + c / 2
        cx, cy = cx + (p[0] + q[0]) * c, cy + (p[1] + q[1]) * c
        polar = polar + (dot(p, p) + dot(p, q) + dot(q, q)) * c / 12
    if is_number(area) and abs(area) < 1e-15:
        raise InputError("a plate's corners enclose no area")
    centroid = (cx / (6 * area), cy / (6 * area))
    return m.fabs(area), centroid, m.fabs(polar) - m.fabs(area) * dot(centroid, centroid)


def _mass_properties(spec: LinkageSpec, body: BodySpec, shape: Mapping[tuple[str, str], Vec], frame: BodyFrame,
                     m) -> tuple[float, Vec, Any]:
    """(mass, centre in the body frame, I_zz about the centre) of a planar body: as given, or from its shape — a
    uniform bar between its first two points (centre in the middle, I = m L²/12) or a uniform plate, the polygon of
    its points in order (centre at the centroid, I = m J_C / A, :func:`plate_properties`). Without a centre it sits
    at the body frame's origin."""
    def at(point: str) -> Vec:
        return shape[(point, body.name)]

    plate = plate_properties([at(p) for p in body.points], m) if body.shape == "plate" else None
    if isinstance(body.com, str):
        centre = at(body.com)
    elif body.com is not None:
        centre = (body.com[0], body.com[1])
    elif body.shape == "bar":
        centre = scaled(add(at(body.points[0]), at(body.points[1])), 0.5)
    elif plate is not None:
        centre = plate[1]
    else:
        centre = frame.origin
    inertia = body.inertia
    if inertia is None and plate is not None:
        inertia = body.mass * plate[2] / plate[0]
    elif inertia is None and body.shape == "bar":
        r = sub(at(body.points[1]), at(body.points[0]))
        inertia = body.mass * dot(r, r) / 12
    elif inertia is None:
        inertia = 0.0
    return body.mass, frame.local(centre, m), inertia

r"""Spatial closed loops from a mechanism file with ``planar = false``: 3D points, joint axes, loops closed by point
constraints (three equations each: the two points coincide).

The tree is drawn in one assembled position with every body frame parallel to the world: a body's frame sits at the
point of its joint, a revolute joint turns about its ``axis`` (world, the drawing), a universal joint about two
(``axes``: the first on the parent, the second on the intermediate cross), a translation joint moves the body along
x, y and z (three coordinates ``<body>_x/_y/_z``). Joint coordinates are zero in the drawing. Universal and
translation joints are chains of one-coordinate joints through massless bodies (``<body>_cross``, ``<body>_tx``,
``<body>_ty``), so that every coordinate has a name and a joint of its own.

A drawing read off paper is closed in joint space: q ← q − J⁺ Φ(q) (minimum-norm Newton steps from q = 0, the
actuated coordinates held at zero), and the loader reports how far every point moved; beyond the tolerance it
refuses, naming the closure. Gravity acts along −z.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .closures import Pin
from .derivatives import PlacementDerivatives, empty
from .dh import inertial_problem
from .mechanism import Measure, Mechanism, Parameter, SketchLine

GROUND = "ground"
Vector = NDArray[np.float64]


#: The smallest sine of the angle between a universal joint's two axes: below it they are parallel.
PARALLEL_SINE = 1e-6


def coordinate_names(kind: str, body: str, coordinate: str | None = None) -> tuple[str, ...]:
    """The coordinates a spatial joint of ``body`` adds: a revolute joint's ``coordinate`` (default
    ``{body}_angle``), a universal joint's ``{body}_angle1`` and ``{body}_angle2``, a translation's ``{body}_x``,
    ``{body}_y``, ``{body}_z``."""
    if kind == "universal":
        return (f"{body}_angle1", f"{body}_angle2")
    if kind == "translation":
        return (f"{body}_x", f"{body}_y", f"{body}_z")
    return (coordinate or f"{body}_angle",)


def axis_problem(axis: Sequence[float]) -> str | None:
    """Why ``axis`` is not a joint axis (3 numbers, not all zero), or ``None``."""
    a = np.asarray(axis, dtype=float)
    if a.shape != (3,) or not float(np.linalg.norm(a)) > 0:
        return f"a joint axis must be 3 numbers, not all zero, got {_numbers(np.ravel(a))}"
    return None


def axes_problem(axes: Sequence[Sequence[float]]) -> str | None:
    """Why ``axes`` are not a universal joint's (two axes, neither zero, not parallel: the sine of their angle at
    least :data:`PARALLEL_SINE`), or ``None``."""
    if len(axes) != 2:
        return "a universal joint needs two axes"
    for axis in axes:
        problem = axis_problem(axis)
        if problem:
            return problem
    u, w = (np.asarray(a, dtype=float) / np.linalg.norm(a) for a in axes)
    if np.linalg.norm(np.cross(u, w)) < PARALLEL_SINE:
        return f"a universal joint's two axes must not be parallel, got {_numbers(axes[0])} and {_numbers(axes[1])}"
    return None


def _numbers(values: Sequence[float] | np.ndarray) -> str:
    return "[" + ", ".join(f"{float(v):g}" for v in values) + "]"


def bar_inertia(mass: float, start: Vector, end: Vector) -> Vector:
    """The 3×3 inertia (kg·m²) of a slender uniform bar about its centre: m L²/12 across, nothing along."""
    axis = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(axis))
    if length == 0:
        return np.zeros((3, 3))
    u = axis / length
    return mass * length**2 / 12 * (np.eye(3) - np.outer(u, u))


class SpatialBuilder:
    """Bodies, joints, points and point closures of a spatial linkage drawn in one assembled position."""

    def __init__(self, name: str, gravity: float = 9.81) -> None:
        self.name = name
        self.model = pin.Model()
        self.model.name = name
        self.model.gravity = pin.Motion(np.array([0.0, 0.0, -gravity]), np.zeros(3))
        frame = self.model.addFrame(pin.Frame(GROUND, 0, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
        self.bodies: dict[str, tuple[int, Vector, int]] = {GROUND: (0, np.zeros(3), frame)}  # joint, origin, frame
        self.points: dict[str, tuple[str, Vector, bool]] = {}
        self.closures: list[Pin] = []
        self.sketch: list[SketchLine] = []
        self.measures: list[Measure] = []

    def point(self, name: str, body: str, at: ArrayLike, *, report: bool = True) -> str:
        """A named point (an operational frame) fixed to ``body`` at the world position ``at`` (m) of the drawing."""
        if name in self.points or self.model.existFrame(name):
            raise InputError(f"{self.name}: point {name!r} defined twice")
        joint, origin, parent_frame = self._body(body)
        xyz = np.asarray(at, dtype=float)
        self.model.addFrame(pin.Frame(name, joint, parent_frame, pin.SE3(np.eye(3), xyz - origin),
                                      pin.FrameType.OP_FRAME))
        self.points[name] = (body, xyz, report)
        return name

    def _body(self, name: str) -> tuple[int, Vector, int]:
        if name not in self.bodies:
            raise InputError(f"{self.name}: unknown body {name!r}")
        return self.bodies[name]

    def _joint(self, body: str, parent: str, model: pin.JointModel, at: Vector, coordinate: str,
               limits: tuple[float, float], mass: float = 0.0, com: Vector | None = None,
               inertia: Vector | None = None) -> None:
        if body in self.bodies:
            raise InputError(f"{self.name}: body {body!r} defined twice")
        parent_joint, parent_origin, _ = self._body(parent)
        joint = self.model.addJoint(parent_joint, model, pin.SE3(np.eye(3), at - parent_origin), coordinate,
                                    np.array([np.inf]), np.array([np.inf]), np.array([limits[0]]),
                                    np.array([limits[1]]))
        frame = self.model.addFrame(pin.Frame(body, joint, self.model.nframes - 1, pin.SE3.Identity(),
                                              pin.FrameType.BODY))
        self.bodies[body] = (joint, at.copy(), frame)
        if mass < 0:
            raise InputError(f"{self.name}: body {body}: mass must be >= 0")
        if mass > 0:
            centre = (at if com is None else np.asarray(com, dtype=float)) - at
            tensor = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float)
            self.model.appendBodyToJoint(joint, pin.Inertia(mass, centre, tensor), pin.SE3.Identity())

    def revolute(self, body: str, at: str, axis: Sequence[float], *, coordinate: str | None = None,
                 limits: tuple[float, float] = (-np.inf, np.inf), mass: float = 0.0, com: Vector | None = None,
                 inertia: Vector | None = None) -> str:
        """``body`` turning about the world ``axis`` through the point ``at`` of its parent (coordinate 0 as drawn)."""
        parent, position, _ = self.points[at] if at in self.points else self._unknown(at)
        self._joint(body, parent, pin.JointModelRevoluteUnaligned(_unit(axis)), position,
                    coordinate_names("revolute", body, coordinate)[0], limits, mass, com, inertia)
        return body

    def universal(self, body: str, at: str, axes: Sequence[Sequence[float]], *,
                  coordinates: Sequence[str] | None = None, mass: float = 0.0, com: Vector | None = None,
                  inertia: Vector | None = None) -> str:
        """``body`` on a universal joint at ``at``: the first axis on the parent, the second on a massless cross."""
        parent, position, _ = self.points[at] if at in self.points else self._unknown(at)
        names = list(coordinates or coordinate_names("universal", body))
        cross = f"{body}_cross"
        limits = (-np.inf, np.inf)
        self._joint(cross, parent, pin.JointModelRevoluteUnaligned(_unit(axes[0])), position, names[0], limits)
        self._joint(body, cross, pin.JointModelRevoluteUnaligned(_unit(axes[1])), position, names[1], limits, mass,
                    com, inertia)
        return body

    def translation(self, body: str, at: str, *, coordinates: Sequence[str] | None = None, mass: float = 0.0,
                    com: Vector | None = None, inertia: Vector | None = None) -> str:
        """``body`` moving along x, y and z (no rotation) from the point ``at`` of its parent (a Delta's
        platform)."""
        parent, position, _ = self.points[at] if at in self.points else self._unknown(at)
        names = list(coordinates or coordinate_names("translation", body))
        limits = (-np.inf, np.inf)
        self._joint(f"{body}_tx", parent, pin.JointModelPX(), position, names[0], limits)
        self._joint(f"{body}_ty", f"{body}_tx", pin.JointModelPY(), position, names[1], limits)
        self._joint(body, f"{body}_ty", pin.JointModelPZ(), position, names[2], limits, mass, com, inertia)
        return body

    def _unknown(self, point: str):
        raise InputError(f"{self.name}: unknown point {point!r}")

    def pin(self, a: str, b: str) -> None:
        """Close a loop: the points ``a`` and ``b`` coincide (three equations)."""
        for p in (a, b):
            if p not in self.points:
                self._unknown(p)
        self.closures.append(Pin(f"{a}={b}", a=a, b=b, planar=False))

    def line(self, name: str, *points: str, kind: str = "link") -> None:
        self.sketch.append(SketchLine(name, tuple(points), kind))

    def build(self, *, actuated: Sequence[str], description: str = "", parameters: dict[str, Parameter] | None = None,
              tool: str | None = None, input_rates: Mapping[str, float] | None = None,
              notes: Sequence[str] = ()) -> Mechanism:
        return Mechanism(name=self.name, model=self.model, parameters=dict(parameters or {}),
                         description=description, closures=list(self.closures), actuated=list(actuated),
                         tool_frame=tool or GROUND, reference_q=np.zeros(self.model.nq),
                         points=[n for n, (_, _, report) in self.points.items() if report], sketch=list(self.sketch),
                         notes=list(notes), measures=list(self.measures), input_rates=dict(input_rates or {}))


def _unit(axis: Sequence[float]) -> Vector:
    problem = axis_problem(axis)
    if problem:
        raise InputError(problem)
    a = np.asarray(axis, dtype=float)
    return a / np.linalg.norm(a)


def close_in_joint_space(mech: Mechanism, tolerance: float, max_iterations: int = 50, spec=None
                         ) -> tuple[Vector, dict[str, float]]:
    """The assembled configuration nearest to the drawing (q = 0): minimum-norm Newton steps on the non-actuated
    coordinates (:meth:`~mechatron.model.closures.ClosureSystem.close`); returns q and how far every point moved (m).

    Raises:
        InputError: if the loops do not close, or close only by moving a point farther than ``tolerance`` (m);
            naming the file of ``spec`` and its field ``points`` if given.
    """
    def error(message: str) -> InputError:
        return spec.error(message, "points") if spec is not None else InputError(f"{mech.name}: {message}")

    system = mech.closure_system()
    index = {n: mech.model.joints[mech.joint_id(n)].idx_q for n in mech.joint_names}
    free = [k for k in range(mech.nq) if k not in {index[a] for a in mech.actuated}]
    phi, _ = system.evaluate(np.zeros(mech.nq))
    worst = system.row_labels()[int(np.argmax(np.abs(phi)))] if phi.size else ""
    first = float(np.abs(phi).max(initial=0.0))
    q, residual = system.close(np.zeros(mech.nq), free, 1e-13, max_iterations)
    if residual > 1e-9:
        raise error(f"the loops do not close near the drawing ({worst} is off by {first:.3g} m)")
    model, data = mech.model, mech.model.createData()
    pin.framesForwardKinematics(model, data, np.zeros(mech.nq))
    drawn = {n: data.oMf[model.getFrameId(n)].translation.copy() for n in mech.points}
    pin.framesForwardKinematics(model, data, q)
    moves = {n: float(np.linalg.norm(data.oMf[model.getFrameId(n)].translation - drawn[n])) for n in drawn}
    far = max(moves.items(), key=lambda item: item[1], default=("", 0.0))
    if far[1] > tolerance:
        raise error(f"the loops do not close within {tolerance * 1e3:.4g} mm: closing {worst} (off by "
                    f"{first * 1e3:.4g} mm in the drawing) moves {far[0]} by {far[1] * 1e3:.4g} mm")
    return q, moves


# ------------------------------------------------------------------------------------------------ from a file
def inertia_matrix(values) -> Vector:
    """The 3×3 tensor (kg·m²) of a spatial body's ``inertia``: (Ixx, Iyy, Izz) or (Ixx, Iyy, Izz, Ixy, Ixz, Iyz)."""
    values = np.atleast_1d(np.asarray(values, dtype=float))
    if values.shape == (3,):
        return np.diag(values)
    if values.shape != (6,):
        raise InputError("a spatial inertia is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg·m²)")
    xx, yy, zz, xy, xz, yz = values
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def check_spatial(spec) -> None:
    """The checks of a spatial spec (``planar = false``), each an :class:`InputError` naming the file and the field:
    every revolute joint's ``axis`` not zero (``joints[i].axis``), every universal joint's two ``axes`` neither zero
    nor parallel (``joints[i].axes``), every body's given ``inertia`` a rigid body's (``bodies[i].inertia``:
    symmetric, positive definite, its principal moments obeying I1 + I2 ≥ I3,
    :func:`~mechatron.model.dh.inertial_problem`; products of inertia may be negative), then the structural checks
    of :func:`~mechatron.model.linkage.check`."""
    from .linkage import check

    for i, j in enumerate(spec.joints, start=1):
        problem = axes_problem(j.axes) if j.kind == "universal" and j.axes is not None else \
            axis_problem(j.axis) if j.kind == "revolute" and j.axis is not None else None
        if problem:
            key = "axes" if j.kind == "universal" else "axis"
            raise spec.error(f"joint of {j.body}: {problem}", f"joints[{i}].{key}")
    for i, b in enumerate(spec.bodies, start=1):
        if b.inertia is not None:
            _check_inertia(spec, b, f"bodies[{i}].inertia")
    check(spec)


def _check_inertia(spec, body, field: str) -> None:
    """A body's given inertia is a rigid body's (with its mass, when that is not negative: a negative mass is the
    structural check's to name)."""
    try:
        tensor = inertia_matrix(body.inertia)
    except InputError as exc:
        raise spec.error(f"body {body.name}: {exc.message}", field) from None
    problem = inertial_problem(body.mass, tensor) if body.mass >= 0 else None
    if problem:
        raise spec.error(f"body {body.name}: {problem}", field)


def _inertia_tensor(body, positions: Mapping[str, Vector]) -> tuple[Vector | None, Vector]:
    """(centre, 3×3 inertia about it) of a spatial body: a bar between its first two points, or the given centre
    and inertia ((Ixx, Iyy, Izz) or (Ixx, Iyy, Izz, Ixy, Ixz, Iyz), world axes, kg·m²)."""
    if isinstance(body.com, str):
        centre = positions[body.com]
    elif body.com is not None:
        centre = np.asarray(body.com, dtype=float)
    elif body.shape == "bar":
        centre = (positions[body.points[0]] + positions[body.points[1]]) / 2
    else:
        centre = None
    if body.inertia is None:
        tensor = bar_inertia(body.mass, positions[body.points[0]], positions[body.points[1]]) \
            if body.shape == "bar" else np.zeros((3, 3))
    else:
        tensor = inertia_matrix(body.inertia)
    return centre, tensor


def build_spatial(spec, *, check_tolerance: bool = True) -> Mechanism:
    """The :class:`~mechatron.model.Mechanism` of a spatial mechanism file (``planar = false``): the tree drawn with
    :class:`SpatialBuilder`, the loops closed by point constraints and, in joint space, to the assembled position
    nearest the drawing (:func:`close_in_joint_space`); parameters are the drawn points' ``_x``, ``_y``, ``_z``.

    Raises:
        InputError: for an unsupported closure (only pins join loops in space), an unknown joint type, a loop that
            does not close within the tolerance (default 2 % of the drawing's size), or inputs that do not match
            the mobility.
    """
    from .linkage import drawing_size, drive_placements, frame_names, joint_coordinate, joint_parent
    from .shapes import with_derived

    check_spatial(spec)
    positions = {name: np.asarray(xyz, dtype=float) for name, xyz in with_derived(spec, spec.drawing()).items()}
    frames = frame_names(spec)
    b = SpatialBuilder(spec.name, gravity=spec.gravity)
    bodies = {x.name: x for x in spec.bodies}

    def add_points(body: str) -> None:
        for p in bodies[body].points:
            name = frames[(p, body)]
            b.point(name, body, positions[p], report=spec.point(p).report and name == p)

    add_points(GROUND)
    pending = [j for j in spec.joints]
    placed = {GROUND}
    while pending:
        ready = [j for j in pending if joint_parent(spec, j) in placed][:1]
        if not ready:
            raise spec.error(f"bodies {', '.join(sorted(j.body for j in pending))} are not connected to the ground "
                             "by the tree joints", "joints")
        j = ready[0]
        parent = joint_parent(spec, j)
        body = bodies[j.body]
        centre, tensor = _inertia_tensor(body, positions)
        at = frames[(j.at, parent)]
        if j.kind == "revolute":
            if j.axis is None:
                raise spec.error(f"joint of {j.body}: a spatial revolute joint needs its axis", "joints")
            b.revolute(j.body, at, j.axis, coordinate=joint_coordinate(j), limits=j.limits, mass=body.mass,
                       com=centre, inertia=tensor)
        elif j.kind == "universal":
            if j.axes is None or len(j.axes) != 2:
                raise spec.error(f"joint of {j.body}: a universal joint needs two axes", "joints")
            b.universal(j.body, at, j.axes, mass=body.mass, com=centre, inertia=tensor)
        elif j.kind == "translation":
            b.translation(j.body, at, mass=body.mass, com=centre, inertia=tensor)
        else:
            raise spec.error(f"joint of {j.body}: a spatial mechanism takes revolute, universal and translation "
                             f"joints, not {j.kind}", "joints")
        placed.add(j.body)
        add_points(j.body)
        pending.remove(j)
    missing = sorted(set(bodies) - placed)
    if missing:
        raise spec.error(f"bodies {', '.join(missing)} have no joint: they are not connected to the tree", "bodies")
    for c in spec.closures:
        if c.kind != "pin":
            raise spec.error(f"a spatial mechanism closes its loops with pins (point constraints), not {c.kind}",
                             "closures")
        owners = list(c.bodies) or spec.owners(c.point)
        if len(owners) != 2:
            raise spec.error(f"pin {c.point}: name the two bodies it joins", "closures")
        b.pin(frames[(c.point, owners[0])], frames[(c.point, owners[1])])
    for body in spec.bodies:
        draw = body.draw if body.draw is not None else body.points
        if len(draw) >= 2:
            b.line(body.name, *(frames.get((p, body.name), p) for p in draw),
                   kind="ground" if body.name == GROUND else body.draw_kind)
    for m in spec.measures:
        b.measures.append(Measure(m.name, m.kind, tuple(m.points), m.minimum))
    parameters = {}
    for p in spec.points:
        if p.at is not None:
            for axis, value in zip("xyz", positions[p.name]):
                parameters[f"{p.name}_{axis}"] = Parameter(f"{p.name}_{axis}", float(value), "length",
                                                           f"{axis} of point {p.name} in the drawing")
    mech = b.build(actuated=list(spec.actuated), description=spec.description, parameters=parameters,
                   tool=spec.tool or spec.points[-1].name, input_rates=spec.input_rates, notes=spec.notes)
    unknown = [a for a in spec.actuated if a not in mech.joint_names]
    if unknown:
        raise spec.error(f"actuated coordinate {unknown[0]!r} is not a joint coordinate", "actuated")
    tolerance = spec.tolerance if spec.tolerance is not None else 0.02 * drawing_size(spec)
    q, moves = close_in_joint_space(mech, tolerance if check_tolerance else np.inf, spec=spec)
    mech.reference_q = q
    mech.branches["reference"] = q
    shifted = {n: d for n, d in moves.items() if d > 1e-9}
    if shifted:
        mech.notes.append("the drawing was closed by moving " + ", ".join(
            f"{n} by {d * 1e3:.3g} mm" for n, d in sorted(shifted.items(), key=lambda item: -item[1])))
    mobility = mech.mobility()
    if mobility != len(spec.actuated):
        raise spec.error(f"{len(spec.actuated)} actuated input(s) ({', '.join(spec.actuated)}) for a mechanism of "
                         f"mobility {mobility}", "actuated")
    mech.source = spec.file or spec.source or None

    def rebuild(values: Mapping[str, float]) -> Mechanism:
        moved = {p.name: np.array([values.get(f"{p.name}_{a}", v) for a, v in zip("xyz", positions[p.name])])
                 for p in spec.points if p.at is not None}
        return build_spatial(spec.with_positions(moved), check_tolerance=False)

    mech.rebuild = rebuild
    mech.derivatives = lambda names: spatial_derivatives(spec, mech, names)
    mech.drives.update(drive_placements(spec))
    return mech


def _model_joints(spec, j) -> list[str]:
    """The coordinates of the Pinocchio joints a spatial tree joint becomes, parent to child."""
    from .linkage import joint_coordinate

    if j.kind == "universal":
        return [f"{j.body}_angle1", f"{j.body}_angle2"]
    if j.kind == "translation":
        return [f"{j.body}_x", f"{j.body}_y", f"{j.body}_z"]
    return [joint_coordinate(j)]


def spatial_derivatives(spec, mech: Mechanism, names: tuple[str, ...]) -> PlacementDerivatives:
    """The exact derivatives of a spatial mechanism's placements and inertias with respect to its point coordinates
    ``names``: every frame sits at P − O_b (its point P less its body's origin O_b, the point of the body's joint),
    every joint at O_b − O_parent (the first Pinocchio joint of a universal or translation joint; the others at its
    origin), every body's centre at C − O_b with its tensor (a bar's m/12 (|d|² 1 − d dᵀ), d its first two points'
    difference), the frames' axes the world's: CasADi differentiates these on symbols for the coordinates, and a
    translation's derivative is the twist [dt; 0]."""
    import casadi as ca

    from .linkage import frame_names, joint_parent
    from .shapes import sub, with_derived

    values = mech.parameter_values()
    symbols = ca.SX.sym("l", len(names))
    variable = {name: symbols[k] for k, name in enumerate(names)}
    drawing = {p.name: tuple(variable.get(f"{p.name}_{a}", values.get(f"{p.name}_{a}", float(v)))
                             for a, v in zip("xyz", p.at)) for p in spec.points if p.between is None}
    positions = with_derived(spec, drawing)
    frames = frame_names(spec)
    model = mech.model
    origin = {GROUND: (0.0, 0.0, 0.0)}
    rows: list = []  # ("joint" or "frame", index, 3 expressions) or ("inertia", index, 10 expressions)
    for point in spec.body(GROUND).points:
        rows.append(("frame", model.getFrameId(frames[(point, GROUND)], pin.FrameType.OP_FRAME), positions[point]))
    for j in spec.joints:
        coordinates = _model_joints(spec, j)
        origin[j.body] = positions[j.at]
        rows.append(("joint", model.getJointId(coordinates[0]), sub(positions[j.at], origin[joint_parent(spec, j)])))
        body = spec.body(j.body)
        for point in body.points:
            rows.append(("frame", model.getFrameId(frames[(point, j.body)], pin.FrameType.OP_FRAME),
                         sub(positions[point], origin[j.body])))
        if body.mass > 0:
            rows.append(("inertia", model.getJointId(coordinates[-1]), _dynamic_parameters(body, positions,
                                                                                          origin[j.body])))
    flat = ca.vertcat(*[ca.SX(e) for _, _, expressions in rows for e in expressions])
    evaluate = ca.Function("derivatives", [symbols], [ca.jacobian(flat, symbols)])
    jacobian = np.asarray(evaluate([values[n] for n in names]), dtype=float)
    out = empty(model, names)
    at = 0
    for kind, index, expressions in rows:
        d = jacobian[at:at + len(expressions)]
        if kind == "inertia":
            out.inertias[:, index] = d.T
        else:
            (out.joints if kind == "joint" else out.frames)[:, index, :3] = d.T
        at += len(expressions)
    return out


def _dynamic_parameters(body, positions, origin) -> list:
    """Pinocchio's dynamic parameters [m, m c, I_O] (about the joint origin O) of a spatial body: its centre C (a
    point, given coordinates, a bar's middle, else O) and tensor I_C (given, or a bar's), I_O = I_C + m (|c|² 1 −
    c cᵀ) with c = C − O. Works on numbers and CasADi expressions."""
    from .shapes import add, dot, scaled, sub

    m = body.mass
    if isinstance(body.com, str):
        centre = positions[body.com]
    elif body.com is not None:
        centre = tuple(float(v) for v in body.com)
    elif body.shape == "bar":
        centre = scaled(add(positions[body.points[0]], positions[body.points[1]]), 0.5)
    else:
        centre = origin
    c = sub(centre, origin)
    if body.inertia is not None:
        tensor = inertia_matrix(body.inertia).tolist()
    elif body.shape == "bar":
        d = sub(positions[body.points[1]], positions[body.points[0]])
        tensor = [[m / 12 * ((dot(d, d) if i == k else 0.0) - d[i] * d[k]) for k in range(3)] for i in range(3)]
    else:
        tensor = [[0.0] * 3 for _ in range(3)]
    about = [[tensor[i][k] + m * ((dot(c, c) if i == k else 0.0) - c[i] * c[k]) for k in range(3)] for i in range(3)]
    return [m, m * c[0], m * c[1], m * c[2], about[0][0], about[0][1], about[1][1], about[0][2], about[1][2],
            about[2][2]]


def build_mechanism(spec, *, check_tolerance: bool = True) -> Mechanism:
    """The mechanism of a mechanism file's spec, planar (:func:`~mechatron.model.linkage.build_linkage`) or spatial
    (:func:`build_spatial`)."""
    from .linkage import build_linkage

    if spec.planar:
        return build_linkage(spec, check_tolerance=check_tolerance)
    return build_spatial(spec, check_tolerance=check_tolerance)

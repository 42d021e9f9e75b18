r"""Closed-loop planar mechanisms described as data: :func:`build_linkage` turns a
:class:`~mechatron.model.linkage_spec.LinkageSpec` (what a mechanism file holds) into a
:class:`~mechatron.model.Mechanism`.

A linkage is described the way it is drawn: the world coordinates (x, y, m) of its named points (pins) in one
assembled position, the bodies and the points each carries (a point carried by two bodies is a pin between them),
the joints of a spanning tree (revolute at a pin, prismatic along a direction, hydraulic cylinders between two pins)
and the closures of the loops (pins, sliders on a line, a point on a curve given as a table, gears). Named lengths
(the distance between two points of one body) are the geometric parameters; a length given a value is
authoritative, and the drawing is corrected to it.

**Bodies held by their frames.** Every point a body carries is fixed in the body at its drawn place
(:mod:`mechatron.model.shapes`): points in line on a bar are as determined as any others, a declared length moves the
later of its two points along the line from the earlier, and a derived point follows the two points of its body it
lies between. The Pinocchio tree is built on these shapes.

**Closing the drawing.** A drawing read off paper rarely closes exactly. With the actuated inputs held at their drawn
values, the other joint coordinates take minimum-norm Gauss–Newton steps from the drawing, q_f ← q_f − J_f⁺ Φ(q),
on the closure equations Φ(q) = 0 with their exact Jacobian J (Pinocchio's frame Jacobians; its cost grows with the
bodies and closures, not with the points). Each point's move is reported; beyond the file's tolerance the loader
refuses, naming the constraint of the drawing that is furthest off (a declared length against its drawn length, a
slider or curve point off its line or curve).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from .closures import Gear, Slider
from .derivatives import PlacementDerivatives, empty, frame_id, planar_dynamic_parameters, planar_twists
from .dh import Drive
from .linkage_spec import (  # noqa: F401  (the spec's names are this module's too)
    GROUND,
    MEASURE_POINTS,
    BodySpec,
    ClosureSpec,
    DriveSpec,
    JointSpec,
    LengthSpec,
    LinkageSpec,
    MeasureSpec,
    PointSpec,
    check,
    curve_functions,
    curve_spline,
    drawing_size,
    frame_names,
    joint_coordinate,
    joint_parent,
)
from .mechanism import Measure, Mechanism, Parameter
from .planar import PlanarBuilder
from .shapes import Layout, circle_sides, in_joint_frame, layout, plate_properties, shapes, turned  # noqa: F401

Vector = NDArray[np.float64]


def drive_placements(spec: LinkageSpec) -> dict[str, Drive]:
    """The :class:`~mechatron.model.dh.Drive` of every coordinate with a ``[[drives]]`` table: its placement is the
    frame of the point ``at`` on its body (:func:`frame_names`)."""
    frames = frame_names(spec)
    return {d.coordinate: Drive(placement=frames[(d.at, d.body or spec.owners(d.at)[0])]) for d in spec.drives}


# ------------------------------------------------------------------------------------------------ the tree
@dataclass
class Assembly:
    """A mechanism built on the shapes of a spec: the mechanism (reference configuration: the drawing's joint
    coordinates), its layout, and the values the actuated inputs are held at when the loops are closed."""

    mech: Mechanism
    layout: Layout
    inputs: dict[int, float]
    shape: dict[tuple[str, str], tuple[float, float]]


def _tree(spec: LinkageSpec) -> Assembly:
    """The Pinocchio tree, closures, sketch and measures of ``spec`` on its body shapes, not yet closed."""
    drawing = _drawing(spec)
    declared = {length.name: length.value for length in spec.lengths if length.value is not None}
    shape = shapes(spec, drawing, declared)
    lay = layout(spec, shape, drawing)
    b = PlanarBuilder(spec.name, gravity=spec.gravity)
    frames_of: dict[str, list] = {GROUND: [], **{j.body: [] for j in lay.joints}}
    for f in lay.frames:
        frames_of[f.body].append(f)
    for f in frames_of[GROUND]:
        b.frame(f)
    for j in lay.joints:  # each body's joint, then its points
        b.joint(j)
        for f in frames_of[j.body]:
            b.frame(f)
    names = frame_names(spec)
    lengths = {j.coordinate: j.reference for j in lay.joints}
    for i, joint in enumerate(spec.joints, start=1):
        if joint.kind == "cylinder":
            stroke = joint.stroke
            if joint.name not in spec.held_inputs and not stroke[0] - 1e-9 <= lengths[joint.name] <= stroke[1] + 1e-9:
                raise spec.error(f"cylinder {joint.name}: its eye {joint.eye} is {lengths[joint.name] * 1e3:.6g} mm "
                                 f"from its base {joint.base} in the drawing, outside its stroke "
                                 f"[{stroke[0] * 1e3:.6g}, {stroke[1] * 1e3:.6g}] mm", f"joints[{i}].stroke")
            b.cylinder_closure(joint.name, names[(joint.base, spec.owners(joint.base)[0])],
                               names[(joint.eye, spec.owners(joint.eye)[0])], stroke, joint.count)
    _closures(spec, b, names, lay)
    _sketch_and_measures(spec, b, names)
    mech = b.build(actuated=list(spec.actuated), description=spec.description, tool=spec.tool or spec.points[-1].name,
                   input_rates=dict(spec.input_rates), check=False)
    assert mech.reference_q is not None  # the builder's drawing
    inputs = {}
    for name in spec.actuated:
        if not mech.model.existJointName(name):
            known = ", ".join(mech.joint_names)
            raise spec.error(f"actuated coordinate {name!r} is not a joint coordinate or a cylinder (known: {known})",
                             "actuated")
        k = mech.model.joints[mech.joint_id(name)].idx_q
        inputs[k] = float(spec.held_inputs.get(name, mech.reference_q[k]))
    return Assembly(mech, lay, inputs, shape)


def _drawing(spec: LinkageSpec) -> dict[str, tuple[float, float]]:
    """The drawn points' positions (m) as number pairs."""
    return {name: (float(x), float(y)) for name, (x, y) in spec.drawing().items()}


def _sketch_and_measures(spec: LinkageSpec, b: PlanarBuilder, frames: Mapping[tuple[str, str], str]) -> None:
    """The polyline of every body (``draw``, else its points) and the measures to watch."""
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


def _closures(spec: LinkageSpec, b: PlanarBuilder, frames: Mapping[tuple[str, str], str], lay: Layout) -> None:
    """The closures of ``spec``: pins, sliders (a locked slider keeps the drawing's relative angle of its two
    frames), curves and gears (default offset: the drawing's q_driven − ratio·q_driver)."""
    angles = {f.name: lay.bodies[f.body].angle + f.angle for f in lay.frames}  # world angles in the drawing
    for i, c in enumerate(spec.closures, start=1):
        where = f"closures[{i}]"
        if c.kind == "pin":
            bodies = list(c.bodies) or spec.owners(c.point)
            if len(bodies) != 2:
                raise spec.error(f"pin {c.point}: carried by {len(bodies)} bodies ({', '.join(bodies)}); name the two "
                                 "it joins", f"{where}.bodies")
            for body in bodies:
                if (c.point, body) not in frames:
                    raise spec.error(f"pin {c.point}: not a point of body {body}", f"{where}.bodies")
            b.pin(frames[(c.point, bodies[0])], frames[(c.point, bodies[1])])
        elif c.kind == "slider":
            body = c.body or spec.owners(c.point)[0]
            line_body = c.line_body or spec.owners(c.line)[0]
            if spec.point(c.line).direction is None:
                raise spec.error(f"slider of {c.point}: the line point {c.line} needs a direction", f"{where}.line")
            point, line = frames[(c.point, body)], frames[(c.line, line_body)]
            b.slider(point, line, lock_angle=c.lock_angle, angle_offset=angles[point] - angles[line])
        elif c.kind == "curve":
            body = c.body or spec.owners(c.point)[0]
            f, df, d2f = curve_functions(c)
            b.on_curve(frames[(c.point, body)], f, df, d2f, label=c.label or f"the curve of {c.point}",
                       spline=curve_spline(c))
        elif c.kind == "gear":
            offset = c.offset
            if offset is None:
                reference = {j.coordinate: j.reference for j in lay.joints}
                offset = reference[_coordinate_of(spec, c.driven)] - c.ratio * reference[_coordinate_of(spec, c.driver)]
            b.gear(c.driver, c.driven, c.ratio, float(offset))
        else:
            raise spec.error(f"unknown closure type {c.kind!r}; expected pin, slider, curve or gear", where)


def _coordinate_of(spec: LinkageSpec, body: str) -> str:
    for j in spec.joints:
        if j.kind != "cylinder" and j.body == body:
            return joint_coordinate(j)
    raise spec.error(f"gear of body {body!r}, which has no joint", "closures")


# ------------------------------------------------------------------------------------ closing the drawing
def inconsistencies(spec: LinkageSpec) -> list[tuple[str, float, str]]:
    """What in the drawing itself does not fit: (label, how far off, unit "m" or "rad") for every declared length
    against its drawn length, every slider point off its line, every curve point off its curve, and every actuated
    input held away from its drawn value (a rebuild's)."""
    drawing = spec.drawing()
    for p in spec.points:
        if p.between is not None:
            a, b = (drawing[n] for n in p.between)
            drawing[p.name] = a + p.fraction * (b - a)
    out = []
    for length in spec.lengths:
        if length.value is not None:
            first, last = length.points
            drawn = float(np.linalg.norm(drawing[last] - drawing[first]))
            out.append((f"length {length.name} = |{first}{last}|", abs(drawn - length.value), "m"))
    for c in spec.closures:
        if c.kind == "slider" and spec.point(c.line).direction is not None:
            d = np.asarray(spec.point(c.line).direction, dtype=float)
            normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
            out.append((f"slider {c.point} on {c.line}", abs(float(normal @ (drawing[c.point] - drawing[c.line]))),
                        "m"))
        elif c.kind == "curve":
            x, y = drawing[c.point]
            out.append((f"{c.point} on its curve", abs(float(y - curve_functions(c)[0](x))), "m"))
    return out


def _worst(found: list[tuple[str, float, str]]) -> tuple[str, float, str] | None:
    """The inconsistency furthest off (lengths in m against angles in rad, as numbers)."""
    return max(found, key=lambda item: item[1], default=None)


def _text(value: float, unit: str) -> str:
    return f"{value:.3g} rad" if unit == "rad" else f"{value * 1e3:.3g} mm"


def _close(spec: LinkageSpec, assembly: Assembly) -> Vector:
    """The assembled configuration nearest the drawing, the inputs held (module docstring).

    Raises:
        InputError: naming the drawing's worst inconsistency (or the closure left open) if the loops do not close
            near the drawing, or naming the mobility if the inputs do not match it.
    """
    mech = assembly.mech
    assert mech.reference_q is not None  # an assembly's mechanism has its drawing's configuration
    q = np.array(mech.reference_q, dtype=float)
    for k, value in assembly.inputs.items():
        q[k] = value
    if not mech.closures:
        return q
    scale = max(1.0, drawing_size(spec))
    free = [k for k in range(mech.nq) if k not in assembly.inputs]
    system = mech.closure_system()
    q, residual = system.close(q, free, 1e-13 * scale)
    if residual > 1e-9 * scale:
        _check_mobility(spec, mech, mech.reference_q)
        held = [(f"input {name}", abs(assembly.inputs[mech.model.joints[mech.joint_id(name)].idx_q]
                                      - mech.reference_q[mech.model.joints[mech.joint_id(name)].idx_q]),
                 "rad" if mech.joint_kind(name) == "revolute" else "m") for name in spec.actuated]
        worst = _worst([item for item in inconsistencies(spec) + held if item[1] > 0])
        if worst is None:
            labels = system.row_labels()
            phi, _ = system.evaluate(q)
            k = int(np.argmax(np.abs(phi)))
            worst = (labels[k], abs(float(phi[k])), "m")
        raise spec.error(f"the drawing cannot be closed: {worst[0]} is off by {_text(worst[1], worst[2])} (the "
                         "lengths, guides and curves do not fit together near the drawing)", "points")
    return q


def _check_mobility(spec: LinkageSpec, mech: Mechanism, q: Vector) -> None:
    mobility = mech.mobility(q)
    if mobility != len(spec.actuated):
        listed = f" ({', '.join(spec.actuated)})" if spec.actuated else ""
        raise spec.error(f"{len(spec.actuated)} actuated input(s){listed} for a mechanism of mobility {mobility}: give "
                         f"{mobility}", "actuated")


def _world(mech: Mechanism, q: Vector) -> pin.Data:
    data = mech.model.createData()
    pin.framesForwardKinematics(mech.model, data, q)
    return data


def _moves(spec: LinkageSpec, assembly: Assembly, q: Vector) -> dict[str, float]:
    """How far each drawn point moved from the drawing to ``q`` (m); a point carried by several bodies as far as the
    farthest of its frames. Derived points follow theirs."""
    mech = assembly.mech
    data = _world(mech, q)
    names = frame_names(spec)
    drawing = spec.drawing()
    moves = {}
    for point, drawn in drawing.items():
        frames = [data.oMf[mech.frame_id(names[(point, body)])].translation[:2] for body in spec.owners(point)]
        moves[point] = max(float(np.linalg.norm(f - drawn)) for f in frames)
    return moves


# ------------------------------------------------------------------------------------------------ building
def build_linkage(spec: LinkageSpec, *, check_tolerance: bool = True) -> Mechanism:
    """The :class:`~mechatron.model.Mechanism` of a linkage spec: the tree built on the bodies' shapes, the drawing
    closed with the inputs held (module docstring), parameters (every named length and every drawn point's ``_x``,
    ``_y``) that rebuild it, named branches assembled.

    Raises:
        InputError: for a structural problem, a drawing that does not close within the tolerance (default 2 % of the
            drawing's size), or actuated inputs that do not match the mobility.
    """
    if not spec.planar:
        raise spec.error("a spatial mechanism (planar = false): build it with mechatron.model.spatial.build_spatial "
                         "or build_mechanism", "planar")
    check(spec)
    assembly = _tree(spec)
    mech = assembly.mech
    q = _close(spec, assembly)
    moves = _moves(spec, assembly, q)
    tolerance = spec.tolerance if spec.tolerance is not None else 0.02 * drawing_size(spec)
    far = max(moves.items(), key=lambda item: item[1], default=("", 0.0))
    if check_tolerance and far[1] > tolerance:
        worst = _worst(inconsistencies(spec)) or ("the loops", 0.0, "m")
        raise spec.error(f"the loops do not close within {tolerance * 1e3:.4g} mm: closing {worst[0]} (off by "
                         f"{_text(worst[1], worst[2])} in the drawing) moves {far[0]} by {far[1] * 1e3:.4g} mm",
                         "points")
    _check_mobility(spec, mech, q)
    mech.reference_q = q
    mech.branches["reference"] = q
    mech.parameters = parameters(spec, assembly.shape)
    held = replace(spec, held_inputs={name: float(q[k]) for name, k in zip(spec.actuated, assembly.inputs)})
    mech.rebuild = lambda values: rebuild(held, values)
    mech.derivatives = lambda names: linkage_derivatives(held, mech, names)
    notes = list(spec.notes)
    shifted = {n: d for n, d in moves.items() if d > 1e-9}
    if shifted:
        notes.append("the drawing was closed by moving " + ", ".join(
            f"{n} by {d * 1e3:.3g} mm" for n, d in sorted(shifted.items(), key=lambda item: -item[1])))
    mech.notes = notes
    mech.source = spec.file or spec.source or None
    mech.branches.update(_branches(spec, mech))
    mech.drives.update(drive_placements(spec))
    return mech


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
        q, _ = system.close(q, [k for k in free if k not in given], 1e-13, max_iterations=20)
        q, residual = system.close(q, free, 1e-13)
        if residual > 1e-9:
            raise spec.error(f"branch {branch}: the loops do not close near the given coordinates",
                             f"branches.{branch}")
        out[branch] = q
    return out


# ------------------------------------------------------------------------------------------------ parameters
def parameters(spec: LinkageSpec, shape: Mapping[tuple[str, str], tuple[float, float]]) -> dict[str, Parameter]:
    """Every named length (m: its declared value, or its length in the shape of a body carrying both points) and the
    x, y of every drawn point as drawn (m)."""
    out = {}
    for length in spec.lengths:
        a, b = length.points
        value = length.value
        if value is None:
            body = next(name for name in spec.owners(a) if (b, name) in shape)
            value = math.dist(shape[(a, body)], shape[(b, body)])
        out[length.name] = Parameter(length.name, float(value), "length", f"length |{a}{b}|")
    for point, drawn in spec.drawing().items():
        for axis, value in zip("xy", drawn):
            name = f"{point}_{axis}"
            if name not in out:
                out[name] = Parameter(name, float(value), "length", f"{axis} of point {point} in the drawing")
    return out


def parameter_spec(spec: LinkageSpec, values: Mapping[str, float]) -> LinkageSpec:
    """``spec`` with other values of its parameters: every named length declared at its value (``values``, else as
    before), the point coordinates moving the drawn points."""
    lengths = {length.name for length in spec.lengths}
    declared = {length.name: length.value for length in spec.lengths if length.value is not None}
    current = parameters(spec, shapes(spec, _drawing(spec), declared))
    moved = spec.drawing()
    for name, value in values.items():
        if name in lengths or name not in current:
            continue
        point, _, axis = name.rpartition("_")
        moved[point] = moved[point].copy()
        moved[point]["xy".index(axis)] = float(value)
    every = tuple(replace(length, value=float(values.get(length.name, current[length.name].value)))
                  for length in spec.lengths)
    return replace(spec.with_positions(moved), lengths=every)


def rebuild(spec: LinkageSpec, values: Mapping[str, float]) -> Mechanism:
    """The linkage with other values of its parameters (:func:`parameter_spec`), its loops closed again with the
    inputs held where ``spec`` holds them (without the tolerance: the change is asked for)."""
    return build_linkage(parameter_spec(spec, values), check_tolerance=False)


# ------------------------------------------------------------------------------------------------ derivatives
def linkage_derivatives(spec: LinkageSpec, mech: Mechanism, names: tuple[str, ...]) -> PlacementDerivatives:
    """The exact derivatives of the placements, inertias and closure constants of the linkage ``mech`` (built from
    ``spec``) with respect to the parameters ``names``: the shapes and layout of :mod:`mechatron.model.shapes`
    written on CasADi symbols for the parameters (every named length declared, as in a rebuild), differentiated by
    CasADi and evaluated at the parameters' values; then each planar placement's (x, y, θ) derivative turned into a
    local twist (:func:`~mechatron.model.derivatives.planar_twists`)."""
    import casadi as ca

    values = mech.parameter_values()
    lengths = {length.name for length in spec.lengths}
    symbols = ca.SX.sym("l", len(names))
    variable = {name: symbols[k] for k, name in enumerate(names)}

    def value(name: str, drawn: float):
        return variable.get(name, values.get(name, drawn)) if name not in lengths else drawn

    drawing = {p.name: (value(f"{p.name}_x", p.at[0]), value(f"{p.name}_y", p.at[1]))
               for p in spec.points if p.at is not None and p.between is None}
    declared = {length.name: variable.get(length.name, values[length.name]) for length in spec.lengths}
    sides = circle_sides(spec, _drawing(spec), {length.name: values[length.name] for length in spec.lengths})
    lay = layout(spec, shapes(spec, drawing, declared, ca, sides), drawing, ca)
    offsets = {GROUND: 0.0, **{j.body: -j.angle for j in lay.joints}}
    model = mech.model
    rows: list = []  # (kind, index, expressions)
    for k, j in enumerate(lay.joints, start=1):
        rows.append(("joint", k, in_joint_frame(j.xy, j.angle, offsets[j.parent], ca)))
        rows.append(("frame", frame_id(model, j.body, pin.FrameType.BODY), (0.0, 0.0, offsets[j.body])))
        centre = turned(j.com, offsets[j.body], ca)
        rows.append(("inertia", k, planar_dynamic_parameters(j.mass, centre[0], centre[1], j.inertia)))
    for f in lay.frames:
        rows.append(("frame", frame_id(model, f.name, pin.FrameType.OP_FRAME),
                     in_joint_frame(f.xy, f.angle, offsets[f.body], ca)))
    angles = {f.name: lay.bodies[f.body].angle + f.angle for f in lay.frames}
    reference = {j.body: j.reference for j in lay.joints}
    given = {(c.driver, c.driven): c.offset for c in spec.closures if c.kind == "gear"}
    for closure in mech.closures:
        if isinstance(closure, Slider) and closure.lock_angle:
            rows.append(("angle_offset", closure.name, (angles[closure.point] - angles[closure.line],)))
        elif isinstance(closure, Gear) and given.get((closure.a, closure.b)) is None:
            rows.append(("offset", closure.name, (reference[closure.b] - closure.ratio * reference[closure.a],)))
    flat = ca.vertcat(*[ca.SX(e) for _, _, expressions in rows for e in expressions])
    evaluate = ca.Function("derivatives", [symbols], [flat, ca.jacobian(flat, symbols)])
    nominal, jacobian = (np.asarray(x, dtype=float) for x in evaluate([values[n] for n in names]))
    nominal = nominal.ravel()
    out = empty(model, names)
    constants: dict[str, dict[str, np.ndarray]] = {}
    at = 0
    for kind, index, expressions in rows:
        d = jacobian[at:at + len(expressions)]
        if kind in ("joint", "frame"):
            target = out.joints if kind == "joint" else out.frames
            target[:, index] = planar_twists(nominal[at + 2], d[0], d[1], d[2])
        elif kind == "inertia":
            out.inertias[:, index] = d.T
        else:
            constants.setdefault(index, {})[kind] = d[0].copy()
        at += len(expressions)
    return replace(out, constants=constants)

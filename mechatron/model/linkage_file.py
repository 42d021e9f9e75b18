"""Mechanism files: closed-loop mechanisms as TOML, planar or (``planar = false``) spatial (the format is in
docs/mechanism_file.md).

:func:`read_linkage_file` reads and checks a file into a :class:`~mechatron.model.linkage.LinkageSpec`;
:func:`linkage_toml` writes a spec back as a file (what the syntheses of :mod:`mechatron.machines` do);
:func:`is_linkage_file` tells a mechanism file from the other TOML formats by its content. Every problem raises an
:class:`~mechatron.errors.InputError` naming the file and the field (``joints[2].at``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..io.schema import REQUIRED, FieldReader
from ..io.toml import read_toml
from .linkage import (
    BodySpec,
    ClosureSpec,
    DriveSpec,
    JointSpec,
    LengthSpec,
    LinkageSpec,
    MeasureSpec,
    PointSpec,
    check,
    joint_coordinate,
)
from .spatial import check_spatial, coordinate_names

JOINT_TYPES = ("revolute", "prismatic", "cylinder", "universal", "translation")
CLOSURE_TYPES = ("pin", "slider", "curve", "gear")
MEASURE_TYPES = ("transmission_angle", "lever_arm", "distance")


def is_linkage_file(data: Mapping[str, Any]) -> bool:
    """Whether parsed TOML is a mechanism file (it has ``points`` and ``[[bodies]]``)."""
    return ("points" in data or "points_mm" in data) and "bodies" in data


def read_linkage_file(path: str | Path) -> LinkageSpec:
    """Read and check a mechanism file (SI units in the spec; ``_mm`` and ``_deg`` fields converted)."""
    path = Path(path)
    return linkage_spec(read_toml(path), file=path, default_name=path.stem)


def linkage_spec(data: Mapping[str, Any], *, file: str | Path | None = None, default_name: str = "linkage"
                 ) -> LinkageSpec:
    """A spec from parsed TOML (see :func:`read_linkage_file`)."""
    top = FieldReader(data, file=file)
    name, description, source = top.header(default_name)
    planar = top.boolean("planar", True)
    dim = 2 if planar else 3
    gravity = top.number("gravity", 9.81, minimum=0.0)
    tolerance = top.length("tolerance", None, positive=True)
    tool = top.string("tool", None)
    actuated = _strings(top, "actuated")
    rates = top.table("input_rates", None)
    input_rates = {}
    if rates is not None:
        for key in list(rates.data):
            input_rates[key] = rates.number(key, positive=True)
        rates.finish()
    notes = tuple(_strings(top, "notes", required=False))
    points = _points(top, dim)
    bodies = tuple(_body(b, dim) for b in top.tables("bodies"))
    joints = tuple(_joint(j, planar) for j in top.tables("joints"))
    closures = tuple(_closure(c) for c in top.tables("closures")) if top.has("closures") else ()
    measures = tuple(_measure(m) for m in top.tables("measures")) if top.has("measures") else ()
    lengths = _lengths(top)
    branches = _branches(top)
    drives = tuple(_drive(d) for d in top.tables("drives")) if top.has("drives") else ()
    top.finish()
    spec = LinkageSpec(name=name, points=points, bodies=bodies, joints=joints, actuated=tuple(actuated),
                       closures=closures, measures=measures, lengths=lengths, branches=branches,
                       description=description, source=source, gravity=gravity, tool=tool, input_rates=input_rates,
                       notes=notes, tolerance=tolerance, file=str(file) if file is not None else None, planar=planar,
                       drives=drives)
    if tool is not None and tool not in {p.name for p in points}:
        raise InputError(f"unknown point {tool!r}", file=file, field="tool")
    _check_inputs(spec)
    (check if planar else check_spatial)(spec)
    return spec


def coordinates(spec: LinkageSpec) -> list[str]:
    """The names of the coordinates of a spec's joints, in file order: a planar joint's (a cylinder's is its name,
    :func:`~mechatron.model.linkage.joint_coordinate`), a spatial joint's one to three
    (:func:`~mechatron.model.spatial.coordinate_names`)."""
    if spec.planar:
        return [joint_coordinate(j) for j in spec.joints]
    return [name for j in spec.joints for name in coordinate_names(j.kind, j.body, j.coordinate)]


def _check_inputs(spec: LinkageSpec) -> None:
    """Every ``actuated`` name is a coordinate of the joints (or a cylinder), once; every key of ``input_rates`` is
    an actuated coordinate (when some are listed: with none, building names ``actuated`` for the mobility)."""
    known = coordinates(spec)
    for name in spec.actuated:
        if name not in known:
            raise spec.error(f"{name!r} is not a joint coordinate or a cylinder (the coordinates: {', '.join(known)})",
                             "actuated")
        if spec.actuated.count(name) > 1:
            raise spec.error(f"{name!r} is listed twice", "actuated")
    for name in spec.input_rates:
        if spec.actuated and name not in spec.actuated:
            raise spec.error(f"{name!r} is not an actuated coordinate (those are: {', '.join(spec.actuated)})",
                             f"input_rates.{name}")


def _strings(reader: FieldReader, key: str, required: bool = True) -> list[str]:
    value = reader.raw(key, REQUIRED if required else None)
    if value is None:
        return []
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise reader.error(key, "expected a list of names")
    return list(value)


def _points(top: FieldReader, dim: int) -> tuple[PointSpec, ...]:
    out = []
    for key, scale in (("points", 1.0), ("points_mm", 1e-3)):
        table = top.table(key, None)
        if table is None:
            continue
        for name in list(table.data):
            value = table.raw(name)
            where = table.field(name)
            if isinstance(value, list):
                out.append(PointSpec(name, _pair(table, name, value, scale, dim), table=key))
                continue
            if not isinstance(value, Mapping):
                raise InputError(f"expected [{', '.join('xyz'[:dim])}] or a table {{at = [...], …}}", file=top.file,
                                 field=where)
            item = FieldReader(value, file=top.file, path=where)
            given = item.lengths("at", dim, None)  # at in the table's unit; at_mm, at_cm, … in theirs
            at = None if given is None else tuple(float(v) * (scale if item.has("at") else 1.0) for v in given)
            between = item.raw("between", None)
            if between is not None and (not isinstance(between, list) or len(between) != 2
                                        or not all(isinstance(v, str) for v in between)):
                raise item.error("between", "expected two point names")
            if (at is None) == (between is None):
                raise item.error("at", "give the point's position (at) or two points it lies between, one of them")
            point = PointSpec(name, at, tuple(between) if between else None, item.number("fraction", 0.5),
                              _direction(item), item.boolean("report", True), table=key)
            item.finish()
            out.append(point)
        table.finish()
    if not out:
        raise top.error("points", "missing required field (the named points of the drawing)")
    return tuple(out)


def _pair(table: FieldReader, name: str, value: list, scale: float, dim: int = 2) -> tuple[float, ...]:
    if len(value) != dim:
        raise table.error(name, f"expected [{', '.join('xyz'[:dim])}], got {len(value)} numbers")
    return tuple(table.to_float(f"{name}[{i}]", v) * scale for i, v in enumerate(value))


def _body(reader: FieldReader, dim: int = 2) -> BodySpec:
    name = reader.string("name")
    points = tuple(_strings(reader, "points"))
    mass = reader.number("mass", 0.0)
    com_raw = reader.raw("com", None) if reader.has("com") else None
    com: Any = None
    if isinstance(com_raw, str):
        com = com_raw
    elif reader.has("com") or reader.has("com_mm"):
        com = tuple(float(v) for v in reader.lengths("com", dim))
    if dim == 3 and isinstance(reader.data.get("inertia"), list):
        values = reader.raw("inertia")
        if len(values) not in (3, 6):
            raise reader.error("inertia", "a spatial inertia is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] "
                                          "(kg·m²)")
        inertia: float | tuple[float, ...] | None = tuple(reader.to_float(f"inertia[{i}]", v)
                                                          for i, v in enumerate(values))
    else:
        inertia = reader.number("inertia", None)
    shape = reader.string("shape", None)
    draw = reader.raw("draw", None)
    if draw is not None and (not isinstance(draw, list) or not all(isinstance(v, str) for v in draw)):
        raise reader.error("draw", "expected a list of point names")
    kind = reader.string("draw_as", "link", choices=("link", "slider", "ground", "cylinder"))
    reader.finish()
    return BodySpec(name, points, mass, com, inertia, shape, tuple(draw) if draw is not None else None, kind)


def _joint(reader: FieldReader, planar: bool = True) -> JointSpec:
    kind = reader.string("type", choices=JOINT_TYPES)
    if kind in ("universal", "translation") and planar:
        raise reader.error("type", f"a {kind} joint is spatial: set planar = false")
    if not planar and kind in ("prismatic", "cylinder"):
        raise reader.error("type", f"a spatial mechanism takes revolute, universal and translation joints, not {kind}")
    if not planar:
        revolute = kind == "revolute"  # universal and translation joints name their coordinates, without limits
        joint = JointSpec(kind, body=reader.string("body"), at=reader.string("at"),
                          parent=reader.string("parent", None),
                          coordinate=reader.string("coordinate", None) if revolute else None,
                          limits=(float(reader.angle("lower", -math.inf)), float(reader.angle("upper", math.inf)))
                          if revolute else (-math.inf, math.inf),
                          axis=tuple(float(v) for v in reader.vector("axis", 3)) if revolute else None,
                          axes=_axes(reader) if kind == "universal" else None)
        reader.finish()
        return joint
    if kind == "cylinder":
        stroke = reader.lengths("stroke", 2)
        count = reader.number("count", 1.0)
        if count != int(count) or count < 1:
            raise reader.error("count", f"the number of cylinders side by side must be a whole number >= 1, "
                                        f"got {count:g}")
        joint = JointSpec("cylinder", name=reader.string("name"), base=reader.string("base"),
                          eye=reader.string("eye"), stroke=(float(stroke[0]), float(stroke[1])), count=int(count),
                          barrel_mass=reader.number("barrel_mass", 0.0, minimum=0.0),
                          rod_mass=reader.number("rod_mass", 0.0, minimum=0.0))
        reader.finish()
        return joint
    body = reader.string("body")
    limit = reader.angle if kind == "revolute" else reader.length
    limits = (limit("lower", -math.inf), limit("upper", math.inf))
    direction = _direction(reader, "the guide's direction [dx, dy] in the drawing") if kind == "prismatic" else None
    joint = JointSpec(kind, body=body, at=reader.string("at"), parent=reader.string("parent", None),
                      coordinate=reader.string("coordinate", None),
                      toward=reader.string("toward", None) if kind == "revolute" else None,
                      angle=reader.angle("angle", None) if kind == "revolute" else None,
                      direction=direction, limits=(float(limits[0]), float(limits[1])))
    if joint.toward is not None and joint.angle is not None:
        raise reader.error("angle", "give toward or angle, not both")
    reader.finish()
    return joint


def _direction(reader: FieldReader, required: str | None = None) -> tuple[float, float] | None:
    """The field ``direction``: 2 numbers, not both zero (no unit); ``None`` when left out, unless ``required``
    (what the direction is) makes it a required field."""
    value = reader.vector("direction", 2, None)
    if value is None:
        if required:
            raise reader.error("direction", f"missing required field ({required})")
        return None
    if not math.hypot(*value) > 0:
        raise reader.error("direction", f"a direction must not be zero, got [{value[0]:g}, {value[1]:g}]")
    return (float(value[0]), float(value[1]))


def _axes(reader: FieldReader) -> tuple[tuple[float, ...], ...]:
    value = reader.raw("axes")
    if not isinstance(value, list) or len(value) != 2 or not all(isinstance(a, list) and len(a) == 3 for a in value):
        raise reader.error("axes", "expected two axes [[x, y, z], [x, y, z]]: the parent's, then the cross's")
    return tuple(tuple(reader.to_float(f"axes[{i}][{k}]", v) for k, v in enumerate(a)) for i, a in enumerate(value))


def _closure(reader: FieldReader) -> ClosureSpec:
    kind = reader.string("type", choices=CLOSURE_TYPES)
    if kind == "pin":
        out = ClosureSpec("pin", point=reader.string("point"), bodies=tuple(_strings(reader, "bodies", False)))
        if out.bodies and len(out.bodies) != 2:
            raise reader.error("bodies", "a pin joins two bodies")
    elif kind == "slider":
        out = ClosureSpec("slider", point=reader.string("point"), body=reader.string("body", None),
                          line=reader.string("line"), line_body=reader.string("line_body", None),
                          lock_angle=reader.boolean("lock_angle", False))
    elif kind == "curve":
        x, y = _table_values(reader, "x"), _table_values(reader, "y")
        out = ClosureSpec("curve", point=reader.string("point"), body=reader.string("body", None), x=x, y=y,
                          label=reader.string("label", ""))
    else:
        out = ClosureSpec("gear", driver=reader.string("driver"), driven=reader.string("driven"),
                          ratio=reader.number("ratio", nonzero=True), offset=reader.angle("offset", None))
    reader.finish()
    return out


def _table_values(reader: FieldReader, key: str) -> tuple[float, ...]:
    actual = key + "_mm" if reader.has(key + "_mm") else key
    value = reader.raw(actual)
    if not isinstance(value, list) or len(value) < 4:
        raise reader.error(actual, "expected a list of at least 4 numbers")
    scale = 1e-3 if actual.endswith("_mm") else 1.0
    return tuple(reader.to_float(f"{actual}[{i}]", v) * scale for i, v in enumerate(value))


def _measure(reader: FieldReader) -> MeasureSpec:
    kind = reader.string("type", choices=MEASURE_TYPES)
    minimum = (reader.angle if kind == "transmission_angle" else reader.length)("min", None)
    out = MeasureSpec(kind, reader.string("name"), tuple(_strings(reader, "points")),
                      float(minimum) if minimum is not None else None)
    reader.finish()
    return out


def _drive(reader: FieldReader) -> DriveSpec:
    out = DriveSpec(reader.string("coordinate"), reader.string("at"), reader.string("body", None))
    reader.finish()
    return out


def _lengths(top: FieldReader) -> tuple[LengthSpec, ...]:
    table = top.table("lengths", None)
    if table is None:
        return ()
    out = []
    for name in list(table.data):
        value = table.raw(name)
        where = table.field(name)
        if isinstance(value, list):
            points, length = value, None
        elif isinstance(value, Mapping):
            item = FieldReader(value, file=top.file, path=where)
            points = item.raw("points")
            length = item.length("value", None, positive=True)
            item.finish()
        else:
            raise InputError("expected [point, point] or {points = [...], value = ...}", file=top.file, field=where)
        if not isinstance(points, list) or len(points) != 2 or not all(isinstance(p, str) for p in points):
            raise InputError("expected two point names", file=top.file, field=where)
        out.append(LengthSpec(name, (points[0], points[1]), float(length) if length is not None else None))
    table.finish()
    return tuple(out)


def _branches(top: FieldReader) -> dict[str, dict[str, float]]:
    table = top.table("branches", None)
    if table is None:
        return {}
    out = {}
    for name in list(table.data):
        item = table.table(name)
        values = {}
        for key in list(item.data):
            if key.endswith("_deg"):
                values[key[:-4]] = item.angle(key[:-4])
            elif key.endswith("_mm"):
                values[key[:-3]] = item.length(key[:-3])
            else:
                values[key] = item.number(key)
        item.finish()
        out[name] = values
    table.finish()
    return out


# ------------------------------------------------------------------------------------------------ writing
def _number(x: float) -> str:
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    text = repr(float(x))
    return text


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return _number(value) if isinstance(value, float) else str(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + " }"
    return "[" + ", ".join(_value(v) for v in value) + "]"


def _key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() else _value(key)


def linkage_toml(spec: LinkageSpec, header: str = "") -> str:
    """The mechanism file of ``spec`` (SI units, full precision), readable by :func:`read_linkage_file`."""
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    top: dict[str, Any] = {"name": spec.name}
    if spec.description:
        top["description"] = spec.description
    if spec.source:
        top["source"] = spec.source
    if not spec.planar:
        top["planar"] = False
    top["gravity"] = float(spec.gravity)
    if spec.tolerance is not None:
        top["tolerance"] = float(spec.tolerance)
    if spec.tool:
        top["tool"] = spec.tool
    top["actuated"] = list(spec.actuated)
    if spec.input_rates:
        top["input_rates"] = {k: float(v) for k, v in spec.input_rates.items()}
    if spec.notes:
        top["notes"] = list(spec.notes)
    lines += [f"{_key(k)} = {_value(v)}" for k, v in top.items()]
    lines += ["", "[points]  # one assembled position, world x, y (m)" if spec.planar else
              "[points]  # one assembled position, world x, y, z (m)"]
    for p in spec.points:
        if p.between is None and p.direction is None and p.report:
            assert p.at is not None  # a drawn point
            lines.append(f"{_key(p.name)} = {_value([float(v) for v in p.at])}")
            continue
        item: dict[str, Any] = {}
        if p.at is not None:
            item["at"] = [float(v) for v in p.at]
        else:
            assert p.between is not None  # a derived point
            item["between"] = list(p.between)
            item["fraction"] = float(p.fraction)
        if p.direction is not None:
            item["direction"] = [float(v) for v in p.direction]
        if not p.report:
            item["report"] = False
        lines.append(f"{_key(p.name)} = {_value(item)}")
    for body in spec.bodies:
        item = {"name": body.name, "points": list(body.points)}
        if body.mass:
            item["mass"] = float(body.mass)
        if body.com is not None:
            item["com"] = body.com if isinstance(body.com, str) else [float(v) for v in body.com]
        if body.inertia is not None:
            item["inertia"] = float(body.inertia) if isinstance(body.inertia, (int, float)) else \
                [float(v) for v in body.inertia]
        if body.shape:
            item["shape"] = body.shape
        if body.draw is not None:
            item["draw"] = list(body.draw)
        if body.draw_kind != "link":
            item["draw_as"] = body.draw_kind
        lines += ["", "[[bodies]]", *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    for j in spec.joints:
        if j.kind == "cylinder":
            item = {"type": "cylinder", "name": j.name, "base": j.base, "eye": j.eye,
                    "stroke": [float(v) for v in j.stroke]}
            if j.count != 1:
                item["count"] = j.count
            if j.barrel_mass:
                item["barrel_mass"] = float(j.barrel_mass)
            if j.rod_mass:
                item["rod_mass"] = float(j.rod_mass)
        else:
            item = {"type": j.kind, "body": j.body, "at": j.at}
            for key in ("parent", "coordinate", "toward"):
                if getattr(j, key) is not None:
                    item[key] = getattr(j, key)
            if j.angle is not None:
                item["angle"] = float(j.angle)
            if j.direction is not None:
                item["direction"] = [float(v) for v in j.direction]
            if j.axis is not None:
                item["axis"] = [float(v) for v in j.axis]
            if j.axes is not None:
                item["axes"] = [[float(v) for v in a] for a in j.axes]
            if math.isfinite(j.limits[0]):
                item["lower"] = float(j.limits[0])
            if math.isfinite(j.limits[1]):
                item["upper"] = float(j.limits[1])
        lines += ["", "[[joints]]", *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    for c in spec.closures:
        item = {"type": c.kind}
        if c.kind == "pin":
            item["point"] = c.point
            if c.bodies:
                item["bodies"] = list(c.bodies)
        elif c.kind == "slider":
            item.update(point=c.point, line=c.line)
            for key in ("body", "line_body"):
                if getattr(c, key) is not None:
                    item[key] = getattr(c, key)
            if c.lock_angle:
                item["lock_angle"] = True
        elif c.kind == "curve":
            item["point"] = c.point
            if c.body is not None:
                item["body"] = c.body
            if c.label:
                item["label"] = c.label
            item["x"], item["y"] = [float(v) for v in c.x], [float(v) for v in c.y]
        else:
            item.update(driver=c.driver, driven=c.driven, ratio=float(c.ratio))
            if c.offset is not None:
                item["offset"] = float(c.offset)
        lines += ["", "[[closures]]", *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    for m in spec.measures:
        item = {"type": m.kind, "name": m.name, "points": list(m.points)}
        if m.minimum is not None:
            item["min"] = float(m.minimum)
        lines += ["", "[[measures]]", *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    for d in spec.drives:
        item = {"coordinate": d.coordinate, "at": d.at, **({"body": d.body} if d.body is not None else {})}
        lines += ["", "[[drives]]", *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    if spec.lengths:
        lines += ["", "[lengths]  # named lengths (m): the geometric parameters"]
        for length in spec.lengths:
            value: Any = list(length.points) if length.value is None else \
                {"points": list(length.points), "value": float(length.value)}
            lines.append(f"{_key(length.name)} = {_value(value)}")
    for name, values in spec.branches.items():
        lines += ["", f"[branches.{_key(name)}]  # approximate joint coordinates (rad, m) of another assembly"]
        lines += [f"{_key(k)} = {_value(float(v))}" for k, v in values.items()]
    return "\n".join(lines) + "\n"


def write_linkage_file(spec: LinkageSpec, path: str | Path, header: str = "") -> Path:
    """Write :func:`linkage_toml` to ``path``, whole or not at all."""
    from ..io.output import write_text

    return write_text(path, linkage_toml(spec, header))

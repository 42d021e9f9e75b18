"""URDF in and out.

:func:`load_urdf` makes a :class:`~mechatron.model.Mechanism` of a URDF file (joint origins become named geometric
parameters ``{joint}_x``, ``{joint}_y``, ``{joint}_z``; rotor data come from a sibling ``.srdf`` file's
``<rotor_params>``; whether the link masses include the drives from a ``<mechatron
link_masses_include_drives="true"/>`` element of the URDF, :func:`masses_include_drives`). :func:`export_urdf`
writes any mechanism made of one-axis joints (revolute, continuous and prismatic) as URDF, plus an SRDF with the
drives' rotor inertia and gear ratio (Pinocchio's ``loadRotorParameters`` turns them back into
``armature = J_rotor·u²``), so that the files loaded by Pinocchio give the same frames, mass matrix and RNEA torques.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import sys
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..errors import InputError
from ..io.values import LARGEST
from .derivatives import PlacementDerivatives, empty
from .dh import Drive
from .mechanism import Mechanism, Parameter, find_frame
from .robotfile import GEAR_RATIO_RANGE

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
_AXIS_NAMES = ("x", "y", "z")


# ------------------------------------------------------------------------------------------------------ loading
@contextlib.contextmanager
def _captured_native_stderr() -> Iterator[list[str]]:
    """Keep what C++ libraries (urdfdom) print on file descriptor 2 out of the terminal; yield it as lines."""
    lines: list[str] = []
    try:
        fd = sys.stderr.fileno()
    except (AttributeError, OSError, ValueError):
        yield lines
        return
    sys.stderr.flush()
    saved = os.dup(fd)
    with tempfile.TemporaryFile(mode="w+b") as sink:
        os.dup2(sink.fileno(), fd)
        try:
            yield lines
        finally:
            os.dup2(saved, fd)
            os.close(saved)
            sink.seek(0)
            lines.extend(line.strip() for line in sink.read().decode(errors="replace").splitlines() if line.strip())


def _attribute(path: Path, where: str, element, attribute: str, default: str | None = None, *, size: int = 1,
               unit: str = "", minimum: float | None = None, largest: float = LARGEST) -> list[float]:
    """The ``size`` numbers of ``attribute`` of ``element`` (``default`` if absent): finite, of magnitude <= LARGEST and
    ``>= minimum``, else an error naming the file, the link or joint (``where``) and the attribute."""
    field = f"{element.tag} {attribute}"
    text = element.get(attribute, default)
    if text is None:
        raise InputError("missing attribute", file=path, row=where, field=field)
    words = text.split()
    need = (f"{size} finite numbers" if size > 1 else "a finite number") + \
        (f" >= {minimum:g}" if minimum is not None else "") + (f" {unit}" if unit else "")
    try:
        values = [float(w) for w in words]
    except ValueError:
        values = []
    if len(values) != size or not all(math.isfinite(v) and abs(v) <= largest for v in values) or \
            (minimum is not None and any(v < minimum for v in values)):
        bound = f" of magnitude <= {largest:g}" if any(math.isfinite(v) and abs(v) > largest for v in values) else ""
        raise InputError(f"must be {need}{bound}, got {text!r}", file=path, row=where, field=field)
    return values


def _check_origin(path: Path, where: str, parent) -> None:
    origin = parent.find("origin")
    if origin is not None:
        _attribute(path, where, origin, "xyz", "0 0 0", size=3, unit="m")
        _attribute(path, where, origin, "rpy", "0 0 0", size=3, unit="rad")


def _inertia_problem(inertia: np.ndarray, physical: bool) -> str | None:
    """Why a URDF inertia tensor is no body's, or ``None``: a principal moment below zero (beyond rounding) or, with
    ``physical``, principal moments breaking the triangle inequality I1 + I2 >= I3."""
    moments = np.linalg.eigvalsh(inertia)
    rounding = 1e-9 * float(np.abs(moments).max())
    if moments[0] < -rounding:
        return f"inertia tensor must be positive semidefinite (principal moments {moments.round(9).tolist()} kg·m²)"
    if physical and moments[0] + moments[1] < moments[2] * (1 - 1e-9) - rounding:
        return (f"principal moments {moments.round(9).tolist()} kg·m² violate the triangle inequality I1 + I2 >= I3 "
                "(no rigid body has them)")
    return None


def check_urdf(path: str | Path, *, physical: bool = False) -> None:
    """Check that the URDF ``path`` holds numbers a body can have (masses, inertias, origins, limits; with
    ``physical`` the triangle inequality of the principal moments too): the checks of :func:`_checked_root`, whose
    parsed tree it drops; else :class:`InputError` naming the file, the link or joint and the attribute."""
    _checked_root(path, physical=physical)


#: The attribute values of ``<mechatron link_masses_include_drives="…"/>`` (XML Schema booleans).
_BOOLEANS = {"true": True, "1": True, "false": False, "0": False}


def masses_include_drives(path: str | Path, root=None) -> bool:
    """Whether the URDF ``path`` says its link masses include the drives: a child ``<mechatron
    link_masses_include_drives="true"/>`` of ``<robot>`` (an element of mechatron's, which URDF readers skip as they
    do ``<gazebo>``); ``false`` without one. ``root``: the file's parsed ``<robot>``, when already read. A second
    such element, another attribute or a value other than true, false, 1 or 0 is an :class:`InputError` naming the
    file and the attribute."""
    path = Path(path)
    root = _checked_root(path) if root is None else root
    elements = root.findall("mechatron")
    if not elements:
        return False
    if len(elements) > 1:
        raise InputError("give one <mechatron> element, not several", file=path, field="mechatron")
    attributes = dict(elements[0].attrib)
    text = attributes.pop("link_masses_include_drives", "false").strip().lower()
    if attributes:
        raise InputError(f"unknown attribute {next(iter(attributes))!r} (known: link_masses_include_drives)",
                         file=path, field="mechatron")
    if text not in _BOOLEANS:
        raise InputError(f"must be true or false, got {elements[0].get('link_masses_include_drives')!r}", file=path,
                         field="mechatron link_masses_include_drives")
    return _BOOLEANS[text]


def _checked_root(path: str | Path, *, physical: bool = False):
    """The physical checks a robot file has, on a URDF: every link's mass (>= 0 kg) and inertia (symmetric, positive
    semidefinite; with ``physical`` its principal moments obeying the triangle inequality too — off by default, as
    URDF has no field to switch it off and published files, and mechatron's export of an arm with
    ``physical_inertia = false``, break it), every origin, and every joint's limits
    (finite, lower <= upper, effort and velocity >= 0) are numbers a body can have; else :class:`InputError` naming
    the file, the link or joint and the attribute. Returns the parsed ``<robot>`` element."""
    import xml.etree.ElementTree as ET

    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise InputError(f"not valid XML: {exc}", file=path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", file=path) from None
    if root.tag != "robot":
        raise InputError(f"not a URDF: the top element is <{root.tag}>, not <robot>", file=path)
    for link in root.iter("link"):
        where = f"link {link.get('name', '?')!r}"
        for visual in [*link.iter("visual"), *link.iter("collision")]:
            _check_origin(path, where, visual)
        inertial = link.find("inertial")
        if inertial is None:
            continue
        _check_origin(path, where, inertial)
        mass_element = inertial.find("mass")
        if mass_element is not None:
            _attribute(path, where, mass_element, "value", unit="kg", minimum=0.0)
        tensor = inertial.find("inertia")
        inertia = np.zeros((3, 3))
        if tensor is not None:
            ixx, ixy, ixz, iyy, iyz, izz = (_attribute(path, where, tensor, k, "0", unit="kg·m²")[0]
                                            for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
            inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        problem = _inertia_problem(inertia, physical)
        if problem is not None:
            raise InputError(problem, file=path, row=where, field="inertia")
    for joint in root.iter("joint"):
        where = f"joint {joint.get('name', '?')!r}"
        _check_origin(path, where, joint)
        axis = joint.find("axis")
        if axis is not None:
            _attribute(path, where, axis, "xyz", "1 0 0", size=3)
        limit = joint.find("limit")
        if limit is None:
            continue
        kind = joint.get("type", "")
        unit = "m" if kind == "prismatic" else "rad"
        # limits: any finite value (1e16 stands for "none" in some published files)
        lower = _attribute(path, where, limit, "lower", "0", unit=unit, largest=math.inf)[0]
        upper = _attribute(path, where, limit, "upper", "0", unit=unit, largest=math.inf)[0]
        for name in ("effort", "velocity"):
            _attribute(path, where, limit, name, "0", minimum=0.0, largest=math.inf)
        if kind in ("revolute", "prismatic") and lower > upper:
            raise InputError(f"lower limit {lower:g} {unit} is above upper limit {upper:g} {unit}", file=path,
                             row=where, field="limit lower")
    return root


def _build(path: Path, locked_joints: Sequence[str]) -> pin.Model:
    try:
        with _captured_native_stderr() as native:
            model = pin.buildModelFromUrdf(str(path))
    except (RuntimeError, ValueError) as exc:
        detail = next((line for line in native if "Error" in line), str(exc).strip().splitlines()[0])
        raise InputError(f"cannot read URDF: {detail}", file=path) from None
    if locked_joints:
        ids = []
        for name in locked_joints:
            if not model.existJointName(name):
                raise InputError(f"no joint {name!r} to lock", file=path)
            ids.append(model.getJointId(name))
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    srdf = path.with_suffix(".srdf")
    if srdf.is_file() and "rotor_params" in srdf.read_text(errors="replace"):
        _check_rotor_numbers(srdf)
        try:
            pin.loadRotorParameters(model, str(srdf), False)
        except (RuntimeError, ValueError) as exc:
            raise InputError(f"cannot read rotor parameters: {exc}", file=srdf) from None
        _check_rotor_parameters(model, srdf)
    return model


def _check_rotor_numbers(srdf: Path) -> None:
    """Every ``mass`` and ``gear_ratio`` attribute of the SRDF's ``<rotor_params>`` joints is a finite number (what
    Pinocchio's reader reports without naming the joint); else an error naming the SRDF, the joint and the
    attribute. A file that is not XML is left to Pinocchio's reader."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(srdf).getroot()
    except ET.ParseError:
        return
    for joint in root.iter("joint"):
        for attribute in ("mass", "gear_ratio"):
            text = joint.get(attribute)
            if text is None:
                continue
            try:
                finite = math.isfinite(float(text))
            except ValueError:
                finite = False
            if not finite:
                raise InputError(f"expected a finite number, got {text!r}", file=srdf,
                                 field=f"rotor_params.{joint.get('name')}.{attribute}")


def _check_rotor_parameters(model: pin.Model, srdf: Path) -> None:
    """Every joint's rotor inertia ``mass`` (kg·m²) ≥ 0 and at most :data:`~mechatron.io.values.LARGEST`, its
    ``gear_ratio`` u with |u| within mechatron's plausible range (:data:`~mechatron.model.robotfile.GEAR_RATIO_RANGE`,
    as a robot file's); else an error naming the SRDF, the joint and the attribute."""
    low, high = GEAR_RATIO_RANGE
    for j in range(1, model.njoints):
        if model.joints[j].nv != 1:
            continue
        i, field = model.joints[j].idx_v, f"rotor_params.{model.names[j]}"
        inertia, ratio = float(model.rotorInertia[i]), float(model.rotorGearRatio[i])
        if not 0 <= inertia <= LARGEST:
            raise InputError(f"the rotor inertia (attribute 'mass', kg m^2) must be >= 0 and <= {LARGEST:g}, got "
                             f"{inertia:g}", file=srdf, field=f"{field}.mass")
        if not low <= abs(ratio) <= high:
            raise InputError(f"|gear ratio| must be between {low:g} and {high:g} (mechatron's plausible range), got "
                             f"{ratio:g}", file=srdf, field=f"{field}.gear_ratio")


def _origin_parameters(model: pin.Model) -> dict[str, Parameter]:
    """Every non-zero component of every joint origin as a length parameter ``{joint}_{x|y|z}``."""
    out: dict[str, Parameter] = {}
    for joint_id in range(1, model.njoints):
        name = model.names[joint_id]
        for k, axis in enumerate(_AXIS_NAMES):
            value = float(model.jointPlacements[joint_id].translation[k])
            if value != 0.0:
                out[f"{name}_{axis}"] = Parameter(f"{name}_{axis}", value, "length",
                                                  f"{axis} of the origin of joint {name} in its parent joint frame")
    return out


def _apply_origin_parameters(model: pin.Model, values: dict[str, float]) -> None:
    for joint_id in range(1, model.njoints):
        placement = model.jointPlacements[joint_id]
        translation = placement.translation.copy()
        for k, axis in enumerate(_AXIS_NAMES):
            key = f"{model.names[joint_id]}_{axis}"
            if key in values:
                translation[k] = values[key]
        placement.translation = translation
        model.jointPlacements[joint_id] = placement


def _add_tool_frame(model: pin.Model, tool: str | None, path: Path) -> None:
    """Add a frame ``tool``: a copy of frame ``tool`` if given, else the last body frame on the last joint."""
    if find_frame(model, "tool") is not None:
        return
    if tool is not None:
        parent_frame = find_frame(model, tool)
        if parent_frame is None:
            raise InputError(f"no frame {tool!r} to use as tool", file=path)
    else:
        last_joint = max(f.parentJoint for f in model.frames)
        bodies = [i for i, f in enumerate(model.frames)
                  if f.parentJoint == last_joint and f.type == pin.FrameType.BODY]
        parent_frame = bodies[-1] if bodies else find_frame(model, model.names[last_joint])
    source = model.frames[parent_frame]
    model.addFrame(pin.Frame("tool", source.parentJoint, parent_frame, source.placement, pin.FrameType.OP_FRAME))


def load_urdf(path: str | Path, name: str | None = None, *, tool: str | None = None,
              locked_joints: Sequence[str] = (), description: str = "",
              values: dict[str, float] | None = None, physical: bool = False,
              link_masses_include_drives: bool | None = None) -> Mechanism:
    """A :class:`Mechanism` of the URDF file ``path``.

    Every URDF joint kind Pinocchio reads is kept as it is: a ``continuous`` joint is Pinocchio's unbounded
    revolute joint, two configuration coordinates (cos θ, sin θ) and one velocity coordinate; give one coordinate per
    joint to :meth:`Mechanism.configuration <mechatron.model.Mechanism.configuration>` to get q.

    Args:
        path: URDF file. A file with the same stem and the suffix ``.srdf`` holding ``<rotor_params>`` sets the rotor
            inertia and gear ratio of the joints (armature = J_rotor·u²).
        name: Mechanism name (default: file stem).
        tool: Frame to copy as the frame ``tool`` (default: the last body frame on the last joint).
        locked_joints: Joints fixed at their neutral position (e.g. gripper fingers).
        description: One line for listings.
        values: Joint origin parameters to override (``{joint}_x``…, metres).
        physical: Check the triangle inequality of the links' principal moments too (:func:`check_urdf`; off by
            default: some published URDFs break it).
        link_masses_include_drives: Whether the links' masses include their drives, so that the sizing adds none
            (:attr:`Mechanism.link_masses_include_drives`); ``None``: what the file says
            (:func:`masses_include_drives`: its ``<mechatron link_masses_include_drives="true"/>``, else false).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError("is a directory, not a file" if path.is_dir() else "no such file", file=path)
    root = _checked_root(path, physical=physical)
    if link_masses_include_drives is None:
        link_masses_include_drives = masses_include_drives(path, root)
    model = _build(path, locked_joints)
    parameters = _origin_parameters(model)
    if values:
        _apply_origin_parameters(model, values)
        parameters = {k: Parameter(p.name, float(values.get(k, p.value)), p.kind, p.description)
                      for k, p in parameters.items()}
    _add_tool_frame(model, tool, path)
    name = name or path.stem
    model.name = name
    drives = {model.names[j]: Drive(float(model.rotorInertia[model.joints[j].idx_v]),
                                    float(model.rotorGearRatio[model.joints[j].idx_v]))
              for j in range(1, model.njoints)
              if model.joints[j].nv == 1 and model.rotorInertia[model.joints[j].idx_v] > 0}

    def rebuild(new_values: dict[str, float]) -> Mechanism:
        return load_urdf(path, name, tool=tool, locked_joints=locked_joints, description=description,
                         values=new_values, physical=physical, link_masses_include_drives=link_masses_include_drives)

    return Mechanism(name=name, model=model, parameters=parameters, description=description or f"URDF {path.name}",
                     source=str(path), drives=drives, rebuild=rebuild,
                     derivatives=lambda names: origin_derivatives(model, names),
                     link_masses_include_drives=bool(link_masses_include_drives))


def origin_derivatives(model: pin.Model, names: Sequence[str]) -> PlacementDerivatives:
    """The exact derivatives of the model's placements with respect to joint-origin parameters ``{joint}_{x|y|z}``:
    moving the origin of joint j along axis k of its parent frame is M_j exp(ξ h) with ξ = [R_jᵀ e_k; 0] (nothing
    else moves: the links' inertias and frames are in their joints' frames)."""
    out = empty(model, names)
    for n, name in enumerate(names):
        joint, _, axis = name.rpartition("_")
        j = model.getJointId(joint)
        out.joints[n, j, :3] = model.jointPlacements[j].rotation.T[:, _AXIS_NAMES.index(axis)]
    return out


# ------------------------------------------------------------------------------------------------------ export
def _num(x: float) -> str:
    x = float(x)
    if math.isinf(x):
        x = math.copysign(np.finfo(float).max, x)
    return repr(x)


def _vec(v: Sequence[float]) -> str:
    return " ".join(_num(x) for x in v)


def _origin(placement: pin.SE3) -> str:
    rpy = pin.rpy.matrixToRpy(placement.rotation)
    return f'<origin xyz="{_vec(placement.translation)}" rpy="{_vec(rpy)}"/>'


def _joint_axis(joint: pin.JointModel, name: str) -> tuple[str, tuple[float, ...]]:
    """URDF type and axis of a one-axis Pinocchio joint (a continuous joint: Pinocchio's unbounded revolute)."""
    short = joint.shortname()
    match = re.fullmatch(r"JointModel(R|P|RUB)(X|Y|Z)", short)
    if match:
        return {"R": "revolute", "P": "prismatic", "RUB": "continuous"}[match[1]], _AXES[match[2]]
    kinds = {"JointModelRevoluteUnaligned": "revolute", "JointModelPrismaticUnaligned": "prismatic",
             "JointModelRevoluteUnboundedUnaligned": "continuous"}
    if short in kinds:
        return kinds[short], tuple(float(a) for a in joint.extract().axis)
    raise InputError(f"joint {name} ({short}) cannot be written as URDF: only one-axis revolute, continuous and "
                     "prismatic joints are supported")


def _body_link_names(model: pin.Model) -> list[str]:
    """URDF link name of each joint's body: a BODY frame at the joint frame if there is one, else ``{joint}_body``."""
    names = ["world"]
    for joint_id in range(1, model.njoints):
        name = f"{model.names[joint_id]}_body"
        for frame in model.frames:
            if (frame.parentJoint == joint_id and frame.type == pin.FrameType.BODY
                    and frame.placement.isIdentity(1e-12)):
                name = frame.name
                break
        names.append(name)
    return names


def _inertial_xml(inertia: pin.Inertia) -> str:
    if inertia.mass == 0 and not np.any(inertia.inertia):
        return ""
    i = inertia.inertia
    return (f'<inertial><origin xyz="{_vec(inertia.lever)}" rpy="0 0 0"/><mass value="{_num(inertia.mass)}"/>'
            f'<inertia ixx="{_num(i[0, 0])}" ixy="{_num(i[0, 1])}" ixz="{_num(i[0, 2])}" iyy="{_num(i[1, 1])}" '
            f'iyz="{_num(i[1, 2])}" izz="{_num(i[2, 2])}"/></inertial>')


def to_urdf(mechanism: Mechanism) -> str:
    """The URDF text of ``mechanism`` (joints, bodies with their inertia, and its named frames as fixed links)."""
    from xml.sax.saxutils import quoteattr  # imported here: it imports urllib.request, http and ssl

    model = mechanism.model
    links = _body_link_names(model)
    lines = ['<?xml version="1.0"?>',
             f"<!-- written by mechatron from {mechanism.name}; gravity {_vec(model.gravity.linear)} m/s^2 -->",
             f"<robot name={quoteattr(mechanism.name)}>", '  <link name="world"/>']
    if mechanism.link_masses_include_drives:  # read back by masses_include_drives
        lines.insert(3, '  <mechatron link_masses_include_drives="true"/>')
    for joint_id in range(1, model.njoints):
        name = model.names[joint_id]
        kind, axis = _joint_axis(model.joints[joint_id], name)
        iq, iv = model.joints[joint_id].idx_q, model.joints[joint_id].idx_v
        # position limits per configuration coordinate (none for a continuous joint), effort and velocity per joint
        # coordinate
        position = ("" if kind == "continuous" else f'lower="{_num(model.lowerPositionLimit[iq])}" '
                    f'upper="{_num(model.upperPositionLimit[iq])}" ')
        lines.append(f"  <link name={quoteattr(links[joint_id])}>{_inertial_xml(model.inertias[joint_id])}</link>")
        parent = links[model.parents[joint_id]]
        lines.append(
            f"  <joint name={quoteattr(name)} type=\"{kind}\"><parent link={quoteattr(parent)}/>"
            f"<child link={quoteattr(links[joint_id])}/>{_origin(model.jointPlacements[joint_id])}"
            f'<axis xyz="{_vec(axis)}"/><limit {position}effort="{_num(model.effortLimit[iv])}" '
            f'velocity="{_num(model.velocityLimit[iv])}"/></joint>')
    skip = set(links) | {"universe"} | set(model.names)
    for frame in model.frames:
        if frame.name in skip or frame.type in (pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT):
            continue
        lines.append(f"  <link name={quoteattr(frame.name)}/>")
        lines.append(f"  <joint name={quoteattr(frame.name + '_fixed')} type=\"fixed\">"
                     f"<parent link={quoteattr(links[frame.parentJoint])}/><child link={quoteattr(frame.name)}/>"
                     f"{_origin(frame.placement)}</joint>")
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


#: The comment that opens every SRDF :func:`to_srdf` writes (how :func:`export_urdf` knows its own SRDF).
SRDF_MARK = ("rotor inertia (attribute 'mass', kg m^2) and gear ratio of each drive; "
             "pinocchio.loadRotorParameters sets armature = mass * gear_ratio^2")


def to_srdf(mechanism: Mechanism) -> str | None:
    """SRDF ``<rotor_params>`` reproducing the model's armature, or ``None`` if every armature is zero."""
    from xml.sax.saxutils import quoteattr

    model = mechanism.model
    entries = []
    for joint_id in range(1, model.njoints):
        iv = model.joints[joint_id].idx_v
        armature = float(model.armature[iv])
        if armature == 0.0:
            continue
        rotor, ratio = float(model.rotorInertia[iv]), float(model.rotorGearRatio[iv])
        if not math.isclose(rotor * ratio**2, armature, rel_tol=1e-12):
            rotor, ratio = armature, 1.0
        entries.append(f'    <joint name={quoteattr(model.names[joint_id])} mass="{_num(rotor)}" '
                       f'gear_ratio="{_num(ratio)}"/>')
    if not entries:
        return None
    return "\n".join(['<?xml version="1.0"?>',
                      f"<!-- {SRDF_MARK} -->",
                      f"<robot name={quoteattr(mechanism.name)}>", "  <rotor_params>", *entries, "  </rotor_params>",
                      "</robot>"]) + "\n"


def export_urdf(mechanism: Mechanism, path: str | Path) -> list[Path]:
    """Write ``mechanism`` as URDF to ``path`` (and its drives as ``path`` with suffix ``.srdf``), both whole and
    together (:func:`mechatron.io.output.transaction`); return the files. Without drives, an SRDF an earlier export
    wrote beside ``path`` (one holding mechatron's rotor data, :data:`SRDF_MARK`) is removed."""
    from ..io.output import output_name, stage_removal, transaction, write_text

    path = Path(path)
    companion = path.with_suffix(".srdf")
    if path.suffix.lower() == ".srdf" or Path(os.path.abspath(companion)) == Path(os.path.abspath(path)):
        raise InputError("the URDF would be written over its own SRDF; name it .urdf", file=output_name(path))
    srdf = to_srdf(mechanism)
    if srdf is not None and path.exists() and not path.is_file():
        raise InputError(f"{mechanism.name} has drives, whose SRDF goes beside the URDF: name a file, not a device",
                         file=output_name(path))
    with transaction():
        written = [write_text(path, to_urdf(mechanism))]
        if srdf is not None:
            written.append(write_text(companion, srdf))
        elif _written_by_mechatron(companion):
            stage_removal(companion)
    return written


def _written_by_mechatron(path: Path) -> bool:
    """Whether ``path`` is an SRDF of :func:`to_srdf` (its comment :data:`SRDF_MARK` in its first lines)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return SRDF_MARK in fh.read(1000)
    except OSError:
        return False

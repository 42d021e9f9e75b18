"""Writing robot files: the DH table of an arm as ``robots/NAME.toml`` text that reads back to the same model.

:func:`robot_toml` writes every field :func:`~mechatron.model.robotfile.read_robot_file` reads — the convention, the
gravity, the base and tool placements (``xyz`` in m, ``rpy`` in rad as URDF roll–pitch–yaw), and per row the joint,
its name, a, α, d, θ, the limits, the speed and effort limits, the mass, centre of mass and inertia, and the drive —
in SI units at full precision (``repr`` of each float), so that the file read back has the same parameters to the
last bit and the same forward kinematics. :func:`write_robot_file` writes it whole or not at all.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin

from .dh import DHLink, DHTable, Drive


def _number(x: float) -> str:
    return repr(float(x) + 0.0)  # + 0.0: no "-0.0"


def _string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ") + '"'


def _vector(values) -> str:
    return "[" + ", ".join(_number(v) for v in np.ravel(values)) + "]"


def _placement(key: str, matrix: np.ndarray) -> list[str]:
    """A ``[base]`` or ``[tool]`` table (xyz m, rpy rad), none for the identity."""
    matrix = np.asarray(matrix, dtype=float)
    if np.array_equal(matrix, np.eye(4)):
        return []
    rpy = pin.rpy.matrixToRpy(matrix[:3, :3])
    return ["", f"[{key}]", f"xyz = {_vector(matrix[:3, 3])}", f"rpy = {_vector(rpy)}"]


def _drive(drive: Drive) -> str:
    fields = [f"rotor_inertia = {_number(drive.rotor_inertia)}", f"gear_ratio = {_number(drive.gear_ratio)}",
              f"efficiency = {_number(drive.efficiency)}", f"viscous_friction = {_number(drive.viscous_friction)}",
              f"coulomb_friction = {_vector(drive.coulomb_friction)}", f"offset = {_vector(drive.offset)}"]
    if drive.placement is not None:
        fields.append(f"placement = {_string(drive.placement)}")
    return "drive = { " + ", ".join(fields) + " }"


def _link(link: DHLink) -> list[str]:
    inertia = link.inertial.inertia
    lines = ["", "[[links]]", f"joint = {_string(link.joint)}", f"name = {_string(link.name)}",
             f"a = {_number(link.a)}", f"alpha = {_number(link.alpha)}", f"d = {_number(link.d)}",
             f"theta = {_number(link.theta)}", f"lower = {_number(link.lower)}", f"upper = {_number(link.upper)}"]
    if math.isfinite(link.velocity_limit):
        lines.append(f"max_velocity = {_number(link.velocity_limit)}")
    if math.isfinite(link.effort_limit):
        lines.append(f"max_effort = {_number(link.effort_limit)}")
    lines += [f"mass = {_number(link.inertial.mass)}", f"com = {_vector(link.inertial.com)}",
              "inertia = { " + ", ".join(f"{k} = {_number(inertia[i, j])}" for k, (i, j) in
                                        (("xx", (0, 0)), ("yy", (1, 1)), ("zz", (2, 2)), ("xy", (0, 1)),
                                         ("xz", (0, 2)), ("yz", (1, 2)))) + " }"]
    if not link.inertial.physical:
        lines.append("physical_inertia = false")
    if link.drive is not None:
        lines.append(_drive(link.drive))
    return lines


def robot_toml(table: DHTable, name: str, *, description: str = "", source: str = "", header: str = "",
               link_masses_include_drives: bool = False) -> str:
    """The robot file of ``table`` (SI units, full precision), readable by
    :func:`~mechatron.model.robotfile.read_robot_file`; ``header`` becomes comment lines at the top."""
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    lines += [f"name = {_string(name)}", f"description = {_string(description)}", f"source = {_string(source)}",
              f"convention = {_string(table.convention)}", f"gravity = {_vector(table.gravity)}"]
    if link_masses_include_drives:
        lines.append("link_masses_include_drives = true")
    lines += _placement("base", table.base) + _placement("tool", table.tool)
    for link in table.links:
        lines += _link(link)
    return "\n".join(lines) + "\n"


def write_robot_file(table: DHTable, path: str | Path, *, name: str | None = None, description: str = "",
                     source: str = "", header: str = "", link_masses_include_drives: bool = False) -> Path:
    """Write :func:`robot_toml` to ``path`` (the name defaults to the file's stem), whole or not at all."""
    from ..io.output import write_text

    path = Path(path)
    return write_text(path, robot_toml(table, name or path.stem, description=description, source=source,
                                       header=header, link_masses_include_drives=link_masses_include_drives))

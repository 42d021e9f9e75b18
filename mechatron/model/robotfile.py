"""Robot files: ``robots/NAME.toml`` describing a DH arm (schema in ``robots/README.md``).

:func:`read_robot_file` parses and validates a file and returns the :class:`~mechatron.dh.DHTable` plus its metadata;
every problem raises :class:`~mechatron.errors.InputError` naming the file and the field (``links[3].mass``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.schema import REQUIRED, FieldReader
from ..io.toml import read_toml
from .dh import CONVENTIONS, JOINT_KINDS, DHLink, DHTable, Drive, Inertial, dh_mechanism, placement_matrix
from .mechanism import Mechanism


@dataclass(frozen=True)
class RobotFile:
    """A parsed robot file."""

    name: str
    description: str
    source: str
    table: DHTable
    path: Path
    #: ``link_masses_include_drives``: the links' masses include their drives (the sizing adds none).
    link_masses_include_drives: bool = False

    def mechanism(self) -> Mechanism:
        return dh_mechanism(self.table, self.name, description=self.description, source=str(self.path),
                            link_masses_include_drives=self.link_masses_include_drives)


def _placement(reader: FieldReader, key: str) -> np.ndarray:
    table = reader.table(key, None)
    if table is None:
        return np.eye(4)
    xyz = table.lengths("xyz", 3, np.zeros(3))
    rpy = table.angles("rpy", 3, np.zeros(3))
    table.finish()
    return placement_matrix(xyz, rpy)


def _checked(reader: FieldReader, build, *args, **kwargs):
    """Call a constructor that validates its data; re-raise its error with this file and field."""
    try:
        return build(*args, **kwargs)
    except InputError as exc:
        raise InputError(exc.message, file=reader.file, field=reader.field(exc.field or "")) from None


def _inertial(link: FieldReader) -> Inertial:
    mass = link.number("mass", 0.0)
    if mass < 0:
        raise link.error("mass", f"must be >= 0 kg, got {mass:g}")
    com = link.lengths("com", 3, np.zeros(3))
    inertia = np.zeros((3, 3))
    table = link.table("inertia", None)
    if table is not None:
        xx, yy, zz = (table.number(k) for k in ("xx", "yy", "zz"))
        xy, xz, yz = (table.number(k, 0.0) for k in ("xy", "xz", "yz"))
        table.finish()
        inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    physical = link.boolean("physical_inertia", True)
    return _checked(link, Inertial, mass, com, inertia, physical)


#: mechatron's plausible range of a drive's efficiency η (its own rule, docs/robot_file.md; the catalogs' too): no
#: transmission keeps less than 1 % of its input, and below it the torque asked of the motor, τ/(u η), overflows.
EFFICIENCY_MIN = 0.01
#: mechatron's plausible range of |u|, a drive's gear ratio (rad/rad, or rad/m for a screw: 2π/lead; its own rule,
#: docs/robot_file.md): from a large pulley driving a small joint to a fine-pitch screw's 2π/0.1 mm ≈ 6.3e4 rad/m.
GEAR_RATIO_RANGE = (1e-3, 1e6)


def _drive(link: FieldReader) -> Drive | None:
    """The ``drive`` table of a link, checked: besides each field's own bounds (:class:`~mechatron.model.dh.Drive`),
    the efficiency and |gear ratio| within mechatron's plausible ranges (:data:`EFFICIENCY_MIN`,
    :data:`GEAR_RATIO_RANGE`) and the Coulomb friction opposing the motion, T_c+ ≥ 0 ≥ T_c− (friction dissipates:
    T_c(ω)·ω ≥ 0)."""
    table = link.table("drive", None)
    if table is None:
        return None
    coulomb = table.vector("coulomb_friction", 2, np.zeros(2))
    if not (coulomb[0] >= 0 and coulomb[1] <= 0):
        raise table.error("coulomb_friction", f"Coulomb friction opposes the motion: [T_c+ >= 0 for positive motor "
                          f"speed, T_c- <= 0 for negative], got [{coulomb[0]:g}, {coulomb[1]:g}]")
    ratio = table.number("gear_ratio", 1.0, nonzero=True)
    if not GEAR_RATIO_RANGE[0] <= abs(ratio) <= GEAR_RATIO_RANGE[1]:
        raise table.error("gear_ratio", f"|gear ratio| must be between {GEAR_RATIO_RANGE[0]:g} and "
                          f"{GEAR_RATIO_RANGE[1]:g} (mechatron's plausible range), got {ratio:g}")
    efficiency = table.number("efficiency", 1.0, positive=True)
    if efficiency < EFFICIENCY_MIN:
        raise table.error("efficiency", f"efficiency must be between {EFFICIENCY_MIN:g} and 1 (mechatron's plausible "
                          f"range), got {efficiency:g}")
    drive = _checked(
        table, Drive,
        rotor_inertia=table.number("rotor_inertia", 0.0, minimum=0.0),
        gear_ratio=ratio,
        efficiency=efficiency,
        viscous_friction=table.number("viscous_friction", 0.0, minimum=0.0),
        coulomb_friction=(float(coulomb[0]), float(coulomb[1])),
        placement=table.string("placement", None),
        offset=tuple(float(x) for x in table.lengths("offset", 3, np.zeros(3))),
    )
    table.finish()
    return drive


def _check_placements(top: FieldReader, links: tuple[DHLink, ...]) -> None:
    """Every drive placement names a frame of the arm: ``base``, ``link1`` … ``linkN`` or ``tool``."""
    frames = ["base", *(f"link{i}" for i in range(1, len(links) + 1)), "tool"]
    for i, link in enumerate(links, start=1):
        if link.drive is not None and link.drive.placement is not None and link.drive.placement not in frames:
            raise top.error(f"links[{i}].drive.placement", f"unknown body {link.drive.placement!r} for the drive of "
                            f"joint {link.name or f'q{i}'} (known: {', '.join(frames)})")


def _link(link: FieldReader) -> DHLink:
    kind = link.string("joint", choices=JOINT_KINDS)
    revolute = kind == "revolute"
    # Revolute limits default to ±180°; a prismatic axis always has a stroke, so its limits are required.
    limit = link.angle if revolute else link.length
    lower = limit("lower", -math.pi if revolute else REQUIRED)
    upper = limit("upper", math.pi if revolute else REQUIRED)
    if not lower < upper:
        raise link.error("lower", f"lower limit {lower:g} must be below upper limit {upper:g}")
    out = _checked(
        link, DHLink,
        joint=kind,
        name=link.string("name", ""),
        a=link.length("a", 0.0),
        alpha=link.angle("alpha", 0.0),
        d=link.length("d", 0.0),
        theta=link.angle("theta", 0.0),
        lower=lower,
        upper=upper,
        velocity_limit=link.number("max_velocity", math.inf, positive=True),
        effort_limit=link.number("max_effort", math.inf, positive=True),
        inertial=_inertial(link),
        drive=_drive(link),
    )
    link.finish()
    return out


def read_robot_file(path: str | Path) -> RobotFile:
    """Read and validate a robot file (schema: ``robots/README.md``)."""
    path = Path(path)
    top = FieldReader(read_toml(path), file=path)
    name, description, source = top.header(path.stem)
    convention = top.string("convention", "standard", choices=CONVENTIONS)
    gravity = top.vector("gravity", 3, np.array([0.0, 0.0, -9.81]))
    base = _placement(top, "base")
    tool = _placement(top, "tool")
    included = top.boolean("link_masses_include_drives", False)
    links = tuple(_link(link) for link in top.tables("links"))
    top.finish()
    _check_placements(top, links)
    table = _checked(top, DHTable, links, convention, base, tool, gravity)
    return RobotFile(name=name, description=description, source=source, table=table, path=path,
                     link_masses_include_drives=included)

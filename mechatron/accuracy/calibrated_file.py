"""Writing a calibrated mechanism as the file it came from: a robot file, a mechanism file or a URDF.

- ``.toml`` of a DH arm: the robot file of its table with the identified a, α, d, θ
  (:func:`~mechatron.model.robot_writer.write_robot_file`); a joint offset δq is folded into the row's constant,
  θ + δq of a revolute joint, d + δq of a prismatic one, and its limits shifted by −δq: the joint's coordinate is
  then the encoder's reading, and its stops stay where they are on the machine (q_model = q_read + δq ∈ [lo, hi]);
- ``.toml`` of a closed-loop linkage read from a mechanism file: that file's spec with the identified lengths and
  pin coordinates (:func:`~mechatron.model.linkage.parameter_spec`,
  :func:`~mechatron.model.linkage_file.write_linkage_file`); it holds no encoder zeros, so joint offsets are refused;
- ``.urdf`` of a serial mechanism: :func:`~mechatron.model.urdf.export_urdf` of the calibrated model, a joint offset
  folded into the joint's origin (origin · exp(axis δq): the joint then reads as the encoder does), its limits
  shifted by −δq likewise.

Each is written whole or not at all, and never over the file the mechanism was read from.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..errors import InputError
from ..model.mechanism import Mechanism

SUFFIXES = (".toml", ".urdf")


def check_calibrated_path(mech: Mechanism, path: str | Path) -> Path:
    """``path`` if a calibrated ``mech`` can be written there (its suffix, its kind, not the file it came from)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise InputError("a calibrated mechanism is a robot or mechanism file (.toml) or a URDF (.urdf)", file=path)
    if mech.source and Path(mech.source).exists() and path.exists() and path.resolve() == Path(mech.source).resolve():
        raise InputError(f"is the file {mech.name} was read from: write the calibrated mechanism to another file",
                         file=path)
    if suffix == ".toml" and mech.dh is None and not _mechanism_file(mech):
        raise InputError(f"{mech.name} is neither a DH arm nor a mechanism file's linkage: write it as .urdf",
                         file=path)
    if suffix == ".urdf" and mech.closures:
        raise InputError(f"{mech.name} is a closed loop: write it as a mechanism file (.toml)", file=path)
    return path


def _mechanism_file(mech: Mechanism) -> bool:
    return bool(mech.closures and mech.source and str(mech.source).endswith(".toml") and Path(mech.source).is_file())


def write_calibrated(mech: Mechanism, offsets: Mapping[str, float], path: str | Path, header: str = "") -> list[Path]:
    """Write the calibrated ``mech`` (its parameters the identified ones) with the joint ``offsets`` (rad, m) to
    ``path`` (module docstring); returns the files written."""
    path = check_calibrated_path(mech, path)
    if path.suffix.lower() == ".urdf":
        from ..model.urdf import export_urdf

        return export_urdf(_offset_model(mech, offsets), path)
    if mech.dh is not None:
        from ..model.robot_writer import write_robot_file

        table = mech.dh
        rows = {link.name: i for i, link in enumerate(table.links, start=1)}
        changes = {}
        for name, offset in offsets.items():
            i = rows[name]
            field = "theta" if table.links[i - 1].is_revolute else "d"
            key = table.parameter_names(i)[field]
            changes[key] = mech.parameter_values()[key] + offset
        table = table.with_values(changes)
        links = [dataclasses.replace(link, lower=link.lower - offsets.get(link.name, 0.0),
                                     upper=link.upper - offsets.get(link.name, 0.0)) for link in table.links]
        table = dataclasses.replace(table, links=tuple(links))
        return [write_robot_file(table, path, description=mech.description,
                                 source=f"calibrated from {Path(mech.source).name if mech.source else mech.name}",
                                 header=header, link_masses_include_drives=mech.link_masses_include_drives)]
    if offsets:
        raise InputError(f"a mechanism file holds no encoder zeros: identify the joint offsets ({', '.join(offsets)}) "
                         "apart, or write the calibrated parameters without them", file=path)
    from ..model.linkage import parameter_spec
    from ..model.linkage_file import read_linkage_file, write_linkage_file

    spec = read_linkage_file(str(mech.source))
    spec = dataclasses.replace(parameter_spec(spec, mech.parameter_values()), name=path.stem)
    return [write_linkage_file(spec, path, header)]


def _offset_model(mech: Mechanism, offsets: Mapping[str, float]) -> Mechanism:
    """``mech`` with each joint's origin turned (slid) by its offset about (along) its axis: M_j exp(S_j δq), S_j
    the joint's motion subspace in its own frame."""
    if not offsets:
        return mech
    model = copy.deepcopy(mech.model)
    for name, offset in offsets.items():
        joint = mech.joint_id(name)
        joint_model = mech.model.joints[joint]
        joint_data = joint_model.createData()
        joint_model.calc(joint_data, pin.neutral(mech.model))
        axis = np.asarray(joint_data.S, dtype=float).reshape(6)
        model.jointPlacements[joint] = mech.model.jointPlacements[joint] * pin.exp6(pin.Motion(axis * offset))
        if joint_model.nq == 1:  # a continuous joint's (cos, sin) has no limits
            lower, upper = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
            lower[joint_model.idx_q] -= offset
            upper[joint_model.idx_q] -= offset
            model.lowerPositionLimit, model.upperPositionLimit = lower, upper
    return dataclasses.replace(mech, model=model)

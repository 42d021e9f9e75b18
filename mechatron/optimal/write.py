"""``mechatron optimize -o DIR``: the results and the optimum's designs as mechanism files (:func:`write_optimum`),
each read back before it is written."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .problem import Problem
from .result import OptimalResult

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd


#: The mark of a design file written by ``optimize -o`` (its header comment begins so): a file in the folder named
#: ``design-NNN.toml`` or ``.urdf`` with it is a companion of an earlier run.
DESIGN_MARK = "mechatron optimize: design "


def output_files(folder: str | Path) -> list[Path]:
    """The files ``optimize -o folder`` may replace or remove: ``optimum.json``, ``designs.csv`` and every
    ``design-NNN.toml`` or ``.urdf`` already there (no command reads them: :func:`mechatron.io.output.will_write`)."""
    folder = Path(folder)
    return [folder / "optimum.json", folder / "designs.csv", *_design_files(folder)]


def _design_files(folder: Path) -> list[Path]:
    import re

    try:
        names = sorted(p for p in folder.iterdir() if re.fullmatch(r"design-\d{3,}\.(toml|urdf)", p.name))
    except OSError:
        return []
    return [p for p in names if p.is_file()]


def earlier_designs(folder: str | Path) -> list[Path]:
    """The design files an earlier ``optimize -o`` wrote in ``folder`` (named ``design-NNN``, with
    :data:`DESIGN_MARK` in their first lines); any other file is left alone."""
    from ..io.output import unchecked

    out = []
    for path in _design_files(Path(folder)):
        try:
            with unchecked(), open(path, "rb") as fh:
                head = fh.read(400).decode("utf-8", "replace")
        except OSError:
            continue
        if DESIGN_MARK in head:
            out.append(path)
    return out


@dataclass
class DesignFile:
    """A design drawn as a mechanism file: its path, its text (written only if it reads back) and, where it does
    not read back, the error naming that file."""

    path: Path
    text: str
    error: InputError | None = None


def draw_designs(spec: Problem, designs: pd.DataFrame, folder: str | Path) -> list[DesignFile]:
    """Each design (a row of the variables) as the text of a mechanism file ``folder/design-NNN``: a planar or
    spatial mechanism file for a mechanism read from one, with its parameters at the design's values, drawn at the
    pose the search evaluated (:func:`_redrawn`); else a URDF of the rebuilt mechanism. Analysis options among the
    variables are not part of a mechanism and are left out. A mechanism file is read back from its text before it
    is written; where it does not read back, its :attr:`DesignFile.error` names the file being written, its field
    and why. Nothing is written here."""
    from ..io.toml import read_toml
    from ..library import robot_origins
    from ..model.linkage_file import is_linkage_file, linkage_spec, linkage_toml
    from ..model.urdf import to_urdf
    from ..studies.spec import study_mechanism

    source = Path(spec.mechanism)
    if not source.is_file():
        source = robot_origins().get(spec.mechanism, (None, None))[1] or source
    data = read_toml(source) if source.suffix.lower() == ".toml" else None
    linkage = linkage_spec(data, file=source) if data is not None and is_linkage_file(data) else None
    mech = study_mechanism(spec.mechanism)
    folder = Path(folder)
    geometry = [p.name for p in spec.variables if p.target is None]
    out = []
    for k, (_, row) in enumerate(designs.iterrows()):
        values = {n: float(row[n]) for n in geometry}
        header = f"{DESIGN_MARK}{k} of {spec.name}: " + ", ".join(f"{n} = {v:.9g}" for n, v in values.items())
        design = mech.with_parameters(values)
        if linkage is None:
            text = to_urdf(design).replace("?>", f"?>\n<!-- {header} -->", 1)
            out.append(DesignFile(folder / f"design-{k:03d}.urdf", text))
            continue
        path = folder / f"design-{k:03d}.toml"
        every = {**mech.parameter_values(), **values}
        drawn = _redrawn(linkage, design, every) if linkage.planar else _moved(linkage, every)
        text = linkage_toml(drawn, header)
        out.append(DesignFile(path, text, _read_back_error(text, path)))
    return out


def write_designs(spec: Problem, designs: pd.DataFrame, folder: str | Path) -> list[Path]:
    """Write the designs of :func:`draw_designs` in ``folder`` (created if needed), all of them or, where one does
    not read back, none (:class:`InputError` naming that file). Returns the paths written."""
    from ..io.output import output_directory, transaction, write_text

    files = draw_designs(spec, designs, folder)
    for f in files:
        if f.error is not None:
            raise f.error
    with transaction():
        output_directory(folder)
        return [write_text(f.path, f.text) for f in files]


def write_optimum(spec: Problem, result: OptimalResult, folder: str | Path
                  ) -> tuple[list[Path], list[InputError]]:
    """``mechatron optimize -o DIR``: first the results — ``optimum.json`` (:meth:`OptimalResult.as_dict`) and
    ``designs.csv`` (every design evaluated: the variables, ``status``, ``reason``, the outputs, ``feasible``) —
    then the best design (two objectives: every design of the front) as mechanism files (:func:`draw_designs`),
    each one that reads back. The design files of an earlier run there (:func:`earlier_designs`) that this run
    does not write are removed in the same commit. Returns the paths written and the errors of the designs not
    written (each naming its file), so that a design that cannot be written never discards the results."""
    import pandas as pd

    from ..io.output import output_directory, stage_removal, transaction, write_table, write_text

    files: list[DesignFile] = []
    with transaction():
        folder = output_directory(folder)
        written = [write_text(folder / "optimum.json", result.to_json() + "\n"),
                   write_table(result.evaluations, folder / "designs.csv")]
        if result.best is not None:
            front = result.front if result.front is not None else pd.DataFrame([result.best])
            files = draw_designs(spec, front, folder)
            written += [write_text(f.path, f.text) for f in files if f.error is None]
        for path in earlier_designs(folder):  # an earlier run's designs: removed in the same commit
            if path not in written:
                stage_removal(path)
    return written, [f.error for f in files if f.error is not None]


def _redrawn(linkage: Any, design: Any, values: dict[str, float]) -> Any:
    """The linkage spec of a design (:func:`~mechatron.model.linkage.parameter_spec`: every length declared at its
    value, the points' coordinates moved) drawn at the design's assembled pose: every drawn point where the
    design's mechanism (``design``, rebuilt as the search evaluated it: its loops closed with the actuated inputs
    held where the file holds them) has it at its reference configuration, a point's direction (a slider's
    line) turned with its body, a centre of mass given by world coordinates moved with it, and every body's x
    axis and prismatic guide turned with it (:func:`_turned_joints`), so that the file read back has the
    evaluated joint coordinates. A design's moved pins (a cylinder's base) can put the *drawn* pose outside a
    cylinder's stroke; drawn at the assembled pose, each held input is at the value the file held it at, within
    its stroke, and the loops close as drawn."""
    import pinocchio as pin

    from ..model.linkage import parameter_spec

    model, data = design.model, design.model.createData()
    q = np.asarray(design.reference_q, dtype=float)
    pin.framesForwardKinematics(model, data, q)
    redrawn = parameter_spec(linkage, values)
    points = []
    for p in redrawn.points:
        if p.at is None or p.between is not None or not model.existFrame(p.name):
            points.append(p)
            continue
        placement = data.oMf[model.getFrameId(p.name)]
        at = tuple(float(v) for v in placement.translation[:len(p.at)])
        direction = p.direction
        if direction is not None and len(direction) == 2:  # planar: the frame's x axis is the point's direction
            dx, dy = (float(v) for v in placement.rotation[:2, 0] * np.linalg.norm(direction))
            direction = (dx, dy)
        points.append(replace(p, at=at, direction=direction))
    bodies = []
    for b in redrawn.bodies:  # a centre of mass given by world coordinates moves with its body
        if isinstance(b.com, tuple) and b.mass > 0 and model.existFrame(b.name, pin.FrameType.BODY):
            joint = model.frames[model.getFrameId(b.name, pin.FrameType.BODY)].parentJoint
            b = replace(b, com=tuple(float(v) for v in data.oMi[joint].act(model.inertias[joint].lever)[:2]))
        bodies.append(b)
    redrawn = replace(redrawn, points=tuple(points), bodies=tuple(bodies))
    return replace(redrawn, joints=_turned_joints(redrawn, model, data, q))


def _turned_joints(spec: Any, model: Any, data: Any, q: np.ndarray) -> tuple:
    """The tree joints of ``spec`` (its points already drawn at the pose ``q`` of ``model``, whose kinematics are
    in ``data``) so that, read back, each joint's coordinate is its value in ``q``. A body's x axis in the file is
    world angle θ (rad): a revolute joint's θ = θ_parent + q (the coordinate is the angle from the parent's x
    axis), a prismatic body's θ = θ_parent. So a revolute joint given by its world ``angle`` gets θ_parent + q
    (not 2π-wrapped, so its limits still hold); one whose x axis the file would take from a point that does not
    turn with it (a ``toward`` point of another body, or none: the parent's axis) gets that ``angle`` too; one
    toward a point of its own body keeps it, θ = atan2 of that point from the pin as the file draws it. A prismatic
    guide's world ``direction`` turns to the joint's x axis at the pose (its length kept)."""
    from ..model.linkage_spec import GROUND, joint_coordinate, joint_parent
    from ..model.shapes import with_derived

    drawn = with_derived(spec, spec.drawing())
    theta: dict[str, float] = {GROUND: 0.0}
    turned: dict[int, Any] = {}
    pending = [k for k, j in enumerate(spec.joints) if j.kind in ("revolute", "prismatic")]
    while pending:  # each joint once its parent's x axis is known, as the file's layout places them
        k = next((k for k in pending if joint_parent(spec, spec.joints[k]) in theta), None)
        if k is None:  # not a tree: left as it is, for the read-back to name
            break
        pending.remove(k)
        j = spec.joints[k]
        parent = theta[joint_parent(spec, j)]
        joint = model.getJointId(joint_coordinate(j))
        if j.kind == "prismatic":
            theta[j.body] = parent
            if j.direction is not None:
                axis = data.oMi[joint].rotation[:2, 0] * float(np.hypot(*j.direction))
                turned[k] = replace(j, direction=(float(axis[0]), float(axis[1])))
            continue
        toward = j.toward or next((p for p in spec.body(j.body).points if p != j.at), None)
        if j.angle is None and toward is not None and toward in spec.body(j.body).points:
            d = np.asarray(drawn[toward], dtype=float) - np.asarray(drawn[j.at], dtype=float)
            theta[j.body] = float(np.arctan2(d[1], d[0]))
            continue
        theta[j.body] = parent + float(q[model.joints[joint].idx_q])
        turned[k] = replace(j, toward=None, angle=theta[j.body])
    return tuple(turned.get(k, j) for k, j in enumerate(spec.joints))


def _moved(linkage: Any, values: dict[str, float]) -> Any:
    """A spatial linkage spec with its drawn points at the design's coordinates ``POINT_x``, ``_y``, ``_z`` (m), as
    its rebuild draws it (:func:`mechatron.model.spatial.build_spatial`: its loops closed from that drawing)."""
    return linkage.with_positions({p.name: [values.get(f"{p.name}_{a}", v) for a, v in zip("xyz", p.at)]
                                   for p in linkage.points if p.at is not None and p.between is None})


def _read_back_error(text: str, path: Path) -> InputError | None:
    """Why the mechanism file ``text`` (to be written to ``path``) would not read back, or None: it is read and
    built as a file at ``path`` would be."""
    from ..errors import MechatronError
    from ..io.toml import tomllib
    from ..model.linkage_file import linkage_spec
    from ..model.spatial import build_mechanism

    try:
        build_mechanism(linkage_spec(tomllib.loads(text), file=path))
    except InputError as exc:
        return InputError(f"the design does not read back, so it is not written: {exc.message}", file=path,
                          row=exc.row, field=exc.field)
    except MechatronError as exc:
        return InputError(f"the design does not read back, so it is not written: {exc}", file=path)
    return None

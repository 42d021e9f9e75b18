r"""Results of the model and pose commands: a mechanism's description (``mechatron show``), the pose of a frame at
one configuration (``mechatron fk``) and its Jacobian (``mechatron jacobian``).

- :func:`mechanism_summary` → :class:`MechanismSummary`: DH table, joints, links, drives, parameters, closures;
- :func:`frame_pose` → :class:`FramePose`: the placement B_{0,i} of a frame ([Egorov, 4.44–4.45]) with its
  roll-pitch-yaw angles;
- :func:`jacobian_summary` → :class:`JacobianSummary`: the 6×n Jacobian ([Egorov, 4.47]) with its singular values.

Joint values are reported as joint coordinates (one per joint: rad or m; a continuous joint's angle, not the
(cos θ, sin θ) of Pinocchio's configuration), see :meth:`~mechatron.model.Mechanism.coordinates`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism
from ..report.result import Result, json_ready
from .frames import Reference, fk_and_jacobian, frame_placement

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The rows of a 6×n Jacobian (linear velocity first, then angular) and their units per unit joint rate.
JACOBIAN_ROWS = ("vx", "vy", "vz", "wx", "wy", "wz")
_ROW_UNITS = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _coordinates_text(mech: Mechanism, coordinates: NDArray[np.float64]) -> str:
    angular = mech.angular_coordinates()
    return ", ".join(f"{name} = {value:.6g} {'rad' if is_angle else 'm'}"
                     for name, value, is_angle in zip(mech.joint_names, coordinates, angular))


def _reference_configuration(mech: Mechanism) -> NDArray[np.float64]:
    return np.asarray(mech.reference_q if mech.reference_q is not None else mech.neutral(), dtype=float)


# ------------------------------------------------------------------------------------------------ mechatron show
@dataclass
class MechanismSummary(Result):
    """What ``mechatron show`` reports about a mechanism.

    Attributes:
        mechanism: The mechanism.
        info: The description as plain data (see :meth:`as_dict`).

    The protocol: :meth:`to_frame` the joints table; :meth:`as_dict` ``info``; :meth:`plot` the mechanism at its
    reference configuration; ``str`` the text report.
    """

    mechanism: Mechanism
    info: dict[str, Any]

    def to_frame(self) -> pd.DataFrame:
        """One row per joint: ``name, kind`` (revolute, prismatic, …), ``unit`` (of its coordinate: rad or m),
        ``lower, upper`` (its limits, rad or m; NaN if unbounded), ``max_velocity`` (rad/s or m/s),
        ``max_effort`` (N·m or N), ``armature`` (kg·m² or kg)."""
        import pandas as pd

        numbers = ["lower", "upper", "max_velocity", "max_effort", "armature"]
        table = pd.DataFrame(self.info["joints"], columns=["name", "kind", "unit", *numbers])
        return table.astype(dict.fromkeys(numbers, float))

    def as_dict(self) -> dict[str, Any]:
        """``name, description, source, convention`` (of the DH table), ``nq, nv, mobility, total_mass`` (kg),
        ``gravity`` (m/s²), ``dh`` (the DH table's rows, θ and α in degrees), ``joints`` (as :meth:`to_frame`),
        ``links`` ({name, mass (kg), com (m, in the joint frame)}), ``drives`` ({joint: rotor_inertia (kg·m²),
        gear_ratio, efficiency, reflected_inertia J·u² (kg·m²)}), ``parameters`` ({name: value, unit,
        description}), ``frames``, ``actuated``, ``closures``, ``redundant_closure_equations``, ``cylinders``
        ({name: base, eye, L_min, L_max (m), count}) and ``notes``."""
        return json_ready(self.info)

    def __str__(self) -> str:
        mech, info = self.mechanism, self.info
        lines = [f"{mech.name}: {mech.description}"]
        if mech.source:
            lines.append(f"from {mech.source}")
        lines.append(f"{mech.nq} coordinates, mobility W = {info['mobility']}, total mass {info['total_mass']:.3f} kg, "
                     f"gravity {info['gravity']} m/s²")
        if mech.dh is not None:
            lines += ["", f"DH table ({mech.dh.convention} convention; θ and α in degrees, lengths in metres):",
                      mech.dh.to_frame().to_string()]
        lines += ["", "joints:"]
        for joint in info["joints"]:
            limits = f"[{joint['lower']:g}, {joint['upper']:g}] {joint['unit']}" if joint["lower"] is not None \
                else "unbounded"
            lines.append(f"  {joint['name']:<22} {joint['kind']:<10} {limits}")
        lines += ["", "links (mass kg, centre of mass m in the joint frame):"]
        for link in info["links"]:
            lines.append(f"  {link['name']:<22} {link['mass']:9.4f}  {np.round(link['com'], 5).tolist()}")
        if info["drives"]:
            lines += ["", "drives (rotor inertia kg·m², gear ratio, efficiency, reflected inertia J·u²):"]
            for name, d in info["drives"].items():
                lines.append(f"  {name:<22} {d['rotor_inertia']:10.3e} {d['gear_ratio']:10.4g} "
                             f"{d['efficiency']:6.3f} {d['reflected_inertia']:10.4g}")
        lines += ["", f"geometric parameters ({len(info['parameters'])}; override with --set NAME=VALUE):"]
        names = list(info["parameters"])
        for start in range(0, len(names), 4):
            lines.append("  " + "  ".join(f"{n}={info['parameters'][n]['value']:.6g}" for n in names[start:start + 4]))
        if mech.closures:
            lines += ["", f"closures ({len(mech.closures)}; redundant equations: "
                          f"{info['redundant_closure_equations']}):"]
            lines += [f"  {text}" for text in info["closures"]]
            lines.append(f"actuated coordinates: {', '.join(mech.actuated)}")
        for name, c in info["cylinders"].items():
            twin = f", {c['count']} side by side" if c["count"] > 1 else ""
            lines.append(f"cylinder {name}: {c['base']} to {c['eye']}, {c['L_min']:.4g} … {c['L_max']:.4g} m{twin}")
        lines += [f"note: {note}" for note in mech.notes]
        lines += ["", f"frames: {', '.join(info['frames'])}"]
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Figure:
        """The mechanism at its reference configuration (the neutral one if it has none), lengths in metres: a
        linkage's drawing, or an arm's joint origins in a side (x–z) and a top (x–y) view with its tool frame
        marked. Given ``ax``, draws the linkage or the side view into it."""
        from .drawing import configuration_figure

        mech = self.mechanism
        tool = mech.tool_frame if mech.tool_frame in mech.frame_names else None
        which = "reference" if mech.reference_q is not None else "neutral"
        return configuration_figure(mech, _reference_configuration(mech), frame=None if mech.sketch else tool, ax=ax,
                                    title=f"{mech.name} at its {which} configuration")


def mechanism_summary(mech: Mechanism) -> MechanismSummary:
    """Everything ``mechatron show`` reports about ``mech``: its DH table, joints with their limits (rad or m),
    velocity (rad/s or m/s) and effort (N·m or N) limits, links with mass (kg) and centre of mass (m), drives,
    geometric parameters, frames, closures, mobility W = nv − rank of the closure Jacobian (Reshetov's count
    [Egorov, 3.11], the redundant closure equations being S) and cylinders, as a :class:`MechanismSummary`."""
    model = mech.model
    angular = mech.angular_coordinates()
    joints = []
    for j in range(1, model.njoints):
        iq, iv = model.joints[j].idx_q, model.joints[j].idx_v
        joints.append({
            "name": model.names[j], "kind": mech.joint_kind(j), "unit": "rad" if angular[iv] else "m",
            "lower": _finite(model.lowerPositionLimit[iq]), "upper": _finite(model.upperPositionLimit[iq]),
            "max_velocity": _finite(model.velocityLimit[iv]), "max_effort": _finite(model.effortLimit[iv]),
            "armature": float(model.armature[iv]),
        })
    links = [{"name": name, "mass": float(model.inertias[j].mass), "com": model.inertias[j].lever.tolist()}
             for j, name in enumerate(mech.link_names, start=1)]
    drives = {name: {"rotor_inertia": d.rotor_inertia, "gear_ratio": d.gear_ratio, "efficiency": d.efficiency,
                     "reflected_inertia": d.reflected_inertia} for name, d in mech.drives.items()}
    info = {
        "name": mech.name, "description": mech.description, "source": mech.source,
        "convention": mech.dh.convention if mech.dh is not None else None,
        "nq": mech.nq, "nv": mech.nv, "mobility": mech.mobility(), "total_mass": mech.total_mass,
        "gravity": model.gravity.linear.tolist(),
        "dh": mech.dh.to_frame().to_dict(orient="records") if mech.dh is not None else None,
        "joints": joints, "links": links, "drives": drives,
        "parameters": {n: {"value": p.value, "unit": p.unit, "description": p.description}
                       for n, p in mech.parameters.items()},
        "frames": sorted({f.name for f in model.frames if f.type in (pin.FrameType.OP_FRAME, pin.FrameType.BODY)}),
        "actuated": list(mech.actuated),
        "closures": [c.describe() for c in mech.closures],
        "redundant_closure_equations": mech.redundant_closure_equations(),
        "cylinders": {n: {"base": c.base, "eye": c.eye, "L_min": c.stroke[0], "L_max": c.stroke[1], "count": c.count}
                      for n, c in mech.cylinders.items()},
        "notes": list(mech.notes),
    }
    return MechanismSummary(mech, info)


# ---------------------------------------------------------------------------------------- mechatron fk, jacobian
@dataclass
class _FrameResult(Result):
    """A result about one frame at one configuration: ``mechanism``, ``frame`` (its name), ``q`` (nq,) and its
    joint ``coordinates`` (nv,; rad or m)."""

    mechanism: Mechanism
    frame: str
    q: NDArray[np.float64]
    coordinates: NDArray[np.float64]


def _one_configuration(mech: Mechanism, q: ArrayLike, frame: str | None, what: str
                       ) -> tuple[NDArray[np.float64], str]:
    """(q as one configuration (nq,), the frame's name, default the tool frame)."""
    q = mech.check_configuration(q)
    if q.ndim != 1:
        raise InputError(f"{what} takes one configuration; use fk_and_jacobian for a batch")
    return q.copy(), frame or mech.tool_frame


@dataclass
class FramePose(_FrameResult):
    """The pose of a frame at one configuration (``mechatron fk``).

    Attributes:
        mechanism: The mechanism.
        frame: The frame's name.
        q: The configuration (nq,).
        coordinates: The joint coordinates (nv,; rad or m) of ``q``.
        position: Origin of the frame in the world (m), (3,).
        rotation: Its rotation matrix in the world, (3, 3).
        rpy: Its roll, pitch and yaw (rad): rotation = R_z(yaw) R_y(pitch) R_x(roll).

    The protocol: :meth:`to_frame` one row (joint coordinates, position, roll-pitch-yaw, rotation entries);
    :meth:`as_dict` the same as plain data; :meth:`plot` the mechanism at ``q`` with the frame marked; ``str`` the
    text report.
    """

    position: NDArray[np.float64]
    rotation: NDArray[np.float64]
    rpy: NDArray[np.float64]

    def to_frame(self) -> pd.DataFrame:
        """One row: ``q_{joint}`` (rad or m) for every joint, ``frame``, ``x, y, z`` (m), ``roll, pitch, yaw``
        (rad) and the rotation matrix entries ``r11 … r33`` (row by row)."""
        import pandas as pd

        row: dict[str, Any] = {f"q_{n}": x for n, x in zip(self.mechanism.joint_names, self.coordinates)}
        row.update(frame=self.frame, x=self.position[0], y=self.position[1], z=self.position[2],
                   roll=self.rpy[0], pitch=self.rpy[1], yaw=self.rpy[2])
        row.update({f"r{i + 1}{j + 1}": self.rotation[i, j] for i in range(3) for j in range(3)})
        return pd.DataFrame([row])

    def as_dict(self) -> dict[str, Any]:
        """``mechanism, frame``, ``joints`` (names) and ``coordinates`` (rad or m), ``position`` [x, y, z] (m),
        ``rotation`` (3×3, rows), ``rpy`` [roll, pitch, yaw] (rad)."""
        return json_ready({"mechanism": self.mechanism.name, "frame": self.frame,
                           "joints": self.mechanism.joint_names, "coordinates": self.coordinates,
                           "position": self.position, "rotation": self.rotation, "rpy": self.rpy})

    def __str__(self) -> str:
        rpy = np.degrees(self.rpy)
        return "\n".join([
            f"{self.mechanism.name}, frame {self.frame} at {_coordinates_text(self.mechanism, self.coordinates)}",
            f"position (m):      {np.array2string(self.position, precision=6, suppress_small=True)}",
            f"roll-pitch-yaw (deg): {np.array2string(rpy, precision=4, suppress_small=True)}",
            "rotation:",
            np.array2string(self.rotation, precision=6, suppress_small=True),
        ])

    def plot(self, ax: Axes | None = None) -> Figure:
        """The mechanism at this configuration (m) with the frame's origin marked: a linkage's drawing or an arm's
        side (x–z) and top (x–y) views. Given ``ax``, draws the linkage or the side view into it."""
        from .drawing import configuration_figure

        return configuration_figure(self.mechanism, self.q, frame=self.frame, ax=ax,
                                    title=f"{self.mechanism.name}, frame {self.frame}")


def frame_pose(mech: Mechanism, q: ArrayLike, frame: str | None = None) -> FramePose:
    """The pose of ``frame`` (default the tool frame) at the configuration ``q`` (nq,): its placement B_{0,i}
    ([Egorov, 4.44–4.45]; position in m, rotation matrix) and its roll-pitch-yaw angles (rad), as a
    :class:`FramePose`."""
    q, frame = _one_configuration(mech, q, frame, "frame_pose")
    placement = frame_placement(mech, q, frame)
    return FramePose(mech, frame, q, mech.coordinates(q), placement.translation.copy(),
                     placement.rotation.copy(), np.asarray(pin.rpy.matrixToRpy(placement.rotation), dtype=float))


@dataclass
class JacobianSummary(_FrameResult):
    """The Jacobian of a frame at one configuration (``mechatron jacobian``).

    Attributes:
        mechanism: The mechanism.
        frame: The frame's name.
        reference: Where the twist is expressed (see :func:`~mechatron.kinematics.frames.reference_frame`).
        q: The configuration (nq,).
        coordinates: Its joint coordinates (nv,; rad or m).
        jacobian: The 6×nv matrix mapping q̇ to the frame's twist [v; ω] ([Egorov, 4.47]): linear rows in m/s and
            angular rows in rad/s per unit joint rate (rad/s or m/s).
        singular_values: Its singular values, largest first.

    The protocol: :meth:`to_frame` the matrix (one row per twist component); :meth:`as_dict` the matrix with its
    singular values; :meth:`plot` its columns as bars; ``str`` the text report.
    """

    reference: str
    jacobian: NDArray[np.float64]
    singular_values: NDArray[np.float64]

    def to_frame(self) -> pd.DataFrame:
        """Six rows ``component`` vx, vy, vz, wx, wy, wz with the ``unit`` of that twist component (m/s or rad/s)
        per unit joint rate, and one column per joint (its column of the Jacobian)."""
        import pandas as pd

        table = pd.DataFrame(self.jacobian, columns=self.mechanism.joint_names)
        table.insert(0, "unit", _ROW_UNITS)
        table.insert(0, "component", JACOBIAN_ROWS)
        return table

    def as_dict(self) -> dict[str, Any]:
        """``mechanism, frame, reference``, ``joints`` (names), ``coordinates`` (rad or m), ``jacobian`` (6 rows:
        vx, vy, vz in m/s, wx, wy, wz in rad/s per unit joint rate) and ``singular_values``."""
        return json_ready({"mechanism": self.mechanism.name, "frame": self.frame, "reference": self.reference,
                           "joints": self.mechanism.joint_names, "coordinates": self.coordinates,
                           "jacobian": self.jacobian, "singular_values": self.singular_values})

    def __str__(self) -> str:
        mech = self.mechanism
        names = mech.joint_names
        width = max(11, *(len(c) for c in names))
        table = [" " * 6 + "".join(f"{c:>{width}}" for c in names)]
        table += [f"{r:<6}" + "".join(f"{x:>{width}.5f}" for x in row) for r, row in zip(JACOBIAN_ROWS, self.jacobian)]
        return "\n".join([
            f"{mech.name}, Jacobian of frame {self.frame} ({self.reference}) at "
            f"{_coordinates_text(mech, self.coordinates)}",
            "rows: linear velocity (m/s) then angular velocity (rad/s) per unit joint rate",
            *table,
            f"singular values: {np.array2string(self.singular_values, precision=5)}",
        ])

    def plot(self, ax: Axes | None = None) -> Figure:
        """Each joint's column of the Jacobian as grouped bars: the linear rows (m/s per unit joint rate: m/rad for
        a revolute joint, m/m for a prismatic one) and the angular rows (rad/s per unit joint rate). Given ``ax``,
        draws the linear rows into it."""
        from ..report.figures import figure_axes, new_figure, style_axes

        if ax is not None:
            figure, axes = figure_axes(ax)[0], [ax]
        else:
            figure = new_figure(10.0, 6.0)
            axes = list(figure.subplots(2, 1, sharex=True))
        names = self.mechanism.joint_names
        x = np.arange(len(names))
        width = 0.8 / 3
        for axis, rows, quantity in zip(axes, (slice(0, 3), slice(3, 6)),
                                        ("∂v/∂q̇ (m/rad or m/m)", "∂ω/∂q̇ (rad/rad or rad/m)")):
            for k, (label, column) in enumerate(zip(JACOBIAN_ROWS[rows], self.jacobian[rows])):
                axis.bar(x + (k - 1) * width, column, width, label=label)
            axis.axhline(0.0, color="black", lw=0.6)
            axis.set_xticks(x, names)
            style_axes(axis, "joint (name)", quantity, legend=True, loc="upper right")
        axes[0].set_title(f"{self.mechanism.name}: Jacobian of frame {self.frame} ({self.reference})", fontsize=10)
        return figure


def jacobian_summary(mech: Mechanism, q: ArrayLike, frame: str | None = None,
                     reference: Reference = "world_aligned") -> JacobianSummary:
    """The 6×nv Jacobian of ``frame`` (default the tool frame) at the configuration ``q`` (nq,), mapping q̇ (rad/s,
    m/s) to the frame's twist [v (m/s); ω (rad/s)] in ``reference`` ([Egorov, 4.47]: its linear rows in
    "world_aligned" are ∂r/∂q), with its singular values, as a :class:`JacobianSummary`."""
    q, frame = _one_configuration(mech, q, frame, "jacobian_summary")
    jacobian = fk_and_jacobian(mech, q[None, :], frame, reference)[2][0]
    return JacobianSummary(mech, frame, q, mech.coordinates(q), reference, jacobian,
                           np.linalg.svd(jacobian, compute_uv=False))

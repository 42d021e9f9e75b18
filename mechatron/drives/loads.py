"""Loads along a motion on both sides of the drives: joint (or actuator) forces, speeds and power, and for joints with
drive data the motor torque and speed (:mod:`mechatron.drives.transmission`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..dynamics.motion import coordinate_names, warn_limits
from ..dynamics.segments import PayloadSchedule, closed_loop_duty
from ..dynamics.series import UNITS, coordinate_columns, load_label, plot_lines, stacked_axes, text_table
from ..dynamics.trajectory import actuator_forces
from ..dynamics.tree import inverse_dynamics
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from ..report.result import Result
from .transmission import motor_loads

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.motion import Trajectory

Array = NDArray[np.float64]


@dataclass(eq=False)
class TrajectoryLoads(Result):
    """Forces along a trajectory, one column per driven coordinate (the joints of a serial arm, the actuated
    coordinates of a closed loop).

    Attributes:
        mechanism: Name of the mechanism.
        kind: ``"joint"`` (serial arm) or ``"actuator"`` (closed loop).
        names: The driven coordinates.
        angular: Which of them are angles (N·m and rad/s; else N and m/s).
        t: Times (N,) (s).
        positions, speeds, accelerations: (N, n) (rad, m and their rates).
        forces: Force or torque of every driven coordinate (N, n) (N·m, N): RNEA, or the constrained inverse
            dynamics of a closed loop.
        motor_torque, motor_speed: (N, n) motor torque (N·m) and speed (rad/s) of the joints with drive data
            (``driven``), ``None`` for a closed loop.
        driven: Which coordinates have drive data (a motor side).
        counts: How many cylinders act side by side on each coordinate (1 for anything else); a coordinate's force
            is that of all of them together (``size`` checks each cylinder with its share, force/count).
    """

    mechanism: str
    kind: str
    names: list[str]
    angular: list[bool]
    t: Array
    positions: Array
    speeds: Array
    accelerations: Array
    forces: Array
    motor_torque: Array | None = None
    motor_speed: Array | None = None
    driven: list[bool] | None = None
    counts: list[int] | None = None

    @property
    def power(self) -> Array:
        """Power τ·q̇ (N, n) (W) delivered to each coordinate."""
        return self.forces * self.speeds

    @property
    def duration(self) -> float:
        """t_end − t_start (s)."""
        return float(self.t[-1] - self.t[0]) if len(self.t) > 1 else 0.0

    def _has_motor(self, i: int) -> bool:
        return self.motor_torque is not None and bool(self.driven and self.driven[i])

    def summary(self) -> list[dict]:
        """Per driven coordinate: ``load`` (``torque`` for an angle, ``force`` for a length), ``cylinders`` (how many
        side by side share the force: 1 for anything else), peak and RMS of that torque or force (``peak_force``,
        ``rms_force``: N·m or N, ``unit``; a cylinder's: the total of its ``cylinders``), peak speed (rad/s or
        m/s), peak power (W), positive work ∫ max(τ q̇, 0) dt (J) and, with drive data, peak and RMS motor torque
        (N·m) and peak motor speed (rad/s). RMS values are √(∫ x² dt / T) (trapezoidal rule)."""
        t, duration, rows = self.t, self.duration, []

        def rms(x: Array) -> float:
            return float(np.sqrt(np.trapezoid(x**2, t) / duration)) if duration > 0 else float(abs(x[0]))

        for i, name in enumerate(self.names):
            tau, power = self.forces[:, i], self.power[:, i]
            row = {"coordinate": name, "load": "torque" if self.angular[i] else "force",
                   "cylinders": self.counts[i] if self.counts else 1,
                   "unit": UNITS[self.angular[i]][3], "peak_force": float(np.abs(tau).max()),
                   "rms_force": rms(tau), "peak_speed": float(np.abs(self.speeds[:, i]).max()),
                   "peak_power": float(np.abs(power).max()),
                   "positive_work": float(np.trapezoid(np.maximum(power, 0.0), t)) if len(t) > 1 else 0.0}
            if self._has_motor(i):
                torque = self.motor_torque[:, i]
                row.update(peak_motor_torque=float(np.abs(torque).max()),
                           rms_motor_torque=rms(torque) if duration > 0 else 0.0,
                           peak_motor_speed=float(np.abs(self.motor_speed[:, i]).max()))
            rows.append(row)
        return rows

    # -------------------------------------------------------------------------------------------- the protocol
    def to_frame(self) -> pd.DataFrame:
        """One row per sample: t (s), every coordinate's position, ``qd_``, ``qdd_`` (rad, m and their rates), its
        force ``tau_<name>`` (N·m, N) and power ``power_<name>`` (W), and for joints with drives
        ``motor_torque_<name>`` (N·m) and ``motor_speed_<name>`` (rad/s)."""
        import pandas as pd

        columns = coordinate_columns(self.t, self.names, self.positions, self.speeds, self.accelerations)
        power = self.power
        for i, name in enumerate(self.names):
            columns[f"tau_{name}"] = self.forces[:, i]
            columns[f"power_{name}"] = power[:, i]
            if self._has_motor(i):
                columns[f"motor_torque_{name}"] = self.motor_torque[:, i]
                columns[f"motor_speed_{name}"] = self.motor_speed[:, i]
        return pd.DataFrame(columns)

    def as_dict(self) -> dict:
        """mechanism, kind, duration (s), samples and coordinates: :meth:`summary`."""
        return {"mechanism": self.mechanism, "kind": self.kind, "duration": self.duration, "samples": len(self.t),
                "coordinates": self.summary()}

    def plot(self, ax: Axes | None = None) -> Figure:
        """Forces against time (drawn into ``ax`` if given), then speeds and power."""
        from ..dynamics.series import unit_label

        figure, axes = stacked_axes(ax, 3, 10.0, 2.3)
        plot_lines(axes[0], self.t, self.forces, self.names, "t (s)", unit_label("force", self.angular, 3),
                   f"{self.mechanism}: {self.kind} loads along the motion")
        if len(axes) > 1:
            plot_lines(axes[1], self.t, self.speeds, self.names, "t (s)", unit_label("speed", self.angular, 1))
            plot_lines(axes[2], self.t, self.power, self.names, "t (s)", "power (W)")
        return figure

    def __str__(self) -> str:
        rows = []
        for i, row in enumerate(self.summary()):
            shared = row.pop("cylinders")
            load = load_label(self.angular[i]) + (f", total of {shared} cylinders" if shared > 1 else "")
            rows.append({"coordinate": row.pop("coordinate"), "load": load, "peak": row.pop("peak_force"),
                         "rms": row.pop("rms_force"),
                         **{k: v for k, v in row.items() if k not in ("load", "unit")}})
        return (f"{self.mechanism}: {self.kind} loads over {self.duration:.3f} s ({len(self.t)} samples)\n"
                + text_table(rows)
                + "\nunits: peak and rms as the load column says (a cylinder's force: all of the cylinders side by "
                  "side together); speed rad/s (a torque's coordinate) or m/s (a force's), power W, work J; motor "
                  "torque N·m, motor speed rad/s")


#: The least time a closed-loop position takes in :func:`trajectory_loads` (assembly, velocity and acceleration
#: analysis, constrained dynamics): s (measured: about 5 ms on a desktop).
CLOSED_LOOP_SECONDS = 1e-3


def loads_bytes(nv: int, closed: bool = False) -> float:
    """Bytes per sample :func:`trajectory_loads` takes for a mechanism of ``nv`` coordinates, closed-loop or not
    (an upper bound, measured with tracemalloc: tests/test_bounded.py)."""
    return 8.0 * (8 + 8 * nv) + (2048.0 if closed else 0.0)


def trajectory_loads(mech: Mechanism, trajectory: Trajectory, loads: Loads = None, *,
                     payload: PayloadSchedule | None = None) -> TrajectoryLoads:
    """Joint (or, for a closed-loop mechanism, actuator) forces along ``trajectory`` (a
    :class:`~mechatron.dynamics.motion.Trajectory` of the joints, or of the actuated coordinates of a closed-loop
    mechanism) under gravity and ``loads``: τ = M q̈ + h − Σ Jᵀ F (RNEA) or the constrained inverse dynamics, with
    the drives' motor side (:func:`~mechatron.drives.transmission.motor_loads`, [Egorov, 4.59]). ``payload``: a
    payload carried on part of the motion only (:class:`~mechatron.dynamics.segments.PayloadSchedule`, a task's
    ``schedule``), attached to ``mech`` at the samples where it is carried."""
    warn_limits(mech, trajectory)
    t = np.asarray(trajectory.t, dtype=float)
    from ..io.budget import count, require, seconds

    fewer = "use fewer samples (a larger time step or a shorter trajectory)"
    require(f"the loads along {count(len(t))} samples", len(t), loads_bytes(mech.nv, bool(mech.closures)),
            advice=fewer)
    if mech.closures:
        seconds(f"the closed-loop loads at {count(len(t))} positions", len(t), CLOSED_LOOP_SECONDS, advice=fewer)
    positions, speeds, accelerations = trajectory.coordinates, trajectory.v, trajectory.a
    if mech.closures:
        names = list(mech.actuated)
        forces = (actuator_forces(mech, trajectory, loads)[1] if payload is None
                  else closed_loop_duty(mech, mech, trajectory, loads, payload).forces)
        angular = [mech.joint_kind(n) == "revolute" for n in names]
        counts = [mech.cylinders[n].count if n in mech.cylinders else 1 for n in names]
        return TrajectoryLoads(mech.name, "actuator", names, angular, t, positions, speeds, accelerations, forces,
                               counts=counts)
    forces = (inverse_dynamics(mech, trajectory.q, speeds, accelerations, loads) if payload is None
              else payload.inverse_dynamics(mech, trajectory.q, speeds, accelerations, loads))
    motor = motor_loads(mech, speeds, accelerations, forces)
    names = coordinate_names(mech)
    driven = [name in mech.drives for name in names]
    return TrajectoryLoads(mech.name, "joint", names, [bool(x) for x in mech.angular_coordinates()], t, positions,
                           speeds, accelerations, forces, motor.torque, motor.speed, driven)

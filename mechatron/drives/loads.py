"""Loads along a motion on both sides of the drives: joint (or actuator) forces, speeds and power, and for joints with
drive data the motor torque and speed (:mod:`mechatron.drives.transmission`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..dynamics.trajectory import actuator_forces
from ..dynamics.tree import inverse_dynamics
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from .transmission import motor_loads

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd


@dataclass
class TrajectoryLoads:
    """Forces along a trajectory: ``table`` has t, every coordinate's q, q̇, q̈, the force/torque of every driven
    coordinate (``tau_<name>``), its power (``power_<name>``) and, for joints with drives, the motor torque and speed;
    ``summary`` per driven coordinate: peak and RMS force, peak speed, peak power, positive work."""

    table: pd.DataFrame
    summary: pd.DataFrame
    names: list[str]


def trajectory_loads(mech: Mechanism, trajectory, loads: Loads = None) -> TrajectoryLoads:
    """Joint (or, for a closed-loop mechanism, actuator) forces along ``trajectory`` (a
    :class:`~mechatron.motion.Trajectory` of the joints, or of the actuated coordinates of a closed-loop
    mechanism), with the drives' motor side (:func:`motor_loads`)."""
    import pandas as pd

    t = np.asarray(trajectory.t, dtype=float)
    if mech.closures:
        forces = actuator_forces(mech, trajectory, loads)[1]
        names, qs, vs, accs, taus = list(mech.actuated), trajectory.q, trajectory.v, trajectory.a, forces
        motor = None
    else:
        names = mech.joint_names
        qs, vs, accs = trajectory.q, trajectory.v, trajectory.a
        taus = inverse_dynamics(mech, qs, vs, accs, loads)
        motor = motor_loads(mech, vs, accs, taus)
    columns: dict[str, np.ndarray] = {"t": t}
    for i, name in enumerate(names):
        columns[name], columns[f"qd_{name}"], columns[f"qdd_{name}"] = qs[:, i], vs[:, i], accs[:, i]
    for i, name in enumerate(names):
        columns[f"tau_{name}"] = taus[:, i]
        columns[f"power_{name}"] = taus[:, i] * vs[:, i]
        if motor is not None and name in mech.drives:
            columns[f"motor_torque_{name}"] = motor.torque[:, i]
            columns[f"motor_speed_{name}"] = motor.speed[:, i]
    table = pd.DataFrame(columns)
    duration = t[-1] - t[0] if len(t) > 1 else 0.0
    rows = []
    for i, name in enumerate(names):
        tau, speed, power = taus[:, i], vs[:, i], taus[:, i] * vs[:, i]
        rms = float(np.sqrt(np.trapezoid(tau**2, t) / duration)) if duration > 0 else float(abs(tau[0]))
        row = {"coordinate": name, "peak_force": float(np.abs(tau).max()), "rms_force": rms,
               "peak_speed": float(np.abs(speed).max()), "peak_power": float(np.abs(power).max()),
               "positive_work": float(np.trapezoid(np.maximum(power, 0.0), t)) if len(t) > 1 else 0.0}
        if motor is not None and name in mech.drives:
            mt = motor.torque[:, i]
            row["peak_motor_torque"] = float(np.abs(mt).max())
            row["rms_motor_torque"] = float(np.sqrt(np.trapezoid(mt**2, t) / duration)) if duration > 0 else 0.0
            row["peak_motor_speed"] = float(np.abs(motor.speed[:, i]).max())
        rows.append(row)
    return TrajectoryLoads(table, pd.DataFrame(rows), names)

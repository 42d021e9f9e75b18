"""The ``dynamics`` analysis of a study: the peak and RMS load of every actuator along a motion.

The motion is a synchronised point-to-point move from ``start`` to ``end`` (one coordinate per joint of a serial
arm, or per actuated input of a closed loop; rad and m, or ``start_deg``/``end_deg`` with the angles in degrees)
with the ``profile`` (default trapezoidal) and the limits ``vmax``, ``amax`` (:func:`mechatron.dynamics.motion.move`)
sampled every ``dt`` s; or the trajectory of a ``task`` file (its payload and loads included, a payload carried on
part of the task only where it is carried: ``payload_from``, ``payload_until``, :mod:`mechatron.dynamics.segments`,
as ``mechatron size`` and :func:`mechatron.drives.loads.trajectory_loads` take it); or, with neither,
the mechanism's default task (:func:`mechatron.dynamics.task.default_task`).

The loads: for a serial arm the joint torques and forces τ = M(q) q̈ + C(q, q̇) q̇ + g(q) (RNEA,
:func:`mechatron.dynamics.tree.inverse_dynamics`), for a closed loop the actuator forces of the constrained inverse
dynamics (:func:`mechatron.dynamics.trajectory.actuator_forces`). Per actuator: the peak max |τ| and the RMS
√(∫τ² dt / T) (trapezoidal rule over the samples), in N·m for an angle (``NAME_peak_Nm``, ``NAME_rms_Nm``) and N
for a displacement (``NAME_peak_N``, ``NAME_rms_N``).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import InputError
from ...io.values import number, numbers

OUTPUTS = ("ACTUATOR_peak_Nm", "ACTUATOR_rms_Nm", "ACTUATOR_peak_N", "ACTUATOR_rms_N")

#: The options and their defaults.
DEFAULTS = {"start": None, "end": None, "start_deg": None, "end_deg": None, "profile": "trapezoidal",
            "vmax": None, "amax": None, "dt": 0.005, "duration": None, "task": None}


def _field(name: str, read):
    """``read()``, its error naming the option ``name``."""
    try:
        return read()
    except InputError as exc:
        raise InputError(exc.message, field=name) from None


def _coordinates(mech) -> tuple[list[str], np.ndarray]:
    """The moving coordinates' names and which are angles: the joints of a serial arm, the inputs of a loop."""
    from ...dynamics.motion import coordinate_names

    if mech.closures:
        from ...kinematics.loops import loop_solver

        solver = loop_solver(mech)
        revolute = mech.angular_coordinates()
        return list(mech.actuated), np.array([bool(revolute[solver.index[n]]) for n in mech.actuated])
    return coordinate_names(mech), np.asarray(mech.angular_coordinates(), dtype=bool)


def _pose(opts: dict[str, Any], key: str, angular: np.ndarray) -> np.ndarray | None:
    given = [k for k in (key, f"{key}_deg") if opts[k] is not None]
    if len(given) > 1:
        raise InputError(f"give {key} or {key}_deg, not both", field=key)
    if not given:
        return None
    values = _field(given[0], lambda: numbers(given[0], opts[given[0]], shape=(len(angular),), unit="rad or m"))
    return np.where(angular, np.radians(values), values) if given[0].endswith("_deg") else values


def _options(mech, options: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(options) - set(DEFAULTS))
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (options: {', '.join(DEFAULTS)})", field=unknown[0])
    opts = {**DEFAULTS, **options}
    names, angular = _coordinates(mech)
    opts["names"], opts["angular"] = names, angular
    opts["start"], opts["end"] = _pose(opts, "start", angular), _pose(opts, "end", angular)
    if (opts["start"] is None) != (opts["end"] is None):
        raise InputError("a move needs both start and end", field="end" if opts["end"] is None else "start")
    if opts["start"] is not None and opts["task"] is not None:
        raise InputError("give a move (start, end) or a task, not both", field="task")
    from ...dynamics.motion import PROFILES

    if opts["profile"] not in PROFILES:
        raise InputError(f"unknown profile {opts['profile']!r}; expected one of: {', '.join(PROFILES)}",
                         field="profile")
    opts["dt"] = _field("dt", lambda: number("dt", opts["dt"], positive=True, unit="s"))
    for key in ("vmax", "amax"):
        if opts[key] is not None:
            opts[key] = _field(key, lambda k=key: numbers(k, np.broadcast_to(opts[k], (len(names),)),
                                                          positive=True))
    return opts


def check(mech, options: dict[str, Any]) -> None:
    """Refuse wrong options (see the module docstring) before any design runs; a task file is read once."""
    opts = _options(mech, options)
    if opts["task"] is not None:
        from ...dynamics.task import read_task

        read_task(opts["task"], mech)


def output_names(mech, options: dict[str, Any]) -> list[str]:
    """The names of the outputs for ``options`` without running: the peak and RMS load of every moving coordinate
    (``NAME_peak_Nm``, ``NAME_rms_Nm`` for an angle, ``NAME_peak_N``, ``NAME_rms_N`` for a displacement)."""
    opts = _options(mech, options)
    return [f"{name}_{kind}_{'Nm' if angle else 'N'}" for name, angle in zip(opts["names"], opts["angular"])
            for kind in ("peak", "rms")]


def task_files(path: str | Path | None, mech) -> list[Path]:
    """The files a task reads: the task file ``path`` (None: the mechanism's own ``robots/tasks/NAME.toml``, if
    any) and the trajectory CSV a task TOML names (relative to the task file's folder)."""
    from ...dynamics.task import task_file
    from ...io.toml import read_toml

    path = task_file(mech) if path is None else Path(path)
    if path is None:
        return []
    named = read_toml(path).get("trajectory") if path.suffix.lower() == ".toml" else None
    if not isinstance(named, str):
        return [path]
    return [path, Path(named) if Path(named).is_absolute() else path.parent / named]


def input_files(mech, options: dict[str, Any]) -> list[Path]:
    """The files the outputs of one design read: the task's (:func:`task_files`; none for a move)."""
    opts = _options(mech, options)
    return [] if opts["start"] is not None else task_files(opts["task"], mech)


def _motion(mech, opts: dict[str, Any]):
    """(mechanism with the task's payload, trajectory, loads, schedule) of one design; with a payload carried on
    part of the task (``payload_from``, ``payload_until``) the mechanism without it and the task's
    :class:`~mechatron.dynamics.segments.PayloadSchedule`, else ``None``."""
    from ...dynamics.motion import move
    from ...dynamics.task import default_task, read_task

    if opts["start"] is not None:
        trajectory = move(None if mech.closures else mech, opts["start"], opts["end"], profile=opts["profile"],
                          vmax=opts["vmax"], amax=opts["amax"], duration=opts["duration"], dt=opts["dt"])
        return mech, trajectory, None, None
    task = read_task(opts["task"], mech) if opts["task"] is not None else default_task(mech)
    if task.schedule is not None:
        return task.unloaded, task.trajectory, task.loads or None, task.schedule
    return task.mechanism, task.trajectory, task.loads or None, None


def outputs(mech, options: dict[str, Any], seed: int) -> dict[str, float]:
    """Peak and RMS load of every actuator (N·m or N) along the motion. ``seed`` is not used (no random draw)."""
    opts = _options(mech, options)
    mech, trajectory, loads, schedule = _motion(mech, opts)
    if mech.closures and schedule is not None:
        from ...dynamics.segments import closed_loop_duty

        loads_ = closed_loop_duty(mech, mech, trajectory, loads, schedule).forces
    elif mech.closures:
        from ...dynamics.trajectory import actuator_forces

        _, loads_ = actuator_forces(mech, trajectory, loads)
    elif schedule is not None:
        loads_ = schedule.inverse_dynamics(mech, trajectory.q, trajectory.v, trajectory.a, loads)
    else:
        from ...dynamics.tree import inverse_dynamics

        loads_ = np.atleast_2d(inverse_dynamics(mech, trajectory.q, trajectory.v, trajectory.a, loads))
    t = trajectory.t
    span = t[-1] - t[0]
    out = {}
    for j, (name, angle) in enumerate(zip(opts["names"], opts["angular"])):
        tau = loads_[:, j]
        unit = "Nm" if angle else "N"
        rms = math.sqrt(np.trapezoid(tau**2, t) / span) if span > 0 else float(np.abs(tau).max())
        out[f"{name}_peak_{unit}"] = float(np.abs(tau).max())
        out[f"{name}_rms_{unit}"] = rms
    return out

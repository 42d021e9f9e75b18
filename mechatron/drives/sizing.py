r"""Motor, converter and ratio selection for every driven joint of a mechanism doing a task: :func:`size`.

The sizing in parts: one joint's choice and its explanation (:mod:`~mechatron.drives.joint`, the objectives), the
search over the motor × converter pairs (:mod:`~mechatron.drives.search`), the mechanism as a system — the drives'
masses loading it until the choice no longer changes — (:mod:`~mechatron.drives.system`), what the sizing
returns (:mod:`~mechatron.drives.result`) and its options as one value, with their defaults
(:class:`~mechatron.drives.options.SizingOptions`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from .joint import JointSizing, size_joint
from .options import (
    CHAIN_EFFICIENCY,
    INERTIA_RATIO_MAX,
    MAX_ITERATIONS,
    MAX_PASSES,
    MIN_EFFICIENCY,
    OBJECTIVE,
    OBJECTIVES,
    PRESSURE,
    SizingOptions,
)
from .result import Iteration, SizingResult
from .search import fastest_scale
from .system import size_mechanism, sizing_bytes, sizing_fixed_bytes

if TYPE_CHECKING:  # pragma: no cover
    from collections.abc import Callable

    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task
    from ..model.loads import Loads
    from ..model.mechanism import Mechanism
    from .checks import DriveLimits
    from .report import DriveSizing

__all__ = ["MAX_ITERATIONS", "MAX_PASSES", "MIN_EFFICIENCY", "OBJECTIVES", "Iteration", "JointSizing", "SizingOptions",
           "SizingResult", "fastest_scale", "size", "size_joint", "size_mechanism", "sizing_bytes",
           "sizing_fixed_bytes"]


def size(mech: Mechanism, task: Task | Trajectory | str | Path | None = None, *,
         motors: pd.DataFrame | str | Path | None = None, gearboxes: pd.DataFrame | str | Path | None = None,
         linear: pd.DataFrame | str | Path | None = None, cylinders: pd.DataFrame | str | Path | None = None,
         objective: str = OBJECTIVE, loads: Loads = None, inertia_ratio_max: float = INERTIA_RATIO_MAX,
         direct: bool = True, pressure: float = PRESSURE, chain_efficiency: float = CHAIN_EFFICIENCY,
         single_pass: bool = False, max_iterations: int = MAX_ITERATIONS,
         progress: Callable[[int, int], None] | None = None, limits: DriveLimits | None = None,
         start: dict[str, DriveSizing] | None = None, options: SizingOptions | None = None,
         resistors: pd.DataFrame | str | Path | None = None, regenerative_supply: bool = False,
         resistor_min: float = 0.0, drives: pd.DataFrame | str | Path | None = None,
         altitude: float = 0.0) -> SizingResult:
    """Choose the drive of every joint of ``mech`` for a task — motor, gearbox and ratio (revolute joints), motor
    and ball screw or rack (prismatic joints), catalog cylinder (hydraulic cylinders of a closed-loop mechanism) —
    with every check vendors run (:mod:`~mechatron.drives.checks`, :mod:`~mechatron.drives.cylinders`), the chosen
    drives' masses loading the mechanism until the choice no longer changes (:func:`size_mechanism`).

    ``mechatron.size(puma)`` sizes the PUMA 560 for its own task with the example catalogs;
    ``mechatron.size(puma, "pick.toml", motors="motors.csv", objective="cost")`` for a task file and a catalog;
    ``mechatron.size(puma, options=SizingOptions(objective="cost", inertia_ratio_max=5.0))`` with the options as
    one value (:class:`~mechatron.drives.options.SizingOptions`, checked when made).

    Args:
        mech: The mechanism (carrying a payload: :func:`~mechatron.model.payload.with_payload`, which
            ``mechatron size --payload MASS --payload-at POINT`` applies; a task file's payload comes on top).
        task: What the mechanism must do:

            - ``None``: its default task (``robots/tasks/<name>.toml`` if there is one, else a generic
              out-and-back move of every coordinate, :func:`~mechatron.dynamics.task.default_task`);
            - the path of a task file (TOML: waypoints, profile, payload in kg at a frame or point with its centre
              and inertia, loads; or a trajectory CSV), read for ``mech``
              (:func:`~mechatron.dynamics.task.read_task`);
            - a :class:`~mechatron.dynamics.task.Task` (its mechanism, payload included, is the one sized);
            - a :class:`~mechatron.dynamics.motion.Trajectory` of ``mech``'s joints (rad, m; s), or of its actuated
              coordinates if it has closed loops.
        motors, gearboxes, linear, cylinders: Catalogs: DataFrames in SI
            (:func:`~mechatron.drives.catalogs.read_catalog`) or CSV paths; the example catalogs where left out.
        objective, inertia_ratio_max, direct, pressure, chain_efficiency, single_pass, max_iterations, limits: The
            fields of :class:`~mechatron.drives.options.SizingOptions` as keywords, their defaults its: the
            objective (``"mass"``, ``"cost"``, ``"margin"`` or ``"time"``, :mod:`mechatron.drives.joint`), the
            largest load-to-motor inertia ratio (J_L/u² + J_c)/J_m, whether gearless (direct-drive) motors are
            tried, the hydraulic system's relief pressure (Pa), the efficiency of the rest of the chain (couplings,
            bearings, belts; η = Π η_i [Egorov, 7.53]; it multiplies every converter's), one pass with weightless
            drives instead of the fixed point, the most passes of the fixed point (≥ 2), and the emergency-stop
            torque or current limit, required screw life, supply voltage and ambient temperature
            (:class:`~mechatron.drives.checks.DriveLimits`; default: the motors' peak torque, 20 000 h, the
            catalog's voltage, 40 °C).
        loads: External loads (:class:`mechatron.model.Load`; N, N·m) in addition to the task's own.
        drives: A servo drive catalog (kind ``drives``): each motor is paired with every drive
            (:func:`~mechatron.drives.servo.pair_drives`) and the pairs checked with the drive's checks; ``None``
            (the default): no drive, the sizing as without one.
        altitude: The site's altitude (m), a field of :class:`~mechatron.drives.options.SizingOptions`: the S1
            derating (:mod:`~mechatron.drives.derating`).
        progress: Called with (done, total) after each coordinate of each pass.
        limits: The emergency-stop torque or current limit, the required screw life and the supply voltage
            (:class:`~mechatron.drives.checks.DriveLimits`); default: the motors' peak torque, 20 000 h, the
            catalog's voltage.
        start: Drives to start the fixed point from (another design's ``{d.joint: d for d in result.joints}``):
            the same result, sooner where the drives load only coordinates sized after them
            (:func:`~mechatron.drives.system.size_mechanism`).
        options: The options as one :class:`~mechatron.drives.options.SizingOptions`, instead of the keywords
            (a keyword given with it is an :class:`~mechatron.errors.InputError`).
        resistors, regenerative_supply, resistor_min: The DC bus's braking resistor chosen from a catalog of kind
            ``resistors`` (a DataFrame in SI or a CSV path) with the drive's smallest resistance ``resistor_min``
            (Ω), or (``regenerative_supply``) no resistor but a regenerative supply's rating
            (:func:`~mechatron.drives.resistors.size_braking`, in ``result.braking`` and the totals).

    Returns:
        A :class:`SizingResult`; ``result.feasible`` is false when some joint has no feasible drive (its closest
        candidates are reported) or the choice did not settle. It keeps the task it sized (``result.given``) for
        its report.
    """
    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task, default_task, read_task
    from ..model.loads import as_loads

    options = SizingOptions.of(options, objective=objective, inertia_ratio_max=inertia_ratio_max, direct=direct,
                               pressure=pressure, chain_efficiency=chain_efficiency, single_pass=single_pass,
                               max_iterations=max_iterations, limits=limits, altitude=altitude)
    if drives is not None:  # every motor paired with every drive (mechatron.drives.servo)
        from .catalogs import default_catalog
        from .servo import pair_drives

        motors = pair_drives(_catalog(motors, "motors") if motors is not None else default_catalog("motors"),
                             _catalog(drives, "drives"), options.limits.voltage)
    if task is None:
        task = default_task(mech)
    elif isinstance(task, Trajectory):
        task = Task("trajectory", mech, task)
    elif not isinstance(task, Task):
        task = read_task(task, mech)
    mechanism = task.mechanism if task.schedule is None or task.unloaded is None else task.unloaded
    result = size_mechanism(mechanism, task.trajectory, _catalog(motors, "motors"),
                            _catalog(gearboxes, "gearboxes"), _catalog(linear, "linear"),
                            _catalog(cylinders, "cylinders"), payload=task.schedule,
                            loads=[*as_loads(task.loads), *as_loads(loads)], task=task.name, progress=progress,
                            start=start, options=options)
    result.given = task
    if resistors is not None or regenerative_supply:
        result.braking = _braking(result, _catalog(resistors, "resistors"), regenerative_supply, resistor_min,
                                  options)
    return result


def _braking(result: SizingResult, resistors: pd.DataFrame | None, regenerative: bool, resistor_min: float,
             options: SizingOptions):
    """The braking resistor or regenerative supply of ``result``'s DC bus; U_max the option's supply voltage, else
    the largest catalog voltage of the chosen motors (NaN where none gives one)."""
    import math

    from .resistors import size_braking

    balance = result.electrical_balance()
    if balance is None:
        return None
    voltages = [j.motor_number("voltage") for j in result.joints if hasattr(j, "motor_number")]
    known = [float(v) for v in voltages if v is not None and math.isfinite(float(v))]
    voltage = options.limits.voltage or (max(known) if known else math.nan)
    return size_braking(balance.t, balance.bus_power, resistors, regenerative=regenerative, bus_voltage=voltage,
                        resistor_min=resistor_min, objective=options.objective)


def _catalog(value: pd.DataFrame | str | Path | None, kind: str) -> pd.DataFrame | None:
    """A catalog of ``kind`` given to :func:`size`: a DataFrame as it is, a path read
    (:func:`~mechatron.drives.catalogs.read_catalog`), ``None`` (the example one, where needed) as it is."""
    from .catalogs import read_catalog

    return read_catalog(value, kind) if value is not None and not isinstance(value, pd.DataFrame) else value

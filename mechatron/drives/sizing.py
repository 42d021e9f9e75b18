r"""Motor, converter and ratio selection for every driven joint of a mechanism doing a task: :func:`size`.

The sizing in parts: one joint's choice and its explanation (:mod:`~mechatron.drives.joint`, the objectives), the
search over the motor × converter pairs (:mod:`~mechatron.drives.search`), the mechanism as a system — the drives'
masses loading it until the choice no longer changes — (:mod:`~mechatron.drives.system`) and what the sizing
returns (:mod:`~mechatron.drives.result`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from .checks import DriveLimits
from .joint import OBJECTIVES, JointSizing, size_joint
from .result import Iteration, SizingResult
from .search import fastest_scale
from .system import (
    MAX_ITERATIONS,
    MAX_PASSES,
    MIN_EFFICIENCY,
    check_arguments,
    size_mechanism,
    sizing_bytes,
    sizing_fixed_bytes,
)

if TYPE_CHECKING:  # pragma: no cover
    from collections.abc import Callable

    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task
    from ..model.loads import Loads
    from ..model.mechanism import Mechanism
    from .report import DriveSizing

__all__ = ["MAX_ITERATIONS", "MAX_PASSES", "MIN_EFFICIENCY", "OBJECTIVES", "Iteration", "JointSizing", "SizingResult",
           "fastest_scale", "size", "size_joint", "size_mechanism", "sizing_bytes", "sizing_fixed_bytes"]


def size(mech: Mechanism, task: Task | Trajectory | str | Path | None = None, *,
         motors: pd.DataFrame | str | Path | None = None, gearboxes: pd.DataFrame | str | Path | None = None,
         linear: pd.DataFrame | str | Path | None = None, cylinders: pd.DataFrame | str | Path | None = None,
         objective: str = "mass", loads: Loads = None, inertia_ratio_max: float = 10.0, direct: bool = True,
         pressure: float = 32e6, chain_efficiency: float = 1.0, single_pass: bool = False,
         max_iterations: int = MAX_ITERATIONS, progress: Callable[[int, int], None] | None = None,
         limits: DriveLimits | None = None, start: dict[str, DriveSizing] | None = None) -> SizingResult:
    """Choose the drive of every joint of ``mech`` for a task — motor, gearbox and ratio (revolute joints), motor
    and ball screw or rack (prismatic joints), catalog cylinder (hydraulic cylinders of a closed-loop mechanism) —
    with every check vendors run (:mod:`~mechatron.drives.checks`, :mod:`~mechatron.drives.cylinders`), the chosen
    drives' masses loading the mechanism until the choice no longer changes (:func:`size_mechanism`).

    ``mechatron.size(puma)`` sizes the PUMA 560 for its own task with the example catalogs;
    ``mechatron.size(puma, "pick.toml", motors="motors.csv", objective="cost")`` for a task file and a catalog.

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
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"`` (:mod:`mechatron.drives.sizing`).
        loads: External loads (:class:`mechatron.model.Load`; N, N·m) in addition to the task's own.
        inertia_ratio_max: The largest load-to-motor inertia ratio allowed.
        direct: Whether gearless (direct-drive) motors are tried.
        pressure: The hydraulic system's relief pressure (Pa).
        chain_efficiency: The efficiency of the rest of the chain (couplings, bearings, belts; η = Π η_i
            [Egorov, 7.53]); multiplies every converter's.
        single_pass: Size each coordinate once with weightless drives instead of to the fixed point.
        max_iterations: The most passes of the fixed point (≥ 2).
        progress: Called with (done, total) after each coordinate of each pass.
        limits: The emergency-stop torque or current limit, the required screw life and the supply voltage
            (:class:`~mechatron.drives.checks.DriveLimits`); default: the motors' peak torque, 20 000 h, the
            catalog's voltage.
        start: Drives to start the fixed point from (another design's ``{d.joint: d for d in result.joints}``):
            the same result, sooner where the drives load only coordinates sized after them
            (:func:`~mechatron.drives.system.size_mechanism`).

    Returns:
        A :class:`SizingResult`; ``result.feasible`` is false when some joint has no feasible drive (its closest
        candidates are reported) or the choice did not settle. It keeps the task it sized (``result.given``) for
        its report.
    """
    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task, default_task, read_task
    from ..model.loads import as_loads
    from .catalogs import read_catalog

    check_arguments(inertia_ratio_max, pressure, chain_efficiency, max_iterations)
    if task is None:
        task = default_task(mech)
    elif isinstance(task, Trajectory):
        task = Task("trajectory", mech, task)
    elif not isinstance(task, Task):
        task = read_task(task, mech)
    catalogs = {kind: read_catalog(value, kind) if value is not None and not isinstance(value, pd.DataFrame)
                else value for kind, value in (("motors", motors), ("gearboxes", gearboxes), ("linear", linear),
                                               ("cylinders", cylinders))}
    result = size_mechanism(task.mechanism if task.schedule is None else task.unloaded, task.trajectory,
                            **catalogs, objective=objective, payload=task.schedule,
                            inertia_ratio_max=inertia_ratio_max, loads=[*as_loads(task.loads), *as_loads(loads)],
                            task=task.name, direct=direct, pressure=pressure, chain_efficiency=chain_efficiency,
                            single_pass=single_pass, max_iterations=max_iterations, progress=progress,
                            limits=limits, start=start)
    result.given = task
    return result

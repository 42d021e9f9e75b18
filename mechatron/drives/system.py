r"""The drives of a mechanism sized as a system (:func:`size_mechanism`): the duty of every driven coordinate from the
dynamics, each sized alone (:func:`~mechatron.drives.joint.size_joint`,
:func:`~mechatron.drives.cylinders.size_cylinder`), then again distal to proximal with every chosen drive's mass on
the body that carries it, until the choice no longer changes (the fixed point).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ..dynamics.motion import warn_limits
from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Cylinder, Mechanism
from .checks import DriveLimits, MotorArrays
from .converters import Converters, converters_for
from .duty import DriveMount, JointDuty, drive_carrier, joint_duties, mount_drives
from .joint import size_joint
from .options import (
    CHAIN_EFFICIENCY,
    INERTIA_RATIO_MAX,
    MAX_ITERATIONS,
    OBJECTIVE,
    PRESSURE,
    SizingOptions,
)
from .report import DriveSizing
from .result import Iteration, SizingResult
from .search import CHUNK, fastest_scale, motor_passes

if TYPE_CHECKING:  # pragma: no cover
    from ..dynamics.motion import Trajectory
    from ..dynamics.segments import PayloadSchedule


#: The arrays built from catalogs that do not change (:func:`keep_arrays`), by the catalog's id: (the catalog,
#: weakly; its arrays by what they were built for).
_kept: dict[int, tuple[weakref.ref, dict]] = {}


def keep_arrays(catalog: pd.DataFrame) -> pd.DataFrame:
    """``catalog``, marked as one that does not change (a catalog read once per process, e.g. by a study): the
    arrays a sizing builds from it — the motors' (:class:`~mechatron.drives.checks.MotorArrays`), the converters to
    try (:func:`~mechatron.drives.converters.converters_for`) — are then built once, not once per sizing."""
    key = id(catalog)
    _kept[key] = (weakref.ref(catalog, lambda _, key=key: _kept.pop(key, None)), {})
    return catalog


def _arrays_of(catalog: pd.DataFrame | None, key: tuple, build: Callable[[], object]):
    """``build()``, once per ``key`` for a catalog of :func:`keep_arrays`, else every time."""
    entry = _kept.get(id(catalog)) if catalog is not None else None
    if entry is None or entry[0]() is not catalog:
        return build()
    if key not in entry[1]:
        entry[1][key] = build()
    return entry[1][key]


def distal_first(mech: Mechanism, names: list[str]) -> list[str]:
    """``names`` ordered distal to proximal: by the depth of their joint in the tree, deepest first (stable)."""
    def depth(name: str) -> int:
        joint, count = mech.joint_id(name), 0
        while joint > 0:
            joint, count = mech.model.parents[joint], count + 1
        return count

    return sorted(names, key=lambda n: -depth(n))


def sizing_bytes(nv: int, single_pass: bool = False) -> float:
    """Bytes per sample a sizing of a mechanism of ``nv`` coordinates keeps beyond its loads (the trajectory, the
    duties and, for the fixed point, the mounted mechanism's dynamics of every pass; an upper bound,
    tests/test_bounded.py): the per-pair checks go a block at a time
    (:data:`~mechatron.drives.checks.SAMPLE_BLOCK`) and do not grow with the task."""
    return 8.0 * (64 + (16 if single_pass else 48) * nv)


def sizing_fixed_bytes(samples: float = math.inf, converters: int = 512, pairs: int = 2 * CHUNK) -> float:
    """Bytes of the per-converter time means (converters × samples, a block of at most
    :data:`~mechatron.drives.checks.SAMPLE_BLOCK` elements, a few arrays of them at once) and of the pairs evaluated
    at a time (at most two :data:`CHUNK` of them, 160 bytes each: indices, scores, checks), for a task of
    ``samples`` samples and a joint with ``converters`` converters and ``pairs`` motor × converter pairs: they stop
    growing with the task at the block's size and with the catalogs at the chunk's."""
    from . import checks

    return 8.0 * 8 * min(checks.SAMPLE_BLOCK, converters * samples) + 160.0 * min(pairs, 2 * CHUNK)


def _catalog_counts(motors: pd.DataFrame | None, gearboxes: pd.DataFrame | None, linear: pd.DataFrame | None
                    ) -> tuple[int, int]:
    """(converters, pairs) of the largest joint the catalogs (the example ones where left out) can give."""
    from .catalogs import default_catalog

    def rows(catalog: pd.DataFrame | None, kind: str) -> int:
        return len(catalog if catalog is not None else default_catalog(kind))

    converters = max(rows(gearboxes, "gearboxes") + 1, rows(linear, "linear"))
    return converters, rows(motors, "motors") * converters


def size_mechanism(mech: Mechanism, trajectory: Trajectory, motors: pd.DataFrame | None = None,
                   gearboxes: pd.DataFrame | None = None, linear: pd.DataFrame | None = None,
                   cylinders: pd.DataFrame | None = None, *, objective: str = OBJECTIVE,
                   inertia_ratio_max: float = INERTIA_RATIO_MAX, loads: Loads = None, task: str = "task",
                   direct: bool = True, pressure: float = PRESSURE, chain_efficiency: float = CHAIN_EFFICIENCY,
                   single_pass: bool = False, max_iterations: int = MAX_ITERATIONS,
                   progress: Callable[[int, int], None] | None = None,
                   limits: DriveLimits | None = None, payload: PayloadSchedule | None = None,
                   start: dict[str, DriveSizing] | None = None, options: SizingOptions | None = None
                   ) -> SizingResult:
    """Size every coordinate of ``mech`` that moves or carries load along ``trajectory``, as a system.

    The duty of every coordinate comes from the inverse dynamics without drive inertia
    (:func:`~mechatron.drives.duty.joint_duties`); then motors with gearboxes (revolute joints) or linear drives —
    ball screws, racks — (prismatic joints) are checked pair by pair (:func:`size_joint`), catalog cylinders for
    hydraulic cylinders (:func:`~mechatron.drives.cylinders.size_cylinder`).

    The drives load the mechanism (:class:`FixedPoint`). Pass 1 sizes every coordinate with weightless drives
    (all a ``single_pass`` sizing does). Each further pass goes distal to proximal: each coordinate is sized with
    every drive chosen so far (this pass's, else the last pass's) on the body that carries it
    (:func:`~mechatron.drives.duty.mount_drives`: its motor's and converter's catalog mass at its placement, by
    default on the joint's parent body at the joint), until a pass chooses what the one before chose: the fixed
    point, where every drive was sized with every other final drive's mass in the model. A drive's spinning parts
    (rotor J_m, the converter's motor side J_c) are counted once, in its own joint's motor torque (J_m + J_c) u ω̇
    (Pinocchio's armature (J_m + J_c) u²), never as a body inertia. A choice that comes back after changing is a
    cycle: the sizing stops and says so, as it does after ``max_iterations`` passes; the result is then not
    feasible. Hydraulic cylinders are sized in the same passes; their masses are the mechanism file's
    (``barrel_mass``, ``rod_mass``), not the catalog's.

    A mechanism whose link masses include its drives (:attr:`~mechatron.model.Mechanism.link_masses_include_drives`:
    a robot file's ``link_masses_include_drives = true``, a URDF's ``<mechatron link_masses_include_drives="true"/>``,
    the example-robot-data arms) gets no drive's mass added: the included masses stand for the chosen drives, so pass
    1, with the link masses as given, is the fixed point — the choice and the duties of ``single_pass`` — and the
    result says so (:attr:`SizingResult.masses_included`); the mounts are still reported, with the chosen drives'
    catalog masses, loading nothing.

    Args:
        mech: The mechanism, payload included (:func:`mechatron.model.payload.with_payload`).
        trajectory: A :class:`~mechatron.dynamics.motion.Trajectory` of the joints (rad, m; s), or of the actuated
            coordinates of a closed-loop mechanism.
        motors, gearboxes, linear, cylinders: Catalogs in SI (:func:`~mechatron.drives.catalogs.read_catalog`); one
            left out is the example one shipped in ``catalogs/``, when the mechanism needs it.
        objective, inertia_ratio_max, direct, pressure, chain_efficiency, single_pass, max_iterations, limits: The
            fields of :class:`~mechatron.drives.options.SizingOptions` as keywords (their defaults are its):
            the objective (``"mass"``, ``"cost"``, ``"margin"`` or ``"time"``), the largest load-to-motor inertia
            ratio (J_L/u² + J_c)/J_m, whether gearless motors are tried, the relief pressure (Pa), the efficiency
            of the rest of the chain (η = Π η_i [Egorov, 7.53], :func:`mechatron.mechanics.efficiency.series`),
            one pass with weightless drives, the most passes (≥ 2), the emergency-stop limit, screw life, supply
            voltage and ambient (:class:`~.checks.DriveLimits`).
        loads: External loads (:class:`mechatron.model.Load`: force in N, moment in N·m) held along the task.
        task: The task's name, for reports.
        progress: Called with (done, total) after each coordinate of each pass.
        payload: A payload carried on part of the trajectory only (a task's
            :class:`~mechatron.dynamics.segments.PayloadSchedule`; ``mech`` then without it): every pass attaches
            it, at the samples where it is carried, to the mechanism with that pass's drives.
        start: Drives (by coordinate) to start the fixed point from, e.g. another design's choice in a study: used
            only where every drive loads only coordinates sized after it (:func:`sees_every_drive`: a serial arm with
            its drives on the proximal links), where pass 1 then sizes each coordinate with the drives chosen
            distal to it already — the fixed point at once, whatever ``start`` is (a coordinate's torque
            τ_k = S_kᵀ Σ_{i ∈ subtree(k)} f_i and its inertia M_kk involve the bodies it moves only), so that pass 2
            only confirms it; ``start`` saves the inverse dynamics of the drives it guessed right. Not with the
            ``time`` objective (its pace is the slowest coordinate's, over every duty).
        options: The options as one :class:`~mechatron.drives.options.SizingOptions`, instead of the keywords (a
            keyword given with it is an :class:`~mechatron.errors.InputError`).
    """
    from ..io.budget import count, require
    from .derating import derate
    from .loads import loads_bytes
    from .thermal import ZERO_CELSIUS

    options = SizingOptions.of(options, objective=objective, inertia_ratio_max=inertia_ratio_max, direct=direct,
                               pressure=pressure, chain_efficiency=chain_efficiency, single_pass=single_pass,
                               max_iterations=max_iterations, limits=limits)
    warn_limits(mech, trajectory, f"task '{task}'")
    given = {"motors": motors, "gearboxes": gearboxes, "linear": linear, "cylinders": cylinders}
    examples = _examples(given, ("motors", "gearboxes", "linear"))  # read once: for the budget and the sizing
    counted = {**given, **examples}
    require(f"sizing along {count(len(trajectory.t))} samples of {mech.name}", len(trajectory.t),
            sizing_bytes(mech.nv, options.single_pass) + loads_bytes(mech.nv, bool(mech.closures)),
            fixed=sizing_fixed_bytes(len(trajectory.t), *_catalog_counts(counted["motors"], counted["gearboxes"],
                                                                         counted["linear"])),
            advice="use fewer samples (a larger time step of the trajectory)")
    bare = {d.name: d for d in joint_duties(mech, trajectory, loads, payload=payload)
            if np.abs(d.speed).max() > 0 or np.abs(d.torque).max() > 0}
    if not bare:
        raise InputError(f"no joint of {mech.name} moves or carries load in the task")
    kinds = {d.kind for d in bare.values()}
    needed = {"motors": not kinds <= {"cylinder"}, "gearboxes": "revolute" in kinds, "linear": "prismatic" in kinds,
              "cylinders": "cylinder" in kinds}
    examples.update(_examples(given, tuple(kind for kind in given if needed[kind] and kind not in examples)))
    catalogs = {kind: value if value is not None else examples[kind] if needed[kind] else None
                for kind, value in given.items()}
    if catalogs["motors"] is not None:  # the S1 curve derated for the site (mechatron.drives.derating)
        catalogs["motors"] = derate(catalogs["motors"], options.limits.ambient - ZERO_CELSIUS, options.altitude)
    return FixedPoint(mech, trajectory, bare, catalogs, options, loads, payload, progress).solve(start, task)


def _examples(catalogs: dict[str, pd.DataFrame | None], kinds: tuple[str, ...]) -> dict[str, pd.DataFrame]:
    """The example catalogs (shipped in ``catalogs/``) of those of ``kinds`` that ``catalogs`` leaves out, read."""
    from .catalogs import default_catalog

    return {kind: default_catalog(kind) for kind in kinds if catalogs[kind] is None}


class FixedPoint:
    """The fixed point of :func:`size_mechanism` for one mechanism, task and options: the passes over the
    coordinates (:meth:`run_pass`), each coordinate sized (:meth:`size_one`) with the drives chosen so far on their
    bodies (:meth:`duties_with`), and what repeats between passes kept — the sizings by duty and pace
    (``sized``), the converters by kind (``built``), the fastest paces by duty (``fastest``), the loaded duties of
    the last mounted drives (``known``).

    Args:
        mech, trajectory, loads, payload, progress: Those of :func:`size_mechanism`.
        bare: The duties (by coordinate) without drives, of the coordinates that move or carry load.
        catalogs: ``motors``, ``gearboxes``, ``linear``, ``cylinders``: the catalogs in SI (``None`` where the
            mechanism needs none).
        options: The sizing's :class:`~mechatron.drives.options.SizingOptions`, checked.
    """

    def __init__(self, mech: Mechanism, trajectory: Trajectory, bare: dict[str, JointDuty],
                 catalogs: dict[str, pd.DataFrame | None], options: SizingOptions, loads: Loads = None,
                 payload: PayloadSchedule | None = None, progress: Callable[[int, int], None] | None = None):
        from .cylinders import cylinder_lengths

        self.mech, self.trajectory, self.bare, self.options = mech, trajectory, bare, options
        self.loads, self.payload, self.progress = loads, payload, progress
        self.motors, self.gearboxes = catalogs["motors"], catalogs["gearboxes"]
        self.linear, self.cylinders = catalogs["linear"], catalogs["cylinders"]
        motors = self.motors
        self.motor_arrays = (_arrays_of(motors, ("motors",), lambda: MotorArrays.of(motors))
                             if motors is not None else None)
        self.names = list(bare)
        self.order = distal_first(mech, self.names)
        self.carriers = {n: drive_carrier(mech, n) for n in self.names if bare[n].kind != "cylinder"}
        self.lengths = cylinder_lengths(mech, trajectory)
        self.sized: dict[tuple, DriveSizing] = {}
        self.built: dict[tuple, Converters] = {}
        self.fastest: dict[tuple, float] = {}
        self.known: dict[tuple, dict[str, JointDuty]] = {}
        self.chosen: dict[str, DriveSizing] = {}
        self.iterations: list[Iteration] = []

    def size_one(self, duty: JointDuty, scale: float | None) -> DriveSizing:
        """The sizing of one coordinate, once per duty and pace: a pass repeats the duties of the coordinates
        whose load did not change (the same arrays give the same choice)."""
        static = duty.static_torque if self.options.objective == "time" else None  # read (made) only where used
        key = (duty.name, scale, duty.load_inertia, duty.stroke, *(None if x is None else x.tobytes() for x in (
            duty.t, duty.speed, duty.acceleration, duty.torque, static, duty.moving)))
        if key not in self.sized:
            self.sized[key] = self.size_fresh(duty, scale)
        return self.sized[key]

    def size_fresh(self, duty: JointDuty, scale: float | None) -> DriveSizing:
        """The sizing of one coordinate doing ``duty`` at the pace ``scale`` (``None``: the duty's own)."""
        from .cylinders import size_cylinder

        o = self.options
        if duty.kind == "cylinder":
            spec, length = self.mech.cylinders[duty.name], self.lengths[duty.name]
            if o.objective == "time":
                return size_cylinder(duty.scaled(scale), spec, self.cylinders, pressure=o.pressure, objective="mass",
                                     length=length)
            return size_cylinder(duty, spec, self.cylinders, pressure=o.pressure, objective=o.objective,
                                 length=length)
        return size_joint(duty, self.motors, self.gearboxes, self.linear, objective=o.objective,
                          inertia_ratio_max=o.inertia_ratio_max, direct=o.direct, time_scale=scale,
                          chain_efficiency=o.chain_efficiency, limits=o.limits, converters=self.converters(duty),
                          motor_arrays=self.motor_arrays)

    def converters(self, duty: JointDuty) -> Converters:
        """The converters to try on a joint, built once per kind (and stroke: a screw's length follows it; and the
        efficiency of the file's drive, a factor of every converter's)."""
        key = (duty.kind, duty.stroke if duty.kind == "prismatic" else None, duty.efficiency)
        if key not in self.built:
            direct, efficiency, gearboxes, linear = (self.options.direct, self.options.chain_efficiency,
                                                     self.gearboxes, self.linear)
            self.built[key] = _arrays_of(gearboxes if duty.kind == "revolute" else linear, (*key, direct, efficiency),
                                         lambda: converters_for(duty, gearboxes, linear, direct, efficiency))
        return self.built[key]

    def fastest_for(self, d: JointDuty) -> float:
        """The fastest pace of one coordinate (:func:`fastest_scale`), once per duty: a pass changes only the
        duties of the coordinates proximal to a drive that changed."""
        key = (d.name, d.torque.tobytes(), d.static_torque.tobytes(), d.load_inertia)
        if key not in self.fastest:
            o = self.options
            self.fastest[key] = fastest_scale(
                _cylinder_passes(d, self.mech.cylinders[d.name], self.cylinders, o.pressure, self.lengths[d.name])
                if d.kind == "cylinder" else
                motor_passes(d, self.motor_arrays, self.converters(d), o.inertia_ratio_max, o.limits))
        return self.fastest[key]

    def pace(self, duties: dict[str, JointDuty]) -> float | None:
        """The ``time`` objective's scale: the slowest coordinate's fastest pace sets the whole task's."""
        if self.options.objective != "time":
            return None
        scales = [self.fastest_for(d) for d in duties.values()]
        return max(scales) if all(math.isfinite(x) for x in scales) else 1.0

    def mounts(self, chosen: dict[str, DriveSizing]) -> dict[str, DriveMount]:
        """The drives of ``chosen`` as masses on the bodies that carry them (cylinders: none)."""
        return {n: DriveMount(n, s.choice(), s.drive_mass() or 0.0, *self.carriers[n])
                for n, s in chosen.items() if n in self.carriers}

    def duties_with(self, chosen: dict[str, DriveSizing]) -> dict[str, JointDuty]:
        """The duties with the drives of ``chosen`` on their bodies (those on a fixed body change nothing)."""
        moving = [m for m in self.mounts(chosen).values() if m.parent > 0 and m.mass > 0]
        key = tuple(sorted((m.joint, m.drive) for m in moving))
        if not key:
            return self.bare
        if key not in self.known:
            self.known.clear()
            loaded = joint_duties(mount_drives(self.mech, moving), self.trajectory, self.loads, kinematics=self.mech,
                                  moving=self.bare[self.names[0]].moving, payload=self.payload)
            self.known[key] = {d.name: d for d in loaded if d.name in self.bare}
        return self.known[key]

    def run_pass(self, weighted: bool, first: bool = False) -> tuple:
        """One pass distal to proximal (``weighted``: each coordinate with the drives chosen so far on their
        bodies, else weightless); (the choices in order, the pace)."""
        chosen, order = self.chosen, self.order
        before = {} if first else dict(chosen)
        scale = self.pace(self.duties_with(chosen) if weighted else self.bare)
        for k, name in enumerate(order):
            chosen[name] = self.size_one((self.duties_with(chosen) if weighted else self.bare)[name], scale)
            if self.progress:
                self.progress(k + 1, len(order))
        changes = tuple((n, before[n].choice() if n in before else None, chosen[n].choice()) for n in order
                        if n not in before or before[n].choice() != chosen[n].choice())
        self.iterations.append(Iteration(len(self.iterations) + 1, weighted, scale or 1.0, changes))
        return tuple(chosen[n].choice() for n in order), scale

    def solve(self, start: dict[str, DriveSizing] | None = None, task: str = "task") -> SizingResult:
        """The passes until the choice settles, cycles or reaches ``max_iterations`` (``start``: that of
        :func:`size_mechanism`); the result for the task named ``task``. Once per :class:`FixedPoint` (the passes
        are kept in it)."""
        o, mech, chosen, iterations = self.options, self.mech, self.chosen, self.iterations
        included = mech.link_masses_include_drives
        warm = start is not None and not o.single_pass and not included and o.objective != "time" and \
            sees_every_drive(mech, self.order, self.carriers)
        if warm:
            chosen.update((n, s) for n, s in start.items() if n in self.carriers)
        history = [self.run_pass(warm, first=True)]
        converged, cycle = True, ()
        if not o.single_pass and not included and any(m.parent > 0 and m.mass > 0
                                                      for m in self.mounts(chosen).values()):
            converged = False
            while len(iterations) < o.max_iterations:
                state = self.run_pass(True)
                if state == history[-1]:
                    converged = True
                    break
                if state in history:
                    cycle = (history.index(state) + 1, len(iterations))
                    break
                history.append(state)
        scale = iterations[-1].time_scale
        sized = [chosen[n] for n in self.names]
        duration = self.bare[self.names[0]].duration
        return SizingResult(mech.name, task, o.objective, sized, scale, iterations, o.single_pass, converged,
                            self.mounts(chosen), cycle, duration, masses_included=included and not o.single_pass)


def sees_every_drive(mech: Mechanism, order: list[str], carriers: dict[str, tuple]) -> bool:
    """Whether sizing the coordinates in ``order`` meets every drive that loads a coordinate before it: each drive's
    body (``carriers``: :func:`~mechatron.drives.duty.drive_carrier`) lies in the subtree of no coordinate sized
    before it, nor of its own, so a pass that mounts each choice at once sizes every coordinate with its final load.
    Never for closed loops (their constraint forces couple every coordinate)."""
    if mech.closures:
        return False
    subtrees = mech.model.subtrees
    for k, name in enumerate(order):
        moved = set(subtrees[mech.joint_id(name)])
        if any(carriers[other][0] in moved for other in order[k:] if other in carriers):
            return False
    return True


def _cylinder_passes(duty: JointDuty, spec: Cylinder, catalog: pd.DataFrame, pressure: float,
                     length: np.ndarray | None = None) -> Callable[[float], bool]:
    from .cylinders import size_cylinder

    return lambda k: size_cylinder(duty.scaled(k), spec, catalog, pressure=pressure, length=length).feasible


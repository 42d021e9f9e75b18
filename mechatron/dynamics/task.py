"""Tasks: what a mechanism must do — a motion (waypoints with a profile, or a trajectory CSV), a payload and
external loads — read from a TOML file, or a default one for every robot.

A task file (TOML; every field optional except the motion)::

    name = "pick and place"
    payload = 2.5                     # kg, carried at the frame payload_at
    payload_at = "tool"               # the frame or point that carries it (default the mechanism's tool frame)
    payload_com = [0.0, 0.0, 0.05]    # m in that frame (or payload_com_mm)
    payload_inertia = [2e-3, 3e-3, 3e-3]   # kg·m² about the payload's centre, that frame's axes: Ixx, Iyy, Izz
                                      # (or six: Ixx, Iyy, Izz, Ixy, Ixz, Iyz); default a point mass
    payload_from = 2                  # picked at waypoint 2 (1-based; default the whole task) ...
    payload_until = 4                 # ... and released at waypoint 4 (mechatron.dynamics.segments)
    profile = "trapezoidal"           # triangular, trapezoidal, scurve, quintic
    dwell = 0.25                      # s of rest at every waypoint after the first
    dt = 0.005                        # s, sampling step
    vmax_deg = [100, 100, 100, 200, 200, 200]   # per joint or one value (or vmax in rad/s and m/s)
    amax_deg = [300, 300, 300, 600, 600, 600]   # (or amax)
    jmax_deg = 3000                   # for the scurve profile (or jmax)
    waypoints_deg = [[0, 0, 0, 0, 0, 0], [45, -30, 20, 0, 30, 90]]   # (or waypoints in rad and m)
    # trajectory = "motion.csv"       # instead of waypoints: a trajectory CSV, relative to this file
    # [cartesian]                     # instead of waypoints: tool waypoints, solved by inverse kinematics
    # points_mm = [[600, -200, 0], [600, 300, 0]]   # (mechatron.dynamics.cartesian; docs/task_file.md)
    # speed = 0.5                     # m/s and m/s² along each straight line
    # acceleration = 2.0

    [[loads]]                         # constant external forces, world axes
    frame = "tool"
    force = [0.0, 0.0, -50.0]         # N
    moment = [0.0, 0.0, 0.0]          # N·m

With ``_deg`` the values of revolute joints are in degrees and those of prismatic joints in metres. For a
closed-loop mechanism the waypoints and limits are its actuated coordinates (cylinder lengths in m), and the payload
joins the body that carries the point ``payload_at`` (:func:`~mechatron.model.payload.with_payload`).
The default task of a robot is ``robots/tasks/<name>.toml`` if there is one, else :func:`generic_task`.

A task's trajectory knows its moves and its dwells (:func:`moving_intervals`): the ``time`` objective of the drive
sizing speeds the moves up and keeps every dwell as long as it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.schema import FieldReader
from ..kinematics.loops import loop_solver
from ..model.loads import Load
from ..model.mechanism import Mechanism
from .motion import (
    PROFILES,
    Trajectory,
    check_input_ranges,
    coordinate_limits,
    coordinate_names,
    cycle,
    read_trajectory,
)
from .segments import PayloadSchedule, read_span, task_schedule


@dataclass
class Task:
    """A task ready for analysis: the mechanism with the payload attached (kg), the trajectory, external loads
    (constant :class:`~mechatron.model.Load` s); ``source`` the file it was read from and ``text`` that file's text
    as read (a TOML task; reports show it as the task was, whatever the file holds later)."""

    name: str
    mechanism: Mechanism
    trajectory: Trajectory
    loads: list[Load] = field(default_factory=list)
    payload: float = 0.0
    source: str = ""
    text: str = ""
    #: The payload carried on part of the task only (``payload_from``, ``payload_until``;
    #: :mod:`mechatron.dynamics.segments`); ``mechanism`` then carries it throughout and ``unloaded`` is without it.
    schedule: PayloadSchedule | None = None
    unloaded: Mechanism | None = None

    @property
    def duration(self) -> float:
        """The trajectory's duration (s)."""
        return self.trajectory.duration

    @property
    def moving(self) -> np.ndarray:
        """(N − 1,) whether each interval between samples belongs to a move (True) or a dwell (False)
        (:func:`moving_intervals`)."""
        return moving_intervals(self.trajectory)

    @property
    def dwells(self) -> list[tuple[float, float]]:
        """The dwells of the task: (start, end) times (s) of every rest between moves (:func:`rests`)."""
        return rests(self.trajectory.t, self.moving)


def moving_intervals(trajectory: Trajectory) -> np.ndarray:
    """(N − 1,) booleans: which intervals [t_i, t_i+1] of ``trajectory`` belong to a move; the others are dwells.

    An interval is a dwell when at both its ends every coordinate's speed and acceleration are zero and the
    coordinates do not change (to 1e-12 relative). For a task made of waypoints (:func:`~mechatron.dynamics.motion.
    cycle`: moves that end at rest, then rests of ``dwell`` seconds) this is exactly its rests; a move never has
    two consecutive samples at rest at the same place."""
    still = np.all(trajectory.v == 0, axis=1) & np.all(trajectory.a == 0, axis=1)
    c = np.atleast_2d(np.asarray(trajectory.coordinates, dtype=float))
    same = np.all(np.abs(np.diff(c, axis=0)) <= 1e-12 * (1 + np.abs(c[1:])), axis=1)
    return ~(still[:-1] & still[1:] & same)


def rests(t: np.ndarray, moving: np.ndarray) -> list[tuple[float, float]]:
    """The maximal runs of intervals that are not ``moving``, as (start, end) times (s)."""
    out: list[tuple[float, float]] = []
    start = None
    for i, m in enumerate(np.append(moving, True)):
        if not m and start is None:
            start = i
        elif m and start is not None:
            out.append((float(t[start]), float(t[i])))
            start = None
    return out


def _coordinates(mech: Mechanism) -> tuple[list[str], np.ndarray]:
    """Names of the coordinates a task moves (the joint coordinates; a closed loop's actuated ones) and which of
    them are angles."""
    if mech.closures:
        names = list(mech.actuated)
        return names, np.array([mech.joint_kind(n) == "revolute" for n in names])
    return coordinate_names(mech), mech.angular_coordinates()


def _per_axis(reader: FieldReader, key: str, angular: np.ndarray) -> np.ndarray | None:
    """A scalar or per-coordinate list from ``key`` (SI) or ``key_deg`` (revolute in degrees, others SI)."""
    if reader.has(key) and reader.has(key + "_deg"):
        raise reader.error(key, f"give only one of {key} and {key}_deg")
    for name, degrees in ((key, False), (key + "_deg", True)):
        if reader.has(name):
            raw = reader.raw(name)
            values = np.atleast_1d(np.asarray(raw, dtype=object))
            if values.ndim != 1 or len(values) not in (1, len(angular)):
                raise reader.error(name, f"give one value or {len(angular)} (one per coordinate)")
            out = np.array([reader.to_float(name, v) for v in values], dtype=float)
            out = np.broadcast_to(out, angular.shape).copy()
            if np.any(out <= 0):
                raise reader.error(name, "every value must be > 0")
            return np.where(angular, np.radians(out), out) if degrees else out
    return None


def _waypoints(reader: FieldReader, angular: np.ndarray) -> list[np.ndarray] | None:
    if reader.has("waypoints") and reader.has("waypoints_deg"):
        raise reader.error("waypoints", "give only one of waypoints and waypoints_deg")
    for name, degrees in (("waypoints", False), ("waypoints_deg", True)):
        if not reader.has(name):
            continue
        raw = reader.raw(name)
        if not isinstance(raw, list) or len(raw) < 2:
            raise reader.error(name, "give a list of at least two waypoints")
        points = []
        for k, point in enumerate(raw):
            where = f"{name}[{k + 1}]"
            if not isinstance(point, list) or len(point) != len(angular):
                raise InputError(f"expected {len(angular)} numbers (one per coordinate)", file=reader.file,
                                 field=reader.field(where))
            values = np.array([reader.to_float(where, v) for v in point], dtype=float)
            points.append(np.where(angular, np.radians(values), values) if degrees else values)
        return points
    return None


def _frame(reader: FieldReader, key: str, mech: Mechanism, default: str | None = None) -> str:
    """The frame (a linkage's point) of ``mech`` that the field ``key`` names (``default`` when left out); an
    unknown one is an error naming the field and listing the frames."""
    name = reader.string(key) if default is None else reader.string(key, default)
    try:
        mech.frame_id(name)
    except InputError as exc:
        raise reader.error(key, exc.message) from None
    return name


def _payload_inertia(reader: FieldReader) -> np.ndarray | None:
    """``payload_inertia``: 3 numbers (I_xx, I_yy, I_zz) or 6 (and I_xy, I_xz, I_yz), kg·m² about the payload's
    centre, axes of the frame ``payload_at``, as a symmetric 3×3 tensor; each moment ≥ 0 (the rest is checked with
    the mass)."""
    if not reader.has("payload_inertia"):
        return None
    raw = reader.raw("payload_inertia")
    if not isinstance(raw, list) or len(raw) not in (3, 6):
        raise reader.error("payload_inertia", "give 3 numbers [Ixx, Iyy, Izz] or 6 [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] "
                                              "(kg·m² about the payload's centre, axes of payload_at)")
    values = [reader.to_float("payload_inertia", v) for v in raw]
    for name, value in zip(("Ixx", "Iyy", "Izz"), values):
        if value < 0:
            raise reader.error("payload_inertia", f"{name} must be >= 0 kg·m², got {value:g}")
    xx, yy, zz, xy, xz, yz = (*values, 0.0, 0.0, 0.0)[:6]
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def read_task(path: str | Path, mech: Mechanism) -> Task:
    """A task for ``mech`` from a TOML file (the format of the module docstring: SI units, or degrees with
    ``_deg``) or a trajectory CSV (:func:`~mechatron.dynamics.motion.read_trajectory`)."""
    from ..io.toml import read_toml

    path = Path(path)
    if path.suffix.lower() == ".csv":
        return Task(path.stem, mech, read_trajectory(path, mech), source=str(path))
    reader = FieldReader(read_toml(path), file=path)
    text = path.read_text(encoding="utf-8")
    name = reader.string("name", path.stem)
    reader.string("description", "")
    names, angular = _coordinates(mech)
    payload = reader.number("payload", 0.0, minimum=0.0)
    at = _frame(reader, "payload_at", mech, mech.tool_frame)
    com = reader.lengths("payload_com", 3, np.zeros(3))
    inertia = _payload_inertia(reader)
    span = read_span(reader)
    loaded = mech
    if payload or inertia is not None:
        from ..model.payload import with_payload

        try:
            loaded = with_payload(mech, payload, at, com=com, inertia=inertia)
        except InputError as exc:
            raise reader.error("payload_inertia" if exc.field == "inertia" else "payload", exc.message) from None
    loads = []
    for load in reader.tables("loads") if reader.has("loads") else []:
        frame = _frame(load, "frame", mech)
        loads.append(Load(frame, load.vector("force", 3, np.zeros(3)), load.vector("moment", 3, np.zeros(3))))
        load.finish()
    if reader.has("trajectory"):
        if reader.has("waypoints") or reader.has("waypoints_deg"):
            raise reader.error("trajectory", "give either a trajectory file or waypoints, not both")
        csv = Path(reader.string("trajectory"))
        trajectory = read_trajectory(csv if csv.is_absolute() else path.parent / csv, mech)
        task_schedule(reader, span, trajectory, None, payload, at, com, inertia)
        reader.finish()
        return Task(name, loaded, trajectory, loads, payload, str(path), text)
    if reader.has("cartesian"):  # tool waypoints, solved by inverse kinematics (mechatron.dynamics.cartesian)
        from .cartesian import cartesian_cycle, read_cartesian

        if reader.has("waypoints") or reader.has("waypoints_deg"):
            raise reader.error("cartesian", "give either tool waypoints ([cartesian]) or joint waypoints, not both")
        route = read_cartesian(reader.table("cartesian"), mech, angular)
        trajectory = cartesian_cycle(
            mech, route, profile=reader.string("profile", "trapezoidal", choices=PROFILES),
            dwell=reader.number("dwell", 0.0, minimum=0.0), dt=reader.number("dt", 0.005, positive=True),
            vmax=_per_axis(reader, "vmax", angular), amax=_per_axis(reader, "amax", angular))
        schedule = task_schedule(reader, span, trajectory, len(route.points), payload, at, com, inertia)
        reader.finish()
        return Task(name, loaded, trajectory, loads, payload, str(path), text, schedule, mech if schedule else None)
    points = _waypoints(reader, angular)
    if points is None:
        raise reader.error("waypoints", "missing the motion: give waypoints, waypoints_deg or trajectory")
    key = "waypoints_deg" if reader.has("waypoints_deg") else "waypoints"
    check_input_ranges(mech, names, np.array(points), file=path,
                       rows=[reader.field(f"{key}[{k + 1}]") for k in range(len(points))], fields=names)
    profile = reader.string("profile", "trapezoidal", choices=PROFILES)
    dwell = reader.number("dwell", 0.0, minimum=0.0)
    dt = reader.number("dt", 0.005, positive=True)
    limits = {k: _per_axis(reader, k, angular) for k in ("vmax", "amax", "jmax")}
    reader.finish()
    trajectory = _remembered_cycle(None if mech.closures else mech, points, dwell=dwell, profile=profile, dt=dt,
                                   dt_name=f"{path}: field 'dt'", dwell_name=f"{path}: field 'dwell'", **limits)
    if mech.closures:
        trajectory = Trajectory(trajectory.t, trajectory.q, trajectory.v, trajectory.a, names,
                                angular=[bool(x) for x in angular])
    schedule = task_schedule(reader, span, trajectory, len(points), payload, at, com, inertia)
    return Task(name, loaded, trajectory, loads, payload, str(path), text, schedule, mech if schedule else None)


#: The cycles made last (:func:`_remembered_cycle`), newest last.
_CYCLES: dict[tuple, Trajectory] = {}
_CYCLES_KEPT = 8


def _remembered_cycle(mech: Mechanism | None, points: list, **options) -> Trajectory:
    """:func:`~mechatron.dynamics.motion.cycle`, made once for the last few (mechanism, waypoints, options): a study
    sizes thousands of designs of one robot on one task, and the trajectory depends only on the joints' kinds,
    names, neutral configuration and velocity limits (the defaults of ``vmax``), not on the lengths and masses that
    vary. The arrays of a remembered trajectory are read-only: tasks share them."""
    signature = None if mech is None else (
        tuple(coordinate_names(mech)), tuple(j.shortname() for j in mech.model.joints[1:]),
        np.asarray(mech.model.velocityLimit, dtype=float).tobytes(), np.asarray(mech.neutral(), float).tobytes())
    key = (signature, np.asarray(points, dtype=float).tobytes(), len(points),
           *((k, v if v is None or isinstance(v, (str, float, int)) else np.asarray(v, float).tobytes())
             for k, v in sorted(options.items())))
    trajectory = _CYCLES.pop(key, None)
    if trajectory is None:
        trajectory = cycle(mech, points, **options)
        assert trajectory.coordinates is not None  # set by __post_init__
        for array in (trajectory.t, trajectory.q, trajectory.v, trajectory.a, trajectory.coordinates):
            array.setflags(write=False)
    _CYCLES[key] = trajectory
    while len(_CYCLES) > _CYCLES_KEPT:
        _CYCLES.pop(next(iter(_CYCLES)))
    return trajectory


def task_file(mech: Mechanism) -> Path | None:
    """The default task file of a robot, ``robots/tasks/<name>.toml``, if there is one."""
    from ..io.data import data_dir

    path = data_dir("robots") / "tasks" / f"{mech.name}.toml"
    return path if path.is_file() else None


def generic_task(mech: Mechanism, dwell: float = 0.2, dt: float = 0.005) -> Task:
    """A task for any mechanism, sampled every ``dt`` seconds: from the reference position (the neutral one of a
    serial arm), every coordinate moves by 40 % of its range (at most 90° or 0.5 m; the sign that stays inside the
    limits) and back, with a trapezoidal profile at the model's velocity limits (1 rad/s or 0.25 m/s where it has
    none; the nominal rates of a closed loop's inputs) reached in 0.25 s, resting ``dwell`` s at each end."""
    names, angular = _coordinates(mech)
    if mech.closures:
        solver = loop_solver(mech)
        index = [solver.index[n] for n in names]
        start = np.asarray(mech.reference_q if mech.reference_q is not None else mech.neutral(), float)[index]
        lower, upper = mech.model.lowerPositionLimit[index], mech.model.upperPositionLimit[index]
        speed = np.array([mech.input_rates.get(n, 1.0 if a else 0.1) for n, a in zip(names, angular)])
    else:
        start = np.zeros(mech.nv)  # the neutral configuration's joint coordinates
        lower, upper = coordinate_limits(mech)
        speed = mech.model.velocityLimit.copy()
        bad = ~np.isfinite(speed) | (speed <= 0) | (speed > 1e30)
        speed[bad] = np.where(angular, 1.0, 0.25)[bad]
    finite = np.isfinite(lower) & np.isfinite(upper) & (upper - lower < 1e10)
    start = np.where(finite, np.clip(start, lower, upper), start)
    span = np.where(finite, 0.4 * (upper - lower), np.where(angular, math.pi / 2, 0.5))
    step = np.minimum(span, np.where(angular, math.pi / 2, 0.5))
    room_up = np.where(finite, upper - start, np.inf)
    end = np.where(room_up >= step, start + step, start - step)
    end = np.where(finite, np.clip(end, lower, upper), end)
    trajectory = cycle(None if mech.closures else mech, [start, end, start], dwell=dwell, vmax=speed,
                       amax=speed / 0.25, dt=dt)
    trajectory = Trajectory(trajectory.t, trajectory.q, trajectory.v, trajectory.a, names, trajectory.coordinates,
                            [bool(x) for x in angular])
    return Task("generic out-and-back", mech, trajectory, source="generic")


def default_task(mech: Mechanism) -> Task:
    """The robot's own task file if it has one, else :func:`generic_task`."""
    path = task_file(mech)
    return read_task(path, mech) if path else generic_task(mech)

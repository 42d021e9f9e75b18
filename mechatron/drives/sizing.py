r"""Motor, converter and ratio selection for every driven joint of a mechanism doing a task.

For each joint: its duty from the dynamics (:mod:`~mechatron.drives.duty`), every motor × converter pair checked
at once (:mod:`~mechatron.drives.checks`), the feasible pairs ranked by an objective and the best one chosen:

- ``mass``: the lightest motor + converter (then the cheapest);
- ``cost``: the cheapest (then the lightest);
- ``margin``: the largest smallest margin over all checks (the most reserve);
- ``time``: the shortest execution of the task. The task is replayed k times slower (k < 1: faster; speeds × 1/k,
  accelerations × 1/k², gravity and external loads unchanged); for each coordinate the smallest k at which some
  drive passes every check is found by bisection, the slowest coordinate sets k for the whole task, and every
  coordinate then gets its lightest drive at that pace.

When no pair passes, the closest pairs (smallest worst load factor) are reported with the checks they fail.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Cylinder, Mechanism
from ..report.result import Result, json_ready
from .checks import PASS_TOLERANCE, Check, DriveLimits, Evaluation, evaluate, motor_side
from .converters import Converters, converters_for
from .duty import JointDuty, joint_duties
from .motor import continuous_torque, peak_torque_limit
from .report import COLUMNS, REPORTED, RPM, DriveSizing

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task

OBJECTIVES = ("mass", "cost", "margin", "time")


@dataclass
class JointSizing(DriveSizing):
    """The sizing of one motor-driven joint: the chosen motor and converter with every check (a result: its table
    is one row per check, its chart the motor's speed–torque zones with the task's operating points).

    Attributes:
        joint, kind: the joint's name and ``"revolute"`` or ``"prismatic"``.
        objective: how the feasible pairs were ranked (``mass``, ``cost``, ``margin``, ``time``).
        feasible: whether any pair passes every check.
        motor, converter, converter_kind, ratio: the chosen pair (or, if none is feasible, the closest one); the
            ratio u is motor speed / joint speed (rad/rad, or rad/m for a screw or rack).
        checks: every applicable check of that pair (:class:`~mechatron.drives.checks.Check`, SI units).
        ranking: the feasible pairs, best first: motor, converter, kind, ratio, mass (kg), price, smallest margin,
            score (the objective's value).
        closest: the pairs with the smallest worst load factor and the checks they fail.
        duty: the joint's duty (:class:`~mechatron.drives.duty.JointDuty`), replayed at ``time_scale``.
        motor_data, converter_data: the chosen pair's catalog data (SI).
        time_scale: the task was replayed this many times slower (``time`` objective; < 1: faster).
    """

    joint: str
    kind: str
    objective: str
    feasible: bool
    motor: str
    converter: str
    converter_kind: str
    ratio: float
    checks: list[Check]
    ranking: pd.DataFrame
    closest: pd.DataFrame
    duty: JointDuty
    motor_data: dict = field(default_factory=dict)
    converter_data: dict = field(default_factory=dict)
    time_scale: float = 1.0

    def operating_points(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Motor speed n = u ω (rad/s) and torque T_m = (J_m + J_c) u ω̇ + τ*/u (N·m) at every sample of the task
        with the chosen pair (:func:`~mechatron.drives.checks.motor_side`)."""
        c = self.converter_data
        n, accel, base = motor_side(self.duty, c["ratio"], c["efficiency"], c["inertia"])
        return n, self.motor_data["rotor_inertia"] * accel + base

    def drive_columns(self) -> dict:
        return {"motor": self.motor, "converter": self.converter, "ratio": self.ratio}

    def headline(self) -> str:
        through = "direct drive" if self.converter == "direct" else \
            f"{self.converter_kind} {self.converter}, u = {self.ratio:.4g}"
        return f"{self.joint}: motor {self.motor} + {through}"

    def candidate(self, row: dict) -> str:
        return f"{row['motor']} + {row['converter']}"

    def as_dict(self) -> dict:
        """joint, kind, feasible, motor, gearbox (the converter's key), converter_kind, ratio, time_scale, checks
        (name, value, limit, unit, margin, pass; SI), alternatives (the best feasible pairs), closest (when none is
        feasible)."""
        return json_ready({
            "joint": self.joint, "kind": self.kind, "feasible": self.feasible, "motor": self.motor,
            "gearbox": self.converter, "converter_kind": self.converter_kind, "ratio": self.ratio,
            "time_scale": self.time_scale, "checks": [c.as_dict() for c in self.checks],
            "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
            "closest": [] if self.feasible else self.closest.to_dict(orient="records")})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chosen motor's speed–torque chart: its continuous (S1) and intermittent zones
        (:mod:`~mechatron.drives.motor`), the task's operating points (|n|, |T_m|) coloured by time and the RMS
        torque at the mean speed (the thermal check); speed in rpm, torque in N·m."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 7.5, 5)
        m = self.motor_data
        n, torque = self.operating_points()
        top = m["max_speed"]
        speed = np.linspace(0.0, top, 200)
        ax.fill_between(speed * RPM, 0, peak_torque_limit(speed, m["peak_torque"], m["rated_torque"],
                                                          m["rated_speed"], top),
                        color="tab:orange", alpha=0.18, label="intermittent zone")
        ax.fill_between(speed * RPM, 0, continuous_torque(speed, m["rated_torque"], m["rated_speed"], top),
                        color="tab:green", alpha=0.3, label="continuous zone (S1)")
        ax.scatter(np.abs(n) * RPM, np.abs(torque), s=6, c=self.duty.t, cmap="viridis",
                   label="operating points (colour: time)")
        rms = next(c for c in self.checks if c.name == "RMS torque")
        mean_speed = next((c.value for c in self.checks if c.name == "transmission mean input speed"),
                          float(np.mean(np.abs(n))))
        ax.plot([mean_speed * RPM], [rms.value], "r*", ms=14, label=f"RMS torque {rms.value:.3g} N·m at mean speed")
        ax.set_xlim(0, top * RPM * 1.05)
        ax.set_ylim(0, max(m["peak_torque"], float(np.abs(torque).max())) * 1.1)
        through = "direct" if self.converter == "direct" else f"{self.converter}, u = {self.ratio:.4g}"
        style_axes(ax, "motor speed (rpm)", "motor torque (N·m)",
                   f"{self.joint}: {self.motor} ({through})" + ("" if self.feasible else " — NOT FEASIBLE"),
                   legend=True, loc="upper right")
        return figure


def fastest_scale(passes: Callable[[float], bool], k_min: float = 0.02, k_max: float = 50.0,
                  tolerance: float = 1e-3) -> float:
    """The smallest time scale k ∈ [k_min, k_max] for which ``passes(k)`` (some drive passes every check with the
    task replayed k times slower), by bisection on log k to a relative ``tolerance``; the value returned is a
    tested, passing k, or inf if nothing passes even at k_max (the static load — gravity, external forces — does
    not scale, so a drive that cannot hold it fails at every k)."""
    if passes(1.0):
        if passes(k_min):
            return k_min
        low, high = k_min, 1.0
    else:
        if not passes(k_max):
            return math.inf
        low, high = 1.0, k_max
    while high / low > 1 + tolerance:
        middle = math.sqrt(low * high)
        if passes(middle):
            high = middle
        else:
            low = middle
    return high


BATCH = 256  # pairs made exact at a time


def _first_feasible(evaluation: Evaluation, m: np.ndarray, c: np.ndarray, count: int
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The first ``count`` pairs (in the given order) that pass every check, making pairs exact a batch at a time
    (the pairs of the last batch that pass are all kept)."""
    found_m, found_c = [], []
    for start in range(0, len(m), BATCH):
        mb, cb = m[start:start + BATCH], c[start:start + BATCH]
        evaluation.refine(mb, cb)
        ok = evaluation.worst_of(mb, cb) <= 1 + PASS_TOLERANCE
        found_m.append(mb[ok])
        found_c.append(cb[ok])
        if sum(len(x) for x in found_m) >= count:
            break
    return (np.concatenate(found_m), np.concatenate(found_c)) if found_m else (m[:0], c[:0])


def _smallest_worst(evaluation: Evaluation, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` pairs with the smallest exact worst load factor (branch and bound on the lower bounds: a pair
    whose bound exceeds the count-th best exact value cannot enter)."""
    bound = evaluation.worst()
    order = np.argsort(bound, axis=None, kind="stable")
    m_all, c_all = np.unravel_index(order, bound.shape)
    done = 0
    while done < len(order):
        evaluation.refine(m_all[done:done + BATCH], c_all[done:done + BATCH])
        done += BATCH
        exact = evaluation.worst_of(m_all[:done], c_all[:done])
        best = np.sort(exact)[:count]
        if len(best) == count and (done >= len(order) or bound.flat[order[min(done, len(order) - 1)]] >= best[-1]):
            break
    exact = evaluation.worst_of(m_all[:done], c_all[:done])
    keep = np.argsort(exact, kind="stable")[:count]
    return m_all[:done][keep], c_all[:done][keep]


def _feasible_by_score(evaluation: Evaluation, score: np.ndarray, tie: np.ndarray, count: int
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The best ``count`` feasible pairs by (score, tie), lowest first."""
    m, c = np.nonzero(evaluation.worst() <= 1 + PASS_TOLERANCE)  # the bounds: a superset of the feasible pairs
    order = np.lexsort((tie[m, c], score[m, c]))
    return _first_feasible(evaluation, m[order], c[order], count)


def _motor_passes(duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float,
                  limits: DriveLimits | None = None) -> Callable[[float], bool]:
    def passes(k: float) -> bool:
        evaluation = evaluate(duty.scaled(k), motors, conv, inertia_ratio_max, exact=False, limits=limits)
        bound = evaluation.worst()
        m, c = np.nonzero(bound <= 1 + PASS_TOLERANCE)
        order = np.argsort(bound[m, c], kind="stable")
        return len(_first_feasible(evaluation, m[order], c[order], 1)[0]) > 0

    return passes


def size_joint(duty: JointDuty, motors: pd.DataFrame, gearboxes: pd.DataFrame | None = None,
               linear: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
               direct: bool = True, time_scale: float | None = None, chain_efficiency: float = 1.0,
               limits: DriveLimits | None = None) -> JointSizing:
    """Check the motor × converter pairs for one joint and choose the best feasible one by ``objective``.

    Every pair is checked; the per-sample checks are made exact in the order of the objective until the best
    pairs are certain (:class:`~mechatron.drives.checks.Evaluation`), so the ranking lists the best feasible
    pairs (at least :data:`~mechatron.drives.report.REPORTED` when there are that many), exact.

    Args:
        duty: The joint's duty (:class:`~mechatron.drives.duty.JointDuty`; rad or m, s, N·m or N).
        motors: The motor catalog in SI (:func:`~mechatron.drives.catalogs.read_catalog`, kind ``motors``).
        gearboxes: Gearboxes for a revolute joint (kind ``gearboxes``), or ``None``.
        linear: Ball screws and racks for a prismatic joint (kind ``linear``), or ``None``.
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"``: with ``time`` the duty is first replayed at
            ``time_scale`` (default: the fastest scale this joint allows, :func:`fastest_scale`) and the lightest
            feasible pair at that pace is chosen.
        inertia_ratio_max: The largest load-to-motor inertia ratio (J_L/u² + J_c)/J_m.
        direct: Whether the motor alone (u = 1) is tried on a revolute joint.
        chain_efficiency: Multiplies every converter's efficiency (η = Π η_i [Egorov, 7.53]).
        limits: Emergency-stop limit, required screw life, supply voltage (:class:`~.checks.DriveLimits`).
    """
    if objective not in OBJECTIVES:
        raise InputError(f"unknown objective {objective!r}; expected one of: {', '.join(OBJECTIVES)}")
    if not inertia_ratio_max > 0:
        raise InputError(f"the inertia ratio limit must be > 0, got {inertia_ratio_max!r}")
    if len(motors) == 0:
        raise InputError("the motor catalog is empty")
    conv = converters_for(duty, gearboxes, linear, direct, chain_efficiency)
    scale = 1.0
    if objective == "time":
        scale = time_scale or fastest_scale(_motor_passes(duty, motors, conv, inertia_ratio_max, limits))
        scale = scale if math.isfinite(scale) else 1.0
        duty = duty.scaled(scale)
    evaluation = evaluate(duty, motors, conv, inertia_ratio_max, exact=False, limits=limits)
    motor_mass = motors["mass"].fillna(0).to_numpy() if "mass" in motors else np.zeros(len(motors))
    motor_price = motors["price"].fillna(0).to_numpy() if "price" in motors else np.zeros(len(motors))
    mass = motor_mass[:, None] + conv.mass[None, :]
    price = motor_price[:, None] + conv.price[None, :]
    if objective == "margin":
        im, ic = _smallest_worst(evaluation, REPORTED)
        ok = evaluation.worst_of(im, ic) <= 1 + PASS_TOLERANCE
        im, ic = im[ok], ic[ok]
        score = evaluation.worst_of(im, ic)
    else:
        primary, tie = (price, mass) if objective == "cost" else (mass, price)
        im, ic = _feasible_by_score(evaluation, primary, tie, REPORTED)
        score = primary[im, ic]
    worst = evaluation.worst_of(im, ic)
    ranking = pd.DataFrame({
        "motor": motors["key"].to_numpy()[im], "converter": conv.key[ic], "kind": conv.kind[ic],
        "ratio": conv.ratio[ic], "mass": mass[im, ic], "price": price[im, ic], "smallest_margin": 1 - worst,
        "score": score, "_m": im, "_c": ic})
    tie_break = ["price"] if objective in ("mass", "time") else ["mass"]
    ranking = ranking.sort_values(["score", *tie_break], kind="stable").reset_index(drop=True)
    feasible = bool(len(ranking))
    closest = pd.DataFrame() if feasible else _closest(evaluation, motors, conv)
    if feasible:
        m, c = int(ranking["_m"].iloc[0]), int(ranking["_c"].iloc[0])
    else:
        m = int(np.flatnonzero(motors["key"].to_numpy() == closest["motor"].iloc[0])[0])
        c = int(np.flatnonzero(conv.key == closest["converter"].iloc[0])[0])
    return JointSizing(duty.name, duty.kind, objective, feasible, str(motors["key"].iloc[m]),
                       str(conv.key[c]), str(conv.kind[c]), float(conv.ratio[c]), evaluation.checks(m, c),
                       ranking.drop(columns=["_m", "_c"]), closest, duty, motors.iloc[m].to_dict(),
                       {f: getattr(conv, f)[c].item() for f in conv.__dataclass_fields__}, scale)


def _closest(evaluation: Evaluation, motors: pd.DataFrame, conv: Converters) -> pd.DataFrame:
    """The pairs with the smallest worst load factor and the checks they fail."""
    rows = []
    for m, c in zip(*_smallest_worst(evaluation, REPORTED)):
        factors, failed = evaluation.load_factors_of(m, c), evaluation.failed(m, c)
        rows.append({"motor": str(motors["key"].iloc[m]), "converter": str(conv.key[c]), "ratio": float(conv.ratio[c]),
                     "worst_load_factor": float(factors.max()), "failed": "; ".join(failed) or "none"})
    return pd.DataFrame(rows)


@dataclass
class SizingResult(Result):
    """The sizing of every driven coordinate of a mechanism for a task: ``joints`` holds a
    :class:`JointSizing` per motor-driven joint and a :class:`~mechatron.drives.cylinders.CylinderSizing` per
    hydraulic cylinder; ``time_scale`` < 1 when the ``time`` objective found the task can run faster.

    ``to_frame()``: one row per joint and check (joint, motor, converter, ratio, check, value, limit, unit, margin,
    pass; SI units). ``as_dict()``: mechanism, task, objective, feasible, time_scale, task_time (s), joints (each
    joint's ``as_dict``). ``plot()``: one panel per joint, its drive's chart. ``str()``: the report of
    ``mechatron size``.
    """

    mechanism: str
    task: str
    objective: str
    joints: list[DriveSizing]
    time_scale: float = 1.0

    @property
    def feasible(self) -> bool:
        """Whether every joint has a drive that passes every check."""
        return all(j.feasible for j in self.joints)

    @property
    def duration(self) -> float:
        """The task's duration as sized (s): the given one, times ``time_scale`` for the ``time`` objective."""
        return self.joints[0].duty.duration if self.joints else 0.0

    def critical(self) -> DriveSizing:
        """The joint whose drive has the smallest margin (an infeasible one first)."""
        return min(self.joints, key=lambda j: j.smallest_margin())

    def to_frame(self) -> pd.DataFrame:
        """One row per joint and check (:data:`~mechatron.drives.report.COLUMNS`), SI units."""
        return pd.DataFrame([row for j in self.joints for row in j.rows()], columns=list(COLUMNS))

    def as_dict(self) -> dict:
        """mechanism, task, objective, feasible, time_scale, task_time (the task's duration as sized, s) and joints
        (every joint's ``as_dict``), JSON-ready."""
        return json_ready({"mechanism": self.mechanism, "task": self.task, "objective": self.objective,
                           "feasible": self.feasible, "time_scale": self.time_scale,
                           "task_time": self.duration if self.joints else None,
                           "joints": [j.as_dict() for j in self.joints]})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chart of every joint's drive, one panel each (motors: speed–torque zones and operating points;
        cylinders: force over speed with the push and pull limits). Given ``ax``, the chart of the
        :meth:`critical` joint is drawn into it."""
        if ax is not None:
            return self.critical().plot(ax)
        from ..report.figures import new_figure

        columns = min(3, len(self.joints))
        rows = -(-len(self.joints) // columns)
        figure = new_figure(5.5 * columns, 4.2 * rows)
        panels = figure.subplots(rows, columns, squeeze=False).ravel()
        for joint, panel in zip(self.joints, panels):
            joint.plot(panel)
        for panel in panels[len(self.joints):]:
            figure.delaxes(panel)
        figure.suptitle(f"{self.mechanism}: drives for '{self.task}'" + ("" if self.feasible else " — NOT FEASIBLE"))
        return figure

    def save_plots(self, directory: str | Path) -> list[Path]:
        """Every joint's chart (:meth:`DriveSizing.plot`) as ``<directory>/<mechanism>_<joint>.png``; the directory
        is created if needed."""
        from ..io.output import output_directory

        directory = output_directory(directory)
        return [j.save_plot(directory / f"{self.mechanism}_{j.joint}.png") for j in self.joints]

    def __str__(self) -> str:
        """The chosen drive of every joint with every check, margin and PASS/FAIL, and the verdict."""
        duration = self.duration
        lines = [f"{self.mechanism}: drive sizing for '{self.task}' ({duration:.3f} s, objective {self.objective})"]
        if self.objective == "time":
            lines.append(f"fastest feasible pace: the task replayed ×{self.time_scale:.3f} in time "
                         f"({duration:.3f} s instead of {duration / self.time_scale:.3f} s)")
        for j in self.joints:
            lines += [""] + j.lines()
        verdict = "every joint has a feasible drive" if self.feasible else \
            "NOT FEASIBLE: no drive passes every check for " + ", ".join(j.joint for j in self.joints if not j.feasible)
        return "\n".join(lines + ["", verdict])


def size_mechanism(mech: Mechanism, trajectory: Trajectory, motors: pd.DataFrame | None = None,
                   gearboxes: pd.DataFrame | None = None, linear: pd.DataFrame | None = None,
                   cylinders: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
                   loads: Loads = None, task: str = "task", direct: bool = True, pressure: float = 32e6,
                   chain_efficiency: float = 1.0, progress: Callable[[int, int], None] | None = None,
                   limits: DriveLimits | None = None) -> SizingResult:
    """Size every coordinate of ``mech`` that moves or carries load along ``trajectory``.

    The duty of every coordinate comes from the inverse dynamics without drive inertia
    (:func:`~mechatron.drives.duty.joint_duties`); then motors with gearboxes (revolute joints) or linear drives —
    ball screws, racks — (prismatic joints) are checked pair by pair (:func:`size_joint`), catalog cylinders for
    hydraulic cylinders (:func:`~mechatron.drives.cylinders.size_cylinder`).

    Args:
        mech: The mechanism, payload included (:func:`mechatron.model.payload.with_payload`).
        trajectory: A :class:`~mechatron.dynamics.motion.Trajectory` of the joints (rad, m; s), or of the actuated
            coordinates of a closed-loop mechanism.
        motors, gearboxes, linear, cylinders: Catalogs in SI (:func:`~mechatron.drives.catalogs.read_catalog`); one
            left out is the example one shipped in ``catalogs/``, when the mechanism needs it.
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"`` (see the module docstring).
        inertia_ratio_max: The largest load-to-motor inertia ratio (J_L/u² + J_c)/J_m allowed.
        loads: External loads (:class:`mechatron.model.Load`: force in N, moment in N·m) held along the task.
        task: The task's name, for reports.
        direct: Whether gearless (direct-drive) motors are tried on revolute joints.
        pressure: The hydraulic system's relief pressure (Pa).
        chain_efficiency: Multiplies every converter's efficiency: the losses of the rest of the chain, the
            series product η = Π η_i [Egorov, 7.53] (:func:`mechatron.mechanics.efficiency.series`).
        progress: Called with (done, total) after each coordinate.
        limits: Emergency-stop limit, required screw life, supply voltage (:class:`~.checks.DriveLimits`).
    """
    from .catalogs import default_catalog
    from .cylinders import cylinder_lengths, size_cylinder

    duties = [d for d in joint_duties(mech, trajectory, loads)
              if np.abs(d.speed).max() > 0 or np.abs(d.torque).max() > 0]
    if not duties:
        raise InputError(f"no joint of {mech.name} moves or carries load in the task")
    kinds = {d.kind for d in duties}
    motors = motors if motors is not None or kinds <= {"cylinder"} else default_catalog("motors")
    gearboxes = gearboxes if gearboxes is not None or "revolute" not in kinds else default_catalog("gearboxes")
    linear = linear if linear is not None or "prismatic" not in kinds else default_catalog("linear")
    cylinders = cylinders if cylinders is not None or "cylinder" not in kinds else default_catalog("cylinders")

    lengths = cylinder_lengths(mech, trajectory)

    def size_one(duty: JointDuty, scale: float | None = None) -> DriveSizing:
        if duty.kind == "cylinder":
            spec, length = mech.cylinders[duty.name], lengths[duty.name]
            if objective == "time":
                return size_cylinder(duty.scaled(scale), spec, cylinders, pressure=pressure, objective="mass",
                                     length=length)
            return size_cylinder(duty, spec, cylinders, pressure=pressure, objective=objective, length=length)
        return size_joint(duty, motors, gearboxes, linear, objective=objective, inertia_ratio_max=inertia_ratio_max,
                          direct=direct, time_scale=scale, chain_efficiency=chain_efficiency, limits=limits)

    scale = None
    if objective == "time":  # the slowest coordinate sets the pace of the whole task
        scales = [fastest_scale(_cylinder_passes(d, mech.cylinders[d.name], cylinders, pressure))
                  if d.kind == "cylinder" else
                  fastest_scale(_motor_passes(d, motors, converters_for(d, gearboxes, linear, direct, chain_efficiency),
                                              inertia_ratio_max, limits)) for d in duties]
        scale = max(scales) if all(math.isfinite(x) for x in scales) else 1.0
    out: list[DriveSizing] = []
    for k, duty in enumerate(duties):
        out.append(size_one(duty, scale))
        if progress:
            progress(k + 1, len(duties))
    return SizingResult(mech.name, task, objective, out, scale or 1.0)


def _cylinder_passes(duty: JointDuty, spec: Cylinder, catalog: pd.DataFrame, pressure: float
                     ) -> Callable[[float], bool]:
    from .cylinders import size_cylinder

    return lambda k: size_cylinder(duty.scaled(k), spec, catalog, pressure=pressure).feasible


def size(mech: Mechanism, task: Task | Trajectory | str | Path | None = None, *,
         motors: pd.DataFrame | str | Path | None = None, gearboxes: pd.DataFrame | str | Path | None = None,
         linear: pd.DataFrame | str | Path | None = None, cylinders: pd.DataFrame | str | Path | None = None,
         objective: str = "mass", loads: Loads = None, inertia_ratio_max: float = 10.0, direct: bool = True,
         pressure: float = 32e6, chain_efficiency: float = 1.0,
         progress: Callable[[int, int], None] | None = None, limits: DriveLimits | None = None) -> SizingResult:
    """Choose the drive of every joint of ``mech`` for a task — motor, gearbox and ratio (revolute joints), motor
    and ball screw or rack (prismatic joints), catalog cylinder (hydraulic cylinders of a closed-loop mechanism) —
    with every check vendors run (:mod:`~mechatron.drives.checks`, :mod:`~mechatron.drives.cylinders`).

    ``mechatron.size(puma)`` sizes the PUMA 560 for its own task with the example catalogs;
    ``mechatron.size(puma, "pick.toml", motors="motors.csv", objective="cost")`` for a task file and a catalog.

    Args:
        mech: The mechanism.
        task: What the mechanism must do:

            - ``None``: its default task (``robots/tasks/<name>.toml`` if there is one, else a generic
              out-and-back move of every coordinate, :func:`~mechatron.dynamics.task.default_task`);
            - the path of a task file (TOML: waypoints, profile, payload in kg, loads; or a trajectory CSV),
              read for ``mech`` (:func:`~mechatron.dynamics.task.read_task`);
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
        progress: Called with (done, total) after each coordinate.
        limits: The emergency-stop torque or current limit, the required screw life and the supply voltage
            (:class:`~mechatron.drives.checks.DriveLimits`); default: the motors' peak torque, 20 000 h, the
            catalog's voltage.

    Returns:
        A :class:`SizingResult`; ``result.feasible`` is false when some joint has no feasible drive (its closest
        candidates are reported).
    """
    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task, default_task, read_task
    from ..model.loads import as_loads
    from .catalogs import read_catalog

    if task is None:
        task = default_task(mech)
    elif isinstance(task, Trajectory):
        task = Task("trajectory", mech, task)
    elif not isinstance(task, Task):
        task = read_task(task, mech)
    catalogs = {kind: read_catalog(value, kind) if value is not None and not isinstance(value, pd.DataFrame)
                else value for kind, value in (("motors", motors), ("gearboxes", gearboxes), ("linear", linear),
                                               ("cylinders", cylinders))}
    return size_mechanism(task.mechanism, task.trajectory, **catalogs, objective=objective,
                          inertia_ratio_max=inertia_ratio_max, loads=[*as_loads(task.loads), *as_loads(loads)],
                          task=task.name, direct=direct, pressure=pressure, chain_efficiency=chain_efficiency,
                          progress=progress, limits=limits)

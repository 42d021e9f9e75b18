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
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import InputError
from ..model.mechanism import Mechanism
from .checks import CHECKS, PASS_TOLERANCE, Check, Evaluation, evaluate, motor_side
from .converters import Converters, converters_for
from .duty import JointDuty, joint_duties

OBJECTIVES = ("mass", "cost", "margin", "time")
#: Number of closest pairs reported when none is feasible, and of alternatives kept in reports.
REPORTED = 5


@dataclass
class JointSizing:
    """The sizing of one joint.

    Attributes:
        feasible: whether any pair passes every check.
        motor, converter, converter_kind, ratio: the chosen pair (or, if none is feasible, the closest one).
        checks: every applicable check of that pair.
        ranking: the feasible pairs, best first (motor, converter, kind, ratio, mass, price, smallest margin, score,
            and ``task_time`` (s) for the ``time`` objective).
        closest: the pairs with the smallest worst load factor and the checks they fail.
        motor_data, converter_data: the chosen pair's catalog data (SI).
        time_scale: the task was replayed this many times slower (``time`` objective; < 1: faster); ``duty`` is
            the replayed one.
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

    @property
    def failed(self) -> list[Check]:
        return [c for c in self.checks if not c.passed]

    def operating_points(self) -> tuple[np.ndarray, np.ndarray]:
        """Motor speed (rad/s) and torque (N·m) at every sample of the task with the chosen pair."""
        c = self.converter_data
        n, accel, base = motor_side(self.duty, c["ratio"], c["efficiency"], c["inertia"])
        return n, self.motor_data["rotor_inertia"] * accel + base

    def as_dict(self) -> dict:
        return {"joint": self.joint, "kind": self.kind, "feasible": self.feasible, "motor": self.motor,
                "gearbox": self.converter, "converter_kind": self.converter_kind, "ratio": self.ratio,
                "time_scale": self.time_scale,
                "checks": [c.as_dict() for c in self.checks],
                "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
                "closest": [] if self.feasible else self.closest.to_dict(orient="records")}


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


def _motor_passes(duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float
                  ) -> Callable[[float], bool]:
    def passes(k: float) -> bool:
        evaluation = evaluate(duty.scaled(k), motors, conv, inertia_ratio_max, exact=False)
        bound = evaluation.worst()
        m, c = np.nonzero(bound <= 1 + PASS_TOLERANCE)
        order = np.argsort(bound[m, c], kind="stable")
        return len(_first_feasible(evaluation, m[order], c[order], 1)[0]) > 0

    return passes


def size_joint(duty: JointDuty, motors: pd.DataFrame, gearboxes: pd.DataFrame | None = None,
               linear: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
               direct: bool = True, time_scale: float | None = None, chain_efficiency: float = 1.0) -> JointSizing:
    """Check the motor × converter pairs for one joint and choose the best feasible one by ``objective``.

    Every pair is checked; the per-sample checks are made exact in the order of the objective until the best
    pairs are certain (:class:`~mechatron.drives.checks.Evaluation`), so the ranking lists the best feasible
    pairs (at least :data:`REPORTED` when there are that many), exact. With ``objective="time"`` the task is first
    replayed at ``time_scale`` (default: the fastest scale this joint allows, :func:`fastest_scale`) and the
    lightest feasible pair at that pace is chosen."""
    if objective not in OBJECTIVES:
        raise InputError(f"unknown objective {objective!r}; expected one of: {', '.join(OBJECTIVES)}")
    if not inertia_ratio_max > 0:
        raise InputError(f"the inertia ratio limit must be > 0, got {inertia_ratio_max!r}")
    if len(motors) == 0:
        raise InputError("the motor catalog is empty")
    conv = converters_for(duty, gearboxes, linear, direct, chain_efficiency)
    scale = 1.0
    if objective == "time":
        scale = time_scale or fastest_scale(_motor_passes(duty, motors, conv, inertia_ratio_max))
        scale = scale if math.isfinite(scale) else 1.0
        duty = duty.scaled(scale)
    evaluation = evaluate(duty, motors, conv, inertia_ratio_max, exact=False)
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
        factors = evaluation.load_factors_of(m, c)
        failed = [f"{name} ×{factors[k]:.2f}" for k, name in enumerate(CHECKS) if factors[k] > 1 + PASS_TOLERANCE]
        rows.append({"motor": str(motors["key"].iloc[m]), "converter": str(conv.key[c]), "ratio": float(conv.ratio[c]),
                     "worst_load_factor": float(factors.max()), "failed": "; ".join(failed) or "none"})
    return pd.DataFrame(rows)


@dataclass
class SizingResult:
    """The sizing of every driven coordinate of a mechanism for a task: ``joints`` holds a
    :class:`JointSizing` per motor-driven joint and a :class:`~mechatron.drives.cylinders.CylinderSizing` per
    hydraulic cylinder; ``time_scale`` < 1 when the ``time`` objective found the task can run faster."""

    mechanism: str
    task: str
    objective: str
    joints: list
    time_scale: float = 1.0

    @property
    def feasible(self) -> bool:
        return all(j.feasible for j in self.joints)

    def as_dict(self) -> dict:
        return {"mechanism": self.mechanism, "task": self.task, "objective": self.objective,
                "feasible": self.feasible, "time_scale": self.time_scale,
                "task_time": self.time_scale * self.joints[0].duty.duration if self.joints else None,
                "joints": [j.as_dict() for j in self.joints]}

    def table(self) -> pd.DataFrame:
        """One row per joint and check: joint, motor, converter, ratio, check, value, limit, unit, margin, pass."""
        rows = [{"joint": j.joint, "motor": getattr(j, "motor", None),
                 "converter": getattr(j, "converter", getattr(j, "cylinder", None)), "ratio": getattr(j, "ratio", None),
                 **{("check" if k == "name" else k): v for k, v in c.as_dict().items()}}
                for j in self.joints for c in j.checks]
        return pd.DataFrame(rows)


def size_mechanism(mech: Mechanism, trajectory, motors: pd.DataFrame | None = None,
                   gearboxes: pd.DataFrame | None = None, linear: pd.DataFrame | None = None,
                   cylinders: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
                   loads: Sequence[Sequence] | None = None, task: str = "task", direct: bool = True,
                   pressure: float = 32e6, chain_efficiency: float = 1.0,
                   progress: Callable[[int, int], None] | None = None) -> SizingResult:
    """Size every coordinate of ``mech`` that moves or carries load along ``trajectory`` (a
    :class:`~mechatron.motion.Trajectory` of the joints, or of the actuated coordinates of a closed-loop
    mechanism): motors with gearboxes (revolute) or linear drives — screws, racks — (prismatic), catalog cylinders
    for hydraulic cylinders
    (``pressure``: the system's relief pressure, Pa). Payloads go into ``mech``
    (:func:`mechatron.dynamics.with_payload`); ``loads`` are external forces as in
    :func:`mechatron.dynamics.inverse_dynamics`. A catalog left out is the example one shipped in ``catalogs/``.
    ``chain_efficiency`` multiplies every converter's efficiency (the losses of the rest of the chain, 7.53)."""
    from .catalogs import default_catalog
    from .cylinders import size_cylinder

    duties = [d for d in joint_duties(mech, trajectory, loads)
              if np.abs(d.speed).max() > 0 or np.abs(d.torque).max() > 0]
    if not duties:
        raise InputError(f"no joint of {mech.name} moves or carries load in the task")
    kinds = {d.kind for d in duties}
    motors = motors if motors is not None or kinds <= {"cylinder"} else default_catalog("motors")
    gearboxes = gearboxes if gearboxes is not None or "revolute" not in kinds else default_catalog("gearboxes")
    linear = linear if linear is not None or "prismatic" not in kinds else default_catalog("linear")
    cylinders = cylinders if cylinders is not None or "cylinder" not in kinds else default_catalog("cylinders")
    def size(duty: JointDuty, scale: float | None = None):
        if duty.kind == "cylinder":
            spec = mech.cylinders[duty.name]
            if objective == "time":
                return size_cylinder(duty.scaled(scale), spec, cylinders, pressure=pressure, objective="mass")
            return size_cylinder(duty, spec, cylinders, pressure=pressure, objective=objective)
        return size_joint(duty, motors, gearboxes, linear, objective=objective, inertia_ratio_max=inertia_ratio_max,
                          direct=direct, time_scale=scale, chain_efficiency=chain_efficiency)

    scale = None
    if objective == "time":  # the slowest coordinate sets the pace of the whole task
        scales = [fastest_scale(_cylinder_passes(d, mech.cylinders[d.name], cylinders, pressure))
                  if d.kind == "cylinder" else
                  fastest_scale(_motor_passes(d, motors, converters_for(d, gearboxes, linear, direct, chain_efficiency),
                                              inertia_ratio_max)) for d in duties]
        scale = max(scales) if all(math.isfinite(x) for x in scales) else 1.0
    out: list = []
    for k, duty in enumerate(duties):
        out.append(size(duty, scale))
        if progress:
            progress(k + 1, len(duties))
    return SizingResult(mech.name, task, objective, out, scale or 1.0)


def _cylinder_passes(duty: JointDuty, spec, catalog: pd.DataFrame, pressure: float) -> Callable[[float], bool]:
    from .cylinders import size_cylinder

    return lambda k: size_cylinder(duty.scaled(k), spec, catalog, pressure=pressure).feasible


def size(mech: Mechanism, task=None, *, motors=None, gearboxes=None, linear=None, cylinders=None,
         objective: str = "mass", **options) -> SizingResult:
    """Choose the drive of every joint of ``mech`` (motor, gearbox and ratio; screw or rack; hydraulic cylinder) for
    a task, with every check vendors run: :func:`size_mechanism` on a :class:`~mechatron.dynamics.task.Task`.

    Args:
        task: A :class:`~mechatron.dynamics.task.Task`, the path of a task file (TOML), or ``None`` for the
            mechanism's default task (``robots/tasks/<name>.toml``, else a generic out-and-back move).
        motors, gearboxes, linear, cylinders: Catalogs as DataFrames (:func:`~mechatron.drives.catalogs.read_catalog`)
            or CSV paths; the example catalogs where left out.
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"``.
        **options: Passed to :func:`size_mechanism` (``inertia_ratio_max``, ``direct``, ``pressure`` in Pa,
            ``chain_efficiency``, ``progress``).
    """
    from ..dynamics.task import Task, default_task, read_task
    from .catalogs import read_catalog

    if task is None:
        task = default_task(mech)
    elif not isinstance(task, Task):
        task = read_task(task, mech)
    catalogs = {kind: read_catalog(value, kind) if value is not None and not isinstance(value, pd.DataFrame)
                else value for kind, value in (("motors", motors), ("gearboxes", gearboxes), ("linear", linear),
                                               ("cylinders", cylinders))}
    return size_mechanism(task.mechanism, task.trajectory, **catalogs, objective=objective, loads=task.loads,
                          task=task.name, **options)


r"""Motor, converter and ratio selection for every driven joint of a mechanism doing a task.

For each joint: its duty from the dynamics (:mod:`~mechatron.drives.duty`), every motor × converter pair checked
at once (:mod:`~mechatron.drives.checks`), the feasible pairs ranked by an objective and the best one chosen:

- ``mass``: the lightest motor + converter (then the cheapest);
- ``cost``: the cheapest (then the lightest);
- ``margin``: the largest smallest margin over all checks (the most reserve);
- ``time``: the shortest execution of the task. The task's moves are replayed k times slower (k < 1: faster;
  speeds × 1/k, accelerations × 1/k², gravity and external loads unchanged) and its dwells keep their length; for
  each coordinate the smallest k at which some drive passes every check is found by bisection, the slowest
  coordinate sets k for the whole task, and every coordinate then gets its lightest drive at that pace.

When no pair passes, the closest pairs (smallest worst load factor) are reported with the checks they fail. Each
choice is explained: its deciding check (the smallest margin) and the runners-up with why they lost
(:meth:`~mechatron.drives.report.DriveSizing.explanation`).

The drives load the mechanism (:func:`size_mechanism`): every chosen motor and gearbox is a mass on the body that
carries it, and the sizing repeats, distal to proximal, until the choice no longer changes.
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

from ..dynamics.motion import warn_limits
from ..errors import InputError
from ..io.values import number
from ..model.loads import Loads
from ..model.mechanism import Cylinder, Mechanism
from ..report.result import Result, json_ready
from .checks import ALL_CHECKS, PASS_TOLERANCE, Check, DriveLimits, PairChecks, _load_factor, failures, motor_side
from .converters import Converters, converters_for
from .duty import DriveMount, JointDuty, drive_carrier, joint_duties, mount_drives
from .motor import continuous_torque, peak_torque_limit
from .report import COLUMNS, REPORTED, RPM, DriveSizing

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task
    from ..report.html import Report
    from .electrical import ElectricalBalance
    from .hydraulics import HydraulicSupply

OBJECTIVES = ("mass", "cost", "margin", "time")


def _known(value: object) -> float:
    """A catalog number, 0 where it is missing (``None`` or NaN)."""
    return 0.0 if value is None or (isinstance(value, float) and math.isnan(value)) else float(value)


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
        time_scale: the task's moves were replayed this many times slower (``time`` objective; < 1: faster), its
            dwells as they are.
        rivals: the pairs ranked just before the chosen one by the objective, nearest first, which fail a check
            (ranking's columns and ``failed``); empty for the ``margin`` objective and when nothing is feasible.
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
    rivals: pd.DataFrame = field(default_factory=pd.DataFrame)

    def operating_points(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Motor speed n = u ω (rad/s) and torque T_m = (J_m + J_c) u ω̇ + τ*/u (N·m) at every sample of the task
        with the chosen pair (:func:`~mechatron.drives.checks.motor_side`)."""
        c = self.converter_data
        n, accel, base = motor_side(self.duty, c["ratio"], c["efficiency"], c["inertia"])
        return n, self.motor_data["rotor_inertia"] * accel + base

    def drive_mass(self) -> float:
        """Motor + converter mass (kg) from the catalogs (a missing mass counts 0)."""
        return _known(self.motor_data.get("mass")) + _known(self.converter_data.get("mass"))

    def drive_price(self) -> float:
        """Motor + converter price (the catalogs' currency; a missing price counts 0)."""
        return _known(self.motor_data.get("price")) + _known(self.converter_data.get("price"))

    def shaft_power(self) -> NDArray[np.float64]:
        """The motor's shaft power T_m n (W) at every sample: > 0 motoring, < 0 braking."""
        n, torque = self.operating_points()
        return n * torque

    def _zones(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(speed (rad/s), S1 torque, intermittent torque (N·m)) of the chosen motor from 0 to its top speed."""
        m = self.motor_data
        speed = np.linspace(0.0, m["max_speed"], 200)
        return (speed, continuous_torque(speed, m["rated_torque"], m["rated_speed"], m["max_speed"]),
                peak_torque_limit(speed, m["peak_torque"], m["rated_torque"], m["rated_speed"], m["max_speed"]))

    def _rms_point(self) -> tuple[float, float]:
        """(mean speed (rad/s), RMS torque (N·m)): the point of the thermal check."""
        rms = next(c for c in self.checks if c.name == "RMS torque")
        mean_speed = next((c.value for c in self.checks if c.name == "transmission mean input speed"),
                          float(np.mean(np.abs(self.operating_points()[0]))))
        return mean_speed, rms.value

    def chart_frame(self) -> pd.DataFrame:
        """The data of :meth:`plot`, one row per point (SI): ``series`` — ``operating point`` (every sample of the
        task: ``t_s`` (s), motor speed and torque, signed; the chart shows their magnitudes), ``continuous limit
        (S1)`` and ``intermittent limit`` (the zones' upper edges), ``RMS torque at mean speed`` (the thermal
        check's point) —, ``speed_rad_s`` (rad/s) and ``torque_Nm`` (N·m)."""
        n, torque = self.operating_points()
        speed, s1, peak = self._zones()
        mean_speed, rms = self._rms_point()
        parts = [pd.DataFrame({"series": "operating point", "t_s": self.duty.t, "speed_rad_s": n,
                               "torque_Nm": torque}),
                 pd.DataFrame({"series": "continuous limit (S1)", "speed_rad_s": speed, "torque_Nm": s1}),
                 pd.DataFrame({"series": "intermittent limit", "speed_rad_s": speed, "torque_Nm": peak}),
                 pd.DataFrame({"series": ["RMS torque at mean speed"], "speed_rad_s": [mean_speed],
                               "torque_Nm": [rms]})]
        return pd.concat(parts, ignore_index=True)[["series", "t_s", "speed_rad_s", "torque_Nm"]]

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
        feasible), and the explanation (:meth:`~mechatron.drives.report.DriveSizing.explanation`): deciding_check,
        runner_up, drive_mass_kg, drive_price."""
        return json_ready({
            "joint": self.joint, "kind": self.kind, "feasible": self.feasible, "motor": self.motor,
            "gearbox": self.converter, "converter_kind": self.converter_kind, "ratio": self.ratio,
            "time_scale": self.time_scale, "checks": [c.as_dict() for c in self.checks],
            "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
            "closest": [] if self.feasible else self.closest.to_dict(orient="records"), **self.explanation()})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chosen motor's speed–torque chart: its continuous (S1) and intermittent zones
        (:mod:`~mechatron.drives.motor`), the task's operating points (|n|, |T_m|) coloured by time and the RMS
        torque at the mean speed (the thermal check); speed in rpm, torque in N·m. Its data:
        :meth:`chart_frame`."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 7.5, 5)
        m = self.motor_data
        n, torque = self.operating_points()
        top = m["max_speed"]
        speed, s1, peak = self._zones()
        ax.fill_between(speed * RPM, 0, peak, color="tab:orange", alpha=0.18, label="intermittent zone")
        ax.fill_between(speed * RPM, 0, s1, color="tab:green", alpha=0.3, label="continuous zone (S1)")
        ax.scatter(np.abs(n) * RPM, np.abs(torque), s=6, c=self.duty.t, cmap="viridis",
                   label="operating points (colour: time)")
        mean_speed, rms = self._rms_point()
        ax.plot([mean_speed * RPM], [rms], "r*", ms=14, label=f"RMS torque {rms:.3g} N·m at mean speed")
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


#: Pairs evaluated at a time (a block of motors × every converter, or a slice of the ranking's order): the
#: sizing's memory does not grow with the catalogs beyond this and the per-motor and per-converter arrays.
CHUNK = 1 << 15
#: Pairs in the first slice of the ranking's order (:func:`_first_in_order`; each next slice twice as many).
FIRST_SLICE = 1 << 11


def _motor_blocks(checks: PairChecks) -> list[slice]:
    """Slices of the motors, each with about :data:`CHUNK` pairs (motors × every converter)."""
    motors, converters = checks.shape
    step = max(1, CHUNK // max(1, converters))
    return [slice(start, min(start + step, motors)) for start in range(0, motors, step)]


def _feasible(checks: PairChecks, m: np.ndarray, c: np.ndarray, screened: bool = False) -> np.ndarray:
    """Which pairs (m[i], c[i]) pass every check: the checks without samples first (:meth:`PairChecks.screen`;
    ``screened``: the pairs passed it already), then lower bounds of the per-sample ones, then those exact, each on
    the pairs the one before let through."""
    ok = np.ones(len(m), dtype=bool) if screened else checks.screen(m, c)
    index = np.flatnonzero(ok)
    ok[index] = checks.bounds_pass(m[index], c[index])
    index = np.flatnonzero(ok)
    ok[index] = checks.worst(m[index], c[index]) <= 1 + PASS_TOLERANCE
    return ok


def _pairs_between(first: np.ndarray, second: np.ndarray, low: float, high: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (m, c) with low < first[m] + second[c] ≤ high, in catalog order (m, then c)."""
    order = np.argsort(second, kind="stable")
    ordered = second[order]
    room = 1e-9 * (abs(high) + np.abs(first) + 1.0)  # the sums' rounding: the pairs are filtered exactly below
    lo = np.searchsorted(ordered, low - first - room, side="left") if math.isfinite(low) else \
        np.zeros(len(first), dtype=int)
    hi = np.searchsorted(ordered, high - first + room, side="right")
    counts = np.maximum(hi - lo, 0)
    m = np.repeat(np.arange(len(first)), counts)
    start = np.repeat(lo - (np.cumsum(counts) - counts), counts)
    c = order[start + np.arange(len(m))]
    total = first[m] + second[c]
    keep = (total > low) & (total <= high)
    m, c = m[keep], c[keep]
    flat = np.argsort(m * len(second) + c, kind="stable")
    return m[flat], c[flat]


def _threshold(first: np.ndarray, second: np.ndarray, low: float, count: int) -> float:
    """A sum s with about ``count`` pairs (m, c) with low < first[m] + second[c] ≤ s (bisection on s), or the
    largest sum when fewer remain."""
    ordered = np.sort(second)
    top = float(first.max() + ordered[-1])

    def pairs_below(s: float) -> int:
        return int(np.searchsorted(ordered, s - first, side="right").sum())

    below = 0 if not math.isfinite(low) else pairs_below(low)
    if pairs_below(top) - below <= count:
        return top
    a, b = (float(first.min() + ordered[0]) if not math.isfinite(low) else low), top
    for _ in range(60):
        middle = 0.5 * (a + b)
        found = pairs_below(middle) - below
        if found < count:
            a = middle
        else:
            b = middle
            if found <= 2 * count:
                break
    return b


def _in_order(m: np.ndarray, c: np.ndarray, primary: tuple[np.ndarray, np.ndarray],
              tie: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (m, c), given in catalog order, sorted by primary, then tie (stable: catalog order last)."""
    order = np.lexsort((tie[0][m] + tie[1][c], primary[0][m] + primary[1][c]))
    return m[order], c[order]


def _first_in_order(checks: PairChecks, primary: tuple[np.ndarray, np.ndarray], tie: tuple[np.ndarray, np.ndarray],
                    count: int, before: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The first ``count`` feasible pairs in the order of the score primary[0][m] + primary[1][c], then of
    tie[0][m] + tie[1][c], then of the catalogs (m, then c), and the ``before`` pairs just before the first of them,
    nearest first (all fail a check): (m, c) of the feasible ones and (m, c) of those before.

    The pairs are taken in slices of the order, each the pairs whose score lies in the next interval (an interval
    with about :data:`FIRST_SLICE` pairs, then twice as many, … up to :data:`CHUNK`), so that the memory stays with
    the slice and the work with the pairs before the ``count``-th feasible one. In a slice the pairs that pass the
    screening (:meth:`PairChecks.screen`) are sorted and checked in order; the pairs before the first feasible one
    are found among all the pairs of its slice (and of the slice before)."""
    found_m, found_c = [np.zeros(0, dtype=int)], [np.zeros(0, dtype=int)]
    low, size, top = -math.inf, FIRST_SLICE, float(primary[0].max() + primary[1].max())
    previous = (np.zeros(0, dtype=int), np.zeros(0, dtype=int))
    prior: tuple[np.ndarray, np.ndarray] | None = None
    while low < top and sum(len(x) for x in found_m) < count:
        high = _threshold(*primary, low, size)
        m, c = _pairs_between(*primary, low, high)
        alive = checks.screen(m, c)
        ms, cs = _in_order(m[alive], c[alive], primary, tie)
        for part in _growing(len(ms)):
            m_part, c_part = ms[part], cs[part]
            ok = np.flatnonzero(_feasible(checks, m_part, c_part, screened=True))
            if prior is None and len(ok):
                prior = _just_before((m, c), previous, (m_part[ok[0]], c_part[ok[0]]), primary, tie, before)
            found_m.append(m_part[ok])
            found_c.append(c_part[ok])
            if sum(len(x) for x in found_m) >= count:
                break
        previous, low, size = (m, c), high, min(2 * size, CHUNK)
    m, c = np.concatenate(found_m)[:count], np.concatenate(found_c)[:count]
    return m, c, *(prior if prior is not None else (m[:0], c[:0]))


def _growing(n: int, first: int = 8) -> list[slice]:
    """Consecutive slices of range(n), the first ``first`` long and each next twice as long (up to
    :data:`FIRST_SLICE`): the pairs in order are checked a few at a time while the first feasible ones are likely
    near, more at a time further on."""
    out, start, size = [], 0, first
    while start < n:
        out.append(slice(start, min(start + size, n)))
        start, size = start + size, min(2 * size, FIRST_SLICE)
    return out


def _just_before(pairs: tuple[np.ndarray, np.ndarray], previous: tuple[np.ndarray, np.ndarray],
                 pair: tuple[int, int], primary: tuple[np.ndarray, np.ndarray], tie: tuple[np.ndarray, np.ndarray],
                 count: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` pairs just before ``pair`` in the order of :func:`_in_order`, nearest first, among ``pairs``
    (its slice, catalog order) and, when these are too few, ``previous`` (the slice before)."""
    m, c = pairs
    size = len(primary[1])
    score, tied = primary[0][m] + primary[1][c], tie[0][m] + tie[1][c]
    f_score, f_tied = primary[0][pair[0]] + primary[1][pair[1]], tie[0][pair[0]] + tie[1][pair[1]]
    earlier = (score < f_score) | ((score == f_score) & ((tied < f_tied) | ((tied == f_tied) & (
        m * size + c < pair[0] * size + pair[1]))))
    m, c = _in_order(m[earlier], c[earlier], primary, tie)
    if len(m) < count:
        pm, pc = _in_order(*previous, primary, tie)
        m, c = np.concatenate([pm, m]), np.concatenate([pc, c])
    return m[::-1][:count], c[::-1][:count]


def _smallest_worst(checks: PairChecks, count: int, feasible_only: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` pairs with the smallest exact worst load factor (ties: the smaller lower bound of
    :meth:`PairChecks.worst` at level 1, then catalog order), by branch and bound a block of motors at a time: a
    pair whose lower bound exceeds the ``count``-th best exact value found so far cannot enter. With
    ``feasible_only`` only the pairs that pass every check count (the ``margin`` ranking)."""
    best = np.zeros((0, 4))  # m, c, exact, bound
    limit = math.inf
    converters = np.arange(checks.shape[1])
    for block in _motor_blocks(checks):
        mm, cc = np.meshgrid(np.arange(block.start, block.stop), converters, indexing="ij")
        m, c = mm.ravel(), cc.ravel()
        if feasible_only:
            keep = checks.screen(m, c)
            m, c = m[keep], c[keep]
        bound = checks.worst(m, c, 0)
        m, c = m[bound <= limit], c[bound <= limit]
        bound = checks.worst(m, c, 1)
        keep = bound <= limit
        m, c, bound = m[keep], c[keep], bound[keep]
        order = np.argsort(bound, kind="stable")
        for start in range(0, len(order), 256):
            part = order[start:start + 256]
            if bound[part[0]] > limit:
                break
            exact = checks.worst(m[part], c[part], 2)
            if feasible_only:
                part, exact = part[exact <= 1 + PASS_TOLERANCE], exact[exact <= 1 + PASS_TOLERANCE]
            rows = np.column_stack([m[part], c[part], exact, bound[part]])
            best = np.concatenate([best, rows])
            if len(best) >= count:
                limit = float(np.sort(best[:, 2])[count - 1])
                best = best[best[:, 2] <= limit]
    order = np.lexsort((best[:, 0] * checks.shape[1] + best[:, 1], best[:, 3], best[:, 2]))[:count]
    return best[order, 0].astype(int), best[order, 1].astype(int)


def _motor_passes(duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float,
                  limits: DriveLimits | None = None) -> Callable[[float], bool]:
    """passes(k): whether some pair passes every check with the task replayed k times slower, a block of motors at
    a time (the pair that passed last is tried first)."""
    last: list[tuple[int, int]] = []

    def passes(k: float) -> bool:
        checks = PairChecks(duty.scaled(k), motors, conv, inertia_ratio_max, limits)
        if last and _feasible(checks, np.array([last[0][0]]), np.array([last[0][1]]))[0]:
            return True
        usable = np.flatnonzero(checks.converter_passes)
        for block in _motor_blocks(checks):
            index = np.arange(block.start, block.stop)
            mm, cc = np.nonzero(checks.screen(index[:, None], usable[None, :]))
            m, c = index[mm], usable[cc]
            ok = np.flatnonzero(_feasible(checks, m, c, screened=True))
            if len(ok):
                last[:] = [(int(m[ok[0]]), int(c[ok[0]]))]
                return True
        return False

    return passes


def size_joint(duty: JointDuty, motors: pd.DataFrame, gearboxes: pd.DataFrame | None = None,
               linear: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
               direct: bool = True, time_scale: float | None = None, chain_efficiency: float = 1.0,
               limits: DriveLimits | None = None) -> JointSizing:
    """Check the motor × converter pairs for one joint and choose the best feasible one by ``objective``.

    Every pair is checked; the per-sample checks are made exact in the order of the objective until the best
    pairs are certain (:class:`~mechatron.drives.checks.Evaluation`), so the ranking lists the best feasible
    pairs (at least :data:`~mechatron.drives.report.REPORTED` when there are that many), exact. The pairs ranked
    just before the chosen one by the objective (all of which fail a check) are kept as its ``rivals``.

    Args:
        duty: The joint's duty (:class:`~mechatron.drives.duty.JointDuty`; rad or m, s, N·m or N).
        motors: The motor catalog in SI (:func:`~mechatron.drives.catalogs.read_catalog`, kind ``motors``).
        gearboxes: Gearboxes for a revolute joint (kind ``gearboxes``), or ``None``.
        linear: Ball screws and racks for a prismatic joint (kind ``linear``), or ``None``.
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"``: with ``time`` the duty's moves are first
            replayed at ``time_scale`` (default: the fastest scale this joint allows, :func:`fastest_scale`; the
            dwells keep their length) and the lightest feasible pair at that pace is chosen.
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
    checks = PairChecks(duty, motors, conv, inertia_ratio_max, limits)
    motor_mass = motors["mass"].fillna(0).to_numpy() if "mass" in motors else np.zeros(len(motors))
    motor_price = motors["price"].fillna(0).to_numpy() if "price" in motors else np.zeros(len(motors))
    mass, price = (motor_mass, conv.mass), (motor_price, conv.price)
    primary, tie = (price, mass) if objective == "cost" else (mass, price)
    before = (np.zeros(0, dtype=int),) * 2
    if objective == "margin":
        im, ic = _smallest_worst(checks, REPORTED, feasible_only=True)
        score = checks.worst(im, ic)
    else:
        im, ic, *before = _first_in_order(checks, primary, tie, REPORTED)
        score = primary[0][im] + primary[1][ic]
    table = _Table(motors, conv, mass, price)
    ranking = table.rows(checks, im, ic).assign(score=score, _m=im, _c=ic)
    tie_break = ["price"] if objective in ("mass", "time") else ["mass"]
    ranking = ranking.sort_values(["score", *tie_break], kind="stable").reset_index(drop=True)
    feasible = bool(len(ranking))
    closest = pd.DataFrame() if feasible else _closest(checks, table)
    if feasible:
        m, c = int(ranking["_m"].iloc[0]), int(ranking["_c"].iloc[0])
    else:
        m = int(np.flatnonzero(motors["key"].to_numpy() == closest["motor"].iloc[0])[0])
        c = int(np.flatnonzero(conv.key == closest["converter"].iloc[0])[0])
    rivals = table.rows(checks, *before, failed=True) if feasible and objective != "margin" else pd.DataFrame()
    return JointSizing(duty.name, duty.kind, objective, feasible, str(motors["key"].iloc[m]),
                       str(conv.key[c]), str(conv.kind[c]), float(conv.ratio[c]), checks.checks(m, c),
                       ranking.drop(columns=["_m", "_c"]), closest, duty, motors.iloc[m].to_dict(),
                       {f: getattr(conv, f)[c].item() for f in conv.__dataclass_fields__}, scale, rivals)


@dataclass(frozen=True)
class _Table:
    """What a report says of a motor × converter pair: names, ratio, mass (kg), price, margin, failed checks; mass
    and price as (per motor, per converter) arrays, the pair's the sum."""

    motors: pd.DataFrame
    conv: Converters
    mass: tuple[np.ndarray, np.ndarray]
    price: tuple[np.ndarray, np.ndarray]

    def rows(self, checks: PairChecks, m: np.ndarray, c: np.ndarray, failed: bool = False) -> pd.DataFrame:
        """The pairs (m[i], c[i]): motor, converter, kind, ratio, mass, price, smallest_margin (1 − the worst load
        factor, exact) and, with ``failed``, worst_load_factor and the checks they fail (``name ×load factor``)."""
        factors = _load_factor(*checks.table(m, c)).reshape(len(m), len(ALL_CHECKS))
        out = pd.DataFrame({"motor": self.motors["key"].to_numpy()[m], "converter": self.conv.key[c],
                            "kind": self.conv.kind[c], "ratio": self.conv.ratio[c],
                            "mass": self.mass[0][m] + self.mass[1][c], "price": self.price[0][m] + self.price[1][c],
                            "smallest_margin": 1 - factors.max(axis=1, initial=0.0)})
        if failed:
            out["worst_load_factor"] = factors.max(axis=1, initial=0.0)
            out["failed"] = [failures(ALL_CHECKS, f) for f in factors]
        return out


def _closest(checks: PairChecks, table: _Table) -> pd.DataFrame:
    """The pairs with the smallest worst load factor and the checks they fail."""
    m, c = _smallest_worst(checks, REPORTED)
    return table.rows(checks, m, c, failed=True).drop(columns=["kind", "smallest_margin"])


# ------------------------------------------------------------------------------------------------ the system
#: The most sizing passes of the fixed point (:func:`size_mechanism`) before it reports that it did not converge.
MAX_ITERATIONS = 10
#: The most passes a sizing may be allowed (``max_iterations``).
MAX_PASSES = 1000
#: The lowest efficiency of the rest of the chain (``chain_efficiency``): below it the drives' currents overflow.
MIN_EFFICIENCY = 0.01


@dataclass(frozen=True)
class Iteration:
    """One pass of the sizing over every driven coordinate (distal to proximal).

    Attributes:
        number: 1, 2, …
        weighted: whether the chosen drives' masses loaded the mechanism (pass 1 sizes with weightless drives).
        time_scale: the pace of the pass's moves (``time`` objective; 1 otherwise).
        changes: (joint, drive before, drive after) for every coordinate whose drive changed (before ``None`` in
            pass 1).
    """

    number: int
    weighted: bool
    time_scale: float
    changes: tuple[tuple[str, str | None, str], ...]

    def as_dict(self) -> dict:
        return {"iteration": self.number, "drive_masses": self.weighted, "time_scale": self.time_scale,
                "changes": [{"joint": j, "from": a, "to": b} for j, a, b in self.changes]}

    def line(self) -> str:
        what = "with the drives' masses on their bodies" if self.weighted else "drives weightless"
        pace = f", moves ×{self.time_scale:.4g}" if self.time_scale != 1.0 else ""
        changed = "; ".join(f"{j} {b}" if a is None else f"{j} {a} → {b}" for j, a, b in self.changes)
        return f"  pass {self.number} ({what}{pace}): {changed or 'no change'}"


@dataclass
class SizingResult(Result):
    """The sizing of every driven coordinate of a mechanism for a task: ``joints`` holds a
    :class:`JointSizing` per motor-driven joint and a :class:`~mechatron.drives.cylinders.CylinderSizing` per
    hydraulic cylinder; ``time_scale`` < 1 when the ``time`` objective found the task's moves can run faster.

    ``iterations`` are the passes of the sizing (:class:`Iteration`): the first with weightless drives (all of a
    ``single_pass`` sizing), the next ones with the chosen drives' masses on the bodies that carry them
    (``mounts``, :class:`~mechatron.drives.duty.DriveMount`) until the choice repeats (``converged``; ``cycle``
    names the passes whose choice came back when it cycles instead).

    ``to_frame()``: one row per joint and check (joint, motor, converter, ratio, check, value, limit, unit, margin,
    pass; SI units). ``as_dict()``: mechanism, task, objective, method, converged, feasible, time_scale, task_time
    (s), iterations, totals, joints (each joint's ``as_dict`` with its explanation and ``mounted_on``). ``plot()``:
    one panel per joint, its drive's chart. ``str()``: the report of ``mechatron size``.
    """

    mechanism: str
    task: str
    objective: str
    joints: list[DriveSizing]
    time_scale: float = 1.0
    iterations: list[Iteration] = field(default_factory=list)
    single_pass: bool = False
    converged: bool = True
    mounts: dict[str, DriveMount] = field(default_factory=dict)
    cycle: tuple[int, ...] = ()
    task_duration: float | None = None

    @property
    def feasible(self) -> bool:
        """Whether every joint has a drive that passes every check, for drives that no longer change."""
        return all(j.feasible for j in self.joints) and self.converged

    @property
    def duration(self) -> float:
        """The task's duration as sized (s): the given one, with the moves × ``time_scale`` for the ``time``
        objective."""
        return self.joints[0].duty.duration if self.joints else 0.0

    @property
    def method(self) -> str:
        """``"single pass"`` (each coordinate sized alone, weightless drives) or ``"fixed point"``."""
        return "single pass" if self.single_pass else "fixed point"

    def critical(self) -> DriveSizing:
        """The joint whose drive has the smallest margin (an infeasible one first)."""
        return min(self.joints, key=lambda j: j.smallest_margin())

    def electrical_balance(self) -> ElectricalBalance | None:
        """The electrical power of the chosen motors over the task, per axis and on a common DC bus
        (:func:`mechatron.drives.electrical.electrical`); ``None`` without a motor."""
        from .electrical import electrical

        return electrical(self) if any(j.kind != "cylinder" for j in self.joints) else None

    def hydraulic_supply(self) -> HydraulicSupply | None:
        """The pump flow and hydraulic power of the chosen cylinders over the task at the system pressure
        (:func:`mechatron.drives.hydraulics.hydraulic_supply`); ``None`` without a cylinder."""
        from .hydraulics import hydraulic_supply

        return hydraulic_supply(self) if any(j.kind == "cylinder" for j in self.joints) else None

    def totals(self) -> dict:
        """The sums over the drives (SI units; ``None`` where they do not apply or a catalog lacks the data):

        - drive_mass_kg and cost: the chosen drives' catalog masses and prices;
        - energy_per_cycle_j: the energy drawn from the supplies per cycle, ∫ max(P_bus, 0) dt of the common DC
          bus (P_bus = Σ (T_m n + R I²), :mod:`~mechatron.drives.electrical`) plus the pump's ∫ p Q dt
          (:mod:`~mechatron.drives.hydraulics`);
        - peak_bus_power_w: max P_bus; regenerated_energy_j: ∫ max(−P_bus, 0) dt, the braking energy per cycle;
          braking_resistor_peak_w and braking_resistor_continuous_w: max(−P_bus) and the regenerated energy over
          the cycle time;
        - peak_pump_power_w and peak_pump_flow_m3_s: max p Q and max Q;
        - cycle_time_s: the task's duration as sized."""
        masses = [j.drive_mass() for j in self.joints]
        prices = [j.drive_price() for j in self.joints]
        balance, supply = self.electrical_balance(), self.hydraulic_supply()
        bus = balance.bus() if balance else None
        pump = supply.rows()[-1] if supply else None
        return {"drive_mass_kg": None if None in masses else float(sum(masses)),
                "cost": None if None in prices else float(sum(prices)),
                "energy_per_cycle_j": (bus["energy_drawn"] if bus else 0.0) + (pump["energy"] if pump else 0.0),
                "peak_bus_power_w": bus["peak_power"] if bus else None,
                "regenerated_energy_j": bus["energy_regenerated"] if bus else None,
                "braking_resistor_peak_w": bus["peak_braking_power"] if bus else None,
                "braking_resistor_continuous_w": bus["continuous_braking_power"] if bus else None,
                "peak_pump_power_w": pump["peak_power"] if pump else None,
                "peak_pump_flow_m3_s": pump["peak_flow"] if pump else None,
                "cycle_time_s": self.duration}

    def _totals_lines(self) -> list[str]:
        totals = self.totals()

        def number(key: str, unit: str) -> str:
            return "unknown" if totals[key] is None else f"{totals[key]:.4g}{unit}"

        lines = [f"totals: drive mass {number('drive_mass_kg', ' kg')}, cost {number('cost', '')}, energy drawn per "
                 f"cycle {number('energy_per_cycle_j', ' J')}"]
        if totals["peak_bus_power_w"] is not None:
            lines.append(f"  common DC bus: peak {number('peak_bus_power_w', ' W')}; braking resistor peak "
                         f"{number('braking_resistor_peak_w', ' W')}, continuous "
                         f"{number('braking_resistor_continuous_w', ' W')} ({number('regenerated_energy_j', ' J')} "
                         "regenerated per cycle; P = T·n + R·I²)")
        if totals["peak_pump_power_w"] is not None:
            lines.append(f"  pump: peak flow {totals['peak_pump_flow_m3_s'] * 6e4:.4g} l/min, peak power "
                         f"{number('peak_pump_power_w', ' W')} (P = p·Q)")
        return lines

    def to_frame(self) -> pd.DataFrame:
        """One row per joint and check (:data:`~mechatron.drives.report.COLUMNS`), SI units."""
        return pd.DataFrame([row for j in self.joints for row in j.rows()], columns=list(COLUMNS))

    def _mounted_on(self, joint: str) -> dict | None:
        mount = self.mounts.get(joint)
        return None if mount is None else {"body": mount.carrier, "mass_kg": mount.mass,
                                            "loads_the_mechanism": mount.parent > 0}

    def as_dict(self) -> dict:
        """mechanism, task, objective, method (``fixed point`` or ``single pass``), converged, cycle, feasible,
        time_scale, task_time (the task's duration as sized, s), iterations (every pass: iteration, drive_masses,
        time_scale, changes: joint, from, to), totals (:meth:`totals`) and joints (every joint's ``as_dict`` with
        deciding_check, runner_up, drive_mass_kg, drive_price and mounted_on: body, mass_kg, loads_the_mechanism),
        electrical (:meth:`electrical_balance`, per axis and the DC bus) and hydraulics (:meth:`hydraulic_supply`,
        per cylinder and the pump), ``None`` where there is no motor or cylinder; JSON-ready."""
        balance, supply = self.electrical_balance(), self.hydraulic_supply()
        return json_ready({"mechanism": self.mechanism, "task": self.task, "objective": self.objective,
                           "method": self.method, "converged": self.converged, "cycle": list(self.cycle),
                           "feasible": self.feasible, "time_scale": self.time_scale,
                           "task_time": self.duration if self.joints else None,
                           "iterations": [i.as_dict() for i in self.iterations], "totals": self.totals(),
                           "electrical": None if balance is None else balance.as_dict(),
                           "hydraulics": None if supply is None else supply.as_dict(),
                           "joints": [{**j.as_dict(), **j.explanation(), "mounted_on": self._mounted_on(j.joint)}
                                      for j in self.joints]})

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
        """Every joint's chart (:meth:`DriveSizing.plot`) as ``<directory>/<mechanism>_<joint>.png`` and its data
        (:meth:`DriveSizing.chart_frame`) as ``<directory>/<mechanism>_<joint>.csv``; the directory is created if
        needed. The files are written whole and all together (:func:`mechatron.io.output.write_folder`), and the
        charts (and their data) an earlier call for the same mechanism wrote there for joints no longer sized are
        removed. Returns the files written."""
        from ..io.output import write_folder

        files: dict = {}
        for j in self.joints:
            files[f"{self.mechanism}_{j.joint}.png"] = j.plot
            files[f"{self.mechanism}_{j.joint}.csv"] = j.chart_frame
        return write_folder(directory, files, owner=f"mechatron size {self.mechanism}")

    def _method_lines(self) -> list[str]:
        if self.single_pass:
            return ["method: single pass — each coordinate sized alone, its drive's mass loading no other joint"]
        if not self.converged:
            what = (f"the choice of pass {self.cycle[-1]} repeats that of pass {self.cycle[0]}: it cycles"
                    if self.cycle else f"the choice still changed after {len(self.iterations)} passes")
            head = f"method: fixed point — NOT CONVERGED: {what}"
        elif not self.mounts:
            head = ("method: fixed point — no motor to place (the cylinders' masses are the mechanism's own), so one "
                    "pass is the fixed point")
        elif len(self.iterations) == 1:
            head = ("method: fixed point — every drive sits on a fixed body, so the drives' masses load no joint "
                    "and one pass is the fixed point")
        else:
            head = (f"method: fixed point — every chosen motor and gearbox is a mass on the body that carries it; "
                    f"sized distal to proximal until the choice repeats: converged in {len(self.iterations)} "
                    "passes")
        return [head, *(i.line() for i in self.iterations)]

    def __str__(self) -> str:
        """The method and its passes, the chosen drive of every joint with every check, margin and PASS/FAIL, why
        it was chosen, where it sits, the totals and the verdict."""
        duration = self.duration
        lines = [f"{self.mechanism}: drive sizing for '{self.task}' ({duration:.3f} s, objective {self.objective})"]
        if self.objective == "time":
            lines.append(f"fastest feasible pace: the moves replayed ×{self.time_scale:.3f} in time, the dwells kept "
                         f"({duration:.3f} s instead of {self.task_duration or duration:.3f} s)")
        lines += self._method_lines()
        for j in self.joints:
            lines += [""] + j.lines()
            mount = self.mounts.get(j.joint)
            if mount is not None:
                lines.append(f"    on {mount.carrier}: {mount.mass:.3g} kg" + ("" if mount.parent > 0 else
                                                                              " (a fixed body: it loads no joint)"))
        lines += ["", *self._totals_lines()]
        if self.feasible:
            verdict = "every joint has a feasible drive"
        elif not self.converged:
            verdict = "NOT FEASIBLE: the choice of drives did not settle (see the method above)"
        else:
            verdict = "NOT FEASIBLE: no drive passes every check for " + ", ".join(
                j.joint for j in self.joints if not j.feasible)
        return "\n".join(lines + ["", verdict])

    def report(self, mechanism: Mechanism | None = None, task: Task | str | Path | None = None, **context) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the method, every joint's drive and the check deciding it,
        per joint every check, the best alternatives (the closest drives when none is feasible) and its chart; given
        ``mechanism`` (and ``task`` as given to :func:`size`, default its default task) the task and the mechanism
        at its most loaded pose: the sample where the :meth:`critical` joint carries its largest |τ| (N·m or N)."""
        import sys

        from ..dynamics.task import Task, default_task, read_task
        from ..kinematics.drawing import configuration_figure
        from ..kinematics.loops import assemble
        from ..report.html import Chart, Code, Method, Report, Section, Table, Text
        from . import checks, cylinders, duty, electrical, hydraulics

        lines = str(self).splitlines()
        kinds = {j.kind for j in self.joints}
        texts = [sys.modules[__name__].__doc__, duty.__doc__] + [checks.__doc__] * bool(kinds - {"cylinder"}) \
            + [cylinders.__doc__] * ("cylinder" in kinds)
        def drive_row(j: DriveSizing) -> dict:
            deciding, mount = j.deciding(), self._mounted_on(j.joint)
            return {"joint": j.joint, "drive": j.headline(), "feasible": j.feasible,
                    "smallest margin": j.smallest_margin(), "deciding check": deciding.name if deciding else "",
                    "drive mass (kg)": j.drive_mass(), "price": j.drive_price(),
                    "on body": mount["body"] if mount else "",
                    "runner-up": " | ".join(f"{r['candidate']}: {r['reason']}" for r in j.runner_up())}

        drives = pd.DataFrame([drive_row(j) for j in self.joints])
        totals = pd.DataFrame([{"quantity": k, "value": v} for k, v in self.totals().items()])
        iterations = pd.DataFrame([{"pass": i.number, "drives' masses": i.weighted, "moves ×": i.time_scale,
                                    "changes": i.line().split(": ", 1)[1]} for i in self.iterations])
        sections = [Section("Method", [Method(text) for text in texts]), Section(
            "Drives", [Text(line) for line in lines[1:lines.index("")]] + [
                Table(drives, "the chosen drive of every joint, the check deciding it and the runners-up", "drives"),
                Table(iterations, "the passes of the sizing", "iterations"),
                Table(totals, "totals (kg, the catalogs' currency, J, W, s)", "totals")])]
        for title, supply, module in (("Electrical", self.electrical_balance(), electrical),
                                      ("Hydraulic supply", self.hydraulic_supply(), hydraulics)):
            if supply is not None:
                table = Table(supply.to_frame(), "SI units (J, W, A, V; m³/s, m³)", title.lower())
                sections.append(Section(title, [Method(module.__doc__), table, Chart(supply.plot())]))
        for j in self.joints:
            sections.append(Section(f"Joint {j.joint}", [Text(j.headline()), *(Text(line.strip()) for line in
                                                                            j.explanation_lines()), Table(
                j.to_frame()[["check", "value", "limit", "unit", "margin", "pass"]], "every check (SI; margin = 1 − "
                "value/limit)", f"checks {j.joint}"), Table(j.ranking.head(REPORTED) if j.feasible else j.closest,
                "the best feasible drives" if j.feasible else "the closest drives and the checks they fail",
                f"alternatives {j.joint}"), Chart(j.plot())]))
        if mechanism is not None:
            given, task = task, task if isinstance(task, Task) else default_task(mechanism) if task is None else \
                read_task(task, mechanism)
            if task.name != self.task:
                raise InputError(f"the report of a sizing for the task '{self.task}' needs that task, not "
                                 f"'{task.name}'")
            loaded, trajectory = self.critical(), task.trajectory
            k = int(np.argmax(np.abs(loaded.duty.torque)))
            if len(trajectory.t) != len(loaded.duty.t):  # resampled: the same fraction of the task
                k = int(np.argmin(np.abs((trajectory.t - trajectory.t[0]) / trajectory.duration
                                         - (loaded.duty.t[k] - loaded.duty.t[0]) / loaded.duty.duration)))
            q = assemble(mechanism, dict(zip(trajectory.names, trajectory.q[k]))) if mechanism.closures else \
                trajectory.q[k] if trajectory.q.shape[1] == mechanism.nq else \
                mechanism.configuration(trajectory.coordinates[k])
            unit = "N" if loaded.kind in ("prismatic", "cylinder") else "N·m"
            where = f"t = {trajectory.t[k]:.4g} s of the task as given, where {loaded.joint} (the smallest margin) " \
                f"carries its largest |τ| = {np.abs(loaded.duty.torque).max():.4g} {unit}"
            frame = mechanism.tool_frame if mechanism.tool_frame in mechanism.frame_names else None
            sections += [Section("Task", [Text(f"{task.name} ({task.source}): payload {task.payload:g} kg"), Table(
                pd.DataFrame(trajectory.as_dict()["coordinates"]), f"{trajectory.duration:.4g} s as given (SI)",
                "task")] + ([Code(Path(task.source).read_text(encoding="utf-8"))]
                            if given is None and Path(task.source).is_file() else [])),
                Section("Most loaded pose", [Text(where), Chart(configuration_figure(
                    mechanism, q, frame=frame, title=f"{mechanism.name} at t = {trajectory.t[k]:.4g} s"))])]
        return Report(lines[0], sections, lines[-1])


def _distal_first(mech: Mechanism, names: list[str]) -> list[str]:
    """``names`` ordered distal to proximal: by the depth of their joint in the tree, deepest first (stable)."""
    def depth(name: str) -> int:
        joint, count = mech.joint_id(name), 0
        while joint > 0:
            joint, count = mech.model.parents[joint], count + 1
        return count

    return sorted(names, key=lambda n: -depth(n))


def sizing_bytes(nv: int) -> float:
    """Bytes per sample a sizing of a mechanism of ``nv`` coordinates keeps beyond its loads (the trajectory, the
    duties, the mounted mechanism's dynamics of every pass; an upper bound, tests/test_bounded.py): the per-pair
    checks go a block at a time (:data:`~mechatron.drives.checks.SAMPLE_BLOCK`) and do not grow with the task."""
    return 8.0 * (64 + 48 * nv)


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
                   cylinders: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
                   loads: Loads = None, task: str = "task", direct: bool = True, pressure: float = 32e6,
                   chain_efficiency: float = 1.0, single_pass: bool = False, max_iterations: int = MAX_ITERATIONS,
                   progress: Callable[[int, int], None] | None = None,
                   limits: DriveLimits | None = None) -> SizingResult:
    """Size every coordinate of ``mech`` that moves or carries load along ``trajectory``, as a system.

    The duty of every coordinate comes from the inverse dynamics without drive inertia
    (:func:`~mechatron.drives.duty.joint_duties`); then motors with gearboxes (revolute joints) or linear drives —
    ball screws, racks — (prismatic joints) are checked pair by pair (:func:`size_joint`), catalog cylinders for
    hydraulic cylinders (:func:`~mechatron.drives.cylinders.size_cylinder`).

    The drives load the mechanism. Pass 1 sizes every coordinate with weightless drives (all a ``single_pass``
    sizing does). Each further pass goes distal to proximal: each coordinate is sized with every drive chosen so
    far (this pass's, else the last pass's) on the body that carries it (:func:`~mechatron.drives.duty.mount_drives`:
    its motor's and converter's catalog mass at its placement, by default on the joint's parent body at the joint),
    until a pass chooses what the one before chose: the fixed point, where every drive was sized with every other
    final drive's mass in the model. A drive's spinning parts (rotor J_m, the converter's motor side J_c) are counted
    once, in its own joint's motor torque (J_m + J_c) u ω̇ (Pinocchio's armature (J_m + J_c) u²), never as a body
    inertia. A choice that comes back after changing is a cycle: the sizing stops and says so, as it does after
    ``max_iterations`` passes; the result is then not feasible. Hydraulic cylinders are sized in the same passes;
    their masses are the mechanism file's (``barrel_mass``, ``rod_mass``), not the catalog's.

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
        single_pass: Size each coordinate once, with weightless drives (the drives load no joint).
        max_iterations: The most passes (≥ 2).
        progress: Called with (done, total) after each coordinate of each pass.
        limits: Emergency-stop limit, required screw life, supply voltage (:class:`~.checks.DriveLimits`).
    """
    from ..io.budget import count, require
    from .catalogs import default_catalog
    from .cylinders import cylinder_lengths, size_cylinder
    from .loads import loads_bytes

    _check_arguments(inertia_ratio_max, pressure, chain_efficiency, max_iterations)
    warn_limits(mech, trajectory, f"task '{task}'")
    require(f"sizing along {count(len(trajectory.t))} samples of {mech.name}", len(trajectory.t),
            sizing_bytes(mech.nv) + loads_bytes(mech.nv, bool(mech.closures)),
            fixed=sizing_fixed_bytes(len(trajectory.t), *_catalog_counts(motors, gearboxes, linear)),
            advice="use fewer samples (a larger time step of the trajectory)")
    bare = {d.name: d for d in joint_duties(mech, trajectory, loads)
            if np.abs(d.speed).max() > 0 or np.abs(d.torque).max() > 0}
    if not bare:
        raise InputError(f"no joint of {mech.name} moves or carries load in the task")
    kinds = {d.kind for d in bare.values()}
    motors = motors if motors is not None or kinds <= {"cylinder"} else default_catalog("motors")
    gearboxes = gearboxes if gearboxes is not None or "revolute" not in kinds else default_catalog("gearboxes")
    linear = linear if linear is not None or "prismatic" not in kinds else default_catalog("linear")
    cylinders = cylinders if cylinders is not None or "cylinder" not in kinds else default_catalog("cylinders")
    names = list(bare)
    order = _distal_first(mech, names)
    carriers = {n: drive_carrier(mech, n) for n in names if bare[n].kind != "cylinder"}

    lengths = cylinder_lengths(mech, trajectory)

    sized: dict[tuple, DriveSizing] = {}

    def size_one(duty: JointDuty, scale: float | None) -> DriveSizing:
        """The sizing of one coordinate, once per duty and pace: a pass repeats the duties of the coordinates
        whose load did not change (the same arrays give the same choice)."""
        key = (duty.name, scale, duty.load_inertia, duty.stroke, *(None if x is None else x.tobytes() for x in (
            duty.t, duty.speed, duty.acceleration, duty.torque, duty.static_torque, duty.moving)))
        if key not in sized:
            sized[key] = size_fresh(duty, scale)
        return sized[key]

    def size_fresh(duty: JointDuty, scale: float | None) -> DriveSizing:
        if duty.kind == "cylinder":
            spec, length = mech.cylinders[duty.name], lengths[duty.name]
            if objective == "time":
                return size_cylinder(duty.scaled(scale), spec, cylinders, pressure=pressure, objective="mass",
                                     length=length)
            return size_cylinder(duty, spec, cylinders, pressure=pressure, objective=objective, length=length)
        return size_joint(duty, motors, gearboxes, linear, objective=objective, inertia_ratio_max=inertia_ratio_max,
                          direct=direct, time_scale=scale, chain_efficiency=chain_efficiency, limits=limits)

    fastest: dict[tuple, float] = {}

    def fastest_for(d: JointDuty) -> float:
        """The fastest pace of one coordinate (:func:`fastest_scale`), once per duty: a pass changes only the
        duties of the coordinates proximal to a drive that changed."""
        key = (d.name, d.torque.tobytes(), d.static_torque.tobytes(), d.load_inertia)
        if key not in fastest:
            fastest[key] = fastest_scale(
                _cylinder_passes(d, mech.cylinders[d.name], cylinders, pressure, lengths[d.name])
                if d.kind == "cylinder" else
                _motor_passes(d, motors, converters_for(d, gearboxes, linear, direct, chain_efficiency),
                              inertia_ratio_max, limits))
        return fastest[key]

    def pace(duties: dict[str, JointDuty]) -> float | None:
        """The ``time`` objective's scale: the slowest coordinate's fastest pace sets the whole task's."""
        if objective != "time":
            return None
        scales = [fastest_for(d) for d in duties.values()]
        return max(scales) if all(math.isfinite(x) for x in scales) else 1.0

    def mounts(chosen: dict[str, DriveSizing]) -> dict[str, DriveMount]:
        return {n: DriveMount(n, s.choice(), s.drive_mass() or 0.0, *carriers[n])
                for n, s in chosen.items() if n in carriers}

    known: dict[tuple, dict[str, JointDuty]] = {}

    def duties_with(chosen: dict[str, DriveSizing]) -> dict[str, JointDuty]:
        """The duties with the drives of ``chosen`` on their bodies (those on a fixed body change nothing)."""
        moving = [m for m in mounts(chosen).values() if m.parent > 0 and m.mass > 0]
        key = tuple(sorted((m.joint, m.drive) for m in moving))
        if not key:
            return bare
        if key not in known:
            known.clear()
            loaded = joint_duties(mount_drives(mech, moving), trajectory, loads)
            known[key] = {d.name: d for d in loaded if d.name in bare}
        return known[key]

    chosen: dict[str, DriveSizing] = {}
    iterations: list[Iteration] = []

    def run_pass(weighted: bool) -> tuple:
        before = dict(chosen)
        scale = pace(duties_with(chosen) if weighted else bare)
        for k, name in enumerate(order):
            chosen[name] = size_one((duties_with(chosen) if weighted else bare)[name], scale)
            if progress:
                progress(k + 1, len(order))
        changes = tuple((n, before[n].choice() if n in before else None, chosen[n].choice()) for n in order
                        if n not in before or before[n].choice() != chosen[n].choice())
        iterations.append(Iteration(len(iterations) + 1, weighted, scale or 1.0, changes))
        return tuple(chosen[n].choice() for n in order), scale

    history = [run_pass(False)]
    converged, cycle = True, ()
    if not single_pass and any(m.parent > 0 and m.mass > 0 for m in mounts(chosen).values()):
        converged = False
        while len(iterations) < max_iterations:
            state = run_pass(True)
            if state == history[-1]:
                converged = True
                break
            if state in history:
                cycle = (history.index(state) + 1, len(iterations))
                break
            history.append(state)
    scale = iterations[-1].time_scale
    sized = [chosen[n] for n in names]
    duration = bare[names[0]].duration
    return SizingResult(mech.name, task, objective, sized, scale, iterations, single_pass, converged,
                        mounts(chosen), cycle, duration)


def _check_arguments(inertia_ratio_max: float, pressure: float, chain_efficiency: float, max_iterations: int
                     ) -> None:
    """The numeric arguments of :func:`size` and :func:`size_mechanism`, checked (one line naming the argument)."""
    if isinstance(max_iterations, float):  # 3.0 is a count, 2.5 is not
        raise InputError(f"max_iterations must be a whole number >= 2 and <= {MAX_PASSES}, got {max_iterations!r}")
    number("max_iterations", max_iterations, integer=True, minimum=2, maximum=MAX_PASSES)
    number("inertia_ratio_max", inertia_ratio_max, positive=True)
    number("pressure", pressure, positive=True, maximum=1e10, unit="Pa")
    number("chain_efficiency", chain_efficiency, minimum=MIN_EFFICIENCY, maximum=1.0)


def _cylinder_passes(duty: JointDuty, spec: Cylinder, catalog: pd.DataFrame, pressure: float,
                     length: np.ndarray | None = None) -> Callable[[float], bool]:
    from .cylinders import size_cylinder

    return lambda k: size_cylinder(duty.scaled(k), spec, catalog, pressure=pressure, length=length).feasible


def size(mech: Mechanism, task: Task | Trajectory | str | Path | None = None, *,
         motors: pd.DataFrame | str | Path | None = None, gearboxes: pd.DataFrame | str | Path | None = None,
         linear: pd.DataFrame | str | Path | None = None, cylinders: pd.DataFrame | str | Path | None = None,
         objective: str = "mass", loads: Loads = None, inertia_ratio_max: float = 10.0, direct: bool = True,
         pressure: float = 32e6, chain_efficiency: float = 1.0, single_pass: bool = False,
         max_iterations: int = MAX_ITERATIONS, progress: Callable[[int, int], None] | None = None,
         limits: DriveLimits | None = None) -> SizingResult:
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

    Returns:
        A :class:`SizingResult`; ``result.feasible`` is false when some joint has no feasible drive (its closest
        candidates are reported) or the choice did not settle.
    """
    from ..dynamics.motion import Trajectory
    from ..dynamics.task import Task, default_task, read_task
    from ..model.loads import as_loads
    from .catalogs import read_catalog

    _check_arguments(inertia_ratio_max, pressure, chain_efficiency, max_iterations)
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
                          single_pass=single_pass, max_iterations=max_iterations, progress=progress,
                          limits=limits)

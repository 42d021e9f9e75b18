r"""The sizing of one motor-driven joint: every motor × converter pair checked (:mod:`~mechatron.drives.checks`),
the feasible pairs ranked by an objective (:mod:`~mechatron.drives.search`) and the best one chosen:

- ``mass``: the lightest motor + converter (then the cheapest);
- ``cost``: the cheapest (then the lightest);
- ``margin``: the largest smallest margin over all checks (the most reserve);
- ``time``: the shortest execution of the task. The task's moves are replayed k times slower (k < 1: faster;
  speeds × 1/k, accelerations × 1/k², gravity and external loads unchanged) and its dwells keep their length; for
  each coordinate the smallest k at which some drive passes every check is found by bisection, the slowest
  coordinate sets k for the whole task, and every coordinate then gets its lightest drive at that pace.

When no pair passes, the closest pairs (smallest worst load factor) are reported with the checks they fail. Each
choice is explained (:class:`JointSizing`): its deciding check (the smallest margin) and the runners-up with why they
lost (:meth:`~mechatron.drives.report.DriveSizing.explanation`). The drives load the mechanism
(:func:`~mechatron.drives.system.size_mechanism`): every chosen motor and gearbox is a mass on the body that carries
it, and the sizing repeats, distal to proximal, until the choice no longer changes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ..errors import InputError
from ..report.result import json_ready
from .checks import ALL_CHECKS, Check, DriveLimits, MotorArrays, PairChecks, _load_factor, failures, motor_side
from .converters import Converters, converters_for
from .duty import JointDuty
from .motor import continuous_torque, peak_torque_limit
from .report import REPORTED, RPM, DriveSizing
from .search import fastest_scale, first_in_order, motor_passes, smallest_worst

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

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
        closest: the pairs with the smallest worst load factor and the checks they fail (empty when a pair is
            feasible).
        duty: the joint's duty (:class:`~mechatron.drives.duty.JointDuty`), replayed at ``time_scale``.
        motor_data, converter_data: the chosen pair's catalog data (SI).
        time_scale: the task's moves were replayed this many times slower (``time`` objective; < 1: faster), its
            dwells as they are.
        alternatives: the ranking and the rivals (:class:`Alternatives`), found when first asked for.

    Properties :attr:`ranking` and :attr:`rivals`: the best feasible pairs and the pairs that come before the chosen
    one by the objective but fail a check (:class:`Alternatives`).
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
    closest: pd.DataFrame
    duty: JointDuty
    motor_data: dict = field(default_factory=dict)
    converter_data: dict = field(default_factory=dict)
    time_scale: float = 1.0
    alternatives: Alternatives | None = field(default=None, repr=False)

    @property
    def ranking(self) -> pd.DataFrame:
        """The feasible pairs, best first (at least :data:`~mechatron.drives.report.REPORTED` when there are that
        many): motor, converter, kind, ratio, mass (kg), price, smallest_margin (exact), score (the objective's
        value)."""
        return self.alternatives.ranking() if self.alternatives else pd.DataFrame()

    @property
    def rivals(self) -> pd.DataFrame:
        """The pairs ranked just before the chosen one by the objective, nearest first, which fail a check (the
        ranking's columns, worst_load_factor and ``failed``); empty for the ``margin`` objective and when nothing
        is feasible."""
        return self.alternatives.rivals() if self.alternatives else pd.DataFrame()

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



def size_joint(duty: JointDuty, motors: pd.DataFrame, gearboxes: pd.DataFrame | None = None,
               linear: pd.DataFrame | None = None, *, objective: str = "mass", inertia_ratio_max: float = 10.0,
               direct: bool = True, time_scale: float | None = None, chain_efficiency: float = 1.0,
               limits: DriveLimits | None = None, converters: Converters | None = None,
               motor_arrays: MotorArrays | None = None) -> JointSizing:
    """Check the motor × converter pairs for one joint and choose the best feasible one by ``objective``.

    The pairs are screened by exact bounds and checked sample by sample in the order of the objective until the
    first feasible one (:func:`~mechatron.drives.search.first_in_order`; ``margin``: by branch and bound,
    :func:`~mechatron.drives.search.smallest_worst`). Its ranking — the best feasible pairs (at least
    :data:`~mechatron.drives.report.REPORTED` when there are that many), exact — and its rivals — the pairs ranked
    just before it by the objective, all of which fail a check — are found the same way when first asked for
    (:class:`Alternatives`).

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
        converters: The converters to try, when already built (:func:`~mechatron.drives.converters.converters_for`
            of this duty, the catalogs, ``direct`` and ``chain_efficiency``).
        motor_arrays: ``motors`` as arrays, when already read (:class:`~mechatron.drives.checks.MotorArrays`).
    """
    if objective not in OBJECTIVES:
        raise InputError(f"unknown objective {objective!r}; expected one of: {', '.join(OBJECTIVES)}")
    if not inertia_ratio_max > 0:
        raise InputError(f"the inertia ratio limit must be > 0, got {inertia_ratio_max!r}")
    if len(motors) == 0:
        raise InputError("the motor catalog is empty")
    conv = converters or converters_for(duty, gearboxes, linear, direct, chain_efficiency)
    arrays = motor_arrays or MotorArrays.of(motors)
    scale = 1.0
    if objective == "time":
        scale = time_scale or fastest_scale(motor_passes(duty, arrays, conv, inertia_ratio_max, limits))
        scale = scale if math.isfinite(scale) else 1.0
        duty = duty.scaled(scale)
    checks = PairChecks(duty, arrays, conv, inertia_ratio_max, limits)
    table = _Table(arrays.key, conv, (arrays.mass, conv.mass), (arrays.price, conv.price))
    alternatives = Alternatives(checks, table, objective)
    if objective == "margin":
        first = alternatives.best()
    else:
        first_m, first_c, *before = first_in_order(checks, *alternatives.order(), 1)
        first = first_m, first_c
        alternatives.before = tuple(before) if len(first_m) else None
    feasible = bool(len(first[0]))
    closest = pd.DataFrame() if feasible else _closest(checks, table)
    if feasible:
        m, c = int(first[0][0]), int(first[1][0])
    else:
        m = int(np.flatnonzero(arrays.key == closest["motor"].iloc[0])[0])
        c = int(np.flatnonzero(conv.key == closest["converter"].iloc[0])[0])
    return JointSizing(duty.name, duty.kind, objective, feasible, str(arrays.key[m]), str(conv.key[c]),
                       str(conv.kind[c]), float(conv.ratio[c]), checks.checks(m, c), closest, duty,
                       motors.iloc[m].to_dict(), {f: getattr(conv, f)[c].item() for f in conv.__dataclass_fields__},
                       scale, alternatives)


@dataclass(frozen=True)
class _Table:
    """What a report says of a motor × converter pair: names, ratio, mass (kg), price, margin, failed checks; the
    motors' keys, mass and price as (per motor, per converter) arrays, the pair's the sum."""

    motors: np.ndarray
    conv: Converters
    mass: tuple[np.ndarray, np.ndarray]
    price: tuple[np.ndarray, np.ndarray]

    def rows(self, checks: PairChecks, m: np.ndarray, c: np.ndarray, failed: bool = False) -> pd.DataFrame:
        """The pairs (m[i], c[i]): motor, converter, kind, ratio, mass, price, smallest_margin (1 − the worst load
        factor, exact) and, with ``failed``, worst_load_factor and the checks they fail (``name ×load factor``)."""
        factors = _load_factor(*checks.table(m, c)).reshape(len(m), len(ALL_CHECKS))
        out = pd.DataFrame({"motor": self.motors[m], "converter": self.conv.key[c],
                            "kind": self.conv.kind[c], "ratio": self.conv.ratio[c],
                            "mass": self.mass[0][m] + self.mass[1][c], "price": self.price[0][m] + self.price[1][c],
                            "smallest_margin": 1 - factors.max(axis=1, initial=0.0)})
        if failed:
            out["worst_load_factor"] = factors.max(axis=1, initial=0.0)
            out["failed"] = [failures(ALL_CHECKS, f) for f in factors]
        return out


@dataclass
class Alternatives:
    """What a joint's choice is weighed against, found when a report first asks (the sizing itself needs only the
    first feasible pair): the ranking — the best feasible pairs by the objective, exact — and the rivals — the
    pairs just before the chosen one by the objective, which fail a check. ``before``: the rivals' (motors,
    converters), set by the search that found the chosen pair."""

    checks: PairChecks
    table: _Table
    objective: str
    before: tuple[np.ndarray, np.ndarray] | None = None
    _ranking: pd.DataFrame | None = field(default=None, repr=False)
    _rivals: pd.DataFrame | None = field(default=None, repr=False)

    def order(self) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """(primary, tie): the objective's (per motor, per converter) scores — mass then price, or price then mass
        for ``cost``."""
        mass, price = self.table.mass, self.table.price
        return (price, mass) if self.objective == "cost" else (mass, price)

    def ranking(self) -> pd.DataFrame:
        """The best feasible pairs (:attr:`JointSizing.ranking`), with their indices ``_m`` and ``_c`` for the
        ``margin`` objective's choice."""
        if self._ranking is None:
            if self.objective == "margin":
                m, c = smallest_worst(self.checks, REPORTED, feasible_only=True)
                score = self.checks.worst(m, c)
            else:
                primary, tie = self.order()
                m, c, *_ = first_in_order(self.checks, primary, tie, REPORTED)
                score = primary[0][m] + primary[1][c]
            tie_break = ["price"] if self.objective in ("mass", "time") else ["mass"]
            rows = self.table.rows(self.checks, m, c).assign(score=score, _m=m, _c=c)
            self._ranking = rows.sort_values(["score", *tie_break], kind="stable").reset_index(drop=True)
        return self._ranking.drop(columns=["_m", "_c"])

    def best(self) -> tuple[np.ndarray, np.ndarray]:
        """(motors, converters) of the ranking's first pair (none when nothing is feasible)."""
        self.ranking()
        return self._ranking["_m"].to_numpy()[:1], self._ranking["_c"].to_numpy()[:1]

    def rivals(self) -> pd.DataFrame:
        """The rivals (:attr:`JointSizing.rivals`): none for the ``margin`` objective (:attr:`before` ``None``)."""
        if self._rivals is None:
            self._rivals = pd.DataFrame() if self.before is None else \
                self.table.rows(self.checks, *self.before, failed=True)
        return self._rivals


def _closest(checks: PairChecks, table: _Table) -> pd.DataFrame:
    """The pairs with the smallest worst load factor and the checks they fail."""
    m, c = smallest_worst(checks, REPORTED)
    return table.rows(checks, m, c, failed=True).drop(columns=["kind", "smallest_margin"])


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
lost (:meth:`~mechatron.drives.report.DriveSizing.explanation`), the gearbox's duty (the task's cycles and load peaks
per hour, the maker's rule its peak torque was checked by, the emergency stops its emergency torque is allowed) and
every kind of converter (direct drive, harmonic gearboxes, ball screws…) that one rule set by an option removes
whole: no pair of that kind passes, but one would without that rule alone (:data:`RULES`: the emergency-stop torque,
the inertia ratio, the supply voltage, the screw life, the gearbox's shock factors); the report names the rule, the
best pair it removed and the option that changes it. The drives load the mechanism
(:func:`~mechatron.drives.system.size_mechanism`): every chosen motor and gearbox is a mass on the body that carries
it, and the sizing repeats, distal to proximal, until the choice no longer changes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ..errors import InputError
from ..report.result import json_ready
from .brakes import NO_BRAKE, assumed, with_brakes
from .checks import (
    ALL_CHECKS,
    PASS_TOLERANCE,
    Check,
    DriveLimits,
    MotorArrays,
    PairChecks,
    _load_factor,
    failures,
    motor_side,
    peak_count,
    peak_torque_factor,
)
from .converters import Converters, converters_for
from .duty import JointDuty
from .motor import continuous_torque, peak_torque_limit
from .options import CHAIN_EFFICIENCY, INERTIA_RATIO_MAX, OBJECTIVE, check_inertia_ratio, check_objective
from .report import REPORTED, RPM, Deferred, DriveSizing, Later
from .search import _growing, _motor_blocks, fastest_scale, feasible_pairs, first_in_order, motor_passes, smallest_worst
from .thermal import DEFAULT_AMBIENT, ZERO_CELSIUS, ThermalData, duty_type, winding_temperature

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The rules whose limit an option sets, by check: what the rule is and the option that changes it (the command
#: line's; the API's and a study's names in parentheses). A kind of converter that one of them removes whole is
#: reported (:meth:`Alternatives.ruled_out`).
RULES: dict[str, tuple[str, str]] = {
    "transmission emergency torque": (
        "the emergency-stop torque: the motor's peak torque through the gear against the gearbox's emergency "
        "torque", "--stop-torque or --stop-current (stop_torque, stop_current): the torque or current the drive "
        "limits an emergency stop to"),
    "inertia ratio": ("the load-to-motor inertia ratio",
                      f"--inertia-ratio (inertia_ratio_max; default {INERTIA_RATIO_MAX:g})"),
    "voltage limit": ("the supply voltage", "--voltage (voltage; default each motor's catalog voltage)"),
    "screw equivalent load": ("the required screw life", "--screw-life-h (screw_life; default 20,000 h)"),
    "transmission peak torque": (
        "the gearbox's peak torque over the maker's shock factor at the task's load peaks per hour",
        "the gearbox catalog's shock_factors column (the maker's factors by cycles per hour), or a slower task"),
}


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
        motor_data, converter_data: the chosen pair's catalog data (SI; the motor's catalog row made when first
            read).
        time_scale: the task's moves were replayed this many times slower (``time`` objective; < 1: faster), its
            dwells as they are.
        alternatives: the ranking and the rivals (:class:`Alternatives`), found when first asked for.
        ambient: the ambient temperature of the thermal check (K; :attr:`DriveLimits.ambient
            <mechatron.drives.checks.DriveLimits.ambient>`).
        motor_figures: the numbers of the motor's catalog row the totals read (:meth:`motor_number`), known
            without the row.
        brake_note: when no pair is feasible and some of the closest pairs' motors lack the brake the joint needs:
            that said plainly, and that those pairs are ranked by their other checks (:func:`brake_note`); else "".

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
    closest: pd.DataFrame = Deferred()
    duty: JointDuty
    motor_data: dict = Deferred(Later(dict))
    converter_data: dict = field(default_factory=dict)
    time_scale: float = 1.0
    alternatives: Alternatives | None = field(default=None, repr=False)
    ambient: float = DEFAULT_AMBIENT
    motor_figures: dict = field(default_factory=dict, repr=False, compare=False)
    brake_note: str = ""

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
        return n, self.motor_number("rotor_inertia") * accel + base

    def motor_number(self, name: str) -> float | None:
        """The motor's catalog number ``name`` (SI; ``None`` or NaN where the catalog lacks it): from
        :attr:`motor_figures` where known there, else from its catalog row :attr:`motor_data`."""
        figures = self.motor_figures
        return figures[name] if name in figures else self.motor_data.get(name)

    def drive_mass(self) -> float:
        """Motor + converter mass (kg) from the catalogs (a missing mass counts 0)."""
        return _known(self.motor_number("mass")) + _known(self.converter_data.get("mass"))

    def drive_price(self) -> float:
        """Motor + converter price (the catalogs' currency; a missing price counts 0)."""
        return _known(self.motor_number("price")) + _known(self.converter_data.get("price"))

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
        """(mean speed (rad/s), RMS torque (N·m)): the point of the RMS check (of the S1 curve's), computed for a
        motor checked by its winding's temperature instead (trapezoidal time means)."""
        n, torque = self.operating_points()
        weights = self.duty.time_weights()
        rms = next((c.value for c in self.checks if c.name == "RMS torque"), math.sqrt(float(weights @ torque**2)))
        mean_speed = next((c.value for c in self.checks if c.name == "transmission mean input speed"),
                          float(weights @ np.abs(n)))
        return mean_speed, rms

    def winding_temperature(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
        """(t (s), T_w, T_h (K)): the winding's and the housing's temperature at every sample of the task repeated
        to its periodic steady state (:func:`~mechatron.drives.thermal.winding_temperature`), for the chosen pair;
        ``None`` for a motor without the thermal data."""
        thermal = ThermalData.of(pd.DataFrame([self.motor_data]))
        if not thermal.given[0]:
            return None
        n, torque = self.operating_points()
        return (self.duty.t, *winding_temperature(self.duty.t, torque, n, thermal, 0, self.ambient))

    def thermal(self) -> dict:
        """How the motor's heat was checked: ``check`` (``winding temperature rise``, the two-node model of the
        catalog's thermal data, or ``RMS torque``, against the S1 curve at the mean speed, for a motor without
        them), ``duty_type``, ``cyclic_duration_factor``, ``duty_reason`` and ``duty_clause`` (IEC 60034-1 of the
        motor's speed and torque, :func:`~mechatron.drives.thermal.duty_type`: why that type, and the clause defining
        it), ``ambient_K``, and with the model ``winding_max_K`` (the winding's highest temperature over the cycle;
        where the losses run away, with the resistance and k_t held at their values at the limit temperature),
        ``winding_limit_K``, ``runaway`` (no steady state) and, where there is one, ``magnet_K`` (the magnets'
        temperature: the housing's time mean over the cycle)."""
        if "_thermal" in self.__dict__:
            return dict(self.__dict__["_thermal"])
        duty = duty_type(self.duty, *self.operating_points())
        out = {"check": "RMS torque", "duty_type": str(duty), "cyclic_duration_factor": duty.factor,
               "duty_reason": duty.reason, "duty_clause": duty.clause, "ambient_K": self.ambient}
        rise = next((c for c in self.checks if c.name == "winding temperature rise"), None)
        if rise is not None:
            hottest = self.winding_temperature()
            runaway = bool(hottest is not None and not np.isfinite(hottest[1]).all())
            out.update(check=rise.name, winding_max_K=self.ambient + rise.value,
                       winding_limit_K=self.ambient + rise.limit, runaway=runaway)
            if hottest is not None and not runaway:
                t, housing = hottest[0], hottest[2]
                out["magnet_K"] = float(np.trapezoid(housing, t) / (t[-1] - t[0]) if len(t) > 1 else housing[0])
        self.__dict__["_thermal"] = out
        return dict(out)

    def thermal_lines(self) -> list[str]:
        """The thermal check used, as a line of the text report."""
        info = self.thermal()
        ambient = f"{info['ambient_K'] - ZERO_CELSIUS:.4g} °C ambient"
        if info["check"] == "RMS torque":
            what = (f"RMS torque against the S1 curve at the mean speed (the catalog gives no thermal data for "
                    f"{self.motor})")
        else:
            hottest, limit = info["winding_max_K"] - ZERO_CELSIUS, info["winding_limit_K"] - ZERO_CELSIUS
            reaches = (f"runs away (its copper loss, the magnets weakening, outgrows the cooling: no steady state; "
                       f"with the resistance and k_t held at their values at its limit temperature it would reach "
                       f"{hottest:.4g} °C)" if info["runaway"] else
                       f"reaches {hottest:.4g} °C, the magnets {info['magnet_K'] - ZERO_CELSIUS:.4g} °C,")
            what = (f"winding temperature, two-node model of winding and housing at {ambient}: the winding {reaches} "
                    f"of its {limit:.4g} °C")
        return [f"    thermal check: {what}; duty type {info['duty_type']} [IEC 60034-1, {info['duty_clause']}]: "
                f"{info['duty_reason']}"]

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

    def gearbox_duty(self) -> dict | None:
        """The chosen gearbox's duty (``None`` for direct drive, a screw or a rack; the module docstring of
        :mod:`~mechatron.drives.checks`): cycles_per_hour = 3600/T (the task of duration T s repeats, as sized),
        peaks_per_cycle n_p (:func:`~mechatron.drives.checks.peak_count`), peaks_per_hour = n_p · 3600/T, peak_rule
        (the rule applied, a key of :data:`~mechatron.drives.converters.PEAK_RULES`) and rule (it, in words, with
        its numbers), shock_factor f_s (the maker's table at peaks_per_hour; ``None`` for the other rules and above
        the table), peak_torque_factor (1/f_s, 0 above the table, else 1: the limit is T2B × it),
        cycle_rating_per_hour (the catalog's), above_rating (whether the peaks per hour exceed it), peak_torque_Nm
        (T2B, the catalog's) and emergency_stops (how many times its emergency torque is allowed in its life)."""
        c = self.converter_data
        if not c.get("peak_rule"):
            return None
        cycles = 1.0 / self.duty.duration if self.duty.duration > 0 else 0.0
        peaks = peak_count(self.duty.acceleration)
        factor = float(peak_torque_factor(peaks * cycles, c["shock_rates"], c["shock_factors"])[0])
        rule = c["peak_rule"]
        duty = {"cycles_per_hour": 3600.0 * cycles, "peaks_per_cycle": peaks, "peaks_per_hour": 3600.0 * peaks * cycles,
                "peak_rule": rule, "shock_factor": 1 / factor if rule == "shock_factors" and factor > 0 else None,
                "peak_torque_factor": factor, "cycle_rating_per_hour": 3600.0 * c["cycle_rating"],
                "above_rating": bool(peaks * cycles > c["cycle_rating"] * (1 + PASS_TOLERANCE)),
                "peak_torque_Nm": c["peak_torque"], "emergency_stops": c["emergency_stops"]}
        return {**duty, "rule": _rule_text(duty, c["shock_rates"])}

    def ruled_out(self) -> list[dict]:
        """The kinds of converter one rule set by an option removes whole (:meth:`Alternatives.ruled_out`)."""
        return self.alternatives.ruled_out() if self.alternatives else []

    def explanation(self) -> dict:
        """:meth:`~mechatron.drives.report.DriveSizing.explanation` with gearbox_duty (:meth:`gearbox_duty`) and
        ruled_out (:meth:`ruled_out`: kind, check, rule, option, candidate, motor, converter, mass, price,
        message)."""
        return {**super().explanation(), "gearbox_duty": self.gearbox_duty(), "ruled_out": self.ruled_out()}

    def cells(self, check: Check) -> tuple[str, str, str, str]:
        """:meth:`~mechatron.drives.report.DriveSizing.cells`; a motor without the brake the joint needs has no
        holding torque: limit ``none``, margin ``no brake`` (not the sentinel's :data:`~mechatron.drives.brakes.
        NO_BRAKE` and its huge negative margin)."""
        value, limit, unit, margin = super().cells(check)
        return (value, "none", unit, margin) if _no_brake(check) else (value, limit, unit, margin)

    def margin_text(self, check: Check) -> str:
        return "no brake" if _no_brake(check) else super().margin_text(check)

    def closest_notes(self) -> list[str]:
        return [self.brake_note] if self.brake_note and not self.feasible else []

    def smallest_margin(self) -> float:
        """The smallest margin over the checks (< 0: a check fails); a missing brake, a yes-or-no failure, counts as
        −1 (−100 %: no holding torque at all; mechatron's rule), not the sentinel :data:`~mechatron.drives.brakes.
        NO_BRAKE`'s margin of about −10⁹, so that a study's ``smallest_margin`` stays a measure of how far."""
        return min((-1.0 if _no_brake(c) else c.margin for c in self.checks), default=math.inf)

    def explanation_lines(self) -> list[str]:
        """The deciding check, the runners-up, the gearbox's duty and the kinds a rule removed whole."""
        lines = [*self.thermal_lines(), *super().explanation_lines()]
        duty = self.gearbox_duty()
        if duty is not None:
            lines.append(f"    gearbox duty: {duty['cycles_per_hour']:.4g} cycles/h (the {self.duty.duration:.4g} s "
                         f"task repeated) × {duty['peaks_per_cycle']} load peaks = {duty['peaks_per_hour']:.4g} "
                         f"peaks/h; peak torque: {duty['rule']}; emergency torque allowed "
                         f"{duty['emergency_stops']:,.0f} times in its life")
        return lines + [f"    ruled out: {row['message']}" for row in self.ruled_out()]

    @property
    def drive(self) -> str | None:
        """The chosen servo drive's key (a motor catalog paired with drives, :func:`~mechatron.drives.servo.
        pair_drives`: :attr:`motor` is then ``motor + drive``), ``None`` without drives."""
        key = self.motor_data.get("drive_key")
        return None if key is None or (isinstance(key, float) and math.isnan(key)) else str(key)

    def drive_line(self) -> str:
        """The servo drive as the text report names it: its key, rated and peak current (A), peak time (s), mass."""
        m = self.motor_data
        return (f"servo drive {self.drive}: {m['drive_rated_current']:.4g} A rated, {m['drive_peak_current']:.4g} A "
                f"peak for {m['drive_peak_time']:.4g} s, {_known(m.get('drive_mass')):.4g} kg")

    def headline(self) -> str:
        through = "direct drive" if self.converter == "direct" else \
            f"{self.converter_kind} {self.converter}, u = {self.ratio:.4g}"
        drive = self.drive
        if drive is None:
            return f"{self.joint}: motor {self.motor} + {through}"
        motor = self.motor.removesuffix(f" + {drive}")
        return f"{self.joint}: motor {motor} with {self.drive_line()} + {through}"

    def candidate(self, row: dict) -> str:
        return f"{row['motor']} + {row['converter']}"

    def as_dict(self) -> dict:
        """joint, kind, feasible, motor, gearbox (the converter's key), converter_kind, ratio, time_scale, checks
        (name, value, limit, unit, margin, pass; SI), alternatives (the best feasible pairs), closest (when none is
        feasible), brake_note (:attr:`brake_note`), thermal (:meth:`thermal`: the thermal check used, the duty
        type, the winding's temperature), and
        the explanation (:meth:`~mechatron.drives.report.DriveSizing.explanation`): deciding_check, runner_up,
        drive_mass_kg, drive_price; ``drive``: the servo drive's key (``None`` without drives)."""
        return json_ready({
            "joint": self.joint, "kind": self.kind, "feasible": self.feasible, "motor": self.motor, "drive": self.drive,
            "gearbox": self.converter, "converter_kind": self.converter_kind, "ratio": self.ratio,
            "time_scale": self.time_scale, "checks": [c.as_dict() for c in self.checks],
            "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
            "closest": [] if self.feasible else self.closest.to_dict(orient="records"), "thermal": self.thermal(),
            "brake_note": self.brake_note, **self.explanation()})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chosen motor's speed–torque chart: its continuous (S1) and intermittent zones
        (:mod:`~mechatron.drives.motor`, the same in every quadrant), the task's operating points folded into the
        first quadrant (|n|, |T_m|) coloured by time (the colour bar), the braking ones (T_m n < 0) ringed, and the
        RMS torque at the mean speed (the thermal check); speed in rpm, torque in N·m. Its data:
        :meth:`chart_frame` (signed)."""
        from ..report.figures import figure_axes, style_axes, time_colour_bar

        figure, ax = figure_axes(ax, 7.5, 5)
        m = self.motor_data
        n, torque = self.operating_points()
        top = m["max_speed"]
        speed, s1, peak = self._zones()
        ax.fill_between(speed * RPM, 0, peak, color="tab:orange", alpha=0.18, label="intermittent zone")
        ax.fill_between(speed * RPM, 0, s1, color="tab:green", alpha=0.3, label="continuous zone (S1)")
        points = ax.scatter(np.abs(n) * RPM, np.abs(torque), s=6, c=self.duty.t, cmap="viridis",
                            label="operating points |n|, |T_m| of all four quadrants (colour: time)")
        time_colour_bar(ax, points)
        braking = n * torque < 0
        if braking.any():
            ax.scatter(np.abs(n[braking]) * RPM, np.abs(torque[braking]), s=24, facecolors="none",
                       edgecolors="black", linewidths=0.6, label="of them braking (T_m·n < 0: quadrants II, IV)")
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
               linear: pd.DataFrame | None = None, *, objective: str = OBJECTIVE,
               inertia_ratio_max: float = INERTIA_RATIO_MAX, direct: bool = True, time_scale: float | None = None,
               chain_efficiency: float = CHAIN_EFFICIENCY,
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
    check_objective(objective)
    check_inertia_ratio(inertia_ratio_max)
    if len(motors) == 0:
        raise InputError("the motor catalog is empty")
    conv = converters or converters_for(duty, gearboxes, linear, direct, chain_efficiency)
    arrays = with_brakes(motor_arrays or MotorArrays.of(motors), duty)  # a brake's J_b and m_b where one is needed
    scale = 1.0
    if objective == "time":
        scale = time_scale or fastest_scale(motor_passes(duty, arrays, conv, inertia_ratio_max, limits))
        scale = scale if math.isfinite(scale) else 1.0
        duty = duty.scaled(scale)
    checks = PairChecks(duty, arrays, conv, inertia_ratio_max, limits)
    table = _Table(arrays.key, conv, (arrays.objective_mass(), conv.mass), (arrays.price, conv.price))
    alternatives = Alternatives(checks, table, objective, motors=arrays, limits=limits or DriveLimits(),
                                inertia_ratio_max=inertia_ratio_max)
    if objective == "margin":
        first = alternatives.best()
    else:
        first_m, first_c, *before = first_in_order(checks, *alternatives.order(), 1)
        first = first_m, first_c
        alternatives.before = tuple(before) if len(first_m) else None
    feasible = bool(len(first[0]))
    closest: Later | pd.DataFrame = Later(pd.DataFrame)  # empty, made if asked for
    note = ""
    if feasible:
        m, c = int(first[0][0]), int(first[1][0])
    else:
        closest = frame = _closest(checks, table, alternatives)
        m = int(np.flatnonzero(arrays.key == frame["motor"].iloc[0])[0])
        c = int(np.flatnonzero(conv.key == frame["converter"].iloc[0])[0])
        note = brake_note(duty, arrays, frame["motor"].to_numpy())
    figures = {"rotor_inertia": arrays.rotor[m], "mass": arrays.mass[m], "price": arrays.price[m],
               "torque_constant": arrays.kt[m], "resistance": arrays.resistance[m]}
    return JointSizing(duty.name, duty.kind, objective, feasible, str(arrays.key[m]), str(conv.key[c]),
                       str(conv.kind[c]), float(conv.ratio[c]), checks.checks(m, c), closest, duty,
                       Later(_catalog_row, motors, m),
                       {f: _entry(getattr(conv, f)[c]) for f in conv.__dataclass_fields__}, scale, alternatives,
                       (limits or DriveLimits()).ambient, {k: float(v) for k, v in figures.items()},
                       note)


def _no_brake(check: Check) -> bool:
    """Whether ``check`` is the holding-torque check of a motor without the brake its joint needs."""
    return check.name == "brake holding torque" and check.limit <= NO_BRAKE


def brake_note(duty: JointDuty, motors: MotorArrays, closest: NDArray[np.str_]) -> str:
    """What an infeasible joint's report says of the brakes of its ``closest`` pairs' motors (keys): "" where each
    has the brake the joint needs, or it needs none; else that they lack it — no motor of the catalog has one, or
    some of the closest do not — and that such pairs are ranked by their other checks, as if each had a brake
    (:func:`_closest`)."""
    brakes = motors.brakes
    if brakes is None or brakes.hold == 0:
        return ""
    index = np.flatnonzero(np.isin(motors.key, closest))
    lacking = sorted(set(motors.key[index[brakes.missing(index)]].tolist()))
    if not lacking:
        return ""
    unit = "N·m" if duty.kind == "revolute" else "N"
    held = f"{duty.name} holds {brakes.hold:.4g} {unit} at rest (gravity and the external loads)"
    if brakes.braked == 0:
        return (f"no motor of the catalog has a brake, and {held}: every candidate fails the brake holding torque "
                f"check; the closest are ranked by their other checks, as if each had a brake")
    return (f"{held}; {', '.join(lacking)} {'has' if len(lacking) == 1 else 'have'} no brake (the catalog gives one "
            f"for {brakes.braked} of its {len(motors)} motors): ranked by the other checks, as if it had one")


def _entry(value: np.ndarray) -> object:
    """One converter's entry of a :class:`~mechatron.drives.converters.Converters` field: a number or a text, or a
    list (a row of a table)."""
    return value.item() if np.ndim(value) == 0 else value.tolist()


def _rule_text(duty: dict, shock_rates: list[float]) -> str:
    """The rule a gearbox's peak torque was checked by (:meth:`JointSizing.gearbox_duty`), in words with its
    numbers."""
    peak, per_hour, rating = duty["peak_torque_Nm"], duty["peaks_per_hour"], duty["cycle_rating_per_hour"]
    if duty["peak_rule"] == "shock_factors":
        if duty["shock_factor"] is None:
            last = 3600.0 * max(r for r in shock_rates if math.isfinite(r))
            return (f"the maker's shock factors end at {last:,.0f}/h: no rating at {per_hour:,.0f} load peaks/h "
                    f"(limit 0)")
        return (f"the maker's shock factor f_s = {duty['shock_factor']:.4g} at {per_hour:,.0f} load peaks/h: "
                f"T2B {peak:.4g} N·m / {duty['shock_factor']:.4g} = {peak * duty['peak_torque_factor']:.4g} N·m")
    if duty["peak_rule"] == "repeated_peak":
        return (f"the maker's repeated peak torque, T2B {peak:.4g} N·m at any rate (a strain-wave gear's limit of the "
                f"torque of every start and stop)")
    if duty["above_rating"]:
        return (f"T2B {peak:.4g} N·m taken unchanged at {per_hour:,.0f} load peaks/h, above its rating of "
                f"{rating:,.0f}/h: no maker rule given (mechatron's assumption, not the maker's)")
    return f"T2B {peak:.4g} N·m, rated up to {rating:,.0f} load peaks/h (no maker rule given above it)"


def _catalog_row(catalog: pd.DataFrame, row: int) -> dict:
    """Row ``row`` of a catalog as a dict (column → value)."""
    return catalog.iloc[row].to_dict()


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
    motors: MotorArrays | None = field(default=None, repr=False)
    limits: DriveLimits = field(default_factory=DriveLimits, repr=False)
    inertia_ratio_max: float = INERTIA_RATIO_MAX
    _ranking: pd.DataFrame | None = field(default=None, repr=False)
    _rivals: pd.DataFrame | None = field(default=None, repr=False)
    _ruled_out: list[dict] | None = field(default=None, repr=False)

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

    def best(self, count: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """(motors, converters) of the ranking's first ``count`` pairs (none when nothing is feasible)."""
        self.ranking()
        return self._ranking["_m"].to_numpy()[:count], self._ranking["_c"].to_numpy()[:count]

    def rivals(self) -> pd.DataFrame:
        """The rivals (:attr:`JointSizing.rivals`): none for the ``margin`` objective (:attr:`before` ``None``)."""
        if self._rivals is None:
            self._rivals = pd.DataFrame() if self.before is None else \
                self.table.rows(self.checks, *self.before, failed=True)
        return self._rivals


    def ruled_out(self) -> list[dict]:
        """The kinds of converter (``direct``, a gearbox ``type``, a linear drive ``type``) of which no pair passes
        every check, but one would without one rule of :data:`RULES` — or without all of them together, where no one
        alone does — made once: each with kind, check (the rule's checks, ``; ``-joined), rule, option, candidate
        (the best pair that rule removed, by the objective; the lightest for ``margin``), motor, converter, mass
        (kg), price and message (one line for the report)."""
        if self._ruled_out is not None:
            return self._ruled_out
        conv, out = self.checks.conv, []
        alive = set(self.ranking()["kind"]) if self.motors is not None else set(conv.kind)
        for kind in dict.fromkeys(conv.kind.tolist()):
            index = np.flatnonzero(conv.kind == kind)
            if kind in alive:
                continue
            passing, alone, together = self._screen_kind(index)
            if passing and self._best(self.checks, index) is not None:
                continue
            subset = conv.subset(index)
            found = [(rule, self._best(self._relaxed((rule,), subset), np.arange(len(index)), index))
                     for rule in RULES if alone[rule] and self._applies(rule, subset)]
            found = [(rule, best) for rule, best in found if best is not None]
            if not found and together:  # several rules together?
                rules = tuple(rule for rule in RULES if self._applies(rule, subset))
                best = self._best(self._relaxed(rules, subset), np.arange(len(index)), index) if rules else None
                found = [(rules, best)] if best is not None and len(rules) > 1 else []
            for rules, (m, c) in found:
                out.append(self._ruled_out_row(kind, (rules,) if isinstance(rules, str) else rules, m, c))
        self._ruled_out = out
        return out

    def _screen_kind(self, converters: np.ndarray) -> tuple[bool, dict[str, bool], bool]:
        """What the pairs of ``converters`` (every motor with each) can be, from lower bounds of their checks
        (:meth:`PairChecks.table` at level 0: the time means in closed form, no pass over the samples; a block of
        motors at a time; necessary conditions): (some pair may pass every check, for each rule of :data:`RULES`
        whether some pair may fail it alone, whether some pair may fail only rules of :data:`RULES`)."""
        columns = [ALL_CHECKS.index(rule) for rule in RULES]
        passing, alone, together = False, np.zeros(len(columns), dtype=bool), False
        for block in _motor_blocks(self.checks):
            m, c = (x.ravel() for x in np.meshgrid(np.arange(block.start, block.stop), converters, indexing="ij"))
            fails = _load_factor(*self.checks.table(m, c, 0)) > 1 + PASS_TOLERANCE
            ruled, other = fails[:, columns], np.delete(fails, columns, axis=1).any(axis=1)
            passing |= bool((~fails).all(axis=1).any())
            alone |= (ruled & ~other[:, None] & (ruled.sum(axis=1) == 1)[:, None]).any(axis=0)
            together |= bool((ruled.any(axis=1) & ~other).any())
        return passing, dict(zip(RULES, alone.tolist())), together

    def _applies(self, rule: str, conv: Converters) -> bool:
        """Whether ``rule`` can remove a converter of ``conv``: its check applies to them (the peak torque's shock
        factors: some of them lower T2B at this task's load peaks per hour)."""
        if rule == "transmission emergency torque":
            return bool(np.isfinite(conv.emergency_torque).any())
        if rule == "screw equivalent load":
            return bool(np.isfinite(conv.dynamic_load).any())
        if rule == "transmission peak torque":
            return bool((peak_torque_factor(self.checks.peak_rate, conv.shock_rates, conv.shock_factors) < 1).any())
        if rule == "voltage limit":
            return bool(np.isfinite(self.checks.voltage).any())
        return True

    def _relaxed(self, rules: tuple[str, ...], conv: Converters) -> PairChecks:
        """The checks of the pairs of ``conv`` without ``rules``: the converters' emergency torque, screw load
        rating or shock factors (none: T2B at any rate), the motors' supply voltage or the inertia ratio limit
        taken as infinite."""
        motors, limits, ratio_max, inf = self.motors, self.limits, self.inertia_ratio_max, np.full(len(conv), np.inf)
        if "transmission emergency torque" in rules:
            conv = replace(conv, emergency_torque=inf)
        if "screw equivalent load" in rules:
            conv = replace(conv, dynamic_load=np.full(len(conv), np.nan))
        if "transmission peak torque" in rules:
            conv = replace(conv, shock_rates=np.full_like(conv.shock_rates, np.nan),
                           shock_factors=np.full_like(conv.shock_factors, np.nan))
        if "voltage limit" in rules:
            motors, limits = replace(motors, voltage=np.full(len(motors), np.nan)), replace(limits, voltage=None)
        if "inertia ratio" in rules:
            ratio_max = math.inf
        return PairChecks(self.checks._duty, motors, conv, ratio_max, limits)

    def _best(self, checks: PairChecks, converters: np.ndarray, catalog: np.ndarray | None = None
              ) -> tuple[int, int] | None:
        """The first pair (motor, converter index of ``checks``) of ``converters`` that passes every check of
        ``checks``, by the objective (mass then price; price then mass for ``cost``; the catalogs' order last);
        ``catalog``: the joint's index of each converter of ``checks`` (default the same)."""
        catalog = converters if catalog is None else catalog
        (first_m, first_c), (tie_m, tie_c) = self.order()
        found_m, found_c = [], []
        for block in _motor_blocks(checks):  # the pairs that pass the screening, a block of motors at a time
            motors = np.arange(block.start, block.stop)
            mm, cc = np.nonzero(checks.screen(motors[:, None], converters[None, :]))
            found_m.append(motors[mm])
            found_c.append(converters[cc])
        m, c = np.concatenate(found_m), np.concatenate(found_c)
        joint_c = catalog[np.searchsorted(converters, c)] if catalog is not converters else c
        order = np.lexsort((tie_m[m] + tie_c[joint_c], first_m[m] + first_c[joint_c]))
        m, c = m[order], c[order]
        for part in _growing(len(m)):
            ok = feasible_pairs(checks, m[part], c[part], screened=True)
            if ok.any():
                k = part.start + int(np.argmax(ok))
                return int(m[k]), int(c[k])
        return None

    def _ruled_out_row(self, kind: str, rules: tuple[str, ...], m: int, c: int) -> dict:
        """One kind a rule removed whole, with the best pair it removed (m: motor, c: the kind's converter)."""
        conv = self.checks.conv
        index = np.flatnonzero(conv.kind == kind)[c]
        motor, converter = str(self.table.motors[m]), str(conv.key[index])
        mass, price = self.table.mass[0][m] + self.table.mass[1][index], \
            self.table.price[0][m] + self.table.price[1][index]
        what = "direct drive" if kind == "direct" else f"{kind} gearbox" if conv.peak_rule[index] else kind
        checks = " and ".join(f"the {rule} check ({RULES[rule][0]})" for rule in rules)
        best = "the lightest" if self.objective == "margin" else "the best"
        chosen = self.ranking()
        than = f"; the chosen drive: {chosen['mass'].iloc[0]:.4g} kg, {chosen['price'].iloc[0]:.4g}" if len(chosen) \
            else ""
        options = "; ".join(RULES[rule][1] for rule in rules)
        message = (f"no {what} passes every check; without {checks} {best} would be {motor} + {converter} "
                   f"({mass:.4g} kg, {price:.4g}{than}) — change it with {options}")
        return {"kind": kind, "check": "; ".join(rules), "rule": "; ".join(RULES[r][0] for r in rules),
                "option": options, "candidate": f"{motor} + {converter}", "motor": motor, "converter": converter,
                "mass": float(mass), "price": float(price), "message": message}


def _closest(checks: PairChecks, table: _Table, alternatives: Alternatives) -> pd.DataFrame:
    """The pairs with the smallest worst load factor and the checks they fail. On a joint that holds a load at rest
    where motors lack a brake (:func:`~mechatron.drives.brakes.assumed`), the pairs are ranked as if each had a brake
    that holds — the brake check is a yes or no, and its factor (τ_g over a holding torque of ~0) would rank them by
    their gravity torque alone: first the pairs that would then pass every check, in the objective's order (those
    the sizing would choose from), then the smallest worst load factor of the others."""
    braked = assumed(alternatives.motors) if alternatives.motors is not None else None
    if braked is None:
        m, c = smallest_worst(checks, REPORTED)
    else:
        relaxed = PairChecks(checks._duty, braked, checks.conv, alternatives.inertia_ratio_max, alternatives.limits)
        would = replace(alternatives, checks=relaxed, _ranking=None, _rivals=None, _ruled_out=None)
        m, c = would.best(REPORTED)
        if len(m) < REPORTED:
            pairs = set(zip(m.tolist(), c.tolist()))
            more = [(i, j) for i, j in zip(*(x.tolist() for x in smallest_worst(relaxed, 2 * REPORTED)))
                    if (i, j) not in pairs][:REPORTED - len(m)]
            m = np.concatenate([m, np.array([i for i, _ in more], dtype=int)]).astype(int)
            c = np.concatenate([c, np.array([j for _, j in more], dtype=int)]).astype(int)
    return table.rows(checks, m, c, failed=True).drop(columns=["kind", "smallest_margin"])


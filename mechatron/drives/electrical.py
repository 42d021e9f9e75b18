r"""The electrical side of a sizing: the power each motor draws or gives back over the task, alone and on a common
DC bus, the braking energy and the braking resistor.

Each chosen motor turns at n(t) (rad/s) with torque T_m(t) (N·m) (:meth:`JointSizing.operating_points
<mechatron.drives.sizing.JointSizing.operating_points>`: the load through the converter's efficiency, plus the
rotor and converter inertia). As its equivalent DC motor (:mod:`mechatron.drives.motor`), with torque constant k_t
(N·m/A) and winding resistance R (Ω) where the catalog gives them, it takes the current I = T_m / k_t and the
electrical power

    P(t) = T_m n + R I²  (W),

the shaft power plus the copper loss (without R, the shaft power alone). P < 0 is power given back (regenerated):
the motor brakes a load that returns kinetic or potential energy. The losses the model counts are those of the
converter (its efficiency, in T_m) and the copper loss; the inverter's and the iron losses are not counted.

- Per axis (a drive with its own DC link): the regenerated energy E_reg = ∫ max(−P, 0) dt over the cycle, the peak
  braking power max(−P) and the continuous braking power E_reg / T (the mean power a braking resistor dissipates
  when the cycle repeats, nothing stored).
- On a common DC bus the axes exchange power: P_bus = Σ P_i, and only E_bus = ∫ max(−P_bus, 0) dt ≤ Σ E_reg,i
  reaches the braking resistor (peak max(−P_bus), continuous E_bus / T).

Integrals are exact for P linear between samples (the trapezoidal rule, split where P changes sign).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Protocol

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..report.result import Result, json_ready

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .report import DriveSizing


class SizedJoints(Protocol):
    """What the power balances read of a sizing (a :class:`~mechatron.drives.result.SizingResult`): its sized
    joints (a protocol, so that this module needs no import of the result, which imports it)."""

    @property
    def joints(self) -> Sequence[DriveSizing]: ...


BUS = "DC bus"
#: The columns of :meth:`ElectricalBalance.to_frame` (SI units; J, W, A, V).
COLUMNS = ("axis", "motor", "energy_drawn", "energy_regenerated", "copper_loss", "peak_power",
           "peak_braking_power", "continuous_braking_power", "peak_current", "rms_current", "peak_voltage")


def positive_energy(t: ArrayLike, power: ArrayLike) -> float:
    """∫ max(P, 0) dt (J) of the power P (W) sampled at the times t (s), linear between samples: the trapezoidal
    rule, with an interval where P changes sign split at its zero."""
    t, p = np.asarray(t, dtype=float), np.asarray(power, dtype=float)
    a, b, dt = p[:-1], p[1:], np.diff(t)
    both = np.where((a >= 0) & (b >= 0), (a + b) / 2, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        rising = np.where((a < 0) & (b > 0), b**2 / (2 * (b - a)), 0.0)
        falling = np.where((a > 0) & (b < 0), a**2 / (2 * (a - b)), 0.0)
    return float(np.sum((both + rising + falling) * dt))


def _time_mean(t: NDArray[np.float64], values: NDArray[np.float64]) -> float:
    duration = t[-1] - t[0]
    return float(np.trapezoid(values, t) / duration) if duration > 0 else float(values[0])


@dataclass
class AxisPower:
    """The electrical power of one motor over the task.

    Attributes:
        axis, motor: the joint and its motor's key.
        t: the sample times (s).
        speed, torque: motor speed n (rad/s) and torque T_m (N·m).
        torque_constant, resistance: k_t (N·m/A) and R (Ω), NaN where the catalog does not give them.

    Its current, copper loss and power are computed when first read, then kept.
    """

    axis: str
    motor: str
    t: NDArray[np.float64]
    speed: NDArray[np.float64]
    torque: NDArray[np.float64]
    torque_constant: float = math.nan
    resistance: float = math.nan

    @cached_property
    def current(self) -> NDArray[np.float64]:
        """I = T_m / k_t (A); NaN without a torque constant."""
        return self.torque / self.torque_constant

    @cached_property
    def copper_loss(self) -> NDArray[np.float64]:
        """R I² (W); 0 without a torque constant and resistance."""
        if not (math.isfinite(self.torque_constant) and math.isfinite(self.resistance)):
            return np.zeros_like(self.torque)
        return self.resistance * self.current**2

    @cached_property
    def power(self) -> NDArray[np.float64]:
        """P = T_m n + R I² (W), > 0 drawn from the supply, < 0 given back."""
        return self.torque * self.speed + self.copper_loss

    def summary(self) -> dict:
        """The row of :data:`COLUMNS` for this axis (J, W, A, V; None where the catalog lacks the data)."""
        p, t = self.power, self.t
        regenerated = positive_energy(t, -p)
        duration = t[-1] - t[0]
        electrical = math.isfinite(self.torque_constant)
        current = self.current if electrical else None
        voltage = (self.torque_constant * self.speed + self.resistance * current
                   if electrical and math.isfinite(self.resistance) else None)
        return {"axis": self.axis, "motor": self.motor, "energy_drawn": positive_energy(t, p),
                "energy_regenerated": regenerated, "copper_loss": float(np.trapezoid(self.copper_loss, t)),
                "peak_power": float(max(p.max(), 0.0)), "peak_braking_power": float(max(-p.min(), 0.0)),
                "continuous_braking_power": regenerated / duration if duration > 0 else 0.0,
                "peak_current": float(np.abs(current).max()) if current is not None else None,
                "rms_current": math.sqrt(_time_mean(t, current**2)) if current is not None else None,
                "peak_voltage": float(np.abs(voltage).max()) if voltage is not None else None}


@dataclass
class ElectricalBalance(Result):
    """The electrical power of every motor of a sizing over the task and of their common DC bus (the module
    docstring), a result.

    ``to_frame()``: one row per axis and a last row ``DC bus`` (:data:`COLUMNS`; J, W, A, V). ``as_dict()``:
    cycle_time (s), axes (each row), bus (the bus row). ``plot()``: the power of every axis and of the bus over
    time, the braking (regenerated) part of the bus shaded. ``str()``: the table and the braking resistor.
    """

    axes: list[AxisPower]
    t: NDArray[np.float64] = field(repr=False)

    @cached_property
    def bus_power(self) -> NDArray[np.float64]:
        """P_bus = Σ P_i (W)."""
        return np.sum([a.power for a in self.axes], axis=0)

    @property
    def cycle_time(self) -> float:
        return float(self.t[-1] - self.t[0])

    def bus(self) -> dict:
        """The bus row: energy drawn and regenerated (J), the copper loss (J), peak power, peak and continuous
        braking power (W)."""
        p = self.bus_power
        regenerated = positive_energy(self.t, -p)
        return {"axis": BUS, "motor": None, "energy_drawn": positive_energy(self.t, p),
                "energy_regenerated": regenerated,
                "copper_loss": float(sum(np.trapezoid(a.copper_loss, self.t) for a in self.axes)),
                "peak_power": float(max(p.max(), 0.0)), "peak_braking_power": float(max(-p.min(), 0.0)),
                "continuous_braking_power": regenerated / self.cycle_time if self.cycle_time > 0 else 0.0,
                "peak_current": None, "rms_current": None, "peak_voltage": None}

    def to_frame(self) -> pd.DataFrame:
        """One row per axis and the ``DC bus`` row (:data:`COLUMNS`), SI units."""
        return pd.DataFrame([a.summary() for a in self.axes] + [self.bus()], columns=list(COLUMNS))

    def as_dict(self) -> dict:
        """cycle_time (s), axes (one dict per axis, :data:`COLUMNS`), bus (the bus row), JSON-ready."""
        return json_ready({"cycle_time": self.cycle_time, "axes": [a.summary() for a in self.axes],
                           "bus": self.bus()})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The electrical power of every axis and of the DC bus over time (W, or kW from 1 kW), the bus's braking
        part shaded."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 8, 4.5)
        largest = max(float(np.abs(a.power).max()) for a in self.axes)
        scale, unit = (1e3, "kW") if largest >= 1e3 else (1.0, "W")
        for a in self.axes:
            ax.plot(self.t, a.power / scale, lw=1, label=f"{a.axis} ({a.motor})")
        bus = self.bus_power / scale
        ax.plot(self.t, bus, color="k", lw=1.8, label="DC bus (sum)")
        ax.fill_between(self.t, bus, 0, where=bus < 0, color="tab:red", alpha=0.25, label="braking (regenerated)")
        ax.axhline(0, color="0.5", lw=0.6)
        style_axes(ax, "time (s)", f"electrical power ({unit}, < 0 regenerated)", "electrical power over the task",
                   legend=True)
        return figure

    def __str__(self) -> str:
        from ..dynamics.series import text_table

        rows = [{"axis": r["axis"], "motor": r["motor"], "drawn (J)": r["energy_drawn"],
                 "regenerated (J)": r["energy_regenerated"], "copper (J)": r["copper_loss"],
                 "peak (W)": r["peak_power"], "peak braking (W)": r["peak_braking_power"],
                 "peak current (A)": r["peak_current"], "RMS current (A)": r["rms_current"]}
                for r in [a.summary() for a in self.axes] + [self.bus()]]
        bus = self.bus()
        return "\n".join([
            f"electrical power over the task ({self.cycle_time:.3f} s): P = T·n + R·I², I = T/k_t",
            text_table(rows, digits=4),
            f"braking resistor on the common DC bus: peak {bus['peak_braking_power']:.4g} W, continuous "
            f"{bus['continuous_braking_power']:.4g} W ({bus['energy_regenerated']:.4g} J per cycle)"])


def axis_power(sizing: DriveSizing) -> AxisPower:
    """The :class:`AxisPower` of a motor-driven joint's sizing (its chosen motor and converter)."""
    n, torque = sizing.operating_points()

    def number(name: str) -> float:
        value = sizing.motor_number(name)
        return math.nan if value is None else float(value)

    return AxisPower(sizing.joint, sizing.motor, np.asarray(sizing.duty.t, dtype=float), n, torque,
                     number("torque_constant"), number("resistance"))


def electrical(sizing: SizedJoints | Sequence[DriveSizing]) -> ElectricalBalance:
    """The electrical power of every motor of ``sizing`` (a :class:`~mechatron.drives.sizing.SizingResult` or
    its joints; hydraulic cylinders are left out) over the task, per axis and on a common DC bus (the module
    docstring)."""
    joints = getattr(sizing, "joints", sizing)
    axes = [axis_power(j) for j in joints if hasattr(j, "operating_points")]
    if not axes:
        raise InputError("no motor-driven joint to take the electrical power of")
    t = axes[0].t
    for a in axes[1:]:
        if a.t is not t and (a.t.shape != t.shape or not np.allclose(a.t, t, rtol=0,
                                                                     atol=1e-12 * max(1.0, abs(t[-1])))):
            raise InputError(f"axis {a.axis} is sampled at other times than {axes[0].axis}: a common bus needs "
                             "one time base")
    return ElectricalBalance(axes, t)

r"""The pump flow and hydraulic power of the cylinders of a sizing over the task.

Each cylinder coordinate with ``count`` cylinders of piston area A_p and annulus A_a moving at v(t) (m/s) under the
force F(t) (N, > 0 pushes) takes in the flow Q_i(t) = count · (A_p v⁺ + A_a v⁻) (m³/s): the piston side when it
extends, the rod side when it retracts (:meth:`CylinderSizing.flow <mechatron.drives.cylinders.CylinderSizing.flow>`),
at the pressure its load needs (:meth:`CylinderSizing.pressure_needed
<mechatron.drives.cylinders.CylinderSizing.pressure_needed>`):

    p_i(t) = min(max(F v, 0) / Q_i(t), p_s),   so  p_i Q_i = min(max(F v, 0), p_s Q_i):

F / (count A_p) where the cylinders push while extending, −F / (count A_a) where they pull while retracting, and 0
where the load drives them (F v < 0: gravity lowering the load; a counterbalance or meter-out valve on the outlet side
holds it, and the pump only fills the inlet side at no pressure) or where they stand still; never above the relief
pressure p_s. The supply is a load-sensing pump: one pump delivers the sum Q(t) = Σ Q_i(t) at the highest pressure
any cylinder taking oil needs, p(t) = max_i {p_i(t) : Q_i(t) > 0} (0 when no oil flows), the cylinders that need
less throttled down to theirs by their valves, so the pump's hydraulic power is P(t) = p(t) Q(t) (W) — the
cylinders' positive power Σ max(F v, 0) when one cylinder moves at a time, more when a lightly loaded cylinder moves
with a heavily loaded one. Lossless otherwise: no cylinder friction, no back pressure on the outlet sides, no
pressure margin of the load sensing, no pump efficiency (the pump's shaft power is P/η of the pump). So a load
raised and lowered by gravity, at rest at both ends, draws its lifting work m g h per cycle.

Reported: per cylinder and for the pump, the peak and mean flow (m³/s), the oil volume per cycle ∫Q dt (m³), the
peak pressure (Pa), the peak and mean power (W), the energy per cycle ∫P dt (J) (a cylinder's own ∫ p_i Q_i dt) and
``energy_at_relief`` = p_s ∫Q dt (J): what a constant-pressure supply at the relief pressure (a fixed pump spilling
over its relief valve) would draw.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ..errors import InputError
from ..report.result import Result, json_ready

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .electrical import SizedJoints
    from .report import DriveSizing

PUMP = "pump"
#: The columns of :meth:`HydraulicSupply.to_frame` (SI units: m³/s, m³, Pa, W, J).
COLUMNS = ("cylinder", "count", "peak_flow", "mean_flow", "volume", "peak_pressure", "peak_power", "mean_power",
           "energy", "energy_at_relief")
#: m³/s → l/min.
L_MIN = 60e3


@dataclass
class HydraulicSupply(Result):
    """The flow, pressure and power of every cylinder coordinate and of the pump over the task (the module
    docstring), a result.

    ``to_frame()``: one row per cylinder coordinate and a last row ``pump`` (:data:`COLUMNS`). ``as_dict()``:
    pressure (Pa), cycle_time (s), cylinders (each row), pump (the pump row). ``plot()``: the flow of every
    cylinder and of the pump over time (l/min). ``str()``: the table with the pump's flow and power.

    Attributes:
        pressure: the system's relief pressure p_s (Pa).
        t: sample times (s).
        flows: cylinder coordinate → Q_i(t) (m³/s).
        counts: cylinder coordinate → how many cylinders side by side.
        pressures: cylinder coordinate → the pressure its load needs, p_i(t) ≤ p_s (Pa); a coordinate left out
            takes the relief pressure at every sample (a constant-pressure supply).
    """

    pressure: float
    t: NDArray[np.float64] = field(repr=False)
    flows: dict[str, NDArray[np.float64]] = field(repr=False)
    counts: dict[str, int] = field(default_factory=dict)
    pressures: dict[str, NDArray[np.float64]] = field(default_factory=dict, repr=False)

    @property
    def pump_flow(self) -> NDArray[np.float64]:
        """Q(t) = Σ Q_i(t) (m³/s)."""
        return np.sum(list(self.flows.values()), axis=0)

    def cylinder_pressure(self, name: str) -> NDArray[np.float64]:
        """p_i(t) (Pa): the pressure cylinder coordinate ``name`` needs (the relief pressure where not given)."""
        given = self.pressures.get(name)
        return np.full(len(self.t), self.pressure) if given is None else np.asarray(given, dtype=float)

    @property
    def pump_pressure(self) -> NDArray[np.float64]:
        """p(t) = max_i {p_i(t) : Q_i(t) > 0} (Pa), 0 where no oil flows: the load-sensing pump's pressure."""
        taking = [np.where(q > 0, self.cylinder_pressure(n), 0.0) for n, q in self.flows.items()]
        return np.max(taking, axis=0)

    @property
    def power(self) -> NDArray[np.float64]:
        """P(t) = p(t) Q(t) (W), the pump's hydraulic power."""
        return self.pump_pressure * self.pump_flow

    @property
    def cycle_time(self) -> float:
        return float(self.t[-1] - self.t[0])

    def _row(self, name: str, count: int | None, flow: NDArray[np.float64], pressure: NDArray[np.float64]) -> dict:
        """Flow, volume, pressure, power and energy of one flow Q(t) at the pressure p(t) (the module docstring)."""
        power = pressure * flow
        volume, energy = float(np.trapezoid(flow, self.t)), float(np.trapezoid(power, self.t))
        duration = self.cycle_time
        mean, mean_power = (volume / duration, energy / duration) if duration > 0 else (float(flow[0]),
                                                                                        float(power[0]))
        return {"cylinder": name, "count": count, "peak_flow": float(flow.max()), "mean_flow": mean,
                "volume": volume, "peak_pressure": float(pressure.max()), "peak_power": float(power.max()),
                "mean_power": mean_power, "energy": energy, "energy_at_relief": self.pressure * volume}

    def rows(self) -> list[dict]:
        """One row per cylinder coordinate and the pump row (:data:`COLUMNS`)."""
        return [self._row(n, self.counts.get(n), q, self.cylinder_pressure(n)) for n, q in self.flows.items()] + \
            [self._row(PUMP, None, self.pump_flow, self.pump_pressure)]

    def to_frame(self) -> pd.DataFrame:
        """One row per cylinder coordinate and the ``pump`` row (:data:`COLUMNS`), SI units."""
        return pd.DataFrame(self.rows(), columns=list(COLUMNS))

    def as_dict(self) -> dict:
        """pressure (Pa), cycle_time (s), cylinders (their rows), pump (the pump row), JSON-ready."""
        rows = self.rows()
        return json_ready({"pressure": self.pressure, "cycle_time": self.cycle_time, "cylinders": rows[:-1],
                           "pump": rows[-1]})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The flow of every cylinder coordinate and the pump flow over time (l/min)."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 8, 4.5)
        for name, flow in self.flows.items():
            ax.plot(self.t, flow * L_MIN, lw=1, label=name)
        ax.plot(self.t, self.pump_flow * L_MIN, color="k", lw=1.8, label="pump (sum)")
        pump = self.rows()[-1]
        style_axes(ax, "time (s)", "flow (l/min)", f"pump flow (relief {self.pressure / 1e6:g} MPa): peak "
                   f"{pump['peak_flow'] * L_MIN:.1f} l/min, {pump['peak_power'] / 1e3:.1f} kW", legend=True)
        return figure

    def __str__(self) -> str:
        from ..dynamics.series import text_table

        rows = [{"cylinder": r["cylinder"], "count": r["count"], "peak flow (l/min)": r["peak_flow"] * L_MIN,
                 "mean flow (l/min)": r["mean_flow"] * L_MIN, "volume (l)": r["volume"] * 1e3,
                 "peak pressure (MPa)": r["peak_pressure"] / 1e6, "peak power (kW)": r["peak_power"] / 1e3,
                 "mean power (kW)": r["mean_power"] / 1e3, "energy (kJ)": r["energy"] / 1e3,
                 "at relief (kJ)": r["energy_at_relief"] / 1e3} for r in self.rows()]
        pump = rows[-1]
        return "\n".join([
            f"hydraulic supply, relief pressure {self.pressure / 1e6:g} MPa, over the task ({self.cycle_time:.3f} s): "
            "Q = A·v per cylinder, summed; P = p·Q at the pressure the loads need (a load-sensing pump; 0 where the "
            "load drives the cylinder)",
            text_table(rows, digits=4),
            f"pump: peak flow {pump['peak flow (l/min)']:.4g} l/min, peak power {pump['peak power (kW)']:.4g} kW, "
            f"mean power {pump['mean power (kW)']:.4g} kW, {pump['energy (kJ)']:.4g} kJ per cycle "
            f"({pump['at relief (kJ)']:.4g} kJ at the relief pressure throughout)"])


def hydraulic_supply(sizing: SizedJoints | Sequence[DriveSizing], pressure: float | None = None
                     ) -> HydraulicSupply:
    """The pump flow and hydraulic power of the cylinders of ``sizing`` (a
    :class:`~mechatron.drives.sizing.SizingResult` or its joints; motor-driven joints are left out), each cylinder at
    the pressure its load needs up to the relief pressure ``pressure`` (Pa; default: the system pressure they were
    sized for)."""
    joints = getattr(sizing, "joints", sizing)
    cylinders = [j for j in joints if hasattr(j, "flow")]
    if not cylinders:
        raise InputError("no hydraulic cylinder to take the flow of")
    pressure = cylinders[0].pressure if pressure is None else pressure
    if not (np.isfinite(pressure) and pressure > 0):
        raise InputError(f"the system pressure must be a finite number > 0 Pa, got {pressure!r}")
    names = [c.joint for c in cylinders]
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:
        raise InputError(f"cylinder {twice} twice: each cylinder coordinate once")
    t = np.asarray(cylinders[0].duty.t, dtype=float)
    for c in cylinders[1:]:
        if c.duty.t.shape != t.shape or not np.allclose(c.duty.t, t, rtol=0, atol=1e-12 * max(1.0, abs(t[-1]))):
            raise InputError(f"cylinder {c.joint} is sampled at other times than {cylinders[0].joint}")
    return HydraulicSupply(float(pressure), t, {c.joint: c.flow() for c in cylinders},
                           {c.joint: c.count for c in cylinders},
                           {c.joint: c.pressure_needed(float(pressure)) for c in cylinders})

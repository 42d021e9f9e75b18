r"""The pump flow and hydraulic power of the cylinders of a sizing over the task.

Each cylinder coordinate with ``count`` cylinders of piston area A_p and annulus A_a moving at v(t) (m/s) takes in
the flow Q_i(t) = count · (A_p v⁺ + A_a v⁻) (m³/s): the piston side when it extends, the rod side when it retracts
(:meth:`CylinderSizing.flow <mechatron.drives.cylinders.CylinderSizing.flow>`). The pump delivers their sum
Q(t) = Σ Q_i(t) at the system pressure p (a constant-pressure supply at the relief pressure), so the hydraulic power
is P(t) = p Q(t) (W). Reported: per cylinder and for the pump, the peak and mean flow (m³/s), the oil volume per
cycle ∫Q dt (m³), the peak and mean power (W) and the energy per cycle ∫P dt (J).
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

    from .report import DriveSizing
    from .sizing import SizingResult

PUMP = "pump"
#: The columns of :meth:`HydraulicSupply.to_frame` (SI units: m³/s, m³, W, J).
COLUMNS = ("cylinder", "count", "peak_flow", "mean_flow", "volume", "peak_power", "mean_power", "energy")
#: m³/s → l/min.
L_MIN = 60e3


@dataclass
class HydraulicSupply(Result):
    """The flow of every cylinder coordinate and of the pump over the task at the system pressure (the module
    docstring), a result.

    ``to_frame()``: one row per cylinder coordinate and a last row ``pump`` (:data:`COLUMNS`). ``as_dict()``:
    pressure (Pa), cycle_time (s), cylinders (each row), pump (the pump row). ``plot()``: the flow of every
    cylinder and of the pump over time (l/min). ``str()``: the table with the pump's flow and power.

    Attributes:
        pressure: the system pressure p (Pa).
        t: sample times (s).
        flows: cylinder coordinate → Q_i(t) (m³/s).
        counts: cylinder coordinate → how many cylinders side by side.
    """

    pressure: float
    t: NDArray[np.float64] = field(repr=False)
    flows: dict[str, NDArray[np.float64]] = field(repr=False)
    counts: dict[str, int] = field(default_factory=dict)

    @property
    def pump_flow(self) -> NDArray[np.float64]:
        """Q(t) = Σ Q_i(t) (m³/s)."""
        return np.sum(list(self.flows.values()), axis=0)

    @property
    def power(self) -> NDArray[np.float64]:
        """P(t) = p Q(t) (W)."""
        return self.pressure * self.pump_flow

    @property
    def cycle_time(self) -> float:
        return float(self.t[-1] - self.t[0])

    def _row(self, name: str, count: int | None, flow: NDArray[np.float64]) -> dict:
        volume = float(np.trapezoid(flow, self.t))
        duration = self.cycle_time
        mean = volume / duration if duration > 0 else float(flow[0])
        return {"cylinder": name, "count": count, "peak_flow": float(flow.max()), "mean_flow": mean,
                "volume": volume, "peak_power": self.pressure * float(flow.max()), "mean_power": self.pressure * mean,
                "energy": self.pressure * volume}

    def rows(self) -> list[dict]:
        """One row per cylinder coordinate and the pump row (:data:`COLUMNS`)."""
        return [self._row(n, self.counts.get(n), q) for n, q in self.flows.items()] + \
            [self._row(PUMP, None, self.pump_flow)]

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
        style_axes(ax, "time (s)", "flow (l/min)", f"pump flow at {self.pressure / 1e6:g} MPa: peak "
                   f"{pump['peak_flow'] * L_MIN:.1f} l/min, {pump['peak_power'] / 1e3:.1f} kW", legend=True)
        return figure

    def __str__(self) -> str:
        from ..dynamics.series import text_table

        rows = [{"cylinder": r["cylinder"], "count": r["count"], "peak flow (l/min)": r["peak_flow"] * L_MIN,
                 "mean flow (l/min)": r["mean_flow"] * L_MIN, "volume (l)": r["volume"] * 1e3,
                 "peak power (kW)": r["peak_power"] / 1e3, "mean power (kW)": r["mean_power"] / 1e3,
                 "energy (kJ)": r["energy"] / 1e3} for r in self.rows()]
        pump = rows[-1]
        return "\n".join([
            f"hydraulic supply at {self.pressure / 1e6:g} MPa over the task ({self.cycle_time:.3f} s): "
            "Q = A·v per cylinder, summed; P = p·Q",
            text_table(rows, digits=4),
            f"pump: peak flow {pump['peak flow (l/min)']:.4g} l/min, peak power {pump['peak power (kW)']:.4g} kW, "
            f"mean power {pump['mean power (kW)']:.4g} kW"])


def hydraulic_supply(sizing: SizingResult | Sequence[DriveSizing], pressure: float | None = None
                     ) -> HydraulicSupply:
    """The pump flow and hydraulic power of the cylinders of ``sizing`` (a
    :class:`~mechatron.drives.sizing.SizingResult` or its joints; motor-driven joints are left out) at
    ``pressure`` (Pa; default: the system pressure they were sized for)."""
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
                           {c.joint: c.count for c in cylinders})

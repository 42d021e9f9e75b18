"""What a front-shovel excavator can lift and dig: the rated lift capacity [ISO 10567]
(:mod:`~mechatron.machines.lift_chart`), the rated tool forces [ISO 6015, 5.2.1–5.2.2] and the digging capability
(mechatron's estimate) (:mod:`~mechatron.machines.digging`) of one design on one machine, as one result (what
``mechatron excavator --lift-chart`` prints)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..report.result import Result
from .digging import DiggingForces, digging_forces
from .excavator import FrontShovelDesign
from .lift_chart import LiftChart, lift_chart
from .shovel_machine import ShovelMachine

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass
class CapacityReport(Result):
    """The lift chart, the rated tool forces and the digging capability of :func:`capacity_report`."""

    lift: LiftChart
    digging: DiggingForces

    def to_frame(self) -> pd.DataFrame:
        """The lift chart: one row per cell and side (:meth:`LiftChart.to_frame
        <mechatron.machines.lift_chart.LiftChart.to_frame>`)."""
        return self.lift.to_frame()

    def as_dict(self) -> dict:
        """``lift_chart`` (rows of radius_m, height_m, over, rated_kg, tipping_kg, hydraulic_kg, limit),
        ``rated_tool_forces`` [ISO 6015, 5.2.1–5.2.2] (``bucket``, ``arm``: force_N, position_m, the cylinder and
        its relief pressure and force, lever_arm_m, radius_m) and ``digging_capability``, mechatron's estimate
        (``bucket``, ``arm``: force_N, position_m, limit and the limits there)
        (:meth:`DiggingForces.as_dict <mechatron.machines.digging.DiggingForces.as_dict>`)."""
        return {**self.lift.as_dict(), **self.digging.as_dict()}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The lift chart as makers draw it (:meth:`LiftChart.plot <mechatron.machines.lift_chart.LiftChart.plot>`)."""
        return self.lift.plot(ax)

    def __str__(self) -> str:
        return f"{self.lift}\n\n{self.digging}"


def capacity_report(design: FrontShovelDesign | None = None, machine: ShovelMachine | None = None,
                    samples: int = 31) -> CapacityReport:
    """The rated lift capacity [ISO 10567] on the default grid (or the machine's ``lift_radii`` × ``lift_heights``),
    the rated tool forces [ISO 6015, 5.2.1–5.2.2] and the digging capability (mechatron's estimate) over
    ``samples``³ positions of the strokes of the front shovel ``design`` on ``machine`` (defaults: the design of
    [Shovel] on the illustrative machine)."""
    design = design or FrontShovelDesign()
    machine = machine or ShovelMachine()
    return CapacityReport(lift_chart(design, machine), digging_forces(design, machine, samples))

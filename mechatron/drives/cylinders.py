r"""Hydraulic cylinders of a closed-loop mechanism chosen from a catalog.

For a cylinder coordinate with force F(t) (N, > 0 pushes: extends the cylinder), speed v(t) (m/s) shared by
``count`` cylinders side by side, and a catalog cylinder of bore D and rod d (piston area A_p = π D²/4, annulus
A_a = A_p − π d²/4):

- push pressure  p = max F⁺ / (count A_p)  ≤ min(rated pressure, system pressure);
- pull pressure  p = max F⁻ / (count A_a)  ≤ the same;
- stroke         L_max − L_min ≤ the catalog's maximum stroke;
- rod buckling   max F⁺ / count ≤ F_E / S, F_E = π² E (π d⁴/64) / L_max² (Euler, pinned ends, the whole cylinder
  taken as a rod of diameter d at full extension — the makers' conservative simplification), S = 3.5;
- flow           Q = count · max(A_p v⁺, A_a v⁻) (m³/s), reported (the pump is a system choice).

The feasible cylinders are ranked by mass (``mass + mass_per_stroke · stroke``), cost or margin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ..errors import InputError
from ..model.mechanism import Cylinder
from ..report.result import json_ready
from .checks import PASS_TOLERANCE, Check, _load_factor
from .duty import JointDuty
from .report import REPORTED, DriveSizing

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

STEEL_MODULUS = 2.1e11  # Pa
BUCKLING_SAFETY = 3.5
CYLINDER_CHECKS = ("push pressure", "pull pressure", "stroke", "rod buckling")


@dataclass
class CylinderSizing(DriveSizing):
    """The chosen catalog cylinder of one cylinder coordinate (or the closest one when none is feasible), a result:
    its table is one row per check, its chart the force per cylinder over the speed with the push and pull limits.

    Attributes:
        joint: the cylinder coordinate's name.
        objective: how the feasible cylinders were ranked (``mass``, ``cost``, ``margin``).
        feasible: whether any catalog cylinder passes every check.
        cylinder, count: the chosen cylinder's key and how many work side by side.
        checks: push and pull pressure (Pa), stroke (m), rod buckling (N).
        peak_flow: Q = count · max(A_p v⁺, A_a v⁻) (m³/s).
        ranking: the feasible cylinders, best first (cylinder, bore, rod, mass, price, smallest margin, peak flow,
            score).
        closest: the cylinders with the smallest worst load factor and the checks they fail.
        duty: the coordinate's duty: force (N, > 0 pushes) and speed (m/s) over time.
        cylinder_data: the chosen cylinder's catalog data (SI).
    """

    joint: str
    objective: str
    feasible: bool
    cylinder: str
    count: int
    checks: list[Check]
    peak_flow: float
    ranking: pd.DataFrame
    closest: pd.DataFrame
    duty: JointDuty
    cylinder_data: dict

    kind = "cylinder"

    @property
    def areas(self) -> tuple[float, float]:
        """(A_p, A_a): the chosen cylinder's piston area π D²/4 and annulus area A_p − π d²/4 (m²)."""
        piston = math.pi * self.cylinder_data["bore"] ** 2 / 4
        return piston, piston - math.pi * self.cylinder_data["rod"] ** 2 / 4

    def drive_columns(self) -> dict:
        return {"motor": None, "converter": self.cylinder, "ratio": None}

    def headline(self) -> str:
        c = self.cylinder_data
        return (f"{self.joint}: cylinder {self.cylinder} ×{self.count} (bore {c['bore'] * 1e3:g} mm, rod "
                f"{c['rod'] * 1e3:g} mm), peak flow {self.peak_flow * 6e4:.1f} l/min")

    def candidate(self, row: dict) -> str:
        return str(row["cylinder"])

    def as_dict(self) -> dict:
        """joint, kind, feasible, motor/gearbox/ratio (None), cylinder, count, bore and rod (m), peak_flow (m³/s) and
        peak_flow_l_min, checks (SI), alternatives, closest (when none is feasible)."""
        return json_ready({
            "joint": self.joint, "kind": "cylinder", "feasible": self.feasible, "motor": None, "gearbox": None,
            "ratio": None, "cylinder": self.cylinder, "count": self.count,
            "bore": self.cylinder_data["bore"], "rod": self.cylinder_data["rod"],
            "peak_flow": self.peak_flow, "peak_flow_l_min": self.peak_flow * 60e3,
            "checks": [c.as_dict() for c in self.checks],
            "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
            "closest": [] if self.feasible else self.closest.to_dict(orient="records")})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The force per cylinder over the cylinder speed along the task (coloured by time), with the push limit
        p A_p and the pull limit −p A_a at the pressure of the push-pressure check; force in kN, speed in m/s."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 7.5, 5)
        push = next(x for x in self.checks if x.name == "push pressure")
        piston, annulus = self.areas
        ax.scatter(self.duty.speed, self.duty.torque / self.count / 1e3, s=6, c=self.duty.t, cmap="viridis",
                   label="force per cylinder along the task (colour: time)")
        ax.axhline(push.limit * piston / 1e3, color="tab:red", label="push limit p·A_piston")
        ax.axhline(-push.limit * annulus / 1e3, color="tab:purple", label="pull limit p·A_annulus")
        style_axes(ax, "cylinder speed (m/s)", "force (kN, + pushes)",
                   f"{self.joint}: {self.count}× {self.cylinder}" + ("" if self.feasible else " — NOT FEASIBLE"),
                   legend=True)
        return figure


def size_cylinder(duty: JointDuty, spec: Cylinder, catalog: pd.DataFrame, *, pressure: float = 32e6,
                  objective: str = "mass") -> CylinderSizing:
    """Choose a catalog cylinder for the coordinate ``spec`` (its stroke and count) doing ``duty``; ``pressure``
    is the system's relief pressure (Pa)."""
    if objective not in ("mass", "cost", "margin"):
        raise InputError(f"cylinders are ranked by mass, cost or margin, not {objective!r}")
    if not pressure > 0:
        raise InputError(f"the system pressure must be > 0 Pa, got {pressure!r}")
    bore, rod = catalog["bore"].to_numpy(), catalog["rod"].to_numpy()
    piston = math.pi * bore**2 / 4
    annulus = piston - math.pi * rod**2 / 4
    stroke = spec.stroke[1] - spec.stroke[0]
    push = max(float(duty.torque.max()), 0.0) / spec.count
    pull = max(float(-duty.torque.min()), 0.0) / spec.count
    limit = np.minimum(catalog["max_pressure"].to_numpy(), pressure)
    euler = math.pi**2 * STEEL_MODULUS * (math.pi * rod**4 / 64) / spec.stroke[1] ** 2
    values = np.stack([push / piston, pull / annulus, np.full(len(catalog), stroke),
                       np.full(len(catalog), push)], axis=1)
    limits = np.stack([limit, limit, catalog["max_stroke"].to_numpy(), euler / BUCKLING_SAFETY], axis=1)
    units = ("Pa", "Pa", "m", "N")
    factors = _load_factor(values, limits)
    worst = factors.max(axis=1)
    feasible = worst <= 1 + PASS_TOLERANCE
    mass = catalog["mass"].fillna(0).to_numpy() if "mass" in catalog else np.zeros(len(catalog))
    if "mass_per_stroke" in catalog:
        mass = mass + catalog["mass_per_stroke"].fillna(0).to_numpy() * stroke
    price = catalog["price"].fillna(0).to_numpy() if "price" in catalog else np.zeros(len(catalog))
    score = {"mass": mass, "cost": price, "margin": worst}[objective]
    extending, retracting = max(float(duty.speed.max()), 0.0), max(-float(duty.speed.min()), 0.0) + 0.0
    flow = spec.count * np.maximum(piston * extending, annulus * retracting)
    index = np.flatnonzero(feasible)
    ranking = pd.DataFrame({"cylinder": catalog["key"].to_numpy()[index], "bore": bore[index], "rod": rod[index],
                            "mass": mass[index] * spec.count, "price": price[index] * spec.count,
                            "smallest_margin": 1 - worst[index], "peak_flow": flow[index], "score": score[index]})
    ranking = ranking.sort_values(["score", "mass"], kind="stable").reset_index(drop=True)
    order = np.argsort(worst, kind="stable")[:REPORTED]
    closest = pd.DataFrame({"cylinder": catalog["key"].to_numpy()[order], "worst_load_factor": worst[order],
                            "failed": ["; ".join(f"{n} ×{factors[i, k]:.2f}" for k, n in enumerate(CYLINDER_CHECKS)
                                                 if factors[i, k] > 1 + PASS_TOLERANCE) or "none" for i in order]})
    i = int(np.flatnonzero(catalog["key"].to_numpy() == ranking["cylinder"].iloc[0])[0]) if len(ranking) \
        else int(order[0])
    checks = [Check(name, float(values[i, k]), float(limits[i, k]), units[k]) for k, name in enumerate(CYLINDER_CHECKS)]
    return CylinderSizing(duty.name, objective, bool(len(ranking)), str(catalog["key"].iloc[i]), spec.count, checks,
                          float(flow[i]), ranking, closest, duty, catalog.iloc[i].to_dict())

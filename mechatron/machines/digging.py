r"""Digging forces of a front-shovel excavator at the bucket lip [ISO 6015], each limited by the hydraulics, by
tipping or by slipping, over the working range.

The bucket-cylinder (breakout) force digs with the bucket cylinder L3 extending (the bucket curls about Q), the
arm-cylinder (tear-out) force with the stick cylinder L2 extending (stick and bucket turn about F) [ISO 6015]; the
other cylinders hold. The lip V then moves along u = ∂V/∂L_j (the other lengths held), and the digging resistance on
the lip is −D û. At each position of the working range (a grid over the three strokes, over the front):

- hydraulic limit D_h: the cylinder forces are linear in D, F(D) = F₀ + D·S with F₀ under the device's own weight
  and S = −(û_x R_x + û_y R_y), R_x, R_y the forces for a unit force along x, y at V (the closed-loop inverse dynamics
  at rest, :func:`~mechatron.dynamics.trajectory.holding_forces`); by virtual work R = −∂V/∂L, so the digging
  cylinder's S_j = |∂V/∂L_j| and, without gravity, D_h = F_relief,j / |∂V/∂L_j|, the calculated tool force of
  [ISO 6015]. D_h is the smallest D at which any cylinder reaches its relief force (the digging one at its relief
  pressure, or a holding one giving way first) (:func:`~mechatron.machines.shovel_machine.largest_load`);
- tipping D_t: the machine tips about its front or rear tipping line
  (:func:`~mechatron.machines.shovel_machine.tipping_force`, the whole machine with the device in that pose);
- slipping D_s = μ M g / (|û_x| − μ û_y): the horizontal force equals the friction of the ground's normal force
  (:func:`~mechatron.machines.shovel_machine.slipping_force`).

The digging force is min(D_h, D_t, D_s), the smallest naming its ``limit``; the largest over the range and where are
reported per tool.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..io.values import number
from ..report.result import Result
from .excavator import FrontShovelDesign
from .shovel_machine import (
    ShovelMachine,
    device_centres,
    gravity,
    largest_load,
    restoring_moments,
    slipping_force,
    tipping_force,
)
from .shovel_poses import assembled, serpentine

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The digging tools of [ISO 6015]: the cylinder that digs by extending and the pivot the lip turns about.
TOOLS = {"bucket": ("L3", "Q"), "arm": ("L2", "F")}
LIMITS = ("hydraulic", "tipping", "slipping")
LIP = "V"


@dataclass
class DiggingForces(Result):
    """The digging forces of :func:`digging_forces`: ``table`` one row per position (cylinder lengths L1_m…L3_m, the
    lip's radius from the slew axis and height, m, and per tool its force and the three limits, N, the governing
    limit and the cylinder that gives way first); ``largest``: per tool the largest force, where, its limit."""

    design: FrontShovelDesign
    machine: ShovelMachine
    table: pd.DataFrame
    largest: dict[str, dict[str, Any]]

    def to_frame(self) -> pd.DataFrame:
        """One row per position of the working range (SI; a limit that never binds is inf)."""
        return self.table

    def as_dict(self) -> dict:
        """``digging_forces``: per tool (``bucket``, ``arm``) the largest force (N), its position (m), its limit, the
        three limits there (N), the hydraulic cylinder that gives way, the cylinder lengths (m) and how many
        positions each limit governs."""
        from ..report.result import json_ready

        return {"digging_forces": json_ready(self.largest)}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The lip over the working range, coloured by the limit that governs each tool's force, the largest marked;
        one panel per tool (only the bucket's when ``ax`` is given)."""
        from ..report.figures import new_figure, style_axes

        if ax is not None:
            fig, axes = ax.get_figure(), [ax]
        else:
            fig = new_figure(11.0, 5.0)
            axes = list(fig.subplots(1, 2, sharey=True))
        colours = {"hydraulic": "tab:blue", "tipping": "tab:red", "slipping": "tab:green"}
        t = self.table
        for panel, tool in zip(axes, TOOLS):
            for limit in LIMITS:
                rows = t[t[f"{tool}_limit"] == limit]
                if len(rows):
                    panel.scatter(rows["lip_radius_m"], rows["lip_height_m"], s=6, color=colours[limit],
                                  label=f"{limit}-limited")
            best = self.largest[tool]
            panel.plot(*best["position_m"], "*", color="black", ms=14,
                       label=f"largest: {best['force_N'] / 1e3:.0f} kN ({best['limit']})")
            panel.axhline(0.0, color="saddlebrown", lw=1.2)
            style_axes(panel, "lip radius from the slew axis (m)", "lip height (m)",
                       f"{tool}-cylinder digging force [ISO 6015]: governing limit", legend=True, loc="lower left")
        return fig

    def lines(self) -> list[str]:
        """The text report's lines."""
        out = [f"digging forces at the bucket lip [ISO 6015], over {len(self.table)} positions of the working "
               f"range (friction {self.machine.friction:g}):"]
        for tool, best in self.largest.items():
            r, h = best["position_m"]
            cylinder = f" ({best['cylinder']} at relief)" if best["limit"] == "hydraulic" else ""
            counts = ", ".join(f"{k} {v}" for k, v in best["governed"].items())
            limits = ", ".join(f"{k} {_kn(best[f'{k}_N'])}" for k in LIMITS)
            out.append(f"  {tool:<6} largest {best['force_N'] / 1e3:8.1f} kN at radius {r:.3f} m, height {h:.3f} m, "
                       f"limited by {best['limit']}{cylinder} ({limits}); positions governed: {counts}")
        return out

    def __str__(self) -> str:
        return "\n".join(self.lines())


def _kn(force: float) -> str:
    return "none" if math.isinf(force) else f"{force / 1e3:.1f} kN"


def stroke_grid(mech: Any, samples: int) -> dict[str, np.ndarray]:
    """Every combination of ``samples`` lengths along each cylinder's stroke (m), in a serpentine order."""
    order = serpentine(samples, len(mech.actuated))
    return {n: np.linspace(*mech.cylinders[n].stroke, samples)[order[:, i]] for i, n in enumerate(mech.actuated)}


def digging_forces(design: FrontShovelDesign | None = None, machine: ShovelMachine | None = None,
                   samples: int = 9, lengths: Mapping[str, ArrayLike] | None = None) -> DiggingForces:
    """The digging forces [ISO 6015] of the front shovel ``design`` (default [Shovel]'s) on ``machine`` (default the
    illustrative one) over the working range: ``samples`` lengths per cylinder stroke (``samples``³ positions), or
    the positions ``lengths`` (cylinder name → lengths, m). See the module docstring for the limits."""
    from ..dynamics.trajectory import holding_forces
    from ..model.linkage import build_linkage
    from ..model.loads import Load
    from .excavator import shovel_spec, synthesize

    design = design or FrontShovelDesign()
    machine = machine or ShovelMachine()
    shovel = synthesize(design)
    mech = build_linkage(shovel_spec(shovel))
    if lengths is None:
        samples = number("samples", samples, integer=True, minimum=2)
        inputs = stroke_grid(mech, samples)
    else:
        inputs = {n: np.atleast_1d(np.asarray(lengths[n], dtype=float)) for n in mech.actuated}
        for name, values in inputs.items():
            low, high = mech.cylinders[name].stroke
            if not np.all((values >= low - 1e-12) & (values <= high + 1e-12)):
                raise InputError(f"{mech.name}: the lengths of {name} must be within its stroke "
                                 f"{low:.6g} … {high:.6g} m, got {values.min():.6g} … {values.max():.6g}")
    Q, found = assembled(mech, shovel, inputs)
    lip = found[LIP]
    ahead = lip[:, 0] - machine.slew_axis > machine.tipping_lines["front"]
    if not ahead.any():
        raise InputError(f"{mech.name}: the lip reaches no position ahead of the front tipping line "
                         f"({machine.tipping_lines['front']:g} m from the slew axis)")
    Q, lip = Q[ahead], lip[ahead]
    inputs = {n: v[ahead] for n, v in inputs.items()}
    g = gravity(mech)
    unit = 1e4  # N: the load of the difference quotients (exact: the forces are linear in it)
    F0 = holding_forces(mech, Q)
    R = [(holding_forces(mech, Q, [Load(LIP, force)]) - F0) / unit for force in ([unit, 0, 0], [0, unit, 0])]
    push, pull = machine.force_limits(design, list(mech.actuated))
    device_mass, device_x = device_centres(mech, Q)
    base_mass, _ = machine.base("front")
    moments = restoring_moments(machine, "front", device_mass, device_x, g)
    radius, height = lip[:, 0] - machine.slew_axis, lip[:, 1]
    columns: dict[str, Any] = {f"{n}_m": inputs[n] for n in mech.actuated}
    columns.update({"lip_radius_m": radius, "lip_height_m": height})
    for tool, (cylinder, _) in TOOLS.items():
        j = mech.actuated.index(cylinder)
        u = -np.column_stack([R[0][:, j], R[1][:, j]])  # ∂V/∂L_j by virtual work
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        S = -(u[:, :1] * R[0] + u[:, 1:] * R[1])
        hydraulic, which = largest_load(F0, S, push, pull)
        tipping = tipping_force(machine, "front", moments, radius, height, u)[0]
        slipping = slipping_force(machine.friction, base_mass + device_mass, g, u)
        stacked = np.column_stack([hydraulic, tipping, slipping])
        governing = np.argmin(stacked, axis=1)
        columns.update({f"{tool}_force_N": stacked.min(axis=1), f"{tool}_hydraulic_N": hydraulic,
                        f"{tool}_tipping_N": tipping, f"{tool}_slipping_N": slipping,
                        f"{tool}_limit": np.array(LIMITS)[governing],
                        f"{tool}_cylinder": np.array([mech.actuated[k] if k >= 0 else "" for k in which])})
    import pandas as pd

    table = pd.DataFrame(columns)
    largest = {}
    for tool in TOOLS:
        k = int(np.argmax(table[f"{tool}_force_N"].to_numpy()))
        row = table.iloc[k]
        largest[tool] = {
            "force_N": float(row[f"{tool}_force_N"]),
            "position_m": [float(row["lip_radius_m"]), float(row["lip_height_m"])],
            "limit": str(row[f"{tool}_limit"]),
            "cylinder": str(row[f"{tool}_cylinder"]) or None,
            **{f"{k}_N": float(row[f"{tool}_{k}_N"]) for k in LIMITS},
            "cylinder_lengths_m": {n: float(row[f"{n}_m"]) for n in mech.actuated},
            "governed": {k: int((table[f"{tool}_limit"] == k).sum()) for k in LIMITS},
        }
    return DiggingForces(design, machine, table, largest)

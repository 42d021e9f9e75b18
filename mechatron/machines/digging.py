r"""Digging forces of a front-shovel excavator at the bucket lip V over the working range: the rated tool forces of
[ISO 6015] and, apart from them, mechatron's estimate of what the machine can dig (its digging capability).

The bucket-cylinder tool force digs with the bucket cylinder L3 extending (the bucket curls about its pivot Q), the
arm-cylinder tool force with the stick cylinder L2 extending (stick and bucket turn about the arm pivot F), each
cylinder operated alone [ISO 6015, 3.1–3.2]; the other cylinders hold. The lip V then moves along u = ∂V/∂L_j (the
other lengths held), tangential to its arc about the pivot [ISO 6015, 4.8.2–4.8.3], and the digging resistance on
the lip is −D û. The model's V is the end of the bucket QV, taken as the lip: the standard's tool force is at the lip
or cutting edge, not at the tips of the teeth [ISO 6015, 3.1]. At each position of the working range (a grid over the
three strokes; the capability only where the lip is ahead of the front tipping line):

- **rated tool force** [ISO 6015, 5.2.1–5.2.2], the calculation as mechatron applies it: the digging cylinder at its
  maximum relief circuit pressure [ISO 6015, 3.16], F_relief,j = p_relief,j · πD_j²/4 · n_j (n_j side by side),
  through the linkage alone (no weights, no friction, the other cylinders rigid). By virtual work,
  F_rated = F_relief,j / |∂V/∂L_j| = F_relief,j · e_j / r_j, with e_j the cylinder's moment arm about the pivot and
  r_j the lip's distance from it (|∂V/∂L_j| = r_j dθ/dL_j = r_j / e_j). A tool's rated force is the largest over the
  positions, the standard's tool forces being taken at the position that gives the largest [ISO 6015, 4.4] (for the
  arm, the bucket positioned for it [ISO 6015, 4.8.2]);
- **digging capability**, mechatron's estimate and no number of the standard: D = min(D_h, D_t, D_s), the smallest
  naming its ``limit``; the names are those of the limit conditions a measured tool force meets [ISO 6015,
  3.17–3.19], their calculation here is mechatron's own:

  - hydraulic D_h: the cylinder forces are linear in D, F(D) = F₀ + D·S with F₀ under the device's own weight and
    S = −(û_x R_x + û_y R_y), R_x, R_y the forces for a unit force along x, y at V (the closed-loop inverse dynamics
    at rest, :func:`~mechatron.dynamics.trajectory.holding_forces`); by virtual work R = −∂V/∂L, so the digging
    cylinder's S_j = |∂V/∂L_j|: without weights, and with the holding cylinders strong enough, D_h is the rated tool
    force. D_h is the smallest D at which any cylinder reaches its relief force (the digging one at its relief
    pressure, or a holding one giving way first) (:func:`~mechatron.machines.shovel_machine.largest_load`);
  - tipping D_t: the machine tips about its front or rear tipping line
    (:func:`~mechatron.machines.shovel_machine.tipping_force`, the whole machine with the device in that pose);
  - slipping D_s = μ M g / (|û_x| − μ û_y): the horizontal force equals the friction of the ground's normal force,
    μ the ground's friction coefficient ``machine.friction``
    (:class:`~mechatron.machines.shovel_machine.ShovelMachine`, its default and range documented there)
    (:func:`~mechatron.machines.shovel_machine.slipping_force`).

The largest capability over the range and where are reported per tool, apart from the rated tool forces.
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
from .excavator import TOOL_FORCES, FrontShovelDesign
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

#: The digging tools [ISO 6015, 3.1–3.2]: the cylinder that digs by extending and the pivot the lip turns about.
TOOLS = {name: TOOL_FORCES[name] for name in ("bucket", "arm")}
LIMITS = ("hydraulic", "tipping", "slipping")
LIP = "V"


@dataclass
class DiggingForces(Result):
    """The digging forces of :func:`digging_forces`: ``table`` one row per position with the lip ahead of the front
    tipping line (cylinder lengths L1_m…L3_m, the lip's radius from the slew axis and height, m, and per tool its
    rated tool force ``TOOL_rated_N`` [ISO 6015, 5.2.1–5.2.2], its capability ``TOOL_force_N`` and the capability's
    three limits, N, the governing limit and the cylinder that gives way first); ``rated``: per tool the rated tool
    force, the largest over all the positions (ahead of the tipping line or not: it is the linkage's alone), and
    where; ``largest``: per tool the largest capability (mechatron's estimate), where, its limit."""

    design: FrontShovelDesign
    machine: ShovelMachine
    table: pd.DataFrame
    largest: dict[str, dict[str, Any]]
    rated: dict[str, dict[str, Any]]

    def to_frame(self) -> pd.DataFrame:
        """One row per position of the working range (SI; a limit that never binds is inf)."""
        return self.table

    def as_dict(self) -> dict:
        """``rated_tool_forces`` [ISO 6015, 5.2.1–5.2.2]: per tool (``bucket``, ``arm``) the rated force (N), the
        lip's position (m), the digging cylinder, its relief pressure (Pa) and force (N), its moment arm about the
        pivot and the lip's distance from the pivot (m), the cylinder lengths (m) and the number of positions it is
        the largest over; ``digging_capability``
        (mechatron's estimate): per tool the largest force (N), its position (m), its limit, the three limits there
        (N), the hydraulic cylinder that gives way, the cylinder lengths (m) and how many positions each limit
        governs."""
        from ..report.result import json_ready

        return {"rated_tool_forces": json_ready(self.rated), "digging_capability": json_ready(self.largest)}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The lip over the working range, coloured by the limit that governs each tool's capability, its largest
        marked, and the position of the rated tool force [ISO 6015]; one panel per tool (only the bucket's when
        ``ax`` is given)."""
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
            best, rated = self.largest[tool], self.rated[tool]
            panel.plot(*best["position_m"], "*", color="black", ms=14,
                       label=f"largest capability: {best['force_N'] / 1e3:.0f} kN ({best['limit']})")
            panel.plot(*rated["position_m"], "P", color="purple", ms=10,
                       label=f"rated tool force [ISO 6015]: {rated['force_N'] / 1e3:.0f} kN")
            panel.axhline(0.0, color="saddlebrown", lw=1.2)
            style_axes(panel, "lip radius from the slew axis (m)", "lip height (m)",
                       f"{tool} cylinder: digging capability (mechatron's estimate)", legend=True, loc="lower left")
        return fig

    def lines(self) -> list[str]:
        """The text report's lines."""
        n, m = len(self.table), self.rated["bucket"]["positions"]
        out = [f"rated tool forces at the bucket lip [ISO 6015, 5.2.1–5.2.2]: the digging cylinder at its relief "
               f"pressure through the linkage, the other cylinders held, no weights; the largest over {m} positions:"]
        for tool, r in self.rated.items():
            radius, height = r["position_m"]
            out.append(f"  {tool:<6} {r['force_N'] / 1e3:8.1f} kN: {r['cylinder']} at {r['relief_pressure_Pa'] / 1e6:g}"
                       f" MPa pushes {r['cylinder_force_N'] / 1e3:.1f} kN with a moment arm of {r['lever_arm_m']:.3f} m"
                       f" about {r['pivot']}, the lip {r['radius_m']:.3f} m from {r['pivot']}; lip at radius "
                       f"{radius:.3f} m, height {height:.3f} m")
        out.append(f"digging capability at the bucket lip (mechatron's estimate, not [ISO 6015]: hydraulics with the "
                   f"weights, tipping, slipping on ground friction {self.machine.friction:g}), over {n} positions:")
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
    """The rated tool forces [ISO 6015, 5.2.1–5.2.2] and the digging capability (mechatron's estimate) of the front
    shovel ``design`` (default [Shovel]'s) on ``machine`` (default the illustrative one) over the working range:
    ``samples`` lengths per cylinder stroke (``samples``³ positions), or the positions ``lengths`` (cylinder name →
    lengths, m). See the module docstring for the calculations."""
    from ..dynamics.trajectory import holding_forces
    from ..model.linkage import build_linkage
    from ..model.loads import Load
    from .excavator import shovel_spec, synthesize

    design = design or FrontShovelDesign()
    machine = machine or ShovelMachine()
    shovel = synthesize(design)
    mech = build_linkage(shovel_spec(shovel))
    if lengths is None:
        from ..kinematics.sweeps import BATCHED_POSITION_SECONDS, positions_budget

        samples = number("samples", samples, integer=True, minimum=2)
        positions_budget(mech, float(samples) ** len(mech.actuated), "samples", value=samples,
                         seconds_per_position=BATCHED_POSITION_SECONDS)
        inputs = stroke_grid(mech, samples)
    else:
        inputs = {n: np.atleast_1d(np.asarray(lengths[n], dtype=float)) for n in mech.actuated}
        for name, values in inputs.items():
            low, high = mech.cylinders[name].stroke
            if not np.all((values >= low - 1e-12) & (values <= high + 1e-12)):
                raise InputError(f"{mech.name}: the lengths of {name} must be within its stroke "
                                 f"{low:.6g} … {high:.6g} m, got {values.min():.6g} … {values.max():.6g}")
    Q, found = assembled(mech, shovel, inputs)
    unit = 1e4  # N: the load of the difference quotients (exact: the forces are linear in it)
    F0 = holding_forces(mech, Q)
    R = [(holding_forces(mech, Q, [Load(LIP, force)]) - F0) / unit for force in ([unit, 0, 0], [0, unit, 0])]
    push, pull = machine.force_limits(design, list(mech.actuated))
    rated = {tool: _rated(mech, machine, Q, found[LIP], inputs, R, push, tool) for tool in TOOLS}
    lip = found[LIP]
    ahead = lip[:, 0] - machine.slew_axis > machine.tipping_lines["front"]
    if not ahead.any():
        given = "front_tipping_line" if machine.front_tipping_line is not None else "track_length"
        raise InputError(f"{mech.name}: the lip reaches no position ahead of the front tipping line "
                         f"({machine.tipping_lines['front']:g} m from the slew axis; the lip reaches "
                         f"{float(np.nanmax(lip[:, 0])) - machine.slew_axis:.4g} m)", field=f"machine.{given}")
    Q, lip, F0, R = Q[ahead], lip[ahead], F0[ahead], [r[ahead] for r in R]
    inputs = {n: v[ahead] for n, v in inputs.items()}
    g = gravity(mech)
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
        columns.update({f"{tool}_rated_N": rated_forces(push, R, j),
                        f"{tool}_force_N": stacked.min(axis=1), f"{tool}_hydraulic_N": hydraulic,
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
    return DiggingForces(design, machine, table, largest, rated)


def rated_forces(push: ArrayLike, R: list[ArrayLike], j: int) -> np.ndarray:
    """The rated tool force (N) of cylinder ``j`` at each position [ISO 6015, 5.2.1–5.2.2]: its relief force
    ``push[j]`` (N) over |∂V/∂L_j| (m/m), ∂V/∂L_j = −(R_x, R_y)_j the cylinder forces for unit forces along x and y
    at the lip (virtual work; rows of ``R``: positions)."""
    return float(np.asarray(push)[j]) / np.hypot(np.asarray(R[0])[:, j], np.asarray(R[1])[:, j])


def _rated(mech: Any, machine: ShovelMachine, Q: np.ndarray, lip: np.ndarray, inputs: Mapping[str, np.ndarray],
           R: list[np.ndarray], push: np.ndarray, tool: str) -> dict[str, Any]:
    """The largest rated tool force of ``tool`` over all the positions Q, and where (see :class:`DiggingForces`)."""
    from ..kinematics.geometry import point_positions

    cylinder, pivot = TOOLS[tool]
    j = mech.actuated.index(cylinder)
    forces = rated_forces(push, R, j)
    k = int(np.argmax(forces))
    centre, tip = point_positions(mech, Q[k], pivot, LIP)
    distance = float(np.linalg.norm(tip - centre))
    force, cylinder_force = float(forces[k]), float(push[j])
    return {"force_N": force, "position_m": [float(lip[k, 0] - machine.slew_axis), float(lip[k, 1])],
            "cylinder": cylinder, "pivot": pivot, "relief_pressure_Pa": float(machine.relief(cylinder)),
            "cylinder_force_N": cylinder_force, "lever_arm_m": force * distance / cylinder_force,
            "radius_m": distance, "cylinder_lengths_m": {n: float(v[k]) for n, v in inputs.items()},
            "positions": len(forces)}

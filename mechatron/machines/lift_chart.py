r"""Rated lift capacity of a front-shovel excavator [ISO 10567] over a grid of radius × height, over the front and
over the side.

The lift point is the arm's nose pin Q (the stick–bucket pin), the bucket removed (its mass left out; its cylinder
then carries nothing). For each cell (radius R from the slew axis, height H above the ground) the boom and stick
angles that put Q there come from the triangle C–F–Q (boom CF = l1, stick FQ = l2, the interior angle θ2 at F below
π [Shovel]): d = |Q − C|, θ2 = acos((l1² + l2² − d²)/(2 l1 l2)), θ1 = atan2(Q − C) + acos((l1² + d² − l2²)/(2 l1 d));
a cell whose angles fall outside the designed ranges (the cylinders' strokes) is not reachable and is left out. Then,
with a load W (kg) hanging at Q:

- tipping load W_t = M_R / (g (R − a)) with the restoring moment M_R = g Σ m_i (a − r_i) of the whole machine
  (upper structure, undercarriage, the working device in that pose) about the tipping line at a
  (:func:`~mechatron.machines.shovel_machine.restoring_moments`); none (``inf``, null in JSON) where R ≤ a;
- hydraulic capacity W_h: the cylinder forces F(W) = F(0) + W·dF/dW from the closed-loop inverse dynamics at rest
  (:func:`~mechatron.dynamics.trajectory.holding_forces`, F(0) under gravity, dF/dW for 1 kg at Q); W_h is the
  smallest W at which a cylinder reaches its relief force, pushing or pulling as its sign says
  (:func:`~mechatron.machines.shovel_machine.largest_load`);
- rated load = min(0.75 W_t, 0.87 W_h), its limit ``tipping`` or ``hydraulic`` [ISO 10567].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..report.result import Result
from .excavator import FrontShovel, FrontShovelDesign, synthesize
from .shovel_machine import (
    OVER,
    ShovelMachine,
    device_centres,
    gravity,
    largest_load,
    restoring_moments,
    tipping_force,
)
from .shovel_poses import assembled

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism

Array = NDArray[np.float64]

#: The lift point: the arm's nose pin (stick–bucket pin) [ISO 10567].
LIFT_POINT = "Q"
#: ISO 10567's factors: rated = min(TIPPING_FACTOR · tipping load, HYDRAULIC_FACTOR · hydraulic capacity).
TIPPING_FACTOR, HYDRAULIC_FACTOR = 0.75, 0.87
#: The step (m) of the default grid, and its first radius.
GRID_STEP, FIRST_RADIUS = 1.0, 3.0
ROW_KEYS = ("radius_m", "height_m", "over", "rated_kg", "tipping_kg", "hydraulic_kg", "limit")


def lift_mechanism(design: FrontShovelDesign) -> tuple[FrontShovel, Mechanism]:
    """The synthesized working device with the bucket removed (bucket mass 0) and its mechanism."""
    from ..model.linkage import build_linkage
    from .excavator import shovel_spec

    shovel = synthesize(replace(design, bucket_mass=0.0))
    return shovel, build_linkage(shovel_spec(shovel))


def lift_angles(shovel: FrontShovel, x: ArrayLike, y: ArrayLike) -> tuple[Array, Array, Array]:
    """(θ1, θ2, reached): the angles (rad) that put the nose pin Q at (x, y) (m, design coordinates; arrays of one
    shape) and where Q gets there within the designed joint ranges (see the module docstring; the angles are
    meaningless where it does not)."""
    d = shovel.design
    l1, l2 = d.boom, d.stick
    cx, cy = d.boom_foot
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    dist = np.hypot(x - cx, y - cy)
    reached = (abs(l1 - l2) < dist) & (dist < l1 + l2)
    with np.errstate(divide="ignore", invalid="ignore"):
        t2 = np.arccos(np.clip((l1 * l1 + l2 * l2 - dist * dist) / (2 * l1 * l2), -1.0, 1.0))
        t1 = np.arctan2(y - cy, x - cx) + np.arccos(np.clip((l1 * l1 + dist * dist - l2 * l2) / (2 * l1 * dist),
                                                            -1.0, 1.0))
    tol = 1e-12
    for t, (lo, hi) in ((t1, shovel.theta1), (t2, shovel.theta2)):
        reached &= (lo - tol <= t) & (t <= hi + tol)
    return t1, t2, reached


def reach_boundary(shovel: FrontShovel, samples: int = 60) -> NDArray[np.float64]:
    """The nose pin's reach (m): Q around the boundary of the (θ1, θ2) ranges, a closed polyline (n, 2)."""
    d = shovel.design
    (a0, a1), (b0, b1) = shovel.theta1, shovel.theta2
    s = np.linspace(0.0, 1.0, samples)
    t1 = np.concatenate([a0 + (a1 - a0) * s, np.full(samples, a1), a1 - (a1 - a0) * s, np.full(samples, a0)])
    t2 = np.concatenate([np.full(samples, b0), b0 + (b1 - b0) * s, np.full(samples, b1), b1 - (b1 - b0) * s])
    c = np.asarray(d.boom_foot, dtype=float)
    q = c + d.boom * np.column_stack([np.cos(t1), np.sin(t1)]) \
        + d.stick * np.column_stack([np.cos(t1 + t2 - np.pi), np.sin(t1 + t2 - np.pi)])
    return q


def default_grid(shovel: FrontShovel, machine: ShovelMachine) -> tuple[list[float], list[float]]:
    """Radii from 3 m and heights every 1 m (m) over the nose pin's reach, or the machine's ``lift_radii`` and
    ``lift_heights``."""
    reach = reach_boundary(shovel)
    r = reach[:, 0] - machine.slew_axis
    step = GRID_STEP
    radii = machine.lift_radii or [FIRST_RADIUS + step * k for k in range(int((r.max() - FIRST_RADIUS) // step) + 1)]
    low, high = math.ceil(reach[:, 1].min() / step), math.floor(reach[:, 1].max() / step)
    heights = machine.lift_heights or [step * k for k in range(low, high + 1)]
    return list(radii), list(heights)


@dataclass
class LiftChart(Result):
    """The rated lift capacity [ISO 10567] of :func:`lift_chart`.

    ``rows``: per reachable cell and ``over`` (``front``, ``side``) the radius from the slew axis and the height of
    the lift point (m), the rated load, the tipping load and the hydraulic capacity (kg; the tipping load ``inf``
    where the load's line is inside the tipping line) and the governing ``limit``; ``cylinders``: per row the
    cylinder that reaches its relief force first; ``radii``, ``heights``: the grid (m); ``reach``: the lift point's
    reach (m, design coordinates).
    """

    design: FrontShovelDesign
    machine: ShovelMachine
    rows: list[dict[str, Any]]
    cylinders: list[str]
    radii: list[float]
    heights: list[float]
    reach: NDArray[np.float64]

    def to_frame(self) -> pd.DataFrame:
        """One row per cell and side: radius_m, height_m, over, rated_kg, tipping_kg (empty where no load tips the
        machine), hydraulic_kg, limit."""
        import pandas as pd

        return pd.DataFrame(self.rows, columns=list(ROW_KEYS)).replace([math.inf], math.nan)

    def as_dict(self) -> dict:
        """``lift_chart``: the rows (the tipping load null where no load tips the machine)."""
        return {"lift_chart": [{k: (v if not (isinstance(v, float) and math.isinf(v)) else None)
                                for k, v in row.items()} for row in self.rows]}

    def cell(self, radius: float, height: float, over: str) -> dict[str, Any] | None:
        """The row of a cell (m), or ``None`` where the lift point does not reach it."""
        for row in self.rows:
            if row["over"] == over and math.isclose(row["radius_m"], radius, abs_tol=1e-9) \
                    and math.isclose(row["height_m"], height, abs_tol=1e-9):
                return row
        return None

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chart as makers print it: radius across, lift-point height down the side, at each cell the rated
        load over the front and over the side (kg), the hydraulic-limited ones marked * (blue); the lift point's
        reach, the tipping lines and the ground."""
        from ..report.figures import figure_axes, style_axes

        fig, ax = figure_axes(ax, 10.0, 7.0)
        slew = self.machine.slew_axis
        ax.plot(self.reach[:, 0] - slew, self.reach[:, 1], color="0.6", lw=1, label="lift-point reach")
        lines = self.machine.tipping_lines
        ax.axvline(lines["front"], color="tab:red", lw=0.8, ls="--", label="tipping line, over the front")
        ax.axvline(lines["side"], color="tab:orange", lw=0.8, ls=":", label="tipping line, over the side")
        ax.axhline(0.0, color="saddlebrown", lw=1.2, label="ground")
        limited = {"tipping": [], "hydraulic": []}
        for radius in self.radii:
            for height in self.heights:
                front, side = self.cell(radius, height, "front"), self.cell(radius, height, "side")
                if front is None:
                    continue
                hydraulic = front["limit"] == "hydraulic" or side["limit"] == "hydraulic"
                limited["hydraulic" if hydraulic else "tipping"].append((radius, height))
                for row, offset in ((front, 5), (side, -5)):
                    ax.annotate(_value(row), (radius, height), xytext=(0, offset), textcoords="offset points",
                                ha="center", va="center", fontsize=7, family="monospace",
                                color="tab:blue" if row["limit"] == "hydraulic" else "black")
        for limit, colour in (("tipping", "0.88"), ("hydraulic", "lightsteelblue")):
            cells = np.array(limited[limit]).reshape(-1, 2)
            if len(cells):
                ax.scatter(cells[:, 0], cells[:, 1], s=900, marker="s", color=colour, zorder=0,
                           label="cell limited by tipping" if limit == "tipping" else
                           "cell with a hydraulic-limited value (*, blue)")
        ax.set_xticks(self.radii)
        ax.set_yticks(self.heights)
        style_axes(ax, "radius from the slew axis (m)", "lift-point height (m)",
                   "rated lift capacity [ISO 10567] (kg), nose pin, bucket removed: over the front (top), over the "
                   "side (below)", legend=True, loc="upper left", markerscale=0.3)
        return fig

    def table(self) -> list[str]:
        """The chart as text: heights down the side, radii across, ``front/side`` (kg), * hydraulic-limited."""
        lines = [f"{'height':>8} |" + "".join(f"{r:>8.1f} m     " for r in self.radii)]
        for height in sorted(self.heights, reverse=True):
            cells = []
            for radius in self.radii:
                front, side = self.cell(radius, height, "front"), self.cell(radius, height, "side")
                cells.append(f"{_value(front) + '/' + _value(side):>15}" if front else f"{'–':>15}")
            if any(c.strip() != "–" for c in cells):
                lines.append(f"{height:>6.1f} m |" + "".join(cells))
        return lines

    def __str__(self) -> str:
        m, lines = self.machine, self.machine.tipping_lines
        return "\n".join([
            f"rated lift capacity [ISO 10567] at the arm's nose pin {LIFT_POINT}, bucket removed: "
            f"min({TIPPING_FACTOR}·tipping, {HYDRAULIC_FACTOR}·hydraulic), kg over the front/over the side, "
            "* hydraulic-limited",
            f"machine: upper structure {m.upper_mass:g} kg at {tuple(m.upper_centre)} m, undercarriage "
            f"{m.undercarriage_mass:g} kg; tipping lines {lines['front']:g} m (front), {lines['rear']:g} m (rear), "
            f"{lines['side']:g} m (side) from the slew axis",
            *self.table()])


#: Memory (bytes) of one cell of the grid while the reached cells are found, and of one reached cell's analysis
#: (its closed-loop position on the path through the cells, its forces and its rows), measured with tracemalloc with
#: a margin; a reached cell's analysis takes at least CELL_SECONDS (s).
GRID_BYTES, CELL_BYTES, CELL_SECONDS = 200.0, 2000.0, 2e-5
GRID_ADVICE = "give fewer lift_radii or lift_heights in the [machine] table"


def grid_cells(mech: Mechanism, radii: list[float], heights: list[float]) -> tuple[Array, Array]:
    """(R, H): the radius and the height (m) of every cell of the grid ``radii`` × ``heights`` in a serpentine order
    (the heights up at one radius, down at the next: short steps between cells), refused (:mod:`mechatron.io.budget`)
    where the grid alone would not fit in memory."""
    from ..io.budget import count, require

    n = float(len(radii)) * len(heights)
    require(f"the lift chart's grid of {count(len(radii))} radii × {count(len(heights))} heights ({count(n)} cells) "
            f"of {mech.name}", n, GRID_BYTES, advice=GRID_ADVICE)
    R, H = np.meshgrid(np.asarray(radii, dtype=float), np.asarray(heights, dtype=float), indexing="ij")
    H[1::2] = H[1::2, ::-1]
    return R.ravel(), H.ravel()


def cells_budget(mech: Mechanism, reached: int) -> None:
    """Refuse (:mod:`mechatron.io.budget`) the analysis of ``reached`` cells past the memory or time limit."""
    from ..io.budget import count, require, seconds
    from ..kinematics.sweeps import position_bytes

    what = f"the lift chart's {count(reached)} cells the lift point of {mech.name} reaches"
    require(what, reached, CELL_BYTES, fixed=position_bytes(mech)[0], advice=GRID_ADVICE)
    seconds(what, reached, CELL_SECONDS, advice=GRID_ADVICE)


def _value(row: dict[str, Any]) -> str:
    return f"{row['rated_kg']:.0f}" + ("*" if row["limit"] == "hydraulic" else "")


def lift_chart(design: FrontShovelDesign | None = None, machine: ShovelMachine | None = None,
               radii: list[float] | None = None, heights: list[float] | None = None) -> LiftChart:
    """The rated lift capacity [ISO 10567] of the front shovel ``design`` on ``machine`` (defaults: the design of
    [Shovel], the illustrative machine) at the cells ``radii`` × ``heights`` (m: radius from the slew axis, height
    above the ground; default :func:`default_grid`), over the front and over the side (module docstring)."""
    from ..dynamics.trajectory import holding_forces
    from ..model.loads import Load

    design = design or FrontShovelDesign()
    machine = machine or ShovelMachine()
    shovel, mech = lift_mechanism(design)
    grid = default_grid(shovel, machine)
    radii = sorted(radii if radii is not None else grid[0])
    heights = sorted(heights if heights is not None else grid[1])
    R, H = grid_cells(mech, radii, heights)
    t1, t2, reached = lift_angles(shovel, machine.slew_axis + R, H)
    cells_budget(mech, int(reached.sum()))
    cells = list(zip(R[reached].tolist(), H[reached].tolist()))
    bucket_mid = sum(shovel.theta3) / 2
    lengths = {c.name: [c.length(a) for a in angles] for c, angles in
               zip(shovel.cylinders, (t1[reached].tolist(), t2[reached].tolist(), [bucket_mid] * len(cells)))}
    rows: list[dict[str, Any]] = []
    names: list[str] = []
    if cells:
        Q = assembled(mech, shovel, lengths)[0]
        g = gravity(mech)
        unit = 1000.0  # kg: the load of the difference quotient (exact: the forces are linear in it)
        F0 = holding_forces(mech, Q)
        S = (holding_forces(mech, Q, [Load(LIFT_POINT, [0.0, -g * unit, 0.0])]) - F0) / unit  # N per kg
        push, pull = machine.force_limits(design, list(mech.actuated))
        hydraulic, which = largest_load(F0, S, push, pull)
        device_mass, device_x = device_centres(mech, Q)
        radius = np.array([c[0] for c in cells])
        height = np.array([c[1] for c in cells])
        up = np.tile([0.0, 1.0], (len(cells), 1))
        for over in OVER:
            moments = restoring_moments(machine, over, device_mass, device_x, g)
            tipping = tipping_force(machine, over, moments, radius, height, up)[0] / g
            for k, (r, h) in enumerate(cells):
                rated_t, rated_h = TIPPING_FACTOR * tipping[k], HYDRAULIC_FACTOR * hydraulic[k]
                rows.append({"radius_m": float(r), "height_m": float(h), "over": over,
                             "rated_kg": float(min(rated_t, rated_h)), "tipping_kg": float(tipping[k]),
                             "hydraulic_kg": float(hydraulic[k]),
                             "limit": "tipping" if rated_t <= rated_h else "hydraulic"})
                names.append(mech.actuated[which[k]] if which[k] >= 0 else "")
    return LiftChart(design, machine, rows, names, radii, heights, reach_boundary(shovel))

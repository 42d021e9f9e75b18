"""The workspace of a two-input linkage: where a point goes over the grid of both inputs' ranges.

Two actuated inputs u₁, u₂ (m or rad) each take ``n₁`` and ``n₂`` equal steps over their range — from the lower to
the upper limit, or a whole turn (2π rad) from the drawn angle for an unlimited revolute input, as in
:func:`~mechatron.kinematics.sweeps.default_inputs` —, the other inputs held at their drawn values. The n₁ × n₂
positions are assembled in one sweep (:func:`~mechatron.kinematics.sweeps.sweep`: batched or compiled, on one
assembly branch by continuation) along a serpentine path through the grid: row i (u₁ = u₁,ᵢ) runs along u₂ forward
when i is even and backward when it is odd, so that each sample continues from its neighbour in the grid. The path
starts from the drawn position in :data:`RAMP` equal steps of every input to the grid's first cell. A cell that
does not assemble (a loop that cannot close, a singular position) is marked.

The cells kept are those of the drawn assembly branch. Two branches meet where J_d, the closure Jacobian's columns
of the passive coordinates, is singular (a fold: the five-bar's two couplers in line), so det J_d has one sign on
the drawn branch's side of it; near a fold a continuation step may land on the other branch. So, in path order, a
cell reached across cells that do not assemble, or whose det J_d has not the drawn position's sign, is solved again
with the assembled cells after it: from its neighbour of the row before (same column) if that is on the branch, else
from the last cell on the branch before it, else from the drawn position, each in :data:`RAMP` steps. A cell still
on the other side is marked as not assembled (on the drawn branch). Where J_d is not square (redundant closure
equations) there is no sign to compare and only the first rule applies.

The point's position r = (x, y) (m) is that of the mechanism's frame; its reach is |r|, the distance from the
drawing's origin (the world frame).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.values import number
from ..model.mechanism import Mechanism
from ..report.result import Result, json_ready

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .sweeps import ProgressCallback

#: Steps from the drawn position to the grid's first cell (continuation along every input).
RAMP = 8
#: Cells per input by default.
GRID = 41


@dataclass
class WorkspaceResult(Result):
    """Results of :func:`workspace`: a point's position over the n₁ × n₂ grid of two inputs.

    Attributes:
        mechanism: The mechanism analysed.
        point: The point (frame name) whose positions these are.
        inputs: The names of the two inputs swept (u₁ along the rows, u₂ along the columns).
        values: Their grid values, (n₁,) and (n₂,) arrays (m or rad).
        held: The other inputs and the values they are held at (m or rad).
        positions: The point's world position at every cell, (n₁, n₂, 2) — (n₁, n₂, 3) in a spatial loop — in m,
            NaN where the cell does not assemble.
        assembled: (n₁, n₂) booleans: which cells assemble.
        reasons: Why each cell that does not assemble does not, by (i, j).
    """

    mechanism: Mechanism
    point: str
    inputs: tuple[str, str]
    values: tuple[NDArray[np.float64], NDArray[np.float64]]
    held: dict[str, float]
    positions: NDArray[np.float64]
    assembled: NDArray[np.bool_]
    reasons: dict[tuple[int, int], str] = field(default_factory=dict)

    # --------------------------------------------------------------------------------------------- the data
    def _unit(self, name: str) -> str:
        angular = dict(zip(self.mechanism.joint_names, self.mechanism.angular_coordinates()))
        return "rad" if angular.get(name, False) else "m"

    @property
    def _axes(self) -> str:
        return "xyz"[:self.positions.shape[2]]

    def extent(self) -> dict[str, Any]:
        """The extent of the assembled cells: ``x, y`` (and ``z``) as [min, max] (m), ``reach`` [min |r|, max |r|]
        (m, from the drawing's origin), ``assembled`` (cells), ``cells`` and ``share`` (assembled / cells); the
        ranges are None when no cell assembles."""
        p = self.positions[self.assembled]
        out: dict[str, Any] = {}
        for k, axis in enumerate(self._axes):
            out[axis] = [float(p[:, k].min()), float(p[:, k].max())] if len(p) else None
        r = np.sqrt((p**2).sum(axis=1))
        out["reach"] = [float(r.min()), float(r.max())] if len(p) else None
        cells = int(self.assembled.size)
        out.update(assembled=int(self.assembled.sum()), cells=cells, share=float(self.assembled.sum()) / cells)
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per cell, row by row: ``i, j`` (the grid indices), the two inputs (m or rad, named as the
        inputs), ``x_m, y_m`` (``z_m`` in a spatial loop; NaN where the cell does not assemble) and
        ``assembled``."""
        import pandas as pd

        n1, n2 = self.assembled.shape
        i, j = np.meshgrid(np.arange(n1), np.arange(n2), indexing="ij")
        u1, u2 = np.meshgrid(*self.values, indexing="ij")
        columns: dict[str, Any] = {"i": i.ravel(), "j": j.ravel(), self.inputs[0]: u1.ravel(),
                                   self.inputs[1]: u2.ravel()}
        for k, axis in enumerate(self._axes):
            columns[f"{axis}_m"] = self.positions[..., k].ravel()
        columns["assembled"] = self.assembled.ravel()
        return pd.DataFrame(columns)

    def as_dict(self) -> dict[str, Any]:
        """The workspace as plain data: ``mechanism, point``, ``inputs`` (each ``name, unit, values``), ``held``
        ({name: value}, m or rad), ``grid`` [n₁, n₂], :meth:`extent` as ``extent``, the cells' positions
        ``x_m, y_m`` (``z_m``) as n₁ lists of n₂ values with null where a cell does not assemble, ``assembled`` (n₁
        lists of n₂ booleans) and ``not_assembled`` (each such cell's ``i, j``, inputs and ``reason``)."""
        names = self.inputs
        out: dict[str, Any] = {
            "mechanism": self.mechanism.name, "point": self.point,
            "inputs": [{"name": n, "unit": self._unit(n), "values": v} for n, v in zip(names, self.values)],
            "held": dict(self.held), "grid": list(self.assembled.shape), "extent": self.extent()}
        for k, axis in enumerate(self._axes):
            out[f"{axis}_m"] = self.positions[..., k]  # NaN → null (json_ready)
        out["assembled"] = self.assembled
        out["not_assembled"] = [{"i": i, "j": j, names[0]: self.values[0][i], names[1]: self.values[1][j],
                                 "reason": reason} for (i, j), reason in sorted(self.reasons.items())]
        return json_ready(out)

    def __str__(self) -> str:
        e = self.extent()
        n1, n2 = self.assembled.shape
        lines = [f"{self.mechanism.name}: workspace of point {self.point} over {self.inputs[0]} × {self.inputs[1]} "
                 f"({n1} × {n2} grid)"]
        for name, v in zip(self.inputs, self.values):
            lines.append(f"  {name}: {v[0]:.6g} … {v[-1]:.6g} {self._unit(name)} ({len(v)} values)")
        for name, value in self.held.items():
            lines.append(f"  {name}: held at {value:.6g} {self._unit(name)}")
        lines.append(f"assembled: {e['assembled']} of {e['cells']} positions ({100 * e['share']:.1f} %)")
        if e["reach"] is not None:
            for axis in self._axes:
                lines.append(f"  {axis}: {e[axis][0]:.6g} … {e[axis][1]:.6g} m")
            lines.append(f"  reach |r| from the drawing's origin: {e['reach'][0]:.6g} … {e['reach'][1]:.6g} m")
        if self.reasons:
            (i, j), reason = min(self.reasons.items())
            lines.append(f"not assembled: {len(self.reasons)} positions; first (cell {i}, {j}): {reason}")
        return "\n".join(lines)

    # -------------------------------------------------------------------------------------------- the chart
    def plot(self, ax: Axes | None = None) -> Figure:
        """The reachable region: the point at every assembled cell (dots) and the images of the grid's four edges
        (an input at a limit: the region's boundary, broken where cells do not assemble), with the mechanism drawn at
        its drawn position, x and y in m, equal scales; beside it the grid of the inputs with the cells that do not
        assemble marked (×). Given ``ax``, draws the region only, the count of cells not assembled in its legend."""
        from ..report.figures import figure_axes, new_figure, style_axes
        from .drawing import draw_mechanism

        if ax is None:
            figure = new_figure(12.0, 5.5)
            region, grid = figure.subplots(1, 2, width_ratios=[1.3, 1])
        else:
            figure, region, grid = figure_axes(ax)[0], ax, None
        x, y = self.positions[..., 0], self.positions[..., 1]
        ok = self.assembled
        region.scatter(x[ok], y[ok], s=4, color="tab:blue", alpha=0.5, label=f"{self.point} at an assembled cell")
        edges = [(x[0], y[0]), (x[-1], y[-1]), (x[:, 0], y[:, 0]), (x[:, -1], y[:, -1])]
        for k, (ex, ey) in enumerate(edges):
            region.plot(ex, ey, color="tab:blue", lw=1.2, label="an input at a limit" if k == 0 else None)
        if self.mechanism.closures:
            assert self.mechanism.reference_q is not None  # a workspace's linkage is assembled from its drawing
            draw_mechanism(self.mechanism, self.mechanism.reference_q, region, labels=False, alpha=0.6)
        missing = int((~ok).sum())
        if missing:
            region.plot([], [], "x", color="tab:red", label=f"{missing} cells not assembled")
        region.set_aspect("equal", adjustable="datalim")
        style_axes(region, "x (m)", "y (m)", f"{self.mechanism.name}: workspace of {self.point}", legend=True,
                   loc="best")
        if grid is not None:
            u1, u2 = np.meshgrid(*self.values, indexing="ij")
            (a, ua), (b, ub) = ((n, self._unit(n)) for n in self.inputs)
            scale = [math.degrees(1.0) if u == "rad" else 1.0 for u in (ua, ub)]
            shown = ["deg" if u == "rad" else u for u in (ua, ub)]
            grid.scatter(u1[ok] * scale[0], u2[ok] * scale[1], s=4, color="tab:blue", label="assembled")
            grid.scatter(u1[~ok] * scale[0], u2[~ok] * scale[1], s=12, marker="x", color="tab:red",
                         label="not assembled")
            style_axes(grid, f"{a} ({shown[0]})", f"{b} ({shown[1]})", "the grid of the inputs", legend=True,
                       loc="best")
        return figure


def workspace(mech: Mechanism, point: str | None = None, *, grid: int | Sequence[int] = GRID,
              inputs: Sequence[str] | None = None, progress: ProgressCallback | None = None) -> WorkspaceResult:
    """The positions of ``point`` (default the tool point) over the grid of two inputs (module docstring).

    Args:
        point: A point (frame) of the mechanism.
        grid: Cells per input, n (n × n) or (n₁, n₂), each a whole number ≥ 2.
        inputs: The two inputs to sweep (default: the mechanism's, if it has two); the others are held at their
            drawn values.
        progress: Called as progress(done, total) during the sweep.

    Raises:
        InputError: a mechanism without closed loops or with fewer than two inputs, an unknown point or input,
            a bad grid, or a grid past the memory or time limit (:mod:`mechatron.io.budget`).
    """
    from ..io import budget
    from .sweeps import BATCHED_POSITION_SECONDS, default_inputs, position_bytes

    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops; a workspace is of a closed-loop linkage")
    names = _inputs(mech, inputs)
    point = point or mech.tool_frame
    if point not in mech.frame_names:
        raise InputError(f"no point {point!r} in {mech.name} (points: {', '.join(mech.points)})", field="point")
    sizes = [grid] * 2 if np.ndim(grid) == 0 else list(cast("Sequence[int]", grid))
    if len(sizes) != 2:
        raise InputError(f"{budget.option('grid')} must be one whole number or two, got {grid!r}")
    n1, n2 = (number(budget.option("grid"), n, integer=True, minimum=2) for n in sizes)
    cells = float(n1) * float(n2)
    what = f"{budget.option('grid')} {n1} × {n2} gives {budget.count(cells)} positions of {mech.name}"
    fixed, row = position_bytes(mech)
    budget.require(what, cells, row, fixed=fixed, advice=f"use a smaller {budget.option('grid')}")
    budget.seconds(what, cells, BATCHED_POSITION_SECONDS, advice=f"use a smaller {budget.option('grid')}")

    values = (default_inputs(mech, n1)[names[0]], default_inputs(mech, n2)[names[1]])
    u1, u2 = np.meshgrid(*values, indexing="ij")
    u2[1::2] = u2[1::2, ::-1]  # the serpentine: every other row backwards
    path = _Path(mech, point, names, np.stack([u1.ravel(), u2.ravel()], axis=1), n2)
    path.solve(progress)
    order = path.index(*np.meshgrid(np.arange(n1), np.arange(n2), indexing="ij"))  # (n1, n2) path indices
    reasons = {(int(i), int(j)): path.reasons[int(order[i, j])] for i, j in np.argwhere(~path.ok[order])}
    held = {n: float(path.drawn[path.solver.index[n]]) for n in mech.actuated if n not in names}
    return WorkspaceResult(mech, point, names, values, held, path.X[order], path.ok[order], reasons)


class _Path:
    """The serpentine path through the grid (module docstring) and its solution: ``U`` (n, 2) the two inputs of
    each path index, ``ok``, ``X`` (n, 2 or 3: the point, m), ``Q`` (n, nq) and ``reasons`` by path index."""

    def __init__(self, mech: Mechanism, point: str, names: tuple[str, str], U: np.ndarray, n2: int) -> None:
        from .loops import loop_solver

        self.mech, self.point, self.names, self.U, self.n2 = mech, point, names, U, n2
        self.solver = loop_solver(mech)
        self.drawn = np.asarray(mech.reference_q, dtype=float)
        n = len(U)
        self.ok = np.zeros(n, dtype=bool)
        self.X = np.full((n, 3 if any(not getattr(c, "planar", True) for c in mech.closures) else 2), np.nan)
        self.Q = np.full((n, len(self.drawn)), np.nan)
        self.sign = np.zeros(n)
        self.reasons: dict[int, str] = {}

    def index(self, i: Any, j: Any) -> Any:
        """The path index of cell (i, j)."""
        return i * self.n2 + np.where(i % 2 == 0, j, self.n2 - 1 - j)

    def solve(self, progress: ProgressCallback | None) -> None:
        """The whole path by one sweep from the drawn position; then, in path order, each cell reached across cells
        that do not assemble, or on another branch than the drawn one (:meth:`_branch`), and the assembled cells
        after it are solved again from an assembled neighbour (:meth:`_anchors`). A cell still on another branch
        is marked as not assembled."""
        self.drawn_sign = self._branch(self.drawn[None])[0]
        self._sweep(0, len(self.U), self.drawn, progress)
        anchored = {0}
        k = 0
        while k < len(self.U):
            restart = k not in anchored and not self.ok[k - 1]
            if self.ok[k] and (restart or not self.good[k]):
                end = k + int(np.argmin(np.append(self.ok[k:], False)))  # the assembled cells [k, end)
                for q in self._anchors(k):
                    if self._sweep(k, end, q) and self.good[k]:
                        break
                anchored.add(k)
                if self.ok[k] and not self.good[k]:
                    self.ok[k], self.X[k], self.Q[k] = False, np.nan, np.nan
                    self.reasons[k] = (f"{self.mech.name}: assembles here only on another assembly branch than the "
                                       "drawn one (det J_d of the other sign)")
            k += 1

    def _branch(self, Q: np.ndarray) -> np.ndarray:
        """The sign of det J_d (the closure Jacobian's columns of the passive coordinates) at each row of Q (n, nq),
        ±1 (0 where singular); all 1 where J_d is not square (redundant closure equations: no sign to compare)."""
        system, dep = self.solver.system, self.solver.dep
        if system.nrows != len(dep) or not len(Q):
            return np.ones(len(Q))
        try:
            _, J = system.stack(system.batched().placements(Q))
        except NotImplementedError:  # joints the batched kinematics does not know: Pinocchio, one by one
            J = np.stack([system.evaluate(q)[1] for q in Q])
        return np.sign(np.linalg.det(J[:, :, dep]))

    @property
    def good(self) -> np.ndarray:
        """Which path indices are assembled on the drawn branch."""
        return self.ok & (self.sign == self.drawn_sign)

    def _anchors(self, start: int) -> list[np.ndarray]:
        """Where to continue to the path index ``start`` from, best first: the cell of the row before in the same
        column, the last assembled cell before it on the path, the drawn position."""
        i, jp = divmod(start, self.n2)
        j = jp if i % 2 == 0 else self.n2 - 1 - jp
        out = []
        if i > 0 and self.ok[(above := int(self.index(i - 1, j)))]:
            out.append(self.Q[above])
        before = np.flatnonzero(self.ok[:start])
        if len(before):
            out.append(self.Q[before[-1]])
        return [*out, self.drawn]

    def _sweep(self, start: int, end: int, q: np.ndarray, progress: ProgressCallback | None = None) -> bool:
        """Path indices [start, end) by one sweep from the configuration q in :data:`RAMP` steps of the inputs to
        the first; the results replace those there. Returns whether every step of the way assembled."""
        from .sweeps import sweep

        columns = self.solver.index
        inputs = {}
        for k, name in enumerate(self.names):
            ramp = np.linspace(q[columns[name]], self.U[start, k], RAMP + 1)[:-1]
            inputs[name] = np.concatenate([ramp, self.U[start:end, k]])
        result = sweep(self.mech, inputs, frames=[self.point], links=[], measures=[], guess=q, progress=progress)
        rows = result.table["sample"].to_numpy()
        if (rows < RAMP).sum() < RAMP:
            return False
        take = rows >= RAMP
        self.ok[start:end] = False
        self.X[start:end] = self.Q[start:end] = np.nan
        self.sign[start:end] = 0.0
        for k in range(start, end):
            self.reasons.pop(k, None)
        cells = rows[take] - RAMP + start
        self.ok[cells] = True
        columns_x = [f"{self.point}_{axis}" for axis in "xyz"[:self.X.shape[1]]]
        self.X[cells] = result.table[columns_x].to_numpy()[take]
        self.Q[cells] = result.q[take]
        self.sign[cells] = self._branch(result.q[take])
        for sample, reason in zip(result.failures["sample"].to_numpy(), result.failures["reason"]):
            if sample >= RAMP:
                self.reasons[int(sample) - RAMP + start] = str(reason)
        return True


def _inputs(mech: Mechanism, inputs: Sequence[str] | None) -> tuple[str, str]:
    """The two inputs to sweep, checked."""
    actuated = list(mech.actuated)
    if inputs is None:
        if len(actuated) != 2:
            raise InputError(f"{mech.name} has {len(actuated)} input{'s' * (len(actuated) != 1)} "
                             f"({', '.join(actuated)}); a workspace sweeps two"
                             + (": name them (inputs)" if len(actuated) > 2 else ""))
        return actuated[0], actuated[1]
    names = list(inputs)
    if len(names) != 2 or names[0] == names[1]:
        raise InputError(f"expected two different inputs, got {', '.join(map(str, names)) or 'none'}",
                         field="inputs")
    for name in names:
        if name not in actuated:
            raise InputError(f"{name!r} is not an input of {mech.name} (inputs: {', '.join(actuated)})",
                             field="inputs")
    return names[0], names[1]

"""Analysis of a mechanism over the strokes of its inputs: N samples into a table (pandas), with the assembly branch
kept by continuation from sample to sample.

The sequential continuation assembles each sample by Newton's method from the polynomial through the last (up to
four) solutions extrapolated one input step further. From :data:`COMPILED_MIN` samples on, where the mechanism has
a symbolic form, that continuation runs compiled (:mod:`mechatron.kinematics.compiled`: a driver in C over the
samples, the analysis of each solution written straight into the table's block; the samples it does not accept go
through the Python continuation). Otherwise, for many samples the same branch is found batched
(:mod:`mechatron.kinematics.batch`): a few anchor samples by that continuation, all others by Newton's method on all
samples at once from guesses interpolated between the anchors, each checked against its neighbour and the doubtful
ones solved again by the continuation. Velocities and accelerations of all samples follow at once, with the frames
from :mod:`mechatron.model.batched` (or from Pinocchio per sample for joints it does not know, and as the reference
with ``BATCHED = False``), chunk by chunk. A sample that cannot be assembled (cylinder out of stroke, a loop that
cannot close, a singular position) goes to ``failures`` with the reason instead of into the table; the sweep goes on
from the last good sample.
"""

from __future__ import annotations

import functools
import math
import textwrap
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, MechatronError, UnreachableError
from ..io.values import number
from ..model.batched import BatchedFrames, batched_frames
from ..model.mechanism import Measure, Mechanism
from ..report.result import Result, frame_records, json_ready
from . import batch, compiled
from .compiled import LoopKernel, loop_kernel
from .geometry import measure_values
from .loops import SINGULAR_RATIO, LoopSolver, loop_solver

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.closures import FrameStates
    from ..report.html import Item, Report

ProgressCallback = Callable[[int, int], None]

#: Units of the per-point and per-link columns of a sweep table, by suffix (angles are charted in degrees).
_POINT_UNITS = {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "v": "m/s", "ax": "m/s²", "ay": "m/s²", "a": "m/s²"}
_LINK_UNITS = {"angle": "deg", "omega": "rad/s", "epsilon": "rad/s²"}
_QUANTITY = {"deg": "angle", "m": "length", "m/s": "speed", "m/s²": "acceleration", "rad/s": "angular velocity",
             "rad/s²": "angular acceleration", "-": "value"}
_MEASURE_QUANTITY: dict[str | None, str] = {"transmission_angle": "transmission angle", "lever_arm": "lever arm",
                                             "distance": "distance"}


@dataclass
class SweepResult(Result):
    """Results of :func:`sweep`: a mechanism analysed along the strokes of its inputs.

    Attributes:
        mechanism: The mechanism swept.
        table: One row per assembled sample: its index ``sample``, the inputs, every joint coordinate ``q_*``,
            velocity ``v_*`` and acceleration ``a_*``, each point's ``{P}_x, _y`` (m), ``_vx, _vy, _v`` (m/s),
            ``_ax, _ay, _a`` (m/s²), each link's ``{L}_angle`` (rad), ``_omega`` (rad/s), ``_epsilon`` (rad/s²)
            and each measure (rad or m). SI units throughout.
        failures: One row per sample that could not be analysed: its index ``sample``, its inputs and the
            ``reason``.
        q, v, a: Joint coordinates, velocities and accelerations of the table's rows, (n, nv) arrays.
        measures: The transmission angles and lever arms evaluated (columns of ``table``).
        points, links: The points and links of ``table``.

    The protocol: :meth:`to_frame` is ``table``; :meth:`as_dict` the ranges of inputs, points and measures with the
    measures' checks and every failure; :meth:`plot` the linkage at several positions beside chosen curves;
    ``str`` the text report of ``mechatron linkage``.
    """

    mechanism: Mechanism
    table: pd.DataFrame
    failures: pd.DataFrame
    q: NDArray[np.float64]
    v: NDArray[np.float64]
    a: NDArray[np.float64]
    measures: list[Measure] = field(default_factory=list)
    points: list[str] = field(default_factory=list)
    links: list[str] = field(default_factory=list)

    # --------------------------------------------------------------------------------------------- the data
    def check_measures(self) -> list[dict[str, Any]]:
        """Each measure's minimum and maximum over the sweep (rad or m) against its required minimum (if any):
        ``name, kind, min, max, required_min, pass`` (``pass`` None when nothing is required)."""
        out = []
        for m in self.measures:
            values = self.table[m.name].to_numpy()
            worst = float(values.min()) if len(values) else math.nan
            out.append({"name": m.name, "kind": m.kind, "min": worst,
                        "max": float(values.max()) if len(values) else math.nan,
                        "required_min": m.minimum, "pass": None if m.minimum is None else bool(worst >= m.minimum)})
        return out

    def _span(self, column: str) -> list[float] | None:
        values = self.table[column]
        return [float(values.min()), float(values.max())] if len(values) else None

    def _rate(self, name: str) -> float | list[float] | None:
        """The rate of input ``name``: one number if constant over the sweep, else its [min, max]."""
        span = self._span(f"v_{name}")
        if span is None:
            return self.mechanism.input_rates.get(name, 1.0)
        return span[0] if span[1] - span[0] <= 1e-12 * max(1.0, abs(span[0])) else span

    def to_frame(self) -> pd.DataFrame:
        """:attr:`table`: one row per assembled sample (SI units; see the class docstring for the columns)."""
        return self.table.copy()

    def write_csv(self, path: str | Path) -> Path:
        """Write :meth:`to_frame` as CSV, whole or not at all; the ``<stem>.failures.csv`` that earlier versions
        wrote beside it (the failures, now in :meth:`as_dict` and the text report) is removed with the same
        commit (:func:`mechatron.io.output.stage_removal`)."""
        from ..io.output import stage_removal, stale_failures, transaction

        with transaction():
            written = super().write_csv(path)
            stale = stale_failures(written)
            if stale is not None:
                stage_removal(stale)
        return written

    def as_dict(self) -> dict[str, Any]:
        """The sweep as plain data: ``mechanism, description, actuated, mobility, redundant_closure_equations``,
        ``samples`` (asked for) and ``assembled`` (analysed), ``inputs`` ({name: [min, max]}, m or rad), ``rates``
        (m/s or rad/s: one number per input, or [min, max] if it varies), ``points`` ({name: {x, y: [min, max]
        (m), v_max (m/s), a_max (m/s²)}}), ``measures`` (:meth:`check_measures`) and ``failures`` (every sample
        not analysed: ``sample``, its inputs, ``reason``)."""
        mech, table = self.mechanism, self.table
        return json_ready({
            "mechanism": mech.name, "description": mech.description, "actuated": list(mech.actuated),
            "mobility": mech.mobility(), "redundant_closure_equations": mech.redundant_closure_equations(),
            "samples": int(len(table) + len(self.failures)), "assembled": int(len(table)),
            "inputs": {name: self._span(name) for name in mech.actuated},
            "rates": {name: self._rate(name) for name in mech.actuated},
            "points": {p: {"x": self._span(f"{p}_x"), "y": self._span(f"{p}_y"),
                           "v_max": float(table[f"{p}_v"].max()) if len(table) else None,
                           "a_max": float(table[f"{p}_a"].max()) if len(table) else None}
                       for p in self.points if f"{p}_x" in table},
            "measures": self.check_measures(),
            "failures": frame_records(self.failures),
        })

    def __str__(self) -> str:
        data = self.as_dict()
        lines = [f"{data['mechanism']}: {data['description']}",
                 f"mobility W = {data['mobility']} (redundant closure equations: "
                 f"{data['redundant_closure_equations']}); {data['assembled']} of {data['samples']} positions "
                 "analysed"]
        angular = dict(zip(self.mechanism.joint_names, self.mechanism.angular_coordinates()))
        for name, span in data["inputs"].items():
            if span:
                rate = data["rates"][name]
                rate = f"{rate:g}" if not isinstance(rate, list) else f"{rate[0]:g} … {rate[1]:g}"
                unit = "rad" if angular.get(name) else "m"
                lines.append(f"  input {name}: {span[0]:.6g} … {span[1]:.6g} {unit} at rate {rate} {unit}/s")
        heads = ("x min (m)", "x max (m)", "y min (m)", "y max (m)", "|v| max (m/s)", "|a| max (m/s²)")
        lines += ["", f"{'point':<10}" + "".join(f"{h:>16}" for h in heads)]
        for name, p in data["points"].items():
            if p["x"]:
                lines.append(f"{name:<10}{p['x'][0]:16.4f}{p['x'][1]:16.4f}{p['y'][0]:16.4f}{p['y'][1]:16.4f}"
                             f"{p['v_max']:16.4g}{p['a_max']:16.4g}")
        if data["measures"] and data["assembled"]:
            lines += ["", f"{'measure':<28} {'min':>10} {'max':>10}  unit check"]
            for m in data["measures"]:
                angle = m["kind"] == "transmission_angle"
                f = math.degrees if angle else float
                unit = "deg" if angle else "m"
                check = "" if m["required_min"] is None else \
                    f"{'PASS' if m['pass'] else 'FAIL'} (>= {f(m['required_min']):.4g} {unit})"
                lines.append(f"{m['name']:<28} {f(m['min']):10.4f} {f(m['max']):10.4f}  {unit:<4} {check}".rstrip())
        if data["failures"]:
            shown = 10
            lines += ["", f"{len(data['failures'])} positions not analysed:"]
            for row in data["failures"][:shown]:
                inputs = ", ".join(f"{n} = {row[n]:.6g}" for n in data["actuated"] if row.get(n) is not None)
                lines.append(f"  sample {row['sample']} ({inputs}): {row['reason']}")
            if len(data["failures"]) > shown:
                lines.append(f"  … and {len(data['failures']) - shown} more (all of them in --json)")
        return "\n".join(lines)

    # -------------------------------------------------------------------------------------------- the chart
    def column_unit(self, column: str) -> str:
        """The unit a chart shows the table column ``column`` in: "deg" for angles (the table holds radians), "m",
        "m/s", "m/s²", "rad/s", "rad/s²", or "-" if unknown."""
        mech = self.mechanism
        for m in self.measures:
            if m.name == column:
                return "deg" if m.kind == "transmission_angle" else "m"
        angular = dict(zip(mech.joint_names, mech.angular_coordinates()))
        if column in angular:
            return "deg" if angular[column] else "m"
        for prefix, units in (("q_", ("deg", "m")), ("v_", ("rad/s", "m/s")), ("a_", ("rad/s²", "m/s²"))):
            if column.startswith(prefix) and column[2:] in angular:
                return units[0] if angular[column[2:]] else units[1]
        for names, suffixes in ((self.points, _POINT_UNITS), (self.links, _LINK_UNITS)):
            for name in names:
                if column.startswith(name + "_") and column[len(name) + 1:] in suffixes:
                    return suffixes[column[len(name) + 1:]]
        return "-"

    def _chart_values(self, column: str) -> NDArray[np.float64]:
        values = self.table[column].to_numpy(dtype=float)
        return np.degrees(values) if self.column_unit(column) == "deg" else values

    def default_curves(self) -> list[str]:
        """The curves :meth:`plot` draws by default: the measures, or the speed of the tool point."""
        if self.measures:
            return [m.name for m in self.measures]
        tool = self.mechanism.tool_frame
        speeds = [f"{p}_v" for p in ([tool] if tool in self.points else self.points[:1])]
        return [c for c in speeds if c in self.table]

    def plot(self, ax: Axes | None = None, *, x: str | None = None, curves: Sequence[str] | None = None,
             positions: int = 6, trace: str | None = None, title: str | None = None) -> Figure:
        """The linkage at ``positions`` configurations of the sweep with the path of the point ``trace`` (default
        the tool point), beside the ``curves`` (table columns; default :meth:`default_curves`) against the column
        ``x`` (default the first input), one chart per unit, with the required minima of the measures drawn.
        Angles are shown in degrees, everything else in SI units. Given ``ax``, draws the linkage into it.

        Raises:
            InputError: if no sample was assembled.
        """
        from ..report.figures import figure_axes, new_figure, style_axes
        from .drawing import draw_positions, key_below

        mech, table = self.mechanism, self.table
        if table.empty:
            raise InputError(f"{mech.name}: no sample could be assembled, nothing to plot")
        x = x or mech.actuated[0]
        if x not in table:
            raise InputError(f"no column {x!r} in the sweep table to plot against")
        curves = [c for c in (self.default_curves() if curves is None else curves) if c in table.columns]
        trace = trace or (mech.tool_frame if mech.tool_frame in self.points else None)
        if ax is None:
            figure = new_figure(12.0, 5.5)
            grid = figure.add_gridspec(max(1, len({self.column_unit(c) for c in curves})), 2, width_ratios=[1.2, 1])
            ax_mech = figure.add_subplot(grid[:, 0])
        else:
            figure, ax_mech = figure_axes(ax)
        picks = np.linspace(0, len(table) - 1, min(positions, len(table))).round().astype(int)
        draw_positions(mech, self.q[picks], ax_mech)
        if trace and f"{trace}_x" in table:
            ax_mech.plot(table[f"{trace}_x"], table[f"{trace}_y"], color="tab:red", lw=1, label=f"path of {trace}")
        # wrapped to the drawing's width (about 64 characters of 10 pt): a long description is not clipped
        ax_mech.set_title(textwrap.fill(title or mech.description or mech.name, 64), fontsize=10)
        if ax is not None:
            ax_mech.legend(loc="upper right", fontsize=8)
            return figure
        key_below(figure, [ax_mech])
        groups: dict[str, list[str]] = {}
        for column in curves:
            groups.setdefault(self.column_unit(column), []).append(column)
        kinds = {m.name: m.kind for m in self.measures}
        x_unit = self.column_unit(x)
        xs = self._chart_values(x)
        first = None
        for row, (unit, columns) in enumerate(groups.items()):
            axis = figure.add_subplot(grid[row, 1], sharex=first)
            first = first or axis
            for column in columns:
                axis.plot(xs, self._chart_values(column), label=column)
            for m in self.measures:
                if m.minimum is not None and m.name in columns:
                    limit = math.degrees(m.minimum) if unit == "deg" else m.minimum
                    axis.axhline(limit, color="gray", ls=":", lw=1, label=f"{m.name} required minimum")
            measured = {kinds.get(c) for c in columns}
            quantity = _MEASURE_QUANTITY.get(measured.pop(), _QUANTITY.get(unit, "value")) if len(measured) == 1 \
                else _QUANTITY.get(unit, "value")
            style_axes(axis, f"{x} ({x_unit})", f"{quantity} ({unit})", legend=True, loc="upper right")
        return figure

    # ---------------------------------------------------------------------------------------- the HTML report
    def critical_measures(self) -> list[str]:
        """The measures that decide the critical position: the transmission angles, else the first measure."""
        return [m.name for m in self.measures if m.kind == "transmission_angle"] or [m.name for m in self.measures][:1]

    def critical_sample(self) -> int | None:
        """The row of :attr:`table` at the smallest value of the :meth:`critical_measures` (the smallest
        transmission angle), or None without measures or rows."""
        names = self.critical_measures()
        return int(np.argmin(self.table[names].min(axis=1).to_numpy())) if names and len(self.table) else None

    def report(self, mechanism: Mechanism | None = None, **context: Any) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the method, every measure's check, the range of every
        point, every position analysed (the inputs, measures and tool point, angles in degrees) and those that could
        not be, the chart, and the linkage drawn at its :meth:`critical_sample` (the mechanism's own
        ``mechanism`` is used; the argument is for the protocol)."""
        import sys

        import pandas as pd

        from ..report.html import Chart, Code, Method, Report, Section, Table, Text
        from . import geometry, loops
        from .drawing import configuration_figure

        mech, table = self.mechanism, self.table
        degrees = {m.name: m.kind == "transmission_angle" for m in self.measures}
        checks = pd.DataFrame([{**row, **{k: math.degrees(row[k]) if degrees[row["name"]] and row[k] is not None
                                          else row[k] for k in ("min", "max", "required_min")},
                                "unit": "deg" if degrees[row["name"]] else "m"} for row in self.check_measures()],
                              columns=["name", "kind", "min", "max", "required_min", "unit", "pass"])
        tool = [f"{mech.tool_frame}_{axis}" for axis in ("x", "y", "z", "v", "a")]
        shown = [c for c in ("sample", *mech.actuated, *degrees, *tool) if c in table]
        positions = pd.DataFrame({c if c == "sample" else f"{c} ({self.column_unit(c)})":
                                  table[c].to_numpy() if c == "sample" else self._chart_values(c) for c in shown})
        points = pd.DataFrame([{"point": name, "x min": p["x"][0], "x max": p["x"][1], "y min": p["y"][0],
                                "y max": p["y"][1], "|v| max (m/s)": p["v_max"], "|a| max (m/s²)": p["a_max"]}
                               for name, p in self.as_dict()["points"].items() if p["x"]])
        lines = str(self).splitlines()
        results: list[Item] = [Code("\n".join(lines[:2])), Table(checks, "measures and their checks", "measures"),
                               Table(points, "the range of every point (m)", "points"),
                               Table(positions, "every position analysed", "positions")]
        methods: list[Item] = [Method(sys.modules[__name__].__doc__ or ""), Method(loops.__doc__ or "")]
        sections = [Section("Method", methods + [Method(geometry.transmission_angles.__doc__ or "")]
                            * any(degrees.values())),
                    Section("Results", results + [Table(self.failures, "positions not analysed", "failures")]
                            * bool(len(self.failures))),
                    Section("Chart", [Chart(self.plot())] if len(table) else [Text("no position could be analysed")])]
        k = self.critical_sample()
        if k is None and len(table):
            sections[-1].items.append(Text(f"{mech.name} has no transmission angle or other measure to find a "
                                           "critical position by ([[measures]] of a mechanism file); the chart draws "
                                           "it at several positions"))
        if k is not None:
            name = min(self.critical_measures(), key=lambda n: table[n].iloc[k])
            where = f"position {int(table['sample'].iloc[k])}"
            text = f"{where}: {name} = {self._chart_values(name)[k]:.4g} {self.column_unit(name)}, its smallest " \
                   "over the stroke"
            frame = mech.tool_frame if mech.tool_frame in mech.frame_names else None
            sections.append(Section("Critical position", [Text(text), Chart(configuration_figure(
                mech, self.q[k], frame=frame, title=f"{mech.name} at {where}"))]))
        return Report(lines[0], sections)


def default_inputs(mech: Mechanism, samples: int) -> dict[str, NDArray[np.float64]]:
    """``samples`` values of every actuated coordinate from its lower to its upper limit together (m or rad; a full
    turn, 2π rad, from the reference angle for an unlimited revolute input)."""
    lower, upper = mech.model.lowerPositionLimit, mech.model.upperPositionLimit
    solver = loop_solver(mech)
    out = {}
    for name in mech.actuated:
        i = solver.index[name]
        if np.isfinite(lower[i]) and np.isfinite(upper[i]):
            out[name] = np.linspace(lower[i], upper[i], samples)
        else:
            start = mech.reference_q[i] if mech.reference_q is not None else 0.0
            out[name] = start + np.linspace(0.0, 2 * math.pi, samples)
    return out


def _as_arrays(values: Mapping[str, object] | None, names: Sequence[str], n: int, default: Callable[[str], float],
               what: str) -> np.ndarray:
    out = np.empty((n, len(names)))
    values = dict(values or {})
    for j, name in enumerate(names):
        value = values.pop(name, None)
        out[:, j] = default(name) if value is None else np.broadcast_to(np.asarray(value, dtype=float), (n,))
    if values:
        raise InputError(f"{what}: {', '.join(values)} not actuated coordinates (actuated: {', '.join(names)})")
    if not np.all(np.isfinite(out)):
        raise InputError(f"{what} must be finite")
    return out


#: The least time one closed-loop position takes (assembly, velocity and acceleration analysis) sample by sample: s
#: (measured: 3 to 6 ms on a desktop), and in a batched sweep (1 to 5 µs with the compiled kernels, 3 to 10 µs with
#: NumPy).
POSITION_SECONDS, BATCHED_POSITION_SECONDS = 1e-3, 1e-6


def position_bytes(mech: Mechanism) -> tuple[float, float]:
    """(fixed bytes, bytes per position) of :func:`sweep`: the working storage of its chunks and anchors, about
    (0.2 nq + 0.03 nq²) MB — 0.01 nq² MB where the mechanism has its compiled driver already (one block, no
    chunks) —, and twice the table's row of 8-byte columns per position — sample, inputs, q, q̇ and q̈ of every joint,
    8 columns per point (11 in a spatial loop), 3 per link (all of the mechanism's, an upper bound), one per measure
    (measured from 400 to 50,000 positions of every shipped closed loop: tests/test_bounded.py)."""
    def build() -> float:
        spatial = any(not getattr(c, "planar", True) for c in mech.closures)
        columns = (1 + len(mech.actuated) + 3 * mech.nv + (11 if spatial else 8) * len(mech.points)
                   + 3 * len(mech.link_names) + len(mech.measures))
        return 16.0 * columns

    kernels: dict[Hashable, LoopKernel | None] = mech.cached("loop_kernels", dict)
    driven = any(k is not None and k.driven for k in kernels.values())
    fixed = 0.01 * mech.nq**2 if driven else 0.2 * mech.nq + 0.03 * mech.nq**2
    return fixed * 1e6, mech.cached("position_bytes", build)


def positions_budget(mech: Mechanism, count: float, name: str, *, per_position: int = 1,
                     seconds_per_position: float = POSITION_SECONDS, value: float | None = None) -> None:
    """Refuse (:mod:`mechatron.io.budget`) ``count`` closed-loop positions (``per_position`` assemblies each of
    ``seconds_per_position``) asked for by ``name`` (``samples``: fewer samples; ``inputs``: fewer input values)
    past the memory or time limit. ``value``: the value of ``name`` that implies ``count`` positions where they
    differ (``--samples 300`` per stroke of three cylinders: 300³ positions)."""
    from ..io.budget import count as shown
    from ..io.budget import option, require, seconds

    label = option(name)
    if value is not None:
        what = f"{label} {shown(value)} gives {shown(count)} positions of {mech.name}"
        require(what, count, position_bytes(mech)[1], fixed=position_bytes(mech)[0], advice=f"use fewer {label}")
        seconds(what, count * per_position, seconds_per_position, advice=f"use fewer {label}")
        return
    what = f"{label} {shown(count)}" if name == "samples" else f"{shown(count)} values of the {label}"
    what += f" gives {shown(count * per_position)} positions of {mech.name}" if per_position > 1 else \
        f": positions of {mech.name}"
    advice = f"use fewer {label}"
    fixed, row = position_bytes(mech)
    require(what, count, row, fixed=fixed, advice=advice)
    seconds(what, count * per_position, seconds_per_position, advice=advice)


def sweep(mech: Mechanism, inputs: Mapping[str, ArrayLike] | None = None, *, samples: int = 200,
          rates: Mapping[str, ArrayLike] | None = None, accelerations: Mapping[str, ArrayLike] | None = None,
          frames: Sequence[str] | None = None, links: Sequence[str] | None = None,
          measures: Sequence[Measure] | None = None, guess: ArrayLike | None = None,
          progress: ProgressCallback | None = None, stop_on_failure: bool = False) -> SweepResult:
    """Analyse ``mech`` at N positions along the input values ``inputs`` (name → N values, m or rad; default
    :func:`default_inputs` with ``samples`` values): positions, velocities and accelerations of every joint, point
    and link, the position analysis by continuation on one assembly branch, the velocity analysis
    q̇ = S q̇_a ([Egorov, 4.2–4.5, 4.9–4.11]) and the acceleration analysis J_d q̈_d = −J_a q̈_a − J̇ q̇
    ([Egorov, 4.6–4.8, 4.14–4.16]).

    Args:
        inputs: Values of the actuated coordinates (m, rad); inputs not given stay at their value in ``guess``.
        samples: Number of positions when ``inputs`` is not given.
        rates: Actuated rates (m/s, rad/s), scalars or arrays of N; default ``mech.input_rates`` or 1.
        accelerations: Actuated accelerations (m/s², rad/s²), default 0.
        frames: Points (frame names) to report (default ``mech.points``).
        links: Links (body frame names) whose angle, angular velocity and acceleration to report (default: none).
        measures: Transmission angles, lever arms (default ``mech.measures``).
        guess: Start of the continuation, a configuration (nq,) (default the reference configuration: its assembly
            branch).
        progress: Called as progress(done, total) every few hundred samples.
        stop_on_failure: End the sweep at the first sample that cannot be analysed: the table holds the samples
            before it, ``failures`` that one with its reason, and no sample after it is tried (a motion that must
            be whole, such as a task, fails as soon as it leaves the reachable range).

    Returns:
        A :class:`SweepResult`; the samples that cannot be analysed (an input out of its range, loops that do not
        close, a singular position) are in its ``failures`` with the reason, not in its table.
    """
    base = loop_solver(mech)
    given = inputs is not None
    if not given:
        samples = number("samples", samples, integer=True, minimum=2)
        positions_budget(mech, samples, "samples", seconds_per_position=BATCHED_POSITION_SECONDS)
    inputs = dict(inputs) if inputs is not None else default_inputs(mech, samples)
    lengths = {len(np.atleast_1d(np.asarray(v))) for v in inputs.values()}
    if len(lengths) != 1:
        raise InputError("every swept input needs the same number of samples")
    n = lengths.pop()
    if given:
        positions_budget(mech, n, "inputs", seconds_per_position=BATCHED_POSITION_SECONDS)
    names = list(mech.actuated)
    q = np.array(mech.reference_q if guess is None else guess, dtype=float)
    held = {name: q[base.index[name]] for name in names}
    U = _as_arrays(inputs, names, n, lambda name: held[name], "inputs")
    R = _as_arrays(rates, names, n, lambda name: mech.input_rates.get(name, 1.0), "rates")
    A = _as_arrays(accelerations, names, n, lambda name: 0.0, "accelerations")
    points = list(mech.points if frames is None else frames)
    links = list(links or [])
    measures = list(mech.measures if measures is None else measures)
    failures = _out_of_range(base, U, names)
    if not stop_on_failure:
        return _analysed(base, U, R, A, q, failures, progress, names, points, links, measures)
    end = min(failures, default=n)  # the samples before the first input out of range
    if end == 0:  # the first sample: a table without rows
        result = _analysed(base, U[:1], R[:1], A[:1], q, {0: failures[0]}, progress, names, points, links, measures)
    else:
        result = _analysed(base, U[:end], R[:end], A[:end], q, {}, progress, names, points, links, measures,
                           stop=True)
    failed = [int(k) for k in result.failures["sample"]]
    if failed or end < n:
        first = min(failed, default=end)
        reason = failures[first] if first == end else \
            result.failures.loc[result.failures["sample"] == first, "reason"].iloc[0]
        keep = (result.table["sample"] < first).to_numpy()
        if not keep.all():
            result.q, result.v, result.a = result.q[keep], result.v[keep], result.a[keep]
            result.table = result.table[keep].reset_index(drop=True)
        result.failures = _failure_frame(U, names, {first: reason})
    return result


def _analysed(base: LoopSolver, U: np.ndarray, R: np.ndarray, A: np.ndarray, q: np.ndarray,
              failures: dict[int, str], progress: ProgressCallback | None, names: list[str], points: list[str],
              links: list[str], measures: list[Measure], stop: bool = False) -> SweepResult:
    """The sweep of :func:`sweep` at the inputs U (N, n_act) with rates R and accelerations A, from the
    configuration q (the samples in ``failures`` out of range): positions by the compiled driver (where the
    mechanism has a kernel), else batched or by continuation; then velocities, accelerations and the table. With
    ``stop`` the positions end at the first sample that does not assemble."""
    mech, n = base.mech, len(U)
    kernel = _kernel(base, points, links, measures, n) if BATCHED else None
    # the compiled continuation and analysis, straight into the table; for input steps longer than the
    # continuation's (a sweep of a few samples), where its guess one step on can land on another assembly branch,
    # in shorter steps, checked (_in_steps), else as below: every long step walked (_Continuation.solve)
    long = n > 1 and bool(np.any(np.abs(np.diff(U, axis=0)) > base.max_step))
    if kernel is not None and kernel.driven and not long:
        return _driven(base, kernel, U, R, A, q, failures, progress, names, points, links, measures, stop)
    if kernel is not None and kernel.driven:
        result = _in_steps(base, kernel, U, R, A, q, failures, progress, names, points, links, measures, stop)
        if result is not None:
            return result
    if kernel is not None and n < COMPILED_MIN:
        kernel = None  # CasADi's virtual machine: only for long sweeps
    wanted = list(dict.fromkeys(points + [p for m in measures for p in m.points] + links))
    solver = LoopSolver(mech, extra_frames=wanted)  # evaluates the reported frames with the closures' frames
    system = solver.system

    # positions: by batched Newton between anchors solved by continuation (kinematics/batch.py) when the batched
    # kinematics knows the joints, else by continuation from sample to sample
    closing = _batched_frames(base) if BATCHED and kernel is None else None  # the closures' frames
    every = _batched_frames(solver) if closing is not None else None  # and the reported ones
    if (kernel is not None or closing is not None) and n >= BATCH_MIN:
        newton: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
        if kernel is not None:
            newton = kernel.newton
        else:
            assert closing is not None
            newton = lambda Q: batch.newton(base.system, closing, Q, base.act, base.dep)
        Q, ok = _batched_positions(base, newton, U, q, failures, progress, kernel, stop)
    else:
        Q, ok, saved = _Continuation(solver, U, q, failures, progress, keep=every is None).run(range(n), stop)
    # velocities q̇ = S q̇_a, accelerations J_d q̈_d = −J_a q̈_a − J̇ q̇ and the reported frames, all samples at once
    reported = [system.index[name] for name in wanted]
    if kernel is not None:
        good, V, Aq, columns = _analyse_compiled(solver, kernel, Q, ok, R, A, points, measures, U, failures)
    elif every is not None:
        good, V, Aq, columns = _analyse_batched(solver, every, reported, Q, ok, R, A, wanted, points, links,
                                                measures, U, failures)
    else:
        assert saved is not None  # kept by the continuation (keep: no batched frames)
        good, V, Aq, columns = _analyse_pinocchio(solver, Q, ok, saved, R, A, reported, wanted, points, links,
                                                  measures, U, failures)
    return _result(mech, U, good, Q[good], V, Aq, columns, links, measures, failures, names, points)


def _out_of_range(solver: LoopSolver, U: np.ndarray, names: list[str]) -> dict[int, str]:
    """The samples whose inputs U (N, n_act) leave their joint's range, with the reason."""
    lower, upper = solver.lower[solver.act], solver.upper[solver.act]
    out_of_range = (U < lower - 1e-12) | (U > upper + 1e-12)
    failures: dict[int, str] = {}
    for k in np.flatnonzero(out_of_range.any(axis=1)):
        j = int(np.argmax(out_of_range[k]))
        failures[int(k)] = f"{names[j]} = {U[k, j]:.6g} is outside its range [{lower[j]:.6g}, {upper[j]:.6g}]"
    return failures


#: Use the batched position analysis and kinematics where the joints allow (False: the sequential reference).
BATCHED = True
#: Fewer samples than this are solved sequentially.
BATCH_MIN = 16
#: From this many samples on, the compiled kernels (:mod:`mechatron.kinematics.compiled`) solve and analyse the
#: samples where the mechanism has a symbolic form (building one costs ~0.03 s, compiling it once ~0.5 s): by their
#: driver, else (no compiler: CasADi's virtual machine) batched.
COMPILED_MIN = 2048


def _batched_frames(solver: LoopSolver, names: Sequence[str] | None = None) -> BatchedFrames | None:
    """The batched kinematics of the frames ``names`` (default: the solver's), or None for joints it does not know
    (then Pinocchio)."""
    mech = solver.mech
    try:
        if names is None:
            return solver.system.batched()
        return batched_frames(mech.model, [mech.frame_id(name) for name in names])
    except NotImplementedError:
        return None


class _Continuation:
    """The sequential position analysis: sample after sample, Newton's method from the polynomial through the last
    (up to four) solutions reached by equal input steps (:func:`_extrapolate`); a sample that cannot be assembled
    gets its reason in ``failures`` and the next one starts again from the last solution."""

    def __init__(self, solver: LoopSolver, U: np.ndarray, q: np.ndarray, failures: dict[int, str],
                 progress: ProgressCallback | None = None, keep: bool = False, polish: bool = True,
                 kernel: LoopKernel | None = None, far: LoopKernel | None = None) -> None:
        self.solver, self.U, self.q, self.failures, self.progress = solver, U, q, failures, progress
        self.kernel = kernel  # with two or more solutions before, a sample is first tried by the compiled Newton
        self.far = far  # Newton's method with halved steps by this kernel's driver (else the solver's, in NumPy)
        self.keep = keep  # keep every sample's closure Jacobian and frame placements and Jacobians (for Pinocchio)
        self.polish = polish  # one more Newton step after convergence (else the residual is only below TOLERANCE)
        self.history: list[np.ndarray] = []  # last good solutions, each reached by the same step as the next

    def solve(self, k: int, same_step: bool) -> tuple[np.ndarray, np.ndarray | None] | None:
        """Sample k: (q, closure Jacobian, None where the compiled Newton solved it) or None (the reason in
        ``failures``)."""
        solver, history = self.solver, self.history
        if k in self.failures:
            history.clear()
            return None
        if history and not same_step:
            del history[:-1]  # the step changed: only the last solution is a good start
        trial = _extrapolate(history, self.q)
        trial[solver.act] = self.U[k]
        if history and np.any(np.abs(self.U[k] - history[-1][solver.act]) > solver.max_step):
            try:  # a long step: walked on the branch
                trial, J = solver.newton(self._walk(history[-1], self.U[k]), polish=self.polish)
            except MechatronError as exc:
                self.failures[k] = str(exc)
                history.clear()
                return None
        elif self.kernel is not None and len(history) >= 2 and self._compiled_newton(trial, history):
            J = None
        else:
            try:
                if self.far is not None and self.polish:
                    J = None
                    if not self.far.far(trial):
                        raise solver.unreachable(trial)
                else:
                    trial, J = solver.newton(trial, polish=self.polish)  # polished: the residual at rounding level
            except MechatronError as exc:
                self.failures[k] = str(exc)
                history.clear()
                return None
        history.append(trial)
        if len(history) > 4:
            del history[0]
        self.q = trial
        return trial, J

    def _walk(self, before: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The solution at the inputs ``u`` on the assembly branch of the solution ``before``, when the input step is
        longer than :attr:`~mechatron.kinematics.loops.LoopSolver.max_step` (a sweep of a few samples, where
        Newton's method from a guess one long step on can land on another branch: a crank-slider's rod folded the
        other way): the step walked in equal steps of at most ``max_step``, each checked (:meth:`_step`)."""
        solver = self.solver
        start = before[solver.act]
        steps = max(1, int(np.ceil(np.max(np.abs(u - start) / solver.max_step, initial=0.0))))
        q, S = before, solver.velocity_matrix(before)
        for j in range(1, steps + 1):
            q, S = self._step(q, S, start + (u - start) * j / steps)
        return q

    def _step(self, q: np.ndarray, S: np.ndarray, u: np.ndarray, depth: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """One step of :meth:`_walk` from the solution q (its velocity map S) to the inputs u: Newton's method from
        the prediction q + S Δu, accepted where the change of the dependent coordinates follows the velocity maps,
        |Δq_d − ½ (S + S_after) Δu| ≤ :data:`batch.JUMP_RATIO` |Δq_d| (the trapezoidal rule, the batched check),
        else the step halved and each half walked, at most :data:`WALK_HALVINGS` times. A step that cannot be
        followed so (next to a singular position, where two branches nearly meet: a crank-slider whose rod is
        about as long as its crank) is an :class:`~mechatron.errors.UnreachableError` naming the inputs; one whose
        last, shortest step finds no solution is Newton's error (the loops do not close there). Returns the solution
        and its velocity map."""
        solver = self.solver
        du = u - q[solver.act]
        trial = q + S @ du
        trial[solver.act] = u
        failure: MechatronError | None = None
        try:
            after, J = solver.newton(trial)
            S_after = solver.velocity_matrix(after, J)
            change = after[solver.dep] - q[solver.dep]
            error = np.abs(change - 0.5 * ((S + S_after)[solver.dep] @ du)).max(initial=0.0)
            if error <= max(batch.JUMP_RATIO * np.abs(change).max(initial=0.0), batch.JUMP_FLOOR):
                return after, S_after
        except MechatronError as exc:
            failure = exc
        if depth >= WALK_HALVINGS and failure is not None:
            raise failure  # no solution next to u: the loops do not close there
        if depth >= WALK_HALVINGS:
            raise UnreachableError(f"{solver.mech.name}: the assembly branch cannot be followed from "
                                   f"{solver._describe_inputs(q)} to {_inputs_text(solver, u)}: a singular "
                                   "position, or two branches nearly meeting, lies between",
                                   inputs=dict(zip(solver.mech.actuated, map(float, u))))
        middle = self._step(q, S, (q[solver.act] + u) / 2, depth + 1)
        return self._step(*middle, u, depth + 1)

    def _compiled_newton(self, trial: np.ndarray, history: list[np.ndarray]) -> bool:
        """Solve ``trial`` in place by the kernel's Newton steps; accepted only if it converged within half the
        change since the previous solution of its guess (else it may have left the branch: full steps have no
        halving)."""
        assert self.kernel is not None  # called with a kernel only
        row = trial[None].copy()
        change = np.abs(history[-1] - history[-2]).max()
        if not (self.kernel.newton(row)[0][0] and np.abs(row[0] - trial).max() <= 0.5 * change + 1e-9):
            return False
        trial[:] = row[0]
        return True

    def run(self, samples: Sequence[int] | np.ndarray, stop: bool = False
            ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...] | None]:
        """Solve ``samples`` in turn: (Q (n, nv), which converged, and with ``keep`` the closure Jacobians,
        placements and frame Jacobians of every sample); with ``stop``, none after the first that fails."""
        samples = list(samples)
        n, nv, states = len(self.U), self.solver.mech.nv, self.solver.system.states
        Q, ok = np.zeros((n, nv)), np.zeros(n, dtype=bool)
        if self.keep:
            saved = (np.zeros((n, self.solver.nrows, nv)), np.zeros((n, len(states.frame_ids), 4, 4)),
                     np.zeros((n, len(states.frame_ids), 6, nv)))
        equal = _same_steps(self.U[samples])
        every = max(1, len(samples) // 100)
        for i, k in enumerate(samples):
            solution = self.solve(k, equal[i])
            if solution is not None:
                Q[k], ok[k] = solution[0], True
                if self.keep:
                    saved[0][k], saved[1][k], saved[2][k] = solution[1], states.homogeneous, states.jacobian
            elif stop:
                break
            if self.progress is not None and (i % every == 0 or i == len(samples) - 1):
                self.progress(i + 1, len(samples))
        return Q, ok, saved if self.keep else None


#: The most halvings of an input step walked on its branch (:meth:`_Continuation._walk`).
WALK_HALVINGS = 12


def _inputs_text(solver: LoopSolver, u: np.ndarray) -> str:
    return ", ".join(f"{n} = {x:.6g}" for n, x in zip(solver.mech.actuated, u))


def _same_steps(U: np.ndarray) -> np.ndarray:
    """same[k]: U[k] − U[k−1] equals U[k−1] − U[k−2] (then the polynomial through earlier solutions extrapolates)."""
    steps = np.diff(U, axis=0)
    scale = np.maximum(np.abs(steps).max(axis=1, initial=0.0), 1e-300)
    same = np.zeros(len(U), dtype=bool)
    same[2:] = np.abs(steps[1:] - steps[:-1]).max(axis=1, initial=0.0) <= 1e-9 * scale[1:]
    return same


def _batched_positions(solver: LoopSolver, newton: Callable, U: np.ndarray, q: np.ndarray,
                       failures: dict[int, str], progress: ProgressCallback | None,
                       kernel: LoopKernel | None = None, stop: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Positions of all samples (see :mod:`mechatron.kinematics.batch`): anchors by continuation (tried by the
    compiled ``kernel``'s Newton first where there is one; without it a second level of anchors by ``newton``), the
    rest by ``newton`` (the contract of :func:`batch.newton`, on a chunk of samples) from interpolated guesses; the
    doubtful samples again by the sequential continuation, from the last good sample before them until its solution
    meets the batched one. With ``stop`` nothing is solved after the first sample that fails: the batched solve
    ends at the first anchor that does not assemble, the samples before it are checked as above, and the
    continuation goes on from there sample by sample up to the first failure."""
    n, dep = len(U), solver.dep
    valid = np.ones(n, dtype=bool)
    valid[list(failures)] = False
    candidates = np.flatnonzero(valid)
    act = solver.act
    coarse = batch.anchor_stride(U, batch.ANCHOR_STEPS * solver.max_step)
    anchors = batch.every(candidates, coarse)
    Qa, solved, _ = _Continuation(solver, U, q, dict(failures), polish=False, kernel=kernel).run(anchors, stop)
    end = n  # the samples solved batched: with stop, up to the first anchor that fails
    if stop and len(anchors) and not solved[anchors].all():
        end = int(anchors[np.argmin(solved[anchors])]) + 1
    anchors = anchors[solved[anchors]]
    values = Qa[anchors]
    stride = max(batch.FINER, batch.anchor_stride(U, solver.max_step / 50.0))
    finer = batch.every(candidates[candidates < end], stride)
    if kernel is None and len(anchors) and 4 * stride <= coarse:  # finer anchors by batched Newton from these
        values = batch.interpolate(anchors, values, finer)
        values[:, act] = U[finer]
        converged = np.zeros(len(finer), dtype=bool)
        for part in batch.chunks(len(finer)):
            converged[part] = newton(values[part])[0]
        anchors, values = finer[converged], values[converged]
    Q = np.zeros((n, solver.mech.nv))
    ok = np.zeros(n, dtype=bool)
    doubtful = np.zeros(n, dtype=bool)
    previous = np.zeros(0, dtype=int)  # the last sample of the previous chunk, the first one's predecessor
    maps = np.zeros((0, len(dep), len(act)))
    if len(anchors):
        for part in batch.chunks(end, compiled.CHUNK if kernel is not None else None):
            rows = np.arange(part.start, part.stop)
            Q[part, dep] = batch.interpolate(anchors, values[:, dep], rows)
            Q[part, act] = U[part]
            converged, chunk_maps = newton(Q[part])
            ok[part] = valid[part] & converged
            run = np.concatenate([previous, rows])
            maps = np.concatenate([maps, chunk_maps])
            doubtful[run] |= batch.jumps(Q[run][:, dep], U[run], maps, ok[run])
            previous, maps = rows[-1:], maps[-1:]
            if progress is not None:
                progress(part.stop, n)
    doubtful[:end] |= valid[:end] & ~ok[:end]
    doubtful[1:end] |= valid[1:end] & ~valid[:end - 1]  # after an input out of range the continuation starts again
    trusted = ok & ~doubtful
    redo = _Continuation(solver, U, q, failures)
    equal = _same_steps(U)
    k = 0
    while True:
        waiting = np.flatnonzero(doubtful[k:end])
        if not len(waiting):
            break
        k += int(waiting[0])
        before = np.flatnonzero(ok[:k])
        redo.q = Q[before[-1]].copy() if len(before) else q.copy()
        redo.history = _history(Q, ok, equal, k)
        while k < n:
            solution = redo.solve(k, equal[k])
            ok[k] = solution is not None
            if solution is not None:
                meets = trusted[k] and np.abs(solution[0] - Q[k]).max() < 1e-8
                Q[k] = solution[0]
                if meets:
                    break
            elif stop:
                return Q, ok
            k += 1
        k += 1
    if end < n and not ok[end:].all():  # all up to the anchor that failed solved: on to the first failure
        start = end + int(np.argmin(ok[end:]))
        redo.q, redo.history = Q[start - 1].copy(), _history(Q, ok, equal, start)
        for k in range(start, n):
            solution = redo.solve(k, equal[k])
            if solution is None:
                break
            Q[k], ok[k] = solution[0], True
    return Q, ok


def _history(Q: np.ndarray, ok: np.ndarray, equal: np.ndarray, k: int) -> list[np.ndarray]:
    """The continuation's history before sample k: the solved samples before it (at most four, none before a
    failure), each but the last two reached by the same input step as the next (``equal``)."""
    history: list[np.ndarray] = []
    for j in range(k - 1, max(k - 5, -1), -1):
        if not ok[j] or (j + 2 < k and not equal[j + 2]):
            break
        history.insert(0, Q[j].copy())
    return history


def _extrapolate(history: list[np.ndarray], q: np.ndarray) -> np.ndarray:
    """Starting point of Newton's method: the polynomial through the last (up to four) solutions, reached in equal
    input steps, extrapolated one more step (a cubic leaves a fourth-order error, so most samples need no Newton
    step); ``q`` when there is no history."""
    m = len(history)
    if m >= 4:
        return 4 * history[-1] - 6 * history[-2] + 4 * history[-3] - history[-4]
    if m == 3:
        return 3 * history[-1] - 3 * history[-2] + history[-3]
    if m == 2:
        return 2 * history[-1] - history[-2]
    return (history[-1] if m else q).copy()


def _velocity_maps(solver: LoopSolver, Jc: np.ndarray, explicit: bool = False
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """S_k (n × nv × n_act) for a stack of closure Jacobians, which samples are singular, and J_d⁻¹ (None without
    dependent coordinates); with ``explicit`` the small square J_d are inverted by :func:`batch.inverse`."""
    n, nv, na = len(Jc), solver.mech.nv, len(solver.act)
    S = np.broadcast_to(solver.selection, (n, nv, na)).copy()
    singular = np.zeros(n, dtype=bool)
    if not (len(solver.dep) and solver.nrows) or n == 0:
        return S, singular, None
    Jd, Ja = Jc[:, :, solver.dep], Jc[:, :, solver.act]
    square = Jd.shape[1] == Jd.shape[2]
    with np.errstate(all="ignore"):
        try:
            if explicit and square and Jd.shape[1] <= batch.EXPLICIT:
                inverse = batch.inverse(Jd)
            else:
                inverse = np.linalg.inv(Jd) if square else np.linalg.pinv(Jd)
        except np.linalg.LinAlgError:  # some sample is exactly singular: invert one by one
            inverse = np.full((n, Jd.shape[2], Jd.shape[1]), np.inf)
            for k in range(n):
                try:
                    inverse[k] = np.linalg.inv(Jd[k])
                except np.linalg.LinAlgError:
                    pass
        singular = ~(np.abs(inverse).max(axis=(1, 2)) <= SINGULAR_RATIO)
        S[:, solver.dep] = -inverse @ Ja
    return S, singular, inverse


def _accelerations(solver: LoopSolver, S: np.ndarray, Jc: np.ndarray, inverse: np.ndarray | None, A: np.ndarray,
                   drift: np.ndarray, apply: Callable | None = None) -> np.ndarray:
    """q̈ of a stack of samples: q̈ = S q̈_a with the dependent rows q̈_d = −J_d⁻¹ (J_a q̈_a + J̇ q̇); ``apply(M, x)``
    multiplies the stacks (default ``einsum``)."""
    apply = apply or (lambda M, x: np.einsum("kij,kj->ki", M, x))
    Aq = apply(S, A)
    if inverse is not None:
        rhs = apply(Jc[:, :, solver.act], A) + drift
        Aq[:, solver.dep] = -apply(inverse, rhs)
    return Aq


def _singular_reason(mech: Mechanism, names: list[str], u: np.ndarray) -> str:
    return (f"{mech.name} is at a singular position (" + ", ".join(f"{name} = {u[j]:.6g}" for j, name in
                                                                   enumerate(names))
            + "): the actuated coordinates do not determine the motion")


def _analyse_batched(solver: LoopSolver, frames: BatchedFrames, reported: list[int], Q: np.ndarray,
                     ok: np.ndarray, R: np.ndarray, A: np.ndarray, wanted: list[str], points: list[str],
                     links: list[str], measures: list[Measure], U: np.ndarray, failures: dict[int, str]):
    """Velocities, accelerations and the reported frames' columns of the samples ``ok``, chunk by chunk with one
    batched evaluation of all frames of ``solver.system`` (the closures' and the ``reported`` ones: placements and
    Jacobians, then their motion at q̇ and q̈ = 0): q̇ = S q̇_a, the drift J̇ q̇ and q̈ from the closures' frames,
    then the motion again at q̈ for the reported frames' classical accelerations: (good samples, V, q̈, columns)."""
    system = solver.system
    closing = len(dict.fromkeys(f for c in system.closures for f in c.frames))
    rows = np.flatnonzero(ok)
    V, Aq = np.zeros((len(rows), solver.mech.nv)), np.zeros((len(rows), solver.mech.nv))
    singular = np.zeros(len(rows), dtype=bool)
    columns: dict[str, np.ndarray] = {}
    parts = batch.chunks(len(rows))
    for part in parts:
        k = rows[part] if len(parts) > 1 or len(rows) < len(Q) else slice(None)
        states = frames.placements(Q[k], jacobians=closing)  # the closures' frames come first
        as_one = cast("FrameStates", states)  # a BatchedStates: the closures broadcast over its leading axis
        _, Jc = system.stack(as_one)
        S, singular[part], inverse = _velocity_maps(solver, Jc, explicit=True)
        V[part] = batch.apply(S, R[k])
        frames.motion(states, V[part])
        Aq[part] = _accelerations(solver, S, Jc, inverse, A[k], system.stack_drift(as_one), batch.apply)
        frames.motion(states, V[part], Aq[part])  # again, at q̈: the reported frames' classical accelerations
        # the reported frames sample-last (contiguous rows for the planar frames, whose arrays are transposed views)
        # (no names kept for them: the next part's arrays are made while these are let go)
        assert states.velocity is not None and states.acceleration0 is not None  # filled by frames.motion
        chunk = _frame_columns(solver.mech, _reported(states.position, reported), _reported(states.angle, reported),
                               _reported(states.velocity, reported), _reported(states.acceleration0, reported),
                               wanted, points, links, measures)
        if len(parts) == 1:
            columns = chunk
            continue
        for name, values in chunk.items():
            columns.setdefault(name, np.empty(len(rows)))[part] = values
    return _drop_singular(solver, rows, singular, V, Aq, columns, U, failures)


def _kernel(solver: LoopSolver, points: list[str], links: list[str], measures: list[Measure],
            n: int = COMPILED_MIN) -> LoopKernel | None:
    """The compiled kernel reporting the table's frame columns (the points, the links, the measures' points) for a
    sweep of n samples: built for :data:`COMPILED_MIN` samples or more, and for fewer once the mechanism's
    structure has one (compiled for another geometry, or met with a second one: a design study's, an
    optimiser's), else None."""
    others = [p for p in dict.fromkeys(p for m in measures for p in m.points) if p not in points]
    spatial = any(not getattr(c, "planar", True) for c in solver.mech.closures)
    return loop_kernel(solver, points, links, others, spatial, build=n >= COMPILED_MIN)


def kept_sweep_kernel(solver: LoopSolver) -> LoopKernel | None:
    """The compiled kernel of a sweep of ``solver``'s mechanism without frames or measures (the states along a
    task, :func:`mechatron.dynamics.trajectory.closed_loop_states`) if such a sweep built one, else None."""
    from .compiled import kept_kernel

    spatial = any(not getattr(c, "planar", True) for c in solver.mech.closures)
    kernel = kept_kernel(solver, [], [], [], spatial)
    return kernel if kernel is not None and kernel.driven else None


def _analyse_compiled(solver: LoopSolver, kernel: LoopKernel, Q: np.ndarray, ok: np.ndarray, R: np.ndarray,
                      A: np.ndarray, points: list[str], measures: list[Measure], U: np.ndarray,
                      failures: dict[int, str]):
    """As :func:`_analyse_batched`, by the compiled kernel: velocities, accelerations and the table's frame columns
    of every sample in one call."""
    rows = np.flatnonzero(ok)
    V, Aq, ratio, columns = kernel.analyse(Q[rows], R[rows], A[rows])
    for m in measures:
        columns[m.name] = measure_values(m, {p: np.stack([columns[f"{p}_x"], columns[f"{p}_y"]], axis=1)
                                             for p in m.points})
    for name in kernel.names[len(kernel.names) - 2 * len(kernel.others):]:
        del columns[name]  # the positions of the measures' other points
    return _drop_singular(solver, rows, ~(ratio <= SINGULAR_RATIO), V, Aq, columns, U, failures)


#: The row of max |J_d⁻¹| in a driven sweep's block (after the table's columns).
_RATIO = "max |J_d⁻¹|"


def _driven(solver: LoopSolver, kernel: LoopKernel, U: np.ndarray, R: np.ndarray, A: np.ndarray, q: np.ndarray,
            failures: dict[int, str], progress: ProgressCallback | None, names: list[str], points: list[str],
            links: list[str], measures: list[Measure], stop: bool = False) -> SweepResult:
    """The sweep by the kernel's compiled driver (:data:`compiled.DRIVER`): the continuation over the samples with
    every solution's analysis written into the rows of one block, the table's columns (:class:`_Layout`); the
    samples it leaves by the sequential continuation (:func:`_drive`), analysed after; then the singular positions
    dropped, the measures and the unwrapped link angles (:func:`_finish_columns`)."""
    mech, n = solver.mech, len(U)
    layout = _layout(solver, kernel, names, measures)
    valid = np.ones(n, dtype=np.uint8)
    valid[list(failures)] = 0
    arrays = {"U": np.ascontiguousarray(U), "R": np.ascontiguousarray(R), "A": np.ascontiguousarray(A),
              "same": _same_steps(U).astype(np.uint8), "valid": valid, "begin": q.copy(),
              "reach": layout.reach,
              "history": np.zeros((4, kernel.nq)), "state": np.zeros(2, dtype=np.int64),
              "maps": np.zeros(kernel.nd * kernel.na), "table": np.empty((len(layout.where), n)),
              "motion": np.empty((3, n, kernel.nq)), "rows": layout.rows}
    run = kernel.run(arrays)
    ok, solved = _drive(solver, run, failures, progress, stop)
    if len(solved):
        run.analyse_rows(solved)
    table, motion = arrays["table"], arrays["motion"]
    table[:len(names)] = U.T
    good = np.flatnonzero(ok)
    singular = ~(table[layout.where[_RATIO], good] <= SINGULAR_RATIO)
    for k in good[singular]:
        failures[int(k)] = _singular_reason(mech, names, U[k])
    good = good[~singular]
    if len(good) < n:
        table, motion = table[:, good], motion[:, good]
    _finish_columns(table, layout.where, links, measures)
    return SweepResult(mech, layout.frame(table, good), _failure_frame(U, names, failures), motion[0], motion[1],
                       motion[2], measures, points, links)


def _in_steps(solver: LoopSolver, kernel: LoopKernel, U: np.ndarray, R: np.ndarray, A: np.ndarray, q: np.ndarray,
              failures: dict[int, str], progress: ProgressCallback | None, names: list[str], points: list[str],
              links: list[str], measures: list[Measure], stop: bool = False) -> SweepResult | None:
    """A driven sweep (:func:`_driven`) whose input steps are longer than the continuation's
    (:attr:`~mechatron.kinematics.loops.LoopSolver.max_step`): the inputs swept with every step cut into equal steps
    of at most ``max_step`` (the rates and accelerations interpolated linearly), the samples asked for kept and
    numbered as asked, their failures as the finer sweep found them (with ``stop``, a failure between two samples
    asked for is the later one's). Every step of the finer sweep is checked as :meth:`_Continuation._step` checks
    one (the velocity maps of all its samples at once, by the kernel): where one left the branch (two branches
    nearly meeting), None — the caller walks the steps instead. ``failures`` is updated only when it returns a
    result."""
    n = len(U)
    steps = np.ceil(np.max(np.abs(np.diff(U, axis=0)) / solver.max_step, axis=1)).astype(int).clip(1)
    keep = np.concatenate([[0], np.cumsum(steps)])
    at = np.concatenate([[0.0], *[k + np.arange(1, m + 1) / m for k, m in enumerate(steps)]])
    i = np.minimum(at.astype(int), n - 2)
    f = (at - i)[:, None]

    def finer(X: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(X[i] + f * (X[i + 1] - X[i]))

    Uf = finer(U)
    Uf[keep] = U  # the samples asked for exactly
    fine = {**_out_of_range(solver, Uf, names), **{int(keep[k]): r for k, r in failures.items()}}
    told = None if progress is None else (lambda done, total: progress(min(n, done * n // max(total, 1)), n))
    result = _driven(solver, kernel, Uf, finer(R), finer(A), q, fine, told, names, points, links, measures, stop)
    sample = result.table["sample"].to_numpy()
    if _left_branch(solver, kernel, result.q, Uf[sample], np.diff(sample) == 1):
        return None
    index = np.full(len(Uf), -1)
    index[keep] = np.arange(n)
    if stop and fine:  # the first failure of the finer sweep: the sample asked for at or after it
        first = min(fine)
        fine = {int(keep[np.searchsorted(keep, first)]): fine[first]}
        index[keep[np.searchsorted(keep, first):]] = -1
    rows = index[sample] >= 0
    table = result.table[rows].reset_index(drop=True)
    table["sample"] = index[sample[rows]]
    asked = {int(k): j for j, k in enumerate(keep)}
    failures.update({asked[k]: r for k, r in fine.items() if k in asked})
    return SweepResult(result.mechanism, table, _failure_frame(U, names, failures), result.q[rows],
                       result.v[rows], result.a[rows], measures, points, links)


def _left_branch(solver: LoopSolver, kernel: LoopKernel, Q: np.ndarray, U: np.ndarray, next_to: np.ndarray
                 ) -> bool:
    """Whether a step between consecutive solutions (rows of Q at inputs U; ``next_to[k]``: rows k and k + 1 are
    neighbouring samples) left its branch: the change of the dependent coordinates off the trapezoidal rule's
    ½ (S_k + S_k+1) Δu by more than :data:`batch.JUMP_RATIO` of it (the velocity maps S_d of every row by the
    kernel)."""
    if len(Q) < 2 or not next_to.any() or not len(solver.dep):
        return False
    converged, maps = kernel.newton(np.array(Q, dtype=float))
    dq = np.diff(Q[:, solver.dep], axis=0)
    du = np.diff(U, axis=0)
    predicted = 0.5 * np.einsum("kda,ka->kd", maps[1:] + maps[:-1], du)
    error = np.abs(dq - predicted).max(axis=1)
    bad = ~(error <= np.maximum(batch.JUMP_RATIO * np.abs(dq).max(axis=1), batch.JUMP_FLOOR))
    return bool((bad & next_to).any())


@dataclass
class _Layout:
    """The block of a driven sweep: its rows are the table's float columns in order (the inputs; q, v and a of
    every joint; the kernel's frame columns but the measures' other points; the measures), then max |J_d⁻¹| and
    the other points' positions. ``columns`` (pandas Index) names the table's columns, ``sample`` first; ``rows``
    the block row of each q_i and each output of the kernel (the driver's ``rows``); ``where`` the row of every
    column by name; ``reach`` the solver's :attr:`~mechatron.kinematics.loops.LoopSolver.max_step`."""

    columns: Any
    rows: np.ndarray
    where: dict[str, int]
    reach: np.ndarray

    def frame(self, table: np.ndarray, good: np.ndarray) -> pd.DataFrame:
        """The table: the samples ``good`` and the block's first rows as they are (one float block, no copy)."""
        import pandas as pd

        floats = table[:len(self.columns) - 1]
        try:
            from pandas.api.internals import create_dataframe_from_blocks
        except ImportError:  # pragma: no cover - pandas before 2.3
            frame = pd.DataFrame(floats.T, columns=self.columns[1:], copy=False)
            frame.insert(0, "sample", good)
            return frame
        return create_dataframe_from_blocks([(good[None, :], np.zeros(1, dtype=np.intp)),
                                             (floats, np.arange(1, len(self.columns)))],
                                            index=pd.RangeIndex(len(good)), columns=self.columns)


def _layout(solver: LoopSolver, kernel: LoopKernel, names: list[str], measures: list[Measure]) -> _Layout:
    """The :class:`_Layout` of a driven sweep of ``kernel`` with these inputs and measures (kept in the
    mechanism's cache)."""
    mech = solver.mech

    def build() -> _Layout:
        import pandas as pd

        nq, na = kernel.nq, len(names)
        columns = list(names)
        for joint in mech.joint_names:
            columns += [f"q_{joint}", f"v_{joint}", f"a_{joint}"]
        others = kernel.names[len(kernel.names) - 2 * len(kernel.others):]
        columns += [c for c in kernel.names if c not in others] + [m.name for m in measures]
        where = {name: row for row, name in enumerate([*columns, _RATIO, *others])}
        joints = na + 3 * np.arange(nq)
        rows = np.concatenate([joints, joints + 1, joints + 2, [where[_RATIO]], [where[c] for c in kernel.names]])
        return _Layout(pd.Index(["sample", *columns]), rows.astype(np.int64), where,
                       np.ascontiguousarray(solver.max_step, dtype=float))

    return mech.cached(("sweep_layout", id(kernel), tuple(names), tuple(m.name for m in measures)), build)


def _drive(solver: LoopSolver, run: compiled.DriverRun, failures: dict[int, str], progress: ProgressCallback | None,
           stop: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The positions of all samples into the run's table and motion: the driver's continuation chunk by chunk
    (:meth:`compiled.DriverRun.continuation`), each sample it leaves solved by the sequential continuation from the
    same history (:meth:`_Continuation.solve`, which records the failures; its Newton's method with halved steps
    by the driver too, :meth:`~mechatron.kinematics.compiled.LoopKernel.far`), and the driver on from there; with
    ``stop``, up to the first sample that fails. Returns which samples were solved and those solved here (not yet
    analysed)."""
    arrays = run.arrays
    U, table, rows, history, state, same, begin = (arrays[key] for key in ("U", "table", "rows", "history",
                                                                            "state", "same", "begin"))
    n, joints = len(U), rows[:len(begin)]
    ok, solved = np.zeros(n, dtype=bool), []
    continuation = _Continuation(solver, U, begin.copy(), failures, far=run.kernel)
    k = 0
    for part in batch.chunks(n, compiled.CHUNK):
        while k < part.stop:
            reached = run.continuation(k, part.stop)
            ok[k:reached] = True
            m = int(state[0])
            continuation.history = [history[i].copy() for i in range(m)]
            continuation.q = history[m - 1].copy() if m else continuation.q
            k = reached
            if k == part.stop:
                break
            solution = continuation.solve(k, bool(same[k]))
            if solution is not None:
                table[joints, k] = arrays["motion"][0, k] = solution[0]
                ok[k] = True
                solved.append(k)
            elif stop:
                return ok, np.array(solved, dtype=np.int64)
            m = len(continuation.history)
            if m:
                history[:m] = continuation.history
            state[:] = (m, 0)
            begin[:] = continuation.q
            k += 1
        if progress is not None:
            progress(part.stop, n)
    return ok, np.array(solved, dtype=np.int64)


def _finish_columns(table: np.ndarray, where: dict[str, int], links: list[str], measures: list[Measure]) -> None:
    """In the block of the good samples: the link angles unwrapped and the measures from the points' rows."""
    for link in links:
        row = where[f"{link}_angle"]
        table[row] = np.unwrap(table[row])
    for m in measures:
        table[where[m.name]] = measure_values(m, {p: np.stack([table[where[f"{p}_x"]], table[where[f"{p}_y"]]],
                                                              axis=1) for p in m.points})


def _failure_frame(U: np.ndarray, names: list[str], failures: dict[int, str]) -> pd.DataFrame:
    """One row per failed sample: ``sample``, its inputs, ``reason`` (without failures a copy of the empty one,
    built once)."""
    if not failures:
        return _no_failures(tuple(names)).copy()
    import pandas as pd

    rows = [{"sample": k, **{name: U[k, j] for j, name in enumerate(names)}, "reason": failures[k]}
            for k in sorted(failures)]
    return pd.DataFrame(rows, columns=["sample", *names, "reason"])


@functools.lru_cache(maxsize=64)
def _no_failures(names: tuple[str, ...]) -> pd.DataFrame:
    """The empty failures of a sweep of the inputs ``names`` (copied for each result)."""
    import pandas as pd

    return pd.DataFrame([], columns=["sample", *names, "reason"])


def _drop_singular(solver: LoopSolver, rows: np.ndarray, singular: np.ndarray, V: np.ndarray, Aq: np.ndarray,
                   columns: dict[str, np.ndarray], U: np.ndarray, failures: dict[int, str]):
    """The analysed ``rows`` without the ``singular`` ones, whose reason goes to ``failures``: (rows, V, q̈,
    columns)."""
    names = list(solver.mech.actuated)
    for k in rows[singular]:
        failures[int(k)] = _singular_reason(solver.mech, names, U[k])
    keep = ~singular
    if not keep.all():
        V, Aq = V[keep], Aq[keep]
        columns = {name: values[keep] for name, values in columns.items()}
    return rows[keep], V, Aq, columns


def _analyse_pinocchio(solver: LoopSolver, Q: np.ndarray, ok: np.ndarray, saved: tuple[np.ndarray, ...],
                       R: np.ndarray, A: np.ndarray, reported: list[int], wanted: list[str], points: list[str],
                       links: list[str], measures: list[Measure], U: np.ndarray, failures: dict[int, str]):
    """As :func:`_analyse_batched`, from the placements and Jacobians the continuation kept and Pinocchio's
    drifts per sample (the reference, and the path for joints the batched kinematics does not know)."""
    Jc, H, Jf = saved
    names = list(solver.mech.actuated)
    good = np.flatnonzero(ok)
    S, singular, inverse = _velocity_maps(solver, Jc[good])
    for k in good[singular]:
        failures[int(k)] = _singular_reason(solver.mech, names, U[k])
    good, S = good[~singular], S[~singular]
    inverse = None if inverse is None else inverse[~singular]
    V = np.einsum("kij,kj->ki", S, R[good])
    # J̇ q̇ and the frames' accelerations at q̈ = 0 from Pinocchio, then q̈ of all samples at once
    drift, accel0 = _drifts(solver, Q[good], V, H[good], Jf[good])
    Aq = _accelerations(solver, S, Jc[good], inverse, A[good], drift)
    Jw = Jf[good][:, reported]
    twist = np.einsum("kfij,kj->kfi", Jw, V)
    accel = accel0[:, reported] + np.einsum("kfij,kj->kfi", Jw, Aq)  # classical acceleration: at q̈ = 0 plus J q̈
    Hw = H[good][:, reported]
    angle = np.arctan2(Hw[..., 1, 0], Hw[..., 0, 0])
    return good, V, Aq, _frame_columns(solver.mech, Hw[..., :3, 3], angle, twist, accel, wanted, points, links,
                                       measures)


def _drifts(solver: LoopSolver, Q: np.ndarray, V: np.ndarray, H: np.ndarray, Jf: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """Closure drift J̇ q̇ and the frames' classical accelerations at q̈ = 0 of every sample."""
    system = solver.system
    states = system.states
    n = len(Q)
    accel0 = np.zeros((n, len(system.frame_names), 6))
    drift = np.zeros((n, system.nrows))
    for k in range(n):
        states.restore(H[k], Jf[k])
        drift[k] = system.drift(Q[k], V[k])
        accel0[k] = states.acceleration0
    return drift, accel0


def _reported(values: np.ndarray, reported: list[int]) -> np.ndarray:
    """The rows ``reported`` of the frames' axis (1) of ``values`` (N, F, ...), a copy."""
    return np.moveaxis(np.moveaxis(values, 0, -1)[reported], -1, 0)


def _frame_columns(mech: Mechanism, position: np.ndarray, angle: np.ndarray, twist: np.ndarray, accel: np.ndarray,
                   frame_names: list[str], points: list[str], links: list[str], measures: list[Measure]
                   ) -> dict[str, np.ndarray]:
    """The table columns of the reported frames (positions (n, F, 3), angles about z (n, F), twists and classical
    accelerations (n, F, 6)): points, links (the angle not yet unwrapped) and measures."""
    index = {name: j for j, name in enumerate(frame_names)}
    columns: dict[str, np.ndarray] = {}
    spatial = any(not getattr(c, "planar", True) for c in mech.closures)  # a spatial loop: z too
    axes = "xyz" if spatial else "xy"
    for p in points:
        j = index[p]
        for k, axis in enumerate(axes):
            columns[f"{p}_{axis}"] = position[:, j, k]
        for k, axis in enumerate(axes):
            columns[f"{p}_v{axis}"] = twist[:, j, k]
        columns[f"{p}_v"] = _norm(twist[:, j, :len(axes)])
        for k, axis in enumerate(axes):
            columns[f"{p}_a{axis}"] = accel[:, j, k]
        columns[f"{p}_a"] = _norm(accel[:, j, :len(axes)])
    for link in links:
        j = index[link]
        columns[f"{link}_angle"] = np.arctan2(np.sin(angle[:, j]), np.cos(angle[:, j]))  # in (−π, π], unwrapped later
        columns[f"{link}_omega"], columns[f"{link}_epsilon"] = twist[:, j, 5], accel[:, j, 5]
    for m in measures:
        columns[m.name] = measure_values(m, {p: position[:, index[p], :2] for p in m.points})
    return columns


def _norm(vectors: np.ndarray) -> np.ndarray:
    """The lengths of the rows of ``vectors`` (n, 2 or 3)."""
    return np.hypot(vectors[:, 0], vectors[:, 1]) if vectors.shape[1] == 2 else np.sqrt((vectors**2).sum(axis=1))


def _result(mech: Mechanism, U: np.ndarray, good: np.ndarray, Q: np.ndarray, V: np.ndarray, A: np.ndarray,
            frame_columns: dict[str, np.ndarray], links: list[str], measures: list[Measure],
            failures: dict[int, str], names: list[str], points: list[str]) -> SweepResult:
    """The table of the samples ``good`` (their q, v, a and the reported frames' :func:`_frame_columns`)."""
    import pandas as pd

    columns: dict[str, np.ndarray] = {"sample": good}
    for j, name in enumerate(names):
        columns[name] = U[good, j]
    for i, joint in enumerate(mech.joint_names):
        columns[f"q_{joint}"], columns[f"v_{joint}"], columns[f"a_{joint}"] = Q[:, i], V[:, i], A[:, i]
    for link in links:
        angle = frame_columns[f"{link}_angle"]
        angle[:] = np.unwrap(angle)
    columns.update(frame_columns)
    table = pd.DataFrame(columns, copy=False)  # pandas keeps the arrays as they are (one block each)
    return SweepResult(mech, table, _failure_frame(U, names, failures), Q, V, A, measures, points, links)

"""The result of a study: the table of designs × outputs, its Pareto front and Sobol indices."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..report.result import Result, frame_records

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..report.html import Report
    from .spec import StudySpec

#: mechatron's own tie rule of a Pareto front: each output is rounded to the nearest multiple of this fraction of
#: its largest magnitude, and equal rounded values tie: the rounding of the analyses that compute the outputs (a
#: sweep's Newton solutions, sums over samples) must not decide a design's place. Values more than one step apart
#: never tie; values less than a step apart tie unless they fall either side of a half step (docs/study_file.md,
#: "The Pareto front: ties").
PARETO_RESOLUTION = 1e-10


def _resolved(v: np.ndarray) -> np.ndarray:
    """``v`` rounded to the nearest multiple of h = :data:`PARETO_RESOLUTION` × max |v|: h · round(v / h)."""
    scale = float(np.abs(v).max(initial=0.0)) * PARETO_RESOLUTION
    return np.round(v / scale) * scale if scale > 0 else v


def pareto_mask(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Which points (x, y) are not dominated when both are minimised: no other point is at most as large in both
    and smaller in one, after each of x and y is rounded by :func:`_resolved` (values that round alike are equal:
    :data:`PARETO_RESOLUTION`). Sorted by x (then y), a point is on the front when its y is below every y before
    it (or it repeats the last point of the front)."""
    x, y = _resolved(np.asarray(x, dtype=float)), _resolved(np.asarray(y, dtype=float))
    order = np.lexsort((y, x))
    keep = np.zeros(len(x), dtype=bool)
    best, last = np.inf, None
    for i in order:
        if y[i] < best or (last is not None and x[i] == x[last] and y[i] == y[last]):
            keep[i] = True
            best, last = min(best, y[i]), i
    return keep


@dataclass
class StudyResult(Result):
    """A finished study (:func:`mechatron.studies.runner.run_study`).

    Attributes:
        spec: The study's spec.
        table: One row per design (sorted by ``design``): the parameters, ``seed``, ``status`` (``ok`` or
            ``failed``), ``reason`` and the analyses' outputs (SI; units in the names).
        out_dir: The study's folder.
        sensitivity: Sobol indices (:func:`mechatron.studies.sensitivity.sobol_indices`): each with its 95 %
            interval's half-width, the Saltelli blocks it used and whether the interval resolves it; or None.
        skipped: Outputs without indices → why.
        warnings: Plain sentences on the indices: outputs whose intervals are wider than their indices, outputs
            that vary only by numerical noise.
        blocks: N, the Saltelli blocks of the designs (of D + 2 designs each), with Sobol indices; else None.
    """

    spec: StudySpec
    table: pd.DataFrame
    out_dir: Path | None = None
    sensitivity: pd.DataFrame | None = None
    skipped: dict[str, str] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    blocks: int | None = None

    def sobol_lines(self) -> list[str]:
        """The report's lines on the Sobol indices: each output's largest total index with both indices' 95 %
        intervals (an output that varies only by noise is not ranked), the blocks used, the outputs without indices
        and the warnings."""
        lines = []
        frame = self.sensitivity
        if frame is not None and len(frame):
            used = sorted(set(int(b) for b in frame["blocks"]))
            warned = {w.split(":", 1)[0] for w in self.warnings}
            lines.append(f"Sobol indices from {_blocks_phrase(used, self.blocks or max(used))}; each output's "
                         "largest total index, ± the half-widths of the 95 % intervals:")
            top = frame.sort_values("ST", ascending=False, kind="stable").groupby("output", sort=False).head(1)
            for r in top.itertuples():
                count = f" [{r.blocks} blocks]" if len(used) > 1 else ""
                flag = " (not resolved: see the warning)" if r.output in warned else ""
                lines.append(f"  {r.output}: {r.parameter} S1 = {r.S1:.3f} ± {r.S1_conf:.3f}, ST = {r.ST:.3f} ± "
                             f"{r.ST_conf:.3f}{count}{flag}")
        for output, why in self.skipped.items():
            line = f"no Sobol indices of {output}: {why}"
            if line not in self.warnings:
                lines.append("  " + line)
        lines.extend(f"warning: {w}" for w in self.warnings)
        return lines

    @property
    def ok(self) -> pd.DataFrame:
        """The designs analysed without failure."""
        return self.table[self.table["status"] == "ok"]

    def outputs(self) -> list[str]:
        """The numeric output columns."""
        from .sensitivity import numeric_outputs

        return numeric_outputs(self.spec, self.table)

    def axes(self) -> tuple[str, str, str, str]:
        """(x, x goal, y, y goal) of the Pareto chart: the spec's, else the first two outputs (or the first
        parameter and the only output), both minimised."""
        if self.spec.pareto is not None:
            return self.spec.pareto
        import pandas as pd

        numeric = [p.name for p in self.spec.parameters if pd.api.types.is_numeric_dtype(self.table[p.name])]
        columns = [*self.outputs(), *numeric, "design", "design"]
        if len(self.outputs()) == 1 and numeric:  # the only output over the first parameter
            columns = [numeric[0], *columns]
        return columns[0], "minimize", columns[1], "minimize"

    def pareto(self, x: str | None = None, y: str | None = None, x_goal: str = "minimize",
               y_goal: str = "minimize") -> pd.DataFrame:
        """The non-dominated ok designs for the outputs ``x`` and ``y`` (default: :meth:`axes`), each minimised or
        maximised, sorted by ``x``; outputs that round alike to :data:`PARETO_RESOLUTION` of their largest
        magnitude tie (:func:`pareto_mask`)."""
        if x is None or y is None:
            x, x_goal, y, y_goal = self.axes()
        ok = self.ok
        values = []
        for column, goal, label in ((x, x_goal, "x"), (y, y_goal, "y")):
            if column not in self.table.columns:
                raise InputError(f"no column {column!r} in the study's table (columns: "
                                 f"{', '.join(self.table.columns)})", file=self.spec.file,
                                 field=f"output.pareto.{label}")
            values.append(ok[column].to_numpy(dtype=float) * (1.0 if goal == "minimize" else -1.0))
        finite = np.isfinite(values[0]) & np.isfinite(values[1])
        mask = np.zeros(len(ok), dtype=bool)
        mask[finite] = pareto_mask(values[0][finite], values[1][finite])
        return ok[mask].sort_values(x, kind="stable")

    # ------------------------------------------------------------------------------------------ the protocol
    def to_frame(self) -> pd.DataFrame:
        return self.table

    def as_dict(self) -> dict[str, Any]:
        x, x_goal, y, y_goal = self.axes()
        return {"spec": self.spec.file, "mechanism": self.spec.mechanism, "method": self.spec.method,
                "designs": len(self.table), "ok": len(self.ok), "failed": len(self.table) - len(self.ok),
                "out_dir": str(self.out_dir) if self.out_dir else None,
                "pareto": {"x": x, "x_goal": x_goal, "y": y, "y_goal": y_goal,
                           "designs": [int(d) for d in self.pareto()["design"]] if len(self.ok) else []},
                "sensitivity": frame_records(self.sensitivity) if self.sensitivity is not None else None,
                "sobol_blocks": self.blocks, "skipped": dict(self.skipped), "warnings": list(self.warnings),
                "rows": frame_records(self.table)}

    def plot(self, ax: Axes | None = None) -> Figure:
        """Every ok design in the plane of the two chosen outputs, the Pareto front highlighted."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax)
        x, x_goal, y, y_goal = self.axes()
        ok, front = self.ok, self.pareto()
        ax.scatter(ok[x], ok[y], s=12, color="0.6", label=f"ok designs ({len(ok)})")
        ax.plot(front[x], front[y], "o-", color="C3", label=f"Pareto front ({len(front)})")
        style_axes(ax, f"{self.axis_label(x)}, {x_goal}d", f"{self.axis_label(y)}, {y_goal}d",
                   f"{Path(self.spec.file).name}: {len(self.table)} designs", legend=True)
        return figure

    def report(self, mechanism: object = None, **context: Any) -> Report:
        """The HTML report (``mechatron study … --report FILE.html``): the text report; the Pareto front of the two
        chosen outputs (every design on it); the failed designs with their reasons; the Sobol indices, when the
        study has them; the chart of the designs in the plane of the two outputs; and every design's row."""
        from ..report.html import Chart, Code, Report, Section, Table

        x, x_goal, y, y_goal = self.axes()
        failed = self.table[self.table["status"] != "ok"]
        sections = [Section("Results", [Code(str(self))])]
        if len(self.ok):
            sections.append(Section("Pareto front", [
                Table(self.pareto(), f"the designs no other design beats in both {x} ({x_goal}d) and {y} "
                                     f"({y_goal}d)", "pareto"),
                Chart(self.plot(), f"every ok design in the plane of {x} and {y}, the Pareto front highlighted")]))
        if len(failed):
            sections.append(Section("Failed designs", [
                Table(failed[["design", *[p.name for p in self.spec.parameters], "reason"]],
                      "the designs an analysis could not evaluate, with the reason", "failed")]))
        if self.sensitivity is not None:
            sections.append(Section("Sensitivity", [
                Table(self.sensitivity, "Sobol indices with their 95 % intervals' half-widths", "sensitivity")]))
        sections.append(Section("Designs", [Table(self.table, "every design of the study (SI; units in the names)",
                                                  "designs")]))
        return Report(f"study {Path(self.spec.file).name}: {self.spec.mechanism}", sections,
                      f"{len(self.table)} designs, {len(self.ok)} ok, {len(failed)} failed")

    def axis_label(self, column: str) -> str:
        """The label of a plot axis for a column of the table: an output's is its quantity's
        (:func:`mechatron.quantities.axis_label`: ``reach (m)``); a parameter's is its name with its unit, that of
        the analysis option it targets or that of the mechanism's geometric parameter (m, rad); another column's is
        its name with the unit its name ends with, if any."""
        from ..quantities import axis_label, is_quantity, unit, unit_of

        parameter = next((p for p in self.spec.parameters if p.name == column), None)
        if parameter is None and is_quantity(column):
            return axis_label(column)
        if parameter is None:  # no quantity of the registry: the unit its name ends with, if any
            found = unit_of(column)
        elif parameter.target is not None:
            option = parameter.target.partition(".")[2]
            found = unit(option) if is_quantity(option) else "-"
        else:
            try:
                from .spec import study_mechanism

                found = study_mechanism(self.spec.mechanism).parameters[column].unit
            except Exception:  # noqa: BLE001 - the mechanism's files gone since the study: the name alone
                found = "-"
        return column if found == "-" else f"{column} ({found})"

    def __str__(self) -> str:
        failed = self.table[self.table["status"] != "ok"]
        lines = [f"study {Path(self.spec.file).name}: {self.spec.mechanism}, {len(self.table)} designs "
                 f"({self.spec.method}), {len(self.ok)} ok, {len(failed)} failed"]
        if len(failed):
            lines.append(f"  first failure: design {int(failed['design'].iloc[0])}: {failed['reason'].iloc[0]}")
        if len(self.ok):
            x, _, y, _ = self.axes()
            front = self.pareto()
            shown = [c for c in ["design", *[p.name for p in self.spec.parameters], x, y]
                     if c in front.columns]
            lines.append(f"Pareto front of {x} and {y} ({len(front)} designs; first 10):")
            lines.extend("  " + line for line in front[list(dict.fromkeys(shown))].head(10)
                         .to_string(index=False, float_format=lambda v: f"{v:.6g}").splitlines())
        lines.extend(self.sobol_lines())
        if self.out_dir is not None:
            lines.append(f"table: {self.out_dir / 'designs.parquet'} and designs.csv")
        return "\n".join(lines)


def _blocks_phrase(used: list[int], total: int) -> str:
    """How many of the ``total`` Saltelli blocks the outputs' indices used (``used``: the counts, one per output)."""
    if not used or min(used) == total:
        return f"{total} Saltelli blocks"
    if min(used) == max(used):
        return f"{used[0]} of {total} Saltelli blocks ({total - used[0]} left out: a failed design in each)"
    return (f"{min(used)} to {max(used)} of {total} Saltelli blocks (those with a failed design left out: each "
            "output's count in brackets)")


def study_result(spec: StudySpec, table: pd.DataFrame, out_dir: Path | None = None) -> StudyResult:
    """The result of a study's table: with its Sobol indices if the spec asks for them; the Pareto columns are
    checked (an error naming ``output.pareto.x`` or ``y`` lists the table's columns)."""
    sensitivity, skipped, notes, blocks = None, {}, [], None
    if spec.sensitivity:
        from .sensitivity import saltelli_blocks, sobol_indices

        sensitivity, skipped, notes = sobol_indices(spec, table)
        blocks = saltelli_blocks(spec, table)
    result = StudyResult(spec, table, out_dir, sensitivity, skipped, notes, blocks)
    if len(result.ok):
        result.pareto()
    return result

"""The result of ``mechatron optimize``, one type (:class:`OptimalResult`: ``feasible``, ``best``, ``front``,
``requirements``, ``notes``, ``solver``, ``evaluations``) in two forms, as its file has two: a design problem's
(:class:`DesignResult`: the best feasible design or the Pareto front, the requirements at the best design, every
design evaluated and the solver's summary) and a named problem's
(:class:`~mechatron.optimal.problems.result.OptimumResult`: the optimum, the start, the solver's convergence and
the DOE it is compared with). Each form keeps its own report and JSON keys."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..quantities import unit_of
from ..report.result import Result, json_ready
from .requirement import Requirement

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass(kw_only=True)
class OptimalResult(Result):
    """The result of :func:`mechatron.optimal.optimize`, both forms of its file (a design file's,
    :class:`DesignResult`; a named problem's, :class:`~mechatron.optimal.problems.result.OptimumResult`), besides the
    result protocol (``to_frame()``, ``as_dict()``, ``plot()``, ``str()``): the problem's ``name`` and
    ``mechanism``, the ``solver`` (a design file's: its summary, a dict; a named problem's: its name), the ``best``
    design (variables and outputs, SI; None where none is feasible), the Pareto ``front`` (two objectives; else
    None), the ``requirements`` at the best design, whether it is ``feasible``, every design ``evaluations`` judged
    (a table: the search's, or a named problem's DOE) and the ``notes``."""

    name: str
    mechanism: str
    solver: Any
    requirements: list[Requirement]
    best: dict[str, Any] | None = None
    front: pd.DataFrame | None = None
    evaluations: pd.DataFrame | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def feasible(self) -> bool:
        """A best design that meets every requirement."""
        return self.best is not None and all(r.met() for r in self.requirements)


def front_mask(values: np.ndarray) -> np.ndarray:
    """Which rows of (n, 2) objectives (both minimised) no other row dominates
    (:func:`mechatron.studies.result.pareto_mask`)."""
    from ..studies.result import pareto_mask

    return pareto_mask(values[:, 0], values[:, 1]) if len(values) else np.zeros(0, dtype=bool)


@dataclass(kw_only=True)
class DesignResult(OptimalResult):
    """An optimal design of a design file: the best feasible design evaluated (one objective) or the Pareto front
    of every feasible design evaluated (two), the requirements at the best design, every design evaluated
    (``evaluations``: the variables, ``status``, ``reason``, the outputs, ``feasible``) and the solver's summary."""

    objectives: tuple[tuple[str, str], ...]
    variables: tuple[str, ...]
    solver: dict[str, Any]
    evaluations: pd.DataFrame
    units: dict[str, str] = field(default_factory=dict)

    @property
    def failed(self) -> int:
        """The designs evaluated that failed (``status`` not ok: not assembled, or refused by an analysis)."""
        return int((self.evaluations["status"] != "ok").sum()) if "status" in self.evaluations else 0

    def to_frame(self) -> pd.DataFrame:
        """Two objectives: the front (its variables and outputs, one design a row, by the first objective). One:
        a row per variable, the objective and each requirement (value, limit, margin, met, verdict, unit:
        :attr:`Requirement.verdict`)."""
        import pandas as pd

        if self.front is not None:
            return self.front.reset_index(drop=True)
        if self.best is None:
            return pd.DataFrame(columns=["kind", "name", "value", "limit", "margin", "met", "verdict", "unit"])
        rows = [{"kind": "variable", "name": v, "value": self.best[v], "unit": self.units.get(v, "-")}
                for v in self.variables]
        name = self.objectives[0][0]
        rows.append({"kind": self.objectives[0][1], "name": name, "value": self.best[name], "unit": unit_of(name)})
        rows += [{"kind": f"requirement ({r.kind})", "name": r.name, "value": r.value, "limit": r.limit,
                  "margin": r.margin, "met": r.met(), "verdict": r.verdict, "unit": r.unit} for r in self.requirements]
        return pd.DataFrame(rows)

    def as_dict(self) -> dict:
        """name, mechanism, objectives, the variables' units, the best design (variables and outputs),
        requirements, feasible, solver, the count of designs evaluated and feasible, the front (two objectives)."""
        from ..report.result import frame_records

        feasible = int(self.evaluations["feasible"].sum()) if len(self.evaluations) else 0
        return json_ready({
            "name": self.name, "mechanism": self.mechanism,
            "objectives": [{"name": n, "goal": g, "unit": unit_of(n)} for n, g in self.objectives],
            "variables": {v: {"unit": self.units.get(v, "-")} for v in self.variables},
            "best": self.best,
            "requirements": [{"name": r.name, "kind": r.kind, "value": r.value, "limit": r.limit, "margin": r.margin,
                              "met": r.met(), "verdict": r.verdict, "unit": r.unit} for r in self.requirements],
            "feasible": self.feasible, "solver": self.solver,
            "evaluated": len(self.evaluations), "evaluated_feasible": feasible, "evaluated_failed": self.failed,
            "front": None if self.front is None else frame_records(self.front),
            "notes": self.notes})

    def plot(self, ax: Axes | None = None) -> Figure:
        """Two objectives: every design evaluated in the objectives' plane (feasible or not) and the front; one:
        the objective of every feasible design in the order evaluated and the best so far."""
        from ..quantities import axis_label
        from ..report.figures import new_figure, style_axes

        figure = new_figure(7.0, 5.0) if ax is None else cast("Figure", ax.get_figure())
        ax = ax if ax is not None else figure.subplots()
        table = self.evaluations
        ok = table["feasible"].to_numpy(dtype=bool) if len(table) else np.zeros(0, dtype=bool)
        if self.front is not None:
            (x, _), (y, _) = self.objectives
            ax.plot(table.loc[~ok, x], table.loc[~ok, y], "x", color="0.6", ms=4, label="requirement not met")
            ax.plot(table.loc[ok, x], table.loc[ok, y], "o", color="tab:blue", ms=3, label="feasible design")
            ax.plot(self.front[x], self.front[y], "o-", color="tab:red", ms=6, label="Pareto front")
            style_axes(ax, axis_label(x), axis_label(y), f"{self.name}: Pareto front", legend=True)
            return figure
        name, goal = self.objectives[0]
        values = table[name].to_numpy(dtype=float) if name in table else np.zeros(len(table))
        index = np.flatnonzero(ok)
        ax.plot(index + 1, values[index], "o", color="tab:blue", ms=3, label="feasible design")
        if len(index):
            best = np.minimum.accumulate(values[index]) if goal == "minimize" else \
                np.maximum.accumulate(values[index])
            ax.step(index + 1, best, where="post", color="tab:red", label="best so far")
        style_axes(ax, "designs evaluated (-)", axis_label(name), f"{self.name}: {goal} {name}", legend=True)
        return figure

    def __str__(self) -> str:
        lines = [f"{self.name} ({self.mechanism}): {self.solver['method']}, {self.solver['status']}; "
                 f"{len(self.evaluations)} designs evaluated, "
                 f"{int(self.evaluations['feasible'].sum()) if len(self.evaluations) else 0} feasible"
                 + (f", {self.failed} failed (not assembled or refused by an analysis: designs.csv's reason)"
                    if self.failed else "")]
        if self.solver.get("failed_trials"):
            first = next(iter(self.solver["failed_trial_reasons"]))
            lines.append(f"  {self.solver['failed_trials']} trial designs of ipopt's line search failed (skipped): "
                         f"{first}")
        if self.front is not None:
            (x, _), (y, _) = self.objectives
            lines.append(f"Pareto front of {x} and {y}: {len(self.front)} designs")
            lines.append("  " + "  ".join(f"{c:>14}" for c in (*self.variables, x, y)))
            for _, row in self.front.iterrows():
                lines.append("  " + "  ".join(_cell(row[c]) for c in (*self.variables, x, y)))
        if self.best is None:
            lines.append("NOT FEASIBLE: no design evaluated meets every requirement" + _why_all_failed(self))
            return "\n".join(lines + [f"note: {n}" for n in self.notes])
        if self.front is None:
            lines.append("best design: " + ", ".join(f"{v} = {_cell(self.best[v]).strip()}" for v in self.variables))
            name, goal = self.objectives[0]
            lines.append(f"  {goal} {name}: {self.best[name]:.6g} {unit_of(name)}")
        lines += [r.line(36) for r in self.requirements]
        if not self.feasible:
            lines.append("NOT FEASIBLE: " + ", ".join(r.name for r in self.requirements if not r.met()))
        return "\n".join(lines + [f"note: {n}" for n in self.notes])


def _why_all_failed(result: DesignResult) -> str:
    """Where every design evaluated failed: ``; none assembled or passed the analyses: REASON`` (the most common
    reason), else nothing."""
    table = result.evaluations
    if not len(table) or "status" not in table or result.failed < len(table) or "reason" not in table:
        return ""
    return f"; every design failed, most often: {table['reason'].astype(str).value_counts().index[0]}"


def _cell(value: Any) -> str:
    return f"{value:14.6g}" if isinstance(value, (int, float, np.floating)) else f"{Path(str(value)).name:>14}"

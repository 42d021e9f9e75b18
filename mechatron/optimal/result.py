"""The result of ``mechatron optimize``, one type (:class:`OptimalResult`) for both models of a
:class:`~mechatron.optimal.problem.Problem`.

Every result has the problem's ``name`` and ``mechanism``, its ``variables`` and ``objectives``, the ``units`` of both,
the ``solver``'s summary (a dict), the ``best`` design (variables and outputs, SI; None where none is feasible), the
Pareto ``front`` (two objectives; else None), the ``requirements`` at the best design, whether it is ``feasible``,
every design judged (``evaluations``: a table) and the ``notes``. A problem on the study analyses (a design file) is
reported as its search: the best design or the front, the designs evaluated, feasible and failed. A problem on an
exact CasADi model (a named problem) is reported as its comparison (:attr:`OptimalResult.compared`): the optimum
against the ``start`` and against the best of a DOE over the same box (``doe_*``), with the solver's convergence,
and for ``cylinder_mass`` the catalog cylinders chosen (``catalog_choice``) and the search's steps (``descent``).
Each keeps its own report and JSON keys (:meth:`OptimalResult.as_dict`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..quantities import unit_of
from ..report.result import Result, json_ready
from .requirement import Requirement, Vector

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def front_mask(values: np.ndarray) -> np.ndarray:
    """Which rows of (n, 2) objectives (both minimised) no other row dominates
    (:func:`mechatron.studies.result.pareto_mask`)."""
    from ..studies.result import pareto_mask

    return pareto_mask(values[:, 0], values[:, 1]) if len(values) else np.zeros(0, dtype=bool)


@dataclass(kw_only=True)
class OptimalResult(Result):
    """The result of :func:`mechatron.optimal.optimize` (see the module docstring), besides the result protocol
    (``to_frame()``, ``as_dict()``, ``plot()``, ``str()``).

    The comparison fields (an exact model's): ``title`` (the problem's), ``lower``, ``upper`` and ``start`` (the box
    and the start, SI), ``start_objective`` and ``start_requirements`` (the Pinocchio model's at the start), the DOE
    (``doe_method``, ``doe_points`` one row per design, ``doe_objective``, ``doe_feasible``) and its best feasible
    design the Pinocchio model confirms (``doe_best``: ``x``, ``objective``, ``met``; None without one), and for
    ``cylinder_mass`` per cylinder the catalog row the drives module chooses at the optimum (``catalog_choice``:
    key, count, bore, rod, stroke m, mass kg, its checks) and the steps of the search (``descent``: step, rows,
    mass kg). The solver's summary of an exact model: ``name``, ``success``, ``status``, ``iterations``,
    ``history`` (the objective at each iterate) and ``casadi_pinocchio_difference`` (the largest relative
    difference of the quantities between the CasADi expressions and the Pinocchio model at the optimum)."""

    name: str
    mechanism: str
    variables: tuple[str, ...]
    objectives: tuple[tuple[str, str], ...]
    solver: dict[str, Any]
    requirements: list[Requirement]
    evaluations: pd.DataFrame
    best: dict[str, Any] | None = None
    front: pd.DataFrame | None = None
    notes: list[str] = field(default_factory=list)
    units: dict[str, str] = field(default_factory=dict)
    title: str = ""
    lower: Vector | None = None
    upper: Vector | None = None
    start: Vector | None = None
    start_objective: float = math.nan
    start_requirements: list[Requirement] = field(default_factory=list)
    doe_method: str = ""
    doe_points: Vector | None = None
    doe_objective: Vector | None = None
    doe_feasible: Any = None
    doe_best: dict[str, Any] | None = None
    catalog_choice: list[dict[str, Any]] | None = None
    descent: list[dict[str, Any]] | None = None

    # ------------------------------------------------------------------------------------------ both forms
    @property
    def compared(self) -> bool:
        """The exact model's form: the optimum compared with the start and a DOE (else a search's)."""
        return self.doe_points is not None

    @property
    def feasible(self) -> bool:
        """A best design that meets every requirement (and every catalog cylinder chosen passing its checks,
        ``cylinder_mass``)."""
        return (self.best is not None and all(r.met() for r in self.requirements)
                and all(c["feasible"] for c in self.catalog_choice or []))

    @property
    def objective_name(self) -> str:
        """The (first) objective's name."""
        return self.objectives[0][0]

    @property
    def objective_unit(self) -> str:
        """The (first) objective's unit."""
        return self.units.get(self.objective_name) or unit_of(self.objective_name)

    @property
    def objective(self) -> float:
        """The (first) objective at the best design (NaN without one)."""
        return math.nan if self.best is None else self.best[self.objective_name]

    @property
    def x(self) -> Vector:
        """The variables' values at the best design (SI; empty without one)."""
        return np.array([] if self.best is None else [self.best[v] for v in self.variables])

    @property
    def success(self) -> bool:
        """The solver reports success (an exact model's solver; a search's reports its status only)."""
        return bool(self.solver.get("success", False))

    @property
    def model_difference(self) -> float:
        """An exact model's largest relative difference between its CasADi expressions and the Pinocchio model at
        the optimum (NaN for a search)."""
        return float(self.solver.get("casadi_pinocchio_difference", math.nan))

    @property
    def beats_doe(self) -> bool | None:
        """The optimum is at least as good as the DOE's best feasible design (None without one)."""
        if self.doe_best is None:
            return None
        return bool(self.objective <= self.doe_best["objective"] + 1e-9 * max(1.0, abs(self.doe_best["objective"])))

    @property
    def failed(self) -> int:
        """The designs evaluated that failed (``status`` not ok: not assembled, or refused by an analysis)."""
        return int((self.evaluations["status"] != "ok").sum()) if "status" in self.evaluations else 0

    def to_frame(self) -> pd.DataFrame:
        """A search's: two objectives: the front (its variables and outputs, one design a row, by the first
        objective); one: a row per variable, the objective and each requirement (value, limit, margin, met,
        verdict, unit: :attr:`Requirement.verdict`). An exact model's: one row per design variable (m), the
        objective and each requirement: the optimum, the start and the DOE's best, bounds or limit, the margin,
        ``met``, ``verdict`` and the unit; for ``cylinder_mass`` also one row per cylinder: its catalog row and
        count (name), mass (kg) and whether it passes the drives module's checks."""
        return self._compared_frame() if self.compared else self._search_frame()

    def as_dict(self) -> dict:
        """A search's: name, mechanism, objectives, the variables' units, the best design (variables and outputs),
        requirements, feasible, solver, the count of designs evaluated and feasible, the front (two objectives).
        An exact model's: name, mechanism, variables (optimum, start, bounds), objective, requirements, solver,
        DOE."""
        return json_ready(self._compared_dict() if self.compared else self._search_dict())

    def plot(self, ax: Axes | None = None) -> Figure:
        """A search's: two objectives: every design evaluated in the objectives' plane (feasible or not) and the
        front; one: the objective of every feasible design in the order evaluated and the best so far. An exact
        model's: the DOE points in the plane of the first two design variables (m; with one variable, the
        objective over it), feasible or not, with the DOE's best, the start and the optimum marked; with no ``ax``
        also the objective at each solver iteration."""
        return self._compared_plot(ax) if self.compared else self._search_plot(ax)

    def __str__(self) -> str:
        return self._compared_text() if self.compared else self._search_text()

    # ------------------------------------------------------------------------------------------ a search's
    def _search_frame(self) -> pd.DataFrame:
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

    def _search_dict(self) -> dict:
        from ..report.result import frame_records

        feasible = int(self.evaluations["feasible"].sum()) if len(self.evaluations) else 0
        return {
            "name": self.name, "mechanism": self.mechanism,
            "objectives": [{"name": n, "goal": g, "unit": unit_of(n)} for n, g in self.objectives],
            "variables": {v: {"unit": self.units.get(v, "-")} for v in self.variables},
            "best": self.best,
            "requirements": [{"name": r.name, "kind": r.kind, "value": r.value, "limit": r.limit, "margin": r.margin,
                              "met": r.met(), "verdict": r.verdict, "unit": r.unit} for r in self.requirements],
            "feasible": self.feasible, "solver": self.solver,
            "evaluated": len(self.evaluations), "evaluated_feasible": feasible, "evaluated_failed": self.failed,
            "front": None if self.front is None else frame_records(self.front),
            "notes": self.notes}

    def _search_plot(self, ax: Axes | None) -> Figure:
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

    def _search_text(self) -> str:
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
            lines.append("NOT FEASIBLE: no design evaluated meets every requirement" + self._why_all_failed())
            return "\n".join(lines + [f"note: {n}" for n in self.notes])
        if self.front is None:
            lines.append("best design: " + ", ".join(f"{v} = {_cell(self.best[v]).strip()}" for v in self.variables))
            name, goal = self.objectives[0]
            lines.append(f"  {goal} {name}: {self.best[name]:.6g} {unit_of(name)}")
        lines += [r.line(36) for r in self.requirements]
        if not self.feasible:
            lines.append("NOT FEASIBLE: " + ", ".join(r.name for r in self.requirements if not r.met()))
        return "\n".join(lines + [f"note: {n}" for n in self.notes])

    def _why_all_failed(self) -> str:
        """Where every design evaluated failed: ``; every design failed, most often: REASON`` (the most common
        reason), else nothing."""
        table = self.evaluations
        if not len(table) or "status" not in table or self.failed < len(table) or "reason" not in table:
            return ""
        return f"; every design failed, most often: {table['reason'].astype(str).value_counts().index[0]}"

    # ------------------------------------------------------------------------------------------ an exact model's
    def _box(self) -> tuple[Vector, Vector, Vector]:
        """(lower, upper, start) of the comparison form."""
        assert self.lower is not None and self.upper is not None and self.start is not None
        return self.lower, self.upper, self.start

    def _doe(self) -> tuple[Vector, Vector, Any]:
        """(points, objective, feasible) of the comparison form's DOE."""
        assert self.doe_points is not None and self.doe_objective is not None
        return self.doe_points, self.doe_objective, self.doe_feasible

    def _compared_frame(self) -> pd.DataFrame:
        import pandas as pd

        lower, upper, start = self._box()
        best = self.doe_best["x"] if self.doe_best else [math.nan] * len(self.variables)
        rows = [{"kind": "variable", "name": v, "optimum": x, "start": s, "doe_best": b, "lower": lo, "upper": hi,
                 "unit": "m"} for v, x, s, b, lo, hi in zip(self.variables, self.x, start, best, lower, upper)]
        rows.append({"kind": "objective", "name": self.objective_name, "optimum": self.objective,
                     "start": self.start_objective,
                     "doe_best": self.doe_best["objective"] if self.doe_best else math.nan,
                     "unit": self.objective_unit})
        for r, s in zip(self.requirements, self.start_requirements):
            rows.append({"kind": "requirement", "name": r.name, "optimum": r.value, "start": s.value,
                         "limit": r.limit, "margin": r.margin, "met": r.met(), "verdict": r.verdict,
                         "unit": r.unit})
        for c in self.catalog_choice or []:
            rows.append({"kind": "cylinder", "name": f"{c['cylinder']} {c['key']} x{c['count']}",
                         "optimum": c["mass"], "met": c["feasible"], "unit": "kg"})
        return pd.DataFrame(rows)

    def _compared_dict(self) -> dict:
        lower, upper, start = self._box()
        points, _, feasible = self._doe()
        return {
            "name": self.name, "mechanism": self.mechanism, "problem": self.title,
            "variables": {v: {"optimum": x, "start": s, "lower": lo, "upper": hi}
                          for v, x, s, lo, hi in zip(self.variables, self.x, start, lower, upper)},
            "objective": {"name": self.objective_name, "unit": self.objective_unit, "optimum": self.objective,
                          "start": self.start_objective},
            "requirements": [{"name": r.name, "value": r.value, "limit": r.limit, "kind": r.kind, "unit": r.unit,
                              "margin": r.margin, "met": r.met(), "verdict": r.verdict} for r in self.requirements],
            "feasible": self.feasible,
            "solver": self.solver,
            "doe": {"method": self.doe_method, "points": len(points), "feasible": int(np.count_nonzero(feasible)),
                    "best": None if self.doe_best is None else {
                        "variables": dict(zip(self.variables, self.doe_best["x"])),
                        "objective": self.doe_best["objective"], "met": self.doe_best["met"]},
                    "optimum_at_least_as_good": self.beats_doe},
            **({} if self.catalog_choice is None else {"cylinders": self.catalog_choice, "descent": self.descent}),
            "notes": self.notes,
        }

    def _compared_plot(self, ax: Axes | None) -> Figure:
        from ..report.figures import new_figure, style_axes

        history = self.solver["history"]
        if ax is None:
            figure = new_figure(12.0, 5.0)
            ax, convergence = figure.subplots(1, 2)
            steps = np.arange(len(history))
            convergence.plot(steps, history, "o-", color="tab:blue", ms=3, label="ipopt iterate")
            if all(h > 0 for h in history):
                convergence.set_yscale("log")
            style_axes(convergence, "iteration (-)", f"{self.objective_name} ({self.objective_unit})",
                       "convergence", legend=True)
        else:
            figure = cast("Figure", ax.get_figure())
        X, values, feasible = self._doe()
        ok = np.asarray(feasible, dtype=bool)
        two = len(self.variables) >= 2

        def y(points: Vector, objective: Any) -> Any:
            return points[:, 1] if two else objective

        ax.plot(X[~ok, 0], y(X[~ok], values[~ok]), "x", color="0.6", ms=4,
                label=f"DOE ({self.doe_method}), requirement not met")
        ax.plot(X[ok, 0], y(X[ok], values[ok]), "o", color="tab:blue", ms=3,
                label=f"DOE ({self.doe_method}), feasible")
        if self.doe_best is not None:
            b = np.atleast_2d(self.doe_best["x"])
            ax.plot(b[:, 0], y(b, [self.doe_best["objective"]]), "s", color="tab:orange", ms=8,
                    label=f"DOE best: {self.doe_best['objective']:.5g} {self.objective_unit}")
        s, o = np.atleast_2d(self._box()[2]), np.atleast_2d(self.x)
        ax.plot(s[:, 0], y(s, [self.start_objective]), "k^", ms=8, label="start")
        ax.plot(o[:, 0], y(o, [self.objective]), "*", color="tab:red", ms=14,
                label=f"optimum: {self.objective:.5g} {self.objective_unit}")
        ylabel = f"{self.variables[1]} (m)" if two else f"{self.objective_name} ({self.objective_unit})"
        style_axes(ax, f"{self.variables[0]} (m)", ylabel, self.title, legend=True, fontsize=8)
        return figure

    def _compared_text(self) -> str:
        lower, upper, start = self._box()
        points, _, feasible = self._doe()
        solver = self.solver
        lines = [f"{self.name}: {self.title} ({self.mechanism})",
                 f"{solver['name']}: {solver['status']} after {solver['iterations']} iterations; CasADi vs "
                 f"Pinocchio at the optimum: {self.model_difference:.2g} (largest relative difference)",
                 f"{'variable':<12}{'optimum':>14}{'start':>12}{'lower':>10}{'upper':>10}  (m)"]
        for v, x, s, lo, hi in zip(self.variables, self.x, start, lower, upper):
            lines.append(f"{v:<12}{x:14.9f}{s:12.6f}{lo:10.4g}{hi:10.4g}")
        lines.append(f"objective {self.objective_name}: {self.objective:.6g} {self.objective_unit} at the optimum, "
                     f"{self.start_objective:.6g} at the start (Pinocchio model)")
        lines += [r.line(42) for r in self.requirements]
        for c in self.catalog_choice or []:
            lines.append(f"  {c['cylinder']}: {c['count']}× {c['key']} (bore {c['bore'] * 1e3:g} mm, rod "
                         f"{c['rod'] * 1e3:g} mm), stroke {c['stroke']:.4f} m, {c['mass']:.2f} kg; "
                         "margins 1 − value/limit: "
                         + ", ".join(f"{x['name']} margin {x['margin']:.3g}" for x in c["checks"])
                         + ("" if c["feasible"] else " NOT FEASIBLE"))
        for step in self.descent or []:
            rows = ", ".join(f"{k} {v}" for k, v in step["rows"].items())
            lines.append(f"  search: {step['step']:<12} {rows}: {step['mass']:.2f} kg")
        count = int(np.count_nonzero(feasible))
        if self.doe_best is None:
            lines.append(f"DOE: {len(points)} {self.doe_method} points, none meets every requirement")
        else:
            best = ", ".join(f"{v} = {x:.6g}" for v, x in zip(self.variables, self.doe_best["x"]))
            lines.append(f"DOE: {len(points)} {self.doe_method} points, {count} feasible; best {best}: "
                         f"{self.doe_best['objective']:.6g} {self.objective_unit}; the optimum is "
                         f"{'at least as good' if self.beats_doe else 'WORSE'}")
        if not self.feasible:
            unmet = [r.name for r in self.requirements if not r.met()]
            unmet += [f"{c['cylinder']} {c['key']}" for c in self.catalog_choice or [] if not c["feasible"]]
            lines.append(f"NOT FEASIBLE: not met at the optimum: {', '.join(unmet)}")
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)


def _cell(value: Any) -> str:
    return f"{value:14.6g}" if isinstance(value, (int, float, np.floating)) else f"{Path(str(value)).name:>14}"

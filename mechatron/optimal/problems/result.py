"""The result of a named problem (:mod:`mechatron.optimal.problems.named`), the named form of the one result type
(:class:`~mechatron.optimal.result.OptimalResult`): the optimum, the start, the solver's convergence and the DOE it
is compared with."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ...report.result import json_ready
from ..requirement import Requirement, Vector
from ..result import OptimalResult

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass(kw_only=True)
class OptimumResult(OptimalResult):
    """An optimal design: the optimum x (SI units) and its objective and requirements from the Pinocchio model, the
    start's, the solver's status and convergence history, the largest relative difference between the CasADi
    expressions and the Pinocchio model at the optimum, and the DOE (points, objective, feasibility, its best). For
    ``cylinder_mass``: ``catalog_choice``, per cylinder the catalog row the drives module chooses at the optimum
    (key, count, bore, rod, stroke m, mass kg, its checks), and ``descent``, the steps of the search (step, rows,
    mass kg)."""

    title: str
    solver: str
    variables: tuple[str, ...]
    lower: Vector
    upper: Vector
    start: Vector
    x: Vector
    objective_name: str
    objective_unit: str
    objective: float
    start_objective: float
    start_requirements: list[Requirement]
    success: bool
    status: str
    iterations: int
    history: list[float]
    model_difference: float
    doe_method: str
    doe_points: Vector
    doe_objective: Vector
    doe_feasible: Any
    doe_best: dict[str, Any] | None
    catalog_choice: list[dict[str, Any]] | None = None
    descent: list[dict[str, Any]] | None = None

    def __post_init__(self) -> None:
        """The optimum as :attr:`best` (each variable's value, m, and the objective's, :attr:`objective_unit`:
        the Pinocchio model's) and the DOE as :attr:`evaluations` (the variables, the objective, ``feasible``)."""
        import pandas as pd

        self.best = {**dict(zip(self.variables, (float(v) for v in self.x))), self.objective_name: self.objective}
        table = pd.DataFrame(np.asarray(self.doe_points, dtype=float).reshape(-1, len(self.variables)),
                             columns=list(self.variables))
        table[self.objective_name] = self.doe_objective
        table["feasible"] = np.asarray(self.doe_feasible, dtype=bool)
        self.evaluations = table

    @property
    def feasible(self) -> bool:
        """Every requirement met at the optimum (Pinocchio model), and every catalog cylinder chosen passing its
        checks (``cylinder_mass``)."""
        return all(r.met() for r in self.requirements) and all(c["feasible"] for c in self.catalog_choice or [])

    @property
    def beats_doe(self) -> bool | None:
        """The optimum is at least as good as the DOE's best feasible design (None without one)."""
        if self.doe_best is None:
            return None
        return bool(self.objective <= self.doe_best["objective"] + 1e-9 * max(1.0, abs(self.doe_best["objective"])))

    def to_frame(self) -> pd.DataFrame:
        """One row per design variable (m), the objective and each requirement: the optimum, the start and the DOE's
        best, bounds or limit, the margin (≥ 0 when met), ``met`` and ``verdict`` (:attr:`Requirement.verdict`: met,
        met within slack, NOT MET) and the unit; for ``cylinder_mass`` also one row per
        cylinder: its catalog row and count (name), mass (kg) and whether it passes the drives module's checks."""
        import pandas as pd

        best = self.doe_best["x"] if self.doe_best else [math.nan] * len(self.variables)
        rows = [{"kind": "variable", "name": v, "optimum": x, "start": s, "doe_best": b, "lower": lo, "upper": hi,
                 "unit": "m"} for v, x, s, b, lo, hi in zip(self.variables, self.x, self.start, best, self.lower,
                                                            self.upper)]
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

    def as_dict(self) -> dict:
        """name, mechanism, variables (optimum, start, bounds), objective, requirements, solver, DOE."""
        return json_ready({
            "name": self.name, "mechanism": self.mechanism, "problem": self.title,
            "variables": {v: {"optimum": x, "start": s, "lower": lo, "upper": hi}
                          for v, x, s, lo, hi in zip(self.variables, self.x, self.start, self.lower, self.upper)},
            "objective": {"name": self.objective_name, "unit": self.objective_unit, "optimum": self.objective,
                          "start": self.start_objective},
            "requirements": [{"name": r.name, "value": r.value, "limit": r.limit, "kind": r.kind, "unit": r.unit,
                              "margin": r.margin, "met": r.met(), "verdict": r.verdict} for r in self.requirements],
            "feasible": self.feasible,
            "solver": {"name": self.solver, "success": self.success, "status": self.status,
                       "iterations": self.iterations, "history": self.history,
                       "casadi_pinocchio_difference": self.model_difference},
            "doe": {"method": self.doe_method, "points": len(self.doe_points),
                    "feasible": int(np.count_nonzero(self.doe_feasible)),
                    "best": None if self.doe_best is None else {
                        "variables": dict(zip(self.variables, self.doe_best["x"])),
                        "objective": self.doe_best["objective"], "met": self.doe_best["met"]},
                    "optimum_at_least_as_good": self.beats_doe},
            **({} if self.catalog_choice is None else {"cylinders": self.catalog_choice, "descent": self.descent}),
            "notes": self.notes,
        })

    def plot(self, ax: Axes | None = None) -> Figure:
        """The DOE points in the plane of the first two design variables (m; with one variable, the objective over
        it), feasible or not, with the DOE's best, the start and the optimum marked; with no ``ax`` also the
        objective at each solver iteration."""
        from ...report.figures import new_figure, style_axes

        if ax is None:
            figure = new_figure(12.0, 5.0)
            ax, convergence = figure.subplots(1, 2)
            steps = np.arange(len(self.history))
            convergence.plot(steps, self.history, "o-", color="tab:blue", ms=3, label="ipopt iterate")
            if all(h > 0 for h in self.history):
                convergence.set_yscale("log")
            style_axes(convergence, "iteration (-)", f"{self.objective_name} ({self.objective_unit})",
                       "convergence", legend=True)
        else:
            figure = cast("Figure", ax.get_figure())
        X, ok = self.doe_points, np.asarray(self.doe_feasible, dtype=bool)
        two = len(self.variables) >= 2

        def y(points: Vector, values: Any) -> Any:
            return points[:, 1] if two else values

        ax.plot(X[~ok, 0], y(X[~ok], self.doe_objective[~ok]), "x", color="0.6", ms=4,
                label=f"DOE ({self.doe_method}), requirement not met")
        ax.plot(X[ok, 0], y(X[ok], self.doe_objective[ok]), "o", color="tab:blue", ms=3,
                label=f"DOE ({self.doe_method}), feasible")
        if self.doe_best is not None:
            b = np.atleast_2d(self.doe_best["x"])
            ax.plot(b[:, 0], y(b, [self.doe_best["objective"]]), "s", color="tab:orange", ms=8,
                    label=f"DOE best: {self.doe_best['objective']:.5g} {self.objective_unit}")
        s, o = np.atleast_2d(self.start), np.atleast_2d(self.x)
        ax.plot(s[:, 0], y(s, [self.start_objective]), "k^", ms=8, label="start")
        ax.plot(o[:, 0], y(o, [self.objective]), "*", color="tab:red", ms=14,
                label=f"optimum: {self.objective:.5g} {self.objective_unit}")
        ylabel = f"{self.variables[1]} (m)" if two else f"{self.objective_name} ({self.objective_unit})"
        style_axes(ax, f"{self.variables[0]} (m)", ylabel, self.title, legend=True, fontsize=8)
        return figure

    def __str__(self) -> str:
        lines = [f"{self.name}: {self.title} ({self.mechanism})",
                 f"{self.solver}: {self.status} after {self.iterations} iterations; CasADi vs Pinocchio at the "
                 f"optimum: {self.model_difference:.2g} (largest relative difference)",
                 f"{'variable':<12}{'optimum':>14}{'start':>12}{'lower':>10}{'upper':>10}  (m)"]
        for v, x, s, lo, hi in zip(self.variables, self.x, self.start, self.lower, self.upper):
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
        feasible = int(np.count_nonzero(self.doe_feasible))
        if self.doe_best is None:
            lines.append(f"DOE: {len(self.doe_points)} {self.doe_method} points, none meets every requirement")
        else:
            best = ", ".join(f"{v} = {x:.6g}" for v, x in zip(self.variables, self.doe_best["x"]))
            lines.append(f"DOE: {len(self.doe_points)} {self.doe_method} points, {feasible} feasible; best {best}: "
                         f"{self.doe_best['objective']:.6g} {self.objective_unit}; the optimum is "
                         f"{'at least as good' if self.beats_doe else 'WORSE'}")
        if not self.feasible:
            unmet = [r.name for r in self.requirements if not r.met()]
            unmet += [f"{c['cylinder']} {c['key']}" for c in self.catalog_choice or [] if not c["feasible"]]
            lines.append(f"NOT FEASIBLE: not met at the optimum: {', '.join(unmet)}")
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)

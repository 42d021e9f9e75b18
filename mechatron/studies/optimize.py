r"""Optimal design with CasADi: ``mechatron optimize SPEC.toml`` and :func:`optimize`.

A spec (docs/optimize_file.md) names a mechanism, the design variables (named parameters with bounds), the
objective and the requirements. :func:`read_spec` checks it (one-line errors naming the file and field) and builds
the problem (:mod:`~mechatron.studies.optimal_bucket`: the bucket synthesis [Bucket] as the bucket angle error;
:mod:`~mechatron.studies.optimal_shovel`: the front shovel [Shovel] with the least largest cylinder force;
:mod:`~mechatron.studies.optimal_mass`: the same with the lightest catalog cylinders, a discrete choice solved by
DOE-then-refine);
:func:`optimize` solves it with ``casadi.nlpsol("ipopt")`` on SX expressions of the loop equations
(:mod:`~mechatron.studies.optimal_solve`), evaluates the optimum with the Pinocchio model, and compares it with the
best of a DOE (scrambled Sobol or Latin-hypercube points of the same box; the best feasible point by the CasADi
expressions that the Pinocchio model confirms, of the ten best). The :class:`OptimumResult` follows the result
protocol; ``mechatron optimize`` exits 1 when a requirement is not met at the optimum (:attr:`OptimumResult.feasible`).

The DOE has at most :data:`MAX_DOE_POINTS` points, a power of two for Sobol points (their balance needs it). A
warning of a library while solving (NumPy, SciPy, CasADi) becomes one of the result's ``notes``, never a raw message
on stderr.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, MechatronError, MechatronWarning
from ..report.result import Result, json_ready
from .optimal_problem import OptimalDesignProblem, Requirement, Vector

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DEG = math.pi / 180
OBJECTIVES = ("bucket_angle_error", "max_cylinder_force", "positioning_error", "cylinder_mass")
WORKING_RANGE = ("max_digging_radius", "max_digging_height", "max_digging_depth", "min_digging_radius")
#: The most DOE points: each is judged in turn in one process (about a millisecond each: 2^20 take minutes).
MAX_DOE_POINTS = 2 ** 20


@dataclass
class Spec:
    """A read optimisation spec: the problem and the options of the solver and of the DOE."""

    name: str
    problem: OptimalDesignProblem
    path: Path | None = None
    method: str = "ipopt"
    max_iterations: int = 200
    tolerance: float = 1e-12
    doe_points: int = 256
    doe_method: str = "sobol"
    seed: int = 0


def _mechanism(reader: Any, folder: Path) -> Any:
    """The spec's mechanism, by the study files' loader and path rule (:func:`mechatron.studies.spec._mechanism`:
    a file relative to the spec's folder, else a shipped name; loaded once per process and content)."""
    from .spec import _mechanism as study_mechanism

    return study_mechanism(reader, folder)[1]


def _bounds(reader: Any, mech: Any, known: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """``[variables]`` read as a design file's (:func:`~mechatron.studies.design_spec.read_variables`), only the
    named problem's ``known`` ones, as ranges: name → (lower, upper) (m)."""
    from .design_spec import read_variables

    variables = read_variables(reader, mech, {}, Path(reader.file or ".").resolve().parent, known)
    return {p.name: (p.low, p.high) for p in variables}


def _start(reader: Any, bounds: dict[str, tuple[float, float]]) -> dict[str, float]:
    """``[start]`` read as a design file's (:func:`~mechatron.studies.design_spec.read_start`)."""
    from .design_spec import read_start
    from .spec import Parameter

    return read_start(reader, [Parameter(name, low, high) for name, (low, high) in bounds.items()])


def _data_file(table: Any, key: str, folder: Path) -> Path:
    """A file named in ``key`` of ``table`` (:func:`~mechatron.studies.spec.file_field`: relative to the spec's
    folder)."""
    from .spec import file_field

    return file_field(table, key, folder)


def _positioning_problem(reader: Any, objective: Any, requirements: Any, mech: Any, folder: Path
                         ) -> OptimalDesignProblem:
    """The positioning-error problem of a spec (:mod:`~mechatron.studies.optimal_accuracy`)."""
    from ..accuracy.sources import read_poses, read_tolerances
    from .optimal_accuracy import PositioningProblem, length_parameters

    if mech.dh is None:
        raise objective.error("type", f"{mech.name} is not a DH arm: positioning_error needs a robot file's DH table")
    bounds = _bounds(reader, mech, length_parameters(mech))
    start = _start(reader, bounds)
    tolerances = _data_file(objective, "tolerances", folder)
    sources = read_tolerances(tolerances, mech)
    _no_graded_variables(tolerances, bounds)
    poses, labels = read_poses(_data_file(objective, "poses", folder), mech)
    reach = requirements.number("min_reach", None, positive=True)
    pose = requirements.vector("reach_pose_deg", len(mech.dh.links), None)
    if (reach is None) != (pose is None):
        raise requirements.error("min_reach" if reach is None else "reach_pose_deg",
                                 "give min_reach (m) and reach_pose_deg (the joint coordinates where it holds) "
                                 "together")
    objective.finish()
    requirements.finish()
    try:
        return PositioningProblem(mech, bounds, start, sources=sources, poses=poses, labels=labels, min_reach=reach,
                                  reach_pose=None if pose is None else _coordinates(mech, pose))
    except InputError as exc:
        raise objective.error("tolerances", exc.message) from None


def _no_graded_variables(path: Path, bounds: dict[str, tuple[float, float]]) -> None:
    """Refuse a design variable whose tolerance is a grade: an IT grade's tolerance steps with the nominal length
    [ISO 286-1], which the solver's derivatives cannot follow."""
    from ..io.tables import read_csv

    frame = read_csv(path)
    if "grade" not in frame.columns:
        return
    for i, row in zip(frame.index, frame.to_dict(orient="records")):
        if row["grade"] and row["parameter"] in bounds:
            raise InputError(f"{row['parameter']} is a design variable: give its tolerance in a tolerance column "
                             f"(tolerance_mm, …), not as {row['grade']}, whose tolerance steps with the length",
                             file=path, row=i, field="grade")


def _coordinates(mech: Any, values_deg: Vector) -> Vector:
    """Joint coordinates from a list in degrees for revolute joints and metres for prismatic ones."""
    return np.array([v * DEG if link.is_revolute else v for v, link in zip(values_deg, mech.dh.links)])


def read_spec(path: str | Path) -> Spec:
    """Read and check an optimisation spec (TOML, docs/optimize_file.md) and build its problem.

    Raises:
        InputError: naming the file and the field for a bad spec.
    """
    from ..io.schema import FieldReader
    from ..io.toml import read_toml
    from .optimal_bucket import VARIABLES as BUCKET_VARIABLES
    from .optimal_bucket import BucketProblem
    from .optimal_shovel import CYLINDERS, ShovelProblem
    from .optimal_shovel import VARIABLES as SHOVEL_VARIABLES

    path = Path(path)
    reader = FieldReader(read_toml(path), file=path)
    name = reader.string("name", path.stem)
    reader.string("description", "")
    mech = _mechanism(reader, path.parent)
    objective = reader.table("objective")
    kind = objective.string("type", choices=OBJECTIVES)
    requirements = reader.table("requirements", None) or FieldReader({}, file=path, path="requirements")
    if kind == "bucket_angle_error":
        if list(mech.cylinders) != ["L1"] or not {"c", "L2", "A_x", "D_x", "F_x", "E_x"} <= set(mech.parameters):
            raise objective.error("type", f"{mech.name} is not a six-link bucket mechanism [Bucket] (a cylinder L1, "
                                          "points D, F, A, B, C, E, lengths c, L2)")
        bounds = _bounds(reader, mech, BUCKET_VARIABLES)
        start = _start(reader, bounds)
        options = dict(initial_angle=objective.number("initial_angle_deg", 50.0) * DEG,
                       turn=objective.number("turn_deg", 160.0, positive=True) * DEG)
        mu = requirements.number("min_transmission_angle_deg", None, positive=True)
        positions = requirements.whole("positions", 9, minimum=2)
        objective.finish()
        requirements.finish()
        problem: OptimalDesignProblem = BucketProblem(
            mech, bounds, start, min_transmission_angle=None if mu is None else mu * DEG, positions=positions,
            **options)
    elif kind == "positioning_error":
        problem = _positioning_problem(reader, objective, requirements, mech, path.parent)
    else:
        if sorted(mech.cylinders) != sorted(CYLINDERS) or not {"C_x", "F_x", "Q_x", "V_x"} <= set(mech.parameters):
            raise objective.error("type", f"{mech.name} is not a front-shovel working device [Shovel] (cylinders "
                                          "L1, L2, L3; points C, F, Q, V, A, B, D, E, G, K)")
        bounds = _bounds(reader, mech, SHOVEL_VARIABLES)
        start = _start(reader, bounds)
        cylinders = objective.raw("cylinders", None)
        if cylinders is not None and (not isinstance(cylinders, list) or not cylinders
                                      or any(c not in CYLINDERS for c in cylinders)):
            raise objective.error("cylinders", f"expected a non-empty list of {', '.join(CYLINDERS)}, "
                                               f"got {cylinders!r}")
        tooth = objective.vector("tooth_force", 2, np.zeros(2))
        kind_of, catalog = ShovelProblem, {}
        if kind == "cylinder_mass":
            from .optimal_mass import MassProblem, catalog_options
            kind_of, catalog = MassProblem, catalog_options(objective, path.parent)
        working = {k: requirements.number(k, None, positive=True) for k in WORKING_RANGE}
        maximum_ratio = requirements.number("max_stroke_ratio", 1.7)
        if not maximum_ratio > 1:
            raise requirements.error("max_stroke_ratio", f"the stroke ratio λ must be > 1, got {maximum_ratio:g}")
        mu = requirements.number("min_transmission_angle_deg", 30.0, positive=True)
        stroke = requirements.number("max_stroke", None, positive=True)
        positions = requirements.whole("positions", 9, minimum=2)
        objective.finish()
        requirements.finish()
        try:
            problem = kind_of(
                mech, bounds, start, working_range={k: v for k, v in working.items() if v},
                cylinders=tuple(cylinders) if cylinders else None, max_ratio=maximum_ratio,
                min_transmission_angle=mu * DEG, max_stroke=stroke, tooth_force=(float(tooth[0]), float(tooth[1])),
                positions=positions, **catalog)
        except InputError as exc:
            raise requirements.error("max_digging_radius", exc.message) from None
    solver = reader.table("solver", None) or FieldReader({}, file=path, path="solver")
    doe = reader.table("doe", None) or FieldReader({}, file=path, path="doe")
    method = solver.string("method", "ipopt", choices=("ipopt", "sqpmethod"))
    doe_method = doe.string("method", "sobol", choices=("sobol", "lhs"))
    spec = Spec(name, problem, path, method, solver.whole("max_iterations", 200, minimum=1),
                solver.number("tolerance", 1e-12, positive=True), _doe_points(doe, doe_method), doe_method,
                doe.whole("seed", 0, minimum=0))
    for table in (solver, doe, reader):
        table.finish()
    return spec


def _doe_points(doe: Any, method: str) -> int:
    """``[doe] points``: at least 2, at most :data:`MAX_DOE_POINTS`, a power of two for Sobol points."""
    points = doe.whole("points", 256, minimum=2)
    if points > MAX_DOE_POINTS:
        raise doe.error("points", f"{points:,} DOE points; a DOE has at most {MAX_DOE_POINTS:,} (2^20)")
    if method == "sobol" and points & (points - 1):
        lower = 1 << (points.bit_length() - 1)
        raise doe.error("points", f"must be a power of 2 for Sobol points (their balance needs it), got {points}: "
                                  f"use {lower} or {2 * lower}, or method = \"lhs\"")
    return points


# ------------------------------------------------------------------------------------------------ running
def optimize(spec: Spec | str | Path) -> OptimumResult:
    """Solve the spec's problem, evaluate the optimum and the start with the Pinocchio model and compare the optimum
    with the best feasible design of a DOE over the same box (see the module docstring)."""
    spec = spec if isinstance(spec, Spec) else read_spec(spec)
    with warnings.catch_warnings(record=True) as caught:  # the filters as they are: what would be shown
        result = _optimize(spec)
    result.notes = _notes(caught)
    return result


def _notes(caught: list[warnings.WarningMessage]) -> list[str]:
    """The library warnings recorded while solving as notes of the result (one line each, each once); mechatron's
    own warnings are warned again, for the command line to show as it shows every command's."""
    notes: list[str] = []
    for w in caught:
        if issubclass(w.category, MechatronWarning):
            warnings.warn(w.message, w.category, stacklevel=3)
            continue
        text = " ".join(str(w.message).split())
        note = f"{w.category.__name__} in {Path(w.filename).parent.name}/{Path(w.filename).name}: {text}"
        if note not in notes:
            notes.append(note)
    return notes


def _optimize(spec: Spec) -> OptimumResult:
    """:func:`optimize` of a read spec."""
    from .optimal_solve import design_of_experiments, judge_with_pinocchio, solve

    p = spec.problem
    try:
        start_objective, start_requirements = p.judge(p.evaluate(p.start))
    except MechatronError as exc:
        raise InputError(f"the start design cannot be evaluated: {getattr(exc, 'message', exc)}", file=spec.path,
                         field="start") from None
    doe, steps, choice = None, None, None
    if p.objective_name == "cylinder_mass":  # a discrete catalog choice: DOE first, then refine and descend
        from .optimal_mass import descend

        doe = design_of_experiments(p, spec.doe_points, spec.doe_method, spec.seed)
        try:
            solution, steps = descend(p, doe, max_iterations=spec.max_iterations, tolerance=spec.tolerance,
                                      solver=spec.method)
        except InputError as exc:
            raise InputError(exc.message, file=spec.path, field=exc.field) from None
    else:
        solution = solve(p, max_iterations=spec.max_iterations, tolerance=spec.tolerance, solver=spec.method)
    try:
        objective, requirements, difference = judge_with_pinocchio(p, solution.x)
    except MechatronError as exc:
        raise MechatronError(f"{spec.name}: {spec.method} ended ({solution.status}) at a design the Pinocchio model "
                             f"cannot evaluate: {getattr(exc, 'message', exc)}") from None
    if steps is not None:
        choice = list(p.choice)  # the drives module's choice at the optimum, on the Pinocchio model's forces
    if doe is None:
        doe = design_of_experiments(p, spec.doe_points, spec.doe_method, spec.seed)
    doe_best = None
    order = np.argsort(np.where(doe.feasible, doe.objective, np.inf))
    for i in order[:min(10, int(np.count_nonzero(doe.feasible)))]:  # the best the Pinocchio model confirms
        try:
            value, met, _ = judge_with_pinocchio(p, doe.points[i])
        except MechatronError:
            continue
        if all(r.met() for r in met):
            doe_best = {"x": doe.points[i], "objective": value, "met": True}
            break
    return OptimumResult(spec.name, p.mech.name, p.title, spec.method, p.variables, p.lower, p.upper, p.start,
                         solution.x, p.objective_name, p.objective_unit, objective, requirements, start_objective,
                         start_requirements, solution.success, solution.status, solution.iterations,
                         solution.history, difference, doe.method, doe.points, doe.objective, doe.feasible, doe_best,
                         choice, steps)


@dataclass
class OptimumResult(Result):
    """An optimal design: the optimum x (SI units) and its objective and requirements from the Pinocchio model, the
    start's, the solver's status and convergence history, the largest relative difference between the CasADi
    expressions and the Pinocchio model at the optimum, and the DOE (points, objective, feasibility, its best). For
    ``cylinder_mass``: ``catalog_choice``, per cylinder the catalog row the drives module chooses at the optimum
    (key, count, bore, rod, stroke m, mass kg, its checks), and ``descent``, the steps of the search (step, rows,
    mass kg)."""

    name: str
    mechanism: str
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
    requirements: list[Requirement]
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
    notes: list[str] = field(default_factory=list)

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
        from ..report.figures import new_figure, style_axes

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
            figure = ax.get_figure()
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
        for r in self.requirements:
            sign = "≥" if r.kind == "min" else "≤"
            lines.append(f"  {r.name:<42} {r.value:12.6g} {sign} {r.limit:<10.6g} margin {r.margin:10.3g} {r.unit}"
                         f"  {r.verdict}")
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

r"""The named problems of ``mechatron optimize`` (docs/optimize_file.md): :func:`named_problem` and
:func:`optimize_named`.

A named problem's spec names a mechanism, the design variables (named parameters with bounds), the objective's
``type`` and the requirements. :func:`named_problem` checks it (from :func:`mechatron.optimal.reader.read_problem`,
which parses the file once; one-line errors naming the file and field) and builds the problem, a
:class:`~mechatron.optimal.problem.Problem` whose model is an exact one, an
:class:`~mechatron.optimal.problems.base.CasadiModel` (:mod:`~mechatron.optimal.problems.bucket`: the
bucket synthesis [Bucket] as the bucket angle error; :mod:`~mechatron.optimal.problems.shovel`: the front shovel
[Shovel] with the least largest cylinder force; :mod:`~mechatron.optimal.problems.mass`: the same with the lightest
catalog cylinders, a discrete choice solved by DOE-then-refine; :mod:`~mechatron.optimal.problems.accuracy`: a DH
arm's positioning error);
:func:`optimize_named` solves it with ``casadi.nlpsol("ipopt")`` on SX expressions of the loop equations
(:mod:`~mechatron.optimal.problems.nlp`), evaluates the optimum with the Pinocchio model, and compares it with the best
of a DOE (scrambled Sobol or Latin-hypercube points of the same box; the best feasible point by the CasADi expressions
that the Pinocchio model confirms, of the ten best), an :class:`~mechatron.optimal.result.OptimalResult` in its
comparison form; ``mechatron optimize`` exits 1 when a requirement is not met at the optimum
(:attr:`OptimalResult.feasible`).

The DOE has at most :data:`MAX_DOE_POINTS` points, a power of two for Sobol points (their balance needs it). A
warning of a library while solving (NumPy, SciPy, CasADi) becomes one of the result's ``notes``, never a raw message
on stderr.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import InputError, MechatronError, MechatronWarning
from ...io.schema import FieldReader
from ..problem import Problem
from ..requirement import Vector
from ..result import OptimalResult
from .base import CasadiModel

DEG = math.pi / 180
OBJECTIVES = ("bucket_angle_error", "max_cylinder_force", "positioning_error", "cylinder_mass")
WORKING_RANGE = ("max_digging_radius", "max_digging_height", "max_digging_depth", "min_digging_radius")
#: The most DOE points: each is judged in turn in one process (about a millisecond each: 2^20 take minutes).
MAX_DOE_POINTS = 2 ** 20


def _mechanism(reader: Any, folder: Path) -> tuple[str, Any]:
    """The spec's mechanism, by the study files' loader and path rule (:func:`mechatron.studies.spec.read_mechanism`:
    a file relative to the spec's folder, else a shipped name; loaded once per process and content): its name or
    absolute file, and the mechanism."""
    from ...studies.spec import read_mechanism as study_mechanism

    return study_mechanism(reader, folder)


def _bounds(reader: Any, mech: Any, known: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """``[variables]`` read as a design file's (:func:`~mechatron.optimal.design_file.read_variables`), only the
    named problem's ``known`` ones, as ranges: name → (lower, upper) (m)."""
    from ..design_file import read_variables

    variables = read_variables(reader, mech, {}, Path(reader.file or ".").resolve().parent, known)
    return {p.name: p.bounds for p in variables}


def _start(reader: Any, bounds: dict[str, tuple[float, float]]) -> dict[str, float]:
    """``[start]`` read as a design file's (:func:`~mechatron.optimal.design_file.read_start`)."""
    from ...studies.spec import Range
    from ..design_file import read_start

    return read_start(reader, [Range(name, low, high) for name, (low, high) in bounds.items()])


def _data_file(table: Any, key: str, folder: Path) -> Path:
    """A file named in ``key`` of ``table`` (:func:`~mechatron.studies.spec.file_field`: relative to the spec's
    folder)."""
    from ...studies.spec import file_field

    return file_field(table, key, folder)


def _positioning_problem(reader: Any, objective: Any, requirements: Any, mech: Any, folder: Path
                         ) -> CasadiModel:
    """The positioning-error problem of a spec (:mod:`~mechatron.optimal.problems.accuracy`)."""
    from ...accuracy.sources import read_poses, read_tolerances
    from .accuracy import PositioningProblem, length_parameters

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
    from ...io.tables import read_csv

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


def named_problem(reader: FieldReader, path: Path) -> Problem:
    """Check a parsed named problem's spec (``reader`` over the file at ``path``, docs/optimize_file.md) and build
    its problem.

    Raises:
        InputError: naming the file and the field for a bad spec.
    """
    from .bucket import VARIABLES as BUCKET_VARIABLES
    from .bucket import BucketProblem
    from .shovel import CYLINDERS, ShovelProblem
    from .shovel import VARIABLES as SHOVEL_VARIABLES

    name = reader.string("name", path.stem)
    reader.string("description", "")
    mechanism, mech = _mechanism(reader, path.parent)
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
        problem: CasadiModel = BucketProblem(
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
        kind_of: type[ShovelProblem] = ShovelProblem
        catalog: dict[str, Any] = {}
        if kind == "cylinder_mass":
            from .mass import MassProblem, catalog_options
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
    from ...studies.ranges import Range

    spec = Problem(str(path), name, mechanism,
                   tuple(Range(v, lo, hi) for v, lo, hi in zip(problem.variables, problem.lower, problem.upper)),
                   ((problem.objective_name, "minimize"),), problem,
                   start=dict(zip(problem.variables, (float(v) for v in problem.start))), method=method,
                   max_iterations=solver.whole("max_iterations", 200, minimum=1),
                   tolerance=solver.number("tolerance", 1e-12, positive=True),
                   doe_points=_doe_points(doe, doe_method), doe_method=doe_method,
                   seed=doe.whole("seed", 0, minimum=0))
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
def optimize_named(spec: Problem | str | Path) -> OptimalResult:
    """Solve the spec's problem, evaluate the optimum and the start with the Pinocchio model and compare the optimum
    with the best feasible design of a DOE over the same box (see the module docstring)."""
    if not isinstance(spec, Problem):
        from ...io.toml import read_toml

        path = Path(spec)
        spec = named_problem(FieldReader(read_toml(path), file=path), path)
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


def _optimize(spec: Problem) -> OptimalResult:
    """:func:`optimize_named` of a read spec."""
    from .nlp import design_of_experiments, judge_with_pinocchio, solve

    p = spec.exact_model
    if p is None:
        raise InputError("a design file, not a named problem's spec: optimize() solves it", file=spec.file)
    try:
        start_objective, start_requirements = p.judge(p.evaluate(p.start))
    except MechatronError as exc:
        raise InputError(f"the start design cannot be evaluated: {getattr(exc, 'message', exc)}", file=spec.file,
                         field="start") from None
    from .mass import MassProblem, descend

    doe, steps, choice = None, None, None
    if isinstance(p, MassProblem):  # a discrete catalog choice: DOE first, then refine and descend
        doe = design_of_experiments(p, spec.doe_points, spec.doe_method, spec.seed)
        try:
            solution, steps = descend(p, doe, max_iterations=spec.max_iterations, tolerance=spec.tolerance,
                                      solver=spec.method)
        except InputError as exc:
            raise InputError(exc.message, file=spec.file, field=exc.field) from None
    else:
        solution = solve(p, max_iterations=spec.max_iterations, tolerance=spec.tolerance, solver=spec.method)
    try:
        objective, requirements, difference = judge_with_pinocchio(p, solution.x)
    except MechatronError as exc:
        raise MechatronError(f"{spec.name}: {spec.method} ended ({solution.status}) at a design the Pinocchio model "
                             f"cannot evaluate: {getattr(exc, 'message', exc)}") from None
    if steps is not None and isinstance(p, MassProblem):
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
    return _result(spec, p, solution, objective, requirements, difference, (start_objective, start_requirements),
                   doe, doe_best, choice, steps)


def _result(spec: Problem, p: CasadiModel, solution: Any, objective: float, requirements: list,
            difference: float, start: tuple[float, list], doe: Any, doe_best: dict[str, Any] | None,
            choice: list[dict[str, Any]] | None, steps: list[dict[str, Any]] | None) -> OptimalResult:
    """The result in its comparison form: the optimum as ``best`` (each variable's value, m, and the objective's:
    the Pinocchio model's), the DOE as ``evaluations`` (the variables, the objective, ``feasible``), the solver's
    summary."""
    import pandas as pd

    best = {**dict(zip(p.variables, (float(v) for v in solution.x))), p.objective_name: objective}
    table = pd.DataFrame(np.asarray(doe.points, dtype=float).reshape(-1, len(p.variables)), columns=list(p.variables))
    table[p.objective_name] = doe.objective
    table["feasible"] = np.asarray(doe.feasible, dtype=bool)
    solver = {"name": spec.method, "success": solution.success, "status": solution.status,
              "iterations": solution.iterations, "history": solution.history,
              "casadi_pinocchio_difference": difference}
    return OptimalResult(name=spec.name, mechanism=p.mech.name, variables=p.variables, objectives=spec.objectives,
                         solver=solver, requirements=requirements, evaluations=table, best=best,
                         units={**dict.fromkeys(p.variables, "m"), p.objective_name: p.objective_unit},
                         title=p.title, lower=p.lower, upper=p.upper, start=p.start, start_objective=start[0],
                         start_requirements=start[1], doe_method=doe.method, doe_points=doe.points,
                         doe_objective=doe.objective, doe_feasible=doe.feasible, doe_best=doe_best,
                         catalog_choice=choice, descent=steps)

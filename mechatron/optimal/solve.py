r"""Optimal design, the one entry point (:func:`optimize`): a file read once (:func:`~mechatron.optimal.reader.
read_problem`) into a :class:`~mechatron.optimal.problem.Problem` and solved by its model — a design file's study
analyses by :func:`optimize_design`, a named problem's exact CasADi model by :func:`~mechatron.optimal.problems.named.
optimize_named` — into an :class:`~mechatron.optimal.result.OptimalResult`.

A design problem (:func:`optimize_design`) is solved with the study's own evaluation of a design
(:class:`~mechatron.studies.evaluator.Evaluator`: the mechanism rebuilt with the design's parameters, every analysis
run on it, the Pinocchio model) in batches, in this process or on the study's Dask engine (``workers``,
``scheduler``).

Methods:

- ``ipopt`` (:mod:`~mechatron.optimal.exact`): exact first derivatives where the analyses give them
  (:class:`~mechatron.studies.evaluator.GradientAnalysis`: the loop
  equations' implicit-function derivatives of the sweep's extremes, :mod:`mechatron.studies.analyses.linkage`),
  CasADi's ``nlpsol("ipopt")`` with a limited-memory Hessian: min f(x) s.t. lo ≤ g(x) ≤ hi, x_lo ≤ x ≤ x_hi,
  after a DOE (``population`` Latin-hypercube points, evaluated as one batch), from ``[start]`` or else the DOE's
  best feasible design.
- ``global`` (:mod:`~mechatron.optimal.search`): SciPy's ``differential_evolution`` (derivative-free; catalog choices,
  sizing outputs that step with the catalog, maxima over a stroke), the requirements as its constraints (Lampinen's
  feasibility rules), over the unit cube of the variables (a list of values is its index, ⌊u k⌋), its population
  evaluated as one batch a generation, the first generation a Latin hypercube of the box (the study's sampler) with the
  start in it.
- ``nsga2``: two objectives, pymoo's NSGA-II, the same batches and first generation; the front reported is the
  non-dominated set of every feasible design evaluated.

The design reported is the best feasible one evaluated (one objective: the smallest; ties, the first), its every
output, requirement value and margin from the analyses.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .evaluations import Evaluations
from .exact import exact_available, solve_exact
from .problem import Problem
from .problems.named import optimize_named
from .reader import ProblemFile, read_problem
from .result import OptimalResult, front_mask
from .search import solve_global, solve_pareto


def optimize(problem: Problem | ProblemFile | str | Path, workers: int = 1,
             scheduler: str | None = None, progress: Any = None) -> OptimalResult:
    """Solve an optimal-design problem — read from its file (:func:`~mechatron.optimal.reader.read_problem`) unless
    given read — and return its result: on the study analyses by :func:`optimize_design` (``workers``,
    ``scheduler`` and ``progress`` as there), on an exact CasADi model (a named problem) by
    :func:`~mechatron.optimal.problems.named.optimize_named`."""
    if not isinstance(problem, Problem):
        problem = read_problem(problem)
    if problem.exact_model is not None:
        return optimize_named(problem)
    return optimize_design(problem, workers=workers, scheduler=scheduler, progress=progress)


def optimize_design(spec: Problem | str | Path, workers: int = 1, scheduler: str | None = None,
                    progress: Any = None) -> OptimalResult:
    """Solve a design file (see the module docstring) in this process (``workers = 1``), on an embedded Dask
    cluster of ``workers`` processes, or on a running ``scheduler``."""
    import warnings

    from ..io.values import number
    from ..studies.analyses import worker_modules
    from ..studies.cluster import connect, disconnect, prestart

    if not isinstance(spec, Problem):
        spec = read_problem(spec)
    if spec.exact_model is not None:
        raise InputError("a named problem's spec, not a design file: optimize() solves it", file=spec.file)
    workers = number("workers", workers, integer=True, minimum=1, maximum=1024)
    method = spec.method
    why = exact_available(spec)
    if method == "ipopt" and why is not None:
        raise InputError(f"ipopt needs exact derivatives: {why}; use method = \"global\"", file=spec.file,
                         field="solver.method")
    if method == "auto":
        method = "nsga2" if len(spec.objectives) == 2 else "ipopt" if why is None else "global"
    prestart(workers, scheduler, worker_modules())
    client = None if method == "ipopt" else connect(workers, scheduler, worker_modules())
    evaluations = Evaluations(spec, client, progress)
    solver: dict[str, Any] = {}
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            solver = {"ipopt": solve_exact, "global": solve_global, "nsga2": solve_pareto}[method](spec, evaluations)
    finally:
        evaluations.pace.finish(_ended(spec, evaluations, solver))
        if client is not None:
            disconnect(client, scheduler)
    notes = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught
                               if not issubclass(w.category, DeprecationWarning)))
    return _result(spec, evaluations, solver, notes)


def _ended(spec: Problem, evaluations: Evaluations, solver: dict[str, Any]) -> str:
    """Why the search ended where it did, for the end of the progress line: stopped (an error), or the solver's
    status and, short of the budget, the designs evaluated of it (a design asked for again is not evaluated again;
    differential evolution runs whole generations; ipopt evaluates the analyses' exact derivatives, not designs)."""
    if not solver:
        return "stopped"
    done = len(evaluations.rows)
    short = f"; {done} of the budget's {spec.evaluations} designs evaluated" if done < spec.evaluations else ""
    return f"ended: {solver['method'].split(' ')[0]}: {solver['status']}{short}"


def _result(spec: Problem, evaluations: Evaluations, solver: dict[str, Any], notes: list[str]) -> OptimalResult:
    table = evaluations.table()
    rows = list(evaluations.rows.values())
    feasible = [i for i, r in enumerate(rows) if evaluations.feasible(r)]
    front = None
    best = None
    if len(spec.objectives) == 2:
        values = np.array([evaluations.objectives(rows[i]) for i in feasible]).reshape(-1, 2)
        keep = [feasible[i] for i in np.flatnonzero(front_mask(values))]
        front = table.iloc[keep].sort_values(spec.objectives[0][0], kind="stable")
        best = rows[keep[0]] if keep else None
    elif "optimum" in solver:  # ipopt: its optimum, evaluated as every design
        key = tuple(solver["optimum"][n] for n in evaluations.names)
        best = evaluations.rows[key]
        if best["status"] != "ok":  # its last design failed: the best feasible one evaluated, if any
            notes = [*notes, f"ipopt ended on a design that failed ({best.get('reason', best['status'])}); "
                             "reported instead: the best feasible design evaluated, if any"]
            scores = [evaluations.objectives(rows[i])[0] for i in feasible]
            best = rows[feasible[int(np.argmin(scores))]] if feasible else None
        elif not evaluations.feasible(best):
            notes = [*notes, "ipopt's optimum does not meet every requirement (evaluated by the analyses)"]
    elif feasible:
        scores = [evaluations.objectives(rows[i])[0] for i in feasible]
        best = rows[feasible[int(np.argmin(scores))]]
    requirements = evaluations.requirements(best) if best is not None else []
    return OptimalResult(name=spec.name, mechanism=Path(spec.mechanism).name, objectives=spec.objectives,
                         variables=tuple(evaluations.names), solver=solver, evaluations=table, best=best,
                         requirements=requirements, front=front, notes=notes, units=_units(spec))


def _units(spec: Problem) -> dict[str, str]:
    """The unit of each variable — its mechanism parameter's (m, rad), the registry's for an analysis option, "-"
    for a list of names — and of each objective (:func:`~mechatron.quantities.unit_of`)."""
    from ..quantities import is_quantity, unit, unit_of
    from ..studies.spec import study_mechanism

    mech = study_mechanism(spec.mechanism)
    out = {}
    for p in spec.variables:
        option = p.target.split(".", 1)[1] if p.target else None
        if option is None:
            out[p.name] = mech.parameters[p.name].unit
        else:
            out[p.name] = unit(option) if is_quantity(option) and p.values is None else "-"
    return {**out, **{name: unit_of(name) for name, _ in spec.objectives}}

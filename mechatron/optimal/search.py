"""The derivative-free methods of a design problem: differential evolution (``global``, one objective) and NSGA-II
(``nsga2``, two), their first generation a Latin hypercube of the unit cube of the variables (the study's
sampler) with the start in it, each generation evaluated as one batch (:mod:`mechatron.optimal.evaluations`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .evaluations import Evaluations
from .problem import Problem


def first_generation(spec: Problem, evaluations: Evaluations) -> np.ndarray:
    """``population`` points of the unit cube: a Latin hypercube (the study's sampler, seeded), the start (when
    given: the middle of the box for the variables it leaves out) first."""
    from ..studies.designs import latin_hypercube

    points = latin_hypercube(spec.population, len(spec.variables), spec.seed)
    if spec.start:
        middle = {p.name: _middle(*p.bounds) if p.values is None else p.values[0] for p in spec.variables}
        points[0] = evaluations.unit({**middle, **spec.start})
    return points


def _middle(low: float, high: float) -> float:
    """The middle of a range: (low + high) / 2."""
    return (low + high) / 2


def _batch(evaluations: Evaluations, U: np.ndarray) -> list[dict[str, Any]]:
    """The rows of the points ``U`` (S, d) of the unit cube."""
    return evaluations([evaluations.design(u) for u in np.atleast_2d(U)])


def solve_global(spec: Problem, evaluations: Evaluations) -> dict[str, Any]:
    """One objective by differential evolution (the module docstring); returns the solver's summary."""
    from scipy.optimize import NonlinearConstraint, differential_evolution

    init = first_generation(spec, evaluations)

    def objective(UT: np.ndarray) -> np.ndarray:
        return np.array([evaluations.objectives(r)[0] for r in _batch(evaluations, np.asarray(UT).T)])

    def margins(UT: np.ndarray) -> np.ndarray:
        return np.array([evaluations.margins(r) for r in _batch(evaluations, np.asarray(UT).T)]).T

    count = sum((b.low is not None) + (b.high is not None) for b in spec.requirements)
    constraints = [NonlinearConstraint(margins, 0.0, np.inf)] if count else []
    generations = max(0, (spec.evaluations - len(init)) // len(init))
    result = differential_evolution(objective, [(0.0, 1.0)] * len(spec.variables), init=init, maxiter=generations,
                                    polish=False, vectorized=True, updating="deferred", rng=spec.seed, tol=0.0,
                                    constraints=constraints)
    return {"method": "global (differential evolution, SciPy)", "success": bool(result.success),
            "status": str(result.message), "iterations": int(result.nit)}


def solve_pareto(spec: Problem, evaluations: Evaluations) -> dict[str, Any]:
    """Two objectives by NSGA-II (pymoo); the front is taken from every design evaluated (:func:`front_mask`)."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem as PymooProblem
    from pymoo.optimize import minimize

    count = sum((b.low is not None) + (b.high is not None) for b in spec.requirements)

    class Design(PymooProblem):
        def __init__(self) -> None:
            super().__init__(n_var=len(spec.variables), n_obj=2, n_ieq_constr=count, xl=0.0, xu=1.0)

        def _evaluate(self, X: np.ndarray, out: dict, *args: Any, **kwargs: Any) -> None:
            rows = _batch(evaluations, X)
            F = np.array([evaluations.objectives(r) for r in rows])
            out["F"] = np.where(np.isfinite(F), F, 1e300)
            if count:
                out["G"] = -np.array([evaluations.margins(r) for r in rows])

    algorithm = NSGA2(pop_size=spec.population, sampling=first_generation(spec, evaluations))
    result = minimize(Design(), algorithm, ("n_eval", spec.evaluations), seed=spec.seed, verbose=False)
    return {"method": "nsga2 (NSGA-II, pymoo)", "success": result.F is not None, "status": "evaluation budget spent",
            "iterations": int(result.algorithm.n_gen)}

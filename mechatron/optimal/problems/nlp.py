r"""Solving an :class:`~mechatron.optimal.problems.base.CasadiModel` and comparing it with a DOE.

:func:`solve`: the NLP  min f(x, s, t)  s.t.  Φ(x, s) = 0,  g(x, s, t) ≥ 0,  x_lo ≤ x ≤ x_hi  with CasADi's
``nlpsol("ipopt")`` (:func:`~mechatron.optimal.nlpsol.run_nlp`; exact first and second derivatives of the SX
expressions), started from the design ``start`` with its states assembled by the Pinocchio model. The optimum is
then evaluated by the Pinocchio model: its objective and requirements are those reported.

:func:`design_of_experiments`: scrambled Sobol or Latin-hypercube points of the same box (``scipy.stats.qmc``,
seeded), each judged by the problem's DOE evaluation (the Pinocchio model, or for an explicit problem without loop
states its CasADi expressions, checked against the Pinocchio model at the best point); the best feasible one is the
design the optimum is compared with.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...studies.designs import sample_box
from ..nlpsol import run_nlp
from ..requirement import Requirement, Vector
from .base import CasadiModel


@dataclass
class Solution:
    """What the NLP solver returned: the design x, the states, the solver status and its objective per iteration."""

    x: Vector
    states: Vector
    success: bool
    status: str
    iterations: int
    history: list[float] = field(default_factory=list)


def solve(problem: CasadiModel, *, max_iterations: int = 200, tolerance: float = 1e-12,
          solver: str = "ipopt") -> Solution:
    """Solve the problem's NLP (see the module docstring) from its ``start``."""
    import casadi as ca

    aux, f, g = problem.nlp_terms(problem.quantities)
    n, m, k = problem.x.numel(), problem.s.numel(), aux.numel()
    w = ca.vertcat(problem.x, problem.s, aux)
    constraints = ca.vertcat(problem.loops, g)
    s0 = problem.states(problem.start)
    q0 = problem.values(problem.start, s0)
    w0 = np.concatenate([problem.start, s0, problem.aux_guess(q0)])
    inf = np.full(m + k, np.inf)
    nl = problem.loops.numel()
    run = run_nlp("optimal_design", {"x": w, "f": f, "g": constraints}, x0=w0,
                  lbx=np.concatenate([problem.lower, -inf]), ubx=np.concatenate([problem.upper, inf]),
                  lbg=np.zeros(nl + g.numel()), ubg=np.concatenate([np.zeros(nl), np.full(g.numel(), np.inf)]),
                  tolerance=tolerance, max_iterations=max_iterations, solver=solver,
                  ipopt={"constr_viol_tol": tolerance, "acceptable_tol": tolerance})
    return Solution(run.w[:n], run.w[n:n + m], run.success, run.status, run.iterations,
                    [v / problem.scale for v in run.history])


@dataclass
class DesignOfExperiments:
    """The DOE points (one row per design), their objective (NaN where not feasible or not assembled) and whether
    they meet every requirement; ``best``: the index of the best feasible point (None if none is)."""

    method: str
    points: Vector
    objective: Vector
    feasible: NDArrayBool
    reasons: list[str]

    @property
    def best(self) -> int | None:
        values = np.where(self.feasible, self.objective, np.inf)
        return int(np.argmin(values)) if np.isfinite(values).any() else None


NDArrayBool = Any


def design_of_experiments(problem: CasadiModel, points: int = 256, method: str = "sobol",
                          seed: int = 0) -> DesignOfExperiments:
    """Judge ``points`` designs of the problem's box (see the module docstring)."""
    X = sample_box(problem.lower, problem.upper, points, method, seed)
    objective, feasible, reasons = np.full(len(X), np.nan), np.zeros(len(X), dtype=bool), []
    functions = problem.functions()
    guess = problem.state_guess(problem.start)
    for i, x in enumerate(X):
        s = problem.states(x, guess)
        if s.size and not np.abs(np.array(functions["loops"](x, s))).max() < 1e-10:
            reasons.append("the loops do not close")
            continue
        q = np.array(functions["quantities"](x, s)).ravel()
        value, requirements = problem.judge(q)
        unmet = [r.name for r in requirements if not r.met()]
        objective[i], feasible[i] = value, not unmet
        reasons.append(f"not met: {', '.join(unmet)}" if unmet else "")
    return DesignOfExperiments(method, X, objective, feasible, reasons)


def judge_with_pinocchio(problem: CasadiModel, x: Vector) -> tuple[float, list[Requirement], float]:
    """(objective, requirements, largest relative difference of the quantities between the CasADi expressions and
    the Pinocchio model) at the design x, the objective and requirements from the Pinocchio model."""
    q = problem.evaluate(x)
    casadi = problem.values(x)
    difference = float(np.max(np.abs(q - casadi) / np.maximum(1.0, np.abs(q))))
    objective, requirements = problem.judge(q)
    return objective, requirements, difference

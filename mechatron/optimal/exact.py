r"""The exact route of a design problem (``ipopt``): exact first derivatives where the analyses give them
(:class:`~mechatron.studies.evaluator.GradientAnalysis`: the loop equations' implicit-function derivatives of the
sweep's extremes, :mod:`mechatron.studies.analyses.linkage`), CasADi's ``nlpsol("ipopt")`` with a limited-memory
Hessian (:func:`~mechatron.optimal.nlpsol.run_nlp`, stopped once too many trial designs failed): min f(x) s.t.
lo ≤ g(x) ≤ hi, x_lo ≤ x ≤ x_hi, after a DOE (``population`` Latin-hypercube points, evaluated as one batch), from
``[start]`` or else the DOE's best feasible design."""

from __future__ import annotations

from typing import Any

import numpy as np

from .evaluations import Evaluations
from .nlpsol import run_nlp
from .problem import Problem
from .search import _batch, _middle, first_generation


def solve_exact(spec: Problem, evaluations: Evaluations) -> dict[str, Any]:
    """One objective with exact first derivatives by ipopt (the module docstring)."""
    import casadi as ca

    model = ExactModel(spec)
    names = [spec.objectives[0][0], *(b.name for b in spec.requirements)]
    outputs = _outputs(model, names)
    x = ca.MX.sym("x", len(spec.variables))
    y = outputs(x)
    sign = 1.0 if spec.objectives[0][1] == "minimize" else -1.0
    lower = np.array([p.low for p in spec.variables])
    upper = np.array([p.high for p in spec.variables])
    start = _doe_start(spec, evaluations)
    low = [-np.inf if b.low is None else b.low for b in spec.requirements]
    high = [np.inf if b.high is None else b.high for b in spec.requirements]
    run = run_nlp("design", {"x": x, "f": sign * y[0], "g": y[1:]}, x0=start, lbx=lower, ubx=upper, lbg=low,
                  ubg=high, tolerance=spec.tolerance, max_iterations=spec.max_iterations,
                  ipopt={"hessian_approximation": "limited-memory"}, options={"show_eval_warnings": False},
                  failures=lambda: sum(model.failed.values()))
    best = np.clip(run.w, lower, upper)
    evaluations([dict(zip(evaluations.names, (float(v) for v in best)))])
    return {"method": "ipopt (exact derivatives, CasADi)", "success": run.success,
            "status": run.status, "iterations": run.iterations,
            "optimum": {n: float(v) for n, v in zip(evaluations.names, best)},
            "failed_trials": sum(model.failed.values()),
            "failed_trial_reasons": dict(sorted(model.failed.items(), key=lambda kv: -kv[1])[:3])}


def _doe_start(spec: Problem, evaluations: Evaluations) -> np.ndarray:
    """The exact route's start: ``[start]`` if given, else the best feasible design of a DOE of ``population``
    points (:func:`first_generation`; the middle of the box when none is feasible)."""
    rows = _batch(evaluations, first_generation(spec, evaluations))
    if spec.start:
        return np.array([spec.start.get(p.name, _middle(*p.bounds)) for p in spec.variables])
    feasible = [r for r in rows if evaluations.feasible(r)]
    if not feasible:
        return np.array([_middle(*p.bounds) for p in spec.variables])
    best = min(feasible, key=lambda r: evaluations.objectives(r)[0])
    return np.array([float(best[n]) for n in evaluations.names])


class ExactModel:
    """The outputs and their exact gradients with respect to the variables at a design (the analyses'
    ``gradients``), each design once."""

    def __init__(self, spec: Problem):
        from ..studies.analyses import gradient_analysis
        from ..studies.spec import study_mechanism

        self.spec = spec
        self.mech = study_mechanism(spec.mechanism)
        self.names = [p.name for p in spec.variables]
        found = {name: gradient_analysis(name) for name in spec.analyses}
        self.analyses = {name: a for name, a in found.items() if a is not None}
        self._last: tuple[bytes, dict, dict] | None = None
        self.failed: dict[str, int] = {}  # why a design the solver asked for failed → how many times

    def __call__(self, x: np.ndarray) -> tuple[dict[str, float], dict[str, np.ndarray]]:
        """The outputs and gradients at ``x``; where the design cannot be built or analysed (its links too short
        to assemble, an analysis refuses it) none (every output NaN: ipopt's line search steps back), the reason
        counted in :attr:`failed`."""
        from ..errors import MechatronError

        x = np.asarray(x, dtype=float).ravel()
        if self._last is None or self._last[0] != x.tobytes():
            values: dict[str, float] = {}
            gradients: dict[str, np.ndarray] = {}
            try:
                mech = self.mech.with_parameters(dict(zip(self.names, x.tolist())))
                for name, module in self.analyses.items():
                    out, grad = module.gradients(mech, self.spec.options(name, {}), self.names)
                    values.update(out)
                    gradients.update(grad)
            except MechatronError as exc:
                self.failed[str(exc)] = self.failed.get(str(exc), 0) + 1
                values, gradients = {}, {}
            self._last = (x.tobytes(), values, gradients)
        return self._last[1], self._last[2]


def exact_available(spec: Problem) -> str | None:
    """None when the exact route applies to ``spec``, else why not (in words)."""
    from ..studies.analyses import gradient_analysis

    if any(p.values is not None or p.target is not None for p in spec.variables):
        return "a variable is a list of values or an analysis option (no derivative)"
    if len(spec.objectives) != 1:
        return "two objectives (a Pareto front)"
    from ..studies.spec import study_mechanism

    mech = study_mechanism(spec.mechanism)
    given = {}
    for name in spec.analyses:
        exact = gradient_analysis(name)
        if exact is not None:
            given.update(dict.fromkeys(exact.gradient_outputs(mech, spec.options(name, {})), name))
    needed = [spec.objectives[0][0], *(b.name for b in spec.requirements)]
    missing = [n for n in needed if n not in given]
    return f"no exact derivative of {', '.join(missing)}" if missing else None


def _outputs(model: ExactModel, names: list[str]) -> Any:
    """A CasADi function x ↦ the outputs ``names`` of :class:`ExactModel`, with its exact Jacobian."""
    import casadi as ca


    n, m = len(model.names), len(names)

    class Jacobian(ca.Callback):
        def __init__(self, name: str, opts: Any):
            ca.Callback.__init__(self)
            self.construct(name, opts)

        def get_n_in(self) -> int:
            return 2

        def get_n_out(self) -> int:
            return 1

        def get_sparsity_in(self, i: int):
            return ca.Sparsity.dense(n, 1) if i == 0 else ca.Sparsity.dense(m, 1)

        def get_sparsity_out(self, i: int):
            return ca.Sparsity.dense(m, n)

        def eval(self, arg: Any) -> Any:
            _, gradients = model(np.array(arg[0]))
            return [np.array([gradients.get(k, np.full(n, np.nan)) for k in names], dtype=float)]

    class Outputs(ca.Callback):
        def __init__(self) -> None:
            ca.Callback.__init__(self)
            self.construct("outputs", {"enable_fd": False})

        def get_n_in(self) -> int:
            return 1

        def get_n_out(self) -> int:
            return 1

        def get_sparsity_in(self, i: int):
            return ca.Sparsity.dense(n, 1)

        def get_sparsity_out(self, i: int):
            return ca.Sparsity.dense(m, 1)

        def eval(self, arg: Any) -> Any:
            values, _ = model(np.array(arg[0]))
            return [np.array([values.get(k, np.nan) for k in names], dtype=float)]

        def has_jacobian(self) -> bool:
            return True

        def get_jacobian(self, name: str, inames: Any, onames: Any, opts: Any) -> Any:
            self._jacobian = Jacobian(name, opts)  # kept alive with the function
            return self._jacobian

    return Outputs()

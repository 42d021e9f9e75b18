r"""Optimal design of any machine (:func:`optimize_design`): a design file (:mod:`~mechatron.studies.design_spec`)
solved with the study's own evaluation of a design — the mechanism rebuilt with the design's parameters, every
analysis run on it (:func:`mechatron.studies.runner.evaluate`: the Pinocchio model) — in batches, in this process or
on the study's Dask engine (``workers``, ``scheduler``).

Methods:

- ``ipopt``: exact first derivatives where the analyses give them (``gradients`` of an analysis module: the loop
  equations' implicit-function derivatives of the sweep's extremes, :mod:`mechatron.studies.analyses.linkage`),
  CasADi's ``nlpsol("ipopt")`` with a limited-memory Hessian: min f(x) s.t. lo ≤ g(x) ≤ hi, x_lo ≤ x ≤ x_hi,
  after a DOE (``population`` Latin-hypercube points, evaluated as one batch), from ``[start]`` or else the DOE's
  best feasible design.
- ``global``: SciPy's ``differential_evolution`` (derivative-free; catalog choices, sizing outputs that step with
  the catalog, maxima over a stroke), the requirements as its constraints (Lampinen's feasibility rules), over the
  unit cube of the variables (a list of values is its index, ⌊u k⌋), its population evaluated as one batch a
  generation, the first generation a Latin hypercube of the box (the study's sampler) with the start in it.
- ``nsga2``: two objectives, pymoo's NSGA-II, the same batches and first generation; the front reported is the
  non-dominated set of every feasible design evaluated.

The design reported is the best feasible one evaluated (one objective: the smallest; ties, the first), its every
output, requirement value and margin from the analyses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..report.result import Result, json_ready
from .design_spec import DesignSpec, read_design
from .optimal_problem import Requirement

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The value standing for a requirement's margin where a design fails (cannot be assembled, an analysis refuses).
FAILED_MARGIN = -1e12


def unit_of(name: str) -> str:
    """The unit of an output (:func:`mechatron.quantities.unit`)."""
    from ..quantities import unit

    return unit(name)


# ----------------------------------------------------------------------------------------------- evaluations
class Evaluations:
    """Designs evaluated through the study's analyses, each once (kept by its variables' values), a batch at a time:
    in this process, or on a Dask client's workers (warmed once: the mechanism and the analyses' files loaded)."""

    def __init__(self, spec: DesignSpec, client: Any = None, progress: Any = None):
        from .pace import Pace

        self.spec, self.client, self.progress = spec, client, progress
        self.names = [p.name for p in spec.variables]
        self.rows: dict[tuple, dict[str, Any]] = {}
        self.pace = Pace(spec.evaluations, progress)
        self._warm = False

    def design(self, u: np.ndarray) -> dict[str, Any]:
        """The design at the point ``u`` of the unit cube (:meth:`~mechatron.studies.spec.Parameter.pick`)."""
        return {p.name: p.pick(float(min(max(x, 0.0), 1.0))) for p, x in zip(self.spec.variables, u)}

    def unit(self, design: dict[str, Any]) -> np.ndarray:
        """The point of the unit cube of a design (a value's index k → (k + ½)/n)."""
        out = []
        for p in self.spec.variables:
            value = design[p.name]
            out.append((value - p.low) / (p.high - p.low) if p.values is None else
                       (p.values.index(value) + 0.5) / len(p.values))
        return np.array(out)

    def __call__(self, designs: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """The rows (``status``, ``reason``, the outputs) of the designs, evaluating those not seen before."""
        keys = [tuple(d[n] for n in self.names) for d in designs]
        missing = list(dict.fromkeys(k for k in keys if k not in self.rows))
        if missing:
            rows, seconds = self._evaluate(missing)
            for key, row in zip(missing, rows):
                self.rows[key] = row
            self.pace.add([r["design"] for r in rows], seconds, [r["status"] for r in rows],
                          [r["reason"] for r in rows])
        return [self.rows[k] for k in keys]

    def _evaluate(self, keys: list[tuple]) -> tuple[list[dict[str, Any]], list[float]]:
        """The rows of the designs ``keys`` (their variables' values) and their times (s)."""
        import pandas as pd

        from .designs import design_seed
        from .runner import design_times, evaluate

        first = len(self.rows)
        frame = pd.DataFrame([dict(zip(self.names, k)) for k in keys])
        frame.insert(0, "design", np.arange(first, first + len(keys)))
        frame["seed"] = [design_seed(self.spec.seed, first + i) for i in range(len(keys))]
        if self.client is None:
            rows = evaluate(self.spec.study, frame)
            return rows.to_dict(orient="records"), design_times(rows)
        from .cluster import slots
        from .runner import _warm_worker

        if not self._warm:
            self.client.run(_warm_worker, self.spec.study, wait=False)
            self._warm = True
        size = max(1, math.ceil(len(frame) / (2 * slots(self.client))))
        chunks = [frame.iloc[k:k + size] for k in range(0, len(frame), size)]
        futures = self.client.map(evaluate, [self.spec.study] * len(chunks), chunks, pure=False)
        parts = self.client.gather(futures)
        seconds = [s for part in parts for s in design_times(part)]
        return pd.concat(parts, ignore_index=True).to_dict(orient="records"), seconds

    # ---------------------------------------------------------------------------------------- judging a row
    def objectives(self, row: dict[str, Any]) -> np.ndarray:
        """The objectives of a row as minimised (a maximised one negated); inf where the design failed."""
        if row["status"] != "ok":
            return np.full(len(self.spec.objectives), math.inf)
        return np.array([float(row[n]) * (1.0 if goal == "minimize" else -1.0) for n, goal in self.spec.objectives])

    def requirements(self, row: dict[str, Any]) -> list[Requirement]:
        """The requirements at a row: one per bound (``min``, ``max``), with its value and margin."""
        out = []
        for b in self.spec.requirements:
            value = float(row[b.name]) if row["status"] == "ok" else math.nan
            for kind, limit in (("min", b.low), ("max", b.high)):
                if limit is not None:
                    out.append(Requirement(b.name, value, float(limit), kind, unit_of(b.name)))
        return out

    def margins(self, row: dict[str, Any]) -> np.ndarray:
        """The requirements' margins (≥ 0 when met), :data:`FAILED_MARGIN` where the design failed."""
        return np.array([r.margin if math.isfinite(r.margin) else FAILED_MARGIN for r in self.requirements(row)])

    def feasible(self, row: dict[str, Any]) -> bool:
        """The design was evaluated and meets every requirement (within
        :data:`~mechatron.studies.optimal_problem.REQUIREMENT_SLACK`: :meth:`Requirement.met`)."""
        return row["status"] == "ok" and all(r.met() for r in self.requirements(row))

    def table(self) -> pd.DataFrame:
        """Every design evaluated, in order: the variables, ``feasible`` and the rows' columns."""
        import pandas as pd

        rows = [{**row, "feasible": self.feasible(row)} for row in self.rows.values()]
        return pd.DataFrame(rows)


# ------------------------------------------------------------------------------------------------ methods
def first_generation(spec: DesignSpec, evaluations: Evaluations) -> np.ndarray:
    """``population`` points of the unit cube: a Latin hypercube (the study's sampler, seeded), the start (when
    given: the middle of the box for the variables it leaves out) first."""
    from .designs import latin_hypercube

    points = latin_hypercube(spec.population, len(spec.variables), spec.seed)
    if spec.start:
        middle = {p.name: (p.low + p.high) / 2 if p.values is None else p.values[0] for p in spec.variables}
        points[0] = evaluations.unit({**middle, **spec.start})
    return points


def _batch(evaluations: Evaluations, U: np.ndarray) -> list[dict[str, Any]]:
    """The rows of the points ``U`` (S, d) of the unit cube."""
    return evaluations([evaluations.design(u) for u in np.atleast_2d(U)])


def solve_global(spec: DesignSpec, evaluations: Evaluations) -> dict[str, Any]:
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


def solve_pareto(spec: DesignSpec, evaluations: Evaluations) -> dict[str, Any]:
    """Two objectives by NSGA-II (pymoo); the front is taken from every design evaluated (:func:`front_mask`)."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    count = sum((b.low is not None) + (b.high is not None) for b in spec.requirements)

    class Design(Problem):
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


def solve_exact(spec: DesignSpec, evaluations: Evaluations) -> dict[str, Any]:
    """One objective with exact first derivatives by ipopt (the module docstring)."""
    import casadi as ca

    model = ExactModel(spec)
    names = [spec.objectives[0][0], *(b.name for b in spec.requirements)]
    outputs = _Outputs(model, names)
    x = ca.MX.sym("x", len(spec.variables))
    y = outputs(x)
    sign = 1.0 if spec.objectives[0][1] == "minimize" else -1.0
    lower = np.array([p.low for p in spec.variables])
    upper = np.array([p.high for p in spec.variables])
    start = _doe_start(spec, evaluations)
    stop = _StopWhenFailing(model, len(spec.variables), len(names) - 1)
    options = {"print_time": False, "show_eval_warnings": False, "iteration_callback": stop, "ipopt": {
        "print_level": 0, "sb": "yes", "tol": spec.tolerance, "max_iter": spec.max_iterations,
        "hessian_approximation": "limited-memory", "honor_original_bounds": "yes"}}
    nlp = ca.nlpsol("design", "ipopt", {"x": x, "f": sign * y[0], "g": y[1:]}, options)
    low = [-np.inf if b.low is None else b.low for b in spec.requirements]
    high = [np.inf if b.high is None else b.high for b in spec.requirements]
    result = nlp(x0=start, lbx=lower, ubx=upper, lbg=low, ubg=high)
    stats = nlp.stats()
    best = np.clip(np.array(result["x"]).ravel(), lower, upper)
    evaluations([dict(zip(evaluations.names, (float(v) for v in best)))])
    status = str(stats.get("return_status", ""))
    if stop.stopped:
        status = f"stopped after {sum(model.failed.values())} failed trial designs ({MAX_FAILED_TRIALS} at most)"
    return {"method": "ipopt (exact derivatives, CasADi)", "success": bool(stats["success"]),
            "status": status, "iterations": int(stats.get("iter_count", 0)),
            "optimum": {n: float(v) for n, v in zip(evaluations.names, best)},
            "failed_trials": sum(model.failed.values()),
            "failed_trial_reasons": dict(sorted(model.failed.items(), key=lambda kv: -kv[1])[:3])}


#: ipopt stops once this many of the designs its line search tries have failed (not assembled, refused by an
#: analysis; each an output NaN, from which the line search steps back): our rule, so that a search pressed
#: against designs that do not assemble ends in seconds, not minutes, with the best design it reached.
MAX_FAILED_TRIALS = 200


class _StopWhenFailing:
    """ipopt's iteration callback (CasADi's ``iteration_callback``): stop once :data:`MAX_FAILED_TRIALS` trial
    designs of the model failed."""

    def __new__(cls, model: ExactModel, nx: int, ng: int):
        import casadi as ca

        class Stop(ca.Callback):
            def __init__(self) -> None:
                ca.Callback.__init__(self)
                self.stopped = False
                self.construct("stop_when_failing", {})

            def get_n_in(self) -> int:
                return ca.nlpsol_n_out()

            def get_n_out(self) -> int:
                return 1

            def get_name_in(self, i: int) -> str:
                return ca.nlpsol_out(i)

            def get_sparsity_in(self, i: int):
                name = ca.nlpsol_out(i)
                size = {"f": 1, "g": ng, "lam_g": ng, "lam_p": 0, "p": 0}.get(name, nx)
                return ca.Sparsity.dense(size, 1)

            def eval(self, arg: list) -> list:
                self.stopped = sum(model.failed.values()) >= MAX_FAILED_TRIALS
                return [1 if self.stopped else 0]

        return Stop()


def _doe_start(spec: DesignSpec, evaluations: Evaluations) -> np.ndarray:
    """The exact route's start: ``[start]`` if given, else the best feasible design of a DOE of ``population``
    points (:func:`first_generation`; the middle of the box when none is feasible)."""
    rows = _batch(evaluations, first_generation(spec, evaluations))
    if spec.start:
        return np.array([spec.start.get(p.name, (p.low + p.high) / 2) for p in spec.variables])
    feasible = [r for r in rows if evaluations.feasible(r)]
    if not feasible:
        return np.array([(p.low + p.high) / 2 for p in spec.variables])
    best = min(feasible, key=lambda r: evaluations.objectives(r)[0])
    return np.array([float(best[n]) for n in evaluations.names])


class ExactModel:
    """The outputs and their exact gradients with respect to the variables at a design (the analyses'
    ``gradients``), each design once."""

    def __init__(self, spec: DesignSpec):
        from .analyses import analysis
        from .spec import study_mechanism

        self.spec = spec
        self.mech = study_mechanism(spec.study.mechanism)
        self.names = [p.name for p in spec.variables]
        self.analyses = {name: analysis(name) for name in spec.study.analyses}
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
                    out, grad = module.gradients(mech, self.spec.study.options(name, {}), self.names)
                    values.update(out)
                    gradients.update(grad)
            except MechatronError as exc:
                self.failed[str(exc)] = self.failed.get(str(exc), 0) + 1
                values, gradients = {}, {}
            self._last = (x.tobytes(), values, gradients)
        return self._last[1], self._last[2]


def exact_available(spec: DesignSpec) -> str | None:
    """None when the exact route applies to ``spec``, else why not (in words)."""
    from .analyses import analysis

    if any(p.values is not None or p.target is not None for p in spec.variables):
        return "a variable is a list of values or an analysis option (no derivative)"
    if len(spec.objectives) != 1:
        return "two objectives (a Pareto front)"
    from .spec import study_mechanism

    mech = study_mechanism(spec.study.mechanism)
    given = {}
    for name in spec.study.analyses:
        module = analysis(name)
        if hasattr(module, "gradient_outputs"):
            given.update(dict.fromkeys(module.gradient_outputs(mech, spec.study.options(name, {})), name))
    needed = [spec.objectives[0][0], *(b.name for b in spec.requirements)]
    missing = [n for n in needed if n not in given]
    return f"no exact derivative of {', '.join(missing)}" if missing else None


class _Outputs:
    """A CasADi function x ↦ the outputs ``names`` of :class:`ExactModel`, with its exact Jacobian."""

    def __new__(cls, model: ExactModel, names: list[str]):
        import casadi as ca

        n, m = len(model.names), len(names)

        class Jacobian(ca.Callback):
            def __init__(self, name: str, opts: dict):
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

            def eval(self, arg: list) -> list:
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

            def eval(self, arg: list) -> list:
                values, _ = model(np.array(arg[0]))
                return [np.array([values.get(k, np.nan) for k in names], dtype=float)]

            def has_jacobian(self) -> bool:
                return True

            def get_jacobian(self, name: str, inames: list, onames: list, opts: dict):
                self._jacobian = Jacobian(name, opts)  # kept alive with the function
                return self._jacobian

        return Outputs()


# ------------------------------------------------------------------------------------------------- result
def front_mask(values: np.ndarray) -> np.ndarray:
    """Which rows of (n, 2) objectives (both minimised) no other row dominates
    (:func:`mechatron.studies.result.pareto_mask`)."""
    from .result import pareto_mask

    return pareto_mask(values[:, 0], values[:, 1]) if len(values) else np.zeros(0, dtype=bool)


@dataclass
class DesignResult(Result):
    """An optimal design of a design file: the best feasible design evaluated (one objective) or the Pareto front
    of every feasible design evaluated (two), the requirements at the best design, every design evaluated
    (``evaluations``: the variables, ``status``, ``reason``, the outputs, ``feasible``) and the solver's summary."""

    name: str
    mechanism: str
    objectives: tuple[tuple[str, str], ...]
    variables: tuple[str, ...]
    solver: dict[str, Any]
    evaluations: pd.DataFrame
    best: dict[str, Any] | None
    requirements: list[Requirement]
    front: pd.DataFrame | None = None
    notes: list[str] = field(default_factory=list)
    units: dict[str, str] = field(default_factory=dict)

    @property
    def feasible(self) -> bool:
        """A design meets every requirement (the best one; for two objectives, a design of the front)."""
        return self.best is not None and all(r.met() for r in self.requirements)

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

        figure = new_figure(7.0, 5.0) if ax is None else ax.get_figure()
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
        for r in self.requirements:
            sign = "≥" if r.kind == "min" else "≤"
            lines.append(f"  {r.name:<36} {r.value:12.6g} {sign} {r.limit:<10.6g} margin {r.margin:10.3g} {r.unit}"
                         f"  {r.verdict}")
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


# ------------------------------------------------------------------------------------------------ solving
def optimize_design(spec: DesignSpec | str | Path, workers: int = 1, scheduler: str | None = None,
                    progress: Any = None) -> DesignResult:
    """Solve a design file (see the module docstring) in this process (``workers = 1``), on an embedded Dask
    cluster of ``workers`` processes, or on a running ``scheduler``."""
    import warnings

    from ..io.values import number
    from .analyses import worker_modules
    from .cluster import connect, disconnect, prestart

    spec = read_design(spec) if not isinstance(spec, DesignSpec) else spec
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


def _ended(spec: DesignSpec, evaluations: Evaluations, solver: dict[str, Any]) -> str:
    """Why the search ended where it did, for the end of the progress line: stopped (an error), or the solver's
    status and, short of the budget, the designs evaluated of it (a design asked for again is not evaluated again;
    differential evolution runs whole generations; ipopt evaluates the analyses' exact derivatives, not designs)."""
    if not solver:
        return "stopped"
    done = len(evaluations.rows)
    short = f"; {done} of the budget's {spec.evaluations} designs evaluated" if done < spec.evaluations else ""
    return f"ended: {solver['method'].split(' ')[0]}: {solver['status']}{short}"


def _result(spec: DesignSpec, evaluations: Evaluations, solver: dict[str, Any], notes: list[str]) -> DesignResult:
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
    return DesignResult(spec.name, Path(spec.study.mechanism).name, spec.objectives,
                        tuple(evaluations.names), solver, table, best, requirements, front, notes,
                        _variable_units(spec))


def _variable_units(spec: DesignSpec) -> dict[str, str]:
    """The unit of each variable: its mechanism parameter's (m, rad), the registry's for an analysis option, "-"
    for a list of names."""
    from ..quantities import is_quantity, unit
    from .spec import study_mechanism

    mech = study_mechanism(spec.study.mechanism)
    out = {}
    for p in spec.variables:
        option = p.target.split(".", 1)[1] if p.target else None
        if option is None:
            out[p.name] = mech.parameters[p.name].unit
        else:
            out[p.name] = unit(option) if is_quantity(option) and p.values is None else "-"
    return out


# ------------------------------------------------------------------------------------------------ writing
#: The mark of a design file written by ``optimize -o`` (its header comment begins so): a file in the folder named
#: ``design-NNN.toml`` or ``.urdf`` with it is a companion of an earlier run.
DESIGN_MARK = "mechatron optimize: design "


def output_files(folder: str | Path) -> list[Path]:
    """The files ``optimize -o folder`` may replace or remove: ``optimum.json``, ``designs.csv`` and every
    ``design-NNN.toml`` or ``.urdf`` already there (no command reads them: :func:`mechatron.io.output.will_write`)."""
    folder = Path(folder)
    return [folder / "optimum.json", folder / "designs.csv", *_design_files(folder)]


def _design_files(folder: Path) -> list[Path]:
    import re

    try:
        names = sorted(p for p in folder.iterdir() if re.fullmatch(r"design-\d{3,}\.(toml|urdf)", p.name))
    except OSError:
        return []
    return [p for p in names if p.is_file()]


def earlier_designs(folder: str | Path) -> list[Path]:
    """The design files an earlier ``optimize -o`` wrote in ``folder`` (named ``design-NNN``, with
    :data:`DESIGN_MARK` in their first lines); any other file is left alone."""
    from ..io.output import unchecked

    out = []
    for path in _design_files(Path(folder)):
        try:
            with unchecked(), open(path, "rb") as fh:
                head = fh.read(400).decode("utf-8", "replace")
        except OSError:
            continue
        if DESIGN_MARK in head:
            out.append(path)
    return out


@dataclass
class DesignFile:
    """A design drawn as a mechanism file: its path, its text (written only if it reads back) and, where it does
    not read back, the error naming that file."""

    path: Path
    text: str
    error: InputError | None = None


def draw_designs(spec: DesignSpec, designs: pd.DataFrame, folder: str | Path) -> list[DesignFile]:
    """Each design (a row of the variables) as the text of a mechanism file ``folder/design-NNN``: a planar or
    spatial mechanism file for a mechanism read from one, with its parameters at the design's values, drawn at the
    pose the search evaluated (:func:`_redrawn`); else a URDF of the rebuilt mechanism. Analysis options among the
    variables are not part of a mechanism and are left out. A mechanism file is read back from its text before it
    is written; where it does not read back, its :attr:`DesignFile.error` names the file being written, its field
    and why. Nothing is written here."""
    from ..io.toml import read_toml
    from ..library import robot_origins
    from ..model.linkage_file import is_linkage_file, linkage_spec, linkage_toml
    from ..model.urdf import to_urdf
    from .spec import study_mechanism

    source = Path(spec.study.mechanism)
    if not source.is_file():
        source = robot_origins().get(spec.study.mechanism, (None, None))[1] or source
    data = read_toml(source) if source.suffix.lower() == ".toml" else None
    linkage = linkage_spec(data, file=source) if data is not None and is_linkage_file(data) else None
    mech = study_mechanism(spec.study.mechanism)
    folder = Path(folder)
    geometry = [p.name for p in spec.variables if p.target is None]
    out = []
    for k, (_, row) in enumerate(designs.iterrows()):
        values = {n: float(row[n]) for n in geometry}
        header = f"{DESIGN_MARK}{k} of {spec.name}: " + ", ".join(f"{n} = {v:.9g}" for n, v in values.items())
        design = mech.with_parameters(values)
        if linkage is None:
            text = to_urdf(design).replace("?>", f"?>\n<!-- {header} -->", 1)
            out.append(DesignFile(folder / f"design-{k:03d}.urdf", text))
            continue
        path = folder / f"design-{k:03d}.toml"
        every = {**mech.parameter_values(), **values}
        drawn = _redrawn(linkage, design, every) if linkage.planar else _moved(linkage, every)
        text = linkage_toml(drawn, header)
        out.append(DesignFile(path, text, _read_back_error(text, path)))
    return out


def write_designs(spec: DesignSpec, designs: pd.DataFrame, folder: str | Path) -> list[Path]:
    """Write the designs of :func:`draw_designs` in ``folder`` (created if needed), all of them or, where one does
    not read back, none (:class:`InputError` naming that file). Returns the paths written."""
    from ..io.output import output_directory, transaction, write_text

    files = draw_designs(spec, designs, folder)
    for f in files:
        if f.error is not None:
            raise f.error
    with transaction():
        output_directory(folder)
        return [write_text(f.path, f.text) for f in files]


def write_optimum(spec: DesignSpec, result: DesignResult, folder: str | Path
                  ) -> tuple[list[Path], list[InputError]]:
    """``mechatron optimize -o DIR``: first the results — ``optimum.json`` (:meth:`DesignResult.as_dict`) and
    ``designs.csv`` (every design evaluated: the variables, ``status``, ``reason``, the outputs, ``feasible``) —
    then the best design (two objectives: every design of the front) as mechanism files (:func:`draw_designs`),
    each one that reads back. The design files of an earlier run there (:func:`earlier_designs`) that this run
    does not write are removed in the same commit. Returns the paths written and the errors of the designs not
    written (each naming its file), so that a design that cannot be written never discards the results."""
    import pandas as pd

    from ..io.output import output_directory, stage_removal, transaction, write_table, write_text

    files: list[DesignFile] = []
    with transaction():
        folder = output_directory(folder)
        written = [write_text(folder / "optimum.json", result.to_json() + "\n"),
                   write_table(result.evaluations, folder / "designs.csv")]
        if result.best is not None:
            front = result.front if result.front is not None else pd.DataFrame([result.best])
            files = draw_designs(spec, front, folder)
            written += [write_text(f.path, f.text) for f in files if f.error is None]
        for path in earlier_designs(folder):  # an earlier run's designs: removed in the same commit
            if path not in written:
                stage_removal(path)
    return written, [f.error for f in files if f.error is not None]


def _redrawn(linkage: Any, design: Any, values: dict[str, float]) -> Any:
    """The linkage spec of a design (:func:`~mechatron.model.linkage.parameter_spec`: every length declared at its
    value, the points' coordinates moved) drawn at the design's assembled pose: every drawn point where the
    design's mechanism (``design``, rebuilt as the search evaluated it: its loops closed with the actuated inputs
    held where the file holds them) has it at its reference configuration, a point's direction (a slider's
    line) turned with its body and a centre of mass given by world coordinates moved with it. A design's moved
    pins (a cylinder's base) can put the *drawn* pose outside a cylinder's stroke; drawn at the assembled pose,
    each held input is at the value the file held it at, within its stroke, and the loops close as drawn."""
    import pinocchio as pin

    from ..model.linkage import parameter_spec

    model, data = design.model, design.model.createData()
    pin.framesForwardKinematics(model, data, np.asarray(design.reference_q, dtype=float))
    redrawn = parameter_spec(linkage, values)
    points = []
    for p in redrawn.points:
        if p.at is None or p.between is not None or not model.existFrame(p.name):
            points.append(p)
            continue
        placement = data.oMf[model.getFrameId(p.name)]
        at = tuple(float(v) for v in placement.translation[:len(p.at)])
        direction = p.direction
        if direction is not None and len(direction) == 2:  # planar: the frame's x axis is the point's direction
            direction = tuple(float(v) for v in placement.rotation[:2, 0] * np.linalg.norm(direction))
        points.append(replace(p, at=at, direction=direction))
    bodies = []
    for b in redrawn.bodies:  # a centre of mass given by world coordinates moves with its body
        if isinstance(b.com, tuple) and b.mass > 0 and model.existFrame(b.name, pin.FrameType.BODY):
            joint = model.frames[model.getFrameId(b.name, pin.FrameType.BODY)].parentJoint
            b = replace(b, com=tuple(float(v) for v in data.oMi[joint].act(model.inertias[joint].lever)[:2]))
        bodies.append(b)
    return replace(redrawn, points=tuple(points), bodies=tuple(bodies))


def _moved(linkage: Any, values: dict[str, float]) -> Any:
    """A spatial linkage spec with its drawn points at the design's coordinates ``POINT_x``, ``_y``, ``_z`` (m), as
    its rebuild draws it (:func:`mechatron.model.spatial.build_spatial`: its loops closed from that drawing)."""
    return linkage.with_positions({p.name: [values.get(f"{p.name}_{a}", v) for a, v in zip("xyz", p.at)]
                                   for p in linkage.points if p.at is not None and p.between is None})


def _read_back_error(text: str, path: Path) -> InputError | None:
    """Why the mechanism file ``text`` (to be written to ``path``) would not read back, or None: it is read and
    built as a file at ``path`` would be."""
    from ..errors import MechatronError
    from ..io.toml import tomllib
    from ..model.linkage_file import linkage_spec
    from ..model.spatial import build_mechanism

    try:
        build_mechanism(linkage_spec(tomllib.loads(text), file=path))
    except InputError as exc:
        return InputError(f"the design does not read back, so it is not written: {exc.message}", file=path,
                          row=exc.row, field=exc.field)
    except MechatronError as exc:
        return InputError(f"the design does not read back, so it is not written: {exc}", file=path)
    return None

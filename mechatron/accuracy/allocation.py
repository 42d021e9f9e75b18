r"""Tolerance allocation at least cost: the tolerances that keep a point's error within a limit at every pose for the
smallest total cost [Chase].

The error sources e_i have sensitivities J = ∂r/∂e at each pose p (:mod:`~mechatron.accuracy.sensitivity`, exact),
biases b_i and tolerances t_i. The error is the one :mod:`~mechatron.accuracy.study` reports, per axis a and with
β = |J b|:

- ``worst``: Δ_a = β_a + Σ_i |J_ai| t_i;
- ``rss``:   Δ_a = β_a + √(Σ_i (J_ai c_i t_i)²), c_i = kσ_i/t_i (1 for a normal error, σ = t/k; k/√3 uniform;
  k/√6 triangular);

|Δr|_p = √(Σ_a Δ_a²), a closed form in t given J. Every row with a cost model (:mod:`~mechatron.accuracy.costs`)
gets a tolerance, every other row keeps its own, so as to

    minimise Σ_i C_i(t_i)   subject to   |Δr|_p(t) ≤ L at every pose p,

- continuous costs C = a + b/t^k with t_min ≤ t ≤ t_max: ipopt (CasADi, exact first and second derivatives) in
  x = ln t. In x the problem is convex (b e^(−kx) is convex; Δ_a is a sum, or a Euclidean norm, of positive
  exponentials, and its square is convex), so the point ipopt finds is the global optimum. With RSS, normal errors,
  no bias and C = b/t the optimum is Lagrange's closed form t_i ∝ (b_i/s_i²)^(1/3), s_i = |∂r/∂e_i|, and with the
  worst case along one axis t_i ∝ √(b_i/s_i) [Chase, Lagrange multiplier solution];
- process tables (a cost per allowed tolerance): an exact branch and bound over the rows' options [Chase, process
  selection]. A node fixes the options of the first rows; it is dropped when even the tightest options of the rest
  (and the continuous rows at t_min) exceed L at some pose (the error rises with every tolerance), or when its bound
  — the costs fixed plus the cheapest option of every other row and every continuous row at t_max — is no lower
  than the best found; when the loosest (cheapest) completion meets L it is the node's optimum. Every combination is
  thus accounted for, none skipped by a greedy choice;
- a mix: the same branch and bound over the process rows, the continuous rows solved by ipopt at each leaf.

The allocation is then verified: the study's worst/RSS error with the allocated tolerances, and a seeded Monte
Carlo of the full nonlinear model (:func:`~mechatron.accuracy.study.analyse_tolerances`), |Δr| at the coverage of
±kσ against L at every pose.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, MechatronError
from ..io.values import LARGEST, number, numbers
from ..model.mechanism import Mechanism
from .allocation_result import AllocationResult
from .costs import ContinuousCost, CostedSource, ProcessTable, read_cost_models
from .error_model import ErrorModel
from .sensitivity import coordinate_names, sensitivities
from .study import analyse_tolerances, configurations

__all__ = ["ALLOCATION_METHODS", "AllocationResult", "ErrorModel", "allocate_tolerances"]

Floats = NDArray[np.float64]

ALLOCATION_METHODS = ("rss", "worst")
#: The largest number of branch-and-bound nodes, and of ipopt solves at its leaves, before the search gives up.
MAX_NODES, MAX_SOLVES = 2_000_000, 5_000
#: Relative slack of the limit when checking a point (rounding of the sums, ipopt's constraint tolerance).
SLACK = 1e-9


class _ContinuousRows:
    """ipopt on the continuous rows (x_j = ln(t_j/u_j), u_j the unit of the row's cost), the process rows' tolerances
    a parameter: :meth:`solve` gives the cheapest continuous tolerances for given process tolerances."""

    def __init__(self, model: ErrorModel, costed: Sequence[CostedSource], continuous: Sequence[int],
                 discrete: Sequence[int], base: Floats, limit: float) -> None:
        import casadi as ca

        self.continuous, self.discrete = list(continuous), list(discrete)
        self.models = [costed[j].continuous() for j in self.continuous]
        x = ca.SX.sym("x", len(self.continuous))
        p = ca.SX.sym("p", len(self.discrete))
        entries = [ca.SX(float(v)) for v in base]
        for m, j in enumerate(self.continuous):
            entries[j] = self.models[m].factor * ca.exp(x[m])
        for m, j in enumerate(self.discrete):
            entries[j] = p[m]
        symbolic = [j in self.continuous or j in self.discrete for j in range(len(base))]
        g = model.squared(ca.vertcat(*entries), symbolic, base) / limit**2
        f = sum((c.a + c.b * ca.exp(-c.k * x[m]) for m, c in enumerate(self.models)), ca.SX(0))
        options: dict[str, Any] = {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-12,
                                                  "constr_viol_tol": 1e-12, "max_iter": 3000}}
        self.solver = ca.nlpsol("allocation", "ipopt", {"x": x, "p": p, "f": f, "g": g}, options)
        self.lower = np.log([c.lower / c.factor for c in self.models])
        self.upper = np.log([c.upper / c.factor for c in self.models])
        self.start = (self.lower + self.upper) / 2
        self.solves, self.iterations = 0, 0

    def solve(self, discrete: Floats) -> tuple[Floats, float, bool]:
        """(continuous tolerances (SI), their cost, whether ipopt converged) for the process rows' ``discrete``."""
        solution = self.solver(x0=self.start, p=discrete, lbx=self.lower, ubx=self.upper, lbg=-np.inf, ubg=1.0)
        stats = self.solver.stats()
        self.solves += 1
        self.iterations += int(stats.get("iter_count", 0))
        x = np.clip(np.asarray(solution["x"], dtype=float).ravel(), self.lower, self.upper)
        self.start = x
        t = np.array([c.factor for c in self.models]) * np.exp(x)
        return t, float(sum(c.cost(v) for c, v in zip(self.models, t))), bool(stats.get("success"))


def _search(model: ErrorModel, costed: Sequence[CostedSource], base: Floats, limit: float,
            continuous: _ContinuousRows | None) -> tuple[Floats, float, dict]:
    """The cheapest tolerances (SI) meeting the limit, their cost and the search's statistics (module docstring)."""
    discrete = [j for j, c in enumerate(costed) if isinstance(c.model, ProcessTable)]
    tables = [costed[j].table() for j in discrete]
    cont = continuous.continuous if continuous else []
    cont_models = [costed[j].continuous() for j in cont]
    cheapest_cont = sum(c.cost(c.upper) for c in cont_models)
    cheapest_rest = np.concatenate([np.cumsum([tb.costs[0] for tb in tables][::-1])[::-1], [0.0]])
    bound_limit = limit * (1 + SLACK)
    best: dict = {"cost": math.inf, "t": None}
    stats = {"nodes": 0, "solves": 0, "converged": True}

    def point(choice: Sequence[int], rest: str) -> Floats:
        t = base.copy()
        for m, j in enumerate(discrete):
            option = choice[m] if m < len(choice) else (0 if rest == "loose" else -1)
            t[j] = tables[m].tolerances[option]
        for m, j in enumerate(cont):
            t[j] = cont_models[m].upper if rest == "loose" else cont_models[m].lower
        return t

    def visit(choice: list[int]) -> None:
        stats["nodes"] += 1
        if stats["nodes"] > MAX_NODES:
            raise InputError(f"the process search passed {MAX_NODES:,} nodes: give fewer process rows or options")
        depth = len(choice)
        if model.norm(point(choice, "tight")).max() > bound_limit:
            return  # even the tightest completion fails: no combination below this node meets the limit
        fixed = sum(tables[m].costs[o] for m, o in enumerate(choice))
        bound = fixed + cheapest_rest[depth] + cheapest_cont
        if bound >= best["cost"]:
            return
        loose = point(choice, "loose")
        if model.norm(loose).max() <= bound_limit:  # the cheapest completion meets the limit: this node's optimum
            best.update(cost=bound, t=loose)
            return
        if depth == len(discrete):  # a leaf with continuous rows: ipopt
            if stats["solves"] >= MAX_SOLVES:
                raise InputError(f"the process search passed {MAX_SOLVES:,} continuous solves: give fewer process "
                                 "rows or options")
            stats["solves"] += 1
            values, cost, converged = continuous.solve(loose[discrete])  # type: ignore[union-attr]
            t = loose.copy()
            t[cont] = values
            if model.norm(t).max() <= limit * (1 + 1e-6) and fixed + cost < best["cost"]:
                best.update(cost=fixed + cost, t=t)
                stats["converged"] &= converged
            return
        for option in range(len(tables[depth].tolerances)):
            visit([*choice, option])

    visit([])
    if best["t"] is None:
        raise MechatronError("the allocation found no tolerances meeting the limit although the tightest ones do "
                             "(ipopt did not converge); report this with the inputs")
    return best["t"], best["cost"], stats


def _costed(mech: Mechanism, sources: Sequence[CostedSource] | str | Path, processes) -> list[CostedSource]:  # noqa: ANN001
    if isinstance(sources, (str, Path)):
        return read_cost_models(sources, mech, processes)
    return list(sources)


def allocate_tolerances(mech: Mechanism, sources: Sequence[CostedSource] | str | Path, poses: ArrayLike,
                        labels: Sequence[str] | None = None, limit: float | None = None, *, method: str = "rss",
                        k: float = 3.0, frame: str | None = None, processes=None,  # noqa: ANN001
                        samples: int = 10000, seed: int = 0, progress: Callable[[int, int], None] | None = None
                        ) -> AllocationResult:
    """The least-cost tolerances keeping |Δr| of ``method`` within ``limit`` at every pose (module docstring).

    Args:
        mech: The mechanism.
        sources: The error sources with their cost models (:func:`~mechatron.accuracy.costs.read_cost_models`), or
            a tolerances CSV path (then ``processes``: its process tables, a path or the tables).
        poses: Coordinate values (N, n_c) (rad, m), as :func:`~mechatron.accuracy.study.analyse_tolerances` takes.
        labels: A label per pose (default 1, 2, …).
        limit: The largest |Δr| allowed (m).
        method: ``rss`` or ``worst``: the error the limit bounds.
        k: The coverage factor (σ = t/k for normal errors).
        frame: The frame whose position is bounded (default the tool frame).
        samples, seed: The verifying Monte Carlo's samples per pose and seed.
        progress: Called with (samples done, samples in all) during the Monte Carlo.

    Raises:
        InputError: a bad input, no row with a cost model, or a limit below the unavoidable error (naming the pose
            and the smallest |Δr| the tightest allowed tolerances reach there).
    """
    if method not in ALLOCATION_METHODS:
        raise InputError(f"tolerance allocation bounds the rss or the worst-case error, not {method!r} (every "
                         "allocation is verified by a Monte Carlo of the full model)")
    limit = number("limit", limit, positive=True, unit="m")
    k = number("k", k, minimum=0.1, maximum=100.0)
    samples = number("samples", samples, integer=True, minimum=2)
    seed = number("seed", seed, integer=True, minimum=0)
    costed = _costed(mech, sources, processes)
    if not costed:
        raise InputError("no error sources")
    if not any(c.model is not None for c in costed):
        raise InputError("no row has a cost model (cost_b with tolerance_min and tolerance_max, or process): nothing "
                         "to allocate")
    frame = frame or mech.tool_frame
    poses = np.atleast_2d(numbers("poses", poses, minimum=-LARGEST, unit="rad or m"))
    labels = list(labels) if labels is not None else [str(i + 1) for i in range(len(poses))]
    Q = configurations(mech, poses, labels)
    if not mech.closures:
        mech.warn_limits(Q, "poses", [f"pose {label}" for label in labels])
    plain = [c.source for c in costed]
    sens = sensitivities(mech, Q, frame, [s.name for s in plain if s.kind == "parameter"],
                         [s.name for s in plain if s.kind == "coordinate"])
    index = {name: i for i, name in enumerate(sens.sources)}
    J = sens.matrix[:, :, [index[s.name] for s in plain]]
    c = np.ones(len(plain)) if method == "worst" else \
        np.array([k * dataclasses.replace(s, tolerance=1.0).sigma(k) for s in plain])
    model = ErrorModel(method, J, np.abs(J @ np.array([s.bias for s in plain])), c)
    tightest = np.array([_tightest(cs) for cs in costed])
    reach = model.norm(tightest)
    worst = int(np.argmax(reach))
    if reach[worst] > limit * (1 + SLACK):
        raise InputError(f"the limit {limit * 1e3:.4g} mm is below the unavoidable error: at pose {labels[worst]} "
                         f"the tightest allowed tolerances give |Δr| = {reach[worst] * 1e3:.4g} mm ({method})")
    base = np.array([cs.source.tolerance for cs in costed])
    continuous = [j for j, cs in enumerate(costed) if isinstance(cs.model, ContinuousCost)]
    discrete = [j for j, cs in enumerate(costed) if isinstance(cs.model, ProcessTable)]
    solver = _ContinuousRows(model, costed, continuous, discrete, base, limit) if continuous else None
    t, total, stats = _search(model, costed, base, limit, solver)
    notes = []
    if solver is not None:
        stats["solves"], stats["iterations"] = solver.solves, solver.iterations
        if not stats["converged"]:
            notes.append("ipopt stopped before its tolerance at the chosen point; the point meets the limit")
    allocated = [dataclasses.replace(cs.source, tolerance=float(v)) for cs, v in zip(costed, t)]
    study = analyse_tolerances(mech, allocated, poses, labels, frame=frame, methods=(method, "mc"), k=k,
                               samples=samples, seed=seed, limit=limit, progress=progress)
    achieved = model.norm(t)
    search = {"continuous": len(continuous), "process": len(discrete),
              "kind": ("ipopt" if not discrete else "branch and bound" + (" with ipopt at the leaves"
                                                                           if continuous else "")), **stats}
    return AllocationResult.build(mech.name, frame, method, k, limit, costed, t, total, model, achieved, study,
                                  labels, tuple(coordinate_names(mech)), poses, search, notes, samples, seed)


def _tightest(costed: CostedSource) -> float:
    if isinstance(costed.model, ContinuousCost):
        return costed.model.lower
    if isinstance(costed.model, ProcessTable):
        return costed.model.tolerances[-1]
    return costed.source.tolerance

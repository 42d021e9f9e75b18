r"""A front shovel [Shovel] with the lightest catalog cylinders: pin positions and one catalog row per cylinder.

The design is that of :class:`~mechatron.optimal.problems.shovel.ShovelProblem` (the cylinders' pin coordinates and
the link lengths; the joint ranges fixed by the working range, each stroke spanning its joint's range) and, per
chosen cylinder j, a row
r_j of a hydraulic-cylinder catalog. The objective is the total mass of the cylinders (kg),

    M = Σ_j n_j (m_r + m'_r · s_j),   s_j = |L_j(θ_max) − L_j(θ_min)|,

with n_j cylinders side by side (the twin boom cylinder: n = 2), m_r the row's mass and m'_r its mass per metre of
stroke. Besides the geometric requirements of the shovel problem (λ, transmission angle, special positions inside
the stroke), each chosen row passes the catalog checks of :mod:`mechatron.drives.cylinders` at the holding forces
F_jk of the special positions k (N, > 0 pushing) and the design's stroke, with p = min(p_s, p_r):

- rated pressure  p_s ≤ p_r (relief pressure p_s; a constant: rows rated below it are never chosen);
- push            F_jk ≤ n_j A_p p,   pull  −F_jk ≤ n_j A_a p   (A_p = π D²/4, A_a = A_p − π d²/4);
- stroke          s_j ≤ the row's maximum stroke;
- rod buckling    F_jk / n_j ≤ F_E(L_max) / 3.5,  F_E(L) = π² E (π d⁴/64) / (K L)²  (the cylinder fully extended,
  L_max = max(L_j(θ_min), L_j(θ_max)): what :func:`~mechatron.drives.cylinders.size_cylinder` checks without the
  lengths of a task).

The choice of rows is discrete, so the problem is solved by DOE-then-refine (:func:`descend`):

1. DOE: every design of the DOE (the same box, ``design_of_experiments``) that meets the geometric requirements gets,
   per cylinder, the lightest catalog row passing every check (``size_cylinder`` ranked by mass on the forces of the
   CasADi expressions); the lightest design, or the start if it is lighter, and its rows start the search.
2. Refine: the rows fixed, ipopt minimises M over the pins subject to every requirement, the rows' checks written as
   smooth rows g(x) ≥ 0 of the same SX forces and lengths (kept 1e-6 inside their limits, so that the Pinocchio
   model's forces, equal to ~1e-9 to 1e-7, pass the drives module's checks).
3. Descend: per cylinder, the catalog rows lighter at the current design are tried, the next lighter first, each by
   the same NLP from the current design; a lighter total that meets every requirement (by the CasADi expressions
   and by the Pinocchio model) is accepted, and the descent repeats until no row is accepted.

Every accepted step lowers M, so the optimum is never heavier than the DOE's best by construction; it is a local
optimum in the pins and in the discrete choice (one row changed at a time), not a global one. The optimum is judged
as every other: the Pinocchio model's forces and lengths, each cylinder sized afresh by ``size_cylinder`` over the
whole catalog (the lightest row passing every check), which is the independent confirmation of the choice.
"""

from __future__ import annotations

import inspect
import math
from dataclasses import replace
from typing import Any

import numpy as np
import pandas as pd

from ...drives.cylinders import BUCKLING_SAFETY, cylinder_areas, size_cylinder
from ...drives.duty import JointDuty
from ...drives.shafts import euler_load, fixing_factors
from ...errors import InputError, MechatronError
from ..requirement import Requirement, Vector
from .nlp import DesignOfExperiments, Solution, solve
from .shovel import CYLINDERS, ShovelProblem

#: The relief pressure the drives module sizes cylinders at by default (Pa).
DEFAULT_PRESSURE = float(inspect.signature(size_cylinder).parameters["pressure"].default)
#: The relative margin the NLP keeps inside each catalog limit.
BACK_OFF = 1e-6


def cylinder_mass(row: pd.Series, stroke: Any, count: int) -> Any:
    """n (m + m' s) (kg) of ``count`` cylinders of a catalog row with stroke s (m; a number or SX); a mass left
    empty in the catalog (or its column missing) counts as 0, as in ``size_cylinder``."""
    def known(key: str) -> float:
        value = float(row.get(key, math.nan))
        return value if math.isfinite(value) else 0.0

    return count * (known("mass") + known("mass_per_stroke") * stroke)


class MassProblem(ShovelProblem):
    """The front shovel with the lightest catalog cylinders (see the module docstring).

    Args:
        mech, bounds, start, **shovel: as :class:`~mechatron.optimal.problems.shovel.ShovelProblem`.
        catalog: the hydraulic cylinders (``read_catalog(path, "cylinders")``, SI units).
        pressure: the relief pressure p_s (Pa).

    ``rows`` (cylinder → catalog row index) fixes the rows of the NLP and of :meth:`judge`; ``None`` (the default)
    lets :meth:`judge` choose the lightest passing rows. ``choice`` is the catalog choice of the last judged design.
    """

    objective_name = "cylinder_mass"
    objective_unit = "kg"
    scale = 1e-2

    def __init__(self, mech: Any, bounds: dict[str, tuple[float, float]], start: dict[str, float] | None = None, *,
                 catalog: pd.DataFrame, pressure: float = DEFAULT_PRESSURE, **shovel: Any) -> None:
        super().__init__(mech, bounds, start, **shovel)
        self.catalog = catalog.reset_index(drop=True)
        self.pressure = float(pressure)
        self.rows: dict[str, int] | None = None
        self.choice: list[dict[str, Any]] = []
        self.title = "front shovel [Shovel]: least mass of the catalog cylinders " + ", ".join(self.cylinders)

    # ------------------------------------------------------------------------------------------ numbers
    def _stroke(self, parts: dict[str, Any], c: str) -> tuple[float, float]:
        j = list(CYLINDERS).index(c)
        lo, hi = parts["sweep_lengths"][j], parts["sweep_lengths"][-3 + j]
        return float(min(lo, hi)), float(max(lo, hi))

    def size(self, q: Vector, c: str, rows: list[int] | None = None) -> Any:
        """``size_cylinder`` of cylinder c at the quantities q: its duty the holding forces at the special positions
        (N), its stroke the design's, over the catalog rows ``rows`` (default all), ranked by mass."""
        parts = self._split(np.asarray(q, dtype=float))
        forces = np.array(parts["forces"][list(CYLINDERS).index(c)::3], dtype=float)
        stroke = self._stroke(parts, c)
        zero = np.zeros(len(forces))
        duty = JointDuty(c, "prismatic", np.arange(len(forces), dtype=float), zero, zero, forces, forces, 0.0,
                         stroke[1] - stroke[0])
        spec = replace(self.mech.cylinders[c], stroke=stroke)
        catalog = self.catalog if rows is None else self.catalog.iloc[rows]
        return size_cylinder(duty, spec, catalog, pressure=self.pressure, objective="mass")

    def judge(self, q: Vector) -> tuple[float, list[Requirement]]:
        """(M, requirements): the shovel problem's requirements and, per cylinder, the five catalog checks of its
        row (``rows``, or the lightest passing one, or the closest when none passes) by ``size_cylinder``."""
        _, requirements = super().judge(q)
        parts = self._split(np.asarray(q, dtype=float))
        total, self.choice = 0.0, []
        for c in self.cylinders:
            sizing = self.size(q, c, None if self.rows is None else [self.rows[c]])
            short, long = self._stroke(parts, c)
            index = int(np.flatnonzero(self.catalog["key"].to_numpy() == sizing.cylinder)[0])
            mass = float(cylinder_mass(self.catalog.iloc[index], long - short, sizing.count))
            total += mass
            self.choice.append({"cylinder": c, "key": sizing.cylinder, "row": index, "count": sizing.count,
                                "bore": sizing.cylinder_data["bore"], "rod": sizing.cylinder_data["rod"],
                                "stroke": long - short, "length_max": long, "mass": mass,
                                "feasible": sizing.feasible, "checks": [x.as_dict() for x in sizing.checks]})
            requirements += [Requirement(f"{c}_catalog_{x.name.replace(' ', '_')}_{x.unit}", x.value, x.limit, "max",
                                         x.unit) for x in sizing.checks]
        return total, requirements

    def rows_of(self, q: Vector) -> dict[str, int] | None:
        """The lightest passing catalog row of each cylinder at q (None if a cylinder has none)."""
        saved, self.rows = self.rows, None
        try:
            self.judge(q)
        finally:
            self.rows = saved
        return {x["cylinder"]: x["row"] for x in self.choice} if all(x["feasible"] for x in self.choice) else None

    # ------------------------------------------------------------------------------------------ NLP
    def nlp_terms(self, q: Any) -> tuple[Any, Any, Any]:
        """No auxiliary variable; f = scale · M; g: each cylinder's geometric rows and its row's checks (module
        docstring), scaled to O(1) (forces in MN, F L² in MN·m²), 1e-6 inside the limits, and with free links the
        rows that keep the range formulas defined."""
        import casadi as ca

        if self.rows is None:
            raise InputError("the catalog rows must be chosen before the NLP is built")
        parts = self._split(q)
        keep = 1 - BACK_OFF
        rows, mass = [], 0
        for c in self.cylinders:
            j = list(CYLINDERS).index(c)
            rows += self.cylinder_rows(parts, j)
            lo, hi = parts["sweep_lengths"][j], parts["sweep_lengths"][-3 + j]
            stroke, longest = ca.fabs(hi - lo), ca.fmax(lo, hi)
            row = self.catalog.iloc[self.rows[c]]
            n = self.mech.cylinders[c].count
            mass += cylinder_mass(row, stroke, n)
            piston, annulus = (float(area) for area in cylinder_areas(row["bore"], row["rod"]))
            p = min(self.pressure, float(row["max_pressure"]))
            K = fixing_factors([row.get("end_fixing", "")])[0][0]
            allowed = float(euler_load(row["rod"], 1.0, K)) / BUCKLING_SAFETY  # F_E(L) L² / 3.5 (N·m²)
            for f in parts["forces"][j::3]:
                rows += [1e-6 * (keep * n * piston * p - f), 1e-6 * (keep * n * annulus * p + f),
                         1e-6 * (keep * allowed - f / n * longest**2)]
            rows.append(keep * float(row["max_stroke"]) - stroke)
        return ca.SX(0, 1), self.scale * mass, ca.vertcat(*rows, self.reach_rows())

    def aux_guess(self, q: Vector) -> Vector:
        return np.zeros(0)


# ------------------------------------------------------------------------------------------------ the search
def _refine(problem: MassProblem, x: Vector, rows: dict[str, int], options: dict[str, Any]
            ) -> tuple[Solution, float] | None:
    """ipopt from x with the rows fixed: (solution, M) if it succeeds and its design meets every requirement by the
    CasADi expressions and by the Pinocchio model (which must be able to rebuild it), else None."""
    start, problem.start, problem.rows = problem.start, np.asarray(x, dtype=float), dict(rows)
    try:
        solution = solve(problem, **options)
        if not solution.success:
            return None
        mass, requirements = problem.judge(problem.values(solution.x))
        if not all(r.met() for r in requirements):
            return None
        try:
            _, requirements = problem.judge(problem.evaluate(solution.x))
        except MechatronError:  # a drawing the mechanism file cannot be rebuilt to
            return None
        return (solution, mass) if all(r.met() for r in requirements) else None
    finally:
        problem.start, problem.rows = start, None


def _lighter(problem: MassProblem, x: Vector, c: str, row: int) -> list[int]:
    """The catalog rows of cylinder c lighter than ``row`` at the design x (its stroke) and rated for the relief
    pressure, the heaviest (the next lighter) first."""
    short, long = problem._stroke(problem._split(problem.values(x)), c)
    n = problem.mech.cylinders[c].count
    mass = [float(cylinder_mass(r, long - short, n)) for _, r in problem.catalog.iterrows()]
    rated = problem.catalog["max_pressure"].to_numpy() >= problem.pressure
    lighter = [i for i in range(len(mass)) if rated[i] and mass[i] < mass[row] * (1 - 1e-12)]
    return sorted(lighter, key=lambda i: -mass[i])


def descend(problem: MassProblem, doe: DesignOfExperiments, *, max_iterations: int = 200, tolerance: float = 1e-12,
            solver: str = "ipopt") -> tuple[Solution, list[dict[str, Any]]]:
    """Steps 1–3 of the module docstring: (the final solution, the steps taken: name, rows, M in kg). The DOE
    must have been judged with ``problem.rows = None`` (each design with its lightest passing rows).

    Raises:
        InputError: (field ``objective.catalog``) when neither a DOE design nor the start has a catalog row passing
            every check for every cylinder while meeting the geometric requirements.
    """
    options = dict(max_iterations=max_iterations, tolerance=tolerance, solver=solver)
    problem.rows = None
    candidates = [(float(doe.objective[i]), doe.points[i], "DOE best") for i in np.flatnonzero(doe.feasible)]
    mass, requirements = problem.judge(problem.values(problem.start))
    if all(r.met() for r in requirements):
        candidates.append((mass, problem.start, "start"))
    # the lightest candidate whose every cylinder has a row passing the drives module's checks (exactly: a
    # requirement counts as met 1e-6 beyond its limit, a drives check only 1e-9)
    found = ((m, x, name, problem.rows_of(problem.values(x))) for m, x, name in sorted(candidates, key=lambda c: c[0]))
    mass, x, name, rows = next((c for c in found if c[3] is not None), (0.0, None, "", None))
    if rows is None or x is None:
        raise InputError(f"no catalog cylinders pass every check at any of the {len(doe.points)} DOE designs or the "
                         "start that meet the geometric requirements; give larger cylinders, a wider box or more DOE "
                         "points", field="objective.catalog")
    key = problem.catalog["key"]
    steps = [{"step": name, "rows": {c: key[r] for c, r in rows.items()}, "mass": mass}]
    history: list[float] = []
    iterations = 0
    solution = Solution(np.asarray(x, dtype=float), np.zeros(0), False,
                        f"{solver} did not refine the {name} design; kept", 0, [mass])
    refined = _refine(problem, x, rows, options)
    if refined is not None:
        solution, mass = refined
        history, iterations = list(solution.history), solution.iterations
        steps.append({"step": "refine", "rows": steps[0]["rows"], "mass": mass})
    improved = True
    while improved:
        improved = False
        for c in problem.cylinders:
            for r in _lighter(problem, solution.x, c, rows[c]):
                trial = _refine(problem, solution.x, {**rows, c: r}, options)
                if trial is not None and trial[1] < mass * (1 - 1e-12):
                    (solution, mass), rows[c], improved = trial, r, True
                    history += solution.history
                    iterations += solution.iterations
                    steps.append({"step": f"descend {c}", "rows": {k: key[v] for k, v in rows.items()},
                                  "mass": mass})
                    break
    return replace(solution, iterations=iterations, history=history or solution.history), steps


# ------------------------------------------------------------------------------------------------ the spec
def catalog_options(objective: Any, folder: Any) -> dict[str, Any]:
    """``catalog`` (a CSV of hydraulic cylinders, relative to the spec's folder; default the shipped one) and
    ``pressure_MPa`` (the relief pressure, > 0; default the drives module's) of a spec's ``[objective]`` table, read
    and checked: at least one row must be rated for the relief pressure.

    Raises:
        InputError: naming the field (or the catalog's file, row and column for a bad catalog).
    """
    from ...drives.catalogs import DEFAULT_FILES, read_catalog
    from ...io.data import data_dir
    from ...studies.spec import file_field

    path = file_field(objective, "catalog", folder, data_dir("catalogs") / DEFAULT_FILES["cylinders"],
                      "catalog file")
    catalog = read_catalog(path, "cylinders")
    pressure = objective.number("pressure_MPa", DEFAULT_PRESSURE / 1e6, positive=True) * 1e6
    rated = catalog["max_pressure"].to_numpy()
    if not (rated >= pressure).any():
        raise objective.error("pressure_MPa", f"no cylinder of {path.name} is rated for the relief pressure "
                                              f"{pressure / 1e6:g} MPa (the highest rating is {rated.max() / 1e6:g} "
                                              "MPa)")
    return {"catalog": catalog, "pressure": pressure}

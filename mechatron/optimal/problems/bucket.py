r"""The six-link bucket synthesis [Bucket] as an optimal-design problem.

The requirement of :func:`mechatron.machines.bucket.synthesize` — the bucket at φ4н when the cylinder is retracted
(L1 = L1н) and turned by Δφ4 when it is extended (L1 = L1н + h) — becomes the objective, the squared error of the
bucket angle at both stroke ends (rad²):

    E(x) = (φ4(L1н) − φ4н)² + (φ4(L1н + h) − φ4н − Δφ4)²,

over the design x ⊂ {c, L2, A_x = a, A_y = b} (m), the other dimensions those of the mechanism file. At every
cylinder length L1 of the positions of interest the states (φ1, φ2, φ3, φ4) solve the loop equations Φ1…Φ4
[Bucket, 8] (:func:`mechatron.machines.bucket.loop_equations`, here in CasADi SX with c, L2, a, b symbolic). With
x = (c, L2) the minimum E = 0 is the synthesis itself. A requirement on the smallest transmission angle μ over the
stroke (at the cylinder eye B between AB and DB, at C between DC and CE, at E between CE and FE, each folded to
[0°, 90°]; cos γ_B = −cos(φ1 + φ2), cos γ_C = cos(φ2 + α − φ3), cos γ_E = cos(φ3 − φ4)) generalises it: the
rows cos²μ_min − cos²γ ≥ 0 at ``positions`` cylinder lengths evenly along the stroke.

The Pinocchio model of the same design is the mechanism file rebuilt with ``c``, A = (a, b) and B moved along DB to
|DB| = L2 (so that the rocker's angle α = ∠BDC stays), assembled at each L1; its φ4 is the signed angle from FD to FE.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...errors import InputError
from ...kinematics.geometry import acute_angle, point_positions
from ...kinematics.loops import assemble
from ...machines.bucket import BucketInputs, loop_equations
from ..requirement import Requirement, Vector
from .base import CasadiModel

#: Design variables this problem knows, each a named parameter of the bucket mechanism (m).
VARIABLES = ("c", "L2", "A_x", "A_y")
DEG = math.pi / 180


def _angle(u: Vector, v: Vector) -> float:
    """Signed angle (rad) from u to v."""
    return math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])


def _cos_line(u: Vector, v: Vector) -> float:
    return float(u @ v / (np.linalg.norm(u) * np.linalg.norm(v)))


class BucketProblem(CasadiModel):
    """The bucket problem (see the module docstring).

    Args:
        mech: the six-link bucket mechanism (``mechatron.load("six_bar_bucket")`` or a file written by
            :func:`~mechatron.machines.bucket.write_bucket`).
        bounds: design variable → (lower, upper) (m).
        start: design variable → starting value (m); default the middle of the box.
        initial_angle: φ4н (rad); turn: Δφ4 (rad).
        min_transmission_angle: μ_min (rad) over the stroke, or None.
        positions: cylinder lengths along the stroke where the transmission angles are required (≥ 2).
    """

    objective_name = "bucket_angle_error"
    objective_unit = "rad²"

    def __init__(self, mech: Any, bounds: dict[str, tuple[float, float]], start: dict[str, float] | None = None, *,
                 initial_angle: float | None = None, turn: float = 160 * DEG,
                 min_transmission_angle: float | None = None, positions: int = 9) -> None:
        import casadi as ca

        d = BucketInputs()
        self.set_box(mech, bounds, start)
        self.base = mech.parameter_values()
        p = self.base
        if abs(p["D_x"]) > 1e-12 or abs(p["D_y"]) > 1e-12 or abs(p["F_y"]) > 1e-12:
            raise InputError(f"{mech.name}: the bucket problem needs the stick frame of [Bucket, 8] (D at the origin, "
                             "F on the x axis)")
        self.alpha = _angle(np.array([p["B_x"], p["B_y"]]), np.array([p["C_x"], p["C_y"]]))
        self.phi4n = (math.pi - d.beta_deg * DEG - d.gamma_deg * DEG) if initial_angle is None else initial_angle
        self.turn = turn
        self.mu_min = min_transmission_angle
        stroke = mech.cylinders["L1"].stroke
        count = max(2, positions) if min_transmission_angle is not None else 2
        self.lengths = np.linspace(stroke[0], stroke[1], count)
        self.title = "six-link bucket [Bucket]: bucket angle error over " + ", ".join(self.variables)

        self.x = ca.SX.sym("x", len(self.variables))
        symbol = {v: self.x[i] for i, v in enumerate(self.variables)}
        dims = {"c": symbol.get("c", p["c"]), "L2": symbol.get("L2", p["L2"]), "a": symbol.get("A_x", p["A_x"]),
                "b": symbol.get("A_y", p["A_y"]), "L3": p["L3"], "L4": p["L4"], "L5": p["L5"], "alpha": self.alpha}
        self.s = ca.SX.sym("s", 4 * count)
        loops, phi4, cosines = [], [], []
        for k, L1 in enumerate(self.lengths):
            p1, p2, p3, p4 = (self.s[4 * k + i] for i in range(4))
            loops += loop_equations(float(L1), p1, p2, p3, p4, **dims, cos=ca.cos, sin=ca.sin)
            phi4.append(p4)
            cosines += [-ca.cos(p1 + p2), ca.cos(p2 + self.alpha - p3), ca.cos(p3 - p4)]
        self.loops = ca.vertcat(*loops)
        self.quantities = ca.vertcat(*phi4, *cosines)
        self.quantity_names = (tuple(f"phi4_{k}_rad" for k in range(count))
                               + tuple(f"cos_{j}_{k}" for k in range(count) for j in "BCE"))

    # ------------------------------------------------------------------------------------------ Pinocchio
    def overrides(self, x: Vector) -> dict[str, float]:
        """The mechanism's parameters of the design x: c, A_x, A_y as they are, L2 as B moved along DB."""
        out: dict[str, float] = {}
        for name, value in zip(self.variables, np.asarray(x, dtype=float)):
            if name == "L2":  # B along DB, |DB| declared: the rocker keeps α
                scale = float(value) / self.base["L2"]
                out.update(L2=float(value), B_x=self.base["B_x"] * scale, B_y=self.base["B_y"] * scale)
            else:
                out[name] = float(value)
        return out

    def _positions(self, x: Vector) -> list[dict[str, Vector]]:
        mech = self.mech.with_parameters(self.overrides(x))
        out, q = [], None
        for L1 in self.lengths:
            q = assemble(mech, {"L1": float(L1)}, guess=q)
            out.append(dict(zip("ABCDEF", point_positions(mech, q, *"ABCDEF"))))
        return out

    def _bucket_angles(self, positions: list[dict[str, Vector]]) -> list[float]:
        """φ4 (rad) at each position: the signed angle from FD to FE, continued from φ4н along the stroke."""
        out, last = [], self.phi4n
        for P in positions:
            last = last + math.remainder(_angle(P["D"] - P["F"], P["E"] - P["F"]) - last, 2 * math.pi)
            out.append(last)
        return out

    def state_guess(self, x: Vector) -> Vector:
        positions = self._positions(x)
        states = []
        for P, phi4 in zip(positions, self._bucket_angles(positions)):
            A, B, C, E = P["A"], P["B"], P["C"], P["E"]
            states += [math.atan2(B[1] - A[1], A[0] - B[0]), math.atan2(B[1], B[0]),
                       math.atan2(C[1] - E[1], C[0] - E[0]), phi4]
        return np.array(states)

    def evaluate(self, x: Vector) -> Vector:
        positions = self._positions(x)
        cosines = []
        for P in positions:
            cosines += [_cos_line(P["B"] - P["A"], P["B"] - P["D"]), _cos_line(P["C"] - P["D"], P["C"] - P["E"]),
                        _cos_line(P["C"] - P["E"], P["E"] - P["F"])]
        return np.array(self._bucket_angles(positions) + cosines)

    # ------------------------------------------------------------------------------------------ objective
    def targets(self) -> tuple[float, float]:
        return self.phi4n, self.phi4n + self.turn

    def nlp_terms(self, q: Any) -> tuple[Any, Any, Any]:
        import casadi as ca

        n = len(self.lengths)
        start, end = self.targets()
        f = (q[0] - start) ** 2 + (q[n - 1] - end) ** 2
        g = ca.vertcat(*[math.cos(self.mu_min) ** 2 - q[i] ** 2 for i in range(n, 4 * n)]) \
            if self.mu_min is not None else ca.SX(0, 1)
        return ca.SX(0, 1), f, g

    def aux_guess(self, q: Vector) -> Vector:
        return np.zeros(0)

    def judge(self, q: Vector) -> tuple[float, list[Requirement]]:
        n = len(self.lengths)
        start, end = self.targets()
        error = float((q[0] - start) ** 2 + (q[n - 1] - end) ** 2)
        requirements = []
        if self.mu_min is not None:
            mu = acute_angle(q[n:])
            requirements.append(Requirement("min_transmission_angle_deg", float(mu.min() / DEG),
                                            self.mu_min / DEG, "min", "deg"))
        return error, requirements

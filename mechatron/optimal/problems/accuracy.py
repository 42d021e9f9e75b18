r"""A DH arm with the least worst-case positioning error over a pose set, as an optimal-design problem.

The design x is a set of DH lengths of the arm (``a2``, ``d4``, … m: link lengths and offsets), the others those
of the robot file. The tool point r(p, q) follows from the DH table: r = (T_base Π_i A_i(q_i) T_tool)[0:3, 3] with
A_i = Rz(θ_i) Tz(S_i) Tx(a_i) Rx(α_i) (standard) or Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i) (modified)
[Egorov, 4.39–4.45], written as CasADi SX expressions of every DH parameter p and of every joint coordinate.
The sensitivities J = ∂r/∂e of the error sources e (parameters of a tolerance file, and the joints' own errors)
are CasADi's exact Jacobians of those expressions [Egorov, 8.4]; they are functions of x, and the derivatives
the solver needs are their derivatives in turn.

With the tolerances t_i and biases b_i of the sources (:mod:`mechatron.accuracy.sources`, read once: an IT grade
is looked up at the robot file's nominal length and kept over the box), the worst case of the tool point at pose k
per axis a is the accuracy module's (:mod:`mechatron.accuracy.study`, ``worst``):

    W_ka = |Σ_i J_kai b_i| + Σ_i |J_kai| t_i,   D_k = √(Σ_a W_ka²)   [Egorov, 8.6],

and the objective is the largest D_k over the poses (m). The absolute values and the largest value are not smooth,
so the NLP carries them as epigraph variables: e_kai ≥ ±J_kai, u_ka ≥ ±(J_k b)_a and τ ≥ √(Σ_a (Σ_i t_i e_kai +
u_ka)²) for every k, minimising τ; at the optimum each bound is tight where it matters, and τ = max_k D_k.

Requirement (optional): the reach, the tool point's distance from the base's z axis √(x² + y²) at a reach pose,
at least R. Shorter links make every joint error smaller; the reach requirement is what keeps the arm useful.

The Pinocchio model of a design is the robot file rebuilt with the lengths (``mech.with_parameters``); its worst
case is :func:`mechatron.accuracy.study.analyse_tolerances` with the same sources and poses (Pinocchio's Jacobians
and the parameter derivatives of the accuracy module), and its reach Pinocchio's forward kinematics.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ...errors import InputError
from ..requirement import Requirement, Vector
from .base import CasadiModel


def _rot_z(ca: Any, angle: Any) -> Any:
    c, s = ca.cos(angle), ca.sin(angle)
    return ca.vertcat(ca.horzcat(c, -s, 0, 0), ca.horzcat(s, c, 0, 0), ca.horzcat(0, 0, 1, 0),
                      ca.horzcat(0, 0, 0, 1))


def _rot_x(ca: Any, angle: Any) -> Any:
    c, s = ca.cos(angle), ca.sin(angle)
    return ca.vertcat(ca.horzcat(1, 0, 0, 0), ca.horzcat(0, c, -s, 0), ca.horzcat(0, s, c, 0),
                      ca.horzcat(0, 0, 0, 1))


def _translation(ca: Any, x: Any = 0.0, z: Any = 0.0) -> Any:
    T = ca.SX.eye(4)
    T[0, 3], T[2, 3] = x, z
    return T


def dh_tool_point(table: Any, parameters: dict[str, Any], coordinates: Sequence[Any]) -> Any:
    """The tool point (3 × 1 SX, m) of the DH ``table`` with its parameters given by name (``a2``, ``alpha2``,
    ``d4``, ``theta1``, … SX or numbers; m, rad) at the joint coordinates (rad, m) [Egorov, 4.39–4.45]."""
    import casadi as ca

    T = ca.SX(ca.DM(table.base))
    for i, (link, q) in enumerate(zip(table.links, coordinates), start=1):
        p = {fld: parameters[name] for fld, name in table.parameter_names(i).items()}
        theta, s = (q + p["theta"], p["d"]) if link.is_revolute else (p["theta"], q + p["d"])
        turn, offset = _rot_z(ca, theta), _translation(ca, z=s)
        twist, length = _rot_x(ca, p["alpha"]), _translation(ca, x=p["a"])
        factors = [turn, offset, length, twist] if table.convention == "standard" else [twist, length, turn, offset]
        A = ca.mtimes(factors)
        T = ca.mtimes(T, A)
    T = ca.mtimes(T, ca.SX(ca.DM(table.tool)))
    return T[0:3, 3]


def length_parameters(mech: Any) -> tuple[str, ...]:
    """The DH lengths of a DH arm that can be design variables (m)."""
    return tuple(name for name, p in mech.parameters.items() if p.kind == "length")


class PositioningProblem(CasadiModel):
    """The positioning-error problem (see the module docstring).

    Args:
        mech: a DH arm (``mech.dh`` set: a robot file).
        bounds: DH length → (lower, upper) (m).
        start: DH length → starting value (m); default the middle of the box.
        sources: the error sources (:func:`mechatron.accuracy.sources.read_tolerances`; m, rad).
        poses: joint coordinates (N, n) (rad, m) of the poses where the error counts.
        labels: a label per pose.
        min_reach: the least reach R (m) at ``reach_pose`` (joint coordinates, rad, m), or None.
    """

    objective_name = "max_worst_case_error"
    objective_unit = "m"

    def __init__(self, mech: Any, bounds: dict[str, tuple[float, float]], start: dict[str, float] | None = None, *,
                 sources: Sequence[Any], poses: Any, labels: Sequence[str] | None = None,
                 min_reach: float | None = None, reach_pose: Any = None) -> None:
        import casadi as ca

        if mech.dh is None:
            raise InputError(f"{mech.name} is not a DH arm: the positioning error needs a robot file's DH table")
        self.set_box(mech, bounds, start)
        self.sources = list(sources)
        if not any(s.tolerance > 0 or s.bias != 0 for s in self.sources):
            raise InputError("every error source has a zero tolerance and no bias: there is no error to minimise")
        self.poses = np.atleast_2d(np.asarray(poses, dtype=float))
        self.labels = list(labels) if labels is not None else [str(k + 1) for k in range(len(self.poses))]
        self.min_reach = min_reach
        self.reach_pose = None if reach_pose is None else np.asarray(reach_pose, dtype=float)
        self.tolerances = np.array([s.tolerance for s in self.sources])
        self.biases = np.array([s.bias for s in self.sources])
        self.title = "DH arm: largest worst-case positioning error over " + ", ".join(self.variables)

        table = mech.dh
        nominal = mech.parameter_values()
        symbols = {name: ca.SX.sym(name) for name in nominal}
        joints = [link.name for link in table.links]
        errors = {name: ca.SX.sym(f"d_{name}") for name in joints}
        self.x = ca.SX.sym("x", len(self.variables))
        self.s = ca.SX(0, 1)
        self.loops = ca.SX(0, 1)
        design = [self.x[self.variables.index(n)] if n in self.variables else nominal[n] for n in nominal]
        wrt = ca.vertcat(*[symbols[s.name] if s.kind == "parameter" else errors[s.name] for s in self.sources])
        every = ca.vertcat(*symbols.values(), *errors.values())
        at_design = ca.vertcat(*design, *([0.0] * len(errors)))

        def substituted(expression: Any) -> Any:
            return ca.substitute(expression, every, at_design)

        self.J = []  # per pose: ∂r/∂e (3 × n_e SX of x)
        worst = []
        for pose in self.poses:
            r = dh_tool_point(table, symbols, [float(v) + errors[n] for v, n in zip(pose, joints)])
            J = substituted(ca.jacobian(r, wrt))
            self.J.append(J)
            W = ca.fabs(ca.mtimes(J, ca.DM(self.biases))) + ca.mtimes(ca.fabs(J), ca.DM(self.tolerances))
            worst.append(ca.norm_2(W))
        quantities, names = worst, [f"dr_worst_{label}_m" for label in self.labels]
        if min_reach is not None and self.reach_pose is not None:
            tip = substituted(dh_tool_point(table, symbols, [float(v) for v in self.reach_pose]))
            quantities.append(ca.sqrt(tip[0] ** 2 + tip[1] ** 2))
            names.append("reach_m")
        self.quantities = ca.vertcat(*quantities)
        self.quantity_names = tuple(names)
        self.sensitivity = ca.Function("sensitivity", [self.x], [ca.vertcat(*self.J)])
        self.scale = 1.0 / max(float(np.max(self.values(self.start)[:len(self.poses)])), 1e-300)

    # ------------------------------------------------------------------------------------------ Pinocchio
    def state_guess(self, x: Vector) -> Vector:
        return np.zeros(0)

    def evaluate(self, x: Vector) -> Vector:
        """D_k of :func:`mechatron.accuracy.study.analyse_tolerances` (method ``worst``) and the reach from Pinocchio's
        forward kinematics, for the robot file rebuilt with the lengths x."""
        import pinocchio as pin

        from ...accuracy.study import analyse_tolerances, configurations

        mech = self.mech.with_parameters(dict(zip(self.variables, map(float, x))))
        study = analyse_tolerances(mech, self.sources, self.poses, self.labels, methods=("worst",))
        out = list(study.poses["dr_worst"].to_numpy(dtype=float))
        if self.min_reach is not None and self.reach_pose is not None:
            q = configurations(mech, self.reach_pose)[0]
            pin.framesForwardKinematics(mech.model, mech.data, q)
            tip = mech.data.oMf[mech.frame_id(mech.tool_frame)].translation
            out.append(math.hypot(tip[0], tip[1]))
        return np.array(out)

    # ------------------------------------------------------------------------------------------ objective
    def nlp_terms(self, q: Any) -> tuple[Any, Any, Any]:
        import casadi as ca

        n_e = len(self.sources)
        tau = ca.SX.sym("tau")
        e = ca.SX.sym("e", len(self.poses) * 3 * n_e)
        u = ca.SX.sym("u", len(self.poses) * 3)
        rows = []
        for k, J in enumerate(self.J):
            ek = ca.reshape(e[3 * n_e * k:3 * n_e * (k + 1)], 3, n_e)
            uk = u[3 * k:3 * (k + 1)]
            shift = ca.mtimes(J, ca.DM(self.biases))
            rows += [ca.vec(ek - J), ca.vec(ek + J), uk - shift, uk + shift]
            rows.append(self.scale * (tau - ca.norm_2(uk + ca.mtimes(ek, ca.DM(self.tolerances)))))
        if self.min_reach is not None:
            rows.append(q[len(self.poses)] - self.min_reach)
        return ca.vertcat(tau, e, u), self.scale * tau, ca.vertcat(*rows)

    def aux_guess(self, q: Vector) -> Vector:
        J = np.array(self.sensitivity(self.start)).reshape(len(self.poses), 3, -1)
        e = np.concatenate([np.abs(Jk).ravel(order="F") for Jk in J])
        u = np.abs(J @ self.biases).ravel()
        return np.concatenate([[float(np.max(q[:len(self.poses)]))], e, u])

    def judge(self, q: Vector) -> tuple[float, list[Requirement]]:
        q = np.asarray(q, dtype=float)
        requirements = []
        if self.min_reach is not None:
            requirements.append(Requirement("reach_m", float(q[len(self.poses)]), self.min_reach, "min", "m"))
        return float(np.max(q[:len(self.poses)])), requirements

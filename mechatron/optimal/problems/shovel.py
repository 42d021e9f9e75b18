r"""A front-shovel working device [Shovel] with the least largest cylinder force, as an optimal-design problem.

The design x is any of the cylinders' pin positions (A on the turntable; B, D on the boom; E, G on the stick; K on
the bucket: ``A_x``, ``A_y``, … m, in the drawing) and the link lengths (``boom`` |CF|, ``stick`` |FQ|, ``bucket``
|QV|, m); the boom foot C stays. The working range the assignment asks for (reach R1max, height H2max, depth H1max,
smallest reach R0min) fixes the joint ranges θ1, θ2, θ3 of the design's links
(:func:`mechatron.machines.excavator.range_angles`, [Shovel, 3.2–3.7]) and the special tooth-tip positions that
attain them (:func:`~mechatron.machines.excavator.special_angles`, [Shovel, 2.1–2.4]), both CasADi expressions of the
link lengths; each cylinder's stroke is chosen to span its joint's range, L_min = L(θ_min), L_max = L(θ_max).

Loop equations: a cylinder across joint j closes the triangle pivot–base–eye, L_j = |P_eye − P_base| with each pin
P = O_b + R(a_b − a_b,ref)(P_drawn − O_b,ref) on its body b (absolute angles a = θ1, θ1 + θ2 − π, θ1 + θ2 + θ3 of
CF, FQ, QV; O_b the body's end C, F or Q at the design's link lengths). Holding force of cylinder j at rest by
virtual work (the other cylinders held, so everything beyond joint j turns rigidly about its pivot O_j):

    F_j = (g Σ_{i beyond j} m_i (x_i − x_Oj) − (−f_x (V_y − O_jy) + f_y (V_x − O_jx))) / (dL_j/dθ_j),

(N, > 0 pushing; m_i, x_i the masses and centres of the links — a centre keeps its place along its link in
proportion to the link's length — f the tooth force). Objective: the largest |F_j| over the special positions and
the chosen cylinders (an epigraph bound t ≥ ±F_jk in the NLP). Requirements per chosen cylinder: the stroke ratio
λ = L_max/L_min ≤ λ_max, the smallest transmission angle over the range (at the eye, between the cylinder and the
driven lever, folded to [0°, 90°]) ≥ μ_min, the stroke L_max − L_min ≤ a catalog's longest (optional), the special
positions inside the stroke; the working range itself, from the tooth tip at the special positions; and, with free
links, every acos and asin argument of the range formulas in [−1, 1] (the links reach the working range). The
Pinocchio model of a design is the file rebuilt with the design's drawing (:meth:`ShovelProblem.drawing`), assembled
at the cylinder lengths of each position (refined by Newton's method until its joint angles are the position's,
1e-11 rad).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from ...errors import InputError
from ...kinematics.geometry import acute_angle, point_positions
from ...kinematics.loops import assemble
from ...machines.excavator import (
    FrontShovelDesign,
    casadi_maths,
    cylinder_loads,
    joint_angles,
    range_angles,
    special_angles,
)
from ..requirement import Requirement, Vector
from .base import CasadiModel

DEG = math.pi / 180
#: cylinder → (base, eye, pivot, joint index): the triangle each cylinder closes.
CYLINDERS = {"L1": ("A", "B", "C", 0), "L2": ("D", "E", "F", 1), "L3": ("G", "K", "Q", 2)}
#: pin → (body, origin, axis end) of the frame it is fixed in; "ground" for the turntable.
PINS = {"A": ("ground", "C", "F"), "B": ("boom", "C", "F"), "D": ("boom", "C", "F"), "E": ("stick", "F", "Q"),
        "G": ("stick", "F", "Q"), "K": ("bucket", "Q", "V")}
#: named lever lengths of the front-shovel file → (pivot, pin).
LEVERS = {"l5": ("C", "A"), "l7": ("C", "B"), "l8": ("F", "D"), "l9": ("F", "E"), "l10": ("Q", "G"), "l11": ("Q", "K")}
#: link lengths of the front-shovel file (m) → (origin, end, the points that move with a change of the length).
LINKS = {"boom": ("C", "F", "FQVEGK"), "stick": ("F", "Q", "QVK"), "bucket": ("Q", "V", "V")}
VARIABLES = tuple(f"{p}_{a}" for p in PINS for a in "xy") + tuple(LINKS)
BODIES = {"boom": (0, "theta1"), "stick": (1, "stick_angle"), "bucket": (2, "bucket_angle")}


def _direction(u: Vector) -> float:
    return math.atan2(u[1], u[0])


class ShovelProblem(CasadiModel):
    """The front-shovel problem (see the module docstring).

    Args:
        mech: the front shovel (``mechatron.load("front_shovel")`` or a file of ``mechatron excavator -o``).
        bounds: pin coordinate or link length → (lower, upper) (m).
        start: pin coordinate or link length → starting value (m); default the middle of the box.
        working_range: overrides of the assignment's max_digging_radius, max_digging_height, max_digging_depth,
            min_digging_radius (m) and ground_angle_deg, dump_angle_deg.
        cylinders: the cylinders whose force is minimised and whose requirements hold (default: those with a free
            pin; all three with a free link).
        max_ratio: λ_max; min_transmission_angle: μ_min (rad); max_stroke: longest stroke (m) or None.
        tooth_force: (f_x, f_y) on the tooth tip (N); positions: samples of each joint range (≥ 2).
    """

    objective_name = "max_cylinder_force"
    objective_unit = "N"
    scale = 1e-6

    def __init__(self, mech: Any, bounds: dict[str, tuple[float, float]], start: dict[str, float] | None = None, *,
                 working_range: dict[str, float] | None = None, cylinders: tuple[str, ...] | None = None,
                 max_ratio: float = 1.7, min_transmission_angle: float = 30 * DEG, max_stroke: float | None = None,
                 tooth_force: tuple[float, float] = (0.0, 0.0), positions: int = 9) -> None:
        import casadi as ca

        self.set_box(mech, bounds, start)
        free = {v[:-2] for v in self.variables if v.endswith(("_x", "_y"))}
        links_free = [v for v in self.variables if v in LINKS]
        self.cylinders = tuple(cylinders) if cylinders else tuple(c for c, pins in CYLINDERS.items()
                                                                    if links_free or free & set(pins[:2]))
        self.max_ratio, self.mu_min, self.max_stroke = max_ratio, min_transmission_angle, max_stroke
        self.tooth_force = np.asarray(tooth_force, dtype=float)
        base = mech.parameter_values()
        self.drawn = {p: np.array([base[f"{p}_x"], base[f"{p}_y"]]) for p in "CFQVABDEGK"}
        P = self.drawn
        self.links = [float(np.linalg.norm(P[b] - P[a])) for a, b, _ in LINKS.values()]
        self.reference = {"ground": 0.0, "boom": _direction(P["F"] - P["C"]), "stick": _direction(P["Q"] - P["F"]),
                          "bucket": _direction(P["V"] - P["Q"])}
        fields: dict[str, Any] = {**(working_range or {}), "boom": self.links[0], "stick": self.links[1],
                                  "bucket": self.links[2], "boom_foot": (float(P["C"][0]), float(P["C"][1]))}
        design = FrontShovelDesign(**fields)
        self.design = design
        self.masses, self.centres = self._links_inertia()
        self.title = "front shovel [Shovel]: largest cylinder force over " + ", ".join(self.variables)

        self.x = ca.SX.sym("x", len(self.variables))
        self.s = ca.SX(0, 1)
        self.loops = ca.SX(0, 1)
        self.link_values = [self.x[self.variables.index(n)] if n in self.variables else ca.SX(length)
                            for n, length in zip(LINKS, self.links)]
        arguments: list[Any] = []  # of acos and asin: |a| ≤ 1 where the links reach the working range
        maths = casadi_maths(arguments)
        boom, stick, bucket = self.link_values
        ranges = range_angles(design, boom, stick, bucket, maths)[:3]
        special = special_angles(design, boom, stick, bucket, ranges[0], ranges[1][1], maths)
        sweep = [tuple(lo + t * (hi - lo) for lo, hi in ranges) for t in np.linspace(0, 1, max(2, positions))]
        self.domain = ca.vertcat(*arguments) if links_free else ca.SX(0, 1)
        self._angles = ca.Function("angles", [self.x], [ca.vertcat(*[a for r in ranges for a in r],
                                                                   *[a for v in special.values() for a in v],
                                                                   *[a for v in sweep for a in v])])
        self.ranges, self.special, self.sweep = self.angles_at(self.start)

        pins = {p: ca.vertcat(*[self.x[self.variables.index(f"{p}_{a}")] if f"{p}_{a}" in self.variables
                                else float(P[p]["xy".index(a)]) for a in "xy"]) for p in PINS}
        theta = ca.SX.sym("theta", 3)
        lengths, slopes, cosines = [], [], []
        for b, e, o, j in CYLINDERS.values():
            pb, pe, po = (self._world(ca, p, pins, theta) for p in (b, e, o))
            length = ca.norm_2(pe - pb)
            lengths.append(length)
            slopes.append(ca.jacobian(length, theta)[j])
            cylinder, lever = pe - pb, pe - po
            cosines.append(ca.dot(cylinder, lever) / (ca.norm_2(cylinder) * ca.norm_2(lever)))
        at = ca.Function("at", [theta, self.x], [ca.vertcat(*lengths), ca.vertcat(*slopes), ca.vertcat(*cosines)])
        forces, special_lengths, tips = [], [], []
        for angles in special.values():
            L, dL, _ = at(ca.vertcat(*angles), self.x)
            moments = self._moments(angles)
            forces += [moments[j] / dL[j] for j in range(3)]
            special_lengths += [L[j] for j in range(3)]
            tip = self._tip(angles)
            tips += [tip[0], tip[1]]
        sweep_lengths, sweep_cosines = [], []
        for angles in sweep:
            L, _, cos = at(ca.vertcat(*angles), self.x)
            sweep_lengths += [L[j] for j in range(3)]
            sweep_cosines += [cos[j] for j in range(3)]
        self.quantities = ca.vertcat(*forces, *special_lengths, *sweep_lengths, *sweep_cosines, *tips)
        names = list(special)
        self.quantity_names = (tuple(f"{c}_force_{p}_N" for p in names for c in CYLINDERS)
                               + tuple(f"{c}_length_{p}_m" for p in names for c in CYLINDERS)
                               + tuple(f"{c}_length_{i}_m" for i in range(len(sweep)) for c in CYLINDERS)
                               + tuple(f"{c}_cos_{i}" for i in range(len(sweep)) for c in CYLINDERS)
                               + tuple(f"V_{a}_{p}_m" for p in names for a in "xy"))
        self.lengths_of = ca.Function("lengths", [theta, self.x], [ca.vertcat(*lengths)])

    def angles_at(self, x: Vector) -> tuple[list[tuple[float, float]], dict[str, tuple[float, float, float]],
                                            list[tuple[float, float, float]]]:
        """(joint ranges, special positions, sweep positions) of the design x: joint angles (rad)."""
        a = np.array(self._angles(x), dtype=float).ravel()
        ranges = [(a[2 * j], a[2 * j + 1]) for j in range(3)]
        names = ("max_digging_radius", "max_digging_height", "max_digging_depth", "max_ground_radius")
        special = {n: tuple(a[6 + 3 * k:9 + 3 * k]) for k, n in enumerate(names)}
        rest = a[6 + 3 * len(names):]
        return ranges, special, [tuple(rest[3 * k:3 * k + 3]) for k in range(len(rest) // 3)]

    # ------------------------------------------------------------------------------------------ geometry
    def _pose(self, angles: Any) -> dict[str, Any]:
        """Frame origin and absolute angle of each body at the joint angles (θ1, θ2, θ3) (numbers or SX)."""
        import casadi as ca

        t1, t2, t3 = angles[0], angles[1], angles[2]
        a = {"ground": 0.0, "boom": t1, "stick": t1 + t2 - math.pi, "bucket": t1 + t2 + t3}
        C = ca.DM(self.drawn["C"])
        F = C + self.link_values[0] * ca.vertcat(ca.cos(a["boom"]), ca.sin(a["boom"]))
        Q = F + self.link_values[1] * ca.vertcat(ca.cos(a["stick"]), ca.sin(a["stick"]))
        return {"ground": (0.0, a["ground"]), "boom": (C, a["boom"]), "stick": (F, a["stick"]),
                "bucket": (Q, a["bucket"]), "origins": {"C": C, "F": F, "Q": Q}}

    def _world(self, ca: Any, point: str, pins: dict[str, Any], theta: Any) -> Any:
        pose = self._pose(theta)
        if point in pose["origins"]:
            return pose["origins"][point]
        body, origin, _ = PINS[point]
        if body == "ground":
            return pins[point]
        O, a = pose[body]
        turn = a - self.reference[body]
        r = pins[point] - ca.DM(self.drawn[origin])
        return O + ca.vertcat(ca.cos(turn) * r[0] - ca.sin(turn) * r[1], ca.sin(turn) * r[0] + ca.cos(turn) * r[1])

    def _links_inertia(self) -> tuple[list[float], list[Vector]]:
        """Masses (kg) of boom, stick and bucket and their centres in the link frames (m), from the Pinocchio model
        at its reference configuration."""
        import pinocchio as pin

        model, data = self.mech.model, self.mech.data
        pin.forwardKinematics(model, data, self.mech.reference_q)
        masses, centres = [], []
        origins = dict(zip("CFQV", point_positions(self.mech, self.mech.reference_q, *"CFQV")))
        for (_, joint), (o, e) in zip(BODIES.values(), (("C", "F"), ("F", "Q"), ("Q", "V"))):
            jid = model.getJointId(joint)
            centre = (data.oMi[jid].act(model.inertias[jid].lever))[:2]
            turn = -_direction(origins[e] - origins[o])
            r = centre - origins[o]
            masses.append(float(model.inertias[jid].mass))
            centres.append(np.array([math.cos(turn) * r[0] - math.sin(turn) * r[1],
                                     math.sin(turn) * r[0] + math.cos(turn) * r[1]]))
        return masses, centres

    def _numbers(self, angles: Any) -> dict[str, Any]:
        """C, F, Q, the tooth tip V and the centres of mass of boom, stick and bucket (2 × 1 SX, m) at the joint
        angles; a centre keeps its place along its link in proportion to the link's length (a bar's middle)."""
        import casadi as ca

        pose = self._pose(angles)
        out = dict(pose["origins"])
        a3 = pose["bucket"][1]
        out["V"] = out["Q"] + self.link_values[2] * ca.vertcat(ca.cos(a3), ca.sin(a3))
        for body, centre, length, reference in zip(BODIES, self.centres, self.link_values, self.links):
            O, a = pose[body]
            along = centre[0] * length / reference
            out[body] = O + ca.vertcat(ca.cos(a) * along - ca.sin(a) * centre[1],
                                       ca.sin(a) * along + ca.cos(a) * centre[1])
        return out

    def _tip(self, angles: Any) -> Any:
        return self._numbers(angles)["V"]

    def _moments(self, angles: Any) -> list[Any]:
        """dPot/dθ_j − (work of the tooth force per dθ_j) (N·m) for j = 1, 2, 3 at the joint angles."""
        g = -float(self.mech.model.gravity.linear[1])
        n = self._numbers(angles)
        fx, fy = self.tooth_force
        out = []
        for j, pivot in enumerate("CFQ"):
            O = n[pivot]
            gravity = g * sum(m * (n[b][0] - O[0]) for m, b in zip(self.masses[j:], ("boom", "stick", "bucket")[j:]))
            work = -fx * (n["V"][1] - O[1]) + fy * (n["V"][0] - O[0])
            out.append(gravity - work)
        return out

    # ------------------------------------------------------------------------------------------ Pinocchio
    def state_guess(self, x: Vector) -> Vector:
        return np.zeros(0)

    def with_strokes(self, mech: Any, x: Vector) -> Any:
        """``mech`` (a fresh rebuild) with each cylinder's stroke the design's, [L(θ_min), L(θ_max)] sorted: the
        cylinder's entry and the position limits of its coordinate in the Pinocchio model (m); and the boom's
        range θ1 the design's (rad)."""
        ranges = self.angles_at(x)[0]
        low = np.array(self.lengths_of(ca_dm([r[0] for r in ranges]), x)).ravel()
        high = np.array(self.lengths_of(ca_dm([r[1] for r in ranges]), x)).ravel()
        boom = mech.model.joints[mech.model.getJointId(BODIES["boom"][1])].idx_q
        mech.model.lowerPositionLimit[boom] = min(mech.model.lowerPositionLimit[boom], ranges[0][0] - 1e-6)
        mech.model.upperPositionLimit[boom] = max(mech.model.upperPositionLimit[boom], ranges[0][1] + 1e-6)
        for (name, cylinder), a, b in zip(list(mech.cylinders.items()), low, high):
            stroke = (float(min(a, b)), float(max(a, b)))
            mech.cylinders[name] = replace(cylinder, stroke=stroke)
            index = mech.model.joints[mech.model.getJointId(name)].idx_q
            # 1e-6 m of slack: Newton's method on the lengths steps 1e-7 m either side of the ends
            mech.model.lowerPositionLimit[index], mech.model.upperPositionLimit[index] = stroke[0] - 1e-6, \
                stroke[1] + 1e-6
        return mech

    def drawing(self, x: Vector) -> dict[str, Vector]:
        """Every point of the design x in the drawing (m): the pins as given, and everything beyond a link's end
        moved along the link by the change of its length (the stick's and bucket's pins keep their places on their
        bodies)."""
        values = dict(zip(self.variables, map(float, x)))
        out = {p: np.array([values.get(f"{p}_{a}", self.drawn[p][i]) for i, a in enumerate("xy")])
               for p in self.drawn}
        for (name, (origin, end, moved)), reference in zip(LINKS.items(), self.links):
            along = (self.drawn[end] - self.drawn[origin]) / reference
            for point in moved:
                out[point] = out[point] + (values.get(name, reference) - reference) * along
        return out

    def overrides(self, x: Vector) -> dict[str, float]:
        """The mechanism's parameters of the design x: the coordinates of every point of :meth:`drawing` and the
        named lengths between them (links and levers, |CF|, |CA|, …; a named length left at its old value would pull
        its point back)."""
        points = self.drawing(x)
        out = {f"{p}_{a}": float(v[i]) for p, v in points.items() for i, a in enumerate("xy")}
        pairs = {**{name: (a, b) for name, (a, b, _) in LINKS.items()}, **LEVERS}
        out.update({name: float(np.linalg.norm(points[b] - points[a])) for name, (a, b) in pairs.items()})
        return out

    def evaluate(self, x: Vector) -> Vector:
        mech = self.with_strokes(self.mech.with_parameters(self.overrides(x)), x)
        forces, special_lengths, tips, sweep_lengths, sweep_cosines = [], [], [], [], []
        q = None
        _, special, sweep = self.angles_at(x)
        for k, angles in enumerate([*special.values(), *sweep]):
            q = self._assemble(mech, x, angles, q)
            P = dict(zip("ABCDEFGKQV", point_positions(mech, q, *"ABCDEFGKQV")))
            lengths = [float(np.linalg.norm(P[e] - P[b])) for b, e, _, _ in CYLINDERS.values()]
            if k < len(special):
                loads = cylinder_loads(mech, [q], tooth_force=self.tooth_force)
                forces += [float(loads[f"{c}_force"].iloc[0]) for c in CYLINDERS]
                special_lengths += lengths
                tips += list(P["V"])
            else:
                sweep_lengths += lengths
                for b, e, o, _ in CYLINDERS.values():
                    u, v = P[e] - P[b], P[e] - P[o]
                    sweep_cosines.append(float(u @ v / (np.linalg.norm(u) * np.linalg.norm(v))))
        return np.array(forces + special_lengths + sweep_lengths + sweep_cosines + tips)

    def _assemble(self, mech: Any, x: Vector, angles: tuple[float, float, float], guess: Any) -> Vector:
        """The configuration of ``mech`` at the report's joint angles: assembled at the cylinder lengths of the
        CasADi triangles, then Newton's method on the lengths (finite-difference Jacobian) until the joint angles
        of the Pinocchio model are ``angles`` to 1e-11 rad."""
        lengths = np.array(self.lengths_of(ca_dm(angles), x)).ravel()
        names = list(CYLINDERS)

        def residual(values: Vector, start: Any) -> tuple[Vector, Vector]:
            q = assemble(mech, dict(zip(names, map(float, values))), guess=start)
            got = joint_angles(mech, q)
            return q, np.array([math.remainder(g - a, 2 * math.pi) for g, a in zip(got, angles)])

        q, r = residual(lengths, guess)
        for _ in range(8):
            if np.abs(r).max() < 1e-11:
                return q
            h = 1e-7
            J = np.column_stack([(residual(lengths + h * e, q)[1] - residual(lengths - h * e, q)[1]) / (2 * h)
                                 for e in np.eye(3)])
            lengths = lengths - np.linalg.solve(J, r)
            q, r = residual(lengths, q)
        if np.abs(r).max() > 1e-9:
            raise InputError(f"{mech.name}: the Pinocchio model does not reach the joint angles "
                             f"{np.round(np.array(angles) / DEG, 3).tolist()}° (off by {np.abs(r).max():.2g} rad)")
        return q

    # ------------------------------------------------------------------------------------------ objective
    def _split(self, q: Any) -> dict[str, Any]:
        k, n = len(self.special), len(self.sweep)
        sizes = {"forces": 3 * k, "special_lengths": 3 * k, "sweep_lengths": 3 * n, "cosines": 3 * n, "tips": 2 * k}
        out, i = {}, 0
        for name, size in sizes.items():
            out[name] = [q[i + m] for m in range(size)]
            i += size
        return out

    def nlp_terms(self, q: Any) -> tuple[Any, Any, Any]:
        import casadi as ca

        parts = self._split(q)
        t = ca.SX.sym("t")
        rows = []
        for c in self.cylinders:
            j = list(CYLINDERS).index(c)
            rows += [self.scale * (t - sign * f) for f in parts["forces"][j::3] for sign in (1, -1)]
            rows += self.cylinder_rows(parts, j)
        return t, self.scale * t, ca.vertcat(*rows, self.reach_rows())

    def reach_rows(self) -> Any:
        """1 − 1e-9 − a² ≥ 0 for every acos and asin argument a of the range formulas: the links reach the working
        range (SX; empty with the links fixed)."""
        return 1 - 1e-9 - self.domain**2

    def cylinder_rows(self, parts: dict[str, Any], j: int) -> list[Any]:
        """The smooth rows g ≥ 0 of cylinder j's requirements (λ, transmission angle, stroke, special positions
        inside the stroke) from the quantities split by :meth:`_split` (SX)."""
        lo, hi = parts["sweep_lengths"][j], parts["sweep_lengths"][-3 + j]
        rows = [self.max_ratio * lo - hi, self.max_ratio * hi - lo]
        rows += [math.cos(self.mu_min) ** 2 - cos**2 for cos in parts["cosines"][j::3]]
        if self.max_stroke is not None:
            rows += [self.max_stroke - (hi - lo), self.max_stroke + (hi - lo)]
        for L in parts["special_lengths"][j::3]:
            rows += [(L - lo) * (hi - L)]  # inside the stroke, whichever way the cylinder extends
        return rows

    def aux_guess(self, q: Vector) -> Vector:
        forces = self._split(q)["forces"]
        return np.array([max(abs(forces[3 * k + list(CYLINDERS).index(c)]) for c in self.cylinders
                             for k in range(len(self.special)))])

    def judge(self, q: Vector) -> tuple[float, list[Requirement]]:
        parts = self._split(np.asarray(q, dtype=float))
        tips = np.array(parts["tips"]).reshape(-1, 2)
        d = self.design
        req = [Requirement("max_digging_radius_m", float(tips[:, 0].max()), d.max_digging_radius, "min", "m"),
               Requirement("max_digging_height_m", float(tips[:, 1].max()), d.max_digging_height, "min", "m"),
               Requirement("max_digging_depth_m", float(-tips[:, 1].min()), d.max_digging_depth, "min", "m")]
        largest = 0.0
        for c in self.cylinders:
            j = list(CYLINDERS).index(c)
            largest = max(largest, max(abs(f) for f in parts["forces"][j::3]))
            lo, hi = parts["sweep_lengths"][j], parts["sweep_lengths"][-3 + j]
            short, long = min(lo, hi), max(lo, hi)
            mu = acute_angle(parts["cosines"][j::3])
            inside = min(min(L - short, long - L) for L in parts["special_lengths"][j::3])
            req += [Requirement(f"{c}_stroke_ratio", long / short, self.max_ratio, "max", "-"),
                    Requirement(f"{c}_min_transmission_angle_deg", float(mu.min() / DEG), self.mu_min / DEG, "min",
                                "deg"),
                    Requirement(f"{c}_special_positions_inside_stroke_m", float(inside), 0.0, "min", "m")]
            if self.max_stroke is not None:
                req.append(Requirement(f"{c}_stroke_m", long - short, self.max_stroke, "max", "m"))
        return largest, req


def ca_dm(values: Any) -> Any:
    import casadi as ca

    return ca.DM([float(v) for v in values])

r"""Front-shovel hydraulic excavator working device (seed 001, notes seed-excavator.md).

Boom (link CF = l1), stick (FQ = l2) and bucket (QV = l3, V the tooth tip), driven by three hydraulic cylinders:
the twin boom cylinder A–B (A on the turntable, B on the boom), the stick cylinder D–E (D on the boom, E on the stick)
and the bucket cylinder G–K (G on the stick, K on the bucket). The report's angles: θ1 is the boom angle of CF from
the horizontal, θ2 the interior angle CFQ at F, θ3 the angle at Q from QF to QV (counter-clockwise); the absolute
angles are θ1, θ1 + θ2 − π (stick) and θ1 + θ2 + θ3 (bucket).

The design follows the report step by step:

1. empirical first sizing L = K ∛m (3.1);
2. joint ranges from the working dimensions (3.2–3.7): R1max, H1max, H2max, R0min, the bucket-to-ground angle ζ and
   the dump angle δ;
3. each cylinder across its joint is a triangle with levers a, s·a; the included angle ψ = θ + c grows with the joint
   angle. The offset c that makes the moment arms at both ends equal in the ratio k = e_start/e_end (3.8–3.9, 3.14):
   tan c = (k sin θ_end − λ sin θ_start)/(λ cos θ_start − k cos θ_end); the lever ratio s and the shortest length
   r·a for a stroke ratio λ = L_max/L_min (3.10–3.13, 3.15–3.17): (λ² − 1)s² − (2λ² cos ψ_start − 2 cos ψ_end)s
   + (λ² − 1) = 0, r² = s² + 1 − 2 s cos ψ_start;
4. lever arms e = a·s·a sin ψ / L and transmission angles (the angle at the driven lever's pin between the cylinder
   and the lever, folded to [0°, 90°]) checked against 30° (3.18–3.19);
5. special tooth-tip positions and the working range from sweeping all strokes.

Reproduced and inconsistent numbers of the report are listed by :func:`report_comparison`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..kinematics.frames import frame_placement, point_velocity
from ..kinematics.loops import assemble, joint_velocity
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

DEG = math.pi / 180


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


# ------------------------------------------------------------------------------------------- first sizing
#: Coefficients K of L = K ∛m (m in tonnes, L in metres). The report's table (its Appendix 1) is an image missing
#: from the text; the printed coefficients are l1 = 1.2, l2 = 0.9 and R2max = 2.45, the others are implied by the
#: report's own numbers at m = 46 t (value / ∛46).
SIZING_COEFFICIENTS = {
    "max_digging_radius": 9.06 / 46 ** (1 / 3),
    "max_digging_depth": 3.2 / 46 ** (1 / 3),
    "max_digging_height": 9.53 / 46 ** (1 / 3),
    "ground_radius": 2.45,
    "min_digging_radius": 4.2 / 46 ** (1 / 3),
    "boom": 1.2,
    "stick": 0.9,
    "bucket": 2.0 / 46 ** (1 / 3),
}


def first_sizing(mass_t: float, coefficients: dict[str, float] | None = None) -> dict[str, float]:
    """Dimensions L = K ∛m (m) of a machine of ``mass_t`` tonnes (eq. 3.1)."""
    if not mass_t > 0:
        raise InputError(f"machine mass must be > 0 t, got {mass_t:g}")
    k = coefficients or SIZING_COEFFICIENTS
    return {name: value * mass_t ** (1 / 3) for name, value in k.items()}


def mass_from_requirements(requirements: dict[str, float], coefficients: dict[str, float] | None = None) -> float:
    """Machine mass (t) whose first sizing best matches the given working dimensions (least squares on ∛m)."""
    k = coefficients or SIZING_COEFFICIENTS
    pairs = [(value, k[name]) for name, value in requirements.items()]
    cube_root = sum(v * c for v, c in pairs) / sum(c * c for _, c in pairs)
    return cube_root**3


# -------------------------------------------------------------------------------------------- cylinder synthesis
def included_angle_offset(theta_start: float, theta_end: float, ratio: float, k: float = 1.0) -> float:
    """Offset c (rad) of the included angle ψ = θ + c that gives moment arms e_start/e_end = k with
    L_end/L_start = ``ratio`` (eq. 3.8–3.9, 3.14; c = α12 for the boom, c = −α34 for the stick)."""
    return math.atan((k * math.sin(theta_end) - ratio * math.sin(theta_start))
                     / (ratio * math.cos(theta_start) - k * math.cos(theta_end)))


def lever_synthesis(psi_end: float, psi_start: float, ratio: float) -> tuple[float, float]:
    """(s, r) of a cylinder triangle: second lever = s·a, shortest length L_min = r·a, for an included angle going
    from ``psi_start`` to ``psi_end`` (rad) with L_max/L_min = ``ratio`` (eq. 3.12–3.13, 3.15–3.17)."""
    if not ratio > 1:
        raise InputError(f"the stroke ratio λ = L_max/L_min must be > 1, got {ratio:g}")
    b = 2 * ratio**2 * math.cos(psi_start) - 2 * math.cos(psi_end)
    discriminant = b * b - 4 * (ratio**2 - 1) ** 2
    if discriminant < 0:
        raise InputError(f"no cylinder with λ = {ratio:g} turns its joint from an included angle of "
                         f"{psi_start / DEG:.4g}° to {psi_end / DEG:.4g}°: choose a larger λ or a smaller range")
    s = (b + math.sqrt(discriminant)) / (2 * (ratio**2 - 1))
    return s, math.sqrt(s * s + 1 - 2 * s * math.cos(psi_start))


def triangle_side(a: float, b: float, angle: float) -> float:
    """Third side of a triangle with sides a, b and the included angle (law of cosines)."""
    return math.sqrt(a * a + b * b - 2 * a * b * math.cos(angle))


def transmission_angle(lever: float, other: float, psi: float) -> float:
    """Angle (rad, folded to [0, π/2]) at the end of ``lever`` between the lever and the cylinder of a triangle with
    the levers ``lever`` and ``other`` and the included angle ψ (the report's fun_driving_angle, folded)."""
    length = triangle_side(lever, other, psi)
    gamma = math.acos(max(-1.0, min(1.0, (lever**2 + length**2 - other**2) / (2 * lever * length))))
    return min(gamma, math.pi - gamma)


# ------------------------------------------------------------------------------------------------- design
@dataclass(frozen=True)
class FrontShovelDesign:
    """Inputs of the design (the report's values by default; lengths m, angles in degrees as named).

    ``height_requirement`` is H2max: 9.53 m in the report's MATLAB code (9.52 in its text).
    """

    max_digging_radius: float = 9.06
    max_digging_depth: float = 3.2
    max_digging_height: float = 9.53
    min_digging_radius: float = 4.2
    ground_angle_deg: float = 25.0  # ζ, bucket QV to the ground at R0min and R2max
    dump_angle_deg: float = 40.0  # δ in θ3min = 2π − θ1max − θ2max − δ (the MATLAB code uses ζ)
    boom_foot: tuple[float, float] = (0.5, 2.7)
    boom: float = 4.3
    stick: float = 3.3
    bucket: float = 2.0
    boom_cylinder_lever: float = 1.2  # l5 = CA
    boom_lever_offset_deg: float = 20.0  # α2 = ∠FCB
    boom_ratio: float = 1.7  # λ of the boom cylinder (the report's text; its MATLAB code uses 1.9)
    stick_cylinder_lever: float = 1.0  # l9 = FE
    stick_lever_angle_deg: float = 40.0  # α3 = ∠CFD
    stick_ratio: float = 1.7
    bucket_cylinder_lever: float = 0.7  # l11 = QK
    bucket_lever_angle_deg: float = 60.0  # α5 = ∠KQV
    bucket_start_angle_deg: float = 40.0  # included angle ∠GQK at θ3min (40.0° in the report's numbers)
    bucket_ratio: float = 1.7
    arm_ratio_k: float = 1.0  # k = e_start/e_end for boom and stick
    boom_cylinders: int = 2
    # masses (kg), centres at mid-link; the report gives none: illustrative values for a 46 t front shovel
    boom_mass: float = 4500.0
    stick_mass: float = 2200.0
    bucket_mass: float = 3800.0

    def __post_init__(self) -> None:
        for name in ("max_digging_radius", "max_digging_depth", "max_digging_height", "min_digging_radius", "boom",
                     "stick", "bucket", "boom_cylinder_lever", "stick_cylinder_lever", "bucket_cylinder_lever"):
            if not getattr(self, name) > 0:
                raise InputError(f"front shovel design: {name} must be > 0 m, got {getattr(self, name)!r}")
        for name in ("boom_mass", "stick_mass", "bucket_mass"):
            if not getattr(self, name) >= 0:
                raise InputError(f"front shovel design: {name} must be >= 0 kg, got {getattr(self, name)!r}")


@dataclass(frozen=True)
class CylinderDesign:
    """A designed cylinder: levers (m), included-angle offset (rad), stroke (m)."""

    name: str
    lever_fixed: float  # lever on the joint's parent side (l5, l8, l10)
    lever_driven: float  # lever on the driven link (l7, l9, l11)
    offset: float  # c in ψ = θ + c
    stroke: tuple[float, float]
    theta_range: tuple[float, float]

    @property
    def ratio(self) -> float:
        return self.stroke[1] / self.stroke[0]

    def length(self, theta: float) -> float:
        return triangle_side(self.lever_fixed, self.lever_driven, theta + self.offset)

    def lever_arm(self, theta: float) -> float:
        """Moment arm e = a b sin ψ / L of the cylinder force about the joint (= dL/dθ)."""
        psi = theta + self.offset
        return self.lever_fixed * self.lever_driven * math.sin(psi) / self.length(theta)

    def min_transmission_angle(self, samples: int = 2001) -> float:
        thetas = np.linspace(*self.theta_range, samples)
        return min(transmission_angle(self.lever_driven, self.lever_fixed, t + self.offset) for t in thetas)


@dataclass(frozen=True)
class FrontShovel:
    """The synthesized front shovel: joint ranges (rad) and the three cylinders."""

    design: FrontShovelDesign
    theta1: tuple[float, float]
    theta2: tuple[float, float]
    theta3: tuple[float, float]
    boom_cylinder: CylinderDesign
    stick_cylinder: CylinderDesign
    bucket_cylinder: CylinderDesign
    theta3_max_candidates: tuple[float, float] = field(default=(0.0, 0.0))

    @property
    def cylinders(self) -> tuple[CylinderDesign, CylinderDesign, CylinderDesign]:
        return self.boom_cylinder, self.stick_cylinder, self.bucket_cylinder

    def tip(self, theta1: float, theta2: float, theta3: float) -> np.ndarray:
        """Tooth tip V (m) for the report's joint angles (rad)."""
        d = self.design
        return (np.asarray(d.boom_foot) + d.boom * _e(theta1) + d.stick * _e(theta1 + theta2 - math.pi)
                + d.bucket * _e(theta1 + theta2 + theta3))

    def cylinder_lengths(self, theta1: float, theta2: float, theta3: float) -> dict[str, float]:
        return {c.name: c.length(t) for c, t in zip(self.cylinders, (theta1, theta2, theta3))}


def joint_ranges(d: FrontShovelDesign) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float],
                                                   tuple[float, float]]:
    """θ1, θ2, θ3 ranges (rad) from the working dimensions (eq. 3.2–3.7) and the two θ3max candidates."""
    l1, l2, l3 = d.boom, d.stick, d.bucket
    xc, yc = d.boom_foot
    zeta = d.ground_angle_deg * DEG

    def acos(x: float, what: str) -> float:
        if not -1 <= x <= 1:
            raise InputError(f"front shovel: the links cannot reach the required {what}")
        return math.acos(x)

    def asin(x: float, what: str) -> float:
        if not -1 <= x <= 1:
            raise InputError(f"front shovel: the links cannot reach the required {what}")
        return math.asin(x)

    t2_max = acos((l1**2 + l2**2 - (d.max_digging_radius - l3 - xc) ** 2) / (2 * l1 * l2), "digging radius")
    t2_min = acos((l1**2 + l2**2 - (yc - l3 * math.sin(zeta)) ** 2
                   - (d.min_digging_radius - l3 * math.cos(zeta) - xc) ** 2) / (2 * l1 * l2), "minimum radius")
    l44 = triangle_side(l1, l2, t2_max)  # |CQ| with the stick out
    t1_max = (asin((d.max_digging_height - l3 - yc) / l44, "digging height")
              + math.asin(l2 * math.sin(t2_max) / l44))
    t1_min = asin((-d.max_digging_depth - yc + l2 + l3) / l1, "digging depth")
    candidates = (2.5 * math.pi - t1_max - t2_max, math.pi + math.asin(l1 * math.sin(t2_max) / l44))
    t3_max = max(candidates)
    t3_min = 2 * math.pi - t1_max - t2_max - d.dump_angle_deg * DEG
    return (t1_min, t1_max), (t2_min, t2_max), (t3_min, t3_max), candidates


def synthesize(d: FrontShovelDesign | None = None) -> FrontShovel:
    """Joint ranges and cylinders of a front shovel (the whole of the report's section 3)."""
    d = d or FrontShovelDesign()
    th1, th2, th3, candidates = joint_ranges(d)
    cylinders = []
    # boom: ψ = θ1 + α12, levers l5 (CA, turntable) and l7 = s·l5 (CB, boom)
    # stick: ψ = θ2 − α34, levers l8 = s·l9 (FD, boom) and l9 (FE, stick)
    # bucket: ψ = θ3 − θ3min + ψ_start, levers l10 = s·l11 (QG, stick) and l11 (QK, bucket)
    for name, (t_lo, t_hi), ratio, lever in (("L1", th1, d.boom_ratio, d.boom_cylinder_lever),
                                             ("L2", th2, d.stick_ratio, d.stick_cylinder_lever)):
        offset = included_angle_offset(t_lo, t_hi, ratio, d.arm_ratio_k)
        s, r = lever_synthesis(t_hi + offset, t_lo + offset, ratio)
        fixed, driven = (lever, s * lever) if name == "L1" else (s * lever, lever)
        cylinders.append(CylinderDesign(name, fixed, driven, offset, (r * lever, ratio * r * lever), (t_lo, t_hi)))
    offset = d.bucket_start_angle_deg * DEG - th3[0]
    s, r = lever_synthesis(th3[1] + offset, th3[0] + offset, d.bucket_ratio)
    lever = d.bucket_cylinder_lever
    cylinders.append(CylinderDesign("L3", s * lever, lever, offset, (r * lever, d.bucket_ratio * r * lever), th3))
    return FrontShovel(d, th1, th2, th3, *cylinders, theta3_max_candidates=candidates)


# ------------------------------------------------------------------------------------------ special positions
def special_positions(shovel: FrontShovel) -> dict[str, tuple[float, float, float]]:
    """The report's special tooth-tip positions (2.1–2.4) as joint angles (θ1, θ2, θ3) in rad:
    maximum digging radius, maximum digging height, maximum digging depth and maximum radius at ground level."""
    d = shovel.design
    l1, l2, l3 = d.boom, d.stick, d.bucket
    xc, yc = d.boom_foot
    t1_min, t1_max = shovel.theta1
    t2_max = shovel.theta2[1]
    l44 = triangle_side(l1, l2, t2_max)
    phi26 = math.asin(l2 * math.sin(t2_max) / l44)  # ∠FCQ
    zeta = d.ground_angle_deg * DEG
    psi = math.asin((yc - l3 * math.sin(zeta)) / l44)
    return {
        # C, Q, V on one horizontal line, stick cylinder fully out
        "max_digging_radius": (phi26, t2_max, math.pi + math.asin(l1 * math.sin(t2_max) / l44)),
        # boom and stick cylinders fully out, QV pointing up
        "max_digging_height": (t1_max, t2_max, 2.5 * math.pi - t1_max - t2_max),
        # boom cylinder fully in, FQ and QV vertical down
        "max_digging_depth": (t1_min, math.pi / 2 - t1_min, math.pi),
        # teeth on the ground, stick out, QV at ζ below the horizontal
        "max_ground_radius": (phi26 - psi, t2_max, 2 * math.pi - (phi26 - psi) - t2_max - zeta),
    }


# ---------------------------------------------------------------------------------------------- mechanism
def build(shovel: FrontShovel | None = None, reference: tuple[float, float, float] | None = None) -> Mechanism:
    """The closed-loop model: boom, stick, bucket and the three cylinders (actuated lengths L1, L2, L3), drawn at
    ``reference`` joint angles (default: mid-range)."""
    shovel = shovel or synthesize()
    d = shovel.design
    t1, t2, t3 = reference or tuple(sum(r) / 2 for r in (shovel.theta1, shovel.theta2, shovel.theta3))
    boom, stick_cyl, bucket_cyl = shovel.cylinders
    C = np.asarray(d.boom_foot, dtype=float)
    F = C + d.boom * _e(t1)
    Q = F + d.stick * _e(t1 + t2 - math.pi)
    V = Q + d.bucket * _e(t1 + t2 + t3)
    alpha2 = d.boom_lever_offset_deg * DEG
    B = C + boom.lever_driven * _e(t1 + alpha2)  # CB at α2 above CF
    A = C + boom.lever_fixed * _e(t1 + alpha2 - (t1 + boom.offset))  # ∠ACB = θ1 + α12, fixed on the turntable
    alpha3 = d.stick_lever_angle_deg * DEG
    D = F + stick_cyl.lever_fixed * _e(t1 + math.pi + alpha3)  # ∠CFD = α3, towards Q
    E = F + stick_cyl.lever_driven * _e(t1 + math.pi + alpha3 + t2 + stick_cyl.offset)  # ∠DFE = θ2 − α34
    alpha5 = d.bucket_lever_angle_deg * DEG
    K = Q + bucket_cyl.lever_driven * _e(t1 + t2 + t3 - alpha5)  # ∠KQV = α5, towards the stick
    G = Q + bucket_cyl.lever_fixed * _e(t1 + t2 + t3 - alpha5 - (t3 + bucket_cyl.offset))  # ∠GQK = θ3 + c

    b = PlanarBuilder("front_shovel")
    b.point("C", GROUND, C)
    b.point("A", GROUND, A)
    b.point("ground_x", GROUND, (C[0] + 1.0, C[1]), report=False)
    def bar(mass: float, start: np.ndarray, end: np.ndarray) -> dict:
        return {"mass": mass, "com": (start + end) / 2, "inertia": mass * float(np.sum((end - start) ** 2)) / 12}

    boom_body = b.revolute("boom", "C", toward=F, coordinate="theta1", limits=shovel.theta1,
                           **bar(d.boom_mass, C, F))
    for name, point in (("F", F), ("B", B), ("D", D)):
        b.point(name, boom_body, point)
    stick_body = b.revolute("stick", "F", toward=Q, coordinate="stick_angle", **bar(d.stick_mass, F, Q))
    for name, point in (("Q", Q), ("E", E), ("G", G)):
        b.point(name, stick_body, point)
    bucket_body = b.revolute("bucket", "Q", toward=V, coordinate="bucket_angle", **bar(d.bucket_mass, Q, V))
    for name, point in (("V", V), ("K", K)):
        b.point(name, bucket_body, point)
    b.cylinder("L1", "A", "B", stroke=boom.stroke, count=d.boom_cylinders)
    b.cylinder("L2", "D", "E", stroke=stick_cyl.stroke)
    b.cylinder("L3", "G", "K", stroke=bucket_cyl.stroke)
    b.line("boom", "C", "B", "D", "F", "C")
    b.line("stick", "F", "E", "Q", "G", "F")
    b.line("bucket", "Q", "K", "V", "Q")
    b.line("turntable", "A", "C", kind="ground")
    for name, cyl, pivot, lever_end in (("boom", "L1", "C", "B"), ("stick", "L2", "F", "E"), ("bucket", "L3", "Q", "K")):
        base, eye = b.cylinders[cyl].base, b.cylinders[cyl].eye
        b.transmission_angle(f"{name}_transmission_angle", base, eye, pivot, lever_end, minimum_deg=30.0)
        b.lever_arm(f"{name}_lever_arm", base, eye, pivot)
    params = {name: Parameter(name, float(value), "ratio" if name.endswith(("_ratio", "_k", "_mass")) else "length",
                              f"design input {name}")
              for name, value in asdict(d).items() if isinstance(value, float) and not name.endswith("_deg")}

    def rebuild(values: dict[str, float]) -> Mechanism:
        return build(synthesize(replace(d, **values)), reference)

    return b.build(actuated=["L1", "L2", "L3"], parameters=params, rebuild=rebuild, tool="V",
                   description="front-shovel excavator working device (boom, stick, bucket, 3 cylinders)",
                   input_rates={"L1": 0.1, "L2": 0.1, "L3": 0.1},
                   notes=["seed 001 course-design report; 'mechatron excavator' compares its numbers with the "
                          "report's (mechatron.machines.excavator.report_comparison)"])


def joint_angles(mech: Mechanism, q: np.ndarray) -> tuple[float, float, float]:
    """The report's (θ1, θ2, θ3) of an assembled configuration (rad)."""
    from ..kinematics.geometry import point_positions

    C, F, Q, V = point_positions(mech, q, "C", "F", "Q", "V")
    a_cf = math.atan2(*(F - C)[::-1])
    a_fc, a_fq = math.atan2(*(C - F)[::-1]), math.atan2(*(Q - F)[::-1])
    a_qf, a_qv = math.atan2(*(F - Q)[::-1]), math.atan2(*(V - Q)[::-1])
    return a_cf, (a_fq - a_fc) % (2 * math.pi), (a_qv - a_qf) % (2 * math.pi)


def front_shovel(**overrides: float) -> Mechanism:
    """Front-shovel excavator working device of seed 001 (boom, stick, bucket; cylinders L1 (twin), L2, L3)."""
    return build(synthesize(replace(FrontShovelDesign(), **overrides)) if overrides else None)


# ---------------------------------------------------------------------------------------------- working range
@dataclass
class WorkingRange:
    """Tooth-tip positions over the whole strokes.

    ``faces``: for each face of the stroke box (one cylinder at a limit) an (n, n, 2) grid of tip positions over the
    other two strokes; ``arcs``: the tip path of each box edge (two cylinders at limits, the third swept). The
    extremes are taken over all of them; the ground reach interpolates the y = 0 crossings along every grid line.
    Their error is of the order of the squared grid step.
    """

    faces: list[np.ndarray]
    arcs: list[np.ndarray]
    failures: int

    @property
    def cloud(self) -> np.ndarray:
        return np.vstack([f.reshape(-1, 2) for f in self.faces])

    def _lines(self) -> list[np.ndarray]:
        lines = list(self.arcs)
        for face in self.faces:
            lines.extend(face[i] for i in range(face.shape[0]))
            lines.extend(face[:, j] for j in range(face.shape[1]))
        return lines

    @property
    def summary(self) -> dict[str, float]:
        points = np.vstack([self.cloud, *self.arcs])
        ground = []
        for line in self._lines():
            y = line[:, 1]
            for i in np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) <= 0):
                t = y[i] / (y[i] - y[i + 1]) if y[i] != y[i + 1] else 0.0
                ground.append(line[i, 0] + t * (line[i + 1, 0] - line[i, 0]))
        return {"max_digging_radius": float(points[:, 0].max()), "max_digging_height": float(points[:, 1].max()),
                "max_digging_depth": float(-points[:, 1].min()),
                "max_ground_radius": float(max(ground)) if ground else math.nan}


def working_range(mech: Mechanism, samples: int = 41, progress=None) -> WorkingRange:
    """Sweep all three cylinder strokes: each face of the stroke box on a ``samples`` × ``samples`` grid (a
    serpentine path, so that every sample continues from its neighbour) and every edge as an arc."""
    from ..kinematics.sweep import sweep

    names = list(mech.cylinders)
    strokes = {n: np.linspace(*mech.cylinders[n].stroke, samples) for n in names}
    runs = []
    for fixed in names:
        free = [n for n in names if n != fixed]
        for limit in mech.cylinders[fixed].stroke:
            a, b = np.meshgrid(strokes[free[0]], strokes[free[1]], indexing="ij")
            b[1::2] = b[1::2, ::-1]  # serpentine: every other row backwards
            runs.append(("face", {fixed: np.full(a.size, limit), free[0]: a.ravel(), free[1]: b.ravel()}))
        for lo_hi in ((0, 0), (0, 1), (1, 1), (1, 0)):
            values = {n: np.full(samples, mech.cylinders[n].stroke[k]) for n, k in zip(free, lo_hi)}
            runs.append(("arc", {fixed: strokes[fixed], **values}))
    faces, arcs, failures = [], [], 0
    q = mech.reference_q
    for k, (kind, inputs) in enumerate(runs):
        q = assemble(mech, {n: float(v[0]) for n, v in inputs.items()}, guess=q)  # continue from the last run
        result = sweep(mech, inputs, frames=["V"], measures=[], guess=q)
        failures += len(result.failures)
        tips = np.full((len(inputs[names[0]]), 2), np.nan)
        tips[result.table["sample"].to_numpy()] = result.table[["V_x", "V_y"]].to_numpy()
        if len(result.table):
            q = result.q[-1]
        if kind == "face":
            grid = tips.reshape(samples, samples, 2)
            grid[1::2] = grid[1::2, ::-1]  # undo the serpentine
            faces.append(grid)
        else:
            arcs.append(tips)
        if progress is not None:
            progress(k + 1, len(runs))
    if failures:
        raise InputError(f"{mech.name}: {failures} positions of the stroke box could not be assembled")
    return WorkingRange(faces, arcs, failures)


def plot_working_range(mech: Mechanism, working: WorkingRange, shovel: FrontShovel, path) -> object:
    """PNG of the working range: reachable tip positions, boundary arcs, the special positions and the machine."""
    from pathlib import Path

    from matplotlib.figure import Figure

    from ..io.output import save_figure as _save
    from ..kinematics.drawing import draw_mechanism

    fig = Figure(figsize=(8, 7), layout="constrained")
    ax = fig.subplots()
    ax.scatter(working.cloud[:, 0], working.cloud[:, 1], s=1, color="tab:blue", alpha=0.15,
               label="tooth tip, all strokes")
    for i, arc in enumerate(working.arcs):
        ax.plot(arc[:, 0], arc[:, 1], color="tab:blue", lw=1, label="two cylinders at a limit" if i == 0 else None)
    for name, angles in special_positions(shovel).items():
        q = assemble(mech, shovel.cylinder_lengths(*angles))
        tip = frame_placement(mech, q, "V").translation
        ax.plot(tip[0], tip[1], "o", color="tab:red")
        ax.annotate(name.replace("_", " "), tip[:2], textcoords="offset points", xytext=(5, 5), fontsize=8)
    draw_mechanism(mech, mech.reference_q, ax, labels=True)
    ax.axhline(0.0, color="saddlebrown", lw=1.5, label="ground")
    ax.set(aspect="equal", xlabel="x (m)", ylabel="y (m)", title="front shovel: working range")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    path = Path(path)
    _save(fig, path)
    return path


# ------------------------------------------------------------------------------------------- report checks
def report_comparison(shovel: FrontShovel | None = None) -> list[dict]:
    """The report's printed numbers against this implementation, with a reason for every one that differs.

    Values in the report's units (m, degrees). ``reproduced`` is true when the printed value is the computed one
    rounded as printed.
    """
    shovel = shovel or synthesize()
    d = shovel.design
    deg = 1 / DEG
    rows: list[dict] = []

    def add(quantity, printed, computed, tolerance, note="", unit="deg"):
        rows.append({"quantity": quantity, "report": printed, "computed": round(float(computed), 4), "unit": unit,
                     "reproduced": bool(abs(printed - computed) <= tolerance), "note": note})

    add("boom l1 = 1.2·∛46 (3.1)", 4.3, first_sizing(46)["boom"], 0.005, unit="m")
    add("stick l2 = 0.9·∛46 (3.1)", 3.3, first_sizing(46)["stick"], 0.05,
        "0.9·∛46 = 3.22 m; the report designs with 3.3 m (as does its MATLAB code), and so does mechatron", "m")
    add("θ2max (3.2)", 118.8, shovel.theta2[1] * deg, 0.05)
    add("θ2min (3.3)", 38.0, shovel.theta2[0] * deg, 0.05,
        "the substitution printed on line 116 (1.7 and 3.6 in place of l3 = 2.0 and R0min = 4.2) would give 33°")
    l44 = triangle_side(d.boom, d.stick, shovel.theta2[1])
    add("L44max = |CQ| (line 128)", 6.84, l44, 0.005,
        "|CQ| = R1max − l3 − xc = 6.56 m by construction of θ2max; 6.84 m would need l3 = 1.72 m", "m")
    add("θ1max (3.3b), line 133", 72.0, shovel.theta1[1] * deg, 0.05,
        "lines 150 and 205 use 73.6°, the value of the formula; 72° comes from the odd substitution on line 131")
    add("θ1max, lines 150 and 205", 73.6, shovel.theta1[1] * deg, 0.05)
    add("θ1min (3.4)", -8.0, shovel.theta1[0] * deg, 0.05)
    add("θ3max, height condition (3.5)", 257.6, shovel.theta3_max_candidates[0] * deg, 0.1)
    add("θ3max', radius condition (3.6)", 207.0, shovel.theta3_max_candidates[1] * deg, 0.5,
        "180° + arcsin(l1 sin θ2max / L44max) = 215.1° (213.4° with the report's 6.84 m); 207° is not reproducible")
    add("θ3min with δ = 40° (3.7)", 127.7, shovel.theta3[0] * deg, 0.05)
    tips = {k: shovel.tip(*v) for k, v in special_positions(shovel).items()}
    add("R2max, ground reach (2.4)", 8.71, tips["max_ground_radius"][0], 0.005,
        "8.71 m is 2.45·∛46 from the empirical table; the geometry gives the tip on the ground at 8.605 m", "m")
    # the stick block exactly as the report computed it, with its rounded range θ2 = 37°…118.8°
    t_lo, t_hi = 37 * DEG, 118.8 * DEG
    c = included_angle_offset(t_lo, t_hi, 1.7)
    s, r = lever_synthesis(t_hi + c, t_lo + c, 1.7)
    add("stick α34 (3.14), θ2 = 37°…118.8°", 4.5, -c * deg, 0.1)
    add("stick s = l8/l9 (3.15)", 2.6, s, 0.05, unit="-")
    add("stick r = L2min/l9 (3.16)", 1.87, r, 0.005, unit="-")
    add("stick L2max", 3.18, 1.7 * r, 0.005, unit="m")
    stick = CylinderDesign("L2", 2.6, 1.0, c, (r, 1.7 * r), (t_lo, t_hi))
    add("stick minimum transmission angle (3.4)", 49.0, stick.min_transmission_angle() * deg, 0.5)
    # the boom block
    t1_lo, t1_hi = shovel.theta1
    add("boom α12 with λ = 1.7 (3.9)", 37.3, included_angle_offset(t1_lo, t1_hi, 1.7) * deg, 0.05,
        "the report states λ = 1.7 but 37.3° needs λ ≈ 1.9, the value hard-coded in its MATLAB code (37.44°)")
    add("boom l7 = CB (3.12)", 2.74, shovel.boom_cylinder.lever_driven, 0.005,
        "l7 = 2.74, L1min = 1.94, L1max = 3.50 m fit together as a triangle but imply λ = 1.80 and k = 1.28, "
        "not the stated λ = 1.7, k = 1; with them the transmission angle at B can never exceed arcsin(l5/l7) = 26°",
        "m")
    add("boom L1min", 1.94, shovel.boom_cylinder.stroke[0], 0.005, "see l7", "m")
    add("boom L1max", 3.50, shovel.boom_cylinder.stroke[1], 0.005, "see l7", "m")
    add("boom minimum transmission angle", 32.0, shovel.boom_cylinder.min_transmission_angle() * deg, 0.5,
        "impossible with the report's own l5 = 1.2, l7 = 2.74 m (at most 26°); the design fails the 30° check")
    # the bucket triangle as printed: l11 = 0.7, λ = 1.7, ∠GQK from 40.0° to 150.2° (the printed lengths fit it)
    s3, r3 = lever_synthesis(150.2 * DEG, 40.0 * DEG, 1.7)
    add("bucket l10 = QG (3.17)", 2.04, s3 * 0.7, 0.005, unit="m")
    add("bucket L3min", 1.57, r3 * 0.7, 0.005, unit="m")
    add("bucket L3max", 2.67, 1.7 * r3 * 0.7, 0.005, unit="m")
    bucket = CylinderDesign("L3", s3 * 0.7, 0.7, 0.0, (r3 * 0.7, 1.7 * r3 * 0.7), (40.0 * DEG, 150.2 * DEG))
    add("bucket minimum transmission angle", 34.0, bucket.min_transmission_angle() * deg, 0.5,
        "over the printed triangle's 110° sweep the angle at K falls to 22.3°; the report itself concludes (line "
        "374) that the four-bar bucket linkage cannot turn the bucket the required 130° with γ >= 30°")
    return rows


# ------------------------------------------------------------------------------------------------ loads
@dataclass(frozen=True)
class CylinderSpec:
    """Bore and rod diameters (m) of one hydraulic cylinder; ``count`` of them act side by side."""

    bore: float
    rod: float
    count: int = 1

    def __post_init__(self) -> None:
        if not (self.bore > self.rod > 0):
            raise InputError(f"cylinder: need bore > rod > 0 m, got bore {self.bore:g}, rod {self.rod:g}")

    @property
    def piston_area(self) -> float:
        return math.pi * self.bore**2 / 4

    @property
    def annulus_area(self) -> float:
        return math.pi * (self.bore**2 - self.rod**2) / 4

    def pressure(self, force: float) -> float:
        """Pressure (Pa) that makes the total force ``force`` (N, > 0 pushing the rod out): on the piston side when
        pushing, on the rod side when pulling."""
        per_cylinder = force / self.count
        return per_cylinder / self.piston_area if per_cylinder >= 0 else -per_cylinder / self.annulus_area

    def force(self, pressure: float, extending: bool = True) -> float:
        """Total force (N) at ``pressure`` (Pa) on the piston (extending) or the annulus (retracting)."""
        return pressure * self.count * (self.piston_area if extending else self.annulus_area)


#: Illustrative cylinders of a 46 t front shovel (the report gives none): twin boom, stick and bucket cylinders.
DEFAULT_CYLINDERS = {"L1": CylinderSpec(0.180, 0.125, 2), "L2": CylinderSpec(0.200, 0.140),
                     "L3": CylinderSpec(0.180, 0.125)}
#: Relief pressure of the working circuits (Pa).
RELIEF_PRESSURE = 32e6

#: Which cylinder turns the bucket lip about which pivot (ISO 6015: arm and bucket cylinder tool forces).
TOOL_FORCES = {"arm": ("L2", "F"), "bucket": ("L3", "Q")}


def tool_forces(mech: Mechanism, q: np.ndarray, cylinders: dict[str, CylinderSpec] | None = None,
                pressure: float = RELIEF_PRESSURE) -> dict[str, dict[str, float]]:
    """Calculated tool forces at the lip V (N) in the manner of ISO 6015: one cylinder at ``pressure`` with the others
    held, the force tangential to the arc the lip describes about the arm pivot F (stick cylinder) or the bucket
    pivot Q (bucket cylinder). By virtual power F_tool = F_cylinder · L̇ / |v_V| for the motion of that cylinder
    alone; gravity and friction are not included (the standard's calculation method). For extending (piston side)
    and retracting (rod side)."""
    cylinders = cylinders or DEFAULT_CYLINDERS
    out = {}
    for name, (cylinder, pivot) in TOOL_FORCES.items():
        v = joint_velocity(mech, q, {cylinder: 1.0})
        lip_speed = float(np.linalg.norm(point_velocity(mech, q, v, "V")[:2]))
        spec = cylinders[cylinder]
        out[name] = {"cylinder": cylinder, "pivot": pivot,
                     "extending": spec.force(pressure, True) / lip_speed,
                     "retracting": spec.force(pressure, False) / lip_speed}
    return out


def cylinder_loads(mech: Mechanism, configurations: np.ndarray, tooth_force: tuple[float, float] = (0.0, 0.0),
                   cylinders: dict[str, CylinderSpec] | None = None) -> pd.DataFrame:
    """Static cylinder forces (N, > 0 pushing) and pressures (Pa) holding the front shovel at each configuration
    against gravity and a force on the tooth tip V (world N): from the closed-loop inverse dynamics at rest."""
    import pandas as pd

    from ..dynamics.constrained import inverse

    cylinders = cylinders or DEFAULT_CYLINDERS
    rows = []
    zero = np.zeros(mech.nv)
    for q in configurations:
        forces, _ = inverse(mech, q, zero, zero, loads=[("V", [tooth_force[0], tooth_force[1], 0.0])])
        tip = frame_placement(mech, q, "V").translation
        row = {"V_x": tip[0], "V_y": tip[1]}
        for name, force in forces.items():
            row[f"{name}_force"] = force
            row[f"{name}_pressure"] = cylinders[name].pressure(force)
        rows.append(row)
    return pd.DataFrame(rows)

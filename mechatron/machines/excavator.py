r"""Front-shovel hydraulic excavator working device, designed as in the course-design report [Shovel].

Boom (link CF = l1), stick (FQ = l2) and bucket (QV = l3, V the tooth tip), driven by three hydraulic cylinders:
the twin boom cylinder A–B (A on the turntable, B on the boom), the stick cylinder D–E (D on the boom, E on the stick)
and the bucket cylinder G–K (G on the stick, K on the bucket). The report's angles: θ1 is the boom angle of CF from
the horizontal, θ2 the interior angle CFQ at F, θ3 the angle at Q from QF to QV (counter-clockwise); the absolute
angles are θ1, θ1 + θ2 − π (stick) and θ1 + θ2 + θ3 (bucket).

The design follows the report step by step:

1. empirical first sizing L = K ∛m [Shovel, 3.1];
2. joint ranges from the working dimensions [Shovel, 3.2–3.7]: R1max, H1max, H2max, R0min, the bucket-to-ground
   angle ζ and the dump angle δ;
3. each cylinder across its joint is a triangle with levers a, s·a; the included angle ψ = θ + c grows with the joint
   angle. The offset c that makes the moment arms at both ends equal in the ratio k = e_start/e_end
   [Shovel, 3.8–3.9, 3.14]: tan c = (k sin θ_end − λ sin θ_start)/(λ cos θ_start − k cos θ_end); the lever ratio s
   and the shortest length r·a for a stroke ratio λ = L_max/L_min [Shovel, 3.10–3.13, 3.15–3.17]:
   (λ² − 1)s² − (2λ² cos ψ_start − 2 cos ψ_end)s + (λ² − 1) = 0, r² = s² + 1 − 2 s cos ψ_start;
4. lever arms e = a·s·a sin ψ / L and transmission angles (the angle at the driven lever's pin between the cylinder
   and the lever, folded to [0°, 90°]) checked against 30° [Shovel, 3.18–3.19];
5. special tooth-tip positions [Shovel, 2.1–2.4] and the working range from sweeping all strokes.

:func:`shovel_spec` describes the synthesized device as a mechanism file (a
:class:`~mechatron.model.linkage.LinkageSpec`) and :func:`write_shovel` writes it (``mechatron excavator --design FILE
-o my_shovel.toml``); the report's design ships as ``robots/front_shovel.toml`` (``mechatron.load("front_shovel")``),
and every command reads such files. :func:`excavator_report` gathers all of it, with the tool forces by the
calculation of [ISO 6015, 5.2.1–5.2.2] and the holding loads, into an :class:`ExcavatorReport` (what ``mechatron
excavator`` prints). The report's printed numbers are compared with these in the test suite's
``validation/excavator.py``.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.values import number
from ..kinematics.frames import frame_placement, point_velocity
from ..kinematics.geometry import acute_angle
from ..kinematics.loops import assemble, joint_velocity
from ..model.linkage import BodySpec, JointSpec, LengthSpec, LinkageSpec, MeasureSpec, PointSpec, build_linkage
from ..model.linkage_file import write_linkage_file
from ..model.mechanism import Mechanism
from ..model.planar import GROUND
from ..report.result import Result
from . import plausible

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DEG = math.pi / 180


def _e(angle: float) -> NDArray[np.float64]:
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
    """Dimensions L = K ∛m (m) of a machine of ``mass_t`` tonnes [Shovel, 3.1]."""
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
    L_end/L_start = ``ratio`` [Shovel, 3.8–3.9, 3.14] (c = α12 for the boom, c = −α34 for the stick). Angles in rad."""
    return math.atan((k * math.sin(theta_end) - ratio * math.sin(theta_start))
                     / (ratio * math.cos(theta_start) - k * math.cos(theta_end)))


def lever_synthesis(psi_end: float, psi_start: float, ratio: float) -> tuple[float, float]:
    """(s, r) of a cylinder triangle: second lever = s·a, shortest length L_min = r·a, for an included angle going
    from ``psi_start`` to ``psi_end`` (rad) with L_max/L_min = ``ratio`` [Shovel, 3.12–3.13, 3.15–3.17]."""
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
    the levers ``lever`` and ``other`` and the included angle ψ (the report's fun_driving_angle, folded): the cylinder
    L = √(a² + b² − 2ab cos ψ) (:func:`triangle_side`), cos γ = (a² + L² − b²)/(2aL), μ = min(γ, π − γ)
    (:func:`~mechatron.kinematics.geometry.acute_angle`)."""
    length = triangle_side(lever, other, psi)
    return float(acute_angle((lever**2 + length**2 - other**2) / (2 * lever * length)))


# ------------------------------------------------------------------------------------------------- design
#: The plausible range of each field of a design (mechatron's, docs/front_shovel_design.md).
DESIGN_RANGES = {
    **dict.fromkeys(("max_digging_radius", "max_digging_depth", "max_digging_height", "min_digging_radius", "boom",
                     "stick", "bucket", "boom_cylinder_lever", "stick_cylinder_lever", "bucket_cylinder_lever"),
                    plausible.LENGTH),
    **dict.fromkeys(("ground_angle_deg", "dump_angle_deg"), plausible.BUCKET_ANGLE),
    **dict.fromkeys(("boom_lever_offset_deg", "stick_lever_angle_deg", "bucket_lever_angle_deg"), plausible.ANGLE),
    "bucket_start_angle_deg": plausible.INCLUDED_ANGLE,
    "boom_foot": plausible.POSITION,
    **dict.fromkeys(("boom_ratio", "stick_ratio", "bucket_ratio"), plausible.STROKE_RATIO),
    "arm_ratio_k": plausible.ARM_RATIO,
    "boom_cylinders": plausible.BOOM_CYLINDERS,
    **dict.fromkeys(("boom_mass", "stick_mass", "bucket_mass"), plausible.LINK_MASS),
}


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
        """Refuse a field outside its plausible range (:data:`DESIGN_RANGES`, mechatron's), naming the field."""
        for name, bounds in DESIGN_RANGES.items():
            value = getattr(self, name)
            if name == "boom_foot":
                if len(value) != 2:
                    raise InputError(f"needs two numbers x, y (m), got {value!r}", field=name)
                for x in value:
                    bounds.check(name, x)
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
                raise InputError(f"expected a number, got {type(value).__name__} {value!r}", field=name)
            if name == "boom_cylinders" and value != math.floor(value):
                raise InputError(f"expected a whole number, got {value!r}", field=name)
            bounds.check(name, value)


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
        """λ = L_max / L_min."""
        return self.stroke[1] / self.stroke[0]

    def length(self, theta: float) -> float:
        """Cylinder length (m) at the joint angle θ (rad): the triangle's third side."""
        return triangle_side(self.lever_fixed, self.lever_driven, theta + self.offset)

    def lever_arm(self, theta: float) -> float:
        """Moment arm e = a b sin ψ / L of the cylinder force about the joint (= dL/dθ)."""
        psi = theta + self.offset
        return self.lever_fixed * self.lever_driven * math.sin(psi) / self.length(theta)

    def min_transmission_angle(self, samples: int = 2001) -> float:
        """The smallest transmission angle (rad) over the joint range, on ``samples`` angles [Shovel, 3.18]."""
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
        """The boom, stick and bucket cylinders."""
        return self.boom_cylinder, self.stick_cylinder, self.bucket_cylinder

    def tip(self, theta1: float, theta2: float, theta3: float) -> NDArray[np.float64]:
        """Tooth tip V (m) for the report's joint angles (rad)."""
        d = self.design
        return (np.asarray(d.boom_foot) + d.boom * _e(theta1) + d.stick * _e(theta1 + theta2 - math.pi)
                + d.bucket * _e(theta1 + theta2 + theta3))

    def cylinder_lengths(self, theta1: float, theta2: float, theta3: float) -> dict[str, float]:
        """Lengths (m) of the cylinders L1, L2, L3 at the report's joint angles (rad)."""
        return {c.name: c.length(t) for c, t in zip(self.cylinders, (theta1, theta2, theta3))}


@dataclass(frozen=True)
class Maths:
    """The functions the range and position formulas use, on numbers (:data:`CHECKED`: an argument of acos or asin
    outside [−1, 1] means the links cannot reach a required dimension, named by ``what``) or on CasADi expressions
    (:func:`casadi_maths`)."""

    acos: Callable[[Any, str], Any]
    asin: Callable[[Any, str], Any]
    sin: Callable[[Any], Any]
    cos: Callable[[Any], Any]
    sqrt: Callable[[Any], Any]
    maximum: Callable[[Any, Any], Any]


#: The field of a design that asks for each working dimension the range formulas check.
REQUIRED_BY = {"digging radius": "max_digging_radius", "minimum radius": "min_digging_radius",
               "digging height": "max_digging_height", "digging depth": "max_digging_depth",
               "radius at ground level": "boom_foot"}


def _checked(f: Callable[[float], float]) -> Callable[[float, str], float]:
    def checked(x: float, what: str) -> float:
        if not -1 <= x <= 1:
            raise InputError(f"front shovel: the links (boom, stick, bucket) cannot reach the required {what}",
                             field=REQUIRED_BY.get(what))
        return f(x)

    return checked


CHECKED = Maths(_checked(math.acos), _checked(math.asin), math.sin, math.cos, math.sqrt, max)


def casadi_maths(arguments: list[Any] | None = None) -> Maths:
    """:class:`Maths` on CasADi expressions; the arguments of acos and asin are appended to ``arguments`` (for the
    requirement |argument| ≤ 1 of an optimisation)."""
    import casadi as ca

    kept = arguments if arguments is not None else []

    def keep(f: Callable[[Any], Any]) -> Callable[[Any, str], Any]:
        def kept_f(x: Any, what: str) -> Any:
            kept.append(x)
            return f(x)

        return kept_f

    return Maths(keep(ca.acos), keep(ca.asin), ca.sin, ca.cos, ca.sqrt, ca.fmax)


def range_angles(d: FrontShovelDesign, l1: Any, l2: Any, l3: Any, m: Maths = CHECKED) -> tuple:
    """θ1, θ2, θ3 ranges (rad) of links l1 = |CF|, l2 = |FQ|, l3 = |QV| (m; numbers or CasADi expressions) that
    reach the working dimensions of ``d`` [Shovel, 3.2–3.7], and the two θ3max candidates (rad): the height
    condition [Shovel, 3.5] and the radius condition [Shovel, 3.6]."""
    xc, yc = d.boom_foot
    zeta = d.ground_angle_deg * DEG
    t2_max = m.acos((l1**2 + l2**2 - (d.max_digging_radius - l3 - xc) ** 2) / (2 * l1 * l2), "digging radius")
    t2_min = m.acos((l1**2 + l2**2 - (yc - l3 * math.sin(zeta)) ** 2
                     - (d.min_digging_radius - l3 * math.cos(zeta) - xc) ** 2) / (2 * l1 * l2), "minimum radius")
    l44 = m.sqrt(l1 * l1 + l2 * l2 - 2 * l1 * l2 * m.cos(t2_max))  # |CQ| with the stick out
    t1_max = (m.asin((d.max_digging_height - l3 - yc) / l44, "digging height")
              + m.asin(l2 * m.sin(t2_max) / l44, "digging height"))
    t1_min = m.asin((-d.max_digging_depth - yc + l2 + l3) / l1, "digging depth")
    candidates = (2.5 * math.pi - t1_max - t2_max, math.pi + m.asin(l1 * m.sin(t2_max) / l44, "digging radius"))
    t3_max = m.maximum(*candidates)
    t3_min = 2 * math.pi - t1_max - t2_max - d.dump_angle_deg * DEG
    return (t1_min, t1_max), (t2_min, t2_max), (t3_min, t3_max), candidates


def joint_ranges(d: FrontShovelDesign) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float],
                                                   tuple[float, float]]:
    """θ1, θ2, θ3 ranges (rad) from the working dimensions [Shovel, 3.2–3.7] and the two θ3max candidates (rad):
    the height condition [Shovel, 3.5] and the radius condition [Shovel, 3.6] (:func:`range_angles` of the
    design's links)."""
    return range_angles(d, d.boom, d.stick, d.bucket)


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
        s, r = _levers(t_hi + offset, t_lo + offset, ratio, "boom_ratio" if name == "L1" else "stick_ratio",
                       "arm_ratio_k")
        fixed, driven = (lever, s * lever) if name == "L1" else (s * lever, lever)
        cylinders.append(CylinderDesign(name, fixed, driven, offset, (r * lever, ratio * r * lever), (t_lo, t_hi)))
    offset = d.bucket_start_angle_deg * DEG - th3[0]
    s, r = _levers(th3[1] + offset, th3[0] + offset, d.bucket_ratio, "bucket_ratio", "bucket_start_angle_deg")
    lever = d.bucket_cylinder_lever
    cylinders.append(CylinderDesign("L3", s * lever, lever, offset, (r * lever, d.bucket_ratio * r * lever), th3))
    return FrontShovel(d, th1, th2, th3, *cylinders, theta3_max_candidates=candidates)


def _levers(psi_end: float, psi_start: float, ratio: float, name: str, angle: str) -> tuple[float, float]:
    """:func:`lever_synthesis`, an error naming the design's field ``name`` (the cylinder's stroke ratio); an included
    angle ψ that passes 0° or 180° over the stroke (a triangle folding through its dead point, where the cylinder
    loses the joint) names the field ``angle`` that sets it."""
    if math.floor(psi_start / math.pi) != math.floor(psi_end / math.pi) or math.sin(psi_start) == 0:
        raise InputError(f"the cylinder's included angle goes from {psi_start / DEG:.4g}° to {psi_end / DEG:.4g}° "
                         "over its stroke, through a dead point (0° or 180°) where the cylinder cannot turn the "
                         "joint", field=angle)
    try:
        return lever_synthesis(psi_end, psi_start, ratio)
    except InputError as exc:
        raise InputError(exc.message, field=name) from None


# ------------------------------------------------------------------------------------------ special positions
def special_angles(d: FrontShovelDesign, l1: Any, l2: Any, l3: Any, theta1: tuple[Any, Any], t2_max: Any,
                   m: Maths = CHECKED) -> dict[str, tuple[Any, Any, Any]]:
    """The special tooth-tip positions [Shovel, 2.1–2.4] as joint angles (θ1, θ2, θ3) (rad) of links l1, l2, l3 (m)
    with the boom's range ``theta1`` and the stick's θ2max (numbers or CasADi expressions)."""
    xc, yc = d.boom_foot
    t1_min, t1_max = theta1
    l44 = m.sqrt(l1 * l1 + l2 * l2 - 2 * l1 * l2 * m.cos(t2_max))
    phi26 = m.asin(l2 * m.sin(t2_max) / l44, "digging radius")  # ∠FCQ
    zeta = d.ground_angle_deg * DEG
    psi = m.asin((yc - l3 * math.sin(zeta)) / l44, "radius at ground level")
    return {
        # C, Q, V on one horizontal line, stick cylinder fully out
        "max_digging_radius": (phi26, t2_max, math.pi + m.asin(l1 * m.sin(t2_max) / l44, "digging radius")),
        # boom and stick cylinders fully out, QV pointing up
        "max_digging_height": (t1_max, t2_max, 2.5 * math.pi - t1_max - t2_max),
        # boom cylinder fully in, FQ and QV vertical down
        "max_digging_depth": (t1_min, math.pi / 2 - t1_min, math.pi),
        # teeth on the ground, stick out, QV at ζ below the horizontal
        "max_ground_radius": (phi26 - psi, t2_max, 2 * math.pi - (phi26 - psi) - t2_max - zeta),
    }


def special_positions(shovel: FrontShovel) -> dict[str, tuple[float, float, float]]:
    """The report's special tooth-tip positions [Shovel, 2.1–2.4] as joint angles (θ1, θ2, θ3) in rad:
    maximum digging radius, maximum digging height, maximum digging depth and maximum radius at ground level
    (:func:`special_angles` of the design's links)."""
    d = shovel.design
    return special_angles(d, d.boom, d.stick, d.bucket, shovel.theta1, shovel.theta2[1])


# ---------------------------------------------------------------------------------------------- mechanism
def shovel_spec(shovel: FrontShovel | None = None, reference: tuple[float, float, float] | None = None
                ) -> LinkageSpec:
    """The mechanism file of a synthesized front shovel (default: :func:`synthesize` of the report's design): boom,
    stick and bucket (uniform bars CF, FQ, QV of the design's masses) and the three cylinders (actuated lengths L1
    (twin: ``boom_cylinders`` side by side), L2, L3, m), drawn at ``reference`` joint angles (θ1, θ2, θ3, rad;
    default mid-range).

    Coordinates: ``theta1`` (the angle of CF from the horizontal, limited to the synthesized range), ``stick_angle``
    and ``bucket_angle`` (of FQ relative to CF and of QV relative to FQ), rad. Measures: each cylinder's transmission
    angle (30° minimum [Shovel, 3.18–3.19]) and lever arm about its joint. Named lengths (m): boom = |CF|,
    stick = |FQ|, bucket = |QV| and the cylinder levers l5 = |CA|, l7 = |CB|, l8 = |FD|, l9 = |FE|, l10 = |QG|,
    l11 = |QK| [Shovel, 3.8–3.17].
    """
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
    pins = {"C": C, "A": A, "F": F, "B": B, "D": D, "Q": Q, "E": E, "G": G, "V": V, "K": K}
    measures = []
    for name, (base, eye, pivot) in (("boom", "ABC"), ("stick", "DEF"), ("bucket", "GKQ")):
        measures += [MeasureSpec("transmission_angle", f"{name}_transmission_angle", (base, eye, pivot, eye),
                                 minimum=30 * DEG),
                     MeasureSpec("lever_arm", f"{name}_lever_arm", (base, eye, pivot))]
    return LinkageSpec(
        name="front_shovel",
        description="front-shovel excavator working device (boom, stick, bucket, 3 cylinders)",
        source="[Shovel]",
        points=tuple(PointSpec(n, (float(p[0]), float(p[1]))) for n, p in pins.items()),
        bodies=(BodySpec(GROUND, ("C", "A"), draw=("A", "C")),
                BodySpec("boom", ("C", "F", "B", "D"), mass=d.boom_mass, shape="bar", draw=("C", "B", "D", "F", "C")),
                BodySpec("stick", ("F", "Q", "E", "G"), mass=d.stick_mass, shape="bar",
                         draw=("F", "E", "Q", "G", "F")),
                BodySpec("bucket", ("Q", "V", "K"), mass=d.bucket_mass, shape="bar", draw=("Q", "K", "V", "Q"))),
        joints=(JointSpec("revolute", body="boom", at="C", toward="F", coordinate="theta1", limits=shovel.theta1),
                JointSpec("revolute", body="stick", at="F", toward="Q", coordinate="stick_angle"),
                JointSpec("revolute", body="bucket", at="Q", toward="V", coordinate="bucket_angle"),
                JointSpec("cylinder", name="L1", base="A", eye="B", stroke=boom.stroke, count=d.boom_cylinders),
                JointSpec("cylinder", name="L2", base="D", eye="E", stroke=stick_cyl.stroke),
                JointSpec("cylinder", name="L3", base="G", eye="K", stroke=bucket_cyl.stroke)),
        actuated=("L1", "L2", "L3"),
        measures=tuple(measures),
        lengths=tuple(LengthSpec(name, (a, b)) for name, (a, b) in (
            ("boom", "CF"), ("stick", "FQ"), ("bucket", "QV"), ("l5", "CA"), ("l7", "CB"), ("l8", "FD"),
            ("l9", "FE"), ("l10", "QG"), ("l11", "QK"))),
        tool="V",
        input_rates={"L1": 0.1, "L2": 0.1, "L3": 0.1},
        notes=("designed as in the front-shovel course-design report [Shovel]; masses illustrative",),
    )


def file_header(shovel: FrontShovel) -> str:
    """The comment heading a written front-shovel file: the design it comes from and its joint ranges."""
    changed = {f.name: getattr(shovel.design, f.name) for f in fields(FrontShovelDesign)
               if getattr(shovel.design, f.name) != f.default}
    design = ", ".join(f"{k} = {v}" for k, v in changed.items()) if changed else "the report's values"
    ranges = ", ".join(f"θ{i} {lo / DEG:.3f}…{hi / DEG:.3f}°" for i, (lo, hi) in
                       enumerate((shovel.theta1, shovel.theta2, shovel.theta3), start=1))
    return "\n".join([
        "Front-shovel excavator working device [Shovel], written by mechatron.machines.excavator.write_shovel",
        "(mechatron excavator --design FILE -o FILE) from the design's synthesis [Shovel, 3.1–3.19]:",
        *textwrap.wrap(f"design: {design};", 110), f"joint ranges: {ranges}.",
        "Drawn at mid-range joint angles; world x horizontal, y up (m), the ground at y = 0. A new design goes",
        "through the synthesis (mechatron excavator --design), not through this file."])


def write_shovel(design: FrontShovelDesign | FrontShovel | None, path: str | Path) -> Path:
    """Write the mechanism file (:func:`shovel_spec`) of a design (synthesized first; default the report's) or of a
    synthesized shovel to ``path``; the mechanism is named after the file (``my_shovel.toml``: ``my_shovel``).
    What ``mechatron excavator --design FILE -o PATH`` does; every command reads the file."""
    shovel = design if isinstance(design, FrontShovel) else synthesize(design)
    spec = replace(shovel_spec(shovel), name=Path(path).stem)
    return write_linkage_file(spec, path, header=file_header(shovel))


def joint_angles(mech: Mechanism, q: ArrayLike) -> tuple[float, float, float]:
    """The report's (θ1, θ2, θ3) of an assembled configuration (rad)."""
    from ..kinematics.geometry import point_positions

    C, F, Q, V = point_positions(mech, q, "C", "F", "Q", "V")
    a_cf = math.atan2(*(F - C)[::-1])
    a_fc, a_fq = math.atan2(*(C - F)[::-1]), math.atan2(*(Q - F)[::-1])
    a_qf, a_qv = math.atan2(*(F - Q)[::-1]), math.atan2(*(V - Q)[::-1])
    return a_cf, (a_fq - a_fc) % (2 * math.pi), (a_qv - a_qf) % (2 * math.pi)


# ---------------------------------------------------------------------------------------------- working range
@dataclass
class WorkingRange:
    """Tooth-tip positions over the whole strokes.

    ``faces``: for each face of the stroke box (one cylinder at a limit) an (n, n, 2) grid of tip positions over the
    other two strokes; ``arcs``: the tip path of each box edge (two cylinders at limits, the third swept). The
    extremes are taken over all of them; the ground reach interpolates the y = 0 crossings along every grid line.
    Their error is of the order of the squared grid step.
    """

    faces: list[NDArray[np.float64]]
    arcs: list[NDArray[np.float64]]
    failures: int

    @property
    def cloud(self) -> NDArray[np.float64]:
        """All tip positions of the faces (m), one per row."""
        return np.vstack([f.reshape(-1, 2) for f in self.faces])

    def _lines(self) -> list[np.ndarray]:
        lines = list(self.arcs)
        for face in self.faces:
            lines.extend(face[i] for i in range(face.shape[0]))
            lines.extend(face[:, j] for j in range(face.shape[1]))
        return lines

    @property
    def summary(self) -> dict[str, float]:
        """The largest digging radius, height and depth and the reach at ground level (m) [Shovel, 2.1–2.4]."""
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


def working_range(mech: Mechanism, samples: int = 41, progress: Callable[[int, int], None] | None = None
                  ) -> WorkingRange:
    """Sweep all three cylinder strokes: each face of the stroke box on a ``samples`` × ``samples`` grid (a
    serpentine path, so that every sample continues from its neighbour) and every edge as an arc. Tip positions in
    m; ``progress(done, total)`` is called after each of the runs."""
    from ..kinematics.sweeps import sweep

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


def plot_working_range(mech: Mechanism, working: WorkingRange, shovel: FrontShovel, ax: Axes | None = None
                       ) -> Figure:
    """The working range (m): the tooth tip over all strokes, the boundary arcs (two cylinders at a limit), the
    special positions [Shovel, 2.1–2.4] and the machine at its reference configuration. Drawn into ``ax`` if given;
    returns the figure."""
    from ..kinematics.drawing import draw_mechanism
    from ..report.figures import figure_axes, style_axes

    fig, ax = figure_axes(ax, 8.0, 7.0)
    ax.scatter(working.cloud[:, 0], working.cloud[:, 1], s=1, color="tab:blue", alpha=0.15,
               label="tooth tip, all strokes")
    for i, arc in enumerate(working.arcs):
        ax.plot(arc[:, 0], arc[:, 1], color="tab:blue", lw=1, label="two cylinders at a limit" if i == 0 else None)
    for i, (name, angles) in enumerate(special_positions(shovel).items()):
        tip = frame_placement(mech, assemble(mech, shovel.cylinder_lengths(*angles)), "V").translation
        ax.plot(tip[0], tip[1], "o", color="tab:red", label="special positions" if i == 0 else None)
        ax.annotate(name.replace("_", " "), tip[:2], textcoords="offset points", xytext=(5, 5), fontsize=8)
    draw_mechanism(mech, mech.reference_q, ax, labels=True)
    ax.axhline(0.0, color="saddlebrown", lw=1.5, label="ground")
    ax.set_aspect("equal")
    style_axes(ax, "x (m)", "y (m)", "front shovel: working range", legend=True, loc="lower left")
    return fig


# ------------------------------------------------------------------------------------------------ design file
def read_design(path: str | Path) -> FrontShovelDesign:
    """A front-shovel design from a TOML file with any fields of :class:`FrontShovelDesign` (lengths m, angles in
    degrees as named, masses kg); the fields not given keep the report's values. The ``[machine]`` table, the rest of
    the machine, is :func:`mechatron.machines.shovel_machine.read_machine`'s."""
    from ..io.schema import FieldReader
    from ..io.toml import read_toml

    reader = FieldReader(read_toml(path), file=path)
    values: dict[str, Any] = {}
    for f in fields(FrontShovelDesign):
        if not reader.has(f.name):
            continue
        if f.name == "boom_foot":
            values[f.name] = tuple(float(x) for x in reader.vector(f.name, 2))
        elif f.name == "boom_cylinders":
            values[f.name] = reader.whole(f.name, minimum=1)
        else:
            values[f.name] = reader.number(f.name)
    reader.table("machine", None)  # read by shovel_machine.read_machine
    reader.finish()
    try:
        return replace(FrontShovelDesign(), **values)
    except InputError as exc:
        raise InputError(exc.message, file=path, field=exc.field) from None


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
    def areas(self) -> tuple[float, float]:
        """(A₁, A₂): the piston area π D²/4 and the annulus area π (D² − d²)/4 (m²) of one cylinder
        (:func:`~mechatron.drives.cylinders.cylinder_areas`)."""
        from ..drives.cylinders import cylinder_areas  # it imports pandas: not on this module's import

        piston, annulus = cylinder_areas(self.bore, self.rod)
        return float(piston), float(annulus)

    @property
    def piston_area(self) -> float:
        """A₁ = π D² / 4 (m²) of one cylinder."""
        return self.areas[0]

    @property
    def annulus_area(self) -> float:
        """A₂ = π (D² − d²) / 4 (m²) of one cylinder."""
        return self.areas[1]

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

#: Which cylinder turns the bucket lip about which pivot: the arm cylinder about the arm pivot F, the bucket cylinder
#: about the bucket pivot Q [ISO 6015, 3.2, 4.8.2–4.8.3].
TOOL_FORCES = {"arm": ("L2", "F"), "bucket": ("L3", "Q")}


def tool_forces(mech: Mechanism, q: ArrayLike, cylinders: dict[str, CylinderSpec] | None = None,
                pressure: float = RELIEF_PRESSURE) -> dict[str, dict[str, Any]]:
    """Tool forces at the lip V (N) at the configuration ``q`` by the calculation of [ISO 6015, 5.2.1–5.2.2] as
    mechatron applies it: one cylinder at ``pressure`` (Pa) with the others held, the force tangential to the arc the
    lip describes about the arm pivot F (stick cylinder) or the bucket pivot Q (bucket cylinder) [ISO 6015,
    4.8.2–4.8.3]. By virtual power F_tool = F_cylinder · L̇ / |v_V| for the motion of that cylinder alone; no weights
    and no friction. ``extending`` (piston side) digs as the standard's forces do; ``retracting`` (rod side) is
    mechatron's addition. The standard's rated force is the largest over the positions
    (:func:`~mechatron.machines.digging.digging_forces`), not the one at ``q``."""
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


def cylinder_loads(mech: Mechanism, configurations: ArrayLike, tooth_force: ArrayLike = (0.0, 0.0),
                   cylinders: dict[str, CylinderSpec] | None = None) -> pd.DataFrame:
    """Static cylinder forces (N, > 0 pushing) and pressures (Pa) holding the front shovel at each configuration
    (rows of ``configurations``) against gravity and a force (Fx, Fy) on the tooth tip V (N, world axes): the
    closed-loop inverse dynamics at rest. Columns V_x, V_y (m), ``NAME_force`` (N) and ``NAME_pressure`` (Pa)."""
    import pandas as pd

    from ..dynamics.constrained import inverse
    from ..model.loads import Load

    cylinders = cylinders or DEFAULT_CYLINDERS
    rows = []
    zero = np.zeros(mech.nv)
    for q in configurations:
        forces, _ = inverse(mech, q, zero, zero, loads=[Load("V", [tooth_force[0], tooth_force[1], 0.0])])
        tip = frame_placement(mech, q, "V").translation
        row = {"V_x": tip[0], "V_y": tip[1]}
        for name, force in forces.items():
            row[f"{name}_force"] = force
            row[f"{name}_pressure"] = cylinders[name].pressure(force)
        rows.append(row)
    return pd.DataFrame(rows)


# ------------------------------------------------------------------------------------------------ the report
@dataclass
class ExcavatorReport(Result):
    """The front-shovel design of :func:`excavator_report` (what ``mechatron excavator`` prints).

    ``cylinders``: per cylinder its levers (m), included-angle offset, strokes (m), λ, lever arms at both ends (m),
    k, smallest transmission angle and the 30° check [Shovel, 3.18–3.19]; ``special``: per special position
    [Shovel, 2.1–2.4] the joint angles, cylinder lengths (m), the tip from the closed-loop model and in closed form
    (m) and the tool forces by [ISO 6015, 5.2.1–5.2.2]'s calculation (N); ``holding``: per cylinder the largest
    pressure (Pa), push and pull (N) holding the device along its strokes against gravity and ``tooth_force``;
    ``working``: the working range.
    """

    design: FrontShovelDesign
    shovel: FrontShovel
    mechanism: Mechanism
    cylinders: dict[str, dict[str, Any]]
    special: dict[str, dict[str, Any]]
    working: WorkingRange
    holding: dict[str, dict[str, float]]
    tooth_force: tuple[float, float]
    relief_pressure: float
    samples: int

    def to_frame(self) -> pd.DataFrame:
        """The special positions: the joint angles θ1…θ3 (rad), cylinder lengths (m), the tooth tip (m) and the
        tool forces of the arm (stick) and bucket cylinders by [ISO 6015, 5.2.1–5.2.2]'s calculation, extending and
        retracting (N)."""
        import pandas as pd

        rows = []
        for name, p in self.special.items():
            row: dict[str, Any] = {"position": name}
            row.update({f"theta{i + 1}_rad": math.radians(a) for i, a in enumerate(p["theta_deg"])})
            row.update({f"{c}_m": length for c, length in p["cylinder_lengths"].items()})
            row.update({"tip_x_m": p["tip"][0], "tip_y_m": p["tip"][1]})
            for tool, forces in p["tool_forces"].items():
                row[f"{tool}_tool_force_extending_N"] = forces["extending"]
                row[f"{tool}_tool_force_retracting_N"] = forces["retracting"]
            rows.append(row)
        return pd.DataFrame(rows)

    def as_dict(self) -> dict:
        """design, joint_ranges_deg, cylinders, special_positions, working_range (m) and loads (N, Pa)."""
        deg = 1 / DEG
        return {
            "design": dict(vars(self.design)),
            "joint_ranges_deg": {"theta1": [x * deg for x in self.shovel.theta1],
                                 "theta2": [x * deg for x in self.shovel.theta2],
                                 "theta3": [x * deg for x in self.shovel.theta3]},
            "cylinders": self.cylinders, "special_positions": self.special, "working_range": self.working.summary,
            "loads": {"tooth_force": list(self.tooth_force), "relief_pressure": self.relief_pressure,
                      "cylinders": self.holding},
        }

    def plot(self, ax: Axes | None = None) -> Figure:
        """The working range and the machine (:func:`plot_working_range`)."""
        return plot_working_range(self.mechanism, self.working, self.shovel, ax)

    def __str__(self) -> str:
        d, deg = self.design, 1 / DEG
        lines = ["front-shovel working device [Shovel], lengths in m, angles in degrees",
                 f"links: boom CF = {d.boom:g}, stick FQ = {d.stick:g}, bucket QV = {d.bucket:g}; "
                 f"boom foot C = {d.boom_foot}"]
        for name, (lo, hi) in zip(("theta1", "theta2", "theta3"), (self.shovel.theta1, self.shovel.theta2,
                                                                     self.shovel.theta3)):
            lines.append(f"  {name}: {lo * deg:8.3f} … {hi * deg:8.3f}")
        lines.append(f"\n{'cylinder':<9}{'levers':>16}{'L_min':>8}{'L_max':>8}{'stroke':>8}{'λ':>7}{'e start':>9}"
                     f"{'e end':>8}{'γ min':>8}  ≥30°")
        for name, c in self.cylinders.items():
            twin = f" (x{c['count']})" if c["count"] > 1 else ""
            lines.append(f"{name + twin:<9}{c['levers'][0]:8.3f}{c['levers'][1]:8.3f}{c['L_min']:8.3f}"
                         f"{c['L_max']:8.3f}{c['stroke']:8.3f}{c['ratio']:7.3f}{c['lever_arm_start']:9.3f}"
                         f"{c['lever_arm_end']:8.3f}{c['min_transmission_angle_deg']:8.2f}  "
                         f"{c['transmission_check']}")
        lines.append("\nspecial tooth-tip positions (θ1, θ2, θ3 → tip from the closed-loop model):")
        for name, p in self.special.items():
            lines.append(f"  {name:<20} ({', '.join(f'{a:.3f}' for a in p['theta_deg'])}) → "
                         f"({p['tip'][0]:.4f}, {p['tip'][1]:.4f})")
        lines.append(f"\ntool forces at the lip by [ISO 6015, 5.2.1–5.2.2]'s calculation, one cylinder at relief "
                     f"pressure {self.relief_pressure / 1e6:g} MPa, no weights (kN, extending / retracting: the rod "
                     "side, mechatron's addition); the rated forces, the largest over the range: --lift-chart")
        for name, p in self.special.items():
            arm, bucket = p["tool_forces"]["arm"], p["tool_forces"]["bucket"]
            lines.append(f"  {name:<20} arm {arm['extending'] / 1e3:7.1f} / {arm['retracting'] / 1e3:6.1f}"
                         f"   bucket {bucket['extending'] / 1e3:7.1f} / {bucket['retracting'] / 1e3:6.1f}")
        lines.append(f"holding loads along the strokes (gravity, tooth force {self.tooth_force} N): largest "
                     "pressure per cylinder")
        for name, p in self.holding.items():
            over = "  EXCEEDS the relief pressure" if p["max_pressure"] > self.relief_pressure else ""
            lines.append(f"  {name}: {p['max_pressure'] / 1e6:7.2f} MPa (push up to {p['max_push'] / 1e3:.1f} kN, "
                         f"pull up to {p['max_pull'] / 1e3:.1f} kN){over}")
        w = self.working.summary
        lines.append(f"\nworking range over all strokes ({self.samples} per stroke): reach "
                     f"{w['max_digging_radius']:.3f}, height {w['max_digging_height']:.3f}, depth "
                     f"{w['max_digging_depth']:.3f}, reach at ground {w['max_ground_radius']:.3f}")
        return "\n".join(lines)


def excavator_report(design: FrontShovelDesign | None = None, samples: int = 31,
                     tooth_force: ArrayLike = (0.0, 0.0), cylinders: dict[str, CylinderSpec] | None = None,
                     pressure: float = RELIEF_PRESSURE, progress: Callable[[int, int], None] | None = None
                     ) -> ExcavatorReport:
    """Design a front shovel as the report does [Shovel, section 3] and check it: the cylinders with their levers,
    strokes, λ, lever arms and transmission angles [Shovel, 3.8–3.19], the special positions [Shovel, 2.1–2.4]
    with their tool forces by [ISO 6015, 5.2.1–5.2.2]'s calculation, the holding loads along the strokes and the
    working range.

    Args:
        design: the design inputs (default: the report's).
        samples: grid points per cylinder stroke for the working range and the holding loads.
        tooth_force: (Fx, Fy) on the tooth tip V for the holding loads (N, world axes).
        cylinders: bore and rod of each cylinder (default :data:`DEFAULT_CYLINDERS`).
        pressure: relief pressure of the working circuits (Pa) for the tool forces.
        progress: called with (done, total) while the working range is swept.
    """
    from ..kinematics.sweeps import sweep

    tooth = np.asarray(tooth_force, dtype=float).reshape(-1)
    if tooth.shape != (2,) or not np.all(np.isfinite(tooth)):
        raise InputError(f"the tooth force needs two finite numbers Fx, Fy (N), got {tooth_force!r}")
    if isinstance(samples, float):  # a count: 31, not 31.0
        raise InputError(f"samples must be a whole number >= 2, got {samples!r}")
    samples = number("samples", samples, integer=True, minimum=2)
    pressure = number("pressure", pressure, positive=True, maximum=1e10, unit="Pa")
    design = design or FrontShovelDesign()
    specs = cylinders or DEFAULT_CYLINDERS
    shovel = synthesize(design)
    mech = build_linkage(shovel_spec(shovel))
    from ..kinematics.sweeps import positions_budget

    positions_budget(mech, samples, "samples", per_position=6 * samples + 1)  # 6 faces of samples² and a sweep
    deg = 1 / DEG
    special = {}
    for name, angles in special_positions(shovel).items():
        lengths = shovel.cylinder_lengths(*angles)
        q = assemble(mech, lengths)
        special[name] = {"theta_deg": [a * deg for a in angles], "cylinder_lengths": lengths,
                         "tip": frame_placement(mech, q, "V").translation[:2].tolist(),
                         "tip_closed_form": shovel.tip(*angles).tolist(),
                         "tool_forces": tool_forces(mech, q, specs, pressure)}
    table = {}
    for c in shovel.cylinders:
        e_start, e_end = c.lever_arm(c.theta_range[0]), c.lever_arm(c.theta_range[1])
        gamma = c.min_transmission_angle() * deg
        table[c.name] = {"levers": [c.lever_fixed, c.lever_driven], "offset_deg": c.offset * deg,
                         "L_min": c.stroke[0], "L_max": c.stroke[1], "stroke": c.stroke[1] - c.stroke[0],
                         "ratio": c.ratio, "lever_arm_start": e_start, "lever_arm_end": e_end,
                         "k": e_start / e_end, "min_transmission_angle_deg": gamma,
                         "transmission_check": "PASS" if gamma >= 30 else "FAIL",
                         "count": mech.cylinders[c.name].count}
    working = working_range(mech, samples, progress=progress)
    loads = cylinder_loads(mech, sweep(mech, samples=samples).q, tooth_force=(tooth[0], tooth[1]), cylinders=specs)
    holding = {name: {"max_pressure": float(loads[f"{name}_pressure"].max()),
                      "max_push": float(loads[f"{name}_force"].max()),
                      "max_pull": float(-loads[f"{name}_force"].min())} for name in mech.actuated}
    return ExcavatorReport(design, shovel, mech, table, special, working, holding, (float(tooth[0]), float(tooth[1])),
                           float(pressure), int(samples))

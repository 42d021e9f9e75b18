r"""Denavit–Hartenberg arms: the link matrices of [Egorov, section 4.3] and the Pinocchio model built from a DH table.

Two conventions are supported.

**Standard ([Egorov, 4.40–4.42]).** Frame i is fixed to link i, z_{i-1} lies along the axis of
pair i and x_i along the common normal of z_{i-1} and z_i. The transform from frame i to frame i−1 is

.. math::

    A_{i-1,i} = R_z(\theta_i)\,T_z(S_i)\,T_x(a_i)\,R_x(\alpha_i)
    = \begin{bmatrix} c\theta & -s\theta c\alpha & s\theta s\alpha & a c\theta \\
                      s\theta & c\theta c\alpha & -c\theta s\alpha & a s\theta \\
                      0 & s\alpha & c\alpha & S \\ 0&0&0&1 \end{bmatrix}

with θ_i = q_i + θ_i⁰ for a revolute pair and S_i = q_i + S_i⁰ for a prismatic pair (the book's S_i is the usual d_i).
The book prints the translation column of (4.40) as (a cos α, a sin α, S); the product (4.41) of the four elementary
matrices (4.42) gives (a cos θ, a sin θ, S), which is what is implemented. The chain to the base is
B_{0,i} = A_{0,1} A_{1,2} … A_{i-1,i} ([Egorov, 4.44–4.45]).

**Modified (Craig).** Frame i sits on the axis of joint i and A_{i-1,i} = R_x(α_{i-1}) T_x(a_{i-1}) R_z(θ_i) T_z(d_i).
A table row i holds (α_{i-1}, a_{i-1}, θ_i, d_i) and its parameters are named with Craig's indices.

The Pinocchio model has one joint per row (``JointModelRZ`` or ``JointModelPZ``) whose frame is the DH frame of the
pair's axis, a BODY frame ``link{i}`` on every link at the DH frame i (where the link's inertial data is given), a frame
``base`` at frame 0 and a frame ``tool`` at the end of the arm. Drives reflect their rotor inertia into the joint as
``armature = J_rotor · u²``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

from ..errors import InputError
from .parameter import Parameter

JointKind = Literal["revolute", "prismatic"]
Convention = Literal["standard", "modified"]
JOINT_KINDS: tuple[str, ...] = ("revolute", "prismatic")
CONVENTIONS: tuple[str, ...] = ("standard", "modified")


# ----------------------------------------------------------------------------------------- elementary transforms
def rot_z(theta: float) -> np.ndarray:
    """Homogeneous rotation about z by ``theta`` (rad): A^θ of [Egorov, 4.42]."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def rot_x(alpha: float) -> np.ndarray:
    """Homogeneous rotation about x by ``alpha`` (rad): A^α of [Egorov, 4.42]."""
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    """Homogeneous translation (m): A^S = trans(z=S) and A^a = trans(x=a) of [Egorov, 4.42]."""
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def se3(matrix: np.ndarray) -> pin.SE3:
    """A 4×4 homogeneous matrix as a ``pinocchio.SE3``."""
    return pin.SE3(np.array(matrix[:3, :3]), np.array(matrix[:3, 3]))


def placement_matrix(xyz: ArrayLike = (0, 0, 0), rpy: ArrayLike = (0, 0, 0)) -> np.ndarray:
    """Homogeneous matrix of a translation ``xyz`` (m) and a roll-pitch-yaw rotation ``rpy`` (rad, URDF order)."""
    out = np.eye(4)
    out[:3, :3] = pin.rpy.rpyToMatrix(*map(float, np.asarray(rpy, dtype=float)))
    out[:3, 3] = np.asarray(xyz, dtype=float)
    return out


# ------------------------------------------------------------------------------------------------ link data
def inertial_problem(mass: float, inertia: np.ndarray, *, triangle: bool = True) -> str | None:
    """Why (``mass``, ``inertia`` about the centre of mass) is not a physical body, or ``None`` if it is.

    The tensor must be symmetric and either zero (a massless link) or positive definite. With ``triangle`` its
    principal moments must also satisfy the triangle inequality I₁ + I₂ ≥ I₃, as those of every rigid body do (some
    published data sets, e.g. the PUMA 560 link 3 of Armstrong et al. 1986, do not; their files switch the check off).
    """
    if not mass >= 0:
        return f"mass must be >= 0 kg, got {mass:g}"
    if not np.allclose(inertia, inertia.T, rtol=0, atol=1e-12 * max(1.0, np.abs(inertia).max())):
        return "inertia tensor must be symmetric"
    if not np.any(inertia):
        return None
    moments = np.linalg.eigvalsh(inertia)
    if moments[0] <= 0:
        return f"inertia tensor must be positive definite (principal moments {moments.round(9).tolist()} kg·m²)"
    if triangle and moments[0] + moments[1] < moments[2] * (1 - 1e-9):
        return (f"principal moments {moments.round(9).tolist()} kg·m² violate the triangle inequality "
                "I1 + I2 >= I3 (no rigid body has them)")
    return None


@dataclass(frozen=True)
class Inertial:
    """Inertial data of one link, in the link's DH frame.

    Attributes:
        mass: Mass (kg), >= 0.
        com: Centre of mass (m) in the link frame.
        inertia: 3×3 inertia tensor (kg·m²) about the centre of mass, axes of the link frame.
        physical: Whether the principal moments must satisfy the triangle inequality (see :func:`inertial_problem`).
    """

    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    physical: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "com", np.asarray(self.com, dtype=float).reshape(3))
        object.__setattr__(self, "inertia", np.asarray(self.inertia, dtype=float).reshape(3, 3))
        problem = inertial_problem(self.mass, self.inertia, triangle=self.physical)
        if problem:
            raise InputError(problem, field="inertia" if "inertia" in problem or "moments" in problem else "mass")

    def to_pinocchio(self) -> pin.Inertia:
        return pin.Inertia(float(self.mass), self.com.copy(), self.inertia.copy())


@dataclass(frozen=True)
class Drive:
    """Motor and transmission of one joint (motor side quantities).

    Attributes:
        rotor_inertia: Rotor inertia J_rotor (kg·m²) on the motor shaft, including what the maker lumps in
            (brake, encoder, first gear stage).
        gear_ratio: Transmission ratio u = ω_motor / ω_joint ([Egorov, 4.58]); its sign says whether the motor turns the
            same way as the joint.
        efficiency: Transmission efficiency η in (0, 1].
        viscous_friction: Viscous friction B (N·m·s/rad) on the motor shaft.
        coulomb_friction: Coulomb friction torque (N·m) on the motor shaft for positive and for negative speed.
        placement: The frame (a body's or a point's) of the body that carries the motor and its gearbox, e.g.
            ``"base"`` or ``"link3"``; ``None``: the proximal body at the joint (the joint's parent), at the joint's
            origin. The drive sizing puts the chosen motor's and gearbox's mass there.
        offset: Where on that body (m), in the axes of ``placement`` from its origin.
    """

    rotor_inertia: float = 0.0
    gear_ratio: float = 1.0
    efficiency: float = 1.0
    viscous_friction: float = 0.0
    coulomb_friction: tuple[float, float] = (0.0, 0.0)
    placement: str | None = None
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not self.rotor_inertia >= 0:
            raise InputError(f"rotor inertia must be >= 0 kg·m², got {self.rotor_inertia:g}", field="rotor_inertia")
        if self.gear_ratio == 0 or not math.isfinite(self.gear_ratio):
            raise InputError(f"gear ratio must be a non-zero number, got {self.gear_ratio:g}", field="gear_ratio")
        if not 0 < self.efficiency <= 1:
            raise InputError(f"efficiency must be in (0, 1], got {self.efficiency:g}", field="efficiency")
        if not self.viscous_friction >= 0:
            raise InputError(f"viscous friction must be >= 0, got {self.viscous_friction:g}", field="viscous_friction")
        positive, negative = (float(x) for x in self.coulomb_friction)
        if not (positive >= 0 >= negative and math.isfinite(positive) and math.isfinite(negative)):
            raise InputError(f"Coulomb friction opposes the motion: (T_c+ >= 0 for positive motor speed, T_c- <= 0 for "
                             f"negative), got ({positive:g}, {negative:g})", field="coulomb_friction")
        offset = tuple(float(x) for x in np.ravel(self.offset))
        if len(offset) != 3 or not all(math.isfinite(x) for x in offset):
            raise InputError(f"a drive's offset is 3 finite numbers (m), got {self.offset!r}", field="offset")
        object.__setattr__(self, "offset", offset)

    @property
    def reflected_inertia(self) -> float:
        """Rotor inertia seen at the joint, J_rotor · u² (kg·m² or kg for a prismatic joint)."""
        return self.rotor_inertia * self.gear_ratio**2


@dataclass(frozen=True)
class DHLink:
    """One row of a DH table.

    Attributes:
        joint: ``"revolute"`` (θ varies) or ``"prismatic"`` (S varies).
        a: Link length a (m) along the common normal.
        alpha: Link twist α (rad).
        d: Constant part of the offset S along z (m): S = d (revolute) or S = q + d (prismatic).
        theta: Constant part of the angle θ (rad): θ = q + theta (revolute) or θ = theta (prismatic).
        name: Name of the joint and of its generalized coordinate.
        lower, upper: Joint limits (rad or m).
        velocity_limit, effort_limit: Joint speed (rad/s or m/s) and torque/force (N·m or N) limits.
        inertial: Mass, centre of mass and inertia in the link frame.
        drive: Motor and gearbox data, if known.
    """

    joint: JointKind
    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    name: str = ""
    lower: float = -math.pi
    upper: float = math.pi
    velocity_limit: float = math.inf
    effort_limit: float = math.inf
    inertial: Inertial = field(default_factory=Inertial)
    drive: Drive | None = None

    def __post_init__(self) -> None:
        if self.joint not in JOINT_KINDS:
            raise InputError(f"unknown joint kind {self.joint!r}; expected one of: {', '.join(JOINT_KINDS)}",
                             field="joint")
        if not self.lower < self.upper:
            raise InputError(f"lower limit {self.lower:g} must be below upper limit {self.upper:g}", field="lower")

    @property
    def is_revolute(self) -> bool:
        return self.joint == "revolute"

    def theta_s(self, q: float) -> tuple[float, float]:
        """(θ_i, S_i) for the joint coordinate ``q``: one varies with q, the other is constant."""
        if self.is_revolute:
            return q + self.theta, self.d
        return self.theta, q + self.d


@dataclass(frozen=True)
class DHTable:
    """A serial arm described by a DH table.

    Attributes:
        links: One row per joint, base to tip.
        convention: ``"standard"`` ([Egorov, 4.40]) or ``"modified"`` (Craig).
        base: 4×4 placement of frame 0 in the world.
        tool: 4×4 placement of the tool frame in the last link frame.
        gravity: Gravity vector in the world (m/s²).
    """

    links: tuple[DHLink, ...]
    convention: Convention = "standard"
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))

    def __post_init__(self) -> None:
        if self.convention not in CONVENTIONS:
            raise InputError(f"unknown DH convention {self.convention!r}; expected one of: {', '.join(CONVENTIONS)}",
                             field="convention")
        if not self.links:
            raise InputError("a DH table needs at least one link", field="links")
        links = tuple(link if link.name else replace(link, name=f"q{i + 1}") for i, link in enumerate(self.links))
        names = [link.name for link in links]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise InputError(f"joint names must be unique, repeated: {', '.join(duplicates)}", field="links")
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "base", np.asarray(self.base, dtype=float).reshape(4, 4))
        object.__setattr__(self, "tool", np.asarray(self.tool, dtype=float).reshape(4, 4))
        object.__setattr__(self, "gravity", np.asarray(self.gravity, dtype=float).reshape(3))

    @property
    def n(self) -> int:
        return len(self.links)

    # --------------------------------------------------------------------------- the matrices of [Egorov, section 4.3]
    def A(self, i: int, qi: float) -> np.ndarray:
        """Link matrix A_{i-1,i}(q_i), 4×4, i = 1…n: maps coordinates in frame i to frame i−1 ([Egorov, 4.39–4.42]).

        Standard convention: Rz(θ_i)·Tz(S_i)·Tx(a_i)·Rx(α_i). Modified: Rx(α_{i-1})·Tx(a_{i-1})·Rz(θ_i)·Tz(d_i).
        """
        if not 1 <= i <= self.n:
            raise InputError(f"link index must be in 1..{self.n}, got {i}")
        link = self.links[i - 1]
        theta, s = link.theta_s(float(qi))
        if self.convention == "standard":
            return rot_z(theta) @ trans(z=s) @ trans(x=link.a) @ rot_x(link.alpha)
        return rot_x(link.alpha) @ trans(x=link.a) @ rot_z(theta) @ trans(z=s)

    def B(self, i: int, q: Sequence[float]) -> np.ndarray:
        """B_{0,i}(q) = A_{0,1}·A_{1,2}·…·A_{i-1,i}: frame i in the base frame 0 ([Egorov, 4.44–4.45]); B_{0,0} = I."""
        if not 0 <= i <= self.n:
            raise InputError(f"link index must be in 0..{self.n}, got {i}")
        out = np.eye(4)
        for k in range(1, i + 1):
            out = out @ self.A(k, q[k - 1])
        return out

    # ------------------------------------------------------------------------------------ parameters
    def parameter_names(self, i: int) -> dict[str, str]:
        """Parameter names of row i (1-based) by field: Craig's indices for a, α in the modified convention."""
        k = i if self.convention == "standard" else i - 1
        return {"a": f"a{k}", "alpha": f"alpha{k}", "d": f"d{i}", "theta": f"theta{i}"}

    def parameters(self) -> dict[str, Parameter]:
        """Every a, α, d (the book's S) and θ constant as a named geometric parameter."""
        out: dict[str, Parameter] = {}
        for i, link in enumerate(self.links, start=1):
            names = self.parameter_names(i)
            variable = "theta" if link.is_revolute else "d"
            for fld, kind, meaning in (
                ("a", "length", "link length a along the common normal"),
                ("alpha", "angle", "link twist alpha"),
                ("d", "length", "offset S along z" + (" (added to q)" if variable == "d" else "")),
                ("theta", "angle", "joint angle theta" + (" offset (added to q)" if variable == "theta" else "")),
            ):
                out[names[fld]] = Parameter(names[fld], float(getattr(link, fld)), kind,  # type: ignore[arg-type]
                                            f"DH {meaning}, row {i} ({link.name})")
        return out

    def with_values(self, values: Mapping[str, float]) -> DHTable:
        """The same table with some parameters replaced (names as in :meth:`parameters`)."""
        links = []
        for i, link in enumerate(self.links, start=1):
            changes: dict[str, Any] = {fld: float(values[name]) for fld, name in self.parameter_names(i).items()
                                       if name in values}
            links.append(replace(link, **changes) if changes else link)
        return replace(self, links=tuple(links))

    # ----------------------------------------------------------------------------------------- tables
    def to_frame(self) -> pd.DataFrame:
        """The DH table as a DataFrame (angles in degrees for reading; limits in the joint's unit)."""
        rows = []
        for link in self.links:
            deg = link.is_revolute
            rows.append({
                "joint": link.name,
                "kind": link.joint,
                "theta_deg": ("q+" if link.is_revolute else "") + f"{math.degrees(link.theta):g}",
                "d_m": ("q+" if not link.is_revolute else "") + f"{link.d:g}",
                "a_m": link.a,
                "alpha_deg": math.degrees(link.alpha),
                "lower": math.degrees(link.lower) if deg else link.lower,
                "upper": math.degrees(link.upper) if deg else link.upper,
                "limit_unit": "deg" if deg else "m",
                "mass_kg": link.inertial.mass,
            })
        import pandas as pd

        return pd.DataFrame(rows, index=pd.RangeIndex(1, self.n + 1, name="row"))

    # --------------------------------------------------------------------------------- pinocchio model
    def _constant_parts(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """(joint placement of row i in the previous joint frame, link frame i in joint frame i), 4×4 each."""
        link = self.links[i - 1]
        theta0, s0 = link.theta_s(0.0)
        if self.convention == "standard":
            previous = self.base if i == 1 else self._constant_parts(i - 1)[1]
            return previous, rot_z(theta0) @ trans(z=s0) @ trans(x=link.a) @ rot_x(link.alpha)
        before = self.base if i == 1 else np.eye(4)
        return before @ rot_x(link.alpha) @ trans(x=link.a) @ rot_z(theta0) @ trans(z=s0), np.eye(4)

    def constant_factors(self, i: int) -> list[tuple[str | None, np.ndarray, np.ndarray]]:
        """The constant part of row i (:meth:`_constant_parts`: the link frame i of the standard convention, the
        joint placement of the modified one) as a product of factors, each (parameter name or None, 4×4 matrix,
        the factor's twist per unit of its parameter, [v; ω]): Rz(θ) is exp([0; e_z] θ), Tz(d) exp([e_z; 0] d),
        Tx(a) exp([e_x; 0] a), Rx(α) exp([0; e_x] α)."""
        link = self.links[i - 1]
        theta0, s0 = link.theta_s(0.0)
        names = self.parameter_names(i)
        z, x = np.array([0, 0, 1.0]), np.array([1.0, 0, 0])
        rz = (names["theta"], rot_z(theta0), np.r_[0, 0, 0, z])
        tz = (names["d"], trans(z=s0), np.r_[z, 0, 0, 0])
        tx = (names["a"], trans(x=link.a), np.r_[x, 0, 0, 0])
        rx = (names["alpha"], rot_x(link.alpha), np.r_[0, 0, 0, x])
        if self.convention == "standard":
            return [rz, tz, tx, rx]
        return ([(None, self.base, np.zeros(6))] if i == 1 else []) + [rx, tx, rz, tz]

    def build_model(self) -> pin.Model:
        """The Pinocchio model of the arm (joints, inertias, limits, armature, frames ``base``, ``link{i}``,
        ``tool``)."""
        model = pin.Model()
        model.name = "dh_arm"
        model.gravity = pin.Motion(self.gravity, np.zeros(3))
        model.addFrame(pin.Frame("base", 0, 0, se3(self.base), pin.FrameType.OP_FRAME))
        parent = 0
        link_frame = np.eye(4)
        for i, link in enumerate(self.links, start=1):
            joint_placement, link_frame = self._constant_parts(i)
            joint_model = pin.JointModelRZ() if link.is_revolute else pin.JointModelPZ()
            joint_id = model.addJoint(
                parent, joint_model, se3(joint_placement), link.name,
                np.array([link.effort_limit]), np.array([link.velocity_limit]),
                np.array([link.lower]), np.array([link.upper]),
            )
            model.appendBodyToJoint(joint_id, link.inertial.to_pinocchio(), se3(link_frame))
            previous_frame = model.nframes - 1
            model.addFrame(pin.Frame(f"link{i}", joint_id, previous_frame, se3(link_frame), pin.FrameType.BODY))
            if link.drive is not None:
                v = model.joints[joint_id].idx_v
                model.rotorInertia[v] = link.drive.rotor_inertia
                model.rotorGearRatio[v] = link.drive.gear_ratio
                model.armature[v] = link.drive.reflected_inertia
            parent = joint_id
        model.addFrame(pin.Frame("tool", parent, model.nframes - 1, se3(link_frame @ self.tool),
                                 pin.FrameType.OP_FRAME))
        return model

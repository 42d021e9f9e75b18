r"""The Delta robot: three motors on a fixed base each swing an upper arm; a parallelogram (here one rod on a
universal joint) joins each elbow to the moving platform, which keeps its orientation and moves in x, y, z.

:func:`delta_spec` writes the mechanism file of a :class:`DeltaDesign` (robots/delta.toml is ``write_delta(None, …)``):
a spatial loop, the platform on a translation joint, each rod's end pinned to the platform by a point constraint.
Motor i sits at angle φ_i = 2π(i − 1)/3 around z, at radius R; its axis is a_i = (−sin φ_i, cos φ_i, 0), so a positive
angle θ_i swings the arm down. Drawn with the arms horizontal (θ = 0) and the platform below the base at
z = −√(L_b² − (R + L_a − r)²).

The closed forms used to check it: the inverse kinematics of arm i (W_i = P + r u_i, the rod's lower end; w its
coordinates relative to the motor pivot along u_i, a_i and z): w_u cos θ − w_z sin θ = (L_a² + |w|² − L_b²)/(2 L_a), and
the forward kinematics, the platform centre P on the three spheres |P + r u_i − E_i(θ_i)| = L_b.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.linkage import BodySpec, ClosureSpec, JointSpec, LinkageSpec, PointSpec
from ..model.linkage_file import write_linkage_file

HEADER = """The Delta robot, written by mechatron.machines.delta.write_delta (a DeltaDesign): a spatial mechanism file.
Motor i at angle 120°·(i − 1) around z, radius R, arm L_a, parallelogram (one rod) L_b, platform radius r.
Drawn with the arms horizontal (theta = 0); masses illustrative."""


@dataclass(frozen=True)
class DeltaDesign:
    """Dimensions (m) and masses (kg) of a Delta robot; ``limits`` of the motor angles (rad, positive down)."""

    base_radius: float = 0.20
    platform_radius: float = 0.05
    upper_arm: float = 0.30
    lower_arm: float = 0.70
    upper_arm_mass: float = 0.35
    lower_arm_mass: float = 0.12
    platform_mass: float = 0.60
    limits: tuple[float, float] = (-0.6, 1.2)

    def __post_init__(self) -> None:
        reach = self.base_radius + self.upper_arm - self.platform_radius
        if not (self.base_radius > 0 and self.platform_radius > 0 and self.upper_arm > 0 and self.lower_arm > reach):
            raise InputError("a Delta needs positive dimensions and a lower arm longer than R + L_a − r "
                             f"({reach:g} m) to hang below the base")

    def directions(self, i: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(u_i, a_i): motor i's radial direction and axis."""
        phi = 2 * math.pi * i / 3
        return np.array([math.cos(phi), math.sin(phi), 0.0]), np.array([-math.sin(phi), math.cos(phi), 0.0])

    def elbow(self, i: int, theta: float) -> NDArray[np.float64]:
        """Elbow E_i (m) at motor angle θ (rad): O_i + L_a (cos θ u_i − sin θ z)."""
        u, _ = self.directions(i)
        return self.base_radius * u + self.upper_arm * (math.cos(theta) * u - math.sin(theta) * np.array([0, 0, 1.0]))

    def inverse(self, platform: NDArray[np.float64]) -> NDArray[np.float64]:
        """Motor angles θ (rad) that put the platform centre at ``platform`` (m), elbows out (closed form)."""
        out = np.empty(3)
        for i in range(3):
            u, a = self.directions(i)
            w = np.asarray(platform, dtype=float) + self.platform_radius * u - self.base_radius * u
            wu, wz = w @ u, w[2]
            k = (self.upper_arm**2 + w @ w - self.lower_arm**2) / (2 * self.upper_arm)
            rho, delta = math.hypot(wu, wz), math.atan2(wz, wu)
            if abs(k) > rho:
                raise InputError(f"the platform position {np.round(platform, 4).tolist()} is out of reach of arm "
                                 f"{i + 1}")
            out[i] = math.remainder(-delta - math.acos(k / rho), 2 * math.pi)
        return out

    def forward(self, theta: NDArray[np.float64]) -> NDArray[np.float64]:
        """The platform centre (m) for motor angles θ (rad), below the base: three spheres intersected (closed
        form)."""
        centres = [self.elbow(i, float(theta[i])) - self.platform_radius * self.directions(i)[0] for i in range(3)]
        c1, c2, c3 = centres
        # |P − c_i|² = L_b²: subtracting pairs gives two planes; P = p0 + t n on their line
        A = np.array([c2 - c1, c3 - c1]) * 2
        b = np.array([c2 @ c2 - c1 @ c1, c3 @ c3 - c1 @ c1])
        n = np.cross(A[0], A[1])
        p0 = np.linalg.lstsq(A, b, rcond=None)[0]
        d = p0 - c1
        roots = np.roots([n @ n, 2 * n @ d, d @ d - self.lower_arm**2])
        t = min(roots.real, key=lambda r: (p0 + r * n)[2])
        return p0 + t * n


def delta_spec(design: DeltaDesign | None = None) -> LinkageSpec:
    """The mechanism file (spec) of a Delta robot drawn with its arms horizontal."""
    d = design or DeltaDesign()
    h = math.sqrt(d.lower_arm**2 - (d.base_radius + d.upper_arm - d.platform_radius) ** 2)
    centre = np.array([0.0, 0.0, -h])
    points = [PointSpec("origin", tuple(centre), report=False), PointSpec("TCP", tuple(centre))]
    bodies = [BodySpec("ground", ("origin",))]
    joints = [JointSpec("translation", body="platform", at="origin")]
    closures = []
    arm_bodies, rod_bodies, ground_points, platform_points = [], [], ["origin"], ["origin", "TCP"]
    for i in range(3):
        u, a = d.directions(i)
        pivot, elbow = d.base_radius * u, d.elbow(i, 0.0)
        end = centre + d.platform_radius * u
        k = i + 1
        points += [PointSpec(f"O{k}", tuple(pivot)), PointSpec(f"E{k}", tuple(elbow)), PointSpec(f"W{k}", tuple(end))]
        ground_points.append(f"O{k}")
        platform_points.append(f"W{k}")
        arm_bodies.append(BodySpec(f"arm{k}", (f"O{k}", f"E{k}"), mass=d.upper_arm_mass, shape="bar"))
        rod_bodies.append(BodySpec(f"rod{k}", (f"E{k}", f"W{k}"), mass=d.lower_arm_mass, shape="bar"))
        rod = (end - elbow) / d.lower_arm
        cross = np.cross(a, rod)
        joints += [JointSpec("revolute", body=f"arm{k}", at=f"O{k}", coordinate=f"theta{k}", limits=d.limits,
                             axis=tuple(float(v) for v in a)),
                   JointSpec("universal", body=f"rod{k}", at=f"E{k}",
                             axes=(tuple(float(v) for v in a), tuple(float(v) for v in cross / np.linalg.norm(cross))))]
        closures.append(ClosureSpec("pin", point=f"W{k}", bodies=(f"rod{k}", "platform")))
    bodies[0] = BodySpec("ground", tuple(ground_points), draw=("O1", "O2", "O3", "O1"), draw_kind="ground")
    bodies += arm_bodies + rod_bodies
    bodies.append(BodySpec("platform", tuple(platform_points), mass=d.platform_mass, com="TCP",
                           inertia=(1e-3, 1e-3, 2e-3), draw=("W1", "W2", "W3", "W1")))
    return LinkageSpec(name="delta", points=tuple(points), bodies=tuple(bodies), joints=tuple(joints),
                       actuated=("theta1", "theta2", "theta3"), closures=tuple(closures), planar=False,
                       description=f"Delta robot (R = {d.base_radius:g} m, r = {d.platform_radius:g} m, "
                                   f"L_a = {d.upper_arm:g} m, L_b = {d.lower_arm:g} m)",
                       tool="TCP", input_rates={"theta1": 1.0, "theta2": 1.0, "theta3": 1.0},
                       notes=("a Delta robot; each parallelogram modelled as one rod on a universal joint",))


def write_delta(design: DeltaDesign | None, path: str | Path) -> Path:
    """Write the mechanism file of ``design`` (default :class:`DeltaDesign`) to ``path``, named after the file."""
    return write_linkage_file(replace(delta_spec(design), name=Path(path).stem), path, header=HEADER)

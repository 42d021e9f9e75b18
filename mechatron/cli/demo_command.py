"""``mechatron demo``: a short tour of the foundation on the PUMA 560 (no files needed)."""

from __future__ import annotations

import argparse

import numpy as np
from numpy.typing import ArrayLike


def _vec(x: ArrayLike, precision: int = 4) -> str:
    return np.array2string(np.asarray(x), precision=precision, suppress_small=True, floatmode="fixed", sign=" ")


def run(robot: str = "puma560") -> None:
    """Load a robot, print its DH table and its kinematics at one pose (rad, m, s)."""
    from ..kinematics.frames import fk_and_jacobian, link_angular_velocities, point_acceleration, point_velocity
    from ..library import load

    mech = load(robot)
    print(f"mechatron tour: {mech.description}")
    print(f"  {mech.nq} joints, mobility W = {mech.mobility()}, total mass {mech.total_mass:.2f} kg\n")
    if mech.dh is not None:
        print(f"DH table ({mech.dh.convention} convention, [Egorov, 4.40]):")
        print(mech.dh.to_frame().drop(columns=["limit_unit"]).to_string(), "\n")

    q = np.radians([0.0, 45.0, -180.0, 0.0, 45.0, 0.0])[: mech.nq]
    v = np.array([0.5, -0.3, 0.4, 1.0, -0.8, 2.0])[: mech.nv]
    a = np.array([1.0, 0.5, -0.5, 0.0, 2.0, 0.0])[: mech.nv]
    positions, rotations, jacobians = fk_and_jacobian(mech, q[None, :])
    print(f"pose q = {_vec(np.degrees(q), 1)} deg")
    print(f"  tool position (m):           {_vec(positions[0])}")
    if mech.dh is not None:
        textbook = mech.dh.base @ mech.dh.B(mech.dh.n, q) @ mech.dh.tool
        print(f"  the B_0,n product [Egorov, 4.45] differs from Pinocchio by "
              f"{np.abs(textbook[:3, 3] - positions[0]).max():.1e} m")
    print("  tool rotation:\n" + "\n".join("    " + _vec(row) for row in rotations[0]))
    jac = jacobians[0]
    sigma = np.linalg.svd(jac, compute_uv=False)
    print(f"  Jacobian singular values:    {_vec(sigma)} (condition number {sigma[0] / sigma[-1]:.1f})")
    print(f"\nrates q' = {_vec(v, 2)} rad/s, q'' = {_vec(a, 2)} rad/s²")
    print(f"  tool velocity (m/s, [Egorov, 4.47]):      {_vec(point_velocity(mech, q, v))}")
    print(f"  tool acceleration (m/s², [Egorov, 4.49]): {_vec(point_acceleration(mech, q, v, a))}")
    omega = link_angular_velocities(mech, q, v)
    print("  link angular velocities (rad/s, [Egorov, 4.56]):")
    for name, w in zip(mech.link_names, omega):
        print(f"    {name:<8} {_vec(w)}")
    print("\nnext: mechatron list | mechatron show puma560 | mechatron fk puma560 --q 0,45,-180,0,45,0 --deg")


def cmd_demo(args: argparse.Namespace) -> int:
    run()
    return 0


def register(sub) -> None:
    p = sub.add_parser("demo", help="a short tour: load a robot and print its kinematics")
    p.set_defaults(func=cmd_demo)

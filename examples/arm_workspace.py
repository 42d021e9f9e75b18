"""Workspace and tool speed of a textbook arm, with the batch API.

Samples random configurations of an arm inside its joint limits, computes the tool position and Jacobian of all of
them in one call, and plots the reachable points coloured by the Yoshikawa manipulability sqrt(det(J_v J_vᵀ)) of the
planar (or spatial) translational Jacobian.

    python examples/arm_workspace.py [ROBOT] [--samples N] [--output FILE.png]
"""

from __future__ import annotations

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mechatron  # noqa: E402
from mechatron.io.output import save_figure  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robot", nargs="?", default="planar_2r")
    parser.add_argument("--samples", type=int, default=20_000)
    parser.add_argument("--output", default="workspace.png")
    args = parser.parse_args()

    arm = mechatron.load(args.robot)
    Q = arm.random_configuration(np.random.default_rng(1), size=args.samples)
    positions, _, jacobians = mechatron.kinematics.fk_and_jacobian(arm, Q)
    linear = jacobians[:, :3, :]
    if arm.nv < 3:
        linear = linear[:, :arm.nv, :]  # a planar arm: the in-plane rows
    manipulability = np.sqrt(np.abs(np.linalg.det(linear @ np.swapaxes(linear, 1, 2))))

    fig, ax = plt.subplots(figsize=(6, 5))
    points = ax.scatter(positions[:, 0], positions[:, 1], c=manipulability, s=2, cmap="viridis")
    fig.colorbar(points, label="manipulability")
    ax.set(xlabel="x (m)", ylabel="y (m)", title=f"{arm.name}: reachable tool positions (top view)", aspect="equal")
    fig.tight_layout()
    save_figure(fig, args.output, dpi=120)  # whole or not at all
    reach = np.linalg.norm(positions[:, :2], axis=1)
    print(f"{arm.name}: {args.samples} configurations, horizontal reach {reach.min():.3f} … {reach.max():.3f} m, "
          f"max manipulability {manipulability.max():.4f}; plot written to {args.output}")


if __name__ == "__main__":
    main()

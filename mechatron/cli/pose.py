"""``mechatron fk / jacobian``."""

from __future__ import annotations

import argparse

import numpy as np

from .common import (
    _configuration,
    _load,
    _matrix_text,
    _pose_arguments,
    _print_json,
    _robot_arguments,
)


def cmd_fk(args: argparse.Namespace) -> int:
    import pinocchio as pin

    from ..kinematics.frames import frame_placement

    mech = _load(args)
    q = _configuration(mech, args.q, args.deg)
    frame = args.frame or mech.tool_frame
    placement = frame_placement(mech, q, frame)
    if args.json:
        _print_json({"frame": frame, "position": placement.translation.tolist(),
                     "rotation": placement.rotation.tolist()})
        return 0
    rpy = np.degrees(pin.rpy.matrixToRpy(placement.rotation))
    print(f"{mech.name}, frame {frame} at q = {np.round(q, 6).tolist()}")
    print(f"position (m):      {np.array2string(placement.translation, precision=6, suppress_small=True)}")
    print(f"roll-pitch-yaw (deg): {np.array2string(rpy, precision=4, suppress_small=True)}")
    print("rotation:")
    print(np.array2string(placement.rotation, precision=6, suppress_small=True))
    return 0

def cmd_jacobian(args: argparse.Namespace) -> int:
    from ..kinematics.frames import fk_and_jacobian

    mech = _load(args)
    q = _configuration(mech, args.q, args.deg)
    frame = args.frame or mech.tool_frame
    _, _, jacobians = fk_and_jacobian(mech, q[None, :], frame, args.reference)
    jacobian = jacobians[0]
    singular_values = np.linalg.svd(jacobian, compute_uv=False)
    if args.json:
        _print_json({"frame": frame, "reference": args.reference, "joints": mech.joint_names,
                     "jacobian": jacobian.tolist(), "singular_values": singular_values.tolist()})
        return 0
    print(f"{mech.name}, Jacobian of frame {frame} ({args.reference}) at q = {np.round(q, 6).tolist()}")
    print("rows: linear velocity (m/s) then angular velocity (rad/s) per unit joint rate")
    print(_matrix_text(jacobian, ["vx", "vy", "vz", "wx", "wy", "wz"], mech.joint_names))
    print(f"singular values: {np.array2string(singular_values, precision=5)}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("fk", help="forward kinematics: position and rotation of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    p.set_defaults(func=cmd_fk)
    p = sub.add_parser("jacobian", help="6×n Jacobian of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    p.add_argument("--reference", choices=["world_aligned", "local", "world"], default="world_aligned",
                   help="world_aligned: world axes at the frame origin (default); local: frame axes; world: "
                        "Pinocchio's spatial convention")
    p.set_defaults(func=cmd_jacobian)

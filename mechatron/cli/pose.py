"""``mechatron fk`` (the pose of a frame) and ``mechatron jacobian`` (its 6×n Jacobian) at one configuration."""

from __future__ import annotations

import argparse

from .common import _configuration, _load, _pose_arguments, _robot_arguments, add_output_options, emit


def cmd_fk(args: argparse.Namespace) -> int:
    from ..kinematics.summary import frame_pose

    mech = _load(args)
    emit(frame_pose(mech, _configuration(mech, args.q, args.deg), args.frame), args)
    return 0


def cmd_jacobian(args: argparse.Namespace) -> int:
    from ..kinematics.summary import jacobian_summary

    mech = _load(args)
    emit(jacobian_summary(mech, _configuration(mech, args.q, args.deg), args.frame, args.reference), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("fk", help="forward kinematics: position and rotation of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    add_output_options(p)
    p.set_defaults(func=cmd_fk)
    p = sub.add_parser("jacobian", help="6×n Jacobian of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    p.add_argument("--reference", choices=["world_aligned", "local", "world"], default="world_aligned",
                   help="world_aligned: world axes at the frame origin (default); local: frame axes; world: "
                        "Pinocchio's spatial convention")
    add_output_options(p)
    p.set_defaults(func=cmd_jacobian)

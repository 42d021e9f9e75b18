"""``mechatron dynamics``: joint torques or actuator forces, speeds, power and energy along a motion."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .common import (
    _carrying,
    _floats,
    _load,
    _payload_arguments,
    _revolute_mask,
    _robot_arguments,
    add_output_options,
    emit,
)
from .values import FILE, Number, Numbers

#: The smallest sampling step (s), :data:`mechatron.dynamics.motion.MIN_STEP` (not imported: --help stays light).
_MIN_STEP = 1e-6

if TYPE_CHECKING:  # pragma: no cover
    from ..dynamics.motion import Trajectory
    from ..model import Mechanism


def _trajectory(mech: Mechanism, args: argparse.Namespace) -> Trajectory:
    """The motion of ``--trajectory FILE`` or ``--move Q0;Q1[;...]`` (one coordinate per joint, or per actuated
    coordinate of a closed loop)."""
    from ..dynamics.motion import cycle, read_trajectory

    if bool(args.trajectory) == bool(args.move):
        raise InputError("give either --trajectory FILE or --move SPEC")
    if args.trajectory:
        return read_trajectory(args.trajectory, mech)
    n = len(mech.actuated) if mech.closures else mech.nv
    angular = (np.array([mech.joint_kind(name) == "revolute" for name in mech.actuated], dtype=bool)
               if mech.closures else _revolute_mask(mech))
    points = []
    for k, part in enumerate(filter(None, (p.strip() for p in args.move.split(";")))):
        values = _floats(part, f"--move point {k + 1}")
        if values.shape != (n,):
            raise InputError(f"--move point {k + 1} needs {n} values ({', '.join(_move_names(mech))}), "
                             f"got {len(values)}")
        points.append(np.where(angular, np.radians(values), values) if args.deg else values)
    if len(points) < 2:
        raise InputError("--move needs at least two points separated by ';'")
    limits = {}
    for key in ("vmax", "amax", "jmax"):
        value = getattr(args, key)
        if value is not None and len(value) not in (1, n):
            raise InputError(f"--{key} needs 1 value or {n} (one per coordinate: {', '.join(_move_names(mech))}), "
                             f"got {len(value)}")
        limits[key] = None if value is None else float(value[0]) if len(value) == 1 else np.array(value)
    return cycle(None if mech.closures else mech, points, dwell=args.dwell, profile=args.profile, dt=args.dt,
                 **limits)


def _move_names(mech: Mechanism) -> list[str]:
    from ..dynamics.motion import coordinate_names

    return list(mech.actuated) if mech.closures else coordinate_names(mech)


def cmd_dynamics(args: argparse.Namespace) -> int:
    from ..drives.loads import trajectory_loads
    from ..dynamics.joint_reactions import joint_reactions

    mech = _carrying(_load(args), args)
    analysis = joint_reactions if args.reactions else trajectory_loads
    emit(analysis(mech, _trajectory(mech, args)), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("dynamics", help="joint torques or cylinder forces, speeds, power and energy along a motion")
    _robot_arguments(p)
    p.add_argument("--trajectory", metavar="FILE", type=FILE,
                   help="CSV with t and one column per joint coordinate (or actuated input)")
    p.add_argument("--move", metavar="Q0;Q1[;Q2...]",
                   help="points to move through, each one coordinate per joint, comma-separated (rad, m); "
                        "closed loops: actuated inputs")
    p.add_argument("--deg", action="store_true", help="revolute values of --move are in degrees (closed loops: its "
                                                      "revolute actuated inputs)")
    p.add_argument("--profile", default="trapezoidal", choices=["triangular", "trapezoidal", "scurve", "quintic"])
    p.add_argument("--vmax", type=Numbers(positive=True, unit="rad/s or m/s"), metavar="V[,V...]",
                   help="velocity limit(s), one value or one per axis (default: the model's or 1)")
    p.add_argument("--amax", type=Numbers(positive=True, unit="rad/s² or m/s²"), metavar="A[,A...]",
                   help="acceleration limit(s) (default 5)")
    p.add_argument("--jmax", type=Numbers(positive=True, unit="rad/s³ or m/s³"), metavar="J[,J...]",
                   help="jerk limit(s) for --profile scurve (default 50)")
    p.add_argument("--dwell", type=Number(minimum=0.0, unit="s"), default=0.0,
                   help="rest at every point after the first (s)")
    p.add_argument("--dt", type=Number(minimum=_MIN_STEP, unit="s"), default=0.005,
                   help=f"sampling step (s, >= {_MIN_STEP:g})")
    p.add_argument("--reactions", action="store_true",
                   help="the force (N) and moment (N·m) each joint transmits, world axes, about the joint's origin, "
                        "and a closed loop's pin forces, instead of the driving loads (--move 'Q;Q': one pose)")
    _payload_arguments(p)
    add_output_options(p)
    p.set_defaults(func=cmd_dynamics)

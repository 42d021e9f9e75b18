"""``mechatron dynamics``: joint torques or actuator forces, speeds, power and energy along a motion."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .common import _floats, _load, _revolute_mask, _robot_arguments, add_output_options, emit

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
    points = []
    for k, part in enumerate(filter(None, (p.strip() for p in args.move.split(";")))):
        values = _floats(part, f"--move point {k + 1}")
        if values.shape != (n,):
            raise InputError(f"--move point {k + 1} needs {n} values, got {len(values)}")
        points.append(np.where(_revolute_mask(mech), np.radians(values), values) if args.deg and not mech.closures
                      else values)
    if len(points) < 2:
        raise InputError("--move needs at least two points separated by ';'")
    limits = {key: _floats(getattr(args, key), f"--{key}") if getattr(args, key) else None
              for key in ("vmax", "amax", "jmax")}
    return cycle(None if mech.closures else mech, points, dwell=args.dwell, profile=args.profile, dt=args.dt,
                 **{k: (v if v is None or len(v) > 1 else float(v[0])) for k, v in limits.items()})


def cmd_dynamics(args: argparse.Namespace) -> int:
    from ..drives.loads import trajectory_loads
    from ..model.payload import with_payload

    mech = _load(args)
    if args.payload:
        if mech.closures:
            raise InputError("--payload is for serial arms (it is carried at the tool)")
        mech = with_payload(mech, args.payload)
    emit(trajectory_loads(mech, _trajectory(mech, args)), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("dynamics", help="joint torques or cylinder forces, speeds, power and energy along a motion")
    _robot_arguments(p)
    p.add_argument("--trajectory", metavar="FILE",
                   help="CSV with t and one column per joint coordinate (or actuated input)")
    p.add_argument("--move", metavar="Q0;Q1[;Q2...]",
                   help="points to move through, each one coordinate per joint, comma-separated (rad, m); "
                        "closed loops: actuated inputs")
    p.add_argument("--deg", action="store_true", help="revolute values of --move are in degrees")
    p.add_argument("--profile", default="trapezoidal", choices=["triangular", "trapezoidal", "scurve", "quintic"])
    p.add_argument("--vmax", help="velocity limit(s), one value or one per axis (default: the model's or 1)")
    p.add_argument("--amax", help="acceleration limit(s) (default 5)")
    p.add_argument("--jmax", help="jerk limit(s) for --profile scurve (default 50)")
    p.add_argument("--dwell", type=float, default=0.0, help="rest at every point after the first (s)")
    p.add_argument("--dt", type=float, default=0.005, help="sampling step (s)")
    p.add_argument("--payload", type=float, default=0.0, help="payload mass at the tool (kg)")
    add_output_options(p)
    p.set_defaults(func=cmd_dynamics)

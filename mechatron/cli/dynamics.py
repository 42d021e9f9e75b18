"""``mechatron dynamics``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .common import (
    _floats,
    _load,
    _print_json,
    _revolute_mask,
    _robot_arguments,
    _write_table,
)

if TYPE_CHECKING:  # pragma: no cover
    from ..model import Mechanism


def _trajectory(mech: Mechanism, args: argparse.Namespace):
    from ..dynamics.motion import cycle, read_trajectory

    if bool(args.trajectory) == bool(args.move):
        raise InputError("give either --trajectory FILE or --move SPEC")
    if args.trajectory:
        trajectory = read_trajectory(args.trajectory, mech)
        if mech.closures and trajectory.q.shape[1] != len(mech.actuated):
            raise InputError(f"{mech.name}: a trajectory file gives the actuated coordinates "
                             f"{', '.join(mech.actuated)}")
        return trajectory
    n = len(mech.actuated) if mech.closures else mech.nq
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
    trajectory = _trajectory(mech, args)
    result = trajectory_loads(mech, trajectory)
    written = []
    if args.csv:
        written.append(_write_table(result.table, args.csv))
    if args.plot:
        written.append(str(_plot_loads(result, args.plot, mech)))
    summary = result.summary
    if args.json:
        _print_json({"mechanism": mech.name, "duration": float(trajectory.t[-1] - trajectory.t[0]),
                     "samples": len(trajectory.t), "coordinates": summary.to_dict(orient="records"),
                     "files": written})
        return 0
    kind = "actuator" if mech.closures else "joint"
    print(f"{mech.name}: {kind} loads over {trajectory.t[-1] - trajectory.t[0]:.3f} s ({len(trajectory.t)} samples)")
    print(summary.to_string(index=False, float_format=lambda x: f"{x:.5g}"))
    print("units: N·m and rad/s for revolute joints, N and m/s for prismatic ones and cylinders; power W, work J")
    for path in written:
        print(f"wrote {path}")
    return 0

def _plot_loads(result, path, mech: Mechanism):
    from matplotlib.figure import Figure

    from ..io.output import save_figure as _save

    table = result.table
    fig = Figure(figsize=(10, 7), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    for name in result.names:
        axes[0].plot(table["t"], table[f"qd_{name}"], label=name)
        axes[1].plot(table["t"], table[f"tau_{name}"], label=name)
        axes[2].plot(table["t"], table[f"power_{name}"], label=name)
    for ax, label in zip(axes, ("speed (rad/s, m/s)", "force (N·m, N)", "power (W)")):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, ncol=min(6, len(result.names)))
    axes[0].set_title(f"{mech.name}: loads along the motion")
    axes[2].set_xlabel("t (s)")
    from pathlib import Path

    _save(fig, Path(path))
    return path


def register(sub) -> None:
    p = sub.add_parser("dynamics", help="joint torques or cylinder forces, speeds, power and energy along a motion")
    _robot_arguments(p)
    p.add_argument("--trajectory", metavar="FILE", help="CSV with t and one column per joint (or actuated input)")
    p.add_argument("--move", metavar="Q0;Q1[;Q2...]",
                   help="points to move through, each comma-separated (rad, m); closed loops: actuated inputs")
    p.add_argument("--deg", action="store_true", help="revolute values of --move are in degrees")
    p.add_argument("--profile", default="trapezoidal", choices=["triangular", "trapezoidal", "scurve", "quintic"])
    p.add_argument("--vmax", help="velocity limit(s), one value or one per axis (default: the model's or 1)")
    p.add_argument("--amax", help="acceleration limit(s) (default 5)")
    p.add_argument("--jmax", help="jerk limit(s) for --profile scurve (default 50)")
    p.add_argument("--dwell", type=float, default=0.0, help="rest at every point after the first (s)")
    p.add_argument("--dt", type=float, default=0.005, help="sampling step (s)")
    p.add_argument("--payload", type=float, default=0.0, help="payload mass at the tool (kg)")
    p.add_argument("--csv", metavar="FILE", help="write every sample")
    p.add_argument("--plot", metavar="FILE", help="write speeds, forces and power against time (PNG)")
    p.set_defaults(func=cmd_dynamics)

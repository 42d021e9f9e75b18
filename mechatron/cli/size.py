"""``mechatron size``."""

from __future__ import annotations

import argparse

from ..errors import InputError
from .common import (
    _load,
    _robot_arguments,
)


def cmd_size(args: argparse.Namespace) -> int:
    """Motor, gearbox (screw, cylinder) and ratio for every joint doing a task; exit 1 when a joint has no
    feasible drive."""
    from ..drives.catalogs import read_catalog
    from ..drives.report import text_report, to_json, write_charts, write_csv
    from ..drives.sizing import size_mechanism
    from ..dynamics.task import default_task, read_task
    from ..report.progress import progress_bar

    mech = _load(args)
    task = read_task(args.task, mech) if args.task else default_task(mech)
    catalogs = {kind: read_catalog(path, kind) if path else None for kind, path in
                (("motors", args.motors), ("gearboxes", args.gearboxes), ("linear", args.linear),
                 ("cylinders", args.cylinders))}
    if not args.pressure_mpa > 0:
        raise InputError(f"--pressure-mpa must be > 0, got {args.pressure_mpa:g}")
    result = size_mechanism(task.mechanism, task.trajectory, **catalogs, objective=args.objective,
                            inertia_ratio_max=args.inertia_ratio, loads=task.loads, task=task.name,
                            direct=not args.no_direct, pressure=args.pressure_mpa * 1e6,
                            chain_efficiency=args.chain_efficiency,
                            progress=None if args.json else progress_bar(f"{mech.name}: sizing"))
    written = [write_csv(result, args.csv)] if args.csv else []
    if args.plots:
        written += write_charts(result, args.plots)
    if args.json:
        print(to_json(result))
    else:
        print(text_report(result))
        for path in written:
            print(f"wrote {path}")
    return 0 if result.feasible else 1


def register(sub) -> None:
    p = sub.add_parser("size", help="choose motor, gearbox and ratio (or screw, or cylinder) for every joint "
                                    "doing a task; exit 1 if a joint has no feasible drive")
    _robot_arguments(p)
    p.add_argument("--task", metavar="FILE", help="task TOML (waypoints, payload, loads) or trajectory CSV "
                                                  "(default: the robot's own task, else a generic out-and-back)")
    p.add_argument("--motors", metavar="CSV", help="servo motor catalog (default: catalogs/servo_motors.csv)")
    p.add_argument("--gearboxes", metavar="CSV", help="gearbox catalog (default: catalogs/gearboxes.csv)")
    p.add_argument("--linear", metavar="CSV", help="linear drives (ball screws, racks) for prismatic joints "
                                                   "(default: catalogs/linear_drives.csv)")
    p.add_argument("--cylinders", metavar="CSV", help="hydraulic cylinder catalog for closed-loop mechanisms")
    p.add_argument("--objective", default="mass", choices=["mass", "cost", "margin", "time"],
                   help="rank feasible drives by mass, cost, margin (largest smallest margin) or time (fastest "
                        "task, then mass); default mass")
    p.add_argument("--inertia-ratio", type=float, default=10.0, help="largest load/motor inertia ratio (default 10)")
    p.add_argument("--no-direct", action="store_true", help="do not consider direct drive (gearless) motors")
    p.add_argument("--pressure-mpa", type=float, default=32.0, help="hydraulic system pressure (default 32 MPa)")
    p.add_argument("--chain-efficiency", type=float, default=1.0,
                   help="efficiency of the rest of the chain (couplings, bearings, belt), multiplies every "
                        "converter's (default 1)")
    p.add_argument("--csv", metavar="FILE", help="write every check of every joint")
    p.add_argument("--plots", metavar="DIR", help="write a speed–torque chart per chosen motor (PNG)")
    p.set_defaults(func=cmd_size)

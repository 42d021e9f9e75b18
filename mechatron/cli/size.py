"""``mechatron size``: the drive of every joint for a task (:func:`mechatron.size`)."""

from __future__ import annotations

import argparse

from .common import _carrying, _load, _payload_arguments, _robot_arguments, add_output_options, emit, output_option
from .values import FILE, Number


def cmd_size(args: argparse.Namespace) -> int:
    """Motor, gearbox (screw, cylinder) and ratio for every joint doing a task; exit 1 when a joint has no
    feasible drive."""
    from ..drives.checks import SCREW_LIFE, DriveLimits
    from ..drives.sizing import size
    from ..drives.thermal import ZERO_CELSIUS
    from ..report.progress import progress_bar

    limits = DriveLimits(args.stop_torque, args.stop_current,
                         SCREW_LIFE if args.screw_life_h is None else args.screw_life_h * 3600.0, args.voltage,
                         args.ambient + ZERO_CELSIUS)
    mech = _carrying(_load(args), args)
    result = size(mech, args.task, motors=args.motors, gearboxes=args.gearboxes, linear=args.linear,
                  cylinders=args.cylinders, objective=args.objective, inertia_ratio_max=args.inertia_ratio,
                  direct=not args.no_direct, pressure=args.pressure_mpa * 1e6,
                  chain_efficiency=args.chain_efficiency, single_pass=args.single_pass,
                  max_iterations=args.max_iterations, limits=limits,
                  progress=None if args.json else progress_bar(f"{mech.name}: sizing"))
    emit(result, args, result.save_plots(args.plots) if args.plots else (), mechanism=mech, task=args.task)
    return 0 if result.feasible else 1


def register(sub) -> None:
    p = sub.add_parser("size", help="choose motor, gearbox and ratio (or screw, or cylinder) for every joint "
                                    "doing a task; exit 1 if a joint has no feasible drive")
    _robot_arguments(p)
    p.add_argument("--task", metavar="FILE", type=FILE,
                   help="task TOML (waypoints, payload, loads) or trajectory CSV (default: the robot's own task, "
                        "else a generic out-and-back)")
    _payload_arguments(p)
    p.add_argument("--motors", metavar="CSV", type=FILE,
                   help="servo motor catalog (default: catalogs/servo_motors.csv)")
    p.add_argument("--gearboxes", metavar="CSV", type=FILE, help="gearbox catalog (default: catalogs/gearboxes.csv)")
    p.add_argument("--linear", metavar="CSV", type=FILE,
                   help="linear drives (ball screws, racks) for prismatic joints (default: "
                        "catalogs/linear_drives.csv)")
    p.add_argument("--cylinders", metavar="CSV", type=FILE,
                   help="hydraulic cylinder catalog for closed-loop mechanisms (default: "
                        "catalogs/hydraulic_cylinders.csv)")
    p.add_argument("--objective", default="mass", choices=["mass", "cost", "margin", "time"],
                   help="rank feasible drives by mass, cost, margin (largest smallest margin) or time (fastest "
                        "task, then mass); default mass")
    p.add_argument("--inertia-ratio", type=Number(positive=True), metavar="R", default=10.0,
                   help="largest load/motor inertia ratio (default 10)")
    p.add_argument("--no-direct", action="store_true", help="do not consider direct drive (gearless) motors")
    p.add_argument("--pressure-mpa", type=Number(positive=True, maximum=1e4, unit="MPa"), metavar="P", default=32.0,
                   help="hydraulic system pressure (default 32 MPa)")
    p.add_argument("--chain-efficiency", type=Number(minimum=0.01, maximum=1.0), metavar="ETA", default=1.0,
                   help="efficiency of the rest of the chain (couplings, bearings, belt), multiplies every "
                        "converter's (default 1)")
    p.add_argument("--single-pass", action="store_true",
                   help="size each joint once with weightless drives (default: the chosen drives' masses load the "
                        "mechanism and the sizing repeats until the choice no longer changes)")
    p.add_argument("--max-iterations", type=Number(integer=True, minimum=2, maximum=1000), default=10, metavar="N",
                   help="the most sizing passes before reporting that the choice did not settle (default 10)")
    stop = p.add_mutually_exclusive_group()
    stop.add_argument("--stop-torque", type=Number(positive=True, unit="N·m"), metavar="NM",
                      help="the motor torque (N·m) the drives are limited to in an emergency stop; the gearbox's "
                           "emergency check takes it instead of the motor's peak torque")
    stop.add_argument("--stop-current", type=Number(positive=True, unit="A"), metavar="A",
                      help="the same as a current limit (A): the stop torque of each motor is k_t times it")
    p.add_argument("--voltage", type=Number(positive=True, unit="V"), metavar="V",
                   help="supply voltage of the voltage-limit check (default: each motor's catalog voltage)")
    p.add_argument("--ambient", type=Number(minimum=-50.0, maximum=100.0, unit="°C"), metavar="DEGC", default=40.0,
                   help="ambient temperature in °C of the motors' winding temperature check (the motors with thermal "
                        "data; the winding may rise by its limit temperature minus it), -50 … 100 (default 40)")
    p.add_argument("--screw-life-h", type=Number(positive=True, unit="h"), metavar="H",
                   help="required nominal (L10) life of ball screws running the task over and over, in hours "
                        "(default 20000)")
    add_output_options(p, report=True)
    output_option(p, "--plots", kind="folder", metavar="DIR",
                  help="write each joint's chart (speed–torque for a motor, force–speed for a cylinder) as "
                       "DIR/<robot>_<joint>.png and its data as DIR/<robot>_<joint>.csv (the charts of an earlier "
                       "run for joints no longer there are removed)")
    p.set_defaults(func=cmd_size)

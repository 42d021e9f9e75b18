"""``mechatron size``: the drive of every joint for a task (:func:`mechatron.size`)."""

from __future__ import annotations

import argparse

from ..drives.derating import ALTITUDE_RANGE
from ..drives.options import (
    AMBIENT_DEGC,
    CHAIN_EFFICIENCY,
    INERTIA_RATIO_MAX,
    MAX_ITERATIONS,
    MAX_PASSES,
    MIN_EFFICIENCY,
    MIN_PASSES,
    MPA,
    OBJECTIVE,
    OBJECTIVES,
    PRESSURE,
    PRESSURE_MAX,
    SizingOptions,
)
from .common import _carrying, _load, _payload_arguments, _robot_arguments, add_output_options, emit, output_option
from .values import FILE, Number


def cmd_size(args: argparse.Namespace) -> int:
    """Motor, gearbox (screw, cylinder) and ratio for every joint doing a task; exit 1 when a joint has no
    feasible drive."""
    from ..drives.sizing import size
    from ..report.progress import progress_bar

    options = sizing_options(args)
    mech = _carrying(_load(args), args)
    result = size(mech, args.task, motors=args.motors, gearboxes=args.gearboxes, linear=args.linear,
                  cylinders=args.cylinders, options=options, resistors=args.resistors,
                  regenerative_supply=args.regenerative_supply, resistor_min=args.resistor_min_ohm,
                  drives=args.drives,
                  progress=None if args.json else progress_bar(f"{mech.name}: sizing"))
    emit(result, args, result.save_plots(args.plots) if args.plots else (), mechanism=mech, task=args.task)
    return 0 if result.feasible else 1


def sizing_options(args: argparse.Namespace) -> SizingOptions:
    """The :class:`~mechatron.drives.options.SizingOptions` of the parsed options of ``mechatron size``."""
    return SizingOptions.in_user_units(
        objective=args.objective, inertia_ratio_max=args.inertia_ratio, pressure_MPa=args.pressure_mpa,
        chain_efficiency=args.chain_efficiency, direct=not args.no_direct, single_pass=args.single_pass,
        max_iterations=args.max_iterations, stop_torque=args.stop_torque, stop_current=args.stop_current,
        voltage=args.voltage, screw_life_h=args.screw_life_h, ambient_degC=args.ambient, altitude=args.altitude,
        brake_factor=args.brake_factor, brake_stops_per_h=args.brake_stops_per_h)


def _brake_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the holding brakes and of the DC bus's braking resistor (mechatron.drives.brakes, .resistors)."""
    from ..drives.brakes import BRAKE_FACTOR, STOPS_PER_HOUR

    p.add_argument("--brake-factor", type=Number(minimum=1.0, maximum=100.0), metavar="F", default=None,
                   help="a holding brake's static torque must be F times the gravity torque at the motor side "
                        f"(motor catalogs with brake columns; default {BRAKE_FACTOR:g}, our default)")
    p.add_argument("--brake-stops-per-h", type=Number(positive=True, maximum=1e6), metavar="N", default=None,
                   help=f"emergency stops per hour of the brake's energy-per-hour check (default {STOPS_PER_HOUR:g})")
    bus = p.add_mutually_exclusive_group()
    bus.add_argument("--resistors", metavar="CSV", type=FILE,
                     help="braking resistor catalog: choose the DC bus's resistor "
                          "(e.g. catalogs/braking_resistors.csv)")
    bus.add_argument("--regenerative-supply", action="store_true",
                     help="the DC bus feeds braking energy back to the mains: no resistor, the supply's rating")
    p.add_argument("--resistor-min-ohm", type=Number(minimum=0.0, unit="Ω"), metavar="OHM", default=0.0,
                   help="the drive's smallest braking resistance (Ω; default 0)")


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
    p.add_argument("--objective", default=OBJECTIVE, choices=OBJECTIVES,
                   help="rank feasible drives by mass, cost, margin (largest smallest margin) or time (fastest "
                        f"task, then mass); default {OBJECTIVE}")
    p.add_argument("--inertia-ratio", type=Number(positive=True), metavar="R", default=INERTIA_RATIO_MAX,
                   help=f"largest load/motor inertia ratio (default {INERTIA_RATIO_MAX:g})")
    p.add_argument("--no-direct", action="store_true", help="do not consider direct drive (gearless) motors")
    p.add_argument("--pressure-mpa", type=Number(positive=True, maximum=PRESSURE_MAX / MPA, unit="MPa"), metavar="P",
                   default=PRESSURE / MPA, help=f"hydraulic system pressure (default {PRESSURE / MPA:g} MPa)")
    p.add_argument("--chain-efficiency", type=Number(minimum=MIN_EFFICIENCY, maximum=1.0), metavar="ETA",
                   default=CHAIN_EFFICIENCY, help="efficiency of the rest of the chain (couplings, bearings, belt), "
                                                  f"multiplies every converter's (default {CHAIN_EFFICIENCY:g})")
    p.add_argument("--single-pass", action="store_true",
                   help="size each joint once with weightless drives (default: the chosen drives' masses load the "
                        "mechanism and the sizing repeats until the choice no longer changes)")
    p.add_argument("--max-iterations", type=Number(integer=True, minimum=MIN_PASSES, maximum=MAX_PASSES),
                   default=MAX_ITERATIONS, metavar="N",
                   help=f"the most sizing passes before reporting that the choice did not settle (default "
                        f"{MAX_ITERATIONS})")
    stop = p.add_mutually_exclusive_group()
    stop.add_argument("--stop-torque", type=Number(positive=True, unit="N·m"), metavar="NM",
                      help="the motor torque (N·m) the drives are limited to in an emergency stop; the gearbox's "
                           "emergency check takes it instead of the motor's peak torque")
    stop.add_argument("--stop-current", type=Number(positive=True, unit="A"), metavar="A",
                      help="the same as a current limit (A): the stop torque of each motor is k_t times it")
    p.add_argument("--voltage", type=Number(positive=True, unit="V"), metavar="V",
                   help="supply voltage of the voltage-limit check (default: each motor's catalog voltage)")
    p.add_argument("--drives", metavar="CSV", type=FILE,
                   help="servo drive catalog (kind drives, e.g. catalogs/servo_drives.csv): each motor paired with "
                        "the lightest (cheapest) drive that passes; default: no drive")
    p.add_argument("--altitude", type=Number(minimum=ALTITUDE_RANGE[0], maximum=ALTITUDE_RANGE[1], unit="m"),
                   metavar="M", default=0.0,
                   help="site altitude in m (-500 … 6000): the motors' S1 torque derated 10 %% per 1000 m above "
                        "1000 m (default 0)")
    p.add_argument("--ambient", type=Number(minimum=-50.0, maximum=100.0, unit="°C"), metavar="DEGC",
                   default=AMBIENT_DEGC,
                   help="ambient temperature in °C of the motors' winding temperature check (the motors with thermal "
                        "data; the winding may rise by its limit temperature minus it), -50 … 100 (default 40)")
    p.add_argument("--screw-life-h", type=Number(positive=True, unit="h"), metavar="H",
                   help="required nominal (L10) life of ball screws running the task over and over, in hours "
                        "(default 20000)")
    _brake_arguments(p)
    add_output_options(p, report=True)
    output_option(p, "--plots", kind="folder", metavar="DIR",
                  help="write each joint's chart (speed–torque for a motor, force–speed for a cylinder) as "
                       "DIR/<robot>_<joint>.png and its data as DIR/<robot>_<joint>.csv (the charts of an earlier "
                       "run for joints no longer there are removed)")
    p.set_defaults(func=cmd_size)

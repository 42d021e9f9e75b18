"""``mechatron calibrate``: geometric parameters and joint offsets identified from measured tool poses."""

from __future__ import annotations

import argparse

from .common import _load, _robot_arguments, add_output_options, emit, output_option
from .values import FILE, NAME


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Identify the parameters of ``--parameters`` from ``--measurements`` (Levenberg–Marquardt on the exact
    Jacobian; :func:`~mechatron.accuracy.calibration.calibrate`), print the result, write ``-o`` if asked."""
    from ..accuracy.calibrated_file import check_calibrated_path
    from ..accuracy.calibration import calibrate
    from ..accuracy.measurements import read_measurements

    mech = _load(args)
    if args.output:
        check_calibrated_path(mech, args.output)
    names = [n.strip() for n in args.parameters.split(",") if n.strip()]
    measurements = read_measurements(args.measurements, mech)
    result = calibrate(mech, measurements, names, args.frame, allow_unidentifiable=args.allow_unidentifiable)
    written = result.write(args.output) if args.output else []
    emit(result, args, written, mechanism=mech)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("calibrate", help="identify geometric parameters and joint offsets from measured tool poses "
                                         "(Levenberg–Marquardt), with identifiability and standard errors")
    _robot_arguments(p)
    p.add_argument("--measurements", required=True, metavar="FILE", type=FILE,
                   help="CSV: the coordinates as read (one per joint), the measured x, y, z (or x_mm…), optionally "
                        "roll, pitch, yaw (or _deg) and sigma (sigma_mm), sigma_rot (sigma_rot_deg)")
    p.add_argument("--parameters", required=True, metavar="NAME,...",
                   help="what to identify: geometric parameters (a2,d3,alpha2,…; see 'mechatron show') and joint "
                        "offsets (a joint's name or q1…)")
    p.add_argument("--frame", type=NAME, help="the measured frame (default: the tool)")
    p.add_argument("--allow-unidentifiable", action="store_true",
                   help="identify the minimum-norm change where the measurements cannot tell parameters apart "
                        "(default: name them and stop)")
    output_option(p, "-o", "--output", kind=None,
                  help="write the calibrated mechanism: a robot file (.toml) of a DH arm, a mechanism file (.toml) "
                       "of a linkage, or a URDF (.urdf)")
    add_output_options(p, report=True)
    p.set_defaults(func=cmd_calibrate)

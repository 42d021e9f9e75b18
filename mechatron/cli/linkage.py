"""``mechatron linkage``: a closed-loop mechanism over the whole stroke of its inputs, and its velocity and
acceleration plans at one position."""

from __future__ import annotations

import argparse
import sys

from ..errors import InputError
from .common import _load, _robot_arguments, add_output_options, emit, output_option, parse_assignments
from .values import Number


def cmd_linkage(args: argparse.Namespace) -> int:
    from ..kinematics.loops import assemble, joint_acceleration, joint_velocity
    from ..kinematics.sweeps import sweep
    from ..kinematics.vector_plans import plans
    from ..report.progress import progress_bar

    mech = _load(args)
    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops; 'mechatron linkage' analyses closed-loop mechanisms "
                         "(see 'mechatron list')")
    result = sweep(mech, samples=args.samples, links=mech.link_names,
                   progress=progress_bar(f"{mech.name}: {args.samples} positions") if args.samples >= 2000 else None)
    written = []
    if args.plans:
        q = assemble(mech, parse_assignments(args.at, "--at"))
        v = joint_velocity(mech, q, {name: mech.input_rates.get(name, 1.0) for name in mech.actuated})
        written.append(plans(mech, q, v, joint_acceleration(mech, q, v)).save_plot(args.plans))
    emit(result, args, written, mechanism=mech)
    if len(result.failures):
        first = result.failures.iloc[0]
        print(f"mechatron: warning: {len(result.failures)} of {len(result.table) + len(result.failures)} positions "
              f"could not be analysed; first: {first['reason']}", file=sys.stderr)
    return 0


def register(sub) -> None:
    p = sub.add_parser("linkage", help="analyse a closed-loop mechanism over the whole stroke of its inputs")
    _robot_arguments(p)
    p.add_argument("--samples", type=Number(integer=True, minimum=2), default=200, metavar="N",
                   help="number of positions (default 200)")
    add_output_options(p, report=True)
    output_option(p, "--plans", kind="figure",
                  help="write the velocity and acceleration plans at one position (.png, .pdf or .svg)")
    p.add_argument("--at", action="append", metavar="INPUT=VALUE,...",
                   help="the position of --plans (actuated coordinates, SI units; default: the reference position)")
    p.set_defaults(func=cmd_linkage)

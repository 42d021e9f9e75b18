"""``mechatron linkage``: a closed-loop mechanism over the whole stroke of its inputs, and its velocity and
acceleration plans at one position; with ``--workspace POINT`` the point's positions over the grid of two inputs
(:func:`mechatron.kinematics.workspaces.workspace`)."""

from __future__ import annotations

import argparse
import sys

from ..errors import InputError
from .common import _load, _robot_arguments, add_output_options, emit, output_option, parse_assignments
from .values import Number


def cmd_linkage(args: argparse.Namespace) -> int:
    from ..kinematics.sweeps import sweep
    from ..report.progress import progress_bar

    mech = _load(args)
    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops; 'mechatron linkage' analyses closed-loop mechanisms "
                         "(see 'mechatron list')")
    if args.workspace is not None and args.interference is not None:
        raise InputError("--interference checks the sweep's poses; it does not go with --workspace")
    if args.workspace is not None:
        return _workspace(mech, args)
    if args.grid is not None or args.workspace_inputs is not None:
        raise InputError("--grid and --workspace-inputs go with --workspace POINT")
    result = sweep(mech, samples=args.samples, links=mech.link_names,
                   progress=progress_bar(f"{mech.name}: {args.samples} positions") if args.samples >= 2000 else None)
    emit(result, args, _plans(mech, args), mechanism=mech)
    if len(result.failures):
        first = result.failures.iloc[0]
        print(f"mechatron: warning: {len(result.failures)} of {len(result.table) + len(result.failures)} positions "
              f"could not be analysed; first: {first['reason']}", file=sys.stderr)
    if args.interference is not None:
        _interference(mech, result, args.interference)
    return 0


def _interference(mech, result, width: float) -> None:
    """``--interference [WIDTH]``: a warning per pair of bodies and cylinders whose outlines (WIDTH wide, m) meet
    along the sweep (:func:`~mechatron.kinematics.interference.interference`), else a note of the pairs checked."""
    from ..kinematics.interference import interference

    check = interference(mech, result, width=width)
    for line in check.warnings():
        print(f"mechatron: warning: {line}", file=sys.stderr)
    if not check.interfering():
        print(f"mechatron: interference: no pair of bodies and cylinders meets along the sweep ({len(check.pairs)} "
              f"checked, outlines {width:g} m wide)", file=sys.stderr)


def _plans(mech, args: argparse.Namespace) -> list:
    """``--plans FILE``: the velocity and acceleration plans at ``--at`` written (the list of files written)."""
    from ..kinematics.loops import assemble, joint_acceleration, joint_velocity
    from ..kinematics.vector_plans import plans

    if not args.plans:
        return []
    q = assemble(mech, parse_assignments(args.at, "--at"))
    v = joint_velocity(mech, q, {name: mech.input_rates.get(name, 1.0) for name in mech.actuated})
    return [plans(mech, q, v, joint_acceleration(mech, q, v)).save_plot(args.plans)]


def _workspace(mech, args: argparse.Namespace) -> int:
    """``--workspace POINT``: :func:`~mechatron.kinematics.workspaces.workspace`, its errors naming the option."""
    from ..kinematics.workspaces import GRID, workspace
    from ..report.progress import progress_bar

    grid = GRID if args.grid is None else args.grid
    inputs = None if args.workspace_inputs is None else [n.strip() for n in args.workspace_inputs.split(",")]
    if inputs is None and len(mech.actuated) > 2:
        raise InputError(f"--workspace: {mech.name} has {len(mech.actuated)} inputs ({', '.join(mech.actuated)}): "
                         "name the two to sweep with --workspace-inputs IN1,IN2")
    try:
        result = workspace(mech, args.workspace, grid=grid, inputs=inputs,
                           progress=progress_bar(f"{mech.name}: {grid} × {grid} positions")
                           if grid * grid >= 2000 else None)
    except InputError as exc:
        option = {"point": "--workspace", "inputs": "--workspace-inputs"}.get(exc.field or "")
        if option is None:
            raise
        raise InputError(f"{option}: {exc.message}") from None
    emit(result, args, _plans(mech, args), mechanism=mech)
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
    p.add_argument("--interference", nargs="?", const=0.0, type=Number(unit="m", minimum=0.0), metavar="WIDTH",
                   help="warn of pairs of bodies and cylinders whose outlines (WIDTH wide, m; default 0: the drawn "
                        "lines) meet along the sweep; pairs joined by a pin or closure are not checked")
    p.add_argument("--workspace", metavar="POINT",
                   help="instead of the sweep: the positions of POINT over the grid of two inputs, each over its "
                        "range (the others held at their drawn values)")
    p.add_argument("--grid", type=Number(integer=True, minimum=2), metavar="N",
                   help="with --workspace: N values of each input, N × N positions (default 41)")
    p.add_argument("--workspace-inputs", metavar="IN1,IN2",
                   help="with --workspace: the two inputs to sweep (default: the mechanism's two inputs)")
    p.set_defaults(func=cmd_linkage)

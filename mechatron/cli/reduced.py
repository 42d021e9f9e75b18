"""``mechatron reduced``: the one-mass model of a mechanism with one degree of freedom."""

from __future__ import annotations

import argparse

from .common import _load, _robot_arguments, add_output_options, emit
from .values import Number


def cmd_reduced(args: argparse.Namespace) -> int:
    from ..dynamics.reduced import reduced_table

    emit(reduced_table(_load(args), args.input, samples=args.samples), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("reduced", help="reduced inertia (or mass) and moment (or force) of a 1-DOF mechanism")
    _robot_arguments(p)
    p.add_argument("--input", help="the input coordinate (default: the actuated one)")
    p.add_argument("--samples", type=Number(integer=True, minimum=2), default=73, metavar="N",
                   help="input values over its range (default 73)")
    add_output_options(p)
    p.set_defaults(func=cmd_reduced)

"""``mechatron export-urdf``."""

from __future__ import annotations

import argparse
import sys

from .common import (
    _load,
    _robot_arguments,
)


def cmd_export_urdf(args: argparse.Namespace) -> int:
    from ..model.urdf import export_urdf

    mech = _load(args)
    if mech.closures:
        print(f"mechatron: warning: URDF has no closed loops; {len(mech.closures)} closure(s) of {mech.name} are "
              "not written (only its spanning tree)", file=sys.stderr)
    written = export_urdf(mech, args.output)
    for path in written:
        print(f"wrote {path}")
    if len(written) > 1:
        print("(the .srdf holds the drives' rotor inertia and gear ratio: pinocchio.loadRotorParameters reads it)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("export-urdf", help="write a robot as URDF (plus SRDF rotor data)")
    _robot_arguments(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="URDF file to write")
    p.set_defaults(func=cmd_export_urdf)

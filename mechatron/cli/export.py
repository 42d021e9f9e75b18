"""``mechatron export-urdf``."""

from __future__ import annotations

import argparse
import sys

from .common import _load, _robot_arguments, output_option


def cmd_export_urdf(args: argparse.Namespace) -> int:
    from ..io.output import written_so_far
    from ..model.urdf import export_urdf

    mech = _load(args)
    if mech.closures:
        print(f"mechatron: warning: URDF has no closed loops; {len(mech.closures)} closure(s) of {mech.name} are "
              "not written (only its spanning tree)", file=sys.stderr)
    written = export_urdf(mech, args.output)
    written_so_far()
    for path in written:
        print(f"wrote {path}")
    if len(written) > 1:
        print("(the .srdf holds the drives' rotor inertia and gear ratio: pinocchio.loadRotorParameters reads it)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("export-urdf", help="write a robot as URDF (plus SRDF rotor data)")
    _robot_arguments(p)
    output_option(p, "-o", "--output", kind="urdf", help="URDF file to write (.urdf or .xml; the SRDF beside it)")
    p.set_defaults(func=cmd_export_urdf)

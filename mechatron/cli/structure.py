"""``mechatron structure``."""

from __future__ import annotations

import argparse

from .common import _load, _robot_arguments, add_output_options, emit


def cmd_structure(args: argparse.Namespace) -> int:
    """Structural analysis [Egorov, chapter 3] of a mechanism or of a structural description file."""
    from ..structure.analysis import analyse_structure
    from ..structure.description import structure_file

    subject = args.robot if structure_file(args.robot) else _load(args)
    emit(analyse_structure(subject), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("structure", help="structural analysis: pairs by class, loops, mobility by every formula "
                                         "and from the model, redundancy, Assur groups")
    _robot_arguments(p)
    add_output_options(p)
    p.set_defaults(func=cmd_structure)

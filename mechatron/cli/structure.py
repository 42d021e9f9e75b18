"""``mechatron structure``."""

from __future__ import annotations

import argparse

from .common import (
    _load,
    _print_json,
    _robot_arguments,
)


def cmd_structure(args: argparse.Namespace) -> int:
    """Structural analysis (chapter 3) of a mechanism or of a structural description file."""
    from ..structure.analysis import analyse, text_report
    from ..structure.description import read_structure, structure_file

    path = structure_file(args.robot)
    subject = read_structure(path) if path else _load(args)
    report = analyse(subject)
    if args.json:
        _print_json(report.as_dict())
    else:
        print(text_report(report))
    return 0


def register(sub) -> None:
    p = sub.add_parser("structure", help="structural analysis: pairs by class, loops, mobility by every formula "
                                         "and from the model, redundancy, Assur groups")
    _robot_arguments(p)
    p.set_defaults(func=cmd_structure)

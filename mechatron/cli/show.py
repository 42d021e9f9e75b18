"""``mechatron show``: a mechanism's DH table, joints, links, drives, parameters, closures and frames."""

from __future__ import annotations

import argparse

from .common import _load, _robot_arguments, add_output_options, emit


def cmd_show(args: argparse.Namespace) -> int:
    from ..kinematics.summary import mechanism_summary

    emit(mechanism_summary(_load(args)), args)
    return 0


def register(sub) -> None:
    p = sub.add_parser("show", help="DH table, joints, masses, drives, mobility and parameters of a robot")
    _robot_arguments(p)
    add_output_options(p)
    p.set_defaults(func=cmd_show)

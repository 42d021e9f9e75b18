"""``mechatron demo``."""

from __future__ import annotations

import argparse


def cmd_demo(args: argparse.Namespace) -> int:
    from .demo import run

    run()
    return 0


def register(sub) -> None:
    p = sub.add_parser("demo", help="a short tour: load a robot and print its kinematics")
    p.set_defaults(func=cmd_demo)

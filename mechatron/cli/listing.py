"""``mechatron list``."""

from __future__ import annotations

import argparse

from .common import (
    _print_json,
)


def cmd_list(args: argparse.Namespace) -> int:
    from ..errors import MechatronError
    from ..library import available_robots, builtin_robot_files, installed_example_robots, load

    names = available_robots()
    if args.json:
        _print_json(names)
        return 0
    builtin = builtin_robot_files()
    examples = installed_example_robots()
    print(f"{'name':<18} {'W':>3}  description (W: degrees of mobility)")
    for name in names:
        try:
            mech = load(name)
            print(f"{name:<18} {mech.mobility():>3}  {mech.description}")
        except MechatronError as exc:
            print(f"{name:<18} {'?':>3}  (cannot load: {exc})")
    print(f"\n{len(builtin)} robot files in {next(iter(builtin.values())).parent if builtin else 'robots/'}; "
          f"{len(examples)} arms from example-robot-data")
    from ..structure.description import shipped_structures

    print(f"structural descriptions of the cases of [Egorov, chapter 3] (mechatron structure NAME): "
          f"{', '.join(shipped_structures())}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("list", help="list the robots and mechanisms mechatron can load")
    p.add_argument("--json", action="store_true", help="print a JSON list of names")
    p.set_defaults(func=cmd_list)

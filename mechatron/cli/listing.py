"""``mechatron list``: every name ``load`` accepts, where it comes from (``./robots``, ``MECHATRON_PATH``,
``shipped``, ``example-robot-data``) and, in the text, its mobility and description."""

from __future__ import annotations

import argparse

from .common import (
    _print_json,
)


def cmd_list(args: argparse.Namespace) -> int:
    from ..errors import MechatronError
    from ..library import load, robot_origins, search_path

    origins = robot_origins()
    if args.json:
        _print_json([{"name": name, "origin": origin, "path": str(path) if path is not None else None}
                     for name, (origin, path) in origins.items()])
        return 0
    print(f"{'name':<18} {'W':>3}  {'from':<18} description (W: degrees of mobility)")
    for name, (origin, _) in origins.items():
        try:
            mech = load(name)
            print(f"{name:<18} {mech.mobility():>3}  {origin:<18} {mech.description}")
        except MechatronError as exc:
            print(f"{name:<18} {'?':>3}  {origin:<18} (cannot load: {exc})")
    print("\nfiles by name (NAME.toml), the first folder that has it wins:")
    for folder, origin in search_path():
        state = f"{len(list(folder.glob('*.toml')))} .toml file(s)" if folder.is_dir() else "not there"
        print(f"  {origin:<15} {folder}  ({state})")
    from ..structure.description import shipped_structures

    print(f"structural descriptions of the cases of [Egorov, chapter 3] (mechatron structure NAME): "
          f"{', '.join(shipped_structures())}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("list", help="list the robots and mechanisms mechatron can load, and where each comes from")
    p.add_argument("--json", action="store_true",
                   help="print a JSON list of {name, origin, path}: where each name comes from")
    p.set_defaults(func=cmd_list)

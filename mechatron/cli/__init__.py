"""The ``mechatron`` command line: one module per command, each parses its options, calls the API and prints.

Every command has ``--help``; ``--json`` prints machine-readable output; an error prints one line to stderr and exits
with status 2 (set ``MECHATRON_DEBUG=1`` to see the traceback of an unexpected error).
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
import warnings
from collections.abc import Sequence

from .. import __version__
from ..errors import MechatronError, MechatronWarning
from ..io.budget import command_line
from . import (
    demo_command,
    dynamics,
    excavator,
    export,
    linkage,
    listing,
    optimize,
    pose,
    reduced,
    show,
    size,
    structure,
    study,
    tolerance,
)
from .common import _join_negative_values, _Parser, outputs

COMMANDS = (listing, show, pose, export, linkage, excavator, dynamics, reduced, size, tolerance, structure,
            study, optimize, demo_command)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mechatron", description="Sizing and analysis of mechatronic modules and mechanisms "
                                                   "(Pinocchio inside). SI units throughout.")
    parser.add_argument("--version", action="version", version=f"mechatron {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    for command in COMMANDS:
        command.register(sub)
    return parser


class _Warnings:
    """The :class:`~mechatron.errors.MechatronWarning` of a command, each shown as one line ``mechatron: warning: …``
    on stderr when the command has run; a command that fails shows its error line alone. Other warnings are shown
    as Python shows them, at once."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def show(self, message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
        if issubclass(category, MechatronWarning):
            self.lines.append(f"mechatron: warning: {message}")
        else:
            sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))

    def flush(self) -> None:
        for line in self.lines:
            print(line, file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 a design that fails its checks, 2 error)."""
    parser = build_parser()
    args = parser.parse_args(_join_negative_values(sys.argv[1:] if argv is None else argv))
    shown = _Warnings()
    try:
        with outputs(parser, args), command_line(), warnings.catch_warnings():
            warnings.simplefilter("always", MechatronWarning)
            warnings.showwarning = shown.show
            status = int(args.func(args) or 0)
        shown.flush()
        return status
    except MechatronError as exc:
        print(f"mechatron: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. piped into head
        return 0
    except Exception as exc:  # noqa: BLE001 - the command line never shows a traceback unless asked to
        if os.environ.get("MECHATRON_DEBUG"):
            traceback.print_exc()
        print(f"mechatron: internal error: {type(exc).__name__}: {exc} (set MECHATRON_DEBUG=1 for details)",
              file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

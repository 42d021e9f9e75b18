"""The ``mechatron`` command line: one module per command, each parses its options, calls the API and prints.

Every command has ``--help``; ``--json`` prints machine-readable output; an error prints one line to stderr and exits
with status 2 (set ``MECHATRON_DEBUG=1`` to see the traceback of an unexpected error).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import warnings
from collections.abc import Sequence

from .. import __version__
from ..errors import MechatronError, MechatronWarning
from ..io.budget import command_line
from .common import _join_negative_values, _Parser, outputs

#: Every command → the module of this package that registers it (its ``register(sub)`` adds the sub-parsers of its
#: commands), in the order ``mechatron --help`` lists them. A command's module is imported only when its parser is
#: built: a command run by name builds its own parser alone (see :func:`build_parser`).
COMMANDS = {
    "list": "listing", "show": "show", "fk": "pose", "jacobian": "pose", "export-urdf": "export",
    "linkage": "linkage", "excavator": "excavator", "dynamics": "dynamics", "reduced": "reduced", "size": "size",
    "tolerance": "tolerance", "calibrate": "calibrate", "structure": "structure", "study": "study",
    "optimize": "optimize", "demo": "demo_command",
}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of the command line: every command's sub-parser, or, for ``command`` (a key of :data:`COMMANDS`),
    only the sub-parsers of its module, which parse that command's arguments exactly as the whole parser does
    (the start-up of a command does not build the others' parsers nor import their modules)."""
    parser = _Parser(prog="mechatron", description="Sizing and analysis of mechatronic modules and mechanisms "
                                                   "(Pinocchio inside). SI units throughout.")
    parser.add_argument("--version", action="version", version=f"mechatron {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    modules = [COMMANDS[command]] if command in COMMANDS else COMMANDS.values()
    for module in dict.fromkeys(modules):
        importlib.import_module(f"{__name__}.{module}").register(sub)
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
    arguments = _join_negative_values(sys.argv[1:] if argv is None else argv)
    parser = build_parser(arguments[0] if arguments else None)  # a command's own parser, when it comes first
    args = parser.parse_args(arguments)
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
            import traceback

            traceback.print_exc()
        print(f"mechatron: internal error: {type(exc).__name__}: {exc} (set MECHATRON_DEBUG=1 for details)",
              file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

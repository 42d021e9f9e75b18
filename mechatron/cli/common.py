"""Parsing helpers shared by the commands: values, configurations, outputs, the common options."""

from __future__ import annotations

import argparse
import contextlib
import json
import re
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from ..errors import InputError
from .values import NAME, Number

if TYPE_CHECKING:  # pragma: no cover
    from ..model import Mechanism
    from ..report.result import Result

_NEGATIVE_VALUE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def _get_values(self, action: argparse.Action, arg_strings: list[str]) -> Any:
        # argparse drops a value "--" (``--dt=--``) and stores [] unchecked: refuse it as the value it is
        if action.option_strings and action.nargs is None and arg_strings == ["--"]:
            self.error(f"argument {'/'.join(action.option_strings)}: expected a value, got '--'")
        return super()._get_values(action, arg_strings)


def _floats(text: str, what: str, **bounds: Any) -> np.ndarray:
    """Comma-separated numbers of an option (``what``: its name), each finite and within ``bounds`` (of
    :func:`~mechatron.cli.values.number_list`)."""
    from .values import number_list

    return np.array(number_list(text, what, **bounds))


def parse_assignments(items: Sequence[str] | None, option: str = "--set") -> dict[str, float]:
    """``["a2=0.5,d3=0.1", ...]`` → {"a2": 0.5, "d3": 0.1} (values in SI units) of ``option``; every value finite."""
    from ..io.values import LARGEST, number

    out: dict[str, float] = {}
    for item in items or ():
        for part in filter(None, (p.strip() for p in item.split(","))):
            name, sep, value = part.partition("=")
            if not sep or not name.strip():
                raise InputError(f"{option} expects NAME=VALUE[,NAME=VALUE...], got {part!r}")
            out[name.strip()] = number(f"{option} {name.strip()}", value.strip(), minimum=-LARGEST)
    return out


def _load(args: argparse.Namespace) -> Mechanism:
    from ..library import load

    return load(args.robot, **parse_assignments(args.set))


def _configuration(mech: Mechanism, text: str, degrees: bool) -> np.ndarray:
    """The configuration q (nq,) of ``--q``: one coordinate per joint (rad, m; degrees with ``--deg``), a
    continuous joint's angle turned into its (cos, sin) by :meth:`~mechatron.model.Mechanism.configuration`."""
    values = _floats(text, "--q")
    if values.shape != (mech.nv,):
        raise InputError(f"--q needs {mech.nv} values for {mech.name} ({', '.join(mech.joint_names)}), "
                         f"got {len(values)}")
    if degrees:
        values = np.where(_revolute_mask(mech), np.radians(values), values)
    q = mech.configuration(values)
    mech.warn_limits(q)
    return q


def _revolute_mask(mech: Mechanism) -> np.ndarray:
    """Which joint coordinates (velocity indices) are angles."""
    return mech.angular_coordinates()


def _print_json(obj: Any) -> None:
    print(json.dumps(obj, indent=2, allow_nan=False))


def _robot_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("robot", help="robot name (see 'mechatron list') or a .toml/.urdf file")
    parser.add_argument("--set", action="append", metavar="NAME=VALUE,...",
                        help="override geometric parameters (SI units: m, rad), e.g. --set a2=0.45,d4=0.43")
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON")


def _payload_arguments(parser: argparse.ArgumentParser) -> None:
    """``--payload MASS`` (kg) and ``--payload-at POINT`` (a frame, or a point of a closed loop)."""
    parser.add_argument("--payload", type=Number(minimum=0.0, unit="kg"), default=0.0, metavar="MASS",
                        help="a payload: a point mass (kg) carried at --payload-at, besides any payload of a task")
    parser.add_argument("--payload-at", type=NAME, metavar="POINT",
                        help="the frame or point that carries the payload: any frame of a serial arm, any point of "
                             "a closed loop, which it joins to the body carrying it (default: the tool frame)")


def _carrying(mech: Mechanism, args: argparse.Namespace) -> Mechanism:
    """``mech`` carrying the payload of ``--payload MASS`` at ``--payload-at POINT`` (default its tool frame;
    :func:`~mechatron.model.payload.with_payload`), ``mech`` itself without one."""
    from ..model.payload import with_payload

    if args.payload_at is not None and not args.payload:
        raise InputError("--payload-at names where the payload sits: give its mass with --payload MASS")
    if not args.payload:
        return mech
    try:
        mech.frame_id(args.payload_at or mech.tool_frame)
    except InputError as exc:
        raise InputError(f"--payload-at: {exc.message}") from None
    return with_payload(mech, args.payload, args.payload_at)


def _pose_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--q", required=True, metavar="Q1,Q2,...",
                        help="joint coordinates, one per joint, comma-separated (rad and m; see --deg)")
    parser.add_argument("--deg", action="store_true", help="revolute joint values of --q are in degrees")
    parser.add_argument("--frame", type=NAME, help="frame name (default: tool)")


def _join_negative_values(argv: Sequence[str]) -> list[str]:
    """Let ``--q -0.5,1`` mean ``--q=-0.5,1`` (argparse would take -0.5,1 for an option)."""
    out: list[str] = []
    items = list(argv)
    i = 0
    while i < len(items):
        token = items[i]
        if (token.startswith("--") and "=" not in token and i + 1 < len(items)
                and _NEGATIVE_VALUE.match(items[i + 1])):
            out.append(f"{token}={items[i + 1]}")
            i += 2
            continue
        out.append(token)
        i += 1
    return out


# ------------------------------------------------------------------------------------------- result outputs

class OutputPath:
    """The ``type=`` of an option naming an output (``kind``: a key of :data:`mechatron.io.output.FILE_SUFFIXES`,
    ``"figure"``, ``"folder"`` or None): it marks the option, whose path :func:`outputs` checks before any work.
    The value stays the string given."""

    def __init__(self, kind: str | None = None) -> None:
        self.kind = kind
        self.__name__ = "file name"

    def __call__(self, text: str) -> str:
        if not text:
            raise argparse.ArgumentTypeError("must be a file name, got ''")
        return text


def output_option(parser: argparse.ArgumentParser, *flags: str, kind: str | None, help: str,
                  metavar: str = "FILE") -> None:
    """Add an option naming an output file (``kind``: see :class:`OutputPath`), checked before any work."""
    parser.add_argument(*flags, metavar=metavar, type=OutputPath(kind), help=help)


def add_output_options(parser: argparse.ArgumentParser, *, csv: bool = True, plot: bool = True,
                       report: bool = False) -> None:
    """The options every analysis command has: ``--json`` (and ``--csv FILE``, ``--plot FILE``, ``--report
    FILE.html``), which are exactly the result's ``as_dict``, ``to_frame``, ``plot`` and ``write_html``."""
    if not any(action.dest == "json" for action in parser._actions):
        parser.add_argument("--json", action="store_true", help="print the result as JSON")
    if csv:
        output_option(parser, "--csv", kind="table", help="write the result's table (CSV)")
    if plot:
        output_option(parser, "--plot", kind="figure", help="write the result's chart (.png, .pdf or .svg)")
    if report:
        output_option(parser, "--report", kind="html", metavar="FILE.html",
                      help="write the report as one self-contained HTML file (inputs, method, every check, "
                           "charts, the mechanism at its critical pose) that works offline")
        parser.set_defaults(report_parser=parser)


def _output_actions(parser: argparse.ArgumentParser | None) -> list[argparse.Action]:
    return [a for a in parser._actions if isinstance(a.type, OutputPath)] if parser is not None else []


def _command_parser(parser: argparse.ArgumentParser, args: argparse.Namespace) -> argparse.ArgumentParser | None:
    """The parser of the command ``args`` were parsed for (``parser``'s sub-parser), if any."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices.get(getattr(args, "command", None))
    return None


@contextlib.contextmanager
def outputs(parser: argparse.ArgumentParser, args: argparse.Namespace) -> Iterator[None]:
    """Run a command's work inside one output transaction (:func:`mechatron.io.output.transaction`): every file it
    writes is staged and all of them are renamed together when it succeeds, none when it fails. Before any work,
    each output option's path is checked (:func:`~mechatron.io.output.check_output`: not a directory, its folder
    exists and is writable, a suffix of its kind; ``--plots``: :func:`~mechatron.io.output.check_directory`), and
    two output options naming the same file is an error. No command writes over a file it reads: each output file
    is told to the transaction (:meth:`~mechatron.io.output.Transaction.writes`), which refuses any read of it
    (:func:`~mechatron.io.output.check_input`), wherever the file was named — on the command line (checked here,
    before any work) or in a file the command reads (a spec's designs, catalog, task or mechanism)."""
    from ..io.output import check_directory, check_input, check_output, transaction

    command = _command_parser(parser, args) or parser
    labels: dict[Path, str] = {}
    files: dict[str, str] = {}
    for action in _output_actions(command):
        path = getattr(args, action.dest, None)
        if not path:
            continue
        label, key = "/".join(action.option_strings), Path(path).resolve()
        if action.type.kind == "folder":
            check_directory(path, where=f"{label} {path}")
        else:
            check_output(path, action.type.kind, where=f"{label} {path}")
            files[path] = label
        if key in labels:
            raise InputError(f"{labels[key]} and {label} both name {path}; give each output its own file")
        labels[key] = label
    with transaction(labels) as current:
        for path, label in files.items():
            current.writes(path, label)
        for path in _named_inputs(command, args):
            check_input(path)
        yield


def _named_inputs(command: argparse.ArgumentParser, args: argparse.Namespace) -> list[str]:
    """The input files named on the command line: the robot argument, a command's spec, and the options whose
    metavar is FILE or CSV."""
    return [getattr(args, a.dest) for a in command._actions if not isinstance(a.type, OutputPath)
            and isinstance(getattr(args, a.dest, None), str)
            and (a.dest in ("robot", "spec") or str(a.metavar).startswith(("FILE", "CSV")))]


def emit(result: Result, args: argparse.Namespace, written: Sequence[str | Path] = (), **context: Any) -> None:
    """Write ``--csv`` (``result.to_frame()``), ``--plot`` (``result.plot()``) and ``--report``
    (``result.write_html()`` with the options given, the input files among them, and ``context``: the mechanism
    and what else the result's report uses) if asked, then print ``--json`` (``result.as_dict()``) or the text
    report (``str(result)``). Every file (``written`` too, in the command's transaction) is renamed into place
    together before anything is printed, so a failed write prints nothing. The files written are listed after the
    report, or on stderr with ``--json`` (so that stdout stays one JSON document)."""
    from ..io.output import transaction, written_so_far

    files = [str(path) for path in written]
    with transaction():
        if getattr(args, "csv", None):
            files.append(str(result.write_csv(args.csv)))
        if getattr(args, "plot", None):
            files.append(str(result.save_plot(args.plot)))
        if getattr(args, "report", None):
            options, named = _options(args)
            outputs = {Path(path).resolve() for path in [*files, args.report]}
            inputs = [path for path in named if Path(path).is_file() and Path(path).resolve() not in outputs]
            files.append(str(result.write_html(args.report, inputs=options, files=inputs, **context)))
        text = result.to_json() if getattr(args, "json", False) else str(result)
        written_so_far()
    print(text)
    stream = sys.stderr if getattr(args, "json", False) else sys.stdout
    for path in files:
        print(f"wrote {path}", file=stream)


def _options(args: argparse.Namespace) -> tuple[dict[str, Any], list[str]]:
    """The value of every option of the command (``--name``, or the positional's name) as given or defaulted, and
    the files named: the values of the robot argument and of the options whose metavar is FILE or CSV."""
    parser = getattr(args, "report_parser", None)
    actions = [a for a in parser._actions if not isinstance(a, argparse._HelpAction)] if parser else []
    options = {max(a.option_strings, key=len) if a.option_strings else a.dest: getattr(args, a.dest, None)
               for a in actions}
    named = [getattr(args, a.dest) for a in actions if isinstance(getattr(args, a.dest, None), str)
             and not isinstance(a.type, OutputPath)
             and (a.dest == "robot" or str(a.metavar).startswith(("FILE", "CSV")))]
    return options, named

"""``mechatron excavator``."""

from __future__ import annotations

import argparse

from ..errors import InputError
from .common import _floats, add_output_options, emit, output_option
from .values import FILE, Number


def cmd_excavator(args: argparse.Namespace) -> int:
    """The front-shovel design report [Shovel]: parse, call :func:`~mechatron.machines.excavator.excavator_report`,
    emit. With ``-o FILE``: write the design's mechanism file (:func:`~mechatron.machines.excavator.write_shovel`),
    and the report only if one of its outputs (--json, --csv, --plot) is asked for. With ``--lift-chart``: the
    rated lift capacity [ISO 10567], the rated tool forces [ISO 6015, 5.2.1–5.2.2] and the digging capability
    (mechatron's estimate) of the design on the machine of its ``[machine]`` table
    (:func:`~mechatron.machines.capacity.capacity_report`)."""
    try:
        return _excavator(args)
    except InputError as exc:  # a field of the design file found wanting after it was read: name the file
        if args.design and exc.field and exc.file is None:
            raise InputError(exc.message, file=args.design, field=exc.field) from None
        raise


def _excavator(args: argparse.Namespace) -> int:
    from ..machines.excavator import excavator_report, read_design, write_shovel
    from ..machines.shovel_machine import read_machine
    from ..report.progress import progress_bar

    design = read_design(args.design) if args.design else None
    machine = read_machine(args.design) if args.design else None  # the [machine] table, checked in any case
    if args.lift_chart and args.tooth_force is not None:
        raise InputError("--tooth-force is a load for the design report's holding loads, not for --lift-chart")
    tooth = tuple(_floats(args.tooth_force, "--tooth-force", unit="N")) if args.tooth_force is not None else (0.0, 0.0)
    if len(tooth) != 2:
        raise InputError(f"--tooth-force needs two finite numbers FX,FY (N), got {len(tooth)} values")
    written = [write_shovel(design, args.output)] if args.output else []
    if args.lift_chart:
        from ..machines.capacity import capacity_report

        emit(capacity_report(design, machine, args.samples), args, written)
        return 0
    if written and not (args.json or args.csv or args.plot):
        from ..io.output import written_so_far

        written_so_far()
        print(f"wrote {written[0]}")
        return 0
    progress = progress_bar("working range", force=False) if not args.json else None
    emit(excavator_report(design, args.samples, tooth, progress=progress), args, written)
    return 0


def register(sub) -> None:
    p = sub.add_parser("excavator", help="front-shovel working device: design table, special positions, envelope")
    p.add_argument("--design", metavar="FILE", type=FILE, help="TOML file overriding fields of the design (see docs)")
    p.add_argument("--samples", type=Number(integer=True, minimum=2), default=31, metavar="N",
                   help="grid points per cylinder stroke (default 31; with --lift-chart the digging positions)")
    p.add_argument("--lift-chart", action="store_true",
                   help="rated lift capacity [ISO 10567], rated tool forces [ISO 6015, 5.2] and the digging "
                        "capability (mechatron's estimate) on the machine of the design file's [machine] table "
                        "instead of the design report")
    p.add_argument("--tooth-force", metavar="FX,FY", help="force on the tooth tip for the holding loads (N)")
    output_option(p, "-o", "--output", kind="toml",
                  help="write the design's mechanism file (.toml; every command reads it) instead of the report")
    add_output_options(p)
    p.set_defaults(func=cmd_excavator)

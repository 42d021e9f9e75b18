"""``mechatron optimize``: optimal design from a design file — any mechanism, variables, one or two objectives and
requirements on the study analyses' outputs (docs/design_file.md) — or from a named problem's spec
(docs/optimize_file.md: the bucket, the front shovel, a DH arm's positioning error). Exit 1 when a requirement is not
met at the optimum."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import add_output_options, emit, output_option
from .values import COUNT, FILE


def cmd_optimize(args: argparse.Namespace) -> int:
    """Solve the file and emit the optimum (or the Pareto front); exit 1 when a requirement is not met at the
    optimum (the Pinocchio model's), as ``size`` does without a feasible drive."""
    from ..errors import InputError
    from ..optimal.reader import parse_problem, read_problem

    if args.out:  # no input is one of the files -o replaces or removes (the spec, its mechanism, …)
        from ..io.output import will_write
        from ..optimal.write import output_files

        for path in output_files(args.out):
            will_write(path, "-o")
    parsed = parse_problem(args.spec)  # parsed once: the form decides what -o may write
    if args.out and not parsed.is_design:
        raise InputError("-o writes the designs of a design file (docs/design_file.md); this is a named problem's "
                         "spec", field="-o")
    from ..optimal.solve import optimize
    from ..report.progress import progress_bar

    problem = read_problem(parsed)
    searched = problem.exact_model is None  # the study analyses: designs evaluated, with a progress line
    bar = None if args.json or not searched else progress_bar(f"{Path(args.spec).name} evaluations")
    result = optimize(problem, workers=args.workers, scheduler=args.scheduler, progress=bar)
    written: list[Path] = []
    refused: list[InputError] = []
    if args.out and searched:
        from ..optimal.write import write_optimum

        written, refused = write_optimum(problem, result, args.out)
    emit(result, args, written)  # the results printed and saved before any design that cannot be written is told
    if refused:
        more = f" ({len(refused) - 1} more designs not written likewise)" if len(refused) > 1 else ""
        raise InputError(refused[0].message + more, file=refused[0].file, row=refused[0].row,
                         field=refused[0].field)
    return 0 if result.feasible else 1


def register(sub) -> None:
    p = sub.add_parser("optimize", help="optimal design of a mechanism's named parameters (any mechanism file; "
                                        "exact derivatives with ipopt, a global search, or a Pareto front of two "
                                        "objectives); exit 1 if a requirement is not met at the optimum")
    p.add_argument("spec", type=FILE, metavar="SPEC.toml",
                   help="the design file (docs/design_file.md) or a named problem's spec (docs/optimize_file.md)")
    p.add_argument("--workers", type=COUNT, default=1, metavar="N",
                   help="1: the designs in this process (default); N > 1: an embedded Dask LocalCluster of N "
                        "worker processes (design files)")
    p.add_argument("--scheduler", metavar="ADDR", help="a running Dask scheduler, e.g. tcp://HOST:8786 (design files)")
    output_option(p, "-o", "--out", kind="folder", metavar="DIR",
                  help="write the results in DIR (optimum.json, designs.csv: every design evaluated), then the "
                       "optimum (two objectives: every design of the front) as mechanism files design-NNN.toml (a "
                       "mechanism file's own format, drawn at the pose the search evaluated) or .urdf; a design "
                       "that would not read back is not written and is an error naming its file (exit 2)")
    add_output_options(p, report=True)
    p.set_defaults(func=cmd_optimize)

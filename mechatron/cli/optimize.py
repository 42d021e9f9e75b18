"""``mechatron optimize``: optimal design from a design file — any mechanism, variables, one or two objectives and
requirements on the study analyses' outputs (docs/design_file.md) — or from a named problem's spec
(docs/optimize_file.md: the bucket, the front shovel, a DH arm's positioning error). Exit 1 when a requirement is not
met at the optimum."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .common import add_output_options, emit, output_option
from .values import COUNT, FILE


def cmd_optimize(args: argparse.Namespace) -> int:
    """Solve the file and emit the optimum (or the Pareto front); exit 1 when a requirement is not met at the
    optimum (the Pinocchio model's), as ``size`` does without a feasible drive."""
    from ..errors import InputError
    from ..io.toml import read_toml
    from ..studies.design_spec import is_design_file

    general = is_design_file(read_toml(args.spec))
    if args.out and not general:
        raise InputError("-o writes the designs of a design file (docs/design_file.md); this is a named problem's "
                         "spec", field="-o")
    if general:
        from ..report.progress import progress_bar
        from ..studies.design import optimize_design, write_designs
        from ..studies.design_spec import read_design

        bar = None if args.json else progress_bar(f"{Path(args.spec).name} evaluations")
        spec = read_design(args.spec)
        result = optimize_design(spec, workers=args.workers, scheduler=args.scheduler, progress=bar)
        if args.out and result.best is not None:
            import pandas as pd

            front = result.front if result.front is not None else pd.DataFrame([result.best])
            for path in write_designs(spec, front, args.out):
                print(f"design: {path}", file=sys.stderr)
    else:
        from ..studies.optimize import optimize, read_spec

        result = optimize(read_spec(args.spec))
    emit(result, args)
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
                  help="write the optimum (two objectives: every design of the front) as mechanism files "
                       "design-NNN.toml (a mechanism file's own format) or .urdf, in DIR")
    add_output_options(p)
    p.set_defaults(func=cmd_optimize)

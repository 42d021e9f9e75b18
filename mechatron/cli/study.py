"""``mechatron study``: a design study from a study file (docs/study_file.md), serially or on Dask."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import add_output_options, emit, output_option
from .values import COUNT


def cmd_study(args: argparse.Namespace) -> int:
    from ..report.progress import progress_bar
    from ..studies.runner import run_study
    from ..studies.spec import read_study

    spec = read_study(args.spec)
    out = Path(args.out) if args.out else Path(f"{Path(args.spec).stem}_study")
    where = "on " + args.scheduler if args.scheduler else f"on {args.workers} workers" if args.workers > 1 else ""
    bar = None if args.json else progress_bar(f"{Path(args.spec).name} {where}".strip())
    result = run_study(spec, out, workers=args.workers, scheduler=args.scheduler, chunk_size=args.chunk,
                       progress=bar, restart=args.restart)
    emit(result, args)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("study", help="a design study: designs of experiments over a mechanism's parameters times "
                                     "analyses, serially or on Dask, with its Pareto front and Sobol indices")
    p.add_argument("spec", metavar="SPEC.toml", help="the study file (docs/study_file.md)")
    output_option(p, "--out", kind="folder", metavar="DIR",
                  help="the study's folder: parts, designs.parquet and designs.csv (default: ./SPEC_study); a "
                       "study stopped there resumes")
    p.add_argument("--workers", type=COUNT, default=1, metavar="N",
                   help="1: serially (default); N > 1: an embedded Dask LocalCluster of N worker processes")
    p.add_argument("--scheduler", metavar="ADDR", help="a running Dask scheduler, e.g. tcp://HOST:8786")
    p.add_argument("--chunk", type=COUNT, metavar="N", help="designs per task and per part file (default: n/32, "
                                                           "1 to 64)")
    p.add_argument("--restart", action="store_true",
                   help="discard the study in --out (its rows, parts and tables) and start again, e.g. after a file "
                        "it reads has changed")
    add_output_options(p, report=True)
    p.set_defaults(func=cmd_study)

"""``mechatron tolerance``: the positioning error of a point from the tolerances of parameters and coordinates."""

from __future__ import annotations

import argparse

from ..errors import InputError
from .common import _load, _robot_arguments, add_output_options, emit, output_option
from .values import COUNT, FILE, NAME, Number


def cmd_tolerance(args: argparse.Namespace) -> int:
    """Positioning error of a point from the tolerances of parameters and coordinates [Egorov, chapter 8]."""
    from ..accuracy.sources import read_poses, read_tolerances, reference_pose, workspace_grid
    from ..accuracy.study import analyse_tolerances
    from ..report.progress import progress_bar

    mech = _load(args)
    methods = {"all": ("worst", "rss", "mc")}.get(args.method, (args.method,))
    sources = read_tolerances(args.tolerances, mech, "error" if args.method == "given" else "tolerance")
    if args.poses and args.grid:
        raise InputError("give --poses or --grid, not both")
    if args.poses:
        poses, labels = read_poses(args.poses, mech)
    elif args.grid:
        poses = workspace_grid(mech, args.grid, args.seed)
        labels = [str(i + 1) for i in range(len(poses))]
    else:
        poses, labels = reference_pose(mech), ["reference"]
    limit = args.limit_mm * 1e-3 if args.limit_mm is not None else None
    long_run = "mc" in methods and len(poses) * args.samples >= 200_000 and not args.json
    result = analyse_tolerances(mech, sources, poses, labels, frame=args.frame, methods=methods, k=args.k,
                       samples=args.samples, seed=args.seed, limit=limit,
                       progress=progress_bar(f"{mech.name}: Monte Carlo") if long_run else None)
    written = []
    if args.contributions:
        from ..io.output import write_table

        written.append(write_table(result.contributions, args.contributions))
    if args.plots:
        written += result.save_charts(args.plots)
    emit(result, args, written, mechanism=mech)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("tolerance", help="positioning error of a point from parameter and joint tolerances: "
                                         "worst case, RSS, Monte Carlo, or a given set of errors")
    _robot_arguments(p)
    p.add_argument("--tolerances", required=True, metavar="FILE", type=FILE,
                   help="CSV: parameter, tolerance (or tolerance_mm, …, or grade), distribution, bias, error")
    p.add_argument("--poses", metavar="FILE", type=FILE,
                   help="CSV: one coordinate per joint per row (closed loops: actuated inputs)")
    p.add_argument("--grid", type=COUNT, metavar="N", help="poses over the workspace: N per coordinate (≤ 2 "
                                                         "coordinates) or N random ones")
    p.add_argument("--method", default="all", choices=["worst", "rss", "mc", "all", "given"],
                   help="all = worst, rss and mc (default); given: the Δr of the error column [Egorov, 8.4]")
    p.add_argument("--samples", type=Number(integer=True, minimum=2), default=10000, metavar="N",
                   help="Monte Carlo samples per pose (default 10000)")
    p.add_argument("--seed", type=Number(integer=True, minimum=0), default=0, help="random seed (default 0)")
    p.add_argument("--k", type=Number(minimum=0.1, maximum=100.0), default=3.0,
                   help="coverage factor: σ = t/k for normal errors (default 3)")
    p.add_argument("--limit-mm", type=Number(positive=True, unit="mm"),
                   help="largest acceptable |Δr| (mm) for the Monte Carlo yield")
    p.add_argument("--frame", type=NAME, help="the frame whose position is studied (default: the tool)")
    add_output_options(p, report=True)
    output_option(p, "--contributions", kind="table", help="write the contributions table (CSV)")
    output_option(p, "--plots", kind="folder", metavar="DIR",
                  help="write the error map, Monte Carlo and contribution charts as DIR/<robot>_<chart>.png (the "
                       "charts of an earlier run that this one does not draw are removed)")
    p.set_defaults(func=cmd_tolerance)

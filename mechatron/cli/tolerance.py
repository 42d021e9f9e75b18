"""``mechatron tolerance``: the positioning error of a point from the tolerances of parameters and coordinates."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import InputError
from .common import _load, _robot_arguments, add_output_options, emit, output_option
from .values import COUNT, FILE, NAME, Number

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ..model.mechanism import Mechanism


def cmd_tolerance(args: argparse.Namespace) -> int:
    """Positioning error of a point from the tolerances of parameters and coordinates [Egorov, chapter 8]."""
    from ..accuracy.sources import read_tolerances
    from ..accuracy.study import analyse_tolerances
    from ..report.progress import progress_bar

    mech = _load(args)
    if args.allocate:
        return _allocate(args, mech)
    for option, value in (("--processes", args.processes), ("--allocated", args.allocated)):
        if value:
            raise InputError(f"{option} goes with --allocate")
    args.method = args.method or "all"
    methods = {"all": ("worst", "rss", "mc")}.get(args.method, (args.method,))
    sources = read_tolerances(args.tolerances, mech, "error" if args.method == "given" else "tolerance")
    poses, labels = _poses(args, mech)
    limit = args.limit_mm * 1e-3 if args.limit_mm is not None else None
    long_run = "mc" in methods and len(poses) * args.samples >= 200_000 and not args.json
    if args.capability and ("mc" not in methods or limit is None):
        raise InputError("--capability needs the Monte Carlo (--method mc or all) and a limit (--limit-mm)")
    result = analyse_tolerances(mech, sources, poses, labels, frame=args.frame, methods=methods, k=args.k,
                                samples=args.samples, seed=args.seed, limit=limit, target_error=args.target_error,
                                target=args.target,
                                progress=progress_bar(f"{mech.name}: Monte Carlo") if long_run else None)
    written = []
    from ..io.output import write_table

    if args.contributions:
        written.append(write_table(result.contributions, args.contributions))
    if args.capability:
        written.append(write_table(result.capability, args.capability))
    if args.plots:
        written += result.save_charts(args.plots)
    emit(result, args, written, mechanism=mech)
    return 0


def _poses(args: argparse.Namespace, mech: Mechanism) -> tuple[np.ndarray, list[str]]:
    """The poses of ``--poses``, ``--grid`` or ``--task`` (one of them), else the reference pose."""
    from ..accuracy.sources import read_poses, reference_pose, task_poses, workspace_grid

    given = [option for option, value in (("--poses", args.poses), ("--grid", args.grid), ("--task", args.task))
             if value]
    if len(given) > 1:
        raise InputError(f"give one of --poses, --grid and --task, not {' and '.join(given)}")
    if args.poses:
        return read_poses(args.poses, mech)
    if args.grid:
        poses = workspace_grid(mech, args.grid, args.seed)
        return poses, [str(i + 1) for i in range(len(poses))]
    if args.task:
        return task_poses(args.task, mech)
    return reference_pose(mech), ["reference"]


def _allocate(args: argparse.Namespace, mech: Mechanism) -> int:
    """``--allocate``: the least-cost tolerances for |Δr| ≤ --limit-mm at every pose, verified by a Monte Carlo."""
    from ..accuracy.allocation import ALLOCATION_METHODS, allocate_tolerances
    from ..accuracy.costs import read_cost_models
    from ..report.progress import progress_bar

    if args.limit_mm is None:
        raise InputError("--allocate needs --limit-mm L: the largest |Δr| (mm) allowed at every pose")
    method = args.method or "rss"
    if method not in ALLOCATION_METHODS:
        raise InputError(f"--allocate bounds --method rss or worst, not {method} (every allocation is verified by "
                         "a Monte Carlo of the full nonlinear model)")
    for option, value in (("--contributions", args.contributions), ("--plots", args.plots),
                          ("--capability", args.capability), ("--target-error", getattr(args, "target_error", None))):
        if value:
            raise InputError(f"{option} goes with a tolerance study, not with --allocate (its outputs: --csv, "
                             "--plot, --json, --allocated)")
    costed = read_cost_models(args.tolerances, mech, args.processes)
    poses, labels = _poses(args, mech)
    long_run = len(poses) * args.samples >= 200_000 and not args.json
    result = allocate_tolerances(mech, costed, poses, labels, args.limit_mm * 1e-3, method=method, k=args.k,
                                 frame=args.frame, samples=args.samples, seed=args.seed,
                                 progress=progress_bar(f"{mech.name}: Monte Carlo") if long_run else None)
    written = [result.write_tolerances(args.allocated)] if args.allocated else []
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
    p.add_argument("--task", metavar="FILE", type=FILE,
                   help="poses along a task file's motion (TOML or trajectory CSV): its samples, at most 100")
    p.add_argument("--method", choices=["worst", "rss", "mc", "all", "given"],
                   help="all = worst, rss and mc (default; with --allocate: rss); given: the Δr of the error column "
                        "[Egorov, 8.4]")
    p.add_argument("--samples", type=Number(integer=True, minimum=2), default=10000, metavar="N",
                   help="Monte Carlo samples per pose (default 10000)")
    p.add_argument("--seed", type=Number(integer=True, minimum=0), default=0, help="random seed (default 0)")
    p.add_argument("--k", type=Number(minimum=0.1, maximum=100.0), default=3.0,
                   help="coverage factor: σ = t/k for normal errors (default 3)")
    p.add_argument("--limit-mm", type=Number(positive=True, unit="mm"),
                   help="largest acceptable |Δr| (mm) for the Monte Carlo yield")
    p.add_argument("--target-error", type=Number(positive=True, maximum=0.5), metavar="E",
                   help="Monte Carlo: draw samples per pose until the relative standard error of --target is at "
                        "most E (0 < E ≤ 0.5); --samples is then the most per pose")
    p.add_argument("--target", choices=["sigma", "ppm"], default="sigma",
                   help="what --target-error bounds: sigma (σ of every axis and of |Δr|, default) or ppm (the parts "
                        "per million of |Δr| > --limit-mm)")
    p.add_argument("--frame", type=NAME, help="the frame whose position is studied (default: the tool)")
    p.add_argument("--allocate", action="store_true",
                   help="choose the tolerances of the rows with a cost model at least total cost so that |Δr| "
                        "(--method rss or worst) <= --limit-mm at every pose; verified by a Monte Carlo")
    p.add_argument("--processes", metavar="FILE", type=FILE,
                   help="CSV of process tables (process, option, tolerance[_unit], cost) the process column of "
                        "--tolerances names")
    add_output_options(p, report=True)
    output_option(p, "--allocated", kind="table",
                  help="with --allocate: write the allocated tolerances as a tolerances CSV")
    output_option(p, "--contributions", kind="table", help="write the contributions table (CSV)")
    output_option(p, "--capability", kind="table",
                  help="with --method mc|all and --limit-mm: write the process capability table (CSV): per pose and "
                       "quantity Pp, Ppk, PPM with their 95 %% intervals")
    output_option(p, "--plots", kind="folder", metavar="DIR",
                  help="write the error map, Monte Carlo and contribution charts as DIR/<robot>_<chart>.png (the "
                       "charts of an earlier run that this one does not draw are removed)")
    p.set_defaults(func=cmd_tolerance)

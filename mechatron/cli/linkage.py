"""``mechatron linkage``."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

from ..errors import InputError
from .common import (
    _load,
    _print_json,
    _robot_arguments,
    parse_assignments,
)


def summarize_sweep(result) -> dict[str, Any]:
    """Ranges of the inputs, points and measures of a sweep, as plain data."""
    mech, table = result.mechanism, result.table

    def span(column: str) -> list[float] | None:
        return [float(table[column].min()), float(table[column].max())] if len(table) else None

    return {
        "mechanism": mech.name, "description": mech.description, "actuated": mech.actuated,
        "mobility": mech.mobility(), "redundant_closure_equations": mech.redundant_closure_equations(),
        "samples": int(len(table) + len(result.failures)), "assembled": int(len(table)),
        "failures": result.failures.head(5).to_dict(orient="records"),
        "inputs": {name: span(name) for name in mech.actuated},
        "rates": {name: mech.input_rates.get(name, 1.0) for name in mech.actuated},
        "points": {p: {"x": span(f"{p}_x"), "y": span(f"{p}_y"),
                       "v_max": float(table[f"{p}_v"].max()) if len(table) else None,
                       "a_max": float(table[f"{p}_a"].max()) if len(table) else None}
                   for p in mech.points if f"{p}_x" in table},
        "measures": result.check_measures(),
    }

def cmd_linkage(args: argparse.Namespace) -> int:
    from ..kinematics.loops import assemble, joint_acceleration, joint_velocity
    from ..kinematics.sweep import sweep
    from ..report.progress import progress_bar

    mech = _load(args)
    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops; 'mechatron linkage' analyses closed-loop mechanisms "
                         "(see 'mechatron list')")
    if args.samples < 2:
        raise InputError(f"--samples must be at least 2, got {args.samples}")
    result = sweep(mech, samples=args.samples, links=[n for n in mech.link_names],
                   progress=progress_bar(f"{mech.name}: {args.samples} positions") if args.samples >= 2000 else None)
    summary = summarize_sweep(result)
    written: list[str] = []
    if args.plans:
        from ..kinematics.drawing import plot_plans

        at = parse_assignments(args.at) if args.at else {}
        q = assemble(mech, at)
        v = joint_velocity(mech, q, {name: mech.input_rates.get(name, 1.0) for name in mech.actuated})
        written.append(str(plot_plans(mech, q, v, joint_acceleration(mech, q, v), args.plans)))
    if args.csv:
        written += [str(p) for p in result.to_csv(args.csv)]
    if args.plot:
        from ..kinematics.drawing import plot_sweep

        curves = [m.name for m in mech.measures] or [f"{mech.tool_frame}_v"]
        written.append(str(plot_sweep(result, args.plot, curves=curves, trace=mech.tool_frame)))
    if args.json:
        _print_json({**summary, "files": written})
    else:
        _print_sweep(summary, written)
    if len(result.failures):
        first = result.failures.iloc[0]
        print(f"mechatron: warning: {len(result.failures)} of {summary['samples']} positions could not be analysed; "
              f"first: {first['reason']}", file=sys.stderr)
    return 0

def _print_sweep(summary: dict[str, Any], written: list[str]) -> None:
    print(f"{summary['mechanism']}: {summary['description']}")
    print(f"mobility W = {summary['mobility']} (redundant closure equations: {summary['redundant_closure_equations']})"
          f"; {summary['assembled']} of {summary['samples']} positions analysed")
    for name, span in summary["inputs"].items():
        if span:
            print(f"  input {name}: {span[0]:.6g} … {span[1]:.6g} at rate {summary['rates'][name]:g}")
    print(f"\n{'point':<10} {'x min':>10} {'x max':>10} {'y min':>10} {'y max':>10} {'|v| max':>10} {'|a| max':>10}")
    for name, p in summary["points"].items():
        if p["x"]:
            print(f"{name:<10} {p['x'][0]:10.4f} {p['x'][1]:10.4f} {p['y'][0]:10.4f} {p['y'][1]:10.4f} "
                  f"{p['v_max']:10.4g} {p['a_max']:10.4g}")
    if summary["measures"]:
        print(f"\n{'measure':<28} {'min':>10} {'max':>10}  check")
        for m in summary["measures"]:
            angle = m["kind"] == "transmission_angle"
            f = math.degrees if angle else float
            unit = "deg" if angle else "m"
            check = "" if m["required_min"] is None else \
                f"{'PASS' if m['pass'] else 'FAIL'} (>= {f(m['required_min']):.4g} {unit})"
            print(f"{m['name']:<28} {f(m['min']):10.4f} {f(m['max']):10.4f}  {unit} {check}")
    for path in written:
        print(f"wrote {path}")


def register(sub) -> None:
    p = sub.add_parser("linkage", help="analyse a closed-loop mechanism over the whole stroke of its inputs")
    _robot_arguments(p)
    p.add_argument("--samples", type=int, default=200, help="number of positions (default 200)")
    p.add_argument("--csv", metavar="FILE", help="write the table of every position")
    p.add_argument("--plot", metavar="FILE", help="write a PNG: the linkage at several positions and its curves")
    p.add_argument("--plans", metavar="FILE", help="write the velocity and acceleration plans (PNG) at one position")
    p.add_argument("--at", action="append", metavar="INPUT=VALUE,...",
                   help="the position of --plans (actuated coordinates, SI units; default: the reference position)")
    p.set_defaults(func=cmd_linkage)

"""``mechatron excavator``."""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..errors import InputError
from .common import (
    _floats,
    _print_json,
)


def read_design(path: str):
    """A front-shovel design file: TOML with any fields of FrontShovelDesign (lengths m, angles as named)."""
    from dataclasses import fields, replace

    from ..io.schema import FieldReader
    from ..io.toml import read_toml
    from ..machines.excavator import FrontShovelDesign

    reader = FieldReader(read_toml(path), file=path)
    values: dict[str, Any] = {}
    for f in fields(FrontShovelDesign):
        if not reader.has(f.name):
            continue
        if f.name == "boom_foot":
            values[f.name] = tuple(float(x) for x in reader.vector(f.name, 2))
        elif f.name == "boom_cylinders":
            values[f.name] = int(reader.number(f.name, minimum=1))
        else:
            values[f.name] = reader.number(f.name)
    reader.finish()
    try:
        return replace(FrontShovelDesign(), **values)
    except InputError as exc:
        raise InputError(exc.message, file=path) from None

def cmd_excavator(args: argparse.Namespace) -> int:
    from ..kinematics.frames import frame_placement
    from ..kinematics.loops import assemble
    from ..machines import excavator as ex
    from ..report.progress import progress_bar

    design = read_design(args.design) if args.design else ex.FrontShovelDesign()
    shovel = ex.synthesize(design)
    mech = ex.build(shovel)
    deg = 180 / math.pi
    special = {}
    for name, angles in ex.special_positions(shovel).items():
        lengths = shovel.cylinder_lengths(*angles)
        tip = frame_placement(mech, assemble(mech, lengths), "V").translation
        special[name] = {"theta_deg": [a * deg for a in angles], "cylinder_lengths": lengths,
                         "tip": tip[:2].tolist(), "tip_closed_form": shovel.tip(*angles).tolist()}
    cylinders = {}
    for c in shovel.cylinders:
        e_start, e_end = c.lever_arm(c.theta_range[0]), c.lever_arm(c.theta_range[1])
        gamma = c.min_transmission_angle() * deg
        cylinders[c.name] = {"levers": [c.lever_fixed, c.lever_driven], "offset_deg": c.offset * deg,
                             "L_min": c.stroke[0], "L_max": c.stroke[1], "stroke": c.stroke[1] - c.stroke[0],
                             "ratio": c.ratio, "lever_arm_start": e_start, "lever_arm_end": e_end,
                             "k": e_start / e_end, "min_transmission_angle_deg": gamma,
                             "transmission_check": "PASS" if gamma >= 30 else "FAIL",
                             "count": mech.cylinders[c.name].count}
    working = ex.working_range(mech, args.samples,
                               progress=progress_bar("working range", force=False) if not args.json else None)
    written = []
    if args.plot:
        written.append(str(ex.plot_working_range(mech, working, shovel, args.plot)))
    comparison = ex.report_comparison(shovel)
    tooth = tuple(float(x) for x in _floats(args.tooth_force, "--tooth-force")) if args.tooth_force else (0.0, 0.0)
    if len(tooth) != 2:
        raise InputError("--tooth-force needs two numbers: Fx,Fy (N)")
    for name, p in special.items():
        q = assemble(mech, p["cylinder_lengths"])
        p["tool_forces"] = ex.tool_forces(mech, q)
    from ..kinematics.sweep import sweep

    grid = sweep(mech, samples=args.samples)
    loads = ex.cylinder_loads(mech, grid.q, tooth_force=tooth)
    pressures = {name: {"max_pressure": float(loads[f"{name}_pressure"].max()),
                        "max_push": float(loads[f"{name}_force"].max()),
                        "max_pull": float(-loads[f"{name}_force"].min())} for name in mech.actuated}
    out = {
        "design": {k: v for k, v in vars(design).items()},
        "joint_ranges_deg": {"theta1": [x * deg for x in shovel.theta1], "theta2": [x * deg for x in shovel.theta2],
                             "theta3": [x * deg for x in shovel.theta3]},
        "cylinders": cylinders, "special_positions": special, "working_range": working.summary,
        "loads": {"tooth_force": list(tooth), "relief_pressure": ex.RELIEF_PRESSURE, "cylinders": pressures},
        "report_comparison": comparison, "files": written,
    }
    if args.json:
        _print_json(out)
        return 0
    print("front-shovel working device (seed 001), lengths in m, angles in degrees")
    print(f"links: boom CF = {design.boom:g}, stick FQ = {design.stick:g}, bucket QV = {design.bucket:g}; "
          f"boom foot C = {design.boom_foot}")
    for name, (lo, hi) in out["joint_ranges_deg"].items():
        print(f"  {name}: {lo:8.3f} … {hi:8.3f}")
    print(f"\n{'cylinder':<9}{'levers':>16}{'L_min':>8}{'L_max':>8}{'stroke':>8}{'λ':>7}{'e start':>9}{'e end':>8}"
          f"{'γ min':>8}  ≥30°")
    for name, c in cylinders.items():
        twin = f" (x{c['count']})" if c["count"] > 1 else ""
        print(f"{name + twin:<9}{c['levers'][0]:8.3f}{c['levers'][1]:8.3f}{c['L_min']:8.3f}{c['L_max']:8.3f}"
              f"{c['stroke']:8.3f}{c['ratio']:7.3f}{c['lever_arm_start']:9.3f}{c['lever_arm_end']:8.3f}"
              f"{c['min_transmission_angle_deg']:8.2f}  {c['transmission_check']}")
    print("\nspecial tooth-tip positions (θ1, θ2, θ3 → tip from the closed-loop model):")
    for name, p in special.items():
        print(f"  {name:<20} ({', '.join(f'{a:.3f}' for a in p['theta_deg'])}) → "
              f"({p['tip'][0]:.4f}, {p['tip'][1]:.4f})")
    print(f"\nISO 6015 tool forces at relief pressure {ex.RELIEF_PRESSURE / 1e6:g} MPa (kN, extending/retracting):")
    for name, p in special.items():
        forces = p["tool_forces"]
        print(f"  {name:<20} arm {forces['arm']['extending'] / 1e3:7.1f} / {forces['arm']['retracting'] / 1e3:6.1f}"
              f"   bucket {forces['bucket']['extending'] / 1e3:7.1f} / {forces['bucket']['retracting'] / 1e3:6.1f}")
    print(f"holding loads along the strokes (gravity, tooth force {tooth} N): largest pressure per cylinder")
    for name, p in pressures.items():
        over = "  EXCEEDS the relief pressure" if p["max_pressure"] > ex.RELIEF_PRESSURE else ""
        print(f"  {name}: {p['max_pressure'] / 1e6:7.2f} MPa (push up to {p['max_push'] / 1e3:.1f} kN, "
              f"pull up to {p['max_pull'] / 1e3:.1f} kN){over}")
    w = working.summary
    print(f"\nworking range over all strokes ({args.samples} per stroke): reach {w['max_digging_radius']:.3f}, "
          f"height {w['max_digging_height']:.3f}, depth {w['max_digging_depth']:.3f}, "
          f"reach at ground {w['max_ground_radius']:.3f}")
    print("\nthe report's numbers (✓ reproduced, ✗ not, with the reason):")
    for row in comparison:
        mark = "✓" if row["reproduced"] else "✗"
        print(f"  {mark} {row['quantity']:<40} report {row['report']:>8g}  computed {row['computed']:>9.4f} "
              f"{row['unit']}" + (f"  — {row['note']}" if row["note"] and not row["reproduced"] else ""))
    for path in written:
        print(f"wrote {path}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("excavator", help="front-shovel working device: design table, special positions, envelope")
    p.add_argument("--design", metavar="FILE", help="TOML file overriding fields of the design (see docs)")
    p.add_argument("--samples", type=int, default=31, help="grid points per cylinder stroke (default 31)")
    p.add_argument("--plot", metavar="FILE", help="write the working-range plot (PNG)")
    p.add_argument("--tooth-force", metavar="FX,FY", help="force on the tooth tip for the holding loads (N)")
    p.add_argument("--json", action="store_true", help="print machine-readable JSON")
    p.set_defaults(func=cmd_excavator)

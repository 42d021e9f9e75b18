"""The ``mechatron`` command line.

Every command has ``--help``; ``--json`` prints machine-readable output; an error prints one line to stderr and exits
with status 2 (set ``MECHATRON_DEBUG=1`` to see the traceback of an unexpected error).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import traceback
from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np
import pinocchio as pin

from . import __version__
from .errors import InputError, MechatronError
from .kinematics import REFERENCES, fk_and_jacobian
from .library import available_robots, builtin_robot_files, installed_example_robots, load
from .model import Mechanism
from .urdf import export_urdf

_NEGATIVE_VALUE = re.compile(r"^-\.?\d")


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


# ------------------------------------------------------------------------------------------------- parsing
def _floats(text: str, what: str) -> np.ndarray:
    try:
        values = np.array([float(x) for x in text.replace(" ", "").split(",") if x != ""])
    except ValueError:
        raise InputError(f"{what} must be comma-separated numbers, got {text!r}") from None
    if not np.all(np.isfinite(values)):
        raise InputError(f"{what} must be finite numbers, got {text!r}")
    return values


def parse_assignments(items: Sequence[str] | None) -> dict[str, float]:
    """``["a2=0.5,d3=0.1", ...]`` → {"a2": 0.5, "d3": 0.1} (values in SI units)."""
    out: dict[str, float] = {}
    for item in items or ():
        for part in filter(None, item.split(",")):
            name, sep, value = part.partition("=")
            if not sep or not name.strip():
                raise InputError(f"--set expects NAME=VALUE[,NAME=VALUE...], got {part!r}")
            try:
                out[name.strip()] = float(value)
            except ValueError:
                raise InputError(f"--set {name.strip()}: value must be a number, got {value!r}") from None
    return out


def _load(args: argparse.Namespace) -> Mechanism:
    return load(args.robot, **parse_assignments(args.set))


def _configuration(mech: Mechanism, text: str, degrees: bool) -> np.ndarray:
    q = _floats(text, "--q")
    if q.shape != (mech.nq,):
        raise InputError(f"--q needs {mech.nq} values for {mech.name} ({', '.join(mech.joint_names)}), got {len(q)}")
    if degrees:
        q = np.where(_revolute_mask(mech), np.radians(q), q)
    for message in mech.limit_violations(q):
        print(f"mechatron: warning: {message}", file=sys.stderr)
    return q


def _revolute_mask(mech: Mechanism) -> np.ndarray:
    return np.array([mech.joint_kind(j) == "revolute" for j in range(1, mech.model.njoints)])


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _print_json(obj: Any) -> None:
    print(json.dumps(obj, indent=2, allow_nan=False))


def _write_table(table, path) -> str:
    """Write a DataFrame as CSV; an error naming the file if it cannot be written."""
    from pathlib import Path

    try:
        table.to_csv(path, index=False, float_format="%.10g")
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror}", file=path) from None
    return str(Path(path))


def _matrix_text(matrix: np.ndarray, rows: Sequence[str], cols: Sequence[str], fmt: str = "{:>11.5f}") -> str:
    width = max(11, *(len(c) for c in cols))
    head = " " * 6 + "".join(f"{c:>{width}}" for c in cols)
    lines = [head] + [f"{r:<6}" + "".join(f"{fmt.format(x):>{width}}" for x in row) for r, row in zip(rows, matrix)]
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------ commands
def cmd_list(args: argparse.Namespace) -> int:
    names = available_robots()
    if args.json:
        _print_json(names)
        return 0
    builtin = builtin_robot_files()
    examples = installed_example_robots()
    print(f"{'name':<18} {'W':>3}  description (W: degrees of mobility)")
    for name in names:
        try:
            mech = load(name)
            print(f"{name:<18} {mech.mobility():>3}  {mech.description}")
        except MechatronError as exc:
            print(f"{name:<18} {'?':>3}  (cannot load: {exc})")
    print(f"\n{len(builtin)} robot files in {next(iter(builtin.values())).parent if builtin else 'robots/'}; "
          f"{len(examples)} arms from example-robot-data")
    from .structure.description import shipped_structures

    print(f"structural descriptions of the textbook's cases (mechatron structure NAME): "
          f"{', '.join(shipped_structures())}")
    return 0


def describe(mech: Mechanism) -> dict[str, Any]:
    """Everything ``mechatron show`` prints, as plain data."""
    model = mech.model
    joints = []
    for j in range(1, model.njoints):
        iq, iv = model.joints[j].idx_q, model.joints[j].idx_v
        joints.append({
            "name": model.names[j], "kind": mech.joint_kind(j),
            "lower": _finite(model.lowerPositionLimit[iq]), "upper": _finite(model.upperPositionLimit[iq]),
            "max_velocity": _finite(model.velocityLimit[iv]), "max_effort": _finite(model.effortLimit[iv]),
            "armature": float(model.armature[iv]),
        })
    links = [{"name": name, "mass": float(model.inertias[j].mass), "com": model.inertias[j].lever.tolist()}
             for j, name in enumerate(mech.link_names, start=1)]
    drives = {name: {"rotor_inertia": d.rotor_inertia, "gear_ratio": d.gear_ratio, "efficiency": d.efficiency,
                     "reflected_inertia": d.reflected_inertia} for name, d in mech.drives.items()}
    return {
        "name": mech.name, "description": mech.description, "source": mech.source,
        "convention": mech.dh.convention if mech.dh is not None else None,
        "nq": mech.nq, "nv": mech.nv, "mobility": mech.mobility(), "total_mass": mech.total_mass,
        "gravity": model.gravity.linear.tolist(),
        "dh": mech.dh.to_frame().to_dict(orient="records") if mech.dh is not None else None,
        "joints": joints, "links": links, "drives": drives,
        "parameters": {n: {"value": p.value, "unit": p.unit, "description": p.description}
                       for n, p in mech.parameters.items()},
        "frames": sorted({f.name for f in model.frames if f.type in (pin.FrameType.OP_FRAME, pin.FrameType.BODY)}),
        "actuated": mech.actuated,
        "closures": [c.describe() for c in mech.closures],
        "redundant_closure_equations": mech.redundant_closure_equations(),
        "cylinders": {n: {"base": c.base, "eye": c.eye, "L_min": c.stroke[0], "L_max": c.stroke[1], "count": c.count}
                      for n, c in mech.cylinders.items()},
        "notes": mech.notes,
    }


def cmd_show(args: argparse.Namespace) -> int:
    mech = _load(args)
    info = describe(mech)
    if args.json:
        _print_json(info)
        return 0
    print(f"{mech.name}: {mech.description}")
    if mech.source:
        print(f"from {mech.source}")
    print(f"{mech.nq} coordinates, mobility W = {info['mobility']}, total mass {info['total_mass']:.3f} kg, "
          f"gravity {info['gravity']} m/s²")
    if mech.dh is not None:
        print(f"\nDH table ({mech.dh.convention} convention; θ and α in degrees, lengths in metres):")
        print(mech.dh.to_frame().to_string())
    print("\njoints:")
    for joint in info["joints"]:
        unit = "rad" if joint["kind"] == "revolute" else "m"
        limits = f"[{joint['lower']:g}, {joint['upper']:g}] {unit}" if joint["lower"] is not None else "unbounded"
        print(f"  {joint['name']:<22} {joint['kind']:<10} {limits}")
    print("\nlinks (mass kg, centre of mass m in the joint frame):")
    for link in info["links"]:
        print(f"  {link['name']:<22} {link['mass']:9.4f}  {np.round(link['com'], 5).tolist()}")
    if info["drives"]:
        print("\ndrives (rotor inertia kg·m², gear ratio, efficiency, reflected inertia J·u²):")
        for name, d in info["drives"].items():
            print(f"  {name:<22} {d['rotor_inertia']:10.3e} {d['gear_ratio']:10.4g} {d['efficiency']:6.3f} "
                  f"{d['reflected_inertia']:10.4g}")
    print(f"\ngeometric parameters ({len(info['parameters'])}; override with --set NAME=VALUE):")
    names = list(info["parameters"])
    for start in range(0, len(names), 4):
        print("  " + "  ".join(f"{n}={info['parameters'][n]['value']:.6g}" for n in names[start:start + 4]))
    if mech.closures:
        print(f"\nclosures ({len(mech.closures)}; redundant equations: {info['redundant_closure_equations']}):")
        for text in info["closures"]:
            print(f"  {text}")
        print(f"actuated coordinates: {', '.join(mech.actuated)}")
    for name, c in info["cylinders"].items():
        twin = f", {c['count']} side by side" if c["count"] > 1 else ""
        print(f"cylinder {name}: {c['base']} to {c['eye']}, {c['L_min']:.4g} … {c['L_max']:.4g} m{twin}")
    for note in mech.notes:
        print(f"note: {note}")
    print(f"\nframes: {', '.join(info['frames'])}")
    return 0


def cmd_fk(args: argparse.Namespace) -> int:
    mech = _load(args)
    q = _configuration(mech, args.q, args.deg)
    frame = args.frame or mech.tool_frame
    placement = mech.frame_placement(q, frame)
    if args.json:
        _print_json({"frame": frame, "position": placement.translation.tolist(),
                     "rotation": placement.rotation.tolist()})
        return 0
    rpy = np.degrees(pin.rpy.matrixToRpy(placement.rotation))
    print(f"{mech.name}, frame {frame} at q = {np.round(q, 6).tolist()}")
    print(f"position (m):      {np.array2string(placement.translation, precision=6, suppress_small=True)}")
    print(f"roll-pitch-yaw (deg): {np.array2string(rpy, precision=4, suppress_small=True)}")
    print("rotation:")
    print(np.array2string(placement.rotation, precision=6, suppress_small=True))
    return 0


def cmd_jacobian(args: argparse.Namespace) -> int:
    mech = _load(args)
    q = _configuration(mech, args.q, args.deg)
    frame = args.frame or mech.tool_frame
    _, _, jacobians = fk_and_jacobian(mech, q[None, :], frame, args.reference)
    jacobian = jacobians[0]
    singular_values = np.linalg.svd(jacobian, compute_uv=False)
    if args.json:
        _print_json({"frame": frame, "reference": args.reference, "joints": mech.joint_names,
                     "jacobian": jacobian.tolist(), "singular_values": singular_values.tolist()})
        return 0
    print(f"{mech.name}, Jacobian of frame {frame} ({args.reference}) at q = {np.round(q, 6).tolist()}")
    print("rows: linear velocity (m/s) then angular velocity (rad/s) per unit joint rate")
    print(_matrix_text(jacobian, ["vx", "vy", "vz", "wx", "wy", "wz"], mech.joint_names))
    print(f"singular values: {np.array2string(singular_values, precision=5)}")
    return 0


def cmd_export_urdf(args: argparse.Namespace) -> int:
    mech = _load(args)
    if mech.closures:
        print(f"mechatron: warning: URDF has no closed loops; {len(mech.closures)} closure(s) of {mech.name} are "
              "not written (only its spanning tree)", file=sys.stderr)
    written = export_urdf(mech, args.output)
    for path in written:
        print(f"wrote {path}")
    if len(written) > 1:
        print("(the .srdf holds the drives' rotor inertia and gear ratio: pinocchio.loadRotorParameters reads it)")
    return 0


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
    from .progress import progress_bar
    from .sweep import sweep

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
        from .plots import plot_plans

        at = parse_assignments(args.at) if args.at else {}
        q = mech.assemble(at)
        v = mech.velocity(q, {name: mech.input_rates.get(name, 1.0) for name in mech.actuated})
        written.append(str(plot_plans(mech, q, v, mech.acceleration(q, v), args.plans)))
    if args.csv:
        written += [str(p) for p in result.to_csv(args.csv)]
    if args.plot:
        from .plots import plot_sweep

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


def read_design(path: str):
    """A front-shovel design file: TOML with any fields of FrontShovelDesign (lengths m, angles as named)."""
    from dataclasses import fields, replace

    from .machines.excavator import FrontShovelDesign
    from .robotfile import read_toml
    from .schema import FieldReader

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
    from .machines import excavator as ex
    from .progress import progress_bar

    design = read_design(args.design) if args.design else ex.FrontShovelDesign()
    shovel = ex.synthesize(design)
    mech = ex.build(shovel)
    deg = 180 / math.pi
    special = {}
    for name, angles in ex.special_positions(shovel).items():
        lengths = shovel.cylinder_lengths(*angles)
        tip = mech.frame_placement(mech.assemble(lengths), "V").translation
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
        q = mech.assemble(p["cylinder_lengths"])
        p["tool_forces"] = ex.tool_forces(mech, q)
    from .sweep import sweep

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


def _trajectory(mech: Mechanism, args: argparse.Namespace):
    from .motion import cycle, read_trajectory

    if bool(args.trajectory) == bool(args.move):
        raise InputError("give either --trajectory FILE or --move SPEC")
    if args.trajectory:
        trajectory = read_trajectory(args.trajectory, mech)
        if mech.closures and trajectory.q.shape[1] != len(mech.actuated):
            raise InputError(f"{mech.name}: a trajectory file gives the actuated coordinates "
                             f"{', '.join(mech.actuated)}")
        return trajectory
    n = len(mech.actuated) if mech.closures else mech.nq
    points = []
    for k, part in enumerate(filter(None, (p.strip() for p in args.move.split(";")))):
        values = _floats(part, f"--move point {k + 1}")
        if values.shape != (n,):
            raise InputError(f"--move point {k + 1} needs {n} values, got {len(values)}")
        points.append(np.where(_revolute_mask(mech), np.radians(values), values) if args.deg and not mech.closures
                      else values)
    if len(points) < 2:
        raise InputError("--move needs at least two points separated by ';'")
    limits = {key: _floats(getattr(args, key), f"--{key}") if getattr(args, key) else None
              for key in ("vmax", "amax", "jmax")}
    return cycle(None if mech.closures else mech, points, dwell=args.dwell, profile=args.profile, dt=args.dt,
                 **{k: (v if v is None or len(v) > 1 else float(v[0])) for k, v in limits.items()})


def cmd_dynamics(args: argparse.Namespace) -> int:
    from .dynamics import trajectory_loads, with_payload

    mech = _load(args)
    if args.payload:
        if mech.closures:
            raise InputError("--payload is for serial arms (it is carried at the tool)")
        mech = with_payload(mech, args.payload)
    trajectory = _trajectory(mech, args)
    result = trajectory_loads(mech, trajectory)
    written = []
    if args.csv:
        written.append(_write_table(result.table, args.csv))
    if args.plot:
        written.append(str(_plot_loads(result, args.plot, mech)))
    summary = result.summary
    if args.json:
        _print_json({"mechanism": mech.name, "duration": float(trajectory.t[-1] - trajectory.t[0]),
                     "samples": len(trajectory.t), "coordinates": summary.to_dict(orient="records"),
                     "files": written})
        return 0
    kind = "actuator" if mech.closures else "joint"
    print(f"{mech.name}: {kind} loads over {trajectory.t[-1] - trajectory.t[0]:.3f} s ({len(trajectory.t)} samples)")
    print(summary.to_string(index=False, float_format=lambda x: f"{x:.5g}"))
    print("units: N·m and rad/s for revolute joints, N and m/s for prismatic ones and cylinders; power W, work J")
    for path in written:
        print(f"wrote {path}")
    return 0


def _plot_loads(result, path, mech: Mechanism):
    from matplotlib.figure import Figure

    from .plots import _save

    table = result.table
    fig = Figure(figsize=(10, 7), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    for name in result.names:
        axes[0].plot(table["t"], table[f"qd_{name}"], label=name)
        axes[1].plot(table["t"], table[f"tau_{name}"], label=name)
        axes[2].plot(table["t"], table[f"power_{name}"], label=name)
    for ax, label in zip(axes, ("speed (rad/s, m/s)", "force (N·m, N)", "power (W)")):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, ncol=min(6, len(result.names)))
    axes[0].set_title(f"{mech.name}: loads along the motion")
    axes[2].set_xlabel("t (s)")
    from pathlib import Path

    _save(fig, Path(path))
    return path


def cmd_reduced(args: argparse.Namespace) -> int:
    from .reduced import reduced_table
    from .sweep import default_inputs

    mech = _load(args)
    if len(mech.actuated) != 1 or mech.mobility() != 1:
        raise InputError(f"{mech.name} has {mech.mobility()} degrees of mobility; the reduced (one-mass) model needs 1")
    name = args.input or mech.actuated[0]
    if name not in mech.actuated:
        raise InputError(f"--input must be the actuated coordinate of {mech.name}: {mech.actuated[0]}")
    values = default_inputs(mech, args.samples)[name] if mech.closures else np.linspace(
        mech.model.lowerPositionLimit[0], mech.model.upperPositionLimit[0], args.samples)
    table = reduced_table(mech, name, values)
    linear = mech.joint_kind(name) == "prismatic"
    written = []
    if args.csv:
        written.append(_write_table(table, args.csv))
    if args.plot:
        from matplotlib.figure import Figure

        from .plots import _save

        fig = Figure(figsize=(8, 6), layout="constrained")
        top, bottom = fig.subplots(2, 1, sharex=True)
        top.plot(table[name], table["J_reduced"])
        top.set_ylabel("reduced mass (kg)" if linear else "reduced inertia (kg·m²)")
        bottom.plot(table[name], table["M_reduced"])
        bottom.set_ylabel("reduced force of gravity (N)" if linear else "reduced moment of gravity (N·m)")
        bottom.set_xlabel(f"{name} ({'m' if linear else 'rad'})")
        for ax in (top, bottom):
            ax.grid(True, alpha=0.3)
        top.set_title(f"{mech.name}: one-mass model reduced to {name} (eq. 6.8, 6.20)")
        from pathlib import Path

        _save(fig, Path(args.plot))
        written.append(args.plot)
    if args.json:
        _print_json({"mechanism": mech.name, "input": name, "kind": "mass" if linear else "inertia",
                     "table": table.to_dict(orient="list"), "files": written})
        return 0
    unit = ("kg", "N") if linear else ("kg·m²", "N·m")
    print(f"{mech.name}: reduced {'mass' if linear else 'moment of inertia'} and {'force' if linear else 'moment'} of"
          f" gravity, input {name}")
    print(f"  J_reduced {table['J_reduced'].min():.6g} … {table['J_reduced'].max():.6g} {unit[0]}; "
          f"M_reduced {table['M_reduced'].min():.6g} … {table['M_reduced'].max():.6g} {unit[1]}")
    step = max(1, len(table) // 12)
    print(table.iloc[::step].to_string(index=False, float_format=lambda x: f"{x:.6g}"))
    for path in written:
        print(f"wrote {path}")
    return 0


def cmd_size(args: argparse.Namespace) -> int:
    """Motor, gearbox (screw, cylinder) and ratio for every joint doing a task; exit 1 when a joint has no
    feasible drive."""
    from .drives.catalogs import read_catalog
    from .drives.report import text_report, to_json, write_charts, write_csv
    from .drives.sizing import size_mechanism
    from .progress import progress_bar
    from .tasks import default_task, read_task

    mech = _load(args)
    task = read_task(args.task, mech) if args.task else default_task(mech)
    catalogs = {kind: read_catalog(path, kind) if path else None for kind, path in
                (("motors", args.motors), ("gearboxes", args.gearboxes), ("linear", args.linear),
                 ("cylinders", args.cylinders))}
    if not args.pressure_mpa > 0:
        raise InputError(f"--pressure-mpa must be > 0, got {args.pressure_mpa:g}")
    result = size_mechanism(task.mechanism, task.trajectory, **catalogs, objective=args.objective,
                            inertia_ratio_max=args.inertia_ratio, loads=task.loads, task=task.name,
                            direct=not args.no_direct, pressure=args.pressure_mpa * 1e6,
                            chain_efficiency=args.chain_efficiency,
                            progress=None if args.json else progress_bar(f"{mech.name}: sizing"))
    written = [write_csv(result, args.csv)] if args.csv else []
    if args.plots:
        written += write_charts(result, args.plots)
    if args.json:
        print(to_json(result))
    else:
        print(text_report(result))
        for path in written:
            print(f"wrote {path}")
    return 0 if result.feasible else 1


def cmd_tolerance(args: argparse.Namespace) -> int:
    """Positioning error of a point from the tolerances of parameters and coordinates (textbook chapter 8)."""
    from .accuracy.plots import write_charts
    from .accuracy.sources import read_poses, read_tolerances, reference_pose, workspace_grid
    from .accuracy.study import run_study
    from .progress import progress_bar

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
    if args.limit_mm is not None and not args.limit_mm > 0:
        raise InputError(f"--limit-mm must be > 0, got {args.limit_mm:g}")
    limit = args.limit_mm * 1e-3 if args.limit_mm is not None else None
    long_run = "mc" in methods and len(poses) * args.samples >= 200_000 and not args.json
    result = run_study(mech, sources, poses, labels, point=args.point, methods=methods, k=args.k,
                       samples=args.samples, seed=args.seed, limit=limit,
                       progress=progress_bar(f"{mech.name}: Monte Carlo") if long_run else None)
    written = []
    if args.csv:
        written.append(_write_table(result.poses, args.csv))
    if args.contributions:
        written.append(_write_table(result.contributions, args.contributions))
    if args.plots:
        written += [str(p) for p in write_charts(result, args.plots)]
    if args.json:
        _print_json(result.records())
        return 0
    print(f"{mech.name}: positioning error of {result.point} ({', '.join(methods)}; k = {args.k:g}; "
          f"{len(sources)} error sources, {len(poses)} pose{'s' if len(poses) > 1 else ''})")
    shown = result.poses[["label", *[f"dr_{m}" for m in methods]]].copy()
    shown.iloc[:, 1:] *= 1e3
    shown.columns = ["pose", *[f"|Δr| {m} (mm)" for m in methods]]
    print(shown.head(20).to_string(index=False, float_format=lambda x: f"{x:.5g}"))
    if len(shown) > 20:
        print(f"… {len(shown) - 20} more poses; the largest at pose {result.poses['label'].iloc[result.critical]}")
    print("\ncontributions at the critical pose (% of the variance):")
    c = result.contributions
    print(c[["source", "unit", "tolerance", "sensitivity", "worst_share", "variance_share"]
            + (["mc_share"] if "mc_share" in c else [])].to_string(index=False, float_format=lambda x: f"{x:.4g}"))
    for note in result.notes:
        print(f"note: {note}")
    for path in written:
        print(f"wrote {path}")
    return 0


def cmd_structure(args: argparse.Namespace) -> int:
    """Structural analysis (chapter 3) of a mechanism or of a structural description file."""
    from .structure.analysis import analyse, text_report
    from .structure.description import read_structure, structure_file

    path = structure_file(args.robot)
    subject = read_structure(path) if path else _load(args)
    report = analyse(subject)
    if args.json:
        _print_json(report.as_dict())
    else:
        print(text_report(report))
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    from .demo import run

    run()
    return 0


# ------------------------------------------------------------------------------------------------- parser
def _robot_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("robot", help="robot name (see 'mechatron list') or a .toml/.urdf file")
    parser.add_argument("--set", action="append", metavar="NAME=VALUE,...",
                        help="override geometric parameters (SI units: m, rad), e.g. --set a2=0.45,d4=0.43")
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON")


def _pose_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--q", required=True, metavar="Q1,Q2,...",
                        help="joint coordinates, comma-separated (rad and m; see --deg)")
    parser.add_argument("--deg", action="store_true", help="revolute joint values of --q are in degrees")
    parser.add_argument("--frame", help="frame name (default: tool)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mechatron", description="Sizing and analysis of mechatronic modules and mechanisms "
                                                   "(Pinocchio inside). SI units throughout.")
    parser.add_argument("--version", action="version", version=f"mechatron {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    p = sub.add_parser("list", help="list the robots and mechanisms mechatron can load")
    p.add_argument("--json", action="store_true", help="print a JSON list of names")
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("show", help="DH table, joints, masses, drives, mobility and parameters of a robot")
    _robot_arguments(p)
    p.set_defaults(func=cmd_show)

    p = sub.add_parser("fk", help="forward kinematics: position and rotation of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("jacobian", help="6×n Jacobian of a frame")
    _robot_arguments(p)
    _pose_arguments(p)
    p.add_argument("--reference", choices=list(REFERENCES), default="world_aligned",
                   help="world_aligned: world axes at the frame origin (default); local: frame axes; world: "
                        "Pinocchio's spatial convention")
    p.set_defaults(func=cmd_jacobian)

    p = sub.add_parser("export-urdf", help="write a robot as URDF (plus SRDF rotor data)")
    _robot_arguments(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="URDF file to write")
    p.set_defaults(func=cmd_export_urdf)

    p = sub.add_parser("linkage", help="analyse a closed-loop mechanism over the whole stroke of its inputs")
    _robot_arguments(p)
    p.add_argument("--samples", type=int, default=200, help="number of positions (default 200)")
    p.add_argument("--csv", metavar="FILE", help="write the table of every position")
    p.add_argument("--plot", metavar="FILE", help="write a PNG: the linkage at several positions and its curves")
    p.add_argument("--plans", metavar="FILE", help="write the velocity and acceleration plans (PNG) at one position")
    p.add_argument("--at", action="append", metavar="INPUT=VALUE,...",
                   help="the position of --plans (actuated coordinates, SI units; default: the reference position)")
    p.set_defaults(func=cmd_linkage)

    p = sub.add_parser("excavator", help="front-shovel working device: design table, special positions, envelope")
    p.add_argument("--design", metavar="FILE", help="TOML file overriding fields of the design (see docs)")
    p.add_argument("--samples", type=int, default=31, help="grid points per cylinder stroke (default 31)")
    p.add_argument("--plot", metavar="FILE", help="write the working-range plot (PNG)")
    p.add_argument("--tooth-force", metavar="FX,FY", help="force on the tooth tip for the holding loads (N)")
    p.add_argument("--json", action="store_true", help="print machine-readable JSON")
    p.set_defaults(func=cmd_excavator)

    p = sub.add_parser("dynamics", help="joint torques or cylinder forces, speeds, power and energy along a motion")
    _robot_arguments(p)
    p.add_argument("--trajectory", metavar="FILE", help="CSV with t and one column per joint (or actuated input)")
    p.add_argument("--move", metavar="Q0;Q1[;Q2...]",
                   help="points to move through, each comma-separated (rad, m); closed loops: actuated inputs")
    p.add_argument("--deg", action="store_true", help="revolute values of --move are in degrees")
    p.add_argument("--profile", default="trapezoidal", choices=["triangular", "trapezoidal", "scurve", "quintic"])
    p.add_argument("--vmax", help="velocity limit(s), one value or one per axis (default: the model's or 1)")
    p.add_argument("--amax", help="acceleration limit(s) (default 5)")
    p.add_argument("--jmax", help="jerk limit(s) for --profile scurve (default 50)")
    p.add_argument("--dwell", type=float, default=0.0, help="rest at every point after the first (s)")
    p.add_argument("--dt", type=float, default=0.005, help="sampling step (s)")
    p.add_argument("--payload", type=float, default=0.0, help="payload mass at the tool (kg)")
    p.add_argument("--csv", metavar="FILE", help="write every sample")
    p.add_argument("--plot", metavar="FILE", help="write speeds, forces and power against time (PNG)")
    p.set_defaults(func=cmd_dynamics)

    p = sub.add_parser("reduced", help="reduced inertia (or mass) and moment (or force) of a 1-DOF mechanism")
    _robot_arguments(p)
    p.add_argument("--input", help="the input coordinate (default: the actuated one)")
    p.add_argument("--samples", type=int, default=73)
    p.add_argument("--csv", metavar="FILE")
    p.add_argument("--plot", metavar="FILE", help="write J and M against the input (PNG)")
    p.set_defaults(func=cmd_reduced)

    p = sub.add_parser("size", help="choose motor, gearbox and ratio (or screw, or cylinder) for every joint "
                                    "doing a task; exit 1 if a joint has no feasible drive")
    _robot_arguments(p)
    p.add_argument("--task", metavar="FILE", help="task TOML (waypoints, payload, loads) or trajectory CSV "
                                                  "(default: the robot's own task, else a generic out-and-back)")
    p.add_argument("--motors", metavar="CSV", help="servo motor catalog (default: catalogs/servo_motors.csv)")
    p.add_argument("--gearboxes", metavar="CSV", help="gearbox catalog (default: catalogs/gearboxes.csv)")
    p.add_argument("--linear", metavar="CSV", help="linear drives (ball screws, racks) for prismatic joints "
                                                   "(default: catalogs/linear_drives.csv)")
    p.add_argument("--cylinders", metavar="CSV", help="hydraulic cylinder catalog for closed-loop mechanisms")
    p.add_argument("--objective", default="mass", choices=["mass", "cost", "margin", "time"],
                   help="rank feasible drives by mass, cost, margin (largest smallest margin) or time (fastest "
                        "task, then mass); default mass")
    p.add_argument("--inertia-ratio", type=float, default=10.0, help="largest load/motor inertia ratio (default 10)")
    p.add_argument("--no-direct", action="store_true", help="do not consider direct drive (gearless) motors")
    p.add_argument("--pressure-mpa", type=float, default=32.0, help="hydraulic system pressure (default 32 MPa)")
    p.add_argument("--chain-efficiency", type=float, default=1.0,
                   help="efficiency of the rest of the chain (couplings, bearings, belt), multiplies every "
                        "converter's (default 1)")
    p.add_argument("--csv", metavar="FILE", help="write every check of every joint")
    p.add_argument("--plots", metavar="DIR", help="write a speed–torque chart per chosen motor (PNG)")
    p.set_defaults(func=cmd_size)

    p = sub.add_parser("tolerance", help="positioning error of a point from parameter and joint tolerances: "
                                         "worst case, RSS, Monte Carlo, or a given set of errors")
    _robot_arguments(p)
    p.add_argument("--tolerances", required=True, metavar="FILE",
                   help="CSV: parameter, tolerance (or tolerance_mm, …, or grade), distribution, bias, error")
    p.add_argument("--poses", metavar="FILE", help="CSV: a configuration per row (closed loops: actuated inputs)")
    p.add_argument("--grid", type=int, metavar="N", help="poses over the workspace: N per coordinate (≤ 2 "
                                                         "coordinates) or N random ones")
    p.add_argument("--method", default="all", choices=["worst", "rss", "mc", "all", "given"],
                   help="all = worst, rss and mc (default); given: the Δr of the error column (8.4)")
    p.add_argument("--samples", type=int, default=10000, help="Monte Carlo samples per pose (default 10000)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--k", type=float, default=3.0, help="coverage factor: σ = t/k for normal errors (default 3)")
    p.add_argument("--limit-mm", type=float, help="largest acceptable |Δr| (mm) for the Monte Carlo yield")
    p.add_argument("--point", help="the frame whose position is studied (default: the tool)")
    p.add_argument("--csv", metavar="FILE", help="write the per-pose results")
    p.add_argument("--contributions", metavar="FILE", help="write the contributions table")
    p.add_argument("--plots", metavar="DIR", help="write the error map, Monte Carlo and contribution charts")
    p.set_defaults(func=cmd_tolerance)

    p = sub.add_parser("structure", help="structural analysis: pairs by class, loops, mobility by every formula "
                                         "and from the model, redundancy, Assur groups")
    _robot_arguments(p)
    p.set_defaults(func=cmd_structure)

    p = sub.add_parser("demo", help="a short tour: load a robot and print its kinematics")
    p.set_defaults(func=cmd_demo)
    return parser


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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 error)."""
    parser = build_parser()
    args = parser.parse_args(_join_negative_values(sys.argv[1:] if argv is None else argv))
    try:
        return int(args.func(args) or 0)
    except MechatronError as exc:
        print(f"mechatron: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. piped into head
        return 0
    except Exception as exc:  # noqa: BLE001 - the command line never shows a traceback unless asked to
        if os.environ.get("MECHATRON_DEBUG"):
            traceback.print_exc()
        print(f"mechatron: internal error: {type(exc).__name__}: {exc} (set MECHATRON_DEBUG=1 for details)",
              file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

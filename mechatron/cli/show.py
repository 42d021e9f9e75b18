"""``mechatron show``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

import numpy as np

from .common import (
    _finite,
    _load,
    _print_json,
    _robot_arguments,
)

if TYPE_CHECKING:  # pragma: no cover
    from ..model import Mechanism


def describe(mech: Mechanism) -> dict[str, Any]:
    import pinocchio as pin

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


def register(sub) -> None:
    p = sub.add_parser("show", help="DH table, joints, masses, drives, mobility and parameters of a robot")
    _robot_arguments(p)
    p.set_defaults(func=cmd_show)

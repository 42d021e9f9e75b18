"""``mechatron reduced``."""

from __future__ import annotations

import argparse

import numpy as np

from ..errors import InputError
from .common import (
    _load,
    _print_json,
    _robot_arguments,
    _write_table,
)


def cmd_reduced(args: argparse.Namespace) -> int:
    from ..dynamics.reduced import reduced_table
    from ..kinematics.sweep import default_inputs

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

        from ..io.output import save_figure as _save

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


def register(sub) -> None:
    p = sub.add_parser("reduced", help="reduced inertia (or mass) and moment (or force) of a 1-DOF mechanism")
    _robot_arguments(p)
    p.add_argument("--input", help="the input coordinate (default: the actuated one)")
    p.add_argument("--samples", type=int, default=73)
    p.add_argument("--csv", metavar="FILE")
    p.add_argument("--plot", metavar="FILE", help="write J and M against the input (PNG)")
    p.set_defaults(func=cmd_reduced)

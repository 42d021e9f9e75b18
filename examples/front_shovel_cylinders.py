"""Choose the boom, stick and bucket cylinders of the front shovel [Shovel] from a cylinder catalog for two load
cases of a working cycle, and compare them with the illustrative cylinders of mechatron.machines.excavator.

    python examples/front_shovel_cylinders.py [--dig-force 200] [--payload 4000] [--pressure 32] [--charts DIR]

Load case 1, digging: stick and bucket cylinders extend together while the tooth meets a resistance of
``--dig-force`` kN opposite to the tooth's motion at the start of the cut. Load case 2, lifting: the boom rises and
the stick comes in with ``--payload`` kg of material in the bucket (its weight at the tooth). Each cylinder gets
the larger of the two catalog cylinders (the lightest that passes push and pull pressure at the system pressure,
stroke and rod buckling); the pump flow is the sum over the cylinders of the larger case.
"""

from __future__ import annotations

import argparse

import numpy as np

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.dynamics.motion import Trajectory, cycle
from mechatron.dynamics.task import Task
from mechatron.kinematics.frames import point_velocity
from mechatron.kinematics.loops import assemble, joint_velocity
from mechatron.machines.excavator import DEFAULT_CYLINDERS


def stroke_point(mech, fractions):
    return [lo + f * (hi - lo) for (lo, hi), f in zip((mech.cylinders[n].stroke for n in mech.actuated), fractions)]


def task(mech, start, end, speed):
    tr = cycle(None, [stroke_point(mech, start), stroke_point(mech, end)], vmax=speed, amax=0.5, dt=0.01)
    return Trajectory(tr.t, tr.q, tr.v, tr.a, list(mech.actuated))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dig-force", type=float, default=200.0, help="digging resistance at the tooth (kN)")
    parser.add_argument("--payload", type=float, default=4000.0, help="material in the bucket (kg)")
    parser.add_argument("--pressure", type=float, default=32.0, help="system pressure (MPa)")
    parser.add_argument("--charts", help="directory for the force-speed charts")
    args = parser.parse_args()

    shovel = mechatron.load("front_shovel")
    catalog = default_catalog("cylinders")
    dig = task(shovel, (0.45, 0.15, 0.2), (0.45, 0.85, 0.9), speed=[0.1, 0.15, 0.15])
    q = assemble(shovel, dict(zip(shovel.actuated, dig.q[1])))
    v = joint_velocity(shovel, q, dict(zip(shovel.actuated, dig.v[1] / np.abs(dig.v[1]).max())))
    direction = point_velocity(shovel, q, v, "V")
    resistance = -args.dig_force * 1e3 * direction / np.linalg.norm(direction)
    lift = task(shovel, (0.3, 0.8, 0.9), (0.95, 0.5, 0.9), speed=[0.12, 0.12, 0.1])
    cases = {
        f"digging, {args.dig_force:g} kN at the tooth": (dig, [("V", resistance)]),
        f"lifting {args.payload:g} kg": (lift, [("V", [0.0, -9.81 * args.payload, 0.0])]),
    }
    chosen = {}
    for name, (trajectory, loads) in cases.items():
        result = mechatron.size(shovel, Task(name, shovel, trajectory, loads), cylinders=catalog,
                                pressure=args.pressure * 1e6)
        print(f"{result}\n")
        if args.charts:
            for path in result.save_plots(args.charts):
                print(f"wrote {path}")
        for joint in result.joints:
            mass = joint.ranking["mass"].iloc[0] if joint.feasible else np.inf
            if joint.joint not in chosen or mass > chosen[joint.joint][1]:
                chosen[joint.joint] = (joint, mass)
    print("the cylinders for both load cases (compare: the illustrative ones of machines.excavator):")
    flow = 0.0
    for name, (joint, _) in chosen.items():
        spec = DEFAULT_CYLINDERS[name]
        flow += joint.peak_flow
        print(f"  {name}: {joint.count} × {joint.cylinder} (bore {joint.cylinder_data['bore'] * 1e3:g} mm, rod "
              f"{joint.cylinder_data['rod'] * 1e3:g} mm); illustrative: {spec.count} × {spec.bore * 1e3:g}/"
              f"{spec.rod * 1e3:g} mm")
    print(f"pump flow if all three move at their peak speeds together: {flow * 6e4:.0f} l/min")


if __name__ == "__main__":
    main()

"""Simulate a rod grab scooping (seed 003): the closing rope pulls the jaws shut against the material's resistance.

    python examples/grab_scooping.py [--tension 20000] [--resistance 15000] [--plot grab.png]

The paper's own formulation (7 absolute coordinates and 6 Lagrange multipliers solved together, eq. 8) is
integrated and checked against mechatron's Pinocchio model of the same grab with the same forces.
"""

from __future__ import annotations

import argparse

import numpy as np

import mechatron
from mechatron.dynamics import constrained
from mechatron.kinematics.loops import assemble
from mechatron.machines.grab import GrabGeometry, PaperModel, ScoopingLoads, mechanism_loads, plot_scooping


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tension", type=float, default=20e3, help="closing rope tension (N)")
    parser.add_argument("--resistance", type=float, default=15e3, help="cutting resistance on one jaw (N)")
    parser.add_argument("--plot", default="grab_scooping.png")
    args = parser.parse_args()

    geometry = GrabGeometry()
    loads = ScoopingLoads(rope_tension=args.tension, resistance=args.resistance)
    result = PaperModel(geometry, loads).simulate(geometry.open_angle, 0.0, 3.0, 1e-3)
    closed = result["X"][-1, 2] >= 0
    print(f"jaw {'closed' if closed else 'still open'} after {result['t'][-1]:.3f} s "
          f"(jaw angle {np.degrees(result['X'][-1, 2]):.2f}°)")
    energy = result["kinetic"] + result["potential"]
    print(f"work of rope and resistance {result['work'][-1] / 1e3:.3f} kJ = change of kinetic + potential energy "
          f"{(energy[-1] - energy[0]) / 1e3:.3f} kJ")
    mech = mechatron.load("grab")
    sim = constrained.simulate(mech, assemble(mech, {"phi1": geometry.open_angle}), np.zeros(mech.nv),
                               result["t"][-1], 1e-3, loads_at=mechanism_loads(mech, loads),
                               stop=lambda t, q, v: q[1] >= 0.0)
    n = min(len(sim.t), len(result["t"]))
    print(f"Pinocchio model: largest difference of the jaw angle {np.abs(sim.q[:n, 1] - result['X'][:n, 2]).max():.1e}"
          f" rad, closure residual {sim.residual.max():.1e} m")
    print(f"wrote {plot_scooping(result, geometry, args.plot)}")


if __name__ == "__main__":
    main()

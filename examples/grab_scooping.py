"""Simulate a rod grab scooping [Mikhailov]: the closing rope pulls the jaws shut against the material's resistance.

    python examples/grab_scooping.py [--tension 20000] [--resistance 15000] [--plot grab.png] [--grab my_grab.toml]

The half grab is the mechanism file robots/grab.toml (or your own, written by mechatron.machines.grab.write_grab with
another geometry): a Pinocchio tree closed by a pin and a point-on-curve constraint. The simulation starts with the
jaw open (at the lower limit of its angle phi1), integrates with RK4 on the configuration manifold and keeps the
closures. The work of the rope and the resistance equals the change
of kinetic plus potential energy (the test suite also checks it against the paper's own 13-unknown formulation).
"""

from __future__ import annotations

import argparse

import numpy as np

import mechatron
from mechatron.dynamics import constrained
from mechatron.io.output import save_figure
from mechatron.kinematics.loops import assemble
from mechatron.machines.grab import ScoopingLoads, mechanism_loads, plot_scooping, scooping_forces


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tension", type=float, default=20e3, help="closing rope tension (N)")
    parser.add_argument("--resistance", type=float, default=15e3, help="cutting resistance on one jaw (N)")
    parser.add_argument("--plot", default="grab_scooping.png")
    parser.add_argument("--grab", default="grab", help="the grab's mechanism file (default: the shipped one)")
    args = parser.parse_args()

    loads = ScoopingLoads(rope_tension=args.tension, resistance=args.resistance)
    mech = mechatron.load(args.grab)
    jaw = mech.model.joints[mech.joint_id("phi1")].idx_q
    opened = mech.model.lowerPositionLimit[jaw]
    sim = constrained.simulate(mech, assemble(mech, {"phi1": opened}), np.zeros(mech.nv), 3.0, 2e-3,
                               loads_at=mechanism_loads(mech, loads), stop=lambda t, q, v: q[jaw] >= 0.0)
    closed = sim.q[-1, jaw] >= 0
    print(f"jaw {'closed' if closed else 'still open'} after {sim.t[-1]:.3f} s "
          f"(jaw angle {np.degrees(sim.q[-1, jaw]):.2f}°, closure residual {sim.residual.max():.1e} m)")
    print(f"work of rope and resistance {sim.work[-1] / 1e3:.3f} kJ = change of kinetic + potential energy "
          f"{(sim.energy[-1] - sim.energy[0]) / 1e3:.3f} kJ")
    forces = scooping_forces(mech, sim, loads)
    print("largest pin forces (kN): " + ", ".join(f"{name.replace('_', ' ')} {values.max() / 1e3:.1f}"
                                                  for name, values in forces.items()))
    figure = plot_scooping(mech, sim, loads)
    save_figure(figure, args.plot, dpi=figure.dpi)  # whole or not at all
    print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()

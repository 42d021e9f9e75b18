"""Size the six drives of a PUMA 560 doing a pick-and-place cycle with a 2.5 kg part, from the example catalogs.

    python examples/puma_pick_and_place.py [--objective mass] [--charts DIR] [--csv FILE]

Builds the task in Python (the same cycle and part as robots/tasks/puma560.toml: a 100 × 60 × 55 mm steel block,
its inertia that of a uniform box), sizes every joint for the chosen objective — the chosen motors and gearboxes
sit on the links that carry them, and the sizing repeats until the choice no longer changes — prints the report,
then compares the objectives: mass, cost, margin and the fastest cycle the catalogs allow (its moves faster, its
dwells as long).
"""

from __future__ import annotations

import argparse

import numpy as np

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.dynamics.motion import cycle
from mechatron.dynamics.task import Task
from mechatron.model.payload import with_payload

ABOVE_PICK = [-40, 40, -170, 0, 40, -40]
PICK = [-40, 52, -162, 0, 20, -40]
ABOVE_PLACE = [50, 40, -170, 0, 40, 50]
PLACE = [50, 52, -162, 0, 20, 50]
PART = 2.5, (0.100, 0.060, 0.055)  # kg; its edges along the tool's x, y, z (m)


def box_inertia(mass: float, edges: tuple[float, float, float]) -> np.ndarray:
    """The inertia tensor (kg·m²) of a uniform box about its centre: I_xx = m (b² + c²)/12, … ."""
    a, b, c = edges
    return mass / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objective", default="mass", choices=["mass", "cost", "margin", "time"])
    parser.add_argument("--charts", help="directory for the speed-torque charts")
    parser.add_argument("--csv", help="write every check of every joint")
    args = parser.parse_args()

    puma = with_payload(mechatron.load("puma560"), PART[0], com=(0.0, 0.0, 0.05), inertia=box_inertia(*PART))
    waypoints = np.radians([ABOVE_PICK, PICK, ABOVE_PICK, ABOVE_PLACE, PLACE, ABOVE_PLACE, ABOVE_PICK])
    motion = cycle(puma, waypoints, dwell=0.2, vmax=np.radians([90, 90, 90, 180, 180, 180]),
                   amax=np.radians([270, 270, 270, 540, 540, 540]), dt=0.005)
    task = Task("pick and place, 2.5 kg", puma, motion)
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    print(f"catalogs: {len(motors)} motors × {len(gearboxes) + 1} converters (direct drive included); "
          f"task: {task.duration:.2f} s, {len(motion)} samples\n")

    result = mechatron.size(puma, task, motors=motors, gearboxes=gearboxes, objective=args.objective)
    print(result)
    if args.csv:
        print(f"wrote {result.write_csv(args.csv)}")
    if args.charts:
        for path in result.save_plots(args.charts):
            print(f"wrote {path}")

    print("\nthe objectives side by side (motor + converter per joint; total mass and price):")
    for objective in ("mass", "cost", "margin", "time"):
        other = result if objective == args.objective else mechatron.size(puma, task, motors=motors,
                                                                          gearboxes=gearboxes, objective=objective)
        totals = other.totals()
        mass, price = totals["drive_mass_kg"], totals["drive_cost"]
        pace = f", cycle {other.duration:.2f} s" if objective == "time" else ""
        print(f"  {objective:<7} {mass:6.2f} kg {price:7.0f} EUR{pace}: "
              + "; ".join(f"{j.joint} {j.motor}+{j.converter}" for j in other.joints))


if __name__ == "__main__":
    main()

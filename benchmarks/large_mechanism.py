"""Loading a mechanism file of 1,000 points: a five-stage scissor lift whose arms carry their outlines
(mechatron.machines.scissor, 49 drawn points along each long edge of every arm: 1,002 points, 15 bodies), every drawn
point read off paper up to 1 mm off (seeded), the arms' lengths declared exact, so that the loops must be closed.

Reading the file, checking it, building the bodies' shapes and the Pinocchio tree and closing the loops in joint space
(a Gauss–Newton on the 15 bodies' coordinates, exact Jacobians) must take under 5 s; a drawing closed in the points'
coordinates with a dense finite-difference Jacobian (the earlier loader) took minutes. Also timed: the exact
derivatives of the model's placements with respect to every one of its 2,002 parameters, and a tolerance study's
sensitivities of the deck to all of them at one pose. Run: ``python benchmarks/large_mechanism.py``.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

TARGET_S = 5.0


def best(function, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main(stages: int = 5, edge_points: int = 49) -> None:
    import mechatron
    from mechatron.accuracy.sensitivity import sensitivities
    from mechatron.machines.scissor import ScissorLift, scissor_lift_spec
    from mechatron.model.derivatives import placement_derivatives
    from mechatron.model.linkage_file import write_linkage_file

    lift = ScissorLift(stages=stages, edge_points=edge_points)
    spec = scissor_lift_spec(lift)
    rng = np.random.default_rng(1)
    off = spec.with_positions({name: xy + rng.uniform(-1e-3, 1e-3, 2) for name, xy in spec.drawing().items()})
    with tempfile.TemporaryDirectory() as folder:
        path = write_linkage_file(off, Path(folder) / "lift.toml")
        points = len(spec.points)
        load = best(lambda: mechatron.load(path))
        mech = mechatron.load(path)
        derivatives = best(lambda: placement_derivatives(mechatron.load(path)), 1) - load
        tolerance = statistics.median(
            [best(lambda: sensitivities(mech, mech.reference_q, coordinates=[]), 1) for _ in range(3)])
    print(f"{points} points, {len(mech.parameters)} parameters, {mech.nq} joint coordinates; {mech.notes[-1][:60]}…")
    print(f"load (read, check, build, close): {load:.3f} s  (target < {TARGET_S:g} s: {load / TARGET_S:.3f} of it)")
    print(f"exact placement derivatives, all parameters: {derivatives:.3f} s")
    print(f"deck sensitivities to all parameters at one pose, the derivatives kept: {tolerance:.3f} s")
    if load >= TARGET_S:
        sys.exit(1)


if __name__ == "__main__":
    main()

"""Loading a mechanism file of 1,000 points: a five-stage scissor lift whose arms carry their outlines
(mechatron.machines.scissor, 49 drawn points along each long edge of every arm: 1,002 points, 15 bodies).

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
    from mechatron.machines.scissor import ScissorLift, scissor_lift_spec, write_scissor_lift
    from mechatron.model.derivatives import placement_derivatives

    lift = ScissorLift(stages=stages, edge_points=edge_points)
    with tempfile.TemporaryDirectory() as folder:
        path = write_scissor_lift(Path(folder) / "lift.toml", lift)
        points = len(scissor_lift_spec(lift).points)
        load = best(lambda: mechatron.load(path))
        mech = mechatron.load(path)
        derivatives = best(lambda: placement_derivatives(mechatron.load(path)), 1) - load
        tolerance = statistics.median(
            [best(lambda: sensitivities(mech, mech.reference_q, coordinates=[]), 1) for _ in range(3)])
    print(f"{points} points, {len(mech.parameters)} parameters, {mech.nq} joint coordinates")
    print(f"load (read, check, build, close): {load:.3f} s  (target < {TARGET_S:g} s: {load / TARGET_S:.3f} of it)")
    print(f"exact placement derivatives, all parameters: {derivatives:.3f} s")
    print(f"deck sensitivities to all parameters at one pose, the derivatives kept: {tolerance:.3f} s")
    if load >= TARGET_S:
        sys.exit(1)


if __name__ == "__main__":
    main()

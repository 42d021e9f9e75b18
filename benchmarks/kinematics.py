"""Batch forward kinematics plus Jacobian over 10,000 configurations, against a bare loop of the same Pinocchio calls.

mechatron's ``fk_and_jacobian`` returns the tool position, rotation and 6×n Jacobian of every configuration in arrays.
The baseline is the loop a user would write with Pinocchio alone: ``computeFrameJacobian`` per configuration, keeping
the same three results. Goal: ratio at most 1.3. For reference the last column compares with the Pinocchio calls
alone, results thrown away.

    python benchmarks/kinematics.py [--samples N] [--repeats R]
"""

from __future__ import annotations

import argparse

import numpy as np
import pinocchio as pin
from timing import best_time

import mechatron


def bare_loop(model: pin.Model, data: pin.Data, Q: np.ndarray, frame_id: int):
    positions, rotations, jacobians = [], [], []
    for q in Q:
        jacobians.append(pin.computeFrameJacobian(model, data, q, frame_id, pin.LOCAL_WORLD_ALIGNED))
        placement = data.oMf[frame_id]
        positions.append(placement.translation.copy())
        rotations.append(placement.rotation.copy())
    return np.array(positions), np.array(rotations), np.array(jacobians)


def calls_only(model: pin.Model, data: pin.Data, Q: np.ndarray, frame_id: int) -> None:
    """The Pinocchio calls alone, results thrown away: the floor no Python code can beat."""
    for q in Q:
        pin.computeFrameJacobian(model, data, q, frame_id, pin.LOCAL_WORLD_ALIGNED)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"batch FK + Jacobian of the tool frame, {args.samples} configurations, best of {args.repeats}")
    print(f"{'robot':<10} {'bare loop (ms)':>15} {'mechatron (ms)':>15} {'ratio':>7}  {'goal <= 1.30':<14}"
          f"{'calls only (ms)':>16} {'ratio':>7}")
    for name in ("puma560", "ur5"):
        mech = mechatron.load(name)
        Q = mech.random_configuration(rng, size=args.samples)
        fid = mech.frame_id("tool")
        model, data = mech.model, mech.model.createData()
        ours = mechatron.kinematics.fk_and_jacobian(mech, Q)
        theirs = bare_loop(model, data, Q, fid)
        for a, b in zip(ours, theirs):
            assert np.allclose(a, b, atol=1e-12), "results differ"
        t_bare = best_time(lambda: bare_loop(model, data, Q, fid), args.repeats)
        t_ours = best_time(lambda: mechatron.kinematics.fk_and_jacobian(mech, Q), args.repeats)
        t_floor = best_time(lambda: calls_only(model, data, Q, fid), args.repeats)
        verdict = "ok" if t_ours / t_bare <= 1.3 else "SLOWER"
        print(f"{name:<10} {t_bare * 1e3:>15.1f} {t_ours * 1e3:>15.1f} {t_ours / t_bare:>7.2f}  {verdict:<14}"
              f"{t_floor * 1e3:>16.1f} {t_ours / t_floor:>7.2f}")


if __name__ == "__main__":
    main()

"""Batch forward kinematics plus Jacobian of the tool frame (PUMA 560, UR5) at N = 1, 64, 1,000 and 10,000.

mechatron's ``fk_and_jacobian`` returns the tool position, rotation and 6×nv LOCAL_WORLD_ALIGNED Jacobian of every
configuration in arrays (argument checks included). It is timed against:

- **plain loop** — what a competent Pinocchio user writes: a Python loop calling ``computeFrameJacobian`` (which
  also updates the frame's placement) on one preallocated ``Data``, writing position, rotation and Jacobian into
  preallocated arrays. Goal: mechatron at most 1.3x.
- **calls only** — the same Pinocchio calls with the results thrown away: the floor of any loop over Pinocchio
  from Python. The wheel has no compiled batch forward kinematics (its parallel API covers RNEA, ABA and
  collisions only), so there is no compiled floor.
- **NumPy batch** — mechatron's batched evaluator (:class:`mechatron.model.batched.BatchedFrames`: the joint
  recursion in Python, the samples in NumPy), checked against Pinocchio to 1e-12 here: what vectorizing over the
  samples gives instead of calling Pinocchio per sample.

Times are per configuration, best of ``--repeats``; the candidates take turns within each repeat, each looping
over its call until ~20,000 configurations are done.

    python benchmarks/kinematics.py [--sizes 1 64 1000 10000] [--repeats R]
"""

from __future__ import annotations

import argparse

import numpy as np
import pinocchio as pin
from timing import interleaved

import mechatron
from mechatron.model.batched import batched_frames


def plain_loop(model: pin.Model, data: pin.Data, Q: np.ndarray, frame_id: int, out):
    """Preallocated positions (N, 3), rotations (N, 3, 3) and Jacobians (N, 6, nv), filled per configuration."""
    positions, rotations, jacobians = out
    placement = data.oMf[frame_id]
    for i in range(len(Q)):
        jacobians[i] = pin.computeFrameJacobian(model, data, Q[i], frame_id, pin.LOCAL_WORLD_ALIGNED)
        positions[i] = placement.translation
        rotations[i] = placement.rotation
    return out


def calls_only(model: pin.Model, data: pin.Data, Q: np.ndarray, frame_id: int) -> None:
    """The Pinocchio calls alone, results thrown away: the floor no Python loop can beat."""
    for q in Q:
        pin.computeFrameJacobian(model, data, q, frame_id, pin.LOCAL_WORLD_ALIGNED)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 64, 1_000, 10_000])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"FK + Jacobian of the tool frame, µs per configuration, best of {args.repeats}")
    print(f"{'robot':<9}{'N':>7}{'plain':>9}{'ours':>9}{'ratio':>7} {'<=1.3':<7}{'calls':>9}{'/calls':>7}"
          f"{'NumPy':>9}{'/plain':>7}")
    for name in ("puma560", "ur5"):
        mech = mechatron.load(name)
        fid = mech.frame_id("tool")
        model, data = mech.model, mech.model.createData()
        numpy_batch = batched_frames(model, [fid])
        for n in args.sizes:
            Q = mech.random_configuration(np.random.default_rng(n), size=n)
            out = (np.empty((n, 3)), np.empty((n, 3, 3)), np.empty((n, 6, mech.nv)))
            ours = mechatron.kinematics.fk_and_jacobian(mech, Q)
            for a, b in zip(ours, plain_loop(model, data, Q, fid, out)):
                assert np.array_equal(a, b), "results differ"
            batch = numpy_batch.placements(Q)
            assert np.allclose(batch.position[:, 0], ours[0], rtol=0, atol=1e-12)
            assert np.allclose(batch.rotation[:, 0], ours[1], rtol=0, atol=1e-12)
            assert np.allclose(batch.jacobian[:, 0], ours[2], rtol=0, atol=1e-12)
            t = interleaved({"plain": lambda: plain_loop(model, data, Q, fid, out),
                                   "ours": lambda: mechatron.kinematics.fk_and_jacobian(mech, Q),
                                   "calls": lambda: calls_only(model, data, Q, fid),
                                   "numpy": lambda: numpy_batch.placements(Q)}, n, args.repeats)
            t_plain, t_ours, t_calls, t_numpy = t["plain"], t["ours"], t["calls"], t["numpy"]
            verdict = "ok" if t_ours / t_plain <= 1.3 else "SLOWER"
            print(f"{name:<9}{n:>7}{t_plain * 1e6:>9.2f}{t_ours * 1e6:>9.2f}{t_ours / t_plain:>7.2f} {verdict:<7}"
                  f"{t_calls * 1e6:>9.2f}{t_ours / t_calls:>7.2f}{t_numpy * 1e6:>9.2f}{t_numpy / t_plain:>7.2f}")


if __name__ == "__main__":
    main()

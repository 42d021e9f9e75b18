"""Joint reactions of closed loops (``mechatron dynamics … --reactions``) at once against state by state.

On a motion of about 2,000 samples of each shipped closed loop (its generic task, resampled), with a load at the
tool where it has one, two figures side by side, each a ratio of median CPU times (``time.process_time``,
interleaved repeats, ``timing.cpu_medians``), warm (the loop solver, its kernels and the batched frames built):

- **reactions** — the reactions from the joint states: ``mechatron.dynamics.batched_reactions.reactions_at`` (the
  multipliers and every joint's wrench for all samples in NumPy) against the state-by-state loop that
  ``joint_reactions`` ran before (kept below as the baseline: per sample the constrained inverse dynamics, then one
  Pinocchio RNEA pass with the closure forces as external forces). Goal ≥ 5×.
- **command** — the whole analysis, ``joint_reactions`` (the loops' position, velocity and acceleration analysis
  included, the same in both) against that analysis followed by the baseline loop.

The largest difference of the two paths (relative to the largest value) is printed too: rounding.

    python benchmarks/reactions.py [--repeats R] [--samples N]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from timing import cpu_medians

import mechatron
from mechatron.dynamics import constrained as cd
from mechatron.dynamics.batched_reactions import reactions_at
from mechatron.dynamics.joint_reactions import joint_reactions
from mechatron.dynamics.task import generic_task
from mechatron.dynamics.trajectory import closed_loop_states

ROOT = Path(__file__).resolve().parents[1]
MECHANISMS = {  # name: loads (world force N, moment N·m at a frame)
    "crank_slider": [("C@slider", [1000.0, 0.0, 0.0])],
    "six_bar_bucket": [("K", [2000.0, -5000.0, 0.0])],
    str(ROOT / "examples" / "data" / "scissor_lift.toml"): None,
    "front_shovel": [("K", [1.0e4, -2.0e4, 0.0])],
}


def state_by_state(mech, Q, V, A, loads):
    """The baseline: what ``joint_reactions`` ran per sample before (wrenches (N, njoints − 1, 6), pins)."""
    states = [cd.reactions(mech, q, v, a, cd.inverse(mech, q, v, a, loads)[1], loads) for q, v, a in zip(Q, V, A)]
    wrenches = np.array([s.joints for s in states])
    return wrenches, {name: np.array([s.pins[name] for s in states]) for name in states[0].pins}


def motion(mech, samples: int):
    """The mechanism's generic task resampled to about ``samples`` samples."""
    duration = float(generic_task(mech).trajectory.t[-1])
    return generic_task(mech, dt=duration / (samples - 1)).trajectory


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--samples", type=int, default=2000)
    args = parser.parse_args()
    print(f"{'mechanism':<16}{'samples':>8}{'state by state':>16}{'at once':>10}{'ratio':>8}"
          f"{'command old':>13}{'command':>9}{'ratio':>8}{'largest diff':>14}")
    for name, loads in MECHANISMS.items():
        mech = mechatron.load(name)
        trajectory = motion(mech, args.samples)
        Q, V, A = closed_loop_states(mech, trajectory)
        new = reactions_at(mech, Q, V, A, loads)  # warm: the batched frames built
        assert new is not None
        old = state_by_state(mech, Q, V, A, loads)
        scale = np.abs(old[0]).max()
        diff = max(np.abs(new[0] - old[0]).max() / scale,
                   *(np.abs(new[1][k] - v).max() / np.abs(v).max() for k, v in old[1].items()))
        times = cpu_medians({
            "old": lambda: state_by_state(mech, Q, V, A, loads),
            "new": lambda: reactions_at(mech, Q, V, A, loads),
            "command old": lambda: state_by_state(mech, *closed_loop_states(mech, trajectory), loads),
            "command": lambda: joint_reactions(mech, trajectory, loads),
        }, args.repeats)
        print(f"{Path(name).stem:<16}{len(Q):>8}{times['old']:>14.3f} s{times['new']:>8.3f} s"
              f"{times['old'] / times['new']:>7.1f}x{times['command old']:>11.3f} s{times['command']:>7.3f} s"
              f"{times['command old'] / times['command']:>7.1f}x{diff:>14.1e}")


if __name__ == "__main__":
    main()

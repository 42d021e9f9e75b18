"""Inverse dynamics over a 10,000-sample trajectory of the PUMA 560 and the UR5.

mechatron's batch ``inverse_dynamics`` (RNEA with the drives' reflected inertia; Pinocchio's parallel RNEA over
the batch) against a bare loop of ``pinocchio.rnea`` on the same arrays (goal: at most 1.3x) and against the
Robotics Toolbox for Python's DH dynamics (``DHRobot.rne`` of its Puma560 and UR5 models) on the same trajectory
(goal: mechatron at least 10x faster). The toolbox is timed two ways: called per state, as its Python API is used
in a loop over a trajectory, and with the whole (N, 6) arrays at once, which runs its C loop over the samples.

It also times a closed-loop simulation (``mechatron.dynamics.constrained.simulate``: KKT system, RK4 on the
configuration manifold, projection onto the closures) of the crank-slider, per integration step.

    python benchmarks/dynamics.py [--samples N] [--repeats R]
"""

from __future__ import annotations

import argparse

import numpy as np
import pinocchio as pin
from timing import best_time

import mechatron
from mechatron.dynamics.constrained import simulate
from mechatron.dynamics.tree import inverse_dynamics
from mechatron.kinematics.loops import assemble, joint_velocity


def bare_loop(model: pin.Model, data: pin.Data, Q: np.ndarray, V: np.ndarray, A: np.ndarray) -> np.ndarray:
    return np.array([pin.rnea(model, data, q, v, a) for q, v, a in zip(Q, V, A)])


def trajectory(mech: mechatron.Mechanism, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A smooth multi-joint motion: q = q0 + A sin(ωt), sampled at n points."""
    t = np.linspace(0.0, 10.0, n)[:, None]
    rng = np.random.default_rng(0)
    amplitude, omega = rng.uniform(0.2, 0.8, mech.nq), rng.uniform(0.5, 2.0, mech.nq)
    Q = 0.5 * (mech.model.lowerPositionLimit.clip(-3, 3) + mech.model.upperPositionLimit.clip(-3, 3)) \
        + amplitude * np.sin(omega * t)
    return Q, amplitude * omega * np.cos(omega * t), -amplitude * omega**2 * np.sin(omega * t)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    try:
        import roboticstoolbox as rtb

        toolbox = {"puma560": rtb.models.DH.Puma560(), "ur5": rtb.models.DH.UR5()}
    except ImportError:
        toolbox = {}
        print("(roboticstoolbox-python is not installed: pip install '.[test]' for the comparison)")
    print(f"inverse dynamics along a {args.samples}-sample trajectory, best of {args.repeats}")
    print(f"{'robot':<9}{'bare rnea loop':>16}{'mechatron':>12}{'ratio':>8}  goal<=1.3"
          f"{'RTB per state':>15}{'speed-up':>10}  goal>=10{'RTB arrays':>13}{'speed-up':>10}")
    for name in ("puma560", "ur5"):
        mech = mechatron.load(name)
        Q, V, A = trajectory(mech, args.samples)
        data = mech.model.createData()
        assert np.allclose(inverse_dynamics(mech, Q, V, A), bare_loop(mech.model, data, Q, V, A), atol=1e-9)
        t_bare = best_time(lambda: bare_loop(mech.model, data, Q, V, A), args.repeats)
        t_ours = best_time(lambda: inverse_dynamics(mech, Q, V, A), args.repeats)
        line = (f"{name:<9}{t_bare * 1e3:>13.1f} ms{t_ours * 1e3:>9.1f} ms{t_ours / t_bare:>8.2f}  "
                f"{'ok' if t_ours / t_bare <= 1.3 else 'SLOWER':<9}")
        if name in toolbox:
            robot = toolbox[name]
            t_state = best_time(lambda: [robot.rne(q, v, a) for q, v, a in zip(Q, V, A)], 1)
            t_arrays = best_time(lambda: robot.rne(Q, V, A), args.repeats)
            line += (f"{t_state * 1e3:>12.1f} ms{t_state / t_ours:>9.1f}x  "
                     f"{'ok' if t_state / t_ours >= 10 else 'SLOWER':<7}"
                     f"{t_arrays * 1e3:>10.1f} ms{t_arrays / t_ours:>9.1f}x")
        print(line)
    crank = mechatron.load("crank_slider")
    q0 = assemble(crank, {"q1": 0.2})
    v0 = joint_velocity(crank, q0, {"q1": 8.0})
    steps = 1000
    t_sim = best_time(lambda: simulate(crank, q0, v0, steps * 1e-3, 1e-3), args.repeats)
    print(f"simulate crank_slider, {steps} RK4 steps: {t_sim * 1e3:.0f} ms ({t_sim / steps * 1e6:.0f} µs per step)")


if __name__ == "__main__":
    main()

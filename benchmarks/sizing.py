"""Drive sizing of a 6-axis arm: every motor × converter of the example catalogs against a 2,000-sample cycle.

``mechatron.size`` (the dynamics, then all checks of all pairs of every joint as array operations
over the decisive samples) against a baseline written the way a sizing script usually is: a loop over the pairs,
each checked with NumPy over all samples. The baseline runs on a slice of the pairs and is scaled to all of them;
both must agree on every pair of the slice. Goal: the whole sizing under 1 s.

    python benchmarks/sizing.py [--samples N] [--repeats R] [--baseline-motors M]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from timing import best_time

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.checks import evaluate
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import joint_duties
from mechatron.drives.motor import continuous_torque, peak_torque_limit
from mechatron.dynamics.motion import Trajectory
from mechatron.model.payload import with_payload


def cycle(mech: mechatron.Mechanism, n: int) -> Trajectory:
    """q = q0 + A sin(ωt) over 10 s, n samples."""
    t = np.linspace(0.0, 10.0, n)
    rng = np.random.default_rng(1)
    amplitude, omega = rng.uniform(0.3, 0.9, mech.nq), rng.uniform(0.6, 1.8, mech.nq)
    middle = 0.5 * (mech.model.lowerPositionLimit.clip(-3, 3) + mech.model.upperPositionLimit.clip(-3, 3))
    s, c = np.sin(np.outer(t, omega)), np.cos(np.outer(t, omega))
    return Trajectory(t, middle + amplitude * s, amplitude * omega * c, -amplitude * omega**2 * s, mech.joint_names)


def baseline_worst(duty, motor, conv, c) -> float:
    """The largest value/limit of the checks of one motor × converter pair, straightforwardly."""
    u, eta, Jc = conv.ratio[c], conv.efficiency[c], conv.inertia[c]
    w = duty.time_weights()
    speed, torque = u * duty.speed, np.where(duty.torque * duty.speed >= 0, duty.torque / (u * eta),
                                             duty.torque * eta / u)
    motor_torque = (motor["rotor_inertia"] + Jc) * u * duty.acceleration + torque
    available = peak_torque_limit(speed, motor["peak_torque"], motor["rated_torque"], motor["rated_speed"],
                                  motor["max_speed"])
    mean_speed = float(np.abs(speed) @ w)
    motion = np.abs(duty.speed) * w
    ratios = [
        np.abs(motor_torque).max() / motor["peak_torque"],
        (np.abs(motor_torque) / available).max(),
        np.sqrt(motor_torque**2 @ w) / continuous_torque(mean_speed, motor["rated_torque"], motor["rated_speed"],
                                                         motor["max_speed"]),
        np.abs(speed).max() / motor["max_speed"],
        (duty.load_inertia / u**2 + Jc) / motor["rotor_inertia"] / 10.0,
        (motion @ np.abs(duty.torque) ** 3 / motion.sum()) ** (1 / 3) / conv.rated_torque[c],
        np.abs(duty.torque).max() / conv.peak_torque[c],
        motor["peak_torque"] * u / conv.emergency_torque[c],
        np.abs(speed).max() / conv.max_input_speed[c],
        mean_speed / conv.rated_input_speed[c],
    ]
    return float(max(ratios))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--baseline-motors", type=int, default=8, help="motors in the baseline's slice")
    args = parser.parse_args()

    puma = with_payload(mechatron.load("puma560"), 2.5)
    trajectory = cycle(puma, args.samples)
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    pairs = 6 * len(motors) * (len(gearboxes) + 1)
    print(f"PUMA 560, 6 joints × {len(motors)} motors × {len(gearboxes) + 1} converters = {pairs} pairs, "
          f"{args.samples}-sample cycle; best of {args.repeats}")

    t_dynamics = best_time(lambda: joint_duties(puma, trajectory), args.repeats)
    t_total = best_time(lambda: mechatron.size(puma, trajectory, motors=motors, gearboxes=gearboxes), args.repeats)

    duties = joint_duties(puma, trajectory)
    slice_motors = motors.iloc[:: max(1, len(motors) // args.baseline_motors)].reset_index(drop=True)
    start = time.perf_counter()
    checked = 0
    for duty in duties:
        conv = converters_for(duty, gearboxes)
        ours = evaluate(duty, slice_motors, conv).load_factors().max(axis=2)
        for m, motor in slice_motors.iterrows():
            for c in range(len(conv)):
                value = baseline_worst(duty, motor, conv, c)
                assert np.isclose(value, ours[m, c], rtol=1e-9) or (np.isinf(value) and np.isinf(ours[m, c])), \
                    (duty.name, motor["key"], conv.key[c], value, ours[m, c])
                checked += 1
    t_slice = time.perf_counter() - start
    t_baseline = t_slice * pairs / checked

    print(f"{'':<28}{'time':>10}")
    print(f"{'dynamics (6 joints)':<28}{t_dynamics * 1e3:>7.1f} ms")
    print(f"{'mechatron, dynamics + sizing':<28}{t_total * 1e3:>7.1f} ms   goal < 1000 ms: "
          f"{'ok' if t_total < 1.0 else 'SLOWER'}")
    print(f"{'baseline loop over pairs':<28}{t_baseline * 1e3:>7.0f} ms   (scaled from {checked} pairs in "
          f"{t_slice:.2f} s; agrees on all of them)")
    print(f"{'ratio mechatron / baseline':<28}{t_total / t_baseline:>10.4f}   ({t_baseline / t_total:.0f}x faster)")


if __name__ == "__main__":
    main()

"""Drive sizing of the PUMA 560 on its example task, with the example catalogs and with a catalog ten times larger.

``mechatron`` evaluates the motor × converter pairs a chunk at a time (:class:`mechatron.drives.checks.PairChecks`):
closed-form bounds screen the pairs, a few decisive samples bound the per-sample checks, and only the pairs that
can still win are checked over every sample that can decide them; the pairs are visited in the objective's order
and the work stops at the best feasible ones.

The baseline is what a competent user writes: every pair checked, vectorized with NumPy — per joint, the motor-side
speed and torque of every converter at every sample as (converters × samples) arrays, then for each motor every
check of that motor with every converter at once (a loop over motors only, not a per-pair ``iterrows`` loop) — and
the lightest feasible pair chosen. Both size the same six duties (one pass, no drive masses) and must choose the same
pairs. With the 10× catalog the baseline runs on a slice of the motors and is scaled to all of them.

The 10× catalog scales the example one: each motor and gearbox in ten variants (torques, inertia, ratio, mass and
price × a factor in 0.9–1.1), 1,120 motors × 991 converters = 1.1 million pairs per joint. Printed: the times, their
ratios, the full ``mechatron.size`` (dynamics and the drives' masses to the fixed point) with each catalog — goal
< 2 s with the 10× one — and its peak memory (tracemalloc, a separate run: tracing slows it), and the ``time``
objective with the 10× catalog.

    python benchmarks/sizing.py [--repeats R] [--baseline-motors M]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np
import pandas as pd
from timing import best_time, best_time_and_result

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import joint_duties
from mechatron.drives.motor import continuous_torque, electrical_data, peak_torque_limit
from mechatron.drives.sizing import size_joint
from mechatron.dynamics.task import default_task

MOTOR_COLUMNS = ["rated_torque", "peak_torque", "rotor_inertia", "mass", "price"]
GEARBOX_COLUMNS = ["ratio", "rated_torque", "peak_torque", "mass", "price"]


def larger(catalog: pd.DataFrame, times: int, columns: list[str], seed: int) -> pd.DataFrame:
    """The catalog in ``times`` variants: itself, then copies with ``columns`` × U(0.9, 1.1) and keys ``~k``."""
    rng = np.random.default_rng(seed)
    variants = [catalog]
    for k in range(1, times):
        variant = catalog.copy()
        variant["key"] = variant["key"] + f"~{k}"
        variant[columns] = variant[columns] * rng.uniform(0.9, 1.1, (len(catalog), len(columns)))
        variants.append(variant)
    return pd.concat(variants, ignore_index=True)


def baseline_joint(duty, motors: pd.DataFrame, conv, inertia_ratio_max: float = 10.0) -> tuple[int, int]:
    """The lightest pair (then the cheapest) that passes every check, every pair evaluated with NumPy: (m, c);
    (-1, -1) when none passes."""
    w = duty.time_weights()
    u, eta, Jc = conv.ratio[:, None], conv.efficiency[:, None], conv.inertia[:, None]
    n = u * duty.speed
    accel = u * duty.acceleration
    base = Jc * accel + np.where(duty.torque * duty.speed >= 0, duty.torque / (u * eta), duty.torque * eta / u)
    speed = np.abs(n)
    top, mean = speed.max(axis=1), speed @ w
    motion = np.abs(duty.speed) * w if np.abs(duty.speed).any() else w
    equivalent = (motion @ np.abs(duty.torque) ** 3 / motion.sum()) ** (1 / 3)
    converter_ok = (equivalent <= conv.rated_torque) & (np.abs(duty.torque).max() <= conv.peak_torque) \
        & (top <= conv.max_input_speed) & (mean <= conv.rated_input_speed)
    kt, resistance, voltage = electrical_data(motors)
    tolerance = 1 + 1e-9
    ok = np.zeros((len(motors), len(conv)), dtype=bool)
    for m, motor in enumerate(motors[["rotor_inertia", "peak_torque", "rated_torque", "rated_speed",
                                      "max_speed"]].to_numpy()):
        Jm, peak, rated, rated_speed, max_speed = motor
        torque = np.abs(Jm * accel + base)
        checks = [torque.max(axis=1) <= peak * tolerance,
                  (torque <= peak_torque_limit(n, peak, rated, rated_speed, max_speed) * tolerance).all(axis=1),
                  np.sqrt(torque**2 @ w) <= continuous_torque(mean, rated, rated_speed, max_speed) * tolerance,
                  top <= max_speed * tolerance,
                  (duty.load_inertia / conv.ratio**2 + conv.inertia) / Jm <= inertia_ratio_max * tolerance,
                  peak * conv.ratio <= conv.emergency_torque * tolerance, converter_ok]
        if np.isfinite(voltage[m]):
            checks.append((kt[m] * speed + resistance[m] / kt[m] * torque).max(axis=1) <= voltage[m] * tolerance)
        ok[m] = np.logical_and.reduce(checks)
    mass = motors["mass"].fillna(0).to_numpy()[:, None] + conv.mass[None, :]
    price = motors["price"].fillna(0).to_numpy()[:, None] + conv.price[None, :]
    m, c = np.nonzero(ok)
    if len(m) == 0:
        return -1, -1
    best = np.lexsort((price[m, c], mass[m, c]))[0]
    return int(m[best]), int(c[best])


def peak_memory(function) -> tuple[float, float]:
    """(wall time in s, peak traced memory in MB) of one run of ``function()``."""
    tracemalloc.start()
    start = time.perf_counter()
    function()
    elapsed = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return elapsed, peak / 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--baseline-motors", type=int, default=112, help="motors in the 10x baseline's slice")
    parser.add_argument("--skip-time", action="store_true", help="leave out the time objective (10x)")
    args = parser.parse_args()

    puma = mechatron.load("puma560")
    task = default_task(puma)
    duties = joint_duties(task.mechanism, task.trajectory, task.loads)
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    catalogs = {"1x": (motors, gearboxes),
                "10x": (larger(motors, 10, MOTOR_COLUMNS, 1), larger(gearboxes, 10, GEARBOX_COLUMNS, 2))}
    print(f"PUMA 560, task '{task.name}' ({len(task.trajectory.t)} samples), 6 joints; best of {args.repeats}")
    print(f"{'catalog':<8}{'pairs/joint':>12}{'mechatron':>12}{'baseline':>12}{'ratio':>9}   agree")
    for name, (mot, gear) in catalogs.items():
        pairs = len(mot) * (len(gear) + 1)
        t_ours, ours = best_time_and_result(lambda: [size_joint(d, mot, gear) for d in duties], args.repeats)
        sliced = mot if name == "1x" else mot.iloc[:: max(1, len(mot) // args.baseline_motors)]
        sliced = sliced.reset_index(drop=True)
        start = time.perf_counter()
        theirs = [baseline_joint(d, sliced, converters_for(d, gear)) for d in duties]
        t_base = (time.perf_counter() - start) * len(mot) / len(sliced)
        agree = all((j.motor, j.converter) == (sliced["key"].iloc[m], converters_for(d, gear).key[c])
                    for j, d, (m, c) in zip(ours, duties, theirs)) if name == "1x" else "slice"
        print(f"{name:<8}{pairs:>12,}{t_ours * 1e3:>9.0f} ms{t_base * 1e3:>9.0f} ms{t_ours / t_base:>9.4f}   {agree}"
              + ("" if name == "1x" else f" (baseline on {len(sliced)} motors, scaled)"))

    print(f"\n{'mechatron.size (dynamics, fixed point)':<44}{'time':>9}{'peak memory':>14}")
    for name, (mot, gear) in catalogs.items():
        t_size = best_time(lambda: mechatron.size(puma, motors=mot, gearboxes=gear), args.repeats)
        _, memory = peak_memory(lambda: mechatron.size(puma, motors=mot, gearboxes=gear))
        goal = f"   goal < 2 s: {'ok' if t_size < 2 else 'SLOWER'}" if name == "10x" else ""
        print(f"{'  catalog ' + name + ', objective mass':<44}{t_size:>7.2f} s{memory:>11.1f} MB{goal}")
    if not args.skip_time:
        mot, gear = catalogs["10x"]
        t_time = best_time(lambda: mechatron.size(puma, motors=mot, gearboxes=gear, objective="time"), 1)
        print(f"{'  catalog 10x, objective time':<44}{t_time:>7.2f} s{'':>14}   (one run, memory not traced)")


if __name__ == "__main__":
    main()

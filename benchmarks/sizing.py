"""Drive sizing of the PUMA 560 against its lean floor: what a competent engineer writes with NumPy and Pinocchio.

The floor does the same work as ``mechatron.size`` and chooses the same drives: the same inverse dynamics, gravity
and mass matrix (mechatron's :func:`~mechatron.drives.duty.joint_duties`, Pinocchio's RNEA and CRBA); per joint, the
RMS motor torque and mean speed of every motor × converter pair at once from five time moments of the duty (the
motor torque T = (J_m + J_c) u ω̇ + τ*/u with τ* = τ/η where the load takes power, τη where it gives it back, so
⟨T²⟩ = (J u)² ⟨ω̇²⟩ + 2J(⟨ω̇τ₊⟩/η + ⟨ω̇τ₋⟩η) + (⟨τ₊²⟩/η² + ⟨τ₋²⟩η²)/u²), the pairs that pass those checks and the
gearbox's (its peak torque derated above its cycle rating) in mass order (then price) — for a motor with thermal data
its winding's mean rise in place of RMS —, the per-sample checks — peak torque, the speed–torque curve, the voltage
limit, then the winding's temperature over the repeated task (mechatron's two-node network,
:func:`~mechatron.drives.thermal.periodic_rise`) — only for them until one passes; the same distal-to-proximal
fixed point, the duties recomputed when the drives on the links change. Printed: both times (best of the repeats,
taking turns), their ratio (goal ≤ 2×), whether the drives agree, on the default task (1,115 samples) with and
without the fixed point, on the same cycle sampled finely to 20,000 and 100,000 rows (time linear in the task: the
100,000-row time within 10 % of 5× the 20,000-row one), and with a catalog ten times larger (each motor and gearbox
in ten variants). A closed loop: the scissor lift of examples/data (one hydraulic cylinder) sized along its generic
task sampled to about 5,000 rows, against the sweep of its loops (position, velocity and acceleration analysis,
:func:`mechatron.sweep`) at as many samples (goal ≤ 10×: the sizing's constrained inverse dynamics and cylinder
checks cost at most nine sweeps).

    python benchmarks/sizing.py [--repeats R] [--skip-long]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import DriveMount, drive_carrier, joint_duties, mount_drives
from mechatron.drives.motor import continuous_torque, electrical_data, peak_torque_limit
from mechatron.drives.system import distal_first
from mechatron.drives.thermal import DEFAULT_AMBIENT, REFERENCE, ThermalData, periodic_rise
from mechatron.dynamics.task import generic_task, read_task, task_file

TOLERANCE = 1 + 1e-9  # a check passes at value ≤ limit (1 + 1e-9), as mechatron's
MOTOR_COLUMNS = ["rated_torque", "peak_torque", "rotor_inertia", "mass", "price"]
GEARBOX_COLUMNS = ["ratio", "rated_torque", "peak_torque", "mass", "price"]


def floor_joint(duty, motors: pd.DataFrame, conv, inertia_ratio_max: float = 10.0) -> tuple[int, int]:
    """(motor, converter) indices of the lightest, then cheapest, pair passing every check; (−1, −1) if none."""
    w = duty.time_weights()
    a, om, tau = duty.acceleration, duty.speed, duty.torque
    power = tau * om >= 0
    tp, tn = np.where(power, tau, 0.0), np.where(power, 0.0, tau)
    a2, p1, n1, p2, n2 = w @ a**2, w @ (a * tp), w @ (a * tn), w @ tp**2, w @ tn**2
    u, eta, jc = conv.ratio, conv.efficiency, conv.inertia
    jm = motors["rotor_inertia"].to_numpy()
    j = jm[:, None] + jc[None, :]
    rms = np.sqrt(np.maximum((j * u) ** 2 * a2 + 2 * j * (p1 / eta + n1 * eta) + (p2 / eta**2 + n2 * eta**2) / u**2,
                             0.0))
    peak, rated = motors["peak_torque"].to_numpy()[:, None], motors["rated_torque"].to_numpy()[:, None]
    rated_speed, max_speed = motors["rated_speed"].to_numpy()[:, None], motors["max_speed"].to_numpy()[:, None]
    mean, top = u * (w @ np.abs(om)), u * np.abs(om).max()
    motion = np.abs(om) * w if np.abs(om).any() else w
    equivalent = (motion @ np.abs(tau) ** 3 / motion.sum()) ** (1 / 3)
    # the peak torque derated above the cycle rating: the task repeats every T s, (N_r T)^p with p = lg 2.5/lg 3000
    derating = np.minimum(1.0, (conv.cycle_rating * duty.duration) ** (np.log(2.5) / np.log(3000.0)))
    gearbox = (equivalent <= conv.rated_torque) & (np.abs(tau).max() <= conv.peak_torque * derating) \
        & (top <= conv.max_input_speed) & (mean <= conv.rated_input_speed)
    heat = ThermalData.of(motors)
    heated, allowed = heat.given[:, None], (heat.limit - DEFAULT_AMBIENT)[:, None]
    # the motors with thermal data: their winding's mean rise (R_wh + R_ha)(R(T_a) T_rms²/k_t² + T_f ⟨|n|⟩) bounds
    # its highest from below; the others: RMS against the S1 torque at the mean speed
    total = (heat.r_wh + heat.r_ha)[:, None]
    r_ambient = (heat.resistance * (1 + heat.alpha * (DEFAULT_AMBIENT - REFERENCE)))[:, None]
    mean_rise = total * (r_ambient * (rms / heat.kt[:, None]) ** 2 + heat.loss_torque[:, None] * mean)
    warm = np.where(heated, mean_rise <= allowed * TOLERANCE,
                    rms <= continuous_torque(mean, rated, rated_speed, max_speed) * TOLERANCE)
    ok = warm & (top <= max_speed * TOLERANCE) & gearbox \
        & ((duty.load_inertia / u**2 + jc) / jm[:, None] <= inertia_ratio_max * TOLERANCE) \
        & (peak * u <= conv.emergency_torque * TOLERANCE)
    mass = motors["mass"].fillna(0).to_numpy()[:, None] + conv.mass[None, :]
    price = motors["price"].fillna(0).to_numpy()[:, None] + conv.price[None, :]
    kt, resistance, voltage = electrical_data(motors)
    m, c = np.nonzero(ok)
    for k in np.lexsort((price[m, c], mass[m, c])):
        i, g = m[k], c[k]
        speed = u[g] * np.abs(om)
        torque = np.abs(j[i, g] * u[g] * a + np.where(power, tau / (u[g] * eta[g]), tau * eta[g] / u[g]))
        if torque.max() > peak[i, 0] * TOLERANCE or (torque > peak_torque_limit(
                speed, peak[i, 0], rated[i, 0], rated_speed[i, 0], max_speed[i, 0]) * TOLERANCE).any():
            continue
        if np.isfinite(voltage[i]) and (kt[i] * speed + resistance[i] / kt[i] * torque).max() > voltage[i] * TOLERANCE:
            continue
        if heated[i, 0]:  # the winding over the repeated task, every sample (the two-node network's steady state)
            rise = periodic_rise(duty.t, (torque / heat.kt[i])[None] ** 2, heat.loss_torque[i] * speed[None],
                                 heat.r_wh[i], heat.r_ha[i], heat.tau_w[i], heat.tau_h[i], heat.resistance[i],
                                 heat.alpha[i], DEFAULT_AMBIENT)[0, :, 0]
            if not rise.max() <= allowed[i, 0] * TOLERANCE:  # NaN: runaway
                continue
        return int(i), int(g)
    return -1, -1


def floor_size(mech, trajectory, motors: pd.DataFrame, gearboxes: pd.DataFrame, single_pass: bool = False
               ) -> dict[str, tuple[str, str]]:
    """joint → (motor key, converter key): a pass with weightless drives, then passes distal to proximal, each
    joint with the drives chosen so far on their links, until a pass chooses what the one before chose."""
    bare = {d.name: d for d in joint_duties(mech, trajectory) if np.abs(d.speed).max() or np.abs(d.torque).max()}
    order = distal_first(mech, list(bare))
    carriers = {n: drive_carrier(mech, n) for n in order}
    converters = {n: converters_for(bare[n], gearboxes) for n in order}
    motor_mass = motors["mass"].fillna(0).to_numpy()
    chosen: dict[str, tuple[str, str]] = {}
    masses: dict[str, float] = {}
    known: dict[tuple, dict] = {}

    def duties() -> dict:
        moving = [DriveMount(n, " + ".join(chosen[n]), masses[n], *carriers[n]) for n in chosen
                  if carriers[n][0] > 0 and masses[n] > 0]
        key = tuple(sorted((mount.joint, mount.drive) for mount in moving))
        if key and key not in known:
            known[key] = {d.name: d for d in joint_duties(mount_drives(mech, moving), trajectory) if d.name in bare}
        return known[key] if key else bare

    def one_pass(weighted: bool) -> tuple:
        for name in order:
            i, g = floor_joint(duties()[name] if weighted else bare[name], motors, converters[name])
            chosen[name] = (str(motors["key"].iloc[i]), str(converters[name].key[g]))
            masses[name] = float(motor_mass[i] + converters[name].mass[g])
        return tuple(chosen[n] for n in order)

    history = [one_pass(False)]
    while not single_pass:
        state = one_pass(True)
        if state == history[-1]:
            break
        history.append(state)
    return chosen


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


def task_with(mech, rows: int | None, folder: Path):
    """The PUMA's own task, or the same cycle sampled to about ``rows`` rows (a smaller time step)."""
    path = task_file(mech)
    if rows is None:
        return read_task(path, mech)
    text = path.read_text(encoding="utf-8")
    samples = len(read_task(path, mech).trajectory.t)
    fine = folder / f"puma560_{rows}.toml"
    fine.write_text(text.replace("dt = 0.005", f"dt = {0.005 * (samples - 1) / (rows - 1)!r}"), encoding="utf-8")
    return read_task(fine, mech)


def interleaved_best(functions: dict, repeats: int) -> tuple[dict, dict]:
    """Best time (s) and the last result of each function, the functions taking turns in every repeat."""
    best, results = dict.fromkeys(functions, float("inf")), {}
    for _ in range(repeats):
        for key, function in functions.items():
            start = time.perf_counter()
            results[key] = function()
            best[key] = min(best[key], time.perf_counter() - start)
    return best, results


def compare(label: str, task, motors, gearboxes, single_pass: bool, repeats: int) -> float:
    times, results = interleaved_best({
        "mechatron": lambda: {s.joint: (s.motor, s.converter) for s in mechatron.size(
            task.mechanism, task, motors=motors, gearboxes=gearboxes, single_pass=single_pass).joints},
        "floor": lambda: floor_size(task.mechanism, task.trajectory, motors, gearboxes, single_pass)}, repeats)
    ratio = times["mechatron"] / times["floor"]
    agree = results["mechatron"] == results["floor"]
    print(f"{label:<46}{times['mechatron'] * 1e3:>10.1f} ms{times['floor'] * 1e3:>10.1f} ms{ratio:>8.2f}x"
          f"   {'ok' if ratio <= 2 else 'over 2x'}   same drives: {agree}")
    return times["mechatron"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--skip-long", action="store_true", help="leave out the 20,000- and 100,000-row tasks")
    args = parser.parse_args()
    puma = mechatron.load("puma560")
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    print(f"{'PUMA 560, the shipped catalogs':<46}{'mechatron':>13}{'floor':>13}{'ratio':>9}")
    with tempfile.TemporaryDirectory() as folder:
        task = task_with(puma, None, Path(folder))
        compare(f"default task ({len(task.trajectory.t)} samples), fixed point", task, motors, gearboxes, False,
                args.repeats)
        compare("default task, single pass", task, motors, gearboxes, True, args.repeats)
        if not args.skip_long:
            long_times = {}
            for rows in (20_000, 100_000):
                fine = task_with(puma, rows, Path(folder))
                long_times[rows] = compare(f"the cycle in {len(fine.trajectory.t):,} rows, fixed point", fine, motors,
                                           gearboxes, False, max(1, args.repeats // 2))
            proportion = long_times[100_000] / (5 * long_times[20_000])
            print(f"100,000 rows against 5 × 20,000 rows: {proportion:.2f} (goal 0.9 … 1.1: "
                  f"{'ok' if 0.9 <= proportion <= 1.1 else 'not linear'})")
        big = larger(motors, 10, MOTOR_COLUMNS, 1), larger(gearboxes, 10, GEARBOX_COLUMNS, 2)
        compare(f"catalogs ×10 ({len(big[0])} motors, {len(big[1])} gearboxes)", task, *big, False, 1)
    closed_loop(args.repeats)


def closed_loop(repeats: int, rows: int = 5000) -> float:
    """The scissor lift sized along ``rows`` samples against its sweep of as many (both warm: the loop kernels
    built by a first run of each); prints both and the ratio (goal ≤ 10×)."""
    lift = mechatron.load(Path(__file__).resolve().parents[1] / "examples" / "data" / "scissor_lift.toml")
    probe = generic_task(lift)
    task = generic_task(lift, dt=probe.trajectory.duration / (rows - 1))
    samples = len(task.trajectory.t)
    times, _ = interleaved_best({"size": lambda: mechatron.size(lift, task),
                                 "sweep": lambda: mechatron.sweep(lift, samples=samples)}, repeats + 1)
    ratio = times["size"] / times["sweep"]
    print(f"{'scissor lift (closed loop), ' + f'{samples:,} samples':<46}{times['size'] * 1e3:>10.1f} ms"
          f"{times['sweep'] * 1e3:>10.1f} ms{ratio:>8.2f}x   {'ok' if ratio <= 10 else 'over 10x'}   "
          "(mechatron.size against mechatron.sweep)")
    return ratio


if __name__ == "__main__":
    main()

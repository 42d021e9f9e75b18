"""Drive sizing of the PUMA 560 against its lean floor: what a competent engineer writes with NumPy and Pinocchio.

The floor (:func:`floor_size`) does the checks of ``mechatron.size`` and chooses the same drives (asserted), with
nothing of mechatron but the thermal network's closed form (:func:`~mechatron.drives.thermal.periodic_rise`, the
exact interval maps and their periodic fixed point, in machine code where a C compiler is at hand — both the floor
and the sizing use it): the catalogs read into arrays once; the duties
from Pinocchio (the model with its armature removed and the file's drive friction τ_f = u_f (B u_f q̇ + T_c±) at the
joints, RNEA over the task in Pinocchio's compiled loop, the load inertia the largest diagonal of the CRBA mass
matrix); per joint, every motor × converter pair at once as (N_m, N_c) arrays — the RMS motor torque from five time
moments of the duty (T = (J_m + J_c) u ω̇ + τ*/u, τ* = τ/η where the load takes power, τη where it gives it back,
so ⟨T²⟩ = (J u)² ⟨ω̇²⟩ + 2J(⟨ω̇τ₊⟩/η + ⟨ω̇τ₋⟩η) + (⟨τ₊²⟩/η² + ⟨τ₋²⟩η²)/u²), for a motor with thermal data its
winding's mean rise in place of RMS, the speed, inertia-ratio, emergency-torque and gearbox checks (the peak torque
over the catalog's shock factor at the task's load peaks per hour) —, then the passing pairs in mass order (then
price), each checked sample by sample (peak torque, the speed–torque curve, the voltage limit, then the winding's
temperature over the periodic steady state) until one passes; the same distal-to-proximal fixed point, the drives
as point masses on the bodies that carry them (Pinocchio's ``appendBodyToJoint``), the duties recomputed when the
drives on the links change.

Every figure is a ratio of CPU times (``time.process_time``) measured side by side in this process, the medians of
repeats in which the candidates take turns (:func:`timing.cpu_medians_and_results`): the PUMA's default sizing (its
task, 1,115 samples; the shipped catalogs) against the floor (goal ≤ 1.5×), with and without the fixed point; the
same cycle sampled finely to 20,000 and 100,000 rows (time linear in the task: the 100,000-row time within 10 % of 5×
the 20,000-row one); the catalogs ten times larger (each motor and gearbox in ten variants). Then the CPU time per
design of a study-like loop of PUMA designs (a2, a3, d4 each ± 10 %: ``with_parameters``, then the sizing analysis'
``outputs``, as ``mechatron study`` evaluates a design) and its extrapolation to 10,000 designs (goal ≤ 300 s).

    python benchmarks/sizing.py [--repeats R] [--designs N] [--skip-long]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pinocchio as pin
from timing import cpu_medians_and_results

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.thermal import ALPHA_COPPER, DEFAULT_AMBIENT, MAGNET_COEFFICIENT, REFERENCE, periodic_rise
from mechatron.dynamics.task import read_task, task_file

TOLERANCE = 1 + 1e-9  # a check passes at value ≤ limit (1 + 1e-9), as mechatron's
MOTOR_COLUMNS = ["rated_torque", "peak_torque", "rotor_inertia", "mass", "price"]
GEARBOX_COLUMNS = ["ratio", "rated_torque", "peak_torque", "mass", "price"]
#: A load peak of a gearbox: a run of samples with |ω̇| beyond this fraction of the task's largest (docs/catalogs.md).
PEAK_FRACTION = 0.5


# ------------------------------------------------------------------------------------------------ the floor
def columns(catalog: pd.DataFrame, names: list[str], default: float = math.nan) -> dict[str, np.ndarray]:
    """The catalog's numeric columns ``names`` as float arrays, ``default`` where a column or a cell is missing."""
    return {n: catalog[n].to_numpy(dtype=float, na_value=default) if n in catalog else np.full(len(catalog), default)
            for n in names}


def motor_arrays(motors: pd.DataFrame) -> dict[str, np.ndarray]:
    """The motor columns the checks read (SI), mass and price 0 where missing, α copper's where missing."""
    out = columns(motors, ["rotor_inertia", "rated_torque", "peak_torque", "rated_speed", "max_speed",
                           "torque_constant", "resistance", "voltage", "rth_winding_housing",
                           "rth_housing_ambient", "tau_winding", "tau_housing", "max_winding_temperature"])
    out.update(columns(motors, ["mass", "price", "loss_torque"], 0.0))
    out["alpha"] = columns(motors, ["temperature_coefficient"], ALPHA_COPPER)["temperature_coefficient"]
    out["magnet"] = columns(motors, ["torque_constant_coefficient"], MAGNET_COEFFICIENT)["torque_constant_coefficient"]
    out["key"] = motors["key"].to_numpy(dtype=str)
    out["heated"] = np.isfinite(sum(out[n] for n in ("rth_winding_housing", "rth_housing_ambient", "tau_winding",
                                                     "tau_housing", "max_winding_temperature", "resistance",
                                                     "torque_constant")))
    # columns of the winding's mean rise (R_wh + R_ha)(R(T_a) I² + T_f n) and of its allowed rise T_max − T_a
    out["total"] = (out["rth_winding_housing"] + out["rth_housing_ambient"])[:, None]
    out["r_ambient"] = (out["resistance"] * (1 + out["alpha"] * (DEFAULT_AMBIENT - REFERENCE)))[:, None]
    out["kt"], out["loss"] = out["torque_constant"][:, None], out["loss_torque"][:, None]
    out["allowed"] = (out["max_winding_temperature"] - DEFAULT_AMBIENT)[:, None]
    return out


def converter_arrays(gearboxes: pd.DataFrame) -> dict[str, np.ndarray]:
    """Direct drive, then every gearbox (SI)."""
    g = columns(gearboxes, ["ratio", "efficiency", "input_inertia", "rated_torque", "peak_torque",
                            "emergency_torque", "max_input_speed", "rated_input_speed"])
    g.update(columns(gearboxes, ["mass", "price"], 0.0))
    direct = dict(ratio=1.0, efficiency=1.0, input_inertia=0.0, mass=0.0, price=0.0)
    out = {n: np.concatenate([[direct.get(n, math.inf)], x]) for n, x in g.items()}
    tables = gearboxes["shock_factors"] if "shock_factors" in gearboxes else [()] * len(gearboxes)
    out["shock"] = [()] + [tuple(x) if isinstance(x, tuple) else () for x in tables]  # ((rate 1/s, f_s), …)
    out["key"] = np.concatenate([["direct"], gearboxes["key"].to_numpy(dtype=str)])
    return out


def file_friction(mech, name: str) -> tuple[float, float, float, float]:
    """(B u_f², C+, C−, η_f) of the robot file's drive of joint ``name``: τ_f = B u_f² q̇ + C± at the joint."""
    drive = mech.drives.get(name)
    if drive is None:
        return 0.0, 0.0, 0.0, 1.0
    u, (forward, backward) = drive.gear_ratio, drive.coulomb_friction
    positive, negative = (u * forward, u * backward) if u > 0 else (u * backward, u * forward)
    return drive.viscous_friction * u * u, positive, negative, drive.efficiency


def duties(model: pin.Model, trajectory, friction: dict[str, tuple]) -> dict[str, tuple]:
    """name → (speed, acceleration, torque, load inertia) of every joint, from Pinocchio: RNEA over the task in
    its compiled loop, the file's friction added, the load inertia the largest diagonal of M over ≤ ~200 samples."""
    Q, V, A = (np.ascontiguousarray(x, dtype=float) for x in (trajectory.q, trajectory.v, trajectory.a))
    tau = np.empty_like(V)
    pin.rneaInParallel(1, pin.ModelPool(model, 1), Q.T, V.T, A.T, tau.T)
    data = model.createData()
    step = max(1, len(Q) // 200)
    inertia = np.max([np.diagonal(pin.crba(model, data, q)) for q in Q[::step]], axis=0)
    out = {}
    for name, (b, plus, minus, _) in friction.items():
        j = model.joints[model.getJointId(name)].idx_v
        v = V[:, j]
        out[name] = v, A[:, j], tau[:, j] + b * v + np.where(v > 0, plus, np.where(v < 0, minus, 0.0)), inertia[j]
    return out


def time_weights(t: np.ndarray) -> np.ndarray:
    """Trapezoidal weights w with w · f = the time mean of f over the samples t (s)."""
    step = np.diff(t)
    w = np.zeros(len(t))
    w[1:] += step / 2
    w[:-1] += step / 2
    return w / (t[-1] - t[0])


def load_peaks(a: np.ndarray) -> int:
    """The runs of |ω̇| ≥ PEAK_FRACTION max |ω̇| of one sign over the repeated task (a lone sample below between two
    of one sign does not end a run), each an acceleration or a braking."""
    top = np.abs(a).max()
    if top == 0:
        return 0
    side = np.where(a >= PEAK_FRACTION * top, 1, np.where(a <= -PEAK_FRACTION * top, -1, 0))
    side = np.where((side == 0) & (np.roll(side, 1) == np.roll(side, -1)), np.roll(side, 1), side)
    return max(1, int(np.count_nonzero((side != 0) & (side != np.roll(side, 1)))))


def shock_factors(rate: float, tables: list[tuple]) -> np.ndarray:
    """f_s of every converter at ``rate`` load peaks per second: its table interpolated (the first factor below it),
    inf above its last rate (no rating), 1 without a table."""
    return np.array([1.0 if not table else math.inf if rate > table[-1][0] else np.interp(rate, *zip(*table))
                     for table in tables])


def floor_joint(t: np.ndarray, w: np.ndarray, duty: tuple, motors: dict, conv: dict, inertia_ratio_max: float = 10.0
                ) -> tuple[int, int]:
    """(motor, converter) of the lightest, then cheapest, pair passing every check; (−1, −1) if none (``w``: the
    time weights of the samples ``t``)."""
    om, a, tau, load_inertia = duty
    speed = np.abs(om)
    # the converters' own checks (the gearbox's: equivalent, derated peak torque, input speeds), then every motor
    # with the converters that pass them
    motion = speed * w if speed.any() else w
    equivalent = (motion @ np.abs(tau) ** 3 / motion.sum()) ** (1 / 3)
    derating = 1 / shock_factors(load_peaks(a) / (t[-1] - t[0]), conv["shock"])
    mean_speed, top_speed = w @ speed, speed.max()
    usable = np.flatnonzero((equivalent <= conv["rated_torque"] * TOLERANCE)
                            & (np.abs(tau).max() <= conv["peak_torque"] * derating * TOLERANCE)
                            & (conv["ratio"] * top_speed <= conv["max_input_speed"] * TOLERANCE)
                            & (conv["ratio"] * mean_speed <= conv["rated_input_speed"] * TOLERANCE))
    u, eta, jc = conv["ratio"][usable], conv["efficiency"][usable], conv["input_inertia"][usable]
    power = tau * om >= 0
    tp, tn = np.where(power, tau, 0.0), np.where(power, 0.0, tau)
    a2, p1, n1, p2, n2 = w @ a**2, w @ (a * tp), w @ (a * tn), w @ tp**2, w @ tn**2
    jm = motors["rotor_inertia"][:, None]
    j = jm + jc
    rms = np.sqrt(np.maximum((j * u) ** 2 * a2 + 2 * j * (p1 / eta + n1 * eta) + (p2 / eta**2 + n2 * eta**2) / u**2,
                             0.0))
    mean, top = u * mean_speed, u * top_speed
    peak, rated = motors["peak_torque"][:, None], motors["rated_torque"][:, None]
    rated_speed, max_speed = motors["rated_speed"][:, None], motors["max_speed"][:, None]
    # the winding's mean rise (R_wh + R_ha)(R(T_a) T_rms²/k_t² + T_f ⟨|n|⟩) of the motors with thermal data bounds
    # its highest from below; the others: RMS against the S1 torque at the mean speed
    mean_rise = motors["total"] * (motors["r_ambient"] * (rms / motors["kt"]) ** 2 + motors["loss"] * mean)
    s1 = np.where(mean <= rated_speed, rated, rated * rated_speed / np.maximum(mean, 1e-300))
    warm = np.where(motors["heated"][:, None], mean_rise <= motors["allowed"] * TOLERANCE,
                    rms <= np.where(mean <= max_speed, s1, 0.0) * TOLERANCE)
    ok = warm & (top <= max_speed * TOLERANCE) & ((load_inertia / u**2 + jc) / jm <= inertia_ratio_max * TOLERANCE) \
        & (peak * u <= conv["emergency_torque"][usable] * TOLERANCE)
    m, k = np.nonzero(ok)
    c = usable[k]
    for pair in np.lexsort((motors["price"][m] + conv["price"][c], motors["mass"][m] + conv["mass"][c])):
        i, g = m[pair], c[pair]
        u, eta = conv["ratio"][g], conv["efficiency"][g]
        n = u * speed
        torque = np.abs((motors["rotor_inertia"][i] + conv["input_inertia"][g]) * u * a
                        + np.where(power, tau / (u * eta), tau * eta / u))
        # the intermittent curve: T_p up to n_r, linear down to T_r n_r/n_max at n_max, none beyond
        t_p, t_r, n_r, n_max = (motors[x][i] for x in ("peak_torque", "rated_torque", "rated_speed", "max_speed"))
        curve = t_p + (t_r * n_r / n_max - t_p) * np.clip((n - n_r) / (n_max - n_r), 0.0, 1.0)
        if torque.max() > t_p * TOLERANCE or (torque > np.where(n <= n_max, curve, 0.0) * TOLERANCE).any():
            continue
        kt, voltage = motors["torque_constant"][i], motors["voltage"][i]
        if np.isfinite(voltage) and (kt * n + motors["resistance"][i] / kt * torque).max() > voltage * TOLERANCE:
            continue
        if motors["heated"][i]:  # the winding over the repeated task (the two-node network's periodic steady state)
            rise = periodic_rise(t, (torque / kt)[None] ** 2, motors["loss_torque"][i] * n[None],
                                 *(motors[x][i] for x in ("rth_winding_housing", "rth_housing_ambient", "tau_winding",
                                                          "tau_housing", "resistance", "alpha")), DEFAULT_AMBIENT,
                                 motors["magnet"][i])
            if not rise[0, :, 0].max() <= motors["allowed"][i, 0] * TOLERANCE:  # NaN: runaway
                continue
        return int(i), int(g)
    return -1, -1


def depth(model: pin.Model, joint: int) -> int:
    """The joints between ``joint`` and the ground, itself included."""
    count = 0
    while joint > 0:
        joint, count = model.parents[joint], count + 1
    return count


def floor_size(mech, trajectory, motors: pd.DataFrame, gearboxes: pd.DataFrame, single_pass: bool = False
               ) -> dict[str, tuple[str, str]]:
    """joint → (motor key, converter key): a pass with weightless drives, then passes distal to proximal, each
    joint with the drives chosen so far on their links (point masses at the joints on their parent bodies), until
    a pass chooses what the one before chose."""
    model = pin.Model(mech.model)
    model.armature[:] = 0.0
    names = list(mech.joint_names)
    friction = {n: file_friction(mech, n) for n in names}
    t = np.asarray(trajectory.t, dtype=float)
    w = time_weights(t)
    bare = {n: d for n, d in duties(model, trajectory, friction).items() if np.abs(d[0]).max() or np.abs(d[2]).max()}
    order = sorted(bare, key=lambda n: -depth(model, model.getJointId(n)))  # distal first
    cat = motor_arrays(motors)
    catalog = converter_arrays(gearboxes)
    converters = {n: {**catalog, "efficiency": catalog["efficiency"] * friction[n][3]} for n in order}
    chosen: dict[str, tuple[int, int]] = {}
    known: dict[tuple, dict] = {}

    def loaded() -> dict:
        mounts = [(n, i, g) for n, (i, g) in chosen.items() if model.parents[model.getJointId(n)] > 0
                  and cat["mass"][i] + converters[n]["mass"][g] > 0]
        key = tuple(sorted(mounts))
        if not key:
            return bare
        if key not in known:
            carrying = pin.Model(model)
            for n, i, g in mounts:
                joint = model.getJointId(n)
                carrying.appendBodyToJoint(model.parents[joint], pin.Inertia(
                    float(cat["mass"][i] + converters[n]["mass"][g]), np.zeros(3), np.zeros((3, 3))),
                    model.jointPlacements[joint])
            known[key] = duties(carrying, trajectory, friction)
        return known[key]

    def one_pass(weighted: bool) -> tuple:
        for name in order:
            chosen[name] = floor_joint(t, w, (loaded() if weighted else bare)[name], cat, converters[name])
        return tuple(chosen[n] for n in order)

    history = [one_pass(False)]
    while not single_pass:
        state = one_pass(True)
        if state == history[-1]:
            break
        history.append(state)
    return {n: (str(cat["key"][i]), str(converters[n]["key"][g])) for n, (i, g) in chosen.items()}


# -------------------------------------------------------------------------------------------- the benchmark
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


def compare(label: str, task, motors, gearboxes, single_pass: bool, repeats: int, goal: float = 1.5) -> float:
    """Print mechatron's and the floor's median CPU times, their ratio and whether the drives agree (asserted);
    returns mechatron's time (s)."""
    times, results = cpu_medians_and_results({
        "mechatron": lambda: {s.joint: (s.motor, s.converter) for s in mechatron.size(
            task.mechanism, task, motors=motors, gearboxes=gearboxes, single_pass=single_pass).joints},
        "floor": lambda: floor_size(task.mechanism, task.trajectory, motors, gearboxes, single_pass)}, repeats)
    assert results["mechatron"] == results["floor"], (label, results)
    ratio = times["mechatron"] / times["floor"]
    print(f"{label:<46}{times['mechatron'] * 1e3:>10.1f} ms{times['floor'] * 1e3:>10.1f} ms{ratio:>8.2f}x"
          f"   {'ok' if ratio <= goal else f'over {goal}x'}   same drives")
    return times["mechatron"]


def study_designs(count: int, seed: int = 1) -> tuple[object, list[dict[str, float]]]:
    """The PUMA and ``count`` geometries with a2, a3 and d4 each × U(0.9, 1.1)."""
    base = mechatron.load("puma560")
    nominal = {k: base.parameters[k].value for k in ("a2", "a3", "d4")}
    rows = np.random.default_rng(seed).uniform(0.9, 1.1, (count, 3))
    return base, [{k: v * f for (k, v), f in zip(nominal.items(), row)} for row in rows]


def study_loop(designs: int, rounds: int = 5) -> float:
    """The median CPU time (s) per design of ``rounds`` chunks of a study-like loop over ``designs`` designs
    (``with_parameters``, the sizing analysis' ``outputs``, as ``studies.runner`` evaluates a design)."""
    from mechatron.studies.analyses import sizing

    base, geometries = study_designs(designs + 2)
    for geometry in geometries[:2]:  # warm: the catalogs read, the pair orders made
        sizing.outputs(base.with_parameters(geometry), {}, 0)
    per_design = []
    for chunk in np.array_split(np.arange(2, len(geometries)), rounds):
        start = time.process_time()
        for k in chunk:
            sizing.outputs(base.with_parameters(geometries[k]), {}, 0)
        per_design.append((time.process_time() - start) / len(chunk))
    return float(np.median(per_design))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--designs", type=int, default=500, help="designs of the study-like loop")
    parser.add_argument("--skip-long", action="store_true", help="leave out the 20,000- and 100,000-row tasks")
    args = parser.parse_args()
    puma = mechatron.load("puma560")
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    print(f"{'PUMA 560, the shipped catalogs (CPU, medians)':<46}{'mechatron':>13}{'floor':>13}{'ratio':>9}")
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
                                           gearboxes, False, max(3, args.repeats // 2))
            proportion = long_times[100_000] / (5 * long_times[20_000])
            print(f"100,000 rows against 5 × 20,000 rows: {proportion:.2f} (goal 0.9 … 1.1: "
                  f"{'ok' if 0.9 <= proportion <= 1.1 else 'not linear'})")
        big = larger(motors, 10, MOTOR_COLUMNS, 1), larger(gearboxes, 10, GEARBOX_COLUMNS, 2)
        compare(f"catalogs ×10 ({len(big[0])} motors, {len(big[1])} gearboxes)", task, *big, False, 3)
    per_design = study_loop(args.designs)
    total = 10_000 * per_design
    print(f"study-like loop of {args.designs} PUMA designs (with_parameters + the sizing analysis' outputs): "
          f"{per_design * 1e3:.1f} ms CPU per design, 10,000 designs ≈ {total:.0f} s "
          f"({'ok' if total <= 300 else 'over'} the goal of 300 s)")


if __name__ == "__main__":
    main()

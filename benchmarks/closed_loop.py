"""Closed-loop design at the speed of its kernels: sizing against the sweep, failing designs against passing ones,
optimisation against one sizing. Every figure is a ratio of CPU times (``time.process_time``) measured side by side
in one process, medians of interleaved repeats (timing.cpu_medians), except the one-design studies, which are
whole processes (their CPU from the operating system) run in turns.

1. **Closed-loop sizing against its sweep** (goal ≤ 5×). ``mechatron.size`` of a machine along a task of about
   5,000 samples with a payload and an external load (the shipped hydraulic-cylinder catalog) against
   ``mechatron.sweep`` of the same machine at as many samples (position, velocity and acceleration analysis with
   the mechanism's points and measures: what ``mechatron linkage`` computes). Both warm (the structure's compiled
   loop kernel built). The scissor lift of examples/data (500 kg platform + 150 kg at the deck, 400 N sideways and
   1.5 kN down on it), the front shovel and the six-link bucket (their generic tasks, 300 kg at the bucket's tip,
   a 20 kN digging resistance on it).
2. **A design that cannot assemble against one that does** (goal ≤ 2×). The scissor lift with its cylinder's base
   pin P moved: at P = (1.5, −0.15) m the cylinder's eye Q (0.9 m from foot 1) is at least 0.6 m from P, so the
   lift task's first length, 0.55 m, cannot close; at (0.5…0.6, −0.15) m it does. In one process, each a new
   geometry through a study's evaluation of one design (``mechatron.studies.runner.evaluate``: rebuilt, sized);
   and as one-design studies (``mechatron study``), whole processes.
3. **optimize against one sizing** (goal ≤ 60×): the least ``drive_mass_kg`` with ``smallest_margin ≥ 0`` over
   P_x ∈ [0.6, 1.6] m (the upper part cannot assemble), differential evolution with 32 evaluations
   (``mechatron.optimal.optimize_design``, in this process) against one sizing of a new geometry; then the
   two-variable problem (P_x ∈ [0.6, 1.6], P_y ∈ [−0.4, 0.1] m, 400 evaluations: goal under 5 minutes of CPU) and
   its answer against the best feasible design of a 15 × 15 grid study of the same analyses (goal: no worse).

    python benchmarks/closed_loop.py [--repeats R] [--skip-optimize]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from timing import cpu_medians

import mechatron
from mechatron.drives.catalogs import read_catalog
from mechatron.dynamics.task import Task, generic_task, read_task
from mechatron.model.loads import Load
from mechatron.model.payload import with_payload

ROOT = Path(__file__).resolve().parents[1]
SCISSOR = ROOT / "examples" / "data" / "scissor_lift.toml"
CYLINDERS = ROOT / "catalogs" / "hydraulic_cylinders.csv"
LIFT_TASK = ROOT / "examples" / "design" / "scissor_lift_task.toml"
ROWS = 5000


def scissor_task() -> tuple[mechatron.Mechanism, Task]:
    """The scissor lift raised 0.52 → 0.82 m of cylinder and lowered, 150 kg at the deck and a load on it, sampled
    to about :data:`ROWS` rows."""
    mech = mechatron.load(SCISSOR)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "lift.toml"
        path.write_text('name = "lift with a load"\nprofile = "trapezoidal"\nvmax = 0.05\namax = 0.1\ndwell = 1.0\n'
                        'dt = 0.0027\nwaypoints = [[0.52], [0.82], [0.52]]\npayload = 150\npayload_at = "deck"\n'
                        '[[loads]]\nframe = "deck"\nforce = [400, -1500, 0]\n')
        return mech, read_task(path, mech)


def digging_task(name: str, tip: str) -> tuple[mechatron.Mechanism, Task]:
    """A machine's generic task (every cylinder out by 40 % of its stroke and back) resampled to about
    :data:`ROWS` rows, with 300 kg at the bucket's tip and a 20 kN resistance there."""
    mech = mechatron.load(name)
    duration = generic_task(mech).trajectory.t[-1]
    carrying = with_payload(mech, 300.0, tip)
    task = generic_task(carrying, dt=duration / ROWS)
    return mech, Task(task.name, carrying, task.trajectory, [Load(tip, (-2e4, 5e3, 0.0))], 300.0)


def sizing_against_sweep(repeats: int) -> None:
    print("1. closed-loop sizing against its sweep of as many samples (goal <= 5x)")
    print(f"   {'machine':<34}{'samples':>8}{'size':>11}{'sweep':>11}{'ratio':>8}")
    cases = [("scissor lift", *scissor_task(), {"pressure": 4e6}),
             ("front shovel", *digging_task("front_shovel", "V"), {}),
             ("six-link bucket", *digging_task("six_bar_bucket", "K"), {})]
    for label, mech, task, options in cases:
        n = len(task.trajectory.t)
        catalog = read_catalog(CYLINDERS, "cylinders")

        def size(task=task, options=options, catalog=catalog):
            return mechatron.size(task.mechanism, task, cylinders=catalog, **options)

        def sweep(mech=task.mechanism, n=n):
            return mechatron.sweep(mech, samples=n)

        size(), sweep()  # warm: the loop kernels built
        times = cpu_medians({"size": size, "sweep": sweep}, repeats)
        ratio = times["size"] / times["sweep"]
        print(f"   {label:<34}{n:>8,}{times['size'] * 1e3:>9.1f} ms{times['sweep'] * 1e3:>8.1f} ms{ratio:>7.2f}x  "
              f"{'ok' if ratio <= 5 else 'over 5x'}")


def one_design(P_x: float, P_y: float = -0.15):
    """The study's evaluation of one scissor design (its rows)."""
    import pandas as pd

    from mechatron.studies.runner import evaluate

    return evaluate(one_design.spec, pd.DataFrame([{"design": 0, "P_x": P_x, "P_y": P_y, "seed": 0}]))


def failing_against_passing(repeats: int, folder: Path) -> None:
    from mechatron.studies.spec import read_study as read_spec

    print("2. a scissor design that cannot assemble along its task against one that does (goal <= 2x)")
    spec = folder / "one.toml"
    spec.write_text(f'mechanism = "{SCISSOR.as_posix()}"\n[parameters.P_x]\nvalues = [0.5]\n'
                    '[parameters.P_y]\nvalues = [-0.15]\n[designs]\nmethod = "grid"\n'
                    f'[analyses.sizing]\ntask = "{LIFT_TASK.as_posix()}"\ncylinders = "{CYLINDERS.as_posix()}"\n'
                    'pressure_MPa = 4\n')
    one_design.spec = read_spec(spec)
    counter = iter(range(10**6))
    step = lambda: 1e-4 * next(counter)  # noqa: E731 - every call a new geometry
    fails = one_design(1.5)
    assert fails["status"].iloc[0] == "failed", fails
    print(f"   the failing design's reason: {fails['reason'].iloc[0]}")
    assert one_design(0.5)["status"].iloc[0] == "ok"
    times = cpu_medians({"assembles": lambda: one_design(0.5 + step()), "fails": lambda: one_design(1.5 + step())},
                        repeats * 3)
    ratio = times["fails"] / times["assembles"]
    print(f"   in one process: assembles {times['assembles'] * 1e3:.1f} ms, fails {times['fails'] * 1e3:.1f} ms: "
          f"{ratio:.2f}x  {'ok' if ratio <= 2 else 'over 2x'}")
    specs = {}
    for key, x in (("assembles", 0.5), ("fails", 1.5)):
        specs[key] = folder / f"{key}.toml"
        specs[key].write_text(spec.read_text().replace("values = [0.5]", f"values = [{x}]"))
    cpu: dict[str, list[float]] = {key: [] for key in specs}
    for k in range(max(3, repeats)):
        for key, path in specs.items():
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([sys.executable, "-m", "mechatron", "study", str(path), "--out", str(folder / f"{key}{k}"),
                            "--json"], check=True, capture_output=True, env={**os.environ})
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu[key].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    medians = {key: float(np.median(v)) for key, v in cpu.items()}
    ratio = medians["fails"] / medians["assembles"]
    print(f"   as one-design studies (whole processes): assembles {medians['assembles']:.2f} s, fails "
          f"{medians['fails']:.2f} s of CPU: {ratio:.2f}x  {'ok' if ratio <= 2 else 'over 2x'}")


def design_file(folder: Path, variables: str, solver: str, name: str) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(f'name = "{name}"\nmechanism = "{SCISSOR.as_posix()}"\n[variables]\n{variables}\n'
                    '[objective]\nminimize = "drive_mass_kg"\n[requirements]\nsmallest_margin = { min = 0.0 }\n'
                    f'[analyses.sizing]\ntask = "{LIFT_TASK.as_posix()}"\ncylinders = "{CYLINDERS.as_posix()}"\n'
                    f'pressure_MPa = 4\n[solver]\n{solver}\n')
    return path


def optimize_against_sizing(repeats: int, folder: Path) -> None:
    from mechatron.optimal import optimize_design
    from mechatron.studies.runner import run_study

    print("3. optimize against one sizing (goal <= 60x); two variables (goal < 5 min, no worse than a 15 x 15 grid)")
    one = design_file(folder, "P_x = [0.6, 1.6]", 'method = "global"\npopulation = 8\nevaluations = 32', "px")
    counter = iter(range(10**6))
    optimize_design(one)
    times = cpu_medians({"optimize": lambda: optimize_design(one),
                         "sizing": lambda: one_design(0.5 + 1e-4 * next(counter))}, repeats)
    result = optimize_design(one)
    ratio = times["optimize"] / times["sizing"]
    failed = int((result.evaluations["status"] != "ok").sum())
    print(f"   one variable: {len(result.evaluations)} designs ({failed} cannot assemble), "
          f"{times['optimize']:.2f} s against {times['sizing'] * 1e3:.1f} ms: {ratio:.0f}x  "
          f"{'ok' if ratio <= 60 else 'over 60x'}; best P_x = {result.best['P_x']:.4f} m, "
          f"{result.best['drive_mass_kg']:.3f} kg")
    two = design_file(folder, "P_x = [0.6, 1.6]\nP_y = [-0.4, 0.1]", 'method = "global"', "pxy")
    start = time.process_time()
    result = optimize_design(two)
    seconds = time.process_time() - start
    grid = folder / "grid.toml"
    grid.write_text(f'mechanism = "{SCISSOR.as_posix()}"\n[parameters.P_x]\nlow = 0.6\nhigh = 1.6\n'
                    '[parameters.P_y]\nlow = -0.4\nhigh = 0.1\n[designs]\nmethod = "grid"\nlevels = 15\n'
                    f'[analyses.sizing]\ntask = "{LIFT_TASK.as_posix()}"\ncylinders = "{CYLINDERS.as_posix()}"\n'
                    'pressure_MPa = 4\n')
    start = time.process_time()
    table = run_study(grid, folder / "grid").to_frame()
    grid_seconds = time.process_time() - start
    ok = table[(table["status"] == "ok") & (table["smallest_margin"] >= 0)]
    best = float(ok["drive_mass_kg"].min())
    mass = result.best["drive_mass_kg"]
    print(f"   two variables: {len(result.evaluations)} designs in {seconds:.1f} s of CPU "
          f"({'ok' if seconds < 300 else 'over 5 min'}): {mass:.3f} kg at P = ({result.best['P_x']:.4f}, "
          f"{result.best['P_y']:.4f}) m; the grid's best feasible {best:.3f} kg ({len(table)} designs, "
          f"{int((table['status'] != 'ok').sum())} cannot assemble, {grid_seconds:.1f} s): "
          f"{'ok' if mass <= best + 1e-9 else 'WORSE'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--skip-optimize", action="store_true")
    args = parser.parse_args()
    sizing_against_sweep(args.repeats)
    with tempfile.TemporaryDirectory() as folder:
        failing_against_passing(args.repeats, Path(folder))
        if not args.skip_optimize:
            optimize_against_sizing(max(3, args.repeats // 2), Path(folder))


if __name__ == "__main__":
    main()

"""A design study on Dask: PUMA 560 geometries (a2, a3, d4 each ± 10 %, a Latin hypercube) sized with the robot's own
task and the shipped catalogs (``[analyses.sizing]``), run serially and on an embedded ``LocalCluster`` of two worker
processes, side by side on the same designs.

Printed: the time per design of both runs and their ratio (goal: two workers ≥ 1.6× faster than one process — on a
machine with two idle cores), the identical tables (checked), the scheduler's overhead per task (empty tasks sent
through the same cluster: what a chunk costs beyond its designs), and a projection for 10,000 designs on 1, 2 and
100 workers from the measured time per design, the chunk size and the overhead per task:
T(w) ≈ N·t / w + ⌈N / c⌉·o + start-up (t the time per design, c the designs per chunk, o the overhead per task; the
scheduler hands out tasks one after the other). The baseline is what a designer would run otherwise: the same study
in one process (``--workers 1``), which is the serial loop over ``size_mechanism`` that a script would write.

    python benchmarks/study.py [--designs 10000] [--workers 2] [--chunk 8]

The default is the issue's 10,000 designs: about 47 min in one process and 24 min on two workers on the project's
two-core machine (0.28 s per sizing); ``--designs 2000`` takes a fifth of that and gives the same ratio. Measured
(2026-11-23, idle machine): 2,000 designs, one process 559.9 s (280 ms per design), two workers 319.0 s, speed-up
1.75x, tables identical, LocalCluster start-up 1.4 s, overhead 2.3 ms per task; a one-process run of all 10,000
designs took 46.6 min while other work shared the machine (the projection from 2,000 says 46.7 min), and a
two-worker run of all 10,000 designs 23.3 min on the idle machine (projected: 23.4 min). Before the
workers were spawned without Dask's ``MALLOC_TRIM_THRESHOLD_`` (see ``mechatron.studies.cluster.WORKER_CONFIG``),
a worker sized at 0.41-0.60 s per design against 0.32 s in a plain process, and the ratio was 1.0-1.5x.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import pandas as pd

SPEC = """mechanism = "puma560"
[parameters.a2]
relative = 0.10
[parameters.a3]
relative = 0.10
[parameters.d4]
relative = 0.10
[designs]
method = "lhs"
samples = {designs}
seed = 1
[analyses.sizing]
"""


def timed_study(spec: Path, out: Path, workers: int, chunk: int) -> tuple[float, pd.DataFrame]:
    """(seconds, designs table) of one run of the study."""
    from mechatron.studies.runner import run_study

    start = time.perf_counter()
    result = run_study(spec, out, workers=workers, chunk_size=chunk)
    return time.perf_counter() - start, result.to_frame()


def overhead_per_task(workers: int, tasks: int = 2000) -> tuple[float, float]:
    """(start-up of a LocalCluster of ``workers`` processes, s; scheduler overhead per empty task, s)."""
    from distributed import Client, LocalCluster, wait

    start = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        startup = time.perf_counter() - start
        client.submit(abs, -1).result()  # warm
        start = time.perf_counter()
        wait(client.map(abs, range(-tasks, 0), pure=False))
        return startup, (time.perf_counter() - start) / tasks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=10_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--chunk", type=int, default=8, help="designs per task")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        warm = Path(folder) / "warm.toml"
        warm.write_text(SPEC.format(designs=4))
        timed_study(warm, Path(folder) / "warm", 1, args.chunk)  # imports and catalogs read in this process
        spec = Path(folder) / "study.toml"
        spec.write_text(SPEC.format(designs=args.designs))
        t_serial, serial = timed_study(spec, Path(folder) / "serial", 1, args.chunk)
        t_dask, parallel = timed_study(spec, Path(folder) / "dask", args.workers, args.chunk)
    pd.testing.assert_frame_equal(serial, parallel)
    startup, overhead = overhead_per_task(args.workers)
    per_design = t_serial / args.designs
    ok = int((serial["status"] == "ok").sum())
    print(f"PUMA 560 sizing study, {args.designs} designs ({ok} sized), chunks of {args.chunk}")
    print(f"  one process:          {t_serial:8.2f} s   {per_design * 1e3:7.1f} ms per design")
    print(f"  {args.workers} Dask workers:       {t_dask:8.2f} s   {t_dask / args.designs * 1e3:7.1f} ms per design"
          f"   speed-up {t_serial / t_dask:.2f}x (goal >= 1.6x on two idle cores); tables identical")
    print(f"  LocalCluster start-up {startup:.2f} s; scheduler overhead {overhead * 1e3:.2f} ms per task")
    n = 10_000
    tasks = math.ceil(n / args.chunk)
    for workers in (1, 2, 100):
        projected = n * per_design / workers + (tasks * overhead + startup if workers > 1 else 0.0)
        print(f"  projection, {n:,} designs on {workers:>3} worker(s): {projected / 60:7.1f} min")


if __name__ == "__main__":
    main()

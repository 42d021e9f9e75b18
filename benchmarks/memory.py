"""Peak memory of the requests that grow with the user's counts (issue 13: bounded work).

Each case runs ``mechatron`` in a fresh Python process and reports its peak resident memory (``ru_maxrss``), its
wall time and how it ended: a run within the stated bound, or a clean refusal (exit 2, one line naming the figure
and the limit, :mod:`mechatron.io.budget`). Cases:

- ``size puma560`` on a trajectory CSV of ``--rows`` rows (default 1,000,000; six sinusoids over 10 s): must run
  under ``--size-bound-gb`` (default 4 GB; about 1.7 GB measured). It takes minutes (every motor × gearbox pair is
  checked at the samples that can decide it, which for a smooth motion are most of them).
- ``tolerance puma560 --method mc --samples N`` (default 1e8): the Monte Carlo streams over chunks of samples in
  constant memory (:mod:`mechatron.accuracy.streaming`), so it runs (minutes: ≈ 5 µs a sample) and must stay under
  the ``--memory-gb`` given (default 4; ≈ 0.2–0.3 GB measured), or is refused cleanly by the time bound
  (``MECHATRON_TIME_S``).

    python benchmarks/memory.py [--rows N] [--samples N] [--memory-gb G] [--size-bound-gb G] [--skip-size]

Exits 1 if a case exceeds its bound or ends otherwise than as stated.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: Run in the child: the command line in-process, its output dropped, then the peak RSS (KiB on Linux) and status.
CHILD = """
import contextlib, io, json, resource, sys
from mechatron.cli import main
err = io.StringIO()
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
    try:
        code = main(sys.argv[1:])
    except SystemExit as exc:
        code = exc.code
print(json.dumps({"code": code, "stderr": err.getvalue().strip(),
                  "maxrss_kib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}))
"""


def measure(argv: list[str], memory_gb: float | None = None) -> dict:
    """Peak RSS (GB), wall time (s), exit status and stderr of ``mechatron ARGV`` in a fresh process."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    if memory_gb is not None:
        env["MECHATRON_MEMORY_GB"] = str(memory_gb)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CHILD, *argv], capture_output=True, text=True, env=env, cwd=ROOT)
    wall = time.perf_counter() - start
    if done.returncode != 0 or not done.stdout.strip():
        return {"code": done.returncode, "stderr": done.stderr.strip()[-500:], "peak_gb": float("nan"), "wall": wall}
    result = json.loads(done.stdout.strip().splitlines()[-1])
    result["peak_gb"] = result.pop("maxrss_kib") * 1024 / 1e9
    result["wall"] = wall
    return result


def trajectory_csv(path: Path, rows: int) -> Path:
    """Six sinusoids of the PUMA 560's joints over 10 s, ``rows`` rows."""
    t = np.linspace(0.0, 10.0, rows)
    q = 0.5 * np.sin(np.outer(2 * np.pi * t / 10, np.arange(1, 7) / 3))
    np.savetxt(path, np.column_stack([t, q]), delimiter=",", header="t,q1,q2,q3,q4,q5,q6", comments="",
               fmt="%.9g")
    return path


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", type=int, default=1_000_000)
    parser.add_argument("--samples", type=float, default=1e8)
    parser.add_argument("--memory-gb", type=float, default=4.0, help="MECHATRON_MEMORY_GB of the Monte Carlo")
    parser.add_argument("--size-bound-gb", type=float, default=4.0)
    parser.add_argument("--skip-size", action="store_true")
    args = parser.parse_args()
    failures = 0
    print(f"{'case':58s} {'peak (GB)':>10s} {'wall (s)':>9s}  outcome")
    if not args.skip_size:
        with tempfile.TemporaryDirectory() as folder:
            csv = trajectory_csv(Path(folder) / "long.csv", args.rows)
            r = measure(["size", "puma560", "--task", str(csv), "--json"])
        ok = r["code"] in (0, 1) and r["peak_gb"] <= args.size_bound_gb
        failures += not ok
        print(f"{f'size puma560, {args.rows:,} rows':58s} {r['peak_gb']:10.2f} {r['wall']:9.1f}  "
              f"{'sized' if r['code'] in (0, 1) else r['stderr']} (bound {args.size_bound_gb:g} GB)"
              f"{'' if ok else '  FAILED'}")
    samples = int(args.samples)
    r = measure(["tolerance", "puma560", "--tolerances", "examples/data/tolerances_puma560.csv", "--method", "mc",
                 "--samples", str(samples), "--json"], args.memory_gb)
    refused = r["code"] == 2 and "limit" in r["stderr"] and len(r["stderr"].splitlines()) == 1
    ok = refused or (r["code"] == 0 and r["peak_gb"] <= args.memory_gb * 2**30 / 1e9 + 0.5)
    failures += not ok
    print(f"{f'tolerance puma560 --method mc --samples {samples:.0e}':58s} {r['peak_gb']:10.2f} {r['wall']:9.1f}  "
          f"{r['stderr'] if refused else 'ran'} (MECHATRON_MEMORY_GB={args.memory_gb:g}){'' if ok else '  FAILED'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

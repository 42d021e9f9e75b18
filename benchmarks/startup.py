"""Start-up time of the command line: ``mechatron --help`` against ``python -c "import pinocchio"``.

Both run as fresh processes with the same interpreter, alternating, and the best of several runs is kept (the
fair comparison: every mechatron command needs Pinocchio's import anyway, --help should cost no more than that).
Target: ratio ≤ 1.5. Run: ``python benchmarks/startup.py``.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import time


def run(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main(repeats: int = 15) -> None:
    script = shutil.which("mechatron")
    help_command = [script, "--help"] if script else [sys.executable, "-m", "mechatron", "--help"]
    baseline = [sys.executable, "-c", "import pinocchio"]
    run(help_command), run(baseline)  # warm the file cache
    help_times, baseline_times = [], []
    for _ in range(repeats):
        help_times.append(run(help_command))
        baseline_times.append(run(baseline))
    best_help, best_baseline = min(help_times), min(baseline_times)
    print(f"mechatron --help:        {best_help * 1e3:7.1f} ms (best of {repeats})")
    print(f"python -c 'import pinocchio': {best_baseline * 1e3:7.1f} ms")
    print(f"ratio: {best_help / best_baseline:.2f} (target <= 1.5)")


if __name__ == "__main__":
    main()

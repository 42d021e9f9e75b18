"""Start-up time of real commands against ``python -c "import pinocchio"``.

Every real mechatron command needs Pinocchio's import anyway; what it costs beyond that is the command line's own
start-up (its imports, the robot's lookup and loading, the output transaction), which should stay small: a command
that computes one pose should cost no more than 1.5× the bare import of Pinocchio. Each command and the baseline run
as fresh processes with the same interpreter, alternating (the baseline before each command), and the best of several
runs of each is kept. The ratio of every command is printed with the goal; ``--help`` is shown for reference.

Two settings, both printed:

- *bytecode cached*: every module's bytecode (mechatron's, NumPy's, Pinocchio's) is written once, by the first runs,
  to a temporary folder (``PYTHONPYCACHEPREFIX``) and read from there, as for an installed package;
- *this environment as it is*: with ``PYTHONDONTWRITEBYTECODE=1`` and a source checkout without ``__pycache__``
  folders, mechatron's modules are compiled at every start while the installed packages' bytecode is read, so that
  every module a command imports costs its compilation too.

Run: ``python benchmarks/startup.py [REPEATS]`` (default 10).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: The goal: a real command within this multiple of ``python -c "import pinocchio"``.
GOAL = 1.5

#: The commands timed (arguments of ``mechatron``): a shipped serial robot's pose, a shipped linkage's pose and a
#: mechanism file's summary; ``--help`` last, for reference (not held to the goal).
COMMANDS = [
    ["fk", "puma560", "--q", "0,0,0,0,0,0"],
    ["fk", "crank_slider", "--q", "1,0,0"],
    ["show", "examples/data/four_bar.toml"],
    ["--help"],
]


def run(command: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def measure(title: str, env: dict[str, str], repeats: int) -> list[str]:
    """Time every command of :data:`COMMANDS` against the baseline in ``env``; print the table; returns the commands
    over the goal."""
    script = shutil.which("mechatron")
    prefix = [script] if script else [sys.executable, "-m", "mechatron"]
    baseline = [sys.executable, "-c", "import pinocchio"]
    commands = [prefix + arguments for arguments in COMMANDS]
    for command in [baseline, *commands]:  # warm the file cache (and the bytecode cache), and check every command
        run(command, env)
    times: list[list[float]] = [[] for _ in commands]
    baseline_times: list[float] = []
    for _ in range(repeats):
        for command, out in zip(commands, times):
            baseline_times.append(run(baseline, env))  # alternating: the baseline before each command
            out.append(run(command, env))
    best_baseline = min(baseline_times)
    print(title)
    print(f"  python -c 'import pinocchio'  {best_baseline * 1e3:7.1f} ms (best of {len(baseline_times)})")
    width = max(len(" ".join(arguments)) for arguments in COMMANDS) + len("mechatron ")
    over = []
    for arguments, out in zip(COMMANDS, times):
        label = "mechatron " + " ".join(arguments)
        ratio = min(out) / best_baseline
        held = arguments != ["--help"]
        mark = ("ok" if ratio <= GOAL else "OVER") if held else "reference"
        print(f"  {label:<{width}}  {min(out) * 1e3:7.1f} ms (best of {repeats})  ratio {ratio:5.2f}  "
              f"(goal <= {GOAL}: {mark})")
        if held and ratio > GOAL:
            over.append(label)
    return over


def main(repeats: int = 10) -> None:
    over = []
    with tempfile.TemporaryDirectory(prefix="mechatron-startup-") as cache:
        cached = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        cached["PYTHONPYCACHEPREFIX"] = cache
        over += [f"{label} (bytecode cached)" for label in
                 measure("bytecode cached (as installed):", cached, repeats)]
    writes = "off" if os.environ.get("PYTHONDONTWRITEBYTECODE") else "on"
    over += [f"{label} (this environment)" for label in
             measure(f"this environment as it is (writing bytecode {writes}):", dict(os.environ), repeats)]
    if over:
        print(f"over the goal of {GOAL}x import pinocchio: {'; '.join(over)}")
    else:
        print(f"every real command within {GOAL}x import pinocchio")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)

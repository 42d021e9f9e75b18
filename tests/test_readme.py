"""The README is a contract: every command and every Python block in it runs as written, from the top of a clone,
on the inputs that ship.

Shell blocks run line by line in a scratch folder that sees the clone's ``examples/``, ``robots/`` and
``catalogs/``; the set-up steps of a command (``python3 -m venv``, activating it, ``pip install``, ``pytest``) are
left out, since CI runs exactly those. Every Python block runs on its own in a fresh interpreter (no block relies on
an earlier one), from the same scratch folder.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
SETUP = re.compile(r"^(python3? -m venv|\. \.venv/bin/activate|source \.venv/bin/activate|pip install|pytest)\b")
FENCE = re.compile(r"^```(\w*)\s*$")


def blocks() -> list[tuple[str, int, str]]:
    """(language, first line number, text) of every fenced block of the README."""
    out, language, start, lines = [], None, 0, []
    for number, line in enumerate(README.read_text(encoding="utf-8").splitlines(), start=1):
        match = FENCE.match(line)
        if match and language is None:
            language, start, lines = match.group(1) or "text", number + 1, []
        elif line.startswith("```") and language is not None:
            out.append((language, start, "\n".join(lines)))
            language = None
        elif language is not None:
            lines.append(line)
    return out


def command_blocks() -> list[list[tuple[int, str]]]:
    """The shell blocks, each a list of (line number, command) without comments and set-up steps; a block's commands
    run in order (a later one may read what an earlier one wrote)."""
    out = []
    for language, start, text in blocks():
        if language not in ("sh", "bash", "console"):
            continue
        block = []
        for offset, line in enumerate(text.splitlines()):
            command = re.sub(r"\s+#.*$", "", line).strip()
            if not command or command.startswith("#"):
                continue
            steps = [s.strip() for s in command.split("&&")]
            kept = [s for s in steps if not SETUP.match(s)]
            if kept:
                block.append((start + offset, " && ".join(kept)))
        if block:
            out.append(block)
    return out


def commands() -> list[tuple[int, str]]:
    """(line number, command) of every shell command."""
    return [command for block in command_blocks() for command in block]


def python_blocks() -> list[tuple[int, str]]:
    return [(start, text) for language, start, text in blocks() if language == "python"]


@pytest.fixture(scope="module")
def scratch(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("readme")
    for name in ("examples", "robots", "catalogs"):
        (folder / name).symlink_to(ROOT / name)
    return folder


def _environment() -> dict[str, str]:
    env = dict(os.environ, MPLBACKEND="Agg")
    script_dir = str(Path(sys.executable).parent)
    env["PATH"] = script_dir + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _run(arguments: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(arguments, cwd=cwd, env=_environment(), capture_output=True, text=True, timeout=300)


def test_the_readme_has_commands_and_python_blocks():
    assert len(commands()) >= 20 and len(python_blocks()) >= 5
    assert shutil.which("mechatron", path=_environment()["PATH"]), "the mechatron command is not installed"


def test_every_command_runs(scratch):
    def run_block(block: list[tuple[int, str]]) -> list:
        return [(item, _run(["bash", "-c", item[1]], scratch)) for item in block]

    with ThreadPoolExecutor(max_workers=2) as pool:
        results = [result for block in pool.map(run_block, command_blocks()) for result in block]
    failed = [f"README line {line}: {command}\n  exit {r.returncode}: {(r.stderr or r.stdout).strip()[-400:]}"
              for (line, command), r in results if r.returncode != 0]
    assert not failed, "\n".join(failed)


def test_every_python_block_runs_on_its_own(scratch):
    todo = python_blocks()
    with ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(lambda item: (item, _run([sys.executable, "-c", item[1]], scratch)), todo))
    failed = [f"README block at line {line}:\n{r.stderr.strip()[-800:]}" for (line, _), r in results
              if r.returncode != 0]
    assert not failed, "\n".join(failed)

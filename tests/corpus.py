"""The bad-input corpus's harness: run the command line in-process on a bad input and assert it fails cleanly.

A clean failure (issue 13): exit status 2, nothing on stdout, exactly one line on stderr (file descriptors too: a
LAPACK or C-level message counts) that starts ``mechatron`` and names what is wrong (the option, file, row, field),
never ``internal error`` or a traceback, and every file in the working folder unchanged (no new file, no removed
file, no changed byte). ``run`` is the same without the assertions, for inputs that must succeed cleanly.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from mechatron.cli import main


@dataclass
class Outcome:
    code: int
    out: str
    err: str


def snapshot(folder: Path) -> dict[str, str]:
    """Every file below ``folder`` → the SHA-256 of its bytes (directories → ``"dir"``)."""
    out = {}
    for path in sorted(Path(folder).rglob("*")):
        key = str(path.relative_to(folder))
        out[key] = "dir" if path.is_dir() else hashlib.sha256(path.read_bytes()).hexdigest()
    return out


def run(argv: Sequence[str], capfd, cwd: Path | None = None) -> Outcome:
    """``mechatron ARGV`` in-process (in ``cwd``), with stdout and stderr captured at the file descriptors."""
    capfd.readouterr()
    old = Path.cwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:  # argparse
            code = exc.code if isinstance(exc.code, int) else 2
    finally:
        os.chdir(old)
    out, err = capfd.readouterr()
    return Outcome(code, out, err)


def assert_clean_error(argv: Sequence[str], capfd, folder: Path, names: str | Iterable[str] = (),
                       pattern: str | None = None) -> Outcome:
    """Run ``mechatron ARGV`` in ``folder`` and assert a clean failure whose one stderr line contains every one of
    ``names`` (and matches ``pattern``, a regular expression, if given); the files in ``folder`` are unchanged."""
    before = snapshot(folder)
    outcome = run(argv, capfd, folder)
    context = f"mechatron {' '.join(map(str, argv))}\nexit {outcome.code}\nstdout: {outcome.out!r}\nstderr: " \
              f"{outcome.err!r}"
    assert outcome.code == 2, context
    assert outcome.out == "", context
    lines = outcome.err.strip("\n").split("\n")
    assert len(lines) == 1 and lines[0].startswith("mechatron"), context
    assert "internal error" not in lines[0] and "Traceback" not in lines[0], context
    for name in [names] if isinstance(names, str) else names:
        assert name in lines[0], f"{context}\nmissing: {name!r}"
    if pattern is not None:
        assert re.search(pattern, lines[0]), f"{context}\nno match for {pattern!r}"
    assert snapshot(folder) == before, f"{context}\nfiles changed in {folder}"
    return outcome


#: The numeric edge values every numeric field is tried with.
EDGE_NUMBERS = ("nan", "inf", "-inf", "1e308", "-1e308", "1e-308", "-1", "abc", "")


def cli_error(capsys, *argv: str) -> tuple[int, str]:
    """(exit status, the one line on stderr) of the command line run in-process on ``argv`` (captured by pytest's
    ``capsys``), asserting that nothing went to stdout and stderr is one line without a traceback."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return code, err.strip()

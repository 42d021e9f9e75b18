"""The types a user sees: the package is typed (``py.typed``), its lazy names have their real types for a checker, the
public layers are mypy-clean and the count of mypy's errors in the rest does not grow.

mypy runs as a subprocess on the files ``[tool.mypy]`` of pyproject.toml configures (the whole package), once for
the module; its cache lives in the temporary folder, so a second run is warm (a few seconds; a cold one checks the
whole package in about half a minute of CPU time)."""

from __future__ import annotations

import ast
import hashlib
import importlib
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "mechatron"

#: The public layers: no mypy error in these files (paths relative to the repository, a folder ending in /).
PUBLIC = ("mechatron/__init__.py", "mechatron/_exports.py", "mechatron/errors.py", "mechatron/units.py",
          "mechatron/quantities.py", "mechatron/model/", "mechatron/kinematics/", "mechatron/dynamics/",
          "mechatron/drives/sizing.py", "mechatron/drives/options.py", "mechatron/optimal/")

#: mypy's errors in the whole package at most (all in the layers outside PUBLIC). Lower it when the count falls.
MOST_ERRORS = 449

#: The packages whose names load on first use (PEP 562): each re-imports them under ``if TYPE_CHECKING:``.
LAZY_PACKAGES = ("mechatron", "mechatron.kinematics", "mechatron.dynamics")

ERROR = re.compile(r"^(?P<path>[^:\n]+):(?P<line>\d+): error: (?P<message>.*)$", re.MULTILINE)
REVEALED = re.compile(r"^[^:\n]+:(?P<line>\d+): note: Revealed type is \"(?P<type>.*)\"$", re.MULTILINE)


def _mypy(*arguments: str) -> str:
    """mypy's report (stdout) run from the repository root with the project's configuration."""
    cache = Path(tempfile.gettempdir()) / f"mechatron-mypy-{hashlib.sha1(str(ROOT).encode()).hexdigest()[:12]}"
    result = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(cache), *arguments], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode in (0, 1), f"mypy did not run:\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture(scope="module")
def errors() -> list[tuple[str, str]]:
    """(path, line: message) of every error mypy finds in the configured files."""
    report = _mypy()
    assert re.search(r"^(Success: no issues found|Found \d+ errors?) ", report, re.MULTILINE), report[-2000:]
    return [(m["path"].replace("\\", "/"), f"{m['line']}: {m['message']}") for m in ERROR.finditer(report)]


def test_the_public_layers_are_clean(errors):
    public = [f"{path}:{where}" for path, where in errors if path.startswith(PUBLIC)]
    assert not public, f"{len(public)} mypy errors in the public layers:\n" + "\n".join(public)


def test_the_errors_in_the_rest_do_not_grow(errors):
    assert len(errors) <= MOST_ERRORS, (
        f"mypy finds {len(errors)} errors in the package, more than the {MOST_ERRORS} pinned in this test: type the "
        "new code (or lower the pin where the count fell)")


def _type_only_names(package: str) -> dict[str, str]:
    """What ``package``'s ``if TYPE_CHECKING:`` block imports: {name: its module, relative to the package}."""
    path = PACKAGE.parent / Path(*package.split(".")) / "__init__.py"
    names = {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            for item in node.body:
                assert isinstance(item, ast.ImportFrom) and item.level == 1, ast.unparse(item)
                for alias in item.names:
                    assert alias.asname == alias.name, f"{package}: import {alias.name} as itself (re-exported)"
                    names[alias.name] = f".{item.module}"
    return names


@pytest.mark.parametrize("package", LAZY_PACKAGES)
def test_the_type_only_imports_are_the_lazy_names(package):
    """A checker sees each lazy name where it loads from: the ``TYPE_CHECKING`` imports are the exports."""
    assert _type_only_names(package) == importlib.import_module(package)._EXPORTS


def test_a_user_sees_the_real_types(tmp_path):
    """The package is marked typed, and a user's checker sees every lazy name's own type, not ``Any``: e.g.
    ``mechatron.load`` a function returning a :class:`~mechatron.model.Mechanism`."""
    assert (PACKAGE / "py.typed").is_file()
    names = [(package, name) for package in LAZY_PACKAGES for name in importlib.import_module(package)._EXPORTS]
    user = tmp_path / "user.py"
    user.write_text("import mechatron\nimport mechatron.dynamics\nimport mechatron.kinematics\n\n"
                    + "".join(f"reveal_type({package}.{name})\n" for package, name in names), encoding="utf-8")
    report = _mypy(str(user))
    revealed = {int(m["line"]): m["type"] for m in REVEALED.finditer(report)}
    first = 5  # the line of the first reveal_type
    assert len(revealed) == len(names), report
    untyped = [f"{package}.{name}" for k, (package, name) in enumerate(names) if revealed[first + k] == "Any"]
    assert not untyped, f"Any to a user: {', '.join(untyped)}"
    assert revealed[first + names.index(("mechatron", "load"))].endswith("-> mechatron.model.mechanism.Mechanism")
    assert [m.group(0) for m in ERROR.finditer(report) if m["path"].endswith("user.py")] == []

"""The package's architecture: folders are layers that import only downward, with no import cycle, and every
module imports on its own."""

from __future__ import annotations

import ast
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

from mechatron.cli import COMMANDS, build_parser

PACKAGE = Path(__file__).resolve().parent.parent / "mechatron"

#: Layers from the bottom; a module may import from its own layer's package or from lower layers.
LAYERS = [
    ("errors", "units", "_exports"),
    ("io", "quantities"),
    ("report",),
    ("model",),
    ("kinematics",),
    ("dynamics",),
    ("mechanics", "structure"),
    ("drives", "accuracy"),
    ("machines",),
    ("library",),
    ("studies",),
    ("optimal",),
    ("cli",),
    ("__main__",),
]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}


def modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def _runtime_nodes(tree: ast.AST):
    """Every node of ``tree`` except those under ``if TYPE_CHECKING:`` (imports for annotations only)."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            yield from (n for child in node.orelse for n in [child, *_runtime_nodes(child)])
            continue
        yield node
        yield from _runtime_nodes(node)


def imported(name: str, path: Path, annotations: bool = False) -> set[str]:
    """Every mechatron module ``name`` imports when it runs, at the top or inside functions (``annotations``: and
    those it imports for annotations only, under ``if TYPE_CHECKING:``)."""
    is_package = path.name == "__init__.py"
    package = name if is_package else name.rsplit(".", 1)[0]
    out = set()
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree) if annotations else _runtime_nodes(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("mechatron"):
                submodules = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in MODULES]
                out.update(submodules)  # "from . import x" imports the module x
                if len(submodules) < len(node.names):  # names defined in the package (or module) itself
                    out.add(target)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("mechatron"))
    return {m for m in out if m in MODULES and m != name}


MODULES = modules()


def layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


IMPORT_EACH_ALONE = """
import importlib, sys, traceback
failed = []
for name in sys.argv[1:]:
    for loaded in [m for m in sys.modules if m == "mechatron" or m.startswith("mechatron.")]:
        del sys.modules[loaded]  # every module starts from no mechatron module imported
    try:
        importlib.import_module(name)
    except Exception:
        failed.append(name + ": " + traceback.format_exc().strip().splitlines()[-1])
print("\\n".join(failed))
"""


def test_every_module_imports_alone():
    names = [name for name in MODULES if name != "mechatron.__main__"]
    result = subprocess.run([sys.executable, "-c", IMPORT_EACH_ALONE, *names], capture_output=True, text=True,
                            check=True)
    assert not result.stdout.strip(), result.stdout


def test_layers_import_only_downward():
    wrong = []
    for name, path in MODULES.items():
        here = layer(name)
        if here == "__init__":  # the facade: lazy names only
            continue
        assert here in RANK, f"{name}: the folder {here} is not in the layer list"
        for target in imported(name, path):
            there = layer(target)
            if there == "__init__":
                if target == "mechatron" and here == "cli":  # the version string
                    continue
                wrong.append(f"{name} imports the facade {target}")
            elif there != here and RANK[there] > RANK[here] or (RANK[there] == RANK[here] and there != here):
                wrong.append(f"{name} ({here}) imports {target} ({there})")
    assert not wrong, "\n".join(wrong)


def test_import_graph_is_acyclic():
    graph = {name: imported(name, path) for name, path in MODULES.items()}
    state: dict[str, int] = {}
    cycle: list[str] = []

    def visit(node: str, trail: list[str]) -> bool:
        state[node] = 1
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle.extend(trail[trail.index(nxt):] + [node, nxt] if nxt in trail else [node, nxt])
                return True
            if state.get(nxt) is None and visit(nxt, trail + [node]):
                return True
        state[node] = 2
        return False

    for name in graph:
        if state.get(name) is None and visit(name, []):
            break
    assert not cycle, " -> ".join(cycle)



def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles of ``graph`` (module → the modules it imports): its strongly connected components of more
    than one module (Tarjan's algorithm), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for nxt in graph[node]:
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = stack[stack.index(node):]
            del stack[stack.index(node):]
            if len(component) > 1:
                out.append(sorted(component))

    for name in sorted(graph):
        if name not in index:
            visit(name)
    return out


def test_circles_finds_the_strongly_connected_components():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a", "e"}, "e": {"d"}, "f": set()}
    assert sorted(circles(graph)) == [["a", "b", "c"], ["d", "e"]]


def test_no_type_only_import_circle():
    """With the imports for annotations only (``if TYPE_CHECKING:``) no two modules import
    each other, not even for a type: a type lives in the module it belongs to, or a protocol stands for it."""
    found = circles({name: imported(name, path, annotations=True) for name, path in MODULES.items()})
    assert not found, "\n".join(" <-> ".join(c) for c in found)


@pytest.mark.parametrize("heavy", ["pandas", "matplotlib", "casadi"])
def test_import_mechatron_is_light(heavy):
    code = f"import sys, mechatron, mechatron.model, mechatron.kinematics; print({heavy!r} in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False", f"import mechatron imports {heavy}"


#: Modules a real command of a shipped robot or mechanism needs none of (benchmarks/startup.py times its start-up).
HEAVY = ("pandas", "scipy", "matplotlib", "casadi", "dask", "distributed", "pyarrow", "example_robot_data",
         "importlib.metadata")

RUN_COMMAND = """
import contextlib, io, json, sys
from mechatron.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    status = main(sys.argv[2:])
print(json.dumps({"status": status, "output": out.getvalue(), "loaded": [m for m in json.loads(sys.argv[1])
                                                                        if m in sys.modules]}))
"""


@pytest.mark.parametrize("command", [["fk", "puma560", "--q", "0,0,0,0,0,0"], ["fk", "crank_slider", "--q", "1,0,0"],
                                     ["show", "examples/data/four_bar.toml"]], ids=" ".join)
def test_a_real_command_of_a_shipped_file_is_light(command):
    """A command's start-up imports what it uses: the pose of a shipped robot or linkage, or a mechanism file's
    summary, imports no pandas, SciPy, matplotlib, CasADi, Dask or Arrow, and does not look for example-robot-data;
    only its own command module is imported, and its parser alone is built."""
    code = RUN_COMMAND + "print(sorted(m for m in sys.modules if m.startswith('mechatron.cli.')), file=sys.stderr)"
    result = subprocess.run([sys.executable, "-c", code, json.dumps(HEAVY), *command], capture_output=True, text=True,
                            check=True, cwd=PACKAGE.parent)
    out = json.loads(result.stdout)
    assert out["status"] == 0 and out["output"].strip(), out
    assert not out["loaded"], f"mechatron {' '.join(command)} imports {', '.join(out['loaded'])}"
    commands = {m.rsplit(".", 1)[1] for m in ast.literal_eval(result.stderr.strip().splitlines()[-1])}
    assert commands <= {"common", "values", COMMANDS[command[0]]}, commands


def test_each_command_has_its_module_and_builds_alone():
    """The command line builds a command's parser alone (:func:`mechatron.cli.build_parser` with its name): every
    command of the whole parser is in :data:`mechatron.cli.COMMANDS`, in its order, and its own parser parses and
    describes it exactly as the whole parser's does."""
    whole = _subparsers(build_parser())
    assert list(whole) == list(COMMANDS)
    for name, parser in whole.items():
        alone = _subparsers(build_parser(name))
        assert name in alone and set(alone) == {n for n, m in COMMANDS.items() if m == COMMANDS[name]}
        assert alone[name].format_help() == parser.format_help()
        assert [(a.option_strings, a.dest, a.default, a.required) for a in alone[name]._actions] == \
            [(a.option_strings, a.dest, a.default, a.required) for a in parser._actions]


def _subparsers(parser) -> dict:
    import argparse

    return next(dict(a.choices) for a in parser._actions if isinstance(a, argparse._SubParsersAction))


def test_the_public_api_is_small_and_resolves():
    import mechatron

    names = [n for n in mechatron.__all__ if not n.startswith("__")]
    assert len(names) <= 24
    for name in names:
        assert getattr(mechatron, name) is not None
    assert importlib.import_module("mechatron.kinematics").point_velocity is not None

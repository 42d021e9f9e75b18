r"""The design file (TOML, docs/design_file.md): optimal design of any mechanism over the study's vocabulary.

A design problem is a mechanism (a shipped name or any file a user writes: robot file, URDF, planar or spatial
mechanism file), **variables** (named parameters of the mechanism with bounds, or lists of values — also of an
analysis option such as a catalog file, ``target = "ANALYSIS.OPTION"``), one or two **objectives** and
**requirements** on the outputs of the study analyses of its ``[analyses.NAME]`` tables (docs/study_analyses.md)::

    mechanism = "my_crank.toml"
    [variables]
    l1 = [0.08, 0.12]            # m (SI), or a table as a study parameter: { low_mm = 80, high_mm = 120 }
    l2 = [0.35, 0.45]
    [objective]
    minimize = "reach_m"          # or maximize; two names (a list, or minimize and maximize): a Pareto front
    [requirements]
    x_travel_m = { min = 0.2 }    # bounds on any outputs
    slider = { output = "reach_m", at = "crank up", min = 0.38 }   # an output at a named pose
    [[poses]]                     # named poses of the linkage analysis (its option poses)
    name = "crank up"
    inputs = { q1 = 2.0 }         # the inputs held (m, rad); the others swept
    [analyses.linkage]
    samples = 13

:func:`design_problem` reads it (from :func:`mechatron.optimal.reader.read_problem`, which parses the file once) with
the study file's own readers (:mod:`mechatron.studies.spec`: the mechanism loader, the analyses, the ranges, their path
rule — paths relative to the file) and checks everything before any design is evaluated, one
:class:`~mechatron.errors.InputError` naming the file and the field otherwise: a variable that is no parameter of the
mechanism, inverted, equal or non-finite bounds, a start outside them, an objective or requirement that is no output of
the chosen analyses (the outputs listed), a discrete choice naming a missing file (the analyses' own checks of every
value), an evaluation budget beyond :data:`MAX_EVALUATIONS`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..io.schema import FieldReader
from ..studies.evaluator import Evaluator
from ..studies.spec import Range, check_analyses, input_files, output_names, read_analyses, read_mechanism, read_range
from .problem import Analyses, Bound, Problem

#: Directions of an objective.
GOALS = ("minimize", "maximize")
#: The methods: ``auto`` picks ``ipopt`` (exact derivatives) where every objective and requirement has them and
#: every variable is a range of the mechanism's geometry, else ``global`` (one objective) or ``nsga2`` (two).
METHODS = ("auto", "ipopt", "global", "nsga2")
#: The most evaluations of one problem: each is a design through the analyses (milliseconds to a second).
MAX_EVALUATIONS = 1_000_000


def design_problem(reader: FieldReader, path: Path) -> Problem:
    """Check a parsed design file (``reader`` over the file at ``path``; the module docstring)."""
    folder = path.resolve().parent
    name = reader.string("name", path.stem)
    reader.string("description", "")
    mechanism, mech = read_mechanism(reader, folder)
    analyses = read_analyses(reader, folder)
    poses = _poses(reader, analyses)
    variables = tuple(read_variables(reader, mech, analyses, folder))
    evaluator = Evaluator(mechanism, analyses, variables)
    _checked_analyses(evaluator, mech, str(path), bool(poses))
    outputs = tuple(output_names(evaluator, mech))
    objectives = _objectives(reader, outputs)
    requirements = _requirements(reader, outputs, poses)
    start = read_start(reader, list(variables))
    solver = _solver(reader, len(objectives), len(variables))
    reader.finish()
    return Problem(str(path), name, mechanism, variables, objectives,
                   Analyses(analyses, outputs, tuple(input_files(evaluator, mech))), requirements, start, **solver)


def _checked_analyses(evaluator: Evaluator, mech: Any, file: str, poses: bool = False) -> None:
    """The analyses' checks of every set of options the variables give them (:func:`~mechatron.studies.spec.
    variants`), an error naming the variable (``variables.NAME``) where a value of one is refused, or the file's
    ``poses[k]`` (``poses``: the file has ``[[poses]]``)."""
    try:
        check_analyses(evaluator, mech, file)
    except InputError as exc:
        field_name = exc.field or ""
        if poses and field_name.startswith("analyses.linkage.poses["):
            field_name = field_name.removeprefix("analyses.linkage.")  # the file's [[poses]]
        if field_name.startswith("parameters."):
            field_name = "variables." + field_name.removeprefix("parameters.").split(".values")[0]
        for p in evaluator.parameters:
            if p.target and field_name == f"analyses.{p.target}":
                field_name = f"variables.{p.name}"
        raise InputError(exc.message, file=exc.file, field=field_name or None) from None


def read_variables(reader: FieldReader, mech: Any, analyses: dict, folder: Path,
                   known: tuple[str, ...] | None = None) -> list[Range]:
    """``[variables]``: ``NAME = [lower, upper]`` (SI) or a table as a study's ``[parameters.NAME]``; with
    ``known`` (a named problem's variables) only those, as ranges."""
    variables = _variables(reader, mech, analyses, folder)
    for p in variables if known is not None else ():
        if known is not None and p.name not in known:
            raise InputError(f"not a design variable of this objective; choose from: {', '.join(known)}",
                             file=reader.file, field=f"variables.{p.name}")
        if p.values is not None:
            raise InputError("a variable of this objective is a range: NAME = [lower, upper]", file=reader.file,
                             field=f"variables.{p.name}")
    return variables


def _variables(reader: FieldReader, mech: Any, analyses: dict, folder: Path) -> list[Range]:
    table = reader.table("variables", None)
    if table is None or not table.data:
        raise reader.error("variables", "give at least one design variable: NAME = [lower, upper] (SI) with NAME a "
                                        f"parameter of {mech.name} ({', '.join(mech.parameters)})")
    out = []
    for name in list(table.data):
        if isinstance(table.data[name], dict):
            sub = table.table(name)
            out.append(read_range(sub, name, mech.parameters, analyses, mech.name, folder))
            sub.finish()
            continue
        if name not in mech.parameters:
            raise table.error(name, f"unknown parameter of {mech.name}; its parameters: {', '.join(mech.parameters)}")
        lower, upper = (float(v) for v in table.vector(name, 2))
        if not lower < upper:
            raise table.error(name, f"empty range [{lower:g}, {upper:g}]: the lower bound must be below the upper")
        out.append(Range(name, lower, upper))
    table.finish()
    return out


def _names(table: FieldReader, key: str) -> list[str]:
    raw = table.raw(key)
    names = [raw] if isinstance(raw, str) else raw
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise table.error(key, f"expected an output's name or a list of them, got {raw!r}")
    return names


def _known(table: FieldReader, key: str, name: str, outputs: tuple[str, ...]) -> None:
    if name not in outputs:
        raise table.error(key, f"unknown output {name!r}; the outputs of the analyses: {', '.join(outputs)}")


def _objectives(reader: FieldReader, outputs: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    """``[objective]``: ``minimize`` and/or ``maximize``, each an output or a list; one or two in all."""
    table = reader.table("objective", None)
    if table is None:
        raise reader.error("objective", "missing: give [objective] minimize = \"OUTPUT\" (or maximize)")
    if table.has("type"):
        raise table.error("type", "a design file with [analyses] states its objective as minimize = \"OUTPUT\" "
                                  "or maximize = \"OUTPUT\"; type = ... is the named problems' form "
                                  "(docs/optimize_file.md)")
    out: list[tuple[str, str]] = []
    for key in [k for k in table.data if k in GOALS]:
        for name in _names(table, key):
            _known(table, key, name, outputs)
            if any(name == n for n, _ in out):
                raise table.error(key, f"{name!r} is an objective twice")
            out.append((name, key))
    table.finish()
    if not out:
        raise reader.error("objective", "give minimize = \"OUTPUT\" or maximize = \"OUTPUT\"")
    if len(out) > 2:
        raise reader.error("objective", f"at most two objectives (a Pareto front), got {len(out)}")
    return tuple(out)


def _poses(reader: FieldReader, analyses: dict[str, dict[str, Any]]) -> tuple[str, ...]:
    """``[[poses]]``: named poses (``name``, ``inputs = { INPUT = value }``, ``point``, ``lowest`` or ``highest``),
    handed to the linkage analysis as its ``poses`` option (docs/study_analyses.md); their names."""
    if not reader.has("poses"):
        return ()
    tables = reader.tables("poses")
    if "linkage" not in analyses:
        raise reader.error("poses", "named poses are of the linkage analysis: add an [analyses.linkage] table")
    if analyses["linkage"].get("poses") is not None:
        raise reader.error("poses", "give the poses in [[poses]] or as [analyses.linkage] poses, not both")
    given = []
    for table in tables:
        given.append({k: table.raw(k) for k in list(table.data)})
    analyses["linkage"] = {**analyses["linkage"], "poses": given}
    return tuple(str(p.get("name")) for p in given if isinstance(p, dict))


def _requirements(reader: FieldReader, outputs: tuple[str, ...], poses: tuple[str, ...] = ()
                  ) -> tuple[Bound, ...]:
    """``[requirements]``: ``OUTPUT = { min = a, max = b }`` (either or both); with ``at = "POSE"`` the output at
    that named pose (``POSE.OUTPUT``), and with ``output = "OUTPUT"`` the key is a label of one's own."""
    table = reader.table("requirements", None)
    if table is None:
        return ()
    out = []
    for key in list(table.data):
        if not isinstance(table.data[key], dict):
            raise table.error(key, f"expected {{ min = ..., max = ... }}, got {table.data[key]!r}")
        sub = table.table(key)
        name = sub.string("output", key)
        at = sub.string("at", "")
        if at:
            if at not in poses:
                raise sub.error("at", f"no pose {at!r}; the poses: {', '.join(poses) or 'none ([[poses]])'}")
            name = f"{at}.{name}"
        _known(table, key, name, outputs)
        low, high = sub.number("min", None), sub.number("max", None)
        sub.finish()
        if low is None and high is None:
            raise table.error(key, "give min, max or both")
        if low is not None and high is not None and not low <= high:
            raise table.error(key, f"min {low:g} is above max {high:g}")
        out.append(Bound(name, low, high))
    table.finish()
    return tuple(out)


def read_start(reader: FieldReader, variables: list[Range]) -> dict[str, float]:
    """``[start]``: a value (SI) per ranged variable, inside its bounds."""
    table = reader.table("start", None)
    if table is None:
        return {}
    ranges = {p.name: p for p in variables if p.values is None}
    out = {}
    for name in list(table.data):
        if name not in ranges:
            raise table.error(name, "not a ranged design variable (give it in [variables] as [lower, upper] first)")
        value, (low, high) = table.number(name), ranges[name].bounds
        if not low <= value <= high:
            raise table.error(name, f"{value:g} is outside the bounds [{low:g}, {high:g}]")
        out[name] = value
    table.finish()
    return out


def _solver(reader: FieldReader, objectives: int, variables: int) -> dict[str, Any]:
    """``[solver]``: ``method``, ``evaluations``, ``population``, ``seed``, ``max_iterations``, ``tolerance``."""
    table = reader.table("solver", FieldReader({}, file=reader.file, path="solver"))
    method = table.string("method", "auto", choices=METHODS)
    if method == "nsga2" and objectives != 2:
        raise table.error("method", "nsga2 finds a Pareto front of two objectives; this file has one")
    if method in ("ipopt", "global") and objectives != 1:
        raise table.error("method", f"{method} minimises one objective; for two use nsga2 (or auto)")
    population = table.whole("population", max(16, 4 * variables), minimum=5)
    evaluations = table.whole("evaluations", max(400, 4 * population), minimum=1)
    if evaluations > MAX_EVALUATIONS:
        raise table.error("evaluations", f"{evaluations:,} evaluations; a problem has at most {MAX_EVALUATIONS:,}")
    if population > evaluations:
        raise table.error("population", f"{population} designs a generation exceed the {evaluations} evaluations")
    out: dict[str, Any] = {"method": method, "evaluations": evaluations, "population": population,
                           "seed": table.whole("seed", 0, minimum=0),
                           "max_iterations": table.whole("max_iterations", 100, minimum=1),
                           "tolerance": table.number("tolerance", 1e-8, positive=True)}
    if not math.isfinite(out["tolerance"]):  # pragma: no cover - number() refuses it
        raise table.error("tolerance", "must be finite")
    table.finish()
    return out

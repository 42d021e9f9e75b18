"""The study file (TOML, docs/study_file.md): which mechanism, which parameters over which ranges or values, how the
designs are drawn, which analyses run on every design and what the result shows.

:func:`read_study` checks everything before any design runs — the mechanism loads, every parameter is one of its
named parameters (or an analysis option: ``target = "ANALYSIS.OPTION"``), every range is non-empty, every analysis
is known and its ``check`` accepts the mechanism and the options (with every value of a targeted list), the
``[output.pareto]`` axes are among the analyses' outputs — and raises one :class:`~mechatron.errors.InputError`
naming the file and the field otherwise. The :class:`StudySpec` it returns is plain, picklable data: a worker
rebuilds the mechanism from ``StudySpec.mechanism`` and a design's overrides.

A study's identity (:mod:`mechatron.studies.runner`) is :meth:`StudySpec.digest` — the fields that decide its rows, not
the output settings — and the bytes of every file it reads, ``StudySpec.files``: the mechanism's file, the CSV of
designs and each analysis' files (:func:`input_files`).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..io.schema import FieldReader, field_suffixes
from .evaluator import Evaluator, analysis_options, design_geometry, mechanism_files, study_mechanism
from .ranges import Range

#: The ways designs are drawn (:mod:`mechatron.studies.designs`).
METHODS = ("grid", "lhs", "sobol", "csv")
#: Unit suffixes of ``low``, ``high`` and ``values`` → factor to SI (of the one unit table:
#: :func:`~mechatron.io.schema.field_suffixes`): none, ``_mm`` and ``_deg``.
UNIT_SUFFIXES = {**field_suffixes("length", "mm"), **field_suffixes("angle", "deg")}
#: Directions of a Pareto axis.
GOALS = ("minimize", "maximize")
#: The fields of a :class:`StudySpec` that do not decide its rows: the file's name, what the result shows (recomputed
#: from the table of a finished study) and the files read (their bytes are compared apart, to name the one that
#: changed).
NOT_ROWS = ("file", "pareto", "sensitivity", "files")


@dataclass(frozen=True)
class StudySpec:
    """A checked study file. Paths (the mechanism file, a CSV of designs, file names among option values) are
    absolute; ``analyses`` maps each analysis to its options in the file's order."""

    file: str
    mechanism: str
    parameters: tuple[Range, ...]
    method: str = "lhs"
    samples: int | None = None
    levels: int | None = None
    csv: str | None = None
    seed: int = 0
    analyses: dict[str, dict[str, Any]] = field(default_factory=dict)
    pareto: tuple[str, str, str, str] | None = None  # x, x goal, y, y goal
    sensitivity: bool = False
    files: tuple[str, ...] = ()

    def digest(self) -> str:
        """SHA-256 of the fields that decide the study's rows (not those of :data:`NOT_ROWS`)."""
        data = {k: v for k, v in asdict(self).items() if k not in NOT_ROWS}
        return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()

    def options(self, name: str, design: dict[str, Any]) -> dict[str, Any]:
        """The options of analysis ``name`` for one design: the file's, with the targeted parameters' values."""
        return analysis_options(self.analyses, self.parameters, name, design)

    def geometry(self, design: dict[str, Any]) -> dict[str, float]:
        """The mechanism's parameters a design overrides (m, rad)."""
        return design_geometry(self.parameters, design)

    @property
    def evaluator(self) -> Evaluator:
        """The evaluation of this study's designs (:class:`~mechatron.studies.evaluator.Evaluator`)."""
        return Evaluator(self.mechanism, self.analyses, self.parameters)


def spec_path(folder: Path, name: str) -> Path:
    """The one path rule of study, design and optimisation files: a file they name is relative to their own folder
    (an absolute path as it is), links kept (a file read through a link is named as it is read). A study's spec
    holds them absolute (:func:`absolute`): its workers may run elsewhere."""
    return Path(folder) / name


def absolute(path: Path) -> str:
    """``path`` made absolute (from the working folder), links kept."""
    return os.path.abspath(path)


def file_field(reader: FieldReader, key: str, folder: Path, default: Path | None = None,
               what: str = "file") -> Path:
    """The file a field names (:func:`spec_path`), ``default`` when left out; one that does not exist is an error
    naming the field."""
    given = reader.string(key, "")
    path = spec_path(folder, given) if given else default
    if path is None or not Path(path).is_file():
        raise reader.error(key, f"no such {what}: {path if path is not None else given}")
    return Path(path)


def _resolve(value: Any, folder: Path) -> Any:
    """A string naming a file relative to the study file's folder → its absolute path; anything else as it is."""
    if isinstance(value, str) and value and spec_path(folder, value).is_file():
        return absolute(spec_path(folder, value))
    return value


def _quantity(reader: FieldReader, key: str) -> tuple[str, float] | None:
    """Which of ``key``, ``key_mm``, ``key_deg`` is given (one at most) and its factor to SI."""
    given = [(key + s, f) for s, f in UNIT_SUFFIXES.items() if reader.has(key + s)]
    if len(given) > 1:
        raise reader.error(key, f"give only one of {' and '.join(k for k, _ in given)}")
    return given[0] if given else None


def read_range(reader: FieldReader, name: str, known: dict, analyses: dict, mech_name: str,
               folder: Path) -> Range:
    target = reader.string("target", None)
    if target is None and name not in known:
        raise InputError(f"unknown parameter {name!r} of {mech_name} (its parameters: {', '.join(known)}; or give "
                         "target = \"ANALYSIS.OPTION\")", file=reader.file, field=reader.path)
    if target is not None:
        analysis, _, option = target.partition(".")
        if analysis not in analyses or not option:
            raise reader.error("target", f"must be ANALYSIS.OPTION with one of this study's analyses "
                                         f"({', '.join(analyses) or 'none'}), got {target!r}")
    values, bounds = _quantity(reader, "values"), [_quantity(reader, "low"), _quantity(reader, "high")]
    relative = reader.number("relative", None, positive=True)
    if values is not None:
        if any(bounds) or relative is not None:
            raise reader.error(values[0], "give either values or a range (low and high, or relative), not both")
        return Range(name, values=_values(reader, *values, folder, numeric=target is None), target=target)
    if relative is not None:
        if any(bounds) or target is not None:
            raise reader.error("relative", "relative (± a fraction of the nominal value) is for the mechanism's "
                                           "parameters, alone")
        nominal = known[name].value
        low, high = sorted((nominal * (1 - relative), nominal * (1 + relative)))
        if not low < high:
            raise reader.error("relative", f"gives an empty range: the nominal value of {name} is {nominal:g}")
        return Range(name, low, high, target=target)
    if not all(bounds):
        raise reader.error("low" if bounds[0] is None else "high", "missing: give low and high (SI, or _mm, "
                                                                   "_deg), relative, or values")
    low, high = (reader.number(k) * f for k, f in bounds)
    if not low < high:
        raise reader.error(bounds[0][0], f"empty range: low {low:g} must be < high {high:g} (SI)")
    return Range(name, low, high, target=target)


def _values(reader: FieldReader, key: str, factor: float, folder: Path, numeric: bool) -> tuple[Any, ...]:
    raw = reader.raw(key)
    if not isinstance(raw, list) or not raw:
        raise reader.error(key, f"expected a non-empty list, got {raw!r}")
    if all(isinstance(v, str) for v in raw) and not numeric:
        return tuple(_resolve(v, folder) for v in raw)
    values = tuple(reader.to_float(f"{key}[{i}]", v) * factor for i, v in enumerate(raw))
    if len(set(values)) != len(values):
        raise reader.error(key, "lists a value twice")
    return values


def _designs(reader: FieldReader, folder: Path, parameters: list[Range]) -> dict[str, Any]:
    method = reader.string("method", "lhs", choices=METHODS)
    out: dict[str, Any] = {"method": method, "seed": reader.whole("seed", 0, minimum=0)}
    if method in ("lhs", "sobol"):
        out["samples"] = reader.whole("samples", minimum=1)
        if method == "sobol" and out["samples"] & (out["samples"] - 1):
            raise reader.error("samples", f"must be a power of 2 for Sobol points (Saltelli's scheme gives "
                                          f"samples × (parameters + 2) designs), got {out['samples']}")
    if method == "grid":
        out["levels"] = reader.whole("levels", 5 if any(p.values is None for p in parameters) else None,
                                     minimum=2)
    if method == "csv":
        path = folder / reader.string("file")
        if not path.is_file():
            raise reader.error("file", f"no such file: {path}")
        out["csv"] = str(path.resolve())
    elif not parameters:
        raise InputError("no [parameters.NAME] to vary", file=reader.file, field="parameters")
    _count(reader, out, parameters)
    reader.finish()
    return out


#: The most designs of one study (its tables must fit in memory: ~100 bytes a cell).
MAX_DESIGNS = 10_000_000


def _count(reader: FieldReader, designs: dict[str, Any], parameters: list[Range]) -> None:
    """Refuse a study of more than :data:`MAX_DESIGNS` designs, naming the field that sets their number."""
    method = designs["method"]
    if method == "grid":
        count, key = math.prod(len(p.values) if p.values is not None else designs["levels"] for p in parameters), \
            "levels"
    elif method in ("lhs", "sobol"):
        count, key = designs["samples"] * ((len(parameters) + 2) if method == "sobol" else 1), "samples"
    else:
        return
    if count > MAX_DESIGNS:
        raise reader.error(key, f"gives {count:,} designs; a study has at most {MAX_DESIGNS:,}")


def _output(reader: FieldReader | None, method: str) -> dict[str, Any]:
    if reader is None:
        return {"pareto": None, "sensitivity": method == "sobol"}
    pareto = reader.table("pareto", None)
    if pareto is not None:
        axes = (pareto.string("x"), pareto.string("x_goal", "minimize", choices=GOALS),
                pareto.string("y"), pareto.string("y_goal", "minimize", choices=GOALS))
        pareto.finish()
        pareto = axes
    sensitivity = reader.boolean("sensitivity", method == "sobol")
    if sensitivity and method != "sobol":
        raise reader.error("sensitivity", "Sobol indices need [designs] method = \"sobol\" (Saltelli's scheme)")
    reader.finish()
    return {"pareto": pareto, "sensitivity": sensitivity}


def read_analyses(reader: FieldReader, folder: Path) -> dict[str, dict[str, Any]]:
    from .analyses import analysis

    tables = reader.raw("analyses")
    if not isinstance(tables, dict) or not tables:
        raise reader.error("analyses", "expected at least one [analyses.NAME] table (linkage, dynamics, sizing, "
                                       "accuracy)")
    out = {}
    for name, options in tables.items():
        try:
            analysis(name)
        except InputError as exc:
            raise InputError(exc.message, file=reader.file, field=f"analyses.{name}") from None
        if not isinstance(options, dict):
            raise reader.error(f"analyses.{name}", "expected a table [analyses.NAME] of options")
        out[name] = {k: _resolve(v, folder) for k, v in options.items()}
    return out


def read_mechanism(reader: FieldReader, folder: Path) -> tuple[str, Any]:
    given = reader.string("mechanism")
    where = absolute(spec_path(folder, given)) if spec_path(folder, given).is_file() else given
    try:
        return where, study_mechanism(where)
    except InputError as exc:
        if exc.file:
            raise
        raise InputError(exc.message, file=reader.file, field="mechanism") from None


def read_study(path: str | Path) -> StudySpec:
    """Read and check a study file (docs/study_file.md); see the module docstring for what is checked."""
    from ..io.toml import read_toml

    path = Path(path)
    reader = FieldReader(read_toml(path), file=path)
    folder = path.resolve().parent
    mechanism, mech = read_mechanism(reader, folder)
    analyses = read_analyses(reader, folder)
    tables = reader.table("parameters", {})
    parameters = []
    for name in (tables.data if isinstance(tables, FieldReader) else {}):
        table = tables.table(name)
        parameters.append(read_range(table, name, mech.parameters, analyses, mech.name, folder))
        table.finish()
    designs = _designs(reader.table("designs", FieldReader({}, file=path, path="designs")), folder, parameters)
    if designs["method"] == "csv":
        from .designs import read_designs_csv

        if parameters:
            raise InputError("a CSV of designs names its parameters in its columns: give no [parameters.NAME]",
                             file=path, field="parameters")
        columns = read_designs_csv(designs["csv"], mech.parameters).columns
        parameters = [Range(name) for name in columns]
    output = _output(reader.table("output", None), designs["method"])
    reader.finish()
    spec = StudySpec(str(path), mechanism, tuple(parameters), analyses=analyses, **designs, **output)
    check_analyses(spec, mech, spec.file)
    _check_pareto(spec, mech)
    return replace(spec, files=tuple(input_files(spec, mech, spec.csv)))


def variants(spec: StudySpec | Evaluator) -> Iterator[tuple[str, dict[str, Any], str | None]]:
    """(analysis, options, field) of every set of options the designs give an analysis, as far as its targeted
    lists go: the first value of every targeted parameter, then each further value of a targeted list with the others
    at their first; ``field`` names that value in the spec (``parameters.NAME.values[i]``), None for the first."""
    first = {p.name: p.pick(0.0) for p in spec.parameters if p.target}
    for name in spec.analyses:
        yield name, spec.options(name, first), None
        for p in spec.parameters:
            if p.target and p.target.split(".", 1)[0] == name and p.values is not None:
                for i, value in enumerate(p.values[1:], start=1):
                    yield name, spec.options(name, {**first, p.name: value}), f"parameters.{p.name}.values[{i}]"


def check_analyses(spec: StudySpec | Evaluator, mech: Any, file: str) -> None:
    """Each analysis' ``check`` on the nominal mechanism with every set of options of :func:`variants` (every file
    of a targeted list exists and reads)."""
    from .analyses import analysis

    for name, options, where in variants(spec):
        try:
            analysis(name).check(mech, options)
        except InputError as exc:
            if exc.file:
                raise
            field_name = where or f"analyses.{name}" + (f".{exc.field}" if exc.field else "")
            message = exc.message if where is None or not exc.field else f"{exc.field}: {exc.message}"
            raise InputError(message, file=file, field=field_name) from None


def output_names(spec: StudySpec | Evaluator, mech: Any) -> list[str]:
    """The output columns of the study's rows, in order: each analysis' ``output_names`` for every set of options
    of :func:`variants`."""
    from .analyses import analysis

    names = [n for name, options, _ in variants(spec) for n in analysis(name).output_names(mech, options)]
    return list(dict.fromkeys(names))


def _check_pareto(spec: StudySpec, mech: Any) -> None:
    """Refuse a Pareto axis that is neither an output of the analyses nor a numeric parameter, naming
    ``output.pareto.x`` or ``y`` and listing the known outputs."""
    if spec.pareto is None:
        return
    outputs = output_names(spec, mech)
    numeric = [p.name for p in spec.parameters
               if p.values is None or all(isinstance(v, (int, float)) for v in p.values)]
    for axis, column in (("x", spec.pareto[0]), ("y", spec.pareto[2])):
        if column not in outputs and column not in numeric:
            raise InputError(f"unknown output {column!r}; the analyses' outputs: {', '.join(outputs)}"
                             + (f" (or a parameter: {', '.join(numeric)})" if numeric else ""),
                             file=spec.file, field=f"output.pareto.{axis}")


def input_files(spec: StudySpec | Evaluator, mech: Any, csv: str | None = None) -> list[str]:
    """Every file the study's rows are computed from (absolute paths, each once): the mechanism's, the CSV of
    designs, and the files every analysis reads for every set of options of :func:`variants` (``input_files`` of
    the analysis: tasks and their trajectories, catalogs, tolerances, poses — given or default)."""
    from .analyses import analysis

    paths = [*mechanism_files(spec.mechanism), *([csv] if csv else [])]
    for name, options, _ in variants(spec):
        paths.extend(analysis(name).input_files(mech, options))
    return list(dict.fromkeys(str(Path(p).resolve()) for p in paths))

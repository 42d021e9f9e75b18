r"""Cost models of tolerances, for tolerance allocation (:mod:`~mechatron.accuracy.allocation`).

A row of a tolerances file (:mod:`~mechatron.accuracy.sources`) may say what its tolerance costs:

- a **continuous** cost [Chase, reciprocal power model]: C(t) = a + b / t^k (columns ``cost_a`` (default 0),
  ``cost_b`` (> 0), ``cost_k`` (> 0, default 1)), t measured in the unit of the row's bounds
  ``tolerance_min[_unit]`` and ``tolerance_max[_unit]`` (one unit for both: with ``tolerance_min_mm`` t is in mm
  and b in cost·mmᵏ), the tolerance chosen in [t_min, t_max];
- a **process table** (column ``process``): the name of a table of a processes file (:func:`read_processes`), its
  allowed tolerance values with their costs, the tolerance chosen among them [Chase, process selection];
- neither: the tolerance is fixed as the row gives it.

A cost must rise as the tolerance tightens: b > 0 and k > 0, and along a process table, sorted from the loosest
tolerance to the tightest, every cost above the one before. Costs are in one currency (or time) throughout, ≥ 0.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..io.tables import number, read_csv
from ..model.mechanism import Mechanism
from .sources import ANGLE_UNITS, LARGEST_ERROR, LENGTH_UNITS, SMALLEST_ERROR, ErrorSource, read_tolerances

#: The largest cost a model may give (at its tightest tolerance): beyond it a sum of costs loses its digits.
LARGEST_COST = 1e15
#: The largest exponent k of a continuous cost.
LARGEST_EXPONENT = 10.0
PROCESS_COLUMNS = ("process", "option", "cost", "note", "description", "label")


@dataclass(frozen=True)
class ContinuousCost:
    """C(t) = a + b / (t/u)^k for t in [lower, upper] (SI: m, rad), u = ``factor`` the SI value of the unit ``unit``
    the bounds were given in (b in cost·unitᵏ) [Chase, reciprocal power model]."""

    a: float
    b: float
    k: float
    unit: str
    factor: float
    lower: float
    upper: float

    def cost(self, tolerance: float) -> float:
        """The cost of the tolerance ``tolerance`` (SI)."""
        return self.a + self.b * (tolerance / self.factor) ** -self.k


@dataclass(frozen=True)
class ProcessTable:
    """The tolerances (SI, loosest first) a process table allows, their costs (rising), option names and units."""

    name: str
    tolerances: tuple[float, ...]
    costs: tuple[float, ...]
    options: tuple[str, ...]
    units: tuple[str, ...]
    kind: str  # "length", "angle" or "" (SI columns only: fits any source)


@dataclass(frozen=True)
class CostedSource:
    """An error source with its cost model (None: a fixed tolerance), the unit its tolerance is shown in (a unit
    suffix of :data:`mechatron.units.UNITS`, '' for SI) and whether the file gave its tolerance."""

    source: ErrorSource
    model: ContinuousCost | ProcessTable | None
    unit: str
    given: bool

    @property
    def factor(self) -> float:
        """The SI value of :attr:`unit`."""
        return (ANGLE_UNITS if self.source.unit == "rad" else LENGTH_UNITS).get(self.unit, 1.0)

    def continuous(self) -> ContinuousCost:
        """The continuous cost model (an error for another row)."""
        if not isinstance(self.model, ContinuousCost):
            raise TypeError(f"{self.source.name} has no continuous cost")
        return self.model

    def table(self) -> ProcessTable:
        """The process table (an error for another row)."""
        if not isinstance(self.model, ProcessTable):
            raise TypeError(f"{self.source.name} has no process table")
        return self.model

    def cost(self, tolerance: float) -> float:
        """The cost of ``tolerance`` (SI): the model's; of a process table, its cheapest option that holds it (a
        tolerance ≤ it; NaN if none does); 0 for a fixed row."""
        if isinstance(self.model, ContinuousCost):
            return self.model.cost(tolerance)
        if isinstance(self.model, ProcessTable):
            held = [c for t, c in zip(self.model.tolerances, self.model.costs) if t <= tolerance * (1 + 1e-9)]
            return held[0] if held else math.nan
        return 0.0


def _units(unit: str) -> Mapping[str, float]:
    return ANGLE_UNITS if unit == "rad" else LENGTH_UNITS if unit == "m" else {"": 1.0}


def _suffix(column: str, prefix: str) -> str:
    return column[len(prefix):].lstrip("_")


def _one(row: dict, columns: Sequence[str], path: Path, line: int, what: str) -> str | None:
    given = [c for c in columns if row.get(c)]
    if len(given) > 1:
        raise InputError(f"give the {what} in one column, not {' and '.join(given)}", file=path, row=line,
                         field=given[1])
    return given[0] if given else None


def _tolerance_value(text: str, factor: float, path: Path, line: int, column: str, unit: str) -> float:
    value = number(text, file=path, row=line, field=column) * factor
    if not SMALLEST_ERROR <= value <= LARGEST_ERROR:
        raise InputError(f"must be from {SMALLEST_ERROR:g} to {LARGEST_ERROR:g} {unit} (in SI), got {value:g} {unit}",
                         file=path, row=line, field=column)
    return value


def _continuous(row: dict, source: ErrorSource, columns: Sequence[str], path: Path, line: int) -> ContinuousCost:
    def value(name: str, default: float) -> float:
        return number(row[name], file=path, row=line, field=name) if row.get(name) else default

    a, b, k = value("cost_a", 0.0), value("cost_b", 0.0), value("cost_k", 1.0)
    if b <= 0:
        raise InputError(f"cost_b must be > 0, got {b:g}: with b <= 0 the cost a + b/t^k does not rise as the "
                         "tolerance tightens (a row without a cost model keeps its tolerance)", file=path, row=line,
                         field="cost_b")
    if not 0 < k <= LARGEST_EXPONENT:
        raise InputError(f"cost_k must be > 0 and <= {LARGEST_EXPONENT:g}, got {k:g}"
                         + (": with k <= 0 the cost does not rise as the tolerance tightens" if k <= 0 else ""),
                         file=path, row=line, field="cost_k")
    if a < 0:
        raise InputError(f"cost_a must be >= 0 (a cost), got {a:g}", file=path, row=line, field="cost_a")
    bounds = {}
    units = _units(source.unit)
    for prefix in ("tolerance_min", "tolerance_max"):
        column = _one(row, [c for c in columns if c.startswith(prefix)], path, line, prefix)
        if column is None:
            raise InputError(f"a cost_b row needs {prefix}[_unit], the {'tightest' if 'min' in prefix else 'loosest'}"
                             " tolerance it may get", file=path, row=line, field=prefix)
        suffix = _suffix(column, prefix)
        if suffix not in units:
            what = {"m": "a length", "rad": "an angle"}.get(source.unit, "a ratio")
            raise InputError(f"{what} cannot be given in {suffix}", file=path, row=line, field=column)
        bounds[prefix] = (column, suffix, _tolerance_value(row[column], units[suffix], path, line, column,
                                                           source.unit))
    (_, low_unit, low), (high_column, high_unit, high) = bounds["tolerance_min"], bounds["tolerance_max"]
    if low_unit != high_unit:
        raise InputError(f"give tolerance_min and tolerance_max in one unit (the cost's t is in it), not {low_unit!r} "
                         f"and {high_unit!r}", file=path, row=line, field=high_column)
    if not low < high:
        unit = low_unit or source.unit
        raise InputError(f"tolerance_max {high / units[low_unit]:g} {unit} must be above tolerance_min "
                         f"{low / units[low_unit]:g} {unit}", file=path, row=line, field=high_column)
    model = ContinuousCost(a, b, k, low_unit, units[low_unit], low, high)
    try:
        tightest = model.cost(low)
    except OverflowError:
        tightest = math.inf
    if not tightest <= LARGEST_COST:
        raise InputError(f"the cost at tolerance_min, {tightest:g}, is not a number up to {LARGEST_COST:g}",
                         file=path, row=line, field="cost_b")
    return model


def read_processes(path: str | Path) -> dict[str, ProcessTable]:
    """The process tables of a processes CSV: a row per allowed tolerance of a process — ``process`` (the table's
    name), ``option`` (a name for it, optional), the tolerance ``tolerance`` or ``tolerance_<unit>`` (> 0; one column
    per row), its ``cost`` (≥ 0). Along each table, from the loosest tolerance to the tightest, the cost must rise.

    Raises:
        InputError: naming the file, the row and the column of a bad value.
    """
    path = Path(path)
    frame = read_csv(path)
    tolerance_columns = []
    for column in frame.columns:
        if column == "tolerance" or column.startswith("tolerance_"):
            suffix = _suffix(column, "tolerance")
            if suffix not in LENGTH_UNITS and suffix not in ANGLE_UNITS:
                known = ", ".join(sorted(u for u in {**LENGTH_UNITS, **ANGLE_UNITS} if u))
                raise InputError(f"unknown unit {suffix!r} (known: {known})", file=path, field=column)
            tolerance_columns.append(column)
        elif column not in PROCESS_COLUMNS:
            raise InputError("unknown column (expected process, option, tolerance[_unit], cost)", file=path,
                             field=column)
    for column in ("process", "cost"):
        if column not in frame.columns:
            raise InputError(f"missing column {column!r}", file=path, field=column)
    if not tolerance_columns:
        raise InputError("missing column 'tolerance' (or tolerance_mm, …)", file=path, field="tolerance")
    rows: dict[str, list[tuple[float, float, str, str, int, str]]] = {}
    for line, row in zip(frame.index, frame.to_dict(orient="records")):
        name = row["process"]
        if not name:
            raise InputError("missing value", file=path, row=line, field="process")
        column = _one(row, tolerance_columns, path, line, "tolerance")
        if column is None:
            raise InputError("missing tolerance", file=path, row=line, field=tolerance_columns[0])
        suffix = _suffix(column, "tolerance")
        kind = "" if not suffix else "length" if suffix in LENGTH_UNITS else "angle"
        factor = LENGTH_UNITS[suffix] if kind == "length" else ANGLE_UNITS[suffix] if kind == "angle" else 1.0
        tolerance = _tolerance_value(row[column], factor, path, line, column, "m or rad")
        if not row["cost"]:
            raise InputError("missing value", file=path, row=line, field="cost")
        cost = number(row["cost"], file=path, row=line, field="cost")
        if not 0 <= cost <= LARGEST_COST:
            raise InputError(f"a cost must be from 0 to {LARGEST_COST:g}, got {cost:g}", file=path, row=line,
                             field="cost")
        rows.setdefault(name, []).append((tolerance, cost, row.get("option") or "", suffix, int(line), kind))
    return {name: _table(name, options, path) for name, options in rows.items()}


def _table(name: str, options: list[tuple[float, float, str, str, int, str]], path: Path) -> ProcessTable:
    kinds = {o[5] for o in options if o[5]}
    if len(kinds) > 1:
        line = next(o[4] for o in options if o[5] != options[0][5])
        raise InputError(f"process {name!r} mixes length and angle tolerances", file=path, row=line,
                         field="process")
    ordered = sorted(options, key=lambda o: -o[0])  # loosest first
    for looser, tighter in zip(ordered, ordered[1:]):
        shown = f"{tighter[0] / _factor(tighter[3]):g} {tighter[3] or 'SI'}"
        if tighter[0] == looser[0]:
            raise InputError(f"process {name!r} gives the tolerance {shown} twice (row {looser[4]})", file=path,
                             row=tighter[4], field="tolerance" + (f"_{tighter[3]}" if tighter[3] else ""))
        if not tighter[1] > looser[1]:
            raise InputError(f"the cost {tighter[1]:g} of the tolerance {shown} is not above the cost {looser[1]:g} "
                             f"of the looser tolerance {looser[0] / _factor(looser[3]):g} {looser[3] or 'SI'} (row "
                             f"{looser[4]}): a process's cost must rise as its tolerance falls", file=path,
                             row=tighter[4], field="cost")
    return ProcessTable(name, tuple(o[0] for o in ordered), tuple(o[1] for o in ordered),
                        tuple(o[2] for o in ordered), tuple(o[3] for o in ordered), kinds.pop() if kinds else "")


def _factor(suffix: str) -> float:
    return LENGTH_UNITS.get(suffix) or ANGLE_UNITS.get(suffix) or 1.0


def read_cost_models(path: str | Path, mech: Mechanism, processes: str | Path | Mapping[str, ProcessTable] | None = None
                     ) -> list[CostedSource]:
    """The error sources of the tolerances file ``path`` for ``mech`` with their cost models (module docstring);
    ``processes``: the process tables (a processes CSV path, or :func:`read_processes`' tables) the ``process``
    column names.

    Raises:
        InputError: naming the file, the row and the column of a bad value: a cost that does not rise as the
            tolerance tightens, a process table that is missing or does not fit the source.
    """
    path = Path(path)
    sources = read_tolerances(path, mech, "allocate")
    frame = read_csv(path)
    tables = read_processes(processes) if isinstance(processes, (str, Path)) else processes
    bounds = [c for c in frame.columns if c.startswith(("tolerance_min", "tolerance_max"))]
    tolerance_columns = [c for c in frame.columns if (c == "tolerance" or c.startswith("tolerance_"))
                         and c not in bounds]
    out = []
    for source, (line, row) in zip(sources, zip(frame.index, frame.to_dict(orient="records"))):
        line = int(line)
        given_column = next((c for c in tolerance_columns if row[c]), None)
        given = given_column is not None or bool(row.get("grade"))
        unit = _suffix(given_column, "tolerance") if given_column else ("um" if source.unit == "m" else
                                                                         "arcsec" if source.unit == "rad" else "")
        model: ContinuousCost | ProcessTable | None = None
        if row.get("cost_b") and row.get("process"):
            raise InputError("give cost_b or process, not both", file=path, row=line, field="process")
        if row.get("cost_b"):
            model = _continuous(row, source, bounds, path, line)
            unit = model.unit
        elif row.get("process"):
            model = _process(row["process"], source, tables, path, line)
            unit = model.units[0]
        else:
            extra = next((c for c in ("cost_a", "cost_k", *bounds) if row.get(c)), None)
            if extra is not None:
                raise InputError(f"{extra} needs cost_b (the cost model a + b/t^k)", file=path, row=line, field=extra)
        out.append(CostedSource(source, model, unit, given))
    return out


def _process(name: str, source: ErrorSource, tables: Mapping[str, ProcessTable] | None, path: Path, line: int
             ) -> ProcessTable:
    if tables is None:
        raise InputError(f"process {name!r} needs the process tables (--processes FILE)", file=path, row=line,
                         field="process")
    if name not in tables:
        known = ", ".join(sorted(tables)) or "none"
        raise InputError(f"no process table {name!r} (tables: {known})", file=path, row=line, field="process")
    table = tables[name]
    kind = {"m": "length", "rad": "angle"}.get(source.unit, "")
    if table.kind and table.kind != kind:
        raise InputError(f"process {name!r} gives {table.kind} tolerances but {source.name} is "
                         f"{'an angle' if kind == 'angle' else 'a length' if kind == 'length' else 'a ratio'}",
                         file=path, row=line, field="process")
    return table

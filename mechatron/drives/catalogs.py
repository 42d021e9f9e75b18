"""Catalogs of drive components in CSV files (schemas in ``catalogs/README.md``).

Each catalog kind has a schema: its fields, their kind of quantity (which fixes the accepted unit suffixes, see
:data:`mechatron.units.UNITS`), whether they are required, and their bounds. Reading a file checks every row and
every value and converts to SI; a problem raises :class:`~mechatron.errors.InputError` naming the file, the row
(as in a spreadsheet: the header is row 1) and the column.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..io.data import data_dir
from ..io.tables import number, read_csv
from ..model.robotfile import EFFICIENCY_MIN
from ..units import SI, UNITS, offset
from .motor import ELECTRICAL_COLUMNS
from .shafts import end_fixing


@dataclass(frozen=True)
class Field:
    """One column of a catalog: its name, kind of quantity (a key of :data:`mechatron.units.UNITS`), whether every
    row must give it, whether it must be > 0 (else ≥ 0), its largest value and its smallest (SI); ``table``: a cell
    holds ``x:y`` pairs separated by ``;``, x of the field's kind (its column's unit), y a plain number
    (:func:`_rate_table`). A field of kind ``count`` holds whole numbers."""

    name: str
    kind: str
    required: bool = True
    positive: bool = True  # > 0 (else >= 0)
    maximum: float | None = None
    minimum: float | None = None
    table: bool = False
    #: mechatron's plausible range (SI), its own rule (docs/catalogs.md, "Plausible ranges"): a value outside it is
    #: refused as a slip of unit or digit, not a product; ``None``: none beyond the bounds above.
    plausible: tuple[float, float] | None = None


#: mechatron's plausible range of a motor's thermal resistances (K/W): a motor of a few millimetres sheds its heat
#: through some 100 K/W, a large water-cooled one through 0.01 K/W.
THERMAL_RESISTANCE = (1e-3, 1e3)
#: mechatron's plausible range of a converter's efficiency: a worm or a lead screw loses most of its input, none
#: keeps less than 1 % (below it 1/η overflows the torque asked of the motor); a robot file's drive has the same.
EFFICIENCY = (EFFICIENCY_MIN, 1.0)
#: mechatron's plausible largest shock factor of a gearbox maker's table (the makers' tables stop below 3).
SHOCK_FACTOR_MAX = 10.0

SCHEMAS: dict[str, tuple[Field, ...]] = {
    "motors": (
        Field("key", "text"), Field("maker", "text", False), Field("series", "text", False),
        Field("rated_torque", "torque"), Field("peak_torque", "torque"), Field("rated_speed", "speed"),
        Field("max_speed", "speed"), Field("rotor_inertia", "inertia"),
        Field("torque_constant", "torque_constant", False), Field("rated_current", "current", False),
        Field("rated_power", "power", False), Field("resistance", "resistance", False),
        Field("voltage", "voltage", False),
        # the two-node thermal model (mechatron.drives.thermal): all five or none, with k_t and R (at 25 °C)
        Field("rth_winding_housing", "thermal_resistance", False, plausible=THERMAL_RESISTANCE),
        Field("rth_housing_ambient", "thermal_resistance", False, plausible=THERMAL_RESISTANCE),
        Field("tau_winding", "time", False, plausible=(1e-2, 1e4)), Field("tau_housing", "time", False,
                                                                           plausible=(1.0, 1e5)),
        Field("max_winding_temperature", "temperature", False, minimum=273.15, maximum=773.15),
        Field("temperature_coefficient", "temperature_coefficient", False, positive=False, maximum=0.1,
              plausible=(0.0, 0.01)),
        # k_t's temperature coefficient β (mechatron.drives.thermal: the magnets heat too), ≤ 0
        Field("torque_constant_coefficient", "temperature_coefficient", False, minimum=-0.01, maximum=0.0),
        Field("loss_torque", "torque", False, positive=False),
        Field("mass", "mass", False), Field("price", "money", False),
        # a holding brake (mechatron.drives.brakes): the holding torque wherever another brake column is given
        Field("brake_holding_torque", "torque", False), Field("brake_inertia", "inertia", False, positive=False),
        Field("brake_mass", "mass", False, positive=False), Field("brake_stop_energy", "energy", False),
        Field("brake_energy_per_h", "energy", False),
    ),
    "resistors": (  # braking resistors (mechatron.drives.resistors)
        Field("key", "text"), Field("maker", "text", False), Field("resistance", "resistance"),
        Field("continuous_power", "power"), Field("pulse_energy", "energy"), Field("pulse_time", "time"),
        Field("mass", "mass", False), Field("price", "money", False),
    ),
    "gearboxes": (
        Field("key", "text"), Field("maker", "text", False), Field("type", "text"),
        Field("stages", "count", False, plausible=(1, 10)), Field("ratio", "ratio", plausible=(1.0, 1e4)),
        Field("rated_torque", "torque"),
        Field("peak_torque", "torque"), Field("emergency_torque", "torque"), Field("max_input_speed", "speed"),
        Field("rated_input_speed", "speed"), Field("efficiency", "fraction", maximum=1.0, plausible=EFFICIENCY),
        Field("cycle_rating", "rate", False), Field("emergency_stops", "count", False),
        # the maker's rule of the peak torque (docs/catalogs.md, "Gearbox duty"; mechatron.drives.converters)
        Field("peak_rule", "text", False), Field("shock_factors", "rate", False, table=True),
        Field("input_inertia", "inertia"), Field("backlash", "angle", False, positive=False),
        Field("mass", "mass", False), Field("price", "money", False),
    ),
    "linear": (
        Field("key", "text"), Field("maker", "text", False), Field("type", "text"), Field("diameter", "length"),
        Field("lead", "length"), Field("efficiency", "fraction", maximum=1.0, plausible=EFFICIENCY),
        Field("inertia", "inertia", False),
        Field("inertia_per_length", "inertia_per_length", False), Field("max_speed", "speed"),
        Field("dynamic_load", "force", False), Field("root_diameter", "length", False),
        Field("end_fixing", "text", False), Field("max_length", "length", False),
        Field("permitted_force", "force", False), Field("mass", "mass", False),
        Field("mass_per_length", "linear_density", False), Field("price", "money", False),
    ),
    "cylinders": (
        Field("key", "text"), Field("maker", "text", False), Field("bore", "length"), Field("rod", "length"),
        Field("max_stroke", "length"), Field("max_pressure", "pressure"), Field("end_fixing", "text", False),
        Field("mass", "mass", False), Field("mass_per_stroke", "linear_density", False),
        Field("price", "money", False),
    ),
    "drives": (  # servo drives (amplifiers), mechatron.drives.servo
        Field("key", "text"), Field("maker", "text", False),
        Field("rated_current", "current", plausible=(0.01, 1e4)), Field("peak_current", "current",
                                                                         plausible=(0.01, 1e4)),
        Field("peak_time", "time", plausible=(1e-3, 600.0)), Field("dc_link_min", "voltage", plausible=(1.0, 1e4)),
        Field("dc_link_max", "voltage", plausible=(1.0, 1e4)), Field("mass", "mass", False, plausible=(1e-3, 1e3)),
        Field("price", "money", False),
    ),
    "rotary_tables": (  # the direct-drive rotary tables of [Egorov, table 2.11]
        Field("key", "text"), Field("torque_30min", "torque"), Field("torque_5min", "torque"),
        Field("diameter", "length"), Field("height", "length"), Field("positioning_error", "angle"),
    ),
    "gearmotor_ranges": (  # the gearmotor families of [Egorov, section 2.2], as printed
        Field("maker", "text"), Field("family", "text"), Field("codes", "text"), Field("stages", "text", False),
        Field("ratio_min", "ratio", False), Field("ratio_max", "ratio", False),
        Field("output_speed_min", "speed", False), Field("output_speed_max", "speed", False),
        Field("output_torque_min", "torque", False), Field("output_torque_max", "torque", False),
        Field("input_power_min", "power", False), Field("input_power_max", "power", False),
    ),
}

#: The example catalogs shipped in ``catalogs/``.
DEFAULT_FILES = {"motors": "servo_motors.csv", "gearboxes": "gearboxes.csv", "linear": "linear_drives.csv",
                 "cylinders": "hydraulic_cylinders.csv", "rotary_tables": "rotary_tables_table_2_11.csv",
                 "gearmotor_ranges": "gearmotor_ranges_section_2_2.csv", "drives": "servo_drives.csv"}


def _column_field(column: str, schema: tuple[Field, ...], path: Path) -> tuple[Field, float] | None:
    """The field a column holds and its unit factor, ``None`` for an extra column; an error for a known field in an
    unknown unit."""
    for field in sorted(schema, key=lambda f: -len(f.name)):
        if column == field.name:
            units = UNITS[field.kind]
            if "" not in units:
                raise InputError(f"give the unit in the column name, one of: "
                                 f"{', '.join(field.name + '_' + u for u in units)}", file=path, field=column)
            return field, units[""]
        if column.startswith(field.name + "_"):
            suffix = column[len(field.name) + 1:]
            units = UNITS[field.kind]
            if suffix in units:
                return field, units[suffix]
            raise InputError(f"unknown unit {suffix!r} for {field.name} (known: "
                             f"{', '.join(u for u in units if u) or 'SI only'})", file=path, field=column)
    return None


#: Catalogs parsed in this process, by (kind, the SHA-256 of the file's bytes): a sizing reads the same catalogs for
#: every joint, pass and design; a file whose bytes changed is parsed again.
_PARSED: dict[tuple[str, bytes], pd.DataFrame] = {}
#: The most catalogs kept (the oldest goes first).
PARSED_KEPT = 32


def read_catalog(path: str | Path, kind: str) -> pd.DataFrame:
    """A validated catalog of ``kind`` (a key of :data:`SCHEMAS`) as a DataFrame in SI units with the schema's field
    names (extra columns kept as text; a value left empty in an optional column is NaN).

    Every cell is checked (a number, finite, > 0 or ≥ 0, within the field's maximum and mechatron's plausible range
    :attr:`Field.plausible`, whole for a count), converted by the unit of its
    column (:data:`mechatron.units.UNITS`), and so are keys (unique) and relations between columns (peak ≥ rated…).
    The same bytes are parsed once per process (:data:`_PARSED`); each call returns its own copy.

    Raises:
        InputError: naming the file, the row (the file's line number) and the column.
    """
    if kind not in SCHEMAS:
        raise InputError(f"unknown catalog kind {kind!r}; expected one of: {', '.join(SCHEMAS)}")
    path = Path(path)
    try:
        key = (kind, hashlib.sha256(path.read_bytes()).digest())
    except OSError:
        return _parse_catalog(path, kind)  # read_csv names what is wrong with the file
    if key not in _PARSED:
        _PARSED[key] = _parse_catalog(path, kind)
        while len(_PARSED) > PARSED_KEPT:
            _PARSED.pop(next(iter(_PARSED)))
    return _PARSED[key].copy()


def _parse_catalog(path: Path, kind: str) -> pd.DataFrame:
    """The table of :func:`read_catalog`, read and checked."""
    raw = read_csv(path, allow_empty=True)
    schema = SCHEMAS[kind]
    columns: dict[str, tuple[str, float]] = {}
    for column in raw.columns:
        found = _column_field(column, schema, path)
        if found is not None:
            field, factor = found
            if field.name in {name for name, _ in columns.values()}:
                raise InputError(f"{field.name} is given twice", file=path, field=column)
            columns[column] = (field.name, factor)
    present = {name for name, _ in columns.values()}
    for field in schema:
        if field.required and field.name not in present:
            raise InputError(f"missing column {field.name!r}", file=path, field=field.name)
    if raw.empty:
        raise InputError("the catalog has no rows", file=path)
    by_name = {f.name: f for f in schema}
    out = {name: _column_values(raw[column], by_name[name], factor, path, column)
           for column, (name, factor) in columns.items()}
    table = pd.DataFrame(out)
    lines = [int(n) for n in raw.index]  # the file's line number of each row
    for column in raw.columns:  # extra columns: kept as text, ignored by the sizing
        if column not in columns and column not in table:
            table[column] = raw[column].to_numpy()
    if "key" in table:
        duplicated = table["key"][table["key"].duplicated()]
        if len(duplicated):
            row = lines[int(duplicated.index[0])]
            raise InputError(f"key {duplicated.iloc[0]!r} repeats an earlier row", file=path, row=row, field="key")
    _check_consistency(table, kind, path, {name: column for column, (name, _) in columns.items()}, lines)
    return table


def _column_values(cells: pd.Series, field: Field, factor: float, path: Path, column: str) -> list:
    """The cells of one column (text, stripped) as the field's values: text as is, numbers × ``factor`` (SI), NaN for
    an empty optional cell."""
    values: list = []
    suffix = column[len(field.name) + 1:]
    shift = offset(field.kind, suffix)  # °C → K
    for row, text in zip(cells.index, cells):
        if not text:
            if field.required:
                raise InputError("missing value", file=path, row=row, field=column)
            values.append("" if field.kind == "text" else math.nan)
            continue
        if field.kind == "text":
            values.append(text)
            continue
        if field.table:
            values.append(_rate_table(text, factor, path, row, column))
            continue
        value = number(text, file=path, row=row, field=column) * factor + shift
        top = math.inf if field.maximum is None else field.maximum
        if field.minimum is not None and not field.minimum <= value <= top:
            raise InputError(f"must be between {_shown(field.minimum, field)} and {_shown(field.maximum, field)}, "
                             f"got {text}", file=path, row=row, field=column)
        if (field.minimum is None or field.minimum >= 0) and (value < 0 or (field.positive and value == 0)):
            raise InputError(f"must be {'> 0' if field.positive else '>= 0'}, got {text}", file=path, row=row,
                             field=column)
        if field.maximum is not None and value > field.maximum:
            raise InputError(f"must be <= {field.maximum:g}, got {text}", file=path, row=row, field=column)
        if field.kind == "count" and not value.is_integer():
            raise InputError(f"must be a whole number (a count), got {text}", file=path, row=row, field=column)
        if field.plausible is not None and not field.plausible[0] <= value <= field.plausible[1]:
            raise InputError(f"must be between {_shown(field.plausible[0], field)} and "
                             f"{_shown(field.plausible[1], field)} (mechatron's plausible range), got {text}"
                             f"{' ' + suffix if suffix else ''}", file=path, row=row, field=column)
        values.append(value)
    return values


def _rate_table(text: str, factor: float, path: Path, row: int, column: str) -> tuple[tuple[float, float], ...]:
    """A cell of ``rate:factor`` pairs separated by ``;`` (``1000:1;3000:1.2``) as ((rate (1/s), factor), …): each
    rate > 0 in the column's unit (× ``factor`` to 1/s), rising from pair to pair, each factor ≥ 1 (a maker's shock
    factor multiplies the load; it never raises the rating) and ≤ :data:`SHOCK_FACTOR_MAX` (mechatron's rule)."""
    pairs = []
    for part in text.split(";"):
        cells = part.split(":")
        if len(cells) != 2:
            raise InputError(f"expected rate:factor pairs separated by ';' (e.g. 1000:1;3000:1.2), got {text!r}",
                             file=path, row=row, field=column)
        rate, value = (number(cell.strip(), file=path, row=row, field=column) for cell in cells)
        if not rate > 0:
            raise InputError(f"a rate must be > 0, got {cells[0].strip()}", file=path, row=row, field=column)
        if value < 1:
            raise InputError(f"a shock factor must be >= 1 (it multiplies the peak torque asked for), got "
                             f"{cells[1].strip()}", file=path, row=row, field=column)
        if value > SHOCK_FACTOR_MAX:
            raise InputError(f"a shock factor must be <= {SHOCK_FACTOR_MAX:g} (mechatron's plausible range), got "
                             f"{cells[1].strip()}", file=path, row=row, field=column)
        if pairs and rate * factor <= pairs[-1][0]:
            raise InputError(f"the rates must rise from pair to pair, got {cells[0].strip()} after a larger or equal "
                             "one", file=path, row=row, field=column)
        pairs.append((rate * factor, value))
    return tuple(pairs)


def _shown(value: float, field: Field) -> str:
    """A bound of ``field`` (SI) as an error says it: ``273.15 K (0 °C)`` for a temperature."""
    text = f"{value:g} {SI.get(field.kind, '').strip('-')}".strip()
    return f"{text} ({value - 273.15:g} °C)" if field.kind == "temperature" else text


def _check_consistency(table: pd.DataFrame, kind: str, path: Path, column_of: dict[str, str],
                       lines: list[int]) -> None:
    """Relations between columns: peak ≥ rated, max speed ≥ rated speed, rod < bore (strictly: a rod as wide as
    the bore leaves no annulus to pull with), a screw's root diameter < its diameter, a known end fixing, and the
    electrical and the thermal columns of a motor all or none."""
    rules = {"motors": [("peak_torque", "rated_torque", False), ("max_speed", "rated_speed", False)],
             "gearboxes": [("peak_torque", "rated_torque", False), ("emergency_torque", "peak_torque", False),
                           ("max_input_speed", "rated_input_speed", False)],
             "linear": [("diameter", "root_diameter", True)],
             "cylinders": [("bore", "rod", True)], "rotary_tables": [("torque_5min", "torque_30min", False)],
             "drives": [("peak_current", "rated_current", False), ("dc_link_max", "dc_link_min", False)]}
    for high, low, strict in rules.get(kind, []):
        if high not in table or low not in table:
            continue
        bad = table.index[table[high] <= table[low]] if strict else table.index[table[high] < table[low]]
        if len(bad):
            relation = "is not above" if strict else "is below"
            raise InputError(f"{high} {relation} {low}", file=path, row=lines[int(bad[0])], field=column_of[high])
    if "end_fixing" in table:
        for row, name in zip(lines, table["end_fixing"]):
            if name:
                try:
                    end_fixing(name)
                except InputError as error:
                    raise InputError(error.message, file=path, row=row, field=column_of["end_fixing"]) from None
    if kind == "gearboxes":
        _check_peak_rule(table, path, column_of, lines)
    if kind == "motors":
        thermal = _check_thermal(table, path, column_of, lines)
        _check_electrical(table, path, column_of, lines, thermal)
        _check_brakes(table, path, column_of, lines)


def _check_peak_rule(table: pd.DataFrame, path: Path, column_of: dict[str, str], lines: list[int]) -> None:
    """A gearbox's ``peak_rule`` is one of :data:`~mechatron.drives.converters.PEAK_RULES` (empty: ``shock_factors``
    where the row gives that table, else ``cycle_rating``) and agrees with its ``shock_factors`` cell: the table
    with ``shock_factors``, none with the other two."""
    from .converters import PEAK_RULES

    rules = table["peak_rule"] if "peak_rule" in table else pd.Series("", index=table.index)
    tables = table["shock_factors"] if "shock_factors" in table else pd.Series(math.nan, index=table.index)
    for line, rule, factors in zip(lines, rules, tables):
        given = isinstance(factors, tuple)
        if rule and rule not in PEAK_RULES:
            raise InputError(f"unknown peak rule {rule!r}; expected one of: {', '.join(PEAK_RULES)} (or empty)",
                             file=path, row=line, field=column_of["peak_rule"])
        if rule == "shock_factors" and not given:
            raise InputError("missing value: peak_rule shock_factors needs the row's shock_factors table", file=path,
                             row=line, field=column_of.get("shock_factors", "shock_factors"))
        if given and rule not in ("", "shock_factors"):
            raise InputError(f"a shock_factors table with peak_rule {rule}: give one rule (the table, or "
                             f"{rule} without it)", file=path, row=line, field=column_of["peak_rule"])


def _given(table: pd.DataFrame, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Which rows give each column of ``names`` (a value, not empty)."""
    return {name: table[name].notna().to_numpy() if name in table else np.zeros(len(table), dtype=bool)
            for name in names}


def _check_thermal(table: pd.DataFrame, path: Path, column_of: dict[str, str], lines: list[int]) -> bool:
    """The thermal columns of a motor catalog (:data:`~mechatron.drives.thermal.THERMAL_COLUMNS`) are given in
    every row, with the torque constant and the resistance (the copper loss I² R of I = T/k_t), or in none: else the
    first row that lacks one names it. Whether the catalog gives them."""
    from .thermal import REFERENCE, THERMAL_COLUMNS

    needed = (*THERMAL_COLUMNS, "torque_constant", "resistance")
    given = _given(table, needed)
    if not any(given[name].any() for name in THERMAL_COLUMNS):
        return False
    complete = np.all(list(given.values()), axis=0)
    if not complete.all():
        i = int(np.flatnonzero(~complete)[0])
        missing = next(name for name in needed if not given[name][i])
        raise InputError(f"missing value: the thermal columns are given for some rows or columns only; the winding "
                         f"temperature needs all of {', '.join(needed)} in every row (or none of "
                         f"{', '.join(THERMAL_COLUMNS)} in any)", file=path, row=lines[i],
                         field=column_of.get(missing, missing))
    if "torque_constant_coefficient" in table:  # k_t(T_max) = k_t₂₅ (1 + β (T_max − 25 °C)) > 0
        beta = table["torque_constant_coefficient"].to_numpy(dtype=float)
        vanishing = np.flatnonzero(1 + beta * (table["max_winding_temperature"].to_numpy(dtype=float) - REFERENCE)
                                   <= 0)
        if len(vanishing):
            raise InputError("k_t(T_max) = k_t₂₅·(1 + β·(T_max − 25 °C)) must stay > 0: the magnets would lose all "
                             "their flux below the winding's limit temperature", file=path,
                             row=lines[int(vanishing[0])], field=column_of["torque_constant_coefficient"])
    return True


def _check_brakes(table: pd.DataFrame, path: Path, column_of: dict[str, str], lines: list[int]) -> None:
    """A motor row that gives any brake column (:data:`~mechatron.drives.brakes.BRAKE_COLUMNS`) gives the brake's
    holding torque: else the row names it."""
    from .brakes import BRAKE_COLUMNS

    given = _given(table, BRAKE_COLUMNS)
    partial = np.any([given[name] for name in BRAKE_COLUMNS[1:]], axis=0) & ~given["brake_holding_torque"]
    if partial.any():
        i = int(np.flatnonzero(partial)[0])
        other = next(name for name in BRAKE_COLUMNS[1:] if given[name][i])
        raise InputError(f"missing value: a brake without its holding torque ({column_of[other]} given); give "
                         "brake_holding_torque (N·m) or none of the brake columns", file=path, row=lines[i],
                         field=column_of.get("brake_holding_torque", "brake_holding_torque"))


def _check_electrical(table: pd.DataFrame, path: Path, column_of: dict[str, str], lines: list[int],
                      thermal: bool = False) -> None:
    """A motor that gives its resistance or supply voltage gives all of the torque constant, the resistance and the
    voltage (the voltage limit needs the three; a catalog with the thermal columns may give k_t and R without the
    voltage: its copper loss needs them); else the row names the first one missing."""
    given = _given(table, ELECTRICAL_COLUMNS)
    partial = (given["resistance"] | given["voltage"]) & ~np.all(list(given.values()), axis=0)
    if thermal:
        partial &= given["voltage"]
    if partial.any():
        i = int(np.flatnonzero(partial)[0])
        missing = next(name for name in ELECTRICAL_COLUMNS if not given[name][i])
        present = [name for name in ELECTRICAL_COLUMNS if given[name][i]]
        raise InputError(f"missing value: the electrical columns are half filled ({', '.join(present)} given); the "
                         f"voltage limit needs all of {', '.join(ELECTRICAL_COLUMNS)} (or none of resistance and "
                         "voltage)", file=path, row=lines[i], field=column_of.get(missing, missing))


def default_catalog(kind: str) -> pd.DataFrame:
    """The example catalog of ``kind`` shipped with mechatron."""
    return read_catalog(data_dir("catalogs") / DEFAULT_FILES[kind], kind)

r"""The ``sizing`` analysis of a study: the drives of one design for a task (:func:`mechatron.drives.sizing.size`,
the same sizing as ``mechatron size``), reduced to a row of numbers.

Options (the spec's ``[analyses.sizing]`` table; every one optional, see ``docs/study_analyses.md``): ``task``
(a task TOML or trajectory CSV; default the mechanism's own ``robots/tasks/<name>.toml``, else the generic
out-and-back task), the catalogs ``motors``, ``gearboxes``, ``linear``, ``cylinders`` (CSV; default the example
catalogs of ``catalogs/``), ``objective`` (``mass``, ``cost``, ``margin``, ``time``), ``inertia_ratio``,
``direct``, ``pressure_MPa``, ``chain_efficiency``, ``single_pass``, ``max_iterations``, ``stop_torque`` (N·m),
``stop_current`` (A), ``voltage`` (V), ``screw_life_h`` (h), ``ambient`` (°C, as ``--ambient``) — the options of
``mechatron size``. The old
spelling ``pressure_mpa`` is read for one more release, with a warning (:data:`mechatron.quantities.RENAMED`).

Outputs (SI; :mod:`mechatron.quantities`): ``feasible``; ``drive_mass_kg`` and ``drive_cost`` (Σ of the drives'
catalog masses and prices); ``smallest_margin`` (min over the drives' checks of 1 − value/limit, a
cylinder's rated pressure and stroke — pass/fail filters — only when they fail);
``energy_per_cycle_J`` (energy drawn per cycle: ∫ max(P_bus, 0) dt of the common DC bus plus the pump's ∫ p Q dt,
:meth:`~mechatron.drives.sizing.SizingResult.totals`);
``peak_power_W`` (the bus's peak power plus the pump's peak power p·Q; each alone when the mechanism has only
motors or only cylinders); ``cycle_time_s`` (the task's duration as sized: shorter than the task's with the
``time`` objective).

An infeasible design is a row, not an error: ``feasible`` is false and the other outputs are those of the
closest candidates (the drive of each coordinate with the smallest worst load factor, as ``mechatron size``
reports it; a held coordinate that no braked motor can drive ranks them as if each had a brake, its missing brake
a margin of −1), so that ``smallest_margin`` is negative — how far the design is from feasible — and the masses and
costs are finite.

The helpers ``field_*`` check the options of any analysis (one line naming ``[analyses.NAME] FIELD``).
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...drives.options import (
    AMBIENT_DEGC,
    CHAIN_EFFICIENCY,
    INERTIA_RATIO_MAX,
    MAX_ITERATIONS,
    MAX_PASSES,
    MIN_EFFICIENCY,
    MIN_PASSES,
    MPA,
    OBJECTIVE,
    PRESSURE,
    PRESSURE_MAX,
    SizingOptions,
    check_objective,
)
from ...errors import InputError, MechatronError
from ...io.values import number

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from ...drives.report import DriveSizing
    from ...drives.sizing import SizingResult
    from ...dynamics.task import Task
    from ...model.mechanism import Mechanism

OUTPUTS = ("feasible", "drive_mass_kg", "drive_cost", "smallest_margin", "energy_per_cycle_J", "peak_power_W",
           "cycle_time_s")

#: The catalog options: the kinds of :data:`mechatron.drives.catalogs.SCHEMAS`.
CATALOGS = ("motors", "gearboxes", "linear", "cylinders")
#: The numeric options: their defaults and bounds (those of ``mechatron size``).
NUMBERS: dict[str, tuple[float | None, dict]] = {
    "inertia_ratio": (INERTIA_RATIO_MAX, dict(positive=True)),
    "pressure_MPa": (PRESSURE / MPA, dict(positive=True, maximum=PRESSURE_MAX / MPA, unit="MPa")),
    "chain_efficiency": (CHAIN_EFFICIENCY, dict(minimum=MIN_EFFICIENCY, maximum=1.0)),
    "max_iterations": (MAX_ITERATIONS, dict(integer=True, minimum=MIN_PASSES, maximum=MAX_PASSES)),
    "stop_torque": (None, dict(positive=True, unit="N·m")), "stop_current": (None, dict(positive=True, unit="A")),
    "voltage": (None, dict(positive=True, unit="V")), "screw_life_h": (None, dict(positive=True, unit="h")),
    "ambient": (AMBIENT_DEGC, dict(minimum=-50.0, maximum=100.0, unit="°C"))}
#: The options that are true or false.
FLAGS = ("direct", "single_pass")
OPTIONS = ("task", *CATALOGS, "objective", *NUMBERS, *FLAGS)


# ------------------------------------------------------------------------------------- options of any analysis
def field_error(analysis: str, field: str, message: str) -> InputError:
    """The error of one option: ``[analyses.NAME] FIELD: message``."""
    return InputError(f"[analyses.{analysis}] {field}: {message}")


def field_names(analysis: str, options: dict, known: tuple[str, ...]) -> None:
    """Refuse an option that is not one of ``known`` (the first, with the known ones listed)."""
    if not isinstance(options, dict):
        raise InputError(f"[analyses.{analysis}] must be a table of options, got {options!r}")
    for key in options:
        if key not in known:
            raise field_error(analysis, key, f"unknown option; known: {', '.join(known)}")


def field_number(analysis: str, options: dict, field: str, default: Any = None, **bounds) -> Any:
    """The option ``field`` checked as by :func:`~mechatron.io.values.number` (``default`` when left out)."""
    try:
        return number(field, options.get(field, default), allow_none=True, **bounds)
    except InputError as exc:
        raise field_error(analysis, field, exc.message.removeprefix(f"{field} ")) from None


def field_flag(analysis: str, options: dict, field: str, default: bool) -> bool:
    """The option ``field``: ``true`` or ``false``."""
    value = options.get(field, default)
    if not isinstance(value, bool):
        raise field_error(analysis, field, f"must be true or false, got {value!r}")
    return value


def field_file(analysis: str, options: dict, field: str) -> Path | None:
    """The option ``field``: the path of a file that exists (absolute or relative to the working folder; the study
    resolves the spec's relative paths), ``None`` when left out."""
    value = options.get(field)
    if value is None:
        return None
    if not isinstance(value, (str, Path)) or not str(value):
        raise field_error(analysis, field, f"must be the path of a file, got {value!r}")
    path = Path(value)
    if not path.is_file():
        raise field_error(analysis, field, f"no such file: '{path}'")
    return path


# ------------------------------------------------------------------------------------------------ the sizing
@functools.lru_cache(maxsize=32)
def _catalog(path: str, stamp: int, kind: str) -> pd.DataFrame:
    """A catalog read once per process (and again when the file changes: ``stamp`` is its modification time)."""
    from ...drives.catalogs import read_catalog
    from ...drives.system import keep_arrays

    return keep_arrays(read_catalog(path, kind))


def catalog_files(options: dict) -> dict[str, Path]:
    """The four catalogs' files: the options', the example ones of ``catalogs/`` where left out."""
    from ...drives.catalogs import DEFAULT_FILES
    from ...io.data import data_dir

    return {kind: field_file("sizing", options, kind) or data_dir("catalogs") / DEFAULT_FILES[kind]
            for kind in CATALOGS}


def catalogs(options: dict) -> dict[str, pd.DataFrame]:
    """The four catalogs of the options (the example ones where left out), read and checked once per process."""
    out = {}
    for kind, path in catalog_files(options).items():
        try:
            out[kind] = _catalog(str(path.resolve()), path.stat().st_mtime_ns, kind)
        except InputError as exc:
            raise field_error("sizing", kind, str(exc)) from None
    return out


def coordinates(mech: Mechanism) -> list[str]:
    """The driven coordinates: the actuated ones of a closed-loop mechanism, every joint of a serial one."""
    return list(mech.actuated) if mech.closures else list(mech.joint_names)


def sizing_options(options: dict) -> SizingOptions:
    """The :class:`~mechatron.drives.options.SizingOptions` of the options (checked: one line naming
    ``[analyses.sizing] FIELD``; the pressure in MPa, the screw life in h, the ambient in °C)."""
    objective = options.get("objective", OBJECTIVE)
    try:
        check_objective(objective)
    except InputError as exc:
        raise field_error("sizing", "objective", str(exc)) from None
    values = {name: field_number("sizing", options, name, default, **bounds)
              for name, (default, bounds) in NUMBERS.items()}
    if values["stop_torque"] is not None and values["stop_current"] is not None:
        raise field_error("sizing", "stop_current", "give the emergency-stop limit as stop_torque or as "
                                                    "stop_current, not both")
    return SizingOptions.in_user_units(
        objective=objective, inertia_ratio_max=values["inertia_ratio"], pressure_MPa=values["pressure_MPa"],
        chain_efficiency=values["chain_efficiency"], direct=field_flag("sizing", options, "direct", True),
        single_pass=field_flag("sizing", options, "single_pass", False), max_iterations=values["max_iterations"],
        stop_torque=values["stop_torque"], stop_current=values["stop_current"], voltage=values["voltage"],
        screw_life_h=values["screw_life_h"], ambient_degC=values["ambient"])


def inputs(mech: Mechanism, options: dict) -> tuple[Task, dict[str, pd.DataFrame], SizingOptions]:
    """What :func:`mechatron.drives.sizing.size` sizes ``mech`` with for the options, checked: the task (read for
    ``mech``), the four catalogs (DataFrames) and the :func:`sizing_options`."""
    from ...dynamics.task import default_task, read_task
    from ...quantities import renamed

    options = renamed(options, "[analyses.sizing]")
    field_names("sizing", options, OPTIONS)
    if not coordinates(mech):
        raise InputError(f"[analyses.sizing] {mech.name} has no actuated joint to size a drive for")
    settings = sizing_options(options)
    path = field_file("sizing", options, "task")
    try:
        task = default_task(mech) if path is None else read_task(path, mech)
    except InputError as exc:
        raise field_error("sizing", "task", str(exc)) from None
    return task, catalogs(options), settings


def arguments(mech: Mechanism, options: dict) -> dict:
    """The keyword arguments of :func:`mechatron.drives.sizing.size` for the options (checked; the task read for
    ``mech``, the catalogs as DataFrames, the fields of the :func:`sizing_options`)."""
    task, tables, settings = inputs(mech, options)
    return dict(task=task, **tables, **settings.keywords())


def check(mech: Mechanism, options: dict) -> None:
    """Refuse unknown options, bad values, missing or malformed task and catalog files, and a mechanism without
    an actuated joint (:class:`~mechatron.errors.InputError` naming ``[analyses.sizing] FIELD``)."""
    arguments(mech, options)


def output_names(mech: Mechanism, options: dict) -> list[str]:
    """The names of the outputs (the same for every mechanism and options): :data:`OUTPUTS`."""
    return list(OUTPUTS)


def input_files(mech: Mechanism, options: dict) -> list[Path]:
    """The files the sizing of one design reads: the task's (its trajectory CSV too; the mechanism's own task when
    left out) and the four catalogs."""
    from .dynamics import task_files

    return [*task_files(field_file("sizing", options, "task"), mech), *catalog_files(options).values()]


def _known(value: Any) -> float:
    """A catalog number, 0 where the catalog leaves it out (``None``, NaN)."""
    return 0.0 if value is None or not math.isfinite(float(value)) else float(value)


def drive_mass_price(mech: Mechanism, sizing: DriveSizing) -> tuple[float, float]:
    """The mass (kg) and price of a coordinate's drive: the chosen one, else (none feasible) the closest candidate
    (the first row of ``closest``; for a cylinder its catalog mass + mass per stroke × stroke, times the count)."""
    mass, price = sizing.drive_mass(), sizing.drive_price()
    if mass is not None:
        return mass, _known(price)
    if "mass" in sizing.closest:
        first = sizing.closest.iloc[0]
        return _known(first["mass"]), _known(first["price"])
    data, spec = sizing.cylinder_data, mech.cylinders[sizing.joint]
    stroke = spec.stroke[1] - spec.stroke[0]
    return (sizing.count * (_known(data.get("mass")) + _known(data.get("mass_per_stroke")) * stroke),
            sizing.count * _known(data.get("price")))


def summary(mech: Mechanism, result: SizingResult) -> dict[str, float | bool]:
    """The outputs (see the module) of a sizing result of ``mech``.

    Raises:
        MechatronError: when an output is not a finite number (a catalog without the data it needs).
    """
    drives = [drive_mass_price(mech, j) for j in result.joints]
    margins = [j.smallest_margin() for j in result.joints]
    totals = result.totals()
    out = {"feasible": bool(result.feasible), "drive_mass_kg": sum(m for m, _ in drives),
           "drive_cost": sum(p for _, p in drives), "smallest_margin": min(margins),
           "energy_per_cycle_J": totals["energy_per_cycle_J"],
           "peak_power_W": (totals["peak_bus_power_W"] or 0.0) + (totals["peak_pump_power_W"] or 0.0),
           "cycle_time_s": totals["cycle_time_s"]}
    for key, value in out.items():
        if not math.isfinite(value):
            raise MechatronError(f"sizing of {mech.name}: {key} is not a finite number ({value})")
    return {key: value if key == "feasible" else float(value) for key, value in out.items()}


#: The drives the last sizing of each mechanism (by name) chose in this process: the next design's start
#: (``start`` of :func:`mechatron.drives.sizing.size`: the same result, with fewer inverse dynamics).
_last_choice: dict[str, dict] = {}


def run(mech: Mechanism, options: dict) -> SizingResult:
    """The sizing of ``mech`` with the options: :func:`mechatron.drives.sizing.size` (the task's mechanism, payload
    included, is the one sized), started from the drives the design before chose."""
    from ...drives.sizing import size

    task, tables, settings = inputs(mech, options)
    result = size(mech, task, **tables, options=settings, start=_last_choice.get(mech.name))
    _last_choice.clear()
    _last_choice[mech.name] = {j.joint: j for j in result.joints}
    return result


def outputs(mech: Mechanism, options: dict, seed: int) -> dict[str, float | bool]:
    """The outputs of one design (see the module); ``seed`` is not used (the sizing draws nothing)."""
    return summary(mech, run(mech, options))

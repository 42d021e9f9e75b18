"""The one vocabulary of quantities: every output, option and column name that the study analyses, the
optimisation, the results, their JSON and the plot axes use, each with its unit and its meaning
(``docs/quantities.md`` lists them; ``tests/test_quantities.py`` checks that page, the analyses' outputs and the
units of ``docs/study_analyses.md`` against :data:`QUANTITIES` and :data:`PATTERNS`).

The rules:

- **One spelling per quantity.** The same quantity has the same name wherever it appears: a study output, a
  requirement or objective of an optimisation, a key of a result's ``as_dict`` (JSON), a column of its
  ``to_frame`` (CSV), a plot axis. An old spelling a user may have written in a file is kept for one release in
  :data:`RENAMED` (its reader accepts it with a :class:`~mechatron.errors.MechatronWarning` naming the new one).
- **The unit in the name**, as in the files (``docs/units.md``, :mod:`mechatron.units`): a name ends in its unit
  suffix written as the unit is (case-sensitive: ``_m``, ``_mm``, ``_deg``, ``_N``, ``_Nm``, ``_Pa``, ``_MPa``,
  ``_kg``, ``_s``, ``_h``, ``_W``, ``_J``, ``_m3_s``; never ``_mpa``, ``_j``, ``_w``). An output always carries
  its suffix, SI or not (``reach_m``, ``energy_per_cycle_J``), so that a column says its unit; an option in SI may
  go without one, as a file field does (``stop_torque`` in N·m, ``dt`` in s). A name that ends in a suffix of
  :data:`SUFFIXES` is in that unit.
- **Per-item names**: a quantity of each cylinder or actuator has the item's name in place of an upper-case
  placeholder, ``CYLINDER_max_force_N`` → ``boom_max_force_N`` (:data:`PATTERNS`).
- **Units as printed**: ``N·m``, ``m³/s``; ``-`` for a pure number (ratio, fraction, count, flag, name, path).
- **Axis labels** (:func:`axis_label`): the name without its unit suffix, underscores as spaces, and the unit in
  brackets unless it is ``-``: ``reach (m)``, ``drive mass (kg)``, ``energy per cycle (J)``.

This module imports nothing but :mod:`mechatron.errors`: plots and readers may use it freely.
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import InputError


@dataclass(frozen=True)
class Quantity:
    """A named quantity: its ``name`` (one spelling), its ``unit`` as printed (``-`` for a pure number) and what
    it is (``meaning``, one phrase)."""

    name: str
    unit: str
    meaning: str


#: Unit suffix of a name → the unit as printed (the longest suffix that ends a name is its unit: ``_m3_s``
#: before ``_s``). The one table of printed units of suffixes; their factors to SI are those of the one unit table,
#: :data:`mechatron.units.UNITS` (every suffix here but ``J`` and ``m3_s`` is a unit there, printed as its kind's SI
#: unit where its factor is 1: ``tests/test_formulas.py``).
SUFFIXES: dict[str, str] = {"m": "m", "mm": "mm", "deg": "deg", "N": "N", "Nm": "N·m", "Pa": "Pa", "MPa": "MPa",
                            "kg": "kg", "s": "s", "h": "h", "W": "W", "J": "J", "m3_s": "m³/s"}

#: The placeholders of per-item names: each stands for the name of one item of the mechanism.
PLACEHOLDERS: dict[str, str] = {"CYLINDER": "a hydraulic cylinder of the mechanism",
                                "ACTUATOR": "a joint of a serial arm or an actuated input of a closed loop"}

_PATH = "path of a file, relative to the spec file's folder"

_ENTRIES: tuple[tuple[str, str, str], ...] = (
    # the study's table
    ("design", "-", "the design's number in the study (0, 1, …)"),
    ("seed", "-", "the seed of the design's random draws"),
    ("status", "-", "ok or failed: whether every analysis of the design ran"),
    ("reason", "-", "why the design failed (the first line of the error), empty when ok"),
    # linkage: outputs
    ("reach_m", "m", "largest x of the point over the sweep"),
    ("height_m", "m", "largest y of the point over the sweep"),
    ("depth_m", "m", "largest −y of the point over the sweep"),
    ("x_travel_m", "m", "extent of the point's path along x"),
    ("y_travel_m", "m", "extent of the point's path along y"),
    ("z_travel_m", "m", "extent of the point's path along z (a spatial loop)"),
    ("min_transmission_angle_deg", "deg", "smallest transmission angle over the sweep, of the mechanism's "
                                          "transmission-angle measures"),
    # linkage: options
    ("samples", "-", "how many samples: positions of the linkage sweep, Monte Carlo samples per pose of the "
                     "accuracy analysis"),
    ("point", "-", "the point whose path the linkage analysis measures (default the tool point)"),
    ("working_range", "-", "true or false: a three-cylinder working device's extremes over the whole stroke box"),
    ("load", "N", "the force (Fx, Fy) on the point, for the cylinder forces"),
    ("hold", "m or rad", "linkage: INPUT = value per input held while the others sweep"),
    ("cylinders", "-", "linkage: NAME = { bore, rod, count } per cylinder, for its pressures; sizing: the "
                       "hydraulic cylinder catalog (" + _PATH + ")"),
    ("bore", "m", "piston diameter of a cylinder"),
    ("rod", "m", "rod diameter of a cylinder"),
    ("count", "-", "how many equal cylinders act side by side"),
    # dynamics: options
    ("start", "rad or m", "the move's first pose: one coordinate per joint or actuated input"),
    ("end", "rad or m", "the move's last pose: one coordinate per joint or actuated input"),
    ("start_deg", "deg or m", "the move's first pose, the angles in degrees"),
    ("end_deg", "deg or m", "the move's last pose, the angles in degrees"),
    ("profile", "-", "the move's profile: triangular, trapezoidal, scurve or quintic"),
    ("vmax", "rad/s or m/s", "velocity limit of the move, one value or one per coordinate"),
    ("amax", "rad/s² or m/s²", "acceleration limit of the move, one value or one per coordinate"),
    ("dt", "s", "sampling step of the move"),
    ("duration", "s", "the least duration of the move"),
    ("task", "-", "task TOML or trajectory CSV (" + _PATH + ")"),
    # sizing: options
    ("motors", "-", "servo motor catalog (" + _PATH + ")"),
    ("gearboxes", "-", "gearbox catalog (" + _PATH + ")"),
    ("linear", "-", "ball screw and rack catalog (" + _PATH + ")"),
    ("objective", "-", "how feasible drives are ranked: mass, cost, margin or time"),
    ("inertia_ratio", "-", "largest load-to-motor inertia ratio"),
    ("direct", "-", "true or false: try gearless (direct-drive) motors"),
    ("pressure_MPa", "MPa", "hydraulic system (relief) pressure"),
    ("chain_efficiency", "-", "efficiency of the rest of the drive chain, multiplies every converter's"),
    ("single_pass", "-", "true or false: size each coordinate once with weightless drives"),
    ("max_iterations", "-", "the most sizing passes before the choice is reported as not settled"),
    ("stop_torque", "N·m", "emergency-stop torque limit of the motors"),
    ("stop_current", "A", "emergency-stop current limit of the motors"),
    ("voltage", "V", "supply voltage of the voltage-limit check"),
    ("screw_life_h", "h", "required nominal life of ball screws"),
    ("ambient", "°C", "ambient temperature of the motors' winding temperature check (in °C, as the option says)"),
    # sizing: outputs and the sizing result's totals
    ("feasible", "-", "true or false: every coordinate has a drive that passes every check, and the choice settled"),
    ("drive_mass_kg", "kg", "Σ of the drives' catalog masses"),
    ("drive_cost", "catalog currency", "Σ of the drives' catalog prices"),
    ("smallest_margin", "-", "smallest margin 1 − value/limit over every check of every drive, a cylinder's rated "
     "pressure (a pass/fail filter) only when it fails (< 0: a check fails)"),
    ("energy_per_cycle_J", "J", "energy drawn per cycle: ∫ max(P_bus, 0) dt of the common DC bus plus the pump's "
                                "∫ p Q dt"),
    ("peak_power_W", "W", "peak power of the common DC bus plus the pump's peak power p Q"),
    ("cycle_time_s", "s", "the task's duration as sized"),
    ("peak_bus_power_W", "W", "peak power of the common DC bus, max P_bus"),
    ("regenerated_energy_J", "J", "braking energy per cycle, ∫ max(−P_bus, 0) dt"),
    ("braking_resistor_peak_W", "W", "peak braking power of the bus, max(−P_bus)"),
    ("braking_resistor_continuous_W", "W", "regenerated energy over the cycle time"),
    ("peak_pump_power_W", "W", "peak hydraulic power of the pump, max p Q"),
    ("peak_pump_flow_m3_s", "m³/s", "peak flow of the pump, max Q"),
    # accuracy: options
    ("tolerances", "-", "tolerances CSV: the error sources (" + _PATH + ")"),
    ("limit_mm", "mm", "largest acceptable |Δr|, for the yield"),
    ("poses", "-", "accuracy: poses CSV (" + _PATH + "); linkage: the named poses { name, inputs, point, lowest or "
                   "highest } whose outputs are POSE.OUTPUT"),
    ("grid", "-", "instead of poses: N poses per coordinate, or N random ones"),
    ("frame", "-", "the frame whose position error is studied (default the tool)"),
    ("quantile", "-", "the quantile of |Δr| the Monte Carlo reports"),
    ("k", "-", "coverage factor: σ = t/k for normal errors, RSS at ±kσ"),
    # accuracy: outputs
    ("worst_case_mm", "mm", "largest worst-case position error |Δr| over the poses"),
    ("rss_mm", "mm", "largest statistical (RSS) position error |Δr| over the poses"),
    ("mc_quantile_mm", "mm", "largest Monte Carlo quantile of |Δr| over the poses (full nonlinear model)"),
    ("yield", "-", "smallest fraction over the poses of the Monte Carlo samples with |Δr| ≤ limit_mm"),
)

#: Every quantity with a fixed name, by name.
QUANTITIES: dict[str, Quantity] = {name: Quantity(name, unit, meaning) for name, unit, meaning in _ENTRIES}

#: The per-item quantities, by pattern: a placeholder of :data:`PLACEHOLDERS` in place of the item's name.
PATTERNS: dict[str, Quantity] = {q.name: q for q in (
    Quantity("CYLINDER_max_force_N", "N", "largest static force of cylinder CYLINDER holding the mechanism over "
                                          "the sweep, at rest against gravity, the task's payload and loads and the "
                                          "load"),
    Quantity("CYLINDER_max_pressure_Pa", "Pa", "largest pressure of cylinder CYLINDER over the sweep (force over "
                                               "the piston or annulus area)"),
    Quantity("ACTUATOR_peak_Nm", "N·m", "peak torque max |τ| of ACTUATOR (one that turns) along the motion"),
    Quantity("ACTUATOR_rms_Nm", "N·m", "RMS torque √(∫τ² dt / T) of ACTUATOR (one that turns) along the motion"),
    Quantity("ACTUATOR_peak_N", "N", "peak force max |F| of ACTUATOR (one that slides) along the motion"),
    Quantity("ACTUATOR_rms_N", "N", "RMS force √(∫F² dt / T) of ACTUATOR (one that slides) along the motion"),
)}

#: Old spelling → the one now used. A file field in the old spelling is read for one release, with a warning.
RENAMED: dict[str, str] = {"pressure_mpa": "pressure_MPa"}


def _pattern(name: str) -> tuple[Quantity, str] | None:
    """(the pattern, the item's name) of a per-item name, or None."""
    for pattern, q in PATTERNS.items():
        tail = pattern.partition("_")[2]
        if name.endswith("_" + tail) and len(name) > len(tail) + 1:
            return q, name[: -len(tail) - 1]
    return None


def quantity(name: str) -> Quantity:
    """The quantity named ``name``: one of :data:`QUANTITIES`, or a per-item name of :data:`PATTERNS` (its
    meaning naming the item).

    Raises:
        InputError: for an unknown name (with the new spelling of an old one, or the closest known names).
    """
    if name in QUANTITIES:
        return QUANTITIES[name]
    pose, dot, rest = name.partition(".") if isinstance(name, str) else ("", "", "")
    if dot and pose and rest:  # an output at a named pose of the linkage analysis: POSE.OUTPUT
        q = quantity(rest)
        return Quantity(name, q.unit, f"{q.meaning}, at the pose {pose}")
    found = _pattern(name) if isinstance(name, str) else None
    if found is not None:
        q, item = found
        placeholder = q.name.partition("_")[0]
        return Quantity(name, q.unit, q.meaning.replace(placeholder, item))
    if name in RENAMED:
        raise InputError(f"unknown quantity {name!r}: it is now spelled {RENAMED[name]!r}")
    import difflib  # only an error needs it

    close = difflib.get_close_matches(str(name), [*QUANTITIES, *PATTERNS], n=3)
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    raise InputError(f"unknown quantity {name!r}{hint} (the quantities: docs/quantities.md)")


def is_quantity(name: str) -> bool:
    """Whether ``name`` is a quantity of the registry (a fixed or a per-item name)."""
    if name in QUANTITIES or (isinstance(name, str) and _pattern(name) is not None):
        return True
    pose, dot, rest = name.partition(".") if isinstance(name, str) else ("", "", "")
    return bool(dot and pose and rest) and is_quantity(rest)


def unit(name: str) -> str:
    """The unit of the quantity ``name`` as printed (``-`` for a pure number).

    Raises:
        InputError: for an unknown name.
    """
    return quantity(name).unit


def suffix(name: str) -> str | None:
    """The unit suffix that ends ``name`` (the longest of :data:`SUFFIXES`), or None."""
    found = [s for s in SUFFIXES if name.endswith("_" + s) and len(name) > len(s) + 1]
    return max(found, key=len) if found else None


def unit_of(column: str) -> str:
    """The unit of an output column: of a quantity of the registry its unit (:func:`unit`: ``reach_m`` → m); of a
    column that is none, the unit its name ends with (:data:`SUFFIXES`), else ``-``."""
    if is_quantity(column):
        return unit(column)
    end = suffix(column)
    return "-" if end is None else SUFFIXES[end]


def axis_label(name: str) -> str:
    """The label of a plot axis for the quantity ``name``: the name without its unit suffix, underscores as spaces,
    the unit in brackets unless it is ``-`` (``reach_m`` → ``reach (m)``, ``energy_per_cycle_J`` → ``energy per
    cycle (J)``, ``yield`` → ``yield``).

    Raises:
        InputError: for an unknown name.
    """
    q = quantity(name)
    words = name
    end = suffix(name)
    if end is not None and q.unit.startswith(SUFFIXES[end]):
        words = name[: -len(end) - 1]
    words = words.replace("_", " ")
    return words if q.unit == "-" else f"{words} ({q.unit})"


def renamed(options: dict, where: str) -> dict:
    """``options`` (a table of a file) with every field of an old spelling (:data:`RENAMED`) under its new one, each
    with a :class:`~mechatron.errors.MechatronWarning` naming both (``where``: the table, e.g.
    ``[analyses.sizing]``).

    Raises:
        InputError: when a field is given in both spellings.
    """
    if not isinstance(options, dict) or not any(key in RENAMED for key in options):
        return options
    import warnings

    from .errors import MechatronWarning

    out = {}
    for key, value in options.items():
        new = RENAMED.get(key)
        if new is None:
            out[key] = value
            continue
        if new in options:
            raise InputError(f"{where} {key}: give {new} only ({key} is its old spelling)")
        warnings.warn(f"{where} {key}: renamed {new}; the old spelling will not be read by the next release",
                      MechatronWarning, stacklevel=3)
        out[new] = value
    return out


__all__ = ["PATTERNS", "PLACEHOLDERS", "QUANTITIES", "RENAMED", "SUFFIXES", "Quantity", "axis_label", "is_quantity",
           "quantity", "renamed", "suffix", "unit"]

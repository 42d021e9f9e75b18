"""The one unit table of mechatron: every unit a file field or column may carry, with its factor to SI.

SI is used inside and in the API (m, rad, kg, s, N, N·m, Pa, W). A file field or column in another unit says so
in its name, as ``<field>_<unit>``: ``stroke_mm``, ``angle_deg``, ``rated_speed_rpm``, ``rotor_inertia_kgcm2``,
``tolerance_arcmin``; a field without a suffix is in SI. Every reader converts with :func:`factor` (and
:func:`offset`: a temperature in °C, ``_degC``, is T_K = T_°C + 273.15).
"""

from __future__ import annotations

import math

#: kind of quantity → unit suffix → factor to SI ("" is the SI unit itself).
UNITS: dict[str, dict[str, float]] = {
    "length": {"": 1.0, "m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6},
    "angle": {"": 1.0, "rad": 1.0, "deg": math.pi / 180, "arcmin": math.pi / 10800, "arcsec": math.pi / 648000,
              "mrad": 1e-3, "urad": 1e-6},
    "torque": {"": 1.0, "Nm": 1.0, "mNm": 1e-3, "kNm": 1e3},
    "force": {"": 1.0, "N": 1.0, "kN": 1e3},
    "speed": {"": 1.0, "rad_s": 1.0, "rpm": 2 * math.pi / 60},
    "linear_speed": {"": 1.0, "m_s": 1.0, "mm_s": 1e-3, "m_min": 1 / 60},
    "inertia": {"": 1.0, "kgm2": 1.0, "kgcm2": 1e-4, "gcm2": 1e-7},
    "inertia_per_length": {"": 1.0, "kgm2_m": 1.0, "kgcm2_m": 1e-4},
    "linear_density": {"": 1.0, "kg_m": 1.0},
    "mass": {"": 1.0, "kg": 1.0, "g": 1e-3},
    "power": {"": 1.0, "W": 1.0, "kW": 1e3},
    "energy": {"": 1.0, "J": 1.0, "kJ": 1e3},
    "pressure": {"": 1.0, "Pa": 1.0, "MPa": 1e6, "bar": 1e5},
    "current": {"": 1.0, "A": 1.0},
    "voltage": {"": 1.0, "V": 1.0},
    "resistance": {"": 1.0, "ohm": 1.0, "mohm": 1e-3},
    "torque_constant": {"": 1.0, "Nm_A": 1.0},
    "ratio": {"": 1.0},
    "fraction": {"": 1.0, "percent": 0.01},
    "money": {"eur": 1.0, "usd": 1.0},
    "time": {"": 1.0, "s": 1.0, "min": 60.0, "h": 3600.0},
    "temperature": {"": 1.0, "K": 1.0, "degC": 1.0},
    "thermal_resistance": {"": 1.0, "K_W": 1.0},
    "temperature_coefficient": {"": 1.0, "per_K": 1.0, "percent_K": 0.01},
    "rate": {"per_s": 1.0, "per_min": 1 / 60, "per_h": 1 / 3600},  # events per time, 1/s inside; a suffix required
    "text": {"": 1.0},
    "count": {"": 1.0},
}

#: The SI unit of each kind, as printed in reports.
SI: dict[str, str] = {"length": "m", "angle": "rad", "torque": "N·m", "force": "N", "speed": "rad/s",
                      "linear_speed": "m/s", "inertia": "kg·m²", "mass": "kg", "power": "W", "pressure": "Pa",
                      "time": "s", "rate": "1/s", "ratio": "-", "fraction": "-", "temperature": "K",
                      "thermal_resistance": "K/W", "temperature_coefficient": "1/K",
                      "energy": "J"}

#: Units whose zero is not SI's: (kind, suffix) → the offset added after the factor (T_K = T_°C + 273.15). A
#: temperature is read in °C only from a field whose name says so (``_degC``).
OFFSETS: dict[tuple[str, str], float] = {("temperature", "degC"): 273.15}


def factor(kind: str, suffix: str) -> float | None:
    """The factor that converts a value of ``kind`` given in unit ``suffix`` to SI, or ``None`` if that unit is not
    known for that kind."""
    return UNITS[kind].get(suffix)


def offset(kind: str, suffix: str) -> float:
    """What is added to a value of ``kind`` in unit ``suffix`` after its factor (:func:`factor`) to make it SI: 0
    but for °C (273.15)."""
    return OFFSETS.get((kind, suffix), 0.0)


def suffixes(kind: str) -> list[str]:
    """The unit suffixes accepted for ``kind`` (without the SI one, which needs no suffix)."""
    return [s for s in UNITS[kind] if s]

r"""Derating of a motor's continuous (S1) torque for where the machine runs: the ambient temperature and the altitude.

A motor's catalog rating holds at the rated site of IEC 60034-1: a coolant (air) of at most 40 °C and an altitude of
at most 1,000 m [IEC 60034-1, 6]. Beyond it (mechatron's documented default, applied to every motor of a catalog):

- **ambient** θ_a > 40 °C, the rise-limited rule: the copper loss I² R, ∝ T², may raise the winding by the rated
  rise ΔT_r less the extra ambient, so T_S1 is scaled by

      f_θ = √((ΔT_r − (θ_a − 40 °C)) / ΔT_r)    (0 once θ_a ≥ 40 °C + ΔT_r; 1 at or below 40 °C: no uprating),

  ΔT_r = :data:`RATED_RISE` (100 K, our default: a class-F winding rated for a 100 K rise at 40 °C). A motor rated
  for 100 K run at 65 °C keeps √(75/100) = 0.866 of its S1 torque.
- **altitude** h > 1,000 m, the thinner air cooling less: T_S1 is scaled by

      f_h = 1 − :data:`ALTITUDE_RATE` · (h − 1,000 m)    (10 % per 1,000 m, our default),

  floored at 0.

A motor with the thermal columns (:mod:`mechatron.drives.thermal`) is derated by its own model instead: the ambient
enters its allowed rise T_max − θ_a (so f_θ is not applied twice) and the altitude its housing-to-ambient thermal
resistance, R_ha / f_h² (the torque the same copper loss allows scales as √(1/R): f_h for R_ha alone, on the safe
side of the two-node network). The derated catalog's S1 curve is the one checked and charted.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..errors import InputError

#: The rated site (IEC 60034-1): ambient (°C) and altitude (m) up to which a catalog's rating holds.
RATED_AMBIENT_DEGC = 40.0
RATED_ALTITUDE = 1000.0
#: The winding rise (K) of the rating, our default (module docstring).
RATED_RISE = 100.0
#: The S1 torque lost per metre above :data:`RATED_ALTITUDE` (1/m): 10 % per 1,000 m, our default.
ALTITUDE_RATE = 1e-4
#: The altitudes a sizing accepts (m): from below the lowest dry land (the Dead Sea's shore, about −430 m) to above
#: the highest permanent settlements (about 5,100 m), our range: beyond it an altitude is a slip of unit or sign.
ALTITUDE_RANGE = (-500.0, 6000.0)


def check_altitude(value: object) -> float:
    """``value``, an altitude in metres within :data:`ALTITUDE_RANGE`, else an :class:`~mechatron.errors.InputError`
    giving the range."""
    low, high = ALTITUDE_RANGE
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise InputError(f"altitude must be a number of {low:g} … {high:g} m (from below the Dead Sea's shore to "
                         f"above the highest settlements), got {value!r}")
    return float(value)


def ambient_factor(ambient_degC: float, rated_rise: float = RATED_RISE) -> float:
    """f_θ = √((ΔT_r − (θ_a − 40)) / ΔT_r) for the ambient θ_a (°C) and the rated rise ΔT_r (K); 1 at or below
    40 °C, 0 once the ambient takes the whole rise."""
    extra = max(ambient_degC - RATED_AMBIENT_DEGC, 0.0)
    return math.sqrt(max(rated_rise - extra, 0.0) / rated_rise)


def altitude_factor(altitude: float) -> float:
    """f_h = 1 − :data:`ALTITUDE_RATE` · (h − 1,000 m) for the altitude h (m) above 1,000 m, 1 below, ≥ 0."""
    return max(1.0 - ALTITUDE_RATE * max(altitude - RATED_ALTITUDE, 0.0), 0.0)


def derate(motors: pd.DataFrame, ambient_degC: float, altitude: float = 0.0) -> pd.DataFrame:
    """The motor catalog ``motors`` (SI) derated for the ambient θ_a (°C) and the altitude h (m) (module docstring):
    rated torque × f_θ f_h for a motor without the thermal columns, R_ha / f_h² for one with them (its ambient is its
    own model's). The catalog itself where both factors are 1."""
    f_theta, f_h = ambient_factor(ambient_degC), altitude_factor(check_altitude(altitude))
    if f_theta == 1.0 and f_h == 1.0:
        return motors
    out = motors.copy()
    heated = out["rth_housing_ambient"].notna().to_numpy() if "rth_housing_ambient" in out else \
        np.zeros(len(out), dtype=bool)
    rated = out["rated_torque"].to_numpy(dtype=float)
    out["rated_torque"] = np.where(heated, rated, rated * f_theta * f_h)
    if heated.any():
        with np.errstate(divide="ignore"):
            out["rth_housing_ambient"] = np.where(heated, out["rth_housing_ambient"].to_numpy(dtype=float) / f_h**2,
                                                  math.nan)
    return out

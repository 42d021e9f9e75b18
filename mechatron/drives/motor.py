"""Speed–torque limits of a servo motor from its catalog data (vectorized over motors).

The catalogs give rated torque T_r, peak torque T_p, rated speed n_r and maximum speed n_max. The limits used:

- continuous (S1) zone: T_r up to n_r, then constant power T_r·n_r/n up to n_max;
- intermittent (peak) zone: T_p up to n_r, then falling linearly to T_r·n_r/n_max at n_max (the voltage limit);
- no torque beyond n_max.

Real curves differ in detail from maker to maker; a user's catalog with measured curves would refine this.

Where a catalog also gives the torque constant k_t (N·m/A), the winding resistance R (Ω) and the supply voltage U
(V), the motor is also taken as its equivalent DC motor: current I = T/k_t, terminal voltage u = k_e ω + R I with
k_e = k_t (SI units: V·s/rad = N·m/A, so that the electrical power u I = T ω + R I² is the shaft power plus the
copper loss). The voltage limit |u| ≤ U is the line T_U(ω) = k_t (U − k_t |ω|) / R of the speed–torque plane: the
speed at which the back-EMF and the resistive drop reach the supply voltage, ω_U(T) = (U − R |T| / k_t) / k_t.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

#: The optional catalog columns of the equivalent DC motor: all three, or none, in a row.
ELECTRICAL_COLUMNS = ("torque_constant", "resistance", "voltage")


def catalog_column(catalog: pd.DataFrame, name: str, default: float = math.nan) -> NDArray[np.float64]:
    """The numbers of column ``name`` of a catalog (float), ``default`` where the column or a cell is missing."""
    if name not in catalog:
        return np.full(len(catalog), default)
    values = catalog[name].to_numpy(dtype=float)
    return values if math.isnan(default) else np.where(np.isnan(values), default, values)


def continuous_torque(speed: ArrayLike, rated_torque: ArrayLike, rated_speed: ArrayLike,
                      max_speed: ArrayLike) -> NDArray[np.float64]:
    """S1 torque (N·m) available at |speed| (rad/s): T_r up to n_r, T_r n_r / n up to n_max, 0 beyond; torques in
    N·m, speeds in rad/s; arrays broadcast together."""
    n = np.abs(speed)
    out = np.where(n <= rated_speed, rated_torque, rated_torque * rated_speed / np.maximum(n, 1e-300))
    return np.where(n <= max_speed, out, 0.0)


def peak_torque_limit(speed: ArrayLike, peak_torque: ArrayLike, rated_torque: ArrayLike,
                      rated_speed: ArrayLike, max_speed: ArrayLike) -> NDArray[np.float64]:
    """Intermittent torque (N·m) available at |speed| (rad/s): T_p up to n_r, then linear down to T_r n_r / n_max
    at n_max, 0 beyond; torques in N·m, speeds in rad/s; arrays broadcast together."""
    n = np.abs(speed)
    at_max = rated_torque * rated_speed / max_speed
    fraction = np.clip((n - rated_speed) / np.maximum(max_speed - rated_speed, 1e-300), 0.0, 1.0)
    out = peak_torque + (at_max - peak_torque) * fraction
    return np.where(n <= max_speed, out, 0.0)


def electrical_data(motors: pd.DataFrame, voltage: float | None = None
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(k_t in N·m/A, R in Ω, U in V) of every motor of a catalog, NaN where the catalog does not give them;
    ``voltage`` (V) replaces the catalog's supply voltage of the motors with k_t and R."""
    kt, resistance, supply = (catalog_column(motors, name) for name in ELECTRICAL_COLUMNS)
    if voltage is not None:
        supply = np.where(np.isfinite(kt) & np.isfinite(resistance), voltage, math.nan)
    return kt, resistance, supply


def current(torque: ArrayLike, torque_constant: ArrayLike) -> NDArray[np.float64]:
    """Motor current I = T / k_t (A) for the torque T (N·m) and torque constant k_t (N·m/A)."""
    return np.asarray(torque, dtype=float) / np.asarray(torque_constant, dtype=float)


def terminal_voltage(speed: ArrayLike, torque: ArrayLike, torque_constant: ArrayLike,
                     resistance: ArrayLike) -> NDArray[np.float64]:
    """u = k_t ω + R T / k_t (V), the back-EMF plus the resistive drop, at the speed ω (rad/s) and torque T (N·m)."""
    kt = np.asarray(torque_constant, dtype=float)
    return kt * np.asarray(speed, dtype=float) + np.asarray(resistance) * np.asarray(torque, dtype=float) / kt


def voltage_limited_torque(speed: ArrayLike, torque_constant: ArrayLike, resistance: ArrayLike,
                           voltage: ArrayLike) -> NDArray[np.float64]:
    """T_U(ω) = k_t (U − k_t |ω|) / R (N·m, ≥ 0): the largest torque the supply voltage U (V) allows at |ω| (rad/s)
    for the torque constant k_t (N·m/A) and resistance R (Ω); arrays broadcast."""
    kt = np.asarray(torque_constant, dtype=float)
    return np.maximum(kt * (np.asarray(voltage) - kt * np.abs(speed)) / np.asarray(resistance), 0.0)


def voltage_limit_speed(torque: ArrayLike, torque_constant: ArrayLike, resistance: ArrayLike,
                        voltage: ArrayLike) -> NDArray[np.float64]:
    """ω_U(T) = (U − R |T| / k_t) / k_t (rad/s, ≥ 0): the speed at which the back-EMF k_t ω plus the drop R I of
    the current I = |T| / k_t reaches the supply voltage U (V); arrays broadcast."""
    kt = np.asarray(torque_constant, dtype=float)
    return np.maximum((np.asarray(voltage) - np.asarray(resistance) * np.abs(torque) / kt) / kt, 0.0)

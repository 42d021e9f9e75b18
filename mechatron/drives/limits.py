"""The settings of the vendor checks beyond the catalogs: :class:`DriveLimits` (the emergency-stop limit, the screw
life, the supply voltage, the ambient and the holding brakes'), a value of its own so that the checks
(:mod:`~mechatron.drives.checks`, which re-exports it) and the options of a sizing (:mod:`~mechatron.drives.options`)
both import it from below.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .brakes import BRAKE_FACTOR, STOPS_PER_HOUR
from .screws import SCREW_LIFE
from .thermal import AMBIENT_RANGE, DEFAULT_AMBIENT, ZERO_CELSIUS


class MotorColumns(Protocol):
    """The columns of a motor catalog the limits read, one entry a motor (SI): peak torque T_peak (N·m), torque
    constant k_t (N·m/A), winding resistance R (Ω) and catalog voltage U (V), NaN where missing
    (:class:`~mechatron.drives.checks.MotorArrays`)."""

    @property
    def peak(self) -> NDArray[np.float64]: ...

    @property
    def kt(self) -> NDArray[np.float64]: ...

    @property
    def resistance(self) -> NDArray[np.float64]: ...

    @property
    def voltage(self) -> NDArray[np.float64]: ...



@dataclass(frozen=True)
class DriveLimits:
    """Settings of the vendor checks beyond the catalogs (SI units).

    Attributes:
        stop_torque: The motor torque (N·m) the drive is limited to in an emergency stop; the gearbox's
            emergency check takes min(stop_torque, T_peak) · u instead of T_peak · u.
        stop_current: The same as a current limit (A): the stop torque of each motor is k_t · stop_current (never
            above T_peak; a motor without a torque constant keeps T_peak). Give one of the two.
        screw_life: The required nominal life of a screw running the task over and over (s; default 20 000 h).
        voltage: The supply voltage (V) of the voltage-limit check, instead of each motor's catalog voltage.
        ambient: The ambient temperature (K; default 313.15 K, 40 °C) of the winding temperature check
            (:mod:`~mechatron.drives.thermal`): the winding may rise by its limit temperature minus it.
        brake_factor: The holding brake's factor f ≥ 1: T_h ≥ f · T_g (:mod:`~mechatron.drives.brakes`; default 2).
        brake_stops_per_hour: The emergency stops per hour of the brake's energy-per-hour check (> 0; default 1).
    """

    stop_torque: float | None = None
    stop_current: float | None = None
    screw_life: float = SCREW_LIFE
    voltage: float | None = None
    ambient: float = DEFAULT_AMBIENT
    brake_factor: float = BRAKE_FACTOR
    brake_stops_per_hour: float = STOPS_PER_HOUR

    def __post_init__(self) -> None:
        if not (isinstance(self.brake_factor, (int, float)) and 1 <= self.brake_factor <= 100):
            raise InputError(f"brake_factor must be a number of 1 … 100, got {self.brake_factor!r}")
        if not (isinstance(self.brake_stops_per_hour, (int, float)) and 0 < self.brake_stops_per_hour <= 1e6):
            raise InputError(f"brake_stops_per_hour must be a number > 0 and <= 1e6, got {self.brake_stops_per_hour!r}")
        for name in ("stop_torque", "stop_current", "voltage"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"{name} must be a finite number > 0, got {value!r}")
        if self.stop_torque is not None and self.stop_current is not None:
            raise InputError("give the emergency-stop limit as a torque or as a current, not both")
        if not (math.isfinite(self.screw_life) and self.screw_life > 0):
            raise InputError(f"screw_life must be a finite number of seconds > 0, got {self.screw_life!r}")
        low, high = AMBIENT_RANGE
        if not (isinstance(self.ambient, (int, float)) and low <= self.ambient <= high):
            raise InputError(f"ambient must be a temperature of {low:g} … {high:g} K ({low - ZERO_CELSIUS:g} … "
                             f"{high - ZERO_CELSIUS:g} °C), got {self.ambient!r}")

    def stop_torques(self, motors: MotorColumns) -> NDArray[np.float64]:
        """The torque (N·m) each motor gives in an emergency stop: min(limit, T_peak), T_peak without a limit (a
        current limit: k_t · current, T_peak for a motor without k_t)."""
        if self.stop_torque is not None:
            return np.minimum(motors.peak, self.stop_torque)
        if self.stop_current is not None:
            return np.where(np.isfinite(motors.kt), np.minimum(motors.peak, motors.kt * self.stop_current), motors.peak)
        return motors.peak

    def supply(self, motors: MotorColumns) -> NDArray[np.float64]:
        """The supply voltage (V) of each motor's voltage-limit check: :attr:`voltage` for the motors with k_t and
        R, else the catalog's (NaN where it does not apply)."""
        if self.voltage is None:
            return motors.voltage
        return np.where(np.isfinite(motors.kt) & np.isfinite(motors.resistance), self.voltage, math.nan)

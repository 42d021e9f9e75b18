r"""Servo drives (amplifiers) from a catalog (kind ``drives``): each motor paired with a drive, and the drive's checks.

A drive gives the motor its current: a rated (continuous) output current I_r, a peak current I_p ≥ I_r for at most
t_p seconds, from a DC link of U_min … U_max volts. Pairing motor and drive (:func:`pair_drives`):

- the pair's usable peak torque is T_p' = k_t · min(I_p,motor, I_p) = min(T_p, k_t I_p), the motor's peak current
  being I_p,motor = T_p / k_t (a motor without a torque constant k_t cannot be paired: it is left out);
- the voltage-limit check (:mod:`mechatron.drives.motor`) takes the drive's DC link as the supply: U = min(the
  motor's catalog voltage, U_max), U_max where the catalog gives none; a supply given as an option (``--voltage``)
  pairs only the drives whose range U_min … U_max holds it;
- the objective's mass and price count the drive's (the drive sits in the cabinet: its mass loads no body).

The drive's overload model is **mechatron's two-level foldback** (ours, not a maker's rule): the drive gives up to
I_p for at most t_p, then folds back to I_r; over the task repeated (:func:`overload`)

    RMS current  √⟨I²⟩ ≤ I_r,    longest run of |I(t)| > I_r  ≤ t_p,    I = T_m / k_t,

the RMS the thermal budget of the drive's power stage (its I²t in steady state), the run the time the peak may
last (a run through the task's end and start counts once: the task repeats). The peak |I| ≤ I_p is the motor's
peak-torque check with T_p'.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .motor import catalog_column

#: The columns a paired motor row carries from its drive (SI): key, rated and peak current (A), peak time (s), mass
#: (kg), price.
DRIVE_COLUMNS = ("drive_key", "drive_rated_current", "drive_peak_current", "drive_peak_time", "drive_mass",
                 "drive_price")


def pair_drives(motors: pd.DataFrame, drives: pd.DataFrame, voltage: float | None = None) -> pd.DataFrame:
    """The motor catalog ``motors`` (SI) paired with every drive of ``drives`` (SI, kind ``drives``): one row per
    motor × drive, keyed ``motor + drive``, with the peak torque min(T_p, k_t I_p), the supply voltage of the
    drive's DC link (module docstring), the price of both, and the drive's :data:`DRIVE_COLUMNS`. Motors without a
    torque constant are left out; ``voltage`` (V, the sizing's supply) pairs only the drives whose DC-link range
    holds it.

    Raises:
        InputError: when no pair is left (no motor with a torque constant, or no drive for the supply voltage).
    """
    kt = catalog_column(motors, "torque_constant")
    paired = motors[np.isfinite(kt)]
    if voltage is not None:
        drives = drives[(drives["dc_link_min"] <= voltage) & (voltage <= drives["dc_link_max"])]
    if paired.empty or drives.empty:
        why = "no motor gives its torque constant (torque_constant)" if paired.empty else \
            f"no drive's DC-link range holds the supply voltage {voltage:g} V"
        raise InputError(f"no motor can be paired with a drive: {why}")
    rows = []
    for _, drive in drives.iterrows():
        rows.append(_paired(paired, drive))
    return pd.concat(rows, ignore_index=True)


def _paired(motors: pd.DataFrame, drive: pd.Series) -> pd.DataFrame:
    """The rows of ``motors`` (each with k_t) paired with one ``drive`` (:func:`pair_drives`)."""
    out = motors.copy()
    kt = out["torque_constant"].to_numpy(dtype=float)
    out["key"] = out["key"].astype(str) + " + " + str(drive["key"])
    out["peak_torque"] = np.minimum(out["peak_torque"].to_numpy(dtype=float), kt * float(drive["peak_current"]))
    if "resistance" in out:
        given = catalog_column(out, "voltage")
        supply = np.where(np.isnan(given), drive["dc_link_max"], np.minimum(given, drive["dc_link_max"]))
        out["voltage"] = np.where(np.isfinite(out["resistance"].to_numpy(dtype=float)), supply, math.nan)
    price = float(drive["price"]) if "price" in drive and np.isfinite(drive["price"]) else 0.0
    out["price"] = catalog_column(out, "price", 0.0) + price
    values = (str(drive["key"]), drive["rated_current"], drive["peak_current"], drive["peak_time"],
              drive["mass"] if "mass" in drive and np.isfinite(drive["mass"]) else 0.0, price)
    for name, value in zip(DRIVE_COLUMNS, values):
        out[name] = value
    return out


@dataclass(frozen=True)
class DriveData:
    """The drives paired with the motors of a catalog, as arrays (SI): rated current I_r (A; inf for a motor
    without a drive, so that its checks do not apply), peak time t_p (s; inf), mass (kg; 0) and price (0)."""

    rated: NDArray[np.float64]
    peak_time: NDArray[np.float64]
    mass: NDArray[np.float64]

    @classmethod
    def of(cls, motors: pd.DataFrame) -> DriveData | None:
        """The drives of a paired motor catalog (:func:`pair_drives`), ``None`` for a catalog without drives."""
        if "drive_rated_current" not in motors:
            return None
        return cls(catalog_column(motors, "drive_rated_current", math.inf),
                   catalog_column(motors, "drive_peak_time", math.inf), catalog_column(motors, "drive_mass", 0.0))


def longest_run(t: ArrayLike, above: ArrayLike) -> float:
    """The longest time (s) ``above`` holds over the samples ``t`` (s) of a task that repeats: a run lasts from its
    first sample to the first sample after it (each sample stands for the interval to the next one; the last
    sample's to the task's end, t[-1], is none), and a run through the task's end and its start counts once."""
    t, above = np.asarray(t, dtype=float), np.asarray(above, dtype=bool)
    if not above.any():
        return 0.0
    step = np.diff(t)
    if above[:-1].all():
        return float(t[-1] - t[0])
    longest, run = 0.0, 0.0
    # twice round the task (the cycle repeats), intervals [t_k, t_k+1] counted where the sample k is above
    for k in list(range(len(step))) * 2:
        run = run + step[k] if above[k] else 0.0
        longest = max(longest, run)
    return float(longest)


def overload(t: ArrayLike, current: ArrayLike, rated: float) -> tuple[float, float]:
    """(RMS current √⟨I²⟩ (A), the longest run of |I| > I_r (s)) of the current ``current`` (A) at the samples ``t``
    (s) of a repeated task: the values of the foldback checks (module docstring), the mean by the trapezoidal
    rule."""
    t, i = np.asarray(t, dtype=float), np.asarray(current, dtype=float)
    span = t[-1] - t[0]
    rms = math.sqrt(float(np.trapezoid(i * i, t) / span)) if span > 0 else float(np.abs(i).max(initial=0.0))
    return rms, longest_run(t, np.abs(i) > rated * (1 + 1e-12))


def read_drives(path: str) -> pd.DataFrame:
    """The drive catalog at ``path`` (kind ``drives``, checked: :func:`~mechatron.drives.catalogs.read_catalog`)."""
    from .catalogs import read_catalog

    return read_catalog(path, "drives")


#: The servo drive's checks of a motor × converter pair (:mod:`mechatron.drives.checks`) and their units.
DRIVE_CHECKS = ("drive RMS current", "drive overload time")
DRIVE_UNITS = ("A", "s")

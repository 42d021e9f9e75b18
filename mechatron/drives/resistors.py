r"""The braking resistor of a common DC bus chosen from a catalog, or a regenerative supply: :func:`size_braking`.

The bus power P_bus(t) (W, < 0 given back; :class:`~mechatron.drives.electrical.ElectricalBalance`) over a cycle of
length T gives

- the peak braking power P_peak = max(−P_bus, 0);
- the mean regenerated power per cycle P_mean = E_reg / T, E_reg = ∫ max(−P_bus, 0) dt;
- the braking intervals (the runs where P_bus < 0, split at the zeros of the linear interpolation) and the largest
  regenerated energy of one of them, E_pulse = max ∫_interval −P_bus dt, with that interval's length t_pulse.

A resistor of the ``resistors`` catalog (resistance R (Ω), continuous power P_c (W), pulse energy E_p (J) taken in
the pulse time t_p (s), mass, price) passes where

    R_min ≤ R ≤ U_max² / P_peak,   P_c ≥ P_mean,   E_p + P_c · max(0, t_pulse − t_p) ≥ E_pulse,

R_min the drive's smallest braking resistance (its chopper's current limit; ``resistor_min``, default 0) and U_max
the bus voltage at which the chopper switches the resistor in (``bus_voltage``; default the largest supply voltage
of the chosen motors): at U_max the resistor takes U_max²/R ≥ P_peak. A pulse longer than t_p is taken as the pulse
energy plus the continuous power over the rest (our rule, the conservative reading of a two-figure rating). Of the
resistors that pass, the lightest (then the cheapest; ``cost``: the cheapest, then the lightest) is chosen.

With a regenerative supply (``regenerative=True``) no resistor is chosen: the supply must feed P_peak back to the
mains, and the totals give the rating it needs (peak and mean regenerated power).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..errors import InputError
from ..report.result import json_ready

#: The checks of a braking resistor (value ≤ limit; the resistance's lower bound as R_min ≤ R).
RESISTOR_CHECKS = ("resistance (max U²/P_peak)", "resistance (min of the drive)", "continuous power",
                   "pulse energy")


def braking_intervals(t: ArrayLike, power: ArrayLike) -> list[tuple[float, float]]:
    """The intervals where the power P (W) sampled at t (s), linear between samples, is < 0, each as (its
    regenerated energy ∫ −P dt (J), its length (s)); the crossings of zero found by linear interpolation."""
    t, p = np.asarray(t, dtype=float), np.asarray(power, dtype=float)
    out: list[tuple[float, float]] = []
    energy, start = 0.0, None
    for k in range(len(t) - 1):
        a, b, t0, t1 = p[k], p[k + 1], t[k], t[k + 1]
        if a < 0 and start is None:
            start = t0
        if a >= 0 and b < 0:  # enters braking inside the interval
            tz = t0 + (t1 - t0) * a / (a - b)
            start, energy = tz, energy - b * (t1 - tz) / 2
        elif a < 0 and b >= 0:  # leaves braking inside the interval
            tz = t0 + (t1 - t0) * (-a) / (b - a)
            energy -= a * (tz - t0) / 2
            out.append((energy, tz - start))
            energy, start = 0.0, None
        elif a < 0 and b < 0:
            energy -= (a + b) * (t1 - t0) / 2
    if start is not None:
        out.append((energy, t[-1] - start))
    return out


@dataclass
class BrakingSupply:
    """What takes the DC bus's regenerated energy: a braking resistor from a catalog, or a regenerative supply.

    Attributes:
        regenerative: a regenerative supply (no resistor).
        peak_power, mean_power: P_peak and P_mean (W); pulse_energy, pulse_time: E_pulse (J) and its interval's
            length (s); bus_voltage: U_max (V, NaN where unknown); resistor_min: R_min (Ω).
        resistor: the chosen resistor's catalog row (``None``: none passes, or a regenerative supply).
        checks: the chosen (or, where none passes, the closest) resistor's checks: (name, value, limit, unit).
    """

    regenerative: bool
    peak_power: float
    mean_power: float
    pulse_energy: float
    pulse_time: float
    bus_voltage: float
    resistor_min: float
    resistor: dict | None = None
    checks: list[tuple[str, float, float, str]] = field(default_factory=list)

    @property
    def feasible(self) -> bool:
        return self.regenerative or (self.resistor is not None and all(v <= lim * (1 + 1e-9)
                                                                       for _, v, lim, _ in self.checks))

    def as_dict(self) -> dict:
        """kind (``regenerative supply`` or ``braking resistor``), the needs (W, J, s, V, Ω), the resistor's key,
        and its checks with their margins (1 − value/limit)."""
        return json_ready({
            "kind": "regenerative supply" if self.regenerative else "braking resistor", "feasible": self.feasible,
            "peak_braking_power_W": self.peak_power, "mean_regenerated_power_W": self.mean_power,
            "largest_pulse_energy_J": self.pulse_energy, "pulse_duration_s": self.pulse_time,
            "bus_voltage_V": self.bus_voltage, "resistor": None if self.resistor is None else self.resistor["key"],
            "checks": [{"name": n, "value": v, "limit": lim, "unit": u, "margin": _margin(v, lim)}
                       for n, v, lim, u in self.checks]})

    def line(self) -> str:
        """The totals' line: which, and the margins."""
        if self.regenerative:
            return (f"  regenerative supply: rated to feed back {self.peak_power:.4g} W peak, {self.mean_power:.4g} W "
                    f"mean ({self.pulse_energy:.4g} J the largest braking pulse); no braking resistor")
        if self.resistor is None and not self.checks:
            return "  braking resistor: none in the catalog"
        margins = ", ".join(f"{n} {v:.4g}/{lim:.4g} {u} (margin {_margin(v, lim):+.1%})"
                            for n, v, lim, u in self.checks)
        name = self.resistor["key"] if self.resistor is not None else "none passes"
        return f"  braking resistor: {name}{'' if self.feasible else ' — NOT FEASIBLE'}: {margins}"


def _margin(value: float, limit: float) -> float:
    return 1 - value / limit if limit > 0 else (1.0 if value <= 0 else -math.inf)


def size_braking(t: ArrayLike, bus_power: ArrayLike, resistors: pd.DataFrame | None = None, *,
                 regenerative: bool = False, bus_voltage: float = math.nan, resistor_min: float = 0.0,
                 objective: str = "mass") -> BrakingSupply:
    """The braking resistor (or regenerative supply) for the bus power ``bus_power`` (W) at the times ``t`` (s):
    the module docstring. ``resistors``: a catalog of kind ``resistors`` (SI, :func:`~mechatron.drives.catalogs.
    read_catalog`); ``bus_voltage``: U_max (V; NaN: the resistance's upper bound is not checked)."""
    t, p = np.asarray(t, dtype=float), np.asarray(bus_power, dtype=float)
    if not (math.isfinite(resistor_min) and resistor_min >= 0):
        raise InputError(f"resistor_min must be a finite resistance >= 0 (Ω), got {resistor_min!r}")
    from .electrical import positive_energy

    duration = float(t[-1] - t[0])
    peak = float(max(-p.min(initial=0.0), 0.0))
    mean = positive_energy(t, -p) / duration if duration > 0 else 0.0
    pulses = braking_intervals(t, p)
    pulse, length = max(pulses, default=(0.0, 0.0))
    out = BrakingSupply(regenerative, peak, mean, pulse, length, bus_voltage, resistor_min)
    if regenerative or resistors is None or len(resistors) == 0:
        return out
    r = resistors["resistance"].to_numpy(dtype=float)
    pc, ep, tp = (resistors[k].to_numpy(dtype=float) for k in ("continuous_power", "pulse_energy", "pulse_time"))
    top = bus_voltage**2 / peak if peak > 0 and math.isfinite(bus_voltage) else math.inf
    values = np.column_stack([r, np.full(len(r), resistor_min), np.full(len(r), mean), np.full(len(r), pulse)])
    limits = np.column_stack([np.full(len(r), top), r, pc, ep + pc * np.maximum(0.0, length - tp)])
    with np.errstate(divide="ignore", invalid="ignore"):
        factors = np.where(values <= 0, 0.0, values / limits).max(axis=1)
    mass = np.nan_to_num(resistors["mass"].to_numpy(dtype=float)) if "mass" in resistors else np.zeros(len(r))
    price = np.nan_to_num(resistors["price"].to_numpy(dtype=float)) if "price" in resistors else np.zeros(len(r))
    first, second = (price, mass) if objective == "cost" else (mass, price)
    passing = np.flatnonzero(factors <= 1 + 1e-9)
    if len(passing):
        best = int(passing[np.lexsort((passing, second[passing], first[passing]))[0]])
    else:
        best = int(np.argmin(factors))
    out.resistor = {k: (v.item() if hasattr(v, "item") else v) for k, v in resistors.iloc[best].items()}
    units = ("Ω", "Ω", "W", "J")
    out.checks = [(n, float(values[best, k]), float(limits[best, k]), units[k]) for k, n in enumerate(RESISTOR_CHECKS)
                  if math.isfinite(limits[best, k])]
    return out

r"""Mechanical efficiency [Egorov, section 7.7].

η = A_П / A_D = 1 − ψ with the loss coefficient ψ = A_B / A_D [Egorov, 7.45–7.47], or from the cycle-average powers
η = P_П / P_D [Egorov, 7.48–7.50], or from the efforts and the transmission ratio U = ω_in/ω_out [Egorov, 7.52]:
η = M_out / (M_in U) [Egorov, 7.51] (the book's last form F_out / M_in lacks U: with it, η = F_out / (M_in U) for a
rotary→linear converter). Series chains multiply [Egorov, 7.53]. Idle running has η = 0, ψ = 1; η < 0 means
self-locking, and |η| says how firmly [Egorov, section 7.7]. Not in the book, added for drives: parallel branches
and the screw pair. Efficiencies are dimensionless.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError


def efficiency_from_work(driving_work: float, lost_work: float) -> float:
    """η = 1 − A_B / A_D [Egorov, 7.46, 7.47]: driving and lost work (J) over a steady cycle."""
    if not driving_work > 0:
        raise InputError(f"the driving work over a cycle must be > 0 J, got {driving_work!r}")
    return 1.0 - lost_work / driving_work


def loss_coefficient(efficiency: float) -> float:
    """ψ = 1 − η [Egorov, 7.46]."""
    return 1.0 - efficiency


def efficiency_from_powers(output_power: float, input_power: float) -> float:
    """η = P_П / P_D [Egorov, 7.48] from cycle-average powers (W), P = M ω or F v [Egorov, 7.49, 7.50]."""
    if not input_power > 0:
        raise InputError(f"the input power must be > 0 W, got {input_power!r}")
    return output_power / input_power


def efficiency_from_ratio(output_effort: float, input_effort: float, ratio: float) -> float:
    """η = M_out / (M_in U) [Egorov, 7.51] (corrected): output and input torques or forces (N·m or N) and the ratio
    U = ω_in/ω_out [Egorov, 7.52] (rad/m for rotary→linear, m/rad for linear→rotary)."""
    if input_effort == 0 or ratio == 0:
        raise InputError("the input effort and the ratio must not be 0")
    return output_effort / (input_effort * ratio)


def series(efficiencies: ArrayLike) -> float:
    """η = Π η_i [Egorov, 7.53] of converters in series."""
    values = _values(efficiencies)
    if not values:
        raise InputError("a series chain needs at least one efficiency")
    out = 1.0
    for eta in values:
        _check(eta)
        out *= eta
    return out


def parallel(efficiencies: ArrayLike, input_powers: ArrayLike) -> float:
    """η = Σ P_i η_i / Σ P_i for branches sharing the input power P_i (W) (not in the book)."""
    efficiencies, input_powers = _values(efficiencies), _values(input_powers)
    if len(efficiencies) != len(input_powers) or not efficiencies:
        raise InputError("give one input power per branch")
    total = sum(input_powers)
    if not total > 0:
        raise InputError("the branches' input power must be > 0 W")
    return sum(e * p for e, p in zip(efficiencies, input_powers)) / total


def self_locking(efficiency: float) -> bool:
    """η < 0: the mechanism cannot be driven from this side [Egorov, section 7.7]."""
    return efficiency < 0


def screw_efficiency(lead: float, diameter: float, f: float, flank_angle: float = 0.0,
                     back_driven: bool = False) -> float:
    """A sliding screw pair (not in the book): lead angle λ = arctan(lead / (π d₂)), friction angle
    φ' = arctan(f / cos(flank half-angle)); driving the nut η = tan λ / tan(λ + φ'), back-driven
    η = tan(λ − φ') / tan λ (negative: self-locking). Lengths in m, angles in rad."""
    if not (lead > 0 and diameter > 0 and f >= 0):
        raise InputError("a screw needs lead > 0, diameter > 0 and f >= 0")
    lam = math.atan(lead / (math.pi * diameter))
    phi = math.atan(f / math.cos(flank_angle))
    if back_driven:
        return math.tan(lam - phi) / math.tan(lam)
    return math.tan(lam) / math.tan(lam + phi)


def _values(values: ArrayLike) -> list[float]:
    return [float(x) for x in np.asarray(values, dtype=float).ravel()]


def _check(eta: float) -> None:
    if not (math.isfinite(eta) and eta <= 1):
        raise InputError(f"an efficiency must be a finite number <= 1, got {eta!r}")

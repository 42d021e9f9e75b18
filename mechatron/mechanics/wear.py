r"""Wear and the service life of plain bearings [Egorov, sections 7.5–7.6], in consistent SI units.

The book's units in its sections 7.5–7.6 do not fit together, so
every function here works in SI with the **dimensionless** linear wear intensity J_h = wear depth / friction path
(the classic definition; the book's range 10⁻¹³…10⁻³ and its recommended 10⁻¹⁰ for mechatronic friction units only
make sense so, although the text labels J_h µm/km). What the book prints, where it differs:

- [Egorov, 7.29] L = [I] / ((J_h1 S₁ + J_h2 S₂) n) with n in rev/min gives minutes; here n is in rev/s and L in s;
- [Egorov, 7.33] L = [I] 10⁻⁶ / (J_h v) and [Egorov, 7.34] L = (π/φ₀)·[I] 10⁻⁶ / (J_h v) are right for [I] in µm,
  v in m/s and L in **seconds** (not hours);
- [Egorov, 7.36] "L in hours" with ν in 1/s gives seconds;
- [Egorov, 7.38] swaps R₁ and R₂ (index 1 is the bushing throughout);
- [Egorov, 7.39–7.44] carry 10⁻³ where D₂ in metres needs 10⁻⁶, and [Egorov, 7.41–7.42] take β in degrees
  (57.3 = 180/π) while [Egorov, 7.39–7.40] take it in radians;
- φ₀, called the friction angle, is the half-angle of the loaded contact arc.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.values import positives as _positive

ZONES = ("bushing", "shaft")


def wear_rate(wear: float, duration: float) -> float:
    """γ_h = ΔI_h / Δt [Egorov, 7.20], m/s (the book: µm/h; 2…4·10⁻⁴ µm/h for bearings, guides, lead screws, gears)."""
    _positive(duration=duration)
    return wear / duration


def linear_wear_intensity(wear: float, path: float) -> float:
    """J_h = I_h / S [Egorov, 7.21], dimensionless (m of wear per m of friction path)."""
    _positive(path=path)
    return wear / path


def mass_wear_intensity(mass_loss: float, path: float) -> float:
    """J_m = I_m / S [Egorov, 7.22], kg/m."""
    _positive(path=path)
    return mass_loss / path


def volume_wear_intensity(volume_loss: float, path: float) -> float:
    """J_v = I_v / S [Egorov, 7.23], m³/m."""
    _positive(path=path)
    return volume_loss / path


def wear_depth(t: ArrayLike, pressure: ArrayLike, speed: ArrayLike, k: float, m: float = 1.0, n: float = 1.0
               ) -> NDArray[np.float64]:
    """I_h(t) = ∫₀ᵗ k p^m v^n dt [Egorov, 7.24] (m = n = 1: [Egorov, 7.25–7.26], γ_h = k p v), m, along samples t (s)
    of the contact pressure p (Pa) and sliding speed v (m/s); k in m / (Pa^m (m/s)^n s). The book gives
    m = 0.5…3.0 and n = 0.9…1.2 [Egorov, section 7.5]."""
    t = np.asarray(t, dtype=float)
    p = np.broadcast_to(np.asarray(pressure, dtype=float), t.shape)
    v = np.broadcast_to(np.asarray(speed, dtype=float), t.shape)
    if len(t) < 2 or np.any(np.diff(t) <= 0):
        raise InputError("give at least two samples at increasing times")
    if np.any(p < 0):
        raise InputError("a contact pressure must be >= 0")
    _positive(m=m, n=n)
    rate = k * p**m * np.abs(v) ** n
    return np.concatenate([[0.0], np.cumsum(np.diff(t) * (rate[1:] + rate[:-1]) / 2)])


# ------------------------------------------------------------------------------------------------ bearings
@dataclass(frozen=True)
class Bearing:
    """A cylindrical plain bearing: shaft radius R₁ and bushing radius R₂ (m), the half-angle φ₀ (rad) of the
    loaded contact arc (2φ₀ wide), the allowable wear [I] (m; a wear layer h, or [Δ] − Δ of 7.30) and the wear
    intensities of the bushing J_h1 and of the shaft J_h2 (dimensionless; 0 for an element that does not wear)."""

    shaft_radius: float
    bushing_radius: float
    contact_half_angle: float
    allowable_wear: float
    bushing_intensity: float = 1e-10
    shaft_intensity: float = 1e-10

    def __post_init__(self) -> None:
        _positive(shaft_radius=self.shaft_radius, bushing_radius=self.bushing_radius,
                  allowable_wear=self.allowable_wear)
        if not 0 < self.contact_half_angle <= math.pi:
            raise InputError(f"the contact half-angle must be in (0, π] rad, got {self.contact_half_angle!r}")
        for name in ("bushing_intensity", "shaft_intensity"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise InputError(f"{name} must be >= 0 (dimensionless), got {value!r}")
        if self.bushing_intensity == 0 and self.shaft_intensity == 0:
            raise InputError("at least one element must wear (a wear intensity > 0)")

    def revolution_paths(self, zone: str) -> tuple[float, float]:
        """(S₁ bushing, S₂ shaft), the friction path (m) per revolution: with the loaded zone fixed on the bushing
        ([Egorov, fig. 7.5] a, b: shaft turning under a fixed load, or bushing turning with the load) S₁ = 2πR₂,
        S₂ = 2φ₀R₁ [Egorov, 7.31]; fixed on the shaft (c, d) S₁ = 2φ₀R₂, S₂ = 2πR₁ [Egorov, 7.32]."""
        R1, R2, phi0 = self.shaft_radius, self.bushing_radius, self.contact_half_angle
        if zone == "bushing":
            return 2 * math.pi * R2, 2 * phi0 * R1
        if zone == "shaft":
            return 2 * phi0 * R2, 2 * math.pi * R1
        raise InputError(f"the loaded zone is fixed on the 'bushing' or the 'shaft', got {zone!r}")

    def swing_paths(self, zone: str, swing: float) -> tuple[float, float]:
        """(S₁, S₂), the friction path (m) per swing cycle of amplitude β (rad): the element carrying the loaded
        zone slides 2βR; the other slides 2βR while β < 2φ₀ (its points stay in the zone) and 4φ₀R beyond
        [Egorov, 7.37, 7.38] (in 7.38 the book swaps R₁ and R₂)."""
        _positive(swing=swing)
        R1, R2, phi0 = self.shaft_radius, self.bushing_radius, self.contact_half_angle
        if zone == "bushing":
            return 2 * swing * R2, (2 * swing if swing < 2 * phi0 else 4 * phi0) * R1
        if zone == "shaft":
            return (2 * swing if swing < 2 * phi0 else 4 * phi0) * R2, 2 * swing * R1
        raise InputError(f"the loaded zone is fixed on the 'bushing' or the 'shaft', got {zone!r}")

    def _cycles(self, paths: tuple[float, float]) -> float:
        return self.allowable_wear / (self.bushing_intensity * paths[0] + self.shaft_intensity * paths[1])

    def revolutions(self, zone: str) -> float:
        """N = [I] / (J_h1 S₁ + J_h2 S₂) [Egorov, 7.35]: revolutions until the allowable wear."""
        return self._cycles(self.revolution_paths(zone))

    def life(self, zone: str, speed: float) -> float:
        """L = N / n [Egorov, 7.29], s, turning at ``speed`` rad/s."""
        _positive(speed=speed)
        return self.revolutions(zone) / (speed / (2 * math.pi))

    def swing_cycles(self, zone: str, swing: float) -> float:
        """Swing cycles until the allowable wear [Egorov, 7.36 with 7.37/7.38] at the swing amplitude β (rad)."""
        return self._cycles(self.swing_paths(zone, swing))

    def swing_life(self, zone: str, swing: float, frequency: float) -> float:
        """L = cycles / ν [Egorov, 7.36], s, at ν swings per second."""
        _positive(frequency=frequency)
        return self.swing_cycles(zone, swing) / frequency


def single_element_life(allowable_wear: float, intensity: float, sliding_speed: float,
                        contact_half_angle: float | None = None) -> float:
    """L (s) of one wearing element at the sliding speed v = ωR (m/s): L = [I] / (J_h v) when the element carries
    the loaded zone (it slides all the time, 7.33), L = (π/φ₀)·[I] / (J_h v) when the zone moves over it (it slides
    2φ₀ of every 2π, 7.34; give φ₀). The book's 10⁻⁶ converts [I] in µm to m; the result is in seconds."""
    _positive(allowable_wear=allowable_wear, intensity=intensity, sliding_speed=sliding_speed)
    life = allowable_wear / (intensity * sliding_speed)
    if contact_half_angle is None:
        return life
    _positive(contact_half_angle=contact_half_angle)
    return math.pi / contact_half_angle * life

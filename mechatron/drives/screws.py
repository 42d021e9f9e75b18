r"""The checks of ball screws and racks over a task, for every linear drive of a joint at once.

A prismatic joint with force F(t) (N) and speed v(t) (m/s) driven through a screw of lead p (m per turn; ratio
u = 2π/p) turns it at n = u v (rad/s). The checks, each a value against a limit (margin = 1 − value/limit), apply
where the catalog row gives the data they need (:mod:`mechatron.drives.catalogs`, kind ``linear``):

=====================  ===============================================  ==============================================
check                  value                                            limit
=====================  ===============================================  ==============================================
screw equivalent load  F_m = (Σ |v| |F|³ Δt / Σ |v| Δt)^(1/3)           C (10⁶ / L_req)^(1/3), C the dynamic load
                                                                        rating (``dynamic_load``)
screw critical speed   max |n|                                          0.8 ω_cr (``root_diameter``, ``end_fixing``)
screw buckling         max |F|                                          F_E / 2 (``root_diameter``, ``end_fixing``)
rack tooth force       max |F|                                          the permitted tangential force
                                                                        (``permitted_force``)
screw length           the length used, L = stroke + 0.2 m              ``max_length``
=====================  ===============================================  ==============================================

- **Life** [ISO 3408-5]: the equivalent axial load is the cubic mean of the force weighted by the revolutions
  (dN = |n| dt / 2π, so by |v| dt), and the nominal life is L10 = (C / F_m)³ · 10⁶ revolutions. Run over and over,
  the task turns the screw N = ∫|v| dt / p times per cycle of duration T, so a required life of ``life`` seconds is
  L_req = life · N / T revolutions; L10 ≥ L_req exactly when F_m ≤ C (10⁶ / L_req)^(1/3), the check's limit (in
  load, like the gearboxes' equivalent torque). The load factor f_w of the operating conditions is 1 (smooth
  running): multiply F by it in a task's loads for shocks.
- **Critical speed** and **buckling** of the screw shaft of root diameter d_r over its free length L, the distance
  between its bearings, taken as the length used (stroke + 0.2 m, as for its inertia and mass), with the end fixing
  of its bearings (:mod:`mechatron.drives.shafts`): ω_cr = λ² d_r √(E/ρ)/(4 L²), F_E = π² E (π d_r⁴/64)/(K L)²;
  the makers allow 80 % of the critical speed and half the Euler load ([Vendor sizing]). The force's direction
  (compression or tension of the shaft) depends on which bearing takes the thrust, so |F| is checked.
- **Rack tooth force**: the tangential force at the pinion's pitch circle is the joint force, against the
  permitted force of the rack and pinion (the makers' value for the module and face width, its safety included).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .shafts import critical_speed, euler_load

if TYPE_CHECKING:  # pragma: no cover
    from .converters import Converters
    from .duty import JointDuty

SCREW_CHECKS = ("screw equivalent load", "screw critical speed", "screw buckling", "rack tooth force",
                "screw length")
SCREW_UNITS = ("N", "rad/s", "N", "N", "m")
#: The fraction of the critical speed a screw may turn at.
CRITICAL_SPEED_FACTOR = 0.8
#: Euler load / allowed axial force of a screw shaft.
SCREW_BUCKLING_SAFETY = 2.0
#: The default required nominal life of a screw, running the task over and over (s): 20 000 h.
SCREW_LIFE = 20000 * 3600.0


def equivalent_load(duty: JointDuty) -> float:
    """F_m = (Σ |v| |F|³ Δt / Σ |v| Δt)^(1/3) (N): the cubic mean of the axial force weighted by the revolutions
    [ISO 3408-5] (the time mean of |F|³ when the joint does not move)."""
    weights = duty.time_weights()
    motion = np.abs(duty.speed) * weights
    if motion.sum() == 0:
        motion = weights
    return float((motion @ np.abs(duty.torque) ** 3 / motion.sum()) ** (1 / 3))


def revolutions_per_second(duty: JointDuty, lead: float | NDArray[np.float64]) -> NDArray[np.float64]:
    """The screw's mean revolutions per second over the task, ⟨|v|⟩ / p (rev/s), for a lead p (m)."""
    mean_speed = float(np.abs(duty.speed) @ duty.time_weights())
    return mean_speed / np.asarray(lead, dtype=float)


def l10_revolutions(dynamic_load: float | NDArray[np.float64], load: float | NDArray[np.float64]
                    ) -> NDArray[np.float64]:
    """L10 = (C / F_m)³ · 10⁶ revolutions [ISO 3408-5] for the dynamic load rating C and equivalent load F_m (N);
    inf without load."""
    C, F = np.asarray(dynamic_load, dtype=float), np.asarray(load, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(F > 0, (C / np.where(F > 0, F, 1.0)) ** 3 * 1e6, math.inf)


def screw_life(duty: JointDuty, lead: float, dynamic_load: float) -> dict:
    """The nominal life of a screw of lead p (m) and dynamic load rating C (N) running ``duty`` over and over:
    equivalent_load F_m (N), l10_revolutions, revolutions_per_cycle and l10_hours (h)."""
    load = equivalent_load(duty)
    revolutions = float(l10_revolutions(dynamic_load, load))
    rate = float(revolutions_per_second(duty, lead))
    return {"equivalent_load": load, "l10_revolutions": revolutions,
            "revolutions_per_cycle": rate * duty.duration,
            "l10_hours": revolutions / rate / 3600 if rate > 0 else math.inf}


def screw_checks(duty: JointDuty, conv: Converters, life: float = SCREW_LIFE
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(values, limits), each (len(conv), len(SCREW_CHECKS)), of the screw and rack checks of every converter
    (the module docstring); a check whose data the converter lacks has the limit inf (it does not apply).
    ``life`` is the required nominal life (s) of a screw running the task over and over."""
    count = len(conv)
    values, limits = np.zeros((count, len(SCREW_CHECKS))), np.full((count, len(SCREW_CHECKS)), math.inf)
    if not any(np.isfinite(x).any() for x in (conv.dynamic_load, conv.root_diameter, conv.permitted_force,
                                              conv.max_length)):
        return values, limits  # no screw or rack among the converters (gearboxes): no check applies
    force = float(np.abs(duty.torque).max())
    top_speed = np.abs(duty.speed).max() * conv.ratio
    # life: L10 ≥ L_req ⟺ F_m ≤ C (10⁶ / L_req)^(1/3)
    required = life * revolutions_per_second(duty, 2 * math.pi / conv.ratio)
    rated = np.isfinite(conv.dynamic_load)
    values[:, 0] = equivalent_load(duty)
    with np.errstate(divide="ignore"):
        allowed = conv.dynamic_load * np.cbrt(1e6 / np.where(required > 0, required, 1.0))
    limits[:, 0] = np.where(rated & (required > 0), allowed, math.inf)
    shaft = np.isfinite(conv.root_diameter)
    root = np.where(shaft, conv.root_diameter, 1.0)
    length = np.where(shaft, conv.length, 1.0)
    values[:, 1] = top_speed
    limits[:, 1] = np.where(shaft, CRITICAL_SPEED_FACTOR * critical_speed(root, length, conv.whirl_factor), math.inf)
    values[:, 2] = force
    limits[:, 2] = np.where(shaft, euler_load(root, length, conv.buckling_factor) / SCREW_BUCKLING_SAFETY,
                            math.inf)
    values[:, 3], limits[:, 3] = force, conv.permitted_force
    values[:, 4], limits[:, 4] = np.nan_to_num(conv.length), conv.max_length
    return values, limits

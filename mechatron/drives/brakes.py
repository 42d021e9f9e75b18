r"""Holding brakes: which joints need one, and the checks of a motor's brake on such a joint.

A motor catalog may give a brake with each motor (optional columns, SI: ``brake_holding_torque`` T_h (N·m),
``brake_inertia`` J_b (kg·m²), ``brake_mass`` m_b (kg), ``brake_stop_energy`` E_stop (J, permitted per emergency
stop), ``brake_energy_per_h`` E_h (J, permitted per hour)). The checks apply only where the motor catalog has the
``brake_holding_torque`` column; without it the sizing is that of a catalog without brakes.

**Which joints need a brake.** A joint holds a load at rest where its static torque τ_s (gravity and the external
loads, :attr:`~mechatron.drives.duty.JointDuty.static_torque`) at the task's rest poses — its first and last sample
and every sample of a dwell — is not zero: τ_hold = max |τ_s| over those samples, counted where it exceeds
:data:`HOLD_TOLERANCE` × max |τ| over the task (rounding; a joint whose axis is vertical has τ_s ~ 1e-15). A joint
with τ_hold = 0 needs no brake, and its motors are sized as without brakes.

**The brake is an option of the motor.** On a joint that needs one, the brake's inertia and mass are added to the
motor's (J_m + J_b, m + m_b) wherever those count: every check (the acceleration torque (J_m + J_b + J_c) u ω̇,
the inertia ratio (J_L/u² + J_c)/(J_m + J_b), the thermal and the electrical ones), the objective, the ``time``
objective's pace (the joint's and the whole task's), the mass loading the mechanism.

**Checks** (u the ratio, η the converter's efficiency, J_c its motor-side inertia, J_L the largest load inertia, the
diagonal of the mass matrix at the worst pose, ω_max the task's largest joint speed):

- brake holding torque: f · T_g ≤ T_h, T_g = τ_hold / (u η) the gravity torque at the motor side (the converter's
  efficiency divides, as for a load that takes power: the conservative side; a back-driven gearbox holds part of
  the load by its own friction, which is not counted), f the brake factor (``--brake-factor``, default
  :data:`BRAKE_FACTOR` = 2, our default, no standard's or vendor's number: it leaves room for the holding torque
  lost to wear, heat and contamination and for a load heavier than planned).
  A motor without a brake (T_h missing) has the limit :data:`NO_BRAKE` (~0): it cannot drive such a joint, and
  this check is its one failure (the energy checks below do not apply to it: there is no brake to take the energy).
  That failure is a yes or no, not a degree: the closest pairs of a joint that such motors leave infeasible are
  ranked as if each had a brake that holds (:func:`assumed`; ours): first those that would then pass every check,
  by the objective, then the others by their worst load factor; the report says which motors have no brake.
- brake stop energy: an emergency stop from ω_max with the brake's torque (taken as T_h: the dynamic torque is
  about the holding one) against the kinetic energy at the motor side and gravity going on pulling. The kinetic
  energy E_k = ½ J_tot ω_m², J_tot = J_m + J_b + J_c + J_L/u², ω_m = u ω_max; over the braking angle θ_m (motor
  side) the brake's work T_h θ_m takes E_k and the potential energy released T_g θ_m, so
  θ_m = E_k / (T_h − T_g) and the energy the brake dissipates is

      E = T_h θ_m = E_k · T_h / (T_h − T_g)   (J; infinite where T_h ≤ T_g: the brake cannot stop the axis),

  against E_stop (checked where the catalog gives it).
- brake energy per hour: N · E against E_h, N the emergency stops per hour (``--brake-stops-per-h``, default
  :data:`STOPS_PER_HOUR`: one, our default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, TypeVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from .duty import JointDuty

if TYPE_CHECKING:  # pragma: no cover
    from .converters import Converters

#: The motor catalog's brake columns (SI field names).
BRAKE_COLUMNS = ("brake_holding_torque", "brake_inertia", "brake_mass", "brake_stop_energy", "brake_energy_per_h")
#: The brake checks, their units.
BRAKE_CHECKS = ("brake holding torque", "brake stop energy", "brake energy per hour")
BRAKE_UNITS = ("N·m", "J", "J")
#: The default brake factor f: static holding torque ≥ f × the gravity torque at the motor side (our default).
BRAKE_FACTOR = 2.0
#: The default emergency stops per hour of the energy-per-hour check (our default).
STOPS_PER_HOUR = 1.0
#: The holding torque (N·m) of a motor without a brake: a brake of no torque, finite so that every load factor is a
#: number; a load factor above :data:`NO_BRAKE_FACTOR` says "no brake" (the closest pairs are ranked without it).
NO_BRAKE = 1e-9
NO_BRAKE_FACTOR = 1e6
#: A static torque at rest below this fraction of the joint's largest |τ| is rounding: no load held.
HOLD_TOLERANCE = 1e-6


def rest_samples(duty: JointDuty) -> NDArray[np.intp]:
    """The samples where the task is at rest: the first, the last and both ends of every dwell interval
    (:attr:`~mechatron.drives.duty.JointDuty.moving` false)."""
    n = len(duty.t)
    rest = {0, n - 1}
    if duty.moving is not None:
        dwell = np.flatnonzero(~np.asarray(duty.moving, dtype=bool))
        rest.update(dwell.tolist())
        rest.update((dwell + 1).tolist())
    return np.array(sorted(k for k in rest if 0 <= k < n), dtype=np.intp)


def holding_torque(duty: JointDuty) -> float:
    """τ_hold = max |τ_s| at the rest poses (N·m or N), 0 where it is below :data:`HOLD_TOLERANCE` × max |τ|
    (the joint needs no brake)."""
    held = float(np.abs(duty.static_torque[rest_samples(duty)]).max(initial=0.0))
    scale = float(np.abs(duty.torque).max(initial=0.0))
    return held if held > HOLD_TOLERANCE * max(scale, held) and held > 1e-12 else 0.0


@dataclass(frozen=True)
class BrakeData:
    """The brake columns of a motor catalog as arrays (SI; NaN where a motor lacks the value; T_h NaN: no brake),
    and ``hold``, the static torque τ_hold of the joint being sized (0: none needed, the checks do not apply).
    ``assumed``: a motor without a brake is checked as if it had one that holds (its holding torque unchecked) —
    how the closest pairs of a joint that no braked motor can drive are ranked (:func:`assumed`)."""

    holding: NDArray[np.float64]
    inertia: NDArray[np.float64]
    mass: NDArray[np.float64]
    stop_energy: NDArray[np.float64]
    energy_per_h: NDArray[np.float64]
    hold: float = 0.0
    assumed: bool = False

    @classmethod
    def of(cls, motors: pd.DataFrame) -> BrakeData | None:
        """The brake data of a motor catalog, ``None`` where it has no ``brake_holding_torque`` column."""
        if "brake_holding_torque" not in motors:
            return None
        holding, inertia, mass, stop_energy, energy_per_h = (
            motors[name].to_numpy(dtype=float) if name in motors else np.full(len(motors), math.nan)
            for name in BRAKE_COLUMNS)
        return cls(holding, inertia, mass, stop_energy, energy_per_h)

    def missing(self, m: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether each motor of ``m`` lacks the brake this joint needs (τ_hold > 0 and T_h NaN): its holding-torque
        check fails whatever its size, a yes-or-no failure (:data:`NO_BRAKE`), not a degree of one."""
        return np.isnan(self.holding[m]) if self.hold > 0 else np.zeros(len(m), dtype=bool)

    @property
    def braked(self) -> int:
        """How many motors of the catalog have a brake (T_h given)."""
        return int(np.count_nonzero(~np.isnan(self.holding)))


class BrakedMotors(Protocol):
    """What :func:`with_brakes` reads of a motor catalog's arrays (a dataclass,
    :class:`~mechatron.drives.checks.MotorArrays`): the rotor inertia J_m (kg·m²), the mass (kg) and the brakes'."""

    __dataclass_fields__: ClassVar[dict[str, Any]]

    @property
    def rotor(self) -> NDArray[np.float64]: ...

    @property
    def mass(self) -> NDArray[np.float64]: ...

    @property
    def brakes(self) -> BrakeData | None: ...


Motors = TypeVar("Motors", bound=BrakedMotors)


def with_brakes(motors: Motors, duty: JointDuty) -> Motors:
    """``motors`` for the joint of ``duty``: unchanged where the catalog has no brakes or the joint holds no load;
    else each motor with its brake's inertia and mass added (J_m + J_b, m + m_b) and the joint's τ_hold kept, so that
    the brake checks apply (:func:`brake_table`). Once: arrays that carry a τ_hold already are returned as they are
    (the brake is not added twice)."""
    brakes = motors.brakes
    if brakes is None or brakes.hold > 0:  # no brakes, or added already
        return motors
    hold = holding_torque(duty)
    if hold == 0:
        return motors
    return replace(motors, rotor=motors.rotor + np.nan_to_num(brakes.inertia), mass=motors.mass +
                   np.nan_to_num(brakes.mass), brakes=replace(brakes, hold=hold))


def assumed(motors: Motors) -> Motors | None:
    """``motors`` (arrays of :func:`with_brakes`) with every motor that lacks the brake its joint needs checked as
    if it had one that holds (:attr:`BrakeData.assumed`): the brake check met, the other checks as they are; ``None``
    where no motor lacks one (or the joint needs none)."""
    brakes = motors.brakes
    if brakes is None or brakes.hold == 0 or brakes.braked == len(brakes.holding):
        return None
    return replace(motors, brakes=replace(brakes, assumed=True))


def brake_table(duty: JointDuty, brakes: BrakeData | None, rotor: NDArray[np.float64], conv: Converters,
                m: NDArray[np.intp], c: NDArray[np.intp], factor: float = BRAKE_FACTOR,
                stops_per_hour: float = STOPS_PER_HOUR) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(values, limits), each (len(m), 3), of the brake checks (:data:`BRAKE_CHECKS`, the module docstring) of the
    pairs (m[i], c[i]); ``rotor``: J_m + J_b of every motor. Where they do not apply (no brake data, no load held)
    the values are 0 and the limits inf; the holding torque of a motor without a brake has the limit
    :data:`NO_BRAKE`, or inf where :attr:`BrakeData.assumed`."""
    values, limits = np.zeros((len(m), 3)), np.full((len(m), 3), math.inf)
    if brakes is None or brakes.hold == 0:
        return values, limits
    u, eta, jc = np.abs(conv.ratio[c]), conv.efficiency[c], conv.inertia[c]
    gravity = brakes.hold / (u * eta)  # T_g at the motor side
    held = brakes.holding[m]
    t_h = np.nan_to_num(held, nan=NO_BRAKE)
    braked = ~np.isnan(held)  # a motor without a brake fails the holding torque alone
    top = float(np.abs(duty.speed).max(initial=0.0))
    kinetic = 0.5 * ((rotor[m] + jc) * u**2 + duty.load_inertia) * top**2
    with np.errstate(divide="ignore", invalid="ignore"):
        energy = np.where(t_h > gravity, kinetic * t_h / (t_h - gravity), math.inf)
    energy = np.where(kinetic == 0, 0.0, energy)
    values[:, 0], limits[:, 0] = factor * gravity, np.where(braked | (not brakes.assumed), t_h, math.inf)
    for k, (permitted, stops) in enumerate(((brakes.stop_energy, 1.0), (brakes.energy_per_h, stops_per_hour)), 1):
        limits[:, k] = np.where(braked, np.nan_to_num(permitted[m], nan=math.inf), math.inf)
        values[:, k] = np.where(np.isfinite(limits[:, k]), stops * energy, 0.0)  # unchecked: 0, as documented
    return values, limits

r"""The drive side of a joint: motor torque and speed through a transmission of ratio u = ω_m/q̇ [Egorov, 4.58] and
efficiency η.

The rotor and gear inertia is in the dynamics already, reflected into the joint as Pinocchio's ``armature``
J_rotor·u² (:mod:`mechatron.model.dh`); efficiency and friction act outside Pinocchio, on the motor side, and depend
on the direction of the power flow:

- motoring (the joint takes power, τ_load·q̇ ≥ 0): τ_m = τ_load / (u·η) [Egorov, 4.59–4.62],
- back-driven (the load returns power): τ_m = τ_load·η / u,

plus the rotor's own inertia torque J_rotor·u·q̈ and the motor-side friction B·ω_m + T_c(sign ω_m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism

Array = NDArray[np.float64]


@dataclass(frozen=True)
class MotorLoads:
    """Motor-side loads of every joint (arrays (N, nv), or (nv,) for one state); joints without drive data are
    direct drives (u = 1, η = 1).

    Attributes:
        torque: Motor torque τ_m (N·m), rotor inertia, transmission losses and friction included.
        speed: Motor speed ω_m = u·q̇ (rad/s).
        joint_torque: τ from the dynamics (rotor inertia included).
        load_torque: τ − J_rotor u² q̈, what the transmission delivers to the joint.
        motoring: Whether power flows from the motor to the load (τ_load·q̇ ≥ 0).
    """

    torque: Array
    speed: Array
    joint_torque: Array
    load_torque: Array
    motoring: NDArray[np.bool_]

    @property
    def power(self) -> Array:
        """Motor shaft power τ_m·ω_m (W)."""
        return self.torque * self.speed


def transmitted_torque(load: ArrayLike, speed: ArrayLike, ratio: ArrayLike, efficiency: ArrayLike) -> Array:
    """The motor-side torque (N·m) that carries the joint load τ (N·m or N) through a transmission of ratio u
    (1, or rad/m for a rotary-to-linear drive) and efficiency η: τ/(u η) when the load takes power (τ q̇ ≥ 0, the
    speed q̇ in rad/s or m/s) [Egorov, 4.59], τ η/u when it drives the motor back. Arrays broadcast."""
    load, speed = np.asarray(load, dtype=float), np.asarray(speed, dtype=float)
    motoring = load * speed >= 0
    return np.where(motoring, load / (ratio * efficiency), load * efficiency / ratio)


def motor_loads(mech: Mechanism, v: ArrayLike, a: ArrayLike, tau: ArrayLike) -> MotorLoads:
    """Motor torques (N·m) and speeds (rad/s) for joint velocities v (rad/s, m/s), accelerations a (rad/s², m/s²)
    and joint torques τ (N·m, N; from the dynamics), (nv,) or (N, nv).

    τ_m = J_rotor·u·q̈ + τ_load/(u·η) when motoring, J_rotor·u·q̈ + τ_load·η/u when back-driven, + B·ω_m + T_c,
    with τ_load = τ − J_rotor·u²·q̈ (the reflected rotor inertia is counted once: in τ through the armature, and
    taken back out of what the transmission carries).
    """
    single = np.ndim(v) == 1
    V = np.atleast_2d(np.asarray(v, dtype=float))
    A = np.atleast_2d(np.asarray(a, dtype=float))
    T = np.atleast_2d(np.asarray(tau, dtype=float))
    if not (V.shape == A.shape == T.shape) or V.shape[1] != mech.nv:
        raise InputError(f"v, a and tau must have the same shape (N, {mech.nv})")
    ratio, efficiency, rotor = np.ones(mech.nv), np.ones(mech.nv), np.zeros(mech.nv)
    viscous, coulomb_pos, coulomb_neg = np.zeros(mech.nv), np.zeros(mech.nv), np.zeros(mech.nv)
    for name, drive in mech.drives.items():
        i = mech.model.joints[mech.joint_id(name)].idx_v
        ratio[i], efficiency[i], rotor[i] = drive.gear_ratio, drive.efficiency, drive.rotor_inertia
        viscous[i] = drive.viscous_friction
        coulomb_pos[i], coulomb_neg[i] = drive.coulomb_friction
    load = T - rotor * ratio**2 * A
    motoring = load * V >= 0
    transmitted = transmitted_torque(load, V, ratio, efficiency)
    speed = ratio * V
    friction = viscous * speed + np.where(speed > 0, coulomb_pos, np.where(speed < 0, coulomb_neg, 0.0))
    torque = rotor * ratio * A + transmitted + friction
    if single:
        return MotorLoads(torque[0], speed[0], T[0], load[0], motoring[0])
    return MotorLoads(torque, speed, T, load, motoring)

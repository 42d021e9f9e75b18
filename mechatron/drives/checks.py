r"""The checks vendor sizing tools run, for every motor × converter pair of a joint at once.

A converter of ratio u, efficiency η and motor-side inertia J_c (gearbox input, screw) between a motor of rotor
inertia J_m and a joint with the duty ω(t), ω̇(t), τ(t) (see :mod:`mechatron.drives.duty`) gives the motor

    n = u ω,    T_m = (J_m + J_c) u ω̇ + τ* / u,    τ* = τ/η if τ ω ≥ 0 (the load takes power), else τ η,

so the rotor and gearbox inertia are counted exactly once (the duty has none). The checks, each a value against a
limit (margin = 1 − value/limit):

====================================  ==============================================================  ==========
check                                 value                                                           limit
====================================  ==============================================================  ==========
peak torque                           max |T_m|                                                       T_peak
speed-torque curve                    max |T_m| / T_int(|n|), the intermittent curve of               1
                                      :func:`~mechatron.drives.motor.peak_torque_limit`
RMS torque (thermal)                  √⟨T_m²⟩                                                         T_S1(⟨|n|⟩)
max speed                             max |n|                                                         n_max
inertia ratio                         (J_L/u² + J_c) / J_m, J_L the largest load inertia              10 (option)
transmission equivalent torque        (Σ |ω| |τ|³ Δt / Σ |ω| Δt)^(1/3)                                T2N
transmission peak torque              max |τ|                                                         T2B
transmission emergency torque         T_peak u (the motor's peak torque through the gear)             T2Stop
transmission max input speed          max |n|                                                         n1max
transmission mean input speed         ⟨|n|⟩                                                           n1N
====================================  ==============================================================  ==========

⟨·⟩ is the time mean over the task (trapezoidal rule). The S1 torque at the mean speed follows the drive makers'
configuration manuals; the speed-weighted cubic mean is the gearbox makers' equivalent output torque; the emergency
check is M_max,gear ≥ M_0 i with the peak torque for M_0 ([Vendor sizing]), or the torque the drive is limited to in
an emergency stop (:class:`DriveLimits`: a torque, or a current times the torque constant k_t; never above T_peak).

Beyond these (:data:`ALL_CHECKS`), where the catalogs give the data:

- **voltage limit** (V) of a motor with torque constant k_t (N·m/A), winding resistance R (Ω) and supply voltage U
  (V) (:mod:`mechatron.drives.motor`): max (k_t |n| + R |T_m| / k_t) ≤ U, the back-EMF k_e ω plus the resistive
  drop R I of the current I = T_m / k_t (k_e = k_t in SI units), at every sample — the voltage-limit line of the
  speed–torque curve, applied to |T_m| in all four quadrants as the makers' curves are (conservative when braking);
- the screw and rack checks of :mod:`mechatron.drives.screws` (equivalent load and L10 life, critical speed,
  buckling, rack tooth force, length).

A check whose data a motor or converter lacks has the limit inf and is not reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .converters import Converters
from .duty import JointDuty
from .motor import continuous_torque, electrical_data, peak_torque_limit
from .screws import SCREW_CHECKS, SCREW_LIFE, SCREW_UNITS, screw_checks

#: The checks of a motor and a gearbox (each applies to a motor with a gearbox).
CHECKS = ("peak torque", "speed-torque curve", "RMS torque", "max speed", "inertia ratio",
          "transmission equivalent torque", "transmission peak torque", "transmission emergency torque",
          "transmission max input speed", "transmission mean input speed")
UNITS = ("N·m", "-", "N·m", "rad/s", "-", "N·m", "N·m", "N·m", "rad/s", "rad/s")
#: Every check of a motor × converter pair: :data:`CHECKS`, the voltage limit, the screw and rack checks.
ALL_CHECKS = CHECKS + ("voltage limit",) + SCREW_CHECKS
ALL_UNITS = UNITS + ("V",) + SCREW_UNITS
_VOLTAGE = len(CHECKS)
#: The checks evaluated sample by sample (lower bounds until refined).
PER_SAMPLE = (0, 1, _VOLTAGE)
#: Relative tolerance of a pass: value ≤ limit (1 + PASS_TOLERANCE).
PASS_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Check:
    """One check of one drive: value and limit in ``unit``; margin = 1 − value/limit."""

    name: str
    value: float
    limit: float
    unit: str

    @property
    def margin(self) -> float:
        return 1.0 - _load_factor(self.value, self.limit)

    @property
    def passed(self) -> bool:
        return _load_factor(self.value, self.limit) <= 1 + PASS_TOLERANCE

    def as_dict(self) -> dict:
        return {"name": self.name, "value": float(self.value), "limit": float(self.limit), "unit": self.unit,
                "margin": float(self.margin), "pass": bool(self.passed)}


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
    """

    stop_torque: float | None = None
    stop_current: float | None = None
    screw_life: float = SCREW_LIFE
    voltage: float | None = None

    def __post_init__(self) -> None:
        for name in ("stop_torque", "stop_current", "voltage"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"{name} must be a finite number > 0, got {value!r}")
        if self.stop_torque is not None and self.stop_current is not None:
            raise InputError("give the emergency-stop limit as a torque or as a current, not both")
        if not (math.isfinite(self.screw_life) and self.screw_life > 0):
            raise InputError(f"screw_life must be a finite number of seconds > 0, got {self.screw_life!r}")

    def stop_torques(self, motors: pd.DataFrame) -> NDArray[np.float64]:
        """The torque (N·m) each motor gives in an emergency stop: min(limit, T_peak), T_peak without a limit."""
        peak = motors["peak_torque"].to_numpy(dtype=float)
        if self.stop_torque is not None:
            return np.minimum(peak, self.stop_torque)
        if self.stop_current is not None and "torque_constant" in motors:
            kt = motors["torque_constant"].to_numpy(dtype=float)
            return np.where(np.isfinite(kt), np.minimum(peak, kt * self.stop_current), peak)
        return peak


def _load_factor(value: ArrayLike, limit: ArrayLike) -> NDArray[np.float64] | float:
    """value / limit with 0/0 = 0, x/0 = inf and x/inf = 0."""
    value, limit = np.asarray(value, dtype=float), np.asarray(limit, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(value <= 0, 0.0, np.where(limit > 0, value / limit, np.inf))
    return out if out.ndim else float(out)


def motor_side(duty: JointDuty, u: ArrayLike, eta: ArrayLike, inertia: ArrayLike,
               samples: slice | NDArray[np.intp] | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(n, a, b): motor speed n = u ω (rad/s), motor acceleration a = u ω̇ (rad/s²) and the motor torque without the
    rotor, b = J_c u ω̇ + τ*/u (N·m), for the ratio u (rad/rad or rad/m), efficiency η and motor-side converter
    inertia J_c (kg·m²); ``u``, ``eta``, ``inertia`` broadcast against the samples (give them as columns); only at
    ``samples`` (a slice or indices) when given. The motor torque is then T_m = J_m a + b (the module docstring)."""
    from .transmission import transmitted_torque

    every = slice(None) if samples is None else samples
    torque, speed, acceleration = duty.torque[every], duty.speed[every], duty.acceleration[every]
    load = transmitted_torque(torque, speed, u, eta)
    accel = u * acceleration
    return u * speed, accel, inertia * accel + load


#: Elements of the largest (converters × samples) array of an evaluation (8 bytes each): the per-sample work goes
#: a block of samples (or of pairs) at a time, so that its memory does not grow with the length of the task.
SAMPLE_BLOCK = 1 << 22


def _blocks(samples: int, converters: int) -> list[slice]:
    """Slices of the samples, each at most :data:`SAMPLE_BLOCK` / ``converters`` long (one slice for short tasks)."""
    size = max(1, SAMPLE_BLOCK // max(1, converters))
    return [slice(start, min(start + size, samples)) for start in range(0, max(samples, 1), size)]


class Evaluation:
    """The checks of every motor × converter pair of one joint: ``values`` and ``limits`` (N_m, N_c,
    len(ALL_CHECKS)).

    The per-sample checks (peak torque, speed–torque curve, voltage limit) cost a pass over the samples per pair;
    they start as lower bounds from a few decisive samples (:meth:`JointDuty.strong_samples`) and are made exact
    for the pairs given to :meth:`refine` (``exact`` marks them) over the samples that can decide them
    (:meth:`JointDuty.envelope`: the voltage k_t |n| + R |T_m| / k_t grows with |n| and |T_m| like the load on the
    speed–torque curve). Every other check is exact from the start (time means over the samples per converter,
    combined per motor). A lower bound never passes a pair that fails. The work goes a block of samples (of pairs in
    :meth:`refine`) at a time, so that its memory stays within :data:`SAMPLE_BLOCK` elements per array however long
    the task.
    """

    def __init__(self, duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float = 10.0,
                 limits: DriveLimits | None = None):
        limits = limits or DriveLimits()
        weights = duty.time_weights()
        u, eta, Jc = conv.ratio[:, None], conv.efficiency[:, None], conv.inertia[:, None]
        self._u, self._eta, self._Jc = u, eta, Jc
        self.rotor = motors["rotor_inertia"].to_numpy()
        self.rated, self.peak = motors["rated_torque"].to_numpy(), motors["peak_torque"].to_numpy()
        self.rated_speed, self.top_speed = motors["rated_speed"].to_numpy(), motors["max_speed"].to_numpy()
        kt, resistance, voltage = electrical_data(motors, limits.voltage)
        checked = np.isfinite(voltage)  # motors with the voltage data
        # u = back_emf |n| + drop |T_m| (V): k_e = k_t, drop = R / k_t
        self.back_emf, self.drop = np.where(checked, kt, 0.0), np.where(checked, resistance / kt, 0.0)
        shape = (len(motors), len(conv))
        self.values, self.limits = np.empty(shape + (len(ALL_CHECKS),)), np.empty(shape + (len(ALL_CHECKS),))
        self.exact = np.zeros(shape, dtype=bool)
        values, lim, Jm = self.values, self.limits, self.rotor

        # thermal: ⟨T_m²⟩ = J_m² ⟨a²⟩ + 2 J_m ⟨a b⟩ + ⟨b²⟩; the time means a block of samples at a time (memory
        # bounded by SAMPLE_BLOCK, whatever the length of the task)
        m_aa, m_ab, m_bb, mean_speed, top_speed = (np.zeros(len(conv)) for _ in range(5))
        for block in _blocks(len(weights), len(conv)):
            n, accel, base = motor_side(duty, u, eta, Jc, block)  # (N_c, samples of the block)
            w = weights[block]
            m_aa += (accel**2) @ w
            m_ab += (accel * base) @ w
            m_bb += (base**2) @ w
            mean_speed += np.abs(n) @ w
            top_speed = np.maximum(top_speed, np.abs(n).max(axis=1))
            del n, accel, base
        values[..., 2] = np.sqrt(np.maximum(np.outer(Jm**2, m_aa) + 2 * np.outer(Jm, m_ab) + m_bb, 0.0))
        lim[..., 2] = continuous_torque(mean_speed[None, :], self.rated[:, None], self.rated_speed[:, None],
                                        self.top_speed[:, None])
        values[..., 3], lim[..., 3] = top_speed[None, :], self.top_speed[:, None]
        values[..., 4] = (duty.load_inertia / conv.ratio**2 + conv.inertia)[None, :] / Jm[:, None]
        lim[..., 4] = inertia_ratio_max
        # transmission (output side)
        motion = np.abs(duty.speed) * weights
        if motion.sum() == 0:
            motion = weights
        values[..., 5] = (motion @ np.abs(duty.torque) ** 3 / motion.sum()) ** (1 / 3)
        values[..., 6] = np.abs(duty.torque).max()
        values[..., 7] = np.outer(limits.stop_torques(motors), conv.ratio)
        values[..., 8], values[..., 9] = top_speed[None, :], mean_speed[None, :]
        for k, limit in zip(range(5, 10), (conv.rated_torque, conv.peak_torque, conv.emergency_torque,
                                           conv.max_input_speed, conv.rated_input_speed)):
            lim[..., k] = limit[None, :]
        lim[..., 0], lim[..., 1] = self.peak[:, None], 1.0
        lim[..., _VOLTAGE] = np.where(checked, voltage, math.inf)[:, None]
        screw_values, screw_limits = screw_checks(duty, conv, limits.screw_life)
        values[..., _VOLTAGE + 1:], lim[..., _VOLTAGE + 1:] = screw_values[None], screw_limits[None]

        # the per-sample checks: lower bounds now, exact on demand
        self._duty = duty
        strong = duty.strong_samples(2)
        rows, cols = np.indices(shape)
        bounds = self._per_sample(rows.ravel(), cols.ravel(), *motor_side(duty, u, eta, Jc, strong))
        for k, bound in zip(PER_SAMPLE, bounds):
            values[..., k] = bound.reshape(shape)
        self._keep = duty.envelope()

    def _per_sample(self, m: NDArray[np.intp], c: NDArray[np.intp], n: NDArray[np.float64],
                    accel: NDArray[np.float64], base: NDArray[np.float64]
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(max |T_m|, max |T_m| / T_intermittent(|n|), max k_t |n| + R |T_m| / k_t) of the pairs (m[i], c[i]) over
        the given samples (n, accel, base: (N_c, samples) of :func:`motor_side`)."""
        torque = np.abs(self.rotor[m, None] * accel[c] + base[c])
        available = peak_torque_limit(n[c], self.peak[m, None], self.rated[m, None], self.rated_speed[m, None],
                                      self.top_speed[m, None])
        if not self.back_emf.any():  # no motor with the voltage data
            return torque.max(axis=1), _load_factor(torque, available).max(axis=1), np.zeros(len(m))
        voltage = self.back_emf[m, None] * np.abs(n[c]) + self.drop[m, None] * torque
        return torque.max(axis=1), _load_factor(torque, available).max(axis=1), voltage.max(axis=1)

    def refine(self, m: ArrayLike, c: ArrayLike, batch: int = 512) -> None:
        """Make the per-sample checks exact for the pairs (m[i], c[i])."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        todo = ~self.exact[m, c]
        m, c = m[todo], c[todo]
        batch = max(1, min(batch, SAMPLE_BLOCK // max(1, len(self._keep))))  # (batch, samples) arrays stay bounded
        for start in range(0, len(m), batch):
            mb, cb = m[start:start + batch], c[start:start + batch]
            used = np.unique(cb)  # the converters of the batch, at the samples that can decide
            side = motor_side(self._duty, self._u[used], self._eta[used], self._Jc[used], self._keep)
            exact = self._per_sample(mb, np.searchsorted(used, cb), *side)
            for k, value in zip(PER_SAMPLE, exact):
                self.values[mb, cb, k] = value
            self.exact[mb, cb] = True

    def refine_all(self) -> Evaluation:
        m, c = np.nonzero(~self.exact)
        self.refine(m, c)
        return self

    def load_factors(self) -> NDArray[np.float64]:
        """value/limit of every check, (N_m, N_c, len(ALL_CHECKS)); > 1 fails."""
        return _load_factor(self.values, self.limits)

    def load_factors_of(self, m: ArrayLike, c: ArrayLike) -> NDArray[np.float64]:
        """value/limit of every check of the pairs (m, c): (..., len(ALL_CHECKS))."""
        return _load_factor(self.values[m, c], self.limits[m, c])

    def worst_of(self, m: ArrayLike, c: ArrayLike) -> NDArray[np.float64]:
        """The largest load factor of the pairs (m, c)."""
        return self.load_factors_of(m, c).max(axis=-1)

    def worst(self) -> NDArray[np.float64]:
        """The largest load factor of every pair, (N_m, N_c): exact where :attr:`exact`, else a lower bound."""
        return self.load_factors().max(axis=2)

    def checks(self, m: int, c: int) -> list[Check]:
        """The checks of one pair that apply (finite limit), made exact first."""
        self.refine([m], [c])
        return [Check(name, float(self.values[m, c, k]), float(self.limits[m, c, k]), ALL_UNITS[k])
                for k, name in enumerate(ALL_CHECKS) if math.isfinite(self.limits[m, c, k])]

    def failed(self, m: int, c: int) -> list[str]:
        """The checks the pair (m, c) fails, as ``name ×load factor``."""
        factors = self.load_factors_of(m, c)
        return [f"{name} ×{factors[k]:.2f}" for k, name in enumerate(ALL_CHECKS) if factors[k] > 1 + PASS_TOLERANCE]


def evaluate(duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float = 10.0,
             exact: bool = True, limits: DriveLimits | None = None) -> Evaluation:
    """Every check of every motor × converter pair (see the module docstring); with ``exact=False`` the
    per-sample checks are lower bounds until :meth:`Evaluation.refine` is called. ``limits``: the emergency-stop
    limit, required screw life and supply voltage (:class:`DriveLimits`)."""
    evaluation = Evaluation(duty, motors, conv, inertia_ratio_max, limits)
    return evaluation.refine_all() if exact else evaluation

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
transmission peak torque              max |τ|                                                         T2B / f_s
transmission emergency torque         T_peak u (the motor's peak torque through the gear)             T2Stop
transmission max input speed          max |n|                                                         n1max
transmission mean input speed         ⟨|n|⟩                                                           n1N
====================================  ==============================================================  ==========

⟨·⟩ is the time mean over the task (trapezoidal rule). The S1 torque at the mean speed follows the drive makers'
configuration manuals; the speed-weighted cubic mean is the gearbox makers' equivalent output torque; the emergency
check is M_max,gear ≥ M_0 i with the peak torque for M_0 ([Vendor sizing]), or the torque the drive is limited to in
an emergency stop (:class:`DriveLimits`: a torque, or a current times the torque constant k_t; never above T_peak).

**Gearbox duty.** The task repeats: it runs 1/T times a second (T its duration, dwells included), and each time
meets n_p load peaks, its accelerations and brakings counted one by one (:func:`peak_count`: the runs of samples
whose joint acceleration is beyond :data:`PEAK_FRACTION` of the task's largest |ω̇|, of one sign each — a move
that starts and stops meets two, in opposite directions; mechatron's own counting rule). The peak torque T2B is
checked by the rule the gearbox's maker gives (``peak_rule``, :data:`~mechatron.drives.converters.PEAK_RULES`):

- ``shock_factors``, the planetary gearhead makers' rule: T2B holds up to a cycle rate (commonly 1,000 cycles/h)
  and above it the peak torque asked for is multiplied by a shock factor f_s ≥ 1 read off the maker's table by
  cycles per hour [Vendor sizing]: the limit is T2B / f_s at the load peak rate N_p = n_p / T
  (:func:`peak_torque_factor`: the catalog's table interpolated linearly, its first factor below its first rate,
  no rating — a limit of 0, the check fails — above its last);
- ``repeated_peak``, the strain-wave makers' rule: T2B is the repeated peak torque, the limit of the torque of
  every start and stop, at any rate [Strain wave] (the count-limited momentary peak torque is T2Stop, below);
- ``cycle_rating``, no maker rule given: T2B holds up to the catalog's cycle rating N_r (``cycle_rating``, default
  1,000 cycles/h, :data:`~mechatron.drives.converters.CYCLE_RATING`); above it mechatron takes T2B unchanged and
  the report says that no maker rule covers that rate.

The emergency torque T2Stop (a strain-wave gear's momentary peak torque) is a count-limited load: the catalog
allows it ``emergency_stops`` times in the gearbox's life (default 1,000,
:data:`~mechatron.drives.converters.EMERGENCY_STOPS`); its check carries that count (:attr:`Check.count`) and the
report states it.

Beyond these (:data:`ALL_CHECKS`), where the catalogs give the data:

- **voltage limit** (V) of a motor with torque constant k_t (N·m/A), winding resistance R (Ω) and supply voltage U
  (V) (:mod:`mechatron.drives.motor`): max (k_t |n| + R |T_m| / k_t) ≤ U, the back-EMF k_e ω plus the resistive
  drop R I of the current I = T_m / k_t (k_e = k_t in SI units), at every sample — the voltage-limit line of the
  speed–torque curve, applied to |T_m| in all four quadrants as the makers' curves are (conservative when braking);
- **winding temperature rise** (K) of a motor with the thermal columns (:mod:`mechatron.drives.thermal`): the
  winding's highest rise above the ambient T_a over the task repeated to its periodic steady state, in the two-node
  network of winding and housing with the copper loss I² R(T) (I = T_m/k_t(T_m), k_t at the magnets'
  temperature, the housing's mean: the magnets heat too) and the speed losses, ≤ T_max − T_a
  (:attr:`DriveLimits.ambient`, default 40 °C). It replaces the RMS torque check, which such a motor does not
  take (its limit is inf); the screening bounds it from below by the mean rise (R_wh + R_ha)(R(T_a)
  ⟨T_m²⟩/k_t(T_a)² + T_f ⟨|n|⟩), and the network is simulated only for the pairs checked exactly
  (:meth:`PairChecks.winding`);
- the screw and rack checks of :mod:`mechatron.drives.screws` (equivalent load and L10 life, critical speed,
  buckling, rack tooth force, length).
- the holding brake's checks of :mod:`mechatron.drives.brakes` (holding torque, energy per emergency stop and per
  hour) on a joint that holds a load at rest, where the motor catalog has brakes.

A check whose data a motor or converter lacks has the limit inf and is not reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from .brakes import BRAKE_CHECKS, BRAKE_UNITS, NO_BRAKE_FACTOR, BrakeData, brake_table
from .converters import Converters
from .duty import JointDuty
from .limits import DriveLimits as DriveLimits  # re-exported: it lives below checks and options
from .motor import catalog_column, continuous_torque, electrical_data, peak_torque_limit
from .options import INERTIA_RATIO_MAX
from .screws import SCREW_CHECKS, SCREW_UNITS, screw_checks
from .screws import SCREW_LIFE as SCREW_LIFE  # re-exported: the default of DriveLimits.screw_life
from .servo import DRIVE_CHECKS, DRIVE_UNITS, DriveData, overload
from .thermal import BATCH_ELEMENTS, ThermalData, highest_rise

#: The checks of a motor and a gearbox (each applies to a motor with a gearbox).
CHECKS = ("peak torque", "speed-torque curve", "RMS torque", "max speed", "inertia ratio",
          "transmission equivalent torque", "transmission peak torque", "transmission emergency torque",
          "transmission max input speed", "transmission mean input speed")
UNITS = ("N·m", "-", "N·m", "rad/s", "-", "N·m", "N·m", "N·m", "rad/s", "rad/s")
#: Every check of a motor × converter pair: :data:`CHECKS`, the voltage limit, the screw and rack checks.
ALL_CHECKS = CHECKS + ("voltage limit", "winding temperature rise") + SCREW_CHECKS + BRAKE_CHECKS + DRIVE_CHECKS
ALL_UNITS = UNITS + ("V", "K") + SCREW_UNITS + BRAKE_UNITS + DRIVE_UNITS
_VOLTAGE = len(CHECKS)
_WINDING = _VOLTAGE + 1  # the thermal model's check (mechatron.drives.thermal)
_DRIVE = len(ALL_CHECKS) - len(DRIVE_CHECKS)  # the servo drive's checks (mechatron.drives.servo)
_DRIVE_RMS, _DRIVE_RUN = _DRIVE, _DRIVE + 1
_BRAKE = _DRIVE - len(BRAKE_CHECKS)  # the holding brake's checks (mechatron.drives.brakes)
#: Pairs of a joint checked sample by sample over every sample before the samples that can decide are sought
#: (:meth:`JointDuty.envelope`, worth its cost only for many pairs; :meth:`PairChecks.per_sample`).
BEFORE_ENVELOPE = 32
#: The checks evaluated sample by sample (lower bounds until refined).
PER_SAMPLE = (0, 1, _VOLTAGE)
#: Relative tolerance of a pass: value ≤ limit (1 + PASS_TOLERANCE).
PASS_TOLERANCE = 1e-9
#: A load peak of a gearbox (:func:`peak_count`) is a run of samples whose joint acceleration is beyond this
#: fraction of the task's largest |ω̇| (mechatron's own rule: an acceleration or a braking phase of a move).
PEAK_FRACTION = 0.5
_EMERGENCY = CHECKS.index("transmission emergency torque")
#: What an infinite load factor of a check means — a value where its limit is 0: no multiple of the limit is
#: enough — in the words of a reason (:func:`failure`); other checks say it with :data:`NO_LIMIT`.
BEYOND = {"speed-torque curve": "outside it (torque asked above the motor's maximum speed)",
          "winding temperature rise": "no rise allowed (the ambient is at or above the winding's limit temperature)",
          "RMS torque": "no continuous torque at the mean speed (above the motor's maximum speed)",
          "transmission peak torque": "no rating at this many load peaks per hour (above the last rate of the "
                                      "catalog's shock_factors)",
          "brake holding torque": "no brake (the motor catalog gives no brake_holding_torque for this motor) on a "
                                  "joint that holds a load at rest",
          "brake stop energy": "the brake cannot stop the axis (its holding torque is at or below the gravity torque)",
          "brake energy per hour": "the brake cannot stop the axis (its holding torque is at or below the gravity "
                                   "torque)"}
NO_LIMIT = "a limit of 0 where a value is needed"


@dataclass(frozen=True)
class Check:
    """One check of one drive: value and limit in ``unit``; margin = 1 − value/limit. ``count``: how many times
    the limit may be reached in the component's life (a gearbox's emergency torque), ``None`` for a limit without
    a count."""

    name: str
    value: float
    limit: float
    unit: str
    count: float | None = None

    @property
    def margin(self) -> float:
        return 1.0 - _factor(self.value, self.limit)

    @property
    def passed(self) -> bool:
        return _factor(self.value, self.limit) <= 1 + PASS_TOLERANCE

    def as_dict(self) -> dict:
        """name, value, limit, unit, margin, pass, and count where the limit has one."""
        out = {"name": self.name, "value": float(self.value), "limit": float(self.limit), "unit": self.unit,
               "margin": float(self.margin), "pass": bool(self.passed)}
        return out if self.count is None else {**out, "count": float(self.count)}


@dataclass(frozen=True)
class MotorArrays:
    """The columns of a motor catalog the checks read, as arrays (SI; :func:`read_catalog
    <mechatron.drives.catalogs.read_catalog>`), read once for a whole sizing: ``key``; rotor inertia J_m (kg·m²);
    rated and peak torque (N·m); rated and top speed (rad/s); torque constant k_t (N·m/A), winding resistance R (Ω)
    and supply voltage U (V), NaN where the catalog lacks them; mass (kg) and price, 0 where missing; the thermal
    model's data (:class:`~mechatron.drives.thermal.ThermalData`); the brakes' (:class:`~mechatron.drives.brakes.
    BrakeData`, ``None`` for a catalog without brakes)."""

    key: NDArray[np.str_]
    rotor: NDArray[np.float64]
    rated: NDArray[np.float64]
    peak: NDArray[np.float64]
    rated_speed: NDArray[np.float64]
    top_speed: NDArray[np.float64]
    kt: NDArray[np.float64]
    resistance: NDArray[np.float64]
    voltage: NDArray[np.float64]
    mass: NDArray[np.float64]
    price: NDArray[np.float64]
    thermal: ThermalData | None = None
    brakes: BrakeData | None = None
    drive: DriveData | None = None  # the servo drive paired with each motor (mechatron.drives.servo)

    @classmethod
    def of(cls, motors: pd.DataFrame | MotorArrays) -> MotorArrays:
        """The arrays of a motor catalog (a DataFrame), or ``motors`` if it is already one."""
        if isinstance(motors, MotorArrays):
            return motors

        kt, resistance, voltage = electrical_data(motors)
        return cls(motors["key"].to_numpy(dtype=str), *(motors[name].to_numpy(dtype=float) for name in (
            "rotor_inertia", "rated_torque", "peak_torque", "rated_speed", "max_speed")), kt, resistance, voltage,
            catalog_column(motors, "mass", 0.0), catalog_column(motors, "price", 0.0), ThermalData.of(motors),
            BrakeData.of(motors), DriveData.of(motors))

    def objective_mass(self) -> NDArray[np.float64]:
        """The mass (kg) the objective counts: the motor's and its paired servo drive's."""
        return self.mass if self.drive is None else self.mass + self.drive.mass

    def __len__(self) -> int:
        return len(self.key)


def peak_count(acceleration: ArrayLike) -> int:
    """The load peaks n_p a repeated task puts on a gearbox: the runs of samples with ω̇ ≥ f a or ω̇ ≤ −f a
    (a = max |ω̇| over the task, f = :data:`PEAK_FRACTION`), each run one peak — every acceleration and every braking,
    so a move that starts and stops meets two, one in each direction. A run of one sign goes on through a lone
    sample below f a between two of its own (the sample where two moves meet, braking the first and accelerating
    the second the same way: one pulse); two samples below end it. The task repeats, so a run through its last and
    first samples counts once; a task without acceleration meets none."""
    a = np.asarray(acceleration, dtype=float)
    top = float(np.abs(a).max(initial=0.0))
    if top == 0:
        return 0
    side = np.where(a >= PEAK_FRACTION * top, 1, np.where(a <= -PEAK_FRACTION * top, -1, 0))
    before, after = np.roll(side, 1), np.roll(side, -1)
    side = np.where((side == 0) & (before == after), before, side)  # a lone sample below: the run goes on
    starts = int(np.count_nonzero((side != 0) & (side != np.roll(side, 1))))
    return max(starts, 1)  # no start: one run over the whole task


def peak_torque_factor(rate: float, shock_rates: ArrayLike, shock_factors: ArrayLike) -> NDArray[np.float64]:
    """The factor 1/f_s of each gearbox's peak torque T2B at ``rate`` load peaks per second (the module docstring):
    f_s from its row of the maker's table (``shock_rates`` (1/s) and ``shock_factors``, (N_c, K), rising rates
    padded with NaN) interpolated linearly in the rate, its first factor below its first rate; 0 above its last rate
    (no rating there); 1 for a row without a table (NaN: no maker factor)."""
    rates, factors = np.atleast_2d(np.asarray(shock_rates, dtype=float)), np.atleast_2d(np.asarray(shock_factors,
                                                                                                   dtype=float))
    given = np.count_nonzero(np.isfinite(rates), axis=1)
    below = np.count_nonzero(rates <= rate, axis=1)  # entries at or below the rate (NaN compares false)
    rows = np.arange(len(rates))
    high = np.minimum(below, np.maximum(given - 1, 0))
    low = np.maximum(high - 1, 0)
    r0, r1, f0, f1 = rates[rows, low], rates[rows, high], factors[rows, low], factors[rows, high]
    with np.errstate(divide="ignore", invalid="ignore"):
        f_s = np.where(r1 > r0, f0 + (f1 - f0) * (rate - r0) / (r1 - r0), f1)
    f_s = np.where(below == 0, factors[:, 0], f_s)
    out = np.where(given == 0, 1.0, 1.0 / f_s)
    return np.where((given > 0) & (rate > rates[rows, np.maximum(given - 1, 0)]), 0.0, out)


def failure(name: str, factor: float) -> str:
    """A check that fails, as the reasons say it: ``name ×load factor`` (``peak torque ×1.17``), or for an infinite
    load factor what it means (``speed-torque curve: outside it (…)``, :data:`BEYOND`)."""
    if name == "brake holding torque" and factor > NO_BRAKE_FACTOR:
        return f"{name}: {BEYOND[name]}"
    if math.isfinite(factor):
        return f"{name} ×{factor:.2f}"
    return f"{name}: {BEYOND.get(name, NO_LIMIT)}"


def failures(names: tuple[str, ...], factors: ArrayLike) -> str:
    """The checks that fail (load factor > 1 + :data:`PASS_TOLERANCE`) of one candidate, ``; ``-joined
    :func:`failure` texts, or ``none``; ``factors``: the load factor of each of ``names``."""
    return "; ".join(failure(name, float(f)) for name, f in zip(names, factors) if f > 1 + PASS_TOLERANCE) or "none"


def _load_factor(value: ArrayLike, limit: ArrayLike) -> NDArray[np.float64] | float:
    """value / limit with 0/0 = 0, x/0 = inf and x/inf = 0."""
    value, limit = np.asarray(value, dtype=float), np.asarray(limit, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(value <= 0, 0.0, np.where(limit > 0, value / limit, np.inf))
    return out if out.ndim else float(out)


def _factor(value: float, limit: float) -> float:
    """:func:`_load_factor` of one value and limit (numbers): value / limit, 0/0 = 0, x/0 = inf, x/inf = 0."""
    if value <= 0:
        return 0.0
    return value / limit if limit > 0 else math.inf


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


#: Elements (converters × samples) of the motor-side arrays over every sample kept per joint
#: (:meth:`PairChecks._full_side`): those of the few candidate converters checked exactly.
KEPT_SIDES = 1 << 14


def _blocks(samples: int, converters: int) -> list[slice]:
    """Slices of the samples, each at most :data:`SAMPLE_BLOCK` / ``converters`` long (one slice for short tasks)."""
    size = max(1, SAMPLE_BLOCK // max(1, converters))
    return [slice(start, min(start + size, samples)) for start in range(0, max(samples, 1), size)]


class PairChecks:
    r"""The checks of one joint for any list of motor × converter pairs, without a (N_m, N_c) array.

    Built once per joint in O((N_m + N_c) · samples) work and memory (the time means per converter a block of
    samples at a time, :data:`SAMPLE_BLOCK`); then :meth:`table` gives the values and limits of the pairs
    (m[i], c[i]) in O(len(m)) and :meth:`screen` a pass/fail test of the checks that need no pass over the samples
    for index arrays that broadcast (a block of motors × converters). The per-sample checks (peak torque,
    speed–torque curve, voltage limit) come at three levels: 0 (none: 0, a lower bound), 1 (lower bounds from a
    few decisive samples, :meth:`JointDuty.strong_samples`), 2 (exact over the samples that can decide them,
    :meth:`JointDuty.envelope`). A lower bound never passes a pair that fails; each value is computed by the same
    floating-point operations whatever the pairs asked for, so a pair's checks do not depend on its company.
    """

    def __init__(self, duty: JointDuty, motors: pd.DataFrame | MotorArrays, conv: Converters,
                 inertia_ratio_max: float = INERTIA_RATIO_MAX, limits: DriveLimits | None = None):
        limits = limits or DriveLimits()
        motors = MotorArrays.of(motors)
        weights = duty.time_weights()
        u, eta, Jc = conv.ratio[:, None], conv.efficiency[:, None], conv.inertia[:, None]
        self._duty, self._u, self._eta, self._Jc = duty, u, eta, Jc
        self.conv, self.shape = conv, (len(motors), len(conv))
        self.rotor, self.rated, self.peak = motors.rotor, motors.rated, motors.peak
        self.rated_speed, self.top_speed = motors.rated_speed, motors.top_speed
        kt, resistance, voltage = motors.kt, motors.resistance, limits.supply(motors)
        checked = np.isfinite(voltage)  # motors with the voltage data
        # u = back_emf |n| + drop |T_m| (V): k_e = k_t, drop = R / k_t
        self.back_emf, self.drop = np.where(checked, kt, 0.0), np.where(checked, resistance / kt, 0.0)
        self.voltage = np.where(checked, voltage, math.inf)
        self.stop = limits.stop_torques(motors)
        self.drive, self.kt = motors.drive, kt
        self._runs: dict[tuple[int, int], float] = {}  # the drive's longest overload run of the pairs checked
        self.brakes, self.limits = motors.brakes, limits
        self.inertia_ratio_max = inertia_ratio_max
        # the winding temperature (mechatron.drives.thermal) of the motors with the thermal data, instead of RMS
        self.thermal, self.ambient = motors.thermal or ThermalData.of(pd.DataFrame(index=range(len(motors)))), \
            limits.ambient
        self.heated = self.thermal.given  # the motors checked by the thermal model
        self.allowed_rise = np.where(self.heated, self.thermal.allowed_rise(self.ambient), math.inf)
        self._rises: dict[tuple[int, int], float] = {}  # the exact rise of the pairs simulated
        # the exact (values, limits) of the pairs found to pass every check (:meth:`passes_exactly`)
        self._passing: dict[tuple[int, int], tuple[NDArray[np.float64], NDArray[np.float64]]] = {}

        # thermal: ⟨T_m²⟩ = J_m² ⟨a²⟩ + 2 J_m ⟨a b⟩ + ⟨b²⟩ and the mean and top motor speeds of each converter:
        # exact (sums over the samples) for the converters asked for (:meth:`_means`); in closed form from moments
        # of the duty for the screening (:meth:`_bounds`)
        self._weights = weights
        self._exact = np.full((5, len(conv)), math.nan)
        self._closed_form(duty, weights, conv)
        self.load_inertia = duty.load_inertia / conv.ratio**2 + conv.inertia  # J_L/u² + J_c (kg·m²)
        # transmission (output side): values of the duty alone, limits of the converter
        motion = np.abs(duty.speed) * weights
        if motion.sum() == 0:
            motion = weights
        self.equivalent = (motion @ np.abs(duty.torque) ** 3 / motion.sum()) ** (1 / 3)
        self.peak_load = np.abs(duty.torque).max()
        # the peak torque by the maker's rule: the task repeats, 1/T times a second, meeting n_p load peaks each time
        self.cycle_rate = 1.0 / duty.duration if duty.duration > 0 else 0.0
        self.peak_rate = peak_count(duty.acceleration) * self.cycle_rate
        self.peak_factor = peak_torque_factor(self.peak_rate, conv.shock_rates, conv.shock_factors)
        self.transmission = np.stack([conv.rated_torque, conv.peak_torque * self.peak_factor,
                                      conv.emergency_torque, conv.max_input_speed, conv.rated_input_speed], axis=1)
        self.screw_values, self.screw_limits = screw_checks(duty, conv, limits.screw_life)
        # the converters that pass the checks of the converter alone (transmission and screw, but the emergency)
        alone = np.column_stack([np.full(len(conv), self.equivalent), np.full(len(conv), self.peak_load),
                                 self._top_low, self._mean_low, self.screw_values])
        self.converter_passes = _passes(alone, np.column_stack([self.transmission[:, [0, 1, 3, 4]],
                                                                self.screw_limits])).all(axis=1)
        self._strong = motor_side(duty, u, eta, Jc, duty.strong_samples(2))
        self._keep: NDArray[np.intp] | None = None  # the envelope's samples, when many pairs are checked
        self._checked = 0  # pairs checked sample by sample so far
        self._sides: dict[int, tuple[NDArray[np.float64], ...]] = {}  # kept by :meth:`_full_side`

    def table(self, m: ArrayLike, c: ArrayLike, level: int = 2, thermal: bool = True
              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(values, limits) of every check (:data:`ALL_CHECKS`) of the pairs (m[i], c[i]), each (len(m),
        len(ALL_CHECKS)), SI units; the per-sample checks at ``level`` (0: 0, 1: lower bounds, 2: exact), the winding
        temperature rise as its mean-rise bound but at level 2 with ``thermal`` (then simulated, :meth:`winding`)."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        values, lim = np.empty((len(m), len(ALL_CHECKS))), np.empty((len(m), len(ALL_CHECKS)))
        Jm = self.rotor[m]
        if level == 0:
            rms, mean_speed, top_speed = self._bounds(m, c)
        else:
            m_aa, m_ab, m_bb, mean_speed, top_speed = self._means(c)[:, c]
            rms = np.sqrt(np.maximum(Jm**2 * m_aa + 2 * (Jm * m_ab) + m_bb, 0.0))
        values[:, 2] = rms
        lim[:, 2] = continuous_torque(mean_speed, self.rated[m], self.rated_speed[m], self.top_speed[m])
        heated = self.heated[m]
        if heated.any():  # the thermal model instead of RMS: its mean rise, a lower bound, or (level 2) exact
            lim[:, 2] = np.where(heated, math.inf, lim[:, 2])
            values[:, _WINDING] = np.where(heated, self.thermal.mean_bound(m, rms, mean_speed, self.ambient), 0.0)
            if level == 2 and thermal:
                values[heated, _WINDING] = self.winding(m[heated], c[heated])
        else:
            values[:, _WINDING] = 0.0
        lim[:, _WINDING] = self.allowed_rise[m]
        values[:, 3], lim[:, 3] = top_speed, self.top_speed[m]
        values[:, 4], lim[:, 4] = self.load_inertia[c] / Jm, self.inertia_ratio_max
        values[:, 5], values[:, 6], values[:, 7] = self.equivalent, self.peak_load, self.stop[m] * self.conv.ratio[c]
        values[:, 8], values[:, 9] = top_speed, mean_speed
        lim[:, 5:10] = self.transmission[c]
        lim[:, 0], lim[:, 1], lim[:, _VOLTAGE] = self.peak[m], 1.0, self.voltage[m]
        values[:, _WINDING + 1:_BRAKE], lim[:, _WINDING + 1:_BRAKE] = self.screw_values[c], self.screw_limits[c]
        values[:, _BRAKE:_DRIVE], lim[:, _BRAKE:_DRIVE] = brake_table(
            self._duty, self.brakes, self.rotor, self.conv, m, c, self.limits.brake_factor,
            self.limits.brake_stops_per_hour)
        self._drive_table(m, c, values, lim, level == 2 and thermal)
        if level == 0:
            values[:, PER_SAMPLE] = 0.0
        else:
            values[:, PER_SAMPLE] = np.column_stack(self._per_sample(m, c, *self._strong)) if level == 1 else \
                self.per_sample(m, c)
        return values, lim

    def worst(self, m: ArrayLike, c: ArrayLike, level: int = 2, thermal: bool = True) -> NDArray[np.float64]:
        """The largest load factor (value/limit) of each pair (m[i], c[i]), the per-sample checks at ``level`` (the
        winding's rise simulated at level 2 with ``thermal``, else its bound)."""
        return _load_factor(*self.table(m, c, level, thermal)).max(axis=1)

    def passes_exactly(self, m: ArrayLike, c: ArrayLike) -> NDArray[np.bool_]:
        """Whether the pairs (m[i], c[i]) pass every check, exact (as :meth:`worst` ≤ 1 + PASS_TOLERANCE), the
        winding simulated (:meth:`winding`) only for the pairs that pass every other check and its bound."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        values, lim = self.table(m, c, 2, thermal=False)
        ok = _load_factor(values, lim).max(axis=1) <= 1 + PASS_TOLERANCE
        sharp = np.flatnonzero(ok & self.heated[m])
        if len(sharp):
            values[sharp, _WINDING] = self.winding(m[sharp], c[sharp])
            ok[sharp] = _load_factor(values[sharp], lim[sharp]).max(axis=1) <= 1 + PASS_TOLERANCE
        driven = np.flatnonzero(ok & np.isfinite(lim[:, _DRIVE_RUN]))
        if len(driven):
            values[driven, _DRIVE_RUN] = self.overload_run(m[driven], c[driven])
            ok[driven] = _load_factor(values[driven], lim[driven]).max(axis=1) <= 1 + PASS_TOLERANCE
        for i in np.flatnonzero(ok).tolist():  # kept: the chosen pair's checks are these
            self._passing[int(m[i]), int(c[i])] = values[i], lim[i]
        return ok

    def checks(self, m: int, c: int) -> list[Check]:
        """The checks of one pair that apply (finite limit), exact (those :meth:`passes_exactly` found, where it
        did: the same numbers)."""
        row = self._passing.get((int(m), int(c)))
        values, lim = row if row is not None else (x[0] for x in self.table([m], [c]))
        return _check_list(values, lim, self.conv.emergency_stops[c])

    def screen(self, m: NDArray[np.intp], c: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether the pairs (m, c) — index arrays that broadcast, e.g. a column of motors and a row of converters
        — pass every check that needs no pass over the samples: those of the converter alone
        (:attr:`converter_passes`), RMS torque, max speed, inertia ratio and emergency torque; and the peak
        torque's bound RMS ≤ max |T_m| (with room for rounding). Necessary for a pass (never false for a pair
        that passes every check), in the same floating-point operations as :meth:`table`. A motor with the thermal
        data takes the bound of its winding's rise (its mean rise) instead of the RMS torque check."""
        rms, mean_speed, top_speed = self._bounds(m, c)
        ok = self.converter_passes[c] & _passes(top_speed, self.top_speed[m]) \
            & _passes(self.load_inertia[c] / self.rotor[m], self.inertia_ratio_max) \
            & _passes(self.stop[m] * self.conv.ratio[c], self.transmission[c, 2])
        ok &= _passes(rms * (1 - 1e-6), self.peak[m])
        heated = self.heated[m]
        if not heated.any():
            return ok & _passes(rms, continuous_torque(mean_speed, self.rated[m], self.rated_speed[m],
                                                       self.top_speed[m]))
        warm = _passes(self.thermal.mean_bound(m, rms, mean_speed, self.ambient), self.allowed_rise[m])
        if heated.all():
            return ok & warm
        return ok & np.where(heated, warm, _passes(rms, continuous_torque(mean_speed, self.rated[m],
                                                                          self.rated_speed[m], self.top_speed[m])))

    def bounds_pass(self, m: NDArray[np.intp], c: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether the pairs (m[i], c[i]) pass the per-sample checks at the few decisive samples (level 1): necessary
        for a pass, without the other checks."""
        torque, curve, voltage = self._per_sample(m, c, *self._strong)
        return _passes(torque, self.peak[m]) & _passes(curve, 1.0) & _passes(voltage, self.voltage[m])

    def _means(self, c: NDArray[np.intp]) -> NDArray[np.float64]:
        """(⟨a²⟩, ⟨a b⟩, ⟨b²⟩, ⟨|n|⟩, max |n|) of every converter (5, N_c) (a, b, n of :func:`motor_side`;
        trapezoidal time means), computed now for those of ``c`` not computed yet, all of them together, a block of
        samples at a time (memory bounded by :data:`SAMPLE_BLOCK`, whatever the length of the task)."""
        todo = _distinct(c[np.isnan(self._exact[0, c])])[0]
        if len(todo) == 0:
            return self._exact
        u, eta, Jc, weights = self._u[todo], self._eta[todo], self._Jc[todo], self._weights
        m_aa, m_ab, m_bb, mean_speed, top_speed = (np.zeros(len(todo)) for _ in range(5))
        blocks = _blocks(len(weights), len(todo))
        for block in blocks:  # (converters, samples of the block)
            n, accel, base = self._full_side(todo) if len(blocks) == 1 else motor_side(self._duty, u, eta, Jc, block)
            w = weights[block]
            m_aa += (accel**2) @ w
            m_ab += (accel * base) @ w
            m_bb += (base**2) @ w
            mean_speed += np.abs(n) @ w
            top_speed = np.maximum(top_speed, np.abs(n).max(axis=1))
            del n, accel, base
        self._exact[:, todo] = m_aa, m_ab, m_bb, mean_speed, top_speed
        return self._exact

    def _closed_form(self, duty: JointDuty, weights: NDArray[np.float64], conv: Converters) -> None:
        r"""The time means of every converter from seven moments of the duty, O(samples + N_c): with
        T_m = K u ω̇ + L, K = J_m + J_c, L = τ/(u η) where the load takes power (τ ω ≥ 0) and τ η / u elsewhere,

            ⟨T_m²⟩ = K² u² ⟨ω̇²⟩ + 2 K (⟨ω̇ τ⟩₊/η + η ⟨ω̇ τ⟩₋) + (⟨τ²⟩₊/η² + η² ⟨τ²⟩₋) / u²,

        ⟨·⟩₊ and ⟨·⟩₋ the time means over the motoring and the braking samples; ⟨|n|⟩ = |u| ⟨|ω|⟩ and
        max |n| = |u| max |ω|. They equal the sums over the samples up to rounding: relative to the same sum of
        magnitudes, M = K² u² ⟨ω̇²⟩ + 2 K (⟨|ω̇ τ|⟩₊/η + η ⟨|ω̇ τ|⟩₋) + ⟨L²⟩, both differ by at most ~N ε (N
        samples, ε the machine epsilon); the bounds of :meth:`_bounds` subtract ROUNDING = max(1e-9, 8 N ε) of it."""
        motoring = duty.torque * duty.speed >= 0
        product = duty.acceleration * duty.torque
        # the time means over the motoring and the braking samples: weights zero elsewhere, one dot product each
        plus = np.where(motoring, weights, 0.0)
        minus = weights - plus
        sums = np.stack([plus, minus]) @ np.stack([product, np.abs(product), duty.torque**2]).T  # (2, 3)
        (cross_p, abs_p, load_p), (cross_n, abs_n, load_n) = sums.tolist()

        u, eta = conv.ratio, conv.efficiency
        self._aa = u**2 * float(weights @ duty.acceleration**2)
        self._cross = cross_p / eta + eta * cross_n
        self._cross_abs = abs_p / eta + eta * abs_n
        self._load2 = (load_p / eta**2 + eta**2 * load_n) / u**2
        self._rounding = max(1e-9, 8 * len(weights) * np.finfo(float).eps)
        low = 1 - self._rounding
        self._mean_low = np.abs(u) * float(weights @ np.abs(duty.speed)) * low
        self._top_low = np.abs(u) * float(np.abs(duty.speed).max(initial=0.0)) * low

    def _bounds(self, m: NDArray[np.intp], c: NDArray[np.intp]
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Lower bounds of (RMS motor torque, mean motor speed, top motor speed) of the pairs (m, c) (index arrays
        that broadcast), in closed form (:meth:`_closed_form`): the exact values are at least these."""
        K = self.rotor[m] + self.conv.inertia[c]
        square = K**2 * self._aa[c] + 2 * K * self._cross[c] + self._load2[c]
        magnitude = K**2 * self._aa[c] + 2 * K * self._cross_abs[c] + self._load2[c]
        rms = np.sqrt(np.maximum(square - self._rounding * magnitude, 0.0))
        return rms, self._mean_low[c], self._top_low[c]

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

    def per_sample(self, m: ArrayLike, c: ArrayLike, batch: int = 512) -> NDArray[np.float64]:
        """The exact per-sample checks (:data:`PER_SAMPLE`) of the pairs (m[i], c[i]), (len(m), 3): over every
        sample for the first :data:`BEFORE_ENVELOPE` pairs of the joint, then over the samples that can decide them
        (:meth:`JointDuty.envelope`: the same maxima, the samples left out having a kept one that needs at least
        their torque at a speed at least as high); ``batch`` pairs at a time, so that the (pairs, samples) arrays
        stay within :data:`SAMPLE_BLOCK` elements."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        out = np.empty((len(m), len(PER_SAMPLE)))
        self._checked += len(m)
        if self._keep is None and self._checked > BEFORE_ENVELOPE:
            self._keep = self._duty.envelope()
        samples = slice(None) if self._keep is None else self._keep
        batch = max(1, min(batch, SAMPLE_BLOCK // max(1, len(self._duty.t[samples]))))
        for start in range(0, len(m), batch):
            mb, cb = m[start:start + batch], c[start:start + batch]
            used, where = _distinct(cb)  # the converters of the batch, at the samples that can decide
            side = self._full_side(used) if self._keep is None else \
                motor_side(self._duty, self._u[used], self._eta[used], self._Jc[used], samples)
            out[start:start + batch] = np.column_stack(self._per_sample(mb, where, *side))
        return out


    def _full_side(self, used: NDArray[np.intp]) -> tuple[NDArray[np.float64], ...]:
        """(n, a, b) of :func:`motor_side` over every sample for the converters ``used`` (sorted, distinct), each
        (len(used), samples); those of the first converters asked for kept (at most :data:`KEPT_SIDES` elements
        each), so that the exact means, the per-sample checks and the winding of a candidate take one pass."""
        kept = self._sides
        missing = [k for k in used.tolist() if k not in kept]
        if missing:
            index = np.array(missing)
            side = motor_side(self._duty, self._u[index], self._eta[index], self._Jc[index])
            if (len(kept) + len(missing)) * len(self._duty.t) > KEPT_SIDES:
                return side if len(missing) == len(used) else \
                    motor_side(self._duty, self._u[used], self._eta[used], self._Jc[used])
            kept.update((k, tuple(x[i:i + 1] for x in side)) for i, k in enumerate(missing))
        if len(used) == 1:
            return kept[int(used[0])]
        rows = [kept[k] for k in used.tolist()]
        return tuple(np.concatenate([row[j] for row in rows]) for j in range(3))

    def _drive_table(self, m: NDArray[np.intp], c: NDArray[np.intp], values: NDArray[np.float64],
                     lim: NDArray[np.float64], exact: bool) -> None:
        """The servo drive's checks into ``values`` and ``lim`` (:mod:`~mechatron.drives.servo`): RMS current
        √⟨T_m²⟩ / k_t against I_r, the longest run above I_r (exact with ``exact``, else 0, a lower bound) against
        t_p; limits inf (not applied) for a motor without a drive."""
        if self.drive is None:
            values[:, _DRIVE:], lim[:, _DRIVE:] = 0.0, math.inf
            return
        values[:, _DRIVE_RMS] = np.where(np.isfinite(self.drive.rated[m]), values[:, 2] / self.kt[m], 0.0)
        lim[:, _DRIVE_RMS], lim[:, _DRIVE_RUN] = self.drive.rated[m], self.drive.peak_time[m]
        values[:, _DRIVE_RUN] = 0.0
        if exact:
            driven = np.isfinite(lim[:, _DRIVE_RUN])
            values[driven, _DRIVE_RUN] = self.overload_run(m[driven], c[driven])

    def overload_run(self, m: ArrayLike, c: ArrayLike) -> NDArray[np.float64]:
        """The longest run (s) of the motor current |T_m / k_t| above the paired drive's rated current of the pairs
        (m[i], c[i]) over the task repeated (:func:`~mechatron.drives.servo.overload`), every sample; kept."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        for pair in zip(m.tolist(), c.tolist()):
            if pair not in self._runs:
                _, accel, base = self._full_side(np.array([pair[1]]))
                current = (self.rotor[pair[0]] * accel[0] + base[0]) / self.kt[pair[0]]
                self._runs[pair] = overload(self._duty.t, current, float(self.drive.rated[pair[0]]))[1]
        return np.array([self._runs[pair] for pair in zip(m.tolist(), c.tolist())])

    def winding(self, m: ArrayLike, c: ArrayLike) -> NDArray[np.float64]:
        """The winding's highest rise above the ambient (K) of the pairs (m[i], c[i]) over the task repeated to its
        periodic steady state (:func:`~mechatron.drives.thermal.highest_rise`, every sample of the task, the
        magnets at their fixed point): the pairs not simulated yet all at once, each simulation vectorised over them
        (in batches of :data:`~mechatron.drives.thermal.BATCH_ELEMENTS` pairs × samples; the magnet iteration's
        further simulations over the pairs not converged yet), then kept; 0 for a motor without the thermal data.
        Where the losses run away (no steady state) the rise with the resistance and k_t held at their values at
        the limit temperature: finite, above the allowed rise (the winding cannot stay below its limit, else those
        values would bound its losses) and above the mean-rise bound, so that a margin says how far the pair is
        from passing."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        pairs = list(zip(m.tolist(), c.tolist()))
        heated = self.heated[m].tolist()
        todo = [i for i, pair in enumerate(pairs) if heated[i] and pair not in self._rises]
        if todo:
            self._simulate(m[todo], c[todo])
        return np.array([self._rises[pair] if hot else 0.0 for pair, hot in zip(pairs, heated)])

    def _simulate(self, m: NDArray[np.intp], c: NDArray[np.intp]) -> None:
        """The winding's highest rise of the pairs (m[i], c[i]) (motors with the thermal data), into the kept ones."""
        duty, th = self._duty, self.thermal
        batch = max(1, BATCH_ELEMENTS // len(duty.t))
        for start in range(0, len(m), batch):
            mb, cb = m[start:start + batch], c[start:start + batch]
            used, where = _distinct(cb)
            n, accel, base = self._full_side(used)
            current = (self.rotor[mb, None] * accel[where] + base[where]) / th.kt[mb, None]
            loss = th.loss_torque[mb, None] * np.abs(n[where])
            top = highest_rise(duty.t, current * current, loss, *(x[mb, None] for x in (
                th.r_wh, th.r_ha, th.tau_w, th.tau_h, th.resistance, th.alpha)), self.ambient, th.limit[mb, None],
                th.magnet[mb, None])
            self._rises.update(zip(zip(mb.tolist(), cb.tolist()), top.tolist()))


def _distinct(index: NDArray[np.intp]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(the distinct values of ``index``, sorted; where each entry of ``index`` is among them): ``np.unique`` with
    its inverse, at once for one entry."""
    if len(index) == 1:
        return index.copy(), np.zeros(1, dtype=np.intp)
    return np.unique(index, return_inverse=True)


def _passes(value: ArrayLike, limit: ArrayLike) -> NDArray[np.bool_]:
    """Whether value/limit ≤ 1 + PASS_TOLERANCE, as :func:`_load_factor` counts it (0/0 passes, x/0 fails)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return (value <= 0) | ((limit > 0) & (value / limit <= 1 + PASS_TOLERANCE))


def _check_list(values: NDArray[np.float64], limits: NDArray[np.float64], stops: float = math.nan) -> list[Check]:
    """The checks of one pair whose limit is finite (they apply); the emergency torque's with its count ``stops``
    (the times it is allowed in the gearbox's life; NaN: none)."""
    return [Check(name, float(values[k]), float(limits[k]), ALL_UNITS[k],
                  float(stops) if k == _EMERGENCY and math.isfinite(stops) else None)
            for k, name in enumerate(ALL_CHECKS) if math.isfinite(limits[k])]


class Evaluation:
    """The checks of every motor × converter pair of one joint as arrays: ``values`` and ``limits`` (N_m, N_c,
    len(ALL_CHECKS)), for small catalogs and tests (the sizing itself goes through :class:`PairChecks` a chunk of
    pairs at a time).

    The per-sample checks (peak torque, speed–torque curve, voltage limit) start as lower bounds from a few decisive
    samples (:meth:`JointDuty.strong_samples`) and are made exact for the pairs given to :meth:`refine` (``exact``
    marks them) over the samples that can decide them (:meth:`JointDuty.envelope`). Every other check is exact from
    the start (the winding temperature rise simulated for every pair). A lower bound never passes a pair that
    fails.
    """

    def __init__(self, duty: JointDuty, motors: pd.DataFrame, conv: Converters,
                 inertia_ratio_max: float = INERTIA_RATIO_MAX, limits: DriveLimits | None = None):
        self.pairs = PairChecks(duty, motors, conv, inertia_ratio_max, limits)
        shape = self.pairs.shape
        rows, cols = np.indices(shape)
        values, lim = self.pairs.table(rows.ravel(), cols.ravel(), level=1)
        heated = self.pairs.heated[rows.ravel()]  # the winding's temperature exact from the start, as RMS is
        values[heated, _WINDING] = self.pairs.winding(rows.ravel()[heated], cols.ravel()[heated])
        driven = np.isfinite(lim[:, _DRIVE_RUN])  # and the drive's overload run (mechatron.drives.servo)
        values[driven, _DRIVE_RUN] = self.pairs.overload_run(rows.ravel()[driven], cols.ravel()[driven])
        self.values, self.limits = values.reshape(shape + (-1,)), lim.reshape(shape + (-1,))
        self.exact = np.zeros(shape, dtype=bool)

    def refine(self, m: ArrayLike, c: ArrayLike) -> None:
        """Make the per-sample checks exact for the pairs (m[i], c[i])."""
        m, c = np.asarray(m, dtype=int), np.asarray(c, dtype=int)
        todo = ~self.exact[m, c]
        m, c = m[todo], c[todo]
        exact = self.pairs.per_sample(m, c)
        for i, k in enumerate(PER_SAMPLE):
            self.values[m, c, k] = exact[:, i]
        self.exact[m, c] = True

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

    def failed(self, m: int, c: int) -> list[str]:
        """The checks the pair (m, c) fails, each as :func:`failure` says it (``name ×load factor``)."""
        factors = self.load_factors_of(m, c)
        return [failure(name, factors[k]) for k, name in enumerate(ALL_CHECKS) if factors[k] > 1 + PASS_TOLERANCE]

    def checks(self, m: int, c: int) -> list[Check]:
        """The checks of one pair that apply (finite limit), made exact first."""
        self.refine([m], [c])
        return _check_list(self.values[m, c], self.limits[m, c], self.pairs.conv.emergency_stops[c])


def evaluate(duty: JointDuty, motors: pd.DataFrame, conv: Converters, inertia_ratio_max: float = INERTIA_RATIO_MAX,
             exact: bool = True, limits: DriveLimits | None = None) -> Evaluation:
    """Every check of every motor × converter pair (see the module docstring); with ``exact=False`` the
    per-sample checks are lower bounds until :meth:`Evaluation.refine` is called. ``limits``: the emergency-stop
    limit, required screw life and supply voltage (:class:`DriveLimits`)."""
    evaluation = Evaluation(duty, motors, conv, inertia_ratio_max, limits)
    return evaluation.refine_all() if exact else evaluation

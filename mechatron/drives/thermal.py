r"""The heat of a motor over the repeated task: a two-node thermal network of its winding and housing, at its
periodic steady state, and the IEC 60034-1 duty type of a task.

**The network** (the makers' model: maxon, Siemens SIZER, Kollmorgen): the winding (node w, heat capacity C_w) gives
its heat through the thermal resistance R_wh (K/W) to the housing (node h, C_h), which gives it through R_ha to the
ambient air at T_a. With the rises θ = T − T_a (K),

    C_w dθ_w/dt = P(t) − (θ_w − θ_h)/R_wh,
    C_h dθ_h/dt = (θ_w − θ_h)/R_wh − θ_h/R_ha.

The catalogs give the two thermal resistances and the two thermal time constants as the makers print them,
τ_w = R_wh C_w (winding) and τ_h = R_ha C_h (housing, "motor"), so C_w = τ_w/R_wh and C_h = τ_h/R_ha (J/K).

**The losses** heat the winding: the copper loss I² R(T_w) of the current I = T_m/k_t (T_m the motor torque, k_t
the torque constant) with the winding resistance rising with its temperature,

    R(T) = R₂₅ (1 + α (T − 25 °C)),    α = 0.0039 1/K for copper (the catalog's ``temperature_coefficient``),

and, where the catalog gives a ``loss_torque`` T_f (N·m), the speed-dependent losses T_f |n| (friction and iron
losses as a torque lost at the motor speed n, in W). Conservatively all of them enter the winding node.

**Exact over each sample interval.** Between two samples t_k, t_k+1 of the task (step h_k) the current is taken
constant, I_k² = (I²(t_k) + I²(t_k+1))/2, and so is the speed loss (the trapezoidal time means of the sizing's RMS
torque: the mean loss over the cycle is the one the RMS check sees). As P = I_k² R_a + I_k² R₂₅ α θ_w + P_f is
linear in θ_w (R_a = R(T_a)), each interval is a linear system with constant coefficients, dθ/dt = A_k θ + b_k,

    A_k = [[−1/τ_w + R₂₅ α I_k²/C_w,  1/τ_w], [1/(R_wh C_h),  −1/(R_wh C_h) − 1/τ_h]],
    b_k = [(I_k² R_a + P_f,k)/C_w, 0],

solved exactly: θ(t_k+1) = E_k θ(t_k) + g_k with E_k = exp(A_k h_k) and g_k = A_k⁻¹ (E_k − 1) b_k, from the two
real eigenvalues of A_k (λ₁ = s − q, λ₂ = det A_k / λ₁, s = tr A_k / 2, q = √((a₁₁ − a₂₂)²/4 + a₁₂ a₂₁) > 0) and
their spectral projectors P₁ = (A_k − λ₂)/(λ₁ − λ₂), P₂ = 1 − P₁: E_k = e^{λ₁h} P₁ + e^{λ₂h} P₂,
A_k⁻¹(E_k − 1) = (e^{λ₁h} − 1)/λ₁ P₁ + (e^{λ₂h} − 1)/λ₂ P₂ (expm1, h where λ = 0). No step size, no iteration: the
resistance's rise with temperature is exact too.

**The periodic steady state** of the task repeated for ever is the fixed point of the cycle's map, the affine map
θ ↦ M θ + G composed of the intervals' maps: θ(0) = (1 − M)⁻¹ G, solved directly (no simulation of cycle after
cycle). The maps are composed interval by interval in machine code (or, without a C compiler, pairwise up a balanced
tree: log₂ N levels of vectorised 2 × 2 products), then the states at every sample follow from θ(0). When the cycle
map has an eigenvalue ≥ 1 — the copper loss growing with temperature faster than the network sheds it — there is no
steady state (thermal runaway): NaN, an infinite rise. The winding's highest temperature over the cycle is taken at
the samples (the task's resolution).

The check (:mod:`~mechatron.drives.checks`, "winding temperature rise"): max θ_w ≤ T_max − T_a, the allowed rise of
the winding's limit temperature T_max above the ambient (``mechatron size --ambient``, default 40 °C): the ambient
derates the motor. Where the losses run away the check takes the rise with the resistance held at R(T_max): finite,
and above the allowed rise (were it not, that resistance would bound the losses below the limit, and the winding
could not run away), so that its margin says how far the motor is from passing. A lower bound, for screening many
pairs cheaply: over a period the heat stored returns to its start, so the time means obey ⟨θ_w⟩ = (R_wh + R_ha) ⟨P⟩
exactly, and since θ_w ≥ 0,

    max θ_w ≥ ⟨θ_w⟩ ≥ (R_wh + R_ha) (R_a ⟨T_m²⟩/k_t² + T_f ⟨|n|⟩),

the RMS torque's own bound. A motor whose catalog row lacks the thermal data is checked by its RMS torque against the
S1 curve at the mean speed instead.

**Duty type** (IEC 60034-1, :func:`duty_type`): from the task's moves and dwells (:attr:`JointDuty.moving
<mechatron.drives.duty.JointDuty.moving>`): S1 (continuous running duty) when the task has no dwell; S3 x %
(intermittent periodic duty) when the joint rests without load in the dwells (its motor carries no torque, as
de-energised); S6 x % (continuous-operation periodic duty) when it holds a load in them (its motor is never
de-energised); x is the cyclic duration factor, the time moving over the cycle time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .motor import catalog_column

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .duty import JointDuty

#: The temperature coefficient of copper's resistance (1/K) near 25 °C, the default of ``temperature_coefficient``.
ALPHA_COPPER = 0.0039
#: 0 °C in K.
ZERO_CELSIUS = 273.15
#: The reference temperature of the catalog's resistance R₂₅ (K): 25 °C.
REFERENCE = ZERO_CELSIUS + 25.0
#: The default ambient temperature (K): 40 °C, the rating ambient of IEC 60034-1.
DEFAULT_AMBIENT = ZERO_CELSIUS + 40.0
#: The ambient temperatures accepted (K): −50 … 100 °C.
AMBIENT_RANGE = (ZERO_CELSIUS - 50.0, ZERO_CELSIUS + 100.0)
#: The thermal columns of a motor catalog that go together (all or none in a row), with k_t and R.
THERMAL_COLUMNS = ("rth_winding_housing", "rth_housing_ambient", "tau_winding", "tau_housing",
                   "max_winding_temperature")
#: Elements of the (pairs × samples) arrays of one batch of simulations (:func:`periodic_rise`'s memory).
BATCH_ELEMENTS = 1 << 18


@dataclass(frozen=True)
class ThermalData:
    """The thermal data of every motor of a catalog (SI; NaN where a row lacks them): thermal resistances winding →
    housing ``r_wh`` and housing → ambient ``r_ha`` (K/W), time constants ``tau_w`` and ``tau_h`` (s), the
    winding's limit temperature ``limit`` (K), its resistance at 25 °C ``resistance`` (Ω) and temperature
    coefficient ``alpha`` (1/K), the torque constant ``kt`` (N·m/A) and the speed-dependent ``loss_torque`` (N·m,
    0 where not given); ``given``: which motors have the whole model."""

    r_wh: NDArray[np.float64]
    r_ha: NDArray[np.float64]
    tau_w: NDArray[np.float64]
    tau_h: NDArray[np.float64]
    limit: NDArray[np.float64]
    resistance: NDArray[np.float64]
    alpha: NDArray[np.float64]
    kt: NDArray[np.float64]
    loss_torque: NDArray[np.float64]

    @property
    def given(self) -> NDArray[np.bool_]:
        return np.isfinite(self.r_wh + self.r_ha + self.tau_w + self.tau_h + self.limit + self.resistance + self.kt)

    @classmethod
    def of(cls, motors: pd.DataFrame) -> ThermalData:
        """The thermal data of a motor catalog read by :func:`~mechatron.drives.catalogs.read_catalog`."""
        return cls(*(catalog_column(motors, name) for name in (*THERMAL_COLUMNS, "resistance")),
                   catalog_column(motors, "temperature_coefficient", ALPHA_COPPER),
                   catalog_column(motors, "torque_constant"), catalog_column(motors, "loss_torque", 0.0))

    def allowed_rise(self, ambient: float) -> NDArray[np.float64]:
        """T_max − T_a (K) of every motor: the rise the winding may take at the ambient ``ambient`` (K)."""
        return self.limit - ambient

    def mean_bound(self, m: ArrayLike, rms: ArrayLike, mean_speed: ArrayLike, ambient: float) -> NDArray[np.float64]:
        """(R_wh + R_ha)(R(T_a) T_rms²/k_t² + T_f ⟨|n|⟩) (K): the mean winding rise of motor ``m`` at the RMS torque
        ``rms`` (N·m) and mean speed ``mean_speed`` (rad/s), a lower bound of its highest rise (module docstring;
        arrays broadcast)."""
        r_amb = self.resistance[m] * (1 + self.alpha[m] * (ambient - REFERENCE))
        return (self.r_wh[m] + self.r_ha[m]) * (r_amb * (np.asarray(rms) / self.kt[m]) ** 2
                                                + self.loss_torque[m] * np.asarray(mean_speed))


def interval_maps(h: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                  tau_w: ArrayLike, tau_h: ArrayLike, r_ambient: ArrayLike, dr_dt: ArrayLike
                  ) -> tuple[NDArray[np.float64], ...]:
    """The exact maps θ(t_k+1) = E_k θ(t_k) + g_k of the intervals (module docstring) as six arrays (E₁₁, E₁₂,
    E₂₁, E₂₂, g₁, g₂), for the steps ``h`` (s), the interval's squared current ``current_sq`` (A²) and speed loss
    ``speed_loss`` (W), the network (thermal resistances in K/W, time constants in s), the resistance at the
    ambient ``r_ambient`` (Ω) and its slope R₂₅ α ``dr_dt`` (Ω/K); every argument broadcasts (a column per motor
    against a row of intervals)."""
    with np.errstate(over="ignore", invalid="ignore"):  # a runaway interval overflows: its cycle has no steady state
        return _interval_maps(h, current_sq, speed_loss, r_wh, r_ha, tau_w, tau_h, r_ambient, dr_dt)


def _interval_maps(h: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                   tau_w: ArrayLike, tau_h: ArrayLike, r_ambient: ArrayLike, dr_dt: ArrayLike
                   ) -> tuple[NDArray[np.float64], ...]:
    h, i2 = np.asarray(h, dtype=float), np.asarray(current_sq, dtype=float)
    r_wh, r_ha, tau_w, tau_h = (np.asarray(x, dtype=float) for x in (r_wh, r_ha, tau_w, tau_h))
    c_w, c_h = tau_w / r_wh, tau_h / r_ha
    a12 = 1.0 / tau_w
    a21 = 1.0 / (r_wh * c_h)
    a22 = -a21 - 1.0 / tau_h
    a11 = np.asarray(dr_dt) / c_w * i2 - a12
    b1 = (i2 * (np.asarray(r_ambient) / c_w) + np.asarray(speed_loss) / c_w)
    half = 0.5 * (a11 - a22)
    q = np.sqrt(half * half + a12 * a21)
    l1 = 0.5 * (a11 + a22) - q  # ≤ a22 < 0: never zero
    l2 = (a11 * a22 - a12 * a21) / l1
    span = -2.0 * q  # λ1 − λ2, never zero
    f1 = np.expm1(l1 * h)
    e1 = f1 + 1.0
    f1 /= l1
    x2 = l2 * h
    f2 = np.expm1(x2)
    e2 = f2 + 1.0
    small = x2 == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        f2 /= l2
    if small.any():
        f2 = np.where(small, h, f2)
    # P1 = (A − λ2)/(λ1 − λ2), P2 = 1 − P1
    p11 = (a11 - l2) / span
    de = (e1 - e2) / span
    df = (f1 - f2) / span
    return (e2 + (e1 - e2) * p11, de * a12, de * a21, e2 + de * (a22 - l2),
            (f2 + (f1 - f2) * p11) * b1, df * a21 * b1)


def periodic_states(maps: tuple[NDArray[np.float64], ...]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The states (θ_w, θ_h), each (..., N), at the start of each of the N intervals whose maps are ``maps`` (the six
    arrays (..., N) of :func:`interval_maps`), for the periodic steady state: the state after the last interval is
    the first one (the fixed point θ₀ = (1 − M)⁻¹ G of the cycle map M θ + G). NaN (all of a batch row) where the
    cycle map has an eigenvalue of modulus ≥ 1: no steady state (thermal runaway).

    Machine code where a C compiler is at hand (:mod:`~mechatron.drives.periodic_kernel`: the cycle's map composed
    interval by interval, its fixed point, the states interval by interval; a few floating-point operations an
    interval), else :func:`tree_states`; the two agree to rounding."""
    from .periodic_kernel import native_states

    states = native_states(maps)
    return states if states is not None else tree_states(maps)


def tree_states(maps: tuple[NDArray[np.float64], ...]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`periodic_states` in NumPy: the maps composed pairwise up a balanced tree (the intervals padded with
    identities to a power of two), the cycle's map solved at its top, and the start states brought down the tree:
    O(N) work in log₂ N vectorised steps."""
    maps = np.broadcast_arrays(*maps)
    n = maps[0].shape[-1]
    packed = np.empty((2, 3, *maps[0].shape))  # [[E₁₁, E₁₂, g₁], [E₂₁, E₂₂, g₂]]
    for (row, column), x in zip(((0, 0), (0, 1), (1, 0), (1, 1), (0, 2), (1, 2)), maps):
        packed[row, column] = x
    with np.errstate(over="ignore", invalid="ignore"):  # a runaway: inf and NaN, then NaN states
        w, c = _descend(_tree(packed))
    return w[..., :n], c[..., :n]


def _tree(maps: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """The levels of the pairwise composition of the interval maps, each level one array (2, 3, ..., S) of affine
    maps [[E₁₁, E₁₂, g₁], [E₂₁, E₂₂, g₂]]: level 0 the maps, each next one B ∘ A of every pair (A the first, B the
    second map: C₍ᵢⱼ₎ = B₍ᵢ₁₎ A₍₁ⱼ₎ + B₍ᵢ₂₎ A₍₂ⱼ₎, g_C += g_B) and the last map of an odd level as it is, down to the
    whole cycle's; a few array operations a level, on every row of the batch at once. (Carrying the odd one up is
    its composition with an identity, I ∘ A = A to the bit: the tree of the intervals padded to a power of two.)"""
    levels = [maps]
    while maps.shape[-1] > 1:
        pairs = maps.shape[-1] // 2
        a, b = maps[..., 0:2 * pairs:2], maps[..., 1:2 * pairs:2]  # the first map of each pair, then the second
        upper = np.empty((*maps.shape[:-1], maps.shape[-1] - pairs))
        upper[..., :pairs] = b[:, 0:1] * a[0] + b[:, 1:2] * a[1]
        upper[:, 2, ..., :pairs] += b[:, 2]
        if maps.shape[-1] % 2:
            upper[..., pairs] = maps[..., -1]
        maps = upper
        levels.append(maps)
    return levels


def _descend(levels: list[NDArray[np.float64]]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The periodic steady state (θ_w, θ_h), each (..., S), at the start of every interval of level 0 of
    ``levels`` (:func:`_tree`): the fixed point of the cycle's map at the top, then down the levels, each pair's
    second interval starting where its first map takes the pair's start (E θ + g). NaN (a whole row) where the
    cycle's map has an eigenvalue of modulus ≥ 1."""
    (m11, m12, g1), (m21, m22, g2) = levels[-1][..., 0]
    i11, i22 = 1.0 - m11, 1.0 - m22
    det = i11 * i22 - m12 * m21
    with np.errstate(divide="ignore"):
        w = (i22 * g1 + m12 * g2) / det
        c = (i11 * g2 + m21 * g1) / det
        # the spectral radius of M: its eigenvalues from its trace and determinant
        tr, dm = m11 + m22, m11 * m22 - m12 * m21
        disc = tr * tr / 4 - dm
        radius = np.where(disc >= 0, np.abs(tr) / 2 + np.sqrt(np.maximum(disc, 0.0)), np.sqrt(np.abs(dm)))
    runaway = ~(radius < 1.0) | ~np.isfinite(w) | ~np.isfinite(c)
    state = np.stack([np.where(runaway, np.nan, w), np.where(runaway, np.nan, c)])[..., None]
    for level in reversed(levels[:-1]):
        pairs = level.shape[-1] // 2
        first = level[..., 0:2 * pairs:2]
        inner = np.empty((2, *level.shape[2:]))
        inner[..., 0::2] = state  # each pair's first interval (and an odd last one) starts where the pair does
        inner[..., 1::2] = first[:, 0] * state[0, ..., :pairs] + first[:, 1] * state[1, ..., :pairs] + first[:, 2]
        state = inner
    return state[0], state[1]


def periodic_rise(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                  tau_w: ArrayLike, tau_h: ArrayLike, resistance: ArrayLike, alpha: ArrayLike,
                  ambient: float) -> NDArray[np.float64]:
    """The winding's and the housing's rise above the ambient (K), (..., N, 2), at the N samples ``t`` (s) of one
    cycle repeated for ever (its periodic steady state, the module docstring): ``current_sq`` I² (A²) and
    ``speed_loss`` (W) at the samples (..., N), the network of each row (..., 1): thermal resistances (K/W), time
    constants (s), R₂₅ (Ω) and α (1/K); ``ambient`` T_a (K). The loss is constant over each interval, the mean of
    its ends. NaN (a whole row) where the losses run away (no steady state)."""
    samples = len(np.asarray(t))
    w, c = _interval_starts(t, current_sq, speed_loss, r_wh, r_ha, tau_w, tau_h, resistance, alpha, ambient)
    # the states at the start of every interval; the last sample's is the first's
    return np.stack([np.concatenate([w, w[..., :1]], axis=-1), np.concatenate([c, c[..., :1]], axis=-1)],
                    axis=-1)[..., :samples, :]


def _interval_starts(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                     tau_w: ArrayLike, tau_h: ArrayLike, resistance: ArrayLike, alpha: ArrayLike, ambient: float
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(θ_w, θ_h) (K), each (..., max(N − 1, 1)), at the start of every interval of :func:`periodic_rise` (its
    arguments): the rises at the samples but the last, whose is the first's."""
    t = np.asarray(t, dtype=float)
    i2, loss = np.broadcast_arrays(np.asarray(current_sq, dtype=float), np.asarray(speed_loss, dtype=float))
    if len(t) < 2:  # one sample: a constant load, its steady state
        i2, loss, t = np.concatenate([i2, i2], axis=-1), np.concatenate([loss, loss], axis=-1), np.array([0.0, 1.0])
    resistance, alpha = np.asarray(resistance, dtype=float), np.asarray(alpha, dtype=float)
    return periodic_states(interval_maps(
        np.diff(t), 0.5 * (i2[..., 1:] + i2[..., :-1]), 0.5 * (loss[..., 1:] + loss[..., :-1]), r_wh, r_ha, tau_w,
        tau_h, resistance * (1 + alpha * (ambient - REFERENCE)), resistance * alpha))


def highest_rise(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                 tau_w: ArrayLike, tau_h: ArrayLike, resistance: ArrayLike, alpha: ArrayLike, ambient: float,
                 limit: ArrayLike) -> NDArray[np.float64]:
    """The winding's highest rise above the ambient (K) over the periodic steady state, max_k θ_w(t_k) (at least
    0), of every row of a batch — one simulation for all of them, vectorised over the rows: the arguments of
    :func:`periodic_rise` (rows (..., N), networks (..., 1)) and each row's winding limit temperature ``limit``
    T_max (K, (..., 1)). Where the losses run away (no steady state) the highest rise with the resistance held at
    R(T_max) = R₂₅ (1 + α (T_max − 25 °C)) instead: finite, and above the allowed rise T_max − T_a (the check's
    value of a winding that cannot stay below its limit; the module docstring)."""
    w, _ = _interval_starts(t, current_sq, speed_loss, r_wh, r_ha, tau_w, tau_h, resistance, alpha, ambient)
    top = np.max(w, axis=-1, initial=0.0)
    runaway = np.isnan(top)
    if runaway.any():
        i2, loss = np.broadcast_arrays(np.asarray(current_sq, dtype=float), np.asarray(speed_loss, dtype=float))
        network = [np.broadcast_to(np.asarray(x, dtype=float), top.shape + (1,))[runaway]
                   for x in (r_wh, r_ha, tau_w, tau_h, resistance, alpha, limit)]
        held = network[4] * (1 + network[5] * (network[6] - REFERENCE))
        w, _ = _interval_starts(t, i2[runaway], loss[runaway], *network[:4], held, 0.0, ambient)
        top[runaway] = np.max(w, axis=-1, initial=0.0)
    return top


def winding_temperature(t: ArrayLike, torque: ArrayLike, speed: ArrayLike, thermal: ThermalData, motor: int,
                        ambient: float = DEFAULT_AMBIENT) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(T_w, T_h): the winding's and the housing's temperature (K) at the samples ``t`` (s) of a cycle repeated for
    ever, for the motor torque ``torque`` (N·m) and speed ``speed`` (rad/s) of motor ``motor`` of ``thermal``, at
    the ambient ``ambient`` (K); inf where the losses run away."""
    i2 = (np.asarray(torque, dtype=float) / thermal.kt[motor]) ** 2
    loss = thermal.loss_torque[motor] * np.abs(np.asarray(speed, dtype=float))
    rise = periodic_rise(t, i2[None, :], loss[None, :], *(x[motor] for x in (
        thermal.r_wh, thermal.r_ha, thermal.tau_w, thermal.tau_h, thermal.resistance, thermal.alpha)), ambient)[0]
    rise = np.where(np.isnan(rise), np.inf, rise)
    return ambient + rise[:, 0], ambient + rise[:, 1]


def duty_type(duty: JointDuty) -> tuple[str, float]:
    """The IEC 60034-1 duty type of a joint's task and its cyclic duration factor x (the time moving over the cycle
    time): ``("S1", 1.0)`` without dwells, ``("S3", x)`` when the joint carries no torque in its dwells (at rest,
    de-energised), ``("S6", x)`` when it holds a load there (never de-energised)."""
    moving = duty.moving
    if moving is None or moving.all() or duty.duration <= 0:
        return "S1", 1.0
    step = np.diff(duty.t)
    x = float(step[moving].sum() / duty.duration)
    ends = np.zeros(len(duty.t), dtype=bool)  # the samples at the ends of a dwell interval
    ends[:-1] |= ~moving
    ends[1:] |= ~moving
    scale = float(np.abs(duty.torque).max(initial=0.0))
    holding = bool(np.any(np.abs(duty.torque[ends]) > 1e-9 * scale))
    return ("S6" if holding else "S3"), x


def duty_text(kind: str, factor: float) -> str:
    """``S1``, ``S3 25 %``, ``S6 40 %``."""
    return kind if kind == "S1" else f"{kind} {100 * factor:.0f} %"

r"""The heat of a motor over the repeated task: a two-node thermal network of its winding and housing, at its
periodic steady state, and the IEC 60034-1 duty type of a task.

**The network** (the makers' model: maxon, Siemens SIZER, Kollmorgen): the winding (node w, heat capacity C_w) gives
its heat through the thermal resistance R_wh (K/W) to the housing (node h, C_h), which gives it through R_ha to the
ambient air at T_a. With the rises θ = T − T_a (K),

    C_w dθ_w/dt = P(t) − (θ_w − θ_h)/R_wh,
    C_h dθ_h/dt = (θ_w − θ_h)/R_wh − θ_h/R_ha.

The catalogs give the two thermal resistances and the two thermal time constants as the makers print them,
τ_w = R_wh C_w (winding) and τ_h = R_ha C_h (housing, "motor"), so C_w = τ_w/R_wh and C_h = τ_h/R_ha (J/K).

**The losses** heat the winding: the copper loss I² R(T_w) of the current I = T_m/k_t(T_m) (T_m the motor torque,
k_t the torque constant at the magnets' temperature T_m) with the winding resistance rising with its temperature,

    R(T) = R₂₅ (1 + α (T − 25 °C)),    α = 0.0039 1/K for copper (the catalog's ``temperature_coefficient``),

and, where the catalog gives a ``loss_torque`` T_f (N·m), the speed-dependent losses T_f |n| (friction and iron
losses as a torque lost at the motor speed n, in W). Conservatively all of them enter the winding node.

**The magnets heat too.** A permanent-magnet motor's torque constant is proportional to its magnets' flux, which
falls with their temperature as their remanence does; mechatron takes it linear (its own model; the armature's
reaction left out),

    k_t(T) = k_t₂₅ (1 + β (T − 25 °C)),    β = −0.0011 1/K for NdFeB (the catalog's ``torque_constant_coefficient``),

k_t₂₅ the catalog's ``torque_constant`` (at 25 °C, as R₂₅), β of sintered NdFeB's remanence −0.09 … −0.12 %/K
[Magnets] (SmCo −0.03 … −0.05 %/K; 0: k_t constant). The magnets sit on the rotor, across the air gap from the
stator and its housing and far from the copper; mechatron takes their temperature as the housing's mean over the
cycle, T_m = T_a + x, x = ⟨θ_h⟩ (its own choice: the rotor's time constant, like the housing's, is much longer than
a task's cycle, and the winding, the hottest part, would overstate their heating). The current is then I² =
(T_m/k_t₂₅)² s(x), s(x) = 1/(1 + β (T_a − 25 °C + x))², the same over the whole cycle, so that every interval stays
exact as below; only x must be found: the fixed point x = ⟨θ_h⟩(s(x)) of the housing's trapezoidal time mean over
the cycle simulated at s(x), for each pair on its own (:class:`_MagnetRoot`). Its start is the root of the mean
model — θ_w at its mean, ⟨P⟩ = (s ⟨I²⟩ R_a + ⟨P_f⟩)/(1 − s ⟨I²⟩ R₂₅ α (R_wh + R_ha)), ⟨θ_h⟩ = R_ha ⟨P⟩ (exact for
a constant load) —, then a secant step on each simulation (the first with the mean model's slope), kept within a
bracket of the root, until |⟨θ_h⟩ − x| ≤ 1e-3 K (:data:`MAGNET_TOLERANCE`; the winding's rise then within ~1e-3 K
of the fixed point's): most pairs of a robot's task take one or two simulations, a motor with β = 0 exactly one.
A hot winding runs hotter for it: magnets at 125 °C lose 11 % of k_t₂₅, which takes 12 % more current and 26 % more
copper loss.

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
cycle). The maps are made and composed interval by interval in machine code (or, without a C compiler, in NumPy
pairwise up a balanced tree: log₂ N levels of vectorised 2 × 2 products), then the states at every sample follow
from θ(0). When the cycle map has an eigenvalue ≥ 1 — the copper loss growing with temperature faster than the
network sheds it — there is no steady state (thermal runaway): NaN, an infinite rise; so too where the magnet
iteration finds none (the magnets weakening with the heat they cause faster than the network sheds it). The
winding's highest temperature over the cycle is taken at the samples (the task's resolution).

The check (:mod:`~mechatron.drives.checks`, "winding temperature rise"): max θ_w ≤ T_max − T_a, the allowed rise of
the winding's limit temperature T_max above the ambient (``mechatron size --ambient``, default 40 °C): the ambient
derates the motor. Where the losses run away the check takes the rise with the resistance held at R(T_max) and k_t
at k_t(T_max): finite, and above the allowed rise (were it not, those values would bound the losses below the limit,
and the winding could not run away), so that its margin says how far the motor is from passing. A lower bound, for
screening many pairs cheaply: over a period the heat stored returns to its start, so the time means obey ⟨θ_w⟩ =
(R_wh + R_ha) ⟨P⟩ exactly, and since θ_w, θ_h ≥ 0 (and β ≤ 0: k_t(T_m) ≤ k_t(T_a)),

    max θ_w ≥ ⟨θ_w⟩ ≥ (R_wh + R_ha) (R_a ⟨T_m²⟩/k_t(T_a)² + T_f ⟨|n|⟩),

the RMS torque's own bound. A motor whose catalog row lacks the thermal data is checked by its RMS torque against the
S1 curve at the mean speed instead. Left out: a derating of the torque at standstill (a held torque concentrates the
current in one or two phases; the makers derate their stall torque for it), for want of a factor a source states.

**Duty type** (:func:`duty_type`): a label for the report, after the definitions of IEC 60034-1 [IEC 60034-1,
4.2] applied to the motor's torque T and speed n over the task repeated for ever (identical cycles); the check itself
simulates the cycle whatever its label. A sample is *at rest de-energised* where |T| and |n| are both within
:data:`DUTY_TOLERANCE` (5 %, mechatron's own) of their largest over the cycle; *starting* or *braking* where the
joint's |ω̇| is above 5 % of its largest (braking: ω̇ against ω), the braking *electric* where the motor's torque is
against its speed (T n < 0, the motor generating); *running* elsewhere: at *no load* where |T| is within 5 % of zero
(holding a load at standstill is running at that load, at zero speed: not the no-load of S6), else *under load*, a
*constant load* where |T| and |n| stay within a band 5 % of their largest wide (a reversal at the same load is
constant). Then:

- S1, continuous running duty [4.2.1]: a constant load, no rest, no starting or braking, no no-load running;
- S3 x %, intermittent periodic duty [4.2.3]: a constant load and rests, no starting or braking (a load switched on
  and off);
- S4 x % [4.2.4] / S5 x % [4.2.5], intermittent periodic duty with starting / with electric braking: starting, a
  constant load, braking and rests; S5 where the motor brakes (a servo's deceleration), S4 where the load does;
- S6 x %, continuous-operation periodic duty [4.2.6]: a constant load and no-load running, no rest;
- S7, continuous-operation periodic duty with electric braking [4.2.7]: starting, a constant load and electric
  braking, no rest;
- S9, duty with non-periodic load and speed variations [4.2.9]: any other cycle, a load or a speed varying under
  load above all (a robot's joint carrying gravity and inertia along its path: its moves, 5 % constant nowhere).

x is the cyclic duration factor, the time energised over the cycle's (starting, under load and braking; S6: under
load) [4.2.3–4.2.6]. Not assigned: S2 (short-time duty: a rest long enough to cool within 2 K of the coolant) and
S10 (each of a few loads held to thermal equilibrium), which depend on the motor's thermal time constants, not on
the cycle alone (such a cycle is labelled S3 or S9), and S8 (constant loads at related speeds), labelled S9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .motor import catalog_column
from .periodic_kernel import PARAMETERS, native_states

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .duty import JointDuty

#: The temperature coefficient of copper's resistance (1/K) near 25 °C, the default of ``temperature_coefficient``.
ALPHA_COPPER = 0.0039
#: 0 °C in K.
ZERO_CELSIUS = 273.15
#: The reference temperature of the catalog's resistance R₂₅ (K): 25 °C.
REFERENCE = ZERO_CELSIUS + 25.0
#: The default ambient temperature (°C): 40 °C, the ambient air of the ratings [IEC 60034-1, 6].
AMBIENT_DEGC = 40.0
#: The default ambient temperature (K).
DEFAULT_AMBIENT = ZERO_CELSIUS + AMBIENT_DEGC
#: The ambient temperatures accepted (K): −50 … 100 °C.
AMBIENT_RANGE = (ZERO_CELSIUS - 50.0, ZERO_CELSIUS + 100.0)
#: The thermal columns of a motor catalog that go together (all or none in a row), with k_t and R.
THERMAL_COLUMNS = ("rth_winding_housing", "rth_housing_ambient", "tau_winding", "tau_housing",
                   "max_winding_temperature")
#: Elements of the (pairs × samples) arrays of one batch of simulations (:func:`periodic_rise`'s memory).
BATCH_ELEMENTS = 1 << 18
#: k_t's temperature coefficient β (1/K), the default of ``torque_constant_coefficient``: mechatron's value for
#: sintered NdFeB magnets, within the range −0.09 … −0.12 %/K of their remanence's coefficient [Magnets].
MAGNET_COEFFICIENT = -0.0011
#: The magnet iteration stops where the housing's mean rise is within this of the magnet rise it was simulated at
#: (K; mechatron's own).
MAGNET_TOLERANCE = 1e-3
#: The most simulations of one row in the magnet iteration (a row not converged by then has no steady state).
MAGNET_ITERATIONS = 60
#: The duty type's tolerance (mechatron's own; IEC 60034-1 defines the types in words): a load or a speed counts as
#: zero within this fraction of its largest over the cycle, as constant where it stays within a band of that width.
DUTY_TOLERANCE = 0.05


@dataclass(frozen=True)
class ThermalData:
    """The thermal data of every motor of a catalog (SI; NaN where a row lacks them): thermal resistances winding →
    housing ``r_wh`` and housing → ambient ``r_ha`` (K/W), time constants ``tau_w`` and ``tau_h`` (s), the
    winding's limit temperature ``limit`` (K), its resistance at 25 °C ``resistance`` (Ω) and temperature
    coefficient ``alpha`` (1/K), the torque constant ``kt`` (N·m/A, at 25 °C), the speed-dependent ``loss_torque``
    (N·m, 0 where not given) and k_t's temperature coefficient ``magnet`` β (1/K, ≤ 0; not given:
    :data:`MAGNET_COEFFICIENT` for every motor); ``given``: which motors have the whole model."""

    r_wh: NDArray[np.float64]
    r_ha: NDArray[np.float64]
    tau_w: NDArray[np.float64]
    tau_h: NDArray[np.float64]
    limit: NDArray[np.float64]
    resistance: NDArray[np.float64]
    alpha: NDArray[np.float64]
    kt: NDArray[np.float64]
    loss_torque: NDArray[np.float64]
    magnet: NDArray[np.float64] = field(default=None)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.magnet is None:
            object.__setattr__(self, "magnet", np.full(len(self.r_wh), MAGNET_COEFFICIENT))

    @property
    def given(self) -> NDArray[np.bool_]:
        return np.isfinite(self.r_wh + self.r_ha + self.tau_w + self.tau_h + self.limit + self.resistance + self.kt)

    @classmethod
    def of(cls, motors: pd.DataFrame) -> ThermalData:
        """The thermal data of a motor catalog read by :func:`~mechatron.drives.catalogs.read_catalog`."""
        return cls(*(catalog_column(motors, name) for name in (*THERMAL_COLUMNS, "resistance")),
                   catalog_column(motors, "temperature_coefficient", ALPHA_COPPER),
                   catalog_column(motors, "torque_constant"), catalog_column(motors, "loss_torque", 0.0),
                   catalog_column(motors, "torque_constant_coefficient", MAGNET_COEFFICIENT))

    def allowed_rise(self, ambient: float) -> NDArray[np.float64]:
        """T_max − T_a (K) of every motor: the rise the winding may take at the ambient ``ambient`` (K)."""
        return self.limit - ambient

    def mean_bound(self, m: ArrayLike, rms: ArrayLike, mean_speed: ArrayLike, ambient: float) -> NDArray[np.float64]:
        """(R_wh + R_ha)(R(T_a) T_rms²/k_t(T_a)² + T_f ⟨|n|⟩) (K): the mean winding rise of motor ``m`` at the RMS
        torque ``rms`` (N·m) and mean speed ``mean_speed`` (rad/s), the resistance and the torque constant at the
        ambient (k_t(T_a) = k_t₂₅ (1 + β (T_a − 25 °C))), a lower bound of its highest rise (module docstring;
        arrays broadcast)."""
        r_amb = self.resistance[m] * (1 + self.alpha[m] * (ambient - REFERENCE))
        return (self.r_wh[m] + self.r_ha[m]) * (r_amb * magnet_scale(self.magnet[m], ambient, 0.0)
                                                * (np.asarray(rms) / self.kt[m]) ** 2
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


def cycle_states(t: NDArray[np.float64], current_sq: NDArray[np.float64], speed_loss: NDArray[np.float64],
                 parameters: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(θ_w, θ_h), each (R, N − 1), at the start of every interval of the periodic steady state, and the housing's
    trapezoidal time mean ⟨θ_h⟩ (R,) (K), of R rows: the N ≥ 2 samples ``t`` (s), the squared current ``current_sq``
    (A², before the row's scale s) and speed loss ``speed_loss`` (W) at the samples, (R, N) each, and ``parameters``
    (R, 7): R_wh, R_ha (K/W), τ_w, τ_h (s), R(T_a) (Ω), R₂₅ α (Ω/K) and s (the interval's I² is s times the mean
    of its ends). NaN (a whole row) where the cycle map has an eigenvalue of modulus ≥ 1: no steady state.

    Machine code where a C compiler is at hand (:mod:`~mechatron.drives.periodic_kernel`: each interval's map made
    and composed in one pass, its fixed point, the states in a second), else :func:`interval_maps` and
    :func:`tree_states` in NumPy; the two agree to rounding."""
    native = native_states(t, current_sq, speed_loss, parameters)
    if native is not None:
        return native
    r_wh, r_ha, tau_w, tau_h, r_ambient, dr_dt, scale = (parameters[:, k:k + 1] for k in range(PARAMETERS))
    h = np.diff(t)
    w, c = tree_states(interval_maps(h, 0.5 * (current_sq[:, 1:] + current_sq[:, :-1]) * scale,
                                     0.5 * (speed_loss[:, 1:] + speed_loss[:, :-1]), r_wh, r_ha, tau_w, tau_h,
                                     r_ambient, dr_dt))
    return w, c, 0.5 * ((c + np.roll(c, -1, axis=-1)) @ h) / (t[-1] - t[0])


def tree_states(maps: tuple[NDArray[np.float64], ...]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The states (θ_w, θ_h), each (..., N), at the start of each of the N intervals whose maps are ``maps`` (the six
    arrays (..., N) of :func:`interval_maps`), for the periodic steady state: the state after the last interval is
    the first one (the fixed point θ₀ = (1 − M)⁻¹ G of the cycle map M θ + G); NaN (all of a batch row) where the
    cycle map has an eigenvalue of modulus ≥ 1: no steady state (thermal runaway). In NumPy, :func:`cycle_states`'
    path without a C compiler: the maps composed pairwise up a balanced tree (the intervals padded with identities
    to a power of two), the cycle's map solved at its top, and the start states brought down the tree: O(N) work in
    log₂ N vectorised steps."""
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


def magnet_scale(magnet: ArrayLike, ambient: float, rise: ArrayLike) -> NDArray[np.float64]:
    """s = (k_t₂₅ / k_t(T))² = 1 / (1 + β (T − 25 °C))² at the magnet temperature T = T_a + ``rise`` (K; T_a
    ``ambient``, K), β = ``magnet`` (1/K): the factor of I² = (T_m / k_t₂₅)² s (the module docstring)."""
    return 1.0 / (1.0 + np.asarray(magnet) * (ambient - REFERENCE + np.asarray(rise))) ** 2


class _MagnetRoot:
    r"""The magnet iteration of one row (the module docstring): the magnet rise x with x = ⟨θ_h⟩(s(x)), from the
    row's time means ⟨I²⟩ ``q`` (A², at k_t₂₅) and ⟨P_f⟩ ``loss`` (W), its R_ha and R_wh + R_ha ``total`` (K/W),
    R(T_a) ``r_ambient`` (Ω), R₂₅ α ``dr_dt`` (Ω/K), β ``magnet`` (1/K) and ``base`` = T_a − 25 °C (K).

    The mean model, θ_w at its mean: ⟨P⟩(x) = (s q R(T_a) + ⟨P_f⟩) / (1 − s q R₂₅ α (R_wh + R_ha)), s = s(x), the
    housing's mean F(x) = R_ha ⟨P⟩(x); it gives the start (its own root) and the first step's slope. Then each
    simulation's ⟨θ_h⟩ − x narrows a bracket [lo, hi] of the root (lo: a rise found too low, at first 0; hi: one
    too high, or one where the losses ran away, at first the rise where k_t = 0), and the next x is the secant's
    (the first: a Newton step on the mean model's slope), or the bracket's middle where that leaves it."""

    def __init__(self, q: float, loss: float, r_ha: float, total: float, r_ambient: float, dr_dt: float,
                 magnet: float, base: float):
        self.q, self.loss, self.r_ha, self.total, self.r_ambient, self.dr_dt = q, loss, r_ha, total, r_ambient, dr_dt
        self.magnet, self.base = magnet, base
        self.lo, self.hi = 0.0, -1.0 / magnet - base
        self.seen = False  # whether lo is a rise simulated (else 0, not yet)
        self.runaway = True  # whether hi is a rise where the losses ran away (or k_t = 0)
        self.last: tuple[float, float] | None = None  # the last finite (x, ⟨θ_h⟩ − x)
        self.steady = False
        self.x = 0.0
        for _ in range(3):  # Newton's steps on the mean model from 0: F is convex, they rise to its root
            value, slope = self.model(self.x)
            if not (math.isfinite(value) and slope < 1.0):
                break
            self.x += (value - self.x) / (1.0 - slope)

    @property
    def scale(self) -> float:
        """s(x) (:func:`magnet_scale`)."""
        return float(magnet_scale(self.magnet, self.base + REFERENCE, self.x))

    def model(self, x: float) -> tuple[float, float]:
        """(F(x), dF/dx) of the mean model: dF/dx = R_ha q s′ (R(T_a) + ⟨P_f⟩ R₂₅ α R_tot) / (1 − s q R₂₅ α R_tot)²,
        s′ = −2 β s / (1 + β (base + x)); NaN where its losses run away."""
        ratio = 1.0 + self.magnet * (self.base + x)
        if not ratio > 0:
            return math.nan, math.nan
        s = 1.0 / ratio**2
        room = 1.0 - s * self.q * self.dr_dt * self.total
        if not room > 0:
            return math.nan, math.nan
        value = self.r_ha * (s * self.q * self.r_ambient + self.loss) / room
        slope = self.r_ha * self.q * (-2.0 * self.magnet * s / ratio) * (self.r_ambient + self.loss * self.dr_dt
                                                                          * self.total) / room**2
        return value, slope

    def update(self, mean: float) -> bool:
        """Take the housing's mean rise ``mean`` (K; NaN: the losses ran away) simulated at :attr:`x`; whether to
        simulate again (at the new :attr:`x`): not where it is within :data:`MAGNET_TOLERANCE` of x (a steady
        state) or where the bracket has closed on a runaway (none)."""
        x, g = self.x, mean - self.x
        finite = math.isfinite(g)
        if finite and abs(g) <= MAGNET_TOLERANCE:
            self.steady = True
            return False
        if finite and g >= 0:
            self.lo, self.seen = max(self.lo, x), True
        elif x <= self.hi:
            self.hi, self.runaway = x, not finite
        if self.runaway and self.hi - self.lo <= MAGNET_TOLERANCE:
            return False
        if not finite:
            step = 0.5 * (self.lo + self.hi) if self.seen else self.lo
        elif self.last is not None and g != self.last[1]:
            step = x - g * (x - self.last[0]) / (g - self.last[1])
        else:
            slope = self.model(x)[1]
            step = x + g / (1.0 - min(slope, 0.5)) if math.isfinite(slope) else x + g
        if not self.lo <= step <= self.hi or step == x:
            step = 0.5 * (self.lo + self.hi)
        self.last = (x, g) if finite else None
        self.x = step
        return True


def _steady_states(t: NDArray[np.float64], current_sq: NDArray[np.float64], speed_loss: NDArray[np.float64],
                   network: list[NDArray[np.float64]], ambient: float
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """(θ_w, θ_h) (R, N − 1) at the interval starts with the magnets at their fixed point, and whether each row has a
    steady state (R,): the rows of :func:`cycle_states` with ``network`` = (R_wh, R_ha, τ_w, τ_h, R₂₅, α, β) (R,)
    each. A row with β = 0 is simulated once (s = 1); the others take the magnet iteration (:class:`_MagnetRoot`),
    each on its own and the simulations of all of them at once, until ⟨θ_h⟩ is within :data:`MAGNET_TOLERANCE` of
    x. No steady state where the losses run away at every magnet rise left in the bracket, or where a row has not
    converged in :data:`MAGNET_ITERATIONS` simulations."""
    r_wh, r_ha, tau_w, tau_h, resistance, alpha, magnet = network
    parameters = np.empty((len(r_wh), PARAMETERS))
    parameters[:, :4] = np.column_stack([r_wh, r_ha, tau_w, tau_h])
    parameters[:, 4], parameters[:, 5], parameters[:, 6] = resistance * (1 + alpha * (ambient - REFERENCE)), \
        resistance * alpha, 1.0
    hot = np.flatnonzero(magnet)
    roots: list[_MagnetRoot] = []
    if len(hot):
        weights = np.zeros(len(t))  # trapezoidal: the time means of the intervals' I² and P_f
        weights[1:] += 0.5 * np.diff(t) / (t[-1] - t[0])
        weights[:-1] += weights[1:]
        means = (current_sq[hot] @ weights, speed_loss[hot] @ weights, r_ha[hot], r_wh[hot] + r_ha[hot],
                 parameters[hot, 4], parameters[hot, 5], magnet[hot])
        roots = [_MagnetRoot(*row, ambient - REFERENCE) for row in zip(*(x.tolist() for x in means))]
        parameters[hot, 6] = [root.scale for root in roots]
    w, c, mean = cycle_states(t, current_sq, speed_loss, parameters)
    steady = np.isfinite(mean)
    active = list(range(len(hot)))
    for _ in range(MAGNET_ITERATIONS):
        averages = mean[hot[active]].tolist()
        active = [k for k, value in zip(active, averages) if roots[k].update(value)]
        if not active:
            break
        rows = hot[active]
        parameters[rows, 6] = [roots[k].scale for k in active]
        w[rows], c[rows], mean[rows] = cycle_states(t, current_sq[rows], speed_loss[rows], parameters[rows])
    if len(hot):
        steady[hot] = [root.steady for root in roots]
    return w, c, steady


def _rows(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, network: tuple[ArrayLike, ...]
          ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], list[NDArray[np.float64]],
                     tuple[int, ...]]:
    """(t, I², P_f, network, shape): the samples as rows (R, N) of the batch's shape (...) flattened, each argument of
    ``network`` as (R,) (given as (..., 1) or a number); one sample becomes two a second apart (a constant load)."""
    t = np.asarray(t, dtype=float)
    i2, loss = np.broadcast_arrays(np.asarray(current_sq, dtype=float), np.asarray(speed_loss, dtype=float))
    if len(t) < 2:
        i2, loss, t = np.concatenate([i2, i2], axis=-1), np.concatenate([loss, loss], axis=-1), np.array([0.0, 1.0])
    shape = i2.shape[:-1]
    rows = math.prod(shape)
    columns = [np.asarray(x, dtype=float) for x in network]
    columns = [x.reshape(-1) if x.size == rows else np.broadcast_to(x, (*shape, 1)).reshape(-1) for x in columns]
    return t, i2.reshape(-1, len(t)), loss.reshape(-1, len(t)), columns, shape


def periodic_rise(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                  tau_w: ArrayLike, tau_h: ArrayLike, resistance: ArrayLike, alpha: ArrayLike,
                  ambient: float, magnet: ArrayLike = 0.0) -> NDArray[np.float64]:
    """The winding's and the housing's rise above the ambient (K), (..., N, 2), at the N samples ``t`` (s) of one
    cycle repeated for ever (its periodic steady state, the module docstring): ``current_sq`` I² = (T_m/k_t₂₅)² (A²,
    k_t at 25 °C) and ``speed_loss`` (W) at the samples (..., N), the network of each row (..., 1): thermal
    resistances (K/W), time constants (s), R₂₅ (Ω), α (1/K) and ``magnet`` β ≤ 0, k_t's temperature coefficient
    (1/K; 0: k_t constant); ``ambient`` T_a (K). The loss is constant over each interval, the mean of its ends. NaN (a
    whole row) where there is no steady state (the losses run away)."""
    samples = len(np.asarray(t))
    t, i2, loss, network, shape = _rows(t, current_sq, speed_loss, (r_wh, r_ha, tau_w, tau_h, resistance, alpha,
                                                                   magnet))
    w, c, steady = _steady_states(t, i2, loss, network, ambient)
    w[~steady], c[~steady] = np.nan, np.nan
    # the states at the start of every interval; the last sample's is the first's
    rise = np.stack([np.concatenate([w, w[:, :1]], axis=-1), np.concatenate([c, c[:, :1]], axis=-1)], axis=-1)
    return rise[:, :samples, :].reshape(*shape, samples, 2)


def highest_rise(t: ArrayLike, current_sq: ArrayLike, speed_loss: ArrayLike, r_wh: ArrayLike, r_ha: ArrayLike,
                 tau_w: ArrayLike, tau_h: ArrayLike, resistance: ArrayLike, alpha: ArrayLike, ambient: float,
                 limit: ArrayLike, magnet: ArrayLike = 0.0) -> NDArray[np.float64]:
    """The winding's highest rise above the ambient (K) over the periodic steady state, max_k θ_w(t_k) (at least
    0), of every row of a batch — vectorised over the rows: the arguments of :func:`periodic_rise` (rows (..., N),
    networks (..., 1)) and each row's winding limit temperature ``limit`` T_max (K, (..., 1)). Where there is no
    steady state (the losses run away) the highest rise with the resistance held at R(T_max) = R₂₅ (1 + α (T_max −
    25 °C)) and k_t at k_t(T_max) instead: finite, and above the allowed rise T_max − T_a (the check's value of a
    winding that cannot stay below its limit; the module docstring)."""
    t, i2, loss, network, shape = _rows(t, current_sq, speed_loss, (r_wh, r_ha, tau_w, tau_h, resistance, alpha,
                                                                   magnet, limit))
    w, _, steady = _steady_states(t, i2, loss, network[:7], ambient)
    top = np.max(w, axis=-1, initial=0.0)
    held = ~steady
    if held.any():
        r_wh, r_ha, tau_w, tau_h, resistance, alpha, magnet, limit = (x[held] for x in network)
        parameters = np.column_stack([r_wh, r_ha, tau_w, tau_h, resistance * (1 + alpha * (limit - REFERENCE)),
                                      np.zeros(len(r_wh)), magnet_scale(magnet, ambient, limit - ambient)])
        w, _, _ = cycle_states(t, i2[held], loss[held], parameters)
        top[held] = np.max(w, axis=-1, initial=0.0)
    return top.reshape(shape)


def winding_temperature(t: ArrayLike, torque: ArrayLike, speed: ArrayLike, thermal: ThermalData, motor: int,
                        ambient: float = DEFAULT_AMBIENT) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(T_w, T_h): the winding's and the housing's temperature (K) at the samples ``t`` (s) of a cycle repeated for
    ever, for the motor torque ``torque`` (N·m) and speed ``speed`` (rad/s) of motor ``motor`` of ``thermal``, at
    the ambient ``ambient`` (K), the magnets at their fixed point; inf where there is no steady state."""
    i2 = (np.asarray(torque, dtype=float) / thermal.kt[motor]) ** 2
    loss = thermal.loss_torque[motor] * np.abs(np.asarray(speed, dtype=float))
    rise = periodic_rise(t, i2[None, :], loss[None, :], *(x[motor] for x in (
        thermal.r_wh, thermal.r_ha, thermal.tau_w, thermal.tau_h, thermal.resistance, thermal.alpha)), ambient,
        thermal.magnet[motor])[0]
    rise = np.where(np.isnan(rise), np.inf, rise)
    return ambient + rise[:, 0], ambient + rise[:, 1]


@dataclass(frozen=True)
class DutyType:
    """The IEC 60034-1 duty type of a motor's cycle (:func:`duty_type`): ``kind`` (``S1`` … ``S9``), the cyclic
    duration factor ``factor`` x (S3 … S6: the time energised — starting, under load, braking — over the cycle, the
    no-load running of S6 left out [IEC 60034-1, 4.2.3–4.2.6]; 1 for the others), why in words (``reason``) and
    the standard's clause defining it (``clause``)."""

    kind: str
    factor: float
    reason: str
    clause: str

    def __str__(self) -> str:
        """``S1``, ``S3 25 %``, ``S9``: the cyclic duration factor where the type has one."""
        return f"{self.kind} {100 * self.factor:.0f} %" if self.kind in ("S3", "S4", "S5", "S6") else self.kind


def duty_type(duty: JointDuty, speed: ArrayLike | None = None, torque: ArrayLike | None = None) -> DutyType:
    """The IEC 60034-1 duty type of a motor on the joint's task repeated for ever (the module docstring), from the
    motor's ``speed`` n (rad/s) and ``torque`` T (N·m) at the task's samples (default: the joint's own) and the
    joint's acceleration: a label for the report (the thermal check simulates the cycle itself, whatever its type).
    The samples are at rest de-energised where |T| and |n| are within :data:`DUTY_TOLERANCE` of their largest of the
    cycle of zero, starting or braking where |ω̇| is above that fraction of its largest (braking: ω̇ against ω;
    electric where the motor's torque is against its speed, T n < 0), running elsewhere — at no load where |T| is
    within it of zero (holding a load at standstill is running at that load, at zero speed), else under load, a
    constant load where |T| and |n| stay within a band of that fraction of their largest."""
    n = np.asarray(duty.speed if speed is None else speed, dtype=float)
    load = np.asarray(duty.torque if torque is None else torque, dtype=float)
    acceleration = duty.acceleration
    tol = DUTY_TOLERANCE
    top_load, top_speed, top_acceleration = (float(np.abs(x).max(initial=0.0)) for x in (load, n, acceleration))
    if top_load == 0:
        return DutyType("S1", 1.0, "no load over the whole cycle (a constant load of zero)", "4.2.1")
    unloaded = np.abs(load) <= tol * top_load
    rest = unloaded & (np.abs(n) <= tol * top_speed)  # at standstill and de-energised
    changing = np.abs(acceleration) > tol * top_acceleration
    braking = changing & (acceleration * duty.speed < 0)
    running = ~rest & ~changing
    loaded = running & ~unloaded
    step = np.diff(duty.t)

    def share(mask: NDArray[np.bool_]) -> float:
        """The time of the intervals with both ends in ``mask`` over the cycle's."""
        return float(step[mask[1:] & mask[:-1]].sum() / duty.duration) if duty.duration > 0 else 0.0

    resting, idle = share(rest), share(running & unloaded)
    moves = bool(changing.any())
    electric = bool(np.any(braking & (load * n < 0) & ~unloaded))
    spreads = {what: float(np.ptp(np.abs(x[loaded])) / top) if loaded.any() and top > 0 else 0.0
               for what, x, top in (("load", load, top_load), ("speed", n, top_speed))}
    varying = [f"the {what} spans {100 * spread:.0f} % of its largest magnitude" for what, spread in spreads.items()
               if spread > tol]
    if varying:
        return DutyType("S9", 1.0, f"load and speed vary over the cycle: under load, outside starting and braking, "
                        f"{' and '.join(varying)} (mechatron counts a band of {100 * tol:.0f} % as constant)", "4.2.9")
    if idle > 0 and (resting > 0 or moves):
        return DutyType("S9", 1.0, f"no-load running with {'rests' if resting > 0 else 'starting and braking'}: "
                        "no periodic duty type of S1 … S8 has both", "4.2.9")
    if idle > 0:
        return DutyType("S6", 1.0 - idle, "identical cycles of a constant load and no-load running, no rest", "4.2.6")
    if not moves:
        if resting > 0:
            return DutyType("S3", 1.0 - resting, "identical cycles of a constant load and a rest de-energised, no "
                            "starting or braking", "4.2.3")
        return DutyType("S1", 1.0, "a constant load at a constant speed the whole cycle", "4.2.1")
    if resting > 0:
        if electric:
            return DutyType("S5", 1.0 - resting, "identical cycles of starting, a constant load, electric braking (the "
                            "motor's torque against its speed) and a rest de-energised", "4.2.5")
        return DutyType("S4", 1.0 - resting, "identical cycles of starting, a constant load and a rest de-energised; "
                        "braked by the load, not electrically", "4.2.4")
    if electric:
        return DutyType("S7", 1.0, "identical cycles of starting, a constant load and electric braking, no rest",
                        "4.2.7")
    return DutyType("S9", 1.0, "speed changes braked by the load, not electrically, and no rest: none of S1 … S8",
                    "4.2.9")

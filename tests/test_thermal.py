"""The two-node motor thermal model (mechatron.drives.thermal, issue 25 item 1) against independent references: the
closed form of a constant loss step from cold (the two exponentials of the 2 × 2 network), the periodic steady state
of a square-wave loss (each mode's own geometric sum), the steady state with the resistance rising with temperature,
and a time stepping of this test's own (RK4 on the network's equations, the cycle's affine map found from three
runs); a batch of pairs simulated at once as each alone; the mean-rise bound the screening uses; the IEC 60034-1
duty type; the sizing deciding by the winding's temperature where RMS would decide the other way; bad thermal
columns refused naming file, row and field; a motor without them checked by RMS, the report saying so; --ambient
and the study option."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from mechatron.cli import main
from mechatron.drives.catalogs import read_catalog
from mechatron.drives.checks import DriveLimits
from mechatron.drives.duty import JointDuty
from mechatron.drives.joint import size_joint
from mechatron.drives.thermal import (
    ALPHA_COPPER,
    DEFAULT_AMBIENT,
    ThermalData,
    duty_text,
    duty_type,
    highest_rise,
    periodic_rise,
    winding_temperature,
)
from mechatron.errors import InputError

ZERO = 273.15
AMBIENT = ZERO + 40.0
#: A network: R_wh, R_ha (K/W), τ_w, τ_h (s).
NETWORK = (0.8, 1.7, 25.0, 900.0)


def modes(r_wh: float, r_ha: float, tau_w: float, tau_h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(λ, V, β) of the network dθ/dt = A θ + (P/C_w, 0): the eigenvalues λ of A = [[−a, a], [b, −(b + c)]]
    (a = 1/τ_w, b = 1/(R_wh C_h), c = 1/τ_h: trace −(a + b + c), determinant a c), their eigenvectors (columns,
    first component 1: v = (1, (a + λ)/a)) and the input per watt in their basis (V β = (1/C_w, 0))."""
    c_w, c_h = tau_w / r_wh, tau_h / r_ha
    a, b, c = 1 / tau_w, 1 / (r_wh * c_h), 1 / tau_h
    s, d = a + b + c, a * c
    lam = np.array([(-s - math.sqrt(s * s - 4 * d)) / 2, (-s + math.sqrt(s * s - 4 * d)) / 2])
    V = np.array([[1.0, 1.0], [(a + lam[0]) / a, (a + lam[1]) / a]])
    beta = np.linalg.solve(V, [1 / c_w, 0.0])
    return lam, V, beta


def rise(t, current, loss=None, network=NETWORK, resistance=1.0, alpha=0.0, ambient=AMBIENT):
    """The model's winding and housing rise (K) at the samples, one motor."""
    current = np.asarray(current, dtype=float)
    loss = np.zeros_like(current) if loss is None else np.asarray(loss, dtype=float)
    return periodic_rise(t, (current**2)[None], loss[None], *network, resistance, alpha, ambient)[0]


# ------------------------------------------------------------------------------------------- closed forms
def test_a_constant_loss_step_from_cold_is_the_two_exponentials():
    """P = 40 W from t = 0, the motor at the ambient before (the cycle ends with 10⁶ s at rest: e^{λ·10⁶} = 0):
    θ_w(t) = P(R_wh + R_ha) + K₁ e^{λ₁t} + K₂ e^{λ₂t} with K₁ + K₂ = −θ_w(∞) and λ₁K₁ + λ₂K₂ = P/C_w, at unevenly
    spaced samples, to 1e-6 K."""
    r_wh, r_ha, tau_w, tau_h = NETWORK
    power = 40.0
    rng = np.random.default_rng(1)
    on = np.sort(np.concatenate([[0.0, 3000.0], rng.uniform(0, 3000, 400)]))
    t = np.concatenate([on, [3000 + 1e-9, 1e6]])
    current = np.concatenate([np.full(len(on), math.sqrt(power)), [0.0, 0.0]])  # R₂₅ = 1 Ω, α = 0
    model = rise(t, current)
    lam, V, beta = modes(*NETWORK)
    final = power * (r_wh + r_ha)
    k1 = (power * r_wh / tau_w + lam[1] * final) / (lam[0] - lam[1])
    k2 = -final - k1
    expected = final + k1 * np.exp(lam[0] * on) + k2 * np.exp(lam[1] * on)
    assert np.max(np.abs(model[: len(on), 0] - expected)) < 1e-6
    assert model[0, 0] == pytest.approx(0.0, abs=1e-9) and expected[-1] > 0.9 * final  # it heats up to near P R


def square_wave(power: float, t_on: float, t_off: float, t: np.ndarray) -> np.ndarray:
    """θ_w at the times t ∈ [0, T] of the periodic steady state of the loss P on [0, t_on), 0 on [t_on, T): each
    mode z' = λz + βP has z(0) = βP (e^{λt_on} − 1)/λ · e^{λt_off} / (1 − e^{λT}); θ_w = z₁ + z₂."""
    lam, V, beta = modes(*NETWORK)
    out = np.zeros_like(t)
    for k in range(2):
        lk, bk = lam[k], beta[k] * power
        z0 = bk * np.expm1(lk * t_on) / lk * np.exp(lk * t_off) / (1 - np.exp(lk * (t_on + t_off)))
        z_on = np.exp(lk * np.minimum(t, t_on)) * z0 + bk * np.expm1(lk * np.minimum(t, t_on)) / lk
        out += V[0, k] * np.where(t <= t_on, z_on, np.exp(lk * (t - t_on)) * z_on)
    return out


@pytest.mark.parametrize("t_on, t_off", [(10.0, 30.0), (200.0, 1000.0), (2.0, 0.5)])
def test_a_square_wave_loss_at_its_periodic_steady_state(t_on, t_off):
    """The loss P = 60 W for t_on, then nothing for t_off, repeated for ever: the model's winding rise at every
    sample equals the modes' geometric sums to 1e-6 K (the loss switches within 1e-9 s between two samples)."""
    power = 60.0
    on = np.linspace(0, t_on, 301)
    off = np.linspace(t_on + 1e-9, t_on + t_off, 301)
    t = np.concatenate([on, off])
    current = np.concatenate([np.full(301, math.sqrt(power)), np.zeros(301)])
    model = rise(t, current)[:, 0]
    expected = square_wave(power, t_on, t_off, t)
    assert np.max(np.abs(model - expected)) < 1e-6
    assert np.argmax(model) in (300, 301)  # the winding is hottest as the loss stops


def test_the_resistance_rising_with_temperature_at_a_constant_current():
    """A constant current I: the steady state θ_w = I² R_a R_tot / (1 − I² R₂₅ α R_tot), R_a = R₂₅(1 + α(T_a −
    25 °C)), to 1e-6 K — 1/(1 − I² R₂₅ α R_tot) = 1.21 times the rise at a constant resistance R_a; and the loss
    outgrowing the cooling (I² R₂₅ α R_tot ≥ 1) has no steady state."""
    r_wh, r_ha, *_ = NETWORK
    total, r25, current = r_wh + r_ha, 0.5, 6.0
    t = np.linspace(0.0, 7.0, 50)
    r_ambient = r25 * (1 + ALPHA_COPPER * (AMBIENT - ZERO - 25))
    model = rise(t, np.full(50, current), resistance=r25, alpha=ALPHA_COPPER)
    expected = current**2 * r_ambient * total / (1 - current**2 * r25 * ALPHA_COPPER * total)
    assert np.max(np.abs(model[:, 0] - expected)) < 1e-6
    assert np.max(np.abs(model[:, 1] - expected * r_ha / total)) < 1e-6  # the housing: R_ha of the same heat
    constant = rise(t, np.full(50, current), resistance=r_ambient, alpha=0.0)[:, 0]
    assert np.allclose(constant, current**2 * r_ambient * total, rtol=1e-12)
    assert expected / constant[0] == pytest.approx(1.2129, abs=1e-4)
    runaway = math.sqrt(1.01 / (r25 * ALPHA_COPPER * total))
    assert np.isnan(rise(t, np.full(50, runaway), resistance=r25, alpha=ALPHA_COPPER)).all()


# ------------------------------------------------------------------------------------- own time stepping
def rk4_cycle(t, current, loss, theta0, network=NETWORK, r25=1.0, alpha=ALPHA_COPPER, ambient=AMBIENT, sub=20):
    """This test's own integration of the network over one cycle from θ₀: classic RK4, ``sub`` steps per interval,
    the interval's I² and speed loss the means of its ends (the model's statement), P = I² R₂₅ (1 + α (T_w −
    25 °C)) + loss. The states at the samples."""
    r_wh, r_ha, tau_w, tau_h = network
    c_w, c_h = tau_w / r_wh, tau_h / r_ha
    i2, loss = np.asarray(current) ** 2, np.asarray(loss)

    def f(x, q, p_f):
        power = q * r25 * (1 + alpha * (ambient + x[0] - ZERO - 25)) + p_f
        flow = (x[0] - x[1]) / r_wh
        return np.array([(power - flow) / c_w, (flow - x[1] / r_ha) / c_h])

    x, out = np.array(theta0, dtype=float), [np.array(theta0, dtype=float)]
    for k in range(len(t) - 1):
        h = (t[k + 1] - t[k]) / sub
        q, p_f = 0.5 * (i2[k] + i2[k + 1]), 0.5 * (loss[k] + loss[k + 1])
        for _ in range(sub):
            k1 = f(x, q, p_f)
            k2 = f(x + h / 2 * k1, q, p_f)
            k3 = f(x + h / 2 * k2, q, p_f)
            k4 = f(x + h * k3, q, p_f)
            x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(x.copy())
    return np.array(out)


def stepped_periodic(t, current, loss, sub=20, **kw):
    """The periodic steady state by this test's stepping: the cycle map θ₀ ↦ θ(T) is affine (P is linear in θ_w),
    so three runs (from 0, e₁, e₂) give M and G, the fixed point solves (1 − M) θ₀ = G, and a fourth run from it
    gives the states."""
    g = rk4_cycle(t, current, loss, [0.0, 0.0], sub=sub, **kw)[-1]
    m = np.column_stack([rk4_cycle(t, current, loss, e, sub=sub, **kw)[-1] - g for e in np.eye(2)])
    theta0 = np.linalg.solve(np.eye(2) - m, g)
    return rk4_cycle(t, current, loss, theta0, sub=sub, **kw)


def test_the_model_against_an_own_time_stepping_with_resistance_and_speed_losses():
    """A robot-like cycle: current and speed loss varying smoothly and a rest, the resistance rising with
    temperature: the model equals the RK4 stepping (converged: 20 and 40 steps per interval agree) to 1e-6 K."""
    t = np.concatenate([np.linspace(0, 4, 161), np.linspace(4.05, 6, 40)])
    current = np.where(t < 4, 9 * np.sin(np.pi * t / 4) ** 2 + 2 * np.sin(3 * t), 1.5)
    loss = np.where(t < 4, 12 * np.abs(np.sin(np.pi * t / 4)), 0.0)
    network = (0.8, 1.7, 5.0, 60.0)
    stepped = stepped_periodic(t, current, loss, network=network)
    finer = stepped_periodic(t, current, loss, sub=40, network=network)
    assert np.max(np.abs(stepped - finer)) < 1e-8
    model = periodic_rise(t, (current**2)[None], loss[None], *network, 1.0, ALPHA_COPPER, AMBIENT)[0]
    assert np.max(np.abs(model - stepped)) < 1e-6
    assert 20 < model[:, 0].max() < 200


def random_rows(count: int, samples: int, seed: int) -> tuple[np.ndarray, ...]:
    """A batch of ``count`` motors on a cycle of ``samples`` uneven samples: (t, I², speed loss, R_wh, R_ha, τ_w,
    τ_h, R₂₅, α, T_max), the networks and limits as columns (count, 1)."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(np.concatenate([[0.0], rng.uniform(0.01, 0.4, samples - 1)]))
    i2 = rng.uniform(0.0, 3.0, (count, samples)) ** 2
    loss = rng.uniform(0.0, 5.0, (count, samples)) * (rng.uniform(size=(count, 1)) < 0.7)
    network = [rng.uniform(lo, hi, (count, 1)) for lo, hi in ((0.2, 1.5), (0.5, 3.0), (2.0, 40.0), (60.0, 900.0),
                                                               (0.5, 3.0), (0.0, 0.006), (390.0, 450.0))]
    return (t, i2, loss, *network)


def test_the_batched_winding_simulation_equals_each_pair_alone():
    """One simulation of a batch of pairs (thermal.highest_rise, vectorised over the rows) gives each row's highest
    winding rise as the single-row simulation does (1e-12), the first row also as this test's RK4 stepping (1e-6
    K); a row whose losses run away (I² R₂₅ α R_tot ≥ 1: no steady state) takes the rise at the resistance held
    at R(T_max), above the allowed rise."""
    t, i2, loss, r_wh, r_ha, tau_w, tau_h, r25, alpha, limit = random_rows(9, 37, seed=3)
    i2[4] = 400.0  # 20 A: a runaway
    alpha[4] = ALPHA_COPPER
    batched = highest_rise(t, i2, loss, r_wh, r_ha, tau_w, tau_h, r25, alpha, AMBIENT, limit)
    for k in range(len(i2)):
        one = periodic_rise(t, i2[k:k + 1], loss[k:k + 1], r_wh[k], r_ha[k], tau_w[k], tau_h[k], r25[k],
                            alpha[k], AMBIENT)[0, :, 0]
        if k == 4:
            assert np.isnan(one).all()
            held = r25[k] * (1 + alpha[k] * (limit[k] - ZERO - 25))
            one = periodic_rise(t, i2[k:k + 1], loss[k:k + 1], r_wh[k], r_ha[k], tau_w[k], tau_h[k], held, 0.0,
                                AMBIENT)[0, :, 0]
            assert batched[k] > limit[k, 0] - AMBIENT
        assert batched[k] == pytest.approx(one.max(), rel=1e-12)
    network = (r_wh[0, 0], r_ha[0, 0], tau_w[0, 0], tau_h[0, 0])
    stepped = stepped_periodic(t, np.sqrt(i2[0]), loss[0], network=network, r25=r25[0, 0], alpha=alpha[0, 0])
    assert batched[0] == pytest.approx(stepped[:, 0].max(), abs=1e-6)
    # the rows in another company, or alone, give the same numbers
    order = np.arange(len(i2))[::-1]
    again = highest_rise(t, i2[order], loss[order], *(x[order] for x in (r_wh, r_ha, tau_w, tau_h, r25, alpha)),
                         AMBIENT, limit[order])
    assert again[::-1] == pytest.approx(batched, rel=1e-12)


@pytest.mark.parametrize("samples", [1, 2, 3, 37, 1114])
def test_the_compiled_periodic_state_equals_the_numpy_tree(samples):
    """The periodic steady state in machine code (periodic_kernel: the cycle's map composed interval by interval)
    equals the NumPy tree of pairwise compositions (thermal.tree_states) to 1e-11 relative on random batches of
    uneven cycles — the same fixed point, summed in another order — and gives NaN on exactly the same rows: a
    runaway (I² R₂₅ α R_tot ≥ 1) and a row with an infinite loss. Without a C compiler the tree is the path; the
    kernel must be there by default (only MECHATRON_COMPILE=0 switches it off)."""
    import os

    from mechatron.drives.periodic_kernel import available, native_states
    from mechatron.drives.thermal import REFERENCE, interval_maps, tree_states

    if os.environ.get("MECHATRON_COMPILE") == "0":
        assert not available()
        return
    assert available()
    t, i2, loss, r_wh, r_ha, tau_w, tau_h, r25, alpha, _ = random_rows(8, samples + 1, seed=samples)
    i2[2] = 400.0  # a runaway
    alpha[2] = ALPHA_COPPER
    loss[5, -1] = np.inf
    maps = interval_maps(np.diff(t), 0.5 * (i2[:, 1:] + i2[:, :-1]), 0.5 * (loss[:, 1:] + loss[:, :-1]), r_wh, r_ha,
                         tau_w, tau_h, r25 * (1 + alpha * (AMBIENT - REFERENCE)), r25 * alpha)
    for tree, native in zip(tree_states(maps), native_states(maps)):
        assert native.shape == tree.shape == (8, samples)
        np.testing.assert_array_equal(np.isnan(native), np.isnan(tree))
        assert np.isnan(tree[2]).all() and np.isnan(tree[5]).all() and np.isfinite(np.delete(tree, [2, 5], 0)).all()
        np.testing.assert_allclose(native, tree, rtol=1e-11, atol=0.0)
    one = native_states(tuple(m[0] for m in maps))  # one row as a 1-d array
    np.testing.assert_allclose(one[0], tree_states(tuple(m[0] for m in maps))[0], rtol=1e-11, atol=0.0)


def test_the_sizing_simulates_a_block_of_pairs_as_each_alone():
    """PairChecks.winding of a block of random motor × gearbox pairs of the shipped catalogs on a robot-like duty
    equals each pair simulated alone by periodic_rise with this test's own motor torque T_m = (J_m + J_c) u ω̇ +
    τ*/u (τ* = τ/η motoring, τ η braking) and current I = T_m/k_t (1e-12)."""
    from mechatron.drives.catalogs import default_catalog
    from mechatron.drives.checks import PairChecks
    from mechatron.drives.converters import converters_for

    t = np.linspace(0.0, 3.0, 301)
    speed = 1.5 * np.sin(2 * np.pi * t / 3)
    acceleration = np.pi * np.cos(2 * np.pi * t / 3)
    torque = 20 * acceleration / np.pi + 15 * np.cos(t) + 3
    duty = JointDuty("q1", "revolute", t, speed, acceleration, torque, 15 * np.cos(t) + 3, 0.5, 1.0)
    motors, conv = default_catalog("motors"), converters_for(duty, default_catalog("gearboxes"))
    rng = np.random.default_rng(5)
    m, c = rng.integers(0, len(motors), 12), rng.integers(0, len(conv), 12)
    block = PairChecks(duty, motors, conv).winding(m, c)
    th, runaways = ThermalData.of(motors), 0
    for k in range(len(m)):
        i, g = m[k], c[k]
        u, eta = conv.ratio[g], conv.efficiency[g]
        load = np.where(torque * speed >= 0, torque / eta, torque * eta) / u
        current = ((motors["rotor_inertia"].iloc[i] + conv.inertia[g]) * u * acceleration + load) / th.kt[i]
        r25, alpha = th.resistance[i], th.alpha[i]
        alone = periodic_rise(t, current[None] ** 2, th.loss_torque[i] * np.abs(u * speed)[None], th.r_wh[i],
                              th.r_ha[i], th.tau_w[i], th.tau_h[i], r25, alpha, DEFAULT_AMBIENT)
        if np.isnan(alone).all():  # a runaway: the rise at the resistance held at R(T_max)
            runaways += 1
            alone = periodic_rise(t, current[None] ** 2, th.loss_torque[i] * np.abs(u * speed)[None], th.r_wh[i],
                                  th.r_ha[i], th.tau_w[i], th.tau_h[i], r25 * (1 + alpha * (th.limit[i] - ZERO - 25)),
                                  0.0, DEFAULT_AMBIENT)
        assert block[k] == pytest.approx(alone[0, :, 0].max(), rel=1e-12)
        assert PairChecks(duty, motors, conv).winding([i], [g])[0] == pytest.approx(block[k], rel=1e-12)
    assert 0 < runaways < len(m)  # both kinds in the block


def test_a_cold_start_settles_on_the_periodic_state():
    """Stepped from the ambient, cycle after cycle, the winding settles on the model's periodic state (a short
    housing constant, so that 300 cycles suffice)."""
    t = np.linspace(0.0, 2.0, 41)
    current = np.where(t < 1.0, 6.0, 0.5)
    network = (0.5, 1.0, 1.0, 5.0)
    x = np.zeros(2)
    for _ in range(300):
        states = rk4_cycle(t, current, np.zeros_like(t), x, network=network, sub=5)
        x = states[-1]
    model = periodic_rise(t, (current**2)[None], np.zeros((1, len(t))), *network, 1.0, ALPHA_COPPER, AMBIENT)[0]
    assert np.max(np.abs(model - states)) < 1e-6


def test_the_mean_rise_bounds_the_highest_rise_from_below():
    """(R_wh + R_ha)(R(T_a) ⟨I²⟩ + ⟨P_f⟩) ≤ max θ_w for random cycles (the screening's bound), and equals the time
    mean of θ_w at a constant resistance."""
    rng = np.random.default_rng(7)
    thermal = ThermalData(*(np.array([x]) for x in (*NETWORK, 428.15, 0.7, ALPHA_COPPER, 0.9, 0.02)))
    for _ in range(20):
        t = np.cumsum(rng.uniform(0.01, 0.5, 200))
        torque, speed = rng.normal(0, 3, 200), rng.normal(0, 100, 200)
        w = np.zeros(200)
        w[1:] += np.diff(t) / 2
        w[:-1] += np.diff(t) / 2
        w /= t[-1] - t[0]
        rms, mean_speed = math.sqrt(w @ torque**2), w @ np.abs(speed)
        bound = float(thermal.mean_bound(0, rms, mean_speed, AMBIENT))
        hottest = winding_temperature(t, torque, speed, thermal, 0, AMBIENT)[0].max() - AMBIENT
        assert bound <= hottest * (1 + 1e-12)
    flat = ThermalData(*(np.array([x]) for x in (*NETWORK, 428.15, 0.7, 0.0, 0.9, 0.0)))
    t = np.linspace(0, 10, 2001)
    torque = 3 * np.sin(t) ** 2
    w = np.full(2001, t[1] - t[0]) / 10
    w[[0, -1]] /= 2
    mean = np.trapezoid(winding_temperature(t, torque, 0 * t, flat, 0, AMBIENT)[0] - AMBIENT, t) / 10
    assert flat.mean_bound(0, math.sqrt(w @ torque**2), 0.0, AMBIENT) == pytest.approx(mean, rel=1e-5)


# --------------------------------------------------------------------------------------------- duty type
def _duty(t, torque, speed=None, moving=None, acceleration=None):
    t = np.asarray(t, dtype=float)
    speed = np.zeros_like(t) if speed is None else np.asarray(speed, dtype=float)
    acceleration = np.zeros_like(t) if acceleration is None else acceleration
    torque = np.asarray(torque, dtype=float)
    return JointDuty("q1", "revolute", t, speed, acceleration, torque, torque.copy(), 1e-4, 0.0, moving)


def test_the_duty_type_from_the_moves_and_dwells():
    t = np.array([0.0, 1.0, 2.0, 3.0, 7.0])
    moving = np.array([True, True, True, False])
    assert duty_type(_duty(t, [1, 2, 3, 1, 1])) == ("S1", 1.0)
    assert duty_type(_duty(t, [1, 2, 3, 0, 0], moving=moving)) == ("S3", 3 / 7)
    kind, factor = duty_type(_duty(t, [1, 2, 3, 1, 1], moving=moving))  # holds 1 N·m at rest: energised
    assert (kind, factor) == ("S6", 3 / 7) and duty_text(kind, factor) == "S6 43 %" and duty_text("S1", 1) == "S1"


# ------------------------------------------------------------------------------------------------ sizing
#: Two motors checked by their winding (R₂₅ = 1 Ω, k_t = 1 N·m/A: I = T_m): A light, rated 4.5 N·m S1 but able
#: to carry 5.04 N·m continuously at standstill by its network (R_tot = 3 K/W); B heavier, with twice the cooling.
MOTORS = pd.DataFrame([
    {"key": "A", "rated_torque": 4.5, "peak_torque": 20.0, "rated_speed": 300.0, "max_speed": 500.0,
     "rotor_inertia": 1e-4, "torque_constant": 1.0, "resistance": 1.0, "rth_winding_housing": 1.0,
     "rth_housing_ambient": 2.0, "tau_winding": 20.0, "tau_housing": 600.0, "max_winding_temperature": 428.15,
     "mass": 1.0, "price": 100.0},
    {"key": "B", "rated_torque": 7.5, "peak_torque": 30.0, "rated_speed": 300.0, "max_speed": 500.0,
     "rotor_inertia": 2e-4, "torque_constant": 1.0, "resistance": 1.0, "rth_winding_housing": 0.4,
     "rth_housing_ambient": 0.8, "tau_winding": 20.0, "tau_housing": 600.0, "max_winding_temperature": 428.15,
     "mass": 2.0, "price": 200.0},
])
THERMAL = ["rth_winding_housing", "rth_housing_ambient", "tau_winding", "tau_housing", "max_winding_temperature"]


def burst(torque: float, t_on: float, t_off: float, dt: float = 0.25) -> JointDuty:
    """A joint at rest pushing ``torque`` for t_on, then nothing for t_off (the step within 1e-9 s)."""
    on = np.arange(0, t_on + dt / 2, dt)
    off = np.linspace(t_on + 1e-9, t_on + t_off, int(t_off / dt) + 1)
    t = np.concatenate([on, off])
    return _duty(t, np.where(t <= t_on, torque, 0.0))


def reference_rise(duty: JointDuty, row: dict) -> float:
    """The winding's highest rise of motor ``row`` on ``duty`` (direct drive: I = τ/k_t) by the own stepping."""
    network = tuple(row[k] for k in THERMAL[:4])
    states = stepped_periodic(duty.t, duty.torque / row["torque_constant"], np.zeros_like(duty.t), sub=4,
                              network=network, r25=row["resistance"])
    return states[:, 0].max()


@pytest.mark.parametrize("case, duty, rms_pick, thermal_pick", [
    # 7 N·m for 100 s of every 300 s: RMS 4.04 N·m passes A's 4.5, but the winding (τ_w = 20 s) overheats
    ("long", burst(7.0, 100.0, 200.0), "A", "B"),
    # 8.3 N·m for 1 s of every 3 s: RMS 4.79 N·m fails A's 4.5, but the winding stays below its limit
    ("bursts", burst(8.3, 1.0, 2.0, dt=0.05), "B", "A"),
])
def test_the_sizing_decides_by_the_winding_where_rms_decides_the_other_way(case, duty, rms_pick, thermal_pick):
    rms = math.sqrt(duty.time_weights() @ duty.torque**2)
    by_rms = size_joint(duty, MOTORS.drop(columns=THERMAL), direct=True)
    assert by_rms.motor == rms_pick and (rms < 4.5) == (rms_pick == "A")
    assert by_rms.thermal()["check"] == "RMS torque" and "RMS torque" in {c.name for c in by_rms.checks}
    sized = size_joint(duty, MOTORS, direct=True)
    assert sized.motor == thermal_pick and sized.feasible
    assert "RMS torque" not in {c.name for c in sized.checks}
    # A's winding as the own stepping finds it decides: over its allowed rise (115 K) for the long push only
    row = MOTORS.iloc[0].to_dict()
    hottest = reference_rise(duty, row)
    a = size_joint(duty, MOTORS.iloc[:1].reset_index(drop=True), direct=True)
    check = next(c for c in a.checks if c.name == "winding temperature rise")
    assert check.value == pytest.approx(hottest, abs=1e-6) and check.limit == pytest.approx(115.0)
    assert a.feasible == (thermal_pick == "A") == (hottest <= 115.0)
    assert abs(hottest / 115.0 - 1) > 0.05  # a clear decision
    info = a.thermal()
    assert info["check"] == "winding temperature rise" and info["winding_max_K"] == pytest.approx(AMBIENT + hottest)
    assert info["duty_type"] == "S1"


def test_a_runaway_winding_fails_with_the_rise_at_its_limit_resistance():
    """20 A through A's winding: I² R₂₅ α R_tot = 4.7 ≥ 1, no steady state; the check takes the rise at the
    resistance held at R(155 °C), I² R(T_max) R_tot = 1808 K (finite: a margin), and the report says it runs
    away."""
    duty = burst(20.0, 5.0, 0.0)
    a = size_joint(duty, MOTORS.iloc[:1].reset_index(drop=True), direct=True)
    check = next(c for c in a.checks if c.name == "winding temperature rise")
    held = 1.0 * (1 + ALPHA_COPPER * 130.0)
    assert check.value == pytest.approx(400 * held * 3.0, abs=1e-6) and not a.feasible
    assert a.thermal()["runaway"] and "the winding runs away" in str(a)
    assert np.isinf(a.winding_temperature()[1]).all()


def test_the_ambient_derates_the_motor():
    """At 60 °C the winding may rise 95 K: the long bursts' motor B still passes with the same rise (the losses do
    not depend on the ambient but through R(T_a)), with 20 K less room."""
    duty = burst(7.0, 100.0, 200.0)
    warm = size_joint(duty, MOTORS, direct=True, limits=DriveLimits(ambient=ZERO + 60))
    check = next(c for c in warm.checks if c.name == "winding temperature rise")
    assert check.limit == pytest.approx(95.0) and warm.thermal()["ambient_K"] == pytest.approx(ZERO + 60)
    cool = size_joint(duty, MOTORS, direct=True)
    assert next(c for c in cool.checks if c.name == "winding temperature rise").limit == pytest.approx(115.0)
    with pytest.raises(InputError, match="ambient"):
        DriveLimits(ambient=ZERO + 150)


def test_a_motor_without_thermal_data_falls_back_to_rms_and_the_report_says_so():
    duty = burst(3.0, 1.0, 2.0, dt=0.1)
    plain = size_joint(duty, MOTORS.drop(columns=THERMAL), direct=True)
    text = str(plain)
    assert "thermal check: RMS torque against the S1 curve at the mean speed (the catalog gives no thermal data" \
        in text
    assert plain.as_dict()["thermal"]["check"] == "RMS torque" and plain.winding_temperature() is None
    modelled = size_joint(duty, MOTORS, direct=True)
    assert "thermal check: winding temperature, two-node model of winding and housing at 40 °C ambient" in \
        str(modelled)
    t, winding, housing = modelled.winding_temperature()
    assert np.all(winding >= housing) and np.all(housing > DEFAULT_AMBIENT)
    assert modelled.as_dict()["thermal"]["winding_max_K"] == pytest.approx(winding.max())


# -------------------------------------------------------------------------------------------- the catalog
HEADER = ("key,rated_torque,peak_torque,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2,torque_constant,"
          "resistance_ohm,rth_winding_housing_K_W,rth_housing_ambient,tau_winding_s,tau_housing_min,"
          "max_winding_temperature_degC,temperature_coefficient_percent_K")
GOOD = "M1,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,30,10,155,0.39"


def test_thermal_columns_read_in_their_units(tmp_path):
    path = tmp_path / "motors.csv"
    path.write_text(f"{HEADER}\n{GOOD}\nM2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,30,10,130,\n")
    table = read_catalog(path, "motors")
    assert table["tau_housing"].tolist() == [600.0, 600.0]
    assert table["max_winding_temperature"].tolist() == pytest.approx([428.15, 403.15])
    thermal = ThermalData.of(table)
    assert thermal.given.all() and thermal.alpha.tolist() == pytest.approx([0.0039, ALPHA_COPPER])


@pytest.mark.parametrize("row, field, message", [
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,,10,155,", "tau_winding_s", "thermal columns are given for some"),
    ("M2,1.2,3.6,3000,6000,1.5,,,,,,,,", "rth_winding_housing_K_W", "thermal columns are given for some rows"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,,0.5,1.2,30,10,155,", "resistance_ohm", "winding temperature needs"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0,1.2,30,10,155,", "rth_winding_housing_K_W", "must be > 0"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,-1.2,30,10,155,", "rth_housing_ambient", "must be > 0"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,30,0,155,", "tau_housing_min", "must be > 0"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,30,10,inf,", "max_winding_temperature_degC", "finite"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,30,10,-300,", "max_winding_temperature_degC", "between"),
    ("M2,1.2,3.6,3000,6000,1.5,0.5,2.0,0.5,1.2,nan,10,155,", "tau_winding_s", "finite"),
])
def test_bad_thermal_columns_name_file_row_and_field(tmp_path, row, field, message):
    path = tmp_path / "motors.csv"
    path.write_text(f"{HEADER}\n{GOOD}\n{row}\n")
    with pytest.raises(InputError, match=message) as info:
        read_catalog(path, "motors")
    assert (info.value.file, info.value.row, info.value.field) == (str(path), 3, field)
    assert str(info.value).count("\n") == 0 and f"motors.csv: row 3: field '{field}'" in str(info.value)


def test_a_temperature_in_celsius_needs_its_suffix(tmp_path):
    """155 in a column without a suffix is 155 K, below any winding's limit: refused, the range said in K and °C."""
    path = tmp_path / "motors.csv"
    path.write_text(HEADER.replace("max_winding_temperature_degC", "max_winding_temperature") + "\n" + GOOD + "\n")
    with pytest.raises(InputError, match=r"between 273.15 K \(0 °C\) and 773.15 K \(500 °C\), got 155"):
        read_catalog(path, "motors")


def test_the_shipped_catalogs_carry_consistent_thermal_data():
    """catalogs/servo_motors.csv and examples/data/motors.csv: every motor modelled; at its rated torque and speed,
    continuously at 40 °C, its winding reaches its limit (within the rounding of the files)."""
    from mechatron.drives.catalogs import default_catalog
    from mechatron.io.data import data_dir

    for motors in (default_catalog("motors"), read_catalog(data_dir("examples/data") / "motors.csv", "motors")):
        thermal = ThermalData.of(motors)
        assert thermal.given.all()
        for i in range(0, len(motors), 7):
            t = np.linspace(0, 1, 3)
            hottest = winding_temperature(t, np.full(3, motors["rated_torque"][i]),
                                          np.full(3, motors["rated_speed"][i]), thermal, i, AMBIENT)[0].max()
            assert hottest == pytest.approx(ZERO + 155, abs=3.0), motors["key"][i]


# ----------------------------------------------------------------------------------- command line, studies
def test_size_ambient_option(capsys):
    assert main(["size", "planar_2r", "--ambient", "60", "--single-pass", "--json"]) in (0, 1)
    joints = json.loads(capsys.readouterr().out)["joints"]
    for joint in joints:
        assert joint["thermal"]["ambient_K"] == pytest.approx(ZERO + 60)
        rise = next(c for c in joint["checks"] if c["name"] == "winding temperature rise")
        assert rise["limit"] == pytest.approx(joint["thermal"]["winding_limit_K"] - ZERO - 60)
    with pytest.raises(SystemExit) as refused:  # refused as it is parsed
        main(["size", "planar_2r", "--ambient", "150"])
    err = capsys.readouterr().err
    assert refused.value.code == 2 and "--ambient: must be a finite number >= -50 and <= 100 °C" in err
    assert err.count("\n") == 1


def test_the_study_option_ambient():
    import mechatron
    from mechatron.studies.analyses.sizing import arguments

    mech = mechatron.load("planar_2r")
    assert arguments(mech, {"ambient": 25})["limits"].ambient == pytest.approx(ZERO + 25)
    assert arguments(mech, {})["limits"].ambient == pytest.approx(DEFAULT_AMBIENT)
    with pytest.raises(InputError, match=r"\[analyses.sizing\] ambient"):
        arguments(mech, {"ambient": 400})

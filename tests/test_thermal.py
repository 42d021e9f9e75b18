"""The two-node motor thermal model (mechatron.drives.thermal, issue 25 item 1) against independent references: the
closed form of a constant loss step from cold (the two exponentials of the 2 × 2 network), the periodic steady state
of a square-wave loss (each mode's own geometric sum), the steady state with the resistance rising with temperature,
and a time stepping of this test's own (RK4 on the network's equations, the cycle's affine map found from three
runs); a batch of pairs simulated at once as each alone; the mean-rise bound the screening uses; the magnets heating
too (issue 31 item 4: k_t at the housing's temperature, against a hand fixed point by brentq, the own stepping
iterated by substitution, and a hand case without a steady state); the IEC 60034-1 duty types from the standard's
definitions (issue 31 item 2: S1, S3, S4, S5, S6, S7 and the PUMA's S9 with its reasons); the sizing deciding by the
winding's temperature where RMS would decide the other way; bad thermal columns refused naming file, row and field; a
motor without them checked by RMS, the report saying so; --ambient and the study option."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.catalogs import read_catalog
from mechatron.drives.checks import DriveLimits
from mechatron.drives.duty import JointDuty
from mechatron.drives.joint import size_joint
from mechatron.drives.thermal import (
    ALPHA_COPPER,
    DEFAULT_AMBIENT,
    ThermalData,
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
    """The periodic steady state in machine code (periodic_kernel: each interval's map made and composed in one
    pass) equals the NumPy maps (thermal.interval_maps) composed up the tree of pairwise compositions
    (thermal.tree_states) to 1e-11 relative on random batches of uneven cycles with a random scale s of I² — the
    same fixed point, summed in another order —, its housing mean equals NumPy's trapezoid of those states over the
    cycle, and it gives NaN on exactly the same rows: a runaway (I² R₂₅ α R_tot ≥ 1) and a row with an infinite
    loss. Without a C compiler the tree is the path; the kernel must be there by default (only MECHATRON_COMPILE=0
    switches it off)."""
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
    scale = np.random.default_rng(samples).uniform(0.8, 1.3, (8, 1))
    r_amb, dr = r25 * (1 + alpha * (AMBIENT - REFERENCE)), r25 * alpha
    maps = interval_maps(np.diff(t), 0.5 * (i2[:, 1:] + i2[:, :-1]) * scale, 0.5 * (loss[:, 1:] + loss[:, :-1]), r_wh,
                         r_ha, tau_w, tau_h, r_amb, dr)
    tree = tree_states(maps)
    native = native_states(t, i2, loss, np.hstack([r_wh, r_ha, tau_w, tau_h, r_amb, dr, scale]))
    for a, b in zip(tree, native[:2]):
        assert b.shape == a.shape == (8, samples)
        np.testing.assert_array_equal(np.isnan(b), np.isnan(a))
        assert np.isnan(a[2]).all() and np.isnan(a[5]).all() and np.isfinite(np.delete(a, [2, 5], 0)).all()
        np.testing.assert_allclose(b, a, rtol=1e-11, atol=0.0)
    housing = np.concatenate([tree[1], tree[1][:, :1]], axis=1)  # the last sample's state is the first's
    mean = np.trapezoid(housing, t, axis=1) / (t[-1] - t[0])
    np.testing.assert_array_equal(np.isnan(native[2]), np.isnan(mean))
    np.testing.assert_allclose(native[2], mean, rtol=1e-11, atol=0.0)


def test_the_sizing_simulates_a_block_of_pairs_as_each_alone():
    """PairChecks.winding of a block of random motor × gearbox pairs of the shipped catalogs on a robot-like duty
    equals each pair simulated alone by periodic_rise with this test's own motor torque T_m = (J_m + J_c) u ω̇ +
    τ*/u (τ* = τ/η motoring, τ η braking) and current I = T_m/k_t₂₅, the catalog's magnet coefficient (the NdFeB
    default) given (1e-12); a runaway's with R and k_t held at T_max (k_t(T_max) = k_t₂₅ (1 + β (T_max − 25 °C)))."""
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
                              th.r_ha[i], th.tau_w[i], th.tau_h[i], r25, alpha, DEFAULT_AMBIENT, th.magnet[i])
        if np.isnan(alone).all():  # a runaway: the rise with R and k_t held at their values at T_max
            runaways += 1
            hot = current / (1 + th.magnet[i] * (th.limit[i] - ZERO - 25))  # I = T_m / k_t(T_max)
            alone = periodic_rise(t, hot[None] ** 2, th.loss_torque[i] * np.abs(u * speed)[None], th.r_wh[i],
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
    flat = ThermalData(*(np.array([x]) for x in (*NETWORK, 428.15, 0.7, 0.0, 0.9, 0.0, 0.0)))  # R and k_t constant
    t = np.linspace(0, 10, 2001)
    torque = 3 * np.sin(t) ** 2
    w = np.full(2001, t[1] - t[0]) / 10
    w[[0, -1]] /= 2
    mean = np.trapezoid(winding_temperature(t, torque, 0 * t, flat, 0, AMBIENT)[0] - AMBIENT, t) / 10
    assert flat.mean_bound(0, math.sqrt(w @ torque**2), 0.0, AMBIENT) == pytest.approx(mean, rel=1e-5)


# ------------------------------------------------------------------------------------------------ magnets
BETA = -0.0011  # 1/K: NdFeB


def hand_steady_state(current: float, r25: float, alpha: float, beta: float, network=NETWORK,
                      ambient=AMBIENT) -> tuple[float, float]:
    """This test's own steady state (θ_w, θ_h) (K) of a constant current I (T_m/k_t₂₅) with k_t at the housing's
    temperature: the loss P solves P = I² R₂₅ (1 + α (T_a + R_tot P − 25 °C)) / (1 + β (T_a + R_ha P − 25 °C))²
    (θ_w = R_tot P, θ_h = R_ha P at a constant load), its smallest root by brentq (the first sign change of a scan)."""
    from scipy.optimize import brentq

    r_wh, r_ha, *_ = network
    total, base = r_wh + r_ha, ambient - ZERO - 25

    def excess(p):
        return current**2 * r25 * (1 + alpha * (base + total * p)) / (1 + beta * (base + r_ha * p)) ** 2 - p

    grid = np.linspace(0.0, 200.0, 20001)
    upper = grid[np.argmax([excess(p) < 0 for p in grid])]
    power = brentq(excess, 0.0, upper, xtol=1e-14)
    return total * power, r_ha * power


def test_a_hot_winding_with_magnets_runs_hotter_by_the_hand_fixed_point():
    """7 A at constant torque through R₂₅ = 0.5 Ω: without magnet coefficient the winding rises to the closed form
    I² R_a R_tot / (1 − I² R₂₅ α R_tot) = 85.2 K; with NdFeB's β = −0.11 %/K and the magnets at the housing's
    temperature, to the hand fixed point (brentq on P = I² R(T_w) / (1 + β (T_h − 25 °C))²) 114.2 K, 29 K
    hotter (the magnets at 117.7 °C have lost 10.2 % of k_t₂₅) — the model's winding and housing equal it to 1e-3 K
    (the magnet iteration's tolerance), through periodic_rise and through the sizing, whose report gives the
    magnets' temperature T_a + R_ha P."""
    r_wh, r_ha, *_ = NETWORK
    current, r25 = 7.0, 0.5
    t = np.linspace(0.0, 5.0, 11)
    cold = rise(t, np.full(11, current), resistance=r25, alpha=ALPHA_COPPER)[:, 0]
    r_ambient = r25 * (1 + ALPHA_COPPER * (AMBIENT - ZERO - 25))
    closed = current**2 * r_ambient * (r_wh + r_ha) / (1 - current**2 * r25 * ALPHA_COPPER * (r_wh + r_ha))
    assert cold == pytest.approx(np.full(11, closed), abs=1e-9) and closed == pytest.approx(85.2, abs=0.05)
    winding, housing = hand_steady_state(current, r25, ALPHA_COPPER, BETA)
    model = periodic_rise(t, np.full((1, 11), current**2), np.zeros((1, 11)), *NETWORK, r25, ALPHA_COPPER, AMBIENT,
                          BETA)[0]
    assert np.max(np.abs(model[:, 0] - winding)) < 1e-3 and np.max(np.abs(model[:, 1] - housing)) < 1e-3
    assert winding == pytest.approx(114.2, abs=0.05) and winding - closed > 28.0
    # the same through the sizing: a motor of this network at k_t₂₅ = 1 N·m/A holding 7 N·m at standstill
    motor = pd.DataFrame([{**MOTORS.iloc[0].to_dict(), "resistance": r25, "rth_winding_housing": r_wh,
                           "rth_housing_ambient": r_ha, "tau_winding": NETWORK[2], "tau_housing": NETWORK[3],
                           "temperature_coefficient": ALPHA_COPPER, "torque_constant_coefficient": BETA}])
    sized = size_joint(_duty(t, np.full(11, current)), motor, direct=True)
    check = next(c for c in sized.checks if c.name == "winding temperature rise")
    assert check.value == pytest.approx(winding, abs=1e-3)
    assert sized.thermal()["magnet_K"] == pytest.approx(AMBIENT + housing, abs=1e-3)
    assert "the magnets 117.7 °C" in str(sized) and sized.as_dict()["thermal"]["duty_type"] == "S1"


def test_the_magnet_fixed_point_of_a_robot_like_cycle_against_the_own_stepping():
    """The robot-like cycle of the RK4 test above with NdFeB magnets: this test's own RK4 stepping at the scale s =
    1/(1 + β (T_a + x − 25 °C))² of I², x taken by plain substitution x ← ⟨θ_h⟩ (the trapezoidal mean of the
    stepped housing at the samples) until it moves less than 1e-9 K, equals the model to 1e-3 K (the magnet
    iteration's tolerance; 4e-7 K here); 31 K hotter than the model without magnet coefficient."""
    t = np.concatenate([np.linspace(0, 4, 81), np.linspace(4.05, 6, 20)])
    current = np.where(t < 4, 9 * np.sin(np.pi * t / 4) ** 2 + 2 * np.sin(3 * t), 1.5)
    loss = np.where(t < 4, 12 * np.abs(np.sin(np.pi * t / 4)), 0.0)
    network = (0.8, 1.7, 5.0, 60.0)
    x = 0.0
    for _ in range(40):
        scale = 1 / (1 + BETA * (AMBIENT - ZERO - 25 + x)) ** 2
        stepped = stepped_periodic(t, current * math.sqrt(scale), loss, sub=8, network=network)
        x, before = np.trapezoid(stepped[:, 1], t) / (t[-1] - t[0]), x
        if abs(x - before) < 1e-9:
            break
    assert abs(x - before) < 1e-9
    model = periodic_rise(t, (current**2)[None], loss[None], *network, 1.0, ALPHA_COPPER, AMBIENT, BETA)[0]
    assert np.max(np.abs(model - stepped)) < 1e-3
    plain = periodic_rise(t, (current**2)[None], loss[None], *network, 1.0, ALPHA_COPPER, AMBIENT)[0]
    assert model[:, 0].max() - plain[:, 0].max() > 30.0


def test_magnets_that_weaken_faster_than_the_cooling_leave_no_steady_state():
    """β = −0.5 %/K (allowed: k_t(155 °C) = 0.35 k_t₂₅ > 0): at a current where the copper alone has a steady state
    at every magnet temperature below some x_r, the housing's steady rise at the magnet rise x, F(x) = R_ha P(x),
    P(x) = I² s(x) R_a / (1 − I² s(x) R₂₅ α R_tot), stays above x on [0, x_r) (this test's scan): no fixed point,
    no steady state (periodic_rise NaN); the check takes the rise with R and k_t held at T_max, I² s(T_max − T_a)
    R(T_max) R_tot by hand, above the allowed rise. The same current without magnet coefficient has one."""
    r_wh, r_ha, *_ = NETWORK
    total, r25, beta, limit = r_wh + r_ha, 0.5, -0.005, ZERO + 155
    base = AMBIENT - ZERO - 25
    r_ambient = r25 * (1 + ALPHA_COPPER * base)

    def housing(x, current):
        s = 1 / (1 + beta * (base + x)) ** 2
        room = 1 - current**2 * s * r25 * ALPHA_COPPER * total
        return np.where(room > 0, r_ha * current**2 * s * r_ambient / np.where(room > 0, room, 1.0), np.inf)

    x = np.linspace(0.0, -1 / beta - base - 1e-6, 200001)
    current = 6.0
    assert np.all(housing(x, current) > x) and np.isfinite(housing(0.0, current))  # no fixed point; stable at x = 0
    t = np.linspace(0.0, 3.0, 7)
    i2 = np.full((1, 7), current**2)
    assert np.isnan(periodic_rise(t, i2, np.zeros((1, 7)), *NETWORK, r25, ALPHA_COPPER, AMBIENT, beta)).all()
    assert np.isfinite(periodic_rise(t, i2, np.zeros((1, 7)), *NETWORK, r25, ALPHA_COPPER, AMBIENT)).all()
    top = highest_rise(t, i2, np.zeros((1, 7)), *NETWORK, r25, ALPHA_COPPER, AMBIENT, limit, beta)[0]
    held = current**2 / (1 + beta * (limit - ZERO - 25)) ** 2 * r25 * (1 + ALPHA_COPPER * 130) * total
    assert top == pytest.approx(held, rel=1e-9) and top > limit - AMBIENT


def test_the_magnet_coefficient_column(tmp_path):
    """``torque_constant_coefficient`` in %/K: −0.11 %/K read as −0.0011 1/K, empty as the NdFeB default, absent as
    the default too; a positive coefficient, one below −1 %/K and one that leaves no k_t at the limit temperature
    (−0.8 %/K at 155 °C: 1 − 0.008 · 130 < 0) refused naming file, row and field."""
    from mechatron.drives.thermal import MAGNET_COEFFICIENT

    header = HEADER + ",torque_constant_coefficient_percent_K"
    path = tmp_path / "motors.csv"
    path.write_text(f"{header}\n{GOOD},-0.11\n{GOOD.replace('M1', 'M2')},\n")
    assert ThermalData.of(read_catalog(path, "motors")).magnet.tolist() == pytest.approx([-0.0011, MAGNET_COEFFICIENT])
    assert MAGNET_COEFFICIENT == -0.0011
    path.write_text(f"{HEADER}\n{GOOD}\n")
    assert ThermalData.of(read_catalog(path, "motors")).magnet.tolist() == [MAGNET_COEFFICIENT]
    for value, message in (("0.05", "must be between"), ("-1.5", "must be between"), ("-0.8", "must stay > 0")):
        path.write_text(f"{header}\n{GOOD},-0.11\n{GOOD.replace('M1', 'M2')},{value}\n")
        with pytest.raises(InputError, match=message) as info:
            read_catalog(path, "motors")
        assert (info.value.row, info.value.field) == (3, "torque_constant_coefficient_percent_K")
        assert str(info.value).count("\n") == 0


# --------------------------------------------------------------------------------------------- duty type
def _duty(t, torque, speed=None, moving=None, acceleration=None):
    t = np.asarray(t, dtype=float)
    speed = np.zeros_like(t) if speed is None else np.asarray(speed, dtype=float)
    acceleration = np.zeros_like(t) if acceleration is None else acceleration
    torque = np.asarray(torque, dtype=float)
    return JointDuty("q1", "revolute", t, speed, acceleration, torque, torque.copy(), 1e-4, 0.0, moving)


def test_constant_load_running_continuously_is_s1():
    """IEC 60034-1, 4.2.1: S1 is operation at a constant load: 2 N·m at 30 rad/s the whole cycle, and 2 N·m held at
    standstill the whole cycle (a load at zero speed, energised), are S1; the same with the load varying by 20 %
    is not (S9, the load varying: from 1.6 to 2.4 N·m, a third of its largest)."""
    t = np.linspace(0.0, 10.0, 101)
    running = duty_type(_duty(t, np.full(101, 2.0), speed=np.full(101, 30.0)))
    assert (running.kind, running.factor, str(running), running.clause) == ("S1", 1.0, "S1", "4.2.1")
    assert duty_type(_duty(t, np.full(101, 2.0))).kind == "S1"
    varying = duty_type(_duty(t, 2.0 + 0.4 * np.sin(t), speed=np.full(101, 30.0)))
    assert varying.kind == "S9" and "the load spans 33 %" in varying.reason


def on_off(t_on: float, t_off: float, torque: float, speed: float, dt: float = 0.05) -> JointDuty:
    """``torque`` at ``speed`` for t_on, then no torque at standstill for t_off (the steps within 1e-9 s)."""
    on = np.arange(0.0, t_on + dt / 2, dt)
    t = np.concatenate([on, np.linspace(t_on + 1e-9, t_on + t_off, int(round(t_off / dt)) + 1)])
    loaded = t <= t_on
    return _duty(t, np.where(loaded, torque, 0.0), speed=np.where(loaded, speed, 0.0))


def test_a_constant_load_switched_on_and_off_is_s3():
    """IEC 60034-1, 4.2.3: S3 is identical cycles of a constant load and a rest de-energised (at standstill, no
    torque), the starting not affecting the temperature: 3 N·m at 50 rad/s for 1 s in every 4 s is S3 25 % (x the
    time under load over the cycle's, 1/4), at standstill too (a load pushed and released); holding the load in
    the rest instead is no rest (S9: the speed under load varies)."""
    duty = on_off(1.0, 3.0, 3.0, 50.0)
    kind = duty_type(duty)
    assert (kind.kind, str(kind), kind.clause) == ("S3", "S3 25 %", "4.2.3")
    assert kind.factor == pytest.approx(0.25, abs=1e-8)
    assert str(duty_type(on_off(1.0, 3.0, 3.0, 0.0))) == "S3 25 %"
    held = _duty(duty.t, np.full(len(duty.t), 3.0), speed=duty.speed)
    assert duty_type(held).kind == "S9"


def test_holding_a_load_at_rest_is_not_no_load_running():
    """IEC 60034-1, 4.2.6: S6 is a constant load and no-load running (at speed, no torque), no rest: 2 N·m at 20
    rad/s for 1 s, then 20 rad/s without torque for 3 s, is S6 25 %; the same load held at standstill for those 3 s
    (energised, at zero speed) is a load at another speed, not S6's no-load: S9."""
    t = np.concatenate([np.linspace(0.0, 1.0, 21), np.linspace(1.0 + 1e-9, 4.0, 61)])
    loaded = t <= 1.0
    idle = duty_type(_duty(t, np.where(loaded, 2.0, 0.0), speed=np.full(len(t), 20.0)))
    assert (str(idle), idle.clause) == ("S6 25 %", "4.2.6") and idle.factor == pytest.approx(0.25, abs=1e-8)
    holding = duty_type(_duty(t, np.full(len(t), 2.0), speed=np.where(loaded, 20.0, 0.0)))
    assert holding.kind == "S9" and "the speed spans 100 %" in holding.reason


def servo_moves(friction: float, rest: float, reverse: bool = False) -> JointDuty:
    """Trapezoidal moves of a rotor J = 0.01 kg·m²: 50 rad/s² for 0.2 s up to 10 rad/s, 0.6 s at it, 0.2 s braking,
    then ``rest`` s at standstill (the next move the other way where ``reverse``); torque J ω̇ + ``friction`` with
    the speed's sign while moving (a constant load), none at rest."""
    dt = 0.005
    move = np.arange(0.0, 1.0 + dt / 2, dt)
    acceleration = np.where(move < 0.2, 50.0, np.where(move > 0.8, -50.0, 0.0))
    speed = np.minimum(np.minimum(50 * move, 10.0), 50 * (1.0 - move)).clip(0.0)
    parts_t, parts_w, parts_a = [move], [speed], [acceleration]
    if rest:
        parts_t.append(np.linspace(1.0 + dt, 1.0 + rest, int(round(rest / dt))))
        parts_w.append(np.zeros(len(parts_t[-1])))
        parts_a.append(np.zeros(len(parts_t[-1])))
    t, w, a = (np.concatenate(p) for p in (parts_t, parts_w, parts_a))
    if reverse:
        t, w, a = np.concatenate([t, t[-1] + dt + t]), np.concatenate([w, -w]), np.concatenate([a, -a])
    torque = 0.01 * a + friction * np.sign(w)
    return _duty(t, torque, speed=w, acceleration=a)


def test_servo_moves_with_rests_are_s5_braked_by_the_motor_s4_by_the_load_and_s7_without_rest():
    """IEC 60034-1, 4.2.4/4.2.5/4.2.7: starting (0.5 N·m of acceleration), a constant load (the friction, at
    constant speed) and braking, then a rest de-energised, is S5 where the motor brakes (friction 0.2 N·m: −0.3
    N·m against the speed) and S4 where the friction does (0.8 N·m: the torque stays with the speed); x the time
    energised (starting, load, braking: 1 s) over the cycle (2 s). Reversing moves without a rest, braked by the
    motor: S7 (no cyclic duration factor)."""
    electric = duty_type(servo_moves(0.2, 1.0))
    assert (electric.kind, electric.clause) == ("S5", "4.2.5") and electric.factor == pytest.approx(0.5, abs=0.01)
    assert str(electric) == "S5 50 %" and "electric braking" in electric.reason
    by_load = duty_type(servo_moves(0.8, 1.0))
    assert (by_load.kind, str(by_load)) == ("S4", "S4 50 %") and "braked by the load" in by_load.reason
    reversing = duty_type(servo_moves(0.2, 0.0, reverse=True))
    assert (reversing.kind, reversing.factor, str(reversing)) == ("S7", 1.0, "S7")


def test_the_puma_pick_and_place_is_s9_and_says_why():
    """IEC 60034-1, 4.2.9: the PUMA 560's own task (mechatron.load("puma560"), robots/tasks/puma560.toml: moves
    between waypoints and 0.2 s dwells) gives every joint's motor, sized, S9 — none of S1 … S8, each by the
    definitions, read off the motor's own torque T and speed n here: five joints carry a load under load that is
    not constant (outside the joint's starting and braking, |T| ≥ 5 % of its largest, |T| spreads more than 5 %
    of its largest: gravity and inertia change along the path); joint 5 carries a constant load but is never at
    rest de-energised (its wrist's gravity held in every dwell) and never brakes electrically (T n ≥ 0 wherever
    it decelerates): neither S3 … S5 (a rest) nor S7 (electric braking). The report and JSON say why."""
    result = mechatron.size(mechatron.load("puma560"))
    for joint in result.joints:
        n, torque = joint.operating_points()
        duty = joint.duty
        kind = duty_type(duty, n, torque)
        assert (kind.kind, str(kind), kind.clause) == ("S9", "S9", "4.2.9"), joint.joint
        info = joint.as_dict()["thermal"]
        assert info["duty_type"] == "S9" and info["duty_reason"] == kind.reason
        assert f"duty type S9 [IEC 60034-1, 4.2.9]: {kind.reason}" in str(joint)
        top = np.abs(torque).max()
        steady = np.abs(duty.acceleration) <= 0.05 * np.abs(duty.acceleration).max()
        loaded = steady & (np.abs(torque) > 0.05 * top)
        spread = np.ptp(np.abs(torque[loaded])) / top
        if joint.joint != "q5":
            assert spread > 0.05 and "load and speed vary over the cycle" in kind.reason, joint.joint
            continue
        assert spread <= 0.05 and not np.any((np.abs(torque) <= 0.05 * top) & (np.abs(n) <= 0.05 * np.abs(n).max()))
        assert np.all(torque[duty.acceleration * duty.speed < 0] * n[duty.acceleration * duty.speed < 0] >= 0)
        assert kind.reason.startswith("speed changes braked by the load, not electrically, and no rest")


# ------------------------------------------------------------------------------------------------ sizing
#: Two motors checked by their winding (R₂₅ = 1 Ω, k_t = 1 N·m/A whatever the magnets' temperature: I = T_m): A
#: light, rated 4.5 N·m S1 but able to carry 5.04 N·m continuously at standstill by its network (R_tot = 3 K/W); B
#: heavier, with twice the cooling.
MOTORS = pd.DataFrame([
    {"key": "A", "rated_torque": 4.5, "peak_torque": 20.0, "rated_speed": 300.0, "max_speed": 500.0,
     "rotor_inertia": 1e-4, "torque_constant": 1.0, "resistance": 1.0, "rth_winding_housing": 1.0,
     "rth_housing_ambient": 2.0, "tau_winding": 20.0, "tau_housing": 600.0, "max_winding_temperature": 428.15,
     "torque_constant_coefficient": 0.0,
     "mass": 1.0, "price": 100.0},
    {"key": "B", "rated_torque": 7.5, "peak_torque": 30.0, "rated_speed": 300.0, "max_speed": 500.0,
     "rotor_inertia": 2e-4, "torque_constant": 1.0, "resistance": 1.0, "rth_winding_housing": 0.4,
     "rth_housing_ambient": 0.8, "tau_winding": 20.0, "tau_housing": 600.0, "max_winding_temperature": 428.15,
     "torque_constant_coefficient": 0.0,
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
    # a constant load on and off, at standstill: IEC 60034-1's S3, x the time under load over the cycle's
    assert info["duty_type"] == "S3 33 %" and info["cyclic_duration_factor"] == pytest.approx(1 / 3, abs=1e-8)


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

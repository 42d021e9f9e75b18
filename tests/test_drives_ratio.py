"""Transmission ratio [Egorov, section 4.4]: every closed form against the numerical optimum of the same move-time
model (CasADi/Ipopt) and an independent brute-force grid, and the RMS ratio band against direct RMS sums.

The move model (derived in mechatron/drives/ratio.py): a rest-to-rest move of γ, motor torque M_i, motor speed
limit Ω_d, output acceleration a = M_i / (J_d u + P_h/(u η)); trapezoidal time γu/Ω_d + Ω_d J_d/M_i +
Ω_d P_h/(u² M_i η) when the speed limit is reached, triangular 2√(γ/a) otherwise.
"""

import math

import numpy as np
import pytest

from mechatron.drives.ratio import (
    cycle_ratio,
    design_displacement,
    inertia_matching_ratio,
    load_dominance,
    minimum_time_ratio,
    motor_side_inertia,
    move_time,
    optimal_ratio,
    rms_ratio_band,
    static_ratio,
    textbook_ratio,
)
from mechatron.errors import InputError

# The worked case used throughout: Ω_d = 314 rad/s (3000 rpm), J_h = 2 kg·m², γ = 1 rad, M_i = 2 N·m, η = 0.9.
OMEGA, JH, GAMMA, MI, ETA = 314.0, 2.0, 1.0, 2.0, 0.9


def grid_optimum(time_of_u, lo, hi, n=200001):
    """Brute force on a log grid, then a local refinement: independent of CasADi."""
    u = np.geomspace(lo, hi, n)
    t = np.array([time_of_u(x) for x in u])
    k = int(np.argmin(t))
    fine = np.linspace(u[max(k - 1, 0)], u[min(k + 1, n - 1)], 20001)
    tf = np.array([time_of_u(x) for x in fine])
    return float(fine[np.argmin(tf)]), float(tf.min())


def test_minimum_time_ratio_closed_form_value():
    # u³ = 2·314²·2 / (1·2·0.9) = 219 102.2…  →  u = 60.2859…
    u = minimum_time_ratio(OMEGA, JH, GAMMA, MI, ETA)
    assert u**3 == pytest.approx(2 * OMEGA**2 * JH / (GAMMA * MI * ETA), rel=1e-14)
    assert u == pytest.approx(60.2859, abs=5e-5)


@pytest.mark.parametrize("eta", [1.0, 0.9, 0.7])
def test_minimum_time_ratio_is_the_numerical_optimum_for_a_load_dominated_drive(eta):
    drive = 1e-5  # J_h/(u² J_d) ≈ 55: the load dominates
    formula = minimum_time_ratio(OMEGA, JH, GAMMA, MI, eta)
    assert load_dominance(JH, formula, drive) > 1
    u, t = optimal_ratio(OMEGA, JH, GAMMA, MI, eta, drive)
    assert u == pytest.approx(formula, rel=1e-6)
    u_grid, t_grid = grid_optimum(lambda x: move_time(x, OMEGA, JH, GAMMA, MI, eta, drive), 1, 1000)
    assert u_grid == pytest.approx(formula, rel=1e-3)
    assert t == pytest.approx(t_grid, rel=1e-9)
    # at the optimum the motor accelerates over a quarter of the move (why the cube root has the 2)
    speed = OMEGA / u
    acceleration = MI / (drive * u + JH / (u * eta))
    assert speed**2 / (2 * acceleration) == pytest.approx(GAMMA / 4 + speed**2 / 2 * drive * u / MI, rel=1e-9)


def test_motor_inertia_does_not_move_the_trapezoidal_optimum():
    # J_d only adds Ω_d J_d / M_i to the trapezoidal time: the optimum stays at [Egorov, 4.63] while the profile
    # stays trapezoidal
    for drive in (0.0, 1e-6, 1e-5, 5e-5):
        u, _ = optimal_ratio(OMEGA, JH, GAMMA, MI, ETA, drive)
        assert u == pytest.approx(minimum_time_ratio(OMEGA, JH, GAMMA, MI, ETA), rel=1e-6)


@pytest.mark.parametrize("eta", [1.0, 0.9])
def test_inertia_matching_is_the_optimum_when_the_drive_inertia_dominates(eta):
    drive = 1e-3  # J_h/(u_mt² J_d) ≈ 0.55 < η: the move never reaches the speed limit
    u_mt = minimum_time_ratio(OMEGA, JH, GAMMA, MI, eta)
    assert load_dominance(JH, u_mt, drive) < eta
    u, t = optimal_ratio(OMEGA, JH, GAMMA, MI, eta, drive)
    assert u == pytest.approx(math.sqrt(JH / (eta * drive)), rel=1e-6)  # √(J_h/(η J_d)); [Egorov, 4.69] has η = 1
    assert u == pytest.approx(inertia_matching_ratio(JH, drive, eta), rel=1e-6)
    u_grid, t_grid = grid_optimum(lambda x: move_time(x, OMEGA, JH, GAMMA, MI, eta, drive), 1, 1000)
    assert u_grid == pytest.approx(u, rel=1e-3)
    assert t == pytest.approx(t_grid, rel=1e-9)
    if eta == 1.0:
        assert u == pytest.approx(44.72136, rel=1e-6)  # √(2/0.001), [Egorov, 4.69] exactly
    else:
        assert u == pytest.approx(47.14045, rel=1e-6)  # the book's 44.72 is 5 % low with η = 0.9


def test_textbook_switch_follows_eq_4_66():
    rotor = 1e-3 / 1.2  # J_d = 1.2 J_rotor = 1e-3 [Egorov, 4.67]
    choice = textbook_ratio(OMEGA, JH, GAMMA, MI, rotor, ETA)
    assert choice.rule.startswith("inertia matching")
    assert choice.dominance == pytest.approx(JH / (60.2859**2 * 1e-3), rel=1e-5)
    assert choice.ratio == pytest.approx(math.sqrt(2 / 1e-3))
    light = textbook_ratio(OMEGA, JH, GAMMA, MI, 1e-5, ETA)
    assert light.rule.startswith("minimum time") and light.ratio == pytest.approx(60.2859, abs=5e-5)
    assert motor_side_inertia(1e-3) == pytest.approx(1.2e-3)
    with pytest.raises(InputError, match="1.1…1.3"):
        motor_side_inertia(1e-3, factor=3)


def test_exact_switch_is_dominance_equal_to_eta_not_one():
    """Where the book and the numerical optimum differ: for η < 1 the minimum-time ratio stays optimal down to
    J_h/(u² J_d) = η (the profile is trapezoidal exactly while η J_d u² ≤ J_h), but [Egorov, 4.66] switches at
    1."""
    eta = 0.8
    u_mt = minimum_time_ratio(OMEGA, JH, GAMMA, MI, eta)
    drive = JH / (0.9 * u_mt**2)  # dominance 0.9: between η and 1
    assert load_dominance(JH, u_mt, drive) == pytest.approx(0.9)
    u_opt, t_opt = optimal_ratio(OMEGA, JH, GAMMA, MI, eta, drive)
    assert u_opt == pytest.approx(u_mt, rel=1e-5)
    book = textbook_ratio(OMEGA, JH, GAMMA, MI, drive / 1.2, eta)
    assert book.rule.startswith("inertia matching")  # the book's rule picks the other formula...
    t_book = move_time(book.ratio, OMEGA, JH, GAMMA, MI, eta, drive)
    assert t_book > t_opt * 1.001  # ...and a slower move
    # just below η the optimum leaves the formula
    drive = JH / (0.7 * u_mt**2)
    u_opt, _ = optimal_ratio(OMEGA, JH, GAMMA, MI, eta, drive)
    assert u_opt == pytest.approx(inertia_matching_ratio(JH, drive, eta), rel=1e-5)


def test_rotary_to_linear_ratio_4_70():
    # a ball screw axis: motor 314 rad/s, 0.2 N·m, carriage 50 kg, moves of 0.2 m; u in rad/m, lead = 2π/u
    u = minimum_time_ratio(314.0, 50.0, 0.2, 0.2, 0.9)
    assert u == pytest.approx((2 * 314**2 * 50 / (0.2 * 0.2 * 0.9)) ** (1 / 3))
    u_opt, _ = optimal_ratio(314.0, 50.0, 0.2, 0.2, 0.9, 1e-6)
    assert u_opt == pytest.approx(u, rel=1e-6)
    lead = 2 * math.pi / u
    assert 0.005 < lead < 0.05  # 5–50 mm: a real screw lead


def test_linear_to_rotary_ratio_4_71():
    # a linear actuator (0.5 m/s, 2 kN) turning a 40 kg·m² arm through 1 rad: u in m/rad (a lever arm)
    u = minimum_time_ratio(0.5, 40.0, 1.0, 2000.0, 0.95)
    u_opt, _ = optimal_ratio(0.5, 40.0, 1.0, 2000.0, 0.95, 1.0)
    assert u_opt == pytest.approx(u, rel=1e-6)
    assert 0.01 < u < 1.0


def test_cycle_ratio_4_72_to_4_75_minimizes_the_cycle_time():
    loads, moves = [2.0, 0.5, 4.5], [1.0, 0.4, 1.6]
    u = cycle_ratio(OMEGA, loads, moves, MI, ETA)
    assert u**3 == pytest.approx(2 * OMEGA**2 * sum(loads) / (sum(moves) * MI * ETA))
    u_opt, t_opt = optimal_ratio(OMEGA, loads, moves, MI, ETA, 1e-6)
    assert u_opt == pytest.approx(u, rel=1e-6)

    def cycle_time(x):
        return sum(move_time(x, OMEGA, p, g, MI, ETA, 1e-6) for p, g in zip(loads, moves))

    u_grid, _ = grid_optimum(cycle_time, 1, 1000, 20001)
    assert u_grid == pytest.approx(u, rel=1e-3)
    # neither the first segment's ratio nor the mean of the segments' ratios: the sums matter
    assert abs(minimum_time_ratio(OMEGA, loads[0], moves[0], MI, ETA) - u) > 1
    mean = np.mean([minimum_time_ratio(OMEGA, p, g, MI, ETA) for p, g in zip(loads, moves)])
    assert abs(mean - u) > 1


def test_static_ratio_and_design_displacement():
    u = static_ratio(load=120.0, motor_effort=1.5, efficiency=0.8)  # [Egorov, 4.59-4.62]
    assert 120.0 / (u * 0.8) == pytest.approx(1.5)
    assert design_displacement(math.pi) == pytest.approx(math.pi / 2)  # [Egorov, 4.64]
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(InputError, match="load"):
            static_ratio(bad, 1.0)


# ----------------------------------------------------------------------------------------------- RMS band
def _duty_cycle():
    t = np.linspace(0.0, 2.0, 4001)
    acc = np.where(t < 0.3, 20.0, np.where(t < 0.6, -20.0, 0.0))
    speed = np.cumsum(acc) * (t[1] - t[0])
    torque = 0.8 * acc + 15.0 * np.sin(t)  # inertia plus a slowly varying load
    return t, acc, torque, speed


def _rms(u, J, t, acc, torque, speed, eta):
    effective = np.where(torque * speed >= 0, torque / eta, torque * eta)
    motor = J * u * acc + effective / u
    return math.sqrt(np.trapezoid(motor**2, t) / (t[-1] - t[0]))


def test_rms_band_endpoints_and_optimum():
    t, acc, torque, speed = _duty_cycle()
    J, rated, eta = 2e-4, 0.6, 0.9
    band = rms_ratio_band(J, rated, t, acc, torque, eta, load_speed=speed)
    assert band.feasible and band.lower < band.optimal < band.upper
    assert _rms(band.lower, J, t, acc, torque, speed, eta) == pytest.approx(rated, rel=1e-9)
    assert _rms(band.upper, J, t, acc, torque, speed, eta) == pytest.approx(rated, rel=1e-9)
    effective = np.where(torque * speed >= 0, torque / eta, torque * eta)

    def rms_on(grid):  # _rms at every ratio of the grid
        return np.sqrt(np.trapezoid((J * grid[:, None] * acc + effective / grid[:, None]) ** 2, t, axis=1)
                       / (t[-1] - t[0]))

    coarse = np.geomspace(band.lower, band.upper, 1001)  # the minimum on the band, then finer around it
    k = int(np.argmin(rms_on(coarse)))
    grid = np.geomspace(coarse[max(k - 2, 0)], coarse[min(k + 2, len(coarse) - 1)], 1001)
    values = rms_on(grid)
    assert grid[int(np.argmin(values))] == pytest.approx(band.optimal, rel=1e-4)
    assert band.rms_at_optimal == pytest.approx(min(values), rel=1e-6)
    # a motor too small for the cycle: no ratio works
    small = rms_ratio_band(J, 0.5 * band.rms_at_optimal, t, acc, torque, eta, load_speed=speed)
    assert not small.feasible
    # a speed limit caps the band
    capped = rms_ratio_band(J, rated, t, acc, torque, eta, max_motor_speed=100.0, load_speed=speed)
    assert capped.upper == pytest.approx(100.0 / np.abs(speed).max())

"""Friction, wear, life and efficiency [Egorov, chapter 7]. The chapter has no worked numbers: the oracles are
derived from its formulas (recomputed here by hand) and checked against the model's own reactions where a model
applies."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.dynamics.motion import Trajectory
from mechatron.dynamics.tree import joint_wrenches
from mechatron.errors import InputError
from mechatron.mechanics import efficiency as E
from mechatron.mechanics import friction as Fr
from mechatron.mechanics.wear import Bearing, linear_wear_intensity, single_element_life, wear_depth, wear_rate
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism
from tests.protocol import check_result


# ------------------------------------------------------------------------------------------------ friction
def test_friction_forces_7_1_to_7_3():
    assert Fr.static_friction(0.15, 100) == pytest.approx(15.0)  # O1
    assert Fr.sliding_friction(0.1, -100) == pytest.approx(10.0)
    moment, force = Fr.rolling_resistance(0.01e-3, 1000, 0.02)  # O1b: f_k = 0.01 mm
    assert (moment, force) == pytest.approx((0.01, 0.5))
    with pytest.raises(InputError, match=">= 0"):
        Fr.sliding_friction(-0.1, 10)


def test_sliding_pair_7_4_to_7_10():
    s = Fr.sliding_pair(100.0, math.radians(10), 0.15)  # O2
    assert math.degrees(s.friction_angle) == pytest.approx(8.530766, abs=1e-6)
    assert (s.normal, s.tangential, s.friction, s.net) == pytest.approx((98.480775, 17.364818, 14.772116, 2.592701),
                                                                       abs=1e-6)
    assert s.regime == "accelerating"
    assert Fr.sliding_pair(100.0, math.radians(8), 0.15).regime == "at rest (self-locking)"  # O2b: tan 8° < 0.15
    assert Fr.sliding_pair(100.0, math.atan(0.15), 0.15).regime == "uniform"


def test_incline_against_the_model():
    """A 3 kg carriage on a prismatic joint inclined at 25°: the model's joint reaction across the axis is
    m g cos θ, and with friction f the force to push it up is |τ| + f m g cos θ = m g (sin θ + f cos θ)."""
    theta, mass, f = math.radians(25), 3.0, 0.2
    base = np.eye(4)
    base[:3, :3] = np.array([[1, 0, 0], [0, math.cos(math.pi / 2 - theta), -math.sin(math.pi / 2 - theta)],
                             [0, math.sin(math.pi / 2 - theta), math.cos(math.pi / 2 - theta)]])
    link = DHLink("prismatic", name="s", lower=0.0, upper=1.0, inertial=Inertial(mass, np.zeros(3), np.eye(3) * 1e-3))
    mech = dh_mechanism(DHTable((link,), base=base), "incline")
    q, zero = np.array([0.3]), np.zeros(1)
    wrench = joint_wrenches(mech, q, zero, zero)[0]
    axis = base[:3, 2]
    force = wrench[:3]
    across = np.linalg.norm(force - (force @ axis) * axis)
    tau = mechatron.inverse_dynamics(mech, q, zero, zero)[0]
    assert abs(tau) == pytest.approx(mass * 9.81 * math.sin(theta), rel=1e-9)
    assert across == pytest.approx(mass * 9.81 * math.cos(theta), rel=1e-9)
    incline = Fr.Incline(mass, theta, f)
    assert incline.push_up == pytest.approx(abs(tau) + f * across, rel=1e-9)
    assert incline.slides_by_itself == (math.tan(theta) > f)
    assert Fr.Incline(mass, math.radians(5), f).hold_down < 0  # it must be pushed down


def test_journal_and_higher_pair_7_11_to_7_19():
    assert Fr.friction_circle(0.01, 0.1, exact=False) == pytest.approx(0.001)  # O3, (7.13)
    assert Fr.friction_circle(0.01, 0.1) == pytest.approx(0.000995037, rel=1e-6)  # r sin(arctan f)
    assert Fr.friction_circle(0.01, 0.3, exact=False) / Fr.friction_circle(0.01, 0.3) == pytest.approx(1.0440,
                                                                                                         abs=1e-4)
    assert Fr.journal_reaction(1.0, 0.01, 0.1, exact=False) == pytest.approx((100.0, 1000.0))  # O3b
    assert Fr.journal_friction_torque(1000.0, 0.01, 0.1, exact=False) == pytest.approx(1.0)
    phi, force, torque = Fr.higher_pair_friction(0.5, 0.02, 0.1)  # O4
    assert (math.degrees(phi), force, torque) == pytest.approx((5.710593, 25.0, 0.5), abs=1e-6)


def test_friction_losses_of_a_turning_link():
    """A 2 kg link, centre 0.3 m from a vertical axis, turning at 4 rad/s: the joint carries the centripetal
    force m ω² a across its axis (gravity is along it), so the journal loses ρ m ω² a ω."""
    mass, a, omega, r, f = 2.0, 0.3, 4.0, 0.015, 0.12
    link = DHLink("revolute", name="q1", inertial=Inertial(mass, np.array([-0.0, 0.0, 0.0]), np.eye(3) * 1e-3),
                  a=a)
    mech = dh_mechanism(DHTable((link,)), "turntable")
    t = np.linspace(0, 1, 11)
    traj = Trajectory(t, (omega * t)[:, None], np.full((11, 1), omega), np.zeros((11, 1)), ["q1"])
    losses = Fr.friction_losses(mech, traj, {"q1": Fr.PairFriction(f, r)})
    rho = r * math.sin(math.atan(f))
    table = losses.to_frame()
    assert np.allclose(table["load_q1"], mass * omega**2 * a, rtol=1e-9)
    assert np.allclose(table["power_q1"], rho * mass * omega**2 * a * omega, rtol=1e-9)
    assert np.allclose(table["friction_torque_q1"], rho * mass * omega**2 * a, rtol=1e-9)  # M_T = F ρ (7.14)
    assert losses.friction_work == pytest.approx(rho * mass * omega**3 * a, rel=1e-9)
    (pair,) = losses.as_dict()["pairs"]
    assert pair["work"] == pytest.approx(losses.friction_work, rel=1e-12)
    assert pair["peak_power"] == pytest.approx(rho * mass * omega**3 * a, rel=1e-9) == pair["mean_power"]


def test_pin_friction_of_the_crank_slider():
    """The rod–slider pin C turns at the rod's angular speed ω₂ = −l1 cos q1 q̇1 / √(l2² − l1² sin² q1) (the
    slider does not turn) and carries the pin force of the constrained dynamics."""
    mech = mechatron.load("crank_slider")
    l1, l2, w = 0.1, 0.4, 10.0
    t = np.linspace(0, 0.3, 31)
    q1 = 0.3 + w * t
    traj = Trajectory(t, q1[:, None], np.full((31, 1), w), np.zeros((31, 1)), ["q1"])
    pin_name = mech.closures[0].name
    losses = Fr.friction_losses(mech, traj, {pin_name: Fr.PairFriction(0.1, 0.01), "q1": Fr.PairFriction(0.1, 0.02)})
    omega2 = -l1 * np.cos(q1) * w / np.sqrt(l2**2 - l1**2 * np.sin(q1) ** 2)
    table = losses.to_frame()
    assert np.allclose(table[f"speed_{pin_name}"], omega2, atol=1e-9)
    assert losses.driving_work > 0 and losses.friction_work > 0 and 0 < losses.efficiency < 1
    # the losses are the sum over the pairs; η = 1 − A_friction / A_driving (7.46)
    powers = table[[f"power_{pin_name}", "power_q1"]].to_numpy().sum(axis=1)
    assert losses.friction_work == pytest.approx(np.trapezoid(powers, t), rel=1e-12)
    data = check_result(losses)
    assert data["efficiency"] == pytest.approx(1 - losses.friction_work / losses.driving_work, rel=1e-12)
    assert f"η = 1 − A_friction/A_driving = {losses.efficiency:.6g}" in str(losses)
    lines = losses.plot().axes[0].get_lines()
    assert [line.get_label() for line in lines] == [f"{pin_name} (revolute)", "q1 (revolute)"]
    np.testing.assert_allclose(lines[1].get_ydata(), table["power_q1"])


# ------------------------------------------------------------------------------------------------ wear
def test_wear_rate_intensity_and_law():
    assert wear_rate(4e-6, 10000 * 3600) * 3600 * 1e6 == pytest.approx(4e-4)  # O5: 4 µm in 10,000 h
    assert linear_wear_intensity(4e-6, 100e3) == pytest.approx(4e-11)  # dimensionless (the book: 0.04 µm/km)
    t = np.linspace(0, 100, 201)
    depth = wear_depth(t, 2e6, 0.5, 1e-15)  # γ = k p v with m = n = 1 (7.25, 7.26)
    assert depth[-1] == pytest.approx(1e-15 * 2e6 * 0.5 * 100)
    curved = wear_depth(t, 2e6 * (1 + t / 100), 0.5, 1e-18, m=1.5)  # (7.24) by the trapezoidal rule
    exact = 1e-18 * 0.5 * (2e6) ** 1.5 * 100 * (2**2.5 - 1) / 2.5
    assert curved[-1] == pytest.approx(exact, rel=1e-4)


def test_revolving_bearing_life_7_29_to_7_35():
    bearing = Bearing(0.01, 0.01, math.pi / 6, 20e-6, 1e-10, 1e-10)  # O6
    S1, S2 = bearing.revolution_paths("bushing")
    assert (S1, S2) == pytest.approx((0.0628319, 0.0104720), rel=1e-5)
    assert bearing.revolutions("bushing") == pytest.approx(2728370.45, rel=1e-8)
    life = bearing.life("bushing", 600 * 2 * math.pi / 60)
    assert life / 60 == pytest.approx(4547.284, rel=1e-6)  # minutes, = 75.788 h
    assert bearing.revolutions("shaft") == pytest.approx(2728370.45, rel=1e-8)  # O6b: symmetric here
    # one element wears (7.33, 7.34): the closed forms equal the general form
    v = 0.01 * 600 * 2 * math.pi / 60
    bushing_only = Bearing(0.01, 0.01, math.pi / 6, 20e-6, 1e-10, 0.0)
    assert bushing_only.life("bushing", 600 * 2 * math.pi / 60) == pytest.approx(
        single_element_life(20e-6, 1e-10, v), rel=1e-12)
    assert single_element_life(20e-6, 1e-10, v) == pytest.approx(318309.886, rel=1e-8)  # O7b
    shaft_only = Bearing(0.01, 0.01, math.pi / 6, 20e-6, 0.0, 1e-10)
    assert shaft_only.life("bushing", 600 * 2 * math.pi / 60) == pytest.approx(
        single_element_life(20e-6, 1e-10, v, math.pi / 6), rel=1e-12)
    assert single_element_life(20e-6, 1e-10, 0.1) == pytest.approx(2.0e6)  # O7: the book's 10⁻⁶ gives seconds
    assert single_element_life(20e-6, 1e-10, 0.1, math.pi / 6) == pytest.approx(1.2e7)  # O8: π/φ₀ = 6 times


def test_oscillating_bearing_life_7_36_to_7_44():
    bearing = Bearing(0.01, 0.01, math.radians(30), 20e-6, 1e-10, 1e-10)
    small = math.radians(10)  # β < 2φ₀: both elements slide 2βR per cycle (O9)
    assert bearing.swing_paths("bushing", small) == pytest.approx((0.00349066, 0.00349066), rel=1e-5)
    assert bearing.swing_cycles("bushing", small) == pytest.approx(28647889.76, rel=1e-8)
    assert bearing.swing_life("bushing", small, 2.0) == pytest.approx(14323944.88, rel=1e-8)
    large = math.radians(90)  # β ≥ 2φ₀: the element off the zone saturates at 4φ₀R (O9b)
    assert bearing.swing_paths("bushing", large) == pytest.approx((0.0314159, 0.0209440), rel=1e-5)
    assert bearing.swing_cycles("bushing", large) == pytest.approx(3819718.63, rel=1e-8)
    # (7.39) for one element, in consistent units: L = [I] / (J D β ν) = 5.7296e7 s (the printed 10⁻³ gives 1000×)
    one = Bearing(0.01, 0.01, math.radians(30), 20e-6, 1e-10, 0.0)
    assert one.swing_life("bushing", small, 1.0) == pytest.approx(20e-6 / (1e-10 * 0.02 * small * 1.0), rel=1e-12)
    assert one.swing_life("bushing", small, 1.0) == pytest.approx(5.7296e7, rel=1e-4)
    with pytest.raises(InputError, match="'bushing' or the 'shaft'"):
        bearing.swing_paths("rim", small)
    with pytest.raises(InputError, match="at least one element must wear"):
        Bearing(0.01, 0.01, 0.5, 20e-6, 0.0, 0.0)


# ------------------------------------------------------------------------------------------------ efficiency
def test_efficiency_7_45_to_7_53():
    eta = E.series([0.9, 0.95, 0.98])  # O10
    assert eta == pytest.approx(0.8379) and E.loss_coefficient(eta) == pytest.approx(0.1621)
    assert E.efficiency_from_ratio(8.5, 1.0, 10.0) == pytest.approx(0.85)  # O10b
    U = 2 * math.pi / 0.005  # a 5 mm ball screw, rad/m (7.52)
    assert E.efficiency_from_ratio(1000.0, 1.0, U) == pytest.approx(0.795775, rel=1e-6)  # O10c, 7.51 corrected
    assert E.efficiency_from_powers(1000 * 0.25, 1.0 * 3000 * math.pi / 30) == pytest.approx(0.795775, rel=1e-6)
    assert E.efficiency_from_work(100.0, 100.0) == 0.0  # idle running: η = 0, ψ = 1
    assert E.parallel([0.9, 0.8], [100.0, 300.0]) == pytest.approx(0.825)
    # a sliding screw: M10, lead 1.5 mm, f = 0.15, 30° flank half-angle: drives forward, self-locks backward
    forward = E.screw_efficiency(1.5e-3, 9.026e-3, 0.15, math.radians(30))
    backward = E.screw_efficiency(1.5e-3, 9.026e-3, 0.15, math.radians(30), back_driven=True)
    assert 0 < forward < 0.3 and E.self_locking(backward) and not E.self_locking(forward)
    with pytest.raises(InputError, match="<= 1"):
        E.series([0.9, 1.2])


def test_chain_efficiency_feeds_the_drive_sizing():
    """The hand case of tests/test_drives_sizing.py with the rest of the chain at 0.95: the motoring torque
    through the gearbox becomes 5 / (50 · 0.9 · 0.95)."""
    from test_drives_sizing import GEARBOX, MOTOR, disc, disc_move

    from mechatron.drives.sizing import size_mechanism

    chain = E.series([0.98, 0.97])  # a coupling and a bearing
    (joint,) = size_mechanism(disc(), disc_move(dt=1e-3), MOTOR, GEARBOX, direct=False,
                              chain_efficiency=chain).joints
    torque = joint.operating_points()[1]
    t = joint.duty.t
    assert torque[np.searchsorted(t, 0.1)] == pytest.approx(0.06 + 5 / (50 * 0.9 * chain), rel=1e-9)
    assert torque[np.searchsorted(t, 1.1)] == pytest.approx(-0.06 - 5 * 0.9 * chain / 50, rel=1e-9)

"""The dynamics results follow the result protocol (``check_result``), and what they report agrees with independent
references: closed-form durations and speeds, energy balances, the kinetic energy, hand-computed forces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from protocol import check_result

import mechatron
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics import constrained as cd
from mechatron.dynamics import reduced as rd
from mechatron.dynamics.kinetostatics import kinetostatics
from mechatron.dynamics.motion import cycle, move
from mechatron.kinematics.loops import assemble, joint_velocity


@pytest.fixture(scope="module")
def crank():
    return mechatron.load("crank_slider")


def test_trajectory(crank):
    mech = mechatron.load("planar_2r")
    traj = move(mech, [0.0, 0.0], [1.0, -0.5], profile="trapezoidal", vmax=2.0, amax=10.0, dt=0.001)
    data = check_result(traj)
    assert data["duration"] == pytest.approx(1 / 2 + 2 / 10)  # D/v + v/a for the axis that sets the pace
    first = data["coordinates"][0]
    assert (first["start"], first["end"]) == (0.0, pytest.approx(1.0))
    assert first["peak_speed"] == pytest.approx(2.0) and first["peak_acceleration"] == pytest.approx(10.0)
    assert list(traj.to_frame().columns) == ["t", "q1", "q2", "qd_q1", "qd_q2", "qdd_q1", "qdd_q2"]
    assert "q1" in str(traj)


def test_joint_loads_of_a_rest_to_rest_move_do_the_work_of_gravity():
    """∫ Σ τ q̇ dt = ΔV: a rest-to-rest move ends with the kinetic energy it started with."""
    mech = mechatron.load("planar_2r")
    traj = cycle(mech, [[0.2, 0.3], [1.2, -0.7]], profile="quintic", vmax=2.0, amax=8.0, dt=0.0005)
    loads = trajectory_loads(mech, traj)
    data = check_result(loads)
    assert data["kind"] == "joint" and data["samples"] == len(traj)
    work = np.trapezoid(loads.power.sum(axis=1), loads.t)
    rise = mechatron.dynamics.potential_energy(mech, traj.q[-1]) - mechatron.dynamics.potential_energy(mech, traj.q[0])
    assert work == pytest.approx(rise, rel=1e-5, abs=1e-6)
    # τ = M q̈ + h at a sample, from the mass matrix and the bias forces
    k = len(traj) // 3
    M = mechatron.dynamics.mass_matrix(mech, traj.q[k])
    expected = M @ traj.a[k] + mechatron.dynamics.bias_forces(mech, traj.q[k], traj.v[k])
    np.testing.assert_allclose(loads.to_frame()[["tau_q1", "tau_q2"]].to_numpy()[k], expected, atol=1e-10)


def test_motor_side_columns_of_an_arm_with_drives():
    mech = mechatron.load("scara")
    loads = trajectory_loads(mech, move(mech, [0, 0, 0, 0], [1.0, -1.0, 0.1, 2.0], profile="scurve", dt=0.004))
    data = check_result(loads)
    drive = mech.drives["q1"]
    row = data["coordinates"][0]
    assert row["peak_motor_speed"] == pytest.approx(drive.gear_ratio * row["peak_speed"])  # ω_m = u q̇ [Egorov, 4.58]
    assert {"motor_torque_q1", "motor_speed_q4", "power_q3"} <= set(loads.to_frame().columns)


def test_actuator_loads_of_a_cylinder_stroke_do_the_work_of_gravity():
    """A rest-to-rest stroke of the bucket cylinder: ∫ F L̇ dt = ΔV."""
    mech = mechatron.load("six_bar_bucket")
    loads = trajectory_loads(mech, move(None, [1.2], [1.8], vmax=0.2, amax=1.0, dt=0.002))
    data = check_result(loads)
    assert data["kind"] == "actuator" and data["coordinates"][0]["unit"] == "N"
    q0, q1 = assemble(mech, {"L1": 1.2}), assemble(mech, {"L1": 1.8})
    rise = mechatron.dynamics.potential_energy(mech, q1) - mechatron.dynamics.potential_energy(mech, q0)
    assert np.trapezoid(loads.power[:, 0], loads.t) == pytest.approx(rise, rel=1e-4)


def motor(t, q, v):
    return {"q1": 5.0 * (1.0 - v[0] / 30.0)}


def slider_damper(t, q, v):
    return [mechatron.Load("C@slider", [-40.0 * v[2], 0.0, 0.0])]


def test_simulation_balances_energy_and_work(crank):
    q0 = assemble(crank, {"q1": 0.0})
    sim = cd.simulate(crank, q0, joint_velocity(crank, q0, {"q1": 1.0}), 0.3, 1e-3, actuation=motor,
                      loads_at=slider_damper)
    data = check_result(sim)
    assert data["samples"] == 301 and data["duration"] == pytest.approx(0.3)
    # E − E₀ = W: the energy the motor put in, less what the damper took, is in the mechanism
    assert data["energy_end"] - data["energy_start"] == pytest.approx(data["work"], rel=1e-6)
    assert data["energy_balance_error"] < 1e-6 * abs(data["work"]) and data["max_residual"] < 1e-9
    frame = sim.to_frame()
    assert {"t", "q1", "qd_phi2", "qdd_xC", "energy", "work", "residual", "lambda_1", "lambda_2"} <= set(frame.columns)


def test_reduced_model_gives_the_kinetic_energy():
    mech = mechatron.load("six_bar_bucket")
    model = rd.reduced_table(mech, samples=9)
    data = check_result(model)
    assert data["kind"] == "mass" and data["units"]["J_reduced"] == "kg" and data["input"] == "L1"
    np.testing.assert_allclose(data["table"]["L1"], np.linspace(1.1, 2.0, 9))
    for L, J in zip(data["table"]["L1"], data["table"]["J_reduced"]):
        q = assemble(mech, {"L1": L})
        rate = 0.3
        kinetic = mechatron.dynamics.kinetic_energy(mech, q, joint_velocity(mech, q, {"L1": rate}))
        assert 0.5 * J * rate**2 == pytest.approx(kinetic, rel=1e-10)  # ½ m_пр v² = T [Egorov, 6.4]
    assert "reduced mass" in str(model)


def test_reduced_motion_keeps_kinetic_plus_potential_energy(crank):
    """Under gravity alone the one-mass model keeps ½ J_пр ω² + V(φ) constant."""
    motion = rd.differential_form(crank, "q1", 0.3, 6.0, 0.2, 1e-3)
    data = check_result(motion)
    assert data["input"] == "q1" and data["units"]["speed"] == "rad/s"
    guess = None
    total = []
    for phi, kinetic in zip(motion.phi, motion.kinetic_energy):
        guess = assemble(crank, {"q1": phi}, guess)
        total.append(kinetic + mechatron.dynamics.potential_energy(crank, guess))
    assert np.ptp(total) < 1e-8 * max(total)
    assert list(motion.to_frame().columns) == ["t", "q1", "qd_q1", "qdd_q1", "J_reduced", "M_reduced",
                                               "kinetic_energy"]


def test_motion_regimes_of_closed_form_motions():
    t = np.linspace(0.0, 3.0, 30001)
    steady = rd.motion_regimes(t, 5.0 * t, np.full_like(t, 5.0))  # constant speed: ω_mean = 5, δ = 0
    data = check_result(steady)
    assert [c["regime"] for c in data["cycles"]] == ["steady"] * 2
    assert data["cycles"][0]["omega_mean"] == pytest.approx(5.0) and data["cycles"][0]["fluctuation"] == 0.0
    # constant acceleration α from ω0: cycle k starts at ω = √(ω0² + 2 α 2π k)
    alpha, omega0 = 2.0, 3.0
    speeding = rd.motion_regimes(t, omega0 * t + alpha * t**2 / 2, omega0 + alpha * t)
    check_result(speeding)
    assert set(speeding.regimes) == {"run-up"}
    for c in speeding.cycles:
        assert c.omega_start == pytest.approx(math.sqrt(omega0**2 + 2 * alpha * 2 * math.pi * c.cycle), rel=1e-6)


def test_kinetostatics_reports_the_hand_computed_forces(crank):
    """The crank-slider case of test_closed_loop_dynamics: M_D = 63.112255 N·m, slider on rod 1009.9501, −120.2979 N."""
    k = kinetostatics(crank, assemble(crank, {"q1": math.radians(30)}), {"q1": 10.0},
                      loads=[mechatron.Load("C@slider", [1000.0, 0.0, 0.0])])
    data = check_result(k)
    assert data["driving"]["q1"] == pytest.approx(63.112255, abs=1e-6)
    assert data["zhukovsky"]["q1"] == pytest.approx(63.112255, abs=1e-6) and data["units"]["q1"] == "N·m"
    np.testing.assert_allclose(data["pins"]["C=C@slider"], [1009.9501, -120.2979], atol=1e-4)
    frame = k.to_frame()
    pin_row = frame[frame["kind"] == "pin"].iloc[0]
    assert (pin_row["force_x"], pin_row["force_y"]) == (pytest.approx(1009.9501, abs=1e-4),
                                                       pytest.approx(-120.2979, abs=1e-4))
    assert (pin_row["x"], pin_row["y"]) == (pytest.approx(0.1 * math.cos(math.radians(30))
                                                          + math.sqrt(0.4**2 - 0.05**2)), pytest.approx(0.0, abs=1e-12))

"""Closed-loop dynamics, kinetostatics ([Egorov, ch. 5]) and the reduced one-mass model ([Egorov, ch. 6]).

The crank-slider numbers were worked by hand by the force analysis of [Egorov, section 5.6] (the central
crank-slider of [Egorov, fig. 5.7]) with chosen dimensions and masses, by two independent methods, the reaction
chain of the Assur dyad and the power balance (Zhukovsky's lever, [Egorov, 5.18]): l1 = 0.1, L2 = 0.4 m,
q1 = 30°, q̇1 = 10 rad/s, q̈1 = 0, rod 2 kg at its middle with J_S2 = m L²/12, slider 1 kg, crank balanced,
g = 9.81 m/s², 1000 N on the slider along +x.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron import dynamics as dyn
from mechatron.dynamics import constrained as cd
from mechatron.dynamics import reduced as rd
from mechatron.dynamics.kinetostatics import kinetostatics
from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity, loop_solver
from mechatron.kinematics.sweeps import sweep

SLIDER_LOAD = [("C@slider", [1000.0, 0.0, 0.0])]


@pytest.fixture(scope="module")
def crank():
    return mechatron.load("crank_slider")


def test_crank_slider_kinetostatics(crank):
    q = assemble(crank, {"q1": math.radians(30)})
    k = kinetostatics(crank, q, {"q1": 10.0}, loads=SLIDER_LOAD)
    assert k.driving["q1"] == pytest.approx(63.112255, abs=1e-6)  # M_D
    assert k.zhukovsky["q1"] == pytest.approx(63.112255, abs=1e-6)  # Zhukovsky's lever (virtual power)
    # force of the slider on the rod at C, of the crank on the rod at B, of the guide on the slider
    np.testing.assert_allclose(k.reactions.pins["C=C@slider"], [1009.9501, -120.2979], atol=1e-4)
    np.testing.assert_allclose(k.reactions.joints[1, :2], [-1028.5605, 134.9179], atol=1e-4)
    assert k.reactions.joints[2, 1] == pytest.approx(-110.4879, abs=1e-4)
    assert k.reactions.joints[0, 5] == pytest.approx(63.112255, abs=1e-6)  # the crank's moment at A
    inertia = {b.body: b for b in k.inertia}
    np.testing.assert_allclose(inertia["rod"].force[:2], [18.61039, 5.0], atol=1e-5)  # Φ2 = −m2 a_S2
    assert inertia["rod"].couple[2] == pytest.approx(-0.3199699, abs=1e-7)  # M_И2 = −J_S2 ε2
    assert inertia["slider"].force[0] == pytest.approx(9.950133, abs=1e-6)
    # quasi-static part only (no inertia, no gravity): M_D = F3 |v_qC| = 60.910895 N·m
    static = mechatron.load("crank_slider")
    static.model.gravity = pin.Motion.Zero()
    ks = kinetostatics(static, q, {"q1": 1e-9}, loads=SLIDER_LOAD)
    assert ks.driving["q1"] == pytest.approx(60.910895, abs=1e-5)


def test_forward_dynamics_matches_pinocchio_constraint_dynamics(crank, rng):
    """The KKT solution against Pinocchio's own proximal constrained dynamics with a 3-D point contact."""
    model = crank.model
    a_frame, b_frame = model.frames[crank.frame_id("C")], model.frames[crank.frame_id("C@slider")]
    contact = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, model, a_frame.parentJoint, a_frame.placement,
                                       b_frame.parentJoint, b_frame.placement, pin.ReferenceFrame.LOCAL)
    contact_data = contact.createData()
    data = model.createData()
    pin.initConstraintDynamics(model, data, [contact], [contact_data])
    settings = pin.ProximalSettings(1e-14, 1e-12, 200)
    for _ in range(5):
        q = assemble(crank, {"q1": rng.uniform(-3, 3)})
        v = joint_velocity(crank, q, {"q1": rng.normal() * 5})
        tau = rng.normal(size=3)
        ours, _ = cd.forward(crank, q, v, {"q1": tau[0], "phi2": tau[1], "xC": tau[2]})
        theirs = pin.constraintDynamics(model, data, q, v, tau, [contact], [contact_data], settings)
        np.testing.assert_allclose(ours, theirs, atol=1e-8)


def test_inverse_and_forward_dynamics_agree(rng):
    mech = mechatron.load("six_bar_bucket")
    q = assemble(mech, {"L1": 1.5})
    v = joint_velocity(mech, q, {"L1": 0.1})
    a = joint_acceleration(mech, q, v, {"L1": 0.3})
    forces, lam = cd.inverse(mech, q, v, a, loads=[("K", [2000.0, -5000.0, 0.0])])
    a2, lam2 = cd.forward(mech, q, v, forces, loads=[("K", [2000.0, -5000.0, 0.0])])
    np.testing.assert_allclose(a2, a, atol=1e-8)
    np.testing.assert_allclose(lam2, lam, rtol=1e-7)
    # virtual power: the cylinder force equals the reduced force Sᵀ(M q̈ + h − Q)
    S = joint_velocity(mech, q, {"L1": 1.0})
    need = pin.rnea(mech.model, mech.data, q, v, a) + \
        mechatron.frame_jacobian(mech, q, "K")[:3].T @ -np.array([2000.0, -5000.0, 0.0])
    assert forces["L1"] == pytest.approx(S @ need, rel=1e-9)


def test_simulation_keeps_constraints_and_energy(crank):
    q0 = assemble(crank, {"q1": 0.2})
    v0 = joint_velocity(crank, q0, {"q1": 8.0})
    sim = cd.simulate(crank, q0, v0, 5.0, 1e-3)  # no drive, no damping: only gravity, which is conservative
    assert sim.residual.max() < 1e-8
    assert np.abs(sim.energy - sim.energy[0]).max() / sim.energy[0] < 1e-6
    velocity_constraint = max(np.abs(loop_solver(crank).system.evaluate(q)[1] @ v).max()
                              for q, v in zip(sim.q[::50], sim.v[::50]))
    assert velocity_constraint < 1e-10


def test_reduced_inertia_gives_the_kinetic_energy():
    for name, input, rate in (("crank_slider", "q1", 3.0), ("six_bar_bucket", "L1", 0.2), ("grab", "phi1", 0.7),
                              ("slotted_link", "q1", -2.0)):
        mech = mechatron.load(name)
        for q in sweep(mech, samples=7).q:
            J = dyn.reduced_inertia(mech, q, input)
            v = joint_velocity(mech, q, {input: rate})
            assert 0.5 * J * rate**2 == pytest.approx(dyn.kinetic_energy(mech, q, v), rel=1e-12)


def test_reduced_inertia_derivative_equals_finite_differences():
    h = 1e-6
    for name, input, values in (("crank_slider", "q1", (0.3, 1.9, 4.0)), ("six_bar_bucket", "L1", (1.2, 1.6, 1.9))):
        mech = mechatron.load(name)
        for value in values:
            q = assemble(mech, {input: value})
            J = [dyn.reduced_inertia(mech, assemble(mech, {input: value + s * h}, q), input) for s in (1, -1)]
            assert dyn.reduced_inertia_derivative(mech, q, input) == pytest.approx((J[0] - J[1]) / (2 * h),
                                                                                          rel=1e-6, abs=1e-9)


def test_reduced_moment_of_gravity_is_minus_the_derivative_of_potential_energy():
    mech = mechatron.load("six_bar_bucket")
    q = assemble(mech, {"L1": 1.4})
    h = 1e-6
    V = [dyn.potential_energy(mech, assemble(mech, {"L1": 1.4 + s * h}, q)) for s in (1, -1)]
    assert dyn.reduced_moment(mech, q, "L1") == pytest.approx(-(V[0] - V[1]) / (2 * h), rel=1e-6)


def motor(t, q, v):
    return {"q1": 5.0 * (1.0 - v[0] / 30.0)}  # a shunt motor characteristic M = M0 (1 − ω/ω0)


def slider_damper(t, q, v):
    return [("C@slider", [-40.0 * v[2], 0.0, 0.0])]


def test_one_mass_model_reproduces_the_full_simulation(crank):
    q0 = assemble(crank, {"q1": 0.0})
    v0 = joint_velocity(crank, q0, {"q1": 1.0})
    dt, duration = 5e-4, 0.4
    full = cd.simulate(crank, q0, v0, duration, dt, actuation=motor, loads_at=slider_damper)
    one = rd.differential_form(crank, "q1", 0.0, 1.0, duration, dt, actuation=motor, loads_at=slider_damper)
    np.testing.assert_allclose(one.phi, full.q[:, 0], atol=1e-8)
    np.testing.assert_allclose(one.omega, full.v[:, 0], rtol=1e-7, atol=1e-7)
    # ½ J_пр ω² is the kinetic energy along the motion [Egorov, 6.6]
    kinetic = np.array([dyn.kinetic_energy(crank, q, v) for q, v in zip(full.q, full.v)])
    np.testing.assert_allclose(0.5 * one.inertia * one.omega**2, kinetic, rtol=1e-6)


def test_energy_form_matches_the_simulation_for_a_position_dependent_moment(crank):
    """With M_пр depending on φ only (a constant torque and gravity), [Egorov, 6.40] gives ω(φ) without time."""
    q0 = assemble(crank, {"q1": 0.0})
    full = cd.simulate(crank, q0, joint_velocity(crank, q0, {"q1": 2.0}), 0.5, 5e-4,
                       actuation=lambda t, q, v: {"q1": 1.5})
    phi = full.q[:, 0]  # the energy form on the positions the simulation went through
    table = rd.reduced_table(crank, "q1", phi, forces={"q1": 1.5})
    omega = rd.energy_form(phi, table.inertia, table.moment, 2.0)
    np.testing.assert_allclose(omega, full.v[:, 0], rtol=1e-5)


def test_motion_regimes_and_speed_fluctuation(crank):
    q0 = assemble(crank, {"q1": 0.0})
    sim = cd.simulate(crank, q0, joint_velocity(crank, q0, {"q1": 1.0}), 2.5, 1e-3, actuation=motor,
                      loads_at=slider_damper)
    regimes = rd.motion_regimes(sim.t, sim.q[:, 0], sim.v[:, 0])
    assert regimes.regimes[0] == "run-up"
    assert all(regime == "steady" for regime in regimes.regimes[1:])
    steady = regimes.cycles[-1]
    assert steady.fluctuation == pytest.approx((steady.omega_max - steady.omega_min) / steady.omega_mean)
    # over a steady cycle the work of all forces is zero: the speed returns to its value [Egorov, 6.53]
    assert steady.omega_end == pytest.approx(steady.omega_start, rel=1e-3)
    # switching the motor off (a light damper left) gives a run-down
    off = cd.simulate(crank, sim.q[-1], sim.v[-1], 2.0, 2e-3,
                      loads_at=lambda t, q, v: [("C@slider", [-0.3 * v[2], 0.0, 0.0])])
    regimes = rd.motion_regimes(off.t, off.q[:, 0], off.v[:, 0]).regimes
    assert len(regimes) >= 2 and set(regimes) == {"run-down"}

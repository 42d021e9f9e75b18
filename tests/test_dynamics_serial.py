"""Serial dynamics: RNEA/ABA consistency, energies, joint wrenches, reflected drive inertia and the motor side."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from conftest import random_state

import mechatron
from mechatron import dynamics as dyn
from mechatron.drives.transmission import motor_loads
from mechatron.dynamics import constrained as cd
from mechatron.model.dh import dh_mechanism
from mechatron.model.payload import with_payload
from mechatron.model.planar import GROUND, PlanarBuilder


@pytest.mark.parametrize("name", ["puma560", "scara", "ur5", "articulated_rrr"])
def test_aba_inverts_rnea(rng, name):
    mech = mechatron.load(name)
    Q = mech.random_configuration(rng, 200)  # a batch long enough for the parallel path
    V, A = rng.normal(size=(200, mech.nv)), rng.normal(size=(200, mech.nv))
    tau = mechatron.inverse_dynamics(mech, Q, V, A)
    np.testing.assert_allclose(mechatron.forward_dynamics(mech, Q, V, tau), A, atol=1e-9)
    for i in range(3):  # single states take the serial path and give the same
        np.testing.assert_allclose(mechatron.inverse_dynamics(mech, Q[i], V[i], A[i]), tau[i], atol=1e-12)
        np.testing.assert_allclose(mechatron.forward_dynamics(mech, Q[i], V[i], tau[i]), A[i], atol=1e-9)


def test_terms_of_the_equation_of_motion(rng):
    mech = mechatron.load("puma560")
    q, v, a = random_state(mech, rng)
    M = dyn.mass_matrix(mech, q)
    np.testing.assert_allclose(M, M.T, atol=0)
    np.testing.assert_allclose(mechatron.inverse_dynamics(mech, q, v, a), M @ a + dyn.bias_forces(mech, q, v),
                               atol=1e-10)
    np.testing.assert_allclose(dyn.bias_forces(mech, q, np.zeros(6)), dyn.gravity_torques(mech, q),
                               atol=1e-12)
    assert dyn.kinetic_energy(mech, q, v) == pytest.approx(0.5 * v @ M @ v, rel=1e-12)
    # g(q) = ∂V/∂q by central differences of the potential energy
    h = 1e-6
    grad = [(dyn.potential_energy(mech, q + h * e) - dyn.potential_energy(mech, q - h * e)) / (2 * h)
            for e in np.eye(6)]
    np.testing.assert_allclose(grad, dyn.gravity_torques(mech, q), atol=1e-6)


def test_energy_is_kept_by_an_unforced_simulation():
    """No drive torque, no damping: the mechanical energy of the free arm stays constant (relative drift < 1e-6
    over 5 s)."""
    mech = mechatron.load("articulated_rrr")
    sim = cd.simulate(mech, np.array([0.3, 0.8, -0.6]), np.array([1.0, -0.5, 1.5]), 5.0, 1e-3)
    drift = np.abs(sim.energy - sim.energy[0]).max() / abs(sim.energy[0])
    assert drift < 1e-6
    assert sim.t[-1] == pytest.approx(5.0)


def test_joint_wrenches_carry_the_joint_torques(rng):
    mech = mechatron.load("puma560")
    q, v, a = random_state(mech, rng)
    wrenches = dyn.joint_wrenches(mech, q, v, a)
    tau = mechatron.inverse_dynamics(mech, q, v, a)
    pin.forwardKinematics(mech.model, mech.data, q)
    for j in range(6):
        joint_axis = mech.data.oMi[j + 1].rotation[:, 2]  # DH joints turn about their z axis
        # the wrench through the joint drives the links; the rotor's inertia (armature) is the motor's own
        assert wrenches[j, 3:] @ joint_axis == pytest.approx(tau[j] - mech.model.armature[j] * a[j], abs=1e-9)
    # a static payload: the first joint's force balances the whole weight
    static = dyn.joint_wrenches(mech, q, np.zeros(6), np.zeros(6))
    assert static[0, 2] == pytest.approx(mech.total_mass * 9.81, rel=1e-12)


def test_external_load_equals_jacobian_transpose(rng):
    mech = mechatron.load("ur5")
    q, v, a = random_state(mech, rng)
    force = np.array([10.0, -20.0, 30.0])
    loaded = mechatron.inverse_dynamics(mech, q, v, a, loads=[("tool", force)])
    J = mechatron.frame_jacobian(mech, q, "tool")
    np.testing.assert_allclose(loaded, mechatron.inverse_dynamics(mech, q, v, a) - J[:3].T @ force, atol=1e-10)


def test_reflected_inertia_equals_an_explicit_geared_rotor():
    """A link (inertia I about its pivot) driven through a gear u by a rotor J_r as a separate body coupled by a
    gear closure: q̈ = u τ_m / (I + J_r u²), the armature model's, counted once."""
    u, Jr, I = 50.0, 2e-4, 0.3
    b = PlanarBuilder("geared", gravity=0.0)
    b.point("O", GROUND, (0.0, 0.0))
    b.point("R", GROUND, (0.5, 0.0))
    arm = b.revolute("arm", "O", toward=(1.0, 0.0), coordinate="q", mass=1.0, com=(0.3, 0.0), inertia=I - 0.09)
    b.revolute("rotor", "R", coordinate="motor", inertia=Jr)
    b.gear(arm, "rotor", u)
    explicit = b.build(actuated=["motor"])
    a, _ = cd.forward(explicit, explicit.reference_q, np.zeros(2), forces={"motor": 0.01})
    assert a[0] == pytest.approx(u * 0.01 / (I + Jr * u**2), rel=1e-9)
    assert a[1] == pytest.approx(u * a[0], rel=1e-9)
    # the same with the armature of a DH arm: one revolute link, drive (J_r, u)
    arm_dh = mechatron.load("planar_2r")
    table = arm_dh.dh
    link = replace(table.links[0], drive=mechatron.model.dh.Drive(rotor_inertia=Jr, gear_ratio=u))
    mech = dh_mechanism(replace(table, links=(link,)))
    inertia = dyn.mass_matrix(mech, np.zeros(1))[0, 0]
    bare = dh_mechanism(replace(table, links=(table.links[0],)))
    assert inertia - dyn.mass_matrix(bare, np.zeros(1))[0, 0] == pytest.approx(Jr * u**2, rel=1e-12)


def test_motor_side_with_efficiency_and_power_direction():
    mech = mechatron.load("scara")  # drives with u = 80, 50, 314.159, 20 and η = 0.8, 0.8, 0.9, 0.85
    drive = mech.drives["q1"]
    a = np.array([2.0, 0.0, 0.0, 0.0])
    v = np.array([1.0, 0.0, 0.0, 0.0])
    rotor = drive.rotor_inertia * drive.gear_ratio**2 * a[0]
    for load in (30.0, -30.0):
        tau = np.array([load + rotor, 0.0, 0.0, 0.0])
        loads = motor_loads(mech, v, a, tau)
        expected = drive.rotor_inertia * drive.gear_ratio * a[0] + (
            load / (drive.gear_ratio * drive.efficiency) if load > 0 else load * drive.efficiency / drive.gear_ratio)
        assert loads.torque[0] == pytest.approx(expected, rel=1e-12)
        assert loads.speed[0] == pytest.approx(drive.gear_ratio)
        assert bool(loads.motoring[0]) is (load > 0)
    # lossless drive and no friction: motor power = joint power, τ_m = τ/u
    ideal = replace(mech, drives={n: replace(d, efficiency=1.0) for n, d in mech.drives.items()})
    tau = np.array([12.0, -3.0, 40.0, 0.5])
    v = np.array([0.7, -1.1, 0.2, 3.0])
    loads = motor_loads(ideal, v, np.zeros(4), tau)
    np.testing.assert_allclose(loads.power, tau * v, rtol=1e-12)


def test_payload_adds_its_weight():
    mech = mechatron.load("scara")
    q = np.zeros(4)
    loaded = with_payload(mech, 2.0)
    g = dyn.gravity_torques(loaded, q) - dyn.gravity_torques(mech, q)
    assert g[2] == pytest.approx(-2.0 * 9.81)  # the quill (z down-positive, α2 = 180°) carries the weight
    assert loaded.total_mass == pytest.approx(mech.total_mass + 2.0)

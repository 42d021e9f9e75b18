"""Kinematics against finite differences and the angular-velocity sums of [Egorov, 4.56–4.57], on DH and URDF
robots."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import DH_ROBOTS, central_difference, random_state, time_derivative
from reference import textbook_angular_accelerations, textbook_angular_velocities

import mechatron
from mechatron.kinematics.frames import frame_placement

ALL_ROBOTS = DH_ROBOTS + ["ur5", "panda"]


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_jacobian_equals_finite_differences(rng, name):
    mech = mechatron.load(name)
    for _ in range(5):
        q = mech.random_configuration(rng)
        jac = mechatron.frame_jacobian(mech, q, "tool", "world_aligned")
        linear = central_difference(lambda x: mechatron.kinematics.frame_position(mech, x), q)
        R0 = mechatron.kinematics.frame_rotation(mech, q)
        angular = central_difference(lambda x: pin.log3(mechatron.kinematics.frame_rotation(mech, x) @ R0.T), q)
        np.testing.assert_allclose(jac[:3], linear, atol=1e-8)
        np.testing.assert_allclose(jac[3:], angular, atol=1e-8)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_point_velocity_and_acceleration_along_a_trajectory(rng, name):
    """v = d r/dt (4.47) and a = d v/dt (4.49) along q(t) = q0 + q̇0 t + q̈0 t²/2, for a point off the frame origin."""
    mech = mechatron.load(name)
    offset = np.array([0.03, -0.05, 0.08])
    q0, v0, a0 = random_state(mech, rng)

    def q_of(t):
        return q0 + v0 * t + 0.5 * a0 * t**2

    def position(t):
        placement = frame_placement(mech, q_of(t), "tool")
        return placement.translation + placement.rotation @ offset

    def velocity(t):
        return mechatron.kinematics.point_velocity(mech, q_of(t), v0 + a0 * t, "tool", offset=offset)

    np.testing.assert_allclose(velocity(0.0), time_derivative(position), atol=1e-8)
    np.testing.assert_allclose(mechatron.kinematics.point_acceleration(mech, q0, v0, a0, "tool", offset=offset),
                               time_derivative(velocity), atol=1e-7)
    # and the point Jacobian gives the same velocity: v = J q̇ (4.47)
    np.testing.assert_allclose(mechatron.kinematics.point_jacobian(mech, q0, "tool", offset=offset) @ v0, velocity(0.0),
                               atol=1e-12)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_link_angular_acceleration_is_derivative_of_angular_velocity(rng, name):
    mech = mechatron.load(name)
    q0, v0, a0 = random_state(mech, rng)

    def omega(t):
        return mechatron.kinematics.link_angular_velocities(mech, q0 + v0 * t + 0.5 * a0 * t**2, v0 + a0 * t)

    np.testing.assert_allclose(mechatron.kinematics.link_angular_accelerations(mech, q0, v0, a0),
                               time_derivative(omega), atol=1e-7)
    # per-link functions agree with the all-links form
    for k, link in enumerate(mech.link_names):
        np.testing.assert_allclose(mechatron.kinematics.angular_velocity(mech, q0, v0, link), omega(0.0)[k], atol=1e-13)


@pytest.mark.parametrize("name", DH_ROBOTS)
def test_angular_velocity_and_acceleration_equal_textbook_sums(rng, name):
    """Ω_i = Σ σ_j B_{j-1} e_z q̇_j (4.56) and its derivative E_i (4.57), summed independently from the A matrices."""
    mech = mechatron.load(name)
    for _ in range(10):
        q, v, a = random_state(mech, rng)
        np.testing.assert_allclose(mechatron.kinematics.link_angular_velocities(mech, q, v),
                                   textbook_angular_velocities(mech.dh, q, v), atol=1e-12)
        np.testing.assert_allclose(mechatron.kinematics.link_angular_accelerations(mech, q, v, a),
                                   textbook_angular_accelerations(mech.dh, q, v, a), atol=1e-12)


def test_batch_forms_equal_single_calls(rng):
    mech = mechatron.load("puma560")
    Q = mech.random_configuration(rng, size=25)
    V = rng.normal(size=(25, 6))
    A = rng.normal(size=(25, 6))
    positions, rotations, jacobians = mechatron.kinematics.fk_and_jacobian(mech, Q)
    assert positions.shape == (25, 3) and rotations.shape == (25, 3, 3) and jacobians.shape == (25, 6, 6)
    np.testing.assert_allclose(mechatron.kinematics.frame_position(mech, Q), positions, atol=0)
    np.testing.assert_allclose(mechatron.kinematics.frame_rotation(mech, Q), rotations, atol=0)
    velocities = mechatron.kinematics.point_velocity(mech, Q, V)
    accelerations = mechatron.kinematics.point_acceleration(mech, Q, V, A)
    omegas = mechatron.kinematics.link_angular_velocities(mech, Q, V)
    assert velocities.shape == (25, 3) and omegas.shape == (25, 6, 3)
    for i in range(25):
        placement = frame_placement(mech, Q[i])
        np.testing.assert_allclose(positions[i], placement.translation, atol=1e-15)
        np.testing.assert_allclose(rotations[i], placement.rotation, atol=1e-15)
        np.testing.assert_allclose(jacobians[i], mechatron.frame_jacobian(mech, Q[i]), atol=1e-15)
        np.testing.assert_allclose(velocities[i], mechatron.kinematics.point_velocity(mech, Q[i], V[i]), atol=1e-15)
        np.testing.assert_allclose(accelerations[i], mechatron.kinematics.point_acceleration(mech, Q[i], V[i], A[i]),
                                   atol=1e-15)
        np.testing.assert_allclose(omegas[i], mechatron.kinematics.link_angular_velocities(mech, Q[i], V[i]),
                                   atol=1e-15)
        np.testing.assert_allclose(jacobians[i][:3] @ V[i], velocities[i], atol=1e-12)


def test_local_and_world_aligned_jacobians(rng):
    mech = mechatron.load("ur5")
    q = mech.random_configuration(rng)
    R = mechatron.kinematics.frame_rotation(mech, q)
    aligned = mechatron.frame_jacobian(mech, q, reference="world_aligned")
    local = mechatron.frame_jacobian(mech, q, reference="local")
    np.testing.assert_allclose(local[:3], R.T @ aligned[:3], atol=1e-13)
    np.testing.assert_allclose(local[3:], R.T @ aligned[3:], atol=1e-13)
    # Pinocchio's spatial WORLD Jacobian: linear part is the velocity of the body point at the world origin,
    # v_O = v_p + ω × (O − p) = v_p + p × ω
    world = mechatron.frame_jacobian(mech, q, reference="world")
    p = mechatron.kinematics.frame_position(mech, q)
    np.testing.assert_allclose(world[:3], aligned[:3] + np.cross(p[:, None], aligned[3:], axis=0), atol=1e-13)


def test_shape_errors_are_clear():
    mech = mechatron.load("puma560")
    with pytest.raises(mechatron.InputError, match="must have 6 values for puma560"):
        mechatron.kinematics.frame_position(mech, [0.1, 0.2])
    with pytest.raises(mechatron.InputError, match="v must have shape"):
        mechatron.kinematics.point_velocity(mech, np.zeros((3, 6)), np.zeros((2, 6)))
    with pytest.raises(mechatron.InputError, match="unknown frame of puma560 'tol'; did you mean tool"):
        mechatron.kinematics.frame_position(mech, np.zeros(6), "tol")
    with pytest.raises(mechatron.InputError, match="unknown reference"):
        mechatron.frame_jacobian(mech, np.zeros(6), reference="global")
    with pytest.raises(mechatron.InputError, match="finite"):
        mechatron.kinematics.frame_position(mech, [np.nan] * 6)


def test_every_kinematics_name_resolves_with_units_in_its_docstring():
    import importlib
    import inspect

    kinematics = importlib.import_module("mechatron.kinematics")
    importlib.import_module("mechatron.kinematics.sweeps")  # importing the modules does not hide the functions
    importlib.import_module("mechatron.kinematics.vector_plans")
    assert inspect.isfunction(kinematics.sweep) and inspect.isfunction(kinematics.plans)
    for name in kinematics.__all__:
        value = getattr(kinematics, name)
        assert callable(value) and not inspect.ismodule(value), name
        doc = inspect.getdoc(value) or ""
        assert doc.strip(), f"{name} has no docstring"
        numeric = name not in ("loop_solver", "reference_frame", "key_below") and not name.startswith("draw_")
        if inspect.isfunction(value) and numeric:
            assert any(unit in doc for unit in ("(m", "m/s", "rad", " m)", "metres", "(nq,)")), f"{name}: no units"

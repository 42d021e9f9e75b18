"""The arms of [Egorov, section 4.1] (the planar 2R arm of fig. 4.7, the cylindrical robot of fig. 4.8, the
articulated robot of fig. 4.9) against their closed forms.

The closed forms are re-derived here by hand; the printed misprints are corrected and named where they matter:
- 2R arm, acceleration of C (fig. 4.7): the book's ÿ_C has l2·cos q1·q̈1 where differentiation gives l1·cos q1·q̈1;
- 2R arm: the modulus of the acceleration is labelled v_c; it is a_C;
- cylindrical robot (fig. 4.8): "z_Δ = q̈2" is z̈_D = q̈2.
The worked values below (the book prints none) were computed from these closed forms and checked by central finite
differences of the position functions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechatron

angles = st.floats(-3.0, 3.0)
rates = st.floats(-3.0, 3.0)


def planar_2r(l1, l2, q, qd, qdd):
    """Position, velocity and acceleration of C (section 4.1, fig. 4.7), with the book's l2 in ÿ_C corrected to l1."""
    q1, q2 = q
    d1, d2 = qd
    a1, a2 = qdd
    s1, c1, s12, c12 = math.sin(q1), math.cos(q1), math.sin(q1 + q2), math.cos(q1 + q2)
    pos = [l1 * c1 + l2 * c12, l1 * s1 + l2 * s12, 0.0]
    vel = [-l1 * s1 * d1 - l2 * s12 * (d1 + d2), l1 * c1 * d1 + l2 * c12 * (d1 + d2), 0.0]
    acc = [-l1 * c1 * d1**2 - l1 * s1 * a1 - l2 * c12 * (d1 + d2) ** 2 - l2 * s12 * (a1 + a2),
           -l1 * s1 * d1**2 + l1 * c1 * a1 - l2 * s12 * (d1 + d2) ** 2 + l2 * c12 * (a1 + a2), 0.0]
    return np.array(pos), np.array(vel), np.array(acc)


def cylindrical(l1, q, qd, qdd):
    """Point D of the cylindrical robot (fig. 4.8, α = 90°, β = 270°): x = q3 cos q1, y = q3 sin q1, z = l1 + q2."""
    q1, q2, q3 = q
    d1, d2, d3 = qd
    a1, a2, a3 = qdd
    s, c = math.sin(q1), math.cos(q1)
    pos = [q3 * c, q3 * s, l1 + q2]
    vel = [-q3 * s * d1 + d3 * c, q3 * c * d1 + d3 * s, d2]
    acc = [-q3 * (c * d1**2 + s * a1) - 2 * d3 * s * d1 + a3 * c,
           q3 * (-s * d1**2 + c * a1) + 2 * d3 * c * d1 + a3 * s, a2]
    return np.array(pos), np.array(vel), np.array(acc)


def articulated(l1, l2, l3, q, qd, qdd):
    """Point D of the articulated robot (fig. 4.9, α = 90°): radius ρ = −(l2 sin q2 + l3 sin(q2+q3)),
    x = ρ cos q1, y = ρ sin q1, z = l1 + l2 cos q2 + l3 cos(q2+q3); derivatives by hand."""
    q1, q2, q3 = q
    d1, d2, d3 = qd
    a1, a2, a3 = qdd
    s1, c1, s2, c2 = math.sin(q1), math.cos(q1), math.sin(q2), math.cos(q2)
    s23, c23, d23, a23 = math.sin(q2 + q3), math.cos(q2 + q3), d2 + d3, a2 + a3
    rho = -(l2 * s2 + l3 * s23)
    rho_d = -(l2 * c2 * d2 + l3 * c23 * d23)
    rho_dd = -(l2 * (-s2 * d2**2 + c2 * a2) + l3 * (-s23 * d23**2 + c23 * a23))
    pos = [rho * c1, rho * s1, l1 + l2 * c2 + l3 * c23]
    vel = [rho_d * c1 - rho * s1 * d1, rho_d * s1 + rho * c1 * d1, -l2 * s2 * d2 - l3 * s23 * d23]
    acc = [rho_dd * c1 - 2 * rho_d * s1 * d1 - rho * c1 * d1**2 - rho * s1 * a1,
           rho_dd * s1 + 2 * rho_d * c1 * d1 - rho * s1 * d1**2 + rho * c1 * a1,
           -l2 * (c2 * d2**2 + s2 * a2) - l3 * (c23 * d23**2 + s23 * a23)]
    return np.array(pos), np.array(vel), np.array(acc)


def kinematics(mech, q, qd, qdd):
    return (mechatron.kinematics.frame_position(mech, q), mechatron.kinematics.point_velocity(mech, q, qd),
            mechatron.kinematics.point_acceleration(mech, q, qd, qdd))


def test_planar_2r_worked_values():
    mech = mechatron.load("planar_2r")
    q, qd, qdd = np.radians([30.0, 45.0]), np.array([1.0, 2.0]), np.array([0.5, -1.0])
    pos, vel, acc = kinematics(mech, q, qd, qdd)
    np.testing.assert_allclose(pos, [0.5365403, 0.6363703, 0.0], atol=1e-7)
    np.testing.assert_allclose(vel, [-1.409111, 0.7435956, 0.0], atol=1e-6)
    np.testing.assert_allclose(acc, [-1.296576, -3.562590, 0.0], atol=1e-6)
    assert np.linalg.norm(vel) == pytest.approx(1.593276, abs=1e-6)
    assert np.linalg.norm(acc) == pytest.approx(3.791195, abs=1e-6)
    # the printed ÿ_C with l2 in place of l1 (fig. 4.7) would give -3.605892: the book's misprint, not the tool's
    assert acc[1] != pytest.approx(-3.605892, abs=1e-3)


def test_cylindrical_worked_values():
    mech = mechatron.load("cylindrical_rpp")
    q, qd, qdd = np.array([math.radians(30), 0.2, 0.5]), np.array([1.0, 0.1, 0.2]), np.array([0.5, 0.05, -0.1])
    pos, vel, acc = kinematics(mech, q, qd, qdd)
    np.testing.assert_allclose(pos, [0.4330127, 0.25, 0.5], atol=1e-7)
    np.testing.assert_allclose(vel, [-0.07679492, 0.5330127, 0.1], atol=1e-7)
    np.testing.assert_allclose(acc, [-0.8446152, 0.2629165, 0.05], atol=1e-7)
    assert np.linalg.norm(vel) == pytest.approx(0.5477226, abs=1e-7)
    assert np.linalg.norm(acc) == pytest.approx(0.8860023, abs=1e-7)


def test_articulated_worked_values():
    mech = mechatron.load("articulated_rrr")
    q, qd, qdd = np.radians([30.0, 20.0, 40.0]), np.array([1.0, 0.5, -0.5]), np.array([0.2, 0.1, 0.3])
    pos, vel, acc = kinematics(mech, q, qd, qdd)
    np.testing.assert_allclose(pos, [-0.2763594, -0.1595562, 0.8069078], atol=1e-7)
    np.testing.assert_allclose(vel, [0.03748654, -0.3468364, -0.05130302], atol=1e-7)
    np.testing.assert_allclose(acc, [0.4037242, -0.1661246, -0.1673401], atol=1e-7)
    assert np.linalg.norm(acc) == pytest.approx(0.4675397, abs=1e-7)


@settings(max_examples=60, deadline=None)
@given(st.tuples(angles, angles), st.tuples(rates, rates), st.tuples(rates, rates))
def test_planar_2r_closed_form(q, qd, qdd):
    mech = mechatron.load("planar_2r")
    for got, expected in zip(kinematics(mech, q, qd, qdd), planar_2r(0.5, 0.4, q, qd, qdd)):
        np.testing.assert_allclose(got, expected, atol=1e-12)
    # link angular velocities: Ω1 = q̇1 z, Ω2 = (q̇1 + q̇2) z (eq. 4.56)
    omega = mechatron.kinematics.link_angular_velocities(mech, q, qd)
    np.testing.assert_allclose(omega, [[0, 0, qd[0]], [0, 0, qd[0] + qd[1]]], atol=1e-12)
    eps = mechatron.kinematics.link_angular_accelerations(mech, q, qd, qdd)
    np.testing.assert_allclose(eps, [[0, 0, qdd[0]], [0, 0, qdd[0] + qdd[1]]], atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.tuples(angles, st.floats(0.0, 0.5), st.floats(0.2, 0.8)), st.tuples(rates, rates, rates),
       st.tuples(rates, rates, rates))
def test_cylindrical_closed_form(q, qd, qdd):
    mech = mechatron.load("cylindrical_rpp")
    for got, expected in zip(kinematics(mech, q, qd, qdd), cylindrical(0.3, q, qd, qdd)):
        np.testing.assert_allclose(got, expected, atol=1e-12)
    # both prismatic pairs carry the column's rotation only: σ2 = σ3 = 0 in eq. 4.56
    omega = mechatron.kinematics.link_angular_velocities(mech, q, qd)
    np.testing.assert_allclose(omega, [[0, 0, qd[0]]] * 3, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.tuples(angles, angles, angles), st.tuples(rates, rates, rates), st.tuples(rates, rates, rates))
def test_articulated_closed_form(q, qd, qdd):
    mech = mechatron.load("articulated_rrr")
    for got, expected in zip(kinematics(mech, q, qd, qdd), articulated(0.4, 0.3, 0.25, q, qd, qdd)):
        np.testing.assert_allclose(got, expected, atol=1e-12)


def test_planar_3r_closed_form_and_jacobian_of_fig_8_4(rng):
    # x = Σ l_k cos(q1+…+q_k), y = Σ l_k sin(q1+…+q_k) and the partial derivatives written out in
    # [Egorov, section 8, fig. 8.4]
    mech = mechatron.load("planar_3r")
    lengths = [0.4, 0.3, 0.2]
    for _ in range(20):
        q = rng.uniform(-2, 2, 3)
        cum = np.cumsum(q)
        expected = [sum(l * math.cos(c) for l, c in zip(lengths, cum)),
                    sum(l * math.sin(c) for l, c in zip(lengths, cum)), 0.0]
        np.testing.assert_allclose(mechatron.kinematics.frame_position(mech, q), expected, atol=1e-13)
        jac = mechatron.kinematics.point_jacobian(mech, q)
        dx_dq = [-sum(l * math.sin(c) for l, c in zip(lengths[k:], cum[k:])) for k in range(3)]
        dy_dq = [sum(l * math.cos(c) for l, c in zip(lengths[k:], cum[k:])) for k in range(3)]
        np.testing.assert_allclose(jac[0], dx_dq, atol=1e-13)
        np.testing.assert_allclose(jac[1], dy_dq, atol=1e-13)

"""The DH matrices of [Egorov, section 4.3] (eq. 4.40–4.45) and the Pinocchio model built from a DH table.

The reference is an independent NumPy implementation written from the printed element-by-element matrix (4.40), not
from mechatron's code. The book prints the translation column of (4.40) as (a·cos α, a·sin α, S); multiplying out its
own factorisation (4.41)-(4.42), Rz(θ)·Tz(S)·Tx(a)·Rx(α), gives (a·cos θ, a·sin θ, S), and only that version places
the end of the crank of the book's worked example (fig. 4.18) at (l1 cos q1, l1 sin q1). The misprint is corrected here.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
from conftest import DH_ROBOTS
from reference import numpy_chain, textbook_A

import mechatron
from mechatron.kinematics.frames import frame_placement
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism


def random_table(rng: np.random.Generator, convention: str, n: int = 5) -> DHTable:
    links = []
    for i in range(n):
        kind = "prismatic" if i == 2 else "revolute"
        links.append(DHLink(kind, a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-np.pi, np.pi), d=rng.uniform(-0.3, 0.3),
                            theta=rng.uniform(-np.pi, np.pi), lower=-1.0, upper=1.0,
                            inertial=Inertial(rng.uniform(0.5, 3), rng.uniform(-0.1, 0.1, 3),
                                              np.diag(rng.uniform(0.02, 0.04, 3)))))
    return DHTable(tuple(links), convention=convention)


def test_link_matrix_equals_written_out_4_40(rng):
    table = random_table(rng, "standard")
    for i, link in enumerate(table.links, start=1):
        q = rng.uniform(-1, 1)
        theta, S = link.theta_s(q)
        np.testing.assert_allclose(table.A(i, q), textbook_A(theta, S, link.a, link.alpha), atol=1e-15)


def test_link_matrix_is_product_of_elementary_matrices_4_41():
    # A = A^θ · A^S · A^a · A^α with the printed elementary matrices (4.42).
    theta, S, a, alpha = 0.7, 0.2, 0.35, -1.1
    A_theta = np.array([[math.cos(theta), -math.sin(theta), 0, 0], [math.sin(theta), math.cos(theta), 0, 0],
                        [0, 0, 1, 0], [0, 0, 0, 1]])
    A_S = np.eye(4)
    A_S[2, 3] = S
    A_a = np.eye(4)
    A_a[0, 3] = a
    A_alpha = np.array([[1, 0, 0, 0], [0, math.cos(alpha), -math.sin(alpha), 0],
                        [0, math.sin(alpha), math.cos(alpha), 0], [0, 0, 0, 1]])
    table = DHTable((DHLink("revolute", a=a, alpha=alpha, d=S),))
    np.testing.assert_allclose(table.A(1, theta), A_theta @ A_S @ A_a @ A_alpha, atol=1e-15)
    # and the translation is (a cos θ, a sin θ, S), not the printed (a cos α, a sin α, S)
    np.testing.assert_allclose(table.A(1, theta)[:3, 3], [a * math.cos(theta), a * math.sin(theta), S], atol=1e-15)


def test_inverse_is_4_36(rng):
    # Eq. 4.36 (frame i-1 -> frame i) is the inverse of 4.40; check the printed element layout of 4.36.
    theta, S, a, alpha = rng.uniform(-2, 2, 4)
    A36 = np.array([
        [math.cos(theta), math.sin(theta), 0, -a],
        [-math.sin(theta) * math.cos(alpha), math.cos(theta) * math.cos(alpha), math.sin(alpha), -S * math.sin(alpha)],
        [math.sin(theta) * math.sin(alpha), -math.cos(theta) * math.sin(alpha), math.cos(alpha), -S * math.cos(alpha)],
        [0, 0, 0, 1],
    ])
    table = DHTable((DHLink("revolute", a=a, alpha=alpha, d=S),))
    np.testing.assert_allclose(A36 @ table.A(1, theta), np.eye(4), atol=1e-14)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_chain_B_and_pinocchio_frames_equal_numpy_product(rng, convention):
    table = random_table(rng, convention)
    mech = dh_mechanism(table)
    for _ in range(20):
        q = rng.uniform(-1, 1, table.n)
        reference = numpy_chain(table, q)
        pin.framesForwardKinematics(mech.model, mech.data, q)
        for i in range(1, table.n + 1):
            np.testing.assert_allclose(table.B(i, q), reference[i - 1], atol=1e-13)
            np.testing.assert_allclose(mech.data.oMf[mech.frame_id(f"link{i}")].homogeneous, reference[i - 1],
                                       atol=1e-13)
        np.testing.assert_allclose(mech.data.oMf[mech.frame_id("tool")].homogeneous, reference[-1], atol=1e-13)


@pytest.mark.parametrize("name", DH_ROBOTS)
def test_shipped_robots_frames_equal_numpy_product(rng, name):
    mech = mechatron.load(name)
    table = mech.dh
    for _ in range(10):
        q = mech.random_configuration(rng)
        reference = numpy_chain(table, q)
        pin.framesForwardKinematics(mech.model, mech.data, q)
        for i in range(1, table.n + 1):
            np.testing.assert_allclose(mech.data.oMf[mech.frame_id(f"link{i}")].homogeneous,
                                       table.base @ reference[i - 1], atol=1e-13)


def test_base_and_tool_placements():
    base = np.eye(4)
    base[:3, 3] = (1.0, 2.0, 0.5)
    tool = np.eye(4)
    tool[:3, 3] = (0.0, 0.0, 0.1)
    table = DHTable((DHLink("revolute", a=0.5), DHLink("revolute", a=0.4)), base=base, tool=tool)
    mech = dh_mechanism(table)
    q = np.array([0.3, -0.4])
    expected = base @ numpy_chain(table, q)[-1] @ tool
    np.testing.assert_allclose(frame_placement(mech, q, "tool").homogeneous, expected, atol=1e-14)
    np.testing.assert_allclose(frame_placement(mech, q, "base").homogeneous, base, atol=0)


def test_every_length_and_offset_is_a_named_parameter():
    mech = mechatron.load("puma560")
    params = mech.parameters
    assert {f"a{i}" for i in range(1, 7)} <= set(params)
    assert {f"d{i}" for i in range(1, 7)} <= set(params)
    assert params["a2"].value == pytest.approx(0.4318) and params["a2"].unit == "m"
    assert params["d3"].value == pytest.approx(0.15005)
    assert params["alpha1"].value == pytest.approx(math.pi / 2) and params["alpha1"].unit == "rad"


def test_modified_convention_uses_craig_indices():
    table = DHTable((DHLink("revolute", a=0.0, alpha=0.0), DHLink("revolute", a=0.3, alpha=math.pi / 2)),
                    convention="modified")
    names = set(table.parameters())
    assert {"a0", "alpha0", "a1", "alpha1", "d1", "d2", "theta1", "theta2"} == names


def test_parameter_override_changes_geometry():
    # planar 2R: x = l1 cos q1 + l2 cos(q1 + q2) with l2 = a2 overridden to 0.55 m
    mech = mechatron.load("planar_2r", a2=0.55)
    q1, q2 = 0.4, 0.9
    expected = [0.5 * math.cos(q1) + 0.55 * math.cos(q1 + q2), 0.5 * math.sin(q1) + 0.55 * math.sin(q1 + q2), 0.0]
    np.testing.assert_allclose(mechatron.kinematics.frame_position(mech, [q1, q2]), expected, atol=1e-14)
    assert mech.parameters["a2"].value == 0.55
    # the original is untouched and with_parameters gives the same as load(..., **overrides)
    original = mechatron.load("planar_2r")
    assert original.parameters["a2"].value == 0.4
    longer = original.with_parameters(a2=0.55)
    np.testing.assert_allclose(mechatron.kinematics.frame_position(longer, [q1, q2]), expected, atol=1e-14)


def test_unknown_parameter_is_an_error():
    with pytest.raises(mechatron.InputError, match="unknown parameter of puma560 'a7'"):
        mechatron.load("puma560", a7=0.1)


def test_prismatic_offset_adds_to_coordinate():
    # S = q + d for a prismatic pair, θ constant ([Egorov, section 4.3.2])
    table = DHTable((DHLink("prismatic", d=0.2, theta=0.3, lower=0, upper=1),))
    np.testing.assert_allclose(table.A(1, 0.5)[:3, 3], [0.0, 0.0, 0.7], atol=1e-15)
    np.testing.assert_allclose(table.A(1, 0.5)[:3, :3], textbook_A(0.3, 0.7, 0, 0)[:3, :3], atol=1e-15)


def test_drive_inertia_is_reflected_once_into_armature():
    mech = mechatron.load("puma560")
    expected = [2e-4 * 62.6111**2, 2e-4 * 107.815**2, 2e-4 * 53.7063**2,
                3.3e-5 * 76.0364**2, 3.3e-5 * 71.923**2, 3.3e-5 * 76.686**2]
    np.testing.assert_allclose(mech.model.armature, expected, rtol=1e-12)
    # the mass matrix diagonal grows by exactly J·u² compared with the same arm without drives
    bare = dh_mechanism(replace(mech.dh, links=tuple(replace(link, drive=None) for link in mech.dh.links)))
    q = np.array([0.1, 0.7, -2.0, 0.3, 0.4, 0.5])
    M = pin.crba(mech.model, mech.data, q)
    M0 = pin.crba(bare.model, bare.data, q)
    np.testing.assert_allclose(np.diag(M) - np.diag(M0), expected, rtol=1e-12)

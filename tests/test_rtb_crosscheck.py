"""Cross-check against another established robotics library: Peter Corke's Robotics Toolbox for Python.

Its PUMA 560 (models.DH.Puma560) carries the same published kinematic, inertial and motor data as robots/puma560.toml,
computed by its own DH kinematics and recursive Newton-Euler code. Its motor model adds G²·Jm·q̈ to every joint, the
same reflected inertia mechatron puts into Pinocchio's armature; its friction is switched off (mechatron applies
friction outside Pinocchio). Link 1's inertia about axes other than the joint axis differs (see the robot file) and does
not enter any of these quantities.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.kinematics.frames import frame_placement
from mechatron.model.dh import DHLink, DHTable, Drive, Inertial, dh_mechanism

rtb = pytest.importorskip("roboticstoolbox")  # a test dependency: pip install ".[test]"

TOL = 1e-8


@pytest.fixture(scope="module")
def puma_pair():
    return mechatron.load("puma560"), rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)


def mass_matrix(mech, q):
    M = pin.crba(mech.model, mech.data, q)
    return np.triu(M) + np.triu(M, 1).T


def test_puma_matches_published_table(puma_pair):
    mech, robot = puma_pair
    for link, other in zip(mech.dh.links, robot.links):
        assert (link.a, link.alpha, link.d, link.theta) == pytest.approx((other.a, other.alpha, other.d, other.offset))
        assert link.inertial.mass == pytest.approx(other.m)
        np.testing.assert_allclose(link.inertial.com, other.r)
        assert link.drive.reflected_inertia == pytest.approx(other.Jm * other.G**2)
        assert (link.lower, link.upper) == pytest.approx(tuple(other.qlim))


def test_puma_kinematics_and_dynamics_at_random_states(puma_pair, rng):
    mech, robot = puma_pair
    for _ in range(50):
        q = mech.random_configuration(rng)
        v, a = rng.normal(size=6), rng.normal(size=6)
        np.testing.assert_allclose(frame_placement(mech, q, "tool").homogeneous, robot.fkine(q).A, atol=TOL)
        for i, frame in enumerate(robot.fkine_all(q)[1:], start=1):
            np.testing.assert_allclose(frame_placement(mech, q, f"link{i}").homogeneous, frame.A, atol=TOL)
        np.testing.assert_allclose(mechatron.frame_jacobian(mech, q), robot.jacob0(q), atol=TOL)
        np.testing.assert_allclose(mechatron.frame_jacobian(mech, q, reference="local"), robot.jacobe(q), atol=TOL)
        np.testing.assert_allclose(mass_matrix(mech, q), robot.inertia(q), atol=TOL)
        np.testing.assert_allclose(pin.rnea(mech.model, mech.data, q, v, a), robot.rne(q, v, a), atol=TOL)
        np.testing.assert_allclose(pin.computeGeneralizedGravity(mech.model, mech.data, q), robot.gravload(q),
                                   atol=TOL)


def test_modified_dh_matches_toolbox_mdh(rng):
    """A random 5-joint arm (one prismatic) in Craig's convention against the toolbox's RevoluteMDH/PrismaticMDH."""
    links, rtb_links = [], []
    for i in range(5):
        alpha, a, d, theta = rng.uniform(-np.pi, np.pi), rng.uniform(-0.4, 0.4), rng.uniform(-0.3, 0.3), \
            rng.uniform(-np.pi, np.pi)
        m, r, inertia = rng.uniform(0.5, 3.0), rng.uniform(-0.1, 0.1, 3), np.diag(rng.uniform(0.02, 0.04, 3))
        jm, gear = rng.uniform(1e-5, 1e-4), rng.uniform(20, 100)
        prismatic = i == 2
        kind = "prismatic" if prismatic else "revolute"
        links.append(DHLink(kind, a=a, alpha=alpha, d=d, theta=theta, lower=-1.0, upper=1.0,
                            inertial=Inertial(m, r, inertia), drive=Drive(jm, gear)))
        common = dict(a=a, alpha=alpha, offset=d if prismatic else theta, m=m, r=r, I=inertia, Jm=jm, G=gear,
                      qlim=[-1.0, 1.0])
        rtb_links.append(rtb.PrismaticMDH(theta=theta, **common) if prismatic else rtb.RevoluteMDH(d=d, **common))
    mech = dh_mechanism(DHTable(tuple(links), convention="modified"))
    robot = rtb.DHRobot(rtb_links)
    for _ in range(20):
        q = mech.random_configuration(rng)
        v, a = rng.normal(size=5), rng.normal(size=5)
        np.testing.assert_allclose(frame_placement(mech, q, "tool").homogeneous, robot.fkine(q).A, atol=TOL)
        np.testing.assert_allclose(mechatron.frame_jacobian(mech, q), robot.jacob0(q), atol=TOL)
        np.testing.assert_allclose(mass_matrix(mech, q), robot.inertia(q), atol=TOL)
        np.testing.assert_allclose(pin.rnea(mech.model, mech.data, q, v, a), robot.rne(q, v, a), atol=TOL)

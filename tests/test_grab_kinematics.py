"""The half grab [Mikhailov]: the constraints of [Mikhailov, 6] and the closed-form positions for any jaw angle.

The paper gives no numbers; the geometry is the reconstruction documented in mechatron.machines.grab. The closed
form used as the reference here: with the tip r straight below the hinge when closed, x_tip = r sin φ,
y_hinge = η(x_tip) + r cos φ, and the upper crosshead from |P4 − P3| = rod length (checked against the
reconstruction's independent Newton solution: closed jaw y_hinge = 1.104321 m, crosshead 3.050030 m).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity
from mechatron.kinematics.sweeps import sweep
from mechatron.machines.grab import GrabGeometry, grab_spec
from mechatron.model.linkage import build_linkage


@pytest.fixture(scope="module")
def mech():
    return mechatron.load("grab")


def test_structure(mech):
    assert mech.mobility() == 1 and mech.redundant_closure_equations() == 0
    assert mech.actuated == ["phi1"]


def test_positions_equal_closed_form(mech):
    g = GrabGeometry()
    assert g.curvature == pytest.approx(0.5 / 0.9**2)  # A = (e − b)/(L/2 − d)²
    for phi in np.linspace(g.open_angle, 0.0, 9):
        q = assemble(mech, {"phi1": phi})
        expected = g.closed_form(phi)
        for point, key in (("P1", "hinge"), ("P2", "tip"), ("P3", "ear"), ("P4", "pin4")):
            np.testing.assert_allclose(frame_placement(mech, q, point).translation[:2], expected[key], atol=1e-10)
        assert frame_placement(mech, q, "C3").translation[1] == pytest.approx(expected["upper_crosshead"], abs=1e-10)
    closed = g.closed_form(0.0)
    assert closed["hinge"][1] == pytest.approx(1.104321, abs=1e-6)
    assert closed["upper_crosshead"] == pytest.approx(3.050030, abs=1e-6)
    assert g.closed_form(g.open_angle)["tip"] == pytest.approx((-1.4, -0.25))  # x = −L/2, y = −b


def test_constraints_hold_along_the_scoop(mech):
    g = GrabGeometry()
    result = sweep(mech, samples=300)
    assert len(result.failures) == 0
    x, y = result.table["P2_x"].to_numpy(), result.table["P2_y"].to_numpy()
    np.testing.assert_allclose(y, [g.eta(xi) for xi in x], atol=1e-10)  # Φ2: tip on the curve
    np.testing.assert_allclose(result.table["P1_x"], 0.0, atol=1e-12)  # Φ1: hinge on the axis
    assert x[0] == pytest.approx(-1.4) and x[-1] == pytest.approx(0.0, abs=1e-12)
    # the tip's velocity is tangent to the curve: v_y = η'(x) v_x
    vx, vy = result.table["P2_vx"].to_numpy(), result.table["P2_vy"].to_numpy()
    np.testing.assert_allclose(vy, 2 * g.curvature * (x + g.deepest_x) * vx, atol=1e-9)


def test_velocity_and_acceleration_equal_finite_differences(mech):
    h = 1e-6
    for phi in (-0.9, -0.5, -0.1):
        q = assemble(mech, {"phi1": phi})
        plus, minus = assemble(mech, {"phi1": phi + h}, q), assemble(mech, {"phi1": phi - h}, q)
        v = joint_velocity(mech, q, {"phi1": 1.0})
        np.testing.assert_allclose(v, (plus - minus) / (2 * h), atol=1e-7)
        a = joint_acceleration(mech, q, v)
        rate = {"phi1": 1.0}
        np.testing.assert_allclose(a, (joint_velocity(mech, plus, rate) - joint_velocity(mech, minus, rate)) / (2 * h),
                                   atol=1e-5)


def test_bad_geometry():
    """Other curves and jaws go through the reconstruction (the file holds its result)."""
    with pytest.raises(mechatron.InputError, match="cannot open"):
        grab_spec(opening=4.0)
    with pytest.raises(mechatron.InputError, match="scooping curve"):
        grab_spec(depth=0.2)
    deeper = build_linkage(grab_spec(depth=0.8))
    assert math.isfinite(deeper.reference_q.sum())
    assert not any("closed by moving" in note for note in deeper.notes)  # the reconstruction draws it exactly
    g = GrabGeometry(depth=0.8)
    q = assemble(deeper, {"phi1": -0.4})
    np.testing.assert_allclose(frame_placement(deeper, q, "P2").translation[:2], g.closed_form(-0.4)["tip"], atol=1e-10)

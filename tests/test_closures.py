"""Closures evaluated on their own: a gear pair alone closes its loop by the coordinates (no frames)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechatron.kinematics.loops import assemble, joint_velocity
from mechatron.model.planar import GROUND, PlanarBuilder


def gear_pair(ratio: float, offset: float):
    """Two gears on the ground, q_driven = ratio·q_driver + offset."""
    b = PlanarBuilder("gear_pair")
    b.point("O1", GROUND, (0.0, 0.0))
    b.point("O2", GROUND, (0.3, 0.0))
    driver = b.revolute("driver", "O1", angle=0.0, mass=1.0)
    driven = b.revolute("driven", "O2", angle=offset, mass=2.0)
    b.gear(driver, driven, ratio, offset)
    return b.build(actuated=["driver_angle"], tool="O1")


@pytest.mark.parametrize("ratio, offset", [(-0.5, 0.0), (2.5, 0.3)])
def test_a_gear_alone_closes_by_the_coordinates(ratio, offset):
    mech = gear_pair(ratio, offset)
    for angle in (0.4, -1.2, 2.0):
        q = assemble(mech, {"driver_angle": angle})
        assert q[1] == pytest.approx(ratio * angle + offset, abs=1e-12)
    np.testing.assert_allclose(joint_velocity(mech, q, {"driver_angle": math.pi}), [math.pi, ratio * math.pi], atol=1e-12)

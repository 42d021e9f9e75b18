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
    np.testing.assert_allclose(joint_velocity(mech, q, {"driver_angle": math.pi}), [math.pi, ratio * math.pi],
                               atol=1e-12)


def crank_slider_variant(kind: str, l1: float = 0.1, l2: float = 0.4, q1: float = 1.0):
    """The central crank-slider with a massless slider, closed three ways: a prismatic slider pinned to the rod
    (``pin``), the rod's end on the curve y = 0 (``curve``), or on a line of the ground (``slider``)."""
    B = np.array([l1 * math.cos(q1), l1 * math.sin(q1)])
    C = np.array([B[0] + math.sqrt(l2**2 - B[1] ** 2), 0.0])
    b = PlanarBuilder(f"crank_slider_{kind}")
    b.point("A", GROUND, (0.0, 0.0))
    b.point("guide", GROUND, (0.0, 0.0), direction=(1.0, 0.0))
    crank = b.revolute("crank", "A", toward=B, coordinate="q1", mass=1.0, com=(0.02, 0.01), inertia=1e-3)
    b.point("B", crank, B)
    rod = b.revolute("rod", "B", toward=C, coordinate="phi2", mass=2.0, com=(B + C) / 2, inertia=2.0 * l2**2 / 12)
    b.point("C", rod, C)
    if kind == "pin":
        slider = b.prismatic("slider", "guide", (1.0, 0.0), reference=C[0], coordinate="xC")
        b.point("C_slider", slider, C)
        b.pin("C", "C_slider")
    elif kind == "curve":
        b.on_curve("C", lambda x: 0.0, lambda x: 0.0, lambda x: 0.0, label="y = 0")
    else:
        b.slider("C", "guide")
    return b.build(actuated=["q1"], tool="C")


def test_joint_reactions_do_not_depend_on_how_the_loop_is_closed():
    """The wrenches in the crank's and the rod's joints follow from Newton's laws of the crank and the rod alone, so
    they must be the same whether the rod's end is held by a pinned massless slider, a curve or a line closure: the
    closure's force must enter the joints' equilibrium."""
    from mechatron.dynamics.constrained import inverse, reactions
    from mechatron.kinematics.loops import joint_acceleration

    variants = {kind: crank_slider_variant(kind) for kind in ("pin", "curve", "slider")}
    for angle, rate, acceleration in ((0.7, 12.0, 30.0), (2.5, -8.0, 5.0), (4.0, 20.0, -50.0)):
        wrenches = {}
        for kind, mech in variants.items():
            q = assemble(mech, {"q1": angle})
            v = joint_velocity(mech, q, {"q1": rate})
            a = joint_acceleration(mech, q, v, {"q1": acceleration})
            forces, lam = inverse(mech, q, v, a, loads=[("C", [-150.0, 0.0, 0.0])])
            wrenches[kind] = (forces["q1"], reactions(mech, q, v, a, lam, loads=[("C", [-150.0, 0.0, 0.0])]).joints[:2])
        for kind in ("curve", "slider"):
            assert wrenches[kind][0] == pytest.approx(wrenches["pin"][0], rel=1e-9, abs=1e-9)
            np.testing.assert_allclose(wrenches[kind][1], wrenches["pin"][1], rtol=1e-9, atol=1e-8)


def test_errors_carry_the_inputs_the_residual_and_the_worst_closure():
    """An input outside the loop's reach raises an error that says where: the inputs asked for, the residual left
    and the closure row that would not close; a singular position gives the inputs and the velocity ratio."""
    import mechatron
    from mechatron.errors import SingularityError, UnreachableError
    from mechatron.kinematics.loops import loop_solver

    mech = mechatron.load("crank_slider")
    solver = loop_solver(mech)
    q = np.array(mech.reference_q, dtype=float)
    q[solver.dep] += 5.0  # far from any solution: Newton's method stalls
    q[solver.act] = 1.0
    with pytest.raises(UnreachableError) as caught:
        solver.newton(q, max_iterations=2)
    error = caught.value
    assert error.inputs == {"q1": 1.0}
    assert error.residual > 1e-10 and error.closure in solver.system.row_labels()
    rocker = mechatron.load("crank_slider", l1=0.1, l2=0.4)
    at_dead_centre = assemble(rocker, {"q1": 0.0})
    # the slider as input: at the dead centre the crank angle is not determined
    slider_driven = rocker.with_actuated(["xC"])
    with pytest.raises(SingularityError) as caught:
        joint_velocity(slider_driven, at_dead_centre, {"xC": 1.0})
    assert caught.value.inputs == {"xC": pytest.approx(0.5)} and caught.value.ratio > 1e8

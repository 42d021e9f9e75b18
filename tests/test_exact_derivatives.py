"""Exact parameter derivatives of every kind of mechanism, against converged central differences of the rebuilt
mechanism: the placement twists and inertia derivatives of :func:`mechatron.model.derivatives.placement_derivatives`
and the position sensitivities ∂r/∂l of :func:`mechatron.accuracy.sensitivity.sensitivities` at fixed inputs.

The differences are Richardson's extrapolation of central differences, D = (4 D(h/2) − D(h))/3 (error O(h⁴)), taken
at h and h/2 with h = 1e-3 max(1, |l|): the two extrapolations agreeing shows the differences have converged (their
truncation error is below the tolerance), and the exact derivative must then agree with them to 1e-8 of the
scale: the largest derivative, at least 1 and at least 1e-3 of the largest of the quantities themselves (the inertias
of an excavator are 1e4 kg·m²: their rounding, not their derivative, sets what differences resolve)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

import mechatron
import mechatron.cli
from mechatron.accuracy.sensitivity import sensitivities
from mechatron.model.derivatives import inertia_variation, placement_derivatives, placements
from mechatron.model.dh import dh_mechanism

EXAMPLES = "examples/data/"
MECHANISMS = ["puma560", "scara", "cylindrical_rpp", "articulated_rrr", "planar_2r", "planar_3r", "crank_slider",
              "scotch_yoke", "slotted_link", "six_bar_bucket", "seven_bar", "front_shovel", "grab", "delta",
              EXAMPLES + "four_bar.toml", EXAMPLES + "scissor_lift.toml", EXAMPLES + "turret_arm.urdf",
              "puma560 modified"]
TOLERANCE = 1e-8


def load(name: str) -> mechatron.Mechanism:
    if name.endswith(" modified"):
        arm = mechatron.load(name.split()[0])
        return dh_mechanism(replace(arm.dh, convention="modified"), "puma_modified")
    return mechatron.load(name)


def configurations(mech: mechatron.Mechanism) -> list[np.ndarray]:
    """The reference configuration and one other: the inputs moved a little for a closed loop, a random pose
    within the limits for a serial arm."""
    if mech.closures:
        q = mech.reference_q
        inputs = {n: q[mech.model.joints[mech.joint_id(n)].idx_q] for n in mech.actuated}
        moved = {n: v + (0.05 if mech.joint_kind(n) == "revolute" else 0.01) for n, v in inputs.items()}
        return [q, mechatron.assemble(mech, moved, guess=q)]
    rng = np.random.default_rng(7)
    lower, upper = mech.model.lowerPositionLimit, mech.model.upperPositionLimit
    middle = np.where(np.isfinite(lower) & np.isfinite(upper), (lower + upper) / 2, 0.0)
    return [mech.configuration(np.zeros(mech.nv)), mech.configuration(middle[:mech.nv] + rng.uniform(-0.3, 0.3,
                                                                                                     mech.nv))]


def inputs_of(mech: mechatron.Mechanism, q: np.ndarray) -> dict[str, float]:
    return {n: float(q[mech.model.joints[mech.joint_id(n)].idx_q]) for n in mech.actuated}


def quantities(mech: mechatron.Mechanism, nominal: mechatron.Mechanism, poses: list[np.ndarray]) -> np.ndarray:
    """Everything whose derivative is checked, of ``mech`` (a rebuilt ``nominal``), flattened: every placement's
    local twist from the nominal one (log of M₀⁻¹ M), every joint's dynamic parameters, and the tool's position at
    each pose, the loops closed at the nominal inputs."""
    twists = [pin.log6(m.actInv(p)).vector for m, p in zip(placements(nominal.model), placements(mech.model))]
    dynamic = [inertia.toDynamicParameters() for inertia in mech.model.inertias]
    positions = []
    for q in poses:
        if mech.closures:
            q = mechatron.assemble(mech, inputs_of(nominal, q), guess=q)
        positions.append(mechatron.frame_placement(mech, q).translation)
    return np.concatenate([np.ravel(twists), np.ravel(dynamic), np.ravel(positions)])


def differences(mech: mechatron.Mechanism, name: str, poses: list[np.ndarray], h: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Two Richardson extrapolations (steps h and h/2) of ∂(quantities)/∂l."""
    value = mech.parameters[name].value

    def central(step: float) -> np.ndarray:
        plus, minus = (quantities(mech.with_parameters({name: value + s}), mech, poses) for s in (step, -step))
        return (plus - minus) / (2 * step)

    d = [central(h / 2**k) for k in range(3)]
    return (4 * d[1] - d[0]) / 3, (4 * d[2] - d[1]) / 3


@pytest.mark.parametrize("name", MECHANISMS)
def test_exact_derivatives_are_the_converged_differences(name):
    mech = load(name)
    assert mech.derivatives is not None  # every kind of mechanism carries its exact derivatives
    poses = configurations(mech)
    names = list(mech.parameters)  # every one
    derivatives = placement_derivatives(mech, names)
    exact_positions = sensitivities(mech, np.array(poses), parameters=names, coordinates=[]).matrix  # (2, 3, n_l)
    nj, nf = mech.model.njoints, mech.model.nframes
    split = np.cumsum([6 * (nj + nf), 10 * nj])
    sizes = [1e-3 * np.abs(x).max(initial=0.0) for x in np.split(quantities(mech, mech, poses), split)]
    for k, parameter in enumerate(names):
        exact = np.split(np.concatenate([np.ravel(np.r_[derivatives.joints[k], derivatives.frames[k]]),
                                         np.ravel(derivatives.inertias[k]), np.ravel(exact_positions[:, :, k])]), split)
        h = 1e-3 * max(1.0, abs(mech.parameters[parameter].value))
        for _ in range(4):  # a smaller step where the geometry bends sharply (a triangle near flat)
            coarse, fine = (np.split(x, split) for x in differences(mech, parameter, poses, h))
            scales = [max(1.0, size, np.abs(b).max(initial=0.0)) for b, size in zip(fine, sizes)]
            if all(np.abs(a - b).max(initial=0.0) < TOLERANCE * scale / 10
                   for a, b, scale in zip(coarse, fine, scales)):
                break
            h /= 8
        else:
            pytest.fail(f"{name}: the differences of {parameter} do not converge")
        for label, e, b, scale in zip(("placements", "inertias", "tool positions"), exact, fine, scales):
            assert np.abs(e - b).max(initial=0.0) < TOLERANCE * scale, \
                f"{name} ∂{label}/∂{parameter}: exact {e}, differences {b}"


def test_inertia_variation_is_the_derivative_of_a_moved_inertia():
    """d/dδ exp(η δ)·Y at δ = 0 against central differences of Pinocchio's ``SE3.act`` on an inertia."""
    rng = np.random.default_rng(3)
    inertia = pin.Inertia(2.5, rng.normal(size=3), np.array([[0.3, 0.01, -0.02], [0.01, 0.4, 0.03],
                                                             [-0.02, 0.03, 0.5]]))
    for _ in range(3):
        eta = rng.normal(size=6)
        h = 1e-5
        moved = [pin.exp6(pin.Motion(eta * s)).act(inertia).toDynamicParameters() for s in (h, -h)]
        np.testing.assert_allclose(inertia_variation(inertia, eta), (moved[0] - moved[1]) / (2 * h), atol=1e-8)


# ---------------------------------------------------------------------------------------- bars with in-line pins
def test_a_declared_length_of_a_bar_with_in_line_pins_varies(tmp_path, capsys):
    """--set arm1=1.2001: arm 1's top moves along the bar to 1.2001 m from its foot, the crossing pin K stays at
    the middle of arm 1 and where it is drawn on arm 2 (0.6 m from arm 2's foot), the cylinder length held."""
    mech = mechatron.load(EXAMPLES + "scissor_lift.toml", arm1=1.2001)
    q = mech.reference_q
    at = {n: mechatron.frame_placement(mech, q, n).translation[:2] for n in ("foot1", "top1", "K", "foot2", "top2",
                                                                              "K@arm2")}
    assert math.dist(at["foot1"], at["top1"]) == pytest.approx(1.2001, abs=1e-12)
    assert at["K"] == pytest.approx((at["foot1"] + at["top1"]) / 2, abs=1e-12)
    assert at["K@arm2"] == pytest.approx(at["K"], abs=1e-10)
    assert math.dist(at["foot2"], at["K@arm2"]) == pytest.approx(0.6, abs=1e-12)
    assert math.dist(at["foot2"], at["top2"]) == pytest.approx(1.2, abs=1e-12)
    code = mechatron.cli.main(["linkage", EXAMPLES + "scissor_lift.toml", "--set", "arm1=1.2001", "--samples", "5"])
    assert code == 0, capsys.readouterr().err


def test_moving_a_pin_keeps_a_derived_pin_rigid_on_both_arms():
    """--set P_x=0.81 moves the cylinder's base; the crossing pin K (derived on arm 1, listed by arm 2) stays where
    it is drawn on arm 2: 0.6 m from arm 2's foot and its top, and on arm 1's middle."""
    mech = mechatron.load(EXAMPLES + "scissor_lift.toml", P_x=0.81)
    q = mech.reference_q
    at = {n: mechatron.frame_placement(mech, q, n).translation[:2] for n in ("foot1", "top1", "K", "foot2", "top2",
                                                                              "K@arm2", "P")}
    assert at["P"] == pytest.approx([0.81, -0.15], abs=1e-15)
    assert at["K@arm2"] == pytest.approx(at["K"], abs=1e-10)
    assert math.dist(at["foot2"], at["K@arm2"]) == pytest.approx(0.6, abs=1e-12)
    assert math.dist(at["top2"], at["K@arm2"]) == pytest.approx(0.6, abs=1e-12)
    assert at["K"] == pytest.approx((at["foot1"] + at["top1"]) / 2, abs=1e-12)

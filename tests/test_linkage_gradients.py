"""Exact gradients of the study's ``linkage`` outputs with respect to a mechanism's geometric parameters
(:func:`mechatron.studies.analyses.linkage.gradients`): the crank-slider's closed form, and central differences of the
outputs of rebuilt mechanisms on a four-bar, the scissor lift, the six-link bucket, a spatial delta and the front
shovel's working range."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.kinematics.sweeps import default_inputs
from mechatron.studies.analyses import linkage

DATA = Path(__file__).resolve().parent.parent / "examples" / "data"


def differences(mech, options: dict, parameters: list[str], h: float = 1e-6) -> dict[str, np.ndarray]:
    """d(output)/dl of every output by central differences of ``outputs`` on the rebuilt mechanism (step h of
    max(1, |l|))."""
    values = mech.parameter_values()
    out: dict[str, np.ndarray] = {}
    for k, name in enumerate(parameters):
        step = h * max(1.0, abs(values[name]))
        up = linkage.outputs(mech.with_parameters({name: values[name] + step}), options, 0)
        down = linkage.outputs(mech.with_parameters({name: values[name] - step}), options, 0)
        for key in up:
            out.setdefault(key, np.zeros(len(parameters)))[k] = (up[key] - down[key]) / (2 * step)
    return out


def check_against_differences(mech, options: dict, parameters: list[str], skip: tuple[str, ...] = (),
                              rtol: float = 1e-6) -> dict[str, np.ndarray]:
    """The gradients of every output (but ``skip``) equal central differences to ``rtol`` of the largest entry (or
    of 1 unit per unit: the differences of a derivative that is 0 are the sweep's rounding over the step); the
    outputs are exactly those of ``outputs``."""
    out, grad = linkage.gradients(mech, options, parameters)
    assert out == linkage.outputs(mech, options, 0)
    assert set(grad) == set(out) == set(linkage.gradient_outputs(mech, options))
    numeric = differences(mech, options, parameters)
    for key in out:
        assert grad[key].shape == (len(parameters),)
        if key in skip:
            continue
        scale = max(np.abs(numeric[key]).max(), 1.0)
        assert np.abs(grad[key] - numeric[key]).max() <= rtol * scale, (key, grad[key], numeric[key])
    return grad


# ------------------------------------------------------------------------------------------------ closed form
@pytest.mark.parametrize(("l1", "l2"), [(0.1, 0.4), (0.08, 0.45), (0.12, 0.35), (0.1, 0.35)])
def test_crank_slider_reach_and_travel_are_the_closed_form(l1, l2):
    # x_C = l1 cos q1 + sqrt(l2² − l1² sin² q1): largest l1 + l2 at q1 = 0, smallest l2 − l1 at q1 = π (both are
    # samples of the default 73 from the reference 60°), so reach = l1 + l2 and x_travel = 2 l1 [Egorov, fig. 4.18]
    mech = mechatron.load("crank_slider").with_parameters(l1=l1, l2=l2)
    out, grad = linkage.gradients(mech, {}, ["l1", "l2"])
    assert out["reach_m"] == pytest.approx(l1 + l2, abs=1e-12)
    assert out["x_travel_m"] == pytest.approx(2 * l1, abs=1e-12)
    np.testing.assert_allclose(grad["reach_m"], [1.0, 1.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(grad["x_travel_m"], [2.0, 0.0], rtol=0, atol=1e-12)
    for key in ("height_m", "depth_m", "y_travel_m"):  # the slider stays on y = 0
        np.testing.assert_allclose(grad[key], 0.0, atol=1e-12)


def test_crank_slider_gradients_of_every_parameter_are_the_differences():
    mech = mechatron.load("crank_slider")
    # the slider's y is 0 at every sample: its extremes are ties, their differences noise
    check_against_differences(mech, {"samples": 37}, list(mech.parameters),
                              skip=("height_m", "depth_m", "y_travel_m"))


# ------------------------------------------------------------------------------------------------ differences
@pytest.mark.parametrize("point", [None, "M"])
def test_four_bar_gradients_are_the_central_differences(point):
    mech = mechatron.load(str(DATA / "four_bar.toml"))  # the tool point C, or the coupler's middle M (derived)
    grad = check_against_differences(mech, {"point": point}, ["a", "b", "c", "d", "D_x", "B_x", "C_y"])
    assert np.abs(grad["min_transmission_angle_deg"]).max() > 10  # deg per m: the angle moves


def test_scissor_lift_gradients_with_a_load_and_a_cylinder_table():
    mech = mechatron.load(str(DATA / "scissor_lift.toml"))
    options = {"cylinders": {"cyl": {"bore": 0.08, "rod": 0.045}}, "load": [100.0, -2000.0], "samples": 41}
    # the deck moves straight up (x the same at every sample): reach and x travel are ties over the whole stroke,
    # not differentiable; every other output is
    grad = check_against_differences(mech, options, ["arm1", "arm2", "P_x", "P_y", "deck_y", "top2_y"],
                                     skip=("reach_m", "x_travel_m"))
    assert {"cyl_max_force_N", "cyl_max_pressure_Pa", "min_transmission_angle_deg"} <= set(grad)


def test_six_link_bucket_gradients_are_the_central_differences():
    mech = mechatron.load("six_bar_bucket")
    check_against_differences(mech, {}, ["c", "L2", "L3", "Lk", "A_x", "B_y", "E_x"])


def test_spatial_delta_z_travel_gradient_is_the_central_difference():
    mech = mechatron.load("delta")
    names = list(mech.parameters)[:10]
    # the platform moves along z (all three arms together): x and y are ties at 0 over the sweep
    grad = check_against_differences(mech, {"samples": 21}, names,
                                     skip=("reach_m", "height_m", "depth_m", "x_travel_m", "y_travel_m"))
    assert np.abs(grad["z_travel_m"]).max() > 0.1


def test_front_shovel_working_range_and_cylinder_forces_are_the_central_differences():
    mech = mechatron.load("front_shovel")
    grad = check_against_differences(mech, {"samples": 9, "working_range": True}, ["boom", "l7", "A_x", "D_y"])
    assert np.abs(grad["reach_m"]).max() > 0.1 and np.abs(grad["L1_max_force_N"]).max() > 1e3


# ------------------------------------------------------------------------------------------------ the inputs held
@pytest.mark.parametrize("name", ["crank_slider", "six_bar_bucket", "front_shovel", "seven_bar", "grab", "delta",
                                  str(DATA / "four_bar.toml"), str(DATA / "scissor_lift.toml")])
def test_the_swept_inputs_do_not_move_with_the_parameters(name):
    # the gradients hold the inputs at their samples: limits (strokes) and a crank's reference angle are not moved
    # by any parameter of the shipped mechanisms
    mech = mechatron.load(name)
    nominal = default_inputs(mech, 5)
    for parameter, value in mech.parameter_values().items():
        moved = default_inputs(mech.with_parameters({parameter: value + 1e-3}), 5)
        for key, values in nominal.items():
            np.testing.assert_array_equal(moved[key], values, err_msg=f"{name}: {parameter} moves {key}")


# ------------------------------------------------------------------------------------------------ the interface
def test_gradient_outputs_and_refusals():
    mech = mechatron.load("crank_slider")
    assert {"reach_m", "height_m", "depth_m", "x_travel_m", "y_travel_m", "z_travel_m",
            "min_transmission_angle_deg"} <= set(linkage.GRADIENT_OUTPUTS)
    out, grad = linkage.gradients(mech, {"samples": 13}, [])
    assert out == linkage.outputs(mech, {"samples": 13}, 0)
    assert all(g.shape == (0,) for g in grad.values())
    with pytest.raises(InputError, match="l3"):
        linkage.gradients(mech, {}, ["l1", "l3"])
    with pytest.raises(InputError) as info:
        linkage.gradients(mech, {"samples": 1}, ["l1"])
    assert info.value.field == "samples"

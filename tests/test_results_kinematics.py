"""The kinematics results follow the result protocol, and their numbers agree with closed forms and finite differences:
sweeps, velocity and acceleration plans ([Egorov, fig. 4.10]), the mechanism summary of ``mechatron show``, the frame
pose of ``mechatron fk`` and the Jacobian of ``mechatron jacobian``."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from protocol import check_result

import mechatron
from mechatron.kinematics.frames import frame_position, frame_rotation
from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity
from mechatron.kinematics.summary import (
    FramePose,
    JacobianSummary,
    MechanismSummary,
    frame_pose,
    jacobian_summary,
    mechanism_summary,
)
from mechatron.kinematics.sweeps import SweepResult, sweep
from mechatron.kinematics.vector_plans import Plans, plans

URDF = Path(__file__).parent / "data" / "continuous_prismatic_arm.urdf"


# ----------------------------------------------------------------------------------------------------- sweeps
def test_sweep_result_protocol_and_ranges_against_the_closed_form():
    """Crank-slider l1 = 0.1, l2 = 0.4 over a full turn in 1° steps: the slider runs between l2 − l1 and l1 + l2
    and its speed is |dx_C/dq1| q̇1 with dx_C/dq1 = −l1 sin q1 − l1² sin 2q1 / (2√(l2² − l1² sin² q1))
    ([Egorov, section 4.1, fig. 4.2])."""
    mech = mechatron.load("crank_slider")
    result = sweep(mech, samples=361, rates={"q1": 2.0})
    assert isinstance(result, SweepResult)
    data = check_result(result)
    assert data["samples"] == data["assembled"] == 361 and data["failures"] == []
    assert data["points"]["C"]["x"] == pytest.approx([0.3, 0.5], abs=1e-12)
    q1 = result.table["q1"].to_numpy()
    v_q = -0.1 * np.sin(q1) - 0.01 * np.sin(2 * q1) / (2 * np.sqrt(0.16 - 0.01 * np.sin(q1) ** 2))
    assert data["points"]["C"]["v_max"] == pytest.approx(2.0 * np.abs(v_q).max(), rel=1e-9)
    assert data["rates"] == {"q1": 2.0}
    assert data["inputs"]["q1"] == pytest.approx([q1[0], q1[0] + 2 * math.pi])
    frame = result.to_frame()
    assert frame.equals(result.table) and frame is not result.table
    text = str(result)
    assert "361 of 361 positions analysed" in text and "at rate 2" in text


def rocker():
    """A rocker OR (0.3 m) about O pushed by a cylinder from P = (0.4, −0.1) to R, stroke 0.05 … 0.9 m (most of it
    out of reach), with a transmission angle of at least 30°."""
    from mechatron.model.planar import GROUND, PlanarBuilder

    b = PlanarBuilder("rocker")
    b.point("O", GROUND, (0.0, 0.0))
    b.point("P", GROUND, (0.4, -0.1))
    R = 0.3 * np.array([math.cos(math.pi / 3), math.sin(math.pi / 3)])
    arm = b.revolute("arm", "O", toward=R, coordinate="theta", mass=2.0, com=R / 2, inertia=0.015)
    b.point("R", arm, R)
    b.cylinder("s", "P", "R", stroke=(0.05, 0.9))
    b.line("arm", "O", "R")
    b.transmission_angle("mu", "P", "R", "O", "R", minimum_deg=30)
    return b.build(actuated=["s"], description="cylinder-driven rocker")


def test_sweep_with_failures_and_a_measure_check():
    """The loop closes for s ≤ |OP| + |OR| = √0.17 + 0.3; the transmission angle between the cylinder PR and the
    arm OR follows from the triangle O-P-R: cos ∠ORP = (|OR|² + s² − |OP|²) / (2 |OR| s)."""
    result = sweep(rocker(), {"s": np.linspace(0.2, 0.8, 61)})
    data = check_result(result)
    reach = math.sqrt(0.17) + 0.3
    s = np.linspace(0.2, 0.8, 61)
    assert [f["s"] for f in data["failures"]] == pytest.approx(s[s > reach + 1e-9].tolist())
    assert data["assembled"] == len(s[s <= reach])
    reached = s[s <= reach]
    angle = np.arccos(np.clip((0.09 + reached**2 - 0.17) / (2 * 0.3 * reached), -1, 1))
    mu = np.minimum(angle, math.pi - angle)
    (check,) = data["measures"]
    assert check["min"] == pytest.approx(mu.min(), abs=1e-9) and check["max"] == pytest.approx(mu.max(), abs=1e-9)
    assert check["pass"] is bool(mu.min() >= math.radians(30)) is False
    text = str(result)
    assert f"{len(data['failures'])} positions not analysed" in text and "sample 60 (s = 0.8)" in text
    assert ("PASS" if check["pass"] else "FAIL") in text


def test_sweep_plot_draws_the_positions_and_the_curves_in_their_units():
    mech = mechatron.load("crank_slider")
    result = sweep(mech, {"q1": np.linspace(0.0, math.pi, 19)}, links=["rod"])
    figure = result.plot(curves=["C_v", "rod_omega", "rod_angle"], trace="C", positions=3)
    linkage, *charts = figure.axes
    assert (linkage.get_xlabel(), linkage.get_ylabel()) == ("x (m)", "y (m)")
    assert [ax.get_ylabel() for ax in charts] == ["speed (m/s)", "angular velocity (rad/s)", "angle (deg)"]
    assert all(ax.get_xlabel() == "q1 (deg)" for ax in charts)
    np.testing.assert_allclose(charts[0].get_lines()[0].get_xdata(), np.degrees(np.linspace(0.0, math.pi, 19)))
    # the rod angle θ2 = −β, sin β = l1 sin q1 / l2, in degrees
    np.testing.assert_allclose(charts[2].get_lines()[0].get_ydata(),
                               -np.degrees(np.arcsin(0.25 * np.sin(np.linspace(0.0, math.pi, 19)))), atol=1e-9)
    path = [line for line in linkage.get_lines() if line.get_label() == "path of C"][0]
    np.testing.assert_allclose(path.get_ydata(), 0.0, atol=1e-12)
    assert "path of C" in [text.get_text() for text in figure.legends[0].get_texts()]


# ------------------------------------------------------------------------------------------------------ plans
@pytest.mark.parametrize("name,inputs,rates", [
    ("crank_slider", {"q1": 0.5}, {"q1": 10.0}),
    ("six_bar_bucket", {"L1": 1.5}, {"L1": 0.1}),
    ("slotted_link", {"q1": 2.0}, {"q1": -3.0}),
])
def test_plans_equal_finite_differences_of_the_positions(name, inputs, rates):
    """A plan's velocity of a point is d(position)/dt = dr/du · u̇ and, at a constant input rate, its acceleration
    d²r/du² · u̇² ([Egorov, 4.3, 4.8]): central differences of the assembled positions along the input u."""
    mech = mechatron.load(name)
    (u_name, u), (rate,) = next(iter(inputs.items())), rates.values()
    q = assemble(mech, inputs)
    v = joint_velocity(mech, q, rates)
    result = plans(mech, q, v, joint_acceleration(mech, q, v))
    assert isinstance(result, Plans)
    check_result(result)
    h = 1e-4

    def positions(value):
        placed = assemble(mech, {u_name: value}, q)
        return np.array([frame_position(mech, placed, p)[:2] for p in result.frames])

    ahead, here, behind = positions(u + h), positions(u), positions(u - h)
    table = result.to_frame()
    assert list(table.columns) == ["point", "x", "y", "vx", "vy", "v", "ax", "ay", "a"]
    np.testing.assert_allclose(table[["x", "y"]].to_numpy(), here, atol=1e-12)
    np.testing.assert_allclose(table[["vx", "vy"]].to_numpy(), (ahead - behind) / (2 * h) * rate, atol=1e-7)
    np.testing.assert_allclose(table[["ax", "ay"]].to_numpy(), (ahead - 2 * here + behind) / h**2 * rate**2,
                               atol=2e-5 * max(1.0, np.abs(table[["ax", "ay"]].to_numpy()).max()))
    data = result.as_dict()
    assert data["velocities"][u_name] == pytest.approx(rate)
    first = result.frames[0]
    assert data["points"][first]["velocity"][:2] == pytest.approx(table[["vx", "vy"]].to_numpy()[0].tolist())


def test_plans_chart_shows_the_vectors_from_the_pole():
    """Crank-slider at q1 = 30°, q̇1 = 10 rad/s: the crank pin B moves at ω l1 = 1 m/s perpendicular to AB and
    accelerates at ω² l1 = 10 m/s² toward A ([Egorov, fig. 4.10])."""
    mech = mechatron.load("crank_slider")
    q = assemble(mech, {"q1": math.radians(30)})
    v = joint_velocity(mech, q, {"q1": 10.0})
    result = plans(mech, q, v, joint_acceleration(mech, q, v))
    row = result.to_frame().set_index("point").loc["B"]
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert (row.vx, row.vy, row.v) == pytest.approx((-s, c, 1.0), abs=1e-12)
    assert (row.ax, row.ay, row.a) == pytest.approx((-10 * c, -10 * s, 10.0), abs=1e-12)
    figure = result.plot()
    _, velocity_plan, acceleration_plan = figure.axes
    assert (velocity_plan.get_xlabel(), velocity_plan.get_ylabel()) == ("v_x (m/s)", "v_y (m/s)")
    assert (acceleration_plan.get_xlabel(), acceleration_plan.get_ylabel()) == ("a_x (m/s²)", "a_y (m/s²)")
    arrows = {t.get_text(): t.xy for t in velocity_plan.texts if t.get_text()}
    assert arrows["b"] == pytest.approx((-s, c), abs=1e-12)
    assert "B" in str(result) and "m/s²" in str(result)
    with pytest.raises(mechatron.InputError, match="one configuration"):
        plans(mech, q, v[:2], v)


# ------------------------------------------------------------------------------------------- show, fk, jacobian
def test_mechanism_summary_of_an_arm_and_a_linkage():
    arm = mechatron.load("planar_2r")
    result = mechanism_summary(arm)
    assert isinstance(result, MechanismSummary)
    data = check_result(result)
    assert data["mobility"] == 2 and data["nq"] == 2
    joints = result.to_frame()
    assert joints["name"].tolist() == arm.joint_names and set(joints["unit"]) == {"rad"}
    np.testing.assert_allclose(joints["lower"], arm.model.lowerPositionLimit)
    # the stick figure at the neutral configuration: joint origins at x = 0 and l1 = 0.5, the tool at l1 + l2 = 0.9
    side, top = result.plot().axes
    assert (side.get_xlabel(), side.get_ylabel(), top.get_ylabel()) == ("x (m)", "z (m)", "y (m)")
    links = [line for line in top.get_lines() if line.get_linewidth() == 2.5]
    np.testing.assert_allclose([line.get_xdata() for line in links], [[0.0, 0.0], [0.0, 0.5]], atol=1e-12)
    (tool,) = [line for line in top.get_lines() if line.get_label() == "frame tool"]
    assert (tool.get_xdata()[0], tool.get_ydata()[0]) == pytest.approx((0.9, 0.0), abs=1e-12)
    assert "mobility W = 2" in str(result)

    linkage = mechanism_summary(mechatron.load("crank_slider"))
    data = check_result(linkage)
    assert data["mobility"] == 1 and data["actuated"] == ["q1"] and len(data["closures"]) >= 1
    assert linkage.to_frame()["unit"].tolist() == ["rad", "rad", "m"]
    (ax,) = linkage.plot().axes
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (m)", "y (m)")


def test_frame_pose_reports_joint_coordinates_of_a_continuous_joint():
    """The URDF arm: tool0 at spin θ, shoulder φ, extension s is (L cos φ cos θ, L cos φ sin θ, 0.5 − L sin φ) with
    L = 0.6 + s, rotated by R_z(θ) R_y(φ): roll 0, pitch φ, yaw θ."""
    mech = mechatron.load(str(URDF))
    theta, phi, s = 2.5, 0.4, 0.1
    q = mech.configuration([theta, phi, s])
    assert q.shape == (4,)  # the continuous joint's (cos θ, sin θ)
    result = frame_pose(mech, q, "tool0")
    assert isinstance(result, FramePose)
    data = check_result(result)
    L = 0.6 + s
    assert data["coordinates"] == pytest.approx([theta, phi, s], abs=1e-12)
    assert data["joints"] == ["spin", "shoulder", "extend"]
    assert data["position"] == pytest.approx([L * math.cos(phi) * math.cos(theta), L * math.cos(phi) * math.sin(theta),
                                              0.5 - L * math.sin(phi)], abs=1e-12)
    assert data["rpy"] == pytest.approx([0.0, phi, theta], abs=1e-12)
    row = result.to_frame().iloc[0]
    assert (row.q_spin, row.x, row.yaw, row.r33) == pytest.approx((theta, data["position"][0], theta, math.cos(phi)))
    text = str(result)
    assert "spin = 2.5 rad" in text and "extend = 0.1 m" in text
    side, top = result.plot().axes
    (marker,) = [line for line in side.get_lines() if line.get_label() == "frame tool0"]
    assert (marker.get_xdata()[0], marker.get_ydata()[0]) == pytest.approx((data["position"][0], data["position"][2]))


def test_frame_pose_of_a_linkage_point():
    mech = mechatron.load("crank_slider")
    q = assemble(mech, {"q1": 0.0})
    result = frame_pose(mech, q, "C")
    data = check_result(result)
    assert data["position"] == pytest.approx([0.5, 0.0, 0.0], abs=1e-12)  # l1 + l2 at the dead centre


def test_jacobian_summary_against_finite_differences(rng):
    """Linear rows: ∂r/∂q by central differences of the frame position ([Egorov, 4.47]); angular rows: the axial
    vector of Ṙ Rᵀ by central differences of the rotation; singular values of that matrix by numpy."""
    mech = mechatron.load(str(URDF))
    coordinates = np.array([-2.0, 0.7, 0.2])
    result = jacobian_summary(mech, mech.configuration(coordinates), "tool0")
    assert isinstance(result, JacobianSummary)
    data = check_result(result)
    h = 1e-6
    expected = np.zeros((6, 3))
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        plus, minus = mech.configuration(coordinates + step), mech.configuration(coordinates - step)
        expected[:3, k] = (frame_position(mech, plus, "tool0") - frame_position(mech, minus, "tool0")) / (2 * h)
        rate = (frame_rotation(mech, plus, "tool0") - frame_rotation(mech, minus, "tool0")) / (2 * h)
        w = rate @ frame_rotation(mech, mech.configuration(coordinates), "tool0").T
        expected[3:, k] = [w[2, 1], w[0, 2], w[1, 0]]
    np.testing.assert_allclose(data["jacobian"], expected, atol=1e-8)
    np.testing.assert_allclose(data["singular_values"], np.linalg.svd(expected, compute_uv=False), atol=1e-8)
    table = result.to_frame()
    assert table["component"].tolist() == ["vx", "vy", "vz", "wx", "wy", "wz"]
    assert table["unit"].tolist() == ["m/s"] * 3 + ["rad/s"] * 3
    np.testing.assert_allclose(table[["spin", "shoulder", "extend"]].to_numpy(), expected, atol=1e-8)
    linear, angular = result.plot().axes
    assert linear.get_ylabel() == "∂v/∂q̇ (m/rad or m/m)" and angular.get_ylabel() == "∂ω/∂q̇ (rad/rad or rad/m)"
    bars = [patch.get_height() for patch in linear.patches]
    np.testing.assert_allclose(sorted(bars), sorted(expected[:3].ravel()), atol=1e-8)
    assert "singular values" in str(result) and "spin = -2 rad" in str(result)

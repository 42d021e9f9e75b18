"""Closed loops: the crank-slider (fig. 4.2), scotch-yoke (fig. 4.4) and slotted-link (figs. 4.5–4.6) mechanisms of
[Egorov, section 4.1] against their closed forms, finite differences, assembly failures and branches.

Sign conventions: mechatron measures every angle counter-clockwise. The book's rod angle β of the crank-slider and
its slotted-link angle β are clockwise, so θ2 = −β and θ3 = π − β here. The book prints the crank-slider's
ω_q2 = dβ/dq1 with a minus sign that belongs to the counter-clockwise angle, while its ε_q2 is the derivative of
+dβ/dq1; with θ2 = −β both come out consistent: ω_q2 = −l1 cos q1/√(l2² − l1² sin² q1) and ε_q2 = −d²β/dq1².
The worked values (the book prints none) were computed from the closed forms and checked by central finite
differences of the position functions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechatron
from mechatron.errors import InputError, SingularityError, UnreachableError
from mechatron.kinematics.frames import (
    angular_acceleration,
    angular_velocity,
    frame_placement,
    point_acceleration,
    point_velocity,
)
from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity, loop_solver
from mechatron.kinematics.sweeps import sweep
from mechatron.kinematics.transfer import transfer_functions
from mechatron.model.planar import GROUND, PlanarBuilder

angles = st.floats(-math.pi, math.pi)


# ------------------------------------------------------------------------------------------- closed forms
def crank_slider_closed_form(l1, l2, q):
    root = math.sqrt(l2**2 - l1**2 * math.sin(q) ** 2)
    x = l1 * math.cos(q) + root
    v_q = -l1 * math.sin(q) - l1**2 * math.sin(2 * q) / (2 * root)
    a_q = -l1 * math.cos(q) - (l1**2 / 4) * (4 * math.cos(2 * q) + l1**2 * math.sin(2 * q) ** 2 / root**2) / root
    beta_q = l1 * math.cos(q) / root  # dβ/dq, β clockwise
    beta_qq = l1 * (l1**2 - l2**2) * math.sin(q) / root**3
    return x, v_q, a_q, beta_q, beta_qq


def slotted_link_closed_form(l1, d, q):
    denominator = l1**2 + d**2 - 2 * d * l1 * math.cos(q)
    beta = math.atan2(l1 * math.sin(q), d - l1 * math.cos(q))
    omega_q = l1 * (d * math.cos(q) - l1) / denominator  # [Egorov, 4.10] for the slotted link, β clockwise
    epsilon_q = d * l1 * (l1**2 - d**2) * math.sin(q) / denominator**2  # [Egorov, 4.15], denominator squared
    return beta, omega_q, epsilon_q, math.sqrt(denominator)


@settings(max_examples=40, deadline=None)
@given(angles)
def test_crank_slider_transfer_functions(q):
    mech = mechatron.load("crank_slider")
    qq = assemble(mech, {"q1": q})
    x, v_q, a_q, beta_q, beta_qq = crank_slider_closed_form(0.1, 0.4, q)
    slider = transfer_functions(mech, qq, "q1", frame="C")
    assert frame_placement(mech, qq, "C").translation[0] == pytest.approx(x, abs=1e-12)
    assert slider.first[0] == pytest.approx(v_q, abs=1e-10)
    assert slider.second[0] == pytest.approx(a_q, abs=1e-10)
    rod = transfer_functions(mech, qq, "q1", link="rod")
    assert rod.first == pytest.approx(-beta_q, abs=1e-10)  # θ2 = −β
    assert rod.second == pytest.approx(-beta_qq, abs=1e-10)


def test_crank_slider_point_on_rod():
    """l1 = 0.1, L2 = 0.4, B at mid-rod (the book's fig. 4.2 naming; here point S2), q1 = 30°, q̇1 = 10 rad/s."""
    mech = mechatron.load("crank_slider")
    q = assemble(mech, {"q1": math.radians(30)})
    v = joint_velocity(mech, q, {"q1": 10.0})
    for qdd, expected in ((0.0, [-9.305193, -2.5]), (5.0, [-9.582471, -2.283494])):
        a = joint_acceleration(mech, q, v, {"q1": qdd})
        np.testing.assert_allclose(point_acceleration(mech, q, v, a, "S2")[:2], expected, atol=1e-6)
    np.testing.assert_allclose(frame_placement(mech, q, "S2").translation[:2], [0.2850339, 0.025], atol=1e-7)
    np.testing.assert_allclose(point_velocity(mech, q, v, "S2")[:2], [-0.554554, 0.433013], atol=1e-6)
    np.testing.assert_allclose(point_velocity(mech, q, v, "C")[:2], [-0.6091089, 0.0], atol=1e-7)
    # rod: |ω2| = 2.182179 rad/s; counter-clockwise ω2 = −2.182179, ε2 = +11.998872 (q̈1 = 0)
    assert angular_velocity(mech, q, v, "rod")[2] == pytest.approx(-2.182179, abs=1e-6)
    a = joint_acceleration(mech, q, v, {"q1": 0.0})
    assert angular_acceleration(mech, q, v, a, "rod")[2] == pytest.approx(11.998872, abs=1e-6)


def test_crank_slider_hand_checks():
    mech = mechatron.load("crank_slider")
    q0 = assemble(mech, {"q1": 0.0})
    assert frame_placement(mech, q0, "C").translation[0] == pytest.approx(0.5)
    assert transfer_functions(mech, q0, "q1", frame="C").second[0] == pytest.approx(-0.125)
    assert transfer_functions(mech, q0, "q1", link="rod").first == pytest.approx(-0.25)
    q90 = assemble(mech, {"q1": math.pi / 2})
    assert frame_placement(mech, q90, "C").translation[0] == pytest.approx(0.3872983, abs=1e-7)
    tf = transfer_functions(mech, q90, "q1", frame="C")
    assert tf.first[0] == pytest.approx(-0.1) and tf.second[0] == pytest.approx(0.02581989, abs=1e-8)


@settings(max_examples=40, deadline=None)
@given(angles)
def test_scotch_yoke(q):
    mech = mechatron.load("scotch_yoke")
    qq = assemble(mech, {"q1": q})
    tf = transfer_functions(mech, qq, "q1", frame="C")
    assert frame_placement(mech, qq, "C").translation[0] == pytest.approx(0.1 * math.cos(q), abs=1e-12)
    assert tf.first[0] == pytest.approx(-0.1 * math.sin(q), abs=1e-10)
    assert tf.second[0] == pytest.approx(-0.1 * math.cos(q), abs=1e-10)


def test_scotch_yoke_worked_values():
    # the book's "a_C = −l1 cos q1 q̇1" (fig. 4.4, at q̇1 constant) lacks the square: it would give −0.866
    mech = mechatron.load("scotch_yoke")
    q = assemble(mech, {"q1": math.radians(30)})
    v = joint_velocity(mech, q, {"q1": 10.0})
    assert point_velocity(mech, q, v, "C")[0] == pytest.approx(-0.5)
    for qdd, expected in ((0.0, -8.660254), (5.0, -8.910254)):
        a = joint_acceleration(mech, q, v, {"q1": qdd})
        assert point_acceleration(mech, q, v, a, "C")[0] == pytest.approx(expected, abs=1e-6)


@settings(max_examples=40, deadline=None)
@given(angles)
def test_slotted_link(q):
    mech = mechatron.load("slotted_link")
    qq = assemble(mech, {"q1": q})
    beta, omega_q, epsilon_q, l3 = slotted_link_closed_form(0.1, 0.3, q)
    theta3 = mechatron.kinematics.link_angle(mech, qq, "coulisse")
    assert math.remainder(theta3 - (math.pi - beta), 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    tf = transfer_functions(mech, qq, "q1", link="coulisse")
    assert tf.first == pytest.approx(-omega_q, abs=1e-10)  # θ3 = π − β
    assert tf.second == pytest.approx(-epsilon_q, abs=1e-10)
    assert mechatron.kinematics.distance(mech, qq, "B", "C") == pytest.approx(l3, abs=1e-12)


def test_slotted_link_worked_values():
    mech = mechatron.load("slotted_link")
    q = assemble(mech, {"q1": math.radians(30)})
    v = joint_velocity(mech, q, {"q1": 10.0})
    assert mechatron.kinematics.link_angle(mech, q, "coulisse") == pytest.approx(math.radians(166.813215), abs=1e-8)
    assert angular_velocity(mech, q, v, "coulisse")[2] == pytest.approx(-3.326659, abs=1e-6)
    for qdd, expected in ((0.0, -51.99994), (5.0, -50.33661)):
        a = joint_acceleration(mech, q, v, {"q1": qdd})
        assert angular_acceleration(mech, q, v, a, "coulisse")[2] == pytest.approx(-expected, abs=1e-4)
    # hand checks: q1 = 0 → ω_q3 = l1/(d − l1) = 0.5; q1 = 180° → −0.25; q1 = 90° → −0.1, ε_q3 = −0.24
    for q1, w, e in ((0.0, 0.5, 0.0), (math.pi, -0.25, 0.0), (math.pi / 2, -0.1, -0.24)):
        tf = transfer_functions(mech, assemble(mech, {"q1": q1}), "q1", link="coulisse")
        assert (tf.first, tf.second) == pytest.approx((-w, -e), abs=1e-10)


# ------------------------------------------------------------------------------------- finite differences
@pytest.mark.parametrize("name", ["crank_slider", "scotch_yoke", "slotted_link"])
def test_velocity_and_acceleration_equal_finite_differences(name):
    mech = mechatron.load(name)
    h = 1e-5
    for q1 in np.linspace(-3.0, 3.0, 7):
        q = assemble(mech, {"q1": q1})
        plus, minus = assemble(mech, {"q1": q1 + h}, q), assemble(mech, {"q1": q1 - h}, q)
        v = joint_velocity(mech, q, {"q1": 1.0})
        np.testing.assert_allclose(v, (plus - minus) / (2 * h), atol=1e-8)
        a = joint_acceleration(mech, q, v, {"q1": 0.0})
        v_plus, v_minus = joint_velocity(mech, plus, {"q1": 1.0}), joint_velocity(mech, minus, {"q1": 1.0})
        np.testing.assert_allclose(a, (v_plus - v_minus) / (2 * h), atol=1e-6)


# ------------------------------------------------------------------------------- a cylinder-driven rocker
def rocker(stroke=(0.25, 0.45)):
    """A rocker OR (0.3 m) about O, pushed by a cylinder from P = (0.4, −0.1) to R; drawn at θ = 60°."""
    b = PlanarBuilder("rocker")
    b.point("O", GROUND, (0.0, 0.0))
    b.point("P", GROUND, (0.4, -0.1))
    R = 0.3 * np.array([math.cos(math.pi / 3), math.sin(math.pi / 3)])
    arm = b.revolute("arm", "O", toward=R, coordinate="theta", mass=2.0, com=R / 2, inertia=0.015)
    b.point("R", arm, R)
    b.cylinder("s", "P", "R", stroke=stroke)
    b.line("arm", "O", "R")
    b.transmission_angle("mu", "P", "R", "O", "R", minimum_deg=30)
    return b.build(actuated=["s"], description="cylinder-driven rocker")


def rocker_angle(s):
    """θ from the triangle O-P-R: |R − P| = s with |R| = 0.3 (branch with R above the line OP's start)."""
    # solve 0.3²(cos θ, sin θ) − P: |0.3 e(θ) − P|² = s²
    P = np.array([0.4, -0.1])
    c = (0.09 + P @ P - s**2) / (2 * 0.3 * np.linalg.norm(P))
    phi = math.atan2(P[1], P[0])
    return phi + math.acos(c)


def test_cylinder_rocker_position_and_velocity():
    mech = rocker()
    assert mech.mobility() == 1 and mech.redundant_closure_equations() == 0
    for s in np.linspace(0.26, 0.44, 7):
        q = assemble(mech, {"s": s})
        theta = q[loop_solver(mech).index["theta"]]
        assert theta == pytest.approx(rocker_angle(s), abs=1e-10)
        # lever arm e = dL/dθ, so θ̇ = ṡ / e for a unit cylinder speed
        e = mechatron.kinematics.lever_arm(mech, q, "P", "R", "O")
        v = joint_velocity(mech, q, {"s": 1.0})
        assert v[loop_solver(mech).index["theta"]] == pytest.approx(1.0 / e, rel=1e-9)


def test_assembly_failures_name_inputs_and_residual():
    mech = rocker(stroke=(0.05, 0.9))
    with pytest.raises(UnreachableError, match=r"s = 0.95 is outside its range \[0.05, 0.9\]"):
        assemble(mech, {"s": 0.95})
    # in stroke but longer than |OP| + |OR| = 0.712: the loop cannot close
    with pytest.raises(UnreachableError, match=r"cannot assemble at s = 0.8 .*closure residual"):
        assemble(mech, {"s": 0.8})
    with pytest.raises(InputError, match="unknown actuated coordinate of rocker 'theta'"):
        assemble(mech, {"theta": 0.1})


def test_sweep_marks_unreachable_samples_instead_of_nan_rows(tmp_path):
    mech = rocker(stroke=(0.05, 0.9))
    result = sweep(mech, {"s": np.linspace(0.2, 0.8, 61)})
    assert len(result.failures) > 0 and len(result.table) + len(result.failures) == 61
    assert not result.table.isna().any().any()
    assert set(result.failures.columns) == {"sample", "s", "reason"}
    assert (result.failures["s"] > 0.7).all() and "do not close" in result.failures["reason"].iloc[0]
    # every failure, with its input and reason, in the plain data and the text report; the CSV is the table alone
    data = result.as_dict()
    assert [f["sample"] for f in data["failures"]] == result.failures["sample"].tolist()
    assert data["samples"] == 61 and data["assembled"] == len(result.table)
    assert all(f["s"] > 0.7 and "do not close" in f["reason"] for f in data["failures"])
    assert f"{len(result.failures)} positions not analysed" in str(result)
    import pandas as pd

    written = pd.read_csv(result.write_csv(tmp_path / "rocker.csv"))
    assert list(written.columns) == list(result.table.columns) and len(written) == len(result.table)
    assert not (tmp_path / "rocker.failures.csv").exists()


def test_singular_position_is_reported():
    # the crank-slider driven by its slider (xC) is singular at the dead centre (crank and rod aligned)
    mech = mechatron.load("crank_slider").with_actuated(["xC"])
    dead_centre = np.array([0.0, 0.0, 0.5])  # crank and rod along +x: an exact solution of the closure
    assert np.abs(loop_solver(mech).system.evaluate(dead_centre)[0]).max() < 1e-15
    with pytest.raises(SingularityError, match="singular position"):
        joint_velocity(mech, dead_centre, {"xC": 1.0})


def test_branch_is_kept_and_chosen_by_guess():
    mech = mechatron.load("crank_slider")
    result = sweep(mech, samples=500)
    assert (result.table["C_x"] > 0.29).all()  # the slider stays on the +x branch over a full crank turn
    # the other branch (slider at x = l1 cos q1 − √(…)) by name, and from a rough guess on that side
    left_x = 0.1 * math.cos(0.3) - math.sqrt(0.16 - 0.01 * math.sin(0.3) ** 2)
    other = assemble(mech, {"q1": 0.3}, branch="left")
    assert frame_placement(mech, other, "C").translation[0] == pytest.approx(left_x, abs=1e-12)
    rough = other + 0.01
    rough[0] = 0.3
    assert frame_placement(mech, assemble(mech, {"q1": 0.3}, guess=rough), "C").translation[0] == pytest.approx(
        left_x, abs=1e-12)
    assert sweep(mech, samples=200, guess=mech.branches["left"]).table["C_x"].max() < -0.29
    with pytest.raises(InputError, match="unknown assembly branch of crank_slider 'up'"):
        assemble(mech, {"q1": 0.3}, branch="up")


def test_mobility_and_redundancy_of_a_spatial_pin():
    from mechatron.model.closures import Pin

    mech = mechatron.load("crank_slider").with_closures([Pin("C=C@slider (3 rows)", a="C", b="C@slider",
                                                              planar=False)])
    assert mech.mobility() == 1 and mech.redundant_closure_equations() == 1  # the z row repeats 0 = 0


def test_sweep_velocity_and_acceleration_columns_agree_with_single_calls():
    mech = mechatron.load("slotted_link")
    result = sweep(mech, {"q1": np.linspace(0.0, 2 * math.pi, 50)}, rates={"q1": 3.0}, accelerations={"q1": -2.0},
                   links=["coulisse"])
    for row in result.table.itertuples():
        q = assemble(mech, {"q1": row.q1})
        v = joint_velocity(mech, q, {"q1": 3.0})
        a = joint_acceleration(mech, q, v, {"q1": -2.0})
        assert row.B_vy == pytest.approx(point_velocity(mech, q, v, "B")[1], abs=1e-9)
        assert row.coulisse_epsilon == pytest.approx(angular_acceleration(mech, q, v, a, "coulisse")[2], abs=1e-8)


def test_plans_and_sweep_plots(tmp_path):
    from mechatron.kinematics.vector_plans import plans

    mech = mechatron.load("crank_slider")
    q = assemble(mech, {"q1": 0.5})
    v = joint_velocity(mech, q, {"q1": 10.0})
    a = joint_acceleration(mech, q, v)
    assert plans(mech, q, v, a).save_plot(tmp_path / "plans.png").stat().st_size > 20_000
    result = sweep(rocker(), samples=30)
    figure = result.plot(curves=["mu"], trace="R")
    curves = figure.axes[1]
    assert curves.get_ylabel() == "transmission angle (deg)" and curves.get_xlabel() == "s (m)"
    # the curve is the table's angle in degrees, and the required minimum of 30° is drawn
    mu, minimum = curves.get_lines()
    np.testing.assert_allclose(mu.get_ydata(), np.degrees(result.table["mu"]))
    np.testing.assert_allclose(minimum.get_ydata(), [30.0, 30.0])


def test_linkage_command(tmp_path, capsys):
    import json

    from mechatron.cli import main

    assert main(["linkage", "slotted_link", "--samples", "90", "--json", "--csv", str(tmp_path / "s.csv"),
                 "--plot", str(tmp_path / "s.png"), "--set", "d=0.25"]) == 0
    out, err = capsys.readouterr()
    summary = json.loads(out)
    assert summary["mobility"] == 1 and summary["assembled"] == 90
    assert summary["points"]["B"]["x"] == pytest.approx([-0.1, 0.1], abs=1e-3)
    assert (tmp_path / "s.csv").exists() and (tmp_path / "s.png").exists()
    assert f"wrote {tmp_path / 's.csv'}" in err
    assert main(["linkage", "puma560"]) == 2
    assert "no closed loops" in capsys.readouterr().err
    assert main(["linkage", "crank_slider", "--samples", "20", "--plans", str(tmp_path / "plans.png"),
                 "--at", "q1=0.5"]) == 0
    assert (tmp_path / "plans.png").stat().st_size > 20_000


@pytest.mark.parametrize("name", ["crank_slider", "scotch_yoke", "slotted_link", "six_bar_bucket", "front_shovel",
                                  "seven_bar", "grab"])
def test_every_builtin_mechanism_sweeps_from_the_command_line(name, capsys):
    import json

    from mechatron.cli import main

    assert main(["linkage", name, "--samples", "25", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["assembled"] == 25 and summary["mobility"] == len(summary["actuated"])

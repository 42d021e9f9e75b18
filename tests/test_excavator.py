"""Front-shovel excavator working device [Shovel] against the report's self-consistent numbers, recomputed by hand
from its formulas [Shovel, 3.1–3.19], and against the closed-loop model; the excavator report and its command.

The report's inconsistent numbers are not asserted as results; each one is asserted to differ from what its own
formulas give, with the reason in validation/excavator.py (report_comparison).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import mechatron
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble, loop_solver
from mechatron.machines import excavator as ex
from tests.protocol import check_result
from validation.excavator import comparison_text, report_comparison

DEG = math.pi / 180


@pytest.fixture(scope="module")
def shovel():
    return ex.synthesize()


@pytest.fixture(scope="module")
def mech(shovel):
    """The shipped file robots/front_shovel.toml, which the synthesis wrote (tests/test_pipeline.py)."""
    return mechatron.load("front_shovel")


def test_joint_ranges_by_hand(shovel):
    # MATLAB pipeline of the report with l1 = 4.3, l2 = 3.3, l3 = 2, R0 = 4.2, R1 = 9.06, H1 = 3.2, H2 = 9.53,
    # C = (0.5, 2.7), ζ = 25°, and the text's δ = 40° for θ3min
    l1, l2, l3, xc, yc, zeta = 4.3, 3.3, 2.0, 0.5, 2.7, 25 * DEG
    t2max = math.acos((l1**2 + l2**2 - (9.06 - l3 - xc) ** 2) / (2 * l1 * l2))
    t2min = math.acos((l1**2 + l2**2 - (yc - l3 * math.sin(zeta)) ** 2 - (4.2 - l3 * math.cos(zeta) - xc) ** 2)
                      / (2 * l1 * l2))
    l44 = math.sqrt(l1**2 + l2**2 - 2 * l1 * l2 * math.cos(t2max))
    t1max = math.asin((9.53 - l3 - yc) / l44) + math.asin(l2 * math.sin(t2max) / l44)
    t1min = math.asin((-3.2 - yc + l2 + l3) / l1)
    assert shovel.theta2 == pytest.approx((t2min, t2max), abs=1e-12)
    assert shovel.theta1 == pytest.approx((t1min, t1max), abs=1e-12)
    assert shovel.theta3 == pytest.approx((2 * math.pi - t1max - t2max - 40 * DEG, 2.5 * math.pi - t1max - t2max))
    # the report's rounded values [Shovel, 3.2–3.7]
    assert np.degrees(shovel.theta2) == pytest.approx((38.0, 118.8), abs=0.05)
    assert np.degrees(shovel.theta1) == pytest.approx((-8.0, 73.6), abs=0.05)
    assert np.degrees(shovel.theta3) == pytest.approx((127.7, 257.6), abs=0.1)


def test_special_positions_closed_form_and_model(shovel, mech):
    """Tips of [Shovel, 2.1–2.4] recomputed: (9.060, 2.700), (4.939, 9.530), (4.758, −3.200) and the ground reach
    8.605 (not the printed 8.71)."""
    expected = {"max_digging_radius": (9.06, 2.7), "max_digging_height": (4.939, 9.53),
                "max_digging_depth": (4.758, -3.2), "max_ground_radius": (8.605, 0.0)}
    for name, angles in ex.special_positions(shovel).items():
        assert shovel.tip(*angles) == pytest.approx(expected[name], abs=1e-3)
        # the same tip from the closed-loop model assembled at the matching cylinder lengths
        q = assemble(mech, shovel.cylinder_lengths(*angles))
        np.testing.assert_allclose(frame_placement(mech, q, "V").translation[:2], shovel.tip(*angles), atol=1e-9)
        wrapped = np.remainder(np.subtract(ex.joint_angles(mech, q), angles) + np.pi, 2 * np.pi) - np.pi
        np.testing.assert_allclose(wrapped, 0.0, atol=1e-9)


def test_stick_cylinder_block_as_in_report():
    """[Shovel, 3.14–3.16] with the report's rounded θ2 = 37°…118.8°, λ = 1.7, k = 1, l9 = 1.0 m."""
    c = ex.included_angle_offset(37 * DEG, 118.8 * DEG, 1.7)
    s, r = ex.lever_synthesis(118.8 * DEG + c, 37 * DEG + c, 1.7)
    assert -c / DEG == pytest.approx(4.56, abs=0.01)  # α34 = 4.5° printed
    assert (s, r, 1.7 * r) == pytest.approx((2.636, 1.871, 3.180), abs=1e-3)  # l8 = 2.6, L2 = 1.87 / 3.18 printed
    # equal moment arms at both ends (k = 1): e = l8 l9 sin ψ / L
    cyl = ex.CylinderDesign("L2", s, 1.0, c, (r, 1.7 * r), (37 * DEG, 118.8 * DEG))
    assert cyl.lever_arm(37 * DEG) == pytest.approx(cyl.lever_arm(118.8 * DEG), rel=1e-12)
    assert cyl.lever_arm(37 * DEG) == pytest.approx(0.756, abs=1e-3)
    assert cyl.min_transmission_angle() / DEG == pytest.approx(49.1, abs=0.1)  # 49° printed


def test_bucket_triangle_as_printed():
    """[Shovel, 3.17]: l11 = 0.7, λ = 1.7 and an included angle from 40.0° to 150.2° give l10 = 2.04,
    L3 = 1.57 / 2.67."""
    s, r = ex.lever_synthesis(150.2 * DEG, 40.0 * DEG, 1.7)
    assert (0.7 * s, 0.7 * r, 0.7 * 1.7 * r) == pytest.approx((2.042, 1.572, 2.672), abs=1e-3)


def test_lever_synthesis_closes_both_triangles():
    for psi_start, psi_end, ratio in ((20 * DEG, 110 * DEG, 1.6), (35 * DEG, 140 * DEG, 1.8)):
        s, r = ex.lever_synthesis(psi_end, psi_start, ratio)
        assert ex.triangle_side(1.0, s, psi_start) == pytest.approx(r, rel=1e-12)
        assert ex.triangle_side(1.0, s, psi_end) == pytest.approx(ratio * r, rel=1e-12)
    # a 20° sweep from 80° can stretch a cylinder by at most sin 50°/sin 40° = 1.19 (equal levers)
    with pytest.raises(mechatron.InputError, match="no cylinder with λ = 1.5"):
        ex.lever_synthesis(100 * DEG, 80 * DEG, 1.5)


def test_the_file_has_the_designed_lengths_and_cylinders(shovel, mech):
    """The named lengths of the file are the design's links and the synthesized levers [Shovel, 3.8–3.17]; the boom
    angle is limited to the synthesized θ1 range."""
    d = shovel.design
    boom, stick, bucket = shovel.cylinders
    values = mech.parameter_values()
    for name, expected in (("boom", d.boom), ("stick", d.stick), ("bucket", d.bucket), ("l5", boom.lever_fixed),
                           ("l7", boom.lever_driven), ("l8", stick.lever_fixed), ("l9", stick.lever_driven),
                           ("l10", bucket.lever_fixed), ("l11", bucket.lever_driven), ("C_x", d.boom_foot[0]),
                           ("C_y", d.boom_foot[1])):
        assert values[name] == pytest.approx(expected, abs=1e-12), name
    index = mech.joint_names.index("theta1")
    assert (mech.model.lowerPositionLimit[index], mech.model.upperPositionLimit[index]) == pytest.approx(
        shovel.theta1, abs=1e-15)
    assert {m.name: m.minimum for m in mech.measures if m.kind == "transmission_angle"} == pytest.approx(
        {"boom_transmission_angle": 30 * DEG, "stick_transmission_angle": 30 * DEG,
         "bucket_transmission_angle": 30 * DEG})
    assert mech.input_rates == {"L1": 0.1, "L2": 0.1, "L3": 0.1} and mech.tool_frame == "V"
    assert mech.total_mass == pytest.approx(d.boom_mass + d.stick_mass + d.bucket_mass)


def test_a_longer_boom_from_the_command_line_rebuilds_through_the_file():
    """--set boom=4.5 moves F to 4.5 m from C (the stick, bucket and levers keep their lengths)."""
    from mechatron.kinematics.geometry import distance

    longer = mechatron.load("front_shovel", boom=4.5)
    q = assemble(longer, {"L1": 3.0, "L2": 2.5, "L3": 2.2})
    assert distance(longer, q, "C", "F") == pytest.approx(4.5, abs=1e-9)
    assert distance(longer, q, "F", "Q") == pytest.approx(3.3, abs=1e-9)
    assert distance(longer, q, "Q", "V") == pytest.approx(2.0, abs=1e-9)


def test_cylinders_span_the_joint_ranges(shovel, mech):
    for cyl, (lo, hi) in zip(shovel.cylinders, (shovel.theta1, shovel.theta2, shovel.theta3)):
        assert cyl.length(lo) == pytest.approx(cyl.stroke[0], rel=1e-12)
        assert cyl.length(hi) == pytest.approx(cyl.stroke[1], rel=1e-12)
        assert cyl.ratio == pytest.approx(1.7)
    assert mech.cylinders["L1"].count == 2  # twin boom cylinders
    assert mech.mobility() == 3 and mech.actuated == ["L1", "L2", "L3"]


def test_lever_arm_is_derivative_of_cylinder_length(shovel, mech):
    """e = dL/dθ: the model's lever arm of each cylinder equals the ratio of cylinder speed to joint speed."""
    q = assemble(mech, shovel.cylinder_lengths(0.4, 1.4, 3.3))
    for cyl, pivot, rate_name in (("L1", "C", "L1"), ("L2", "F", "L2"), ("L3", "Q", "L3")):
        c = mech.cylinders[cyl]
        h = 1e-6
        length = q[loop_solver(mech).index[rate_name]]
        plus, minus = (assemble(mech, {rate_name: length + s * h}, q) for s in (1, -1))
        dtheta = (np.array(ex.joint_angles(mech, plus)) - np.array(ex.joint_angles(mech, minus))) / (2 * h)
        joint = ["L1", "L2", "L3"].index(cyl)
        arm = mechatron.kinematics.lever_arm(mech, q, c.base, c.eye, pivot)  # from the pin geometry alone
        assert 1.0 / dtheta[joint] == pytest.approx(arm, rel=1e-5)


def test_report_comparison_flags_exactly_the_inconsistent_numbers(shovel):
    rows = {r["quantity"]: r for r in report_comparison(shovel)}
    not_reproduced = {q for q, r in rows.items() if not r["reproduced"]}
    assert not_reproduced == {
        "stick l2 = 0.9·∛46 (3.1)", "L44max = |CQ| (3.3b)", "θ1max (3.3b)",
        "θ3max', radius condition (3.6)", "R2max, ground reach (2.4)", "boom α12 with λ = 1.7 (3.9)",
        "boom l7 = CB (3.12)", "boom L1min", "boom L1max", "boom minimum transmission angle",
        "bucket minimum transmission angle",
    }
    assert all(rows[q]["note"] for q in not_reproduced)
    assert rows["L44max = |CQ| (3.3b)"]["computed"] == pytest.approx(6.56, abs=1e-3)
    assert rows["θ3max', radius condition (3.6)"]["computed"] == pytest.approx(215.075, abs=1e-3)


def test_report_boom_lengths_are_a_triangle_with_lambda_1_8():
    # l5 = 1.2, l7 = 2.74, L1min = 1.94, L1max = 3.50: λ = 1.80, included angles 37.97° → 120.1°, k = 1.28
    def angle(L):
        return math.acos((1.2**2 + 2.74**2 - L**2) / (2 * 1.2 * 2.74))

    start, end = angle(1.94), angle(3.50)
    assert (start / DEG, end / DEG) == pytest.approx((37.97, 120.1), abs=0.05)
    k = (1.2 * 2.74 * math.sin(start) / 1.94) / (1.2 * 2.74 * math.sin(end) / 3.50)
    assert k == pytest.approx(1.28, abs=0.01)
    assert math.degrees(math.asin(1.2 / 2.74)) == pytest.approx(26.0, abs=0.05)  # the most γ1 can ever be


def test_first_sizing():
    sizes = ex.first_sizing(46)
    assert sizes["boom"] == pytest.approx(4.300, abs=5e-4)
    assert ex.mass_from_requirements({"max_digging_radius": 9.06, "max_digging_depth": 3.2,
                                      "max_digging_height": 9.53}) == pytest.approx(46.0, rel=1e-9)


def test_working_range_matches_special_positions(mech):
    working = ex.working_range(mech, samples=21)
    summary = working.summary
    assert summary["max_digging_radius"] == pytest.approx(9.06, abs=0.01)
    assert summary["max_digging_height"] == pytest.approx(9.53, abs=0.01)
    assert summary["max_digging_depth"] == pytest.approx(3.2, abs=0.01)
    # the ground reach over all strokes is at least the report's ζ = 25° position (8.605 m)
    assert 8.60 <= summary["max_ground_radius"] <= 8.7


def test_transmission_checks_in_sweep(mech):
    from mechatron.kinematics.sweeps import sweep

    result = sweep(mech, samples=60)
    checks = {c["name"]: c for c in result.check_measures()}
    assert checks["stick_transmission_angle"]["pass"] is True
    assert checks["boom_transmission_angle"]["pass"] is False  # the report's boom geometry cannot reach 30°


def test_excavator_command(tmp_path, capsys):
    from mechatron.cli import main

    design = tmp_path / "design.toml"
    design.write_text("boom_ratio = 1.9\nmax_digging_height = 9.52\n")
    assert main(["excavator", "--design", str(design), "--samples", "5", "--json",
                 "--plot", str(tmp_path / "range.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["cylinders"]["L1"]["ratio"] == pytest.approx(1.9)
    assert out["joint_ranges_deg"]["theta1"][1] == pytest.approx(73.455, abs=1e-3)  # with the text's H2 = 9.52
    assert (tmp_path / "range.png").stat().st_size > 30_000
    # the command prints the result of excavator_report: --json is as_dict, the text is str, --csv is to_frame
    report = ex.excavator_report(ex.read_design(design), 5)
    assert out == json.loads(report.to_json())
    assert "report_comparison" not in out  # validation material, not the command's
    assert main(["excavator", "--design", str(design), "--samples", "5", "--csv", str(tmp_path / "e.csv")]) == 0
    text = capsys.readouterr().out
    assert text == f"{report}\nwrote {tmp_path / 'e.csv'}\n"
    import pandas as pd

    pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "e.csv"), report.to_frame(), check_exact=False, rtol=1e-9)
    # -o writes the design's mechanism file; with --json the report is printed as well, the file named on stderr
    assert main(["excavator", "--design", str(design), "--samples", "5", "--json", "-o", str(tmp_path / "d.toml")]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out) == json.loads(report.to_json()) and err == f"wrote {tmp_path / 'd.toml'}\n"
    low, high = mechatron.load(tmp_path / "d.toml").cylinders["L1"].stroke
    assert (low, high) == pytest.approx((report.cylinders["L1"]["L_min"], report.cylinders["L1"]["L_max"]))
    assert high / low == pytest.approx(1.9)  # the design file's boom_ratio
    bad = tmp_path / "bad.toml"
    bad.write_text("boom = -1.0\n")
    assert main(["excavator", "--design", str(bad)]) == 2
    assert "bad.toml" in capsys.readouterr().err
    assert main(["excavator", "--tooth-force", "1,2,3"]) == 2
    assert "two finite numbers" in capsys.readouterr().err


def test_excavator_report(shovel):
    """The report follows the protocol; its tables are the design's: the special positions (to_frame) in SI, the
    cylinders with the 30° check [Shovel, 3.18–3.19], the tool forces of [ISO 6015] at each special position."""
    report = ex.excavator_report(samples=5, tooth_force=(-40e3, 0.0))
    data = check_result(report)
    frame = report.to_frame().set_index("position")
    for name, angles in ex.special_positions(shovel).items():
        np.testing.assert_allclose(frame.loc[name, ["theta1_rad", "theta2_rad", "theta3_rad"]], angles, atol=1e-12)
        np.testing.assert_allclose(frame.loc[name, ["tip_x_m", "tip_y_m"]], shovel.tip(*angles), atol=1e-9)
        lengths = shovel.cylinder_lengths(*angles)
        np.testing.assert_allclose(frame.loc[name, ["L1_m", "L2_m", "L3_m"]], [lengths[c] for c in ("L1", "L2", "L3")])
        q = assemble(report.mechanism, lengths)
        forces = ex.tool_forces(report.mechanism, q)
        assert frame.loc[name, "bucket_tool_force_extending_N"] == pytest.approx(forces["bucket"]["extending"])
    for c in shovel.cylinders:
        row = data["cylinders"][c.name]
        assert (row["L_min"], row["L_max"]) == pytest.approx(c.stroke)
        assert row["transmission_check"] == ("PASS" if c.min_transmission_angle() >= 30 * DEG else "FAIL")
    assert data["cylinders"]["L2"]["k"] == pytest.approx(1.0)  # equal lever arms at both ends (k = 1)
    assert data["loads"]["tooth_force"] == [-40e3, 0.0]
    text = str(report)
    assert "[ISO 6015, 5.2.1–5.2.2]" in text and "[Shovel]" in text and "report's numbers" not in text
    with pytest.raises(mechatron.InputError, match="two finite numbers"):
        ex.excavator_report(samples=5, tooth_force=(1.0,))


def test_report_comparison_text():
    """One line per printed number, ✓ or ✗ as reproduced, with the reason on every ✗."""
    rows = report_comparison()
    lines = comparison_text(rows).splitlines()[1:]
    assert len(lines) == len(rows)
    for row, line in zip(rows, lines):
        assert line.strip().startswith("✓" if row["reproduced"] else "✗") and row["quantity"] in line
        assert (bool(row["note"]) and row["note"] in line) == (not row["reproduced"] and bool(row["note"]))


def test_iso6015_tool_forces_by_lever_arms(shovel, mech):
    """With only the bucket cylinder moving, the bucket turns about Q, so F_tool = F_cyl · e3 / |QV| (e3 its arm about
    Q); with only the stick cylinder, the stick and bucket turn about F: F_tool = F_cyl · e2 / |FV|."""
    from mechatron.kinematics.geometry import distance, lever_arm

    spec = ex.DEFAULT_CYLINDERS
    for angles in ex.special_positions(shovel).values():
        q = assemble(mech, shovel.cylinder_lengths(*angles))
        forces = ex.tool_forces(mech, q)
        e3 = lever_arm(mech, q, "G", "K", "Q")
        assert forces["bucket"]["extending"] == pytest.approx(
            spec["L3"].force(ex.RELIEF_PRESSURE) * e3 / distance(mech, q, "Q", "V"), rel=1e-9)
        e2 = lever_arm(mech, q, "D", "E", "F")
        assert forces["arm"]["retracting"] == pytest.approx(
            spec["L2"].force(ex.RELIEF_PRESSURE, extending=False) * e2 / distance(mech, q, "F", "V"), rel=1e-9)


def test_static_cylinder_loads_balance_the_bucket(shovel, mech):
    """The bucket cylinder holds the bucket: its force times its arm about Q equals the moment of the bucket's
    weight (centre at the middle of QV) and of the tooth force about Q."""
    from mechatron.kinematics.geometry import lever_arm, point_positions

    q = assemble(mech, shovel.cylinder_lengths(0.5, 1.6, 3.4))
    tooth = np.array([-40e3, 15e3])
    table = ex.cylinder_loads(mech, q[None, :], tooth_force=tuple(tooth))
    Qp, V, G, K = point_positions(mech, q, "Q", "V", "G", "K")
    weight = np.array([0.0, -9.81 * shovel.design.bucket_mass])

    def moment(point, force):
        r = point - Qp
        return r[0] * force[1] - r[1] * force[0]

    load_moment = moment((Qp + V) / 2, weight) + moment(V, tooth)
    axis = (K - G) / np.linalg.norm(K - G)
    cylinder_moment = moment(K, axis * table["L3_force"].iloc[0])  # the rod pushes K away from G when > 0
    assert cylinder_moment + load_moment == pytest.approx(0.0, abs=1e-6 * abs(load_moment))
    assert abs(table["L3_force"].iloc[0]) * lever_arm(mech, q, "G", "K", "Q") == pytest.approx(abs(load_moment),
                                                                                                rel=1e-9)
    # pressure: the piston side when pushing, the rod side when pulling
    spec = ex.DEFAULT_CYLINDERS["L3"]
    force = table["L3_force"].iloc[0]
    area = spec.piston_area if force > 0 else spec.annulus_area
    assert table["L3_pressure"].iloc[0] == pytest.approx(abs(force) / area)


def test_twin_boom_cylinder_pressure():
    spec = ex.CylinderSpec(0.18, 0.125, count=2)
    assert spec.pressure(2 * 100e3) == pytest.approx(100e3 / (np.pi * 0.18**2 / 4))
    assert spec.pressure(-2 * 50e3) == pytest.approx(50e3 / (np.pi * (0.18**2 - 0.125**2) / 4))
    with pytest.raises(mechatron.InputError, match="bore > rod"):
        ex.CylinderSpec(0.1, 0.12)

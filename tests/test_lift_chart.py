"""Rated lift capacity of the front shovel [ISO 10567]: the tipping load against a moment balance of the whole machine
written out by hand, the hydraulic capacity against the virtual work of the cylinder forces, the rated load
min(0.75·tipping, 0.87·hydraulic) in every cell; the machine data of the design file's [machine] table and its
refusals; ``mechatron excavator --lift-chart``.

The hand references use the design's numbers only: the boom CF and the stick FQ as uniform bars (centres at mid-link),
the nose pin Q from the triangle C–F–Q, the relief forces p·πD²/4 and p·π(D² − d²)/4 per cylinder.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

import mechatron
from mechatron.machines import excavator as ex
from mechatron.machines.capacity import capacity_report
from mechatron.machines.lift_chart import lift_chart, lift_mechanism
from mechatron.machines.shovel_machine import ShovelMachine, read_machine
from tests.protocol import check_result

G = 9.81
DESIGN = ex.FrontShovelDesign()
MACHINE = ShovelMachine()


@pytest.fixture(scope="module")
def chart():
    return lift_chart(DESIGN, MACHINE, radii=[3.0, 4.0, 5.0, 6.0, 7.0], heights=[-1.0, 0.0, 2.0, 3.0, 5.0])


def hand_pose(design, radius, height, slew=0.0):
    """(C, F, Q) by the triangle C–F–Q, the interior angle at F below π (the stick hangs clockwise from the boom)."""
    C = np.array(design.boom_foot)
    Q = np.array([slew + radius, height])
    d = np.linalg.norm(Q - C)
    l1, l2 = design.boom, design.stick
    at_c = math.acos((l1**2 + d**2 - l2**2) / (2 * l1 * d))
    boom = math.atan2(*(Q - C)[::-1]) + at_c
    F = C + l1 * np.array([math.cos(boom), math.sin(boom)])
    assert np.linalg.norm(Q - F) == pytest.approx(l2, rel=1e-12)
    return C, F, Q


def hand_tipping_kg(design, machine, radius, height, over):
    """Tipping load (kg) by the moment balance about the tipping line: W (R − a) = Σ m_i (a − r_i)."""
    C, F, Q = hand_pose(design, radius, height, machine.slew_axis)
    a = machine.front_tipping_line or machine.track_length / 2 if over == "front" else \
        machine.side_tipping_line or machine.track_gauge / 2
    undercarriage_r = machine.undercarriage_centre[0] - machine.slew_axis if over == "front" else 0.0
    masses = [(machine.upper_mass, machine.upper_centre[0] - machine.slew_axis),
              (machine.undercarriage_mass, undercarriage_r),
              (design.boom_mass, (C[0] + F[0]) / 2 - machine.slew_axis),
              (design.stick_mass, (F[0] + Q[0]) / 2 - machine.slew_axis)]  # the bucket removed
    return sum(m * (a - r) for m, r in masses) / (radius - a)


CELLS = [(3.0, 0.0), (4.0, 2.0), (5.0, -1.0), (6.0, 3.0), (7.0, 3.0), (5.0, 5.0)]


@pytest.mark.parametrize("radius, height", CELLS)
@pytest.mark.parametrize("over", ["front", "side"])
def test_tipping_load_by_hand_moment_balance(chart, radius, height, over):
    row = chart.cell(radius, height, over)
    assert row["tipping_kg"] == pytest.approx(hand_tipping_kg(DESIGN, MACHINE, radius, height, over), rel=1e-9)


def relief_forces(design, machine):
    """(push, pull) N per cylinder L1, L2, L3 by hand: p π D²/4 and p π (D² − d²)/4 times the cylinders."""
    push, pull = {}, {}
    for name, (bore, rod) in machine.bores.items():
        count = design.boom_cylinders if name == "L1" else 1
        p = machine.reliefs.get(name, machine.relief_pressure)
        push[name] = count * p * math.pi * bore**2 / 4
        pull[name] = count * p * math.pi * (bore**2 - rod**2) / 4
    return push, pull


def hand_hydraulic_kg(design, machine, radius, height):
    """Virtual work: with only cylinder j moving (the others held), F_j δL_j = W g δy_Q for the load W at Q, so
    dF_j/dW = g ∂y_Q/∂L_j (central differences of the loop closure); the weights' part F₀ from the constrained
    inverse dynamics, checked against Σ m g ∂y_centre/∂L_j. W_h = the smallest W at which a cylinder meets p·A."""
    from mechatron.dynamics.trajectory import holding_forces
    from mechatron.kinematics.geometry import point_positions
    from mechatron.kinematics.loops import assemble

    shovel, mech = lift_mechanism(design)
    _, F, Q = hand_pose(design, radius, height, machine.slew_axis)
    # the lengths of the boom and stick cylinders at those angles: the triangles of the design
    theta1 = math.atan2(*(F - np.array(design.boom_foot))[::-1])
    theta2 = (math.atan2(*(Q - F)[::-1]) - theta1 + math.pi) % (2 * math.pi)
    lengths = {"L1": shovel.boom_cylinder.length(theta1), "L2": shovel.stick_cylinder.length(theta2),
               "L3": shovel.bucket_cylinder.length(sum(shovel.theta3) / 2)}
    q = assemble(mech, lengths)
    assert point_positions(mech, q, "Q")[0] == pytest.approx(Q, abs=1e-9)
    F0 = dict(zip(mech.actuated, holding_forces(mech, q[None, :])[0]))
    push, pull = relief_forces(design, machine)
    h, capacity = 1e-6, math.inf
    for name in ("L1", "L2"):
        ends = []
        for step in (h, -h):
            qs = assemble(mech, {**lengths, name: lengths[name] + step}, q)
            C_, F_, Q_ = point_positions(mech, qs, "C", "F", "Q")
            ends.append((Q_[1], design.boom_mass * (C_[1] + F_[1]) / 2 + design.stick_mass * (F_[1] + Q_[1]) / 2))
        dy_q = (ends[0][0] - ends[1][0]) / (2 * h)
        weights = G * (ends[0][1] - ends[1][1]) / (2 * h)
        assert F0[name] == pytest.approx(weights, rel=1e-6)  # gravity by virtual work too
        slope = G * dy_q  # N per kg
        limit = (push[name] - F0[name]) / slope if slope > 0 else (pull[name] + F0[name]) / -slope
        capacity = min(capacity, limit)
    assert abs(F0["L3"]) < 1e-6  # the bucket removed: its cylinder carries nothing
    return capacity


@pytest.mark.parametrize("radius, height", [(3.0, 0.0), (4.0, 2.0), (5.0, -1.0), (6.0, 3.0), (7.0, 3.0)])
def test_hydraulic_capacity_by_virtual_work(chart, radius, height):
    expected = hand_hydraulic_kg(DESIGN, MACHINE, radius, height)
    for over in ("front", "side"):
        assert chart.cell(radius, height, over)["hydraulic_kg"] == pytest.approx(expected, rel=1e-6)


def test_rated_load_is_the_smaller_factored_limit_in_every_cell(chart):
    assert len(chart.rows) >= 20
    for row in chart.rows:
        tipping, hydraulic = 0.75 * row["tipping_kg"], 0.87 * row["hydraulic_kg"]
        assert row["rated_kg"] == pytest.approx(min(tipping, hydraulic), rel=1e-12)
        assert row["limit"] == ("tipping" if tipping <= hydraulic else "hydraulic")


def test_unreachable_cells_are_absent_and_every_reached_one_is_there(chart):
    """A cell whose boom and stick angles fall outside the designed ranges is left out, both sides."""
    shovel = ex.synthesize(DESIGN)
    for radius in chart.radii:
        for height in chart.heights:
            C = np.array(DESIGN.boom_foot)
            d = math.hypot(radius - C[0], height - C[1])
            inside = False
            if abs(DESIGN.boom - DESIGN.stick) < d < DESIGN.boom + DESIGN.stick:
                _, F, Q = hand_pose(DESIGN, radius, height)
                t1 = math.atan2(*(F - C)[::-1])
                t2 = (math.atan2(*(Q - F)[::-1]) - t1 + math.pi) % (2 * math.pi)
                inside = shovel.theta1[0] <= t1 <= shovel.theta1[1] and shovel.theta2[0] <= t2 <= shovel.theta2[1]
            for over in ("front", "side"):
                assert (chart.cell(radius, height, over) is not None) == inside, (radius, height)
    assert chart.cell(3.0, 3.0, "front") is None  # closer to C than the stick folds: |CQ| < |CQ|min


def test_tipping_governs_far_out_over_the_front_hydraulics_close_in(chart):
    """The illustrative machine: over the front, the 7 m cells tip first, the 3 m cells are hydraulic-limited; over
    the side (tipping line at half the gauge) tipping governs at 5 m and beyond."""
    for height in (2.0, 3.0):
        assert chart.cell(7.0, height, "front")["limit"] == "tipping"
    for height in (0.0,):
        assert chart.cell(3.0, height, "front")["limit"] == "hydraulic"
    assert all(r["limit"] == "tipping" for r in chart.rows if r["over"] == "side" and r["radius_m"] >= 6)
    # weaker cylinders (a lower relief pressure): hydraulics governs everywhere over the front
    weak = lift_chart(DESIGN, replace(MACHINE, relief_pressure=12e6), radii=[3.0, 5.0, 7.0], heights=[0.0, 3.0])
    assert {r["limit"] for r in weak.rows if r["over"] == "front"} == {"hydraulic"}
    for row in weak.rows:
        strong = chart.cell(row["radius_m"], row["height_m"], row["over"])
        assert row["tipping_kg"] == pytest.approx(strong["tipping_kg"], rel=1e-12)  # the same weights


def test_a_line_of_load_inside_the_tipping_line_cannot_tip():
    machine = replace(MACHINE, front_tipping_line=2.8)
    chart = lift_chart(DESIGN, machine, radii=[2.5], heights=[0.5])
    front, side = chart.cell(2.5, 0.5, "front"), chart.cell(2.5, 0.5, "side")
    assert front["tipping_kg"] == math.inf and front["limit"] == "hydraulic"
    assert side["tipping_kg"] == pytest.approx(hand_tipping_kg(DESIGN, machine, 2.5, 0.5, "side"), rel=1e-9)
    data = check_result(chart)
    assert data["lift_chart"][0]["tipping_kg"] is None  # JSON: null, not inf or NaN
    assert math.isnan(chart.to_frame()["tipping_kg"].iloc[0])  # CSV: an empty cell


def test_a_second_design_file_with_its_machine(tmp_path):
    """Any design file: a longer boom, heavier links, the machine of its [machine] table, the slew axis moved."""
    path = tmp_path / "other.toml"
    path.write_text("boom = 4.6\nstick = 3.0\nboom_foot = [0.8, 2.6]\nboom_mass = 5200.0\nboom_cylinders = 1\n"
                    "max_digging_radius = 9.1\n\n[machine]\nupper_mass = 22000.0\nupper_centre = [-1.0, 1.7]\n"
                    "undercarriage_mass = 15000.0\nundercarriage_centre = [0.4, 0.5]\nslew_axis = 0.3\n"
                    "track_length = 4.2\ntrack_gauge = 2.6\nside_tipping_line = 1.4\nrelief_pressure = 30e6\n"
                    "\n[machine.boom_cylinder]\nbore = 0.25\nrod = 0.16\nrelief_pressure = 34e6\n")
    design, machine = ex.read_design(path), read_machine(path)
    assert machine.tipping_lines == {"front": 2.1, "rear": 2.1, "side": 1.4}
    assert machine.relief("L1") == 34e6 and machine.relief("L2") == 30e6
    chart = lift_chart(design, machine, radii=[4.0, 6.0], heights=[0.0, 2.0])
    assert chart.rows
    for row in chart.rows:
        r, h = row["radius_m"], row["height_m"]
        assert row["tipping_kg"] == pytest.approx(hand_tipping_kg(design, machine, r, h, row["over"]), rel=1e-9)
        assert row["hydraulic_kg"] == pytest.approx(hand_hydraulic_kg(design, machine, r, h), rel=1e-6)
        assert row["rated_kg"] == pytest.approx(min(0.75 * row["tipping_kg"], 0.87 * row["hydraulic_kg"]))


BAD = [
    ("upper_mass = -100.0", "machine.upper_mass", "must be > 0 kg"),
    ("undercarriage_mass = 0.0", "machine.undercarriage_mass", "must be > 0 kg"),
    ("upper_centre = [-1.0, -0.5]", "machine.upper_centre", "below the ground"),
    ("upper_centre = [-9.0, 1.5]", "machine.upper_centre", "tips backwards, the upper structure facing along"),
    ("undercarriage_centre = [3.0, 0.5]", "machine.undercarriage_centre", "tipping lines"),
    ("front_tipping_line = -0.5", "machine.front_tipping_line", "does not enclose the slew axis"),
    ("side_tipping_line = 0.0", "machine.side_tipping_line", "does not enclose the slew axis"),
    ("track_gauge = -2.0", "machine.track_gauge", "must be > 0 m"),
    ("relief_pressure = 0.0", "machine.relief_pressure", "must be a pressure in Pa"),
    ("relief_pressure = 32.0", "machine.relief_pressure", "32 MPa is 32e6"),
    ("friction = 0.0", "machine.friction", "friction coefficient"),
    ("[machine.stick_cylinder]\nrelief_pressure = -1e6", "machine.stick_cylinder.relief_pressure",
     "must be a pressure in Pa"),
    ("[machine.bucket_cylinder]\nbore = 0.1\nrod = 0.12", "machine.bucket_cylinder.bore", "bore > rod"),
    ("[machine.bucket_cylinder]\nbore_mm = 180", "machine.bucket_cylinder.bore_mm", "unknown field"),
    ("upper_mass_t = 19", "machine.upper_mass_t", "unknown field"),
    ("upper_mass = \"heavy\"", "machine.upper_mass", "expected a number"),
    ("lift_radii = [3.0, -1.0]", "machine.lift_radii", "radii > 0"),
]


@pytest.mark.parametrize("line, field, message", BAD, ids=[b[1] + ":" + b[0].split("=")[0].strip() for b in BAD])
def test_bad_machine_data_is_refused_naming_the_field(tmp_path, capsys, line, field, message):
    from mechatron.cli import main

    path = tmp_path / "bad.toml"
    table = "[machine]\n" + line + "\n" if not line.startswith("[") else line + "\n"
    path.write_text(table)
    with pytest.raises(mechatron.InputError) as error:
        read_machine(path)
    assert f"bad.toml: field '{field}'" in str(error.value) and message in str(error.value)
    assert main(["excavator", "--design", str(path), "--lift-chart"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"field '{field}'" in err and "Traceback" not in err
    assert main(["excavator", "--design", str(path)]) == 2  # the design report reads the same file
    assert f"field '{field}'" in capsys.readouterr().err


def test_the_machine_refuses_bad_data_in_python():
    with pytest.raises(mechatron.InputError, match="field 'upper_mass'"):
        ShovelMachine(upper_mass=-1.0)
    with pytest.raises(mechatron.InputError, match="field 'rear_tipping_line'.*enclose"):
        ShovelMachine(rear_tipping_line=-0.1)


def test_command_prints_the_lift_chart_and_the_digging_forces(tmp_path, capsys):
    """--json is as_dict with exactly the keys of the issue; the text has the chart and the digging forces; --csv is
    the lift chart's rows; --plot the chart."""
    from mechatron.cli import main

    assert main(["excavator", "--lift-chart", "--samples", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"lift_chart", "rated_tool_forces", "digging_capability"}
    assert {tuple(row) for row in out["lift_chart"]} == {("radius_m", "height_m", "over", "rated_kg", "tipping_kg",
                                                         "hydraulic_kg", "limit")}
    assert {row["over"] for row in out["lift_chart"]} == {"front", "side"}
    assert {row["limit"] for row in out["lift_chart"]} == {"tipping", "hydraulic"}
    assert set(out["rated_tool_forces"]) == set(out["digging_capability"]) == {"bucket", "arm"}
    for tool in out["digging_capability"].values():
        assert {"force_N", "position_m", "limit"} <= set(tool) and tool["limit"] in ("hydraulic", "tipping",
                                                                                    "slipping")
        assert len(tool["position_m"]) == 2 and tool["force_N"] > 0
    report = capacity_report(samples=3)
    assert out == json.loads(report.to_json())
    assert main(["excavator", "--lift-chart", "--samples", "3", "--csv", str(tmp_path / "l.csv"),
                 "--plot", str(tmp_path / "l.png")]) == 0
    text = capsys.readouterr().out
    assert text.startswith(str(report)) and "[ISO 10567]" in text and "[ISO 6015, 5.2.1–5.2.2]" in text
    assert "digging capability at the bucket lip (mechatron's estimate, not [ISO 6015]" in text
    assert "bucket" in text and "arm" in text and "*" in text
    import pandas as pd

    pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "l.csv"), report.to_frame(), check_exact=False, rtol=1e-9,
                                  check_dtype=False)
    assert (tmp_path / "l.png").stat().st_size > 30_000
    assert main(["excavator", "--lift-chart", "--tooth-force=-5e4,0"]) == 2
    assert "--tooth-force" in capsys.readouterr().err


def test_results_follow_the_protocol():
    report = capacity_report(samples=3)
    check_result(report)
    check_result(report.lift)
    check_result(report.digging)
    frame = report.to_frame()
    assert list(frame.columns) == ["radius_m", "height_m", "over", "rated_kg", "tipping_kg", "hydraulic_kg", "limit"]


def test_the_cells_the_page_quotes_by_hand():
    """docs/front_shovel_design.md quotes cells of the default chart: they are the hand references' numbers."""
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "front_shovel_design.md").read_text(encoding="utf-8")
    chart = lift_chart(DESIGN, MACHINE, radii=[3.0, 6.0], heights=[0.0, 3.0])
    row = chart.cell(3.0, 0.0, "front")
    assert row["limit"] == "hydraulic"
    hydraulic = hand_hydraulic_kg(DESIGN, MACHINE, 3.0, 0.0)
    tipping = hand_tipping_kg(DESIGN, MACHINE, 3.0, 0.0, "front")
    for value in (0.87 * hydraulic, hydraulic, tipping):
        assert f"{value:,.0f} kg".replace(",", " ") in page
    for over in ("front", "side"):
        tipping = hand_tipping_kg(DESIGN, MACHINE, 6.0, 3.0, over)
        assert chart.cell(6.0, 3.0, over)["limit"] == "tipping"
        assert f"{0.75 * tipping:,.0f} kg".replace(",", " ") in page


def test_the_shipped_example_reads_its_machine():
    from pathlib import Path

    machine = read_machine(Path(__file__).resolve().parent.parent / "examples" / "data" / "front_shovel_design.toml")
    assert (machine.upper_mass, machine.upper_centre, machine.undercarriage_mass) == (20000.0, (-1.5, 1.8), 16500.0)
    assert machine.tipping_lines == {"front": 2.25, "rear": 2.25, "side": 1.375}
    assert machine.bores["L2"] == (0.22, 0.16) and machine.relief("L2") == 34e6 and machine.relief("L1") == 32e6
    assert machine.bores["L1"] == ShovelMachine().bores["L1"]


def test_the_examples_cell_the_page_quotes_by_hand():
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    path = root / "examples" / "data" / "front_shovel_design.toml"
    page = (root / "docs" / "front_shovel_design.md").read_text(encoding="utf-8").replace("\n", " ")
    design, machine = ex.read_design(path), read_machine(path)
    chart = lift_chart(design, machine, radii=[7.0], heights=[4.0])
    front, side = (hand_tipping_kg(design, machine, 7.0, 4.0, over) for over in ("front", "side"))
    assert chart.cell(7.0, 4.0, "front")["limit"] == chart.cell(7.0, 4.0, "side")["limit"] == "tipping"
    front, side = (f"{0.75 * x:,.0f}".replace(",", " ") for x in (front, side))
    assert f"lifts {front} kg over the front and {side} kg over the side at a radius of 7 m and a height of 4 m, " \
           "both tipping-limited" in page

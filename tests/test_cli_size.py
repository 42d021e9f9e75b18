"""The size command and task files: the public JSON contract, outputs, exit codes and bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.sizing import size_mechanism
from mechatron.dynamics.task import default_task, generic_task, read_task
from mechatron.errors import InputError


def run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse: an option's value refused as it is parsed
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


ROOT = Path(__file__).resolve().parents[1]
REQUIRED_CHECKS = {"peak torque", "max speed", "inertia ratio"}
#: The thermal check: RMS torque, or the winding temperature of a motor with the thermal data (the shipped ones).
THERMAL_CHECKS = {"RMS torque", "winding temperature rise"}
#: The IEC 60034-1 duty types mechatron gives but S9 (x: the cyclic duration factor, in whole percent).
DUTY_TYPES = {"S1", "S7"} | {f"S{k} {x} %" for k in (3, 4, 5, 6) for x in range(101)}


@pytest.fixture(scope="module")
def puma_json():
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        code = main(["size", "puma560", "--json"])
    return code, json.loads(buffer.getvalue())


def test_size_puma_json_contract(puma_json):
    code, result = puma_json
    assert code == 0 and result["feasible"]
    joints = result["joints"]
    assert [j["joint"] for j in joints] == [f"q{i}" for i in range(1, 7)]
    for j in joints:
        assert {"joint", "motor", "gearbox", "ratio", "checks"} <= set(j)
        assert isinstance(j["motor"], str) and isinstance(j["gearbox"], str) and j["ratio"] > 0
        names = {c["name"] for c in j["checks"]}
        assert REQUIRED_CHECKS <= names and len(THERMAL_CHECKS & names) == 1
        assert j["thermal"]["check"] in names and j["thermal"]["duty_type"] in DUTY_TYPES | {"S9"}
        assert j["thermal"]["duty_clause"].startswith("4.2.") and j["thermal"]["duty_reason"]
        for c in j["checks"]:
            assert {"name", "value", "limit", "margin", "pass"} <= set(c)
            assert c["pass"] is (c["value"] <= c["limit"] * (1 + 1e-9))
            assert c["margin"] == pytest.approx(1 - c["value"] / c["limit"])
        assert {"deciding_check", "runner_up", "drive_mass_kg", "mounted_on"} <= set(j)
    assert {"iterations", "totals", "method", "converged"} <= set(result)


def test_size_json_equals_the_api(puma_json):
    _, result = puma_json
    api = mechatron.size(mechatron.load("puma560"))
    assert result == json.loads(api.to_json())  # --json is as_dict()
    task = default_task(mechatron.load("puma560"))
    lower = size_mechanism(task.mechanism, task.trajectory, loads=task.loads)
    for j, joint in zip(result["joints"], lower.joints):
        assert (j["motor"], j["gearbox"], j["ratio"]) == (joint.motor, joint.converter, joint.ratio)
        peak = next(c for c in j["checks"] if c["name"] == "peak torque")
        assert peak["value"] == pytest.approx(np.abs(joint.operating_points()[1]).max(), rel=1e-12)


def test_size_outputs_are_the_results(tmp_path, capsys):
    """--json prints as_dict(), --csv writes to_frame(), --plot draws plot(), the text is str(), --plots DIR writes
    each joint's chart: all of the result mechatron.size returns for the same input."""
    api = mechatron.size(mechatron.load("planar_2r"), objective="cost")
    code, out, _ = run(capsys, "size", "planar_2r", "--objective", "cost", "--csv", str(tmp_path / "s.csv"),
                       "--plot", str(tmp_path / "s.png"), "--plots", str(tmp_path / "charts"))
    assert code == 0
    text, _, written = out.partition("\nwrote ")
    assert text == str(api)
    assert "q1: motor" in out and "PASS" in out and "every joint has a feasible drive" in out
    table = pd.read_csv(tmp_path / "s.csv")
    expected = api.to_frame()
    assert list(table.columns) == ["joint", "motor", "converter", "ratio", "check", "value", "limit", "unit",
                                   "margin", "pass"]
    assert len(table) == 2 * 10
    assert table[["joint", "motor", "converter", "check", "unit"]].equals(expected[["joint", "motor", "converter",
                                                                                   "check", "unit"]])
    assert np.allclose(table[["ratio", "value", "limit", "margin"]], expected[["ratio", "value", "limit", "margin"]],
                       rtol=1e-9)
    assert (table["pass"] == expected["pass"]).all()
    assert (tmp_path / "s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    api.save_plot(tmp_path / "api.png")
    assert (tmp_path / "s.png").read_bytes() == (tmp_path / "api.png").read_bytes()
    charts = sorted(p.name for p in (tmp_path / "charts").iterdir())
    assert charts == ["planar_2r_q1.csv", "planar_2r_q1.png", "planar_2r_q2.csv", "planar_2r_q2.png"]
    assert all((tmp_path / "charts" / c).stat().st_size > 10_000 for c in charts if c.endswith(".png"))
    for joint in api.joints:  # each chart's data: the joint's chart_frame
        data = pd.read_csv(tmp_path / "charts" / f"planar_2r_{joint.joint}.csv")
        pd.testing.assert_frame_equal(data, joint.chart_frame(), check_exact=False, rtol=1e-12)
    files = ("s.csv", "s.png", "charts/planar_2r_q1.png", "charts/planar_2r_q1.csv", "charts/planar_2r_q2.png",
             "charts/planar_2r_q2.csv")
    assert {line.strip() for line in ("wrote " + written).splitlines()} == {f"wrote {tmp_path / f}" for f in files}


def test_single_pass_option(capsys):
    """--single-pass is the API's single_pass: one pass with weightless drives, and the report says so."""
    code, out, _ = run(capsys, "size", "planar_2r", "--single-pass", "--json")
    data = json.loads(out)
    api = mechatron.size(mechatron.load("planar_2r"), single_pass=True)
    assert code == 0 and data == json.loads(api.to_json())
    assert data["method"] == "single pass" and len(data["iterations"]) == 1
    assert not data["iterations"][0]["drive_masses"]
    code, out, _ = run(capsys, "size", "planar_2r", "--single-pass")
    assert "method: single pass" in out
    code, out, err = run(capsys, "size", "planar_2r", "--max-iterations", "1")
    assert code == 2 and out == "" and "--max-iterations: must be a whole number >= 2" in err


def test_drive_limit_options(capsys):
    """--stop-torque, --stop-current, --voltage and --screw-life-h are the API's DriveLimits: with a stop torque of
    0.5 N·m the emergency check of every gearbox is min(0.5, T_peak) · u (N·m)."""
    from mechatron.drives.checks import DriveLimits

    motors = str(ROOT / "examples" / "data" / "motors.csv")  # with k_t, R and U: the voltage limit applies
    code, out, _ = run(capsys, "size", "planar_2r", "--motors", motors, "--stop-torque", "0.5", "--voltage", "400",
                       "--json")
    data = json.loads(out)
    api = mechatron.size(mechatron.load("planar_2r"), motors=motors,
                         limits=DriveLimits(stop_torque=0.5, voltage=400.0))
    assert code == 0 and data == json.loads(api.to_json())
    for joint in api.joints:
        if joint.converter_kind != "direct":
            check = next(c for c in joint.checks if c.name == "transmission emergency torque")
            peak = joint.motor_data["peak_torque"]
            assert check.value == pytest.approx(min(0.5, peak) * joint.ratio, rel=1e-12)
        voltage = next(c for c in joint.checks if c.name == "voltage limit")
        assert voltage.limit == 400.0
    for argv, message in ((["--stop-torque", "nan"], "--stop-torque: must be a finite number > 0"),
                          (["--stop-current", "-1"], "--stop-current: must be a finite number > 0"),
                          (["--screw-life-h", "0"], "--screw-life-h: must be a finite number > 0"),
                          (["--voltage", "inf"], "--voltage: must be a finite number > 0")):
        code, out, err = run(capsys, "size", "planar_2r", *argv)
        assert code == 2 and out == "" and message in err and len(err.strip().splitlines()) == 1


def test_infeasible_sizing_exits_1_and_names_failed_checks(tmp_path, capsys):
    tiny = tmp_path / "tiny.csv"
    tiny.write_text("key,rated_torque,peak_torque,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2\n"
                    "T1,0.01,0.03,3000,5000,0.01\nT2,0.02,0.06,3000,5000,0.02\n")
    code, out, _ = run(capsys, "size", "puma560", "--motors", str(tiny))
    assert code == 1
    assert "NO FEASIBLE DRIVE" in out and "closest candidates" in out and "FAIL" in out
    assert "NOT FEASIBLE" in out
    code, out, _ = run(capsys, "size", "puma560", "--motors", str(tiny), "--json")
    result = json.loads(out)
    assert code == 1 and not result["feasible"]
    failing = [j for j in result["joints"] if not j["feasible"]]
    assert failing and all(j["closest"] and any(not c["pass"] for c in j["checks"]) for j in failing)
    assert all("×" in row["failed"] for row in failing[0]["closest"])


def test_bad_catalog_exits_2_naming_file_and_row(tmp_path, capsys):
    bad = tmp_path / "motors.csv"
    bad.write_text("key,rated_torque,peak_torque,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2\n"
                   "A,1,3,3000,5000,1\nB,-1,3,3000,5000,1\n")
    code, out, err = run(capsys, "size", "planar_2r", "--motors", str(bad))
    assert code == 2 and out == ""
    assert "motors.csv: row 3: field 'rated_torque': must be > 0" in err and "Traceback" not in err
    bad.write_text("key,rated_torque,peak_torque,rated_speed_rpm,max_speed_furlongs,rotor_inertia_kgcm2\n"
                   "A,1,3,3000,5000,1\n")
    code, _, err = run(capsys, "size", "planar_2r", "--motors", str(bad))
    assert code == 2 and "unknown unit 'furlongs' for max_speed" in err


def test_closed_loop_sizes_cylinders(capsys):
    code, out, _ = run(capsys, "size", "six_bar_bucket", "--json")
    assert code == 0
    (joint,) = json.loads(out)["joints"]
    assert joint["kind"] == "cylinder" and joint["cylinder"].startswith("HC")
    assert {c["name"] for c in joint["checks"]} == {"rated pressure", "push pressure", "pull pressure", "stroke",
                                                    "rod buckling"}


# ----------------------------------------------------------------------------------------------- tasks
def test_task_file(tmp_path, capsys):
    path = tmp_path / "task.toml"
    path.write_text('name = "two moves"\npayload = 1.5\nvmax_deg = 60\namax_deg = [200, 300]\ndwell = 0.1\n'
                    'waypoints_deg = [[0, 0], [30, -45], [0, 0]]\n'
                    '[[loads]]\nframe = "tool"\nforce = [0.0, -20.0, 0.0]\n')
    mech = mechatron.load("planar_2r")
    task = read_task(path, mech)
    assert task.name == "two moves" and task.payload == 1.5
    assert task.mechanism.total_mass == pytest.approx(mech.total_mass + 1.5)
    assert np.abs(task.trajectory.v).max() == pytest.approx(np.radians(60))
    assert np.allclose(task.trajectory.q[-1], 0) and np.allclose(task.trajectory.q.max(axis=0)[0], np.radians(30))
    assert task.loads[0].frame == "tool" and np.allclose(task.loads[0].force, [0, -20, 0])
    code, out, _ = run(capsys, "size", "planar_2r", "--task", str(path), "--json")
    assert code == 0 and json.loads(out)["task"] == "two moves"


@pytest.mark.parametrize("text, field, message", [
    ('waypoints_deg = [[0, 0], [30]]', "waypoints_deg[2]", "expected 2 numbers"),
    ('waypoints = [[0, 0]]', "waypoints", "at least two waypoints"),
    ('payload = -1\nwaypoints = [[0, 0], [1, 1]]', "payload", "must be >= 0"),
    ('vmax = [1, 2, 3]\nwaypoints = [[0, 0], [1, 1]]', "vmax", "one value or 2"),
    ('profile = "cubic"\nwaypoints = [[0, 0], [1, 1]]', "profile", "unknown value"),
    ('name = "x"', "waypoints", "missing the motion"),
    ('speed = 3\nwaypoints = [[0, 0], [1, 1]]', "speed", "unknown"),
    ('waypoints = [[0, 0], [1, 1]]\n[[loads]]\nframe = "nowhere"\nforce = [0, 0, 0]', "loads[1].frame", "nowhere"),
])
def test_bad_task_files(tmp_path, text, field, message):
    path = tmp_path / "task.toml"
    path.write_text(text + "\n")
    with pytest.raises(InputError, match=message) as info:
        read_task(path, mechatron.load("planar_2r"))
    assert info.value.file == str(path) and info.value.field == field


def test_generic_task_stays_inside_the_limits():
    for name in ("puma560", "scara", "cylindrical_rpp", "ur5", "front_shovel", "crank_slider"):
        mech = mechatron.load(name)
        task = generic_task(mech)
        names = list(mech.actuated) if mech.closures else mech.joint_names
        assert task.trajectory.q.shape[1] == len(names)
        moved = np.ptp(task.trajectory.q, axis=0)
        assert np.all(moved > 0)
        if not mech.closures:
            lower, upper = mech.model.lowerPositionLimit, mech.model.upperPositionLimit
            assert np.all(task.trajectory.q >= lower - 1e-12) and np.all(task.trajectory.q <= upper + 1e-12)


def test_closed_loop_trajectory_csv(tmp_path):
    mech = mechatron.load("six_bar_bucket")
    task = generic_task(mech)
    path = task.trajectory.to_csv(tmp_path / "strokes.csv")
    again = read_task(path, mech)
    assert np.allclose(again.trajectory.q, task.trajectory.q)

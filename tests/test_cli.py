"""The command line: machine-readable output, --set, and one-line errors with exit status 2."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_list_json(capsys):
    code, out, _ = run(capsys, "list", "--json")
    entries = json.loads(out)
    assert code == 0 and isinstance(entries, list)
    origins = {entry["name"]: entry["origin"] for entry in entries}
    assert {"puma560", "planar_2r", "cylindrical_rpp", "articulated_rrr", "planar_3r", "scara", "ur5",
            "panda"} <= set(origins)
    assert origins["puma560"] == "shipped" and origins["ur5"] == "example-robot-data"


def test_list_text(capsys):
    code, out, _ = run(capsys, "list")
    assert code == 0 and "puma560" in out and "Unimation PUMA 560" in out


def test_fk_json_matches_closed_form(capsys):
    # planar 2R, q = (30°, 45°): C = (l1 cos 30° + l2 cos 75°, l1 sin 30° + l2 sin 75°)
    code, out, _ = run(capsys, "fk", "planar_2r", "--q", "30,45", "--deg", "--json")
    result = json.loads(out)
    assert code == 0 and set(result) == {"mechanism", "frame", "joints", "coordinates", "position", "rotation", "rpy"}
    assert result["frame"] == "tool" and result["coordinates"] == pytest.approx([math.radians(30), math.radians(45)])
    assert result["rpy"] == pytest.approx([0.0, 0.0, math.radians(75)], abs=1e-12)
    x = 0.5 * math.cos(math.radians(30)) + 0.4 * math.cos(math.radians(75))
    y = 0.5 * math.sin(math.radians(30)) + 0.4 * math.sin(math.radians(75))
    np.testing.assert_allclose(result["position"], [x, y, 0.0], atol=1e-12)
    c, s = math.cos(math.radians(75)), math.sin(math.radians(75))
    np.testing.assert_allclose(result["rotation"], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-12)


def test_fk_negative_values_frame_and_set(capsys):
    code, out, _ = run(capsys, "fk", "planar_2r", "--q", "-0.5,1.0", "--frame", "link1", "--set", "a1=0.6", "--json")
    result = json.loads(out)
    assert code == 0 and result["frame"] == "link1"
    np.testing.assert_allclose(result["position"], [0.6 * math.cos(-0.5), 0.6 * math.sin(-0.5), 0.0], atol=1e-12)


def test_fk_text_and_limit_warning(capsys):
    code, out, err = run(capsys, "fk", "puma560", "--q", "0,0,0,0,0,3")
    assert code == 0 and "position (m)" in out
    assert err == ""
    code, out, err = run(capsys, "fk", "puma560", "--q", "3,0,0,0,0,0")
    assert code == 0 and "warning: q1 = 3 outside" in err


def test_jacobian_json_equals_api(capsys):
    q = [0.1, 0.7, -2.0, 0.3, 0.4, 0.5]
    code, out, _ = run(capsys, "jacobian", "puma560", "--q", ",".join(map(str, q)), "--json")
    result = json.loads(out)
    assert code == 0 and result["joints"] == ["q1", "q2", "q3", "q4", "q5", "q6"]
    expected = mechatron.frame_jacobian(mechatron.load("puma560"), np.array(q))
    np.testing.assert_allclose(result["jacobian"], expected, atol=1e-14)
    code, out, _ = run(capsys, "jacobian", "puma560", "--q", ",".join(map(str, q)))
    assert code == 0 and "singular values" in out and "vx" in out


def test_show(capsys):
    code, out, _ = run(capsys, "show", "puma560")
    assert code == 0 and "DH table" in out and "mobility W = 6" in out and "17.4" in out
    code, out, _ = run(capsys, "show", "scara", "--json")
    info = json.loads(out)
    assert info["mobility"] == 4 and info["nq"] == 4
    assert [j["kind"] for j in info["joints"]] == ["revolute", "revolute", "prismatic", "revolute"]
    assert info["parameters"]["a1"]["value"] == pytest.approx(0.325)
    assert info["drives"]["q3"]["reflected_inertia"] == pytest.approx(1e-5 * 314.159**2)


def test_demo(capsys):
    code, out, _ = run(capsys, "demo")
    assert code == 0 and "PUMA 560" in out and "tool position" in out


@pytest.mark.parametrize("argv,piece", [
    (["fk", "no_such_robot", "--q", "0"], "unknown robot 'no_such_robot'"),
    (["fk", "puma560", "--q", "0,0"], "--q needs 6 values for puma560"),
    (["fk", "puma560", "--q", "0,a,0,0,0,0"], "--q must be comma-separated numbers"),
    (["fk", "puma560", "--q", "0,0,0,0,0,0", "--frame", "hand"], "unknown frame of puma560 'hand'"),
    (["fk", "puma560", "--q", "0,0,0,0,0,0", "--set", "a9=1"], "unknown parameter of puma560 'a9'"),
    (["fk", "puma560", "--q", "0,0,0,0,0,0", "--set", "a2"], "--set expects NAME=VALUE"),
    (["show", "robots/missing.toml"], "no such file"),
    (["fk", "puma560"], "the following arguments are required: --q"),
    (["frobnicate"], "invalid choice"),
])
def test_errors_are_one_line_with_status_2(capsys, argv, piece):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 2
    assert piece in err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err


def test_malformed_robot_file_through_console_script(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[links]]\njoint = "revolute"\nmass = -2.0\n')
    proc = subprocess.run([sys.executable, "-m", "mechatron", "show", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"mechatron: error: {bad}: field 'links[1].mass': must be >= 0 kg, got -2"
    assert proc.stdout == ""


def test_help_for_every_command():
    for command in ["list", "show", "fk", "jacobian", "export-urdf", "demo"]:
        proc = subprocess.run([sys.executable, "-m", "mechatron", command, "--help"], capture_output=True, text=True)
        assert proc.returncode == 0 and "usage: mechatron" in proc.stdout


# ------------------------------------------------------------------- --json, --csv and --plot are the result's
def fingerprint(figure):
    """What a figure shows, axes by axes: labels, title, every line's data, every text and where it is, every bar,
    and the legends' entries."""
    out = []
    for ax in figure.axes:
        out.append((ax.get_xlabel(), ax.get_ylabel(), ax.get_title(),
                    [(line.get_label(), np.asarray(line.get_xydata()).round(12).tolist()) for line in ax.get_lines()],
                    [(text.get_text(), np.round(text.xy, 12).tolist()) for text in ax.texts],
                    [round(patch.get_height(), 12) for patch in ax.patches],
                    [text.get_text() for text in ax.get_legend().get_texts()] if ax.get_legend() else None))
    out.append([[text.get_text() for text in legend.get_texts()] for legend in figure.legends])
    return out


@pytest.fixture
def drawn(monkeypatch):
    """The figures the command line saves (kept, not rendered: what they show is compared, not their pixels)."""
    figures = {}

    def save_figure(figure, path, dpi=110):
        figures[Path(path).name] = figure
        return Path(path)

    monkeypatch.setattr("mechatron.io.output.save_figure", save_figure)
    return figures


def same_outputs(capsys, tmp_path, drawn, argv, result):
    """``mechatron ARGV --json --csv --plot`` prints ``result.as_dict()``, writes ``result.to_frame()`` and draws
    ``result.plot()``; without them it prints ``str(result)``."""
    import pandas as pd

    csv, png = tmp_path / "out.csv", tmp_path / "out.png"
    code, out, err = run(capsys, *argv, "--json", "--csv", str(csv), "--plot", str(png))
    assert code == 0, err
    assert json.loads(out) == json.loads(json.dumps(result.as_dict(), allow_nan=False))
    assert f"wrote {csv}" in err and f"wrote {png}" in err
    written, frame = pd.read_csv(csv), result.to_frame()
    assert list(written.columns) == list(frame.columns) and len(written) == len(frame)
    for column in frame.columns:
        if pd.api.types.is_numeric_dtype(frame[column]):
            np.testing.assert_allclose(written[column], frame[column], rtol=1e-9, atol=1e-12)
        else:
            assert written[column].tolist() == frame[column].tolist()
    assert fingerprint(drawn["out.png"]) == fingerprint(result.plot())
    code, text, _ = run(capsys, *argv)
    assert code == 0 and text.strip() == str(result).strip()


def test_show_outputs_are_the_result(capsys, tmp_path, drawn):
    from mechatron.kinematics.summary import mechanism_summary

    same_outputs(capsys, tmp_path, drawn, ["show", "scara"], mechanism_summary(mechatron.load("scara")))
    same_outputs(capsys, tmp_path, drawn, ["show", "crank_slider"], mechanism_summary(mechatron.load("crank_slider")))


def test_fk_outputs_are_the_result(capsys, tmp_path, drawn):
    from mechatron.kinematics.summary import frame_pose

    mech = mechatron.load("puma560")
    q = [0.1, 0.7, -2.0, 0.3, 0.4, 0.5]
    same_outputs(capsys, tmp_path, drawn, ["fk", "puma560", "--q", ",".join(map(str, q)), "--frame", "link4"],
                 frame_pose(mech, np.array(q), "link4"))


def test_fk_of_a_continuous_joint_prints_its_angle(capsys):
    urdf = str(Path(__file__).parent / "data" / "continuous_prismatic_arm.urdf")
    code, out, _ = run(capsys, "fk", urdf, "--q", "170,30,0.2", "--deg", "--frame", "tool0", "--json")
    result = json.loads(out)
    assert code == 0 and result["coordinates"] == pytest.approx([math.radians(170), math.radians(30), 0.2])
    L, phi, theta = 0.8, math.radians(30), math.radians(170)
    assert result["position"] == pytest.approx([L * math.cos(phi) * math.cos(theta),
                                                L * math.cos(phi) * math.sin(theta), 0.5 - L * math.sin(phi)])
    code, out, _ = run(capsys, "fk", urdf, "--q", "170,30,0.2", "--deg", "--frame", "tool0")
    assert f"spin = {math.radians(170):.6g} rad" in out


def test_jacobian_outputs_are_the_result(capsys, tmp_path, drawn):
    from mechatron.kinematics.summary import jacobian_summary

    mech = mechatron.load("ur5")
    q = [0.0, -1.57, 1.57, 0.0, 0.3, 0.0]
    same_outputs(capsys, tmp_path, drawn, ["jacobian", "ur5", "--q", ",".join(map(str, q)), "--reference", "local"],
                 jacobian_summary(mech, np.array(q), None, "local"))


def test_linkage_outputs_are_the_result(capsys, tmp_path, drawn):
    from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity
    from mechatron.kinematics.sweeps import sweep
    from mechatron.kinematics.vector_plans import plans

    mech = mechatron.load("six_bar_bucket")
    same_outputs(capsys, tmp_path, drawn, ["linkage", "six_bar_bucket", "--samples", "40"],
                 sweep(mech, samples=40, links=mech.link_names))
    # --plans draws the plans result at the position --at, the inputs moving at their nominal rates
    code, out, err = run(capsys, "linkage", "six_bar_bucket", "--samples", "10", "--plans", str(tmp_path / "p.png"),
                         "--at", "L1=1.5")
    assert code == 0 and f"wrote {tmp_path / 'p.png'}" in out, err
    q = assemble(mech, {"L1": 1.5})
    v = joint_velocity(mech, q, {"L1": mech.input_rates.get("L1", 1.0)})
    assert fingerprint(drawn["p.png"]) == fingerprint(plans(mech, q, v, joint_acceleration(mech, q, v)).plot())

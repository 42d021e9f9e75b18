"""The command line: machine-readable output, --set, and one-line errors with exit status 2."""

from __future__ import annotations

import json
import math
import subprocess
import sys

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
    names = json.loads(out)
    assert code == 0 and isinstance(names, list)
    assert {"puma560", "planar_2r", "cylindrical_rpp", "articulated_rrr", "planar_3r", "scara", "ur5", "panda"} <= set(names)


def test_list_text(capsys):
    code, out, _ = run(capsys, "list")
    assert code == 0 and "puma560" in out and "Unimation PUMA 560" in out


def test_fk_json_matches_closed_form(capsys):
    # planar 2R, q = (30°, 45°): C = (l1 cos 30° + l2 cos 75°, l1 sin 30° + l2 sin 75°)
    code, out, _ = run(capsys, "fk", "planar_2r", "--q", "30,45", "--deg", "--json")
    result = json.loads(out)
    assert code == 0 and set(result) == {"frame", "position", "rotation"}
    assert result["frame"] == "tool"
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

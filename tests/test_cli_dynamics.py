"""The dynamics and reduced commands."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics.motion import move
from mechatron.dynamics.reduced import reduced_table
from mechatron.kinematics.loops import assemble


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_dynamics_move_json_equals_the_api(capsys):
    code, out, _ = run(capsys, "dynamics", "planar_2r", "--move", "0,0;0.5,-1", "--profile", "trapezoidal",
                       "--vmax", "1", "--amax", "4", "--dt", "0.001", "--json")
    assert code == 0
    result = json.loads(out)
    mech = mechatron.load("planar_2r")
    traj = move(mech, [0, 0], [0.5, -1], profile="trapezoidal", vmax=1, amax=4, dt=0.001)
    tau = mechatron.inverse_dynamics(mech, traj.q, traj.v, traj.a)
    rows = {r["coordinate"]: r for r in result["coordinates"]}
    assert rows["q2"]["peak_force"] == pytest.approx(np.abs(tau[:, 1]).max(), rel=1e-12)
    assert result["duration"] == pytest.approx(traj.t[-1])


def test_dynamics_outputs_are_the_result_s(tmp_path, capsys):
    """--json is as_dict(), --csv is to_frame(), --plot is plot(), the text is str()."""
    argv = ["dynamics", "planar_2r", "--move", "0,0;30,-60", "--deg", "--vmax", "1", "--amax", "4"]
    code, out, err = run(capsys, *argv, "--json", "--csv", str(tmp_path / "loads.csv"), "--plot",
                         str(tmp_path / "loads.svg"))
    assert code == 0
    mech = mechatron.load("planar_2r")
    result = trajectory_loads(mech, move(mech, [0, 0], np.radians([30, -60]), vmax=1, amax=4))
    assert json.loads(out) == json.loads(result.to_json())
    written = pd.read_csv(tmp_path / "loads.csv")
    expected = result.to_frame()
    assert list(written.columns) == list(expected.columns)
    np.testing.assert_allclose(written.to_numpy(), expected.to_numpy(), rtol=1e-9, atol=1e-12)
    assert (tmp_path / "loads.svg").read_text().count("<svg") == 1 and "wrote" in err
    code, out, _ = run(capsys, *argv)
    assert code == 0 and out.strip() == str(result).strip()


def test_dynamics_trajectory_file_with_payload_and_outputs(tmp_path, capsys):
    mech = mechatron.load("scara")
    traj = move(mech, [0, 0, 0, 0], [1.0, -1.0, 0.1, 2.0], profile="scurve", dt=0.002)
    path = traj.to_csv(tmp_path / "move.csv")
    code, out, _ = run(capsys, "dynamics", "scara", "--trajectory", str(path), "--payload", "2",
                       "--csv", str(tmp_path / "loads.csv"), "--plot", str(tmp_path / "loads.png"))
    assert code == 0 and "peak_motor_torque" in out
    assert (tmp_path / "loads.png").stat().st_size > 20_000
    table = pd.read_csv(tmp_path / "loads.csv")
    assert {"tau_q1", "motor_torque_q1", "power_q3"} <= set(table.columns)


def test_dynamics_of_a_cylinder_mechanism(capsys):
    code, out, _ = run(capsys, "dynamics", "six_bar_bucket", "--move", "1.1;2.0", "--vmax", "0.2", "--amax", "1",
                       "--json")
    assert code == 0
    result = json.loads(out)
    assert result["coordinates"][0]["coordinate"] == "L1" and result["coordinates"][0]["peak_force"] > 1000


@pytest.mark.parametrize("argv,piece", [
    (["dynamics", "puma560"], "give either --trajectory FILE or --move SPEC"),
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0"], "at least two points"),
    (["dynamics", "puma560", "--move", "0,0;1,1"], "needs 6 values"),
    (["dynamics", "six_bar_bucket", "--move", "1.1;2.5"], "outside its range"),
    (["reduced", "puma560"], "degrees of mobility"),
    (["reduced", "crank_slider", "--input", "xC"], "actuated coordinate"),
])
def test_errors(capsys, argv, piece):
    code, _, err = run(capsys, *argv)
    assert code == 2 and piece in err and len(err.strip().splitlines()) == 1


def test_reduced_command(tmp_path, capsys):
    code, out, _ = run(capsys, "reduced", "crank_slider", "--samples", "13", "--json", "--plot",
                       str(tmp_path / "r.png"))
    assert code == 0
    result = json.loads(out)
    mech = mechatron.load("crank_slider")
    for phi, J in zip(result["table"]["q1"], result["table"]["J_reduced"]):
        assert J == pytest.approx(mechatron.dynamics.reduced_inertia(mech, assemble(mech, {"q1": phi}), "q1"), rel=1e-9)
    assert (tmp_path / "r.png").exists()
    code, out, _ = run(capsys, "reduced", "six_bar_bucket")
    assert code == 0 and "reduced mass" in out
    assert out.strip() == str(reduced_table(mechatron.load("six_bar_bucket"))).strip()
    code, out, _ = run(capsys, "reduced", "crank_slider", "--samples", "5", "--csv", str(tmp_path / "r.csv"),
                       "--json")
    expected = reduced_table(mech, samples=5)
    assert json.loads(out) == json.loads(expected.to_json())
    np.testing.assert_allclose(pd.read_csv(tmp_path / "r.csv").to_numpy(), expected.to_frame().to_numpy(),
                               rtol=1e-9, atol=1e-12)

"""``mechatron optimize -o DIR`` never throws away a finished search (issue 32): a design whose moved pin puts the
*drawn* pose outside its cylinder's stroke is written drawn at the pose the search evaluated, and reads back to the
same outputs; a design that would not read back is an error naming the file being written, after the results are
printed and saved; the progress line ends on its own line with why it ended.

The mechanism is a rocker O-B-T pinned to the ground at O and lifted by a cylinder from a ground pin A = (a, 0) to
its bracket B, |OB| = r = 0.5 m, the tip T on the line OB at 1 m. With the cylinder at length c the law of cosines
gives cos φ = (a² + r² − c²) / (2 a r), so the tip's x = cos φ and, over the stroke [c₀, c₁] = [0.40, 0.65] m, the
x travel is (c₁² − c₀²) / (2 a r) = 0.2625 / a: least at the largest a. Drawn at a = 0.6 with B = (0.3, 0.4)
(|AB| = 0.5 m), the bound a = 0.85 puts the drawn |AB| at √(0.55² + 0.4²) = 0.680 m, outside the stroke, while
the search's rebuild holds the cylinder at its drawn 0.5 m: there |OB| = |AB| = r, so B = (a/2, √(r² − a²/4)).
"""

import json
import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from mechatron.errors import InputError

ROCKER = """
name = "rocker"
gravity = 9.81
tool = "T"
actuated = ["cyl"]

[points]
O = [0.0, 0.0]
A = [0.6, 0.0]
B = [0.3, 0.4]
T = [0.6, 0.8]
{extra_points}
[[bodies]]
name = "ground"
points = ["O", "A"{extra_ground}]

[[bodies]]
name = "rocker"
points = ["O", "B", "T"]
mass = 20.0
com = "B"
inertia = 1.5

[[joints]]
type = "revolute"
body = "rocker"
at = "O"
coordinate = "phi"
toward = "T"

[[joints]]
type = "cylinder"
name = "cyl"
base = "A"
eye = "B"
stroke_mm = [400, 650]
{extra_joints}"""

DESIGN = """
name = "rocker travel"
mechanism = "rocker.toml"
[variables]
A_x = [0.3, 0.85]
[objective]
minimize = "x_travel_m"
[analyses.linkage]
samples = 9
[solver]
method = "ipopt"
population = 6
"""


def _files(folder, extra_points="", extra_ground="", extra_joints=""):
    (folder / "rocker.toml").write_text(ROCKER.format(extra_points=extra_points, extra_ground=extra_ground,
                                                      extra_joints=extra_joints))
    design = folder / "rocker_design.toml"
    design.write_text(DESIGN)
    return design


def _outputs(spec, mechanism):
    """The study analyses' outputs of the mechanism file ``mechanism`` (no variables: as it is)."""
    from mechatron.studies.runner import evaluate

    study = replace(spec.evaluator, mechanism=str(mechanism), parameters=())
    (row,) = evaluate(study, pd.DataFrame({"design": [0], "seed": [0]})).to_dict(orient="records")
    assert row["status"] == "ok", row["reason"]
    return row


def test_a_moved_pin_outside_the_drawn_stroke_is_written_at_the_evaluated_pose_and_reads_back(tmp_path):
    import mechatron
    from mechatron.model.linkage import build_linkage, parameter_spec
    from mechatron.model.linkage_file import read_linkage_file
    from mechatron.optimal.reader import read_problem as read_design
    from mechatron.optimal.solve import optimize_design
    from mechatron.optimal.write import write_designs

    spec = read_design(_files(tmp_path))
    result = optimize_design(spec)
    a = result.best["A_x"]
    assert a == pytest.approx(0.85, abs=1e-9)  # the x travel 0.2625 / a is least at the largest a
    assert result.best["x_travel_m"] == pytest.approx(0.2625 / a, rel=1e-9)  # law of cosines at both stroke ends
    drawn = math.hypot(a - 0.3, 0.4)
    assert drawn > 0.65  # the drawn pose's cylinder leaves the stroke [0.40, 0.65] m ...
    with pytest.raises(InputError, match="outside its stroke"):  # ... so the design drawn as the file draws it fails
        build_linkage(parameter_spec(read_linkage_file(tmp_path / "rocker.toml"), {"A_x": a}))

    (path,) = write_designs(spec, pd.DataFrame([result.best]), tmp_path / "best")
    written = read_linkage_file(path).drawing()
    b = np.array([a / 2, math.sqrt(0.25 - a * a / 4)])  # |OB| = |AB| = 0.5 m: the cylinder held at its drawn length
    np.testing.assert_allclose(written["A"], [a, 0.0], atol=1e-12)
    np.testing.assert_allclose(written["B"], b, atol=1e-12)
    np.testing.assert_allclose(written["T"], 2 * b, atol=1e-12)
    assert mechatron.load(path).notes == []  # drawn closed: no point moved when it is read back
    again = _outputs(spec, path)
    outputs = [k for k in again if k.endswith(("_m", "_N", "_deg", "_Pa"))]
    assert "x_travel_m" in outputs and "cyl_max_force_N" in outputs
    for name in outputs:
        assert again[name] == pytest.approx(result.best[name], rel=1e-9, abs=1e-12), name


def test_the_command_line_saves_the_results_and_the_design_and_ends_the_progress_line(tmp_path, capsys, monkeypatch):
    import io

    from mechatron.cli import main
    from mechatron.report import progress

    stream = io.StringIO()
    real = progress.progress_bar
    monkeypatch.setattr(progress, "progress_bar", lambda label: real(label, stream, force=True))
    design = _files(tmp_path)
    out = tmp_path / "best"
    assert main(["optimize", str(design), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("rocker travel (rocker.toml)")
    data = json.loads((out / "optimum.json").read_text())
    table = pd.read_csv(out / "designs.csv")
    assert data["evaluated"] == len(table) and data["best"]["x_travel_m"] == pytest.approx(
        0.2625 / data["best"]["A_x"], rel=1e-9)
    assert (out / "design-000.toml").is_file() and f"wrote {out / 'design-000.toml'}" in printed
    line = stream.getvalue()
    assert line.endswith("\n") and line.count("\n") == 1  # the report starts on its own line
    last = line.rsplit("\r", 1)[-1]
    assert f"{len(table)} done" in last  # the designs evaluated: a design asked for again is not evaluated again
    assert "100%" in last or f"{len(table)} of the budget's 400 designs evaluated" in last


PASSIVE = dict(extra_points='C = [0.6, 0.6]\n', extra_ground=', "C"',
               extra_joints='\n[[joints]]\ntype = "cylinder"\nname = "damper"\nbase = "C"\neye = "T"\n'
                            'stroke_mm = [200, 280]\n')


def test_a_design_that_would_not_read_back_is_an_error_naming_the_written_file_after_the_results(tmp_path, capsys):
    # a passive damper C-T, C = (0.6, 0.6): drawn |CT| = 0.2 m; at a = 0.85 the held cylinder turns the rocker to
    # T = 2B = (0.85, 0.527), |CT| = √(0.25² + 0.073²) = 0.260 m — inside [0.20, 0.28] m; the stroke of the damper is
    # then narrowed so that it is not: the written drawing (the evaluated pose) would not read back
    from mechatron.cli import main

    design = _files(tmp_path, **{**PASSIVE, "extra_joints": PASSIVE["extra_joints"].replace("280", "240")})
    out = tmp_path / "best"
    assert main(["optimize", str(design), "-o", str(out), "--json"]) == 2
    captured = capsys.readouterr()
    data = json.loads(captured.out)  # the results printed first ...
    assert data["best"] is not None
    assert json.loads((out / "optimum.json").read_text())["best"] == data["best"]  # ... and saved
    assert (out / "designs.csv").is_file() and not (out / "design-000.toml").exists()
    error = captured.err.strip().splitlines()[-1]
    assert error.startswith(f"mechatron: error: {out / 'design-000.toml'}: field 'joints[3].stroke'")
    assert "outside its stroke" in error and str(tmp_path / "rocker.toml") not in error

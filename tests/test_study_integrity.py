"""A study's integrity (issue 22, items 1, 2 and 5): its identity is the bytes of every file it reads, its part
files record their designs, its output settings are checked before any design runs and are not part of its rows,
and every file of a targeted list is checked up front. Through the command line: exit codes, one-line messages
naming the file or field, tables equal to a fresh run, the folder byte-identical after every refused run."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest
from pandas.testing import assert_frame_equal

import mechatron
from mechatron.studies.analyses import analysis
from mechatron.studies.runner import run_study
from mechatron.studies.spec import read_study as read_spec
from tests.corpus import assert_clean_error, run

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "examples" / "data"

LINKAGE = """mechanism = "{mechanism}"
[parameters.l1]
values = [0.09, 0.1, 0.11, 0.12]
[designs]
method = "grid"
[analyses.linkage]
samples = 13
"""


def table(folder: Path) -> pd.DataFrame:
    return pd.read_parquet(folder / "designs.parquet")


def fresh(capfd, folder: Path, spec: str = "s.toml", out: str = "fresh") -> pd.DataFrame:
    """The table of a run of ``spec`` in a new folder ``out``."""
    outcome = run(["study", spec, "--out", out], capfd, folder)
    assert outcome.code == 0, outcome.err
    return table(folder / out)


# ------------------------------------------------------------------------ 1. the bytes of every file read
def _mechanism(folder: Path) -> str:
    shutil.copy(ROOT / "robots" / "crank_slider.toml", folder / "mech.toml")
    (folder / "s.toml").write_text(LINKAGE.format(mechanism="mech.toml"))
    return "mech.toml"


def _designs_csv(folder: Path) -> str:
    (folder / "designs.csv").write_text("l1,l2\n0.09,0.4\n0.1,0.4\n0.11,0.38\n0.12,0.36\n")
    (folder / "s.toml").write_text('mechanism = "crank_slider"\n[designs]\nmethod = "csv"\nfile = "designs.csv"\n'
                                   '[analyses.linkage]\nsamples = 13\n')
    return "designs.csv"


def _tolerances(folder: Path) -> str:
    shutil.copy(DATA / "tolerances_crank_slider.csv", folder / "tol.csv")
    (folder / "s.toml").write_text(LINKAGE.format(mechanism="crank_slider")
                                   + '[analyses.accuracy]\ntolerances = "tol.csv"\nlimit_mm = 2.0\nsamples = 50\n')
    return "tol.csv"


def _second_of_a_list(folder: Path) -> str:
    for name in ("tol_a.csv", "tol_b.csv"):
        shutil.copy(DATA / "tolerances_crank_slider.csv", folder / name)
    (folder / "s.toml").write_text('mechanism = "crank_slider"\n[parameters.l1]\nvalues = [0.09, 0.11]\n'
                                   '[parameters.tol]\ntarget = "accuracy.tolerances"\n'
                                   'values = ["tol_a.csv", "tol_b.csv"]\n[designs]\nmethod = "grid"\n'
                                   '[analyses.accuracy]\nlimit_mm = 2.0\nsamples = 50\n')
    return "tol_b.csv"


def _trajectory_of_a_task(folder: Path) -> str:
    # a file read through another: the task names its trajectory CSV
    shutil.copy(DATA / "planar_2r_move.csv", folder / "move.csv")
    (folder / "task.toml").write_text('trajectory = "move.csv"\npayload = 1.0\n')
    (folder / "s.toml").write_text('mechanism = "planar_2r"\n[parameters.a2]\nvalues = [0.3, 0.35, 0.4, 0.45]\n'
                                   '[designs]\nmethod = "grid"\n[analyses.dynamics]\ntask = "task.toml"\n')
    return "move.csv"


def _edit(path: Path) -> None:
    """Change a file's content so that its rows change: the tool point of a mechanism, a number doubled or
    changed."""
    text = path.read_text()
    for old, new in (('tool = "C"', 'tool = "B"'), ("l1,1.0,", "l1,2.0,"), ("0.11,0.38", "0.11,0.39"),
                     (",2.88,-5.76", ",5.76,-5.76")):
        if old in text:
            path.write_text(text.replace(old, new, 1))
            return
    raise AssertionError(f"nothing to edit in {path}")


@pytest.mark.parametrize("setup", [_mechanism, _designs_csv, _tolerances, _second_of_a_list, _trajectory_of_a_task])
def test_a_changed_file_is_refused_and_restart_starts_again(tmp_path, capfd, setup):
    # a study stopped after one of its chunks; a file it reads edited; the resume refused in one line naming the
    # file and how to start over, the folder untouched; --restart gives the table of a fresh run on the new file
    changed = setup(tmp_path)
    before = fresh(capfd, tmp_path, out="before")
    assert run_study(tmp_path / "s.toml", tmp_path / "out", chunk_size=1, max_chunks=1) is None
    _edit(tmp_path / changed)
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path,
                       ["out/study.json", f": {changed} changed since this study started", "--restart",
                        "the 1 row done", "another --out"])
    outcome = run(["study", "s.toml", "--out", "out", "--restart"], capfd, tmp_path)
    assert outcome.code == 0 and outcome.err == "", outcome.err
    after = table(tmp_path / "out")
    assert_frame_equal(after, fresh(capfd, tmp_path))
    assert not after.drop(columns="tol", errors="ignore").equals(before.drop(columns="tol", errors="ignore"))
    assert len(list((tmp_path / "out" / "parts").glob("*.parquet"))) == 4  # every chunk of one design anew


def test_a_file_missing_on_resume_is_refused(tmp_path, capfd):
    # the task's trajectory removed: the spec is refused (the task does not read), naming the file
    _trajectory_of_a_task(tmp_path)
    assert run_study(tmp_path / "s.toml", tmp_path / "out", chunk_size=1, max_chunks=1) is None
    (tmp_path / "move.csv").unlink()
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path, ["move.csv"])


def test_the_files_read_are_recorded(tmp_path, capfd):
    # the mechanism, the task and its trajectory, the four catalogs (the defaults): each with its SHA-256
    import hashlib

    _trajectory_of_a_task(tmp_path)
    (tmp_path / "s.toml").write_text((tmp_path / "s.toml").read_text() + "[analyses.sizing]\ntask = \"task.toml\"\n")
    spec = read_spec(tmp_path / "s.toml")
    names = [Path(p).name for p in spec.files]
    assert names == ["planar_2r.toml", "task.toml", "move.csv", "servo_motors.csv", "gearboxes.csv",
                     "linear_drives.csv", "hydraulic_cylinders.csv"]
    assert run_study(spec, tmp_path / "out", chunk_size=1, max_chunks=1) is None
    files = json.loads((tmp_path / "out" / "study.json").read_text())["files"]
    assert files == {p: hashlib.sha256(Path(p).read_bytes()).hexdigest() for p in spec.files}


def test_a_urdf_and_its_srdf_are_files_of_the_study(tmp_path):
    for name in ("turret_arm.urdf", "turret_arm.srdf"):
        shutil.copy(DATA / name, tmp_path / name)
    mech = mechatron.load(tmp_path / "turret_arm.urdf")
    joint = next(iter(mech.parameters))
    (tmp_path / "s.toml").write_text(f'mechanism = "turret_arm.urdf"\n[parameters.{joint}]\nrelative = 0.1\n'
                                     '[designs]\nmethod = "grid"\nlevels = 2\n[analyses.dynamics]\n')
    spec = read_spec(tmp_path / "s.toml")
    assert [Path(p).name for p in spec.files] == ["turret_arm.urdf", "turret_arm.srdf"]


# ------------------------------------------------------------------------------------- 2. the part files
def _copied_over(parts: Path) -> str:
    shutil.copy(parts / "part-00000.parquet", parts / "part-00002.parquet")
    return "part-00002.parquet holds designs 0, not 2"


def _truncated(parts: Path) -> str:
    data = (parts / "part-00001.parquet").read_bytes()
    (parts / "part-00001.parquet").write_bytes(data[: len(data) // 2])
    return "part-00001.parquet does not read"


def _corrupt_bytes(parts: Path) -> str:
    data = bytearray((parts / "part-00003.parquet").read_bytes())
    data[8:200] = bytes(192)
    (parts / "part-00003.parquet").write_bytes(bytes(data))
    return "part-00003.parquet does not read"


def _unrecorded(parts: Path) -> str:
    # the right rows, written by hand: nothing says which designs they are
    pd.read_parquet(parts / "part-00001.parquet").to_parquet(parts / "part-00001.parquet", index=False)
    return "part-00001.parquet records no designs"


@pytest.mark.parametrize("damage", [_copied_over, _truncated, _corrupt_bytes, _unrecorded])
def test_a_part_that_does_not_hold_its_designs_is_computed_again(tmp_path, capfd, damage):
    _mechanism(tmp_path)
    assert run(["study", "s.toml", "--out", "out", "--chunk", "1"], capfd, tmp_path).code == 0
    note = damage(tmp_path / "out" / "parts")
    outcome = run(["study", "s.toml", "--out", "out", "--json"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    lines = outcome.err.strip("\n").split("\n")
    assert len(lines) == 1 and lines[0].startswith("mechatron: warning: ") and note in lines[0], outcome.err
    assert "computed again" in lines[0] and "internal error" not in lines[0]
    data = json.loads(outcome.out)
    assert data["designs"] == 4 and sorted(row["design"] for row in data["rows"]) == [0, 1, 2, 3]
    assert_frame_equal(table(tmp_path / "out"), fresh(capfd, tmp_path))
    again = run(["study", "s.toml", "--out", "out"], capfd, tmp_path)  # the part is whole again: no note
    assert again.code == 0 and again.err == ""


def test_a_part_of_another_study_is_computed_again(tmp_path, capfd):
    # the state file removed and the mechanism edited: the parts left are of another study
    _mechanism(tmp_path)
    assert run(["study", "s.toml", "--out", "out", "--chunk", "1"], capfd, tmp_path).code == 0
    (tmp_path / "out" / "study.json").unlink()
    _edit(tmp_path / "mech.toml")
    outcome = run(["study", "s.toml", "--out", "out", "--chunk", "1"], capfd, tmp_path)
    assert outcome.code == 0 and "part-00000.parquet is of another study (and 3 more)" in outcome.err
    assert_frame_equal(table(tmp_path / "out"), fresh(capfd, tmp_path))


# -------------------------------------------------------------------------------------- output settings
@pytest.mark.parametrize("axis", ["x", "y"])
def test_an_unknown_pareto_output_is_refused_before_any_design(tmp_path, capfd, axis):
    _mechanism(tmp_path)
    other = "reach_m" if axis == "x" else "x_travel_m"
    pareto = {"x": "x_travle_m", "y": other} if axis == "x" else {"x": other, "y": "x_travle_m"}
    with (tmp_path / "s.toml").open("a") as fh:
        fh.write(f'[output.pareto]\nx = "{pareto["x"]}"\ny = "{pareto["y"]}"\n')
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path,
                       ["s.toml", f"field 'output.pareto.{axis}'", "unknown output 'x_travle_m'",
                        "reach_m, height_m, depth_m, x_travel_m, y_travel_m", "or a parameter: l1"])


def test_output_settings_change_on_a_finished_study_without_a_row_computed(tmp_path, capfd):
    # a finished Sobol study, then other Pareto axes and goals and Sobol indices asked for: the same folder, no part
    # written again, the chart's axes and the indices those of the new settings
    base = ('mechanism = "crank_slider"\n[parameters.l1]\nlow = 0.08\nhigh = 0.12\n[parameters.l2]\nlow = 0.35\n'
            'high = 0.45\n[designs]\nmethod = "sobol"\nsamples = 8\nseed = 1\n[analyses.linkage]\nsamples = 13\n')
    (tmp_path / "s.toml").write_text(base + "[output]\nsensitivity = false\n")
    first = run(["study", "s.toml", "--out", "out", "--json"], capfd, tmp_path)
    assert first.code == 0 and json.loads(first.out)["sensitivity"] is None
    parts = tmp_path / "out" / "parts"
    stamps = {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in parts.iterdir()}
    (tmp_path / "s.toml").write_text(base + '[output]\nsensitivity = true\n[output.pareto]\nx = "reach_m"\n'
                                            'x_goal = "maximize"\ny = "x_travel_m"\n')
    second = run(["study", "s.toml", "--out", "out", "--json"], capfd, tmp_path)
    assert second.code == 0, second.err
    data = json.loads(second.out)
    assert (data["pareto"]["x"], data["pareto"]["x_goal"], data["pareto"]["y"]) == ("reach_m", "maximize",
                                                                                     "x_travel_m")
    assert {row["output"] for row in data["sensitivity"]} >= {"reach_m", "x_travel_m"}
    assert {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in parts.iterdir()} == stamps
    assert read_spec(tmp_path / "s.toml").digest() == read_spec(tmp_path / "s.toml").digest()
    (tmp_path / "t.toml").write_text(base)
    assert read_spec(tmp_path / "t.toml").digest() == read_spec(tmp_path / "s.toml").digest()


@pytest.mark.parametrize("mechanism, name, options", [
    ("crank_slider", "linkage", {"samples": 13}),
    ("front_shovel", "linkage", {"samples": 3, "cylinders": {"L2": {"bore": 0.2, "rod": 0.14}}}),
    ("delta", "linkage", {"samples": 5}),
    ("planar_2r", "dynamics", {"start": [0.0, 0.0], "end": [1.0, 0.5], "dt": 0.05}),
    ("crank_slider", "dynamics", {"start": [0.0], "end": [1.0], "dt": 0.05}),
    ("crank_slider", "accuracy", {"tolerances": str(DATA / "tolerances_crank_slider.csv"), "limit_mm": 2.0,
                                  "samples": 20}),
])
def test_output_names_are_the_outputs(mechanism, name, options):
    mech = mechatron.load(mechanism)
    module = analysis(name)
    assert module.output_names(mech, options) == list(module.outputs(mech, options, seed=0))


# ------------------------------------------------------------------------- 5. every file of a targeted list
@pytest.mark.parametrize("values, bad, field", [
    (["tol_a.csv", "tol_b.csv"], None, "values[1]"),
    (["tol_a.csv", "tol_a.csv", "tol_b.csv"], None, "values[2]"),
    (["tol_a.csv", "tol_b.csv"], "l9,1.0,,1.0,,normal,no such parameter\n", "values[1]"),
])
def test_every_file_of_a_targeted_list_is_checked_up_front(tmp_path, capfd, values, bad, field):
    shutil.copy(DATA / "tolerances_crank_slider.csv", tmp_path / "tol_a.csv")
    if bad is not None:
        (tmp_path / "tol_b.csv").write_text((tmp_path / "tol_a.csv").read_text() + bad)
    listed = ", ".join(f'"{v}"' for v in values)
    (tmp_path / "s.toml").write_text('mechanism = "crank_slider"\n[parameters.tol]\ntarget = "accuracy.tolerances"\n'
                                     f'values = [{listed}]\n[designs]\nmethod = "grid"\n'
                                     '[analyses.accuracy]\nlimit_mm = 2.0\nsamples = 50\n')
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path,
                       ["s.toml", f"field 'parameters.tol.{field}'", "tolerances", "tol_b.csv"])


def test_every_value_of_a_targeted_option_list_is_checked_up_front(tmp_path, capfd):
    # not files only: a profile misspelt in the second place of the list is refused before any design runs
    (tmp_path / "s.toml").write_text('mechanism = "planar_2r"\n[parameters.profile]\ntarget = "dynamics.profile"\n'
                                     'values = ["trapezoidal", "quintik"]\n[designs]\nmethod = "grid"\n'
                                     '[analyses.dynamics]\nstart = [0.0, 0.0]\nend = [1.0, 0.0]\n')
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path,
                       ["s.toml", "field 'parameters.profile.values[1]'", "unknown profile 'quintik'", "quintic"])

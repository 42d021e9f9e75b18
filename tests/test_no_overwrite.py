"""No command writes over a file it reads, wherever that file was named (issue 22, item 3).

A study's designs CSV and catalogs, an optimisation's poses, tolerances and cylinder catalog, a task's trajectory:
each named inside a file the command reads, not on its command line. An output option naming one of them is refused
in one line naming the option and the file, exit 2, with every file of the folder byte-identical and nothing
written (:func:`tests.corpus.assert_clean_error`). A study's own folder (``--out``), whose parts it writes and reads
back, holds no inputs.
"""

from __future__ import annotations

import os
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from mechatron.errors import InputError
from mechatron.io.output import check_input, transaction
from tests.corpus import assert_clean_error, run

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
DATA = EXAMPLES / "data"

REFUSED = "is an input of this command; write the output to another file"


def _study(folder: Path, sizing: str = "") -> None:
    """A study of two PUMA 560 designs from ``designs.csv``, its sizing analysis with the options ``sizing``."""
    (folder / "designs.csv").write_text("a2,d4\n0.43,0.43\n0.45,0.41\n")
    (folder / "s.toml").write_text('mechanism = "puma560"\n[designs]\nmethod = "csv"\nfile = "designs.csv"\n'
                                   f"[analyses.sizing]\n{sizing}")


def _accuracy(folder: Path, poses: str = "poses.csv") -> None:
    """An optimisation of the PUMA 560's a2 and d4 for accuracy, with its tolerances and poses beside it."""
    shutil.copy(EXAMPLES / "optimize" / "puma_tolerances.csv", folder / "tol.csv")
    shutil.copy(DATA / "poses_puma560.csv", folder / "poses.csv")
    (folder / "opt.toml").write_text(
        'name = "p"\nmechanism = "puma560"\n[objective]\ntype = "positioning_error"\ntolerances = "tol.csv"\n'
        f'poses = "{poses}"\n[variables]\na2 = [0.30, 0.60]\nd4 = [0.20, 0.60]\n'
        '[doe]\npoints = 16\nmethod = "sobol"\nseed = 1\n')


def test_a_study_does_not_write_its_results_over_its_designs_csv(tmp_path, capfd):
    _study(tmp_path)
    assert_clean_error(["study", "s.toml", "--csv", "designs.csv"], capfd, tmp_path, ["--csv designs.csv", REFUSED])


@pytest.mark.parametrize("option, catalog", [("motors", "motors.csv"), ("gearboxes", "gearboxes.csv"),
                                             ("linear", "linear_drives.csv"),
                                             ("cylinders", "hydraulic_cylinders.csv")])
def test_a_study_does_not_write_over_a_catalog_its_spec_names(tmp_path, capfd, option, catalog):
    shutil.copy(DATA / catalog, tmp_path / catalog)
    _study(tmp_path, f'{option} = "{catalog}"\n')
    assert_clean_error(["study", "s.toml", "--out", "out", "--csv", catalog], capfd, tmp_path,
                       [f"--csv {catalog}", REFUSED, f"[analyses.sizing] {option}"])


@pytest.mark.parametrize("name", ["poses.csv", "tol.csv"])
def test_optimize_does_not_write_over_its_poses_or_tolerances(tmp_path, capfd, name):
    _accuracy(tmp_path)
    assert_clean_error(["optimize", "opt.toml", "--csv", name], capfd, tmp_path, [f"--csv {name}", REFUSED])


def test_optimize_does_not_write_over_its_cylinder_catalog(tmp_path, capfd):
    spec = (EXAMPLES / "optimize" / "front_shovel_cylinders.toml").read_text()
    (tmp_path / "shovel.toml").write_text(spec.replace("# catalog = ", "catalog = "))
    shutil.copy(DATA / "hydraulic_cylinders.csv", tmp_path / "my_cylinders.csv")
    assert_clean_error(["optimize", "shovel.toml", "--csv", "my_cylinders.csv"], capfd, tmp_path,
                       ["--csv my_cylinders.csv", REFUSED])


def test_a_file_reached_through_a_link_is_the_same_file(tmp_path, capfd):
    _accuracy(tmp_path, poses="link.csv")
    (tmp_path / "link.csv").symlink_to("poses.csv")
    assert_clean_error(["optimize", "opt.toml", "--csv", "poses.csv"], capfd, tmp_path,
                       ["--csv poses.csv is an input of this command (read as link.csv); write the output"])


def test_size_does_not_write_over_the_trajectory_its_task_names(tmp_path, capfd):
    shutil.copy(DATA / "puma560_move.csv", tmp_path / "move.csv")
    (tmp_path / "task.toml").write_text('trajectory = "move.csv"\n')
    assert_clean_error(["size", "puma560", "--task", "task.toml", "--csv", "move.csv"], capfd, tmp_path,
                       ["--csv move.csv", REFUSED])


def test_a_file_named_on_the_command_line_is_refused_before_any_work(tmp_path, capfd):
    shutil.copy(DATA / "tolerances_puma560.csv", tmp_path / "tol.csv")
    assert_clean_error(["tolerance", "puma560", "--tolerances", "tol.csv", "--contributions", "tol.csv"], capfd,
                       tmp_path, ["--contributions tol.csv", REFUSED])


def test_a_study_reads_back_its_own_folder_and_writes_its_table_there(tmp_path, capfd):
    """Parts and tables in ``--out`` are the study's own, not inputs: a resume with ``--csv`` inside the folder
    runs."""
    (tmp_path / "out").mkdir()
    _study(tmp_path)
    for _ in range(2):  # a fresh run, then a resume from the parts
        outcome = run(["study", "s.toml", "--out", "out", "--csv", "out/designs.csv"], capfd, tmp_path)
        assert outcome.code == 0, outcome.err
        assert "wrote out/designs.csv" in outcome.out
    assert (tmp_path / "designs.csv").read_text() == "a2,d4\n0.43,0.43\n0.45,0.41\n"


def test_any_python_read_of_an_output_is_refused_inside_the_transaction(tmp_path, monkeypatch):
    """The check is every ``open`` for reading (TOML, CSV, the URDF's XML, ``os.open``), not a list of readers;
    writes, other files, and reads outside the transaction or after its commit pass."""
    monkeypatch.chdir(tmp_path)
    Path("robot.urdf").write_text('<robot name="r"/>')
    Path("other.txt").write_text("x")
    with pytest.raises(InputError, match=r"^--out robot.urdf is an input"):
        with transaction() as current:
            current.writes("robot.urdf", "--out")
            assert Path("other.txt").read_text() == "x"
            ET.parse("robot.urdf")
    with transaction() as current:
        current.writes("robot.urdf", "--out")
        with pytest.raises(InputError, match="is an input"):
            os.open("robot.urdf", os.O_RDONLY)
        with open("robot.urdf", "a") as fh:  # opened for writing: no read
            fh.write("")
        check_input("other.txt")
    assert ET.parse("robot.urdf").getroot().tag == "robot"

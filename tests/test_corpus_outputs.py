"""Issue 13, output files: every output option of every command refuses a bad path before any work, in one line
naming the option and the path, with every file in the folder unchanged; a command writes all of its outputs or
none (a failure after some were staged keeps the earlier files); stale companions of an earlier run go.

The bad paths: an existing directory, a folder that does not exist, an unsupported suffix, a regular file as the
folder (never writable, even by root), a read-only folder (when not root), /dev/full (a failed write), two options
naming the same file, an output naming an input file.
"""

from __future__ import annotations

import errno
import os
import shutil
from pathlib import Path

import pytest

from tests.corpus import assert_clean_error, run, snapshot

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "examples" / "data"
FOUR_BAR = str(DATA / "four_bar.toml")

#: Each command with the arguments it needs and its output options (the files they write; the -o of export-urdf
#: and of excavator take different formats).
COMMANDS = {
    "show": (["show", "planar_2r"], ["--csv", "--plot"]),
    "fk": (["fk", "planar_2r", "--q", "0,0"], ["--csv", "--plot"]),
    "jacobian": (["jacobian", "planar_2r", "--q", "0,1"], ["--csv", "--plot"]),
    "linkage": (["linkage", FOUR_BAR, "--samples", "5"], ["--csv", "--plot", "--report", "--plans"]),
    "excavator": (["excavator", "--samples", "3"], ["--csv", "--plot", "-o"]),
    "dynamics": (["dynamics", "planar_2r", "--move", "0,0;1,1"], ["--csv", "--plot"]),
    "reduced": (["reduced", "crank_slider", "--samples", "5"], ["--csv", "--plot"]),
    "size": (["size", "planar_2r"], ["--csv", "--plot", "--report", "--plots"]),
    "tolerance": (["tolerance", "puma560", "--tolerances", str(DATA / "tolerances_puma560.csv"), "--samples", "50"],
                  ["--csv", "--plot", "--report", "--contributions", "--plots"]),
    "structure": (["structure", FOUR_BAR], ["--csv", "--plot"]),
    "export-urdf": (["export-urdf", "planar_2r"], ["-o"]),
}
GOOD = {"--csv": "out.csv", "--plot": "out.png", "--plans": "plans.svg", "--report": "out.html",
        "--contributions": "contributions.csv", "--plots": "charts", "-o excavator": "out.toml",
        "-o export-urdf": "out.urdf"}
UNSUPPORTED = {"--csv": "out.png", "--plot": "out.xyz", "--plans": "plans.csv", "--report": "out.pdf",
               "--contributions": "contributions.html", "-o excavator": "out.urdf", "-o export-urdf": "out.srdf"}
FILE_OPTIONS = [(command, option) for command, (_, options) in COMMANDS.items() for option in options
                if option != "--plots"]
FOLDER_OPTIONS = [(command, "--plots") for command, (_, options) in COMMANDS.items() if "--plots" in options]


def key(command: str, option: str) -> str:
    return f"{option} {command}" if option == "-o" else option


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A working folder with earlier outputs, a sub-folder and a regular file (never a folder)."""
    for name in ("out.csv", "out.png", "out.html", "contributions.csv", "out.urdf", "out.toml", "plans.svg"):
        (tmp_path / name).write_text(f"earlier {name}\n")
    (tmp_path / "adir").mkdir()
    (tmp_path / "adir" / "keep.txt").write_text("keep\n")
    (tmp_path / "afile").write_text("a file\n")
    return tmp_path


def clean(argv, capfd, folder, option, path, pattern=None):
    """The one line names the option (as argparse shows it: ``-o/--output``) and the path."""
    assert_clean_error(argv, capfd, folder, [option, str(path)], pattern)


# ------------------------------------------------------------------------------------ refused before any work
@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS)
def test_a_directory_is_not_an_output_file(command, option, capfd, folder):
    clean([*COMMANDS[command][0], option, "adir"], capfd, folder, option, "adir", "is a directory")


@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS)
def test_a_missing_folder_is_refused(command, option, capfd, folder):
    path = Path("nowhere") / GOOD[key(command, option)]
    clean([*COMMANDS[command][0], option, str(path)], capfd, folder, option, path, "nowhere does not exist")
    assert not (folder / "nowhere").exists()


@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS)
def test_an_unsupported_format_is_refused(command, option, capfd, folder):
    path = UNSUPPORTED[key(command, option)]
    clean([*COMMANDS[command][0], option, path], capfd, folder, option, path, "cannot write .* as a .* file; use")


@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS)
def test_a_file_as_the_folder_is_refused(command, option, capfd, folder):
    """``afile/out.csv``: a regular file is never a writable folder, whoever runs the test."""
    path = Path("afile") / GOOD[key(command, option)]
    clean([*COMMANDS[command][0], option, str(path)], capfd, folder, option, path, "afile is a file, not a folder")


@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS + FOLDER_OPTIONS)
def test_a_name_too_long_is_refused(command, option, capfd, folder):
    path = "n" * 300 + Path(GOOD[key(command, option)]).suffix
    clean([*COMMANDS[command][0], option, path], capfd, folder, option, path, "longer than 255 bytes|too long")


@pytest.mark.parametrize(("command", "option"), FILE_OPTIONS + FOLDER_OPTIONS)
def test_a_read_only_folder_is_refused(command, option, capfd, folder, monkeypatch):
    locked = folder / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    if os.geteuid() == 0:  # root may write anyway: make the permission check answer as it does for anyone else
        access = os.access

        def no_write(path, mode, *args, **kwargs):
            if mode & os.W_OK and Path(path).resolve() == locked.resolve():
                return False
            return access(path, mode, *args, **kwargs)

        monkeypatch.setattr(os, "access", no_write)
    try:
        path = Path("locked") / GOOD[key(command, option)]
        clean([*COMMANDS[command][0], option, str(path)], capfd, folder, option, path, "not writable")
    finally:
        locked.chmod(0o755)


@pytest.mark.parametrize(("command", "option"), FOLDER_OPTIONS)
@pytest.mark.parametrize(("path", "pattern"), [("afile", "is a file, not a folder"),
                                               ("nowhere/charts", "nowhere does not exist"),
                                               ("afile/charts", "afile is a file, not a folder")])
def test_plots_wants_a_folder(command, option, path, pattern, capfd, folder):
    clean([*COMMANDS[command][0], option, path], capfd, folder, option, path, pattern)
    assert not (folder / "nowhere").exists()


@pytest.mark.parametrize(("command", "first", "second", "path"),
                         [("tolerance", "--csv", "--contributions", "out.csv"),
                          ("tolerance", "--contributions", "--csv", "contributions.csv"),
                          ("linkage", "--plot", "--plans", "out.png"), ("linkage", "--plans", "--plot", "plans.svg")])
def test_two_options_naming_one_file_are_refused(command, first, second, path, capfd, folder):
    assert_clean_error([*COMMANDS[command][0], first, path, second, path], capfd, folder, [first, second, path],
                       "both name .*; give each output its own file")


def test_an_output_over_an_input_is_refused(capfd, folder):
    shutil.copy(DATA / "tolerances_puma560.csv", folder / "tolerances.csv")
    argv = ["tolerance", "puma560", "--tolerances", "tolerances.csv"]
    for option in ("--csv", "--contributions"):
        clean([*argv, option, "tolerances.csv"], capfd, folder, option, "tolerances.csv", "is an input")
    shutil.copy(FOUR_BAR, folder / "four_bar.toml")
    clean(["excavator", "--design", "four_bar.toml", "-o", "four_bar.toml"], capfd, folder, "-o", "four_bar.toml",
          "is an input")


def test_the_srdf_is_not_written_over_the_urdf(capfd, folder):
    """``export-urdf -o x.srdf`` wrote the SRDF over the URDF: the URDF must be .urdf (or .xml)."""
    clean(["export-urdf", "puma560", "-o", "x.srdf"], capfd, folder, "-o", "x.srdf", "use .urdf")


def test_an_empty_name_is_refused(capfd, folder):
    outcome = assert_clean_error(["show", "planar_2r", "--csv", ""], capfd, folder, ["--csv", "''"])
    assert "file name" in outcome.err


# ------------------------------------------------------------------------------------------------- a failed write
@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("argv", [["show", "planar_2r", "--csv", "out.csv", "--plot"],
                                  ["fk", "planar_2r", "--q", "0,0", "--plot", "out.png", "--csv"],
                                  ["structure", FOUR_BAR, "--json", "--csv"],
                                  ["export-urdf", "planar_2r", "-o"]])
def test_a_full_disk_is_an_error_and_nothing_is_replaced(argv, capfd, folder):
    """/dev/full takes nothing (no space left): the command fails, and the other outputs are not replaced."""
    option = "-o" if argv[-1] == "-o" else argv[-1]
    clean([*argv, "/dev/full"], capfd, folder, option, "/dev/full", "No space left on device")


def test_a_device_takes_the_output(capfd, folder):
    outcome = run(["show", "planar_2r", "--csv", "/dev/null", "--plot", "out.png"], capfd, folder)
    assert outcome.code == 0 and "wrote /dev/null" in outcome.out
    assert (folder / "out.png").read_bytes()[:4] == b"\x89PNG"


def full_disk_after(monkeypatch, calls: int) -> None:
    """Every write after the first ``calls`` fails as on a full disk."""
    from mechatron.io import output

    real, count = output._render, [0]

    def render(fh, write, binary):
        count[0] += 1
        if count[0] > calls:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(fh, write, binary)

    monkeypatch.setattr(output, "_render", render)


def test_a_full_disk_midway_keeps_every_earlier_file(monkeypatch, capfd, folder):
    """size: the --plots folder's four files and the --csv table are staged, then the disk fills while the --plot
    chart is written: the error names --plot and its file; no file changed, no temporary file or new folder left."""
    full_disk_after(monkeypatch, 5)
    argv = ["size", "planar_2r", "--plots", "charts", "--csv", "out.csv", "--plot", "out.png"]
    assert_clean_error(argv, capfd, folder, ["--plot out.png"], "cannot write: No space left on device")
    assert not (folder / "charts").exists()
    monkeypatch.undo()
    full_disk_after(monkeypatch, 1)  # the second file of --plots
    assert_clean_error(argv, capfd, folder, ["--plots charts/planar_2r_q1.csv"], "No space left on device")


def test_a_failing_report_keeps_the_staged_table_and_chart_out(monkeypatch, capfd, folder):
    """linkage: --csv and --plot are staged, then the report fails: out.csv and out.png keep the earlier run's."""
    from mechatron.errors import InputError
    from mechatron.report import html

    def fail(*args, **kwargs):
        raise InputError("the report cannot be made")

    monkeypatch.setattr(html, "render", fail)
    assert_clean_error(["linkage", FOUR_BAR, "--samples", "5", "--csv", "out.csv", "--plot", "out.png", "--report",
                        "out.html"], capfd, folder, "the report cannot be made")


def test_size_with_a_file_as_plots_keeps_the_csv(capfd, folder):
    """Issue 13: ``size --csv out.csv --plots FILE`` rewrote out.csv and then failed."""
    clean(["size", "planar_2r", "--csv", "out.csv", "--plots", "afile"], capfd, folder, "--plots", "afile")


def test_a_csv_the_plots_folder_would_overwrite(capfd, folder):
    """--csv inside the --plots folder, on the name of a joint's table: found when staging, nothing written."""
    (folder / "charts").mkdir()
    (folder / "charts" / "planar_2r_q1.csv").write_text("earlier\n")
    assert_clean_error(["size", "planar_2r", "--plots", "charts", "--csv", "charts/planar_2r_q1.csv"], capfd, folder,
                       ["charts/planar_2r_q1.csv", "(--csv and --plots)"], "written twice")


# --------------------------------------------------------------------------------------------- stale companions
def test_stale_joint_charts_go_and_other_files_stay(capfd, folder):
    """size --plots: the marked chart of a joint no longer there and its table go; a chart mechatron did not mark,
    one marked for another robot, and other files stay."""
    from matplotlib.figure import Figure

    from mechatron.io.output import save_figure

    charts = folder / "charts"
    charts.mkdir()
    save_figure(Figure(), charts / "planar_2r_q9.png", owner="mechatron size planar_2r")
    (charts / "planar_2r_q9.csv").write_text("earlier\n")
    save_figure(Figure(), charts / "puma560_q1.png", owner="mechatron size puma560")
    save_figure(Figure(), charts / "planar_2r_photo.png")
    (charts / "notes.csv").write_text("mine\n")
    (charts / "planar_2r_q1.csv").write_text("earlier\n")
    outcome = run(["size", "planar_2r", "--plots", "charts"], capfd, folder)
    assert outcome.code == 0, outcome.err
    assert sorted(p.name for p in charts.iterdir()) == [
        "notes.csv", "planar_2r_photo.png", "planar_2r_q1.csv", "planar_2r_q1.png", "planar_2r_q2.csv",
        "planar_2r_q2.png", "puma560_q1.png"]
    assert (charts / "planar_2r_q1.csv").read_text() != "earlier\n"


def test_a_chart_no_longer_drawn_goes(capfd, folder):
    """tolerance --plots: the Monte Carlo chart of a run with --method all goes with --method worst."""
    argv = ["tolerance", "puma560", "--tolerances", str(DATA / "tolerances_puma560.csv"), "--samples", "50",
            "--plots", "charts"]
    assert run([*argv, "--method", "all"], capfd, folder).code == 0
    assert sorted(p.name for p in (folder / "charts").iterdir()) == ["puma560_contributions.png",
                                                                      "puma560_monte_carlo.png"]
    assert run([*argv, "--method", "worst"], capfd, folder).code == 0
    assert sorted(p.name for p in (folder / "charts").iterdir()) == ["puma560_contributions.png"]


def test_a_stale_srdf_goes_and_a_foreign_one_stays(capfd, folder):
    outcome = run(["export-urdf", "puma560", "-o", "arm.urdf"], capfd, folder)
    assert outcome.code == 0 and (folder / "arm.srdf").is_file()
    outcome = run(["export-urdf", "planar_2r", "-o", "arm.urdf"], capfd, folder)  # no drives: no SRDF
    assert outcome.code == 0 and not (folder / "arm.srdf").exists()
    assert "planar_2r" in (folder / "arm.urdf").read_text()
    (folder / "arm.srdf").write_text("<robot name='mine'><group name='arm'/></robot>\n")  # e.g. MoveIt's
    assert run(["export-urdf", "planar_2r", "-o", "arm.urdf"], capfd, folder).code == 0
    assert (folder / "arm.srdf").read_text().startswith("<robot name='mine'>")


def test_a_stale_failures_table_goes(capfd, folder):
    """linkage --csv X.csv: the X.failures.csv of earlier versions (last column ``reason``) goes; another stays."""
    (folder / "out.failures.csv").write_text("sample,q1,reason\n3,0.5,the loops do not close\n")
    (folder / "mine.failures.csv").write_text("sample,comment\n")
    (folder / "mine.csv").write_text("earlier\n")
    before = snapshot(folder)
    for name in ("out.csv", "mine.csv"):
        assert run(["linkage", FOUR_BAR, "--samples", "5", "--csv", name], capfd, folder).code == 0
    assert not (folder / "out.failures.csv").exists()
    assert snapshot(folder)["mine.failures.csv"] == before["mine.failures.csv"]


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_a_failed_run_shows_its_error_alone(capfd, folder):
    """q6 = 9 rad is outside its limits (a warning when the run succeeds); the run fails at its full disk: the error
    is the one line on stderr."""
    clean(["fk", "puma560", "--q", "0,0,0,0,0,9", "--plot", "/dev/full"], capfd, folder, "--plot", "/dev/full",
          "No space left")
    outcome = run(["fk", "puma560", "--q", "0,0,0,0,0,9"], capfd, folder)
    assert outcome.code == 0 and outcome.err.strip() == "mechatron: warning: q6 = 9 outside [-4.64258, 4.64258]"

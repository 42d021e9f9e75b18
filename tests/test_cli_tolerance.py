"""The tolerance command: the public JSON contract, the given-errors check of the example of [Egorov, fig. 8.3],
outputs and bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mechatron.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def crank_files(tmp_path):
    tolerances = tmp_path / "tolerances.csv"
    tolerances.write_text("parameter,tolerance,error\nl1,1e-3,1e-3\nl2,1.5e-3,1.5e-3\nq1,1e-3,1e-3\n")
    poses = tmp_path / "poses.csv"
    poses.write_text(f"q1\n{math.pi / 3!r}\n0.5\n2.0\n")
    return tolerances, poses


def test_given_errors_reproduce_the_textbook_example(capsys, crank_files):
    tolerances, poses = crank_files
    code, out, _ = run(capsys, "tolerance", "crank_slider", "--set", "l1=0.2,l2=0.346", "--tolerances",
                       str(tolerances), "--poses", str(poses), "--method", "given", "--json")
    assert code == 0
    result = json.loads(out)
    assert result["methods"] == ["given"] and result["frame"] == "C" and len(result["poses"]) == 3
    first = result["poses"][0]
    assert first["dx"] == pytest.approx(1.500914e-3, rel=1e-6)  # +1.5 mm, see tests/test_accuracy.py
    assert first["dy"] == pytest.approx(0, abs=1e-15) and first["dz"] == pytest.approx(0, abs=1e-15)
    assert first["dr"] == pytest.approx(abs(first["dx"]))
    assert first["coordinates"]["q1"] == pytest.approx(math.pi / 3)


@pytest.mark.parametrize("method", ["worst", "rss", "mc", "all"])
def test_every_method_prints_the_contract(capsys, crank_files, method):
    tolerances, poses = crank_files
    code, out, _ = run(capsys, "tolerance", "crank_slider", "--set", "l1=0.2,l2=0.346", "--tolerances",
                       str(tolerances), "--poses", str(poses), "--method", method, "--samples", "2000", "--json")
    assert code == 0
    for record in json.loads(out)["poses"]:
        assert {"dx", "dy", "dz", "dr"} <= set(record)
        assert record["dr"] == pytest.approx(math.sqrt(record["dx"] ** 2 + record["dy"] ** 2 + record["dz"] ** 2)) \
            or method in ("mc", "all") and record["dr"] > 0
    if method == "all":
        first = json.loads(out)["poses"][0]["methods"]
        assert set(first) == {"worst", "rss", "mc"} and first["worst"]["dr"] >= first["rss"]["dr"]


def test_text_outputs_and_plots(capsys, tmp_path, crank_files):
    tolerances, poses = crank_files
    code, out, _ = run(capsys, "tolerance", "crank_slider", "--tolerances", str(tolerances), "--grid", "40",
                       "--samples", "3000", "--limit-mm", "2", "--csv", str(tmp_path / "poses_out.csv"),
                       "--contributions", str(tmp_path / "c.csv"), "--plots", str(tmp_path / "charts"))
    assert code == 0 and "contributions at the critical pose" in out
    assert sorted(p.name for p in (tmp_path / "charts").iterdir()) == [
        "crank_slider_contributions.png", "crank_slider_error_map.png", "crank_slider_monte_carlo.png"]
    table = (tmp_path / "poses_out.csv").read_text().splitlines()
    assert len(table) == 41 and "yield_mc" in table[0]
    assert (tmp_path / "c.csv").read_text().startswith("source,kind,unit,tolerance")


def test_serial_arm_reference_pose_and_grades(capsys, tmp_path):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,tolerance_mm,tolerance_arcsec,grade,size_mm\na2,0.02,,,\nd4,,,IT7,\n"
                          "alpha2,,,AT7,400\nq2,,20,,\n")
    code, out, _ = run(capsys, "tolerance", "puma560", "--tolerances", str(tolerances), "--method", "worst",
                       "--json")
    assert code == 0
    (record,) = json.loads(out)["poses"]
    assert record["label"] == "reference" and 0 < record["dr"] < 1e-3


@pytest.mark.parametrize("text, message", [
    ("parameter,tolerance\nl9,1e-3\n", "row 2: field 'parameter': unknown parameter or coordinate"),
    ("parameter,tolerance\nl1,-1e-3\n", "row 2: field 'tolerance': a tolerance must be >= 0"),
    ("parameter,grade\nl1,IT99\n", "row 2: field 'grade': unknown grade"),
    ("parameter,grade,size_mm\nl1,IT7,5000\n", "row 2: field 'grade': size 5000 mm is outside the IT table"),
    ("", "not a readable CSV"),
])
def test_bad_input_exits_2_naming_file_row_and_column(capsys, tmp_path, text, message):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text(text)
    code, out, err = run(capsys, "tolerance", "crank_slider", "--tolerances", str(tolerances), "--json")
    assert code == 2 and out == "" and "Traceback" not in err
    assert "t.csv" in err and message in err


def test_given_needs_the_error_column(capsys, tmp_path):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,tolerance\nl1,1e-3\n")
    code, _, err = run(capsys, "tolerance", "crank_slider", "--tolerances", str(tolerances), "--method", "given")
    assert code == 2 and "missing column 'error'" in err


def test_unreachable_pose_is_a_clear_error(capsys, tmp_path):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,tolerance\nL1,1e-3\n")
    poses = tmp_path / "p.csv"
    poses.write_text("L1\n1.5\n9.0\n")
    code, _, err = run(capsys, "tolerance", "six_bar_bucket", "--tolerances", str(tolerances), "--poses",
                       str(poses))
    assert code == 2 and "pose 2" in err and np.isfinite(1.0)


@pytest.mark.parametrize("method", ["worst", "rss", "mc", "all"])
def test_a_closed_loop_with_only_an_input_row(capsys, tmp_path, method):
    """A tolerances file with only the input's row (no parameter) on a closed loop: the crank-slider's slider
    C at x_C = l1 cos φ + √(l2² − l1² sin² φ) moves by ∂x_C/∂φ t with ∂x_C/∂φ = −l1 sin φ − l1² sin φ cos φ /
    √(l2² − l1² sin² φ) (l1 = 0.1, l2 = 0.4 m): its worst case for ±t, and for one normal error (the default, σ = t/3)
    the RSS k σ |∂x_C/∂φ| with k = 3, the same number, which the Monte Carlo's k·σ of the sampled Δx estimates."""
    tolerances = tmp_path / "tolerances.csv"
    tolerances.write_text("parameter,tolerance_arcmin\nq1,5\n")
    poses = tmp_path / "poses.csv"
    poses.write_text("q1\n0.3\n1.0\n2.5\n")
    code, out, err = run(capsys, "tolerance", "crank_slider", "--tolerances", str(tolerances), "--poses", str(poses),
                         "--method", method, "--json")
    assert code == 0, err
    t, l1, l2 = math.radians(5 / 60), 0.1, 0.4
    for pose, phi in zip(json.loads(out)["poses"], (0.3, 1.0, 2.5)):
        root = math.sqrt(l2**2 - (l1 * math.sin(phi)) ** 2)
        worst = abs(-l1 * math.sin(phi) - l1**2 * math.sin(phi) * math.cos(phi) / root) * t
        if method in ("worst", "all"):
            assert pose["methods"]["worst"]["dx"] == pytest.approx(worst, rel=1e-9)
            assert pose["methods"]["worst"]["dy"] == pytest.approx(0.0, abs=1e-15)
        if method in ("rss", "all"):
            assert pose["methods"]["rss"]["dx"] == pytest.approx(worst, rel=1e-9)
        if method in ("mc", "all"):
            assert pose["methods"]["mc"]["dx"] == pytest.approx(worst, rel=0.05)


def test_a_cylinder_row_alone(capsys, tmp_path):
    """Only the cylinder's row: the scissor lift's deck moves by ∂h/∂c t with ∂h/∂c = 1.839298 at the drawing (the
    closed form of tests/test_scissor_lift.py), and not sideways (∂x/∂c = 0)."""
    tolerances = tmp_path / "tolerances.csv"
    tolerances.write_text("parameter,tolerance_mm\ncyl,0.5\n")
    lift = Path(__file__).resolve().parent.parent / "examples" / "data" / "scissor_lift.toml"
    code, out, err = run(capsys, "tolerance", str(lift), "--tolerances", str(tolerances),
                         "--method", "worst", "--json")
    assert code == 0, err
    worst = json.loads(out)["poses"][0]["methods"]["worst"]
    assert worst["dy"] == pytest.approx(1.839298 * 0.5e-3, rel=1e-6) and worst["dx"] < 1e-15

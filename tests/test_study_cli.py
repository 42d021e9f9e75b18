"""``mechatron study``: its outputs, and bad study files and options as one line with exit status 2."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from tests.corpus import assert_clean_error, run

GOOD = """mechanism = "crank_slider"
[parameters.l1]
low = 0.08
high = 0.12
[designs]
method = "grid"
levels = 2
[analyses.linkage]
samples = 13
"""


def write(folder, text=GOOD, name="s.toml"):
    (folder / name).write_text(text)
    return name


def test_study_command_outputs(tmp_path, capfd):
    write(tmp_path)
    outcome = run(["study", "s.toml", "--out", "out", "--json", "--csv", "t.csv", "--plot", "p.png"], capfd,
                  tmp_path)
    assert outcome.code == 0, outcome.err
    data = json.loads(outcome.out)
    assert data["designs"] == 2 and data["ok"] == 2
    # x travel 2 l1 of l1 = 0.08 and 0.12 m
    assert [row["x_travel_m"] for row in data["rows"]] == pytest.approx([0.16, 0.24], abs=1e-9)
    table = pd.read_csv(tmp_path / "t.csv")
    assert table["design"].tolist() == [0, 1] and (tmp_path / "p.png").stat().st_size > 0
    assert pd.read_csv(tmp_path / "out" / "designs.csv")["x_travel_m"].tolist() == pytest.approx([0.16, 0.24])
    again = run(["study", "s.toml", "--out", "out"], capfd, tmp_path)  # every part there: the same table
    assert again.code == 0 and "2 designs" in again.out and "2 ok" in again.out


@pytest.mark.parametrize("change, names", [
    (("[parameters.l1]", "[parameters.l9]"), ["s.toml", "parameters.l9", "unknown parameter 'l9'", "l1, l2"]),
    (("high = 0.12", "high = 0.08"), ["s.toml", "parameters.l1.low", "empty range"]),
    (("high = 0.12", 'high = "abc"'), ["s.toml", "parameters.l1.high", "expected a number"]),
    (("[analyses.linkage]", "[analyses.kinematics]"), ["s.toml", "analyses.kinematics", "unknown analysis"]),
    (('"crank_slider"\n[parameters.l1]', '"puma560"\n[parameters.a2]'), ["s.toml", "analyses.linkage",
                                                                     "no closed loops"]),
    (("samples = 13", "samples = 1"), ["s.toml", "analyses.linkage.samples"]),
    (('method = "grid"', 'method = "sobol"\nsamples = 6'), ["s.toml", "designs.samples", "power of 2"]),
    (('method = "grid"', 'method = "random"'), ["s.toml", "designs.method"]),
    (("levels = 2", "levels = 2\nseed = -1"), ["s.toml", "designs.seed"]),
    (('"crank_slider"', '"no_such_mechanism"'), ["no_such_mechanism"]),
    (("levels = 2", "levels = 20000000"), ["s.toml", "designs.levels", "20,000,000 designs", "at most 10,000,000"]),
    (('method = "grid"', 'method = "sobol"\nsamples = 4194304'), ["s.toml", "designs.samples", "12,582,912"]),
])
def test_bad_study_files(tmp_path, capfd, change, names):
    write(tmp_path, GOOD.replace(*change))
    assert_clean_error(["study", "s.toml"], capfd, tmp_path, names)


def test_sensitivity_needs_sobol_designs(tmp_path, capfd):
    write(tmp_path, GOOD + "[output]\nsensitivity = true\n")
    assert_clean_error(["study", "s.toml"], capfd, tmp_path, ["output.sensitivity", "sobol"])


def test_unreachable_scheduler(tmp_path, capfd):
    write(tmp_path)
    assert_clean_error(["study", "s.toml", "--scheduler", "tcp://127.0.0.1:9"], capfd, tmp_path,
                       ["--scheduler", "tcp://127.0.0.1:9", "cannot reach"])


def test_another_spec_in_the_same_folder(tmp_path, capfd):
    write(tmp_path)
    assert run(["study", "s.toml", "--out", "out"], capfd, tmp_path).code == 0
    write(tmp_path, GOOD.replace("levels = 2", "levels = 3"))
    assert_clean_error(["study", "s.toml", "--out", "out"], capfd, tmp_path, ["out", "another spec"])
    assert_clean_error(["study", "s.toml", "--out", "s.toml"], capfd, tmp_path, ["--out", "s.toml"])
    assert_clean_error(["study", "s.toml", "--workers", "0"], capfd, tmp_path, ["--workers"])
    assert_clean_error(["study", "missing.toml"], capfd, tmp_path, ["missing.toml"])

"""StudyResult follows the result protocol, and the tolerance command's --json, --csv and --plot are the result's
as_dict, to_frame and plot."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from protocol import check_result

import mechatron
from mechatron.accuracy.sources import ErrorSource, read_poses, read_tolerances
from mechatron.accuracy.study import analyse_tolerances as run_study
from mechatron.cli import main


def crank_sources():
    return [ErrorSource("l1", "parameter", "m", 1e-3, error=1e-3), ErrorSource("l2", "parameter", "m", 1.5e-3,
                                                                                "uniform", error=1.5e-3),
            ErrorSource("q1", "coordinate", "rad", 1e-3, "triangular", error=1e-3)]


@pytest.mark.parametrize("methods, poses", [(("worst", "rss", "mc"), [[0.5], [1.0], [2.0]]),
                                            (("given",), [[math.pi / 3]])])
def test_study_result_follows_the_protocol(methods, poses):
    mech = mechatron.load("crank_slider", l1=0.2, l2=0.346)
    result = run_study(mech, crank_sources(), poses, frame="C", methods=methods, samples=2000, limit=2e-3)
    data = check_result(result)
    assert set(data) == {"mechanism", "frame", "methods", "k", "limit", "critical_pose", "poses", "contributions",
                         "notes"}
    assert (data["mechanism"], data["frame"], data["methods"], data["limit"]) == ("crank_slider", "C",
                                                                                  list(methods), 2e-3)
    table = result.to_frame()
    assert len(data["poses"]) == len(table) == len(poses)
    main = methods[0]
    for record, row in zip(data["poses"], table.to_dict(orient="records")):
        assert record["label"] == row["label"] and record["coordinates"] == {"q1": row["q1"]}
        assert [record[a] for a in ("x", "y", "z", "dx", "dy", "dz", "dr")] == \
            [row[c] for c in ("x", "y", "z", f"dx_{main}", f"dy_{main}", f"dz_{main}", f"dr_{main}")]
        assert set(record["methods"]) == set(methods)
        assert record["methods"][main]["dr"] == row[f"dr_{main}"]
    assert data["critical_pose"] == table["label"].iloc[int(np.argmax(table[f"dr_{main}"]))]
    assert [c["source"] for c in data["contributions"]] == list(result.contributions["source"])
    assert "positioning error of C" in str(result) and "contributions at the critical pose" in str(result)


def test_study_plot_panels_and_charts():
    mech = mechatron.load("crank_slider")
    result = run_study(mech, crank_sources(), [[0.5], [1.0], [2.0]], frame="C", methods=["rss", "mc"], samples=500)
    figure = result.plot()
    titles = [ax.get_title() for ax in figure.axes]
    assert len(titles) == 3 and "Monte Carlo" in titles[1] and "contributions" in titles[2]
    charts = result.charts()
    assert list(charts) == ["error_map", "monte_carlo", "contributions"]
    # the error map's classes hold every pose, the critical one starred
    ax = charts["error_map"].axes[0]
    points = sum(len(c.get_offsets()) for c in ax.collections)
    assert points == 3 and ax.get_lines()[0].get_xdata()[0] == result.poses["x"].iloc[result.critical]
    single = run_study(mech, crank_sources(), [[1.0]], frame="C", methods=["worst"])
    assert list(single.charts()) == ["contributions"]  # one pose: no map; no Monte Carlo: no histogram


@pytest.fixture
def crank_files(tmp_path):
    tolerances = tmp_path / "tolerances.csv"
    tolerances.write_text("parameter,tolerance_mm,tolerance_deg,distribution\nl1,1,,normal\nl2,1.5,,uniform\n"
                          "q1,,0.0573,triangular\n")
    poses = tmp_path / "poses.csv"
    poses.write_text("label,q1_deg\nA,30\nB,60\nC,120\n")
    return tolerances, poses


def test_cli_json_csv_and_plot_are_the_results(capsys, tmp_path, crank_files):
    tolerances, poses = crank_files
    argv = ["tolerance", "crank_slider", "--tolerances", str(tolerances), "--poses", str(poses), "--samples", "1500",
            "--seed", "5", "--limit-mm", "1.5", "--frame", "C"]
    code = main([*argv, "--json", "--csv", str(tmp_path / "cli.csv"), "--plot", str(tmp_path / "cli.png")])
    out, err = capsys.readouterr()
    assert code == 0
    mech = mechatron.load("crank_slider")
    result = run_study(mech, read_tolerances(tolerances, mech), *read_poses(poses, mech), frame="C",
                       methods=["worst", "rss", "mc"], samples=1500, seed=5, limit=1.5e-3)
    assert json.loads(out) == json.loads(result.to_json())
    assert "wrote" in err  # the files are listed on stderr, stdout stays one JSON document
    pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "cli.csv"), pd.read_csv(result.write_csv(tmp_path / "a.csv")))
    assert (tmp_path / "cli.png").read_bytes() == result.save_plot(tmp_path / "a.png").read_bytes()
    code = main(argv)
    out, _ = capsys.readouterr()
    assert code == 0 and out == str(result) + "\n"

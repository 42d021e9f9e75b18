"""Design studies (mechatron/studies): the spec, the designs, serial and Dask runs, resuming, failed designs, the
result and the Sobol indices against closed forms."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from pandas.testing import assert_frame_equal

from mechatron.errors import InputError
from mechatron.io.budget import available_cores
from mechatron.studies.designs import make_designs
from mechatron.studies.result import pareto_mask
from mechatron.studies.runner import evaluate, run_study
from mechatron.studies.spec import read_study as read_spec
from tests.protocol import check_result

CRANK = """
mechanism = "crank_slider"
[parameters.l1]
{l1}
[parameters.l2]
low_mm = 350
high_mm = 450
[designs]
{designs}
[analyses.linkage]
samples = 13
"""


def spec_file(folder: Path, l1: str = "low = 0.08\nhigh = 0.12", designs: str = 'method = "grid"\nlevels = 3',
              name: str = "study.toml", extra: str = "") -> Path:
    path = folder / name
    path.write_text(CRANK.format(l1=l1, designs=designs) + extra)
    return path


def test_grid_designs_and_seeds(tmp_path):
    # 2 values × 3 levels, the last parameter fastest; seeds from SeedSequence([study seed, design])
    spec = read_spec(spec_file(tmp_path, "values_mm = [90, 110]", 'method = "grid"\nlevels = 3\nseed = 7'))
    table = make_designs(spec)
    assert list(table.columns) == ["design", "l1", "l2", "seed"]
    assert table["design"].tolist() == list(range(6))
    assert table["l1"].tolist() == pytest.approx([0.09] * 3 + [0.11] * 3)
    assert table["l2"].tolist() == pytest.approx([0.35, 0.40, 0.45] * 2)
    expected = [int(np.random.SeedSequence([7, k]).generate_state(1, np.uint32)[0]) for k in range(6)]
    assert table["seed"].tolist() == expected


def test_latin_hypercube(tmp_path):
    # one point in each of the n equal strata of every parameter's range; the same seed, the same designs
    spec = read_spec(spec_file(tmp_path, designs='method = "lhs"\nsamples = 20\nseed = 3'))
    table = make_designs(spec)
    for name, low, high in (("l1", 0.08, 0.12), ("l2", 0.35, 0.45)):
        strata = np.floor((table[name] - low) / (high - low) * 20).astype(int)
        assert sorted(strata) == list(range(20))
    assert_frame_equal(table, make_designs(read_spec(spec_file(tmp_path, designs='method = "lhs"\nsamples = 20\n'
                                                                                 'seed = 3'))))
    other = make_designs(read_spec(spec_file(tmp_path, designs='method = "lhs"\nsamples = 20\nseed = 4')))
    assert not np.allclose(other["l1"], table["l1"])


@pytest.mark.parametrize("n, d, seed", [(1, 1, 0), (20, 2, 3), (7, 5, 0), (1000, 3, 12345)])
def test_latin_hypercube_is_scipys(n, d, seed):
    # the NumPy Latin hypercube draws SciPy's points to the last bit (a study of the same seed, the same designs),
    # without importing scipy.stats
    from scipy.stats import qmc

    from mechatron.studies.designs import latin_hypercube

    expected = qmc.LatinHypercube(d=d, scramble=True, rng=np.random.default_rng(seed)).random(n)
    assert np.array_equal(latin_hypercube(n, d, seed), expected)


def test_saltelli_layout(tmp_path):
    # N (D + 2) designs; in each block A, A_B^(1), A_B^(2), B: A_B^(i) is A with column i of B
    spec = read_spec(spec_file(tmp_path, designs='method = "sobol"\nsamples = 8'))
    x = make_designs(spec)[["l1", "l2"]].to_numpy()
    assert x.shape == (8 * 4, 2)
    for block in x.reshape(8, 4, 2):
        a, ab1, ab2, b = block
        assert ab1.tolist() == [b[0], a[1]] and ab2.tolist() == [a[0], b[1]]


def test_csv_designs(tmp_path):
    (tmp_path / "designs.csv").write_text("l1,l2\n0.1,0.4\n# a comment\n0.12,0.38\n")
    path = tmp_path / "study.toml"
    path.write_text('mechanism = "crank_slider"\n[designs]\nmethod = "csv"\nfile = "designs.csv"\n'
                    '[analyses.linkage]\nsamples = 13\n')
    table = make_designs(read_spec(path))
    assert table[["l1", "l2"]].to_numpy().tolist() == [[0.1, 0.4], [0.12, 0.38]]
    (tmp_path / "designs.csv").write_text("l1,l2\n0.1,0.4\n\n0.12,abc\n")
    with pytest.raises(InputError, match=r"designs.csv: row 4: field 'l2': not a number"):
        read_spec(path)


def test_failed_design_is_a_row_with_its_reason(tmp_path):
    # l1 = 0.3 > l2 = 0.28: the crank cannot pass q1 = 90°; l1 = 0.3, l2 = 0.2: not even the drawing closes
    spec = read_spec(spec_file(tmp_path, "values = [0.1, 0.3]", 'method = "grid"', extra=""))
    spec_l2 = read_spec(spec_file(tmp_path, "values = [0.1, 0.3]", 'method = "grid"'))
    designs = pd.DataFrame({"design": [0, 1, 2], "l1": [0.1, 0.3, 0.3], "l2": [0.4, 0.28, 0.2], "seed": [1, 2, 3]})
    rows = evaluate(spec_l2, designs)
    assert rows["status"].tolist() == ["ok", "failed", "failed"]
    assert rows["reason"].iloc[0] == ""
    assert "cannot be assembled" in rows["reason"].iloc[1]
    assert "cannot be closed" in rows["reason"].iloc[2]
    assert rows["x_travel_m"].iloc[0] == pytest.approx(0.2, abs=1e-9)
    assert spec == spec_l2


def run(spec_path: Path, out: Path, **options) -> pd.DataFrame:
    result = run_study(spec_path, out, **options)
    return result.to_frame()


def test_serial_and_local_cluster_give_the_same_table(tmp_path):
    spec = spec_file(tmp_path, "values = [0.1, 0.4]", 'method = "grid"\nlevels = 4')  # l1 = 0.4 > l2: 2 fail
    serial = run(spec, tmp_path / "serial", chunk_size=3)
    dask = run(spec, tmp_path / "dask", workers=min(2, available_cores()), chunk_size=3)  # 2 where there are 2
    assert_frame_equal(serial, dask)
    assert len(serial) == 8 and set(serial["status"]) == {"ok", "failed"}
    assert_frame_equal(pd.read_parquet(tmp_path / "dask" / "designs.parquet"), serial)
    assert len(list((tmp_path / "dask" / "parts").glob("part-*.parquet"))) == 3


@pytest.mark.parametrize("l1", [[0.1, 0.12], [0.1, 0.3], [0.3, 0.3]], ids=["ok", "mixed", "failed"])
def test_the_rows_kept_are_those_of_the_part_file(tmp_path, l1):
    # the study keeps each chunk's rows as written instead of reading its part file back: the same frame, dtypes
    # included (a boolean output with a failed row, a chunk without outputs, a column of names)
    from mechatron.studies.runner import _read_part, _write_part

    spec = read_spec(spec_file(tmp_path, "values = [0.1, 0.3]", 'method = "grid"'))
    designs = pd.DataFrame({"design": [0, 1], "l1": l1, "l2": [0.28, 0.28], "seed": [1, 2], "tag": ["a", "b"]})
    path = tmp_path / "part.parquet"
    kept = _write_part(evaluate(spec, designs), {"study": "s", "designs": [0, 1], "values": ""}, path)
    assert_frame_equal(kept, _read_part(path))
    # a sizing's rows: ``feasible`` true, false or missing (a failed design), an output missing
    rows = pd.DataFrame([{"design": 0, "status": "ok", "reason": "", "feasible": True, "drive_mass_kg": 1.5},
                         {"design": 1, "status": "ok", "reason": "", "feasible": False, "drive_mass_kg": 2.0},
                         {"design": 2, "status": "failed", "reason": "no drive"}])
    kept = _write_part(rows, {"study": "s", "designs": [0, 1, 2], "values": ""}, path)
    assert_frame_equal(kept, _read_part(path))


def test_default_chunk_gives_each_worker_about_16_chunks():
    # n/32 serially and on 2 workers (part files to resume from), n/(16 w) on more, 1 to 64 designs
    from mechatron.studies.runner import default_chunk

    assert [default_chunk(320, w) for w in (1, 2, 4, 8, 16)] == [10, 10, 5, 3, 2]
    assert default_chunk(1000, 16) == 4 and default_chunk(10, 1) == 1 and default_chunk(10**6, 2) == 64


def test_a_stopped_study_resumes_to_the_same_table(tmp_path):
    spec = spec_file(tmp_path, designs='method = "lhs"\nsamples = 10')
    whole = run(spec, tmp_path / "whole", chunk_size=2)
    seen = []
    assert run_study(spec, tmp_path / "half", chunk_size=2, max_chunks=2,
                     progress=lambda done, total: seen.append((done, total))) is None
    assert seen == [(0, 10), (2, 10), (4, 10)]
    assert len(list((tmp_path / "half" / "parts").glob("*.parquet"))) == 2
    seen.clear()
    resumed = run(spec, tmp_path / "half", progress=lambda done, total: seen.append((done, total)))
    assert seen[0] == (4, 10) and seen[-1] == (10, 10)
    assert_frame_equal(whole, resumed)


def test_a_killed_study_resumes_to_the_same_table(tmp_path):
    # a real interruption: the command line in a subprocess, killed once its first part files are on disk
    spec = spec_file(tmp_path, designs='method = "lhs"\nsamples = 60')
    out = tmp_path / "killed"
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    process = subprocess.Popen([sys.executable, "-m", "mechatron", "study", str(spec), "--out", str(out),
                                "--chunk", "2"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while time.time() < deadline and len(list((out / "parts").glob("part-*.parquet"))) < 2:
        time.sleep(0.02)
    process.send_signal(signal.SIGKILL)
    process.wait()
    parts = len(list((out / "parts").glob("part-*.parquet")))
    assert 2 <= parts < 30 and not (out / "designs.parquet").exists()
    resumed = run(spec, out)
    assert_frame_equal(run(spec, tmp_path / "whole", chunk_size=2), resumed)


def test_sobol_indices_of_the_crank_slider(tmp_path):
    # x travel = 2 l1 depends on l1 alone: S1(l1) = ST(l1) = 1, S1(l2) = ST(l2) = 0.
    # reach = l1 + l2, additive in independent uniforms: S1_i = ST_i = Var_i / (Var_1 + Var_2), Var = w²/12:
    # widths 0.04 and 0.1 m → S1(l1) = 0.0016/0.0116 = 0.1379, S1(l2) = 0.8621.
    # 128 blocks estimate them to within 5 % of each index (a 10 % bias fails); and the indices of the linkage
    # analysis's outputs are SALib's of the closed-form outputs 2 l1 and l1 + l2 of the same designs.
    from SALib.analyze import sobol

    spec = spec_file(tmp_path, designs='method = "sobol"\nsamples = 128\nseed = 1',
                     extra="[output]\nsensitivity = true\n")
    result = run_study(spec, tmp_path / "out")
    s = result.sensitivity.set_index(["output", "parameter"])
    for key, expected in {("x_travel_m", "l1"): 1.0, ("x_travel_m", "l2"): 0.0, ("reach_m", "l1"): 0.0016 / 0.0116,
                          ("reach_m", "l2"): 0.01 / 0.0116}.items():
        row = s.loc[key]
        assert abs(row["S1"] - expected) <= 0.05 * expected + 1e-9, (key, row.to_dict())
        assert abs(row["ST"] - expected) <= 0.05 * expected + 1e-9, (key, row.to_dict())
    designs = result.table.sort_values("design")
    problem = {"num_vars": 2, "names": ["l1", "l2"], "bounds": [[0.0, 1.0]] * 2}
    for output, closed in (("x_travel_m", 2 * designs["l1"]), ("reach_m", designs["l1"] + designs["l2"])):
        expected = sobol.analyze(problem, closed.to_numpy(), calc_second_order=False,
                                 seed=np.random.SeedSequence(1))
        for j, name in enumerate(("l1", "l2")):
            for kind in ("S1", "S1_conf", "ST", "ST_conf"):
                assert s.loc[(output, name), kind] == pytest.approx(expected[kind][j], rel=1e-9, abs=1e-12)
    assert s.loc[("x_travel_m", "l2"), "S1"] == pytest.approx(0.0, abs=1e-9)  # l2 leaves the travel unchanged
    assert set(result.skipped) == {"height_m", "depth_m", "y_travel_m"}  # y = 0 on every design
    text = str(result)
    assert "x_travel_m: l1" in text and "512 designs" in text


def test_pareto_front():
    # (1, 5) (2, 3) (3, 4) (4, 1) (2, 3): (3, 4) is dominated by (2, 3); the repeated (2, 3) stays
    x = np.array([1.0, 2.0, 3.0, 4.0, 2.0])
    y = np.array([5.0, 3.0, 4.0, 1.0, 3.0])
    assert pareto_mask(x, y).tolist() == [True, True, False, True, True]


@pytest.mark.parametrize("x, y, front", [
    # the largest magnitude of each output is 2: one step of the rounding is 2e-10 (docs/study_file.md)
    ([1.0, 1.0 + 3e-11, 2.0], [2.0, 2.0, 1.0], [True, True, True]),    # 3e-11 apart in x: a tie, both stay
    ([1.0, 1.0 + 6e-10, 2.0], [2.0, 2.0, 1.0], [True, False, True]),   # 6e-10 (3 steps): dominated by (1, 2)
    ([1.0, 1.0, 2.0], [2.0, 2.0 - 3e-11, 1.0], [True, True, True]),    # 3e-11 apart in y: a tie
    ([1.0, 1.0, 2.0], [2.0, 2.0 - 6e-10, 1.0], [False, True, True]),   # 6e-10: (1, 2) dominated
    # 2e-11 apart but either side of the half step 1 + 1e-10: rounded to 1 and 1 + 2e-10, not a tie
    ([1.0 + 0.9e-10, 1.0 + 1.1e-10, 2.0], [2.0, 2.0, 1.0], [True, False, True]),
])
def test_pareto_ties_are_outputs_equal_after_rounding_to_the_resolution(x, y, front):
    from mechatron.studies.result import PARETO_RESOLUTION

    assert PARETO_RESOLUTION == 1e-10
    assert pareto_mask(np.array(x), np.array(y)).tolist() == front


def test_result_protocol_and_pareto_goals(tmp_path):
    spec = spec_file(tmp_path, extra='[output.pareto]\nx = "x_travel_m"\nx_goal = "maximize"\ny = "reach_m"\n')
    result = run_study(spec, tmp_path / "out")
    data = check_result(result)
    assert data["designs"] == 9 and data["ok"] == 9 and data["sensitivity"] is None
    # the largest travel 2·0.12 with the shortest reach 0.12 + 0.35, down to the shortest travel with the
    # shortest reach: the three designs with l2 = 0.35 m
    front = result.pareto()
    assert front["l2"].tolist() == pytest.approx([0.35] * 3)
    assert front["l1"].tolist() == pytest.approx([0.08, 0.10, 0.12])
    assert math.isclose(result.plot().axes[0].get_xlabel().count("(m)"), 1)


def test_values_sent_to_an_analysis_option(tmp_path):
    # target = "dynamics.amax": the planar 2R's joint 1 turns 1 rad (joint 2 held at 0) with amax 2 or 5 rad/s²;
    # the peak torque of joint 1 is M11·amax with M11 = 0.92303545 kg·m² (tests/test_study_outputs.py), and the
    # profile's name, a categorical value, reaches the analysis too (quintic: a smaller peak than trapezoidal).
    path = tmp_path / "arm.toml"
    path.write_text('mechanism = "planar_2r"\n'
                    '[parameters.amax]\ntarget = "dynamics.amax"\nvalues = [2.0, 5.0]\n'
                    '[parameters.profile]\ntarget = "dynamics.profile"\nvalues = ["trapezoidal", "quintic"]\n'
                    '[designs]\nmethod = "grid"\n'
                    '[analyses.dynamics]\nstart = [0.0, 0.0]\nend = [1.0, 0.0]\nvmax = 1.0\ndt = 0.0005\n')
    table = run(path, tmp_path / "out")
    assert table["profile"].tolist() == ["trapezoidal", "quintic"] * 2
    peak = table.filter(like="_peak_Nm").iloc[:, 0].to_numpy()
    assert peak[[0, 2]] == pytest.approx([0.92303545 * 2, 0.92303545 * 5], rel=1e-5)
    assert peak[1] < peak[0] and peak[3] < peak[2]
    bad = path.read_text().replace('"dynamics.profile"', '"sizing.profile"')
    path.write_text(bad)
    with pytest.raises(InputError, match=r"field 'parameters.profile.target'"):
        read_spec(path)


def test_a_running_scheduler(tmp_path):
    # a scheduler started elsewhere (here: in this process, one worker thread) gets the chunks: the same table
    from distributed import LocalCluster

    spec = spec_file(tmp_path)
    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster:
        remote = run(spec, tmp_path / "remote", scheduler=cluster.scheduler_address, chunk_size=4)
    assert_frame_equal(run(spec, tmp_path / "serial", chunk_size=4), remote)


def test_a_study_whose_designs_all_fail(tmp_path):
    # l1 = 0.5 m > l2: no design assembles; the study ends with every row failed and its reason
    result = run_study(spec_file(tmp_path, "values = [0.5]", 'method = "grid"\nlevels = 2'), tmp_path / "out")
    table = result.to_frame()
    assert table["status"].tolist() == ["failed", "failed"] and table["reason"].str.len().min() > 0
    data = result.as_dict()
    assert data["ok"] == 0 and data["failed"] == 2 and data["pareto"]["designs"] == []
    assert "0 ok, 2 failed" in str(result)

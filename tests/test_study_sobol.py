"""Sobol indices of a study (issue 22, item 6): reported with their 95 % intervals, a plain warning where an
interval is wider than its index or an output varies only by numerical noise, and failed designs removing only
their Saltelli blocks. Closed forms: the crank-slider's travel 2·l1 (S₁(l1) = S_T(l1) = 1, S₁(l2) = S_T(l2) = 0
exactly: f(A_B^(l2)) = f(A) on every block) and its reach l1 + l2 (additive: S₁ = S_T = w_i² / Σ w², widths 0.04
and 0.1 m → 0.0016 / 0.0116 = 0.1379 and 0.8621), and the Ishigami function [Ishigami] (interactions: S₁ ≠ S_T),
each to a tolerance that a 10 % bias of an index fails; the indices of the real analyses' outputs equal SALib's of
the closed-form outputs of the same designs."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from pandas.testing import assert_frame_equal

from mechatron.studies.designs import make_designs
from mechatron.studies.result import study_result
from mechatron.studies.sensitivity import NOISE, RESOLUTION, sobol_indices, unresolved
from mechatron.studies.spec import read_study as read_spec
from tests.corpus import run
from tests.protocol import check_result

CRANK = """mechanism = "crank_slider"
[parameters.l1]
low = {low}
high = {high}
[parameters.l2]
low_mm = 350
high_mm = 450
[designs]
method = "sobol"
samples = {samples}
seed = {seed}
[analyses.linkage]
samples = 13
[output]
sensitivity = true
"""

REACH_L1 = 0.0016 / 0.0116


def write(folder, samples=256, seed=0, low=0.08, high=0.12, name="s.toml"):
    path = folder / name
    path.write_text(CRANK.format(samples=samples, seed=seed, low=low, high=high))
    return path


def exact_table(spec) -> pd.DataFrame:
    """The designs with the closed-form outputs of the crank-slider (what the linkage analysis gives to 1e-12)."""
    table = make_designs(spec)
    table["status"], table["reason"] = "ok", ""
    table["x_travel_m"] = 2 * table["l1"]
    table["reach_m"] = table["l1"] + table["l2"]
    table["height_m"] = 0.0
    return table


@pytest.fixture(scope="module")
def exact(tmp_path_factory):
    spec = read_spec(write(tmp_path_factory.mktemp("exact")))
    return spec, exact_table(spec)


def failed(table: pd.DataFrame, designs, outputs=("x_travel_m", "reach_m", "height_m")) -> pd.DataFrame:
    """``table`` with ``designs`` failed: no value of ``outputs``."""
    table = table.copy()
    rows = table["design"].isin(designs)
    table.loc[rows, list(outputs)] = np.nan
    if len(outputs) == 3:
        table.loc[rows, "status"], table.loc[rows, "reason"] = "failed", "cannot be assembled"
    return table


def salib(spec, y: np.ndarray) -> dict:
    """SALib's indices of the outputs ``y`` (whole blocks), seeded as the study seeds them."""
    from SALib.analyze import sobol

    problem = {"num_vars": 2, "names": ["l1", "l2"], "bounds": [[0.0, 1.0]] * 2}
    return sobol.analyze(problem, y, calc_second_order=False, seed=np.random.SeedSequence(spec.seed))


def test_closed_forms_with_their_intervals(exact):
    spec, table = exact
    indices, skipped, warnings = sobol_indices(spec, table)
    s = indices.set_index(["output", "parameter"])
    for key, expected in {("x_travel_m", "l1"): 1.0, ("reach_m", "l1"): REACH_L1,
                          ("reach_m", "l2"): 1 - REACH_L1}.items():
        row = s.loc[key]
        # 0.002 is 1.5 % of the smallest index (0.138): a 10 % bias fails; the interval covers the closed form too
        assert abs(row["S1"] - expected) <= 0.002 and abs(row["ST"] - expected) <= 0.002, (key, row.to_dict())
        assert abs(row["S1"] - expected) <= row["S1_conf"] and abs(row["ST"] - expected) <= row["ST_conf"], key
    assert s.loc[("x_travel_m", "l2"), ["S1", "S1_conf", "ST", "ST_conf"]].abs().max() <= 1e-12
    assert s["blocks"].tolist() == [256] * 4 and s["resolved"].all()
    assert skipped == {"height_m": "the same on every design"} and warnings == []


ISHIGAMI = """mechanism = "planar_2r"
[parameters.a1]
low = 0.4
high = 0.6
[parameters.a2]
low = 0.3
high = 0.5
[parameters.d1]
low = 0.0
high = 0.1
[designs]
method = "sobol"
samples = 4096
seed = 0
[analyses.dynamics]
[output]
sensitivity = true
"""


def test_the_ishigami_function_to_its_closed_form_indices(tmp_path):
    """f = sin x1 + a sin² x2 + b x3⁴ sin x1 with x1, x2, x3 independent and uniform on [−π, π] [Ishigami],
    a = 7, b = 0.1; here x_i is the unit coordinate of the study's i-th parameter mapped to [−π, π]. By hand, with
    E sin² x = 1/2, E sin⁴ x = 3/8, E x⁴ = π⁴/5 and E x⁸ = π⁸/9 over [−π, π]: f = sin x1 (1 + b x3⁴) + a sin² x2,
    V1 = Var E[f | x1] = ½ (1 + b π⁴/5)², V2 = a² (3/8 − 1/4) = a²/8, V3 = 0, V13 = ½ E(1 + b x3⁴)² − V1 =
    ½ b² π⁸ (1/9 − 1/25) = 8 b² π⁸/225, V = V1 + V2 + V13: S1 = V1/V = 0.3139, S2 = S_T2 = V2/V = 0.4424, S3 = 0,
    S_T1 = (V1 + V13)/V = 0.5576, S_T3 = V13/V = 0.2437. 4096 Saltelli blocks of scrambled Sobol points estimate
    them to 0.01, under 10 % of the smallest non-zero index (0.2437): a 10 % bias fails."""
    path = tmp_path / "ishigami.toml"
    path.write_text(ISHIGAMI)
    spec = read_spec(path)
    table = make_designs(spec)
    x = [-math.pi + 2 * math.pi * (table[p.name] - low) / (high - low)
         for p, low, high in zip(spec.parameters, (0.4, 0.3, 0.0), (0.6, 0.5, 0.1))]
    a, b = 7.0, 0.1
    table["status"], table["reason"] = "ok", ""
    table["f_m"] = np.sin(x[0]) + a * np.sin(x[1]) ** 2 + b * x[2] ** 4 * np.sin(x[0])
    v1, v2, v13 = 0.5 * (1 + b * math.pi**4 / 5) ** 2, a**2 / 8, 8 * b**2 * math.pi**8 / 225
    v = v1 + v2 + v13
    expected = {"a1": (v1 / v, (v1 + v13) / v), "a2": (v2 / v, v2 / v), "d1": (0.0, v13 / v)}
    assert [round(e, 4) for e in (v1 / v, v2 / v, v13 / v)] == [0.3139, 0.4424, 0.2437]  # as quoted for a = 7, b = 0.1
    indices, skipped, _ = sobol_indices(spec, table)
    s = indices.set_index(["output", "parameter"])
    for name, (first, total) in expected.items():
        row = s.loc[("f_m", name)]
        assert abs(row["S1"] - first) <= 0.01 and abs(row["ST"] - total) <= 0.01, (name, row.to_dict())
    assert s["blocks"].tolist() == [4096] * 3 and not skipped


def test_the_bootstrap_is_seeded_by_seed_zero_too(exact):
    # SALib seeds its bootstrap only with a truthy seed: the study's seed 0 drew from NumPy's global state
    spec, table = exact
    assert spec.seed == 0
    first = sobol_indices(spec, table)[0]
    np.random.seed(12345)
    assert_frame_equal(first, sobol_indices(spec, table)[0])


@pytest.mark.parametrize("designs, blocks", [([5], 255), ([4, 7], 255), ([5, 1022], 254)])
def test_a_failed_design_removes_only_its_block(exact, designs, blocks):
    # block j = designs 4j … 4j + 3 (A, A_B^(l1), A_B^(l2), B): the indices are SALib's of the other blocks
    spec, table = exact
    indices, skipped, warnings = sobol_indices(spec, failed(table, designs))
    assert set(indices["blocks"]) == {blocks} and skipped == {"height_m": "the same on every design"}
    keep = ~np.isin(np.arange(256), [d // 4 for d in designs])
    for output in ("x_travel_m", "reach_m"):
        y = table[output].to_numpy().reshape(256, 4)[keep].ravel()
        expected = salib(spec, y)
        got = indices[indices["output"] == output]
        for kind in ("S1", "S1_conf", "ST", "ST_conf"):
            assert got[kind].tolist() == pytest.approx(list(expected[kind]), rel=1e-12, abs=1e-15), (output, kind)
    result = study_result(spec, failed(table, designs))
    text = str(result)
    assert f"Sobol indices from {blocks} of 256 Saltelli blocks ({256 - blocks} left out: a failed design in each)" \
        in text
    data = check_result(result)
    assert data["sobol_blocks"] == 256 and {r["blocks"] for r in data["sensitivity"]} == {blocks}


def test_blocks_counted_per_output(exact):
    # a value missing of one output only: its own blocks are left out, the other output keeps all 256
    spec, table = exact
    result = study_result(spec, failed(table, [9, 13], outputs=("reach_m",)))
    blocks = result.sensitivity.groupby("output")["blocks"].first().to_dict()
    assert blocks == {"x_travel_m": 256, "reach_m": 254}
    text = str(result)
    assert "254 to 256 of 256 Saltelli blocks" in text and "reach_m: l2" in text and "[254 blocks]" in text


def test_too_few_blocks_left(exact):
    spec, table = exact
    broken = failed(table, [4 * j for j in range(256) if j != 17])
    indices, skipped, _ = sobol_indices(spec, broken)
    assert indices.empty
    assert skipped["x_travel_m"] == "a design without a value in 255 of the 256 Saltelli blocks (1 left; indices " \
                                    "need 2)"


def test_an_output_at_the_level_of_numerical_noise(exact):
    # 0.5 m ± 3e-10 m (6e-10 of the scale, below 1e-9): no indices and a warning, no ranking; a real effect of
    # 3e-8 m (6e-8 of the scale) has indices: S1(l1) = 1 within its interval; ±1e-16 about zero is the same
    spec, table = exact
    table = table.copy()
    table["noise_m"] = 0.5 + 3e-10 * np.sin(7.0 * table["design"])
    table["small_m"] = 0.5 + 3e-8 * (table["l1"] - 0.08) / 0.04
    table["zero_m"] = 1e-16 * np.cos(table["design"])
    result = study_result(spec, table)
    assert set(result.skipped) == {"height_m", "noise_m", "zero_m"}
    assert result.skipped["zero_m"] == "the same on every design"
    why = result.skipped["noise_m"]
    assert why.startswith("it varies by only 6e-10 m over the designs (6e-10 of its scale 1 m)")
    assert f"below {NOISE:g}" in why and "rank noise" in why
    assert result.warnings == [f"no Sobol indices of noise_m: {why}"]
    text = str(result)
    assert f"warning: no Sobol indices of noise_m: {why}" in text
    assert "  noise_m:" not in text and text.count("noise_m") == 1  # not ranked, and said once
    small = result.sensitivity.set_index(["output", "parameter"]).loc[("small_m", "l1")]
    assert abs(small["S1"] - 1) <= 0.01 and abs(small["ST"] - 1) <= 0.01  # affine in l1 alone: S1 = ST = 1
    assert json.loads(result.to_json())["warnings"] == result.warnings


@pytest.mark.parametrize("index, half, expected", [
    (-1.29, 2.02, True),     # the N = 16: the interval wider than the index
    (0.954, 0.628, False),
    (1.113, 0.662, False),   # above 1, but within its interval
    (1e-16, 4e-16, False),   # a parameter the output does not depend on: zero, resolved
    (0.005, 0.02, True),
    (-0.5, 0.2, True),       # negative beyond its interval
    (1.5, 0.2, True),
    (0.5, 0.5, False),
])
def test_unresolved(index, half, expected):
    assert unresolved(index, half) is expected
    assert RESOLUTION == 0.01


def test_sixteen_samples_are_warned_through_the_cli(tmp_path, capfd):
    # N = 16 of the real linkage analysis: S1(l1) of the reach, 0.138 in closed form, is 0.0096 ± 0.21; the
    # indices are printed with their intervals, the reach is marked and the warning says why, exit 0
    write(tmp_path, samples=16, seed=1)
    outcome = run(["study", "s.toml", "--out", "out"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    lines = outcome.out.splitlines()
    assert "Sobol indices from 16 Saltelli blocks; each output's largest total index, ± the half-widths of the 95 % " \
           "intervals:" in lines
    reach = next(line for line in lines if line.startswith("  reach_m: "))
    assert reach.endswith("(not resolved: see the warning)") and " ± " in reach
    warning = next(line for line in lines if line.startswith("warning: reach_m:"))
    # the estimate and its interval: SALib's of the closed-form reach l1 + l2 of the same designs
    designs = make_designs(read_spec(tmp_path / "s.toml"))
    reach = salib(read_spec(tmp_path / "s.toml"), (designs["l1"] + designs["l2"]).to_numpy())
    assert warning.startswith(f"warning: reach_m: not resolved by 16 Saltelli blocks: S1(l1) = {reach['S1'][0]:.3g} "
                              f"± {reach['S1_conf'][0]:.3g} (its 95 % interval is wider than the index)")
    assert "take more samples" in warning
    assert not any(line.startswith("  x_travel_m:") and "not resolved" in line for line in lines)
    data = json.loads(run(["study", "s.toml", "--out", "out", "--json"], capfd, tmp_path).out)
    assert data["warnings"] == [warning.removeprefix("warning: ")] and data["sobol_blocks"] == 16
    flags = {(r["output"], r["parameter"]): r["resolved"] for r in data["sensitivity"]}
    assert flags == {("reach_m", "l1"): False, ("reach_m", "l2"): True, ("x_travel_m", "l1"): True,
                     ("x_travel_m", "l2"): True}


def test_failed_designs_through_the_cli(tmp_path, capfd):
    # l1 up to 0.4 m, l2 from 0.35 m: a design with l1 > l2 cannot pass q1 = 90° and fails. Its blocks (which,
    # from the designs' geometry: 3 of 16) are left out; the travel's indices stay exact on the others
    path = write(tmp_path, samples=16, seed=1, low=0.1, high=0.4)
    designs = make_designs(read_spec(path))
    broken = (designs["l1"] > designs["l2"]).to_numpy().reshape(16, 4).any(axis=1)
    assert broken.sum() == 3
    outcome = run(["study", "s.toml", "--out", "out", "--json"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    data = json.loads(outcome.out)
    assert data["failed"] == 4 and data["sobol_blocks"] == 16
    rows = {(r["output"], r["parameter"]): r for r in data["sensitivity"]}
    assert {r["blocks"] for r in rows.values()} == {13}
    travel = rows[("x_travel_m", "l2")]
    assert max(abs(travel[k]) for k in ("S1", "S1_conf", "ST", "ST_conf")) <= 1e-9
    # the 13 blocks left: the indices are SALib's of the closed-form travel 2·l1 of those blocks' designs
    expected = salib(read_spec(path), 2 * designs["l1"].to_numpy().reshape(16, 4)[~broken].ravel())
    for kind in ("S1", "S1_conf", "ST", "ST_conf"):
        assert rows[("x_travel_m", "l1")][kind] == pytest.approx(expected[kind][0], rel=1e-9, abs=1e-12), kind
    text = run(["study", "s.toml", "--out", "out"], capfd, tmp_path).out
    assert "Sobol indices from 13 of 16 Saltelli blocks (3 left out: a failed design in each)" in text
    assert not math.isnan(rows[("reach_m", "l1")]["S1"])

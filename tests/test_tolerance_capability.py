"""Issue 36, part 2: the process capability of the Monte Carlo (Pp, Ppk per axis and of |Δr|, PPM out, their 95 %
intervals) and the sample count chosen by a target error.

The reference case is linear in one parameter: the planar 2R arm stretched along x (q = 0) with an error of its
first length a1 only, so that Δx = Δa1 exactly and Δy = Δz = 0. With a1 normal, bias μ and σ = t/3, the closed
forms are those of the normal distribution (scipy.stats.norm): Pp = 2L/(6σ), Ppk = (L − |μ|)/(3σ),
PPM = 10⁶ (Φ((−L − μ)/σ) + 1 − Φ((L − μ)/σ)); |Δr| = |Δx| is folded normal (scipy.stats.foldnorm), its Ppk
(L − E|Δr|)/(3 sd|Δr|) and its PPM the same as Δx's.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from protocol import check_result
from scipy import stats

import mechatron
from mechatron.accuracy.capability import ppm_error, sigma_error
from mechatron.accuracy.sources import ErrorSource, read_poses, read_tolerances
from mechatron.accuracy.streaming import CentralMoments
from mechatron.accuracy.study import analyse_tolerances
from mechatron.cli import main
from tests.corpus import assert_clean_error

MU, SIGMA, LIMIT = 0.05e-3, 0.1e-3, 0.2e-3  # m: bias, standard deviation (t = 3σ) and limit
POSE = [[0.0, 0.0]]


@pytest.fixture(scope="module")
def arm():
    return mechatron.load("planar_2r")


def sources(mu: float = MU, sigma: float = SIGMA) -> list[ErrorSource]:
    return [ErrorSource("a1", "parameter", "m", 3 * sigma, "normal", bias=mu)]


def truth(mu: float = MU, sigma: float = SIGMA, limit: float = LIMIT) -> dict[str, dict[str, float]]:
    """The closed forms of the linear case: per quantity pp, ppk, ppm."""
    ppm = 1e6 * (stats.norm.cdf((-limit - mu) / sigma) + stats.norm.sf((limit - mu) / sigma))
    folded = stats.foldnorm(abs(mu) / sigma, scale=sigma)
    return {"dx": {"pp": 2 * limit / (6 * sigma), "ppk": (limit - abs(mu)) / (3 * sigma), "ppm": ppm},
            "dr": {"ppk": (limit - folded.mean()) / (3 * folded.std()), "ppm": ppm}}


def study(arm, samples: int, seed: int, **options):
    return analyse_tolerances(arm, sources(), POSE, methods=["mc"], samples=samples, seed=seed, limit=LIMIT,
                              **options)


def rows(result) -> dict[str, dict]:
    return {row["quantity"]: row for row in result.capability.to_dict(orient="records")}


def test_the_case_is_linear_with_unit_sensitivity(arm):
    result = analyse_tolerances(arm, sources(), POSE, methods=["worst"])
    assert result.sensitivities.matrix[0, :, 0] == pytest.approx([1.0, 0.0, 0.0], abs=1e-12)


def test_indices_and_ppm_match_the_normal_closed_form_within_their_intervals(arm):
    result = study(arm, 200_000, seed=3)
    row, want = rows(result), truth()
    for quantity, values in want.items():
        for name, value in values.items():
            r = row[quantity]
            assert r[f"{name}_low"] <= value <= r[f"{name}_high"], (quantity, name, r, value)
            assert r[name] == pytest.approx(value, rel=0.02)
    assert row["dx"]["ppk"] == pytest.approx(0.5, rel=0.02)  # (0.2 − 0.05)/(3 · 0.1)
    assert row["dx"]["ppm"] == pytest.approx(73_000, rel=0.02)  # Φ(−2.5) + Φ(−1.5)
    for quantity in ("dy", "dz"):  # no spread: Pp, Ppk infinite, nothing out
        assert row[quantity]["std"] == 0 and math.isinf(row[quantity]["ppk"]) and row[quantity]["ppm"] == 0
    assert row["dr"]["spec"] == "≤ L" and math.isnan(row["dr"]["pp"])
    # per axis |Δx| > L implies |Δr| > L: the same samples out here
    assert row["dr"]["ppm"] == row["dx"]["ppm"]
    assert row["dx"]["samples"] == 200_000


def test_intervals_cover_the_true_values_over_seeds(arm):
    want = truth()
    inside = {(q, name): 0 for q, values in want.items() for name in values}
    seeds = range(40)
    for seed in seeds:
        row = rows(study(arm, 2000, seed=100 + seed))
        for (q, name) in inside:
            inside[(q, name)] += row[q][f"{name}_low"] <= want[q][name] <= row[q][f"{name}_high"]
    coverage = {key: count / len(seeds) for key, count in inside.items()}
    assert all(c >= 0.9 for c in coverage.values()), coverage


def test_target_error_of_sigma_is_reached_and_its_spread_is_the_target(arm):
    target = 0.05
    sigmas, counts = {"dx": [], "dr": []}, []
    for seed in range(30):
        result = study(arm, 100_000, seed=seed, target_error=target)
        reached = float(result.poses["reached_error_mc"].iloc[0])
        assert reached <= target
        row = rows(result)
        assert row["dx"]["sigma_error"] == pytest.approx(reached)
        counts.append(int(result.poses["samples_mc"].iloc[0]))
        for q in sigmas:
            sigmas[q].append(row[q]["std"])
    assert max(counts) < 100_000  # stopped before the cap
    # the empirical relative spread of σ over the seeds: the largest is the one the target bounds
    folded = stats.foldnorm(MU / SIGMA, scale=SIGMA)
    spread = max(np.std(sigmas["dx"], ddof=1) / SIGMA, np.std(sigmas["dr"], ddof=1) / folded.std())
    assert target / 1.5 <= spread <= target * 1.5, (spread, counts)
    # a normal σ̂ needs about 1 + 1/(2E²) samples; |Δr| (lighter tails) needs no more
    assert 0.5 * (1 + 1 / (2 * target**2)) <= np.median(counts) <= 2 * (1 + 1 / (2 * target**2))


def test_target_error_of_the_ppm_is_reached_and_its_spread_is_the_target(arm):
    target = 0.1
    p = truth()["dr"]["ppm"] / 1e6
    ppms, counts = [], []
    for seed in range(30):
        result = study(arm, 200_000, seed=seed, target_error=target, target="ppm")
        reached = float(result.poses["reached_error_mc"].iloc[0])
        assert reached <= target and result.target == "ppm" and result.target_error == target
        ppms.append(rows(result)["dr"]["ppm"])
        counts.append(int(result.poses["samples_mc"].iloc[0]))
    spread = np.std(ppms, ddof=1) / (1e6 * p)
    assert target / 1.5 <= spread <= target * 1.5, (spread, counts)
    assert np.median(counts) == pytest.approx((1 - p) / (p * target**2), rel=0.3)  # √((1 − p)/(n p)) = E


def test_a_target_beyond_the_cap_stops_at_the_cap_and_says_so(arm):
    result = study(arm, 500, seed=0, target_error=0.001)
    assert int(result.poses["samples_mc"].iloc[0]) == 500
    assert result.poses["reached_error_mc"].iloc[0] > 0.001
    assert any("was not reached" in note for note in result.notes)


def test_progress_shows_the_error_converging(arm):
    seen, texts = [], []

    def progress(done, total):
        seen.append((done, total))

    progress.status = texts.append  # type: ignore[attr-defined]
    study(arm, 100_000, seed=1, target_error=0.02, progress=progress)
    errors = [float(t.split("relative error of σ ")[1].split(" ")[0]) for t in texts]
    assert len(errors) >= 2 and errors[-1] <= 0.02 < errors[0]
    assert seen[-1] == (100_000, 100_000)  # the pose's share is done when it stops early


def test_streamed_fourth_moment_equals_the_whole():
    rng = np.random.default_rng(7)
    x = np.column_stack([rng.gamma(2.0, size=5000), rng.standard_normal(5000) * 1e-4 + 3.0])
    moments = CentralMoments(2)
    for part in np.array_split(x, [1, 7, 700, 2500]):
        moments.add(part)
    assert moments.n == len(x)
    assert moments.mean == pytest.approx(x.mean(axis=0), rel=1e-13)
    for p, value in ((2, moments.m2), (3, moments.m3), (4, moments.m4)):
        assert value / len(x) == pytest.approx(stats.moment(x, p, axis=0), rel=1e-9)
    # the relative standard error of σ̂ of normal samples: 1/√(2(n − 1))
    n = 10_000
    assert sigma_error(n, np.array([1.0]), np.array([3.0])) == pytest.approx(1 / math.sqrt(2 * (n - 1)))
    assert ppm_error(25, 10_000) == pytest.approx(math.sqrt(0.9975 / 25)) and math.isinf(ppm_error(0, 10))


def test_result_protocol_table_json_and_chart(arm):
    result = study(arm, 5000, seed=2, target_error=0.05)
    data = check_result(result)
    assert data["target_error"] == 0.05 and data["target"] == "sigma"
    (record,) = data["poses"]
    capability = record["capability"]
    assert capability["samples"] == int(result.poses["samples_mc"].iloc[0])
    assert set(capability) >= {"dx", "dy", "dz", "dr", "sigma_error", "ppm_error"}
    assert capability["dy"]["ppk"] is None and capability["dr"]["pp"] is None  # infinite and undefined: null
    assert record["methods"]["mc"]["samples"] == capability["samples"]
    text = str(result)
    assert "process capability against L = 0.2 mm" in text and "samples chosen for a relative standard error" in text
    figure = result.monte_carlo_chart()
    ax = figure.axes[-1]
    assert ax.get_xlabel() == "pose (label)" and ax.get_ylabel() == "Ppk (-)" and ax.get_legend() is not None


def test_no_capability_without_a_limit(arm):
    result = analyse_tolerances(arm, sources(), POSE, methods=["mc"], samples=500, target_error=0.1)
    assert result.capability is None and "samples_mc" in result.poses
    assert "capability" not in result.as_dict()["poses"][0]


@pytest.fixture
def files(tmp_path):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_mm,bias_mm\na1,0.3,0.05\n")
    (tmp_path / "poses.csv").write_text("q1,q2\n0,0\n")
    return tmp_path


BASE = ["tolerance", "planar_2r", "--tolerances", "tol.csv", "--poses", "poses.csv"]


@pytest.mark.parametrize("value", ["nan", "0", "-0.1", "1", "2", "inf", "0.6"])
def test_cli_bad_target_error(capfd, files, value):
    assert_clean_error([*BASE, "--method", "mc", "--target-error", value], capfd, files, ["--target-error"])


@pytest.mark.parametrize("extra, words", [(["--method", "worst", "--target-error", "0.1"], ["--target-error", "mc"]),
                                          (["--method", "mc", "--target-error", "0.1", "--target", "ppm"],
                                           ["--target-error", "--limit-mm"]),
                                          (["--method", "mc", "--target", "cpk"], ["--target"])])
def test_cli_target_error_needs_the_monte_carlo(capfd, files, extra, words):
    assert_clean_error([*BASE, *extra], capfd, files, words)


def test_cli_json_is_the_result(capsys, files, monkeypatch, arm):
    monkeypatch.chdir(files)
    code = main([*BASE, "--method", "mc", "--limit-mm", "0.2", "--target-error", "0.05", "--samples", "20000",
                 "--seed", "4", "--json"])
    out, _ = capsys.readouterr()
    assert code == 0
    data = json.loads(out)
    result = analyse_tolerances(arm, read_tolerances(files / "tol.csv", arm), *read_poses(files / "poses.csv", arm),
                                methods=["mc"], samples=20000, seed=4, limit=LIMIT, target_error=0.05)
    assert data == json.loads(result.to_json())
    assert data["poses"][0]["capability"]["sigma_error"] <= 0.05


def test_cli_writes_the_capability_table(files, monkeypatch, capsys):
    """``--capability FILE``: the table of every pose and quantity, whose Ppk and PPM of Δx hold the normal closed
    form within the written 95 % intervals."""
    import pandas as pd

    monkeypatch.chdir(files)
    code = main([*BASE, "--method", "mc", "--limit-mm", "0.2", "--samples", "100000", "--seed", "2",
                 "--capability", "cap.csv"])
    assert code == 0 and "wrote cap.csv" in capsys.readouterr().out
    table = pd.read_csv(files / "cap.csv").set_index("quantity")
    assert list(table.index) == ["dx", "dy", "dz", "dr"]
    want = truth()
    for name in ("ppk", "ppm"):
        assert table.loc["dx", f"{name}_low"] <= want["dx"][name] <= table.loc["dx", f"{name}_high"]
    assert table.loc["dx", "std"] == pytest.approx(SIGMA, rel=0.02)  # m


@pytest.mark.parametrize("extra", [["--method", "rss", "--limit-mm", "0.2"], ["--method", "mc"]])
def test_cli_capability_needs_the_monte_carlo_and_a_limit(capfd, files, extra):
    assert_clean_error([*BASE, *extra, "--capability", "cap.csv"], capfd, files, ["--capability"])
    assert not (files / "cap.csv").exists()

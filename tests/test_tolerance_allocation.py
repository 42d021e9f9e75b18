"""Tolerance allocation at least cost [Chase]: the closed-form Lagrange optima of the RSS and worst-case limits, the
process selection against brute force over every combination, the shipped PUMA allocation verified by a Monte Carlo,
and bad inputs through the command line.

The sensitivities of the planar 2R arm (lengths a1 = 0.5 m, a2 = 0.4 m, tool at the end of link 2) are known in
closed form: r = (a1 c1 + a2 c12, a1 s1 + a2 s12, 0), so ∂r/∂a1 = (c1, s1, 0), ∂r/∂a2 = (c12, s12, 0),
∂r/∂q1 = (−y, x, 0) and ∂r/∂q2 = (−a2 s12, a2 c12, 0).
"""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.accuracy.allocation import allocate_tolerances
from mechatron.accuracy.costs import read_cost_models, read_processes
from mechatron.accuracy.sources import read_poses, read_tolerances
from mechatron.cli import main

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "examples" / "data"
A1, A2 = 0.5, 0.4
MM, MRAD = 1e-3, 1e-3


def planar_jacobian(q1: float, q2: float) -> dict[str, np.ndarray]:
    """∂r/∂e of the planar 2R arm's tool for a1, a2 (m/m), q1, q2 (m/rad), in closed form."""
    c1, s1, c12, s12 = math.cos(q1), math.sin(q1), math.cos(q1 + q2), math.sin(q1 + q2)
    x, y = A1 * c1 + A2 * c12, A1 * s1 + A2 * s12
    return {"a1": np.array([c1, s1, 0.0]), "a2": np.array([c12, s12, 0.0]), "q1": np.array([-y, x, 0.0]),
            "q2": np.array([-A2 * s12, A2 * c12, 0.0])}


@pytest.fixture(scope="module")
def arm():
    return mechatron.load("planar_2r")


def continuous_file(tmp_path: Path, costs: dict[str, float], distribution: str = "normal") -> Path:
    """A tolerances file of continuous costs b/t (t in mm or mrad) over wide bounds (the optimum inside them)."""
    lines = ["parameter,tolerance_min_mm,tolerance_max_mm,tolerance_min_mrad,tolerance_max_mrad,cost_b,distribution"]
    for name, b in costs.items():
        bounds = "1e-4,10,," if name.startswith("a") else ",,1e-4,10"
        lines.append(f"{name},{bounds},{b!r},{distribution}")
    path = tmp_path / "costs.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


# ------------------------------------------------------------------------------------- (a) RSS: Lagrange's optimum
def test_rss_two_sources_meet_the_lagrange_closed_form(arm, tmp_path):
    """min Σ b_i/t_i s.t. Σ s_i² t_i² = L² (RSS of normal errors, σ = t/k, so kσ = t): −b_i/t_i² + 2λ s_i² t_i = 0
    gives t_i = (b_i/s_i²)^(1/3)·μ, and the constraint μ = L/√(Σ_j s_j^(2/3) b_j^(2/3)). Here t_1 in mm (a1),
    t_2 in mrad (q1): s_i in m per mm (mrad)."""
    b = {"a1": 2.0, "q1": 5.0}
    path = continuous_file(tmp_path, b)
    limit = 0.1e-3
    q = (0.3, 0.7)
    J = planar_jacobian(*q)
    s = np.array([np.linalg.norm(J["a1"]) * MM, np.linalg.norm(J["q1"]) * MRAD])
    bb = np.array([b["a1"], b["q1"]])
    expected = (bb / s**2) ** (1 / 3) * limit / math.sqrt(np.sum(s ** (2 / 3) * bb ** (2 / 3)))
    result = allocate_tolerances(arm, path, np.array([q]), limit=limit, method="rss", samples=2000)
    table = result.table.set_index("source")
    assert table.loc[["a1", "q1"], "tolerance"].to_numpy() == pytest.approx(expected, rel=1e-6)
    assert table.loc["a1", "tolerance_si"] == pytest.approx(expected[0] * MM, rel=1e-6)
    assert result.total_cost == pytest.approx(float(np.sum(bb / expected)), rel=1e-6)
    assert result.binding == ["1"] and result.poses["dr"].iloc[0] == pytest.approx(limit, rel=1e-9)
    # the error shares are s_i² t_i² / L²
    assert table.loc[["a1", "q1"], "share"].to_numpy() == pytest.approx(100 * (s * expected) ** 2 / limit**2,
                                                                         rel=1e-6)
    assert result.meets and str(result) and json.dumps(result.as_dict(), allow_nan=False)


def test_rss_binds_at_the_pose_of_the_largest_sensitivity(arm, tmp_path):
    """Over several poses the constraint binds where |∂r/∂q1| = √(a1² + a2² + 2 a1 a2 cos q2) is largest (q2 = 0):
    the optimum is that pose's closed form, the other poses slack."""
    b = {"a1": 1.0, "q1": 3.0}
    path = continuous_file(tmp_path, b)
    limit = 0.05e-3
    poses = np.array([[0.2, 1.5], [0.0, 0.0], [1.0, -1.0]])
    s = np.array([1.0 * MM, (A1 + A2) * MRAD])
    bb = np.array([b["a1"], b["q1"]])
    expected = (bb / s**2) ** (1 / 3) * limit / math.sqrt(np.sum(s ** (2 / 3) * bb ** (2 / 3)))
    result = allocate_tolerances(arm, path, poses, ["bent", "stretched", "other"], limit, samples=1000)
    assert result.table["tolerance"].to_numpy() == pytest.approx(expected, rel=1e-6)
    assert result.binding == ["stretched"] and result.critical == "stretched"
    assert (result.poses["dr"].to_numpy()[[0, 2]] < limit * (1 - 1e-3)).all()


def test_uniform_errors_weigh_k_over_root_3(arm, tmp_path):
    """Uniform errors: kσ = k t/√3, so the same closed form with s_i → s_i·k/√3 (k = 3: √3)."""
    b = {"a1": 2.0, "q1": 5.0}
    path = continuous_file(tmp_path, b, "uniform")
    limit = 0.1e-3
    q = (0.3, 0.7)
    J = planar_jacobian(*q)
    s = math.sqrt(3) * np.array([np.linalg.norm(J["a1"]) * MM, np.linalg.norm(J["q1"]) * MRAD])
    bb = np.array([b["a1"], b["q1"]])
    expected = (bb / s**2) ** (1 / 3) * limit / math.sqrt(np.sum(s ** (2 / 3) * bb ** (2 / 3)))
    result = allocate_tolerances(arm, path, np.array([q]), limit=limit, samples=1000)
    assert result.table["tolerance"].to_numpy() == pytest.approx(expected, rel=1e-6)


# ------------------------------------------------------------------------------------- (d) worst case: Lagrange
def test_worst_case_along_one_axis_meets_the_closed_form(arm, tmp_path):
    """At q = (0, 0) ∂r/∂q1 = (0, a1 + a2, 0) and ∂r/∂q2 = (0, a2, 0) lie along y, so the worst case is linear,
    Σ s_i t_i ≤ L; min Σ b_i/t_i: −b_i/t_i² + λ s_i = 0, t_i = √(b_i/s_i)·L/Σ_j √(b_j s_j)."""
    b = {"q1": 4.0, "q2": 1.5}
    path = continuous_file(tmp_path, b)
    limit = 0.2e-3
    s = np.array([(A1 + A2) * MRAD, A2 * MRAD])
    bb = np.array([b["q1"], b["q2"]])
    expected = np.sqrt(bb / s) * limit / np.sum(np.sqrt(bb * s))
    result = allocate_tolerances(arm, path, np.array([[0.0, 0.0]]), limit=limit, method="worst", samples=1000)
    assert result.table["tolerance"].to_numpy() == pytest.approx(expected, rel=1e-6)
    assert result.total_cost == pytest.approx(float(np.sum(bb / expected)), rel=1e-6)
    assert result.poses["dr"].iloc[0] == pytest.approx(limit, rel=1e-9)


# ------------------------------------------------------------------------------------- (b) discrete: brute force
PROCESSES = """process,option,tolerance_mm,tolerance_mrad,cost
length,rough,0.2,,1.0
length,fine,0.08,,2.7
length,ground,0.03,,6.1
length,lapped,0.01,,13.9
encoder,12 bit,,1.5,3.2
encoder,14 bit,,0.4,7.5
encoder,16 bit,,0.1,18.0
"""
#: The tables of PROCESSES in SI: (tolerance m or rad, cost), loosest first.
TABLES = {"length": [(0.2e-3, 1.0), (0.08e-3, 2.7), (0.03e-3, 6.1), (0.01e-3, 13.9)],
          "encoder": [(1.5e-3, 3.2), (0.4e-3, 7.5), (0.1e-3, 18.0)]}
POSES = np.array([[0.0, 0.0], [0.4, 1.2], [-0.7, 2.2]])


def brute_force(method: str, limit: float, rows: dict[str, str], distributions: dict[str, str],
                tables: dict[str, list[tuple[float, float]]]) -> tuple[float, tuple[float, ...]]:
    """The cheapest combination of every row's options meeting the limit at every pose, by trying each."""
    Js = [planar_jacobian(*q) for q in POSES]
    weight = {"normal": 1.0, "uniform": 3 / math.sqrt(3)}
    best = (math.inf, ())
    names = list(rows)
    for choice in itertools.product(*(tables[rows[n]] for n in names)):
        t = [c[0] for c in choice]
        cost = sum(c[1] for c in choice)
        errors = []
        for J in Js:
            if method == "worst":
                axes = sum(np.abs(J[n]) * ti for n, ti in zip(names, t))
            else:
                axes = np.sqrt(sum((J[n] * weight[distributions[n]] * ti) ** 2 for n, ti in zip(names, t)))
            errors.append(np.linalg.norm(axes))
        if max(errors) <= limit and cost < best[0]:
            best = (cost, tuple(t))
    return best


@pytest.mark.parametrize("method, limit", [("rss", 0.3e-3), ("rss", 0.6e-3), ("rss", 1.2e-3), ("worst", 0.5e-3),
                                           ("worst", 0.9e-3), ("worst", 1.8e-3)])
def test_process_selection_equals_brute_force(arm, tmp_path, method, limit):
    processes = tmp_path / "processes.csv"
    processes.write_text(PROCESSES)
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,process,distribution\na1,length,normal\na2,length,uniform\n"
                          "q1,encoder,uniform\nq2,encoder,normal\n")
    tables = TABLES
    rows = {"a1": "length", "a2": "length", "q1": "encoder", "q2": "encoder"}
    distributions = {"a1": "normal", "a2": "uniform", "q1": "uniform", "q2": "normal"}
    cost, t = brute_force(method, limit, rows, distributions, tables)
    assert math.isfinite(cost)
    result = allocate_tolerances(arm, tolerances, POSES, limit=limit, method=method, processes=processes,
                                 samples=500)
    assert result.total_cost == pytest.approx(cost, rel=1e-12)
    assert result.table["tolerance_si"].to_numpy() == pytest.approx(np.array(t), rel=1e-12)
    assert result.search["nodes"] < 3 * 4 * 4 * 3 * 3  # the bound prunes: fewer nodes than the full tree's


def test_a_mix_of_process_and_continuous_rows_equals_brute_force(arm, tmp_path):
    """Process rows a1, q1 and a continuous row q2 (cost 2/t, t in mrad): for each combination of the process rows
    the cheapest q2 is the loosest one meeting the limit, t = min(t_max, min over poses √((L² − rest)/s²)) (RSS of
    normal errors, no bias), so brute force over the combinations is exact."""
    processes = tmp_path / "processes.csv"
    processes.write_text(PROCESSES)
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,process,tolerance_min_mrad,tolerance_max_mrad,cost_b\na1,length,,,\n"
                          "q1,encoder,,,\nq2,,0.01,5,2\n")
    tables = TABLES
    limit = 0.5e-3
    Js = [planar_jacobian(*q) for q in POSES]
    best = (math.inf, ())
    for (ta, ca), (tq, cq) in itertools.product(tables["length"], tables["encoder"]):
        room = [limit**2 - np.sum((J["a1"] * ta) ** 2 + (J["q1"] * tq) ** 2) for J in Js]
        if min(room) <= 0:
            continue
        t2 = min(5e-3, min(math.sqrt(r / np.sum(J["q2"] ** 2)) for r, J in zip(room, Js)))
        if t2 < 0.01e-3:
            continue
        cost = ca + cq + 2.0 / (t2 / MRAD)
        if cost < best[0]:
            best = (cost, (ta, tq, t2))
    result = allocate_tolerances(arm, tolerances, POSES, limit=limit, processes=processes, samples=500)
    assert result.total_cost == pytest.approx(best[0], rel=1e-7)
    assert result.table["tolerance_si"].to_numpy() == pytest.approx(np.array(best[1]), rel=1e-6)


# ------------------------------------------------------------------------------------- (c) the shipped PUMA
def test_the_puma_allocation_meets_its_limit_in_the_monte_carlo(tmp_path):
    puma = mechatron.load("puma560")
    poses, labels = read_poses(DATA / "poses_puma560.csv", puma)
    limit = 0.25e-3
    result = allocate_tolerances(puma, DATA / "tolerances_puma560_costs.csv", poses, labels, limit,
                                 processes=DATA / "processes_puma560.csv", samples=20000, seed=3)
    assert (result.poses["dr"] <= limit * (1 + 1e-6)).all() and result.binding
    # an independent study of the written allocation: its RSS and its Monte Carlo within the limit at every pose
    written = result.write_tolerances(tmp_path / "allocated.csv")
    study = mechatron.tolerance_study(puma, written, DATA / "poses_puma560.csv", methods=["rss", "mc"],
                                      samples=20000, seed=5, limit=limit)
    assert study.poses["dr_rss"].to_numpy() == pytest.approx(result.poses["dr"].to_numpy(), rel=1e-9)
    assert (study.poses["dr_mc"] <= limit).all() and result.meets
    # the file's own tolerances fail the limit; the allocation costs what its rows say
    costed = read_cost_models(DATA / "tolerances_puma560_costs.csv", puma, DATA / "processes_puma560.csv")
    cost = sum(c.cost(t) for c, t in zip(costed, result.table["tolerance_si"]))
    assert result.total_cost == pytest.approx(cost, rel=1e-9)
    given = mechatron.tolerance_study(puma, DATA / "tolerances_puma560_costs.csv", DATA / "poses_puma560.csv",
                                      methods=["rss"])
    assert given.poses["dr_rss"].max() > limit
    result.plot()


def test_written_tolerances_read_back_with_their_units(arm, tmp_path):
    path = continuous_file(tmp_path, {"a1": 2.0, "q1": 5.0})
    result = allocate_tolerances(arm, path, np.array([[0.3, 0.7]]), limit=0.1e-3, samples=500)
    back = read_tolerances(result.write_tolerances(tmp_path / "out.csv"), arm)
    assert [s.tolerance for s in back] == pytest.approx(list(result.table["tolerance_si"]), rel=1e-15)
    assert "tolerance_mm" in (tmp_path / "out.csv").read_text().splitlines()[0]


# ------------------------------------------------------------------------------------- (e) bad inputs, the CLI
def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


BAD_COSTS = [
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_b\na1,0.01,1,-2\n", "row 2: field 'cost_b'",
     "cost_b must be > 0"),
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_b,cost_k\na1,0.01,1,2,-1\n", "row 2: field 'cost_k'",
     "does not rise"),
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_b\na1,0.01,1,nan\n", "row 2: field 'cost_b'", "not a finite"),
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_a,cost_b\na1,0.01,1,-3,2\n", "row 2: field 'cost_a'",
     "must be >= 0"),
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_b\na1,0.01,1,1e308\n", "row 2: field 'cost_b'", "cost"),
    ("parameter,tolerance_min_mm,tolerance_max_mm,cost_b\na1,1,0.01,2\n", "row 2: field 'tolerance_max_mm'",
     "above tolerance_min"),
    ("parameter,tolerance_min_mm,cost_b\na1,0.01,2\n", "row 2: field 'tolerance_max'", "needs tolerance_max"),
    ("parameter,tolerance_min_deg,tolerance_max_deg,cost_b\na1,0.01,1,2\n", "row 2: field 'tolerance_min_deg'",
     "a length cannot be given in deg"),
    ("parameter,process\na1,turning\n", "row 2: field 'process'", "needs the process tables"),
]


@pytest.mark.parametrize("text, where, message", BAD_COSTS)
def test_bad_cost_models_are_one_line_naming_file_row_and_field(capsys, tmp_path, text, where, message):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text(text)
    out_file = tmp_path / "allocated.csv"
    code, out, err = run(capsys, "tolerance", "planar_2r", "--tolerances", str(tolerances), "--allocate",
                         "--limit-mm", "0.1", "--allocated", str(out_file))
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert f"t.csv: {where}" in err and message in err, err
    assert tolerances.read_text() == text and not out_file.exists()


BAD_PROCESSES = [
    ("process,tolerance_mm,cost\n", "the file has no rows", "p.csv"),
    ("process,tolerance_mm,cost\nturning,0.1,5\nturning,0.05,4\n", "row 3: field 'cost'", "must rise"),
    ("process,tolerance_mm,cost\nturning,0.1,5\nturning,0.05,nan\n", "row 3: field 'cost'", "not a finite"),
    ("process,tolerance_mm,cost\nturning,0.1,-5\n", "row 2: field 'cost'", "from 0"),
    ("process,tolerance_mm,cost\ngrinding,0.1,5\n", "row 2: field 'process'", "no process table 'turning'"),
    ("process,tolerance_arcsec,cost\nturning,10,5\n", "row 2: field 'process'", "angle tolerances but a1 is a length"),
]


@pytest.mark.parametrize("text, where, message", BAD_PROCESSES)
def test_bad_process_tables_are_one_line(capsys, tmp_path, text, where, message):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,process\na1,turning\n")
    processes = tmp_path / "p.csv"
    processes.write_text(text)
    code, out, err = run(capsys, "tolerance", "planar_2r", "--tolerances", str(tolerances), "--allocate",
                         "--limit-mm", "0.1", "--processes", str(processes))
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert where in err and message in err, err
    assert processes.read_text() == text


def test_a_limit_below_the_unavoidable_error_names_the_pose(capsys, tmp_path):
    """The fixed rows alone (q1 ±1 mrad at a reach of 0.9 m, normal: 0.9 mm RSS at the stretched pose) exceed
    L = 0.5 mm whatever a1 gets: the message names the pose and the smallest |Δr| reachable there."""
    tolerances = tmp_path / "t.csv"
    text = "parameter,tolerance_mrad,tolerance_min_mm,tolerance_max_mm,cost_b\nq1,1,,,\na1,,0.01,1,2\n"
    tolerances.write_text(text)
    poses = tmp_path / "poses.csv"
    poses.write_text("label,q1,q2\nbent,0,2.5\nstretched,0,0\n")
    out_file = tmp_path / "allocated.csv"
    code, out, err = run(capsys, "tolerance", "planar_2r", "--tolerances", str(tolerances), "--poses", str(poses),
                         "--allocate", "--limit-mm", "0.5", "--allocated", str(out_file))
    reach = math.hypot(0.9, 0.01)  # q1: 0.9 mm along y, a1 at its tightest 0.01 mm along x
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "pose stretched" in err and f"{reach:.4g} mm" in err and "unavoidable" in err, err
    assert not out_file.exists() and tolerances.read_text() == text


@pytest.mark.parametrize("argv, message", [
    ([], "--allocate needs --limit-mm"),
    (["--limit-mm", "0.1", "--method", "mc"], "--allocate bounds --method rss or worst, not mc"),
    (["--limit-mm", "0.1", "--method", "all"], "not all"),
])
def test_allocate_options(capsys, tmp_path, argv, message):
    tolerances = continuous_file(tmp_path, {"a1": 2.0})
    code, out, err = run(capsys, "tolerance", "planar_2r", "--tolerances", str(tolerances), "--allocate", *argv)
    assert code == 2 and out == "" and message in err and len(err.strip().splitlines()) == 1


def test_no_cost_model_is_nothing_to_allocate(capsys, tmp_path):
    tolerances = tmp_path / "t.csv"
    tolerances.write_text("parameter,tolerance_mm\na1,0.1\n")
    code, _, err = run(capsys, "tolerance", "planar_2r", "--tolerances", str(tolerances), "--allocate",
                       "--limit-mm", "1")
    assert code == 2 and "nothing to allocate" in err


def test_the_cli_prints_and_writes_the_allocation(capsys, tmp_path):
    out_file, table = tmp_path / "allocated.csv", tmp_path / "table.csv"
    code, out, err = run(capsys, "tolerance", "puma560", "--tolerances", str(DATA / "tolerances_puma560_costs.csv"),
                         "--processes", str(DATA / "processes_puma560.csv"), "--poses",
                         str(DATA / "poses_puma560.csv"), "--allocate", "--limit-mm", "0.25", "--samples", "2000",
                         "--allocated", str(out_file), "--csv", str(table), "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["meets_limit_mc"] and data["binding_poses"] and data["total_cost"] > 0
    assert {r["source"] for r in data["tolerances"]} == {s.name for s in read_tolerances(out_file,
                                                                                           mechatron.load("puma560"))}
    assert out_file.exists() and table.exists()
    code, out, _ = run(capsys, "tolerance", "puma560", "--tolerances", str(DATA / "tolerances_puma560_costs.csv"),
                       "--processes", str(DATA / "processes_puma560.csv"), "--task",
                       str(DATA / "pick_and_place.toml"), "--allocate", "--limit-mm", "0.3", "--samples", "500")
    assert code == 0 and "binding poses" in out and "total cost" in out



def test_the_report_holds_the_allocation_method_and_poses(capsys, tmp_path):
    """``--report``: the allocated table, the method, every pose with the Monte Carlo's verdict, as the JSON says."""
    import re

    report = tmp_path / "allocation.html"
    code, out, err = run(capsys, "tolerance", "puma560", "--tolerances", str(DATA / "tolerances_puma560_costs.csv"),
                         "--processes", str(DATA / "processes_puma560.csv"), "--poses",
                         str(DATA / "poses_puma560.csv"), "--allocate", "--limit-mm", "0.25", "--samples", "500",
                         "--report", str(report), "--json")
    assert code == 0, err
    data, text = json.loads(out), report.read_text(encoding="utf-8")
    assert re.findall(r"<h2[^>]*>(.*?)</h2>", text)[1:5] == ["Allocation", "Method", "Poses", "Charts"]
    assert f"total cost {data['total_cost']:.6g}" in text and "branch and bound" in text
    assert text.count(">PASS<") == len(data["poses"]) == 6 and data["meets_limit_mc"]

def test_processes_file_reads_sorted_with_rising_costs():
    tables = read_processes(DATA / "processes_puma560.csv")
    for table in tables.values():
        assert list(table.tolerances) == sorted(table.tolerances, reverse=True)
        assert all(b > a for a, b in zip(table.costs, table.costs[1:]))

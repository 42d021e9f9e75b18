"""The workspace of a two-input linkage (mechatron.kinematics.workspaces, ``mechatron linkage --workspace``) against
the closed form of a five-bar.

tests/data/five_bar.toml: cranks AB about A = (0, 0) and ED about E = (d, 0), both of length a, at the world angles
q1 and q2; couplers BP and DP, both of length b, meet at P. With B = a(cos q1, sin q1), D = (d, 0) + a(cos q2,
sin q2) and L = |D − B|, the pin P is one of the two intersections of the circles of radius b about B and D:
P = (B + D)/2 + h n, h = √(b² − L²/4), n the unit normal of D − B turned +90° (the drawn branch, P above the line
B → D). It assembles where L ≤ 2b; the inputs run over the joints' limits, q1 ∈ [60°, 180°], q2 ∈ [0°, 120°].
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.cli import main
from mechatron.errors import InputError
from mechatron.kinematics.workspaces import workspace
from tests.protocol import check_result

FIVE_BAR = str(Path(__file__).resolve().parent / "data" / "five_bar.toml")
A_LEN, D_LEN, B_LEN = 0.15, 0.2, 0.22  # crank, frame, coupler (m), as the file's header says
Q1 = (math.radians(60), math.radians(180))
Q2 = (0.0, math.radians(120))


def closed_form(q1: np.ndarray, q2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(P (…, 2) on the drawn branch, NaN where it does not assemble; L = |BD|) of the module docstring."""
    B = A_LEN * np.stack([np.cos(q1), np.sin(q1)], axis=-1)
    D = np.array([D_LEN, 0.0]) + A_LEN * np.stack([np.cos(q2), np.sin(q2)], axis=-1)
    u = D - B
    L = np.hypot(u[..., 0], u[..., 1])
    with np.errstate(invalid="ignore"):
        h = np.sqrt(B_LEN**2 - L**2 / 4)
    n = np.stack([-u[..., 1], u[..., 0]], axis=-1) / L[..., None]
    return (B + D) / 2 + h[..., None] * n, L


@pytest.fixture(scope="module")
def five_bar():
    return mechatron.load(FIVE_BAR)


@pytest.fixture(scope="module")
def result(five_bar):
    return workspace(five_bar, "P", grid=(21, 15))


def test_every_cell_is_the_closed_form(result):
    q1, q2 = np.meshgrid(np.linspace(*Q1, 21), np.linspace(*Q2, 15), indexing="ij")
    np.testing.assert_allclose(result.values[0], q1[:, 0], atol=1e-15)
    np.testing.assert_allclose(result.values[1], q2[0], atol=1e-15)
    P, L = closed_form(q1, q2)
    clear = np.abs(L - 2 * B_LEN) > 1e-6  # off the boundary of assembly (a singular position)
    assert clear.all()
    np.testing.assert_array_equal(result.assembled, L <= 2 * B_LEN)
    assert 0 < (~result.assembled).sum() < result.assembled.size  # part of the grid does not assemble
    ok = result.assembled
    np.testing.assert_allclose(result.positions[ok], P[ok], atol=1e-9, rtol=0)
    assert np.isnan(result.positions[~ok]).all()
    assert set(result.reasons) == {tuple(map(int, c)) for c in np.argwhere(~ok)}
    # past the fold (L > 2b) the loops do not close; a cell just past it may be where the branch cannot be followed
    assert all("do not close" in r or "branch cannot be followed" in r for r in result.reasons.values())


def test_the_drawn_branch_is_kept_past_a_fold(five_bar):
    """On the 9 × 9 grid the row q1 = 150° passes a cell next to the fold (L = 0.437 m of 2b = 0.44 m), after which
    a plain continuation along the row lands on the other branch (P below the line B → D); the workspace solves
    those cells again from the row before and keeps the drawn branch everywhere."""
    w = workspace(five_bar, "P", grid=9)
    q1, q2 = np.meshgrid(np.linspace(*Q1, 9), np.linspace(*Q2, 9), indexing="ij")
    P, L = closed_form(q1, q2)
    assert abs(L[6, 3] - 2 * B_LEN) < 0.004
    np.testing.assert_array_equal(w.assembled, L <= 2 * B_LEN)
    np.testing.assert_allclose(w.positions[w.assembled], P[w.assembled], atol=1e-9, rtol=0)


def test_extent_and_text(result):
    q1, q2 = np.meshgrid(np.linspace(*Q1, 21), np.linspace(*Q2, 15), indexing="ij")
    P, L = closed_form(q1, q2)
    P = P[L <= 2 * B_LEN]
    e = result.extent()
    np.testing.assert_allclose(e["x"], [P[:, 0].min(), P[:, 0].max()], atol=1e-9)
    np.testing.assert_allclose(e["y"], [P[:, 1].min(), P[:, 1].max()], atol=1e-9)
    r = np.hypot(P[:, 0], P[:, 1])
    np.testing.assert_allclose(e["reach"], [r.min(), r.max()], atol=1e-9)
    assert e["assembled"] == len(P) and e["cells"] == 21 * 15
    assert e["share"] == pytest.approx(len(P) / (21 * 15), abs=1e-15)
    text = str(result)
    assert f"{len(P)} of 315 positions ({100 * len(P) / 315:.1f} %)" in text
    assert f"reach |r| from the drawing's origin: {r.min():.6g} … {r.max():.6g} m" in text


def test_json_marks_the_cells_not_assembled_null(result):
    data = json.loads(json.dumps(result.as_dict(), allow_nan=False))
    q1, q2 = np.meshgrid(np.linspace(*Q1, 21), np.linspace(*Q2, 15), indexing="ij")
    P, L = closed_form(q1, q2)
    assert data["grid"] == [21, 15]
    assert [i["name"] for i in data["inputs"]] == ["q1", "q2"] and data["inputs"][0]["unit"] == "rad"
    for i in range(21):
        for j in range(15):
            x, y, ok = data["x_m"][i][j], data["y_m"][i][j], data["assembled"][i][j]
            assert ok == bool(L[i, j] <= 2 * B_LEN)
            if ok:
                assert abs(x - P[i, j, 0]) < 1e-9 and abs(y - P[i, j, 1]) < 1e-9
            else:
                assert x is None and y is None
    assert len(data["not_assembled"]) == int((L > 2 * B_LEN).sum())
    cell = data["not_assembled"][0]
    assert cell["q1"] == pytest.approx(q1[cell["i"], cell["j"]]) and cell["q2"] == pytest.approx(q2[cell["i"],
                                                                                                      cell["j"]])


def test_frame_and_plot(result):
    check_result(result)
    frame = result.to_frame()
    assert list(frame.columns) == ["i", "j", "q1", "q2", "x_m", "y_m", "assembled"]
    assert len(frame) == 315 and frame["assembled"].sum() == result.assembled.sum()
    row = frame.iloc[7 * 15 + 4]
    P, _ = closed_form(np.array(row["q1"]), np.array(row["q2"]))
    assert (row["i"], row["j"]) == (7, 4) and row["x_m"] == pytest.approx(P[0], abs=1e-9)
    figure = result.plot()
    region, grid = figure.axes[:2]
    assert (region.get_xlabel(), region.get_ylabel()) == ("x (m)", "y (m)")
    assert (grid.get_xlabel(), grid.get_ylabel()) == ("q1 (deg)", "q2 (deg)")
    assert any("not assembled" in t.get_text() for t in grid.get_legend().get_texts())
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    assert result.plot(ax) is ax.get_figure() and ax.get_xlabel() == "x (m)"


def test_api_refuses_bad_input(five_bar):
    with pytest.raises(InputError, match="no point 'Q'"):
        workspace(five_bar, "Q")
    with pytest.raises(InputError, match="grid must be a whole number >= 2"):
        workspace(five_bar, grid=1)
    with pytest.raises(InputError, match="'q9' is not an input"):
        workspace(five_bar, inputs=("q1", "q9"))
    with pytest.raises(InputError, match="crank_slider has 1 input"):
        workspace(mechatron.load("crank_slider"))


def run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_json_and_csv(capsys, tmp_path):
    table = tmp_path / "ws.csv"
    code, out, err = run(capsys, "linkage", FIVE_BAR, "--workspace", "P", "--grid", "9", "--json", "--csv",
                         str(table))
    assert code == 0, err
    data = json.loads(out)
    q1, q2 = np.meshgrid(np.linspace(*Q1, 9), np.linspace(*Q2, 9), indexing="ij")
    P, L = closed_form(q1, q2)
    assert data["extent"]["assembled"] == int((L <= 2 * B_LEN).sum())
    rows = list(csv.DictReader(table.open(encoding="utf-8")))
    assert len(rows) == 81 and list(rows[0]) == ["i", "j", "q1", "q2", "x_m", "y_m", "assembled"]
    for row in rows:
        i, j = int(row["i"]), int(row["j"])
        if row["assembled"] == "True":
            assert abs(float(row["x_m"]) - P[i, j, 0]) < 1e-9 and abs(float(row["y_m"]) - P[i, j, 1]) < 1e-9
        else:
            assert L[i, j] > 2 * B_LEN and row["x_m"] == ""
    code, out, err = run(capsys, "linkage", FIVE_BAR, "--workspace", "P", "--grid", "5")
    assert code == 0 and "workspace of point P over q1 × q2 (5 × 5 grid)" in out


@pytest.mark.parametrize("argv,piece", [
    ([FIVE_BAR, "--workspace", "P", "--grid", "0"], "argument --grid: must be a whole number >= 2, got 0"),
    ([FIVE_BAR, "--workspace", "P", "--grid", "1e9"], "--grid 1000000000 × 1000000000 gives 1.0e+18 positions"),
    ([FIVE_BAR, "--workspace", "Q"], "--workspace: no point 'Q' in five_bar"),
    ([FIVE_BAR, "--workspace", "P", "--workspace-inputs", "q1"], "--workspace-inputs: expected two different"),
    ([FIVE_BAR, "--grid", "5"], "--grid and --workspace-inputs go with --workspace POINT"),
    (["crank_slider", "--workspace", "C"], "crank_slider has 1 input (q1); a workspace sweeps two"),
    (["front_shovel", "--workspace", "V"], "--workspace: front_shovel has 3 inputs (L1, L2, L3): name the two"),
])
def test_cli_errors_are_one_line_with_status_2(capsys, argv, piece):
    code, out, err = run(capsys, "linkage", *argv)
    assert code == 2
    assert piece in err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err

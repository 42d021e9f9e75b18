"""Bad design files and ``optimize -o`` (issue 33) through the command line: every malformed field of a design file
is one line naming the file and the field, exit 2, the inputs byte-identical; a range that lets links be too short
(or negative) to assemble gives infeasible points with their reason, never a traceback, and a best design whose
reported outputs are those of the crank-slider's closed form; ``-o`` refuses to replace an input and removes its
own earlier design files only.

The crank-slider (``examples/design/my_crank.toml``): with a crank l1 and a rod l2 ≥ l1 the slider's reach is
l1 + l2 and its travel 2 l1 [Egorov, fig. 4.18]; with l2 < l1 the loop does not close at every crank angle.
"""

from __future__ import annotations

import hashlib
import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tomllib

from mechatron.cli import main

DESIGN = Path(__file__).resolve().parent.parent / "examples" / "design"
BASE = (DESIGN / "crank_reach.toml").read_text()
L1, L2 = "l1 = [0.08, 0.12]", "l2 = [0.35, 0.45]"
REQ = "x_travel_m = { min = 0.2 }"

#: name → (the design file's text, the field the one line must name)
CASES = {
    "a NaN bound": (BASE.replace(L1, "l1 = [nan, 0.12]"), "variables.l1[0]"),
    "an infinite bound": (BASE.replace(L1, "l1 = [0.08, inf]"), "variables.l1[1]"),
    "a reversed range": (BASE.replace(L1, "l1 = [0.12, 0.08]"), "variables.l1"),
    "an empty range": (BASE.replace(L1, "l1 = [0.1, 0.1]"), "variables.l1"),
    "a bound of 1e308": (BASE.replace(L1, "l1 = [0.08, 1e308]"), "variables.l1[1]"),
    "three bounds": (BASE.replace(L1, "l1 = [0.08, 0.1, 0.12]"), "variables.l1"),
    "a text bound": (BASE.replace(L1, 'l1 = ["a", 0.12]'), "variables.l1[0]"),
    "an unknown parameter": (BASE.replace(L1, "l9 = [0.08, 0.12]"), "variables.l9"),
    "a number for a range": (BASE.replace(L1, "l1 = 0.1"), "variables.l1"),
    "no bounds": (BASE.replace(L1, "l1 = []"), "variables.l1"),
    "a table without its high": (BASE.replace(L1, "l1 = { low = 0.08 }"), "variables.l1.high"),
    "an empty list of values": (BASE.replace(L1, "l1 = { values = [] }"), "variables.l1.values"),
    "no variables": (BASE.replace(L1, "").replace(L2, ""), "variables"),
    "an unknown objective": (BASE.replace('"reach_m"', '"nope_m"'), "objective.minimize"),
    "a number for an objective": (BASE.replace('"reach_m"', "3"), "objective.minimize"),
    "three objectives": (BASE.replace('"reach_m"', '["reach_m", "x_travel_m", "height_m"]'), "objective"),
    "no objective": (BASE.replace('[objective]\nminimize = "reach_m"\n', ""), "objective"),
    "an unknown requirement": (BASE.replace(REQ, "nope = { min = 0.2 }"), "requirements.nope"),
    "a NaN limit": (BASE.replace(REQ, "x_travel_m = { min = nan }"), "requirements.x_travel_m.min"),
    "an infinite limit": (BASE.replace(REQ, "x_travel_m = { min = inf }"), "requirements.x_travel_m.min"),
    "min above max": (BASE.replace(REQ, "x_travel_m = { min = 0.3, max = 0.2 }"), "requirements.x_travel_m"),
    "a text limit": (BASE.replace(REQ, 'x_travel_m = { min = "a" }'), "requirements.x_travel_m.min"),
    "no limit": (BASE.replace(REQ, "x_travel_m = { }"), "requirements.x_travel_m"),
    "a misspelt limit": (BASE.replace(REQ, "x_travel_m = { least = 0.2 }"), "requirements.x_travel_m.least"),
    "a number for a requirement": (BASE.replace(REQ, "x_travel_m = 0.2"), "requirements.x_travel_m"),
    "an unknown pose": (BASE.replace(REQ, 'x = { output = "reach_m", at = "nowhere", min = 0.2 }'),
                        "requirements.x.at"),
    "no samples": (BASE.replace("samples = 13", "samples = 0"), "analyses.linkage.samples"),
    "negative samples": (BASE.replace("samples = 13", "samples = -5"), "analyses.linkage.samples"),
    "fractional samples": (BASE.replace("samples = 13", "samples = 2.5"), "analyses.linkage.samples"),
    "1e308 samples": (BASE.replace("samples = 13", "samples = 1e308"), "analyses.linkage.samples"),
    "an unknown analysis": (BASE.replace("[analyses.linkage]", "[analyses.nope]"), "analyses.nope"),
    "an unknown option": (BASE.replace("samples = 13", "samples = 13\nbogus = 1"), "analyses.linkage.bogus"),
    "a number for the mechanism": (BASE.replace('"my_crank.toml"', "5"), "mechanism"),
    "an unknown method": (BASE + '\n[solver]\nmethod = "magic"\n', "solver.method"),
    "no evaluations": (BASE + '\n[solver]\nmethod = "global"\nevaluations = 0\n', "solver.evaluations"),
    "fractional evaluations": (BASE + '\n[solver]\nmethod = "global"\nevaluations = 2.5\n', "solver.evaluations"),
    "a population of 2": (BASE + '\n[solver]\nmethod = "global"\npopulation = 2\n', "solver.population"),
    "a negative seed": (BASE + "\n[solver]\nseed = -1\n", "solver.seed"),
    "no iterations": (BASE + "\n[solver]\nmax_iterations = 0\n", "solver.max_iterations"),
    "a negative tolerance": (BASE + "\n[solver]\ntolerance = -1e-8\n", "solver.tolerance"),
    "a NaN tolerance": (BASE + "\n[solver]\ntolerance = nan\n", "solver.tolerance"),
    "a misspelt solver field": (BASE + "\n[solver]\nbogus = 1\n", "solver.bogus"),
    "a start outside the box": (BASE + "\n[start]\nl1 = 0.5\n", "start.l1"),
    "a start of no variable": (BASE + "\n[start]\nl9 = 0.1\n", "start.l9"),
    "a NaN start": (BASE + "\n[start]\nl1 = nan\n", "start.l1"),
    "a pose of no input": (BASE + '\n[[poses]]\nname = "p"\ninputs = { q9 = 2.0 }\n', "poses[1].inputs.q9"),
    "a NaN pose input": (BASE + '\n[[poses]]\nname = "p"\ninputs = { q1 = nan }\n', "poses[1].inputs.q1"),
}


def digest(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    shutil.copy(DESIGN / "my_crank.toml", tmp_path / "my_crank.toml")
    return tmp_path


@pytest.mark.parametrize("case", list(CASES))
def test_a_bad_design_field_is_one_line_naming_it(case, folder, capsys):
    text, field = CASES[case]
    path = folder / "d.toml"
    path.write_text(text)
    before = digest(folder)
    assert main(["optimize", str(path), "-o", str(folder / "out")]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and f"field '{field}'" in lines[0] and "d.toml" in lines[0], lines
    assert "Traceback" not in captured.out + captured.err
    assert digest(folder) == before and not (folder / "out").exists()


def test_a_file_that_is_no_toml_is_one_line(folder, capsys):
    path = folder / "d.toml"
    path.write_text("name = [")
    assert main(["optimize", str(path)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "d.toml: not valid TOML" in lines[0]


def check_best_is_the_closed_form(result: dict) -> None:
    best = result["best"]
    l1, l2 = best["l1"], best["l2"]
    assert l2 >= l1 - 1e-12  # a design that assembles at every crank angle
    assert best["reach_m"] == pytest.approx(l1 + l2, abs=1e-9)
    assert best["x_travel_m"] == pytest.approx(2 * l1, abs=1e-9)
    assert best["x_travel_m"] >= 0.2 - 1e-6


@pytest.mark.parametrize("rod", ["[0.05, 0.45]", "[-0.1, 0.45]"])
def test_links_too_short_to_assemble_are_infeasible_points_with_their_reason(rod, folder, capsys):
    """The rod's range reaches lengths at which the loop cannot close (and, for the second, negative lengths):
    those designs are infeasible with a reason naming the length, the search ends by itself, and the best design's
    outputs are the closed form's at its lengths."""
    import json

    path = folder / "d.toml"
    path.write_text(BASE.replace(L2, f"l2 = {rod}"))
    out = folder / "out"
    assert main(["optimize", str(path), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "Traceback" not in captured.out + captured.err and len(captured.err) < 2000
    result = json.loads((out / "optimum.json").read_text())
    check_best_is_the_closed_form(result)
    designs = pd.read_csv(out / "designs.csv")
    failed = designs[designs["status"] != "ok"]
    assert len(failed) == result["evaluated_failed"] > 0
    assert (failed["l2"] < failed["l1"] + 1e-9).all()  # only designs whose rod is shorter than the crank fail
    # the reason: the drawing that cannot close with that rod, a negative rod, or the first angle it cannot reach
    assert failed["reason"].str.contains(r"length l2 = \|BC\||length l2 must be > 0|cannot be assembled").all()
    assert not failed["feasible"].any()
    assert f"{len(failed)} failed" in captured.out
    ok = designs[designs["status"] == "ok"]
    np.testing.assert_allclose(ok["x_travel_m"], 2 * ok["l1"], atol=1e-9)  # every reported design, not only the best
    np.testing.assert_allclose(ok["reach_m"], ok["l1"] + ok["l2"], atol=1e-9)
    # the written design reads back to the reported lengths
    written = tomllib.loads((out / "design-000.toml").read_text())["points"]
    a, b, c = (np.array(written[k]) for k in "ABC")
    assert math.dist(a, b) == pytest.approx(result["best"]["l1"], abs=1e-9)
    assert math.dist(b, c) == pytest.approx(result["best"]["l2"], abs=1e-9)


def test_o_never_replaces_an_input_named_like_its_output(folder, capsys):
    (folder / "my_crank.toml").rename(folder / "design-000.toml")
    path = folder / "d.toml"
    path.write_text(BASE.replace("my_crank.toml", "design-000.toml"))
    before = digest(folder)
    assert main(["optimize", str(path), "-o", str(folder)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "design-000.toml" in lines[0] and "-o" in lines[0]
    assert digest(folder) == before  # nothing written, nothing replaced


def test_o_removes_its_own_earlier_designs_only(folder, capsys):
    path = folder / "d.toml"
    path.write_text(BASE)
    out = folder / "out"
    assert main(["optimize", str(path), "-o", str(out)]) == 0
    first = (out / "design-000.toml").read_text()
    (out / "design-002.toml").write_text(first.replace("design 0 of", "design 2 of"))  # an earlier front's design
    (out / "design-001.toml").write_text("name = 'mine'\n")  # a user's file that only looks like one
    capsys.readouterr()
    assert main(["optimize", str(path), "-o", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["design-000.toml", "design-001.toml", "designs.csv",
                                                     "optimum.json"]
    assert (out / "design-001.toml").read_text() == "name = 'mine'\n"
    assert (out / "design-000.toml").read_text() == first


def test_o_into_a_folder_that_cannot_be_made_is_one_line(folder, capsys):
    path = folder / "d.toml"
    path.write_text(BASE)
    assert main(["optimize", str(path), "-o", "/proc/mechatron-cannot/out"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "-o" in lines[0] and "/proc/mechatron-cannot/out" in lines[0]


def test_a_sweep_of_a_few_long_steps_stays_on_its_branch():
    """Five samples a quarter turn apart (steps of π/2 rad, 31× the continuation's): every sample on the branch
    of the drawing, x_C = l1 cos θ + √(l2² − l1² sin² θ)."""
    import mechatron
    from mechatron.kinematics import sweeps

    mech = mechatron.load(str(DESIGN / "my_crank.toml"))
    theta = 0.2 + np.linspace(0.0, 2 * np.pi, 5)
    table = sweeps.sweep(mech, {"q1": theta}).table
    l1, l2 = 0.1, 0.4
    np.testing.assert_allclose(table["C_x"], l1 * np.cos(theta) + np.sqrt(l2**2 - (l1 * np.sin(theta)) ** 2),
                               atol=1e-12)


@pytest.mark.parametrize("method", ["ipopt", "global"])
def test_a_box_where_nothing_assembles_ends_with_its_reason(method, folder, capsys):
    """Every rod of the box is shorter than the shortest crank minus nothing the drawing can close with: each
    design fails, the search ends (ipopt after its start's failures, differential evolution after its budget),
    exit 1 with the most common reason on the NOT FEASIBLE line; no best design, no design file written."""
    import json

    path = folder / "d.toml"
    path.write_text(BASE.replace(L2, "l2 = [0.01, 0.05]") + f'\n[solver]\nmethod = "{method}"\nevaluations = 64\n'
                    if method == "global" else BASE.replace(L2, "l2 = [0.01, 0.05]"))
    out = folder / "out"
    assert main(["optimize", str(path), "-o", str(out)]) == 1
    printed = capsys.readouterr().out
    line = next(x for x in printed.splitlines() if x.startswith("NOT FEASIBLE"))
    assert "every design failed, most often:" in line and "length l2 = |BC|" in line
    result = json.loads((out / "optimum.json").read_text())
    assert result["best"] is None and result["evaluated"] == result["evaluated_failed"] > 0
    assert not list(out.glob("design-*.toml"))

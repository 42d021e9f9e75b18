"""The drive-mass objective of ``mechatron optimize`` (``type = "cylinder_mass"``): front-shovel pins and catalog
cylinders for the least total cylinder mass, against references written out here.

- the optimum meets every requirement by the Pinocchio model and every catalog check by the drives module, and is
  no heavier than the DOE's best (the search only accepts lighter steps);
- at the optimum, the holding forces are recomputed by hand (virtual work of the links' weights, bars with their
  centres mid-way, over the cylinder's lever arm), the strokes from the assembled model's pins at the ends of the
  joint ranges, and a brute-force enumeration of the catalog file's rows with the hand formulas p = F/(n π D²/4),
  p = F/(n π (D² − d²)/4), F/n ≤ π² E (π d⁴/64) / L_max² / 3.5 finds no lighter feasible cylinder;
- the derivative of the mass objective equals central finite differences of the Pinocchio model's;
- bad catalog fields fail with one line naming the field.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.kinematics.geometry import point_positions
from mechatron.optimal import optimize
from mechatron.optimal import read_problem as read_spec
from mechatron.optimal.problems.mass import MassProblem
from tests.corpus import assert_clean_error
from tests.protocol import check_result

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "optimize" / "front_shovel_cylinders.toml"
CATALOG = ROOT / "catalogs" / "hydraulic_cylinders.csv"
G, E_STEEL, RELIEF = 9.81, 2.1e11, 32e6
#: link masses (kg) of the front-shovel file, each a bar with its centre mid-way between its joints
LINKS = {"CF": 4500.0, "FQ": 2200.0, "QV": 3800.0}


@pytest.fixture(scope="module")
def solved():
    spec = read_spec(EXAMPLE)
    return spec.model, optimize(spec)


def catalog_rows() -> list[dict]:
    """The catalog file's rows in SI units, read here with the csv module (the columns carry their units)."""
    with open(CATALOG, encoding="utf-8") as f:
        lines = [line for line in f if not line.startswith("#")]
    return [{"key": r["key"], "D": float(r["bore_mm"]) / 1e3, "d": float(r["rod_mm"]) / 1e3,
             "S": float(r["max_stroke_mm"]) / 1e3, "p": float(r["max_pressure_MPa"]) * 1e6, "m": float(r["mass"]),
             "m1": float(r["mass_per_stroke"])} for r in csv.DictReader(lines)]


def hand_forces(problem: MassProblem, x: np.ndarray) -> dict[str, list[float]]:
    """Holding forces (N, > 0 pushing) of L1 and L2 at the special positions by virtual work: F = dPot/dθ / dL/dθ,
    dPot/dθ = g Σ m_i (x_i − x_O) over the links beyond the joint, dL/dθ = u · (ẑ × (P − O)) for the pin P that turns
    about the joint O, u the unit vector from base to eye; the pins from the assembled Pinocchio model."""
    mech = problem.with_strokes(problem.mech.with_parameters(problem.overrides(x)), x)
    out: dict[str, list[float]] = {"L1": [], "L2": []}
    q = None
    for angles in problem.angles_at(x)[1].values():
        q = problem._assemble(mech, x, angles, q)
        P = dict(zip("ABCDEFQV", point_positions(mech, q, *"ABCDEFQV")))
        for name, base, eye, turning, pivot, links in (("L1", "A", "B", "B", "C", "CF FQ QV"),
                                                      ("L2", "D", "E", "E", "F", "FQ QV")):
            O = P[pivot]
            moment = G * sum(LINKS[k] * ((P[k[0]][0] + P[k[1]][0]) / 2 - O[0]) for k in links.split())
            u = (P[eye] - P[base]) / np.linalg.norm(P[eye] - P[base])
            r = P[turning] - O
            out[name].append(moment / (u[0] * -r[1] + u[1] * r[0]))
    return out


def hand_strokes(problem: MassProblem, x: np.ndarray) -> dict[str, tuple[float, float]]:
    """(stroke, L_max) (m) of L1 and L2: the pin distances |AB|, |DE| of the assembled model at both ends of the
    joint ranges."""
    mech = problem.with_strokes(problem.mech.with_parameters(problem.overrides(x)), x)
    ends = []
    for k in (0, 1):
        q = problem._assemble(mech, x, tuple(r[k] for r in problem.angles_at(x)[0]), None)
        A, B, D, E = point_positions(mech, q, *"ABDE")
        ends.append((np.linalg.norm(B - A), np.linalg.norm(E - D)))
    return {c: (abs(ends[1][i] - ends[0][i]), max(ends[1][i], ends[0][i])) for i, c in enumerate(("L1", "L2"))}


def lightest(forces: list[float], stroke: float, longest: float, count: int) -> tuple[str, float]:
    """Brute force over every catalog row: the lightest count (m + m' s) passing rated pressure, push, pull,
    stroke and Euler buckling (pinned-pinned, K = 1, fully extended, safety 3.5)."""
    push, pull = max(max(forces), 0.0) / count, max(-min(forces), 0.0) / count
    feasible = []
    for r in catalog_rows():
        p = min(RELIEF, r["p"])
        piston, annulus = math.pi * r["D"] ** 2 / 4, math.pi * (r["D"] ** 2 - r["d"] ** 2) / 4
        buckling = math.pi**2 * E_STEEL * math.pi * r["d"] ** 4 / 64 / longest**2 / 3.5
        if r["p"] >= RELIEF and push <= piston * p and pull <= annulus * p and stroke <= r["S"] and push <= buckling:
            feasible.append((count * (r["m"] + r["m1"] * stroke), r["key"]))
    mass, key = min(feasible)
    return key, mass


def test_optimum_meets_every_requirement_and_catalog_check(solved):
    problem, result = solved
    assert result.feasible  # every requirement by the Pinocchio model, the catalog checks included
    assert result.beats_doe and result.objective <= result.doe_best["objective"]
    assert result.objective < 0.7 * result.start_objective  # the start misses λ ≤ 1.7 by 6e-5; sized anyway
    choice = {c["cylinder"]: c for c in result.catalog_choice}
    assert set(choice) == {"L1", "L2"} and all(c["feasible"] for c in choice.values())
    assert all(x["pass"] for c in choice.values() for x in c["checks"])  # the drives module's own verdict
    # the search: every step lighter than the one before, the last one the optimum
    masses = [s["mass"] for s in result.descent]
    assert all(b < a for a, b in zip(masses, masses[1:])) and masses[-1] == pytest.approx(result.objective, rel=1e-7)
    assert result.descent[-1]["rows"] == {c: choice[c]["key"] for c in choice}
    names = {r.name: r for r in result.requirements}
    assert names["max_digging_radius_m"].value == pytest.approx(9.06, abs=1e-6)
    assert all(names[f"{c}_min_transmission_angle_deg"].value >= 14 - 1e-6 for c in choice)
    check_result(result)


def test_no_lighter_catalog_cylinder_at_the_optimum(solved):
    problem, result = solved
    forces = hand_forces(problem, result.x)
    pinocchio = problem._split(problem.evaluate(result.x))["forces"]
    for j, c in enumerate(("L1", "L2")):
        assert forces[c] == pytest.approx(pinocchio[j::3], rel=1e-6, abs=1e-3)  # N
    strokes = hand_strokes(problem, result.x)
    total = 0.0
    for c in result.catalog_choice:
        name, count = c["cylinder"], problem.mech.cylinders[c["cylinder"]].count
        stroke, longest = strokes[name]
        assert c["stroke"] == pytest.approx(stroke, rel=1e-9)
        key, mass = lightest(forces[name], stroke, longest, count)
        assert key == c["key"] and mass == pytest.approx(c["mass"], rel=1e-9)
        total += mass
    assert total == pytest.approx(result.objective, rel=1e-9)
    # the boom cylinder's push pressure by hand: the largest holding force over two pistons of its bore
    boom = next(c for c in result.catalog_choice if c["cylinder"] == "L1")
    push = next(x for x in boom["checks"] if x["name"] == "push pressure")
    assert boom["count"] == 2
    assert push["value"] == pytest.approx(max(forces["L1"]) / (2 * math.pi * boom["bore"] ** 2 / 4), rel=1e-6)


def test_mass_derivative_equals_finite_differences_of_pinocchio():
    mech = mechatron.load("front_shovel")
    p = mech.parameter_values()
    names = ("A_x", "B_y", "E_x")
    spec = read_spec(EXAMPLE)
    problem = MassProblem(mech, {n: (p[n] - 0.3, p[n] + 0.3) for n in names}, cylinders=("L1", "L2"), positions=2,
                          catalog=spec.model.catalog, pressure=RELIEF)
    x = problem.start + np.array([0.1, -0.1, 0.05])
    problem.rows = problem.rows_of(problem.values(x))
    import casadi as ca

    _, f, _ = problem.nlp_terms(problem.quantities)
    gradient = np.array(ca.Function("f", [problem.x], [ca.gradient(f, problem.x)])(x)).ravel() / problem.scale
    h = 1e-4
    fd = [(problem.judge(problem.evaluate(x + h * e))[0] - problem.judge(problem.evaluate(x - h * e))[0]) / (2 * h)
          for e in np.eye(3)]
    assert gradient == pytest.approx(fd, rel=1e-6)


def test_page_example_is_the_shipped_file():
    text = (ROOT / "docs" / "optimize_file.md").read_text(encoding="utf-8")
    block = re.search(r"## Complete example: `examples/optimize/front_shovel_cylinders.toml`\n\n```toml\n(.*?)```",
                      text, re.S)
    assert block is not None and block[1] == EXAMPLE.read_text(encoding="utf-8")


def spec_text(**objective: str) -> str:
    """The shipped example with 16 DOE points and the ``[objective]`` fields given (TOML values)."""
    text = EXAMPLE.read_text(encoding="utf-8").replace("points = 256", "points = 16")
    for key, value in objective.items():
        text = re.sub(rf"^{key} = .*\n", "", text, flags=re.M)
        text = text.replace('type = "cylinder_mass"\n', f'type = "cylinder_mass"\n{key} = {value}\n')
    return text


@pytest.mark.parametrize("objective, names", [
    ({"catalog": '"nope.csv"'}, ["s.toml", "objective.catalog", "no such catalog file"]),
    ({"pressure_MPa": "-5.0"}, ["s.toml", "objective.pressure_MPa", "> 0"]),
    ({"pressure_MPa": "40.0"}, ["s.toml", "objective.pressure_MPa", "rated for the relief pressure 40 MPa"]),
])
def test_bad_catalog_fields_fail_with_one_line(tmp_path, capfd, objective, names):
    (tmp_path / "s.toml").write_text(spec_text(**objective))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, names)


def test_bad_catalog_row_names_file_row_and_column(tmp_path, capfd):
    text = CATALOG.read_text(encoding="utf-8").replace("HC40/22-25,example,40,", "HC40/22-25,example,-40,")
    (tmp_path / "c.csv").write_text(text)
    (tmp_path / "s.toml").write_text(spec_text(catalog='"c.csv"'))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, ["c.csv", "bore_mm", "> 0"])


def test_catalog_without_a_feasible_cylinder_fails_with_one_line(tmp_path, capfd):
    rows = CATALOG.read_text(encoding="utf-8").splitlines()
    (tmp_path / "small.csv").write_text("\n".join(rows[:2] + [r for r in rows if r.startswith("HC40/22-32")]) + "\n")
    (tmp_path / "s.toml").write_text(spec_text(catalog='"small.csv"'))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path,
                       ["s.toml", "objective.catalog", "no catalog cylinders pass every check"])

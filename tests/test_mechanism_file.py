r"""Mechanism files (docs/mechanism_file.md), the acceptance of issue 11:

- the four-bar written from the documentation, examples/data/four_bar.toml, against Freudenstein's equation
  (output angle, angular velocity and acceleration, transmission angle) at many crank angles, on both assembly
  branches; its drawing, given about 2 mm off, closes to the exact position, and a tolerance below the move refuses
  it naming the constraint;
- every kind of bad file gives one line naming the file and the field (an InputError; exit status 2 on the command
  line);
- the parameters: ``--set a=0.12`` gives Freudenstein's motion of the new crank, and a tolerance study on the
  four-bar agrees with central differences of the rebuilt model and with the closed form;
- files by name: ./robots, then MECHATRON_PATH, then the shipped ones, and ``mechatron list`` says which.

The closed form. Frame AD on the x axis, A at the origin, crank AB = a at θ2, coupler BC = b, rocker DC = c at θ4,
frame AD = d. The loop |C − B| = b with C = D + c (cos θ4, sin θ4) gives Freudenstein's equation

    f(θ2, θ4) = K1 cos θ4 − K2 cos θ2 + K3 − cos(θ2 − θ4) = 0,  K1 = d/a, K2 = d/c, K3 = (a² − b² + c² + d²)/(2ac),

solved with t = tan(θ4/2): A t² + B t + C = 0, A = cos θ2 − K1 − K2 cos θ2 + K3, B = −2 sin θ2,
C = K1 − (K2 + 1) cos θ2 + K3, θ4 = 2 atan((−B + σ √(B² − 4AC)) / 2A); σ = −1 is the branch of the drawing (C above
AD), σ = +1 the crossed one. Differentiating f along the motion: θ4' = −f₂/f₄ and
θ4'' = −(f₂₂ + 2 f₂₄ θ4' + f₄₄ θ4'²)/f₄ with f₂ = K2 sin θ2 + sin(θ2 − θ4), f₄ = −K1 sin θ4 − sin(θ2 − θ4),
f₂₂ = K2 cos θ2 + cos(θ2 − θ4), f₂₄ = −cos(θ2 − θ4), f₄₄ = −K1 cos θ4 + cos(θ2 − θ4); at a constant crank speed ω2,
ω4 = θ4' ω2 and ε4 = θ4'' ω2². The transmission angle μ between BC and DC follows from the triangles ABD and BCD:
cos μ = (b² + c² − a² − d² + 2ad cos θ2)/(2bc); mechatron reports the acute angle between the lines, min(μ, π − μ).
"""

from __future__ import annotations

import json
import math
import os
import re
import shlex
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.errors import InputError
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble
from mechatron.model.linkage import build_linkage
from mechatron.model.linkage_file import read_linkage_file
from tests.boom import boom
from tests.corpus import cli_error

ROOT = Path(__file__).resolve().parent.parent
FOUR_BAR = ROOT / "examples" / "data" / "four_bar.toml"
TOLERANCES = ROOT / "examples" / "data" / "tolerances_four_bar.csv"
LENGTHS = {"a": 0.100, "b": 0.300, "c": 0.250, "d": 0.300}  # the file's [lengths], m
RATE = 10.0  # the file's input_rates: rad/s
ARCMIN = math.pi / 10800


# ------------------------------------------------------------------------------------------------ closed form
def freudenstein(theta2: float, a: float, b: float, c: float, d: float, sigma: int = -1
                 ) -> tuple[float, float, float, float]:
    """θ4, dθ4/dθ2, d²θ4/dθ2² (rad) and the acute transmission angle (rad) of the four-bar (module docstring)."""
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    A = math.cos(theta2) - K1 - K2 * math.cos(theta2) + K3
    B = -2 * math.sin(theta2)
    C = K1 - (K2 + 1) * math.cos(theta2) + K3
    theta4 = 2 * math.atan2(-B + sigma * math.sqrt(B * B - 4 * A * C), 2 * A)
    s = theta2 - theta4
    f2 = K2 * math.sin(theta2) + math.sin(s)
    f4 = -K1 * math.sin(theta4) - math.sin(s)
    f22, f24, f44 = K2 * math.cos(theta2) + math.cos(s), -math.cos(s), -K1 * math.cos(theta4) + math.cos(s)
    first = -f2 / f4
    second = -(f22 + 2 * f24 * first + f44 * first**2) / f4
    mu = math.acos((b * b + c * c - a * a - d * d + 2 * a * d * math.cos(theta2)) / (2 * b * c))
    return theta4, first, second, min(mu, math.pi - mu)


def output_point(theta2: float, a: float, b: float, c: float, d: float, D_y: float = 0.0) -> np.ndarray:
    """C (m) in closed form; D_y raises the drawn bearing D = (0.3, D_y) m, which turns the frame line AD by
    φ = atan2(D_y, 0.3) (|AD| stays d): Freudenstein's equation in the frame's axes at θ2 − φ, turned back by φ."""
    phi = math.atan2(D_y, 0.3)
    theta4 = freudenstein(theta2 - phi, a, b, c, d)[0] + phi
    return np.array([d * math.cos(phi) + c * math.cos(theta4), d * math.sin(phi) + c * math.sin(theta4)])


def angle_difference(x, y):
    return np.remainder(np.asarray(x) - np.asarray(y) + math.pi, 2 * math.pi) - math.pi


def test_closed_form_against_its_own_finite_differences():
    """The derivatives of :func:`freudenstein` are those of its angle (central differences, h = 1e-5)."""
    h = 1e-5
    for theta2 in np.radians([0, 37, 90, 181, 275, 333]):
        _, first, second, _ = freudenstein(theta2, **LENGTHS)
        minus, plus = freudenstein(theta2 - h, **LENGTHS)[0], freudenstein(theta2 + h, **LENGTHS)[0]
        assert angle_difference(plus, minus) / (2 * h) == pytest.approx(first, abs=1e-8)
        d_minus, d_plus = freudenstein(theta2 - h, **LENGTHS)[1], freudenstein(theta2 + h, **LENGTHS)[1]
        assert (d_plus - d_minus) / (2 * h) == pytest.approx(second, abs=1e-7)


# ------------------------------------------------------------------------------------ the four-bar of the docs
@pytest.fixture(scope="module")
def four_bar() -> mechatron.Mechanism:
    return mechatron.load(FOUR_BAR)


def check_sweep(table: pd.DataFrame, lengths: dict[str, float], sigma: int = -1) -> None:
    expected = np.array([freudenstein(t, **lengths, sigma=sigma) for t in table["q1"]])
    assert np.abs(angle_difference(table["q_q3"], expected[:, 0])).max() < 1e-9
    assert np.allclose(table["v_q3"], expected[:, 1] * RATE, rtol=0, atol=1e-8)
    assert np.allclose(table["a_q3"], expected[:, 2] * RATE**2, rtol=0, atol=1e-6)
    assert np.allclose(table["mu"], expected[:, 3], rtol=0, atol=1e-9)


def test_four_bar_follows_freudenstein_over_a_whole_turn(four_bar):
    result = mechatron.sweep(four_bar, samples=145, links=["rocker"])
    table = result.table
    assert len(table) == 145 and result.failures.empty
    assert table["q1"].iloc[-1] - table["q1"].iloc[0] == pytest.approx(2 * math.pi)
    check_sweep(table, LENGTHS)
    # the rocker is on the ground: its angle, speed and acceleration are q3's
    assert np.allclose(table["rocker_omega"], table["v_q3"]) and np.allclose(table["rocker_epsilon"], table["a_q3"])
    # and the output point C = D + c (cos θ4, sin θ4)
    theta4 = table["q_q3"].to_numpy()
    assert np.allclose(table["C_x"], 0.3 + 0.25 * np.cos(theta4), atol=1e-12)
    assert np.allclose(table["C_y"], 0.25 * np.sin(theta4), atol=1e-12)
    # the design check of the file: μ ≥ 40°, and the smallest μ is at θ2 = 0: cos μ = (b² + c² − (d − a)²)/(2bc)
    mu_min = math.acos((0.3**2 + 0.25**2 - 0.2**2) / (2 * 0.3 * 0.25))
    assert table["mu"].min() == pytest.approx(mu_min, abs=1e-9) and math.degrees(mu_min) > 40
    check = result.check_measures()[0]
    assert check["required_min"] == pytest.approx(math.radians(40)) and check["pass"] is True


def test_crossed_branch_follows_the_other_root(four_bar):
    theta4 = freudenstein(math.pi / 2, **LENGTHS, sigma=+1)[0]
    assert angle_difference(four_bar.branches["crossed"][2], theta4) == pytest.approx(0, abs=1e-12)  # not −136°
    assert math.degrees(math.remainder(theta4, 2 * math.pi)) == pytest.approx(-136, abs=0.5)
    table = mechatron.sweep(four_bar, samples=73, guess=four_bar.branches["crossed"]).table
    check_sweep(table, LENGTHS, sigma=+1)


def test_masses_of_the_file_give_the_reduced_model_of_the_kinetic_energy(four_bar):
    """The file's masses as the page says (a bar: centre in the middle, I = m L²/12; the coupler's centre M,
    0.009 kg·m² about it): J = Σ (m v_G² + I ω²)/ω2² [Egorov, 6.5] and M = −g Σ m ẏ_G/ω2 (gravity's power over
    the crank rate) [Egorov, 6.20], with the velocities of the closed form."""
    from mechatron.dynamics.reduced import reduced_inertia, reduced_moment

    a, b, c, d = LENGTHS.values()
    for theta2 in np.radians([0, 55, 90, 180, 260, 315]):
        theta4, first, _, _ = freudenstein(theta2, **LENGTHS)
        e2, e4 = np.array([-math.sin(theta2), math.cos(theta2)]), np.array([-math.sin(theta4), math.cos(theta4)])
        B, C = a * np.array([math.cos(theta2), math.sin(theta2)]), output_point(theta2, **LENGTHS)
        vB, vC = a * e2, c * first * e4  # per unit crank rate
        theta3 = math.atan2(*(C - B)[::-1])
        omega3 = (vC - vB) @ np.array([-math.sin(theta3), math.cos(theta3)]) / b
        vM = (vB + vC) / 2
        J = 0.5 * a**2 / 3 + 1.2 * vM @ vM + 0.009 * omega3**2 + 0.8 * c**2 / 3 * first**2
        M = -9.81 * (0.5 * vB[1] / 2 + 1.2 * vM[1] + 0.8 * vC[1] / 2)
        q = assemble(four_bar, {"q1": theta2}, guess=four_bar.reference_q)
        assert reduced_inertia(four_bar, q, "q1") == pytest.approx(J, abs=1e-12)
        assert reduced_moment(four_bar, q, "q1") == pytest.approx(M, abs=1e-11)


def test_drawing_given_two_mm_off_closes_to_the_exact_position(four_bar):
    """The file draws B and C about 2 mm off; the closed drawing is the exact position at the drawn crank angle
    (90°), and the note gives each pin's move, computed here from the closed form."""
    spec = read_linkage_file(FOUR_BAR)
    drawn = spec.drawing()
    exact_B = np.array([0.0, 0.1])
    exact_C = output_point(math.pi / 2, **LENGTHS)
    move_B, move_C = np.linalg.norm(drawn["B"] - exact_B), np.linalg.norm(drawn["C"] - exact_C)
    assert 1.9e-3 < move_B < 2.1e-3 and 1.9e-3 < move_C < 2.1e-3  # the drawing is about 2 mm off
    q = four_bar.reference_q
    assert q[0] == pytest.approx(math.pi / 2, abs=1e-12)  # the input keeps its drawn angle
    for point in "AD":  # the points that need not move keep their drawn coordinates exactly
        assert [four_bar.parameters[f"{point}_{axis}"].value for axis in "xy"] == list(drawn[point])
    assert frame_placement(four_bar, q, "B").translation[:2] == pytest.approx(exact_B, abs=1e-12)
    assert frame_placement(four_bar, q, "C").translation[:2] == pytest.approx(exact_C, abs=1e-12)
    assert frame_placement(four_bar, q, "M").translation[:2] == pytest.approx((exact_B + exact_C) / 2, abs=1e-12)
    moves = f"C by {move_C * 1e3:.3g} mm, B by {move_B * 1e3:.3g} mm"
    assert four_bar.notes == [f"the drawing was closed by moving {moves}"]
    # any other drawing 2 mm off closes to the same position
    for angle in np.radians([0, 45, 160, 250]):
        shift = 2e-3 * np.array([math.cos(angle), math.sin(angle)])
        other = build_linkage(spec.with_positions({"C": drawn["C"] + shift, "M": drawn["C"]}))
        assert frame_placement(other, other.reference_q, "C").translation[:2] == pytest.approx(exact_C, abs=1e-12)


def test_tolerance_below_the_move_refuses_the_drawing_naming_the_constraint(tmp_path, capsys):
    """At 1 mm the drawing is refused: the worst constraint of the drawing is |AB| = a, drawn 102 mm (2 mm off),
    and closing it moves C by |C_drawn − C_exact|."""
    spec = read_linkage_file(FOUR_BAR)
    move_C = np.linalg.norm(spec.drawing()["C"] - output_point(math.pi / 2, **LENGTHS))
    with pytest.raises(InputError) as caught:
        build_linkage(replace(spec, tolerance=1e-3))
    error = caught.value
    assert error.file == str(FOUR_BAR) and error.field == "points"
    assert error.message == (f"the loops do not close within 1 mm: closing length a = |AB| (off by 2 mm in the "
                             f"drawing) moves C by {move_C * 1e3:.4g} mm")
    build_linkage(replace(spec, tolerance=2.1e-3))  # just above the largest move: accepted
    bad = tmp_path / "tight.toml"
    bad.write_text(FOUR_BAR.read_text(encoding="utf-8").replace("tolerance_mm = 5 ", "tolerance_mm = 1 "))
    code, err = cli_error(capsys, "show", str(bad))
    assert code == 2 and err.startswith(f"mechatron: error: {bad}: field 'points': the loops do not close within 1 mm")


# -------------------------------------------------------------------------------------- the page's commands
PAGE = (ROOT / "docs" / "mechanism_file.md").read_text(encoding="utf-8")
COMMANDS = [line for block in re.findall(r"```sh\n(.*?)```", PAGE, re.S) for line in block.splitlines()]


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_of_the_page_runs(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # the files they write
    program, *argv = shlex.split(command)
    assert program == "mechatron"
    code = main([arg.replace("examples/data/", f"{ROOT}/examples/data/") for arg in argv])
    out, err = capsys.readouterr()
    assert code == 0 and out, err
    for written in re.findall(r"--(?:plot|plans|csv) (\S+)", command):
        assert (tmp_path / written).stat().st_size > 0


@pytest.mark.parametrize("block", re.findall(r"```python\n(.*?)```", PAGE, re.S))
def test_the_python_of_the_page_runs(block, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    exec(compile(block, "mechanism_file.md", "exec"), {})
    assert capsys.readouterr().out


# ------------------------------------------------------------------------------------------------- bad files
BOOM = boom()  # a boom lifted by a cylinder 0.5 m long in the drawing

ON_CURVE = """name = "on_curve"
actuated = ["q1"]
[points]
A = [0.0, 0.0]
B = [0.3, 0.4]
P = [0.8, 0.4]
[[bodies]]
name = "ground"
points = ["A"]
[[bodies]]
name = "arm"
points = ["A", "B"]
[[bodies]]
name = "forearm"
points = ["B", "P"]
[[joints]]
type = "revolute"
body = "arm"
at = "A"
coordinate = "q1"
[[joints]]
type = "revolute"
body = "forearm"
at = "B"
[[closures]]
type = "curve"
point = "P"
x = [0.0, 0.4, 0.8, 1.2]
y = [0.464, 0.416, 0.4, 0.416]
"""  # a two-link arm whose tip P runs on the parabola y = 0.4 + 0.1 (x − 0.8)²

ROCKER_JOINT = 'body = "rocker"\nat = "D"\ncoordinate = "q3"\n'
BAD_FILES = {  # name: (base file, text(s) replaced, replacement(s), field, words of the message)
    "unknown point": ("four_bar", 'points = ["B", "C", "M"]', 'points = ["B", "X", "M"]', "bodies[3].points",
                      "unknown point 'X'"),
    "unknown body of a joint": ("four_bar", 'body = "rocker"', 'body = "rockr"', "joints[3].body",
                                "unknown body 'rockr'"),
    "unknown body of a pin": ("four_bar", '["coupler", "rocker"]', '["coupler", "rockr"]', "closures[1].bodies",
                              "unknown body 'rockr'"),
    "unknown parent": ("four_bar", ROCKER_JOINT, ROCKER_JOINT + 'parent = "frame"\n', "joints[3].parent",
                       "unknown parent body 'frame'"),
    "body not connected": ("four_bar", '[[joints]]\ntype = "revolute"\n' + ROCKER_JOINT + 'toward = "C"', "#",
                           "bodies[4]",
                           "body rocker has no joint: it is not connected to the tree"),
    "bodies not connected to the ground": ("four_bar", ('body = "coupler"\nat = "B"', ROCKER_JOINT),
                                           ('body = "coupler"\nat = "C"\nparent = "rocker"',
                                            ROCKER_JOINT.replace('"D"', '"C"\nparent = "coupler"')), "joints[2]",
                                           "bodies coupler, rocker are not connected to the ground"),
    "pin joining a body to itself": ("four_bar", '["coupler", "rocker"]', '["coupler", "coupler"]',
                                     "closures[1].bodies", "pin C joins body coupler to itself"),
    "duplicate body": ("four_bar", 'name = "rocker"', 'name = "coupler"', "bodies",
                       "body 'coupler' is defined twice"),
    "duplicate point": ("four_bar", "[points_mm]", "[points]\nD = [0.3, 0.0]\n\n[points_mm]", "points",
                        "point 'D' is defined twice"),
    "duplicate coordinate": ("four_bar", 'coordinate = "q3"', 'coordinate = "q1"', "joints[3].coordinate",
                             "coordinate 'q1' is defined twice"),
    "duplicate measure": ("four_bar", "\n[lengths]", '\n[[measures]]\ntype = "distance"\nname = "mu"\n'
                          'points = ["A", "C"]\n\n[lengths]', "measures", "measure 'mu' is defined twice"),
    "loop not closing": ("four_bar", "tolerance_mm = 5 ", "tolerance_mm = 1 ", "points",
                         "the loops do not close within 1 mm"),
    "cylinder L_min = L_max": ("boom", "stroke = [0.4, 0.7]", "stroke_mm = [700, 700]", "joints[2].stroke",
                               "the stroke needs 0 < L_min < L_max, got [0.7, 0.7] m"),
    "cylinder L_min > L_max": ("boom", "stroke = [0.4, 0.7]", "stroke = [0.7, 0.4]", "joints[2].stroke",
                               "the stroke needs 0 < L_min < L_max"),
    "eye outside its stroke": ("boom", "stroke = [0.4, 0.7]", "stroke = [0.55, 0.8]", "joints[2].stroke",
                               "its eye E is 500 mm from its base B0 in the drawing, outside its stroke [550, 800] mm"),
    "negative mass": ("four_bar", "mass = 0.8", "mass = -0.8", "bodies[4].mass", "mass must be >= 0 kg, got -0.8"),
    "negative inertia": ("four_bar", "inertia = 0.009", "inertia = -0.009", "bodies[3].inertia",
                         "inertia must be >= 0 kg·m², got -0.009"),
    "inertia without mass": ("four_bar", "mass = 1.2\n", "", "bodies[3].inertia",
                             "an inertia of 0.009 kg·m² without mass"),
    "two inputs for mobility 1": ("four_bar", 'actuated = ["q1"]', 'actuated = ["q1", "q3"]', "actuated",
                                  "2 actuated input(s) (q1, q3) for a mechanism of mobility 1"),
    "no input for mobility 1": ("four_bar", 'actuated = ["q1"]', "actuated = []", "actuated",
                                "0 actuated input(s) for a mechanism of mobility 1"),
    "cylinder and crank for mobility 1": ("boom", 'actuated = ["lift"]', 'actuated = ["lift", "boom_angle"]',
                                          "actuated", "for a mechanism of mobility 1"),
    "curve not monotonic": ("on_curve", "x = [0.0, 0.4, 0.8, 1.2]", "x = [0.0, 0.8, 0.4, 1.2]", "closures[1].x",
                            "x must increase (x[3] = 0.4 after 0.8)"),
}
BASES = {"four_bar": FOUR_BAR.read_text(encoding="utf-8"), "boom": BOOM, "on_curve": ON_CURVE}


@pytest.mark.parametrize("base", sorted(BASES))
def test_the_bases_of_the_bad_files_load(base, tmp_path):
    path = tmp_path / f"{base}.toml"
    path.write_text(BASES[base], encoding="utf-8")
    mech = mechatron.load(path)
    assert mech.mobility() == len(mech.actuated) == 1


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_file_gives_one_line_naming_the_file_and_the_field(case, tmp_path, capsys):
    base, old, new, field, words = BAD_FILES[case]
    text = BASES[base]
    for before, after in zip(*((old, new) if isinstance(old, tuple) else ((old,), (new,)))):
        assert text.count(before) == 1, f"{case}: the base file changed"
        text = text.replace(before, after)
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as caught:
        mechatron.load(path)
    assert (caught.value.file, caught.value.field) == (str(path), field)
    assert words in caught.value.message
    code, err = cli_error(capsys, "show", str(path))
    assert code == 2 and err == f"mechatron: error: {path}: field '{field}': {caught.value.message}"


def test_a_toml_that_is_neither_a_robot_nor_a_mechanism_file(tmp_path, capsys):
    path = tmp_path / "other.toml"
    path.write_text('name = "other"\n[[things]]\nsize = 1\n', encoding="utf-8")
    code, err = cli_error(capsys, "show", str(path))
    assert code == 2 and err.startswith(f"mechatron: error: {path}: neither a robot file")
    assert "docs/mechanism_file.md" in err


def test_point_tables_take_their_units(tmp_path):
    """In [points_mm] a point's ``at`` is in mm, ``at_cm`` in cm; in [points] ``at`` is in m."""
    text = BASES["four_bar"].replace("C = [262, 249]", "C = { at_cm = [26.2, 24.9] }")
    path = tmp_path / "units.toml"
    text = text.replace('points = ["A", "D"]\n', 'points = ["A", "D", "E"]\n', 1)  # E: a point of the frame, in m
    path.write_text(text.replace("[points_mm]", "[points]\nE = { at = [0.1, 0.2] }\n\n[points_mm]"))
    drawing = read_linkage_file(path).drawing()
    assert drawing["C"] == pytest.approx([0.262, 0.249]) and drawing["E"] == pytest.approx([0.1, 0.2])
    assert drawing["B"] == pytest.approx([0.0, 0.102])


# ------------------------------------------------------------------------------------------------ parameters
def test_set_crank_length_gives_freudenstein_of_the_new_crank(tmp_path, capsys):
    table_path = tmp_path / "sweep.csv"
    code = main(["linkage", str(FOUR_BAR), "--set", "a=0.12", "--samples", "72", "--csv", str(table_path)])
    capsys.readouterr()
    assert code == 0
    table = pd.read_csv(table_path)
    assert len(table) == 72
    check_sweep(table, {**LENGTHS, "a": 0.12})
    mech = mechatron.load(FOUR_BAR, a=0.12)  # the same through the API
    assert mech.parameters["a"].value == pytest.approx(0.12)
    assert frame_placement(mech, mech.reference_q, "B").translation[:2] == pytest.approx([0.0, 0.12], abs=1e-12)


POSES = np.radians([[90.0], [0.0], [140.0], [250.0], [330.0]])  # crank angles q1


@pytest.fixture(scope="module")
def given_study(four_bar):
    return mechatron.tolerance_study(four_bar, TOLERANCES, POSES, methods=["given"], frame="C")


def rebuilt_output(mech: mechatron.Mechanism, q1: float, guess: np.ndarray) -> np.ndarray:
    return frame_placement(mech, assemble(mech, {"q1": q1}, guess=guess), "C").translation


def test_tolerance_sensitivities_are_central_differences_of_the_rebuilt_model(four_bar, given_study):
    """∂C/∂p of the study against (C(p + h) − C(p − h))/2h of the model rebuilt through the file, at the same crank
    angle and on the same branch, and against the closed form's central differences."""
    h = 1e-6
    nominal = {name: four_bar.parameters[name].value for name in (*LENGTHS, "D_y")}
    sensitivities = given_study.sensitivities
    for k, (q1,) in enumerate(POSES):
        guess = sensitivities.q[k]
        for name, value in nominal.items():
            plus = rebuilt_output(four_bar.with_parameters({name: value + h}), q1, guess)
            minus = rebuilt_output(four_bar.with_parameters({name: value - h}), q1, guess)
            column = sensitivities.column(name)[k]
            assert column == pytest.approx((plus - minus) / (2 * h), abs=2e-6), (name, q1)
            closed = {**nominal, name: value + h}, {**nominal, name: value - h}
            expected = (output_point(q1, **closed[0]) - output_point(q1, **closed[1])) / (2 * h)
            assert column[:2] == pytest.approx(expected, abs=2e-6), (name, q1)
        # the crank angle: ∂C/∂θ2 = c θ4' (−sin θ4, cos θ4)
        theta4, first, _, _ = freudenstein(q1, **LENGTHS)
        expected = 0.25 * first * np.array([-math.sin(theta4), math.cos(theta4), 0.0])
        assert sensitivities.column("q1")[k] == pytest.approx(expected, abs=1e-9)


def test_given_errors_move_the_output_as_the_closed_form_says(four_bar, given_study):
    """The file's errors (a +0.02, b −0.03, c +0.04, d +0.05, D_y −0.02 mm, q1 +2′): to first order
    Σ ∂C/∂e·Δe [Egorov, 8.4], the closed form's derivative along the errors; the full model's |Δr| is the closed
    form's |C(p + Δp, θ2 + Δθ2) − C(p, θ2)| for the lengths and the crank angle (the study's model is exact in them;
    D_y, which turns the frame, it takes to first order)."""
    from mechatron.accuracy.sources import read_tolerances

    errors = {"a": 0.02e-3, "b": -0.03e-3, "c": 0.04e-3, "d": 0.05e-3, "D_y": -0.02e-3}

    def moved(q1: float, t: float, names) -> np.ndarray:
        return output_point(q1 + t * 2 * ARCMIN, **{n: LENGTHS.get(n, 0.0) + t * errors[n] for n in names})

    h = 1e-2  # of the errors: a step of 0.5 µm at most
    for k, (q1,) in enumerate(POSES):
        row = given_study.poses.iloc[k]
        first_order = (moved(q1, h, errors) - moved(q1, -h, errors)) / (2 * h)
        assert [row["dx_given"], row["dy_given"]] == pytest.approx(first_order, abs=1e-13)
    sources = [s for s in read_tolerances(TOLERANCES, four_bar, "error") if s.name != "D_y"]
    exact = mechatron.tolerance_study(four_bar, sources, POSES, methods=["given"], frame="C").poses
    lengths = [n for n in errors if n != "D_y"]
    for k, (q1,) in enumerate(POSES):
        change = np.linalg.norm(moved(q1, 1.0, lengths) - moved(q1, 0.0, lengths))
        assert exact["dr_nonlinear_given"].iloc[k] == pytest.approx(change, abs=1e-14)
        assert exact["dr_given"].iloc[k] != pytest.approx(change, abs=1e-11)  # the first order is not exact


def test_tolerances_of_the_sample(four_bar):
    """a: IT8 of 100 mm is a 54 µm zone [ISO 286-1], t = 27 µm; q1: 3′ uniform; d uniform."""
    from mechatron.accuracy.sources import read_tolerances

    sources = {s.name: s for s in read_tolerances(TOLERANCES, four_bar)}
    assert list(sources) == ["a", "b", "c", "d", "D_y", "q1"]
    assert sources["a"].tolerance == pytest.approx(27e-6) and sources["b"].tolerance == pytest.approx(50e-6)
    assert sources["d"].distribution == "uniform" and sources["q1"].tolerance == pytest.approx(3 * ARCMIN)
    assert sources["q1"].kind == "coordinate" and sources["D_y"].kind == "parameter"


# ------------------------------------------------------------------------------------------ files by name
@pytest.fixture
def user_folders(tmp_path, monkeypatch):
    """A working directory with ./robots/my_linkage.toml (crank a = 101 mm) and a MECHATRON_PATH folder with
    my_linkage.toml (a = 100 mm), shop_linkage.toml and crank_slider.toml (a shipped file's name)."""
    work, library = tmp_path / "work", tmp_path / "library"
    (work / "robots").mkdir(parents=True)
    library.mkdir()
    text = FOUR_BAR.read_text(encoding="utf-8")
    (work / "robots" / "my_linkage.toml").write_text(text.replace("value_mm = 100", "value_mm = 101"))
    for name in ("my_linkage", "shop_linkage", "crank_slider"):
        shutil.copy(FOUR_BAR, library / f"{name}.toml")
    monkeypatch.chdir(work)
    monkeypatch.setenv("MECHATRON_PATH", os.pathsep.join([str(tmp_path / "missing"), str(library)]))
    return work, library


def test_files_by_name_search_robots_then_mechatron_path_then_shipped(user_folders, capsys):
    work, library = user_folders
    assert mechatron.load("my_linkage").parameters["a"].value == pytest.approx(0.101)  # ./robots wins
    assert mechatron.load("shop_linkage").parameters["a"].value == pytest.approx(0.10)
    assert mechatron.load("crank_slider").source == str(library / "crank_slider.toml")  # before the shipped one
    assert mechatron.load("scara").source.endswith(os.path.join("robots", "scara.toml"))
    code = main(["show", "my_linkage"])
    out, _ = capsys.readouterr()
    assert code == 0 and f"from {work / 'robots' / 'my_linkage.toml'}" in out and "a=0.101" in out
    code = main(["show", "shop_linkage", "--json"])
    assert code == 0 and json.loads(capsys.readouterr().out)["mobility"] == 1


def test_list_says_where_each_name_comes_from(user_folders, capsys):
    work, library = user_folders
    code = main(["list", "--json"])
    entries = {e["name"]: e for e in json.loads(capsys.readouterr().out)}
    assert code == 0
    assert (entries["my_linkage"]["origin"], entries["my_linkage"]["path"]) == \
        ("./robots", str(work / "robots" / "my_linkage.toml"))
    assert entries["shop_linkage"]["origin"] == "MECHATRON_PATH"
    assert entries["crank_slider"] == {"name": "crank_slider", "origin": "MECHATRON_PATH",
                                       "path": str(library / "crank_slider.toml")}
    assert entries["puma560"]["origin"] == "shipped" and entries["seven_bar"]["origin"] == "shipped"
    assert list(entries) == mechatron.available_robots()
    code = main(["list"])
    out = capsys.readouterr().out
    assert code == 0
    rows = {line.split()[0]: line.split()[2] for line in out.splitlines()[1:] if re.match(r"\w+ +[\d?]+ ", line)}
    assert rows["my_linkage"] == "./robots" and rows["shop_linkage"] == "MECHATRON_PATH"
    assert rows["scara"] == "shipped" and rows["grab"] == "shipped"
    assert f"./robots        {work / 'robots'}  (1 .toml file(s))" in out
    assert f"MECHATRON_PATH  {library.parent / 'missing'}  (not there)" in out


def test_the_shipped_folder_stays_shipped_when_it_is_also_the_working_directorys(tmp_path, monkeypatch):
    """Working in a source checkout, ./robots is the shipped folder: its files are `shipped`, and a MECHATRON_PATH
    file of the same name still comes first."""
    from mechatron.io.data import data_dir
    from mechatron.library import robot_origins

    shipped = data_dir("robots")
    monkeypatch.chdir(shipped.parent)
    shutil.copy(FOUR_BAR, tmp_path / "scara.toml")
    monkeypatch.setenv("MECHATRON_PATH", str(tmp_path))
    origins = robot_origins()
    assert origins["puma560"] == ("shipped", shipped / "puma560.toml")
    assert origins["scara"] == ("MECHATRON_PATH", tmp_path / "scara.toml")
    assert mechatron.load("scara").joint_names == ["q1", "q2", "q3"]  # the four-bar, not the SCARA


def test_a_plate_body_has_the_centre_and_inertia_of_its_polygon(tmp_path):
    """shape = "plate": the coupler as a uniform triangle B, C, E: its centre at the centroid (the mean of the
    corners) and I = m (a² + b² + c²)/36 about it, the closed form of a triangular lamina of sides a, b, c."""
    text = FOUR_BAR.read_text(encoding="utf-8")
    assert "[points_mm]" in text
    plate = text.replace("[points_mm]", "[points_mm]\nE = [150, 320]", 1)
    start = plate.index('name = "coupler"')
    end = plate.index("[[bodies]]", start)
    plate = plate[:start] + 'name = "coupler"\npoints = ["B", "C", "M", "E"]\nmass = 1.2\nshape = "plate"\n' + \
        'draw = ["B", "C", "E", "B"]\n\n' + plate[end:]
    path = tmp_path / "plate_four_bar.toml"
    path.write_text(plate.replace('points = ["B", "C", "M", "E"]', 'points = ["B", "C", "E"]').replace(
        'M = { between = ["B", "C"], fraction = 0.5 }', ""), encoding="utf-8")
    mech = mechatron.load(path)
    q = mech.reference_q
    corners = np.array([mechatron.frame_placement(mech, q, p).translation[:2] for p in ("B", "C", "E")])
    joint = mech.model.getJointId("coupler_angle") if mech.model.existJointName("coupler_angle") else \
        next(j for j in range(1, mech.model.njoints) if mech.link_names[j - 1] == "coupler")
    inertia = mech.model.inertias[joint]
    centre = mechatron.frame_placement(mech, q, "coupler").act(inertia.lever)[:2]
    np.testing.assert_allclose(centre, corners.mean(axis=0), atol=1e-12)
    sides = [np.linalg.norm(corners[i] - corners[(i + 1) % 3]) for i in range(3)]
    assert inertia.mass == pytest.approx(1.2)
    assert inertia.inertia[2, 2] == pytest.approx(1.2 * sum(s * s for s in sides) / 36, rel=1e-12)

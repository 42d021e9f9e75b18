"""Bad drive data in robot files and in a URDF's SRDF rotor parameters (issue 33): through ``mechatron size``, each
is refused with exit status 2 and one line naming the file and the field (``links[1].drive.coulomb_friction``,
``rotor_params.q1.gear_ratio``), the inputs byte-identical and no output written. Among them a Coulomb pair with its
signs swapped or both of one sign, which used to be accepted and then *drove* the joint (friction must oppose the
motion: T_c+ ≥ 0 ≥ T_c−), an efficiency of 1e-300 (an internal error), and ratios and efficiencies outside
mechatron's plausible ranges (docs/robot_file.md). The legal extremes give the closed form of the holding arm of
tests/test_bad_catalog_columns.py: T_m = τ/(u η_gearbox η_file).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from mechatron.cli import main
from mechatron.errors import InputError
from tests.corpus import cli_error
from tests.test_bad_catalog_columns import HOLD, check, files, rise, run_json

ROBOT = """name = "holder"
gravity = [0.0, -9.81, 0.0]
[[links]]
joint = "revolute"
a = 0.3
mass = {mass}
com = [-0.15, 0.0, 0.0]
drive = {{ {drive} }}
"""
GOOD_FIELDS = {"rotor_inertia": "1e-4", "gear_ratio": "50.0", "viscous_friction": "2e-3",
               "coulomb_friction": "[0.3, -0.5]"}
GOOD = ", ".join(f"{k} = {v}" for k, v in GOOD_FIELDS.items())

COULOMB = "Coulomb friction opposes the motion: [T_c+ >= 0 for positive motor speed, T_c- <= 0 for negative], got"
PLAUSIBLE = "(mechatron's plausible range)"
# (the drive table's fields replacing GOOD's of the same name, the field named, words of the message)
CASES = [
    ("coulomb_friction = [-0.3, 0.5]", "coulomb_friction", COULOMB + " [-0.3, 0.5]"),  # swapped
    ("coulomb_friction = [0.3, 0.5]", "coulomb_friction", COULOMB + " [0.3, 0.5]"),  # both positive
    ("coulomb_friction = [-0.3, -0.5]", "coulomb_friction", COULOMB),  # both negative
    ("coulomb_friction = [-1e-9, 0.0]", "coulomb_friction", COULOMB),
    ("coulomb_friction = [0.0, 1e-9]", "coulomb_friction", COULOMB),
    ("coulomb_friction = [nan, -0.5]", "coulomb_friction[0]", "expected a finite number, got nan"),
    ("coulomb_friction = [0.3, -inf]", "coulomb_friction[1]", "expected a finite number"),
    ("coulomb_friction = [1e308, -0.5]", "coulomb_friction[0]", "magnitude <= 1e+12"),
    ("coulomb_friction = ['a', -0.5]", "coulomb_friction[0]", "expected a number, got str 'a'"),
    ("coulomb_friction = [0.3]", "coulomb_friction", "expected a list of 2 numbers"),
    ("coulomb_friction = [0.3, -0.5, 0.1]", "coulomb_friction", "expected a list of 2 numbers, got 3"),
    ("coulomb_friction = 0.3", "coulomb_friction", "expected a list of 2 numbers"),
    ("efficiency = 1e-300", "efficiency", "efficiency must be between 0.01 and 1 " + PLAUSIBLE + ", got 1e-300"),
    ("efficiency = 0.005", "efficiency", PLAUSIBLE),
    ("efficiency = 0.0", "efficiency", "must be > 0"),
    ("efficiency = -1.0", "efficiency", "must be > 0"),
    ("efficiency = 1.2", "efficiency", "efficiency must be in (0, 1], got 1.2"),
    ("efficiency = nan", "efficiency", "expected a finite number"),
    ("efficiency = inf", "efficiency", "expected a finite number"),
    ("efficiency = '0.9'", "efficiency", "expected a number, got str '0.9'"),
    ("efficiency = true", "efficiency", "expected a number, got bool True"),
    ("gear_ratio = 0.0", "gear_ratio", "must not be zero"),
    ("gear_ratio = 1e-300", "gear_ratio", "|gear ratio| must be between 0.001 and 1e+06 " + PLAUSIBLE),
    ("gear_ratio = -1e-4", "gear_ratio", PLAUSIBLE + ", got -0.0001"),
    ("gear_ratio = 1e7", "gear_ratio", PLAUSIBLE),
    ("gear_ratio = -1e7", "gear_ratio", PLAUSIBLE),
    ("gear_ratio = nan", "gear_ratio", "expected a finite number"),
    ("gear_ratio = 'x'", "gear_ratio", "expected a number"),
    ("viscous_friction = -1.0", "viscous_friction", "must be >= 0"),
    ("viscous_friction = nan", "viscous_friction", "expected a finite number"),
    ("viscous_friction = 1e308", "viscous_friction", "magnitude <= 1e+12"),
    ("rotor_inertia = -1.0", "rotor_inertia", "must be >= 0"),
    ("rotor_inertia = inf", "rotor_inertia", "expected a finite number"),
    ("placement = 'hand'", "placement", "unknown body 'hand' for the drive of joint q1"),
    ("offset = [1.0, 2.0]", "offset", "expected a list of 3 numbers"),
    ("eficiency = 0.9", "eficiency", "unknown field"),
]


def drive_table(change: str) -> str:
    """GOOD with the field of ``change`` replaced (or added)."""
    name = change.split("=")[0].strip()
    return ", ".join([*(f"{k} = {v}" for k, v in GOOD_FIELDS.items() if k != name), change])


def robot_paths(tmp_path: Path, drive: str) -> dict:
    paths = {"robot": tmp_path / "holder.toml", "task": tmp_path / "hold.csv"}
    paths["robot"].write_text(ROBOT.format(mass=2.0, drive=drive), encoding="utf-8")
    paths["task"].write_text(HOLD, encoding="utf-8")
    return paths


def refused(tmp_path: Path, capsys, paths: dict) -> str:
    """The one line of a refused ``size`` (exit 2), the inputs unchanged and no --csv written."""
    before = {name: path.read_bytes() for name, path in paths.items()}
    out = tmp_path / "sizing.csv"
    code, line = cli_error(capsys, "size", str(paths["robot"]), "--task", str(paths["task"]), "--csv", str(out))
    assert code == 2
    assert {name: path.read_bytes() for name, path in paths.items()} == before
    assert not out.exists()
    return line


@pytest.mark.parametrize("change, field, words", CASES, ids=[c[0] for c in CASES])
def test_a_bad_drive_field_is_one_line_naming_file_and_field(tmp_path, capsys, change, field, words):
    paths = robot_paths(tmp_path, drive_table(change))
    line = refused(tmp_path, capsys, paths)
    assert line.startswith(f"mechatron: error: {paths['robot']}: field 'links[1].drive.{field}': "), line
    assert words in line, line


def test_the_good_drive_table_loads(tmp_path, capsys):
    """The table the cases edit sizes (the holding arm at rest: its friction acts on no motion)."""
    paths = robot_paths(tmp_path, GOOD)
    assert main(["size", str(paths["robot"]), "--task", str(paths["task"]), "--json"]) in (0, 1)
    assert capsys.readouterr().err == ""


SRDF_CASES = [
    ('gear_ratio="0"', "gear_ratio", "|gear ratio| must be between 0.001 and 1e+06 " + PLAUSIBLE + ", got 0"),
    ('gear_ratio="1e-300"', "gear_ratio", PLAUSIBLE),
    ('gear_ratio="-1e7"', "gear_ratio", PLAUSIBLE),
    ('gear_ratio="nan"', "gear_ratio", "expected a finite number, got 'nan'"),
    ('gear_ratio="inf"', "gear_ratio", "expected a finite number"),
    ('gear_ratio=""', "gear_ratio", "expected a finite number, got ''"),
    ('gear_ratio="fifty"', "gear_ratio", "expected a finite number"),
    ('mass="-1"', "mass", "the rotor inertia (attribute 'mass', kg m^2) must be >= 0 and <= 1e+12, got -1"),
    ('mass="1e300"', "mass", "must be >= 0 and <= 1e+12"),
    ('mass="x"', "mass", "expected a finite number, got 'x'"),
]


@pytest.fixture(scope="module")
def urdf_text(tmp_path_factory) -> tuple[str, str]:
    """A URDF of the holding arm and its SRDF (``mass="0.0001" gear_ratio="50.0"``), as mechatron exports them."""
    import mechatron
    from mechatron.model.urdf import export_urdf

    folder = tmp_path_factory.mktemp("urdf")
    paths = robot_paths(folder, "rotor_inertia = 1e-4, gear_ratio = 50.0")
    urdf, srdf = export_urdf(mechatron.load(paths["robot"]), folder / "holder.urdf")
    return urdf.read_text(encoding="utf-8"), srdf.read_text(encoding="utf-8")


@pytest.mark.parametrize("attribute, field, words", SRDF_CASES, ids=[c[0] for c in SRDF_CASES])
def test_a_bad_rotor_parameter_names_the_srdf_joint_and_attribute(tmp_path, capsys, urdf_text, attribute, field,
                                                                   words):
    urdf, srdf = urdf_text
    name = attribute.split("=")[0]
    good = 'mass="0.0001"' if name == "mass" else 'gear_ratio="50.0"'
    assert good in srdf
    paths = {"robot": tmp_path / "holder.urdf", "srdf": tmp_path / "holder.srdf", "task": tmp_path / "hold.csv"}
    paths["robot"].write_text(urdf, encoding="utf-8")
    paths["srdf"].write_text(srdf.replace(good, attribute), encoding="utf-8")
    paths["task"].write_text(HOLD, encoding="utf-8")
    line = refused(tmp_path, capsys, paths)
    assert line.startswith(f"mechatron: error: {paths['srdf']}: field 'rotor_params.q1.{field}': "), line
    assert words in line, line


def test_the_legal_extremes_of_a_drive_table_give_the_closed_form(tmp_path, capsys):
    """efficiency = 0.01 (the plausible floor), gear_ratio = −1e6 (the plausible top), a one-sided Coulomb pair
    [0.3, 0]: the arm of 0.1 kg held at rest (τ = 0.1 · 9.81 · 0.15 = 0.14715 N·m; at rest no friction) through G1
    (u = 10, η = 0.9) asks T_m = τ/(u η η_f) = 0.14715/(10 · 0.9 · 0.01) = 1.635 N·m of the motor, and its winding the
    closed-form rise 3 · 10.69 · 1.0585/(1 − 3 · 10.69 · 0.0039) = 38.81 K."""
    paths = files(tmp_path, mass=0.1)
    drive = "rotor_inertia = 1e-4, gear_ratio = -1e6, efficiency = 0.01, coulomb_friction = [0.3, 0.0]"
    paths["robot"].write_text(ROBOT.format(mass=0.1, drive=drive), encoding="utf-8")
    sized = run_json(capsys, paths, "--no-direct")
    (joint,) = sized["joints"]
    torque = 0.1 * 9.81 * 0.15 / (10 * 0.9 * 0.01)
    assert torque == pytest.approx(1.635, abs=5e-4) and joint["gearbox"] == "G1"
    assert check(joint, "peak torque") == pytest.approx(torque, rel=1e-9)
    assert rise(torque, 3.0, 0.0039, 40.0) == pytest.approx(38.81, abs=0.01)
    assert check(joint, "winding temperature rise") == pytest.approx(rise(torque, 3.0, 0.0039, 40.0), rel=1e-6)


@pytest.mark.parametrize("pair", [(-0.2, 0.1), (0.2, 0.1), (-0.2, -0.1), (math.nan, 0.0), (0.0, -math.inf)])
def test_the_python_api_drive_refuses_friction_that_drives_the_joint(pair):
    """``Drive(...)`` itself (the Python API path, not only the robot file) refuses a Coulomb pair that would push
    the motor along its motion: T_c+ ≥ 0 ≥ T_c− and finite."""
    from mechatron.model.dh import Drive

    with pytest.raises(InputError, match="Coulomb friction opposes the motion") as caught:
        Drive(coulomb_friction=pair)
    assert caught.value.field == "coulomb_friction"
    assert Drive(coulomb_friction=(0.3, -0.2)).coulomb_friction == (0.3, -0.2)

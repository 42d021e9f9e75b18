"""Bad mechanism files that used to load and do the wrong thing, or fail without naming the field (issue 21, item 6):
each is refused with one line naming the file and the field, exit status 2 on the command line. Each case edits a
good file that loads — the complete four-bar example, a boom lifted by a cylinder, the Delta robot (spatial) — in one
place. And the other side of the inertia check: a spatial inertia with a negative product of inertia that is a rigid
body's loads, with the tensor the file gives."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from tests.boom import boom
from tests.corpus import cli_error

ROOT = Path(__file__).resolve().parent.parent
BOOM = boom(top="input_rates = { lift = 0.05 }\n", points="T = { at = [1.0, 0.2], direction = [1, 0] }")
# a boom lifted by a cylinder 0.5 m long in the drawing
ARM = boom(points="S = [0.7, 0.2]\nT = [1.0, 0.3]", carried='"O", "E", "S", "T"',
           tail='[lengths]\na = { points = ["O", "T"], value = 1.044 }\nb = { points = ["E", "T"], value = 0.5385 }\n')
# the boom with a fourth point, T placed by two declared lengths (drawn 0.03 mm off: |OT| 1.04403, |ET| 0.53852)
BASES = {"arm": ARM, "boom": BOOM,
         "four_bar": (ROOT / "examples" / "data" / "four_bar.toml").read_text(encoding="utf-8"),
         "delta": (ROOT / "robots" / "delta.toml").read_text(encoding="utf-8")}
DELTA_RATES = "input_rates = { theta1 = 1.0, theta2 = 1.0, theta3 = 1.0 }"
ROD1_AXES = "axes = [[-0.0, 1.0, 0.0], [-0.7659860924831149, -0.0, 0.642857142857143]]"
PLATFORM_INERTIA = "inertia = [0.001, 0.001, 0.002]"

# case: (base, text replaced, its replacement, field, words of the message)
BAD_FILES = {
    "a misspelt input rate": ("four_bar", "input_rates = { q1 = 10.0 }", "input_rates = { q_1 = 10.0 }",
                              "input_rates.q_1", "'q_1' is not an actuated coordinate (those are: q1)"),
    "a rate of a coordinate that is not actuated": ("four_bar", "input_rates = { q1 = 10.0 }",
                                                    "input_rates = { q1 = 10.0, q3 = 2.0 }", "input_rates.q3",
                                                    "'q3' is not an actuated coordinate"),
    "a misspelt cylinder rate": ("boom", "input_rates = { lift = 0.05 }", "input_rates = { lft = 0.05 }",
                                 "input_rates.lft", "'lft' is not an actuated coordinate (those are: lift)"),
    "a misspelt spatial rate": ("delta", DELTA_RATES, DELTA_RATES.replace("theta3", "theta_3"),
                                "input_rates.theta_3", "'theta_3' is not an actuated coordinate"),
    "an unknown actuated coordinate": ("four_bar", ('actuated = ["q1"]', "input_rates = { q1 = 10.0 }"),
                                       ('actuated = ["q9"]', ""), "actuated",
                                       "'q9' is not a joint coordinate or a cylinder (the coordinates: q1, q2, q3)"),
    "an unknown cylinder": ("boom", ('actuated = ["lift"]', "input_rates = { lift = 0.05 }"),
                            ('actuated = ["lift2"]', ""), "actuated",
                            "'lift2' is not a joint coordinate or a cylinder (the coordinates: boom_angle, lift)"),
    "an actuated coordinate twice": ("four_bar", 'actuated = ["q1"]', 'actuated = ["q1", "q1"]', "actuated",
                                     "'q1' is listed twice"),
    "an unknown spatial coordinate": ("delta", ('actuated = ["theta1", "theta2", "theta3"]', DELTA_RATES),
                                      ('actuated = ["theta1", "theta2", "rod1_angle3"]', ""), "actuated",
                                      "'rod1_angle3' is not a joint coordinate or a cylinder (the coordinates: "
                                      "platform_x, platform_y, platform_z, theta1, rod1_angle1, rod1_angle2, theta2"),
    "a point's zero direction": ("boom", "direction = [1, 0]", "direction = [0, 0]", "points.T.direction",
                                 "a direction must not be zero, got [0, 0]"),
    "a point's zero direction in mm": ("four_bar", "A = [0, 0]  ", "A = { at = [0, 0], direction = [0.0, 0.0] }",
                                       "points_mm.A.direction", "a direction must not be zero"),
    "a universal joint with parallel axes": ("delta", ROD1_AXES, "axes = [[0.0, 1.0, 0.0], [0.0, -2.0, 0.0]]",
                                             "joints[3].axes", "joint of rod1: a universal joint's two axes must "
                                                               "not be parallel, got [0, 1, 0] and [0, -2, 0]"),
    "a universal joint with a zero axis": ("delta", ROD1_AXES, "axes = [[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]",
                                           "joints[3].axes", "a joint axis must be 3 numbers, not all zero"),
    "a universal joint's coordinate (always <body>_angle1, 2)": ("delta", ROD1_AXES, ROD1_AXES + '\ncoordinate = "u"',
                                                                  "joints[3].coordinate", "unknown field"),
    "a zero spatial axis": ("delta", "axis = [-0.0, 1.0, 0.0]", "axis = [0, 0, 0]", "joints[2].axis",
                            "joint of arm1: a joint axis must be 3 numbers, not all zero, got [0, 0, 0]"),
    "an inertia that is not positive definite": ("delta", PLATFORM_INERTIA,
                                                 "inertia = [0.001, 0.001, 0.002, 0.005, 0.0, 0.0]",
                                                 "bodies[8].inertia", "body platform: inertia tensor must be "
                                                                      "positive definite"),
    "moments that break the triangle inequality": ("delta", PLATFORM_INERTIA, "inertia = [0.001, 0.001, 0.003]",
                                                   "bodies[8].inertia", "violate the triangle inequality"),
    "a negative moment": ("delta", PLATFORM_INERTIA, "inertia = [-0.001, 0.002, 0.002]", "bodies[8].inertia",
                          "positive definite"),
    # a drawing that leaves a point undetermined, or derived points and declared lengths that do not fit (item 2)
    "a point no body carries": ("four_bar", "C = [262, 249]", "C = [262, 249]\nE = [100, 100]", "points_mm.E",
                                "point E is carried by no body, so nothing fixes it"),
    "a derived point between points of other bodies": ("four_bar", 'between = ["B", "C"]', 'between = ["A", "C"]',
                                                       "points_mm.M", "none of the bodies carrying it (coupler) "
                                                                      "carries both"),
    "a named length to a derived point": ("four_bar", "d = { points", 'x = ["B", "M"]\nd = { points', "lengths.x",
                                          "M is a derived point"),
    "three declared lengths to one point": ("arm", "[lengths]", '[lengths]\nc = { points = ["S", "T"], value = 0.32 }',
                                            "lengths.c", "point T of body boom has 3 declared lengths to points before "
                                                         "it (a, b, c): two fix it"),
    "declared lengths that cannot meet": ("arm", ("value = 1.044 ", "value = 0.5385 "),
                                          ("value = 0.1 ", "value = 0.1 "), "lengths.b",
                                          "point T: the declared lengths a and b cannot meet"),
}


def edited(base: str, old, new) -> str:
    text = BASES[base]
    for before, after in zip(*((old, new) if isinstance(old, tuple) else ((old,), (new,)))):
        assert text.count(before) == 1, f"the base file {base} changed: {before!r}"
        text = text.replace(before, after)
    return text


@pytest.mark.parametrize("base", sorted(BASES))
def test_the_bases_load(base, tmp_path):
    path = tmp_path / f"{base}.toml"
    path.write_text(BASES[base], encoding="utf-8")
    mech = mechatron.load(path)
    assert mech.mobility() == len(mech.actuated) >= 1


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_file_gives_one_line_naming_the_file_and_the_field(case, tmp_path, capsys):
    base, old, new, field, words = BAD_FILES[case]
    path = tmp_path / "bad.toml"
    path.write_text(edited(base, old, new), encoding="utf-8")
    with pytest.raises(InputError) as caught:
        mechatron.load(path)
    assert (caught.value.file, caught.value.field) == (str(path), field), caught.value
    assert words in caught.value.message
    code, err = cli_error(capsys, "show", str(path))
    assert code == 2 and err == f"mechatron: error: {path}: field '{field}': {caught.value.message}"


def test_a_spatial_inertia_with_a_negative_product_loads_with_its_tensor(tmp_path):
    """I = [[2, −0.5, 0], [−0.5, 2, 0], [0, 0, 3]]·1e-3 kg·m²: principal moments 1.5, 2.5, 3 (·1e-3), positive and
    1.5 + 2.5 ≥ 3 — a rigid body's (a plate's, I_zz = I_xx + I_yy at most). The platform's joint carries it as given
    about the platform's centre TCP (the arms and rods are bars, with nothing about their own axis)."""
    path = tmp_path / "delta.toml"
    path.write_text(edited("delta", PLATFORM_INERTIA, "inertia = [0.002, 0.002, 0.003, -0.0005, 0.0, 0.0]"),
                    encoding="utf-8")
    mech = mechatron.load(path)
    expected = np.array([[2.0, -0.5, 0.0], [-0.5, 2.0, 0.0], [0.0, 0.0, 3.0]]) * 1e-3
    assert np.allclose(np.linalg.eigvalsh(expected), [1.5e-3, 2.5e-3, 3e-3])
    inertia = mech.model.inertias[mech.joint_id("platform_z")]
    assert inertia.mass == pytest.approx(0.6)
    np.testing.assert_allclose(inertia.inertia, expected, rtol=1e-12, atol=1e-15)


def test_a_spatial_mechanism_built_in_python_names_the_field_too():
    """A spec made in Python (as the syntheses do) goes through the same checks when built: the field, no file."""
    from dataclasses import replace

    from mechatron.model.linkage_file import read_linkage_file
    from mechatron.model.spatial import build_spatial

    spec = read_linkage_file(ROOT / "robots" / "delta.toml")
    joints = tuple(replace(j, axis=(0.0, 0.0, 0.0)) if j.coordinate == "theta2" else j for j in spec.joints)
    with pytest.raises(InputError) as caught:
        build_spatial(replace(spec, joints=joints, file=None))
    assert caught.value.field == "joints[4].axis" and "not all zero" in caught.value.message

"""Robot files: loading by name and path, and clear errors naming the file and the field for malformed ones."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.library import builtin_robot_files

GOOD = """
name = "two_link"
convention = "standard"

[[links]]
joint = "revolute"
a = 0.5
mass = 1.0
com = [-0.25, 0.0, 0.0]
inertia = { xx = 0.001, yy = 0.02, zz = 0.02 }

[[links]]
joint = "prismatic"
alpha_deg = 90.0
lower_mm = 0.0
upper_mm = 300.0
mass = 0.5
inertia = { xx = 0.001, yy = 0.001, zz = 0.001 }
"""


def write(tmp_path: Path, text: str, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_good_file_loads_with_units_in_field_names(tmp_path):
    mech = mechatron.load(write(tmp_path, GOOD))
    assert mech.name == "two_link" and mech.nq == 2
    assert mech.model.upperPositionLimit[1] == pytest.approx(0.3)  # upper_mm = 300
    assert mech.dh.links[1].alpha == pytest.approx(math.pi / 2)  # alpha_deg = 90
    assert mech.model.lowerPositionLimit[0] == pytest.approx(-math.pi)  # revolute default ±180°
    assert mech.total_mass == pytest.approx(1.5)


def test_every_shipped_file_loads():
    files = builtin_robot_files()
    assert {"planar_2r", "cylindrical_rpp", "articulated_rrr", "planar_3r", "scara", "puma560"} <= set(files)
    for name in files:
        mech = mechatron.load(name)
        assert mech.model.existFrame(mech.tool_frame)
        assert mech.source.endswith(f"{name}.toml")


def test_example_robot_data_arms_load_from_disk():
    ur5 = mechatron.load("ur5")
    panda = mechatron.load("panda")
    assert ur5.nq == 6 and panda.nq == 7  # the panda's fingers are locked
    assert "tool" in ur5.frame_names and "tool" in panda.frame_names
    # the UR5 tool0 frame at the zero pose: upper arm 0.425 m, forearm 0.39225 m along x, wrist offsets along y/z
    np.testing.assert_allclose(mechatron.kinematics.frame_position(ur5, np.zeros(6)), [0.81725, 0.19145, -0.005491],
                               atol=1e-6)
    # joint origins are named parameters and can be overridden
    assert ur5.parameters["elbow_joint_z"].value == pytest.approx(0.425)
    longer = mechatron.load("ur5", elbow_joint_z=0.5)
    np.testing.assert_allclose(mechatron.kinematics.frame_position(longer, np.zeros(6))[0], 0.81725 + 0.075, atol=1e-6)


def test_load_urdf_by_path(tmp_path):
    from mechatron.library import installed_example_robots

    path = installed_example_robots()["ur5"]
    mech = mechatron.load(path)
    assert mech.nq == 6 and mech.name == "ur5_robot"


CASES = [
    # (description, file text, pieces the message must contain)
    ("missing field", GOOD.replace('joint = "prismatic"\n', ""), ["links[2].joint", "missing required field"]),
    ("wrong type", GOOD.replace("a = 0.5", 'a = "half a metre"'), ["links[1].a", "expected a number"]),
    ("negative mass", GOOD.replace("mass = 1.0", "mass = -1.0"), ["links[1].mass", ">= 0"]),
    ("inertia not positive definite",
     GOOD.replace("xx = 0.001, yy = 0.02, zz = 0.02", "xx = -0.001, yy = 0.02, zz = 0.02"),
     ["links[1].inertia", "positive definite"]),
    ("inertia violating triangle inequality",
     GOOD.replace("xx = 0.001, yy = 0.02, zz = 0.02", "xx = 0.001, yy = 0.002, zz = 0.02"),
     ["links[1].inertia", "triangle inequality"]),
    ("unknown joint kind", GOOD.replace('joint = "prismatic"', 'joint = "spherical"'),
     ["links[2].joint", "unknown value 'spherical'", "revolute, prismatic"]),
    ("unknown field", GOOD.replace("a = 0.5", "a = 0.5\nalpah = 0.1"), ["links[1].alpah", "unknown field"]),
    ("prismatic without stroke", GOOD.replace("lower_mm = 0.0\n", ""), ["links[2].lower", "missing required field"]),
    ("limits reversed", GOOD.replace("upper_mm = 300.0", "upper_mm = -300.0"), ["links[2].lower", "below upper"]),
    ("both units", GOOD.replace("alpha_deg = 90.0", "alpha_deg = 90.0\nalpha = 1.5"),
     ["links[2].alpha", "only one of alpha and alpha_deg"]),
    ("unknown convention", GOOD.replace('"standard"', '"craig"'), ["convention", "standard, modified"]),
    ("no links", 'name = "x"\n', ["neither a robot file", "[[links]]", "mechanism file"]),
    ("bad vector", GOOD.replace("com = [-0.25, 0.0, 0.0]", "com = [-0.25, 0.0]"), ["links[1].com", "3 numbers"]),
    ("bad drive", GOOD.replace("mass = 0.5", "mass = 0.5\ndrive = { gear_ratio = 0.0 }"),
     ["links[2].drive.gear_ratio", "must not be zero"]),
    ("efficiency above one", GOOD.replace("mass = 0.5", "mass = 0.5\ndrive = { efficiency = 1.2 }"),
     ["links[2].drive.efficiency", "(0, 1]"]),
    ("TOML syntax", GOOD.replace("a = 0.5", "a = = 0.5"), ["not valid TOML", "line"]),
    ("bool for number", GOOD.replace("mass = 1.0", "mass = true"), ["links[1].mass", "expected a number"]),
]


@pytest.mark.parametrize("case,text,pieces", CASES, ids=[c[0] for c in CASES])
def test_malformed_file_errors_name_file_and_field(tmp_path, case, text, pieces):
    path = write(tmp_path, text, "bad_robot.toml")
    with pytest.raises(mechatron.InputError) as info:
        mechatron.load(path)
    message = str(info.value)
    assert "bad_robot.toml" in message
    for piece in pieces:
        assert piece in message, f"{case}: {piece!r} not in {message!r}"


def test_unknown_robot_name_suggests():
    with pytest.raises(mechatron.InputError, match=r"unknown robot 'puma650'; did you mean puma560"):
        mechatron.load("puma650")


def test_missing_file_and_unknown_suffix(tmp_path):
    with pytest.raises(mechatron.InputError, match="no such file"):
        mechatron.load(tmp_path / "nothing.toml")
    other = tmp_path / "robot.yaml"
    other.write_text("x: 1")
    with pytest.raises(mechatron.InputError, match="unknown kind of file"):
        mechatron.load(other)


def test_broken_urdf_is_reported(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(mechatron.InputError, match="broken.urdf"):
        mechatron.load(path)

"""Link masses that include the drives (issue 32, item 2): a robot file's ``link_masses_include_drives = true``, a
URDF's ``<mechatron link_masses_include_drives="true"/>`` and the example-robot-data arms make the sizing add no
chosen drive's mass (the included masses stand for them), and the report says which applied.

References: the closed-form dynamics of a two-link arm with point masses (written out below), Pinocchio's RNEA on
the Panda's URDF read by Pinocchio alone, and the single-pass sizing (a separate path of the sizing: one pass with
weightless drives, which with the link masses as given must choose the same drives)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pinocchio as pin
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.sizing import size_mechanism
from mechatron.dynamics.motion import move
from mechatron.dynamics.task import default_task
from mechatron.errors import InputError
from mechatron.library import EXAMPLE_ROBOTS, installed_example_robots
from mechatron.model.urdf import export_urdf, load_urdf

# Two links in a vertical plane (joint axes along z, gravity along −y): point masses m1 = 4 kg at the elbow (the far
# end of link 1, L1 = 0.5 m) and m2 = 3 kg at the tip (L2 = 0.4 m further). The shoulder swings from −0.5 to 0.5 rad
# (trapezoid, 1 rad/s, 2 rad/s²), the elbow held straight (q2 = q̇2 = q̈2 = 0). A drive of mass m_w on link 1 at
# distance d from the shoulder gives
#
#     τ1 = (m1 L1² + m_w d² + m2 (L1 + L2)²) q̈1 + g cos q1 (m1 L1 + m_w d + m2 (L1 + L2)),
#     τ2 = m2 L2 (L1 + L2) q̈1 + m2 g L2 cos q1,
#
# and a direct-drive motor of rotor inertia J_m needs T_m = J_m q̈ + τ: max |T_m1| = 51.48 N·m without the wrist
# drive (S54 fits, S59 is heavier), max |T_m2| = 13.55 N·m (W20, 2 kg, the wrist drive); with that 2 kg at the elbow
# (d = L1, the default placement) max |T_m1| = 61.97 N·m (S70).
L1, L2, M1, M2, G, J_M = 0.5, 0.4, 4.0, 3.0, 9.81, 1e-3
MOTORS = pd.DataFrame([
    {"key": key, "rated_torque": torque, "peak_torque": torque, "rated_speed": 100.0, "max_speed": 200.0,
     "rotor_inertia": J_M, "mass": mass, "price": 100.0 * mass}
    for key, torque, mass in (("W10", 10.0, 1.0), ("W20", 20.0, 2.0), ("S54", 54.0, 3.0), ("S59", 59.0, 4.0),
                              ("S70", 70.0, 5.0))])

ROBOT = """name = "two_link"
gravity = [0.0, -9.81, 0.0]
{flag}
[[links]]
joint = "revolute"
name = "q1"
a = 0.5
mass = 4.0

[[links]]
joint = "revolute"
name = "q2"
a = 0.4
mass = 3.0
"""


def two_link(tmp_path: Path, flag: str) -> mechatron.Mechanism:
    path = tmp_path / "two_link.toml"
    path.write_text(ROBOT.format(flag=flag))
    return mechatron.load(path)


def hand_motor_torques(tr, wrist_mass: float, d: float) -> tuple[np.ndarray, np.ndarray]:
    q1, a1 = tr.q[:, 0], tr.a[:, 0]
    tau1 = (M1 * L1**2 + wrist_mass * d**2 + M2 * (L1 + L2) ** 2) * a1 \
        + G * np.cos(q1) * (M1 * L1 + wrist_mass * d + M2 * (L1 + L2))
    tau2 = M2 * L2 * (L1 + L2) * a1 + M2 * G * L2 * np.cos(q1)
    return J_M * a1 + tau1, J_M * tr.a[:, 1] + tau2


def sized(mech, **options):
    tr = move(mech, [-0.5, 0.0], [0.5, 0.0], vmax=1.0, amax=2.0, dt=0.005)
    return tr, size_mechanism(mech, tr, MOTORS, pd.DataFrame(), inertia_ratio_max=1e4, **options)


def test_a_robot_file_whose_masses_include_the_drives_adds_none(tmp_path):
    """With ``link_masses_include_drives = true`` the wrist drive (2 kg) is not put on link 1: joint 1's motor
    torque is the hand closed form without it (peak 51.48 N·m → S54) and the choice is the single pass's; the same
    file without the field adds it at the elbow (61.97 N·m → S70), as before."""
    mech = two_link(tmp_path, "link_masses_include_drives = true")
    assert mech.link_masses_include_drives and mech.with_parameters(a1=0.5).link_masses_include_drives
    tr, result = sized(mech)
    hand1, hand2 = hand_motor_torques(tr, 0.0, 0.0)
    assert np.abs(hand1).max() == pytest.approx(51.48, abs=0.005)
    q1, q2 = result.joints
    for joint, hand in ((q1, hand1), (q2, hand2)):
        assert np.allclose(joint.operating_points()[1], hand, rtol=1e-9, atol=1e-9)
    assert [j.motor for j in result.joints] == ["S54", "W20"]
    assert len(result.iterations) == 1 and result.converged and result.feasible
    assert result.drive_masses == "included" and result.masses_included

    _, single = sized(mech, single_pass=True)
    assert [j.choice() for j in single.joints] == [j.choice() for j in result.joints]
    assert all(np.array_equal(a.duty.torque, b.duty.torque) for a, b in zip(single.joints, result.joints))

    text = str(result)
    assert "drive masses: included in the link masses of two_link (link_masses_include_drives) — not added" in text
    assert "on link1: 2 kg (included in the link masses: not added)" in text
    data = json.loads(json.dumps(result.as_dict()))
    assert data["method"] == "fixed point" and data["drive_masses"] == "included"
    assert data["joints"][1]["mounted_on"] == {"body": "link1", "mass_kg": 2.0, "loads_the_mechanism": False}

    added = two_link(tmp_path, "link_masses_include_drives = false")
    assert not added.link_masses_include_drives and not two_link(tmp_path, "").link_masses_include_drives
    tr, fixed = sized(added)
    loaded1, _ = hand_motor_torques(tr, 2.0, L1)
    assert np.abs(loaded1).max() == pytest.approx(61.97, abs=0.005)
    assert np.allclose(fixed.joints[0].operating_points()[1], loaded1, rtol=1e-9, atol=1e-9)
    assert fixed.joints[0].motor == "S70" and fixed.drive_masses == "added"
    assert f"drive masses: added at their mounts (7 kg in all), fixed point after {len(fixed.iterations)} passes" \
        in str(fixed)
    assert fixed.as_dict()["joints"][1]["mounted_on"]["loads_the_mechanism"] is True
    assert single.drive_masses == "weightless" and "drive masses: not added (single pass" in str(single)


def panda_rnea(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """The Panda's joint torques by Pinocchio alone: its URDF as Pinocchio reads it, fingers locked at zero,
    no armature (the sizing's duties carry no drive inertia)."""
    model = pin.buildModelFromUrdf(str(installed_example_robots()["panda"]))
    fingers = [model.getJointId(n) for n in EXAMPLE_ROBOTS["panda"].locked]
    model = pin.buildReducedModel(model, fingers, pin.neutral(model))
    data = model.createData()
    return np.array([pin.rnea(model, data, qk, vk, ak).copy() for qk, vk, ak in zip(q, v, a)])


def test_the_panda_sizes_as_a_single_pass_with_its_link_masses():
    """example-robot-data's Panda (link masses of whole links, actuators inside) sizes as ``--single-pass``
    would: the same drives, the same duty torques to 1e-12, and these torques are Pinocchio's RNEA of the URDF as
    given (nothing added). Loaded by path without the statement, the fixed point adds the drives and joint 2's
    peak torque grows (the issue's double count)."""
    panda = mechatron.load("panda")
    assert panda.link_masses_include_drives
    task = default_task(panda)
    result = mechatron.size(panda, task)
    single = mechatron.size(panda, task, single_pass=True)
    assert result.drive_masses == "included" and len(result.iterations) == 1
    assert [j.choice() for j in result.joints] == [j.choice() for j in single.joints]
    tr = task.trajectory
    reference = panda_rnea(tr.q, tr.v, tr.a)
    for k, (ours, theirs) in enumerate(zip(result.joints, single.joints)):
        peak = np.abs(ours.duty.torque).max()
        assert peak == pytest.approx(np.abs(theirs.duty.torque).max(), rel=1e-12, abs=1e-12)
        assert np.allclose(ours.duty.torque, theirs.duty.torque, rtol=1e-12, atol=1e-12)
        assert np.allclose(ours.duty.torque, reference[:, k], rtol=1e-9, atol=1e-9), ours.joint
    assert all(m["loads_the_mechanism"] is False for m in (j["mounted_on"] for j in result.as_dict()["joints"]))

    robot = EXAMPLE_ROBOTS["panda"]
    bare = load_urdf(installed_example_robots()["panda"], "panda", tool=robot.tool, locked_joints=robot.locked)
    assert not bare.link_masses_include_drives
    doubled = mechatron.size(bare, default_task(bare))
    assert doubled.drive_masses == "added" and len(doubled.iterations) > 1
    assert np.abs(doubled.joints[1].duty.torque).max() > np.abs(result.joints[1].duty.torque).max() * 1.05


TURRET = Path(__file__).resolve().parent.parent / "examples" / "data" / "turret_arm.urdf"


def turret_copy(tmp_path: Path, element: str) -> Path:
    text = TURRET.read_text().replace('<robot name="turret_arm">', f'<robot name="turret_arm">\n  {element}', 1)
    path = tmp_path / "turret_arm.urdf"
    path.write_text(text)
    return path


def test_a_urdf_says_it_with_a_mechatron_element(tmp_path):
    """``<mechatron link_masses_include_drives="true"/>`` sets the statement, Pinocchio reads the rest of the file
    unchanged (the same total mass, 6.8 kg), ``load_urdf(..., link_masses_include_drives=)`` overrides it, a rebuilt
    arm keeps it and ``export-urdf`` writes it back."""
    path = turret_copy(tmp_path, '<mechatron link_masses_include_drives="true"/>')
    arm = mechatron.load(path)
    assert arm.link_masses_include_drives and arm.total_mass == pytest.approx(4.0 + 2.0 + 0.8, rel=1e-15)
    assert arm.with_parameters(turn_z=0.35).link_masses_include_drives
    assert not load_urdf(path, link_masses_include_drives=False).link_masses_include_drives
    assert load_urdf(TURRET, link_masses_include_drives=True).link_masses_include_drives
    assert not mechatron.load(TURRET).link_masses_include_drives
    assert load_urdf(turret_copy(tmp_path, '<mechatron link_masses_include_drives="0"/>')).link_masses_include_drives \
        is False
    out = tmp_path / "out" / "arm.urdf"
    out.parent.mkdir()
    export_urdf(arm, out)
    assert mechatron.load(out).link_masses_include_drives
    export_urdf(mechatron.load(TURRET), out)
    assert not mechatron.load(out).link_masses_include_drives


@pytest.mark.parametrize("element, message", [
    ('<mechatron link_masses_include_drives="yes"/>',
     "field 'mechatron link_masses_include_drives': must be true or false, got 'yes'"),
    ('<mechatron link_masses_include_drive="true"/>',
     "field 'mechatron': unknown attribute 'link_masses_include_drive' (known: link_masses_include_drives)"),
    ('<mechatron/><mechatron/>', "field 'mechatron': give one <mechatron> element, not several"),
])
def test_a_bad_statement_is_one_line_naming_the_file(tmp_path, capsys, element, message):
    path = turret_copy(tmp_path, element)
    with pytest.raises(InputError) as caught:
        mechatron.load(path)
    assert str(caught.value) == f"{path}: {message}"
    assert main(["size", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(message) and "\n" not in err and "Traceback" not in err


def test_a_bad_robot_file_field_names_it(tmp_path):
    path = tmp_path / "two_link.toml"
    path.write_text(ROBOT.format(flag='link_masses_include_drives = "yes"'))
    with pytest.raises(InputError, match="field 'link_masses_include_drives': expected true or false, got 'yes'"):
        mechatron.load(path)


def test_the_cli_report_says_which_applied(tmp_path, capsys):
    """``mechatron size`` of a URDF whose masses include the drives prints it and writes ``drive_masses`` in its
    JSON; the URDF without the element keeps the fixed point with the drives added."""
    path = turret_copy(tmp_path, '<mechatron link_masses_include_drives="true"/>')
    assert main(["size", str(path), "--json"]) in (0, 1)
    data = json.loads(capsys.readouterr().out)
    assert data["drive_masses"] == "included" and len(data["iterations"]) == 1
    assert main(["size", str(path)]) in (0, 1)
    assert "drive masses: included in the link masses of turret_arm" in capsys.readouterr().out
    assert main(["size", str(TURRET), "--json"]) in (0, 1)
    assert json.loads(capsys.readouterr().out)["drive_masses"] == "added"

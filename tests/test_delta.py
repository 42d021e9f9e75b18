"""The Delta robot, a spatial closed loop from a mechanism file (``planar = false``): its kinematics against the
closed forms of its inverse and forward kinematics, its dynamics against the energy balance, and the sizing of its
three motors."""

from __future__ import annotations

import json

import numpy as np
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics.motion import move
from mechatron.dynamics.tree import potential_energy
from mechatron.errors import InputError
from mechatron.io.data import data_dir
from mechatron.kinematics import joint_velocity, point_velocity
from mechatron.machines.delta import DeltaDesign, write_delta
from mechatron.model.linkage_file import read_linkage_file
from tests.written_files import assert_same_toml


@pytest.fixture(scope="module")
def delta():
    return mechatron.load("delta")


def test_the_shipped_file_is_what_the_design_writes(tmp_path):
    written = write_delta(None, tmp_path / "delta.toml")
    assert_same_toml(written, data_dir("robots") / "delta.toml")  # its numbers to 1e-12, not their last digit
    spec = read_linkage_file(written)
    assert not spec.planar and len(spec.points[0].at) == 3


def test_positions_agree_with_the_closed_forms(delta):
    design = DeltaDesign()
    assert delta.mobility() == 3 and delta.actuated == ["theta1", "theta2", "theta3"]
    rng = np.random.default_rng(7)
    for _ in range(12):
        theta = rng.uniform(-0.4, 1.0, 3)
        q = mechatron.assemble(delta, dict(zip(delta.actuated, theta)))
        platform = mechatron.frame_placement(delta, q, "TCP").translation
        np.testing.assert_allclose(platform, design.forward(theta), atol=1e-12)   # three spheres
        np.testing.assert_allclose(design.inverse(platform), theta, atol=1e-11)   # each arm's own equation
        for i in range(3):  # the platform keeps its orientation: each attachment is r·u_i off the centre
            u, _ = design.directions(i)
            attachment = mechatron.frame_placement(delta, q, f"W{i + 1}").translation
            np.testing.assert_allclose(attachment - platform, design.platform_radius * u, atol=1e-12)


def test_velocity_is_the_derivative_of_the_forward_kinematics(delta):
    design = DeltaDesign()
    theta, rates = np.array([0.3, -0.1, 0.6]), np.array([0.8, -1.5, 0.4])
    q = mechatron.assemble(delta, dict(zip(delta.actuated, theta)))
    v = joint_velocity(delta, q, dict(zip(delta.actuated, rates)))
    h = 1e-6
    expected = (design.forward(theta + h * rates) - design.forward(theta - h * rates)) / (2 * h)
    np.testing.assert_allclose(point_velocity(delta, q, v, "TCP"), expected, atol=1e-8)


def test_motor_torques_balance_the_energy(delta):
    """Rest to rest, the motors' work ∫ τ·θ̇ dt equals the change of potential energy (the kinetic energy is zero at
    both ends)."""
    motion = move(None, [0.0, 0.0, 0.0], [0.6, 0.2, -0.3], profile="quintic", vmax=2.0, amax=10.0, dt=0.001)
    loads = trajectory_loads(delta, motion)
    table = loads.to_frame()
    power = sum(table[f"tau_{n}"] * table[f"qd_{n}"] for n in delta.actuated)
    work = np.trapezoid(power, table["t"])
    start = mechatron.assemble(delta, dict(zip(delta.actuated, motion.q[0])))
    end = mechatron.assemble(delta, dict(zip(delta.actuated, motion.q[-1])))
    change = potential_energy(delta, end) - potential_energy(delta, start)
    assert work == pytest.approx(change, rel=2e-4, abs=1e-5)


def test_size_chooses_the_three_motors(capsys):
    code = main(["size", "delta", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["feasible"]
    assert [j["joint"] for j in out["joints"]] == ["theta1", "theta2", "theta3"]
    assert all(j["motor"] for j in out["joints"])


def test_spatial_files_take_point_closures_only(tmp_path):
    text = (data_dir("robots") / "delta.toml").read_text()
    bad = tmp_path / "bad_delta.toml"
    pin = 'type = "pin"\npoint = "W3"\nbodies = ["rod3", "platform"]'
    assert pin in text
    bad.write_text(text.replace(pin, 'type = "slider"\npoint = "W3"\nline = "W2"'))
    with pytest.raises(InputError, match="spatial mechanism closes its loops with pins"):
        mechatron.load(bad)
    bad.write_text(text.replace('type = "translation"', 'type = "prismatic"', 1))
    with pytest.raises(InputError, match="joints.*spatial mechanism takes revolute, universal and translation"):
        mechatron.load(bad)

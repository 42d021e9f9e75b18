"""Joints with more than one configuration coordinate: a URDF arm with a continuous joint (q = (cos θ, sin θ)), a
revolute and a prismatic joint, checked against the same arm with the continuous joint made a revolute joint with
wide limits (q = θ), which Pinocchio treats as a plain vector space."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics import constrained as cd
from mechatron.dynamics.kinetostatics import kinetostatics
from mechatron.dynamics.motion import move, read_trajectory
from mechatron.dynamics.task import generic_task
from mechatron.model.urdf import export_urdf

ARM = Path(__file__).parent / "data" / "continuous_prismatic_arm.urdf"


@pytest.fixture(scope="module")
def arm() -> mechatron.Mechanism:
    return mechatron.load(str(ARM))


@pytest.fixture(scope="module")
def twin(tmp_path_factory) -> mechatron.Mechanism:
    """The same arm with ``spin`` a revolute joint limited to ±10 rad."""
    text = ARM.read_text().replace('type="continuous"', 'type="revolute"').replace(
        '<limit effort="50" velocity="3"/>', '<limit lower="-10" upper="10" effort="50" velocity="3"/>')
    path = tmp_path_factory.mktemp("twin") / "revolute_twin.urdf"
    path.write_text(text)
    return mechatron.load(str(path))


def states(mech, rng, n):
    """n random joint coordinates (θ over more than a turn) with velocities and accelerations."""
    coordinates = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-2, 2, n), rng.uniform(0, 0.3, n)])
    return coordinates, rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))


def test_the_continuous_joint_has_two_configuration_coordinates(arm, twin):
    assert (arm.nq, arm.nv, twin.nq, twin.nv) == (4, 3, 3, 3)
    assert [arm.joint_kind(j) for j in arm.joint_names] == ["revolute", "revolute", "prismatic"]
    assert arm.angular_coordinates().tolist() == [True, True, False]
    q = arm.configuration([math.radians(170), 0.4, 0.1])
    np.testing.assert_allclose(q, [math.cos(math.radians(170)), math.sin(math.radians(170)), 0.4, 0.1])
    # coordinates ∘ configuration is the identity, angles brought into (−π, π]
    np.testing.assert_allclose(arm.coordinates(arm.configuration([4.0, 0.4, 0.1])), [4.0 - 2 * math.pi, 0.4, 0.1],
                               atol=1e-12)


def test_random_configurations_give_unit_cos_sin_pairs(arm, rng):
    Q = arm.random_configuration(rng, 500)
    assert Q.shape == (500, 4)
    np.testing.assert_allclose(np.hypot(Q[:, 0], Q[:, 1]), 1.0, atol=1e-12)
    angles = np.arctan2(Q[:, 1], Q[:, 0])
    assert angles.min() < -2.5 and angles.max() > 2.5  # the whole circle, not a box in (cos, sin)
    assert np.all((Q[:, 2] >= -2) & (Q[:, 2] <= 2) & (Q[:, 3] >= 0) & (Q[:, 3] <= 0.3))
    assert all(not arm.limit_violations(q) for q in Q)
    # seeded from the numpy generator: the same seed gives the same configurations
    np.testing.assert_array_equal(arm.random_configuration(np.random.default_rng(5), 3),
                                  arm.random_configuration(np.random.default_rng(5), 3))


def test_forward_kinematics_equals_the_revolute_twin(arm, twin, rng):
    coordinates, _, _ = states(arm, rng, 20)
    for c in coordinates:
        q, q_twin = arm.configuration(c), twin.configuration(c)
        for frame in ("turret", "arm", "slide", "tool"):
            placement = mechatron.frame_placement(arm, q, frame)
            expected = mechatron.frame_placement(twin, q_twin, frame)
            np.testing.assert_allclose(placement.homogeneous, expected.homogeneous, atol=1e-12)
        np.testing.assert_allclose(mechatron.frame_jacobian(arm, q, "tool"), mechatron.frame_jacobian(twin, q_twin,
                                                                                                      "tool"),
                                   atol=1e-12)


def test_inverse_and_forward_dynamics_equal_the_revolute_twin(arm, twin, rng):
    coordinates, V, A = states(arm, rng, 100)  # a batch long enough for Pinocchio's parallel RNEA and ABA
    Q, Q_twin = arm.configuration(coordinates), twin.configuration(coordinates)
    tau = mechatron.inverse_dynamics(arm, Q, V, A)
    np.testing.assert_allclose(tau, mechatron.inverse_dynamics(twin, Q_twin, V, A), atol=1e-10)
    np.testing.assert_allclose(mechatron.forward_dynamics(arm, Q, V, tau), A, atol=1e-9)
    load = [mechatron.Load("tool", [5.0, -3.0, -20.0], [0.0, 1.0, 0.0])]
    for i in range(3):  # single states, with an external load
        np.testing.assert_allclose(mechatron.inverse_dynamics(arm, Q[i], V[i], A[i], load),
                                   mechatron.inverse_dynamics(twin, Q_twin[i], V[i], A[i], load), atol=1e-10)
        np.testing.assert_allclose(mechatron.dynamics.mass_matrix(arm, Q[i]), mechatron.dynamics.mass_matrix(
            twin, Q_twin[i]), atol=1e-12)


def test_simulation_of_the_free_arm_keeps_its_energy_and_follows_the_twin(arm, twin):
    """No drive, no damping: the mechanical energy stays constant while the continuous joint turns through ±π, and
    the motion is the revolute twin's (its angle unwrapped)."""
    c0, v0 = np.array([2.5, 0.3, 0.1]), np.array([3.0, -0.5, 0.2])
    sim = cd.simulate(arm, arm.configuration(c0), v0, 1.0, 2e-3)
    assert np.ptp(sim.coordinates[:, 0]) > 5.0  # wrapped at ±π: the joint turned past it
    np.testing.assert_allclose(np.hypot(sim.q[:, 0], sim.q[:, 1]), 1.0, atol=1e-12)
    assert np.abs(sim.energy - sim.energy[0]).max() / abs(sim.energy[0]) < 1e-6
    reference = cd.simulate(twin, c0, v0, 1.0, 2e-3)
    assert reference.q[:, 0].max() > math.pi  # the twin's angle went on past π
    np.testing.assert_allclose(np.unwrap(sim.coordinates[:, 0]), reference.q[:, 0], atol=1e-9)
    np.testing.assert_allclose(sim.coordinates[:, 1:], reference.q[:, 1:], atol=1e-9)


def test_a_move_through_plus_minus_170_degrees(arm, twin, tmp_path):
    """From −170° to +170°: the continuous joint turns 340° through 0 (its coordinate), not 20° through 180°."""
    start, end = [math.radians(-170), 0.0, 0.05], [math.radians(170), 0.5, 0.25]
    traj = move(arm, start, end, profile="quintic", vmax=2.0, amax=5.0, dt=0.002)
    spin = traj.coordinates[:, 0]
    assert np.all(np.diff(spin) >= 0) and np.abs(spin).min() < 0.01
    np.testing.assert_allclose(traj.q[:, :2], np.column_stack([np.cos(spin), np.sin(spin)]), atol=1e-12)
    assert traj.q.shape == (len(traj), 4) and traj.v.shape == (len(traj), 3)
    # the file has one column per joint coordinate, and reads back as the same motion
    frame = pd.read_csv(traj.to_csv(tmp_path / "spin.csv"))
    assert list(frame.columns[:4]) == ["t", "spin", "shoulder", "extend"]
    back = read_trajectory(tmp_path / "spin.csv", arm)
    np.testing.assert_allclose(back.q, traj.q, atol=1e-11)
    # the joint torques along it are the revolute twin's along the same coordinates
    twin_move = move(twin, start, end, profile="quintic", vmax=2.0, amax=5.0, dt=0.002)
    np.testing.assert_allclose(trajectory_loads(arm, traj).forces, trajectory_loads(twin, twin_move).forces,
                               atol=1e-10)


def test_dynamics_command_moves_the_continuous_joint(arm, twin, capsys):
    code = main(["dynamics", str(ARM), "--move", "-170,0,0.05;170,30,0.25", "--deg", "--vmax", "2", "--json"])
    out = capsys.readouterr().out
    assert code == 0
    rows = {row["coordinate"]: row for row in json.loads(out)["coordinates"]}
    start, end = np.radians([-170, 0]).tolist() + [0.05], np.radians([170, 30]).tolist() + [0.25]
    expected = trajectory_loads(twin, move(twin, start, end, vmax=2.0)).summary()
    for row in expected:
        assert rows[row["coordinate"]]["peak_force"] == pytest.approx(row["peak_force"], rel=1e-9)


def test_kinetostatics_and_tasks_of_the_continuous_arm(arm, twin):
    c = np.array([3.0, 0.4, 0.1])
    rates, accelerations = {"spin": 1.5, "shoulder": -0.5, "extend": 0.1}, {"spin": 2.0, "extend": -1.0}
    k = kinetostatics(arm, arm.configuration(c), rates, accelerations)
    k_twin = kinetostatics(twin, c, rates, accelerations)
    for name in arm.joint_names:
        assert k.driving[name] == pytest.approx(k_twin.driving[name], abs=1e-10)
        assert k.zhukovsky[name] == pytest.approx(k.driving[name], abs=1e-10)  # virtual power [Egorov, 5.18]
    task = generic_task(arm)
    assert task.trajectory.q.shape[1] == 4 and task.trajectory.coordinates.shape[1] == 3
    np.testing.assert_allclose(np.hypot(task.trajectory.q[:, 0], task.trajectory.q[:, 1]), 1.0, atol=1e-12)


def test_urdf_export_keeps_the_continuous_joint(arm, tmp_path, rng):
    (path,) = export_urdf(arm, tmp_path / "again.urdf")
    again = mechatron.load(str(path))
    assert (again.nq, again.nv) == (4, 3) and 'type="continuous"' in path.read_text()
    Q = arm.random_configuration(rng, 5)
    V, A = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    np.testing.assert_allclose(mechatron.inverse_dynamics(again, Q, V, A), mechatron.inverse_dynamics(arm, Q, V, A),
                               atol=1e-10)

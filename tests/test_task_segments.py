"""Loads per segment of a task: a payload picked at one waypoint and released at another (``payload_from``,
``payload_until``; mechatron.dynamics.segments). References: the inverse dynamics of the arm with and without the
payload over the whole motion (each sample's torque is the one of the body it carries at that moment), and the
static torques of a vertical 2R arm by hand, τ1 = g Σ m_i x_i, τ2 = g Σ_{beyond joint 2} m_i (x_i − x_2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.duty import joint_duties
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics.task import read_task
from mechatron.errors import InputError
from tests.boom import boom

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
G, M1, M2, L1, L2, PAYLOAD = 9.81, 2.0, 1.5, 0.5, 0.4, 3.0


@pytest.fixture()
def arm(tmp_path):
    """The planar 2R arm of robots/planar_2r.toml turned into a vertical plane (gravity −y)."""
    text = (ROOT / "robots" / "planar_2r.toml").read_text()
    path = tmp_path / "arm.toml"
    path.write_text(text.replace('convention = "standard"', 'convention = "standard"\ngravity = [0.0, -9.81, 0.0]'))
    return mechatron.load(str(path))


def task(tmp_path, text: str, name: str = "task.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def static_torques(q1: float, q2: float, payload: float) -> np.ndarray:
    """Hand: centres at mid-length of each link, the payload at the tip; x measured from joint 1."""
    c1, c12 = math.cos(q1), math.cos(q1 + q2)
    x2 = L1 * c1
    xs = [(M1, L1 / 2 * c1), (M2, x2 + L2 / 2 * c12), (payload, x2 + L2 * c12)]
    return np.array([G * sum(m * x for m, x in xs), G * sum(m * (x - x2) for m, x in xs[1:])])


def test_released_at_the_second_waypoint(arm, tmp_path):
    path = task(tmp_path, f"payload = {PAYLOAD}\npayload_until = 2\ndwell = 0.2\n"
                          "waypoints_deg = [[10, 20], [60, -30], [10, 20]]\n")
    t = read_task(path, arm)
    carried = t.schedule.carried
    runs = np.flatnonzero(np.all(t.trajectory.v == 0, axis=1))
    arrival = runs[1]  # the first sample at rest at waypoint 2
    assert carried[: arrival + 1].all() and not carried[arrival + 1:].any()
    segmented = trajectory_loads(t.unloaded, t.trajectory, payload=t.schedule).forces
    without = trajectory_loads(t.unloaded, t.trajectory).forces
    loaded = trajectory_loads(t.mechanism, t.trajectory).forces
    np.testing.assert_allclose(segmented[arrival + 1:], without[arrival + 1:], rtol=0, atol=1e-9)  # the return
    np.testing.assert_allclose(segmented[: arrival + 1], loaded[: arrival + 1], rtol=0, atol=1e-9)  # the way out
    assert np.abs(loaded[arrival + 1:] - without[arrival + 1:]).max() > 1.0  # the payload does weigh
    dwell = arrival + 5  # a sample of the dwell at waypoint 2 (released): the bare arm at rest, by hand
    np.testing.assert_allclose(segmented[dwell], static_torques(math.radians(60), math.radians(-30), 0.0),
                               rtol=0, atol=1e-9)
    duties = joint_duties(t.unloaded, t.trajectory, payload=t.schedule)
    bare = joint_duties(t.unloaded, t.trajectory)
    for d, b in zip(duties, bare):
        np.testing.assert_allclose(d.torque[arrival + 1:], b.torque[arrival + 1:], rtol=0, atol=1e-9)
        np.testing.assert_allclose(d.static_torque[arrival + 1:], b.static_torque[arrival + 1:], rtol=0, atol=1e-9)


def test_carried_through_an_intermediate_dwell(arm, tmp_path):
    """Picked at waypoint 1, released at 3: held in the dwell at 2 (static torque with the payload, by hand), not in
    the dwell at 3 (without it)."""
    path = task(tmp_path, f"payload = {PAYLOAD}\npayload_from = 1\npayload_until = 3\ndwell = 0.2\n"
                          "waypoints_deg = [[10, 20], [60, -30], [-20, 50], [10, 20]]\n")
    t = read_task(path, arm)
    tau = trajectory_loads(t.unloaded, t.trajectory, payload=t.schedule).forces
    rest = np.all(t.trajectory.v == 0, axis=1) & np.all(t.trajectory.a == 0, axis=1)
    at = {k: np.flatnonzero(rest & np.all(np.isclose(t.trajectory.q, np.radians(w)), axis=1))
          for k, w in ((2, [60, -30]), (3, [-20, 50]))}
    np.testing.assert_allclose(tau[at[2][2]], static_torques(math.radians(60), math.radians(-30), PAYLOAD),
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(tau[at[3][2]], static_torques(math.radians(-20), math.radians(50), 0.0),
                               rtol=0, atol=1e-9)
    assert t.schedule.label == "carried from waypoint 1 to waypoint 3"


def test_closed_loop_released(tmp_path):
    """A boom on a cylinder with 100 kg at its tip T, released at waypoint 2: the cylinder force on the return is
    that of the empty boom, on the way out that of the loaded one."""
    mech = mechatron.load(str(task(tmp_path, boom(), "boom.toml")))
    path = task(tmp_path, 'payload = 100.0\npayload_at = "T"\npayload_until = 2\nwaypoints = [[0.45], [0.65], '
                          '[0.45]]\nvmax = 0.1\namax = 0.2\n')
    t = read_task(path, mech)
    cut = np.flatnonzero(t.schedule.carried)[-1]
    segmented = trajectory_loads(t.unloaded, t.trajectory, payload=t.schedule).forces
    np.testing.assert_allclose(segmented[cut + 1:], trajectory_loads(mech, t.trajectory).forces[cut + 1:],
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(segmented[: cut + 1], trajectory_loads(t.mechanism, t.trajectory).forces[: cut + 1],
                               rtol=0, atol=1e-9)
    duty = joint_duties(t.unloaded, t.trajectory, payload=t.schedule)[0]
    np.testing.assert_allclose(duty.torque[cut + 1:], joint_duties(mech, t.trajectory)[0].torque[cut + 1:],
                               rtol=0, atol=1e-9)


def test_sizing_takes_the_schedule(arm, tmp_path):
    """``size`` of a segmented task sizes each joint for the torques of the arm with the payload on the way out and
    without it on the return (the duty it keeps: the loaded and the empty arm's RNEA, sample by sample)."""
    path = task(tmp_path, f"payload = {PAYLOAD}\npayload_until = 2\ndwell = 0.2\n"
                          "waypoints_deg = [[10, 20], [60, -30], [10, 20]]\n")
    result = mechatron.size(arm, path, single_pass=True)
    t = result.given
    cut = np.flatnonzero(t.schedule.carried)[-1]
    without = trajectory_loads(arm, t.trajectory).forces
    loaded = trajectory_loads(t.mechanism, t.trajectory).forces
    for j, sized in enumerate(result.joints):
        np.testing.assert_allclose(sized.duty.torque[cut + 1:], without[cut + 1:, j], rtol=0, atol=1e-9)
        np.testing.assert_allclose(sized.duty.torque[: cut + 1], loaded[: cut + 1, j], rtol=0, atol=1e-9)


@pytest.mark.parametrize("text, field, words", [
    ("payload = 1.0\npayload_until = 4\nwaypoints = [[0, 0], [1, 1], [0, 0]]\n", "payload_until",
     "1 <= payload_from < payload_until <= 3"),
    ("payload = 1.0\npayload_from = 2\npayload_until = 2\nwaypoints = [[0, 0], [1, 1], [0, 0]]\n", "payload_from",
     "payload_from < payload_until"),
    ("payload_until = 2\nwaypoints = [[0, 0], [1, 1], [0, 0]]\n", "payload_until", "needs a payload mass > 0"),
    ("payload = 1.0\npayload_until = 1.5\nwaypoints = [[0, 0], [1, 1]]\n", "payload_until", "whole number"),
    ("payload = 1.0\npayload_until = 3\nwaypoints = [[0, 0], [1, 1], [1, 1]]\n", "payload_until", "rests 2 times"),
])
def test_bad_span(arm, tmp_path, text, field, words):
    with pytest.raises(InputError) as info:
        read_task(task(tmp_path, text), arm)
    assert f"field '{field}'" in str(info.value) and words in str(info.value) and "\n" not in str(info.value)


def test_bad_span_cli(tmp_path, capsys):
    path = task(tmp_path, "payload = 1.0\npayload_until = 9\nwaypoints = [[0, 0], [1, 1], [0, 0]]\n")
    assert main(["size", "planar_2r", "--task", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "payload_until" in err and str(path.name) in err


def test_trajectory_file_has_no_waypoints(arm, tmp_path):
    (tmp_path / "m.csv").write_text("t,q1,q2\n0,0,0\n0.1,0.1,0.1\n")
    with pytest.raises(InputError, match="payload_from.*needs waypoints"):
        read_task(task(tmp_path, 'payload = 1.0\npayload_from = 1\ntrajectory = "m.csv"\n'), arm)

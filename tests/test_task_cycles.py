"""A task file's trajectory is made once per robot and waypoints (a study sizes thousands of designs on one task):
the remembered trajectory must equal the one made afresh, follow the joint limits it depends on, and not be
writable through any task that shares it."""

import numpy as np
import pytest

import mechatron
from mechatron.dynamics import task as task_module
from mechatron.dynamics.motion import cycle
from mechatron.dynamics.task import read_task

TASK = """
payload = 1.0
dwell = 0.1
waypoints_deg = [[0, 0, 0, 0, 0, 0], [30, -20, 10, 0, 20, 40], [0, 0, 0, 0, 0, 0]]
"""


@pytest.fixture
def task_file(tmp_path):
    path = tmp_path / "task.toml"
    path.write_text(TASK)
    return path


def _fresh(mech):
    points = [np.radians(w) for w in ([0] * 6, [30, -20, 10, 0, 20, 40], [0] * 6)]
    return cycle(mech, points, dwell=0.1)


def test_another_design_of_the_robot_gets_the_same_trajectory_as_made_afresh(task_file):
    puma = mechatron.load("puma560")
    longer = puma.with_parameters(a2=0.5)
    first, second = read_task(task_file, puma), read_task(task_file, longer)
    assert second.trajectory is first.trajectory  # made once
    fresh = _fresh(longer)
    for key in ("t", "q", "v", "a", "coordinates"):
        np.testing.assert_array_equal(getattr(second.trajectory, key), getattr(fresh, key))
    # the payload is the design's own: attached to the longer arm
    def placements(mech):
        return np.array([p.translation for p in mech.model.jointPlacements])

    assert second.mechanism.total_mass == pytest.approx(longer.total_mass + 1.0)
    np.testing.assert_array_equal(placements(second.mechanism), placements(longer))
    assert not np.allclose(placements(second.mechanism), placements(puma))


def test_other_velocity_limits_give_another_trajectory(task_file):
    puma = mechatron.load("puma560")
    slow = mechatron.load("puma560")
    slow.model.velocityLimit[:] = 0.5  # rad/s: the default vmax of the task, longer moves
    assert read_task(task_file, slow).duration == pytest.approx(_fresh(slow).duration)
    assert read_task(task_file, slow).duration > read_task(task_file, puma).duration + 0.1


def test_a_remembered_trajectory_cannot_be_changed_through_a_task(task_file):
    trajectory = read_task(task_file, mechatron.load("puma560")).trajectory
    with pytest.raises(ValueError, match="read-only"):
        trajectory.q[0, 0] = 1.0


def test_only_the_last_few_cycles_are_kept(task_file, tmp_path):
    puma = mechatron.load("puma560")
    for k in range(task_module._CYCLES_KEPT + 3):
        path = tmp_path / f"task{k}.toml"
        path.write_text(TASK.replace("dwell = 0.1", f"dwell = {0.1 + 0.01 * k}"))
        read_task(path, puma)
    assert len(task_module._CYCLES) == task_module._CYCLES_KEPT

"""Cartesian tasks (tool waypoints solved by inverse kinematics, issue 32) against hand references: the planar 2R
arm's closed-form inverse kinematics (both elbow branches), its hand Jacobian and acceleration, the hand
trapezoidal profile of the path length, and the planar 3R arm's closed form with the tool's orientation."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import mechatron
from mechatron.dynamics.task import read_task
from mechatron.errors import InputError
from mechatron.kinematics.frames import frame_position
from tests.corpus import assert_clean_error

ARM = """name = "arm2r"
[[links]]
joint = "revolute"
a = {l1}
mass = 2.0
com = [-0.25, 0.0, 0.0]
inertia = {{ xx = 1.8e-3, yy = 0.0425667, zz = 0.0425667 }}
[[links]]
joint = "revolute"
a = {l2}
mass = 1.5
com = [-0.2, 0.0, 0.0]
inertia = {{ xx = 9.375e-4, yy = 0.02046875, zz = 0.02046875 }}
"""

#: Two lines: 500 mm along +y, then 300 mm along −x, in the arm's plane; 0.5 m/s, 2 m/s², 0.1 s rests.
POINTS = np.array([[0.6, -0.2], [0.6, 0.3], [0.3, 0.3]])
V, A, DWELL = 0.5, 2.0, 0.1
TASK = """dwell = 0.1
dt = 0.01
[cartesian]
points_mm = [[600, -200, 0], [600, 300, 0], [300, 300, 0]]
seed_deg = {seed}
speed = 0.5
acceleration = 2.0
"""


def arm(tmp_path, l1=0.5, l2=0.4):
    path = tmp_path / f"arm_{l1}.toml"
    path.write_text(ARM.format(l1=l1, l2=l2))
    return mechatron.load(path)


def task(tmp_path, mech, seed="[-30, 60]", text=TASK, name="line.toml"):
    path = tmp_path / name
    path.write_text(text.format(seed=seed))
    return read_task(path, mech)


def trapezoid(tau, length):
    """Distance (m), speed (m/s) and acceleration (m/s²) along a line of ``length`` at time ``tau`` after its start,
    rest to rest at V and A (the hand trapezoid: accelerate for V/A, cruise, decelerate). Where the acceleration
    jumps at the ends, a sample takes the phase that begins there: A at the start, rest (0) at the end."""
    ta, T = V / A, length / V + V / A
    if tau >= T:
        return length, 0.0, 0.0
    if tau < ta:
        return A * tau**2 / 2, A * tau, A
    if tau <= T - ta:
        return V * tau - V**2 / (2 * A), V, 0.0
    r = T - tau
    return length - A * r**2 / 2, A * r, -A


def hand_path(t):
    """The tool's hand position, velocity and acceleration (2,) at time t: lines through POINTS, each timed by the
    hand trapezoid and followed by a rest of DWELL."""
    start = 0.0
    for a, b in zip(POINTS[:-1], POINTS[1:]):
        length = float(np.linalg.norm(b - a))
        T = length / V + V / A
        if t <= start + T + 1e-12:
            d, v, acc = trapezoid(min(max(t - start, 0.0), T), length)
            u = (b - a) / length
            return a + d * u, v * u, acc * u
        start += T
        if t <= start + DWELL + 1e-12:
            return b, np.zeros(2), np.zeros(2)
        start += DWELL
    raise AssertionError(f"t = {t} beyond the task")


def hand_ik(p, l1, l2, elbow=1.0):
    """q2 = ±acos((x²+y²−l1²−l2²)/(2 l1 l2)), q1 = atan2(y, x) − atan2(l2 sin q2, l1 + l2 cos q2)."""
    x, y = p
    q2 = elbow * math.acos((x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2))
    return np.array([math.atan2(y, x) - math.atan2(l2 * math.sin(q2), l1 + l2 * math.cos(q2)), q2])


def hand_rates(q, xd, xdd, l1, l2):
    """q̇ = J⁻¹ ẋ and q̈ = J⁻¹ (ẍ − J̇q̇) of the 2R arm, J and J̇q̇ by hand."""
    s1, c1, s12, c12 = math.sin(q[0]), math.cos(q[0]), math.sin(q[0] + q[1]), math.cos(q[0] + q[1])
    J = np.array([[-l1 * s1 - l2 * s12, -l2 * s12], [l1 * c1 + l2 * c12, l2 * c12]])
    qd = np.linalg.solve(J, xd)
    w1, w12 = qd[0], qd[0] + qd[1]
    drift = np.array([-l1 * c1 * w1**2 - l2 * c12 * w12**2, -l1 * s1 * w1**2 - l2 * s12 * w12**2])
    return qd, np.linalg.solve(J, xdd - drift)


@pytest.mark.parametrize("seed, elbow", [("[-30, 60]", 1.0), ("[30, -60]", -1.0)])
def test_straight_lines_match_the_hand_inverse_kinematics(tmp_path, seed, elbow):
    mech = arm(tmp_path)
    trajectory = task(tmp_path, mech, seed).trajectory
    # the duration of the hand trapezoids: 0.5/0.5 + 0.25 and 0.3/0.5 + 0.25, plus two rests
    assert trajectory.duration == pytest.approx(1.25 + 0.85 + 2 * DWELL, abs=1e-12)
    assert np.max(np.diff(trajectory.t)) <= 0.01 + 1e-12
    for t, q, qd, qdd in zip(trajectory.t, trajectory.q, trajectory.v, trajectory.a):
        p, xd, xdd = hand_path(t)
        expected = hand_ik(p, 0.5, 0.4, elbow)
        np.testing.assert_allclose(q, expected, rtol=0, atol=1e-9)  # every sample, on the seed's branch
        hand_qd, hand_qdd = hand_rates(expected, xd, xdd, 0.5, 0.4)
        np.testing.assert_allclose(qd, hand_qd, rtol=0, atol=1e-9)
        # where s̈ jumps (the phases' ends), either side's value: the hand accelerations 1e-12 s before and after
        sides = [hand_rates(expected, xd, hand_path(t + e)[2], 0.5, 0.4)[1] for e in (-1e-12, 0.0, 1e-12)]
        assert min(np.max(np.abs(qdd - side)) for side in sides) < 1e-8
    assert np.all(np.sign(trajectory.q[:, 1]) == elbow)  # the branch is kept along the whole task


@pytest.mark.parametrize("how", ["file", "parameter"])
def test_a_longer_first_link_keeps_the_tool_path(tmp_path, how):
    original = arm(tmp_path)
    longer = arm(tmp_path, l1=0.6) if how == "file" else original.with_parameters(a1=0.6)
    before, after = (task(tmp_path, m).trajectory for m in (original, longer))
    np.testing.assert_allclose(after.t, before.t, rtol=0, atol=1e-12)  # the same timing: it is the tool's
    tool = frame_position(longer, after.q)
    for t, position, q in zip(after.t, tool, after.q):
        p = hand_path(t)[0]
        np.testing.assert_allclose(position, [*p, 0.0], rtol=0, atol=1e-9)
        np.testing.assert_allclose(q, hand_ik(p, 0.6, 0.4), rtol=0, atol=1e-9)
    assert np.max(np.abs(after.q - before.q)) > 0.05  # the joints do change


def test_an_unreachable_waypoint_names_it_and_the_residual(tmp_path):
    mech = arm(tmp_path)
    text = TASK.replace("[300, 300, 0]]", "[1000, 0, 0]]")  # 1.0 m from the base: 0.1 m beyond l1 + l2
    with pytest.raises(InputError) as caught:
        task(tmp_path, mech, text=text, name="far.toml")
    message = str(caught.value)
    assert "far.toml: field 'cartesian.points_mm[3]': unreachable" in message and "\n" not in message
    residual = float(re.search(r"than ([0-9.]+) mm", message).group(1))
    assert residual == pytest.approx(1000.0 - 900.0, abs=1e-4)


def test_a_line_through_the_inner_hole_is_refused(tmp_path):
    # the inner boundary is a circle of radius l1 − l2 = 0.1 m: the line y = 0.05 m enters it at x = ±0.0866 m
    mech = arm(tmp_path)
    text = TASK.replace("[[600, -200, 0], [600, 300, 0], [300, 300, 0]]", "[[300, 50, 0], [-300, 50, 0]]")
    with pytest.raises(InputError, match=r"points_mm\[2\]': unreachable: the line .* leaves the reach .* at "
                                         r"(3[5-6][.0-9]*) %"):
        task(tmp_path, mech, seed="[60, 120]", text=text, name="hole.toml")


def test_joint_speed_limits_slow_the_line_down(tmp_path):
    mech = arm(tmp_path)
    free = task(tmp_path, mech).trajectory
    text = TASK.replace("dt = 0.01", "dt = 0.002\nvmax_deg = 30")
    slow = task(tmp_path, mech, text=text, name="slow.toml").trajectory
    assert np.max(np.abs(free.v)) > math.radians(30)
    peak = np.max(np.abs(slow.v))
    assert peak <= math.radians(30) * (1 + 1e-3) and peak >= math.radians(30) * 0.98
    # slowed down as a whole, the path is the same: every sample on the hand lines
    for position in frame_position(mech, slow.q):
        distances = [np.linalg.norm(np.cross([*(b - a), 0], position - [*a, 0])) / np.linalg.norm(b - a)
                     for a, b in zip(POINTS[:-1], POINTS[1:])]
        assert min(distances) < 1e-9


PLANAR_3R = """name = "arm3r"
[[links]]
joint = "revolute"
a = 0.5
mass = 1.0
[[links]]
joint = "revolute"
a = 0.4
mass = 1.0
[[links]]
joint = "revolute"
a = 0.1
mass = 0.5
"""


def test_orientations_follow_the_hand_closed_form_of_a_3r_arm(tmp_path):
    (tmp_path / "arm3r.toml").write_text(PLANAR_3R)
    mech = mechatron.load(tmp_path / "arm3r.toml")
    (tmp_path / "turn.toml").write_text("""dt = 0.01
[cartesian]
points_mm = [[600, -100, 0], [600, 200, 0]]
rpy_deg = [[0, 0, -20], [0, 0, 40]]
seed_deg = [-30, 60, 0]
speed = 0.5
acceleration = 2.0
angular_speed_deg = 90
angular_acceleration_deg = 360
""")
    trajectory = read_task(tmp_path / "turn.toml", mech).trajectory
    # ṡ ≤ min(0.5/0.3, 90°/60°) = 1.5 /s, s̈ ≤ min(2/0.3, 360°/60°) = 6 /s²: T = 1/1.5 + 1.5/6
    assert trajectory.duration == pytest.approx(1 / 1.5 + 1.5 / 6, abs=1e-12)
    for t, q in zip(trajectory.t, trajectory.q):
        T, ta = 1 / 1.5 + 1.5 / 6, 1.5 / 6
        s = 3 * t**2 if t < ta else (1.5 * t - 1.5**2 / 12 if t <= T - ta else 1 - 3 * (T - t) ** 2)
        phi = math.radians(-20 + 60 * s)
        wrist = np.array([0.6, -0.1 + 0.3 * s]) - 0.1 * np.array([math.cos(phi), math.sin(phi)])
        q12 = hand_ik(wrist, 0.5, 0.4)
        np.testing.assert_allclose(q, [*q12, phi - q12.sum()], rtol=0, atol=1e-9)


@pytest.mark.parametrize("table, message", [
    ('points_mm = [[600, 0, 0]]\nspeed = 1\nacceleration = 1', "'cartesian.points_mm': give a list of at least two"),
    ('points_mm = [[600, 0], [0, 600, 0]]\nspeed = 1\nacceleration = 1', "'cartesian.points_mm[1]': expected 3"),
    ('points = [[0.6, 0, 0], [0, 0.6, 0]]\nspeed = 1', "'cartesian.acceleration': missing required field"),
    ('points = [[0.6, 0, 0], [0, 0.6, 0]]\nspeed = 1\nacceleration = 1\nseed_deg = [1, 2, 3]',
     "'cartesian.seed_deg': expected a list of 2 numbers, got 3"),
    ('points = [[0.6, 0, 0], [0, 0.6, 0]]\nspeed = 1\nacceleration = 1\nframe = "hand"',
     "'cartesian.frame': unknown frame"),
    ('points = [[0.6, 0, 0], [0, 0.6, 0]]\nrpy = [[0, 0, 0], [0, 0, 1]]\nspeed = 1\nacceleration = 1',
     "'cartesian.points[2]': the orientation changes: give angular_speed"),
])
def test_bad_cartesian_fields_name_the_field(tmp_path, table, message):
    mech = arm(tmp_path)
    (tmp_path / "bad.toml").write_text("[cartesian]\n" + table + "\n")
    with pytest.raises(InputError) as caught:
        read_task(tmp_path / "bad.toml", mech)
    assert message in str(caught.value) and str(caught.value).startswith(str(tmp_path / "bad.toml"))


def test_joint_waypoints_next_to_cartesian_ones_are_refused(tmp_path):
    mech = arm(tmp_path)
    (tmp_path / "both.toml").write_text("waypoints = [[0, 0], [1, 1]]\n[cartesian]\npoints = [[0.6, 0, 0], "
                                        "[0, 0.6, 0]]\nspeed = 1\nacceleration = 1\n")
    with pytest.raises(InputError, match="both.toml: field 'cartesian': give either tool waypoints"):
        read_task(tmp_path / "both.toml", mech)


def test_a_closed_loop_is_refused(tmp_path):
    (tmp_path / "c.toml").write_text("[cartesian]\npoints = [[0.6, 0, 0], [0, 0.6, 0]]\nspeed = 1\n"
                                     "acceleration = 1\n")
    with pytest.raises(InputError, match="c.toml: field 'cartesian.frame': .* closed loops"):
        read_task(tmp_path / "c.toml", mechatron.load("crank_slider"))


def test_the_shipped_example_lasts_its_hand_trapezoids():
    from pathlib import Path

    example = Path(__file__).resolve().parent.parent / "examples" / "data" / "cartesian_line.toml"
    mech = mechatron.load("planar_2r")  # l1 = 0.5 m, l2 = 0.4 m
    task_ = read_task(example, mech)
    lengths = [0.5, 0.3, math.hypot(0.3, 0.5)]  # the lines between its points, m; 0.5 m/s, 2 m/s², 0.2 s rests
    assert task_.duration == pytest.approx(sum(L / 0.5 + 0.5 / 2 for L in lengths) + 3 * 0.2, abs=1e-12)
    assert task_.payload == 1.0
    assert np.all(task_.trajectory.q[:, 1] > 0)  # elbow down, as seeded
    tool = frame_position(mech, task_.trajectory.q)
    np.testing.assert_allclose(tool[-1], [0.6, -0.2, 0.0], rtol=0, atol=1e-9)
    assert np.max(np.abs(task_.trajectory.v)) < math.radians(120)


def test_the_command_line_names_the_unreachable_waypoint_and_exits_2(tmp_path, capfd):
    (tmp_path / "far.toml").write_text(TASK.format(seed="[-30, 60]").replace("[300, 300, 0]]", "[1000, 0, 0]]"))
    assert_clean_error(["size", "planar_2r", "--task", "far.toml"], capfd, tmp_path,
                       ["far.toml: field 'cartesian.points_mm[3]': unreachable", "than 100 mm"])

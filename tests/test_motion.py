"""Motion profiles, synchronised moves, cycles and trajectory files."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.dynamics.motion import PROFILES, cycle, make_profile, move, read_trajectory


def derivatives(profile, n=200_001):
    t = np.linspace(0.0, profile.duration, n)
    s, ds, dds = profile.evaluate(t)
    return t, s, ds, dds


@pytest.mark.parametrize("kind", PROFILES)
def test_profiles_are_consistent_and_within_limits(kind):
    v, a, j = 2.0, 10.0, 100.0
    profile = make_profile(kind, v, a, j)
    t, s, ds, dds = derivatives(profile)
    assert s[0] == 0 and s[-1] == pytest.approx(1.0, abs=1e-12)
    assert ds[0] == 0 and ds[-1] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(np.gradient(s, t), ds, atol=2e-4)  # ṡ is the derivative of s
    assert ds.max() <= (math.inf if kind == "triangular" else v) + 1e-9
    assert np.abs(dds).max() <= a + 1e-9
    if kind == "scurve":
        assert np.abs(np.gradient(dds, t)[5:-5]).max() <= j * (1 + 1e-6)


def test_closed_form_durations():
    assert make_profile("triangular", 1.0, 4.0).duration == pytest.approx(2 * math.sqrt(1 / 4))  # 2√(D/a)
    assert make_profile("trapezoidal", 2.0, 10.0).duration == pytest.approx(1 / 2 + 2 / 10)  # D/v + v/a
    assert make_profile("trapezoidal", 20.0, 10.0).duration == pytest.approx(2 / math.sqrt(10))  # triangular
    assert make_profile("quintic", 2.0, 100.0).duration == pytest.approx(15 / 16)  # 15D/(8v)
    # double S with both limits reached: T = D/v + v/a + a/j
    assert make_profile("scurve", 2.0, 10.0, 100.0).duration == pytest.approx(1 / 2 + 2 / 10 + 10 / 100)
    # stretched to a longer duration, same shape
    assert make_profile("trapezoidal", 2.0, 10.0, duration=3.0).duration == pytest.approx(3.0)


def test_synchronised_move_respects_every_axis():
    mech = mechatron.load("puma560")
    start, end = np.zeros(6), np.array([1.0, -0.5, 0.25, 2.0, 0.0, -1.0])
    vmax, amax = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0]), np.array([4.0, 4.0, 4.0, 8.0, 8.0, 8.0])
    traj = move(mech, start, end, profile="trapezoidal", vmax=vmax, amax=amax, dt=0.001)
    np.testing.assert_allclose(traj.q[0], start)
    np.testing.assert_allclose(traj.q[-1], end, atol=1e-12)
    assert np.all(np.abs(traj.v).max(axis=0) <= vmax + 1e-9)
    assert np.all(np.abs(traj.a).max(axis=0) <= amax + 1e-9)
    # the straight line in joint space: every axis covers the same fraction at every time
    fraction = (traj.q - start)[:, 0] / end[0]
    np.testing.assert_allclose((traj.q - start)[:, 3] / end[3], fraction, atol=1e-12)
    # axis 4 limits (2 rad at 2 rad/s) and axis 1 (1 rad at 1 rad/s) both give T = 1/1 + 1/4
    assert traj.t[-1] == pytest.approx(1.25, abs=1e-3)


def test_cycle_with_dwells_and_csv_round_trip(tmp_path):
    mech = mechatron.load("planar_2r")
    traj = cycle(mech, [[0, 0], [1, -1], [0.5, 0.5]], dwell=0.2, profile="quintic", vmax=2, amax=10, dt=0.002)
    resting = np.all(traj.v == 0, axis=1)
    assert resting.sum() >= 2 * 0.2 / 0.002 - 2  # two dwells
    path = traj.to_csv(tmp_path / "cycle.csv")
    back = read_trajectory(path, mech)
    np.testing.assert_allclose(back.q, traj.q, atol=1e-11)
    np.testing.assert_allclose(back.a, traj.a, atol=1e-9)
    # a file with positions only: velocities and accelerations by differentiation
    frame = traj.to_frame()[["t", "q1", "q2"]]
    frame.to_csv(tmp_path / "positions.csv", index=False)
    derived = read_trajectory(tmp_path / "positions.csv", mech)
    middle = slice(10, -10)
    np.testing.assert_allclose(derived.v[middle], traj.v[middle], atol=1e-3)
    # comments (lines starting with #) are read like the other CSV files
    commented = tmp_path / "commented.csv"
    commented.write_text("# a planar 2R move, rad\n" + (tmp_path / "positions.csv").read_text())
    np.testing.assert_array_equal(read_trajectory(commented, mech).q, derived.q)


@pytest.mark.parametrize("text,pieces", [
    ("q1,q2\n0,0\n", ["missing column", "'t'"]),
    ("t,q1\n0,0\n1,1\n", ["q2"]),
    ("t,q1,q2\n0,0,0\n0.1,abc,0\n", ["row 3", "'q1'", "abc"]),
    ("t,q1,q2\n0,0,0\n0,1,1\n", ["times must increase", "row 3"]),
    ("t,q1,q2\n0,0,0\n", ["at least two rows"]),
])
def test_bad_trajectory_files(tmp_path, text, pieces):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(mechatron.InputError) as info:
        read_trajectory(path, mechatron.load("planar_2r"))
    for piece in pieces:
        assert piece in str(info.value)
    assert "bad.csv" in str(info.value)


def test_bad_profile_and_limits():
    with pytest.raises(mechatron.InputError, match="unknown profile"):
        make_profile("sine", 1, 1)
    with pytest.raises(mechatron.InputError, match="acceleration limit"):
        make_profile("trapezoidal", 1, -1)

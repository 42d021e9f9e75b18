"""``mechatron dynamics --reactions``: the force and moment each joint transmits (mechatron.dynamics.joint_reactions).
References: free-body diagrams of a vertical 2R arm by hand — at rest the base joint carries the whole weight,
F = (m1 + m2 + m_p) g upwards, and the moment M_z = g Σ m_i x_i; in motion Newton's law for the links beyond each
joint, F = Σ m_i (c̈_i − g), with the centres' accelerations by hand, c̈ = l (θ̈ e⊥ − θ̇² e)."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.dynamics.joint_reactions import joint_reactions
from mechatron.dynamics.motion import cycle
from mechatron.model.payload import with_payload
from tests.protocol import check_result

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
G, M1, M2, L1, L2 = 9.81, 2.0, 1.5, 0.5, 0.4


@pytest.fixture()
def arm_file(tmp_path):
    """robots/planar_2r.toml in a vertical plane (gravity −y)."""
    text = (ROOT / "robots" / "planar_2r.toml").read_text()
    path = tmp_path / "arm.toml"
    path.write_text(text.replace('convention = "standard"', 'convention = "standard"\ngravity = [0.0, -9.81, 0.0]'))
    return path


def test_static_free_body(arm_file):
    mech = with_payload(mechatron.load(str(arm_file)), 1.2)  # 1.2 kg at the tool (the tip)
    q1, q2 = math.radians(30), math.radians(40)
    result = joint_reactions(mech, cycle(mech, [[q1, q2], [q1, q2]]))
    c1, c12 = math.cos(q1), math.cos(q1 + q2)
    x2 = L1 * c1
    masses = [(M1, L1 / 2 * c1), (M2, x2 + L2 / 2 * c12), (1.2, x2 + L2 * c12)]
    base, elbow = result.wrenches[0]
    np.testing.assert_allclose(base, [0, G * (M1 + M2 + 1.2), 0, 0, 0, G * sum(m * x for m, x in masses)],
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(elbow, [0, G * (M2 + 1.2), 0, 0, 0, G * sum(m * (x - x2) for m, x in masses[1:])],
                               rtol=0, atol=1e-9)
    check_result(result)


def test_moving_newton(arm_file):
    """Along a move the force each joint transmits is Σ m (c̈ − g) of the links beyond it (centres by hand)."""
    mech = mechatron.load(str(arm_file))
    motion = cycle(mech, [[0.2, 0.3], [1.1, -0.6]], vmax=2.0, amax=6.0, dt=0.01)
    result = joint_reactions(mech, motion)
    q1, q2 = motion.q.T
    w1, w2 = motion.v.T
    a1, a2 = motion.a.T

    def acceleration(l, th, w, a):
        e, n = np.stack([np.cos(th), np.sin(th)], 1), np.stack([-np.sin(th), np.cos(th)], 1)
        return l * (a[:, None] * n - (w**2)[:, None] * e)

    elbow = acceleration(L1, q1, w1, a1)  # joint 2's origin
    c1 = acceleration(L1 / 2, q1, w1, a1)
    c2 = elbow + acceleration(L2 / 2, q1 + q2, w1 + w2, a1 + a2)
    g = np.array([0.0, -G])
    np.testing.assert_allclose(result.wrenches[:, 0, :2], M1 * (c1 - g) + M2 * (c2 - g), rtol=0, atol=1e-9)
    np.testing.assert_allclose(result.wrenches[:, 1, :2], M2 * (c2 - g), rtol=0, atol=1e-9)
    frame = result.to_frame()
    assert list(frame.columns[:7]) == ["t", "q1_Fx", "q1_Fy", "q1_Fz", "q1_Mx", "q1_My", "q1_Mz"]


def test_cli(arm_file, tmp_path, capsys):
    csv = tmp_path / "r.csv"
    assert main(["dynamics", str(arm_file), "--move", "30,40;30,40", "--deg", "--reactions", "--json",
                 "--csv", str(csv)]) == 0
    data = json.loads(capsys.readouterr().out)
    c1, c12 = math.cos(math.radians(30)), math.cos(math.radians(70))
    moment = G * (M1 * L1 / 2 * c1 + M2 * (L1 * c1 + L2 / 2 * c12))
    np.testing.assert_allclose(data["joints"]["q1"]["force_N"][0], [0, G * (M1 + M2), 0], atol=1e-9)
    np.testing.assert_allclose(data["joints"]["q1"]["moment_Nm"][0], [0, 0, moment], atol=1e-9)
    frame = pd.read_csv(csv)
    assert frame["q1_Fy"].iloc[0] == pytest.approx(G * (M1 + M2), abs=1e-9)
    assert main(["dynamics", str(arm_file), "--move", "30,40;30,40", "--deg", "--reactions"]) == 0
    text = capsys.readouterr().out
    assert "Fy (N)" in text and "34.335" in text


def test_closed_loop_balance(tmp_path):
    """A boom on a cylinder at rest: the cylinder's prismatic joint transmits along its axis the actuator force that
    the sizing's constrained inverse dynamics finds by virtual work (trajectory_loads), a second computation."""
    import pinocchio as pin

    from mechatron.drives.loads import trajectory_loads
    from mechatron.dynamics.trajectory import closed_loop_states
    from tests.boom import boom

    path = tmp_path / "boom.toml"
    path.write_text(boom())
    mech = mechatron.load(str(path))
    pose = cycle(None, [[0.55], [0.55]])
    result = joint_reactions(mech, pose)
    check_result(result)
    force = trajectory_loads(mech, pose).forces[0, 0]
    lift = result.joints.index("lift")
    q = closed_loop_states(mech, pose)[0][0]
    data = mech.model.createData()
    pin.forwardKinematics(mech.model, data, q)
    j = mech.model.getJointId("lift")
    assert mech.model.joints[j].shortname() == "JointModelPX"
    axis = data.oMi[j].rotation @ np.array([1.0, 0.0, 0.0])  # the cylinder's axis in world axes
    assert abs(result.wrenches[0, lift, :3] @ axis) == pytest.approx(abs(force), rel=1e-9)


# ------------------------------------------------------------------ all samples at once (batched_reactions)
def _random_states(mech, rng, count):
    """``count`` random states of a closed loop: positions along its generic task, random input rates (±1) and
    accelerations (±5) with the dependent coordinates' by the loops' velocity and acceleration analysis."""
    from mechatron.dynamics.task import generic_task
    from mechatron.dynamics.trajectory import closed_loop_states
    from mechatron.kinematics.loops import joint_acceleration, joint_velocity

    Q = closed_loop_states(mech, generic_task(mech).trajectory)[0]
    Q = Q[rng.choice(len(Q), count, replace=False)]
    V = np.array([joint_velocity(mech, q, {n: rng.uniform(-1, 1) for n in mech.actuated}) for q in Q])
    A = np.array([joint_acceleration(mech, q, v, {n: rng.uniform(-5, 5) for n in mech.actuated})
                  for q, v in zip(Q, V)])
    return Q, V, A


def _state_by_state(mech, Q, V, A, loads):
    """The reference: the constrained inverse dynamics and one Pinocchio RNEA pass (data.f) per state."""
    from mechatron.dynamics import constrained as cd

    states = [cd.reactions(mech, q, v, a, cd.inverse(mech, q, v, a, loads)[1], loads) for q, v, a in zip(Q, V, A)]
    return np.array([s.joints for s in states]), {k: np.array([s.pins[k] for s in states]) for k in states[0].pins}


@pytest.mark.parametrize(("name", "loads"), [
    ("robots/six_bar_bucket.toml", [("K", [2000.0, -5000.0, 0.0])]),
    ("crank_slider", [("C@slider", [1000.0, 0.0, 0.0], [0.0, 0.0, 30.0])]),
    ("examples/data/scissor_lift.toml", None),  # pins and two sliders
    ("front_shovel", [("K", [1.0e4, -2.0e4, 0.0])]),
])
def test_batched_matches_state_by_state(name, loads, rng):
    """At random states the batched Newton–Euler balance gives Pinocchio's RNEA wrenches and the per-state
    multipliers to rounding (relative 1e-9 of the largest value)."""
    from mechatron.dynamics.batched_reactions import reactions_at

    mech = mechatron.load(str(ROOT / name) if "/" in name else name)
    Q, V, A = _random_states(mech, rng, 40)
    wrenches, pins = reactions_at(mech, Q, V, A, loads)
    reference, reference_pins = _state_by_state(mech, Q, V, A, loads)
    np.testing.assert_allclose(wrenches, reference, rtol=0, atol=1e-9 * np.abs(reference).max())
    assert list(pins) == list(reference_pins)
    scale = max(np.abs(p).max() for p in reference_pins.values())
    for key, value in reference_pins.items():
        np.testing.assert_allclose(pins[key], value, rtol=0, atol=1e-9 * scale)


@pytest.fixture()
def crank_states():
    from mechatron.kinematics.loops import assemble, joint_acceleration, joint_velocity

    mech = mechatron.load("crank_slider")
    rows = []
    for angle, rate, accel in [(30, 10.0, 0.0), (75, -3.0, 40.0)] * 3:
        q = assemble(mech, {"q1": math.radians(angle)})
        v = joint_velocity(mech, q, {"q1": rate})
        rows.append((q, v, joint_acceleration(mech, q, v, {"q1": accel})))
    return (mech, *(np.array(x) for x in zip(*rows)))


def test_batched_crank_slider_free_body(crank_states):
    """The crank-slider of tests/test_closed_loop_dynamics.py worked by hand ([Egorov, 5.6]: l1 = 0.1, L2 = 0.4 m,
    q1 = 30°, q̇1 = 10 rad/s, q̈1 = 0, 1000 N on the slider): the pin force on the rod at C, the crank's force on
    the rod at B, the guide's force on the slider and the crank's moment at A — at every one of several copies of
    the state, batched with other states."""
    from mechatron.dynamics.batched_reactions import reactions_at

    mech, Q, V, A = crank_states
    wrenches, pins = reactions_at(mech, Q, V, A, [("C@slider", [1000.0, 0.0, 0.0])])
    hand = slice(0, None, 2)  # the even rows are the hand-worked state
    np.testing.assert_allclose(pins["C=C@slider"][hand], np.tile([1009.9501, -120.2979], (3, 1)), atol=1e-4)
    np.testing.assert_allclose(wrenches[hand, 1, :2], np.tile([-1028.5605, 134.9179], (3, 1)), atol=1e-4)
    np.testing.assert_allclose(wrenches[hand, 2, 1], -110.4879, atol=1e-4)
    np.testing.assert_allclose(wrenches[hand, 0, 5], 63.112255, atol=1e-6)


def test_joint_reactions_closed_loop_trajectory():
    """Along a move of the six-bar bucket (its cylinder 1.1 → 2.0 m) with a payload at K, the result equals the
    state-by-state reference at every sample."""
    from mechatron.dynamics.trajectory import closed_loop_states

    mech = with_payload(mechatron.load("six_bar_bucket"), 800.0, "K")
    motion = cycle(None, [[1.1], [2.0]], vmax=0.2, amax=0.5, dt=0.02)
    result = joint_reactions(mech, motion)
    reference, pins = _state_by_state(mech, *closed_loop_states(mech, motion), None)
    np.testing.assert_allclose(result.wrenches, reference, rtol=0, atol=1e-9 * np.abs(reference).max())
    for key, value in pins.items():
        np.testing.assert_allclose(result.pins[key], value, rtol=0, atol=1e-9 * np.abs(value).max())
    check_result(result)


def test_serial_batched_matches_rnea(rng):
    """A PUMA 560 with a force and a moment at its tool, at random states: Pinocchio's RNEA wrenches (data.f)."""
    from mechatron.dynamics.batched_reactions import reactions_at
    from mechatron.dynamics.tree import transmitted_wrenches

    mech = mechatron.load("puma560")
    Q = rng.uniform(-2, 2, (30, mech.nq))
    V, A = rng.uniform(-2, 2, (30, mech.nv)), rng.uniform(-8, 8, (30, mech.nv))
    loads = [("tool", [10.0, -20.0, 5.0], [1.0, 2.0, 3.0])]
    wrenches, pins = reactions_at(mech, Q, V, A, loads)
    reference = np.array([transmitted_wrenches(mech, q, v, a, loads) for q, v, a in zip(Q, V, A)])
    np.testing.assert_allclose(wrenches, reference, rtol=0, atol=1e-9 * np.abs(reference).max())
    assert pins == {}

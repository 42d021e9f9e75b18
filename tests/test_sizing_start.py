"""A sizing started from another design's drives (``start``, what a study passes from one design to the next) reaches
the same fixed point as one started from weightless drives, wherever each drive loads only coordinates sized after it;
elsewhere the start is not used.

The reason (``mechatron.drives.system.size_mechanism``): in a serial arm a joint's torque τ_k = S_kᵀ Σ_{i ∈
subtree(k)} f_i and its inertia M_kk involve only the bodies it moves, and the drive of joint j sits on body j − 1, so
a distal-first pass that mounts each choice at once sizes every joint with its final load. The references here are
the sizing without a start — itself checked against the PUMA with its drives put in by hand
(tests/test_system_sizing.py) — and the definition of the fixed point: the duties of the arm with the chosen drives
mounted."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_system_sizing import MOTORS, NO_GEARBOX, swing, two_link

import mechatron
from mechatron.drives.duty import drive_carrier, joint_duties, mount_drives
from mechatron.drives.sizing import size_mechanism
from mechatron.drives.system import distal_first, keep_arrays, sees_every_drive
from mechatron.model.dh import Drive

SCISSOR = Path(__file__).resolve().parent.parent / "examples" / "data" / "scissor_lift.toml"


def _design(mech, factor):
    return mech.with_parameters({"a2": mech.dh.links[1].a * factor, "d4": mech.dh.links[3].d * factor})


def _carriers(mech):
    return {n: drive_carrier(mech, n) for n in mech.joint_names}


def _same(a, b):
    """Every joint's choice and every check's value and limit, exactly."""
    assert [j.choice() for j in a.joints] == [j.choice() for j in b.joints]
    for x, y in zip(a.joints, b.joints):
        assert [(c.name, c.value, c.limit) for c in x.checks] == [(c.name, c.value, c.limit) for c in y.checks]
        assert np.array_equal(x.duty.torque, y.duty.torque)
    assert a.totals() == b.totals() and a.feasible == b.feasible and a.converged and b.converged


def test_a_start_from_another_puma_design_gives_the_same_drives():
    puma = mechatron.load("puma560")
    short, long = _design(puma, 0.9), _design(puma, 1.1)
    guess = {j.joint: j for j in mechatron.size(long).joints}
    reference = mechatron.size(short)
    assert [j.choice() for j in reference.joints] != [guess[j.joint].choice() for j in reference.joints]
    started = mechatron.size(short, start=guess)
    _same(started, reference)
    # pass 1 is weighted and already the fixed point; pass 2 only confirms it
    assert [i.weighted for i in started.iterations] == [True, True] and started.iterations[-1].changes == ()
    assert [i.weighted for i in reference.iterations][0] is False


def test_the_started_duties_are_those_of_the_arm_with_its_chosen_drives():
    """The fixed point by its definition: each joint's duty is the inverse dynamics of the arm (with the task's part)
    carrying every chosen drive's catalog mass on its parent link at its joint."""
    puma = mechatron.load("puma560")
    short = _design(puma, 0.9)
    guess = {j.joint: j for j in mechatron.size(_design(puma, 1.1)).joints}
    result = mechatron.size(short, start=guess)
    task = result.given
    loaded = joint_duties(mount_drives(task.mechanism, list(result.mounts.values())), task.trajectory, task.loads)
    for joint, duty in zip(result.joints, loaded):
        assert np.allclose(joint.duty.torque, duty.torque, rtol=1e-12, atol=1e-12), joint.joint


def test_which_mechanisms_a_start_serves():
    puma = mechatron.load("puma560")
    order = distal_first(puma, list(puma.joint_names))
    assert sees_every_drive(puma, order, _carriers(puma))
    assert not sees_every_drive(puma, order[::-1], _carriers(puma))  # proximal first: a drive loads a joint sized
    arm = two_link()
    assert sees_every_drive(arm, ["q2", "q1"], _carriers(arm))
    arm.drives["q1"] = Drive(placement="link2")  # the shoulder's drive at the tip loads the shoulder itself
    assert not sees_every_drive(arm, ["q2", "q1"], _carriers(arm))
    scissor = mechatron.load(str(SCISSOR))
    assert scissor.closures and not sees_every_drive(scissor, list(scissor.actuated), {})


def test_a_start_is_not_used_where_a_drive_loads_its_own_joint():
    """The cycling arm of tests/test_system_sizing.py (the shoulder's drive at the tip): started from its cycle's
    second choice it still runs the weightless pass 1 and reports the same three passes and the cycle."""
    arm = two_link()
    arm.drives["q1"] = Drive(placement="link2")
    motors = MOTORS.copy()
    tr = swing(arm)
    plain = size_mechanism(arm, tr, motors, NO_GEARBOX, objective="cost", inertia_ratio_max=1e6)
    guess = {j.joint: j for j in size_mechanism(two_link(), tr, motors, NO_GEARBOX, objective="cost",
                                                 inertia_ratio_max=1e6).joints}
    started = size_mechanism(arm, tr, motors, NO_GEARBOX, objective="cost", inertia_ratio_max=1e6, start=guess)
    assert [i.changes for i in started.iterations] == [i.changes for i in plain.iterations]
    assert started.iterations[0].weighted is False


@pytest.mark.parametrize("objective", ["mass", "cost"])
def test_a_start_on_the_two_link_arm_gives_the_weightless_start_s_drives(objective):
    arm = two_link()
    tr = swing(arm)
    plain = size_mechanism(arm, tr, MOTORS, NO_GEARBOX, objective=objective, inertia_ratio_max=1e4)
    # the weightless drives as the start: the shoulder's S54 (51.48 N·m needed) is short of the fixed point's
    guess = {j.joint: j for j in size_mechanism(arm, tr, MOTORS, NO_GEARBOX, objective=objective,
                                                 inertia_ratio_max=1e4, single_pass=True).joints}
    assert guess["q1"].choice() == "S54 + direct" != plain.joints[0].choice()
    started = size_mechanism(arm, tr, MOTORS, NO_GEARBOX, objective=objective, inertia_ratio_max=1e4, start=guess)
    _same(started, plain)


def test_arrays_kept_for_a_catalog_that_does_not_change():
    """A catalog marked with ``keep_arrays`` (as a study marks those it reads once) gives the same sizing as a fresh
    copy, and another catalog object — even one at the same address later — never gets its arrays: a wrist motor
    rated 13 N·m instead of 20 cannot hold the wrist's 13.55 N·m (tests/test_system_sizing.py), so the choice
    moves."""
    arm = two_link()
    tr = swing(arm)
    kept = keep_arrays(MOTORS.copy())
    first = size_mechanism(arm, tr, kept, NO_GEARBOX, inertia_ratio_max=1e4)
    again = size_mechanism(arm, tr, kept, NO_GEARBOX, inertia_ratio_max=1e4)
    _same(again, first)
    _same(first, size_mechanism(arm, tr, MOTORS.copy(), NO_GEARBOX, inertia_ratio_max=1e4))
    weaker = MOTORS.copy()
    weaker.loc[weaker["key"] == "W20", "rated_torque"] = 13.0
    weaker.loc[weaker["key"] == "W20", "peak_torque"] = 13.0
    other = size_mechanism(arm, tr, weaker, NO_GEARBOX, inertia_ratio_max=1e4)
    assert first.joints[1].motor == "W20" and other.joints[1].motor != "W20"

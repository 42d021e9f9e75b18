"""A joint's static torque (gravity, external loads) is made only when read — the mass, cost and margin objectives
never read it — and is then the RNEA at rest of every sample."""

import pickle

import numpy as np
import pinocchio as pin

import mechatron
from mechatron.drives import duty as duty_module
from mechatron.drives.duty import joint_duties
from mechatron.dynamics import tree
from mechatron.dynamics.task import default_task


def _counting(monkeypatch):
    calls = []
    original = tree.inverse_dynamics

    def counted(*args, **kwargs):
        calls.append(args[2] is not None and not np.any(args[2]))  # at rest?
        return original(*args, **kwargs)

    monkeypatch.setattr(tree, "inverse_dynamics", counted)
    return calls


def test_the_static_torque_is_made_once_when_first_read_and_is_the_rnea_at_rest(monkeypatch):
    calls = _counting(monkeypatch)
    task = default_task(mechatron.load("puma560"))
    duties = joint_duties(task.mechanism, task.trajectory)
    assert calls == [False]  # the torques only
    shoulder = duties[1].static_torque
    assert calls == [False, True]
    for d in duties:  # every joint's column from that one call
        assert len(d.static_torque) == len(task.trajectory.t)
    assert calls == [False, True]
    model = pin.Model(task.mechanism.model)
    model.armature[:] = 0.0
    data = model.createData()
    rest = np.zeros(model.nv)
    expected = [pin.rnea(model, data, q, rest, rest)[1] for q in task.trajectory.q[::50]]
    np.testing.assert_allclose(shoulder[::50], expected, rtol=1e-12, atol=1e-12)


def test_sizing_for_mass_never_makes_it_and_for_time_does(monkeypatch):
    mech = mechatron.load("puma560")
    task = default_task(mech)
    calls = _counting(monkeypatch)
    mechatron.size(mech, task, single_pass=True)
    assert True not in calls
    mechatron.size(mech, task, single_pass=True, objective="time")
    assert True in calls


def test_a_pickled_duty_carries_its_static_torque():
    task = default_task(mechatron.load("puma560"))
    duty = joint_duties(task.mechanism, task.trajectory)[2]
    assert callable(duty.static_source)
    copy = pickle.loads(pickle.dumps(duty))
    assert isinstance(copy.static_source, np.ndarray)
    np.testing.assert_array_equal(copy.static_torque, duty.static_torque)
    assert duty_module.JointDuty.static_torque.__doc__

"""The actuator duty of a closed loop along a task (dynamics.trajectory.actuator_duty), all samples at once,
against the constrained inverse dynamics state by state (dynamics.constrained.inverse: [B Jᵀ][τ_a; λ] =
M q̈ + h − Q), the holding forces at rest, and the reduced inertia Sᵀ M S from the loop solver's velocity matrix
and Pinocchio's CRBA; the loops of another mechanism of the same linkage (drives' masses mounted) give the same
duty as its own."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.dynamics.constrained import inverse
from mechatron.dynamics.task import generic_task
from mechatron.dynamics.trajectory import actuator_duty
from mechatron.kinematics.loops import loop_solver
from mechatron.model.loads import Load

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module", params=["examples/data/scissor_lift.toml", "robots/six_bar_bucket.toml"])
def case(request):
    mech = mechatron.load(ROOT / request.param)
    task = generic_task(mech, dt=0.02)
    return mech, task


def test_forces_and_holding_forces_equal_the_constrained_inverse_dynamics(case, rng):
    mech, task = case
    loads = [Load(frame=mech.points[-1], force=(150.0, -400.0, 0.0))]
    duty = actuator_duty(mech, task.trajectory, loads)
    solver = loop_solver(mech)
    for k in rng.choice(len(duty.q), 12, replace=False):
        q = duty.q[k]
        v = solver.velocity(q, task.trajectory.v[k])
        a = solver.acceleration(q, v, task.trajectory.a[k])
        moving = inverse(mech, q, v, a, loads)[0]
        still = inverse(mech, q, np.zeros(mech.nv), np.zeros(mech.nv), loads)[0]
        scale = max(1.0, np.abs(duty.forces).max())
        np.testing.assert_allclose(duty.forces[k], [moving[n] for n in mech.actuated], rtol=1e-7, atol=1e-9 * scale)
        np.testing.assert_allclose(duty.holding[k], [still[n] for n in mech.actuated], rtol=1e-7, atol=1e-9 * scale)


def test_reduced_inertia_is_the_largest_diagonal_of_s_t_m_s(case):
    mech, task = case
    duty = actuator_duty(mech, task.trajectory, inertia_samples=20)
    solver = loop_solver(mech)
    expected = np.zeros(len(mech.actuated))
    for q in duty.q[:: max(1, len(duty.q) // 20)]:
        S = solver.velocity_matrix(q)
        M = pin.crba(mech.model, mech.model.createData(), q)
        M = np.triu(M) + np.triu(M, 1).T
        expected = np.maximum(expected, np.diagonal(S.T @ M @ S))
    np.testing.assert_allclose(duty.inertia, expected, rtol=1e-9)
    assert np.all(duty.inertia > 0)


def test_the_loops_of_the_same_linkage_give_the_same_duty(case):
    mech, task = case
    model = pin.Model(mech.model)
    model.appendBodyToJoint(model.njoints - 1, pin.Inertia(7.5, np.zeros(3), np.zeros((3, 3))), pin.SE3.Identity())
    from dataclasses import replace

    heavier = replace(mech, model=model)
    own, shared = actuator_duty(heavier, task.trajectory), actuator_duty(heavier, task.trajectory, kinematics=mech)
    np.testing.assert_allclose(shared.q, own.q, atol=1e-12)
    for a, b in ((shared.forces, own.forces), (shared.holding, own.holding)):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
    light = actuator_duty(mech, task.trajectory)
    assert not np.allclose(light.holding, own.holding, rtol=1e-6)  # the mass counts

"""The batched frame kinematics (mechatron.model.batched) and the closures evaluated for N configurations at once,
against Pinocchio and the per-configuration closures at random states."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.model.batched import BatchedFrames, PlanarFrames, batched_frames
from mechatron.model.closures import ClosureSystem, FrameStates, _curve

LWA = pin.LOCAL_WORLD_ALIGNED
CLOSED_LOOPS = ["crank_slider", "six_bar_bucket", "front_shovel", "grab", "seven_bar", "scotch_yoke", "slotted_link",
                "delta"]


def random_tree(seed: int = 3) -> pin.Model:
    """A spatial tree of every supported joint type (branching) with random placements and frames."""
    rng = np.random.default_rng(seed)
    pin.seed(seed)
    model = pin.Model()
    kinds = [pin.JointModelRX(), pin.JointModelPY(), pin.JointModelRevoluteUnaligned(*rng.normal(size=3)),
             pin.JointModelPrismaticUnaligned(*rng.normal(size=3)), pin.JointModelRY(), pin.JointModelPX(),
             pin.JointModelRZ(), pin.JointModelPZ()]
    for k, joint in enumerate(kinds):
        parent = 0 if k == 0 else int(rng.integers(0, k + 1))  # joint ids 1..k exist
        jid = model.addJoint(parent, joint, pin.SE3.Random(), f"j{k}")
        model.addJointFrame(jid)
        model.addFrame(pin.Frame(f"f{k}", jid, model.getFrameId(f"j{k}"), pin.SE3.Random(), pin.FrameType.OP_FRAME))
    model.lowerPositionLimit[:] = -2.0
    model.upperPositionLimit[:] = 2.0
    return model


def random_planar_tree(seed: int = 4) -> pin.Model:
    """A planar tree (turns about z, slides in the xy plane, an axis along −z) with random placements in the plane."""
    rng = np.random.default_rng(seed)

    def placement():
        return pin.SE3(pin.utils.rotate("z", rng.uniform(-3, 3)), rng.normal(size=3))

    model = pin.Model()
    kinds = [pin.JointModelRZ(), pin.JointModelPX(), pin.JointModelRevoluteUnaligned(0.0, 0.0, -1.0),
             pin.JointModelPrismaticUnaligned(0.6, -0.8, 0.0), pin.JointModelPY(), pin.JointModelRZ()]
    for k, joint in enumerate(kinds):
        parent = 0 if k == 0 else int(rng.integers(0, k + 1))
        jid = model.addJoint(parent, joint, placement(), f"j{k}")
        model.addJointFrame(jid)
        model.addFrame(pin.Frame(f"f{k}", jid, model.getFrameId(f"j{k}"), placement(), pin.FrameType.OP_FRAME))
    model.lowerPositionLimit[:] = -2.0
    model.upperPositionLimit[:] = 2.0
    return model


def random_states(model: pin.Model, n: int, seed: int = 0):
    """n configurations within the limits (±π where a limit is infinite), velocities and accelerations."""
    rng = np.random.default_rng(seed)
    lower = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi)
    upper = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi)
    Q = np.array([pin.randomConfiguration(model, lower, upper) for _ in range(n)])
    return Q, rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))


def models():
    return [pytest.param(mechatron.load(name).model, id=name) for name in CLOSED_LOOPS] + \
        [pytest.param(random_tree(), id="random_spatial_tree"), pytest.param(random_planar_tree(), id="random_planar")]


@pytest.mark.parametrize("kind", [BatchedFrames, batched_frames])
@pytest.mark.parametrize("model", models())
def test_batched_frames_equal_pinocchio(model, kind):
    """The spatial recursion for every model, and the planar one (by batched_frames) for the planar trees."""
    frames = list(range(model.nframes))
    Q, V, A = random_states(model, 6)
    batched = kind(model, frames)
    states = batched.motion(batched.placements(Q), V)
    with_acceleration = batched.motion(batched.placements(Q), V, A).acceleration0
    data = model.createData()
    for k in range(len(Q)):
        pin.computeJointJacobians(model, data, Q[k])
        pin.forwardKinematics(model, data, Q[k], V[k], np.zeros(model.nv))
        pin.updateFramePlacements(model, data)
        for j, f in enumerate(frames):
            np.testing.assert_allclose(states.position[k, j], data.oMf[f].translation, atol=1e-12)
            np.testing.assert_allclose(states.rotation[k, j], data.oMf[f].rotation, atol=1e-12)
            np.testing.assert_allclose(states.jacobian[k, j], pin.getFrameJacobian(model, data, f, LWA), atol=1e-12)
            np.testing.assert_allclose(states.velocity[k, j], pin.getFrameVelocity(model, data, f, LWA).vector,
                                       atol=1e-12)
            np.testing.assert_allclose(states.acceleration0[k, j],
                                       pin.getFrameClassicalAcceleration(model, data, f, LWA).vector, atol=1e-12)
        pin.forwardKinematics(model, data, Q[k], V[k], A[k])
        for j, f in enumerate(frames):
            np.testing.assert_allclose(with_acceleration[k, j],
                                       pin.getFrameClassicalAcceleration(model, data, f, LWA).vector, atol=1e-12)


def test_planar_trees_are_recognized():
    assert PlanarFrames.applies(random_planar_tree(), [1, 2])
    assert not PlanarFrames.applies(random_tree(), [])
    assert isinstance(batched_frames(mechatron.load("six_bar_bucket").model, [0]), PlanarFrames)
    assert not isinstance(batched_frames(mechatron.load("delta").model, [0]), PlanarFrames)


def test_other_joints_are_refused():
    model = pin.Model()
    model.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    with pytest.raises(NotImplementedError, match="ball"):
        BatchedFrames(model, [0])


@pytest.mark.parametrize("name", CLOSED_LOOPS)
def test_batched_closures_equal_the_per_configuration_ones(name):
    mech = mechatron.load(name)
    system = ClosureSystem(mech.model, mech.closures, mech.frame_id, mech.points)
    Q, V, _ = random_states(mech.model, 5, seed=1)
    batched = system.batched()
    states = batched.motion(batched.placements(Q), V)
    phi, J = system.stack(states)
    drift = system.stack_drift(states)
    single = FrameStates(mech.model, system.states.frame_ids)
    for k in range(len(Q)):
        single.update(Q[k])
        single.update_motion(Q[k], V[k])
        rows = 0
        for closure in system.closures:
            part = slice(rows, rows + closure.nrows)
            np.testing.assert_allclose(phi[k, part], closure.residual(single), atol=1e-12)
            np.testing.assert_allclose(J[k, part], closure.jacobian(single), atol=1e-12)
            np.testing.assert_allclose(drift[k, part], closure.drift(single), atol=1e-12)
            rows += closure.nrows
        phi_k, J_k = system.evaluate(Q[k])
        np.testing.assert_allclose(phi[k], phi_k, atol=1e-12)
        np.testing.assert_allclose(J[k], J_k, atol=1e-12)
        np.testing.assert_allclose(drift[k], system.drift(Q[k], V[k]), atol=1e-12)


def test_a_curve_of_floats_only_is_called_per_sample():
    x = np.array([[0.1, 0.2], [0.3, 0.4]])
    np.testing.assert_allclose(_curve(lambda v: float(v) ** 2, x), x**2, rtol=1e-15)
    np.testing.assert_allclose(_curve(lambda v: 0.0, x), np.zeros_like(x))
    assert _curve(lambda v: v + 1.0, 0.5) == 1.5


@pytest.mark.parametrize("model", [pytest.param(random_tree(), id="spatial"), pytest.param(random_planar_tree(),
                                                                                           id="planar")])
def test_jacobians_of_the_leading_frames_only(model):
    """placements(Q, jacobians=m): the Jacobians of the first m frames, the same as with all of them; False: none."""
    frames = batched_frames(model, list(range(model.nframes)))
    Q = random_states(model, 4)[0]
    every = frames.placements(Q)
    for m in (0, 3, False):
        part = frames.placements(Q, jacobians=m)
        assert part.jacobian.shape == (4, int(m), 6, model.nv)
        np.testing.assert_array_equal(part.jacobian, every.jacobian[:, :int(m)])
        np.testing.assert_array_equal(part.position, every.position)

"""Exact parameter sensitivities (mechatron.dynamics.sensitivity) against converged central differences of the rebuilt
mechanism: re-assembled at the same inputs, then Pinocchio's positions, velocities (joint_velocity and the frame
Jacobian), classical accelerations, mechatron's constrained inverse dynamics at rest and in motion, with and without
external loads, and the re-assembled coordinates; the nominal values against mechatron's own; the result protocol;
refused mechanisms."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.dynamics import constrained
from mechatron.dynamics.sensitivity import parameter_sensitivities
from mechatron.errors import InputError
from mechatron.kinematics.loops import joint_acceleration, joint_velocity, loop_solver
from mechatron.model.closures import OnCurve
from mechatron.model.loads import Load
from tests.protocol import check_result

LWA = pin.LOCAL_WORLD_ALIGNED
#: The exact derivatives against the rebuilt mechanism's converged differences, relative to each output's scale.
RTOL = 1e-8
#: Nominal values (δ = 0) against mechatron's own, relative to each quantity's scale.
NOMINAL = 1e-10
#: Central-difference steps h, h/2, h/4 (m or rad): the reference derivative is Richardson's extrapolation of the last
#: two, which must agree with that of the first two.
STEP = 1e-3

#: (mechanism, serial configuration or None for the reference and a moved one, loads)
CASES = [
    ("puma560", [0.3, -0.5, 0.7, 0.2, -0.4, 0.9], [Load("tool", [10.0, -20.0, 30.0], [1.0, -2.0, 0.5])]),
    ("robots/crank_slider.toml", None, []),
    ("robots/scotch_yoke.toml", None, []),
    ("robots/slotted_link.toml", None, []),
    ("geared_five_bar", None, [Load("C", [0.0, -40.0, 0.0])]),
    ("examples/data/four_bar.toml", None, [Load("C", [3.0, -5.0, 0.0], [0.0, 0.0, 0.4])]),
    ("robots/six_bar_bucket.toml", None, []),
    ("robots/front_shovel.toml", None, [Load("V", [-5e4, 2e4, 0.0])]),
    ("robots/grab.toml", None, []),
    ("examples/data/scissor_lift.toml", None, [Load("deck", [200.0, -1000.0, 0.0])]),
    ("robots/delta.toml", None, [Load("TCP", [5.0, -3.0, -20.0])]),
]


#: A five-bar linkage whose two cranks are geared together (q3 = −q1 + the drawing's offset): a gear closure whose
#: offset moves with the points.
GEARED_FIVE_BAR = """
name = "geared_five_bar"
tool = "C"
actuated = ["q1"]

[points]
A = [0.0, 0.0]
E = [0.3, 0.0]
B = [0.02, 0.1]
D = [0.36, 0.11]
C = [0.2, 0.33]

[[bodies]]
name = "ground"
points = ["A", "E"]

[[bodies]]
name = "crank"
points = ["A", "B"]
mass = 0.5
shape = "bar"

[[bodies]]
name = "left"
points = ["B", "C"]
mass = 1.0
shape = "bar"

[[bodies]]
name = "gear"
points = ["E", "D"]
mass = 0.4
shape = "bar"

[[bodies]]
name = "right"
points = ["D", "C"]
mass = 0.8
shape = "bar"

[[joints]]
type = "revolute"
body = "crank"
at = "A"
coordinate = "q1"

[[joints]]
type = "revolute"
body = "left"
at = "B"
coordinate = "q2"

[[joints]]
type = "revolute"
body = "gear"
at = "E"
coordinate = "q3"

[[joints]]
type = "revolute"
body = "right"
at = "D"
coordinate = "q4"

[[closures]]
type = "pin"
point = "C"
bodies = ["left", "right"]

[[closures]]
type = "gear"
driver = "crank"
driven = "gear"
ratio = -1.0
"""


def load(name: str, folder):
    """A shipped mechanism, or the geared five-bar written to ``folder``."""
    if name == "geared_five_bar":
        path = folder / "geared_five_bar.toml"
        path.write_text(GEARED_FIVE_BAR, encoding="utf-8")
        return mechatron.load(str(path))
    return mechatron.load(name)


def inputs_of(mech) -> list[str]:
    return list(mech.actuated) if mech.closures else mech.joint_names


def configurations(mech, serial_q) -> list[np.ndarray]:
    """A serial arm's given configuration; a linkage's reference and one with every input moved (towards the middle
    of its range, or by 0.4 rad, or as given for the delta robot)."""
    if serial_q is not None:
        return [np.asarray(serial_q, dtype=float)]
    solver = loop_solver(mech)
    q0 = mech.reference_q
    moved = {}
    for k, (name, i) in enumerate(zip(mech.actuated, solver.act)):
        lo, hi = mech.model.lowerPositionLimit[i], mech.model.upperPositionLimit[i]
        moved[name] = q0[i] + 0.3 * ((lo + hi) / 2 - q0[i]) if np.isfinite([lo, hi]).all() \
            else q0[i] + 0.4
        if mech.name == "delta":
            moved[name] = [0.2, -0.1, 0.35][k]
    return [q0, mechatron.assemble(mech, moved, guess=q0)]


def states(mech, configs):
    """(q, rates, accelerations) per sample: every configuration at rest, then in motion."""
    n = len(inputs_of(mech))
    rest, rates, accelerations = np.zeros(n), 0.3 + 0.1 * np.arange(n), -0.2 + 0.05 * np.arange(n)
    return ([q for q in configs for _ in range(2)], [x for _ in configs for x in (rest, rates)],
            [x for _ in configs for x in (rest, accelerations)])


def nonlinear(mech, q_inputs, frames, rates, accelerations, loads):
    """Every output by Pinocchio and mechatron at the inputs of q_inputs: positions, velocities and classical
    accelerations of the frames, actuator forces (constrained inverse dynamics) for each (rates, accelerations)."""
    names = inputs_of(mech)
    if mech.closures:
        solver = loop_solver(mech)
        q = mechatron.assemble(mech, {n: q_inputs[i] for n, i in zip(names, solver.act)}, guess=q_inputs)
    else:
        q = np.asarray(q_inputs, dtype=float)
    model, data = mech.model, mech.data
    out = []
    for u, w in zip(rates, accelerations):
        if mech.closures:
            v = joint_velocity(mech, q, dict(zip(names, u)))
            a = joint_acceleration(mech, q, v, dict(zip(names, w)))
        else:
            v, a = np.asarray(u, dtype=float), np.asarray(w, dtype=float)
        p_, v_, a_ = [], [], []
        for frame in frames:
            fid = mech.frame_id(frame)
            p_.append(mechatron.frame_placement(mech, q, frame).translation)
            v_.append(pin.computeFrameJacobian(model, data, q, fid, LWA)[:3] @ v)
            pin.forwardKinematics(model, data, q, v, a)
            a_.append(pin.getFrameClassicalAcceleration(model, data, fid, LWA).linear)
        forces = constrained.inverse(mech, q, v, a, loads)[0]
        out.append(np.concatenate([np.ravel(p_), np.ravel(v_), np.ravel(a_), [forces[n] for n in names], q]))
    return np.array(out)  # (samples, outputs)


def flattened(result, k: int | None = None):
    """The result's outputs (samples, outputs) in the order of :func:`nonlinear`, or their derivatives to
    parameter k."""
    if k is None:
        parts = [result.position, result.velocity, result.acceleration]
        return np.concatenate([*(x.reshape(len(x), -1) for x in parts), result.force, result.q], axis=1)
    parts = [result.d_position, result.d_velocity, result.d_acceleration]
    return np.concatenate([*(x[..., k].reshape(len(x), -1) for x in parts), result.d_force[..., k],
                           result.d_q[..., k]], axis=1)


def scales(reference: np.ndarray, nf: int, nq: int) -> np.ndarray:
    """Per output (last axis) its scale: its largest |value| over the other axes, at least 1e-3 of the largest of
    its quantity (positions, velocities, accelerations, forces, coordinates), and a floor."""
    flat = np.abs(reference).reshape(-1, reference.shape[-1]).max(axis=0)
    groups = [slice(0, 3 * nf), slice(3 * nf, 6 * nf), slice(6 * nf, 9 * nf), slice(9 * nf, -nq), slice(-nq, None)]
    out = flat.copy()
    for g in groups:
        out[g] = np.maximum(flat[g], 1e-3 * flat[g].max(initial=0.0))
    return np.maximum(out, 1e-12)


@pytest.mark.parametrize("name, serial_q, loads", CASES, ids=[c[0].split("/")[-1] for c in CASES])
def test_exact_sensitivities_equal_converged_central_differences(name, serial_q, loads, tmp_path):
    mech = load(name, tmp_path)
    frames = [mech.tool_frame]
    configs = configurations(mech, serial_q)
    Q, U, A = states(mech, configs)
    result = parameter_sensitivities(mech, np.array(Q), rates=np.array(U), accelerations=np.array(A),
                                     frames=frames, loads=loads)
    nf = len(frames)

    # nominal values equal mechatron's own (Pinocchio, constrained inverse dynamics)
    own = np.vstack([nonlinear(mech, q, frames, U[2 * c:2 * c + 2], A[2 * c:2 * c + 2], loads)
                     for c, q in enumerate(configs)])
    mine = flattened(result)
    nominal_error = np.abs(mine - own) / scales(own, nf, mech.nq)
    assert nominal_error.max() < NOMINAL, nominal_error.max()

    values = mech.parameter_values()
    exact = np.stack([flattened(result, k) for k in range(len(result.parameters))], axis=-1)  # (samples, out, n_l)
    reference = np.empty_like(exact)
    spread = np.empty_like(exact)
    for k, parameter in enumerate(result.parameters):
        differences = []
        for h in (STEP, STEP / 2, STEP / 4):
            sides = []
            for sign in (1.0, -1.0):
                other = mech.with_parameters({parameter: values[parameter] + sign * h})
                sides.append(np.vstack([nonlinear(other, q, frames, U[2 * c:2 * c + 2], A[2 * c:2 * c + 2], loads)
                                        for c, q in enumerate(configs)]))
            differences.append((sides[0] - sides[1]) / (2 * h))
        # Richardson's extrapolation of two central differences, error O(h⁴), from two pairs of steps
        coarse, fine = ((4 * differences[i + 1] - differences[i]) / 3 for i in (0, 1))
        reference[..., k], spread[..., k] = fine, fine - coarse
    scale = scales(np.swapaxes(reference, 1, 2), nf, mech.nq)[None, :, None]  # per output, over samples and parameters
    converged = np.abs(spread) / scale
    assert converged.max() < RTOL / 4, f"central differences not converged: {converged.max():.2e}"
    error = np.abs(exact - reference) / scale
    worst = np.unravel_index(np.argmax(error), error.shape)
    labels = [f"{f}_{kind}{axis}" for kind in ("", "v", "a") for f in frames for axis in "xyz"] + \
        [f"force_{n}" for n in result.inputs] + [f"q_{n}" for n in mech.joint_names]
    print(f"{name}: worst relative error {error.max():.2e} (∂{labels[worst[1]]}/∂{result.parameters[worst[2]]}), "
          f"nominal {nominal_error.max():.2e}, spread of the differences {converged.max():.2e}")
    assert error.max() < RTOL, (f"{name}: ∂{labels[worst[1]]}/∂{result.parameters[worst[2]]} at sample {worst[0]}: "
                                f"{exact[worst]:.10g} against {reference[worst]:.10g} (relative {error.max():.2e})")


def test_closed_loop_coordinates_follow_the_implicit_function_theorem():
    """∂q/∂l with the input held: the actuated row is zero and the loops stay closed to first order (the rebuilt
    four-bar re-assembled at the same crank angle moves its dependent coordinates by ∂q/∂l · h)."""
    mech = mechatron.load("examples/data/four_bar.toml")
    q0 = mech.reference_q
    result = parameter_sensitivities(mech, q0, parameters=["a", "C_x"])
    solver = loop_solver(mech)
    assert np.all(result.d_q[0, solver.act] == 0.0)
    for k, parameter in enumerate(result.parameters):
        h = 1e-5
        moved = [mechatron.assemble(mech.with_parameters({parameter: mech.parameters[parameter].value + s * h}),
                                    {"q1": q0[solver.act[0]]}, guess=q0) for s in (1, -1)]
        assert np.allclose(result.d_q[0, :, k], (moved[0] - moved[1]) / (2 * h), rtol=RTOL, atol=RTOL)


def test_many_configurations_equal_one_at_a_time():
    mech = mechatron.load("robots/six_bar_bucket.toml")
    configs = configurations(mech, None)
    both = parameter_sensitivities(mech, np.array(configs), rates={"L1": 0.1}, accelerations={"L1": 0.05})
    for i, q in enumerate(configs):
        one = parameter_sensitivities(mech, q, rates={"L1": 0.1}, accelerations={"L1": 0.05})
        assert np.allclose(both.d_force[i], one.d_force[0], rtol=1e-12, atol=1e-9)
        assert np.allclose(both.d_velocity[i], one.d_velocity[0], rtol=1e-12, atol=1e-14)


def test_the_result_follows_the_protocol():
    mech = mechatron.load("robots/crank_slider.toml")
    result = parameter_sensitivities(mech, mech.reference_q, rates={"q1": 2.0})
    data = check_result(result)
    assert data["samples"][0]["outputs"]["force_q1"]["unit"] == "N·m"
    assert set(data["samples"][0]["outputs"]["C_x"]["derivatives"]) == set(mech.parameters)
    frame = result.to_frame()
    assert {"output", "unit", "value", *(f"d_{p}" for p in mech.parameters)} <= set(frame.columns)
    assert "force_q1" in str(result) and "N·m" in str(result)
    assert result.derivative("C_x", "l1")[0] == pytest.approx(result.d_position[0, 0, 0, 0])
    many = parameter_sensitivities(mech, [mech.reference_q, mech.reference_q], rates={"q1": 2.0})
    check_result(many)


def test_unsupported_mechanisms_are_refused_naming_what():
    turret = mechatron.load("examples/data/turret_arm.urdf")
    with pytest.raises(InputError, match="turn"):
        parameter_sensitivities(turret, turret.neutral())
    grab = mechatron.load("robots/grab.toml")
    closures = [dataclasses.replace(c, spline=None) if isinstance(c, OnCurve) else c for c in grab.closures]
    with pytest.raises(InputError, match="P2 on"):
        parameter_sensitivities(grab.with_closures(closures), grab.reference_q)


def test_bad_input_is_refused():
    mech = mechatron.load("examples/data/four_bar.toml")
    q0 = mech.reference_q
    with pytest.raises(InputError, match="not assembled"):
        parameter_sensitivities(mech, q0 + 0.01)
    with pytest.raises(InputError, match="parameter"):
        parameter_sensitivities(mech, q0, parameters=["nope"])
    with pytest.raises(InputError, match="frame"):
        parameter_sensitivities(mech, q0, frames=["nope"])
    with pytest.raises(InputError, match="input"):
        parameter_sensitivities(mech, q0, rates={"q9": 1.0})
    with pytest.raises(InputError):
        parameter_sensitivities(mech, q0[:2])

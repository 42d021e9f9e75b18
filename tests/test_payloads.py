"""Payloads everywhere: a payload carried at a point of a closed loop (``--payload MASS --payload-at POINT`` of
``dynamics`` and ``size``, a task file's ``payload_at``, :func:`mechatron.model.payload.with_payload`) against the
same mass built into the body in the mechanism file, its centre and inertia combined by hand (parallel-axis
theorem); on a serial arm ``--payload-at tool`` against today's ``--payload`` and against the virtual work of the
payload's weight (τ = m g J_zᵀ); the bad inputs; and the default frame of ``frame_placement``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.dynamics.motion import move
from mechatron.dynamics.task import read_task
from mechatron.dynamics.trajectory import actuator_forces
from mechatron.errors import InputError
from mechatron.model.payload import with_payload
from tests.boom import boom

ROOT = Path(__file__).resolve().parent.parent

# The boom of tests/boom.py; T, a point of the boom, has a frame whose x axis is the direction (3, 4)/5 in the drawing.
BOOM_MASS, BOOM_COM, BOOM_INERTIA = 20.0, (0.45, 0.05), 1.7   # kg, m (drawing), kg·m² about the centre
T, T_AXIS = np.array([1.0, 0.2]), np.array([0.6, 0.8])        # the point T and its frame's x axis in the drawing
PAYLOAD = 500.0                                               # kg
PAYLOAD_COM = np.array([0.1, -0.05, 0.02])                    # m, in T's frame
# kg·m² about the payload's centre, T's axes: Ixx, Iyy, Izz, Ixy, Ixz, Iyz (only I_zz turns in the plane)
PAYLOAD_INERTIA = (30.0, 40.0, 50.0, 2.0, -3.0, 1.5)
MOVE = ("--move", "0.45;0.65", "--vmax", "0.2", "--amax", "1", "--dt", "0.01")


def tensor(values) -> np.ndarray:
    xx, yy, zz, xy, xz, yz = values
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def combined(mass: float, com_in_t: np.ndarray, izz: float) -> tuple[float, np.ndarray, float]:
    """The boom with a payload of ``mass`` (kg) centred at ``com_in_t`` (m, T's frame) with I_zz ``izz`` (kg·m²)
    about its centre, by hand: masses add, the centre is the mass-weighted mean, and the moments about the common
    centre add by the parallel-axis theorem, I = Σ (I_i + m_i d_i²) with d_i the in-plane distance."""
    normal = np.array([-T_AXIS[1], T_AXIS[0]])
    centre = T + com_in_t[0] * T_AXIS + com_in_t[1] * normal   # z is out of the plane: no lever for the plane
    total = BOOM_MASS + mass
    common = (BOOM_MASS * np.array(BOOM_COM) + mass * centre) / total
    inertia = (BOOM_INERTIA + BOOM_MASS * np.sum((np.array(BOOM_COM) - common) ** 2)
               + izz + mass * np.sum((centre - common) ** 2))
    return total, common, inertia


def boom_file(folder: Path, name: str, mass: float = BOOM_MASS, com=BOOM_COM, inertia: float = BOOM_INERTIA) -> Path:
    path = folder / f"{name}.toml"
    fields = f"mass = {float(mass)!r}\ncom = [{float(com[0])!r}, {float(com[1])!r}]\ninertia = {float(inertia)!r}"
    path.write_text(boom(points="T = { at = [1.0, 0.2], direction = [3, 4] }", body=fields),
                    encoding="utf-8")
    return path


def run(capsys, *argv: str) -> tuple[int, str, str]:
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # an option argparse refuses
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def one_line_error(capsys, *argv: str) -> str:
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err.strip()


def assert_same_numbers(a, b, rel: float = 1e-9, where: str = "") -> None:
    """Two JSON documents equal, numbers to ``rel`` relative (1e-9 of the largest of the pair, or 1e-9 absolute)."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for key in a:
            assert_same_numbers(a[key], b[key], rel, f"{where}.{key}")
    elif isinstance(a, list):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same_numbers(x, y, rel, f"{where}[{k}]")
    elif isinstance(a, float) and not isinstance(a, bool):
        assert numbers_close(a, b, rel), f"{where}: {a} != {b}"
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


def numbers_close(a: float, b: float, rel: float) -> bool:
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-9)


def lift_move():
    return move(None, [0.45], [0.65], vmax=0.2, amax=1.0, dt=0.01)


# ------------------------------------------------------------------------------ (a) a closed loop, by the API
def test_a_payload_at_a_point_of_a_closed_loop_is_the_body_with_it_built_in(tmp_path):
    """with_payload(boom, 500 kg, "T", centre, inertia) gives the cylinder force of the file whose boom has the
    combined mass, centre and inertia, to 1e-9 relative, at every sample of a move that accelerates."""
    base = mechatron.load(boom_file(tmp_path, "boom"))
    loaded = with_payload(base, PAYLOAD, "T", com=PAYLOAD_COM, inertia=tensor(PAYLOAD_INERTIA))
    built_in = mechatron.load(boom_file(tmp_path, "built_in", *combined(PAYLOAD, PAYLOAD_COM, PAYLOAD_INERTIA[2])))
    trajectory = lift_move()
    expected = actuator_forces(built_in, trajectory)[1]
    bare = actuator_forces(base, trajectory)[1]
    assert np.abs(expected - bare).min() > 1e3  # the payload matters: kN more on the cylinder
    np.testing.assert_allclose(actuator_forces(loaded, trajectory)[1], expected, rtol=1e-9)


def test_a_payload_at_a_pin_joins_the_body_named_by_the_frame(tmp_path):
    """The pin O is the frame O on the ground and O@boom on the boom: a payload at O loads nothing (the ground
    carries it), one at O@boom is a point mass at the boom's pivot, which the gravity of a turning boom does not
    load either, but its inertia does: both are the files built that way."""
    base = mechatron.load(boom_file(tmp_path, "boom"))
    trajectory = lift_move()
    bare = actuator_forces(base, trajectory)[1]
    on_ground = with_payload(base, PAYLOAD, "O", inertia=np.diag([1.0, 1.0, 2.0]))
    np.testing.assert_allclose(actuator_forces(on_ground, trajectory)[1], bare, rtol=1e-9)
    on_boom = with_payload(base, PAYLOAD, "O@boom", inertia=np.diag([1.0, 1.0, 2.0]))
    # a point at the pivot, (0, 0) in the drawing, with I_zz = 2 about itself
    total = BOOM_MASS + PAYLOAD
    common = BOOM_MASS * np.array(BOOM_COM) / total
    inertia = BOOM_INERTIA + BOOM_MASS * np.sum((np.array(BOOM_COM) - common) ** 2) + 2.0 \
        + PAYLOAD * np.sum(common**2)
    built_in = mechatron.load(boom_file(tmp_path, "built_in", total, common, inertia))
    np.testing.assert_allclose(actuator_forces(on_boom, trajectory)[1], actuator_forces(built_in, trajectory)[1],
                               rtol=1e-9)


# ------------------------------------------------------------------------------ (a) a closed loop, by the CLI
def test_dynamics_payload_at_a_point_on_the_command_line(tmp_path, capsys):
    """``dynamics --payload 500 --payload-at T`` writes the forces of the file with a 500 kg point mass at T built
    into the boom."""
    base = boom_file(tmp_path, "boom")
    built_in = boom_file(tmp_path, "built_in", *combined(PAYLOAD, np.zeros(3), 0.0))
    code, _, _ = run(capsys, "dynamics", base, *MOVE, "--payload", "500", "--payload-at", "T",
                     "--csv", tmp_path / "payload.csv")
    assert code == 0
    code, _, _ = run(capsys, "dynamics", built_in, *MOVE, "--csv", tmp_path / "built_in.csv")
    assert code == 0
    carried, reference = pd.read_csv(tmp_path / "payload.csv"), pd.read_csv(tmp_path / "built_in.csv")
    assert list(carried.columns) == list(reference.columns)
    np.testing.assert_allclose(carried.to_numpy(float), reference.to_numpy(float), rtol=1e-9, atol=1e-9)
    assert np.abs(reference["tau_lift"]).max() > 1e4


def test_size_payload_at_a_point_on_the_command_line(tmp_path, capsys):
    """``size --payload 500 --payload-at T`` sizes the cylinder of the file with the payload built in: the same
    JSON, numbers to 1e-9."""
    task = tmp_path / "lift.toml"
    task.write_text('name = "lift"\nwaypoints = [[0.45], [0.65]]\nvmax = 0.2\namax = 1.0\ndt = 0.01\n',
                    encoding="utf-8")
    base = boom_file(tmp_path, "boom")
    built_in = boom_file(tmp_path, "built_in", *combined(PAYLOAD, np.zeros(3), 0.0))
    code, out, _ = run(capsys, "size", base, "--task", task, "--payload", "500", "--payload-at", "T", "--json")
    assert code in (0, 1)
    code_ref, reference, _ = run(capsys, "size", built_in, "--task", task, "--json")
    assert code == code_ref
    assert_same_numbers(json.loads(out), json.loads(reference))


# ------------------------------------------------------------------------------------ (c) a task file's payload_at
def write_task(folder: Path, name: str, payload: str = "") -> Path:
    path = folder / f"{name}.toml"
    path.write_text(f'name = "lift"\n{payload}waypoints = [[0.45], [0.65]]\nvmax = 0.2\namax = 1.0\ndt = 0.01\n',
                    encoding="utf-8")
    return path


PAYLOAD_FIELDS = (f'payload = {PAYLOAD}\npayload_at = "T"\npayload_com_mm = {[float(1e3 * c) for c in PAYLOAD_COM]}\n'
                  f"payload_inertia = {list(PAYLOAD_INERTIA)}\n")


def test_a_task_file_payload_at_a_point_of_a_closed_loop(tmp_path):
    """A task's payload with ``payload_at = "T"``, its centre in mm and six inertia numbers in T's axes: the
    task's mechanism gives the forces of the file with the payload built in."""
    task = read_task(write_task(tmp_path, "carry", PAYLOAD_FIELDS), mechatron.load(boom_file(tmp_path, "boom")))
    assert task.payload == PAYLOAD
    built_in = mechatron.load(boom_file(tmp_path, "built_in", *combined(PAYLOAD, PAYLOAD_COM, PAYLOAD_INERTIA[2])))
    np.testing.assert_allclose(actuator_forces(task.mechanism, task.trajectory)[1],
                               actuator_forces(built_in, task.trajectory)[1], rtol=1e-9)


def test_size_and_a_study_take_a_task_with_payload_at(tmp_path, capsys):
    """``size --task`` with the payload at T equals the sizing of the built-in file with a task without one, and the
    study's dynamics analysis (which passes the task's mechanism on) gives the built-in file's peak and RMS."""
    from mechatron.studies.analyses import dynamics as study_dynamics

    carry, plain = write_task(tmp_path, "carry", PAYLOAD_FIELDS), write_task(tmp_path, "plain")
    base = boom_file(tmp_path, "boom")
    built_in = boom_file(tmp_path, "built_in", *combined(PAYLOAD, PAYLOAD_COM, PAYLOAD_INERTIA[2]))
    code, out, _ = run(capsys, "size", base, "--task", carry, "--json")
    code_ref, reference, _ = run(capsys, "size", built_in, "--task", plain, "--json")
    assert code == code_ref and code in (0, 1)
    assert_same_numbers(json.loads(out), json.loads(reference))
    study = study_dynamics.outputs(mechatron.load(base), {"task": str(carry)}, 0)
    expected = study_dynamics.outputs(mechatron.load(built_in), {"task": str(plain)}, 0)
    assert study.keys() == expected.keys() and expected["lift_peak_N"] > 1e4
    for key in study:
        assert study[key] == pytest.approx(expected[key], rel=1e-9)


# ---------------------------------------------------------------------------------------- (b) a serial arm
PUMA_MOVE = ("--move", "0,0,0,0,0,0;30,45,-120,10,40,20", "--deg", "--dt", "0.01")


@pytest.mark.parametrize("command", ["dynamics", "size"])
def test_payload_at_tool_is_the_payload_of_a_serial_arm(command, capsys):
    """On the PUMA 560 ``--payload-at tool`` is ``--payload`` alone (the tool frame is the default), in the JSON."""
    extra = PUMA_MOVE if command == "dynamics" else ("--single-pass",)
    code, default, _ = run(capsys, command, "puma560", *extra, "--payload", "2.5", "--json")
    code_at, at_tool, _ = run(capsys, command, "puma560", *extra, "--payload", "2.5", "--payload-at", "tool", "--json")
    assert code == code_at and code in (0, 1)
    assert json.loads(at_tool) == json.loads(default)
    code, bare, _ = run(capsys, command, "puma560", *extra, "--json")
    assert json.loads(bare) != json.loads(default)


def test_a_payload_at_a_frame_of_a_serial_arm_is_its_weight_by_virtual_work():
    """At rest a payload m at a frame adds τ = m g J_zᵀ to the joint torques (the virtual work of its weight; J_z
    the z row of the frame's Jacobian): at the tool (default) and at link3."""
    puma = mechatron.load("puma560")
    q = puma.configuration(np.radians([30, 45, -120, 10, 40, 20]))
    zero = np.zeros(puma.nv)
    bare = mechatron.inverse_dynamics(puma, q, zero, zero)
    for frame in (None, "link3"):
        loaded = with_payload(puma, 2.5, frame)
        added = mechatron.inverse_dynamics(loaded, q, zero, zero) - bare
        jz = mechatron.frame_jacobian(puma, q, frame or "tool")[2]
        np.testing.assert_allclose(added, 2.5 * 9.81 * jz, rtol=1e-9, atol=1e-12)


# ----------------------------------------------------------------------------------------------- (d) bad inputs
@pytest.mark.parametrize("command", ["dynamics", "size"])
@pytest.mark.parametrize("argv,words", [
    (["--payload", "500", "--payload-at", "Q"], ["--payload-at", "unknown frame of boom 'Q'", "T"]),
    (["--payload-at", "T"], ["--payload-at", "--payload MASS"]),
    (["--payload", "-500", "--payload-at", "T"], ["--payload", ">= 0 kg", "got -500"]),
    (["--payload", "nan", "--payload-at", "T"], ["--payload", "got nan"]),
])
def test_bad_payload_options(command, argv, words, tmp_path, capsys):
    extra = MOVE if command == "dynamics" else ()
    err = one_line_error(capsys, command, boom_file(tmp_path, "boom"), *extra, *argv)
    assert err.startswith("mechatron") and all(w in err for w in words), err


@pytest.mark.parametrize("fields,field,words", [
    ('payload = 500\npayload_at = "Q"\n', "payload_at", "unknown frame of boom 'Q'"),
    ('payload = -500\npayload_at = "T"\n', "payload", "must be >= 0"),
    ('payload = nan\npayload_at = "T"\n', "payload", "expected a finite number"),
    ('payload = 500\npayload_at = 3\n', "payload_at", "expected a string"),
])
def test_bad_task_payload_fields(fields, field, words, tmp_path, capsys):
    task = write_task(tmp_path, "bad", fields)
    base = boom_file(tmp_path, "boom")
    with pytest.raises(InputError) as caught:
        read_task(task, mechatron.load(base))
    assert (caught.value.file, caught.value.field) == (str(task), field) and words in caught.value.message
    err = one_line_error(capsys, "size", base, "--task", task)
    assert err == f"mechatron: error: {task}: field '{field}': {caught.value.message}"


@pytest.mark.parametrize("mass,frame,words", [
    (500.0, "Q", "unknown frame of boom 'Q'"),
    (-1.0, "T", "payload mass"),
    (math.nan, "T", "payload mass"),
])
def test_bad_with_payload_arguments(mass, frame, words, tmp_path):
    with pytest.raises(InputError, match=words):
        with_payload(mechatron.load(boom_file(tmp_path, "boom")), mass, frame)


# ---------------------------------------------------------------------------- the tool frame by default (item 7)
def test_frame_placement_and_jacobian_default_to_the_mechanism_s_tool_frame():
    """A mechanism file's ``tool = "C"``: frame_placement(mech, q) is that of C, and so is frame_jacobian."""
    four_bar = mechatron.load(ROOT / "examples" / "data" / "four_bar.toml")
    assert four_bar.tool_frame == "C" and "tool" not in four_bar.frame_names
    q = mechatron.assemble(four_bar, {"q1": 0.7})
    default, at_c = mechatron.frame_placement(four_bar, q), mechatron.frame_placement(four_bar, q, "C")
    np.testing.assert_array_equal(default.homogeneous, at_c.homogeneous)
    np.testing.assert_array_equal(mechatron.frame_jacobian(four_bar, q), mechatron.frame_jacobian(four_bar, q, "C"))
    puma = mechatron.load("puma560")
    q = puma.neutral()
    np.testing.assert_array_equal(mechatron.frame_placement(puma, q).homogeneous,
                                  mechatron.frame_placement(puma, q, "tool").homogeneous)

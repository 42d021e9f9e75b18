"""Designs at the speed of their kernels (issue 30), each behaviour against an independent reference:

- the generalized forces of external loads for a batch of states (dynamics/tree.py ``load_forces``, Σ J_pᵀ [F; M] by
  the batched kinematics) against Pinocchio's RNEA with the loads as external forces, state by state;
- the loop kernels compiled once per structure with the geometry as parameters (model/symbolic.py ``Geometry``,
  kinematics/compiled.py): every geometry of a design study shares one compiled code, whose sweeps equal the
  sequential Python continuation (Pinocchio per sample) of that geometry;
- a sweep that stops at its first failure (``stop_on_failure``) and a task that leaves the reachable range: the same
  first failure as the full sweep, and no sample after it tried;
- the closed loop's actuator forces from the kernel's velocity maps, τ_a = Sᵀ (M q̈ + h − Q), against the
  constrained inverse dynamics [B Jᵀ][τ_a; λ] = M q̈ + h − Q state by state, with loads and a payload;
- the pace of a study (studies/pace.py): designs done and failed, the slow design named in a warning.
"""

from __future__ import annotations

import importlib
import io
import math
import re
import warnings

import numpy as np
import pinocchio as pin
import pytest
from test_results_kinematics import rocker  # a cylinder-driven rocker: closes for s ≤ |OP| + |OR|

import mechatron
from mechatron.dynamics.constrained import inverse
from mechatron.dynamics.tree import external_forces, inverse_dynamics, load_forces
from mechatron.errors import InputError, MechatronWarning
from mechatron.io import native
from mechatron.kinematics.loops import LoopSolver, loop_solver
from mechatron.model.loads import Load

sweeps = importlib.import_module("mechatron.kinematics.sweeps")
SCISSOR = "examples/data/scissor_lift.toml"


def random_states(mech, rng, n=40):
    lower = np.where(np.isfinite(mech.model.lowerPositionLimit), mech.model.lowerPositionLimit, -2.0)
    upper = np.where(np.isfinite(mech.model.upperPositionLimit), mech.model.upperPositionLimit, 2.0)
    Q = np.array([pin.randomConfiguration(mech.model, lower, upper) for _ in range(n)])
    return Q, rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))


# ------------------------------------------------------------------------------------------- load forces
@pytest.mark.parametrize("name, frames", [("puma560", ["tool", "link3", "tool"]), (SCISSOR, ["deck", "Q", "K"]),
                                          ("delta", ["TCP", "E1"])])
def test_batched_load_forces_equal_rnea_with_external_forces(name, frames, rng):
    mech = mechatron.load(name)
    loads = [Load(f, rng.normal(size=3) * 300, rng.normal(size=3) * 20) for f in frames]
    Q, V, A = random_states(mech, rng)
    reference = np.array([pin.rnea(mech.model, mech.data, Q[i], V[i], A[i], external_forces(mech, Q[i], loads))
                          for i in range(len(Q))])
    scale = np.abs(reference).max()
    np.testing.assert_allclose(inverse_dynamics(mech, Q, V, A, loads), reference, rtol=0, atol=1e-12 * scale)
    # the loads' part alone is the virtual work Q·δq of the forces: RNEA without them minus with them
    plain = np.array([pin.rnea(mech.model, mech.data, Q[i], V[i], A[i]) for i in range(len(Q))])
    np.testing.assert_allclose(load_forces(mech, Q, loads), plain - reference, rtol=0, atol=1e-12 * scale)


def test_loads_on_joints_the_batched_kinematics_does_not_know_go_state_by_state(rng):
    mech = mechatron.load("examples/data/turret_arm.urdf")  # a continuous joint: (cos θ, sin θ)
    loads = [Load(mech.tool_frame, (10.0, -20.0, 5.0), (1.0, 0.0, 2.0))]
    Q, V, A = random_states(mech, rng, 10)
    reference = np.array([pin.rnea(mech.model, mech.data, Q[i], V[i], A[i], external_forces(mech, Q[i], loads))
                          for i in range(len(Q))])
    np.testing.assert_allclose(inverse_dynamics(mech, Q, V, A, loads), reference, rtol=1e-13, atol=1e-12)
    with pytest.raises(NotImplementedError):
        load_forces(mech, Q, loads)


# ------------------------------------------------------------------------------------- parametric kernels
def test_every_geometry_of_a_structure_shares_one_compiled_code(monkeypatch, tmp_path):
    monkeypatch.setenv(native.CACHE_VARIABLE, str(tmp_path))
    runs = []
    real = native.subprocess.run
    monkeypatch.setattr(native.subprocess, "run", lambda *a, **k: runs.append(a) or real(*a, **k))
    monkeypatch.setattr(sweeps, "COMPILED_MIN", 16)
    base = mechatron.load(SCISSOR)
    codes = set()
    for values in ({"P_x": 0.5}, {"P_x": 0.62, "P_y": -0.2}, {"arm1": 1.3, "arm2": 1.3}):
        mech = base.with_parameters(values)
        result = sweeps.sweep(mech, samples=120)
        kernel = sweeps._kernel(loop_solver(mech), list(mech.points), [], list(mech.measures), 120)
        codes.add(id(kernel.code))
        with monkeypatch.context() as patch:
            patch.setattr(sweeps, "BATCHED", False)
            reference = sweeps.sweep(mech, samples=120)
        assert len(result.table) == len(reference.table) == 120
        expected = reference.table.to_numpy(float)
        assert np.abs(result.table.to_numpy(float) - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())
    assert len(codes) == 1
    assert len(runs) == 2  # newton, and analyse with step and the driver: once for the three geometries


def test_the_parameters_are_the_models_numbers():
    from mechatron.model.symbolic import Geometry, rotation_kind

    mech = mechatron.load(SCISSOR).with_parameters({"P_x": 0.55})
    system = loop_solver(mech).system
    geometry = Geometry(mech.model, [mech.frame_id(n) for n in system.frame_names], system)
    p = geometry.values(mech.model, system)
    assert len(p) == geometry.size == 3 * (mech.model.njoints - 1 + len(system.frame_names))  # identities: no angle
    assert p[-3:].tolist() == list(mech.model.frames[mech.frame_id(system.frame_names[-1])].placement.translation)
    turn = pin.utils.rotate("z", 0.3)
    assert (rotation_kind(np.eye(3)), rotation_kind(turn), rotation_kind(pin.utils.rotate("x", 0.3))) == \
        ("identity", "z", "full")


# ------------------------------------------------------------------------------------ the first failure
def masked(reason):
    """A failure's reason with the residual left after Newton's iterations masked (it depends on the last bits of
    the start)."""
    return re.sub(r"\(closure residual .* iterations\)", "(…)", reason)


@pytest.mark.parametrize("path", ["numpy", "compiled"])
def test_a_sweep_stops_at_its_first_failure(monkeypatch, path):
    monkeypatch.setattr(sweeps, "COMPILED_MIN", 16 if path == "compiled" else 10**12)
    mech = rocker()
    reach = math.sqrt(0.17) + 0.3
    strokes = np.concatenate([np.linspace(0.2, reach - 1e-3, 200), reach + np.linspace(0.001, 0.05, 30),
                              np.linspace(reach - 1e-3, 0.3, 50)])
    full = sweeps.sweep(mech, {"s": strokes})
    tried = []
    solve = sweeps._Continuation.solve
    monkeypatch.setattr(sweeps._Continuation, "solve", lambda self, k, same: tried.append(k) or solve(self, k, same))
    result = sweeps.sweep(mech, {"s": strokes}, stop_on_failure=True)
    assert result.failures["sample"].tolist() == [200] == full.failures["sample"].tolist()[:1]
    assert masked(result.failures["reason"].iloc[0]) == masked(full.failures["reason"].iloc[0])
    assert "do not close at s = " in result.failures["reason"].iloc[0]
    assert result.table["sample"].tolist() == list(range(200))
    np.testing.assert_allclose(result.table.to_numpy(float), full.table.to_numpy(float)[:200], atol=1e-12)
    assert max(tried, default=0) <= 200  # nothing after the failure


def test_a_sweep_that_starts_out_of_range_stops_there():
    mech = rocker()
    result = sweeps.sweep(mech, {"s": np.array([0.01, 0.3, 0.4])}, stop_on_failure=True)
    assert result.table.empty and result.failures["sample"].tolist() == [0]
    assert "outside its range" in result.failures["reason"].iloc[0]


@pytest.mark.parametrize("path", ["compiled", "numpy"])
def test_a_design_that_cannot_assemble_fails_at_once_with_its_reason(monkeypatch, path):
    """P 1.5 m from the base: the cylinder's eye Q (0.9 m from foot1) is at least 1.5 − 0.9 m from P, so the task's
    first length 0.55 m cannot close; the loops are solved once (by the compiled driver of the structure, which a
    second geometry builds; without a compiler by NumPy)."""
    from mechatron.dynamics.task import read_task
    from mechatron.dynamics.trajectory import closed_loop_states

    if path == "numpy":
        monkeypatch.setenv(native.COMPILE_VARIABLE, "0")
    base = mechatron.load(SCISSOR)
    for values in ({"P_x": 0.5}, {"P_x": 0.51}):  # two geometries: the structure gets its compiled code
        closed_loop_states(base.with_parameters(values), read_task("examples/design/scissor_lift_task.toml",
                                                                   base.with_parameters(values)).trajectory)
    mech = base.with_parameters({"P_x": 1.5, "P_y": -0.15})
    task = read_task("examples/design/scissor_lift_task.toml", mech)
    calls = []
    newton = LoopSolver.newton
    monkeypatch.setattr(LoopSolver, "newton", lambda self, *a, **k: calls.append(1) or newton(self, *a, **k))
    with pytest.raises(InputError) as info:
        closed_loop_states(task.mechanism, task.trajectory)
    assert re.fullmatch(r"scissor_lift: the trajectory leaves the reachable range: scissor_lift: the loops do not "
                        r"close at cyl = 0\.55 \(closure residual 0\.0\d+ at pin cyl_eye = Q \[0\] after 50 Newton "
                        r"iterations\)", str(info.value)), str(info.value)
    assert len(calls) <= 3
    assert (sweeps.kept_sweep_kernel(loop_solver(task.mechanism)) is not None) == (path == "compiled")


# --------------------------------------------------------------------------- forces by the velocity maps
def test_actuator_forces_by_the_kernels_maps_equal_the_constrained_inverse_dynamics(monkeypatch, rng, tmp_path):
    from mechatron.dynamics.task import read_task
    from mechatron.dynamics.trajectory import actuator_duty

    monkeypatch.setattr(sweeps, "COMPILED_MIN", 16)
    task_file = tmp_path / "lift.toml"
    task_file.write_text('profile = "trapezoidal"\nvmax = 0.05\namax = 0.1\ndt = 0.05\npayload = 150\n'
                         'payload_at = "deck"\nwaypoints = [[0.52], [0.82]]\n'
                         '[[loads]]\nframe = "deck"\nforce = [400, -1500, 0]\n[[loads]]\nframe = "K"\n'
                         'force = [0, 200, 0]\nmoment = [0, 0, 50]\n')
    mech = mechatron.load(SCISSOR)
    task = read_task(task_file, mech)
    duty = actuator_duty(task.mechanism, task.trajectory, task.loads)
    assert sweeps.kept_sweep_kernel(loop_solver(task.mechanism)) is not None  # the forces came from its maps
    solver = loop_solver(task.mechanism)
    scale = np.abs(duty.forces).max()
    for k in rng.choice(len(duty.q), 15, replace=False):
        q = duty.q[k]
        v = solver.velocity(q, task.trajectory.v[k])
        a = solver.acceleration(q, v, task.trajectory.a[k])
        moving = inverse(task.mechanism, q, v, a, task.loads)[0]["cyl"]
        still = inverse(task.mechanism, q, np.zeros(mech.nv), np.zeros(mech.nv), task.loads)[0]["cyl"]
        assert abs(duty.forces[k, 0] - moving) <= 1e-9 * scale
        assert abs(duty.holding[k, 0] - still) <= 1e-9 * scale


# ------------------------------------------------------------------------------------------------- pace
def test_pace_counts_designs_and_names_the_slow_one():
    from mechatron.report.progress import progress_bar
    from mechatron.studies.pace import Pace

    stream = io.StringIO()
    bar = progress_bar("study", stream, force=True)
    pace = Pace(8, bar)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pace.add([0, 1, 2, 3], [0.1, 0.12, 0.09, 0.11], ["ok"] * 4, [""] * 4)
        assert not caught  # fewer than five designs: no median yet
        pace.add([4, 5, 6, 7], [0.1, 2.5, 0.1, 0.3], ["ok", "failed", "ok", "ok"], ["", "loops do not close", "", ""])
    assert pace.done == 8 and pace.failed == 1
    slow = [str(w.message) for w in caught if issubclass(w.category, MechatronWarning)]
    assert slow == ["design 5 took 2.5 s, 24× the median design's 0.105 s; it failed: loops do not close"]
    assert "8 done, 1 failed, " in stream.getvalue() and "designs/s" in stream.getvalue()


def test_a_study_shows_its_pace_and_its_failed_design(tmp_path, monkeypatch):
    from mechatron.studies import runner

    spec = tmp_path / "study.toml"
    spec.write_text(f'mechanism = "{(runner.Path.cwd() / SCISSOR).as_posix()}"\n'
                    '[parameters.P_x]\nvalues = [0.5, 1.5, 0.55, 0.6, 0.65, 0.7]\n[designs]\nmethod = "grid"\n'
                    '[analyses.sizing]\n'
                    f'task = "{(runner.Path.cwd() / "examples/design/scissor_lift_task.toml").as_posix()}"\n'
                    'pressure_MPa = 4\n')
    seen = []

    def progress(done, total):
        seen.append((done, total))

    progress.status = lambda text: seen.append(text)
    monkeypatch.setattr(runner, "design_times", lambda rows: [50.0 if x == 1.5 else 1.0 for x in rows["P_x"]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = runner.run_study(spec, tmp_path / "out", progress=progress, chunk_size=1)
    table = result.table if hasattr(result, "table") else result.to_frame()
    failed = table[table["status"] != "ok"]
    assert failed["P_x"].tolist() == [1.5]
    assert "the trajectory leaves the reachable range" in failed["reason"].iloc[0]
    assert seen[-1] == (6, 6) and any(isinstance(x, str) and x.startswith("6 done, 1 failed") for x in seen)
    slow = [str(w.message) for w in caught if issubclass(w.category, MechatronWarning)]
    assert len(slow) == 1 and slow[0].startswith("design 1 took 50 s, 50× the median design's 1 s; it failed: ")


def test_a_toml_file_read_again_is_parsed_once_and_changes_are_seen(tmp_path, monkeypatch):
    from mechatron.io import toml

    path = tmp_path / "task.toml"
    path.write_text("dt = 0.005\nwaypoints = [[0.1], [0.2]]\n")
    first = toml.read_toml(path)
    first["waypoints"].append([9.9])  # the caller's own copy
    parsed = []
    loads = toml.tomllib.loads
    monkeypatch.setattr(toml.tomllib, "loads", lambda text: parsed.append(text) or loads(text))
    assert toml.read_toml(path) == {"dt": 0.005, "waypoints": [[0.1], [0.2]]} and not parsed
    path.write_text("dt = 0.007\nwaypoints = [[0.1], [0.2]]\n")  # the same size, at once
    assert toml.read_toml(path)["dt"] == 0.007 and len(parsed) == 1

"""The compiled closed-loop kernels (kinematics/compiled.py, model/symbolic.py) against Pinocchio: the sequential
sweep (``sweep.BATCHED = False``: Pinocchio's frames and Jacobians per sample) at random rates and accelerations is
the reference of the kernels' Newton solve, velocities, accelerations and frame columns, to 1e-12; the virtual
machine and a missing compiler give the same numbers; a compiled library is kept and reused."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

import mechatron
from mechatron.io import native
from mechatron.kinematics.loops import LoopSolver

sweep_module = importlib.import_module("mechatron.kinematics.sweeps")
WITH_KERNELS = ["crank_slider", "six_bar_bucket", "front_shovel", "seven_bar", "scotch_yoke", "slotted_link", "delta"]


def kernel_of(mech, links=()):
    solver = LoopSolver(mech, extra_frames=[*mech.points, *links])
    return solver, sweep_module._kernel(solver, list(mech.points), list(links), list(mech.measures))


def reference_sweep(mech, links=(), samples=40, seed=0):
    """The sequential (Pinocchio) sweep at random actuated rates and accelerations."""
    rng = np.random.default_rng(seed)
    names = list(mech.actuated)
    rates = {name: rng.uniform(-2.0, 2.0, samples) for name in names}
    accelerations = {name: rng.uniform(-5.0, 5.0, samples) for name in names}
    inputs = sweep_module.default_inputs(mech, samples)
    original = sweep_module.BATCHED
    sweep_module.BATCHED = False
    try:
        result = sweep_module.sweep(mech, inputs, rates=rates, accelerations=accelerations, links=list(links))
    finally:
        sweep_module.BATCHED = original
    good = result.table["sample"].to_numpy()
    R = np.column_stack([rates[n][good] for n in names])
    A = np.column_stack([accelerations[n][good] for n in names])
    return result, R, A


def assert_close(actual, expected, tolerance=1e-12):
    scale = np.maximum(1.0, np.abs(expected))
    assert np.all(np.abs(actual - expected) <= tolerance * scale), np.abs(actual - expected).max()


@pytest.mark.parametrize("name", WITH_KERNELS)
def test_kernels_equal_pinocchio(name):
    mech = mechatron.load(name)
    links = [mech.model.frames[mech.model.nframes - 1].name] if name == "crank_slider" else []
    solver, kernel = kernel_of(mech, links)
    assert kernel is not None
    result, R, A = reference_sweep(mech, links)
    table = result.table
    assert len(table) >= 30
    # velocities, accelerations and every frame column at Pinocchio's assembled positions
    V, Aq, ratio, columns = kernel.analyse(result.q, R, A)
    assert_close(V, result.v)
    assert_close(Aq, result.a)
    assert (ratio < 1e8).all()
    for column, values in columns.items():
        if column.endswith("_angle"):  # the table's link angles are unwrapped
            values = np.unwrap(values)
        assert_close(values, table[column].to_numpy())
    # Newton from guesses 1e-4 off the solution comes back to it, and its velocity maps are S_d = −J_d⁻¹ J_a
    rng = np.random.default_rng(1)
    guess = result.q.copy()
    guess[:, solver.dep] += rng.uniform(-1e-4, 1e-4, (len(guess), len(solver.dep)))
    converged, maps = kernel.newton(guess)
    assert converged.all()
    assert_close(guess, result.q)
    for k in range(0, len(guess), 7):
        S = solver.velocity_matrix(result.q[k])
        assert_close(maps[k], S[solver.dep], 1e-9)


def test_a_guess_that_does_not_converge_is_reported():
    mech = mechatron.load("crank_slider")
    solver, kernel = kernel_of(mech)
    q = np.array([mech.reference_q, mech.reference_q])
    q[1, solver.dep] += 1.5  # far off: four Newton steps do not close the loop
    converged, maps = kernel.newton(q)
    assert converged[0] and not converged[1]
    assert np.isnan(maps[1]).all() and np.isfinite(maps[0]).all()


def test_virtual_machine_and_missing_compiler_give_the_same_numbers(monkeypatch, tmp_path):
    mech = mechatron.load("six_bar_bucket")
    result, R, A = reference_sweep(mech)
    outputs = []
    for variables in ({"MECHATRON_COMPILE": "0"}, {"CC": str(tmp_path / "no-such-compiler")}, {}):
        with monkeypatch.context() as patch:
            patch.setenv("MECHATRON_CACHE", str(tmp_path / "cache"))
            for key, value in variables.items():
                patch.setenv(key, value)
            _, kernel = kernel_of(mechatron.load("six_bar_bucket"))
            kind = kernel._analyse.class_name()
            outputs.append((kind, kernel.analyse(result.q, R, A)))
    assert [kind for kind, _ in outputs] == ["SXFunction", "SXFunction", "External"]
    for _, (V, Aq, _, columns) in outputs:
        assert_close(V, result.v)
        assert_close(Aq, result.a)
        for column, values in columns.items():
            assert_close(values, outputs[-1][1][3][column], 1e-14)


def test_a_compiled_library_is_kept_and_reused(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHATRON_CACHE", str(tmp_path))
    _, kernel = kernel_of(mechatron.load("crank_slider"))
    libraries = sorted(p.name for p in tmp_path.iterdir())
    assert len(libraries) == 2 and all(name.endswith(".so") for name in libraries)  # newton and analyse

    def no_compiler(*args, **kwargs):
        raise AssertionError("compiled again")

    monkeypatch.setattr(native.subprocess, "run", no_compiler)
    _, again = kernel_of(mechatron.load("crank_slider"))
    assert again._newton.class_name() == "External"
    assert sorted(p.name for p in tmp_path.iterdir()) == libraries  # no temporary left behind


def test_a_closure_with_no_symbolic_form_uses_the_numpy_path():
    grab = mechatron.load("grab")  # a point on a curve given by a Python function
    assert kernel_of(grab)[1] is None
    inputs = sweep_module.default_inputs(grab, 3000)
    result = sweep_module.sweep(grab, inputs)
    assert len(result.table) == 3000

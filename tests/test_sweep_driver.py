"""The compiled closed-loop sweep driver (kinematics/compiled.py ``DRIVER``, run by ``sweeps._driven`` from
``sweeps.COMPILED_MIN`` samples on, lowered here) against independent references: the sequential Python
continuation (``sweeps.BATCHED = False``: Pinocchio per sample), the crank-slider's closed form
x_C = l1 cos q1 + sqrt(l2² − (l1 sin q1)²) with its derivatives, and the loop closure residual Φ(q) ≈ 0 — over uneven
input steps, inputs that go back and forth or repeat, chunk by chunk, out of reach, and without a C compiler."""

from __future__ import annotations

import importlib
import os
import re
import shutil

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.io import native
from mechatron.kinematics import compiled
from mechatron.kinematics.loops import loop_solver

sweeps = importlib.import_module("mechatron.kinematics.sweeps")
L1, L2 = 0.1, 0.4  # the shipped crank-slider's crank and rod (m)


@pytest.fixture
def spy(monkeypatch):
    """The compiled paths switched on from 16 samples; returns the driver's runs (their sample counts) and, in
    ``runs.left``, the samples the Python continuation solved (those the driver left, or all without it)."""
    monkeypatch.setattr(sweeps, "COMPILED_MIN", 16)
    runs, real, solve = Runs(), sweeps._driven, sweeps._Continuation.solve

    def driven(*args, **kwargs):
        runs.append(len(args[2]))
        return real(*args, **kwargs)

    def solved(self, k, same_step):
        runs.left.append(k)
        return solve(self, k, same_step)

    monkeypatch.setattr(sweeps, "_driven", driven)
    monkeypatch.setattr(sweeps._Continuation, "solve", solved)
    return runs


class Runs(list):
    def __init__(self):
        super().__init__()
        self.left = []


@pytest.fixture
def driver(spy):
    """As :func:`spy`; the driver needs a C compiler (.ci/run's machine has one): without it the test fails, unless
    compiling is switched off on purpose (``MECHATRON_COMPILE=0``: skipped)."""
    if os.environ.get(native.COMPILE_VARIABLE) == "0":  # only when asked: by default the driver must be tested
        pytest.skip("MECHATRON_COMPILE=0: no compiled driver")
    if shutil.which(os.environ.get("CC", "cc")) is None:
        pytest.fail("no C compiler to build the compiled driver (cc, or the one CC names)")
    return spy


def python_path(monkeypatch, mech, inputs, **options):
    """The sequential reference sweep (no batching, no kernels)."""
    with monkeypatch.context() as patch:
        patch.setattr(sweeps, "BATCHED", False)
        return sweeps.sweep(mech, inputs, **options)


def assert_same(result, reference, tolerance=1e-9):
    """Same samples, columns and failures; q within ``tolerance`` (m, rad), v, a and every column relative to
    max(1, |value|)."""
    assert list(result.table.columns) == list(reference.table.columns)
    np.testing.assert_array_equal(result.table["sample"], reference.table["sample"])
    assert np.abs(result.q - reference.q).max(initial=0.0) <= tolerance
    for actual, expected in ((result.v, reference.v), (result.a, reference.a),
                             (result.table.to_numpy(float), reference.table.to_numpy(float))):
        assert np.all(np.abs(actual - expected) <= tolerance * np.maximum(1.0, np.abs(expected)))
    assert reasons(result) == reasons(reference)


def reasons(result):
    """The failures' records, the residual left after Newton iterations that do not converge masked (its last bits
    depend on the start, which the two paths reach by different rounding)."""
    return [{**row, "reason": re.sub(r"\(closure residual .* iterations\)", "(…)", row["reason"])}
            for row in result.failures.to_dict("records")]


def assert_closed(mech, result):
    """Every assembled row closes its loops: max |Φ(q)| at rounding level."""
    system = loop_solver(mech).system
    assert max(np.abs(system.evaluate(q)[0]).max() for q in result.q) < 1e-12


def crank_slider_closed_form(theta, omega, alpha):
    """x_C and its rate and acceleration (right branch) at crank angle θ, rate ω and acceleration α."""
    s, c = np.sin(theta), np.cos(theta)
    root = np.sqrt(L2**2 - (L1 * s) ** 2)
    x = L1 * c + root
    dx = -L1 * s - L1**2 * s * c / root
    ddx = -L1 * c - L1**2 * (np.cos(2 * theta) / root + L1**2 * s**2 * c**2 / root**3)
    return x, dx * omega, ddx * omega**2 + dx * alpha


def check_crank_slider(result, omega=1.0, alpha=0.0):
    theta = result.table["q1"].to_numpy()
    x, v, a = crank_slider_closed_form(theta, omega, alpha)
    np.testing.assert_allclose(result.table["q_xC"], x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result.table["v_xC"], v, rtol=0, atol=1e-11)
    np.testing.assert_allclose(result.table["a_xC"], a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(result.table["C_x"], x, rtol=0, atol=1e-12)


def test_uneven_input_steps(monkeypatch, driver):
    rng = np.random.default_rng(7)
    mech = mechatron.load("crank_slider")
    steps = rng.uniform(1e-4, 0.045, 499)
    steps[::50] = 0.07  # ten steps longer than the continuation's 0.05 rad: each cut in two for the driver
    angles = 0.2 + np.concatenate([[0.0], np.cumsum(steps)])
    result = sweeps.sweep(mech, {"q1": angles}, links=["rod"])
    assert driver == [510] and len(result.table) == 500 and result.failures.empty
    np.testing.assert_array_equal(result.table["q1"], angles)  # the samples asked for, exactly
    assert len(driver.left) <= 20  # the driver solved the others
    assert_same(result, python_path(monkeypatch, mech, {"q1": angles}, links=["rod"]))
    check_crank_slider(result)
    assert_closed(mech, result)
    # two inputs with different uneven steps, one rising and one falling
    seven = mechatron.load("seven_bar")
    t = np.sort(rng.uniform(0.0, 1.0, 400))
    inputs = {"s1": 0.53 + 0.18 * t, "s2": 0.755 - 0.18 * t**1.5}
    driver.left.clear()  # the reference sweep's samples
    result = sweeps.sweep(seven, inputs)
    assert driver[-1] == 400 and len(result.table) == 400 and len(driver.left) <= 10
    assert_same(result, python_path(monkeypatch, seven, inputs))
    assert_closed(seven, result)


def test_back_and_forth_and_repeated_inputs(monkeypatch, driver):
    mech = mechatron.load("crank_slider")
    up, down = np.linspace(0.0, 5.0, 251), np.linspace(5.0, -1.0, 301)[1:]  # 0.02 rad steps each way
    steady = np.repeat(np.linspace(-1.0, 0.5, 60), 3)  # each input three times: zero steps between equal steps
    angles = np.concatenate([up, down, steady, np.full(40, 0.5)])
    result = sweeps.sweep(mech, {"q1": angles})
    assert driver == [len(angles)] and len(result.table) == len(angles) and len(driver.left) <= 10
    assert_same(result, python_path(monkeypatch, mech, {"q1": angles}))
    check_crank_slider(result)  # back on the same branch after turning round
    assert_closed(mech, result)
    q = result.q
    # the same input gives the same state, whichever way it was reached
    by_angle = {}
    for k, theta in enumerate(angles):
        by_angle.setdefault(round(float(theta), 12), []).append(k)
    repeated = [rows for rows in by_angle.values() if len(rows) > 1]
    assert len(repeated) >= 250  # each angle of the rise met again on the way down, and the repeated ones
    for rows in repeated:
        assert np.abs(q[rows] - q[rows[0]]).max() <= 1e-12, rows


def test_progress_is_reported_chunk_by_chunk(monkeypatch, driver):
    monkeypatch.setattr(compiled, "CHUNK", 128)
    mech = mechatron.load("six_bar_bucket")
    strokes = np.linspace(1.15, 1.95, 500)
    calls = []
    result = sweeps.sweep(mech, {"L1": strokes}, progress=lambda done, total: calls.append((done, total)))
    assert driver == [500] and len(driver.left) <= 10
    assert calls == [(128, 500), (256, 500), (384, 500), (500, 500)]
    # the continuation's history goes across the chunks: the same numbers as the sequential path
    assert_same(result, python_path(monkeypatch, mech, {"L1": strokes}))
    assert_closed(mech, result)


@pytest.mark.parametrize("name", ["crank_slider", "six_bar_bucket", "seven_bar"])
def test_driver_equals_the_python_path(monkeypatch, driver, name):
    mech = mechatron.load(name)
    rng = np.random.default_rng(3)
    n = 600
    inputs = sweeps.default_inputs(mech, n)
    rates = {a: rng.uniform(-2.0, 2.0, n) for a in mech.actuated}
    accelerations = {a: rng.uniform(-5.0, 5.0, n) for a in mech.actuated}
    links = ["rod"] if name == "crank_slider" else []
    options = {"rates": rates, "accelerations": accelerations, "links": links}
    result = sweeps.sweep(mech, inputs, **options)
    assert driver == [n] and len(result.table) >= 0.9 * n and len(driver.left) <= 0.1 * n
    assert_same(result, python_path(monkeypatch, mech, inputs, **options))
    assert_closed(mech, result)
    if name == "crank_slider":
        check_crank_slider(result, rates["q1"], accelerations["q1"])


def test_out_of_reach_fails_as_in_the_python_path(monkeypatch, driver):
    # a crank-slider with the rod shorter than the crank: the loop closes only where |l1 sin q1| <= l2
    mech = mechatron.load("crank_slider", l2=0.09)
    angles = np.linspace(0.0, np.pi, 301)
    result = sweeps.sweep(mech, {"q1": angles})
    reference = python_path(monkeypatch, mech, {"q1": angles})
    assert driver == [301]
    assert_same(result, reference)
    failed = result.failures["sample"].to_numpy()
    margin = np.abs(L1 * np.sin(angles)) - 0.09
    assert set(np.flatnonzero(margin > 0)) <= set(failed)  # every sample out of reach
    assert not set(np.flatnonzero(margin < -2e-3)) & set(failed)  # and none well inside it
    for k, reason in zip(failed, result.failures["reason"]):
        assert f"q1 = {angles[k]:.6g}" in reason
    assert "do not close" in " ".join(result.failures["reason"])
    assert_closed(mech, result)
    # a cylinder's stroke out of its range [1.1, 2] m, from the first sample on and at the end
    bucket = mechatron.load("six_bar_bucket")
    strokes = np.linspace(1.0, 2.1, 400)
    result = sweeps.sweep(bucket, {"L1": strokes})
    reference = python_path(monkeypatch, bucket, {"L1": strokes})
    assert_same(result, reference)
    outside = np.flatnonzero((strokes < 1.1 - 1e-12) | (strokes > 2.0 + 1e-12))
    np.testing.assert_array_equal(result.failures["sample"], outside)
    for k, reason in zip(outside, result.failures["reason"]):
        assert reason.startswith(f"L1 = {strokes[k]:.6g} is outside its range")
    # inputs that cannot be swept at all: the same error from both paths
    for bad, match in (({"L1": np.append(strokes[:50], np.nan)}, "finite"), ({"L9": strokes}, "L9")):
        with pytest.raises(InputError, match=match):
            sweeps.sweep(bucket, bad)
        with pytest.raises(InputError, match=match), monkeypatch.context() as patch:
            patch.setattr(sweeps, "BATCHED", False)
            sweeps.sweep(bucket, bad)


@pytest.mark.parametrize("variable", ["CC", native.COMPILE_VARIABLE])
def test_without_a_compiler(monkeypatch, spy, tmp_path, variable):
    monkeypatch.setenv(native.CACHE_VARIABLE, str(tmp_path / "cache"))  # no library compiled before
    monkeypatch.setenv(variable, str(tmp_path / "no-such-cc") if variable == "CC" else "0")
    mech = mechatron.load("crank_slider")  # a fresh one: kernels are kept per mechanism
    angles = np.linspace(0.0, 6.0, 400)
    angles[150:] += np.linspace(0.0, 0.3, 250) ** 2  # uneven steps too
    result = sweeps.sweep(mech, {"q1": angles}, links=["rod"])
    assert spy == []  # no driver: the kernels in CasADi's virtual machine, batched
    assert not list((tmp_path / "cache").glob("*.so"))
    assert_same(result, python_path(monkeypatch, mech, {"q1": angles}, links=["rod"]))
    check_crank_slider(result)
    assert_closed(mech, result)

"""The batched sweep (kinematics/batch.py) against the sequential continuation (``sweep.BATCHED = False``, the
reference: Pinocchio per sample): every column of the table and every failure with its reason, on every shipped
closed loop, off the reference branch, with inputs out of range, loops that do not close (and back) and inputs in no
order — each by both batched paths: the NumPy evaluator and the compiled CasADi kernels
(kinematics/compiled.py, used from ``sweep.COMPILED_MIN`` samples on, lowered here so that they run)."""

from __future__ import annotations

import importlib
import math
import re

import numpy as np
import pytest
from test_results_kinematics import rocker  # a cylinder-driven rocker: closes for s ≤ |OP| + |OR|

import mechatron
from mechatron.kinematics import batch
from mechatron.kinematics.loops import loop_solver

sweep_module = importlib.import_module("mechatron.kinematics.sweeps")
CLOSED_LOOPS = ["crank_slider", "six_bar_bucket", "front_shovel", "grab", "seven_bar", "scotch_yoke", "slotted_link",
                "delta"]


@pytest.fixture(autouse=True, params=["numpy", "compiled"])
def batched_path(request, monkeypatch):
    """Run each test by the NumPy batched path and by the compiled kernels."""
    monkeypatch.setattr(sweep_module, "COMPILED_MIN", 16 if request.param == "compiled" else 10**12)
    return request.param


def both(monkeypatch, mech, inputs=None, **options):
    """(sequential, batched) sweeps of ``mech``."""
    with monkeypatch.context() as patch:
        patch.setattr(sweep_module, "BATCHED", False)
        reference = sweep_module.sweep(mech, inputs, **options)
    return reference, sweep_module.sweep(mech, inputs, **options)


def assert_same(reference, result, tolerance=1e-10):
    assert list(result.table.columns) == list(reference.table.columns)
    np.testing.assert_array_equal(result.table["sample"], reference.table["sample"])
    expected = reference.table.to_numpy(float)
    scale = np.maximum(1.0, np.abs(expected))
    assert np.abs(result.table.to_numpy(float) - expected).max(initial=0.0) <= tolerance * scale.max(initial=1.0)
    assert _reasons(result) == _reasons(reference)


def _reasons(result):
    """The failures' records with the residual and the worst closure row left after 50 Newton iterations that do
    not converge masked: they depend on the last bits of the start (the batched and the sequential solutions before
    it differ by rounding)."""
    return [{**row, "reason": re.sub(r"\(closure residual .* iterations\)", "(…)", row["reason"])}
            for row in result.failures.to_dict("records")]


@pytest.mark.parametrize("name", CLOSED_LOOPS)
def test_batched_sweep_equals_the_sequential_one(monkeypatch, name):
    mech = mechatron.load(name)
    reference, result = both(monkeypatch, mech, samples=150)
    assert len(result.table) == 150
    assert_same(reference, result)


def test_the_other_branch_and_inputs_out_of_range(monkeypatch):
    mech = mechatron.load("crank_slider")
    angles = np.linspace(-4.0, 4.0, 300)
    reference, result = both(monkeypatch, mech, {"q1": angles}, guess=mech.branches["left"], links=["rod"])
    assert_same(reference, result)
    bucket = mechatron.load("six_bar_bucket")
    i = loop_solver(bucket).index["L1"]
    lower, upper = bucket.model.lowerPositionLimit[i], bucket.model.upperPositionLimit[i]
    strokes = np.linspace(lower - 0.1, upper + 0.1, 400)
    reference, result = both(monkeypatch, bucket, {"L1": strokes})
    assert len(result.failures) > 0 and "outside its range" in result.failures["reason"].iloc[0]
    assert_same(reference, result)


def test_loops_that_do_not_close(monkeypatch):
    mech = rocker()
    reach = math.sqrt(0.17) + 0.3
    strokes = np.concatenate([np.linspace(0.2, reach - 1e-3, 200), reach + np.linspace(0.001, 0.05, 30),
                              np.linspace(reach - 1e-3, 0.3, 50)])
    reference, result = both(monkeypatch, mech, {"s": strokes})
    reasons = " ".join(result.failures["reason"])
    assert "do not close" in reasons
    assert_same(reference, result)


def test_inputs_in_no_order_are_solved_sequentially(monkeypatch):
    mech = mechatron.load("crank_slider")
    angles = np.random.default_rng(5).uniform(-3.0, 3.0, 200)
    reference, result = both(monkeypatch, mech, {"q1": angles})
    assert_same(reference, result)


def test_interpolation_and_stride():
    anchors = np.array([0, 10, 20, 30, 40])
    values = (anchors**3 - 2.0 * anchors)[:, None]
    samples = np.arange(41)
    np.testing.assert_allclose(batch.interpolate(anchors, values, samples)[:, 0], samples**3 - 2.0 * samples,
                               atol=1e-9)
    U = 0.5 * np.arange(101.0)[:, None]
    assert batch.anchor_stride(U, np.array([4.0])) == 8
    assert batch.anchor_stride(U[:1], np.array([4.0])) == 1
    np.testing.assert_array_equal(batch.every(np.arange(10), 4), [0, 4, 8, 9])


def _rows_agree(reference, result, rows, tolerance):
    """Whether the table rows ``rows`` agree element by element to ``tolerance`` relative to max(1, |value|)."""
    expected = reference.table.to_numpy(float)[rows]
    difference = np.abs(result.table.to_numpy(float)[rows] - expected)
    return bool((difference <= tolerance * np.maximum(1.0, np.abs(expected))).all())


def test_through_singular_positions(monkeypatch):
    """Sweeps through singular positions, where Newton's method converges only linearly (the closure Jacobian J_d is
    singular at the solution) and a position is exact to about √TOLERANCE: the batched sweep keeps the same samples
    and branch as the sequential one, agrees with it to 1e-10 away from the singular positions and to 1e-4 (m, rad)
    in the positions at them."""
    # a crank-slider with l1 = l2: at q1 = π/2 (sample 100) the slider pin C meets the crank's pivot A and the folded
    # branch (C stays at A) crosses the open one (x_C = 2 l1 cos q1); both sweeps report that sample as a singular
    # position (J_d is singular there: q1 does not determine the rod's angle)
    mech = mechatron.load("crank_slider", l2=0.1)
    angles = np.linspace(0.3, np.pi - 0.3, 201)
    reference, result = both(monkeypatch, mech, {"q1": angles})
    assert abs(angles[100] - np.pi / 2) < 1e-15
    assert list(reference.failures["sample"]) == [100] and "singular position" in reference.failures["reason"][0]
    assert len(result.table) == len(reference.table) == 200 and _reasons(result) == _reasons(reference)
    samples = reference.table["sample"].to_numpy()
    away = np.flatnonzero((samples < 99) | (samples > 101))
    assert _rows_agree(reference, result, away, 1e-10)
    assert np.abs(reference.table["q_xC"][samples < 99]).max() < 1e-9  # folded before the crossing; after it both
    # sweeps go on along the same branch (which one, the folded or the open, is decided by the last bits of the
    # position at the crossing)
    positions = [f"q_{joint}" for joint in mech.joint_names]
    assert np.abs(result.table[positions].to_numpy() - reference.table[positions].to_numpy()).max() < 1e-4
    # the crank-slider driven by its slider from the inner to the outer dead centre (x_C = l2 ∓ l1): the crank's
    # rate grows without bound at both ends
    mech = mechatron.load("crank_slider").with_actuated(["xC"])
    reference, result = both(monkeypatch, mech, {"xC": np.linspace(0.3, 0.5, 101)})
    assert len(result.table) == len(reference.table) == 101 and _reasons(result) == _reasons(reference)
    assert _rows_agree(reference, result, np.arange(1, 100), 1e-10)
    assert np.abs(result.table[positions].to_numpy() - reference.table[positions].to_numpy()).max() < 1e-4
    assert (np.abs(result.table["v_q1"].iloc[[0, -1]]) > 1e4).all()

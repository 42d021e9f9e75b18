"""The fast paths of the closed-loop Monte Carlo: the planar evaluator (placements as complex numbers) against the
spatial one and against one Pinocchio loop solve per sample, at random samples, to 1e-12 m; the vectorized Gaussian
elimination of the Newton systems against LAPACK, with its pivot test and fallbacks; the bucket's study statistics
by both paths and seeded runs, and its memory within the Monte Carlo's estimate; the shortened series and the blocked
transpose of the serial evaluator."""

from __future__ import annotations

import numpy as np
import pytest
from test_accuracy import geometric_parameters  # the parameters that keep the drawn inputs in range
from test_bounded import peak

import mechatron
from mechatron.accuracy import nonlinear, study
from mechatron.accuracy.nonlinear import (
    SERIES_LIMIT,
    PerturbedLoop,
    PerturbedLoops,
    _cos_sin,
    _eliminate,
    _rows_product,
    _screw,
    _solve_batch,
    _transposed,
)
from mechatron.accuracy.sources import ErrorSource
from mechatron.accuracy.study import analyse_tolerances as run_study
from mechatron.kinematics.loops import assemble

PLANAR = [("crank_slider", {"q1": 1.0}, "C"), ("six_bar_bucket", {"L1": 1.5}, "K"),
          ("seven_bar", {"s1": 0.6, "s2": 0.65}, None), ("slotted_link", {"q1": 2.0}, None),
          ("scotch_yoke", {}, None), ("grab", {}, None)]


@pytest.mark.parametrize("name, inputs, frame", PLANAR)
def test_planar_path_equals_spatial_path_and_pinocchio(name, inputs, frame):
    """Pins, sliders (a locked angle, rotating parameter factors on the slotted link), a curve: the planar path,
    the spatial path and the per-sample Pinocchio loop solver give the same point to 1e-12 m, at errors of 2 % and
    of 10 % of the parameters (several Newton steps)."""
    rng = np.random.default_rng(7)
    mech = mechatron.load(name)
    frame = frame or mech.tool_frame
    q = assemble(mech, inputs)
    names = geometric_parameters(mech)
    planar, spatial = PerturbedLoops(mech, frame, names), PerturbedLoops(mech, frame, names, planar=False)
    assert planar.planar is not None and spatial.planar is None
    slow = PerturbedLoop(mech, frame, names)
    values = mech.parameter_values()
    for size in (2e-2, 1e-1):
        scale = np.array([size * max(0.1, abs(values[n])) for n in names])
        dl = rng.normal(size=(8, len(names))) * scale
        dq = rng.normal(size=(8, len(mech.actuated))) * size
        reference = slow.positions(q, dl, dq)
        closed = np.isfinite(reference).all(axis=1)
        assert closed.sum() >= 4, name
        for evaluator in (planar, spatial):
            fast = evaluator.positions(q, dl, dq)
            assert np.array_equal(np.isfinite(fast).all(axis=1), closed), name
            assert np.allclose(fast[closed], reference[closed], atol=1e-12, rtol=0), name


def test_rotating_factors_take_the_general_planar_product():
    """The slotted link's parameters turn a placement (ω ≠ 0): those factors are composed one by one."""
    mech = mechatron.load("slotted_link")
    loops = PerturbedLoops(mech, mech.tool_frame, geometric_parameters(mech))
    assert loops.planar.moving


def test_elimination_equals_lapack_and_falls_back_where_the_pivots_fail():
    """Near-equal systems (a Monte Carlo's) are solved by elimination to LAPACK's accuracy; systems whose rows would
    need another pivot order fail the pivot test and are solved by LAPACK; a singular one by least squares."""
    rng = np.random.default_rng(3)
    for m in (1, 2, 4, 6):
        A = rng.normal(size=(m, m, 1)) + 1e-3 * rng.normal(size=(m, m, 500))
        b = rng.normal(size=(m, 500))
        x, good = _eliminate(A, b)
        assert good.all()
        exact = np.linalg.solve(A.transpose(2, 0, 1), b.T[..., None])[..., 0].T
        assert np.allclose(x, exact, atol=1e-10 * np.abs(exact).max(), rtol=0)
    A = rng.normal(size=(4, 4, 300))  # unrelated systems: the first one's pivot order fails some
    A[:, :, 7] = 0.0
    A[:, 0, 7] = A[:, 1, 7] = 1.0  # singular, rank 2
    b = rng.normal(size=(4, 300))
    good = _eliminate(A, b)[1]
    assert 0 < good.sum() < 299 and not good[7]
    x = _solve_batch(A, b)
    exact = np.linalg.lstsq(A[:, :, 7], b[:, 7], rcond=None)[0]
    assert np.allclose(x[:, 7], exact, atol=1e-10)
    rest = np.delete(np.arange(300), 7)
    residual = np.einsum("ijn,jn->in", A[:, :, rest], x[:, rest]) - b[:, rest]
    assert np.abs(residual).max() < 1e-9


def bucket_study(seed):
    mech = mechatron.load("six_bar_bucket")
    sources = [ErrorSource(n, "parameter", "m", 1e-3) for n in mech.parameters]
    sources += [ErrorSource(n, "coordinate", "m", 5e-4) for n in mech.actuated]
    return run_study(mech, sources, [[1.5]], frame="K", methods=["mc"], samples=3000, seed=seed)


def test_bucket_study_by_both_paths_and_seeded(monkeypatch):
    """The bucket's Monte Carlo statistics by the planar path equal the spatial path's (the same samples to
    1e-12 m) and a seeded run repeats exactly."""
    fast = bucket_study(5)
    assert fast.poses.equals(bucket_study(5).poses)
    monkeypatch.setattr(study, "perturbed_positions",
                        lambda mech, frame, names: nonlinear.PerturbedLoops(mech, frame, names, planar=False))
    spatial = bucket_study(5)
    columns = [c for c in fast.poses.columns if c.endswith("_mc")]
    assert columns
    assert np.allclose(fast.poses[columns].to_numpy(float), spatial.poses[columns].to_numpy(float), rtol=1e-9,
                       atol=1e-13)
    assert np.allclose(fast.samples, spatial.samples, atol=1e-12, rtol=0)


def test_bucket_study_memory_within_the_estimate():
    """The closed-loop Monte Carlo's traced peak stays within the Monte Carlo's memory estimate."""
    mech = mechatron.load("six_bar_bucket")
    sources = [ErrorSource(n, "parameter", "m", 1e-3) for n in mech.parameters]
    sources += [ErrorSource(n, "coordinate", "m", 5e-4) for n in mech.actuated]
    run_study(mech, sources, [[1.5]], frame="K", methods=["mc"], samples=1000)
    measured, _ = peak(lambda: run_study(mech, sources, [[1.5]], frame="K", methods=["mc"], samples=70_000))
    assert measured <= study.monte_carlo_budget(70_000, len(sources), 1)


@pytest.mark.parametrize("largest", [1e-9, 1e-6, 4e-4, 3e-3, SERIES_LIMIT, 0.5])
def test_series_with_the_fewest_terms_are_exact_to_rounding(largest):
    """cos, sin (about an offset too) and the screw factors (1 − cos θ)/θ, (θ − sin θ)/θ by the shortened series
    equal the library functions to rounding at every magnitude."""
    angle = np.linspace(-largest, largest, 101)
    c, s = _cos_sin(angle)
    assert np.allclose(c, np.cos(angle), atol=2e-16, rtol=0) and np.allclose(s, np.sin(angle), atol=2e-16, rtol=0)
    c, s = _cos_sin(angle, 0.7)
    assert np.allclose(c, np.cos(0.7 + angle), atol=3e-16) and np.allclose(s, np.sin(0.7 + angle), atol=3e-16)
    if largest > SERIES_LIMIT:
        return
    a, b = _screw(angle)
    a_exact = 2 * np.sin(angle / 2) ** 2 / np.where(angle == 0, 1.0, angle)  # (1 − cos θ)/θ without cancellation
    b_exact = angle ** 2 / 6 - angle ** 4 / 120 + angle ** 6 / 5040 - angle ** 8 / 362880  # error < 3e-23
    assert np.allclose(a, a_exact, atol=1e-17, rtol=1e-14) and np.allclose(b, b_exact, atol=1e-17, rtol=1e-14)


def test_blocked_transpose_and_product():
    rng = np.random.default_rng(0)
    a, B = rng.normal(size=(1300, 7)), rng.normal(size=(7, 3))
    assert np.array_equal(_transposed(a), a.T) and _transposed(a).flags.c_contiguous
    assert np.allclose(_rows_product(a, B), a @ B, atol=1e-13, rtol=0)


@pytest.mark.parametrize("planar", [True, False])
def test_no_sample_and_one_sample(planar):
    mech = mechatron.load("six_bar_bucket")
    q, names = assemble(mech, {"L1": 1.5}), list(mech.parameters)
    loops = PerturbedLoops(mech, "K", names, planar=planar)
    assert loops.positions(q, np.zeros((0, len(names))), np.zeros((0, 1))).shape == (0, 3)
    dl, dq = np.full((1, len(names)), 1e-3), np.full((1, 1), -2e-3)
    assert np.allclose(loops.positions(q, dl, dq), PerturbedLoop(mech, "K", names).positions(q, dl, dq), atol=1e-12,
                       rtol=0)

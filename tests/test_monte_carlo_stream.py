"""The Monte Carlo in constant memory (issue 14): streamed statistics equal the all-in-memory ones on the same seeded
samples — moments to 1e-12 relative, the yield exactly, the variance shares to 1e-9, the quantiles exact up to the
exact store and within half a histogram bin beyond — whatever the chunk size."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.accuracy import streaming, study
from mechatron.accuracy.nonlinear import perturbed_positions
from mechatron.accuracy.sources import ErrorSource
from mechatron.accuracy.streaming import Moments, Quantiles, variance_shares
from mechatron.accuracy.study import analyse_tolerances as run_study
from mechatron.accuracy.study import draw_errors


def lstsq_shares(delta, errors):
    """The shares as the all-in-memory Monte Carlo computed them: lstsq of centred Δr on centred errors."""
    centred = errors - errors.mean(axis=0)
    response = delta - delta.mean(axis=0)
    beta, *_ = np.linalg.lstsq(centred, response, rcond=None)
    part = ((beta * centred.std(axis=0)[:, None]) ** 2).sum(axis=1)
    return 100 * part / response.var(axis=0).sum()


def chunks(x, size):
    return [x[i:i + size] for i in range(0, len(x), size)]


@pytest.mark.parametrize("size", [1, 7, 1000, 20000])
def test_moments_and_shares_merged_over_chunks_equal_the_whole(size):
    rng = np.random.default_rng(3)
    errors = rng.normal(size=(20000, 5)) * [1e-4, 3e-5, 2e-4, 1e-3, 5e-5] + 1e-4  # biased: mean ≫ spread
    delta = errors @ rng.normal(size=(5, 3)) + 1e-3 * errors**2 @ rng.normal(size=(5, 3)) + 0.01
    x = np.concatenate([errors, delta], axis=1)
    moments = Moments(8)
    for part in chunks(x, size):
        moments.add(part)
    assert moments.n == len(x)
    assert np.allclose(moments.mean, x.mean(axis=0), rtol=1e-12, atol=0)
    assert np.allclose(moments.variance(), x.var(axis=0, ddof=1), rtol=1e-12, atol=0)
    assert np.allclose(variance_shares(moments, 5), lstsq_shares(delta, errors), rtol=1e-9, atol=1e-9)


def test_quantiles_exact_then_within_half_a_bin():
    rng = np.random.default_rng(5)
    r = np.linalg.norm(rng.normal(size=(60000, 3)), axis=1) * 1e-4
    levels = [0.5, 0.95, 0.99, 0.9973, 0.0, 1.0]
    exact = Quantiles(len(r))
    for part in chunks(r, 7000):
        exact.add(part)
    assert exact.bound == 0 and np.array_equal(exact.quantiles(levels), np.quantile(r, levels))
    binned = Quantiles(len(r), exact=10000, bins=4096)
    for part in chunks(r, 7000):
        binned.add(part)
    top = streaming.HEADROOM * r[:14000].max()  # the store and the chunk past it
    assert binned.bound == pytest.approx(top / 4096 / 2)
    assert np.all(np.abs(binned.quantiles(levels) - np.quantile(r, levels)) <= binned.bound * (1 + 1e-12))
    assert binned.largest == r.max()
    spread = Quantiles(4, exact=2, bins=16)  # a sample far past the range: the overflow gives the largest
    spread.add(np.array([1.0, 1.0]))
    spread.add(np.array([1.0, 100.0]))
    assert spread.quantiles([1.0])[0] == 100.0 and spread.quantiles([0.0])[0] == pytest.approx(1.0, abs=spread.bound)


def puma_sources(mech):
    out = [ErrorSource(n, "parameter", "m" if p.kind == "length" else "rad", 5e-5 if p.kind == "length" else 1e-4,
                       "uniform" if p.kind == "length" else "normal")
           for n, p in mech.parameters.items() if p.kind in ("length", "angle")]
    return out + [ErrorSource(n, "coordinate", "rad", 2e-4, bias=1e-5) for n in mech.joint_names]


def in_memory(mech, sources, q, nominal, samples, seed, k):
    """Δr and errors of the same seeded draws, all in memory (the chunks of the study's draws)."""
    rng = np.random.default_rng(seed)
    errors = np.concatenate([draw_errors(sources, min(study.CHUNK, samples - s), rng, k)
                             for s in range(0, samples, study.CHUNK)])
    parameters = [j for j, s in enumerate(sources) if s.kind == "parameter"]
    evaluator = perturbed_positions(mech, "tool", [sources[j].name for j in parameters])
    delta = evaluator.positions(q, errors[:, parameters], errors[:, len(parameters):]) - nominal
    return delta, errors


@pytest.mark.parametrize("exact", [None, 20000])
def test_streamed_study_equals_the_statistics_of_all_samples(monkeypatch, exact):
    """The PUMA with 30 sources, 70,000 samples (three chunks): the table's statistics against the same samples
    kept whole; with a 20,000-sample exact store the quantiles are within the stated half bin."""
    if exact:
        monkeypatch.setattr(streaming, "EXACT_SAMPLES", exact)
    mech = mechatron.load("puma560")
    sources = puma_sources(mech)
    q = np.array([0.3, -0.5, 0.7, 0.2, -0.4, 0.9])
    samples, k, limit = 70000, 3.0, 4e-4
    result = run_study(mech, sources, q, methods=["mc"], samples=samples, seed=11, limit=limit)
    delta, errors = in_memory(mech, sources, q, result.sensitivities.positions[0], samples, 11, k)
    row = result.poses.iloc[0]
    r = np.linalg.norm(delta, axis=1)
    mean, std = delta.mean(axis=0), delta.std(axis=0, ddof=1)
    for axis, value in zip(("dx", "dy", "dz"), np.abs(mean) + k * std):
        assert row[f"{axis}_mc"] == pytest.approx(value, rel=1e-12)
    assert row["mean_dr_mc"] == pytest.approx(r.mean(), rel=1e-12)
    assert row["std_dr_mc"] == pytest.approx(r.std(ddof=1), rel=1e-12)
    assert row["max_dr_mc"] == r.max() and row["failed_mc"] == 0
    assert row["yield_mc"] == np.mean(r <= limit)
    levels = [math.erf(k / math.sqrt(2)), 0.5, 0.95, 0.99]
    quantiles = [row[c] for c in ("dr_mc", "p50_dr_mc", "p95_dr_mc", "p99_dr_mc")]
    top = streaming.HEADROOM * r[:study.CHUNK].max()  # the first chunk overflows the store
    bound = 0.0 if exact is None else top / streaming.BINS / 2
    assert np.all(np.abs(np.array(quantiles) - np.quantile(r, levels)) <= bound * (1 + 1e-12))
    assert any("histogram" in note for note in result.notes) == bool(exact)
    shares = result.contributions.set_index("source")["mc_share"]
    expected = dict(zip([s.name for s in sources], lstsq_shares(delta, errors)))
    assert np.allclose([shares[n] for n in expected], list(expected.values()), rtol=1e-9, atol=1e-9)
    assert np.array_equal(result.samples, delta)


def test_kept_samples_are_bounded_and_the_budget_is_a_time_bound(monkeypatch):
    from mechatron.io import budget

    monkeypatch.setattr(study, "KEPT_SAMPLES", 1000)
    mech = mechatron.load("planar_2r")
    sources = [ErrorSource("q1", "coordinate", "rad", 1e-3), ErrorSource("q2", "coordinate", "rad", 1e-3)]
    result = run_study(mech, sources, [[0.3, 0.4]], methods=["mc"], samples=5000, seed=1)
    assert result.samples.shape == (1000, 3)
    small, large = study.monte_carlo_budget(2000, 30, 1), study.monte_carlo_budget(1e8, 30, 1)
    assert large == study.monte_carlo_budget(2e6, 30, 1) and large < 2**30 and small <= large
    with pytest.raises(budget.BudgetError, match="at least"):
        study.monte_carlo_budget(1e9, 30, 1)


def test_closed_loop_study_equals_pinocchio_per_sample():
    """The bucket's Monte Carlo (loops closed for all samples at once) against one Pinocchio solve per sample on
    the same seeded draws: Δr to 1e-10 m."""
    from mechatron.accuracy.nonlinear import PerturbedLoop

    mech = mechatron.load("six_bar_bucket")
    sources = [ErrorSource(n, "parameter", "m", 1e-3) for n in mech.parameters]
    sources += [ErrorSource(n, "coordinate", "m", 5e-4) for n in mech.actuated]
    result = run_study(mech, sources, [[1.5]], frame="K", methods=["mc"], samples=150, seed=4)
    errors = draw_errors(sources, 150, np.random.default_rng(4), 3.0)
    names = list(mech.parameters)
    slow = PerturbedLoop(mech, "K", names).positions(result.sensitivities.q[0], errors[:, : len(names)],
                                                     errors[:, len(names):])
    assert np.allclose(result.samples, slow - result.sensitivities.positions[0], atol=1e-10, rtol=0)

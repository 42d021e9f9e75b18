"""Tolerance studies: the PUMA 560 tool point with errors on all 24 DH parameters and the 6 joint coordinates, and
the six-bar bucket linkage (two closed loops) with errors on its 4 parameters and its cylinder.

1. Monte Carlo of the full nonlinear model of the PUMA, 1,000,000 samples at one pose (goal: under 3 s), against a
   plain per-sample Pinocchio loop (a model copy takes the perturbed placements, then forward kinematics), timed on a
   slice and scaled; both agree on the slice. That loop is the reference of correctness, not what a competent user
   would time against: the fair comparison is 4.
2. The linear methods (worst case and RSS) over 10,000 poses (goal: under 1 s), against finite differences of
   forward kinematics with the rebuilt models (the way a script without the regressors does it), timed on a slice.
3. Monte Carlo of the closed loops, 100,000 samples at one pose (goal: under 3 s), vectorized over the samples
   (the loops closed by Newton's method for all samples at once), against the per-sample Pinocchio loop solver,
   timed on a slice and scaled; both agree on the slice.

4. The serial evaluator against a hand-tuned NumPy standard-DH chain (what a competent user writes: the tool point
   carried back through Rz(θ+q) Tz(d) Tx(a) Rx(α) of the 24 perturbed DH values and 6 joint errors, one cos/sin
   pair per angle, over all samples at once) on the same draws (goal: at most 1.5x per sample), and the whole
   Monte Carlo (``run_study``: draws, evaluation, streamed statistics) against the same work in NumPy
   (:func:`lean_monte_carlo`: the same draws chunk by chunk, that chain, and the study's statistics — per axis
   |mean| + k·std, the mean, spread, largest value and quantiles of |Δr|, the co-moments of the errors and Δr merged
   chunk by chunk and each error's variance share from them, the samples kept for the charts), timed in turns
   (timing.interleaved) and checked to give the study's numbers.
5. The closed-loop Monte Carlo (bucket) against the serial one (PUMA) per sample (goal: at most 5x), and its
   evaluator's planar path (placements as complex numbers) against its spatial path (3x3 rotations) on the same draws.
6. The peak resident memory of a 1e8-sample PUMA study, run in a subprocess (goal: under 1 GB; the statistics are
   streamed in chunks, see mechatron/accuracy/streaming.py).

    python benchmarks/accuracy.py [--samples N] [--poses N] [--loop-samples N] [--peak-samples N]
"""

from __future__ import annotations

import argparse
import math
import resource
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin
from timing import best_time, interleaved

import mechatron
from mechatron.accuracy.nonlinear import PerturbedChain, PerturbedLoop, PerturbedLoops
from mechatron.accuracy.sources import ErrorSource
from mechatron.accuracy.streaming import EXACT_SAMPLES
from mechatron.accuracy.study import CHUNK, draw_errors
from mechatron.accuracy.study import analyse_tolerances as run_study
from mechatron.kinematics.loops import assemble


def sources(mech: mechatron.Mechanism) -> list[ErrorSource]:
    out = [ErrorSource(n, "parameter", "m" if p.kind == "length" else "rad", 5e-5 if p.kind == "length" else 1e-4)
           for n, p in mech.parameters.items() if p.kind in ("length", "angle")]
    return out + [ErrorSource(n, "coordinate", "rad", 2e-4) for n in mech.joint_names]


def finite_difference_rows(rebuilt, q: np.ndarray, steps: np.ndarray, fid: int) -> np.ndarray:
    """∂r/∂l by central differences of FK with the models rebuilt at l ± h (rebuilt: list of (plus, minus))."""
    columns = []
    for (plus, minus), h in zip(rebuilt, steps):
        positions = []
        for model, data in (plus, minus):
            pin.framesForwardKinematics(model, data, q)
            positions.append(data.oMf[fid].translation.copy())
        columns.append((positions[0] - positions[1]) / (2 * h))
    return np.array(columns).T


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--poses", type=int, default=10_000)
    parser.add_argument("--loop-samples", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--peak-samples", type=float, default=1e8, help="samples of the peak-memory study (0: skip)")
    parser.add_argument("--peak-child", type=float, default=0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.peak_child:
        return peak_child(int(args.peak_child))
    puma = mechatron.load("puma560")
    errors = sources(puma)
    q = np.array([0.3, -0.5, 0.7, 0.2, -0.4, 0.9])
    run_study(puma, errors, q, methods=["mc"], samples=1000)  # placement twists and factor order, once

    print(f"PUMA 560 tool point, {len(errors)} error sources")
    t_mc = best_time(lambda: run_study(puma, errors, q, methods=["mc"], samples=args.samples), args.repeats)
    names = [s.name for s in errors if s.kind == "parameter"]
    chain, loop = PerturbedChain(puma, "tool", names), PerturbedLoop(puma, "tool", names)
    draws = draw_errors(errors, 2000, np.random.default_rng(1), 3.0)
    dl, dq = draws[:, : len(names)], draws[:, len(names):]
    start = time.perf_counter()
    slow = np.array([loop.position(q, dl[i], dq[i]) for i in range(len(draws))])
    t_loop = (time.perf_counter() - start) * args.samples / len(draws)
    assert np.allclose(chain.positions(q, dl, dq), slow, atol=1e-12, rtol=0)
    print(f"{'':<44}{'time':>10}")
    print(f"{'Monte Carlo, ' + format(args.samples, ',') + ' samples, one pose':<44}{t_mc:>8.2f} s   goal < 3 s: "
          f"{'ok' if t_mc < 3 else 'SLOWER'}")
    print(f"{'  per-sample Pinocchio loop (scaled)':<44}{t_loop:>8.1f} s   ratio {t_mc / t_loop:.4f} "
          f"({t_loop / t_mc:.0f}x faster; agree to 1e-12 m on {len(draws)} samples)")

    Q = puma.random_configuration(np.random.default_rng(0), size=args.poses)
    t_linear = best_time(lambda: run_study(puma, errors, Q, methods=["worst", "rss"]), args.repeats)
    values = puma.parameter_values()
    steps = np.array([1e-6 * max(1.0, abs(values[n])) for n in names])
    rebuilt = []
    for name, h in zip(names, steps):
        pair = []
        for sign in (1, -1):
            model = puma.with_parameters({name: values[name] + sign * h}).model
            pair.append((model, model.createData()))
        rebuilt.append(pair)
    fid = puma.frame_id("tool")
    reference = run_study(puma, errors, Q[:200], methods=["worst"]).sensitivities.matrix[:, :, : len(names)]
    start = time.perf_counter()
    slow = np.array([finite_difference_rows(rebuilt, qi, steps, fid) for qi in Q[:200]])
    t_fd = (time.perf_counter() - start) * args.poses / 200
    assert np.allclose(slow, reference, atol=1e-7)
    print(f"{'worst case + RSS, ' + format(args.poses, ',') + ' poses':<44}{t_linear:>8.2f} s   goal < 1 s: "
          f"{'ok' if t_linear < 1 else 'SLOWER'}")
    print(f"{'  finite differences of FK (scaled)':<44}{t_fd:>8.2f} s   ratio {t_linear / t_fd:.3f} "
          f"(parameter columns only; agree to 1e-7 on 200 poses)")
    t_serial = closed_loops(args.loop_samples, args.repeats, t_mc / args.samples)
    dh_chain(puma, errors, q, args.samples, args.repeats, t_serial)
    if args.peak_samples:
        peak_memory(int(args.peak_samples))


def closed_loops(samples: int, repeats: int, serial: float) -> float:
    """Monte Carlo of the bucket linkage: vectorized against one sample at a time, and per sample against the
    serial Monte Carlo (``serial`` s per sample). Returns the serial time per sample."""
    bucket = mechatron.load("six_bar_bucket")
    errors = [ErrorSource(n, "parameter", "m", 1e-3) for n in bucket.parameters]
    errors += [ErrorSource(n, "coordinate", "m", 5e-4) for n in bucket.actuated]
    q = assemble(bucket, {"L1": 1.5})
    run_study(bucket, errors, [[1.5]], frame="K", methods=["mc"], samples=1000)
    t_mc = best_time(lambda: run_study(bucket, errors, [[1.5]], frame="K", methods=["mc"], samples=samples), repeats)
    names = [s.name for s in errors if s.kind == "parameter"]
    fast, slow = PerturbedLoops(bucket, "K", names), PerturbedLoop(bucket, "K", names)
    draws = draw_errors(errors, 500, np.random.default_rng(1), 3.0)
    dl, dq = draws[:, : len(names)], draws[:, len(names):]
    start = time.perf_counter()
    reference = slow.positions(q, dl, dq)
    t_loop = (time.perf_counter() - start) * samples / len(draws)
    assert np.allclose(fast.positions(q, dl, dq), reference, atol=1e-12, rtol=0)
    print(f"{'Monte Carlo, bucket, ' + format(samples, ',') + ' samples':<44}{t_mc:>8.2f} s   goal < 3 s: "
          f"{'ok' if t_mc < 3 else 'SLOWER'}")
    print(f"{'  per-sample Pinocchio loop solver (scaled)':<44}{t_loop:>8.1f} s   ratio {t_mc / t_loop:.4f} "
          f"({t_loop / t_mc:.0f}x faster; agree to 1e-12 m on {len(draws)} samples)")
    draws = draw_errors(errors, 32768, np.random.default_rng(2), 3.0)
    dl, dq = draws[:, : len(names)], draws[:, len(names):]
    spatial = PerturbedLoops(bucket, "K", names, planar=False)
    assert fast.planar is not None
    assert np.allclose(fast.positions(q, dl, dq), spatial.positions(q, dl, dq), atol=1e-12, rtol=0)
    t_planar = best_time(lambda: fast.positions(q, dl, dq), repeats) / len(dl)
    t_spatial = best_time(lambda: spatial.positions(q, dl, dq), repeats) / len(dl)
    print(f"{'  evaluator, planar path, per sample':<44}{t_planar * 1e6:>7.2f} µs   ratio {t_planar / t_spatial:.2f} "
          f"vs the spatial path ({t_spatial * 1e6:.2f} µs; agree to 1e-12 m on {len(dl)} samples)")
    per_sample = t_mc / samples
    print(f"{'  per sample vs the serial (PUMA) Monte Carlo':<44}{per_sample * 1e6:>7.2f} µs   ratio "
          f"{per_sample / serial:.2f} (serial {serial * 1e6:.2f} µs)   goal <= 5: "
          f"{'ok' if per_sample <= 5 * serial else 'SLOWER'}")
    return serial


def dh_point(table: np.ndarray, q: np.ndarray, dl: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """The tool point (N, 3) of a standard-DH chain with perturbed rows: table (6, 4) of a, α, d, θ; dl (N, 24) the
    errors of a, α, d, θ row by row; dq (N, 6). The point is carried from the tool back to the base,
    p ← Rz(θ + q) Tz(d) Tx(a) Rx(α) p, one cos/sin pair per angle, on (N,) arrays."""
    n = len(dl)
    x, y, z = np.zeros(n), np.zeros(n), np.zeros(n)
    for i in range(len(table) - 1, -1, -1):
        a, alpha = table[i, 0] + dl[:, 4 * i], table[i, 1] + dl[:, 4 * i + 1]
        d, theta = table[i, 2] + dl[:, 4 * i + 2], table[i, 3] + q[i] + dl[:, 4 * i + 3] + dq[:, i]
        ca, sa = np.cos(alpha), np.sin(alpha)
        y, z = ca * y - sa * z, sa * y + ca * z + d
        x = x + a
        ct, st = np.cos(theta), np.sin(theta)
        x, y = ct * x - st * y, st * x + ct * y
    return np.stack([x, y, z], axis=1)


def dh_chain(puma: mechatron.Mechanism, errors: list[ErrorSource], q: np.ndarray, samples: int, repeats: int,
             serial: float) -> None:
    """The serial evaluator against the NumPy DH chain per sample on the same draws, and the whole Monte Carlo
    against :func:`lean_monte_carlo` (``serial``: the study's time per sample measured alone, printed beside)."""
    table = dh_table(puma, errors)
    names = [s.name for s in errors if s.kind == "parameter"]
    chunk = 32768
    draws = draw_errors(errors, chunk, np.random.default_rng(2), 3.0)
    dl, dq = draws[:, : len(names)], draws[:, len(names):]
    chain = PerturbedChain(puma, "tool", names)
    assert np.allclose(chain.positions(q, dl, dq), dh_point(table, q, dl, dq), atol=1e-14, rtol=0)
    t_chain = best_time(lambda: chain.positions(q, dl, dq), 3 * repeats) / chunk
    t_dh = best_time(lambda: dh_point(table, q, dl, dq), 3 * repeats) / chunk
    print(f"{'serial evaluator, per sample (PUMA, 30 errors)':<44}{t_chain * 1e6:>7.2f} µs   ratio "
          f"{t_chain / t_dh:.2f} vs a NumPy DH chain ({t_dh * 1e6:.2f} µs; agree to 1e-14 m)   goal <= 1.5: "
          f"{'ok' if t_chain <= 1.5 * t_dh else 'SLOWER'}")
    study = run_study(puma, errors, q, methods=["mc"], samples=samples)
    lean = lean_monte_carlo(errors, table, q, samples, 3.0)
    histogram = samples > EXACT_SAMPLES  # the study's quantiles from its histogram: within its bound, not equal
    agree = max(abs(float(study.poses[column].iloc[0]) - value) / max(abs(value), 1e-300)
                for column, value in lean.items()
                if column in study.poses and not (histogram and column[:2] in ("dr", "p5", "p9")))
    shares = np.abs(study.contributions.set_index("source").loc[[e.name for e in errors], "mc_share"].to_numpy()
                    - lean["shares"]).max()
    assert agree < 1e-9 and shares < 1e-6, (agree, shares)
    times = interleaved({"study": lambda: run_study(puma, errors, q, methods=["mc"], samples=samples),
                         "lean": lambda: lean_monte_carlo(errors, table, q, samples, 3.0)}, samples, repeats)
    print(f"{'  whole Monte Carlo, per sample':<44}{times['study'] * 1e6:>7.2f} µs   ratio "
          f"{times['study'] / times['lean']:.2f} vs the same draws, DH chain and statistics in NumPy "
          f"({times['lean'] * 1e6:.2f} µs, in turns; same numbers to {agree:.0e}, shares to {shares:.0e} %; "
          f"the study alone before: {serial * 1e6:.2f} µs)")


def dh_table(puma: mechatron.Mechanism, errors: list[ErrorSource]) -> np.ndarray:
    """The PUMA's standard-DH table (6, 4) of a, α, d, θ (m, rad), in the order of the parameter errors."""
    values = puma.parameter_values()
    names = [s.name for s in errors if s.kind == "parameter"]
    assert names == [f"{c}{i}" for i in range(1, 7) for c in ("a", "alpha", "d", "theta")]
    return np.array([[values[f"{c}{i}"] for c in ("a", "alpha", "d", "theta")] for i in range(1, 7)])


def lean_monte_carlo(errors: list[ErrorSource], table: np.ndarray, q: np.ndarray, samples: int, k: float,
                     seed: int = 0) -> dict[str, object]:
    """What ``run_study(methods=["mc"])`` computes at one pose, in NumPy: ``samples`` draws of the errors in the
    study's chunks (:data:`~mechatron.accuracy.study.CHUNK`, one generator seeded with ``seed``: the study's
    samples), the tool point by :func:`dh_point`, Δr from the nominal point with the samples that are not finite
    left out, and the study's statistics: per axis |mean| + k·std (m), the mean, spread (ddof 1), largest value and
    quantiles of |Δr| at the coverage erf(k/√2), 50, 95 and 99 % (``numpy.quantile`` of all |Δr|, kept), the
    co-moments of [errors, Δr, |Δr|] (centred per chunk, merged by Chan's update; their products in blocks of 128
    rows, single-threaded as the study's) and each error's share (%) of the variance of Δr by least squares on
    them, and the first million Δr kept for the charts. Returns the study's column names with their values, and
    ``shares``."""
    rng = np.random.default_rng(seed)
    n_e = len(errors)
    nominal = dh_point(table, q, np.zeros((1, 4 * len(table))), np.zeros((1, len(table))))[0]
    count, mean, comoment = 0, np.zeros(n_e + 4), np.zeros((n_e + 4, n_e + 4))
    r_all, kept = np.empty(samples), np.empty((min(samples, 10**6), 3))
    for start in range(0, samples, CHUNK):
        e = draw_errors(errors, min(CHUNK, samples - start), rng, k)
        delta = dh_point(table, q, e[:, :4 * len(table)], e[:, 4 * len(table):]) - nominal
        good = np.isfinite(delta).all(axis=1)
        e, delta = (e, delta) if good.all() else (e[good], delta[good])
        r = np.sqrt((delta**2).sum(axis=1))
        r_all[count:count + len(r)] = r
        take = max(0, min(len(delta), len(kept) - count))
        kept[count:count + take] = delta[:take]
        x = np.concatenate([e, delta, r[:, None]], axis=1)
        chunk_mean = x.mean(axis=0)
        centred = x - chunk_mean
        pad = -len(centred) % 128
        blocks = np.concatenate([centred, np.zeros((pad, n_e + 4))]).reshape(-1, 128, n_e + 4)
        step, total = chunk_mean - mean, count + len(x)
        comoment += np.matmul(blocks.transpose(0, 2, 1), blocks).sum(axis=0) + np.outer(step, step) * (
            count * len(x) / total)
        mean, count = mean + step * (len(x) / total), total
    std = np.sqrt(np.diag(comoment) / (count - 1))
    dx, dy, dz = np.abs(mean[n_e:n_e + 3]) + k * std[n_e:n_e + 3]
    coverage = math.erf(k / math.sqrt(2))
    dr, p50, p95, p99 = np.quantile(r_all[:count], [coverage, 0.5, 0.95, 0.99])
    ee, ed = comoment[:n_e, :n_e], comoment[:n_e, n_e:n_e + 3]
    scale = np.sqrt(np.diag(ee))
    beta = np.linalg.lstsq(ee / np.outer(scale, scale), ed / scale[:, None], rcond=None)[0] / scale[:, None]
    spread = np.sqrt(np.diag(ee) / count)
    shares = 100 * ((beta * spread[:, None]) ** 2).sum(axis=1) / (np.trace(comoment[n_e:n_e + 3, n_e:n_e + 3])
                                                                   / count)
    return {"dx_mc": dx, "dy_mc": dy, "dz_mc": dz, "dr_mc": dr, "mean_dr_mc": mean[-1], "std_dr_mc": std[-1],
            "p50_dr_mc": p50, "p95_dr_mc": p95, "p99_dr_mc": p99, "max_dr_mc": r_all[:count].max(),
            "failed_mc": samples - count, "shares": shares, "kept": kept}


def peak_child(samples: int) -> None:
    """In the subprocess: the PUMA study with ``samples`` samples."""
    puma = mechatron.load("puma560")
    result = run_study(puma, sources(puma), np.array([0.3, -0.5, 0.7, 0.2, -0.4, 0.9]), methods=["mc"],
                       samples=samples)
    print(result.poses["dr_mc"].iloc[0], result.notes)


def peak_memory(samples: int) -> None:
    """The peak resident memory (ru_maxrss of the child) of a ``samples``-sample study in a subprocess."""
    start = time.perf_counter()
    subprocess.run([sys.executable, __file__, "--peak-child", str(samples)], check=True, capture_output=True)
    elapsed = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024 / 1e9  # KiB on Linux
    print(f"{'peak memory, ' + format(samples, ',') + '-sample study':<44}{peak:>7.2f} GB   goal < 1 GB: "
          f"{'ok' if peak < 1 else 'LARGER'} ({elapsed:.0f} s, the interpreter and libraries included)")


if __name__ == "__main__":
    main()

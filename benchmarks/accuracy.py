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
   Monte Carlo (draws, evaluation, streamed statistics) against drawing the same errors and running that chain.
5. The closed-loop Monte Carlo (bucket) against the serial one (PUMA) per sample (goal: at most 5x), and its
   evaluator's planar path (placements as complex numbers) against its spatial path (3x3 rotations) on the same draws.
6. The peak resident memory of a 1e8-sample PUMA study, run in a subprocess (goal: under 1 GB; the statistics are
   streamed in chunks, see mechatron/accuracy/streaming.py).

    python benchmarks/accuracy.py [--samples N] [--poses N] [--loop-samples N] [--peak-samples N]
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin
from timing import best_time

import mechatron
from mechatron.accuracy.nonlinear import PerturbedChain, PerturbedLoop, PerturbedLoops
from mechatron.accuracy.sources import ErrorSource
from mechatron.accuracy.study import draw_errors, run_study
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
    """The serial evaluator and the whole Monte Carlo against the NumPy DH chain, per sample, on the same draws."""
    values = puma.parameter_values()
    names = [s.name for s in errors if s.kind == "parameter"]
    assert names == [f"{c}{i}" for i in range(1, 7) for c in ("a", "alpha", "d", "theta")]
    table = np.array([[values[f"{c}{i}"] for c in ("a", "alpha", "d", "theta")] for i in range(1, 7)])
    chunk = 32768
    draws = draw_errors(errors, chunk, np.random.default_rng(2), 3.0)
    dl, dq = draws[:, : len(names)], draws[:, len(names):]
    chain = PerturbedChain(puma, "tool", names)
    assert np.allclose(chain.positions(q, dl, dq), dh_point(table, q, dl, dq), atol=1e-14, rtol=0)
    t_chain = best_time(lambda: chain.positions(q, dl, dq), 3 * repeats) / chunk
    t_dh = best_time(lambda: dh_point(table, q, dl, dq), 3 * repeats) / chunk
    t_draw = best_time(lambda: draw_errors(errors, chunk, np.random.default_rng(2), 3.0), 3 * repeats) / chunk
    print(f"{'serial evaluator, per sample (PUMA, 30 errors)':<44}{t_chain * 1e6:>7.2f} µs   ratio "
          f"{t_chain / t_dh:.2f} vs a NumPy DH chain ({t_dh * 1e6:.2f} µs; agree to 1e-14 m)   goal <= 1.5: "
          f"{'ok' if t_chain <= 1.5 * t_dh else 'SLOWER'}")
    print(f"{'  whole Monte Carlo, per sample':<44}{serial * 1e6:>7.2f} µs   ratio {serial / (t_dh + t_draw):.2f} "
          f"vs drawing the errors and the DH chain ({(t_dh + t_draw) * 1e6:.2f} µs)")


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

"""Tolerance studies: the PUMA 560 tool point with errors on all 24 DH parameters and the 6 joint coordinates, and
the six-bar bucket linkage (two closed loops) with errors on its 4 parameters and its cylinder.

1. Monte Carlo of the full nonlinear model of the PUMA, 1,000,000 samples at one pose (goal: under 3 s), against a
   plain per-sample Pinocchio loop (a model copy takes the perturbed placements, then forward kinematics), timed on a
   slice and scaled; both agree on the slice.
2. The linear methods (worst case and RSS) over 10,000 poses (goal: under 1 s), against finite differences of
   forward kinematics with the rebuilt models (the way a script without the regressors does it), timed on a slice.
3. Monte Carlo of the closed loops, 100,000 samples at one pose (goal: under 3 s), vectorized over the samples
   (the loops closed by Newton's method for all samples at once), against the per-sample Pinocchio loop solver,
   timed on a slice and scaled; both agree on the slice.

    python benchmarks/accuracy.py [--samples N] [--poses N] [--loop-samples N]
"""

from __future__ import annotations

import argparse
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
    args = parser.parse_args()
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
    closed_loops(args.loop_samples, args.repeats)


def closed_loops(samples: int, repeats: int) -> None:
    """Monte Carlo of the bucket linkage: vectorized against one sample at a time."""
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


if __name__ == "__main__":
    main()

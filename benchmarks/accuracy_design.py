"""Accuracy as a design tool (issue 36) against what a competent user would write, side by side.

- **calibration** — ``mechatron.calibrate`` (Levenberg–Marquardt on the exact pose Jacobian) of the shipped PUMA
  example (50 measured poses with orientation, 7 unknowns) against ``scipy.optimize.least_squares(method="lm")`` on
  the same weighted residuals with its finite-difference Jacobian (MINPACK's ``lmdif``). Printed: the CPU time of
  each (median of interleaved repeats), their ratio, the residual evaluations, and the largest difference of the
  identified values in units of their standard errors.
- **allocation** — the least-cost choice of processes by ``mechatron.allocate_tolerances`` (exact branch and bound;
  the verifying Monte Carlo cut to 2 samples per pose) against a brute force over every combination, vectorized in
  NumPy in chunks (the RSS |Δr| at every pose of each combination, the cheapest that meets the limit), for 6, 8 and
  10 process rows of 4 options each at the 6 poses of ``poses_puma560.csv``. Printed: the time of each, the ratio,
  the combinations, and whether both found the same cost.

    python benchmarks/accuracy_design.py [--repeats R]
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import numpy as np
from timing import cpu_medians_and_results

import mechatron
from mechatron.accuracy.calibration import CalibrationProblem, calibrate
from mechatron.accuracy.costs import CostedSource, ProcessTable
from mechatron.accuracy.measurements import read_measurements
from mechatron.accuracy.sensitivity import sensitivities
from mechatron.accuracy.sources import ErrorSource, read_poses
from mechatron.accuracy.study import configurations

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "examples" / "data"
UNKNOWNS = ["a2", "d3", "d4", "alpha2", "alpha3", "q2", "q3"]
LIMIT = 0.2e-3  # m
#: Process tables: (tolerance (m or rad), cost) from loosest to tightest, the cost rising as the tolerance falls.
LENGTHS = ((0.1e-3, 4.0), (0.05e-3, 7.0), (0.02e-3, 15.0), (0.005e-3, 45.0))
ANGLES = ((2.9e-4, 25.0), (1.45e-4, 40.0), (7.3e-5, 70.0), (3.6e-5, 130.0))
ROWS = ["d1", "a2", "a3", "d3", "d4", "q1", "q2", "q3", "alpha2", "alpha3"]


def scipy_calibration(puma: mechatron.Mechanism, measurements) -> tuple[np.ndarray, int]:
    """The identified changes x by MINPACK's Levenberg–Marquardt with finite differences, and its evaluations."""
    from scipy.optimize import least_squares

    problem = CalibrationProblem(puma, measurements, tuple(UNKNOWNS[:5]), tuple(UNKNOWNS[5:]), puma.tool_frame)
    fit = least_squares(lambda x: problem.residuals(x)[0], np.zeros(len(UNKNOWNS)), method="lm", xtol=1e-12)
    return fit.x, int(fit.nfev)


def bench_calibration(repeats: int) -> None:
    puma = mechatron.load("puma560")
    measurements = read_measurements(DATA / "measurements_puma560.csv", puma)
    times, results = cpu_medians_and_results({
        "mechatron": lambda: calibrate(puma, measurements, UNKNOWNS),
        "scipy": lambda: scipy_calibration(puma, measurements)}, repeats)
    ours, (x, evaluations) = results["mechatron"], results["scipy"]
    spread = max(abs(u.change - dx) / u.std_error for u, dx in zip(ours.unknowns, x))
    print(f"calibration, PUMA, {len(measurements)} poses with orientation, {len(UNKNOWNS)} unknowns:")
    print(f"  mechatron.calibrate (exact Jacobian): {times['mechatron'] * 1e3:8.1f} ms, {ours.iterations} iterations")
    print(f"  scipy least_squares lm (finite diff.): {times['scipy'] * 1e3:8.1f} ms, {evaluations} residual "
          f"evaluations")
    print(f"  ratio scipy / mechatron: {times['scipy'] / times['mechatron']:.2f}x; largest difference of the "
          f"identified values: {spread:.2g} standard errors")


def process_rows(names: list[str]) -> list[CostedSource]:
    out = []
    for name in names:
        angle = name.startswith(("q", "alpha"))
        table = ANGLES if angle else LENGTHS
        model = ProcessTable("encoder" if angle else "offset", tuple(t for t, _ in table), tuple(c for _, c in table),
                             tuple(f"option {i}" for i in range(len(table))), ("",) * len(table),
                             "angle" if angle else "length")
        source = ErrorSource(name, "coordinate" if name.startswith("q") else "parameter", "rad" if angle else "m",
                             table[0][0])
        out.append(CostedSource(source, model, "", False))
    return out


def brute_force(puma: mechatron.Mechanism, names: list[str], poses: np.ndarray) -> float:
    """The cheapest combination of options whose RSS |Δr| (normal errors: √Σ(J t)² per axis) meets LIMIT at every
    pose, over every combination (chunks of 65,536)."""
    Q = configurations(puma, poses)
    s = sensitivities(puma, Q, puma.tool_frame, [n for n in names if not n.startswith("q")],
                      [n for n in names if n.startswith("q")])
    index = {name: i for i, name in enumerate(s.sources)}
    J2 = s.matrix[:, :, [index[n] for n in names]] ** 2  # (N, 3, n)
    tables = [ANGLES if n.startswith(("q", "alpha")) else LENGTHS for n in names]
    t2 = [np.array([t for t, _ in table]) ** 2 for table in tables]
    costs = [np.array([c for _, c in table]) for table in tables]
    best = np.inf
    combos = itertools.product(range(4), repeat=len(names))
    while chunk := list(itertools.islice(combos, 65536)):
        choice = np.array(chunk)
        tt = np.stack([t2[j][choice[:, j]] for j in range(len(names))], axis=1)  # (C, n)
        dr2 = np.einsum("pan,cn->cp", J2, tt)  # Σ_axes Σ_i J² t²: |Δr|² per pose
        ok = (dr2 <= (LIMIT * (1 + 1e-9)) ** 2).all(axis=1)
        if ok.any():
            cost = sum(costs[j][choice[ok, j]] for j in range(len(names)))
            best = min(best, float(cost.min()))
    return best


def bench_allocation(repeats: int) -> None:
    from mechatron.accuracy.allocation import allocate_tolerances

    puma = mechatron.load("puma560")
    poses, labels = read_poses(DATA / "poses_puma560.csv", puma)
    print(f"allocation, PUMA, RSS |Δr| <= {LIMIT * 1e3:g} mm at {len(poses)} poses, 4 processes per row:")
    for n in (6, 8, 10):
        names = ROWS[:n]
        rows = process_rows(names)
        times, results = cpu_medians_and_results({
            "branch and bound": lambda: allocate_tolerances(puma, rows, poses, labels, LIMIT, samples=2),
            "brute force": lambda: brute_force(puma, names, poses)}, repeats if n < 10 else 1)
        ours, brute = results["branch and bound"].total_cost, results["brute force"]
        ratio = times["brute force"] / times["branch and bound"]
        print(f"  {n:2d} rows, {4 ** n:>9,} combinations: branch and bound {times['branch and bound']:7.3f} s, "
              f"brute force {times['brute force']:7.3f} s, ratio {ratio:6.1f}x, "
              f"costs {ours:g} and {brute:g} ({'equal' if abs(ours - brute) < 1e-9 else 'DIFFERENT'})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    bench_calibration(args.repeats)
    bench_allocation(args.repeats)


if __name__ == "__main__":
    main()

"""Full position, velocity and acceleration sweep of the six-link bucket mechanism over 10,000 stroke samples.

mechatron's generic closed-loop analysis (a Pinocchio tree with closures: Newton assembly by continuation, velocity
and acceleration analysis, every point and transmission angle) against the paper's own closed-form vector-loop
analysis ([Bucket, 8, 12, 18]) vectorized with NumPy over all samples, which knows this one mechanism only. Goal: the
mechatron sweep under 1 s.

    python benchmarks/linkages.py [--samples N] [--repeats R]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from timing import best_time_and_result as best_time

import mechatron
from mechatron.kinematics.sweep import sweep
from mechatron.machines.bucket import synthesize

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the validation folder of the clone
from validation.bucket import analytic_analysis  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    linkage = synthesize()
    mech = mechatron.load("six_bar_bucket")
    strokes = np.linspace(linkage.L1n, linkage.L1n + linkage.stroke, args.samples)
    t_ours, result = best_time(lambda: sweep(mech, {"L1": strokes}, rates={"L1": 0.1}), args.repeats)
    t_closed, reference = best_time(lambda: analytic_analysis(linkage, strokes, 0.1), args.repeats)
    table = result.table
    errors = {
        "bucket angle (rad)": np.abs(table["q_phi4"] - reference["q"][:, 4]).max(),
        "bucket angular velocity (rad/s)": np.abs(table["v_phi4"] - reference["qd"][:, 4]).max(),
        "bucket angular acceleration (rad/s²)": np.abs(table["a_phi4"] - reference["qdd"][:, 4]).max(),
        "tooth velocity (m/s)": np.abs(table[["K_vx", "K_vy"]].to_numpy() - reference["K_velocity"]).max(),
    }
    print(f"six-link bucket mechanism, {args.samples} stroke samples, positions + velocities + accelerations "
          f"(best of {args.repeats})")
    print(f"  mechatron sweep (generic closed loops):   {t_ours:8.3f} s   goal < 1 s: "
          f"{'ok' if t_ours < 1.0 else 'SLOWER'}  ({len(table)} samples, {len(table.columns)} columns)")
    print(f"  closed-form baseline (NumPy, this linkage): {t_closed:8.4f} s   ratio {t_ours / t_closed:.0f}x")
    for name, value in errors.items():
        print(f"  largest difference, {name}: {value:.2e}")


if __name__ == "__main__":
    main()

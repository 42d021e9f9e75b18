"""Closed-loop sweeps against vectorized closed forms: the crank-slider and the six-link bucket mechanism.

mechatron's generic closed-loop sweep (a Pinocchio tree with closures: positions by Newton's method over all samples
from guesses interpolated between a few samples solved by continuation, velocities and accelerations of every joint
and point; from 2,048 samples on by kernels compiled from CasADi expressions of the loop equations and mapped over the
samples, mechatron/kinematics/compiled.py — their one-time compilation, ~0.5 s per mechanism, is done before the
timing and printed) against the closed form per mechanism vectorized with NumPy over all samples, which knows that
one mechanism only. The baseline is what a competent user would write for the same outputs: the crank-slider's
x = l1 cos φ + √(l2² − (l1 sin φ)²) with its first and second time derivatives and the rod's angle, the points'
positions, velocities and accelerations and their magnitudes; the bucket's closed form is the paper's own analysis
(validation/bucket.py: circle intersections and the stacked 5 × 5 velocity and acceleration solves). Printed per
mechanism and number of samples: µs per sample of both (best of the repeats), their ratio (goal ≤ 10×), the peak of
traced memory per sample (tracemalloc peak / N, with the table the sweep returns, whose own size is printed beside)
and the largest differences between the two.

    python benchmarks/linkages.py [--samples 10000 1000000] [--repeats R]

The default sizes are 10,000 and 1,000,000 samples (the issue's "1e6 samples on this machine").
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from timing import best_time_and_result as best_time

import mechatron
from mechatron.kinematics.sweep import default_inputs as sweep_inputs
from mechatron.kinematics.sweep import sweep
from mechatron.machines.bucket import synthesize

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the validation folder of the clone
from validation.bucket import analytic_analysis  # noqa: E402

L1, L2 = 0.1, 0.4  # crank AB and rod BC of robots/crank_slider.toml (m)


def crank_slider(phi: np.ndarray, omega: float = 1.0) -> dict[str, np.ndarray]:
    """The central crank-slider in closed form at crank angles φ (rad) turning at ω (rad/s), ε = 0: with
    g = l1 sin φ and h = √(l2² − g²), the slider x = l1 cos φ + h, ẋ = −l1 ω sin φ + ḣ, ẍ = −l1 ω² cos φ + ḧ
    (ḣ = −g ġ / h, ḧ = −(ġ² + g g̈) / h − (g ġ)² / h³), the rod's angle ψ = atan2(−g, h) with ψ̇ = −ġ / h,
    ψ̈ = −(g̈ h − ġ ḣ) / h², and the crank pin B, the slider pin C and the rod's middle S2 with their velocities,
    accelerations and magnitudes (m, m/s, m/s², rad, rad/s, rad/s²)."""
    c, s = np.cos(phi), np.sin(phi)
    g, gd, gdd = L1 * s, L1 * omega * c, -L1 * omega**2 * s
    h = np.sqrt(L2**2 - g**2)
    hd = -g * gd / h
    hdd = -(gd**2 + g * gdd) / h - (g * gd) ** 2 / h**3
    x, xd, xdd = L1 * c + h, -L1 * omega * s + hd, -L1 * omega**2 * c + hdd
    psi, psid = np.arctan2(-g, h), -gd / h
    psidd = -(gdd * h - gd * hd) / h**2
    out = {"q1": phi, "phi2": psi - phi, "xC": x, "v_phi2": psid - omega, "v_xC": xd, "a_phi2": psidd,
           "a_xC": xdd}
    B = (L1 * c, g, -L1 * omega * s, gd, -L1 * omega**2 * c, gdd)
    C = (x, 0.0 * x, xd, 0.0 * x, xdd, 0.0 * x)
    for name, point in (("B", B), ("C", C), ("S2", tuple((b + c_) / 2 for b, c_ in zip(B, C)))):
        px, py, vx, vy, ax, ay = point
        out.update({f"{name}_x": px, f"{name}_y": py, f"{name}_vx": vx, f"{name}_vy": vy, f"{name}_v": np.hypot(vx, vy),
                    f"{name}_ax": ax, f"{name}_ay": ay, f"{name}_a": np.hypot(ax, ay)})
    return out


def peak_bytes(function) -> int:
    """The peak of memory traced while ``function()`` runs (bytes)."""
    tracemalloc.start()
    try:
        function()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def compare(title: str, ours, closed_form, differences, n: int, repeats: int) -> None:
    t_ours, result = best_time(ours, repeats)
    t_closed, reference = best_time(closed_form, repeats)
    table_bytes = result.table.memory_usage(index=True).sum()  # its q, v and a are the table's columns
    peak_ours, peak_closed = peak_bytes(ours), peak_bytes(closed_form)
    ratio = t_ours / t_closed
    print(f"{title}, {n} samples, positions + velocities + accelerations (best of {repeats})")
    print(f"  mechatron sweep:     {t_ours / n * 1e6:8.3f} µs/sample  peak {peak_ours / n:7.0f} B/sample "
          f"(its table: {table_bytes / n:.0f} B/sample, {len(result.table.columns)} columns)")
    print(f"  closed form (NumPy): {t_closed / n * 1e6:8.3f} µs/sample  peak {peak_closed / n:7.0f} B/sample")
    print(f"  ratio {ratio:.1f}x (goal <= 10x: {'ok' if ratio <= 10 else 'SLOWER'}); working storage beyond the "
          f"table {max(peak_ours - table_bytes, 0) / n:.0f} B/sample (goal <= 1 KB)")
    for name, value in differences(result.table, reference).items():
        print(f"  largest difference, {name}: {value:.2e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, nargs="+", default=[10_000, 1_000_000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    crank = mechatron.load("crank_slider")
    linkage = synthesize()
    bucket = mechatron.load("six_bar_bucket")
    for mech in (crank, bucket):  # build (and, the first time, compile) the kernels
        start = time.perf_counter()
        sweep(mech, sweep_inputs(mech, 4096))
        print(f"{mech.name}: kernels built in {time.perf_counter() - start:.2f} s (compiled once, then cached)")
    for n in args.samples:
        phi = np.linspace(0.0, 2 * np.pi, n)
        compare("crank-slider", lambda: sweep(crank, {"q1": phi}, rates={"q1": 1.0}), lambda: crank_slider(phi),
                lambda table, ref: {f"slider {key} (m, m/s, m/s²)": np.abs(table[f"{key}_xC"] - ref[name]).max()
                                    for key, name in (("q", "xC"), ("v", "v_xC"), ("a", "a_xC"))}, n, args.repeats)
        strokes = np.linspace(linkage.L1n, linkage.L1n + linkage.stroke, n)
        compare("six-link bucket", lambda: sweep(bucket, {"L1": strokes}, rates={"L1": 0.1}),
                lambda: analytic_analysis(linkage, strokes, 0.1),
                lambda table, ref: {
                    "bucket angle (rad)": np.abs(table["q_phi4"] - ref["q"][:, 4]).max(),
                    "bucket angular velocity (rad/s)": np.abs(table["v_phi4"] - ref["qd"][:, 4]).max(),
                    "bucket angular acceleration (rad/s²)": np.abs(table["a_phi4"] - ref["qdd"][:, 4]).max(),
                    "tooth velocity (m/s)": np.abs(table[["K_vx", "K_vy"]].to_numpy() - ref["K_velocity"]).max()},
                n, args.repeats)


if __name__ == "__main__":
    main()

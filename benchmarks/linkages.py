"""Closed-loop sweeps against vectorized closed forms: the crank-slider and the six-link bucket mechanism.

mechatron's generic closed-loop sweep (a Pinocchio tree with closures: positions by Newton's method over all samples
from guesses interpolated between a few samples solved by continuation, velocities and accelerations of every joint
and point; from 2,048 samples on by kernels compiled from CasADi expressions of the loop equations and run over the
samples, mechatron/kinematics/compiled.py — their one-time compilation, ~0.5 s per mechanism, is done before the
timing and printed) against the closed form per mechanism vectorized with NumPy over all samples, which knows that
one mechanism only.

Same outputs: the sweep is asked for its default table (every joint's coordinate, rate and acceleration, every
point's position, velocity and acceleration with their sizes, every measure) and the closed form computes that same
set of columns — 43 for the crank-slider, 77 for the bucket —, as NumPy arrays by column name (the sweep returns a
pandas DataFrame; building it is part of its time, not of the baseline's). Every column is compared and the largest
difference printed by kind. The crank-slider's closed form: x = l1 cos φ + √(l2² − (l1 sin φ)²) with its first and
second time derivatives and the rod's angle, the points A (at rest), B, C and S2; the bucket's is the paper's own
analysis (validation/bucket.py: circle intersections and the stacked 5 × 5 velocity and acceleration solves) with
the points of its links turning about their fixed pivots, the three transmission angles and the cylinder's lever
arm. Timing: the two candidates take turns within every repeat (timing.interleaved), best of the repeats. Printed per
mechanism and number of samples: µs per sample of both, their ratio (goal ≤ 3×), the peak of traced memory per sample
(tracemalloc peak / N, with the table the sweep returns, whose own size is printed beside).

    python benchmarks/linkages.py [--samples 10000 1000000] [--repeats R]

The default sizes are 10,000 and 1,000,000 samples.
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from timing import interleaved

import mechatron
from mechatron.kinematics.sweeps import default_inputs as sweep_inputs
from mechatron.kinematics.sweeps import sweep
from mechatron.machines.bucket import BucketLinkage, synthesize

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the validation folder of the clone
from validation.bucket import analytic_analysis  # noqa: E402

L1, L2 = 0.1, 0.4  # crank AB and rod BC of robots/crank_slider.toml (m)
GOAL = 3.0  # the sweep's time at most this many times the closed form's


def point_columns(name: str, position: tuple, velocity: tuple, acceleration: tuple) -> dict[str, np.ndarray]:
    """A point's columns of the sweep's table from its (x, y) position (m), velocity (m/s) and acceleration (m/s²):
    ``{name}_x, _y, _vx, _vy, _v, _ax, _ay, _a`` (the sizes by ``hypot``)."""
    (px, py), (vx, vy), (ax, ay) = position, velocity, acceleration
    return {f"{name}_x": px, f"{name}_y": py, f"{name}_vx": vx, f"{name}_vy": vy, f"{name}_v": np.hypot(vx, vy),
            f"{name}_ax": ax, f"{name}_ay": ay, f"{name}_a": np.hypot(ax, ay)}


def joint_columns(name: str, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> dict[str, np.ndarray]:
    """A joint's columns ``q_{name}, v_{name}, a_{name}`` (m or rad and their rates)."""
    return {f"q_{name}": q, f"v_{name}": v, f"a_{name}": a}


def crank_slider(phi: np.ndarray, omega: float = 1.0) -> dict[str, np.ndarray]:
    """The sweep's 43 columns of the central crank-slider in closed form at crank angles φ (rad) turning at ω
    (rad/s), ε = 0: with g = l1 sin φ and h = √(l2² − g²), the slider x = l1 cos φ + h, ẋ = −l1 ω sin φ + ḣ,
    ẍ = −l1 ω² cos φ + ḧ (ḣ = −g ġ / h, ḧ = −(ġ² + g g̈) / h − (g ġ)² / h³), the rod's angle ψ = atan2(−g, h)
    with ψ̇ = −ġ / h, ψ̈ = −(g̈ h − ġ ḣ) / h² (its joint φ2 = ψ − φ), and the pivot A (at rest), the crank pin B,
    the slider pin C and the rod's middle S2 with their velocities, accelerations and sizes (m, m/s, m/s², rad,
    rad/s, rad/s²)."""
    n = len(phi)
    c, s = np.cos(phi), np.sin(phi)
    g, gd, gdd = L1 * s, L1 * omega * c, -L1 * omega**2 * s
    h = np.sqrt(L2**2 - g**2)
    hd = -g * gd / h
    hdd = -(gd**2 + g * gdd) / h - (g * gd) ** 2 / h**3
    x, xd, xdd = L1 * c + h, -L1 * omega * s + hd, -L1 * omega**2 * c + hdd
    psi, psid = np.arctan2(-g, h), -gd / h
    psidd = -(gdd * h - gd * hd) / h**2
    zero = np.zeros(n)
    out = {"sample": np.arange(n), "q1": phi, **joint_columns("q1", phi, np.full(n, omega), zero),
           **joint_columns("phi2", psi - phi, psid - omega, psidd), **joint_columns("xC", x, xd, xdd)}
    B = ((L1 * c, g), (-L1 * omega * s, gd), (-L1 * omega**2 * c, gdd))
    C = ((x, zero), (xd, zero), (xdd, zero))
    S2 = tuple(tuple(0.5 * (b + c_) for b, c_ in zip(pb, pc)) for pb, pc in zip(B, C))
    out.update(point_columns("A", (zero, zero), (zero, zero), (zero, zero)))
    for name, point in (("B", B), ("C", C), ("S2", S2)):
        out.update(point_columns(name, *point))
    return out


def turning(pivot: tuple[float, float], length: float, angle: np.ndarray, rate: np.ndarray,
            acceleration: np.ndarray) -> tuple:
    """Position, velocity and acceleration ((x, y) each) of a point at ``length`` (m) from a fixed ``pivot`` along
    ``angle`` (rad) turning at ``rate`` (rad/s) and ``acceleration`` (rad/s²): r = ℓ (cos θ, sin θ),
    v = θ̇ e_z × r, a = θ̈ e_z × r − θ̇² r."""
    rx, ry = length * np.cos(angle), length * np.sin(angle)
    return ((pivot[0] + rx, pivot[1] + ry), (-rate * ry, rate * rx),
            (-acceleration * ry - rate**2 * rx, acceleration * rx - rate**2 * ry))


def transmission(a: tuple, b: tuple, c: tuple, d: tuple) -> np.ndarray:
    """The angle (rad, in [0, π/2]) between the lines ab and cd of points given as (x, y) arrays (m)."""
    ux, uy, wx, wy = b[0] - a[0], b[1] - a[1], d[0] - c[0], d[1] - c[1]
    return np.arccos(np.minimum(1.0, np.abs(ux * wx + uy * wy) / (np.hypot(ux, uy) * np.hypot(wx, wy))))


def bucket(lk: BucketLinkage, strokes: np.ndarray, rate: float) -> dict[str, np.ndarray]:
    """The sweep's 77 columns of the six-link bucket at cylinder lengths L1 (m) extending at ``rate`` (m/s): the
    paper's q = (L1, φ1, φ2, φ3, φ4), q̇ and q̈ (:func:`validation.bucket.analytic_analysis`) as the model's
    joints (phi2 = φ2, link_angle = φ3 − φ2 + π, phi4 = φ4, L1_angle = π − φ1, L1), the pivots D, F, A at rest,
    B and C on the rocker about D, E and K on the bucket about F, the transmission angles at B, C, E and the
    cylinder's lever arm about D (m, rad and their rates)."""
    ref = analytic_analysis(lk, strokes, rate)
    (L, phi1, phi2, phi3, phi4), (Ld, w1, w2, w3, w4), (Ldd, e1, e2, e3, e4) = ref["q"].T, ref["qd"].T, ref["qdd"].T
    n = len(strokes)
    zero = np.zeros(n)
    out = {"sample": np.arange(n), "L1": strokes, **joint_columns("phi2", phi2, w2, e2),
           **joint_columns("link_angle", phi3 - phi2 + np.pi, w3 - w2, e3 - e2), **joint_columns("phi4", phi4, w4, e4),
           **joint_columns("L1_angle", np.pi - phi1, -w1, -e1), **joint_columns("L1", L, Ld, Ldd)}
    D, F, A = (0.0, 0.0), (-lk.c, 0.0), (lk.a, lk.b)
    points = {"D": D, "F": F, "A": A}
    for name, pivot in points.items():
        out.update(point_columns(name, (zero + pivot[0], zero + pivot[1]), (zero, zero), (zero, zero)))
    moving = {"B": turning(D, lk.L2, phi2, w2, e2), "C": turning(D, lk.L3, phi2 + lk.alpha, w2, e2),
              "E": turning(F, lk.L5, phi4, w4, e4), "K": turning(F, lk.Lk, phi4 + lk.gamma, w4, e4)}
    for name, point in moving.items():
        out.update(point_columns(name, *point))
        points[name] = point[0]
    p = points
    out["mu_B"] = transmission(p["A"], p["B"], p["D"], p["B"])
    out["mu_C"] = transmission(p["D"], p["C"], p["C"], p["E"])
    out["mu_E"] = transmission(p["C"], p["E"], p["F"], p["E"])
    ax, ay, rx, ry = p["B"][0] - A[0], p["B"][1] - A[1], D[0] - A[0], D[1] - A[1]
    out["cylinder_arm_about_D"] = np.abs(ax * ry - ay * rx) / np.hypot(ax, ay)
    return out


def peak_bytes(function) -> int:
    """The peak of memory traced while ``function()`` runs (bytes)."""
    tracemalloc.start()
    try:
        function()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def differences(table, reference: dict[str, np.ndarray]) -> dict[str, tuple[float, str]]:
    """The largest difference between the sweep's table and the closed form's columns by kind of column (joints,
    positions, velocities, accelerations, measures): (value, column). Raises if they do not have the same columns."""
    if list(table.columns) != list(reference):
        raise AssertionError(f"different columns: {list(table.columns)} and {list(reference)}")
    kinds: dict[str, tuple[float, str]] = {}
    for name, values in reference.items():
        kind = name.split("_")[0] if name.split("_")[0] in ("q", "v", "a") else \
            {"x": "p", "y": "p", "vx": "v", "vy": "v", "v": "v", "ax": "a", "ay": "a", "a": "a"}.get(
                name.rsplit("_", 1)[-1], "measure")
        label = {"q": "positions (m, rad)", "p": "positions (m, rad)", "v": "velocities (m/s, rad/s)",
                 "a": "accelerations (m/s², rad/s²)", "measure": "inputs, samples and measures (m, rad)"}[kind]
        value = float(np.abs(table[name].to_numpy() - values).max())
        if value >= kinds.get(label, (-1.0, ""))[0]:
            kinds[label] = (value, name)
    return kinds


def compare(title: str, ours, closed_form, n: int, repeats: int) -> float:
    """Time the sweep ``ours()`` and the closed form ``closed_form()`` in turns, print the comparison and return the
    ratio of their times."""
    result, reference = ours(), closed_form()
    times = interleaved({"ours": ours, "closed": closed_form}, n, repeats)
    t_ours, t_closed = times["ours"], times["closed"]
    table_bytes = result.table.memory_usage(index=True).sum()
    peak_ours, peak_closed = peak_bytes(ours), peak_bytes(closed_form)
    ratio = t_ours / t_closed
    print(f"{title}, {n} samples, the sweep's {len(result.table.columns)} columns (best of {repeats}, in turns)")
    print(f"  mechatron sweep:     {t_ours * 1e6:8.3f} µs/sample  peak {peak_ours / n:7.0f} B/sample "
          f"(its table: {table_bytes / n:.0f} B/sample)")
    print(f"  closed form (NumPy): {t_closed * 1e6:8.3f} µs/sample  peak {peak_closed / n:7.0f} B/sample")
    print(f"  ratio {ratio:.2f}x (goal <= {GOAL:g}x: {'ok' if ratio <= GOAL else 'SLOWER'}); working storage beyond "
          f"the table {max(peak_ours - table_bytes, 0) / n:.0f} B/sample (goal <= 1 KB)")
    for label, (value, name) in differences(result.table, reference).items():
        print(f"  largest difference, {label}: {value:.2e} ({name})")
    return ratio


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, nargs="+", default=[10_000, 1_000_000])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    crank = mechatron.load("crank_slider")
    linkage = synthesize()
    six_bar = mechatron.load("six_bar_bucket")
    for mech in (crank, six_bar):  # build (and, the first time, compile) the kernels
        start = time.perf_counter()
        sweep(mech, sweep_inputs(mech, 4096))
        print(f"{mech.name}: kernels built in {time.perf_counter() - start:.2f} s (compiled once, then cached)")
    ratios = []
    for n in args.samples:
        phi = np.linspace(0.0, 2 * np.pi, n)
        ratios.append(compare("crank-slider", lambda: sweep(crank, {"q1": phi}, rates={"q1": 1.0}),
                              lambda: crank_slider(phi), n, args.repeats))
        strokes = np.linspace(linkage.L1n, linkage.L1n + linkage.stroke, n)
        ratios.append(compare("six-link bucket", lambda: sweep(six_bar, {"L1": strokes}, rates={"L1": 0.1}),
                              lambda: bucket(linkage, strokes, 0.1), n, args.repeats))
    print(f"largest ratio {max(ratios):.2f}x (goal <= {GOAL:g}x)")


if __name__ == "__main__":
    main()

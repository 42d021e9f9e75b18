"""Batched dynamics — RNEA, ABA, CRBA — of the PUMA 560 and the UR5 at N = 1, 64, 1,000 and 100,000 states.

Each mechatron call (``inverse_dynamics``, ``forward_dynamics``, ``mass_matrix``: argument checks included, threads
chosen by size and idle cores unless ``--threads``) is timed against:

- **plain loop** — what a competent Pinocchio user writes: a Python loop calling ``pin.rnea`` / ``pin.aba`` /
  ``pin.crba`` on one preallocated ``Data``, writing rows of a preallocated output (CRBA: the matrices as
  ``pin.crba`` returns them, already symmetric — its Python binding copies the upper triangle down). Goal: mechatron
  at most 1.0x at every N.
- **compiled floor** — Pinocchio's own C++ batch loop, ``rneaInParallel`` / ``abaInParallel`` with one thread on a
  ``ModelPool`` (no Python per state and no argument checks): what a Python API can approach at best. The wheel has
  no compiled CRBA batch, so CRBA has no floor.
- **Robotics Toolbox** (RNEA only) — ``DHRobot.rne`` called once with the whole (N, 6) arrays, its C loop over the
  samples (not a per-state ``rne`` loop), on its own DH model of the same robot: a timing reference, not the same
  numbers.

Times are per state, best of ``--repeats``; the candidates take turns within each repeat, each looping over its
call until ~20,000 states are done. The last block gives mechatron's peak memory at the largest N next to the
output's size, and the time of a closed-loop simulation step (``mechatron.dynamics.constrained.simulate`` of the
crank-slider).

    python benchmarks/dynamics.py [--sizes 1 64 1000 100000] [--repeats R] [--threads T]
"""

from __future__ import annotations

import argparse
import tracemalloc

import numpy as np
import pinocchio as pin
from timing import best_time, interleaved

import mechatron
from mechatron.dynamics import tree
from mechatron.dynamics.constrained import simulate
from mechatron.kinematics.loops import assemble, joint_velocity


def plain_rnea(model, data, Q, V, A, out):
    for i in range(len(Q)):
        out[i] = pin.rnea(model, data, Q[i], V[i], A[i])
    return out


def plain_aba(model, data, Q, V, T, out):
    for i in range(len(Q)):
        out[i] = pin.aba(model, data, Q[i], V[i], T[i])
    return out


def plain_crba(model, data, Q, out):
    for i in range(len(Q)):
        out[i] = pin.crba(model, data, Q[i])
    return out


def compiled(algorithm, pool, Q, V, X, out):
    algorithm(1, pool, Q.T, V.T, X.T, out.T)
    return out


def rows(name: str, mech, n: int, repeats: int, threads: int | None, toolbox) -> list[str]:
    """One line per algorithm: times per state (µs) and ratios."""
    rng = np.random.default_rng(n)
    Q = mech.random_configuration(rng, size=n)
    V, A = rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))
    model, data, pool = mech.model, mech.model.createData(), pin.ModelPool(mech.model, 1)
    out, M = np.empty((n, mech.nv)), np.empty((n, mech.nv, mech.nv))
    T = plain_rnea(model, data, Q, V, A, out).copy()
    assert np.array_equal(tree.inverse_dynamics(mech, Q, V, A, threads=threads), T)
    assert np.allclose(tree.forward_dynamics(mech, Q, V, T, threads=threads), A, atol=1e-9)
    assert np.array_equal(tree.mass_matrix(mech, Q, threads=threads), plain_crba(model, data, Q, M))
    cases = {
        "rnea": (lambda: tree.inverse_dynamics(mech, Q, V, A, threads=threads),
                 lambda: plain_rnea(model, data, Q, V, A, out),
                 lambda: compiled(pin.rneaInParallel, pool, Q, V, A, out)),
        "aba": (lambda: tree.forward_dynamics(mech, Q, V, T, threads=threads),
                lambda: plain_aba(model, data, Q, V, T, out),
                lambda: compiled(pin.abaInParallel, pool, Q, V, T, out)),
        "crba": (lambda: tree.mass_matrix(mech, Q, threads=threads),
                 lambda: plain_crba(model, data, Q, M), None),
    }
    lines = []
    for algorithm, (ours, plain, floor) in cases.items():
        candidates = {"ours": ours, "plain": plain}
        if floor is not None:
            candidates["floor"] = floor
        if algorithm == "rnea" and toolbox is not None:
            candidates["rtb"] = lambda: toolbox.rne(Q, V, A)
        t = interleaved(candidates, n, repeats)
        verdict = "ok" if t["ours"] <= t["plain"] else "SLOWER"
        line = (f"{name:<8}{algorithm:<6}{n:>8}{tree.thread_count(n, threads):>4}{t['plain'] * 1e6:>9.2f}"
                f"{t['ours'] * 1e6:>9.2f}{t['ours'] / t['plain']:>7.2f} {verdict:<7}")
        line += f"{t['floor'] * 1e6:>9.2f}{t['ours'] / t['floor']:>7.2f}" if "floor" in t else f"{'-':>9}{'-':>7}"
        if "rtb" in t:
            line += f"{t['rtb'] * 1e6:>10.2f}{t['rtb'] / t['ours']:>8.1f}x"
        lines.append(line)
    return lines


def peak_memory(mech, n: int, threads: int | None) -> str:
    """tracemalloc peak (MB) of each call at n states, next to the output's size."""
    rng = np.random.default_rng(1)
    Q = mech.random_configuration(rng, size=n)
    V, A = rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))
    parts = []
    for algorithm, call, size in (("rnea", lambda: tree.inverse_dynamics(mech, Q, V, A, threads=threads), mech.nv),
                                  ("aba", lambda: tree.forward_dynamics(mech, Q, V, A, threads=threads), mech.nv),
                                  ("crba", lambda: tree.mass_matrix(mech, Q, threads=threads), mech.nv**2)):
        tracemalloc.start()
        call()
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        parts.append(f"{algorithm} {peak / 1e6:.1f} MB (output {n * size * 8 / 1e6:.1f} MB)")
    return ", ".join(parts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 64, 1_000, 100_000])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=None, help="force a thread count (default: chosen)")
    args = parser.parse_args()
    try:
        import roboticstoolbox as rtb

        toolbox = {"puma560": rtb.models.DH.Puma560(), "ur5": rtb.models.DH.UR5()}
    except ImportError:
        toolbox = {}
        print("(roboticstoolbox-python is not installed: pip install '.[test]' for the comparison)")
    print(f"batched dynamics, µs per state, best of {args.repeats}; cores available "
          f"{tree.available_cores()}, idle {tree.idle_cores(tree.available_cores())}")
    print(f"{'robot':<8}{'algo':<6}{'N':>8}{'thr':>4}{'plain':>9}{'ours':>9}{'ratio':>7} {'<=1.0':<7}"
          f"{'floor':>9}{'/floor':>7}{'RTB arr':>10}{'RTB/ours':>9}")
    for name in ("puma560", "ur5"):
        mech = mechatron.load(name)
        for n in args.sizes:
            for line in rows(name, mech, n, args.repeats, args.threads, toolbox.get(name)):
                print(line)
    largest = max(args.sizes)
    print(f"peak memory at N = {largest} (puma560): "
          f"{peak_memory(mechatron.load('puma560'), largest, args.threads)}")
    crank = mechatron.load("crank_slider")
    q0 = assemble(crank, {"q1": 0.2})
    v0 = joint_velocity(crank, q0, {"q1": 8.0})
    steps = 1000
    t_sim = best_time(lambda: simulate(crank, q0, v0, steps * 1e-3, 1e-3), args.repeats)
    print(f"simulate crank_slider, {steps} RK4 steps: {t_sim * 1e3:.0f} ms ({t_sim / steps * 1e6:.0f} µs per step)")


if __name__ == "__main__":
    main()

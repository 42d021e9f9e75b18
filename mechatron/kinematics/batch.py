r"""Position analysis of many samples at once: Newton's method batched over samples, from guesses interpolated between
a few samples solved by continuation, checked sample by sample.

A sweep asks for the assembly of N samples of the inputs on one assembly branch. The sequential continuation
(:func:`mechatron.kinematics.sweeps.sweep`) solves one sample after the other; here

1. ``anchors`` — every m-th sample, m chosen so that the anchors' input step is at most :data:`ANCHOR_STEPS`
   continuation steps (:attr:`~mechatron.kinematics.loops.LoopSolver.max_step`) — are solved by that continuation
   (they keep the branch); a finer level of anchors, every :data:`FINER`-th sample or an input step of a fiftieth of
   a continuation step, is solved as in 2. from them, so that most samples start within the tolerance and need one
   evaluation;
2. every other sample starts from the cubic (Lagrange) interpolation in the sample index through the four nearest
   anchors and is solved by Newton's method on all samples at once: Φ(q) and J(q) of a chunk of samples from
   :class:`~mechatron.model.batched.BatchedFrames`, the steps J_d Δq_d = −Φ from one stacked ``np.linalg.solve``,
   until every residual is below :data:`~mechatron.kinematics.loops.TOLERANCE`, then one more step (rounding level);
3. each sample is checked against its predecessor: the change of the dependent coordinates must follow the velocity
   maps, Δq_d ≈ ½ (S_{k−1} + S_k) Δu (trapezoidal rule, error O(Δu³)); a sample that did not converge, jumped (error
   above a tenth of its change) or follows an input out of range is *doubtful*, and the caller solves it again by
   the sequential continuation, from the last good sample before it until its solution meets the batched one.

Memory: the work is done in chunks of at most :data:`CHUNK` samples (:func:`chunks`), so that it does not grow with N
beyond the (N, nq) array of the solutions.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from ..model.batched import BatchedFrames
from ..model.closures import ClosureSystem, FrameStates
from .loops import TOLERANCE

#: Samples evaluated together (the working storage is a few kB per sample of a chunk), at most and at least.
CHUNK = 2048
SMALLEST_CHUNK = 256
#: The anchors solved by continuation are this many continuation steps apart; the finer ones every FINER samples.
ANCHOR_STEPS = 8.0
FINER = 8
#: Newton iterations of the batched solve before a sample counts as not converged.
ITERATIONS = 12
#: A sample whose change from its predecessor differs from the velocity maps' prediction by more than this fraction
#: of the change (and more than :data:`JUMP_FLOOR`) is doubtful: it may have left the branch.
JUMP_RATIO = 0.1
JUMP_FLOOR = 1e-9


#: Square systems up to this size are solved by the explicit inverse (adjugate over determinant), vectorized.
EXPLICIT = 3


def inverse(A: np.ndarray) -> np.ndarray:
    r"""The inverses of a stack of square matrices A (n, m, m), m ≤ :data:`EXPLICIT`, by the adjugate:
    A⁻¹ = adj(A) / det A, the cofactors written out (m = 1: 1/a; m = 2: [[d, −b], [−c, a]] / (ad − bc); m = 3: the
    cross products of the columns, det A = a₀ · (a₁ × a₂)). Each element takes a few multiplications over all n
    matrices at once (no per-matrix LAPACK call); the rounding error is of the order of cond(A) · ε, as for LU. A
    singular matrix (det A = 0) gives inf or NaN entries."""
    n, m = A.shape[0], A.shape[1]
    out = np.empty((n, m, m))
    with np.errstate(divide="ignore", invalid="ignore"):
        if m == 1:
            np.divide(1.0, A, out=out)
        elif m == 2:
            a, b, c, d = A[:, 0, 0], A[:, 0, 1], A[:, 1, 0], A[:, 1, 1]
            scale = 1.0 / (a * d - b * c)
            np.multiply(d, scale, out=out[:, 0, 0])
            np.multiply(a, scale, out=out[:, 1, 1])
            np.multiply(-b, scale, out=out[:, 0, 1])
            np.multiply(-c, scale, out=out[:, 1, 0])
        else:  # the rows of A⁻¹ are the cross products of A's columns over det A
            columns = [A[:, :, j] for j in range(3)]
            rows = [_cross(columns[(i + 1) % 3], columns[(i + 2) % 3]) for i in range(3)]
            scale = 1.0 / np.einsum("ki,ki->k", columns[0], rows[0])
            for i in range(3):
                np.multiply(rows[i], scale[:, None], out=out[:, i, :])
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a × b of two (n, 3) arrays."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def product(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """A_k B_k for stacks A (n, m, l) and B (n, l, p) of small matrices: l multiply-adds of (n, m, p) arrays (faster
    than ``matmul`` on millions of tiny matrices)."""
    out = A[:, :, 0, None] * B[:, None, 0, :]
    for j in range(1, A.shape[2]):
        out += A[:, :, j, None] * B[:, None, j, :]
    return out


def apply(M: np.ndarray, x: np.ndarray) -> np.ndarray:
    """M_k x_k for a stack M (n, …, m) of small matrices (or stacks of them) and vectors x (n, m): m multiply-adds
    over the last axis (``einsum`` is several times slower at this shape)."""
    x = x.reshape(len(x), *(1,) * (M.ndim - 2), x.shape[-1])
    out = M[..., 0] * x[..., 0]
    for j in range(1, M.shape[-1]):
        out += M[..., j] * x[..., j]
    return out


def solve(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Solve A_k X_k = B_k for stacks of matrices A (n, m, m) and B (n, m, p): by :func:`inverse` for
    m ≤ :data:`EXPLICIT`, else by LU (``np.linalg.solve``); by least squares (``pinv``) where A_k is singular or not
    square."""
    m = A.shape[1]
    if m != A.shape[2]:
        return np.linalg.pinv(A) @ B
    if m > EXPLICIT:
        try:
            return np.linalg.solve(A, B)
        except np.linalg.LinAlgError:
            return np.linalg.pinv(A) @ B
    with np.errstate(invalid="ignore", over="ignore"):
        X = product(inverse(A), B)
    bad = ~np.isfinite(X).all(axis=(1, 2))
    if bad.any():
        X[bad] = np.linalg.pinv(A[bad]) @ B[bad]
    return X


def chunks(n: int, size: int | None = None) -> list[slice]:
    """Consecutive slices of at most ``size`` covering range(n); by default :data:`CHUNK`, or an eighth of n (at
    least :data:`SMALLEST_CHUNK`) when smaller, so that the working storage of a chunk (a few kB per sample) stays
    below 1 kB per sample of the whole run."""
    size = size or min(CHUNK, max(SMALLEST_CHUNK, n // 8))
    return [slice(start, min(start + size, n)) for start in range(0, n, size)]


def anchor_stride(U: np.ndarray, step: np.ndarray) -> int:
    """Every how many samples to take an anchor so that the anchors' input steps are at most ``step`` (m or rad, one
    per input), for the largest input step between samples in U (n, n_act)."""
    largest = np.abs(np.diff(U, axis=0)).max(axis=0, initial=0.0) if len(U) > 1 else np.zeros(U.shape[1])
    with np.errstate(divide="ignore"):
        stride = np.min(np.where(largest > 0, step / largest, np.inf))
    return int(max(1, min(stride, len(U)))) if np.isfinite(stride) else len(U)


def every(samples: np.ndarray, stride: int) -> np.ndarray:
    """Every ``stride``-th of ``samples`` and the last one."""
    out = samples[::stride]
    return np.append(out, samples[-1]) if len(samples) and out[-1] != samples[-1] else out


def interpolate(anchors: np.ndarray, values: np.ndarray, samples: np.ndarray) -> np.ndarray:
    """Values at ``samples`` (indices) of the cubic through the four nearest ``anchors`` (sorted indices, their
    ``values`` (n_anchors, nq)); fewer anchors give a lower degree. Newton's form: the divided differences
    c_k = f[x₀, …, x_k] of every window of four consecutive anchors (computed once per window), then at each sample
    p(s) = c₀ + (s − x₀)(c₁ + (s − x₁)(c₂ + (s − x₂) c₃)) (Horner) with its window's x and c. Samples in any order;
    sorted ones (runs sharing a window) are the fast case."""
    m = len(anchors)
    order = min(4, m)
    out = np.zeros((len(samples), values.shape[1]))
    if not (len(samples) and m):
        return out
    first = np.clip(np.searchsorted(anchors, samples) - order // 2, 0, m - order)
    windows = m - order + 1
    x = np.stack([anchors[i:i + windows] for i in range(order)], axis=1).astype(float)  # (windows, order)
    c = np.stack([values[i:i + windows] for i in range(order)], axis=1).astype(float)  # (windows, order, nq)
    for level in range(1, order):  # c[:, i] ← f[x_{i−level}, …, x_i], from the top down
        for i in range(order - 1, level - 1, -1):
            c[:, i] = (c[:, i] - c[:, i - 1]) / (x[:, i] - x[:, i - level])[:, None]
    # each run of samples with the same window takes its x and c by np.repeat (several times faster than a gather),
    # sample-last (contiguous rows of all samples: NumPy's inner loops then run over the samples)
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(first)) + 1, [len(first)]])
    window, counts = first[bounds[:-1]], np.diff(bounds)
    x = np.repeat(x.T[:, window], counts, axis=1)
    c = np.repeat(c.transpose(1, 2, 0)[:, :, window], counts, axis=2)
    s = np.asarray(samples, dtype=float)
    out = c[order - 1]
    for i in range(order - 2, -1, -1):
        out = c[i] + (s - x[i]) * out
    return np.ascontiguousarray(out.T)


def newton(system: ClosureSystem, frames: BatchedFrames, Q: np.ndarray, act: np.ndarray, dep: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Newton's method on the dependent coordinates ``dep`` of every row of Q (n, nq) at once, in place: returns
    which rows converged (residual below :data:`TOLERANCE` within :data:`ITERATIONS`, then one more step) and their
    dependent velocity maps S_d = −J_d⁻¹ J_a (n, n_dep, n_act) at the last evaluation (NaN where not converged)."""
    converged = np.zeros(len(Q), dtype=bool)
    maps = np.full((len(Q), len(dep), len(act)), np.nan)
    active = np.arange(len(Q))
    for _ in range(ITERATIONS + 1):
        if not len(active):
            break
        # a BatchedStates: the closures broadcast over its leading axis
        phi, J = system.stack(cast(FrameStates, frames.placements(Q[active])))
        with np.errstate(invalid="ignore"):
            error = np.abs(phi).max(axis=1, initial=0.0)
        below, finite = error < TOLERANCE, np.isfinite(error)
        if not finite.all():
            phi, J = phi[finite], J[finite]
        rows = active[finite]
        # one solve for the step J_d Δq_d = −Φ and the maps J_d S_d = −J_a
        X = solve(J[:, :, dep], -np.concatenate([phi[:, :, None], J[:, :, act]], axis=2))
        Q[rows[:, None], dep] += X[:, :, 0]  # the converged rows take their last, polishing step too
        done = below[finite]
        maps[rows[done]] = X[done, :, 1:]
        converged[rows[done]] = True
        active = rows[~done]
    return converged, maps


def jumps(Q: np.ndarray, U: np.ndarray, maps: np.ndarray, solved: np.ndarray) -> np.ndarray:
    """Which samples 1 … n−1 of a run (Q (n, nq) of the dependent coordinates, inputs U (n, n_act), dependent maps
    (n, n_dep, n_act)) changed from their predecessor (both ``solved``) otherwise than the velocity maps predict,
    Δq_d ≈ ½ (S_{k−1} + S_k) Δu (see the module docstring); false for sample 0."""
    with np.errstate(all="ignore"):  # sample-last arrays: NumPy's inner loops run over the samples
        steps = np.ascontiguousarray(np.diff(U, axis=0).T)
        M = np.ascontiguousarray(maps.transpose(1, 2, 0))
        predicted = sum(0.5 * (M[:, j, 1:] + M[:, j, :-1]) * steps[j] for j in range(U.shape[1]))
        change = np.diff(np.ascontiguousarray(Q.T), axis=1)
        error = np.abs(change - predicted).max(axis=0, initial=0.0)
        bad = ~(error <= JUMP_RATIO * np.abs(change).max(axis=0, initial=0.0) + JUMP_FLOOR)
    return np.concatenate([[False], bad & solved[1:] & solved[:-1]])

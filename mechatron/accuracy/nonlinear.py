r"""The position of a point with finite errors of the parameters and coordinates: the full nonlinear model
r' = r(l + Δl, q + Δq) [Egorov, 8.2], for Monte Carlo studies and for checking the first-order error [Egorov, 8.4].

A parameter error Δl turns every constant placement M into M · Π_k exp(ξ_k Δl_k) (the twists of
:func:`~mechatron.model.derivatives.placement_derivatives`), the factors in the order the parameters enter the
placement: for DH tables (Tz(d) Tx(a) Rx(α), Rz(θ)) and URDF origins (translation, then yaw, pitch, roll) that
order makes it exact, and :func:`factor_order` finds it by comparing with the rebuilt model. Where a placement is
not a product of one-parameter exponentials (a linkage body frame that turns toward a moved pin) the product is
exact to first order and the second-order terms (products of two errors) are approximate; ``exact`` says which.

A coordinate error Δq moves the configuration on its manifold: q ⊕ Δq (``pin.integrate``), one error per joint
coordinate (a continuous joint, whose q is (cos θ, sin θ), has one: its angle).

Three evaluators of the same model, each with ``positions(q, dl, dq) -> (N, 3)``:

- :class:`PerturbedChain` — a serial chain, vectorized over samples in NumPy (the point carried through the
  placements, the factor exponentials and the joint motions; revolute, continuous and prismatic joints): millions
  of samples per second;
- :class:`PerturbedLoops` — a closed loop, vectorized over samples: the placements of the tree for every sample
  (complex numbers for a planar mechanism, NumPy SE(3) products otherwise), the closures solved by Newton's method
  for all samples at once, from the first-order prediction of the dependent coordinates, with the Jacobians from
  the frame Jacobians and the small Newton systems by Gaussian elimination written over the samples;
- :class:`PerturbedLoop` — any mechanism, one sample at a time with Pinocchio: a copy of the model takes the
  perturbed placements, the loops are closed again by the loop solver's Newton method with the actuated
  coordinates at their perturbed values, and the point is read from the frame placement. It is the reference of
  the two others and the fallback for closures and joints they do not know.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, UnreachableError
from ..kinematics.loops import TOLERANCE, loop_solver
from ..model.closures import Gear, OnCurve, Pin, Slider
from ..model.derivatives import PlacementDerivatives, placement_derivatives
from ..model.derivatives import placements as _placements
from ..model.mechanism import Mechanism
from .sensitivity import loop_derivatives

#: Parameters per placement up to which every factor order is tried.
MAX_PERMUTED = 5

Floats = NDArray[np.float64]


@dataclass(frozen=True)
class FactorOrder:
    """For every placement (joints first, then frames) the parameters that move it, in factor order, and whether
    the ordered product reproduced the rebuilt model to second order (``exact``)."""

    order: tuple[tuple[int, ...], ...]
    exact: tuple[bool, ...]

    @property
    def all_exact(self) -> bool:
        return all(self.exact)


def factor_order(mech: Mechanism, derivatives: PlacementDerivatives, probe: float = 1e-3) -> FactorOrder:
    """The factor order of each placement: the permutation of its parameters whose product of exponentials best
    matches the model rebuilt with every parameter moved by ``probe`` (relative, with alternating signs); exact when
    the mismatch is below 1e-4 of the second-order terms. Kept in the mechanism's cache."""
    cache = mech.cached("accuracy.factor_order", dict)
    if derivatives.names not in cache:
        cache[derivatives.names] = _factor_order(mech, derivatives, probe)
    return cache[derivatives.names]


def _factor_order(mech: Mechanism, derivatives: PlacementDerivatives, probe: float) -> FactorOrder:
    values = mech.parameter_values()
    steps = np.array([probe * max(1.0, abs(values[n])) * (1 if k % 2 == 0 else -1)
                      for k, n in enumerate(derivatives.names)])
    moved = mech.with_parameters({n: values[n] + s for n, s in zip(derivatives.names, steps)}).model
    twists = np.concatenate([derivatives.joints, derivatives.frames], axis=1)  # (n_l, n_placements, 6)
    order, exact = [], []
    for j, (nominal, target) in enumerate(zip(_placements(mech.model), _placements(moved))):
        involved = [k for k in range(len(steps)) if np.abs(twists[k, j]).max() > 1e-12]
        second = sum(np.linalg.norm(twists[k, j]) * abs(steps[k]) for k in involved) ** 2

        def mismatch(perm: Sequence[int]) -> float:
            placement = nominal
            for k in perm:
                placement = placement * pin.exp6(twists[k, j] * steps[k])
            return float(np.linalg.norm(pin.log6(placement.actInv(target)).vector))

        candidates = itertools.permutations(involved) if len(involved) <= MAX_PERMUTED else [tuple(involved)]
        best = min(candidates, key=mismatch, default=())
        order.append(tuple(best))
        exact.append(second == 0 or mismatch(best) <= 1e-4 * second)
    return FactorOrder(tuple(order), tuple(exact))


# ------------------------------------------------------------------------------------------ SE(3) over samples
#: Below this |angle| the sines and cosines come from their Taylor series.
SERIES_LIMIT = 0.01
#: The series stop at the first term whose bound is below this (absolute, for unit values: below rounding).
SERIES_ERROR = 1e-17
#: Taylor coefficients: cos x = Σ (−1)^k x^2k/(2k)!, sin x = x Σ (−1)^k x^2k/(2k+1)!,
#: (1 − cos x)/x = x Σ (−1)^k x^2k/(2k+2)!, (x − sin x)/x = x² Σ (−1)^k x^2k/(2k+3)!.
COSINE, SINE, VERSINE, EXCESS = ([1 / math.factorial(2 * k + j) for k in range(5)] for j in (0, 1, 2, 3))


def _series(x2: Floats, coefficients: Sequence[float], largest: float) -> Floats:
    """Σ_k (−1)^k c_k x2^k by Horner's rule, with the fewest terms K whose first omitted one is below
    :data:`SERIES_ERROR` at the largest |x| (``largest``, at most :data:`SERIES_LIMIT`): the error of an alternating
    series with decreasing terms is below its first omitted term, c_K largest^2K. At |x| ≤ 4e-4 (errors of a
    Monte Carlo) two terms suffice, at 0.01 four."""
    K = next((k for k in range(1, len(coefficients)) if coefficients[k] * largest ** (2 * k) <= SERIES_ERROR),
             len(coefficients))
    if K == 1:
        return np.full_like(x2, coefficients[0])
    p = coefficients[K - 2] - x2 * coefficients[K - 1]
    for k in range(K - 3, -1, -1):
        p = coefficients[k] - x2 * p
    return p


def _cos_sin(angle: Floats, offset: float = 0.0) -> tuple[Floats, Floats]:
    """cos and sin of offset + angle; with small angles by series (:func:`_series`) and the addition theorem (no
    trigonometric calls per sample)."""
    largest = np.abs(angle).max(initial=0.0)
    if not largest <= SERIES_LIMIT:  # NaN too takes np.cos, np.sin
        return np.cos(offset + angle), np.sin(offset + angle)
    a2 = angle * angle
    c, s = _series(a2, COSINE, largest), angle * _series(a2, SINE, largest)
    if offset == 0.0:
        return c, s
    c0, s0 = math.cos(offset), math.sin(offset)
    return c0 * c - s0 * s, s0 * c + c0 * s


def _screw(theta: Floats, c: Floats | None = None, s: Floats | None = None) -> tuple[Floats, Floats]:
    """(1 − cos θ)/θ and (θ − sin θ)/θ (0 at θ = 0), the translation factors of a screw motion; by series below
    :data:`SERIES_LIMIT`, else from cos θ, sin θ (``c``, ``s`` if known)."""
    largest = np.abs(theta).max(initial=0.0)
    if not largest <= SERIES_LIMIT:
        c, s = (np.cos(theta), np.sin(theta)) if c is None else (c, s)
        safe = np.where(theta == 0, 1.0, theta)
        return np.where(theta == 0, 0.0, (1 - c) / safe), np.where(theta == 0, 0.0, (theta - s) / safe)
    t2 = theta * theta
    return theta * _series(t2, VERSINE, largest), t2 * _series(t2, EXCESS, largest)


def _skew(axis: Floats) -> Floats:
    return np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])


def _rotation_matrices(axis: Floats, angle: Floats, offset: float = 0.0) -> Floats:
    """Rotations (N, 3, 3) about the unit ``axis`` by offset + ``angle`` (N,): I + sin θ K + (1 − cos θ) K²."""
    return _rotated(np.eye(3), axis, angle, offset)


def _rotated(R: Floats, axis: Floats, angle: Floats, offset: float = 0.0) -> Floats:
    """R · Rot(axis, offset + angle) (N, 3, 3) for one (3, 3) or N (N, 3, 3) rotations R: R + sin θ R K +
    (1 − cos θ) R K², without a product of stacks."""
    c, s = _cos_sin(angle, offset)
    K = _skew(axis)
    RK = _product(R, K)
    return R + s[:, None, None] * RK + (1 - c)[:, None, None] * _product(RK, K)


def _exp_parts(xi: Floats, t: Floats) -> tuple[Floats | None, Floats, Floats]:
    """exp(ξ t) for one twist ξ = [v; ω] and N scalars t: (unit rotation axis or None, angles θ = |ω| t (N,),
    translations p (N, 3)), p = (I + (1 − cos θ)/θ K + (θ − sin θ)/θ K²) v t with K = [axis]×."""
    v, w = xi[:3], xi[3:]
    norm = np.linalg.norm(w)
    if norm < 1e-15:
        return None, np.zeros_like(t), t[:, None] * v
    axis = w / norm
    theta = norm * t
    a, b = _screw(theta)
    K = _skew(axis)
    Kv = K @ v
    return axis, theta, t[:, None] * v + (a * t)[:, None] * Kv + (b * t)[:, None] * (K @ Kv)


def _product(A: Floats, B: Floats) -> Floats:
    """A B for rotations that are one (3, 3) or N (N, 3, 3) each (a stack times one matrix as one GEMM; a stack
    that repeats one matrix, stride 0, taken as that matrix)."""
    A = A[0] if A.ndim == 3 and A.strides[0] == 0 else A
    B = B[0] if B.ndim == 3 and B.strides[0] == 0 else B
    if A.ndim == 3 and B.ndim == 2:
        return (A.reshape(-1, 3) @ np.ascontiguousarray(B)).reshape(A.shape)
    return A @ B


def _turn(R: Floats, x: Floats) -> Floats:
    """R x for one (3, 3) or N (N, 3, 3) rotations and one (3,) or N (N, 3) vectors."""
    if R.ndim == 2:
        return x @ R.T
    if x.ndim == 1:
        return (R.reshape(-1, 3) @ x).reshape(R.shape[:2])
    return R[:, :, 0] * x[:, 0, None] + R[:, :, 1] * x[:, 1, None] + R[:, :, 2] * x[:, 2, None]


def _compose(R1: Floats, p1: Floats, R2: Floats, p2: Floats) -> tuple[Floats, Floats]:
    """(R1, p1) · (R2, p2) for placements that are one (3, 3), (3,) or N (N, 3, 3), (N, 3) each."""
    return _product(R1, R2), p1 + _turn(R1, p2)


def _exp_placement(xi: Floats, t: Floats) -> tuple[Floats, Floats]:
    """exp(ξ t) as N placements (R (N, 3, 3), or one (3, 3) for a translation, p (N, 3))."""
    axis, theta, p = _exp_parts(xi, t)
    return (np.eye(3) if axis is None else _rotation_matrices(axis, theta)), p


# ------------------------------------------------------------------------------------------------ joints
def _joint_axis(joint: pin.JointModel) -> tuple[str, Floats]:
    """("revolute" or "prismatic", unit axis in the joint frame) of a one-axis joint (continuous ones included)."""
    short = joint.shortname()
    unit = {"X": np.array([1.0, 0, 0]), "Y": np.array([0, 1.0, 0]), "Z": np.array([0, 0, 1.0])}
    if short in ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRUBX", "JointModelRUBY",
                 "JointModelRUBZ"):
        return "revolute", unit[short[-1]]
    if short in ("JointModelPX", "JointModelPY", "JointModelPZ"):
        return "prismatic", unit[short[-1]]
    if short in ("JointModelRevoluteUnaligned", "JointModelRevoluteUnboundedUnaligned"):
        return "revolute", np.asarray(joint.extract().axis, dtype=float)
    if short == "JointModelPrismaticUnaligned":
        return "prismatic", np.asarray(joint.extract().axis, dtype=float)
    raise InputError(f"a vectorized error model needs revolute, continuous and prismatic joints, not {short}")


def _joint_value(joint: pin.JointModel, q: Floats) -> Floats:
    """The joint's coordinate (angle in rad or displacement in m) at q (..., nq): q itself, or the angle
    atan2(sin, cos) of a continuous joint."""
    i = joint.idx_q
    if joint.nq == 2:
        return np.arctan2(q[..., i + 1], q[..., i])
    return q[..., i]


def vectorizable(mech: Mechanism) -> bool:
    """Whether the vectorized evaluators know every joint (one-axis: revolute, continuous, prismatic) and every
    closure (pin, slider, curve, gear) of ``mech``."""
    try:
        for joint in mech.model.joints[1:]:
            _joint_axis(joint)
    except InputError:
        return False
    return all(isinstance(c, (Pin, Slider, OnCurve, Gear)) for c in mech.closures)


class _Factors:
    """The parameter factors Π_k exp(ξ_k Δl_k) of every placement, in factor order."""

    def __init__(self, mech: Mechanism, parameters: Sequence[str]) -> None:
        self.mech = mech
        self.derivatives = placement_derivatives(mech, parameters)
        self.order = factor_order(mech, self.derivatives) if len(parameters) else None

    @property
    def exact(self) -> bool:
        return self.order is None or self.order.all_exact

    def twists(self, placement: int) -> tuple[Floats, tuple[int, ...]]:
        """(twists (n_l, 6), factor order) of placement ``placement`` (joints first, then frames)."""
        nj, d = self.mech.model.njoints, self.derivatives
        twists = d.joints[:, placement] if placement < nj else d.frames[:, placement - nj]
        return twists, (self.order.order[placement] if self.order is not None else ())


# ------------------------------------------------------------------------------------------------ serial
Point = tuple[Floats, Floats, Floats]  # a point's x, y, z over the samples (each (N,) or a scalar 0)


def _sum(terms: list) -> Floats | float:
    """Σ coefficient · value over the terms with a nonzero coefficient (a coefficient of 1 is not multiplied)."""
    out: Floats | float = 0.0
    for c, v in terms:
        if isinstance(c, float) and c == 0.0:
            continue
        term = v if isinstance(c, float) and c == 1.0 else c * v
        out = term if isinstance(out, float) and out == 0.0 else out + term
    return out


def _place(x: Point, R: Floats, t: Floats) -> Point:
    """R x + t for one constant placement, row by row (zero entries of R skipped)."""
    return tuple(_sum([(float(t[i]), 1.0)] + [(float(R[i, j]), x[j]) for j in range(3)]) for i in range(3))


def _turn_point(x: Point, axis: Floats, c: Floats, s: Floats) -> Point:
    """x turned about the unit ``axis`` by the angle of cosine c, sine s: two rows for a coordinate axis
    (x_i' = c x_i − s x_j, x_j' = s x_i + c x_j, (i, j, k) cyclic), else Rodrigues:
    x c + (a × x) s + a (a·x)(1 − c)."""
    nonzero = np.flatnonzero(axis)
    if len(nonzero) == 1:
        k = int(nonzero[0])
        i, j = (k + 1) % 3, (k + 2) % 3
        s = s if axis[k] > 0 else -s
        out = [x[0], x[1], x[2]]
        out[i], out[j] = c * x[i] - s * x[j], s * x[i] + c * x[j]
        return tuple(out)
    a = [float(v) for v in axis]
    dot = (1 - c) * _sum([(a[n], x[n]) for n in range(3)])
    cross = [a[1] * x[2] - a[2] * x[1], a[2] * x[0] - a[0] * x[2], a[0] * x[1] - a[1] * x[0]]
    return tuple(x[n] * c + cross[n] * s + a[n] * dot for n in range(3))


def _exp_point(x: Point, xi: Floats, t: Floats) -> Point:
    """exp(ξ t) x for one twist ξ = [v; ω] and N scalars t: x turned by θ = |ω| t about ω/|ω|, plus
    p = t v + (1 − cos θ)/θ t K v + (θ − sin θ)/θ t K² v (K = [ω/|ω|]×; series below :data:`SERIES_LIMIT`)."""
    v, w = xi[:3], xi[3:]
    norm = float(np.linalg.norm(w))
    if norm < 1e-15:
        return tuple(x[n] + t * float(v[n]) if v[n] != 0 else x[n] for n in range(3))
    axis = w / norm
    theta = norm * t
    c, s = _cos_sin(theta)
    x = _turn_point(x, axis, c, s)
    K = _skew(axis)
    Kv, KKv = K @ v, K @ (K @ v)
    if not (v.any() or Kv.any()):
        return x
    a, b = _screw(theta, c, s)
    a, b = a * t, b * t
    return tuple(x[n] + _sum([(float(v[n]), t), (float(Kv[n]), a), (float(KKv[n]), b)]) for n in range(3))


#: Rows of a tall matrix multiplied at a time by :func:`_rows_product`.
PRODUCT_BLOCK = 512


def _rows_product(a: Floats, B: Floats) -> Floats:
    """a @ B for a tall a (N, k) and a small B (k, m), :data:`PRODUCT_BLOCK` rows at a time: each block is below
    OpenBLAS's threading threshold (about 2.6e5 multiply-adds), so the product runs on one thread — on a busy
    two-core machine the threads of one large product wait for each other (5–7× slower measured, 1.5 ms against
    10 ms for 32,768 × 20 × 5)."""
    out = np.empty((len(a), B.shape[1]))
    for start in range(0, len(a), PRODUCT_BLOCK):
        np.matmul(a[start:start + PRODUCT_BLOCK], B, out=out[start:start + PRODUCT_BLOCK])
    return out


#: Rows of a tall array transposed at a time by :func:`_transposed`.
TRANSPOSE_BLOCK = 512


def _transposed(a: Floats) -> Floats:
    """a.T (m, N) contiguous for a (N, m), copied in blocks of :data:`TRANSPOSE_BLOCK` rows that stay in the cache
    (one transposed copy of a tall array strides through memory, several times slower)."""
    out = np.empty(a.shape[::-1])
    for start in range(0, len(a), TRANSPOSE_BLOCK):
        out[:, start:start + TRANSPOSE_BLOCK] = a[start:start + TRANSPOSE_BLOCK].T
    return out


class PerturbedChain(_Factors):
    """The position of ``frame`` of a serial mechanism for N samples of parameter errors (N, n_l) and
    coordinate errors (N, nv) at one nominal configuration, vectorized over the samples: the point is carried from
    the frame back to the world through every factor (constant placement, parameter exponentials, joint motion),
    so only vectors are transformed, component by component (three contiguous (N,) arrays; rotations about a
    coordinate axis touch two of them, pure translations one per nonzero entry, zero entries of a placement are
    skipped)."""

    def __init__(self, mech: Mechanism, frame: str, parameters: Sequence[str]) -> None:
        if mech.closures:
            raise InputError(f"{mech.name} is a closed loop: use PerturbedLoops")
        super().__init__(mech, parameters)
        self.fid = mech.frame_id(frame)
        model = mech.model
        self.path = [j for j in model.supports[model.frames[self.fid].parentJoint] if j != 0]
        self.axes = {j: _joint_axis(model.joints[j]) for j in self.path}

    def _factors(self, x: Point, placement: int, dl: Floats) -> Point:
        """Π_k exp(ξ_k Δl_k) x for the placement's parameters in factor order (applied last factor first)."""
        twists, order = self.twists(placement)
        for k in reversed(order):
            x = _exp_point(x, twists[k], dl[k])
        return x

    def positions(self, q: ArrayLike, dl: ArrayLike, dq: ArrayLike) -> Floats:
        """Point positions (N, 3) (m) at the nominal configuration ``q`` (nq,) with parameter errors ``dl`` (N, n_l)
        (m, rad) and joint coordinate errors ``dq`` (N, nv) (rad, m)."""
        model = self.mech.model
        q = np.asarray(q, dtype=float)
        dl = _transposed(np.asarray(dl, dtype=float))  # rows: one error over the samples
        dq = _transposed(np.asarray(dq, dtype=float))
        n = dl.shape[1] if dl.size or not dq.size else dq.shape[1]
        zero = np.zeros(n)
        x = self._factors((zero, zero, zero), model.njoints + self.fid, dl)
        M = model.frames[self.fid].placement
        x = _place(x, M.rotation, M.translation)
        for j in reversed(self.path):
            kind, axis = self.axes[j]
            joint = model.joints[j]
            value = float(_joint_value(joint, q))
            if kind == "revolute":
                x = _turn_point(x, axis, *_cos_sin(dq[joint.idx_v], value))
            else:
                x = tuple(x[i] + (value + dq[joint.idx_v]) * float(axis[i]) if axis[i] != 0 else x[i]
                          for i in range(3))
            x = self._factors(x, j, dl)
            M = model.jointPlacements[j]
            x = _place(x, M.rotation, M.translation)
        return np.stack([np.broadcast_to(c, (n,)) for c in x], axis=1)


# ------------------------------------------------------------------------------------------------ closed loops
def _wrap(angle: Floats) -> Floats:
    """Angles wrapped to [−π, π]."""
    return angle - 2 * np.pi * np.round(angle / (2 * np.pi))


def _curve(f: Callable[[float], float], x: Floats) -> Floats:
    """f(x) for an array of x: one call if f takes arrays, else one call per value."""
    try:
        y = np.asarray(f(x), dtype=float)
        if y.shape == x.shape:
            return y
    except (TypeError, ValueError):
        pass
    return np.array([f(float(v)) for v in x])


#: Square systems up to this size are solved by :func:`_eliminate`, larger ones by LAPACK.
ELIMINATED = 6
#: Threshold of the pivots of :func:`_eliminate`: |pivot| at least this fraction of its column's largest entry.
PIVOT_THRESHOLD = 0.5


def _solve_batch(A: Floats, b: Floats) -> Floats:
    """x (n, N) with A x = b for N systems, samples last (A (m, n, N), b (m, N)): :func:`_eliminate` for square
    systems up to :data:`ELIMINATED`, else (and where elimination fails its pivot test) LU (``np.linalg.solve``);
    least squares (``pinv``) where A is not square or singular."""
    if A.shape[0] == A.shape[1] and A.shape[0] <= ELIMINATED and A.shape[2]:
        x, good = _eliminate(A, b)
        bad = np.flatnonzero(~good)
        if len(bad):
            x[:, bad] = _lapack_solve(A[:, :, bad], b[:, bad])
        return x
    return _lapack_solve(A, b)


def _lapack_solve(A: Floats, b: Floats) -> Floats:
    """:func:`_solve_batch` by LAPACK, one system after the other."""
    A, b = A.transpose(2, 0, 1), b.T[..., None]
    if A.shape[1] == A.shape[2]:
        try:
            return np.linalg.solve(A, b)[..., 0].T
        except np.linalg.LinAlgError:
            pass
    return (np.linalg.pinv(A) @ b)[..., 0].T


def _pivot_order(A: Floats) -> list[int]:
    """The row order of Gaussian elimination with partial pivoting of one matrix A (m, m) (identity if A is not
    finite)."""
    m = len(A)
    if not np.isfinite(A).all():
        return list(range(m))
    A, order = A.copy(), list(range(m))
    for k in range(m):
        p = k + int(np.abs(A[k:, k]).argmax())
        A[[k, p]], order[k], order[p] = A[[p, k]], order[p], order[k]
        if A[k, k] != 0:
            A[k + 1:] -= np.outer(A[k + 1:, k] / A[k, k], A[k])
    return order


def _eliminate(A: Floats, b: Floats) -> tuple[Floats, NDArray[np.bool_]]:
    r"""Solve A_k x_k = b_k for N small square systems, samples last (A (m, m, N), b (m, N)), by Gaussian
    elimination written on (N,) arrays, one entry at a time (no per-matrix LAPACK call: about m³/3 multiply-adds
    over all N at once). The rows are taken in one order for all systems, partial pivoting's order for the first
    one (the systems of a Monte Carlo differ little); a system is *good* where each pivot is at least
    :data:`PIVOT_THRESHOLD` of the largest entry of its column (threshold partial pivoting: growth at most
    (1 + 1/threshold)^(m−1), a rounding error of the order of that times cond(A) ε, as for LU) and the solution is
    finite. Returns (x (m, N), good (N,))."""
    m = len(A)
    rows = [[A[r, j] for j in range(m)] + [b[r]] for r in _pivot_order(A[:, :, 0])]
    good = np.ones(A.shape[2], dtype=bool)
    with np.errstate(all="ignore"):
        for k in range(m):
            pivot = rows[k][k]
            largest = np.abs(pivot)
            for i in range(k + 1, m):
                largest = np.maximum(largest, np.abs(rows[i][k]))
            good &= np.abs(pivot) >= PIVOT_THRESHOLD * largest
            for i in range(k + 1, m):
                f = rows[i][k] / pivot
                rows[i] = rows[i][:k + 1] + [rows[i][j] - f * rows[k][j] for j in range(k + 1, m + 1)]
        x = [rows[0][0]] * m
        for k in range(m - 1, -1, -1):
            total = rows[k][m]
            for j in range(k + 1, m):
                total = total - rows[k][j] * x[j]
            x[k] = total / rows[k][k]
        x = np.stack(x)
        good &= np.isfinite(x).all(axis=0)
    return x, good


#: Planar mechanisms: placements whose rotation leaves z and twists whose z and tilt parts are below this.
PLANAR_TOLERANCE = 1e-14

Planar = tuple[complex | Floats, complex | Floats]  # a planar placement: rotation e^{iθ}, translation x + iy


def _unit(angle: Floats) -> Floats:
    """e^{i angle} (N,) complex: the cosines and sines by :func:`_cos_sin` about the first angle (series when
    all angles lie within :data:`SERIES_LIMIT` of it)."""
    a0 = float(angle[0]) if len(angle) and np.isfinite(angle[0]) else 0.0
    c, s = _cos_sin(angle - a0, a0)
    out = np.empty(len(angle), dtype=complex)
    out.real, out.imag = c, s
    return out


class _PlanarLoops:
    r"""The placements of a planar mechanism (revolute joints about ±z, prismatic ones in the plane, placements that
    turn about z, parameter twists [v_x, v_y, 0, 0, 0, ω_z]) as complex numbers: a placement is (e^{iθ}, x + iy),
    composed as (z₁, p₁)(z₂, p₂) = (z₁ z₂, p₁ + z₁ p₂) — four real products for a rotation instead of 27, one
    complex ufunc call each. The parameter factors of a placement that are all translations (the common case) sum to
    p₀ + Σ_k Δl_k z₀ v_k, one matrix product for all such placements; a rotating factor exp(ξ t) is
    (e^{i ω t}, p) with p from :func:`_exp_parts`. The z coordinates are constant (every motion is in the plane):
    the point's z is its nominal one. The same numbers as the spatial path to rounding."""

    def __init__(self, loops: PerturbedLoops) -> None:
        self.loops = loops
        model = loops.mech.model
        self.keys = [("joint", j) for j in loops.joints] + [("frame", f) for f in loops.frames]
        placements = [(j, model.jointPlacements[j]) for j in loops.joints]
        placements += [(model.njoints + f, model.frames[f].placement) for f in loops.frames]
        self.nominal, self.moving, columns = [], [], []
        for m, (index, M) in enumerate(placements):
            z0, p0 = complex(M.rotation[0, 0], M.rotation[1, 0]), complex(*M.translation[:2])
            twists, order = loops.twists(index)
            self.nominal.append((z0, p0))
            if any(twists[k][5] != 0 for k in order):  # a rotating factor: the factors one by one
                self.moving.append((m, [(twists[k], k) for k in order]))
            else:
                columns.extend((m, k, z0 * complex(*twists[k][:2])) for k in order)
        self.translated = sorted({m for m, _, _ in columns})
        self.weights = np.zeros((len(loops.derivatives.names), 2 * len(self.translated)))  # (n_l, 2 P): re, im
        for m, k, w in columns:
            c = 2 * self.translated.index(m)
            self.weights[k, c] += w.real
            self.weights[k, c + 1] += w.imag
        self.signs = {j: float(axis[2]) if kind == "revolute" else complex(*axis[:2])
                      for j, (kind, axis) in loops.axes.items()}
        self.turned = {loops.frame_ids[name] for name in loops.angled}
        frame = model.frames[loops.fid]
        self.z = frame.placement.translation[2] + sum(model.jointPlacements[j].translation[2]
                                                      for j in model.supports[frame.parentJoint] if j != 0)

    @staticmethod
    def applies(loops: PerturbedLoops) -> bool:
        """Whether the mechanism is planar in the sense above and its pins compare x and y only."""
        model = loops.mech.model
        if any(isinstance(c, Pin) and c.nrows != 2 for c in loops.closures):
            return False
        for kind, axis in loops.axes.values():
            if np.abs(axis[:2] if kind == "revolute" else axis[2:]).max() > PLANAR_TOLERANCE:
                return False
        indices = list(loops.joints) + [model.njoints + f for f in loops.frames]
        placements = [model.jointPlacements[j] for j in loops.joints] + [model.frames[f].placement
                                                                          for f in loops.frames]
        for index, M in zip(indices, placements):
            R = M.rotation
            if max(np.abs(R[2, :2]).max(), np.abs(R[:2, 2]).max(), abs(R[2, 2] - 1)) > PLANAR_TOLERANCE:
                return False
            twists, order = loops.twists(index)
            if order and np.abs(twists[list(order)][:, 2:5]).max() > PLANAR_TOLERANCE:
                return False
        return True

    def constants(self, dl: Floats) -> list[Planar]:
        """The perturbed constant placements (z, p) of the keys, each (N,) or one for all samples."""
        out: list[Planar] = list(self.nominal)
        if len(self.translated):
            moved = np.ascontiguousarray(_rows_product(dl, self.weights).view(complex).T)  # (P, N): Σ Δl_k z₀ v_k
            for row, m in zip(moved, self.translated):
                out[m] = (out[m][0], row + out[m][1])
        for m, factors in self.moving:
            z, p = out[m]
            for twist, k in factors:
                axis, theta, shift = _exp_parts(twist, dl[:, k])
                p = p + z * (shift[:, 0] + 1j * shift[:, 1])
                if axis is not None:
                    z = z * _unit(axis[2] * theta)
            out[m] = (z, p)
        return out

    @staticmethod
    def select(constants: list[Planar], rows: NDArray[np.intp]) -> list[Planar]:
        return [(z[rows] if np.ndim(z) else z, p[rows] if np.ndim(p) else p) for z, p in constants]

    def world(self, q: Floats, constants: list[Planar], point_only: bool = False
              ) -> tuple[dict[int, Planar], dict[int, Planar]]:
        """World placements (z, p) of the frames used (or only the studied one) and of their joints at q (N, nq); a
        frame's z only where a slider needs its angle (else None)."""
        loops, model = self.loops, self.loops.mech.model
        index = {key: m for m, key in enumerate(self.keys)}
        joints: dict[int, Planar] = {0: (1.0 + 0j, 0j)}
        for j in loops.point_joints if point_only else loops.joints:
            zp, pp = joints[model.parents[j]]
            z0, p0 = constants[index[("joint", j)]]
            value = _joint_value(model.joints[j], q)
            sign = self.signs[j]
            if isinstance(sign, float):  # revolute about ±z
                joints[j] = zp * z0 * _unit(sign * value), pp + zp * p0
            else:  # prismatic along the in-plane axis
                z = zp * z0
                joints[j] = z, pp + zp * p0 + z * (sign * value)
        frames = {}
        for f in [loops.fid] if point_only else loops.frames:
            z, p = joints[model.frames[f].parentJoint]
            z0, p0 = constants[index[("frame", f)]]
            frames[f] = z * z0 if f in self.turned else None, p + z * p0
        return frames, joints

    def quantities(self, q: Floats, constants: list[Planar]) -> tuple[dict, dict, dict]:
        """Per closure frame: the position (x, y), the linear Jacobian columns (∂x/∂q_d, ∂y/∂q_d) (n_dep, N) each
        (revolute: i s (p_f − p_j); prismatic: z_j a), the angular one ∂θ/∂q_d (n_dep, 1), and the angles of the
        slider frames (arg z)."""
        loops = self.loops
        frames, joints = self.world(q, constants)
        position, linear, turn, angle = {}, {}, {}, {}
        for name, f in loops.frame_ids.items():
            z, p = frames[f]
            position[name] = (p.real, p.imag)
            columns = np.zeros((len(loops.dep), len(q)), dtype=complex)
            spin = np.zeros((len(loops.dep), 1))
            for c, j in loops.moved_by[f]:
                sign = self.signs[j]
                if isinstance(sign, float):
                    columns[c] = 1j * sign * (p - joints[j][1])
                    spin[c] = sign
                else:
                    columns[c] = joints[j][0] * sign
            linear[name], turn[name] = (columns.real, columns.imag), spin
            if name in loops.angled:
                angle[name] = np.angle(z)
        return position, angle, linear, turn

    def point(self, q: Floats, constants: list[Planar]) -> Floats:
        """The studied point (N, 3) at q (N, nq)."""
        p = self.world(q, constants, point_only=True)[0][self.loops.fid][1]
        return np.stack([p.real, p.imag, np.full(len(q), self.z)], axis=1)


@dataclass
class Perturbed:
    """What the parameter errors of N samples change: the constant placements (by the evaluator's own key) and the
    closures' offsets, {closure name: (N,)} (a locked slider's angle offset, a gear's offset)."""

    placements: dict | list
    offsets: dict[str, Floats]


def closure_offsets(closures: Sequence, derivatives: PlacementDerivatives, dl: Floats) -> dict[str, Floats]:
    """The offsets of the closures the parameters move, for the errors ``dl`` (N, n_l): c + Σ_k ∂c/∂l_k Δl_k (N,),
    exact to first order (:attr:`~mechatron.model.derivatives.PlacementDerivatives.constants`)."""
    out = {}
    for c in closures:
        moved = derivatives.constants.get(c.name, {})
        if isinstance(c, Slider) and c.lock_angle and "angle_offset" in moved:
            out[c.name] = c.angle_offset + dl @ moved["angle_offset"]
        elif isinstance(c, Gear) and "offset" in moved:
            out[c.name] = c.offset + dl @ moved["offset"]
    return out


def _take(a, rows: NDArray[np.intp], n: int, select: Callable | None = None):
    """The samples ``rows`` of ``a`` (samples last, or by ``select(a, rows)``), ``a`` itself when the rows are all n."""
    if len(rows) == n:
        return a
    return select(a, rows) if select else a[..., rows]


class PerturbedLoops(_Factors):
    """The position of ``frame`` of a closed-loop mechanism for N samples of parameter errors (N, n_l) and errors
    of the actuated coordinates (N, n_act) at one assembled configuration, vectorized over the samples.

    For every sample the tree's placements carry the parameter factors; the closures Φ(q, l) = 0 are solved for the
    dependent coordinates by Newton's method for all samples together, starting from the first-order prediction
    q + ∂q/∂l Δl + S Δq_a (the implicit-function theorem), with the step halved where it makes a residual grow,
    until every residual is below the loop solver's tolerance, and one more step. The closure Jacobians ∂Φ/∂q_d
    come from the frame Jacobians (ω = R a, v = ω × (p_f − p_j) for a revolute joint, v = R a for a prismatic one) as
    :mod:`mechatron.model.closures` forms them; the Newton systems are solved by :func:`_solve_batch`. Samples whose
    loops do not close in :data:`MAX_ITERATIONS` steps give NaN.

    A planar mechanism (``planar``, the default, and :meth:`_PlanarLoops.applies`) takes the planar path: its
    placements are complex numbers (:class:`_PlanarLoops`); any other one the spatial path: (N, 3, 3) rotations and
    (N, 3) translations. Both give the same numbers to rounding."""

    #: Newton steps at the most.
    MAX_ITERATIONS = 50

    def __init__(self, mech: Mechanism, frame: str, parameters: Sequence[str], planar: bool = True) -> None:
        if not mech.closures:
            raise InputError(f"{mech.name} has no closures: use PerturbedChain")
        if not vectorizable(mech):
            raise InputError(f"{mech.name}: a vectorized error model needs one-axis joints and pin, slider, curve "
                             "or gear closures: use PerturbedLoop")
        super().__init__(mech, parameters)
        model = mech.model
        self.solver = loop_solver(mech)
        self.closures = list(self.solver.system.closures)
        self.fid = mech.frame_id(frame)
        self.frame_ids = {name: mech.frame_id(name) for name in self.solver.system.frame_names}
        frames = {self.fid, *self.frame_ids.values()}
        joints = {j for f in frames for j in model.supports[model.frames[f].parentJoint] if j != 0}
        self.joints = sorted(joints)  # a parent's index is below its children's
        self.frames = sorted(frames)
        self.point_joints = [j for j in self.joints if j in model.supports[model.frames[self.fid].parentJoint]]
        self.axes = {j: _joint_axis(model.joints[j]) for j in self.joints}
        by_index = {model.joints[j].idx_v: j for j in range(1, model.njoints)}
        self.dep = self.solver.dep
        self.dep_joints = [by_index[int(i)] for i in self.dep]
        self.moved_by = {f: [(c, j) for c, j in enumerate(self.dep_joints)
                             if j in model.supports[model.frames[f].parentJoint]] for f in self.frame_ids.values()}
        self.angled = {name for c in self.closures if isinstance(c, Slider) for name in (c.line, c.point)}
        self.planar = _PlanarLoops(self) if planar and _PlanarLoops.applies(self) else None

    # --------------------------------------------------------------------------------------- placements
    def _constant(self, placement: int, M: pin.SE3, dl: Floats) -> tuple[Floats, Floats]:
        R, p = M.rotation, M.translation
        twists, order = self.twists(placement)
        for k in order:
            if twists[k][3:].any():
                R, p = _compose(R, p, *_exp_placement(twists[k], dl[:, k]))
            else:  # a translation exp([v; 0] t): R unchanged, p + t R v
                p = p + dl[:, k, None] * _turn(R, twists[k][:3])
        return R, p

    def _constants(self, dl: Floats) -> Perturbed:
        """The perturbed constant placements of the joints and frames used and the closures' offsets, one per sample
        (or one for all)."""
        return Perturbed(self._placement_constants(dl), closure_offsets(self.closures, self.derivatives, dl))

    def _placement_constants(self, dl: Floats) -> dict | list:
        if self.planar:
            return self.planar.constants(dl)
        model = self.mech.model
        out = {("joint", j): self._constant(j, model.jointPlacements[j], dl) for j in self.joints}
        out.update({("frame", f): self._constant(model.njoints + f, model.frames[f].placement, dl)
                    for f in self.frames})
        return out

    def _select(self, constants: Perturbed, rows: NDArray[np.intp]) -> Perturbed:
        offsets = {name: value[rows] for name, value in constants.offsets.items()}
        if self.planar:
            return Perturbed(self.planar.select(constants.placements, rows), offsets)
        return Perturbed({key: (R[rows] if R.ndim == 3 else R, p[rows] if p.ndim == 2 else p)
                          for key, (R, p) in constants.placements.items()}, offsets)

    def _placements(self, q: Floats, constants: dict, point_only: bool = False
                    ) -> tuple[dict[int, tuple[Floats, Floats]], dict[int, tuple[Floats, Floats]]]:
        """World placements (R, p) of the frames used and of the joints at the configurations q (N, nq); with
        ``point_only`` only the studied frame's and its joints' (spatial path)."""
        model = self.mech.model
        world: dict[int, tuple[Floats, Floats]] = {0: (np.eye(3), np.zeros(3))}
        for j in self.point_joints if point_only else self.joints:
            R, p = constants[("joint", j)]
            kind, axis = self.axes[j]
            value = _joint_value(model.joints[j], q)
            if kind == "revolute":
                R = _rotated(R, axis, value)
            else:
                p = p + _turn(R, axis) * value[:, None]
            world[j] = _compose(*world[model.parents[j]], R, p)
        n = len(q)
        frames = {}
        for f in [self.fid] if point_only else self.frames:
            R, p = _compose(*world[model.frames[f].parentJoint], *constants[("frame", f)])
            frames[f] = np.broadcast_to(R, (n, 3, 3)), np.broadcast_to(p, (n, 3))
        return frames, world

    def _quantities(self, q: Floats, constants: dict) -> tuple[dict, dict, dict, dict]:
        """Per closure frame (spatial path): the position (x, y, z) (N,) each, the angle about z of the slider
        frames, the linear Jacobian columns (∂x/∂q_d, ∂y/∂q_d, ∂z/∂q_d) (n_dep, N) each and ∂θ_z/∂q_d (n_dep, N),
        world-aligned: ω = R a, v = ω × (p_f − p_j) for a revolute joint, v = R a for a prismatic one."""
        frames, world = self._placements(q, constants)
        n = len(q)
        position, angle, linear, turn = {}, {}, {}, {}
        for name, f in self.frame_ids.items():
            R, p = frames[f]
            lin, ang = np.zeros((3, len(self.dep), n)), np.zeros((3, len(self.dep), n))
            for c, j in self.moved_by[f]:
                kind, axis = self.axes[j]
                Rj, pj = world[j]
                direction = np.broadcast_to(_turn(Rj, axis), (n, 3))
                if kind == "revolute":
                    ang[:, c] = direction.T
                    lin[:, c] = np.cross(direction, p - pj).T
                else:
                    lin[:, c] = direction.T
            position[name], linear[name], turn[name] = tuple(p.T), tuple(lin), ang[2]
            if name in self.angled:
                angle[name] = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        return position, angle, linear, turn

    def _evaluate(self, q: Floats, constants: Perturbed) -> tuple[Floats, Floats]:
        """(Φ (rows, N), ∂Φ/∂q_d (rows, n_dep, N)) of every closure at the configurations q (N, nq), samples last."""
        path = self.planar.quantities if self.planar else self._quantities
        position, angle, linear, turn = path(q, constants.placements)
        offsets = constants.offsets
        n, n_dep = len(q), len(self.dep)
        phi, J = np.empty((self.solver.system.nrows, n)), np.empty((self.solver.system.nrows, n_dep, n))
        r = 0
        for c in self.closures:
            if isinstance(c, Pin):
                for i in range(c.nrows):
                    np.subtract(position[c.a][i], position[c.b][i], out=phi[r + i])
                    np.subtract(linear[c.a][i], linear[c.b][i], out=J[r + i])
            elif isinstance(c, Slider):  # the point's offset r from the line frame along the normal of its x axis
                cos, sin = np.cos(angle[c.line]), np.sin(angle[c.line])
                rx, ry = (position[c.point][i] - position[c.line][i] for i in range(2))
                drx, dry = (linear[c.point][i] - linear[c.line][i] for i in range(2))
                phi[r] = cos * ry - sin * rx
                J[r] = cos * dry - sin * drx - (cos * rx + sin * ry) * turn[c.line]
                if c.lock_angle:
                    phi[r + 1] = _wrap(angle[c.point] - angle[c.line] - offsets.get(c.name, c.angle_offset))
                    J[r + 1] = turn[c.point] - turn[c.line]
            elif isinstance(c, OnCurve):
                x, y = position[c.point][0], position[c.point][1]
                phi[r] = y - _curve(c.f, x)
                J[r] = linear[c.point][1] - _curve(c.df, x) * linear[c.point][0]
            else:  # Gear
                a, b = c.columns
                phi[r] = q[:, b] - c.ratio * q[:, a] - offsets.get(c.name, c.offset)
                J[r] = 0.0
                for column, value in ((a, -c.ratio), (b, 1.0)):
                    if column in self.dep:
                        J[r, list(self.dep).index(column)] += value
            r += c.nrows
        return phi, J

    # --------------------------------------------------------------------------------------- Newton
    def _close(self, q: Floats, constants: Perturbed) -> tuple[Floats, NDArray[np.bool_]]:
        """The configurations (N, nq) with the closures solved for the dependent coordinates, and which closed."""
        phi, J = self._evaluate(q, constants)
        error = np.abs(phi).max(axis=0, initial=0.0)
        n = len(q)
        for _ in range(self.MAX_ITERATIONS):
            rows = np.flatnonzero(error >= TOLERANCE)  # NaN errors are failures: not iterated further
            if not len(rows):
                break
            local = _take(constants, rows, n, self._select)
            step = _solve_batch(_take(J, rows, n), -_take(phi, rows, n))
            t = np.ones(len(rows))
            pending = np.arange(len(rows))
            while len(pending):  # halve the step where it makes the residual grow
                at = _take(rows, pending, len(rows))
                trial = q.copy() if len(at) == n else q[at]
                move = _take(step, pending, len(rows))
                trial[:, self.dep] += (move if len(pending) == len(rows) else t[pending] * move).T  # t = 1 at first
                phi_t, J_t = self._evaluate(trial, _take(local, pending, len(rows), self._select))
                error_t = np.abs(phi_t).max(axis=0, initial=0.0)
                accept = (error_t < error[at]) | (t[pending] < 1e-3)
                if len(at) == n and accept.all():
                    q, phi, J, error = trial, phi_t, J_t, error_t
                else:
                    done = at[accept]
                    q[done], error[done] = trial[accept], error_t[accept]
                    phi[:, done], J[:, :, done] = phi_t[:, accept], J_t[:, :, accept]
                pending = pending[~accept]
                t[pending] /= 2
        closed = error < TOLERANCE
        rows = np.flatnonzero(closed & (error > 0))
        if len(rows) == n:  # one more step: the residual to rounding level
            q[:, self.dep] += _solve_batch(J, -phi).T
        elif len(rows):
            q[rows[:, None], self.dep] += _solve_batch(J[:, :, rows], -phi[:, rows]).T
        return q, closed

    def positions(self, q: ArrayLike, dl: ArrayLike, dq: ArrayLike) -> Floats:
        """Point positions (N, 3) (m) at the assembled nominal configuration ``q`` (nq,) with parameter errors
        ``dl`` (N, n_l) (m, rad) and errors of the actuated coordinates ``dq`` (N, n_act) (rad, m); NaN where the
        loops do not close."""
        q, dq = np.asarray(q, dtype=float), np.asarray(dq, dtype=float)
        dl = np.ascontiguousarray(dl, dtype=float)  # matrix products of a strided view do not go to BLAS
        if not len(dq):
            return np.zeros((0, 3))
        dq_dl, S = loop_derivatives(self.mech, self.solver, self.derivatives, q)
        # the actuated coordinates exactly at their values, the others predicted
        start = q + _rows_product(dl, dq_dl.T) + _rows_product(dq, S.T)
        constants = self._constants(dl)
        closed_q, closed = self._close(start, constants)
        if self.planar:
            out = self.planar.point(closed_q, constants.placements)
        else:
            out = self._placements(closed_q, constants.placements, point_only=True)[0][self.fid][1].copy()
        out[~closed] = np.nan
        return out


# ------------------------------------------------------------------------------------------------ per sample
def _frame_factors(twists: Floats, order: tuple[int, ...], dl: Floats) -> pin.SE3:
    out = pin.SE3.Identity()
    for k in order:
        out = out * pin.exp6(twists[k] * dl[k])
    return out


class PerturbedLoop(_Factors):
    """The position of ``frame`` for one sample of errors at a time, with Pinocchio on a perturbed copy of the
    model; closed loops are re-closed (Newton) with the actuated coordinates at their perturbed values."""

    def __init__(self, mech: Mechanism, frame: str, parameters: Sequence[str]) -> None:
        super().__init__(mech, parameters)
        self.copy = replace(mech, model=pin.Model(mech.model), closures=[copy.copy(c) for c in mech.closures])
        self.fid = mech.frame_id(frame)
        self.nominal = _placements(mech.model)
        self.solver = loop_solver(self.copy) if mech.closures else None
        self.data = self.copy.model.createData()

    def _perturb(self, dl: Floats) -> None:
        model = self.copy.model
        nj = model.njoints
        if self.order is None:
            return
        offsets = closure_offsets(self.mech.closures, self.derivatives, dl[None, :])
        for closure in self.copy.closures:
            if closure.name in offsets:
                setattr(closure, "angle_offset" if isinstance(closure, Slider) else "offset",
                        float(offsets[closure.name][0]))
        for j in range(1, nj):
            model.jointPlacements[j] = self.nominal[j] * _frame_factors(*self.twists(j), dl)
        for f in range(model.nframes):
            frame = model.frames[f]
            frame.placement = self.nominal[nj + f] * _frame_factors(*self.twists(nj + f), dl)
            model.frames[f] = frame

    def position(self, q: ArrayLike, dl: ArrayLike, dq: ArrayLike) -> Floats:
        """The point (3,) (m) at the assembled nominal ``q`` (nq,) with parameter errors ``dl`` (n_l,) and errors of
        the error coordinates ``dq`` (rad, m): a joint error vector (nv,) for a serial mechanism (q ⊕ dq), the
        actuated coordinates' errors (n_act,) of a closed loop.

        Raises:
            UnreachableError: if the loops do not close.
        """
        self._perturb(np.asarray(dl, dtype=float))
        q, dq = np.array(q, dtype=float), np.asarray(dq, dtype=float)
        if self.solver is None:
            q = pin.integrate(self.copy.model, q, dq)
        else:
            self.solver.system.states.refresh_fixed()
            q[self.solver.act] += dq
            q, _ = self.solver.newton(q, polish=True)
        pin.framesForwardKinematics(self.copy.model, self.data, q)
        return self.data.oMf[self.fid].translation.copy()

    def positions(self, q: ArrayLike, dl: ArrayLike, dq: ArrayLike) -> Floats:
        """:meth:`position` for N samples (N, 3); NaN where the loops do not close."""
        dl, dq = np.asarray(dl, dtype=float), np.asarray(dq, dtype=float)
        return sample_positions(lambda n: self.position(q, dl[n], dq[n]), len(dl))[0]


def sample_positions(evaluate: Callable[[int], Floats], count: int,
                     progress: Callable[[int, int], None] | None = None) -> tuple[Floats, int]:
    """Run ``evaluate(i)`` for i < count, collecting positions (count, 3); samples whose loops do not close are NaN
    and counted."""
    out = np.full((count, 3), np.nan)
    failures = 0
    step = max(1, count // 100)
    for i in range(count):
        try:
            out[i] = evaluate(i)
        except UnreachableError:
            failures += 1
        if progress and (i + 1) % step == 0:
            progress(i + 1, count)
    return out, failures


def perturbed_positions(mech: Mechanism, frame: str, parameters: Sequence[str]
                        ) -> PerturbedChain | PerturbedLoops | PerturbedLoop:
    """The fastest evaluator of the nonlinear model that knows ``mech``: :class:`PerturbedChain` (serial),
    :class:`PerturbedLoops` (closed loops), else :class:`PerturbedLoop` (one sample at a time)."""
    if not vectorizable(mech):
        return PerturbedLoop(mech, frame, parameters)
    return PerturbedLoops(mech, frame, parameters) if mech.closures else PerturbedChain(mech, frame, parameters)

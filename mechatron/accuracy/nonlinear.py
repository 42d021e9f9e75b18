r"""The position of a point with finite errors of the parameters and coordinates (the full nonlinear model of 8.2),
for Monte Carlo studies and for checking the first-order (8.4).

A parameter error Δl turns every constant placement M into M · Π_k exp(ξ_k Δl_k) (the twists of
:func:`~mechatron.accuracy.sensitivity.placement_derivatives`), the factors in the order the parameters enter the
placement: for DH tables (Tz(d) Tx(a) Rx(α), Rz(θ)) and URDF origins (translation, then yaw, pitch, roll) that
order makes it exact, and :func:`factor_order` finds it by comparing with the rebuilt model. Where a placement is
not a product of one-parameter exponentials (a linkage body frame that turns toward a moved pin) the product is
exact to first order and the second-order terms (products of two errors) are approximate; ``exact`` says which.

Two evaluators of the same model:

- :class:`PerturbedChain` — a serial chain, vectorized over samples in NumPy (SE(3) products of the placements,
  the factor exponentials and the joint motions; revolute and prismatic joints): millions of samples per second;
- :class:`PerturbedLoop` — any mechanism, one sample at a time with Pinocchio: a copy of the model takes the
  perturbed placements, the loops are closed again by Newton's method with the actuated coordinates at their
  perturbed values, and the point is read from the frame placement.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from ..errors import InputError, UnreachableError
from ..kinematics.loops import loop_solver
from ..model.mechanism import Mechanism
from .sensitivity import PlacementDerivatives, _placements, placement_derivatives

#: Parameters per placement up to which every factor order is tried.
MAX_PERMUTED = 5


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
    the mismatch is below 1e-4 of the second-order terms. Cached on the mechanism."""
    cache = mech.__dict__.setdefault("_factor_order", {})
    if derivatives.names in cache:
        return cache[derivatives.names]
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
    result = FactorOrder(tuple(order), tuple(exact))
    cache[derivatives.names] = result
    return result


# ------------------------------------------------------------------------------------------------ vectorized
#: Below this |angle| the sines and cosines come from their Taylor series (error < 1e-18).
SERIES_LIMIT = 0.01


def _cos_sin(angle: np.ndarray, offset: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of offset + angle; with small angles by series and the addition theorem (no trigonometric
    calls per sample)."""
    if np.abs(angle).max(initial=0.0) > SERIES_LIMIT:
        return np.cos(offset + angle), np.sin(offset + angle)
    a2 = angle * angle
    c = 1 - a2 / 2 * (1 - a2 / 12 * (1 - a2 / 30))
    s = angle * (1 - a2 / 6 * (1 - a2 / 20 * (1 - a2 / 42)))
    if offset == 0.0:
        return c, s
    c0, s0 = math.cos(offset), math.sin(offset)
    return c0 * c - s0 * s, s0 * c + c0 * s


def _skew(axis: np.ndarray) -> np.ndarray:
    return np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])


def _rotate(x: np.ndarray, axis: np.ndarray, angle: np.ndarray, offset: float = 0.0) -> np.ndarray:
    """Vectors x (N, 3) turned about the unit ``axis`` by offset + ``angle`` (N,) (Rodrigues, without matrices:
    x cos + (a × x) sin + a (a·x)(1 − cos))."""
    c, s = _cos_sin(angle, offset)
    along = x @ np.outer(axis, axis)
    return (x - along) * c[:, None] + (x @ _skew(axis).T) * s[:, None] + along


def _apply_exp(x: np.ndarray, xi: np.ndarray, t: np.ndarray) -> np.ndarray:
    """exp(ξ t) applied to the points x (N, 3), one twist ξ = [v; ω], N scalars t."""
    v, w = xi[:3], xi[3:]
    norm = np.linalg.norm(w)
    if norm < 1e-15:
        return x + t[:, None] * v
    axis = w / norm
    theta = norm * t
    # exp(ξ t) = (R, p) with p = (I + (1 − cos θ)/θ K + (θ − sin θ)/θ K²) v t, K = [axis]× (θ = |ω| t)
    if np.abs(theta).max(initial=0.0) > SERIES_LIMIT:
        safe = np.where(theta == 0, 1.0, theta)
        a = np.where(theta == 0, 0.0, (1 - np.cos(theta)) / safe)
        b = np.where(theta == 0, 0.0, (theta - np.sin(theta)) / safe)
    else:
        t2 = theta * theta
        a = theta / 2 * (1 - t2 / 12 * (1 - t2 / 30))
        b = t2 / 6 * (1 - t2 / 20 * (1 - t2 / 42))
    K = _skew(axis)
    Kv = K @ v
    p = t[:, None] * v + (a * t)[:, None] * Kv + (b * t)[:, None] * (K @ Kv)
    return _rotate(x, axis, theta) + p


def _joint_axis(joint) -> tuple[str, np.ndarray]:
    short = joint.shortname()
    unit = {"X": np.array([1.0, 0, 0]), "Y": np.array([0, 1.0, 0]), "Z": np.array([0, 0, 1.0])}
    if short in ("JointModelRX", "JointModelRY", "JointModelRZ"):
        return "revolute", unit[short[-1]]
    if short in ("JointModelPX", "JointModelPY", "JointModelPZ"):
        return "prismatic", unit[short[-1]]
    if short == "JointModelRevoluteUnaligned":
        return "revolute", np.asarray(joint.extract().axis, dtype=float)
    if short == "JointModelPrismaticUnaligned":
        return "prismatic", np.asarray(joint.extract().axis, dtype=float)
    raise InputError(f"a vectorized error model needs revolute and prismatic joints, not {short}")


class PerturbedChain:
    """The position of ``frame`` of a serial mechanism for N samples of parameter errors (N, n_l) and
    coordinate errors (N, nq) at one nominal configuration, vectorized over the samples: the point is carried from
    the frame back to the world through every factor (constant placement, parameter exponentials, joint motion),
    so only vectors are transformed."""

    def __init__(self, mech: Mechanism, frame: str, parameters: Sequence[str]) -> None:
        if mech.closures:
            raise InputError(f"{mech.name} is a closed loop: use PerturbedLoop")
        self.mech = mech
        self.fid = mech.frame_id(frame)
        self.derivatives = placement_derivatives(mech, parameters)
        self.order = factor_order(mech, self.derivatives) if len(parameters) else None
        model = mech.model
        frame = model.frames[self.fid]
        self.path = [j for j in model.supports[frame.parentJoint] if j != 0]
        self.axes = {j: _joint_axis(model.joints[j]) for j in self.path}

    @property
    def exact(self) -> bool:
        return self.order is None or self.order.all_exact

    def _factors(self, x: np.ndarray, placement: int, twists: np.ndarray, dl: np.ndarray) -> np.ndarray:
        """Π_k exp(ξ_k Δl_k) x for the placement's parameters in factor order (applied last factor first)."""
        if self.order is None:
            return x
        for k in reversed(self.order.order[placement]):
            x = _apply_exp(x, twists[k], dl[:, k])
        return x

    def positions(self, q: np.ndarray, dl: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """Point positions (N, 3) at the nominal configuration ``q`` (nq,) with errors ``dl`` (N, n_l) and ``dq``
        (N, nq)."""
        model, d = self.mech.model, self.derivatives
        x = np.zeros((len(dl), 3))
        x = self._factors(x, model.njoints + self.fid, d.frames[:, self.fid], dl)
        M = model.frames[self.fid].placement
        x = x @ M.rotation.T + M.translation
        for j in reversed(self.path):
            kind, axis = self.axes[j]
            index = model.joints[j].idx_q
            if kind == "revolute":
                x = _rotate(x, axis, dq[:, index], float(q[index]))
            else:
                x = x + (q[index] + dq[:, index])[:, None] * axis
            x = self._factors(x, j, d.joints[:, j], dl)
            M = model.jointPlacements[j]
            x = x @ M.rotation.T + M.translation
        return x


def _frame_factors(twists: np.ndarray, order: tuple[int, ...], dl: np.ndarray) -> pin.SE3:
    out = pin.SE3.Identity()
    for k in order:
        out = out * pin.exp6(twists[k] * dl[k])
    return out


class PerturbedLoop:
    """The position of ``frame`` for one sample of errors at a time, with Pinocchio on a perturbed copy of the
    model; closed loops are re-closed (Newton) with the actuated coordinates at their perturbed values."""

    def __init__(self, mech: Mechanism, frame: str, parameters: Sequence[str]) -> None:
        self.mech = mech
        self.derivatives = placement_derivatives(mech, parameters)
        self.order = factor_order(mech, self.derivatives) if len(parameters) else None
        self.copy = replace(mech, model=pin.Model(mech.model))
        self.fid = mech.frame_id(frame)
        self.nominal = _placements(mech.model)
        self.solver = loop_solver(self.copy) if mech.closures else None
        self.data = self.copy.model.createData()

    @property
    def exact(self) -> bool:
        return self.order is None or self.order.all_exact

    def _perturb(self, dl: np.ndarray) -> None:
        model, d = self.copy.model, self.derivatives
        nj = model.njoints
        if self.order is None:
            return
        for j in range(1, nj):
            model.jointPlacements[j] = self.nominal[j] * _frame_factors(d.joints[:, j], self.order.order[j], dl)
        for f in range(model.nframes):
            frame = model.frames[f]
            frame.placement = self.nominal[nj + f] * _frame_factors(d.frames[:, f], self.order.order[nj + f], dl)
            model.frames[f] = frame

    def position(self, q: np.ndarray, dl: np.ndarray, dq_actuated: np.ndarray) -> np.ndarray:
        """The point (3,) at the assembled nominal ``q`` with parameter errors ``dl`` and errors of the error
        coordinates ``dq_actuated`` (a full (nq,) vector of joint errors for a serial mechanism, the actuated ones of
        a closed loop)."""
        self._perturb(dl)
        q = np.array(q, dtype=float)
        if self.solver is None:
            q = q + dq_actuated
        else:
            self.solver.system.states.refresh_fixed()
            q[self.solver.act] += dq_actuated
            q, _ = self.solver.newton(q, polish=True)
        pin.framesForwardKinematics(self.copy.model, self.data, q)
        return self.data.oMf[self.fid].translation.copy()


def sample_positions(evaluate: Callable[[int], np.ndarray], count: int,
                     progress: Callable[[int, int], None] | None = None) -> tuple[np.ndarray, int]:
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

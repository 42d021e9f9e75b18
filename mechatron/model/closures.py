r"""Closure constraints of closed kinematic loops, evaluated from Pinocchio.

A closed-loop mechanism is a Pinocchio tree plus closures Φ(q) = 0. Differentiating twice along a motion,

.. math::

    J(q)\,\dot q = 0, \qquad J(q)\,\ddot q + \dot J(q,\dot q)\,\dot q = 0,

so every closure provides its residual Φ, its Jacobian J = ∂Φ/∂q and its drift term ``drift`` = J̇ q̇ (the second time
derivative of Φ at q̈ = 0). All three come from Pinocchio frame placements, frame Jacobians and classical frame
accelerations computed at q̈ = 0 for the frames the closures use (:class:`FrameStates`). Mechanisms are planar in the
world xy plane unless a closure says otherwise: a pin then has the two in-plane rows only.

Every closure's ``residual``, ``jacobian`` and ``drift`` broadcast over leading sample axes: given the
:class:`~mechatron.model.batched.BatchedStates` of N configurations (arrays with a leading axis N) they return
(N, nrows), (N, nrows, nv) and (N, nrows) — the same numbers as N calls with :class:`FrameStates`.

Closures:

- :class:`Pin` — two frame points coincide (a revolute pair that closes a loop);
- :class:`Slider` — a frame point stays on a line fixed to a body (a higher pair or a massless block), optionally with
  the two bodies' angles locked (a full prismatic pair);
- :class:`OnCurve` — a frame point stays on a curve y = f(x) in the world (the grab's jaw tip on the scooping curve).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from .loads import Load

LWA = pin.LOCAL_WORLD_ALIGNED


class FrameStates:
    """Positions, rotations, Jacobians, twists and q̈ = 0 accelerations of a fixed list of frames.

    ``update(q)`` fills positions, angles and Jacobians; ``update_motion(q, v)`` fills twists and the accelerations at
    q̈ = 0 (classical linear acceleration, angular acceleration), i.e. J̇ q̇ of every frame.
    """

    def __init__(self, model: pin.Model, frame_ids: list[int]) -> None:
        self.model = model
        self.data = model.createData()
        self.frame_ids = frame_ids
        n = len(frame_ids)
        self.homogeneous = np.tile(np.eye(4), (n, 1, 1))
        self.jacobian = np.zeros((n, 6, model.nv))
        self.velocity = np.zeros((n, 6))
        self.acceleration0 = np.zeros((n, 6))
        self._zero = np.zeros(model.nv)
        self.q = np.zeros(model.nq)
        # frames on the ground never move: their placement is computed once, their Jacobian and motion stay zero
        self._moving = [(k, fid) for k, fid in enumerate(frame_ids) if model.frames[fid].parentJoint != 0]
        pin.framesForwardKinematics(model, self.data, pin.neutral(model))
        for k, fid in enumerate(frame_ids):
            if model.frames[fid].parentJoint == 0:
                self.homogeneous[k] = self.data.oMf[fid].homogeneous
        self.position = self.homogeneous[:, :3, 3]  # a view: follows every update
        self.angle = np.arctan2(self.homogeneous[:, 1, 0], self.homogeneous[:, 0, 0])

    def refresh_fixed(self) -> None:
        """Recompute the placements of the frames on the ground (after the model's placements changed)."""
        pin.framesForwardKinematics(self.model, self.data, pin.neutral(self.model))
        for k, fid in enumerate(self.frame_ids):
            if self.model.frames[fid].parentJoint == 0:
                self.homogeneous[k] = self.data.oMf[fid].homogeneous

    def update(self, q: np.ndarray) -> None:
        model, data = self.model, self.data
        self.q = q
        pin.computeJointJacobians(model, data, q)
        for k, fid in self._moving:
            self.homogeneous[k] = pin.updateFramePlacement(model, data, fid).homogeneous
            self.jacobian[k] = pin.getFrameJacobian(model, data, fid, LWA)
        np.arctan2(self.homogeneous[:, 1, 0], self.homogeneous[:, 0, 0], out=self.angle)

    def restore(self, homogeneous: np.ndarray, jacobian: np.ndarray) -> None:
        """Put back placements and Jacobians saved from an earlier :meth:`update`."""
        self.homogeneous[:] = homogeneous
        self.jacobian[:] = jacobian
        np.arctan2(self.homogeneous[:, 1, 0], self.homogeneous[:, 0, 0], out=self.angle)

    def update_motion(self, q: np.ndarray, v: np.ndarray) -> None:
        """Twists J q̇ and the classical accelerations at q̈ = 0, after :meth:`update` at the same q."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v, self._zero)
        for k, fid in self._moving:
            self.acceleration0[k] = pin.getFrameClassicalAcceleration(model, data, fid, LWA).vector
        np.matmul(self.jacobian, v, out=self.velocity)


@dataclass
class Closure(ABC):
    """Base class: a closure uses some frames (by name) and contributes ``nrows`` equations; each kind gives its
    residual, Jacobian and drift."""

    name: str
    frames: tuple[str, ...] = field(init=False, default=())
    nrows: int = field(init=False, default=0)

    def bind(self, index: dict[str, int]) -> None:
        """Remember where this closure's frames sit in the :class:`FrameStates` arrays."""
        self._k = [index[f] for f in self.frames]

    @abstractmethod
    def residual(self, s: FrameStates) -> np.ndarray: ...

    @abstractmethod
    def jacobian(self, s: FrameStates) -> np.ndarray: ...

    @abstractmethod
    def drift(self, s: FrameStates) -> np.ndarray: ...

    def evaluate_one(self, s: FrameStates) -> tuple[np.ndarray, np.ndarray]:
        """(residual, Jacobian) at one configuration (:class:`FrameStates`)."""
        return np.atleast_1d(self.residual(s)), np.atleast_2d(self.jacobian(s))

    @abstractmethod
    def loads(self, s: FrameStates, multipliers: np.ndarray) -> list[Load]:
        """The closure's generalized force Jᵀλ for its ``multipliers`` λ (its rows of the KKT solution) as forces
        (N) and moments (N·m, world axes) on the bodies it joins, at the frames of :meth:`~FrameStates.update`."""

    def describe(self) -> str:
        return self.name


@dataclass
class Pin(Closure):
    """Frame points ``a`` and ``b`` coincide: Φ = p_a − p_b (x, y rows; also z when ``planar`` is false)."""

    a: str = ""
    b: str = ""
    planar: bool = True

    def __post_init__(self) -> None:
        self.frames = (self.a, self.b)
        self.nrows = 2 if self.planar else 3
        self._rows = slice(0, self.nrows)

    def residual(self, s: FrameStates) -> np.ndarray:
        ka, kb = self._k
        return (s.position[..., ka, :] - s.position[..., kb, :])[..., self._rows]

    def jacobian(self, s: FrameStates) -> np.ndarray:
        ka, kb = self._k
        return (s.jacobian[..., ka, :, :] - s.jacobian[..., kb, :, :])[..., self._rows, :]

    def drift(self, s: FrameStates) -> np.ndarray:
        ka, kb = self._k
        return (s.acceleration0[..., ka, :] - s.acceleration0[..., kb, :])[..., self._rows]

    def loads(self, s: FrameStates, multipliers: np.ndarray) -> list[Load]:
        """λ on the body of ``a``, −λ on the body of ``b``: the pin force (N) that ``a`` receives from ``b``."""
        force = np.zeros(3)
        force[:self.nrows] = multipliers
        return [Load(self.a, force), Load(self.b, -force)]

    def describe(self) -> str:
        return f"pin {self.a} = {self.b}"


@dataclass
class Slider(Closure):
    """Frame point ``point`` stays on the line through the origin of frame ``line`` along that frame's x axis
    (planar). With ``lock_angle`` the frame ``point`` also keeps its angle to the line frame (a prismatic pair
    between two bodies): Φ = [n·(p − o), θ_point − θ_line − θ₀].

    With d the line direction and n = e_z × d its normal, both turning with the line body at ω:
    dΦ₁/dt = n·(ṗ − ȯ) − ω d·(p − o), and at q̈ = 0
    d²Φ₁/dt² = n·(p̈ − ö) − 2ω d·(ṗ − ȯ) − (ω̇ d + ω² n)·(p − o).
    """

    point: str = ""
    line: str = ""
    lock_angle: bool = False
    angle_offset: float = 0.0

    def __post_init__(self) -> None:
        self.frames = (self.point, self.line)
        self.nrows = 2 if self.lock_angle else 1

    def _geometry(self, s: FrameStates):
        kp, kl = self._k
        theta = s.angle[..., kl]
        d = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        n = np.stack([-d[..., 1], d[..., 0]], axis=-1)
        r = (s.position[..., kp, :] - s.position[..., kl, :])[..., :2]
        return kp, kl, d, n, r

    def residual(self, s: FrameStates) -> np.ndarray:
        if s.position.ndim == 2:  # one configuration: in floats (the Newton iterations of a single sample)
            return self._one(s)[0]
        kp, kl, d, n, r = self._geometry(s)
        rows = [_dot(n, r)]
        if self.lock_angle:
            rows.append(_wrap(s.angle[..., kp] - s.angle[..., kl] - self.angle_offset))
        return np.stack(rows, axis=-1)

    def evaluate_one(self, s: FrameStates) -> tuple[np.ndarray, np.ndarray]:
        return self._one(s)

    def _one(self, s: FrameStates) -> tuple[np.ndarray, np.ndarray]:
        """(Φ, J) of one configuration, the formulas of the class docstring in floats."""
        kp, kl = self._k
        theta = float(s.angle[kl])
        c, sn = math.cos(theta), math.sin(theta)
        (px, py), (ox, oy) = s.position[kp, :2].tolist(), s.position[kl, :2].tolist()
        rx, ry = px - ox, py - oy
        Jp, Jl = s.jacobian[kp], s.jacobian[kl]
        residual = [c * ry - sn * rx]
        rows = [c * (Jp[1] - Jl[1]) - sn * (Jp[0] - Jl[0]) - (c * rx + sn * ry) * Jl[5]]
        if self.lock_angle:
            residual.append(float(_wrap(s.angle[kp] - theta - self.angle_offset)))
            rows.append(Jp[5] - Jl[5])
        return np.array(residual), np.array(rows)

    def jacobian(self, s: FrameStates) -> np.ndarray:
        if s.position.ndim == 2:
            return self._one(s)[1]
        kp, kl, d, n, r = self._geometry(s)
        Jp, Jl = s.jacobian[..., kp, :, :], s.jacobian[..., kl, :, :]
        normal = (n[..., None, :] @ (Jp[..., :2, :] - Jl[..., :2, :]))[..., 0, :]  # n·(J_p − J_l), rows x and y
        rows = [normal - _dot(d, r)[..., None] * Jl[..., 5, :]]
        if self.lock_angle:
            rows.append(Jp[..., 5, :] - Jl[..., 5, :])
        return np.stack(rows, axis=-2)

    def drift(self, s: FrameStates) -> np.ndarray:
        kp, kl, d, n, r = self._geometry(s)
        w = s.velocity[..., kl, 5, None]
        wdot = s.acceleration0[..., kl, 5, None]
        rdot = (s.velocity[..., kp, :] - s.velocity[..., kl, :])[..., :2]
        rddot = (s.acceleration0[..., kp, :] - s.acceleration0[..., kl, :])[..., :2]
        rows = [_dot(n, rddot) - 2 * w[..., 0] * _dot(d, rdot) - _dot(wdot * d + w * w * n, r)]
        if self.lock_angle:
            rows.append(s.acceleration0[..., kp, 5] - s.acceleration0[..., kl, 5])
        return np.stack(rows, axis=-1)

    def loads(self, s: FrameStates, multipliers: np.ndarray) -> list[Load]:
        """λ₁·n (N) on the body of ``point`` at the point, −λ₁·n on the line's body at the same point (a force at
        the line frame's origin o with the moment −λ₁ d·(p − o) about z); with the angle locked, the moments λ₂ and
        −λ₂ (N·m) about z."""
        _, _, d, n, r = self._geometry(s)
        normal = multipliers[0] * np.array([n[0], n[1], 0.0])
        out = [Load(self.point, normal), Load(self.line, -normal, (0.0, 0.0, -multipliers[0] * float(_dot(d, r))))]
        if self.lock_angle:
            out += [Load(self.point, np.zeros(3), (0.0, 0.0, multipliers[1])),
                    Load(self.line, np.zeros(3), (0.0, 0.0, -multipliers[1]))]
        return out

    def describe(self) -> str:
        return f"slider {self.point} on {self.line}" + (" (angle locked)" if self.lock_angle else "")


@dataclass
class OnCurve(Closure):
    """Frame point ``point`` stays on the world curve y = f(x): Φ = y − f(x).

    dΦ/dt = ẏ − f′(x) ẋ and, at q̈ = 0, d²Φ/dt² = ÿ − f′(x) ẍ − f″(x) ẋ².
    Args:
        f, df, d2f: the curve y = f(x) and its first and second derivatives (SI units).
    """

    point: str = ""
    f: Callable[[float], float] = field(default=lambda x: 0.0, repr=False)
    df: Callable[[float], float] = field(default=lambda x: 0.0, repr=False)
    d2f: Callable[[float], float] = field(default=lambda x: 0.0, repr=False)
    label: str = "y = f(x)"
    #: The curve as a piecewise polynomial, if it is one (a ``scipy.interpolate.PPoly``: breakpoints ``x``,
    #: coefficients ``c`` highest power first): what a symbolic form of the closure needs.
    spline: object | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        self.frames = (self.point,)
        self.nrows = 1

    def residual(self, s: FrameStates) -> np.ndarray:
        p = s.position[..., self._k[0], :]
        return (p[..., 1] - _curve(self.f, p[..., 0]))[..., None]

    def jacobian(self, s: FrameStates) -> np.ndarray:
        J = s.jacobian[..., self._k[0], :, :]
        x = s.position[..., self._k[0], 0]
        return (J[..., 1, :] - _curve(self.df, x)[..., None] * J[..., 0, :])[..., None, :]

    def drift(self, s: FrameStates) -> np.ndarray:
        k = self._k[0]
        x = s.position[..., k, 0]
        xdot = s.velocity[..., k, 0]
        a = s.acceleration0[..., k, :]
        return (a[..., 1] - _curve(self.df, x) * a[..., 0] - _curve(self.d2f, x) * xdot**2)[..., None]

    def loads(self, s: FrameStates, multipliers: np.ndarray) -> list[Load]:
        """The curve's reaction λ·(−f′(x), 1) (N) at the point: normal to the curve."""
        x = s.position[self._k[0]][0]
        return [Load(self.point, multipliers[0] * np.array([-self.df(x), 1.0, 0.0]))]

    def describe(self) -> str:
        return f"{self.point} on {self.label}"


@dataclass
class Gear(Closure):
    """A transmission between two joint coordinates (a gear pair, a belt): Φ = q_b − ratio·q_a − offset.

    It needs frames only to find the joints: ``a`` and ``b`` name the BODY frames of the two joints' bodies.
    The Jacobian row is constant and the drift is zero.
    """

    a: str = ""
    b: str = ""
    ratio: float = 1.0
    offset: float = 0.0
    columns: tuple[int, int] = (0, 0)  # velocity indices of the joints, set by :func:`bind_gear`

    def __post_init__(self) -> None:
        self.frames = ()
        self.nrows = 1

    def residual(self, s: FrameStates) -> np.ndarray:
        q = s.q
        return (q[..., self.columns[1]] - self.ratio * q[..., self.columns[0]] - self.offset)[..., None]

    def jacobian(self, s: FrameStates) -> np.ndarray:
        row = np.zeros((1, s.q.shape[-1]))
        row[0, self.columns[0]] -= self.ratio
        row[0, self.columns[1]] += 1.0
        return np.broadcast_to(row, (*s.q.shape[:-1], 1, s.q.shape[-1])).copy()

    def drift(self, s: FrameStates) -> np.ndarray:
        return np.zeros((*s.q.shape[:-1], 1))

    def loads(self, s: FrameStates, multipliers: np.ndarray) -> list[Load]:
        """None: a gear's Jᵀλ is the joint torques −u·λ and λ on the two coordinates, which the joints' transmitted
        moments carry like an actuator's torque."""
        return []

    def describe(self) -> str:
        return f"gear {self.b} = {self.ratio:g}·{self.a}"


def _wrap(angle: np.ndarray) -> np.ndarray:
    """Angle (rad) wrapped to [−π, π] (an array or a float)."""
    return angle - 2 * math.pi * np.round(angle / (2 * math.pi))


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a · b along the last axis, broadcasting the others."""
    return np.sum(a * b, axis=-1)


def _curve(function: Callable, x: np.ndarray) -> np.ndarray:
    """``function`` (a curve y(x) or a derivative) at a float or an array of x (m): a function that takes floats
    only is called once per element."""
    if np.ndim(x) == 0:
        return np.asarray(function(x), dtype=float)
    try:
        y = np.asarray(function(x), dtype=float)
    except (TypeError, ValueError):
        y = None
    if y is None or y.shape != np.shape(x):
        y = np.array([function(value) for value in np.ravel(x)], dtype=float).reshape(np.shape(x))
    return y


class ClosureSystem:
    """All closures of a mechanism, evaluated together: Φ(q), J(q) and the drift J̇ q̇."""

    def __init__(self, model: pin.Model, closures: list[Closure], frame_id: Callable[[str], int],
                 extra_frames: tuple[str, ...] | list[str] = ()) -> None:
        self.closures = list(closures)
        names: list[str] = []
        for closure in self.closures:
            names.extend(f for f in closure.frames if f not in names)
        names.extend(f for f in extra_frames if f not in names)
        self.frame_names = names
        self.states = FrameStates(model, [frame_id(n) for n in names])
        self.index = {n: i for i, n in enumerate(names)}
        for closure in self.closures:
            closure.bind(self.index)
            if isinstance(closure, Gear):
                closure.columns = tuple(model.joints[model.frames[frame_id(f)].parentJoint].idx_v
                                        for f in (closure.a, closure.b))
        self.nrows = sum(c.nrows for c in self.closures)
        self.nv = model.nv
        self._empty = (np.zeros(0), np.zeros((0, self.nv)))
        # planar pins, the common case, are evaluated together with one gather per quantity; their rows come first
        self._pins = [c for c in self.closures if isinstance(c, Pin) and c.planar]
        self._others = [c for c in self.closures if c not in self._pins]
        self.closures = self._pins + self._others
        self._a = np.array([self.index[c.a] for c in self._pins], dtype=int)
        self._b = np.array([self.index[c.b] for c in self._pins], dtype=int)

    def __bool__(self) -> bool:
        return bool(self.closures)

    def batched(self):
        """A :class:`~mechatron.model.batched.BatchedFrames` of this system's frames (their states for N
        configurations at once go to :meth:`stack` and :meth:`stack_drift`).

        Raises:
            NotImplementedError: if the model has joints the batched kinematics does not know.
        """
        from .batched import batched_frames

        return batched_frames(self.states.model, self.states.frame_ids)

    def evaluate(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(Φ(q), J(q)); also fills the frame states (positions, Jacobians) at q."""
        if self.frame_names:
            self.states.update(q)
        else:
            self.states.q = q  # gear closures read the coordinates themselves
        if not self.closures:
            return self._empty
        return self.stack(self.states)

    def close(self, q: np.ndarray, free: list[int], tolerance: float, max_iterations: int = 50
              ) -> tuple[np.ndarray, float]:
        """The configuration nearest ``q`` that closes the loops, moving only the coordinates ``free``: minimum-norm
        Gauss–Newton steps q_f ← q_f − t J_f⁺ Φ(q) (t = 1, halved while the step does not lower |Φ|), until
        max |Φ| < ``tolerance``. Returns (q, max |Φ|) — the caller decides whether what is left is closed."""
        q = np.array(q, dtype=float)
        phi, J = self.evaluate(q)
        norm = float(np.linalg.norm(phi))
        for _ in range(max_iterations):
            if np.abs(phi).max(initial=0.0) < tolerance or not free:
                break
            step = np.linalg.lstsq(J[:, free], phi, rcond=None)[0]
            for _ in range(30):
                trial = q.copy()
                trial[free] -= step
                trial_phi, trial_J = self.evaluate(trial)
                trial_norm = float(np.linalg.norm(trial_phi))
                if trial_norm < norm or not np.isfinite(norm):
                    break
                step = step / 2
            else:
                break
            q, phi, J, norm = trial, trial_phi, trial_J, trial_norm
        self.evaluate(q)
        return q, float(np.abs(phi).max(initial=0.0))

    def stack(self, s: FrameStates) -> tuple[np.ndarray, np.ndarray]:
        """(Φ, J) from frame states ``s``: one configuration (:class:`FrameStates`) or N at once
        (:class:`~mechatron.model.batched.BatchedStates`, then Φ is (N, nrows) and J (N, nrows, nv))."""
        lead = s.position.shape[:-2]
        phi = (s.position[..., self._a, :2] - s.position[..., self._b, :2]).reshape(*lead, -1)
        J = (s.jacobian[..., self._a, :2, :] - s.jacobian[..., self._b, :2, :]).reshape(*lead, -1, self.nv)
        if self._others and not lead:  # one configuration
            parts = [c.evaluate_one(s) for c in self._others]
            return np.concatenate([phi, *(p[0] for p in parts)]), np.concatenate([J, *(p[1] for p in parts)])
        if self._others:
            phi = np.concatenate([phi, *(c.residual(s) for c in self._others)], axis=-1)
            J = np.concatenate([J, *(c.jacobian(s) for c in self._others)], axis=-2)
        return phi, J

    def jacobian_for(self, frame_motions: np.ndarray) -> np.ndarray:
        """∂Φ/∂x for other variables x that move the closures' frames, after :meth:`evaluate` at the same q:
        ``frame_motions`` (n_frames, 6, n_x) gives each frame's world-aligned twist per unit of each x (instead of
        the joint Jacobians). Gear rows, which do not depend on frames, are zero."""
        s = self.states
        width = frame_motions.shape[2]
        saved = s.jacobian
        s.jacobian = frame_motions
        try:
            rows = [np.zeros((1, width)) if isinstance(c, Gear) else np.atleast_2d(c.jacobian(s))
                    for c in self.closures]
        finally:
            s.jacobian = saved
        return np.vstack(rows) if rows else np.zeros((0, width))

    def constants_jacobian(self, constants: Mapping[str, Mapping[str, np.ndarray]], width: int) -> np.ndarray:
        """∂Φ/∂x (nrows, width) through the closures' constants that other variables x move: ``constants`` is
        {closure name: {"angle_offset" or "offset": ∂c/∂x (width,)}}; a locked slider's angle row and a gear's row
        are Φ = … − c, so they take −∂c/∂x."""
        out = np.zeros((self.nrows, width))
        row = 0
        for closure in self.closures:
            moved = constants.get(closure.name, {})
            if isinstance(closure, Slider) and closure.lock_angle and "angle_offset" in moved:
                out[row + 1] = -np.asarray(moved["angle_offset"])
            elif isinstance(closure, Gear) and "offset" in moved:
                out[row] = -np.asarray(moved["offset"])
            row += closure.nrows
        return out

    def drift(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """J̇(q, q̇) q̇, after :meth:`evaluate` at the same q; also fills the frame velocities and accelerations at
        q̈ = 0."""
        if self.frame_names:
            self.states.update_motion(q, v)
        if not self.closures:
            return self._empty[0]
        return self.stack_drift(self.states)

    def stack_drift(self, s: FrameStates) -> np.ndarray:
        """J̇ q̇ from frame states ``s`` with their motion: one configuration or N at once ((N, nrows))."""
        lead = s.position.shape[:-2]
        drift = (s.acceleration0[..., self._a, :2] - s.acceleration0[..., self._b, :2]).reshape(*lead, -1)
        if self._others:
            drift = np.concatenate([drift, *(c.drift(s) for c in self._others)], axis=-1)
        return drift

    def row_labels(self) -> list[str]:
        labels: list[str] = []
        for closure in self.closures:
            labels.extend(f"{closure.describe()} [{i}]" for i in range(closure.nrows))
        return labels

r"""Frame placements, Jacobians and q̈ = 0 accelerations of N configurations at once, in NumPy.

:class:`~mechatron.model.closures.FrameStates` asks Pinocchio for one configuration at a time; a sweep of a closed loop
needs the same few frames at thousands of configurations. :class:`BatchedFrames` runs the forward recursion along the
joint tree with every quantity an array over the N samples (the joints loop in Python, the samples in NumPy). It
supports the joints of planar and spatial linkages: revolute about a fixed axis (RX, RY, RZ, RevoluteUnaligned) and
prismatic along one (PX, PY, PZ, PrismaticUnaligned); any other joint raises :class:`NotImplementedError`, and the
caller falls back to Pinocchio.

For joint i with parent λ, joint placement (R₀, p₀) in λ and unit axis â (in the joint frame), in world axes:

.. math::

    z_i = R_λ R_0 â, \qquad
    R_i = R_λ R_0 \,\mathrm{Rot}(â, q_i) \;(\text{revolute}) \;\text{or}\; R_λ R_0 \;(\text{prismatic}), \qquad
    p_i = p_λ + R_λ p_0 \;[+\, z_i q_i \;\text{prismatic}],

with Rot(â, q) = cos q I + sin q [â]× + (1 − cos q) â âᵀ (Rodrigues). Velocities and classical accelerations of the
joint origins at q̈ = 0 follow with r = p_i − p_λ:

.. math::

    ω_i = ω_λ + z_i \dot q_i, \quad α_i = α_λ + ω_λ × z_i \dot q_i \qquad (\text{revolute; prismatic: } ω_i = ω_λ,
    α_i = α_λ),

    v_i = v_λ + ω_λ × r \;[+\, z_i \dot q_i], \qquad
    a_i = a_λ + α_λ × r + ω_λ × (ω_λ × r) \;[+\, 2 ω_λ × z_i \dot q_i] \quad (\text{the brackets: prismatic}),

and a frame at r_f = p_f − p_i on joint i moves with v_f = v_i + ω_i × r_f, a_f = a_i + α_i × r_f + ω_i × (ω_i × r_f).
Given joint accelerations q̈ the terms z_i q̈_i join α_i (revolute) or a_i (prismatic). The LOCAL_WORLD_ALIGNED
Jacobian column of a joint j supporting frame f is [z_j × (p_f − p_j); z_j] (revolute) or [z_j; 0] (prismatic).
Units: m, rad, s throughout; twists and accelerations are (linear; angular) as in Pinocchio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

#: Joint models the recursion knows: the axis is read from the joint's motion subspace.
REVOLUTE = ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned")
PRISMATIC = ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned")


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b along the last axis (length 3), broadcasting the others."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def _skew(a: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


@dataclass
class BatchedStates:
    """The frames of :class:`BatchedFrames` at N configurations, with the attribute names of
    :class:`~mechatron.model.closures.FrameStates` and a leading sample axis: ``q`` (N, nq), ``position`` (N, F, 3),
    ``angle`` (N, F) (about z, rad; wrapped to (−π, π] or, in a planar tree, continuous), ``jacobian``
    (N, F, 6, nv), :attr:`rotation` (N, F, 3, 3); after
    :meth:`BatchedFrames.motion` also ``velocity`` and ``acceleration0`` (N, F, 6). ``joints`` holds what the
    motion needs of the joints (their origins and axes)."""

    q: np.ndarray
    position: np.ndarray
    angle: np.ndarray
    jacobian: np.ndarray
    joints: tuple
    frame_rotation: np.ndarray | None = None
    velocity: np.ndarray | None = None
    acceleration0: np.ndarray | None = None

    @property
    def rotation(self) -> np.ndarray:
        """The frames' rotation matrices (N, F, 3, 3) (about z from ``angle`` for a planar tree)."""
        if self.frame_rotation is None:
            c, s = np.cos(self.angle), np.sin(self.angle)
            R = np.zeros((*self.angle.shape, 3, 3))
            R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1], R[..., 2, 2] = c, -s, s, c, 1.0
            self.frame_rotation = R
        return self.frame_rotation


class BatchedFrames:
    """Placements, LOCAL_WORLD_ALIGNED Jacobians and classical accelerations of the frames ``frame_ids`` of
    ``model`` for N configurations at once (see the module docstring for the recursion).

    Raises:
        NotImplementedError: if the model has a joint other than revolute or prismatic about one fixed axis.
    """

    def __init__(self, model: pin.Model, frame_ids: list[int]) -> None:
        data = model.createData()
        pin.forwardKinematics(model, data, pin.neutral(model))
        self.nv = model.nv
        self.parent = [int(p) for p in model.parents]
        self.placement = [(m.rotation.copy(), m.translation.copy()) for m in model.jointPlacements]
        self.revolute = np.zeros(model.njoints, dtype=bool)
        self.axis = np.zeros((model.njoints, 3))
        self.column = np.zeros(model.njoints, dtype=int)
        for i in range(1, model.njoints):
            kind = model.joints[i].shortname()
            if kind not in REVOLUTE + PRISMATIC:
                raise NotImplementedError(f"batched kinematics: joint {model.names[i]} is a {kind}")
            self.revolute[i] = kind in REVOLUTE
            motion = np.asarray(data.joints[i].S).ravel()  # (linear; angular) per unit q̇ in the joint frame
            self.axis[i] = motion[3:] if self.revolute[i] else motion[:3]
            self.column[i] = model.joints[i].idx_v
        # Rodrigues: R₀ Rot(â, q) = cos q R₀ + sin q R₀[â]× + (1 − cos q) R₀ â âᵀ
        self.skewed = [R @ _skew(a) for (R, _), a in zip(self.placement, self.axis)]
        self.along = [R @ np.outer(a, a) for (R, _), a in zip(self.placement, self.axis)]
        frames = [model.frames[f] for f in frame_ids]
        self.frame_joint = np.array([f.parentJoint for f in frames], dtype=int)
        self.frame_rotation = np.array([f.placement.rotation for f in frames]).reshape(-1, 3, 3)
        self.frame_offset = np.array([f.placement.translation for f in frames]).reshape(-1, 3)
        # support[f, j]: joint j moves frame f (j on the path from the root to the frame's joint)
        self.support = np.zeros((len(frames), model.njoints), dtype=bool)
        for k, i in enumerate(self.frame_joint):
            while i > 0:
                self.support[k, i] = True
                i = self.parent[i]

    def placements(self, Q: np.ndarray, jacobians: bool | int = True) -> BatchedStates:
        """Frame positions (m), rotations, angles about z (rad) and Jacobians at the N configurations ``Q`` (N, nq):
        ``jacobians`` True for every frame, False for none, a number m for the first m frames (``jacobian`` is then
        (N, m, 6, nv))."""
        Q = np.asarray(Q, dtype=float)
        n, nj = len(Q), len(self.parent)
        R = np.empty((n, nj, 3, 3))
        p = np.zeros((n, nj, 3))
        z = np.zeros((n, nj, 3))
        R[:, 0] = np.eye(3)
        for i in range(1, nj):
            lam = self.parent[i]
            R0, p0 = self.placement[i]
            q = Q[:, self.column[i], None, None]
            Rl = R[:, lam]
            p[:, i] = p[:, lam] + Rl @ p0
            z[:, i] = Rl @ (R0 @ self.axis[i])
            if self.revolute[i]:
                c, s = np.cos(q), np.sin(q)
                R[:, i] = Rl @ (c * R0 + s * self.skewed[i] + (1.0 - c) * self.along[i])
            else:
                R[:, i] = Rl @ R0
                p[:, i] += z[:, i] * q[:, 0]
        Rj = R[:, self.frame_joint]
        position = p[:, self.frame_joint] + (Rj @ self.frame_offset[..., None])[..., 0]
        rotation = Rj @ self.frame_rotation
        angle = np.arctan2(rotation[..., 1, 0], rotation[..., 0, 0])
        m = _count(jacobians, len(self.frame_joint))
        jacobian = self._jacobian(position[:, :m], p, z, m) if m else np.zeros((n, 0, 6, self.nv))
        return BatchedStates(Q, position, angle, jacobian, (p, z), rotation)

    def _jacobian(self, position: np.ndarray, p: np.ndarray, z: np.ndarray, m: int) -> np.ndarray:
        """(N, m, 6, nv) of the first m frames: column j of frame f is [z_j × (p_f − p_j); z_j] (revolute),
        [z_j; 0] (prismatic), zero where joint j does not support frame f."""
        n, nf = position.shape[:2]
        moved = cross(z[:, None, 1:], position[:, :, None] - p[:, None, 1:])  # (N, m, nj − 1, 3)
        revolute, support = self.revolute[1:], self.support[:m, 1:]
        linear = np.where(revolute[:, None], moved, z[:, None, 1:]) * support[..., None]
        angular = z[:, None, 1:] * (support & revolute)[..., None]
        jacobian = np.zeros((n, nf, 6, self.nv))
        jacobian[:, :, :3, self.column[1:]] = linear.transpose(0, 1, 3, 2)
        jacobian[:, :, 3:, self.column[1:]] = angular.transpose(0, 1, 3, 2)
        return jacobian

    def motion(self, states: BatchedStates, V: np.ndarray, A: np.ndarray | None = None) -> BatchedStates:
        """Fill ``states.velocity`` (twists, m/s and rad/s) and ``states.acceleration0`` (classical accelerations,
        m/s² and rad/s²) of the frames for joint velocities ``V`` (N, nv), at q̈ = 0 or at the joint accelerations
        ``A`` (N, nv)."""
        p, z = states.joints
        n, nj = p.shape[:2]
        w, alpha, v, a = (np.zeros((n, nj, 3)) for _ in range(4))
        for i in range(1, nj):
            lam = self.parent[i]
            qd = V[:, self.column[i], None]
            r = p[:, i] - p[:, lam]
            wl = w[:, lam]
            turn = cross(wl, r)
            v[:, i] = v[:, lam] + turn
            a[:, i] = a[:, lam] + cross(alpha[:, lam], r) + cross(wl, turn)
            zq = z[:, i] * qd
            if self.revolute[i]:
                w[:, i] = wl + zq
                alpha[:, i] = alpha[:, lam] + cross(wl, zq)
            else:
                w[:, i], alpha[:, i] = wl, alpha[:, lam]
                v[:, i] += zq
                a[:, i] += 2.0 * cross(wl, zq)
            if A is not None:
                (alpha if self.revolute[i] else a)[:, i] += z[:, i] * A[:, self.column[i], None]
        j = self.frame_joint
        r = states.position - p[:, j]
        wf = w[:, j]
        turn = cross(wf, r)
        states.velocity = np.concatenate([v[:, j] + turn, wf], axis=-1)
        states.acceleration0 = np.concatenate([a[:, j] + cross(alpha[:, j], r) + cross(wf, turn), alpha[:, j]],
                                              axis=-1)
        return states


class PlanarFrames(BatchedFrames):
    r""":class:`BatchedFrames` for a planar tree — every revolute axis along the world z axis, every prismatic axis
    in the xy plane, every joint and frame placement a turn about z — in the plane: a joint is its angle θ and
    origin (x, y), z stays constant. With Rot(θ) the plane rotation, σ_i = ±1 the revolute axis' z and d_i the
    slide direction:

    .. math::

        θ_i = θ_λ + θ_0 + σ_i q_i \;(\text{prismatic: } θ_λ + θ_0), \qquad
        p_i = p_λ + \mathrm{Rot}(θ_λ) p_0 \;[+\, d_i q_i], \qquad d_i = \mathrm{Rot}(θ_λ) R_0 â,

        ω_i = ω_λ + σ_i \dot q_i, \quad α_i = α_λ \;(+\, σ_i \ddot q_i), \qquad
        v_i = v_λ + ω_λ e_z × r \;[+\, d_i \dot q_i], \qquad
        a_i = a_λ + α_λ e_z × r − ω_λ^2 r \;[+\, 2 ω_λ e_z × d_i \dot q_i \;(+\, d_i \ddot q_i)]

    (the brackets: prismatic), the special case of the spatial recursion with every ω and α along z.
    """

    @staticmethod
    def applies(model: pin.Model, frame_ids: list[int]) -> bool:
        """Whether the joints and the frames ``frame_ids`` of ``model`` form a planar tree (in the xy plane)."""
        turns_about_z = [m.rotation for m in model.jointPlacements] + [model.frames[f].placement.rotation
                                                                       for f in frame_ids]
        if any(abs(R[2, 2] - 1.0) > 1e-12 for R in turns_about_z):
            return False
        frames = BatchedFrames(model, [])
        return all(abs(abs(a[2]) - 1.0) < 1e-12 if r else abs(a[2]) < 1e-12
                   for a, r in zip(frames.axis[1:], frames.revolute[1:]))

    def __init__(self, model: pin.Model, frame_ids: list[int]) -> None:
        super().__init__(model, frame_ids)
        self.sign = self.axis[:, 2]  # σ of the revolute joints
        self.turn = np.array([math.atan2(R[1, 0], R[0, 0]) for R, _ in self.placement])  # θ_0
        self.slide = np.array([math.atan2(*(R @ a)[1::-1]) for (R, _), a in zip(self.placement, self.axis)])
        self.offset = np.array([p[:2] for _, p in self.placement])  # p_0 (x, y)
        self.frame_turn = np.arctan2(self.frame_rotation[:, 1, 0], self.frame_rotation[:, 0, 0])
        data = model.createData()
        pin.framesForwardKinematics(model, data, pin.neutral(model))
        self.frame_z = np.array([data.oMf[f].translation[2] for f in frame_ids])
        pairs = np.argwhere(self.support)  # (frame, joint) pairs where the joint moves the frame
        self.turning = pairs[self.revolute[pairs[:, 1]]]
        self.sliding = pairs[~self.revolute[pairs[:, 1]]]

    def placements(self, Q: np.ndarray, jacobians: bool | int = True) -> BatchedStates:
        Q = np.asarray(Q, dtype=float)
        n, nj = len(Q), len(self.parent)
        q = np.ascontiguousarray(Q.T)
        theta, x, y, dx, dy, s = (np.zeros((nj, n)) for _ in range(6))
        c = np.ones((nj, n))
        for i in range(1, nj):
            lam, (px, py), qi = self.parent[i], self.offset[i], q[self.column[i]]
            x[i] = x[lam] + c[lam] * px - s[lam] * py
            y[i] = y[lam] + s[lam] * px + c[lam] * py
            if self.revolute[i]:
                theta[i] = theta[lam] + (self.turn[i] + self.sign[i] * qi)
            else:
                theta[i] = theta[lam] + self.turn[i]
                dx[i], dy[i] = np.cos(theta[lam] + self.slide[i]), np.sin(theta[lam] + self.slide[i])
                x[i] += dx[i] * qi
                y[i] += dy[i] * qi
            c[i], s[i] = np.cos(theta[i]), np.sin(theta[i])
        j, (fx, fy) = self.frame_joint, self.frame_offset[:, :2].T[..., None]
        X = x[j] + c[j] * fx - s[j] * fy  # (F, N)
        Y = y[j] + s[j] * fx + c[j] * fy
        angle = (theta[j] + self.frame_turn[:, None]).T  # not wrapped to (−π, π]
        # built sample-last (contiguous rows of N) and returned as transposed views
        position = np.empty((3, len(j), n))
        position[0], position[1], position[2] = X, Y, self.frame_z[:, None]
        position = position.transpose(2, 1, 0)
        m = _count(jacobians, len(j))
        jacobian = np.zeros((m, 6, self.nv, n))
        if m:  # revolute columns σ (−(y_f − y_j), x_f − x_j, 0, 0, 0, 1), prismatic ones (d_x, d_y, 0, …)
            f, k = self.turning[self.turning[:, 0] < m].T
            sigma, column = self.sign[k][:, None], self.column[k]
            jacobian[f, 0, column] = -sigma * (Y[f] - y[k])
            jacobian[f, 1, column] = sigma * (X[f] - x[k])
            jacobian[f, 5, column] = sigma
            f, k = self.sliding[self.sliding[:, 0] < m].T
            jacobian[f, 0, self.column[k]] = dx[k]
            jacobian[f, 1, self.column[k]] = dy[k]
        jacobian = jacobian.transpose(3, 0, 1, 2)
        return BatchedStates(Q, position, angle, jacobian, (x, y, dx, dy, X, Y))

    def motion(self, states: BatchedStates, V: np.ndarray, A: np.ndarray | None = None) -> BatchedStates:
        x, y, dx, dy, X, Y = states.joints
        nj, n = x.shape
        v = np.ascontiguousarray(V.T)
        a = None if A is None else np.ascontiguousarray(A.T)
        w, alpha, vx, vy, ax, ay = (np.zeros((nj, n)) for _ in range(6))
        for i in range(1, nj):
            lam, qd = self.parent[i], v[self.column[i]]
            rx, ry, wl = x[i] - x[lam], y[i] - y[lam], w[lam]
            vx[i] = vx[lam] - wl * ry
            vy[i] = vy[lam] + wl * rx
            ax[i] = ax[lam] - alpha[lam] * ry - wl * wl * rx
            ay[i] = ay[lam] + alpha[lam] * rx - wl * wl * ry
            w[i], alpha[i] = wl, alpha[lam]
            if self.revolute[i]:
                w[i] = wl + self.sign[i] * qd
                if a is not None:
                    alpha[i] = alpha[lam] + self.sign[i] * a[self.column[i]]
            else:
                vx[i] += dx[i] * qd
                vy[i] += dy[i] * qd
                ax[i] -= 2.0 * wl * dy[i] * qd
                ay[i] += 2.0 * wl * dx[i] * qd
                if a is not None:
                    ax[i] += dx[i] * a[self.column[i]]
                    ay[i] += dy[i] * a[self.column[i]]
        j = self.frame_joint
        rx, ry, wf, af = X - x[j], Y - y[j], w[j], alpha[j]
        velocity, acceleration = np.zeros((6, len(j), n)), np.zeros((6, len(j), n))  # sample-last, as placements
        velocity[0], velocity[1], velocity[5] = vx[j] - wf * ry, vy[j] + wf * rx, wf
        acceleration[0], acceleration[1] = ax[j] - af * ry - wf * wf * rx, ay[j] + af * rx - wf * wf * ry
        acceleration[5] = af
        states.velocity, states.acceleration0 = velocity.transpose(2, 1, 0), acceleration.transpose(2, 1, 0)
        return states


def _count(jacobians: bool | int, frames: int) -> int:
    """How many leading frames get Jacobians: all for True, none for False, else min(jacobians, frames)."""
    return frames if jacobians is True else min(int(jacobians), frames)


def batched_frames(model: pin.Model, frame_ids: list[int]) -> BatchedFrames:
    """:class:`PlanarFrames` for a planar tree, else :class:`BatchedFrames`.

    Raises:
        NotImplementedError: if the model has a joint other than revolute or prismatic about one fixed axis.
    """
    return (PlanarFrames if PlanarFrames.applies(model, frame_ids) else BatchedFrames)(model, frame_ids)

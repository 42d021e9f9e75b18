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
    ``rotation`` (N, F, 3, 3), ``angle`` (N, F) (about z, rad), ``jacobian`` (N, F, 6, nv); after
    :meth:`BatchedFrames.motion` also ``velocity`` and ``acceleration0`` (N, F, 6)."""

    q: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    angle: np.ndarray
    jacobian: np.ndarray
    origins: np.ndarray  # joint origins p_i (N, nj, 3), the universe first
    axes: np.ndarray  # joint axes z_i in world (N, nj, 3)
    velocity: np.ndarray | None = None
    acceleration0: np.ndarray | None = None


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

    def placements(self, Q: np.ndarray, jacobians: bool = True) -> BatchedStates:
        """Frame positions (m), rotations, angles about z (rad) and (with ``jacobians``) Jacobians at the N
        configurations ``Q`` (N, nq)."""
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
        jacobian = self._jacobian(position, p, z) if jacobians else np.zeros((n, 0, 6, self.nv))
        return BatchedStates(Q, position, rotation, angle, jacobian, p, z)

    def _jacobian(self, position: np.ndarray, p: np.ndarray, z: np.ndarray) -> np.ndarray:
        """(N, F, 6, nv): column j of frame f is [z_j × (p_f − p_j); z_j] (revolute), [z_j; 0] (prismatic), zero
        where joint j does not support frame f."""
        n, nf = position.shape[:2]
        moved = cross(z[:, None, 1:], position[:, :, None] - p[:, None, 1:])  # (N, F, nj − 1, 3)
        revolute, support = self.revolute[1:], self.support[:, 1:]
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
        p, z = states.origins, states.axes
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

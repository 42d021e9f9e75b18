r"""What each joint of a mechanism must do in a task: its duty (speed, acceleration and torque over time).

The duty comes from the dynamics of the model *without* drive inertia (armature zero): the candidate drives bring
their own rotor and gearbox inertia, which the sizing adds exactly once. A duty can be replayed k times slower
(k < 1: faster): t → k t, ω → ω/k, ω̇ → ω̇/k², the dynamic part of the torque × 1/k², the static part (gravity,
external loads) unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError
from ..kinematics.loops import loop_solver
from ..model.loads import Loads
from ..model.mechanism import Mechanism

if TYPE_CHECKING:  # pragma: no cover
    from ..dynamics.motion import Trajectory


@dataclass(frozen=True)
class JointDuty:
    """One joint's duty over a task.

    Attributes:
        name, kind: joint name, ``"revolute"`` (rad, N·m) or ``"prismatic"`` (m, N).
        t: sample times (s).
        speed, acceleration: joint speed (rad/s or m/s) and acceleration (rad/s² or m/s²).
        torque: joint torque or force without drive inertia (N·m or N).
        static_torque: its part that does not depend on speed or acceleration (gravity, external loads).
        load_inertia: the largest load inertia the joint sees, the diagonal of the mass matrix (kg·m² or kg).
        stroke: range of the joint's position in the task (rad or m).
    """

    name: str
    kind: str
    t: NDArray[np.float64]
    speed: NDArray[np.float64]
    acceleration: NDArray[np.float64]
    torque: NDArray[np.float64]
    static_torque: NDArray[np.float64]
    load_inertia: float
    stroke: float = 0.0

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0]) if len(self.t) > 1 else 0.0

    def scaled(self, k: float) -> JointDuty:
        """The same motion replayed k times slower (k < 1: faster)."""
        if k == 1.0:
            return self
        dynamic = self.torque - self.static_torque
        return replace(self, t=self.t[0] + (self.t - self.t[0]) * k, speed=self.speed / k,
                       acceleration=self.acceleration / k**2, torque=dynamic / k**2 + self.static_torque)

    def time_weights(self) -> NDArray[np.float64]:
        """Trapezoidal-rule weights w_i with Σ w_i f_i / duration = the time mean of f (one sample: weight 1)."""
        if len(self.t) < 2:
            return np.ones(1)
        step = np.diff(self.t)
        w = np.zeros(len(self.t))
        w[1:] += step / 2
        w[:-1] += step / 2
        return w / self.duration

    def strong_samples(self, count: int = 4, among: NDArray[np.intp] | None = None) -> NDArray[np.intp]:
        """Indices of samples likely to decide the peak motor torque whatever the drive: the ``count`` largest of
        several weighted sums of |ω|, |ω̇| and |τ| (each scaled to its maximum), ``among`` the given samples."""
        among = np.arange(len(self.t)) if among is None else among
        if len(among) == 0:
            return among
        magnitudes = [np.abs(x[among]) for x in (self.speed, self.acceleration, self.torque)]
        scaled = np.stack([x / x.max() if x.max() > 0 else x for x in magnitudes], axis=1)
        weights = np.array([[1, 1, 1], [2, 1, 1], [1, 2, 1], [1, 1, 2], [1, 0, 0], [0, 1, 0], [0, 0, 1],
                            [1, 1, 0], [1, 0, 1], [0, 1, 1], [0, 1, 3], [0, 3, 1]], dtype=float)
        return np.unique(among[np.argsort(-(scaled @ weights.T), axis=0, kind="stable")[:count].ravel()])

    def envelope(self) -> NDArray[np.intp]:
        """Indices of the samples that can decide a per-sample motor check, for *every* converter and motor.

        Through a converter of ratio u and efficiency η, sample i loads a motor (with the converter's inertia,
        x = (J_m + J_c) u² ≥ 0) with |T_m| = |x ω̇_i + τ*_i| / u at the speed u |ω_i|, where τ* = τ/η when the
        load takes power and τ η when it returns it. Sample j makes sample i redundant when |ω_j| ≥ |ω_i|,
        |ω̇_j| ≥ |ω̇_i|, |τ_j| ≥ |τ_i|, ω̇_j and τ_j do not oppose each other (so |x ω̇_j + τ*_j| grows with x as fast
        as possible) and j motors if i does: then for every x ≥ 0 and η ≤ 1, sample j needs at least the torque of
        sample i at a speed at least as high, and every limit curve falls with speed. Exact (a superset of the
        undominated samples): a few dozen of thousands remain for moves with constant-acceleration phases; a smooth
        motion (sinusoids) keeps most of its samples.
        """
        s, A, M = np.abs(self.speed), np.abs(self.acceleration), np.abs(self.torque)
        aligned = self.acceleration * self.torque >= 0
        motoring = self.torque * self.speed >= 0
        index = np.arange(len(s))

        def dominated(rows: NDArray[np.intp], by: NDArray[np.intp]) -> NDArray[np.bool_]:
            """Which ``rows`` some sample of ``by`` (aligned samples) makes redundant; strict, with ties broken
            by index, so the relation is a strict partial order and every removed sample has a kept dominator."""
            r, d = rows[:, None], by[None, :]
            ge = (s[d] >= s[r]) & (A[d] >= A[r]) & (M[d] >= M[r]) & (motoring[d] | ~motoring[r])
            strict = (s[d] > s[r]) | (A[d] > A[r]) | (M[d] > M[r]) | (motoring[d] & ~motoring[r]) \
                | ~aligned[r] | (d < r)
            return np.any(ge & strict & (d != r), axis=1)

        candidates = index[aligned]
        if len(candidates) == 0:
            return index
        # a few strong dominators first, then all of them
        left = index[~dominated(index, self.strong_samples(16, candidates))]
        if len(left) > len(index) // 2:  # smooth motions: few samples are dominated, the full pass would not pay
            return left
        survivors = np.intersect1d(left, candidates)
        return np.concatenate([part[~dominated(part, survivors)]
                               for part in np.array_split(left, max(1, len(left) // 1024))])


def joint_duties(mech: Mechanism, trajectory: Trajectory, loads: Loads = None) -> list[JointDuty]:
    """The duty of every driven coordinate along a :class:`~mechatron.dynamics.motion.Trajectory` (``loads``:
    external :class:`~mechatron.model.Load` s, N and N·m, as in :func:`mechatron.dynamics.tree.inverse_dynamics`),
    from the model with its drive inertia (armature) removed.

    A serial mechanism: every joint, torques from RNEA, load inertia the diagonal of the mass matrix; the
    trajectory's q holds Pinocchio configurations (nq columns) or one coordinate per joint (nv columns, turned into
    configurations by :meth:`~mechatron.model.Mechanism.configuration`, so a continuous joint's angle becomes its
    (cos, sin)). A closed-loop mechanism (the trajectory gives its actuated coordinates): every actuated coordinate,
    forces from the constrained inverse dynamics, load inertia the reduced inertia Sᵀ M S of that coordinate with
    the other inputs held (the reduced moment of inertia [Egorov, 6.8]); its kind is ``"cylinder"`` for a
    hydraulic cylinder. Joints of more than one coordinate (spherical, free-flyer) cannot be sized."""
    model = pin.Model(mech.model)
    model.armature[:] = 0.0
    bare = replace(mech, model=model)
    t = np.asarray(trajectory.t, dtype=float)
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        raise InputError("a sizing task needs at least two samples at increasing times")
    V, A = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (trajectory.v, trajectory.a))
    if mech.closures:
        Q, tau, static, inertia = _closed_loop(bare, trajectory, loads)
        names = list(mech.actuated)
        kinds = ["cylinder" if n in mech.cylinders else mech.joint_kind(n) for n in names]
        positions = np.asarray(trajectory.q, dtype=float)
        columns = list(range(len(names)))
    else:
        from ..dynamics.tree import inverse_dynamics, mass_matrix

        for name in mech.joint_names:
            joint = mech.model.joints[mech.joint_id(name)]
            if joint.nv != 1:
                raise InputError(f"joint {name}: cannot size a {mech.joint_kind(name)} joint (only revolute and "
                                 "prismatic)")
        positions = np.atleast_2d(np.asarray(trajectory.coordinates, dtype=float))  # one per joint, unwrapped
        Q = np.atleast_2d(np.asarray(trajectory.q, dtype=float))
        if Q.shape[1] != mech.nq:  # the trajectory was given in joint coordinates only
            Q = mech.configuration(positions)
        tau = inverse_dynamics(bare, Q, V, A, loads)
        static = inverse_dynamics(bare, Q, np.zeros_like(V), np.zeros_like(A), loads)
        step = max(1, len(Q) // 200)
        inertia = np.max(np.diagonal(mass_matrix(bare, Q[::step]), axis1=1, axis2=2), axis=0)
        names = mech.joint_names
        kinds = [mech.joint_kind(n) for n in names]
        columns = [mech.model.joints[mech.joint_id(n)].idx_v for n in names]
    return [JointDuty(name, kind, t, V[:, j], A[:, j], tau[:, j], static[:, j], float(inertia[j]),
                      float(np.ptp(positions[:, j])))
            for name, kind, j in zip(names, kinds, columns)]


def _closed_loop(mech: Mechanism, trajectory: Trajectory, loads: Loads
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(Q, forces, holding forces, largest reduced inertia of each actuated coordinate) along the trajectory."""
    from ..dynamics.trajectory import actuator_forces, holding_forces
    from ..dynamics.tree import mass_matrix

    Q, forces = actuator_forces(mech, trajectory, loads)
    static = holding_forces(mech, Q, loads)
    solver = loop_solver(mech)
    inertia = np.zeros(len(mech.actuated))
    for q in Q[:: max(1, len(Q) // 50)]:
        S = solver.velocity_matrix(q)
        inertia = np.maximum(inertia, np.diagonal(S.T @ mass_matrix(mech, q) @ S))
    return Q, forces, static, inertia

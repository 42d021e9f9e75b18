r"""What each joint of a mechanism must do in a task: its duty (speed, acceleration and torque over time).

The duty comes from the dynamics of the model *without* drive inertia (armature zero): the candidate drives bring
their own rotor and gearbox inertia, which the sizing adds exactly once. A duty can be replayed with its moves k
times slower (k < 1: faster): within a move t → k t, ω → ω/k, ω̇ → ω̇/k², the inertial part of the torque × 1/k², the
static part (gravity, external loads) unchanged, the friction part taken at the new speed; the dwells between moves
keep their length (:func:`~mechatron.dynamics.task.moving_intervals`).

**The drive data of the mechanism's file** (a robot file's ``drive`` table, :class:`~mechatron.model.dh.Drive`):
its rotor inertia is replaced by each candidate's own (the armature is removed), while its friction and efficiency
stay with the joint. The friction is given on the motor shaft of that drive (viscous B, N·m·s/rad; Coulomb T_c+
for positive and T_c− for negative motor speed, N·m) with its gear ratio u_f; seen at the joint it is

    τ_f(q̇) = u_f (B u_f q̇ + T_c(u_f q̇)),    T_c(ω) = T_c+ if ω > 0, T_c− if ω < 0, 0 at rest,

a torque (N·m, or a force in N for a prismatic joint) with the sign of the speed, added to the joint torque: the
converter carries it, so it passes through the converter's efficiency like the rest of the load
(:attr:`JointDuty.friction`). The file's efficiency η_f multiplies every candidate converter's, as a factor of the
chain: η = η_converter · η_chain · η_f (:attr:`JointDuty.efficiency`,
:func:`~mechatron.drives.converters.converters_for`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Mechanism

if TYPE_CHECKING:  # pragma: no cover
    from ..dynamics.motion import Trajectory
    from ..dynamics.segments import PayloadSchedule


#: The envelope's full pass (:meth:`JointDuty.envelope`) is done when it compares at most this many times as many
#: pairs of samples as the task has samples (its cost, about that of checking as many motor × converter pairs over
#: every sample).
ENVELOPE_WORK = 64

@dataclass(frozen=True)
class JointDuty:
    """One joint's duty over a task.

    Attributes:
        name, kind: joint name, ``"revolute"`` (rad, N·m) or ``"prismatic"`` (m, N).
        t: sample times (s).
        speed, acceleration: joint speed (rad/s or m/s) and acceleration (rad/s² or m/s²).
        torque: joint torque or force without drive inertia (N·m or N), the file's drive friction included.
        static_torque: its part that does not depend on speed or acceleration (gravity, external loads); given
            as an array or as a function that makes it (called once, when first read: only the ``time``
            objective and reports need it).
        load_inertia: the largest load inertia the joint sees, the diagonal of the mass matrix (kg·m² or kg).
        stroke: range of the joint's position in the task (rad or m).
        moving: (N − 1,) which intervals between samples belong to a move (the others are dwells, which keep
            their length when the duty is replayed faster); ``None``: every interval moves.
        friction: the joint-side friction of the mechanism file's drive (the module docstring): (B_q, C+, C−), the
            viscous coefficient B_q = B u_f² (N·m·s/rad or N·s/m) and the Coulomb torques (N·m or N) for positive
            and negative joint speed; τ_f = B_q q̇ + C± (0 at rest), part of :attr:`torque`.
        efficiency: the efficiency η_f of the mechanism file's drive, in (0, 1]: a factor of every converter's.
    """

    name: str
    kind: str
    t: NDArray[np.float64]
    speed: NDArray[np.float64]
    acceleration: NDArray[np.float64]
    torque: NDArray[np.float64]
    static_source: NDArray[np.float64] | Callable[[], NDArray[np.float64]]
    load_inertia: float
    stroke: float = 0.0
    moving: NDArray[np.bool_] | None = None
    friction: tuple[float, float, float] = (0.0, 0.0, 0.0)
    efficiency: float = 1.0

    @property
    def static_torque(self) -> NDArray[np.float64]:
        """The static part of the torque (N·m or N), made when first read."""
        value = self.static_source
        if callable(value):
            value = value()
            object.__setattr__(self, "static_source", value)  # a frozen dataclass: made once, then kept
        return value

    def __getstate__(self) -> dict:
        """A pickled duty holds its static torque, made if need be (a function does not pickle)."""
        return {**self.__dict__, "static_source": self.static_torque}

    def friction_torque(self, speed: NDArray[np.float64]) -> NDArray[np.float64]:
        """The friction torque τ_f = B_q q̇ + C± (N·m or N) at the joint speeds ``speed`` (rad/s or m/s):
        :attr:`friction`, with the sign of the speed, 0 at rest."""
        return friction_torque(self.friction, speed)

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0]) if len(self.t) > 1 else 0.0

    def scaled(self, k: float) -> JointDuty:
        """The same motion with its moves replayed k times slower (k < 1: faster): every interval of a move lasts
        k times as long, every dwell as long as before (t_{i+1} − t_i → k (t_{i+1} − t_i) where :attr:`moving`);
        speeds × 1/k, accelerations and the inertial torque × 1/k² (zero in a dwell), the static torque kept, the
        friction torque τ_f(q̇/k) (:meth:`friction_torque`)."""
        if k == 1.0:
            return self
        dynamic = self.torque - self.static_torque
        if self.moving is None or self.moving.all():
            t = self.t[0] + (self.t - self.t[0]) * k
        else:
            step = np.diff(self.t)
            t = self.t[0] + np.concatenate([[0.0], np.cumsum(np.where(self.moving, step * k, step))])
        speed = self.speed / k
        if not any(self.friction):
            return replace(self, t=t, speed=speed, acceleration=self.acceleration / k**2,
                           torque=dynamic / k**2 + self.static_torque)
        inertial = dynamic - self.friction_torque(self.speed)
        return replace(self, t=t, speed=speed, acceleration=self.acceleration / k**2,
                       torque=inertial / k**2 + self.static_torque + self.friction_torque(speed))

    def time_weights(self) -> NDArray[np.float64]:
        """Trapezoidal-rule weights w_i with Σ w_i f_i / duration = the time mean of f (one sample: weight 1); made
        once per duty (read-only)."""
        w = self.__dict__.get("_time_weights")
        if w is None:
            if len(self.t) < 2:
                w = np.ones(1)
            else:
                step = np.diff(self.t)
                w = np.zeros(len(self.t))
                w[1:] += step / 2
                w[:-1] += step / 2
                w /= self.duration
            w.setflags(write=False)
            self.__dict__["_time_weights"] = w  # a frozen dataclass: its fields, not this cache, are fixed
        return w

    def strong_samples(self, count: int = 4, among: NDArray[np.intp] | None = None) -> NDArray[np.intp]:
        """Indices of samples likely to decide the peak motor torque whatever the drive: the ``count`` largest of
        several weighted sums of |ω|, |ω̇| and |τ| (each scaled to its maximum), ``among`` the given samples."""
        among = np.arange(len(self.t)) if among is None else among
        if len(among) == 0:
            return among
        every = len(among) == len(self.t)  # all samples: no copies
        magnitudes = [np.abs(x if every else x[among]) for x in (self.speed, self.acceleration, self.torque)]
        scaled = np.stack([x / x.max() if x.max() > 0 else x for x in magnitudes], axis=1)
        weights = np.array([[1, 1, 1], [2, 1, 1], [1, 2, 1], [1, 1, 2], [1, 0, 0], [0, 1, 0], [0, 0, 1],
                            [1, 1, 0], [1, 0, 1], [0, 1, 1], [0, 1, 3], [0, 3, 1]], dtype=float)
        return np.unique(among[_largest(scaled @ weights.T, count)])

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
        # a few strong dominators first, then all of them where that costs no more than checking a few pairs over
        # every sample (the pass compares every sample left with every aligned one left: quadratic)
        left = index[~dominated(index, self.strong_samples(16, candidates))]
        survivors = np.intersect1d(left, candidates)
        if len(left) * len(survivors) > ENVELOPE_WORK * len(index):
            return left
        return np.concatenate([part[~dominated(part, survivors)]
                               for part in np.array_split(left, max(1, len(left) // 1024))])


@dataclass(frozen=True)
class DriveMount:
    """A chosen drive as a body of the mechanism: its housing's ``mass`` (kg; the motor's and the converter's
    catalog masses) as a point mass at ``placement`` in the frame of joint ``parent`` (0: the ground, where it loads
    no joint), on the body ``carrier`` (:func:`drive_carrier`).

    Its spinning parts — the rotor J_m and the converter's motor side J_c — are not part of the body: they are counted
    once, as the reflected inertia (J_m + J_c) u² of the joint the drive turns (the sizing's motor torque
    (J_m + J_c) u ω̇ + τ*/u; Pinocchio's ``armature``). Their turning with the carrying body and the gyroscopic
    coupling between the two are neglected, as in the reflected-inertia model of the dynamics
    (:mod:`mechatron.drives.transmission`); catalogs give no housing inertia, hence the point mass."""

    joint: str
    drive: str
    mass: float
    parent: int
    placement: pin.SE3
    carrier: str


def friction_torque(friction: tuple[float, float, float], speed: NDArray[np.float64]) -> NDArray[np.float64]:
    """τ_f = B_q q̇ + C± (N·m or N) of the friction (B_q, C+, C−) (:attr:`JointDuty.friction`) at the joint speeds
    ``speed`` (rad/s or m/s), with the sign of the speed, 0 at rest."""
    viscous, positive, negative = friction
    return viscous * speed + np.where(speed > 0, positive, np.where(speed < 0, negative, 0.0))


def _largest(scores: NDArray[np.float64], count: int) -> NDArray[np.intp]:
    """Row indices of the ``count`` largest values of every column of ``scores`` (N, k), ≥ 0 and finite, ties in
    row order (as a stable sort of −score): ``count`` passes of argmax, O(count · N · k)."""
    scores = np.array(scores, order="F")  # a copy, each column contiguous for argmax
    columns, found = np.arange(scores.shape[1]), []
    for _ in range(min(count, len(scores))):
        best = scores.argmax(axis=0)  # the first of the largest: ties in row order
        found.append(best)
        scores[best, columns] = -np.inf
    return np.concatenate(found)


def drive_carrier(mech: Mechanism, joint: str) -> tuple[int, pin.SE3, str]:
    """Where the drive of ``joint`` sits: (the Pinocchio joint of the carrying body (0: the ground), the drive's
    placement in that joint's frame, the body's name). By default on the joint's parent body, at the joint's origin
    (the proximal link at the joint); where the mechanism's :class:`~mechatron.model.dh.Drive` has a ``placement``
    (a robot file's ``drive.placement``, a mechanism file's ``[[drives]]``), at its ``offset`` (m) in that frame."""
    drive = mech.drives.get(joint)
    if drive is not None and drive.placement is not None:
        try:
            frame = mech.model.frames[mech.frame_id(drive.placement)]
        except InputError as exc:
            raise InputError(f"the drive of {joint} is placed on an unknown body: {exc.message}") from None
        offset = pin.SE3(np.eye(3), np.asarray(drive.offset, dtype=float))
        return frame.parentJoint, frame.placement * offset, drive.placement
    index = mech.joint_id(joint)
    parent = mech.model.parents[index]
    return parent, mech.model.jointPlacements[index], mech.link_names[parent - 1] if parent else "the ground"


def mount_drives(mech: Mechanism, mounts: list[DriveMount]) -> Mechanism:
    """A copy of ``mech`` carrying every drive of ``mounts`` as a point mass on its body (Pinocchio's
    ``appendBodyToJoint``; the ones on the ground change nothing)."""
    model = pin.Model(mech.model)
    for m in mounts:
        if m.parent > 0 and m.mass > 0:
            model.appendBodyToJoint(m.parent, pin.Inertia(float(m.mass), np.zeros(3), np.zeros((3, 3))), m.placement)
    return replace(mech, model=model, rebuild=None, derivatives=None)


def joint_duties(mech: Mechanism, trajectory: Trajectory, loads: Loads = None, *,
                 kinematics: Mechanism | None = None, moving: NDArray[np.bool_] | None = None,
                 payload: PayloadSchedule | None = None) -> list[JointDuty]:
    """The duty of every driven coordinate along a :class:`~mechatron.dynamics.motion.Trajectory` (``loads``:
    external :class:`~mechatron.model.Load` s, N and N·m, as in :func:`mechatron.dynamics.tree.inverse_dynamics`),
    from the model with its drive inertia (armature) removed and the friction of its file's drives added at the
    joints (:func:`drive_losses`: τ_f = u_f (B u_f q̇ + T_c±), with the sign of the speed; the module docstring).

    A serial mechanism: every joint, torques from RNEA, load inertia the diagonal of the mass matrix; the
    trajectory's q holds Pinocchio configurations (nq columns) or one coordinate per joint (nv columns, turned into
    configurations by :meth:`~mechatron.model.Mechanism.configuration`, so a continuous joint's angle becomes its
    (cos, sin)). A closed-loop mechanism (the trajectory gives its actuated coordinates): every actuated coordinate,
    forces from the constrained inverse dynamics, load inertia the reduced inertia Sᵀ M S of that coordinate with
    the other inputs held (the reduced moment of inertia [Egorov, 6.8]); its kind is ``"cylinder"`` for a
    hydraulic cylinder. Joints of more than one coordinate (spherical, free-flyer) cannot be sized. Every duty knows
    the trajectory's moves and dwells (:func:`~mechatron.dynamics.task.moving_intervals`). ``kinematics``: a
    mechanism of the same linkage whose loops to solve (``mech`` with its drives mounted changes only masses; the
    loops' compiled kernels are kept by the mechanism that built them), default ``mech``; ``moving``: the
    trajectory's moves (:func:`~mechatron.dynamics.task.moving_intervals`), when already known; ``payload``: a
    payload carried on part of the task only (:class:`~mechatron.dynamics.segments.PayloadSchedule`), attached to
    ``mech`` at the samples where it is carried (torques, static torques and load inertias of each set of samples
    from its own mechanism)."""
    from ..dynamics.task import moving_intervals

    model = pin.Model(mech.model)
    model.armature[:] = 0.0
    bare = replace(mech, model=model)
    t = np.asarray(trajectory.t, dtype=float)
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        raise InputError("a sizing task needs at least two samples at increasing times")
    V, A = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (trajectory.v, trajectory.a))
    if mech.closures:
        Q, tau, holding, inertia = _closed_loop(bare, kinematics or mech, trajectory, loads, payload)
        check_strokes(mech, Q, t)
        static = _Columns(holding)  # the holding forces are computed when first read
        names = list(mech.actuated)
        kinds = ["cylinder" if n in mech.cylinders else mech.joint_kind(n) for n in names]
        positions = np.asarray(trajectory.q, dtype=float)
        columns = list(range(len(names)))
    else:
        from ..dynamics.tree import inverse_dynamics, mass_matrix

        names = mech.joint_names
        for name in names:
            joint = mech.model.joints[mech.joint_id(name)]
            if joint.nv != 1:
                raise InputError(f"joint {name}: cannot size a {mech.joint_kind(name)} joint (only revolute and "
                                 "prismatic)")
        positions = np.atleast_2d(np.asarray(trajectory.coordinates, dtype=float))  # one per joint, unwrapped
        Q = np.atleast_2d(np.asarray(trajectory.q, dtype=float))
        if Q.shape[1] != mech.nq:  # the trajectory was given in joint coordinates only
            Q = mech.configuration(positions)
        step = max(1, len(Q) // 200)
        if payload is None:
            tau = inverse_dynamics(bare, Q, V, A, loads)
            static = _Columns(lambda: inverse_dynamics(bare, Q, np.zeros_like(V), np.zeros_like(A), loads))
            inertia = np.max(np.diagonal(mass_matrix(bare, Q[::step]), axis1=1, axis2=2), axis=0)
        else:
            tau = payload.inverse_dynamics(bare, Q, V, A, loads)
            static = _Columns(lambda: payload.inverse_dynamics(bare, Q, np.zeros_like(V), np.zeros_like(A), loads))
            inertia = np.max(payload.thinned(step).per_sample(
                bare, lambda m, q: np.diagonal(np.atleast_3d(mass_matrix(m, q)).reshape(len(q), m.nv, m.nv),
                                               axis1=1, axis2=2), Q[::step]), axis=0)
        kinds = [mech.joint_kind(n) for n in names]
        columns = [mech.model.joints[mech.joint_id(n)].idx_v for n in names]
    moving = moving_intervals(trajectory) if moving is None else moving
    strokes = np.ptp(positions, axis=0)
    duties = []
    for name, kind, j in zip(names, kinds, columns):
        friction, efficiency = drive_losses(mech, name)
        torque = tau[:, j] + friction_torque(friction, V[:, j]) if any(friction) else tau[:, j]
        duties.append(JointDuty(name, kind, t, V[:, j], A[:, j], torque, static.column(j), float(inertia[j]),
                                float(strokes[j]), moving, friction, efficiency))
    return duties


#: How far (m) a cylinder's length may pass its stroke's ends in :func:`check_strokes` (rounding of the loops).
STROKE_TOLERANCE = 1e-9


def check_strokes(mech: Mechanism, Q: NDArray[np.float64], t: NDArray[np.float64]) -> None:
    """Refuse (:class:`~mechatron.errors.MechatronError`, one line) a task that moves a hydraulic cylinder of
    ``mech`` beyond its stroke [L_min, L_max] (m): its length (the cylinder joint's coordinate in the configurations
    ``Q`` of the samples at times ``t``, s) outside it by more than :data:`STROKE_TOLERANCE` at some sample. A
    passive cylinder's length follows the loops (no catalog cylinder of that stroke can follow the motion, whatever
    its other checks); a driven one's is the task's own (refused where the task is read)."""
    from ..errors import MechatronError

    for name, spec in mech.cylinders.items():
        length = np.asarray(Q, dtype=float)[:, mech.model.joints[mech.joint_id(name)].idx_q]
        low, high = spec.stroke
        outside = (length < low - STROKE_TOLERANCE) | (length > high + STROKE_TOLERANCE)
        if outside.any():
            k = int(np.argmax(np.maximum(low - length, length - high)))  # the farthest out
            role = "driven" if name in mech.actuated else "passive: its length follows the loops"
            raise MechatronError(
                f"{mech.name}: cylinder {name} ({role}) is {length.min() * 1e3:.1f} … {length.max() * 1e3:.1f} mm "
                f"long along the task, outside its stroke [{low * 1e3:g}, {high * 1e3:g}] mm (farthest at t = "
                f"{t[k]:g} s, {length[k] * 1e3:.1f} mm): no cylinder of that stroke can follow the motion")


def drive_losses(mech: Mechanism, name: str) -> tuple[tuple[float, float, float], float]:
    """The friction and efficiency the mechanism's file gives the drive of coordinate ``name`` (its
    :class:`~mechatron.model.dh.Drive`: motor-side viscous B and Coulomb T_c±, gear ratio u_f, efficiency η_f), as
    the sizing applies them at the joint (the module docstring): ((B u_f², C+, C−), η_f), with C+ = u_f T_c+ and
    C− = u_f T_c− for u_f > 0, C+ = u_f T_c− and C− = u_f T_c+ for u_f < 0 (the motor turns the other way);
    ((0, 0, 0), 1) without drive data."""
    drive = mech.drives.get(name)
    if drive is None:
        return (0.0, 0.0, 0.0), 1.0
    u = float(drive.gear_ratio)
    forward, backward = (float(x) for x in drive.coulomb_friction)
    positive, negative = (u * forward, u * backward) if u > 0 else (u * backward, u * forward)
    return (float(drive.viscous_friction) * u * u, positive, negative), float(drive.efficiency)


class _Columns:
    """The columns of an (N, n) array made by ``make`` when the first is read (:attr:`JointDuty.static_torque`)."""

    def __init__(self, make: Callable[[], NDArray[np.float64]] | NDArray[np.float64]):
        self._make, self._array = make, None

    def column(self, j: int) -> Callable[[], NDArray[np.float64]] | NDArray[np.float64]:
        if not callable(self._make):
            return self._make[:, j]
        return lambda: self._made()[:, j]

    def _made(self) -> NDArray[np.float64]:
        if self._array is None:
            self._array = self._make()
        return self._array


def _closed_loop(mech: Mechanism, kinematics: Mechanism, trajectory: Trajectory, loads: Loads,
                 payload: PayloadSchedule | None = None
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], Callable[[], NDArray[np.float64]],
                            NDArray[np.float64]]:
    """(Q, forces, the holding forces (a function making them), largest reduced inertia of each actuated coordinate)
    along the trajectory: the loops of ``kinematics``, the masses of ``mech``
    (:func:`~mechatron.dynamics.trajectory.actuator_duty`; with ``payload``,
    :func:`~mechatron.dynamics.segments.closed_loop_duty`)."""
    from ..dynamics.segments import closed_loop_duty
    from ..dynamics.trajectory import actuator_duty

    duty = (actuator_duty(mech, trajectory, loads, kinematics=kinematics) if payload is None else
            closed_loop_duty(mech, kinematics, trajectory, loads, payload))
    return duty.q, duty.forces, lambda: duty.holding, duty.inertia

r"""Dynamics of the kinematic tree of a :class:`~mechatron.model.Mechanism`, from Pinocchio.

Equation of motion of the tree: M(q) q̈ + C(q, q̇) q̇ + g(q) = τ + Σ J_pᵀ F_p, with M from CRBA, the bias
h = C q̇ + g from ``nonLinearEffects``, inverse dynamics from RNEA and forward dynamics from ABA. The rotor and gear
inertia of a drive is reflected into its joint once, as Pinocchio's ``armature`` J_rotor·u² (see :mod:`mechatron.dh`);
efficiency and friction act outside Pinocchio, on the motor side, and depend on the direction of the power flow
(:func:`motor_loads`):

- motoring (the joint takes power, τ_load·q̇ ≥ 0): τ_m = τ_load / (u·η),
- back-driven (the load returns power): τ_m = τ_load·η / u,

plus the rotor's own inertia torque J_rotor·u·q̈ and the motor-side friction B·ω_m + T_c(sign ω_m).

Every function takes one state or a batch: q of shape (nq,) or (N, nq), v and a of shape (nv,) or (N, nv).
Units: N·m for revolute and N for prismatic joints, J for energies, SI everywhere.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from .errors import InputError
from .kinematics import samples
from .model import Mechanism

Load = tuple[str, Sequence[float]]  # (frame, world force (3,)) or (frame, world force (3,), world moment (3,))


def external_forces(mech: Mechanism, q: np.ndarray, loads: Sequence[Sequence] | None) -> list[pin.Force] | None:
    """Pinocchio's per-joint external forces (local frames) for world forces (and moments) applied at frames."""
    if not loads:
        return None
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q)
    out = [pin.Force.Zero() for _ in range(model.njoints)]
    for load in loads:
        frame, force = load[0], np.asarray(load[1], dtype=float)
        moment = np.asarray(load[2], dtype=float) if len(load) > 2 else np.zeros(3)
        fid = mech.frame_id(frame)
        joint = mech.model.frames[fid].parentJoint
        placement = pin.updateFramePlacement(model, data, fid)
        oMi = data.oMi[joint]
        # a world force f at point p and moment m, expressed in the joint frame about its origin
        r = placement.translation - oMi.translation
        out[joint] += pin.Force(oMi.rotation.T @ force, oMi.rotation.T @ (moment + np.cross(r, force)))
    return out


#: Batches at least this long go to Pinocchio's parallel RNEA/ABA (C++ loop over the samples, all cores).
PARALLEL_BATCH = 64


def _model_pool(mech: Mechanism) -> pin.ModelPool:
    """A pool of model/data copies for Pinocchio's parallel algorithms, kept with the mechanism."""
    pool = getattr(mech, "_model_pool", None)
    if pool is None or pool[0] is not mech.model:
        pool = (mech.model, pin.ModelPool(mech.model, _threads()))
        mech._model_pool = pool
    return pool[1]


def _threads() -> int:
    return max(1, min(os.cpu_count() or 1, 16))


def _parallel(algorithm, mech: Mechanism, Q: np.ndarray, V: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Run a batch through ``rneaInParallel``/``abaInParallel`` (arrays (N, n) in and out; Pinocchio takes the
    transposed, column-major views)."""
    out = np.empty((len(Q), mech.nv))
    algorithm(_threads(), _model_pool(mech), np.ascontiguousarray(Q).T, np.ascontiguousarray(V).T,
              np.ascontiguousarray(X).T, out.T)
    return out


def inverse_dynamics(mech: Mechanism, q, v, a, loads: Sequence[Sequence] | None = None) -> np.ndarray:
    """Joint torques/forces τ = M q̈ + C q̇ + g − Σ J_pᵀ F_p (RNEA), reflected drive inertia included.

    Args:
        loads: External loads acting on the mechanism, each (frame, force) or (frame, force, moment) with the
            force (N) and moment (N·m) in world axes applied at the frame's origin.

    Returns:
        (nv,) or (N, nv). Long batches without loads run in Pinocchio's parallel RNEA.
    """
    single, Q, (V, A) = samples(mech, q, v, a)
    model, data = mech.model, mech.data
    if not loads and len(Q) >= PARALLEL_BATCH:
        return _parallel(pin.rneaInParallel, mech, Q, V, A)
    out = np.empty((len(Q), mech.nv))
    rnea = pin.rnea
    if loads:
        for i in range(len(Q)):
            out[i] = rnea(model, data, Q[i], V[i], A[i], external_forces(mech, Q[i], loads))
    else:
        for i in range(len(Q)):
            out[i] = rnea(model, data, Q[i], V[i], A[i])
    return out[0] if single else out


def forward_dynamics(mech: Mechanism, q, v, tau) -> np.ndarray:
    """Joint accelerations q̈ = M⁻¹(τ − C q̇ − g) (ABA): (nv,) or (N, nv)."""
    single, Q, (V, T) = samples(mech, q, v, tau)
    if len(Q) >= PARALLEL_BATCH:
        return _parallel(pin.abaInParallel, mech, Q, V, T)
    model, data = mech.model, mech.data
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.aba(model, data, Q[i], V[i], T[i])
    return out[0] if single else out


def mass_matrix(mech: Mechanism, q) -> np.ndarray:
    """Joint-space inertia matrix M(q) (CRBA, symmetrised), including the armature: (nv, nv) or (N, nv, nv)."""
    single, Q, _ = samples(mech, q)
    model, data = mech.model, mech.data
    out = np.empty((len(Q), mech.nv, mech.nv))
    for i in range(len(Q)):
        M = pin.crba(model, data, Q[i])
        out[i] = np.triu(M) + np.triu(M, 1).T
    return out[0] if single else out


def bias_forces(mech: Mechanism, q, v) -> np.ndarray:
    """h(q, q̇) = C(q, q̇) q̇ + g(q): the torques for zero acceleration."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.nonLinearEffects(mech.model, mech.data, Q[i], V[i])
    return out[0] if single else out


def gravity_torques(mech: Mechanism, q) -> np.ndarray:
    """g(q): the joint torques that hold the mechanism against gravity."""
    single, Q, _ = samples(mech, q)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.computeGeneralizedGravity(mech.model, mech.data, Q[i])
    return out[0] if single else out


def kinetic_energy(mech: Mechanism, q, v) -> np.ndarray | float:
    """T = ½ q̇ᵀ M q̇ (J), rotors included through the armature (eq. 6.2 summed over links)."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.array([pin.computeKineticEnergy(mech.model, mech.data, Q[i], V[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def potential_energy(mech: Mechanism, q) -> np.ndarray | float:
    """Gravitational potential energy (J), zero at the world origin's height."""
    single, Q, _ = samples(mech, q)
    out = np.array([pin.computePotentialEnergy(mech.model, mech.data, Q[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def mechanical_energy(mech: Mechanism, q, v) -> np.ndarray | float:
    """T + V (J): constant along an unforced, undamped motion."""
    return kinetic_energy(mech, q, v) + potential_energy(mech, q)


def joint_wrenches(mech: Mechanism, q, v, a, loads: Sequence[Sequence] | None = None) -> np.ndarray:
    """Force (N) and moment (N·m) transmitted through every joint of the tree, from the parent body to the child
    subtree, in world axes about the joint's origin: array (njoints − 1, 6) = [force; moment] per joint (chapter 5,
    the kinetostatic reactions of a serial chain; the joint's torque is the moment's component on its axis)."""
    single, Q, (V, A) = samples(mech, q, v, a)
    if not single:
        raise InputError("joint_wrenches takes one state")
    model, data = mech.model, mech.data
    fext = external_forces(mech, Q[0], loads)
    if fext is None:
        pin.rnea(model, data, Q[0], V[0], A[0])
    else:
        pin.rnea(model, data, Q[0], V[0], A[0], fext)
    pin.updateGlobalPlacements(model, data)  # RNEA leaves the joints' world placements (oMi) as they were
    out = np.empty((model.njoints - 1, 6))
    for j in range(1, model.njoints):
        R = data.oMi[j].rotation
        f = data.f[j]
        out[j - 1, :3] = R @ f.linear
        out[j - 1, 3:] = R @ f.angular
    return out


# ---------------------------------------------------------------------------------------------- drive side
@dataclass(frozen=True)
class MotorLoads:
    """Motor-side loads of every joint (arrays (N, nv), or (nv,) for one state); joints without drive data are direct drives (u = 1, η = 1).

    Attributes:
        torque: Motor torque τ_m (N·m), rotor inertia, transmission losses and friction included.
        speed: Motor speed ω_m = u·q̇ (rad/s).
        joint_torque: τ from the dynamics (rotor inertia included).
        load_torque: τ − J_rotor u² q̈, what the transmission delivers to the joint.
        motoring: Whether power flows from the motor to the load (τ_load·q̇ ≥ 0).
    """

    torque: np.ndarray
    speed: np.ndarray
    joint_torque: np.ndarray
    load_torque: np.ndarray
    motoring: np.ndarray

    @property
    def power(self) -> np.ndarray:
        """Motor shaft power τ_m·ω_m (W)."""
        return self.torque * self.speed


def transmitted_torque(load, speed, ratio, efficiency):
    """The motor-side torque that carries the joint load τ through a transmission of ratio u and efficiency η:
    τ/(u η) when the load takes power (τ q̇ ≥ 0), τ η/u when it drives the motor back. Arrays broadcast."""
    motoring = load * speed >= 0
    return np.where(motoring, load / (ratio * efficiency), load * efficiency / ratio)


def motor_loads(mech: Mechanism, v, a, tau) -> MotorLoads:
    """Motor torques and speeds for joint velocities v, accelerations a and joint torques τ (from the dynamics).

    τ_m = J_rotor·u·q̈ + τ_load/(u·η) when motoring, J_rotor·u·q̈ + τ_load·η/u when back-driven, + B·ω_m + T_c,
    with τ_load = τ − J_rotor·u²·q̈ (the reflected rotor inertia is counted once: in τ through the armature, and
    taken back out of what the transmission carries).
    """
    single = np.ndim(v) == 1
    V = np.atleast_2d(np.asarray(v, dtype=float))
    A = np.atleast_2d(np.asarray(a, dtype=float))
    T = np.atleast_2d(np.asarray(tau, dtype=float))
    if not (V.shape == A.shape == T.shape) or V.shape[1] != mech.nv:
        raise InputError(f"v, a and tau must have the same shape (N, {mech.nv})")
    ratio, efficiency, rotor = np.ones(mech.nv), np.ones(mech.nv), np.zeros(mech.nv)
    viscous, coulomb_pos, coulomb_neg = np.zeros(mech.nv), np.zeros(mech.nv), np.zeros(mech.nv)
    for name, drive in mech.drives.items():
        i = mech.model.joints[mech.joint_id(name)].idx_v
        ratio[i], efficiency[i], rotor[i] = drive.gear_ratio, drive.efficiency, drive.rotor_inertia
        viscous[i] = drive.viscous_friction
        coulomb_pos[i], coulomb_neg[i] = drive.coulomb_friction
    load = T - rotor * ratio**2 * A
    motoring = load * V >= 0
    transmitted = transmitted_torque(load, V, ratio, efficiency)
    speed = ratio * V
    friction = viscous * speed + np.where(speed > 0, coulomb_pos, np.where(speed < 0, coulomb_neg, 0.0))
    torque = rotor * ratio * A + transmitted + friction
    if single:
        return MotorLoads(torque[0], speed[0], T[0], load[0], motoring[0])
    return MotorLoads(torque, speed, T, load, motoring)


def with_payload(mech: Mechanism, mass: float, frame: str | None = None, com: Sequence[float] = (0, 0, 0),
                 inertia: Sequence[Sequence[float]] | None = None) -> Mechanism:
    """A copy of ``mech`` carrying a payload (kg) rigidly at ``frame`` (default the tool), its centre ``com`` (m)
    in that frame and its inertia (kg·m², about the centre, frame axes; default a point mass)."""
    if not mass >= 0:
        raise InputError(f"payload mass must be >= 0 kg, got {mass:g}")
    frame = frame or mech.tool_frame
    fid = mech.frame_id(frame)
    model = pin.Model(mech.model)
    placement = model.frames[fid].placement
    body = pin.Inertia(float(mass), np.asarray(com, dtype=float),
                       np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float))
    model.appendBodyToJoint(model.frames[fid].parentJoint, body, placement)
    return replace(mech, model=model, rebuild=None)


# ------------------------------------------------------------------------------------------ along a trajectory
@dataclass
class TrajectoryLoads:
    """Forces along a trajectory: ``table`` has t, every coordinate's q, q̇, q̈, the force/torque of every driven
    coordinate (``tau_<name>``), its power (``power_<name>``) and, for joints with drives, the motor torque and speed;
    ``summary`` per driven coordinate: peak and RMS force, peak speed, peak power, positive work."""

    table: "pd.DataFrame"
    summary: "pd.DataFrame"
    names: list[str]


def closed_loop_states(mech: Mechanism, trajectory) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Q, V, A): the full joint states (N, nq/nv) of a closed-loop mechanism along a trajectory of its actuated
    coordinates (assembly, velocity and acceleration analysis); an error if the motion leaves the reachable range."""
    from .sweep import sweep

    inputs = {name: trajectory.q[:, i] for i, name in enumerate(mech.actuated)}
    rates = {name: trajectory.v[:, i] for i, name in enumerate(mech.actuated)}
    accels = {name: trajectory.a[:, i] for i, name in enumerate(mech.actuated)}
    result = sweep(mech, inputs, rates=rates, accelerations=accels, points=[], measures=[])
    if len(result.failures):
        raise InputError(f"{mech.name}: the trajectory leaves the reachable range: "
                         f"{result.failures['reason'].iloc[0]}")
    return result.q, result.v, result.a


def actuator_forces(mech: Mechanism, trajectory, loads: Sequence[Sequence] | None = None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(Q, F): the joint positions (N, nq) of a closed-loop mechanism along a trajectory of its actuated
    coordinates and the actuator forces (N, n_actuated; N for a cylinder, N·m for a crank) that drive it
    (constrained inverse dynamics)."""
    Q, V, A = closed_loop_states(mech, trajectory)
    return Q, _forces(mech, Q, V, A, loads)


def holding_forces(mech: Mechanism, Q: np.ndarray, loads: Sequence[Sequence] | None = None) -> np.ndarray:
    """Actuator forces (N, n_actuated) that hold a closed-loop mechanism at rest in each assembled position of Q."""
    return _forces(mech, Q, np.zeros((len(Q), mech.nv)), np.zeros((len(Q), mech.nv)), loads)


def _forces(mech: Mechanism, Q, V, A, loads) -> np.ndarray:
    from .constrained import inverse

    return np.array([[f[n] for n in mech.actuated] for f in
                     (inverse(mech, q, v, a, loads)[0] for q, v, a in zip(Q, V, A))])


def trajectory_loads(mech: Mechanism, trajectory, loads: Sequence[Sequence] | None = None) -> TrajectoryLoads:
    """Joint (or, for a closed-loop mechanism, actuator) forces along ``trajectory`` (a
    :class:`~mechatron.motion.Trajectory` of the joints, or of the actuated coordinates of a closed-loop
    mechanism), with the drives' motor side (:func:`motor_loads`)."""
    import pandas as pd

    t = np.asarray(trajectory.t, dtype=float)
    if mech.closures:
        forces = actuator_forces(mech, trajectory, loads)[1]
        names, qs, vs, accs, taus = list(mech.actuated), trajectory.q, trajectory.v, trajectory.a, forces
        motor = None
    else:
        names = mech.joint_names
        qs, vs, accs = trajectory.q, trajectory.v, trajectory.a
        taus = inverse_dynamics(mech, qs, vs, accs, loads)
        motor = motor_loads(mech, vs, accs, taus)
    columns: dict[str, np.ndarray] = {"t": t}
    for i, name in enumerate(names):
        columns[name], columns[f"qd_{name}"], columns[f"qdd_{name}"] = qs[:, i], vs[:, i], accs[:, i]
    for i, name in enumerate(names):
        columns[f"tau_{name}"] = taus[:, i]
        columns[f"power_{name}"] = taus[:, i] * vs[:, i]
        if motor is not None and name in mech.drives:
            columns[f"motor_torque_{name}"] = motor.torque[:, i]
            columns[f"motor_speed_{name}"] = motor.speed[:, i]
    table = pd.DataFrame(columns)
    duration = t[-1] - t[0] if len(t) > 1 else 0.0
    rows = []
    for i, name in enumerate(names):
        tau, speed, power = taus[:, i], vs[:, i], taus[:, i] * vs[:, i]
        rms = float(np.sqrt(np.trapezoid(tau**2, t) / duration)) if duration > 0 else float(abs(tau[0]))
        row = {"coordinate": name, "peak_force": float(np.abs(tau).max()), "rms_force": rms,
               "peak_speed": float(np.abs(speed).max()), "peak_power": float(np.abs(power).max()),
               "positive_work": float(np.trapezoid(np.maximum(power, 0.0), t)) if len(t) > 1 else 0.0}
        if motor is not None and name in mech.drives:
            mt = motor.torque[:, i]
            row["peak_motor_torque"] = float(np.abs(mt).max())
            row["rms_motor_torque"] = float(np.sqrt(np.trapezoid(mt**2, t) / duration)) if duration > 0 else 0.0
            row["peak_motor_speed"] = float(np.abs(motor.speed[:, i]).max())
        rows.append(row)
    return TrajectoryLoads(table, pd.DataFrame(rows), names)

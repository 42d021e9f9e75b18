r"""Dynamics of the kinematic tree of a :class:`~mechatron.model.Mechanism`, from Pinocchio.

Equation of motion of the tree: M(q) q̈ + C(q, q̇) q̇ + g(q) = τ + Σ J_pᵀ F_p, with M from CRBA, the bias
h = C q̇ + g from ``nonLinearEffects``, inverse dynamics from RNEA and forward dynamics from ABA. The rotor and gear
inertia of a drive is reflected into its joint once, as Pinocchio's ``armature`` J_rotor·u² (see
:mod:`mechatron.model.dh`); efficiency and friction act outside Pinocchio, on the motor side
(:mod:`mechatron.drives.transmission`).

Every function takes one state or a batch: q of shape (nq,) or (N, nq), v and a of shape (nv,) or (N, nv).
Units: N·m for revolute and N for prismatic joints, J for energies, SI everywhere.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Mapping

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..kinematics.frames import samples
from ..model.loads import Loads, as_loads
from ..model.mechanism import Mechanism

Array = NDArray[np.float64]


def external_forces(mech: Mechanism, q: ArrayLike, loads: Loads) -> list[pin.Force] | None:
    """Pinocchio's per-joint external forces (local frames, N and N·m about the joint origin) at the configuration
    q for :class:`~mechatron.model.loads.Load` s: world forces (N) and moments (N·m) applied at frames' origins;
    ``None`` without loads."""
    loads = as_loads(loads)
    if not loads:
        return None
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q)
    out = [pin.Force.Zero() for _ in range(model.njoints)]
    for load in loads:
        fid = frame_index(mech, load.frame)
        joint = model.frames[fid].parentJoint
        placement = pin.updateFramePlacement(model, data, fid)
        oMi = data.oMi[joint]
        # a world force f at point p and moment m, expressed in the joint frame about its origin: m + r × f
        r = placement.translation - oMi.translation
        out[joint] += pin.Force(oMi.rotation.T @ load.force,
                                oMi.rotation.T @ (load.moment + pin.skew(r) @ load.force))
    return out


def frame_index(mech: Mechanism, name: str) -> int:
    """``mech.frame_id(name)``, remembered in the mechanism's cache (the loads of a simulation ask at every
    stage)."""
    known = mech.cached("frame_index", dict)
    if name not in known:
        known[name] = mech.frame_id(name)
    return known[name]


def generalized_forces(mech: Mechanism, q: ArrayLike, forces: Mapping[str, float] | None = None,
                       loads: Loads = None) -> Array:
    """τ + Q (nv,; N, N·m) at the configuration q: forces or torques on named joint coordinates plus the
    generalized forces Q = Σ J_pᵀ [F_p; M_p] of external ``loads``, J_p the Jacobian of the load's frame origin in
    world axes (Q·q̇ is the loads' power, [Egorov, 6.15])."""
    tau = np.zeros(mech.nv)
    for name, value in (forces or {}).items():
        tau[mech.model.joints[mech.joint_id(name)].idx_v] += value
    for load in as_loads(loads):
        J = pin.computeFrameJacobian(mech.model, mech.data, q, frame_index(mech, load.frame),
                                     pin.LOCAL_WORLD_ALIGNED)
        tau += J[:3].T @ load.force + J[3:].T @ load.moment
    return tau


def joint_space_inertia(model: pin.Model, data: pin.Data, q: ArrayLike) -> Array:
    """M(q) (nv, nv; kg, kg·m, kg·m²) from CRBA, whose upper triangle is the matrix: symmetrised from it."""
    M = pin.crba(model, data, q)
    return np.where(_below_diagonal(model.nv), M.T, M)


@functools.lru_cache(maxsize=32)
def _below_diagonal(n: int) -> NDArray[np.bool_]:
    """The (n, n) mask of the entries below the diagonal."""
    return np.tri(n, k=-1, dtype=bool)


#: Batches at least this long go to Pinocchio's parallel RNEA/ABA (C++ loop over the samples, all cores).
PARALLEL_BATCH = 64


def _model_pool(mech: Mechanism) -> pin.ModelPool:
    """A pool of model/data copies for Pinocchio's parallel algorithms, kept in the mechanism's cache."""
    return mech.cached("model_pool", lambda: pin.ModelPool(mech.model, _threads()))


def _threads() -> int:
    return max(1, min(os.cpu_count() or 1, 16))


def _parallel(algorithm, mech: Mechanism, Q: np.ndarray, V: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Run a batch through ``rneaInParallel``/``abaInParallel`` (arrays (N, n) in and out; Pinocchio takes the
    transposed, column-major views)."""
    out = np.empty((len(Q), mech.nv))
    algorithm(_threads(), _model_pool(mech), np.ascontiguousarray(Q).T, np.ascontiguousarray(V).T,
              np.ascontiguousarray(X).T, out.T)
    return out


def inverse_dynamics(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, loads: Loads = None) -> Array:
    """Joint torques/forces τ = M q̈ + C q̇ + g − Σ J_pᵀ F_p (N·m, N; RNEA), reflected drive inertia included.

    Args:
        q: Configuration(s) (nq,) or (N, nq) (Pinocchio's q: a continuous joint's (cos θ, sin θ)).
        v, a: Joint velocities (rad/s, m/s) and accelerations (rad/s², m/s²), (nv,) or (N, nv).
        loads: External loads acting on the mechanism (:class:`~mechatron.model.loads.Load`: force in N and moment
            in N·m, world axes, at a frame's origin).

    Returns:
        (nv,) or (N, nv). Long batches without loads run in Pinocchio's parallel RNEA.
    """
    single, Q, (V, A) = samples(mech, q, v, a)
    model, data = mech.model, mech.data
    loads = as_loads(loads)
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


def forward_dynamics(mech: Mechanism, q: ArrayLike, v: ArrayLike, tau: ArrayLike) -> Array:
    """Joint accelerations q̈ = M⁻¹(τ − C q̇ − g) (rad/s², m/s²; ABA) for joint torques/forces τ (N·m, N) at the
    state (q, q̇): (nv,) or (N, nv)."""
    single, Q, (V, T) = samples(mech, q, v, tau)
    if len(Q) >= PARALLEL_BATCH:
        return _parallel(pin.abaInParallel, mech, Q, V, T)
    model, data = mech.model, mech.data
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.aba(model, data, Q[i], V[i], T[i])
    return out[0] if single else out


def mass_matrix(mech: Mechanism, q: ArrayLike) -> Array:
    """Joint-space inertia matrix M(q) (kg, kg·m, kg·m²; CRBA, symmetrised), including the armature: (nv, nv) or
    (N, nv, nv). ½ q̇ᵀ M q̇ is the kinetic energy [Egorov, 6.2]."""
    single, Q, _ = samples(mech, q)
    model, data = mech.model, mech.data
    out = np.empty((len(Q), mech.nv, mech.nv))
    for i in range(len(Q)):
        out[i] = joint_space_inertia(model, data, Q[i])
    return out[0] if single else out


def bias_forces(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array:
    """h(q, q̇) = C(q, q̇) q̇ + g(q) (N·m, N): the torques for zero acceleration."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.nonLinearEffects(mech.model, mech.data, Q[i], V[i])
    return out[0] if single else out


def gravity_torques(mech: Mechanism, q: ArrayLike) -> Array:
    """g(q) (N·m, N): the joint torques that hold the mechanism against gravity, g = ∂V/∂q."""
    single, Q, _ = samples(mech, q)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.computeGeneralizedGravity(mech.model, mech.data, Q[i])
    return out[0] if single else out


def kinetic_energy(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array | float:
    """T = ½ q̇ᵀ M q̇ (J), rotors included through the armature: [Egorov, 6.2] summed over the links."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.array([pin.computeKineticEnergy(mech.model, mech.data, Q[i], V[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def potential_energy(mech: Mechanism, q: ArrayLike) -> Array | float:
    """Gravitational potential energy (J), zero at the world origin's height."""
    single, Q, _ = samples(mech, q)
    out = np.array([pin.computePotentialEnergy(mech.model, mech.data, Q[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def mechanical_energy(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array | float:
    """T + V (J): constant along an unforced, undamped motion."""
    return kinetic_energy(mech, q, v) + potential_energy(mech, q)


def joint_wrenches(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, loads: Loads = None) -> Array:
    """Force (N) and moment (N·m) transmitted through every joint of the tree, from the parent body to the child
    subtree, in world axes about the joint's origin, at one state: array (njoints − 1, 6) = [force; moment] per
    joint (the reactions in the pairs of a serial chain, [Egorov, 5.1–5.2]; the joint's torque is the moment's
    component on its axis)."""
    single, Q, (V, A) = samples(mech, q, v, a)
    if not single:
        raise InputError("joint_wrenches takes one state")
    return transmitted_wrenches(mech, Q[0], V[0], A[0], loads)


def transmitted_wrenches(mech: Mechanism, q: Array, v: Array, a: Array, loads: Loads = None) -> Array:
    """(njoints − 1, 6): [force; moment] (N, N·m, world axes, about the joint origin) that each tree joint transmits
    to its child subtree, from one RNEA pass with the loads as external forces."""
    model, data = mech.model, mech.data
    fext = external_forces(mech, q, loads)
    if fext is None:
        pin.rnea(model, data, q, v, a)
    else:
        pin.rnea(model, data, q, v, a, fext)
    pin.updateGlobalPlacements(model, data)  # RNEA leaves the joints' world placements (oMi) as they were
    out = np.empty((model.njoints - 1, 6))
    for j in range(1, model.njoints):
        R = data.oMi[j].rotation
        out[j - 1, :3] = R @ data.f[j].linear
        out[j - 1, 3:] = R @ data.f[j].angular
    return out

r"""Kinematics of a :class:`~mechatron.model.Mechanism`, all from Pinocchio.

Every function takes one configuration ``q`` of shape (nq,) or a batch of shape (N, nq) (with velocities ``v`` and
accelerations ``a`` of shape (nv,) or (N, nv)) and returns one result or an array of N results. Positions are in
metres, angles in radians, everything is expressed in the world (base) frame unless said otherwise. A ``frame``
left out is the mechanism's tool frame (``mech.tool_frame``: a robot file's ``tool``, a mechanism file's ``tool``
point).

The equations of [Egorov, 4.44–4.57]: the position of a point M is r = B_{0,i} r_i ([Egorov, 4.44–4.45]); its
velocity v = Σ_k ∂r/∂q_k q̇_k = J q̇ ([Egorov, 4.46–4.48]); its acceleration a = J q̈ + Σ_k Σ_s ∂²r/∂q_k∂q_s q̇_k q̇_s
([Egorov, 4.49–4.50]); the angular velocity of link i is Ω_i = Σ_{j≤i} σ_j z_{j-1} q̇_j ([Egorov, 4.56]) and its
angular acceleration E_i = dΩ_i/dt ([Egorov, 4.57]), σ_j = 1 for a revolute and 0 for a prismatic pair.
"""

from __future__ import annotations

import math
from typing import Literal, cast

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism

Reference = Literal["world_aligned", "local", "world"]
REFERENCES: dict[str, pin.ReferenceFrame] = {
    "world_aligned": pin.LOCAL_WORLD_ALIGNED,
    "local": pin.LOCAL,
    "world": pin.WORLD,
}


def reference_frame(reference: str) -> pin.ReferenceFrame:
    """Pinocchio's reference frame for ``"world_aligned"`` (origin at the frame, world axes), ``"local"`` (frame
    axes) or ``"world"`` (Pinocchio's spatial convention: origin at the world origin)."""
    try:
        return REFERENCES[reference]
    except KeyError:
        raise InputError(f"unknown reference {reference!r}; expected one of: {', '.join(REFERENCES)}") from None


def samples(mech: Mechanism, q: ArrayLike, *rates: ArrayLike
            ) -> tuple[bool, NDArray[np.float64], list[NDArray[np.float64]]]:
    """Validate shapes: (is a single sample, Q of shape (N, nq), each rate of shape (N, nv)); q in Pinocchio's
    configuration (nq,) or (N, nq), rates (joint velocities, accelerations) (nv,) or (N, nv)."""
    q = mech.check_configuration(q)
    single = q.ndim == 1
    Q = np.atleast_2d(q)
    if Q.ndim != 2:
        raise InputError(f"q must have shape (nq,) or (N, nq), got {q.shape}")
    out = []
    for name, rate in zip(("v", "a"), rates):
        arr = np.atleast_2d(np.asarray(rate, dtype=float))
        if arr.shape != (len(Q), mech.nv):
            raise InputError(f"{name} must have shape {(mech.nv,) if single else (len(Q), mech.nv)} to match q, "
                             f"got {np.shape(rate)}")
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} must be finite")
        out.append(arr)
    return single, Q, out


def lean_samples(mech: Mechanism, q: ArrayLike, *rates: ArrayLike
                 ) -> tuple[bool, NDArray[np.float64], list[NDArray[np.float64]]]:
    """:func:`samples` (single?, Q (N, nq), rates (N, nv)) with a shortcut for what a
    loop over states passes: float64 arrays of the right shapes whose sums are finite (a finite sum has only finite
    entries; a sum that overflows falls back to the full check)."""
    nq, nv = mech.nq, mech.nv
    if type(q) is not np.ndarray or q.dtype != np.float64 or q.ndim not in (1, 2) or q.shape[-1] != nq:
        return samples(mech, q, *rates)
    shape = q.shape[:-1] + (nv,)
    for x in rates:
        if type(x) is not np.ndarray or x.dtype != np.float64 or x.shape != shape:
            return samples(mech, q, *rates)
    arrays = cast("tuple[NDArray[np.float64], ...]", (q, *rates))  # each a float64 array of its shape (above)
    for x in arrays:
        if not math.isfinite(x.sum() if x.size > 64 else sum(x.tolist() if x.ndim == 1 else x.ravel().tolist())):
            return samples(mech, q, *rates)
    return q.ndim == 1, q.reshape(-1, nq), [x.reshape(-1, nv) for x in arrays[1:]]


def _offset(offset: ArrayLike | None) -> NDArray[np.float64] | None:
    if offset is None:
        return None
    p = np.asarray(offset, dtype=float)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise InputError(f"offset must be 3 finite coordinates (m) in the frame, got {offset!r}")
    return p


# ------------------------------------------------------------------------------------------------- positions
def frame_placement(mech: Mechanism, q: ArrayLike, frame: str | None = None) -> pin.SE3:
    """Placement (SE3; translation in m) of ``frame`` (default the mechanism's tool frame, ``mech.tool_frame``: a
    robot file's ``tool``, a mechanism file's ``tool`` point) in the world at one configuration q (nq,): B_{0,i} of
    [Egorov, 4.45] for a DH arm."""
    q = mech.check_configuration(q)
    if q.ndim != 1:
        raise InputError("frame_placement takes one configuration; use frame_position/frame_rotation for a batch")
    fid = mech.frame_id(frame or mech.tool_frame)
    pin.forwardKinematics(mech.model, mech.data, q)
    return pin.updateFramePlacement(mech.model, mech.data, fid).copy()


def _placements(mech: Mechanism, q: ArrayLike, frame: str | None
                ) -> tuple[bool, NDArray[np.float64], NDArray[np.float64]]:
    single, Q, _ = samples(mech, q)
    fid = mech.frame_id(frame or mech.tool_frame)
    model, data = mech.model, mech.data
    homogeneous = np.empty((len(Q), 4, 4))
    for i, qi in enumerate(Q):
        pin.forwardKinematics(model, data, qi)
        homogeneous[i] = pin.updateFramePlacement(model, data, fid).homogeneous
    return single, homogeneous[:, :3, 3].copy(), homogeneous[:, :3, :3].copy()


def frame_position(mech: Mechanism, q: ArrayLike, frame: str | None = None) -> NDArray[np.float64]:
    """Position (m) of the origin of ``frame`` in the world ([Egorov, 4.44]) at q (nq,) or (N, nq): (3,) or
    (N, 3)."""
    single, positions, _ = _placements(mech, q, frame)
    return positions[0] if single else positions


def frame_rotation(mech: Mechanism, q: ArrayLike, frame: str | None = None) -> NDArray[np.float64]:
    """Rotation matrix of ``frame`` in the world (the 3×3 block of B_{0,i}, [Egorov, 4.45]) at q (nq,) or (N, nq):
    (3, 3) or (N, 3, 3)."""
    single, _, rotations = _placements(mech, q, frame)
    return rotations[0] if single else rotations


# ------------------------------------------------------------------------------------------------- Jacobians
def fk_and_jacobian(mech: Mechanism, q: ArrayLike, frame: str | None = None, reference: Reference = "world_aligned"
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Positions (m; N, 3), rotations (N, 3, 3) and 6×nv Jacobians (N, 6, nv) of ``frame`` over a batch ``q``
    (N, nq).

    One Pinocchio call (``computeFrameJacobian``) per sample gives both the placement and the Jacobian. The Jacobian
    maps q̇ (rad/s, m/s) to the frame's twist [v (m/s); ω (rad/s)] in ``reference`` (:func:`reference_frame`); its
    linear rows in ``"world_aligned"`` are ∂r/∂q of [Egorov, 4.47].
    """
    _, Q, _ = lean_samples(mech, q)
    fid = mech.frame_id(frame or mech.tool_frame)
    rf = reference_frame(reference)
    model, data = mech.model, mech.data
    n = len(Q)
    compute = pin.computeFrameJacobian
    if n == 1:  # one configuration: no loop, no preallocation
        jacobian = compute(model, data, Q[0], fid, rf)
        homogeneous = data.oMf[fid].homogeneous
        return homogeneous[None, :3, 3], homogeneous[None, :3, :3], jacobian[None]
    homogeneous, jacobians = np.empty((n, 4, 4)), np.empty((n, 6, mech.nv))
    placement = data.oMf[fid]  # a view into data, updated by every call below
    for i, qi in enumerate(Q):
        jacobians[i] = compute(model, data, qi, fid, rf)
        homogeneous[i] = placement.homogeneous  # one conversion instead of two (translation, rotation)
    return homogeneous[:, :3, 3].copy(), homogeneous[:, :3, :3].copy(), jacobians


def frame_jacobian(mech: Mechanism, q: ArrayLike, frame: str | None = None,
                   reference: Reference = "world_aligned") -> NDArray[np.float64]:
    """6×nv Jacobian of ``frame`` (default the mechanism's tool frame, ``mech.tool_frame``) at q (nq,) or (N, nq):
    linear rows (m/s per unit joint rate) first, then angular rows (rad/s per unit joint rate) ([Egorov, 4.47]):
    (6, nv) or (N, 6, nv). See :func:`fk_and_jacobian`."""
    single = np.ndim(q) == 1
    jacobians = fk_and_jacobian(mech, q, frame or mech.tool_frame, reference)[2]
    return jacobians[0] if single else jacobians


def point_jacobian(mech: Mechanism, q: ArrayLike, frame: str | None = None, offset: ArrayLike | None = None
                   ) -> NDArray[np.float64]:
    """∂r/∂q (3×nv, world axes; m/rad or m/m) of a point fixed to the body of ``frame`` ([Egorov, 4.47]) at q
    (nq,) or (N, nq): (3, nv) or (N, 3, nv).

    Args:
        offset: Coordinates (m) of the point in ``frame``; default the frame's origin.
    """
    p = _offset(offset)
    single = np.ndim(q) == 1
    _, rotations, jacobians = fk_and_jacobian(mech, q, frame, "world_aligned")
    out = jacobians[:, :3, :].copy()
    if p is not None:
        r = rotations @ p  # (N, 3): the point relative to the frame origin, world axes
        out -= np.cross(r[:, :, None], jacobians[:, 3:, :], axis=1)  # v_p = v_o + ω × r = v_o − r × ω
    return out[0] if single else out


# ----------------------------------------------------------------------------------- velocities, accelerations
def _frame_motion(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike | None, frame: str | None,
                  offset: ArrayLike | None = None):
    """World linear velocity of the point, angular velocity, and (if ``a`` is given) the point's classical linear
    acceleration and the angular acceleration of the body of ``frame``; each (N, 3)."""
    p = _offset(offset)
    single, Q, rates = samples(mech, q, v) if a is None else samples(mech, q, v, a)
    fid = mech.frame_id(frame or mech.tool_frame)
    model, data = mech.model, mech.data
    n = len(Q)
    lin_v, ang_v = np.empty((n, 3)), np.empty((n, 3))
    lin_a, ang_a = (np.empty((n, 3)), np.empty((n, 3))) if a is not None else (None, None)
    for i in range(n):
        if a is None:
            pin.forwardKinematics(model, data, Q[i], rates[0][i])
        else:
            pin.forwardKinematics(model, data, Q[i], rates[0][i], rates[1][i])
        placement = pin.updateFramePlacement(model, data, fid)
        twist = pin.getFrameVelocity(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
        lin_v[i], ang_v[i] = twist.linear, twist.angular
        if lin_a is not None and ang_a is not None:  # a is given
            acc = pin.getFrameClassicalAcceleration(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            lin_a[i], ang_a[i] = acc.linear, acc.angular
        if p is not None:
            r = placement.rotation @ p
            w = ang_v[i]
            lin_v[i] += np.cross(w, r)
            if lin_a is not None and ang_a is not None:
                lin_a[i] += np.cross(ang_a[i], r) + np.cross(w, np.cross(w, r))
    return single, lin_v, ang_v, lin_a, ang_a


def point_velocity(mech: Mechanism, q: ArrayLike, v: ArrayLike, frame: str | None = None,
                   offset: ArrayLike | None = None) -> NDArray[np.float64]:
    """Velocity (m/s, world) of a point of the body of ``frame`` at q (nq,) moving with joint velocity v (nv,;
    rad/s, m/s): v = J q̇ ([Egorov, 4.47–4.48]). (3,), or (N, 3) for batches (N, nq), (N, nv).

    Args:
        offset: Coordinates (m) of the point in ``frame``; default the frame's origin.
    """
    single, lin_v, *_ = _frame_motion(mech, q, v, None, frame, offset)
    return lin_v[0] if single else lin_v


def point_acceleration(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, frame: str | None = None,
                       offset: ArrayLike | None = None) -> NDArray[np.float64]:
    """Acceleration (m/s², world) of a point of the body of ``frame`` at q (nq,) with joint velocity v and
    acceleration a (nv,; rad/s, m/s; rad/s², m/s²): a = J q̈ + Σ_k Σ_s ∂²r/∂q_k∂q_s q̇_k q̇_s ([Egorov, 4.49–4.50]),
    the classical (not spatial) acceleration. (3,), or (N, 3) for batches.

    Args:
        offset: Coordinates (m) of the point in ``frame``; default the frame's origin.
    """
    single, _, _, lin_a, _ = _frame_motion(mech, q, v, a, frame, offset)
    return lin_a[0] if single else lin_a


def angular_velocity(mech: Mechanism, q: ArrayLike, v: ArrayLike, link: str) -> NDArray[np.float64]:
    """Absolute angular velocity Ω (rad/s, world) of the body carrying the frame ``link`` at q (nq,) with joint
    velocity v (nv,) ([Egorov, 4.56]): (3,), or (N, 3) for batches."""
    single, _, ang_v, _, _ = _frame_motion(mech, q, v, None, link)
    return ang_v[0] if single else ang_v


def angular_acceleration(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, link: str
                         ) -> NDArray[np.float64]:
    """Absolute angular acceleration E = dΩ/dt (rad/s², world) of the body carrying the frame ``link`` at q (nq,)
    with joint velocity v and acceleration a (nv,) ([Egorov, 4.57]): (3,), or (N, 3) for batches."""
    single, _, _, _, ang_a = _frame_motion(mech, q, v, a, link)
    return ang_a[0] if single else ang_a


def _link_motion(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike | None = None
                 ) -> tuple[bool, NDArray[np.float64], NDArray[np.float64] | None]:
    """World angular velocity and acceleration of every joint's body: (N, njoints−1, 3) each."""
    single, Q, rates = samples(mech, q, v) if a is None else samples(mech, q, v, a)
    model, data = mech.model, mech.data
    n, nb = len(Q), model.njoints - 1
    omega = np.empty((n, nb, 3))
    epsilon = np.empty((n, nb, 3)) if a is not None else None
    for i in range(n):
        if a is None:
            pin.forwardKinematics(model, data, Q[i], rates[0][i])
        else:
            pin.forwardKinematics(model, data, Q[i], rates[0][i], rates[1][i])
        for j in range(1, model.njoints):
            rotation = data.oMi[j].rotation
            omega[i, j - 1] = rotation @ data.v[j].angular
            if epsilon is not None:
                # The angular part of the body's spatial acceleration is Rᵀ·dΩ/dt in body axes.
                epsilon[i, j - 1] = rotation @ data.a[j].angular
    return single, omega, epsilon


def link_angular_velocities(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """Ω_i (rad/s, world) of every link i, in the order of ``mech.link_names`` ([Egorov, 4.56]), at q (nq,) with
    joint velocity v (nv,): (n, 3), or (N, n, 3) for batches."""
    single, omega, _ = _link_motion(mech, q, v)
    return omega[0] if single else omega


def link_angular_accelerations(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> NDArray[np.float64]:
    """E_i (rad/s², world) of every link i, in the order of ``mech.link_names`` ([Egorov, 4.57]), at q (nq,) with
    joint velocity v and acceleration a (nv,): (n, 3), or (N, n, 3) for batches."""
    single, _, epsilon = _link_motion(mech, q, v, a)
    assert epsilon is not None  # a is given
    return epsilon[0] if single else epsilon

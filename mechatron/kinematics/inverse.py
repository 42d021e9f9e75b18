r"""Inverse kinematics of a serial chain on its Pinocchio model: the configuration at which a frame reaches a target
position (m, world axes) and, if one is given, a target orientation.

Damped least squares (Levenberg–Marquardt) on the frame Jacobian: with the error

    e(q) = [p* − p(q);  log₃(R* R(q)ᵀ)]      (m; rad, world axes — the second block only with a target R*)

and J(q) the matching rows of ``pin.computeFrameJacobian`` in ``LOCAL_WORLD_ALIGNED`` (∂p/∂q and the angular
velocity per unit joint rate, world axes), one step is

    Δq = (JᵀJ + λ² I)⁻¹ Jᵀ e,   λ² = μ ‖e‖²,   q ← q ⊕ Δq (``pin.integrate``).

A step that does not reduce ‖e‖ is refused and μ is multiplied by 10; an accepted one divides μ by 3, so that near
the solution the step is Newton's and converges quadratically. The iteration starts from a seed and stays on the
seed's branch (elbow up or down) as long as the seed is near the solution: a path is solved point after point, each
from the previous solution. It stops when ‖e‖ ≤ ``tolerance`` or when no step reduces ‖e‖ any more; the caller
reads the residual ‖e‖ to tell a reached target from an unreachable one. Our method, not a standard's.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..model.mechanism import Mechanism

#: ‖e‖ (m, rad) at which a target counts as reached.
TOLERANCE = 1e-12
#: The most Levenberg–Marquardt iterations of one solve.
MAX_ITERATIONS = 200
#: How far (rad, m) a solution may pass a joint's position limit in :func:`limit_violation` (rounding).
LIMIT_TOLERANCE = 1e-9


def pose_error(model: pin.Model, data: pin.Data, q: np.ndarray, fid: int, position: np.ndarray,
               rotation: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """(e, J) at q (nq,): the error e of the module docstring (3 or 6 values: m, rad) and the matching rows of the
    frame Jacobian (3 or 6, nv) of frame ``fid``, world-aligned."""
    jacobian = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
    placement = data.oMf[fid]
    error = position - placement.translation
    if rotation is None:
        return error, jacobian[:3]
    return np.concatenate([error, pin.log3(rotation @ placement.rotation.T)]), jacobian


def inverse_kinematics(mech: Mechanism, position: ArrayLike, seed: ArrayLike, *, frame: str | None = None,
                       rotation: ArrayLike | None = None, tolerance: float = TOLERANCE,
                       data: pin.Data | None = None) -> tuple[NDArray[np.float64], float]:
    """(q, residual): the configuration q (nq,) nearest the ``seed`` configuration (nq,) in the sense of the
    module docstring's iteration at which ``frame`` (default the tool frame) is at ``position`` (3,) (m, world) and,
    if ``rotation`` (3×3, world) is given, has that orientation; ``residual`` is ‖e(q)‖ (m, rad), ≤ ``tolerance``
    when the target is reached. ``data``: a ``pin.Data`` of the model to work in (default a new one)."""
    model = mech.model
    data = data if data is not None else model.createData()
    fid = mech.frame_id(frame or mech.tool_frame)
    target = np.asarray(position, dtype=float)
    orientation = None if rotation is None else np.asarray(rotation, dtype=float)
    q = np.asarray(seed, dtype=float).copy()
    error, jacobian = pose_error(model, data, q, fid, target, orientation)
    norm = float(np.linalg.norm(error))
    mu = 1e-2
    for _ in range(MAX_ITERATIONS):
        if norm <= tolerance:
            break
        normal = jacobian.T @ jacobian
        gradient = jacobian.T @ error
        while mu < 1e12:
            step = np.linalg.lstsq(normal + mu * norm**2 * np.eye(mech.nv), gradient, rcond=None)[0]
            trial = pin.integrate(model, q, step)
            trial_error, trial_jacobian = pose_error(model, data, trial, fid, target, orientation)
            trial_norm = float(np.linalg.norm(trial_error))
            if trial_norm < norm:
                q, error, jacobian, norm = trial, trial_error, trial_jacobian, trial_norm
                mu = max(mu / 3, 1e-12)
                break
            mu *= 10
        else:
            break  # no step reduces the error: the nearest the frame comes to the target
    return q, norm


def _limited(mech: Mechanism):
    """(joint name, its coordinate's index in q, lower, upper) of every joint of one coordinate (limits may be
    infinite)."""
    model = mech.model
    for name in mech.joint_names:
        joint = model.joints[mech.joint_id(name)]
        if joint.nq == 1:  # a continuous or multi-coordinate joint has no position limit of one coordinate
            i = joint.idx_q
            yield name, i, float(model.lowerPositionLimit[i]), float(model.upperPositionLimit[i])


def into_limits(mech: Mechanism, q: ArrayLike) -> NDArray[np.float64]:
    """q (nq,) with every revolute joint's angle outside its finite limits turned by a whole number of turns,
    q + 2π k, where that brings it inside: the same pose (an inverse kinematics solution from a seed may come out a
    turn away, ``pin.integrate`` does not wrap angles). Other values as they are."""
    out: NDArray[np.float64] = np.asarray(q, dtype=float).copy()
    for name, i, low, high in _limited(mech):
        if mech.joint_kind(name) != "revolute" or not (np.isfinite(low) and np.isfinite(high)) or low <= out[i] <= high:
            continue
        turned = low + (out[i] - low) % (2 * np.pi)
        if turned <= high:
            out[i] = turned
    return out


def limit_violation(mech: Mechanism, q: ArrayLike, tolerance: float = LIMIT_TOLERANCE) -> str | None:
    """The first joint of one coordinate whose value in the configuration q (nq,) is outside the model's finite
    position limits (``lowerPositionLimit``, ``upperPositionLimit``) by more than ``tolerance``, as words (``joint
    q2 at -100°, outside its limits [-90, 90]°,``; degrees for an angle, mm for a length); ``None`` when every
    joint is within its limits. The iteration of :func:`inverse_kinematics` knows no limits: the caller checks."""
    q = np.asarray(q, dtype=float)
    for name, i, low, high in _limited(mech):
        value = float(q[i])
        if not (np.isfinite(low) and value < low - tolerance or np.isfinite(high) and value > high + tolerance):
            continue
        scale, unit = (180 / np.pi, "°") if mech.joint_kind(name) == "revolute" else (1e3, " mm")
        return (f"joint {name} at {value * scale:.6g}{unit}, outside its limits [{low * scale:.6g}, "
                f"{high * scale:.6g}]{unit},")
    return None

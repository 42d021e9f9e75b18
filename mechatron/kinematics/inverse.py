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

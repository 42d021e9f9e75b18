r"""Sensitivities of a frame's whole pose — position and orientation — to the parameters and the coordinates.

The 6-D counterpart of :func:`~mechatron.accuracy.sensitivity.sensitivities`, for calibration: at each
configuration the world-aligned twist [v; ω] of the frame per unit of every parameter l_k and of every coordinate
q_j, so that to first order

    p(l + Δl, q + Δq) = p + Σ v_k Δl_k + Σ v_j Δq_j ,   R(l + Δl, q + Δq) = exp([Σ ω_k Δl_k + Σ ω_j Δq_j]×) R .

The parameter columns are :func:`~mechatron.accuracy.sensitivity.frame_parameter_twists` (the placement twists
through Pinocchio's frame kinematic regressor), the coordinate columns the frame Jacobian's (world-aligned); in a
closed loop the dependent coordinates follow by the implicit-function theorem
(:func:`~mechatron.accuracy.sensitivity.loop_derivatives`): d/dl = ξ_l + J ∂q/∂l, d/dq_a = J S.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..kinematics.loops import loop_solver
from ..model.derivatives import placement_derivatives
from ..model.mechanism import Mechanism
from .sensitivity import LWA, frame_parameter_twists, loop_derivatives

Floats = NDArray[np.float64]


def pose_sensitivities(mech: Mechanism, q: ArrayLike, frame: str, parameters: Sequence[str],
                       coordinates: Sequence[str]) -> tuple[Floats, list[pin.SE3]]:
    """(twists (N, 6, n_l + n_c), placements): the world-aligned twist [v; ω] of ``frame`` per unit of each of
    ``parameters`` then ``coordinates`` (m/m, rad/m, m/rad, rad/rad) at the configurations ``q`` ((N, nq),
    assembled ones for a closed loop), and the frame's placement (world) at each."""
    Q = np.atleast_2d(np.asarray(q, dtype=float))
    fid = mech.frame_id(frame)
    n_l = len(parameters)
    derivatives = placement_derivatives(mech, list(parameters))
    columns = [mech.model.joints[mech.joint_id(c)].idx_v for c in coordinates]
    solver = loop_solver(mech) if mech.closures else None
    model, data = mech.model, mech.data
    out = np.empty((len(Q), 6, n_l + len(coordinates)))
    placements = []
    for i, qi in enumerate(Q):
        J = pin.computeFrameJacobian(model, data, qi, fid, LWA)
        pin.updateFramePlacements(model, data)
        placements.append(data.oMf[fid].copy())
        twists = frame_parameter_twists(mech, derivatives, fid) if n_l else np.zeros((6, 0))
        if solver is None:
            out[i, :, :n_l] = twists
            out[i, :, n_l:] = J[:, columns]
            continue
        dq_dl, S = loop_derivatives(mech, solver, derivatives, qi)
        out[i, :, :n_l] = twists + J @ dq_dl
        actuated = {name: k for k, name in enumerate(mech.actuated)}
        out[i, :, n_l:] = (J @ S)[:, [actuated[c] for c in coordinates]]
    return out, placements

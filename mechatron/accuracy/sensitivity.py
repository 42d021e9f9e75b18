r"""Sensitivities of a point's position to the geometric parameters and the coordinates [Egorov, 8.3–8.5].

The position of the output point r(l, q) [Egorov, 8.1] depends on the named geometric parameters l of the mechanism
(DH a, d, α, θ; URDF joint origins; linkage lengths and pin coordinates) and on the coordinates q. To first order
[Egorov, 8.4]

    Δr = Σ_i ∂r/∂l_i Δl_i + Σ_j ∂r/∂q_j Δq_j ,

and per axis Δx, Δy, Δz [Egorov, 8.5]. How the derivatives are computed:

- a parameter l_k moves the constant placements of the model: every joint placement M_j and frame placement M_f
  turns into M exp(ξ Δl_k) (a local twist ξ per placement and parameter). The twists depend only on how the model is
  built from its parameters (:func:`~mechatron.model.derivatives.placement_derivatives`);
- at a configuration, Pinocchio's frame kinematic regressor maps the joint-placement twists to the motion of the
  output frame (``computeFrameKinematicRegressor``), the frame's own placement twist adds R_f ξ_f, and the frame
  Jacobian gives ∂r/∂q, one column per joint coordinate (a continuous joint, whose q is (cos θ, sin θ), has one
  coordinate, its angle: the Jacobian's velocity column);
- in a closed loop the dependent coordinates move to keep the loops closed (implicit-function theorem on the
  closures Φ(q, l) = 0): ∂q_d/∂l = −J_d⁻¹ ∂Φ/∂l and ∂q_d/∂q_a = −J_d⁻¹ J_a, with ∂Φ/∂l from the same placement
  twists of the closures' frames (:func:`loop_derivatives`). The coordinates with errors are then the actuated ones.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..kinematics.loops import LoopSolver, loop_solver
from ..model.derivatives import PlacementDerivatives, placement_derivatives
from ..model.mechanism import Mechanism

LWA = pin.LOCAL_WORLD_ALIGNED


def frame_parameter_twists(mech: Mechanism, derivatives: PlacementDerivatives, frame: int) -> NDArray[np.float64]:
    """World-aligned twists (6, n_l) of frame ``frame`` (index) per unit of each parameter (m/m, rad/m, m/rad,
    rad/rad) at the configuration last given to ``mech.data`` (forward kinematics and frame placements up to
    date)."""
    model, data = mech.model, mech.data
    n_l = len(derivatives.names)
    if not n_l:
        return np.zeros((6, 0))
    regressor = pin.computeFrameKinematicRegressor(model, data, frame, LWA)  # (6, 6 (njoints − 1))
    joint_twists = derivatives.joints[:, 1:, :].reshape(n_l, -1).T  # (6 (nj − 1), n_l)
    out = regressor @ joint_twists
    rotation = data.oMf[frame].rotation
    own = derivatives.frames[:, frame, :]  # (n_l, 6)
    out[:3] += rotation @ own[:, :3].T
    out[3:] += rotation @ own[:, 3:].T
    return out


@dataclass(frozen=True)
class Sensitivities:
    """∂r/∂e of a point for every error source e at N configurations: ``matrix`` (N, 3, n_e) in m per unit of the
    source (m/m, m/rad); ``sources`` names the columns (parameters first, then coordinates); ``positions`` (N, 3) the
    nominal positions; ``q`` (N, nq) the configurations."""

    sources: tuple[str, ...]
    matrix: NDArray[np.float64]
    positions: NDArray[np.float64]
    q: NDArray[np.float64]

    def column(self, name: str) -> NDArray[np.float64]:
        """∂r/∂e (N, 3) of the source called ``name``."""
        return self.matrix[:, :, self.sources.index(name)]


def coordinate_names(mech: Mechanism) -> list[str]:
    """The coordinates that can carry errors: every joint of a serial mechanism, the actuated ones of a closed loop."""
    return list(mech.actuated) if mech.closures else mech.joint_names


def resolve_coordinate(mech: Mechanism, name: str) -> str | None:
    """The coordinate a source name means (its own name, or ``qk`` for the k-th), or None if it is not one."""
    names = coordinate_names(mech)
    if name in names:
        return name
    if name.startswith("q") and name[1:].isdigit() and 1 <= int(name[1:]) <= len(names):
        return names[int(name[1:]) - 1]
    return None


def sensitivities(mech: Mechanism, q: ArrayLike, frame: str | None = None, parameters: Sequence[str] | None = None,
                  coordinates: Sequence[str] | None = None) -> Sensitivities:
    """∂r/∂l and ∂r/∂q [Egorov, 8.4] of ``frame`` (default the tool frame) at the configurations ``q`` ((nq,) or
    (N, nq), assembled ones for a closed loop), for ``parameters`` (default all) and ``coordinates`` (default every
    joint, or the actuated ones of a closed loop): m per m of a length, m per rad of an angle (the translational
    rows of :func:`pose_sensitivities`)."""
    Q = np.atleast_2d(np.asarray(q, dtype=float))
    if Q.shape[1] != mech.nq:
        raise InputError(f"configurations of {mech.name} need {mech.nq} values, got {Q.shape[1]}")
    parameters = list(mech.parameters) if parameters is None else list(parameters)
    coordinates = coordinate_names(mech) if coordinates is None else list(coordinates)
    twists, placements = pose_sensitivities(mech, Q, frame or mech.tool_frame, parameters, coordinates)
    positions = np.array([p.translation for p in placements]).reshape(len(Q), 3)
    return Sensitivities(tuple(parameters) + tuple(coordinates), np.ascontiguousarray(twists[:, :3]), positions, Q)


def pose_sensitivities(mech: Mechanism, q: ArrayLike, frame: str, parameters: Sequence[str],
                       coordinates: Sequence[str]) -> tuple[NDArray[np.float64], list[pin.SE3]]:
    r"""(twists (N, 6, n_l + n_c), placements): the world-aligned twist [v; ω] of ``frame`` per unit of each of
    ``parameters`` then ``coordinates`` (m/m, rad/m, m/rad, rad/rad) at the configurations ``q`` ((N, nq),
    assembled ones for a closed loop), and the frame's placement (world) at each; to first order

        p(l + Δl, q + Δq) = p + Σ v_k Δl_k + Σ v_j Δq_j ,   R(l + Δl, q + Δq) = exp([Σ ω_k Δl_k + Σ ω_j Δq_j]×) R .

    The parameter columns are :func:`frame_parameter_twists`, the coordinate columns the frame Jacobian's; in a
    closed loop the dependent coordinates follow by :func:`loop_derivatives`: d/dl = ξ_l + J ∂q/∂l, d/dq_a = J S."""
    Q = np.atleast_2d(np.asarray(q, dtype=float))
    fid = mech.frame_id(frame)
    n_l = len(parameters)
    derivatives = placement_derivatives(mech, list(parameters))
    columns = [mech.model.joints[mech.joint_id(c)].idx_v for c in coordinates]
    solver = loop_solver(mech) if mech.closures else None
    actuated = {name: k for k, name in enumerate(mech.actuated)}
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
        out[i, :, n_l:] = (J @ S)[:, [actuated[c] for c in coordinates]]
    return out, placements


def loop_derivatives(mech: Mechanism, solver: LoopSolver, derivatives: PlacementDerivatives, q: ArrayLike
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(∂q/∂l (nv, n_l), S = ∂q/∂q_a (nv, n_act)) of a closed loop at the assembled ``q``: how the coordinates
    move with the parameters and with the actuated coordinates to keep the loops closed (implicit-function theorem:
    ∂q_d/∂l = −J_d⁻¹ ∂Φ/∂l, ∂q_d/∂q_a = −J_d⁻¹ J_a; the actuated rows of ∂q/∂l are zero)."""
    q = np.asarray(q, dtype=float)
    twists = closure_parameter_twists(mech, solver, derivatives, q)
    phi, Jc = solver.system.evaluate(q)
    n_l = len(derivatives.names)
    dphi_dl = solver.system.jacobian_for(twists) if n_l else np.zeros((len(phi), 0))
    dphi_dl = dphi_dl + solver.system.constants_jacobian(derivatives.constants, n_l)
    dq_dl = np.zeros((mech.nv, n_l))
    dq_dl[solver.dep] = -solver.dependent_inverse(q, Jc) @ dphi_dl
    return dq_dl, solver.velocity_matrix(q, Jc)


def closure_parameter_twists(mech: Mechanism, solver: LoopSolver, derivatives: PlacementDerivatives, q: ArrayLike
                             ) -> NDArray[np.float64]:
    """World-aligned twists (n_closure_frames, 6, n_l) of the closures' frames per unit of each parameter at q."""
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    frame_ids = solver.system.states.frame_ids
    return np.array([frame_parameter_twists(mech, derivatives, f) for f in frame_ids]).reshape(
        len(frame_ids), 6, len(derivatives.names))

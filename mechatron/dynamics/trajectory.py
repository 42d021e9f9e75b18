"""Closed-loop mechanisms along a motion of their inputs: the full joint states and the actuator forces.

The trajectory gives the actuated coordinates (cylinder lengths, crank angles) with their rates and accelerations;
position, velocity and acceleration analysis of the loops (:func:`mechatron.kinematics.sweep.sweep`) give every
joint's state, and the constrained inverse dynamics (:func:`mechatron.dynamics.constrained.inverse`) the forces.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from .constrained import inverse

if TYPE_CHECKING:  # pragma: no cover
    from .motion import Trajectory

Array = NDArray[np.float64]


def closed_loop_states(mech: Mechanism, trajectory: Trajectory) -> tuple[Array, Array, Array]:
    """(Q, V, A): the full joint states (N, nq/nv; rad, m and their rates) of a closed-loop mechanism along a
    trajectory of its actuated coordinates (assembly, velocity and acceleration analysis of the loops); an error
    if the motion leaves the reachable range."""
    from ..kinematics.sweep import sweep  # pandas: only when a trajectory is analysed

    inputs = {name: trajectory.coordinates[:, i] for i, name in enumerate(mech.actuated)}
    rates = {name: trajectory.v[:, i] for i, name in enumerate(mech.actuated)}
    accels = {name: trajectory.a[:, i] for i, name in enumerate(mech.actuated)}
    result = sweep(mech, inputs, rates=rates, accelerations=accels, frames=[], measures=[])
    if len(result.failures):
        raise InputError(f"{mech.name}: the trajectory leaves the reachable range: "
                         f"{result.failures['reason'].iloc[0]}")
    return result.q, result.v, result.a


def actuator_forces(mech: Mechanism, trajectory: Trajectory, loads: Loads = None) -> tuple[Array, Array]:
    """(Q, F): the joint positions (N, nq) of a closed-loop mechanism along a trajectory of its actuated
    coordinates and the actuator forces (N, n_actuated; N for a cylinder, N·m for a crank) that drive it under
    gravity and ``loads`` (constrained inverse dynamics, :func:`~mechatron.dynamics.constrained.inverse`)."""
    Q, V, A = closed_loop_states(mech, trajectory)
    return Q, _forces(mech, Q, V, A, loads)


def holding_forces(mech: Mechanism, Q: ArrayLike, loads: Loads = None) -> Array:
    """Actuator forces (N, n_actuated; N or N·m) that hold a closed-loop mechanism at rest, under gravity and
    ``loads``, in each assembled position of Q (N, nq)."""
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    return _forces(mech, Q, np.zeros((len(Q), mech.nv)), np.zeros((len(Q), mech.nv)), loads)


def _forces(mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads) -> Array:
    """The actuator forces (N, n_actuated) of the constrained inverse dynamics at every state, all at once where the
    closures are not redundant: with need = M q̈ + h − Q (batched RNEA) and the closure Jacobian J split into its
    actuated and dependent columns, [B Jᵀ][τ_a; λ] = need reads J_dᵀ λ = need_d and τ_a = need_a − J_aᵀ λ (the
    sweep that gave the states has refused the singular ones, where J_d is not invertible). Redundant closures, or
    joints the batched kinematics does not know: :func:`~mechatron.dynamics.constrained.inverse` state by state."""
    from ..kinematics import batch
    from ..kinematics.loops import loop_solver
    from .tree import inverse_dynamics

    solver = loop_solver(mech)
    system = solver.system
    try:
        frames = system.batched() if system.nrows == len(solver.dep) else None
    except NotImplementedError:
        frames = None
    if frames is None or not len(Q):
        return np.array([[f[n] for n in mech.actuated] for f in
                         (inverse(mech, q, v, a, loads)[0] for q, v, a in zip(Q, V, A))]).reshape(len(Q), -1)
    need = np.atleast_2d(inverse_dynamics(mech, Q, V, A, loads))
    out = np.empty((len(Q), len(solver.act)))
    for part in batch.chunks(len(Q)):
        _, J = system.stack(frames.placements(Q[part]))
        lam = batch.solve(np.swapaxes(J[:, :, solver.dep], 1, 2), need[part][:, solver.dep, None])[..., 0]
        out[part] = need[part][:, solver.act] - batch.apply(np.swapaxes(J[:, :, solver.act], 1, 2), lam)
    return out

"""Closed-loop mechanisms along a motion of their inputs: the full joint states and the actuator forces.

The trajectory gives the actuated coordinates (cylinder lengths, crank angles) with their rates and accelerations;
position, velocity and acceleration analysis of the loops (:func:`mechatron.kinematics.sweep.sweep`) give every
joint's state, and the constrained inverse dynamics (:func:`mechatron.dynamics.constrained.inverse`) the forces.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..kinematics.sweep import sweep
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from .constrained import inverse


def closed_loop_states(mech: Mechanism, trajectory) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Q, V, A): the full joint states (N, nq/nv) of a closed-loop mechanism along a trajectory of its actuated
    coordinates (assembly, velocity and acceleration analysis); an error if the motion leaves the reachable range."""
    inputs = {name: trajectory.q[:, i] for i, name in enumerate(mech.actuated)}
    rates = {name: trajectory.v[:, i] for i, name in enumerate(mech.actuated)}
    accels = {name: trajectory.a[:, i] for i, name in enumerate(mech.actuated)}
    result = sweep(mech, inputs, rates=rates, accelerations=accels, frames=[], measures=[])
    if len(result.failures):
        raise InputError(f"{mech.name}: the trajectory leaves the reachable range: "
                         f"{result.failures['reason'].iloc[0]}")
    return result.q, result.v, result.a


def actuator_forces(mech: Mechanism, trajectory, loads: Loads = None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(Q, F): the joint positions (N, nq) of a closed-loop mechanism along a trajectory of its actuated
    coordinates and the actuator forces (N, n_actuated; N for a cylinder, N·m for a crank) that drive it
    (constrained inverse dynamics)."""
    Q, V, A = closed_loop_states(mech, trajectory)
    return Q, _forces(mech, Q, V, A, loads)


def holding_forces(mech: Mechanism, Q: np.ndarray, loads: Loads = None) -> np.ndarray:
    """Actuator forces (N, n_actuated) that hold a closed-loop mechanism at rest in each assembled position of Q."""
    return _forces(mech, Q, np.zeros((len(Q), mech.nv)), np.zeros((len(Q), mech.nv)), loads)


def _forces(mech: Mechanism, Q, V, A, loads) -> np.ndarray:
    return np.array([[f[n] for n in mech.actuated] for f in
                     (inverse(mech, q, v, a, loads)[0] for q, v, a in zip(Q, V, A))])

r"""Transfer functions of closed-loop mechanisms ([Egorov, 4.2–4.16]): the velocity and acceleration of a point or
a link per unit rate of one input.

For a 1-DOF mechanism the first transfer function of a point is dr/dq_in (m/rad or m/m) and the second
d²r/dq_in²; for a link dφ/dq_in and d²φ/dq_in². They are the point's velocity and acceleration for q̇_in = 1,
q̈_in = 0 (the other inputs held), from the velocity and acceleration analysis of :mod:`mechatron.kinematics.loops`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism
from .frames import angular_acceleration, angular_velocity, frame_placement
from .loops import loop_solver


def point_state(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, frame: str
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """World position (m), velocity (m/s) and classical acceleration (m/s²) of the origin of ``frame`` at q (nq,)
    with joint velocity v and acceleration a (nv,): r, v = J q̇, a = J q̈ + J̇ q̇ ([Egorov, 4.44, 4.47–4.50])."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    fid = mech.frame_id(frame)
    pin.forwardKinematics(mech.model, mech.data, q, v, a)
    placement = pin.updateFramePlacement(mech.model, mech.data, fid)
    velocity = pin.getFrameVelocity(mech.model, mech.data, fid, pin.LOCAL_WORLD_ALIGNED).linear
    acceleration = pin.getFrameClassicalAcceleration(mech.model, mech.data, fid, pin.LOCAL_WORLD_ALIGNED).linear
    return placement.translation.copy(), velocity.copy(), acceleration.copy()


def link_angle(mech: Mechanism, q: ArrayLike, link: str) -> float:
    """Angle φ (rad, in (−π, π]) of the x axis of frame ``link`` in the world xy plane at q (nq,): the link angle
    whose derivatives are the angular transfer functions ([Egorov, 4.9–4.10])."""
    rotation = frame_placement(mech, q, link).rotation
    return math.atan2(rotation[1, 0], rotation[0, 0])


@dataclass(frozen=True)
class TransferFunctions:
    """First and second transfer functions of a point or a link with respect to one input ([Egorov, 4.2–4.16]).

    For a point: ``first`` = dr/dq_in (m/rad or m/m, [Egorov, 4.2]), ``second`` = d²r/dq_in² (m/rad² or 1/m,
    [Egorov, 4.7]), world 3-vectors. For a link: ``first`` = dφ/dq_in (rad/rad or rad/m, [Egorov, 4.10]),
    ``second`` = d²φ/dq_in² (1/rad or rad/m², [Egorov, 4.15]), scalars (the z components).
    """

    first: NDArray[np.float64] | float
    second: NDArray[np.float64] | float


def transfer_functions(mech: Mechanism, q: ArrayLike, input: str, *, frame: str | None = None,
                       link: str | None = None) -> TransferFunctions:
    """Transfer functions of the origin of ``frame`` or of the body ``link`` w.r.t. the actuated coordinate
    ``input`` (rad or m) at an assembled ``q`` (nq,): the velocity and acceleration for q̇_in = 1, q̈_in = 0 and the
    other inputs held ([Egorov, 4.8, 4.16]: a = a_q q̇² + v_q q̈, ε = ε_q q̇² + ω_q q̈).
    """
    q = np.asarray(q, dtype=float)
    if (frame is None) == (link is None):
        raise InputError("give either frame= or link=")
    solver = loop_solver(mech)
    v = solver.velocity(q, {input: 1.0})
    a = solver.acceleration(q, v, {})
    if frame is not None:
        _, first, second = point_state(mech, q, v, a, frame)
        return TransferFunctions(first, second)
    assert link is not None  # one of the two is given
    return TransferFunctions(float(angular_velocity(mech, q, v, link)[2]),
                             float(angular_acceleration(mech, q, v, a, link)[2]))

r"""CasADi expressions of a mechanism's frames and closure equations, from its Pinocchio model.

The pip wheel of Pinocchio has no ``pinocchio.casadi``, so the forward kinematics is written out here on CasADi
``SX`` scalars with the recursion of :mod:`mechatron.model.batched` (the same joints: revolute about and prismatic
along one fixed axis). For joint i with parent λ, joint placement (R₀, p₀) in λ and unit axis â:

.. math::

    R_i = R_λ R_0 \,\mathrm{Rot}(â, q_i) \;(\text{revolute}) \;\text{or}\; R_λ R_0 \;(\text{prismatic}), \qquad
    p_i = p_λ + R_λ p_0 \;[+\, R_λ R_0 â \, q_i \;\text{prismatic}],

Rot(â, q) = cos q I + sin q [â]× + (1 − cos q) â âᵀ (Rodrigues), and a frame at (R_f, p_f) on joint i is at
(R_i R_f, p_i + R_i p_f). The closures' residuals Φ(q) follow from the frames as in
:mod:`mechatron.model.closures` (pins, sliders, gears); their Jacobians and drifts are CasADi's exact derivatives of
these expressions (:func:`casadi.jacobian`, :func:`casadi.jtimes`), so they agree with Pinocchio's to rounding.
Units: m, rad.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from .batched import BatchedFrames
from .closures import ClosureSystem, Gear, Pin, Slider


class Unsupported(Exception):
    """The mechanism has a joint or a closure with no symbolic form here (the caller uses the numeric path)."""


def _matrix(ca, values: np.ndarray):
    return ca.SX(ca.DM(np.asarray(values, dtype=float)))


def joint_placements(model: pin.Model, q) -> list[tuple]:
    """World rotations R_i (3 × 3 SX) and origins p_i (3 × 1 SX) of every joint of ``model`` at the symbolic
    configuration ``q`` (nq × 1 SX), index 0 the world.

    Raises:
        Unsupported: for a joint other than revolute or prismatic about one fixed axis.
    """
    import casadi as ca

    try:
        tree = BatchedFrames(model, [])
    except NotImplementedError as exc:
        raise Unsupported(str(exc)) from None
    world = [(ca.SX.eye(3), ca.SX.zeros(3, 1))]
    for i in range(1, model.njoints):
        Rl, pl = world[tree.parent[i]]
        R0, p0 = tree.placement[i]
        qi = q[int(tree.column[i])]
        p = pl + ca.mtimes(Rl, _matrix(ca, p0))
        if tree.revolute[i]:
            c, s = ca.cos(qi), ca.sin(qi)
            turn = c * _matrix(ca, R0) + s * _matrix(ca, tree.skewed[i]) + (1 - c) * _matrix(ca, tree.along[i])
            R = ca.mtimes(Rl, turn)
        else:
            R = ca.mtimes(Rl, _matrix(ca, R0))
            p = p + ca.mtimes(R, _matrix(ca, tree.axis[i])) * qi
        world.append((R, p))
    return world


def frame_placements(model: pin.Model, frame_ids: list[int], q) -> list[tuple]:
    """World rotation (3 × 3 SX) and origin (3 × 1 SX) of each frame ``frame_ids`` at the configuration ``q``."""
    import casadi as ca

    joints = joint_placements(model, q)
    out = []
    for f in frame_ids:
        frame = model.frames[f]
        R, p = joints[frame.parentJoint]
        out.append((ca.mtimes(R, _matrix(ca, frame.placement.rotation)),
                    p + ca.mtimes(R, _matrix(ca, frame.placement.translation))))
    return out


def angle_about_z(R):
    """The angle (rad) of a rotation about z, atan2(R₁₀, R₀₀)."""
    import casadi as ca

    return ca.atan2(R[1, 0], R[0, 0])


def _wrap(ca, angle):
    """Angle wrapped to [−π, π): x − 2π ⌊x / 2π + ½⌋ (the derivative is 1, as for the numeric closure)."""
    return angle - 2 * math.pi * ca.floor(angle / (2 * math.pi) + 0.5)


def closure_residual(system: ClosureSystem, placements: dict[str, tuple], q):
    """Φ(q) (nrows × 1 SX) of ``system``'s closures, in its row order, from the placements of its frames (by name)
    and the configuration ``q`` (for gears): pins p_a − p_b (x, y; z too when spatial), sliders n·(p − o) with the
    line's normal n = (−sin θ, cos θ) (θ its angle about z) and, with the angle locked, θ_p − θ_l − θ₀ wrapped, gears
    q_b − u q_a − offset.

    Raises:
        Unsupported: for a closure kind with no symbolic form (a point on a curve given by a Python function).
    """
    import casadi as ca

    rows = []
    for closure in system.closures:
        if isinstance(closure, Pin):
            rows.append((placements[closure.a][1] - placements[closure.b][1])[:closure.nrows])
        elif isinstance(closure, Slider):
            R_line, o = placements[closure.line]
            R_point, p = placements[closure.point]
            theta = angle_about_z(R_line)  # the line's direction d = (cos θ, sin θ)
            rows.append(-ca.sin(theta) * (p[0] - o[0]) + ca.cos(theta) * (p[1] - o[1]))
            if closure.lock_angle:
                rows.append(_wrap(ca, angle_about_z(R_point) - theta - closure.angle_offset))
        elif isinstance(closure, Gear):
            a, b = closure.columns
            rows.append(q[b] - closure.ratio * q[a] - closure.offset)
        else:
            raise Unsupported(f"no symbolic form of the closure {closure.describe()}")
    return ca.vertcat(*rows) if rows else ca.SX.zeros(0, 1)

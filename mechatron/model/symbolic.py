r"""CasADi expressions of a mechanism's frames and closure equations, from its Pinocchio model.

The pip wheel of Pinocchio has no ``pinocchio.casadi``, so the forward kinematics is written out here on CasADi
``SX`` scalars with the recursion of :mod:`mechatron.model.batched` (the same joints: revolute about and prismatic
along one fixed axis). For joint i with parent λ, joint placement (R₀, p₀) in λ and unit axis â:

.. math::

    R_i = R_λ R_0 \,\mathrm{Rot}(â, q_i) \;(\text{revolute}) \;\text{or}\; R_λ R_0 \;(\text{prismatic}), \qquad
    p_i = p_λ + R_λ p_0 \;[+\, R_λ R_0 â \, q_i \;\text{prismatic}],

Rot(â, q) = cos q I + sin q [â]× + (1 − cos q) â âᵀ (Rodrigues), and a frame at (R_f, p_f) on joint i is at
(R_i R_f, p_i + R_i p_f). The closures' residuals Φ(q) follow from the frames as in
:mod:`mechatron.model.closures` (pins, sliders, gears; points on a world curve given as a piecewise polynomial, on
request); their Jacobians and drifts are CasADi's exact derivatives of these expressions (:func:`casadi.jacobian`,
:func:`casadi.jtimes`), so they agree with Pinocchio's to rounding.

For derivatives with respect to the model's parameters, any constant placement (R₀, p₀) may be varied by a local
twist ξ = (v, ω) that is linear in symbolic parameter deviations δ: M₀ exp(ξ) = (R₀ (I + [ω]×), p₀ + R₀ v) + O(|δ|²)
(:func:`varied`), which gives every first derivative at δ = 0 exactly. Units: m, rad.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from .batched import BatchedFrames
from .closures import ClosureSystem, Gear, OnCurve, Pin, Slider


class Unsupported(Exception):
    """The mechanism has a joint or a closure with no symbolic form here (the caller uses the numeric path)."""


def _matrix(ca, values: np.ndarray):
    return ca.SX(ca.DM(np.asarray(values, dtype=float)))


def joint_tree(model: pin.Model) -> BatchedFrames:
    """The joint structure the expressions are written from (parents, placements, axes, revolute or prismatic,
    coordinate columns).

    Raises:
        Unsupported: for a joint other than revolute or prismatic about one fixed axis (the message names it).
    """
    try:
        return BatchedFrames(model, [])
    except NotImplementedError as exc:
        raise Unsupported(str(exc).removeprefix("batched kinematics: ")) from None


def varied(ca, rotation: np.ndarray, translation: np.ndarray, twist: tuple | None) -> tuple:
    r"""A constant placement (R₀, p₀) varied by a local twist ξ = (v, ω) (two 3 × 1 SX, linear in the parameter
    deviations), to first order: M₀ exp(ξ) = (R₀ (I + [ω]×), p₀ + R₀ v) + O(|ξ|²); (R₀, p₀) as SX without a
    twist."""
    R0, p0 = _matrix(ca, rotation), _matrix(ca, np.reshape(translation, (3, 1)))
    if twist is None:
        return R0, p0
    v, w = twist
    return R0 + ca.mtimes(R0, ca.skew(w)), p0 + ca.mtimes(R0, v)


def joint_placements(model: pin.Model, q, twists: list | None = None) -> list[tuple]:
    """World rotations R_i (3 × 3 SX) and origins p_i (3 × 1 SX) of every joint of ``model`` at the symbolic
    configuration ``q`` (nq × 1 SX), index 0 the world.

    ``twists``, optional: per joint (index 0 unused) None or a local twist (v, ω) that varies its placement to
    first order, (R₀, p₀) → (R₀ (I + [ω]×), p₀ + R₀ v) (:func:`varied`): the model with its parameters moved, for
    first derivatives with respect to them.

    Raises:
        Unsupported: for a joint other than revolute or prismatic about one fixed axis.
    """
    import casadi as ca

    tree = joint_tree(model)
    world = [(ca.SX.eye(3), ca.SX.zeros(3, 1))]
    for i in range(1, model.njoints):
        Rl, pl = world[tree.parent[i]]
        R0, p0 = tree.placement[i]
        qi = q[int(tree.column[i])]
        twist = twists[i] if twists is not None else None
        if twist is not None:
            R0s, p0s = varied(ca, R0, p0, twist)
            p = pl + ca.mtimes(Rl, p0s)
            axis = _matrix(ca, np.reshape(tree.axis[i], (3, 1)))
            if tree.revolute[i]:
                c, s = ca.cos(qi), ca.sin(qi)
                along = np.outer(tree.axis[i], tree.axis[i])
                turn = c * ca.SX.eye(3) + s * ca.skew(axis) + (1 - c) * _matrix(ca, along)
                R = ca.mtimes(Rl, ca.mtimes(R0s, turn))
            else:
                R = ca.mtimes(Rl, R0s)
                p = p + ca.mtimes(R, axis) * qi
            world.append((R, p))
            continue
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


def frame_placements(model: pin.Model, frame_ids: list[int], q, twists: dict | None = None,
                     joints: list[tuple] | None = None) -> list[tuple]:
    """World rotation (3 × 3 SX) and origin (3 × 1 SX) of each frame ``frame_ids`` at the configuration ``q``.

    ``twists``, optional: {frame id: local twist (v, ω)} varying frame placements to first order (:func:`varied`);
    ``joints``: the joints' placements from :func:`joint_placements` if already written (else written here)."""
    import casadi as ca

    joints = joint_placements(model, q) if joints is None else joints
    out = []
    for f in frame_ids:
        frame = model.frames[f]
        R, p = joints[frame.parentJoint]
        twist = (twists or {}).get(f)
        if twist is None:
            out.append((ca.mtimes(R, _matrix(ca, frame.placement.rotation)),
                        p + ca.mtimes(R, _matrix(ca, frame.placement.translation))))
            continue
        Rf, pf = varied(ca, frame.placement.rotation, frame.placement.translation, twist)
        out.append((ca.mtimes(R, Rf), p + ca.mtimes(R, pf)))
    return out


def angle_about_z(R):
    """The angle (rad) of a rotation about z, atan2(R₁₀, R₀₀)."""
    import casadi as ca

    return ca.atan2(R[1, 0], R[0, 0])


def _wrap(ca, angle):
    """Angle wrapped to [−π, π): x − 2π ⌊x / 2π + ½⌋ (the derivative is 1, as for the numeric closure)."""
    return angle - 2 * math.pi * ca.floor(angle / (2 * math.pi) + 0.5)


def piecewise_polynomial(ca, spline, x):
    """y(x) (SX) of a ``scipy.interpolate.PPoly`` (breakpoints b₀ < … < b_m, coefficients c (k, m), highest power
    first): Σ_j c_{j,i} (x − b_i)^{k−1−j} on the piece i with b_i ≤ x < b_{i+1}, the first and last pieces
    extrapolated as PPoly does (a chain of ``if_else``: its derivatives are those of the piece x is on)."""
    breaks = np.asarray(spline.x, dtype=float)
    coefficients = np.asarray(spline.c, dtype=float)
    if breaks.ndim != 1 or coefficients.ndim != 2 or not np.all(np.diff(breaks) > 0):
        raise Unsupported("a curve that is not one piecewise polynomial y(x) with increasing breakpoints")

    def piece(i: int):
        t = x - float(breaks[i])
        value = ca.SX(float(coefficients[0, i]))
        for c in coefficients[1:, i]:
            value = value * t + float(c)
        return value

    y = piece(0)
    for i in range(1, coefficients.shape[1]):
        y = ca.if_else(x >= float(breaks[i]), piece(i), y)
    return y


def closure_residual(system: ClosureSystem, placements: dict[str, tuple], q, *, curves: bool = False,
                     constants: dict | None = None):
    """Φ(q) (nrows × 1 SX) of ``system``'s closures, in its row order, from the placements of its frames (by name)
    and the configuration ``q`` (for gears): pins p_a − p_b (x, y; z too when spatial), sliders n·(p − o) with the
    line's normal n = (−sin θ, cos θ) (θ its angle about z) and, with the angle locked, θ_p − θ_l − θ₀ wrapped, gears
    q_b − u q_a − offset; with ``curves``, points on a world curve given as a piecewise polynomial,
    y − f(x) (:func:`piecewise_polynomial`).

    ``constants``, optional: {closure name: {"angle_offset" | "ratio" | "offset": SX}} deviations added to the
    closures' constants θ₀, u and offset (for derivatives with respect to parameters that move them).

    Raises:
        Unsupported: for a closure kind with no symbolic form (a point on a curve given by a Python function, or any
            curve without ``curves``).
    """
    import casadi as ca

    rows = []
    for closure in system.closures:
        change = (constants or {}).get(closure.name, {})
        if isinstance(closure, Pin):
            rows.append((placements[closure.a][1] - placements[closure.b][1])[:closure.nrows])
        elif isinstance(closure, Slider):
            R_line, o = placements[closure.line]
            R_point, p = placements[closure.point]
            theta = angle_about_z(R_line)  # the line's direction d = (cos θ, sin θ)
            rows.append(-ca.sin(theta) * (p[0] - o[0]) + ca.cos(theta) * (p[1] - o[1]))
            if closure.lock_angle:
                offset = closure.angle_offset + change.get("angle_offset", 0.0)
                rows.append(_wrap(ca, angle_about_z(R_point) - theta - offset))
        elif isinstance(closure, Gear):
            a, b = closure.columns
            ratio, offset = closure.ratio + change.get("ratio", 0.0), closure.offset + change.get("offset", 0.0)
            rows.append(q[b] - ratio * q[a] - offset)
        elif curves and isinstance(closure, OnCurve) and closure.spline is not None:
            p = placements[closure.point][1]
            rows.append(p[1] - piecewise_polynomial(ca, closure.spline, p[0]))
        else:
            raise Unsupported(f"no symbolic form of the closure {closure.describe()}")
    return ca.vertcat(*rows) if rows else ca.SX.zeros(0, 1)

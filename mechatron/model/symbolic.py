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


def joint_placements(model: pin.Model, q, twists: list | None = None, given: dict | None = None) -> list[tuple]:
    """World rotations R_i (3 × 3 SX) and origins p_i (3 × 1 SX) of every joint of ``model`` at the symbolic
    configuration ``q`` (nq × 1 SX), index 0 the world.

    ``twists``, optional: per joint (index 0 unused) None or a local twist (v, ω) that varies its placement to
    first order, (R₀, p₀) → (R₀ (I + [ω]×), p₀ + R₀ v) (:func:`varied`): the model with its parameters moved, for
    first derivatives with respect to them. ``given``, optional: {joint: (R₀, p₀) as SX} in place of the model's
    numbers (:class:`Geometry`: the placements as parameters).

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
        R0s, p0s = (given or {}).get(i, (None, None))  # None: the model's numbers
        p = pl + ca.mtimes(Rl, _matrix(ca, p0) if p0s is None else p0s)
        if R0s is not None:  # the rotation as an expression: R₀ Rot(â, q) = c R₀ + s R₀[â]× + (1 − c) R₀ â âᵀ
            skewed = ca.SX(ca.skew(ca.DM(tree.axis[i])))
            along = _matrix(ca, np.outer(tree.axis[i], tree.axis[i]))
            if tree.revolute[i]:
                c, s = ca.cos(qi), ca.sin(qi)
                R = ca.mtimes(Rl, c * R0s + s * ca.mtimes(R0s, skewed) + (1 - c) * ca.mtimes(R0s, along))
            else:
                R = ca.mtimes(Rl, R0s)
                p = p + ca.mtimes(R, _matrix(ca, tree.axis[i])) * qi
        elif tree.revolute[i]:
            c, s = ca.cos(qi), ca.sin(qi)
            turn = c * _matrix(ca, R0) + s * _matrix(ca, tree.skewed[i]) + (1 - c) * _matrix(ca, tree.along[i])
            R = ca.mtimes(Rl, turn)
        else:
            R = ca.mtimes(Rl, _matrix(ca, R0))
            p = p + ca.mtimes(R, _matrix(ca, tree.axis[i])) * qi
        world.append((R, p))
    return world


def frame_placements(model: pin.Model, frame_ids: list[int], q, twists: dict | None = None,
                     joints: list[tuple] | None = None, given: dict | None = None) -> list[tuple]:
    """World rotation (3 × 3 SX) and origin (3 × 1 SX) of each frame ``frame_ids`` at the configuration ``q``.

    ``twists``, optional: {frame id: local twist (v, ω)} varying frame placements to first order (:func:`varied`);
    ``joints``: the joints' placements from :func:`joint_placements` if already written (else written here);
    ``given``: {frame id: (R_f, p_f) as SX} in place of the model's numbers (:class:`Geometry`)."""
    import casadi as ca

    joints = joint_placements(model, q) if joints is None else joints
    out = []
    for f in frame_ids:
        frame = model.frames[f]
        R, p = joints[frame.parentJoint]
        twist = (twists or {}).get(f)
        if given is not None and f in given:
            Rf, pf = given[f]
            Rf = _matrix(ca, frame.placement.rotation) if Rf is None else Rf  # None: the model's rotation
            out.append((ca.mtimes(R, Rf), p + ca.mtimes(R, pf)))
            continue
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
                     constants: dict | None = None, given: dict | None = None):
    """Φ(q) (nrows × 1 SX) of ``system``'s closures, in its row order, from the placements of its frames (by name)
    and the configuration ``q`` (for gears): pins p_a − p_b (x, y; z too when spatial), sliders n·(p − o) with the
    line's normal n = (−sin θ, cos θ) (θ its angle about z) and, with the angle locked, θ_p − θ_l − θ₀ wrapped, gears
    q_b − u q_a − offset; with ``curves``, points on a world curve given as a piecewise polynomial,
    y − f(x) (:func:`piecewise_polynomial`).

    ``constants``, optional: {closure name: {"angle_offset" | "ratio" | "offset": SX}} deviations added to the
    closures' constants θ₀, u and offset (for derivatives with respect to parameters that move them); ``given``,
    the same keys with the constants themselves (:class:`Geometry`).

    Raises:
        Unsupported: for a closure kind with no symbolic form (a point on a curve given by a Python function, or any
            curve without ``curves``).
    """
    import casadi as ca

    rows = []
    for closure in system.closures:
        change = (constants or {}).get(closure.name, {})
        values = (given or {}).get(closure.name, {})
        if isinstance(closure, Pin):
            rows.append((placements[closure.a][1] - placements[closure.b][1])[:closure.nrows])
        elif isinstance(closure, Slider):
            R_line, o = placements[closure.line]
            R_point, p = placements[closure.point]
            theta = angle_about_z(R_line)  # the line's direction d = (cos θ, sin θ)
            rows.append(-ca.sin(theta) * (p[0] - o[0]) + ca.cos(theta) * (p[1] - o[1]))
            if closure.lock_angle:
                offset = values.get("angle_offset", closure.angle_offset) + change.get("angle_offset", 0.0)
                rows.append(_wrap(ca, angle_about_z(R_point) - theta - offset))
        elif isinstance(closure, Gear):
            a, b = closure.columns
            ratio = values.get("ratio", closure.ratio) + change.get("ratio", 0.0)
            offset = values.get("offset", closure.offset) + change.get("offset", 0.0)
            rows.append(q[b] - ratio * q[a] - offset)
        elif curves and isinstance(closure, OnCurve) and closure.spline is not None:
            p = placements[closure.point][1]
            rows.append(p[1] - piecewise_polynomial(ca, closure.spline, p[0]))
        else:
            raise Unsupported(f"no symbolic form of the closure {closure.describe()}")
    return ca.vertcat(*rows) if rows else ca.SX.zeros(0, 1)


# ------------------------------------------------------------------------------------------ geometry as parameters
def rotation_kind(R: np.ndarray) -> str:
    """How a constant rotation enters the parametric expressions (:class:`Geometry`): ``"identity"`` (exactly I: no
    parameter), ``"z"`` (exactly a turn about z, [[c, −s, 0], [s, c, 0], [0, 0, 1]]: the parameters c and s) or
    ``"full"`` (its nine entries)."""
    R = np.asarray(R, dtype=float)
    if np.array_equal(R, np.eye(3)):
        return "identity"
    about_z = R[2, 2] == 1.0 and not R[2, :2].any() and not R[:2, 2].any()
    return "z" if about_z and R[0, 1] == -R[1, 0] and R[1, 1] == R[0, 0] else "full"


_ROTATION_SIZE = {"identity": 0, "z": 2, "full": 9}


class Geometry:
    r"""The numbers of a model's constant placements and of its closures' constants as one parameter vector p, so
    that expressions written once serve every model of the same structure (a design study's geometries: compiled
    once, evaluated with each design's p).

    The parameters, in order: of every joint (1 … njoints − 1), then of every frame of ``frame_ids``, its placement
    (R₀, p₀) in its parent — the rotation by :func:`rotation_kind` (none, c and s of a turn about z, or its nine
    entries row by row) and the translation's three coordinates (m) —; then of the closures a locked slider's angle
    offset θ₀ (rad) and a gear's ratio u and offset. :attr:`signature` is everything else the expressions depend
    on — the joints' parents, kinds, axes and coordinate columns, the frames' joints, each rotation's kind, the
    closures' kinds, frames and rows — so that two models with equal signatures give the same expressions of
    (q, p) and differ only in :meth:`values`.

    Raises:
        Unsupported: for a joint other than revolute or prismatic about one fixed axis.
    """

    def __init__(self, model: pin.Model, frame_ids: list[int], system: ClosureSystem) -> None:
        tree = joint_tree(model)
        self.frame_ids = list(frame_ids)
        self.joint_kinds = [rotation_kind(R) for R, _ in tree.placement[1:]]
        self.frame_kinds = [rotation_kind(model.frames[f].placement.rotation) for f in self.frame_ids]
        self.constants = [(c.name, key) for c in system.closures for key in _closure_constants(c)]
        joints = tuple((int(tree.parent[i]), bool(tree.revolute[i]), tuple(map(float, tree.axis[i])),
                        int(tree.column[i]), self.joint_kinds[i - 1]) for i in range(1, model.njoints))
        frames = tuple((int(f), int(model.frames[f].parentJoint), kind) for f, kind in zip(self.frame_ids,
                                                                                             self.frame_kinds))
        closures = tuple((type(c).__name__, c.frames, c.nrows, bool(getattr(c, "lock_angle", False)),
                          bool(getattr(c, "planar", True)), tuple(getattr(c, "columns", ()))) for c in system.closures)
        self.signature = (model.nq, model.nv, joints, frames, closures, tuple(self.constants))
        self.size = sum(_ROTATION_SIZE[k] + 3 for k in self.joint_kinds + self.frame_kinds) + len(self.constants)

    def values(self, model: pin.Model, system: ClosureSystem) -> np.ndarray:
        """p of ``model`` and its closures ``system`` (a model of this signature), in the order of the class
        docstring."""
        out = []
        placements = [model.jointPlacements[i] for i in range(1, model.njoints)] + \
            [model.frames[f].placement for f in self.frame_ids]
        for placement, kind in zip(placements, self.joint_kinds + self.frame_kinds):
            R = placement.rotation
            out += [] if kind == "identity" else [R[0, 0], R[1, 0]] if kind == "z" else list(R.ravel())
            out += list(placement.translation)
        closures = {c.name: c for c in system.closures}
        out += [float(getattr(closures[name], key)) for name, key in self.constants]
        return np.array(out, dtype=float)

    def symbols(self, ca, p) -> tuple[dict, dict, dict]:
        """The placements as expressions of the parameters ``p`` (an SX of :attr:`size` entries): ({joint: (R₀,
        p₀)}, {frame id: (R_f, p_f)}, {closure name: {constant: SX}}), as :func:`joint_placements`,
        :func:`frame_placements` and :func:`closure_residual` take them (``given``); an identity rotation is None
        (the constant itself)."""
        at = 0

        def placement(kind: str) -> tuple:
            nonlocal at
            if kind == "identity":
                R = None  # the model's exact identity, as a constant
            elif kind == "z":
                c, s = p[at], p[at + 1]
                R = ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))
            else:
                R = ca.vertcat(*(ca.horzcat(*(p[at + 3 * r + k] for k in range(3))) for r in range(3)))
            at += _ROTATION_SIZE[kind]
            t = ca.vertcat(p[at], p[at + 1], p[at + 2])
            at += 3
            return R, t

        joints = {i + 1: placement(kind) for i, kind in enumerate(self.joint_kinds)}
        frames = {f: placement(kind) for f, kind in zip(self.frame_ids, self.frame_kinds)}
        constants: dict[str, dict] = {}
        for name, key in self.constants:
            constants.setdefault(name, {})[key] = p[at]
            at += 1
        return joints, frames, constants


def _closure_constants(closure) -> tuple[str, ...]:
    """The constants of a closure that are parameters of :class:`Geometry`."""
    if isinstance(closure, Slider) and closure.lock_angle:
        return ("angle_offset",)
    if isinstance(closure, Gear):
        return ("ratio", "offset")
    return ()

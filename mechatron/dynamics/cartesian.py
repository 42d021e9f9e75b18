r"""Cartesian tasks: a frame of a serial arm (the tool) moved along straight lines through waypoints in space, the
joints found by inverse kinematics on the Pinocchio model (:func:`~mechatron.kinematics.inverse.inverse_kinematics`).

Between waypoints p_a and p_b (m, world axes; orientations R_a and R_b if given) the frame follows

    p(s) = p_a + s (p_b − p_a),   R(s) = R_a Exp(s θ),  θ = log₃(R_aᵀ R_b),   s(t) from 0 to 1,

sampled every ``dt`` along the path, not only at its ends. s(t) is the task's rest-to-rest profile
(:func:`~mechatron.dynamics.motion.make_profile`: trapezoidal, triangular, scurve or quintic) with the limits of s
from the frame's: ṡ ≤ min(v/L, ω/|θ|), s̈ ≤ min(a/L, α/|θ|), s⃛ ≤ min(j/L, j_ω/|θ|), L = ‖p_b − p_a‖ (v, a, j in m/s,
m/s², m/s³; ω, α, j_ω in rad/s, rad/s², rad/s³). At every sample the configuration is the inverse kinematics from
the previous sample's solution (the first waypoint's from the seed), so the branch (elbow up or down) of the seed is
kept along the whole task. The joint rates are those of the path:

    q̇ = J⁺ ẋ,   q̈ = J⁺ (ẍ − J̇ q̇),   ẋ = [p_b − p_a; R_a θ] ṡ,   ẍ = [p_b − p_a; R_a θ] s̈,

J the frame Jacobian (world-aligned; its linear rows only without orientations), J⁺ its pseudo-inverse (the least
norm rates of a redundant arm) and J̇ q̇ the frame's classical acceleration at zero joint acceleration. Where the
joint limits ``vmax`` or ``amax`` (a task's; ``vmax`` by default the model's velocity limits) would be passed, the
line is slowed down as a whole: its duration times k = max(1, max|q̇_i|/v_max,i, √(max|q̈_i|/a_max,i)), which scales
every q̇ by 1/k and q̈ by 1/k² (the peaks at the samples). ``dwell`` rests at every waypoint after the first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import InputError
from ..io.schema import FieldReader
from ..kinematics.inverse import into_limits, inverse_kinematics, limit_violation, pose_error
from ..model.mechanism import Mechanism
from .motion import Trajectory, coordinate_names, make_profile

#: The largest residual ‖e‖ (m, rad) of a solved sample; a larger one is an unreachable target.
REACHED = 1e-9
#: The most samples of one line (each is an inverse kinematics).
MAX_LINE_SAMPLES = 1_000_000


@dataclass(frozen=True)
class CartesianPath:
    """Waypoints of a frame in space and the limits of its motion.

    Attributes:
        frame: The frame that follows the path (a robot's ``tool``).
        points: (K, 3) positions (m, world axes), K ≥ 2.
        rotations: (K, 3, 3) orientations (world axes), or None: positions only.
        seed: The configuration (nq,) the inverse kinematics of the first waypoint starts from.
        speed, acceleration, jerk: The frame's limits along a line (m/s, m/s², m/s³; jerk for ``scurve`` only).
        angular_speed, angular_acceleration, angular_jerk: Its limits of rotation (rad/s, rad/s², rad/s³), needed
            where the orientation changes.
        labels: How each waypoint is named in messages (a file's field, ``cartesian.points_mm[2]``).
        file: The file the path came from, if any.
    """

    frame: str
    points: np.ndarray
    rotations: np.ndarray | None
    seed: np.ndarray
    speed: float
    acceleration: float
    jerk: float | None = None
    angular_speed: float | None = None
    angular_acceleration: float | None = None
    angular_jerk: float | None = None
    labels: tuple[str, ...] = ()
    file: str | None = None

    def error(self, k: int, message: str) -> InputError:
        """An error about waypoint ``k`` (0-based), naming its field."""
        label = self.labels[k] if k < len(self.labels) else f"point {k + 1}"
        return InputError(message, file=self.file, field=label)


def _limit(linear: float | None, angular: float | None, length: float, angle: float) -> float:
    """The limit of s from the frame's linear and angular ones: min(linear/L, angular/|θ|) (inf where none)."""
    rates = [math.inf]
    if length > 0 and linear is not None:
        rates.append(linear / length)
    if angle > 0 and angular is not None:
        rates.append(angular / angle)
    return min(rates)


def _joint_limits(mech: Mechanism, vmax: np.ndarray | None, amax: np.ndarray | None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Joint speed limits (``vmax``, else the model's finite velocity limits, else none) and acceleration limits
    (``amax``, else none): inf where there is none."""
    if vmax is None:
        vmax = np.asarray(mech.model.velocityLimit, dtype=float).copy()
        vmax[~np.isfinite(vmax) | (vmax <= 0) | (vmax > 1e30)] = math.inf
    return np.asarray(vmax, dtype=float), np.full(mech.nv, math.inf) if amax is None else np.asarray(amax, float)


class _Follower:
    """The inverse kinematics and rates of one frame along a path (one ``pin.Data`` for all samples)."""

    def __init__(self, mech: Mechanism, path: CartesianPath) -> None:
        self.mech, self.path = mech, path
        self.model, self.data = mech.model, mech.model.createData()
        self.fid = mech.frame_id(path.frame)
        self.rows = 3 if path.rotations is None else 6

    def solve(self, q: np.ndarray, position: np.ndarray, rotation: np.ndarray | None) -> tuple[np.ndarray, float]:
        return inverse_kinematics(self.mech, position, q, frame=self.path.frame, rotation=rotation, data=self.data)

    def miss(self, q: np.ndarray, k: int) -> str:
        """How far the frame at q is from waypoint k: the distance (mm) and, with orientations, the angle (°)."""
        rotation = None if self.path.rotations is None else self.path.rotations[k]
        return self.miss_at(q, self.path.points[k], rotation)

    def miss_at(self, q: np.ndarray, position: np.ndarray, rotation: np.ndarray | None) -> str:
        error = pose_error(self.model, self.data, q, self.fid, position, rotation)[0]
        text = f"{np.linalg.norm(error[:3]) * 1e3:.6g} mm"
        return text if rotation is None else f"{text} and {math.degrees(np.linalg.norm(error[3:])):.6g}°"

    def rates(self, q: np.ndarray, direction: np.ndarray, ds: float, dds: float) -> tuple[np.ndarray, np.ndarray]:
        """(q̇, q̈) at q of the frame moving by ``direction`` (3 or 6: m, rad per unit s) at ṡ and s̈."""
        model, data = self.model, self.data
        jacobian = pin.computeFrameJacobian(model, data, q, self.fid, pin.LOCAL_WORLD_ALIGNED)[:self.rows]
        qd = np.linalg.lstsq(jacobian, direction * ds, rcond=None)[0]
        pin.forwardKinematics(model, data, q, qd, np.zeros(model.nv))
        drift = pin.getFrameClassicalAcceleration(model, data, self.fid, pin.LOCAL_WORLD_ALIGNED).vector[:self.rows]
        return qd, np.linalg.lstsq(jacobian, direction * dds - drift, rcond=None)[0]


def _line(follower: _Follower, k: int, q: np.ndarray, profile: str, dt: float, vlim: np.ndarray, alim: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(t, Q, V, A) of the line from waypoint k − 1 to waypoint k, starting at the configuration q (that solves
    waypoint k − 1), t from 0; None when the frame does not move."""
    path = follower.path
    start, delta = path.points[k - 1], path.points[k] - path.points[k - 1]
    length = float(np.linalg.norm(delta))
    if path.rotations is None:
        axis, direction = np.zeros(3), delta
    else:
        axis = pin.log3(path.rotations[k - 1].T @ path.rotations[k])
        direction = np.concatenate([delta, path.rotations[k - 1] @ axis])
    angle = float(np.linalg.norm(axis))
    if length == 0 and angle == 0:
        return None
    vmax, amax, jmax = (_limit(getattr(path, name), getattr(path, "angular_" + name), length, angle)
                        for name in ("speed", "acceleration", "jerk"))
    shape = make_profile(profile, vmax, amax, jmax)
    for _ in range(4):
        steps = max(1, math.ceil(shape.duration / dt))
        if steps > MAX_LINE_SAMPLES:
            raise path.error(k, f"the line to this waypoint lasts {shape.duration:.6g} s: {steps} samples of "
                                f"dt = {dt:g} s, more than {MAX_LINE_SAMPLES}: raise dt or the limits")
        t = np.linspace(0.0, shape.duration, steps + 1)
        s, ds, dds = shape.evaluate(t)
        Q = np.empty((len(t), follower.model.nq))
        V, A = np.empty((len(t), follower.model.nv)), np.empty((len(t), follower.model.nv))
        current = q
        for i, si in enumerate(s):
            rotation = None if path.rotations is None else path.rotations[k - 1] @ pin.exp3(si * axis)
            current, residual = follower.solve(current, start + si * delta, rotation)
            if residual > REACHED:
                raise _unreachable(follower, k, current, si, follower.miss_at(current, start + si * delta, rotation))
            outside = limit_violation(follower.mech, current)
            if outside is not None:
                where = "at this waypoint" if i == len(s) - 1 else f"at {100 * si:.4g} % of the line to this waypoint"
                raise path.error(k, f"the inverse kinematics (the seed's branch) puts {outside} {where}")
            Q[i] = current
            V[i], A[i] = follower.rates(current, direction, ds[i], dds[i])
        stretch = max(1.0, float(np.max(np.abs(V) / vlim)), math.sqrt(float(np.max(np.abs(A) / alim))))
        if stretch <= 1 + 1e-9:
            break
        shape = make_profile(profile, vmax, amax, jmax, duration=shape.duration * stretch * (1 + 1e-6))
    return t, Q, V, A


def _check_limits(path: CartesianPath, profile: str) -> None:
    """Refuse a line whose limits are missing: angular ones where the orientation changes, jerks for ``scurve``."""
    for k in range(1, len(path.points)):
        moves = bool(np.any(path.points[k] != path.points[k - 1]))
        turns = path.rotations is not None and float(np.linalg.norm(
            pin.log3(path.rotations[k - 1].T @ path.rotations[k]))) > 0
        if turns and (path.angular_speed is None or path.angular_acceleration is None):
            raise path.error(k, "the orientation changes: give angular_speed and angular_acceleration (or _deg)")
        if profile == "scurve" and (moves and path.jerk is None or turns and path.angular_jerk is None):
            raise path.error(k, "the scurve profile needs jerk (m/s³)" + (" and angular_jerk" if turns else ""))


def _unreachable(follower: _Follower, k: int, q: np.ndarray, s: float, miss: str) -> InputError:
    """The error of a line to waypoint k that the frame cannot follow beyond the fraction ``s`` (where it stays
    ``miss`` away): the waypoint itself out of reach (as near as the inverse kinematics from ``q`` comes), or the
    line between."""
    path = follower.path
    end, last = follower.solve(q, path.points[k], None if path.rotations is None else path.rotations[k])
    if last > REACHED:
        return path.error(k, f"unreachable: frame '{path.frame}' comes no nearer to this waypoint than "
                             f"{follower.miss(end, k)}")
    return path.error(k, f"unreachable: the line to this waypoint leaves the reach of frame '{path.frame}' at "
                         f"{100 * s:.4g} % of its length (residual {miss})")


def cartesian_cycle(mech: Mechanism, path: CartesianPath, *, profile: str = "trapezoidal", dwell: float = 0.0,
                    dt: float = 0.005, vmax: np.ndarray | None = None, amax: np.ndarray | None = None) -> Trajectory:
    """The trajectory (joint coordinates, rates) of ``path`` on the serial arm ``mech``, as in the module docstring:
    lines through the waypoints timed by ``profile`` at the frame's limits, sampled every ``dt`` s, resting
    ``dwell`` s at every waypoint after the first, slowed where the joint limits ``vmax`` (rad/s, m/s; default the
    model's) and ``amax`` (rad/s², m/s²; default none) would be passed. An unreachable waypoint or line is an
    :class:`~mechatron.errors.InputError` naming the waypoint and the residual; so is a solution, at a waypoint or
    along the line to it, outside a joint's position limits (the model's, where finite: naming the joint,
    :func:`~mechatron.kinematics.inverse.limit_violation`)."""
    if mech.closures:
        raise InputError(f"{mech.name} has closed loops: Cartesian waypoints need a serial arm (give the inputs' "
                         "waypoints instead)", file=path.file, field="cartesian")
    _check_limits(path, profile)
    follower = _Follower(mech, path)
    vlim, alim = _joint_limits(mech, vmax, amax)
    first = None if path.rotations is None else path.rotations[0]
    q, residual = follower.solve(np.asarray(path.seed, dtype=float), path.points[0], first)
    if residual > REACHED:
        raise path.error(0, f"unreachable: frame '{path.frame}' comes no nearer to this waypoint than "
                            f"{follower.miss(q, 0)} (from the seed configuration)")
    q = into_limits(mech, q)  # the same pose: a solution a turn away from the seed comes back within the limits
    outside = limit_violation(mech, q)
    if outside is not None:
        raise path.error(0, f"the inverse kinematics (from the seed configuration) puts {outside} at this waypoint")
    zeros = np.zeros((1, mech.nv))
    times, Qs, Vs, As = [np.zeros(1)], [q[None]], [zeros], [zeros]
    end = 0.0
    for k in range(1, len(path.points)):
        line = _line(follower, k, q, profile, dt, vlim, alim)
        if line is not None:
            t, Q, V, A = line
            if len(times) == 1:  # the task starts with this line: its first sample (s̈ > 0) replaces the seed's
                times, Qs, Vs, As = [end + t], [Q], [V], [A]
            else:  # it starts where the last line or rest ended
                times.append(end + t[1:])
                Qs.append(Q[1:])
                Vs.append(V[1:])
                As.append(A[1:])
            end, q = end + float(t[-1]), Q[-1]
        if dwell > 0:
            rest = np.arange(0.0, dwell + dt / 2, dt)[1:]
            times.append(end + rest)
            Qs.append(np.repeat(q[None], len(rest), axis=0))
            Vs.append(np.zeros((len(rest), mech.nv)))
            As.append(np.zeros((len(rest), mech.nv)))
            end += float(rest[-1]) if len(rest) else 0.0
    Q = np.concatenate(Qs)
    return Trajectory(np.concatenate(times), Q, np.concatenate(Vs), np.concatenate(As), coordinate_names(mech),
                      _unwrapped(mech, Q), [bool(x) for x in mech.angular_coordinates()])


def _unwrapped(mech: Mechanism, Q: np.ndarray) -> np.ndarray:
    """Joint coordinates (N, nv) of configurations Q: q itself when nq = nv, else the first one's coordinates plus
    the sum of the differences q_i ⊖ q_(i−1) (``pin.difference``), so that a continuous joint's angle is not wrapped."""
    if mech.nq == mech.nv:
        return Q.copy()
    steps = np.array([pin.difference(mech.model, a, b) for a, b in zip(Q[:-1], Q[1:])]).reshape(-1, mech.nv)
    return mech.coordinates(Q[0]) + np.concatenate([np.zeros((1, mech.nv)), np.cumsum(steps, axis=0)])


# ------------------------------------------------------------------------------------------------- the file
def _point_list(reader: FieldReader, names: tuple[str, str], count: int | None, what: str) -> tuple[str, list] | None:
    """(field, values) of the list of 3-number lists under one of ``names`` (SI, then the scaled form)."""
    given = [n for n in names if reader.has(n)]
    if len(given) > 1:
        raise reader.error(given[1], f"give only one of {' and '.join(given)}")
    if not given:
        return None
    name = given[0]
    raw = reader.raw(name)
    if not isinstance(raw, list) or len(raw) < 2 or (count is not None and len(raw) != count):
        wanted = f"{count} (one per point)" if count is not None else "at least two"
        raise reader.error(name, f"give a list of {wanted} {what}")
    for k, item in enumerate(raw):
        if not isinstance(item, list) or len(item) != 3:
            raise reader.error(f"{name}[{k + 1}]", f"expected 3 numbers ({what})")
    return name, [[reader.to_float(f"{name}[{k + 1}]", v) for v in item] for k, item in enumerate(raw)]


def read_cartesian(reader: FieldReader, mech: Mechanism, angular: np.ndarray) -> CartesianPath:
    """A :class:`CartesianPath` from the table ``[cartesian]`` of a task file (docs/task_file.md): ``frame``,
    ``points`` (m) or ``points_mm``, optional ``rpy``/``rpy_deg`` (one per point), ``seed``/``seed_deg``,
    ``speed``, ``acceleration``, ``jerk``, ``angular_speed``, ``angular_acceleration``, ``angular_jerk`` (or
    ``_deg``). ``angular``: which joint coordinates are angles (for ``seed_deg``)."""
    if mech.closures:
        raise reader.error("frame", f"{mech.name} has closed loops: Cartesian waypoints need a serial arm (give the "
                                    "inputs' waypoints instead)")
    frame = reader.string("frame", mech.tool_frame)
    try:
        mech.frame_id(frame)
    except InputError as exc:
        raise reader.error("frame", exc.message) from None
    found = _point_list(reader, ("points", "points_mm"), None, "positions [x, y, z] (world axes)")
    if found is None:
        raise reader.error("points", "missing required field (give points or points_mm)")
    key, values = found
    points = np.array(values) * (1e-3 if key == "points_mm" else 1.0)
    turned = _point_list(reader, ("rpy", "rpy_deg"), len(points), "orientations [roll, pitch, yaw]")
    rotations = None
    if turned is not None:
        angles = np.array(turned[1]) * (math.pi / 180 if turned[0] == "rpy_deg" else 1.0)
        rotations = np.array([pin.rpy.rpyToMatrix(*a) for a in angles])
    if reader.has("seed") and reader.has("seed_deg"):
        raise reader.error("seed", "give only one of seed and seed_deg")
    if reader.has("seed_deg"):
        seed = reader.vector("seed_deg", len(angular))
        seed = np.where(angular, np.radians(seed), seed)
    else:
        seed = reader.vector("seed", len(angular), None)
    home = mech.reference_q if mech.reference_q is not None else mech.neutral()
    seed_q = np.asarray(home, dtype=float) if seed is None else mech.configuration(seed)

    speed = reader.number("speed", positive=True)
    acceleration = reader.number("acceleration", positive=True)
    jerk = reader.number("jerk", None, positive=True)
    turning_speed, turning_acceleration, turning_jerk = (reader.angle(f"angular_{n}", None, positive=True)
                                                         for n in ("speed", "acceleration", "jerk"))
    reader.finish()
    return CartesianPath(frame, points, rotations, seed_q, speed, acceleration, jerk, turning_speed,
                         turning_acceleration, turning_jerk,
                         labels=tuple(reader.field(f"{key}[{k + 1}]") for k in range(len(points))),
                         file=str(reader.file) if reader.file else None)

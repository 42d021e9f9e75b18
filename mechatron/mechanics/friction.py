r"""Friction in kinematic pairs [Egorov, sections 7.2–7.3] and the friction losses of a mechanism's pairs along a
motion, from the reactions of its model ([Egorov, 7.46]: the efficiency of the motion).

SI units: forces N, torques N·m, lengths m, angles rad, speeds m/s and rad/s, powers W. Coefficients f are
dimensionless; the rolling coefficient f_k is a length (m; the book gives it in mm).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from ..report.result import Result, json_ready

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

G = 9.81


def _coefficient(f: float, name: str = "f") -> float:
    if not (math.isfinite(f) and f >= 0):
        raise InputError(f"a friction coefficient {name} must be >= 0, got {f!r}")
    return float(f)


def static_friction(f0: float, normal: float) -> float:
    """F_t0 = f₀ Fⁿ [Egorov, 7.1]: the largest friction force before sliding (N)."""
    return _coefficient(f0, "f0") * abs(normal)


def sliding_friction(fc: float, normal: float) -> float:
    """F_T = f_c Fⁿ [Egorov, 7.2]: the sliding friction force (N) under the normal force Fⁿ (N); f_c < f₀, 0.1–0.3
    for most metals."""
    return _coefficient(fc, "fc") * abs(normal)


def rolling_resistance(fk: float, normal: float, radius: float) -> tuple[float, float]:
    """(M_k, F_k) = (f_k Fⁿ, f_k Fⁿ / r): the rolling-resistance moment (N·m) and force (N) of a roller of radius
    r (m); f_k is a length (m). The book's [Egorov, 7.3] writes F = f_k Fⁿ, which has the units of a moment: it is
    the moment; f_k = 0.005–0.015 mm for metals."""
    if not radius > 0:
        raise InputError(f"a roller radius must be > 0 m, got {radius!r}")
    moment = _coefficient(fk, "fk") * abs(normal)
    return moment, moment / radius


def friction_angle(f: float) -> float:
    """φ = arctan f [Egorov, 7.6, 7.17], rad; φ ≈ f for small f [Egorov, 7.7]."""
    return math.atan(_coefficient(f))


@dataclass(frozen=True)
class SlidingPairState:
    """A force F at angle α to the common normal on a sliding pair with friction f [Egorov, 7.4–7.10]: its normal and
    tangential components, the friction force, the net driving force and the regime."""

    normal: float
    tangential: float
    friction: float
    net: float
    friction_angle: float
    regime: str  # "accelerating", "uniform" or "at rest (self-locking)"


def sliding_pair(force: float, angle: float, f: float) -> SlidingPairState:
    """The sliding pair loaded by F (N) at α (rad) to the normal: Fⁿ = F cos α, Fᵗ = F sin α [Egorov, 7.4],
    F_T = f Fⁿ [Egorov, 7.5]; it moves when Fᵗ ≥ F_T [Egorov, 7.8], i.e. exactly when α ≥ φ = arctan f
    [Egorov, 7.10] (the book reaches it through F_ij/F ≈ 1, the exact test is tan α ≥ f)."""
    f = _coefficient(f)
    normal, tangential = force * math.cos(angle), force * math.sin(angle)
    friction = f * abs(normal)
    net = abs(tangential) - friction
    phi = math.atan(f)
    if math.isclose(abs(tangential), friction, rel_tol=1e-12, abs_tol=1e-15):
        regime = "uniform"
    else:
        regime = "accelerating" if net > 0 else "at rest (self-locking)"
    return SlidingPairState(normal, tangential, friction, net, phi, regime)


@dataclass(frozen=True)
class Incline:
    """A block of mass m (kg) on a plane inclined at θ (rad) with friction f: whether it slides down by itself
    (tan θ > f: the weight's angle to the normal is θ, [Egorov, 7.10]), and the force along the plane (N) to push it
    up or to let it down at constant speed, m g (sin θ ± f cos θ)."""

    mass: float
    angle: float
    f: float

    @property
    def slides_by_itself(self) -> bool:
        """tan θ > f [Egorov, 7.10]."""
        return math.tan(self.angle) > self.f

    @property
    def push_up(self) -> float:
        """m g (sin θ + f cos θ) (N)."""
        return self.mass * G * (math.sin(self.angle) + self.f * math.cos(self.angle))

    @property
    def hold_down(self) -> float:
        """The force along the plane, up the slope, that keeps the block sliding down at constant speed (negative:
        it must be pushed down)."""
        return self.mass * G * (math.sin(self.angle) - self.f * math.cos(self.angle))


def friction_circle(radius: float, f: float, exact: bool = True) -> float:
    """ρ = r sin φ [Egorov, 7.11], the radius (m) of the friction circle of a journal of radius r (m); ρ ≈ r f
    [Egorov, 7.13] with ``exact=False``. It does not depend on the load. At f = 0.3 the approximation is 4.4 %
    high."""
    if not radius > 0:
        raise InputError(f"a journal radius must be > 0 m, got {radius!r}")
    f = _coefficient(f)
    return radius * (math.sin(math.atan(f)) if exact else f)


def journal_friction_torque(load: float, radius: float, f: float, exact: bool = True) -> float:
    """M_T = F ρ [Egorov, 7.14]: the friction torque (N·m) of a journal carrying the radial load F (N)."""
    return abs(load) * friction_circle(radius, f, exact)


def journal_reaction(torque: float, radius: float, f: float, exact: bool = True) -> tuple[float, float]:
    """(F_T, F_ij) = (M/r, M/ρ) [Egorov, 7.15, 7.16]: the friction force at the contact and the full reaction (N) of a
    journal held at the edge of sliding by the torque M (N·m)."""
    return abs(torque) / radius, abs(torque) / friction_circle(radius, f, exact)


def higher_pair_friction(torque: float, radius: float, f: float) -> tuple[float, float, float]:
    """(φ, F_T, M_T) = (arctan f, M/r, F_T r) [Egorov, 7.17–7.19] (rad, N, N·m) for a higher pair with the radius of
    curvature r (m) under the torque M (N·m); rolling friction neglected (f_k ≪ f, [Egorov, section 7.3])."""
    force = abs(torque) / radius
    return friction_angle(f), force, force * radius


def sliding_power(normal: ArrayLike, speed: ArrayLike, f: float) -> NDArray[np.float64]:
    """Friction power (W) of a sliding pair: f |Fⁿ| |v| [Egorov, 7.2] for the normal force Fⁿ (N) and the sliding
    speed v (m/s) (arrays allowed)."""
    return _coefficient(f) * np.abs(normal) * np.abs(speed)


def journal_power(load: ArrayLike, angular_speed: ArrayLike, radius: float, f: float, exact: bool = True
                  ) -> NDArray[np.float64]:
    """Friction power (W) of a journal: ρ |F| |ω_rel| [Egorov, 7.14] for the radial load F (N), the relative angular
    speed ω_rel (rad/s), the journal radius (m) and f (arrays allowed)."""
    return friction_circle(radius, f, exact) * np.abs(load) * np.abs(angular_speed)


# ------------------------------------------------------------------------------------------------ mechanisms
@dataclass(frozen=True)
class PairFriction:
    """Friction data of one pair: journal radius (m) of a revolute pair (or None for a sliding pair) and f."""

    f: float
    radius: float | None = None


@dataclass(frozen=True)
class PairLoss:
    """The friction of one pair along a motion: the load across its axis (N), its relative speed (rad/s for a
    revolute pair or pin, m/s for a prismatic pair), its friction torque (N·m) or force (N) and the power lost (W),
    one value per sample."""

    name: str
    kind: str  # "revolute" or "prismatic"
    load: NDArray[np.float64]
    speed: NDArray[np.float64]
    friction: NDArray[np.float64]
    power: NDArray[np.float64]


def _integral(values: NDArray[np.float64], t: NDArray[np.float64]) -> float:
    return float(np.trapezoid(values, t)) if len(t) > 1 else 0.0


@dataclass
class FrictionLosses(Result):
    """Friction losses along a motion: per pair (:class:`PairLoss`) the load, relative speed, friction torque or
    force and power at each time ``t`` (s); the driving work of the actuators and the work lost in friction (J) and
    the efficiency η = 1 − A_friction / A_driving [Egorov, 7.46]."""

    t: NDArray[np.float64]
    pairs: list[PairLoss]
    driving_work: float
    friction_work: float

    @property
    def efficiency(self) -> float:
        """η = 1 − A_friction / A_driving [Egorov, 7.46] (NaN without driving work)."""
        return 1.0 - self.friction_work / self.driving_work if self.driving_work > 0 else float("nan")

    @property
    def summary(self) -> list[dict[str, Any]]:
        """Per pair: its kind, peak and mean friction power (W) and the work lost (J)."""
        duration = self.t[-1] - self.t[0] if len(self.t) > 1 else 0.0
        return [{"pair": p.name, "kind": p.kind, "peak_power": float(p.power.max()),
                 "mean_power": _integral(p.power, self.t) / duration if duration > 0 else 0.0,
                 "work": _integral(p.power, self.t)} for p in self.pairs]

    def to_frame(self) -> pd.DataFrame:
        """Per sample: ``t`` (s) and per pair ``friction_torque_NAME`` (N·m) or ``friction_force_NAME`` (N),
        ``load_NAME`` (N across the axis), ``speed_NAME`` (rad/s or m/s) and ``power_NAME`` (W)."""
        import pandas as pd

        columns: dict[str, NDArray[np.float64]] = {"t": self.t}
        for p in self.pairs:
            columns[f"{'friction_torque' if p.kind == 'revolute' else 'friction_force'}_{p.name}"] = p.friction
            columns[f"load_{p.name}"], columns[f"speed_{p.name}"], columns[f"power_{p.name}"] = p.load, p.speed, p.power
        return pd.DataFrame(columns)

    def as_dict(self) -> dict:
        """duration (s), samples, pairs (per pair: kind, peak and mean power in W, work in J), driving_work,
        friction_work (J) and efficiency."""
        return {"duration": float(self.t[-1] - self.t[0]) if len(self.t) else 0.0, "samples": len(self.t),
                "pairs": self.summary, "driving_work": self.driving_work, "friction_work": self.friction_work,
                "efficiency": json_ready(self.efficiency)}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The friction power of each pair against time."""
        from ..report.figures import figure_axes, style_axes

        fig, ax = figure_axes(ax)
        for p in self.pairs:
            ax.plot(self.t, p.power, label=f"{p.name} ({p.kind})")
        style_axes(ax, "t (s)", "friction power (W)", f"friction losses: η = {self.efficiency:.4g}", legend=True)
        return fig

    def __str__(self) -> str:
        lines = [f"friction losses over {len(self.t)} samples, {self.as_dict()['duration']:g} s",
                 f"{'pair':<28}{'kind':<11}{'peak (W)':>12}{'mean (W)':>12}{'work (J)':>12}"]
        for row in self.summary:
            lines.append(f"{row['pair']:<28}{row['kind']:<11}{row['peak_power']:12.4g}{row['mean_power']:12.4g}"
                         f"{row['work']:12.4g}")
        lines.append(f"driving work A_driving = {self.driving_work:.6g} J, friction work A_friction = "
                     f"{self.friction_work:.6g} J")
        lines.append(f"efficiency η = 1 − A_friction/A_driving = {self.efficiency:.6g} [Egorov, 7.46]")
        return "\n".join(lines)


def friction_losses(mech: Mechanism, trajectory: Any, pairs: Mapping[str, PairFriction], loads: Loads = None
                    ) -> FrictionLosses:
    """Friction power (W) of the given pairs along ``trajectory`` (a :class:`~mechatron.dynamics.motion.Trajectory`:
    t in s, q, v, a of the joints or, for a closed loop, of the actuated coordinates) under the external ``loads``,
    from the model's reactions computed without friction (a first-order estimate). ``pairs`` maps tree joints — and,
    for a closed loop, pin closures by name — to their friction data. A revolute pair or pin is a journal loaded by
    the reaction across its axis (for a pin of a planar loop: its in-plane force) turning at the relative angular
    speed of its two bodies [Egorov, 7.11–7.14]; a prismatic pair slides under the reaction across its axis
    [Egorov, 7.2]. The driving work is the positive work of the actuators (the joints of a serial arm, the actuated
    coordinates of a closed loop); the efficiency is η = 1 − A_friction / A_driving [Egorov, 7.46]."""
    import pinocchio as pin

    from ..dynamics.trajectory import closed_loop_states
    from ..dynamics.tree import inverse_dynamics, joint_wrenches

    model = mech.model
    data = model.createData()
    t = np.asarray(trajectory.t, dtype=float)
    pins: list[dict[str, NDArray[np.float64]]] = []
    if mech.closures:
        from ..dynamics.constrained import inverse, reactions

        Q, V, A = closed_loop_states(mech, trajectory)
        wrenches, forces = [], []
        for q, v, a in zip(Q, V, A):
            force, lam = inverse(mech, q, v, a, loads)
            r = reactions(mech, q, v, a, lam, loads)
            wrenches.append(r.joints)
            pins.append(r.pins)
            forces.append([force[n] for n in mech.actuated])
        W = np.array(wrenches)  # (N, njoints − 1, 6): world force and moment each joint transmits
        actuator_power = np.array(forces) * np.asarray(trajectory.v, dtype=float)
    else:
        Q, V, A = (np.asarray(x, dtype=float) for x in (trajectory.q, trajectory.v, trajectory.a))
        W = np.array([joint_wrenches(mech, q, v, a, loads) for q, v, a in zip(Q, V, A)])
        actuator_power = inverse_dynamics(mech, Q, V, A, loads) * V
    closures = {c.name: c for c in mech.closures}
    losses: list[PairLoss] = []
    total = np.zeros(len(t))
    for name, pair in pairs.items():
        if name in closures:
            closure = closures[name]
            if not hasattr(closure, "a") or not hasattr(closure, "planar"):
                raise InputError(f"closure {name}: friction is modelled for pins only")
            across = np.array([np.linalg.norm(p[name][:2] if closure.planar else p[name]) for p in pins])
            fa, fb = mech.frame_id(closure.a), mech.frame_id(closure.b)
            speed = np.empty(len(t))
            for i, (q, v) in enumerate(zip(Q, V)):
                pin.forwardKinematics(model, data, q, v)
                speed[i] = (pin.getFrameVelocity(model, data, fa, pin.LOCAL_WORLD_ALIGNED).angular
                            - pin.getFrameVelocity(model, data, fb, pin.LOCAL_WORLD_ALIGNED).angular)[2]
            kind = "revolute"
        else:
            j = mech.joint_id(name)
            kind = mech.joint_kind(j)
            axes = np.empty((len(Q), 3))
            for i, q in enumerate(Q):
                pin.forwardKinematics(model, data, q)
                axes[i] = data.oMi[j].rotation @ _local_axis(model.joints[j])
            force = W[:, j - 1, :3]
            across = np.linalg.norm(force - (force * axes).sum(axis=1, keepdims=True) * axes, axis=1)
            speed = V[:, model.joints[j].idx_v]
        if kind == "revolute":
            if pair.radius is None:
                raise InputError(f"pair {name} is revolute: give its journal radius")
            power = journal_power(across, speed, pair.radius, pair.f)
            friction = across * friction_circle(pair.radius, pair.f)
        elif kind == "prismatic":
            power = sliding_power(across, speed, pair.f)
            friction = pair.f * across
        else:
            raise InputError(f"joint {name}: friction of a {kind} joint is not modelled")
        losses.append(PairLoss(name, kind, across, speed, friction, power))
        total += power
    driving = np.maximum(np.atleast_2d(actuator_power), 0.0).sum(axis=1)
    return FrictionLosses(t, losses, _integral(driving, t), _integral(total, t))


def _local_axis(joint: Any) -> NDArray[np.float64]:
    short = joint.shortname()
    if short[-1] in "XYZ" and ("JointModelR" in short or "JointModelP" in short):
        return np.eye(3)["XYZ".index(short[-1])]
    if "Unaligned" in short:
        return np.asarray(joint.extract().axis, dtype=float)
    raise InputError(f"friction needs revolute or prismatic joints, not {short}")

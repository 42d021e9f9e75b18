r"""Friction in kinematic pairs (textbook chapter 7, sections 7.2–7.3) and the friction losses of a mechanism's
pairs along a motion, from the reactions of its model.

SI units: forces N, torques N·m, lengths m, angles rad, speeds m/s and rad/s, powers W. Coefficients f are
dimensionless; the rolling coefficient f_k is a length (m; the book gives it in mm).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError
from ..model.mechanism import Mechanism

G = 9.81


def _coefficient(f: float, name: str = "f") -> float:
    if not (math.isfinite(f) and f >= 0):
        raise InputError(f"a friction coefficient {name} must be >= 0, got {f!r}")
    return float(f)


def static_friction(f0: float, normal: float) -> float:
    """F_t0 = f₀ Fⁿ (7.1): the largest friction force before sliding (N)."""
    return _coefficient(f0, "f0") * abs(normal)


def sliding_friction(fc: float, normal: float) -> float:
    """F_T = f_c Fⁿ (7.2): the sliding friction force (N); f_c < f₀, 0.1–0.3 for most metals (line 4110)."""
    return _coefficient(fc, "fc") * abs(normal)


def rolling_resistance(fk: float, normal: float, radius: float) -> tuple[float, float]:
    """(M_k, F_k) = (f_k Fⁿ, f_k Fⁿ / r): the rolling-resistance moment (N·m) and force (N) of a roller of radius
    r (m); f_k is a length (m). The book's (7.3) writes F = f_k Fⁿ, which has the units of a moment: it is the
    moment; f_k = 0.005–0.015 mm for metals (line 4116)."""
    if not radius > 0:
        raise InputError(f"a roller radius must be > 0 m, got {radius!r}")
    moment = _coefficient(fk, "fk") * abs(normal)
    return moment, moment / radius


def friction_angle(f: float) -> float:
    """φ = arctan f (7.6, 7.17), rad; φ ≈ f for small f (7.7)."""
    return math.atan(_coefficient(f))


@dataclass(frozen=True)
class SlidingPairState:
    """A force F at angle α to the common normal on a sliding pair with friction f (7.4–7.10): its normal and
    tangential components, the friction force, the net driving force and the regime."""

    normal: float
    tangential: float
    friction: float
    net: float
    friction_angle: float
    regime: str  # "accelerating", "uniform" or "at rest (self-locking)"


def sliding_pair(force: float, angle: float, f: float) -> SlidingPairState:
    """The sliding pair loaded by F (N) at α (rad) to the normal: Fⁿ = F cos α, Fᵗ = F sin α (7.4), F_T = f Fⁿ
    (7.5); it moves when Fᵗ ≥ F_T (7.8), i.e. exactly when α ≥ φ = arctan f (7.10; the book reaches it through
    F_ij/F ≈ 1, the exact test is tan α ≥ f)."""
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
    (tan θ > f: the weight's angle to the normal is θ, 7.10), and the force along the plane (N) to push it up or
    to let it down at constant speed, m g (sin θ ± f cos θ)."""

    mass: float
    angle: float
    f: float

    @property
    def slides_by_itself(self) -> bool:
        return math.tan(self.angle) > self.f

    @property
    def push_up(self) -> float:
        return self.mass * G * (math.sin(self.angle) + self.f * math.cos(self.angle))

    @property
    def hold_down(self) -> float:
        """The force along the plane, up the slope, that keeps the block sliding down at constant speed (negative:
        it must be pushed down)."""
        return self.mass * G * (math.sin(self.angle) - self.f * math.cos(self.angle))


def friction_circle(radius: float, f: float, exact: bool = True) -> float:
    """ρ = r sin φ (7.11), the radius (m) of the friction circle of a journal of radius r; ρ ≈ r f (7.13) with
    ``exact=False``. It does not depend on the load (line 4190). At f = 0.3 the approximation is 4.4 % high."""
    if not radius > 0:
        raise InputError(f"a journal radius must be > 0 m, got {radius!r}")
    f = _coefficient(f)
    return radius * (math.sin(math.atan(f)) if exact else f)


def journal_friction_torque(load: float, radius: float, f: float, exact: bool = True) -> float:
    """M_T = F ρ (7.14): the friction torque (N·m) of a journal carrying the radial load F (N)."""
    return abs(load) * friction_circle(radius, f, exact)


def journal_reaction(torque: float, radius: float, f: float, exact: bool = True) -> tuple[float, float]:
    """(F_T, F_ij) = (M/r, M/ρ) (7.15, 7.16): the friction force at the contact and the full reaction (N) of a
    journal held at the edge of sliding by the torque M (N·m)."""
    return abs(torque) / radius, abs(torque) / friction_circle(radius, f, exact)


def higher_pair_friction(torque: float, radius: float, f: float) -> tuple[float, float, float]:
    """(φ, F_T, M_T) = (arctan f, M/r, F_T r) (7.17–7.19) for a higher pair with the radius of curvature r (m);
    rolling friction neglected (f_k ≪ f, line 4206)."""
    force = abs(torque) / radius
    return friction_angle(f), force, force * radius


def sliding_power(normal, speed, f: float):
    """Friction power (W) of a sliding pair: f |Fⁿ| |v| (arrays allowed)."""
    return _coefficient(f) * np.abs(normal) * np.abs(speed)


def journal_power(load, angular_speed, radius: float, f: float, exact: bool = True):
    """Friction power (W) of a journal: ρ |F| |ω_rel| (arrays allowed)."""
    return friction_circle(radius, f, exact) * np.abs(load) * np.abs(angular_speed)


# ------------------------------------------------------------------------------------------------ mechanisms
@dataclass(frozen=True)
class PairFriction:
    """Friction data of one pair: journal radius (m) of a revolute pair (or None for a sliding pair) and f."""

    f: float
    radius: float | None = None


@dataclass
class FrictionLosses:
    """Friction losses along a motion: ``table`` (t, per pair: load (N), relative speed, friction force or torque,
    power), ``summary`` (per pair: peak and mean power, work), the driving work of the actuators and the
    efficiency η = 1 − A_friction / A_driving (7.46)."""

    table: pd.DataFrame
    summary: pd.DataFrame
    driving_work: float
    friction_work: float

    @property
    def efficiency(self) -> float:
        return 1.0 - self.friction_work / self.driving_work if self.driving_work > 0 else float("nan")


def friction_losses(mech: Mechanism, trajectory, pairs: Mapping[str, PairFriction],
                    loads: Sequence[Sequence] | None = None) -> FrictionLosses:
    """Friction power of the given pairs along ``trajectory`` from the model's reactions, computed without
    friction (a first-order estimate). ``pairs`` maps tree joints — and, for a closed loop, pin closures by name —
    to their friction data. A revolute pair or pin is a journal loaded by the reaction across its axis (for a pin
    of a planar loop: its in-plane force) turning at the relative angular speed of its two bodies; a prismatic
    pair slides under the reaction across its axis. The driving work is the positive work of the actuators (the
    joints of a serial arm, the actuated coordinates of a closed loop)."""
    import pinocchio as pin

    from ..dynamics.trajectory import closed_loop_states
    from ..dynamics.tree import inverse_dynamics, joint_wrenches

    model = mech.model
    data = model.createData()
    t = np.asarray(trajectory.t, dtype=float)
    pins: list[dict[str, np.ndarray]] = []
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
    columns: dict[str, np.ndarray] = {"t": t}
    rows = []
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
            columns[f"friction_torque_{name}"] = across * friction_circle(pair.radius, pair.f)
        elif kind == "prismatic":
            power = sliding_power(across, speed, pair.f)
            columns[f"friction_force_{name}"] = pair.f * across
        else:
            raise InputError(f"joint {name}: friction of a {kind} joint is not modelled")
        columns[f"load_{name}"], columns[f"speed_{name}"], columns[f"power_{name}"] = across, speed, power
        total += power
        rows.append({"pair": name, "kind": kind, "peak_power": float(power.max()),
                     "mean_power": float(np.trapezoid(power, t) / (t[-1] - t[0])) if len(t) > 1 else 0.0,
                     "work": float(np.trapezoid(power, t)) if len(t) > 1 else 0.0})
    driving = np.maximum(np.atleast_2d(actuator_power), 0.0).sum(axis=1)
    driving_work = float(np.trapezoid(driving, t)) if len(t) > 1 else 0.0
    return FrictionLosses(pd.DataFrame(columns), pd.DataFrame(rows), driving_work,
                          float(np.trapezoid(total, t)) if len(t) > 1 else 0.0)


def _local_axis(joint) -> np.ndarray:
    short = joint.shortname()
    if short[-1] in "XYZ" and ("JointModelR" in short or "JointModelP" in short):
        return np.eye(3)["XYZ".index(short[-1])]
    if "Unaligned" in short:
        return np.asarray(joint.extract().axis, dtype=float)
    raise InputError(f"friction needs revolute or prismatic joints, not {short}")

r"""Kinetostatics (textbook chapter 5): the forces at one position of a moving mechanism.

d'Alembert: every body carries its inertia force Φ = −m a_S (5.3) at its centre of mass and its inertia couple
M_И = −J_S ε (5.4); with them and the external loads the mechanism is in equilibrium, which gives the driving
forces of the inputs and the reactions in the pairs (:func:`kinetostatics`, through the closure multipliers and an
RNEA pass — the numerical form of the book's group-by-group procedure of 5.6).

Zhukovsky's lever (5.11–5.19) is the principle of virtual power: for a unit rate of input k (the others held),
Q_D,k + Σ_i (F_i · v_i + M_i ω_i) = 0 over all external, gravity and inertia forces and couples, so
Q_D,k = −Σ_i (F_i · v_i + M_i ω_i) with v_i, ω_i the first transfer functions (:func:`zhukovsky`). It is an
independent check of the driving forces. The book's (5.19) prints F_D = −[Σ M_p(F_n) − Σ M_p(F_И)]/h_FD; from (5.18)
it must be F_D = −[Σ M_p(F_n) + Σ M_p(F_И)]/h_FD.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..kinematics.loops import joint_acceleration, joint_velocity
from ..model.mechanism import Mechanism
from . import constrained


@dataclass(frozen=True)
class InertiaLoad:
    """d'Alembert load of one body: Φ = −m a_S (N, world) at the centre S (m, world), M_И = −J_S ε (N·m, world)."""

    body: str
    centre: np.ndarray
    force: np.ndarray
    couple: np.ndarray


def inertia_loads(mech: Mechanism, q, v, a) -> list[InertiaLoad]:
    """Inertia force and couple of every body with mass, from its centre's classical acceleration and its angular
    acceleration (world axes): M_И = −(I_S ε + ω × I_S ω)."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q, v, a)
    out = []
    names = mech.link_names
    for j in range(1, model.njoints):
        inertia = model.inertias[j]
        if inertia.mass == 0 and not np.any(inertia.inertia):
            continue
        R, c = data.oMi[j].rotation, inertia.lever
        w, dw, acc = data.v[j].angular, data.a[j].angular, data.a[j].linear
        # classical acceleration of the centre, body axes: a_O + ω × v_O + α × c + ω × (ω × c)
        a_centre = acc + np.cross(w, data.v[j].linear) + np.cross(dw, c) + np.cross(w, np.cross(w, c))
        I = inertia.inertia
        out.append(InertiaLoad(names[j - 1], data.oMi[j].act(c), -inertia.mass * (R @ a_centre),
                               -(R @ (I @ dw + np.cross(w, I @ w)))))
    return out


@dataclass(frozen=True)
class Kinetostatics:
    """Forces at one position: the driving force/torque of each input, the pin forces and joint wrenches
    (:class:`~mechatron.constrained.Reactions`), the bodies' inertia loads, and the driving forces again from
    Zhukovsky's lever (virtual power)."""

    driving: dict[str, float]
    reactions: constrained.Reactions
    inertia: list[InertiaLoad]
    zhukovsky: dict[str, float]
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray


def kinetostatics(mech: Mechanism, q, rates: Mapping[str, float], accelerations: Mapping[str, float] | None = None,
                  loads: Sequence[Sequence] | None = None) -> Kinetostatics:
    """Driving forces and reactions of ``mech`` at the assembled ``q`` moving with the input ``rates`` and
    ``accelerations`` (missing ones 0) under gravity and ``loads`` [(frame, world force[, world moment]), …]."""
    q = np.asarray(q, dtype=float)
    v = joint_velocity(mech, q, rates) if mech.closures else np.array([rates.get(n, 0.0) for n in mech.joint_names])
    if mech.closures:
        a = joint_acceleration(mech, q, v, accelerations or {})
    else:
        a = np.array([(accelerations or {}).get(n, 0.0) for n in mech.joint_names])
    driving, lam = constrained.inverse(mech, q, v, a, loads)
    return Kinetostatics(driving, constrained.reactions(mech, q, v, a, lam, loads), inertia_loads(mech, q, v, a),
                         zhukovsky(mech, q, v, a, loads), q, v, a)


def zhukovsky(mech: Mechanism, q, v, a, loads: Sequence[Sequence] | None = None) -> dict[str, float]:
    """Driving force of each input from virtual power: Q_D,k = −Σ (F·v_k + M·ω_k) over gravity, external loads and
    the inertia loads, for the transfer functions of a unit rate of input k."""
    q = np.asarray(q, dtype=float)
    model, data = mech.model, mech.data
    gravity = model.gravity.linear
    bodies = inertia_loads(mech, q, v, a)
    out = {}
    for name in mech.actuated:
        unit = joint_velocity(mech, q, {name: 1.0}) if mech.closures else \
            np.eye(mech.nv)[mech.model.joints[mech.joint_id(name)].idx_v]
        pin.forwardKinematics(model, data, q, unit)
        power = 0.0
        for j, body in zip([j for j in range(1, model.njoints) if model.inertias[j].mass > 0
                            or np.any(model.inertias[j].inertia)], bodies):
            R = data.oMi[j].rotation
            w = R @ data.v[j].angular
            v_centre = R @ (data.v[j].linear + np.cross(data.v[j].angular, model.inertias[j].lever))
            weight = model.inertias[j].mass * gravity
            power += (body.force + weight) @ v_centre + body.couple @ w
        for load in loads or []:
            fid = mech.frame_id(load[0])
            pin.updateFramePlacement(model, data, fid)
            twist = pin.getFrameVelocity(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            power += np.asarray(load[1], dtype=float) @ twist.linear
            if len(load) > 2:
                power += np.asarray(load[2], dtype=float) @ twist.angular
        out[name] = float(-power)
    return out

r"""Kinetostatics: the forces at one position of a moving mechanism ([Egorov, ch. 5]).

d'Alembert: every body carries its inertia force Φ = −m a_S [Egorov, 5.3] at its centre of mass and its inertia
couple M_И = −J_S ε [Egorov, 5.4]; with them and the external loads the mechanism is in equilibrium
[Egorov, 5.1–5.2], which gives the driving forces of the inputs and the reactions in the pairs
(:func:`kinetostatics`, through the closure multipliers and an RNEA pass — the numerical form of the book's
group-by-group procedure, [Egorov, section 5.6]).

Zhukovsky's lever [Egorov, 5.11–5.19] is the principle of virtual power: for a unit rate of input k (the others
held), Q_D,k + Σ_i (F_i · v_i + M_i ω_i) = 0 over all external, gravity and inertia forces and couples, so
Q_D,k = −Σ_i (F_i · v_i + M_i ω_i) with v_i, ω_i the first transfer functions (:func:`zhukovsky`). It is an
independent check of the driving forces. [Egorov, 5.19] prints F_D = −[Σ M_p(F_n) − Σ M_p(F_И)]/h_FD; from
[Egorov, 5.18] it must be F_D = −[Σ M_p(F_n) + Σ M_p(F_И)]/h_FD.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..kinematics.loops import joint_acceleration, joint_velocity
from ..model.closures import Pin
from ..model.loads import Loads, as_loads
from ..model.mechanism import Mechanism
from ..report.result import Result
from . import constrained
from .motion import coordinate_names
from .series import text_table

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

Array = NDArray[np.float64]


@dataclass(frozen=True)
class InertiaLoad:
    """d'Alembert load of one body: Φ = −m a_S (N, world) [Egorov, 5.3] at the centre S (m, world),
    M_И = −J_S ε (N·m, world) [Egorov, 5.4]."""

    body: str
    centre: Array
    force: Array
    couple: Array


def _bodies(mech: Mechanism) -> list[int]:
    """The joints whose bodies have mass or inertia."""
    model = mech.model
    return [j for j in range(1, model.njoints) if model.inertias[j].mass > 0 or np.any(model.inertias[j].inertia)]


def inertia_loads(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> list[InertiaLoad]:
    """Inertia force Φ = −m a_S (N) and couple M_И = −(I_S ε + ω × I_S ω) (N·m) of every body with mass, from its
    centre's classical acceleration and its angular acceleration (world axes) at the state (q, q̇, q̈) (rad, m and
    their rates): [Egorov, 5.3–5.4], with the gyroscopic term of a spatial body."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q, v, a)
    out = []
    names = mech.link_names
    for j in _bodies(mech):
        inertia = model.inertias[j]
        R, c = data.oMi[j].rotation, inertia.lever
        w, dw, acc = data.v[j].angular, data.a[j].angular, data.a[j].linear
        # classical acceleration of the centre, body axes: a_O + ω × v_O + α × c + ω × (ω × c)
        a_centre = acc + np.cross(w, data.v[j].linear) + np.cross(dw, c) + np.cross(w, np.cross(w, c))
        I = inertia.inertia
        out.append(InertiaLoad(names[j - 1], data.oMi[j].act(c), -inertia.mass * (R @ a_centre),
                               -(R @ (I @ dw + np.cross(w, I @ w)))))
    return out


@dataclass(frozen=True, eq=False)
class Kinetostatics(Result):
    """Forces at one position.

    Attributes:
        driving: Driving force (N) or torque (N·m) of each input, from the constrained inverse dynamics.
        reactions: Pin forces and tree-joint wrenches (:class:`~mechatron.dynamics.constrained.Reactions`).
        inertia: The bodies' inertia loads.
        zhukovsky: The driving forces again, from Zhukovsky's lever (virtual power) [Egorov, 5.18].
        q, v, a: The state (configuration; rad/s, m/s; rad/s², m/s²).
        mechanism: Name of the mechanism.
        joints: Names of the tree joints (rows of ``reactions.joints``).
        origins: World positions (m) of the joint origins (njoints − 1, 3).
        parents: Each joint's parent joint (0: the ground), for drawing.
        pin_points: World position (m) of each pin closure's point ``a`` (where its force acts).
        angular: Which inputs are angles (their driving force is a torque, N·m).
    """

    driving: dict[str, float]
    reactions: constrained.Reactions
    inertia: list[InertiaLoad]
    zhukovsky: dict[str, float]
    q: Array
    v: Array
    a: Array
    mechanism: str = ""
    joints: list[str] = field(default_factory=list)
    origins: Array = field(default_factory=lambda: np.zeros((0, 3)))
    parents: list[int] = field(default_factory=list)
    pin_points: dict[str, Array] = field(default_factory=dict)
    angular: dict[str, bool] = field(default_factory=dict)

    def _unit(self, name: str) -> str:
        return "N·m" if self.angular.get(name, True) else "N"

    def to_frame(self) -> pd.DataFrame:
        """One row per item: ``kind`` ("driving", "zhukovsky", "joint", "pin", "inertia"), ``name``, ``value``
        (driving force, N or N·m), ``force_x/y/z`` (N) and ``moment_x/y/z`` (N·m) in world axes, and the world
        point ``x/y/z`` (m) where they act (joint origin, pin point, centre of mass)."""
        import pandas as pd

        rows: list[dict] = []
        for kind, values in (("driving", self.driving), ("zhukovsky", self.zhukovsky)):
            rows += [{"kind": kind, "name": name, "value": value} for name, value in values.items()]

        def vector_row(kind: str, name: str, force, moment, point) -> dict:
            row: dict[str, Any] = {"kind": kind, "name": name}
            for prefix, vector in (("force", force), ("moment", moment)):
                if vector is not None:
                    padded = np.zeros(3)
                    padded[:len(vector)] = vector
                    row.update({f"{prefix}_{axis}": float(x) for axis, x in zip("xyz", padded)})
            row.update({axis: float(x) for axis, x in zip("xyz", point)})
            return row

        for name, wrench, origin in zip(self.joints, self.reactions.joints, self.origins):
            rows.append(vector_row("joint", name, wrench[:3], wrench[3:], origin))
        for name, force in self.reactions.pins.items():
            rows.append(vector_row("pin", name, force, None, self.pin_points.get(name, np.full(3, np.nan))))
        for body in self.inertia:
            rows.append(vector_row("inertia", body.body, body.force, body.couple, body.centre))
        columns = ["kind", "name", "value", *(f"{p}_{a}" for p in ("force", "moment") for a in "xyz"), "x", "y", "z"]
        return pd.DataFrame(rows, columns=columns)

    def as_dict(self) -> dict:
        """mechanism; driving and zhukovsky (input → N or N·m); joints (joint → force N, moment N·m, origin m, world
        axes); pins (closure → force N); inertia (body, centre m, force N, couple N·m); q, v, a."""
        return {"mechanism": self.mechanism, "driving": dict(self.driving), "zhukovsky": dict(self.zhukovsky),
                "units": {name: self._unit(name) for name in self.driving},
                "joints": {name: {"force": w[:3].tolist(), "moment": w[3:].tolist(), "origin": o.tolist()}
                           for name, w, o in zip(self.joints, self.reactions.joints, self.origins)},
                "pins": {name: np.asarray(f).tolist() for name, f in self.reactions.pins.items()},
                "inertia": [{"body": b.body, "centre": b.centre.tolist(), "force": b.force.tolist(),
                             "couple": b.couple.tolist()} for b in self.inertia],
                "q": self.q.tolist(), "v": self.v.tolist(), "a": self.a.tolist()}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The forces as arrows at the points where they act (joint reactions at the joint origins, pin forces,
        inertia forces at the centres of mass), on the world plane in which the points spread most; one scale
        (N per m of drawing) for all arrows."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, 8.0, 6.0)
        groups = [("joint reactions", self.origins, self.reactions.joints[:, :3], "tab:blue"),
                  ("pin forces", np.array([self.pin_points[n] for n in self.reactions.pins if n in self.pin_points]),
                   np.array([np.pad(f, (0, 3 - len(f))) for n, f in self.reactions.pins.items()
                             if n in self.pin_points]), "tab:red"),
                  ("inertia forces", np.array([b.centre for b in self.inertia]),
                   np.array([b.force for b in self.inertia]), "tab:green")]
        groups = [(label, np.reshape(p, (-1, 3)), np.reshape(f, (-1, 3)), c) for label, p, f, c in groups if len(p)]
        points = np.vstack([p for _, p, _, _ in groups])
        spread = np.ptp(points, axis=0)
        i, j = sorted(np.argsort(-spread, kind="stable")[:2]) if spread.max() > 0 else (0, 2)
        span = max(spread[i], spread[j], 1e-3)
        largest = max(float(np.hypot(f[:, i], f[:, j]).max(initial=0.0)) for _, _, f, _ in groups) or 1.0
        scale = 0.25 * span / largest  # m of drawing per N
        links = [(self.origins[parent - 1], self.origins[child - 1]) for child, parent in
                 enumerate(self.parents, start=1) if parent > 0]
        for k, (start, end) in enumerate(links):
            ax.plot([start[i], end[i]], [start[j], end[j]], color="0.75", linewidth=2,
                    label="links (joint to child joint)" if k == 0 else "_")
        ax.plot(self.origins[:, i], self.origins[:, j], "o", color="0.3", markersize=4, label="joint origins")
        tips = [points]
        for label, p, f, colour in groups:
            ax.quiver(p[:, i], p[:, j], f[:, i] * scale, f[:, j] * scale, angles="xy", scale_units="xy", scale=1,
                      color=colour, width=0.004, label=label)
            tips.append(p + f * scale)
        extent = np.vstack(tips)[:, [i, j]]
        low, high = extent.min(axis=0), extent.max(axis=0)
        pad = 0.08 * max(float(np.max(high - low)), 1e-3)
        ax.set_xlim(low[0] - pad, high[0] + pad)
        ax.set_ylim(low[1] - pad, high[1] + pad)
        ax.set_aspect("equal", adjustable="box")
        axis = "xyz"
        style_axes(ax, f"{axis[i]} (m)", f"{axis[j]} (m)",
                   f"{self.mechanism}: forces at one position (arrows: {1 / scale:.4g} N per m)", legend=True)
        return figure

    def __str__(self) -> str:
        driving = [{"input": n, "driving": f, "zhukovsky": self.zhukovsky.get(n), "unit": self._unit(n)}
                   for n, f in self.driving.items()]
        joints = [{"joint": n, **{f"F{a}": w[k] for k, a in enumerate("xyz")},
                   **{f"M{a}": w[3 + k] for k, a in enumerate("xyz")}}
                  for n, w in zip(self.joints, self.reactions.joints)]
        pins = [{"pin": n, **{f"F{a}": x for a, x in zip("xyz", f)}} for n, f in self.reactions.pins.items()]
        bodies = [{"body": b.body, **{f"F{a}": b.force[k] for k, a in enumerate("xyz")},
                   **{f"M{a}": b.couple[k] for k, a in enumerate("xyz")}} for b in self.inertia]
        parts = [f"{self.mechanism}: forces at one position (world axes; N, N·m)",
                 "driving forces (inverse dynamics; Zhukovsky's lever, [Egorov, 5.18]):", text_table(driving),
                 "forces and moments the joints transmit to the child bodies (about the joint origins):",
                 text_table(joints)]
        if pins:
            parts += ["forces on the pins' first points:", text_table(pins)]
        parts += ["inertia loads Φ = −m a_S, M_И = −J_S ε [Egorov, 5.3–5.4]:", text_table(bodies)]
        return "\n".join(parts)


def _joint_rates(mech: Mechanism, values: Mapping[str, float] | None) -> Array:
    """Joint-coordinate values (nv,) from {coordinate name: value} (missing ones 0)."""
    values = values or {}
    return np.array([float(values.get(n, 0.0)) for n in coordinate_names(mech)])


def kinetostatics(mech: Mechanism, q: ArrayLike, rates: Mapping[str, float],
                  accelerations: Mapping[str, float] | None = None, loads: Loads = None) -> Kinetostatics:
    """Driving forces (N, N·m) and reactions of ``mech`` at the assembled configuration ``q`` moving with the input
    ``rates`` (rad/s, m/s) and ``accelerations`` (rad/s², m/s²; missing ones 0) under gravity and ``loads``
    (:class:`~mechatron.model.Load` s): d'Alembert's equilibrium [Egorov, 5.1–5.4] solved by the constrained
    inverse dynamics, checked by Zhukovsky's lever [Egorov, 5.18]. For a serial arm the rates are the joints'."""
    q = mech.check_configuration(q)
    loads = as_loads(loads)
    if mech.closures:
        v = joint_velocity(mech, q, rates)
        a = joint_acceleration(mech, q, v, accelerations or {})
    else:
        v, a = _joint_rates(mech, rates), _joint_rates(mech, accelerations)
    driving, lam = constrained.inverse(mech, q, v, a, loads)
    reactions = constrained.reactions(mech, q, v, a, lam, loads)
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    origins = np.array([data.oMi[j].translation for j in range(1, model.njoints)])
    pin_points = {c.name: data.oMf[mech.frame_id(c.a)].translation.copy() for c in mech.closures
                  if isinstance(c, Pin)}
    angular = {n: mech.joint_kind(n) == "revolute" for n in mech.actuated}
    return Kinetostatics(driving, reactions, inertia_loads(mech, q, v, a), zhukovsky(mech, q, v, a, loads), q, v, a,
                         mech.name, mech.joint_names, origins, list(model.parents)[1:], pin_points, angular)


def zhukovsky(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, loads: Loads = None) -> dict[str, float]:
    """Driving force (N) or torque (N·m) of each input from virtual power (Zhukovsky's lever, [Egorov, 5.18]):
    Q_D,k = −Σ (F·v_k + M·ω_k) over gravity, external ``loads`` and the inertia loads [Egorov, 5.3–5.4] (the drives'
    rotors too, J_r u² q̈ through the armature), for the transfer functions v_k, ω_k of a unit rate of input k, at
    the state (q, q̇, q̈)."""
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
        for j, body in zip(_bodies(mech), bodies):
            R = data.oMi[j].rotation
            w = R @ data.v[j].angular
            v_centre = R @ (data.v[j].linear + np.cross(data.v[j].angular, model.inertias[j].lever))
            weight = model.inertias[j].mass * gravity
            power += (body.force + weight) @ v_centre + body.couple @ w
        power -= float(model.armature @ (np.asarray(a, dtype=float) * unit))  # the drives' rotors, J_r u² q̈
        for load in as_loads(loads):
            fid = mech.frame_id(load.frame)
            pin.updateFramePlacement(model, data, fid)
            twist = pin.getFrameVelocity(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            power += load.force @ twist.linear + load.moment @ twist.angular
        out[name] = float(-power)
    return out

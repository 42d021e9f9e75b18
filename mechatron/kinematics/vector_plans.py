r"""Velocity and acceleration plans of a mechanism at one position ([Egorov, 4.2, fig. 4.10]).

The plan method draws every point's absolute velocity from a pole p and its acceleration from a pole π; the segment
joining the tips of two points B, C of one body is their relative velocity v_CB = v_C − v_B (acceleration a_CB), and
the figure of a body on the plan is similar to the body itself. :func:`plans` computes the vectors the plans are
drawn from, exactly (from Pinocchio, not graphically): v = J q̇ ([Egorov, 4.47–4.48]) and the classical acceleration
a = J q̈ + J̇ q̇ ([Egorov, 4.49–4.50]).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism
from ..report.result import Result, json_ready
from .transfer import point_state

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass
class Plans(Result):
    """Positions, velocities and accelerations of the points of a mechanism at one position: what its velocity and
    acceleration plans are drawn from ([Egorov, fig. 4.10]).

    Attributes:
        mechanism: The mechanism.
        q, v, a: The configuration (nq,), joint velocity and joint acceleration (nv,).
        frames: The points (frame names), in order.
        positions: World positions (m) of their origins, (n, 3).
        velocities: Their velocities (m/s), (n, 3).
        accelerations: Their classical accelerations (m/s²), (n, 3).

    The protocol: :meth:`to_frame` one row per point (``point, x, y, vx, vy, v, ax, ay, a``); :meth:`as_dict` the
    joint coordinates, velocities and accelerations and each point's vectors; :meth:`plot` the mechanism beside its
    velocity and acceleration plans; ``str`` the table.
    """

    mechanism: Mechanism
    q: NDArray[np.float64]
    v: NDArray[np.float64]
    a: NDArray[np.float64]
    frames: list[str]
    positions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    accelerations: NDArray[np.float64]

    def to_frame(self) -> pd.DataFrame:
        """One row per point: ``point``, its position ``x, y`` (m), velocity ``vx, vy`` and magnitude ``v`` (m/s),
        acceleration ``ax, ay`` and magnitude ``a`` (m/s²), in the plane of the plans (world x, y)."""
        import pandas as pd

        p, v, a = self.positions, self.velocities, self.accelerations
        return pd.DataFrame({"point": self.frames, "x": p[:, 0], "y": p[:, 1],
                             "vx": v[:, 0], "vy": v[:, 1], "v": np.hypot(v[:, 0], v[:, 1]),
                             "ax": a[:, 0], "ay": a[:, 1], "a": np.hypot(a[:, 0], a[:, 1])})

    def as_dict(self) -> dict[str, Any]:
        """``mechanism``; ``coordinates``, ``velocities``, ``accelerations``: {joint: value} (m or rad, per s,
        per s²); ``points``: {name: {position (m), velocity (m/s), acceleration (m/s²)}}, world 3-vectors."""
        mech = self.mechanism
        joints = mech.joint_names
        return json_ready({
            "mechanism": mech.name,
            "coordinates": dict(zip(joints, mech.coordinates(self.q))),
            "velocities": dict(zip(joints, self.v)),
            "accelerations": dict(zip(joints, self.a)),
            "points": {name: {"position": self.positions[i], "velocity": self.velocities[i],
                              "acceleration": self.accelerations[i]} for i, name in enumerate(self.frames)},
        })

    def __str__(self) -> str:
        mech = self.mechanism
        at = ", ".join(f"{n} = {x:.6g}" for n, x in zip(mech.joint_names, mech.coordinates(self.q))
                       if n in mech.actuated)
        rates = ", ".join(f"{n} = {self.v[i]:.6g}" for i, n in enumerate(mech.joint_names) if n in mech.actuated)
        lines = [f"{mech.name}: velocity and acceleration plans at {at} (m, rad), input rates {rates} (m/s, rad/s)",
                 f"{'point':<10} {'x (m)':>10} {'y (m)':>10} {'vx (m/s)':>11} {'vy (m/s)':>11} {'|v| (m/s)':>11} "
                 f"{'ax (m/s²)':>11} {'ay (m/s²)':>11} {'|a| (m/s²)':>11}"]
        for row in self.to_frame().itertuples(index=False):
            lines.append(f"{row.point:<10} {row.x:10.4f} {row.y:10.4f} {row.vx:11.5g} {row.vy:11.5g} {row.v:11.5g} "
                         f"{row.ax:11.5g} {row.ay:11.5g} {row.a:11.5g}")
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Figure:
        """The mechanism (m) beside its velocity plan (m/s, pole p) and acceleration plan (m/s², pole π), the tips
        of the points of one body joined ([Egorov, fig. 4.10]). Given ``ax``, draws the velocity plan into it."""
        from ..report.figures import figure_axes, new_figure
        from .drawing import draw_mechanism, draw_plan, key_below

        mech = self.mechanism
        groups = [line.points for line in mech.sketch]
        velocity = dict(zip(self.frames, self.velocities))
        if ax is not None:
            draw_plan(ax, velocity, groups, pole="p", unit="m/s", quantity="v")
            ax.set_title("velocity plan", fontsize=10)
            return figure_axes(ax)[0]
        figure = new_figure(13.0, 4.5)
        ax_mech, ax_v, ax_a = figure.subplots(1, 3)
        if mech.sketch:
            draw_mechanism(mech, self.q, ax_mech, key=True)
        else:
            ax_mech.plot(self.positions[:, 0], self.positions[:, 1], "o", color="tab:blue", label="points")
            for name, xy in zip(self.frames, self.positions):
                ax_mech.annotate(name, xy[:2], textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax_mech.set(aspect="equal", xlabel="x (m)", ylabel="y (m)")
        ax_mech.set_title(f"{mech.name}: mechanism", fontsize=10)
        ax_mech.grid(True, alpha=0.3)
        draw_plan(ax_v, velocity, groups, pole="p", unit="m/s", quantity="v", legend=False)
        ax_v.set_title("velocity plan", fontsize=10)
        draw_plan(ax_a, dict(zip(self.frames, self.accelerations)), groups, pole="π", unit="m/s²", quantity="a",
                  legend=False)
        ax_a.set_title("acceleration plan", fontsize=10)
        key_below(figure, [ax_mech, ax_v, ax_a])
        return figure


def plans(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, frames: Sequence[str] | None = None) -> Plans:
    """The velocity and acceleration plans ([Egorov, 4.2, fig. 4.10]) of the points ``frames`` (frame names;
    default ``mech.points``) of ``mech`` at configuration ``q`` (nq,) moving with joint velocity ``v`` and joint
    acceleration ``a`` (nv,; m/s, rad/s and m/s², rad/s²), consistent with the closures (e.g. from
    :func:`~mechatron.kinematics.loops.joint_velocity` and :func:`~mechatron.kinematics.loops.joint_acceleration`).

    Each point's velocity is v = J q̇ ([Egorov, 4.47–4.48]) and its acceleration the classical a = J q̈ + J̇ q̇
    ([Egorov, 4.49–4.50]), world components.
    """
    q = mech.check_configuration(q)
    v, a = (np.asarray(x, dtype=float) for x in (v, a))
    if q.ndim != 1 or v.shape != (mech.nv,) or a.shape != (mech.nv,):
        raise InputError(f"plans take one configuration ({mech.nq} values) and one velocity and acceleration "
                         f"({mech.nv} values each), got shapes {q.shape}, {v.shape}, {a.shape}")
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(a))):
        raise InputError("v and a must be finite")
    frames = list(mech.points if frames is None else frames)
    if not frames:
        raise InputError(f"{mech.name} has no named points; give the frames of the plans")
    states = [point_state(mech, q, v, a, name) for name in frames]
    return Plans(mech, q.copy(), v.copy(), a.copy(), frames, *(np.array(s) for s in zip(*states)))

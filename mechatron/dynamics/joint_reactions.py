"""Reaction forces in the joints along a motion: the force and moment every joint transmits, and a closed loop's
pin forces (``mechatron dynamics … --reactions``).

At every sample one RNEA pass gives, for each joint of the tree, the spatial force the parent body transmits
through the joint to the child subtree (Pinocchio's ``data.f`` after ``rnea``, turned into world axes, about the
joint's origin: :func:`~mechatron.dynamics.tree.transmitted_wrenches`): the reaction in the pair, [Egorov, 5.1–5.2].
It balances everything the subtree carries: F = Σ_subtree m_i (a_ci − g) − Σ F_ext, M = Σ (r_ci × m_i (a_ci − g) +
ḣ_i) − Σ (r × F_ext + M_ext), moments about the joint origin. Its component along the joint's axis is the joint's
torque (or force); the rest is what the bearing carries. A closed loop's samples are solved for their states
first (:func:`~mechatron.dynamics.trajectory.closed_loop_states`), its multipliers λ from the constrained inverse
dynamics, and the closure forces join the RNEA as external forces (:func:`~mechatron.dynamics.constrained.
reactions`): each pin's λ is the force (N, world axes) that its point ``a`` receives.

All samples are computed at once in NumPy (the same Newton–Euler balance and multipliers,
:mod:`~mechatron.dynamics.batched_reactions`; benchmarks/reactions.py measures it against the state-by-state
passes); redundant closures, or joints the batched kinematics does not know, take the RNEA pass state by state.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..model.loads import Loads
from ..model.mechanism import Mechanism
from ..report.result import Result, json_ready
from .series import plot_lines, stacked_axes, text_table

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .motion import Trajectory

Array = NDArray[np.float64]
AXES = ("x", "y", "z")


@dataclass(eq=False)
class JointReactions(Result):
    """The reactions along a motion.

    Attributes:
        mechanism: its name. t: sample times (N,) (s).
        joints: the tree joints' names; ``wrenches`` (N, n_joints, 6): [F_x, F_y, F_z, M_x, M_y, M_z] each joint
            transmits from its parent body to its child subtree (N, N·m; world axes, moment about the joint's
            origin).
        pins: each closure's name and the force its point ``a`` receives (N, 2 or 3) (N, world axes); empty for a
            serial mechanism.
    """

    mechanism: str
    t: Array
    joints: list[str]
    wrenches: Array
    pins: dict[str, Array] = field(default_factory=dict)

    def summary(self) -> list[dict]:
        """Per joint: the largest |F| (N) and |M| (N·m) and the time (s) of each; per pin the largest |F| (N)."""
        rows = []
        for k, name in enumerate(self.joints):
            F, M = (np.linalg.norm(self.wrenches[:, k, part], axis=1) for part in (slice(0, 3), slice(3, 6)))
            rows.append({"joint": name, "peak_force_N": float(F.max()), "t_force_s": float(self.t[F.argmax()]),
                         "peak_moment_Nm": float(M.max()), "t_moment_s": float(self.t[M.argmax()])})
        for name, force in self.pins.items():
            F = np.linalg.norm(force, axis=1)
            rows.append({"joint": f"pin {name}", "peak_force_N": float(F.max()), "t_force_s": float(self.t[F.argmax()]),
                         "peak_moment_Nm": None, "t_moment_s": None})
        return rows

    def to_frame(self) -> pd.DataFrame:
        """One row per sample: t (s); for each joint ``<joint>_Fx`` … ``_Fz`` (N) and ``<joint>_Mx`` … ``_Mz``
        (N·m), world axes, about the joint's origin; for each pin ``pin_<name>_Fx`` … (N)."""
        import pandas as pd

        columns: dict[str, Array] = {"t": self.t}
        for k, name in enumerate(self.joints):
            for i, label in enumerate(f"{kind}{axis}" for kind in "FM" for axis in AXES):
                columns[f"{name}_{label}"] = self.wrenches[:, k, i]
        for name, force in self.pins.items():
            for i in range(force.shape[1]):
                columns[f"pin_{name}_F{AXES[i]}"] = force[:, i]
        return pd.DataFrame(columns)

    def as_dict(self) -> dict:
        """mechanism, samples, t (s), the :meth:`summary`, and per joint its ``force`` (N) and ``moment`` (N·m)
        at every sample (world axes), per pin its ``force`` (N)."""
        return json_ready({"mechanism": self.mechanism, "samples": len(self.t), "t": self.t, "axes": "world",
                           "summary": self.summary(),
                           "joints": {name: {"force_N": self.wrenches[:, k, :3], "moment_Nm": self.wrenches[:, k, 3:]}
                                      for k, name in enumerate(self.joints)},
                           "pins": {name: {"force_N": force} for name, force in self.pins.items()}})

    def plot(self, ax: Axes | None = None) -> Figure:
        """|F| of every joint against time (drawn into ``ax`` if given), then |M|."""
        figure, axes = stacked_axes(ax, 2)
        F = np.linalg.norm(self.wrenches[:, :, :3], axis=2)
        names = [*self.joints, *(f"pin {n}" for n in self.pins)]
        pins = [np.linalg.norm(f, axis=1)[:, None] for f in self.pins.values()]
        plot_lines(axes[0], self.t, np.hstack([F, *pins]), names, "t (s)", "reaction force |F| (N)",
                   f"{self.mechanism}: joint reactions")
        if len(axes) > 1:
            plot_lines(axes[1], self.t, np.linalg.norm(self.wrenches[:, :, 3:], axis=2), self.joints, "t (s)",
                       "reaction moment |M| (N·m)")
        return figure

    def __str__(self) -> str:
        head = (f"{self.mechanism}: joint reactions over {len(self.t)} sample(s) (force and moment each joint "
                "transmits to the bodies beyond it; world axes, moment about the joint's origin)")
        if len(self.t) == 1:
            rows = [{"joint": n, **{f"F{a} (N)": self.wrenches[0, k, i] for i, a in enumerate(AXES)},
                     **{f"M{a} (N·m)": self.wrenches[0, k, 3 + i] for i, a in enumerate(AXES)}}
                    for k, n in enumerate(self.joints)]
            rows += [{"joint": f"pin {n}", **{f"F{AXES[i]} (N)": f[0, i] for i in range(f.shape[1])}}
                     for n, f in self.pins.items()]
            return f"{head}\n{text_table(rows)}"
        rows = [{"joint": r["joint"], "peak |F| (N)": r["peak_force_N"], "at t (s)": r["t_force_s"],
                 "peak |M| (N·m)": r["peak_moment_Nm"], "|M| at t (s)": r["t_moment_s"]} for r in self.summary()]
        return f"{head}\n{text_table(rows)}"


def joint_reactions(mech: Mechanism, trajectory: Trajectory, loads: Loads = None) -> JointReactions:
    """The :class:`JointReactions` of ``mech`` along ``trajectory`` (of its joints; of a closed loop's actuated
    coordinates) under gravity and ``loads`` (the module docstring): all samples at once
    (:func:`~mechatron.dynamics.batched_reactions.reactions_at`), or state by state where the closures are redundant
    or the batched kinematics does not know a joint."""
    from .batched_reactions import reactions_at
    from .trajectory import closed_loop_states

    joints = list(mech.model.names[1:])
    t = np.asarray(trajectory.t, float)
    if mech.closures:
        Q, V, A = closed_loop_states(mech, trajectory)
    else:
        Q = np.atleast_2d(np.asarray(trajectory.q, dtype=float))
        if Q.shape[1] != mech.nq:
            Q = mech.configuration(np.atleast_2d(np.asarray(trajectory.coordinates, dtype=float)))
        V, A = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (trajectory.v, trajectory.a))
    batched = reactions_at(mech, Q, V, A, loads) if len(Q) else None
    wrenches, pins = batched if batched is not None else _state_by_state(mech, Q, V, A, loads)
    return JointReactions(mech.name, t, joints, wrenches.reshape(len(Q), len(joints), 6), pins)


def _state_by_state(mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads) -> tuple[Array, dict[str, Array]]:
    """(wrenches, pins): one constrained inverse dynamics (a closed loop) and one RNEA pass per state."""
    from .constrained import inverse, reactions
    from .tree import transmitted_wrenches

    if not mech.closures:
        return np.array([transmitted_wrenches(mech, q, v, a, loads) for q, v, a in zip(Q, V, A)]), {}
    states = [reactions(mech, q, v, a, inverse(mech, q, v, a, loads)[1], loads) for q, v, a in zip(Q, V, A)]
    wrenches = np.array([s.joints for s in states])
    return wrenches, {name: np.array([s.pins[name] for s in states]) for name in (states[0].pins if states else {})}

"""Loads per segment of a task: a payload picked up at one waypoint and put down at another.

A task file's ``payload_from`` and ``payload_until`` (waypoint numbers, 1-based; :mod:`mechatron.dynamics.task`)
say on which part of the motion the payload is carried. A waypoint of a cycle is a run of samples at rest (the
arrival, then its dwell); the payload is carried from the last sample at rest at waypoint ``payload_from`` (the
start of the move that lifts it) to the first sample at rest at waypoint ``payload_until`` (the end of the move that
puts it down), both included: it is not carried while the gripper closes or opens in those two dwells, and it is
carried in the dwells of the waypoints between them.

The inverse dynamics of each sample is that of the mechanism with the payload attached
(:func:`~mechatron.model.payload.with_payload`) where it is carried and of the mechanism without it elsewhere: the
samples are split in two sets, each computed in one batched call with its own mechanism
(:meth:`PayloadSchedule.per_sample`). The closed loops' positions are solved once along the whole task (the
payload changes no position), their forces per set.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from ..model.payload import with_payload

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PayloadSchedule:
    """A payload carried on part of a task.

    Attributes:
        mass: kg. frame: the frame (a closed loop's point) that carries it. com: its centre in that frame (m).
        inertia: 3×3 about its centre, the frame's axes (kg·m²), ``None``: a point mass.
        carried: (N,) booleans, True at the samples of the task where the payload is carried.
        label: the load case in words (``"carried from waypoint 1 to waypoint 2"``).
    """

    mass: float
    frame: str
    com: Array
    inertia: Array | None
    carried: NDArray[np.bool_]
    label: str = ""

    def on(self, mech: Mechanism) -> Mechanism:
        """``mech`` with the payload attached (:func:`~mechatron.model.payload.with_payload`)."""
        return with_payload(mech, self.mass, self.frame, com=self.com, inertia=self.inertia)

    def per_sample(self, mech: Mechanism, compute: Callable[..., Array], *rows: Array) -> Array:
        """(N, …): ``compute(mechanism, *rows)`` of the samples where the payload is carried with ``mech`` carrying
        it, of the others with ``mech`` as it is — one call for each set — put back in the samples' order, as
        (N, k) (each sample's result flattened). ``rows`` are (N, …) arrays (configurations, speeds,
        accelerations); ``compute`` returns one result per sample."""
        carried = np.asarray(self.carried, dtype=bool)
        if any(len(r) != len(carried) for r in rows):
            raise InputError(f"the payload's schedule has {len(carried)} samples, the motion "
                             f"{', '.join(str(len(r)) for r in rows)}")
        out: Array | None = None
        for mask, m in ((carried, self.on(mech) if carried.any() else None), (~carried, mech)):
            if not mask.any():
                continue
            part = np.asarray(compute(m, *(r[mask] for r in rows)), dtype=float).reshape(int(mask.sum()), -1)
            if out is None:
                out = np.empty((len(carried), *part.shape[1:]))
            out[mask] = part
        assert out is not None
        return out

    def thinned(self, step: int) -> PayloadSchedule:
        """The schedule of every ``step``-th sample (a trajectory thinned as ``Q[::step]``)."""
        return PayloadSchedule(self.mass, self.frame, self.com, self.inertia, self.carried[::step], self.label)

    def inverse_dynamics(self, mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads = None) -> Array:
        """τ (N, nv; N·m, N) = M q̈ + h − Σ Jᵀ F of a serial mechanism (RNEA,
        :func:`~mechatron.dynamics.tree.inverse_dynamics`), with the payload where it is carried."""
        from .tree import inverse_dynamics

        return self.per_sample(mech, lambda m, q, v, a: inverse_dynamics(m, q, v, a, loads), *(
            np.atleast_2d(np.asarray(x, dtype=float)) for x in (Q, V, A)))


def rest_runs(trajectory) -> list[tuple[int, int]]:
    """(first, last) sample of every run of samples at rest (every speed zero), in order: the waypoints of a
    cycle (:func:`~mechatron.dynamics.motion.cycle`: a move ends and starts at rest, a dwell is a run at rest)."""
    still = np.all(np.atleast_2d(trajectory.v) == 0, axis=1)
    runs, start = [], None
    for i, s in enumerate(np.append(still, False)):
        if s and start is None:
            start = i
        elif not s and start is not None:
            runs.append((start, i - 1))
            start = None
    return runs


def carried_between(trajectory, first: int, last: int, waypoints: int) -> NDArray[np.bool_]:
    """(N,) True from the last sample at rest at waypoint ``first`` to the first at rest at waypoint ``last``
    (1-based, ``first`` < ``last`` ≤ ``waypoints``, the number of waypoints the cycle was made of), both
    included (the module docstring)."""
    if not 1 <= first < last <= waypoints:
        raise InputError(f"the payload is picked at waypoint {first} and released at waypoint {last}: give "
                         f"1 <= payload_from < payload_until <= {waypoints} (the number of waypoints)")
    runs = rest_runs(trajectory)
    if len(runs) != waypoints:
        raise InputError(f"the motion rests {len(runs)} times, not once at each of its {waypoints} waypoints "
                         "(two equal waypoints in a row?): cannot tell where the payload is picked and released")
    carried = np.zeros(len(trajectory.t), dtype=bool)
    carried[runs[first - 1][1]:runs[last - 1][0] + 1] = True
    return carried


def closed_loop_duty(mech: Mechanism, kinematics: Mechanism, trajectory, loads: Loads,
                     payload: PayloadSchedule, inertia_samples: int = 50):
    """:func:`~mechatron.dynamics.trajectory.actuator_duty` with the payload where it is carried: the loops of
    ``kinematics`` solved once along the whole trajectory, the driving and holding forces and the reduced
    inertias Sᵀ M S of each set of samples with its own mechanism (:meth:`PayloadSchedule.per_sample`)."""
    from .trajectory import ActuatorDuty, _forces, _velocity_matrices, closed_loop_states
    from .tree import mass_matrix

    Q, V, A = closed_loop_states(kinematics, trajectory)
    forces = payload.per_sample(mech, lambda m, q, v, a: _forces(m, kinematics, q, v, a, (loads,))[0], Q, V, A)
    step = max(1, len(Q) // inertia_samples)
    thin = payload.thinned(step)

    def reduced(m: Mechanism, q: Array) -> Array:
        S = _velocity_matrices(kinematics, q)
        M = np.atleast_3d(mass_matrix(m, q)).reshape(len(q), m.nv, -1)
        return np.einsum("kia,kij,kja->ka", S, M, S)

    inertia = thin.per_sample(mech, reduced, Q[::step])

    def holding() -> Array:
        return payload.per_sample(mech, lambda m, q, v, a: _forces(m, kinematics, q, v, a, (loads,),
                                                                   at_rest=(True,))[0], Q, V, A)

    return ActuatorDuty(Q, forces, np.max(inertia, axis=0, initial=0.0), holding)


def read_span(reader) -> tuple[int | None, int | None]:
    """The task file's ``payload_from`` and ``payload_until`` (waypoint numbers, 1-based; ``None`` where left out;
    a :class:`~mechatron.io.schema.FieldReader`)."""
    start, end = (reader.whole(key, None, minimum=1) if reader.has(key) else None
                  for key in ("payload_from", "payload_until"))
    return start, end


def task_schedule(reader, span: tuple[int | None, int | None], trajectory, waypoints: int | None, mass: float,
                  frame: str, com: Array, inertia: Array | None) -> PayloadSchedule | None:
    """The :class:`PayloadSchedule` of a task file whose ``span`` (:func:`read_span`) names a waypoint, ``None``
    when it names none (the payload is carried along the whole task). Picked at waypoint ``payload_from`` (default
    1), released at ``payload_until`` (default the last); ``waypoints``: how many the motion was made of (``None``
    for a trajectory CSV, which has none). A problem names the field."""
    first, last = span
    if first is None and last is None:
        return None
    key = "payload_from" if first is not None else "payload_until"
    if waypoints is None:
        raise reader.error(key, "needs waypoints (a trajectory file has none)")
    if not mass > 0:
        raise reader.error(key, "needs a payload mass > 0")
    first, last = first or 1, last or waypoints
    try:
        carried = carried_between(trajectory, first, last, waypoints)
    except InputError as exc:
        raise reader.error(key, exc.message) from None
    return PayloadSchedule(mass, frame, np.asarray(com, dtype=float), inertia, carried,
                           f"carried from waypoint {first} to waypoint {last}")

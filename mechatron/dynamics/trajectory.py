"""Closed-loop mechanisms along a motion of their inputs: the full joint states and the actuator forces.

The trajectory gives the actuated coordinates (cylinder lengths, crank angles) with their rates and accelerations;
position, velocity and acceleration analysis of the loops (:func:`mechatron.kinematics.sweeps.sweep`) give every
joint's state, and the constrained inverse dynamics (:func:`mechatron.dynamics.constrained.inverse`) the forces.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from .constrained import inverse

if TYPE_CHECKING:  # pragma: no cover
    from .motion import Trajectory

Array = NDArray[np.float64]


def closed_loop_states(mech: Mechanism, trajectory: Trajectory) -> tuple[Array, Array, Array]:
    """(Q, V, A): the full joint states (N, nq/nv; rad, m and their rates) of a closed-loop mechanism along a
    trajectory of its actuated coordinates (assembly, velocity and acceleration analysis of the loops); an error
    if the motion leaves the reachable range."""
    from ..kinematics.sweeps import sweep  # pandas: only when a trajectory is analysed

    assert trajectory.coordinates is not None  # set by __post_init__
    inputs = {name: trajectory.coordinates[:, i] for i, name in enumerate(mech.actuated)}
    rates = {name: trajectory.v[:, i] for i, name in enumerate(mech.actuated)}
    accels = {name: trajectory.a[:, i] for i, name in enumerate(mech.actuated)}
    result = sweep(mech, inputs, rates=rates, accelerations=accels, frames=[], measures=[], stop_on_failure=True)
    if len(result.failures):
        raise InputError(f"{mech.name}: the trajectory leaves the reachable range: "
                         f"{result.failures['reason'].iloc[0]}")
    return result.q, result.v, result.a


def actuator_forces(mech: Mechanism, trajectory: Trajectory, loads: Loads = None) -> tuple[Array, Array]:
    """(Q, F): the joint positions (N, nq) of a closed-loop mechanism along a trajectory of its actuated
    coordinates and the actuator forces (N, n_actuated; N for a cylinder, N·m for a crank) that drive it under
    gravity and ``loads`` (constrained inverse dynamics, :func:`~mechatron.dynamics.constrained.inverse`)."""
    Q, V, A = closed_loop_states(mech, trajectory)
    return Q, _forces(mech, mech, Q, V, A, (loads,))[0]


def holding_forces(mech: Mechanism, Q: ArrayLike, loads: Loads = None) -> Array:
    """Actuator forces (N, n_actuated; N or N·m) that hold a closed-loop mechanism at rest, under gravity and
    ``loads``, in each assembled position of Q (N, nq)."""
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    return _forces(mech, mech, Q, np.zeros((len(Q), mech.nv)), np.zeros((len(Q), mech.nv)), (loads,))[0]


@dataclass(frozen=True)
class ActuatorDuty:
    """What the actuators of a closed-loop mechanism carry along a trajectory of its actuated coordinates (SI:
    N for a cylinder, N·m for a crank; kg or kg·m²).

    Attributes:
        q: the joint positions (N, nq).
        forces: the actuator forces that drive the motion (N, n_actuated).
        inertia: the largest reduced inertia of each actuated coordinate with the other inputs held, the diagonal
            of Sᵀ M S over about ``inertia_samples`` positions (the reduced moment of inertia [Egorov, 6.8]).
        holding: the forces that hold each position at rest (gravity and the loads alone) (N, n_actuated),
            computed when first read.
    """

    q: Array
    forces: Array
    inertia: Array
    at_rest: Callable[[], Array] = field(repr=False)

    @functools.cached_property
    def holding(self) -> Array:
        return self.at_rest()


def actuator_duty(mech: Mechanism, trajectory: Trajectory, loads: Loads = None, *,
                  kinematics: Mechanism | None = None, inertia_samples: int = 50) -> ActuatorDuty:
    """The :class:`ActuatorDuty` of a closed-loop mechanism along ``trajectory``: its loops solved once (position,
    velocity and acceleration analysis), the driving forces (and, when first asked for, the holding forces, from
    the same states), and the reduced inertias at every (N // ``inertia_samples``)-th position.

    ``kinematics``: the mechanism whose loops give the states and the Jacobians, when ``mech`` only changes the
    masses of the same linkage (its drives' masses mounted on the bodies, the armature removed): its compiled loop
    kernels are built once for every such variant (default ``mech``)."""
    from .tree import mass_matrix

    kinematics = kinematics or mech
    Q, V, A = closed_loop_states(kinematics, trajectory)
    forces = _forces(mech, kinematics, Q, V, A, (loads,))[0]
    Qs = Q[:: max(1, len(Q) // inertia_samples)]
    S = _velocity_matrices(kinematics, Qs)
    inertia = np.einsum("kia,kij,kja->ka", S, np.atleast_3d(mass_matrix(mech, Qs)).reshape(len(Qs), mech.nv, -1), S)
    return ActuatorDuty(Q, forces, np.max(inertia, axis=0, initial=0.0),
                        lambda: _forces(mech, kinematics, Q, V, A, (loads,), at_rest=(True,))[0])


def _velocity_matrices(kinematics: Mechanism, Q: Array) -> Array:
    """S (N, nv, n_actuated) with q̇ = S q̇_a at every position: S_a = I, S_d = −J_d⁻¹ J_a, all at once where the
    closures are not redundant (else :meth:`~mechatron.kinematics.loops.LoopSolver.velocity_matrix` each)."""
    from ..kinematics import batch
    from ..kinematics.loops import loop_solver

    solver = loop_solver(kinematics)
    frames = _batched_frames(solver)
    if frames is None:
        return np.array([solver.velocity_matrix(q) for q in Q]).reshape(len(Q), kinematics.nv, len(solver.act))
    S = np.zeros((len(Q), kinematics.nv, len(solver.act)))
    S[:, solver.act, np.arange(len(solver.act))] = 1.0
    if len(solver.dep):
        _, J = solver.system.stack(frames.placements(Q))
        S[:, solver.dep] = -batch.solve(J[:, :, solver.dep], J[:, :, solver.act])
    return S


def _batched_frames(solver):
    """The closures' batched frame placements, or ``None`` where the closures are redundant or the batched
    kinematics does not know a joint."""
    system = solver.system
    try:
        return system.batched() if system.nrows == len(solver.dep) else None
    except NotImplementedError:
        return None


def _forces(mech: Mechanism, kinematics: Mechanism, Q: Array, V: Array, A: Array, loads: tuple[Loads, ...],
            at_rest: tuple[bool, ...] = (False,)) -> list[Array]:
    """The actuator forces (N, n_actuated) of the constrained inverse dynamics at every state, for each of
    ``loads`` (at rest — zero velocities and accelerations — where ``at_rest`` says so), all at once where the
    closures are not redundant: with need = M q̈ + h − Q (batched RNEA, the loads' generalized forces Q by the
    batched kinematics, :func:`~mechatron.dynamics.tree.load_forces`, once for each set of loads) and the closure
    Jacobian J split into its actuated and dependent columns, [B Jᵀ][τ_a; λ] = need reads J_dᵀ λ = need_d and
    τ_a = need_a − J_aᵀ λ, that is τ_a = Sᵀ need with the velocity maps S = [I; S_d], S_d = −J_d⁻¹ J_a (virtual
    work; the sweep that gave the states has refused the singular ones, where J_d is not invertible). S_d comes
    from the loops' compiled kernel where the sweep had one, else from the batched closure Jacobians. Redundant
    closures, or joints the batched kinematics does not know: :func:`~mechatron.dynamics.constrained.inverse`
    state by state. The loops of ``kinematics`` (the same linkage), the masses of ``mech``."""
    from ..kinematics import batch
    from ..kinematics.loops import loop_solver
    from ..kinematics.sweeps import kept_sweep_kernel
    from ..model.loads import as_loads
    from .tree import inverse_dynamics, load_forces

    solver = loop_solver(kinematics)
    kernel = kept_sweep_kernel(solver)  # its closures determine the dependent coordinates: S_d from its maps
    frames = _batched_frames(solver) if kernel is None else None
    rest = np.zeros_like(V)
    states = [(rest, rest) if still else (V, A) for still in at_rest]
    if (kernel is None and frames is None) or not len(Q):
        return [np.array([[f[n] for n in mech.actuated] for f in
                          (inverse(mech, q, v, a, load)[0] for q, v, a in zip(Q, Vs, As))]).reshape(len(Q), -1)
                for load, (Vs, As) in zip(loads, states)]
    applied: dict[tuple, Array] = {}

    def need(load: Loads, Vs: Array, As: Array) -> Array:
        """M q̈ + h − Q (N, nv) of one case, the loads' Q computed once for equal loads."""
        load = as_loads(load)
        key = tuple((x.frame, *x.force, *x.moment) for x in load)
        try:
            if key not in applied:
                applied[key] = load_forces(mech, Q, load)
        except NotImplementedError:
            return np.atleast_2d(inverse_dynamics(mech, Q, Vs, As, load))
        return np.atleast_2d(inverse_dynamics(mech, Q, Vs, As)) - applied[key]

    needs = np.stack([need(load, Vs, As) for load, (Vs, As) in zip(loads, states)], axis=-1)  # (N, nv, cases)
    act, dep = solver.act, solver.dep
    out = np.empty((len(Q), len(act), len(loads)))
    for part in batch.chunks(len(Q)):
        if kernel is not None:
            maps = kernel.maps(Q[part])  # S_d (n, n_dep, n_act)
        else:
            assert frames is not None  # no kernel: the batched frames
            _, J = solver.system.stack(frames.placements(Q[part]))
            maps = -batch.solve(J[:, :, dep], J[:, :, act])
        out[part] = needs[part][:, act] + np.swapaxes(maps, 1, 2) @ needs[part][:, dep]
    return [out[..., k] for k in range(len(loads))]

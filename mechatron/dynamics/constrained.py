r"""Dynamics of closed-loop mechanisms: the tree's equations of motion with the closures' Lagrange multipliers.

With M(q) and h(q, q̇) = C q̇ + g of the tree (Pinocchio), the closure Jacobian J and drift J̇ q̇
(:mod:`mechatron.closures`), applied joint forces τ (the actuators: cylinder forces on their rod coordinates, crank
torques) and external loads Q = Σ J_pᵀ F_p:

.. math::

    M \ddot q + h = \tau + Q + J^T \lambda, \qquad J \ddot q = -\dot J \dot q

- :func:`forward` solves this KKT system for q̈ and λ (least squares, so redundant closure rows are allowed);
- :func:`inverse` solves for the actuated forces and λ along a known motion: [B  Jᵀ][τ_a; λ] = M q̈ + h − Q;
- :func:`reactions` turns λ into pin forces and, with an RNEA pass carrying them as external forces, the force and
  moment in every tree joint (textbook chapter 5: the reactions in the kinematic pairs);
- :func:`simulate` integrates the motion (classical Runge–Kutta on the configuration manifold, fixed step,
  :mod:`mechatron.dynamics.integrate`) and projects positions and velocities back onto the closures after every
  step, so the constraint drift stays at rounding level.

A pin closure's multiplier is the force (N) its point ``a`` receives from point ``b`` (and −λ the other way).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import InputError
from ..kinematics.loops import loop_solver
from ..model.closures import Pin
from ..model.loads import Load, Loads, as_loads
from ..model.mechanism import Mechanism
from .integrate import rk4_step, time_steps
from .tree import generalized_forces, joint_space_inertia, transmitted_wrenches

#: (t, q, q̇) → {joint coordinate: force (N) or torque (N·m)}: the actuators' law along a simulation.
Actuation = Callable[[float, np.ndarray, np.ndarray], Mapping[str, float]]
#: (t, q, q̇) → loads: the external loads along a simulation.
LoadsAt = Callable[[float, np.ndarray, np.ndarray], Sequence[Load]]


def _closure_terms(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    system = loop_solver(mech).system
    _, J = system.evaluate(q)
    return J, system.drift(q, v)


def forward(mech: Mechanism, q, v, forces: Mapping[str, float] | None = None,
            loads: Loads = None) -> tuple[np.ndarray, np.ndarray]:
    """(q̈, λ) of a closed-loop mechanism under actuator forces (by joint coordinate: N, N·m) and external loads:
    the KKT system [M −Jᵀ; J 0][q̈; λ] = [τ + Q − h; −J̇ q̇]."""
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    model, data = mech.model, mech.data
    M = joint_space_inertia(model, data, q)
    h = pin.nonLinearEffects(model, data, q, v)
    rhs = generalized_forces(mech, q, forces, loads) - h
    if not mech.closures:
        return np.linalg.solve(M, rhs), np.zeros(0)
    J, drift = _closure_terms(mech, q, v)
    m, n = J.shape[0], mech.nv
    kkt = np.block([[M, -J.T], [J, np.zeros((m, m))]])
    solution = np.linalg.lstsq(kkt, np.concatenate([rhs, -drift]), rcond=None)[0]
    return solution[:n], solution[n:]


def inverse(mech: Mechanism, q, v, a, loads: Loads = None) -> tuple[dict[str, float], np.ndarray]:
    """Actuator forces (by actuated coordinate: N for a cylinder, N·m for a crank) and closure multipliers λ that
    produce the motion (q, q̇, q̈), which must satisfy the closures."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    model, data = mech.model, mech.data
    need = pin.rnea(model, data, q, v, a) - generalized_forces(mech, q, None, loads)  # M q̈ + h − Q
    solver = loop_solver(mech)
    B = solver.selection
    J = _closure_terms(mech, q, v)[0] if mech.closures else np.zeros((0, mech.nv))
    system = np.hstack([B, J.T])
    solution, _, rank, _ = np.linalg.lstsq(system, need, rcond=None)
    if rank < len(mech.actuated) + np.linalg.matrix_rank(J) if J.size else rank < len(mech.actuated):
        raise InputError(f"{mech.name}: the actuated coordinates cannot hold this motion (singular position)")
    forces = {name: float(solution[k]) for k, name in enumerate(mech.actuated)}
    return forces, solution[len(mech.actuated):]


@dataclass(frozen=True)
class Reactions:
    """Reactions at one state: ``pins`` maps each pin closure to the force (N, world xy or xyz) that its point
    ``a`` receives; ``joints`` is (njoints − 1, 6): force and moment (world axes, about the joint origin) that each
    tree joint transmits from the parent body to the child subtree."""

    pins: dict[str, np.ndarray]
    joints: np.ndarray


def reactions(mech: Mechanism, q, v, a, lam, loads: Loads = None) -> Reactions:
    """Pin forces from the multipliers and every tree joint's wrench (an RNEA pass with the closure forces as
    external forces)."""
    q, v, a, lam = (np.asarray(x, dtype=float) for x in (q, v, a, lam))
    system = loop_solver(mech).system
    pins: dict[str, np.ndarray] = {}
    applied = list(as_loads(loads))
    row = 0
    for closure in system.closures:
        rows = lam[row:row + closure.nrows]
        row += closure.nrows
        if isinstance(closure, Pin):
            force = np.zeros(3)
            force[:closure.nrows] = rows
            pins[closure.name] = rows.copy()
            applied += [Load(closure.a, force), Load(closure.b, -force)]
        else:
            # other closures: their generalized force Jᵀλ acts through the frames they use
            pins[closure.name] = rows.copy()
    return Reactions(pins, transmitted_wrenches(mech, q, v, a, applied))


# ------------------------------------------------------------------------------------------------ simulation
@dataclass
class Simulation:
    """A simulated motion: t (N,), q (N, nq), v, a (N, nv), multipliers (N, m), mechanical energy (N,) (J),
    work (N,) done by the actuators and loads since the start (J) and the closure residual (N,)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    multipliers: np.ndarray
    energy: np.ndarray
    work: np.ndarray
    residual: np.ndarray


def project(mech: Mechanism, q: np.ndarray, v: np.ndarray, iterations: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """The nearest q satisfying the closures (minimum-norm Newton steps on all coordinates) and the q̇ with
    J q̇ = 0 nearest to v."""
    if not mech.closures:
        return q, v
    system = loop_solver(mech).system
    q = q.copy()
    for _ in range(iterations):
        phi, J = system.evaluate(q)
        if np.abs(phi).max() < 1e-14:
            break
        q -= np.linalg.lstsq(J, phi, rcond=None)[0]
    _, J = system.evaluate(q)
    v = v - np.linalg.lstsq(J, J @ v, rcond=None)[0]
    return q, v


def simulate(mech: Mechanism, q0, v0, duration: float, dt: float = 1e-3, *,
             actuation: Actuation | None = None, loads_at: LoadsAt | None = None,
             stop: Callable[[float, np.ndarray, np.ndarray], bool] | None = None) -> Simulation:
    """Integrate the motion from (q0, v0) for ``duration`` seconds (s): fixed-step RK4 on the configuration manifold
    (:func:`~mechatron.dynamics.integrate.rk4_step`), then projection onto the closures.

    Args:
        actuation: (t, q, v) → {joint coordinate: force (N) or torque (N·m)}.
        loads_at: (t, q, v) → external loads [:class:`~mechatron.model.loads.Load`, …].
        stop: (t, q, v) → True to end the simulation early (e.g. a jaw closed).
    """
    if not (duration > 0 and dt > 0 and np.isfinite(duration) and np.isfinite(dt)):
        raise InputError("the duration and the time step of a simulation must be finite and > 0")
    q, v = project(mech, np.asarray(q0, dtype=float), np.asarray(v0, dtype=float))
    model = mech.model

    def dynamics(t: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        forces = actuation(t, q, v) if actuation else None
        external = loads_at(t, q, v) if loads_at else None
        a, lam = forward(mech, q, v, forces, external)
        power = float(generalized_forces(mech, q, forces, external) @ v)
        return a, power, lam

    def retraction(q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        return pin.integrate(model, q, dq)

    steps = time_steps(duration, dt)
    t_out, q_out, v_out, a_out, lam_out, work_out = [], [], [], [], [], []
    work, t = 0.0, 0.0
    for k in range(steps + 1):
        first = dynamics(t, q, v)
        t_out.append(t), q_out.append(q), v_out.append(v), a_out.append(first[0]), lam_out.append(first[2])
        work_out.append(work)
        if k == steps or (stop is not None and stop(t, q, v)):
            break
        q, v, step_work = rk4_step(dynamics, t, q, v, dt, first, retraction)
        work += step_work
        q, v = project(mech, q, v)
        t += dt
    Q, V = np.array(q_out), np.array(v_out)
    system = loop_solver(mech).system
    residual = np.array([np.abs(system.evaluate(x)[0]).max(initial=0.0) for x in Q])
    energy = np.array([pin.computeMechanicalEnergy(mech.model, mech.data, x, y) for x, y in zip(Q, V)])
    return Simulation(np.array(t_out), Q, V, np.array(a_out), np.array(lam_out), energy, np.array(work_out),
                      residual)

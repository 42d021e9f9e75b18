r"""Dynamics of closed-loop mechanisms: the tree's equations of motion with the closures' Lagrange multipliers.

With M(q) and h(q, q̇) = C q̇ + g of the tree (Pinocchio), the closure Jacobian J and drift J̇ q̇
(:mod:`mechatron.closures`), applied joint forces τ (the actuators: cylinder forces on their rod coordinates, crank
torques) and external loads Q = Σ J_pᵀ F_p:

.. math::

    M \ddot q + h = \tau + Q + J^T \lambda, \qquad J \ddot q = -\dot J \dot q

- :func:`forward` solves this KKT system for q̈ and λ (least squares, so redundant closure rows are allowed);
- :func:`inverse` solves for the actuated forces and λ along a known motion: [B  Jᵀ][τ_a; λ] = M q̈ + h − Q;
- :func:`reactions` turns λ into pin forces and, with an RNEA pass carrying them as external forces, the force and
  moment in every tree joint (the reactions in the kinematic pairs of [Egorov, 5.1–5.2]);
- :func:`simulate` integrates the motion (classical Runge–Kutta on the configuration manifold, fixed step,
  :mod:`mechatron.dynamics.integrate`) and projects positions and velocities back onto the closures after every
  step, so the constraint drift stays at rounding level.

A pin closure's multiplier is the force (N) its point ``a`` receives from point ``b`` (and −λ the other way).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.values import number
from ..kinematics.loops import loop_solver
from ..model.loads import Loads, as_loads
from ..model.mechanism import Mechanism
from ..report.result import Result
from .integrate import rk4_step, time_steps
from .motion import coordinate_names
from .series import coordinate_columns, plot_lines, stacked_axes, text_table, unit_label
from .tree import generalized_forces, joint_space_inertia, transmitted_wrenches

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

Array = NDArray[np.float64]
#: (t, q, q̇) → {joint coordinate: force (N) or torque (N·m)}: the actuators' law along a simulation.
Actuation = Callable[[float, Array, Array], Mapping[str, float]]
#: (t, q, q̇) → loads: the external loads along a simulation (:class:`~mechatron.model.Load` s or tuples).
LoadsAt = Callable[[float, Array, Array], Loads]


def _closure_terms(mech: Mechanism, q: Array, v: Array) -> tuple[Array, Array]:
    system = loop_solver(mech).system
    _, J = system.evaluate(q)
    return J, system.drift(q, v)


def forward(mech: Mechanism, q: ArrayLike, v: ArrayLike, forces: Mapping[str, float] | None = None,
            loads: Loads = None) -> tuple[Array, Array]:
    """(q̈, λ) of a closed-loop mechanism at (q, q̇) (rad, m; rad/s, m/s) under actuator forces (by joint
    coordinate: N, N·m), gravity and external ``loads``: the KKT system [M −Jᵀ; J 0][q̈; λ] = [τ + Q − h; −J̇ q̇]
    of the module docstring (q̈ in rad/s², m/s²; λ in N per pin row). Without closures, q̈ = M⁻¹(τ + Q − h)."""
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    return _accelerations(mech, q, v, generalized_forces(mech, q, forces, loads))


def _accelerations(mech: Mechanism, q: Array, v: Array, applied: Array) -> tuple[Array, Array]:
    """(q̈, λ) for the applied generalized forces τ + Q (nv,): the KKT system of :func:`forward`."""
    model, data = mech.model, mech.data
    M = joint_space_inertia(model, data, q)
    rhs = applied - pin.nonLinearEffects(model, data, q, v)
    if not mech.closures:
        return np.linalg.solve(M, rhs), np.zeros(0)
    J, drift = _closure_terms(mech, q, v)
    m, n = J.shape[0], mech.nv
    kkt = np.zeros((n + m, n + m))
    kkt[:n, :n], kkt[:n, n:], kkt[n:, :n] = M, -J.T, J
    solution = _least_squares(mech, kkt, np.concatenate([rhs, -drift]))
    return solution[:n], solution[n:]


def _least_squares(mech: Mechanism, A: Array, b: Array) -> Array:
    """The minimum-norm least-squares solution of A x = b. With independent closure equations (no redundant rows,
    decided once per mechanism) the square systems of the closures are regular and solved directly, which gives the
    same x; else, or at a singular position, by SVD (``lstsq``)."""
    if A.shape[0] == A.shape[1] and _independent_closures(mech):
        try:
            return np.asarray(np.linalg.solve(A, b), dtype=float)
        except np.linalg.LinAlgError:
            pass
    return np.asarray(np.linalg.lstsq(A, b, rcond=None)[0], dtype=float)


def _min_norm(mech: Mechanism, J: Array, b: Array) -> Array:
    """J⁺ b, the smallest x with J x = b for a closure Jacobian J (m, nv): Jᵀ (J Jᵀ)⁻¹ b when the rows are
    independent, else by SVD."""
    if _independent_closures(mech):
        try:
            return J.T @ np.asarray(np.linalg.solve(J @ J.T, b), dtype=float)
        except np.linalg.LinAlgError:
            pass
    return np.asarray(np.linalg.lstsq(J, b, rcond=None)[0], dtype=float)


def _independent_closures(mech: Mechanism) -> bool:
    """Whether the closure equations of ``mech`` are independent (rank = rows at the reference configuration)."""
    return mech.cached("independent_closures", lambda: mech.redundant_closure_equations() == 0)


def inverse(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike,
            loads: Loads = None) -> tuple[dict[str, float], Array]:
    """Actuator forces (by actuated coordinate: N for a cylinder, N·m for a crank) and closure multipliers λ (N)
    that produce the motion (q, q̇, q̈) under gravity and ``loads``: [B  Jᵀ][τ_a; λ] = M q̈ + h − Q (module
    docstring). The motion must satisfy the closures."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    model, data = mech.model, mech.data
    need = pin.rnea(model, data, q, v, a) - generalized_forces(mech, q, None, loads)  # M q̈ + h − Q
    if mech.closures:
        B, J = loop_solver(mech).selection, _closure_terms(mech, q, v)[0]
    else:  # a serial arm: the actuated joints' own coordinates
        B, J = np.eye(mech.nv)[:, [mech.model.joints[mech.joint_id(n)].idx_v for n in mech.actuated]], \
            np.zeros((0, mech.nv))
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


def reactions(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, lam: ArrayLike,
              loads: Loads = None) -> Reactions:
    """Closure forces from the multipliers λ and every tree joint's wrench (N, N·m): an RNEA pass with the closure
    forces and ``loads`` as external forces gives the reactions in the pairs, [Egorov, 5.1–5.2].

    A closure's generalized force Jᵀλ acts on the bodies it joins as the forces of
    :meth:`~mechatron.model.closures.Closure.loads` (a pin's λ and −λ at the common point, a curve's normal
    reaction, a slider's normal force and its moment on the line's body).
    """
    q, v, a, lam = (np.asarray(x, dtype=float) for x in (q, v, a, lam))
    pins: dict[str, np.ndarray] = {}
    applied = list(as_loads(loads))
    row = 0
    system = loop_solver(mech).system if mech.closures else None
    if system is not None:
        system.evaluate(q)  # the closures' frames at q
        for closure in system.closures:
            rows = lam[row:row + closure.nrows]
            row += closure.nrows
            pins[closure.name] = rows.copy()
            applied += closure.loads(system.states, rows)
    return Reactions(pins, transmitted_wrenches(mech, q, v, a, applied))


# ------------------------------------------------------------------------------------------------ simulation
@dataclass(eq=False)
class Simulation(Result):
    """A simulated motion.

    Attributes:
        t: Times (N,) (s).
        q: Configurations (N, nq) (Pinocchio's q).
        v, a: Joint velocities and accelerations (N, nv) (rad/s, m/s; rad/s², m/s²).
        multipliers: Closure multipliers λ (N, m) (N per pin row).
        energy: Mechanical energy T + V (N,) (J).
        work: Work (N,) done by the actuators and external loads since the start (J); energy − energy[0] equals it
            up to the integration error.
        residual: Largest closure residual |Φ(q)| (N,) (m).
        mechanism: Name of the mechanism.
        names: One name per joint coordinate.
        coordinates: Joint coordinates (N, nv) (rad, m; q ⊖ neutral, continuous joints' angles in (−π, π]).
        angular: Which coordinates are angles.
    """

    t: Array
    q: Array
    v: Array
    a: Array
    multipliers: Array
    energy: Array
    work: Array
    residual: Array
    mechanism: str = ""
    names: list[str] = field(default_factory=list)
    coordinates: Array | None = None
    angular: list[bool] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.coordinates is None:
            self.coordinates = self.q
        if not self.names:
            self.names = [f"q{i + 1}" for i in range(self.coordinates.shape[1])]

    @property
    def duration(self) -> float:
        """Simulated time (s)."""
        return float(self.t[-1] - self.t[0])

    def to_frame(self) -> pd.DataFrame:
        """Columns t (s), ``<joint>``, ``qd_<joint>``, ``qdd_<joint>`` (rad, m and their rates), ``energy`` (J),
        ``work`` (J), ``residual`` (m) and ``lambda_<k>`` (N), one row per sample."""
        import pandas as pd

        assert self.coordinates is not None  # set by __post_init__
        columns = coordinate_columns(self.t, self.names, self.coordinates, self.v, self.a)
        columns.update(energy=self.energy, work=self.work, residual=self.residual)
        multipliers = np.asarray(self.multipliers, dtype=float).reshape(len(self.t), -1)
        for k in range(multipliers.shape[1]):
            columns[f"lambda_{k + 1}"] = multipliers[:, k]
        return pd.DataFrame(columns)

    def _rows(self) -> list[dict]:
        assert self.coordinates is not None  # set by __post_init__
        return [{"coordinate": name, "start": float(self.coordinates[0, i]), "end": float(self.coordinates[-1, i]),
                 "speed_end": float(self.v[-1, i]), "peak_speed": float(np.abs(self.v[:, i]).max())}
                for i, name in enumerate(self.names)]

    def as_dict(self) -> dict:
        """mechanism, duration (s), samples, energy at the start and end (J), the work of actuators and loads (J),
        the largest |E − E₀ − W| (J) and closure residual (m), and per coordinate its start, end and speeds."""
        balance = self.energy - self.energy[0] - self.work
        return {"mechanism": self.mechanism, "duration": self.duration, "samples": len(self.t),
                "energy_start": float(self.energy[0]), "energy_end": float(self.energy[-1]),
                "work": float(self.work[-1]), "energy_balance_error": float(np.abs(balance).max()),
                "max_residual": float(np.max(self.residual, initial=0.0)), "coordinates": self._rows()}

    def plot(self, ax: Axes | None = None) -> Figure:
        """Joint coordinates against time (drawn into ``ax`` if given), then speeds, then the energy change
        E − E₀ beside the work W of the actuators and loads."""
        assert self.coordinates is not None  # set by __post_init__
        figure, axes = stacked_axes(ax, 3)
        plot_lines(axes[0], self.t, self.coordinates, self.names, "t (s)", unit_label("position", self.angular, 0),
                   f"{self.mechanism}: simulated motion")
        if len(axes) > 1:
            plot_lines(axes[1], self.t, self.v, self.names, "t (s)", unit_label("speed", self.angular, 1))
            plot_lines(axes[2], self.t, np.column_stack([self.energy - self.energy[0], self.work]),
                       ["mechanical energy change E − E₀", "work of actuators and loads W"], "t (s)", "energy (J)")
        return figure

    def __str__(self) -> str:
        d = self.as_dict()
        return (f"{self.mechanism}: simulated {self.duration:.4g} s in {len(self.t)} samples\n"
                f"mechanical energy {d['energy_start']:.6g} J → {d['energy_end']:.6g} J, work of actuators and loads "
                f"{d['work']:.6g} J (balance error {d['energy_balance_error']:.3g} J); closure residual ≤ "
                f"{d['max_residual']:.3g} m\n" + text_table(self._rows())
                + "\n(rad and rad/s for angles, m and m/s for lengths)")


def project(mech: Mechanism, q: ArrayLike, v: ArrayLike, iterations: int = 5) -> tuple[Array, Array]:
    """The configuration nearest q satisfying the closures Φ(q) = 0 (minimum-norm Newton steps on all coordinates,
    q ← q ⊕ −J⁺Φ with ``pin.integrate``) and the velocity with J q̇ = 0 nearest to v (rad/s, m/s)."""
    q, v, _ = _project(mech, np.asarray(q, dtype=float), np.asarray(v, dtype=float), iterations)
    return q, v


def _project(mech: Mechanism, q: Array, v: Array, iterations: int = 5) -> tuple[Array, Array, float]:
    """:func:`project`, with the largest closure residual |Φ| (m) left at the projected q."""
    if not mech.closures:
        return q, v, 0.0
    system = loop_solver(mech).system
    phi, J = system.evaluate(q)
    for _ in range(iterations):
        if np.abs(phi).max() < 1e-14:
            break
        q = pin.integrate(mech.model, q, -_min_norm(mech, J, phi))
        phi, J = system.evaluate(q)
    v = v - _min_norm(mech, J, J @ v)
    return q, v, float(np.abs(phi).max(initial=0.0))


def simulate(mech: Mechanism, q0: ArrayLike, v0: ArrayLike, duration: float, dt: float = 1e-3, *,
             actuation: Actuation | None = None, loads_at: LoadsAt | None = None,
             stop: Callable[[float, Array, Array], bool] | None = None) -> Simulation:
    """Integrate the motion from (q0, v0) (configuration, nq; velocities, nv: rad/s, m/s) for ``duration`` seconds
    with the fixed step ``dt`` (s): the KKT system of :func:`forward` (M q̈ + h = τ + Q + Jᵀλ, J q̈ = −J̇ q̇), RK4 on the
    configuration manifold (:func:`~mechatron.dynamics.integrate.rk4_step`), then projection onto the closures
    (:func:`project`).

    Args:
        actuation: (t, q, v) → {joint coordinate: force (N) or torque (N·m)}.
        loads_at: (t, q, v) → external loads [:class:`~mechatron.model.loads.Load`, …].
        stop: (t, q, v) → True to end the simulation early (e.g. a jaw closed).
    """
    duration = number("duration", duration, positive=True, unit="s")
    dt = number("dt", dt, positive=True, unit="s")
    v = np.asarray(v0, dtype=float)
    if v.shape != (mech.nv,):
        raise InputError(f"v0 must have {mech.nv} values for {mech.name}, got shape {v.shape}")
    q, v, residual = _project(mech, mech.check_configuration(q0, "q0"), v)
    model = mech.model

    def dynamics(t: float, q: Array, v: Array) -> tuple[Array, float, Array]:
        applied = generalized_forces(mech, q, actuation(t, q, v) if actuation else None,
                                     loads_at(t, q, v) if loads_at else None)
        a, lam = _accelerations(mech, q, v, applied)
        return a, float(applied @ v), lam

    def retraction(q: Array, dq: Array) -> Array:
        return pin.integrate(model, q, dq)

    steps = time_steps(duration, dt)
    t_out, q_out, v_out, a_out, lam_out, work_out, residual_out = [], [], [], [], [], [], []
    work, t = 0.0, 0.0
    for k in range(steps + 1):
        first = dynamics(t, q, v)
        t_out.append(t)
        q_out.append(q)
        v_out.append(v)
        a_out.append(first[0])
        lam_out.append(first[2])
        work_out.append(work)
        residual_out.append(residual)
        if k == steps or (stop is not None and stop(t, q, v)):
            break
        q, v, step_work = rk4_step(dynamics, t, q, v, dt, first, retraction)
        work += step_work
        q, v, residual = _project(mech, q, v)
        t += dt
    Q, V = np.array(q_out), np.array(v_out)
    energy = np.array([pin.computeMechanicalEnergy(model, mech.data, x, y) for x, y in zip(Q, V)])
    return Simulation(np.array(t_out), Q, V, np.array(a_out), np.array(lam_out), energy, np.array(work_out),
                      np.array(residual_out), mech.name, coordinate_names(mech), mech.coordinates(Q),
                      [bool(x) for x in mech.angular_coordinates()])

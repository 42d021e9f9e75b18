r"""The one-mass dynamic model of textbook chapter 6: masses and forces reduced to the input link.

For a mechanism with one degree of freedom and input coordinate φ (an angle, or a length S for a translating input)
the joint velocities are q̇ = S(q) φ̇ (the velocity map of the closed loops, :mod:`mechatron.linkages`). Then:

- reduced moment of inertia (6.8, 6.26) or reduced mass (6.5, 6.25): J_пр = Sᵀ M S = Σ m_i (v_Si/ω)² + J_Si (ω_i/ω)²,
  by kinetic-energy equality ½ J_пр φ̇² = T;
- its derivative dJ_пр/dφ = 2 Sᵀ (M S′ + C(q, S) S), with S′ = dS/dφ the second transfer functions: an RNEA pass
  without gravity at q̇ = S, q̈ = S′ (analytic, no finite differences);
- reduced moment (6.20, 6.28) or force (6.17, 6.27) of the applied forces by power equality: M_пр = Sᵀ(τ + Q − g),
  gravity and external loads included, inertia forces not;
- the equation of motion in energy form (6.40): ω = √(2∫M_пр dφ / J_пр + J_пр0 ω0² / J_пр), and in differential
  form (6.50, 6.52): ε = M_пр/J_пр − (dJ_пр/dφ) ω² / (2 J_пр).

The book's (6.21) writes the products of inertia as −J_xy ω_x ω_y inside ½(…); the kinetic energy of a rigid body
has −2 J_xy ω_x ω_y there (T = ½ ωᵀ J ω). mechatron uses Pinocchio's full inertia, so the point does not arise.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
import pinocchio as pin

from ..errors import InputError
from ..kinematics.loops import assemble, loop_solver
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from .constrained import Actuation, LoadsAt
from .integrate import rk4_step, time_steps
from .tree import generalized_forces, joint_space_inertia


def _one_dof(mech: Mechanism, input: str) -> None:
    if input not in mech.actuated:
        raise InputError(f"{input!r} is not an actuated coordinate of {mech.name} ({', '.join(mech.actuated)})")
    if mech.mobility() != 1 or len(mech.actuated) != 1:
        raise InputError(f"{mech.name} has {mech.mobility()} degrees of mobility; the one-mass model needs 1")


def velocity_map(mech: Mechanism, q, input: str) -> tuple[np.ndarray, np.ndarray]:
    """(S, S′): joint velocities for a unit input rate and joint accelerations for φ̇ = 1, φ̈ = 0."""
    q = np.asarray(q, dtype=float)
    if mech.closures:
        solver = loop_solver(mech)
        S = solver.velocity(q, {input: 1.0})
        return S, solver.acceleration(q, S, {})
    S = np.zeros(mech.nv)
    S[mech.model.joints[mech.joint_id(input)].idx_v] = 1.0
    return S, np.zeros(mech.nv)


def _inertia_terms(mech: Mechanism, q: np.ndarray, input: str) -> tuple[float, float]:
    """(J_пр, dJ_пр/dφ) from one velocity analysis."""
    S, S2 = velocity_map(mech, q, input)
    M = joint_space_inertia(mech.model, mech.data, q)
    inertial = pin.rnea(mech.model, mech.data, q, S, S2) - pin.computeGeneralizedGravity(mech.model, mech.data, q)
    return float(S @ M @ S), float(2 * S @ inertial)


def reduced_inertia(mech: Mechanism, q, input: str) -> float:
    """J_пр = Sᵀ M S (kg·m² for an angular input, kg — the reduced mass m_пр — for a linear one), eq. 6.5/6.8."""
    _one_dof(mech, input)
    return _inertia_terms(mech, np.asarray(q, dtype=float), input)[0]


def reduced_inertia_derivative(mech: Mechanism, q, input: str) -> float:
    """dJ_пр/dφ = 2 Sᵀ (M S′ + C(q, S) S) (kg·m²/rad or kg/m)."""
    _one_dof(mech, input)
    return _inertia_terms(mech, np.asarray(q, dtype=float), input)[1]


def reduced_moment(mech: Mechanism, q, input: str, forces: Mapping[str, float] | None = None,
                   loads: Loads = None, gravity: bool = True) -> float:
    """M_пр = Sᵀ(τ + Q − g) (N·m, or F_пр in N for a linear input), eq. 6.17/6.20/6.27/6.28: the power of the
    actuator forces, external loads and (optionally) gravity divided by the input rate."""
    _one_dof(mech, input)
    q = np.asarray(q, dtype=float)
    S, _ = velocity_map(mech, q, input)
    applied = generalized_forces(mech, q, forces, loads)
    if gravity:
        applied = applied - pin.computeGeneralizedGravity(mech.model, mech.data, q)
    return float(S @ applied)


def reduced_table(mech: Mechanism, input: str, values: np.ndarray, forces: Mapping[str, float] | None = None,
                  loads: Loads = None) -> pd.DataFrame:
    """J_пр, dJ_пр/dφ and M_пр (gravity and the given forces) over input values, assembled by continuation."""
    _one_dof(mech, input)
    rows = []
    q = None
    for value in np.asarray(values, dtype=float):
        q = assemble(mech, {input: value}, guess=q) if mech.closures else _serial_q(mech, input, value, q)
        rows.append({input: value, "J_reduced": reduced_inertia(mech, q, input),
                     "dJ_reduced": reduced_inertia_derivative(mech, q, input),
                     "M_reduced": reduced_moment(mech, q, input, forces, loads)})
    return pd.DataFrame(rows)


def _serial_q(mech: Mechanism, input: str, value: float, q: np.ndarray | None) -> np.ndarray:
    q = mech.neutral() if q is None else q.copy()
    q[mech.model.joints[mech.joint_id(input)].idx_q] = value
    return q


# ------------------------------------------------------------------------------------------ equations of motion
def energy_form(phi: np.ndarray, J: np.ndarray, M: np.ndarray, omega0: float) -> np.ndarray:
    """ω(φ) from the energy form (6.40): ½ J_пр ω² − ½ J_пр0 ω0² = ∫ M_пр dφ (trapezoidal rule on the grid).

    Raises:
        InputError: where the kinetic energy would become negative (the mechanism stops before reaching φ).
    """
    phi, J, M = (np.asarray(x, dtype=float) for x in (phi, J, M))
    work = np.concatenate([[0.0], np.cumsum(0.5 * (M[1:] + M[:-1]) * np.diff(phi))])
    twice_energy = 2 * work + J[0] * omega0**2
    if np.any(twice_energy < 0):
        stop = phi[int(np.argmax(twice_energy < 0))]
        raise InputError(f"the mechanism stops before {stop:.6g}: the work of the forces exceeds the kinetic energy")
    return np.sign(omega0 if omega0 else 1.0) * np.sqrt(twice_energy / J)


@dataclass
class ReducedMotion:
    """Time history of the one-mass model: t, φ, ω (φ̇), ε (φ̈), and J_пр and M_пр along it."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    inertia: np.ndarray
    moment: np.ndarray


def differential_form(mech: Mechanism, input: str, phi0: float, omega0: float, duration: float, dt: float = 1e-3,
                      *, actuation: Actuation | None = None, loads_at: LoadsAt | None = None) -> ReducedMotion:
    """Integrate J_пр ε + ½ (dJ_пр/dφ) ω² = M_пр (6.50, ε from 6.52) in time (s) by RK4
    (:func:`~mechatron.dynamics.integrate.rk4_step`).

    J_пр, dJ_пр/dφ and M_пр = Sᵀ(τ + Q − g) are evaluated on the mechanism at every stage (assembled from the
    previous stage's configuration). ``actuation`` and ``loads_at`` take (t, q, q̇) like
    :func:`~mechatron.dynamics.constrained.simulate`'s, so the one-mass model and the full simulation can be given
    the same forces.
    """
    _one_dof(mech, input)
    state = {"q": assemble(mech, {input: phi0})}
    solver = loop_solver(mech) if mech.closures else None
    model, data = mech.model, mech.data

    def terms(t: float, phi: float, omega: float) -> tuple[float, float, tuple[float, float]]:
        """(ε, 0, (J_пр, M_пр)) at (t, φ, ω)."""
        if solver is not None:
            q = state["q"].copy()
            q[solver.act] = phi
            q, J = solver.newton(q, polish=True)
            _, S, S2 = solver.analyse(q, J, np.ones(1), np.zeros(1))  # q̇ and q̈ for φ̇ = 1, φ̈ = 0
        else:
            q = _serial_q(mech, input, phi, state["q"])
            S, S2 = velocity_map(mech, q, input)
        state["q"] = q
        M = joint_space_inertia(model, data, q)
        gravity = pin.computeGeneralizedGravity(model, data, q)
        inertia = float(S @ M @ S)
        d_inertia = float(2 * S @ (pin.rnea(model, data, q, S, S2) - gravity))
        v = S * omega
        applied = generalized_forces(mech, q, actuation(t, q, v) if actuation else None,
                                     loads_at(t, q, v) if loads_at else None)
        moment = float(S @ (applied - gravity))
        return (moment - 0.5 * d_inertia * omega**2) / inertia, 0.0, (inertia, moment)

    steps = time_steps(duration, dt)
    t, phi, omega = 0.0, float(phi0), float(omega0)
    rows = []
    for k in range(steps + 1):
        first = terms(t, phi, omega)
        rows.append((t, phi, omega, first[0], *first[2]))
        if k == steps:
            break
        phi, omega, _ = rk4_step(terms, t, phi, omega, dt, first)
        t += dt
    return ReducedMotion(*(np.array(column) for column in zip(*rows)))


# ------------------------------------------------------------------------------------------ motion regimes
def motion_regimes(t: np.ndarray, phi: np.ndarray, omega: np.ndarray, period: float = 2 * math.pi,
                   tolerance: float = 1e-3) -> pd.DataFrame:
    """Split a motion into cycles of the input (each ``period`` of φ from the start) and name each one's regime
    (section 6.7); if the input turns back, the cycles end there. Over a cycle the mechanism returns to the same position, so J_пр is the same at both ends and the
    work of all forces ΣA = ½ J_пр (ω_end² − ω_start²) (6.53): ``run-up`` if the speed at the end of the cycle is
    higher by more than ``tolerance`` (relative), ``run-down`` if lower, ``steady`` otherwise. Each cycle also gets
    its mean speed and coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean."""
    t, phi, omega = (np.asarray(x, dtype=float) for x in (t, phi, omega))
    travel = (phi - phi[0]) * np.sign(phi[-1] - phi[0] or 1.0)
    backwards = np.flatnonzero(np.diff(travel) < 0)
    if len(backwards):  # the input stopped and turned back: only the motion before that is in cycles
        end = int(backwards[0]) + 1
        t, travel, omega = t[:end], travel[:end], omega[:end]
    rows = []
    for k in range(int(travel[-1] // period)):
        start, end = k * period, (k + 1) * period
        inside = (travel >= start) & (travel <= end)
        w_start, w_end = np.interp([start, end], travel, omega)
        t_start, t_end = np.interp([start, end], travel, t)
        w = np.concatenate([[w_start], omega[inside], [w_end]])
        times = np.concatenate([[t_start], t[inside], [t_end]])
        mean = float(np.trapezoid(w, times) / (t_end - t_start))
        change = (abs(w_end) - abs(w_start)) / abs(w_start) if w_start else math.inf
        regime = "steady" if abs(change) <= tolerance else ("run-up" if change > 0 else "run-down")
        rows.append({"cycle": k, "t_start": float(t_start), "t_end": float(t_end), "omega_start": float(w_start),
                     "omega_end": float(w_end), "omega_mean": mean, "omega_min": float(w.min()),
                     "omega_max": float(w.max()), "fluctuation": float((w.max() - w.min()) / abs(mean)),
                     "regime": regime})
    columns = ["cycle", "t_start", "t_end", "omega_start", "omega_end", "omega_mean", "omega_min", "omega_max",
               "fluctuation", "regime"]
    return pd.DataFrame(rows, columns=columns)

r"""Transmission ratio of a motion converter [Egorov, section 4.4], u = Ω_motor / Ω_output [Egorov, 4.58].

Ω is an angular (rad/s) or linear (m/s) speed, M a torque (N·m) or force (N), P an inertia (kg·m²) or mass (kg),
γ an angle (rad) or distance (m): the same formulas serve rotary, rotary→linear and linear→rotary converters
(u then has units: rad/m or m/rad).

- static (load-dominated) choice [Egorov, 4.59–4.62]: u = M_h / (M_d,tr η);
- minimum-time choice when the dynamic load dominates [Egorov, 4.63, 4.65, 4.70, 4.71]:
  u = ∛(2 Ω_d² P_h / (γ M_i η)) with γ = γ_max/2 by default [Egorov, 4.64]; valid while the load inertia
  dominates, J_h / (u² J_d) > 1 [Egorov, 4.66] with J_d = (1.1…1.3) J_rotor [Egorov, 4.67]; otherwise inertia
  matching u = √(J_h / J_d) [Egorov, 4.68–4.69];
- a load that changes over a cycle of n segments [Egorov, 4.72–4.75]: u = ∛(2 Ω_d² Σ P_hj / (Σ γ_j M_i η)).

Where the cube root comes from: a rest-to-rest move of γ with the motor limited to the speed Ω_d and accelerating
with the torque M_i takes t(u) = γ u / Ω_d + Ω_d J_d / M_i + Ω_d P_h / (u² M_i η) when it reaches the speed limit
(output acceleration a = M_i / (J_d u + P_h / (u η))); dt/du = 0 gives [Egorov, 4.63] and, at that ratio, the profile
accelerates over a quarter of the distance. The motor inertia only adds a constant, as long as the profile stays
trapezoidal; when the speed limit is not reached (a large J_d) the move is triangular, t = 2 √(γ / a), and its optimum
is inertia matching with the efficiency, u = √(P_h / (η J_d)). :func:`optimal_ratio` minimizes the exact piecewise
t(u) with CasADi (Ipopt), so each formula can be checked against it.

For duty cycles where the RMS torque decides, :func:`rms_ratio_band` gives the ratios for which a motor's RMS torque
stays within its rating ([vdStraete]; [Giberti]) and the RMS-optimal ratio.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..io.values import positives as _positive

if TYPE_CHECKING:  # pragma: no cover
    import casadi as ca


def static_ratio(load: float, motor_effort: float, efficiency: float = 1.0) -> float:
    """u = M_h / (M_d,tr η) [Egorov, 4.59–4.62]: the ratio at which the motor's required torque (N·m) or force (N)
    M_d,tr = ``motor_effort`` holds the resisting load M_h = ``load`` (N·m or N) through a converter of efficiency
    η (0…1); u in rad/rad, rad/m or m/rad by the kinds of motion."""
    _positive(load=load, motor_effort=motor_effort, efficiency=efficiency)
    return load / (motor_effort * efficiency)


def design_displacement(maximum: float) -> float:
    """γ = γ_max / 2 [Egorov, 4.64]: the displacement (rad or m) to size for when the task moves vary."""
    _positive(maximum=maximum)
    return maximum / 2


def minimum_time_ratio(motor_speed: float, load_inertia: float, displacement: float, dynamic_effort: float,
                       efficiency: float = 1.0) -> float:
    """u = ∛(2 Ω_d² P_h / (γ M_i η)) [Egorov, 4.63] (rotary [Egorov, 4.65], rotary→linear [Egorov, 4.70],
    linear→rotary [Egorov, 4.71]): the ratio of the shortest rest-to-rest move of γ = ``displacement`` (rad or m)
    with the motor speed Ω_d = ``motor_speed`` (rad/s or m/s), the load inertia P_h = ``load_inertia`` (kg·m² or
    kg), the motor's dynamic torque or force M_i = ``dynamic_effort`` (N·m or N) and the efficiency η."""
    _positive(motor_speed=motor_speed, load_inertia=load_inertia, displacement=displacement,
              dynamic_effort=dynamic_effort, efficiency=efficiency)
    return (2 * motor_speed**2 * load_inertia / (displacement * dynamic_effort * efficiency)) ** (1 / 3)


def cycle_ratio(motor_speed: float, load_inertias: Sequence[float], displacements: Sequence[float],
                dynamic_effort: float, efficiency: float = 1.0) -> float:
    """u = ∛(2 Ω_d² Σ P_hj / (Σ γ_j M_i η)) [Egorov, 4.72–4.75] for a cycle whose segments j move different loads
    (units as :func:`minimum_time_ratio`)."""
    if len(load_inertias) != len(displacements) or not load_inertias:
        raise InputError("give one load inertia per displacement of the cycle")
    for k, (p, g) in enumerate(zip(load_inertias, displacements)):
        _positive(**{f"load_inertias[{k}]": p, f"displacements[{k}]": g})
    return minimum_time_ratio(motor_speed, float(sum(load_inertias)), float(sum(displacements)), dynamic_effort,
                              efficiency)


def motor_side_inertia(rotor_inertia: float, factor: float = 1.2) -> float:
    """J_d = (1.1…1.3) J_rotor [Egorov, 4.67] (kg·m²): the rotor plus the converter reflected to the motor shaft."""
    if not 1.0 <= factor <= 1.5:
        raise InputError(f"the factor of [Egorov, 4.67] is 1.1…1.3, got {factor:g}")
    _positive(rotor_inertia=rotor_inertia)
    return factor * rotor_inertia


def load_dominance(load_inertia: float, ratio: float, drive_inertia: float) -> float:
    """J_h / (u² J_d) [Egorov, 4.66] (dimensionless; J_h in kg·m² or kg, J_d in kg·m², u in rad/rad or rad/m):
    > 1 when the load's inertia dominates (the minimum-time formula applies)."""
    _positive(load_inertia=load_inertia, ratio=ratio, drive_inertia=drive_inertia)
    return load_inertia / (ratio**2 * drive_inertia)


def inertia_matching_ratio(load_inertia: float, drive_inertia: float, efficiency: float = 1.0) -> float:
    """u = √(J_h / (η J_d)) (J_h in kg·m² or kg, J_d in kg·m²): the optimum of a move that never reaches the speed
    limit; [Egorov, 4.69] is the lossless case √(J_h / J_d)."""
    _positive(load_inertia=load_inertia, drive_inertia=drive_inertia, efficiency=efficiency)
    return math.sqrt(load_inertia / (efficiency * drive_inertia))


@dataclass(frozen=True)
class RatioChoice:
    """The textbook's choice: the minimum-time ratio [Egorov, 4.63] if the load dominates there [Egorov, 4.66],
    else inertia matching [Egorov, 4.69]; ``dominance`` is J_h/(u² J_d) at the minimum-time ratio."""

    ratio: float
    rule: str
    minimum_time: float
    inertia_matching: float
    dominance: float


def textbook_ratio(motor_speed: float, load_inertia: float, displacement: float, dynamic_effort: float,
                   rotor_inertia: float, efficiency: float = 1.0, factor: float = 1.2) -> RatioChoice:
    """The procedure of [Egorov, section 4.4]: [Egorov, 4.63], checked by [Egorov, 4.66] with J_d from
    [Egorov, 4.67] (``factor`` × ``rotor_inertia``, kg·m²), else [Egorov, 4.69]; units as
    :func:`minimum_time_ratio`."""
    u = minimum_time_ratio(motor_speed, load_inertia, displacement, dynamic_effort, efficiency)
    drive = motor_side_inertia(rotor_inertia, factor)
    dominance = load_dominance(load_inertia, u, drive)
    matching = math.sqrt(load_inertia / drive)  # [Egorov, 4.69] as printed
    if dominance > 1:
        return RatioChoice(u, "minimum time [Egorov, 4.63]", u, matching, dominance)
    return RatioChoice(matching, "inertia matching [Egorov, 4.69]", u, matching, dominance)


def move_time(ratio: float | ca.SX, motor_speed: float, load_inertia: float, displacement: float,
              dynamic_effort: float, efficiency: float = 1.0, drive_inertia: float = 0.0, *,
              backend: Any = math) -> float | ca.SX:
    """Time (s) of a rest-to-rest move of γ = ``displacement`` (rad or m) through the ratio u: the motor accelerates
    and brakes with the torque M_i = ``dynamic_effort`` (N·m; N for a linear motor) and runs at most at
    Ω_d = ``motor_speed`` (rad/s or m/s), so the output accelerates at a = M_i / (J_d u + P_h / (u η)) with the load
    inertia P_h = ``load_inertia`` (kg·m² or kg) and the motor-side inertia J_d = ``drive_inertia`` (kg·m²).
    Trapezoidal if it reaches the speed limit, t = γ u / Ω_d + Ω_d / (u a) (whose minimum over u is
    [Egorov, 4.63] when J_d = 0), triangular otherwise, t = 2 √(γ / a). ``backend=casadi`` builds the expression
    for a symbolic u."""
    u = ratio
    acceleration = dynamic_effort / (drive_inertia * u + load_inertia / (u * efficiency))
    speed = motor_speed / u
    trapezoid = displacement / speed + speed / acceleration
    triangle = 2 * backend.sqrt(displacement / acceleration)
    reaches = speed**2 <= displacement * acceleration  # accelerate + brake within the distance
    if backend is math:
        return trapezoid if reaches else triangle
    return backend.if_else(reaches, trapezoid, triangle)


def optimal_ratio(motor_speed: float, load_inertia: float | ArrayLike, displacement: float | ArrayLike,
                  dynamic_effort: float, efficiency: float = 1.0, drive_inertia: float = 0.0) -> tuple[float, float]:
    """(u, t): the ratio that minimizes the time of a move (:func:`move_time`), or of a cycle of moves j with
    their own load inertias and displacements (sequences: the sum of their times), found with CasADi/Ipopt on
    log u from [Egorov, 4.72] and the inertia-matching ratio (and a decade either side); t in s, units of the
    arguments as :func:`move_time`."""
    import casadi as ca

    loads = np.atleast_1d(np.asarray(load_inertia, dtype=float))
    moves = np.atleast_1d(np.asarray(displacement, dtype=float))
    if loads.shape != moves.shape:
        raise InputError("give one load inertia per displacement")
    for k, (p, g) in enumerate(zip(loads, moves)):
        _positive(**{f"load_inertia[{k}]": float(p), f"displacement[{k}]": float(g)})
    _positive(motor_speed=motor_speed, dynamic_effort=dynamic_effort, efficiency=efficiency)

    def total(u, backend=math):
        return sum(move_time(u, motor_speed, float(p), float(g), dynamic_effort, efficiency, drive_inertia,
                             backend=backend) for p, g in zip(loads, moves))

    x = ca.SX.sym("log_u")
    solver = ca.nlpsol("ratio", "ipopt", {"x": x, "f": total(ca.exp(x), ca)},
                       {"ipopt.print_level": 0, "print_time": False, "ipopt.tol": 1e-12,
                        "ipopt.sb": "yes", "ipopt.max_iter": 200})
    formula = cycle_ratio(motor_speed, list(loads), list(moves), dynamic_effort, efficiency)
    starts = [formula, formula / 10, formula * 10]
    if drive_inertia > 0:
        starts.append(inertia_matching_ratio(float(loads.sum()), drive_inertia * len(loads), efficiency))
    best = None
    for start in starts:
        solution = solver(x0=math.log(start), lbx=math.log(formula) - 12, ubx=math.log(formula) + 12)
        u = math.exp(float(solution["x"]))
        t = total(u)
        if best is None or t < best[1]:
            best = (u, t)
    return best


@dataclass(frozen=True)
class RatioBand:
    """Ratios for which a motor's RMS torque over a duty cycle stays within its rated torque: [lower, upper]
    (empty if ``feasible`` is false), the RMS-optimal ratio and the RMS torque there (N·m)."""

    lower: float
    upper: float
    optimal: float
    rms_at_optimal: float
    feasible: bool


def rms_ratio_band(rotor_inertia: float, rated_torque: float, times: ArrayLike, load_acceleration: ArrayLike,
                   load_torque: ArrayLike, efficiency: float = 1.0, max_motor_speed: float | None = None,
                   load_speed: ArrayLike | None = None) -> RatioBand:
    """The feasible ratio band of a motor for a load cycle (RMS torque criterion).

    The motor: rotor inertia J_m = ``rotor_inertia`` (kg·m²), rated torque T_rated (N·m), top speed (rad/s). The
    cycle, sampled at ``times`` (s): the load's acceleration ω̇_L (rad/s²), torque T_L (N·m) and, if given, speed
    ω_L (rad/s; without it the load is taken to always take power).

    With the motor torque T_m = J_m u ω̇_L + T*/u (T* = T_L/η when the load takes power, T_L·η when it returns it),
    T_rms²(u) = J_m² u² ⟨ω̇_L²⟩ + 2 J_m ⟨ω̇_L T*⟩ + ⟨T*²⟩ / u², the band is where T_rms ≤ T_rated — a quadratic in u²;
    the RMS-optimal ratio is u* = (⟨T*²⟩ / (J_m² ⟨ω̇_L²⟩))^{1/4}. A motor speed limit caps the band at
    ω_m,max / max |ω_L|.
    """
    t = np.asarray(times, dtype=float)
    acc, torque = np.asarray(load_acceleration, dtype=float), np.asarray(load_torque, dtype=float)
    duration = t[-1] - t[0]
    if not duration > 0:
        raise InputError("the duty cycle must last longer than 0 s")
    speed = np.asarray(load_speed, dtype=float) if load_speed is not None else np.gradient(np.zeros_like(t), t)
    from .transmission import transmitted_torque

    effective = transmitted_torque(torque, speed, 1.0, efficiency)  # T*: T/η or T·η by the direction of power

    def mean(x: np.ndarray) -> float:
        return float(np.trapezoid(x, t) / duration)

    a2, at, t2 = mean(acc**2), mean(acc * effective), mean(effective**2)
    J = rotor_inertia
    optimal = (t2 / (J**2 * a2)) ** 0.25 if a2 > 0 else math.inf
    rms_at = math.sqrt(J**2 * optimal**2 * a2 + 2 * J * at + t2 / optimal**2) if math.isfinite(optimal) else \
        math.sqrt(max(t2, 0.0))
    # J²a2 x² + (2 J at − T_r²) x + t2 ≤ 0, x = u²
    A, B, C = J**2 * a2, 2 * J * at - rated_torque**2, t2
    discriminant = B * B - 4 * A * C
    if A == 0:
        lower, upper = (math.sqrt(-C / B), math.inf) if B < 0 else (math.inf, 0.0)
    elif discriminant < 0:
        lower, upper = math.inf, 0.0
    else:
        roots = sorted(((-B - math.sqrt(discriminant)) / (2 * A), (-B + math.sqrt(discriminant)) / (2 * A)))
        lower, upper = (math.sqrt(max(roots[0], 0.0)), math.sqrt(roots[1])) if roots[1] > 0 else (math.inf, 0.0)
    if max_motor_speed is not None and load_speed is not None and np.abs(speed).max() > 0:
        upper = min(upper, max_motor_speed / float(np.abs(speed).max()))
    return RatioBand(lower, upper, optimal, rms_at, lower <= upper)

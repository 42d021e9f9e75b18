r"""The one-mass dynamic model: masses and forces reduced to the input link ([Egorov, ch. 6]).

For a mechanism with one degree of freedom and input coordinate φ (an angle, or a length S for a translating input)
the joint velocities are q̇ = S(q) φ̇ (the velocity map of the closed loops, :mod:`mechatron.kinematics.loops`).
Then:

- reduced moment of inertia [Egorov, 6.8, 6.26] or reduced mass [Egorov, 6.5, 6.25]:
  J_пр = Sᵀ M S = Σ m_i (v_Si/ω)² + J_Si (ω_i/ω)², by kinetic-energy equality ½ J_пр φ̇² = T [Egorov, 6.7];
- its derivative dJ_пр/dφ = 2 Sᵀ (M S′ + C(q, S) S), with S′ = dS/dφ the second transfer functions: an RNEA pass
  without gravity at q̇ = S, q̈ = S′ (analytic, no finite differences);
- reduced moment [Egorov, 6.20, 6.28] or force [Egorov, 6.17, 6.27] of the applied forces by power equality:
  M_пр = Sᵀ(τ + Q − g), gravity and external loads included, inertia forces not;
- the equation of motion in energy form, ω = √(2∫M_пр dφ / J_пр + J_пр0 ω0² / J_пр) [Egorov, 6.40], and in
  differential form, ε = M_пр/J_пр − (dJ_пр/dφ) ω² / (2 J_пр) [Egorov, 6.50, 6.52].

[Egorov, 6.21] writes the products of inertia as −J_xy ω_x ω_y inside ½(…); the kinetic energy of a rigid body has
−2 J_xy ω_x ω_y there (T = ½ ωᵀ J ω). mechatron uses Pinocchio's full inertia, so the point does not arise.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.values import LARGEST, number
from ..kinematics.loops import assemble, loop_solver
from ..model.loads import Loads
from ..model.mechanism import Mechanism
from ..report.result import Result
from .constrained import Actuation, LoadsAt
from .integrate import rk4_step, time_steps
from .motion import coordinate_limits
from .series import plot_lines, stacked_axes, text_table
from .tree import generalized_forces, joint_space_inertia

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

Array = NDArray[np.float64]


def _units(linear: bool) -> dict[str, str]:
    """Units of the one-mass model for an angular or a linear input."""
    if linear:
        return {"input": "m", "speed": "m/s", "acceleration": "m/s²", "inertia": "kg", "derivative": "kg/m",
                "moment": "N", "inertia_name": "reduced mass", "moment_name": "reduced force"}
    return {"input": "rad", "speed": "rad/s", "acceleration": "rad/s²", "inertia": "kg·m²",
            "derivative": "kg·m²/rad", "moment": "N·m", "inertia_name": "reduced moment of inertia",
            "moment_name": "reduced moment"}


def _one_dof(mech: Mechanism, input: str | None) -> str:
    """The input coordinate (default: the actuated one), or an error if the one-mass model does not apply."""
    input = input if input is not None else mech.actuated[0]
    if input not in mech.actuated:
        from ..io.budget import option

        raise InputError(f"{option('input')} {input!r} is not an actuated coordinate of {mech.name} "
                         f"({', '.join(mech.actuated)})")
    if mech.mobility() != 1 or len(mech.actuated) != 1:
        raise InputError(f"{mech.name} has {mech.mobility()} degrees of mobility; the one-mass model needs 1")
    return input


def velocity_map(mech: Mechanism, q: ArrayLike, input: str) -> tuple[Array, Array]:
    """(S, S′) (nv,): the joint velocities for a unit input rate (the first transfer functions: rad/rad, m/rad, …)
    and the joint accelerations for φ̇ = 1, φ̈ = 0 (the second transfer functions)."""
    q = np.asarray(q, dtype=float)
    if mech.closures:
        solver = loop_solver(mech)
        S = solver.velocity(q, {input: 1.0})
        return S, solver.acceleration(q, S, {})
    S = np.zeros(mech.nv)
    S[mech.model.joints[mech.joint_id(input)].idx_v] = 1.0
    return S, np.zeros(mech.nv)


def _terms(mech: Mechanism, q: Array, S: Array, S2: Array, applied: Array) -> tuple[float, float, float]:
    """(J_пр, dJ_пр/dφ, M_пр) at q for the first and second transfer functions S, S′ and the applied generalized
    forces τ + Q: Sᵀ M S, 2 Sᵀ(M S′ + C(q, S) S) (an RNEA pass less gravity) and Sᵀ(τ + Q − g)."""
    model, data = mech.model, mech.data
    gravity = pin.computeGeneralizedGravity(model, data, q)
    inertia = float(S @ joint_space_inertia(model, data, q) @ S)
    return inertia, float(2 * S @ (pin.rnea(model, data, q, S, S2) - gravity)), float(S @ (applied - gravity))


def _inertia_terms(mech: Mechanism, q: Array, input: str) -> tuple[float, float]:
    """(J_пр, dJ_пр/dφ) from one velocity analysis."""
    S, S2 = velocity_map(mech, q, input)
    return _terms(mech, q, S, S2, np.zeros(mech.nv))[:2]


def reduced_inertia(mech: Mechanism, q: ArrayLike, input: str) -> float:
    """J_пр = Sᵀ M S at the configuration q: kg·m² for an angular input, kg — the reduced mass m_пр — for a linear
    one [Egorov, 6.5, 6.8, 6.25, 6.26]."""
    _one_dof(mech, input)
    return _inertia_terms(mech, np.asarray(q, dtype=float), input)[0]


def reduced_inertia_derivative(mech: Mechanism, q: ArrayLike, input: str) -> float:
    """dJ_пр/dφ = 2 Sᵀ (M S′ + C(q, S) S) (kg·m²/rad or kg/m), the coefficient of ω²/2 in [Egorov, 6.50]."""
    _one_dof(mech, input)
    return _inertia_terms(mech, np.asarray(q, dtype=float), input)[1]


def reduced_moment(mech: Mechanism, q: ArrayLike, input: str, forces: Mapping[str, float] | None = None,
                   loads: Loads = None, gravity: bool = True) -> float:
    """M_пр = Sᵀ(τ + Q − g) (N·m, or F_пр in N for a linear input) [Egorov, 6.17, 6.20, 6.27, 6.28]: the power of
    the actuator ``forces`` (by joint coordinate: N, N·m), external ``loads`` and (optionally) gravity divided by the
    input rate."""
    _one_dof(mech, input)
    q = np.asarray(q, dtype=float)
    S, _ = velocity_map(mech, q, input)
    applied = generalized_forces(mech, q, forces, loads)
    if gravity:
        applied = applied - pin.computeGeneralizedGravity(mech.model, mech.data, q)
    return float(S @ applied)


@dataclass(eq=False)
class ReducedModel(Result):
    """The one-mass model over the input's range: J_пр, dJ_пр/dφ and M_пр against the input.

    Attributes:
        mechanism: Name of the mechanism.
        input: The input coordinate φ (or S).
        linear: Whether the input is a length (then J_пр is the reduced mass m_пр, M_пр the reduced force F_пр).
        values: Input values (N,) (rad or m).
        inertia: J_пр (N,) (kg·m² or kg) [Egorov, 6.8, 6.5].
        inertia_derivative: dJ_пр/dφ (N,) (kg·m²/rad or kg/m).
        moment: M_пр (N,) (N·m or N) of gravity and the given forces [Egorov, 6.20, 6.17].
    """

    mechanism: str
    input: str
    linear: bool
    values: Array
    inertia: Array
    inertia_derivative: Array
    moment: Array

    def to_frame(self) -> pd.DataFrame:
        """Columns ``<input>`` (rad or m), ``J_reduced`` (kg·m² or kg), ``dJ_reduced`` (kg·m²/rad or kg/m),
        ``M_reduced`` (N·m or N)."""
        import pandas as pd

        return pd.DataFrame({self.input: self.values, "J_reduced": self.inertia,
                             "dJ_reduced": self.inertia_derivative, "M_reduced": self.moment})

    def as_dict(self) -> dict:
        """mechanism, input, kind ("inertia" or "mass"), units, and table: the columns of :meth:`to_frame` as lists."""
        units = _units(self.linear)
        return {"mechanism": self.mechanism, "input": self.input, "kind": "mass" if self.linear else "inertia",
                "units": {self.input: units["input"], "J_reduced": units["inertia"],
                          "dJ_reduced": units["derivative"], "M_reduced": units["moment"]},
                "table": {k: v.tolist() for k, v in self.to_frame().items()}}

    def plot(self, ax: Axes | None = None) -> Figure:
        """J_пр against the input (drawn into ``ax`` if given), then M_пр against the input."""
        units = _units(self.linear)
        figure, axes = stacked_axes(ax, 2, 8.0, 3.0)
        xlabel = f"{self.input} ({units['input']})"
        plot_lines(axes[0], self.values, self.inertia, [f"J_reduced [Egorov, {'6.5' if self.linear else '6.8'}]"],
                   xlabel, f"{units['inertia_name']} ({units['inertia']})",
                   f"{self.mechanism}: one-mass model reduced to {self.input}")
        if len(axes) > 1:
            plot_lines(axes[1], self.values, self.moment,
                       [f"M_reduced [Egorov, {'6.17' if self.linear else '6.20'}]"], xlabel,
                       f"{units['moment_name']} ({units['moment']})")
        return figure

    def __str__(self) -> str:
        units = _units(self.linear)
        frame = self.to_frame()
        step = max(1, len(frame) // 12)
        rows = frame.iloc[::step].to_dict(orient="records")
        return (f"{self.mechanism}: {units['inertia_name']} and {units['moment_name']} of gravity and the given "
                f"forces, input {self.input} ({units['input']})\n"
                f"  J_reduced {self.inertia.min():.6g} … {self.inertia.max():.6g} {units['inertia']}; "
                f"M_reduced {self.moment.min():.6g} … {self.moment.max():.6g} {units['moment']}\n"
                + text_table(rows, digits=6))


def default_values(mech: Mechanism, input: str, samples: int = 73) -> Array:
    """``samples`` values of ``input`` over its range (rad, m): between its limits, or a full turn from its
    reference value where it has none."""
    lower, upper = coordinate_limits(mech)
    v = mech.model.joints[mech.joint_id(input)].idx_v
    if np.isfinite(lower[v]) and np.isfinite(upper[v]):
        return np.linspace(lower[v], upper[v], samples)
    start = 0.0
    if mech.closures and mech.reference_q is not None:
        start = float(mech.reference_q[loop_solver(mech).index[input]])
    return start + np.linspace(0.0, 2 * math.pi, samples)


#: The least time one value of the one-mass model takes (s; measured: about 15 ms for a closed loop on a desktop)
#: and its bytes (the values and the three terms, with room: measured about 60).
REDUCED_SECONDS, REDUCED_BYTES = 2e-3, 128.0


def _samples_budget(samples: float) -> None:
    """Refuse (:mod:`mechatron.io.budget`) ``samples`` values of the one-mass model past the memory or time limit."""
    from ..io.budget import count, option, require, seconds

    what, advice = f"{option('samples')} {count(samples)}: values of the one-mass model", \
        f"use fewer {option('samples')}"
    require(what, samples, REDUCED_BYTES, advice=advice)
    seconds(what, samples, REDUCED_SECONDS, advice=advice)


def reduced_table(mech: Mechanism, input: str | None = None, values: ArrayLike | None = None, *, samples: int = 73,
                  forces: Mapping[str, float] | None = None, loads: Loads = None) -> ReducedModel:
    """J_пр [Egorov, 6.8], dJ_пр/dφ and M_пр [Egorov, 6.20] (gravity, the actuator ``forces`` by joint coordinate
    in N or N·m, and ``loads``) over input ``values`` (rad or m; default :func:`default_values`, ``samples`` of
    them), assembled by continuation. ``input`` defaults to the actuated coordinate."""
    input = _one_dof(mech, input)
    if values is None:
        samples = number("samples", samples, integer=True, minimum=2)
        _samples_budget(samples)
    values = default_values(mech, input, samples) if values is None else np.atleast_1d(np.asarray(values, float))
    if values.ndim != 1 or len(values) < 2 or not np.all(np.isfinite(values)):
        raise InputError(f"the one-mass model needs at least two finite values of {input}, got {len(values)}")
    out = np.empty((len(values), 3))
    q = None
    for k, value in enumerate(values):
        q = assemble(mech, {input: value}, guess=q) if mech.closures else _serial_q(mech, input, value, q)
        out[k] = _terms(mech, q, *velocity_map(mech, q, input), generalized_forces(mech, q, forces, loads))
    return ReducedModel(mech.name, input, mech.joint_kind(input) == "prismatic", values, *out.T.copy())


def _serial_q(mech: Mechanism, input: str, value: float, q: Array | None) -> Array:
    """The configuration of a serial mechanism with the input joint's coordinate at ``value`` (rad, m), the other
    coordinates as in ``q`` (default neutral): q = neutral ⊕ coordinates."""
    coordinates = np.zeros(mech.nv) if q is None else mech.coordinates(q)
    coordinates[mech.model.joints[mech.joint_id(input)].idx_v] = value
    return mech.configuration(coordinates)


# ------------------------------------------------------------------------------------------ equations of motion
def energy_form(phi: ArrayLike, J: ArrayLike, M: ArrayLike, omega0: float) -> Array:
    """ω(φ) (rad/s or m/s) from the energy form ½ J_пр ω² − ½ J_пр0 ω0² = ∫ M_пр dφ [Egorov, 6.39–6.40]
    (trapezoidal rule on the grid φ), for J_пр (kg·m² or kg) and M_пр (N·m or N) on that grid.

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


@dataclass(eq=False)
class ReducedMotion(Result):
    """Time history of the one-mass model.

    Attributes:
        t: Times (N,) (s).
        phi: The input φ (N,) (rad or m).
        omega: Its rate ω = φ̇ (rad/s or m/s).
        epsilon: Its acceleration ε = φ̈ (rad/s² or m/s²) [Egorov, 6.52].
        inertia: J_пр along the motion (kg·m² or kg).
        moment: M_пр along the motion (N·m or N).
        input: Name of the input coordinate.
        linear: Whether the input is a length.
        mechanism: Name of the mechanism.
    """

    t: Array
    phi: Array
    omega: Array
    epsilon: Array
    inertia: Array
    moment: Array
    input: str = "phi"
    linear: bool = False
    mechanism: str = ""

    @property
    def kinetic_energy(self) -> Array:
        """T = ½ J_пр ω² (J) [Egorov, 6.6]."""
        return 0.5 * self.inertia * self.omega**2

    def to_frame(self) -> pd.DataFrame:
        """Columns t (s), ``<input>`` (rad or m), ``qd_<input>``, ``qdd_<input>`` (its rate and acceleration),
        ``J_reduced`` (kg·m² or kg), ``M_reduced`` (N·m or N), ``kinetic_energy`` (J)."""
        import pandas as pd

        return pd.DataFrame({"t": self.t, self.input: self.phi, f"qd_{self.input}": self.omega,
                             f"qdd_{self.input}": self.epsilon, "J_reduced": self.inertia,
                             "M_reduced": self.moment, "kinetic_energy": self.kinetic_energy})

    def as_dict(self) -> dict:
        """mechanism, input, units, duration (s), samples, and the input, its rate and the kinetic energy at the
        start and the end, with the extreme rates."""
        units = _units(self.linear)
        return {"mechanism": self.mechanism, "input": self.input,
                "units": {"input": units["input"], "speed": units["speed"], "kinetic_energy": "J"},
                "duration": float(self.t[-1] - self.t[0]), "samples": len(self.t),
                "start": {"input": float(self.phi[0]), "speed": float(self.omega[0]),
                          "kinetic_energy": float(self.kinetic_energy[0])},
                "end": {"input": float(self.phi[-1]), "speed": float(self.omega[-1]),
                        "kinetic_energy": float(self.kinetic_energy[-1])},
                "speed_min": float(self.omega.min()), "speed_max": float(self.omega.max())}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The input's rate against time (drawn into ``ax`` if given), then the input itself."""
        units = _units(self.linear)
        figure, axes = stacked_axes(ax, 2)
        plot_lines(axes[0], self.t, self.omega, [f"qd_{self.input} [Egorov, 6.50]"], "t (s)",
                   f"speed of {self.input} ({units['speed']})", f"{self.mechanism}: one-mass model")
        if len(axes) > 1:
            plot_lines(axes[1], self.t, self.phi, [self.input], "t (s)", f"{self.input} ({units['input']})")
        return figure

    def __str__(self) -> str:
        d, units = self.as_dict(), _units(self.linear)
        return (f"{self.mechanism}: one-mass model reduced to {self.input}, {d['duration']:.4g} s in {d['samples']} "
                f"samples\n" + text_table([{"": k, self.input: d[k]["input"], "speed": d[k]["speed"],
                                              "kinetic_energy": d[k]["kinetic_energy"]} for k in ("start", "end")])
                + f"\n(input {units['input']}, speed {units['speed']}, kinetic energy J); speed "
                f"{d['speed_min']:.6g} … {d['speed_max']:.6g} {units['speed']}")


def differential_form(mech: Mechanism, input: str, phi0: float, omega0: float, duration: float, dt: float = 1e-3,
                      *, actuation: Actuation | None = None, loads_at: LoadsAt | None = None) -> ReducedMotion:
    """Integrate J_пр ε + ½ (dJ_пр/dφ) ω² = M_пр [Egorov, 6.50] (ε from [Egorov, 6.52]) from φ0 (rad, m) at the
    rate ω0 (rad/s, m/s) for ``duration`` seconds with the step ``dt`` (s), by RK4
    (:func:`~mechatron.dynamics.integrate.rk4_step`).

    J_пр, dJ_пр/dφ and M_пр = Sᵀ(τ + Q − g) are evaluated on the mechanism at every stage (assembled from the
    previous stage's configuration). ``actuation`` and ``loads_at`` take (t, q, q̇) like
    :func:`~mechatron.dynamics.constrained.simulate`'s, so the one-mass model and the full simulation can be given
    the same forces.
    """
    input = _one_dof(mech, input)
    phi0 = number("phi0", phi0, minimum=-LARGEST, unit="rad or m")
    omega0 = number("omega0", omega0, minimum=-LARGEST, unit="rad/s or m/s")
    duration = number("duration", duration, positive=True, unit="s")
    dt = number("dt", dt, positive=True, unit="s")
    state = {"q": assemble(mech, {input: phi0}) if mech.closures else _serial_q(mech, input, phi0, None)}
    solver = loop_solver(mech) if mech.closures else None

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
        v = S * omega
        applied = generalized_forces(mech, q, actuation(t, q, v) if actuation else None,
                                     loads_at(t, q, v) if loads_at else None)
        inertia, d_inertia, moment = _terms(mech, q, S, S2, applied)
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
    times, angles, speeds, epsilon, inertia, moment = (np.array(column) for column in zip(*rows))
    return ReducedMotion(times, angles, speeds, epsilon, inertia, moment, input=input,
                         linear=mech.joint_kind(input) == "prismatic", mechanism=mech.name)


# ------------------------------------------------------------------------------------------ motion regimes
@dataclass(frozen=True)
class Cycle:
    """One cycle of the input: times (s), speeds at its ends, mean, least and largest (rad/s or m/s), the
    coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean and the regime ("run-up", "steady", "run-down")."""

    cycle: int
    t_start: float
    t_end: float
    omega_start: float
    omega_end: float
    omega_mean: float
    omega_min: float
    omega_max: float
    fluctuation: float
    regime: str


@dataclass(eq=False)
class MotionRegimes(Result):
    """The cycles of a motion and their regimes [Egorov, section 6.7]; ``unit`` is the input's (rad or m)."""

    cycles: list[Cycle] = field(default_factory=list)
    unit: str = "rad"

    @property
    def regimes(self) -> list[str]:
        """The regime of every cycle, in order."""
        return [c.regime for c in self.cycles]

    def to_frame(self) -> pd.DataFrame:
        """One row per cycle: cycle, t_start, t_end (s), omega_start, omega_end, omega_mean, omega_min, omega_max
        (rad/s or m/s), fluctuation (δ, 1), regime."""
        import pandas as pd

        return pd.DataFrame([vars(c) for c in self.cycles], columns=list(Cycle.__dataclass_fields__))

    def as_dict(self) -> dict:
        """unit (of the input), cycles: one dict per cycle with the columns of :meth:`to_frame`."""
        return {"unit": self.unit, "cycles": [vars(c) for c in self.cycles]}

    def plot(self, ax: Axes | None = None) -> Figure:
        """Mean speed of every cycle at its middle time, with its least and largest speed as an error bar, one
        colour per regime."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax)
        colours = {"run-up": "tab:orange", "steady": "tab:green", "run-down": "tab:blue"}
        for regime, colour in colours.items():
            chosen = [c for c in self.cycles if c.regime == regime]
            if chosen:
                middle = [(c.t_start + c.t_end) / 2 for c in chosen]
                mean = np.array([c.omega_mean for c in chosen])
                spread = np.array([[c.omega_mean - c.omega_min for c in chosen],
                                   [c.omega_max - c.omega_mean for c in chosen]])
                ax.errorbar(middle, mean, yerr=spread, fmt="o", color=colour, capsize=3, label=regime)
        style_axes(ax, "t (s)", f"mean speed of a cycle, least to largest ({self.unit}/s)",
                   "motion regimes [Egorov, section 6.7]", legend=True)
        return figure

    def __str__(self) -> str:
        return (f"{len(self.cycles)} cycle(s) of the input (speeds in {self.unit}/s, times in s; fluctuation "
                "δ = (ω_max − ω_min)/ω_mean):\n" + text_table([vars(c) for c in self.cycles]))


def motion_regimes(t: ArrayLike, phi: ArrayLike, omega: ArrayLike, period: float = 2 * math.pi,
                   tolerance: float = 1e-3, unit: str = "rad") -> MotionRegimes:
    """Split a motion (times t in s, input φ in ``unit``, its rate ω) into cycles of the input (each ``period`` of
    φ from the start) and name each one's regime [Egorov, section 6.7]; if the input turns back, the cycles end
    there. Over a cycle the mechanism returns to the same position, so J_пр is the same at both ends and the work of
    all forces ΣA = ½ J_пр (ω_end² − ω_start²) [Egorov, 6.53]: ``run-up`` if the speed at the end of the cycle is
    higher by more than ``tolerance`` (relative), ``run-down`` if lower, ``steady`` otherwise. Each cycle also gets
    its mean speed and coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean."""
    t, phi, omega = (np.asarray(x, dtype=float) for x in (t, phi, omega))
    travel = (phi - phi[0]) * np.sign(phi[-1] - phi[0] or 1.0)
    backwards = np.flatnonzero(np.diff(travel) < 0)
    if len(backwards):  # the input stopped and turned back: only the motion before that is in cycles
        last = int(backwards[0]) + 1
        t, travel, omega = t[:last], travel[:last], omega[:last]
    cycles = []
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
        cycles.append(Cycle(k, float(t_start), float(t_end), float(w_start), float(w_end), mean, float(w.min()),
                            float(w.max()), float((w.max() - w.min()) / abs(mean)), regime))
    return MotionRegimes(cycles, unit)

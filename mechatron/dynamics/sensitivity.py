r"""Exact first derivatives of positions, velocities, accelerations and actuator forces with respect to the named
geometric parameters of a mechanism (lengths, pin coordinates, DH parameters), by the implicit-function theorem.

A parameter l_k moves the constant placements of the Pinocchio model and the mass properties of its bodies; to first
order (:func:`~mechatron.model.derivatives.placement_derivatives`) every joint or frame placement turns into
M₀ exp(Σ_k ξ_k δ_k) and every body's dynamic parameters into π₀ + Σ_k ∂π/∂l_k δ_k, with δ = l − l₀. The model is
written out in CasADi ``SX`` (:mod:`mechatron.model.symbolic`) with symbolic coordinates q, rates q̇, accelerations
q̈ and deviations δ; only first derivatives at δ = 0 are taken, for which the first-order placements are exact.

**Expressions** (world axes, SI units):

- frame origins p_f(q, δ), their velocities and classical accelerations

  .. math:: v_f = \frac{∂p_f}{∂q}\dot q, \qquad a_f = \frac{∂p_f}{∂q}\ddot q + \Big(\frac{∂}{∂q}\frac{∂p_f}{∂q}
            \dot q\Big)\dot q ;

- the closures Φ(q, δ) = 0 (pins, sliders, gears, points on a curve given as a piecewise cubic) and their first
  and second time derivatives c₁ = Φ_q q̇ = 0, c₂ = Φ_q q̈ + (Φ_q q̇)_q q̇ = 0;
- the inverse dynamics of the tree, by virtual power over the bodies b (origin p_b, angular velocity
  ω_b = Σ_{revolute j ≤ b} z_j q̇_j, mass m, first moment h = R_b (m c), inertia I_O = R_b I Rᵀ_b about the origin, all
  three linear in π):

  .. math::

      f_b = m (a_b − g) + α_b × h + ω_b × (ω_b × h), \qquad
      n_b = I_O α_b + ω_b × I_O ω_b + h × (a_b − g),

      τ = \mathrm{diag}(J_r) \ddot q + Σ_b \Big[\Big(\frac{∂p_b}{∂q}\Big)^T f_b + \Big(\frac{∂ω_b}{∂\dot q}\Big)^T
      n_b\Big] − Σ_f J_f^T \begin{bmatrix}F_f \\ M_f\end{bmatrix},

  (the Newton–Euler equations about the body origin, the same as m (a_c − g) and I_c α + ω × I_c ω about the centre
  of mass; J_r the drives' armature; F_f, M_f external loads at frames) — Pinocchio's RNEA minus the loads'
  generalized forces.

**Nominal values** at an assembled q (Φ = 0) and actuated rates q̇_a and accelerations q̈_a: with the coordinates
split as :class:`~mechatron.kinematics.loops.LoopSolver` splits them (actuated a, dependent d),
S = [I; −Φ_d⁻¹ Φ_a], q̇ = S q̇_a, q̈ = S q̈_a − [0; Φ_d⁻¹ (Φ_q q̇)_q q̇], and the actuator forces

.. math:: τ_a = S^T τ(q, \dot q, \ddot q), \qquad λ = Φ_d^{-T} τ_d ,

which is the solution of mechatron's constrained inverse dynamics [B Φ_qᵀ][τ_a; λ] = τ (virtual work: the closure
forces Φ_qᵀλ do no work along S). A serial arm has no closures: every coordinate is an input, S = I.

**Total derivatives** at δ = 0, the actuated q_a, q̇_a, q̈_a held (implicit-function theorem on Φ, c₁ and c₂, each
derivative the exact CasADi Jacobian ∂/∂q, ∂/∂q̇, ∂/∂q̈, ∂/∂δ at the nominal state, the dependent rows only):

.. math::

    \frac{dq_d}{dδ} = −Φ_d^{-1} Φ_δ, \qquad
    \frac{d\dot q_d}{dδ} = −Φ_d^{-1}\Big(\frac{∂c_1}{∂q}\frac{dq}{dδ} + \frac{∂c_1}{∂δ}\Big), \qquad
    \frac{d\ddot q_d}{dδ} = −Φ_d^{-1}\Big(\frac{∂c_2}{∂q}\frac{dq}{dδ} + \frac{∂c_2}{∂\dot q}\frac{d\dot q}{dδ}
    + \frac{∂c_2}{∂δ}\Big),

    \frac{dy}{dδ} = \frac{∂y}{∂q}\frac{dq}{dδ} + \frac{∂y}{∂\dot q}\frac{d\dot q}{dδ}
    + \frac{∂y}{∂\ddot q}\frac{d\ddot q}{dδ} + \frac{∂y}{∂δ} \quad (y = p_f, v_f, a_f),

    \frac{dτ_a}{dδ} = S^T\Big(\frac{dτ}{dδ} − \frac{∂(Φ_q^T λ)}{∂q}\frac{dq}{dδ} − \frac{∂(Φ_q^T λ)}{∂δ}\Big)

(the last from differentiating B τ_a + Φ_qᵀ λ = τ and multiplying by Sᵀ, which removes dλ). No finite difference of
the analysis is taken here: the placement twists ξ, the inertia derivatives and the few closure constants a parameter
may move (a locked slider's angle offset, a gear's offset) come from
:func:`~mechatron.model.derivatives.placement_derivatives`.

The CasADi functions are built once per mechanism, parameter list, frame list and load frames (kept in the
mechanism's cache) and mapped over the N configurations (``Function.map``); the linear solves run in NumPy.
Mechanisms with joints other than one-axis revolute or prismatic ones, or with a closure that has no symbolic form
(a curve given only as a Python function), are refused with an :class:`~mechatron.errors.InputError` that names
what is unsupported.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, SingularityError
from ..kinematics.loops import SINGULAR_RATIO, loop_solver
from ..model.derivatives import placement_derivatives
from ..model.loads import Loads, as_loads
from ..model.mechanism import Mechanism, unknown_name_error
from ..model.symbolic import Unsupported, closure_residual, frame_placements, joint_placements, joint_tree
from ..report.result import Result
from .series import text_table

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

Array = NDArray[np.float64]

#: A configuration counts as assembled when every closure residual is below this (m, rad).
ASSEMBLED = 1e-8


# ------------------------------------------------------------------------------------------------ the kernel
class _Kernel:
    """The CasADi functions of one mechanism, parameter list, frame list and list of load frames:

    - ``closure``: q → (Φ, Φ_q) at δ = 0;
    - ``state``: (q, q̇, W) → (c₂ at q̈ = 0, i.e. (Φ_q q̇)_q q̇; τ at q̈ = 0; ∂τ/∂q̈ = M + diag(J_r));
    - ``derivatives``: (q, q̇, q̈, λ, W) → (y = [p_f; v_f; a_f], the Jacobian of [Φ; c₁; c₂; y; τ; Φ_qᵀλ] with
      respect to [q; q̇; q̈; δ]) at δ = 0;

    W (6, n_loads) holds the loads' world forces and moments at ``load_frames``."""

    def __init__(self, mech: Mechanism, parameters: tuple[str, ...], frames: tuple[str, ...],
                 load_frames: tuple[str, ...]) -> None:
        import casadi as ca

        model = mech.model
        tree = joint_tree(model)
        if model.nq != model.nv:
            raise Unsupported("joints with more than one coordinate")
        derivatives = placement_derivatives(mech, parameters)
        nq, n_l = model.nq, len(parameters)
        q, qd, qdd = ca.SX.sym("q", nq), ca.SX.sym("qd", nq), ca.SX.sym("qdd", nq)
        delta = ca.SX.sym("delta", n_l)
        state, motion = ca.vertcat(q, qd), ca.vertcat(qd, qdd)

        def linear(rows: np.ndarray):
            """Σ_k rows[k] δ_k (SX column) over the parameters that move it; None if none does."""
            used = [k for k in range(n_l) if np.any(rows[k] != 0.0)]
            if not used:
                return None
            return ca.mtimes(ca.DM(np.asarray(rows[used], dtype=float).T), ca.vertcat(*[delta[k] for k in used]))

        def twist(rows: np.ndarray):
            xi = linear(rows)
            return None if xi is None else (xi[:3], xi[3:])

        def rate(x):  # d/dt of an expression of q
            return ca.jtimes(x, q, qd)

        def second(x):  # d/dt of an expression of (q, q̇)
            return ca.jtimes(x, state, motion)

        joints = joint_placements(model, q, [None] + [twist(derivatives.joints[:, j]) for j in
                                                      range(1, model.njoints)])
        omega = [ca.SX.zeros(3, 1)]  # ω_i = ω_λ + z_i q̇_i (revolute), z_i = R_i â_i
        for i in range(1, model.njoints):
            w = omega[tree.parent[i]]
            if tree.revolute[i]:
                w = w + ca.mtimes(joints[i][0], ca.DM(tree.axis[i].reshape(3, 1))) * qd[int(tree.column[i])]
            omega.append(w)

        solver = loop_solver(mech) if mech.closures else None
        closing = list(solver.system.frame_names) if solver is not None else []
        names = list(dict.fromkeys([*frames, *closing, *load_frames]))
        ids = [mech.frame_id(n) for n in names]
        frame_twists = {f: twist(derivatives.frames[:, f]) for f in ids}
        placements = dict(zip(names, frame_placements(model, ids, q, frame_twists, joints)))

        # outputs: frame origins, velocities, classical accelerations
        outputs = []
        for name in frames:
            p = placements[name][1]
            v = rate(p)
            outputs += [p, v, second(v)]
        y = ca.vertcat(*outputs) if outputs else ca.SX.zeros(0, 1)

        # inverse dynamics by virtual power, bodies about their origins (π linear in δ), minus the loads
        gravity = ca.DM(model.gravity.linear.reshape(3, 1))
        tau = ca.mtimes(ca.DM(np.diag(np.asarray(model.armature, dtype=float))), qdd)
        for j in range(1, model.njoints):
            pi0 = np.asarray(model.inertias[j].toDynamicParameters(), dtype=float)
            change = linear(derivatives.inertias[:, j])
            if change is None and not np.any(pi0):
                continue
            pi = ca.DM(pi0.reshape(10, 1)) + (0 if change is None else change)
            R, p = joints[j]
            m, h = pi[0], ca.mtimes(R, pi[1:4])
            inertia = ca.vertcat(ca.horzcat(pi[4], pi[5], pi[7]), ca.horzcat(pi[5], pi[6], pi[8]),
                                 ca.horzcat(pi[7], pi[8], pi[9]))
            inertia = ca.mtimes(ca.mtimes(R, inertia), R.T)
            v, w = rate(p), omega[j]
            a, alpha = second(v), second(w)
            f = m * (a - gravity) + ca.cross(alpha, h) + ca.cross(w, ca.cross(w, h))
            n = ca.mtimes(inertia, alpha) + ca.cross(w, ca.mtimes(inertia, w)) + ca.cross(h, a - gravity)
            tau = tau + ca.mtimes(ca.jacobian(p, q).T, f) + ca.mtimes(ca.jacobian(w, qd).T, n)
        wrenches = ca.SX.sym("wrenches", 6, len(load_frames))
        for k, name in enumerate(load_frames):
            joint = model.frames[mech.frame_id(name)].parentJoint
            tau = tau - ca.mtimes(ca.jacobian(placements[name][1], q).T, wrenches[:3, k]) \
                - ca.mtimes(ca.jacobian(omega[joint], qd).T, wrenches[3:, k])

        # closures and their time derivatives
        if solver is not None:
            constants = {name: {constant: linear(rows[:, None]) for constant, rows in changes.items()}
                         for name, changes in derivatives.constants.items()}
            phi = closure_residual(solver.system, {n: placements[n] for n in closing}, q, curves=True,
                                   constants=constants)
        else:
            phi = ca.SX.zeros(0, 1)
        m_rows = phi.shape[0]
        c1 = rate(phi)
        c2 = second(c1)
        lam = ca.SX.sym("lam", m_rows)
        reaction = ca.jtimes(phi, q, lam, True) if m_rows else ca.SX.zeros(nq, 1)  # Φ_qᵀ λ

        zero = ca.DM.zeros(n_l, 1)

        def nominal(*expressions):
            return [ca.cse(ca.substitute(e, delta, zero)) for e in expressions]

        self.closure = ca.Function("closure", [q], nominal(phi, ca.jacobian(phi, q)))
        no_acceleration = [ca.substitute(e, qdd, ca.DM.zeros(nq, 1)) for e in (c2, tau)]
        self.state = ca.Function("state", [q, qd, wrenches],
                                 nominal(*no_acceleration, ca.jacobian(tau, qdd)))
        stacked = ca.vertcat(phi, c1, c2, y, tau, reaction)
        self.derivatives = ca.Function("derivatives", [q, qd, qdd, lam, wrenches],
                                       nominal(y, ca.jacobian(stacked, ca.vertcat(q, qd, qdd, delta))))
        self.nq, self.n_l, self.m, self.ny = nq, n_l, m_rows, y.shape[0]
        self._mapped: dict = {}

    def evaluate(self, function, *arrays: np.ndarray) -> list[np.ndarray]:
        """``function`` at N samples: each argument (N, rows, cols) or (N, rows); each output (N, rows, cols)."""
        n = len(arrays[0])
        key = (function.name(), n)
        if key not in self._mapped:
            self._mapped[key] = function.map(n) if n > 1 else function
        columns = []
        for x in arrays:  # sample i's (rows, cols) block goes to columns i·cols … (i + 1)·cols − 1
            x = np.asarray(x, dtype=float)
            x = x.reshape(n, x.shape[1], x.shape[2] if x.ndim == 3 else 1)
            columns.append(np.ascontiguousarray(x.transpose(1, 0, 2).reshape(x.shape[1], n * x.shape[2])))
        out = self._mapped[key].call(columns)
        results = []
        for k, value in enumerate(out):
            rows, cols = function.size_out(k)
            results.append(np.asarray(value, dtype=float).reshape(rows, n, cols).transpose(1, 0, 2))
        return results


def _kernel(mech: Mechanism, parameters: tuple[str, ...], frames: tuple[str, ...], load_frames: tuple[str, ...]
            ) -> _Kernel:
    """The :class:`_Kernel` of these lists, built once (kept in the mechanism's cache)."""
    def build() -> _Kernel:
        try:
            return _Kernel(mech, parameters, frames, load_frames)
        except Unsupported as exc:
            raise InputError(f"{mech.name}: exact parameter sensitivities are not available: {exc} (they need "
                             "revolute or prismatic joints about one fixed axis and closures that are pins, sliders, "
                             "gears or curves given as piecewise polynomials)") from None

    return mech.cached(("dynamics.parameter_sensitivities", parameters, frames, load_frames), build)


# ------------------------------------------------------------------------------------------------ the result
@dataclass(frozen=True, eq=False)
class ParameterSensitivities(Result):
    """Nominal values and exact derivatives with respect to the named parameters at N configurations.

    Attributes:
        mechanism: Name of the mechanism.
        parameters: The parameters l (columns of every derivative); ``parameter_units`` their units ("m", "rad",
            "-") and ``parameter_values`` their nominal values.
        frames: The frames whose origins are reported; ``axes`` the world axes reported ("xy" for a planar
            linkage, else "xyz").
        inputs: The actuated coordinates (every joint of a serial arm): their rates, accelerations and forces;
            ``angular`` which of them are angles (force in N·m) or lengths (N).
        q: Configurations (N, nq); ``rates`` and ``accelerations`` (N, n_inputs) the actuated rates (rad/s, m/s) and
            accelerations (rad/s², m/s²).
        position, velocity, acceleration: Frame origins (N, n_frames, 3) in m, m/s, m/s² (world axes).
        force: Actuator forces (N, n_inputs): N for a linear input, N·m for an angular one.
        d_position, d_velocity, d_acceleration: ∂/∂l (N, n_frames, 3, n_l): m, m/s, m/s² per unit of l.
        d_force: ∂(force)/∂l (N, n_inputs, n_l): N or N·m per unit of l.
        d_q: ∂q/∂l (N, nq, n_l) with the inputs held: how the dependent coordinates move to keep the loops closed
            (rad or m per unit of l; zero rows for the inputs and for every joint of a serial arm).
    """

    mechanism: str
    parameters: tuple[str, ...]
    parameter_units: tuple[str, ...]
    parameter_values: Array
    frames: tuple[str, ...]
    axes: str
    inputs: tuple[str, ...]
    angular: tuple[bool, ...]
    q: Array
    rates: Array
    accelerations: Array
    position: Array
    velocity: Array
    acceleration: Array
    force: Array
    d_position: Array
    d_velocity: Array
    d_acceleration: Array
    d_force: Array
    d_q: Array

    @property
    def samples(self) -> int:
        """Number of configurations N."""
        return len(self.q)

    def force_unit(self, k: int) -> str:
        return "N·m" if self.angular[k] else "N"

    def outputs(self) -> list[tuple[str, str, str, Array, Array]]:
        """Every reported output as (label, quantity, unit, nominal (N,), derivative (N, n_l)): per frame and axis
        ``<frame>_x`` (position, m), ``<frame>_vx`` (velocity, m/s), ``<frame>_ax`` (acceleration, m/s²); per input
        ``force_<input>`` (N or N·m)."""
        out = []
        for quantity, prefix, unit, value, derivative in (
                ("position", "", "m", self.position, self.d_position),
                ("velocity", "v", "m/s", self.velocity, self.d_velocity),
                ("acceleration", "a", "m/s²", self.acceleration, self.d_acceleration)):
            for i, frame in enumerate(self.frames):
                for axis in self.axes:
                    k = "xyz".index(axis)
                    out.append((f"{frame}_{prefix}{axis}", quantity, unit, value[:, i, k], derivative[:, i, k]))
        for k, name in enumerate(self.inputs):
            out.append((f"force_{name}", "force", self.force_unit(k), self.force[:, k], self.d_force[:, k]))
        return out

    def derivative(self, output: str, parameter: str) -> Array:
        """∂(output)/∂(parameter) (N,) by the labels of :meth:`outputs` and a parameter's name."""
        for label, _, _, _, derivative in self.outputs():
            if label == output:
                if parameter not in self.parameters:
                    raise unknown_name_error("parameter", parameter, list(self.parameters))
                return derivative[:, self.parameters.index(parameter)]
        raise unknown_name_error("output", output, [o[0] for o in self.outputs()])

    def to_frame(self) -> pd.DataFrame:
        """One row per configuration and output: ``sample``, ``output`` (label of :meth:`outputs`), ``quantity``,
        ``unit``, ``value`` (the nominal value) and one column ``d_<parameter>`` per parameter (the output's unit per
        m of a length, per rad of an angle)."""
        import pandas as pd

        rows = []
        for i in range(self.samples):
            for label, quantity, unit, value, derivative in self.outputs():
                rows.append({"sample": i, "output": label, "quantity": quantity, "unit": unit,
                             "value": float(value[i]),
                             **{f"d_{p}": float(derivative[i, k]) for k, p in enumerate(self.parameters)}})
        return pd.DataFrame(rows, columns=["sample", "output", "quantity", "unit", "value",
                                           *(f"d_{p}" for p in self.parameters)])

    def as_dict(self) -> dict:
        """mechanism; parameters (name, unit, nominal value); frames; inputs (name, force unit); per configuration
        its q, the inputs' rates and accelerations and every output's value, unit and derivatives {parameter:
        value} (the output's unit per unit of the parameter)."""
        outputs = self.outputs()
        return {"mechanism": self.mechanism,
                "parameters": [{"name": p, "unit": u, "value": float(v)} for p, u, v in
                               zip(self.parameters, self.parameter_units, self.parameter_values)],
                "frames": list(self.frames), "axes": self.axes,
                "inputs": [{"name": n, "force_unit": self.force_unit(k)} for k, n in enumerate(self.inputs)],
                "samples": [{"q": self.q[i].tolist(),
                             "rates": dict(zip(self.inputs, self.rates[i].tolist())),
                             "accelerations": dict(zip(self.inputs, self.accelerations[i].tolist())),
                             "outputs": {label: {"quantity": quantity, "unit": unit, "value": float(value[i]),
                                                 "derivatives": dict(zip(self.parameters,
                                                                         derivative[i].tolist()))}
                                         for label, quantity, unit, value, derivative in outputs}}
                            for i in range(self.samples)]}

    def _default_output(self) -> str:
        """The largest actuator force if any force is not zero, else the position coordinate most sensitive."""
        outputs = self.outputs()
        forces = [o for o in outputs if o[1] == "force"]
        if forces and max(float(np.abs(o[3]).max(initial=0.0)) for o in forces) > 0.0:
            return max(forces, key=lambda o: float(np.abs(o[3]).max(initial=0.0)))[0]
        positions = [o for o in outputs if o[1] == "position"] or outputs
        return max(positions, key=lambda o: float(np.abs(o[4]).max(initial=0.0)))[0]

    def plot(self, ax: Axes | None = None, output: str | None = None, sample: int | None = None) -> Figure:
        """A bar chart of ∂(output)/∂l for every parameter l at one configuration: ``output`` (a label of
        :meth:`outputs`; default the largest actuator force, or the most sensitive position coordinate when the
        forces are zero) at ``sample`` (default the configuration where that output's derivatives are largest)."""
        from ..report.figures import figure_axes, style_axes

        output = output or self._default_output()
        found = [o for o in self.outputs() if o[0] == output]
        if not found:
            raise unknown_name_error("output", output, [o[0] for o in self.outputs()])
        label, quantity, unit, value, derivative = found[0]
        if sample is None:
            sample = int(np.argmax(np.abs(derivative).max(axis=1, initial=0.0))) if self.samples else 0
        figure, ax = figure_axes(ax, 8.0, max(3.0, 0.28 * len(self.parameters) + 1.2))
        positions = np.arange(len(self.parameters))
        values = derivative[sample] if len(self.parameters) else np.zeros(0)
        ax.barh(positions, values, color=["tab:blue" if u == "m" else "tab:orange" for u in self.parameter_units])
        ax.set_yticks(positions, [f"{p} ({u})" for p, u in zip(self.parameters, self.parameter_units)])
        ax.invert_yaxis()
        ax.axvline(0.0, color="0.3", linewidth=0.8)
        units = sorted(set(self.parameter_units), key=["m", "rad", "-"].index)
        per = ", ".join(f"{unit}/{u}" if u != "-" else unit for u in units)
        style_axes(ax, f"∂{label}/∂l ({per})", "parameter l (unit)",
                   f"{self.mechanism}: ∂{label}/∂l at configuration {sample} ({quantity} {label} = "
                   f"{value[sample]:.6g} {unit})")
        return figure

    def __str__(self) -> str:
        outputs = self.outputs()
        n = self.samples
        head = (f"{self.mechanism}: exact sensitivities to {len(self.parameters)} parameters at {n} "
                f"configuration{'s' if n != 1 else ''} (frames {', '.join(self.frames) or '-'}; inputs "
                f"{', '.join(self.inputs)})")
        labels = [o[0] for o in outputs]
        if n == 1:
            rates = ", ".join(f"{name} {self.rates[0, k]:.6g}" for k, name in enumerate(self.inputs))
            nominal = [{"output": label, "unit": unit, "value": float(value[0])}
                       for label, _, unit, value, _ in outputs]
            title = "∂(output)/∂(parameter), the output's unit per unit of the parameter:"
            table = [{"parameter": p, "unit": u, **{label: float(o[4][0, k]) for label, o in zip(labels, outputs)}}
                     for k, (p, u) in enumerate(zip(self.parameters, self.parameter_units))]
            parts = [head, f"input rates (rad/s, m/s): {rates}", "nominal values:", text_table(nominal)]
        else:
            nominal = [{"output": label, "unit": unit, "min": float(value.min()), "max": float(value.max())}
                       for label, _, unit, value, _ in outputs]
            title = (f"largest |∂(output)/∂(parameter)| over the {n} configurations, the output's unit per unit of "
                     "the parameter:")
            table = [{"parameter": p, "unit": u,
                      **{label: float(np.abs(o[4][:, k]).max()) for label, o in zip(labels, outputs)}}
                     for k, (p, u) in enumerate(zip(self.parameters, self.parameter_units))]
            parts = [head, "nominal values over the configurations:", text_table(nominal)]
        return "\n".join(parts + [title, text_table(table, digits=4),
                                  "(positions m, velocities m/s, accelerations m/s², forces N or N·m; "
                                  "parameters m or rad)"])


# ------------------------------------------------------------------------------------------------ the call
def _inverses(matrices: Array) -> Array:
    """The inverses of (N, n, n) matrices; inf for the singular ones."""
    try:
        return np.asarray(np.linalg.inv(matrices), dtype=float)
    except np.linalg.LinAlgError:
        out = np.full_like(matrices, np.inf)
        for i, matrix in enumerate(matrices):
            try:
                out[i] = np.linalg.inv(matrix)
            except np.linalg.LinAlgError:
                pass
        return out


def _per_sample(values: Mapping[str, float] | ArrayLike | None, inputs: list[str], n: int, what: str) -> Array:
    """(N, n_inputs) from None (zeros), {input name: value} (missing ones 0) or an array (n_inputs,) or
    (N, n_inputs)."""
    if values is None:
        return np.zeros((n, len(inputs)))
    if isinstance(values, Mapping):
        row = np.zeros(len(inputs))
        for name, value in values.items():
            if name not in inputs:
                raise unknown_name_error(f"input whose {what} is given", name, inputs)
            if isinstance(value, bool) or not np.isfinite(value):
                raise InputError(f"the {what} of {name} must be a finite number, got {value!r}")
            row[inputs.index(name)] = float(value)
        return np.tile(row, (n, 1))
    array = np.asarray(values, dtype=float)
    if array.ndim == 1:
        array = np.tile(array, (n, 1))
    if array.shape != (n, len(inputs)) or not np.all(np.isfinite(array)):
        raise InputError(f"{what} must be {len(inputs)} finite values ({', '.join(inputs)}) per configuration, "
                         f"got shape {np.shape(values)}")
    return array


def parameter_sensitivities(mech: Mechanism, q: ArrayLike, *, rates: Mapping[str, float] | ArrayLike | None = None,
                            accelerations: Mapping[str, float] | ArrayLike | None = None,
                            frames: str | Sequence[str] | None = None, parameters: Sequence[str] | None = None,
                            loads: Loads = None) -> ParameterSensitivities:
    r"""Exact derivatives of frame positions, velocities, accelerations and actuator forces with respect to the
    named parameters (see the module docstring for the equations), at one or N configurations.

    Args:
        q: Assembled configurations, (nq,) or (N, nq) (rad, m).
        rates: The inputs' rates (rad/s, m/s): {input: value} (missing ones 0), (n_inputs,) or (N, n_inputs);
            default 0 (at rest). The inputs are the actuated coordinates, every joint of a serial arm.
        accelerations: The inputs' accelerations (rad/s², m/s²), the same forms; default 0.
        frames: The frames whose origins are reported (default the tool frame).
        parameters: The parameters l (default every one of the mechanism).
        loads: External loads (:class:`~mechatron.model.loads.Load` s: world forces, N, and moments, N·m, at frame
            origins), the same at every configuration; gravity is the model's.

    Returns:
        :class:`ParameterSensitivities`: m, m/s, m/s² and N or N·m per m of a length parameter or per rad of an angle.

    Raises:
        InputError: for unknown names, a configuration that is not assembled, or a mechanism with joints or
            closures that have no symbolic form (named).
        SingularityError: at a singular position (the inputs do not determine the motion).
    """
    Q = np.atleast_2d(np.asarray(q, dtype=float))
    if Q.ndim != 2 or Q.shape[1] != mech.nq or not np.all(np.isfinite(Q)):
        raise InputError(f"configurations of {mech.name} need {mech.nq} finite values each, got shape "
                         f"{np.shape(q)}")
    n = len(Q)
    frames = (mech.tool_frame,) if frames is None else (frames,) if isinstance(frames, str) else tuple(frames)
    for name in frames:
        mech.frame_id(name)
    parameters = tuple(mech.parameters) if parameters is None else tuple(parameters)
    for name in parameters:
        if name not in mech.parameters:
            raise unknown_name_error(f"parameter of {mech.name}", name, list(mech.parameters))
    applied: dict[str, Array] = {}
    for load in as_loads(loads):
        mech.frame_id(load.frame)
        applied[load.frame] = applied.get(load.frame, np.zeros(6)) + np.concatenate([load.force, load.moment])
    load_frames = tuple(applied)
    W = np.tile(np.array([applied[f] for f in load_frames]).T.reshape(6, len(load_frames)), (n, 1, 1))

    inputs = list(mech.actuated) if mech.closures else mech.joint_names
    U = _per_sample(rates, inputs, n, "rates")
    A = _per_sample(accelerations, inputs, n, "accelerations")
    kernel = _kernel(mech, parameters, frames, load_frames)
    nq, n_l, m = kernel.nq, kernel.n_l, kernel.m
    if mech.closures:
        solver = loop_solver(mech)
        act, dep = [int(i) for i in solver.act], [int(i) for i in solver.dep]
    else:
        act, dep = [mech.model.joints[mech.joint_id(name)].idx_v for name in inputs], []
    if len(dep) != m:
        raise InputError(f"{mech.name}: exact parameter sensitivities need closures that determine the dependent "
                         f"coordinates one to one ({m} closure equations for {len(dep)} dependent coordinates)")

    S = np.zeros((n, nq, len(act)))
    S[:, act, np.arange(len(act))] = 1.0
    D = np.zeros((n, len(dep), len(dep)))
    if m:
        phi, Jq = kernel.evaluate(kernel.closure, Q)
        residual = np.abs(phi[:, :, 0]).max(axis=1)
        if np.any(residual > ASSEMBLED):
            i = int(np.argmax(residual))
            raise InputError(f"{mech.name}: configuration {i} is not assembled (closure residual {residual[i]:.3g}); "
                             "assemble it first (mechatron.assemble)")
        D = _inverses(Jq[:, :, dep])
        ratio = np.nan_to_num(np.abs(D).reshape(n, -1).max(axis=1), nan=np.inf)
        if np.any(ratio > SINGULAR_RATIO):
            i = int(np.argmax(ratio))
            values = {name: float(Q[i, j]) for name, j in zip(inputs, act)}
            raise SingularityError(f"{mech.name} is at a singular position in configuration {i} "
                                   f"({', '.join(f'{k} = {v:.6g}' for k, v in values.items())}): the actuated "
                                   "coordinates do not determine the motion", inputs=values, ratio=float(ratio[i]))
        S[:, dep] = -D @ Jq[:, :, act]
    V = S @ U[:, :, None]  # (N, nq, 1)
    gamma, tau0, M = kernel.evaluate(kernel.state, Q, V, W)
    Acc = S @ A[:, :, None]
    if m:
        Acc[:, dep] -= D @ gamma
    tau = tau0 + M @ Acc
    lam = np.swapaxes(D, 1, 2) @ tau[:, dep] if m else np.zeros((n, 0, 1))
    force = (np.swapaxes(S, 1, 2) @ tau)[:, :, 0]
    y, J = kernel.evaluate(kernel.derivatives, Q, V, Acc, lam, W)

    # the blocks of J: rows [Φ; c₁; c₂; y; τ; Φ_qᵀλ], columns [q; q̇; q̈; δ]
    rows = np.cumsum([0, m, m, m, kernel.ny, nq, nq])
    cols = np.cumsum([0, nq, nq, nq, n_l])

    def block(r: int, c: int) -> Array:
        return J[:, rows[r]:rows[r + 1], cols[c]:cols[c + 1]]

    dq, dqd, dqdd = (np.zeros((n, nq, n_l)) for _ in range(3))
    if m:
        dq[:, dep] = -D @ block(0, 3)
        dqd[:, dep] = -D @ (block(1, 0) @ dq + block(1, 3))
        dqdd[:, dep] = -D @ (block(2, 0) @ dq + block(2, 1) @ dqd + block(2, 3))
    dy = block(3, 0) @ dq + block(3, 1) @ dqd + block(3, 2) @ dqdd + block(3, 3)
    dtau = block(4, 0) @ dq + block(4, 1) @ dqd + block(4, 2) @ dqdd + block(4, 3)
    dtau -= block(5, 0) @ dq + block(5, 3)
    dforce = np.swapaxes(S, 1, 2) @ dtau

    nf = len(frames)
    frame_values = y[:, :, 0].reshape(n, nf, 3, 3)  # frame, quantity (p, v, a), axis
    dy = dy.reshape(n, nf, 3, 3, n_l)
    spatial = not mech.closures or any(not getattr(c, "planar", True) for c in mech.closures)
    return ParameterSensitivities(
        mech.name, parameters, tuple(mech.parameters[p].unit for p in parameters),
        np.array([mech.parameters[p].value for p in parameters], dtype=float), frames, "xyz" if spatial else "xy",
        tuple(inputs), tuple(mech.joint_kind(name) == "revolute" for name in inputs), Q, U, A,
        frame_values[:, :, 0], frame_values[:, :, 1], frame_values[:, :, 2], force,
        dy[:, :, 0], dy[:, :, 1], dy[:, :, 2], dforce, dq)


__all__ = ["ASSEMBLED", "ParameterSensitivities", "parameter_sensitivities"]

r"""Closed-loop mechanisms: position analysis (assembly), velocity and acceleration analysis.

With the closure equations Φ(q) = 0 of a mechanism (see :mod:`mechatron.model.closures`) and its coordinates split into
actuated q_a (the inputs: crank angles, cylinder lengths) and dependent q_d:

- position analysis solves Φ(q_a, q_d) = 0 for q_d by Newton's method, starting from a named assembly branch or a
  previous solution, so that a sweep keeps its branch;
- velocity analysis: J_d q̇_d = −J_a q̇_a, i.e. q̇ = S q̇_a with S = [I; −J_d⁻¹ J_a];
- acceleration analysis: J_d q̈_d = −J_a q̈_a − J̇ q̇.

For a 1-DOF mechanism the columns of S are the first transfer functions ([Egorov, 4.2, 4.10]) of all coordinates
with respect to the input, and the accelerations at q̇_a = 1, q̈_a = 0 are the second transfer functions
([Egorov, 4.7, 4.15]).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, SingularityError, UnreachableError
from ..model.closures import ClosureSystem
from ..model.mechanism import Mechanism, unknown_name_error

#: A float array (coordinates, rates, Jacobians: m, rad and their rates).
Vector = NDArray[np.float64]

#: Newton stops when every closure residual is below this (m for positions, rad for angles).
TOLERANCE = 1e-10
#: An entry of J_d⁻¹ above this (a velocity ratio of 1e8) means the actuated coordinates no longer determine the
#: motion: a singular position.
SINGULAR_RATIO = 1e8


class LoopSolver:
    """Assembly, velocity and acceleration analysis of one mechanism (built once, reused for every sample)."""

    def __init__(self, mech: Mechanism, extra_frames: tuple[str, ...] | list[str] = ()) -> None:
        """``extra_frames`` are evaluated along with the closures' frames (positions and Jacobians in
        :meth:`newton`, velocities and q̈ = 0 accelerations in :meth:`analyse`), see ``system.states``."""
        model = mech.model
        if model.nq != model.nv:
            raise InputError(f"{mech.name}: closed-loop analysis needs joints with one coordinate each")
        self.mech = mech
        self.system = ClosureSystem(model, mech.closures, mech.frame_id, extra_frames)
        self.nrows = self.system.nrows
        names = mech.joint_names
        for name in mech.actuated:
            if name not in names:
                raise unknown_name_error(f"actuated coordinate of {mech.name}", name, names)
        self.index = {name: model.joints[model.getJointId(name)].idx_q for name in names}
        self.act = np.array([self.index[n] for n in mech.actuated], dtype=int)
        self.dep = np.array([i for i in range(model.nq) if i not in set(self.act)], dtype=int)
        self.lower = model.lowerPositionLimit.copy()
        self.upper = model.upperPositionLimit.copy()
        self.selection = np.zeros((model.nv, len(self.act)))  # S with only the actuated rows (the identity) filled
        self.selection[self.act, np.arange(len(self.act))] = 1.0

    # ------------------------------------------------------------------------------------------ helpers
    def _inputs(self, values: Mapping[str, float] | Vector, what: str) -> dict[int, float]:
        """Actuated values by coordinate index; only actuated names are accepted."""
        if isinstance(values, np.ndarray):
            if values.shape != (len(self.act),):
                raise InputError(f"{what} must have {len(self.act)} values ({', '.join(self.mech.actuated)})")
            return {int(i): float(x) for i, x in zip(self.act, values)}
        out = {}
        for name, value in values.items():
            if name not in self.mech.actuated:
                raise unknown_name_error(f"actuated coordinate of {self.mech.name}", name, self.mech.actuated)
            if isinstance(value, bool) or not math.isfinite(value):
                raise InputError(f"{what} {name} must be a finite number, got {value!r}")
            out[self.index[name]] = float(value)
        return out

    def rank(self, q: Vector) -> int:
        """Rank of the closure Jacobian at q."""
        _, J = self.system.evaluate(np.asarray(q, dtype=float))
        if J.size == 0:
            return 0
        return int(np.linalg.matrix_rank(J, tol=1e-9 * max(1.0, np.abs(J).max())))

    @staticmethod
    def solve(A: Vector, b: Vector) -> Vector:
        """A x = b (least squares if A is not square or is singular)."""
        if A.shape[0] == A.shape[1]:
            try:
                return np.asarray(np.linalg.solve(A, b), dtype=float)
            except np.linalg.LinAlgError:
                pass
        return np.asarray(np.linalg.lstsq(A, b, rcond=None)[0], dtype=float)

    def _input_values(self, q: Vector) -> dict[str, float]:
        return {n: float(q[self.index[n]]) for n in self.mech.actuated}

    def _describe_inputs(self, q: Vector) -> str:
        return ", ".join(f"{n} = {q[self.index[n]]:.6g}" for n in self.mech.actuated)

    # ------------------------------------------------------------------------------------------ position
    def assemble(self, inputs: Mapping[str, float] | Vector, guess: ArrayLike | None = None,
                 max_iterations: int = 50) -> Vector:
        """Solve the closures for the dependent coordinates with the actuated ones at ``inputs``.

        If ``guess`` (default: the reference configuration) is an assembled configuration, the inputs are moved from
        its values to ``inputs`` in small steps, each solved by Newton's method from a prediction along the
        velocity map: the solution is the one on the guess's assembly branch. Otherwise ``guess`` is taken as an
        approximate solution and Newton's method starts from it. Actuated coordinates not in ``inputs`` keep their
        value in ``guess``.
        """
        mech = self.mech
        if guess is None:
            if mech.reference_q is None:
                raise InputError(f"{mech.name} has no reference configuration to start the assembly from")
            guess = mech.reference_q
        q = np.array(guess, dtype=float)
        target = q[self.act].copy()
        for i, value in self._inputs(inputs, "input").items():
            if not self.lower[i] - 1e-12 <= value <= self.upper[i] + 1e-12:
                name = mech.actuated[list(self.act).index(i)]
                raise UnreachableError(f"{mech.name}: {name} = {value:.6g} is outside its range "
                                       f"[{self.lower[i]:.6g}, {self.upper[i]:.6g}]", inputs={name: value})
            target[list(self.act).index(i)] = value
        phi, _ = self.system.evaluate(q)
        if phi.size and np.abs(phi).max() < TOLERANCE:  # an assembled start: continue along the inputs
            start = q[self.act].copy()
            steps = max(1, int(np.ceil(np.max(np.abs(target - start) / self.max_step, initial=0.0))))
            try:
                for k in range(1, steps + 1):
                    u = start + (target - start) * k / steps
                    q, J = self.newton(q + self.velocity_matrix(q) @ (u - q[self.act]), max_iterations,
                                       polish=k == steps)
                return q
            except (UnreachableError, SingularityError) as exc:
                wanted = ", ".join(f"{n} = {x:.6g}" for n, x in zip(mech.actuated, target))
                raise UnreachableError(f"{mech.name}: cannot assemble at {wanted} on the branch of the start "
                                       f"position: {str(exc).removeprefix(mech.name + ': ')}",
                                       inputs=dict(zip(mech.actuated, map(float, target))),
                                       residual=getattr(exc, "residual", None),
                                       closure=getattr(exc, "closure", None)) from None
        q[self.act] = target
        return self.newton(q, max_iterations, polish=True)[0]

    @property
    def max_step(self) -> Vector:
        """Largest input step of a continuation: 0.05 rad for angles, 2% of the stroke (or 5 mm) for lengths."""
        steps = []
        for i in self.act:
            joint = self.mech.model.joints[[j.idx_q for j in self.mech.model.joints].index(i)]
            if joint.shortname().startswith("JointModelP"):
                span = self.upper[i] - self.lower[i]
                steps.append(0.02 * span if np.isfinite(span) else 0.005)
            else:
                steps.append(0.05)
        return np.array(steps)

    def newton(self, q: Vector, max_iterations: int = 50, polish: bool = False) -> tuple[Vector, Vector]:
        """Newton's method on the dependent coordinates of q; returns (q, closure Jacobian at q), the residual Φ(q)
        being left in :attr:`residual`. It stops below :data:`TOLERANCE`; with ``polish`` it takes one more step,
        which brings the residual to rounding level."""
        phi, J = self.system.evaluate(q)
        self.residual = phi
        error = np.abs(phi).max(initial=0.0)
        for _ in range(max_iterations):
            if error < TOLERANCE:
                if polish and error > 0.0:
                    q = q.copy()
                    q[self.dep] += self.solve(J[:, self.dep], -phi)
                    phi, J = self.system.evaluate(q)
                    self.residual = phi
                return q, J
            step = self.solve(J[:, self.dep], -phi)
            t = 1.0
            while True:  # halve the step while it makes the residual grow (keeps far guesses on their branch)
                trial = q.copy()
                trial[self.dep] += t * step
                phi_t, J_t = self.system.evaluate(trial)
                error_t = np.abs(phi_t).max(initial=0.0)
                if error_t < error or t < 1e-3:
                    break
                t /= 2
            q, phi, J, error = trial, phi_t, J_t, error_t
            self.residual = phi
        if error < TOLERANCE:
            return q, J
        raise self.unreachable(q, phi, max_iterations)

    def unreachable(self, q: Vector, phi: Vector | None = None, iterations: int = 50) -> UnreachableError:
        """The error of a Newton's method that ended at q without closing the loops (``iterations`` of them): the
        inputs, the largest closure residual Φ(q) (evaluated here unless given) and its closure row."""
        if phi is None:
            phi, _ = self.system.evaluate(q)
        error = float(np.abs(phi).max(initial=0.0))
        labels = self.system.row_labels()
        worst = labels[int(np.argmax(np.abs(phi)))]
        return UnreachableError(f"{self.mech.name}: the loops do not close at {self._describe_inputs(q)} "
                                f"(closure residual {error:.3g} at {worst} after {iterations} Newton iterations)",
                                inputs=self._input_values(q), residual=error, closure=worst)

    # ------------------------------------------------------------------------------------ velocity, acceleration
    def dependent_inverse(self, q: Vector, J: Vector) -> NDArray[np.floating]:
        """J_d⁻¹ (or its pseudo-inverse when the closure equations are redundant), checked for singularity."""
        Jd = J[:, self.dep]
        try:
            inverse = np.linalg.inv(Jd) if Jd.shape[0] == Jd.shape[1] else np.linalg.pinv(Jd)
        except np.linalg.LinAlgError:
            inverse = np.full((Jd.shape[1], Jd.shape[0]), np.inf)
        if not np.abs(inverse).max() <= SINGULAR_RATIO:  # also catches inf and nan
            raise SingularityError(f"{self.mech.name} is at a singular position ({self._describe_inputs(q)}): "
                                   "the actuated coordinates do not determine the motion",
                                   inputs=self._input_values(q), ratio=float(np.nan_to_num(np.abs(inverse).max(),
                                                                                           posinf=np.inf)))
        return inverse

    def analyse(self, q: Vector, J: Vector, rates: Vector, accelerations: Vector
                ) -> tuple[Vector, Vector, Vector]:
        """(S, q̇, q̈) at an assembled q with closure Jacobian J, for actuated rates and accelerations in
        ``mech.actuated`` order: q̇ = S q̇_a, J_d q̈_d = −J_a q̈_a − J̇ q̇. Leaves J_d⁻¹ in :attr:`inverse`."""
        S = self.selection.copy()
        a = S @ accelerations
        if len(self.dep) and J.size:
            inverse = self.inverse = self.dependent_inverse(q, J)
            Ja = J[:, self.act]
            S[self.dep] = -inverse @ Ja
            v = S @ rates
            a[self.dep] = -inverse @ (Ja @ accelerations + self.system.drift(q, v))
        else:
            v = S @ rates
            self.system.drift(q, v)
        return S, v, a

    def inverse_correction(self) -> Vector:
        """The Newton step J_d⁻¹ Φ (as a full-length vector) for the last :meth:`newton` residual and the last
        :meth:`analyse` inverse; subtracting it from q brings the residual to second order."""
        correction = np.zeros(self.mech.nv)
        correction[self.dep] = self.inverse @ self.residual
        return correction

    def _vector(self, values: Mapping[str, float] | Vector, what: str) -> Vector:
        given = self._inputs(values, what)
        return np.array([given.get(int(i), 0.0) for i in self.act])

    def velocity_matrix(self, q: ArrayLike, J: Vector | None = None) -> Vector:
        """S (nv × n_act) with q̇ = S q̇_a: S_a = I, S_d = −J_d⁻¹ J_a."""
        q = np.asarray(q, dtype=float)
        J = self.system.evaluate(q)[1] if J is None else J
        S = np.zeros((self.mech.nv, len(self.act)))
        S[self.act, np.arange(len(self.act))] = 1.0
        if len(self.dep) and J.size:
            S[self.dep] = -self.dependent_inverse(q, J) @ J[:, self.act]
        return S

    def velocity(self, q: ArrayLike, rates: Mapping[str, float] | Vector) -> Vector:
        """q̇ for the actuated rates (missing ones are 0)."""
        return self.velocity_matrix(q) @ self._vector(rates, "rate")

    def acceleration(self, q: ArrayLike, v: ArrayLike, accelerations: Mapping[str, float] | Vector) -> Vector:
        """q̈ for the joint velocity v (consistent with the closures) and the actuated accelerations (missing ones
        are 0): J_d q̈_d = −J_a q̈_a − J̇ q̇."""
        q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
        J = self.system.evaluate(q)[1]
        a = np.zeros(self.mech.nv)
        a[self.act] = self._vector(accelerations, "acceleration")
        if len(self.dep) and J.size:
            drift = self.system.drift(q, v)
            a[self.dep] = -self.dependent_inverse(q, J) @ (J[:, self.act] @ a[self.act] + drift)
        return a


# ------------------------------------------------------------------------------------------ the public calls
def loop_solver(mech: Mechanism) -> LoopSolver:
    """The :class:`LoopSolver` of ``mech`` (assembly, velocity and acceleration analysis of its closed loops), built
    once and kept in its cache."""
    return mech.cached("loop_solver", lambda: LoopSolver(mech))


def assemble(mech: Mechanism, inputs: Mapping[str, float] | None = None, guess: ArrayLike | None = None,
             branch: str | None = None) -> Vector:
    """Configuration q (length nq) with the actuated coordinates at ``inputs`` (m, rad) and all closures Φ(q) = 0
    satisfied (position analysis, Newton's method on the dependent coordinates, to 1e-10 m or rad).

    The solution continues from ``guess`` (a previous solution) or from the named assembly ``branch`` (one of
    ``mech.branches``; default the reference configuration) and stays on its branch.

    Raises:
        UnreachableError: if the loops cannot close (with the inputs, the residual and the worst closure row).
    """
    if branch is not None:
        if branch not in mech.branches:
            raise unknown_name_error(f"assembly branch of {mech.name}", branch, list(mech.branches))
        if guess is not None:
            raise InputError("give a guess or a branch, not both")
        guess = mech.branches[branch]
    return loop_solver(mech).assemble(inputs or {}, guess)


def joint_velocity(mech: Mechanism, q: ArrayLike, rates: Mapping[str, float]) -> Vector:
    """Joint velocity q̇ = S·q̇_a (length nv; rad/s, m/s) for the actuated rates (m/s or rad/s; missing ones 0) at an
    assembled q: S = [I; −J_d⁻¹ J_a] from the closure Jacobian, its columns the first transfer functions
    ([Egorov, 4.2–4.3, 4.10–4.11]).

    Raises:
        SingularityError: at a singular position (the actuated coordinates do not determine the motion).
    """
    return loop_solver(mech).velocity(q, rates)


def joint_acceleration(mech: Mechanism, q: ArrayLike, v: ArrayLike,
                       accelerations: Mapping[str, float] | None = None) -> Vector:
    """Joint acceleration q̈ (length nv; rad/s², m/s²) from J_d q̈_d = −J_a q̈_a − J̇ q̇ with the actuated
    accelerations q̈_a (m/s², rad/s²; default 0) at an assembled q moving with q̇ = ``v`` (rad/s, m/s): the
    acceleration analysis whose result at q̇_a = 1, q̈_a = 0 is the second transfer functions, a = a_q q̇² + v_q q̈
    ([Egorov, 4.7–4.8, 4.15–4.16])."""
    return loop_solver(mech).acceleration(q, v, accelerations or {})

r"""The exact model of a named problem (:class:`CasadiModel`, the ``model`` of its
:class:`~mechatron.optimal.problem.Problem`): what every worked case states, and what the solver needs of it.

A design x (named parameters of a mechanism, SI units, within box bounds) fixes the geometry; the loop equations
Φ(x, s) = 0 of the mechanism's positions of interest fix the states s (joint angles); the quantities q(x, s) (bucket
angles, cylinder forces, lengths, cosines of transmission angles) are smooth CasADi SX expressions of both. The
objective and the requirements are functions of the quantities. The same quantities are computed by the Pinocchio
model (:meth:`CasadiModel.evaluate`: rebuild with ``mech.with_parameters``, assemble, evaluate), which is
what checks the CasADi derivatives (central finite differences) and every requirement at the optimum.

The derivative of q with respect to x along the loop equations is the implicit-function one:
dq/dx = ∂q/∂x − ∂q/∂s (∂Φ/∂s)⁻¹ ∂Φ/∂x, all three Jacobians from CasADi's automatic differentiation.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

import numpy as np

from ..requirement import Requirement, Vector


class CasadiModel(ABC):
    """The exact CasADi model of a named problem (see the module docstring). Subclasses set, in ``__init__``:

    - ``mech`` (the base mechanism), ``variables`` (names), ``lower``, ``upper``, ``start`` (arrays, SI units);
    - ``x`` (SX, the design), ``s`` (SX, the states; may be empty), ``loops`` (SX, Φ(x, s), one row per state);
    - ``quantities`` (SX, q(x, s)) and ``quantity_names``;
    - ``objective_name``, ``objective_unit``, ``scale`` (the NLP minimises ``scale`` × objective);
    """

    mech: Any
    variables: tuple[str, ...]
    lower: Vector
    upper: Vector
    start: Vector
    x: Any
    s: Any
    loops: Any
    quantities: Any
    quantity_names: tuple[str, ...]
    objective_name: str
    objective_unit: str
    scale: float = 1.0
    title: str = ""
    _functions: dict[str, Any] | None = None

    def set_box(self, mech: Any, bounds: dict[str, tuple[float, float]], start: dict[str, float] | None) -> None:
        """Set ``mech``, the variables and their bounds (m) and the start (default: the middle of the box)."""
        self.mech = mech
        self.variables = tuple(bounds)
        self.lower = np.array([bounds[v][0] for v in self.variables], dtype=float)
        self.upper = np.array([bounds[v][1] for v in self.variables], dtype=float)
        middle = (self.lower + self.upper) / 2
        self.start = np.array([(start or {}).get(v, m) for v, m in zip(self.variables, middle)], dtype=float)

    @abstractmethod
    def state_guess(self, x: Vector) -> Vector:
        """States s near the solution of Φ(x, s) = 0 on the mechanism's assembly branch (from the Pinocchio model)."""

    @abstractmethod
    def evaluate(self, x: Vector) -> Vector:
        """The quantities q at the design x, from the Pinocchio model (rebuilt, assembled)."""

    @abstractmethod
    def nlp_terms(self, q: Any) -> tuple[Any, Any, Any]:
        """(aux, f, g) of the NLP from the quantities' SX: auxiliary variables (e.g. an epigraph bound; SX, may be
        empty), the scaled objective and the smooth requirement rows g ≥ 0."""

    @abstractmethod
    def aux_guess(self, q: Vector) -> Vector:
        """Starting values of the auxiliary variables from the quantities."""

    @abstractmethod
    def judge(self, q: Vector) -> tuple[float, list[Requirement]]:
        """(objective, requirements) at numeric quantities q (the reported, unscaled objective)."""

    # ------------------------------------------------------------------------------------------ CasADi
    def functions(self) -> dict[str, Any]:
        """CasADi functions of (x, s): Φ, q and their Jacobians (built once)."""
        import casadi as ca

        if self._functions is not None:
            return self._functions
        x, s = self.x, self.s
        self._functions = {"loops": ca.Function("loops", [x, s], [self.loops]),
                           "newton": ca.Function("newton", [x, s], [self.loops, ca.jacobian(self.loops, s)]),
                "quantities": ca.Function("quantities", [x, s], [self.quantities]),
                "derivatives": ca.Function("derivatives", [x, s],
                                           [ca.jacobian(self.loops, x), ca.jacobian(self.loops, s),
                                            ca.jacobian(self.quantities, x), ca.jacobian(self.quantities, s)])}
        return self._functions

    def states(self, x: Vector, guess: Vector | None = None) -> Vector:
        """The states at x: Newton's method on Φ(x, ·) = 0 from ``guess`` (default :meth:`state_guess`), to 1e-13."""
        f = self.functions()
        s = np.asarray(self.state_guess(x) if guess is None else guess, dtype=float)
        if s.size == 0:
            return s
        for _ in range(30):
            phi, Js = (np.array(m) for m in f["newton"](x, s))
            if np.abs(phi).max() < 1e-13:
                break
            try:
                step = np.linalg.solve(Js, phi.ravel())
            except np.linalg.LinAlgError:  # a singular position: left unsolved (the caller checks Φ)
                break
            s = s - step
            if np.abs(step).max() < 1e-15:
                break
        return s

    def values(self, x: Vector, s: Vector | None = None) -> Vector:
        """The quantities q at x from the CasADi expressions (states solved unless given)."""
        s = self.states(x) if s is None else s
        return np.array(self.functions()["quantities"](x, s)).ravel()

    def jacobian(self, x: Vector) -> Vector:
        """dq/dx along the loop equations (implicit-function derivative of the CasADi expressions)."""
        s = self.states(np.asarray(x, dtype=float))
        Jx, Js, Qx, Qs = (np.array(m) for m in self.functions()["derivatives"](x, s))
        if s.size == 0:
            return Qx
        return Qx - Qs @ np.linalg.solve(Js, Jx)

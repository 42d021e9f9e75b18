r"""The error of a tolerance allocation as a closed form in the tolerances t [Chase]: per axis a, with the
sensitivities J = ∂r/∂e (:mod:`~mechatron.accuracy.sensitivity`) and β = |J b| (the biases b),

- ``worst``: Δ_a = β_a + Σ_i |J_ai| t_i;
- ``rss``:   Δ_a = β_a + √(Σ_i (J_ai c_i t_i)²), c_i = kσ_i/t_i,

and |Δr| = √(Σ_a Δ_a²), the error :mod:`~mechatron.accuracy.study` reports for those methods.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

Floats = NDArray[np.float64]


@dataclass(frozen=True)
class ErrorModel:
    """|Δr| of ``method`` at every pose as a closed form in the tolerances t (SI) (the module docstring):
    sensitivities ``J`` (N, 3, n) (m per unit of each source), ``shift`` β = |J b| (N, 3) (m), ``c`` (n,) kσ/t."""

    method: str
    J: Floats
    shift: Floats
    c: Floats

    def per_axis(self, t: ArrayLike) -> Floats:
        """Δ_a (N, 3) (m) of the tolerances ``t`` (n,) (SI)."""
        t = np.asarray(t, dtype=float)
        if self.method == "worst":
            return self.shift + np.abs(self.J) @ t
        return self.shift + np.sqrt((self.J**2) @ (self.c * t) ** 2)

    def norm(self, t: ArrayLike) -> Floats:
        """|Δr| (N,) (m) at every pose."""
        return np.linalg.norm(self.per_axis(t), axis=1)

    def shares(self, t: ArrayLike, pose: int) -> Floats:
        """Each source's share (%) of the error at ``pose``: of Σ_a Σ_i |J_ai| t_i (worst) or of the variance
        Σ_a Σ_i (J_ai c_i t_i)² (rss); the bias is not shared out."""
        t = np.asarray(t, dtype=float)
        part = (np.abs(self.J[pose]) * t).sum(axis=0) if self.method == "worst" else \
            ((self.J[pose] * self.c * t) ** 2).sum(axis=0)
        share = 100 * part / max(part.sum(), 1e-300)
        return np.where(share < 1e-12, 0.0, share)

    def squared(self, t, symbolic: Sequence[bool], values: Floats):  # noqa: ANN001, ANN201 (CasADi expressions)
        """|Δr|² (N,) as a CasADi column of the tolerances ``t`` (an SX column (n,)), whose entries that are not
        ``symbolic`` are the numbers ``values``; an axis whose error depends on no symbolic entry stays a number."""
        import casadi as ca

        n = self.J.shape[2]
        rows = self.J.reshape(-1, n)
        beta = self.shift.reshape(-1)
        moving = np.asarray(symbolic, dtype=bool)
        if self.method == "worst":
            axes = beta + ca.mtimes(ca.DM(np.abs(rows)), t)
            squares = axes * axes
        else:
            weights = (rows * self.c) ** 2
            variance = ca.mtimes(ca.DM(weights), t * t)
            squares = []
            for r in range(len(beta)):
                if beta[r] == 0:
                    squares.append(variance[r])
                elif not weights[r, moving].any():  # a constant axis: never √0 of a symbolic expression
                    squares.append((beta[r] + math.sqrt(weights[r, ~moving] @ values[~moving] ** 2)) ** 2)
                else:
                    squares.append((beta[r] + ca.sqrt(variance[r])) ** 2)
            squares = ca.vertcat(*squares)
        return ca.sum1(ca.reshape(squares, 3, -1)).T

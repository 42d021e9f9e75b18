r"""One integrator for every equation of motion of mechatron: classical Runge–Kutta (RK4) on the configuration
manifold.

A second-order system q̈ = a(t, q, q̇) is integrated as the first-order system (q, q̇). Configurations live on a Lie
group (a continuous joint's q is (cos θ, sin θ), a free flyer's a position and a quaternion), so q is never updated
as q + Δt·q̇: every stage moves along the tangent space with ``pin.integrate`` (q ⊕ δ). With k_i the stage
velocities and accelerations,

.. math::

    q_{n+1} = q_n \oplus \tfrac{Δt}{6}(v_1 + 2 v_2 + 2 v_3 + v_4), \qquad
    \dot q_{n+1} = \dot q_n + \tfrac{Δt}{6}(a_1 + 2 a_2 + 2 a_3 + a_4),

with v_1 = q̇_n, v_2 = q̇_n + Δt/2·a_1, v_3 = q̇_n + Δt/2·a_2, v_4 = q̇_n + Δt·a_3 and the accelerations at
(q_n, v_1), (q_n ⊕ Δt/2·v_1, v_2), (q_n ⊕ Δt/2·v_2, v_3), (q_n ⊕ Δt·v_3, v_4). For vector spaces (q ⊕ δ = q + δ)
this is the classical RK4, fourth-order accurate. A scalar rate (a power) can be integrated alongside (its work).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

#: a(t, q, q̇) → (q̈, rate, anything): the acceleration, a scalar rate to integrate alongside (0 if none) and data
#: the caller wants back from the first stage (e.g. the Lagrange multipliers).
Dynamics = Callable[[float, Any, Any], tuple[Any, float, Any]]
#: q ⊕ δ: moves q along the tangent vector δ (``lambda q, d: pin.integrate(model, q, d)``; ``np.add`` for vectors).
Retraction = Callable[[Any, Any], Any]


def rk4_step(dynamics: Dynamics, t: float, q: Any, v: Any, dt: float, first: tuple[Any, float, Any] | None = None,
             retraction: Retraction = np.add) -> tuple[Any, Any, float]:
    """One RK4 step of q̈ = a(t, q, q̇) from (t, q, q̇) over ``dt`` (s), the scheme of the module docstring: returns
    (q_{n+1}, q̇_{n+1}, ∫ rate dt over the step).

    Args:
        first: ``dynamics(t, q, v)`` if the caller has it already (it is the first stage).
        retraction: q ⊕ δ on the configuration space (default: vector addition).
    """
    a1, p1, _ = first if first is not None else dynamics(t, q, v)
    v2 = v + dt / 2 * a1
    a2, p2, _ = dynamics(t + dt / 2, retraction(q, dt / 2 * v), v2)
    v3 = v + dt / 2 * a2
    a3, p3, _ = dynamics(t + dt / 2, retraction(q, dt / 2 * v2), v3)
    v4 = v + dt * a3
    a4, p4, _ = dynamics(t + dt, retraction(q, dt * v3), v4)
    q_next = retraction(q, dt / 6 * (v + 2 * v2 + 2 * v3 + v4))
    v_next = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
    return q_next, v_next, dt / 6 * (p1 + 2 * p2 + 2 * p3 + p4)


#: A step's bytes (the state, its derivatives and the multipliers kept per step, as Python objects) and its least
#: time (four evaluations of the dynamics; s), for :func:`time_steps`' refusal (:mod:`mechatron.io.budget`).
STEP_BYTES, STEP_SECONDS = 2048.0, 1e-4


def time_steps(duration: float, dt: float) -> int:
    """The number of fixed steps of length ``dt`` that cover ``duration`` (s); both checked (finite, > 0), and a
    count whose memory or time exceeds the limits of :mod:`mechatron.io.budget` refused."""
    from ..io.budget import count, option, require, seconds
    from ..io.values import number

    duration = number("duration", duration, positive=True, unit="s")
    dt = number(option("dt"), dt, positive=True, unit="s")
    steps = float(np.ceil(duration / dt))
    what, advice = f"{option('dt')} {dt:g} gives {count(steps)} steps over {duration:g} s", \
        f"use a larger {option('dt')} or a shorter duration"
    require(what, steps, STEP_BYTES, advice=advice)
    seconds(what, steps, STEP_SECONDS, advice=advice)
    return int(steps)

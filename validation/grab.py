r"""The grab paper's own formulation [Mikhailov, 6–25]: seven absolute coordinates and six Lagrange multipliers
solved together at each instant, integrated with the same RK4 step as mechatron's simulations. It checks the
Pinocchio model of robots/grab.toml (:func:`mechatron.machines.grab.grab_spec`, a spanning tree with closures) on the
same forces.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mechatron.dynamics.integrate import rk4_step, time_steps
from mechatron.machines.grab import GrabGeometry, ScoopingLoads

Vector = NDArray[np.float64]


class PaperModel:
    r"""The paper's formulation [Mikhailov, 6–25]: absolute coordinates X = (x10, y10, φ10, x20, y20, φ20, y30) of
    the jaw's and the rods' centres (m) and angles (rad) and the upper crosshead's height (m), six constraints
    Φ(X) = 0 [Mikhailov, 6] and [Mikhailov, 8]

    .. math::

        \begin{bmatrix} M & T \\ T^T & 0 \end{bmatrix} \begin{bmatrix} \ddot X \\ \lambda \end{bmatrix}
        = \begin{bmatrix} Q \\ U \end{bmatrix}, \quad M = \mathrm{diag}(m_1, m_1, J_1, 2m_2, 2m_2, 2J_2, m_3/2),
        \quad U = -\dot T^T \dot X,

    13 unknowns (7 accelerations, 6 multipliers) at each instant. T is derived here from Φ; the printed
    [Mikhailov, 18] has ∂Φ6/∂φ10 where ∂Φ6/∂φ20 belongs (Φ6 does not depend on φ10).
    """

    def __init__(self, g: GrabGeometry, loads: ScoopingLoads, gravity: float = 9.81) -> None:
        self.g, self.loads, self.gravity = g, loads, gravity
        centre = np.asarray(g.jaw_centre)
        # body points relative to the body's centre, in body axes (jaw axes = world axes when closed)
        self.jaw = {1: -centre, 2: np.array([0.0, -g.tip_length]) - centre, 3: np.asarray(g.ear) - centre}
        self.rod = {3: np.array([-g.rod_length / 2, 0.0]), 4: np.array([g.rod_length / 2, 0.0])}
        self.pin4 = np.asarray(g.crosshead_pin)
        m2, J2 = 2 * g.rod_mass, 2 * g.rod_mass * g.rod_length**2 / 12
        self.M = np.diag([g.jaw_mass, g.jaw_mass, g.jaw_inertia, m2, m2, J2, g.upper_crosshead_mass / 2])

    @staticmethod
    def _point(x: float, y: float, phi: float, rho: ArrayLike) -> tuple[Vector, Vector, Vector]:
        c, s = math.cos(phi), math.sin(phi)
        r = np.array([c * rho[0] - s * rho[1], s * rho[0] + c * rho[1]])
        return np.array([x, y]) + r, np.array([-r[1], r[0]]), -r  # position, ∂/∂φ, ∂²/∂φ²

    def constraints(self, X: ArrayLike, Xd: ArrayLike | None = None):
        """Φ (6,) (m) of [Mikhailov, 6], its Jacobian Tᵀ (6 × 7) and, with Ẋ, the velocity terms Ṫᵀ Ẋ (6,)
        (m/s²) of [Mikhailov, 19–25]."""
        x1, y1, p1, x2, y2, p2, y3 = X
        g = self.g
        A, d, e = g.curvature, g.deepest_x, g.depth
        P1, dP1, ddP1 = self._point(x1, y1, p1, self.jaw[1])
        P2, dP2, ddP2 = self._point(x1, y1, p1, self.jaw[2])
        P3, dP3, ddP3 = self._point(x1, y1, p1, self.jaw[3])
        R3, dR3, ddR3 = self._point(x2, y2, p2, self.rod[3])
        R4, dR4, ddR4 = self._point(x2, y2, p2, self.rod[4])
        eta = -e + A * (P2[0] + d) ** 2
        slope = 2 * A * (P2[0] + d)
        phi = np.array([P1[0], P2[1] - eta, P3[0] - R3[0], P3[1] - R3[1], R4[0] - self.pin4[0],
                        R4[1] - y3 - self.pin4[1]])
        J = np.zeros((6, 7))
        J[0, [0, 2]] = 1.0, dP1[0]
        J[1, [0, 1, 2]] = -slope, 1.0, dP2[1] - slope * dP2[0]
        J[2, [0, 2, 3, 5]] = 1.0, dP3[0], -1.0, -dR3[0]
        J[3, [1, 2, 4, 5]] = 1.0, dP3[1], -1.0, -dR3[1]
        J[4, [3, 5]] = 1.0, dR4[0]
        J[5, [4, 5, 6]] = 1.0, dR4[1], -1.0
        if Xd is None:
            return phi, J
        w1, w2 = Xd[2], Xd[5]
        tip_x_rate = Xd[0] + dP2[0] * w1
        drift = np.array([ddP1[0] * w1**2,
                          ddP2[1] * w1**2 - slope * ddP2[0] * w1**2 - 2 * A * tip_x_rate**2,
                          ddP3[0] * w1**2 - ddR3[0] * w2**2, ddP3[1] * w1**2 - ddR3[1] * w2**2,
                          ddR4[0] * w2**2, ddR4[1] * w2**2])
        return phi, J, drift

    def tip(self, X: ArrayLike, Xd: ArrayLike) -> tuple[Vector, Vector]:
        """Position (m) and velocity (m/s) of the cutting edge, point 2."""
        P2, dP2, _ = self._point(X[0], X[1], X[2], self.jaw[2])
        return P2, np.asarray(Xd[:2]) + dP2 * Xd[2]

    def applied(self, X: ArrayLike, Xd: ArrayLike, gravity: bool = True) -> Vector:
        """Q (N, N·m) of [Mikhailov, 8]: gravity (optionally), the rope forces and the cutting resistance as
        generalized forces on X."""
        Q = -self.gravity * np.diag(self.M) * np.array([0, 1, 0, 0, 1, 0, 1]) if gravity else np.zeros(7)
        P1, dP1, _ = self._point(X[0], X[1], X[2], self.jaw[1])
        hinge = np.array([0.0, self.loads.hinge_force()])
        Q[[0, 1]] += hinge
        Q[2] += dP1 @ hinge
        Q[6] += self.loads.crosshead_force()
        _, velocity = self.tip(X, Xd)
        cut = self.loads.cutting_force(velocity)
        _, dP2, _ = self._point(X[0], X[1], X[2], self.jaw[2])
        Q[[0, 1]] += cut
        Q[2] += dP2 @ cut
        return Q

    def solve(self, X: ArrayLike, Xd: ArrayLike) -> tuple[Vector, Vector]:
        """(Ẍ, λ) from the 13 × 13 system of [Mikhailov, 8] with M Ẍ + T λ = Q, Tᵀ Ẍ = U."""
        _, J, drift = self.constraints(X, Xd)
        T = J.T
        system = np.block([[self.M, T], [T.T, np.zeros((6, 6))]])
        solution = np.linalg.solve(system, np.concatenate([self.applied(X, Xd), -drift]))
        return solution[:7], solution[7:]

    def initial_state(self, phi1: float, rate: float = 0.0) -> tuple[Vector, Vector]:
        """X and Ẋ for the jaw angle φ1 (rad) and its rate (rad/s), from the closed form (positions) and the
        constraints."""
        g = self.g
        pose = g.closed_form(phi1)
        centre = pose["hinge"] + self._point(0, 0, phi1, np.asarray(g.jaw_centre))[0]
        rod_centre = (pose["ear"] + pose["pin4"]) / 2
        rod_angle = math.atan2(*(pose["pin4"] - pose["ear"])[::-1])
        X = np.array([centre[0], centre[1], phi1, rod_centre[0], rod_centre[1], rod_angle, pose["upper_crosshead"]])
        _, J = self.constraints(X)
        free = [0, 1, 3, 4, 5, 6]
        Xd = np.zeros(7)
        Xd[2] = rate
        Xd[free] = np.linalg.solve(J[:, free], -J[:, 2] * rate)
        return X, Xd

    def project(self, X: Vector, Xd: Vector) -> tuple[Vector, Vector]:
        """The nearest X with Φ = 0 (three minimum-norm Newton steps) and Ẋ with Tᵀ Ẋ = 0."""
        for _ in range(3):
            phi, J = self.constraints(X)
            X = X - np.linalg.lstsq(J, phi, rcond=None)[0]
        _, J = self.constraints(X)
        return X, Xd - np.linalg.lstsq(J, J @ Xd, rcond=None)[0]

    def simulate(self, phi1: float, rate: float, duration: float, dt: float = 1e-3) -> dict[str, Vector]:
        """Fixed-step RK4 (:func:`mechatron.dynamics.integrate.rk4_step`) with projection onto the constraints after
        each step, from the jaw angle φ1 (rad) and rate (rad/s) for at most ``duration`` s; stops when the jaw
        closes (φ1 ≥ 0).

        Returns arrays t (s), X, Ẋ, Ẍ, the multipliers (N), the work of the forces other than gravity since the start
        (J), and the kinetic and potential energies (J): work = Δ(kinetic + potential).
        """
        X, Xd = self.initial_state(phi1, rate)

        def dynamics(t: float, X: Vector, Xd: Vector) -> tuple[Vector, float, Vector]:
            a, lam = self.solve(X, Xd)  # accelerations, multipliers, and the power of the forces but gravity
            return a, float(self.applied(X, Xd, gravity=False) @ Xd), lam

        rows = []
        work, t = 0.0, 0.0
        for _ in range(time_steps(duration, dt) + 1):
            first = dynamics(t, X, Xd)
            rows.append((t, X, Xd, first[0], first[2], work))
            if X[2] >= 0.0:
                break
            X, Xd, step_work = rk4_step(dynamics, t, X, Xd, dt, first)
            work += step_work
            X, Xd = self.project(X, Xd)
            t += dt
        t, X, Xd, A, lam, work = (np.array(column) for column in zip(*rows))
        kinetic = 0.5 * np.einsum("ki,ij,kj->k", Xd, self.M, Xd)
        potential = self.gravity * (X[:, [1, 4, 6]] @ np.diag(self.M)[[1, 4, 6]])
        return {"t": t, "X": X, "Xd": Xd, "Xdd": A, "multipliers": lam, "work": work, "kinetic": kinetic,
                "potential": potential}

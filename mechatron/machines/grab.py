r"""Half of a two-rope rod (clamshell) grab while scooping (seed 003, Mikhailov 2006; notes seed-linkages.md).

Bodies (the paper's numbering): jaw 1 (m1, J1) with its hinge point 1 on the grab axis, its cutting edge 2 and its
ear 3; the rods 2 (two parallel rods: 2 m2, 2 J2) from the ear 3 to point 4 of the upper crosshead 3 (half of it:
m3/2), which slides on the axis. The lower crosshead carrying the jaw hinge slides on the axis too (massless here, as
in the paper, which has no body for it). The constraints of eq. (6):

- Φ1: jaw point 1 stays on the axis x = 0 (here: the jaw turns on the lower crosshead, a vertical slider);
- Φ2: the tip 2 stays on the scooping curve y = η(x) = −e + A (x + d)², A = (e − b)/(L/2 − d)², −L/2 ≤ x ≤ 0;
- Φ3, Φ4: revolute pair jaw–rods at point 3; Φ5, Φ6: revolute pair rods–upper crosshead at point 4.

The origin is on the material surface (η(−L/2) = −b: the tip starts at the initial penetration b) and the modelled
jaw is the left one: open at x_tip = −L/2, closed at x_tip = 0 where both tips meet. The paper gives no numbers; the
default geometry (a grab of about 1.4 m³) is the reconstruction of /work notes, see :func:`grab`. The jaw's shape is
given in its closed position relative to its hinge; its angle φ1 (the coordinate ``phi1``, the paper's φ10 with the
jaw frame parallel to the world when closed) is negative when open.

For any jaw angle φ the positions follow in closed form (used by the tests): x_tip = r sin φ (r = hinge–tip
length, the tip straight below the hinge when closed), y_hinge = η(x_tip) + r cos φ, and the upper crosshead height
from |P4 − P3| = rod length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder


@dataclass(frozen=True)
class GrabGeometry:
    """Geometry and masses of the half grab (SI units)."""

    opening: float = 2.80  # L, tip-to-tip span of the open grab
    penetration: float = 0.25  # b, tip depth at x = −L/2
    depth: float = 0.75  # e = H, depth of the deepest point of the curve
    deepest_x: float = 0.50  # d, the deepest point is at x = −d
    tip_length: float = 1.70  # hinge to tip, vertical when closed
    ear: tuple[float, float] = (-1.00, 0.10)  # ear 3 relative to the hinge, closed
    jaw_centre: tuple[float, float] = (-0.55, -0.80)  # jaw centre of mass relative to the hinge, closed
    rod_length: float = 1.90
    crosshead_pin: tuple[float, float] = (-0.25, -0.10)  # point 4 relative to the upper crosshead's centre
    jaw_mass: float = 650.0  # m1
    jaw_inertia: float = 200.0  # J1 about its centre
    rod_mass: float = 60.0  # m2, one rod (the model carries 2 m2)
    upper_crosshead_mass: float = 450.0  # m3, whole (the model carries m3/2)

    @property
    def curvature(self) -> float:
        """A = (e − b)/(L/2 − d)² (1/m)."""
        return (self.depth - self.penetration) / (self.opening / 2 - self.deepest_x) ** 2

    def eta(self, x: float) -> float:
        return -self.depth + self.curvature * (x + self.deepest_x) ** 2

    def closed_form(self, phi: float) -> dict[str, np.ndarray | float]:
        """Hinge, tip, ear, point 4 and the upper crosshead height for the jaw angle φ (rad, ≤ 0 open)."""
        c, s = math.cos(phi), math.sin(phi)
        rotate = np.array([[c, -s], [s, c]])
        tip_x = self.tip_length * s
        hinge = np.array([0.0, self.eta(tip_x) + self.tip_length * c])
        ear = hinge + rotate @ np.asarray(self.ear)
        dx = self.crosshead_pin[0] - ear[0]
        if abs(dx) > self.rod_length:
            raise InputError("grab: the rod cannot reach the upper crosshead")
        pin4 = np.array([self.crosshead_pin[0], ear[1] + math.sqrt(self.rod_length**2 - dx * dx)])
        return {"hinge": hinge, "tip": hinge + rotate @ np.array([0.0, -self.tip_length]), "ear": ear, "pin4": pin4,
                "upper_crosshead": pin4[1] - self.crosshead_pin[1]}

    @property
    def open_angle(self) -> float:
        """φ1 with the tip at x = −L/2."""
        ratio = -self.opening / 2 / self.tip_length
        if not -1 <= ratio <= 1:
            raise InputError(f"grab: the jaw ({self.tip_length:g} m) cannot open to L = {self.opening:g} m")
        return math.asin(ratio)


def grab(**overrides: float) -> Mechanism:
    """Half of a rod (clamshell) grab scooping along a parabola (seed 003); input: the jaw angle ``phi1``."""
    g = GrabGeometry(**overrides)
    if not (0 <= g.deepest_x < g.opening / 2 and g.depth > g.penetration > 0):
        raise InputError("grab: the scooping curve needs 0 <= d < L/2 and e > b > 0")
    phi_open = g.open_angle
    pose = g.closed_form(phi_open)
    c, s = math.cos(phi_open), math.sin(phi_open)
    rotate = np.array([[c, -s], [s, c]])
    hinge, tip, ear, pin4 = pose["hinge"], pose["tip"], pose["ear"], pose["pin4"]
    crosshead = np.array([0.0, pose["upper_crosshead"]])

    b = PlanarBuilder("grab")
    b.point("axis_low", GROUND, (0.0, hinge[1]), report=False)
    b.point("axis_high", GROUND, crosshead, report=False)
    lower = b.prismatic("lower_crosshead", "axis_low", (0.0, 1.0), coordinate="y_lower")
    b.point("P1_lower", lower, hinge, report=False)
    jaw = b.revolute("jaw", "P1_lower", angle=phi_open, coordinate="phi1", limits=(phi_open, 0.0), mass=g.jaw_mass,
                     com=hinge + rotate @ np.asarray(g.jaw_centre), inertia=g.jaw_inertia)
    b.point("P1", jaw, hinge)
    b.point("P2", jaw, tip)
    b.point("P3", jaw, ear)
    b.point("C1", jaw, hinge + rotate @ np.asarray(g.jaw_centre))
    upper = b.prismatic("upper_crosshead", "axis_high", (0.0, 1.0), coordinate="y3", mass=g.upper_crosshead_mass / 2,
                        com=crosshead)
    b.point("C3", upper, crosshead)
    b.point("P4", upper, pin4)
    rods = b.revolute("rods", "P4", toward=ear, coordinate="rods_angle", mass=2 * g.rod_mass,
                      com=(ear + pin4) / 2, inertia=2 * g.rod_mass * g.rod_length**2 / 12)
    b.point("P3_rods", rods, ear, report=False)
    b.point("C2", rods, (ear + pin4) / 2)
    b.pin("P3_rods", "P3")
    A, d, e = g.curvature, g.deepest_x, g.depth
    b.on_curve("P2", lambda x: -e + A * (x + d) ** 2, lambda x: 2 * A * (x + d), lambda x: 2 * A,
               label=f"y = -{e:g} + {A:.6g} (x + {d:g})^2")
    b.line("jaw", "P1", "P3", "P2", "P1")
    b.line("rods", "P3", "P4")
    b.line("upper crosshead", "C3", "P4")
    params = {name: Parameter(name, float(value), "length", name)
              for name, value in (("opening", g.opening), ("penetration", g.penetration), ("depth", g.depth),
                                  ("deepest_x", g.deepest_x), ("tip_length", g.tip_length),
                                  ("rod_length", g.rod_length))}
    return b.build(actuated=["phi1"], parameters=params, tool="P2",
                   description=f"half of a rod grab (L = {g.opening:g} m opening, scooping depth {g.depth:g} m)",
                   rebuild=lambda v: grab(**{**overrides, **v}), input_rates={"phi1": 0.5},
                   notes=["geometry invented (the paper gives no numbers); see mechatron.machines.grab"])


# ------------------------------------------------------------------------------------------------ dynamics
@dataclass(frozen=True)
class ScoopingLoads:
    """Forces of the scooping simulation (the paper gives them only as symbols, eq. 12).

    The closing rope runs over ``branches`` sheaves between the crossheads with tension ``rope_tension`` (N): the
    tackle pulls the lower crosshead — and with it the jaw hinge, point 1 — up with n·S/2 for this half grab and the
    upper crosshead down with (n − 1)·S/2 (one branch leaves it towards the winch). The material resists the
    cutting edge with ``resistance`` (N) along the curve against the tip's motion (smoothed below
    ``speed_scale`` m/s so that the force is continuous at rest). Gravity acts on every body.
    """

    rope_tension: float = 20e3
    branches: int = 4
    resistance: float = 15e3
    speed_scale: float = 1e-3

    def hinge_force(self) -> float:
        return self.branches * self.rope_tension / 2

    def crosshead_force(self) -> float:
        return -(self.branches - 1) * self.rope_tension / 2

    def cutting_force(self, tip_velocity: np.ndarray) -> np.ndarray:
        speed = float(np.hypot(tip_velocity[0], tip_velocity[1]))
        if speed == 0.0:
            return np.zeros(2)
        return -self.resistance * math.tanh(speed / self.speed_scale) * np.asarray(tip_velocity[:2]) / speed


def mechanism_loads(mech: Mechanism, loads: ScoopingLoads):
    """The scooping loads as a ``loads(t, q, q̇)`` function for :func:`mechatron.constrained.simulate`."""
    tip = mech.frame_id("P2")

    def applied(t: float, q: np.ndarray, v: np.ndarray) -> list:
        import pinocchio as pin

        pin.forwardKinematics(mech.model, mech.data, q, v)
        pin.updateFramePlacement(mech.model, mech.data, tip)
        tip_velocity = pin.getFrameVelocity(mech.model, mech.data, tip, pin.LOCAL_WORLD_ALIGNED).linear
        cut = loads.cutting_force(tip_velocity)
        return [("P1", [0.0, loads.hinge_force(), 0.0]), ("C3", [0.0, loads.crosshead_force(), 0.0]),
                ("P2", [cut[0], cut[1], 0.0])]

    return applied


class PaperModel:
    r"""The paper's formulation (eq. 6–25): absolute coordinates X = (x10, y10, φ10, x20, y20, φ20, y30) of the jaw's
    and the rods' centres and angles and the upper crosshead's height, six constraints Φ(X) = 0 and

    .. math::

        \begin{bmatrix} M & T \\ T^T & 0 \end{bmatrix} \begin{bmatrix} \ddot X \\ \lambda \end{bmatrix}
        = \begin{bmatrix} Q \\ U \end{bmatrix}, \quad M = \mathrm{diag}(m_1, m_1, J_1, 2m_2, 2m_2, 2J_2, m_3/2),
        \quad U = -\dot T^T \dot X,

    13 unknowns (7 accelerations, 6 multipliers) at each instant. T is derived here from Φ; the printed eq. (18) has
    ∂Φ6/∂φ10 where ∂Φ6/∂φ20 belongs (Φ6 does not depend on φ10).
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
    def _point(x: float, y: float, phi: float, rho: np.ndarray):
        c, s = math.cos(phi), math.sin(phi)
        r = np.array([c * rho[0] - s * rho[1], s * rho[0] + c * rho[1]])
        return np.array([x, y]) + r, np.array([-r[1], r[0]]), -r  # position, ∂/∂φ, ∂²/∂φ²

    def constraints(self, X: np.ndarray, Xd: np.ndarray | None = None):
        """Φ (6,), its Jacobian (6 × 7) and, with Ẋ, the velocity terms Ṫᵀ Ẋ (6,)."""
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

    def tip(self, X: np.ndarray, Xd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        P2, dP2, _ = self._point(X[0], X[1], X[2], self.jaw[2])
        return P2, Xd[:2] + dP2 * Xd[2]

    def applied(self, X: np.ndarray, Xd: np.ndarray, gravity: bool = True) -> np.ndarray:
        """Q: gravity (optionally), the rope forces and the cutting resistance as generalized forces on X."""
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

    def solve(self, X: np.ndarray, Xd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(Ẍ, λ) from the 13 × 13 system of eq. (8) with M Ẍ + T λ = Q, Tᵀ Ẍ = U."""
        _, J, drift = self.constraints(X, Xd)
        T = J.T
        system = np.block([[self.M, T], [T.T, np.zeros((6, 6))]])
        solution = np.linalg.solve(system, np.concatenate([self.applied(X, Xd), -drift]))
        return solution[:7], solution[7:]

    def initial_state(self, phi1: float, rate: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """X and Ẋ for the jaw angle φ1 and its rate, from the closed form (positions) and the constraints."""
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

    def simulate(self, phi1: float, rate: float, duration: float, dt: float = 1e-3) -> dict[str, np.ndarray]:
        """RK4 with projection onto the constraints after each step; stops when the jaw closes (φ1 ≥ 0).

        Returns arrays t, X, Ẋ, Ẍ, the multipliers, the work of the forces other than gravity since the start
        (J), and the kinetic and potential energies (J): work = Δ(kinetic + potential).
        """
        X, Xd = self.initial_state(phi1, rate)
        rows = []
        work = 0.0
        t = 0.0

        def deriv(X, Xd):  # accelerations, multipliers and the power of the forces other than gravity
            a, lam = self.solve(X, Xd)
            return a, lam, float(self.applied(X, Xd, gravity=False) @ Xd)

        for _ in range(int(math.ceil(duration / dt)) + 1):
            a, lam, power = deriv(X, Xd)
            rows.append((t, X.copy(), Xd.copy(), a, lam, work))
            if X[2] >= 0.0:
                break
            k1 = (Xd, a, power)
            k2 = (Xd + dt / 2 * k1[1],) + deriv(X + dt / 2 * k1[0], Xd + dt / 2 * k1[1])[::2]
            k3 = (Xd + dt / 2 * k2[1],) + deriv(X + dt / 2 * k2[0], Xd + dt / 2 * k2[1])[::2]
            k4 = (Xd + dt * k3[1],) + deriv(X + dt * k3[0], Xd + dt * k3[1])[::2]
            X = X + dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            Xd = Xd + dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            work += dt / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
            for _ in range(3):  # projection onto Φ = 0 and T^T Ẋ = 0
                phi, J = self.constraints(X)
                X = X - np.linalg.lstsq(J, phi, rcond=None)[0]
            _, J = self.constraints(X)
            Xd = Xd - np.linalg.lstsq(J, J @ Xd, rcond=None)[0]
            t += dt
        t, X, Xd, A, lam, work = (np.array(column) for column in zip(*rows))
        kinetic = 0.5 * np.einsum("ki,ij,kj->k", Xd, self.M, Xd)
        potential = self.gravity * (X[:, [1, 4, 6]] @ np.diag(self.M)[[1, 4, 6]])
        return {"t": t, "X": X, "Xd": Xd, "Xdd": A, "multipliers": lam, "work": work, "kinetic": kinetic,
                "potential": potential}


def plot_scooping(result: dict, geometry: GrabGeometry, path) -> object:
    """PNG of a scooping simulation (:meth:`PaperModel.simulate`): the jaw tip's path on the scooping curve, the
    tip speed and the jaw's angular speed, and the pin forces (the multipliers: the hinge's horizontal force, the
    material's normal force on the cutting edge, the jaw–rod and rod–crosshead pins)."""
    from pathlib import Path

    from matplotlib.figure import Figure

    from ..io.output import save_figure as _save

    model = PaperModel(geometry, ScoopingLoads())
    tips = np.array([model.tip(X, Xd)[0] for X, Xd in zip(result["X"], result["Xd"])])
    speeds = np.array([np.linalg.norm(model.tip(X, Xd)[1]) for X, Xd in zip(result["X"], result["Xd"])])
    lam, t = result["multipliers"], result["t"]
    fig = Figure(figsize=(12, 4.5), layout="constrained")
    ax_path, ax_speed, ax_force = fig.subplots(1, 3)
    x = np.linspace(-geometry.opening / 2, 0.0, 200)
    ax_path.plot(x, [geometry.eta(v) for v in x], color="saddlebrown", lw=3, alpha=0.4, label="scooping curve")
    ax_path.plot(tips[:, 0], tips[:, 1], color="tab:red", label="jaw tip")
    ax_path.set(aspect="equal", xlabel="x (m)", ylabel="y (m)", title="jaw tip path")
    ax_path.legend(fontsize=8)
    ax_speed.plot(t, speeds, label="tip speed (m/s)")
    ax_speed.plot(t, result["Xd"][:, 2], label="jaw ω (rad/s)")
    ax_speed.set(xlabel="t (s)", title="speeds")
    ax_speed.legend(fontsize=8)
    for label, values in (("hinge, horizontal", np.abs(lam[:, 0])), ("cutting edge, normal", np.abs(lam[:, 1])),
                          ("jaw–rods pin", np.hypot(lam[:, 2], lam[:, 3])),
                          ("rods–crosshead pin", np.hypot(lam[:, 4], lam[:, 5]))):
        ax_force.plot(t, values / 1e3, label=label)
    ax_force.set(xlabel="t (s)", ylabel="kN", title="pin forces (multipliers)")
    ax_force.legend(fontsize=8)
    for ax in (ax_path, ax_speed, ax_force):
        ax.grid(True, alpha=0.3)
    path = Path(path)
    _save(fig, path)
    return path

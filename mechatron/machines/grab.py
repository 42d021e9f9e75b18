r"""Half of a two-rope rod (clamshell) grab while scooping, after I. V. Mikhailov's motion model [Mikhailov].

Bodies (the paper's numbering): jaw 1 (m1, J1) with its hinge point 1 on the grab axis, its cutting edge 2 and its
ear 3; the rods 2 (two parallel rods: 2 m2, 2 J2) from the ear 3 to point 4 of the upper crosshead 3 (half of it:
m3/2), which slides on the axis. The lower crosshead carrying the jaw hinge slides on the axis too (massless here, as
in the paper, which has no body for it). The constraints of [Mikhailov, 6]:

- Φ1: jaw point 1 stays on the axis x = 0 (here: the jaw turns on the lower crosshead, a vertical slider);
- Φ2: the tip 2 stays on the scooping curve y = η(x) = −e + A (x + d)², A = (e − b)/(L/2 − d)², −L/2 ≤ x ≤ 0;
- Φ3, Φ4: revolute pair jaw–rods at point 3; Φ5, Φ6: revolute pair rods–upper crosshead at point 4.

The origin is on the material surface (η(−L/2) = −b: the tip starts at the initial penetration b) and the modelled
jaw is the left one: open at x_tip = −L/2, closed at x_tip = 0 where both tips meet. The paper gives no numbers; the
default geometry (a grab of about 1.4 m³) is a reconstruction, see :class:`GrabGeometry`. The jaw's shape is given in
its closed position relative to its hinge; its angle φ1 (the coordinate ``phi1``, the paper's φ10 with the jaw frame
parallel to the world when closed) is negative when open.

For any jaw angle φ the positions follow in closed form (:meth:`GrabGeometry.closed_form`): x_tip = r sin φ
(r = hinge–tip length, the tip straight below the hinge when closed), y_hinge = η(x_tip) + r cos φ, and the upper
crosshead height from |P4 − P3| = rod length. The paper's own formulation (absolute coordinates and Lagrange
multipliers, [Mikhailov, 8]) is in the test suite's ``validation/grab.py``.

The reconstruction (:class:`GrabGeometry`, :func:`grab_spec`) writes the mechanism file ``robots/grab.toml``
(:func:`write_grab`), which ``mechatron.load("grab")`` and every command read; its named lengths are ``tip_length``
and ``rod_length``. The scooping curve is a table in the file (a "curve" closure). Another curve or grab goes through
the reconstruction: ``write_grab("my_grab.toml", depth=0.8)`` or ``build_linkage(grab_spec(depth=0.8))``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.linkage import BodySpec, ClosureSpec, JointSpec, LengthSpec, LinkageSpec, PointSpec, build_linkage
from ..model.linkage_file import write_linkage_file
from ..model.loads import Load
from ..model.mechanism import Mechanism
from ..model.planar import GROUND

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.constrained import Simulation


@dataclass(frozen=True)
class GrabGeometry:
    """Geometry and masses of the half grab (m, kg, kg·m²). The paper gives no numbers: the defaults are a
    reconstruction for a grab of about 1.4 m³."""

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
        """η(x) (m), the scooping curve at x (m) [Mikhailov, 6]."""
        return -self.depth + self.curvature * (x + self.deepest_x) ** 2

    def closed_form(self, phi: float) -> dict[str, NDArray[np.float64] | float]:
        """Hinge, tip, ear, point 4 (m, world xy) and the upper crosshead height (m) for the jaw angle φ (rad, ≤ 0
        open)."""
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
        """φ1 (rad) with the tip at x = −L/2."""
        ratio = -self.opening / 2 / self.tip_length
        if not -1 <= ratio <= 1:
            raise InputError(f"grab: the jaw ({self.tip_length:g} m) cannot open to L = {self.opening:g} m")
        return math.asin(ratio)


#: The comment at the top of robots/grab.toml.
HEADER = """Half of a two-rope rod (clamshell) grab while scooping, after I. V. Mikhailov's motion model
[Mikhailov]: written by mechatron.machines.grab.write_grab() from GrabGeometry (the paper gives no numbers: a
reconstruction for a grab of about 1.4 m³); do not edit it by hand, change the reconstruction and write it again.
Drawn open (the jaw's tip at x = -L/2 on the material surface). The jaw turns on the lower crosshead, which slides on
the grab's axis x = 0; the two rods join the jaw's ear P3 to the upper crosshead's pin P4; the tip P2 follows the
scooping curve y = -e + A (x + d)^2, given as a table (a not-a-knot cubic spline through it is the parabola itself)."""


def grab_spec(**overrides: float) -> LinkageSpec:
    """The mechanism file of the half grab [Mikhailov] as a :class:`~mechatron.model.linkage.LinkageSpec`, drawn
    open (φ1 = :attr:`GrabGeometry.open_angle`, from :meth:`GrabGeometry.closed_form`): the massless lower crosshead
    sliding on the axis (``y_lower``), the jaw turning on it (``phi1``, the input, limits open … 0), the upper
    crosshead (m3/2, ``y3``) and the two rods (2 m2 as one bar from P4 to P3, ``rods_angle``); closures: the pin P3
    and the tip P2 on the scooping curve η(x) as a table of 8 points from x = −L/2 to 0 (m). Named lengths
    ``tip_length`` (P1P2) and ``rod_length`` (P4P3).

    ``overrides`` are fields of :class:`GrabGeometry` (m, kg, kg·m²).

    Raises:
        InputError: for a curve that is not 0 ≤ d < L/2, e > b > 0, or a jaw that cannot open to L.
    """
    g = GrabGeometry(**overrides)
    if not (0 <= g.deepest_x < g.opening / 2 and g.depth > g.penetration > 0):
        raise InputError("grab: the scooping curve needs 0 <= d < L/2 and e > b > 0")
    phi_open = g.open_angle
    pose = g.closed_form(phi_open)
    c, s = math.cos(phi_open), math.sin(phi_open)
    centre = pose["hinge"] + np.array([[c, -s], [s, c]]) @ np.asarray(g.jaw_centre)

    def at(xy: ArrayLike) -> tuple[float, float]:
        return (float(xy[0]), float(xy[1]))

    crosshead = (0.0, float(pose["upper_crosshead"]))
    points = (PointSpec("axis_low", (0.0, float(pose["hinge"][1])), report=False),
              PointSpec("axis_high", crosshead, report=False),
              PointSpec("P1", at(pose["hinge"])), PointSpec("P2", at(pose["tip"])), PointSpec("P3", at(pose["ear"])),
              PointSpec("C1", at(centre)), PointSpec("C3", crosshead), PointSpec("P4", at(pose["pin4"])),
              PointSpec("C2", between=("P3", "P4")))
    bodies = (BodySpec(GROUND, ("axis_low", "axis_high")),
              BodySpec("jaw", ("P1", "P2", "P3", "C1"), mass=g.jaw_mass, com="C1", inertia=g.jaw_inertia,
                       draw=("P1", "P3", "P2", "P1")),
              BodySpec("lower_crosshead", ("P1",)),
              BodySpec("upper_crosshead", ("C3", "P4"), mass=g.upper_crosshead_mass / 2, com="C3"),
              BodySpec("rods", ("P4", "P3", "C2"), mass=2 * g.rod_mass, shape="bar", draw=("P3", "P4")))
    joints = (JointSpec("prismatic", body="lower_crosshead", at="axis_low", direction=(0.0, 1.0), coordinate="y_lower"),
              JointSpec("revolute", body="jaw", at="P1", coordinate="phi1", angle=phi_open, limits=(phi_open, 0.0)),
              JointSpec("prismatic", body="upper_crosshead", at="axis_high", direction=(0.0, 1.0), coordinate="y3"),
              JointSpec("revolute", body="rods", at="P4", coordinate="rods_angle", toward="P3"))
    x = [round(float(v), 12) for v in np.linspace(-g.opening / 2, 0.0, 8)]  # round: a readable table
    A, d, e = g.curvature, g.deepest_x, g.depth
    closures = (ClosureSpec("pin", point="P3", bodies=("rods", "jaw")),
                ClosureSpec("curve", point="P2", x=tuple(x), y=tuple(float(g.eta(v)) for v in x),
                            label=f"y = -{e:g} + {A:.6g} (x + {d:g})^2"))
    lengths = (LengthSpec("tip_length", ("P1", "P2"), g.tip_length),
               LengthSpec("rod_length", ("P4", "P3"), g.rod_length))
    return LinkageSpec(
        name="grab", points=points, bodies=bodies, joints=joints, actuated=("phi1",), closures=closures,
        lengths=lengths, description=f"half of a rod grab (L = {g.opening:g} m opening, scooping depth {g.depth:g} m)",
        source="[Mikhailov]; geometry and masses reconstructed (the paper gives no numbers)", tool="P2",
        input_rates={"phi1": 0.5},
        notes=("geometry reconstructed (the paper gives no numbers); see mechatron.machines.grab",))


def grab(**overrides: float) -> Mechanism:
    """Half of a rod (clamshell) grab scooping along a parabola [Mikhailov]; input: the jaw angle ``phi1``.

    The mechanism of :func:`grab_spec`, as ``mechatron.load("grab")`` reads it from robots/grab.toml.

    ``overrides`` are fields of :class:`GrabGeometry` (m, kg, kg·m²)."""
    return build_linkage(grab_spec(**overrides))


def write_grab(path: str | Path, **overrides: float) -> Path:
    """Write the mechanism file of :func:`grab_spec` to ``path`` (robots/grab.toml is this with the defaults)."""
    return write_linkage_file(grab_spec(**overrides), path, HEADER)


# ------------------------------------------------------------------------------------------------ dynamics
@dataclass(frozen=True)
class ScoopingLoads:
    """Forces of the scooping simulation (the paper gives them only as symbols, [Mikhailov, 12]).

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
        """The tackle's upward pull on the jaw hinge, n·S/2 (N)."""
        return self.branches * self.rope_tension / 2

    def crosshead_force(self) -> float:
        """The tackle's pull on the upper crosshead, −(n − 1)·S/2 (N, upward positive)."""
        return -(self.branches - 1) * self.rope_tension / 2

    def cutting_force(self, tip_velocity: ArrayLike) -> NDArray[np.float64]:
        """The material's resistance (N, world xy) against the cutting edge moving at ``tip_velocity`` (m/s)."""
        speed = float(np.hypot(tip_velocity[0], tip_velocity[1]))
        if speed == 0.0:
            return np.zeros(2)
        return -self.resistance * math.tanh(speed / self.speed_scale) * np.asarray(tip_velocity[:2]) / speed


def mechanism_loads(mech: Mechanism, loads: ScoopingLoads) -> Callable[[float, NDArray[np.float64],
                                                                         NDArray[np.float64]], list[Load]]:
    """The scooping loads as a ``loads_at(t, q, q̇)`` function for :func:`mechatron.dynamics.constrained.simulate`:
    the rope forces at P1 and C3 and the cutting resistance at P2 (N, world axes)."""
    tip = mech.frame_id("P2")

    def applied(t: float, q: NDArray[np.float64], v: NDArray[np.float64]) -> list[Load]:
        import pinocchio as pin

        pin.forwardKinematics(mech.model, mech.data, q, v)
        pin.updateFramePlacement(mech.model, mech.data, tip)
        tip_velocity = pin.getFrameVelocity(mech.model, mech.data, tip, pin.LOCAL_WORLD_ALIGNED).linear
        cut = loads.cutting_force(tip_velocity)
        return [Load("P1", [0.0, loads.hinge_force(), 0.0]), Load("C3", [0.0, loads.crosshead_force(), 0.0]),
                Load("P2", [cut[0], cut[1], 0.0])]

    return applied


def scooping_forces(mech: Mechanism, simulation: Simulation, loads: ScoopingLoads | None = None
                    ) -> dict[str, NDArray[np.float64]]:
    """The pin forces (N) along a scooping simulation of :func:`grab` (:func:`mechatron.dynamics.constrained.simulate`
    with :func:`mechanism_loads` of ``loads``): what the paper's multipliers λ1…λ6 give [Mikhailov, 8].

    From the closure multipliers: the material's normal force on the cutting edge, |λ| √(1 + η′²) for the curve
    Φ = y − η(x), and the jaw–rods pin force. From Newton's law for each body, m a_C = m g + Σ F: the horizontal
    force of the axis on the jaw hinge (the lower crosshead is massless) and the rods–upper crosshead pin force.
    Keys ``hinge_horizontal``, ``cutting_edge_normal``, ``jaw_rods_pin``, ``rods_crosshead_pin`` (magnitudes, N).
    """
    from ..kinematics.frames import frame_placement, point_acceleration
    from ..kinematics.loops import loop_solver
    from ..model.closures import OnCurve, Pin

    applied = mechanism_loads(mech, loads or ScoopingLoads())
    rows, k = {}, 0
    for closure in loop_solver(mech).system.closures:
        rows[type(closure)] = slice(k, k + closure.nrows)
        k += closure.nrows
    curve = next(c for c in mech.closures if isinstance(c, OnCurve))
    jaw, rods = mech.joint_id("phi1"), mech.joint_id("rods_angle")
    m_jaw, m_rods = mech.model.inertias[jaw].mass, mech.model.inertias[rods].mass
    gravity = mech.model.gravity.linear[:2]
    out = {name: np.empty(len(simulation.t)) for name in ("hinge_horizontal", "cutting_edge_normal", "jaw_rods_pin",
                                                            "rods_crosshead_pin")}
    for i, (t, q, v, a, lam) in enumerate(zip(simulation.t, simulation.q, simulation.v, simulation.a,
                                              simulation.multipliers)):
        pin_force = lam[rows[Pin]][:2]  # on the rods at P3 (the jaw receives the opposite)
        x = frame_placement(mech, q, "P2").translation[0]
        normal = lam[rows[OnCurve]][0] * np.array([-curve.df(x), 1.0])  # Jᵀλ of Φ = y − η(x), at the tip
        on_jaw = sum((L.force[:2] for L in applied(t, q, v)
                      if mech.model.frames[mech.frame_id(L.frame)].parentJoint == jaw), np.zeros(2))
        hinge = (m_jaw * (point_acceleration(mech, q, v, a, "C1")[:2] - gravity) - on_jaw - normal + pin_force)
        crosshead = m_rods * (point_acceleration(mech, q, v, a, "C2")[:2] - gravity) - pin_force
        out["hinge_horizontal"][i] = abs(hinge[0])
        out["cutting_edge_normal"][i] = np.linalg.norm(normal)
        out["jaw_rods_pin"][i] = np.linalg.norm(pin_force)
        out["rods_crosshead_pin"][i] = np.linalg.norm(crosshead)
    return out


def plot_scooping(mech: Mechanism, simulation: Simulation, loads: ScoopingLoads | None = None,
                  ax: Axes | None = None) -> Figure:
    """A scooping simulation of the grab (:func:`mechatron.dynamics.constrained.simulate` with
    :func:`mechanism_loads` of ``loads``, default :class:`ScoopingLoads`): the cutting edge's path on the scooping
    curve (m, from the drawn tip of the open jaw to the axis); the tip speed (m/s) and the jaw's angular speed
    (rad/s); the pin forces of :func:`scooping_forces` (kN). With ``ax`` only the path is drawn, into it; returns the
    figure.
    """
    from ..kinematics.frames import frame_placement, point_velocity
    from ..model.closures import OnCurve
    from ..report.figures import figure_axes, new_figure, style_axes

    curve = next(c for c in mech.closures if isinstance(c, OnCurve))
    t = simulation.t
    tips = np.array([frame_placement(mech, q, "P2").translation[:2] for q in simulation.q])
    if ax is None:
        fig = new_figure(13.0, 4.5)
        ax_path, ax_speed, ax_force = fig.subplots(1, 3)
    else:
        fig, ax_path = figure_axes(ax)
        ax_speed = ax_force = None
    open_tip = frame_placement(mech, mech.reference_q, "P2").translation[0]  # the drawing: the jaw open
    x = np.linspace(min(open_tip, tips[:, 0].min()), max(0.0, tips[:, 0].max()), 200)
    ax_path.plot(x, [curve.f(v) for v in x], color="saddlebrown", lw=3, alpha=0.4, label="scooping curve")
    ax_path.plot(tips[:, 0], tips[:, 1], color="tab:red", label="cutting edge")
    ax_path.set_aspect("equal")
    style_axes(ax_path, "x (m)", "y (m)", "cutting edge path", legend=True)
    if ax_speed is not None and ax_force is not None:
        speeds = [np.linalg.norm(point_velocity(mech, q, v, "P2")[:2]) for q, v in zip(simulation.q, simulation.v)]
        ax_speed.plot(t, speeds, label="tip speed (m/s)")
        ax_speed.plot(t, simulation.v[:, mech.model.joints[mech.joint_id("phi1")].idx_v],
                      label="jaw angular speed (rad/s)")
        style_axes(ax_speed, "t (s)", "speed (m/s, rad/s)", "speeds", legend=True)
        labels = {"hinge_horizontal": "hinge, horizontal", "cutting_edge_normal": "cutting edge, normal",
                  "jaw_rods_pin": "jaw–rods pin", "rods_crosshead_pin": "rods–crosshead pin"}
        for name, values in scooping_forces(mech, simulation, loads).items():
            ax_force.plot(t, values / 1e3, label=labels[name])
        style_axes(ax_force, "t (s)", "force (kN)", "pin forces", legend=True)
    return fig

r"""Six-link bucket mechanism of construction and road machines [Bucket].

A planar 1-DOF linkage on the stick (the frame): a hydraulic cylinder A–B (barrel eye A on the stick, rod eye B on
the rocker) turns the rocker D-B-C about D (a bent lever: arms DB = L2 and DC = L3 at the angle α), and the
connecting link C–E (L4) turns the bucket about F (hinge spacing FE = L5, tooth tip K at L_k from F, ∠EFK = γ).
In the frame of the paper's loop equations [Bucket, 8] the origin is the rocker pivot D, x runs along the stick line DF
from the bucket pivot F = (−c, 0) towards the cylinder eye A = (a, b):

    Φ1 = L1 cos φ1 + L2 cos φ2 − a            Φ3 = c − L5 cos φ4 − L4 cos φ3 + L3 cos(φ2 + α)
    Φ2 = L2 sin φ2 − L1 sin φ1 − b            Φ4 = L5 sin φ4 − L3 sin(φ2 + α) + L4 sin φ3

with B = L2∠φ2 = A + L1(−cos φ1, sin φ1), C = L3∠(φ2 + α), E = F + L5∠φ4 = C − L4∠φ3 and φ4 = ∠DFE the bucket
angle. (The paper's figures are missing; this reading is the only one in which the rocker is rigid and c > 0 — the
backhoe layout.)

- :func:`first_sizing`: empirical first sizing from the bucket volume q [Bucket, 1–4]: L_k = 1.25 ∛q + 0.25,
  L5 = 0.4 L_k = L4 = L3, stroke h ≈ 1.83 L5 (taken from a standard series), L1н = H_T + h;
- :func:`synthesize`: c and L2 from L1н, φ4н, h and Δφ4 by solving the eight loop equations at the initial and
  final positions for (φ1н, φ2н, φ3н, φ1к, φ2к, φ3к, c, L2) with CasADi's Newton rootfinder;
- :func:`build`: the closed-loop :class:`~mechatron.model.Mechanism`, actuated by the cylinder length ``L1``.

The paper's own closed-form analysis [Bucket, 12–22], the reference this model is checked against, is in the test
suite's ``validation/bucket.py``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..kinematics.loops import assemble, loop_solver
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder

DEG = math.pi / 180
#: Standard cylinder strokes (mm), an R20-type series (GOST 6540 style), for "a standard stroke from a maker's
#: range" after [Bucket, 4].
STROKE_SERIES_MM = (100, 110, 125, 140, 160, 180, 200, 220, 250, 280, 320, 360, 400, 450, 500, 560, 630, 710, 800,
                    900, 1000, 1120, 1250, 1400, 1600, 1800, 2000, 2240, 2500, 2800, 3200)


@dataclass(frozen=True)
class BucketInputs:
    """Design inputs (lengths m, angles in degrees as named).

    ``a`` (axial distance of the cylinder eye A from the rocker pivot D) is a stick dimension the paper does not
    size; by default a = L1н + h/2, which makes the rocker swing symmetrically about the normal to the stick.
    ``initial_angle_deg`` is φ4н; by default 180° − β − γ (the tooth line at β to the stick axis when the bucket is
    fully open). ``turn_deg`` is the required bucket rotation Δφ4 (the paper gives no value; 150–180° is usual).
    """

    volume: float = 0.5  # q, m³
    alpha_deg: float = 12.5  # 10…15°
    beta_deg: float = 30.0  # 27…32°
    gamma_deg: float = 100.0  # 95…110°
    dead_length: float = 0.2  # H_T, 0.1…0.3 m
    offset: float = 0.2  # b, 0.1…0.3 m
    standard_stroke: bool = True
    a: float | None = None
    initial_angle_deg: float | None = None
    turn_deg: float = 160.0


@dataclass(frozen=True)
class BucketLinkage:
    """A synthesized six-link bucket mechanism (m, rad)."""

    inputs: BucketInputs
    Lk: float
    L3: float
    L4: float
    L5: float
    stroke: float  # h
    L1n: float
    a: float
    b: float
    alpha: float
    gamma: float
    phi4n: float
    turn: float
    c: float
    L2: float
    initial: tuple[float, float, float]  # φ1н, φ2н, φ3н
    final: tuple[float, float, float]  # φ1к, φ2к, φ3к

    def pins(self, L1: float, phi: tuple[float, float, float], phi4: float) -> dict[str, NDArray[np.float64]]:
        """Pin positions (m) in the stick frame for the paper's coordinates (L1 in m; φ1, φ2, φ3, φ4 in rad)."""
        p1, p2, _ = phi
        A = np.array([self.a, self.b])
        F = np.array([-self.c, 0.0])
        return {"A": A, "B": A + L1 * np.array([-math.cos(p1), math.sin(p1)]),
                "C": self.L3 * np.array([math.cos(p2 + self.alpha), math.sin(p2 + self.alpha)]),
                "D": np.zeros(2), "E": F + self.L5 * np.array([math.cos(phi4), math.sin(phi4)]), "F": F,
                "K": F + self.Lk * np.array([math.cos(phi4 + self.gamma), math.sin(phi4 + self.gamma)])}


def first_sizing(inputs: BucketInputs) -> dict[str, float]:
    """Empirical first sizing [Bucket, 1–4]: L_k, L5 = L4 = L3, the stroke h and the retracted length L1н (m)."""
    if not inputs.volume > 0:
        raise InputError(f"bucket volume q must be > 0 m³, got {inputs.volume:g}")
    Lk = 1.25 * inputs.volume ** (1 / 3) + 0.25  # [Bucket, 1]
    L5 = 0.4 * Lk  # [Bucket, 2]
    raw = 1.83 * L5  # [Bucket, 4]
    h = min(STROKE_SERIES_MM, key=lambda s: abs(s / 1000 - raw)) / 1000 if inputs.standard_stroke else raw
    return {"Lk": Lk, "L5": L5, "L4": L5, "L3": L5, "stroke_raw": raw, "stroke": h,
            "L1n": inputs.dead_length + h}  # [Bucket, 3]


def loop_equations(L1: Any, phi1: Any, phi2: Any, phi3: Any, phi4: Any, *, a: Any, b: Any, c: Any, L2: Any, L3: Any,
                   L4: Any, L5: Any, alpha: Any, cos: Callable[[Any], Any] = math.cos,
                   sin: Callable[[Any], Any] = math.sin) -> list[Any]:
    """Φ1…Φ4 (m) of [Bucket, 8] for lengths in m and angles in rad (numbers or CasADi expressions)."""
    return [L1 * cos(phi1) + L2 * cos(phi2) - a,
            L2 * sin(phi2) - L1 * sin(phi1) - b,
            c - L5 * cos(phi4) - L4 * cos(phi3) + L3 * cos(phi2 + alpha),
            L5 * sin(phi4) - L3 * sin(phi2 + alpha) + L4 * sin(phi3)]


def synthesize(inputs: BucketInputs | None = None) -> BucketLinkage:
    """c and L2 from L1н, φ4н, h and Δφ4: the eight loop equations at the initial and final positions solved for
    (φ1н, φ2н, φ3н, φ1к, φ2к, φ3к, c, L2) by CasADi's Newton rootfinder from a sketch (rocker swinging 35°→145°,
    L2 = L3, c = 0.8 L5). The root must have c > 0 and L2 > 0; :func:`build` then checks by continuation that the
    mechanism reaches the final position on one assembly branch. Lengths in m, angles in rad."""
    import casadi as ca

    inputs = inputs or BucketInputs()
    size = first_sizing(inputs)
    h, L1n, L3, L4, L5 = size["stroke"], size["L1n"], size["L3"], size["L4"], size["L5"]
    alpha, gamma = inputs.alpha_deg * DEG, inputs.gamma_deg * DEG
    a = inputs.a if inputs.a is not None else L1n + h / 2
    b = inputs.offset
    phi4n = inputs.initial_angle_deg * DEG if inputs.initial_angle_deg is not None else \
        math.pi - inputs.beta_deg * DEG - gamma
    turn = inputs.turn_deg * DEG
    x = ca.SX.sym("x", 8)
    p1n, p2n, p3n, p1k, p2k, p3k, c, L2 = (x[i] for i in range(8))
    common = dict(a=a, b=b, c=c, L2=L2, L3=L3, L4=L4, L5=L5, alpha=alpha, cos=ca.cos, sin=ca.sin)
    g = ca.vertcat(*loop_equations(L1n, p1n, p2n, p3n, phi4n, **common),
                   *loop_equations(L1n + h, p1k, p2k, p3k, phi4n + turn, **common))
    guess_b = [L3 * np.array([math.cos(t), math.sin(t)]) for t in (35 * DEG, 145 * DEG)]
    guess = [math.atan2(B[1] - b, a - B[0]) for B in guess_b]
    x0 = [guess[0], 35 * DEG, 0.0, guess[1], 145 * DEG, 0.0, 0.8 * L5, L3]
    solver = ca.rootfinder("bucket_synthesis", "newton", ca.Function("g", [x], [g]),
                           {"abstol": 1e-14, "max_iter": 100, "error_on_fail": False})
    solution = np.array(solver(x0)).ravel()
    residual = np.abs(np.array(ca.Function("g", [x], [g])(solution)).ravel()).max()
    if not residual < 1e-10 or not solution[6] > 0 or not solution[7] > 0:
        raise InputError(f"six-bar bucket synthesis: no physical solution for Δφ4 = {inputs.turn_deg:g}°, "
                         f"φ4н = {phi4n / DEG:.4g}°, a = {a:.4g} m (residual {residual:.2g}, c = {solution[6]:.4g} m, "
                         f"L2 = {solution[7]:.4g} m); try another a or a smaller turn")
    wrap = [math.remainder(v, 2 * math.pi) for v in solution[:6]]
    return BucketLinkage(inputs, size["Lk"], L3, L4, L5, h, L1n, a, b, alpha, gamma, phi4n, turn,
                         float(solution[6]), float(solution[7]), tuple(wrap[:3]), tuple(wrap[3:]))


def build(linkage: BucketLinkage | None = None) -> Mechanism:
    """The closed-loop model, drawn at the initial position (cylinder retracted, bucket open); actuated ``L1``.

    Coordinates: ``L1`` (cylinder length), ``rocker`` (= φ2, the angle of DB), ``link`` and ``bucket`` (= φ4, the
    bucket angle ∠DFE measured as the angle of FE from +x). Masses are illustrative (bucket 450 kg, rocker 25 kg,
    link 15 kg, cylinder 40 + 20 kg).
    """
    lk = linkage or synthesize()
    pins = lk.pins(lk.L1n, lk.initial, lk.phi4n)
    bucket_centre = pins["F"] + 0.55 * (pins["K"] - pins["F"]) + 0.15 * (pins["E"] - pins["F"])
    b = PlanarBuilder("six_bar_bucket")
    for name in ("A", "D", "F"):
        b.point(name, GROUND, pins[name])
    b.point("stick_end", GROUND, (lk.a + 0.3, 0.0), report=False)
    rocker = b.revolute("rocker", "D", toward=pins["B"], coordinate="phi2", mass=25.0,
                        com=(pins["B"] + pins["C"]) / 3, inertia=25.0 * lk.L3**2 / 12)
    b.point("B", rocker, pins["B"])
    b.point("C", rocker, pins["C"])
    link = b.revolute("link", "C", toward=pins["E"], coordinate="link_angle", mass=15.0,
                      com=(pins["C"] + pins["E"]) / 2, inertia=15.0 * lk.L4**2 / 12)
    b.point("E_link", link, pins["E"], report=False)
    bucket = b.revolute("bucket", "F", toward=pins["E"], coordinate="phi4", mass=450.0, com=bucket_centre,
                        inertia=450.0 * (0.45 * lk.Lk) ** 2)
    b.point("E", bucket, pins["E"])
    b.point("K", bucket, pins["K"])
    b.point("S_bucket", bucket, bucket_centre)
    b.pin("E_link", "E")
    b.cylinder("L1", "A", "B", stroke=(lk.L1n, lk.L1n + lk.stroke), barrel_mass=40.0, rod_mass=20.0)
    b.line("stick", "stick_end", "A", "D", "F")
    b.line("rocker", "D", "B", "C", "D")
    b.line("link", "C", "E")
    b.line("bucket", "F", "E", "K", "F")
    b.transmission_angle("mu_B", "A", "B", "D", "B", minimum_deg=None)
    b.transmission_angle("mu_C", "D", "C", "C", "E")
    b.transmission_angle("mu_E", "C", "E", "F", "E")
    b.lever_arm("cylinder_arm_about_D", "A", "B", "D")
    params = {name: Parameter(name, float(getattr(lk.inputs, name)), kind, description)
              for name, kind, description in (("volume", "ratio", "bucket volume q (m³)"),
                                              ("dead_length", "length", "cylinder dead length H_T"),
                                              ("offset", "length", "offset b of the cylinder eye from the stick line"),
                                              ("turn_deg", "ratio", "required bucket rotation Δφ4 (degrees)"))}

    def rebuild(values: dict[str, float]) -> Mechanism:
        return build(synthesize(replace(lk.inputs, **values)))

    mech = b.build(actuated=["L1"], parameters=params, rebuild=rebuild, tool="K",
                   description=f"six-link bucket mechanism (q = {lk.inputs.volume:g} m³, turn "
                               f"{lk.turn / DEG:.4g}°, c = {lk.c:.4f} m, L2 = {lk.L2:.4f} m)",
                   input_rates={"L1": 0.1},
                   notes=["geometry reconstructed from the loop equations [Bucket, 8]; masses illustrative"])
    final = assemble(mech, {"L1": lk.L1n + lk.stroke})
    reached = final[loop_solver(mech).index["phi4"]] - mech.reference_q[loop_solver(mech).index["phi4"]]
    if abs(reached - lk.turn) > 1e-8:
        raise InputError(f"six-bar bucket: the synthesized mechanism turns the bucket by {reached / DEG:.4g}°, not "
                         f"{lk.turn / DEG:.4g}°: the root lies on another assembly branch")
    return mech


def six_bar_bucket(**overrides: float) -> Mechanism:
    """Six-link bucket mechanism [Bucket] (cylinder + rocker + link + bucket), synthesized for Δφ4.

    ``overrides`` are fields of :class:`BucketInputs` (m³, m, degrees as named)."""
    return build(synthesize(replace(BucketInputs(), **overrides)) if overrides else None)

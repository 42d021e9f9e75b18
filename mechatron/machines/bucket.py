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
- :func:`bucket_spec`: the mechanism file of the result (a :class:`~mechatron.model.linkage.LinkageSpec`, checked to
  turn the bucket by Δφ4), actuated by the cylinder length ``L1``; :func:`write_bucket` writes it. The default
  synthesis ships as ``robots/six_bar_bucket.toml`` (``mechatron.load("six_bar_bucket")``); another design goes
  through the synthesis: ``build_linkage(bucket_spec(synthesize(BucketInputs(turn_deg=150))))``.

The paper's own closed-form analysis [Bucket, 12–22], the reference this model is checked against, is in the test
suite's ``validation/bucket.py``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.linkage import BodySpec, ClosureSpec, JointSpec, LengthSpec, LinkageSpec, MeasureSpec, PointSpec
from ..model.linkage_file import write_linkage_file
from ..model.planar import GROUND

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

    def assembled(self, L1: float) -> dict[str, NDArray[np.float64]]:
        """Pin positions (m) in the stick frame at the cylinder length L1 (m) on the synthesized assembly branch:
        B at L2 from D and L1 from A, E at L5 from F and L4 from C (circle intersections), each on the side of DA
        and of FC where it is at the start."""
        start = self.pins(self.L1n, self.initial, self.phi4n)

        def apex(p: str, Q: NDArray[np.float64], q: str, to_p: float, to_q: float, name: str) -> NDArray[np.float64]:
            P, d = start[p], Q - start[p]
            base = float(np.hypot(*d))
            along = (to_p**2 - to_q**2 + base**2) / (2 * base)
            across = math.sqrt(max(0.0, to_p**2 - along**2))
            u, r = start[q] - P, start[name] - P  # the side of PQ the point is on at the start
            side = math.copysign(1.0, u[0] * r[1] - u[1] * r[0])
            return P + (along * d + side * across * np.array([-d[1], d[0]])) / base

        B = apex("D", start["A"], "A", self.L2, L1, "B")
        phi2 = math.atan2(B[1], B[0])
        C = self.L3 * np.array([math.cos(phi2 + self.alpha), math.sin(phi2 + self.alpha)])
        E = apex("F", C, "C", self.L5, self.L4, "E")
        A, F = start["A"], start["F"]
        phi1, phi3 = math.atan2(B[1] - A[1], A[0] - B[0]), math.atan2(C[1] - E[1], C[0] - E[0])
        return self.pins(L1, (phi1, phi2, phi3), math.atan2(E[1] - F[1], E[0] - F[0]))


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
    L2 = L3, c = 0.8 L5). The root must have c > 0 and L2 > 0; :func:`bucket_spec` then checks by continuation that
    the mechanism reaches the final position on one assembly branch. Lengths in m, angles in rad."""
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


def bucket_spec(linkage: BucketLinkage | None = None) -> LinkageSpec:
    """The mechanism file of a synthesized linkage (default: :func:`synthesize` with the default inputs), drawn in the
    stick frame a quarter of the way along the stroke, L1 = L1н + h/4 (:meth:`BucketLinkage.assembled`): inside the
    stroke, so that every drawn point and length can move either way, and, for the default design, before the link
    passes 180°, so that the joint coordinates continue those of the retracted start without 2π jumps. Actuated by
    the cylinder length ``L1``.

    Coordinates: ``L1`` (cylinder length, m), ``phi2`` (the angle of DB), ``link_angle`` (of CE relative to the
    rocker) and ``phi4`` (the bucket angle ∠DFE, the angle of FE from +x), rad. Named lengths (m): c = |DF|,
    L2 = |DB|, L3 = |DC|, L4 = |CE|, L5 = |FE|, Lk = |FK|; the cylinder eye A is at (a, b) = (A_x, A_y). Masses are
    illustrative (bucket 450 kg, rocker 25 kg, link 15 kg, cylinder 40 + 20 kg).

    Raises:
        InputError: if the mechanism it describes does not turn the bucket by Δφ4 over the stroke from the drawn
            position (the root of :func:`synthesize` lies on another assembly branch).
    """
    lk = linkage or synthesize()
    pins = lk.assembled(lk.L1n + lk.stroke / 4)
    centre = pins["F"] + 0.55 * (pins["K"] - pins["F"]) + 0.15 * (pins["E"] - pins["F"])

    def at(*names: str) -> tuple[PointSpec, ...]:
        return tuple(PointSpec(n, (float(pins[n][0]), float(pins[n][1]))) for n in names)

    def xy(v: NDArray[np.float64]) -> tuple[float, float]:
        return float(v[0]), float(v[1])

    spec = LinkageSpec(
        name="six_bar_bucket",
        description=f"six-link bucket mechanism (q = {lk.inputs.volume:g} m³, turn {lk.turn / DEG:.4g}°, "
                    f"c = {lk.c:.4f} m, L2 = {lk.L2:.4f} m)",
        source="[Bucket]",
        points=(*at("D", "F", "A"),
                PointSpec("stick_end", between=("D", "F"), fraction=-(lk.a + 0.3) / lk.c, report=False),
                *at("B", "C", "E", "K")),
        bodies=(BodySpec(GROUND, ("D", "F", "A", "stick_end"), draw=("stick_end", "A", "D", "F")),
                BodySpec("rocker", ("D", "B", "C"), mass=25.0, com=xy((pins["B"] + pins["C"]) / 3),
                         inertia=25.0 * lk.L3**2 / 12, draw=("D", "B", "C", "D")),
                BodySpec("bucket", ("F", "E", "K"), mass=450.0, com=xy(centre), inertia=450.0 * (0.45 * lk.Lk) ** 2,
                         draw=("F", "E", "K", "F")),
                BodySpec("link", ("C", "E"), mass=15.0, com=xy((pins["C"] + pins["E"]) / 2),
                         inertia=15.0 * lk.L4**2 / 12)),
        joints=(JointSpec("revolute", body="rocker", at="D", toward="B", coordinate="phi2"),
                JointSpec("revolute", body="link", at="C", toward="E", coordinate="link_angle"),
                JointSpec("revolute", body="bucket", at="F", toward="E", coordinate="phi4"),
                JointSpec("cylinder", name="L1", base="A", eye="B", stroke=(lk.L1n, lk.L1n + lk.stroke),
                          barrel_mass=40.0, rod_mass=20.0)),
        actuated=("L1",),
        closures=(ClosureSpec("pin", point="E", bodies=("link", "bucket")),),
        measures=(MeasureSpec("transmission_angle", "mu_B", ("A", "B", "D", "B")),
                  MeasureSpec("transmission_angle", "mu_C", ("D", "C", "C", "E")),
                  MeasureSpec("transmission_angle", "mu_E", ("C", "E", "F", "E")),
                  MeasureSpec("lever_arm", "cylinder_arm_about_D", ("A", "B", "D"))),
        lengths=tuple(LengthSpec(name, points) for name, points in (
            ("c", ("D", "F")), ("L2", ("D", "B")), ("L3", ("D", "C")), ("L4", ("C", "E")), ("L5", ("F", "E")),
            ("Lk", ("F", "K")))),
        tool="K",
        input_rates={"L1": 0.1},
        notes=("geometry reconstructed from the loop equations [Bucket, 8]; masses illustrative",),
    )
    _check_turn(spec, lk)
    return spec


def _check_turn(spec: LinkageSpec, lk: BucketLinkage) -> None:
    """The mechanism of ``spec``, assembled from its drawing at both ends of the stroke, turns the bucket by Δφ4."""
    from ..kinematics.loops import assemble, loop_solver
    from ..model.linkage import build_linkage

    mech = build_linkage(spec)
    index = loop_solver(mech).index["phi4"]
    start, end = (assemble(mech, {"L1": L1})[index] for L1 in (lk.L1n, lk.L1n + lk.stroke))
    if abs(end - start - lk.turn) > 1e-8:
        raise InputError(f"six-bar bucket: the synthesized mechanism turns the bucket by {(end - start) / DEG:.4g}°, "
                         f"not {lk.turn / DEG:.4g}°: the root lies on another assembly branch")


def file_header(lk: BucketLinkage) -> str:
    """The comment heading a written bucket file: the synthesis it comes from, its inputs and results."""
    i = lk.inputs
    return "\n".join([
        "Six-link bucket mechanism [Bucket], written by mechatron.machines.bucket.write_bucket from the synthesis of",
        "c and L2 by the loop equations [Bucket, 8] at the initial and final positions, for",
        f"q = {i.volume:g} m³, α = {i.alpha_deg:g}°, β = {i.beta_deg:g}°, γ = {i.gamma_deg:g}°, "
        f"H_T = {i.dead_length:g} m, b = {lk.b:g} m, a = {lk.a:.6g} m, φ4н = {lk.phi4n / DEG:.6g}°, "
        f"Δφ4 = {lk.turn / DEG:.6g}°:",
        f"c = {lk.c:.9f} m, L2 = {lk.L2:.9f} m. Drawn a quarter of the way along the stroke "
        f"(L1 = {lk.L1n + lk.stroke / 4:.6g} m) in the stick frame:",
        "origin the rocker pivot D, x along the stick from the bucket pivot F towards the cylinder eye A = (a, b).",
        "A new design goes through the synthesis (BucketInputs), not through this file."])


def write_bucket(linkage: BucketLinkage | None, path: str | Path) -> Path:
    """Write the mechanism file (:func:`bucket_spec`) of a synthesized linkage (default: the default inputs') to
    ``path``; the mechanism is named after the file. robots/six_bar_bucket.toml is ``write_bucket(None, ...)``."""
    lk = linkage or synthesize()
    return write_linkage_file(replace(bucket_spec(lk), name=Path(path).stem), path, header=file_header(lk))

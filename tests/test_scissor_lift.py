r"""The scissor lift of examples/data/scissor_lift.toml against its hand closed form (issue 21): a mechanism drawn
the way a user draws it, each arm's pins (foot, crossing pin, top) in line, the crossing pin a derived point carried
by both arms, the cylinder's eye a derived point of arm 1.

- the deck's height h and its x over the cylinder's stroke (assembled model, and the `linkage` sweep with its
  velocities, transmission angle and lever arm);
- the static cylinder force holding the 500 kg platform and the two 30 kg arms (constrained inverse dynamics at
  rest) against virtual work;
- the sensitivities ∂h/∂p, ∂x/∂p of the parameters arm1 (ℓ), arm2, P_x, P_y and of the cylinder length, from
  ``mechatron.accuracy.sensitivity.sensitivities`` and from converged central differences of the rebuilt mechanism,
  against the closed form (1e-8 relative);
- the rebuilt bodies keep their points where the file's rules put them (``--set P_x=…``, ``--set arm1=…``);
- the tolerance study of examples/data/tolerances_scissor_lift.csv: its worst case and RSS are the closed form's, its
  Monte Carlo agrees with them;
- the file runs through ``mechatron show``, ``linkage``, ``tolerance`` and ``dynamics`` (whose work lifting the
  deck is the rise of the potential energy).

Two variants of the file run the same checks on the sensitivities to P_x, P_y and the cylinder length (arms of rigid
drawn shape: the same closed form; not arm1 and arm2, whose change leaves plain points where they are drawn on the
arm, which the closed form does not describe):

- *inline*: the crossing pin and the bracket drawn as plain points, still in line on the arms (the loader of
  issue 21 fixes every point of a body in the body's frame; a loader holding points by distances to two earlier
  points fixes these only to second order, and its sensitivities come out wrong);
- *variant*: the same with an off-line point listed second on each arm (X1, X2), which holds every point by
  well-conditioned distances even so.

The closed form. Ground: foot1 at the origin, foot2 rolling on the line y = 0. Arm 1 (length ℓ = arm1) turns about
foot1 at the angle θ: with e = (cos θ, sin θ) its top is top1 = ℓ e, its crossing pin K = (ℓ/2) e and the bracket
Q = f ℓ e, f = 0.75 (K and Q are derived points between foot1 and top1, which arm 1 carries: they stay at 1/2 and
3/4 of arm 1 whatever its length). Arm 2 (length ℓ2 = arm2, declared from foot2 to top2) carries K at its drawn
place: κ = 0.6 m from foot2, on the line to top2 (arm 2 does not carry foot1 and top1, so K is fixed in it as
drawn; a changed ℓ2 moves top2 along the line from foot2 and leaves K where it is). Its foot on y = 0 with
|foot2 − K| = κ:

    foot2 = ((ℓ/2) cos θ + S, 0),  S = √(κ² − (ℓ/2)² sin² θ)   (the foot on the far side of K),
    top2 = foot2 + λ (K − foot2) = ((ℓ/2) cos θ + (1 − λ) S, λ (ℓ/2) sin θ),  λ = ℓ2/κ.

The platform is pinned at top2 and top1 rolls on its rail, drawn level through top2, so the platform turns by the
angle φ of top1 − top2 = Δ: φ = atan2(Δ_y, Δ_x). The deck, drawn a = 0.6 m right of and b = 0.08 m above top2, is at

    x = top2_x + a cos φ − b sin φ,    h = top2_y + a sin φ + b cos φ.

In the file's design, ℓ = ℓ2 = 2κ: S = (ℓ/2) cos θ, top2 = (0, ℓ sin θ) straight above foot1, level with top1, φ = 0,
so h = ℓ sin θ + b and x = a.

The cylinder from P = (P_x, P_y) to Q: g = |f ℓ e − P|² − c² = 0, i.e. f ℓ (P_x cos θ + P_y sin θ) =
(f²ℓ² + ρ² − c²)/2 with ρ = |P|, α = atan2(P_y, P_x):

    θ = α + arccos k,    k = (f²ℓ² + ρ² − c²)/(2 f ℓ ρ)

(the root with θ − α in (0, π), on which c grows with θ). Implicit derivatives of g, with
G = P_x sin θ − P_y cos θ = ρ sin(θ − α) > 0: g_θ = 2 f ℓ G, g_c = −2c, g_Px = −2(f ℓ cos θ − P_x),
g_Py = −2(f ℓ sin θ − P_y), g_ℓ = 2f (f ℓ − P_x cos θ − P_y sin θ), g_ℓ2 = 0; θ_p = −g_p/g_θ (the cylinder length
is held: the sensitivities are at a fixed input).

The chain rule for a source p: dtop1 = ℓ e⊥ θ_p + e [p = ℓ] (e⊥ = (−sin θ, cos θ)),
dtop2 = ∂top2/∂θ θ_p + ∂top2/∂p with, from S_θ = −ℓ² sin θ cos θ/(4S), S_ℓ = −ℓ sin² θ/(4S),

    ∂top2/∂θ = (−(ℓ/2) sin θ + (1 − λ) S_θ, λ (ℓ/2) cos θ),
    ∂top2/∂ℓ = (cos θ/2 + (1 − λ) S_ℓ, λ sin θ/2),   ∂top2/∂ℓ2 = (−S/κ, (ℓ/2) sin θ/κ),

dφ = (Δ_x dΔ_y − Δ_y dΔ_x)/|Δ|², and dx = dtop2_x − (a sin φ + b cos φ) dφ, dh = dtop2_y + (a cos φ − b sin φ) dφ.

In the design (ℓ = ℓ2 = 2κ, φ = 0) this is, with s = sin θ, c_θ = cos θ:

    ∂h/∂c = ℓ c_θ θ_c,  ∂h/∂P_x = ℓ c_θ θ_Px,  ∂h/∂P_y = ℓ c_θ θ_Py,  ∂x/∂c = ∂x/∂P_x = ∂x/∂P_y = 0,
    ∂h/∂ℓ = s + ℓ c_θ θ_ℓ,  ∂x/∂ℓ = 1/(2 c_θ)   (top2 rises with top1: the platform stays level),
    ∂h/∂ℓ2 = s − a tan θ/ℓ,  ∂x/∂ℓ2 = −c_θ + b tan θ/ℓ   (top2 moves along arm 2 by (−c_θ, s), the platform
                                                        turns by dφ = −tan θ/ℓ about it).

The cylinder's lever arm about foot1 is |P × (Q − P)|/c = f ℓ G/c = 1/θ_c, and the acute angle between the cylinder
and arm 1 is μ = atan2(G, |f ℓ − P_x cos θ − P_y sin θ|) (the cross and dot products of e with Q − P).

Static force (virtual work, F δc = δV): the platform's 500 kg is at the deck (height h), each arm's 30 kg at its
middle (a bar: the middle of its first two points), arm 1's at (ℓ/2) sin θ and arm 2's at top2_y/2 (foot2 is at
y = 0), the cylinder massless: V = g (m_p h + m_a (ℓ/2) sin θ + m_a top2_y/2) + const, so

    F = ∂V/∂c = g (m_p ∂h/∂c + m_a ((ℓ/2) cos θ θ_c + ∂top2_y/∂c/2)) = g (m_p + m_a) ∂h/∂c  in the design,

positive: the cylinder pushes (mechatron's force on the rod coordinate, the length).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.accuracy.sensitivity import sensitivities
from mechatron.accuracy.sources import read_tolerances
from mechatron.cli import main
from mechatron.dynamics.constrained import inverse
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble

ROOT = Path(__file__).resolve().parent.parent
LIFT = ROOT / "examples" / "data" / "scissor_lift.toml"
TOLERANCES = ROOT / "examples" / "data" / "tolerances_scissor_lift.csv"

# the file's numbers (SI)
ARM = 1.2                       # arm1 = arm2 (m), declared
FRACTION = 0.75                 # the bracket Q on arm 1: between foot1 and top1
P_NOMINAL = (0.5, -0.15)        # the cylinder's base pin (m)
DECK = (0.6, 0.08)              # the deck from top2 (m), a platform point
KAPPA = 0.6                     # K's drawn distance from foot2 on arm 2 (m)
M_PLATFORM, M_ARM, GRAVITY = 500.0, 30.0, 9.81
STROKE = (0.5, 0.84)            # m
RATE = 0.05                     # input_rates: m/s
C_DRAWN = math.hypot(0.72 - 0.5, 0.54 + 0.15)   # the drawn cylinder length: Q = (0.72, 0.54), P = (0.5, −0.15)
POSES = (0.52, 0.62, C_DRAWN, 0.80, 0.83)       # cylinder lengths (m) for the sensitivities
PARAMETERS = ("arm1", "arm2", "P_x", "P_y")
VARIANT_PARAMETERS = ("P_x", "P_y")
RTOL = 1e-8
STEPS = (2e-5, 5e-6)            # central differences: steps relative to the parameter


# ------------------------------------------------------------------------------------------------ closed form
def lift(c: float, arm1: float = ARM, arm2: float = ARM, P_x: float = P_NOMINAL[0], P_y: float = P_NOMINAL[1]
         ) -> dict:
    """The closed form of the module docstring at the cylinder length c (m): θ, h, x, the derivatives
    ``dh``/``dx`` by source (cyl, arm1, arm2, P_x, P_y), the static force (N), the lever arm (m), μ (rad) and the
    points (m)."""
    f, ell, ell2, a, b = FRACTION, arm1, arm2, *DECK
    lam = ell2 / KAPPA
    rho, alpha = math.hypot(P_x, P_y), math.atan2(P_y, P_x)
    k = (f * f * ell * ell + rho * rho - c * c) / (2 * f * ell * rho)
    theta = alpha + math.acos(k)
    s, co = math.sin(theta), math.cos(theta)
    e, e_perp = np.array([co, s]), np.array([-s, co])
    S = math.sqrt(KAPPA**2 - (ell / 2) ** 2 * s * s)
    foot2 = np.array([ell / 2 * co + S, 0.0])
    top1, top2 = ell * e, np.array([ell / 2 * co + (1 - lam) * S, lam * ell / 2 * s])
    delta = top1 - top2
    phi = math.atan2(delta[1], delta[0])
    x = top2[0] + a * math.cos(phi) - b * math.sin(phi)
    h = top2[1] + a * math.sin(phi) + b * math.cos(phi)
    # θ_p from the cylinder's equation g = 0
    G = P_x * s - P_y * co
    g_theta = 2 * f * ell * G
    g = {"cyl": -2 * c, "arm1": 2 * f * (f * ell - P_x * co - P_y * s), "arm2": 0.0,
         "P_x": -2 * (f * ell * co - P_x), "P_y": -2 * (f * ell * s - P_y)}
    dtheta = {p: -value / g_theta for p, value in g.items()}
    # the chain rule through top1, top2 and φ
    S_theta, S_ell = -ell * ell * s * co / (4 * S), -ell * s * s / (4 * S)
    top2_theta = np.array([-ell / 2 * s + (1 - lam) * S_theta, lam * ell / 2 * co])
    top1_explicit = {"arm1": e}
    top2_explicit = {"arm1": np.array([co / 2 + (1 - lam) * S_ell, lam * s / 2]),
                     "arm2": np.array([-S / KAPPA, ell / 2 * s / KAPPA])}
    dh, dx, dtop2_y = {}, {}, {}
    for p, t in dtheta.items():
        d_top1 = ell * e_perp * t + top1_explicit.get(p, 0.0)
        d_top2 = top2_theta * t + top2_explicit.get(p, 0.0)
        d_delta = d_top1 - d_top2
        d_phi = (delta[0] * d_delta[1] - delta[1] * d_delta[0]) / (delta @ delta)
        dx[p] = d_top2[0] - (a * math.sin(phi) + b * math.cos(phi)) * d_phi
        dh[p] = d_top2[1] + (a * math.cos(phi) - b * math.sin(phi)) * d_phi
        dtop2_y[p] = d_top2[1]
    force = GRAVITY * (M_PLATFORM * dh["cyl"] + M_ARM * (ell / 2 * co * dtheta["cyl"] + dtop2_y["cyl"] / 2))
    mu = math.atan2(G, abs(f * ell - P_x * co - P_y * s))
    return {"theta": theta, "phi": phi, "h": h, "x": x, "dh": dh, "dx": dx, "force": force, "lever": f * ell * G / c,
            "mu": mu, "points": {"foot1": np.zeros(2), "top1": top1, "K": ell / 2 * e, "Q": f * ell * e,
                                 "foot2": foot2, "top2": top2, "deck": np.array([x, h])}}


def close(actual: float, expected: float, rtol: float = RTOL, scale: float = 1.0) -> bool:
    """|actual − expected| within rtol of max(|expected|, scale): relative, and absolute for an expected zero."""
    return abs(actual - expected) <= rtol * max(abs(expected), scale)


def test_closed_form_against_its_own_finite_differences():
    """Every derivative of :func:`lift` is that of its h and x (central differences of the closed form itself,
    h = 1e-6 m), at nominal and at changed lengths and pin (where ∂x/∂p ≠ 0)."""
    step = 1e-6
    for values in ({}, {"arm1": 1.25, "arm2": 1.17, "P_x": 0.55, "P_y": -0.1}):
        for c in (0.52, 0.65, 0.8):
            nominal = lift(c, **values)
            for p in ("cyl", *PARAMETERS):
                def at(delta):
                    if p == "cyl":
                        return lift(c + delta, **values)
                    given = {"arm1": ARM, "arm2": ARM, "P_x": P_NOMINAL[0], "P_y": P_NOMINAL[1], **values}
                    given[p] += delta
                    return lift(c, **given)
                plus, minus = at(step), at(-step)
                assert (plus["h"] - minus["h"]) / (2 * step) == pytest.approx(nominal["dh"][p], abs=1e-8)
                assert (plus["x"] - minus["x"]) / (2 * step) == pytest.approx(nominal["dx"][p], abs=1e-8)

            def potential(one):  # g (m_p h + m_a y of arm 1's middle + m_a y of arm 2's middle), J
                return GRAVITY * (M_PLATFORM * one["h"] + M_ARM * (one["points"]["top1"][1] + one["points"]["foot2"][1]
                                                                   + one["points"]["top2"][1]) / 2)

            work = (potential(lift(c + step, **values)) - potential(lift(c - step, **values))) / (2 * step)
            assert work == pytest.approx(nominal["force"], rel=1e-8)
            # the cylinder has the length c, its lever arm about foot1 and μ are those of the points
            theta, P = nominal["theta"], np.array([values.get("P_x", P_NOMINAL[0]), values.get("P_y", P_NOMINAL[1])])
            rod = nominal["points"]["Q"] - P
            assert np.linalg.norm(rod) == pytest.approx(c, rel=1e-14)
            assert nominal["lever"] == pytest.approx(abs(P[0] * rod[1] - P[1] * rod[0]) / c, rel=1e-12)
            cosine = abs(rod @ [math.cos(theta), math.sin(theta)]) / c
            assert nominal["mu"] == pytest.approx(math.acos(cosine), abs=1e-12)
            # top1 on the platform's rail: the line through top2 at the platform's angle φ
            delta = nominal["points"]["top1"] - nominal["points"]["top2"]
            assert delta @ [-math.sin(nominal["phi"]), math.cos(nominal["phi"])] == pytest.approx(0.0, abs=1e-14)
            K, foot2 = nominal["points"]["K"], nominal["points"]["foot2"]
            assert np.linalg.norm(K - foot2) == pytest.approx(KAPPA, rel=1e-14)
            assert np.linalg.norm(nominal["points"]["top2"] - foot2) == pytest.approx(values.get("arm2", ARM),
                                                                                      rel=1e-14)


def test_closed_form_of_the_design():
    """At the drawn cylinder length the closed form gives the drawing (θ = asin 0.6, top1 = (0.96, 0.72), the deck
    at (0.6, 0.8)); over the stroke its derivatives are the short formulas of the design (ℓ = ℓ2 = 2κ, φ = 0) in the
    module docstring, and its force g (m_p + m_a) ∂h/∂c."""
    nominal = lift(C_DRAWN)
    assert nominal["theta"] == pytest.approx(math.asin(0.6), abs=1e-14)
    assert nominal["points"]["top1"] == pytest.approx([0.96, 0.72], abs=1e-14)
    assert nominal["points"]["foot2"] == pytest.approx([0.96, 0.0], abs=1e-14)
    assert nominal["points"]["top2"] == pytest.approx([0.0, 0.72], abs=1e-14)
    assert nominal["points"]["Q"] == pytest.approx([0.72, 0.54], abs=1e-14)
    assert (nominal["x"], nominal["h"]) == pytest.approx((0.6, 0.8), abs=1e-14)
    # at the drawing: ∂h/∂ℓ2 = 0.6 − 0.6 · 0.75/1.2 = 0.225 and ∂x/∂ℓ2 = −0.8 + 0.08 · 0.75/1.2 = −0.75
    assert (nominal["dh"]["arm2"], nominal["dx"]["arm2"]) == pytest.approx((0.225, -0.75), abs=1e-14)
    (P_x, P_y), ell, f, (a, b) = P_NOMINAL, ARM, FRACTION, DECK
    for c in np.linspace(*STROKE, 9):
        one = lift(c)
        theta = one["theta"]
        s, co = math.sin(theta), math.cos(theta)
        G = P_x * s - P_y * co
        theta_p = {"cyl": c / (f * ell * G), "P_x": (f * ell * co - P_x) / (f * ell * G),
                   "P_y": (f * ell * s - P_y) / (f * ell * G), "arm1": -(f * ell - P_x * co - P_y * s) / (ell * G)}
        assert one["phi"] == pytest.approx(0.0, abs=1e-14)
        assert (one["x"], one["h"]) == pytest.approx((a, ell * s + b), abs=1e-14)
        for p in ("cyl", "P_x", "P_y"):
            assert one["dh"][p] == pytest.approx(ell * co * theta_p[p], rel=1e-12)
            assert one["dx"][p] == pytest.approx(0.0, abs=1e-12)
        assert one["dh"]["arm1"] == pytest.approx(s + ell * co * theta_p["arm1"], rel=1e-12)
        assert one["dx"]["arm1"] == pytest.approx(1 / (2 * co), rel=1e-12)
        assert one["dh"]["arm2"] == pytest.approx(s - a * math.tan(theta) / ell, rel=1e-12)
        assert one["dx"]["arm2"] == pytest.approx(-co + b * math.tan(theta) / ell, rel=1e-12)
        assert one["force"] == pytest.approx(GRAVITY * (M_PLATFORM + M_ARM) * one["dh"]["cyl"], rel=1e-12)
    # the design: the deck from 0.31 m to 0.99 m over the stroke, the force from 14.1 kN to 7.9 kN
    low, high = lift(STROKE[0]), lift(STROKE[1])
    assert (round(low["h"], 2), round(high["h"], 2)) == (0.31, 0.99)
    assert (round(low["force"] / 1e3, 1), round(high["force"] / 1e3, 1)) == (14.1, 7.9)


# ----------------------------------------------------------------------------------------------- mechanisms
def inline_text() -> str:
    """The file with the crossing pin and the bracket drawn as plain points, at the closed form's places: still in
    line on arm 1 (and K on arm 2), as the file draws them."""
    text = LIFT.read_text(encoding="utf-8")
    for old, new in [('K = { between = ["foot1", "top1"], fraction = 0.5 }', "K = [0.48, 0.36]"),
                     ('Q = { between = ["foot1", "top1"], fraction = 0.75 }', "Q = [0.72, 0.54]")]:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


def variant_text() -> str:
    """The in-line file (:func:`inline_text`) with an off-line point listed second on each arm, X1 and X2 (the arms'
    centres of mass given, as a bar's centre would be the middle of foot1 and X1)."""
    text = inline_text().replace("K = [0.48, 0.36]", "K = [0.48, 0.36]\nX1 = [0.3, 0.5]\nX2 = [0.7, 0.6]")
    for old, new in [('points = ["foot1", "top1", "K", "Q"]', 'points = ["foot1", "X1", "top1", "K", "Q"]'),
                     ('points = ["foot2", "top2", "K"]', 'points = ["foot2", "X2", "top2", "K"]')]:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    text, count = re.subn(r'^shape = "bar".*$', f'com = "K"\ninertia = {M_ARM * ARM**2 / 12!r}', text, flags=re.M)
    assert count == 2
    return text


@pytest.fixture(scope="module")
def shipped() -> mechatron.Mechanism:
    return mechatron.load(LIFT)


@pytest.fixture(scope="module")
def variant(tmp_path_factory) -> mechatron.Mechanism:
    path = tmp_path_factory.mktemp("scissor") / "scissor_lift_variant.toml"
    path.write_text(variant_text(), encoding="utf-8")
    return mechatron.load(path)


@pytest.fixture(scope="module")
def inline(tmp_path_factory) -> mechatron.Mechanism:
    path = tmp_path_factory.mktemp("scissor") / "scissor_lift_inline.toml"
    path.write_text(inline_text(), encoding="utf-8")
    return mechatron.load(path)


@pytest.fixture(params=["shipped", "inline", "variant"])
def case(request) -> tuple[mechatron.Mechanism, tuple[str, ...]]:
    """(mechanism, the parameters whose sensitivities the closed form gives): the shipped file with all four; the
    in-line and the off-line variants with P_x and P_y (with plain points K and Q, a changed arm length leaves them
    where they are drawn on the arm, which the closed form does not describe)."""
    mech = request.getfixturevalue(request.param)
    return mech, PARAMETERS if request.param == "shipped" else VARIANT_PARAMETERS


def deck(mech: mechatron.Mechanism, q) -> np.ndarray:
    return frame_placement(mech, q, "deck").translation[:2]


def test_height_and_x_over_the_stroke(case):
    """h and x of the deck at 35 cylinder lengths over the stroke, to 1e-9 m; the platform stays level, the points
    where the closed form puts them."""
    mech, _ = case
    q = None
    for c in np.linspace(*STROKE, 35):
        q = assemble(mech, {"cyl": c}, guess=q)
        expected = lift(c)
        assert deck(mech, q) == pytest.approx([expected["x"], expected["h"]], abs=1e-9)
        for point, where in expected["points"].items():
            assert frame_placement(mech, q, point).translation[:2] == pytest.approx(where, abs=1e-9), point
        assert frame_placement(mech, q, "K@arm2").translation[:2] == pytest.approx(expected["points"]["K"], abs=1e-9)
        rotation = frame_placement(mech, q, "platform").rotation
        assert math.atan2(rotation[1, 0], rotation[0, 0]) == pytest.approx(0.0, abs=1e-9)


def test_static_cylinder_force(case):
    """The cylinder force holding the platform and the arms at rest (constrained inverse dynamics) is the virtual
    work's F = g (m_p + m_a) ∂h/∂c, to 1e-7 relative."""
    mech, _ = case
    zero = np.zeros(mech.nv)
    for c in np.linspace(*STROKE, 9):
        forces, _ = inverse(mech, assemble(mech, {"cyl": c}), zero, zero)
        assert forces["cyl"] == pytest.approx(lift(c)["force"], rel=1e-7)


def test_sensitivities_against_the_closed_form(case):
    """``sensitivities`` of the deck to the parameters and the cylinder length at five poses, to 1e-8 relative."""
    mech, parameters = case
    Q = np.array([assemble(mech, {"cyl": c}) for c in POSES])
    sens = sensitivities(mech, Q, "deck", parameters=list(parameters), coordinates=["cyl"])
    assert sens.sources == (*parameters, "cyl")
    for i, c in enumerate(POSES):
        expected = lift(c)
        for k, p in enumerate(sens.sources):
            got_x, got_h = sens.matrix[i, 0, k], sens.matrix[i, 1, k]
            assert close(got_h, expected["dh"][p]), f"∂h/∂{p} at c = {c:.4g} m: {got_h:.10g}, " \
                                                     f"closed form {expected['dh'][p]:.10g}"
            assert close(got_x, expected["dx"][p]), f"∂x/∂{p} at c = {c:.4g} m: {got_x:.10g}, " \
                                                     f"closed form {expected['dx'][p]:.10g}"


def central_difference(mech: mechatron.Mechanism, name: str, c: float, step: float) -> np.ndarray:
    """(∂x/∂p, ∂h/∂p) by central differences of the mechanism rebuilt at p ± step, assembled at the cylinder length
    c."""
    value = mech.parameter_values()[name]
    ends = []
    for sign in (1, -1):
        other = mech.with_parameters({name: value + sign * step})
        ends.append(deck(other, assemble(other, {"cyl": c})))
    return (ends[0] - ends[1]) / (2 * step)


def test_sensitivities_against_converged_central_differences(case):
    """Central differences of the rebuilt mechanism, steps 2e-5 and 5e-6 of the parameter (relative), agree with
    each other and with the closed form to 1e-8 relative (the closed form's own truncation error at these steps is
    below 4e-9: :func:`test_closed_form_truncation_at_the_steps`)."""
    mech, parameters = case
    values = mech.parameter_values()
    for c in (0.55, C_DRAWN, 0.82):
        expected = lift(c)
        for p in parameters:
            coarse, fine = (central_difference(mech, p, c, rel * abs(values[p])) for rel in STEPS)
            for axis, key in enumerate(("dx", "dh")):
                want = expected[key][p]
                assert close(coarse[axis], fine[axis], scale=max(1.0, abs(want))), \
                    f"{key}/d{p} at c = {c:.4g} m: steps 2e-5 and 5e-6 give {coarse[axis]:.10g} and {fine[axis]:.10g}"
                assert close(fine[axis], want), f"{key}/d{p} at c = {c:.4g} m: central differences " \
                                                f"{fine[axis]:.10g}, closed form {want:.10g}"
                assert close(coarse[axis], want)


def test_closed_form_truncation_at_the_steps():
    """The steps of the central differences above are small enough: on the closed form itself both steps agree
    with its derivatives to 4e-9 relative (at 1e-4 the truncation error h² h'''/6 reaches 8e-8, too much for
    1e-8)."""
    nominal = {"arm1": ARM, "arm2": ARM, "P_x": P_NOMINAL[0], "P_y": P_NOMINAL[1]}
    for c in (0.55, C_DRAWN, 0.82):
        expected = lift(c)
        for p in PARAMETERS:
            for rel in STEPS:
                step = rel * abs(nominal[p])
                plus, minus = lift(c, **{**nominal, p: nominal[p] + step}), lift(c, **{**nominal, p: nominal[p] - step})
                assert close((plus["h"] - minus["h"]) / (2 * step), expected["dh"][p], rtol=4e-9)
                assert close((plus["x"] - minus["x"]) / (2 * step), expected["dx"][p], rtol=4e-9)


# ------------------------------------------------------------------------------------- rebuilt bodies (rules)
@pytest.mark.parametrize("values", [{"P_x": 0.6}, {"P_y": -0.1}, {"arm1": 1.25}, {"arm2": 1.23},
                                    {"arm1": 1.17, "arm2": 1.18, "P_x": 0.45}],
                         ids=lambda v: ",".join(f"{k}={x}" for k, x in v.items()))
def test_rebuilt_lift_keeps_its_bodies(shipped, values):
    """A changed pin P or arm length (``--set``) gives the closed form's lift at every cylinder length, to 1e-9 m:
    arm 1's top moved along the arm (radially from foot1), K and Q at 1/2 and 3/4 of the new arm 1; arm 2's top
    moved along arm 2 (radially from foot2), K still 0.6 m from foot2 on arm 2; the platform turned to keep top1 on
    its rail."""
    other = shipped.with_parameters(values)
    for name in ("arm1", "arm2"):
        assert other.parameter_values()[name] == pytest.approx(values.get(name, ARM), abs=1e-12)
    q = None
    for c in np.linspace(0.55, 0.82, 7):
        q = assemble(other, {"cyl": c}, guess=q)
        expected = lift(c, **values)
        for point, where in expected["points"].items():
            assert frame_placement(other, q, point).translation[:2] == pytest.approx(where, abs=1e-9), point
        assert frame_placement(other, q, "K@arm2").translation[:2] == pytest.approx(expected["points"]["K"], abs=1e-9)
        rotation = frame_placement(other, q, "platform").rotation
        assert math.atan2(rotation[1, 0], rotation[0, 0]) == pytest.approx(expected["phi"], abs=1e-9)


# ------------------------------------------------------------------------------------------ tolerance study
def test_tolerance_study_linear_and_monte_carlo(case):
    """The study of tolerances_scissor_lift.csv at three poses: worst case Σ|∂r/∂e| t and RSS 3√Σ(∂r/∂e σ)² per
    axis are the closed form's (1e-8 relative); the Monte Carlo of the full model (small tolerances: second-order
    effects ~1e-3 of the first) gives per axis |mean| + 3 std within 5 % of the RSS (sampling spread of the 3σ
    estimate from 4000 samples: about 1.1 %)."""
    mech, parameters = case
    sources = [s for s in read_tolerances(TOLERANCES, mech) if s.name in (*parameters, "cyl")]
    poses = np.array([[0.55], [C_DRAWN], [0.82]])
    result = mechatron.tolerance_study(mech, sources, poses, methods=["worst", "rss", "mc"], samples=4000, seed=1)
    table = result.poses
    sigma = {s.name: s.sigma(3.0) for s in sources}
    tolerance = {s.name: s.tolerance for s in sources}
    assert tolerance == pytest.approx({n: t for n, t in {"arm1": 2e-4, "P_x": 5e-4, "P_y": 5e-4, "cyl": 5e-4}.items()
                                       if n in tolerance}, abs=1e-15)
    for i, c in enumerate(poses[:, 0]):
        expected = lift(c)
        for axis, key in (("x", "dx"), ("y", "dh")):
            worst = sum(abs(expected[key][n]) * tolerance[n] for n in tolerance)
            rss = 3 * math.sqrt(sum((expected[key][n] * sigma[n]) ** 2 for n in sigma))
            scale = sum(tolerance.values())  # a zero sensitivity within 1e-8 m/m, as in the tests above
            assert close(table[f"d{axis}_worst"][i], worst, scale=scale), (axis, c)
            assert close(table[f"d{axis}_rss"][i], rss, scale=scale), (axis, c)
            if rss > 1e-3 * scale:
                assert table[f"d{axis}_mc"][i] == pytest.approx(rss, rel=0.05), (axis, c)
            else:  # the variant's x moves with none of its sources: the Monte Carlo's too is rounding
                assert table[f"d{axis}_mc"][i] < 1e-8 * scale
        assert table["failed_mc"][i] == 0


# ----------------------------------------------------------------------------------------------- the commands
def test_linkage_sweep_follows_the_closed_form(shipped):
    """``linkage`` sweeps the stroke at 0.05 m/s: the deck's height and vertical speed dh/dc · ċ, the transmission
    angle and the lever arm as the closed form gives them."""
    table = mechatron.sweep(shipped, samples=20).table
    assert len(table) == 20
    assert table["cyl"].iloc[0] == pytest.approx(STROKE[0]) and table["cyl"].iloc[-1] == pytest.approx(STROKE[1])
    for _, row in table.iterrows():
        expected = lift(row["cyl"])
        assert row["deck_y"] == pytest.approx(expected["h"], abs=1e-9)
        assert row["deck_x"] == pytest.approx(expected["x"], abs=1e-9)
        assert row["deck_vy"] == pytest.approx(expected["dh"]["cyl"] * RATE, abs=1e-9)
        assert row["deck_vx"] == pytest.approx(0.0, abs=1e-9)
        assert row["mu"] == pytest.approx(expected["mu"], abs=1e-9)
        assert row["cylinder_arm"] == pytest.approx(expected["lever"], abs=1e-9)
    assert math.degrees(table["mu"].min()) > 25


@pytest.mark.parametrize("argv", [
    ["show", str(LIFT)],
    ["linkage", str(LIFT), "--samples", "20"],
    ["tolerance", str(LIFT), "--tolerances", str(TOLERANCES), "--method", "mc", "--samples", "500"],
    ["tolerance", str(LIFT), "--tolerances", str(TOLERANCES), "--method", "all", "--samples", "500"],
    ["dynamics", str(LIFT), "--move", "0.55;0.8", "--vmax", "0.05", "--amax", "0.1"],
], ids=["show", "linkage", "tolerance-mc", "tolerance-all", "dynamics"])
def test_commands_run(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 0 and out, err


def test_dynamics_lifts_with_the_work_of_the_potential_energy(capsys):
    """``mechatron dynamics --move 0.55;0.8``: from rest to rest, the cylinder never pulls (the deck rises slowly),
    so its positive work is the rise of the potential energy g (m_p + m_a) (h(0.8) − h(0.55)) = 2583.6 J (up to
    the quadrature of the sampled power, 1e-4)."""
    code = main(["dynamics", str(LIFT), "--move", "0.55;0.8", "--vmax", "0.05", "--amax", "0.1", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    (cylinder,) = json.loads(out)["coordinates"]
    assert cylinder["coordinate"] == "cyl" and cylinder["unit"] == "N"
    rise = GRAVITY * (M_PLATFORM + M_ARM) * (lift(0.8)["h"] - lift(0.55)["h"])
    assert rise == pytest.approx(2583.6, abs=0.05)
    assert cylinder["positive_work"] == pytest.approx(rise, rel=1e-4)

"""Scissor lifts of many stages (mechatron.machines.scissor) against their closed form, and a drawing of 1,000 points.

With every arm at the angle θ to the horizontal, the cylinder from P (distance ρ, angle α from the fixed foot) to the
bracket at fraction f of arm a0 has the length c² = f²ℓ² + ρ² − 2fℓρ cos(θ − α), so θ = α + arccos((f²ℓ² + ρ² −
c²)/(2fℓρ)) on the drawn branch, and dθ/dc = c/(fℓρ sin(θ − α)). The deck is at h = nℓ sin θ + e. The platform's M
and the 2n arms' m (centres at (i + ½) ℓ sin θ) have the potential energy V = gℓ sin θ (nM + n²m) + const, so the
cylinder holds the lift at rest with F = dV/dc = gℓ cos θ (dθ/dc)(nM + n²m) (virtual work)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.dynamics.constrained import inverse
from mechatron.machines.scissor import ScissorLift, scissor_lift_spec, write_scissor_lift
from mechatron.model.linkage import build_linkage

G = 9.81


def closed_form(lift: ScissorLift, c: float) -> tuple[float, float]:
    """(deck height h (m), static cylinder force F (N)) at the cylinder length c (module docstring)."""
    px, py = lift.base
    rho, alpha, f, ell = math.hypot(px, py), math.atan2(py, px), lift.fraction, lift.arm
    theta = alpha + math.acos((f * f * ell * ell + rho * rho - c * c) / (2 * f * ell * rho))
    dtheta = c / (f * ell * rho * math.sin(theta - alpha))
    n = lift.stages
    h = n * ell * math.sin(theta) + lift.deck
    force = G * ell * math.cos(theta) * dtheta * (n * lift.platform_mass + n * n * lift.arm_mass)
    return h, force


@pytest.mark.parametrize("stages", [1, 3])
def test_height_and_cylinder_force_of_an_n_stage_lift(stages):
    lift = ScissorLift(stages=stages)
    mech = build_linkage(scissor_lift_spec(lift))
    assert mech.mobility() == 1 and not mech.notes  # drawn exactly: nothing to close
    zero = np.zeros(mech.nv)
    for c in np.linspace(lift.stroke[0], lift.stroke[1], 7):
        q = mechatron.assemble(mech, {"cyl": c})
        h, force = closed_form(lift, c)
        assert mechatron.frame_placement(mech, q).translation[1] == pytest.approx(h, abs=1e-10)
        forces, _ = inverse(mech, q, zero, zero)
        assert forces["cyl"] == pytest.approx(force, rel=1e-8)


def test_a_drawing_of_a_thousand_points_loads_and_is_right(tmp_path):
    """Five stages whose arms carry their outlines (49 drawn points along each long edge): 1,002 points, 2,004 point
    coordinates and 10 named lengths as parameters. The file loads (closing its loops in joint space costs what its
    15 bodies cost, not what its points do: benchmarks/large_mechanism.py times it) and the lift is the closed form."""
    lift = ScissorLift(stages=5, edge_points=49)
    path = write_scissor_lift(tmp_path / "lift.toml", lift)
    mech = mechatron.load(path)
    spec = scissor_lift_spec(lift)
    assert len(spec.points) >= 1000 and len(mech.parameters) == 2 * (len(spec.points) - 6) + 10
    h, force = closed_form(lift, 0.7)
    q = mechatron.assemble(mech, {"cyl": 0.7})
    assert mechatron.frame_placement(mech, q).translation[1] == pytest.approx(h, abs=1e-10)
    forces, _ = inverse(mech, q, np.zeros(mech.nv), np.zeros(mech.nv))
    assert forces["cyl"] == pytest.approx(force, rel=1e-8)
    # every outline point stays on its arm: the corner points of a0's edges at ±edge/2 from the line L0–R1
    a, b = (mechatron.frame_placement(mech, q, n).translation[:2] for n in ("L0", "R1"))
    unit = (b - a) / np.linalg.norm(b - a)
    for k in range(2 * lift.edge_points):
        p = mechatron.frame_placement(mech, q, f"a0_edge{k}").translation[:2]
        assert abs(unit[0] * (p - a)[1] - unit[1] * (p - a)[0]) == pytest.approx(lift.edge / 2, abs=1e-12)


def test_a_thousand_points_read_off_paper_close():
    """The same drawing with every point up to 1 mm off and the arms' lengths declared: the loader closes the loops
    (the arms keep their declared 1.2 m, the crossing pins their places on the arms), notes the moves, and the lift
    differs from the exact one only by what the drawn-off pins change (within 1 cm at the deck)."""
    lift = ScissorLift(stages=5, edge_points=49)
    spec = scissor_lift_spec(lift)
    rng = np.random.default_rng(1)
    off = spec.with_positions({name: xy + rng.uniform(-1e-3, 1e-3, 2) for name, xy in spec.drawing().items()})
    mech = build_linkage(off)
    assert mech.notes[-1].startswith("the drawing was closed by moving")
    q = mechatron.assemble(mech, {"cyl": 0.7}, guess=mech.reference_q)
    for i in range(lift.stages):
        ends = [mechatron.frame_placement(mech, q, n).translation[:2] for n in (f"L{i}", f"R{i + 1}")]
        assert math.dist(*ends) == pytest.approx(lift.arm, abs=1e-12)
    assert mechatron.frame_placement(mech, q).translation[1] == pytest.approx(closed_form(lift, 0.7)[0], abs=1e-2)

"""Cylinders that explain themselves (issue 25, item 3): the deciding check is the one that binds, the lighter rows
that were rejected are listed with the checks they fail and by how much, and the pump draws the pressure the loads
need — against hand calculations, Euler's load and the energy balance of a lift raised and lowered by gravity.

The rated pressure is a pass/fail filter (rating p_r ≥ relief pressure p_s): its "margin" 1 − p_s/p_r is 0 for every
row rated at the system pressure, by construction, and says nothing of the load. The checks that can bind are the
push and pull pressure (p = F/A against min(p_r, p_s): margin 1 − F/(p A), the force left) and rod buckling (F
against F_E/3.5, F_E = π² E (π d⁴/64)/(K L)²); the stroke is a filter too since issue 32 (its margin is the row's
stroke left, no load).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.cylinders import BINDING, BUCKLING_SAFETY, FILTERS, size_cylinder
from mechatron.drives.duty import JointDuty
from mechatron.drives.hydraulics import hydraulic_supply
from mechatron.dynamics.task import read_task
from mechatron.io.data import data_dir
from mechatron.model import Cylinder

E = 2.1e11  # Pa, steel
G = 9.81  # m/s², the scissor lift's file


def duty_of(t, speed, force, stroke=0.8, name="L") -> JointDuty:
    return JointDuty(name, "cylinder", t, speed, np.gradient(speed, t), force, force, 0.0, stroke)


def row(key, bore, rod, rated=32e6, stroke=3.0, mass=10.0, per_stroke=0.0, price=100.0) -> dict:
    return {"key": key, "bore": bore, "rod": rod, "max_stroke": stroke, "max_pressure": rated, "mass": mass,
            "mass_per_stroke": per_stroke, "price": price}


def allowed(rod: float, buckling_length: float) -> float:
    """Euler's load of a steel rod of diameter ``rod`` over ``buckling_length`` (m), over the safety 3.5 (N)."""
    return math.pi**2 * E * (math.pi * rod**4 / 64) / buckling_length**2 / 3.5


# ------------------------------------------------------------------------------------------- the deciding check
def test_the_rated_pressure_is_a_filter_and_the_binding_check_decides():
    """A push of 100 kN on one cylinder, 1.0 → 1.8 m, pinned at both ends, 32 MPa. Catalog (mass order):

    - R 100/56 rated 25 MPa: fails the rating, 32/25 = 1.28, and buckling, 100 kN of 88 232 N: ×1.13 (its push,
      100 kN/7.854e-3 m² = 12.73 MPa, would pass);
    - S 100/45: Euler at L = 1.8 m, π² E (π 0.045⁴/64)/1.8² /3.5 = 36 790 N: buckling ×2.718;
    - C 100/63 rated 32 MPa, chosen: push 12.73 MPa of 32 (margin 60.21 %), buckling 100 kN of
      π² E (π 0.063⁴/64)/1.8²/3.5 = 141 331 N (margin 29.24 %), stroke 0.8 of 3 m (73.3 %): buckling decides;
    - H 125/70 rated 40 MPa, heavier: a rating 'margin' 1 − 32/40 = 20 %, never its deciding check.
    """
    t = np.linspace(0.0, 1.0, 201)
    duty = duty_of(t, np.full_like(t, 0.8), np.full_like(t, 100e3))
    spec = Cylinder("L", "A", "B", (1.0, 1.8))
    catalog = pd.DataFrame([row("R", 0.1, 0.056, rated=25e6, mass=9.0), row("S", 0.1, 0.045, mass=9.5),
                            row("C", 0.1, 0.063, mass=10.0), row("H", 0.125, 0.07, rated=40e6, mass=20.0)])
    sized = size_cylinder(duty, spec, catalog, pressure=32e6)
    assert sized.feasible and sized.cylinder == "C"
    checks = {c.name: c for c in sized.checks}
    assert checks["rated pressure"].margin == 0.0 and sized.is_filter(checks["rated pressure"])
    push = 100e3 / (math.pi * 0.1**2 / 4)
    assert checks["push pressure"].value == pytest.approx(push) and push == pytest.approx(12.732e6, rel=1e-4)
    assert checks["push pressure"].margin == pytest.approx(1 - push / 32e6)
    assert allowed(0.063, 1.8) == pytest.approx(141331, rel=1e-5)
    assert (allowed(0.045, 1.8), allowed(0.056, 1.8)) == pytest.approx((36790, 88232), rel=1e-4)
    assert checks["rod buckling"].limit == pytest.approx(allowed(0.063, 1.8), rel=1e-12)
    deciding = sized.deciding()
    assert deciding.name == "rod buckling" and deciding.margin == pytest.approx(1 - 100e3 / allowed(0.063, 1.8))
    assert sized.smallest_margin() == deciding.margin == pytest.approx(0.29244, abs=1e-5)
    data = sized.as_dict()
    assert data["deciding_check"]["name"] == "rod buckling"
    assert [c["filter"] for c in data["checks"]] == [c.name in FILTERS for c in sized.checks]
    assert set(BINDING) | set(FILTERS) == {c.name for c in sized.checks}
    # the rejected lighter rows, nearest first, with the check each fails and its load factor
    assert list(sized.rivals["cylinder"]) == ["S", "R"]
    assert sized.rivals["worst_load_factor"].tolist() == pytest.approx([100e3 / allowed(0.045, 1.8), 32 / 25],
                                                                       rel=1e-12)
    assert list(sized.rivals["failed"]) == ["rod buckling ×2.72", "rated pressure ×1.28; rod buckling ×1.13"]
    assert [r["cylinder"] for r in data["rejected"]] == ["S", "R"]
    text = str(sized)
    assert "deciding check: rod buckling, margin 29.2%" in text and "rated pressure ×1.28" in text
    assert "lighter rows rejected" in text and "filter  PASS" in text
    # the heavier row rated 40 MPa alone: its rating 'margin' (20 %) is not its deciding check
    alone = size_cylinder(duty, spec, catalog.iloc[[3]].reset_index(drop=True), pressure=32e6)
    rating = next(c for c in alone.checks if c.name == "rated pressure")
    assert rating.margin == pytest.approx(0.2) and alone.deciding().name != "rated pressure"
    assert alone.deciding().margin > rating.margin and alone.rivals.empty


def test_cheaper_rows_for_the_cost_objective_and_none_for_the_margin_objective():
    """Ranked by cost, the rejected rows are the cheaper ones; by margin there are none (as for motors). The margin
    objective ranks by the binding checks, never by the rating: H (125/70: buckling 100 kN of 215.4 kN, margin
    53.6 %) before C (29.2 %) — with the rating, their smallest margins were its 20 % and 0 %."""
    t = np.linspace(0.0, 1.0, 201)
    duty = duty_of(t, np.full_like(t, 0.8), np.full_like(t, 100e3))
    spec = Cylinder("L", "A", "B", (1.0, 1.8))
    catalog = pd.DataFrame([row("S", 0.1, 0.045, mass=5.0, price=50.0), row("C", 0.1, 0.063, mass=10.0, price=80.0),
                            row("H", 0.125, 0.07, rated=40e6, mass=20.0, price=60.0)])
    cost = size_cylinder(duty, spec, catalog, pressure=32e6, objective="cost")
    assert cost.cylinder == "H" and list(cost.rivals["cylinder"]) == ["S"]
    assert "cheaper rows rejected" in str(cost)
    margin = size_cylinder(duty, spec, catalog, pressure=32e6, objective="margin")
    h = 1 - 100e3 / allowed(0.07, 1.8)  # H's buckling margin, its smallest of the binding checks
    assert margin.cylinder == "H" and margin.smallest_margin() == pytest.approx(h, rel=1e-12)
    assert margin.ranking["smallest_margin"].tolist() == pytest.approx([h, 1 - 100e3 / allowed(0.063, 1.8)])
    assert margin.rivals.empty


def test_a_failing_rating_still_decides_an_infeasible_cylinder():
    """Rated 25 MPa in a 40 MPa system: no row passes; the deciding check is the failing filter (margin −60 %)."""
    t = np.linspace(0, 1, 101)
    duty = duty_of(t, 0.1 * np.ones_like(t), np.full_like(t, 1e6 * math.pi * 0.05**2))
    sized = size_cylinder(duty, Cylinder("L", "A", "B", (1.0, 1.8)), pd.DataFrame([row("R", 0.1, 0.056, 25e6)]),
                          pressure=40e6)
    assert not sized.feasible and sized.deciding().name == "rated pressure"
    assert sized.deciding().margin == pytest.approx(-0.6) and sized.smallest_margin() == pytest.approx(-0.6)
    assert sized.rivals.empty


# ------------------------------------------------------------------------------------------- the front shovel
def test_front_shovel_no_deciding_check_by_construction_and_the_lighter_rows_rejected(capsys):
    """`mechatron size front_shovel`: every cylinder's deciding check is one that binds, with a margin > 0, the
    smallest of those checks; every lighter catalog row is listed as rejected with the check it fails, and a
    rejected row's rod buckling load factor is F (K L)² 3.5 / (π² E π d⁴/64) at the chosen row's pose (the pose of
    the largest F⁺ (K L)², the same for every row of one fixing)."""
    assert main(["size", "front_shovel", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    catalog = default_catalog("cylinders").set_index("key")
    mech = mechatron.load("front_shovel")
    for joint in data["joints"]:
        deciding = joint["deciding_check"]
        binding = [c for c in joint["checks"] if not c["filter"]]
        assert deciding["name"] in BINDING and deciding["margin"] > 0
        assert deciding["margin"] == min(c["margin"] for c in binding)
        spec = mech.cylinders[joint["joint"]]
        stroke = spec.stroke[1] - spec.stroke[0]
        mass = (catalog["mass"] + catalog["mass_per_stroke"] * stroke) * spec.count
        lighter = set(catalog.index[mass < joint["drive_mass_kg"] * (1 - 1e-12)])
        rejected = joint["rejected"]
        assert lighter and {r["cylinder"] for r in rejected} == lighter
        assert [r["mass"] for r in rejected] == sorted((r["mass"] for r in rejected), reverse=True)  # nearest first
        buckling = next(c for c in joint["checks"] if c["name"] == "rod buckling")
        for r in rejected:
            assert r["failed"] != "none" and r["worst_load_factor"] > 1
            d = catalog.loc[r["cylinder"], "rod"]
            factor = buckling["value"] * joint["buckling_length"] ** 2 * BUCKLING_SAFETY / (
                math.pi**2 * E * math.pi * d**4 / 64)
            rated = 32e6 / catalog.loc[r["cylinder"], "max_pressure"]
            assert r["worst_load_factor"] == pytest.approx(max(factor, rated), rel=1e-9)
            if factor > 1:
                assert f"rod buckling ×{factor:.2f}" in r["failed"]
            if rated > 1:
                assert f"rated pressure ×{rated:.2f}" in r["failed"]
        assert any("rod buckling" in r["failed"] for r in rejected)
    assert main(["size", "front_shovel"]) == 0
    text = capsys.readouterr().out
    assert "deciding check: rated pressure" not in text and "margin 0.0%" not in text
    assert text.count("lighter rows rejected") == 3 and "HC140/90-32 (" in text


def test_the_html_report_lists_the_rejected_rows(tmp_path):
    """The HTML report's section of each cylinder has a table of its rejected lighter rows."""
    result = mechatron.size(mechatron.load("front_shovel"))
    report = result.report()
    for j in result.joints:
        (section,) = [s for s in report.sections if s.title == f"Joint {j.joint}"]
        (table,) = [item for item in section.items if getattr(item, "name", "") == f"rejected {j.joint}"]
        assert list(table.frame["cylinder"]) == list(j.rivals["cylinder"]) and len(table.frame)
        assert not any("deciding check: rated pressure" in getattr(item, "text", "") for item in section.items)


# ------------------------------------------------------------------------------------------------ pump energy
def scissor_energy(c: float) -> float:
    """The scissor lift's potential energy (J, + const) at the cylinder length c (m), in closed form: arm 1 at
    θ = α + arccos((f²ℓ² + ρ² − c²)/(2 f ℓ ρ)) (P at distance ρ, angle α from the fixed foot; the bracket at f ℓ), the
    deck level at ℓ sin θ + 0.08 m, the two 30 kg arms' centres at (ℓ/2) sin θ: V = g ℓ sin θ (500 + 30) kg."""
    f, ell, (px, py) = 0.75, 1.2, (0.5, -0.15)
    rho, alpha = math.hypot(px, py), math.atan2(py, px)
    theta = alpha + math.acos((f * f * ell * ell + rho * rho - c * c) / (2 * f * ell * rho))
    return G * ell * math.sin(theta) * (500.0 + 30.0)


def test_a_lift_lowered_by_gravity_draws_its_lifting_work():
    """The scissor lift of examples/data raised from 0.55 to 0.80 m of cylinder length and lowered back by gravity
    (examples/design/scissor_lift_task.toml, rest to rest): the cylinder always pushes (F > 0), so raising it takes
    F v ≥ 0 and the pump draws the rise of the potential energy, V(0.80) − V(0.55) = 2583.6 J (up to the trapezoidal
    rule over the 20 ms samples); lowering, the load drives the cylinder (F v < 0), a counterbalance valve holds it,
    and the pump draws nothing. Before issue 25 the pump took the 32 MPa relief pressure for all the oil in both
    directions: p_s ∫Q dt = 17.07 kJ, 6.6 times the lifting work, still reported as energy_at_relief."""
    lift = mechatron.load(data_dir("examples/data") / "scissor_lift.toml")
    task = read_task(data_dir("examples/design") / "scissor_lift_task.toml", lift)
    result = mechatron.size(lift, task)
    (joint,) = result.joints
    rise = scissor_energy(0.80) - scissor_energy(0.55)
    assert rise == pytest.approx(2583.6, abs=0.05)
    assert joint.duty.torque.min() > 0  # it pushes throughout: gravity lowers it
    pump = result.hydraulic_supply().rows()[-1]
    assert pump["energy"] == pytest.approx(rise, rel=1e-4)
    assert result.totals()["energy_per_cycle_J"] == pump["energy"]
    lowering = joint.duty.speed < 0
    assert lowering.any() and np.all(joint.pressure_needed()[lowering] == 0)
    # the peak pressure is about the push-pressure check's, the largest push over the piston area
    push = next(c for c in joint.checks if c.name == "push pressure")
    assert push.value * (1 - 1e-3) < pump["peak_pressure"] <= push.value  # the push at rest takes no oil
    bore, rod = joint.cylinder_data["bore"], joint.cylinder_data["rod"]
    oil = math.pi * (2 * bore**2 - rod**2) / 4 * 0.25  # m³: 0.25 m out on the piston, back on the annulus
    assert pump["energy_at_relief"] == pytest.approx(32e6 * oil, rel=1e-6)
    assert pump["energy_at_relief"] == pytest.approx(17065, rel=1e-4) and pump["energy_at_relief"] > 6 * rise
    text = str(result)
    assert "2583 J per cycle" in text and "17,065 J at the relief pressure" in text  # issue 32: not 1.707e+04


def test_a_cylinder_pulling_its_load_in_and_one_pushed_out_by_it():
    """One 100/56 cylinder, v = 0.1 sin πt m/s over 2 s, under F = −20 kN: extending (t < 1) the load pulls it out
    (F v < 0): p = 0; retracting it pulls against the load on the annulus, p = 20 kN / A_a = 3.7098 MPa, and the
    pump draws F v = 2 kW |sin πt| there: 2 kW · 2/π = 1273.2 J, the work done on the load."""
    t = np.linspace(0.0, 2.0, 20001)
    v = 0.1 * np.sin(math.pi * t)
    sized = size_cylinder(duty_of(t, v, np.full_like(t, -20e3)), Cylinder("L", "A", "B", (1.0, 1.8)),
                          pd.DataFrame([row("C", 0.1, 0.056)]), pressure=25e6)
    annulus = math.pi * (0.1**2 - 0.056**2) / 4
    p = sized.pressure_needed()
    assert np.all(p[v > 0] == 0) and p[v < 0] == pytest.approx(20e3 / annulus, rel=1e-12)
    assert 20e3 / annulus == pytest.approx(3.7098e6, rel=1e-4)
    (cylinder, pump) = hydraulic_supply([sized]).rows()
    assert pump["energy"] == cylinder["energy"] == pytest.approx(2e3 * 2 / math.pi, rel=1e-6)
    assert pump["peak_power"] == pytest.approx(2e3, rel=1e-6)
    # at most the relief pressure: at 2 MPa relief the pressure is cut there (the pull check fails then)
    capped = sized.pressure_needed(relief=2e6)
    assert capped.max() == 2e6

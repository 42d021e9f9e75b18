"""Hydraulic cylinders: the rated pressure against the system pressure, rod buckling at every pose with the end
fixing, the ISO 3320 series, and the pump flow and hydraulic power over the cycle, against hand calculations."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from protocol import check_result

import mechatron
from mechatron.cli import main
from mechatron.drives.catalogs import default_catalog, read_catalog
from mechatron.drives.cylinders import ISO_3320_BORES, ISO_3320_RODS, cylinder_lengths, iso_3320, size_cylinder
from mechatron.drives.duty import JointDuty
from mechatron.drives.hydraulics import hydraulic_supply
from mechatron.dynamics.task import default_task
from mechatron.errors import InputError
from mechatron.io.data import data_dir
from mechatron.model import Cylinder

E = 2.1e11  # Pa


def one(key="C", bore=0.14, rod=0.09, rated=32e6, stroke=3.0, **extra) -> pd.DataFrame:
    return pd.DataFrame([{"key": key, "bore": bore, "rod": rod, "max_stroke": stroke, "max_pressure": rated,
                          "mass": 10.0, **extra}])


def duty_of(t, speed, force, stroke=0.8, name="L") -> JointDuty:
    return JointDuty(name, "cylinder", t, speed, np.gradient(speed, t), force, force, 0.0, stroke)


# ------------------------------------------------------------------------------------------------ pressure
def test_a_cylinder_rated_below_the_system_pressure_fails():
    """A cylinder rated 25 MPa in a 40 MPa system fails the rated-pressure check (40/25 = 1.6) even though the
    task's forces need only 1 MPa: the relief pressure reaches it. At 25 MPa it passes."""
    t = np.linspace(0, 1, 101)
    spec = Cylinder("L", "A", "B", (1.0, 1.8))
    duty = duty_of(t, 0.1 * np.ones_like(t), np.full_like(t, 1e6 * math.pi * 0.05**2))  # 1 MPa on a 100 mm bore
    sized = size_cylinder(duty, spec, one(bore=0.1, rod=0.056, rated=25e6), pressure=40e6)
    assert not sized.feasible
    assert [c.name for c in sized.failed] == ["rated pressure"]
    rated = sized.failed[0]
    assert (rated.value, rated.limit, rated.unit) == (40e6, 25e6, "Pa")
    assert sized.closest["failed"].iloc[0] == "rated pressure ×1.60"
    push = next(c for c in sized.checks if c.name == "push pressure")
    assert push.value == pytest.approx(1e6) and push.passed
    assert size_cylinder(duty, spec, one(bore=0.1, rod=0.056, rated=25e6), pressure=25e6).feasible


def test_a_pressure_above_every_rating_is_a_report_not_an_error(capsys):
    """The shipped catalog rates its cylinders 25 and 32 MPa: at 40 MPa no cylinder passes; `size` exits 1 and
    reports the rated-pressure check failing by 40/32 = 1.25 at best."""
    code = main(["size", "six_bar_bucket", "--pressure-mpa", "40", "--json"])
    out, err = capsys.readouterr()
    assert code == 1 and "Traceback" not in err
    (joint,) = json.loads(out)["joints"]
    assert joint["feasible"] is False
    assert {c["name"] for c in joint["checks"] if not c["pass"]} == {"rated pressure"}
    assert joint["closest"] and all(c["failed"].startswith("rated pressure ×1.25") for c in joint["closest"])


# ------------------------------------------------------------------------------------------------ buckling
def test_buckling_at_every_pose_with_the_end_fixing():
    """The cylinder extends from L = 1.0 to 1.8 m while its push falls, F = 300 kN − 125 kN/m · L: the Euler load
    goes as 1/L², so the pose of the largest F L² decides: d(F L²)/dL = 600 L − 375 L² = 0 at L = 1.6 m, F = 100 kN.
    Rod 90 mm: I = π 0.09⁴/64 = 3.2206e-6 m⁴; fixed–free (K = 2): F_E/3.5 = π² E I/(2 · 1.6)²/3.5 = 186 248 N,
    buckling length 3.2 m. The old check, the largest push (175 kN) against L = 1.8 m, would have failed (147 159 N)."""
    t = np.linspace(0.0, 1.0, 801)
    length = 1.0 + 0.8 * t
    force = 300e3 - 125e3 * length
    spec = Cylinder("L", "A", "B", (1.0, 1.8))
    duty = duty_of(t, np.full_like(t, 0.8), force)
    sized = size_cylinder(duty, spec, one(), length=length, end_fixing="fixed-free")
    buckling = next(c for c in sized.checks if c.name == "rod buckling")
    inertia = math.pi * 0.09**4 / 64
    assert inertia == pytest.approx(3.220623e-6, rel=1e-6)
    assert buckling.value == pytest.approx(100e3, rel=1e-9)
    assert buckling.limit == pytest.approx(math.pi**2 * E * inertia / (2 * 1.6) ** 2 / 3.5, rel=1e-9)
    assert buckling.limit == pytest.approx(186247.7, rel=1e-6) and buckling.passed
    assert sized.buckling_length == pytest.approx(3.2) and sized.end_fixing == "fixed-free"
    assert 175e3 > math.pi**2 * E * inertia / (2 * 1.8) ** 2 / 3.5  # fully extended at the largest push: fails
    # the end fixing from the catalog row, or as a factor K
    from_row = size_cylinder(duty, spec, one(end_fixing="fixed-free"), length=length)
    assert next(c for c in from_row.checks if c.name == "rod buckling").limit == pytest.approx(buckling.limit)
    as_factor = size_cylinder(duty, spec, one(), length=length, end_fixing=2.0)
    assert next(c for c in as_factor.checks if c.name == "rod buckling").limit == pytest.approx(buckling.limit)
    assert as_factor.end_fixing == "K = 2"
    # pinned at both ends (the default): K = 1, four times the allowed force
    pinned = size_cylinder(duty, spec, one(), length=length)
    assert next(c for c in pinned.checks if c.name == "rod buckling").limit == pytest.approx(4 * buckling.limit)


def test_the_sizing_takes_the_lengths_of_the_task():
    """In the six-bar bucket the cylinder's length along the task is its actuated coordinate; the buckling check
    is that of the pose of the largest F⁺ L², and the lengths reach the result."""
    mech = mechatron.load("six_bar_bucket")
    task = default_task(mech)
    result = mechatron.size(mech, task)
    (joint,) = result.joints
    length = np.asarray(task.trajectory.q)[:, list(mech.actuated).index(joint.joint)]
    assert np.array_equal(joint.length, length)
    assert cylinder_lengths(mech, task.trajectory)[joint.joint] == pytest.approx(length)
    force = np.maximum(joint.duty.torque / joint.count, 0.0)
    pose = int(np.argmax(force * length**2))
    buckling = next(c for c in joint.checks if c.name == "rod buckling")
    rod = joint.cylinder_data["rod"]
    assert buckling.value == pytest.approx(force[pose])
    assert buckling.limit == pytest.approx(math.pi**3 * E * rod**4 / 64 / length[pose] ** 2 / 3.5, rel=1e-12)


def test_bad_lengths_and_fixings():
    t = np.linspace(0, 1, 11)
    duty = duty_of(t, np.ones_like(t), np.ones_like(t))
    spec = Cylinder("L", "A", "B", (1.0, 1.8))
    with pytest.raises(InputError, match="give a length > 0"):
        size_cylinder(duty, spec, one(), length=np.ones(5))
    with pytest.raises(InputError, match="unknown end fixing"):
        size_cylinder(duty, spec, one(), end_fixing="welded")
    with pytest.raises(InputError, match="factor K must be"):
        size_cylinder(duty, spec, one(), end_fixing=-1.0)


# ------------------------------------------------------------------------------------------------ ISO 3320
def test_iso_3320_series():
    """The bores and rods of ISO 3320; the shipped cylinders are of the series, a 70 mm bore or a 60 mm rod is not."""
    assert iso_3320(0.1, 0.056) and iso_3320(0.14, 0.09) and iso_3320(0.32, 0.2)
    assert not iso_3320(0.07, 0.036) and not iso_3320(0.1, 0.06)
    assert {63, 100, 125, 160, 200} <= set(ISO_3320_BORES) and {22, 36, 56, 70, 90} <= set(ISO_3320_RODS)
    for catalog in (default_catalog("cylinders"),
                    read_catalog(data_dir("examples/data") / "hydraulic_cylinders.csv", "cylinders")):
        assert iso_3320(catalog["bore"], catalog["rod"]).all()
    t = np.linspace(0, 1, 11)
    sized = size_cylinder(duty_of(t, np.ones_like(t), np.ones_like(t)), Cylinder("L", "A", "B", (1.0, 1.8)),
                          one(bore=0.07, rod=0.036))
    assert sized.as_dict()["iso_3320"] is False and "not of the ISO 3320 series" in str(sized)


# ------------------------------------------------------------------------------------------------ pump
def test_pump_flow_and_power_by_hand():
    """Two 100/56 cylinders side by side at v_A = 0.1 sin(πt) m/s and one 80/45 at v_B = −0.2 sin(πt) m/s, T = 2 s,
    25 MPa relief, both under F = 10 kN sin(πt). While A extends (piston side, A_p = 7.854e-3 m²) B retracts (rod
    side, A_a = 3.436e-3 m²): Q = (2 · 7.854e-3 · 0.1 + 3.436e-3 · 0.2) sin πt = k1 sin πt, k1 = 2.2580e-3; then
    (2 · 5.391e-3 · 0.1 + 5.027e-3 · 0.2) |sin πt| = k2 |sin πt|, k2 = 2.0835e-3. Peak 2.2580e-3 m³/s (135.48 l/min)
    at t = 0.5 s; volume (k1 + k2) · 2/π = 2.7639e-3 m³ per cycle, mean flow V/T.

    The pressures the loads need (issue 25: before, every flow at the 25 MPa relief pressure, 69.10 kJ per cycle,
    kept as energy_at_relief): A works against its load throughout (F v = 1 kW sin² πt ≥ 0), at
    p_A = F/(2 A_p) = 636.6 kPa sin πt extending and F/(2 A_a) = 927.5 kPa |sin πt| retracting, so its energy is
    its work ∫ F v dt = 1 kJ; B is driven by its load throughout (F v = −2 kW sin² πt ≤ 0): p_B = 0, no energy. The
    load-sensing pump gives the sum of the flows at A's pressure (B's throttled): P = 10 kN k1 sin² πt / (2 A_p) =
    1437.5 W sin² πt, then 10 kN k2 sin² πt / (2 A_a) = 1932.4 W sin² πt; energy (1437.5 + 1932.4) W · ½ s =
    1684.9 J, peak 1932.4 W at t = 1.5 s."""
    t = np.linspace(0.0, 2.0, 20001)
    s = np.sin(math.pi * t)
    a = size_cylinder(duty_of(t, 0.1 * s, 1e4 * s, name="A"), Cylinder("A", "a", "b", (1.0, 1.8), count=2),
                      one("A", 0.1, 0.056), pressure=25e6)
    b = size_cylinder(duty_of(t, -0.2 * s, 1e4 * s, name="B"), Cylinder("B", "c", "d", (1.0, 1.8)),
                      one("B", 0.08, 0.045), pressure=25e6)
    supply = hydraulic_supply([a, b])
    k1 = 2 * math.pi * 0.1**2 / 4 * 0.1 + math.pi * (0.08**2 - 0.045**2) / 4 * 0.2
    k2 = 2 * math.pi * (0.1**2 - 0.056**2) / 4 * 0.1 + math.pi * 0.08**2 / 4 * 0.2
    assert (k1, k2) == pytest.approx((2.25802e-3, 2.08350e-3), rel=1e-5)
    pump = supply.to_frame().set_index("cylinder").loc["pump"]
    assert pump["peak_flow"] == pytest.approx(k1, rel=1e-12)
    assert pump["volume"] == pytest.approx((k1 + k2) * 2 / math.pi, rel=1e-6)
    assert pump["mean_flow"] == pytest.approx((k1 + k2) / math.pi, rel=1e-6)
    assert pump["energy_at_relief"] == pytest.approx(25e6 * (k1 + k2) * 2 / math.pi, rel=1e-6)
    assert pump["energy_at_relief"] == pytest.approx(69099, rel=1e-4)
    piston, annulus = math.pi * 0.1**2 / 4, math.pi * (0.1**2 - 0.056**2) / 4
    extend, retract = 1e4 * k1 / (2 * piston), 1e4 * k2 / (2 * annulus)  # W: the pump's power over sin² πt
    assert (extend, retract) == pytest.approx((1437.5, 1932.4), abs=0.05)
    assert pump["peak_power"] == pytest.approx(retract, rel=1e-6)
    assert pump["peak_pressure"] == pytest.approx(1e4 / (2 * annulus), rel=1e-6)
    assert pump["energy"] == pytest.approx((extend + retract) / 2, rel=1e-6)
    assert pump["mean_power"] == pytest.approx(pump["energy"] / 2, rel=1e-12)
    cylinders = supply.to_frame().set_index("cylinder")
    assert cylinders.loc["A", "energy"] == pytest.approx(1e3, rel=1e-6)  # its work ∫ F v dt: 1 kW · ½ s · 2
    assert cylinders.loc["B", "energy"] == 0 and cylinders.loc["B", "peak_pressure"] == 0
    # per cylinder: A's peak is its piston side, 2 A_p 0.1; the peak of the sum is not the sum of the peaks
    frame = supply.to_frame().set_index("cylinder")
    assert frame.loc["A", "peak_flow"] == pytest.approx(2 * math.pi * 0.1**2 / 4 * 0.1, rel=1e-12)
    assert frame.loc["A", "peak_flow"] + frame.loc["B", "peak_flow"] > pump["peak_flow"]
    assert a.peak_flow == pytest.approx(frame.loc["A", "peak_flow"], rel=1e-12)
    data = check_result(supply)
    assert data["pressure"] == 25e6 and data["pump"]["peak_flow"] == pytest.approx(k1)
    assert data["pump"]["energy"] == pytest.approx(pump["energy"])
    assert "l/min" in str(supply)
    with pytest.raises(InputError, match="cylinder A twice"):
        hydraulic_supply([a, a])


def test_the_supply_of_a_sized_machine():
    """The six-bar bucket sized at the default 32 MPa: the pump's flow is its cylinder's, the power p Q at the
    pressure its load needs — for one cylinder the cylinder's positive power max(F v, 0) (issue 25: before, 32 MPa ×
    the peak flow)."""
    result = mechatron.size(mechatron.load("six_bar_bucket"))
    supply = hydraulic_supply(result)
    (joint,) = result.joints
    assert supply.pressure == 32e6 == joint.pressure
    assert supply.to_frame().iloc[-1]["peak_flow"] == pytest.approx(joint.peak_flow, rel=1e-12)
    # the sizing's totals and JSON carry the pump: no motor, so the energy drawn is the pump's ∫ p Q dt
    pump, totals = supply.rows()[-1], result.totals()
    assert totals["energy_per_cycle_J"] == pump["energy"] > 0
    positive = np.maximum(joint.duty.torque * joint.duty.speed, 0.0)  # W
    assert totals["peak_pump_power_W"] == pytest.approx(positive.max(), rel=1e-12)
    assert pump["energy"] == pytest.approx(np.trapezoid(positive, joint.duty.t), rel=1e-12)
    assert pump["energy_at_relief"] == pytest.approx(32e6 * pump["volume"], rel=1e-12)
    assert pump["energy_at_relief"] > 5 * pump["energy"]
    assert totals["peak_bus_power_W"] is None and result.as_dict()["electrical"] is None
    assert result.as_dict()["hydraulics"]["pump"]["energy"] == pump["energy"]
    assert "pump: peak flow" in str(result)
    with pytest.raises(InputError, match="no hydraulic cylinder"):
        hydraulic_supply(mechatron.size(mechatron.load("planar_2r")))

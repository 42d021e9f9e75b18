"""One function per formula (issue 34): the cylinder areas, the transmission-angle fold and the unit suffixes each
live in one function or table, and every place that used its own copy gives the numbers of the closed form.

The references are hand numbers and closed forms written here, never the functions under test:

- a cylinder of bore D = 0.1 m and rod d = 0.05 m: A₁ = π 0.1²/4 = 7.853981634e-3 m², A₂ = π (0.1² − 0.05²)/4
  = 5.890486225e-3 m²;
- the acute angle between two lines at θ: θ folded to [0, π/2], min(θ mod π, π − θ mod π), and for a triangle or
  four points the angle of two direction vectors by atan2(|u × w|, u · w), folded the same way;
- the unit suffixes: the factors of docs/units.md (1 mm = 1e-3 m, 1° = π/180 rad, …).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from mechatron.drives.cylinders import cylinder_areas, size_cylinder
from mechatron.drives.duty import JointDuty
from mechatron.errors import InputError
from mechatron.io.output import FILE_SUFFIXES, check_output
from mechatron.io.schema import ANGLE_UNITS, LENGTH_UNITS, FieldReader, field_suffixes
from mechatron.kinematics.geometry import acute_angle, transmission_angles
from mechatron.machines.excavator import CylinderSpec, transmission_angle
from mechatron.model import Cylinder
from mechatron.quantities import SUFFIXES
from mechatron.units import SI, UNITS

A1, A2 = 7.853981634e-3, 5.890486225e-3  # m², D = 0.1 m, d = 0.05 m, by hand


def folded(theta: float) -> float:
    """θ (rad, any) folded to the acute angle between two lines, [0, π/2]."""
    r = theta % math.pi
    return min(r, math.pi - r)


def line_angle(u, w) -> float:
    """The angle (rad, [0, π]) between two plane vectors, by atan2 of their cross and dot products."""
    return math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1])


# ----------------------------------------------------------------------------------------------- cylinder areas
def test_cylinder_areas_by_hand():
    piston, annulus = cylinder_areas(0.1, 0.05)
    assert float(piston) == pytest.approx(A1, rel=1e-9) and float(annulus) == pytest.approx(A2, rel=1e-9)
    pistons, annuli = cylinder_areas([0.1, 0.2], [0.05, 0.1])  # rows alike: D and d doubled, areas × 4
    np.testing.assert_allclose(pistons, [A1, 4 * A1], rtol=1e-9)
    np.testing.assert_allclose(annuli, [A2, 4 * A2], rtol=1e-9)


def test_the_shovel_cylinder_areas_pressures_and_forces():
    spec = CylinderSpec(0.1, 0.05, count=2)
    assert spec.piston_area == pytest.approx(A1, rel=1e-9) and spec.annulus_area == pytest.approx(A2, rel=1e-9)
    assert spec.areas == pytest.approx((A1, A2), rel=1e-9)
    assert spec.pressure(10e3) == pytest.approx(5e3 / A1, rel=1e-9)  # pushing: on the piston, per cylinder
    assert spec.pressure(-10e3) == pytest.approx(5e3 / A2, rel=1e-9)  # pulling: on the annulus
    assert spec.force(20e6) == pytest.approx(2 * 20e6 * A1, rel=1e-9)
    assert spec.force(20e6, extending=False) == pytest.approx(2 * 20e6 * A2, rel=1e-9)


def test_the_catalog_cylinder_areas_pressures_and_flow():
    """A one-row catalog, D = 0.1 m, d = 0.05 m: a push of 50 kN needs 50e3/A₁ Pa, a pull of 30 kN 30e3/A₂; out at
    0.2 m/s the flow is 0.2 A₁, in at 0.1 m/s 0.1 A₂."""
    t = np.linspace(0.0, 2.0, 201)
    speed = np.where(t < 1.0, 0.2, -0.1)
    force = np.where(t < 1.0, 50e3, -30e3)
    duty = JointDuty("L", "cylinder", t, speed, np.gradient(speed, t), force, force, 0.0, 0.3)
    catalog = pd.DataFrame([{"key": "C", "bore": 0.1, "rod": 0.05, "max_stroke": 3.0, "max_pressure": 32e6,
                             "mass": 10.0, "price": 100.0}])
    sized = size_cylinder(duty, Cylinder("L", "A", "B", (1.0, 1.8)), catalog, pressure=32e6)
    assert sized.areas == pytest.approx((A1, A2), rel=1e-9)
    checks = {c.name: c.value for c in sized.checks}
    assert checks["push pressure"] == pytest.approx(50e3 / A1, rel=1e-9)
    assert checks["pull pressure"] == pytest.approx(30e3 / A2, rel=1e-9)
    assert sized.peak_flow == pytest.approx(max(0.2 * A1, 0.1 * A2), rel=1e-9)
    np.testing.assert_allclose(sized.flow(), np.where(speed > 0, 0.2 * A1, 0.1 * A2), rtol=1e-9)


# ------------------------------------------------------------------------------------------- transmission angle
@pytest.mark.parametrize("theta", [0.0, math.pi / 2, math.pi, 3 * math.pi / 2, 2 * math.pi, -math.pi / 3,
                                   -2 * math.pi / 3, -math.pi / 2, -math.pi, 0.3, 2.8, 7.0])
def test_the_fold_at_edge_and_negative_angles(theta):
    assert float(acute_angle(math.cos(theta))) == pytest.approx(folded(theta), abs=1e-7)


def test_the_fold_of_cosines():
    np.testing.assert_allclose(acute_angle([1.0, 0.0, -1.0, 0.5, -0.5]), [0, math.pi / 2, 0, math.pi / 3, math.pi / 3],
                               atol=1e-12)
    assert acute_angle(1.0 + 1e-15) == 0.0 and acute_angle(-1.0 - 1e-15) == 0.0  # rounded past ±1
    mu = acute_angle(np.cos(np.linspace(-10, 10, 1001)))
    assert mu.min() >= 0.0 and mu.max() <= math.pi / 2


@pytest.mark.parametrize("a, b, c, d", [
    ((0, 0), (1, 0), (0, 0), (0, 1)),  # perpendicular: 90°
    ((0, 0), (1, 0), (2, 2), (5, 2)),  # parallel: 0°
    ((0, 0), (1, 0), (3, 0), (-1, 0)),  # opposite: 0°
    ((0, 0), (1, 0), (0, 0), (-math.sqrt(3), 1)),  # 150° apart: 30°
    ((1, 1), (2, 3), (0, -1), (4, 0.5)),  # general
])
def test_transmission_angles_of_points(a, b, c, d):
    u, w = np.subtract(b, a), np.subtract(d, c)
    assert float(transmission_angles(a, b, c, d)[0]) == pytest.approx(folded(line_angle(u, w)), abs=1e-12)


@pytest.mark.parametrize("lever, other, psi_deg, expected_deg", [
    (1.0, 1.0, 90.0, 45.0),  # isosceles right triangle
    (1.0, 2.0, 60.0, 90.0),  # 30–60–90: the angle at the lever's end is the right angle
    (2.0, 1.0, 60.0, 30.0),
    (1.0, 2.0, 30.0, None),  # obtuse at the lever's end: folded
    (0.8, 2.5, 150.0, None),
    (3.0, 0.5, 10.0, None),
])
def test_the_shovel_transmission_angle_of_a_triangle(lever, other, psi_deg, expected_deg):
    """The pivot at the origin, the lever along x to A = (a, 0), the other lever to B = b (cos ψ, sin ψ): the angle
    at A between the lever (A → pivot) and the cylinder (A → B), folded."""
    psi = math.radians(psi_deg)
    A, B = (lever, 0.0), (other * math.cos(psi), other * math.sin(psi))
    reference = folded(line_angle((-A[0], -A[1]), (B[0] - A[0], B[1] - A[1])))
    if expected_deg is not None:
        assert reference == pytest.approx(math.radians(expected_deg), abs=1e-12)
    assert transmission_angle(lever, other, psi) == pytest.approx(reference, abs=1e-9)


# ------------------------------------------------------------------------------------------------ unit suffixes
def test_the_field_suffixes_of_lengths_and_angles():
    assert LENGTH_UNITS == {"": 1.0, "_cm": 1e-2, "_mm": 1e-3, "_um": 1e-6}
    assert ANGLE_UNITS == pytest.approx({"": 1.0, "_deg": math.pi / 180, "_arcmin": math.pi / 180 / 60,
                                         "_arcsec": math.pi / 180 / 3600, "_mrad": 1e-3, "_urad": 1e-6}, rel=1e-15)
    assert list(LENGTH_UNITS)[0] == "" and "_m" not in LENGTH_UNITS and "_rad" not in ANGLE_UNITS
    # the study file's ranges: SI, _mm or _deg
    assert {**field_suffixes("length", "mm"), **field_suffixes("angle", "deg")} == \
        pytest.approx({"": 1.0, "_mm": 1e-3, "_deg": math.pi / 180}, rel=1e-15)
    reader = FieldReader({"a_mm": 12.5, "alpha_deg": 90.0, "b_cm": 3.0}, file="f.toml")
    assert reader.length("a") == pytest.approx(0.0125, rel=1e-15)
    assert reader.angle("alpha") == pytest.approx(math.pi / 2, rel=1e-15)
    assert reader.length("b") == pytest.approx(0.03, rel=1e-15)
    with pytest.raises(InputError, match="give only one of a and a_mm"):
        FieldReader({"a": 1.0, "a_mm": 2.0}, file="f.toml").length("a")


def test_the_name_suffixes_of_the_quantities_agree_with_the_unit_table():
    """Every unit suffix of an output name is a unit of :data:`mechatron.units.UNITS` (but J and m³/s, of no file
    field), printed as the SI unit of its kind where it is that unit and as written otherwise."""
    for suffix, printed in SUFFIXES.items():
        kinds = [k for k in UNITS if suffix in UNITS[k]]
        if not kinds:
            assert suffix in ("J", "m3_s"), suffix
        for kind in kinds:
            assert printed == (SI[kind] if UNITS[kind][suffix] == 1.0 else suffix), (suffix, kind)


def test_the_file_suffixes_of_outputs(tmp_path):
    assert FILE_SUFFIXES["table"] == (".csv", ".txt") and FILE_SUFFIXES["toml"] == (".toml",)
    assert check_output(tmp_path / "a.csv", "table") == tmp_path / "a.csv"
    with pytest.raises(InputError, match=r"\.csv"):
        check_output(tmp_path / "a.png", "table")

"""Two-cylinder seven-link mechanism [ShiLiang] against [ShiLiang, table 2] and the paper's own closed forms
[ShiLiang, 3–20] (both in validation/seven_bar.py).

Only V_C of table 2 is reproducible. The paper's closed forms, read through the text extraction's digit swaps,
agree with the generic model, and both disagree with the printed V_D, β1, ω_CD, V_H and β2. The three of them that
are speeds correspond to the same mechanism with the cylinder DE at rest; β1 and β2 contradict the paper's own
equations (validation.seven_bar.table2_comparison gives the reasons).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.kinematics.frames import angular_velocity, frame_placement, point_velocity
from mechatron.kinematics.loops import assemble, joint_velocity
from mechatron.machines.seven_bar import SevenBarData
from validation.seven_bar import law_of_cosines, paper_closed_forms, table2_comparison, table2_quantities

MM = 1e-3


@pytest.fixture(scope="module")
def mech():
    return mechatron.load("seven_bar")


def test_structure_and_pins(mech):
    assert mech.mobility() == 2 and mech.actuated == ["s1", "s2"]
    assert set("ABCDEFGHI") <= set(mech.points)
    q = mech.reference_q
    # pin coordinates of the independent reconstruction (mm)
    expected = {"B": (46.870968, 152.980758), "C": (-165.152697, 561.203695), "D": (13.529421, 651.051905),
                "E": (132.25, 98.665787), "F": (560.453125, 71.535269), "H": (-381.288080, 867.651889),
                "I": (13.010452, 650.790948)}
    for name, xy in expected.items():
        np.testing.assert_allclose(frame_placement(mech, q, name).translation[:2] / MM, xy, atol=1e-5)
    data = SevenBarData()
    for a, b, length in (("A", "B", data.l7), ("A", "C", data.l2), ("B", "C", data.l6), ("C", "D", data.l5),
                         ("C", "H", data.l3), ("H", "I", data.l4), ("A", "E", data.l8), ("E", "G", data.l9),
                         ("A", "F", data.l10), ("F", "G", data.l11), ("B", "F", data.s1_min),
                         ("D", "E", data.s2_min)):
        assert mechatron.kinematics.distance(mech, q, a, b) == pytest.approx(length, abs=1e-12)


def test_table2_velocity_of_C(mech):
    q = mech.reference_q
    v = joint_velocity(mech, q, {"s1": 0.005, "s2": 0.006})
    # V_C = V1 l2 / (l7 sin ∠ABF) [ShiLiang, 3–4]: 18.462 mm/s as printed
    assert np.linalg.norm(point_velocity(mech, q, v, "C")) / MM == pytest.approx(18.461960, abs=1e-6)
    assert round(np.linalg.norm(point_velocity(mech, q, v, "C")) / MM, 3) == 18.462
    # ω of the boom does not depend on the second cylinder
    assert angular_velocity(mech, q, v, "ABC")[2] == pytest.approx(0.005 / (0.16 * math.sin(
        law_of_cosines(160, 520, 565))), rel=1e-12)


def test_model_equals_papers_closed_forms(mech):
    for v2 in (6.0, 3.0):
        model = table2_quantities(mech, 0.005, v2 * MM)
        paper = paper_closed_forms(5.0, v2)
        for key in ("V_C", "V_D", "beta1_deg", "omega_CD", "V_H", "beta2_deg"):
            assert model[key] == pytest.approx(paper[key], rel=1e-10), key


def test_table2_comparison(mech):
    rows = {r["quantity"]: r for r in table2_comparison(mech)}
    assert [k for k, r in rows.items() if r["reproduced"]] == ["V_C"]
    # the printed V_D, ω_CD, V_H are the mechanism with the cylinder DE at rest, to within 0.4 %
    for key in ("V_D", "omega_CD", "V_H"):
        assert rows[key]["model_v2_zero"] == pytest.approx(rows[key]["printed"], rel=4e-3)
    # β1: [ShiLiang, 14–15] give cos β1 = V2 / V_D, so even the printed V_D implies 71.36°, not 13.48°
    assert math.degrees(math.acos(6 / rows["V_D"]["printed"])) == pytest.approx(71.362, abs=1e-3)
    # β2: |v_H − v_C| = ω_CD·CH bounds the angle between v_H and v_C
    bound = math.degrees(math.asin(rows["omega_CD"]["printed"] * 375 / rows["V_C"]["printed"]))
    assert bound == pytest.approx(8.32, abs=0.01) and rows["beta2_deg"]["printed"] > bound


def test_two_input_velocity_against_finite_differences(mech):
    q = assemble(mech, {"s1": 0.6, "s2": 0.65})
    h = 1e-6
    for rates in ({"s1": 1.0, "s2": 0.0}, {"s1": 0.0, "s2": 1.0}, {"s1": 0.005, "s2": 0.006}):
        step = {k: 0.6 + h * rates["s1"] if k == "s1" else 0.65 + h * rates["s2"] for k in rates}
        back = {k: 0.6 - h * rates["s1"] if k == "s1" else 0.65 - h * rates["s2"] for k in rates}
        plus, minus = assemble(mech, step, q), assemble(mech, back, q)
        np.testing.assert_allclose(joint_velocity(mech, q, rates), (plus - minus) / (2 * h), atol=1e-8)


def test_sweep_both_cylinders(mech):
    from mechatron.kinematics.sweeps import sweep

    result = sweep(mech, samples=101)
    assert len(result.failures) == 0
    assert result.table["s1"].iloc[-1] == pytest.approx(0.72) and result.table["s2"].iloc[-1] == pytest.approx(0.765)

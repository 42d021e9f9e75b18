"""Six-link bucket mechanism [Bucket]: first sizing, synthesis of c and L2, analysis over the stroke.

The paper prints no worked example; the reference numbers below were computed independently (a separate
reconstruction of the geometry from the loop equations [Bucket, 8], solved with CasADi, Ipopt and SciPy from its own
sketch guess): for q = 0.5 m³, α = 12.5°, β = 30°, γ = 100°, H_T = b = 0.2 m, a = L1н + h/2 and Δφ4 = 160°,
c = 0.410349095 m and L2 = 0.493108381 m. The paper's Φ_t [Bucket, 15] and Φ_tt [Bucket, 21] are printed with four
rows and (21) with the label Φ_t; its (17) has "=" where a product belongs. The Jacobian [Bucket, 12] and its
derivative [Bucket, 18] are correct as printed; the analytic reference validation.bucket.analytic_analysis uses
them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble
from mechatron.kinematics.sweeps import sweep
from mechatron.machines import bucket as bk
from mechatron.model.linkage import build_linkage
from validation.bucket import analytic_analysis

DEG = math.pi / 180


@pytest.fixture(scope="module")
def linkage():
    return bk.synthesize()


@pytest.fixture(scope="module")
def mech(linkage):
    """The shipped file robots/six_bar_bucket.toml, which the synthesis wrote (tests/test_pipeline.py)."""
    return mechatron.load("six_bar_bucket")


def test_first_sizing():
    size = bk.first_sizing(bk.BucketInputs(volume=0.5))
    assert size["Lk"] == pytest.approx(1.25 * 0.5 ** (1 / 3) + 0.25)  # [Bucket, 1]: 1.242126 m
    assert size["Lk"] == pytest.approx(1.242125657, abs=1e-9)
    assert size["L5"] == size["L4"] == size["L3"] == pytest.approx(0.4 * size["Lk"])  # [Bucket, 2, 3]
    assert size["stroke_raw"] == pytest.approx(1.83 * size["L5"])  # [Bucket, 4]: 0.909 m
    assert size["stroke"] == 0.9  # the nearest standard stroke
    assert size["L1n"] == pytest.approx(1.1)  # L1н = H_T + h
    assert bk.first_sizing(bk.BucketInputs(volume=1.0, standard_stroke=False))["stroke"] == pytest.approx(
        1.83 * 0.4 * 1.5)


def test_synthesis_solves_the_eight_loop_equations(linkage):
    assert (linkage.c, linkage.L2) == pytest.approx((0.410349095, 0.493108381), abs=1e-9)
    common = dict(a=linkage.a, b=linkage.b, c=linkage.c, L2=linkage.L2, L3=linkage.L3, L4=linkage.L4,
                  L5=linkage.L5, alpha=linkage.alpha)
    start = bk.loop_equations(linkage.L1n, *linkage.initial, linkage.phi4n, **common)
    end = bk.loop_equations(linkage.L1n + linkage.stroke, *linkage.final, linkage.phi4n + linkage.turn, **common)
    assert np.abs(start + end).max() < 1e-12
    assert np.degrees(linkage.initial) == pytest.approx((0.084919, 24.135538, -9.748385), abs=1e-6)
    assert np.degrees(linkage.final) == pytest.approx((0.046825, 155.863929, 44.563119), abs=1e-6)


def test_bucket_turns_by_the_required_angle(linkage, mech):
    """Over the whole stroke the assembled mechanism turns the bucket by exactly Δφ4 = 160°, monotonically."""
    result = sweep(mech, samples=400)
    assert len(result.failures) == 0
    phi4 = result.table["q_phi4"].to_numpy()
    assert phi4[-1] - phi4[0] == pytest.approx(160 * DEG, abs=1e-9)
    assert (np.diff(phi4) > 0).all()
    assert mech.mobility() == 1 and mech.redundant_closure_equations() == 0
    # pins at the start as synthesized, in the stick frame (origin D, x towards A)
    q0 = assemble(mech, {"L1": linkage.L1n})
    for name, expected in linkage.pins(linkage.L1n, linkage.initial, linkage.phi4n).items():
        np.testing.assert_allclose(frame_placement(mech, q0, name).translation[:2], expected, atol=1e-10)


def test_generic_analysis_equals_the_papers_equations(linkage, mech):
    """Pinocchio tree + closures against [Bucket, 8, 12, 18] at a constant and an accelerating cylinder."""
    strokes = np.linspace(linkage.L1n, linkage.L1n + linkage.stroke, 101)
    for rate, accel in ((0.1, 0.0), (0.25, 0.4)):
        result = sweep(mech, {"L1": strokes}, rates={"L1": rate}, accelerations={"L1": accel})
        reference = analytic_analysis(linkage, strokes, rate, accel)
        table = result.table
        np.testing.assert_allclose(table["q_phi2"], reference["q"][:, 2], atol=1e-9)
        np.testing.assert_allclose(table["q_phi4"], reference["q"][:, 4], atol=1e-9)
        np.testing.assert_allclose(table["v_phi4"], reference["qd"][:, 4], atol=1e-9)
        np.testing.assert_allclose(table["a_phi4"], reference["qdd"][:, 4], atol=1e-8)
        np.testing.assert_allclose(table[["K_x", "K_y"]], reference["K"], atol=1e-9)
        np.testing.assert_allclose(table[["K_vx", "K_vy"]], reference["K_velocity"], atol=1e-9)
        np.testing.assert_allclose(table[["K_ax", "K_ay"]], reference["K_acceleration"], atol=1e-8)


def test_transmission_angles(mech):
    result = sweep(mech, samples=801)
    worst = {m["name"]: math.degrees(m["min"]) for m in result.check_measures()}
    # cylinder-rocker 24.1° at both ends, link-bucket 14.6° at full curl (independent reconstruction: same values)
    assert worst["mu_B"] == pytest.approx(24.09, abs=0.05)
    assert worst["mu_E"] == pytest.approx(14.56, abs=0.05)


def test_infeasible_synthesis_is_reported():
    with pytest.raises(mechatron.InputError, match="no physical solution|another assembly branch"):
        bk.synthesize(bk.BucketInputs(turn_deg=260.0))


def test_assembled_positions_are_the_synthesized_ones_at_both_ends(linkage):
    """The circle intersections of BucketLinkage.assembled (the file's drawing) on the start's branch give, at the
    end of the stroke, the pins of the synthesis' final angles (φ1к, φ2к, φ3к, φ4н + Δφ4)."""
    for L1, phi, phi4 in ((linkage.L1n, linkage.initial, linkage.phi4n),
                          (linkage.L1n + linkage.stroke, linkage.final, linkage.phi4n + linkage.turn)):
        pins, expected = linkage.assembled(L1), linkage.pins(L1, phi, phi4)
        for name in expected:
            np.testing.assert_allclose(pins[name], expected[name], atol=1e-12, err_msg=name)


def test_the_spec_checks_the_turn_of_the_synthesis(linkage):
    """bucket_spec builds the mechanism and refuses a synthesis whose mechanism does not turn by Δφ4."""
    from dataclasses import replace

    with pytest.raises(mechatron.InputError, match="turns the bucket by 160°, not 165°"):
        bk.bucket_spec(replace(linkage, turn=165 * DEG))


def test_another_synthesis_through_its_file(tmp_path):
    """A 150° turn: synthesis → mechanism file → model; the model read back turns the bucket by 150°."""
    linkage = bk.synthesize(bk.BucketInputs(turn_deg=150.0))
    mech = mechatron.load(bk.write_bucket(linkage, tmp_path / "bucket_150.toml"))
    result = sweep(mech, samples=50)
    assert result.table["q_phi4"].iloc[-1] - result.table["q_phi4"].iloc[0] == pytest.approx(150 * DEG, abs=1e-9)
    # the same from the spec without a file
    direct = build_linkage(bk.bucket_spec(linkage))
    np.testing.assert_array_equal(direct.reference_q, mech.reference_q)


def test_the_file_has_the_synthesized_lengths(linkage, mech):
    """The named lengths of the file are those of the first sizing and the synthesis; the cylinder eye A = (a, b)."""
    values = mech.parameter_values()
    for name, expected in (("c", linkage.c), ("L2", linkage.L2), ("L3", linkage.L3), ("L4", linkage.L4),
                           ("L5", linkage.L5), ("Lk", linkage.Lk), ("A_x", linkage.a), ("A_y", linkage.b)):
        assert values[name] == pytest.approx(expected, abs=1e-12), name
    assert mech.cylinders["L1"].stroke == pytest.approx((1.1, 2.0), abs=1e-12)  # L1н = H_T + h, L1н + h
    assert mech.input_rates == {"L1": 0.1} and mech.tool_frame == "K"


def test_a_longer_length_from_the_command_line_rebuilds_through_the_file():
    """--set L4=... changes the link CE: the rebuilt model has |CE| = L4 at every position."""
    from mechatron.kinematics.geometry import distance

    longer = mechatron.load("six_bar_bucket", L4=0.52)
    for q in sweep(longer, samples=5).q:
        assert distance(longer, q, "C", "E") == pytest.approx(0.52, abs=1e-9)

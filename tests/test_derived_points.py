"""Derived points (``between``) wherever a point goes: a loop's pin, a cylinder's eye (tests/test_scissor_lift.py),
a payload's place (tests/test_payloads.py), a spatial drawing — rigid on every body that lists them."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import mechatron

ROOT = Path(__file__).resolve().parent.parent
L1, L2 = 0.1, 0.4  # the crank-slider's crank and rod (m)


def slider_position(q1: float, l2: float = L2) -> float:
    """x_C = l1 cos q1 + √(l2² − l1² sin² q1): the central crank-slider's slider pin."""
    return L1 * math.cos(q1) + math.sqrt(l2**2 - (L1 * math.sin(q1)) ** 2)


def crank_slider_with_a_derived_pin(tmp_path: Path) -> Path:
    """The shipped crank-slider whose rod is drawn longer, to an end E at 1.5 l2 from B, with the slider pin C the
    derived point two thirds of the way from B to E (l2 from B): the pin closure of the loop is at a derived point,
    which the slider carries too (where it is drawn). The rod's length BE is a named length, ``rod``."""
    text = (ROOT / "robots" / "crank_slider.toml").read_text(encoding="utf-8")
    b = np.array([0.05, 0.08660254037844387])
    c = np.array([slider_position(math.pi / 3), 0.0])
    e = b + 1.5 * (c - b)
    for old, new in (("C = [0.4405124837953327, 0.0]", f"E = [{float(e[0])!r}, {float(e[1])!r}]\n"
                      f'C = {{ between = ["B", "E"], fraction = {2 / 3!r} }}'),
                     ('S2 = { between = ["B", "C"] }', f'S2 = {{ between = ["B", "E"], fraction = {1 / 3!r} }}'),
                     ('points = ["B", "C", "S2"]', 'points = ["B", "E", "C", "S2"]'),
                     ('toward = "C"                         # phi2', 'toward = "E"                         # phi2'),
                     ('l2 = { points = ["B", "C"], value = 0.4 }', 'rod = ["B", "E"]')):
        assert text.count(old) == 1
        text = text.replace(old, new)
    path = tmp_path / "crank_slider_derived.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_loop_closed_at_a_derived_pin(tmp_path):
    mech = mechatron.load(crank_slider_with_a_derived_pin(tmp_path))
    assert mech.mobility() == 1 and mech.parameters["rod"].value == pytest.approx(1.5 * L2, rel=1e-12)
    for q1 in (0.3, 1.2, 2.5, 4.0):
        q = mechatron.assemble(mech, {"q1": q1}, guess=mech.reference_q)
        for frame in ("C", "C@slider"):
            assert mechatron.frame_placement(mech, q, frame).translation[:2] == pytest.approx(
                [slider_position(q1), 0.0], abs=1e-12)
    # a longer rod: E moves along the rod away from B, C stays two thirds of the way, so l2 = 2/3 BE
    longer = mech.with_parameters(rod=0.66)
    q = mechatron.assemble(longer, {"q1": 1.0}, guess=longer.reference_q)
    assert mechatron.frame_placement(longer, q, "C").translation[0] == pytest.approx(slider_position(1.0, 0.44),
                                                                                     abs=1e-12)


def test_a_spatial_derived_point_is_the_midpoint_in_space(tmp_path):
    """A point of the Delta's platform halfway between two of its wrist pins W1 and W2 (x, y and z) stays there as
    the platform moves."""
    text = (ROOT / "robots" / "delta.toml").read_text(encoding="utf-8")
    text = text.replace("W3 = [", 'M = { between = ["W1", "W2"] }\nW3 = [', 1)
    text = text.replace('points = ["origin", "TCP", "W1", "W2", "W3"]',
                        'points = ["origin", "TCP", "W1", "W2", "W3", "M"]')
    path = tmp_path / "delta.toml"
    path.write_text(text, encoding="utf-8")
    delta = mechatron.load(path)
    q = mechatron.assemble(delta, {"theta1": 0.3, "theta2": -0.1, "theta3": 0.2}, guess=delta.reference_q)
    w1, w2, m = (mechatron.frame_placement(delta, q, n).translation for n in ("W1", "W2", "M"))
    assert m == pytest.approx((w1 + w2) / 2, abs=1e-12) and abs(m[2]) > 0.3

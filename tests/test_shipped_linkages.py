"""The shipped mechanism files of the textbook linkages [Egorov, figs. 4.2, 4.4–4.6], the seven-link mechanism
[ShiLiang] and the grab [Mikhailov]: each loads by name from robots/, its drawing is exact (closing it moves no
point), its named lengths rebuild it as the closed forms say, and the two reconstructions' files are what the
reconstructions write now (so that the file and the Python reconstruction cannot drift apart).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np
import pytest

import mechatron
from mechatron.io.data import data_dir
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble
from mechatron.machines.grab import GrabGeometry, grab_spec, write_grab
from mechatron.machines.seven_bar import SevenBarData, pins, seven_bar, seven_bar_spec, write_seven_bar
from mechatron.model.linkage import curve_functions, inconsistencies
from mechatron.model.linkage_file import read_linkage_file
from tests.written_files import assert_same_toml

SHIPPED = ("crank_slider", "scotch_yoke", "slotted_link", "seven_bar", "grab")


def shipped(name):
    return data_dir("robots") / f"{name}.toml"


def same(a, b, where="spec"):
    """Two specs (dataclasses, tuples, mappings) equal, their floats to 1e-12 (the file's full precision)."""
    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        for f in dataclasses.fields(a):
            if f.name != "file":
                same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, Mapping):
        assert list(a) == list(b), where
        for key in a:
            same(a[key], b[key], f"{where}[{key}]")
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{where}[{k}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-15), where
    else:
        assert a == b, where


@pytest.mark.parametrize("name", SHIPPED)
def test_loads_by_name_from_its_file_and_the_drawing_is_exact(name):
    mech = mechatron.load(name)
    assert mech.source == str(shipped(name)) and mech.name == name
    assert max((off for _, off, _ in inconsistencies(read_linkage_file(shipped(name)))), default=0.0) < 1e-15
    assert not any("closed by moving" in note for note in mech.notes)
    assert mech.mobility() == len(mech.actuated) and mech.redundant_closure_equations() == 0


@pytest.mark.parametrize("name, spec, write", [("seven_bar", seven_bar_spec, write_seven_bar),
                                               ("grab", grab_spec, write_grab)])
def test_reconstructions_write_the_shipped_files(name, spec, write, tmp_path):
    same(read_linkage_file(shipped(name)), spec())
    written = write(tmp_path / f"{name}.toml")
    assert_same_toml(written, shipped(name))  # its numbers to 1e-12, not their last digit


# ------------------------------------------------------------------------------------------- textbook files
def slider_x(l1, l2, q):
    """x_C = l1 cos q + sqrt(l2² − l1² sin² q) [Egorov, fig. 4.18]; the other branch with −sqrt."""
    root = math.sqrt(l2**2 - (l1 * math.sin(q)) ** 2)
    return l1 * math.cos(q) + root, l1 * math.cos(q) - root


def test_crank_slider_file_and_its_lengths():
    mech = mechatron.load("crank_slider")
    assert mech.actuated == ["q1"] and mech.joint_names == ["q1", "phi2", "xC"] and mech.tool_frame == "C"
    assert {k: p.value for k, p in mech.parameters.items() if k in ("l1", "l2")} == {"l1": 0.1, "l2": 0.4}
    assert mech.reference_q[0] == pytest.approx(math.pi / 3, abs=1e-15)  # drawn at q1 = 60°
    drawn = frame_placement(mech, mech.reference_q, "C").translation[0]
    assert drawn == pytest.approx(slider_x(0.1, 0.4, math.pi / 3)[0], abs=1e-15)
    book = mechatron.load("crank_slider", l1=0.2, l2=0.346)  # [Egorov, fig. 8.3]
    for q in (0.0, 1.0, math.pi / 3, 2.5, -2.0):
        right, left = slider_x(0.2, 0.346, q)
        assert frame_placement(book, assemble(book, {"q1": q}), "C").translation[0] == pytest.approx(right, abs=1e-12)
        other = assemble(book, {"q1": q}, branch="left")
        assert frame_placement(book, other, "C").translation[0] == pytest.approx(left, abs=1e-12)
        # S2 stays the rod's middle
        B, C, S2 = (frame_placement(book, other, p).translation for p in ("B", "C", "S2"))
        np.testing.assert_allclose(S2, (B + C) / 2, atol=1e-15)
    # the rod is a uniform bar of 2 kg: its centre in the middle of BC, I = m l2²/12 with the new l2
    rod = book.model.inertias[book.joint_id("phi2")]
    assert rod.mass == 2.0 and rod.lever[0] == pytest.approx(0.346 / 2, abs=1e-15)
    assert rod.inertia[2, 2] == pytest.approx(2.0 * 0.346**2 / 12, rel=1e-14)


def test_scotch_yoke_file_rebuilt_with_another_crank():
    mech = mechatron.load("scotch_yoke", l1=0.25)
    for q in (0.3, 1.7, -2.9):
        assert frame_placement(mech, assemble(mech, {"q1": q}), "C").translation[0] == pytest.approx(
            0.25 * math.cos(q), abs=1e-12)  # x_C = l1 cos q1 [Egorov, fig. 4.4]


def test_slotted_link_file_rebuilt_with_other_lengths():
    """θ3 = π − β with tan β = l1 sin q1 / (d − l1 cos q1) [Egorov, figs. 4.5, 4.6], here a rotating coulisse."""
    l1, d = 0.12, 0.09
    mech = mechatron.load("slotted_link", l1=l1, d=d)
    assert frame_placement(mech, mech.reference_q, "C").translation[0] == pytest.approx(d, abs=1e-15)
    for q in (0.4, 2.0, -2.5):
        beta = math.atan2(l1 * math.sin(q), d - l1 * math.cos(q))
        theta = mechatron.kinematics.link_angle(mech, assemble(mech, {"q1": q}), "coulisse")
        assert math.remainder(theta - (math.pi - beta), 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    coulisse = mech.model.inertias[mech.joint_id("phi3")]  # a uniform bar of 2 kg along the 0.4 m slot
    assert coulisse.inertia[2, 2] == pytest.approx(2.0 * 0.4**2 / 12, rel=1e-14)


# ------------------------------------------------------------------------------------------- reconstructions
def test_seven_bar_lengths_rebuild_as_the_reconstruction():
    """A named length of the file (l9 = EG and l11 = FG join two frame pins, neither of them A) moves the pins as the
    reconstruction's circle intersections do [ShiLiang, table 1]."""
    for change in ({"l9": 0.7}, {"l11": 0.24}, {"l7": 0.17, "l2": 0.6}):
        data = SevenBarData(**change)
        expected = pins(data, data.s1_min, data.s2_min)
        mech = mechatron.load("seven_bar", **change)
        for point, xy in expected.items():
            if point not in "HI":  # H and I keep their drawn offsets from CD, not the reconstruction's angle α0
                np.testing.assert_allclose(frame_placement(mech, mech.reference_q, point).translation[:2], xy,
                                           atol=1e-12, err_msg=f"{change} {point}")
        assert mech.parameters[next(iter(change))].value == pytest.approx(next(iter(change.values())), abs=1e-15)
    rebuilt, direct = mechatron.load("seven_bar", l9=0.7), seven_bar(l9=0.7)
    np.testing.assert_allclose(rebuilt.reference_q, direct.reference_q, atol=1e-12)


def test_grab_curve_table_is_the_parabola():
    """The file's curve table through a not-a-knot cubic spline is η(x) = −e + A (x + d)² itself, with η′ and
    η″ = 2A, inside the table and beyond its ends [Mikhailov, 6]."""
    g = GrabGeometry()
    curve = next(c for c in read_linkage_file(shipped("grab")).closures if c.kind == "curve")
    f, df, d2f = curve_functions(curve)
    for x in np.linspace(-1.6, 0.2, 37):
        assert f(x) == pytest.approx(g.eta(x), abs=1e-14)
        assert df(x) == pytest.approx(2 * g.curvature * (x + g.deepest_x), abs=1e-13)
        assert d2f(x) == pytest.approx(2 * g.curvature, abs=1e-12)


def test_grab_rod_length_rebuilds_as_the_closed_form():
    g = GrabGeometry(rod_length=2.0)
    mech = mechatron.load("grab", rod_length=2.0)
    for phi in (g.open_angle, -0.5, 0.0):
        q = assemble(mech, {"phi1": phi})
        expected = g.closed_form(phi)
        np.testing.assert_allclose(frame_placement(mech, q, "P4").translation[:2], expected["pin4"], atol=1e-10)
        assert frame_placement(mech, q, "C3").translation[1] == pytest.approx(expected["upper_crosshead"], abs=1e-10)

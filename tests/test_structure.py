"""Structural analysis [Egorov, chapter 3]: the book's worked cases with their printed results, synthesis,
agreement of the formulas with the model's numeric mobility for every built-in mechanism, groups, bad input, the
result protocol and the command's outputs."""

from __future__ import annotations

import json
from fractions import Fraction

import numpy as np
import pytest

import mechatron
from mechatron.cli import main
from mechatron.errors import InputError
from mechatron.library import available_robots
from mechatron.model.planar import GROUND, PlanarBuilder
from mechatron.structure import formulas as F
from mechatron.structure.analysis import analyse, analyse_structure
from mechatron.structure.description import (
    Pair,
    StructuralDescription,
    pair_kind,
    read_structure,
    shipped_structures,
    structure_file,
)
from tests.protocol import check_result

# case: (K, S_j, H, W by 3.16, planar W by 3.3 / 3.17 or None, W by 3.2), as printed [Egorov, figs. 3.10–3.20]
BOOK = {
    "ice_3_10a": (1, [3], 1, 1, (1, 1), -2),
    "ice_3_10b": (1, [0], 1, 1, None, 1),
    "cam_3_11a": (1, [1], 1, 1, (2, 1), 1),     # the book: (3.3) gives 2 "wrong", (3.17) 1
    "cam_3_11b": (1, [0], 1, 1, None, 1),
    "cam_3_11c": (1, [0], None, 1, None, 2),
    "cam_3_11d": (1, [-2], None, 1, None, 4),
    "gripper_3_12a": (4, [1, 1, 3, 3], 1, 1, (1, 1), -7),
    "gripper_3_12b": (4, [0, 0, 0, 0], 1, 1, None, 1),
    "robot_3_13a": (2, [2, -1], 3, 3, None, 2),
    "robot_3_13b": (2, [0, 0], 3, 3, None, 3),
    "slotted_3_14": (1, [0], 1, 1, None, 1),
    "robot_3_15": (0, [], 3, 5, None, 5),
    "planetary_3_17": (2, [1, 1], 1, 1, None, -1),
    "differential_3_18": (1, [1], 1, 2, None, 1),
    "robot_3_20": (1, [2], 3, 3, None, 1),
}


@pytest.mark.parametrize("case", sorted(BOOK))
def test_textbook_structural_cases(case):
    K, S, H, W, planar, malyshev = BOOK[case]
    report = analyse(read_structure(structure_file(case)))
    assert report.loops == K
    assert report.loop_redundancies == S
    assert report.degrees_of_mobility == H
    assert report.formulas["per_loop_3_16"] == W
    assert report.formulas["malyshev_3_2"] == malyshev
    if planar:
        assert (report.formulas["chebyshev_3_3"], report.formulas["planar_with_redundant_links_3_17"]) == planar
    assert report.true_mobility == W


def test_shipped_cases_are_all_tested():
    assert set(shipped_structures()) == set(BOOK)


def test_book_formulas_by_hand():
    # (3.14): a class-4 pair removes 1, class 3 removes 2, a class-2 (higher) pair 2, class 1 three
    assert F.loop_redundancy({5: 4}) == 3
    assert F.loop_redundancy({5: 2, 4: 1, 3: 1}) == 0
    assert F.loop_redundancy({2: 1, 5: 3}) == 1 and F.loop_redundancy({1: 1, 3: 1, 5: 2}) == -2
    # (3.16), ICE a: 6·3 − 5·4 + 3 = 1; robot 3.13 a: 6·7 − 3·2 − 4·1 − 5·6 + 2 − 1 = 3
    assert F.full_mobility(3, {5: 4}, [3]) == 1
    assert F.full_mobility(7, {3: 2, 4: 1, 5: 6}, [2, -1]) == 3
    assert F.reshetov_redundancy(3, {5: 4}, 1) == 3  # (3.12): S = W₀ − 6n + Σ i p_i
    assert F.compound_hinge_pairs(2) == 1 and F.compound_hinge_pairs(4) == 3  # (3.1)
    assert F.degrees_of_mobility(7, [2, 2, 1, 1]) == 1  # (3.18), gripper
    with pytest.raises(InputError, match="A_j"):
        F.degrees_of_mobility(3, [3])
    with pytest.raises(InputError, match="class"):
        F.malyshev(2, {6: 1})


def test_structural_groups_and_synthesis():
    # planar groups of lower pairs (3.9): (n, p5) = (2, 3), (4, 6), (6, 9);
    # spatial class-5 groups (3.6): 5 links, 6 pairs
    for n, p in ((2, 3), (4, 6), (6, 9)):
        assert F.group_links({5: p}, planar=True) == n and F.group_mobility(n, {5: p}, planar=True) == 0
    assert F.group_links({5: 6}) == 5 and F.group_links({5: 5}) == Fraction(25, 6)
    assert F.group_links({3: 1, 4: 1, 5: 1}) == 2  # ex. J (3.5), fig. 3.19
    assert F.group_links({4: 1, 5: 2}, redundancy=2) == 2  # group EFM of fig. 3.20 (3.24)
    assert F.group_mobility(2, {4: 1, 5: 2}, redundancy=2) == 0  # (3.23): 12 − 14 + 2
    # synthesis (3.19)–(3.22), the book's examples E–K
    assert F.synthesis_links(1, {5: 4}, planar=True) == 3  # E by (3.20)
    assert F.synthesis_links(1, {3: 1, 4: 1, 5: 2}) == 3  # E by (3.19)
    assert F.synthesis_links(5, {4: 2, 5: 1}) == 3  # F
    assert F.synthesis_links(1, {2: 1, 5: 3}, redundancy=1, redundant_links=1) == 3  # G (3.21)
    assert F.synthesis_links(1, {2: 2, 5: 3}, redundancy=2) == 3  # H
    assert F.synthesis_links(2, {2: 1, 5: 3}, redundancy=1) == 3  # I
    assert F.synthesis_links(3, {4: 1, 5: 5}, redundancy=2) == 5  # K
    schemes = F.enumerate_schemes(1, [3, 4, 5], max_pairs=6)
    assert {"n": 3, "pairs": {5: 2, 4: 1, 3: 1}, "loops": 1, "constraints": 17} in schemes
    assert all(Fraction(1 + s["constraints"], 6) == s["n"] for s in schemes)
    assert {"n": 3, "pairs": {5: 1, 4: 2}, "loops": 0, "constraints": 13} in F.enumerate_schemes(5, [4, 5], max_pairs=3)


@pytest.mark.parametrize("name", available_robots())
def test_formulas_agree_with_the_model_for_every_built_in_mechanism(name):
    mech = mechatron.load(name)
    report = analyse(mech)
    W = report.mobility
    assert W == mech.mobility() == len(mech.actuated)
    assert report.formulas["reshetov_3_11"] == W
    if report.description.planar:
        assert report.formulas["per_loop_3_16"] == W
    else:
        # The per-loop S_j = 3 − Σ (5 − i) p_i of [Egorov, 3.14] counts a loop's constraints as a planar loop's: the
        # Delta's spatial loops (a spherical closure, S_j = 1 each) come out 3 over, which the model does not have.
        assert report.formulas["per_loop_3_16"] == W + sum(report.loop_redundancies)
    if report.description.planar:
        assert report.formulas["chebyshev_3_3"] == W
        # Malyshev counts spatial constraints: S_j = 3 per planar loop of lower pairs (1 with a line contact)
        assert report.formulas["malyshev_3_2"] == W - sum(report.loop_redundancies)
    else:
        assert report.formulas["malyshev_3_2"] == W
    assert report.loops == len(mech.closures) and report.redundant_equations == 0
    if report.degrees_of_mobility is not None and name != "grab":
        assert report.degrees_of_mobility == len(mech.actuated)


def test_assur_groups_of_the_built_in_linkages():
    expected = {"crank_slider": ["RRP"], "scotch_yoke": ["RPP"], "slotted_link": ["RPR"],
                "front_shovel": ["RRR", "RRR", "RRR"], "six_bar_bucket": ["RRR", "RRR"], "seven_bar": ["RRR", "RRR"]}
    for name, dyads in expected.items():
        decomposition = analyse(mechatron.load(name)).decomposition
        assert decomposition.complete
        assert [g.dyad for g in decomposition.groups] == dyads, name
    shovel = analyse(mechatron.load("front_shovel")).decomposition
    assert [g.driven for g in shovel.groups] == [("L1",), ("L2",), ("L3",)]  # each cylinder inside its dyad
    gripper = analyse(read_structure(structure_file("gripper_3_12a"))).decomposition
    assert [len(g.links) for g in gripper.groups] == [1, 1, 2, 2] and gripper.driving_links == ("rack",)


def test_special_geometry_the_formula_cannot_see():
    """A double parallelogram: Chebyshev gives 3·4 − 2·6 = 0, but the parallel extra link leaves it movable."""
    b = PlanarBuilder("double_parallelogram")
    b.point("A", GROUND, (0.0, 0.0))
    b.point("D", GROUND, (1.0, 0.0))
    b.point("G", GROUND, (0.5, 0.0))
    crank = b.revolute("crank", "A", toward=(0.0, 1.0), coordinate="q1")
    b.point("B", crank, (0.0, 1.0))
    coupler = b.revolute("coupler", "B", toward=(1.0, 1.0), coordinate="q2")
    b.point("C", coupler, (1.0, 1.0))
    b.point("H", coupler, (0.5, 1.0))
    rocker = b.revolute("rocker", "D", toward=(1.0, 1.0), coordinate="q3")
    b.point("C_r", rocker, (1.0, 1.0))
    extra = b.revolute("extra", "G", toward=(0.5, 1.0), coordinate="q4")
    b.point("H_e", extra, (0.5, 1.0))
    b.pin("C", "C_r")
    b.pin("H", "H_e")
    mech = b.build(actuated=["q1"], tool="C")
    report = analyse(mech)
    assert report.formulas["chebyshev_3_3"] == 0 and report.mobility == 1 and report.redundant_equations == 1
    assert not report.agreement["chebyshev_3_3"]
    assert any("dependent at this geometry" in note for note in report.notes)


@pytest.mark.parametrize("text, message", [
    ('links = ["1"]\n[[pairs]]\nname = "A"\nclass = 7\nlinks = ["0", "1"]\n', "unknown pair class 7"),
    ('links = ["1"]\n[[pairs]]\nname = "A"\nkind = "Q"\n', "unknown pair kind"),
    ('links = ["1"]\n[[pairs]]\nname = "A"\nkind = "R"\nclass = 4\n', "is class 5, not 4"),
    ('links = ["1"]\n[[pairs]]\nname = "A"\nkind = "R"\nlinks = ["1", "1"]\n', "joins link '1' to itself"),
    ('links = ["1"]\n[[pairs]]\nname = "A"\nkind = "R"\nlinks = ["0", "9"]\n', "unknown link '9'"),
    ('links = ["1", "2"]\n[[pairs]]\nname = "A"\nkind = "R"\n[[pairs]]\nname = "B"\nkind = "R"\n'
     '[[pairs]]\nname = "C"\nkind = "R"\n[[loops]]\npairs = ["A", "B", "C"]\n[[loops]]\npairs = ["A", "B"]\n',
     "inconsistent counts"),
    ('links = ["1", "2", "3"]\n[[pairs]]\nname = "A"\nkind = "R"\n', "inconsistent counts"),
    ('links = ["1", "2"]\n[[pairs]]\nname = "A"\nkind = "R"\nlinks = ["0", "1"]\n[[pairs]]\nname = "B"\n'
     'kind = "R"\nlinks = ["1", "2"]\n[[pairs]]\nname = "C"\nkind = "R"\nlinks = ["1", "2"]\n'
     '[[loops]]\npairs = ["A", "B", "C"]\n', "is not closed"),
    ('links = ["1"]\n[[pairs]]\nname = "A"\nkind = "R"\n[[loops]]\npairs = ["Z"]\n', "unknown pair"),
])
def test_bad_structure_files(tmp_path, text, message):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as info:
        read_structure(path)
    assert info.value.file == str(path)


def test_pair_kinds_table_3_1():
    assert pair_kind("В").name == "revolute" and pair_kind("r").cls == 5
    assert pair_kind("Сп").mobilities == 2 and pair_kind("С").cls == 3 and pair_kind("T").cls == 1


def test_structure_command(capsys, tmp_path):
    assert main(["structure", "crank_slider", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["mobility"] == 1
    assert result["formulas"]["chebyshev_3_3"] == 1 and result["formulas"]["malyshev_3_2"] == -2
    assert result["groups"][0]["dyad"] == "RRP"
    assert main(["structure", "gripper_3_12a"]) == 0
    out = capsys.readouterr().out
    assert "S_3 = 3 [Egorov, 3.14]" in out and "H [Egorov, 3.18] = 1" in out
    assert main(["structure", "puma560", "--json"]) == 0
    puma = json.loads(capsys.readouterr().out)
    assert puma["mobility"] == 6 and puma["formulas"]["malyshev_3_2"] == 6
    bad = tmp_path / "bad.toml"
    bad.write_text('links = ["1"]\n[[pairs]]\nname = "A"\nclass = 9\n')
    assert main(["structure", str(bad)]) == 2
    assert "bad.toml" in capsys.readouterr().err
    assert np.isfinite(1.0)


def test_structure_report_protocol():
    """to_frame is the pairs table, as_dict the JSON, plot the mobility by formula; for a model and a description."""
    for report in (analyse(mechatron.load("six_bar_bucket")), analyse_structure("gripper_3_12a")):
        data = check_result(report)
        frame = report.to_frame()
        assert list(frame["pair"]) == [p.name for p in report.description.pairs]
        assert (frame["class"] + frame["mobilities"] == 6).all()
        assert frame["actuated"].sum() == sum(p.actuated for p in report.description.pairs)
        for j, loop in enumerate(report.description.loops, start=1):  # each loop's pairs carry its number
            assert set(frame.loc[frame["loops"].str.split().apply(lambda x: str(j) in x), "pair"]) == set(loop.pairs)
        assert data["formulas"] == report.formulas and data["mobility"] == report.true_mobility
        ax = report.plot().axes[0]
        bars = {patch.get_y() + patch.get_height() / 2: patch.get_width() for patch in ax.patches}
        assert [bars[k] for k in sorted(bars)] == list(report.formulas.values())  # a bar per formula, in order


def test_structure_command_outputs_are_the_result(capsys, tmp_path):
    report = analyse(mechatron.load("crank_slider"))
    assert main(["structure", "crank_slider", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads(report.to_json())
    csv, png = tmp_path / "pairs.csv", tmp_path / "mobility.png"
    assert main(["structure", "crank_slider", "--csv", str(csv), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(str(report)) and f"wrote {csv}" in out and png.stat().st_size > 0
    import pandas as pd

    pd.testing.assert_frame_equal(pd.read_csv(csv, dtype=str, keep_default_na=False), report.to_frame().astype(str))


def test_open_chain_of_many_pairs_is_fast():
    """The group search tries only connected sets grown from the placed links: an open chain of 400 passive pairs
    (no group exists: each link adds 3 − 2 = 1 mobility) is analysed at once, H = n (3.18 with K = 0)."""
    import time

    n = 400
    links = [f"l{i}" for i in range(1, n + 1)]
    pairs = [Pair(f"p{i}", 5, "R", ("0" if i == 1 else f"l{i - 1}", f"l{i}")) for i in range(1, n + 1)]
    start = time.perf_counter()
    report = analyse(StructuralDescription("chain", links, pairs, planar=True))
    assert time.perf_counter() - start < 2.0
    assert report.decomposition.groups == () and len(report.decomposition.unplaced) == n
    assert report.degrees_of_mobility == n and report.formulas["chebyshev_3_3"] == n  # 3n − 2n
    # a chain of dyads, each hung between the last one and the frame: every dyad found, in order
    links, pairs = [], []
    previous = "0"
    for k in range(60):
        a, b = f"a{k}", f"b{k}"
        links += [a, b]
        pairs += [Pair(f"A{k}", 5, "R", (previous, a)), Pair(f"B{k}", 5, "R", (a, b)), Pair(f"C{k}", 5, "R", (b, "0"))]
        previous = b
    start = time.perf_counter()
    chain = analyse(StructuralDescription("dyads", links, pairs, planar=True)).decomposition
    assert time.perf_counter() - start < 2.0
    assert chain.complete and [g.dyad for g in chain.groups] == ["RRR"] * 60
    assert [g.links for g in chain.groups] == [(f"a{k}", f"b{k}") for k in range(60)]

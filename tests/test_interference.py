"""Interference of a linkage's bodies and cylinders along a sweep (mechatron.kinematics.interference): the signed
segment distance against hand closed forms, a crank-slider whose rod meets a post on the frame at a crank angle
derived by hand, the pairs joined by design left out, the shipped scissor lift and front shovel, and the CLI."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.kinematics.interference import interference, point_segment_distance, segment_distance

EXAMPLES = "examples/data/"


# ------------------------------------------------------------------------------------------- segment distances
def test_point_segment_distance_hand_values():
    a, b = (0.0, 0.0), (1.0, 0.0)
    assert point_segment_distance((0.5, 1.0), a, b) == pytest.approx(1.0)  # foot of the normal inside
    assert point_segment_distance((2.0, 1.0), a, b) == pytest.approx(math.sqrt(2.0))  # nearest end b
    assert point_segment_distance((-3.0, -4.0), a, b) == pytest.approx(5.0)  # nearest end a: a 3-4-5 triangle
    assert point_segment_distance((3.0, 4.0), (0.0, 0.0), (0.0, 0.0)) == pytest.approx(5.0)  # a point


def test_crossing_segments_are_minus_the_least_move_that_parts_them():
    # AB on the x axis from -1 to 2, CD on the y axis from -0.5 to 3: they cross at the origin. Parting them takes
    # moving CD up by 0.5 (C onto AB's line), less than 1 (A onto CD's line), 2 or 3.
    assert segment_distance((-1.0, 0.0), (2.0, 0.0), (0.0, -0.5), (0.0, 3.0)) == pytest.approx(-0.5)
    # the same pair tilted by 30° and moved: a rigid motion keeps the distance
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)

    def moved(p):
        return (c * p[0] - s * p[1] + 0.3, s * p[0] + c * p[1] - 1.0)

    assert segment_distance(*(moved(p) for p in ((-1, 0), (2, 0), (0, -0.5), (0, 3)))) == pytest.approx(-0.5)
    # an X of two diagonals of the unit square: each end is 1/√2 from the other line
    assert segment_distance((0, 0), (1, 1), (0, 1), (1, 0)) == pytest.approx(-1 / math.sqrt(2))


def test_parallel_touching_and_skew_segments():
    assert segment_distance((0, 0), (1, 0), (0.5, 0.3), (2, 0.3)) == pytest.approx(0.3)  # parallel, overlapping
    assert segment_distance((0, 0), (1, 0), (1.5, 0.3), (2, 0.3)) == pytest.approx(math.hypot(0.5, 0.3))  # B to C
    assert segment_distance((0, 0), (2, 0), (1, 0), (3, 0)) == pytest.approx(0.0)  # collinear, overlapping
    assert segment_distance((0, 0), (2, 0), (1, 0), (1, 2)) == pytest.approx(0.0)  # a T: C on AB
    # skew, apart: C = (1, 0) is 1/√2 from the line y = x, its foot (0.5, 0.5) inside AB
    assert segment_distance((0, 0), (1, 1), (1, 0), (2, -1)) == pytest.approx(1 / math.sqrt(2))


def test_segment_distance_broadcasts_and_matches_dense_sampling():
    rng = np.random.default_rng(3)
    a, b, c, d = (rng.uniform(-1, 1, (400, 2)) for _ in range(4))
    s = segment_distance(a, b, c, d)
    # 2001 points along AB, each one's distance to CD by the foot of its normal clipped to CD
    p = a[:, None] + np.linspace(0.0, 1.0, 2001)[None, :, None] * (b - a)[:, None]  # (N, 2001, 2)
    cd = (d - c)[:, None]
    u = np.clip(np.sum((p - c[:, None]) * cd, axis=-1) / np.sum(cd * cd, axis=-1), 0.0, 1.0)
    brute = np.linalg.norm(p - (c[:, None] + u[..., None] * cd), axis=-1).min(axis=1)
    apart = s > 0
    assert apart.sum() > 100 and (~apart).sum() > 50
    assert np.allclose(s[apart], brute[apart], atol=1e-3)  # dense sampling finds the same least distance
    assert np.all(brute[~apart] < 1e-3)  # a crossing pair: AB's samples reach CD


# ------------------------------------------------------------------------------------ a crank-slider and a post
R, L, CROSS_DEG = 0.1, 0.3, 45.0  # crank, rod (m); the crank angle where the rod reaches the post (deg)


def _crank_slider_with_post(tmp_path):
    """A central crank-slider (crank AB = R about A, rod BC = L, C on the x axis) with a vertical post S1–S2 on the
    frame, S1 the middle of the rod at the crank angle 45°: B = R (cos 45°, sin 45°), C = (R cos 45° +
    sqrt(L² − R² sin² 45°), 0). The rod's height at the post's x rises with the crank angle up to 55°, so the rod
    reaches S1 at 45° and crosses the post beyond it. Drawn at 20°."""
    t = math.radians(CROSS_DEG)
    bx, by = R * math.cos(t), R * math.sin(t)
    cx = bx + math.sqrt(L * L - by * by)
    s1 = ((bx + cx) / 2, by / 2)
    d = math.radians(20.0)
    b0 = (R * math.cos(d), R * math.sin(d))
    c0 = b0[0] + math.sqrt(L * L - b0[1] ** 2)
    text = f"""
name = "post_crank"
actuated = ["theta"]
[points]
A = [0.0, 0.0]
B = [{b0[0]!r}, {b0[1]!r}]
C = [{c0!r}, 0.0]
S1 = [{s1[0]!r}, {s1[1]!r}]
S2 = [{s1[0]!r}, {s1[1] + 0.1!r}]
[[bodies]]
name = "ground"
points = ["A", "S1", "S2"]
draw = ["S1", "S2"]
[[bodies]]
name = "crank"
points = ["A", "B"]
[[bodies]]
name = "rod"
points = ["B", "C"]
[[bodies]]
name = "slider"
points = ["C"]
draw_as = "slider"
[[joints]]
type = "revolute"
body = "crank"
at = "A"
coordinate = "theta"
toward = "B"
lower_deg = 0
upper_deg = 120
[[joints]]
type = "revolute"
body = "rod"
at = "B"
[[joints]]
type = "prismatic"
body = "slider"
at = "A"
direction = [1.0, 0.0]
[[closures]]
type = "pin"
point = "C"
"""
    path = tmp_path / "post_crank.toml"
    path.write_text(text)
    return path, s1


def test_the_rod_meets_the_post_at_the_hand_crank_angle(tmp_path):
    path, s1 = _crank_slider_with_post(tmp_path)
    mech = mechatron.load(str(path))
    samples = 241  # 0.5° steps over 0…120°
    result = interference(mech, samples=samples)
    step = 120.0 / (samples - 1)
    (line,) = result.warnings()
    assert line.startswith("interference: ground and rod at theta = ")
    (row,) = [r for r in result.rows() if r["interferes"]]
    assert (row["first"], row["second"]) == ("ground", "rod")
    assert CROSS_DEG < math.degrees(row["theta"]) <= CROSS_DEG + step + 1e-9
    # at theta = 0 the rod lies on the x axis below the post: the gap is S1's height R sin 45° / 2
    assert result.sweep.table["theta"].iloc[0] == pytest.approx(0.0)
    k = [(result.elements[i].name, result.elements[j].name) for i, j in result.pairs].index(("ground", "rod"))
    assert result.gap[0, k] == pytest.approx(s1[1], abs=1e-9)


def test_pairs_joined_by_design_are_left_out_and_widths_count(tmp_path):
    path, _ = _crank_slider_with_post(tmp_path)
    mech = mechatron.load(str(path))
    width = 0.02
    result = interference(mech, samples=121, width=width)
    checked = {frozenset((result.elements[i].name, result.elements[j].name)) for i, j in result.pairs}
    assert checked == {frozenset(("ground", "rod")), frozenset(("crank", "slider"))}
    assert {frozenset(p) for p in result.excluded} == {frozenset(p) for p in (
        ("ground", "crank"), ("ground", "slider"), ("crank", "rod"), ("rod", "slider"))}
    # crank and rod share the pin B: 20 mm wide they overlap there, yet are never named
    assert all("crank and rod" not in w and "rod and slider" not in w for w in result.warnings())
    # the crank–slider gap by hand: C = (x_C, 0) to the segment AB, less the width (two halves of 20 mm)
    theta = result.sweep.table["theta"].to_numpy()
    xc = R * np.cos(theta) + np.sqrt(L * L - (R * np.sin(theta)) ** 2)
    along = xc * np.cos(theta)  # C's projection on the crank's line, from A
    hand = np.where(along >= R, L, np.where(along >= 0.0, xc * np.abs(np.sin(theta)), xc)) - width
    k = [frozenset((result.elements[i].name, result.elements[j].name)) for i, j in result.pairs].index(
        frozenset(("crank", "slider")))
    assert np.allclose(result.gap[:, k], hand, atol=1e-9)


def test_result_protocol(tmp_path):
    path, _ = _crank_slider_with_post(tmp_path)
    result = interference(mechatron.load(str(path)), samples=61)
    frame = result.to_frame()
    assert list(frame.columns[:5]) == ["first", "second", "interferes", "first_sample", "theta"]
    assert frame["interferes"].sum() == 1
    data = json.loads(json.dumps(result.as_dict(), allow_nan=False))
    assert data["warnings"] == result.warnings() and len(data["pairs"]) == 2
    assert "ground and rod" in str(result)
    ax = result.plot().axes[0]
    assert ax.get_xlabel() == "theta (deg)" and ax.get_ylabel() == "gap between outlines (m)"
    assert any(line.get_label() == "ground – rod" for line in ax.get_lines())


def test_bad_input_names_the_option(tmp_path):
    path, _ = _crank_slider_with_post(tmp_path)
    mech = mechatron.load(str(path))
    with pytest.raises(InputError, match="width for boom: no such body or cylinder"):
        interference(mech, samples=5, widths={"boom": 0.1})
    with pytest.raises(InputError, match="clearance"):
        interference(mech, samples=5, clearance=-1.0)
    with pytest.raises(InputError, match="ignore"):
        interference(mech, samples=5, ignore=[("rod", "boom")])
    assert not interference(mech, samples=121, ignore=[("rod", "ground")]).warnings()


# ------------------------------------------------------------------------------------------ the shipped examples
def _crosses(a, b, c, d):
    """Whether segments ab and cd cross (rows of (N, 2)), by solving a + t (b − a) = c + u (d − c) for t, u: a
    method of its own, not the module's signs of cross products."""
    m = np.stack([b - a, c - d], axis=-1)  # (N, 2, 2): columns b − a and −(d − c)
    tu = np.linalg.solve(m, (c - a)[..., None])[..., 0]
    return np.all((tu > 0.0) & (tu < 1.0), axis=-1)


def _xy(table, frame):
    name = frame.split("@")[0]
    return table[[f"{name}_x", f"{name}_y"]].to_numpy()


def _crossing_pairs(result):
    """The pairs whose outlines cross at some pose of the sweep, from the sweep's own point columns."""
    table, out = result.sweep.table, set()
    for i, j in result.pairs:
        ei, ej = result.elements[i], result.elements[j]
        for p, q in zip(ei.frames, ei.frames[1:]):
            for r, s in zip(ej.frames, ej.frames[1:]):
                if _crosses(_xy(table, p), _xy(table, q), _xy(table, r), _xy(table, s)).any():
                    out.add((ei.label, ej.label))
    return out


def test_scissor_lift_cylinder_crosses_arm2_in_the_drawing():
    """The scissor lift's cylinder P–Q crosses arm 2 over its whole stroke in the drawing's plane (in the machine
    it sits between the arms); nothing else meets."""
    mech = mechatron.load(EXAMPLES + "scissor_lift.toml")
    result = interference(mech, samples=60)
    assert [(r["first"], r["second"]) for r in result.rows() if r["interferes"]] == [("cylinder cyl", "arm2")]
    assert _crossing_pairs(result) == {("cylinder cyl", "arm2")}
    # by hand: θ from the cylinder's length c = |Q − P|, Q = 0.9 (cos θ, sin θ), P = (0.5, −0.15); arm 2 runs from
    # (1.2 cos θ, 0) to (0, 1.2 sin θ); the two cross at every length of the stroke 0.5…0.84 m
    c = result.sweep.table["cyl"].to_numpy()
    theta = np.array([_scissor_angle(x) for x in c])
    P = np.tile([0.5, -0.15], (len(c), 1))
    Q = 0.9 * np.column_stack([np.cos(theta), np.sin(theta)])
    foot2 = np.column_stack([1.2 * np.cos(theta), 0 * theta])
    top2 = np.column_stack([0 * theta, 1.2 * np.sin(theta)])
    assert _crosses(P, Q, foot2, top2).all()
    k = [r["first"] for r in result.rows()].index("cylinder cyl")
    assert (result.gap[:, k] < 0).all() and result.rows()[k]["first_sample"] == 0


def _scissor_angle(c):
    """θ with |0.9 (cos θ, sin θ) − (0.5, −0.15)| = c: c² = 0.81 + 0.2725 − 0.9 (cos θ − 0.3 sin θ) (2·0.5), so
    cos θ − 0.3 sin θ = (1.0825 − c²) / 0.9, i.e. √1.09 cos(θ + atan 0.3) = (1.0825 − c²) / 0.9."""
    return math.acos((1.0825 - c * c) / 0.9 / math.sqrt(1.09)) - math.atan(0.3)


def test_front_shovel_design_bucket_cylinder_meets_boom_and_stick_cylinder():
    """The front shovel of front_shovel_design.toml, its three cylinders swept together: in the side view the
    bucket cylinder L3 crosses the boom's outline and the stick cylinder L2; the pairs flagged are exactly those a
    separate crossing test finds on the sweep's point columns."""
    from mechatron.machines.excavator import read_design, shovel_spec, synthesize
    from mechatron.model.linkage import build_linkage

    mech = build_linkage(shovel_spec(synthesize(read_design(EXAMPLES + "front_shovel_design.toml"))))
    result = interference(mech, samples=100)
    flagged = {(r["first"], r["second"]) for r in result.rows() if r["interferes"]}
    assert flagged == _crossing_pairs(result) == {("cylinder L2", "cylinder L3"), ("cylinder L3", "boom")}


# ------------------------------------------------------------------------------------------------------ the CLI
def test_cli_warns_with_the_pair_and_the_pose(tmp_path, capsys):
    from mechatron.cli import main

    path, _ = _crank_slider_with_post(tmp_path)
    assert main(["linkage", str(path), "--samples", "241", "--interference"]) == 0
    err = capsys.readouterr().err
    (line,) = [x for x in err.splitlines() if "interference" in x]
    assert line.startswith("mechatron: warning: interference: ground and rod at theta = 45.5 deg (distance -")
    assert main(["linkage", str(path), "--samples", "21"]) == 0
    assert "interference" not in capsys.readouterr().err  # only when asked
    assert main(["linkage", "crank_slider", "--samples", "21", "--interference", "0.01"]) == 0
    assert "no pair of bodies and cylinders meets" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exit_code:  # argparse: one line, exit 2
        main(["linkage", str(path), "--interference", "-1"])
    assert exit_code.value.code == 2
    assert "--interference" in capsys.readouterr().err

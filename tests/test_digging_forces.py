"""Digging forces of the front shovel at the bucket lip: the rated tool forces [ISO 6015, 5.2.1–5.2.2] of the
command against the moment balance of the massless linkage about the pivot (F_cyl · e / r, e the perpendicular
distance from the pivot to the cylinder's line, r the lip's distance from the pivot, from the pins' positions) and
against finite differences of the loop closure (F_cyl / |ΔV/ΔL|); the digging capability (mechatron's estimate): the
hydraulic limit against the virtual work of the cylinder forces, the tipping limit against a moment balance of the
whole machine about its tipping lines, the slipping limit against the friction of the ground's normal force, all
written out by hand; one case governed by each limit (the illustrative machine: hydraulics; a light machine:
tipping; low friction: slipping); the largest capability over the working range and where.

By hand: with only cylinder j moving (the others held) the lip V moves along u_j = ∂V/∂L_j (central differences of
the loop closure); a digging resistance −D û_j on the lip loads each cylinder i by D û_j·∂V/∂L_i (virtual work:
F_i δL_i = −f·δV), on top of its share F₀ of the weights (the constrained inverse dynamics, checked against the virtual
work of the weights). The masses: the boom, stick and bucket as uniform bars CF, FQ, QV.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from mechatron.dynamics.trajectory import holding_forces
from mechatron.kinematics.geometry import point_positions
from mechatron.kinematics.loops import assemble
from mechatron.machines import excavator as ex
from mechatron.machines.digging import digging_forces
from mechatron.machines.shovel_machine import ShovelMachine

G = 9.81
DESIGN = ex.FrontShovelDesign()
POSES = {"L1": [3.0, 2.6, 3.3], "L2": [2.5, 2.2, 2.8], "L3": [2.2, 2.4, 2.0]}
LIGHT = ShovelMachine(upper_mass=6000.0, undercarriage_mass=5000.0, upper_centre=(-0.5, 1.5))
SLIPPERY = ShovelMachine(friction=0.1)


@pytest.fixture(scope="module")
def mech():
    return ex.build_linkage(ex.shovel_spec(ex.synthesize(DESIGN)))


def hand_limits(mech, design, machine, lengths, tool):
    """(hydraulic, tipping, slipping) N for the tool's cylinder extending (bucket: L3, arm: L2) by hand."""
    q = assemble(mech, lengths)
    pins = dict(zip("CFQV", point_positions(mech, q, "C", "F", "Q", "V")))
    h, dV, dW = 1e-6, {}, {}
    masses = {"CF": design.boom_mass, "FQ": design.stick_mass, "QV": design.bucket_mass}
    for name in ("L1", "L2", "L3"):
        # central differences, or second-order one-sided ones at the end of a stroke
        low, high = mech.cylinders[name].stroke
        side = 1 if lengths[name] - h < low else -1 if lengths[name] + h > high else 0
        steps, weights = ((h, -h), (1, -1)) if side == 0 else ((0.0, side * h, 2 * side * h), (-1.5 * side, 2 * side,
                                                                                                -0.5 * side))
        values = []
        for step in steps:
            qs = assemble(mech, {**lengths, name: lengths[name] + step}, q)
            p = dict(zip("CFQV", point_positions(mech, qs, "C", "F", "Q", "V")))
            values.append((p["V"], sum(m * (p[a][1] + p[b][1]) / 2 for (a, b), m in masses.items())))
        scale = 2 * h if side == 0 else h
        dV[name] = sum(w * v[0] for w, v in zip(weights, values)) / scale
        dW[name] = G * sum(w * v[1] for w, v in zip(weights, values)) / scale  # the weights' virtual work
    F0 = dict(zip(mech.actuated, holding_forces(mech, q[None, :])[0]))
    for name in F0:
        assert F0[name] == pytest.approx(dW[name], rel=1e-6, abs=1.0)
    u = dV["L3" if tool == "bucket" else "L2"]
    u = u / np.linalg.norm(u)
    # hydraulics: F_i(D) = F0_i + D û·∂V/∂L_i within −pull … push
    hydraulic = math.inf
    for name in mech.actuated:
        bore, rod = machine.bores[name]
        count = design.boom_cylinders if name == "L1" else 1
        p = machine.relief(name)
        push, pull = count * p * math.pi * bore**2 / 4, count * p * math.pi * (bore**2 - rod**2) / 4
        slope = float(u @ dV[name])
        if slope > 0:
            hydraulic = min(hydraulic, (push - F0[name]) / slope)
        elif slope < 0:
            hydraulic = min(hydraulic, (pull + F0[name]) / -slope)
    # tipping: moments about the front line (a, 0) and the rear line (−b, 0) of the weights and of −D û at V
    a, b = machine.track_length / 2, machine.track_length / 2
    weights = [(machine.upper_mass, machine.upper_centre[0]), (machine.undercarriage_mass, 0.0)]
    weights += [(m, (pins[s][0] + pins[e][0]) / 2) for (s, e), m in masses.items()]
    V = pins["V"]
    tipping = math.inf
    resisting_front = G * sum(m * (a - x) for m, x in weights)
    arm_front = (V[0] - a) * u[1] - V[1] * u[0]  # the moment of +û about (a, 0)
    if arm_front > 0:  # −D û turns the machine forwards over the front line
        tipping = min(tipping, resisting_front / arm_front)
    resisting_back = G * sum(m * (x + b) for m, x in weights)
    arm_back = (V[0] + b) * u[1] - V[1] * u[0]
    if arm_back < 0:
        tipping = min(tipping, resisting_back / -arm_back)
    # slipping: D |u_x| = μ (M g + D u_y)
    mass = machine.upper_mass + machine.undercarriage_mass + sum(masses.values())
    denominator = abs(u[0]) - machine.friction * u[1]
    slipping = machine.friction * mass * G / denominator if denominator > 0 else math.inf
    return {"hydraulic": hydraulic, "tipping": tipping, "slipping": slipping}, V


@pytest.mark.parametrize("machine, governs", [(ShovelMachine(), "hydraulic"), (LIGHT, "tipping"),
                                              (SLIPPERY, "slipping")], ids=["hydraulic", "tipping", "slipping"])
def test_each_limit_governs_a_case_as_by_hand(mech, machine, governs):
    result = digging_forces(DESIGN, machine, lengths=POSES)
    table = result.to_frame()
    assert len(table) == 3
    seen = set()
    for k in range(3):
        lengths = {n: POSES[n][k] for n in POSES}
        for tool in ("bucket", "arm"):
            limits, V = hand_limits(mech, DESIGN, machine, lengths, tool)
            row = table.iloc[k]
            assert (row["lip_radius_m"], row["lip_height_m"]) == pytest.approx(tuple(V), abs=1e-9)
            for limit, value in limits.items():
                assert row[f"{tool}_{limit}_N"] == pytest.approx(value, rel=1e-6), (tool, limit)
            best = min(limits, key=limits.get)
            assert row[f"{tool}_force_N"] == pytest.approx(limits[best], rel=1e-6)
            assert row[f"{tool}_limit"] == best
            seen.add(best)
    assert governs in seen
    if governs == "hydraulic":
        assert seen == {"hydraulic"}


def test_without_weights_the_hydraulic_limit_is_the_iso6015_calculated_force():
    """With massless links the digging cylinder's relief force through the lip's lever is the calculated tool force of
    [ISO 6015] (excavator.tool_forces), where that cylinder is the one that gives way."""
    design = replace(DESIGN, boom_mass=0.0, stick_mass=0.0, bucket_mass=0.0)
    mech = ex.build_linkage(ex.shovel_spec(ex.synthesize(design)))
    machine = ShovelMachine()
    table = digging_forces(design, machine, lengths=POSES).to_frame()
    cylinders = machine.cylinders(design)
    checked = 0
    for k in range(3):
        q = assemble(mech, {n: POSES[n][k] for n in POSES})
        tool = ex.tool_forces(mech, q, cylinders, machine.relief_pressure)
        for name, cylinder in (("bucket", "L3"), ("arm", "L2")):
            if table.iloc[k][f"{name}_cylinder"] == cylinder:
                assert table.iloc[k][f"{name}_hydraulic_N"] == pytest.approx(tool[name]["extending"], rel=1e-9)
                checked += 1
            else:  # a holding cylinder gives way first: less than the calculated tool force
                assert table.iloc[k][f"{name}_hydraulic_N"] < tool[name]["extending"]
    assert checked >= 2


def relief_push(design, machine, name):
    """p·πD²/4 times the cylinders side by side (N): the cylinder's force at its relief pressure, extending."""
    bore, _ = machine.bores[name]
    return (design.boom_cylinders if name == "L1" else 1) * machine.relief(name) * math.pi * bore**2 / 4


def hand_rated(mech, design, machine, tool, lengths, q=None):
    """(force N, lip V m, q) of the tool's cylinder at its relief force through the massless linkage by the moment
    balance about the pivot: the bucket cylinder G–K turns the bucket about Q, the stick cylinder D–E the stick and
    bucket about F, so F_cyl · e = F_lip · r with the lip's force tangential to its arc (no weights)."""
    base, eye, pivot, name = ("G", "K", "Q", "L3") if tool == "bucket" else ("D", "E", "F", "L2")
    q = assemble(mech, lengths, q)
    B, E, P, V = point_positions(mech, q, base, eye, pivot, "V")
    axis, r = E - B, P - B
    e = abs(axis[0] * r[1] - axis[1] * r[0]) / math.hypot(*axis)  # the perpendicular from the pivot to the line
    return relief_push(design, machine, name) * e / math.hypot(*(V - P)), V, q


def hand_rated_maxima(mech, design, machine, samples):
    """Per tool the largest hand rated force over the grid of ``samples`` lengths per stroke and its lengths: the
    bucket's depends on L3 alone (the bucket cylinder lies on the stick), the arm's on L2 and L3 (the stick cylinder
    lies on the boom; the bucket's angle sets |FV|), none on L1 (the boom turns the rest rigidly)."""
    grid = {n: np.linspace(*mech.cylinders[n].stroke, samples) for n in ("L1", "L2", "L3")}
    L1 = grid["L1"][samples // 2]
    best = {"bucket": (-1.0, None), "arm": (-1.0, None)}
    q = None
    for L2 in grid["L2"]:
        for L3 in grid["L3"]:
            lengths = {"L1": L1, "L2": L2, "L3": L3}
            for tool in best:
                force, _, q = hand_rated(mech, design, machine, tool, lengths, q)
                if force > best[tool][0] * (1 + 1e-12):
                    best[tool] = (force, lengths)
    return best


@pytest.mark.parametrize("design_file", [None, "examples/data/front_shovel_design.toml"], ids=["default", "example"])
def test_the_commands_rated_tool_forces_are_the_massless_linkages(design_file, capsys):
    """`mechatron excavator --lift-chart --json`: the rated tool forces [ISO 6015, 5.2.1–5.2.2] are the largest over
    the grid of the hand moment balance of the massless linkage (the design's masses play no part), at the hand's
    lengths; at that position the finite differences of the loop closure give the same force (virtual work,
    F_cyl / |ΔV/ΔL|); the capability is a separate result, below the rated force (the weights, tipping, slipping)."""
    import json
    from pathlib import Path

    from mechatron.cli import main
    from mechatron.machines.shovel_machine import read_machine

    args = ["excavator", "--lift-chart", "--samples", "5", "--json"]
    design, machine = DESIGN, ShovelMachine()
    if design_file:
        path = Path(__file__).resolve().parent.parent / design_file
        args += ["--design", str(path)]
        design, machine = ex.read_design(path), read_machine(path)
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"lift_chart", "rated_tool_forces", "digging_capability"}
    mech = ex.build_linkage(ex.shovel_spec(ex.synthesize(design)))
    best = hand_rated_maxima(mech, design, machine, 5)
    for tool, name, pivot in (("bucket", "L3", "Q"), ("arm", "L2", "F")):
        rated = out["rated_tool_forces"][tool]
        force, lengths = best[tool]
        assert rated["force_N"] == pytest.approx(force, rel=1e-9), tool
        assert (rated["cylinder"], rated["pivot"]) == (name, pivot)
        assert rated["cylinder_force_N"] == pytest.approx(relief_push(design, machine, name), rel=1e-12)
        assert rated["relief_pressure_Pa"] == machine.relief(name)
        reported = rated["cylinder_lengths_m"]
        kept = ("L3",) if tool == "bucket" else ("L2", "L3")
        assert [reported[n] for n in kept] == pytest.approx([lengths[n] for n in kept], abs=1e-9)
        at, V, q = hand_rated(mech, design, machine, tool, reported)
        assert at == pytest.approx(force, rel=1e-9)
        assert rated["position_m"] == pytest.approx([V[0] - machine.slew_axis, V[1]], abs=1e-9)
        assert rated["radius_m"] == pytest.approx(math.hypot(*(V - point_positions(mech, q, pivot)[0])), rel=1e-9)
        # virtual work by finite differences: F_lip |δV| = F_cyl δL with the others held
        h = 1e-6
        low, high = mech.cylinders[name].stroke
        a, b = max(low, reported[name] - h), min(high, reported[name] + h)
        ends = [point_positions(mech, assemble(mech, {**reported, name: x}, q), "V")[0] for x in (a, b)]
        assert rated["force_N"] == pytest.approx(rated["cylinder_force_N"] * (b - a) / math.hypot(*(ends[1] - ends[0])),
                                                 rel=1e-6)
        capability = out["digging_capability"][tool]
        assert capability["force_N"] < rated["force_N"]
        assert capability["limit"] in ("hydraulic", "tipping", "slipping")


def test_the_rated_tool_forces_leave_the_weights_out():
    """The same design with ten times the link masses has the same rated tool forces [ISO 6015, 5.2.1–5.2.2] (no
    weights) and a different capability (the weights load the cylinders)."""
    heavy = replace(DESIGN, boom_mass=45000.0, stick_mass=22000.0, bucket_mass=38000.0)
    light, loaded = (digging_forces(d, ShovelMachine(), lengths=POSES) for d in (DESIGN, heavy))
    for tool in ("bucket", "arm"):
        assert loaded.rated[tool]["force_N"] == pytest.approx(light.rated[tool]["force_N"], rel=1e-9)
        np.testing.assert_allclose(loaded.table[f"{tool}_rated_N"], light.table[f"{tool}_rated_N"], rtol=1e-9)
        assert not np.allclose(loaded.table[f"{tool}_hydraulic_N"], light.table[f"{tool}_hydraulic_N"], rtol=1e-3)


def test_the_largest_force_over_the_range_and_where():
    result = digging_forces(DESIGN, ShovelMachine(), samples=5)
    table = result.to_frame()
    front = ShovelMachine().tipping_lines["front"]
    assert (table["lip_radius_m"] > front).all()  # the lip ahead of the front tipping line
    assert len(table) <= 125
    data = result.as_dict()["digging_capability"]
    for tool in ("bucket", "arm"):
        k = table[f"{tool}_force_N"].idxmax()
        best = data[tool]
        assert best["force_N"] == pytest.approx(table[f"{tool}_force_N"].max())
        assert best["position_m"] == pytest.approx([table.loc[k, "lip_radius_m"], table.loc[k, "lip_height_m"]])
        assert best["limit"] == table.loc[k, f"{tool}_limit"]
        assert min(best[f"{x}_N"] or math.inf for x in ("hydraulic", "tipping", "slipping")) == \
            pytest.approx(best["force_N"])
        assert sum(best["governed"].values()) == len(table)


def test_the_largest_forces_the_page_quotes_by_hand(mech):
    """docs/front_shovel_design.md quotes the largest digging forces of the default command (31 lengths a stroke):
    their three limits at the quoted positions are the hand references'."""
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "front_shovel_design.md").read_text(encoding="utf-8")
    result = digging_forces(DESIGN, ShovelMachine(), samples=31)
    for tool, words in (("bucket", "bucket-cylinder"), ("arm", "arm-cylinder")):
        best = result.largest[tool]
        limits, V = hand_limits(mech, DESIGN, ShovelMachine(), best["cylinder_lengths_m"], tool)
        assert best["position_m"] == pytest.approx(list(V), abs=1e-9)
        assert best["force_N"] == pytest.approx(min(limits.values()), rel=1e-6)
        assert best["limit"] == min(limits, key=limits.get) == "hydraulic"
        radius, height = best["position_m"]
        assert f"largest {words} force is {best['force_N'] / 1e3:.1f} kN, hydraulic-limited" in page.replace("\n", " ")
        assert f"radius of {radius:.3f} m and {-height:.3f} m below the ground" in page.replace("\n", " ")
    rated = hand_rated_maxima(mech, DESIGN, ShovelMachine(), 31)
    for tool, words in (("bucket", "bucket cylinder"), ("arm", "arm cylinder")):
        assert result.rated[tool]["force_N"] == pytest.approx(rated[tool][0], rel=1e-9)
        assert f"{rated[tool][0] / 1e3:.1f} kN for the {words}" in page.replace("\n", " ")
    counts = result.largest["bucket"]["governed"], result.largest["arm"]["governed"]
    assert f"Slipping governs {counts[0]['slipping']} of the {len(result.table):,} positions".replace(",", " ") \
        in page.replace("\n", " ")
    assert f"{counts[1]['slipping']} for the arm" in page


def test_the_examples_largest_forces_the_page_quotes_by_hand():
    from pathlib import Path

    from mechatron.machines.shovel_machine import read_machine

    root = Path(__file__).resolve().parent.parent
    path = root / "examples" / "data" / "front_shovel_design.toml"
    page = (root / "docs" / "front_shovel_design.md").read_text(encoding="utf-8").replace("\n", " ")
    design, machine = ex.read_design(path), read_machine(path)
    mech = ex.build_linkage(ex.shovel_spec(ex.synthesize(design)))
    result = digging_forces(design, machine, samples=31)
    forces = []
    for tool in ("bucket", "arm"):
        best = result.largest[tool]
        limits, _ = hand_limits(mech, design, machine, best["cylinder_lengths_m"], tool)
        assert best["limit"] == min(limits, key=limits.get) == "slipping"
        assert best["force_N"] == pytest.approx(limits["slipping"], rel=1e-6)
        assert limits["hydraulic"] > limits["slipping"]
        forces.append(best["force_N"] / 1e3)
    assert f"limited by slipping on the ground of friction 0.5: {forces[0]:.1f} kN for the bucket cylinder and " \
           f"{forces[1]:.1f} kN for the arm cylinder" in page
    rated = hand_rated_maxima(mech, design, machine, 31)
    assert f"rated tool forces [ISO 6015, 5.2.1–5.2.2] are {rated['bucket'][0] / 1e3:.1f} kN for the bucket cylinder " \
           f"and {rated['arm'][0] / 1e3:.1f} kN for the arm cylinder" in page


def test_lengths_outside_a_stroke_are_refused():
    import mechatron

    with pytest.raises(mechatron.InputError, match="lengths of L3 must be within its stroke"):
        digging_forces(DESIGN, lengths={"L1": [3.0], "L2": [2.5], "L3": [5.0]})

"""Issue 33: bad input on the front-shovel design file's fields and its ``[machine]`` table, and ``--lift-chart``'s
work bounded before it starts.

Every field is fuzzed through the command line (NaN, ±inf, 1e308, negative, 0, the default given in mm/g, a string):
exit 2, one line naming the file and the field, the input byte-identical. The plausible ranges are
mechatron's (docs/front_shovel_design.md, "Plausible ranges"); at their bounds a value is accepted and just beyond it
refused. The links that cannot reach a working dimension, a tipping line behind the lip's reach and a cylinder
triangle through its dead point name the field that asks for it, checked against the closed forms by hand.
"""

from __future__ import annotations

import dataclasses
import gc
import math
import tracemalloc

import numpy as np
import pytest
from corpus import assert_clean_error, run

from mechatron.errors import InputError
from mechatron.io import budget
from mechatron.kinematics.sweeps import position_bytes
from mechatron.machines import lift_chart as lc
from mechatron.machines.excavator import DESIGN_RANGES, FrontShovelDesign, synthesize
from mechatron.machines.shovel_machine import ShovelMachine

DESIGN = FrontShovelDesign()
MACHINE = ShovelMachine()


def _scaled(value, factor: float) -> str:
    if isinstance(value, tuple):
        return "[" + ", ".join(repr(float(v) * factor) for v in value) + "]"
    return repr(float(value) * factor)


def _design_cases() -> list[tuple[str, str, str]]:
    """(field, TOML line, id) for every design field and bad value; the default × 1000 (mm, g) among them."""
    cases = []
    for f in dataclasses.fields(FrontShovelDesign):
        default = getattr(DESIGN, f.name)
        values = ["nan", "inf", "-inf", "1e308", "-1.0", '"abc"', _scaled(default, 1000)]
        if f.name not in ("boom_foot", "ground_angle_deg", "dump_angle_deg", "boom_lever_offset_deg",
                          "stick_lever_angle_deg", "bucket_lever_angle_deg") and not f.name.endswith("_mass"):
            values.append("0.0")  # 0 is a legal angle, mass and coordinate
        if f.name in ("boom_lever_offset_deg", "stick_lever_angle_deg", "bucket_lever_angle_deg"):
            values.remove("-1.0")  # a legal angle
        if f.name == "boom_foot":
            values = [f"[{v}, 2.7]" if v != '"abc"' else v for v in values[:-1]] + [values[-1]]
            values.remove("[-1.0, 2.7]")  # a legal coordinate
        cases += [(f.name, f"{f.name} = {v}\n", f"{f.name}={v}") for v in values]
    return cases


def _machine_cases() -> list[tuple[str, str, str]]:
    cases = []
    for f in dataclasses.fields(ShovelMachine):
        if f.name in ("bores", "reliefs"):
            continue
        default = getattr(MACHINE, f.name)
        if f.name.endswith("_tipping_line"):
            default = 2.25
        if f.name.startswith("lift_"):
            default = (4.0,)
        values = ["nan", "inf", "-inf", "1e308", '"abc"']
        if f.name != "slew_axis":  # any finite slew axis within ±100 m is legal, 0 in mm is 0
            values.append(_scaled(default, 1000))
        if f.name not in ("slew_axis", "upper_centre", "undercarriage_centre", "lift_heights"):
            values += ["-1.0", "0.0"]
        for v in values:
            if f.name.endswith("_centre") and v != '"abc"' and not v.startswith("["):
                v = f"[{v}, 0.6]"
            elif f.name.startswith("lift_") and v != '"abc"' and not v.startswith("["):
                v = f"[{v}]"
            cases.append((f"machine.{f.name}", f"[machine]\n{f.name} = {v}\n", f"machine.{f.name}={v}"))
    for table, bore, rod in (("boom_cylinder", 0.18, 0.125), ("stick_cylinder", 0.2, 0.14),
                             ("bucket_cylinder", 0.18, 0.125)):
        for key, default in (("bore", bore), ("rod", rod), ("relief_pressure", 32e6)):
            for v in ("nan", "inf", "1e308", "-1.0", "0.0", '"abc"', repr(default * 1000)):
                cases.append((f"machine.{table}.{key}", f"[machine.{table}]\n{key} = {v}\n",
                              f"machine.{table}.{key}={v}"))
    return cases


CASES = _design_cases() + _machine_cases()


def test_the_fuzz_covers_every_field():
    fields = {c[0] for c in CASES}
    assert {f.name for f in dataclasses.fields(FrontShovelDesign)} <= fields
    assert {f"machine.{f.name}" for f in dataclasses.fields(ShovelMachine) if f.name not in ("bores", "reliefs")} \
        <= fields
    assert len(CASES) > 250


@pytest.mark.parametrize("field, text, label", CASES, ids=[c[2] for c in CASES])
def test_a_bad_field_is_refused_naming_the_file_and_the_field(tmp_path, capfd, field, text, label):
    (tmp_path / "d.toml").write_text(text)
    # the design report and the lift chart read the same file; the field may carry an index: boom_foot[0]
    for extra in (["--lift-chart"], []):
        outcome = assert_clean_error(["excavator", "--design", "d.toml", "--samples", "2", *extra], capfd, tmp_path,
                                     ["d.toml"])
        assert f"field '{field}'" in outcome.err or f"field '{field}[" in outcome.err, outcome.err


# ------------------------------------------------------------------------------------------- the ranges
@pytest.mark.parametrize("name", sorted(DESIGN_RANGES))
def test_each_design_range_is_refused_just_beyond_its_bounds(name):
    """Just beyond a bound (by 1e-9 of it, or 1e-9 where the bound is 0; a count by 1) refused naming the field and
    the range."""
    plausible = DESIGN_RANGES[name]
    for bound, sign in ((plausible.low, -1), (plausible.high, 1)):
        beyond = bound + sign * (1 if name == "boom_cylinders" else max(abs(bound), 1.0) * 1e-9)
        value = (beyond, 2.7) if name == "boom_foot" else beyond
        with pytest.raises(InputError) as error:
            FrontShovelDesign(**{name: value})
        assert error.value.field == name and f"{plausible.high:g}" in error.value.message


def test_the_bounds_themselves_are_accepted_where_the_design_allows_them():
    """At the bounds the check itself lets a value through (λ = 1.1 and 3 on the boom still synthesise)."""
    for ratio in (1.1, 3.0):
        shovel = synthesize(FrontShovelDesign(boom_ratio=ratio))
        assert shovel.boom_cylinder.ratio == pytest.approx(ratio, rel=1e-12)
    assert FrontShovelDesign(boom_cylinders=4).boom_cylinders == 4
    assert FrontShovelDesign(boom_mass=0.0).boom_mass == 0.0
    with pytest.raises(InputError, match="whole number"):
        FrontShovelDesign(boom_cylinders=2.5)


def test_the_issue_cases_name_the_field_and_its_range(tmp_path, capfd):
    """A boom in mm, a stroke ratio of 1 and a tipping line 1e6 m from the slew axis."""
    for text, field, words in (("boom = 4300.0\n", "boom", ["0.01 to 100 m", "mm"]),
                               ("boom_ratio = 1.0\n", "boom_ratio", ["1.1 to 3"]),
                               ("[machine]\nfront_tipping_line = 1e6\n", "machine.front_tipping_line",
                                ["0.01 to 100 m"])):
        (tmp_path / "d.toml").write_text(text)
        assert_clean_error(["excavator", "--design", "d.toml", "--lift-chart", "--samples", "2"], capfd, tmp_path,
                           [f"d.toml: field '{field}'", *words])


def test_links_too_short_name_the_working_dimension(tmp_path, capfd):
    """A 1 m boom: the stick-out triangle of [Shovel, 3.2] needs cos θ2max = (l1² + l2² − (R1max − l3 − x_C)²) /
    (2 l1 l2), here (1 + 3.3² − (9.06 − 2 − 0.5)²) / (2·1·3.3) < −1: the digging radius is out of reach."""
    argument = (1.0 + 3.3**2 - (9.06 - 2.0 - 0.5) ** 2) / (2 * 1.0 * 3.3)
    assert argument < -1
    (tmp_path / "d.toml").write_text("boom = 1.0\n")
    assert_clean_error(["excavator", "--design", "d.toml"], capfd, tmp_path,
                       ["d.toml: field 'max_digging_radius'", "cannot reach the required digging radius"])


def test_a_tipping_line_behind_the_reach_names_the_field(tmp_path, capfd):
    """The lip reaches at most l1 + l2 + l3 + x_C = 4.3 + 3.3 + 2 + 0.5 = 10.1 m from the slew axis: a front tipping
    line at 50 m leaves no position ahead of it."""
    assert 4.3 + 3.3 + 2.0 + 0.5 < 50
    (tmp_path / "d.toml").write_text("[machine]\nfront_tipping_line = 50.0\n")
    assert_clean_error(["excavator", "--design", "d.toml", "--lift-chart", "--samples", "3"], capfd, tmp_path,
                       ["d.toml: field 'machine.front_tipping_line'", "ahead of the front tipping line"])


def test_a_cylinder_through_its_dead_point_names_the_angle(tmp_path, capfd):
    """The bucket cylinder's included angle runs from bucket_start_angle_deg over θ3's range: past 180° the
    triangle folds. 40° + the range stays below 180° (the default design); 60° + the range does not."""
    span = math.degrees(np.diff(synthesize().theta3)[0])
    assert 40 + span < 180 < 60 + span
    (tmp_path / "d.toml").write_text("bucket_start_angle_deg = 60.0\n")
    assert_clean_error(["excavator", "--design", "d.toml"], capfd, tmp_path,
                       ["d.toml: field 'bucket_start_angle_deg'", "dead point"])


def test_a_legal_extreme_gives_finite_numbers(tmp_path, capfd):
    """Massless links, the smallest bore and a tipping line just beyond the tracks: finite numbers in the JSON."""
    (tmp_path / "d.toml").write_text("boom_mass = 0.0\nstick_mass = 0.0\n[machine]\nfront_tipping_line = 3.0\n"
                                     "[machine.bucket_cylinder]\nbore = 0.01\nrod = 1e-300\n")
    outcome = run(["excavator", "--design", "d.toml", "--lift-chart", "--samples", "2", "--json"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    assert "NaN" not in outcome.out and "Infinity" not in outcome.out and outcome.err == ""


# ----------------------------------------------------------------------------------------------- the budget
@pytest.fixture
def limit(monkeypatch):
    monkeypatch.setenv(budget.ENVIRONMENT, "0.05")
    monkeypatch.delenv(budget.TIME_ENVIRONMENT, raising=False)


def _grid_file(path, radii, heights):
    path.write_text("[machine]\nlift_radii = [" + ", ".join(f"{r:.6f}" for r in radii) + "]\nlift_heights = ["
                    + ", ".join(f"{h:.6f}" for h in heights) + "]\n")


def test_a_grid_too_large_for_memory_is_refused_before_it_is_made(tmp_path, capfd):
    """20,000 radii × 20,000 heights: 4e8 cells × 200 B is 75 GiB, over any default limit (half the memory free);
    refused at once, naming the [machine] table's grid."""
    _grid_file(tmp_path / "g.toml", np.linspace(3, 9, 20000), np.linspace(-3, 8, 20000))
    with budget.memory_limit(16):
        assert_clean_error(["excavator", "--design", "g.toml", "--lift-chart"], capfd, tmp_path,
                           ["20,000 radii × 20,000 heights", "4.0e+08 cells", "lift_radii or lift_heights"])


def test_the_reached_cells_are_refused_past_the_limit(tmp_path, capfd, limit):
    """200 × 200 cells of 4 … 7 m × 0 … 5 m, most of them reached: 2000 B a cell is over 0.05 GiB."""
    _grid_file(tmp_path / "g.toml", np.linspace(4, 7, 200), np.linspace(0, 5, 200))
    assert_clean_error(["excavator", "--design", "g.toml", "--lift-chart"], capfd, tmp_path,
                       ["cells the lift point of front_shovel reaches", "limit 0.05 GiB", "lift_radii"])


def test_the_digging_positions_are_refused_past_the_limit(tmp_path, capfd, limit):
    """--samples 300 per stroke of three cylinders: 300³ = 2.7e7 positions, named as the option."""
    assert_clean_error(["excavator", "--lift-chart", "--samples", "300"], capfd, tmp_path,
                       ["--samples 300 gives 2.7e+07 positions of front_shovel", "use fewer --samples"])


def test_the_lift_chart_estimate_bounds_its_measured_peak():
    """The estimate (grid cells × GRID_BYTES + the sweep's fixed storage + reached cells × CELL_BYTES) is at least
    the peak tracemalloc measures and at most 4 times it (the rule of tests/test_bounded.py)."""
    shovel, mech = lc.lift_mechanism(DESIGN)
    lc.lift_chart(DESIGN, ShovelMachine(lift_radii=(4.0,), lift_heights=(1.0,)))  # imports and caches first
    radii, heights = tuple(np.linspace(4, 7, 80)), tuple(np.linspace(0, 5, 80))
    gc.collect()
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        chart = lc.lift_chart(DESIGN, ShovelMachine(lift_radii=radii, lift_heights=heights))
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    reached = len(chart.rows) // 2
    assert reached > 3000
    estimate = 80 * 80 * lc.GRID_BYTES + position_bytes(mech)[0] + reached * lc.CELL_BYTES
    assert peak <= estimate <= 4 * peak, (estimate, peak)


def test_the_lift_chart_of_a_grid_matches_the_cells_one_by_one():
    """The cells found at once over the grid are the cells found one by one at each (R, H)."""
    shovel, _ = lc.lift_mechanism(DESIGN)
    radii, heights = [3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.5], [-2.0, 0.0, 2.0, 4.0, 6.0, 9.0]
    chart = lc.lift_chart(DESIGN, MACHINE, radii=radii, heights=heights)
    found = {(row["radius_m"], row["height_m"]) for row in chart.rows}
    one_by_one = set()
    for r in radii:
        for h in heights:
            d = math.hypot(r - 0.5, h - 2.7)  # C = (0.5, 2.7), l1 = 4.3, l2 = 3.3
            if not 1.0 < d < 7.6:
                continue
            t2 = math.acos((4.3**2 + 3.3**2 - d * d) / (2 * 4.3 * 3.3))
            t1 = math.atan2(h - 2.7, r - 0.5) + math.acos((4.3**2 + d * d - 3.3**2) / (2 * 4.3 * d))
            if shovel.theta1[0] <= t1 <= shovel.theta1[1] and shovel.theta2[0] <= t2 <= shovel.theta2[1]:
                one_by_one.add((r, h))
    assert found == one_by_one and 10 <= len(found) < 42

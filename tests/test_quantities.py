"""The registry of quantities (mechatron.quantities) against its page (docs/quantities.md), the outputs and options
of every study analysis on the shipped mechanisms and study examples, the sizing result's totals, the units of
docs/study_analyses.md, and the charts of a study."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.quantities import (
    PATTERNS,
    PLACEHOLDERS,
    QUANTITIES,
    RENAMED,
    SUFFIXES,
    Quantity,
    axis_label,
    is_quantity,
    quantity,
    suffix,
    unit,
)
from mechatron.studies.analyses import MODULES, analysis

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
ROW = re.compile(r"^\| `(?P<name>[^`]+)` \| (?P<unit>[^|]*?) \| (?P<meaning>.*) \|$")


def tables(text: str, *header: str) -> list[list[dict[str, str]]]:
    """Every table of ``text`` whose header row starts with the cells ``header``: its rows as dicts (cells by the
    header's names, stripped)."""
    out = []
    for block in re.split(r"\n\s*\n", text):
        lines = [line for line in block.strip().splitlines() if line.startswith("|")]
        if len(lines) < 2:
            continue
        names = [c.strip() for c in lines[0].strip("|").split(" | ")]
        if names[: len(header)] != list(header):
            continue
        rows = []
        for line in lines[2:]:
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
            rows.append(dict(zip(names, cells)))
        out.append(rows)
    return out


def name_of(cell: str) -> str:
    return cell.strip().strip("`")


# --------------------------------------------------------------------------------------------------- the page
def page_rows() -> list[dict[str, str]]:
    text = (DOCS / "quantities.md").read_text(encoding="utf-8")
    return [row for table in tables(text, "name", "unit", "meaning") for row in table]


def test_the_page_lists_every_quantity_once_with_its_unit():
    rows = page_rows()
    names = [name_of(r["name"]) for r in rows]
    assert len(names) == len(set(names)), [n for n in names if names.count(n) > 1]
    assert {name_of(r["name"]): r["unit"] for r in rows} == \
        {q.name: q.unit for q in [*QUANTITIES.values(), *PATTERNS.values()]}


def test_the_index_links_the_page():
    assert "](quantities.md)" in (DOCS / "index.md").read_text(encoding="utf-8")


def test_the_pages_python_block_runs():
    text = (DOCS / "quantities.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1
    exec(compile(blocks[0], "docs/quantities.md", "exec"), {})  # noqa: S102 - the page's own example


# ------------------------------------------------------------------------------------------------ the rules
def test_a_unit_suffix_names_the_unit():
    """A name that ends in a unit suffix (the longest: _m3_s before _s) is in that unit; one spelling per quantity:
    no two names differ by case alone, and no name ends in a suffix of the wrong case (_mpa, _j, _w)."""
    names = [*QUANTITIES, *PATTERNS]
    for name in names:
        end = suffix(name)
        if end is not None:
            assert quantity(name).unit.startswith(SUFFIXES[end]), name
        tail = name.rsplit("_", 1)[-1]
        assert tail in SUFFIXES or tail.lower() not in {s.lower() for s in SUFFIXES}, name
    lower = [n.lower() for n in names]
    assert len(lower) == len(set(lower))
    # every output carries its unit in its name: the outputs of the analyses with a unit end in its suffix (the
    # drive cost is in the catalogs' currency, which no suffix names)
    for module in MODULES:
        for name in analysis(module).OUTPUTS:
            if quantity(name).unit not in ("-", "catalog currency"):
                assert suffix(name) is not None, name


def test_old_spellings_are_no_quantities():
    for old, new in RENAMED.items():
        assert old not in QUANTITIES and new in QUANTITIES
        with pytest.raises(InputError, match=f"now spelled '{new}'"):
            quantity(old)


@pytest.mark.parametrize("name, label", [
    ("reach_m", "reach (m)"), ("drive_mass_kg", "drive mass (kg)"), ("energy_per_cycle_J", "energy per cycle (J)"),
    ("min_transmission_angle_deg", "min transmission angle (deg)"), ("yield", "yield"),
    ("peak_pump_flow_m3_s", "peak pump flow (m³/s)"), ("stop_torque", "stop torque (N·m)"),
    ("pressure_MPa", "pressure (MPa)"), ("boom_max_force_N", "boom max force (N)"),
    ("J1_peak_Nm", "J1 peak (N·m)"), ("slider_rms_N", "slider rms (N)"), ("L1_max_pressure_Pa", "L1 max pressure (Pa)"),
])
def test_axis_labels(name, label):
    assert axis_label(name) == label


def test_every_label_of_a_quantity_with_a_unit_shows_it():
    for q in [*QUANTITIES.values(), *PATTERNS.values()]:
        name = q.name.replace("CYLINDER", "boom").replace("ACTUATOR", "J1")
        assert axis_label(name).endswith(f" ({q.unit})") == (q.unit != "-"), name


def test_per_item_names():
    q = quantity("boom_max_force_N")
    assert q == Quantity("boom_max_force_N", "N", PATTERNS["CYLINDER_max_force_N"].meaning.replace("CYLINDER", "boom"))
    assert unit("J2_rms_Nm") == "N·m" and unit("d3_peak_N") == "N"
    assert set(PLACEHOLDERS) == {p.split("_", 1)[0] for p in PATTERNS}
    assert not is_quantity("_max_force_N") and not is_quantity("max_force")


def test_an_unknown_name_is_one_short_line():
    with pytest.raises(InputError) as caught:
        quantity("energy_J")
    message = str(caught.value)
    assert "energy_per_cycle_J" in message and "\n" not in message and len(message) < 200
    for call in (unit, axis_label):
        with pytest.raises(InputError, match="unknown quantity 'reach'"):
            call("reach")


def test_the_module_imports_nothing_heavy():
    code = ("import sys, mechatron.quantities as q; q.axis_label('reach_m'); "
            "print(sorted(m for m in ('pandas', 'matplotlib', 'numpy', 'pinocchio', 'scipy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


# ------------------------------------------------------------------------- the analyses, results and docs
def test_every_option_and_declared_output_of_the_analyses_is_a_quantity():
    from mechatron.studies.analyses import accuracy, dynamics, linkage, sizing

    options = [*linkage.DEFAULTS, "bore", "rod", "count", *dynamics.DEFAULTS, *sizing.OPTIONS, *accuracy.OPTIONS]
    assert [o for o in options if o not in QUANTITIES] == []
    for name in MODULES:
        for output in analysis(name).OUTPUTS:
            assert output in QUANTITIES or output in PATTERNS, (name, output)


def _linkage_options(mech) -> dict:
    """Options that give every output of the linkage analysis: a bore and rod for every cylinder (its pressure)."""
    return {"cylinders": {name: {"bore": 0.1, "rod": 0.05} for name in mech.cylinders}} if mech.cylinders else {}


MECHANISMS = [*mechatron.available_robots(), "examples/data/four_bar.toml", "examples/data/scissor_lift.toml"]


@pytest.mark.parametrize("name", MECHANISMS)
def test_every_output_of_every_analysis_of_a_shipped_mechanism_is_a_quantity(name):
    mech = mechatron.load(str(ROOT / name) if name.endswith(".toml") else name)
    names = []
    if mech.closures:
        names += analysis("linkage").output_names(mech, _linkage_options(mech))
    names += analysis("dynamics").output_names(mech, {})
    names += analysis("sizing").output_names(mech, {}) + analysis("accuracy").output_names(mech, {})
    assert names and [n for n in names if not is_quantity(n)] == []
    assert all(axis_label(n) for n in names)


@pytest.mark.parametrize("path", sorted((ROOT / "examples" / "studies").glob("*.toml")), ids=lambda p: p.name)
def test_every_output_of_a_shipped_study_is_a_quantity(path):
    from mechatron.studies.spec import output_names, study_mechanism
    from mechatron.studies.spec import read_study as read_spec

    spec = read_spec(path)
    names = output_names(spec, study_mechanism(spec.mechanism))
    assert names and [n for n in names if not is_quantity(n)] == []


def test_the_sizing_results_totals_are_quantities():
    from mechatron.studies.analyses import sizing

    result = sizing.run(mechatron.load("planar_2r"), {})
    totals = result.totals()
    assert [k for k in totals if not is_quantity(k)] == []
    assert set(result.as_dict()["totals"]) == set(totals)
    assert {"drive_mass_kg", "drive_cost", "energy_per_cycle_J", "cycle_time_s"} <= set(totals)


def test_the_analyses_page_gives_the_registrys_units():
    """The option and output tables of docs/study_analyses.md: every name a quantity, its unit the registry's (an
    empty cell: a pure number, ``-``)."""
    text = (DOCS / "study_analyses.md").read_text(encoding="utf-8")
    outputs = [r for table in tables(text, "output", "unit") for r in table]
    options = [r for table in tables(text, "option", "type", "unit") for r in table]
    assert len(outputs) == 11 and len(options) == 28
    for row in outputs:
        assert row["unit"] == unit(name_of(row["output"])), row["output"]
    for row in options:
        assert (row["unit"] or "-") == unit(name_of(row["option"])), row["option"]


def test_the_study_chart_labels_its_axes_by_the_registry(tmp_path):
    """A study's chart: an output's axis by :func:`axis_label`, a parameter's with its unit (the mechanism's
    geometric parameter: m)."""
    import pandas as pd

    from mechatron.studies.result import StudyResult
    from mechatron.studies.spec import read_study as read_spec

    spec = read_spec(ROOT / "examples" / "studies" / "crank_slider_sobol.toml")
    result = StudyResult(spec, pd.DataFrame({"design": [0], "status": ["ok"]}))
    assert result.axis_label("x_travel_m") == "x travel (m)"
    assert result.axis_label(spec.parameters[0].name) == f"{spec.parameters[0].name} (m)"


def test_a_parameter_that_targets_an_option_is_labelled_with_the_options_unit(tmp_path):
    import pandas as pd

    from mechatron.studies.result import StudyResult
    from mechatron.studies.spec import read_study as read_spec

    path = tmp_path / "arm.toml"
    path.write_text('mechanism = "planar_2r"\n[parameters.acceleration]\ntarget = "dynamics.amax"\n'
                    'values = [2.0, 5.0]\n[designs]\nmethod = "grid"\n'
                    '[analyses.dynamics]\nstart = [0.0, 0.0]\nend = [1.0, 0.0]\n')
    result = StudyResult(read_spec(path), pd.DataFrame({"design": [0], "status": ["ok"]}))
    assert result.axis_label("acceleration") == "acceleration (rad/s² or m/s²)"
    assert result.axis_label("q1_peak_Nm") == "q1 peak (N·m)"
    assert result.axis_label("design") == "design"

"""The study file's page (docs/study_file.md) and the shipped study examples (examples/studies/)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from mechatron.io.toml import read_toml
from mechatron.studies.designs import make_designs
from mechatron.studies.runner import evaluate
from mechatron.studies.spec import read_study as read_spec

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "study_file.md"
EXAMPLE = re.compile(r"<!-- study example: (?P<path>\S+) -->\n```toml\n(?P<body>.*?)```", re.S)


def test_page_embeds_every_example_verbatim():
    embedded = {m["path"]: m["body"] for m in EXAMPLE.finditer(PAGE.read_text(encoding="utf-8"))}
    shipped = {f"examples/studies/{p.name}" for p in (ROOT / "examples" / "studies").glob("*.toml")}
    assert set(embedded) == shipped
    for path, body in embedded.items():
        assert body == (ROOT / path).read_text(encoding="utf-8"), path
        assert read_toml(ROOT / path)


def test_puma_example_varies_the_arm_by_ten_percent():
    # a2 = d4 = 0.4318 m, a3 = 0.0203 m in robots/puma560.toml; ± 10 % ranges (its sizing analysis is run by the
    # tests of the analyses)
    data = read_toml(ROOT / "examples/studies/puma560_sizing.toml")
    assert data["mechanism"] == "puma560" and set(data["parameters"]) == {"a2", "a3", "d4"}
    assert all(p == {"relative": 0.10} for p in data["parameters"].values())
    assert {"sizing", "dynamics"} <= set(data["analyses"])


def test_puma_example_reads_and_sizes_its_first_designs():
    """The example's spec passes every analysis' check; its first two designs are sized and moved, each row equal
    to the sizing analysis run on the rebuilt arm directly (the analysis is tested against size_mechanism)."""
    import mechatron
    from mechatron.studies.analyses import sizing

    spec = read_spec(ROOT / "examples/studies/puma560_sizing.toml")
    designs = make_designs(spec)
    assert len(designs) == 200
    rows = evaluate(spec, designs.iloc[:2])
    assert (rows["status"] == "ok").all()
    for k in range(2):
        geometry = {name: float(designs.iloc[k][name]) for name in ("a2", "a3", "d4")}
        direct = sizing.outputs(mechatron.load("puma560").with_parameters(geometry), {}, 0)
        for name, value in direct.items():
            column = name if name in rows else f"sizing.{name}"
            assert rows.iloc[k][column] == value, name


def test_crank_slider_example_reads_and_its_first_block_runs():
    # 64 × (2 + 2) Saltelli designs; in the first block (A, A_B1, A_B2, B) the travel is 2·l1 on every row
    spec = read_spec(ROOT / "examples/studies/crank_slider_sobol.toml")
    designs = make_designs(spec)
    assert len(designs) == 256 and spec.sensitivity
    rows = evaluate(spec, designs.iloc[:4])
    assert rows["status"].tolist() == ["ok"] * 4
    assert rows["x_travel_m"].to_numpy() == pytest.approx(2 * rows["l1"].to_numpy(), abs=1e-9)


def test_front_shovel_example_reads_and_one_design_runs():
    spec = read_spec(ROOT / "examples/studies/front_shovel_linkage.toml")
    designs = make_designs(spec)
    assert len(designs) == 9
    # stick from 2.7 to 3.3 m (given in mm), boom 4.3 m ± 8 %
    assert sorted(set(designs["stick"].round(9))) == pytest.approx([2.7, 3.0, 3.3])
    assert sorted(set(designs["boom"].round(9))) == pytest.approx([4.3 * 0.92, 4.3, 4.3 * 1.08])
    row = evaluate(spec, designs.iloc[4:5]).iloc[0]
    assert row["status"] == "ok", row["reason"]
    assert {"reach_m", "height_m", "depth_m", "min_transmission_angle_deg", "L1_max_force_N",
            "L1_max_pressure_Pa"} <= set(row.index)
    # p = F / (2 π D² / 4) at the largest pushing force of the twin boom cylinders (or the annulus when pulling)
    assert row["L1_max_pressure_Pa"] <= row["L1_max_force_N"] / (2 * 3.14159265 * (0.18**2 - 0.125**2) / 4)

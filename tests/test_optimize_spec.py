"""The optimisation spec (docs/optimize_file.md) and ``mechatron optimize``: the page's complete examples are the
shipped files, the command writes what it is asked to, and bad specs fail with one line naming file and field.

The optimum of the bucket's turn error over (c, L2) is zero at the synthesis of c and L2 from the loop equations
[Bucket, 8] (``machines.bucket.synthesize``, a Newton solution of the eight equations for the two stroke ends,
checked in tests/test_bucket.py against an independent reconstruction): both solvers must find it."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from mechatron.machines.bucket import synthesize
from tests.corpus import assert_clean_error, run

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "optimize"
PAGE = ROOT / "docs" / "optimize_file.md"

BUCKET = """mechanism = "six_bar_bucket"
[objective]
type = "bucket_angle_error"
[variables]
c = [0.30, 0.55]
L2 = [0.40, 0.60]
[start]
c = 0.45
L2 = 0.52
[doe]
points = 16
"""


def test_page_examples_are_the_shipped_files():
    text = PAGE.read_text(encoding="utf-8")
    for name in ("bucket_synthesis.toml", "front_shovel_boom.toml"):
        block = re.search(rf"## Complete example: `examples/optimize/{name}`\n\n```toml\n(.*?)```", text, re.S)
        assert block is not None and block[1] == (EXAMPLES / name).read_text(encoding="utf-8")
    assert {p.name for p in EXAMPLES.glob("*.toml")} <= set(re.findall(r"examples/optimize/(\w+\.toml)", text))


def test_command_writes_json_csv_and_plot(tmp_path, capfd):
    spec = tmp_path / "bucket.toml"
    spec.write_text(BUCKET)
    outcome = run(["optimize", spec, "--json", "--csv", tmp_path / "o.csv", "--plot", tmp_path / "o.png"], capfd,
                  tmp_path)
    assert outcome.code == 0, outcome.err
    data = json.loads(outcome.out)
    synthesis = synthesize()
    assert data["variables"]["c"]["optimum"] == pytest.approx(synthesis.c, abs=1e-8)
    assert data["variables"]["L2"]["optimum"] == pytest.approx(synthesis.L2, abs=1e-8)
    assert data["objective"]["optimum"] <= 1e-12  # rad²: the turn requirement met exactly
    assert data["doe"]["points"] == 16 and data["doe"]["optimum_at_least_as_good"]
    assert (tmp_path / "o.csv").read_text().startswith("kind,name,optimum") and (tmp_path / "o.png").stat().st_size


def test_sqpmethod_finds_the_same_synthesis(tmp_path):
    from mechatron.optimal import optimize

    spec = tmp_path / "bucket.toml"
    spec.write_text(BUCKET + '[solver]\nmethod = "sqpmethod"\n')
    result = optimize(spec)
    assert result.solver["name"] == "sqpmethod" and result.success
    synthesis = synthesize()
    assert result.x == pytest.approx([synthesis.c, synthesis.L2], abs=1e-8)


@pytest.mark.parametrize("change, names", [
    (("c = [0.30, 0.55]", "l99 = [0.30, 0.55]"), ["s.toml", "variables.l99", "unknown parameter"]),
    (("c = [0.30, 0.55]", "L3 = [0.30, 0.55]"), ["s.toml", "variables.L3", "not a design variable"]),
    (("c = [0.30, 0.55]", "c = [0.55, 0.30]"), ["s.toml", "variables.c", "empty range"]),
    (("c = [0.30, 0.55]", "c = [0.30]"), ["s.toml", "variables.c", "2 numbers"]),
    (("c = 0.45", "c = 0.7"), ["s.toml", "start.c", "outside the bounds"]),
    (('"six_bar_bucket"', '"front_shovel"'), ["s.toml", "objective.type", "not a six-link bucket"]),
    (('"bucket_angle_error"', '"mass"'), ["s.toml", "objective.type", "unknown value"]),
    (('"six_bar_bucket"', '"no_such_machine"'), ["s.toml", "mechanism"]),
    (("points = 16", "pionts = 16"), ["s.toml", "doe.pionts", "unknown field"]),
    (("points = 16", 'method = "grid"'), ["s.toml", "doe.method"]),
    (("c = 0.45\nL2 = 0.52", "c = 0.35\nL2 = 0.45"), ["s.toml", "start", "cannot be evaluated"]),
])
def test_bad_specs_fail_with_one_line(tmp_path, capfd, change, names):
    (tmp_path / "s.toml").write_text(BUCKET.replace(*change))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, names)


def test_bad_shovel_requirement_names_its_field(tmp_path, capfd):
    text = (EXAMPLES / "front_shovel_boom.toml").read_text().replace("max_stroke_ratio = 1.7", "max_stroke_ratio = 0.9")
    (tmp_path / "s.toml").write_text(text)
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, ["s.toml", "requirements.max_stroke_ratio"])


def test_missing_spec_file(tmp_path, capfd):
    assert_clean_error(["optimize", "nope.toml"], capfd, tmp_path, ["nope.toml"])

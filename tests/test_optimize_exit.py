"""``mechatron optimize``'s exit status and the bounds of its DOE (issue 22, item 7).

The command exits 1 when a requirement is not met at the optimum, as ``size`` does without a feasible drive; its
``[doe] points`` are bounded (:data:`~mechatron.studies.optimize.MAX_DOE_POINTS`) and a power of two for Sobol
points, each refused in one line naming ``doe.points``; no library warning reaches stderr (it becomes a note of the
result).
"""

from __future__ import annotations

import json
import warnings

import pytest

from mechatron.optimal.problems import named as optimize_module
from tests.corpus import assert_clean_error, run

#: The six-link bucket asked for a transmission angle it cannot have: the optimum misses it.
UNMET = """mechanism = "six_bar_bucket"
[objective]
type = "bucket_angle_error"
[variables]
c = [0.30, 0.55]
L2 = [0.40, 0.60]
[requirements]
min_transmission_angle_deg = 80.0
positions = 3
[solver]
max_iterations = 30
[doe]
points = 8
"""

MET = UNMET.replace("min_transmission_angle_deg = 80.0", "min_transmission_angle_deg = 10.0")


def test_a_requirement_not_met_at_the_optimum_exits_1(tmp_path, capfd):
    (tmp_path / "s.toml").write_text(UNMET)
    outcome = run(["optimize", "s.toml", "--csv", "o.csv"], capfd, tmp_path)
    assert outcome.code == 1, outcome.err
    assert "NOT MET" in outcome.out and "NOT FEASIBLE: not met at the optimum: min_transmission_angle_deg" \
        in outcome.out
    assert outcome.err == "" and (tmp_path / "o.csv").is_file()  # the result is written all the same
    outcome = run(["optimize", "s.toml", "--json"], capfd, tmp_path)
    assert outcome.code == 1 and json.loads(outcome.out)["feasible"] is False


def test_every_requirement_met_exits_0(tmp_path, capfd):
    (tmp_path / "s.toml").write_text(MET)
    outcome = run(["optimize", "s.toml", "--json"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    assert json.loads(outcome.out)["feasible"] is True and outcome.err == ""


@pytest.mark.parametrize("points, method, names", [
    ("1e12", "sobol", ["1,000,000,000,000 DOE points", "at most 1,048,576"]),
    (str(2 ** 20 + 1), "lhs", ["1,048,577 DOE points", "at most 1,048,576"]),
    ("12", "sobol", ["must be a power of 2 for Sobol points", "got 12: use 8 or 16"]),
    ("1000", "sobol", ["got 1000: use 512 or 1024"]),
])
def test_doe_points_are_bounded_and_a_power_of_two_for_sobol(tmp_path, capfd, points, method, names):
    (tmp_path / "s.toml").write_text(MET.replace("points = 8", f'points = {points}\nmethod = "{method}"'))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, ["s.toml", "doe.points", *names])


def test_latin_hypercube_points_need_no_power_of_two(tmp_path, capfd):
    (tmp_path / "s.toml").write_text(MET.replace("points = 8", 'points = 12\nmethod = "lhs"'))
    outcome = run(["optimize", "s.toml"], capfd, tmp_path)
    assert outcome.code == 0 and outcome.err == "", outcome.err
    assert "DOE: 12 lhs points" in outcome.out


def test_a_library_warning_is_a_note_not_a_message_on_stderr(tmp_path, capfd, monkeypatch):
    solve = optimize_module._optimize

    def noisy(spec):
        warnings.warn("invalid value encountered in arccos", RuntimeWarning, stacklevel=1)
        warnings.warn("invalid value encountered in arccos", RuntimeWarning, stacklevel=1)
        return solve(spec)

    monkeypatch.setattr(optimize_module, "_optimize", noisy)
    (tmp_path / "s.toml").write_text(MET)
    outcome = run(["optimize", "s.toml"], capfd, tmp_path)
    assert outcome.code == 0 and outcome.err == "", outcome.err
    notes = [line for line in outcome.out.splitlines() if line.startswith("note: ")]
    assert notes == ["note: RuntimeWarning in tests/test_optimize_exit.py: invalid value encountered in arccos"]

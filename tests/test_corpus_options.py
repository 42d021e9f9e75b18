"""Issue 13, command-line option values and API arguments: every bad value of every option of every command ends in
one clean line naming the option (exit 2, nothing on stdout, no file touched), and the API functions the commands
call refuse the same bad arguments with an InputError naming the argument. Joint values outside their limits are
one warning line each, and only then.

The tables of options are built from the parsers themselves (``mechatron.cli.build_parser()``): an option added with
a ``Number`` type or an ``InputFile`` type is in the corpus without a change here.
"""

from __future__ import annotations

import argparse
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechatron
from mechatron.cli import build_parser
from mechatron.cli.values import InputFile, Number, Numbers
from mechatron.errors import InputError, LimitWarning
from mechatron.io.values import LARGEST
from tests.corpus import EDGE_NUMBERS, assert_clean_error, run

# ------------------------------------------------------------------------------------------------ the folder

TOLERANCES = "parameter,tolerance\na1,0.001\nq1,0.001\n"
POSES_OUTSIDE = "q1,q2\n0,0\n0.5,4\n"  # planar_2r: q2 limit ±2.96706 rad
TRAJECTORY_OUTSIDE = "t,q1,q2\n0,0,0\n0.5,0.2,1\n1,0.4,3.5\n1.5,0.5,3.5\n"
DESIGN = ('mechanism = "crank_slider"\n[variables]\nl1 = [0.08, 0.12]\n[objective]\nminimize = "reach_m"\n'
          '[analyses.linkage]\nsamples = 5\n')


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The working folder of every case: the input files the base commands read, and a sub-folder (a directory
    given where a file is wanted)."""
    path = tmp_path_factory.mktemp("options")
    (path / "tol.csv").write_text(TOLERANCES)
    (path / "poses_outside.csv").write_text(POSES_OUTSIDE)
    (path / "trajectory_outside.csv").write_text(TRAJECTORY_OUTSIDE)
    (path / "a_directory").mkdir()
    (path / "design.toml").write_text(DESIGN)
    return path


#: A valid invocation of every command with numeric or file options, so that the option under test is what fails.
BASE = {
    "linkage": ["linkage", "crank_slider"],
    "excavator": ["excavator"],
    "dynamics": ["dynamics", "planar_2r", "--move", "0,0;0.5,0.5"],
    "reduced": ["reduced", "crank_slider"],
    "size": ["size", "planar_2r", "--single-pass"],
    "tolerance": ["tolerance", "planar_2r", "--tolerances", "tol.csv", "--method", "worst"],
    "calibrate": ["calibrate", "planar_2r", "--parameters", "a1"],  # --measurements: the file option under test
    "fk": ["fk", "planar_2r", "--q", "0,0"],
    "jacobian": ["jacobian", "planar_2r", "--q", "0,0"],
    "show": ["show", "planar_2r"],
    "structure": ["structure", "planar_2r"],
    "export-urdf": ["export-urdf", "planar_2r", "-o", "x.urdf"],
    "study": ["study", "study.toml"],
    "optimize": ["optimize", "design.toml"],
}


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _typed_options(kind: type) -> list[tuple[str, str, object]]:
    """(command, option, type) of every option whose ``type`` is a ``kind``."""
    return [(command, max(action.option_strings, key=len), action.type)
            for command, sub in _subparsers().items() for action in sub._actions
            if action.option_strings and isinstance(action.type, kind)]


def _invalid(text: str, bounds: dict) -> bool:
    """Whether ``text`` breaks the bounds a ``Number`` type declares (the specification of the option, written
    out here independently of :func:`mechatron.io.values.number`)."""
    try:
        x = float(text)
    except ValueError:
        return True
    if not math.isfinite(x) or abs(x) > LARGEST:
        return True
    if bounds["positive"] and not x > 0:
        return True
    if bounds["minimum"] is not None and x < bounds["minimum"]:
        return True
    if bounds["maximum"] is not None and x > bounds["maximum"]:
        return True
    return bool(bounds.get("integer") and x != math.floor(x))


def _own_values(bounds: dict) -> list[str]:
    """Values just outside an option's own bounds: below its minimum, zero when it must be positive, above its
    maximum, a fraction when it must be whole."""
    out = ["-0", "0", "1e12", "1.0000001e12", "-1e12", "1e-300", "0x10", "1,2", "3 4"]
    if bounds["minimum"] is not None:
        out += [repr(bounds["minimum"] - 1), repr(bounds["minimum"] - 1e-9 * max(1.0, abs(bounds["minimum"])))]
    if bounds["maximum"] not in (None, LARGEST):
        out += [repr(bounds["maximum"] * 1.5), repr(bounds["maximum"] + 1)]
    if bounds.get("integer"):
        out += ["2.5", "1e0.5", "3.000001"]
    return out


NUMBER_OPTIONS = _typed_options(Number)


def _invalid_value(text: str, kind: Number) -> bool:
    """:func:`_invalid` of a value, or of any of a list's comma-separated values (a ``Numbers`` type)."""
    if isinstance(kind, Numbers):
        parts = [part for part in text.split(",") if part.strip()]
        return not parts or any(_invalid(part, kind.bounds) for part in parts)
    return _invalid(text, kind.bounds)


NUMBER_CASES = sorted({(command, option, value) for command, option, kind in NUMBER_OPTIONS
                       for value in (*EDGE_NUMBERS, *_own_values(kind.bounds)) if _invalid_value(value, kind)})


def test_the_tables_cover_every_numeric_option():
    """Every option that takes a number has a Number type (none is a bare ``type=int`` or ``float``), and every
    command with one has a base invocation here."""
    bare = [(command, action.option_strings) for command, sub in _subparsers().items() for action in sub._actions
            if action.type in (int, float)]
    assert bare == []
    assert {command for command, _, _ in NUMBER_OPTIONS} <= set(BASE)
    assert len(NUMBER_OPTIONS) >= 20 and len(NUMBER_CASES) >= 200


@pytest.mark.parametrize("command,option,value", NUMBER_CASES)
def test_bad_number_of_an_option(command, option, value, capfd, folder):
    """``--option=value``: one line naming the option and what it must be (``--option value``, as two words, is
    in the issue's cases below)."""
    base = BASE[command]
    outcome = assert_clean_error([*base[:2], f"{option}={value}", *base[2:]], capfd, folder, [option])
    assert "must be" in outcome.err


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], deadline=None, max_examples=40)
@given(case=st.sampled_from(NUMBER_OPTIONS),
       x=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**15, 10**15),
                   st.text(alphabet="0123456789.eE+-naif ,x", max_size=8)))
def test_any_value_of_a_numeric_option_parses_or_fails_cleanly(case, x, capfd, folder):
    """Any number or near-number given to a numeric option: parsed to a value within its bounds, or one clean
    line naming the option (parse only: the command's own work is not run)."""
    command, option, kind = case
    text = repr(x) if isinstance(x, float) else str(x)
    if _invalid_value(text, kind):
        positional = "design.toml" if command == "optimize" else "x"  # optimize checks its file as it parses
        outcome = assert_clean_error([command, positional, f"{option}={text}"], capfd, folder, [option])
        assert "must be" in outcome.err or "expected" in outcome.err
    else:
        values = np.atleast_1d(kind(text))
        given = np.array([float(part) for part in text.split(",") if part.strip()])
        assert np.all(np.isfinite(values)) and np.all(np.abs(values) <= LARGEST) and np.allclose(values, given)


# ------------------------------------------------------------------------------------------------ list options

LIST_CASES = [
    # (argv, the name the line must hold, and more)
    *[(["fk", "planar_2r", "--q", q], ["--q"]) for q in
      ("1", "1,2,3", "1,nan", "nan,0", "inf,0", "0,-inf", "a,b", "", ",", "1e308,0", "0,-1e308", "1;2", "0x1,2")],
    *[(["jacobian", "planar_2r", "--q", q], ["--q"]) for q in ("1", "1,nan", "1e13,0")],
    *[(["dynamics", "planar_2r", "--move", m], ["--move"]) for m in
      ("0,0", "0,0;1", "0,0;1,nan", "0,0;1,1e308", "0,0;1,inf", "x", "", ";", "0,0;1,2,3", "0,0;;", "0,0;a,b")],
    *[(["dynamics", "articulated_rrr", "--move", "0,0,0;1,1,1", option, value], [option]) for option in
      ("--vmax", "--amax", "--jmax") for value in ("1,2", "1,2,3,4", "1,nan,1", "1,0,1", "1,-1,1", "0", "1e308")],
    *[(["dynamics", "crank_slider", "--move", m], ["--move"]) for m in ("0,0;1,1", "0;nan", "0")],
    *[(["show", "planar_2r", "--set", s], ["--set"]) for s in
      ("a2", "a2=", "=1", "a2=nan", "a2=inf", "a2=-inf", "a2=1e308", "a2=x", "a2=1,d1=nan")],
    *[(["linkage", "crank_slider", "--plans", "plans.png", "--at", a], ["--at"]) for a in
      ("q1", "q1=nan", "q1=inf", "q1=1e308", "q1=x")],
    *[(["excavator", "--tooth-force", f], ["--tooth-force"]) for f in
      ("1", "1,2,3", "nan,0", "0,inf", "a,b", "1e308,0", "")],
]


@pytest.mark.parametrize("argv,names", LIST_CASES)
def test_bad_list_option(argv, names, capfd, folder):
    assert_clean_error(argv, capfd, folder, names)


def test_a_list_option_names_the_bad_value_and_its_place(capfd, folder):
    outcome = assert_clean_error(["dynamics", "articulated_rrr", "--move", "0,0,0;1,1,1", "--vmax", "1,2"], capfd,
                                 folder, ["--vmax", "1 value or 3", "got 2"])
    assert "q1, q2, q3" in outcome.err
    assert_clean_error(["fk", "planar_2r", "--q", "0,nan"], capfd, folder, ["--q value 2", "finite", "nan"])
    assert_clean_error(["show", "planar_2r", "--set", "a2=inf"], capfd, folder, ["--set a2", "finite", "inf"])


# ------------------------------------------------------------------------------------------------ file options

FILE_OPTIONS = _typed_options(InputFile)
FILE_EXTRA = {"dynamics": ["--trajectory"], "tolerance": []}


def _file_case(command: str, option: str, path: str) -> list[str]:
    base = [a for a in BASE[command] if command != "dynamics" or a not in ("--move", "0,0;0.5,0.5")]
    if option == "--tolerances":
        base = ["tolerance", "planar_2r"]
    return [*base[:2], option, path, *base[2:]]


def test_file_options_are_typed():
    options = {(command, option) for command, option, _ in FILE_OPTIONS}
    assert {("dynamics", "--trajectory"), ("size", "--task"), ("size", "--motors"), ("size", "--gearboxes"),
            ("size", "--linear"), ("size", "--cylinders"), ("tolerance", "--tolerances"), ("tolerance", "--poses"),
            ("excavator", "--design")} <= options


@pytest.mark.parametrize("command,option", [(c, o) for c, o, _ in FILE_OPTIONS])
@pytest.mark.parametrize("path,words", [("a_directory", "is a directory"), ("missing.csv", "no such file"),
                                        ("", "needs a file name"), ("a_directory/missing.toml", "no such file")])
def test_bad_file_option(command, option, path, words, capfd, folder):
    assert_clean_error(_file_case(command, option, path), capfd, folder, [option, words, path])


# ------------------------------------------------------------------------------------------------ the issue's cases

MOVE = ["--move", "0,0,0;1,1,1"]


@pytest.mark.parametrize("argv,names", [
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0;1,1,1,1,1,1", "--dt", "0"], ["--dt", "got 0"]),
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0;1,1,1,1,1,1", "--dt", "nan"], ["--dt", "got nan"]),
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0;1,1,1,1,1,1", "--dt", "-1"], ["--dt", "got -1"]),
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0;1,1,1,1,1,1", "--dt", "1e-308"], ["--dt", ">= 1e-06 s"]),
    (["excavator", "--samples", "0"], ["--samples", ">= 2"]),
    (["excavator", "--samples", "1", "--json"], ["--samples", ">= 2"]),
    (["excavator", "--samples", "2.5"], ["--samples", "whole number"]),
    (["reduced", "crank_slider", "--samples", "0"], ["--samples", ">= 2"]),
    (["linkage", "crank_slider", "--samples", "1"], ["--samples", ">= 2"]),
    (["tolerance", "planar_2r", "--tolerances", "tol.csv", "--seed", "-1"], ["--seed", ">= 0", "got -1"]),
    (["tolerance", "planar_2r", "--tolerances", "tol.csv", "--samples", "2.5"], ["--samples", "whole number"]),
    (["tolerance", "planar_2r", "--tolerances", "tol.csv", "--grid", "0"], ["--grid", ">= 1"]),
    (["dynamics", "articulated_rrr", *MOVE, "--vmax", "1,2"], ["--vmax"]),
    (["dynamics", "articulated_rrr", *MOVE, "--dwell", "-5"], ["--dwell", ">= 0 s", "got -5"]),
    (["dynamics", "articulated_rrr", *MOVE, "--dwell", "nan"], ["--dwell", "got nan"]),
    (["dynamics", "articulated_rrr", *MOVE, "--payload", "inf"], ["--payload", "kg", "got inf"]),
    (["dynamics", "articulated_rrr", *MOVE, "--payload", "1e308"], ["--payload", "<= 1e+12 kg"]),
    (["dynamics", "articulated_rrr", *MOVE, "--payload", "-1"], ["--payload", ">= 0 kg", "got -1"]),
    (["dynamics", "articulated_rrr", *MOVE, "--amax", "1e308", "--vmax", "1e308"], ["--amax", "<= 1e+12"]),
    (["dynamics", "articulated_rrr", *MOVE, "--vmax", "0"], ["--vmax", "> 0", "got 0"]),
    (["size", "planar_2r", "--pressure-mpa", "inf"], ["--pressure-mpa", "MPa", "got inf"]),
    (["size", "planar_2r", "--inertia-ratio", "0"], ["--inertia-ratio", "> 0", "got 0"]),
    (["size", "planar_2r", "--inertia-ratio", "nan"], ["--inertia-ratio", "got nan"]),
    (["size", "planar_2r", "--chain-efficiency", "0"], ["--chain-efficiency", "<= 1", "got 0"]),
    (["size", "planar_2r", "--chain-efficiency", "1.5"], ["--chain-efficiency", "<= 1", "got 1.5"]),
    (["size", "planar_2r", "--chain-efficiency", "nan"], ["--chain-efficiency", "got nan"]),
    (["size", "planar_2r", "--max-iterations", "1.5"], ["--max-iterations", "whole number", "got 1.5"]),
    (["size", "planar_2r", "--max-iterations", "1"], ["--max-iterations", ">= 2"]),
    (["dynamics", "planar_2r", "--trajectory", "a_directory"], ["--trajectory", "a_directory", "directory"]),
    (["size", "planar_2r", "--motors", "a_directory"], ["--motors", "a_directory", "directory"]),
    (["size", "planar_2r", "--task", "a_directory"], ["--task", "a_directory", "directory"]),
    (["dynamics", "articulated_rrr", "--move", "0,0,0;1,1,1", "--dt", "-inf"], ["--dt", "got -inf"]),
    (["dynamics", "planar_2r", "--move", "0,0;1,1", "--vmax", "1e-300"], ["samples", "dt", "vmax"]),
    (["dynamics", "planar_2r", "--move", "0,0;1,1", "--profile", "quintic", "--amax", "1e-12"], ["samples", "amax"]),
    (["dynamics", "planar_2r", "--move", "0,0;1,1", "--dwell", "1e12"], ["samples", "dwell"]),
    (["dynamics", "planar_2r", "--move", "0,0;1,1", "--dt", "1e-6", "--dwell", "1e3"], ["samples", "dt"]),
    (["size", "planar_2r", "--chain-efficiency", "1e-300"], ["--chain-efficiency", ">= 0.01"]),
    (["tolerance", "planar_2r", "--tolerances", "tol.csv", "--k", "1e-300"], ["--k", ">= 0.1"]),
])
def test_issue_cases(argv, names, capfd, folder):
    assert_clean_error(argv, capfd, folder, names)


def test_excavator_smallest_sample_count_gives_finite_json(capfd, folder):
    """``--samples 2``, the smallest count allowed, gives a whole report: valid JSON without NaN."""
    import json

    outcome = run(["excavator", "--samples", "2", "--json"], capfd, folder)
    assert outcome.code == 0, outcome.err
    json.loads(outcome.out, parse_constant=lambda name: pytest.fail(f"{name} in the JSON"))


# ------------------------------------------------------------------------------------------------ --deg

def test_deg_is_honoured_for_closed_loops(capfd, folder):
    """``dynamics crank_slider --move 0;90 --deg`` is the move to π/2 rad (before: 90 rad)."""
    import json

    degrees = run(["dynamics", "crank_slider", "--move", "0;90", "--deg", "--json"], capfd, folder)
    radians = run(["dynamics", "crank_slider", "--move", f"0;{math.pi / 2!r}", "--json"], capfd, folder)
    assert degrees.code == radians.code == 0, degrees.err + radians.err
    a, b = json.loads(degrees.out), json.loads(radians.out)
    assert a["duration"] == pytest.approx(b["duration"]) and a["samples"] == b["samples"]
    assert a["duration"] < 5  # 90 rad at 1 rad/s would take 90 s


def test_deg_converts_only_the_revolute_inputs(capfd, folder):
    """The front shovel's inputs are cylinder lengths: ``--deg`` leaves them as they are (m)."""
    import json

    lengths = "2.2,1.9,1.6;2.3,2.0,1.7"
    with_deg = run(["dynamics", "front_shovel", "--move", lengths, "--deg", "--json"], capfd, folder)
    without = run(["dynamics", "front_shovel", "--move", lengths, "--json"], capfd, folder)
    assert with_deg.code == without.code
    if with_deg.code == 0:
        assert json.loads(with_deg.out)["duration"] == pytest.approx(json.loads(without.out)["duration"])


# ------------------------------------------------------------------------------------------------ limit warnings

def _warnings(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("mechatron: warning:")]


def test_fk_outside_a_limit_warns_once_per_joint(capfd, folder):
    outcome = run(["fk", "planar_2r", "--q", "4,-4"], capfd, folder)
    lines = _warnings(outcome.err)
    assert outcome.code == 0 and len(lines) == 2 == len(outcome.err.splitlines())
    assert "q1 = 4 outside [-3.14159, 3.14159]" in lines[0] and "q2 = -4 outside" in lines[1]


@pytest.mark.parametrize("argv", [
    ["fk", "planar_2r", "--q", "2.9,-2.9"],
    ["dynamics", "planar_2r", "--move", "0,0;2.9,-2.9"],
    ["tolerance", "planar_2r", "--tolerances", "tol.csv", "--method", "worst"],
    ["size", "planar_2r", "--single-pass", "--json"],
])
def test_inside_the_limits_no_warning(argv, capfd, folder):
    outcome = run(argv, capfd, folder)
    assert outcome.code in (0, 1) and _warnings(outcome.err) == [] and "Warning" not in outcome.err, outcome.err


def test_dynamics_move_outside_a_limit_warns(capfd, folder):
    outcome = run(["dynamics", "planar_2r", "--move", "0,0;170,190", "--deg"], capfd, folder)
    lines = _warnings(outcome.err)
    assert outcome.code == 0 and len(lines) == 1 == len(outcome.err.splitlines()), outcome.err
    assert "q2 = 3.31613 outside [-2.96706, 2.96706]" in lines[0] and "at t = " in lines[0]


def test_dynamics_trajectory_outside_a_limit_warns(capfd, folder):
    outcome = run(["dynamics", "planar_2r", "--trajectory", "trajectory_outside.csv"], capfd, folder)
    lines = _warnings(outcome.err)
    assert outcome.code == 0 and len(lines) == 1, outcome.err
    assert "q2 = 3.5 outside [-2.96706, 2.96706] at t = 1 s (and 1 more of 4)" in lines[0]


def test_size_trajectory_outside_a_limit_warns(capfd, folder):
    outcome = run(["size", "planar_2r", "--task", "trajectory_outside.csv", "--single-pass", "--json"], capfd,
                  folder)
    lines = _warnings(outcome.err)
    assert outcome.code in (0, 1) and len(lines) == 1, outcome.err
    assert "q2 = 3.5 outside [-2.96706, 2.96706]" in lines[0]


def test_tolerance_pose_outside_a_limit_warns(capfd, folder):
    outcome = run(["tolerance", "planar_2r", "--tolerances", "tol.csv", "--poses", "poses_outside.csv",
                   "--method", "worst", "--json"], capfd, folder)
    lines = _warnings(outcome.err)
    assert outcome.code == 0 and len(lines) == 1, outcome.err
    assert "q2 = 4 outside [-2.96706, 2.96706] at pose 2" in lines[0]


def test_api_limit_warnings():
    mech = mechatron.load("planar_2r")
    with pytest.warns(LimitWarning, match=r"q2 = 3\.5 outside"):
        mechatron.size(mech, mechatron.move(mech, [0, 0], [0.5, 3.5]), single_pass=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert mech.limit_violations([0.1, 0.2]) == []
        mechatron.move(mech, [0, 0], [0.5, 1.0])


# ------------------------------------------------------------------------------------------------ the API


@pytest.fixture(scope="module")
def arm():
    return mechatron.load("planar_2r")


BAD = [math.nan, math.inf, -math.inf, 1e308, -1.0, 0.0]


@pytest.mark.parametrize("name,value", [(n, v) for n in ("dt",) for v in BAD]
                         + [("dwell", v) for v in (math.nan, math.inf, -1.0, 1e308)]
                         + [(n, v) for n in ("vmax", "amax", "jmax") for v in (*BAD, [1.0, 2.0, 3.0], [1, math.nan])])
def test_api_cycle_arguments(arm, name, value):
    from mechatron.dynamics.motion import cycle

    with pytest.raises(InputError, match=name):
        cycle(arm, [[0, 0], [0.5, 0.5]], profile="scurve", **{name: value})


@pytest.mark.parametrize("value", [[0, math.nan], [0, math.inf], [1e308, 0], ["a", 0]])
def test_api_move_ends(arm, value):
    with pytest.raises(InputError, match="end"):
        mechatron.move(arm, [0, 0], value)


@pytest.mark.parametrize("name,value", [
    *[("inertia_ratio_max", v) for v in BAD],
    *[("pressure", v) for v in BAD],
    *[("chain_efficiency", v) for v in (*BAD, 1.5)],
    *[("max_iterations", v) for v in (1, 2.5, 3.0, math.nan, -1, 10**6)],
])
def test_api_size_arguments(arm, name, value):
    with pytest.raises(InputError, match=name):
        mechatron.size(arm, **{name: value})


@pytest.mark.parametrize("name,value", [
    *[("k", v) for v in BAD], *[("samples", v) for v in (math.nan, 1, 2.5, -3, math.inf)],
    *[("seed", v) for v in (-1, 1.5, math.nan)], *[("limit", v) for v in BAD],
])
def test_api_study_arguments(arm, name, value):
    from mechatron.accuracy.sources import ErrorSource

    with pytest.raises(InputError, match=name):
        mechatron.tolerance_study(arm, [ErrorSource("a1", "parameter", "m", 1e-3)], None, methods=("worst", "mc"),
                                  **{name: value})


@pytest.mark.parametrize("value", [[[0, math.nan]], [[1e308, 0]], [[0, math.inf]]])
def test_api_study_poses(arm, value):
    from mechatron.accuracy.sources import ErrorSource

    with pytest.raises(InputError, match="poses"):
        mechatron.tolerance_study(arm, [ErrorSource("a1", "parameter", "m", 1e-3)], np.array(value),
                                  methods=("worst",))


@pytest.mark.parametrize("value", [0, -1, 2.5, math.nan, math.inf])
def test_api_counts(arm, value):
    from mechatron.accuracy.sources import workspace_grid
    from mechatron.dynamics.reduced import reduced_table
    from mechatron.kinematics.sweeps import sweep
    from mechatron.machines.excavator import excavator_report

    slider = mechatron.load("crank_slider")
    with pytest.raises(InputError, match="count"):
        workspace_grid(arm, value)
    for call in (lambda: reduced_table(slider, samples=value), lambda: sweep(slider, samples=value),
                 lambda: excavator_report(samples=value)):
        with pytest.raises(InputError, match="samples"):
            call()


@pytest.mark.parametrize("value", [math.nan, math.inf, 1e308, -1.0])
def test_api_payload(arm, value):
    from mechatron.model.payload import with_payload

    with pytest.raises(InputError, match="payload mass"):
        with_payload(arm, value)


def test_number_list_type_bounds():
    kind = Numbers(positive=True, unit="s")
    assert kind("1, 2,3") == (1.0, 2.0, 3.0)
    for text in ("", "1,nan", "0", "a", "1e13"):
        with pytest.raises(argparse.ArgumentTypeError):
            kind(text)


def test_step_bound_is_the_apis():
    from mechatron.cli.dynamics import _MIN_STEP
    from mechatron.dynamics.motion import MIN_STEP

    assert _MIN_STEP == MIN_STEP


@pytest.mark.parametrize("argv", [["fk", "puma560", "--q", "0,0,0,0,0,0", "--frame", ""],
                                  ["jacobian", "puma560", "--q", "0,0,0,0,0,0", "--frame", " "],
                                  ["tolerance", "planar_2r", "--tolerances", "tol.csv", "--frame", ""]])
def test_an_empty_frame_name_is_refused(argv, capfd, tmp_path):
    (tmp_path / "tol.csv").write_text("parameter,tolerance\na1,1e-4\n")
    assert_clean_error(argv, capfd, tmp_path, ["--frame", "needs a name"])

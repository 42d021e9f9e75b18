"""The options of a drive sizing as one value (:class:`mechatron.drives.options.SizingOptions`): each bad field
refused once, with one line naming it (API and command line); the value gives exactly the sizing the keywords give;
every default written once, in ``mechatron/drives/options.py``, and taken from there by every signature, the
command line and a study."""

from __future__ import annotations

import inspect
import math
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.cli import build_parser, main
from mechatron.drives import options as o
from mechatron.drives.checks import SCREW_LIFE, DriveLimits
from mechatron.drives.options import SizingOptions
from mechatron.drives.thermal import ZERO_CELSIUS
from mechatron.errors import InputError

ROOT = Path(__file__).resolve().parents[1]

BAD_NUMBERS = [math.nan, math.inf, -math.inf, -1.0, 0.0]


@pytest.fixture(scope="module")
def arm():
    return mechatron.load("planar_2r")


def _one_line_naming(exc: pytest.ExceptionInfo, name: str) -> None:
    text = str(exc.value)
    assert name in text and "\n" not in text, text


# ------------------------------------------------------------------------------------------------ bad fields, API
@pytest.mark.parametrize("name,value", [
    *[("inertia_ratio_max", v) for v in BAD_NUMBERS],
    *[("pressure", v) for v in (*BAD_NUMBERS, 2e10)],
    *[("chain_efficiency", v) for v in (*BAD_NUMBERS, 1.5, 0.005)],
    *[("max_iterations", v) for v in (2.5, 3.0, 1, -1, 1001, math.nan, math.inf)],
    ("objective", "speed"), ("objective", None),
    ("direct", "yes"), ("single_pass", 1),
    ("limits", {"stop_torque": 1.0}),
])
def test_a_bad_field_is_one_input_error_naming_it(arm, name, value):
    with pytest.raises(InputError) as made:
        SizingOptions(**{name: value})
    _one_line_naming(made, name)
    with pytest.raises(InputError) as keyword:  # the same check, once, through the keywords of size
        mechatron.size(arm, **{name: value})
    _one_line_naming(keyword, name)


@pytest.mark.parametrize("name,value", [("pressure", 20e6), ("objective", "cost"), ("max_iterations", 5),
                                        ("single_pass", True), ("limits", DriveLimits(stop_torque=1.0))])
def test_options_and_keywords_at_once_are_refused(arm, name, value):
    from mechatron.drives.system import size_mechanism
    from mechatron.dynamics.task import default_task

    with pytest.raises(InputError, match="not both") as given:
        mechatron.size(arm, options=SizingOptions(), **{name: value})
    _one_line_naming(given, name)
    task = default_task(arm)
    with pytest.raises(InputError, match="not both"):
        size_mechanism(arm, task.trajectory, options=SizingOptions(), **{name: value})


def test_options_must_be_a_sizing_options(arm):
    with pytest.raises(InputError, match="options must be a SizingOptions"):
        mechatron.size(arm, options={"objective": "cost"})


def test_the_value_is_frozen_and_keeps_python_numbers():
    options = SizingOptions(inertia_ratio_max=np.float64(5), max_iterations=np.int64(4), pressure="2e7")
    assert type(options.inertia_ratio_max) is float and options.inertia_ratio_max == 5.0
    assert type(options.max_iterations) is int and options.max_iterations == 4
    assert options.pressure == 2e7
    with pytest.raises(AttributeError):
        options.pressure = 1e6  # type: ignore[misc]


# ------------------------------------------------------------------------------------------------ bad fields, CLI
@pytest.mark.parametrize("argv,name", [
    (["--inertia-ratio", "nan"], "--inertia-ratio"),
    (["--inertia-ratio", "inf"], "--inertia-ratio"),
    (["--inertia-ratio", "-2"], "--inertia-ratio"),
    (["--pressure-mpa", "nan"], "--pressure-mpa"),
    (["--pressure-mpa", "-32"], "--pressure-mpa"),
    (["--pressure-mpa", "2e4"], "--pressure-mpa"),
    (["--chain-efficiency", "inf"], "--chain-efficiency"),
    (["--chain-efficiency", "-0.5"], "--chain-efficiency"),
    (["--max-iterations", "2.5"], "--max-iterations"),
    (["--max-iterations", "1"], "--max-iterations"),
    (["--objective", "speed"], "--objective"),
])
def test_the_command_line_refuses_a_bad_option_in_one_line(capsys, argv, name):
    try:
        code = main(["size", "planar_2r", *argv])
    except SystemExit as exc:  # argparse: refused as it is parsed
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and name in err and err.count("\n") == 1, err


# ------------------------------------------------------------------------------------------------ the same sizing
def _same(a, b) -> None:
    """Two values equal to the last bit: floats by their bits (NaN equal to NaN), containers entry by entry."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b)
        for key in a:
            _same(a[key], b[key])
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b)
        for x, y in zip(a, b):
            _same(x, y)
    elif isinstance(a, float):
        assert isinstance(b, float) and np.float64(a).tobytes() == np.float64(b).tobytes(), (a, b)
    else:
        assert a == b, (a, b)


def _same_sizing(a, b) -> None:
    assert [j.choice() for j in a.joints] == [j.choice() for j in b.joints]
    assert a.converged == b.converged and len(a.iterations) == len(b.iterations)
    _same(a.as_dict(), b.as_dict())


def test_the_options_give_the_puma_sizing_of_the_keywords():
    """The PUMA 560 with its own task and the example catalogs: not the defaults, so each field is used."""
    puma = mechatron.load("puma560")
    fields = dict(objective="cost", inertia_ratio_max=8.0, chain_efficiency=0.95, max_iterations=6,
                  limits=DriveLimits(stop_torque=20.0, ambient=ZERO_CELSIUS + 30.0))
    by_keywords = mechatron.size(puma, **fields)
    by_options = mechatron.size(puma, options=SizingOptions(**fields))
    assert by_options.objective == "cost" and by_options.joints[0].ambient == ZERO_CELSIUS + 30.0
    _same_sizing(by_keywords, by_options)


def test_the_options_give_the_cylinder_sizing_of_the_keywords():
    """A closed-loop mechanism with a hydraulic cylinder, at 25 MPa instead of 32: the pressure reaches it."""
    bucket = mechatron.load("six_bar_bucket")
    by_keywords = mechatron.size(bucket, pressure=25e6, objective="cost")
    by_options = mechatron.size(bucket, options=SizingOptions(pressure=25e6, objective="cost"))
    assert {j.pressure for j in by_options.joints if hasattr(j, "pressure")} == {25e6}
    _same_sizing(by_keywords, by_options)


def test_the_command_line_and_a_study_build_the_options_of_the_api():
    """``mechatron size`` and ``[analyses.sizing]``: their units (MPa, h, °C) to SI, the same value."""
    from mechatron.cli.size import sizing_options
    from mechatron.studies.analyses.sizing import sizing_options as study_options

    args = build_parser("size").parse_args(
        ["size", "planar_2r", "--objective", "margin", "--inertia-ratio", "4", "--pressure-mpa", "25",
         "--chain-efficiency", "0.9", "--no-direct", "--single-pass", "--max-iterations", "3", "--stop-current", "2",
         "--voltage", "48", "--screw-life-h", "1000", "--ambient", "25"])
    expected = SizingOptions(objective="margin", inertia_ratio_max=4.0, pressure=25e6, chain_efficiency=0.9,
                             direct=False, single_pass=True, max_iterations=3,
                             limits=DriveLimits(None, 2.0, 1000 * 3600.0, 48.0, 298.15))
    assert sizing_options(args) == expected
    assert study_options({"objective": "margin", "inertia_ratio": 4, "pressure_MPa": 25, "chain_efficiency": 0.9,
                          "direct": False, "single_pass": True, "max_iterations": 3, "stop_current": 2,
                          "voltage": 48, "screw_life_h": 1000, "ambient": 25}) == expected
    assert sizing_options(build_parser("size").parse_args(["size", "planar_2r"])) == SizingOptions()
    assert study_options({}) == SizingOptions()


# ------------------------------------------------------------------------------------------------ the defaults
def test_the_defaults_are_those_written_in_options():
    """The project's defaults (docs/cli.md, docs/study_analyses.md): mass, an inertia ratio of 10, 32 MPa, no
    loss in the rest of the chain, 10 passes of 2 … 1000, efficiency ≥ 0.01, pressure ≤ 10 000 MPa."""
    assert (o.OBJECTIVE, o.INERTIA_RATIO_MAX, o.PRESSURE, o.CHAIN_EFFICIENCY) == ("mass", 10.0, 32e6, 1.0)
    assert (o.MAX_ITERATIONS, o.MIN_PASSES, o.MAX_PASSES, o.MIN_EFFICIENCY, o.PRESSURE_MAX) == (10, 2, 1000, 0.01, 1e10)
    assert o.OBJECTIVES == ("mass", "cost", "margin", "time")
    made = SizingOptions()
    assert (made.objective, made.inertia_ratio_max, made.pressure, made.chain_efficiency, made.max_iterations,
            made.direct, made.single_pass) == ("mass", 10.0, 32e6, 1.0, 10, True, False)
    assert made.limits == DriveLimits() and made.limits.screw_life == SCREW_LIFE


def _defaults(function) -> dict:
    return {n: p.default for n, p in inspect.signature(function).parameters.items()
            if p.default is not inspect.Parameter.empty}


def test_every_signature_takes_its_defaults_from_options():
    from mechatron.drives.checks import Evaluation, PairChecks, evaluate
    from mechatron.drives.cylinders import CylinderSizing, size_cylinder
    from mechatron.drives.joint import Alternatives, size_joint
    from mechatron.drives.search import motor_passes
    from mechatron.drives.sizing import size
    from mechatron.drives.system import size_mechanism

    expected = {"objective": o.OBJECTIVE, "inertia_ratio_max": o.INERTIA_RATIO_MAX, "pressure": o.PRESSURE,
                "chain_efficiency": o.CHAIN_EFFICIENCY, "max_iterations": o.MAX_ITERATIONS, "direct": True,
                "single_pass": False}
    for function in (size, size_mechanism):
        defaults = _defaults(function)
        assert {k: defaults[k] for k in expected} == expected, function
        assert defaults["options"] is None and defaults["limits"] is None
    for function in (size_joint, Alternatives, PairChecks, Evaluation, evaluate, motor_passes):
        defaults = _defaults(function)
        assert defaults.get("inertia_ratio_max", o.INERTIA_RATIO_MAX) == o.INERTIA_RATIO_MAX, function
    assert _defaults(size_cylinder)["pressure"] == o.PRESSURE and _defaults(CylinderSizing)["pressure"] == o.PRESSURE


def test_the_command_line_and_a_study_take_their_defaults_from_options():
    from mechatron.studies.analyses.sizing import NUMBERS

    args = build_parser("size").parse_args(["size", "planar_2r"])
    assert (args.objective, args.inertia_ratio, args.pressure_mpa * 1e6, args.chain_efficiency,
            args.max_iterations) == (o.OBJECTIVE, o.INERTIA_RATIO_MAX, o.PRESSURE, o.CHAIN_EFFICIENCY,
                                     o.MAX_ITERATIONS)
    assert NUMBERS["inertia_ratio"][0] == o.INERTIA_RATIO_MAX and NUMBERS["pressure_MPa"][0] * 1e6 == o.PRESSURE
    assert NUMBERS["chain_efficiency"] == (o.CHAIN_EFFICIENCY, dict(minimum=o.MIN_EFFICIENCY, maximum=1.0))
    assert NUMBERS["max_iterations"] == (o.MAX_ITERATIONS, dict(integer=True, minimum=o.MIN_PASSES,
                                                                maximum=o.MAX_PASSES))
    cli = (ROOT / "docs" / "cli.md").read_text()
    assert f"(default {o.INERTIA_RATIO_MAX:g})" in cli and f"(default {o.PRESSURE / 1e6:g} MPa)" in cli

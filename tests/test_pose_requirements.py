r"""Requirements at named poses and sweeps of one input with the others held (issue 32, item 4), against hand
closed forms.

- The central crank-slider (examples/design/my_crank.toml): the slider at the crank angle θ0 is at
  x_C(θ0) = l1 cos θ0 + √(l2² − l1² sin² θ0) [Egorov, fig. 4.18]. Minimising the reach l1 + l2 with the travel
  2 l1 ≥ 0.2 m and x_C(θ0) ≥ X: d(l1 + l2)/dl1 along x_C = X is (l1 s² − c (X − l1 c))/l2 > 0 for θ0 = 2 rad
  (c = cos θ0 < 0), so l1 = 0.1 m (the travel binding) and l2 = √((X − l1 c)² + (l1 s)²) (the pose binding).
  Its exact gradient: ∂x_C/∂l1 = c − l1 s²/√(l2² − l1² s²), ∂x_C/∂l2 = l2/√(l2² − l1² s²).
- The crank pin B highest (θ = 90°, on the sweep of 73 samples from 60°): the slider at √(l2² − l1²), on the axis.
- The seven-bar [ShiLiang] (robots/seven_bar.toml): the cylinder s1 = BF from the ground pin F turns the body ABC
  about the ground pin A alone, so with s1 held and s2 swept C stays where the triangle ABF puts it: the angle of AB
  is that of AF plus β, cos β = (|AB|² + |AF|² − s1²)/(2 |AB| |AF|) (law of cosines), C turned with it about A.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.optimal.reader import read_problem as read_design
from mechatron.optimal.solve import optimize_design
from mechatron.studies.analyses import analysis

ROOT = Path(__file__).resolve().parent.parent
THETA0, X = 2.0, 0.38

DESIGN = f"""name = "crank pose"
mechanism = "my_crank.toml"

[variables]
l1 = [0.08, 0.12]
l2 = [0.35, 0.45]

[objective]
minimize = "reach_m"

[requirements]
x_travel_m = {{ min = 0.2 }}
slider = {{ output = "reach_m", at = "crank up", min = {X} }}

[[poses]]
name = "crank up"
inputs = {{ q1 = {THETA0} }}

[analyses.linkage]
samples = 13
"""


def x_slider(l1: float, l2: float, q: float) -> float:
    return l1 * math.cos(q) + math.sqrt(l2**2 - (l1 * math.sin(q)) ** 2)


@pytest.fixture
def design(tmp_path):
    shutil.copy(ROOT / "examples" / "design" / "my_crank.toml", tmp_path / "my_crank.toml")
    path = tmp_path / "design.toml"
    path.write_text(DESIGN)
    return path


def test_a_requirement_at_a_named_pose_binds_at_the_hand_optimum(design):
    result = optimize_design(design)
    assert result.solver["method"].startswith("ipopt") and result.feasible
    l1 = 0.1
    l2 = math.hypot(X - l1 * math.cos(THETA0), l1 * math.sin(THETA0))
    assert result.best["l1"] == pytest.approx(l1, abs=1e-6)
    assert result.best["l2"] == pytest.approx(l2, abs=1e-6)
    assert result.best["crank up.reach_m"] == pytest.approx(X, abs=1e-6)
    (pose,) = [r for r in result.requirements if r.name == "crank up.reach_m"]
    assert pose.unit == "m" and abs(pose.margin) < 1e-6
    assert "crank up.reach_m" in str(result)


def test_the_exact_gradient_at_a_pose_is_the_hand_derivative(design):
    from mechatron.optimal.exact import ExactModel

    l1, l2 = 0.093, 0.41
    values, gradients = ExactModel(read_design(design))(np.array([l1, l2]))
    s, c = math.sin(THETA0), math.cos(THETA0)
    root = math.sqrt(l2**2 - (l1 * s) ** 2)
    assert values["crank up.reach_m"] == pytest.approx(x_slider(l1, l2, THETA0), abs=1e-10)
    np.testing.assert_allclose(gradients["crank up.reach_m"], [c - l1 * s**2 / root, l2 / root], atol=1e-9)
    assert "crank up.x_travel_m" not in values  # one position: no travels


def test_a_pose_at_the_highest_of_another_output():
    crank = mechatron.load("crank_slider")
    options = {"point": "B", "poses": [{"name": "pin up", "highest": "height_m", "point": "C"}]}
    out = analysis("linkage").outputs(crank, options, seed=0)
    l1, l2 = 0.1, 0.4
    assert out["pin up.reach_m"] == pytest.approx(math.sqrt(l2**2 - l1**2), abs=1e-10)
    assert out["pin up.height_m"] == pytest.approx(0.0, abs=1e-10)
    assert out["height_m"] == pytest.approx(l1, abs=1e-10)  # B's highest over the sweep


def _c_held(mech, s1: float) -> np.ndarray:
    """C by the law of cosines in the triangle ABF (the module docstring), from the drawn points."""
    from mechatron.kinematics.frames import frame_placement

    q = mech.reference_q
    A, B, C, F = (frame_placement(mech, q, n).translation[:2] for n in "ABCF")
    ab, af = np.linalg.norm(B - A), np.linalg.norm(F - A)
    beta = math.acos((ab**2 + af**2 - s1**2) / (2 * ab * af))
    turn = math.atan2(*(F - A)[::-1]) + beta - math.atan2(*(B - A)[::-1])
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return A + rotation @ (C - A)


def test_one_input_swept_with_the_other_held():
    bar = mechatron.load("seven_bar")
    linkage = analysis("linkage")
    expected = _c_held(bar, 0.6)
    held = linkage.outputs(bar, {"point": "C", "hold": {"s1": 0.6}, "samples": 9}, seed=0)
    assert held["reach_m"] == pytest.approx(expected[0], abs=1e-9)
    assert held["height_m"] == pytest.approx(expected[1], abs=1e-9)
    assert held["x_travel_m"] < 1e-9 and held["y_travel_m"] < 1e-9
    # the same as a named pose of the full sweep, and the tip H moving while C stays
    options = {"samples": 9, "poses": [{"name": "s1 held", "inputs": {"s1": 0.6}, "point": "C"},
                                       {"name": "tip", "inputs": {"s1": 0.6}}]}
    out = linkage.outputs(bar, options, seed=0)
    assert out["s1 held.reach_m"] == pytest.approx(expected[0], abs=1e-9)
    assert out["s1 held.y_travel_m"] < 1e-9 and out["tip.y_travel_m"] > 1e-3


@pytest.mark.parametrize("pose, field, words", [
    ('name = "p"\ninputs = { q9 = 1.0 }', "poses[1].inputs.q9", "not an input"),
    ('name = "p"\npoint = "Z"', "poses[1].point", "no point 'Z'"),
    ('name = "p"\nlowest = "x_travel_m"', "poses[1].lowest", "no value at one position"),
    ('name = "a.b"', "poses[1].name", "without dots"),
])
def test_a_wrong_pose_is_one_line_naming_the_file_and_field(design, pose, field, words):
    design.write_text(DESIGN.replace('name = "crank up"\ninputs = { q1 = 2.0 }', pose)
                      .replace('slider = { output = "reach_m", at = "crank up", min = 0.38 }\n', ""))
    with pytest.raises(InputError) as caught:
        read_design(design)
    message = str(caught.value)
    assert str(design) in message and f"'{field}'" in message and words in message and "\n" not in message


def test_a_requirement_at_an_unknown_pose_is_refused(design):
    design.write_text(DESIGN.replace('at = "crank up"', 'at = "crank down"'))
    with pytest.raises(InputError, match=r"requirements.slider.at.*no pose 'crank down'; the poses: crank up"):
        read_design(design)


def test_the_cli_refuses_a_wrong_pose_with_exit_2(design):
    import subprocess
    import sys

    design.write_text(DESIGN.replace("q1 = 2.0", "q1 = 'x'"))
    run = subprocess.run([sys.executable, "-m", "mechatron", "optimize", str(design)], capture_output=True, text=True)
    assert run.returncode == 2 and "Traceback" not in run.stderr and "poses[1].inputs.q1" in run.stderr


def test_the_docs_pages_poses_run_on_the_seven_bar():
    """The block of docs/study_analyses.md with named poses: C at the held s1 by the law of cosines; the lowest H
    with s1 held long is the held sweep's lowest (its −depth)."""
    import tomllib

    text = (ROOT / "docs" / "study_analyses.md").read_text(encoding="utf-8")
    (block,) = [b.split("```", 1)[0] for b in text.split("```toml\n")[1:] if "[[analyses.linkage.poses]]" in b]
    options = tomllib.loads(block)["analyses"]["linkage"]
    bar = mechatron.load("seven_bar")
    linkage = analysis("linkage")
    linkage.check(bar, options)
    out = linkage.outputs(bar, options, seed=0)
    expected = _c_held(bar, 0.56)
    assert out["s1 short.reach_m"] == pytest.approx(expected[0], abs=1e-9)
    assert out["s1 short.height_m"] == pytest.approx(expected[1], abs=1e-9)
    held = linkage.outputs(bar, {"samples": 21, "hold": {"s1": 0.72}}, seed=0)
    assert out["s1 long, H lowest.height_m"] == pytest.approx(-held["depth_m"], abs=1e-12)
    assert "s1 long, H lowest.x_travel_m" not in out

"""A design written by ``mechatron optimize -o`` is drawn at the pose the search evaluated, and every body's x axis
turns with its body there: a revolute joint given by its world ``angle`` (or whose axis no point of its own body
sets) is written at the angle its body has in that pose, a prismatic guide's ``direction`` turned with its parent,
so that the file reads back with the evaluated joint coordinates, the evaluated points and the same outputs.

The mechanism (tests/data/redraw/turned.toml, described in its header) is a rocker O-B-T on the ground at O lifted
by the cylinder A-B, |OB| = |AB| = r = 0.5 m. The design moves A to (a, 0) with the cylinder held at its drawn
0.5 m, so B = (a/2, r sin α) with cos α = a / (2r): the rocker turns from its drawn line angle β = atan2(0.8, 0.6)
to α, by α − β. Its x axis was drawn at θ₀ = β + 0.3, so at the pose φ = θ₀ + (α − β) = α + 0.3. The block slides
along OT to the line y = 0.3: S = (0.3 / tan α, 0.3), its travel s = |OS| = 0.3 / sin α. The flag's gear gives
ψ = 2φ + 0.7 − 3θ₀, its world angle φ + ψ, so F = S + R(φ + ψ − 0.7)(F₀ − S₀) (R: the rotation; the flag was
drawn at 0.7 rad). The vane's gear gives ν = θ₀ − φ.
"""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pinocchio as pin
import pytest

DATA = Path(__file__).parent / "data" / "redraw"
A, R = 0.85, 0.5
BETA = math.atan2(0.8, 0.6)
THETA0 = BETA + 0.3
S0 = np.array([0.225, 0.3])
F0 = S0 + 0.2 * np.array([math.cos(0.2), math.sin(0.2)])

DESIGN = """
name = "{name} travel"
mechanism = "{mechanism}"
[variables]
A_x = [0.3, 0.85]
[objective]
minimize = "x_travel_m"
[analyses.linkage]
samples = 9
[solver]
method = "ipopt"
population = 6
"""


def _expected():
    """The closed forms of the module docstring at a = 0.85 m: the points (m) and the coordinates (rad, m)."""
    alpha = math.acos(A / (2 * R))
    b = np.array([A / 2, R * math.sin(alpha)])
    phi = alpha + 0.3
    psi = 2 * phi + 0.7 - 3 * THETA0
    turn = phi + psi - 0.7
    s = np.array([0.3 / math.tan(alpha), 0.3])
    f = s + np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]]) @ (F0 - S0)
    points = {"A": np.array([A, 0.0]), "B": b, "T": 2 * b, "S": s, "F": f}
    return points, {"phi": phi, "s": 0.3 / math.sin(alpha), "psi": psi, "nu": THETA0 - phi, "cyl": 0.5}, alpha


def _pose(mech):
    """The coordinates and the points' world positions of ``mech`` at its reference configuration."""
    q = np.asarray(mech.reference_q, dtype=float)
    data = mech.model.createData()
    pin.framesForwardKinematics(mech.model, data, q)
    coordinates = {name: float(q[mech.model.joints[mech.joint_id(name)].idx_q]) for name in mech.joint_names}
    points = {f.name: data.oMf[k].translation[:2].copy() for k, f in enumerate(mech.model.frames)}
    return coordinates, points


def _outputs(spec, mechanism, values):
    """The study analyses' outputs of ``mechanism`` with the variables at ``values`` (none: the file as it is)."""
    from mechatron.studies.runner import evaluate

    study = replace(spec.evaluator, mechanism=str(mechanism), parameters=spec.evaluator.parameters if values else ())
    (row,) = evaluate(study, pd.DataFrame({"design": [0], "seed": [0], **{k: [v] for k, v in values.items()}})
                      ).to_dict(orient="records")
    assert row["status"] == "ok", row["reason"]
    return row


def test_world_angles_and_a_guide_turn_with_their_bodies_and_the_design_reads_back_to_the_evaluated_pose(tmp_path):
    import mechatron
    from mechatron.model.linkage_file import read_linkage_file
    from mechatron.optimal.reader import read_problem
    from mechatron.optimal.write import write_designs

    (tmp_path / "turned.toml").write_text((DATA / "turned.toml").read_text())
    (tmp_path / "design.toml").write_text(DESIGN.format(name="turned", mechanism="turned.toml"))
    spec = read_problem(tmp_path / "design.toml")
    (path,) = write_designs(spec, pd.DataFrame({"A_x": [A]}), tmp_path / "out")
    points, coordinates, alpha = _expected()

    written = read_linkage_file(path)
    joints = {j.body: j for j in written.joints if j.kind != "cylinder"}
    assert joints["rocker"].angle == pytest.approx(alpha + 0.3, abs=1e-9)  # θ₀ turned by α − β
    assert joints["flag"].angle == pytest.approx(coordinates["phi"] + coordinates["psi"], abs=1e-9)
    assert joints["vane"].angle == pytest.approx(THETA0, abs=1e-9) and joints["vane"].toward is None  # φ + ν
    np.testing.assert_allclose(joints["block"].direction, [math.cos(alpha), math.sin(alpha)], atol=1e-9)
    for name, xy in points.items():  # drawn at the evaluated pose
        np.testing.assert_allclose(written.drawing()[name], xy, atol=1e-9, err_msg=name)

    back = mechatron.load(path)
    assert back.notes == []  # drawn closed: no point moved when it is read back
    q, at = _pose(back)
    for name, value in coordinates.items():
        assert q[name] == pytest.approx(value, abs=1e-9), name
    for name, xy in points.items():
        np.testing.assert_allclose(at[name], xy, atol=1e-9, err_msg=name)

    evaluated = _outputs(spec, spec.mechanism, {"A_x": A})
    again = _outputs(spec, path, {})
    outputs = [k for k in evaluated if k.endswith(("_m", "_N"))]
    assert "x_travel_m" in outputs and "cyl_max_force_N" in outputs
    for name in outputs:
        assert again[name] == pytest.approx(evaluated[name], rel=1e-9, abs=1e-12), name


ROCKER = """
name = "rocker"
tool = "T"
actuated = ["cyl"]

[points]
O = [0.0, 0.0]
A = [0.6, 0.0]
B = [0.3, 0.4]
T = [0.6, 0.8]

[[bodies]]
name = "ground"
points = ["O", "A"]

[[bodies]]
name = "rocker"
points = ["O", "B", "T"]
mass = 20.0
com = "B"
inertia = 1.5

[[joints]]
type = "revolute"
body = "rocker"
at = "O"
coordinate = "phi"
angle = {angle!r}
lower = 6.0
upper = 7.5

[[joints]]
type = "cylinder"
name = "cyl"
base = "A"
eye = "B"
stroke_mm = [400, 650]
"""


def test_the_command_line_writes_a_world_angle_a_whole_turn_up_at_the_evaluated_angle_within_its_limits(tmp_path):
    # the rocker's x axis drawn along OT a whole turn up, θ₀ = β + 2π, limited to [6.0, 7.5] rad: at the optimum
    # a = 0.85 (the x travel 0.2625 / a is least at the largest a) φ = α + 2π = 6.838 rad, where a wrapped angle
    # (α = 0.555 rad) would be outside the limits
    import mechatron
    from mechatron.cli import main

    (tmp_path / "rocker.toml").write_text(ROCKER.format(angle=BETA + 2 * math.pi))
    design = tmp_path / "design.toml"
    design.write_text(DESIGN.format(name="rocker", mechanism="rocker.toml"))
    out = tmp_path / "best"
    assert main(["optimize", str(design), "-o", str(out)]) == 0
    best = pd.read_csv(out / "designs.csv").sort_values("x_travel_m").iloc[0]
    assert best["A_x"] == pytest.approx(A, abs=1e-9)
    alpha = math.acos(A / (2 * R))
    back = mechatron.load(out / "design-000.toml")
    assert back.notes == []
    q, at = _pose(back)
    assert q["phi"] == pytest.approx(alpha + 2 * math.pi, abs=1e-9) and q["cyl"] == pytest.approx(0.5, abs=1e-9)
    b = np.array([A / 2, R * math.sin(alpha)])
    np.testing.assert_allclose(at["B"], b, atol=1e-9)
    np.testing.assert_allclose(at["T"], 2 * b, atol=1e-9)

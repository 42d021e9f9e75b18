"""The positioning-error objective of ``mechatron optimize`` (:mod:`mechatron.studies.optimal_accuracy`).

References: the planar 2R arm's sensitivities and its constrained optimum derived by hand below; the accuracy
module's worst case (Pinocchio's Jacobians, :func:`mechatron.accuracy.study.run_study`); central finite differences
of that Pinocchio evaluation.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.accuracy.sources import read_poses, read_tolerances
from mechatron.optimal.problems.accuracy import PositioningProblem
from tests.corpus import assert_clean_error, run
from tests.protocol import check_result

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "examples" / "data"
ARCMIN = math.radians(1 / 60)


def _planar(tmp_path: Path, tolerances: str, poses: str) -> tuple:
    (tmp_path / "tol.csv").write_text(tolerances)
    (tmp_path / "poses.csv").write_text(poses)
    mech = mechatron.load("planar_2r")
    P, labels = read_poses(tmp_path / "poses.csv", mech)
    return mech, read_tolerances(tmp_path / "tol.csv", mech), P, labels


def test_planar_2r_worst_case_equals_the_hand_sensitivities(tmp_path):
    # r = (a1 c1 + a2 c12, a1 s1 + a2 s12): ∂r/∂a1 = (c1, s1), ∂r/∂a2 = (c12, s12), ∂r/∂q1 = (−y, x),
    # ∂r/∂q2 = a2 (−s12, c12); worst per axis |J b| + Σ|J_i| t_i, |Δr| its norm [Egorov, 8.4–8.6]
    mech, sources, P, labels = _planar(
        tmp_path, "parameter,tolerance_mm,tolerance_arcmin,bias_arcmin\na1,0.05,,\na2,0.02,,\nq1,,2,1\nq2,,3,\n",
        "label,q1_deg,q2_deg\nA,30,50\nB,-70,120\n")
    problem = PositioningProblem(mech, {"a1": (0.3, 0.8), "a2": (0.2, 0.6)}, sources=sources, poses=P, labels=labels)
    for a1, a2 in ((0.5, 0.4), (0.72, 0.25)):
        expected = []
        for q1, q2 in P:
            c1, s1, c12, s12 = math.cos(q1), math.sin(q1), math.cos(q1 + q2), math.sin(q1 + q2)
            x, y = a1 * c1 + a2 * c12, a1 * s1 + a2 * s12
            J = np.array([[c1, c12, -y, -a2 * s12], [s1, s12, x, a2 * c12]])
            t = np.array([0.05e-3, 0.02e-3, 2 * ARCMIN, 3 * ARCMIN])
            b = np.array([0, 0, ARCMIN, 0])
            expected.append(np.linalg.norm(np.abs(J @ b) + np.abs(J) @ t))
        assert problem.values(np.array([a1, a2])) == pytest.approx(expected, rel=1e-12)
        assert problem.evaluate(np.array([a1, a2])) == pytest.approx(expected, rel=1e-12)


def test_planar_2r_optimum_is_the_lagrange_solution(tmp_path):
    # one pose q = (0, 90°), joint errors ±t only: r = (a1, a2), W = (2 a2 t, a1 t), D = t √(4 a2² + a1²);
    # min D subject to the reach a1 + a2 ≥ R (q = 0): 8 a2 = λ = 2 a1 ⇒ a1 = 4R/5, a2 = R/5, D = 2 t R/√5
    from mechatron.optimal import optimize

    (tmp_path / "tol.csv").write_text("parameter,tolerance_arcmin\nq1,1\nq2,1\n")
    (tmp_path / "poses.csv").write_text("label,q1_deg,q2_deg\nbent,0,90\n")
    (tmp_path / "s.toml").write_text(SPEC_2R)
    result = optimize(tmp_path / "s.toml")
    assert result.success and result.feasible and result.beats_doe
    assert result.x == pytest.approx([0.8, 0.2], abs=1e-7)
    assert result.objective == pytest.approx(2 * ARCMIN * 1.0 / math.sqrt(5), rel=1e-9)
    assert result.requirements[0].value == pytest.approx(1.0, abs=1e-9)
    assert result.doe_best["objective"] >= result.objective
    check_result(result)


SPEC_2R = """mechanism = "planar_2r"
[objective]
type = "positioning_error"
tolerances = "tol.csv"
poses = "poses.csv"
[variables]
a1 = [0.1, 1.0]
a2 = [0.1, 1.0]
[requirements]
min_reach = 1.0
reach_pose_deg = [0, 0]
[doe]
points = 64
"""


def _every_source(mech) -> list:
    from mechatron.accuracy.sources import ErrorSource, source_unit

    rng = np.random.default_rng(3)
    names = list(mech.parameters) + [link.name for link in mech.dh.links]
    out = []
    for name in names:
        resolved, unit = source_unit(mech, name)
        kind = "parameter" if name in mech.parameters else "coordinate"
        scale = 1e-4 if unit == "m" else 1e-3
        out.append(ErrorSource(resolved, kind, unit, float(rng.uniform(0.2, 1) * scale), bias=float(scale * 0.3)))
    return out


@pytest.mark.parametrize("robot", ["puma560", "scara", "cylindrical_rpp", "articulated_rrr", "planar_3r",
                                   "puma560 modified"])
def test_dh_chain_worst_case_equals_the_accuracy_module_on_every_arm(robot):
    # every a, α, d, θ and every joint as an error source with a bias, at random poses within the limits: both DH
    # conventions, revolute and prismatic joints; and one length as the design variable away from its nominal
    from dataclasses import replace

    from mechatron.model.dh import dh_mechanism

    mech = mechatron.load(robot.split()[0])
    if robot.endswith("modified"):
        mech = dh_mechanism(replace(mech.dh, convention="modified"), "puma_modified")
    rng = np.random.default_rng(11)
    links = mech.dh.links
    poses = rng.uniform([link.lower for link in links], [link.upper for link in links], (4, len(links)))
    length = next(n for n, p in mech.parameters.items() if p.kind == "length" and abs(p.value) > 0.05)
    nominal = mech.parameters[length].value
    box = tuple(sorted((0.8 * nominal, 1.2 * nominal)))
    problem = PositioningProblem(mech, {length: box}, sources=_every_source(mech), poses=poses)
    for x in (nominal, 1.1 * nominal):
        assert problem.values(np.array([x])) == pytest.approx(problem.evaluate(np.array([x])), rel=1e-10, abs=1e-15)


@pytest.fixture(scope="module")
def puma_problem():
    mech = mechatron.load("puma560")
    sources = read_tolerances(DATA / "tolerances_puma560.csv", mech)
    P, labels = read_poses(DATA / "poses_puma560.csv", mech)
    return PositioningProblem(mech, {"a2": (0.30, 0.60), "d4": (0.20, 0.60), "a3": (0.0, 0.05)}, sources=sources,
                              poses=P, labels=labels, min_reach=0.8, reach_pose=np.radians([0, 0, -90, 0, 0, 0]))


def test_puma_casadi_worst_case_equals_the_accuracy_module(puma_problem):
    # the tolerance file has lengths, twists (AT grade), a bias and every joint: CasADi's Jacobians of the DH chain
    # against Pinocchio's and the accuracy module's parameter derivatives, and the reach against Pinocchio's FK
    rng = np.random.default_rng(7)
    p = puma_problem
    for x in rng.uniform(p.lower, p.upper, (3, len(p.lower))):
        assert p.values(x) == pytest.approx(p.evaluate(x), rel=1e-10, abs=1e-15)


def test_puma_gradients_equal_finite_differences_of_the_pinocchio_model(puma_problem):
    p, h = puma_problem, 1e-6
    for x in (np.array([0.45, 0.35, 0.02]), np.array([0.55, 0.25, 0.04])):
        fd = np.column_stack([(p.evaluate(x + h * e) - p.evaluate(x - h * e)) / (2 * h) for e in np.eye(len(x))])
        assert p.jacobian(x) == pytest.approx(fd, rel=1e-6, abs=1e-9 * np.abs(fd).max())


def test_shipped_puma_example_is_feasible_and_beats_its_doe():
    from mechatron.optimal import optimize

    result = optimize(ROOT / "examples" / "optimize" / "puma_accuracy.toml")
    assert result.success and result.feasible and result.beats_doe
    assert result.objective < result.start_objective
    assert result.model_difference < 1e-9
    # the optimum as the accuracy module sees it: the largest |Δr| of its worst case over the poses
    from mechatron.accuracy.study import analyse_tolerances as run_study

    mech = mechatron.load("puma560").with_parameters(dict(zip(result.variables, result.x)))
    study = run_study(mech, read_tolerances(ROOT / "examples" / "optimize" / "puma_tolerances.csv", mech),
                      read_poses(DATA / "poses_puma560.csv", mech)[0], methods=("worst",))
    assert study.poses["dr_worst"].max() == pytest.approx(result.objective, rel=1e-12)


@pytest.mark.parametrize("change, names", [
    (('"planar_2r"', '"six_bar_bucket"'), ["s.toml", "objective.type", "not a DH arm"]),
    (('"tol.csv"', '"none.csv"'), ["s.toml", "objective.tolerances", "no such file"]),
    (("a1 = [0.1, 1.0]", "alpha1 = [0.1, 1.0]"), ["s.toml", "variables.alpha1", "not a design variable"]),
    (("reach_pose_deg = [0, 0]\n", ""), ["s.toml", "requirements.reach_pose_deg", "together"]),
    (("reach_pose_deg = [0, 0]", "reach_pose_deg = [0]"), ["s.toml", "requirements.reach_pose_deg"]),
    (("min_reach = 1.0", "min_reach = -1.0"), ["s.toml", "requirements.min_reach"]),
])
def test_bad_positioning_specs_fail_with_one_line(tmp_path, capfd, change, names):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_arcmin\nq1,1\nq2,1\n")
    (tmp_path / "poses.csv").write_text("label,q1_deg,q2_deg\nbent,0,90\n")
    (tmp_path / "s.toml").write_text(SPEC_2R.replace(*change))
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, names)


def test_a_graded_design_variable_is_refused(tmp_path, capfd):
    (tmp_path / "tol.csv").write_text("parameter,grade,tolerance_arcmin\na1,IT7,\nq1,,1\n")
    (tmp_path / "poses.csv").write_text("label,q1_deg,q2_deg\nbent,0,90\n")
    (tmp_path / "s.toml").write_text(SPEC_2R)
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, ["tol.csv", "grade", "a1 is a design variable"])


def test_bad_tolerance_file_names_its_row(tmp_path, capfd):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_arcmin\nq1,1\nq2,nan\n")
    (tmp_path / "poses.csv").write_text("label,q1_deg,q2_deg\nbent,0,90\n")
    (tmp_path / "s.toml").write_text(SPEC_2R)
    assert_clean_error(["optimize", "s.toml"], capfd, tmp_path, ["tol.csv", "tolerance_arcmin"])


def test_command_prints_the_optimum(tmp_path, capfd):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_arcmin\nq1,1\nq2,1\n")
    (tmp_path / "poses.csv").write_text("label,q1_deg,q2_deg\nbent,0,90\n")
    (tmp_path / "s.toml").write_text(SPEC_2R)
    outcome = run(["optimize", "s.toml"], capfd, tmp_path)
    assert outcome.code == 0, outcome.err
    assert "max_worst_case_error" in outcome.out and "reach_m" in outcome.out

"""Optimal design of any machine from a design file (docs/design_file.md): a user's crank-slider by exact
derivatives, a scissor lift's cylinder pin against a grid study, a Pareto front against the non-dominated set of a
study over the same designs, DH angles and a URDF's origins as variables, and every refusal before any evaluation."""

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mechatron.errors import InputError
from mechatron.studies.design import Evaluations, ExactModel, optimize_design
from mechatron.studies.design_spec import MAX_EVALUATIONS, read_design
from mechatron.studies.result import pareto_mask

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "design"


@pytest.fixture
def crank(tmp_path):
    """A user's crank-slider file (a copy of the shipped one under another name) and its design file."""
    shutil.copy(EXAMPLES / "my_crank.toml", tmp_path / "my_crank.toml")
    shutil.copy(EXAMPLES / "crank_reach.toml", tmp_path / "crank_reach.toml")
    return tmp_path / "crank_reach.toml"


def _write(folder: Path, text: str, name: str = "design.toml") -> Path:
    path = folder / name
    path.write_text(text)
    return path


def test_the_crank_slider_by_exact_derivatives(crank):
    # reach = l1 + l2 (the slider's farthest x), travel = 2 l1 [Egorov, fig. 4.18]: least l1 + l2 with 2 l1 >= 0.2
    # is l1 = 0.1 (the requirement binding) and l2 = 0.35 (its lower bound)
    result = optimize_design(crank)
    assert result.solver["method"].startswith("ipopt")
    assert result.best["l1"] == pytest.approx(0.1, abs=1e-6)
    assert result.best["l2"] == pytest.approx(0.35, abs=1e-6)
    assert result.best["reach_m"] == pytest.approx(0.45, abs=2e-6)
    assert result.feasible
    frame = result.to_frame()
    assert list(frame.loc[frame["kind"] == "variable", "unit"]) == ["m", "m"]
    (travel,) = [r for r in result.requirements if r.name == "x_travel_m"]
    assert travel.margin == pytest.approx(2 * result.best["l1"] - 0.2, abs=1e-9) and travel.unit == "m"
    data = json.loads(json.dumps(result.as_dict(), allow_nan=False))
    assert data["objectives"] == [{"name": "reach_m", "goal": "minimize", "unit": "m"}]
    assert "reach" in str(result) and result.plot().axes[0].get_ylabel() == "reach (m)"


def test_the_exact_gradients_equal_central_differences_of_the_evaluated_outputs(crank):
    spec = read_design(crank)
    model, evaluations = ExactModel(spec), Evaluations(spec)
    x = np.array([0.093, 0.41])
    _, gradients = model(x)
    for name in ("reach_m", "x_travel_m"):
        fd = []
        for k in range(2):
            step = np.zeros(2)
            step[k] = 1e-6
            up, down = evaluations([dict(l1=v[0], l2=v[1]) for v in (x + step, x - step)])
            fd.append((up[name] - down[name]) / 2e-6)
        np.testing.assert_allclose(gradients[name], fd, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(gradients["reach_m"], [1.0, 1.0], atol=1e-9)
    np.testing.assert_allclose(gradients["x_travel_m"], [2.0, 0.0], atol=1e-9)


def test_the_crank_slider_by_the_global_route_meets_the_requirement_near_the_optimum(crank):
    text = crank.read_text() + '\n[solver]\nmethod = "global"\npopulation = 16\nevaluations = 320\n'
    result = optimize_design(_write(crank.parent, text))
    assert result.solver["method"].startswith("global")
    assert result.feasible and result.best["x_travel_m"] >= 0.2 - 1e-9
    assert result.best["reach_m"] == pytest.approx(0.45, abs=2e-3)
    evaluated = result.evaluations
    assert len(evaluated) <= 320
    ok = evaluated[evaluated["feasible"]]
    assert result.best["reach_m"] == ok["reach_m"].min()


def _grid_best(spec_path: Path, levels: int) -> pd.Series:
    """The best feasible design of a grid study of the design file's variables and analyses."""
    from mechatron.studies.design import Evaluations

    spec = read_design(spec_path)
    evaluations = Evaluations(spec)
    axes = [np.linspace(0.0, 1.0, levels)] * len(spec.variables)
    points = np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)
    rows = evaluations([evaluations.design(u) for u in points])
    table = pd.DataFrame(rows)
    feasible = table[[evaluations.feasible(r) for r in rows]]
    return feasible.sort_values("drive_mass_kg", kind="stable").iloc[0]


@pytest.mark.parametrize("workers", [1, 2])
def test_the_scissor_lift_cylinder_pin_is_no_worse_than_a_grid_study(workers):
    path = EXAMPLES / "scissor_cylinder.toml"
    result = optimize_design(path, workers=workers)
    assert result.feasible
    grid = _grid_best(path, 6)
    assert result.best["drive_mass_kg"] <= grid["drive_mass_kg"] + 1e-9
    assert result.best["smallest_margin"] >= 0.0
    serial = optimize_design(path) if workers == 2 else result
    assert (result.best["P_x"], result.best["P_y"]) == (serial.best["P_x"], serial.best["P_y"])


def test_the_pareto_front_is_the_non_dominated_set_of_the_same_designs(tmp_path):
    path = _write(tmp_path, """
mechanism = "puma560"
[variables]
a2 = [0.39, 0.47]
a3 = [0.0, 0.04]
[objective]
minimize = ["drive_mass_kg", "cycle_time_s"]
[requirements]
feasible = { min = 1 }
[analyses.sizing]
objective = "time"
single_pass = true
[solver]
population = 8
evaluations = 24
""")
    result = optimize_design(path)
    assert result.solver["method"].startswith("nsga2")
    # a study of the same designs (a CSV of them), its own evaluation and its own Pareto front
    from mechatron.studies.runner import run_study

    designs = result.evaluations[["a2", "a3"]]
    designs.to_csv(tmp_path / "designs.csv", index=False)
    _write(tmp_path, """
mechanism = "puma560"
[designs]
method = "csv"
file = "designs.csv"
[analyses.sizing]
objective = "time"
single_pass = true
[output.pareto]
x = "drive_mass_kg"
y = "cycle_time_s"
""", "study.toml")
    study = run_study(tmp_path / "study.toml", tmp_path / "study")
    feasible = study.table[study.table["feasible"].astype(bool) & (study.table["status"] == "ok")]
    mask = pareto_mask(feasible["drive_mass_kg"].to_numpy(float), feasible["cycle_time_s"].to_numpy(float))
    expected = feasible[mask].sort_values("drive_mass_kg", kind="stable")
    assert len(result.front) >= 1
    columns = ["a2", "a3", "drive_mass_kg", "cycle_time_s"]
    np.testing.assert_allclose(result.front[columns].to_numpy(float), expected[columns].to_numpy(float),
                               rtol=1e-12)
    table = result.evaluations[result.evaluations["feasible"]]
    assert len(table) == len(feasible)  # the same designs feasible
    figure = result.plot()
    assert "(kg)" in figure.axes[0].get_xlabel() and "(s)" in figure.axes[0].get_ylabel()


def test_dh_angles_and_urdf_origins_are_variables(tmp_path):
    dh = optimize_design(_write(tmp_path, """
mechanism = "puma560"
[variables]
alpha3 = [-0.2, 0.2]
theta2 = [-0.1, 0.1]
[objective]
minimize = "q2_peak_Nm"
[analyses.dynamics]
[solver]
method = "global"
population = 6
evaluations = 12
""", "dh.toml"))
    assert set(dh.best) >= {"alpha3", "theta2"} and dh.feasible
    urdf = ROOT / "examples" / "data" / "turret_arm.urdf"
    arm = optimize_design(_write(tmp_path, f"""
mechanism = "{urdf}"
[variables]
extend_x = [0.2, 0.4]
[objective]
minimize = "shoulder_peak_Nm"
[analyses.dynamics]
[solver]
method = "global"
population = 5
evaluations = 10
""", "urdf.toml"))
    assert 0.2 <= arm.best["extend_x"] <= 0.4


BAD = {
    "unknown variable": ('[variables]\nl9 = [0.1, 0.2]', "variables.l9", "unknown parameter"),
    "inverted bounds": ('[variables]\nl1 = [0.12, 0.08]', "variables.l1", "empty range"),
    "equal bounds": ('[variables]\nl1 = [0.1, 0.1]', "variables.l1", "empty range"),
    "non-finite bound": ('[variables]\nl1 = [0.08, inf]', "variables.l1", "finite"),
    "start outside": ('[variables]\nl1 = [0.08, 0.12]\n[start]\nl1 = 0.2', "start.l1", "outside"),
    "unknown objective": ('[variables]\nl1 = [0.08, 0.12]\n[objective]\nminimize = "reach"', "objective.minimize",
                          "reach_m"),
    "unknown requirement": ('[variables]\nl1 = [0.08, 0.12]\n[requirements]\nspeed = { min = 1 }',
                            "requirements.speed", "x_travel_m"),
    "budget": (f'[variables]\nl1 = [0.08, 0.12]\n[solver]\nevaluations = {MAX_EVALUATIONS + 1}',
               "solver.evaluations", "at most"),
    "pareto of one": ('[variables]\nl1 = [0.08, 0.12]\n[solver]\nmethod = "nsga2"', "solver.method", "two"),
}


def test_a_discrete_choice_naming_a_missing_file_is_refused_naming_the_variable(tmp_path):
    catalog = ROOT / "catalogs" / "hydraulic_cylinders.csv"
    path = _write(tmp_path, f"""
mechanism = "{ROOT / 'examples' / 'data' / 'scissor_lift.toml'}"
[variables]
P_x = [0.35, 0.65]
[variables.catalog]
values = ["{catalog}", "nope.csv"]
target = "sizing.cylinders"
[objective]
minimize = "drive_mass_kg"
[analyses.sizing]
task = "{EXAMPLES / 'scissor_lift_task.toml'}"
""")
    with pytest.raises(InputError) as error:
        read_design(path)
    assert "variables.catalog" in str(error.value) and "nope.csv" in str(error.value)


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_design_files_are_refused_naming_the_field(crank, case):
    body, field, words = BAD[case]
    base = 'mechanism = "my_crank.toml"\n'
    objective = "" if "[objective]" in body else '[objective]\nminimize = "reach_m"\n'
    text = base + body + "\n" + objective + "[analyses.linkage]\nsamples = 5\n"
    if "[solver]" in body and "[objective]" not in body:
        text = base + objective + "[analyses.linkage]\nsamples = 5\n" + body + "\n"
    with pytest.raises(InputError) as error:
        read_design(_write(crank.parent, text))
    message = str(error.value)
    assert field in message and words in message, message


def test_the_front_and_the_optimum_are_written_as_mechanism_files_that_load(crank, tmp_path):
    import mechatron
    from mechatron.studies.design import write_designs

    spec = read_design(crank)
    designs = pd.DataFrame({"l1": [0.1, 0.11], "l2": [0.36, 0.4]})
    paths = write_designs(spec, designs, tmp_path / "out")
    assert [p.name for p in paths] == ["design-000.toml", "design-001.toml"]
    for path, (_, row) in zip(paths, designs.iterrows()):
        mech = mechatron.load(path)
        assert mech.parameters["l1"].value == pytest.approx(row["l1"], abs=1e-12)
        assert mech.parameters["l2"].value == pytest.approx(row["l2"], abs=1e-12)
    dh = _write(tmp_path, 'mechanism = "puma560"\n[variables]\na2 = [0.4, 0.45]\n[objective]\nminimize = '
                          '"q2_peak_Nm"\n[analyses.dynamics]\n', "arm.toml")
    (urdf,) = write_designs(read_design(dh), pd.DataFrame({"a2": [0.42]}), tmp_path / "arm")
    arm, reference = mechatron.load(urdf), mechatron.load("puma560", a2=0.42)
    q = np.array([0.1, -0.4, 0.3, 0.2, -0.5, 0.6])
    np.testing.assert_allclose(mechatron.frame_placement(arm, q, "tool").translation,
                               mechatron.frame_placement(reference, q, "tool").translation, atol=1e-12)


def test_the_command_line_writes_the_optimum_and_exits_1_when_a_requirement_cannot_be_met(crank, tmp_path):
    from mechatron.cli import main

    assert main(["optimize", str(crank), "-o", str(tmp_path / "best"), "--json"]) == 0
    assert (tmp_path / "best" / "design-000.toml").is_file()
    impossible = crank.read_text().replace("x_travel_m = { min = 0.2 }", "x_travel_m = { min = 0.5 }")
    impossible += '\n[solver]\nmethod = "global"\npopulation = 5\nevaluations = 10\n'
    assert main(["optimize", str(_write(crank.parent, impossible, "impossible.toml"))]) == 1

"""Issue 13, input files: generated bad files of every format, each run through the command that reads it, must fail
cleanly (exit 2, one stderr line naming the file — and the row and field where they apply —, files unchanged).

Formats: robot TOML, mechanism TOML, task TOML, structure TOML, URDF, the catalog CSVs (motors, gearboxes, linear
drives, hydraulic cylinders), trajectory CSV, tolerance CSV and poses CSV. The rows named are the files' line numbers
(comment lines count). Hypothesis draws the numbers of the numeric fields from the bad ones (NaN, ±inf, huge,
negative where a value must not be).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.corpus import assert_clean_error

ROOT = Path(__file__).resolve().parent.parent
FAST = settings(suppress_health_check=[HealthCheck.function_scoped_fixture], deadline=None, max_examples=8)

#: TOML spellings of the bad numbers: not finite, too large to compute with, not a number.
NOT_FINITE = ("nan", "inf", "-inf", "1e308", "-1e308", '"abc"', '""', "[1.0]")
NEGATIVE = ("-1", "-1e-3")


def toml_number(x: float) -> str:
    return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf") if math.isinf(x) else repr(float(x))


#: Numbers a physical value can never have (hypothesis): NaN, ±inf, beyond 1e12 either side.
huge = st.one_of(st.just(math.nan), st.just(math.inf), st.just(-math.inf),
                 st.floats(min_value=1.001e12, max_value=1e308), st.floats(min_value=-1e308, max_value=-1.001e12))
negative = st.floats(min_value=-1e11, max_value=-1e-6)


# ------------------------------------------------------------------------------------------------ robot TOML
ROBOT = """name = "arm"
[[links]]
joint = "revolute"
a = {a}
alpha_deg = {alpha_deg}
lower_deg = {lower_deg}
upper_deg = {upper_deg}
max_velocity = {max_velocity}
mass = {mass}
com = [{com}, 0.0, 0.0]
inertia = {{ xx = {xx}, yy = 0.04, zz = 0.04 }}
drive = {{ gear_ratio = {gear_ratio}, rotor_inertia = {rotor_inertia}, efficiency = {efficiency} }}

[[links]]
joint = "prismatic"
lower = 0.0
upper = {upper}
mass = 1.0
"""
ROBOT_OK = dict(a="0.5", alpha_deg="0.0", lower_deg="-170", upper_deg="170", max_velocity="2.0", mass="2.0",
                com="-0.25", xx="0.002", gear_ratio="100", rotor_inertia="1e-5", efficiency="0.9", upper="0.3")
#: field → (name in the message, extra bad values besides NOT_FINITE)
ROBOT_FIELDS = {"a": ("links[1].a", ()), "alpha_deg": ("links[1].alpha_deg", ()),
                "lower_deg": ("lower", ("200",)), "upper_deg": ("upper", ()),
                "max_velocity": ("links[1].max_velocity", ("0", *NEGATIVE)), "mass": ("links[1].mass", NEGATIVE),
                "com": ("links[1].com", ()), "xx": ("inertia", ("-1", "0.5")),
                "gear_ratio": ("gear_ratio", ("0",)), "rotor_inertia": ("rotor_inertia", NEGATIVE),
                "efficiency": ("efficiency", ("0", "-0.5")), "upper": ("links[2]", ("-1",))}


def robot_text(**changes: str) -> str:
    return ROBOT.format(**{**ROBOT_OK, **changes})


def test_the_robot_template_is_good(tmp_path, capfd):
    """The corpus's template reads: every failure below is the changed field's."""
    from mechatron.model.robotfile import read_robot_file

    (tmp_path / "arm.toml").write_text(robot_text())
    assert read_robot_file(tmp_path / "arm.toml").table.n == 2


@pytest.mark.parametrize("field,value", [(f, v) for f, (_, extra) in ROBOT_FIELDS.items()
                                         for v in NOT_FINITE + extra])
def test_robot_file_bad_numbers(tmp_path, capfd, field, value):
    (tmp_path / "arm.toml").write_text(robot_text(**{field: value}))
    assert_clean_error(["show", "arm.toml"], capfd, tmp_path, ["arm.toml", ROBOT_FIELDS[field][0]])


@FAST
@given(mass=st.one_of(huge, negative), xx=huge)
def test_robot_file_hypothesis_masses_and_inertias(tmp_path, capfd, mass, xx):
    (tmp_path / "arm.toml").write_text(robot_text(mass=toml_number(mass)))
    assert_clean_error(["show", "arm.toml"], capfd, tmp_path, ["arm.toml", "links[1].mass"])
    (tmp_path / "arm.toml").write_text(robot_text(xx=toml_number(xx)))
    assert_clean_error(["show", "arm.toml"], capfd, tmp_path, ["arm.toml", "inertia"])


# ------------------------------------------------------------------------------------------- mechanism TOML
def crank_slider() -> str:
    return (ROOT / "robots" / "crank_slider.toml").read_text()


MECHANISM_FIELDS = {  # (text to replace, template with {v}, name in the message, extra bad values)
    "point": ("A = [0.0, 0.0]", "A = [{v}, 0.0]", "A", ()),
    "mass": ("mass = 2.0", "mass = {v}", "mass", NEGATIVE),
    "inertia": ("inertia = 1e-3", "inertia = {v}", "inertia", ("-1",)),
    "rate": ("input_rates = { q1 = 1.0 }", "input_rates = {{ q1 = {v} }}", "q1", ("0", "-1")),
}


@pytest.mark.parametrize("field,value", [(f, v) for f, spec in MECHANISM_FIELDS.items()
                                         for v in NOT_FINITE + spec[3]])
def test_mechanism_file_bad_numbers(tmp_path, capfd, field, value):
    old, template, name, _ = MECHANISM_FIELDS[field]
    text = crank_slider()
    assert old in text
    (tmp_path / "slider.toml").write_text(text.replace(old, template.format(v=value), 1))
    assert_clean_error(["show", "slider.toml"], capfd, tmp_path, ["slider.toml", name])


def test_mechanism_file_gravity(tmp_path, capfd):
    for value in ("nan", "inf", "1e308", "-1", '"g"'):
        (tmp_path / "slider.toml").write_text(f"gravity = {value}\n" + crank_slider())
        assert_clean_error(["show", "slider.toml"], capfd, tmp_path, ["slider.toml", "gravity"])


# ------------------------------------------------------------------------------------------------ task TOML
TASK = """name = "move"
payload = {payload}
payload_com = [0.0, 0.0, {com}]
dwell = {dwell}
dt = {dt}
vmax = [{vmax}, 1.0]
amax = [4.0, 4.0]
waypoints = [[0.0, 0.0], [0.5, {q2}]]
"""
TASK_OK = dict(payload="1.0", com="0.05", dwell="0.2", dt="0.01", vmax="1.0", q2="0.5")
TASK_FIELDS = {"payload": ("payload", NEGATIVE), "com": ("payload_com", ()), "dwell": ("dwell", NEGATIVE),
               "dt": ("dt", ("0", "-1")), "vmax": ("vmax", ("0", "-1")), "q2": ("waypoints", ())}


@pytest.mark.parametrize("field,value", [(f, v) for f, (_, extra) in TASK_FIELDS.items()
                                         for v in NOT_FINITE + extra])
def test_task_file_bad_numbers(tmp_path, capfd, field, value):
    (tmp_path / "move.toml").write_text(TASK.format(**{**TASK_OK, field: value}))
    assert_clean_error(["size", "planar_2r", "--task", "move.toml"], capfd, tmp_path,
                       ["move.toml", TASK_FIELDS[field][0]])


# ------------------------------------------------------------------------------------------- structure TOML
def four_bar_structure() -> str:
    return (ROOT / "examples" / "data" / "four_bar_structure.toml").read_text()


STRUCTURE = (ROOT / "robots" / "structures" / "cam_3_11a.toml").read_text()


@pytest.mark.parametrize("value", ["0.5", "2.5", "-1", "nan", "inf", "1e308", '"one"'])
def test_structure_file_redundant_links_are_whole(tmp_path, capfd, value):
    (tmp_path / "cam.toml").write_text(STRUCTURE.replace("redundant_links = 1", f"redundant_links = {value}"))
    assert_clean_error(["structure", "cam.toml"], capfd, tmp_path, ["cam.toml", "redundant_links"])


@pytest.mark.parametrize("value", ["2.5", "0", "6", "nan", '"x"'])
def test_structure_file_pair_class(tmp_path, capfd, value):
    text = STRUCTURE.replace('kind = "L"', f"class = {value}", 1)
    (tmp_path / "cam.toml").write_text(text)
    assert_clean_error(["structure", "cam.toml"], capfd, tmp_path, ["cam.toml", "class"])


def test_structure_file_without_pairs_is_named_as_one(tmp_path, capfd):
    (tmp_path / "cam.toml").write_text('name = "cam"\nplanar = true\nlinks = ["cam", "roller", "follower"]\n')
    for command in (["show", "cam.toml"], ["structure", "cam.toml"]):
        out = assert_clean_error(command, capfd, tmp_path, ["cam.toml"])
        assert "pairs" in out.err


# ------------------------------------------------------------------------------------------------------ URDF
URDF = """<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <link name="upper">
    <inertial>
      <origin xyz="{com} 0 0" rpy="0 0 0"/>
      <mass value="{mass}"/>
      <inertia ixx="{ixx}" iyy="0.04" izz="0.04" ixy="{ixy}" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <link name="fore">
    <inertial><mass value="1.0"/><inertia ixx="0.001" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <origin xyz="0 0 {z}" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="{lower}" upper="{upper}" effort="{effort}" velocity="2"/>
  </joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.5 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="50" velocity="2"/></joint>
</robot>
"""
URDF_OK = dict(com="0.25", mass="2.0", ixx="0.002", ixy="0", z="0.3", lower="-2", upper="2", effort="50")
URDF_BAD = {"NaN": "nan", "inf": "inf", "-inf": "-inf", "text": "abc", "empty": ""}
URDF_FIELDS = {  # field → (what the message names, extra bad values)
    "mass": (["link 'upper'", "mass value"], {"negative": "-1", "1e308": "1e308", "two": "1 2"}),
    "ixx": (["link 'upper'", "inertia"], {"negative": "-1", "1e308": "1e308"}),
    "ixy": (["link 'upper'", "inertia"], {"not definite": "0.5", "1e40": "1e40"}),
    "com": (["link 'upper'", "origin xyz"], {"1e308": "1e308"}),
    "z": (["joint 'shoulder'", "origin xyz"], {"1e13": "1e13"}),
    "lower": (["joint 'shoulder'", "lower"], {"reversed": "3"}),
    "upper": (["joint 'shoulder'", "upper"], {"reversed": "-3"}),
    "effort": (["joint 'shoulder'", "effort"], {"negative": "-5"}),
}


def test_the_urdf_template_is_good(tmp_path):
    import mechatron

    (tmp_path / "two.urdf").write_text(URDF.format(**URDF_OK))
    assert mechatron.load(tmp_path / "two.urdf").nv == 2


@pytest.mark.parametrize("field,value", [(f, v) for f, (_, extra) in URDF_FIELDS.items()
                                         for v in {**URDF_BAD, **extra}.values()])
def test_urdf_bad_numbers(tmp_path, capfd, field, value):
    (tmp_path / "two.urdf").write_text(URDF.format(**{**URDF_OK, field: value}))
    names = URDF_FIELDS[field][0]
    if field in ("lower", "upper") and value in ("3", "-3"):
        names = ["joint 'shoulder'", "lower limit 3", "above upper limit"] if value == "3" else \
            ["joint 'shoulder'", "lower limit -2", "above upper limit -3"]
    assert_clean_error(["show", "two.urdf"], capfd, tmp_path, ["two.urdf", *names])


def test_urdf_negative_inertia_gives_no_huge_torque(tmp_path, capfd):
    """A negative principal moment was read and gave a peak torque of 2e61 N·m; now it is refused by name."""
    (tmp_path / "two.urdf").write_text(URDF.format(**{**URDF_OK, "ixx": "-0.5"}))
    assert_clean_error(["dynamics", "two.urdf"], capfd, tmp_path, ["two.urdf", "link 'upper'", "positive semidefinite"])


def test_urdf_not_xml(tmp_path, capfd):
    (tmp_path / "two.urdf").write_text(URDF.format(**URDF_OK)[:300])
    assert_clean_error(["show", "two.urdf"], capfd, tmp_path, ["two.urdf", "not valid XML"])


def test_urdf_triangle_inequality_checked_on_request(tmp_path):
    from mechatron.errors import InputError
    from mechatron.model.urdf import check_urdf

    (tmp_path / "two.urdf").write_text(URDF.format(**{**URDF_OK, "ixx": "0.1"}))  # 0.04 + 0.04 < 0.1
    check_urdf(tmp_path / "two.urdf")
    with pytest.raises(InputError, match="triangle inequality"):
        check_urdf(tmp_path / "two.urdf", physical=True)


# ------------------------------------------------------------------------------------------------ catalog CSVs
def catalog(name: str) -> tuple[list[str], list[str]]:
    """(header, first data row) of an example catalog."""
    lines = [line for line in (ROOT / "examples" / "data" / name).read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    return lines[0].split(","), lines[1].split(",")


CATALOGS = {"motors.csv": "--motors", "gearboxes.csv": "--gearboxes", "linear_drives.csv": "--linear",
            "hydraulic_cylinders.csv": "--cylinders"}
CSV_BAD = ("nan", "inf", "-inf", "1e308", "-1", "abc", "")


def catalog_cases():
    for name, option in CATALOGS.items():
        header, row = catalog(name)
        for j, column in enumerate(header):
            if column in ("key", "maker", "series", "type", "end_fixing", "stages", "permitted_force_kN"):
                continue
            for value in (CSV_BAD[j % 7], CSV_BAD[(j + 3) % 7], CSV_BAD[(j + 5) % 7]):  # every value, in turn
                if value == "" and column in ("price_eur", "resistance_ohm", "voltage_V", "torque_constant_Nm_A",
                                              "rated_current_A", "rated_power_W", "mass_kg", "max_length_mm",
                                              "mass_per_length_kg_m", "mass_per_stroke_kg_m", "backlash_arcmin",
                                              "inertia_per_length_kgcm2_m", "root_diameter_mm",
                                              "emergency_torque_Nm", "rated_input_speed_rpm", "input_inertia_kgcm2",
                                              "efficiency_percent", "efficiency", "inertia_kgcm2",
                                              "dynamic_load_kN", "max_speed_rpm", "max_stroke_mm", "loss_torque_Nm",
                                              "peak_rule", "shock_factors_per_h", "emergency_stops"):
                    continue  # optional columns: empty is allowed
                yield pytest.param(name, option, j, value, id=f"{name}-{column}-{value or 'empty'}")


@pytest.mark.parametrize("name,option,j,value", list(catalog_cases()))
def test_catalog_bad_cells(tmp_path, capfd, name, option, j, value):
    """A bad cell in row 4 of the file (a comment line and the header before two rows): the error names line 4."""
    header, row = catalog(name)
    bad = list(row)
    bad[j] = value
    bad[0] = row[0] + "x"
    (tmp_path / name).write_text("# a catalog\n" + ",".join(header) + "\n" + ",".join(row) + "\n" + ",".join(bad)
                                 + "\n")
    robot = "front_shovel" if option == "--cylinders" else "cylindrical_rpp" if option == "--linear" else "planar_2r"
    assert_clean_error(["size", robot, option, name], capfd, tmp_path, [name, "row 4", header[j]])


@pytest.mark.parametrize("name,option", list(CATALOGS.items()))
def test_catalog_header_problems(tmp_path, capfd, name, option):
    header, row = catalog(name)
    robot = "front_shovel" if option == "--cylinders" else "cylindrical_rpp" if option == "--linear" else "planar_2r"
    # a column given twice
    (tmp_path / name).write_text(",".join([*header, header[2]]) + "\n" + ",".join([*row, row[2]]) + "\n")
    assert_clean_error(["size", robot, option, name], capfd, tmp_path, [name, "row 1", header[2], "twice"])
    # a required column missing
    drop = header.index({"motors.csv": "rated_torque_Nm", "gearboxes.csv": "ratio", "linear_drives.csv": "lead_mm",
                         "hydraulic_cylinders.csv": "bore_mm"}[name])
    (tmp_path / name).write_text(",".join(header[:drop] + header[drop + 1:]) + "\n"
                                 + ",".join(row[:drop] + row[drop + 1:]) + "\n")
    assert_clean_error(["size", robot, option, name], capfd, tmp_path, [name, "missing column"])
    # a row with more cells than the header, after comments: named by its line
    (tmp_path / name).write_text("# c\n\n" + ",".join(header) + "\n# c\n" + ",".join([*row, "1"]) + "\n")
    assert_clean_error(["size", robot, option, name], capfd, tmp_path, [name, "row 5", "cells"])
    # a header cell without a name
    (tmp_path / name).write_text(",".join([*header, ""]) + "\n" + ",".join([*row, "1"]) + "\n")
    assert_clean_error(["size", robot, option, name], capfd, tmp_path, [name, "no name"])


# ------------------------------------------------------------------------------------------- trajectory CSV
def trajectory(rows: list[str]) -> str:
    return "# a move of the planar 2R\n\nt,q1,q2\n" + "\n".join(rows) + "\n"


GOOD_ROWS = ["0,0,0", "0.1,0.01,0.02", "0.2,0.04,0.08", "0.3,0.09,0.18"]


@pytest.mark.parametrize("column", [0, 1, 2])
@pytest.mark.parametrize("value", CSV_BAD[:4] + ("abc", ""))
def test_trajectory_bad_cells(tmp_path, capfd, column, value):
    rows = list(GOOD_ROWS)
    cells = rows[2].split(",")
    cells[column] = value
    rows[2] = ",".join(cells)
    (tmp_path / "move.csv").write_text(trajectory(rows))
    name = ["t", "q1", "q2"][column]
    for command in (["dynamics", "planar_2r", "--trajectory", "move.csv"], ["size", "planar_2r", "--task", "move.csv"]):
        assert_clean_error(command, capfd, tmp_path, ["move.csv", "row 6", f"'{name}'"])


def test_trajectory_times_must_increase_named_by_line(tmp_path, capfd):
    rows = list(GOOD_ROWS)
    rows[2] = "0.05,0.04,0.08"
    (tmp_path / "move.csv").write_text(trajectory(rows[:2] + ["# a comment in the middle"] + rows[2:]))
    assert_clean_error(["dynamics", "planar_2r", "--trajectory", "move.csv"], capfd, tmp_path,
                       ["move.csv", "row 7", "'t'", "increase"])


@pytest.mark.parametrize("header", ["t,q1,q1", "t,q1", "q1,q2", "t,q1,q2,"])
def test_trajectory_header_problems(tmp_path, capfd, header):
    (tmp_path / "move.csv").write_text(header + "\n" + "\n".join(r + ("," if header.endswith(",") else "")
                                                                   for r in GOOD_ROWS) + "\n")
    assert_clean_error(["dynamics", "planar_2r", "--trajectory", "move.csv"], capfd, tmp_path, ["move.csv"])


# --------------------------------------------------------------------------------------------- tolerance CSV
def tolerances(value: str, column: str = "tolerance_mm") -> str:
    return f"# tolerances\nparameter,{column},distribution\nlinks[1].a,0.01,normal\nlinks[2].a,{value},uniform\n"


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e308", "1e39", "1e-50", "1e-8", "-0.1", "abc", "2e12"])
def test_tolerance_bad_values(tmp_path, capfd, value):
    (tmp_path / "tol.csv").write_text(tolerances(value).replace("links[1].a", "a1").replace("links[2].a", "a2"))
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv"], capfd, tmp_path,
                       ["tol.csv", "row 4", "tolerance_mm"])


@pytest.mark.parametrize("column,value", [("bias_mm", "1e308"), ("bias_mm", "nan"), ("bias_mm", "2e6"),
                                          ("bias_mm", "abc"), ("error_mm", "inf"), ("error_mm", "5e6")])
def test_tolerance_bad_bias_and_error(tmp_path, capfd, column, value):
    (tmp_path / "tol.csv").write_text(f"parameter,tolerance_mm,{column}\n# c\na1,0.01,0\na2,0.01,{value}\n")
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv"], capfd, tmp_path,
                       ["tol.csv", "row 4", column])


@pytest.mark.parametrize("text,names", [
    ("parameter,tolerance_mm,tolerance_mm\na1,0.1,0.1\n", ["row 1", "twice"]),
    ("tolerance_mm\n0.1\n", ["parameter"]),
    ("parameter,tolerance_mm\n# c\na1,0.1\na1,0.1\n", ["row 4", "repeats row 3"]),
    ("parameter,tolerance_mm\na1,0.1,5\n", ["row 2", "cells"]),
    ("parameter,distribution\na1,normal\n", ["tolerance"]),
    ("parameter,tolerance_mm,distribution\n\n\na1,0.1,gauss\n", ["row 4", "distribution"]),
])
def test_tolerance_file_structure(tmp_path, capfd, text, names):
    (tmp_path / "tol.csv").write_text(text)
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv"], capfd, tmp_path, ["tol.csv", *names])


@FAST
@given(value=st.one_of(huge, st.floats(min_value=1e-300, max_value=9.9e-10), st.floats(min_value=1e3 * 1.01,
                                                                                      max_value=1e11)))
def test_tolerance_hypothesis(tmp_path, capfd, value):
    (tmp_path / "tol.csv").write_text(f"parameter,tolerance\na1,{value!r}\n")
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv", "--method", "worst"], capfd, tmp_path,
                       ["tol.csv", "row 2", "tolerance"])


def test_tiny_tolerances_monte_carlo_agrees_with_the_worst_case():
    """Tolerances of 1e-9 m (the smallest accepted) drawn in double precision: the Monte Carlo's spread is the linear
    one (it was 0 with single-precision draws of 1e-50)."""
    import mechatron
    from mechatron.accuracy.sources import ErrorSource
    from mechatron.accuracy.study import analyse_tolerances as run_study

    mech = mechatron.load("planar_2r")
    sources = [ErrorSource("a1", "parameter", "m", 1e-9, "uniform")]
    result = run_study(mech, sources, [[0.3, 0.4]], methods=["worst", "mc"], samples=2000, seed=1)
    worst = result.poses["dr_worst"].iloc[0]
    assert worst == pytest.approx(1e-9, rel=1e-9)  # ∂r/∂a1 is a unit vector
    dr = np.linalg.norm(result.samples, axis=1)
    assert dr.max() <= worst * (1 + 1e-5) and dr.max() > 0.95 * worst


def test_rss_against_a_hand_calculation():
    """RSS is the k·σ estimate k·√Σ(∂r/∂p·σ)²: one uniform source ±0.1 mm of unit sensitivity gives 3·0.1/√3 =
    0.1732 mm, above the worst case 0.1 mm; a normal one (σ = t/3) gives exactly the worst case; two normal ones
    √(0.1² + 0.2²) ≤ 0.1 + 0.2."""
    import mechatron
    from mechatron.accuracy.sources import ErrorSource
    from mechatron.accuracy.study import analyse_tolerances as run_study

    mech = mechatron.load("planar_2r")
    pose = [[0.0, 0.0]]  # stretched along x: ∂r/∂a1 = ∂r/∂a2 = (1, 0, 0)
    uniform = run_study(mech, [ErrorSource("a1", "parameter", "m", 1e-4, "uniform")], pose, methods=["worst", "rss"])
    assert uniform.poses["dr_worst"].iloc[0] == pytest.approx(1e-4, rel=1e-12)
    assert uniform.poses["dr_rss"].iloc[0] == pytest.approx(3 * 1e-4 / math.sqrt(3), rel=1e-12)
    normal = run_study(mech, [ErrorSource("a1", "parameter", "m", 1e-4), ErrorSource("a2", "parameter", "m", 2e-4)],
                       pose, methods=["worst", "rss"])
    assert normal.poses["dr_rss"].iloc[0] == pytest.approx(math.hypot(1e-4, 2e-4), rel=1e-12)
    assert normal.poses["dr_worst"].iloc[0] == pytest.approx(3e-4, rel=1e-12)


def test_error_source_api_refuses_absurd_tolerances():
    from mechatron.accuracy.sources import ErrorSource
    from mechatron.errors import InputError

    for value in (1e-50, 1e39, math.nan, math.inf, -1.0):
        with pytest.raises(InputError, match="tolerance of a1"):
            ErrorSource("a1", "parameter", "m", value)
    with pytest.raises(InputError, match="bias of a1"):
        ErrorSource("a1", "parameter", "m", 1e-3, bias=math.nan)


# ------------------------------------------------------------------------------------------------- poses CSV
@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e308", "abc", ""])
@pytest.mark.parametrize("column", ["q1", "q2_deg"])
def test_poses_bad_cells(tmp_path, capfd, value, column):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_mm\na1,0.01\n")
    row = f"{value},10" if column == "q1" else f"0.1,{value}"
    (tmp_path / "poses.csv").write_text(f"q1,q2_deg\n# c\n0.1,10\n{row}\n")
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv", "--poses", "poses.csv"], capfd, tmp_path,
                       ["poses.csv", "row 4", column])


@pytest.mark.parametrize("header,names", [("q1,q1,q2", ["twice"]), ("q1", ["missing", "q2"]),
                                          ("q1,q2,q3", ["q3"]), ("q1,q2_furlong", ["furlong"])])
def test_poses_header_problems(tmp_path, capfd, header, names):
    (tmp_path / "tol.csv").write_text("parameter,tolerance_mm\na1,0.01\n")
    (tmp_path / "poses.csv").write_text(header + "\n" + ",".join(["0.1"] * len(header.split(","))) + "\n")
    assert_clean_error(["tolerance", "planar_2r", "--tolerances", "tol.csv", "--poses", "poses.csv"], capfd, tmp_path,
                       ["poses.csv", *names])


# ------------------------------------------------------------------- values outside a closed loop's strokes
@pytest.mark.parametrize("value", ["5", "1", "3.9"])
def test_out_of_stroke_values_name_the_file_and_row(tmp_path, capfd, value):
    """The front shovel's boom cylinder L1 strokes over [2.2404, 3.80868] m: a value beyond is refused by file, row
    (line) and column in a trajectory, a poses file and a task's waypoints."""
    (tmp_path / "move.csv").write_text(f"t,L1,L2,L3\n0,3,2.5,2.2\n# c\n0.5,3.1,2.5,2.2\n1,{value},2.5,2.2\n")
    assert_clean_error(["dynamics", "front_shovel", "--trajectory", "move.csv"], capfd, tmp_path,
                       ["move.csv", "row 5", "'L1'", f"L1 = {value} m", "stroke [2.2404, 3.80868] m"])
    (tmp_path / "poses.csv").write_text(f"L1_mm,L2,L3\n3000,2.5,2.2\n{float(value) * 1000:g},2.5,2.2\n")
    (tmp_path / "tol.csv").write_text("parameter,tolerance_mm\nL1,0.1\n")
    assert_clean_error(["tolerance", "front_shovel", "--tolerances", "tol.csv", "--poses", "poses.csv"], capfd,
                       tmp_path, ["poses.csv", "row 3", "'L1_mm'", f"L1 = {value} m", "stroke"])
    (tmp_path / "task.toml").write_text(f"waypoints = [[3, 2.5, 2.2], [{value}, 2.5, 2.2]]\n")
    assert_clean_error(["size", "front_shovel", "--task", "task.toml"], capfd, tmp_path,
                       ["task.toml", "waypoints[2]", f"L1 = {value} m", "stroke"])


@pytest.mark.parametrize("value", ["0.01", "0.02"])
def test_drawing_that_cannot_close_gives_the_residual_with_its_unit(tmp_path, capfd, value):
    text = crank_slider()
    assert "value = 0.4 }" in text
    (tmp_path / "slider.toml").write_text(text.replace("value = 0.4 }", f"value = {value} }}"))
    assert_clean_error(["show", "slider.toml"], capfd, tmp_path, ["slider.toml", "cannot be closed", "l2"],
                       pattern=r"off by [0-9.e+]+ mm")


SHOVEL_FIELDS = {  # (text to replace, template with {v}, name in the message, extra bad values)
    "stroke": ("stroke = [2.240401862275488, 3.80868316586833]", "stroke = [2.240401862275488, {v}]", "stroke",
               ("-1", "1", "0")),
    "count": ("count = 2", "count = {v}", "count", ("2.5", "0", "-1")),
    "lower": ("lower = -0.13999168775447282", "lower = {v}", "lower", ("1.5",)),
}


@pytest.mark.parametrize("field,value", [(f, v) for f, spec in SHOVEL_FIELDS.items() for v in NOT_FINITE[:6] + spec[3]])
def test_mechanism_file_cylinders_and_limits(tmp_path, capfd, field, value):
    old, template, name, _ = SHOVEL_FIELDS[field]
    text = (ROOT / "robots" / "front_shovel.toml").read_text()
    assert old in text
    (tmp_path / "shovel.toml").write_text(text.replace(old, template.format(v=value), 1))
    assert_clean_error(["show", "shovel.toml"], capfd, tmp_path, ["shovel.toml"], pattern=name)


@FAST
@given(cell=st.one_of(huge, st.sampled_from(["abc", "", "1e400", "0x10", "--1"])), column=st.sampled_from([0, 1, 2]))
def test_trajectory_hypothesis(tmp_path, capfd, cell, column):
    rows = list(GOOD_ROWS)
    cells = rows[1].split(",")
    cells[column] = cell if isinstance(cell, str) else repr(cell)
    rows[1] = ",".join(cells)
    (tmp_path / "move.csv").write_text(trajectory(rows))
    assert_clean_error(["dynamics", "planar_2r", "--trajectory", "move.csv"], capfd, tmp_path,
                       ["move.csv", "row 5", ["'t'", "'q1'", "'q2'"][column]])


@FAST
@given(value=st.one_of(huge, negative), column=st.sampled_from(["rated_torque_Nm", "rotor_inertia_kgcm2",
                                                                 "mass_kg", "max_speed_rpm"]))
def test_motor_catalog_hypothesis(tmp_path, capfd, value, column):
    header, row = catalog("motors.csv")
    cells = list(row)
    cells[header.index(column)] = repr(value)
    (tmp_path / "motors.csv").write_text(",".join(header) + "\n" + ",".join(cells) + "\n")
    assert_clean_error(["size", "planar_2r", "--motors", "motors.csv"], capfd, tmp_path,
                       ["motors.csv", "row 2", column])


@pytest.mark.parametrize("kind,column", [("rotary_tables", "torque_30min"), ("rotary_tables", "diameter_mm"),
                                         ("gearmotor_ranges", "ratio_min"),
                                         ("gearmotor_ranges", "output_speed_max_rpm")])
@pytest.mark.parametrize("value", ["nan", "-inf", "1e308", "-1", "abc"])
def test_catalogs_read_by_the_api(tmp_path, kind, column, value):
    """The rotary-table and gearmotor catalogs (read by Python only): the error names the file, the line and the
    column."""
    from mechatron.drives.catalogs import DEFAULT_FILES, read_catalog
    from mechatron.errors import InputError

    lines = [line for line in (ROOT / "catalogs" / DEFAULT_FILES[kind]).read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    header = lines[0].split(",")
    cells = lines[1].split(",")
    cells[header.index(column)] = value
    (tmp_path / "c.csv").write_text("# c\n" + lines[0] + "\n" + lines[1] + "\n" + ",".join(cells) + "\n")
    with pytest.raises(InputError) as error:
        read_catalog(tmp_path / "c.csv", kind)
    assert error.value.row == 4 and error.value.field == column and "c.csv" in str(error.value)

"""Issue 32's leftovers. References: the inverse dynamics of the mechanism with and without the payload, each over
the samples where the task carries it or not (found here from the task's rests, by hand), and hand statics."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import mechatron
from mechatron.drives.loads import trajectory_loads
from mechatron.dynamics.task import read_task
from mechatron.dynamics.tree import inverse_dynamics
from mechatron.studies.analyses import analysis
from mechatron.studies.runner import run_study
from tests.boom import boom

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
G = 9.81
ARM_TASK = "payload = 3.0\n{span}dwell = 0.2\nwaypoints_deg = [[10, 20], [60, -30], [10, 20]]\n"


def write(folder, name: str, text: str):
    path = folder / name
    path.write_text(text)
    return path


@pytest.fixture()
def arm(tmp_path):
    """The planar 2R arm of robots/planar_2r.toml in a vertical plane (gravity −y)."""
    text = (ROOT / "robots" / "planar_2r.toml").read_text()
    return mechatron.load(str(write(tmp_path, "arm.toml", text.replace(
        'convention = "standard"', 'convention = "standard"\ngravity = [0.0, -9.81, 0.0]'))))


def carried_until_second_arrival(trajectory) -> np.ndarray:
    """By hand: carried from the start to the first sample at rest at waypoint 2 (the end of the first move)."""
    still = np.flatnonzero(np.all(trajectory.v == 0, axis=1))
    arrival = still[np.flatnonzero(np.diff(still) > 1)[0] + 1]  # the first rest after the first move
    carried = np.zeros(len(trajectory.t), dtype=bool)
    carried[: arrival + 1] = True
    return carried


# ------------------------------------------------------------------------ (a) study analyses take the schedule
def test_study_dynamics_of_a_released_payload(arm, tmp_path):
    path = write(tmp_path, "released.toml", ARM_TASK.format(span="payload_until = 2\n"))
    always = write(tmp_path, "always.toml", ARM_TASK.format(span=""))
    out = analysis("dynamics").outputs(arm, {"task": str(path)}, 0)
    t = read_task(path, arm)
    carried = carried_until_second_arrival(t.trajectory)
    q, v, a = t.trajectory.q, t.trajectory.v, t.trajectory.a
    hand = np.where(carried[:, None], inverse_dynamics(t.mechanism, q, v, a), inverse_dynamics(arm, q, v, a))
    command = trajectory_loads(t.unloaded, t.trajectory, payload=t.schedule).forces  # what `size`/`dynamics` see
    carried_out = analysis("dynamics").outputs(arm, {"task": str(always)}, 0)
    for j, name in enumerate(["q1", "q2"]):
        peak = out[f"{name}_peak_Nm"]
        assert peak == pytest.approx(np.abs(command[:, j]).max(), rel=0, abs=1e-9)
        assert peak == pytest.approx(np.abs(hand[:, j]).max(), rel=0, abs=1e-9)
        rms = math.sqrt(np.trapezoid(hand[:, j] ** 2, t.trajectory.t) / t.duration)
        assert out[f"{name}_rms_Nm"] == pytest.approx(rms, rel=1e-12)
        assert carried_out[f"{name}_rms_Nm"] - out[f"{name}_rms_Nm"] > 0.5  # the return is without the payload


def test_study_sizing_of_a_released_payload(arm, tmp_path):
    from mechatron.studies.analyses.sizing import run

    path = write(tmp_path, "released.toml", ARM_TASK.format(span="payload_until = 2\n"))
    result = run(arm, {"task": str(path), "single_pass": True})
    t = result.given
    carried = carried_until_second_arrival(t.trajectory)
    q, v, a = t.trajectory.q, t.trajectory.v, t.trajectory.a
    hand = np.where(carried[:, None], inverse_dynamics(t.mechanism, q, v, a), inverse_dynamics(arm, q, v, a))
    loaded = inverse_dynamics(t.mechanism, q, v, a)
    for j, sized in enumerate(result.joints):
        np.testing.assert_allclose(sized.duty.torque, hand[:, j], rtol=0, atol=1e-9)
        assert np.abs(sized.duty.torque - loaded[:, j]).max() > 1.0  # not the always-carried payload


BOOM = boom(points="T = [1.0, 0.2]\nP = [-0.5, 0.0]", carried='"O", "E", "T", "P"',
            body="mass = 20.0\ncom = [0.5, 0.0]")
BOOM_TASK = ('payload = 20.0\npayload_at = "P"\n{span}dwell = 0.5\nwaypoints = [[0.45], [0.65], [0.45]]\n'
             'vmax = 0.1\namax = 0.2\n')


def test_study_of_a_boom_with_a_released_counterweight(tmp_path):
    """A boom (20 kg, centre at x = 0.5 m in the drawing) with 20 kg at P (x = −0.5 m) behind its pivot O, released
    at waypoint 2. Drawn pose, by hand (moments about O, the cylinder along u = (E − B0)/|E − B0| = (0.6, 0.8),
    its arm about O r_E × u = 0.5·0.8 − 0.1·0.6 = 0.34 m): carried, g (20·0.5 − 20·0.5)/0.34 = 0 N; released
    g·20·0.5/0.34 = 288.53 N — the linkage analysis' envelope of both. The dynamics analysis of a full study equals
    the dynamics of the same task (payload where carried) to 1e-9."""
    mech_path = write(tmp_path, "boom.toml", BOOM)
    task = write(tmp_path, "released.toml", BOOM_TASK.format(span="payload_until = 2\n"))
    always = write(tmp_path, "always.toml", BOOM_TASK.format(span=""))
    pose = '[[analyses.linkage.poses]]\nname = "drawn"\ninputs = { lift = 0.5 }\n'
    spec = write(tmp_path, "study.toml", f'mechanism = "{mech_path}"\n[parameters.T_x]\nvalues = [1.0]\n'
                 f'[designs]\nmethod = "grid"\n[analyses.dynamics]\ntask = "{task}"\n'
                 f'[analyses.linkage]\nsamples = 7\ntask = "{task}"\n{pose}')
    row = run_study(spec, tmp_path / "out").to_frame().iloc[0]
    mech = mechatron.load(str(mech_path))
    t = read_task(task, mech)
    command = trajectory_loads(t.unloaded, t.trajectory, payload=t.schedule).forces[:, 0]
    carried = carried_until_second_arrival(t.trajectory)
    loaded, bare = (trajectory_loads(m, t.trajectory).forces[:, 0] for m in (t.mechanism, mech))
    assert row["lift_peak_N"] == pytest.approx(np.abs(command).max(), rel=0, abs=1e-9)
    assert row["lift_peak_N"] == pytest.approx(np.abs(np.where(carried, loaded, bare)).max(), rel=0, abs=1e-9)
    assert row["lift_peak_N"] - np.abs(loaded).max() > 50.0  # the counterweight released: the bare boom pulls more
    assert row["drawn.lift_max_force_N"] == pytest.approx(G * 20 * 0.5 / 0.34, rel=1e-9)
    out = analysis("linkage").outputs(mech, {"samples": 7, "task": str(always), "poses": [
        {"name": "drawn", "inputs": {"lift": 0.5}}]}, 0)
    assert out["drawn.lift_max_force_N"] == pytest.approx(0.0, abs=1e-6)  # always carried: balanced
    assert out["lift_max_force_N"] == pytest.approx(0.0, abs=1e-6)  # the centre of boom and weight at O throughout
    assert row["lift_max_force_N"] > 280.0  # the released case at the sweep's positions


# ------------------------------------------------------------------- (b) twin cylinders: the report per cylinder
def test_twin_cylinders_chart_and_table_per_cylinder(tmp_path):
    """A massless-cylinder boom (20 kg, centre x = 0.5 m) holding 100 kg at T (x = 1.0 m) on one cylinder or on two
    side by side (``count = 2``), one catalog row so that both choose it. At rest in the drawn pose (lift = 0.5 m,
    the dwell that ends the task) the total force by hand is g (20·0.5 + 100·1.0)/0.34 = 3173.8 N (moments about
    O); the chart and the load checks of the twin hold half of it, what one catalog cylinder carries."""
    from mechatron.drives.catalogs import default_catalog

    catalog = default_catalog("cylinders")
    catalog = catalog[catalog["key"] == "HC40/22-32"].reset_index(drop=True)
    task = write(tmp_path, "task.toml", 'payload = 100.0\npayload_at = "T"\ndwell = 0.5\n'
                 'waypoints = [[0.5], [0.6], [0.5]]\nvmax = 0.1\namax = 0.2\n')
    sized = {}
    for count in (1, 2):
        path = write(tmp_path, f"boom{count}.toml", boom(body="mass = 20.0\ncom = [0.5, 0.0]",
                                                         tail=f"count = {count}\n"))
        sized[count] = mechatron.size(mechatron.load(str(path)), task, cylinders=catalog, single_pass=True).joints[0]
    one, two = sized[1], sized[2]
    assert one.cylinder == two.cylinder == "HC40/22-32" and two.count == 2
    total = G * (20 * 0.5 + 100 * 1.0) / 0.34
    chart = {k: j.chart_frame() for k, j in sized.items()}
    points = {k: c[c["series"] == "operating point"]["force_per_cylinder_N"].to_numpy() for k, c in chart.items()}
    assert points[1][-1] == pytest.approx(total, rel=1e-9) and points[2][-1] == pytest.approx(total / 2, rel=1e-9)
    np.testing.assert_allclose(points[2], points[1] / 2, rtol=1e-12, atol=1e-9)
    limits = {k: c[c["series"] == "rod buckling limit"]["force_per_cylinder_N"].to_numpy() for k, c in chart.items()}
    np.testing.assert_allclose(limits[2], limits[1], rtol=1e-12)  # the same rod, the same lengths
    table = {k: j.to_frame().set_index("check") for k, j in sized.items()}
    for check in ("push pressure", "rod buckling"):
        assert table[2].loc[check, "value"] == pytest.approx(table[1].loc[check, "value"] / 2, rel=1e-12)
        assert table[2].loc[check, "limit"] == pytest.approx(table[1].loc[check, "limit"], rel=1e-12)
    ax = two.plot().axes[0]
    assert "per cylinder" in ax.get_ylabel()


# ------------------------------------------------------------------------- (c) which drive masses the sizing added
def test_drive_masses_line_of_cylinders_and_of_motors():
    """Scissor lift (one cylinder, no motor): the catalog cylinder's mass, (mass + mass_per_stroke × stroke) × count
    from the catalog row, is not in the model — the fixed point's forces equal those of weightless drives (single
    pass) sample by sample — and the line says so. Planar 2R: the motors' and gearboxes' catalog masses, summed from
    their rows, are added at their mounts."""
    from mechatron.drives.catalogs import default_catalog

    lift = mechatron.load(str(ROOT / "examples" / "data" / "scissor_lift.toml"))
    task = ROOT / "examples" / "design" / "scissor_lift_task.toml"
    fixed, single = (mechatron.size(lift, task, single_pass=flag) for flag in (False, True))
    (joint,) = fixed.joints
    row = default_catalog("cylinders").set_index("key").loc[joint.cylinder]
    low, high = lift.cylinders[joint.joint].stroke
    mass = (row["mass"] + row["mass_per_stroke"] * (high - low)) * lift.cylinders[joint.joint].count
    np.testing.assert_allclose(joint.duty.torque, single.joints[0].duty.torque, rtol=0, atol=1e-9)
    assert (f"drive masses: none added — the cylinders' catalog masses ({mass:.4g} kg in all) are not in the model, "
            "which carries the barrel_mass and rod_mass of scissor_lift's cylinder joints as given") in str(fixed)
    arm = mechatron.size(mechatron.load("planar_2r"))
    motors, gearboxes = (default_catalog(kind).set_index("key")["mass"] for kind in ("motors", "gearboxes"))
    added = sum(motors[j.motor] + gearboxes[j.converter] for j in arm.joints)
    text = str(arm)
    assert f"drive masses: added at their mounts ({added:.4g} kg in all), fixed point after" in text
    assert "cylinders'" not in text


# ------------------------------------------------------------------- (d) a cylinder moved beyond its stroke
def passive_boom(stroke: str) -> str:
    """The boom with a second, passive cylinder "damper" from the ground pin B1 = (−0.2, −0.3) to F = (0.3, 0.05)
    on the boom (drawn 610.7 mm long)."""
    return boom(points="T = [1.0, 0.2]\nB1 = [-0.2, -0.3]\nF = [0.3, 0.05]", carried='"O", "E", "T", "F"',
                body="mass = 20.0\ncom = [0.5, 0.0]",
                tail=f'[[joints]]\ntype = "cylinder"\nname = "damper"\nbase = "B1"\neye = "F"\nstroke = {stroke}\n'
                ).replace('points = ["O", "B0"]', 'points = ["O", "B0", "B1"]')


def damper_length(lift: float) -> float:
    """By hand: the boom turns about O until |E − B0| = lift (law of cosines in the triangle O B0 E, the drawn
    branch: E above the line O B0), then F turns with it."""
    e, b0, b1, f = (np.array(p) for p in ((0.5, 0.1), (0.2, -0.3), (-0.2, -0.3), (0.3, 0.05)))
    alpha = math.acos((e @ e + b0 @ b0 - lift**2) / (2 * math.hypot(*e) * math.hypot(*b0)))
    turn = math.atan2(b0[1], b0[0]) + alpha - math.atan2(e[1], e[0])
    c, s = math.cos(turn), math.sin(turn)
    return float(np.hypot(*(np.array([c * f[0] - s * f[1], s * f[0] + c * f[1]]) - b1)))


def test_passive_cylinder_beyond_its_stroke_is_refused(tmp_path):
    from mechatron.errors import InputError, MechatronError

    task = write(tmp_path, "task.toml", 'payload = 100.0\npayload_at = "T"\ndwell = 0.5\n'
                 'waypoints = [[0.45], [0.65], [0.45]]\nvmax = 0.1\namax = 0.2\n')
    low, high = damper_length(0.45), damper_length(0.65)  # 589.8 and 655.3 mm: the damper lengthens as lift does
    assert damper_length(0.5) == pytest.approx(math.hypot(0.5, 0.35), rel=1e-12)  # the drawing
    short = mechatron.load(str(write(tmp_path, "short.toml", passive_boom("[0.55, 0.62]"))))
    with pytest.raises(MechatronError) as info:
        mechatron.size(short, task)
    message = str(info.value)
    assert (f"cylinder damper (passive: its length follows the loops) is {low * 1e3:.1f} … {high * 1e3:.1f} mm long "
            "along the task, outside its stroke [550, 620] mm") in message and "\n" not in message
    with pytest.raises(MechatronError, match="cylinder damper"):  # a study's sizing: the design's row fails so
        analysis("sizing").outputs(short, {"task": str(task)}, 0)
    wide = mechatron.load(str(write(tmp_path, "wide.toml", passive_boom(f"[0.55, {high + 1e-4:.6f}]"))))
    assert mechatron.size(wide, task, single_pass=True).feasible  # the same task within the stroke
    beyond = write(tmp_path, "beyond.toml", task.read_text().replace("[0.65]", "[0.75]"))
    with pytest.raises(InputError, match=r"lift = 0\.75 m is outside its stroke \[0\.4, 0\.7\] m"):  # driven
        mechatron.size(wide, beyond)


# ------------------------------------------------------------- (e) Cartesian waypoints within the joint limits
ELBOW_LIMITED = """name = "arm2r"
[[links]]
joint = "revolute"
a = 0.5
mass = 2.0
[[links]]
joint = "revolute"
a = 0.4
mass = 1.5
lower_deg = -150
upper_deg = 90
"""
LINE = """dt = 0.002
[cartesian]
points_mm = {points}
seed_deg = [0, 50]
speed = 0.5
acceleration = 2.0
"""


def elbow(r: float) -> float:
    """By hand: the planar 2R's elbow angle at distance r from its base, cos q2 = (r² − l1² − l2²)/(2 l1 l2) (deg)."""
    return math.degrees(math.acos((r * r - 0.25 - 0.16) / (2 * 0.5 * 0.4)))


def test_cartesian_waypoint_outside_a_joint_limit_is_refused(tmp_path):
    """A planar 2R (l1 = 0.5, l2 = 0.4 m) whose elbow stops at q2 = 90°, on the seed's elbow-positive branch: at
    r = 0.8 m the hand IK gives q2 = 54.90° (within), at r = 0.5 m q2 = 113.58° (beyond); q2 = 90° at r = √(l1² + l2²)
    = 0.6403 m, 53.23 % of the way along the radial line from r = 0.8 to 0.5 m."""
    from mechatron.errors import InputError

    mech = mechatron.load(str(write(tmp_path, "arm.toml", ELBOW_LIMITED)))
    ok = read_task(write(tmp_path, "ok.toml", LINE.format(points="[[800, 0, 0], [700, 0, 0]]")), mech)
    assert math.degrees(ok.trajectory.q[0, 1]) == pytest.approx(elbow(0.8), abs=1e-6)
    assert math.degrees(ok.trajectory.q[-1, 1]) == pytest.approx(elbow(0.7), abs=1e-6)
    with pytest.raises(InputError) as info:
        read_task(write(tmp_path, "line.toml", LINE.format(points="[[800, 0, 0], [500, 0, 0]]")), mech)
    message = str(info.value)
    assert "field 'cartesian.points_mm[2]'" in message and "joint q2 at 90" in message and "\n" not in message
    assert "outside its limits [-150, 90]°" in message
    where = float(re.search(r"at ([0-9.]+) % of the line to this waypoint", message).group(1))
    crossing = (0.8 - math.sqrt(0.41)) / 0.3
    assert 100 * crossing <= where < 100 * crossing + 1.0  # the first sample past the stop
    with pytest.raises(InputError) as info:
        read_task(write(tmp_path, "start.toml", LINE.format(points="[[500, 0, 0], [800, 0, 0]]")), mech)
    message = str(info.value)
    assert "field 'cartesian.points_mm[1]'" in message and f"joint q2 at {elbow(0.5):.6g}°" in message

"""Drive sizing: a hand-checked one-joint case, no double counting of the rotor inertia (against the dynamics'
own motor model), the sample envelope is exact, vectorized checks equal one-pair checks, ranking by each
objective, the time objective, infeasible joints and cylinders."""

import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from every_pair import passes, worst_load_factors
from reference import file_friction_at_joints

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.checks import CHECKS, PairChecks, evaluate
from mechatron.drives.converters import converters_for
from mechatron.drives.cylinders import BUCKLING_SAFETY, STEEL_MODULUS, size_cylinder
from mechatron.drives.duty import JointDuty, joint_duties
from mechatron.drives.sizing import size_joint, size_mechanism
from mechatron.drives.transmission import motor_loads
from mechatron.dynamics.motion import Trajectory, move
from mechatron.dynamics.task import default_task
from mechatron.dynamics.tree import inverse_dynamics
from mechatron.errors import InputError
from mechatron.model.dh import DHLink, DHTable, Drive, Inertial, dh_mechanism

# ------------------------------------------------------------------------------------------ the hand case
# A disc of 0.5 kg·m² on a vertical axis (no gravity torque) moves 2 rad: trapezoid, 2 rad/s, 10 rad/s².
# Motor: T_r 0.1, T_p 0.3 N·m, n_r 300, n_max 500 rad/s, J_m 1e-4 kg·m². Gearbox: u 50, η 0.9, J_c 2e-5 kg·m².
# By hand: accelerating 0.2 s with τ = 5 N·m (motoring): T_m = 1.2e-4·50·10 + 5/(50·0.9) = 0.171111 N·m;
# braking 0.2 s with τ = −5 N·m (the load drives the gear): T_m = −0.06 − 5·0.9/50 = −0.15 N·m; cruising 0.8 s
# with 0. RMS = √((0.171111²·0.2 + 0.15²·0.2)/1.2) = 0.092897 N·m against T_r at the mean speed 50·2/1.2 =
# 83.3 rad/s; inertia ratio (0.5/50² + 2e-5)/1e-4 = 2.2; output equivalent torque (speed-weighted cubic mean)
# (125·(0.2 + 0.2)/2)^(1/3) = 2.9240 N·m; emergency 0.3·50 = 15 N·m. The gearbox gives no maker rule for its peak
# torque (no shock_factors): T2B 10 N·m at the move's 6,000 load peaks per hour, the report saying that no maker
# rule covers that rate (docs/catalogs.md, "Gearbox duty"; issue 31; tests/test_gearbox_duty.py).

MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 0.1, "peak_torque": 0.3, "rated_speed": 300.0,
                       "max_speed": 500.0, "rotor_inertia": 1e-4, "mass": 1.0, "price": 100.0}])
GEARBOX = pd.DataFrame([{"key": "G50", "type": "planetary", "ratio": 50.0, "rated_torque": 5.0, "peak_torque": 10.0,
                         "emergency_torque": 20.0, "max_input_speed": 600.0, "rated_input_speed": 400.0,
                         "efficiency": 0.9, "input_inertia": 2e-5, "mass": 1.0, "price": 100.0}])


def disc():
    link = DHLink("revolute", name="q1", inertial=Inertial(0.0, np.zeros(3), np.diag([0.25, 0.25, 0.5])))
    return dh_mechanism(DHTable((link,)), "disc")


def disc_move(dt=1e-4):
    return move(disc(), [0.0], [2.0], profile="trapezoidal", vmax=2.0, amax=10.0, dt=dt)


def test_hand_checked_one_joint_one_motor_one_gearbox():
    mech = disc()
    result = size_mechanism(mech, disc_move(), MOTOR, GEARBOX, direct=False)
    (joint,) = result.joints
    assert joint.feasible and joint.motor == "M" and joint.converter == "G50" and joint.ratio == 50
    checks = {c.name: c for c in joint.checks}
    assert set(checks) == set(CHECKS)
    expected = {
        "peak torque": (0.171111, 0.3), "speed-torque curve": (0.171111 / 0.3, 1.0),
        "RMS torque": (math.sqrt((0.171111**2 * 0.2 + 0.15**2 * 0.2) / 1.2), 0.1), "max speed": (100.0, 500.0),
        "inertia ratio": (2.2, 10.0), "transmission equivalent torque": (25 ** (1 / 3), 5.0),
        "transmission peak torque": (5.0, 10.0),
        "transmission emergency torque": (15.0, 20.0),
        "transmission max input speed": (100.0, 600.0), "transmission mean input speed": (50 * 2 / 1.2, 400.0),
    }
    for name, (value, limit) in expected.items():
        assert checks[name].value == pytest.approx(value, rel=2e-3), name
        assert checks[name].limit == pytest.approx(limit, rel=1e-12), name
        assert checks[name].margin == pytest.approx(1 - checks[name].value / limit)
        assert checks[name].passed
    # the motor side over time, at one accelerating and one braking sample
    n, torque = joint.operating_points()
    t = joint.duty.t
    assert torque[np.searchsorted(t, 0.1)] == pytest.approx(0.06 + 5 / 45, rel=1e-9)
    assert torque[np.searchsorted(t, 1.1)] == pytest.approx(-0.06 - 0.09, rel=1e-9)
    assert n.max() == pytest.approx(100.0)


def test_hand_case_fails_the_right_checks_with_a_weaker_drive():
    weak = MOTOR.assign(rated_torque=0.08, peak_torque=0.16)  # RMS 0.093 > 0.08; peak 0.171 > 0.16
    (joint,) = size_mechanism(disc(), disc_move(dt=1e-3), weak, GEARBOX, direct=False).joints
    assert not joint.feasible
    failed = {c.name for c in joint.failed}
    assert failed == {"peak torque", "speed-torque curve", "RMS torque"}
    assert "peak torque" in joint.closest["failed"].iloc[0] and "RMS torque" in joint.closest["failed"].iloc[0]


# ------------------------------------------------------------------------------------ no double counting
@pytest.fixture(scope="module")
def puma_task():
    return default_task(mechatron.load("puma560"))


@pytest.fixture(scope="module")
def puma_sizing(puma_task):
    """The single-pass sizing: each joint alone, the drives weightless (tests/test_system_sizing.py: the drives'
    masses on the arm)."""
    return size_mechanism(puma_task.mechanism, puma_task.trajectory, loads=puma_task.loads, task=puma_task.name,
                          single_pass=True)


def test_duty_has_no_drive_inertia(puma_task):
    """The duty is the dynamics without the file's rotor inertia (armature), with the file's drive friction seen at
    the joint (issue 25: the friction of a robot file loads the joint in the sizing)."""
    mech, tr = puma_task.mechanism, puma_task.trajectory
    assert np.any(mech.model.armature > 0)  # the PUMA model carries its own motors' J·u²
    duties = joint_duties(mech, tr)
    full = inverse_dynamics(mech, tr.q, tr.v, tr.a) + file_friction_at_joints(mech.dh, tr.v)
    for j, duty in enumerate(duties):
        assert np.allclose(duty.torque, full[:, j] - mech.model.armature[j] * tr.a[:, j], atol=1e-9)


def test_motor_torque_matches_the_dynamics_motor_model(puma_task, puma_sizing):
    """Put the chosen motors and gearboxes into the DH model as drives (armature (J_m + J_c) u²) and compare
    dynamics.motor_loads with the sizing's motor torques: the rotor inertia is counted exactly once. The file's
    drive friction loads the joint (issue 25): it is added to the joint torque the geared model's drives carry."""
    mech = puma_task.mechanism
    table = mech.dh
    drives = {}
    for j in puma_sizing.joints:
        c = j.converter_data
        drives[j.joint] = Drive(rotor_inertia=j.motor_data["rotor_inertia"] + c["inertia"], gear_ratio=c["ratio"],
                                efficiency=c["efficiency"])
    links = tuple(replace(link, drive=drives[link.name]) for link in table.links)
    # the task's part: a uniform 100 × 60 × 55 mm block of 2.5 kg
    part = 2.5 / 12 * np.diag([0.06**2 + 0.055**2, 0.1**2 + 0.055**2, 0.1**2 + 0.06**2])
    geared = mechatron.model.payload.with_payload(dh_mechanism(replace(table, links=links), "puma_geared"), 2.5,
                                                  com=(0.0, 0.0, 0.05), inertia=part)
    tr = puma_task.trajectory
    motors = motor_loads(geared, tr.v, tr.a, inverse_dynamics(geared, tr.q, tr.v, tr.a)
                         + file_friction_at_joints(table, tr.v))
    for k, j in enumerate(puma_sizing.joints):
        speed, torque = j.operating_points()
        assert np.allclose(speed, motors.speed[:, k], rtol=1e-12)
        assert np.allclose(torque, motors.torque[:, k], rtol=1e-9, atol=1e-12)


# ------------------------------------------------------------------------------- vectorization and pruning
def random_duty(rng, n=600):
    t = np.linspace(0, 3, n)
    speed = np.cumsum(rng.normal(size=n)) * 0.05
    acceleration = np.gradient(speed, t)
    static = 3 * np.sin(2 * t + rng.uniform(0, 6))
    return JointDuty("j", "revolute", t, speed, acceleration, static + 0.8 * acceleration + 0.1 * speed, static,
                     0.8, 1.0)


def every_exact_check(duty, motors, gearboxes):
    """(values, limits) of every check of every pair, exact (the per-sample checks through the envelope once more
    than BEFORE_ENVELOPE pairs are checked, as in the sizing) but the winding's rise at its mean-rise bound."""
    checks = PairChecks(duty, motors, converters_for(duty, gearboxes))
    m, c = (x.ravel() for x in np.indices(checks.shape))
    return checks.table(m, c, level=2, thermal=False)


def test_envelope_is_exact(monkeypatch, puma_sizing, rng):
    """The per-sample checks over the envelope's samples equal those over every sample, for every pair of a third
    of the motors (rotor inertias and speed–torque curves across the catalog's range) and every converter: every
    value and limit of every check of every pair, float for float. The winding's rise is compared at its bound: its
    simulation runs over every sample of the task whatever the envelope (PairChecks.winding, against the test's own
    motor torque and simulation in tests/test_thermal.py), and was 95 % of this test's time when simulated twice."""
    motors, gearboxes = default_catalog("motors").iloc[::3].reset_index(drop=True), default_catalog("gearboxes")
    duties = [j.duty for j in puma_sizing.joints] + [random_duty(rng) for _ in range(3)]
    pruned = [every_exact_check(d, motors, gearboxes) for d in duties]
    assert any(len(d.envelope()) < len(d.t) / 10 for d in duties)
    monkeypatch.setattr(JointDuty, "envelope", lambda self: np.arange(len(self.t)))
    for d, fast in zip(duties, pruned):
        full = every_exact_check(d, motors, gearboxes)
        assert np.array_equal(fast[0], full[0]) and np.array_equal(fast[1], full[1])


def test_matrix_evaluation_equals_one_pair_at_a_time(puma_sizing, rng):
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    duty = puma_sizing.joints[1].duty
    conv = converters_for(duty, gearboxes)
    matrix = evaluate(duty, motors, conv)
    for m, c in zip(rng.integers(0, len(motors), 25), rng.integers(0, len(conv), 25)):
        single = evaluate(duty, motors.iloc[[m]], conv.subset([c]))
        assert np.allclose(single.values[0, 0], matrix.values[m, c], rtol=1e-12)
        assert np.allclose(single.limits[0, 0], matrix.limits[m, c], rtol=1e-12)


# --------------------------------------------------------------------------------------- ranking
@pytest.fixture(scope="module")
def third_joint(puma_sizing):
    """The third joint's duty and the worst load factor of each of its pairs (every check of every pair, exact for
    every pair that passes, tests/every_pair.py: all that the ranking's checks read), computed once for the three
    objectives."""
    duty = puma_sizing.joints[2].duty
    return duty, worst_load_factors(duty, default_catalog("motors"), converters_for(duty, default_catalog("gearboxes")))


@pytest.mark.parametrize("objective", ["mass", "cost", "margin"])
def test_objective_picks_the_best_feasible_pair(third_joint, objective):
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    duty, worst = third_joint
    result = size_joint(duty, motors, gearboxes, objective=objective)
    conv = converters_for(duty, gearboxes)
    feasible = worst <= 1 + 1e-9
    mass = motors["mass"].to_numpy()[:, None] + conv.mass[None, :]
    price = motors["price"].to_numpy()[:, None] + conv.price[None, :]
    m = int(np.flatnonzero(motors["key"] == result.motor)[0])
    c = int(np.flatnonzero(conv.key == result.converter)[0])
    assert feasible[m, c] and 5 <= len(result.ranking) <= feasible.sum()
    score = {"mass": mass, "cost": price, "margin": worst}[objective]
    assert score[m, c] == pytest.approx(score[feasible].min())
    # the ranking is the best feasible pairs, exact, in order: the head of the sorted feasible scores
    best = np.sort(score[feasible])[: len(result.ranking)]
    assert np.allclose(result.ranking["score"], best, rtol=1e-12)
    ranked = [(int(np.flatnonzero(motors["key"] == a)[0]), int(np.flatnonzero(conv.key == b)[0]))
              for a, b in zip(result.ranking["motor"], result.ranking["converter"])]
    assert all(feasible[i, j] for i, j in ranked)
    assert np.allclose(result.ranking["smallest_margin"], [1 - worst[i, j] for i, j in ranked], rtol=1e-12)
    assert result.ranking["score"].is_monotonic_increasing
    assert min(ch.margin for ch in result.checks) == pytest.approx(1 - worst[m, c])


def test_objectives_trade_off(puma_sizing):
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    duty = puma_sizing.joints[1].duty
    by = {o: size_joint(duty, motors, gearboxes, objective=o) for o in ("mass", "cost", "margin")}
    mass = {o: r.ranking.set_index(["motor", "converter"]).loc[(r.motor, r.converter), "mass"] for o, r in by.items()}
    assert mass["mass"] <= mass["cost"] and mass["mass"] <= mass["margin"]
    margin = {o: min(c.margin for c in r.checks) for o, r in by.items()}
    assert margin["margin"] >= margin["mass"] and margin["margin"] >= margin["cost"]


def test_time_objective_finds_the_fastest_feasible_pace(puma_task):
    """The fastest pace of the time objective is that of every pair checked: at it some pair of every joint passes,
    0.3 % faster some joint has none. Every pair of the example catalogs is checked at both paces by every check,
    the winding simulated for the pairs that pass every other check (tests/every_pair.py): the pass or fail of every
    pair of the dense evaluation, without its windings of the pairs that fail anyway."""
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    result = size_mechanism(puma_task.mechanism, puma_task.trajectory, motors, gearboxes, objective="time",
                            loads=puma_task.loads, single_pass=True)
    k = result.time_scale
    assert 0.02 < k < 1  # the catalog allows a faster cycle than the task's
    assert result.feasible and all(j.time_scale == k for j in result.joints)
    duties = joint_duties(puma_task.mechanism, puma_task.trajectory)

    def anything_passes(duty, scale):  # every check of every pair (tests/every_pair.py)
        return passes(worst_load_factors(duty.scaled(scale), motors, converters_for(duty, gearboxes))).any()

    assert all(anything_passes(d, k) for d in duties)
    assert not all(anything_passes(d, k / 1.003) for d in duties)  # a little faster and some joint fails
    for j in result.joints:  # and the lightest pair at that pace was chosen
        assert j.ranking["mass"].iloc[0] == j.ranking["mass"].min()


def test_scaled_duty_equals_the_dynamics_of_the_replayed_trajectory(puma_task):
    """The moves replayed 0.6 times as long, the dwells (both ends of an interval at rest, every speed zero, at the
    same place) as long as they were: the scaled duty is the dynamics of that trajectory."""
    mech, tr = puma_task.mechanism, puma_task.trajectory
    k = 0.6
    rest = np.all(tr.v == 0, axis=1)
    dwell = rest[:-1] & rest[1:] & np.all(np.diff(tr.q, axis=0) == 0, axis=1)
    assert dwell.sum() == 6 * 40  # six rests of 0.2 s sampled every 5 ms
    t = np.concatenate([[0.0], np.cumsum(np.diff(tr.t) * np.where(dwell, 1.0, k))])
    faster = Trajectory(t, tr.q, tr.v / k, tr.a / k**2, tr.names)
    for scaled, direct in zip((d.scaled(k) for d in joint_duties(mech, tr)), joint_duties(mech, faster)):
        assert np.allclose(scaled.torque, direct.torque, atol=1e-9)
        assert np.allclose(scaled.t, direct.t, rtol=0, atol=1e-12) and np.allclose(scaled.speed, direct.speed)
    assert t[-1] == pytest.approx(k * (tr.duration - 6 * 0.2) + 6 * 0.2, rel=1e-12)


# ------------------------------------------------------------------------------------- bad input
def test_bad_sizing_input():
    duty = joint_duties(disc(), disc_move(dt=1e-2))[0]
    with pytest.raises(InputError, match="unknown objective"):
        size_joint(duty, MOTOR, GEARBOX, objective="speed")
    with pytest.raises(InputError, match="inertia ratio"):
        size_joint(duty, MOTOR, GEARBOX, inertia_ratio_max=0)
    with pytest.raises(InputError, match="no converter"):
        size_joint(duty, MOTOR, None, direct=False)
    prismatic = replace(duty, kind="prismatic")
    with pytest.raises(InputError, match="catalog of linear drives"):
        size_joint(prismatic, MOTOR, GEARBOX)
    rest = np.zeros((len(duty.t), 1))
    with pytest.raises(InputError, match="no joint of disc moves"):
        size_mechanism(disc(), Trajectory(duty.t, rest, rest, rest, ["q1"]), MOTOR, GEARBOX)


# ------------------------------------------------------------------------------------- screws, cylinders
def test_prismatic_joint_gets_a_ball_screw():
    mech = mechatron.load("cylindrical_rpp")
    task = default_task(mech)
    result = size_mechanism(mech, task.trajectory)
    kinds = {j.joint: j.converter_kind for j in result.joints}
    assert kinds["q2"] == "ball screw" and kinds["q3"] == "ball screw"
    screw = next(j for j in result.joints if j.joint == "q2")
    row = default_catalog("linear").set_index("key").loc[screw.converter]
    u = 2 * math.pi / row["lead"]  # rad/m
    assert screw.ratio == pytest.approx(u)
    checks = {c.name: c for c in screw.checks}
    assert checks["max speed"].value == pytest.approx(u * np.abs(screw.duty.speed).max())
    length = screw.duty.stroke + 0.2
    screw_inertia = np.nan_to_num(row["inertia"]) + np.nan_to_num(row["inertia_per_length"]) * length
    reflected = screw.duty.load_inertia / u**2 + screw_inertia  # kg/u² + the screw's own inertia, kg·m²
    assert checks["inertia ratio"].value == pytest.approx(reflected / screw.motor_data["rotor_inertia"])
    assert checks["transmission max input speed"].limit == pytest.approx(row["max_speed"])


def test_cylinder_hand_check():
    spec = mechatron.model.Cylinder("L", "A", "B", (1.0, 1.8), count=2)
    t = np.linspace(0, 2, 201)
    force = 2e5 * np.sin(np.pi * t)  # pushes 200 kN (100 kN per cylinder), pulls 200 kN
    speed = 0.2 * np.cos(np.pi * t)
    duty = JointDuty("L", "cylinder", t, speed, np.gradient(speed, t), force, force, 0.0, 0.8)
    catalog = default_catalog("cylinders")
    sized = size_cylinder(duty, spec, catalog, pressure=25e6)
    bore, rod = sized.cylinder_data["bore"], sized.cylinder_data["rod"]
    piston, annulus = math.pi * bore**2 / 4, math.pi * (bore**2 - rod**2) / 4
    checks = {c.name: c for c in sized.checks}
    assert checks["push pressure"].value == pytest.approx(1e5 / piston)
    assert checks["pull pressure"].value == pytest.approx(1e5 / annulus)
    assert checks["rod buckling"].limit == pytest.approx(
        math.pi**2 * STEEL_MODULUS * math.pi * rod**4 / 64 / 1.8**2 / BUCKLING_SAFETY)
    assert sized.peak_flow == pytest.approx(2 * piston * 0.2, rel=1e-6)
    assert sized.feasible and all(c.passed for c in sized.checks)
    # the lightest feasible one: every lighter catalog cylinder fails a check
    mass = catalog["mass"] + catalog["mass_per_stroke"] * 0.8
    chosen = mass[catalog["key"] == sized.cylinder].iloc[0]
    for key in catalog["key"][mass < chosen]:
        assert not size_cylinder(duty, spec, catalog[catalog["key"] == key].reset_index(drop=True),
                                 pressure=25e6).feasible


def test_lazy_evaluation_bounds_and_closest_pairs(puma_sizing):
    """The per-sample checks start as lower bounds; the closest infeasible pairs found by branch and bound are the
    true five smallest worst load factors."""
    motors = default_catalog("motors")
    small = motors[motors["rated_torque"] < 0.4].reset_index(drop=True)
    gearboxes = default_catalog("gearboxes")
    duty = puma_sizing.joints[1].duty
    conv = converters_for(duty, gearboxes)
    for sample in (duty, random_duty(np.random.default_rng(3))):  # a trapezoidal cycle, a smooth random motion
        lazy, full = evaluate(sample, motors, conv, exact=False), evaluate(sample, motors, conv)
        bounds, values = lazy.values[..., :2], full.values[..., :2]  # peak torque, speed-torque curve
        assert np.all(bounds <= values * (1 + 1e-12))
        assert np.array_equal(lazy.values[..., 2:], full.values[..., 2:])
    assert not lazy.exact.any() and full.exact.all()
    exact = evaluate(duty, small, conv).worst()
    result = size_joint(duty, small, gearboxes)
    assert not result.feasible and exact.min() > 1
    assert np.allclose(result.closest["worst_load_factor"], np.sort(exact, axis=None)[:5], rtol=1e-12)
    assert result.motor == result.closest["motor"].iloc[0] and result.failed


def test_rack_and_pinion_counts_the_pinion_once():
    mech = mechatron.load("cylindrical_rpp")
    racks = default_catalog("linear").query("type == 'rack and pinion'").reset_index(drop=True)
    result = size_mechanism(mech, default_task(mech).trajectory, linear=racks)
    joint = next(j for j in result.joints if j.joint == "q3")
    row = racks.set_index("key").loc[joint.converter]
    assert joint.ratio == pytest.approx(2 * np.pi / row["lead"])
    assert joint.ratio == pytest.approx(2 / row["diameter"], rel=1e-5)  # u = 2π/(π d), the lead rounded to µm
    assert joint.converter_data["inertia"] == pytest.approx(row["inertia"])  # no per-length part
    checks = {c.name: c for c in joint.checks}
    J = joint.motor_data["rotor_inertia"]
    reflected = joint.duty.load_inertia / joint.ratio**2 + row["inertia"]
    assert checks["inertia ratio"].value == pytest.approx(reflected / J)


# ------------------------------------------------------------------------------------- continuous joints
URDF = """<robot name="{name}">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0.3 0 0"/><mass value="4"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.12" iyz="0" izz="0.12"/></inertial></link>
  <link name="slide"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="turn" type="{kind}"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>{limit}</joint>
  <joint name="reach" type="prismatic"><parent link="arm"/><child link="slide"/><origin xyz="0.2 0 0"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="500" velocity="1"/></joint>
</robot>
"""


def test_continuous_joint_is_sized_like_its_revolute_twin(tmp_path):
    """A URDF turntable on a continuous joint (q = (cos θ, sin θ), nq = 3, nv = 2) carrying a prismatic slide: its
    duties and drives equal those of the same robot with a revolute joint, and the slide's stroke (the screw
    length) is the slide's travel, whether the trajectory gives configurations (with their coordinates) or one
    coordinate per joint."""
    from mechatron.model.urdf import load_urdf

    paths = {}
    for kind, limit in (("continuous", ""), ("revolute", '<limit lower="-4" upper="4" effort="500" velocity="3"/>')):
        paths[kind] = tmp_path / f"{kind}.urdf"
        paths[kind].write_text(URDF.format(name=kind, kind=kind, limit=limit))
    endless, twin = load_urdf(paths["continuous"]), load_urdf(paths["revolute"])
    assert (endless.nq, endless.nv, twin.nq) == (3, 2, 2)
    t = np.linspace(0.0, 1.5, 301)
    tau = t / t[-1]
    s, ds, dds = 10 * tau**3 - 15 * tau**4 + 6 * tau**5, (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / t[-1], \
        (60 * tau - 180 * tau**2 + 120 * tau**3) / t[-1] ** 2
    travel = np.array([2.8, 0.35])  # the turn passes θ = π: the continuous joint's (cos, sin) wraps
    start = np.array([0.5, 0.05])
    coordinates = start + np.outer(s, travel)
    motion = Trajectory(t, coordinates, np.outer(ds, travel), np.outer(dds, travel), ["turn", "reach"])
    configurations = Trajectory(t, endless.configuration(coordinates), motion.v, motion.a, motion.names,
                                coordinates=coordinates)
    reference = joint_duties(twin, motion)
    assert reference[1].stroke == pytest.approx(0.35)
    for trajectory in (motion, configurations):
        for duty, expected in zip(joint_duties(endless, trajectory), reference):
            assert duty.kind == expected.kind and duty.stroke == pytest.approx(expected.stroke, rel=1e-12)
            assert np.allclose(duty.torque, expected.torque, rtol=1e-9, atol=1e-9)
            assert duty.load_inertia == pytest.approx(expected.load_inertia, rel=1e-9)
    sized, twin_sized = size_mechanism(endless, configurations), size_mechanism(twin, motion)
    assert [(j.motor, j.converter) for j in sized.joints] == [(j.motor, j.converter) for j in twin_sized.joints]
    assert [j.converter_kind for j in sized.joints][1] in ("ball screw", "rack and pinion")

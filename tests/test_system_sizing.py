"""Sizing as a system (issue 12): the chosen drives' masses load the mechanism until the choice no longer changes,
drive placements from robot and mechanism files, the payload's inertia, the time objective's dwells, the report
that explains (deciding check, runners-up, totals) and bad input.

Every number is checked against a hand calculation written out here: the closed-form dynamics of a two-link arm
with point masses, the reflected inertia of a box-shaped part, the virtual work of a mass on a four-bar, a
piecewise-constant motor torque over a trapezoidal move."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pinocchio as pin
import pytest
from reference import file_friction_at_joints

import mechatron
from mechatron.cli import main
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.duty import joint_duties
from mechatron.drives.sizing import size_mechanism
from mechatron.drives.transmission import motor_loads
from mechatron.dynamics.motion import Trajectory, move
from mechatron.dynamics.task import default_task, read_task
from mechatron.dynamics.tree import inverse_dynamics
from mechatron.errors import InputError
from mechatron.model.dh import DHLink, DHTable, Drive, Inertial, dh_mechanism
from mechatron.model.payload import with_payload

FOUR_BAR = Path(__file__).resolve().parent.parent / "examples" / "data" / "four_bar.toml"

# ------------------------------------------------------------------------------------------ the two-link arm
# Two links in a vertical plane (joint axes along z, gravity along −y): point masses m1 = 4 kg at the elbow (the end
# of link 1, L1 = 0.5 m) and m2 = 3 kg at the tip (L2 = 0.4 m further). The shoulder swings from −0.5 to 0.5 rad
# (trapezoid, 1 rad/s, 2 rad/s²) with the elbow held straight (q2 = 0). A mass m_w at distance d from the shoulder on
# link 1 (the wrist drive) gives, with q̇2 = q̈2 = q2 = 0,
#
#     τ1 = (m1 L1² + m_w d² + m2 (L1 + L2)²) q̈1 + g cos q1 (m1 L1 + m_w d + m2 (L1 + L2)),
#     τ2 = m2 L2 (L1 + L2) q̈1 + m2 g L2 cos q1                (the wrist drive is proximal to joint 2),
#
# and a direct-drive motor of rotor inertia J_m needs T_m = J_m q̈ + τ. Over the move, max |T_m1| = 51.48 N·m with
# weightless drives, 56.47 N·m with a 2 kg wrist drive at mid-link (d = 0.25 m) and 61.97 N·m at the elbow
# (d = L1: the default placement, on the parent body of joint 2 at the joint); max |T_m2| = 13.55 N·m. Every motor
# has its rated torque equal to its peak torque and speeds far above the move's, so the peak torque decides.

L1, L2, M1, M2, G = 0.5, 0.4, 4.0, 3.0, 9.81
J_M = 1e-3
MOTORS = pd.DataFrame([
    {"key": key, "rated_torque": torque, "peak_torque": torque, "rated_speed": 100.0, "max_speed": 200.0,
     "rotor_inertia": J_M, "mass": mass, "price": 100.0 * mass}
    for key, torque, mass in (("W10", 10.0, 1.0), ("W20", 20.0, 2.0), ("S54", 54.0, 3.0), ("S59", 59.0, 4.0),
                              ("S70", 70.0, 5.0))])
NO_GEARBOX = pd.DataFrame()


def two_link(drive2: Drive | None = None, elbow_mass: float = M1) -> mechatron.Mechanism:
    links = (DHLink("revolute", a=L1, name="q1", inertial=Inertial(elbow_mass)),
             DHLink("revolute", a=L2, name="q2", inertial=Inertial(M2), drive=drive2))
    return dh_mechanism(DHTable(links, gravity=np.array([0.0, -G, 0.0])), "two_link")


def swing(mech) -> Trajectory:
    return move(mech, [-0.5, 0.0], [0.5, 0.0], vmax=1.0, amax=2.0, dt=0.005)


def hand_torques(tr: Trajectory, wrist_mass: float, d: float) -> tuple[np.ndarray, np.ndarray]:
    q1, a1 = tr.q[:, 0], tr.a[:, 0]
    tau1 = (M1 * L1**2 + wrist_mass * d**2 + M2 * (L1 + L2) ** 2) * a1 \
        + G * np.cos(q1) * (M1 * L1 + wrist_mass * d + M2 * (L1 + L2))
    tau2 = M2 * L2 * (L1 + L2) * a1 + M2 * G * L2 * np.cos(q1)
    return tau1, tau2


def size_arm(mech, **options):
    return size_mechanism(mech, swing(mech), MOTORS, NO_GEARBOX, inertia_ratio_max=1e4, **options)


def test_the_wrist_drive_s_mass_changes_the_shoulder_s_choice():
    mech = two_link()
    tr = swing(mech)
    weightless, wrist = (np.abs(J_M * tr.a[:, 0] + tau).max() for tau in (hand_torques(tr, 0.0, 0.0)[0],
                                                                          hand_torques(tr, 2.0, L1)[0]))
    assert 51 < weightless < 54 < 59 < wrist < 70  # S54 holds the arm alone, only S70 with the wrist drive on it
    single = size_arm(mech, single_pass=True)
    assert [(j.joint, j.motor) for j in single.joints] == [("q1", "S54"), ("q2", "W20")]
    assert single.method == "single pass" and len(single.iterations) == 1

    result = size_arm(mech)
    q1, q2 = result.joints
    assert (q1.motor, q2.motor) == ("S70", "W20") and result.converged and result.feasible
    # the passes: weightless, then distal to proximal with the drives on the arm, then no change
    assert [i.weighted for i in result.iterations] == [False, True, True]
    assert result.iterations[0].changes == (("q2", None, "W20 + direct"), ("q1", None, "S54 + direct"))
    assert result.iterations[1].changes == (("q1", "S54 + direct", "S70 + direct"),)
    assert result.iterations[2].changes == ()
    # the duties are the hand dynamics with W20's 2 kg at the elbow
    tau1, tau2 = hand_torques(tr, 2.0, L1)
    assert np.allclose(q1.duty.torque, tau1, rtol=1e-9, atol=1e-9)
    assert np.allclose(q2.duty.torque, tau2, rtol=1e-9, atol=1e-9)
    peak = next(c for c in q1.checks if c.name == "peak torque")
    assert peak.value == pytest.approx(wrist, rel=1e-12) and peak.limit == 70.0
    # where each drive sits: the shoulder's on the ground, the wrist's on link 1
    assert result.mounts["q2"].carrier == "link1" and result.mounts["q2"].mass == 2.0
    assert result.mounts["q1"].parent == 0
    # why: the deciding check is the peak torque; the lighter S59 and S54 fail it by max|T_m| / T_peak
    assert q1.deciding().name == "peak torque" and q1.deciding().margin == pytest.approx(1 - wrist / 70)
    runners = q1.runner_up()
    assert [(r["motor"], r["lost_on"]) for r in runners] == [("S59", "check"), ("S54", "check")]
    assert runners[0]["reason"] == f"lighter (4 kg against 5 kg) but fails peak torque ×{wrist / 59:.2f}; " \
                                   f"speed-torque curve ×{wrist / 59:.2f}"
    text = str(result)
    assert "converged in 3 passes" in text and "q1 S54 + direct → S70 + direct" in text
    assert "on link1: 2 kg" in text


def test_the_fixed_point_is_the_model_with_the_chosen_drives():
    """Put the chosen drives into the arm by hand: W20's 2 kg at the elbow (added to link 1's point mass) and each
    rotor as the joint's reflected inertia J_m u² (u = 1). The dynamics' motor torques are the sizing's, and every
    check passes."""
    mech = two_link()
    result = size_arm(mech)
    equipped = two_link(Drive(rotor_inertia=J_M), elbow_mass=M1 + 2.0)
    equipped.drives["q1"] = Drive(rotor_inertia=J_M)
    model = equipped.model
    model.armature[:] = J_M
    tr = swing(mech)
    motors = motor_loads(equipped, tr.v, tr.a, inverse_dynamics(equipped, tr.q, tr.v, tr.a))
    for k, joint in enumerate(result.joints):
        speed, torque = joint.operating_points()
        assert np.allclose(torque, motors.torque[:, k], rtol=1e-9, atol=1e-9)
        assert np.allclose(speed, motors.speed[:, k], rtol=1e-12)
        assert all(c.passed for c in joint.checks)


def test_a_robot_file_places_the_wrist_drive_mid_link(tmp_path):
    """drive.placement = "link1" with offset_mm = [-250, 0, 0]: frame 1 is at the elbow with x1 along link 1, so the
    drive sits 0.25 m from the shoulder: max |T_m1| = 56.47 N·m, S59 is the lightest that holds it."""
    path = tmp_path / "two_link.toml"
    path.write_text(f"""name = "two_link"
gravity = [0.0, -{G}, 0.0]
[[links]]
joint = "revolute"
a = {L1}
mass = {M1}
[[links]]
joint = "revolute"
a = {L2}
mass = {M2}
drive = {{ placement = "link1", offset_mm = [-250, 0, 0] }}
""")
    mech = mechatron.load(path)
    assert mech.drives["q2"].placement == "link1" and mech.drives["q2"].offset == (-0.25, 0.0, 0.0)
    result = size_arm(mech)
    tr = swing(mech)
    tau1, _ = hand_torques(tr, 2.0, 0.25)
    assert np.allclose(result.joints[0].duty.torque, tau1, rtol=1e-9, atol=1e-9)
    assert [j.motor for j in result.joints] == ["S59", "W20"] and result.converged
    # on the base it loads nothing: one pass is the fixed point, the single pass's choice
    path.write_text(path.read_text().replace('placement = "link1", offset_mm = [-250, 0, 0]', 'placement = "base"'))
    grounded = size_arm(mechatron.load(path))
    assert [j.motor for j in grounded.joints] == ["S54", "W20"] and len(grounded.iterations) == 1
    assert "every drive sits on a fixed body" in str(grounded)


def test_a_choice_that_cycles_is_reported():
    """A choice that comes back. The shoulder's drive rides at the tip (placement "link2": it loads both joints),
    the wrist's at the elbow; the objective is cost. With m_e at the elbow and m_t at the tip the hand formulas
    (m_e = 4 kg + the wrist drive, m_t = 3 kg + the shoulder drive) give the peak motor torques

        drives weightless (4, 3 kg):      |T1| = 51.48, |T2| = 13.55 N·m → wrist Wa (20 N·m), shoulder Sh (100 N·m);
        Wa 1 kg, Sh 8 kg (5, 11 kg):                     |T2| = 49.69 → wrist Wb (50.5 N·m, 6 kg);
        Wb 6 kg, Sh 8 kg (10, 11 kg):     |T1| = 164.27           → shoulder Sl (170 N·m, 1 kg);
        Sl 1 kg (4 kg at the tip):                       |T2| = 18.07 → wrist Wa;
        Wa 1 kg, Sl 1 kg (5, 4 kg):       |T1| = 66.89            → shoulder Sh, the cheapest that holds it:

    pass 3 chooses what pass 1 chose, so pass 4 would repeat pass 2: a cycle; the sizing stops and the design is
    not feasible."""
    motors = pd.DataFrame([
        {"key": key, "rated_torque": torque, "peak_torque": torque, "rated_speed": 100.0, "max_speed": 200.0,
         "rotor_inertia": J_M, "mass": mass, "price": price}
        for key, torque, mass, price in (("Wa", 20.0, 1.0, 100.0), ("Wb", 50.5, 6.0, 200.0),
                                         ("Sh", 100.0, 8.0, 300.0), ("Sl", 170.0, 1.0, 900.0))])
    mech = two_link()
    mech.drives["q1"] = Drive(placement="link2")
    tr = swing(mech)

    def peaks(elbow, tip):
        q1, a1 = tr.q[:, 0], tr.a[:, 0]
        tau1 = (elbow * L1**2 + tip * (L1 + L2) ** 2) * a1 + G * np.cos(q1) * (elbow * L1 + tip * (L1 + L2))
        tau2 = tip * L2 * (L1 + L2) * a1 + tip * G * L2 * np.cos(q1)
        return np.abs(tau1 + J_M * a1).max(), np.abs(tau2 + J_M * a1).max()

    assert peaks(4, 3)[0] < 100 and peaks(4, 3)[1] < 20 < 50.5 < peaks(4, 3)[0]
    assert 20 < peaks(5, 11)[1] < 50.5 and 100 < peaks(10, 11)[0] < 170
    assert peaks(5, 4)[1] < 20 and 50.5 < peaks(5, 4)[0] < 100
    result = size_mechanism(mech, tr, motors, NO_GEARBOX, objective="cost", inertia_ratio_max=1e6)
    assert [i.changes for i in result.iterations] == [
        (("q2", None, "Wa + direct"), ("q1", None, "Sh + direct")),
        (("q2", "Wa + direct", "Wb + direct"), ("q1", "Sh + direct", "Sl + direct")),
        (("q2", "Wb + direct", "Wa + direct"), ("q1", "Sl + direct", "Sh + direct"))]
    assert not result.converged and result.cycle == (1, 3) and not result.feasible
    assert all(j.feasible for j in result.joints)  # each drive passes for the others of the pass before
    text = str(result)
    assert "NOT CONVERGED: the choice of pass 3 repeats that of pass 1: it cycles" in text
    assert text.rstrip().endswith("NOT FEASIBLE: the choice of drives did not settle (see the method above)")
    assert result.as_dict()["cycle"] == [1, 3] and result.as_dict()["feasible"] is False
    capped = size_mechanism(mech, tr, motors, NO_GEARBOX, objective="cost", inertia_ratio_max=1e6, max_iterations=2)
    assert len(capped.iterations) == 2 and not capped.converged and capped.cycle == ()
    assert "the choice still changed after 2 passes" in str(capped)
    with pytest.raises(InputError, match="whole number >= 2"):
        size_mechanism(mech, tr, motors, NO_GEARBOX, max_iterations=1)


# ------------------------------------------------------------------------------------------------- the PUMA
# The default task carries a 2.5 kg steel block (100 × 60 × 55 mm, its centre 50 mm out on joint 6's axis):
# I_zz = m (a² + b²)/12 = 2.5 (0.1² + 0.06²)/12 kg·m² about that axis. Link 6's own I_zz is 4.0e-5 kg·m² with its
# centre on the axis, so joint 6 carries J = 4.0e-5 + 2.8333e-3 kg·m² at every pose.
PART_ZZ = 2.5 * (0.100**2 + 0.060**2) / 12
PART_INERTIA = np.diag([2.5 * (0.060**2 + 0.055**2) / 12, 2.5 * (0.100**2 + 0.055**2) / 12, PART_ZZ])


@pytest.fixture(scope="module")
def puma():
    mech = mechatron.load("puma560")
    task = default_task(mech)
    return mech, task, mechatron.size(mech, task)


def test_the_puma_task_carries_the_part_s_inertia(puma):
    _, task, result = puma
    q6 = next(j for j in result.joints if j.joint == "q6")
    assert q6.duty.load_inertia == pytest.approx(4.0e-5 + PART_ZZ, rel=1e-12)
    # the part's inertia through the gearbox: (J/u² + J_c)/J_m
    ratio = next(c for c in q6.checks if c.name == "inertia ratio")
    reflected = (4.0e-5 + PART_ZZ) / q6.ratio**2 + q6.converter_data["inertia"]
    assert ratio.value == pytest.approx(reflected / q6.motor_data["rotor_inertia"], rel=1e-12)
    # a direct drive lighter than the chosen drive cannot hold the part's inertia: J/J_m > 10
    motors = default_catalog("motors")
    lighter = motors[motors["mass"] < q6.drive_mass()]
    assert q6.converter != "direct" and len(lighter)
    assert ((4.0e-5 + PART_ZZ) / lighter["rotor_inertia"] > 10).all()


def test_no_wrist_drive_is_heavier_than_what_it_moves(puma):
    mech, _, result = puma
    mass = {link.name: link.inertial.mass for link in mech.dh.links}
    drives = {j.joint: j for j in result.joints}
    catalogs = default_catalog("motors").set_index("key"), default_catalog("gearboxes").set_index("key")
    for k, joint in ((4, "q4"), (5, "q5"), (6, "q6")):
        moved = sum(mass[f"q{i}"] for i in range(k, 7)) + 2.5  # its links and the part
        d = drives[joint]
        by_catalog = catalogs[0].loc[d.motor, "mass"] + (catalogs[1].loc[d.converter, "mass"]
                                                         if d.converter != "direct" else 0.0)
        assert d.drive_mass() == pytest.approx(by_catalog, rel=1e-12) and by_catalog < moved


def test_the_puma_fixed_point_is_the_arm_with_its_drives(puma):
    """Every chosen motor and gearbox put into the PUMA by hand — drive data (J_m + J_c, u, η) on the DH rows,
    each drive's catalog mass a point mass on the parent link at its joint's origin — gives the sizing's motor
    torques (1e-9) through the dynamics' own motor model, with the file's drive friction at the joints (issue 25),
    and every check passes."""
    mech, task, result = puma
    assert result.converged and result.feasible and result.method == "fixed point"
    assert len(result.iterations) >= 2 and result.iterations[-1].changes == ()
    drives = {j.joint: j for j in result.joints}
    links = tuple(replace(link, drive=Drive(
        rotor_inertia=drives[link.name].motor_data["rotor_inertia"] + drives[link.name].converter_data["inertia"],
        gear_ratio=drives[link.name].ratio, efficiency=drives[link.name].converter_data["efficiency"]))
        for link in mech.dh.links)
    geared = with_payload(dh_mechanism(replace(mech.dh, links=links), "puma_geared"), 2.5, com=(0.0, 0.0, 0.05),
                          inertia=PART_INERTIA)
    model = geared.model
    for i in range(2, 7):  # the drive of joint i on link i−1, at joint i's origin
        drive = drives[f"q{i}"]
        model.appendBodyToJoint(i - 1, pin.Inertia(drive.drive_mass(), np.zeros(3), np.zeros((3, 3))),
                                model.jointPlacements[i])
    geared = replace(geared, model=model)
    tr = task.trajectory
    motors = motor_loads(geared, tr.v, tr.a, inverse_dynamics(geared, tr.q, tr.v, tr.a, task.loads)
                         + file_friction_at_joints(mech.dh, tr.v))
    for k, joint in enumerate(result.joints):
        speed, torque = joint.operating_points()
        assert np.allclose(torque, motors.torque[:, k], rtol=1e-9, atol=1e-12), joint.joint
        assert all(c.passed for c in joint.checks)
    # the single pass leaves the drives weightless: its duties are those of the bare arm
    bare = joint_duties(task.mechanism, tr)
    single = mechatron.size(mech, task, single_pass=True)
    assert all(np.array_equal(j.duty.torque, d.torque) for j, d in zip(single.joints, bare))
    assert "method: single pass" in str(single)


# ------------------------------------------------------------------------------------------- the time objective
def test_the_time_objective_keeps_every_dwell(puma):
    """The PUMA's cycle has six moves each followed by a 0.2 s rest. Replayed at the fastest pace, every rest
    (consecutive samples at rest at the same place) lasts as long as before (1e-12 s) and every move k times as
    long."""
    mech, task, _ = puma
    result = mechatron.size(mech, task, objective="time", single_pass=True)
    k = result.time_scale
    assert 0.02 < k < 1
    before, after = task.trajectory.t, result.joints[0].duty.t
    assert all(np.array_equal(j.duty.t, after) for j in result.joints)
    speed = np.column_stack([j.duty.speed for j in result.joints])
    rest = np.all(speed == 0, axis=1)
    still = rest[:-1] & rest[1:] & np.all(np.diff(task.trajectory.q, axis=0) == 0, axis=1)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], still.astype(int), [0]])))
    runs = list(zip(edges[::2], edges[1::2]))  # [start, end) of every run of resting intervals
    assert len(runs) == 6
    for start, end in runs:
        assert after[end] - after[start] == pytest.approx(before[end] - before[start], abs=1e-12)
        assert before[end] - before[start] == pytest.approx(0.2, abs=1e-12)
    moves = [(0, runs[0][0])] + [(runs[i][1], runs[i + 1][0]) for i in range(5)]
    for start, end in moves:
        assert after[end] - after[start] == pytest.approx(k * (before[end] - before[start]), rel=1e-9)
    assert result.duration == pytest.approx(k * (task.duration - 1.2) + 1.2, rel=1e-12)
    assert task.dwells == [(before[start], before[end]) for start, end in runs]  # the task knows its dwells


def test_size_time_json_keeps_the_dwells(capsys):
    """planar_2r's generic task: out, 0.2 s rest, back, 0.2 s rest."""
    task = default_task(mechatron.load("planar_2r"))
    code = main(["size", "planar_2r", "--objective", "time", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["objective"] == "time"
    k = data["time_scale"]
    assert data["task_time"] == pytest.approx(k * (task.duration - 0.4) + 0.4, rel=1e-12)
    assert data["totals"]["cycle_time_s"] == data["task_time"]


# ------------------------------------------------------------------------------------------------ totals
def test_totals_against_a_hand_calculation():
    """A disc of 0.5 kg·m² on a vertical axis turns 2 rad (trapezoid 2 rad/s, 10 rad/s²) through a gearbox of
    u = 50, η = 0.9, J_c = 2e-5 kg·m² from a motor of J_m = 1e-4 kg·m². Accelerating (0.2 s) the motor gives
    T_m = (J_m + J_c) u ω̇ + τ/(u η) = 0.06 + 5/45 N·m at n = 500 t rad/s, so its energy is
    ½ T_m n_max t_a = ½ · 0.171111 · 100 · 0.2 J and its peak power T_m · 100 W; cruising needs nothing. Braking
    (0.2 s) the load drives the gearbox back, T_m = −(J_m + J_c) u · 10 − 5 η / u = −0.06 − 0.09 N·m, so the motor
    regenerates ½ · 0.15 · 100 · 0.2 = 1.5 J, at most 15 W, 1.5 J / 1.2 s on average (the catalog gives no k_t or
    R: the shaft power alone). Mass and price: motor 1 kg + gearbox 1.5 kg, 100 + 250."""
    motor = pd.DataFrame([{"key": "M", "rated_torque": 0.1, "peak_torque": 0.3, "rated_speed": 300.0,
                           "max_speed": 500.0, "rotor_inertia": 1e-4, "mass": 1.0, "price": 100.0}])
    gearbox = pd.DataFrame([{"key": "G50", "type": "planetary", "ratio": 50.0, "rated_torque": 5.0,
                             "peak_torque": 10.0, "emergency_torque": 20.0, "max_input_speed": 600.0,
                             "rated_input_speed": 400.0, "efficiency": 0.9, "input_inertia": 2e-5, "mass": 1.5,
                             "price": 250.0}])
    link = DHLink("revolute", name="q1", inertial=Inertial(0.0, np.zeros(3), np.diag([0.25, 0.25, 0.5])))
    disc = dh_mechanism(DHTable((link,)), "disc")
    result = size_mechanism(disc, move(disc, [0.0], [2.0], vmax=2.0, amax=10.0, dt=1e-4), motor, gearbox,
                            direct=False)
    torque = 0.06 + 5 / 45
    totals = result.totals()
    assert totals["drive_mass_kg"] == 2.5 and totals["drive_cost"] == 350.0
    assert totals["energy_per_cycle_J"] == pytest.approx(0.5 * torque * 100 * 0.2, rel=1e-3)
    assert totals["peak_bus_power_W"] == pytest.approx(torque * 100, rel=1e-3)
    assert totals["regenerated_energy_J"] == pytest.approx(1.5, rel=1e-3)
    assert totals["braking_resistor_peak_W"] == pytest.approx(15.0, rel=1e-3)
    assert totals["braking_resistor_continuous_W"] == pytest.approx(1.5 / 1.2, rel=1e-3)
    assert totals["peak_pump_power_W"] is None and totals["peak_pump_flow_m3_s"] is None
    assert totals["cycle_time_s"] == pytest.approx(1.2, rel=1e-12)
    assert result.as_dict()["totals"] == pytest.approx(totals)


def test_size_json_explains_every_joint(capsys):
    code = main(["size", "puma560", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["method"] == "fixed point" and data["converged"] is True
    assert [i["iteration"] for i in data["iterations"]] == list(range(1, len(data["iterations"]) + 1))
    assert data["iterations"][0]["drive_masses"] is False and data["iterations"][-1]["changes"] == []
    masses = []
    for j in data["joints"]:
        deciding = j["deciding_check"]
        assert deciding["margin"] == min(c["margin"] for c in j["checks"])
        assert deciding in j["checks"]
        assert j["runner_up"] and all(r["lost_on"] in ("check", "objective") and r["reason"] for r in j["runner_up"])
        assert j["drive_mass_kg"] > 0 and j["mounted_on"]["mass_kg"] == j["drive_mass_kg"]
        masses.append(j["drive_mass_kg"])
    assert data["joints"][0]["mounted_on"] == {"body": "the ground", "mass_kg": masses[0],
                                               "loads_the_mechanism": False}
    assert data["joints"][5]["mounted_on"]["body"] == "link5"
    assert data["totals"]["drive_mass_kg"] == pytest.approx(sum(masses), rel=1e-12)
    assert set(data["totals"]) == {"drive_mass_kg", "drive_cost", "energy_per_cycle_J", "peak_bus_power_W",
                                   "regenerated_energy_J", "braking_resistor_peak_W", "braking_resistor_continuous_W",
                                   "peak_pump_power_W", "peak_pump_flow_m3_s", "cycle_time_s"}
    bus = data["electrical"]["bus"]
    assert data["totals"]["energy_per_cycle_J"] == bus["energy_drawn"] and data["hydraulics"] is None
    assert data["totals"]["regenerated_energy_J"] == bus["energy_regenerated"]


# ----------------------------------------------------------------------------------------- a closed loop
FOUR_BAR_DRIVE = """
[[drives]]                     # the crank's motor rides on the rocker, at C
coordinate = "q1"
at = "C"
body = "rocker"
"""


def test_a_mechanism_file_places_a_motor_on_a_moving_body(tmp_path):
    """The four-bar's crank motor placed on the rocker at C (a [[drives]] table): a 2 kg motor there adds
    m g ∂y_C/∂q1 to the crank's holding torque (virtual work; ∂y_C/∂q1 by central differences of the assembled
    positions). The crank's own joint sees it: pass 2 sizes with it, pass 3 finds the same motor."""
    path = tmp_path / "four_bar.toml"
    path.write_text(FOUR_BAR.read_text() + FOUR_BAR_DRIVE)
    mech = mechatron.load(path)
    assert mech.drives["q1"].placement == "C@rocker"  # C's frame on its second body
    task_file = tmp_path / "turn.toml"
    task_file.write_text("waypoints = [[1.0], [2.0]]\nvmax = 2\namax = 10\n")
    task = read_task(task_file, mech)
    motor = MOTORS.iloc[[4]].assign(mass=2.0).reset_index(drop=True)
    result = size_mechanism(mech, task.trajectory, motor, NO_GEARBOX, inertia_ratio_max=1e6)
    (crank,) = result.joints
    assert result.converged and result.mounts["q1"].carrier == "C@rocker" and result.mounts["q1"].parent > 0
    added = crank.duty.static_torque - joint_duties(mech, task.trajectory)[0].static_torque
    h = 1e-6
    for i in np.linspace(0, len(task.trajectory) - 1, 7).astype(int):
        q1 = task.trajectory.q[i, 0]
        y = [mechatron.frame_placement(mech, mechatron.assemble(mech, {"q1": q1 + s}), "C").translation[1]
             for s in (h, -h)]
        assert added[i] == pytest.approx(2.0 * 9.81 * (y[0] - y[1]) / (2 * h), rel=1e-6)


# ------------------------------------------------------------------------------------------------ bad input
def test_a_drive_placed_on_an_unknown_body(tmp_path, capsys):
    robot = tmp_path / "arm.toml"
    robot.write_text('[[links]]\njoint = "revolute"\na = 0.5\nmass = 1\n'
                     '[[links]]\njoint = "revolute"\na = 0.4\nmass = 1\ndrive = { placement = "hand" }\n')
    with pytest.raises(InputError, match="unknown body 'hand'") as info:
        mechatron.load(robot)
    assert info.value.file == str(robot) and info.value.field == "links[2].drive.placement"
    code = main(["size", str(robot)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "links[2].drive.placement" in err
    linkage = tmp_path / "four_bar.toml"
    linkage.write_text(FOUR_BAR.read_text() + FOUR_BAR_DRIVE.replace('"rocker"', '"arm"'))
    with pytest.raises(InputError, match="unknown body 'arm'") as info:
        mechatron.load(linkage)
    assert info.value.file == str(linkage) and info.value.field == "drives[1].body"
    for text, field, message in (('coordinate = "q3"\nat = "C"', "drives[1].coordinate", "not an actuated"),
                                 ('coordinate = "q1"\nat = "Z"', "drives[1].at", "unknown point"),
                                 ('coordinate = "q1"\nat = "A"\nbody = "rocker"', "drives[1].at",
                                  "not a point of body rocker")):
        linkage.write_text(FOUR_BAR.read_text() + "\n[[drives]]\n" + text + "\n")
        with pytest.raises(InputError, match=message) as info:
            mechatron.load(linkage)
        assert info.value.field == field


@pytest.mark.parametrize("value, message", [
    ("[-1e-3, 2e-3, 2e-3]", "Ixx must be >= 0"),
    ("[1e-3, nan, 2e-3]", "expected a finite number"),
    ("[1e-3, 2e-3, inf]", "expected a finite number"),
    ("[1e-3, 2e-3]", "give 3 numbers"),
    ("[1e-3, 1e-3, 3e-3]", "triangle inequality"),
    ("[2e-3, 2e-3, 2e-3, 3e-3, 0, 0]", "positive definite"),
    ('"big"', "give 3 numbers"),
])
def test_a_bad_payload_inertia(tmp_path, capsys, value, message):
    path = tmp_path / "task.toml"
    path.write_text(f"payload = 2.5\npayload_inertia = {value}\nwaypoints = [[0, 0], [0.5, 0.5]]\n")
    with pytest.raises(InputError, match=message) as info:
        read_task(path, mechatron.load("planar_2r"))
    assert info.value.file == str(path) and info.value.field == "payload_inertia"
    code = main(["size", "planar_2r", "--task", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "payload_inertia" in err


def test_payload_inertia_without_mass_and_with_six_numbers(tmp_path):
    path = tmp_path / "task.toml"
    path.write_text("payload_inertia = [1e-3, 1e-3, 1e-3]\nwaypoints = [[0, 0], [0.5, 0.5]]\n")
    with pytest.raises(InputError, match="without mass") as info:
        read_task(path, mechatron.load("planar_2r"))
    assert info.value.field == "payload_inertia"
    # six numbers: the products of inertia, tool axes; the tensor reaches the model as given
    path.write_text("payload = 2\npayload_inertia = [3e-3, 4e-3, 5e-3, 1e-3, -5e-4, 2e-4]\n"
                    "waypoints = [[0, 0], [0.5, 0.5]]\n")
    arm = mechatron.load("planar_2r")
    task = read_task(path, arm)
    tensor = np.array([[3e-3, 1e-3, -5e-4], [1e-3, 4e-3, 2e-4], [-5e-4, 2e-4, 5e-3]])
    expected = with_payload(arm, 2.0, inertia=tensor)
    assert np.allclose(task.mechanism.model.inertias[2].inertia, expected.model.inertias[2].inertia, rtol=1e-15)
    assert not np.allclose(task.mechanism.model.inertias[2].inertia, with_payload(arm, 2.0).model.inertias[2].inertia)

"""Holding brakes (mechatron.drives.brakes): which joints need one, the checks, bad catalogs."""

import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.drives.brakes import BrakeData, brake_table, holding_torque
from mechatron.drives.catalogs import default_catalog, read_catalog
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import JointDuty, joint_duties
from mechatron.dynamics.task import read_task
from mechatron.errors import InputError


@pytest.fixture(scope="module")
def puma_duties():
    puma = mechatron.load("puma560")
    task = read_task("robots/tasks/puma560.toml", puma)
    return task, {d.name: d for d in joint_duties(task.mechanism, task.trajectory)}


def test_puma_q2_q3_need_brakes_q6_none(puma_duties):
    task, duties = puma_duties
    mech = task.mechanism
    q0 = task.trajectory.q[0]
    # the gravity torque at the first rest pose, from Pinocchio's own generalized gravity (not the duty's code)
    gravity = pin.computeGeneralizedGravity(mech.model, mech.model.createData(), q0)
    for name in ("q2", "q3"):
        assert holding_torque(duties[name]) >= abs(gravity[mech.joint_id(name) - 1]) * (1 - 1e-9) > 1.0
    # q6 turns about the flange axis through the payload's centre: gravity has no moment about it
    assert holding_torque(duties["q6"]) == 0.0


def pendulum_duty(mass=2.0, length=0.5, speed=3.0):
    """A point mass m on a massless link of length L, horizontal at rest (gravity torque m g L), and swinging at
    most at ``speed``: J_L = m L²."""
    t = np.linspace(0.0, 1.0, 11)
    w = speed * np.sin(np.pi * t)
    tau = np.full_like(t, mass * 9.81 * length)
    return JointDuty("q1", "revolute", t, w, np.gradient(w, t), tau, tau, mass * length**2, 1.0)


def test_emergency_stop_energy_by_hand():
    """E = E_k T_h/(T_h − T_g), E_k = ½ (J_m + J_b) (u ω)² + ½ J_L ω², T_g = m g L / u (direct drive u = 1)."""
    duty = pendulum_duty()
    m, g, L, w = 2.0, 9.81, 0.5, 3.0
    conv = converters_for(duty, None, None, True, 1.0)
    direct = int(np.flatnonzero(conv.ratio == 1.0)[0])
    brakes = BrakeData(*(np.array([x]) for x in (30.0, 1e-4, 0.5, 100.0, 1000.0)), hold=m * g * L)
    rotor = np.array([1e-3 + 1e-4])
    values, limits = brake_table(duty, brakes, rotor, conv, np.array([0]), np.array([direct]), 2.0, 3.0)
    kinetic = 0.5 * (1.1e-3 + m * L**2) * w**2
    t_g = m * g * L
    assert values[0, 0] == pytest.approx(2 * t_g, rel=1e-12)
    assert values[0, 1] == pytest.approx(kinetic * 30.0 / (30.0 - t_g), rel=1e-12)
    assert values[0, 2] == pytest.approx(3 * kinetic * 30.0 / (30.0 - t_g), rel=1e-12)
    assert list(limits[0]) == [30.0, 100.0, 1000.0]


def braked_catalog():
    cat = default_catalog("motors")
    cat["brake_holding_torque"] = cat["rated_torque"] * 1.2
    cat["brake_inertia"] = cat["rotor_inertia"] * 0.1
    cat["brake_mass"] = 0.3
    cat["brake_stop_energy"] = 50.0
    return cat


def test_puma_sizing_with_brakes():
    puma = mechatron.load("puma560")
    plain = mechatron.size(puma)
    cat = braked_catalog()
    braked = mechatron.size(puma, motors=cat)
    by = {j.joint: j for j in braked.joints}
    for name in ("q2", "q3"):
        names = [c.name for c in by[name].checks]
        assert "brake holding torque" in names and "brake stop energy" in names
        assert all(c.passed for c in by[name].checks)
        k = int(np.flatnonzero(cat["key"] == by[name].motor)[0])  # the brake's mass and inertia are counted
        assert by[name].motor_number("mass") == pytest.approx(cat["mass"][k] + 0.3)
        assert by[name].motor_number("rotor_inertia") == pytest.approx(cat["rotor_inertia"][k] * 1.1)
    assert not any(c.name.startswith("brake") for c in by["q6"].checks)
    # a catalog without brake columns: exactly today's sizing
    assert [j.motor for j in plain.joints] == [j.motor for j in mechatron.size(puma).joints]


@pytest.mark.parametrize("cells, message", [
    (("", "0.1", ""), "brake_holding_torque"), (("nan", "", ""), "not a finite number"),
    (("-1", "", ""), "> 0"), (("1", "", "-2"), ">= 0")])
def test_bad_brake_columns(tmp_path, cells, message):
    path = tmp_path / "motors.csv"
    source = [x for x in open("catalogs/servo_motors.csv").read().splitlines() if not x.startswith("#")]
    lines = [source[0] + ",brake_holding_torque_Nm,brake_mass_kg,brake_inertia_kgcm2"]
    lines += [source[1] + "," + ",".join(cells)] + [row + ",,," for row in source[2:4]]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as error:
        read_catalog(path, "motors")
    text = str(error.value)
    assert str(path) in text and "row 2" in text and message in text
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--motors", str(path)],
                         capture_output=True, text=True)
    assert cli.returncode == 2 and message in cli.stderr and len(cli.stderr.strip().splitlines()) == 1

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


def unbraked_catalog(tmp_path):
    """The shipped motor catalog with an empty brake_holding_torque column: brake columns, but no motor has one."""
    path = tmp_path / "no_brakes.csv"
    source = [x for x in open("catalogs/servo_motors.csv").read().splitlines() if not x.startswith("#")]
    path.write_text("\n".join([source[0] + ",brake_holding_torque_Nm"] + [row + "," for row in source[1:]]) + "\n")
    return path


@pytest.mark.parametrize("stop_energy", [None, 50.0])
def test_no_motor_has_a_brake(stop_energy):
    """A joint held against gravity at rest (m g L = 9.81 N·m) and a catalog with brake columns but no brake: an
    infeasible joint whose closest pairs fail the holding torque as "no brake", never an error; the stop energy
    is not checked for a motor that has no brake (there is nothing to take the energy)."""
    from mechatron.drives.joint import size_joint

    cat = default_catalog("motors")
    cat["brake_holding_torque"] = np.nan
    if stop_energy is not None:
        cat["brake_stop_energy"] = stop_energy
    result = size_joint(pendulum_duty(), cat)
    assert not result.feasible and len(result.closest)
    assert all("brake holding torque: no brake" in reason for reason in result.closest["failed"])
    assert not any("brake stop energy" in reason for reason in result.closest["failed"])
    names = [c.name for c in result.checks if not c.passed]
    assert "brake holding torque" in names and "brake stop energy" not in names


def test_a_brake_too_weak_to_stop():
    """T_h = 1e-3 N·m ≤ T_g on every pair: the stop energy is infinite, said in words, not "a limit of 0"."""
    from mechatron.drives.joint import size_joint

    cat = default_catalog("motors")
    cat["brake_holding_torque"], cat["brake_stop_energy"] = 1e-3, 50.0
    result = size_joint(pendulum_duty(), cat)
    assert not result.feasible
    reason = result.closest["failed"].iloc[0]
    assert "brake stop energy: the brake cannot stop the axis" in reason and "a limit of 0" not in reason


def test_no_brake_through_the_cli(tmp_path):
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--motors",
                          str(unbraked_catalog(tmp_path))], capture_output=True, text=True)
    assert cli.returncode == 1 and "Traceback" not in cli.stderr
    assert "NO FEASIBLE DRIVE" in cli.stdout and "no feasible" in (cli.stdout + cli.stderr).lower()
    for joint in ("q2", "q3"):  # the joints the PUMA holds against gravity
        block = cli.stdout.split(f"\n{joint}: ")[1].split("\nq")[0]
        assert "NO FEASIBLE DRIVE" in block.splitlines()[0] and "brake holding torque: no brake" in block
    assert "NO FEASIBLE" not in cli.stdout.split("\nq6: ")[1].split("\nq")[0].splitlines()[0]

"""Leftovers of the holding brakes (issue 35): how the closest candidates of a joint that no braked motor can drive
are ranked, and the brake's inertia in the ``time`` objective.

References: a catalog whose brake_holding_torque column is empty is the plain catalog plus a brake check that every
motor fails (J_b = m_b = 0), so "ranked as if each had a brake" is the plain catalog's own sizing; the fastest pace
of a direct drive on a bang-bang move with a constant gravity torque is a closed form.
"""

import math

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import JointDuty
from mechatron.drives.joint import size_joint
from mechatron.drives.search import fastest_scale, motor_passes

NO_BRAKE = "brake holding torque: no brake"


def held_duty(mass=2.0, length=0.5, speed=3.0):
    """A point mass m at the end of a massless link of length L, the link horizontal at rest (τ_g = m g L), swinging
    at most at ``speed`` rad/s: J_L = m L², τ = J_L ω̇ + τ_g."""
    t = np.linspace(0.0, 1.0, 41)
    w = speed * np.sin(np.pi * t) ** 2
    a = 2 * np.pi * speed * np.sin(np.pi * t) * np.cos(np.pi * t)
    inertia, gravity = mass * length**2, mass * 9.81 * length
    return JointDuty("q1", "revolute", t, w, a, inertia * a + gravity, np.full_like(t, gravity), inertia, 1.0)


def without_brakes(catalog: pd.DataFrame) -> pd.DataFrame:
    out = catalog.copy()
    out["brake_holding_torque"] = np.nan
    return out


def test_closest_without_any_brake_are_the_plain_ranking():
    """No motor has a brake: the closest pairs are exactly those the plain catalog's sizing ranks first (the pairs
    that would be chosen with a brake), each failing the brake alone, and the report says so in words."""
    duty, motors, gearboxes = held_duty(), default_catalog("motors"), default_catalog("gearboxes")
    plain = size_joint(duty, motors, gearboxes)
    unbraked = size_joint(duty, without_brakes(motors), gearboxes)
    assert plain.feasible and not unbraked.feasible
    expected = plain.ranking[["motor", "converter"]].head(5)
    assert unbraked.closest[["motor", "converter"]].reset_index(drop=True).equals(expected.reset_index(drop=True))
    assert (unbraked.motor, unbraked.converter) == (plain.motor, plain.converter)
    assert all(reason.startswith(NO_BRAKE) and ";" not in reason for reason in unbraked.closest["failed"])
    note = unbraked.brake_note
    assert note.startswith("no motor of the catalog has a brake") and f"{2 * 9.81 * 0.5:.4g} N·m" in note
    text = str(unbraked)
    assert note in text and "margin no brake" in text and "e+" not in text and "%  FAIL" not in \
        next(line for line in text.splitlines() if line.strip().startswith("brake holding torque"))
    assert unbraked.as_dict()["brake_note"] == note and plain.as_dict()["brake_note"] == ""


def test_closest_with_some_brakes():
    """The lighter half of the motors lack a brake, the heavier half have one too weak to hold (T_h < 2 τ_g / u η
    on every pair): the closest pairs are first the brakeless pairs that pass every other check, lightest first —
    the plain sizing of the brakeless motors alone —, and the note names those without a brake."""
    duty, motors, gearboxes = held_duty(), default_catalog("motors"), default_catalog("gearboxes")
    order = np.argsort(motors["mass"].to_numpy(), kind="stable")
    light = motors.index[order[: len(motors) // 2]]
    mixed = motors.copy()
    mixed["brake_holding_torque"] = 1e-6
    mixed.loc[light, "brake_holding_torque"] = np.nan
    sized = size_joint(duty, mixed, gearboxes)
    assert not sized.feasible
    alone = size_joint(duty, motors.loc[light].reset_index(drop=True), gearboxes)
    assert alone.feasible
    would = alone.ranking[["motor", "converter"]].head(5).reset_index(drop=True)
    assert sized.closest[["motor", "converter"]].head(len(would)).reset_index(drop=True).equals(would)
    lacking = set(sized.closest["motor"]) & set(motors.loc[light, "key"])
    assert lacking and all(key in sized.brake_note for key in lacking)
    assert f"for {len(motors) - len(light)} of its {len(motors)} motors" in sized.brake_note


def test_system_without_brakes_closest_as_plain():
    """The PUMA with a catalog of no brakes (issue 35's case): every joint gets the plain sizing's drive, the joints
    held against gravity as their closest candidate (the drive masses on the links are then the same too)."""
    puma = mechatron.load("puma560")
    plain = mechatron.size(puma)
    unbraked = mechatron.size(puma, motors=without_brakes(default_catalog("motors")))
    assert [(j.motor, j.converter) for j in unbraked.joints] == [(j.motor, j.converter) for j in plain.joints]
    by = {j.joint: j for j in unbraked.joints}
    assert not by["q2"].feasible and not by["q3"].feasible and by["q6"].feasible
    assert by["q2"].brake_note.startswith("no motor of the catalog has a brake")


def one_motor(peak: float, rotor: float, brake_inertia: float, holding: float) -> pd.DataFrame:
    """One motor whose peak torque alone can decide a slow move (rated torque = peak, speeds far above the task's)."""
    return pd.DataFrame({"key": ["M"], "rated_torque": [peak], "peak_torque": [peak], "rated_speed": [1e4],
                         "max_speed": [2e4], "rotor_inertia": [rotor], "mass": [1.0], "price": [1.0],
                         "brake_holding_torque": [holding], "brake_inertia": [brake_inertia], "brake_mass": [0.2]})


def bang_bang(inertia=5e-3, gravity=2.0, accel=10.0):
    """±``accel`` rad/s² over a 1 s move, τ = J_L ω̇ + τ_g: the largest motor torque of a direct drive (u = η = 1)
    at the pace k is (J_m + J_b + J_L) a / k² + τ_g."""
    t = np.linspace(0.0, 1.0, 40)  # no sample at the switch
    a = np.where(t < 0.5, accel, -accel)
    w = np.where(t < 0.5, accel * t, accel * (1.0 - t))
    return JointDuty("q1", "revolute", t, w, a, inertia * a + gravity, np.full_like(t, gravity), inertia, 1.0)


@pytest.mark.parametrize("brake_inertia", [0.0, 1e-3, 4e-3])
def test_time_objective_counts_the_brake_inertia(brake_inertia):
    """The fastest pace k* = √((J_m + J_b + J_L) a / (T_p − τ_g)): found by the joint's sizing and by the search the
    system sizing paces the task with (the raw catalog given, as there); at it the peak torque is
    (J_m + J_b + J_L) a / k² + τ_g and the inertia ratio J_L / (J_m + J_b)."""
    rotor, load, gravity, accel, peak = 1e-3, 5e-3, 2.0, 10.0, 4.0
    duty, motors = bang_bang(load, gravity, accel), one_motor(peak, rotor, brake_inertia, 10.0)
    conv = converters_for(duty, None, None, True, 1.0)
    total = rotor + brake_inertia + load
    k_star = math.sqrt(total * accel / (peak - gravity))
    paced = fastest_scale(motor_passes(duty, motors, conv, 10.0))  # the system's call (mechatron.drives.system)
    assert k_star * (1 - 1e-9) <= paced <= k_star * (1 + 2e-3)
    sized = size_joint(duty, motors, objective="time")
    assert sized.feasible and k_star * (1 - 1e-9) <= sized.time_scale <= k_star * (1 + 2e-3)
    checks = {c.name: c for c in sized.checks}
    k = sized.time_scale
    assert checks["peak torque"].value == pytest.approx(total * accel / k**2 + gravity, rel=1e-12)
    assert checks["inertia ratio"].value == pytest.approx(load / (rotor + brake_inertia), rel=1e-12)
    assert checks["brake holding torque"].value == pytest.approx(2 * gravity, rel=1e-12)
    torque = sized.operating_points()[1]  # the acceleration torque (J_m + J_b) a / k² in the chart's points
    assert torque.max() == pytest.approx(total * accel / k**2 + gravity, rel=1e-12)


def test_system_time_pace_counts_the_brake():
    """``size(objective="time")`` of a robot whose held joints' motors carry a heavy brake (J_b = 3 J_m): the pace
    is the slowest joint's fastest pace with the brakes (each joint sized alone at its final duty by the joint's own
    search, which adds J_b) and every joint is feasible at it."""
    puma = mechatron.load("puma560")
    cat = default_catalog("motors")
    cat["brake_holding_torque"] = cat["peak_torque"] * 3
    cat["brake_inertia"] = cat["rotor_inertia"] * 3
    result = mechatron.size(puma, motors=cat, objective="time", single_pass=True)
    assert all(j.feasible for j in result.joints)
    gearboxes = default_catalog("gearboxes")
    base = {j.joint: j.duty.scaled(1 / result.time_scale) for j in result.joints}
    alone = [size_joint(d, cat, gearboxes, objective="time").time_scale for d in base.values()]
    assert result.time_scale == pytest.approx(max(alone), rel=2e-3)


def test_smallest_margin_counts_a_missing_brake_as_minus_one():
    """A study's ``smallest_margin`` of a joint that no braked motor drives: the missing brake is −1 (no holding torque
    at all), the other checks keep their own margins 1 − value/limit, not the 1e-9 N·m sentinel's −10⁹."""
    duty, motors, gearboxes = held_duty(), default_catalog("motors"), default_catalog("gearboxes")
    unbraked = size_joint(duty, without_brakes(motors), gearboxes)
    others = [c.margin for c in unbraked.checks if c.name != "brake holding torque"]
    assert unbraked.smallest_margin() == min([-1.0, *others])
    assert all(1 - c.value / c.limit == pytest.approx(c.margin) for c in unbraked.checks
               if c.name != "brake holding torque" and c.limit > 0 and math.isfinite(c.limit) and c.value >= 0)
    plain = size_joint(duty, motors, gearboxes)
    assert plain.smallest_margin() == min(c.margin for c in plain.checks) > 0

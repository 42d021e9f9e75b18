"""Gearbox duty (issue 25, item 2): the task's cycles per hour, the peak torque derated above the catalog's cycle
rating, the emergency torque as a count-limited load, and the report naming every kind of converter that one rule
set by an option removes whole (the PUMA's harmonic gears, removed by the motor peak × ratio rule without
--stop-torque).

The hand case: a disc of 0.5 kg·m² on a vertical axis (no gravity torque) moves 2 rad in 1.2 s (trapezoid,
2 rad/s, 10 rad/s²): 5 N·m at the joint while accelerating and braking, nothing while cruising. Repeated, it runs
3600/1.2 = 3,000 cycles per hour.
"""

from __future__ import annotations

import contextlib
import html
import io
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.catalogs import read_catalog
from mechatron.drives.checks import DriveLimits, PairChecks, evaluate, peak_torque_factor
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import joint_duties
from mechatron.drives.sizing import size_joint, size_mechanism
from mechatron.dynamics.motion import move
from mechatron.errors import InputError
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism
from mechatron.report.html import render

ROOT = Path(__file__).resolve().parents[1]
#: The slope of the ISO 6336-3 life factor of case-hardened teeth, from its two ends: Y_NT = 2.5 at N_L = 10³ and
#: Y_NT = 1 at 3·10⁶ load cycles, Y_NT = (3·10⁶/N_L)^p.
P = math.log10(2.5) / math.log10(3e6 / 1e3)

MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 0.1, "peak_torque": 0.3, "rated_speed": 300.0,
                       "max_speed": 500.0, "rotor_inertia": 1e-4, "mass": 1.0, "price": 100.0}])


def gearbox(**changes) -> pd.DataFrame:
    row = {"key": "G50", "type": "planetary", "ratio": 50.0, "rated_torque": 5.0, "peak_torque": 10.0,
           "emergency_torque": 20.0, "max_input_speed": 600.0, "rated_input_speed": 400.0, "efficiency": 0.9,
           "input_inertia": 2e-5, "mass": 1.0, "price": 100.0}
    return pd.DataFrame([{**row, **changes}])


def disc():
    link = DHLink("revolute", name="q1", inertial=Inertial(0.0, np.zeros(3), np.diag([0.25, 0.25, 0.5])))
    return dh_mechanism(DHTable((link,)), "disc")


@pytest.fixture(scope="module")
def duty():
    mech = disc()
    (d,) = joint_duties(mech, move(mech, [0.0], [2.0], profile="trapezoidal", vmax=2.0, amax=10.0, dt=1e-3))
    assert d.duration == pytest.approx(1.2, rel=1e-12) and np.abs(d.torque).max() == pytest.approx(5.0, rel=1e-9)
    return d


def check(sizing, name):
    return next(c for c in sizing.checks if c.name == name)


# ----------------------------------------------------------------------------------------- the peak torque derating
def test_the_derating_follows_the_iso_6336_3_life_factor():
    """f_c = min(1, (N_r/N)^p): 1 up to the rating, then the Wöhler slope of Y_NT; p from the standard's two ends."""
    assert (3e6 / 1e3) ** P == pytest.approx(2.5, rel=1e-12)
    hour = 1 / 3600
    rates = np.array([500.0, 1000.0, 2000.0, 3000.0, 6000.0]) * hour
    expected = [1.0, 1.0, 0.5**P, (1 / 3) ** P, (1 / 6) ** P]
    assert peak_torque_factor(rates, 1000 * hour) == pytest.approx(expected, rel=1e-12)
    assert expected[2:] == pytest.approx([0.92, 0.88, 0.81], abs=5e-3) and P == pytest.approx(0.1144, abs=5e-5)  # docs
    assert peak_torque_factor(6000 * hour, math.inf) == 1.0  # a direct drive or a screw: no derating


@pytest.mark.parametrize("rating_per_h, factor", [(None, (1000 / 3000) ** P), (1200.0, (1200 / 3000) ** P),
                                                 (3000.0, 1.0), (5000.0, 1.0)])
def test_the_peak_torque_limit_is_derated_above_the_cycle_rating(duty, rating_per_h, factor):
    """3,000 cycles/h against the rating (default 1,000/h): the limit T2B f_c, the value max |τ| = 5 N·m."""
    catalog = gearbox() if rating_per_h is None else gearbox(cycle_rating=rating_per_h / 3600)
    sizing = size_joint(duty, MOTOR, catalog, direct=False)
    peak = check(sizing, "transmission peak torque")
    assert peak.limit == pytest.approx(10.0 * factor, rel=1e-12)
    assert peak.value == pytest.approx(5.0, rel=1e-9)
    assert sizing.gearbox_duty()["cycles_per_hour"] == pytest.approx(3000.0, rel=1e-9)
    assert sizing.gearbox_duty()["peak_torque_factor"] == pytest.approx(factor, rel=1e-12)


def test_the_derating_decides_a_gearbox(duty):
    """T2B 5.5 N·m holds 5 N·m at 1,000 cycles/h but not at 3,000 (5.5 × 0.8818 = 4.85 N·m); rated for 3,000/h it
    passes: the sizing finds no drive, then the gearbox."""
    slow = size_joint(duty, MOTOR, gearbox(peak_torque=5.5), direct=False)
    assert not slow.feasible
    assert check(slow, "transmission peak torque").limit == pytest.approx(5.5 * (1 / 3) ** P, rel=1e-12)
    rated = size_joint(duty, MOTOR, gearbox(peak_torque=5.5, cycle_rating=3000 / 3600), direct=False)
    assert rated.feasible and rated.converter == "G50"
    # replayed twice as slowly (the dwells: none), 1,500 cycles/h: (1000/1500)^p
    slower = duty.scaled(2.0)
    assert PairChecks(slower, MOTOR, converters_for(slower, gearbox(), direct=False)).transmission[0, 1] == \
        pytest.approx(10.0 * (1000 / 1500) ** P, rel=1e-12)


def test_the_time_objective_derates_at_its_own_pace(duty):
    """The time objective replays the moves faster: the cycles per hour of the pace it finds, 3600/(k · 1.2 s)."""
    sizing = size_joint(duty, MOTOR, gearbox(), direct=False, objective="time")
    k = sizing.time_scale
    assert sizing.duty.duration == pytest.approx(1.2 * k, rel=1e-12)
    assert check(sizing, "transmission peak torque").limit == pytest.approx(
        10.0 * min(1.0, (1000 * 1.2 * k / 3600) ** P), rel=1e-12)


# ------------------------------------------------------------------------------------- the emergency torque's count
def test_the_emergency_check_carries_its_count(duty):
    """T2Stop is allowed 1,000 times by default, the catalog's emergency_stops otherwise: the check, its JSON and
    the text report say it; the value is the motor's peak torque × u = 0.3 × 50 = 15 N·m."""
    default = check(size_joint(duty, MOTOR, gearbox(), direct=False), "transmission emergency torque")
    assert default.count == 1000 and default.as_dict()["count"] == 1000 and default.value == pytest.approx(15.0)
    sizing = size_joint(duty, MOTOR, gearbox(emergency_stops=250.0), direct=False)
    emergency = check(sizing, "transmission emergency torque")
    assert emergency.count == 250 and emergency.limit == 20.0
    assert "count" not in check(sizing, "transmission peak torque").as_dict()
    line = next(x for x in str(sizing).splitlines() if "transmission emergency torque" in x)
    assert line.rstrip().endswith("PASS  (allowed 250 times in its life)")
    assert "emergency torque allowed 250 times in its life" in str(sizing)
    assert sizing.as_dict()["gearbox_duty"] == pytest.approx(
        {"cycles_per_hour": 3000.0, "cycle_rating_per_hour": 1000.0, "peak_torque_factor": (1 / 3) ** P,
         "peak_torque_Nm": 10.0, "emergency_stops": 250.0}, rel=1e-9)
    direct = size_joint(duty, pd.DataFrame([{**MOTOR.iloc[0].to_dict(), "peak_torque": 10.0, "rated_torque": 5.0}]),
                        None, inertia_ratio_max=1e4)
    assert direct.converter == "direct" and direct.gearbox_duty() is None and direct.as_dict()["gearbox_duty"] is None


def test_catalog_columns_of_the_gearbox_duty(tmp_path):
    """cycle_rating needs its unit (per_h, per_min, per_s) and is kept in 1/s; emergency_stops is a count > 0;
    an empty cell takes the default; a bad cell names the file, the row and the column."""
    head = ("key,type,ratio,rated_torque,peak_torque,emergency_torque,max_input_speed,rated_input_speed,efficiency,"
            "input_inertia,{}\n")
    rows = "A,planetary,10,5,10,20,600,400,0.9,1e-5,{}\nB,planetary,20,5,10,20,600,400,0.9,1e-5,{}\n"

    def write(columns: str, a: str, b: str) -> Path:
        path = tmp_path / "gearboxes.csv"
        path.write_text(head.format(columns) + rows.format(a, b), encoding="utf-8")
        return path

    table = read_catalog(write("cycle_rating_per_h,emergency_stops", "1800,500", ","), "gearboxes")
    assert table["cycle_rating"].iloc[0] == pytest.approx(0.5, rel=1e-15) and table["emergency_stops"].iloc[0] == 500
    conv = converters_for(joint_duties(disc(), move(disc(), [0.0], [1.0], dt=0.01))[0], table)
    assert conv.key.tolist() == ["direct", "A", "B"]
    assert conv.cycle_rating[1:] == pytest.approx([0.5, 1000 / 3600], rel=1e-15)
    assert conv.emergency_stops[1:].tolist() == [500.0, 1000.0] and math.isnan(conv.emergency_stops[0])
    assert read_catalog(write("cycle_rating_per_min,emergency_stops", "30,1", "60,2"), "gearboxes")[
        "cycle_rating"].tolist() == pytest.approx([0.5, 1.0])
    with pytest.raises(InputError, match=r"gearboxes\.csv: field 'cycle_rating': give the unit in the column name"):
        read_catalog(write("cycle_rating,emergency_stops", "1000,1", "1000,1"), "gearboxes")
    with pytest.raises(InputError, match=r"gearboxes\.csv: row 3: field 'emergency_stops': must be > 0, got 0"):
        read_catalog(write("cycle_rating_per_h,emergency_stops", "1000,1", "1000,0"), "gearboxes")
    with pytest.raises(InputError, match=r"row 2: field 'cycle_rating_per_h': must be > 0, got -5"):
        read_catalog(write("cycle_rating_per_h,emergency_stops", "-5,1", "1000,1"), "gearboxes")


# ----------------------------------------------------------------------------------- a kind removed by one rule
BIG = pd.DataFrame([{"key": "D", "rated_torque": 3.0, "peak_torque": 10.0, "rated_speed": 300.0, "max_speed": 500.0,
                     "rotor_inertia": 1e-3, "mass": 5.0, "price": 500.0}])


def test_every_direct_drive_removed_by_the_inertia_ratio_is_reported(duty):
    """Motor D alone on the disc: peak 5 + 1e-3·10 = 5.01 ≤ 10 N·m, RMS √((5.01² + 4.99²)·0.2/1.2) = 2.89 ≤ 3 N·m,
    but the inertia ratio 0.5/1e-3 = 500 > 10: only that rule removes direct drive, and the report names
    --inertia-ratio and the drive it removed; with the ratio allowed, D + direct is feasible."""
    motors = pd.concat([MOTOR, BIG], ignore_index=True)
    sizing = size_joint(duty, motors, gearbox())
    assert sizing.feasible and sizing.choice() == "M + G50"
    (row,) = sizing.ruled_out()
    assert row["kind"] == "direct" and row["check"] == "inertia ratio" and row["candidate"] == "D + direct"
    assert "--inertia-ratio" in row["option"] and row["mass"] == 5.0
    assert "ruled out: every direct drive fails the inertia ratio check" in str(sizing)
    assert sizing.as_dict()["ruled_out"][0]["candidate"] == "D + direct"
    allowed = size_joint(duty, motors, None, inertia_ratio_max=600.0)
    assert allowed.feasible and allowed.choice() == "D + direct"
    ratio = check(allowed, "inertia ratio")
    assert ratio.value == pytest.approx(0.5 / 1e-3, rel=1e-12)
    assert check(allowed, "RMS torque").value == pytest.approx(math.sqrt((5.01**2 + 4.99**2) * 0.2 / 1.2), rel=5e-3)
    assert allowed.ruled_out() == []


def test_a_kind_removed_by_the_emergency_rule_and_by_the_derating(duty):
    """Every planetary gearbox (one) fails only the emergency rule (15 N·m against 12) or only the derated peak
    torque (5 N·m against 5.5 × 0.8818): each is reported with the option that changes it; a stop torque that
    brings the emergency value under T2Stop lets the gearbox back and nothing is reported."""
    stop = size_joint(duty, MOTOR, gearbox(emergency_torque=12.0), direct=False)
    assert not stop.feasible
    (row,) = stop.ruled_out()
    assert (row["kind"], row["check"], row["candidate"]) == ("planetary", "transmission emergency torque", "M + G50")
    assert "--stop-torque or --stop-current" in row["option"] and "every planetary gearbox" in row["message"]
    limited = size_joint(duty, MOTOR, gearbox(emergency_torque=12.0), direct=False,
                         limits=DriveLimits(stop_torque=0.2))
    assert limited.feasible and limited.ruled_out() == []
    assert check(limited, "transmission emergency torque").value == pytest.approx(0.2 * 50)
    derated = size_joint(duty, MOTOR, gearbox(peak_torque=5.5), direct=False)
    (row,) = derated.ruled_out()
    assert row["check"] == "transmission peak torque" and "cycle_rating" in row["option"]


# ------------------------------------------------------------------------------------------------- the PUMA 560
PUMA = ["size", "puma560", "--task", str(ROOT / "examples/data/pick_and_place.toml"), "--motors",
        str(ROOT / "examples/data/motors.csv"), "--gearboxes", str(ROOT / "examples/data/gearboxes.csv")]


def run_json(*extra: str) -> dict:
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        assert main([*PUMA, *extra, "--json"]) == 0
    return json.loads(buffer.getvalue())


@pytest.fixture(scope="module")
def puma():
    return run_json(), run_json("--stop-torque", "1")


def test_the_puma_names_the_rule_that_removes_its_harmonic_gears(puma):
    """Without --stop-torque the emergency check takes each motor's peak torque × u: no harmonic gear of the
    example catalog holds it on q1, q2, q3, which get planetary gearboxes (26.89 kg of drives, the catalogs' masses
    summed here); each of them says that this rule removed every harmonic gearbox and names --stop-torque. With
    --stop-torque 1 they get harmonic gears (11.26 kg) and no rule removes them."""
    plain, stopped = puma
    masses = {**pd.read_csv(ROOT / "examples/data/motors.csv", comment="#").set_index("key")["mass_kg"],
              **pd.read_csv(ROOT / "examples/data/gearboxes.csv", comment="#").set_index("key")["mass_kg"]}
    for result, kinds in ((plain, ["planetary"] * 3 + ["harmonic"] * 3), (stopped, ["harmonic"] * 6)):
        joints = result["joints"]
        assert [j["converter_kind"] for j in joints] == kinds
        assert result["totals"]["drive_mass_kg"] == pytest.approx(
            sum(masses[j["motor"]] + masses[j["gearbox"]] for j in joints), rel=1e-12)
    assert plain["totals"]["drive_mass_kg"] == pytest.approx(26.89, abs=5e-3)
    assert stopped["totals"]["drive_mass_kg"] == pytest.approx(11.26, abs=5e-3)
    for j in plain["joints"][:3]:
        emergency = [r for r in j["ruled_out"] if r["check"] == "transmission emergency torque"]
        assert [r["kind"] for r in emergency] == ["harmonic"], j["joint"]
        assert "--stop-torque" in emergency[0]["option"] and "--stop-current" in emergency[0]["option"]
        assert emergency[0]["message"].startswith("every harmonic gearbox fails the transmission emergency torque")
        assert j["gearbox_duty"]["cycles_per_hour"] == pytest.approx(3600 / plain["task_time"], rel=1e-12)
        assert next(c for c in j["checks"] if c["name"] == "transmission emergency torque")["count"] == 1000
    for j in stopped["joints"]:
        assert all(r["kind"] != "harmonic" for r in j["ruled_out"])


def test_the_ruled_out_candidate_is_what_the_rule_relaxed_chooses():
    """The best harmonic pair the emergency rule removed from q1 is the lightest harmonic pair the sizing chooses
    when an emergency stop cannot load the gear (a stop torque of 1e-9 N·m), on the same duty."""
    mech = mechatron.load("puma560")
    task = mechatron.dynamics.task.read_task(ROOT / "examples/data/pick_and_place.toml", mech)
    motors = read_catalog(ROOT / "examples/data/motors.csv", "motors")
    gearboxes = read_catalog(ROOT / "examples/data/gearboxes.csv", "gearboxes")
    result = size_mechanism(task.mechanism, task.trajectory, motors, gearboxes, loads=task.loads, single_pass=True)
    q1 = result.joints[0]
    (row,) = [r for r in q1.ruled_out() if r["check"] == "transmission emergency torque"]
    harmonic = gearboxes[gearboxes["type"] == "harmonic"]
    relaxed = size_joint(q1.duty, motors, harmonic, direct=False, limits=DriveLimits(stop_torque=1e-9))
    assert relaxed.feasible and row["candidate"] == relaxed.choice()
    # the text report and the HTML report say it, in the joint's section
    assert f"    ruled out: {row['message']}" in str(result).splitlines()
    page = render(result.report())
    assert f"<p>ruled out: {html.escape(row['message'])}</p>" in page
    assert row["mass"] == pytest.approx(relaxed.drive_mass(), rel=1e-12)
    # and the pair the emergency rule removed fails only that rule, by the motor's peak × u against T2Stop
    motor, gear = motors.set_index("key").loc[row["motor"]], gearboxes.set_index("key").loc[row["converter"]]
    pair = evaluate(q1.duty, motors[motors["key"] == row["motor"]],
                    converters_for(q1.duty, gearboxes[gearboxes["key"] == row["converter"]], direct=False))
    factor = motor["peak_torque"] * gear["ratio"] / gear["emergency_torque"]
    assert pair.failed(0, 0) == [f"transmission emergency torque ×{factor:.2f}"] and factor > 1

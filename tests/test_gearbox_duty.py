"""Gearbox duty (issues 25 and 31): the task's load peaks per hour, the peak torque checked by the rule the
gearbox's maker gives (a table of shock factors by cycles per hour, a strain-wave gear's repeated peak torque, or
the catalog's cycle rating alone), the emergency torque as a count-limited load, and the report naming every kind of
converter that one rule set by an option removes whole (the PUMA's harmonic gears, removed by the motor peak × ratio
rule without --stop-torque).

The hand case: a disc of 0.5 kg·m² on a vertical axis (no gravity torque) moves 2 rad in 1.2 s (trapezoid,
2 rad/s, 10 rad/s²): 5 N·m at the joint while accelerating and −5 N·m while braking, nothing while cruising.
Repeated, it runs 3600/1.2 = 3,000 cycles per hour and meets two torque peaks each time, one in each direction:
6,000 load peaks per hour.

The maker-style table of these tests, TABLE (f_s by cycles per hour, linear between its entries): 1 up to 1,000/h,
1.1 at 2,000, 1.25 at 3,000, 1.5 at 6,000, nothing rated beyond.
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
from mechatron.drives.checks import DriveLimits, PairChecks, evaluate, peak_count, peak_torque_factor
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import joint_duties
from mechatron.drives.sizing import size_joint, size_mechanism
from mechatron.dynamics.motion import cycle, move
from mechatron.errors import InputError
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism
from mechatron.report.html import render

ROOT = Path(__file__).resolve().parents[1]
HOUR = 1 / 3600
#: The maker-style shock factors of the module docstring, as a catalog cell (cycles per hour) and in SI (1/s).
TABLE_CELL = "1000:1;2000:1.1;3000:1.25;6000:1.5"
TABLE = ((1000 * HOUR, 1.0), (2000 * HOUR, 1.1), (3000 * HOUR, 1.25), (6000 * HOUR, 1.5))

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


# --------------------------------------------------------------------------------------------- the load peaks
def test_the_load_peaks_are_counted_per_acceleration_and_braking(duty):
    """Runs of |ω̇| beyond half the largest, one per sign: the disc's move meets 2 (+10 and −10 rad/s²); an
    out-and-back move without rest 2 as well (braking out and accelerating back are one −10 rad/s² pulse through
    the lone sample where the two moves meet, braking back and the next start one +10 rad/s² pulse over the task's
    end); with a rest at each end 4; no motion none."""
    assert peak_count(duty.acceleration) == 2
    mech = disc()
    limits = dict(profile="trapezoidal", vmax=2.0, amax=10.0, dt=1e-3)
    (back,) = joint_duties(mech, cycle(mech, [[0.0], [0.8], [0.0]], **limits))
    (rested,) = joint_duties(mech, cycle(mech, [[0.0], [0.8], [0.0]], dwell=0.3, **limits))
    assert back.duration == pytest.approx(1.2, rel=1e-12)  # 0.8 rad: 0.2 s + 0.2 s + 0.2 s each way
    assert (peak_count(back.acceleration), peak_count(rested.acceleration)) == (2, 4)
    assert peak_count(np.zeros(5)) == 0 and peak_count([3.0, 3.0]) == 1
    assert peak_count([10.0, 4.0, -4.0, 0.0, -10.0, 0.0]) == 2  # ±4 is below half of 10: no peak
    assert peak_count([5.0, 0.0, 0.0, -5.0, 0.0, 0.0, 5.0]) == 2  # the last run continues into the first
    assert peak_count([-5.0, -5.0, 0.0, -5.0, 0.0, 0.0, -5.0, 0.0, 0.0, 5.0]) == 3  # a lone 0 does not split a run


# ------------------------------------------------------------------------------------- the maker's shock factors
def test_the_shock_factor_is_read_off_the_makers_table():
    """1/f_s at each rate, f_s by hand from TABLE: 1 below and at 1,000/h, 1.05 at 1,500 (half-way to 1.1), 1.25 at
    3,000, 1.375 at 4,500 (half-way to 1.5), 1.5 at 6,000; above 6,000/h no rating (0); no table: 1."""
    rates, factors = np.array([TABLE]).transpose(2, 0, 1)  # one row each
    for per_hour, f_s in [(500, 1.0), (1000, 1.0), (1500, 1.05), (3000, 1.25), (4500, 1.375), (6000, 1.5)]:
        assert peak_torque_factor(per_hour * HOUR, rates, factors) == pytest.approx([1 / f_s], rel=1e-12), per_hour
    assert peak_torque_factor(6001 * HOUR, rates, factors).tolist() == [0.0]
    padded = np.array([[1000 * HOUR, 2000 * HOUR, np.nan], [np.nan] * 3])  # a shorter table, and none
    assert peak_torque_factor(1500 * HOUR, padded, [[1.0, 1.2, np.nan], [np.nan] * 3]) == \
        pytest.approx([1 / 1.1, 1.0], rel=1e-12)


@pytest.mark.parametrize("slower, f_s", [(1.0, 1.5), (2.0, 1.25)])
def test_a_reversing_move_gets_the_tables_factor(tmp_path, duty, slower, f_s):
    """The acceptance case, from a CSV catalog with TABLE: the disc's move at 3,000 cycles/h meets 6,000 load peaks
    per hour (one each way), so the peak torque's limit is T2B / f_s(6,000/h) = 10/1.5 N·m — not f_s(3,000/h) =
    1.25, which one peak per cycle would give; replayed twice as slowly, 1,500 cycles/h, 3,000 peaks/h: 10/1.25 N·m,
    the value max |τ| = 5/2² N·m. The report says which rule applied."""
    path = tmp_path / "gearboxes.csv"
    path.write_text("key,type,ratio,rated_torque,peak_torque,emergency_torque,max_input_speed,rated_input_speed,"
                    f"efficiency,input_inertia,shock_factors_per_h\nG50,planetary,50,5,10,20,600,400,0.9,2e-5,"
                    f"{TABLE_CELL}\n", encoding="utf-8")
    catalog = read_catalog(path, "gearboxes")
    assert "peak_rule" not in catalog  # the table's rule by default
    assert np.array(catalog["shock_factors"].iloc[0]) == pytest.approx(np.array(TABLE), rel=1e-15)
    sizing = size_joint(duty.scaled(slower), MOTOR, catalog, direct=False)
    peak = check(sizing, "transmission peak torque")
    assert peak.limit == pytest.approx(10.0 / f_s, rel=1e-12) and peak.value == pytest.approx(5.0 / slower**2)
    report = sizing.gearbox_duty()
    assert report["cycles_per_hour"] == pytest.approx(3000 / slower, rel=1e-9) and report["peaks_per_cycle"] == 2
    assert report["peaks_per_hour"] == pytest.approx(6000 / slower, rel=1e-9)
    assert report["peak_rule"] == "shock_factors" and report["shock_factor"] == pytest.approx(f_s, rel=1e-12)
    assert report["peak_torque_factor"] == pytest.approx(1 / f_s, rel=1e-12)
    assert f"the maker's shock factor f_s = {f_s:.4g} at {6000 / slower:,.0f} load peaks/h" in str(sizing)
    assert sizing.as_dict()["gearbox_duty"]["rule"] == report["rule"]


def test_the_shock_factor_decides_a_gearbox(duty):
    """T2B 7 N·m holds 5 N·m only up to f_s = 1.4: at 6,000 peaks/h (f_s 1.5, 4.67 N·m) the sizing finds no drive,
    and reports the table as the rule that removed the planetary gearboxes; with T2B 8 N·m (5.33 N·m) it passes."""
    low = size_joint(duty, MOTOR, gearbox(peak_torque=7.0, shock_factors=TABLE), direct=False)
    assert not low.feasible
    assert check(low, "transmission peak torque").limit == pytest.approx(7.0 / 1.5, rel=1e-12)
    (row,) = low.ruled_out()
    assert row["check"] == "transmission peak torque" and "shock_factors" in row["option"]
    assert row["message"].startswith("no planetary gearbox passes every check; without the transmission peak torque")
    assert size_joint(duty, MOTOR, gearbox(peak_torque=8.0, shock_factors=TABLE), direct=False).feasible


def test_beyond_the_table_nothing_is_rated(duty):
    """A table that ends at 5,000/h rates nothing at 6,000 peaks/h: the limit is 0 and the check fails, saying
    why; the report says where the table ends."""
    short = ((1000 * HOUR, 1.0), (5000 * HOUR, 1.3))
    sizing = size_joint(duty, MOTOR, gearbox(shock_factors=short), direct=False)
    assert not sizing.feasible and check(sizing, "transmission peak torque").limit == 0.0
    assert "transmission peak torque: no rating at this many load peaks per hour" in sizing.closest["failed"].iloc[0]
    assert sizing.gearbox_duty()["shock_factor"] is None and sizing.gearbox_duty()["peak_torque_factor"] == 0.0
    assert "the maker's shock factors end at 5,000/h: no rating at 6,000 load peaks/h" in str(sizing)


def test_a_strain_wave_gear_holds_its_repeated_peak_at_any_rate(duty):
    """peak_rule repeated_peak: T2B, the repeated peak torque, is the limit at 6,000 peaks/h (no factor), and the
    momentary peak torque (T2Stop) is allowed the catalog's count; the report names the rule."""
    sizing = size_joint(duty, MOTOR, gearbox(type="harmonic", peak_rule="repeated_peak", emergency_stops=1e4),
                        direct=False)
    assert check(sizing, "transmission peak torque").limit == 10.0
    assert check(sizing, "transmission emergency torque").count == 1e4
    report = sizing.gearbox_duty()
    assert report["peak_rule"] == "repeated_peak" and report["shock_factor"] is None
    assert "the maker's repeated peak torque, T2B 10 N·m at any rate" in report["rule"]


@pytest.mark.parametrize("rating_per_h, above", [(None, True), (5000.0, True), (6000.0, False), (8000.0, False)])
def test_without_a_maker_rule_the_report_says_so(duty, rating_per_h, above):
    """No table and no peak_rule: T2B 10 N·m unchanged at 6,000 peaks/h whatever the cycle rating (default 1,000/h);
    above the rating the report says that no maker rule covers it."""
    catalog = gearbox() if rating_per_h is None else gearbox(cycle_rating=rating_per_h * HOUR)
    sizing = size_joint(duty, MOTOR, catalog, direct=False)
    assert check(sizing, "transmission peak torque").limit == 10.0
    report = sizing.gearbox_duty()
    assert report["peak_rule"] == "cycle_rating" and report["above_rating"] is above
    assert report["cycle_rating_per_hour"] == pytest.approx(rating_per_h or 1000.0, rel=1e-12)
    assert ("no maker rule given (mechatron's assumption, not the maker's)" in report["rule"]) is above


def test_the_time_objective_counts_the_peaks_at_its_own_pace(duty):
    """The time objective replays the move k times slower: 2 peaks in 1.2 k s, 6000/k per hour, f_s from TABLE
    (linear between its entries, np.interp)."""
    sizing = size_joint(duty, MOTOR, gearbox(shock_factors=TABLE), direct=False, objective="time")
    k = sizing.time_scale
    assert sizing.duty.duration == pytest.approx(1.2 * k, rel=1e-12)
    per_hour = 6000 / k
    assert per_hour <= 6000  # inside the table
    f_s = np.interp(per_hour, [1000, 2000, 3000, 6000], [1.0, 1.1, 1.25, 1.5])
    assert check(sizing, "transmission peak torque").limit == pytest.approx(10.0 / f_s, rel=1e-12)
    assert PairChecks(duty.scaled(2.0), MOTOR, converters_for(duty, gearbox(shock_factors=TABLE), direct=False)) \
        .transmission[0, 1] == pytest.approx(10.0 / 1.25, rel=1e-12)


def test_the_docs_catalog_of_the_three_rules(tmp_path):
    """docs/catalogs.md's example catalog of the three rules, on a 2 s disc move (3.6 rad at 2 rad/s, 10 rad/s²:
    0.2 + 1.6 + 0.2 s) that accelerates and brakes once, 2 peaks, 3,600 peaks/h: PL90-10 gets f_s = 1.2 + 0.2 ·
    600/3000 = 1.24 (190/1.24 N·m), SW25-100 its 157 N·m at any rate, CY20-89 its 460 N·m, above its 1,000/h
    rating with no maker rule — as the page says."""
    page = (ROOT / "docs/catalogs.md").read_text(encoding="utf-8")
    block = page.split("A gearbox catalog with the three rules", 1)[1].split("```csv\n", 1)[1].split("```", 1)[0]
    path = tmp_path / "three_rules.csv"
    path.write_text(block, encoding="utf-8")
    catalog = read_catalog(path, "gearboxes")
    mech = disc()
    (d,) = joint_duties(mech, move(mech, [0.0], [3.6], profile="trapezoidal", vmax=2.0, amax=10.0, dt=1e-3))
    assert d.duration == pytest.approx(2.0, rel=1e-12) and peak_count(d.acceleration) == 2
    conv = converters_for(d, catalog, direct=False)
    assert conv.peak_rule.tolist() == ["shock_factors", "repeated_peak", "cycle_rating"]
    assert PairChecks(d, MOTOR, conv).transmission[:, 1] == pytest.approx([190 / 1.24, 157.0, 460.0], rel=1e-12)
    assert "190/1.24 = 153.2 N·m" in page and round(190 / 1.24, 1) == 153.2
    assert conv.emergency_stops[1] == 10000
    cycloidal = size_joint(d, MOTOR, catalog[catalog["key"] == "CY20-89"], direct=False).gearbox_duty()
    assert cycloidal["above_rating"] and "no maker rule given" in cycloidal["rule"]


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
    report = sizing.as_dict()["gearbox_duty"]
    assert {k: report[k] for k in ("peak_rule", "peaks_per_cycle", "shock_factor", "above_rating")} == \
        {"peak_rule": "cycle_rating", "peaks_per_cycle": 2, "shock_factor": None, "above_rating": True}
    assert [report[k] for k in ("cycles_per_hour", "peaks_per_hour", "cycle_rating_per_hour", "peak_torque_factor",
                                "peak_torque_Nm", "emergency_stops")] == \
        pytest.approx([3000.0, 6000.0, 1000.0, 1.0, 10.0, 250.0], rel=1e-9)
    direct = size_joint(duty, pd.DataFrame([{**MOTOR.iloc[0].to_dict(), "peak_torque": 10.0, "rated_torque": 5.0}]),
                        None, inertia_ratio_max=1e4)
    assert direct.converter == "direct" and direct.gearbox_duty() is None and direct.as_dict()["gearbox_duty"] is None


def test_catalog_columns_of_the_gearbox_duty(tmp_path):
    """cycle_rating needs its unit (per_h, per_min, per_s) and is kept in 1/s; emergency_stops is a count > 0;
    shock_factors holds rate:factor pairs in its column's unit (rising rates, factors ≥ 1); peak_rule is one of
    three and agrees with the table; an empty cell takes the default; a bad cell names the file, the row and the
    column."""
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
    # the maker's rule: a table of 1/min rates is kept in 1/s; rule and table per row
    table = read_catalog(write("peak_rule,shock_factors_per_min", ",10:1; 50:1.2", "repeated_peak,"), "gearboxes")
    assert np.array(table["shock_factors"].iloc[0]) == pytest.approx(np.array([[10 / 60, 1.0], [50 / 60, 1.2]]),
                                                                     rel=1e-15)
    conv = converters_for(joint_duties(disc(), move(disc(), [0.0], [1.0], dt=0.01))[0], table)
    assert conv.peak_rule.tolist() == ["", "shock_factors", "repeated_peak"]
    assert conv.shock_factors.shape == (3, 2) and np.isnan(conv.shock_factors[[0, 2]]).all()
    for cell, message in [("1000-1", r"expected rate:factor pairs separated by ';'"),
                          ("1000:0.9", r"a shock factor must be >= 1 .*got 0\.9"),
                          ("2000:1;1000:1.2", r"the rates must rise from pair to pair, got 1000"),
                          ("0:1", r"a rate must be > 0, got 0"), ("1000:x", r"not a number: 'x'")]:
        with pytest.raises(InputError, match=r"row 3: field 'shock_factors_per_h': " + message):
            read_catalog(write("shock_factors_per_h", "1000:1", cell), "gearboxes")
    with pytest.raises(InputError, match=r"row 2: field 'peak_rule': unknown peak rule 'shock'"):
        read_catalog(write("peak_rule", "shock", ""), "gearboxes")
    with pytest.raises(InputError, match=r"row 3: field 'shock_factors_per_h': missing value: peak_rule "
                                         r"shock_factors needs"):
        read_catalog(write("peak_rule,shock_factors_per_h", "shock_factors,1000:1", "shock_factors,"), "gearboxes")
    with pytest.raises(InputError, match=r"row 2: field 'peak_rule': a shock_factors table with peak_rule "
                                         r"repeated_peak"):
        read_catalog(write("peak_rule,shock_factors_per_h", "repeated_peak,1000:1", ","), "gearboxes")
    with pytest.raises(InputError, match=r"field 'shock_factors': give the unit in the column name"):
        read_catalog(write("shock_factors", "1000:1", "1000:1"), "gearboxes")


# ----------------------------------------------------------------------------------- a kind removed by one rule
BIG = pd.DataFrame([{"key": "D", "rated_torque": 3.0, "peak_torque": 10.0, "rated_speed": 300.0, "max_speed": 500.0,
                     "rotor_inertia": 1e-3, "mass": 5.0, "price": 500.0}])


def test_every_direct_drive_removed_by_the_inertia_ratio_is_reported(duty):
    """Motor D alone on the disc: ±(5 + 1e-3·10) = ±5.01 N·m while accelerating and braking (the rotor's inertia
    adds to the load's either way), peak 5.01 ≤ 10 N·m; RMS ≤ 3 N·m (the trapezoidal time mean over the samples,
    by hand below); but the inertia ratio 0.5/1e-3 = 500 > 10: only that rule removes direct drive, and the report
    names --inertia-ratio and the drive it removed; with the ratio allowed, D + direct is feasible."""
    motors = pd.concat([MOTOR, BIG], ignore_index=True)
    sizing = size_joint(duty, motors, gearbox())
    assert sizing.feasible and sizing.choice() == "M + G50"
    (row,) = sizing.ruled_out()
    assert row["kind"] == "direct" and row["check"] == "inertia ratio" and row["candidate"] == "D + direct"
    assert "--inertia-ratio" in row["option"] and row["mass"] == 5.0
    assert "ruled out: no direct drive passes every check; without the inertia ratio check" in str(sizing)
    assert sizing.as_dict()["ruled_out"][0]["candidate"] == "D + direct"
    allowed = size_joint(duty, motors, None, inertia_ratio_max=600.0)
    assert allowed.feasible and allowed.choice() == "D + direct"
    ratio = check(allowed, "inertia ratio")
    assert ratio.value == pytest.approx(0.5 / 1e-3, rel=1e-12)
    # the duty's samples, a uniform step h = 1.2/1201 s: +10 rad/s² at samples 0 … 200, −10 at 1001 … 1200, 0
    # elsewhere, so |T| = 5.01 N·m there and 0 elsewhere; the trapezoidal rule gives ∫T² dt = 5.01² h (200.5 + 200)
    # (the accelerating run: 200 whole steps and half the step to the first cruising sample; the braking run: 199
    # whole steps and a half step at each end), RMS = 5.01 √(400.5/1201) N·m
    t, a = allowed.duty.t, allowed.duty.acceleration
    assert len(t) == 1202 and np.diff(t) == pytest.approx(np.full(1201, 1.2 / 1201), rel=1e-12)
    assert np.flatnonzero(a == 10.0).tolist() == list(range(201))
    assert np.flatnonzero(a == -10.0).tolist() == list(range(1001, 1201)) and np.count_nonzero(a) == 401
    assert check(allowed, "RMS torque").value == pytest.approx(5.01 * math.sqrt(400.5 / 1201), rel=1e-12)
    assert allowed.ruled_out() == []


def test_a_kind_removed_by_the_emergency_rule(duty):
    """Every planetary gearbox (one) fails only the emergency rule (0.3 · 50 = 15 N·m against 12): it is reported
    with the option that changes it (the shock factors' case: test_the_shock_factor_decides_a_gearbox); a stop
    torque that brings the emergency value under T2Stop lets the gearbox back and nothing is reported."""
    stop = size_joint(duty, MOTOR, gearbox(emergency_torque=12.0), direct=False)
    assert not stop.feasible
    (row,) = stop.ruled_out()
    assert (row["kind"], row["check"], row["candidate"]) == ("planetary", "transmission emergency torque", "M + G50")
    assert "--stop-torque or --stop-current" in row["option"]
    assert row["message"].startswith("no planetary gearbox passes every check; without the transmission emergency "
                                     "torque check")
    limited = size_joint(duty, MOTOR, gearbox(emergency_torque=12.0), direct=False,
                         limits=DriveLimits(stop_torque=0.2))
    assert limited.feasible and limited.ruled_out() == []
    assert check(limited, "transmission emergency torque").value == pytest.approx(0.2 * 50)


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
    summed here); each of them says that no harmonic gearbox passes every check and that without this rule one
    would, and names --stop-torque. With --stop-torque 1 they get harmonic gears (11.26 kg) and no rule removes
    them. The load peaks, counted from the task's waypoints: q1 moves twice a cycle (to +45° and back), q2 and q3
    four times, each move an acceleration and a braking between rests: 4 and 8 peaks; the planetary gearheads' limit
    is T2B / f_s from the example catalog's table at that many peaks per hour (np.interp)."""
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
        assert emergency[0]["message"].startswith("no harmonic gearbox passes every check; without the "
                                                  "transmission emergency torque check")
        duty = j["gearbox_duty"]
        assert duty["cycles_per_hour"] == pytest.approx(3600 / plain["task_time"], rel=1e-12)
        assert duty["peaks_per_cycle"] == {"q1": 4, "q2": 8, "q3": 8}[j["joint"]] and duty["peak_rule"] == \
            "shock_factors"
        f_s = np.interp(duty["peaks_per_hour"], [1000, 2000, 3000, 4000, 6000, 10000], [1, 1.1, 1.2, 1.3, 1.4, 1.6])
        assert next(c for c in j["checks"] if c["name"] == "transmission peak torque")["limit"] == \
            pytest.approx(masses_free_t2b(j["gearbox"]) / f_s, rel=1e-12)
        assert next(c for c in j["checks"] if c["name"] == "transmission emergency torque")["count"] == 1000
    for j in stopped["joints"]:
        assert all(r["kind"] != "harmonic" for r in j["ruled_out"])


def masses_free_t2b(key: str) -> float:
    """T2B (N·m) of an example gearbox, from the CSV as written."""
    return float(pd.read_csv(ROOT / "examples/data/gearboxes.csv", comment="#").set_index("key").loc[key,
                                                                                                   "peak_torque_Nm"])


def test_the_ruled_out_sentence_claims_only_what_holds():
    """Issue 31, item 5: q1's harmonic gears are reported twice — without the emergency rule one pair would pass,
    without the inertia ratio another — so "every harmonic gearbox fails the emergency torque check" would be false
    (the second pair passes it). What is said is true: every motor × harmonic pair fails some check (the exact
    evaluation of them all), each named pair fails its rule and passes the other."""
    mech = mechatron.load("puma560")
    task = mechatron.dynamics.task.read_task(ROOT / "examples/data/pick_and_place.toml", mech)
    motors = read_catalog(ROOT / "examples/data/motors.csv", "motors")
    gearboxes = read_catalog(ROOT / "examples/data/gearboxes.csv", "gearboxes")
    q1 = size_mechanism(task.mechanism, task.trajectory, motors, gearboxes, loads=task.loads,
                        single_pass=True).joints[0]
    rows = {r["check"]: r for r in q1.ruled_out() if r["kind"] == "harmonic"}
    assert set(rows) == {"transmission emergency torque", "inertia ratio"}
    harmonic = gearboxes[gearboxes["type"] == "harmonic"].reset_index(drop=True)
    every = evaluate(q1.duty, motors, converters_for(q1.duty, harmonic, direct=False))
    assert (every.worst() > 1 + 1e-9).all()  # no harmonic pair passes every check
    for rule, other in (("transmission emergency torque", "inertia ratio"),
                        ("inertia ratio", "transmission emergency torque")):
        m = int(np.flatnonzero(motors["key"] == rows[rule]["motor"])[0])
        c = int(np.flatnonzero(harmonic["key"] == rows[rule]["converter"])[0])
        failed = [name.split(" ×")[0] for name in every.failed(m, c)]
        assert failed == [rule] and other not in failed
        assert rows[rule]["message"].startswith(f"no harmonic gearbox passes every check; without the {rule} check")


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
